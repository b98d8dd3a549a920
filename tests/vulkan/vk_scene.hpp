// The scene and CPU reference of tests/gl/test_gl_shadow_map_e2e.cpp, for the Vulkan tests: a box
// over a ground plane lit by a point light, every receiver pixel classified lit or shadowed by a ray
// cast (segment-box slab test) from its G-buffer position to the light, pixels within one pixel of
// a reference shadow edge, grazing or outside the light's frustum left out. Also the shader pieces
// every test drawing this scene shares: the receiver pass's stages (GLSL and HLSL), the G-buffer
// fragment stage, the position-only depth pass, and the reversed-Z matrix.
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

namespace skvk {

struct SceneVertex {
    glm::vec3 position;
    glm::vec3 normal;
};

struct BoxScene {
    glm::vec3 box_c{0.f, 0.8f, 0.f}, box_h{0.6f, 0.3f, 0.45f};
    float ground_half = 3.f;
    glm::vec3 light{1.f, 4.f, 0.5f};
    std::vector<SceneVertex> vertices;  ///< triangle list, counter-clockwise seen from outside

    BoxScene() {
        auto quad = [&](glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d) {  // counter-clockwise
            const glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
            for (const glm::vec3& p : {a, b, c, a, c, d}) vertices.push_back({p, n});
        };
        const float g = ground_half;
        quad({-g, 0.f, g}, {g, 0.f, g}, {g, 0.f, -g}, {-g, 0.f, -g});
        const glm::vec3 lo = box_c - box_h, hi = box_c + box_h;
        quad({lo.x, hi.y, hi.z}, {hi.x, hi.y, hi.z}, {hi.x, hi.y, lo.z}, {lo.x, hi.y, lo.z});  // +y
        quad({lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, lo.y, hi.z}, {lo.x, lo.y, hi.z});  // -y
        quad({lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z});  // +z
        quad({hi.x, lo.y, lo.z}, {lo.x, lo.y, lo.z}, {lo.x, hi.y, lo.z}, {hi.x, hi.y, lo.z});  // -z
        quad({hi.x, lo.y, hi.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {hi.x, hi.y, hi.z});  // +x
        quad({lo.x, lo.y, lo.z}, {lo.x, lo.y, hi.z}, {lo.x, hi.y, hi.z}, {lo.x, hi.y, lo.z});  // -x
    }
};

/// Does the segment from p to the light hit the box (slab test)?
inline bool segment_hits_box(glm::vec3 p, glm::vec3 light, glm::vec3 lo, glm::vec3 hi) {
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

struct Agreement {
    int compared = 0, agree = 0, lit = 0, shadowed = 0;
    int acne = 0;  ///< lit by the ray cast, dark in `vis`
    double fraction() const { return compared ? double(agree) / double(compared) : 0.0; }
};

/// Per-pixel agreement of `vis` (> 0.5: lit) with the ray cast at the G-buffer's points. `world`,
/// `normal`: 4 floats per pixel (w = 1 where geometry was drawn); `light`: shadowkit's homogeneous
/// light (w = 1: the point light at xyz; w = 0: a directional light toward xyz); `frustum`: the map's
/// matrix for a spot light's cone (pixels outside 98% of it are left out), or nullptr.
inline Agreement compare_with_ray_cast(const BoxScene& s, glm::vec4 light, const glm::mat4* frustum, int w, int h,
                                       const std::vector<float>& vis, const std::vector<float>& world,
                                       const std::vector<float>& normal) {
    std::vector<int> ref(static_cast<std::size_t>(w * h), -1);
    for (int i = 0; i < w * h; ++i) {
        const auto k = static_cast<std::size_t>(i);
        if (world[k * 4 + 3] == 0.f) continue;
        const glm::vec3 p(world[k * 4], world[k * 4 + 1], world[k * 4 + 2]);
        const glm::vec3 n(normal[k * 4], normal[k * 4 + 1], normal[k * 4 + 2]);
        const glm::vec3 to_light = light.w > 0.f ? glm::vec3(light) / light.w - p : glm::vec3(light);
        if (glm::dot(n, glm::normalize(to_light)) <= 0.05f) continue;  // facing away or grazing
        if (frustum) {
            const glm::vec4 lc = *frustum * glm::vec4(p, 1.f);
            if (lc.w <= 0.f || std::abs(lc.x) > 0.98f * lc.w || std::abs(lc.y) > 0.98f * lc.w) continue;
        }
        const glm::vec3 q = p + 1e-3f * n;
        const glm::vec3 end = light.w > 0.f ? glm::vec3(light) / light.w : q + 100.f * glm::normalize(to_light);
        ref[k] = segment_hits_box(q, end, s.box_c - s.box_h, s.box_c + s.box_h) ? 0 : 1;
    }
    Agreement a;
    for (int y = 1; y < h - 1; ++y)
        for (int x = 1; x < w - 1; ++x) {
            const auto k = static_cast<std::size_t>(y * w + x);
            if (ref[k] < 0) continue;
            bool edge = false;
            for (int dy = -1; dy <= 1 && !edge; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int r = ref[static_cast<std::size_t>((y + dy) * w + x + dx)];
                    if (r >= 0 && r != ref[k]) edge = true;
                }
            if (edge) continue;
            ++a.compared;
            (ref[k] ? a.lit : a.shadowed)++;
            if ((vis[k] > 0.5f ? 1 : 0) == ref[k]) ++a.agree;
            if (ref[k] == 1 && !(vis[k] > 0.5f)) ++a.acne;
        }
    return a;
}

// ------------------------------------------------------------------ the receiver pass's shader pieces
// The receiver pass draws the scene (SceneVertex) seen by the camera and writes the visibility, the
// world point and the normal (the three targets compare_with_ray_cast reads). The including test's
// source declares its uniform block `u` (with `view_proj`) before these pieces and writes its lookup.

/// GLSL fragment stage inputs and the three targets (o_visibility, o_world, o_normal).
inline constexpr const char* kReceiverGlslFsIo = R"(
layout(location = 0) in vec3 v_world;
layout(location = 1) in vec3 v_normal;
layout(location = 0) out float o_visibility;
layout(location = 1) out vec4 o_world;
layout(location = 2) out vec4 o_normal;
)";
/// The GLSL vertex stage: `#version 450 core`, the test's Params block (or push constants), then the
/// world point and normal to locations 0 and 1 and the clip position from `view_proj` (a matrix of
/// that block).
inline std::string receiver_glsl_vs(const char* params_block, const char* view_proj = "u.view_proj") {
    return std::string("#version 450 core\n") + params_block + R"(
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 0) out vec3 v_world;
layout(location = 1) out vec3 v_normal;
void main() {
    v_world = a_position;
    v_normal = a_normal;
    gl_Position = )" + view_proj + R"( * vec4(a_position, 1.0);
}
)";
}
/// The G-buffer's GLSL fragment stage after receiver_glsl_vs: world point and normal (no visibility).
inline constexpr const char* kGbufferGlslFs = R"(#version 450 core
layout(location = 0) in vec3 v_world;
layout(location = 1) in vec3 v_normal;
layout(location = 0) out vec4 o_world;
layout(location = 1) out vec4 o_normal;
void main() {
    o_world = vec4(v_world, 1.0);
    o_normal = vec4(normalize(v_normal), 0.0);
}
)";
/// HLSL: the varyings (world point, normal) and the vertex stage `vs_main` (clip position from u.view_proj).
inline constexpr const char* kReceiverHlslVs = R"(
struct Varyings {
    float4 position : SV_Position;
    [[vk::location(0)]] float3 world : TEXCOORD0;
    [[vk::location(1)]] float3 normal : TEXCOORD1;
};
Varyings vs_main([[vk::location(0)]] float3 position : POSITION, [[vk::location(1)]] float3 normal : NORMAL) {
    Varyings o;
    o.world = position;
    o.normal = normal;
    o.position = mul(u.view_proj, float4(position, 1.0));
    return o;
}
)";
/// HLSL: the three targets (visibility, world point, normal) of the fragment stage.
inline constexpr const char* kReceiverHlslTargets = R"(
struct Targets {
    [[vk::location(0)]] float visibility : SV_Target0;
    [[vk::location(1)]] float4 world : SV_Target1;
    [[vk::location(2)]] float4 normal : SV_Target2;
};
)";

/// The map pass of the scene (SceneVertex, position only): one matrix in push constants (the vertex
/// stage's), GLSL and HLSL (entry `main`); depth only.
inline constexpr const char* kSceneDepthGlsl = R"(#version 450 core
layout(push_constant) uniform DepthParams { mat4 light_view_proj; } pc;
layout(location = 0) in vec3 a_position;
void main() { gl_Position = pc.light_view_proj * vec4(a_position, 1.0); }
)";
inline constexpr const char* kSceneDepthHlsl = R"(
struct DepthParams { column_major float4x4 light_view_proj; };
[[vk::push_constant]] ConstantBuffer<DepthParams> pc;
float4 main([[vk::location(0)]] float3 position : POSITION) : SV_Position {
    return mul(pc.light_view_proj, float4(position, 1.0));
}
)";

/// Vulkan's reversed-Z on a [0, 1] projection: z -> w - z (1 at the near plane).
inline glm::mat4 reverse_z() {
    glm::mat4 r(1.f);
    r[2][2] = -1.f;
    r[3][2] = 1.f;
    return r;
}

}  // namespace skvk
