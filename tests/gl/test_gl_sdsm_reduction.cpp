// glsl/cascades.glsl's SDSM reduction on the GL driver: sk_sdsm_reduce_depth on a DEPTH32F depth
// buffer, then sk_sdsm_reduce_minmax level by level down to 1x1, against the CPU min/max of the same
// depth values (the non-background ones), which must be equal exactly (min and max are exact in float,
// texelFetch of a DEPTH32F / RG32F texel returns the stored float). Odd sizes (partial blocks at the
// edges), blocks of 2 to 16, background 1.0 (and 0.0 for reversed-Z), a single receiver pixel in a
// corner, and an all-background buffer (the empty marker, which cascade_sdsm_view_range reads as
// nothing visible). One case draws triangles into the depth buffer (depth test on) and reads it back
// with glReadPixels for the CPU side. The second reduction (sk_sdsm_reduce_bounds, then
// sk_sdsm_reduce_bounds_level) against the CPU's per-cascade light-space bounds of the same pixels'
// world points (computed in double from the same float depths; pixels within 1e-3 of a split left
// out so that float rounding cannot move one across), within 1e-3 world units.
#include <doctest/doctest.h>

#include <shadowkit/cascades.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "gl_test.hpp"

namespace {

const char* kVs = R"(
void main() {
    vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
)";
const char* kFirst = R"(
uniform sampler2D u_src;
uniform int u_block;
uniform float u_background;
out vec2 o_minmax;
void main() { o_minmax = sk_sdsm_reduce_depth(u_src, ivec2(gl_FragCoord.xy), u_block, u_background); }
)";
const char* kNext = R"(
uniform sampler2D u_src;
uniform int u_block;
out vec2 o_minmax;
void main() { o_minmax = sk_sdsm_reduce_minmax(u_src, ivec2(gl_FragCoord.xy), u_block); }
)";

struct Programs {
    GLuint first = 0, next = 0;
};

Programs& programs(int version) {
    static Programs p[2];
    Programs& q = p[version == 330 ? 0 : 1];
    if (!q.first) {
        std::string log;
        const std::string head = "#version " + std::to_string(version) + " core\n";
        const std::string snip = skgl::read_text_file(std::string(SHADOWKIT_GLSL_DIR) + "/cascades.glsl");
        q.first = skgl::compile_program({{GL_VERTEX_SHADER, head + kVs}, {GL_FRAGMENT_SHADER, head + snip + kFirst}}, log);
        REQUIRE_MESSAGE(q.first != 0, log);
        q.next = skgl::compile_program({{GL_VERTEX_SHADER, head + kVs}, {GL_FRAGMENT_SHADER, head + snip + kNext}}, log);
        REQUIRE_MESSAGE(q.next != 0, log);
    }
    return q;
}

// The reduction's passes over depth texture `depth` (w x h): returns the 1x1 level's (min, max).
glm::vec2 reduce(GLuint depth, int w, int h, int block, float background, int version) {
    Programs& p = programs(version);
    GLuint vao = 0;
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    GLuint src = depth;
    std::vector<skgl::Target> levels;
    levels.reserve(16);
    bool first = true;
    while (first || w > 1 || h > 1) {
        w = (w + block - 1) / block;
        h = (h + block - 1) / block;
        levels.emplace_back();
        std::string why;
        REQUIRE(skgl::make_target(levels.back(), w, h, {GL_RG32F}, 0, why));
        skgl::set_nearest_clamped(levels.back().color[0]);
        glBindFramebuffer(GL_FRAMEBUFFER, levels.back().fbo);
        glViewport(0, 0, w, h);
        const GLuint prog = first ? p.first : p.next;
        glUseProgram(prog);
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(GL_TEXTURE_2D, src);
        glUniform1i(glGetUniformLocation(prog, "u_src"), 0);
        glUniform1i(glGetUniformLocation(prog, "u_block"), block);
        if (first) glUniform1f(glGetUniformLocation(prog, "u_background"), background);
        glDrawArrays(GL_TRIANGLES, 0, 3);
        src = levels.back().color[0];
        first = false;
    }
    float out[2] = {0.f, 0.f};
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glReadPixels(0, 0, 1, 1, GL_RG, GL_FLOAT, out);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    for (skgl::Target& t : levels) skgl::destroy_target(t);
    glDeleteVertexArrays(1, &vao);
    return {out[0], out[1]};
}

