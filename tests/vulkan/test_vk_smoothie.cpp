// glsl/smoothie.glsl and hlsl/smoothie.hlsl RUN on Vulkan: the final lookup sk_smoothie_visibility on a
// synthetic 64 x 64 linear shadow map (R32_SFLOAT) and smoothie buffer (R32G32_SFLOAT: half the texels
// cleared to (1e30, 1), half a smoothie in front of the map), 1,024 random receivers (half with a
// receiver-plane gradient), against the CPU: shadowkit::smoothie_visibility_tap at the four texels
// around uv, filtered bilinearly as the snippet's comment says. At most 0.5% of the lookups may differ
// by more than 1e-4 (a receiver depth that ties a stored depth within float rounding may flip a tap,
// as in the PCSS test); every value finite and in [0, 1]; no validation message.
// The three passes RUN end to end as in tests/gl/test_gl_smoothie.cpp (a) and (b): the card over a floor,
// linear map (pass 1), smoothie buffer MIN-blended (pass 2, VK_BLEND_OP_MIN; both variants of the remap)
// and final lookup (pass 3) on 512 x 512 maps for t = 0.05, 0.1, 0.2: every floor texel's visibility
// within 1e-4 of the CPU prediction from the card's closed-form light-NDC distance, and the smoothie
// buffer's depth and alpha within 1e-4 of it; t = 0 bit-identical to an independent hard 2x2 lookup
// seen through an oblique 320 x 240 camera. (c) and (d) of the GL test run the sample's GL technique
// against the Embree reference, which has no Vulkan counterpart here.
#include <doctest/doctest.h>

#include <shadowkit/smoothie.hpp>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "../smoothie_reference.hpp"
#include "vk_harness.hpp"
#include "vk_passes.hpp"

namespace {

using skvk::Source;

const char* kGlsl = R"(
layout(set = 0, binding = 0) uniform sampler2D u_shadow_map;
layout(set = 0, binding = 1) uniform sampler2D u_smoothie_map;
layout(set = 0, binding = 2, std430) readonly buffer Lookups { vec4 lookup[]; };  // (uv, r, bias), (dr_duv, -, -)
layout(location = 0) out float o_value;
void main() {
    int i = int(gl_FragCoord.x);
    vec4 a = lookup[2 * i];
    o_value = sk_smoothie_visibility(u_shadow_map, u_smoothie_map, a.xy, a.z, lookup[2 * i + 1].xy, a.w, false);
}
)";
const char* kHlsl = R"(
[[vk::binding(0, 0)]] Texture2D<float> u_shadow_map;
[[vk::binding(1, 0)]] Texture2D<float2> u_smoothie_map;
[[vk::binding(2, 0)]] StructuredBuffer<float4> lookup;
float ps_main(float4 position : SV_Position) : SV_Target0 {
    int i = int(position.x);
    float4 a = lookup[2 * i];
    return sk_smoothie_visibility(u_shadow_map, u_smoothie_map, a.xy, a.z, lookup[2 * i + 1].xy, a.w, false);
}
)";

constexpr int kSize = 64;

// The snippet's final lookup on the CPU: four taps (smoothie_visibility_tap) filtered bilinearly.
double cpu_visibility(const std::vector<float>& z, const std::vector<float>& sm, glm::vec2 uv, float r, glm::vec2 g, float bias) {
    if (!(r > 0.f) || uv.x < 0.f || uv.y < 0.f || uv.x > 1.f || uv.y > 1.f) return 1.0;
    const glm::vec2 st = uv * float(kSize) - 0.5f;
    const glm::vec2 base = glm::floor(st), f = st - base;
    double v[4];
    for (int k = 0; k < 4; ++k) {
        const int x = std::clamp(int(base.x) + (k & 1), 0, kSize - 1), y = std::clamp(int(base.y) + (k >> 1), 0, kSize - 1);
        const glm::vec2 uv_tap = (glm::vec2(float(x), float(y)) + 0.5f) / float(kSize);
        const float r_tap = r + glm::dot(g, uv_tap - uv);
        const std::size_t t = std::size_t(y * kSize + x);
        v[k] = shadowkit::smoothie_visibility_tap(r_tap, z[t], sm[2 * t], sm[2 * t + 1], bias);
    }
    const double fx = f.x, fy = f.y;
    return (v[0] * (1 - fx) + v[1] * fx) * (1 - fy) + (v[2] * (1 - fx) + v[3] * fx) * fy;
}

