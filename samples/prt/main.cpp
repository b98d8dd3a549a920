// Sample: precomputed radiance transfer shadows (include/shadowkit/prt.hpp +
// spherical_harmonics.hpp, glsl/prt.glsl). A lumpy blob and a box over a floor under a sky + sun
// environment: transfer vectors per vertex (order 5, Embree visibility), the environment in SH,
// rotated live; the GPU does one dot product per vertex.
//
//   sample_prt [--headless [OUT.png]] [--frames N] [--out OUT.png] [--size WxH] [--order 1..5]
//              [--strata N] [--yaw DEG] [--pitch DEG] [--no-shadows] [--exposure X]
//   headless: N frames (the environment turning 360/N degrees of yaw a frame), the last one written
//   to --out (default shot.png).
//   keys: arrows rotate the environment, 1-5 SH order, S shadows on/off, Esc quits.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <shadowkit/prt.hpp>
#include <shadowkit/spherical_harmonics.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "gl.hpp"
#include "prt_scene.hpp"

namespace sk = shadowkit;

namespace {

struct Options {
    bool headless = false;
    std::string out;
    int frames = 1;
    int width = 960, height = 640;
    int order = 5;
    int strata = 32;
    float yaw = 0.f, pitch = 0.f;  // degrees, environment rotation
    bool shadows = true;
    float exposure = 0.8f;
};

const char* kVertexMain = R"(
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_albedo;
uniform mat4 u_view_proj;
uniform vec3 u_env[25];
uniform int u_count;
uniform int u_stride;
out vec3 v_radiance;
void main() {
    v_radiance = a_albedo * sk_prt_shade_vertex(gl_VertexID, u_stride, u_count, u_env);
    gl_Position = u_view_proj * vec4(a_position, 1.0);
}
)";

const char* kFragmentMain = R"(
in vec3 v_radiance;
uniform float u_exposure;
layout(location = 0) out vec4 o_color;
void main() {
    vec3 c = 1.0 - exp(-max(v_radiance, vec3(0.0)) * u_exposure);
    o_color = vec4(pow(c, vec3(1.0 / 2.2)), 1.0);
}
)";

struct Renderer {
    GLuint program = 0, vao = 0, vbo = 0, ibo = 0, ssbo[2] = {0, 0};
    GLsizei index_count = 0;
    GLint loc_vp = -1, loc_env = -1, loc_count = -1, loc_stride = -1, loc_exposure = -1;

