// shadowkit-contact-bench [--frames N] [--sizes WxH,WxH,...] - the GPU cost of contact shadows
// (glsl/contact_shadow.glsl) against a 16-tap Poisson PCF pass (glsl/pcf.glsl) at the same
// resolution, in one run (issue 23: contact shadows must cost <= 0.3x the PCF pass).
//
// The scene: a floor under a 6 x 6 grid of boxes of three heights, seen from above at 45 degrees so
// that the floor fills the screen (no background pixel: every pixel does the full work), lit by a
// sun 35 degrees high. Every pass is a full-screen triangle that reads the camera's depth
// (GL_DEPTH_COMPONENT32F, as the samples' G-buffer), rebuilds the view position and writes one
// float:
//   empty     that much and nothing else (the pass's fixed cost, in every row below)
//   pcf16     the world position into a 2048^2 GL_DEPTH_COMPONENT32F map (hardware compare,
//             GL_LINEAR: every tap a 2x2 bilinear compare), sk_pcf_poisson with 16 taps of radius 3
//             texels rotated by interleaved gradient noise
//   old       sk_contact_shadow as samples/shadow_map ran it with contact=on before the aligned march (which
//             it now runs with max_steps 8): length 16 camera
//             pixels at the receiver, max_steps 32, thickness a tenth of the length, depth_step 0
//             (float32), interleaved-gradient jitter
//   aligned N sk_contact_shadow_aligned, the same length / thickness / jitter, max_steps N
//   half 8    an experiment, not a shipped function: aligned 8 at half resolution (one march per 2 x 2
//             block, from its lower-left pixel; (W/2) x (H/2) pass) ...
//   up 8      ... and its depth-aware upsample at full resolution: the block's result where the pixel's
//             window depth is within 1% of view depth of the block pixel's, else aligned 8 at the pixel
//             itself; the half-resolution cost is half 8 + up 8
// Timing: every frame is one pass closed by glFinish and timed with steady_clock (on llvmpipe GL
// timer queries mean nothing); 3 warm-up frames per pass, then --frames rounds (default 15) in which
// every pass runs once, in a rotating order (the machine is shared: within a round all passes see
// the same load); the median per pass. Before timing, every variant's image is compared with `old`
// (pixels with the same visibility).
#include <shadowkit/contact_shadow.hpp>

#include "gl.hpp"

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <functional>
#include <string>
#include <vector>

namespace {

const char* kSceneVS = R"(#version 450 core
layout(location = 0) in vec3 a_position;
uniform mat4 u_vp;
void main() { gl_Position = u_vp * vec4(a_position, 1.0); }
)";
const char* kSceneFS = R"(#version 450 core
void main() {}
)";
const char* kPassVS = R"(#version 450 core
void main() {
    vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
)";
// Shared by every pass: the camera depth and the view position at a pixel.
const char* kCommon = R"(
layout(binding = 0) uniform sampler2D u_depth;
uniform mat4 u_proj;
uniform mat4 u_inv_proj;
uniform mat4 u_inv_view;
uniform mat4 u_light_vp;
uniform vec4 u_view_light;
uniform float u_pixels;
uniform int u_steps;
float pixel_world(vec3 vp) { return 2.0 * -vp.z / (u_proj[1][1] * float(textureSize(u_depth, 0).y)); }
)";
const char* kEmptyFS = R"(
out float o_v;
void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    float win = texelFetch(u_depth, px, 0).r;
    vec3 vp = sk_contact_view_position(u_inv_proj, textureSize(u_depth, 0), px, win, false);
    o_v = vp.z < 0.0 ? 1.0 : 0.5;
}
)";
const char* kPcfFS = R"(
layout(binding = 1) uniform sampler2DShadow u_sm;
out float o_v;
void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    float win = texelFetch(u_depth, px, 0).r;
    vec3 vp = sk_contact_view_position(u_inv_proj, textureSize(u_depth, 0), px, win, false);
    vec4 c = u_light_vp * (u_inv_view * vec4(vp, 1.0));
    vec3 uvz = c.xyz / c.w * 0.5 + 0.5;
    uvz.z -= 1e-3;
    o_v = sk_pcf_poisson(u_sm, uvz, vec2(0.0), 3.0 / 2048.0, 16, 6.28318531 * sk_interleaved_gradient_noise(gl_FragCoord.xy));
}
)";
const char* kOldFS = R"(
out float o_v;
void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    float win = texelFetch(u_depth, px, 0).r;
    vec3 vp = sk_contact_view_position(u_inv_proj, textureSize(u_depth, 0), px, win, false);
    float len = u_pixels * pixel_world(vp);
    o_v = sk_contact_shadow(u_depth, u_proj, vp, u_view_light, len, u_steps, 0.1 * len, 0.0, false, sk_contact_noise(gl_FragCoord.xy));
}
)";
const char* kAlignedFS = R"(
out float o_v;
void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    float win = texelFetch(u_depth, px, 0).r;
    vec3 vp = sk_contact_view_position(u_inv_proj, textureSize(u_depth, 0), px, win, false);
    float len = u_pixels * pixel_world(vp);
    o_v = sk_contact_shadow_aligned(u_depth, u_proj, vp, u_view_light, len, u_steps, 0.1 * len, 0.0, false, sk_contact_noise(gl_FragCoord.xy));
}
)";



