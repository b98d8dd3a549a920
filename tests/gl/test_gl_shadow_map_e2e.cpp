// End-to-end check of the GL harness: a depth-only shadow map of a box over a plane from a spot
// light, a camera view shaded with a hardware depth compare (sampler2DShadow), and the lit/shadowed
// classification of every receiver pixel compared with an independent CPU ray cast of the same
// scene (ray-box slab test from the G-buffer position to the light).
#include <doctest/doctest.h>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>

#include "gl_test.hpp"
#include "scene.hpp"

namespace {

const char* kDepthVS = R"(#version 450 core
layout(location = 0) in vec3 a_position;
uniform mat4 u_light_view_proj;
void main() { gl_Position = u_light_view_proj * vec4(a_position, 1.0); }
)";
const char* kDepthFS = R"(#version 450 core
void main() {}
)";

const char* kViewVS = R"(#version 450 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
uniform mat4 u_view_proj;
out vec3 v_world;
out vec3 v_normal;
void main() {
    v_world = a_position;
    v_normal = a_normal;
    gl_Position = u_view_proj * vec4(a_position, 1.0);
}
)";
const char* kViewFS = R"(#version 450 core
in vec3 v_world;
in vec3 v_normal;
uniform mat4 u_light_view_proj;
uniform sampler2DShadow u_shadow_map;
layout(location = 0) out float o_visibility;
layout(location = 1) out vec4 o_world;   // xyz = position, w = 1 where geometry was drawn
layout(location = 2) out vec4 o_normal;
void main() {
    vec4 lc = u_light_view_proj * vec4(v_world, 1.0);
    vec3 ndc = lc.xyz / lc.w;
    vec3 uvz = ndc * 0.5 + 0.5;              // GL clip depth [-1,1] -> window [0,1]
    bool inside = all(greaterThanEqual(uvz.xy, vec2(0.0))) && all(lessThanEqual(uvz.xy, vec2(1.0))) && lc.w > 0.0;
    o_visibility = inside ? texture(u_shadow_map, uvz) : 0.0;
    o_world = vec4(v_world, 1.0);
    o_normal = vec4(normalize(v_normal), 0.0);
}
)";

// Independent CPU reference: does the segment from p to the light hit the box (slab test)?
bool segment_hits_box(glm::vec3 p, glm::vec3 light, glm::vec3 lo, glm::vec3 hi) {
    const glm::vec3 d = light - p;
    float t0 = 0.f, t1 = 1.f;
    for (int a = 0; a < 3; ++a) {
        if (std::abs(d[a]) < 1e-12f) {
            if (p[a] < lo[a] || p[a] > hi[a]) return false;
            continue;
        }
        float ta = (lo[a] - p[a]) / d[a], tb = (hi[a] - p[a]) / d[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
        if (t0 > t1) return false;
    }
    return true;
}

}  // namespace

