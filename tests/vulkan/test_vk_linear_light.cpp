// glsl/linear_light.glsl and hlsl/linear_light.hlsl RUN on Vulkan: the lookup sk_linear_light_visibility
// (both endpoints' depth-map tests and visibility-map reads) on synthetic 32 x 32 maps for a segment
// light, 2,048 random receivers, against a CPU evaluation of the two endpoint terms written from the
// snippet's comment, combined by shadowkit::linear_light_shade (clamped to 1 as the snippet does): at most 0.5% may differ by more than
// 1e-5 (a receiver on a texel boundary or a depth tie within float rounding). The matrices are the GL
// ([-1, 1]) ones the snippet takes. No validation message.
// The passes RUN end to end as in tests/gl/test_gl_linear_light.cpp's first case: the `linear` scene,
// k = 1, 2, 4 sub-lights, 512^2 endpoint depth maps, both skins per sub-light built on the GPU
// (sk_linear_light_skin_vertex / sk_linear_light_skin_output, MIN-blended) or, as the GL test's
// default skin=cpu, by linear_light_build_skin from the read-back maps, the lookup at 240 x 180
// pixels against the closed form linear_light_visible_fraction: the GL test's bounds (RMSE < 0.06 at
// k = 1, falling with k). Drawing no skin gives RMSE 0.076 at k = 1 (measured: the bound catches it).
#include <doctest/doctest.h>

#include <shadowkit/linear_light.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include <glm/glm.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "vk_harness.hpp"
#include "vk_passes.hpp"
#include "vk_scene.hpp"

namespace {

using skvk::Source;

const char* kGlsl = R"(
layout(set = 0, binding = 0) uniform sampler2D u_depth_a;
layout(set = 0, binding = 1) uniform sampler2D u_vis_a;
layout(set = 0, binding = 2) uniform sampler2D u_depth_b;
layout(set = 0, binding = 3) uniform sampler2D u_vis_b;
layout(set = 0, binding = 4, std430) readonly buffer Lookups { vec4 lookup[]; };  // (p, -), (n, -)
layout(set = 0, binding = 5, std140) uniform Params { mat4 vp_a; mat4 vp_b; vec4 end_a; vec4 end_b; } u;
layout(location = 0) out float o_value;
void main() {
    int i = int(gl_FragCoord.x);
    o_value = sk_linear_light_visibility(u_depth_a, u_vis_a, u.vp_a, u.end_a.xyz, u_depth_b, u_vis_b, u.vp_b, u.end_b.xyz,
                                         lookup[2 * i].xyz, lookup[2 * i + 1].xyz, 0.0);
}
)";
const char* kHlsl = R"(
[[vk::binding(0, 0)]] Texture2D<float> u_depth_a;
[[vk::binding(1, 0)]] Texture2D<float4> u_vis_a;
[[vk::binding(2, 0)]] Texture2D<float> u_depth_b;
[[vk::binding(3, 0)]] Texture2D<float4> u_vis_b;
[[vk::binding(4, 0)]] StructuredBuffer<float4> lookup;
struct Params { column_major float4x4 vp_a; column_major float4x4 vp_b; float4 end_a; float4 end_b; };
[[vk::binding(5, 0)]] ConstantBuffer<Params> u;
float ps_main(float4 position : SV_Position) : SV_Target0 {
    int i = int(position.x);
    return sk_linear_light_visibility(u_depth_a, u_vis_a, u.vp_a, u.end_a.xyz, u_depth_b, u_vis_b, u.vp_b, u.end_b.xyz,
                                      lookup[2 * i].xyz, lookup[2 * i + 1].xyz, 0.0);
}
)";

constexpr int kSize = 32;

struct Params {
    glm::mat4 vp_a, vp_b;
    glm::vec4 end_a, end_b;
};

// One endpoint's term as glsl/linear_light.glsl's comment defines it: 0 facing away or behind the
// depth sample, 0.5 outside the frustum or where no skin covers, else the skin value; lit = the
// depth test passed and the point faces the endpoint.
float cpu_endpoint(const std::vector<float>& depth, const std::vector<float>& vis, const glm::mat4& vp, glm::vec3 end, glm::vec3 p,
                   glm::vec3 n, bool& lit) {
    lit = false;
    if (glm::dot(n, end - p) <= 0.f) return 0.f;
    const glm::vec4 c = vp * glm::vec4(p, 1.f);
    lit = true;
    if (c.w <= 0.f) return 0.5f;
    const glm::vec3 w = glm::vec3(c) / c.w * 0.5f + 0.5f;
    if (w.x < 0.f || w.y < 0.f || w.x > 1.f || w.y > 1.f) return 0.5f;
    const int i = std::clamp(int(w.x * float(kSize)), 0, kSize - 1), j = std::clamp(int(w.y * float(kSize)), 0, kSize - 1);
    const std::size_t t = std::size_t(j * kSize + i);
    if (w.z > depth[t]) {
        lit = false;
        return 0.f;
    }
    return (vis[4 * t + 1] < 0.5f && w.z >= vis[4 * t + 2] - 1e-6f) ? vis[4 * t] : 0.5f;
}