GLuint depth_texture(const std::vector<float>& d, int w, int h) {
    GLuint t = 0;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_DEPTH_COMPONENT32F, w, h);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, w, h, GL_DEPTH_COMPONENT, GL_FLOAT, d.data());
    skgl::set_nearest_clamped(t);
    return t;
}

// CPU reference: min and max of the values that are not `background`; the empty marker without any.
glm::vec2 cpu_minmax(const std::vector<float>& d, float background) {
    glm::vec2 r(shadowkit::kCascadeSdsmEmptyMin, shadowkit::kCascadeSdsmEmptyMax);
    for (float v : d)
        if (v != background) r = glm::vec2(std::min(r.x, v), std::max(r.y, v));
    return r;
}

}  // namespace

TEST_CASE("sdsm reduction: GPU min/max equals the CPU's exactly on random depth buffers") {
    (void)gl_test_context();
    std::mt19937 rng(25);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const int sizes[][2] = {{301, 173}, {64, 64}, {1, 1}, {17, 1}, {1000, 3}, {513, 257}};
    const int blocks[] = {2, 4, 8, 16};
    int cases = 0;
    for (const auto& s : sizes)
        for (int block : blocks)
            for (float background : {1.0f, 0.0f}) {
                const int w = s[0], h = s[1];
                std::vector<float> d(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
                const float lo = 0.2f * u(rng), hi = 0.8f + 0.2f * u(rng);
                for (float& v : d) v = u(rng) < 0.3f ? background : lo + (hi - lo) * u(rng);
                d[0] = 0.5f;  // at least one receiver
                const GLuint t = depth_texture(d, w, h);
                for (int version : {330, 450}) {
                    const glm::vec2 g = reduce(t, w, h, block, background, version);
                    const glm::vec2 c = cpu_minmax(d, background);
                    INFO("size " << w << "x" << h << " block " << block << " background " << background << " GLSL " << version);
                    CHECK(g.x == c.x);
                    CHECK(g.y == c.y);
                    ++cases;
                }
                glDeleteTextures(1, &t);
            }
    CHECK(cases == 96);
}

TEST_CASE("sdsm reduction: one receiver in the far corner, and nothing but background") {
    (void)gl_test_context();
    const int w = 250, h = 131;
    std::vector<float> d(static_cast<std::size_t>(w * h), 1.0f);
    d.back() = 0.123456789f;  // the last texel: the last partial block of every level
    GLuint t = depth_texture(d, w, h);
    glm::vec2 g = reduce(t, w, h, 8, 1.0f, 450);
    CHECK(g.x == 0.123456789f);
    CHECK(g.y == 0.123456789f);
    glDeleteTextures(1, &t);
    std::fill(d.begin(), d.end(), 1.0f);
    t = depth_texture(d, w, h);
    g = reduce(t, w, h, 8, 1.0f, 450);
    CHECK(g.x == shadowkit::kCascadeSdsmEmptyMin);
    CHECK(g.y == shadowkit::kCascadeSdsmEmptyMax);
    const shadowkit::CascadeSdsmRange r = shadowkit::cascade_sdsm_view_range(
        glm::mat4(1.0f), shadowkit::ClipDepth::NegativeOneToOne, false, g.x, g.y);
    CHECK(r.status == shadowkit::Status::Ok);
    CHECK_FALSE(r.visible);
    glDeleteTextures(1, &t);
}

TEST_CASE("sdsm reduction: a rendered depth buffer, read back with glReadPixels") {
    (void)gl_test_context();
    const int w = 320, h = 200;
    skgl::Target tgt;
    std::string why;
    REQUIRE(skgl::make_target(tgt, w, h, {}, GL_DEPTH_COMPONENT32F, why));
    const char* vs = R"(#version 450 core
layout(location = 0) in vec3 a_p;
void main() { gl_Position = vec4(a_p, 1.0); }
)";
    const char* fs = "#version 450 core\nvoid main() {}\n";
    std::string log;
    const GLuint prog = skgl::compile_program({{GL_VERTEX_SHADER, vs}, {GL_FRAGMENT_SHADER, fs}}, log);
    REQUIRE_MESSAGE(prog != 0, log);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-0.9f, 0.9f);
    std::vector<float> tri;
    for (int i = 0; i < 12 * 3; ++i) {
        tri.push_back(u(rng));
        tri.push_back(u(rng));
        tri.push_back(u(rng));
    }
    GLuint vao = 0, vbo = 0;
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    glGenBuffers(1, &vbo);
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(tri.size() * sizeof(float)), tri.data(), GL_STATIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
    glBindFramebuffer(GL_FRAMEBUFFER, tgt.fbo);
    glViewport(0, 0, w, h);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glClearDepth(1.0);
    glClear(GL_DEPTH_BUFFER_BIT);
    glUseProgram(prog);
    glDrawArrays(GL_TRIANGLES, 0, 12 * 3);
    std::vector<float> d(static_cast<std::size_t>(w * h));
    glReadPixels(0, 0, w, h, GL_DEPTH_COMPONENT, GL_FLOAT, d.data());
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    const glm::vec2 c = cpu_minmax(d, 1.0f);
    REQUIRE(c.x < c.y);  // triangles were drawn
    const glm::vec2 g = reduce(tgt.depth, w, h, 8, 1.0f, 450);
    CHECK(g.x == c.x);
    CHECK(g.y == c.y);
    glDeleteBuffers(1, &vbo);
    glDeleteVertexArrays(1, &vao);
    glDeleteProgram(prog);
    skgl::destroy_target(tgt);
}