void run_smoothie(Source lang) {
    skvk::Context& ctx = skvk::vk_test_context();
    skvk::Scope scope(ctx);
    const std::size_t before = skvk::message_count();
    std::vector<std::uint32_t> vs, fs;
    const char* entries[2] = {"main", "main"};
    if (lang == Source::Glsl) {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_GLSL_DIR) + "/smoothie.glsl");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, skvk::kFullscreenGlsl, "main", "smoothie.glsl.vert");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, "#version 450 core\n" + snippet + kGlsl, "main",
                                   "smoothie.glsl.frag");
    } else {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_HLSL_DIR) + "/smoothie.hlsl");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, snippet + skvk::kFullscreenHlsl + kHlsl, "vs_main", "smoothie.hlsl.vert");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, snippet + skvk::kFullscreenHlsl + kHlsl, "ps_main", "smoothie.hlsl.frag");
        entries[0] = "vs_main";
        entries[1] = "ps_main";
    }
    std::mt19937 rng(2003);
    std::uniform_real_distribution<float> U01(0.f, 1.f), U(-1.f, 1.f);
    std::vector<float> z(kSize * kSize), sm(2 * kSize * kSize);
    for (int t = 0; t < kSize * kSize; ++t) {
        z[std::size_t(t)] = 2.f + 8.f * U01(rng);
        const bool smoothie = U01(rng) < 0.5f;
        sm[2 * std::size_t(t)] = smoothie ? 1.f + (z[std::size_t(t)] - 1.f) * U01(rng) : 1e30f;
        sm[2 * std::size_t(t) + 1] = smoothie ? U01(rng) : 1.f;
    }
    skvk::Image& zmap = scope.own<skvk::Image>();
    skvk::Image& smap = scope.own<skvk::Image>();
    const VkImageUsageFlags up = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    REQUIRE(skvk::make_image(ctx, kSize, kSize, 1, VK_FORMAT_R32_SFLOAT, up, zmap));
    REQUIRE(skvk::make_image(ctx, kSize, kSize, 1, VK_FORMAT_R32G32_SFLOAT, up, smap));
    const VkImageLayout read = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    REQUIRE(skvk::upload_image(ctx, zmap, z, read));
    REQUIRE(skvk::upload_image(ctx, smap, sm, read));

    constexpr std::uint32_t M = 1024;
    struct Lookup {
        glm::vec2 uv, g;
        float r, bias;
    };
    std::vector<Lookup> pts;
    for (std::uint32_t i = 0; i < M; ++i) {
        Lookup l{{0.02f + 0.96f * U01(rng), 0.02f + 0.96f * U01(rng)}, {0.f, 0.f}, 1.f + 11.f * U01(rng), 0.f};
        if (i % 2) l.g = {3.f * U(rng), 3.f * U(rng)};
        l.bias = 1e-3f * l.r;
        pts.push_back(l);
    }
    skvk::Buffer& ssbo = scope.own<skvk::Buffer>();
    REQUIRE(skvk::make_buffer(ctx, M * 2 * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, ssbo));
    auto* dst = static_cast<glm::vec4*>(ssbo.mapped);
    for (std::uint32_t i = 0; i < M; ++i) {
        dst[2 * i] = glm::vec4(pts[i].uv, pts[i].r, pts[i].bias);
        dst[2 * i + 1] = glm::vec4(pts[i].g, 0.f, 0.f);
    }
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

    std::size_t off = 0, partial = 0, bad = 0;
    double max_err = 0;
    for (std::uint32_t i = 0; i < M; ++i) {
        if (!(gpu[i] >= 0.f && gpu[i] <= 1.f)) ++bad;
        if (gpu[i] > 0.01f && gpu[i] < 0.99f) ++partial;
        const double cpu = cpu_visibility(z, sm, pts[i].uv, pts[i].r, pts[i].g, pts[i].bias);
        const double e = std::abs(double(gpu[i]) - cpu);
        max_err = std::max(max_err, e);
        off += e > 1e-4;
    }
    MESSAGE((lang == Source::Glsl ? "GLSL" : "HLSL") << ": " << partial << " partial lookups, " << off << " of " << M
                                                    << " differ from the CPU by > 1e-4 (max " << max_err << ")");
    CHECK(bad == 0);
    CHECK(partial > 100);
    CHECK(off <= M / 200);
    CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());
}


