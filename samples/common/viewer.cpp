#include "viewer.hpp"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include "gl.hpp"
#include "scene.hpp"
#include "techniques.hpp"

namespace sk {

namespace {

struct ViewerOptions {
    std::string scene = "contact";
    bool headless = false;
    std::string out;  // PNG path (--out, or --headless's argument)
    int frames = 1;   // headless: frames rendered, the light moving between them; the last is written
    int width = 800, height = 600;
    ParamSet params;
    bool params_set = false;
    int view = 0;  // 0 shaded, k: the technique's k-th debug image
};

// Simple shading so the sample shows something a person recognises: albedo * (ambient + V * N.L).
std::vector<std::uint8_t> shade(const Scene& scene, const GBuffer& g, const std::vector<float>& v) {
    std::vector<std::uint8_t> rgb(g.kind.size() * 3);
    for (std::size_t k = 0; k < g.kind.size(); ++k) {
        glm::vec3 c(0.18f, 0.2f, 0.24f);
        if (g.kind[k] != 0) {
            const glm::vec3 p(g.position[3 * k], g.position[3 * k + 1], g.position[3 * k + 2]);
            const glm::vec3 n(g.normal[3 * k], g.normal[3 * k + 1], g.normal[3 * k + 2]);
            const glm::vec3 l = scene.light.type == LightType::Directional ? -glm::normalize(scene.light.direction)
                                                                           : glm::normalize(scene.light.position - p);
            const float ndl = std::max(0.f, glm::dot(n, l));
            const glm::vec3 albedo = g.kind[k] == 1 ? glm::vec3(0.85f, 0.82f, 0.75f) : glm::vec3(0.6f, 0.7f, 0.9f);
            c = albedo * (0.15f + 0.85f * v[k] * ndl);
        }
        for (int i = 0; i < 3; ++i)
            rgb[3 * k + static_cast<std::size_t>(i)] =
                static_cast<std::uint8_t>(std::lround(255.f * std::pow(std::clamp(c[i], 0.f, 1.f), 1.f / 2.2f)));
    }
    return rgb;
}

// view 0: the shaded scene; view k > 0: the technique's k-th debug image (if it has one). gpu / g:
// the scene's G-buffer (it depends on the camera and the meshes, not on the light).
bool render_prepared(const Scene& scene, const SceneGpu& gpu, const GBuffer& g, Technique& t, const ParamSet& ps, int w,
                     int h, int view, std::vector<std::uint8_t>& rgb, int& out_w, int& out_h, std::string& view_name,
                     std::string& why, double* cpu_ms = nullptr, double* gpu_ms = nullptr) {
    RunContext ctx{scene, gpu, 1, 0, &g, view > 0};
    RunResult r = t.run(ctx, ps);
    if (!r.ok) {
        why = r.error;
        return false;
    }
    if (cpu_ms) *cpu_ms = r.cpu_ms;
    if (gpu_ms) *gpu_ms = r.gpu_ms;
    if (view > 0 && static_cast<std::size_t>(view) <= r.debug.size()) {
        const DebugImage& d = r.debug[static_cast<std::size_t>(view - 1)];
        rgb = d.rgb;
        out_w = d.width;
        out_h = d.height;
        view_name = d.name;
        return true;
    }
    rgb = shade(scene, g, r.visibility);
    out_w = w;
    out_h = h;
    view_name = view > 0 ? "shaded (no debug image " + std::to_string(view) + ")" : "shaded";
    return true;
}

bool render(const Scene& scene, Technique& t, const ParamSet& ps, int w, int h, int view, std::vector<std::uint8_t>& rgb,
            int& out_w, int& out_h, std::string& view_name, std::string& why) {
    SceneGpu gpu;
    GBuffer g;
    if (!prepare_scene_gpu(scene, w, h, gpu, g, why)) return false;
    return render_prepared(scene, gpu, g, t, ps, w, h, view, rgb, out_w, out_h, view_name, why);
}

// The sweep entry plus the technique's live-only parameters (at their defaults, unless set).
ParamSet with_live_params(ParamSet ps, const Technique& t) {
    for (const auto& [k, v] : t.live_params()) {
        bool present = false;
        for (const auto& e : ps.values) present = present || e.first == k;
        if (!present) ps.values.emplace_back(k, v);
    }
    return ps;
}

struct Orbit {
    float yaw = 0.f, pitch = 0.f;
    bool dragging = false;
    double x = 0.0, y = 0.0;
};

}  // namespace

int run_viewer(int argc, char** argv, const std::string& technique_name) {
    return run_viewer(argc, argv, std::vector<std::string>{technique_name});
}

int run_viewer(int argc, char** argv, const std::vector<std::string>& technique_names) {
    ViewerOptions o;
    std::size_t tech_index = 0;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--scene" && i + 1 < argc) {
            o.scene = argv[++i];
        } else if (a == "--headless") {
            o.headless = true;
            if (i + 1 < argc && argv[i + 1][0] != '-') o.out = argv[++i];  // --headless OUT.png
        } else if (a == "--out" && i + 1 < argc) {
            o.out = argv[++i];
        } else if (a == "--frames" && i + 1 < argc) {
            o.frames = std::atoi(argv[++i]);
            if (o.frames < 1 || o.frames > 100000) {
                std::fprintf(stderr, "%s: --frames wants a count >= 1\n", argv[0]);
                return 2;
            }
        } else if (a == "--size" && i + 1 < argc) {
            if (std::sscanf(argv[++i], "%dx%d", &o.width, &o.height) != 2 || o.width <= 0 || o.height <= 0) {
                std::fprintf(stderr, "%s: --size wants WxH\n", argv[0]);
                return 2;
            }
        } else if (a == "--view" && i + 1 < argc) {
            o.view = std::atoi(argv[++i]);
        } else if (a == "--technique" && i + 1 < argc) {
            const std::string want = argv[++i];
            const auto it = std::find(technique_names.begin(), technique_names.end(), want);
            if (it == technique_names.end()) {
                std::fprintf(stderr, "%s: --technique must be one of this sample's techniques\n", argv[0]);
                return 2;
            }
            tech_index = static_cast<std::size_t>(it - technique_names.begin());
        } else if (a == "--param" && i + 1 < argc) {
            const std::string kv = argv[++i];
            const auto eq = kv.find('=');
            if (eq == std::string::npos) {
                std::fprintf(stderr, "%s: --param wants name=value\n", argv[0]);
                return 2;
            }
            o.params.values.emplace_back(kv.substr(0, eq), std::atof(kv.c_str() + eq + 1));
            o.params_set = true;
        } else {
            std::fprintf(stderr,
                         "usage: %s [--scene NAME] [--technique NAME] [--headless [OUT.png]] [--frames N] "
                         "[--out OUT.png] [--size WxH] [--param name=value]... [--view N]\n",
                         argv[0]);
            return a == "--help" ? 0 : 2;
        }
    }
    auto techniques = make_techniques();
    auto find_tech = [&](const std::string& name) -> Technique* {
        for (auto& t : techniques)
            if (t->name() == name) return t.get();
        return nullptr;
    };
    std::string technique_name = technique_names.at(tech_index);
    Technique* tech = find_tech(technique_name);
    if (!tech) {
        std::fprintf(stderr, "%s: technique '%s' is not built in\n", argv[0], technique_name.c_str());
        return 2;
    }
    Scene scene;
    if (!make_builtin_scene(o.scene, scene)) {
        std::fprintf(stderr, "%s: unknown scene '%s'\n", argv[0], o.scene.c_str());
        return 2;
    }
    auto sweep = tech->sweep(scene, false);
    ParamSet ps = with_live_params(o.params_set ? o.params : (sweep.empty() ? ParamSet{} : sweep[sweep.size() / 2]), *tech);
    std::string why;

    if (o.headless || !o.out.empty()) {
        if (o.out.empty()) o.out = "shot.png";
        auto gl = skgl::create_context(why);
        if (!gl) {
            std::fprintf(stderr, "%s: no headless GL context: %s\n", argv[0], why.c_str());
            return skgl::no_context_exit_code();  // 77: CTest skipped (1 under SHADOWKIT_REQUIRE_GL)
        }
        std::vector<std::uint8_t> rgb;
        int iw = 0, ih = 0;
        std::string view_name;
        // --frames N: the light turns about the vertical axis through the scene's centre, 360/N
        // degrees per frame, as a moving light would (frame 0 is the scene's own light); the last
        // frame is written; the technique's CPU and GPU times are reported as medians over frames
        const Scene base = scene;
        const glm::vec3 centre = 0.5f * (base.bounds_min() + base.bounds_max());
        std::vector<double> cpu(static_cast<std::size_t>(o.frames)), gpu(cpu.size());
        SceneGpu scene_gpu;  // the G-buffer does not depend on the light: prepared once
        GBuffer gbuf;
        if (!prepare_scene_gpu(scene, o.width, o.height, scene_gpu, gbuf, why)) {
            std::fprintf(stderr, "%s: %s\n", argv[0], why.c_str());
            return 1;
        }
        for (int f = 0; f < o.frames; ++f) {
            const float ang = 6.2831853f * float(f) / float(o.frames);
            const float c = std::cos(ang), sn = std::sin(ang);
            auto turn = [&](glm::vec3 v) { return glm::vec3(c * v.x + sn * v.z, v.y, -sn * v.x + c * v.z); };
            scene.light = base.light;
            if (f > 0) {
                scene.light.position = centre + turn(base.light.position - centre);
                scene.light.direction = turn(base.light.direction);
            }
            if (!render_prepared(scene, scene_gpu, gbuf, *tech, ps, o.width, o.height, o.view, rgb, iw, ih, view_name, why,
                                 &cpu[static_cast<std::size_t>(f)], &gpu[static_cast<std::size_t>(f)])) {
                std::fprintf(stderr, "%s: frame %d: %s\n", argv[0], f, why.c_str());
                return 1;
            }
        }
        if (o.view > 0) std::printf("%s: view %d = %s\n", argv[0], o.view, view_name.c_str());
        if (!skgl::write_png(o.out, iw, ih, 3, rgb.data())) {
            std::fprintf(stderr, "%s: cannot write %s\n", argv[0], o.out.c_str());
            return 1;
        }
        auto median = [](std::vector<double> v) {
            std::sort(v.begin(), v.end());
            return v[v.size() / 2];
        };
        std::printf("%s: %s on %s (%s), %d frame%s (median cpu %.3f ms, gpu %.3f ms) -> %s\n", argv[0],
                    technique_name.c_str(), o.scene.c_str(), ps.label().c_str(), o.frames, o.frames == 1 ? "" : "s",
                    median(cpu), median(gpu), o.out.c_str());
        return 0;
    }

    if (!glfwInit()) {
        std::fprintf(stderr, "%s: glfwInit failed (no display? use --headless --out OUT.png or xvfb-run)\n", argv[0]);
        return 1;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    GLFWwindow* win = glfwCreateWindow(o.width, o.height, ("shadowkit: " + technique_name).c_str(), nullptr, nullptr);
    if (!win) {
        std::fprintf(stderr, "%s: cannot create a GL 4.5 core window\n", argv[0]);
        glfwTerminate();
        return 1;
    }
    glfwMakeContextCurrent(win);
    glfwSwapInterval(1);
    const auto names = builtin_scene_names();
    std::size_t scene_index = static_cast<std::size_t>(
        std::find(names.begin(), names.end(), o.scene) - names.begin());
    Orbit orbit;
    const Camera base_camera = scene.camera;
    bool dirty = true;
    GLuint tex = 0, fbo = 0;
    glGenTextures(1, &tex);
    glGenFramebuffers(1, &fbo);
    int last_key_state[GLFW_KEY_LAST + 1] = {};
    int shown_w = 0, shown_h = 0;
    std::size_t param_index = 0;
    int view = o.view;
    while (!glfwWindowShouldClose(win)) {
        auto pressed = [&](int key) {
            const int s = glfwGetKey(win, key);
            const bool edge = s == GLFW_PRESS && last_key_state[key] != GLFW_PRESS;
            last_key_state[key] = s;
            return edge;
        };
        if (pressed(GLFW_KEY_ESCAPE)) break;
        if (pressed(GLFW_KEY_V)) {  // shaded scene -> the technique's debug images -> shaded
            view = view >= 3 ? 0 : view + 1;
            dirty = true;
        }
        for (int k = 0; k < 9; ++k)
            if (pressed(GLFW_KEY_1 + k) && static_cast<std::size_t>(k) < sweep.size()) {
                ps = with_live_params(sweep[static_cast<std::size_t>(k)], *tech);
                dirty = true;
            }
        // live parameters: Tab picks one of the technique's parameters, [ and ] step through the
        // values its sweep uses (e.g. smoothie t, PCSS taps and rotation, z-pass/z-fail method)
        if (pressed(GLFW_KEY_TAB) && !ps.values.empty()) {
            param_index = (param_index + 1) % ps.values.size();
            std::printf("parameter: %s\n", ps.values[param_index].first.c_str());
        }
        const bool up = pressed(GLFW_KEY_RIGHT_BRACKET), down = pressed(GLFW_KEY_LEFT_BRACKET);
        if ((up || down) && !ps.values.empty()) {
            param_index %= ps.values.size();
            auto& [pname, pvalue] = ps.values[param_index];
            std::vector<double> vals;
            for (const auto& e : sweep)
                for (const auto& [k, v] : e.values)
                    if (k == pname && std::find(vals.begin(), vals.end(), v) == vals.end()) vals.push_back(v);
            std::sort(vals.begin(), vals.end());
            auto it = std::find(vals.begin(), vals.end(), pvalue);
            if (vals.size() < 2) {
                // not swept (a live parameter such as light_scale): step by 25%
                pvalue = up ? (pvalue > 0.0 ? pvalue * 1.25 : 0.05) : (pvalue > 0.05 ? pvalue / 1.25 : 0.0);
                std::printf("%s = %g\n", pname.c_str(), pvalue);
                dirty = true;
            } else if (!vals.empty()) {
                std::size_t i = it == vals.end() ? 0 : static_cast<std::size_t>(it - vals.begin());
                i = up ? std::min(i + 1, vals.size() - 1) : (i == 0 ? 0 : i - 1);
                pvalue = vals[i];
                dirty = true;
            }
        }
        // move the light: arrow keys in x/z, PageUp/PageDown in y (a spot light keeps aiming at
        // the scene's centre)
        {
            glm::vec3 d(0.f);
            if (glfwGetKey(win, GLFW_KEY_LEFT) == GLFW_PRESS) d.x -= 1.f;
            if (glfwGetKey(win, GLFW_KEY_RIGHT) == GLFW_PRESS) d.x += 1.f;
            if (glfwGetKey(win, GLFW_KEY_UP) == GLFW_PRESS) d.z -= 1.f;
            if (glfwGetKey(win, GLFW_KEY_DOWN) == GLFW_PRESS) d.z += 1.f;
            if (glfwGetKey(win, GLFW_KEY_PAGE_UP) == GLFW_PRESS) d.y += 1.f;
            if (glfwGetKey(win, GLFW_KEY_PAGE_DOWN) == GLFW_PRESS) d.y -= 1.f;
            if (d != glm::vec3(0.f)) {
                const float step = 0.02f * glm::length(scene.bounds_max() - scene.bounds_min()) / 10.f;
                if (scene.light.type == LightType::Directional) {
                    scene.light.direction = glm::normalize(scene.light.direction + 0.5f * step * glm::vec3(d.x, -d.y, d.z));
                } else {
                    const glm::vec3 aim = 0.5f * (scene.bounds_min() + scene.bounds_max());
                    scene.light.position += step * d;
                    if (scene.light.type != LightType::Linear) scene.light.direction = glm::normalize(aim - scene.light.position);
                }
                dirty = true;
            }
        }
        if (pressed(GLFW_KEY_T) && technique_names.size() > 1) {
            tech_index = (tech_index + 1) % technique_names.size();
            technique_name = technique_names[tech_index];
            if (Technique* t = find_tech(technique_name)) {
                tech = t;
                sweep = tech->sweep(scene, false);
                ps = with_live_params(sweep.empty() ? ParamSet{} : sweep[sweep.size() / 2], *tech);
                dirty = true;
            }
        }
        const bool next = pressed(GLFW_KEY_N), prev = pressed(GLFW_KEY_P);
        if (next || prev) {
            scene_index = (scene_index + (next ? 1 : names.size() - 1)) % names.size();
            make_builtin_scene(names[scene_index], scene);
            sweep = tech->sweep(scene, false);
            if (!sweep.empty()) ps = with_live_params(sweep[sweep.size() / 2], *tech);
            dirty = true;
        }
        double mx, my;
        glfwGetCursorPos(win, &mx, &my);
        if (glfwGetMouseButton(win, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS) {
            if (orbit.dragging) {
                orbit.yaw += static_cast<float>(mx - orbit.x) * 0.01f;
                orbit.pitch = std::clamp(orbit.pitch + static_cast<float>(my - orbit.y) * 0.01f, -1.2f, 1.2f);
                dirty = dirty || mx != orbit.x || my != orbit.y;
            }
            orbit.dragging = true;
        } else {
            orbit.dragging = false;
        }
        orbit.x = mx;
        orbit.y = my;
        if (dirty) {
            Camera c = base_camera;
            const glm::vec3 off = c.eye - c.target;
            const float r = glm::length(off);
            const float yaw0 = std::atan2(off.x, off.z), pitch0 = std::asin(off.y / r);
            const float yaw = yaw0 + orbit.yaw, pitch = std::clamp(pitch0 + orbit.pitch, -1.4f, 1.4f);
            c.eye = c.target + r * glm::vec3(std::cos(pitch) * std::sin(yaw), std::sin(pitch), std::cos(pitch) * std::cos(yaw));
            scene.camera = c;
            int w, h;
            glfwGetFramebufferSize(win, &w, &h);
            std::vector<std::uint8_t> rgb;
            int iw = 0, ih = 0;
            std::string view_name;
            if (render(scene, *tech, ps, w, h, view, rgb, iw, ih, view_name, why)) {
                glBindTexture(GL_TEXTURE_2D, tex);
                glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
                glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB8, iw, ih, 0, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
                shown_w = iw;
                shown_h = ih;
                glfwSetWindowTitle(win, ("shadowkit: " + technique_name + " on " + scene.name + "  " + ps.label() +
                                         "  [" + view_name + "]")
                                            .c_str());
            } else {
                std::fprintf(stderr, "%s\n", why.c_str());
            }
            dirty = false;
        }
        if (shown_w > 0) {
            glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
            glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex, 0);
            glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
            int fw = 0, fh = 0;
            glfwGetFramebufferSize(win, &fw, &fh);
            glClear(GL_COLOR_BUFFER_BIT);
            glBlitFramebuffer(0, 0, shown_w, shown_h, 0, 0, fw, fh, GL_COLOR_BUFFER_BIT, GL_LINEAR);
            glfwSwapBuffers(win);
        }
        glfwWaitEventsTimeout(0.02);
    }
    glDeleteFramebuffers(1, &fbo);
    glDeleteTextures(1, &tex);
    glfwDestroyWindow(win);
    glfwTerminate();
    return 0;
}

}  // namespace sk
