// tests/docs/gl_shadow_cache.cpp - the GL usage of docs/shadow_cache.md, assembled: a stable cascade
// follows a camera over a field of boxes while one box drives around; the map is kept with the
// parts `maps` (a ping-pong pair of depth textures) and `frame` (the plan, the copy, the scissored
// re-render). Each frame the kept map is compared with a full re-render: every texel must hold the
// same surface (depth within 1e-5; the plain pass rounds depth differently after a translation by a
// few float steps, see docs/shadow_cache.md), and at most 0.01% of the texels may differ by more
// (an edge that rounds the other way). Exit 0 when it holds, 1 otherwise, 77 without GL.
#include <shadowkit/shadow_cache.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <vector>

#include "docs_gl.hpp"

namespace {

// The user's stable fit (docs/shadow_cache.md, the CPU program): built in double, world-fixed depth.
glm::dmat4 stable_cascade(const glm::dvec4& light_position, double texel, int size, const glm::dvec3& camera,
                          double s0, double s1) {
    const glm::dvec3 d = -glm::normalize(glm::dvec3(light_position));
    const glm::dvec3 sx = glm::normalize(glm::cross(glm::dvec3(0.0, 1.0, 0.0), d)), sy = glm::cross(d, sx);
    const double kx = std::floor(glm::dot(sx, camera) / texel) - 0.5 * size;
    const double ky = std::floor(glm::dot(sy, camera) / texel) - 0.5 * size;
    const double a = 2.0 / (size * texel), az = 2.0 / (s1 - s0);
    glm::dmat4 m(0.0);
    for (int c = 0; c < 3; ++c) {
        m[c][0] = a * sx[c];
        m[c][1] = a * sy[c];
        m[c][2] = az * d[c];
    }
    m[3][0] = -2.0 * kx / size - 1.0;
    m[3][1] = -2.0 * ky / size - 1.0;
    m[3][2] = -az * s0 - 1.0;
    m[3][3] = 1.0;
    return m;
}

bool overlap(const shadowkit::ShadowCacheRect& a, const shadowkit::ShadowCacheRect& b) {
    return a.x < b.x + b.width && b.x < a.x + a.width && a.y < b.y + b.height && b.y < a.y + a.height;
}

// The scene: one vertex buffer, one box per caster (36 vertices each, drawn by range).
struct Scene {
    std::vector<shadowkit::ShadowCacheCaster> casters;
    std::vector<glm::vec3> vertices;
    GLuint vao = 0, vbo = 0;
    void add(glm::vec3 lo, glm::vec3 hi) {
        shadowkit::ShadowCacheCaster c;
        const float b[6] = {lo.x, lo.y, lo.z, hi.x, hi.y, hi.z};
        std::memcpy(c.bounds, b, sizeof b);
        std::memcpy(c.previous_bounds, b, sizeof b);
        casters.push_back(c);
    }
    void upload() {
        vertices.clear();
        for (const auto& c : casters) {
            const docs::Mesh m = docs::box({c.bounds[0], c.bounds[1], c.bounds[2]}, {c.bounds[3], c.bounds[4], c.bounds[5]});
            for (std::uint32_t i : m.indices) vertices.push_back(m.positions[i]);
        }
        if (vao == 0) {
            glGenVertexArrays(1, &vao);
            glGenBuffers(1, &vbo);
            glBindVertexArray(vao);
            glBindBuffer(GL_ARRAY_BUFFER, vbo);
            glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(glm::vec3), nullptr);
            glEnableVertexAttribArray(0);
        }
        glBindBuffer(GL_ARRAY_BUFFER, vbo);
        glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertices.size() * sizeof(glm::vec3)), vertices.data(), GL_DYNAMIC_DRAW);
        glBindVertexArray(vao);
    }
};

}  // namespace

