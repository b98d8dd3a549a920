// glsl/silhouette_map.glsl and hlsl/silhouette_map.hlsl RUN on Vulkan: the lookup sk_silmap_visibility
// on a synthetic 64 x 64 depth map (R32_SFLOAT, samples 0.3 or 0.7 around receivers at 0.5, so the four
// depth tests of a cell often disagree) and silhouette map (R8G8B8A8_UNORM: random points in each cell,
// weights 1, 2 and some 3 = failure texels), 2,048 random lookups, against the CPU lookup
// shadowkit::silmap_lookup on the same quantized data: at most 0.5% may differ (an angle tie within
// float rounding), and most silhouette lookups must take the sector path (no fallback). No validation message.
// The passes RUN end to end as in tests/gl/test_gl_silhouette_map.cpp's first case: depth map, edge
// pass (sk_silmap_edge_vertex, sk_silmap_point, sk_silmap_occluded, blended as the snippet says) and
// lookup on two floating boxes over a floor (N = 128, 256; 320 x 240 camera), against an exact ray cast
// to the light: the GL test's four bounds (misclassified <= the plain map of equal memory's, wrong
// pixels < 1/5 of its, rmse < half of its, wrong pixels' boundary distance p50 < 0.5 texel). The GL
// test's stack (measured only) and fence cases run the sample's GL technique and are not ported.
#include <doctest/doctest.h>

#include <shadowkit/silhouette.hpp>
#include <shadowkit/silhouette_map.hpp>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "../silmap_reference.hpp"
#include "vk_harness.hpp"
#include "vk_passes.hpp"
#include "vk_scene.hpp"

namespace {

using skvk::Source;

const char* kGlsl = R"(
layout(set = 0, binding = 0) uniform sampler2D u_depth;
layout(set = 0, binding = 1) uniform sampler2D u_silmap;
layout(set = 0, binding = 2, std430) readonly buffer Lookups { vec4 lookup[]; };  // (texel xy, receiver depth, -)
layout(location = 0) out float o_value;
void main() {
    vec4 a = lookup[int(gl_FragCoord.x)];
    o_value = sk_silmap_visibility(u_depth, u_silmap, a.xy, a.z, 0.0);
}
)";
const char* kHlsl = R"(
[[vk::binding(0, 0)]] Texture2D<float> u_depth;
[[vk::binding(1, 0)]] Texture2D<float4> u_silmap;
[[vk::binding(2, 0)]] StructuredBuffer<float4> lookup;
float ps_main(float4 position : SV_Position) : SV_Target0 {
    float4 a = lookup[int(position.x)];
    return sk_silmap_visibility(u_depth, u_silmap, a.xy, a.z, 0.0);
}
)";

constexpr int kSize = 64;