void run_linear(Source lang) {
    skvk::Context& ctx = skvk::vk_test_context();
    skvk::Scope scope(ctx);
    const std::size_t before = skvk::message_count();
    std::vector<std::uint32_t> vs, fs;
    const char* entries[2] = {"main", "main"};
    if (lang == Source::Glsl) {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_GLSL_DIR) + "/linear_light.glsl");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, skvk::kFullscreenGlsl, "main", "linear_light.glsl.vert");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, "#version 450 core\n" + snippet + kGlsl, "main",
                                   "linear_light.glsl.frag");
    } else {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_HLSL_DIR) + "/linear_light.hlsl");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, snippet + skvk::kFullscreenHlsl + kHlsl, "vs_main", "linear_light.hlsl.vert");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, snippet + skvk::kFullscreenHlsl + kHlsl, "ps_main", "linear_light.hlsl.frag");
        entries[0] = "vs_main";
        entries[1] = "ps_main";
    }
    std::mt19937 rng(2000);
    std::uniform_real_distribution<float> U01(0.f, 1.f), U(-1.f, 1.f);
    const glm::vec3 end_a(-0.5f, 4.f, 0.f), end_b(0.5f, 4.f, 0.f);
    const glm::mat4 proj = glm::perspectiveRH_NO(1.4f, 1.f, 0.1f, 20.f);  // GL clip depth, as the snippet takes
    const Params params{proj * glm::lookAt(end_a, end_a + glm::vec3(0.f, -1.f, 0.f), glm::vec3(0.f, 0.f, -1.f)),
                        proj * glm::lookAt(end_b, end_b + glm::vec3(0.f, -1.f, 0.f), glm::vec3(0.f, 0.f, -1.f)),
                        glm::vec4(end_a, 1.f), glm::vec4(end_b, 1.f)};
    std::vector<float> depth[2], vis[2];
    auto& dmap = scope.own<std::array<skvk::Image, 2>>();
    auto& vmap = scope.own<std::array<skvk::Image, 2>>();
    const VkImageUsageFlags up = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    const VkImageLayout read = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    for (int e = 0; e < 2; ++e) {
        depth[e].resize(kSize * kSize);
        vis[e].resize(4 * kSize * kSize);
        for (std::size_t t = 0; t < depth[e].size(); ++t) {
            depth[e][t] = 0.955f + 0.04f * U01(rng);  // window depths around the receivers' (~0.96-0.99)
            vis[e][4 * t] = U01(rng);
            vis[e][4 * t + 1] = U01(rng) < 0.5f ? 0.f : 1.f;
            vis[e][4 * t + 2] = 0.95f + 0.05f * U01(rng);
        }
        REQUIRE(skvk::make_image(ctx, kSize, kSize, 1, VK_FORMAT_R32_SFLOAT, up, dmap[e]));
        REQUIRE(skvk::make_image(ctx, kSize, kSize, 1, VK_FORMAT_R32G32B32A32_SFLOAT, up, vmap[e]));
        REQUIRE(skvk::upload_image(ctx, dmap[e], depth[e], read));
        REQUIRE(skvk::upload_image(ctx, vmap[e], vis[e], read));
    }
    constexpr std::uint32_t M = 2048;
    std::vector<glm::vec4> pts(2 * M);
    for (std::uint32_t i = 0; i < M; ++i) {
        pts[2 * i] = glm::vec4(1.5f * U(rng), U01(rng), 1.5f * U(rng), 0.f);
        pts[2 * i + 1] = glm::vec4(glm::normalize(glm::vec3(0.3f * U(rng), i % 7 == 0 ? -1.f : 1.f, 0.3f * U(rng))), 0.f);
    }
    skvk::Buffer& ssbo = scope.own<skvk::Buffer>();
    skvk::Buffer& ubo = scope.own<skvk::Buffer>();
    REQUIRE(skvk::make_buffer(ctx, pts.size() * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, ssbo));
    std::memcpy(ssbo.mapped, pts.data(), pts.size() * sizeof(glm::vec4));
    REQUIRE(skvk::make_buffer(ctx, sizeof(Params), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, ubo));
    std::memcpy(ubo.mapped, &params, sizeof params);
    VkSampler nearest = scope.keep(skvk::make_sampler(ctx, VK_FILTER_NEAREST, VK_COMPARE_OP_NEVER), vkDestroySampler);
    skvk::DescriptorSet& ds = scope.own<skvk::DescriptorSet>();
    const VkShaderStageFlags frag = VK_SHADER_STAGE_FRAGMENT_BIT;
    const VkDescriptorType tex = skvk::texture_type(lang);
    REQUIRE(skvk::make_descriptor_set(ctx, {{0, tex, frag}, {1, tex, frag}, {2, tex, frag}, {3, tex, frag},
                                            {4, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, frag}, {5, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, frag}},
                                      ds));
    const VkSampler s = lang == Source::Glsl ? nearest : VK_NULL_HANDLE;
    skvk::write_image(ctx, ds, 0, tex, dmap[0].view, s, read);
    skvk::write_image(ctx, ds, 1, tex, vmap[0].view, s, read);
    skvk::write_image(ctx, ds, 2, tex, dmap[1].view, s, read);
    skvk::write_image(ctx, ds, 3, tex, vmap[1].view, s, read);
    skvk::write_buffer(ctx, ds, 4, ssbo, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
    skvk::write_buffer(ctx, ds, 5, ubo);
    skvk::RowPass& row = scope.own<skvk::RowPass>();
    skvk::make_row_pass(ctx, vs, fs, entries[0], entries[1], ds, M, row);
    const std::vector<float> gpu = skvk::draw_row(ctx, row, ds);

    std::size_t off = 0, bad = 0, skin = 0, umbra = 0;
    double max_err = 0;
    for (std::uint32_t i = 0; i < M; ++i) {
        if (!(gpu[i] >= 0.f && gpu[i] <= 1.f)) ++bad;
        const glm::vec3 p(pts[2 * i]), n(pts[2 * i + 1]);
        bool lit_a = false, lit_b = false;
        const float va = cpu_endpoint(depth[0], vis[0], params.vp_a, end_a, p, n, lit_a);
        const float vb = cpu_endpoint(depth[1], vis[1], params.vp_b, end_b, p, n, lit_b);
        const float cpu = std::min(shadowkit::linear_light_shade(lit_a, va, lit_b, vb), 1.f);  // the snippet clamps the sum
        skin += (lit_a && va != 0.5f) || (lit_b && vb != 0.5f);
        umbra += !lit_a && !lit_b;
        const double e = std::abs(double(gpu[i]) - double(cpu));
        max_err = std::max(max_err, e);
        off += e > 1e-5;
    }
    MESSAGE((lang == Source::Glsl ? "GLSL" : "HLSL") << ": " << skin << " lookups read a skin value, " << umbra << " in the umbra; "
                                                    << off << " of " << M << " differ from the CPU by > 1e-5 (max " << max_err << ")");
    CHECK(bad == 0);
    CHECK(skin > M / 8);
    CHECK(umbra > M / 20);
    CHECK(off <= M / 200);
    CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());

}


