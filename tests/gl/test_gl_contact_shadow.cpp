// Contact shadows on GL (glsl/contact_shadow.glsl) against the CPU mirror (contact_shadow.hpp):
//  (a) a floor with a box on it is rendered into a GL_DEPTH_COMPONENT24 texture by a perspective
//      camera; a full-screen pass runs sk_contact_shadow at every pixel (view position rebuilt from
//      the depth texel by sk_contact_view_position); the read-back visibility equals
//      contact_shadow_march run on the read-back depth buffer with the same inputs on >= 99.9% of
//      the pixels (the arithmetic is the same, operation for operation; the rest is float rounding
//      at a compare's edge);
//  (b) independent of both: floor pixels whose ray toward the light runs through the box (slab test
//      on the analytic box, shrunk by a margin) are occluded on the GPU, and floor pixels whose ray
//      the camera sees clear of the box (grown by a margin) everywhere are lit;
//  (c) the same function in a compute shader (8 x 8 groups, imageStore) gives the same image; the
//      fragment and compute passes are timed (glFinish + steady_clock medians; printed, not asserted);
//  (d) the pixel-aligned march (sk_contact_shadow_aligned), at 48 steps and at 8 with jitter 0.5,
//      equals its CPU mirror contact_shadow_march_aligned on >= 99.9% of the pixels and passes (b)'s
//      box checks (its cost: samples/bench/bench_contact_gl.cpp, docs/contact_shadow.md).
#include <doctest/doctest.h>

#include <shadowkit/contact_shadow.hpp>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "gl_test.hpp"

namespace {

constexpr int kW = 256, kH = 192;

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
// The per-pixel body shared by the fragment and the compute pass.
const char* kBody = R"(
uniform sampler2D u_depth;
uniform mat4 u_proj;
uniform mat4 u_inv_proj;
uniform vec4 u_view_light;
uniform float u_length;
uniform int u_steps;
uniform float u_depth_step;
uniform bool u_aligned;
uniform float u_jitter;
float contact_at(ivec2 px) {
    ivec2 size = textureSize(u_depth, 0);
    float win = texelFetch(u_depth, px, 0).r;
    if (win == 1.0) return -1.0;  // background
    vec3 view_pos = sk_contact_view_position(u_inv_proj, size, px, win, false);
    if (u_aligned)
        return sk_contact_shadow_aligned(u_depth, u_proj, view_pos, u_view_light, u_length, u_steps, 0.0, u_depth_step, false, u_jitter);
    return sk_contact_shadow(u_depth, u_proj, view_pos, u_view_light, u_length, u_steps, 0.0, u_depth_step, false, u_jitter);
}
)";
const char* kPassFS = R"(
out float o_v;
void main() { o_v = contact_at(ivec2(gl_FragCoord.xy)); }
)";
const char* kPassCS = R"(
layout(local_size_x = 8, local_size_y = 8) in;
layout(r32f, binding = 0) writeonly uniform image2D u_out;
void main() {
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(px, textureSize(u_depth, 0)))) return;
    imageStore(u_out, px, vec4(contact_at(px)));
}
)";

struct Box {
    glm::dvec3 lo, hi;
};

double hit_box(const Box& b, glm::dvec3 o, glm::dvec3 d) {
    double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 3; ++i) {
        if (d[i] == 0.0) {
            if (o[i] < b.lo[i] || o[i] > b.hi[i]) return std::numeric_limits<double>::infinity();
            continue;
        }
        double ta = (b.lo[i] - o[i]) / d[i], tb = (b.hi[i] - o[i]) / d[i];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    return t0 <= t1 ? t0 : std::numeric_limits<double>::infinity();
}

