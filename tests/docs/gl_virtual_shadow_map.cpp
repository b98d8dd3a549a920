// tests/docs/gl_virtual_shadow_map.cpp - the GL usage of docs/virtual_shadow_map.md, assembled: the
// floor scene of the docs programs under a sun, a virtual shadow map built with the parts `pool` (the
// depth atlas and the snippet's two SSBOs) and `frame` (place, mark, plan, render the listed pages,
// upload the page table), then the lookup at ground points. Two frames: the first fills the pool, the
// second moves a box (its old and new bounds invalidate the pages they touch). Each frame the lookup
// must agree with a CPU ray cast toward the sun at >= 99.5% of the ground points away from shadow
// edges, and the second frame must render fewer pages than the first. Exit 0 when it holds, 1
// otherwise, 77 without GL.
#include <shadowkit/virtual_shadow_map.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "docs_gl.hpp"

namespace {

// The marking and lookup passes over points (docs::shade_points): positions relative to u_anchor.
const char* kMarkFS = R"(
flat in vec4 v_point;
uniform vec3 u_anchor;
uniform float u_pixel_angle;
layout(location = 0) out float o_value;
void main() {
    vec3 rel = v_point.xyz - u_anchor;
    sk_vsm_mark(rel, sk_vsm_level_for_footprint(length(rel) * u_pixel_angle, -2.0), 0);
    o_value = 0.0;
}
)";
const char* kLookupFS = R"(
layout(binding = 0) uniform sampler2D u_pool;
flat in vec4 v_point;
uniform vec3 u_anchor;
uniform float u_pixel_angle;
layout(location = 0) out float o_value;
void main() {
    vec3 rel = v_point.xyz - u_anchor;
    int level = sk_vsm_level_for_footprint(length(rel) * u_pixel_angle, -2.0);
    o_value = sk_vsm_visibility(u_pool, rel, vec3(0.0, 1.0, 0.0), level, 0, 0.0);
}
)";

}  // namespace