// ------------------------------------------------------------------ the passes end to end
// tests/gl/test_gl_linear_light.cpp's first case on Vulkan: the `linear` scene (a box and a post on a
// floor under a 1.6-unit line light), split into k = 1, 2, 4 sub-lights (linear_light_subdivide); per
// end a 512 x 512 depth map of every mesh (depth bias 2 / slope 2, the sample's polygon offset); per
// sub-light both skins on the GPU (sk_linear_light_skin_vertex over 6 (N - 1)^2 attribute-less
// vertices, sk_linear_light_skin_output, MIN-blended into RGBA32F visibility maps cleared to 1); then
// V = mean over sub-lights of sk_linear_light_visibility at every pixel of a 240 x 180 camera, against
// the closed form linear_light_visible_fraction (the GL test's bounds: RMSE < 0.06 at k = 1, and
// falling with k). As hlsl/linear_light.hlsl says: the endpoint maps (and the skin's `view_proj`, whose
// window depth the skin stores) use perspectiveRH_ZO, the lookup and the skin's unprojection the GL
// ([-1, 1]) matrix of the same planes. One unflipped viewport everywhere (uv rows = map rows).
const char* kSkinGlsl = R"(
layout(set = 0, binding = 0, std140) uniform Skin { mat4 other_inv_vp; mat4 this_vp; vec4 p; } s;  // p: near, far, threshold
layout(set = 0, binding = 1) uniform sampler2D u_other_depth;
)";
const char* kSkinVsGlsl = R"(
layout(location = 0) noperspective out float v_value;
void main() {
    gl_Position = sk_linear_light_skin_vertex(u_other_depth, s.other_inv_vp, s.p.x, s.p.y, s.this_vp, s.p.z, gl_VertexIndex,
                                              v_value);
}
)";
// skin=cpu (the sample's default): the skin linear_light_build_skin made from the read-back map
const char* kSkinCpuVsGlsl = R"(
layout(location = 0) in vec3 a_position;
layout(location = 1) in float a_value;
layout(location = 0) noperspective out float v_value;
void main() {
    v_value = a_value;
    gl_Position = s.this_vp * vec4(a_position, 1.0);
}
)";
const char* kSkinFsGlsl = R"(
layout(location = 0) noperspective in float v_value;
layout(location = 0) out vec4 o_vis;
void main() { o_vis = sk_linear_light_skin_output(v_value, gl_FragCoord.z); }
)";
const char* kPassesHlsl = R"(
struct DepthParams { column_major float4x4 light_view_proj; };
[[vk::push_constant]] ConstantBuffer<DepthParams> pc;
float4 depth_vs([[vk::location(0)]] float3 position : POSITION) : SV_Position {
    return mul(pc.light_view_proj, float4(position, 1.0));
}
struct Skin { column_major float4x4 other_inv_vp; column_major float4x4 this_vp; float4 p; };
[[vk::binding(0, 0)]] ConstantBuffer<Skin> s;
[[vk::binding(1, 0)]] Texture2D<float> u_other_depth;
struct SkinV {
    float4 position : SV_Position;
    [[vk::location(0)]] noperspective float value : TEXCOORD0;
};
SkinV skin_vs(uint id : SV_VertexID) {
    SkinV o;
    o.position = sk_linear_light_skin_vertex(u_other_depth, s.other_inv_vp, s.p.x, s.p.y, s.this_vp, s.p.z, int(id), o.value);
    return o;
}
SkinV skin_cpu_vs([[vk::location(0)]] float3 position : POSITION, [[vk::location(1)]] float value : VALUE) {
    SkinV o;
    o.value = value;
    o.position = mul(s.this_vp, float4(position, 1.0));
    return o;
}
float4 skin_ps(SkinV i) : SV_Target0 { return sk_linear_light_skin_output(i.value, i.position.z); }
)";

// The lookup for k sub-lights: depth maps at bindings 1 .. k + 1, visibility maps at 6 .. 5 + 2k (two
// per sub-light: end i's, end i + 1's), constant indices as the sample's lookup.
std::string lookup_source(Source lang, int k) {
    std::string src;
    const bool glsl = lang == Source::Glsl;
    if (glsl) {
        src = "layout(set = 0, binding = 0, std140) uniform Params { mat4 cam_vp; mat4 vp[5]; vec4 end_pos[5]; vec4 p; } u;\n";
        for (int i = 0; i <= k; ++i)
            src += "layout(set = 0, binding = " + std::to_string(1 + i) + ") uniform sampler2D u_depth" + std::to_string(i) + ";\n";
        for (int j = 0; j < 2 * k; ++j)
            src += "layout(set = 0, binding = " + std::to_string(6 + j) + ") uniform sampler2D u_vis" + std::to_string(j) + ";\n";
        src += R"(
layout(location = 0) in vec3 v_world;
layout(location = 1) in vec3 v_normal;
layout(location = 0) out float o_v;
layout(location = 1) out vec4 o_world;
layout(location = 2) out vec4 o_normal;
void main() {
    vec3 p = v_world, n = normalize(v_normal);
    float v = 0.0;
)";
    } else {
        src = "struct Params { column_major float4x4 cam_vp; column_major float4x4 vp[5]; float4 end_pos[5]; float4 p; };\n"
              "[[vk::binding(0, 0)]] ConstantBuffer<Params> u;\n";
        for (int i = 0; i <= k; ++i)
            src += "[[vk::binding(" + std::to_string(1 + i) + ", 0)]] Texture2D<float> u_depth" + std::to_string(i) + ";\n";
        for (int j = 0; j < 2 * k; ++j)
            src += "[[vk::binding(" + std::to_string(6 + j) + ", 0)]] Texture2D<float4> u_vis" + std::to_string(j) + ";\n";
        src += R"(
struct WorldV {
    float4 position : SV_Position;
    [[vk::location(0)]] float3 world : TEXCOORD0;
    [[vk::location(1)]] float3 normal : TEXCOORD1;
};
WorldV lookup_vs([[vk::location(0)]] float3 p : POSITION, [[vk::location(1)]] float3 n : NORMAL) {
    WorldV o;
    o.world = p;
    o.normal = n;
    o.position = mul(u.cam_vp, float4(p, 1.0));
    return o;
}
struct Targets {
    [[vk::location(0)]] float v : SV_Target0;
    [[vk::location(1)]] float4 world : SV_Target1;
    [[vk::location(2)]] float4 normal : SV_Target2;
};
Targets lookup_ps(WorldV i) {
    float3 p = i.world, n = normalize(i.normal);
    float v = 0.0;
)";
    }
    for (int i = 0; i < k; ++i) {
        const std::string a = std::to_string(i), b = std::to_string(i + 1);
        src += "    v += sk_linear_light_visibility(u_depth" + a + ", u_vis" + std::to_string(2 * i) + ", u.vp[" + a + "], u.end_pos[" + a +
               "].xyz, u_depth" + b + ", u_vis" + std::to_string(2 * i + 1) + ", u.vp[" + b + "], u.end_pos[" + b +
               "].xyz, p, n, 0.0);\n";
    }
    if (glsl) return src + "    o_v = v / u.p.x;\n    o_world = vec4(p, 1.0);\n    o_normal = vec4(n, 0.0);\n}\n";
    return src + "    Targets o;\n    o.v = v / u.p.x;\n    o.world = float4(p, 1.0);\n    o.normal = float4(n, 0.0);\n    return o;\n}\n";
}
const char* kLookupParamsGlsl = R"(
layout(set = 0, binding = 0, std140) uniform Params { mat4 cam_vp; mat4 vp[5]; vec4 end_pos[5]; vec4 p; } u;
)";

