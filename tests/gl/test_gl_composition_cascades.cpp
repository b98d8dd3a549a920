// tests/gl/test_gl_composition_cascades.cpp - issue 25's composition test ("Must hold"): cascades +
// cache + Poisson PCF + the automatic bias, put together the way a user would from the docs pages,
// with the public headers (cascades.hpp, shadow_cache.hpp) and glsl/ snippets (cascades.glsl,
// shadow_cache.glsl, shadow_map.glsl, pcf.glsl) only: no sample code. The GL context comes from
// gl_main.cpp, the user's everyday helpers (shader compilation, meshes, ground points, the CPU ray
// cast) from tests/docs/docs_gl.hpp.
//
// The user's frame, for a camera that pans over a ground with boxes while one box (the cart) drives:
//   1 cascade_fit with stable_world_depth (docs/cascades.md, cached cascades);
//   2 per cascade its double matrix with the x/y translation rebuilt from texel_anchor, and
//     shadow_cache_plan against what its layer holds (the cart's old and new boxes);
//   3 a Scroll copied by whole texels (through a scratch texture), then the plan's rectangles cleared
//     and drawn with shadow_cache.glsl's translation-invariant pass under a scissor;
//   4 the lookup: sk_cascade_by_depth + sk_cascade_blend pick the layers, each read with pcf.glsl's
//     Poisson kernel on the array (16 taps, 1.5 texels) at the receiver plane of
//     sk_plane_depth_gradient, less sk_auto_filtered_bias (shadow_map.glsl): nothing to tune.
// Scored on ground points seen by the camera against a CPU ray cast toward the sun, every frame:
// >= 99.5% of the points away from shadow edges (3 texels beyond the kernel) must agree. The cache
// must also be doing its job (no whole render after the first frame, scrolls on the pan), so the
// score is the cached layers', not a fresh render's.
#include "../docs/docs_gl.hpp"

#include <shadowkit/cascades.hpp>
#include <shadowkit/shadow_cache.hpp>

#include <doctest/doctest.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace {

constexpr int kSize = 1024, kCount = 4, kFrames = 8, kGuard = (4096 - kSize) / 2;
constexpr float kPoissonTexels = 1.5f;

// The invariant caster pass (glsl/shadow_cache.glsl's usage comment, verbatim in shape).
const char* kCasterVS = R"(#version 450 core
layout(location = 0) in vec3 a_position;
uniform mat4 u_light_global;
out vec3 v_global;
void main() { v_global = (u_light_global * vec4(a_position, 1.0)).xyz; gl_Position = vec4(0.0); }
)";
const char* kCasterGS = R"(
layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;
in vec3 v_global[];
uniform ivec2 u_viewport_anchor;
uniform vec2 u_viewport_size;
flat out vec3 g_plane;
flat out vec2 g_origin;
void main() {
    vec3 plane;
    vec2 origin;
    if (!sk_shadow_cache_plane(v_global[0], v_global[1], v_global[2], plane, origin)) return;
    for (int i = 0; i < 3; ++i) {
        g_plane = plane;
        g_origin = origin;
        gl_Position = sk_shadow_cache_position(v_global[i].xy, u_viewport_anchor, u_viewport_size);
        EmitVertex();
    }
    EndPrimitive();
}
)";
const char* kCasterFS = R"(
flat in vec3 g_plane;
flat in vec2 g_origin;
uniform ivec2 u_anchor;
void main() { gl_FragDepth = sk_shadow_cache_depth(g_plane, g_origin, gl_FragCoord.xy, u_anchor); }
)";

// The lookup: the cascade by view depth (v_point.w), blended into the next over the band; per layer
// Poisson PCF with the receiver plane and the automatic filtered bias.
const char* kLookupFS = R"(
layout(binding = 0) uniform sampler2DArrayShadow u_cascades;
uniform mat4 u_cascade_vp[4];
uniform vec4 u_split_near;
uniform vec4 u_split_far;
uniform float u_radius_texels;
flat in vec4 v_point;
out float lit;
float layer_lit(int i, vec3 p, vec3 n) {
    vec4 c = sk_shadow_coord(u_cascade_vp[i], p, false);
    if (any(lessThan(c.xy, vec2(0.0))) || any(greaterThan(c.xy, vec2(1.0)))) return 1.0;
    vec4 g = sk_plane_depth_gradient(u_cascade_vp[i], p, n, false);
    if (g.z == 0.0) return 1.0;  // edge-on
    vec2 texel = 1.0 / vec2(textureSize(u_cascades, 0).xy);
    float b = sk_auto_filtered_bias(g, texel, c.z, 0.0);
    return sk_pcf_poisson(u_cascades, float(i), vec3(c.xy, c.z - b), g.xy, u_radius_texels * texel.x, 16, 0.0);
}
void main() {
    vec3 p = v_point.xyz, n = vec3(0.0, 1.0, 0.0);
    int i = sk_cascade_by_depth(v_point.w, u_split_far, 4);
    if (i < 0) { lit = 1.0; return; }
    float v = layer_lit(i, p, n);
    float w = sk_cascade_blend(v_point.w, u_split_near[i], u_split_far[i], 0.1);
    if (w > 0.0 && i + 1 < 4) v = mix(v, layer_lit(i + 1, p, n), w);
    lit = v;
}
)";

