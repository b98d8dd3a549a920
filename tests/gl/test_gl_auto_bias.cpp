// glsl/shadow_map.glsl's automatic bias on the GPU against its CPU mirror (shadow_bias.hpp
// bias_auto_lookup + bias_auto_visibility): a 256^2 float32 depth texture of random depths (a noisy
// surface near the receivers' depths, so that taps land on both sides), random receiver points and
// normals under random perspective and orthographic lights, GL and zero-to-one clip; every lookup's V
// must equal the mirror's (same float arithmetic: within 1e-4 - the GPU may fuse multiply-adds, which
// moves a tap across its compare only where the stored depth lies within rounding of the reference).
// Also the array-layer overload, sk_plane_depth_gradient against bias_plane_gradient, and reversed-Z
// (SK_REVERSED_Z, zero-to-one clip, GL_GEQUAL compare) against the mirror's reversed_z.
#include <shadowkit/shadow_bias.hpp>

#include <doctest/doctest.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "gl_test.hpp"

namespace {

const char* kVS = R"(#version 450 core
layout(location = 0) in vec4 a_pos;      // world position
layout(location = 1) in vec4 a_normal;   // world normal
flat out vec3 v_pos;
flat out vec3 v_normal;
uniform int u_count;
void main() {
    v_pos = a_pos.xyz;
    v_normal = a_normal.xyz;
    gl_Position = vec4((float(gl_VertexID) + 0.5) / float(u_count) * 2.0 - 1.0, 0.0, 0.0, 1.0);
    gl_PointSize = 1.0;
})";

const char* kFS = R"(
layout(binding = 0) uniform sampler2DShadow u_map;
layout(binding = 1) uniform sampler2DArrayShadow u_array;
uniform mat4 u_vp;
uniform bool u_zero_to_one;
uniform float u_depth_step;
flat in vec3 v_pos;
flat in vec3 v_normal;
layout(location = 0) out vec4 o;
void main() {
    float a = sk_shadow_map_visibility_auto(u_map, u_vp, v_pos, v_normal, u_zero_to_one, u_depth_step, 0.5);
    float b = sk_shadow_map_visibility_auto(u_array, 1.0, u_vp, v_pos, v_normal, u_zero_to_one, u_depth_step, 0.5);
    vec4 g = sk_plane_depth_gradient(u_vp, v_pos, v_normal, u_zero_to_one);
    o = vec4(a, b, g.x, g.y);
})";

}  // namespace