// The `linear` scene of samples/app (make_builtin_scene): floor (half size 4, no caster), a box and a post.
struct LinearScene {
    std::vector<skvk::SceneVertex> vertices;
    std::vector<shadowkit::LinearLightBox> casters;
    glm::vec3 lo{INFINITY}, hi{-INFINITY};
    shadowkit::LinearLightSegment seg;
    glm::mat4 cam_vp{1.f};
    LinearScene() {
        auto quad = [&](glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d) {  // counter-clockwise
            const glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
            for (const glm::vec3& q : {a, b, c, a, c, d}) {
                vertices.push_back({q, n});
                lo = glm::min(lo, q);
                hi = glm::max(hi, q);
            }
        };
        quad({-4.f, 0.f, 4.f}, {4.f, 0.f, 4.f}, {4.f, 0.f, -4.f}, {-4.f, 0.f, -4.f});
        for (const auto& [c, h] : {std::pair<glm::vec3, glm::vec3>{{-0.7f, 0.4f, 0.1f}, {0.4f, 0.4f, 0.4f}},
                                   std::pair<glm::vec3, glm::vec3>{{0.8f, 0.7f, -0.2f}, {0.06f, 0.7f, 0.06f}}}) {
            const glm::vec3 l = c - h, u = c + h;
            quad({l.x, u.y, u.z}, {u.x, u.y, u.z}, {u.x, u.y, l.z}, {l.x, u.y, l.z});  // +y
            quad({l.x, l.y, l.z}, {u.x, l.y, l.z}, {u.x, l.y, u.z}, {l.x, l.y, u.z});  // -y
            quad({l.x, l.y, u.z}, {u.x, l.y, u.z}, {u.x, u.y, u.z}, {l.x, u.y, u.z});  // +z
            quad({u.x, l.y, l.z}, {l.x, l.y, l.z}, {l.x, u.y, l.z}, {u.x, u.y, l.z});  // -z
            quad({u.x, l.y, u.z}, {u.x, l.y, l.z}, {u.x, u.y, l.z}, {u.x, u.y, u.z});  // +x
            quad({l.x, l.y, l.z}, {l.x, l.y, u.z}, {l.x, u.y, u.z}, {l.x, u.y, l.z});  // -x
            casters.push_back({l, u});
        }
        seg = shadowkit::linear_light_segment({0.1f, 2.6f, 0.3f}, glm::normalize(glm::vec3(1.f, 0.f, 0.35f)), 1.6f);
        cam_vp = glm::perspectiveRH_ZO(0.9f, 240.f / 180.f, 0.05f, 100.f) *
                 glm::lookAt(glm::vec3(0.3f, 3.4f, 4.4f), glm::vec3(0.f, 0.2f, -0.2f), glm::vec3(0.f, 1.f, 0.f));
    }
};

// An end's frustum as the sample's: toward the scene's centre, near / far around its bounds
// (samples/app fit_box_depth), the cone holding the whole box (x 1.02, at most 1.45 rad).
struct EndView {
    glm::vec3 pos{0.f};
    glm::mat4 vp_gl{1.f}, vp_zo{1.f}, inv_gl{1.f};
    float znear = 0.f, zfar = 0.f;
};
EndView end_view(const LinearScene& sc, glm::vec3 pos) {
    EndView e;
    e.pos = pos;
    const glm::vec3 center = 0.5f * (sc.lo + sc.hi), dir = glm::normalize(center - pos);
    const glm::vec3 up = std::abs(dir.y) > 0.9f ? glm::vec3(0.f, 0.f, 1.f) : glm::vec3(0.f, 1.f, 0.f);
    const glm::mat4 view = glm::lookAt(pos, pos + dir, up);
    float zmin = INFINITY, zmax = 0.f, tan_max = 0.f;
    for (int i = 0; i < 8; ++i) {
        const glm::vec3 c((i & 1) ? sc.hi.x : sc.lo.x, (i & 2) ? sc.hi.y : sc.lo.y, (i & 4) ? sc.hi.z : sc.lo.z);
        const glm::vec3 v = glm::vec3(view * glm::vec4(c, 1.f));
        zmax = std::max(zmax, -v.z);
        zmin = std::min(zmin, -v.z);
        if (-v.z > 1e-6f) tan_max = std::max(tan_max, std::max(std::abs(v.x), std::abs(v.y)) / -v.z);
    }
    e.zfar = zmax * 1.01f;
    e.znear = std::max(zmin * 0.9f, e.zfar * 2e-3f);
    const float half = std::min(std::atan(tan_max) * 1.02f, 1.45f);
    e.vp_gl = glm::perspectiveRH_NO(2.f * half, 1.f, e.znear, e.zfar) * view;
    e.vp_zo = glm::perspectiveRH_ZO(2.f * half, 1.f, e.znear, e.zfar) * view;
    e.inv_gl = glm::inverse(e.vp_gl);
    return e;
}