void add_quad(std::vector<float>& pos, std::vector<std::uint32_t>& idx, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d) {
    const auto base = static_cast<std::uint32_t>(pos.size() / 3);
    for (glm::vec3 p : {a, b, c, d}) pos.insert(pos.end(), {p.x, p.y, p.z});
    idx.insert(idx.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
}

GLint U(GLuint p, const char* n) { return glGetUniformLocation(p, n); }

using MarchFn = shadowkit::ContactShadowResult (*)(const float*, std::size_t, int, int, const glm::mat4&, glm::vec3, glm::vec4,
                                                   const shadowkit::ContactShadowParams&);

// What one GPU image says against the CPU mirror `cpu` on the same read-back depth and, independent of
// both, against the analytic box (floor receivers only).
struct Verdict {
    std::size_t fg = 0, agree = 0, occluded = 0, background_ok = 0, background = 0;
    std::size_t ref_occ = 0, ref_occ_ok = 0, ref_lit = 0, ref_lit_ok = 0;
};
Verdict verify(const std::vector<float>& gpu, const std::vector<float>& depth, MarchFn cpu, const shadowkit::ContactShadowParams& prm,
               const glm::mat4& proj, const glm::mat4& view, glm::vec4 view_light, const Box& box, glm::dvec3 eye, glm::dvec3 sun_dir) {
    Verdict v;
    const glm::mat4 inv_proj = glm::inverse(proj), inv_view = glm::inverse(view);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const std::size_t k = std::size_t(y) * kW + std::size_t(x);
            const float win = depth[k];
            if (win == 1.0f) {
                ++v.background;
                v.background_ok += gpu[k] == -1.0f;
                continue;
            }
            ++v.fg;
            const glm::vec2 ndc_xy = (glm::vec2(float(x), float(y)) + 0.5f) / glm::vec2(float(kW), float(kH)) * 2.0f - 1.0f;
            const glm::vec4 c = inv_proj * glm::vec4(ndc_xy, win * 2.0f - 1.0f, 1.0f);
            const glm::vec3 vp = glm::vec3(c) / c.w;
            const shadowkit::ContactShadowResult m = cpu(depth.data(), depth.size(), kW, kH, proj, vp, view_light, prm);
            if (m.status != shadowkit::Status::Ok) continue;  // counted as a disagreement
            v.agree += m.visibility == gpu[k];
            v.occluded += gpu[k] == 0.0f;
            const glm::dvec3 w(glm::vec3(inv_view * glm::vec4(vp, 1.0f)));
            if (std::fabs(w.y) > 1e-3) continue;
            const double margin = 0.06, L = prm.length_world;
            const Box small{box.lo + margin, box.hi - margin}, big{box.lo - margin, box.hi + margin};
            const double t_in = hit_box(small, w, sun_dir);
            if (t_in > 0.08 && t_in < L - 0.05) {
                ++v.ref_occ;
                v.ref_occ_ok += gpu[k] == 0.0f;
                continue;
            }
            bool near = false;
            for (int i = 0; i <= 200 && !near; ++i) {
                const glm::dvec3 q = w + (L * i / 200.0) * sun_dir;
                near = hit_box(big, eye, q - eye) < 1.0;
            }
            if (!near) {
                ++v.ref_lit;
                v.ref_lit_ok += gpu[k] == 1.0f;
            }
        }
    return v;
}


}  // namespace