TEST_CASE("hard shadow map with sampler2DShadow agrees with a CPU ray cast on >= 99.5% of receiver pixels") {
    auto& ctx = gl_test_context();
    MESSAGE("renderer: " << ctx.renderer);

    const glm::vec3 box_c(0.f, 0.8f, 0.f), box_h(0.6f, 0.3f, 0.45f);
    sk::Mesh floor = sk::make_plane("floor", {0.f, 0.f, 0.f}, 3.f, 3.f);
    sk::Mesh box = sk::make_box("box", box_c, box_h);
    const glm::vec3 light_pos(1.f, 4.f, 0.5f);

    std::vector<skgl::GpuMesh> gpu;
    for (const sk::Mesh* m : {&floor, &box})
        gpu.push_back(skgl::upload_mesh(&m->positions[0].x, &m->normals[0].x, m->positions.size(), m->indices.data(),
                                        m->indices.size()));

    const glm::mat4 light_vp = glm::perspective(glm::radians(80.f), 1.f, 0.5f, 20.f) *
                               glm::lookAt(light_pos, glm::vec3(0.f), glm::vec3(0.f, 0.f, -1.f));
    const int sm_size = 1024;
    std::string why;
    skgl::Target sm;
    REQUIRE_MESSAGE(skgl::make_target(sm, sm_size, sm_size, {}, GL_DEPTH_COMPONENT32F, why), why);

    std::string log;
    GLuint depth_prog = skgl::compile_program({{GL_VERTEX_SHADER, kDepthVS}, {GL_FRAGMENT_SHADER, kDepthFS}}, log);
    REQUIRE_MESSAGE(depth_prog != 0, log);
    GLuint view_prog = skgl::compile_program({{GL_VERTEX_SHADER, kViewVS}, {GL_FRAGMENT_SHADER, kViewFS}}, log);
    REQUIRE_MESSAGE(view_prog != 0, log);

    // Pass 1: shadow map (slope-scaled polygon offset against acne).
    glBindFramebuffer(GL_FRAMEBUFFER, sm.fbo);
    glViewport(0, 0, sm_size, sm_size);
    glEnable(GL_DEPTH_TEST);
    glClearDepth(1.0);
    glClear(GL_DEPTH_BUFFER_BIT);
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(1.5f, 2.f);
    glUseProgram(depth_prog);
    glUniformMatrix4fv(glGetUniformLocation(depth_prog, "u_light_view_proj"), 1, GL_FALSE, glm::value_ptr(light_vp));
    for (const auto& g : gpu) skgl::draw_mesh(g);
    glDisable(GL_POLYGON_OFFSET_FILL);

    // Pass 2: camera view, visibility + G-buffer.
    const int w = 320, h = 240;
    skgl::Target view;
    REQUIRE_MESSAGE(skgl::make_target(view, w, h, {GL_R32F, GL_RGBA32F, GL_RGBA32F}, GL_DEPTH_COMPONENT32F, why), why);
    const glm::mat4 cam_vp = glm::perspective(0.9f, float(w) / float(h), 0.1f, 50.f) *
                             glm::lookAt(glm::vec3(0.f, 3.5f, 5.f), glm::vec3(0.f, 0.3f, 0.f), glm::vec3(0.f, 1.f, 0.f));
    glBindFramebuffer(GL_FRAMEBUFFER, view.fbo);
    glViewport(0, 0, w, h);
    const float zero[4] = {0.f, 0.f, 0.f, 0.f};
    glClearBufferfv(GL_COLOR, 0, zero);
    glClearBufferfv(GL_COLOR, 1, zero);
    glClearBufferfv(GL_COLOR, 2, zero);
    glClear(GL_DEPTH_BUFFER_BIT);
    skgl::set_depth_compare(sm.depth, true, false);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, sm.depth);
    glUseProgram(view_prog);
    glUniform1i(glGetUniformLocation(view_prog, "u_shadow_map"), 0);
    glUniformMatrix4fv(glGetUniformLocation(view_prog, "u_view_proj"), 1, GL_FALSE, glm::value_ptr(cam_vp));
    glUniformMatrix4fv(glGetUniformLocation(view_prog, "u_light_view_proj"), 1, GL_FALSE, glm::value_ptr(light_vp));
    for (const auto& g : gpu) skgl::draw_mesh(g);
    CHECK(skgl::gl_error_string() == "");

    const auto vis = skgl::read_color_float(view, 0, 1);
    const auto world = skgl::read_color_float(view, 1, 4);
    const auto normal = skgl::read_color_float(view, 2, 4);

    // CPU reference classification per pixel: -1 = not a receiver (background or facing away).
    std::vector<int> ref(static_cast<std::size_t>(w * h), -1);
    for (int i = 0; i < w * h; ++i) {
        const auto k = static_cast<std::size_t>(i);
        if (world[k * 4 + 3] == 0.f) continue;
        const glm::vec3 p(world[k * 4], world[k * 4 + 1], world[k * 4 + 2]);
        const glm::vec3 n(normal[k * 4], normal[k * 4 + 1], normal[k * 4 + 2]);
        // facing away from the light, or grazing it (the terminator is an edge too): not compared
        if (glm::dot(n, glm::normalize(light_pos - p)) <= 0.05f) continue;
        // the spot light's cone is its shadow-map frustum: outside it nothing is lit
        const glm::vec4 lc = light_vp * glm::vec4(p, 1.f);
        if (lc.w <= 0.f || std::abs(lc.x) > 0.98f * lc.w || std::abs(lc.y) > 0.98f * lc.w) continue;
        const glm::vec3 q = p + 1e-3f * n;  // offset off the surface (scene size ~6 units)
        ref[k] = segment_hits_box(q, light_pos, box_c - box_h, box_c + box_h) ? 0 : 1;
    }
    int compared = 0, agree = 0, shadowed = 0, lit = 0;
    for (int y = 1; y < h - 1; ++y)
        for (int x = 1; x < w - 1; ++x) {
            const auto k = static_cast<std::size_t>(y * w + x);
            if (ref[k] < 0) continue;
            bool edge = false;  // skip pixels within one pixel of a reference shadow edge
            for (int dy = -1; dy <= 1 && !edge; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int r = ref[static_cast<std::size_t>((y + dy) * w + x + dx)];
                    if (r >= 0 && r != ref[k]) edge = true;
                }
            if (edge) continue;
            ++compared;
            (ref[k] ? lit : shadowed)++;
            if ((vis[k] > 0.5f ? 1 : 0) == ref[k]) ++agree;
        }
    const double agreement = compared ? double(agree) / double(compared) : 0.0;
    MESSAGE("receiver pixels compared: " << compared << ", lit " << lit << ", shadowed " << shadowed
                                         << ", agreement " << agreement);
    CHECK(compared > w * h / 4);
    CHECK(shadowed > compared / 50);  // the test scene really has a shadow to get right
    CHECK(lit > compared / 4);
    CHECK(agreement >= 0.995);

    for (auto& g : gpu) skgl::destroy_mesh(g);
    skgl::destroy_target(sm);
    skgl::destroy_target(view);
    glDeleteProgram(depth_prog);
    glDeleteProgram(view_prog);
}

TEST_CASE("compile errors come back as readable logs with the stage and numbered source") {
    std::string log;
    const GLuint p = skgl::compile_program(
        {{GL_FRAGMENT_SHADER, "#version 450 core\nout vec4 c;\nvoid main() { c = vec4(1.0) }\n"}}, log);
    CHECK(p == 0);
    CHECK(log.find("fragment shader failed to compile") != std::string::npos);
    CHECK(log.find("  3: void main()") != std::string::npos);
}

TEST_CASE("median frame timing is a positive, finite number of milliseconds") {
    std::vector<double> samples;
    const double ms = skgl::median_frame_ms([] { glClear(GL_COLOR_BUFFER_BIT); }, 2, 9, &samples);
    CHECK(samples.size() == 9);
    CHECK(ms >= 0.0);
    CHECK(std::isfinite(ms));
    const auto [lo, hi] = std::minmax_element(samples.begin(), samples.end());
    CHECK(ms >= *lo);
    CHECK(ms <= *hi);
}