struct LinearPasses {
    skvk::Context& ctx;
    Source lang;
    skvk::Scope scope;  ///< everything below; declared first, so destroyed last
    skvk::Buffer& vb = scope.own<skvk::Buffer>();
    VkSampler nearest = VK_NULL_HANDLE;
    skvk::DescriptorSet& skin_layout_ds = scope.own<skvk::DescriptorSet>();  // only its layout is used: the skin draws' sets are made per draw
    VkPipelineLayout depth_layout = VK_NULL_HANDLE, skin_layout = VK_NULL_HANDLE;
    VkRenderPass depth_rp = VK_NULL_HANDLE, skin_rp = VK_NULL_HANDLE, lookup_rp = VK_NULL_HANDLE;
    VkPipeline depth = VK_NULL_HANDLE, skin = VK_NULL_HANDLE, skin_cpu = VK_NULL_HANDLE;
    std::string snippet;

    LinearPasses(skvk::Context& c, Source l, const LinearScene& sc) : ctx(c), lang(l), scope(c) {
        const bool glsl = lang == Source::Glsl;
        snippet = glsl ? skvk::read_text(std::string(SHADOWKIT_GLSL_DIR) + "/linear_light.glsl")
                       : skvk::read_text(std::string(SHADOWKIT_HLSL_DIR) + "/linear_light.hlsl");
        const std::size_t bytes = sc.vertices.size() * sizeof(skvk::SceneVertex);
        REQUIRE(skvk::make_buffer(ctx, bytes, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, vb));
        std::memcpy(vb.mapped, sc.vertices.data(), bytes);
        nearest = scope.keep(skvk::make_sampler(ctx, VK_FILTER_NEAREST, VK_COMPARE_OP_NEVER), vkDestroySampler);
        const VkDescriptorType tex = skvk::texture_type(lang);
        REQUIRE(skvk::make_descriptor_set(ctx, {{0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, VK_SHADER_STAGE_VERTEX_BIT},
                                                {1, tex, VK_SHADER_STAGE_VERTEX_BIT}}, skin_layout_ds));
        depth_layout = scope.keep(skvk::make_pipeline_layout(ctx, nullptr, sizeof(glm::mat4)), vkDestroyPipelineLayout);
        skin_layout = scope.keep(skvk::make_pipeline_layout(ctx, &skin_layout_ds), vkDestroyPipelineLayout);
        depth_rp = scope.keep(skvk::make_render_pass(ctx, {}, VK_FORMAT_D32_SFLOAT, VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL), vkDestroyRenderPass);
        skin_rp = scope.keep(skvk::make_render_pass(ctx, {VK_FORMAT_R32G32B32A32_SFLOAT}, VK_FORMAT_UNDEFINED, VK_IMAGE_LAYOUT_UNDEFINED), vkDestroyRenderPass);
        lookup_rp = scope.keep(skvk::make_render_pass(ctx, {VK_FORMAT_R32_SFLOAT, VK_FORMAT_R32G32B32A32_SFLOAT, VK_FORMAT_R32G32B32A32_SFLOAT},
                                           VK_FORMAT_D32_SFLOAT, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL), vkDestroyRenderPass);
        const VkShaderStageFlagBits V = VK_SHADER_STAGE_VERTEX_BIT, F = VK_SHADER_STAGE_FRAGMENT_BIT;
        skvk::PipelineDesc md, sd;
        std::vector<std::uint32_t> cpu_vs;
        if (glsl) {
            const std::string h = "#version 450 core\n" + snippet + kSkinGlsl;
            md.vs = skvk::compile_checked(lang, V, skvk::kSceneDepthGlsl, "main", "linear_light.glsl.depth.vert");
            sd.vs = skvk::compile_checked(lang, V, h + kSkinVsGlsl, "main", "linear_light.glsl.skin.vert");
            sd.fs = skvk::compile_checked(lang, F, h + kSkinFsGlsl, "main", "linear_light.glsl.skin.frag");
            cpu_vs = skvk::compile_checked(lang, V, h + kSkinCpuVsGlsl, "main", "linear_light.glsl.skin_cpu.vert");
        } else {
            const std::string h = snippet + kPassesHlsl;
            md.vs = skvk::compile_checked(lang, V, h, "depth_vs", "linear_light.hlsl.depth_vs");
            sd.vs = skvk::compile_checked(lang, V, h, "skin_vs", "linear_light.hlsl.skin_vs");
            sd.fs = skvk::compile_checked(lang, F, h, "skin_ps", "linear_light.hlsl.skin_ps");
            cpu_vs = skvk::compile_checked(lang, V, h, "skin_cpu_vs", "linear_light.hlsl.skin_cpu_vs");
            md.vs_entry = "depth_vs";
            sd.vs_entry = "skin_vs";
            sd.fs_entry = "skin_ps";
        }
        md.vertex_stride = sizeof(skvk::SceneVertex);
        md.attributes = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0}};
        md.depth_bias = true;  // the sample's glPolygonOffset(2, 2)
        md.bias_constant = md.bias_slope = 2.f;
        depth = scope.keep(skvk::make_pipeline_checked(ctx, md, depth_layout, depth_rp), vkDestroyPipeline);
        sd.depth_test = sd.depth_write = false;  // attribute-less, MIN blending, no culling
        sd.color_count = 1;
        sd.blend = true;
        sd.blend_op = VK_BLEND_OP_MIN;
        skin = scope.keep(skvk::make_pipeline_checked(ctx, sd, skin_layout, skin_rp), vkDestroyPipeline);
        sd.vs = cpu_vs;
        sd.vs_entry = glsl ? "main" : "skin_cpu_vs";
        sd.vertex_stride = sizeof(shadowkit::LinearLightSkinVertex);
        sd.attributes = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0}, {1, 0, VK_FORMAT_R32_SFLOAT, 12}};
        skin_cpu = scope.keep(skvk::make_pipeline_checked(ctx, sd, skin_layout, skin_rp), vkDestroyPipeline);
    }
};

