// tests/docs/gl_pcss.cpp - the "new user" trial for docs/pcss.md: percentage-closer soft shadows
// built only from that page's blocks (named parts gl_pcss/*, #included below) and the comments of
// glsl/pcf.glsl, glsl/pcss.glsl, glsl/shadow_map.glsl, include/shadowkit/pcss.hpp and
// poisson_disk.hpp. The program adds what a user's renderer has anyway: a GL context, a scene (boxes
// over a floor under a square area light) with its draw call, a camera, and the check: the
// visibility read back per pixel against a CPU ray cast to 8 x 8 stratified points of the square
// light from the same surface points (the light's emitter sampled, as the report's reference does).
// Scored on receiver pixels that see the whole emitter above their tangent plane (floor and box
// tops; PCSS does not model an emitter crossing the horizon). Prints the RMSE and the penumbra RMSE;
// fails above 0.05 (a hard shadow map scores about 0.08 on such scenes in the report).
#include "docs_gl.hpp"

#include <shadowkit/pcss.hpp>
#include <shadowkit/poisson_disk.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace {

struct Box {
    glm::vec3 lo, hi;
};
const Box kBoxes[] = {{{-1.6f, 0.0f, -0.6f}, {-0.6f, 1.0f, 0.4f}},   // on the floor: contact shadows
                      {{0.5f, 0.9f, -0.8f}, {1.6f, 1.3f, 0.3f}},     // floating slab
                      {{-0.4f, 1.9f, 0.7f}, {0.7f, 2.0f, 1.7f}},     // thin plate, high: a wide penumbra
                      {{1.2f, 0.0f, 1.2f}, {1.5f, 2.2f, 1.5f}}};     // a post

// Segment (a, b) against an axis-aligned box (slab test), the CPU reference's early-out.
bool segment_hits_box(glm::vec3 a, glm::vec3 b, const Box& box) {
    double t0 = 0.0, t1 = 1.0;
    for (int i = 0; i < 3; ++i) {
        const double d = double(b[i]) - double(a[i]);
        if (std::abs(d) < 1e-12) {
            if (a[i] < box.lo[i] || a[i] > box.hi[i]) return false;
            continue;
        }
        double u = (double(box.lo[i]) - a[i]) / d, v = (double(box.hi[i]) - a[i]) / d;
        if (u > v) std::swap(u, v);
        t0 = std::max(t0, u);
        t1 = std::min(t1, v);
        if (t0 > t1) return false;
    }
    return true;
}

}  // namespace

int main() {
    const int W = 256, H = 192;
    if (!docs::gl_context(W, H)) return docs::no_gl_exit_code();
    const GLuint window = docs::window_framebuffer();
    docs::Mesh scene = docs::quad_y(0.0f, 4.0f);
    std::vector<docs::Mesh> box_meshes;
    for (const Box& b : kBoxes) {
        box_meshes.push_back(docs::box(b.lo, b.hi));
        docs::append(scene, box_meshes.back());
    }
    // Flat-shaded vertex arrays: attribute 0 position, attribute 1 normal.
    std::vector<glm::vec3> pos, nrm;
    for (std::size_t t = 0; t + 2 < scene.indices.size(); t += 3) {
        const glm::vec3 a = scene.positions[scene.indices[t]], b = scene.positions[scene.indices[t + 1]],
                        c = scene.positions[scene.indices[t + 2]];
        const glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
        for (const glm::vec3& p : {a, b, c}) {
            pos.push_back(p);
            nrm.push_back(n);
        }
    }
    GLuint vao = 0, vbo[2] = {0, 0};
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    glGenBuffers(2, vbo);
    for (int k = 0; k < 2; ++k) {
        const std::vector<glm::vec3>& data = k == 0 ? pos : nrm;
        glBindBuffer(GL_ARRAY_BUFFER, vbo[k]);
        glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(data.size() * sizeof(glm::vec3)), data.data(), GL_STATIC_DRAW);
        glVertexAttribPointer(static_cast<GLuint>(k), 3, GL_FLOAT, GL_FALSE, 0, nullptr);
        glEnableVertexAttribArray(static_cast<GLuint>(k));
    }
    const auto vertex_count = static_cast<GLsizei>(pos.size());
    const auto draw_scene = [&] {
        glBindVertexArray(vao);
        glDrawArrays(GL_TRIANGLES, 0, vertex_count);
    };
    const glm::mat4 camera_view_proj = glm::perspective(glm::radians(50.0f), float(W) / float(H), 0.1f, 50.0f) *
                                       glm::lookAt(glm::vec3(0.5f, 5.5f, 7.5f), glm::vec3(0.0f, 0.5f, 0.0f), glm::vec3(0.0f, 1.0f, 0.0f));
    // The area light: a square of side light_size at light_center, facing down; and the casters' bounds.
    const glm::vec3 light_center(0.3f, 5.0f, 0.4f);
    const float light_size = 1.0f;
    const glm::vec3 casters_min(-1.6f, 0.0f, -0.8f), casters_max(1.6f, 2.2f, 1.7f);
    const glm::vec3 scene_min(-4.0f, 0.0f, -4.0f), scene_max(4.0f, 2.2f, 4.0f);

    namespace sk = shadowkit;