void run_silmap(Source lang) {
    skvk::Context& ctx = skvk::vk_test_context();
    skvk::Scope scope(ctx);
    const std::size_t before = skvk::message_count();
    std::vector<std::uint32_t> vs, fs;
    const char* entries[2] = {"main", "main"};
    if (lang == Source::Glsl) {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_GLSL_DIR) + "/silhouette_map.glsl");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, skvk::kFullscreenGlsl, "main", "silmap.glsl.vert");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, "#version 450 core\n" + snippet + kGlsl, "main",
                                   "silmap.glsl.frag");
    } else {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_HLSL_DIR) + "/silhouette_map.hlsl");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, snippet + skvk::kFullscreenHlsl + kHlsl, "vs_main", "silmap.hlsl.vert");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, snippet + skvk::kFullscreenHlsl + kHlsl, "ps_main", "silmap.hlsl.frag");
        entries[0] = "vs_main";
        entries[1] = "ps_main";
    }
    std::mt19937 rng(2003);
    std::uniform_real_distribution<float> U01(0.f, 1.f);
    std::vector<float> depth(kSize * kSize);
    std::vector<std::uint8_t> rgba(4 * kSize * kSize);
    std::vector<glm::vec2> points(kSize * kSize);
    std::vector<std::uint8_t> weights(kSize * kSize);
    for (std::size_t t = 0; t < depth.size(); ++t) {
        depth[t] = U01(rng) < 0.5f ? 0.3f : 0.7f;
        const auto px = std::uint8_t(rng() % 256), py = std::uint8_t(rng() % 256);
        const std::uint8_t w = std::uint8_t(t % 17 == 0 ? 3 : 1 + rng() % 2);
        rgba[4 * t] = px;
        rgba[4 * t + 1] = py;
        rgba[4 * t + 3] = w;
        points[t] = glm::vec2(float(px) / 255.f, float(py) / 255.f);  // what the GPU reads from UNORM
        weights[t] = w;
    }
    skvk::Image& zmap = scope.own<skvk::Image>();
    skvk::Image& smap = scope.own<skvk::Image>();
    const VkImageUsageFlags up = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    REQUIRE(skvk::make_image(ctx, kSize, kSize, 1, VK_FORMAT_R32_SFLOAT, up, zmap));
    REQUIRE(skvk::make_image(ctx, kSize, kSize, 1, VK_FORMAT_R8G8B8A8_UNORM, up, smap));
    const VkImageLayout read = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    REQUIRE(skvk::upload_image(ctx, zmap, depth, read));
    {  // the RGBA8 map: upload_image takes floats, so the bytes go through a float vector of the same size
        std::vector<float> packed(kSize * kSize);
        std::memcpy(packed.data(), rgba.data(), rgba.size());
        REQUIRE(skvk::upload_image(ctx, smap, packed, read));
    }

    constexpr std::uint32_t M = 2048;
    std::vector<glm::vec4> pts(M);
    for (auto& p : pts) p = glm::vec4(0.5f + 63.f * U01(rng), 0.5f + 63.f * U01(rng), 0.5f, 0.f);
    pts[0] = glm::vec4(0.2f, 10.f, 0.5f, 0.f);  // border lookups: the plain result
    pts[1] = glm::vec4(63.9f, 63.9f, 0.5f, 0.f);
    skvk::Buffer& ssbo = scope.own<skvk::Buffer>();
    REQUIRE(skvk::make_buffer(ctx, M * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, ssbo));
    std::memcpy(ssbo.mapped, pts.data(), M * sizeof(glm::vec4));
    VkSampler nearest = scope.keep(skvk::make_sampler(ctx, VK_FILTER_NEAREST, VK_COMPARE_OP_NEVER), vkDestroySampler);
    skvk::DescriptorSet& ds = scope.own<skvk::DescriptorSet>();
    const VkShaderStageFlags frag = VK_SHADER_STAGE_FRAGMENT_BIT;
    const VkDescriptorType tex = skvk::texture_type(lang);
    REQUIRE(skvk::make_descriptor_set(ctx, {{0, tex, frag}, {1, tex, frag}, {2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, frag}}, ds));
    const VkSampler s = lang == Source::Glsl ? nearest : VK_NULL_HANDLE;
    skvk::write_image(ctx, ds, 0, tex, zmap.view, s, read);
    skvk::write_image(ctx, ds, 1, tex, smap.view, s, read);
    skvk::write_buffer(ctx, ds, 2, ssbo, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
    skvk::RowPass& row = scope.own<skvk::RowPass>();
    skvk::make_row_pass(ctx, vs, fs, entries[0], entries[1], ds, M, row);
    const std::vector<float> gpu = skvk::draw_row(ctx, row, ds);

    std::size_t off = 0, silhouette = 0, sector = 0, bad = 0, plain_differs = 0;
    for (std::uint32_t i = 0; i < M; ++i) {
        if (!(gpu[i] == 0.f || gpu[i] == 1.f)) ++bad;
        const shadowkit::SilmapLookup cpu = shadowkit::silmap_lookup(points.data(), weights.data(), depth.data(),
                                                                     glm::uvec2(kSize), glm::vec2(pts[i]), pts[i].z, 0.f);
        REQUIRE(cpu.status == shadowkit::Status::Ok);
        silhouette += cpu.silhouette_pixel;
        sector += cpu.silhouette_pixel && !cpu.fallback;
        off += (gpu[i] > 0.5f) != cpu.lit;
        // the sector path decides: the plain nearest-sample answer differs on many lookups
        plain_differs += shadowkit::silmap_plain_lookup(depth.data(), glm::uvec2(kSize), glm::vec2(pts[i]), pts[i].z, 0.f).lit != cpu.lit;
    }
    MESSAGE((lang == Source::Glsl ? "GLSL" : "HLSL") << ": " << silhouette << " silhouette lookups (" << sector
                                                    << " through the sectors), " << off << " of " << M << " differ from silmap_lookup (the plain "
                                                    << "lookup differs from it on " << plain_differs << ")");
    CHECK(bad == 0);
    CHECK(sector > M / 4);
    CHECK(off <= M / 200);
    CHECK(plain_differs > M / 20);
    CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());
}