constexpr std::uint32_t kMap = 512, kCamW = 240, kCamH = 180;

struct LinearFrame {
    std::vector<float> v, world, normal;
};

// The lookup pass for k sub-lights over the ends' depth maps and the visibility maps.
LinearFrame render_lookup(LinearPasses& P, const LinearScene& sc, const std::vector<EndView>& ends,
                          const std::vector<skvk::Image>& dmaps, const std::vector<skvk::Image>& vmaps) {
    skvk::Context& ctx = P.ctx;
    skvk::Scope scope(ctx);
    const int k = int(ends.size()) - 1;
    const bool glsl = P.lang == Source::Glsl;
    const VkShaderStageFlagBits V = VK_SHADER_STAGE_VERTEX_BIT, F = VK_SHADER_STAGE_FRAGMENT_BIT;
    skvk::PipelineDesc pd;
    const std::string tag = std::string(glsl ? "linear_light.glsl.lookup" : "linear_light.hlsl.lookup") + std::to_string(k);
    if (glsl) {
        pd.vs = skvk::compile_checked(P.lang, V, skvk::receiver_glsl_vs(kLookupParamsGlsl, "u.cam_vp"), "main", tag + ".vert");
        pd.fs = skvk::compile_checked(P.lang, F, "#version 450 core\n" + P.snippet + lookup_source(P.lang, k), "main", tag + ".frag");
    } else {
        const std::string h = P.snippet + lookup_source(P.lang, k);
        pd.vs = skvk::compile_checked(P.lang, V, h, "lookup_vs", tag + ".vs");
        pd.fs = skvk::compile_checked(P.lang, F, h, "lookup_ps", tag + ".ps");
        pd.vs_entry = "lookup_vs";
        pd.fs_entry = "lookup_ps";
    }
    const VkDescriptorType tex = skvk::texture_type(P.lang);
    std::vector<skvk::Binding> b = {{0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, V | F}};
    for (int i = 0; i <= k; ++i) b.push_back({std::uint32_t(1 + i), tex, F});
    for (int j = 0; j < 2 * k; ++j) b.push_back({std::uint32_t(6 + j), tex, F});
    skvk::DescriptorSet& ds = scope.own<skvk::DescriptorSet>();
    REQUIRE(skvk::make_descriptor_set(ctx, b, ds));
    struct LookupParams {
        glm::mat4 cam_vp, vp[5];
        glm::vec4 end_pos[5], p;
    } params{};
    params.cam_vp = sc.cam_vp;
    for (int i = 0; i <= k; ++i) {
        params.vp[i] = ends[std::size_t(i)].vp_gl;
        params.end_pos[i] = glm::vec4(ends[std::size_t(i)].pos, 1.f);
    }
    params.p = glm::vec4(float(k), 0.f, 0.f, 0.f);
    skvk::Buffer& ubo = scope.own<skvk::Buffer>();
    REQUIRE(skvk::make_buffer(ctx, sizeof params, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, ubo));
    std::memcpy(ubo.mapped, &params, sizeof params);
    skvk::write_buffer(ctx, ds, 0, ubo);
    const VkSampler smp = glsl ? P.nearest : VK_NULL_HANDLE;
    for (int i = 0; i <= k; ++i)
        skvk::write_image(ctx, ds, std::uint32_t(1 + i), tex, dmaps[std::size_t(i)].view, smp, VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL);
    for (int j = 0; j < 2 * k; ++j)
        skvk::write_image(ctx, ds, std::uint32_t(6 + j), tex, vmaps[std::size_t(j)].view, smp, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    VkPipelineLayout layout = scope.keep(skvk::make_pipeline_layout(ctx, &ds), vkDestroyPipelineLayout);
    pd.vertex_stride = sizeof(skvk::SceneVertex);
    pd.attributes = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0}, {1, 0, VK_FORMAT_R32G32B32_SFLOAT, 12}};
    pd.color_count = 3;
    VkPipeline pipe = scope.keep(skvk::make_pipeline_checked(ctx, pd, layout, P.lookup_rp), vkDestroyPipeline);
    skvk::Image& vis = scope.own<skvk::Image>();
    skvk::Image& world = scope.own<skvk::Image>();
    skvk::Image& normal = scope.own<skvk::Image>();
    skvk::Image& zbuf = scope.own<skvk::Image>();
    const VkImageUsageFlags rt = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    REQUIRE(skvk::make_image(ctx, kCamW, kCamH, 1, VK_FORMAT_R32_SFLOAT, rt, vis));
    REQUIRE(skvk::make_image(ctx, kCamW, kCamH, 1, VK_FORMAT_R32G32B32A32_SFLOAT, rt, world));
    REQUIRE(skvk::make_image(ctx, kCamW, kCamH, 1, VK_FORMAT_R32G32B32A32_SFLOAT, rt, normal));
    REQUIRE(skvk::make_image(ctx, kCamW, kCamH, 1, VK_FORMAT_D32_SFLOAT, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, zbuf));
    VkFramebuffer fb = scope.keep(skvk::make_framebuffer(ctx, P.lookup_rp, {vis.view, world.view, normal.view, zbuf.view}, kCamW, kCamH), vkDestroyFramebuffer);
    VkCommandBuffer cmd = skvk::begin_commands(ctx);
    VkClearValue zero{}, far{};
    far.depthStencil = {1.f, 0};
    skvk::draw_pass(cmd, P.lookup_rp, fb, kCamW, kCamH, {zero, zero, zero, far}, pipe, layout, &ds.set, nullptr, P.vb.buffer,
                    static_cast<std::uint32_t>(sc.vertices.size()), false);
    REQUIRE(skvk::submit_and_wait(ctx, cmd));
    LinearFrame f;
    f.v = skvk::read_image(ctx, vis, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 1);
    f.world = skvk::read_image(ctx, world, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 4);
    f.normal = skvk::read_image(ctx, normal, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 4);
    return f;
}