// ------------------------------------------------------------------ the three passes end to end
// tests/gl/test_gl_smoothie.cpp (a) and (b) on Vulkan: the card over a floor, the linear map (pass 1),
// the MIN-blended smoothie buffer (pass 2, VK_BLEND_OP_MIN) and the final lookup (pass 3), all drawn
// with the same unflipped viewport (Vulkan NDC y = -1 is row 0, so uv = ndc * 0.5 + 0.5 addresses the
// maps' rows as drawn, and frag_coord / size * 2 - 1 is the fragment's NDC, as the snippet assumes).
// The matrices are the GL ones: every depth here lies in (0, 1] of GL NDC, so Vulkan's [0, w] clip
// keeps them all and LESS orders them the same.
const char* kPassesGlslCommon = R"(
layout(set = 0, binding = 0, std140) uniform Params { mat4 vp; mat4 view; mat4 cam; vec4 p; } u;  // p: size, remap, bias (pass 3) or y mirror (pass 2)
layout(set = 0, binding = 1) uniform sampler2D u_sm;
layout(set = 0, binding = 2) uniform sampler2D u_sb;
)";
const char* kDepthVsGlsl = R"(
layout(location = 0) in vec3 a_p;
layout(location = 0) out vec3 v_world;
void main() { v_world = a_p; gl_Position = u.vp * vec4(a_p, 1.0); }
)";
const char* kDepthFsGlsl = R"(
layout(location = 0) in vec3 v_world;
layout(location = 0) out float o_depth;
void main() { o_depth = sk_smoothie_linear_depth(u.view, v_world); }
)";
const char* kSmoothieVsGlsl = R"(
layout(location = 0) in vec3 a_position;
layout(location = 1) in float a_alpha;
layout(location = 2) in vec3 a_silhouette;
layout(location = 3) in float a_inv_t;
layout(location = 5) in float a_corner;
layout(location = 0) noperspective out float v_alpha;
layout(location = 1) smooth out float v_depth;
layout(location = 2) flat out vec2 v_sil;
layout(location = 3) flat out float v_inv_t;
layout(location = 4) flat out float v_corner;
void main() {
    vec4 clip;
    sk_smoothie_vertex(u.vp, u.view, a_position, a_silhouette, clip, v_depth, v_sil);
    gl_Position = clip;
    v_alpha = a_alpha;
    v_inv_t = a_inv_t;
    v_corner = a_corner;
}
)";
const char* kSmoothieFsGlsl = R"(
layout(location = 0) noperspective in float v_alpha;
layout(location = 1) smooth in float v_depth;
layout(location = 2) flat in vec2 v_sil;
layout(location = 3) flat in float v_inv_t;
layout(location = 4) flat in float v_corner;
layout(location = 0) out vec2 o;
void main() {
    if (sk_smoothie_hidden(u_sm, gl_FragCoord.xy, v_depth, 0.01)) discard;
    vec2 fc = u.p.w > 0.5 ? vec2(gl_FragCoord.x, u.p.y - gl_FragCoord.y) : gl_FragCoord.xy;  // y-flipped viewport
    vec2 s = sk_smoothie_fragment(fc, u.p.xy, v_alpha, v_sil, v_inv_t, v_corner, v_depth);
    if (u.p.z > 0.5) s.y = sk_smoothie_remap(s.y, v_depth, sk_smoothie_shadow_depth_at(u_sm, gl_FragCoord.xy));
    o = s;
}
)";
const char* kLookupVsGlsl = R"(
layout(location = 0) in vec3 a_p;
layout(location = 0) out vec3 v_world;
void main() { v_world = a_p; gl_Position = u.cam * vec4(a_p, 1.0); }
)";
const char* kLookupFsGlsl = R"(
layout(location = 0) in vec3 v_world;
layout(location = 0) out float o_v;
void main() {
    vec4 c = u.vp * vec4(v_world, 1.0);
    vec2 uv = c.xy / c.w * 0.5 + 0.5;
    float r = sk_smoothie_linear_depth(u.view, v_world);
    vec2 g = sk_smoothie_depth_gradient(dFdx(uv), dFdy(uv), dFdx(r), dFdy(r));
    o_v = sk_smoothie_visibility(u_sm, u_sb, uv, r, g, u.p.w, u.p.z > 0.5);
}
)";
// (b)'s independent hard lookup (no snippet): the same 4 texels, receiver plane and bias, 0/1 per texel.
const char* kHardFsGlsl = R"(
layout(location = 0) in vec3 v_world;
layout(location = 0) out float o_v;
void main() {
    vec4 c = u.vp * vec4(v_world, 1.0);
    vec2 uv = c.xy / c.w * 0.5 + 0.5;
    float r = -(u.view * vec4(v_world, 1.0)).z;
    vec2 dx = dFdx(uv), dy = dFdy(uv);
    float rx = dFdx(r), ry = dFdy(r);
    float det = dx.x * dy.y - dx.y * dy.x;
    vec2 g = abs(det) < 1e-20 ? vec2(0.0) : vec2(rx * dy.y - ry * dx.y, ry * dx.x - rx * dy.x) / det;
    if (!(r > 0.0) || any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) { o_v = 1.0; return; }
    ivec2 size = textureSize(u_sm, 0);
    vec2 st = uv * vec2(size) - 0.5;
    vec2 base = floor(st);
    vec2 f = st - base;
    float v[4];
    for (int k = 0; k < 4; ++k) {
        ivec2 texel = clamp(ivec2(base) + ivec2(k & 1, k >> 1), ivec2(0), size - 1);
        float r_tap = r + dot(g, (vec2(texel) + 0.5) / vec2(size) - uv);
        v[k] = r_tap > texelFetch(u_sm, texel, 0).r + u.p.w ? 0.0 : 1.0;
    }
    o_v = mix(mix(v[0], v[1], f.x), mix(v[2], v[3], f.x), f.y);
}
)";
const char* kPassesHlsl = R"(
struct Params { column_major float4x4 vp; column_major float4x4 view; column_major float4x4 cam; float4 p; };
[[vk::binding(0, 0)]] ConstantBuffer<Params> u;
[[vk::binding(1, 0)]] Texture2D<float> u_sm;
[[vk::binding(2, 0)]] Texture2D<float2> u_sb;
struct WorldV {
    float4 position : SV_Position;
    [[vk::location(0)]] float3 world : TEXCOORD0;
};
WorldV depth_vs([[vk::location(0)]] float3 p : POSITION) {
    WorldV o;
    o.world = p;
    o.position = mul(u.vp, float4(p, 1.0));
    return o;
}
float depth_ps(WorldV i) : SV_Target0 { return sk_smoothie_linear_depth(u.view, i.world); }
struct SmoothieV {
    float4 position : SV_Position;
    [[vk::location(0)]] noperspective float alpha : TEXCOORD0;
    [[vk::location(1)]] float depth : TEXCOORD1;
    [[vk::location(2)]] nointerpolation float2 sil : TEXCOORD2;
    [[vk::location(3)]] nointerpolation float inv_t : TEXCOORD3;
    [[vk::location(4)]] nointerpolation float corner : TEXCOORD4;
};
SmoothieV smoothie_vs([[vk::location(0)]] float3 position : POSITION, [[vk::location(1)]] float alpha : ALPHA,
                      [[vk::location(2)]] float3 sil : SILHOUETTE, [[vk::location(3)]] float inv_t : INV_T,
                      [[vk::location(5)]] float corner : CORNER) {
    SmoothieV o;
    float4 clip;
    sk_smoothie_vertex(u.vp, u.view, position, sil, clip, o.depth, o.sil);
    o.position = clip;
    o.alpha = alpha;
    o.inv_t = inv_t;
    o.corner = corner;
    return o;
}
float2 smoothie_ps(SmoothieV i) : SV_Target0 {
    if (sk_smoothie_hidden(u_sm, i.position.xy, i.depth, 0.01)) discard;
    float2 fc = u.p.w > 0.5 ? float2(i.position.x, u.p.y - i.position.y) : i.position.xy;  // y-flipped viewport
    float2 s = sk_smoothie_fragment(fc, u.p.xy, i.alpha, i.sil, i.inv_t, i.corner, i.depth);
    if (u.p.z > 0.5) s.y = sk_smoothie_remap(s.y, i.depth, sk_smoothie_shadow_depth_at(u_sm, i.position.xy));
    return s;
}
WorldV lookup_vs([[vk::location(0)]] float3 p : POSITION) {
    WorldV o;
    o.world = p;
    o.position = mul(u.cam, float4(p, 1.0));
    return o;
}
float lookup_ps(WorldV i) : SV_Target0 {
    float4 c = mul(u.vp, float4(i.world, 1.0));
    float2 uv = c.xy / c.w * 0.5 + 0.5;
    float r = sk_smoothie_linear_depth(u.view, i.world);
    float2 g = sk_smoothie_depth_gradient(ddx(uv), ddy(uv), ddx(r), ddy(r));
    return sk_smoothie_visibility(u_sm, u_sb, uv, r, g, u.p.w, u.p.z > 0.5);
}
float hard_ps(WorldV i) : SV_Target0 {
    float4 c = mul(u.vp, float4(i.world, 1.0));
    float2 uv = c.xy / c.w * 0.5 + 0.5;
    float r = -mul(u.view, float4(i.world, 1.0)).z;
    float2 dx = ddx(uv), dy = ddy(uv);
    float rx = ddx(r), ry = ddy(r);
    float det = dx.x * dy.y - dx.y * dy.x;
    float2 g = abs(det) < 1e-20 ? float2(0.0, 0.0) : float2(rx * dy.y - ry * dx.y, ry * dx.x - rx * dy.x) / det;
    if (!(r > 0.0) || any(uv < 0.0) || any(uv > 1.0)) return 1.0;
    uint w, h;
    u_sm.GetDimensions(w, h);
    int2 size = int2(w, h);
    float2 st = uv * float2(size) - 0.5;
    float2 base = floor(st);
    float2 f = st - base;
    float v[4];
    [unroll] for (int k = 0; k < 4; ++k) {
        int2 texel = clamp(int2(base) + int2(k & 1, k >> 1), int2(0, 0), size - 1);
        float r_tap = r + dot(g, (float2(texel) + 0.5) / float2(size) - uv);
        v[k] = r_tap > u_sm.Load(int3(texel, 0)) + u.p.w ? 0.0 : 1.0;
    }
    return lerp(lerp(v[0], v[1], f.x), lerp(v[2], v[3], f.x), f.y);
}
)";

