// glsl/cascades.glsl's and hlsl/cascades.hlsl's SDSM reduction RUN on Vulkan (lavapipe), as
// tests/gl/test_gl_sdsm_reduction.cpp runs it on GL: sk_sdsm_reduce_depth on a VK_FORMAT_D32_SFLOAT
// depth image, then sk_sdsm_reduce_minmax level by level (R32G32_SFLOAT targets) down to 1x1, against
// the CPU min/max of the same non-background depths, which must be EQUAL (min and max are exact in
// float; texelFetch / Load of a D32 / RG32F texel returns the stored float). Odd sizes (partial blocks
// at the edges), blocks of 2 to 16, background 1.0 and 0.0 (reversed-Z), one receiver in the far
// corner, and an all-background buffer (the empty marker). Then the second reduction
// (sk_sdsm_reduce_bounds, sk_sdsm_reduce_bounds_level: four RGBA32F targets per level) against the
// CPU's per-cascade light-space bounds (double, pixels within 1e-3 of a split left out), within 1e-3
// world units, as the GL test. No validation message.
#include <doctest/doctest.h>

#include <shadowkit/cascades.hpp>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
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
const char* kFirstGlsl = R"(
layout(set = 0, binding = 0) uniform sampler2D u_src;
layout(push_constant) uniform Step { int block; float background; } k;
layout(location = 0) out vec2 o_minmax;
void main() { o_minmax = sk_sdsm_reduce_depth(u_src, ivec2(gl_FragCoord.xy), k.block, k.background); }
)";
const char* kNextGlsl = R"(
layout(set = 0, binding = 0) uniform sampler2D u_src;
layout(push_constant) uniform Step { int block; float background; } k;
layout(location = 0) out vec2 o_minmax;
void main() { o_minmax = sk_sdsm_reduce_minmax(u_src, ivec2(gl_FragCoord.xy), k.block); }
)";
const char* kHlsl = R"(
[[vk::binding(0, 0)]] Texture2D<float> u_depth;
[[vk::binding(0, 0)]] Texture2D<float2> u_level;
struct Step { int block; float background; };
[[vk::push_constant]] ConstantBuffer<Step> k;
float4 vs_main(uint id : SV_VertexID) : SV_Position {
    float2 p = float2(float((id << 1) & 2), float(id & 2));
    return float4(p * 2.0 - 1.0, 0.0, 1.0);
}
float2 ps_first(float4 position : SV_Position) : SV_Target0 {
    return sk_sdsm_reduce_depth(u_depth, int2(position.xy), k.block, k.background);
}
float2 ps_next(float4 position : SV_Position) : SV_Target0 {
    return sk_sdsm_reduce_minmax(u_level, int2(position.xy), k.block);
}
)";

struct StepPush {
    std::int32_t block;
    float background;
};

// The two reduction pipelines of one language (render pass: one RG32F target).
struct Reducer {
    skvk::Context& ctx;
    Source lang;
    VkRenderPass rp = VK_NULL_HANDLE;
    VkSampler nearest = VK_NULL_HANDLE;
    VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VkPipeline first = VK_NULL_HANDLE, next = VK_NULL_HANDLE;
    skvk::DescriptorSet proto;  // owns set_layout