TEST_CASE("contact shadows: the GLSL pass equals the CPU mirror on the read-back depth; a box shadows the floor; compute = fragment") {
    (void)gl_test_context();
    std::string log, why;
    bool ok = false;
    const std::string snippet = skgl::read_text_file(std::string(SHADOWKIT_GLSL_DIR) + "/contact_shadow.glsl", &ok);
    REQUIRE_MESSAGE(ok, "cannot read glsl/contact_shadow.glsl");
    const GLuint scene_prog = skgl::compile_program({{GL_VERTEX_SHADER, kSceneVS}, {GL_FRAGMENT_SHADER, kSceneFS}}, log);
    REQUIRE_MESSAGE(scene_prog != 0, log);
    const std::string head = std::string("#version 450 core\n") + snippet + kBody;
    const GLuint pass_prog = skgl::compile_program({{GL_VERTEX_SHADER, kPassVS}, {GL_FRAGMENT_SHADER, head + kPassFS}}, log);
    REQUIRE_MESSAGE(pass_prog != 0, log);
    const GLuint compute_prog = skgl::compile_program({{GL_COMPUTE_SHADER, head + kPassCS}}, log);
    REQUIRE_MESSAGE(compute_prog != 0, log);

    // the scene: a floor and a box on it (world space)
    const Box box{glm::dvec3(-0.5, 0.0, -0.4), glm::dvec3(0.5, 0.7, 0.4)};
    std::vector<float> pos;
    std::vector<std::uint32_t> idx;
    add_quad(pos, idx, {-6, 0, -6}, {-6, 0, 6}, {6, 0, 6}, {6, 0, -6});
    const glm::vec3 l(box.lo), h(box.hi);
    add_quad(pos, idx, {l.x, h.y, l.z}, {l.x, h.y, h.z}, {h.x, h.y, h.z}, {h.x, h.y, l.z});  // top
    add_quad(pos, idx, {l.x, l.y, h.z}, {h.x, l.y, h.z}, {h.x, h.y, h.z}, {l.x, h.y, h.z});  // +z
    add_quad(pos, idx, {l.x, l.y, l.z}, {l.x, h.y, l.z}, {h.x, h.y, l.z}, {h.x, l.y, l.z});  // -z
    add_quad(pos, idx, {h.x, l.y, l.z}, {h.x, h.y, l.z}, {h.x, h.y, h.z}, {h.x, l.y, h.z});  // +x
    add_quad(pos, idx, {l.x, l.y, l.z}, {l.x, l.y, h.z}, {l.x, h.y, h.z}, {l.x, h.y, l.z});  // -x
    std::vector<float> nrm(pos.size(), 0.0f);
    skgl::GpuMesh mesh = skgl::upload_mesh(pos.data(), nrm.data(), pos.size() / 3, idx.data(), idx.size());

    const glm::dvec3 eye(2.2, 2.0, 3.2);
    const glm::mat4 view = glm::lookAt(glm::vec3(eye), glm::vec3(0.0f, 0.2f, 0.0f), glm::vec3(0, 1, 0));
    const glm::mat4 proj = glm::perspective(0.9f, float(kW) / float(kH), 0.1f, 40.0f);
    const glm::mat4 inv_proj = glm::inverse(proj);
    const glm::dvec3 sun_dir = glm::normalize(glm::dvec3(-0.8, 0.55, -0.5));  // toward the light, low
    const glm::vec4 view_light = view * glm::vec4(glm::vec3(sun_dir), 0.0f);

    skgl::Target scene_t, out_t;
    REQUIRE_MESSAGE(skgl::make_target(scene_t, kW, kH, {}, GL_DEPTH_COMPONENT24, why), why);
    REQUIRE_MESSAGE(skgl::make_target(out_t, kW, kH, {GL_R32F}, 0, why), why);
    glBindFramebuffer(GL_FRAMEBUFFER, scene_t.fbo);
    glViewport(0, 0, kW, kH);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDisable(GL_CULL_FACE);
    glClearDepth(1.0);
    glClear(GL_DEPTH_BUFFER_BIT);
    glUseProgram(scene_prog);
    glUniformMatrix4fv(U(scene_prog, "u_vp"), 1, GL_FALSE, glm::value_ptr(proj * view));
    skgl::draw_mesh(mesh);
    const std::vector<float> depth = skgl::read_depth_float(scene_t);

    shadowkit::ContactShadowParams prm;
    prm.length_world = 0.6f;
    prm.max_steps = 48;
    prm.depth_format = shadowkit::DepthFormat::Fixed24;
    const shadowkit::ContactShadowDerived dv =
        shadowkit::contact_shadow_derive(kW, kH, proj, glm::vec3(0, 0, -3), view_light, prm);
    REQUIRE(dv.status == shadowkit::Status::Ok);

    bool aligned = false;
    float jitter = 0.0f;
    auto set_uniforms = [&](GLuint p) {
        glUseProgram(p);
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(GL_TEXTURE_2D, scene_t.depth);
        glUniform1i(U(p, "u_depth"), 0);
        glUniformMatrix4fv(U(p, "u_proj"), 1, GL_FALSE, glm::value_ptr(proj));
        glUniformMatrix4fv(U(p, "u_inv_proj"), 1, GL_FALSE, glm::value_ptr(inv_proj));
        glUniform4fv(U(p, "u_view_light"), 1, glm::value_ptr(view_light));
        glUniform1f(U(p, "u_length"), prm.length_world);
        glUniform1i(U(p, "u_steps"), prm.max_steps);
        glUniform1f(U(p, "u_depth_step"), dv.depth_step_window);
        glUniform1i(U(p, "u_aligned"), aligned ? 1 : 0);
        glUniform1f(U(p, "u_jitter"), jitter);
    };
    auto fragment_pass = [&]() {
        glBindFramebuffer(GL_FRAMEBUFFER, out_t.fbo);
        glViewport(0, 0, kW, kH);
        glDisable(GL_DEPTH_TEST);
        glDepthMask(GL_FALSE);
        set_uniforms(pass_prog);
        glDrawArrays(GL_TRIANGLES, 0, 3);
        glDepthMask(GL_TRUE);
    };
    GLuint vao = 0;
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    fragment_pass();
    const std::vector<float> gpu = skgl::read_color_float(out_t, 0, 1);
    REQUIRE(skgl::gl_error_string().empty());

    // (a) the CPU mirror on the read-back buffer, view position rebuilt as the GLSL does; (b) the box
    const Verdict v = verify(gpu, depth, shadowkit::contact_shadow_march, prm, proj, view, view_light, box, eye, sun_dir);
    MESSAGE("pixels with a surface " << v.fg << ", GPU == CPU mirror on " << v.agree << " (" << 100.0 * double(v.agree) / double(v.fg)
                                     << "%), occluded " << v.occluded << "; floor through the box: " << v.ref_occ_ok << " of "
                                     << v.ref_occ << " occluded; floor clear of it: " << v.ref_lit_ok << " of " << v.ref_lit << " lit");
    CHECK(v.background_ok == v.background);
    CHECK(v.fg > std::size_t(kW * kH / 2));
    CHECK(double(v.agree) >= 0.999 * double(v.fg));
    CHECK(v.ref_occ > 300);
    CHECK(v.ref_occ_ok == v.ref_occ);
    CHECK(v.ref_lit > 10000);
    CHECK(v.ref_lit_ok == v.ref_lit);

    // (d) the pixel-aligned march (sk_contact_shadow_aligned) against its CPU mirror and the box, one
    //     sample per pixel (48 steps) and every 4th pixel or so (8 steps, jitter 0.5: stride > 1)
    aligned = true;
    for (int steps : {48, 8}) {
        shadowkit::ContactShadowParams pa = prm;
        pa.max_steps = steps;
        pa.jitter = jitter = steps == 8 ? 0.5f : 0.0f;
        glUseProgram(pass_prog);
        glUniform1i(U(pass_prog, "u_steps"), steps);
        const int saved = prm.max_steps;
        prm.max_steps = steps;
        fragment_pass();
        prm.max_steps = saved;
        const std::vector<float> ga = skgl::read_color_float(out_t, 0, 1);
        const Verdict va = verify(ga, depth, shadowkit::contact_shadow_march_aligned, pa, proj, view, view_light, box, eye, sun_dir);
        std::size_t same_as_old = 0;
        for (std::size_t k = 0; k < ga.size(); ++k) same_as_old += ga[k] == gpu[k];
        MESSAGE("aligned, max_steps " << steps << ": GPU == CPU mirror on " << va.agree << " of " << va.fg << ", occluded " << va.occluded
                                      << "; floor through the box: " << va.ref_occ_ok << " of " << va.ref_occ
                                      << " occluded; floor clear of it: " << va.ref_lit_ok << " of " << va.ref_lit
                                      << " lit; same as sk_contact_shadow (48 steps) on " << same_as_old << " of " << ga.size());
        CHECK(va.background_ok == va.background);
        CHECK(double(va.agree) >= 0.999 * double(va.fg));
        CHECK(va.ref_occ > 300);
        CHECK(va.ref_occ_ok == va.ref_occ);
        CHECK(va.ref_lit > 10000);
        CHECK(va.ref_lit_ok == va.ref_lit);
    }
    aligned = false;
    jitter = 0.0f;

    // (c) the compute version: the same image; timings
    GLuint out_tex = 0;
    glGenTextures(1, &out_tex);
    glBindTexture(GL_TEXTURE_2D, out_tex);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_R32F, kW, kH);
    auto compute_pass = [&]() {
        set_uniforms(compute_prog);
        glBindImageTexture(0, out_tex, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
        glDispatchCompute((kW + 7) / 8, (kH + 7) / 8, 1);
        glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    };
    compute_pass();
    std::vector<float> cs(std::size_t(kW) * kH);
    glBindTexture(GL_TEXTURE_2D, out_tex);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTexImage(GL_TEXTURE_2D, 0, GL_RED, GL_FLOAT, cs.data());
    std::size_t same = 0;
    for (std::size_t k = 0; k < cs.size(); ++k) same += cs[k] == gpu[k];
    MESSAGE("compute == fragment on " << same << " of " << cs.size() << " pixels");
    CHECK(double(same) >= 0.999 * double(cs.size()));
    const double frag_ms = skgl::median_frame_ms(fragment_pass, 3, 15);
    const double comp_ms = skgl::median_frame_ms(compute_pass, 3, 15);
    MESSAGE("timing " << kW << "x" << kH << ", max_steps " << prm.max_steps << " (" << gl_test_context().renderer
                      << "): fragment " << frag_ms << " ms, compute " << comp_ms << " ms (median of 15)");
    REQUIRE(skgl::gl_error_string().empty());

    glDeleteTextures(1, &out_tex);
    glDeleteVertexArrays(1, &vao);
    skgl::destroy_mesh(mesh);
    skgl::destroy_target(scene_t);
    skgl::destroy_target(out_t);
    glDeleteProgram(scene_prog);
    glDeleteProgram(pass_prog);
    glDeleteProgram(compute_prog);
}