struct PassParams {
    glm::mat4 vp, view, cam;
    glm::vec4 p;  // buffer size (x, y), remap flag, bias (pass 3) or y mirror of the fragment's NDC (pass 2)
};

// The GL test's card scene (smoothie_reference.hpp): a square card (half size h at light-view depth b)
// over a floor at depth rf; the light at the origin looking down -z.
using CardScene = smoothie_ref::Card;

// Pipelines of the four passes (one language), the shared descriptor set (params, sm, sb) and the
// card scene's vertex buffer; the maps are made per run (their size varies).
struct CardPasses {
    skvk::Context& ctx;
    Source lang;
    skvk::Scope scope;  ///< everything below; declared first, so destroyed last
    skvk::Buffer& ubo = scope.own<skvk::Buffer>();
    skvk::Buffer& vb = scope.own<skvk::Buffer>();
    skvk::DescriptorSet& ds = scope.own<skvk::DescriptorSet>();
    VkSampler nearest = VK_NULL_HANDLE;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VkRenderPass depth_rp = VK_NULL_HANDLE, smoothie_rp = VK_NULL_HANDLE, lookup_rp = VK_NULL_HANDLE;  ///< lookup_rp is depth_rp
    VkPipeline depth = VK_NULL_HANDLE, smoothie = VK_NULL_HANDLE, lookup = VK_NULL_HANDLE, hard = VK_NULL_HANDLE;

