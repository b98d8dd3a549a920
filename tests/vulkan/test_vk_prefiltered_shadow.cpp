// glsl/prefiltered_shadow.glsl and hlsl/prefiltered_shadow.hlsl RUN on Vulkan: sk_prefilter_visibility
// for every method (VSM, ESM, EVSM2, EVSM4, MSM Hamburger and Hausdorff, MSM also quantized) on 2,048
// filtered moments each (the mean of prefilter_moments over one to three random depths, as a blur
// makes them) and random receiver depths, against the CPU mirror shadowkit::prefilter_visibility: at
// most 1% of the lookups may differ by more than 1e-3 (float solves near a root), every value in
// [0, 1]. Below, the GL test's moment pass, blur (fragment and compute), 4x MSAA resolve and soft
// lookup run as well. No validation message.
#include <doctest/doctest.h>

#include <shadowkit/prefiltered_shadow.hpp>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/packing.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "../prefiltered_reference.hpp"
#include "vk_harness.hpp"
#include "vk_passes.hpp"

namespace {

using skvk::Source;

const char* kGlsl = R"(
layout(set = 0, binding = 0, std430) readonly buffer Samples { vec4 s[]; };  // moments, (t, -, -, -)
layout(push_constant) uniform Case { vec4 params; int method; float moment_bias; int quantized; } k;
layout(location = 0) out float o_value;
void main() {
    int i = int(gl_FragCoord.x);
    o_value = sk_prefilter_visibility(s[2 * i], s[2 * i + 1].x, k.method, k.params, k.moment_bias, k.quantized != 0);
}
)";
const char* kHlsl = R"(
[[vk::binding(0, 0)]] StructuredBuffer<float4> s;
struct Case { float4 params; int method; float moment_bias; int quantized; };
[[vk::push_constant]] ConstantBuffer<Case> k;
float ps_main(float4 position : SV_Position) : SV_Target0 {
    int i = int(position.x);
    return sk_prefilter_visibility(s[2 * i], s[2 * i + 1].x, k.method, k.params, k.moment_bias, k.quantized != 0);
}
)";

struct CasePush {
    glm::vec4 params;
    std::int32_t method;
    float moment_bias;
    std::int32_t quantized;
};

void run_prefiltered(Source lang) {
    skvk::Context& ctx = skvk::vk_test_context();
    skvk::Scope scope(ctx);
    const std::size_t before = skvk::message_count();
    std::vector<std::uint32_t> vs, fs;
    const char* entries[2] = {"main", "main"};
    if (lang == Source::Glsl) {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_GLSL_DIR) + "/prefiltered_shadow.glsl");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, skvk::kFullscreenGlsl, "main", "prefiltered.glsl.vert");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, "#version 450 core\n" + snippet + kGlsl, "main",
                                   "prefiltered.glsl.frag");
    } else {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_HLSL_DIR) + "/prefiltered_shadow.hlsl");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, snippet + skvk::kFullscreenHlsl + kHlsl, "vs_main", "prefiltered.hlsl.vert");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, snippet + skvk::kFullscreenHlsl + kHlsl, "ps_main", "prefiltered.hlsl.frag");
        entries[0] = "vs_main";
        entries[1] = "ps_main";
    }
    constexpr std::uint32_t M = 2048;
    skvk::Buffer& ssbo = scope.own<skvk::Buffer>();
    REQUIRE(skvk::make_buffer(ctx, M * 2 * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, ssbo));
    skvk::DescriptorSet& ds = scope.own<skvk::DescriptorSet>();
    REQUIRE(skvk::make_descriptor_set(ctx, {{0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_FRAGMENT_BIT}}, ds));
    skvk::write_buffer(ctx, ds, 0, ssbo, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
    skvk::RowPass& row = scope.own<skvk::RowPass>();
    skvk::make_row_pass(ctx, vs, fs, entries[0], entries[1], ds, M, row, VK_FORMAT_R32_SFLOAT, 1, sizeof(CasePush));

    struct Method {
        const char* name;
        shadowkit::PrefilterMethod method;
        int code;
        glm::vec2 exponents;
        float min_variance, bleed, moment_bias;
        bool quantized;
    };
    const Method methods[] = {
        {"VSM", shadowkit::PrefilterMethod::Vsm, 0, {0.f, 0.f}, 1e-5f, 0.2f, 0.f, false},
        {"ESM", shadowkit::PrefilterMethod::Esm, 1, {40.f, 0.f}, 0.f, 0.f, 0.f, false},
        {"EVSM2", shadowkit::PrefilterMethod::Evsm2, 2, {20.f, 0.f}, 1e-4f, 0.1f, 0.f, false},
        {"EVSM4", shadowkit::PrefilterMethod::Evsm4, 3, {20.f, 10.f}, 1e-4f, 0.1f, 0.f, false},
        {"MSM", shadowkit::PrefilterMethod::Msm, 4, {0.f, 0.f}, 0.f, 0.f, 3e-5f, false},
        {"MSM quantized", shadowkit::PrefilterMethod::Msm, 4, {0.f, 0.f}, 0.f, 0.f, 6e-5f, true},
        {"MSM Hausdorff", shadowkit::PrefilterMethod::MsmHausdorff, 5, {0.f, 0.f}, 0.f, 0.f, 3e-5f, false},
    };
    std::mt19937 rng(2006);
    std::uniform_real_distribution<float> U01(0.f, 1.f);
    for (const Method& m : methods) {
        shadowkit::PrefilterUniforms u;
        u.status = shadowkit::Status::Ok;
        u.method = m.method;
        u.method_code = m.code;
        u.exponents = m.exponents;
        u.min_variance = m.min_variance;
        u.bleed_reduction = m.bleed;
        u.moment_bias = m.moment_bias;
        u.quantized = m.quantized;
        std::vector<glm::vec4> samples(2 * M);
        for (std::uint32_t i = 0; i < M; ++i) {
            const int n = 1 + int(rng() % 3);
            glm::vec4 sum(0.f);
            float wsum = 0.f;
            for (int j = 0; j < n; ++j) {
                const float w = 0.2f + U01(rng);
                sum += w * shadowkit::prefilter_moments(U01(rng), glm::vec2(0.f), u);
                wsum += w;
            }
            samples[2 * i] = sum / wsum;
            samples[2 * i + 1] = glm::vec4(U01(rng), 0.f, 0.f, 0.f);
        }
        std::memcpy(ssbo.mapped, samples.data(), samples.size() * sizeof(glm::vec4));
        const CasePush cp{u.params(), m.code, m.moment_bias, m.quantized ? 1 : 0};
        const std::vector<float> gpu = skvk::draw_row(ctx, row, ds, &cp);
        std::size_t off = 0, bad = 0, partial = 0;
        double max_err = 0;
        for (std::uint32_t i = 0; i < M; ++i) {
            if (!(gpu[i] >= 0.f && gpu[i] <= 1.f)) ++bad;
            const float cpu = shadowkit::prefilter_visibility(samples[2 * i], samples[2 * i + 1].x, u);
            partial += cpu > 0.01f && cpu < 0.99f;
            const double e = std::abs(double(gpu[i]) - double(cpu));
            max_err = std::max(max_err, e);
            off += e > 1e-3;
        }
        const std::string name = std::string(lang == Source::Glsl ? "GLSL " : "HLSL ") + m.name;
        INFO(name);
        MESSAGE(name << ": " << partial << " partial, " << off << " of " << M << " differ from prefilter_visibility by > 1e-3 (max "
                     << max_err << ")");
        CHECK(bad == 0);
        CHECK(partial > M / 20);
        CHECK(off <= M / 100);
        // the GL test's garbage texels: NaN, +-Inf, +-3e38 among the moments and the receiver depths;
        // always in [0, 1], and equal to prefilter_visibility (2e-3) at 99% of them
        const float specials[] = {NAN, INFINITY, -INFINITY, 3e38f, -3e38f, 0.0f, 1.0f, -1.0f};
        for (std::uint32_t i = 0; i < M; ++i) {
            for (int c = 0; c < 4; ++c) samples[2 * i][c] = rng() % 3u == 0 ? specials[rng() % 8u] : U01(rng) * 4.f - 2.f;
            samples[2 * i + 1].x = rng() % 5u == 0 ? specials[rng() % 8u] : U01(rng);
        }
        std::memcpy(ssbo.mapped, samples.data(), samples.size() * sizeof(glm::vec4));
        const std::vector<float> junk = skvk::draw_row(ctx, row, ds, &cp);
        std::size_t junk_bad = 0, junk_close = 0;
        for (std::uint32_t i = 0; i < M; ++i) {
            junk_bad += !(junk[i] >= 0.f && junk[i] <= 1.f);
            junk_close += std::abs(junk[i] - shadowkit::prefilter_visibility(samples[2 * i], samples[2 * i + 1].x, u)) <= 2e-3f;
        }
        MESSAGE(name << " on garbage texels: " << junk_bad << " outside [0, 1], " << junk_close << " of " << M
                     << " equal prefilter_visibility (2e-3)");
        CHECK(junk_bad == 0);
        CHECK(junk_close >= M * 99 / 100);
    }
    CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());
}

}  // namespace