TEST_CASE("sk_shadow_map_visibility_auto equals bias_auto_lookup + bias_auto_visibility") {
    (void)gl_test_context();
    std::string log;
    const std::string snippet = skgl::read_text_file(std::string(SHADOWKIT_GLSL_DIR) + "/shadow_map.glsl");
    REQUIRE(!snippet.empty());
    const GLuint prog_std = skgl::compile_program({{GL_VERTEX_SHADER, kVS}, {GL_FRAGMENT_SHADER, "#version 450 core\n" + snippet + kFS}}, log);
    REQUIRE_MESSAGE(prog_std != 0, log);
    const GLuint prog_rev = skgl::compile_program(
        {{GL_VERTEX_SHADER, kVS}, {GL_FRAGMENT_SHADER, "#version 450 core\n#define SK_REVERSED_Z\n" + snippet + kFS}}, log);
    REQUIRE_MESSAGE(prog_rev != 0, log);
    constexpr int kSize = 256, kPoints = 4096;
    std::mt19937 rng(42);
    std::uniform_real_distribution<float> U(0.0f, 1.0f);
    // the map: depths around 0.5 with noise (layer 1 of the array holds the same)
    std::vector<float> depth(kSize * kSize);
    for (float& d : depth) d = 0.3f + 0.4f * U(rng);
    GLuint map = 0, array = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &map);
    glTextureStorage2D(map, 1, GL_DEPTH_COMPONENT32F, kSize, kSize);
    glTextureSubImage2D(map, 0, 0, 0, kSize, kSize, GL_DEPTH_COMPONENT, GL_FLOAT, depth.data());
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &array);
    glTextureStorage3D(array, 1, GL_DEPTH_COMPONENT32F, kSize, kSize, 2);
    std::vector<float> ones(kSize * kSize, 1.0f);
    glTextureSubImage3D(array, 0, 0, 0, 0, kSize, kSize, 1, GL_DEPTH_COMPONENT, GL_FLOAT, ones.data());
    glTextureSubImage3D(array, 0, 0, 0, 1, kSize, kSize, 1, GL_DEPTH_COMPONENT, GL_FLOAT, depth.data());
    for (GLuint t : {map, array}) {
        glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glTextureParameteri(t, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_BORDER);
        glTextureParameteri(t, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_BORDER);
        const float border[4] = {1.f, 1.f, 1.f, 1.f};
        glTextureParameterfv(t, GL_TEXTURE_BORDER_COLOR, border);
        glTextureParameteri(t, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
        glTextureParameteri(t, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    }
    glBindTextureUnit(0, map);
    glBindTextureUnit(1, array);
    auto stored_at = [&](glm::vec2 uv) {  // GL_NEAREST at a texel centre; outside: the border (1)
        const int i = int(std::floor(uv.x * kSize)), j = int(std::floor(uv.y * kSize));
        if (i < 0 || j < 0 || i >= kSize || j >= kSize) return 1.0f;
        return depth[std::size_t(j) * kSize + std::size_t(i)];
    };
    GLuint out_tex = 0, fbo = 0, vao = 0, vbo[2] = {0, 0};
    glCreateTextures(GL_TEXTURE_2D, 1, &out_tex);
    glTextureStorage2D(out_tex, 1, GL_RGBA32F, kPoints, 1);
    glCreateFramebuffers(1, &fbo);
    glNamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, out_tex, 0);
    glCreateVertexArrays(1, &vao);
    glCreateBuffers(2, vbo);
    int compared = 0, differ = 0, outside = 0;
    double worst_g = 0.0;
    for (int round = 0; round < 12; ++round) {
        const bool persp = round % 2 == 0;
        const bool rev = round >= 8;  // reversed-Z: zero-to-one clip, the far plane at 0, compare GL_GEQUAL
        const GLuint prog = rev ? prog_rev : prog_std;
        for (GLuint t : {map, array}) glTextureParameteri(t, GL_TEXTURE_COMPARE_FUNC, rev ? GL_GEQUAL : GL_LEQUAL);
        const shadowkit::ClipDepth clip =
            rev || (round / 2) % 2 ? shadowkit::ClipDepth::ZeroToOne : shadowkit::ClipDepth::NegativeOneToOne;
        const glm::vec3 eye = glm::vec3(U(rng) - 0.5f, 1.0f, U(rng) - 0.5f) * 8.0f;
        const glm::mat4 view = glm::lookAt(eye, glm::vec3(0.0f), std::fabs(glm::normalize(eye).y) > 0.9f ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0));
        const bool z01 = clip == shadowkit::ClipDepth::ZeroToOne;
        const glm::mat4 proj = persp ? (z01 ? glm::perspectiveRH_ZO(1.0f, 1.0f, 1.0f, 20.0f) : glm::perspectiveRH_NO(1.0f, 1.0f, 1.0f, 20.0f))
                                     : (z01 ? glm::orthoRH_ZO(-3.f, 3.f, -3.f, 3.f, 1.0f, 20.0f) : glm::orthoRH_NO(-3.f, 3.f, -3.f, 3.f, 1.0f, 20.0f));
        glm::mat4 rz(1.0f);  // z' = w - z: reversed depth in zero-to-one clip
        rz[2][2] = -1.0f;
        rz[3][2] = 1.0f;
        const glm::mat4 vp = rev ? rz * proj * view : proj * view;
        const shadowkit::DepthFormat fmt = (round / 4) % 2 ? shadowkit::DepthFormat::Fixed16 : shadowkit::DepthFormat::Float32;
        const float step = shadowkit::bias_auto_depth_step(fmt).value;
        // receivers: points whose window depth is near the map's depths, random normals facing the light
        std::vector<glm::vec4> pos(kPoints), nrm(kPoints);
        const glm::mat4 inv = glm::inverse(vp);
        for (int k = 0; k < kPoints; ++k) {
            const glm::vec4 w = inv * glm::vec4(U(rng) * 2.2f - 1.1f, U(rng) * 2.2f - 1.1f, z01 ? 0.3f + 0.4f * U(rng) : 0.4f * U(rng) - 0.2f, 1.0f);
            pos[std::size_t(k)] = glm::vec4(glm::vec3(w) / w.w, 1.0f);
            glm::vec3 n(U(rng) - 0.5f, U(rng) - 0.5f, U(rng) - 0.5f);
            if (glm::dot(n, eye - glm::vec3(pos[std::size_t(k)])) < 0.0f) n = -n;
            nrm[std::size_t(k)] = glm::vec4(n, 0.0f);
        }
        glNamedBufferData(vbo[0], GLsizeiptr(pos.size() * sizeof(glm::vec4)), pos.data(), GL_STATIC_DRAW);
        glNamedBufferData(vbo[1], GLsizeiptr(nrm.size() * sizeof(glm::vec4)), nrm.data(), GL_STATIC_DRAW);
        for (GLuint a = 0; a < 2; ++a) {
            glVertexArrayVertexBuffer(vao, a, vbo[a], 0, sizeof(glm::vec4));
            glVertexArrayAttribFormat(vao, a, 4, GL_FLOAT, GL_FALSE, 0);
            glVertexArrayAttribBinding(vao, a, a);
            glEnableVertexArrayAttrib(vao, a);
        }
        glUseProgram(prog);
        glUniform1i(glGetUniformLocation(prog, "u_count"), kPoints);
        glUniformMatrix4fv(glGetUniformLocation(prog, "u_vp"), 1, GL_FALSE, glm::value_ptr(vp));
        glUniform1i(glGetUniformLocation(prog, "u_zero_to_one"), z01 ? 1 : 0);
        glUniform1f(glGetUniformLocation(prog, "u_depth_step"), step);
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        glViewport(0, 0, kPoints, 1);
        glDisable(GL_DEPTH_TEST);
        glDisable(GL_BLEND);
        glBindVertexArray(vao);
        glDrawArrays(GL_POINTS, 0, kPoints);
        std::vector<float> out(std::size_t(kPoints) * 4);
        glReadPixels(0, 0, kPoints, 1, GL_RGBA, GL_FLOAT, out.data());
        for (int k = 0; k < kPoints; ++k) {
            const shadowkit::BiasAutoLookup a = shadowkit::bias_auto_lookup(vp, clip, rev, glm::vec3(pos[std::size_t(k)]),
                                                                           glm::vec3(nrm[std::size_t(k)]), glm::ivec2(kSize), fmt);
            REQUIRE(a.status == shadowkit::Status::Ok);
            float stored[4];
            for (int t = 0; t < 4; ++t) stored[t] = stored_at(a.tap_uv[t]);
            const float expect = shadowkit::bias_auto_visibility(a, stored, rev, 0.5f);
            const float got = out[std::size_t(k) * 4], got_array = out[std::size_t(k) * 4 + 1];
            outside += a.outside ? 1 : 0;
            ++compared;
            if (std::fabs(got - expect) > 1e-4f || std::fabs(got_array - expect) > 1e-4f) ++differ;
            if (!a.outside && !a.edge_on) {
                const glm::vec2 g(out[std::size_t(k) * 4 + 2], out[std::size_t(k) * 4 + 3]);
                const double mag = double(std::fabs(a.dz_duv.x) + std::fabs(a.dz_duv.y)) + 1e-3;
                worst_g = std::fmax(worst_g, double(glm::length(g - a.dz_duv)) / mag);
            }
        }
    }
    MESSAGE(compared << " lookups (" << outside << " outside the map), GPU != CPU mirror: " << differ
                     << "; largest relative gradient difference " << worst_g);
    // a tap whose stored depth lies within float rounding of its reference may flip between the two
    CHECK(differ <= compared / 1000);
    CHECK(worst_g < 1e-3);
    CHECK(outside < compared / 2);
    glDeleteTextures(1, &map);
    glDeleteTextures(1, &array);
    glDeleteTextures(1, &out_tex);
    glDeleteFramebuffers(1, &fbo);
    glDeleteBuffers(2, vbo);
    glDeleteVertexArrays(1, &vao);
    glDeleteProgram(prog_std);
    glDeleteProgram(prog_rev);
}