    CardPasses(skvk::Context& c, Source l, const CardScene& cs) : ctx(c), lang(l), scope(c) {
        const VkShaderStageFlags both = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
        const VkDescriptorType tex = skvk::texture_type(lang);
        REQUIRE(skvk::make_descriptor_set(ctx, {{0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, both}, {1, tex, VK_SHADER_STAGE_FRAGMENT_BIT},
                                                {2, tex, VK_SHADER_STAGE_FRAGMENT_BIT}}, ds));
        REQUIRE(skvk::make_buffer(ctx, sizeof(PassParams), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, ubo));
        skvk::write_buffer(ctx, ds, 0, ubo);
        REQUIRE(skvk::make_buffer(ctx, cs.tris.size() * sizeof(glm::vec3), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, vb));
        std::memcpy(vb.mapped, cs.tris.data(), cs.tris.size() * sizeof(glm::vec3));
        nearest = scope.keep(skvk::make_sampler(ctx, VK_FILTER_NEAREST, VK_COMPARE_OP_NEVER), vkDestroySampler);
        layout = scope.keep(skvk::make_pipeline_layout(ctx, &ds), vkDestroyPipelineLayout);
        depth_rp = scope.keep(skvk::make_render_pass(ctx, {VK_FORMAT_R32_SFLOAT}, VK_FORMAT_D32_SFLOAT,
                                          VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL), vkDestroyRenderPass);
        smoothie_rp = scope.keep(skvk::make_render_pass(ctx, {VK_FORMAT_R32G32_SFLOAT}, VK_FORMAT_UNDEFINED, VK_IMAGE_LAYOUT_UNDEFINED), vkDestroyRenderPass);
        lookup_rp = depth_rp;

        const VkShaderStageFlagBits V = VK_SHADER_STAGE_VERTEX_BIT, F = VK_SHADER_STAGE_FRAGMENT_BIT;
        struct Stage {
            std::vector<std::uint32_t> spv;
            const char* entry;
        };
        Stage s[7];  // depth vs/fs, smoothie vs/fs, lookup vs/fs, hard fs
        if (lang == Source::Glsl) {
            const std::string h = "#version 450 core\n" + skvk::read_text(std::string(SHADOWKIT_GLSL_DIR) + "/smoothie.glsl") +
                                  kPassesGlslCommon;
            const char* src[7] = {kDepthVsGlsl, kDepthFsGlsl, kSmoothieVsGlsl, kSmoothieFsGlsl, kLookupVsGlsl, kLookupFsGlsl, kHardFsGlsl};
            const char* names[7] = {"smoothie.glsl.depth.vert", "smoothie.glsl.depth.frag", "smoothie.glsl.pass2.vert",
                                    "smoothie.glsl.pass2.frag", "smoothie.glsl.lookup.vert", "smoothie.glsl.lookup.frag",
                                    "smoothie.glsl.hard.frag"};
            for (int i = 0; i < 7; ++i)
                s[i] = {skvk::compile_checked(lang, (i % 2 == 0 && i < 6) ? V : F, h + src[i], "main", names[i]), "main"};
        } else {
            const std::string h = skvk::read_text(std::string(SHADOWKIT_HLSL_DIR) + "/smoothie.hlsl") + kPassesHlsl;
            const char* entries[7] = {"depth_vs", "depth_ps", "smoothie_vs", "smoothie_ps", "lookup_vs", "lookup_ps", "hard_ps"};
            for (int i = 0; i < 7; ++i)
                s[i] = {skvk::compile_checked(lang, (i % 2 == 0 && i < 6) ? V : F, h, entries[i],
                                              std::string("smoothie.hlsl.") + entries[i]),
                        entries[i]};
        }
        skvk::PipelineDesc pd;
        pd.vertex_stride = sizeof(glm::vec3);
        pd.attributes = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0}};
        pd.color_count = 1;
        pd.vs = s[0].spv;
        pd.vs_entry = s[0].entry;
        pd.fs = s[1].spv;
        pd.fs_entry = s[1].entry;
        depth = scope.keep(skvk::make_pipeline_checked(ctx, pd, layout, depth_rp), vkDestroyPipeline);
        pd.vs = s[4].spv;
        pd.vs_entry = s[4].entry;
        pd.fs = s[5].spv;
        pd.fs_entry = s[5].entry;
        lookup = scope.keep(skvk::make_pipeline_checked(ctx, pd, layout, lookup_rp), vkDestroyPipeline);
        pd.fs = s[6].spv;
        pd.fs_entry = s[6].entry;
        hard = scope.keep(skvk::make_pipeline_checked(ctx, pd, layout, lookup_rp), vkDestroyPipeline);
        // pass 2: SmoothieVertex (locations 0, 1, 2, 3, 5), no depth test, no culling, MIN blending
        pd.vs = s[2].spv;
        pd.vs_entry = s[2].entry;
        pd.fs = s[3].spv;
        pd.fs_entry = s[3].entry;
        pd.vertex_stride = sizeof(shadowkit::SmoothieVertex);
        pd.attributes = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0}, {1, 0, VK_FORMAT_R32_SFLOAT, 12},
                         {2, 0, VK_FORMAT_R32G32B32_SFLOAT, 16}, {3, 0, VK_FORMAT_R32_SFLOAT, 28}, {5, 0, VK_FORMAT_R32_SFLOAT, 40}};
        pd.depth_test = pd.depth_write = false;
        pd.blend = true;
        pd.blend_op = VK_BLEND_OP_MIN;
        smoothie = scope.keep(skvk::make_pipeline_checked(ctx, pd, layout, smoothie_rp), vkDestroyPipeline);
    }
    void set_params(const PassParams& p) { std::memcpy(ubo.mapped, &p, sizeof p); }
};