TEST_CASE("prefiltered_shadow.glsl on Vulkan: sk_prefilter_visibility of every method equals prefilter_visibility") {
    run_prefiltered(Source::Glsl);
}

TEST_CASE("HLSL prefiltered_shadow.hlsl on Vulkan: sk_prefilter_visibility of every method equals prefilter_visibility") {
    run_prefiltered(Source::Hlsl);
}

// ---------------------------------------------------------------------------------------- the passes
// The passes of tests/gl/test_gl_prefiltered_shadow.cpp RUN on Vulkan with its scenes, CPU references
// and tolerances: (a) the moment pass of every method and format (each texel equals prefilter_moments
// of the t and dt the GPU computed, stored as prefilter_store says; fp16 EVSM4 overflows only above
// the header's exponent limit); (b) the separable blur (two fragment passes, and two compute passes
// with imageStore / RWTexture2D) equals a brute-force 2D convolution; (c) the lookups above, also on
// garbage texels; (d) the 4x MSAA resolve equals the mean of the samples' moments; (e) the blitted
// mip levels are 2x2 means; (g) the soft lookup on the mip chain equals prefilter_soft_visibility on
// the read-back levels and follows the area light's ray-cast penumbra. ((f), the report drivers, is
// GL-only.) Light projections are zero-to-one (glm::perspectiveRH_ZO): the window
// depth and the t of a texel are the same as GL's.
namespace {

using namespace shadowkit;

const char* kFullscreenHlsl = R"(
float4 vs_full(uint id : SV_VertexID) : SV_Position {
    float2 p = float2(float((id << 1) & 2), float(id & 2));
    return float4(p * 2.0 - 1.0, 0.0, 1.0);
}
)";

const char* kMomentVsGlsl = R"(#version 450 core
layout(location = 0) in vec3 a_position;
layout(push_constant) uniform Moment { mat4 proj; vec2 depth_scale_offset; vec2 exponents; int method; int quantized; } k;
layout(location = 0) out float v_light_distance;
void main() {
    v_light_distance = -a_position.z;
    gl_Position = k.proj * vec4(a_position, 1.0);
}
)";
const char* kMomentFsGlsl = R"(
layout(push_constant) uniform Moment { mat4 proj; vec2 depth_scale_offset; vec2 exponents; int method; int quantized; } k;
layout(location = 0) in float v_light_distance;
layout(location = 0) out vec4 o_moments;
layout(location = 1) out vec4 o_t;
void main() {
    float t = sk_prefilter_depth(v_light_distance, k.depth_scale_offset);
    vec2 dt = vec2(dFdx(t), dFdy(t));
    o_moments = sk_prefilter_moments(t, dt, k.method, k.exponents, k.quantized != 0);
    o_t = vec4(t, dt, 1.0);
}
)";
const char* kMomentHlsl = R"(
struct Moment { column_major float4x4 proj; float2 depth_scale_offset; float2 exponents; int method; int quantized; };
[[vk::push_constant]] ConstantBuffer<Moment> k;
struct MomentVaryings {
    float4 position : SV_Position;
    [[vk::location(0)]] float light_distance : TEXCOORD0;
};
MomentVaryings vs_moment([[vk::location(0)]] float3 position : POSITION) {
    MomentVaryings o;
    o.light_distance = -position.z;
    o.position = mul(k.proj, float4(position, 1.0));
    return o;
}
struct MomentTargets {
    [[vk::location(0)]] float4 moments : SV_Target0;
    [[vk::location(1)]] float4 t : SV_Target1;
};
MomentTargets ps_moment(MomentVaryings i) {
    MomentTargets o;
    float t = sk_prefilter_depth(i.light_distance, k.depth_scale_offset);
    float2 dt = float2(ddx(t), ddy(t));
    o.moments = sk_prefilter_moments(t, dt, k.method, k.exponents, k.quantized != 0);
    o.t = float4(t, dt, 1.0);
    return o;
}
)";

const char* kBlurGlsl = R"(
layout(set = 0, binding = 0) uniform sampler2D u_src;
layout(set = 0, binding = 1, std430) readonly buffer Weights { float w[]; };
layout(push_constant) uniform Blur { ivec2 dir; int radius; } k;
layout(location = 0) out vec4 o;
void main() {
    float weights[SK_PREFILTER_MAX_WEIGHTS];
    for (int i = 0; i < SK_PREFILTER_MAX_WEIGHTS; ++i) weights[i] = w[i];
    o = sk_prefilter_blur(u_src, ivec2(gl_FragCoord.xy), k.dir, k.radius, weights);
}
)";
const char* kBlurHlsl = R"(
[[vk::binding(0, 0)]] Texture2D<float4> u_src;
[[vk::binding(1, 0)]] StructuredBuffer<float> w;
struct Blur { int2 dir; int radius; };
[[vk::push_constant]] ConstantBuffer<Blur> k;
float4 ps_blur(float4 position : SV_Position) : SV_Target0 {
    float weights[SK_PREFILTER_MAX_WEIGHTS];
    for (int i = 0; i < SK_PREFILTER_MAX_WEIGHTS; ++i) weights[i] = w[i];
    return sk_prefilter_blur(u_src, int2(position.xy), k.dir, k.radius, weights);
}
)";

const char* kBlurComputeGlsl = R"(
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0) uniform sampler2D u_src;
layout(set = 0, binding = 1, std430) readonly buffer Weights { float w[]; };
layout(set = 0, binding = 2, rgba32f) writeonly uniform image2D u_dst;
layout(push_constant) uniform Blur { ivec2 dir; int radius; } k;
void main() {
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(px, imageSize(u_dst)))) return;
    float weights[SK_PREFILTER_MAX_WEIGHTS];
    for (int i = 0; i < SK_PREFILTER_MAX_WEIGHTS; ++i) weights[i] = w[i];
    imageStore(u_dst, px, sk_prefilter_blur(u_src, px, k.dir, k.radius, weights));
}
)";
const char* kBlurComputeHlsl = R"(
[[vk::binding(0, 0)]] Texture2D<float4> u_src;
[[vk::binding(1, 0)]] StructuredBuffer<float> w;
[[vk::binding(2, 0)]] [[vk::image_format("rgba32f")]] RWTexture2D<float4> u_dst;
struct Blur { int2 dir; int radius; };
[[vk::push_constant]] ConstantBuffer<Blur> k;
[numthreads(8, 8, 1)]
void cs_blur(uint3 id : SV_DispatchThreadID) {
    uint dw, dh;
    u_dst.GetDimensions(dw, dh);
    if (id.x >= dw || id.y >= dh) return;
    float weights[SK_PREFILTER_MAX_WEIGHTS];
    for (int i = 0; i < SK_PREFILTER_MAX_WEIGHTS; ++i) weights[i] = w[i];
    u_dst[int2(id.xy)] = sk_prefilter_blur(u_src, int2(id.xy), k.dir, k.radius, weights);
}
)";

const char* kResolveGlsl = R"(
layout(set = 0, binding = 0) uniform sampler2DMS u_ms;
layout(push_constant) uniform Resolve { vec4 window_map; vec2 exponents; int method; int quantized; } k;
layout(location = 0) out vec4 o_moments;
layout(location = 1) out vec4 o_samples;
void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    o_moments = sk_prefilter_resolve(u_ms, px, 4, k.window_map, k.method, k.exponents, k.quantized != 0);
    o_samples = vec4(texelFetch(u_ms, px, 0).r, texelFetch(u_ms, px, 1).r, texelFetch(u_ms, px, 2).r, texelFetch(u_ms, px, 3).r);
}
)";
const char* kResolveHlsl = R"(
[[vk::binding(0, 0)]] Texture2DMS<float> u_ms;
struct Resolve { float4 window_map; float2 exponents; int method; int quantized; };
[[vk::push_constant]] ConstantBuffer<Resolve> k;
struct ResolveTargets {
    [[vk::location(0)]] float4 moments : SV_Target0;
    [[vk::location(1)]] float4 samples : SV_Target1;
};
ResolveTargets ps_resolve(float4 position : SV_Position) {
    int2 px = int2(position.xy);
    ResolveTargets o;
    o.moments = sk_prefilter_resolve(u_ms, px, 4, k.window_map, k.method, k.exponents, k.quantized != 0);
    o.samples = float4(u_ms.Load(px, 0), u_ms.Load(px, 1), u_ms.Load(px, 2), u_ms.Load(px, 3));
    return o;
}
)";