// ------------------------------------------------------------------ the passes end to end
// tests/gl/test_gl_silhouette_map.cpp's first case on Vulkan: two boxes floating over a floor under the
// stack scene's spot light (only the floor receives), seen by the stack scene's camera at 320 x 240;
// the casters' depth from the light (pass 1, D32, depth bias 2 / slope 2 as the sample's polygon
// offset), the silhouette map (pass 2: one quad per silhouette edge, six vertices carrying the edge,
// blending rgb ONE/ZERO and alpha ONE/ONE), the lookup at every camera pixel (pass 3) next to the
// plain shadow map of equal memory (sqrt(2) N, hardware 2x2 compare through glsl/shadow_map.glsl),
// for N = 128 and 256. The reference is exact: a ray cast to the light against the two boxes (the
// GL test's Embree reference of the same boxes). The matrices are zero-to-one (Vulkan) ones:
// silmap_project_edges with ClipDepth::ZeroToOne, window depth = NDC z. All passes share the
// unflipped viewport, so texel space (uv * size, NDC y = -1 at row 0) is the maps' rows as drawn.
const char* kParamsGlsl = R"(
layout(set = 0, binding = 0, std140) uniform Params { mat4 cam_vp; mat4 light_vp; vec4 p; } u;  // p: N, N, occlusion bias
)";
const char* kDepthVsGlsl = R"(
layout(location = 0) in vec3 a_p;
void main() { gl_Position = u.light_vp * vec4(a_p, 1.0); }
)";
const char* kEdgeVsGlsl = R"(
layout(location = 0) in vec4 a_ab;
layout(location = 1) in vec2 a_z;
layout(location = 0) flat out vec4 v_ab;
layout(location = 1) flat out vec2 v_z;
void main() {
    v_ab = a_ab;
    v_z = a_z;
    gl_Position = sk_silmap_edge_vertex(a_ab.xy, a_ab.zw, gl_VertexIndex, u.p.xy);
}
)";
const char* kEdgeFsGlsl = R"(
layout(set = 0, binding = 1) uniform sampler2D u_depth;
layout(location = 0) flat in vec4 v_ab;
layout(location = 1) flat in vec2 v_z;
layout(location = 0) out vec4 o_silmap;
void main() {
    vec2 local;
    float w;
    if (!sk_silmap_point(gl_FragCoord.xy, v_ab.xy, v_ab.zw, local, w)) discard;
    if (sk_silmap_occluded(u_depth, ivec2(gl_FragCoord.xy), v_ab.xy, v_ab.zw, v_z.x, v_z.y, local, u.p.z)) discard;
    o_silmap = vec4(local, 0.0, w / 255.0);
}
)";
const char* kLookupVsGlsl = R"(
layout(location = 0) in vec3 a_p;
layout(location = 0) out vec3 v_world;
void main() { v_world = a_p; gl_Position = u.cam_vp * vec4(a_p, 1.0); }
)";
const char* kLookupFsGlsl = R"(
layout(set = 0, binding = 1) uniform sampler2D u_depth;
layout(set = 0, binding = 2) uniform sampler2D u_silmap;
layout(set = 0, binding = 3) uniform sampler2DShadow u_plain;
layout(location = 0) in vec3 v_world;
layout(location = 0) out float o_sil;
layout(location = 1) out float o_plain;
layout(location = 2) out vec4 o_world;
void main() {
    vec4 c = u.light_vp * vec4(v_world, 1.0);
    float v = 1.0;
    vec2 uv = c.xy / c.w * 0.5 + 0.5;
    if (c.w > 0.0 && all(greaterThanEqual(uv, vec2(0.0))) && all(lessThanEqual(uv, vec2(1.0))))
        v = sk_silmap_visibility(u_depth, u_silmap, uv * vec2(textureSize(u_depth, 0)), c.z / c.w, 0.0);
    o_sil = v;
    o_plain = sk_shadow_map_visibility(u_plain, u.light_vp, v_world, true, 0.0, 1.0);
    o_world = vec4(v_world, 1.0);
}
)";
const char* kPassesHlsl = R"(
struct Params { column_major float4x4 cam_vp; column_major float4x4 light_vp; float4 p; };
[[vk::binding(0, 0)]] ConstantBuffer<Params> u;
[[vk::binding(1, 0)]] Texture2D<float> u_depth;
[[vk::binding(2, 0)]] Texture2D<float4> u_silmap;
[[vk::binding(3, 0)]] Texture2D<float> u_plain;
[[vk::binding(4, 0)]] SamplerComparisonState u_cmp;
float4 depth_vs([[vk::location(0)]] float3 p : POSITION) : SV_Position { return mul(u.light_vp, float4(p, 1.0)); }
struct EdgeV {
    float4 position : SV_Position;
    [[vk::location(0)]] nointerpolation float4 ab : TEXCOORD0;
    [[vk::location(1)]] nointerpolation float2 z : TEXCOORD1;
};
EdgeV edge_vs([[vk::location(0)]] float4 ab : AB, [[vk::location(1)]] float2 z : Z, uint id : SV_VertexID) {
    EdgeV o;
    o.ab = ab;
    o.z = z;
    o.position = sk_silmap_edge_vertex(ab.xy, ab.zw, int(id), u.p.xy);
    return o;
}
float4 edge_ps(EdgeV i) : SV_Target0 {
    float2 local;
    float w;
    if (!sk_silmap_point(i.position.xy, i.ab.xy, i.ab.zw, local, w)) discard;
    if (sk_silmap_occluded(u_depth, int2(i.position.xy), i.ab.xy, i.ab.zw, i.z.x, i.z.y, local, u.p.z)) discard;
    return float4(local, 0.0, w / 255.0);
}
struct WorldV {
    float4 position : SV_Position;
    [[vk::location(0)]] float3 world : TEXCOORD0;
};
WorldV lookup_vs([[vk::location(0)]] float3 p : POSITION) {
    WorldV o;
    o.world = p;
    o.position = mul(u.cam_vp, float4(p, 1.0));
    return o;
}
struct Targets {
    [[vk::location(0)]] float sil : SV_Target0;
    [[vk::location(1)]] float plain : SV_Target1;
    [[vk::location(2)]] float4 world : SV_Target2;
};
Targets lookup_ps(WorldV i) {
    Targets o;
    float4 c = mul(u.light_vp, float4(i.world, 1.0));
    float v = 1.0;
    float2 uv = c.xy / c.w * 0.5 + 0.5;
    uint w, h;
    u_depth.GetDimensions(w, h);
    if (c.w > 0.0 && all(uv >= 0.0) && all(uv <= 1.0))
        v = sk_silmap_visibility(u_depth, u_silmap, uv * float2(w, h), c.z / c.w, 0.0);
    o.sil = v;
    o.plain = sk_shadow_map_visibility(u_plain, u_cmp, u.light_vp, i.world, true, 0.0, 1.0);
    o.world = float4(i.world, 1.0);
    return o;
}
)";

