// glsl/penumbra_wedge.glsl and hlsl/penumbra_wedge.hlsl RUN on Vulkan: sk_wedge_edge_coverage for
// 2048 random silhouette edges and receiver points under a sphere light, against
// shadowkit::penumbra_edge_coverage (the header's double-precision twin) with the GL test's
// tolerance (max 1e-4, mean 1e-6), and sk_wedge_world_from_depth with zero_to_one (Vulkan's window
// depth) against the inverse of a [0, 1] reversed-Z view-projection in double (relative 1e-4); one
// pixel per sample, no validation message.
#include <doctest/doctest.h>

#include <shadowkit/penumbra_wedge.hpp>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

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
// per sample: e0, e1, (p, -), (ndc.xy, window depth, -)
const char* kGlsl = R"(
layout(set = 0, binding = 0, std430) readonly buffer Samples { vec4 s[]; };
layout(set = 0, binding = 1, std140) uniform Params { mat4 inv_view_proj; vec4 light_position; vec4 radius; } u;
layout(location = 0) out vec4 o_value;
void main() {
    int i = int(gl_FragCoord.x);
    float c = sk_wedge_edge_coverage(s[4 * i].xyz, s[4 * i + 1].xyz, u.light_position, u.radius.x, s[4 * i + 2].xyz);
    vec3 w = sk_wedge_world_from_depth(u.inv_view_proj, s[4 * i + 3].xy, s[4 * i + 3].z, true);
    o_value = vec4(c, w);
}
)";
const char* kHlsl = R"(
[[vk::binding(0, 0)]] StructuredBuffer<float4> s;
struct Params { column_major float4x4 inv_view_proj; float4 light_position; float4 radius; };
[[vk::binding(1, 0)]] ConstantBuffer<Params> u;
float4 vs_main(uint id : SV_VertexID) : SV_Position {
    float2 p = float2(float((id << 1) & 2), float(id & 2));
    return float4(p * 2.0 - 1.0, 0.0, 1.0);
}
float4 ps_main(float4 position : SV_Position) : SV_Target0 {
    int i = int(position.x);
    float c = sk_wedge_edge_coverage(s[4 * i].xyz, s[4 * i + 1].xyz, u.light_position, u.radius.x, s[4 * i + 2].xyz);
    float3 w = sk_wedge_world_from_depth(u.inv_view_proj, s[4 * i + 3].xy, s[4 * i + 3].z, true);
    return float4(c, w);
}
)";

struct Params {
    glm::mat4 inv_view_proj;
    glm::vec4 light_position, radius;
};