// Passes 1 and 2 for k sub-lights: a depth map per end, both skins per sub-light (visibility map
// 2 min(from, into) + (from < into), as the sample), then the lookup.
// skin=cpu: the map read back, every texel unprojected to its world position and linear distance
// (as the sample does), the cells whose distances jump triangulated by linear_light_build_skin.
std::vector<shadowkit::LinearLightSkinVertex> cpu_skin(skvk::Context& ctx, const skvk::Image& map, const EndView& o) {
    const std::vector<float> depth = skvk::read_image(ctx, map, VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL, 1);
    REQUIRE(depth.size() == std::size_t(kMap) * kMap);
    std::vector<glm::vec3> position(depth.size());
    std::vector<float> distance(depth.size());
    for (std::uint32_t j = 0; j < kMap; ++j)
        for (std::uint32_t i = 0; i < kMap; ++i) {
            const std::size_t q = std::size_t(j) * kMap + i;
            const float zn = depth[q] * 2.f - 1.f;  // the map's window depth is GL's: back to GL NDC
            distance[q] = 2.f * o.znear * o.zfar / (o.zfar + o.znear - zn * (o.zfar - o.znear));
            const glm::vec4 w = o.inv_gl * glm::vec4((float(i) + 0.5f) / float(kMap) * 2.f - 1.f,
                                                     (float(j) + 0.5f) / float(kMap) * 2.f - 1.f, zn, 1.f);
            position[q] = glm::vec3(w) / w.w;
        }
    std::vector<shadowkit::LinearLightSkinVertex> skin(shadowkit::linear_light_skin_capacity(kMap, kMap) / 8);
    shadowkit::LinearLightSkinResult r =
        shadowkit::linear_light_build_skin(position.data(), distance.data(), kMap, kMap, 0.05f, skin.data(), skin.size());
    if (r.status == shadowkit::Status::BufferTooSmall) {
        skin.resize(r.needed);
        r = shadowkit::linear_light_build_skin(position.data(), distance.data(), kMap, kMap, 0.05f, skin.data(), skin.size());
    }
    REQUIRE(r.status == shadowkit::Status::Ok);
    skin.resize(r.count);
    return skin;
}

