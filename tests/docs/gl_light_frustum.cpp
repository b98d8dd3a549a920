// docs/light_frustum.md, as one program: the parts marked <!-- example: gl_light_frustum/PART --> in
// the page are included below where a user's program would have them. The program adds what a user has
// anyway (a GL context, a scene, shader compilation) and the check: a grid of ground points seen by the
// camera is shaded by glsl/shadow_map.glsl with the fitted matrix on the GPU and compared with a CPU
// ray cast toward the sun; the culled casters must be the ones that cannot shadow what the camera sees.
// Exits 77 (skipped) without an EGL/GL 4.5 context (1 when SHADOWKIT_REQUIRE_GL is set), 1 if fewer than 99.5% of the points away from
// shadow edges agree. The context, mesh, shader and score helpers are tests/docs/docs_gl.hpp.
#include <shadowkit/light_frustum.hpp>

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
    const std::vector<docs::Box> boxes = {{{-1, 0, -11}, {1, 2.5f, -9}},    {{6, 0, -31}, {9, 6, -27}},
                                          {{-12, 0, -55}, {-6, 10, -49}},  {{-3, 1, -4}, {-2, 1.5f, -3}},
                                          {{-2, 0, 40}, {2, 3, 44}},       {{-50, 0, -20}, {-46, 2, -16}}};  // last two: unseen
    std::vector<float> caster_boxes;  // 6 floats per box for the fit: min xyz, max xyz
    for (const docs::Box& b : boxes) caster_boxes.insert(caster_boxes.end(), {b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y, b.hi.z});
    docs::Mesh casters;  // 12 triangles per box: box k is vertices 36 k .. 36 k + 35 below
    for (const docs::Box& b : boxes) docs::append(casters, docs::box(b.lo, b.hi));
    const GLuint caster_vao = docs::vertex_array(docs::triangles(casters).positions);  // attribute 0: position
    const glm::mat4 view = glm::lookAt(glm::vec3(0, 6, 8), glm::vec3(0, 0, -20), glm::vec3(0, 1, 0));
    const float fovy = glm::radians(60.0f), aspect = 16.0f / 9.0f;
    const glm::mat4 proj = glm::perspective(fovy, aspect, 0.1f, 500.0f);
    const glm::vec3 to_sun = glm::normalize(glm::vec3(0.4f, 1.0f, 0.3f));  // direction toward the sun
    const GLsizei size = 2048;
    const GLuint depth_program = docs::depth_only_program();

#include "fit.inc"
#include "texture.inc"
#include "shadow_pass.inc"
    if (fit.needed != 4) {
        std::fprintf(stderr, "expected 4 of 6 casters kept, got %zu\n", fit.needed);
        return 1;
    }

    // --- the check: ground points seen by the camera, shaded on the GPU by the snippet
    const std::vector<glm::vec4> points = docs::ground_points(view, proj, 0.1f, in.max_distance);
    const GLuint lookup_program = docs::gl_program(docs::points_vertex_shader(), "#version 450 core\n" + docs::snippet("shadow_map") + R"(
layout(binding = 0) uniform sampler2DShadow u_shadow_map;
uniform mat4 u_light_view_proj;
flat in vec4 v_point;
out float lit;
void main() {
    lit = sk_shadow_map_visibility(u_shadow_map, u_light_view_proj, v_point.xyz, false, 0.0, 1.0);
})");
    glUseProgram(lookup_program);
#include "lookup.inc"
    const std::vector<float> lit = docs::shade_points(lookup_program, points);

    // CPU reference: a ray from the point toward the sun; points within 3 texels of a shadow edge
    // (the reference changes within that distance) are not counted. The texel footprint: the map's
    // world extent / size (orthographic fit).
    const double e = 3.0 * 2.0 / double(size) / std::fmin(double(glm::length(glm::vec3(fit.view_proj[0][0], fit.view_proj[1][0], fit.view_proj[2][0]))),
                                                  double(glm::length(glm::vec3(fit.view_proj[0][1], fit.view_proj[1][1], fit.view_proj[2][1]))));
    const docs::GroundScore score = docs::score_ground_points(points, lit, boxes, to_sun, [&](std::size_t) { return e; });
    const int agree = score.agree, counted = score.counted;
    const double ratio = score.ratio();
    std::printf("light_frustum: %zu of %zu casters kept; %d of %d ground points away from shadow edges agree with the ray cast (%.2f%%)\n",
                fit.needed, boxes.size(), agree, counted, 100.0 * ratio);
    return (counted > 1000 && ratio >= 0.995) ? 0 : 1;
}
