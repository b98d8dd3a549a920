// glsl/contact_shadow.glsl and hlsl/contact_shadow.hlsl RUN on Vulkan: the scene of
// tests/gl/test_gl_contact_shadow.cpp (a floor and a box on it) is rendered into a VK_FORMAT_D32_SFLOAT
// depth image by a [0, 1] camera with the negative-height viewport; a full-screen pass runs
// sk_contact_shadow and sk_contact_shadow_aligned at every pixel (view position rebuilt by
// sk_contact_view_position) with zero_to_one and the matrix whose NDC y runs with the stored rows
// (flip_y * proj, the rule of docs/vulkan_and_direct3d.md); the read-back visibility must equal the CPU
// mirrors contact_shadow_march / contact_shadow_march_aligned (ClipDepth::ZeroToOne, Float32) run on
// the read-back depth on >= 99.9% of the pixels (the GL test's tolerance), and the box must occlude
// part of the floor. Reversed-Z runs the same with the camera of infinite_projection.hpp's
// projection_perspective_finite(..., ZeroToOne, reversed_z = true), depth cleared to 0 and drawn with
// GREATER, the snippet after #define SK_REVERSED_Z and the mirrors with reversed_z; its picture must
// also equal the standard run's on >= 99.5% of the foreground. No validation message.
#include <doctest/doctest.h>

#include <shadowkit/contact_shadow.hpp>
#include <shadowkit/infinite_projection.hpp>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <cstring>
#include <string>
#include <vector>

#include "vk_harness.hpp"
#include "vk_passes.hpp"

namespace {

using skvk::Source;

constexpr std::uint32_t kW = 256, kH = 192;

const char* kPassGlsl = R"(
layout(set = 0, binding = 0) uniform sampler2D u_depth;
layout(set = 0, binding = 1, std140) uniform Params { mat4 proj; mat4 inv_proj; vec4 view_light; vec4 march; } u;
layout(location = 0) out vec2 o_v;   // x: sk_contact_shadow, y: sk_contact_shadow_aligned; -1: background
void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    ivec2 size = textureSize(u_depth, 0);
    float win = texelFetch(u_depth, px, 0).r;
#ifdef SK_REVERSED_Z
    if (win == 0.0) { o_v = vec2(-1.0); return; }
#else
    if (win == 1.0) { o_v = vec2(-1.0); return; }
#endif
    vec3 view_pos = sk_contact_view_position(u.inv_proj, size, px, win, true);
    int steps = int(u.march.y);
    o_v = vec2(sk_contact_shadow(u_depth, u.proj, view_pos, u.view_light, u.march.x, steps, 0.0, 0.0, true, 0.0),
               sk_contact_shadow_aligned(u_depth, u.proj, view_pos, u.view_light, u.march.x, steps, 0.0, 0.0, true, 0.0));
}
)";
const char* kPassHlsl = R"(
[[vk::binding(0, 0)]] Texture2D<float> u_depth;
struct Params { column_major float4x4 proj; column_major float4x4 inv_proj; float4 view_light; float4 march; };
[[vk::binding(1, 0)]] ConstantBuffer<Params> u;
float2 ps_main(float4 position : SV_Position) : SV_Target0 {
    int2 px = int2(position.xy);
    uint w, h;
    u_depth.GetDimensions(w, h);
    float win = u_depth.Load(int3(px, 0));
#ifdef SK_REVERSED_Z
    if (win == 0.0) return float2(-1.0, -1.0);
#else
    if (win == 1.0) return float2(-1.0, -1.0);
#endif
    float3 view_pos = sk_contact_view_position(u.inv_proj, int2(w, h), px, win, true);
    int steps = int(u.march.y);
    return float2(sk_contact_shadow(u_depth, u.proj, view_pos, u.view_light, u.march.x, steps, 0.0, 0.0, true, 0.0),
                  sk_contact_shadow_aligned(u_depth, u.proj, view_pos, u.view_light, u.march.x, steps, 0.0, 0.0, true, 0.0));
}
)";

struct Params {
    glm::mat4 proj, inv_proj;
    glm::vec4 view_light, march;
};

void quad(std::vector<glm::vec3>& v, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d) {
    for (const glm::vec3& p : {a, b, c, a, c, d}) v.push_back(p);
}

