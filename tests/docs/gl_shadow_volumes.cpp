// tests/docs/gl_shadow_volumes.cpp - the "new user" trial of issue 13 for stencil shadow volumes: a
// program written only from docs/shadow_volume.md and the header / snippet comments (no
// samples/common). The documented GL path is #included from the page's named parts
// (gl_shadow_volumes/PART); this file adds what a user has anyway: a GL context, a small scene (a
// box over a two-sided floor), cameras and lights, and the check: every pixel's lit / shadow result
// read back and compared with a CPU ray cast (docs::segment_occluded) from the same surface point,
// for a point light, a light right above the box with the camera inside the box's shadow (z-fail),
// and directional lights from the upper and the lower hemisphere. Passes with >= 99.5% agreement on
// pixels away from edges in every case; prints the scores.
#include "docs_gl.hpp"

#include <shadowkit/shadow_volume.hpp>
#include <shadowkit/silhouette.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

namespace sk = shadowkit;
using docs::gl_program;  // the renderer's compile-and-link helper

namespace {

struct Case {
    const char* name;
    glm::vec4 light_position;  // the shadowkit convention: w = 1 point, w = 0 direction TOWARD the light
    glm::vec3 eye, target;
};

}  // namespace

int main() {
    const int W = 256, H = 192;
    if (!docs::gl_context(W, H)) return docs::no_gl_exit_code();
    const GLuint window = docs::window_framebuffer();

    // The scene (world = object space): a floor, two-sided so that it also shadows from below, and
    // a box floating above it; two occluders (casters), and the whole scene for drawing.
    docs::Mesh floor_mesh = docs::quad_y(0.0f, 4.0f);
    {
        docs::Mesh back = docs::quad_y(0.0f, 4.0f);
        for (std::size_t t = 0; t < back.indices.size(); t += 3) std::swap(back.indices[t + 1], back.indices[t + 2]);
        docs::append(floor_mesh, back);
    }
    const std::vector<docs::Mesh> occluders = {floor_mesh, docs::box(glm::vec3(-0.5f, 0.6f, -0.5f), glm::vec3(0.5f, 1.4f, 0.5f))};
    docs::Mesh mesh;
    for (const docs::Mesh& m : occluders) docs::append(mesh, m);
    const std::vector<glm::vec3>& positions = mesh.positions;
    const std::vector<std::uint32_t>& indices = mesh.indices;
    glm::vec3 scene_min(1e30f), scene_max(-1e30f);
    for (const glm::vec3& p : positions) {
        scene_min = glm::min(scene_min, p);
        scene_max = glm::max(scene_max, p);
    }
    // everything that can receive a shadow: the scene's bounds, padded
    scene_min -= glm::vec3(0.01f);
    scene_max += glm::vec3(0.01f);
    const std::string shadow_volume_glsl = docs::snippet("shadow_volume");  // the pasted snippet

    // The scene's own drawing: one program for the depth pre-pass (ambient: black), the lighting
    // (diffuse) and, for the check only, the surface normal; flat normals from derivatives.
    const GLuint scene_program = docs::gl_program(R"(#version 450 core
layout(location = 0) in vec3 a_position;
uniform mat4 u_view_proj;
out vec3 v_world;
void main() { v_world = a_position; gl_Position = u_view_proj * vec4(a_position, 1.0); }
)",
                                                  R"(#version 450 core
in vec3 v_world;
uniform vec4 u_light_position;
uniform int u_mode;  // 0 ambient (black), 1 diffuse, 2 normal (the check)
layout(location = 0) out vec4 o_color;
void main() {
    vec3 n = normalize(cross(dFdx(v_world), dFdy(v_world)));
    vec3 l = normalize(u_light_position.xyz - v_world * u_light_position.w);
    if (u_mode == 0) o_color = vec4(0.0, 0.0, 0.0, 1.0);
    else if (u_mode == 1) o_color = vec4(vec3(max(dot(n, l), 0.0)), 1.0);
    else o_color = vec4(n * 0.5 + 0.5, 1.0);
}
)");
    GLuint scene_vao = 0, scene_vbo = 0, scene_ibo = 0;
    glGenVertexArrays(1, &scene_vao);
    glBindVertexArray(scene_vao);
    glGenBuffers(1, &scene_vbo);
    glBindBuffer(GL_ARRAY_BUFFER, scene_vbo);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(positions.size() * sizeof(glm::vec3)), positions.data(), GL_STATIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(glm::vec3), nullptr);
    glGenBuffers(1, &scene_ibo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, scene_ibo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(indices.size() * 4), indices.data(), GL_STATIC_DRAW);
    glBindVertexArray(0);
    auto draw_scene = [&](int mode, const glm::mat4& view_proj, const glm::vec4& light_position) {
        glUseProgram(scene_program);
        glUniformMatrix4fv(glGetUniformLocation(scene_program, "u_view_proj"), 1, GL_FALSE, glm::value_ptr(view_proj));
        glUniform4fv(glGetUniformLocation(scene_program, "u_light_position"), 1, glm::value_ptr(light_position));
        glUniform1i(glGetUniformLocation(scene_program, "u_mode"), mode);
        glBindVertexArray(scene_vao);
        glDrawElements(GL_TRIANGLES, GLsizei(indices.size()), GL_UNSIGNED_INT, nullptr);
        glBindVertexArray(0);
    };