const char* kHalfFS = R"(
out float o_v;
void main() {
    ivec2 rep = ivec2(gl_FragCoord.xy) * 2;
    float win = texelFetch(u_depth, rep, 0).r;
    vec3 vp = sk_contact_view_position(u_inv_proj, textureSize(u_depth, 0), rep, win, false);
    float len = u_pixels * pixel_world(vp);
    o_v = sk_contact_shadow_aligned(u_depth, u_proj, vp, u_view_light, len, u_steps, 0.1 * len, 0.0, false, sk_contact_noise(vec2(rep) + 0.5));
}
)";
const char* kUpFS = R"(
layout(binding = 2) uniform sampler2D u_half;
out float o_v;
void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    ivec2 rep = (px / 2) * 2;
    float win = texelFetch(u_depth, px, 0).r;
    float win_rep = texelFetch(u_depth, rep, 0).r;
    float v = texelFetch(u_half, px / 2, 0).r;
    vec3 vp = sk_contact_view_position(u_inv_proj, textureSize(u_depth, 0), px, win, false);
    float tol = 0.01 * 0.5 * abs(u_proj[2][2] * u_proj[3][3] - u_proj[3][2] * u_proj[2][3]) / (-vp.z);
    if (!(abs(win_rep - win) <= tol)) {
        float len = u_pixels * pixel_world(vp);
        v = sk_contact_shadow_aligned(u_depth, u_proj, vp, u_view_light, len, u_steps, 0.1 * len, 0.0, false, sk_contact_noise(gl_FragCoord.xy));
    }
    o_v = v;
}
)";
struct Mesh {
    std::vector<float> pos;
    std::vector<std::uint32_t> idx;
    void quad(glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d) {
        const auto base = static_cast<std::uint32_t>(pos.size() / 3);
        for (glm::vec3 p : {a, b, c, d}) pos.insert(pos.end(), {p.x, p.y, p.z});
        idx.insert(idx.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    }
    void box(glm::vec3 l, glm::vec3 h) {
        quad({l.x, h.y, l.z}, {l.x, h.y, h.z}, {h.x, h.y, h.z}, {h.x, h.y, l.z});
        quad({l.x, l.y, h.z}, {h.x, l.y, h.z}, {h.x, h.y, h.z}, {l.x, h.y, h.z});
        quad({l.x, l.y, l.z}, {l.x, h.y, l.z}, {h.x, h.y, l.z}, {h.x, l.y, l.z});
        quad({h.x, l.y, l.z}, {h.x, h.y, l.z}, {h.x, h.y, h.z}, {h.x, l.y, h.z});
        quad({l.x, l.y, l.z}, {l.x, l.y, h.z}, {l.x, h.y, h.z}, {l.x, h.y, l.z});
    }
};

struct Pass {
    std::string name;
    GLuint prog = 0;
    bool compute = false;
    int steps = 0;
    std::vector<float> image;
    std::vector<double> ms;   // wall (steady_clock)
    std::vector<double> cpu;  // the process's CPU time (llvmpipe's threads are ours)
};

double cpu_ms() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

bool parse_sizes(const char* s, std::vector<glm::ivec2>& out) {
    out.clear();
    std::string str(s);
    std::size_t p = 0;
    while (p < str.size()) {
        const std::size_t e = std::min(str.find(',', p), str.size());
        int w = 0, h = 0;
        if (std::sscanf(str.substr(p, e - p).c_str(), "%dx%d", &w, &h) != 2 || w < 16 || h < 16 || w > 4096 || h > 4096)
            return false;
        out.push_back({w, h});
        p = e + 1;
    }
    return !out.empty();
}

}  // namespace