// reversed: the camera from projection_perspective_finite(..., ZeroToOne, reversed_z), depth cleared to 0
// and drawn with GREATER, the snippet after #define SK_REVERSED_Z, the mirrors with reversed_z.
std::vector<float> run_contact(Source lang, bool reversed = false) {
    skvk::Context& ctx = skvk::vk_test_context();
    skvk::Scope scope(ctx);
    const std::size_t before = skvk::message_count();
    std::vector<std::uint32_t> scene_vs, vs, fs;
    const char* entries[2] = {"main", "main"};
    scene_vs = skvk::compile_checked(Source::Glsl, VK_SHADER_STAGE_VERTEX_BIT, skvk::kSceneDepthGlsl, "main", "contact.scene.vert");
    if (lang == Source::Glsl) {
        const std::string snippet = std::string(reversed ? "#define SK_REVERSED_Z 1\n" : "") +
                                    skvk::read_text(std::string(SHADOWKIT_GLSL_DIR) + "/contact_shadow.glsl");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, skvk::kFullscreenGlsl, "main", "contact.glsl.vert");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, "#version 450 core\n" + snippet + kPassGlsl, "main",
                                   reversed ? "contact_rz.glsl.frag" : "contact.glsl.frag");
    } else {
        const std::string snippet = std::string(reversed ? "#define SK_REVERSED_Z 1\n" : "") +
                                    skvk::read_text(std::string(SHADOWKIT_HLSL_DIR) + "/contact_shadow.hlsl");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, snippet + skvk::kFullscreenHlsl + kPassHlsl, "vs_main", "contact.hlsl.vert");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, snippet + skvk::kFullscreenHlsl + kPassHlsl, "ps_main",
                                   reversed ? "contact_rz.hlsl.frag" : "contact.hlsl.frag");
        entries[0] = "vs_main";
        entries[1] = "ps_main";
    }
    // the GL test's scene: a floor and a box on it
    const glm::vec3 l(-0.5f, 0.f, -0.4f), h(0.5f, 0.7f, 0.4f);
    std::vector<glm::vec3> tris;
    quad(tris, {-6, 0, -6}, {-6, 0, 6}, {6, 0, 6}, {6, 0, -6});
    quad(tris, {l.x, h.y, l.z}, {l.x, h.y, h.z}, {h.x, h.y, h.z}, {h.x, h.y, l.z});
    quad(tris, {l.x, l.y, h.z}, {h.x, l.y, h.z}, {h.x, h.y, h.z}, {l.x, h.y, h.z});
    quad(tris, {l.x, l.y, l.z}, {l.x, h.y, l.z}, {h.x, h.y, l.z}, {h.x, l.y, l.z});
    quad(tris, {h.x, l.y, l.z}, {h.x, h.y, l.z}, {h.x, h.y, h.z}, {h.x, l.y, h.z});
    quad(tris, {l.x, l.y, l.z}, {l.x, l.y, h.z}, {l.x, h.y, h.z}, {l.x, h.y, l.z});
    const glm::mat4 view = glm::lookAt(glm::vec3(2.2f, 2.0f, 3.2f), glm::vec3(0.0f, 0.2f, 0.0f), glm::vec3(0, 1, 0));
    const shadowkit::ProjectionResult rz =
        shadowkit::projection_perspective_finite(0.9f, float(kW) / float(kH), 0.1f, 40.0f, shadowkit::ClipDepth::ZeroToOne, true);
    REQUIRE(rz.status == shadowkit::Status::Ok);
    const glm::mat4 proj = reversed ? rz.matrix : glm::perspectiveRH_ZO(0.9f, float(kW) / float(kH), 0.1f, 40.0f);
    glm::mat4 flip(1.f);
    flip[1][1] = -1.f;
    const glm::mat4 proj_rows = flip * proj;  // NDC y runs with the rows the negative-height viewport stores
    const glm::vec4 view_light = view * glm::vec4(glm::normalize(glm::vec3(-0.5f, 0.6f, -0.3f)), 0.f);
    shadowkit::ContactShadowParams prm;
    prm.length_world = 0.5f;
    prm.max_steps = 32;
    prm.depth_format = shadowkit::DepthFormat::Float32;
    prm.clip_depth = shadowkit::ClipDepth::ZeroToOne;
    prm.reversed_z = reversed;
    const Params params{proj_rows, glm::inverse(proj_rows), view_light, glm::vec4(prm.length_world, float(prm.max_steps), 0.f, 0.f)};

    skvk::Buffer& vb = scope.own<skvk::Buffer>();
    skvk::Buffer& ubo = scope.own<skvk::Buffer>();
    REQUIRE(skvk::make_buffer(ctx, sizeof(glm::vec3) * tris.size(), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, vb));
    std::memcpy(vb.mapped, tris.data(), sizeof(glm::vec3) * tris.size());
    REQUIRE(skvk::make_buffer(ctx, sizeof(Params), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, ubo));
    std::memcpy(ubo.mapped, &params, sizeof params);
    skvk::Image& depth = scope.own<skvk::Image>();
    skvk::Image& target = scope.own<skvk::Image>();
    REQUIRE(skvk::make_image(ctx, kW, kH, 1, VK_FORMAT_D32_SFLOAT,
                             VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                             depth));
    REQUIRE(skvk::make_image(ctx, kW, kH, 1, VK_FORMAT_R32G32_SFLOAT,
                             VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, target));
    const VkImageLayout depth_read = VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL;
    VkRenderPass scene_rp = scope.keep(skvk::make_render_pass(ctx, {}, VK_FORMAT_D32_SFLOAT, depth_read), vkDestroyRenderPass);
    VkFramebuffer scene_fb = scope.keep(skvk::make_framebuffer(ctx, scene_rp, {depth.view}, kW, kH), vkDestroyFramebuffer);
    VkPipelineLayout scene_layout = scope.keep(skvk::make_pipeline_layout(ctx, nullptr, sizeof(glm::mat4)), vkDestroyPipelineLayout);
    skvk::PipelineDesc sd;
    sd.vs = scene_vs;
    sd.vertex_stride = sizeof(glm::vec3);
    sd.attributes = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0}};
    sd.depth_compare = reversed ? VK_COMPARE_OP_GREATER : VK_COMPARE_OP_LESS;
    VkPipeline scene_pipe = scope.keep(skvk::make_pipeline_checked(ctx, sd, scene_layout, scene_rp), vkDestroyPipeline);

    VkRenderPass rp = scope.keep(skvk::make_render_pass(ctx, {VK_FORMAT_R32G32_SFLOAT}, VK_FORMAT_UNDEFINED, VK_IMAGE_LAYOUT_UNDEFINED), vkDestroyRenderPass);
    VkFramebuffer fb = scope.keep(skvk::make_framebuffer(ctx, rp, {target.view}, kW, kH), vkDestroyFramebuffer);
    VkSampler nearest = scope.keep(skvk::make_sampler(ctx, VK_FILTER_NEAREST, VK_COMPARE_OP_NEVER), vkDestroySampler);
    skvk::DescriptorSet& ds = scope.own<skvk::DescriptorSet>();
    const VkShaderStageFlags frag = VK_SHADER_STAGE_FRAGMENT_BIT;
    const VkDescriptorType tex = skvk::texture_type(lang);
    REQUIRE(skvk::make_descriptor_set(ctx, {{0, tex, frag}, {1, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, frag}}, ds));
    skvk::write_image(ctx, ds, 0, tex, depth.view, lang == Source::Glsl ? nearest : VK_NULL_HANDLE, depth_read);
    skvk::write_buffer(ctx, ds, 1, ubo);
    VkPipelineLayout layout = scope.keep(skvk::make_pipeline_layout(ctx, &ds), vkDestroyPipelineLayout);
    skvk::PipelineDesc pd;
    pd.vs = vs;
    pd.fs = fs;
    pd.vs_entry = entries[0];
    pd.fs_entry = entries[1];
    pd.depth_test = pd.depth_write = false;
    pd.color_count = 1;
    VkPipeline pipe = scope.keep(skvk::make_pipeline_checked(ctx, pd, layout, rp), vkDestroyPipeline);

    VkCommandBuffer cmd = skvk::begin_commands(ctx);
    VkClearValue far{};
    far.depthStencil = {reversed ? 0.f : 1.f, 0};
    const glm::mat4 vp = proj * view;  // drawn with the negative-height viewport
    skvk::draw_pass(cmd, scene_rp, scene_fb, kW, kH, {far}, scene_pipe, scene_layout, nullptr, &vp, vb.buffer,
                    static_cast<std::uint32_t>(tris.size()), true);
    VkClearValue zero{};
    skvk::draw_pass(cmd, rp, fb, kW, kH, {zero}, pipe, layout, &ds.set, nullptr, VK_NULL_HANDLE, 3, false);
    REQUIRE(skvk::submit_and_wait(ctx, cmd));
    const std::vector<float> d = skvk::read_image(ctx, depth, depth_read, 1);
    const std::vector<float> gpu = skvk::read_image(ctx, target, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 2);
    REQUIRE(d.size() == std::size_t(kW) * kH);

    const glm::mat4 inv = glm::inverse(proj_rows);
    std::size_t fg = 0, agree[2] = {0, 0}, occluded[2] = {0, 0};
    for (std::uint32_t y = 0; y < kH; ++y)
        for (std::uint32_t x = 0; x < kW; ++x) {
            const std::size_t k = std::size_t(y) * kW + x;
            if (d[k] == (reversed ? 0.f : 1.f)) continue;
            ++fg;
            const glm::vec2 ndc = (glm::vec2(float(x), float(y)) + 0.5f) / glm::vec2(float(kW), float(kH)) * 2.0f - 1.0f;
            const glm::vec4 c = inv * glm::vec4(ndc, d[k], 1.f);
            const glm::vec3 view_pos = glm::vec3(c) / c.w;
            const shadowkit::ContactShadowResult a =
                shadowkit::contact_shadow_march(d.data(), d.size(), int(kW), int(kH), proj_rows, view_pos, view_light, prm);
            const shadowkit::ContactShadowResult b =
                shadowkit::contact_shadow_march_aligned(d.data(), d.size(), int(kW), int(kH), proj_rows, view_pos, view_light, prm);
            agree[0] += a.status == shadowkit::Status::Ok && a.visibility == gpu[2 * k];
            agree[1] += b.status == shadowkit::Status::Ok && b.visibility == gpu[2 * k + 1];
            occluded[0] += gpu[2 * k] == 0.f;
            occluded[1] += gpu[2 * k + 1] == 0.f;
        }
    MESSAGE((lang == Source::Glsl ? "GLSL" : "HLSL") << std::string(reversed ? " reversed-Z" : "") << ": " << fg
                                                    << " foreground pixels; march agrees with its CPU mirror on "
                                                    << agree[0] << " (" << occluded[0] << " occluded), aligned march on " << agree[1]
                                                    << " (" << occluded[1] << " occluded)");
    CHECK(fg > kW * kH / 2);
    CHECK(double(agree[0]) >= 0.999 * double(fg));
    CHECK(double(agree[1]) >= 0.999 * double(fg));
    CHECK(occluded[0] > fg / 50);
    CHECK(occluded[1] > fg / 50);
    CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());

    return gpu;
}

