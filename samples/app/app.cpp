// samples/app/app.cpp - the App of app.hpp: options, window (GLFW + Dear ImGui) or EGL headless, orbit
// camera, light, the panel, pass timing, the composite and the PNG. Nothing here knows a technique.
#include "app.hpp"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <utility>
#include <vector>

#if SHADOWKIT_APP_GLFW
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#endif
#if SHADOWKIT_APP_IMGUI
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>
#endif

namespace app {

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
}

std::string join(const std::vector<std::string>& v, const char* sep = ", ") {
    std::string s;
    for (const auto& x : v) s += (s.empty() ? "" : sep) + x;
    return s;
}

// The measured time of one pass of the technique.
struct Pass {
    std::string name;
    bool gpu = false;
    std::vector<double> ms;  // headless: every frame; window: the last 120
};

// Shows a DebugImage into the bound framebuffer's viewport.
class DebugShow {
public:
    DebugShow() = default;
    DebugShow(const DebugShow&) = delete;
    DebugShow& operator=(const DebugShow&) = delete;
    ~DebugShow() {
        if (prog_) glDeleteProgram(prog_);
        if (vao_) glDeleteVertexArrays(1, &vao_);
        if (sampler_) glDeleteSamplers(1, &sampler_);
    }
    bool init(std::string& why) {
        const char* fs = R"(#version 450 core
layout(binding = 3) uniform sampler2D u_value;
layout(binding = 4) uniform usampler2D u_stencil;
uniform int u_mode;      // 0 grey from u_range, 1 stencil count, 2 RGBA as is
uniform vec2 u_range;
uniform vec2 u_viewport;
layout(location = 0) out vec4 o_color;
void main() {
    vec2 uv = gl_FragCoord.xy / u_viewport;
    if (u_mode == 1) {
        o_color = vec4(vec3(min(255.0, 64.0 * float(texture(u_stencil, uv).r)) / 255.0), 1.0);
        return;
    }
    vec4 t = texture(u_value, uv);
    if (u_mode == 2) { o_color = t; return; }
    o_color = vec4(vec3(clamp((t.r - u_range.x) / max(u_range.y - u_range.x, 1e-30), 0.0, 1.0)), 1.0);
}
)";
        prog_ = compile_fullscreen_program(fs, why);
        if (!prog_) return false;
        glGenVertexArrays(1, &vao_);
        // a sampler object overrides the texture's own state: depth maps are read as depth (no compare)
        glGenSamplers(1, &sampler_);
        glSamplerParameteri(sampler_, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glSamplerParameteri(sampler_, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glSamplerParameteri(sampler_, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glSamplerParameteri(sampler_, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        glSamplerParameteri(sampler_, GL_TEXTURE_COMPARE_MODE, GL_NONE);
        return true;
    }
    void draw(const DebugImage& d) {
        const glm::ivec2 vp = begin_fullscreen_pass();
        glUseProgram(prog_);
        glUniform2f(glGetUniformLocation(prog_, "u_viewport"), float(vp.x), float(vp.y));
        int mode = 0;
        if (d.show == DebugImage::Show::Stencil) {
            mode = 1;
            glBindTexture(GL_TEXTURE_2D, d.texture);
            glTexParameteri(GL_TEXTURE_2D, GL_DEPTH_STENCIL_TEXTURE_MODE, GL_STENCIL_INDEX);
            glActiveTexture(GL_TEXTURE4);
            glBindTexture(GL_TEXTURE_2D, d.texture);
            glBindSampler(4, sampler_);
        } else {
            mode = d.show == DebugImage::Show::Overlay ? 2 : 0;
            if (mode == 0) {
                const glm::vec2 r = range(d);
                glUniform2f(glGetUniformLocation(prog_, "u_range"), r.x, r.y);
            }
            glActiveTexture(GL_TEXTURE3);
            glBindTexture(GL_TEXTURE_2D, d.texture);
            glBindSampler(3, sampler_);
        }
        glUniform1i(glGetUniformLocation(prog_, "u_mode"), mode);
        if (mode == 2) {
            glEnable(GL_BLEND);
            glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
        }
        glBindVertexArray(vao_);
        glDrawArrays(GL_TRIANGLES, 0, 3);
        glBindVertexArray(0);
        glDisable(GL_BLEND);
        glBindSampler(3, 0);
        glBindSampler(4, 0);
        if (mode == 1) {
            glBindTexture(GL_TEXTURE_2D, d.texture);
            glTexParameteri(GL_TEXTURE_2D, GL_DEPTH_STENCIL_TEXTURE_MODE, GL_DEPTH_COMPONENT);
        }
        glActiveTexture(GL_TEXTURE0);
    }
    // The finite range of the texture's red channel (depth: of the depths below 1, the cleared far).
    static glm::vec2 range(const DebugImage& d) {
        GLint w = 0, h = 0;
        glGetTextureLevelParameteriv(d.texture, 0, GL_TEXTURE_WIDTH, &w);
        glGetTextureLevelParameteriv(d.texture, 0, GL_TEXTURE_HEIGHT, &h);
        const bool depth = d.show == DebugImage::Show::Depth;
        std::vector<float> px(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
        glPixelStorei(GL_PACK_ALIGNMENT, 4);
        glGetTextureImage(d.texture, 0, depth ? GL_DEPTH_COMPONENT : GL_RED, GL_FLOAT,
                          static_cast<GLsizei>(px.size() * sizeof(float)), px.data());
        float lo = INFINITY, hi = -INFINITY;
        for (float v : px)
            if (std::isfinite(v) && (!depth || v < 1.f)) {
                lo = std::min(lo, v);
                hi = std::max(hi, v);
            }
        return hi > lo ? glm::vec2(lo, hi) : glm::vec2(0.f, 1.f);
    }
    static void size_of(GLuint tex, int& w, int& h) {
        glGetTextureLevelParameteriv(tex, 0, GL_TEXTURE_WIDTH, &w);
        glGetTextureLevelParameteriv(tex, 0, GL_TEXTURE_HEIGHT, &h);
    }

private:
    GLuint prog_ = 0, vao_ = 0, sampler_ = 0;
};

}  // namespace

struct App::Impl {
    std::string title, program;
    // options
    std::string scene_name = "contact", mesh, out;
    bool headless = false;
    int frames = 0;  // 0: not given (headless: 1; window: until closed)
    int width = 800, height = 600;
    std::vector<std::pair<std::string, std::function<DebugImage()>>> debug;
    std::size_t shown = 0;  // 0: the shaded picture; k: debug[k - 1]
    // GL and the scene
    std::unique_ptr<skgl::Context> egl;
    std::string renderer;
    sk::Scene scene, base;  // base: as loaded (headless turns the light from it)
    // the GL objects, released before the context goes
    struct Gl {
        SceneGpu gpu;
        Composite composite;
        DebugShow show;
    };
    std::unique_ptr<Gl> gl;
    GLuint timer_query = 0;
    int frame = -1;
    std::vector<Pass> passes;
    std::function<void()> widgets;
    std::string last_view_label;
    std::vector<sk::Scene> own_scenes;  // add_scene(): offered after the built-in ones
    GLuint picture = 0;                 // present_color(): the technique's own picture instead of the composite
#if SHADOWKIT_APP_GLFW
    GLFWwindow* win = nullptr;
    bool imgui = false, imgui_frame = false;  // the panel's frame began (NewFrame) and is not rendered yet
    int key_state[GLFW_KEY_LAST + 1] = {};
    float yaw = 0.f, pitch = 0.f;
    bool dragging = false;
    double mx = 0.0, my = 0.0;
    int pending_scene = -1;  // a scene picked in the panel, loaded at the next frame
#endif

    Pass& pass(const char* name, bool on_gpu) {
        for (Pass& p : passes)
            if (p.name == name && p.gpu == on_gpu) return p;
        passes.push_back(Pass{name, on_gpu, {}});
        return passes.back();
    }
    void record(const char* name, bool on_gpu, double ms) {
        Pass& p = pass(name, on_gpu);
        p.ms.push_back(ms);
        if (!headless && p.ms.size() > 120) p.ms.erase(p.ms.begin());
    }
    std::vector<std::string> view_names() const {
        std::vector<std::string> n{"shaded"};
        for (const auto& d : debug) n.push_back(d.first);
        return n;
    }
    // The shaded picture or the chosen debug view into framebuffer fbo (w x h). The debug view's
    // function runs first: it may render (and bind framebuffers) itself.
    void draw_view(GLuint visibility, GLuint fbo, int w, int h) {
        DebugImage d;
        if (shown > 0) d = debug[shown - 1].second();
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        glViewport(0, 0, w, h);
        glClearColor(0.f, 0.f, 0.f, 1.f);
        glClear(GL_COLOR_BUFFER_BIT);
        last_view_label = shown == 0 ? "shaded" : debug[shown - 1].first + (d.texture ? "" : " (none for this scene)");
        if ((shown == 0 || d.texture == 0 || d.show == DebugImage::Show::Overlay) && picture)
            gl->show.draw(DebugImage{picture, DebugImage::Show::Overlay});
        else if (shown == 0 || d.texture == 0 || d.show == DebugImage::Show::Overlay)
            gl->composite.draw(gl->gpu, scene.light, visibility);
        if (d.texture) gl->show.draw(d);
    }
    std::vector<std::string> scene_names() const {
        std::vector<std::string> n = sk::builtin_scene_names();
        for (const sk::Scene& s : own_scenes) n.push_back(s.name);
        return n;
    }
    bool load_scene(const std::string& name, std::string& why) {
        sk::Scene s;
        const auto own = std::find_if(own_scenes.begin(), own_scenes.end(), [&](const sk::Scene& o) { return o.name == name; });
        if (!mesh.empty() && name == mesh) {
            if (!sk::load_mesh_scene(mesh, s, why)) return false;
        } else if (own != own_scenes.end()) {
            s = *own;
        } else if (!sk::make_builtin_scene(name, s)) {
            why = "unknown scene '" + name + "'; valid: " + join(scene_names());
            return false;
        }
        scene = base = std::move(s);
        scene_name = name;
        if (gl) upload_scene(scene, gl->gpu);  // (start() loads before the context exists, uploads after)
        return true;
    }
};

App::App(std::string title) : impl_(std::make_unique<Impl>()) { impl_->title = std::move(title); }

App::~App() {
    Impl& I = *impl_;
    if (I.timer_query) glDeleteQueries(1, &I.timer_query);
#if SHADOWKIT_APP_GLFW
    if (I.win) {
#if SHADOWKIT_APP_IMGUI
        if (I.imgui) {
            if (I.imgui_frame) ImGui::EndFrame();  // the sample stopped between next_frame() and present()
            ImGui_ImplOpenGL3_Shutdown();
            ImGui_ImplGlfw_Shutdown();
            ImGui::DestroyContext();
        }
#endif
        I.gl.reset();  // the GL objects go before the context
        glfwDestroyWindow(I.win);
        glfwTerminate();
    }
#endif
}

void App::debug_view(const std::string& name, std::function<DebugImage()> image) {
    impl_->debug.emplace_back(name, std::move(image));
}

void App::default_scene(const std::string& name) { impl_->scene_name = name; }

void App::add_scene(sk::Scene scene) { impl_->own_scenes.push_back(std::move(scene)); }

void App::present_color(GLuint picture) {
    impl_->picture = picture;
    present(0);
    impl_->picture = 0;
}

int App::fail(const std::string& why) {
    std::fprintf(stderr, "%s: %s\n", impl_->program.c_str(), why.c_str());
    exit_code_ = 1;
    return 1;
}

bool App::start(int argc, char** argv) {
    Impl& I = *impl_;
    I.program = argc > 0 ? argv[0] : "sample";
    I.program = I.program.substr(I.program.find_last_of('/') + 1);
    const std::vector<std::string> options = {"--scene NAME", "--mesh FILE",   "--headless [OUT.png]", "--out OUT.png",
                                              "--frames N",   "--size WxH",    "--param name=value",   "--view NAME",
                                              "--help"};
    auto bad = [&](const std::string& msg) {
        std::fprintf(stderr, "%s: %s\n", I.program.c_str(), msg.c_str());
        exit_code_ = 2;
        return false;
    };
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&](const char* what, std::string& v) {
            if (i + 1 >= argc) return false;
            v = argv[++i];
            (void)what;
            return true;
        };
        std::string v;
        if (a == "--help" || a == "-h") {
            std::printf("%s: %s\nusage: %s [%s]\n", I.program.c_str(), I.title.c_str(), I.program.c_str(),
                        join(options, "] [").c_str());
            std::printf("scenes: %s\n", join(I.scene_names()).c_str());
            for (const auto& e : params_.entries()) {
                if (e.kind == Params::Entry::Kind::Number)
                    std::printf("--param %s=<%g..%g> (now %s)\n", e.name.c_str(), e.min, e.max, e.get().c_str());
                else
                    std::printf("--param %s=%s (now %s)\n", e.name.c_str(), join(e.options, "|").c_str(), e.get().c_str());
            }
            std::printf("views: %s\n", join(I.view_names()).c_str());
            exit_code_ = 0;
            return false;
        } else if (a == "--scene") {
            if (!value("NAME", v)) return bad("--scene wants a name; valid: " + join(I.scene_names()));
            const auto names = I.scene_names();
            if (std::find(names.begin(), names.end(), v) == names.end())
                return bad("unknown scene '" + v + "'; valid: " + join(names));
            I.scene_name = v;
        } else if (a == "--mesh") {
            if (!value("FILE", v)) return bad("--mesh wants a file (OBJ, PLY, ...)");
            I.mesh = I.scene_name = v;
        } else if (a == "--headless") {
            I.headless = true;
            if (i + 1 < argc && argv[i + 1][0] != '-') I.out = argv[++i];
        } else if (a == "--out") {
            if (!value("FILE", v) || v.empty()) return bad("--out wants a PNG file name");
            I.out = v;
        } else if (a == "--frames") {
            char* end = nullptr;
            const long n = value("N", v) ? std::strtol(v.c_str(), &end, 10) : 0;
            if (v.empty() || *end != '\0' || n < 1 || n > 100000) return bad("--frames wants a count from 1 to 100000");
            I.frames = static_cast<int>(n);
        } else if (a == "--size") {
            int w = 0, h = 0;
            char x = 0, tail = 0;
            if (!value("WxH", v) || std::sscanf(v.c_str(), "%d%c%d%c", &w, &x, &h, &tail) != 3 || x != 'x' || w < 1 ||
                h < 1 || w > 8192 || h > 8192)
                return bad("--size wants WxH (1x1 to 8192x8192), not '" + v + "'");
            I.width = w;
            I.height = h;
        } else if (a == "--param") {
            std::string why;
            if (!value("name=value", v)) return bad("--param wants name=value; valid names: " + params_.names());
            if (!params_.set(v, why)) return bad(why);
        } else if (a == "--view") {
            const auto names = I.view_names();
            if (!value("NAME", v)) return bad("--view wants a name; valid: " + join(names));
            const auto it = std::find(names.begin(), names.end(), v);
            if (it == names.end()) return bad("unknown view '" + v + "'; valid: " + join(names));
            I.shown = static_cast<std::size_t>(it - names.begin());
        } else {
            return bad("unknown option '" + a + "'; valid: " + join(options));
        }
    }
    if (!I.out.empty()) I.headless = true;
    if (I.headless && I.out.empty()) I.out = "shot.png";
    if (I.headless && I.frames == 0) I.frames = 1;

    std::string why;
    if (!I.load_scene(I.scene_name, why)) return bad(why);  // a mesh file that cannot be read: bad input
    if (I.headless) {
        I.egl = skgl::create_context(why);
        if (!I.egl) {
            std::fprintf(stderr, "%s: no headless GL context: %s\n", I.program.c_str(), why.c_str());
            exit_code_ = skgl::no_context_exit_code();  // 77: CTest skipped (1 under SHADOWKIT_REQUIRE_GL)
            return false;
        }
        I.renderer = I.egl->renderer;
    } else {
#if SHADOWKIT_APP_GLFW
        if (!glfwInit()) {
            std::fprintf(stderr, "%s: glfwInit failed (no display? use --headless or xvfb-run)\n", I.program.c_str());
            exit_code_ = 1;
            return false;
        }
        glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
        glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
        glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
        I.win = glfwCreateWindow(I.width, I.height, ("shadowkit: " + I.title).c_str(), nullptr, nullptr);
        if (!I.win) {
            std::fprintf(stderr, "%s: cannot create a GL 4.5 core window\n", I.program.c_str());
            glfwTerminate();
            exit_code_ = 1;
            return false;
        }
        glfwMakeContextCurrent(I.win);
        glfwSwapInterval(1);
        I.renderer = skgl::note_current_context();
#if SHADOWKIT_APP_IMGUI
        IMGUI_CHECKVERSION();
        ImGui::CreateContext();
        ImGui::GetIO().IniFilename = nullptr;
        I.imgui = ImGui_ImplGlfw_InitForOpenGL(I.win, true) && ImGui_ImplOpenGL3_Init("#version 450");
#endif
#else
        std::fprintf(stderr, "%s: built without GLFW: use --headless\n", I.program.c_str());
        exit_code_ = 1;
        return false;
#endif
    }
    if (skgl::timer_queries_in_use()) glGenQueries(1, &I.timer_query);
    I.gl = std::make_unique<Impl::Gl>();
    upload_scene(I.scene, I.gl->gpu);
    if (!I.gl->composite.init(why) || !I.gl->show.init(why)) {
        fail(why);
        return false;
    }
    return true;
}

bool App::next_frame() {
    Impl& I = *impl_;
    ++I.frame;
    std::string why;
    bool gbuffer = I.frame == 0;
    scene_changed_ = I.frame == 0;
    if (I.headless) {
        if (I.frame >= I.frames) {
            std::string times;
            for (const Pass& p : I.passes) {
                char ms[32];
                std::snprintf(ms, sizeof ms, " %.3f ms", median(p.ms));
                times += (times.empty() ? "" : ", ") + std::string(p.gpu ? "gpu " : "cpu ") + p.name + ms;
            }
            std::printf("%s: %s on %s (%s), %d frame%s, view %s (median %s) -> %s\n", I.program.c_str(), I.title.c_str(),
                        I.scene.name.c_str(), params_.label().c_str(), I.frames, I.frames == 1 ? "" : "s",
                        I.last_view_label.c_str(), times.empty() ? "no passes timed" : times.c_str(), I.out.c_str());
            return false;
        }
        // the light turns about the vertical axis through the scene's center, 360/N degrees a frame
        const glm::vec3 center = 0.5f * (I.base.bounds_min() + I.base.bounds_max());
        const float ang = 6.2831853f * float(I.frame) / float(I.frames);
        const float c = std::cos(ang), s = std::sin(ang);
        auto turn = [&](glm::vec3 v) { return glm::vec3(c * v.x + s * v.z, v.y, -s * v.x + c * v.z); };
        I.scene.light = I.base.light;
        if (I.frame > 0) {
            I.scene.light.position = center + turn(I.base.light.position - center);
            I.scene.light.direction = turn(I.base.light.direction);
        }
        if (gbuffer && !render_gbuffer(I.scene, I.scene.camera, I.width, I.height, I.gl->gpu, why)) {
            fail(why);
            return false;
        }
        view_ = make_view(I.scene, I.gl->gpu);
        return true;
    }
#if SHADOWKIT_APP_GLFW
    if (I.frames > 0 && I.frame >= I.frames) return false;
    glfwPollEvents();
    if (glfwWindowShouldClose(I.win) || glfwGetKey(I.win, GLFW_KEY_ESCAPE) == GLFW_PRESS) return false;
    bool want_mouse = false, want_keys = false;
    auto stop = [&](const std::string& msg) {  // a failure after the panel's frame began
#if SHADOWKIT_APP_IMGUI
        if (I.imgui) ImGui::EndFrame();
        I.imgui_frame = false;
#endif
        fail(msg);
        return false;
    };
#if SHADOWKIT_APP_IMGUI
    if (I.imgui) {
        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        I.imgui_frame = true;
        want_mouse = ImGui::GetIO().WantCaptureMouse;
        want_keys = ImGui::GetIO().WantCaptureKeyboard;
    }
#endif
    auto pressed = [&](int key) {
        const int s = glfwGetKey(I.win, key);
        const bool edge = s == GLFW_PRESS && I.key_state[key] != GLFW_PRESS;
        I.key_state[key] = s;
        return edge && !want_keys;
    };
    auto down = [&](int key) { return !want_keys && glfwGetKey(I.win, key) == GLFW_PRESS; };
    if (pressed(GLFW_KEY_V)) I.shown = (I.shown + 1) % (I.debug.size() + 1);
    // N / P (or the panel's scene list): another built-in scene
    const auto names = I.scene_names();
    const bool next = pressed(GLFW_KEY_N), prev = pressed(GLFW_KEY_P);
    if (next || prev || I.pending_scene >= 0) {
        std::size_t k = static_cast<std::size_t>(std::find(names.begin(), names.end(), I.scene_name) - names.begin());
        if (I.pending_scene >= 0) k = static_cast<std::size_t>(I.pending_scene);
        else if (k >= names.size()) k = 0;
        else k = (k + (next ? 1 : names.size() - 1)) % names.size();
        I.pending_scene = -1;
        if (!I.load_scene(names[k], why)) return stop(why);
        I.yaw = I.pitch = 0.f;
        gbuffer = scene_changed_ = true;
    }
    // arrow keys move the light in x / z, PageUp / PageDown in y (a spot light keeps aiming at the
    // scene's center; a directional light turns)
    glm::vec3 d(0.f);
    if (down(GLFW_KEY_LEFT)) d.x -= 1.f;
    if (down(GLFW_KEY_RIGHT)) d.x += 1.f;
    if (down(GLFW_KEY_UP)) d.z -= 1.f;
    if (down(GLFW_KEY_DOWN)) d.z += 1.f;
    if (down(GLFW_KEY_PAGE_UP)) d.y += 1.f;
    if (down(GLFW_KEY_PAGE_DOWN)) d.y -= 1.f;
    sk::Light& L = I.scene.light;
    if (d != glm::vec3(0.f)) {
        const float step = 0.02f * glm::length(I.scene.bounds_max() - I.scene.bounds_min()) / 10.f;
        if (L.type == sk::LightType::Directional) {
            L.direction = glm::normalize(L.direction + 0.5f * step * glm::vec3(d.x, -d.y, d.z));
        } else {
            const glm::vec3 aim = 0.5f * (I.scene.bounds_min() + I.scene.bounds_max());
            L.position += step * d;
            if (L.type != sk::LightType::Linear) L.direction = glm::normalize(aim - L.position);
        }
    }
    // drag to orbit about the camera's target
    double mx = 0.0, my = 0.0;
    glfwGetCursorPos(I.win, &mx, &my);
    if (glfwGetMouseButton(I.win, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS && (I.dragging || !want_mouse)) {
        if (I.dragging && (mx != I.mx || my != I.my)) {
            I.yaw += static_cast<float>(mx - I.mx) * 0.01f;
            I.pitch = std::clamp(I.pitch + static_cast<float>(my - I.my) * 0.01f, -1.2f, 1.2f);
            gbuffer = true;
        }
        I.dragging = true;
    } else {
        I.dragging = false;
    }
    I.mx = mx;
    I.my = my;
    int w = 0, h = 0;
    glfwGetFramebufferSize(I.win, &w, &h);
    w = std::max(w, 1);
    h = std::max(h, 1);
    if (w != I.gl->gpu.width || h != I.gl->gpu.height) gbuffer = scene_changed_ = true;
    if (gbuffer) {
        sk::Camera c = I.base.camera;
        const glm::vec3 off = c.eye - c.target;
        const float r = glm::length(off);
        const float yaw = std::atan2(off.x, off.z) + I.yaw, pitch = std::clamp(std::asin(off.y / r) + I.pitch, -1.4f, 1.4f);
        c.eye = c.target + r * glm::vec3(std::cos(pitch) * std::sin(yaw), std::sin(pitch), std::cos(pitch) * std::cos(yaw));
        I.scene.camera = c;
        if (!render_gbuffer(I.scene, c, w, h, I.gl->gpu, why)) return stop(why);
    }
    view_ = make_view(I.scene, I.gl->gpu);
    return true;
#else
    return false;
#endif
}

void App::cpu(const char* name, const std::function<void()>& fn) {
    const auto t0 = Clock::now();
    fn();
    impl_->record(name, false, ms_since(t0));
}

void App::gpu(const char* name, const std::function<void()>& fn) {
    Impl& I = *impl_;
    if (I.timer_query) {  // a GPU: its own time for the pass's commands
        glBeginQuery(GL_TIME_ELAPSED, I.timer_query);
        fn();
        glEndQuery(GL_TIME_ELAPSED);
        GLuint64 ns = 0;
        glGetQueryObjectui64v(I.timer_query, GL_QUERY_RESULT, &ns);
        I.record(name, true, double(ns) * 1e-6);
        return;
    }
    glFinish();  // llvmpipe: the pass runs on the CPU; time it to completion
    const auto t0 = Clock::now();
    fn();
    glFinish();
    I.record(name, true, ms_since(t0));
}

void App::panel(std::function<void()> widgets) { impl_->widgets = std::move(widgets); }

void App::present(GLuint visibility) {
    Impl& I = *impl_;
    if (I.headless) {
        if (I.frame != I.frames - 1) return;
        // the last frame: the picture (a debug view at its own size) into an RGBA8 target, then PNG
        int w = I.gl->gpu.width, h = I.gl->gpu.height;
        if (I.shown > 0) {
            const DebugImage d = I.debug[I.shown - 1].second();
            if (d.texture && d.show != DebugImage::Show::Overlay) DebugShow::size_of(d.texture, w, h);
        }
        skgl::Target t;
        std::string why;
        if (!skgl::make_target(t, w, h, {GL_RGBA8}, 0, why)) {
            fail(why);
            return;
        }
        I.draw_view(visibility, t.fbo, w, h);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, t.fbo);
        std::vector<std::uint8_t> rgb(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 3);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadPixels(0, 0, w, h, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
        skgl::destroy_target(t);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        const std::string err = skgl::gl_error_string();
        if (!err.empty()) fail("present: " + err);
        else if (!skgl::write_png(I.out, w, h, 3, rgb.data())) fail("cannot write " + I.out);
        if (exit_code_ != 0) I.frames = I.frame;  // stop: the next next_frame() prints and ends
        return;
    }
#if SHADOWKIT_APP_GLFW
    int w = 0, h = 0;
    glfwGetFramebufferSize(I.win, &w, &h);
    I.draw_view(visibility, 0, w, h);
#if SHADOWKIT_APP_IMGUI
    if (I.imgui) {
        ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
        ImGui::SetNextWindowSize(ImVec2(400, 0), ImGuiCond_FirstUseEver);
        ImGui::Begin(I.title.c_str());
        ImGui::TextWrapped("%s", I.renderer.c_str());
        // scene
        const auto names = I.scene_names();
        std::vector<const char*> items;
        for (const auto& n : names) items.push_back(n.c_str());
        int current = static_cast<int>(std::find(names.begin(), names.end(), I.scene_name) - names.begin());
        if (current < static_cast<int>(names.size())) {
            if (ImGui::Combo("scene (N/P)", &current, items.data(), static_cast<int>(items.size())))
                I.pending_scene = current;
        } else {
            ImGui::Text("scene: %s", I.scene.name.c_str());
        }
        // the technique's settings, as bound by name
        ImGui::Separator();
        ImGui::TextUnformatted("settings");
        for (auto& e : params_.entries()) {
            const std::string now = e.get();
            if (e.kind == Params::Entry::Kind::Toggle) {
                bool on = now == "on";
                if (ImGui::Checkbox(e.name.c_str(), &on)) e.set_choice(on ? 1 : 0);
            } else if (e.kind == Params::Entry::Kind::Choice) {
                std::vector<const char*> opts;
                for (const auto& o : e.options) opts.push_back(o.c_str());
                int k = static_cast<int>(std::find(e.options.begin(), e.options.end(), now) - e.options.begin());
                if (ImGui::Combo(e.name.c_str(), &k, opts.data(), static_cast<int>(opts.size())) && k >= 0)
                    e.set_choice(static_cast<std::size_t>(k));
            } else if (e.integer) {
                int n = static_cast<int>(e.get_number());
                if (ImGui::SliderInt(e.name.c_str(), &n, static_cast<int>(e.min), static_cast<int>(e.max))) e.set_number(n);
            } else {
                float f = static_cast<float>(e.get_number());
                if (ImGui::SliderFloat(e.name.c_str(), &f, static_cast<float>(e.min), static_cast<float>(e.max), "%.4g"))
                    e.set_number(f);
            }
        }
        if (I.widgets) I.widgets();
        // debug views
        ImGui::Separator();
        ImGui::TextUnformatted("view (V)");
        const auto views = I.view_names();
        for (std::size_t k = 0; k < views.size(); ++k)
            if (ImGui::RadioButton(views[k].c_str(), I.shown == k)) I.shown = k;
        // the light
        ImGui::Separator();
        sk::Light& L = I.scene.light;
        ImGui::TextUnformatted("light (arrows, PageUp/PageDown)");
        if (L.type != sk::LightType::Directional) ImGui::DragFloat3("position", glm::value_ptr(L.position), 0.02f);
        if (L.type == sk::LightType::Directional) {
            // the headers' convention (light_position = (xyz, 0): xyz toward the light); the scene keeps
            // the way its rays travel, the opposite
            glm::vec3 toward = -L.direction;
            if (ImGui::DragFloat3("toward light", glm::value_ptr(toward), 0.01f))
                L.direction = glm::length(toward) < 1e-6f ? glm::vec3(0.f, -1.f, 0.f) : -toward;
        } else if (ImGui::DragFloat3("aim (rays travel)", glm::value_ptr(L.direction), 0.01f) &&
                   glm::length(L.direction) < 1e-6f) {
            L.direction = glm::vec3(0.f, -1.f, 0.f);
        }
        if (L.is_area()) ImGui::DragFloat("size", &L.size, 0.01f, 0.f, 100.f);
        // the time of every pass
        ImGui::Separator();
        ImGui::Text("time per pass, ms (%s)", I.timer_query ? "GL timer queries" : "glFinish + clock");
        if (ImGui::BeginTable("passes", 4, ImGuiTableFlags_SizingFixedFit)) {
            for (const Pass& p : I.passes) {
                double mean = 0.0;
                for (double v : p.ms) mean += v;
                mean /= double(std::max<std::size_t>(p.ms.size(), 1));
                ImGui::TableNextRow();
                ImGui::TableNextColumn();
                ImGui::TextUnformatted(p.gpu ? "GPU" : "CPU");
                ImGui::TableNextColumn();
                ImGui::TextUnformatted(p.name.c_str());
                ImGui::TableNextColumn();
                ImGui::Text("%.3f", p.ms.empty() ? 0.0 : p.ms.back());
                ImGui::TableNextColumn();
                ImGui::Text("mean %.3f", mean);
            }
            ImGui::EndTable();
        }
        ImGui::End();
        ImGui::Render();
        I.imgui_frame = false;
        ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    }
#endif
    glfwSetWindowTitle(I.win, ("shadowkit: " + I.title + " on " + I.scene.name + "  " + params_.label() + "  [" +
                               I.last_view_label + "]")
                                  .c_str());
    glfwSwapBuffers(I.win);
#else
    (void)visibility;
#endif
}

}  // namespace app
