// docs/cascades.md, as one program: the parts marked <!-- example: gl_cascades/PART --> in the page
// are included below where a user's program would have them. The program adds what a user has anyway
// (a GL context, a scene, shader compilation) and the check: a grid of ground points seen by the
// camera is shaded by glsl/cascades.glsl on the GPU and compared with a CPU ray cast toward the sun.
// Exits 77 (skipped) without an EGL/GL 4.5 context (1 when SHADOWKIT_REQUIRE_GL is set), 1 if fewer than 99.5% of the points away from
// shadow edges agree. The context, mesh, shader and score helpers are tests/docs/docs_gl.hpp.
#include <shadowkit/cascades.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "docs_gl.hpp"

int main() {
    if (!docs::gl_context(64, 64)) return docs::no_gl_exit_code();
    // --- the user's scene: a ground plane (receiver) and boxes (casters), a camera, the sun
    const std::vector<docs::Box> boxes = {{{-1, 0, -11}, {1, 2.5f, -9}}, {{6, 0, -31}, {9, 6, -27}},
                                          {{-12, 0, -55}, {-6, 10, -49}}, {{-3, 1, -4}, {-2, 1.5f, -3}}};
    docs::Mesh casters;  // 12 triangles per box
    for (const docs::Box& b : boxes) docs::append(casters, docs::box(b.lo, b.hi));
    const std::vector<glm::vec3> caster_tris = docs::triangles(casters).positions;
    const GLuint caster_vao = docs::vertex_array(caster_tris);  // attribute 0: position
    const GLsizei caster_vertex_count = GLsizei(caster_tris.size());
    const glm::mat4 view = glm::lookAt(glm::vec3(0, 6, 8), glm::vec3(0, 0, -20), glm::vec3(0, 1, 0));
    const float fovy = glm::radians(60.0f), aspect = 16.0f / 9.0f;
    const glm::mat4 proj = glm::perspective(fovy, aspect, 0.1f, 500.0f);
    const glm::vec3 to_sun = glm::normalize(glm::vec3(0.4f, 1.0f, 0.3f));  // direction toward the sun
    const GLsizei size = 1024;
    const GLuint depth_program = docs::depth_only_program();

#include "fit.inc"
#include "textures.inc"
#include "shadow_pass.inc"

    // --- the check: ground points seen by the camera, shaded on the GPU by the snippet
    const std::vector<glm::vec4> points = docs::ground_points(view, proj, fit.splits[0], fit.splits[4]);
    const GLuint lookup_program = docs::gl_program(docs::points_vertex_shader(), "#version 450 core\n" + docs::snippet("cascades") + R"(
layout(binding = 0) uniform sampler2DArrayShadow u_cascades;
uniform mat4 u_cascade_vp[4];
uniform vec4 u_split_near;
uniform vec4 u_split_far;
uniform float u_texel[4];
flat in vec4 v_point;
out float lit;
void main() {
    // the page's normal offset (the ground's normal is +y) and its constant bias
    int i = sk_cascade_by_depth(v_point.w, u_split_far, 4);
    bool band = i >= 0 && i + 1 < 4 && sk_cascade_blend(v_point.w, u_split_near[i], u_split_far[i], 0.1) > 0.0;
    float texel = i < 0 ? 0.0 : u_texel[band ? i + 1 : i];
    vec3 p = v_point.xyz + vec3(0.0, 1.0, 0.0) * texel;
    lit = sk_cascade_shadow(u_cascades, u_cascade_vp, u_split_near, u_split_far, 4, p, v_point.w, 0.1, 0.0005, false);
})");
    glUseProgram(lookup_program);
#include "lookup.inc"
    const std::vector<float> lit = docs::shade_points(lookup_program, points);

    // CPU reference: a ray from the point toward the sun; points within 3 texels of a shadow edge
    // (the reference changes within that distance) are not counted
    const docs::GroundScore score = docs::score_ground_points(points, lit, boxes, to_sun, [&](std::size_t k) {
        const int c = shadowkit::cascade_select_by_depth(points[k].w, fit.splits, 4).index;
        return c < 0 ? -1.0 : 3.0 * double(cascades[c].texel_world_size);
    });
    const int agree = score.agree, counted = score.counted;
    const double ratio = score.ratio();
    std::printf("cascades: %d of %d ground points away from shadow edges agree with the ray cast (%.2f%%)\n", agree,
                counted, 100.0 * ratio);
    return (counted > 1000 && ratio >= 0.995) ? 0 : 1;
}
