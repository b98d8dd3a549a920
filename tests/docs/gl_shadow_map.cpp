// tests/docs/gl_shadow_map.cpp - the "new user" trial for docs/shadow_map.md: a hard shadow map
// built only from that page's blocks (named parts gl_shadow_map/*, #included below) and the
// comments of glsl/shadow_map.glsl and include/shadowkit/shadow_bias.hpp. The program adds what a
// user's renderer has anyway: a GL context, a scene (boxes over a floor, one on the floor, two
// floating) with its draw call, a camera, and the check: the lit/shadowed result read back per
// pixel against a CPU ray cast from the same surface points, for a spot light, a point light (cube
// map) and a directional light from either side of the camera (both hemispheres), at least 99.5%
// agreement on pixels away from shadow edges. Prints the score; exit 0 when every light passes.
#include "docs_gl.hpp"

#include <shadowkit/shadow_bias.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

namespace {

// The scene: a floor and four boxes (one resting on it: contact shadows).
docs::Mesh make_scene() {
    docs::Mesh m = docs::quad_y(0.0f, 4.0f);
    docs::append(m, docs::box({-1.6f, 0.0f, -0.6f}, {-0.6f, 1.0f, 0.4f}));   // on the floor
    docs::append(m, docs::box({0.5f, 0.9f, -0.8f}, {1.6f, 1.3f, 0.3f}));     // floating slab
    docs::append(m, docs::box({-0.4f, 1.9f, 0.7f}, {0.7f, 2.0f, 1.7f}));     // thin plate, high
    docs::append(m, docs::box({1.2f, 0.0f, 1.2f}, {1.5f, 2.2f, 1.5f}));      // a post
    return m;
}

// Flat-shaded vertex arrays (position, normal) of the mesh: what the user's renderer draws.
struct FlatMesh {
    std::vector<glm::vec3> pos, nrm;
};
FlatMesh flatten(const docs::Mesh& m) {
    FlatMesh f;
    for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
        const glm::vec3 a = m.positions[m.indices[t]], b = m.positions[m.indices[t + 1]], c = m.positions[m.indices[t + 2]];
        const glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
        for (const glm::vec3& p : {a, b, c}) {
            f.pos.push_back(p);
            f.nrm.push_back(n);
        }
    }
    return f;
}

// The score: per pixel the surface point and normal (a G-buffer pass of the program, not of the
// docs), the CPU ray cast to the light, and the docs' visibility read back from the window.
struct Score {
    int counted = 0, agree = 0;  // away from shadow edges
    int all = 0, all_agree = 0;  // every receiver pixel (edges: the bias's peter-panning, the 2x2 filter)
    double fraction() const { return counted ? double(agree) / double(counted) : 0.0; }
};

}  // namespace

int main() {
    const int W = 320, H = 240;
    if (!docs::gl_context(W, H)) return docs::no_gl_exit_code();
    const GLuint window = docs::window_framebuffer();
    const docs::Mesh scene = make_scene();
    const FlatMesh flat = flatten(scene);
    const auto vertex_count = static_cast<GLsizei>(flat.pos.size());

    // The user's mesh upload and draw call: attribute 0 position, attribute 1 normal.
    GLuint vao = 0, vbo[2] = {0, 0};
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    glGenBuffers(2, vbo);
    for (int k = 0; k < 2; ++k) {
        const std::vector<glm::vec3>& data = k == 0 ? flat.pos : flat.nrm;
        glBindBuffer(GL_ARRAY_BUFFER, vbo[k]);
        glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(data.size() * sizeof(glm::vec3)), data.data(), GL_STATIC_DRAW);
        glVertexAttribPointer(static_cast<GLuint>(k), 3, GL_FLOAT, GL_FALSE, 0, nullptr);
        glEnableVertexAttribArray(static_cast<GLuint>(k));
    }
    const auto draw_scene = [&] {
        glBindVertexArray(vao);
        glDrawArrays(GL_TRIANGLES, 0, vertex_count);
    };
    // The camera.
    const glm::mat4 camera_view_proj = glm::perspective(glm::radians(50.0f), float(W) / float(H), 0.1f, 50.0f) *
                                       glm::lookAt(glm::vec3(0.5f, 5.5f, 7.5f), glm::vec3(0.0f, 0.5f, 0.0f), glm::vec3(0.0f, 1.0f, 0.0f));
    // The scene's bounds (for the light frusta below).
    const glm::vec3 scene_min(-4.0f, 0.0f, -4.0f), scene_max(4.0f, 2.2f, 4.0f);

    namespace sk = shadowkit;