int main() {
    const int size = 512;
    if (!docs::gl_context(64, 64)) return docs::no_gl_exit_code();
    const GLuint caster_program = docs::gl_program(R"(#version 450 core
layout(location = 0) in vec3 a_position;
uniform mat4 u_light_view_proj;
invariant gl_Position;  // the same vertex lands on the same spot in every pass
void main() { gl_Position = u_light_view_proj * vec4(a_position, 1.0); }
)",
                                                   "#version 450 core\nvoid main() {}\n");
    Scene scene;
    scene.add({-60.0f, -1.0f, -60.0f}, {60.0f, 0.0f, 60.0f});  // ground
    for (int z = -5; z <= 5; ++z)
        for (int x = -5; x <= 5; ++x)
            if ((x + z) % 2 == 0) {
                const float cx = 6.0f * float(x), cz = 6.0f * float(z), h = 1.0f + float((x * 7 + z * 3) & 3);
                scene.add({cx - 1.1f, 0.0f, cz - 0.7f}, {cx + 1.1f, h, cz + 0.7f});
            }
    scene.add({2.0f, 0.0f, 2.0f}, {3.5f, 2.0f, 3.0f});  // the cart (last)
    scene.upload();
    auto draw_caster = [&](std::size_t i) { glDrawArrays(GL_TRIANGLES, GLint(i * 36), 36); };
    const std::uint64_t settings_hash = 1;
    const glm::dvec4 sun(0.35, 1.0, 0.25, 0.0);
    const double texel = 0.05;

#include "maps.inc"

    // the reference: a full re-render every frame
    GLuint ref_tex = 0, ref_fbo = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &ref_tex);
    glTextureStorage2D(ref_tex, 1, GL_DEPTH_COMPONENT32F, size, size);
    glCreateFramebuffers(1, &ref_fbo);
    glNamedFramebufferTexture(ref_fbo, GL_DEPTH_ATTACHMENT, ref_tex, 0);
    glNamedFramebufferDrawBuffer(ref_fbo, GL_NONE);

    glm::dvec3 camera(0.2, 1.7, 0.3);
    std::vector<float> kept(std::size_t(size) * size), full(kept.size());
    std::size_t far_texels = 0, total = 0;
    int scrolls = 0;
    for (int frame = 0; frame < 32; ++frame) {
        camera += glm::dvec3(0.13 * std::cos(0.2 * frame), 0.0, 0.11 * std::sin(0.3 * frame));
        auto& cart = scene.casters.back();
        std::memcpy(cart.previous_bounds, cart.bounds, sizeof cart.bounds);
        if (frame % 3 == 1) {
            cart.bounds[0] += 0.4f;
            cart.bounds[3] += 0.4f;
            scene.upload();
        }
        const glm::dmat4 light_view_proj = stable_cascade(sun, texel, size, camera, -80.0, 80.0);
        std::vector<shadowkit::ShadowCacheCaster>& casters = scene.casters;

#include "frame.inc"

        if (plan.action == shadowkit::ShadowCacheAction::Scroll) ++scrolls;
        glBindFramebuffer(GL_FRAMEBUFFER, ref_fbo);
        glViewport(0, 0, size, size);
        glEnable(GL_DEPTH_TEST);
        glDepthMask(GL_TRUE);
        glEnable(GL_POLYGON_OFFSET_FILL);
        glPolygonOffset(1.5f, 2.0f);
        glClear(GL_DEPTH_BUFFER_BIT);
        glUseProgram(caster_program);
        const glm::mat4 gpu_matrix(light_view_proj);
        glUniformMatrix4fv(glGetUniformLocation(caster_program, "u_light_view_proj"), 1, GL_FALSE, &gpu_matrix[0][0]);
        glDrawArrays(GL_TRIANGLES, 0, GLsizei(scene.vertices.size()));
        glDisable(GL_POLYGON_OFFSET_FILL);
        glGetTextureImage(map_tex[current], 0, GL_DEPTH_COMPONENT, GL_FLOAT, GLsizei(kept.size() * sizeof(float)), kept.data());
        glGetTextureImage(ref_tex, 0, GL_DEPTH_COMPONENT, GL_FLOAT, GLsizei(full.size() * sizeof(float)), full.data());
        for (std::size_t k = 0; k < kept.size(); ++k)
            if (std::fabs(kept[k] - full[k]) > 1e-5f) ++far_texels;
        total += kept.size();
    }
    const GLenum err = glGetError();
    std::printf("32 frames, %d scrolls: %zu of %zu texels hold another surface than a full re-render\n", scrolls, far_texels,
                total);
    return err == GL_NO_ERROR && scrolls > 10 && far_texels * 10000 <= total ? 0 : 1;
}