const char* kSoftGlsl = R"(
layout(set = 0, binding = 0) uniform sampler2D u_m;
layout(set = 0, binding = 2, std430) readonly buffer Receivers { vec4 q[]; };  // (u, v, t, 0)
layout(push_constant) uniform Soft { vec4 params; vec4 soft; int method; float moment_bias; int quantized; int width; } k;
layout(location = 0) out float o;
void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec4 r = q[px.y * k.width + px.x];
    o = sk_prefilter_soft_visibility(u_m, r.xy, r.z, k.method, k.params, k.moment_bias, k.quantized != 0, k.soft, vec2(0.0));
}
)";
const char* kSoftHlsl = R"(
[[vk::binding(0, 0)]] Texture2D<float4> u_m;
[[vk::binding(1, 0)]] SamplerState u_trilinear;
[[vk::binding(2, 0)]] StructuredBuffer<float4> q;  // (u, v, t, 0)
struct Soft { float4 params; float4 soft; int method; float moment_bias; int quantized; int width; };
[[vk::push_constant]] ConstantBuffer<Soft> k;
float ps_soft(float4 position : SV_Position) : SV_Target0 {
    int2 px = int2(position.xy);
    float4 r = q[px.y * k.width + px.x];
    return sk_prefilter_soft_visibility(u_m, u_trilinear, r.xy, r.z, k.method, k.params, k.moment_bias, k.quantized != 0, k.soft,
                                        float2(0.0, 0.0));
}
)";

struct MomentPush {
    glm::mat4 proj;
    glm::vec2 depth_scale_offset, exponents;
    std::int32_t method, quantized;
};
struct BlurPush {
    glm::ivec2 dir;
    std::int32_t radius;
};
struct ResolvePush {
    glm::vec4 window_map;
    glm::vec2 exponents;
    std::int32_t method, quantized;
};
struct SoftPush {
    glm::vec4 params, soft;
    std::int32_t method;
    float moment_bias;
    std::int32_t quantized, width;
};

struct Shaders {
    std::vector<std::uint32_t> vs, fs;
    const char* vs_entry = "main";
    const char* fs_entry = "main";
};

// GLSL: glsl_vs alone, "#version" + the snippet + glsl_fs; HLSL: the snippet + vs_full + hlsl, entries vs / ps
Shaders compile_pass(Source lang, const char* glsl_vs, const char* glsl_fs, const char* hlsl, const char* vs, const char* ps,
                     const std::string& name) {
    Shaders s;
    if (lang == Source::Glsl) {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_GLSL_DIR) + "/prefiltered_shadow.glsl");
        s.vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, glsl_vs, "main", name + ".glsl.vert");
        s.fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, "#version 450 core\n" + snippet + glsl_fs, "main",
                                     name + ".glsl.frag");
    } else {
        const std::string text =
            skvk::read_text(std::string(SHADOWKIT_HLSL_DIR) + "/prefiltered_shadow.hlsl") + kFullscreenHlsl + hlsl;
        s.vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, text, vs, name + ".hlsl.vert");
        s.fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, text, ps, name + ".hlsl.frag");
        s.vs_entry = vs;
        s.fs_entry = ps;
    }
    return s;
}

Shaders moment_shaders(Source lang) {
    return compile_pass(lang, kMomentVsGlsl, kMomentFsGlsl, kMomentHlsl, "vs_moment", "ps_moment", "prefiltered_moment");
}

VkPipelineLayout make_layout(skvk::Context& ctx, const skvk::DescriptorSet* ds, std::uint32_t push_bytes,
                             VkShaderStageFlags stages) {
    VkPushConstantRange range{stages, 0, push_bytes};
    VkPipelineLayoutCreateInfo li{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    li.setLayoutCount = ds ? 1u : 0u;
    li.pSetLayouts = ds ? &ds->layout : nullptr;
    li.pushConstantRangeCount = 1;
    li.pPushConstantRanges = &range;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    vkCreatePipelineLayout(ctx.device, &li, nullptr, &layout);
    return layout;
}

VkPipeline make_fullscreen_pipeline(skvk::Context& ctx, const Shaders& sh, VkPipelineLayout layout, VkRenderPass rp,
                                    std::uint32_t colors) {
    skvk::PipelineDesc pd;
    pd.vs = sh.vs;
    pd.fs = sh.fs;
    pd.vs_entry = sh.vs_entry;
    pd.fs_entry = sh.fs_entry;
    pd.depth_test = pd.depth_write = false;
    pd.color_count = colors;
    VkPipeline p = skvk::make_pipeline_checked(ctx, pd, layout, rp);
    return p;
}

// An image with `levels` mip levels and `samples` samples (the harness makes one level, one sample):
// `view` sees every level, layer_views[0] level 0 alone (a render target).
bool make_image_ex(skvk::Context& ctx, std::uint32_t w, std::uint32_t h, std::uint32_t levels, VkSampleCountFlagBits samples,
                   VkFormat format, VkImageUsageFlags usage, skvk::Image& img) {
    VkImageCreateInfo ii{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    ii.imageType = VK_IMAGE_TYPE_2D;
    ii.format = format;
    ii.extent = {w, h, 1};
    ii.mipLevels = levels;
    ii.arrayLayers = 1;
    ii.samples = samples;
    ii.tiling = VK_IMAGE_TILING_OPTIMAL;
    ii.usage = usage;
    ii.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    if (vkCreateImage(ctx.device, &ii, nullptr, &img.image) != VK_SUCCESS) return false;
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(ctx.device, img.image, &req);
    VkPhysicalDeviceMemoryProperties mp;
    vkGetPhysicalDeviceMemoryProperties(ctx.physical, &mp);
    std::uint32_t type = mp.memoryTypeCount;
    for (std::uint32_t i = 0; i < mp.memoryTypeCount && type == mp.memoryTypeCount; ++i)
        if ((req.memoryTypeBits & (1u << i)) && (mp.memoryTypes[i].propertyFlags & VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT)) type = i;
    if (type == mp.memoryTypeCount) return false;
    VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    ai.allocationSize = req.size;
    ai.memoryTypeIndex = type;
    if (vkAllocateMemory(ctx.device, &ai, nullptr, &img.memory) != VK_SUCCESS) return false;
    vkBindImageMemory(ctx.device, img.image, img.memory, 0);
    img.format = format;
    img.aspect = format == VK_FORMAT_D32_SFLOAT ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT;
    img.width = w;
    img.height = h;
    for (std::uint32_t count : {levels, 1u}) {
        VkImageViewCreateInfo vi{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
        vi.image = img.image;
        vi.viewType = VK_IMAGE_VIEW_TYPE_2D;
        vi.format = format;
        vi.subresourceRange = {img.aspect, 0, count, 0, 1};
        VkImageView v = VK_NULL_HANDLE;
        if (vkCreateImageView(ctx.device, &vi, nullptr, &v) != VK_SUCCESS) return false;
        (count == levels && img.view == VK_NULL_HANDLE ? img.view : img.layer_views.emplace_back()) = v;
    }
    return true;
}

void level_barrier(VkCommandBuffer cmd, const skvk::Image& img, std::uint32_t level, std::uint32_t count, VkImageLayout from,
                   VkImageLayout to) {
    VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
    b.srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT;
    b.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
    b.oldLayout = from;
    b.newLayout = to;
    b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = img.image;
    b.subresourceRange = {img.aspect, level, count, 0, 1};
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 0, nullptr, 0, nullptr,
                         1, &b);
}

VkFormat vk_format_of(int channels, PrefilterFormat f) {
    if (f == PrefilterFormat::Unorm16) return channels == 2 ? VK_FORMAT_R16G16_UNORM : VK_FORMAT_R16G16B16A16_UNORM;
    if (f == PrefilterFormat::Float16)
        return channels == 1 ? VK_FORMAT_R16_SFLOAT : channels == 2 ? VK_FORMAT_R16G16_SFLOAT : VK_FORMAT_R16G16B16A16_SFLOAT;
    return channels == 1 ? VK_FORMAT_R32_SFLOAT : channels == 2 ? VK_FORMAT_R32G32_SFLOAT : VK_FORMAT_R32G32B32A32_SFLOAT;
}

// Channel ch of texel i of raw texel bytes (channels of 4 bytes for Float32, 2 bytes otherwise).
float decode(const std::uint8_t* raw, std::size_t i, int ch, int channels, PrefilterFormat f) {
    const std::size_t size = f == PrefilterFormat::Float32 ? 4 : 2;
    const std::uint8_t* p = raw + (i * std::size_t(channels) + std::size_t(ch)) * size;
    if (size == 4) {
        float v;
        std::memcpy(&v, p, 4);
        return v;
    }
    std::uint16_t u;
    std::memcpy(&u, p, 2);
    return f == PrefilterFormat::Unorm16 ? float(u) / 65535.0f : glm::unpackHalf1x16(u);
}

// A 16-bit 2-channel or 32-bit 1-channel texel is one float of read_image, 16-bit 1-channel half of one
std::vector<float> read_raw(skvk::Context& ctx, const skvk::Image& img, int channels, PrefilterFormat f) {
    const std::uint32_t bytes = std::uint32_t(channels) * (f == PrefilterFormat::Float32 ? 4u : 2u);
    return skvk::read_image(ctx, img, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, std::max(1u, bytes / 4u));
}

using prefiltered_ref::test_uniforms;

// The GL test's casters seen by a light at the origin looking down -z: a floor at z = -8, a tilted
// quad and a box; a triangle list.
std::vector<glm::vec3> light_scene() {
    std::vector<glm::vec3> tris;
    tris.reserve(30);
    prefiltered_ref::light_scene_quads([&](glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d) {
        for (const glm::vec3& p : {a, b, c, a, c, d}) tris.push_back(p);
    });
    return tris;
}

MomentPush moment_push(const glm::mat4& proj, const PrefilterDepthRange& r, const PrefilterUniforms& u) {
    return MomentPush{proj, glm::vec2(r.scale, r.offset), u.exponents, u.method_code, u.quantized ? 1 : 0};
}

// The moment pass (samples = 1) into `moments_view` (format `format`, N x N, cleared to `clear`) and
// t, dt, 1 into `t_img` (RGBA32F), depth tested (LESS, cleared to 1), no culling; both targets end in
// TRANSFER_SRC_OPTIMAL. With samples = 4 and no views: depth only into the multisampled `ms_depth`.
void moment_pass(skvk::Context& ctx, const Shaders& sh, VkFormat format, VkImageView moments_view, VkImageView t_view,
                 std::uint32_t N, const MomentPush& push, const glm::vec4& clear, const std::vector<glm::vec3>& tris) {
    skvk::Scope scope(ctx);
    skvk::Image& depth = scope.own<skvk::Image>();
    REQUIRE(skvk::make_image(ctx, N, N, 1, VK_FORMAT_D32_SFLOAT, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, depth));
    VkRenderPass rp = scope.keep(skvk::make_render_pass(ctx, {format, VK_FORMAT_R32G32B32A32_SFLOAT}, VK_FORMAT_D32_SFLOAT,
                                             VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL), vkDestroyRenderPass);
    VkFramebuffer fb = scope.keep(skvk::make_framebuffer(ctx, rp, {moments_view, t_view, depth.view}, N, N), vkDestroyFramebuffer);
    const VkShaderStageFlags stages = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
    VkPipelineLayout layout = scope.keep(make_layout(ctx, nullptr, sizeof(MomentPush), stages), vkDestroyPipelineLayout);
    skvk::PipelineDesc pd;
    pd.vs = sh.vs;
    pd.fs = sh.fs;
    pd.vs_entry = sh.vs_entry;
    pd.fs_entry = sh.fs_entry;
    pd.vertex_stride = sizeof(glm::vec3);
    pd.attributes = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0}};
    pd.color_count = 2;
    VkPipeline pipe = scope.keep(skvk::make_pipeline_checked(ctx, pd, layout, rp), vkDestroyPipeline);
    skvk::Buffer& vb = scope.own<skvk::Buffer>();
    REQUIRE(skvk::make_buffer(ctx, tris.size() * sizeof(glm::vec3), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, vb));
    std::memcpy(vb.mapped, tris.data(), tris.size() * sizeof(glm::vec3));
    VkClearValue c0{}, c1{}, cd{};
    std::memcpy(c0.color.float32, &clear[0], sizeof(float) * 4);
    cd.depthStencil = {1.f, 0};
    VkCommandBuffer cmd = skvk::begin_commands(ctx);
    skvk::draw_pass(cmd, rp, fb, N, N, {c0, c1, cd}, pipe, layout, nullptr, &push, vb.buffer,
                    static_cast<std::uint32_t>(tris.size()), false, sizeof push, stages);
    REQUIRE(skvk::submit_and_wait(ctx, cmd));
}