#include "setup.inc"

    const Case cases[] = {
        {"point light above, camera outside", glm::vec4(-1.5f, 3.0f, -1.0f, 1.0f), glm::vec3(3.5f, 4.0f, 5.0f), glm::vec3(0.0f, 0.4f, 0.0f)},
        {"point light above the box, camera in its shadow (z-fail)", glm::vec4(0.1f, 3.0f, 0.05f, 1.0f), glm::vec3(0.15f, 0.3f, 0.1f),
         glm::vec3(3.0f, 0.0f, 2.0f)},
        {"directional, upper hemisphere", glm::vec4(-0.4f, 1.0f, -0.3f, 0.0f), glm::vec3(3.5f, 4.0f, 5.0f), glm::vec3(0.0f, 0.4f, 0.0f)},
        {"directional, lower hemisphere", glm::vec4(-0.5f, -0.3f, 0.4f, 0.0f), glm::vec3(-3.0f, 3.0f, 4.5f), glm::vec3(0.0f, 0.6f, 0.0f)},
    };
    const float fovy = glm::radians(60.0f), aspect = float(W) / float(H), near_z = 0.05f, far_z = 40.0f;
    bool all_pass = true;
    for (const Case& cs : cases) {
        const glm::vec4 light_position = cs.light_position;
        const glm::mat4 view = glm::lookAt(cs.eye, cs.target, glm::vec3(0.0f, 1.0f, 0.0f));
        const glm::mat4 proj = glm::perspective(fovy, aspect, near_z, far_z);

#include "frame.inc"
#include "depth_prepass.inc"
#include "stencil_clear.inc"
#include "volume_pass.inc"
#include "lighting_pass.inc"

        // ---- the check (not part of the documented path): read back the lit result, the depth and
        // the normal of every pixel and cast a CPU ray from the same surface point to the light
        std::vector<std::uint8_t> rgba(std::size_t(W) * H * 4), nrm(std::size_t(W) * H * 4);
        std::vector<float> depth(std::size_t(W) * H);
        glBindFramebuffer(GL_FRAMEBUFFER, window);
        glReadPixels(0, 0, W, H, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
        glReadPixels(0, 0, W, H, GL_DEPTH_COMPONENT, GL_FLOAT, depth.data());
        glDisable(GL_SCISSOR_TEST);  // the check's own state, whatever the documented path left
        glDisable(GL_STENCIL_TEST);
        glDisable(GL_BLEND);
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_EQUAL);
        glDepthMask(GL_FALSE);
        glEnable(GL_CULL_FACE);
        draw_scene(2, proj * view, light_position);
        glReadPixels(0, 0, W, H, GL_RGBA, GL_UNSIGNED_BYTE, nrm.data());
        glDepthFunc(GL_LESS);
        glDepthMask(GL_TRUE);
        const glm::mat4 inv = glm::inverse(proj * view);
        std::vector<int> ref(std::size_t(W) * H, -1);   // -1 background / ambiguous, 0 shadow or unlit, 1 lit
        std::vector<glm::ivec3> nq(std::size_t(W) * H); // quantized normal: which surface
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const std::size_t i = std::size_t(y) * W + x;
                if (depth[i] >= 1.0f) continue;
                const glm::vec4 ndc((float(x) + 0.5f) / float(W) * 2.0f - 1.0f, (float(y) + 0.5f) / float(H) * 2.0f - 1.0f, depth[i] * 2.0f - 1.0f, 1.0f);
                const glm::vec4 h = inv * ndc;
                const glm::vec3 p = glm::vec3(h) / h.w;
                const glm::vec3 n = glm::normalize(glm::vec3(nrm[4 * i], nrm[4 * i + 1], nrm[4 * i + 2]) / 127.5f - 1.0f);
                nq[i] = glm::ivec3(glm::round(n * 4.0f));
                const glm::vec3 to_light = light_position.w > 0.0f ? glm::vec3(light_position) / light_position.w - p
                                                                   : glm::normalize(glm::vec3(light_position));
                const float ndl = glm::dot(n, glm::normalize(to_light));
                if (std::fabs(ndl) < 0.02f) continue;  // grazing: 8-bit output cannot tell
                const glm::vec3 from = p + n * 2e-3f;
                const glm::vec3 to = light_position.w > 0.0f ? glm::vec3(light_position) / light_position.w : p + to_light * 100.0f;
                ref[i] = (ndl > 0.0f && !docs::segment_occluded(mesh, from, to)) ? 1 : 0;
            }
        std::size_t compared = 0, agree = 0, lit_pixels = 0;
        for (int y = 1; y + 1 < H; ++y)
            for (int x = 1; x + 1 < W; ++x) {
                const std::size_t i = std::size_t(y) * W + x;
                if (ref[i] < 0) continue;
                bool interior = true;  // away from shadow edges and surface edges: a uniform 3x3 neighborhood
                for (int dy = -1; dy <= 1 && interior; ++dy)
                    for (int dx = -1; dx <= 1 && interior; ++dx) {
                        const std::size_t j = std::size_t(y + dy) * W + (x + dx);
                        interior = ref[j] == ref[i] && nq[j] == nq[i];
                    }
                if (!interior) continue;
                const int gpu = rgba[4 * i] > 2 ? 1 : 0;
                ++compared;
                agree += gpu == ref[i];
                lit_pixels += std::size_t(ref[i]);
            }
        const double score = compared ? 100.0 * double(agree) / double(compared) : 0.0;
        std::size_t zfail_count = 0;
        for (const VolumeMesh& v : volumes) zfail_count += v.zfail ? 1 : 0;
        std::printf("%-58s %zu z-fail: %6.2f%% of %zu pixels agree with the CPU ray cast (%zu lit)\n", cs.name, zfail_count,
                    score, compared, lit_pixels);
        if (!(score >= 99.5) || compared < 5000) all_pass = false;
    }
    return all_pass ? 0 : 1;
}
