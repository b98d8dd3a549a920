// glsl/cascades.glsl's SDSM reduction on the GL driver: sk_sdsm_reduce_depth on a DEPTH32F depth
// buffer, then sk_sdsm_reduce_minmax level by level down to 1x1, against the CPU min/max of the same
// depth values (the non-background ones), which must be equal exactly (min and max are exact in float,
// texelFetch of a DEPTH32F / RG32F texel returns the stored float). Odd sizes (partial blocks at the
// edges), blocks of 2 to 16, background 1.0 (and 0.0 for reversed-Z), a single receiver pixel in a
// corner, and an all-background buffer (the empty marker, which cascade_sdsm_view_range reads as
// nothing visible). One case draws triangles into the depth buffer (depth test on) and reads it back
// with glReadPixels for the CPU side.
#include <doctest/doctest.h>

#include <shadowkit/cascades.hpp>

#include <algorithm>
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