// Passes 1 and 2: linear map sm (R32F) and smoothie buffer sb (RG32F), N x N, both left in
// SHADER_READ_ONLY_OPTIMAL and written to the descriptor set.
void render_buffers(CardPasses& P, const CardScene& cs, std::uint32_t N, float t, bool remap_here, skvk::Image& sm,
                    skvk::Image& sb, shadowkit::SmoothieResult& res, bool flip = false, bool mirror = false) {
    skvk::Context& ctx = P.ctx;
    skvk::Scope scope(ctx);
    const VkImageUsageFlags rt = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
    skvk::Image& zbuf = scope.own<skvk::Image>();
    REQUIRE(skvk::make_image(ctx, N, N, 1, VK_FORMAT_R32_SFLOAT, rt, sm));
    REQUIRE(skvk::make_image(ctx, N, N, 1, VK_FORMAT_R32G32_SFLOAT, rt, sb));
    REQUIRE(skvk::make_image(ctx, N, N, 1, VK_FORMAT_D32_SFLOAT, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, zbuf));
    const VkImageLayout read = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    const VkSampler s = P.lang == Source::Glsl ? P.nearest : VK_NULL_HANDLE;
    const VkDescriptorType tex = skvk::texture_type(P.lang);
    skvk::write_image(ctx, P.ds, 1, tex, sm.view, s, read);
    skvk::write_image(ctx, P.ds, 2, tex, sb.view, s, read);
    P.set_params({cs.vp, cs.view, cs.vp, glm::vec4(float(N), float(N), remap_here ? 1.f : 0.f, mirror ? 1.f : 0.f)});
    const auto sv = cs.smoothies(t, res);
    skvk::Buffer& svb = scope.own<skvk::Buffer>();  // the smoothies' vertices, this call's
    if (!sv.empty()) {
        REQUIRE(skvk::make_buffer(ctx, sv.size() * sizeof(shadowkit::SmoothieVertex), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, svb));
        std::memcpy(svb.mapped, sv.data(), sv.size() * sizeof(shadowkit::SmoothieVertex));
    }
    VkFramebuffer fb1 = scope.keep(skvk::make_framebuffer(ctx, P.depth_rp, {sm.view, zbuf.view}, N, N), vkDestroyFramebuffer);
    VkFramebuffer fb2 = scope.keep(skvk::make_framebuffer(ctx, P.smoothie_rp, {sb.view}, N, N), vkDestroyFramebuffer);
    VkCommandBuffer cmd = skvk::begin_commands(ctx);
    VkClearValue big{}, far{}, sclear{};
    big.color.float32[0] = 1e30f;
    far.depthStencil = {1.f, 0};
    sclear.color.float32[0] = 1e30f;
    sclear.color.float32[1] = 1.f;
    skvk::draw_pass(cmd, P.depth_rp, fb1, N, N, {big, far}, P.depth, P.layout, &P.ds.set, nullptr, P.vb.buffer, 12, flip);
    skvk::transition(cmd, sm, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, read);
    skvk::draw_pass(cmd, P.smoothie_rp, fb2, N, N, {sclear}, P.smoothie, P.layout, &P.ds.set, nullptr,
                    sv.empty() ? VK_NULL_HANDLE : svb.buffer, static_cast<std::uint32_t>(sv.size()), flip);
    skvk::transition(cmd, sb, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, read);
    REQUIRE(skvk::submit_and_wait(ctx, cmd));
}