namespace {

const char* kBoundsFirst = R"(
uniform sampler2D u_src;
uniform mat4 u_clip_to_world;
uniform mat4 u_world_to_view;
uniform mat4 u_world_to_light;
uniform vec4 u_split_far;
uniform int u_count;
layout(location = 0) out vec4 o_b0;
layout(location = 1) out vec4 o_b1;
layout(location = 2) out vec4 o_b2;
layout(location = 3) out vec4 o_b3;
void main() {
    vec4 b[4];
    sk_sdsm_reduce_bounds(u_src, ivec2(gl_FragCoord.xy), 4, 1.0, u_clip_to_world, u_world_to_view, u_world_to_light,
                          u_split_far, u_count, false, b);
    o_b0 = b[0]; o_b1 = b[1]; o_b2 = b[2]; o_b3 = b[3];
}
)";
const char* kBoundsNext = R"(
uniform sampler2D u_l0;
uniform sampler2D u_l1;
uniform sampler2D u_l2;
uniform sampler2D u_l3;
layout(location = 0) out vec4 o_b0;
layout(location = 1) out vec4 o_b1;
layout(location = 2) out vec4 o_b2;
layout(location = 3) out vec4 o_b3;
void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    o_b0 = sk_sdsm_reduce_bounds_level(u_l0, p, 4);
    o_b1 = sk_sdsm_reduce_bounds_level(u_l1, p, 4);
    o_b2 = sk_sdsm_reduce_bounds_level(u_l2, p, 4);
    o_b3 = sk_sdsm_reduce_bounds_level(u_l3, p, 4);
}
)";

}  // namespace