struct Box {
    glm::vec3 c, h;
};

// The GL test's floating_boxes(): the stack scene's floor (half size 4), two boxes, its spot light
// and camera; the light frustum fitted as samples/app fit_light does (spot: the cone's angle, near and
// far around the scene's bounds), here with zero-to-one depth.
struct FloatingBoxes {
    Box boxes[2] = {{{-0.3f, 1.0f, 0.1f}, {0.6f, 0.15f, 0.5f}}, {{0.5f, 1.8f, -0.4f}, {0.25f, 0.25f, 0.25f}}};
    glm::vec3 light{1.6f, 4.5f, 1.3f};
    glm::mat4 light_vp{1.f}, cam_vp{1.f};
    std::vector<glm::vec3> tris;                // floor (6 vertices), then the boxes' triangles
    std::vector<glm::vec3> corners[2];          // each box's 8 corners
    std::vector<std::uint32_t> box_indices;     // 12 triangles over 8 corners, counter-clockwise outside
    FloatingBoxes() {
        const float g = 4.f;
        for (const glm::vec3& p : {glm::vec3(-g, 0, g), glm::vec3(g, 0, g), glm::vec3(g, 0, -g), glm::vec3(-g, 0, g),
                                   glm::vec3(g, 0, -g), glm::vec3(-g, 0, -g)})
            tris.push_back(p);
        const int quads[6][4] = {{4, 5, 6, 7}, {1, 0, 3, 2}, {5, 1, 2, 6}, {0, 4, 7, 3}, {7, 6, 2, 3}, {0, 1, 5, 4}};
        for (const auto& q : quads)
            for (int i : {0, 1, 2, 0, 2, 3}) box_indices.push_back(std::uint32_t(q[i]));
        glm::vec3 lo(-g, 0.f, -g), hi(g, 0.f, g);
        for (int b = 0; b < 2; ++b) {
            for (int i = 0; i < 8; ++i)
                corners[b].push_back(boxes[b].c + boxes[b].h * glm::vec3((i == 1 || i == 2 || i == 5 || i == 6) ? 1.f : -1.f,
                                                                         (i == 2 || i == 3 || i == 6 || i == 7) ? 1.f : -1.f,
                                                                         i >= 4 ? 1.f : -1.f));
            for (std::uint32_t k : box_indices) tris.push_back(corners[b][k]);
            lo = glm::min(lo, boxes[b].c - boxes[b].h);
            hi = glm::max(hi, boxes[b].c + boxes[b].h);
        }
        const glm::vec3 dir = glm::normalize(glm::vec3(-1.6f, -4.5f, -1.3f));
        const glm::mat4 view = glm::lookAt(light, light + dir, glm::vec3(0.f, 0.f, 1.f));  // |dir.y| > 0.9: up = +z
        float zmin = INFINITY, zmax = 0.f;
        for (int i = 0; i < 8; ++i) {
            const glm::vec3 c((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
            const float z = -(view * glm::vec4(c, 1.f)).z;
            zmin = std::min(zmin, z);
            zmax = std::max(zmax, z);
        }
        const float zfar = zmax * 1.01f, znear = std::max(zmin * 0.9f, zfar * 2e-3f);
        light_vp = glm::perspectiveRH_ZO(1.4f, 1.f, znear, zfar) * view;
        cam_vp = glm::perspectiveRH_ZO(0.9f, 320.f / 240.f, 0.05f, 100.f) *
                 glm::lookAt(glm::vec3(-2.5f, 3.f, 4.f), glm::vec3(0.f, 0.5f, 0.f), glm::vec3(0.f, 1.f, 0.f));
    }
    // The boxes' silhouette edges for the light in the texel space of a map of `size`.
    std::vector<shadowkit::SilmapEdge> edges(std::uint32_t size) const {
        std::vector<shadowkit::SilmapEdge> out;
        for (int b = 0; b < 2; ++b) {
            const auto adj = shadowkit::silhouette_build_adjacency(corners[b].data(), 8, box_indices.data(), box_indices.size());
            REQUIRE(adj.status == shadowkit::Status::Ok);
            const auto sil = shadowkit::silhouette_compute(adj, corners[b].data(), 8, glm::vec4(light, 1.f));
            REQUIRE(sil.status == shadowkit::Status::Ok);
            std::vector<shadowkit::SilmapEdge> e(sil.indices.size() / 2);
            const auto pr = shadowkit::silmap_project_edges(light_vp, shadowkit::ClipDepth::ZeroToOne, glm::uvec2(size, size),
                                                            corners[b].data(), 8, sil.indices.data(), sil.indices.size() / 2,
                                                            e.data(), e.size());
            REQUIRE(pr.status == shadowkit::Status::Ok);
            out.insert(out.end(), e.begin(), e.begin() + static_cast<std::ptrdiff_t>(pr.count));
        }
        return out;
    }
    bool shadowed(glm::vec3 p) const {
        for (const Box& b : boxes)
            if (skvk::segment_hits_box(p, light, b.c - b.h, b.c + b.h)) return true;
        return false;
    }
};

// Pipelines of the three passes (one language) and their descriptor set (params, N map, silhouette
// map, plain map (+ its comparison sampler for HLSL)).
struct SilPasses {
    skvk::Context& ctx;
    Source lang;
    skvk::Scope scope;  ///< everything below; declared first, so destroyed last
    skvk::Buffer& ubo = scope.own<skvk::Buffer>();
    skvk::Buffer& vb = scope.own<skvk::Buffer>();
    skvk::DescriptorSet& ds = scope.own<skvk::DescriptorSet>();
    VkSampler nearest = VK_NULL_HANDLE, compare = VK_NULL_HANDLE;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VkRenderPass depth_rp = VK_NULL_HANDLE, edge_rp = VK_NULL_HANDLE, lookup_rp = VK_NULL_HANDLE;
    VkPipeline depth = VK_NULL_HANDLE, edge = VK_NULL_HANDLE, lookup = VK_NULL_HANDLE;

    SilPasses(skvk::Context& c, Source l, const FloatingBoxes& sc) : ctx(c), lang(l), scope(c) {
        const VkShaderStageFlags both = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, F = VK_SHADER_STAGE_FRAGMENT_BIT;
        const bool glsl = lang == Source::Glsl;
        const VkDescriptorType tex = skvk::texture_type(lang);
        std::vector<skvk::Binding> b = {{0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, both}, {1, tex, F}, {2, tex, F}, {3, tex, F}};
        if (!glsl) b.push_back({4, VK_DESCRIPTOR_TYPE_SAMPLER, F});
        REQUIRE(skvk::make_descriptor_set(ctx, b, ds));
        REQUIRE(skvk::make_buffer(ctx, 2 * sizeof(glm::mat4) + sizeof(glm::vec4), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, ubo));
        skvk::write_buffer(ctx, ds, 0, ubo);
        REQUIRE(skvk::make_buffer(ctx, sc.tris.size() * sizeof(glm::vec3), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, vb));
        std::memcpy(vb.mapped, sc.tris.data(), sc.tris.size() * sizeof(glm::vec3));
        nearest = scope.keep(skvk::make_sampler(ctx, VK_FILTER_NEAREST, VK_COMPARE_OP_NEVER), vkDestroySampler);
        compare = scope.keep(skvk::make_sampler(ctx, VK_FILTER_LINEAR, VK_COMPARE_OP_LESS_OR_EQUAL), vkDestroySampler);  // 2x2 PCF, as the GL sample
        if (!glsl) skvk::write_sampler(ctx, ds, 4, compare);
        layout = scope.keep(skvk::make_pipeline_layout(ctx, &ds), vkDestroyPipelineLayout);
        depth_rp = scope.keep(skvk::make_render_pass(ctx, {}, VK_FORMAT_D32_SFLOAT, VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL), vkDestroyRenderPass);
        edge_rp = scope.keep(skvk::make_render_pass(ctx, {VK_FORMAT_R8G8B8A8_UNORM}, VK_FORMAT_UNDEFINED, VK_IMAGE_LAYOUT_UNDEFINED), vkDestroyRenderPass);
        lookup_rp = scope.keep(skvk::make_render_pass(ctx, {VK_FORMAT_R32_SFLOAT, VK_FORMAT_R32_SFLOAT, VK_FORMAT_R32G32B32A32_SFLOAT},
                                           VK_FORMAT_D32_SFLOAT, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL), vkDestroyRenderPass);
        const VkShaderStageFlagBits Vs = VK_SHADER_STAGE_VERTEX_BIT, Fs = VK_SHADER_STAGE_FRAGMENT_BIT;
        std::vector<std::uint32_t> spv[5];  // depth vs, edge vs/fs, lookup vs/fs
        const char* entry[5] = {"main", "main", "main", "main", "main"};
        if (glsl) {
            const std::string v = "#version 450 core\n", sil = skvk::read_text(std::string(SHADOWKIT_GLSL_DIR) + "/silhouette_map.glsl");
            const std::string sm = skvk::read_text(std::string(SHADOWKIT_GLSL_DIR) + "/shadow_map.glsl");
            spv[0] = skvk::compile_checked(lang, Vs, v + kParamsGlsl + kDepthVsGlsl, "main", "silmap.glsl.depth.vert");
            spv[1] = skvk::compile_checked(lang, Vs, v + sil + kParamsGlsl + kEdgeVsGlsl, "main", "silmap.glsl.edge.vert");
            spv[2] = skvk::compile_checked(lang, Fs, v + sil + kParamsGlsl + kEdgeFsGlsl, "main", "silmap.glsl.edge.frag");
            spv[3] = skvk::compile_checked(lang, Vs, v + kParamsGlsl + kLookupVsGlsl, "main", "silmap.glsl.lookup.vert");
            spv[4] = skvk::compile_checked(lang, Fs, v + sil + sm + kParamsGlsl + kLookupFsGlsl, "main", "silmap.glsl.lookup.frag");
        } else {
            const std::string h = skvk::read_text(std::string(SHADOWKIT_HLSL_DIR) + "/silhouette_map.hlsl") +
                                  skvk::read_text(std::string(SHADOWKIT_HLSL_DIR) + "/shadow_map.hlsl") + kPassesHlsl;
            const char* e[5] = {"depth_vs", "edge_vs", "edge_ps", "lookup_vs", "lookup_ps"};
            for (int i = 0; i < 5; ++i) {
                entry[i] = e[i];
                spv[i] = skvk::compile_checked(lang, (i == 2 || i == 4) ? Fs : Vs, h, e[i], std::string("silmap.hlsl.") + e[i]);
            }
        }
        skvk::PipelineDesc pd;
        pd.vertex_stride = sizeof(glm::vec3);
        pd.attributes = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0}};
        pd.vs = spv[0];
        pd.vs_entry = entry[0];
        pd.depth_bias = true;  // the sample's glPolygonOffset(2, 2)
        pd.bias_constant = 2.f;
        pd.bias_slope = 2.f;
        depth = scope.keep(skvk::make_pipeline_checked(ctx, pd, layout, depth_rp), vkDestroyPipeline);
        pd.depth_bias = false;
        pd.vs = spv[3];
        pd.vs_entry = entry[3];
        pd.fs = spv[4];
        pd.fs_entry = entry[4];
        pd.color_count = 3;
        lookup = scope.keep(skvk::make_pipeline_checked(ctx, pd, layout, lookup_rp), vkDestroyPipeline);
        // pass 2: six vertices per edge (a.xy, b.xy, za, zb), rgb: the last point; a: the weights add
        pd.vertex_stride = 6 * sizeof(float);
        pd.attributes = {{0, 0, VK_FORMAT_R32G32B32A32_SFLOAT, 0}, {1, 0, VK_FORMAT_R32G32_SFLOAT, 16}};
        pd.vs = spv[1];
        pd.vs_entry = entry[1];
        pd.fs = spv[2];
        pd.fs_entry = entry[2];
        pd.color_count = 1;
        pd.depth_test = pd.depth_write = false;
        pd.blend = true;
        pd.blend_src = VK_BLEND_FACTOR_ONE;
        pd.blend_dst = VK_BLEND_FACTOR_ZERO;
        pd.blend_src_alpha = pd.blend_dst_alpha = VK_BLEND_FACTOR_ONE;
        edge = scope.keep(skvk::make_pipeline_checked(ctx, pd, layout, edge_rp), vkDestroyPipeline);
    }
};