// Final pass (P.lookup or P.hard) over the card scene's triangles (or the floor's only) seen through cam.
std::vector<float> render_lookup(CardPasses& P, const CardScene& cs, VkPipeline pipe, const glm::mat4& cam, std::uint32_t w,
                                 std::uint32_t h, bool floor_only, bool remapped, float bias) {
    skvk::Context& ctx = P.ctx;
    skvk::Scope scope(ctx);
    skvk::Image& out = scope.own<skvk::Image>();
    skvk::Image& zbuf = scope.own<skvk::Image>();
    REQUIRE(skvk::make_image(ctx, w, h, 1, VK_FORMAT_R32_SFLOAT, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, out));
    REQUIRE(skvk::make_image(ctx, w, h, 1, VK_FORMAT_D32_SFLOAT, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, zbuf));
    P.set_params({cs.vp, cs.view, cam, glm::vec4(0.f, 0.f, remapped ? 1.f : 0.f, bias)});
    VkFramebuffer fb = scope.keep(skvk::make_framebuffer(ctx, P.lookup_rp, {out.view, zbuf.view}, w, h), vkDestroyFramebuffer);
    VkCommandBuffer cmd = skvk::begin_commands(ctx);
    VkClearValue neg{}, far{};
    neg.color.float32[0] = -1.f;
    far.depthStencil = {1.f, 0};
    VkRenderPassBeginInfo bi{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    const VkClearValue clears[2] = {neg, far};
    bi.renderPass = P.lookup_rp;
    bi.framebuffer = fb;
    bi.renderArea = {{0, 0}, {w, h}};
    bi.clearValueCount = 2;
    bi.pClearValues = clears;
    vkCmdBeginRenderPass(cmd, &bi, VK_SUBPASS_CONTENTS_INLINE);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipe);
    const VkViewport vp = skvk::viewport(w, h, false);
    const VkRect2D sc{{0, 0}, {w, h}};
    vkCmdSetViewport(cmd, 0, 1, &vp);
    vkCmdSetScissor(cmd, 0, 1, &sc);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, P.layout, 0, 1, &P.ds.set, 0, nullptr);
    const VkDeviceSize offset = 0;
    vkCmdBindVertexBuffers(cmd, 0, 1, &P.vb.buffer, &offset);
    vkCmdDraw(cmd, floor_only ? 6u : 12u, 1, floor_only ? 6u : 0u, 0);
    vkCmdEndRenderPass(cmd);
    REQUIRE(skvk::submit_and_wait(ctx, cmd));
    std::vector<float> v = skvk::read_image(ctx, out, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 1);
    return v;
}

// (a): at every texel of the floor seen from the light, the visibility the CPU predicts from the
// card's closed-form light-NDC distance (smoothie depth b, alpha = d / t within t of the card) and
// smoothie.hpp's remap / falloff / tap rule; and the smoothie buffer's alpha where a smoothie lies.
struct CardStats {
    double max_err = 0.0, max_alpha_err = 0.0;
    std::size_t compared = 0, penumbra = 0, umbra = 0, alphas = 0;
};

// Passes 1 to 3 on the card for (t, remap_here), every floor texel against the CPU prediction from
// the card's closed-form light-NDC distance (texels within 1.5 of the outline left out: rasterization).
CardStats card_run(CardPasses& P, const CardScene& cs, std::uint32_t N, float t, bool remap_here, bool flip, bool mirror) {
    const float bias = 0.01f;
    skvk::Scope scope(P.ctx);
    skvk::Image& sm = scope.own<skvk::Image>();
    skvk::Image& sb = scope.own<skvk::Image>();
    shadowkit::SmoothieResult res;
    render_buffers(P, cs, N, t, remap_here, sm, sb, res, flip, mirror);
    CHECK(res.edge_quads == 4);
    CHECK(res.corners == 4);
    const std::vector<float> sbuf = skvk::read_image(P.ctx, sb, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, 2);
    const std::vector<float> vis = render_lookup(P, cs, P.lookup, cs.vp, N, N, true, remap_here, bias);
    REQUIRE(vis.size() == std::size_t(N) * N);
    CardStats st;
    for (std::uint32_t y = 0; y < N; ++y)
        for (std::uint32_t x = 0; x < N; ++x) {
            const smoothie_ref::CardTexel ref = smoothie_ref::card_texel(cs, int(N), int(x), int(y), t, remap_here, bias);
            if (ref.skip) continue;
            const std::size_t k = std::size_t(y) * N + x;
            if (ref.alpha_known) {
                st.max_alpha_err = std::max(st.max_alpha_err, std::abs(double(sbuf[2 * k + 1]) - double(ref.a_expect)));
                CHECK(std::abs(sbuf[2 * k] - cs.b) < 1e-4f);
                ++st.alphas;
            }
            const float expect = ref.expect;
            st.max_err = std::max(st.max_err, std::abs(double(vis[k]) - double(expect)));
            ++st.compared;
            if (expect > 0.f && expect < 1.f) ++st.penumbra;
            if (expect == 0.f) ++st.umbra;
        }
    return st;
}