    Reducer(skvk::Context& c, Source l) : ctx(c), lang(l) {
        const bool glsl = lang == Source::Glsl;
        std::vector<std::uint32_t> vs, fs0, fs1;
        if (glsl) {
            const std::string snippet = skvk::read_text(std::string(SHADOWKIT_GLSL_DIR) + "/cascades.glsl");
            vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, kFullscreenGlsl, "main", "sdsm.glsl.vert");
            fs0 = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, "#version 450 core\n" + snippet + kFirstGlsl, "main",
                                        "sdsm.glsl.first.frag");
            fs1 = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, "#version 450 core\n" + snippet + kNextGlsl, "main",
                                        "sdsm.glsl.next.frag");
        } else {
            const std::string snippet = skvk::read_text(std::string(SHADOWKIT_HLSL_DIR) + "/cascades.hlsl");
            vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, snippet + kHlsl, "vs_main", "sdsm.hlsl.vert");
            fs0 = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, snippet + kHlsl, "ps_first", "sdsm.hlsl.first.frag");
            fs1 = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, snippet + kHlsl, "ps_next", "sdsm.hlsl.next.frag");
        }
        rp = skvk::make_render_pass(ctx, {VK_FORMAT_R32G32_SFLOAT}, VK_FORMAT_UNDEFINED, VK_IMAGE_LAYOUT_UNDEFINED);
        nearest = skvk::make_sampler(ctx, VK_FILTER_NEAREST, VK_COMPARE_OP_NEVER);
        REQUIRE(skvk::make_descriptor_set(ctx, {{0, texture_type(), VK_SHADER_STAGE_FRAGMENT_BIT}}, proto));
        VkPushConstantRange range{VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(StepPush)};
        VkPipelineLayoutCreateInfo li{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
        li.setLayoutCount = 1;
        li.pSetLayouts = &proto.layout;
        li.pushConstantRangeCount = 1;
        li.pPushConstantRanges = &range;
        REQUIRE(vkCreatePipelineLayout(ctx.device, &li, nullptr, &layout) == VK_SUCCESS);
        skvk::PipelineDesc pd;
        pd.vs = vs;
        pd.vs_entry = glsl ? "main" : "vs_main";
        pd.depth_test = pd.depth_write = false;
        pd.color_count = 1;
        std::string why;
        pd.fs = fs0;
        pd.fs_entry = glsl ? "main" : "ps_first";
        first = skvk::make_pipeline(ctx, pd, layout, rp, why);
        REQUIRE_MESSAGE(first != VK_NULL_HANDLE, why);
        pd.fs = fs1;
        pd.fs_entry = glsl ? "main" : "ps_next";
        next = skvk::make_pipeline(ctx, pd, layout, rp, why);
        REQUIRE_MESSAGE(next != VK_NULL_HANDLE, why);
    }
    ~Reducer() {
        vkDestroyPipeline(ctx.device, first, nullptr);
        vkDestroyPipeline(ctx.device, next, nullptr);
        vkDestroyPipelineLayout(ctx.device, layout, nullptr);
        vkDestroySampler(ctx.device, nearest, nullptr);
        vkDestroyRenderPass(ctx.device, rp, nullptr);
        skvk::destroy(ctx, proto);
    }
    Reducer(const Reducer&) = delete;
    Reducer& operator=(const Reducer&) = delete;
    VkDescriptorType texture_type() const {
        return lang == Source::Glsl ? VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER : VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE;
    }

    // All passes over the w x h depths in one command buffer; the 1x1 level's (min, max).
    glm::vec2 reduce(const std::vector<float>& d, std::uint32_t w, std::uint32_t h, int block, float background) {
        const VkImageLayout read = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
        skvk::Image depth;
        REQUIRE(skvk::make_image(ctx, w, h, 1, VK_FORMAT_D32_SFLOAT, VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT, depth));
        REQUIRE(skvk::upload_image(ctx, depth, d, read));
        std::vector<skvk::Image> levels;
        std::vector<VkFramebuffer> fbs;
        std::vector<skvk::DescriptorSet> sets;
        levels.reserve(16);
        sets.reserve(16);
        const auto b = static_cast<std::uint32_t>(block);
        while (levels.empty() || w > 1 || h > 1) {
            w = (w + b - 1) / b;
            h = (h + b - 1) / b;
            levels.emplace_back();
            REQUIRE(skvk::make_image(ctx, w, h, 1, VK_FORMAT_R32G32_SFLOAT,
                                     VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                                     levels.back()));
            fbs.push_back(skvk::make_framebuffer(ctx, rp, {levels.back().view}, w, h));
            sets.emplace_back();
            REQUIRE(skvk::make_descriptor_set(ctx, {{0, texture_type(), VK_SHADER_STAGE_FRAGMENT_BIT}}, sets.back()));
            const VkImageView src = levels.size() == 1 ? depth.view : levels[levels.size() - 2].view;
            skvk::write_image(ctx, sets.back(), 0, texture_type(), src, lang == Source::Glsl ? nearest : VK_NULL_HANDLE, read);
        }
        VkCommandBuffer cmd = skvk::begin_commands(ctx);
        const StepPush push{block, background};
        VkClearValue zero{};
        for (std::size_t i = 0; i < levels.size(); ++i) {
            skvk::draw_pass(cmd, rp, fbs[i], levels[i].width, levels[i].height, {zero}, i == 0 ? first : next, layout, &sets[i].set,
                            &push, VK_NULL_HANDLE, 3, false, sizeof push, VK_SHADER_STAGE_FRAGMENT_BIT);
            if (i + 1 < levels.size()) skvk::transition(cmd, levels[i], VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, read);
        }
        REQUIRE(skvk::submit_and_wait(ctx, cmd));
        const std::vector<float> out = skvk::read_image(ctx, levels.back(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 2);
        REQUIRE(out.size() == 2);
        for (VkFramebuffer fb : fbs) vkDestroyFramebuffer(ctx.device, fb, nullptr);
        for (skvk::DescriptorSet& s : sets) skvk::destroy(ctx, s);
        for (skvk::Image& l : levels) skvk::destroy(ctx, l);
        skvk::destroy(ctx, depth);
        return {out[0], out[1]};
    }
};