void run_wedge(Source lang) {
    skvk::Context& ctx = skvk::vk_test_context();
    const std::size_t before = skvk::message_count();
    std::vector<std::uint32_t> vs, fs;
    const char* entries[2] = {"main", "main"};
    if (lang == Source::Glsl) {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_GLSL_DIR) + "/penumbra_wedge.glsl");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, kFullscreenGlsl, "main", "wedge.glsl.vert");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, "#version 450 core\n" + snippet + kGlsl, "main",
                                   "wedge.glsl.frag");
    } else {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_HLSL_DIR) + "/penumbra_wedge.hlsl");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, snippet + kHlsl, "vs_main", "wedge.hlsl.vert");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, snippet + kHlsl, "ps_main", "wedge.hlsl.frag");
        entries[0] = "vs_main";
        entries[1] = "ps_main";
    }
    // a sphere light of radius 0.5 at (0, 4, 0); edges around height 2, receivers on the ground
    const shadowkit::PenumbraSphereLight light{glm::vec4(0.f, 4.f, 0.f, 1.f), 0.5f};
    glm::mat4 proj = glm::perspectiveRH_ZO(0.9f, 4.f / 3.f, 0.1f, 50.f);
    glm::mat4 rev(1.f);
    rev[2][2] = -1.f;
    rev[3][2] = 1.f;
    const glm::mat4 view_proj = rev * proj * glm::lookAt(glm::vec3(0.f, 3.5f, 5.f), glm::vec3(0.f), glm::vec3(0.f, 1.f, 0.f));
    const glm::dmat4 inv = glm::inverse(glm::dmat4(view_proj));
    constexpr std::uint32_t M = 2048;
    std::mt19937 rng(2003);
    std::uniform_real_distribution<float> U(-1.f, 1.f), U01(0.f, 1.f);
    std::vector<glm::vec4> samples(std::size_t(M) * 4);
    for (std::uint32_t i = 0; i < M; ++i) {
        const glm::vec3 mid(U(rng), 2.f + 0.3f * U(rng), U(rng));
        const glm::vec3 dir = glm::normalize(glm::vec3(U(rng), 0.2f * U(rng), U(rng)));
        const glm::vec3 e0 = mid - dir * (0.5f + U01(rng)), e1 = mid + dir * (0.5f + U01(rng));
        // the receiver under the edge's hard shadow line, spread across its penumbra
        const glm::vec3 p(mid.x * 2.f + 0.6f * U(rng), 0.f, mid.z * 2.f + 0.6f * U(rng));
        samples[4 * i] = glm::vec4(e0, 0.f);
        samples[4 * i + 1] = glm::vec4(e1, 0.f);
        samples[4 * i + 2] = glm::vec4(p, 0.f);
        samples[4 * i + 3] = glm::vec4(U(rng), U(rng), 0.05f + 0.9f * U01(rng), 0.f);
    }
    const Params params{glm::inverse(view_proj), light.light_position, glm::vec4(light.radius)};
    skvk::Buffer ssbo, ubo;
    REQUIRE(skvk::make_buffer(ctx, samples.size() * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, ssbo));
    std::memcpy(ssbo.mapped, samples.data(), samples.size() * sizeof(glm::vec4));
    REQUIRE(skvk::make_buffer(ctx, sizeof(Params), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, ubo));
    std::memcpy(ubo.mapped, &params, sizeof params);
    skvk::Image target;
    REQUIRE(skvk::make_image(ctx, M, 1, 1, VK_FORMAT_R32G32B32A32_SFLOAT,
                             VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, target));
    VkRenderPass rp = skvk::make_render_pass(ctx, {VK_FORMAT_R32G32B32A32_SFLOAT}, VK_FORMAT_UNDEFINED, VK_IMAGE_LAYOUT_UNDEFINED);
    VkFramebuffer fb = skvk::make_framebuffer(ctx, rp, {target.view}, M, 1);
    skvk::DescriptorSet ds;
    REQUIRE(skvk::make_descriptor_set(ctx, {{0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_FRAGMENT_BIT},
                                            {1, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, VK_SHADER_STAGE_FRAGMENT_BIT}}, ds));
    skvk::write_buffer(ctx, ds, 0, ssbo, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
    skvk::write_buffer(ctx, ds, 1, ubo);
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
    const std::vector<float> gpu = skvk::read_image(ctx, target, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 4);
    REQUIRE(gpu.size() == std::size_t(M) * 4);

    double max_c = 0, sum_c = 0, max_w = 0;
    int nonzero = 0, positive = 0, negative = 0;
    for (std::uint32_t i = 0; i < M; ++i) {
        const shadowkit::PenumbraValue cpu = shadowkit::penumbra_edge_coverage(
            glm::vec3(samples[4 * i]), glm::vec3(samples[4 * i + 1]), light, glm::vec3(samples[4 * i + 2]));
        REQUIRE(cpu.status == shadowkit::Status::Ok);
        const double e = std::abs(double(gpu[4 * i]) - double(cpu.value));
        max_c = std::max(max_c, e);
        sum_c += e;
        nonzero += cpu.value != 0.f;
        positive += cpu.value > 0.f;
        negative += cpu.value < 0.f;
        const glm::dvec4 w = inv * glm::dvec4(samples[4 * i + 3].x, samples[4 * i + 3].y, samples[4 * i + 3].z, 1.0);
        const glm::dvec3 ref = glm::dvec3(w) / w.w;
        const glm::dvec3 got(gpu[4 * i + 1], gpu[4 * i + 2], gpu[4 * i + 3]);
        max_w = std::max(max_w, glm::length(got - ref) / std::max(glm::length(ref), 1.0));
    }
    MESSAGE((lang == Source::Glsl ? "GLSL" : "HLSL") << ": coverage max |GPU - CPU| " << max_c << ", mean " << sum_c / M << " ("
                                                    << nonzero << " of " << M << " non-zero: " << positive << " > 0, "
                                                    << negative << " < 0); world from depth max relative error " << max_w);
    CHECK(nonzero > int(M) / 4);
    CHECK(positive > 50);
    CHECK(negative > 50);
    CHECK(max_c < 1e-4);
    CHECK(sum_c / M < 1e-6);
    CHECK(max_w < 1e-4);
    CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());

    vkDestroyPipeline(ctx.device, pipe, nullptr);
    vkDestroyPipelineLayout(ctx.device, layout, nullptr);
    vkDestroyFramebuffer(ctx.device, fb, nullptr);
    vkDestroyRenderPass(ctx.device, rp, nullptr);
    skvk::destroy(ctx, ds);
    skvk::destroy(ctx, target);
    skvk::destroy(ctx, ssbo);
    skvk::destroy(ctx, ubo);
}

}  // namespace

TEST_CASE("penumbra_wedge.glsl on Vulkan: edge coverage equals penumbra_edge_coverage, world from [0,1] depth") {
    run_wedge(Source::Glsl);
}

TEST_CASE("HLSL penumbra_wedge.hlsl on Vulkan: edge coverage equals penumbra_edge_coverage, world from [0,1] depth") {
    run_wedge(Source::Hlsl);
}