// The scene's casters as one triangle list (attribute 0), rebuilt when the cart moves.
struct CasterBuffer {
    GLuint vao = 0, vbo = 0;
    GLsizei count = 0;
    void upload(const std::vector<docs::Box>& boxes, float ground) {
        docs::Mesh m = docs::quad_y(0.0f, ground);
        for (const docs::Box& b : boxes) docs::append(m, docs::box(b.lo, b.hi));
        const std::vector<glm::vec3> tris = docs::triangles(m).positions;
        if (!vao) {
            glGenVertexArrays(1, &vao);
            glGenBuffers(1, &vbo);
            glBindVertexArray(vao);
            glBindBuffer(GL_ARRAY_BUFFER, vbo);
            glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(glm::vec3), nullptr);
            glEnableVertexAttribArray(0);
        }
        glBindBuffer(GL_ARRAY_BUFFER, vbo);
        glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(tris.size() * sizeof(glm::vec3)), tris.data(), GL_DYNAMIC_DRAW);
        count = GLsizei(tris.size());
    }
};

}  // namespace

TEST_CASE("composition: cached cascades + Poisson PCF + automatic bias through the public snippets match a ray cast") {
    namespace sk = shadowkit;
    // --- the user's scene: a ground (caster and receiver), boxes, a cart that drives; the sun
    const float ground = 150.0f;
    std::vector<docs::Box> boxes = {{{6, 0, -31}, {9, 6, -27}}, {{-12, 0, -55}, {-6, 10, -49}}, {{-3, 1, -4}, {-2, 1.5f, -3}}};
    for (int row = 0; row < 8; ++row)  // a field of boxes along the pan: shadows in every cascade
        for (int col = -3; col <= 3; ++col) {
            const float x = 5.0f * float(col) + 2.5f * float(row % 2), z = -5.0f - 5.0f * float(row);
            const float h = 1.0f + float((row * 3 + col * 5 + 21) % 4);
            boxes.push_back({{x - 0.8f, 0.0f, z - 0.6f}, {x + 0.8f, h, z + 0.6f}});
        }
    boxes.push_back({{-2.5f, 0, -8.5f}, {-1.5f, 1.2f, -7.5f}});  // the cart (last)
    const glm::vec3 to_sun = glm::normalize(glm::vec3(0.4f, 1.0f, 0.3f));
    const glm::mat4 proj = glm::perspective(glm::radians(60.0f), 16.0f / 9.0f, 0.1f, 120.0f);
    CasterBuffer casters_gpu;
    casters_gpu.upload(boxes, ground);
    // the plan's casters: the ground and every box, as boxes this frame and as last rendered
    std::vector<sk::ShadowCacheCaster> casters(boxes.size() + 1);
    auto set_bounds = [&]() {
        const float g[6] = {-ground, 0.0f, -ground, ground, 0.0f, ground};
        std::copy(g, g + 6, casters[0].bounds);
        for (std::size_t i = 0; i < boxes.size(); ++i) {
            const float b[6] = {boxes[i].lo.x, boxes[i].lo.y, boxes[i].lo.z, boxes[i].hi.x, boxes[i].hi.y, boxes[i].hi.z};
            std::copy(b, b + 6, casters[i + 1].bounds);
        }
    };
    set_bounds();

    // --- the programs
    const std::string cache_glsl = "#version 450 core\n" + docs::snippet("shadow_cache");
    const GLuint caster_program = glCreateProgram();
    {
        const std::pair<GLenum, std::string> stages[3] = {
            {GL_VERTEX_SHADER, kCasterVS}, {GL_GEOMETRY_SHADER, cache_glsl + kCasterGS}, {GL_FRAGMENT_SHADER, cache_glsl + kCasterFS}};
        for (const auto& [type, src] : stages) {
            const GLuint sh = glCreateShader(type);
            const char* text = src.c_str();
            glShaderSource(sh, 1, &text, nullptr);
            glCompileShader(sh);
            GLint ok = 0;
            glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
            REQUIRE(ok == GL_TRUE);
            glAttachShader(caster_program, sh);
        }
        glLinkProgram(caster_program);
        GLint linked = 0;
        glGetProgramiv(caster_program, GL_LINK_STATUS, &linked);
        REQUIRE(linked == GL_TRUE);
    }
    const GLuint lookup_program =
        docs::gl_program(docs::points_vertex_shader(), "#version 450 core\n" + docs::snippet("pcf") + docs::snippet("shadow_map") +
                                                           docs::snippet("cascades") + kLookupFS);

    // --- the cascade array (hardware compare, GL_LINEAR: each Poisson tap is a 2x2), its layers'
    //     framebuffers, and the scratch texture a scroll copies through
    GLuint cascades_tex = 0, scratch = 0, fbo[kCount] = {0, 0, 0, 0};
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &cascades_tex);
    glTextureStorage3D(cascades_tex, 1, GL_DEPTH_COMPONENT32F, kSize, kSize, kCount);
    glTextureParameteri(cascades_tex, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(cascades_tex, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(cascades_tex, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glTextureParameteri(cascades_tex, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    glTextureParameteri(cascades_tex, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(cascades_tex, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glCreateTextures(GL_TEXTURE_2D, 1, &scratch);
    glTextureStorage2D(scratch, 1, GL_DEPTH_COMPONENT32F, kSize, kSize);
    glCreateFramebuffers(kCount, fbo);
    for (int i = 0; i < kCount; ++i) {
        glNamedFramebufferTextureLayer(fbo[i], GL_DEPTH_ATTACHMENT, cascades_tex, 0, i);
        glNamedFramebufferDrawBuffer(fbo[i], GL_NONE);
        glNamedFramebufferReadBuffer(fbo[i], GL_NONE);
    }

    sk::ShadowCacheMapState previous[kCount];  // what each layer holds (nothing yet)
    std::vector<sk::ShadowCacheRect> rects(sk::shadow_cache_rect_capacity(casters.size()));
    int renders_after_first = 0, scrolls = 0, worst_counted = 1 << 30, shadowed_points = 0;
    double worst_ratio = 1.0, sum_agree = 0.0, sum_counted = 0.0;
    for (int frame = 0; frame < kFrames; ++frame) {
        // the camera pans right; the cart drives on every other frame
        const glm::vec3 eye(0.45f * float(frame), 6.0f, 8.0f);
        const glm::mat4 view = glm::lookAt(eye, eye + glm::vec3(0, -6, -28), glm::vec3(0, 1, 0));
        for (sk::ShadowCacheCaster& c : casters) std::copy(c.bounds, c.bounds + 6, c.previous_bounds);
        if (frame % 2 == 1) {
            boxes.back().lo.x += 0.6f;
            boxes.back().hi.x += 0.6f;
            casters_gpu.upload(boxes, ground);
            set_bounds();
        }
        // 1. the fit, its depth range fixed in the world
        sk::CascadeInput in;
        in.camera_view = view;
        in.camera_proj = proj;
        in.light_position = glm::vec4(to_sun, 0.0f);
        in.shadow_map_size = kSize;
        in.has_scene_bounds = true;
        in.scene_min = glm::vec3(-ground, 0.0f, -ground);
        in.scene_max = glm::vec3(ground, 10.0f, ground);
        in.stable_world_depth = true;
        sk::Cascade cascades[kCount];
        const sk::CascadeFitResult fit = sk::cascade_fit(in, 0.75f, kCount, cascades, kCount);
        REQUIRE(fit.status == sk::Status::Ok);
        glm::mat4 lookup_vp[kCount];
        for (int i = 0; i < kCount; ++i) {
            // 2. the matrix as the plan compares it: x/y translation rebuilt from texel_anchor
            glm::dmat4 vp(cascades[i].view_proj);
            vp[3][0] = -2.0 * cascades[i].texel_anchor.x / kSize - 1.0;
            vp[3][1] = -2.0 * cascades[i].texel_anchor.y / kSize - 1.0;
            lookup_vp[i] = glm::mat4(vp);
            sk::ShadowCacheMapState now;
            now.view_proj = vp;
            now.width = now.height = kSize;
            const sk::ShadowCachePlan plan = sk::shadow_cache_plan(previous[i], now, casters.data(), casters.size(), rects.data(), rects.size());
            REQUIRE(plan.status == sk::Status::Ok);
            if (frame > 0) {
                renders_after_first += plan.action == sk::ShadowCacheAction::Render ? 1 : 0;
                scrolls += plan.action == sk::ShadowCacheAction::Scroll ? 1 : 0;
            }
            // 3. scroll, then the planned rectangles with the invariant pass
            if (plan.action == sk::ShadowCacheAction::Scroll) {
                const sk::ShadowCacheCopy& c = plan.copy;
                glCopyImageSubData(cascades_tex, GL_TEXTURE_2D_ARRAY, 0, c.src_x, c.src_y, i, scratch, GL_TEXTURE_2D, 0, 0, 0, 0,
                                   c.width, c.height, 1);
                glCopyImageSubData(scratch, GL_TEXTURE_2D, 0, 0, 0, 0, cascades_tex, GL_TEXTURE_2D_ARRAY, 0, c.dst_x, c.dst_y, i,
                                   c.width, c.height, 1);
            }
            const glm::ivec2 anchor(glm::dvec2(cascades[i].texel_anchor));
            glm::dmat4 global(0.0);  // world -> (global texel x, y, window depth)
            for (int k = 0; k < 4; ++k) {
                global[k][0] = 0.5 * kSize * vp[k][0];
                global[k][1] = 0.5 * kSize * vp[k][1];
                global[k][2] = 0.5 * vp[k][2];
            }
            global[3][0] += 0.5 * kSize + anchor.x;
            global[3][1] += 0.5 * kSize + anchor.y;
            global[3][2] += 0.5;
            global[3][3] = 1.0;
            const glm::mat4 global_f(global);
            glBindFramebuffer(GL_FRAMEBUFFER, fbo[i]);
            glViewport(-kGuard, -kGuard, 4096, 4096);
            glEnable(GL_DEPTH_TEST);
            glDepthFunc(GL_LESS);
            glDepthMask(GL_TRUE);
            glClearDepth(1.0);
            glUseProgram(caster_program);
            glUniformMatrix4fv(glGetUniformLocation(caster_program, "u_light_global"), 1, GL_FALSE, glm::value_ptr(global_f));
            glUniform2i(glGetUniformLocation(caster_program, "u_anchor"), anchor.x, anchor.y);
            glUniform2i(glGetUniformLocation(caster_program, "u_viewport_anchor"), anchor.x - kGuard, anchor.y - kGuard);
            glUniform2f(glGetUniformLocation(caster_program, "u_viewport_size"), 4096.0f, 4096.0f);
            glBindVertexArray(casters_gpu.vao);
            glEnable(GL_SCISSOR_TEST);
            for (std::size_t k = 0; k < plan.count; ++k) {
                glScissor(rects[k].x, rects[k].y, rects[k].width, rects[k].height);
                glClear(GL_DEPTH_BUFFER_BIT);
                glDrawArrays(GL_TRIANGLES, 0, casters_gpu.count);
            }
            glDisable(GL_SCISSOR_TEST);
            previous[i] = now;
            previous[i].has_content = true;
        }

        // 4. the lookup at ground points the camera sees, scored against the ray cast
        const std::vector<glm::vec4> points = docs::ground_points(view, proj, fit.splits[0], fit.splits[kCount]);
        glUseProgram(lookup_program);
        glBindTextureUnit(0, cascades_tex);
        glUniformMatrix4fv(glGetUniformLocation(lookup_program, "u_cascade_vp"), kCount, GL_FALSE, glm::value_ptr(lookup_vp[0]));
        glUniform4f(glGetUniformLocation(lookup_program, "u_split_near"), fit.splits[0], fit.splits[1], fit.splits[2], fit.splits[3]);
        glUniform4f(glGetUniformLocation(lookup_program, "u_split_far"), fit.splits[1], fit.splits[2], fit.splits[3], fit.splits[4]);
        glUniform1f(glGetUniformLocation(lookup_program, "u_radius_texels"), kPoissonTexels);
        const std::vector<float> lit = docs::shade_points(lookup_program, points);
        const docs::GroundScore score = docs::score_ground_points(points, lit, boxes, to_sun, [&](std::size_t k) {
            const int c = sk::cascade_select_by_depth(points[k].w, fit.splits, kCount).index;
            if (c < 0) return -1.0;
            const int next = c + 1 < kCount ? c + 1 : c;  // the band reads the next cascade too
            return (kPoissonTexels + 3.0) * double(cascades[next].texel_world_size);
        });
        for (float v : lit) shadowed_points += v < 0.5f ? 1 : 0;  // the score is not all lit ground
        worst_ratio = std::min(worst_ratio, score.ratio());
        worst_counted = std::min(worst_counted, score.counted);
        sum_agree += score.agree;
        sum_counted += score.counted;
    }
    MESSAGE("cached cascades + Poisson PCF + automatic bias, " << kFrames << " frames of a pan with a driving cart: "
            << 100.0 * sum_agree / sum_counted << "% of " << sum_counted << " ground points away from edges agree with the ray "
            << "cast (worst frame " << 100.0 * worst_ratio << "%); " << scrolls << " cascade scrolls, " << renders_after_first
            << " whole renders after the first frame; " << shadowed_points << " points in shadow");
    CHECK(worst_counted > 1000);
    CHECK(shadowed_points > int(sum_counted / 50.0));  // shadows to get wrong: > 2% of the points
    CHECK(worst_ratio >= 0.995);
    CHECK(renders_after_first == 0);
    CHECK(scrolls > 0);
    CHECK(glGetError() == GL_NO_ERROR);
}
