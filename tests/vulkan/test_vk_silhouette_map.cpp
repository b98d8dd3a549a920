// glsl/silhouette_map.glsl and hlsl/silhouette_map.hlsl RUN on Vulkan: the lookup sk_silmap_visibility
// on a synthetic 64 x 64 depth map (R32_SFLOAT, samples 0.3 or 0.7 around receivers at 0.5, so the four
// depth tests of a cell often disagree) and silhouette map (R8G8B8A8_UNORM: random points in each cell,
// weights 1, 2 and some 3 = failure texels), 2,048 random lookups, against the CPU lookup
// shadowkit::silmap_lookup on the same quantized data: at most 0.5% may differ (an angle tie within
// float rounding), and most silhouette lookups must take the sector path (no fallback). The edge pass
// (sk_silmap_edge_vertex, sk_silmap_point, sk_silmap_occluded) is compiled, not run. No validation message.
#include <doctest/doctest.h>

#include <shadowkit/silhouette_map.hpp>

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
float4 vs_main(uint id : SV_VertexID) : SV_Position {
    float2 p = float2(float((id << 1) & 2), float(id & 2));
    return float4(p * 2.0 - 1.0, 0.0, 1.0);
}
float ps_main(float4 position : SV_Position) : SV_Target0 {
    float4 a = lookup[int(position.x)];
    return sk_silmap_visibility(u_depth, u_silmap, a.xy, a.z, 0.0);
}
)";

constexpr int kSize = 64;

void run_silmap(Source lang) {
    skvk::Context& ctx = skvk::vk_test_context();
    const std::size_t before = skvk::message_count();
    std::vector<std::uint32_t> vs, fs;
    const char* entries[2] = {"main", "main"};
    if (lang == Source::Glsl) {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_GLSL_DIR) + "/silhouette_map.glsl");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, kFullscreenGlsl, "main", "silmap.glsl.vert");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, "#version 450 core\n" + snippet + kGlsl, "main",
                                   "silmap.glsl.frag");
    } else {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_HLSL_DIR) + "/silhouette_map.hlsl");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, snippet + kHlsl, "vs_main", "silmap.hlsl.vert");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, snippet + kHlsl, "ps_main", "silmap.hlsl.frag");
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
    skvk::Image zmap, smap;
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
    skvk::Buffer ssbo;
    REQUIRE(skvk::make_buffer(ctx, M * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, ssbo));
    std::memcpy(ssbo.mapped, pts.data(), M * sizeof(glm::vec4));
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

TEST_CASE("silhouette_map.glsl on Vulkan: sk_silmap_visibility equals silmap_lookup on synthetic maps") {
    run_silmap(Source::Glsl);
}

TEST_CASE("HLSL silhouette_map.hlsl on Vulkan: sk_silmap_visibility equals silmap_lookup on synthetic maps") {
    run_silmap(Source::Hlsl);
}