void run_passes(Source lang) {
    skvk::Context& ctx = skvk::vk_test_context();
    const std::size_t before = skvk::message_count();
    const CardScene cs;
    CardPasses P(ctx, lang, cs);
    const std::uint32_t N = 512;  // the GL test's size (at 256, t = 0.05 leaves 636 penumbra texels)
    const std::string name = lang == Source::Glsl ? "GLSL" : "HLSL";
    for (float t : {0.05f, 0.1f, 0.2f})
        for (bool remap_here : {false, true}) {
            CAPTURE(t);
            CAPTURE(remap_here);
            const CardStats st = card_run(P, cs, N, t, remap_here, false, false);
            MESSAGE(name << " t = " << t << std::string(remap_here ? " (remap in the smoothie pass)" : " (remap in the final pass)") << ": "
                         << st.compared << " texels, " << st.penumbra << " penumbra, " << st.umbra << " umbra; max |V - V_cpu| = "
                         << st.max_err << ", smoothie-buffer max |alpha - expected| = " << st.max_alpha_err << " over " << st.alphas);
            CHECK(st.compared > std::size_t(N) * N * 9 / 10);
            CHECK(st.penumbra > 1000);
            CHECK(st.umbra > 1000);
            CHECK(st.alphas > 1000);
            CHECK(st.max_err <= 1e-4);
            CHECK(st.max_alpha_err <= 1e-4);
        }
    // Passes 1 and 2 drawn with the negative-height viewport (the card is symmetric in y, so the
    // mirrored rows the lookup reads hold the same values). sk_smoothie_frag_ndc takes frag_coord /
    // size * 2 - 1 as the NDC, which the flip mirrors in y: the corners' alpha (|p - v| / t) comes out
    // wrong (the control); passing (x, size.y - y) to sk_smoothie_fragment, as the snippets' headers
    // say, restores it.
    const CardStats flipped = card_run(P, cs, N, 0.1f, false, true, false);
    const CardStats mirrored = card_run(P, cs, N, 0.1f, false, true, true);
    MESSAGE(name << " smoothie buffer drawn y-flipped (t = 0.1): max |alpha - expected| = " << flipped.max_alpha_err
                 << ", max |V - V_cpu| = " << flipped.max_err << " (control); with (x, size.y - y) passed to sk_smoothie_fragment: "
                 << mirrored.max_alpha_err << ", " << mirrored.max_err);
    CHECK(flipped.max_alpha_err > 0.1);
    CHECK(mirrored.max_alpha_err <= 1e-4);
    CHECK(mirrored.max_err <= 1e-4);
    CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());
}

// (b): t = 0 draws nothing in pass 2, and the final lookup equals an independent hard 2x2 lookup bit
// for bit, seen through an oblique camera (the bilinear weights and the receiver plane matter).
void run_hard(Source lang) {
    skvk::Context& ctx = skvk::vk_test_context();
    skvk::Scope scope(ctx);
    const std::size_t before = skvk::message_count();
    const CardScene cs;
    CardPasses P(ctx, lang, cs);
    skvk::Image& sm = scope.own<skvk::Image>();
    skvk::Image& sb = scope.own<skvk::Image>();
    shadowkit::SmoothieResult res;
    render_buffers(P, cs, 256, 0.f, false, sm, sb, res);
    CHECK(res.status == shadowkit::Status::Ok);
    CHECK(res.needed == 0);
    const std::uint32_t w = 320, h = 240;
    const glm::mat4 cam = smoothie_ref::oblique_camera(int(w), int(h));
    for (bool remapped : {false, true}) {
        const std::vector<float> v_smoothie = render_lookup(P, cs, P.lookup, cam, w, h, false, remapped, 0.01f);
        const std::vector<float> v_hard = render_lookup(P, cs, P.hard, cam, w, h, false, remapped, 0.01f);
        REQUIRE(v_hard.size() == v_smoothie.size());
        const auto [drawn, differ, fractional, dark] = smoothie_ref::tally_hard(v_smoothie, v_hard);
        MESSAGE(std::string(lang == Source::Glsl ? "GLSL" : "HLSL") << " t = 0" << std::string(remapped ? " (alpha_is_remapped)" : "") << ": " << drawn
                                                        << " pixels, " << differ << " differ, " << dark << " in shadow, "
                                                        << fractional << " filtered (0 < V < 1)");
        CHECK(drawn > std::size_t(w * h / 2));
        CHECK(dark > 1000);
        CHECK(fractional > 100);
        CHECK(differ == 0);
    }
    CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());
}

}  // namespace

TEST_CASE("smoothie.glsl on Vulkan: sk_smoothie_visibility equals four smoothie_visibility_tap filtered bilinearly") {
    run_smoothie(Source::Glsl);
}

TEST_CASE("HLSL smoothie.hlsl on Vulkan: sk_smoothie_visibility equals four smoothie_visibility_tap filtered bilinearly") {
    run_smoothie(Source::Hlsl);
}

TEST_CASE("smoothie.glsl on Vulkan: the three passes match the CPU prediction at every texel (GL test (a), |dV| <= 1e-4)") {
    run_passes(Source::Glsl);
}

TEST_CASE("HLSL smoothie.hlsl on Vulkan: the three passes match the CPU prediction at every texel (GL test (a), |dV| <= 1e-4)") {
    run_passes(Source::Hlsl);
}

TEST_CASE("smoothie.glsl on Vulkan: t = 0 is bit-identical to an independent hard 2x2 lookup (GL test (b))") {
    run_hard(Source::Glsl);
}

TEST_CASE("HLSL smoothie.hlsl on Vulkan: t = 0 is bit-identical to an independent hard 2x2 lookup (GL test (b))") {
    run_hard(Source::Hlsl);
}