    bool init(const skprt::PrtScene& s, const std::vector<float>& shadowed, const std::vector<float>& unshadowed,
              std::string& why) {
        GLint blocks = 0;
        glGetIntegerv(GL_MAX_VERTEX_SHADER_STORAGE_BLOCKS, &blocks);
        if (blocks < 1) {
            why = "the GL implementation has no shader storage blocks in the vertex stage";
            return false;
        }
        bool ok = false;
        const std::string snippet = skgl::read_text_file(std::string(SHADOWKIT_SOURCE_DIR) + "/glsl/prt.glsl", &ok);
        if (!ok) {
            why = "cannot read glsl/prt.glsl";
            return false;
        }
        program = skgl::compile_program({{GL_VERTEX_SHADER, "#version 450 core\n" + snippet + kVertexMain},
                                         {GL_FRAGMENT_SHADER, std::string("#version 450 core\n") + kFragmentMain}},
                                        why);
        if (!program) return false;
        loc_vp = glGetUniformLocation(program, "u_view_proj");
        loc_env = glGetUniformLocation(program, "u_env");
        loc_count = glGetUniformLocation(program, "u_count");
        loc_stride = glGetUniformLocation(program, "u_stride");
        loc_exposure = glGetUniformLocation(program, "u_exposure");
        std::vector<float> vb;
        vb.reserve(s.positions.size() * 6);
        for (std::size_t i = 0; i < s.positions.size(); ++i)
            vb.insert(vb.end(), {s.positions[i].x, s.positions[i].y, s.positions[i].z, s.albedo[i].x, s.albedo[i].y,
                                 s.albedo[i].z});
        glGenVertexArrays(1, &vao);
        glBindVertexArray(vao);
        glGenBuffers(1, &vbo);
        glBindBuffer(GL_ARRAY_BUFFER, vbo);
        glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vb.size() * sizeof(float)), vb.data(), GL_STATIC_DRAW);
        glGenBuffers(1, &ibo);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ibo);
        glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(s.indices.size() * sizeof(std::uint32_t)),
                     s.indices.data(), GL_STATIC_DRAW);
        glEnableVertexAttribArray(0);
        glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
        glEnableVertexAttribArray(1);
        glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), reinterpret_cast<const void*>(3 * sizeof(float)));
        glBindVertexArray(0);
        index_count = static_cast<GLsizei>(s.indices.size());
        glGenBuffers(2, ssbo);
        const std::vector<float>* data[2] = {&shadowed, &unshadowed};
        for (int k = 0; k < 2; ++k) {
            glBindBuffer(GL_SHADER_STORAGE_BUFFER, ssbo[k]);
            glBufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(data[k]->size() * sizeof(float)),
                         data[k]->data(), GL_STATIC_DRAW);
        }
        why = skgl::gl_error_string();
        return why.empty();
    }

    void draw(int w, int h, const glm::mat4& view_proj, const std::vector<glm::vec3>& env, int order, bool shadows,
              float exposure) const {
        glViewport(0, 0, w, h);
        glClearColor(0.05f, 0.06f, 0.08f, 1.f);
        glClearDepth(1.0);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        glEnable(GL_CULL_FACE);
        glUseProgram(program);
        glUniformMatrix4fv(loc_vp, 1, GL_FALSE, glm::value_ptr(view_proj));
        glUniform3fv(loc_env, 25, glm::value_ptr(env[0]));
        glUniform1i(loc_count, order * order);
        glUniform1i(loc_stride, 25);
        glUniform1f(loc_exposure, exposure);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, ssbo[shadows ? 0 : 1]);
        glBindVertexArray(vao);
        glDrawElements(GL_TRIANGLES, index_count, GL_UNSIGNED_INT, nullptr);
        glBindVertexArray(0);
        glUseProgram(0);
    }

    void destroy() {
        if (ssbo[0]) glDeleteBuffers(2, ssbo);
        if (ibo) glDeleteBuffers(1, &ibo);
        if (vbo) glDeleteBuffers(1, &vbo);
        if (vao) glDeleteVertexArrays(1, &vao);
        if (program) glDeleteProgram(program);
    }
};

// The environment's SH vector (order 5, RGB) turned by yaw (about y) then pitch (about x).
std::vector<glm::vec3> rotated_environment(const std::vector<glm::vec3>& env, float yaw_deg, float pitch_deg) {
    const glm::mat3 R = glm::mat3(glm::rotate(glm::mat4(1.f), glm::radians(yaw_deg), glm::vec3(0, 1, 0)) *
                                  glm::rotate(glm::mat4(1.f), glm::radians(pitch_deg), glm::vec3(1, 0, 0)));
    const sk::SHRotation rot = sk::sh_make_rotation(5, R);
    std::vector<glm::vec3> out(25, glm::vec3(0.f));
    if (rot.status != sk::Status::Ok) return env;
    for (int c = 0; c < 3; ++c) {
        float ch[25];
        for (std::size_t i = 0; i < 25; ++i) ch[i] = env[i][c];
        sk::sh_rotate(rot, ch, 25, ch, 25);
        for (std::size_t i = 0; i < 25; ++i) out[i][c] = ch[i];
    }
    return out;
}

glm::mat4 view_proj(int w, int h) {
    const glm::mat4 view = glm::lookAt(glm::vec3(2.3f, 2.4f, 3.6f), glm::vec3(0.15f, 0.35f, 0.f), glm::vec3(0, 1, 0));
    const glm::mat4 proj = glm::perspective(0.75f, static_cast<float>(w) / static_cast<float>(std::max(h, 1)), 0.05f, 50.f);
    return proj * view;
}