constexpr std::uint32_t kW = 320, kH = 240;

struct Frame {
    std::vector<float> sil, plain, world;
};

// The three passes for a silhouette map of N (and the plain map of sqrt(2) N): V at every pixel.
Frame render_frame(SilPasses& P, const FloatingBoxes& sc, std::uint32_t N, const std::vector<shadowkit::SilmapEdge>& edges) {
    skvk::Context& ctx = P.ctx;
    skvk::Scope scope(ctx);
    const auto Np = static_cast<std::uint32_t>(std::lround(std::sqrt(2.0) * N));
    struct Params {
        glm::mat4 cam_vp, light_vp;
        glm::vec4 p;
    } params{sc.cam_vp, sc.light_vp, glm::vec4(float(N), float(N), 2e-4f, 0.f)};  // the sample's occlusion_bias
    std::memcpy(P.ubo.mapped, &params, sizeof params);
    skvk::Buffer& evb = scope.own<skvk::Buffer>();
    std::vector<float> ev;
    for (const shadowkit::SilmapEdge& e : edges)
        for (int k = 0; k < 6; ++k)
            for (float f : {e.a.x, e.a.y, e.b.x, e.b.y, e.depth_a, e.depth_b}) ev.push_back(f);
    REQUIRE(skvk::make_buffer(ctx, ev.size() * sizeof(float), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, evb));
    std::memcpy(evb.mapped, ev.data(), ev.size() * sizeof(float));
    skvk::Image& zmap = scope.own<skvk::Image>();
    skvk::Image& pmap = scope.own<skvk::Image>();
    skvk::Image& silmap = scope.own<skvk::Image>();
    skvk::Image& vis = scope.own<skvk::Image>();
    skvk::Image& plain = scope.own<skvk::Image>();
    skvk::Image& world = scope.own<skvk::Image>();
    skvk::Image& zbuf = scope.own<skvk::Image>();
    const VkImageUsageFlags zu = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
    const VkImageUsageFlags rt = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    REQUIRE(skvk::make_image(ctx, N, N, 1, VK_FORMAT_D32_SFLOAT, zu, zmap));
    REQUIRE(skvk::make_image(ctx, Np, Np, 1, VK_FORMAT_D32_SFLOAT, zu, pmap));
    REQUIRE(skvk::make_image(ctx, N, N, 1, VK_FORMAT_R8G8B8A8_UNORM, rt | VK_IMAGE_USAGE_SAMPLED_BIT, silmap));
    REQUIRE(skvk::make_image(ctx, kW, kH, 1, VK_FORMAT_R32_SFLOAT, rt, vis));
    REQUIRE(skvk::make_image(ctx, kW, kH, 1, VK_FORMAT_R32_SFLOAT, rt, plain));
    REQUIRE(skvk::make_image(ctx, kW, kH, 1, VK_FORMAT_R32G32B32A32_SFLOAT, rt, world));
    REQUIRE(skvk::make_image(ctx, kW, kH, 1, VK_FORMAT_D32_SFLOAT, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, zbuf));
    const bool glsl = P.lang == Source::Glsl;
    const VkDescriptorType tex = skvk::texture_type(P.lang);
    const VkImageLayout zread = VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL, read = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    skvk::write_image(ctx, P.ds, 1, tex, zmap.view, glsl ? P.nearest : VK_NULL_HANDLE, zread);
    skvk::write_image(ctx, P.ds, 2, tex, silmap.view, glsl ? P.nearest : VK_NULL_HANDLE, read);
    skvk::write_image(ctx, P.ds, 3, tex, pmap.view, glsl ? P.compare : VK_NULL_HANDLE, zread);
    VkFramebuffer fz = scope.keep(skvk::make_framebuffer(ctx, P.depth_rp, {zmap.view}, N, N), vkDestroyFramebuffer);
    VkFramebuffer fp = scope.keep(skvk::make_framebuffer(ctx, P.depth_rp, {pmap.view}, Np, Np), vkDestroyFramebuffer);
    VkFramebuffer fs = scope.keep(skvk::make_framebuffer(ctx, P.edge_rp, {silmap.view}, N, N), vkDestroyFramebuffer);
    VkFramebuffer fl = scope.keep(skvk::make_framebuffer(ctx, P.lookup_rp, {vis.view, plain.view, world.view, zbuf.view}, kW, kH), vkDestroyFramebuffer);
    const auto nv = static_cast<std::uint32_t>(sc.tris.size());
    VkCommandBuffer cmd = skvk::begin_commands(ctx);
    VkClearValue far{}, none{}, zero{};
    far.depthStencil = {1.f, 0};
    none.color.float32[0] = none.color.float32[1] = 0.5f;  // "no point": (0.5, 0.5, weight 0)
    // pass 1 (casters only: the floor's 6 vertices are skipped by drawing from a vertex offset)
    for (int m = 0; m < 2; ++m) {
        VkRenderPassBeginInfo bi{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
        const std::uint32_t side = m == 0 ? N : Np;
        bi.renderPass = P.depth_rp;
        bi.framebuffer = m == 0 ? fz : fp;
        bi.renderArea = {{0, 0}, {side, side}};
        bi.clearValueCount = 1;
        bi.pClearValues = &far;
        vkCmdBeginRenderPass(cmd, &bi, VK_SUBPASS_CONTENTS_INLINE);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, P.depth);
        const VkViewport vp = skvk::viewport(side, side, false);
        const VkRect2D scissor{{0, 0}, {side, side}};
        vkCmdSetViewport(cmd, 0, 1, &vp);
        vkCmdSetScissor(cmd, 0, 1, &scissor);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, P.layout, 0, 1, &P.ds.set, 0, nullptr);
        const VkDeviceSize offset = 0;
        vkCmdBindVertexBuffers(cmd, 0, 1, &P.vb.buffer, &offset);
        vkCmdDraw(cmd, nv - 6, 1, 6, 0);
        vkCmdEndRenderPass(cmd);
    }
    skvk::draw_pass(cmd, P.edge_rp, fs, N, N, {none}, P.edge, P.layout, &P.ds.set, nullptr, evb.buffer,
                    static_cast<std::uint32_t>(6 * edges.size()), false);
    skvk::transition(cmd, silmap, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, read);
    skvk::draw_pass(cmd, P.lookup_rp, fl, kW, kH, {zero, zero, zero, far}, P.lookup, P.layout, &P.ds.set, nullptr, P.vb.buffer,
                    nv, false);
    REQUIRE(skvk::submit_and_wait(ctx, cmd));
    Frame f;
    f.sil = skvk::read_image(ctx, vis, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 1);
    f.plain = skvk::read_image(ctx, plain, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 1);
    f.world = skvk::read_image(ctx, world, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 4);
    return f;
}