int main() {
    if (!docs::gl_context(64, 64)) return docs::no_gl_exit_code();
    const glm::dvec3 camera(0.5, 5.5, 7.5);  // docs::floor_scene_camera's eye: the anchor
    const glm::vec4 sun(0.4f, 1.0f, 0.25f, 0.0f);
    // the casters: the floor and the four boxes, each drawn on its own, positions relative to the camera
    std::vector<docs::Box> boxes = docs::floor_boxes();
    std::vector<float> caster_bounds;
    GLuint caster_vao = 0, caster_vbo = 0;
    glGenVertexArrays(1, &caster_vao);
    glGenBuffers(1, &caster_vbo);
    auto upload = [&] {
        std::vector<glm::vec3> v;
        caster_bounds = {-4.0f, 0.0f, -4.0f, 4.0f, 0.0f, 4.0f};
        const docs::Mesh floor = docs::quad_y(0.0f, 4.0f);
        for (std::uint32_t i : floor.indices) v.push_back(floor.positions[i] - glm::vec3(camera));
        for (std::size_t b = 0; b < boxes.size(); ++b) {
            const docs::Mesh m = docs::box(boxes[b].lo, boxes[b].hi);
            for (std::uint32_t i : m.indices) v.push_back(m.positions[i] - glm::vec3(camera));
            caster_bounds.insert(caster_bounds.end(), {boxes[b].lo.x, boxes[b].lo.y, boxes[b].lo.z, boxes[b].hi.x, boxes[b].hi.y, boxes[b].hi.z});
        }
        glBindVertexArray(caster_vao);
        glBindBuffer(GL_ARRAY_BUFFER, caster_vbo);
        glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(v.size() * sizeof(glm::vec3)), v.data(), GL_DYNAMIC_DRAW);
        glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(glm::vec3), nullptr);
        glEnableVertexAttribArray(0);
    };
    upload();
    auto draw_caster = [&](std::uint32_t i) {  // 0: the floor (6 vertices), then 36 per box
        glBindVertexArray(caster_vao);
        if (i == 0) glDrawArrays(GL_TRIANGLES, 0, 6);
        else glDrawArrays(GL_TRIANGLES, GLint(6 + 36 * (i - 1)), 36);
    };
    const GLuint caster_program = docs::gl_program(R"(#version 450 core
layout(location = 0) in vec3 a_position;
uniform mat4 u_light_view_proj;
void main() { gl_Position = u_light_view_proj * vec4(a_position, 1.0); }
)",
                                                   "#version 450 core\nvoid main() {}\n");
    const std::string snippet = docs::snippet("virtual_shadow_map");
    const GLuint mark_program = docs::gl_program(docs::points_vertex_shader(), "#version 450 core\n" + snippet + kMarkFS);
    const GLuint lookup_program = docs::gl_program(docs::points_vertex_shader(), "#version 450 core\n" + snippet + kLookupFS);
    // the ground points of a 96 x 96 grid over the camera's picture, and their pixel's size per unit distance
    const glm::mat4 view = glm::lookAt(glm::vec3(camera), glm::vec3(0.0f, 0.5f, 0.0f), glm::vec3(0.0f, 1.0f, 0.0f));
    const glm::mat4 proj = glm::perspective(glm::radians(50.0f), 1.0f, 0.1f, 50.0f);
    const std::vector<glm::vec4> points = docs::ground_points(view, proj, 0.1f, 50.0f);
    const float pixel_angle = 2.0f * std::tan(glm::radians(25.0f)) / 96.0f;
    for (GLuint p : {mark_program, lookup_program}) {
        glProgramUniform3f(p, glGetUniformLocation(p, "u_anchor"), float(camera.x), float(camera.y), float(camera.z));
        glProgramUniform1f(p, glGetUniformLocation(p, "u_pixel_angle"), pixel_angle);
    }
    auto mark_visible_points = [&] {
        glUseProgram(mark_program);
        docs::shade_points(mark_program, points);
    };

    shadowkit::VsmLayout layout;
    layout.page_texels = 64;
    layout.virtual_texels = 4096;
    layout.level_count = 8;
    layout.level0_extent_world = 1.0;  // level 7: 128 units
    layout.depth_range_world = 50.0;
    layout.pool_pages = 512;
    shadowkit::VsmState vsm;
    if (shadowkit::vsm_state_init(layout, vsm).status != shadowkit::Status::Ok) return 1;

#include "pool.inc"

    std::vector<shadowkit::VsmCasterMove> moves;
    std::size_t rendered[2] = {0, 0};
    bool ok = true;
    for (int frame = 0; frame < 2; ++frame) {
        if (frame == 1) {  // the floating slab (box 1, caster 2) moves by half a unit
            shadowkit::VsmCasterMove m;
            for (int k = 0; k < 3; ++k) {
                m.previous_bounds[k] = boxes[1].lo[k];
                m.previous_bounds[3 + k] = boxes[1].hi[k];
            }
            boxes[1].lo.x -= 0.5f;
            boxes[1].hi.x -= 0.5f;
            for (int k = 0; k < 3; ++k) {
                m.bounds[k] = boxes[1].lo[k];
                m.bounds[3 + k] = boxes[1].hi[k];
            }
            moves.push_back(m);
            upload();
        }

#include "frame.inc"

        rendered[frame] = plan.count;
        glUseProgram(lookup_program);
        glBindTextureUnit(0, pool_tex);
        const std::vector<float> lit = docs::shade_points(lookup_program, points);
        const docs::GroundScore score = docs::score_ground_points(
            points, lit, boxes, glm::normalize(glm::vec3(sun)), [&](std::size_t) { return 0.05; });
        std::printf("frame %d: %zu pages requested, %zu rendered, %zu invalidated; %d of %d ground points agree (%.4f)\n",
                    frame, plan.requested, plan.count, plan.invalidated, score.agree, score.counted, score.ratio());
        ok = ok && score.counted > 3000 && score.ratio() >= 0.995;
    }
    ok = ok && rendered[1] > 0 && rendered[1] < rendered[0];
    return ok ? 0 : 1;
}