#include "map.inc"
#include "programs.inc"

    // The program's G-buffer: world position and normal per pixel (RGBA32F), for the score only.
    GLuint gbuf_fbo = 0, gbuf_tex[2] = {0, 0}, gbuf_depth = 0;
    glGenFramebuffers(1, &gbuf_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, gbuf_fbo);
    glGenTextures(2, gbuf_tex);
    for (int k = 0; k < 2; ++k) {
        glBindTexture(GL_TEXTURE_2D, gbuf_tex[k]);
        glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA32F, W, H);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(k), GL_TEXTURE_2D, gbuf_tex[k], 0);
    }
    glGenRenderbuffers(1, &gbuf_depth);
    glBindRenderbuffer(GL_RENDERBUFFER, gbuf_depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, W, H);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, gbuf_depth);
    const GLenum bufs[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glDrawBuffers(2, bufs);
    const GLuint gbuf_prog = docs::gl_program(R"(#version 450 core
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
    const float far_clear[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    glClearBufferfv(GL_COLOR, 0, far_clear);
    glClearBufferfv(GL_COLOR, 1, far_clear);
    glClear(GL_DEPTH_BUFFER_BIT);
    glUseProgram(gbuf_prog);
    glUniformMatrix4fv(glGetUniformLocation(gbuf_prog, "u_view_proj"), 1, GL_FALSE, glm::value_ptr(camera_view_proj));
    draw_scene();
    std::vector<glm::vec4> gpos(static_cast<std::size_t>(W * H)), gnrm(gpos.size());
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glReadPixels(0, 0, W, H, GL_RGBA, GL_FLOAT, gpos.data());
    glReadBuffer(GL_COLOR_ATTACHMENT1);
    glReadPixels(0, 0, W, H, GL_RGBA, GL_FLOAT, gnrm.data());

    struct Case {
        const char* name;
        glm::vec4 light_position;  // shadowkit's convention: w = 1 point/spot, w = 0 direction toward the light
    };
    const Case cases[] = {{"spot light", glm::vec4(2.5f, 6.0f, 3.0f, 1.0f)},
                          {"point light (cube map)", glm::vec4(0.2f, 3.2f, 0.1f, 1.0f)},
                          {"directional, from the camera's side", glm::vec4(0.35f, 1.0f, 0.55f, 0.0f)},
                          {"directional, from behind the scene", glm::vec4(-0.45f, 0.9f, -0.7f, 0.0f)}};
    bool all_ok = true;
    for (int ci = 0; ci < 4; ++ci) {
        const glm::vec4 light_position = cases[ci].light_position;
        const bool cube = ci == 1;
        if (!cube) {
#include "light.inc"
#include "render_map.inc"
#include "lighting.inc"
        } else {
#include "render_cube.inc"
#include "lighting_cube.inc"
        }
        std::vector<unsigned char> rgba(static_cast<std::size_t>(W * H) * 4);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, window);
        glReadBuffer(GL_COLOR_ATTACHMENT0);
        glReadPixels(0, 0, W, H, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());

        // CPU ray cast per pixel: -1 not a receiver (background, facing away or grazing), 0 shadowed, 1 lit.
        std::vector<int> cls(gpos.size(), -1);
        for (std::size_t k = 0; k < gpos.size(); ++k) {
            if (gpos[k].w == 0.0f) continue;
            const glm::vec3 p(gpos[k]), n(gnrm[k]);
            const glm::vec3 to_light = light_position.w > 0.0f ? glm::vec3(light_position) / light_position.w - p
                                                               : glm::normalize(glm::vec3(light_position));
            if (glm::dot(n, glm::normalize(to_light)) < 0.1f) continue;  // facing away or grazing: the terminator is an edge
            const glm::vec3 from = p + n * 1e-4f;
            const glm::vec3 to = light_position.w > 0.0f ? glm::vec3(light_position) / light_position.w : p + to_light * 100.0f;
            cls[k] = docs::segment_occluded(scene, from, to) ? 0 : 1;
        }
        // Away from shadow edges: every pixel within 2 of it has the same class.
        Score s;
        for (int y = 2; y < H - 2; ++y)
            for (int x = 2; x < W - 2; ++x) {
                const std::size_t k = static_cast<std::size_t>(y * W + x);
                if (cls[k] < 0) continue;
                ++s.all;
                s.all_agree += (rgba[4 * k] >= 128 ? 1 : 0) == cls[k];
                bool interior = true;
                for (int dy = -2; dy <= 2 && interior; ++dy)
                    for (int dx = -2; dx <= 2 && interior; ++dx)
                        interior = cls[static_cast<std::size_t>((y + dy) * W + x + dx)] == cls[k];
                if (!interior) continue;
                ++s.counted;
                const int gpu = rgba[4 * k] >= 128 ? 1 : 0;
                s.agree += gpu == cls[k];
            }
        const bool ok = s.counted > 10000 && s.fraction() >= 0.995;
        all_ok = all_ok && ok;
        std::printf("gl_shadow_map: %-36s %6d pixels away from shadow edges, %.3f%% agree with the ray cast%s"
                    " (all %d receiver pixels: %.2f%%)\n",
                    cases[ci].name, s.counted, 100.0 * s.fraction(), ok ? "" : "  FAIL (< 99.5%)", s.all,
                    100.0 * double(s.all_agree) / double(std::max(s.all, 1)));
    }
    const GLenum err = glGetError();
    if (err != GL_NO_ERROR) {
        std::printf("gl_shadow_map: GL error 0x%x\n", err);
        return 1;
    }
    return all_ok ? 0 : 1;
}