// The GL test's measures against the ray cast at the floor pixels: rmse; the misclassified rate
// away from reference edges (8-neighbourhood, as sk::compute_metrics); every wrong pixel's distance
// in the map's texels to the projected silhouette edges (p50).
struct Score {
    double rmse = 0.0, misclassified = 0.0, p50 = 0.0;
    std::size_t wrong = 0, pixels = 0, shadowed = 0;
};

Score score(const FloatingBoxes& sc, const std::vector<float>& world, const std::vector<float>& v,
            const std::vector<shadowkit::SilmapEdge>& edges, std::uint32_t size) {
    std::vector<int> ref(std::size_t(kW) * kH, -1);
    for (std::size_t k = 0; k < ref.size(); ++k)
        if (world[4 * k + 3] == 1.f && std::abs(world[4 * k + 1]) < 1e-4f)  // a floor pixel (the only receiver)
            ref[k] = sc.shadowed(glm::vec3(world[4 * k], 1e-4f, world[4 * k + 2])) ? 0 : 1;
    Score s;
    double sq = 0.0;
    std::size_t compared = 0, wrong_away = 0;
    std::vector<double> d;
    for (std::uint32_t y = 0; y < kH; ++y)
        for (std::uint32_t x = 0; x < kW; ++x) {
            const std::size_t k = std::size_t(y) * kW + x;
            if (ref[k] < 0) continue;
            ++s.pixels;
            s.shadowed += ref[k] == 0;
            const double e = double(v[k]) - double(ref[k]);
            sq += e * e;
            const bool wrong = (v[k] >= 0.5f ? 1 : 0) != ref[k];
            if (wrong) {
                const glm::vec3 p(world[4 * k], world[4 * k + 1], world[4 * k + 2]);
                d.push_back(silmap_ref::edge_distance(sc.light_vp, p, float(size), edges).texels);
            }
            if (x == 0 || y == 0 || x == kW - 1 || y == kH - 1) continue;
            bool edge = false;
            for (int dy = -1; dy <= 1 && !edge; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int r = ref[std::size_t(int(y) + dy) * kW + std::size_t(int(x) + dx)];
                    if (r >= 0 && r != ref[k]) edge = true;
                }
            if (edge) continue;
            ++compared;
            wrong_away += wrong;
        }
    s.rmse = s.pixels ? std::sqrt(sq / double(s.pixels)) : 0.0;
    s.misclassified = compared ? double(wrong_away) / double(compared) : 0.0;
    s.wrong = d.size();
    if (!d.empty()) {
        std::sort(d.begin(), d.end());
        s.p50 = d[d.size() / 2];
    }
    return s;
}