std::string lang_name(Source lang) { return lang == Source::Glsl ? "GLSL" : "HLSL"; }

// (a) The GL test's moment pass: 128 x 128, perspective 1.2 rad, planes 1 and 10.
void run_moment_pass(Source lang) {
    skvk::Context& ctx = skvk::vk_test_context();
    skvk::Scope scope(ctx);
    const std::size_t before = skvk::message_count();
    const Shaders sh = moment_shaders(lang);
    const std::uint32_t N = 128;
    const float n = 1.0f, f = 10.0f;
    const PrefilterDepthRange range = prefilter_depth_range(n, f);
    REQUIRE(range.status == Status::Ok);
    const std::vector<glm::vec3> tris = light_scene();
    const glm::mat4 P = glm::perspectiveRH_ZO(1.2f, 1.0f, n, f);
    const VkImageUsageFlags usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    skvk::Image& t_img = scope.own<skvk::Image>();
    REQUIRE(skvk::make_image(ctx, N, N, 1, VK_FORMAT_R32G32B32A32_SFLOAT, usage, t_img));
    for (const prefiltered_ref::MomentCase& c : prefiltered_ref::kMomentCases) {
        CAPTURE(int(c.m));
        CAPTURE(int(c.fmt));
        const PrefilterUniforms u = test_uniforms(c.m, c.fmt);
        REQUIRE(u.status == Status::Ok);
        const VkFormat vf = vk_format_of(u.channels, c.fmt);
        skvk::Scope iteration(ctx);
        skvk::Image& mi = iteration.own<skvk::Image>();
        REQUIRE(skvk::make_image(ctx, N, N, 1, vf, usage, mi));
        const glm::vec4 clear = prefilter_moments(1.0f, glm::vec2(0.0f), u);
        moment_pass(ctx, sh, vf, mi.view, t_img.view, N, moment_push(P, range, u), clear, tris);
        const std::vector<float> raw = read_raw(ctx, mi, u.channels, c.fmt);
        const std::vector<float> tt = skvk::read_image(ctx, t_img, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 4);
        const auto* bytes = reinterpret_cast<const std::uint8_t*>(raw.data());
        int covered = 0;
        double worst = 0.0;
        std::size_t bad = 0;
        for (std::size_t i = 0; i < std::size_t(N) * N; ++i) {
            glm::vec4 cpu = clear;
            if (tt[4 * i + 3] > 0.5f) {
                ++covered;
                cpu = prefilter_moments(tt[4 * i], glm::vec2(tt[4 * i + 1], tt[4 * i + 2]), u);
            }
            for (int ch = 0; ch < u.channels; ++ch) {
                const double expect = double(prefilter_store(double(cpu[ch]), c.fmt).value);
                const double got = double(decode(bytes, i, ch, u.channels, c.fmt));
                const double tol = prefiltered_ref::moment_tolerance(c.fmt, expect);
                worst = std::max(worst, std::abs(got - expect) / tol);
                bad += !(std::abs(got - expect) <= tol);
            }
        }
        MESSAGE(lang_name(lang) << " moment pass, method " << int(c.m) << " format " << int(c.fmt) << ": " << bad
                                << " channels off, worst error " << worst << " x tolerance");
        CHECK(bad == 0u);
        CHECK(covered == int(N * N));  // the floor covers the map
    }
    // fp16 EVSM4 at the header's limit holds no Inf; 5% above it the near end's e^(2c) overflows
    for (float scale : {1.0f, 1.05f}) {
        const float lim = prefilter_exponent_limit(PrefilterMethod::Evsm4, PrefilterFormat::Float16, 1).exponent;
        PrefilterUniforms u = test_uniforms(PrefilterMethod::Evsm4, PrefilterFormat::Float16, 0.999f * lim);
        REQUIRE(u.status == Status::Ok);
        u.exponents = glm::vec2(scale == 1.0f ? 0.999f * lim : scale * lim);
        skvk::Scope iteration(ctx);
        skvk::Image& mi = iteration.own<skvk::Image>();
        REQUIRE(skvk::make_image(ctx, N, N, 1, VK_FORMAT_R16G16B16A16_SFLOAT, usage, mi));
        // a range whose near end the casters reach (t clamps to 0 on the tilted quad's near part)
        const PrefilterDepthRange r2 = prefilter_depth_range(4.5f, 8.0f);
        moment_pass(ctx, sh, VK_FORMAT_R16G16B16A16_SFLOAT, mi.view, t_img.view, N, moment_push(P, r2, u), glm::vec4(0.0f), tris);
        const std::vector<float> raw = read_raw(ctx, mi, 4, PrefilterFormat::Float16);
        const auto* bytes = reinterpret_cast<const std::uint8_t*>(raw.data());
        std::size_t over = 0;
        float mx = 0.0f;
        for (std::size_t i = 0; i < std::size_t(N) * N; ++i)
            for (int ch = 0; ch < 4; ++ch) {
                const float v = decode(bytes, i, ch, 4, PrefilterFormat::Float16);
                over += !(std::abs(v) < 65504.0f) ? 1u : 0u;
                if (std::isfinite(v)) mx = std::max(mx, std::abs(v));
            }
        MESSAGE(lang_name(lang) << " fp16 EVSM4, exponent " << scale << " x limit: " << over << " texels overflowed, largest finite "
                                << mx);
        if (scale == 1.0f) CHECK(over == 0u);
        else CHECK(over > 0u);
    }
    CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());
}