// Reversed-Z: both marches equal their mirrors (reversed_z) on the reversed depth, and the picture
// equals the standard run's at nearly every pixel (the two depth encodings round differently).
void run_reversed(Source lang) {
    const std::vector<float> standard = run_contact(lang, false), reversed = run_contact(lang, true);
    REQUIRE(standard.size() == reversed.size());
    std::size_t fg = 0, same[2] = {0, 0};
    for (std::size_t k = 0; k < standard.size() / 2; ++k) {
        if (standard[2 * k] < 0.f) continue;
        ++fg;
        for (int m = 0; m < 2; ++m) same[m] += standard[2 * k + std::size_t(m)] == reversed[2 * k + std::size_t(m)];
    }
    MESSAGE((lang == Source::Glsl ? "GLSL" : "HLSL") << ": reversed-Z equals the standard run on " << same[0] << " (march) and "
                                                    << same[1] << " (aligned) of " << fg << " foreground pixels");
    CHECK(fg > kW * kH / 2);
    CHECK(double(same[0]) >= 0.995 * double(fg));
    CHECK(double(same[1]) >= 0.995 * double(fg));
}

}  // namespace

TEST_CASE("contact_shadow.glsl on Vulkan: both marches on a [0,1] depth image equal their CPU mirrors") {
    run_contact(Source::Glsl);
}

TEST_CASE("HLSL contact_shadow.hlsl on Vulkan: both marches on a [0,1] depth image equal their CPU mirrors") {
    run_contact(Source::Hlsl);
}

TEST_CASE("reversed-Z contact_shadow.glsl on Vulkan: both marches on a reversed [0,1] depth image equal their CPU mirrors") {
    run_reversed(Source::Glsl);
}

TEST_CASE("HLSL reversed-Z contact_shadow.hlsl on Vulkan: both marches on a reversed [0,1] depth image equal their CPU mirrors") {
    run_reversed(Source::Hlsl);
}