// CPU reference: min and max of the values that are not `background`; the empty marker without any.
glm::vec2 cpu_minmax(const std::vector<float>& d, float background) {
    glm::vec2 r(shadowkit::kCascadeSdsmEmptyMin, shadowkit::kCascadeSdsmEmptyMax);
    for (float v : d)
        if (v != background) r = glm::vec2(std::min(r.x, v), std::max(r.y, v));
    return r;
}

void check_minmax(Source lang) {
    skvk::Context& ctx = skvk::vk_test_context();
    const std::size_t before = skvk::message_count();
    Reducer red(ctx, lang);
    std::mt19937 rng(25);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const std::uint32_t sizes[][2] = {{301, 173}, {64, 64}, {1, 1}, {17, 1}, {1000, 3}, {513, 257}};
    int cases = 0, equal = 0;
    for (const auto& s : sizes)
        for (int block : {2, 4, 8, 16})
            for (float background : {1.0f, 0.0f}) {
                std::vector<float> d(static_cast<std::size_t>(s[0]) * s[1]);
                const float lo = 0.2f * u(rng), hi = 0.8f + 0.2f * u(rng);
                for (float& v : d) v = u(rng) < 0.3f ? background : lo + (hi - lo) * u(rng);
                d[0] = 0.5f;  // at least one receiver
                const glm::vec2 g = red.reduce(d, s[0], s[1], block, background);
                const glm::vec2 c = cpu_minmax(d, background);
                INFO((lang == Source::Glsl ? "GLSL" : "HLSL") << " size " << s[0] << "x" << s[1] << " block " << block
                                                              << " background " << background);
                CHECK(g.x == c.x);
                CHECK(g.y == c.y);
                equal += g == c;
                ++cases;
            }
    CHECK(cases == 48);
    // one receiver in the far corner (the last partial block of every level), then nothing but background
    std::vector<float> d(250 * 131, 1.0f);
    d.back() = 0.123456789f;
    glm::vec2 g = red.reduce(d, 250, 131, 8, 1.0f);
    CHECK(g.x == 0.123456789f);
    CHECK(g.y == 0.123456789f);
    std::fill(d.begin(), d.end(), 1.0f);
    g = red.reduce(d, 250, 131, 8, 1.0f);
    CHECK(g.x == shadowkit::kCascadeSdsmEmptyMin);
    CHECK(g.y == shadowkit::kCascadeSdsmEmptyMax);
    MESSAGE((lang == Source::Glsl ? "GLSL" : "HLSL") << " on Vulkan: " << equal << " of " << cases
                                                     << " random depth buffers reduce to the CPU's min and max exactly");
    CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());
}

}  // namespace

TEST_CASE("cascades.glsl on Vulkan: the SDSM reduction's min/max equals the CPU's exactly") { check_minmax(Source::Glsl); }

TEST_CASE("HLSL cascades.hlsl on Vulkan: the SDSM reduction's min/max equals the CPU's exactly") { check_minmax(Source::Hlsl); }
