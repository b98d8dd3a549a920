// glsl/prefiltered_shadow.glsl and hlsl/prefiltered_shadow.hlsl RUN on Vulkan: sk_prefilter_visibility
// for every method (VSM, ESM, EVSM2, EVSM4, MSM Hamburger and Hausdorff, MSM also quantized) on 2,048
// filtered moments each (the mean of prefilter_moments over one to three random depths, as a blur
// makes them) and random receiver depths, against the CPU mirror shadowkit::prefilter_visibility: at
// most 1% of the lookups may differ by more than 1e-3 (float solves near a root), every value in
// [0, 1]. The moment, blur, resolve and soft passes are compiled, not run. No validation message.
#include <doctest/doctest.h>

#include <shadowkit/prefiltered_shadow.hpp>

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
float4 vs_main(uint id : SV_VertexID) : SV_Position {
    float2 p = float2(float((id << 1) & 2), float(id & 2));
    return float4(p * 2.0 - 1.0, 0.0, 1.0);
}
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
    const std::size_t before = skvk::message_count();
    std::vector<std::uint32_t> vs, fs;
    const char* entries[2] = {"main", "main"};
    if (lang == Source::Glsl) {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_GLSL_DIR) + "/prefiltered_shadow.glsl");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, kFullscreenGlsl, "main", "prefiltered.glsl.vert");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, "#version 450 core\n" + snippet + kGlsl, "main",
                                   "prefiltered.glsl.frag");
    } else {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_HLSL_DIR) + "/prefiltered_shadow.hlsl");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, snippet + kHlsl, "vs_main", "prefiltered.hlsl.vert");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, snippet + kHlsl, "ps_main", "prefiltered.hlsl.frag");
        entries[0] = "vs_main";
        entries[1] = "ps_main";
    }
    constexpr std::uint32_t M = 2048;
    skvk::Buffer ssbo;
    REQUIRE(skvk::make_buffer(ctx, M * 2 * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, ssbo));
    skvk::Image target;
    REQUIRE(skvk::make_image(ctx, M, 1, 1, VK_FORMAT_R32_SFLOAT, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                             target));
    VkRenderPass rp = skvk::make_render_pass(ctx, {VK_FORMAT_R32_SFLOAT}, VK_FORMAT_UNDEFINED, VK_IMAGE_LAYOUT_UNDEFINED);
    VkFramebuffer fb = skvk::make_framebuffer(ctx, rp, {target.view}, M, 1);
    skvk::DescriptorSet ds;
    REQUIRE(skvk::make_descriptor_set(ctx, {{0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_FRAGMENT_BIT}}, ds));
    skvk::write_buffer(ctx, ds, 0, ssbo, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
    VkPushConstantRange range{VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(CasePush)};
    VkPipelineLayoutCreateInfo li{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    li.setLayoutCount = 1;
    li.pSetLayouts = &ds.layout;
    li.pushConstantRangeCount = 1;
    li.pPushConstantRanges = &range;
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
        VkCommandBuffer cmd = skvk::begin_commands(ctx);
        VkClearValue zero{};
        skvk::draw_pass(cmd, rp, fb, M, 1, {zero}, pipe, layout, &ds.set, &cp, VK_NULL_HANDLE, 3, false, sizeof cp,
                        VK_SHADER_STAGE_FRAGMENT_BIT);
        REQUIRE(skvk::submit_and_wait(ctx, cmd));
        const std::vector<float> gpu = skvk::read_image(ctx, target, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 1);
        REQUIRE(gpu.size() == M);
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
    }
    CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());

    vkDestroyPipeline(ctx.device, pipe, nullptr);
    vkDestroyPipelineLayout(ctx.device, layout, nullptr);
    vkDestroyFramebuffer(ctx.device, fb, nullptr);
    vkDestroyRenderPass(ctx.device, rp, nullptr);
    skvk::destroy(ctx, ds);
    skvk::destroy(ctx, target);
    skvk::destroy(ctx, ssbo);
}

}  // namespace

TEST_CASE("prefiltered_shadow.glsl on Vulkan: sk_prefilter_visibility of every method equals prefilter_visibility") {
    run_prefiltered(Source::Glsl);
}

TEST_CASE("HLSL prefiltered_shadow.hlsl on Vulkan: sk_prefilter_visibility of every method equals prefilter_visibility") {
    run_prefiltered(Source::Hlsl);
}