int usage(const char* argv0, int rc) {
    std::fprintf(stderr,
                 "usage: %s [--headless [OUT.png]] [--frames N] [--out OUT.png] [--size WxH] [--order 1..5]\n"
                 "          [--strata N] [--yaw DEG] [--pitch DEG] [--no-shadows] [--exposure X]\n"
                 "keys: arrows rotate the environment, 1-5 SH order, S shadows on/off, Esc quits\n",
                 argv0);
    return rc;
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const bool has = i + 1 < argc;
        if (a == "--headless") {
            o.headless = true;
            if (has && argv[i + 1][0] != '-') o.out = argv[++i];
        } else if (a == "--out" && has) {
            o.out = argv[++i];
        } else if (a == "--frames" && has) {
            o.frames = std::atoi(argv[++i]);
            if (o.frames < 1 || o.frames > 100000) return usage(argv[0], 2);
        } else if (a == "--size" && has) {
            if (std::sscanf(argv[++i], "%dx%d", &o.width, &o.height) != 2 || o.width <= 0 || o.height <= 0)
                return usage(argv[0], 2);
        } else if (a == "--order" && has) {
            o.order = std::atoi(argv[++i]);
            if (o.order < 1 || o.order > 5) return usage(argv[0], 2);
        } else if (a == "--strata" && has) {
            o.strata = std::atoi(argv[++i]);
            if (o.strata < 1 || o.strata > 1024) return usage(argv[0], 2);
        } else if (a == "--yaw" && has) {
            o.yaw = static_cast<float>(std::atof(argv[++i]));
        } else if (a == "--pitch" && has) {
            o.pitch = static_cast<float>(std::atof(argv[++i]));
        } else if (a == "--exposure" && has) {
            o.exposure = static_cast<float>(std::atof(argv[++i]));
        } else if (a == "--no-shadows") {
            o.shadows = false;
        } else {
            return usage(argv[0], a == "--help" ? 0 : 2);
        }
    }

    // ---- precomputation (CPU, Embree)
    const skprt::PrtScene scene = skprt::make_prt_scene(1);
    skprt::EmbreeVisibility vis;
    std::string why;
    if (!vis.build(scene, why)) {
        std::fprintf(stderr, "%s: %s\n", argv[0], why.c_str());
        return 1;
    }
    const sk::PrtSamples samples = sk::prt_make_samples(5, o.strata, 1u);
    if (samples.status != sk::Status::Ok) return usage(argv[0], 2);
    std::vector<float> shadowed, unshadowed;
    double secs = 0.0, secs_un = 0.0;
    const auto tr = skprt::compute_transfer(scene, vis, samples, sk::PrtMode::Shadowed, shadowed, secs);
    skprt::compute_transfer(scene, vis, samples, sk::PrtMode::Unshadowed, unshadowed, secs_un, false);
    std::printf("%s: %zu vertices, order 5 transfer from %zu directions: %.2f s (%.1f Mrays)\n", argv[0],
                scene.positions.size(), samples.count(), secs, static_cast<double>(tr.rays) * 1e-6);
    const skprt::Environment env_fn;
    const sk::PrtSamples env_samples = sk::prt_make_samples(5, 128, 7u);
    std::vector<glm::vec3> env(25);
    sk::prt_project_environment(env_samples, env_fn, env.data(), env.size());

    // ---- headless: N frames on EGL, the last one to a PNG
    if (o.headless || !o.out.empty()) {
        if (o.out.empty()) o.out = "shot.png";
        auto gl = skgl::create_context(why);
        if (!gl) {
            std::fprintf(stderr, "%s: no headless GL context: %s\n", argv[0], why.c_str());
            return skgl::no_context_exit_code();  // 77: CTest skipped (1 under SHADOWKIT_REQUIRE_GL)
        }
        Renderer r;
        skgl::Target t;
        if (!r.init(scene, shadowed, unshadowed, why) ||
            !skgl::make_target(t, o.width, o.height, {GL_RGBA8}, GL_DEPTH_COMPONENT24, why)) {
            std::fprintf(stderr, "%s: %s\n", argv[0], why.c_str());
            return 1;
        }
        glBindFramebuffer(GL_FRAMEBUFFER, t.fbo);
        for (int f = 0; f < o.frames; ++f)
            r.draw(o.width, o.height, view_proj(o.width, o.height),
                   rotated_environment(env, o.yaw + 360.f * float(f) / float(o.frames), o.pitch), o.order, o.shadows,
                   o.exposure);
        const std::vector<float> px = skgl::read_color_float(t, 0, 4);
        std::vector<std::uint8_t> rgb(static_cast<std::size_t>(o.width) * static_cast<std::size_t>(o.height) * 3);
        for (std::size_t k = 0; k < rgb.size() / 3; ++k)
            for (std::size_t c = 0; c < 3; ++c)
                rgb[3 * k + c] = static_cast<std::uint8_t>(std::lround(255.f * std::clamp(px[4 * k + c], 0.f, 1.f)));
        const std::string err = skgl::gl_error_string();
        r.destroy();
        skgl::destroy_target(t);
        if (!err.empty()) {
            std::fprintf(stderr, "%s: GL error %s\n", argv[0], err.c_str());
            return 1;
        }
        if (!skgl::write_png(o.out, o.width, o.height, 3, rgb.data())) {
            std::fprintf(stderr, "%s: cannot write %s\n", argv[0], o.out.c_str());
            return 1;
        }
        std::printf("%s: order %d, %s, environment yaw %.0f pitch %.0f, %d frame(s) -> %s (%s)\n", argv[0], o.order,
                    o.shadows ? "shadowed" : "unshadowed", static_cast<double>(o.yaw), static_cast<double>(o.pitch),
                    o.frames, o.out.c_str(), gl->renderer.c_str());
        return 0;
    }

    // ---- window
    if (!glfwInit()) {
        std::fprintf(stderr, "%s: glfwInit failed (no display? use --headless --out OUT.png or xvfb-run)\n", argv[0]);
        return 1;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    GLFWwindow* win = glfwCreateWindow(o.width, o.height, "shadowkit: PRT", nullptr, nullptr);
    if (!win) {
        std::fprintf(stderr, "%s: cannot create a GL 4.5 core window\n", argv[0]);
        glfwTerminate();
        return 1;
    }
    glfwMakeContextCurrent(win);
    glfwSwapInterval(1);
    Renderer r;
    if (!r.init(scene, shadowed, unshadowed, why)) {
        std::fprintf(stderr, "%s: %s\n", argv[0], why.c_str());
        glfwDestroyWindow(win);
        glfwTerminate();
        return 1;
    }
    int last[GLFW_KEY_LAST + 1] = {};
    double t_prev = glfwGetTime();
    while (!glfwWindowShouldClose(win)) {
        auto pressed = [&](int key) {
            const int s = glfwGetKey(win, key);
            const bool edge = s == GLFW_PRESS && last[key] != GLFW_PRESS;
            last[key] = s;
            return edge;
        };
        if (pressed(GLFW_KEY_ESCAPE)) break;
        for (int k = 0; k < 5; ++k)
            if (pressed(GLFW_KEY_1 + k)) o.order = k + 1;
        if (pressed(GLFW_KEY_S)) o.shadows = !o.shadows;
        const double t_now = glfwGetTime();
        const float dt = static_cast<float>(t_now - t_prev), speed = 60.f;  // degrees per second
        t_prev = t_now;
        if (glfwGetKey(win, GLFW_KEY_LEFT) == GLFW_PRESS) o.yaw -= speed * dt;
        if (glfwGetKey(win, GLFW_KEY_RIGHT) == GLFW_PRESS) o.yaw += speed * dt;
        if (glfwGetKey(win, GLFW_KEY_UP) == GLFW_PRESS) o.pitch = std::min(o.pitch + speed * dt, 90.f);
        if (glfwGetKey(win, GLFW_KEY_DOWN) == GLFW_PRESS) o.pitch = std::max(o.pitch - speed * dt, -90.f);
        int w, h;
        glfwGetFramebufferSize(win, &w, &h);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        r.draw(w, h, view_proj(w, h), rotated_environment(env, o.yaw, o.pitch), o.order, o.shadows, o.exposure);
        char title[160];
        std::snprintf(title, sizeof title, "shadowkit: PRT  order %d  %s  yaw %.0f pitch %.0f  (precompute %.2f s)",
                      o.order, o.shadows ? "shadowed" : "unshadowed", static_cast<double>(o.yaw),
                      static_cast<double>(o.pitch), secs);
        glfwSetWindowTitle(win, title);
        glfwSwapBuffers(win);
        glfwPollEvents();
    }
    r.destroy();
    glfwDestroyWindow(win);
    glfwTerminate();
    return 0;
}