TEST_CASE("sdsm bounds reduction: per-cascade light-space bounds equal the CPU's") {
    (void)gl_test_context();
    std::string log;
    const std::string head = "#version 330 core\n";
    const std::string snip = skgl::read_text_file(std::string(SHADOWKIT_GLSL_DIR) + "/cascades.glsl");
    const GLuint first = skgl::compile_program({{GL_VERTEX_SHADER, head + kVs}, {GL_FRAGMENT_SHADER, head + snip + kBoundsFirst}}, log);
    REQUIRE_MESSAGE(first != 0, log);
    const GLuint next = skgl::compile_program({{GL_VERTEX_SHADER, head + kVs}, {GL_FRAGMENT_SHADER, head + snip + kBoundsNext}}, log);
    REQUIRE_MESSAGE(next != 0, log);
    const int w = 203, h = 117;
    const float n = 0.5f, f = 50.0f;
    const glm::mat4 V = glm::lookAt(glm::vec3(3, 2, 5), glm::vec3(0, 0, -10), glm::vec3(0, 1, 0));
    const glm::mat4 P = glm::perspective(0.9f, float(w) / float(h), n, f);
    const glm::mat4 c2w = glm::inverse(P * V);
    shadowkit::CascadeSdsmInput in;
    in.camera.camera_view = V;
    in.camera.camera_proj = P;
    in.camera.light_position = glm::vec4(glm::normalize(glm::vec3(-0.85f, 0.5f, -0.15f)), 0.0f);
    in.view_min = 1.0f;
    in.view_max = 40.0f;
    const shadowkit::CascadeSdsmResult sp = shadowkit::cascade_sdsm_splits(in, nullptr);
    REQUIRE(sp.status == shadowkit::Status::Ok);
    const shadowkit::CascadeSdsmLightView lv = shadowkit::cascade_sdsm_light_view(in.camera.light_position);
    REQUIRE(lv.status == shadowkit::Status::Ok);
    // depths of view depths in [1, 40]; a third background; none within 1e-3 of a split
    std::mt19937 rng(99);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<float> d(static_cast<std::size_t>(w * h));
    glm::dvec4 cpu[4];
    for (glm::dvec4& b : cpu) b = glm::dvec4(1e300, 1e300, -1e300, -1e300);
    const glm::dmat4 c2wd(c2w), Vd(V), Ld(lv.view);
    int used[4] = {0, 0, 0, 0};
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float& dv = d[static_cast<std::size_t>(y * w + x)];
            dv = 1.0f;
            if (u(rng) < 0.33) continue;
            const double z = std::pow(40.0, u(rng));  // view depth
            dv = static_cast<float>(((double(f) + n) / (double(f) - n) - 2.0 * f * n / ((double(f) - n) * z) + 1.0) * 0.5);
            const glm::dvec4 hw = c2wd * glm::dvec4((x + 0.5) / w * 2.0 - 1.0, (y + 0.5) / h * 2.0 - 1.0, 2.0 * double(dv) - 1.0, 1.0);
            const glm::dvec4 pw(glm::dvec3(hw) / hw.w, 1.0);
            const double vd = -(Vd * pw).z;
            bool near_split = false;
            int c = 3;
            for (int i = 3; i >= 0; --i) {
                near_split = near_split || std::fabs(vd - double(sp.splits[i + 1])) < 1e-3 * vd;
                if (vd <= double(sp.splits[i + 1])) c = i;
            }
            if (near_split) { dv = 1.0f; continue; }
            const glm::dvec4 l = Ld * pw;
            cpu[c] = glm::dvec4(std::min(cpu[c].x, l.x), std::min(cpu[c].y, l.y), std::max(cpu[c].z, l.x), std::max(cpu[c].w, l.y));
            ++used[c];
        }
    for (int c = 0; c < 4; ++c) REQUIRE(used[c] > 10);
    const GLuint t = depth_texture(d, w, h);
    GLuint vao = 0;
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    glDisable(GL_DEPTH_TEST);
    std::vector<skgl::Target> levels;
    levels.reserve(16);
    int lw = w, lh = h;
    const GLenum bufs[4] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2, GL_COLOR_ATTACHMENT3};
    while (levels.empty() || lw > 1 || lh > 1) {
        lw = (lw + 3) / 4;
        lh = (lh + 3) / 4;
        levels.emplace_back();
        std::string why;
        REQUIRE(skgl::make_target(levels.back(), lw, lh, {GL_RGBA32F, GL_RGBA32F, GL_RGBA32F, GL_RGBA32F}, 0, why));
        for (GLuint c : levels.back().color) skgl::set_nearest_clamped(c);
        glBindFramebuffer(GL_FRAMEBUFFER, levels.back().fbo);
        glDrawBuffers(4, bufs);
        glViewport(0, 0, lw, lh);
        const bool is_first = levels.size() == 1;
        const GLuint prog = is_first ? first : next;
        glUseProgram(prog);
        if (is_first) {
            glActiveTexture(GL_TEXTURE0);
            glBindTexture(GL_TEXTURE_2D, t);
            glUniform1i(glGetUniformLocation(prog, "u_src"), 0);
            glUniformMatrix4fv(glGetUniformLocation(prog, "u_clip_to_world"), 1, GL_FALSE, glm::value_ptr(c2w));
            glUniformMatrix4fv(glGetUniformLocation(prog, "u_world_to_view"), 1, GL_FALSE, glm::value_ptr(V));
            glUniformMatrix4fv(glGetUniformLocation(prog, "u_world_to_light"), 1, GL_FALSE, glm::value_ptr(lv.view));
            glUniform4f(glGetUniformLocation(prog, "u_split_far"), sp.splits[1], sp.splits[2], sp.splits[3], sp.splits[4]);
            glUniform1i(glGetUniformLocation(prog, "u_count"), 4);
        } else {
            const skgl::Target& prev = levels[levels.size() - 2];
            for (int k = 0; k < 4; ++k) {
                glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(k));
                glBindTexture(GL_TEXTURE_2D, prev.color[static_cast<std::size_t>(k)]);
                glUniform1i(glGetUniformLocation(prog, ("u_l" + std::to_string(k)).c_str()), k);
            }
        }
        glDrawArrays(GL_TRIANGLES, 0, 3);
    }
    glm::vec4 gpu[4];
    for (int k = 0; k < 4; ++k) {
        glReadBuffer(bufs[k]);
        glReadPixels(0, 0, 1, 1, GL_RGBA, GL_FLOAT, glm::value_ptr(gpu[k]));
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    for (int c = 0; c < 4; ++c) {
        INFO("cascade " << c);
        for (int k = 0; k < 4; ++k) CHECK(std::fabs(double(gpu[c][k]) - cpu[c][k]) < 1e-3);
    }
    // the fit with these bounds: every cascade's box inside its slice's box and no larger
    shadowkit::Cascade cs[4], whole[4];
    in.receiver_bounds = gpu;
    const shadowkit::CascadeSdsmResult r = shadowkit::cascade_sdsm_fit(in, nullptr, cs, 4);
    in.receiver_bounds = nullptr;
    const shadowkit::CascadeSdsmResult rw = shadowkit::cascade_sdsm_fit(in, nullptr, whole, 4);
    REQUIRE(r.status == shadowkit::Status::Ok);
    REQUIRE(rw.status == shadowkit::Status::Ok);
    for (int c = 0; c < 4; ++c) CHECK(r.boxes[c].x1 - r.boxes[c].x0 <= rw.boxes[c].x1 - rw.boxes[c].x0);
    for (skgl::Target& tg : levels) skgl::destroy_target(tg);
    glDeleteVertexArrays(1, &vao);
    glDeleteTextures(1, &t);
    glDeleteProgram(first);
    glDeleteProgram(next);
}