int main(int argc, char** argv) {
    int frames = 15;
    std::vector<glm::ivec2> sizes = {{400, 300}, {1280, 720}};
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--frames") && i + 1 < argc) {
            frames = std::max(1, std::atoi(argv[++i]));
        } else if (!std::strcmp(argv[i], "--sizes") && i + 1 < argc) {
            if (!parse_sizes(argv[++i], sizes)) {
                std::fprintf(stderr, "--sizes: WxH[,WxH...] with 16 <= W, H <= 4096\n");
                return 2;
            }
        } else {
            std::fprintf(stderr, "usage: shadowkit-contact-bench [--frames N] [--sizes WxH,WxH,...]\n");
            return 2;
        }
    }
    std::string why, log;
    auto ctx = skgl::create_context(why);
    if (!ctx) {
        std::printf("SKIPPED: no OpenGL 4.5 context: %s\n", why.c_str());
        return skgl::no_context_exit_code();
    }
    bool ok1 = false, ok2 = false;
    const std::string contact = skgl::read_text_file(std::string(SHADOWKIT_SOURCE_DIR) + "/glsl/contact_shadow.glsl", &ok1);
    const std::string pcf = skgl::read_text_file(std::string(SHADOWKIT_SOURCE_DIR) + "/glsl/pcf.glsl", &ok2);
    if (!ok1 || !ok2) {
        std::fprintf(stderr, "cannot read glsl/contact_shadow.glsl or glsl/pcf.glsl\n");
        return 1;
    }
    const std::string head = std::string("#version 450 core\n") + contact + pcf + kCommon;
    auto fragment = [&](const char* body) { return skgl::compile_program({{GL_VERTEX_SHADER, kPassVS}, {GL_FRAGMENT_SHADER, head + body}}, log); };
    std::vector<Pass> passes;
    passes.push_back({"empty", fragment(kEmptyFS), false, 0, {}, {}, {}});
    passes.push_back({"pcf16", fragment(kPcfFS), false, 0, {}, {}, {}});
    passes.push_back({"old 32", fragment(kOldFS), false, 32, {}, {}, {}});
    for (int n : {16, 8}) passes.push_back({"aligned " + std::to_string(n), fragment(kAlignedFS), false, n, {}, {}, {}});
    passes.push_back({"half 8", fragment(kHalfFS), false, 8, {}, {}, {}});
    passes.push_back({"up 8", fragment(kUpFS), false, 8, {}, {}, {}});
    for (const Pass& p : passes)
        if (!p.prog) {
            std::fprintf(stderr, "%s: %s\n", p.name.c_str(), log.c_str());
            return 1;
        }
    const GLuint scene_prog = skgl::compile_program({{GL_VERTEX_SHADER, kSceneVS}, {GL_FRAGMENT_SHADER, kSceneFS}}, log);
    if (!scene_prog) {
        std::fprintf(stderr, "scene: %s\n", log.c_str());
        return 1;
    }

    Mesh m;
    m.quad({-40, 0, -40}, {-40, 0, 40}, {40, 0, 40}, {40, 0, -40});
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j) {
            const glm::vec3 c(-5.0f + 2.0f * float(i), 0.0f, -6.0f + 2.0f * float(j));
            const float h = 0.3f + 0.5f * float((i + 2 * j) % 3);
            m.box(c - glm::vec3(0.4f, 0.0f, 0.4f), c + glm::vec3(0.4f, h, 0.4f));
        }
    std::vector<float> nrm(m.pos.size(), 0.0f);
    skgl::GpuMesh mesh = skgl::upload_mesh(m.pos.data(), nrm.data(), m.pos.size() / 3, m.idx.data(), m.idx.size());
    const glm::mat4 view = glm::lookAt(glm::vec3(0.0f, 7.0f, 7.0f), glm::vec3(0.0f, 0.0f, -1.0f), glm::vec3(0, 1, 0));
    const glm::vec3 sun = glm::normalize(glm::vec3(-0.6f, 0.7f, -0.4f));  // toward the light
    const glm::mat4 light_view = glm::lookAt(sun * 20.0f, glm::vec3(0.0f), glm::vec3(0, 1, 0));
    const glm::mat4 light_vp = glm::ortho(-14.0f, 14.0f, -14.0f, 14.0f, 1.0f, 40.0f) * light_view;

    // the 2048^2 map
    GLuint sm_fbo = 0;
    const GLuint sm = skgl::make_depth_texture(GL_TEXTURE_2D, 2048, 1, GL_LINEAR, GL_CLAMP_TO_BORDER);
    skgl::make_depth_framebuffers(GL_TEXTURE_2D, sm, 1, &sm_fbo);
    glUseProgram(scene_prog);
    glViewport(0, 0, 2048, 2048);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glClearDepth(1.0);
    glClear(GL_DEPTH_BUFFER_BIT);
    glUniformMatrix4fv(glGetUniformLocation(scene_prog, "u_vp"), 1, GL_FALSE, glm::value_ptr(light_vp));
    skgl::draw_mesh(mesh);
    GLuint vao = 0;
    glGenVertexArrays(1, &vao);

    std::printf("renderer: %s | median of %d frames after 3 warm-up, glFinish + steady_clock, passes interleaved\n",
                ctx->renderer.c_str(), frames);
    for (const glm::ivec2 sz : sizes) {
        const int W = sz.x, H = sz.y;
        const glm::mat4 proj = glm::perspective(0.9f, float(W) / float(H), 0.1f, 100.0f);
        skgl::Target cam, out;
        if (!skgl::make_target(cam, W, H, {}, GL_DEPTH_COMPONENT32F, why) || !skgl::make_target(out, W, H, {GL_R32F}, 0, why)) {
            std::fprintf(stderr, "target: %s\n", why.c_str());
            return 1;
        }
        skgl::Target half;
        if (!skgl::make_target(half, (W + 1) / 2, (H + 1) / 2, {GL_R32F}, 0, why)) return 1;
        GLuint out_tex = 0;
        glGenTextures(1, &out_tex);
        glBindTexture(GL_TEXTURE_2D, out_tex);
        glTexStorage2D(GL_TEXTURE_2D, 1, GL_R32F, W, H);
        glBindFramebuffer(GL_FRAMEBUFFER, cam.fbo);
        glViewport(0, 0, W, H);
        glEnable(GL_DEPTH_TEST);
        glDepthMask(GL_TRUE);
        glClear(GL_DEPTH_BUFFER_BIT);
        glUseProgram(scene_prog);
        glUniformMatrix4fv(glGetUniformLocation(scene_prog, "u_vp"), 1, GL_FALSE, glm::value_ptr(proj * view));
        skgl::draw_mesh(mesh);
        const std::vector<float> depth = skgl::read_depth_float(cam);
        const std::size_t background = std::size_t(std::count(depth.begin(), depth.end(), 1.0f));

        auto run = [&](Pass& p) {
            glUseProgram(p.prog);
            glBindTextureUnit(0, cam.depth);
            glBindTextureUnit(1, sm);
            auto U = [&](const char* n) { return glGetUniformLocation(p.prog, n); };
            glUniformMatrix4fv(U("u_proj"), 1, GL_FALSE, glm::value_ptr(proj));
            glUniformMatrix4fv(U("u_inv_proj"), 1, GL_FALSE, glm::value_ptr(glm::inverse(proj)));
            glUniformMatrix4fv(U("u_inv_view"), 1, GL_FALSE, glm::value_ptr(glm::inverse(view)));
            glUniformMatrix4fv(U("u_light_vp"), 1, GL_FALSE, glm::value_ptr(light_vp));
            glUniform4fv(U("u_view_light"), 1, glm::value_ptr(view * glm::vec4(sun, 0.0f)));
            glUniform1f(U("u_pixels"), 16.0f);
            glUniform1i(U("u_steps"), p.steps);
            if (p.compute) {
                glBindImageTexture(0, out_tex, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
                glDispatchCompute(GLuint((W + 15) / 16), GLuint((H + 15) / 16), 1);
                glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
            } else {
                const bool h = p.name.rfind("half", 0) == 0;
                glBindFramebuffer(GL_FRAMEBUFFER, h ? half.fbo : out.fbo);
                glViewport(0, 0, h ? (W + 1) / 2 : W, h ? (H + 1) / 2 : H);
                glBindTextureUnit(2, half.color[0]);
                glDisable(GL_DEPTH_TEST);
                glDepthMask(GL_FALSE);
                glBindVertexArray(vao);
                glDrawArrays(GL_TRIANGLES, 0, 3);
                glDepthMask(GL_TRUE);
            }
        };
        for (Pass& p : passes) {
            run(p);
            glFinish();
            if (p.compute) {
                p.image.assign(std::size_t(W) * H, 0.0f);
                glBindTexture(GL_TEXTURE_2D, out_tex);
                glPixelStorei(GL_PACK_ALIGNMENT, 1);
                glGetTexImage(GL_TEXTURE_2D, 0, GL_RED, GL_FLOAT, p.image.data());
            } else {
                p.image = p.name.rfind("half", 0) == 0 ? std::vector<float>(std::size_t(W) * H, 0.0f) : skgl::read_color_float(out, 0, 1);
            }
            p.ms.clear();
            p.cpu.clear();
            for (int w = 0; w < 2; ++w) {
                run(p);
                glFinish();
            }
        }
        const std::string err = skgl::gl_error_string();
        if (!err.empty()) {
            std::fprintf(stderr, "GL error: %s\n", err.c_str());
            return 1;
        }
        for (int r = 0; r < frames; ++r)
            for (std::size_t q = 0; q < passes.size(); ++q) {
                Pass& p = passes[(q + std::size_t(r)) % passes.size()];
                const double c0 = cpu_ms();
                const auto t0 = std::chrono::steady_clock::now();
                run(p);
                glFinish();
                p.ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
                p.cpu.push_back(cpu_ms() - c0);
            }
        const double pcf_ms = median(passes[1].ms), empty_ms = median(passes[0].ms), pcf_cpu = median(passes[1].cpu);
        std::printf("\n%dx%d (%zu background pixels), contact length 16 pixels:\n", W, H, background);
        std::printf("| pass | median ms | / pcf16 | (ms - empty) / (pcf16 - empty) | CPU ms | CPU / pcf16 | occluded | = old |\n|---|---:|---:|---:|---:|---:|---:|---:|\n");
        const std::vector<float>& old = passes[2].image;
        for (const Pass& p : passes) {
            const double ms = median(p.ms);
            std::size_t occ = 0, same = 0;
            for (std::size_t k = 0; k < p.image.size(); ++k) {
                occ += p.image[k] == 0.0f;
                same += p.image[k] == old[k];
            }
            const double cpu = median(p.cpu);
            std::printf("| %s | %.2f | %.3f | %.3f | %.2f | %.3f | ", p.name.c_str(), ms, ms / pcf_ms, (ms - empty_ms) / (pcf_ms - empty_ms),
                        cpu, cpu / pcf_cpu);
            if (p.name.rfind("half", 0) == 0)
                std::printf("- | - |\n");  // a half-resolution image: compared through `up 8`
            else
                std::printf("%zu | %.2f%% |\n", occ, 100.0 * double(same) / double(old.size()));
        }
        for (const Pass& p : passes)
            if (p.compute)
                for (const Pass& q : passes)
                    if (!q.compute && q.steps == p.steps && q.name.rfind("aligned", 0) == 0) {
                        std::size_t diff = 0;
                        for (std::size_t k = 0; k < p.image.size(); ++k) diff += p.image[k] != q.image[k];
                        std::printf("%s vs %s: %zu pixels differ\n", p.name.c_str(), q.name.c_str(), diff);
                    }
        glDeleteTextures(1, &out_tex);
        skgl::destroy_target(cam);
        skgl::destroy_target(out);
    }
    glDeleteVertexArrays(1, &vao);
    skgl::destroy_mesh(mesh);
    return 0;
}