// (b) The GL test's blur: a 37 x 29 RGBA32F field, box and Gaussian of widths 1, 5 and 12, two
// fragment passes (horizontal into tmp, vertical into out) and the same two as compute dispatches,
// against the brute-force 2D convolution.
void run_blur(Source lang) {
    skvk::Context& ctx = skvk::vk_test_context();
    skvk::Scope scope(ctx);
    const std::size_t before = skvk::message_count();
    const std::uint32_t W = 37, H = 29;
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> ud(-2.0f, 2.0f);
    std::vector<float> data(std::size_t(W) * H * 4);
    for (float& v : data) v = ud(rng);
    const Shaders sh = compile_pass(lang, skvk::kFullscreenGlsl, kBlurGlsl, kBlurHlsl, "vs_full", "ps_blur", "prefiltered_blur");
    skvk::Image& src = scope.own<skvk::Image>();
    skvk::Image& tmp = scope.own<skvk::Image>();
    skvk::Image& out = scope.own<skvk::Image>();
    const VkFormat rgba = VK_FORMAT_R32G32B32A32_SFLOAT;
    REQUIRE(skvk::make_image(ctx, W, H, 1, rgba, VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT, src));
    REQUIRE(skvk::upload_image(ctx, src, data, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL));
    const VkImageUsageFlags target_usage =
        VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    REQUIRE(skvk::make_image(ctx, W, H, 1, rgba, target_usage, tmp));
    REQUIRE(skvk::make_image(ctx, W, H, 1, rgba, target_usage, out));
    skvk::Buffer& weights = scope.own<skvk::Buffer>();
    REQUIRE(skvk::make_buffer(ctx, kPrefilterMaxWeights * sizeof(float), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, weights));
    VkSampler nearest = scope.keep(skvk::make_sampler(ctx, VK_FILTER_NEAREST, VK_COMPARE_OP_NEVER), vkDestroySampler);
    const VkDescriptorType tex_type = skvk::texture_type(lang);
    const VkShaderStageFlags frag = VK_SHADER_STAGE_FRAGMENT_BIT;
    auto& ds = scope.own<std::array<skvk::DescriptorSet, 2>>();  // reads src, reads tmp
    for (int p = 0; p < 2; ++p) {
        REQUIRE(skvk::make_descriptor_set(ctx, {{0, tex_type, frag}, {1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, frag}}, ds[p]));
        skvk::write_image(ctx, ds[p], 0, tex_type, p ? tmp.view : src.view, lang == Source::Glsl ? nearest : VK_NULL_HANDLE,
                          VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
        skvk::write_buffer(ctx, ds[p], 1, weights, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
    }
    VkPipelineLayout layout = scope.keep(make_layout(ctx, &ds[0], sizeof(BlurPush), frag), vkDestroyPipelineLayout);
    VkRenderPass rp = scope.keep(skvk::make_render_pass(ctx, {rgba}, VK_FORMAT_UNDEFINED, VK_IMAGE_LAYOUT_UNDEFINED), vkDestroyRenderPass);
    VkFramebuffer fb_tmp = scope.keep(skvk::make_framebuffer(ctx, rp, {tmp.view}, W, H), vkDestroyFramebuffer);
    VkFramebuffer fb_out = scope.keep(skvk::make_framebuffer(ctx, rp, {out.view}, W, H), vkDestroyFramebuffer);
    VkPipeline pipe = scope.keep(make_fullscreen_pipeline(ctx, sh, layout, rp, 1), vkDestroyPipeline);
    // the compute form: the same two passes, written with imageStore (RWTexture2D) into cout via ctmp
    std::vector<std::uint32_t> cs;
    if (lang == Source::Glsl)
        cs = skvk::compile_checked(lang, VK_SHADER_STAGE_COMPUTE_BIT,
                                   "#version 450 core\n" + skvk::read_text(std::string(SHADOWKIT_GLSL_DIR) + "/prefiltered_shadow.glsl") +
                                       kBlurComputeGlsl,
                                   "main", "prefiltered_blur.glsl.comp");
    else
        cs = skvk::compile_checked(lang, VK_SHADER_STAGE_COMPUTE_BIT,
                                   skvk::read_text(std::string(SHADOWKIT_HLSL_DIR) + "/prefiltered_shadow.hlsl") + kBlurComputeHlsl,
                                   "cs_blur", "prefiltered_blur.hlsl.comp");
    skvk::Image& ctmp = scope.own<skvk::Image>();
    skvk::Image& cout = scope.own<skvk::Image>();
    const VkImageUsageFlags storage_usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    REQUIRE(skvk::make_image(ctx, W, H, 1, rgba, storage_usage, ctmp));
    REQUIRE(skvk::make_image(ctx, W, H, 1, rgba, storage_usage, cout));
    const VkShaderStageFlags comp = VK_SHADER_STAGE_COMPUTE_BIT;
    auto& cds = scope.own<std::array<skvk::DescriptorSet, 2>>();  // src -> ctmp, ctmp -> cout
    for (int p = 0; p < 2; ++p) {
        REQUIRE(skvk::make_descriptor_set(
            ctx, {{0, tex_type, comp}, {1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, comp}, {2, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, comp}}, cds[p]));
        skvk::write_image(ctx, cds[p], 0, tex_type, p ? ctmp.view : src.view, lang == Source::Glsl ? nearest : VK_NULL_HANDLE,
                          p ? VK_IMAGE_LAYOUT_GENERAL : VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
        skvk::write_buffer(ctx, cds[p], 1, weights, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
        skvk::write_image(ctx, cds[p], 2, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, p ? cout.view : ctmp.view, VK_NULL_HANDLE,
                          VK_IMAGE_LAYOUT_GENERAL);
    }
    VkPipelineLayout clayout = scope.keep(make_layout(ctx, &cds[0], sizeof(BlurPush), comp), vkDestroyPipelineLayout);
    VkPipeline cpipe = VK_NULL_HANDLE;
    {
        skvk::Scope module_scope(ctx);  // the module, gone once the pipeline is made
        VkShaderModuleCreateInfo mi{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
        mi.codeSize = cs.size() * 4;
        mi.pCode = cs.data();
        VkShaderModule module = VK_NULL_HANDLE;
        REQUIRE(vkCreateShaderModule(ctx.device, &mi, nullptr, &module) == VK_SUCCESS);
        module_scope.keep(module, vkDestroyShaderModule);
        VkComputePipelineCreateInfo ci{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
        ci.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0, VK_SHADER_STAGE_COMPUTE_BIT, module,
                    lang == Source::Glsl ? "main" : "cs_blur", nullptr};
        ci.layout = clayout;
        REQUIRE(vkCreateComputePipelines(ctx.device, VK_NULL_HANDLE, 1, &ci, nullptr, &cpipe) == VK_SUCCESS);
        scope.keep(cpipe, vkDestroyPipeline);
    }
    for (PrefilterBlur shape : {PrefilterBlur::Box, PrefilterBlur::Gaussian})
        for (float width : {1.0f, 5.0f, 12.0f}) {
            float w[kPrefilterMaxWeights] = {};
            const PrefilterKernel k = prefilter_blur_weights(shape, width, w, kPrefilterMaxWeights);
            REQUIRE(k.status == Status::Ok);
            for (std::size_t i = k.count; i < kPrefilterMaxWeights; ++i) w[i] = 0.0f;
            std::memcpy(weights.mapped, w, sizeof w);
            // brute force: the 2D kernel w[|i|] w[|j|], coordinates clamped to the map
            const std::vector<double> ref = prefiltered_ref::blur_reference(data, int(W), int(H), w, k.radius);
            const BlurPush h{{1, 0}, k.radius}, v{{0, 1}, k.radius};
            VkCommandBuffer cmd = skvk::begin_commands(ctx);
            VkClearValue zero{};
            skvk::draw_pass(cmd, rp, fb_tmp, W, H, {zero}, pipe, layout, &ds[0].set, &h, VK_NULL_HANDLE, 3, false, sizeof h, frag);
            skvk::transition(cmd, tmp, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
            skvk::draw_pass(cmd, rp, fb_out, W, H, {zero}, pipe, layout, &ds[1].set, &v, VK_NULL_HANDLE, 3, false, sizeof v, frag);
            REQUIRE(skvk::submit_and_wait(ctx, cmd));
            const std::vector<float> got = skvk::read_image(ctx, out, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 4);
            REQUIRE(got.size() == ref.size());
            // compute: horizontal into ctmp, barrier, vertical into cout
            cmd = skvk::begin_commands(ctx);
            skvk::transition(cmd, ctmp, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL);
            skvk::transition(cmd, cout, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL);
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, cpipe);
            for (int p = 0; p < 2; ++p) {
                vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, clayout, 0, 1, &cds[p].set, 0, nullptr);
                vkCmdPushConstants(cmd, clayout, comp, 0, sizeof(BlurPush), p ? &v : &h);
                vkCmdDispatch(cmd, (W + 7) / 8, (H + 7) / 8, 1);
                VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
                mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
                mb.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT;
                vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &mb, 0, nullptr, 0,
                                     nullptr);
            }
            REQUIRE(skvk::submit_and_wait(ctx, cmd));
            const std::vector<float> comp_got = skvk::read_image(ctx, cout, VK_IMAGE_LAYOUT_GENERAL, 4);
            REQUIRE(comp_got.size() == ref.size());
            double worst = 0.0, worst_c = 0.0;
            for (std::size_t i = 0; i < ref.size(); ++i) {
                worst = std::max(worst, std::abs(double(got[i]) - ref[i]));
                worst_c = std::max(worst_c, std::abs(double(comp_got[i]) - ref[i]));
            }
            MESSAGE(lang_name(lang) << " blur, " << std::string(shape == PrefilterBlur::Box ? "box" : "Gaussian") << " width " << width
                                    << " (radius " << k.radius << "): max |GPU - brute force| = " << worst << " (fragment), "
                                    << worst_c << " (compute)");
            CHECK(worst < 2e-5);
            CHECK(worst_c < 2e-5);
        }
    CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());
}


// A depth-only render pass of one `samples`-sample D32 attachment (cleared to 1), left for sampling.
VkRenderPass depth_only_pass(skvk::Context& ctx, VkSampleCountFlagBits samples) {
    VkAttachmentDescription a{};
    a.format = VK_FORMAT_D32_SFLOAT;
    a.samples = samples;
    a.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    a.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    a.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    a.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    a.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    a.finalLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL;
    VkAttachmentReference ref{0, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
    VkSubpassDescription sp{};
    sp.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    sp.pDepthStencilAttachment = &ref;
    VkSubpassDependency dep{};
    dep.srcSubpass = 0;
    dep.dstSubpass = VK_SUBPASS_EXTERNAL;
    dep.srcStageMask = VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
    dep.dstStageMask = VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT;
    dep.srcAccessMask = VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
    dep.dstAccessMask = VK_ACCESS_SHADER_READ_BIT;
    VkRenderPassCreateInfo ri{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
    ri.attachmentCount = 1;
    ri.pAttachments = &a;
    ri.subpassCount = 1;
    ri.pSubpasses = &sp;
    ri.dependencyCount = 1;
    ri.pDependencies = &dep;
    VkRenderPass rp = VK_NULL_HANDLE;
    vkCreateRenderPass(ctx.device, &ri, nullptr, &rp);
    return rp;
}

// (d) The GL test's MSAA resolve: the light scene's depth at 4 samples (64 x 64), resolved per texel
// into moments by sk_prefilter_resolve (VSM, EVSM4 fp32; MSM quantized), against the mean of the
// moments of the samples' depths read back by the same pass.
void run_resolve(Source lang) {
    skvk::Context& ctx = skvk::vk_test_context();
    skvk::Scope scope(ctx);
    const std::size_t before = skvk::message_count();
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(ctx.physical, &props);
    const VkSampleCountFlags counts = props.limits.framebufferDepthSampleCounts & props.limits.sampledImageDepthSampleCounts;
    if (!(counts & VK_SAMPLE_COUNT_4_BIT)) {
        MESSAGE(ctx.device_name << " has no 4-sample sampled depth images (sample counts " << counts
                                << "): the MSAA resolve is not run");
        return;
    }
    const std::uint32_t N = 64;
    const int S = 4;
    const float n = 1.0f, f = 10.0f;
    const PrefilterDepthRange range = prefilter_depth_range(n, f);
    const PrefilterWindowMap wm = prefilter_window_depth_map(n, f, true, false, range);
    REQUIRE(wm.status == Status::Ok);
    const std::vector<glm::vec3> tris = light_scene();
    const glm::mat4 P = glm::perspectiveRH_ZO(1.2f, 1.0f, n, f);
    skvk::Image& ms = scope.own<skvk::Image>();
    REQUIRE(make_image_ex(ctx, N, N, 1, VK_SAMPLE_COUNT_4_BIT, VK_FORMAT_D32_SFLOAT,
                          VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT, ms));
    const Shaders msh = moment_shaders(lang);
    {
        skvk::Scope depth_pass(ctx);  // this block's
        VkRenderPass rp = depth_pass.keep(depth_only_pass(ctx, VK_SAMPLE_COUNT_4_BIT), vkDestroyRenderPass);
        VkFramebuffer fb = depth_pass.keep(skvk::make_framebuffer(ctx, rp, {ms.view}, N, N), vkDestroyFramebuffer);
        const VkShaderStageFlags stages = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
        VkPipelineLayout layout = depth_pass.keep(make_layout(ctx, nullptr, sizeof(MomentPush), stages), vkDestroyPipelineLayout);
        skvk::PipelineDesc pd;
        pd.vs = msh.vs;
        pd.vs_entry = msh.vs_entry;
        pd.vertex_stride = sizeof(glm::vec3);
        pd.attributes = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0}};
        pd.samples = VK_SAMPLE_COUNT_4_BIT;
        VkPipeline pipe = depth_pass.keep(skvk::make_pipeline_checked(ctx, pd, layout, rp), vkDestroyPipeline);
        skvk::Buffer& vb = depth_pass.own<skvk::Buffer>();
        REQUIRE(skvk::make_buffer(ctx, tris.size() * sizeof(glm::vec3), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, vb));
        std::memcpy(vb.mapped, tris.data(), tris.size() * sizeof(glm::vec3));
        const MomentPush push = moment_push(P, range, test_uniforms(PrefilterMethod::Vsm, PrefilterFormat::Float32));
        VkClearValue cd{};
        cd.depthStencil = {1.f, 0};
        VkCommandBuffer cmd = skvk::begin_commands(ctx);
        skvk::draw_pass(cmd, rp, fb, N, N, {cd}, pipe, layout, nullptr, &push, vb.buffer, static_cast<std::uint32_t>(tris.size()),
                        false, sizeof push, stages);
        REQUIRE(skvk::submit_and_wait(ctx, cmd));
    }
    const Shaders sh = compile_pass(lang, skvk::kFullscreenGlsl, kResolveGlsl, kResolveHlsl, "vs_full", "ps_resolve", "prefiltered_resolve");
    VkSampler nearest = scope.keep(skvk::make_sampler(ctx, VK_FILTER_NEAREST, VK_COMPARE_OP_NEVER), vkDestroySampler);
    const VkDescriptorType tex_type = skvk::texture_type(lang);
    const VkShaderStageFlags frag = VK_SHADER_STAGE_FRAGMENT_BIT;
    skvk::DescriptorSet& ds = scope.own<skvk::DescriptorSet>();
    REQUIRE(skvk::make_descriptor_set(ctx, {{0, tex_type, frag}}, ds));
    skvk::write_image(ctx, ds, 0, tex_type, ms.view, lang == Source::Glsl ? nearest : VK_NULL_HANDLE,
                      VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL);
    VkPipelineLayout layout = scope.keep(make_layout(ctx, &ds, sizeof(ResolvePush), frag), vkDestroyPipelineLayout);
    const VkFormat rgba = VK_FORMAT_R32G32B32A32_SFLOAT;
    VkRenderPass rp = scope.keep(skvk::make_render_pass(ctx, {rgba, rgba}, VK_FORMAT_UNDEFINED, VK_IMAGE_LAYOUT_UNDEFINED), vkDestroyRenderPass);
    skvk::Image& out = scope.own<skvk::Image>();
    skvk::Image& samples = scope.own<skvk::Image>();
    const VkImageUsageFlags usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    REQUIRE(skvk::make_image(ctx, N, N, 1, rgba, usage, out));
    REQUIRE(skvk::make_image(ctx, N, N, 1, rgba, usage, samples));
    VkFramebuffer fb = scope.keep(skvk::make_framebuffer(ctx, rp, {out.view, samples.view}, N, N), vkDestroyFramebuffer);
    VkPipeline pipe = scope.keep(make_fullscreen_pipeline(ctx, sh, layout, rp, 2), vkDestroyPipeline);
    for (int mi : {0, 3, 4}) {
        const PrefilterUniforms u = test_uniforms(static_cast<PrefilterMethod>(mi), mi == 4 ? PrefilterFormat::Unorm16 : PrefilterFormat::Float32);
        REQUIRE(u.status == Status::Ok);
        const ResolvePush push{wm.coefficients, u.exponents, u.method_code, u.quantized ? 1 : 0};
        VkCommandBuffer cmd = skvk::begin_commands(ctx);
        VkClearValue zero{};
        skvk::draw_pass(cmd, rp, fb, N, N, {zero, zero}, pipe, layout, &ds.set, &push, VK_NULL_HANDLE, 3, false, sizeof push, frag);
        REQUIRE(skvk::submit_and_wait(ctx, cmd));
        const std::vector<float> got = skvk::read_image(ctx, out, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 4);
        const std::vector<float> z = skvk::read_image(ctx, samples, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 4);
        REQUIRE(got.size() == std::size_t(N) * N * 4);
        int edges = 0;
        std::size_t off = 0;
        double worst = 0.0;
        for (std::size_t i = 0; i < std::size_t(N) * N; ++i) {
            const glm::vec4 mean = prefiltered_ref::resolve_reference(z, i, S, wm.coefficients, u);
            if (z[4 * i] != z[4 * i + 1] || z[4 * i] != z[4 * i + 3]) ++edges;
            for (int c = 0; c < 4; ++c) {
                const float e = std::abs(got[4 * i + static_cast<std::size_t>(c)] - mean[c]);
                const float tol = 2e-5f * std::max(1.0f, std::abs(mean[c]));
                worst = std::max(worst, double(e / tol));
                off += !(e <= tol);
            }
        }
        MESSAGE(lang_name(lang) << " 4x MSAA resolve, method " << mi << ": " << edges << " texels on silhouettes, " << off
                                << " channels off, worst error " << worst << " x tolerance");
        CHECK(off == 0u);
        CHECK(edges > 10);  // texels on silhouettes hold samples of two surfaces
    }
    CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());
}

// The levels of a mipmapped image in SHADER_READ_ONLY_OPTIMAL, as raw texels (`bytes` per texel),
// level l of width w >> l; the image is left as it was.
std::vector<std::vector<std::uint8_t>> read_levels(skvk::Context& ctx, const skvk::Image& img, std::uint32_t levels,
                                                   std::uint32_t bytes) {
    std::vector<std::vector<std::uint8_t>> out(levels);
    VkDeviceSize total = 0;
    std::vector<VkBufferImageCopy> copies;
    for (std::uint32_t l = 0; l < levels; ++l) {
        VkBufferImageCopy c{};
        c.bufferOffset = total;
        c.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, l, 0, 1};
        c.imageExtent = {img.width >> l, img.height >> l, 1};
        copies.push_back(c);
        total += VkDeviceSize(img.width >> l) * (img.height >> l) * bytes;
    }
    skvk::Scope scope(ctx);
    skvk::Buffer& b = scope.own<skvk::Buffer>();
    REQUIRE(skvk::make_buffer(ctx, total, VK_BUFFER_USAGE_TRANSFER_DST_BIT, b));
    VkCommandBuffer cmd = skvk::begin_commands(ctx);
    level_barrier(cmd, img, 0, levels, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    vkCmdCopyImageToBuffer(cmd, img.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, b.buffer, levels, copies.data());
    level_barrier(cmd, img, 0, levels, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    REQUIRE(skvk::submit_and_wait(ctx, cmd));
    for (std::uint32_t l = 0; l < levels; ++l) {
        const auto* p = static_cast<const std::uint8_t*>(b.mapped) + copies[l].bufferOffset;
        out[l].assign(p, p + std::size_t(img.width >> l) * (img.height >> l) * bytes);
    }
    return out;
}

// Level 0 rendered (TRANSFER_SRC_OPTIMAL) -> every level by linear blits of the level above, all left
// in SHADER_READ_ONLY_OPTIMAL (glGenerateMipmap of the GL test).
void blit_mips(skvk::Context& ctx, const skvk::Image& img, std::uint32_t levels) {
    VkCommandBuffer cmd = skvk::begin_commands(ctx);
    for (std::uint32_t l = 1; l < levels; ++l) {
        level_barrier(cmd, img, l, 1, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
        VkImageBlit b{};
        const auto sw = std::int32_t(img.width >> (l - 1)), sh = std::int32_t(img.height >> (l - 1));
        b.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, l - 1, 0, 1};
        b.srcOffsets[1] = {sw, sh, 1};
        b.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, l, 0, 1};
        b.dstOffsets[1] = {std::max(sw / 2, 1), std::max(sh / 2, 1), 1};
        vkCmdBlitImage(cmd, img.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, img.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &b,
                       VK_FILTER_LINEAR);
        level_barrier(cmd, img, l, 1, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    }
    level_barrier(cmd, img, 0, levels, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    REQUIRE(skvk::submit_and_wait(ctx, cmd));
}

// (g) The GL test's soft lookup: a half-plane blocker at distance 4 over a floor at 8 under a square
// emitter of width 1 (a 90-degree map from its center, 256 x 256, 9 levels). The GPU's
// sk_prefilter_soft_visibility equals prefilter_soft_visibility with a CPU trilinear lookup of the
// read-back levels (2e-3 at 95% of the points), and follows the ray-cast penumbra within 0.035 RMSE,
// below a quarter of the hard lookup's.
void run_soft(Source lang) {
    skvk::Context& ctx = skvk::vk_test_context();
    skvk::Scope scope(ctx);
    const std::size_t before = skvk::message_count();
    const std::uint32_t N = 256, levels = 9;
    const PrefilterDepthRange range = prefilter_depth_range(3.5f, 8.5f);
    const glm::mat4 P = glm::perspectiveRH_ZO(glm::radians(90.0f), 1.0f, 1.0f, 20.0f);
    // receiver points across the penumbra (centered on x_edge d_r / d_b), uv and t computed here
    const std::uint32_t RX = 128, RY = 4;
    const prefiltered_ref::SoftScene scene(P, range, int(RX), int(RY));
    const float W = scene.w, db = scene.db, dr = scene.dr, x_edge = scene.x_edge;
    const std::vector<glm::vec4>& in = scene.in;
    PrefilterSoftSettings ss;
    ss.light_proj = P;
    ss.light_width = W;
    ss.range = range;
    ss.map_size = int(N);
    const PrefilterSoftUniforms su = prefilter_soft_uniforms(ss);
    REQUIRE(su.status == Status::Ok);
    const glm::vec3 fl[4] = {{-30, -30, -dr}, {30, -30, -dr}, {30, 30, -dr}, {-30, 30, -dr}};
    const glm::vec3 bl[4] = {{-30, -30, -db}, {x_edge, -30, -db}, {x_edge, 30, -db}, {-30, 30, -db}};
    const std::vector<glm::vec3> tris = {fl[0], fl[1], fl[2], fl[0], fl[2], fl[3], bl[0], bl[1], bl[2], bl[0], bl[2], bl[3]};
    const Shaders msh = moment_shaders(lang);
    const Shaders sh = compile_pass(lang, skvk::kFullscreenGlsl, kSoftGlsl, kSoftHlsl, "vs_full", "ps_soft", "prefiltered_soft");
    skvk::Buffer& receivers = scope.own<skvk::Buffer>();
    REQUIRE(skvk::make_buffer(ctx, in.size() * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, receivers));
    VkSamplerCreateInfo si{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    si.magFilter = si.minFilter = VK_FILTER_LINEAR;
    si.mipmapMode = VK_SAMPLER_MIPMAP_MODE_LINEAR;
    si.addressModeU = si.addressModeV = si.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    si.maxLod = float(levels);
    VkSampler trilinear = VK_NULL_HANDLE;
    REQUIRE(vkCreateSampler(ctx.device, &si, nullptr, &trilinear) == VK_SUCCESS);
    scope.keep(trilinear, vkDestroySampler);
    skvk::Image& t_img = scope.own<skvk::Image>();
    skvk::Image& out = scope.own<skvk::Image>();
    const VkImageUsageFlags target_usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    REQUIRE(skvk::make_image(ctx, N, N, 1, VK_FORMAT_R32G32B32A32_SFLOAT, target_usage, t_img));
    REQUIRE(skvk::make_image(ctx, RX, RY, 1, VK_FORMAT_R32_SFLOAT, target_usage, out));
    VkRenderPass rp = scope.keep(skvk::make_render_pass(ctx, {VK_FORMAT_R32_SFLOAT}, VK_FORMAT_UNDEFINED, VK_IMAGE_LAYOUT_UNDEFINED), vkDestroyRenderPass);
    VkFramebuffer fb = scope.keep(skvk::make_framebuffer(ctx, rp, {out.view}, RX, RY), vkDestroyFramebuffer);
    const VkShaderStageFlags frag = VK_SHADER_STAGE_FRAGMENT_BIT;
    for (const PrefilterFormat fmt : {PrefilterFormat::Float32, PrefilterFormat::Unorm16}) {
        const PrefilterMethod method = fmt == PrefilterFormat::Float32 ? PrefilterMethod::Vsm : PrefilterMethod::Msm;
        CAPTURE(int(method));
        PrefilterSettings s;
        s.method = method;
        s.format = fmt;
        const PrefilterUniforms u = prefilter_uniforms(s);
        REQUIRE(u.status == Status::Ok);
        const float bias = method == PrefilterMethod::Msm ? 0.002f : 0.0f;
        const VkFormat vf = vk_format_of(u.channels, fmt);
        VkFormatProperties fp;
        vkGetPhysicalDeviceFormatProperties(ctx.physical, vf, &fp);
        const VkFormatFeatureFlags need = VK_FORMAT_FEATURE_BLIT_SRC_BIT | VK_FORMAT_FEATURE_BLIT_DST_BIT |
                                          VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT | VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BIT;
        REQUIRE_MESSAGE((fp.optimalTilingFeatures & need) == need, "format " << int(vf) << " cannot be blitted and filtered");
        skvk::Scope iteration(ctx);  // this method's map, set and pipeline
        skvk::Image& map = iteration.own<skvk::Image>();
        REQUIRE(make_image_ex(ctx, N, N, levels, VK_SAMPLE_COUNT_1_BIT, vf,
                              VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                                  VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                              map));
        moment_pass(ctx, msh, vf, map.layer_views[0], t_img.view, N, moment_push(P, range, u), u.clear_value, tris);
        blit_mips(ctx, map, levels);
        // the GPU's soft lookup at every receiver point
        for (std::size_t k = 0; k < in.size(); ++k) static_cast<glm::vec4*>(receivers.mapped)[k] = in[k] - glm::vec4(0, 0, bias, 0);
        skvk::DescriptorSet& ds = iteration.own<skvk::DescriptorSet>();
        if (lang == Source::Glsl) {
            REQUIRE(skvk::make_descriptor_set(ctx, {{0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, frag},
                                                    {2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, frag}}, ds));
            skvk::write_image(ctx, ds, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, map.view, trilinear,
                              VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
        } else {
            REQUIRE(skvk::make_descriptor_set(ctx, {{0, VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, frag}, {1, VK_DESCRIPTOR_TYPE_SAMPLER, frag},
                                                    {2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, frag}}, ds));
            skvk::write_image(ctx, ds, 0, VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, map.view, VK_NULL_HANDLE,
                              VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
            skvk::write_sampler(ctx, ds, 1, trilinear);
        }
        skvk::write_buffer(ctx, ds, 2, receivers, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
        VkPipelineLayout layout = iteration.keep(make_layout(ctx, &ds, sizeof(SoftPush), frag), vkDestroyPipelineLayout);
        VkPipeline pipe = iteration.keep(make_fullscreen_pipeline(ctx, sh, layout, rp, 1), vkDestroyPipeline);
        const SoftPush push{u.params(), su.params(), u.method_code, u.moment_bias, u.quantized ? 1 : 0, std::int32_t(RX)};
        VkCommandBuffer cmd = skvk::begin_commands(ctx);
        VkClearValue zero{};
        skvk::draw_pass(cmd, rp, fb, RX, RY, {zero}, pipe, layout, &ds.set, &push, VK_NULL_HANDLE, 3, false, sizeof push, frag);
        REQUIRE(skvk::submit_and_wait(ctx, cmd));
        const std::vector<float> gpu = skvk::read_image(ctx, out, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 1);
        REQUIRE(gpu.size() == in.size());
        // the levels as stored, and a CPU trilinear lookup (clamp to edge) of them
        const std::uint32_t bytes = std::uint32_t(u.channels) * (fmt == PrefilterFormat::Float32 ? 4u : 2u);
        const std::vector<std::vector<std::uint8_t>> mip = read_levels(ctx, map, levels, bytes);
        auto texel = [&](int l, int x, int y) {
            const int nl = int(N) >> l;
            x = std::clamp(x, 0, nl - 1);
            y = std::clamp(y, 0, nl - 1);
            glm::vec4 v(0.0f);
            for (int c = 0; c < u.channels; ++c)
                v[c] = decode(mip[std::size_t(l)].data(), std::size_t(y * nl + x), c, u.channels, fmt);
            return v;
        };
        // (e) the blitted levels are 2x2 means of the level above (filtering moments is linear), as
        // glGenerateMipmap's: within float rounding, or one 16-bit step
        double worst_mip = 0.0;
        for (int l = 0; l + 1 < int(levels); ++l)
            for (int y = 0; y < (int(N) >> (l + 1)); ++y)
                for (int x = 0; x < (int(N) >> (l + 1)); ++x) {
                    const glm::vec4 mean = 0.25f * (texel(l, 2 * x, 2 * y) + texel(l, 2 * x + 1, 2 * y) +
                                                    texel(l, 2 * x, 2 * y + 1) + texel(l, 2 * x + 1, 2 * y + 1));
                    const glm::vec4 d = glm::abs(texel(l + 1, x, y) - mean);
                    worst_mip = std::max(worst_mip, double(std::max(std::max(d.x, d.y), std::max(d.z, d.w))));
                }
        MESSAGE(lang_name(lang) << " mip chain, method " << int(method) << ": max |level - 2x2 mean of the level above| = " << worst_mip);
        CHECK(worst_mip <= (fmt == PrefilterFormat::Float32 ? 1e-6 : 1.01 / 65535.0));
        const auto mirror = prefiltered_ref::mip_mirror(texel, int(N), int(levels));
        int close = 0;
        std::size_t outside = 0;
        double se_soft = 0.0, se_hard = 0.0;
        for (std::size_t k = 0; k < in.size(); ++k) {
            const prefiltered_ref::SoftPoint pt = prefiltered_ref::soft_point(mirror, in[k], bias, u, su);
            outside += !(gpu[k] >= 0.0f && gpu[k] <= 1.0f);
            if (std::fabs(gpu[k] - pt.cpu) <= 2e-3f) ++close;
            const double exact = scene.exact(k);
            se_soft += (double(gpu[k]) - exact) * (double(gpu[k]) - exact);
            se_hard += (pt.hard - exact) * (pt.hard - exact);
        }
        const double rmse = std::sqrt(se_soft / double(in.size())), rmse_hard = std::sqrt(se_hard / double(in.size()));
        MESSAGE(lang_name(lang) << " soft lookup, method " << int(method) << ": GPU = CPU mirror (2e-3) at " << close << " of "
                                << in.size() << "; RMSE against the ray cast " << rmse << " (hard lookup " << rmse_hard << ")");
        CHECK(outside == 0u);
        CHECK(close >= int(in.size()) * 95 / 100);
        CHECK(rmse < 0.035);
        CHECK(rmse < 0.25 * rmse_hard);
    }
    CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());
}

}  // namespace

TEST_CASE("prefiltered_shadow.glsl on Vulkan: the moment pass of every method and format equals prefilter_moments") {
    run_moment_pass(Source::Glsl);
}
TEST_CASE("HLSL prefiltered_shadow.hlsl on Vulkan: the moment pass of every method and format equals prefilter_moments") {
    run_moment_pass(Source::Hlsl);
}
TEST_CASE("prefiltered_shadow.glsl on Vulkan: the separable blur equals a brute-force 2D convolution") { run_blur(Source::Glsl); }
TEST_CASE("HLSL prefiltered_shadow.hlsl on Vulkan: the separable blur equals a brute-force 2D convolution") { run_blur(Source::Hlsl); }
TEST_CASE("prefiltered_shadow.glsl on Vulkan: the 4x MSAA resolve is the mean of the samples' moments") { run_resolve(Source::Glsl); }
TEST_CASE("HLSL prefiltered_shadow.hlsl on Vulkan: the 4x MSAA resolve is the mean of the samples' moments") { run_resolve(Source::Hlsl); }
TEST_CASE("prefiltered_shadow.glsl on Vulkan: the soft lookup equals its CPU mirror and follows the ray-cast penumbra") {
    run_soft(Source::Glsl);
}
TEST_CASE("HLSL prefiltered_shadow.hlsl on Vulkan: the soft lookup equals its CPU mirror and follows the ray-cast penumbra") {
    run_soft(Source::Hlsl);
}