#include "light.inc"
#include "map.inc"
#include "taps.inc"
#include "program.inc"
#include "render.inc"
#include "lighting.inc"

    std::vector<unsigned char> rgba(static_cast<std::size_t>(W * H) * 4);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, window);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glReadPixels(0, 0, W, H, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());

    // The program's G-buffer (world position, normal) for the score, then the ray cast.
    GLuint gfbo = 0, gtex[2] = {0, 0}, gdepth = 0;
    glGenFramebuffers(1, &gfbo);
    glBindFramebuffer(GL_FRAMEBUFFER, gfbo);
    glGenTextures(2, gtex);
    for (int k = 0; k < 2; ++k) {
        glBindTexture(GL_TEXTURE_2D, gtex[k]);
        glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA32F, W, H);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(k), GL_TEXTURE_2D, gtex[k], 0);
    }
    glGenRenderbuffers(1, &gdepth);
    glBindRenderbuffer(GL_RENDERBUFFER, gdepth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, W, H);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, gdepth);
    const GLenum bufs[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glDrawBuffers(2, bufs);
    const GLuint gprog = docs::gl_program(R"(#version 450 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
uniform mat4 u_view_proj;
out vec3 v_world;
out vec3 v_normal;
void main() { v_world = a_position; v_normal = a_normal; gl_Position = u_view_proj * vec4(a_position, 1.0); })",
                                          R"(#version 450 core
in vec3 v_world;
in vec3 v_normal;
layout(location = 0) out vec4 o_pos;
layout(location = 1) out vec4 o_nrm;
void main() { o_pos = vec4(v_world, 1.0); o_nrm = vec4(normalize(v_normal), 1.0); })");
    glViewport(0, 0, W, H);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    glClearBufferfv(GL_COLOR, 0, zero);
    glClearBufferfv(GL_COLOR, 1, zero);
    glClear(GL_DEPTH_BUFFER_BIT);
    glUseProgram(gprog);
    glUniformMatrix4fv(glGetUniformLocation(gprog, "u_view_proj"), 1, GL_FALSE, glm::value_ptr(camera_view_proj));
    draw_scene();
    std::vector<glm::vec4> gpos(static_cast<std::size_t>(W * H)), gnrm(gpos.size());
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glReadPixels(0, 0, W, H, GL_RGBA, GL_FLOAT, gpos.data());
    glReadBuffer(GL_COLOR_ATTACHMENT1);
    glReadPixels(0, 0, W, H, GL_RGBA, GL_FLOAT, gnrm.data());

    // 8 x 8 stratified, jittered points of the square emitter (plane y = light_center.y).
    std::mt19937 rng(2005);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    const int strata = 8;
    double se = 0.0, se_pen = 0.0;
    int counted = 0, penumbra = 0;
    for (std::size_t k = 0; k < gpos.size(); ++k) {
        if (gpos[k].w == 0.0f) continue;
        const glm::vec3 p(gpos[k]), n(gnrm[k]);
        bool whole_light_above = true;  // every emitter corner above the tangent plane
        for (int c = 0; c < 4; ++c) {
            const glm::vec3 corner = light_center + 0.5f * light_size * glm::vec3((c & 1) ? 1.0f : -1.0f, 0.0f, (c & 2) ? 1.0f : -1.0f);
            whole_light_above = whole_light_above && glm::dot(n, corner - p) > 0.0f;
        }
        if (!whole_light_above) continue;
        int visible = 0;
        for (int i = 0; i < strata; ++i)
            for (int j = 0; j < strata; ++j) {
                const glm::vec3 s = light_center + light_size * glm::vec3((float(i) + u01(rng)) / strata - 0.5f, 0.0f,
                                                                          (float(j) + u01(rng)) / strata - 0.5f);
                const glm::vec3 from = p + n * 1e-4f;
                bool blocked = false;
                for (std::size_t b = 0; b < box_meshes.size() && !blocked; ++b)
                    blocked = segment_hits_box(from, s, kBoxes[b]) && docs::segment_occluded(box_meshes[b], from, s);
                visible += blocked ? 0 : 1;
            }
        const double ref = double(visible) / double(strata * strata);
        const double v = double(rgba[4 * k]) / 255.0;
        se += (v - ref) * (v - ref);
        ++counted;
        if (ref > 0.0 && ref < 1.0) {
            se_pen += (v - ref) * (v - ref);
            ++penumbra;
        }
    }
    const double rmse = std::sqrt(se / std::max(counted, 1)), rmse_pen = std::sqrt(se_pen / std::max(penumbra, 1));
    std::printf("gl_pcss: %d receiver pixels (%d in penumbrae), RMSE %.4f, penumbra RMSE %.4f against an 8x8-sample "
                "area-light ray cast%s\n",
                counted, penumbra, rmse, rmse_pen, rmse <= 0.05 ? "" : "  FAIL (> 0.05)");
    const GLenum err = glGetError();
    if (err != GL_NO_ERROR) {
        std::printf("gl_pcss: GL error 0x%x\n", err);
        return 1;
    }
    return counted > 10000 && penumbra > 500 && rmse <= 0.05 ? 0 : 1;
}
