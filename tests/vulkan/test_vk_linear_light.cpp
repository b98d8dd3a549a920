// glsl/linear_light.glsl and hlsl/linear_light.hlsl RUN on Vulkan: the lookup sk_linear_light_visibility
// (both endpoints' depth-map tests and visibility-map reads) on synthetic 32 x 32 maps for a segment
// light, 2,048 random receivers, against a CPU evaluation of the two endpoint terms written from the
// snippet's comment, combined by shadowkit::linear_light_shade (clamped to 1 as the snippet does): at most 0.5% may differ by more than
// 1e-5 (a receiver on a texel boundary or a depth tie within float rounding). The matrices are the GL
// ([-1, 1]) ones the snippet takes. The skin pass is compiled, not run. No validation message.
#include <doctest/doctest.h>

#include <shadowkit/linear_light.hpp>

#include <glm/gtc/matrix_transform.hpp>

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
float4 vs_main(uint id : SV_VertexID) : SV_Position {
    float2 p = float2(float((id << 1) & 2), float(id & 2));
    return float4(p * 2.0 - 1.0, 0.0, 1.0);
}
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
    const std::size_t before = skvk::message_count();
    std::vector<std::uint32_t> vs, fs;
    const char* entries[2] = {"main", "main"};
    if (lang == Source::Glsl) {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_GLSL_DIR) + "/linear_light.glsl");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, kFullscreenGlsl, "main", "linear_light.glsl.vert");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, "#version 450 core\n" + snippet + kGlsl, "main",
                                   "linear_light.glsl.frag");
    } else {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_HLSL_DIR) + "/linear_light.hlsl");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, snippet + kHlsl, "vs_main", "linear_light.hlsl.vert");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, snippet + kHlsl, "ps_main", "linear_light.hlsl.frag");
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
    skvk::Image dmap[2], vmap[2];
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
    skvk::Buffer ssbo, ubo;
    REQUIRE(skvk::make_buffer(ctx, pts.size() * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, ssbo));
    std::memcpy(ssbo.mapped, pts.data(), pts.size() * sizeof(glm::vec4));
    REQUIRE(skvk::make_buffer(ctx, sizeof(Params), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, ubo));
    std::memcpy(ubo.mapped, &params, sizeof params);
    skvk::Image target;
    REQUIRE(skvk::make_image(ctx, M, 1, 1, VK_FORMAT_R32_SFLOAT, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                             target));
    VkRenderPass rp = skvk::make_render_pass(ctx, {VK_FORMAT_R32_SFLOAT}, VK_FORMAT_UNDEFINED, VK_IMAGE_LAYOUT_UNDEFINED);
    VkFramebuffer fb = skvk::make_framebuffer(ctx, rp, {target.view}, M, 1);
    VkSampler nearest = skvk::make_sampler(ctx, VK_FILTER_NEAREST, VK_COMPARE_OP_NEVER);
    skvk::DescriptorSet ds;
    const VkShaderStageFlags frag = VK_SHADER_STAGE_FRAGMENT_BIT;
    const VkDescriptorType tex = lang == Source::Glsl ? VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER : VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE;
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

    vkDestroyPipeline(ctx.device, pipe, nullptr);
    vkDestroyPipelineLayout(ctx.device, layout, nullptr);
    vkDestroySampler(ctx.device, nearest, nullptr);
    vkDestroyFramebuffer(ctx.device, fb, nullptr);
    vkDestroyRenderPass(ctx.device, rp, nullptr);
    skvk::destroy(ctx, ds);
    for (skvk::Image* i : {&dmap[0], &dmap[1], &vmap[0], &vmap[1], &target}) skvk::destroy(ctx, *i);
    skvk::destroy(ctx, ssbo);
    skvk::destroy(ctx, ubo);
}

}  // namespace

TEST_CASE("linear_light.glsl on Vulkan: sk_linear_light_visibility equals its CPU evaluation on synthetic maps") {
    run_linear(Source::Glsl);
}

TEST_CASE("HLSL linear_light.hlsl on Vulkan: sk_linear_light_visibility equals its CPU evaluation on synthetic maps") {
    run_linear(Source::Hlsl);
}