void run_passes(Source lang) {
    skvk::Context& ctx = skvk::vk_test_context();
    const std::size_t before = skvk::message_count();
    const FloatingBoxes sc;
    SilPasses P(ctx, lang, sc);
    const std::string name = lang == Source::Glsl ? "GLSL" : "HLSL";
    for (std::uint32_t N : {128u, 256u}) {
        CAPTURE(N);
        const auto Np = static_cast<std::uint32_t>(std::lround(std::sqrt(2.0) * N));
        const std::vector<shadowkit::SilmapEdge> edges = sc.edges(N);
        const Frame f = render_frame(P, sc, N, edges);
        REQUIRE(f.sil.size() == std::size_t(kW) * kH);
        std::size_t not_hard = 0;
        for (float x : f.sil) not_hard += !(x == 0.f || x == 1.f);
        const Score ms = score(sc, f.world, f.sil, edges, N), mp = score(sc, f.world, f.plain, sc.edges(Np), Np);
        MESSAGE(name << " size " << N << " (" << edges.size() << " silhouette edges; " << ms.pixels << " floor pixels, "
                     << ms.shadowed << " shadowed): silhouette map misclassified " << ms.misclassified << " (" << ms.wrong
                     << " wrong pixels, boundary error p50 " << ms.p50 << " texels) vs plain " << Np << "^2 misclassified "
                     << mp.misclassified << " (" << mp.wrong << " wrong pixels, p50 " << mp.p50 << " of its texels); rmse "
                     << ms.rmse << " vs " << mp.rmse);
        CHECK(not_hard == 0);
        CHECK(ms.shadowed > 1000);
        CHECK(ms.misclassified <= mp.misclassified);
        CHECK(ms.wrong * 5 < mp.wrong);
        CHECK(ms.rmse < 0.5 * mp.rmse);
        CHECK(ms.p50 < 0.5);
    }
    CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());
}

}  // namespace

TEST_CASE("silhouette_map.glsl on Vulkan: sk_silmap_visibility equals silmap_lookup on synthetic maps") {
    run_silmap(Source::Glsl);
}

TEST_CASE("HLSL silhouette_map.hlsl on Vulkan: sk_silmap_visibility equals silmap_lookup on synthetic maps") {
    run_silmap(Source::Hlsl);
}

TEST_CASE("silhouette_map.glsl on Vulkan: depth, edge and lookup passes beat the plain map of equal memory (GL test)") {
    run_passes(Source::Glsl);
}

TEST_CASE("HLSL silhouette_map.hlsl on Vulkan: depth, edge and lookup passes beat the plain map of equal memory (GL test)") {
    run_passes(Source::Hlsl);
}
