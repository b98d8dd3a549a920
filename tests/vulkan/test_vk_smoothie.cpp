// glsl/smoothie.glsl and hlsl/smoothie.hlsl RUN on Vulkan: the final lookup sk_smoothie_visibility on a
// synthetic 64 x 64 linear shadow map (R32_SFLOAT) and smoothie buffer (R32G32_SFLOAT: half the texels
// cleared to (1e30, 1), half a smoothie in front of the map), 1,024 random receivers (half with a
// receiver-plane gradient), against the CPU: shadowkit::smoothie_visibility_tap at the four texels
// around uv, filtered bilinearly as the snippet's comment says. At most 0.5% of the lookups may differ
// by more than 1e-4 (a receiver depth that ties a stored depth within float rounding may flip a tap,
// as in the PCSS test); every value finite and in [0, 1]; no validation message.
#include <doctest/doctest.h>

#include <shadowkit/smoothie.hpp>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "vk_harness.hpp"
#include "vk_passes.hpp"

namespace {

using skvk::Source;

const char* kFullscreenGlsl = R"(#version 450 core
void main() {
    vec2 p = vec2(float((gl_VertexIndex << 1) & 2), float(gl_VertexIndex & 2));
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
)";
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
float4 vs_main(uint id : SV_VertexID) : SV_Position {
    float2 p = float2(float((id << 1) & 2), float(id & 2));
    return float4(p * 2.0 - 1.0, 0.0, 1.0);
}
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
    const std::size_t before = skvk::message_count();
    std::vector<std::uint32_t> vs, fs;
    const char* entries[2] = {"main", "main"};
    if (lang == Source::Glsl) {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_GLSL_DIR) + "/smoothie.glsl");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, kFullscreenGlsl, "main", "smoothie.glsl.vert");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, "#version 450 core\n" + snippet + kGlsl, "main",
                                   "smoothie.glsl.frag");
    } else {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_HLSL_DIR) + "/smoothie.hlsl");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, snippet + kHlsl, "vs_main", "smoothie.hlsl.vert");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, snippet + kHlsl, "ps_main", "smoothie.hlsl.frag");
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
    skvk::Image zmap, smap;
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
    skvk::Buffer ssbo;
    REQUIRE(skvk::make_buffer(ctx, M * 2 * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, ssbo));
    auto* dst = static_cast<glm::vec4*>(ssbo.mapped);
    for (std::uint32_t i = 0; i < M; ++i) {
        dst[2 * i] = glm::vec4(pts[i].uv, pts[i].r, pts[i].bias);
        dst[2 * i + 1] = glm::vec4(pts[i].g, 0.f, 0.f);
    }
    skvk::Image target;
    REQUIRE(skvk::make_image(ctx, M, 1, 1, VK_FORMAT_R32_SFLOAT, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                             target));
    VkRenderPass rp = skvk::make_render_pass(ctx, {VK_FORMAT_R32_SFLOAT}, VK_FORMAT_UNDEFINED, VK_IMAGE_LAYOUT_UNDEFINED);
    VkFramebuffer fb = skvk::make_framebuffer(ctx, rp, {target.view}, M, 1);
    VkSampler nearest = skvk::make_sampler(ctx, VK_FILTER_NEAREST, VK_COMPARE_OP_NEVER);
    skvk::DescriptorSet ds;
    const VkShaderStageFlags frag = VK_SHADER_STAGE_FRAGMENT_BIT;
    const VkDescriptorType tex = lang == Source::Glsl ? VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER : VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE;
    REQUIRE(skvk::make_descriptor_set(ctx, {{0, tex, frag}, {1, tex, frag}, {2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, frag}}, ds));
    const VkSampler s = lang == Source::Glsl ? nearest : VK_NULL_HANDLE;
    skvk::write_image(ctx, ds, 0, tex, zmap.view, s, read);
    skvk::write_image(ctx, ds, 1, tex, smap.view, s, read);
    skvk::write_buffer(ctx, ds, 2, ssbo, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
    VkPipelineLayoutCreateInfo li{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    li.setLayoutCount = 1;
    li.pSetLayouts = &ds.layout;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    REQUIRE(vkCreatePipelineLayout(ctx.device, &li, nullptr, &layout) == VK_SUCCESS);
    skvk::PipelineDesc pd;
    pd.vs = vs;
    pd.fs = fs;
    pd.vs_entry = entries[0];
    pd.fs_entry = entries[1];
    pd.depth_test = pd.depth_write = false;
    pd.color_count = 1;
    std::string why;
    VkPipeline pipe = skvk::make_pipeline(ctx, pd, layout, rp, why);
    REQUIRE_MESSAGE(pipe != VK_NULL_HANDLE, why);
    VkCommandBuffer cmd = skvk::begin_commands(ctx);
    VkClearValue zero{};
    skvk::draw_pass(cmd, rp, fb, M, 1, {zero}, pipe, layout, &ds.set, nullptr, VK_NULL_HANDLE, 3, false);
    REQUIRE(skvk::submit_and_wait(ctx, cmd));
    const std::vector<float> gpu = skvk::read_image(ctx, target, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 1);
    REQUIRE(gpu.size() == M);

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

    vkDestroyPipeline(ctx.device, pipe, nullptr);
    vkDestroyPipelineLayout(ctx.device, layout, nullptr);
    vkDestroySampler(ctx.device, nearest, nullptr);
    vkDestroyFramebuffer(ctx.device, fb, nullptr);
    vkDestroyRenderPass(ctx.device, rp, nullptr);
    skvk::destroy(ctx, ds);
    for (skvk::Image* i : {&zmap, &smap, &target}) skvk::destroy(ctx, *i);
    skvk::destroy(ctx, ssbo);
}

}  // namespace

TEST_CASE("smoothie.glsl on Vulkan: sk_smoothie_visibility equals four smoothie_visibility_tap filtered bilinearly") {
    run_smoothie(Source::Glsl);
}

TEST_CASE("HLSL smoothie.hlsl on Vulkan: sk_smoothie_visibility equals four smoothie_visibility_tap filtered bilinearly") {
    run_smoothie(Source::Hlsl);
}