LinearFrame render_k(LinearPasses& P, const LinearScene& sc, const std::vector<EndView>& ends, bool cpu) {
    skvk::Context& ctx = P.ctx;
    skvk::Scope scope(ctx);
    const std::size_t k = ends.size() - 1;
    const bool glsl = P.lang == Source::Glsl;
    auto& dmaps = scope.own<std::vector<skvk::Image>>(k + 1);
    auto& vmaps = scope.own<std::vector<skvk::Image>>(2 * k);
    std::vector<VkFramebuffer> fbs;
    auto& sets = scope.own<std::vector<skvk::DescriptorSet>>(2 * k);
    auto& ubos = scope.own<std::vector<skvk::Buffer>>(2 * k);
    VkCommandBuffer cmd = skvk::begin_commands(ctx);
    VkClearValue far{}, one{};
    far.depthStencil = {1.f, 0};
    for (float& c : one.color.float32) c = 1.f;
    const auto nv = static_cast<std::uint32_t>(sc.vertices.size());
    for (std::size_t i = 0; i <= k; ++i) {
        REQUIRE(skvk::make_image(ctx, kMap, kMap, 1, VK_FORMAT_D32_SFLOAT,
                                 VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                                 dmaps[i]));
        fbs.push_back(scope.keep(skvk::make_framebuffer(ctx, P.depth_rp, {dmaps[i].view}, kMap, kMap), vkDestroyFramebuffer));
        skvk::draw_pass(cmd, P.depth_rp, fbs.back(), kMap, kMap, {far}, P.depth, P.depth_layout, nullptr, &ends[i].vp_zo,
                        P.vb.buffer, nv, false);
    }
    REQUIRE(skvk::submit_and_wait(ctx, cmd));
    auto& skin_vbs = scope.own<std::vector<skvk::Buffer>>(cpu ? k + 1 : 0);
    std::vector<std::uint32_t> skin_counts(k + 1, 6 * (kMap - 1) * (kMap - 1));
    for (std::size_t i = 0; i < skin_vbs.size(); ++i) {
        const auto skin = cpu_skin(ctx, dmaps[i], ends[i]);
        skin_counts[i] = static_cast<std::uint32_t>(skin.size());
        REQUIRE(!skin.empty());
        REQUIRE(skvk::make_buffer(ctx, skin.size() * sizeof(skin[0]), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, skin_vbs[i]));
        std::memcpy(skin_vbs[i].mapped, skin.data(), skin.size() * sizeof(skin[0]));
    }
    cmd = skvk::begin_commands(ctx);
    const VkDescriptorType tex = skvk::texture_type(P.lang);
    struct SkinParams {
        glm::mat4 other_inv_vp, this_vp;
        glm::vec4 p;
    };
    for (std::size_t d = 0; d < 2 * k; ++d) {
        const std::size_t i = d / 2, from = d % 2 == 0 ? i + 1 : i, into = d % 2 == 0 ? i : i + 1;
        const std::size_t slot = 2 * std::min(from, into) + (from < into ? 1 : 0);
        REQUIRE(skvk::make_image(ctx, kMap, kMap, 1, VK_FORMAT_R32G32B32A32_SFLOAT,
                                 VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                                 vmaps[slot]));
        REQUIRE(skvk::make_descriptor_set(ctx, {{0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, VK_SHADER_STAGE_VERTEX_BIT},
                                                {1, tex, VK_SHADER_STAGE_VERTEX_BIT}}, sets[d]));
        const SkinParams sp{ends[from].inv_gl, ends[into].vp_zo, glm::vec4(ends[from].znear, ends[from].zfar, 0.05f, 0.f)};
        REQUIRE(skvk::make_buffer(ctx, sizeof sp, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, ubos[d]));
        std::memcpy(ubos[d].mapped, &sp, sizeof sp);
        skvk::write_buffer(ctx, sets[d], 0, ubos[d]);
        skvk::write_image(ctx, sets[d], 1, tex, dmaps[from].view, glsl ? P.nearest : VK_NULL_HANDLE,
                          VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL);
        fbs.push_back(scope.keep(skvk::make_framebuffer(ctx, P.skin_rp, {vmaps[slot].view}, kMap, kMap), vkDestroyFramebuffer));
        skvk::draw_pass(cmd, P.skin_rp, fbs.back(), kMap, kMap, {one}, cpu ? P.skin_cpu : P.skin, P.skin_layout, &sets[d].set,
                        nullptr, cpu ? skin_vbs[from].buffer : VK_NULL_HANDLE, skin_counts[from], false);
        skvk::transition(cmd, vmaps[slot], VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    }
    REQUIRE(skvk::submit_and_wait(ctx, cmd));
    LinearFrame f = render_lookup(P, sc, ends, dmaps, vmaps);
    return f;
}

void run_passes(Source lang, bool cpu) {
    skvk::Context& ctx = skvk::vk_test_context();
    const std::size_t before = skvk::message_count();
    const LinearScene sc;
    REQUIRE(sc.seg.status == shadowkit::Status::Ok);
    LinearPasses P(ctx, lang, sc);
    const std::string name = lang == Source::Glsl ? "GLSL" : "HLSL";
    const float diag = glm::length(sc.hi - sc.lo);
    const glm::vec3 center = 0.5f * (sc.seg.end_a + sc.seg.end_b);
    double rm[3] = {0.0, 0.0, 0.0};
    int idx = 0;
    for (std::uint32_t k : {1u, 2u, 4u}) {
        CAPTURE(k);
        glm::vec3 pts[5];
        REQUIRE(shadowkit::linear_light_subdivide(sc.seg, k, pts, 5).status == shadowkit::Status::Ok);
        std::vector<EndView> ends;
        for (std::uint32_t i = 0; i <= k; ++i) ends.push_back(end_view(sc, pts[i]));
        const LinearFrame f = render_k(P, sc, ends, cpu);
        REQUIRE(f.v.size() == std::size_t(kCamW) * kCamH);
        double sq = 0.0, mx = 0.0, psq = 0.0;
        std::size_t n = 0, penumbra = 0;
        for (std::size_t q = 0; q < f.v.size(); ++q) {
            if (f.world[4 * q + 3] != 1.f) continue;  // background
            const glm::vec3 nn(f.normal[4 * q], f.normal[4 * q + 1], f.normal[4 * q + 2]);
            const glm::vec3 p(f.world[4 * q], f.world[4 * q + 1], f.world[4 * q + 2]);
            if (!(glm::dot(nn, center - p) > 0.f)) continue;  // the metrics' faces_light
            const auto exact = shadowkit::linear_light_visible_fraction(p + 1e-5f * diag * nn, nn, sc.seg.end_a, sc.seg.end_b,
                                                                      sc.casters.data(), sc.casters.size(), 0.f);
            REQUIRE(exact.status == shadowkit::Status::Ok);
            const double e = double(f.v[q]) - double(exact.fraction);
            sq += e * e;
            mx = std::max(mx, std::abs(e));
            ++n;
            if (exact.fraction > 0.f && exact.fraction < 1.f) {
                ++penumbra;
                psq += e * e;
            }
        }
        rm[idx] = n ? std::sqrt(sq / double(n)) : 1.0;
        MESSAGE(name << " segments = " << k << " (" << ends.size() << " maps of " << kMap << "^2, " << std::string(cpu ? "CPU" : "GPU")
                     << " skins): RMSE vs closed form "
                     << rm[idx] << ", max " << mx << " over " << n << " pixels; " << penumbra << " in penumbra, RMSE there "
                     << (penumbra ? std::sqrt(psq / double(penumbra)) : 0.0));
        CHECK(penumbra > n / 20);
        ++idx;
    }
    CHECK(rm[0] < 0.06);
    CHECK(rm[1] < rm[0]);  // subdividing fixes the thin post (neither endpoint sees the light) ...
    CHECK(rm[2] < rm[1]);  // ... and shortens every interpolated penumbra
    CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());
}

}  // namespace

TEST_CASE("linear_light.glsl on Vulkan: sk_linear_light_visibility equals its CPU evaluation on synthetic maps") {
    run_linear(Source::Glsl);
}

TEST_CASE("HLSL linear_light.hlsl on Vulkan: sk_linear_light_visibility equals its CPU evaluation on synthetic maps") {
    run_linear(Source::Hlsl);
}

TEST_CASE("linear_light.glsl on Vulkan: depth maps, GPU skins and lookup against the closed form (GL test bounds)") {
    run_passes(Source::Glsl, false);
}

TEST_CASE("HLSL linear_light.hlsl on Vulkan: depth maps, GPU skins and lookup against the closed form (GL test bounds)") {
    run_passes(Source::Hlsl, false);
}

TEST_CASE("linear_light.glsl on Vulkan: depth maps, CPU skins (the GL test's skin=cpu) and lookup against the closed form") {
    run_passes(Source::Glsl, true);
}

TEST_CASE("HLSL linear_light.hlsl on Vulkan: depth maps, CPU skins (the GL test's skin=cpu) and lookup against the closed form") {
    run_passes(Source::Hlsl, true);
}
