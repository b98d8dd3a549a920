// glsl/cascades.glsl and hlsl/cascades.hlsl RUN on Vulkan: four cascades from shadowkit::cascade_fit
// (ClipDepth::ZeroToOne, standard and reversed-Z, a directional light) rendered into the four layers
// of one VK_FORMAT_D32_SFLOAT array (a render pass per layer, plain viewport: the lookup takes each
// cascade's view_proj as it is, the first row of docs/vulkan_and_direct3d.md's table), then a camera
// pass (negative-height viewport) calling sk_cascade_shadow with the blend band; every receiver pixel
// is compared with the CPU ray cast toward the light (tests/gl/test_gl_shadow_map_e2e.cpp's test and
// tolerance: >= 99.5% away from shadow edges), at least three cascades must each hold 1% of the pixels,
// and the validation layer must report nothing.
#include <doctest/doctest.h>

#include <shadowkit/cascades.hpp>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "vk_harness.hpp"
#include "vk_passes.hpp"
#include "vk_scene.hpp"

namespace {

using skvk::Source;


// Params: params.x = cascade count, .y = blend band, .z = bias.
const char* kReceiverGlslVs = R"(#version 450 core
layout(set = 0, binding = 1, std140) uniform Params {
    mat4 view_proj; mat4 view; mat4 light_vp[4]; vec4 split_near; vec4 split_far; vec4 params;
} u;
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 0) out vec3 v_world;
layout(location = 1) out vec3 v_normal;
layout(location = 2) out float v_view_depth;
void main() {
    v_world = a_position;
    v_normal = a_normal;
    v_view_depth = -(u.view * vec4(a_position, 1.0)).z;
    gl_Position = u.view_proj * vec4(a_position, 1.0);
}
)";
const char* kReceiverGlslFs = R"(
layout(set = 0, binding = 0) uniform sampler2DArrayShadow u_cascades;
layout(set = 0, binding = 1, std140) uniform Params {
    mat4 view_proj; mat4 view; mat4 light_vp[4]; vec4 split_near; vec4 split_far; vec4 params;
} u;
layout(location = 0) in vec3 v_world;
layout(location = 1) in vec3 v_normal;
layout(location = 2) in float v_view_depth;
layout(location = 0) out float o_visibility;
layout(location = 1) out vec4 o_world;
layout(location = 2) out vec4 o_normal;
void main() {
    int count = int(u.params.x);
    o_visibility = sk_cascade_shadow(u_cascades, u.light_vp, u.split_near, u.split_far, count, v_world, v_view_depth,
                                     u.params.y, u.params.z, true);
    o_world = vec4(v_world, 1.0);
    o_normal = vec4(normalize(v_normal), float(sk_cascade_by_depth(v_view_depth, u.split_far, count)));
}
)";
const char* kReceiverHlsl = R"(
struct Params {
    column_major float4x4 view_proj; column_major float4x4 view; column_major float4x4 light_vp[4];
    float4 split_near; float4 split_far; float4 params;
};
[[vk::binding(0, 0)]] Texture2DArray<float> u_cascades;
[[vk::binding(1, 0)]] ConstantBuffer<Params> u;
[[vk::binding(2, 0)]] SamplerComparisonState u_compare;
struct Varyings {
    float4 position : SV_Position;
    [[vk::location(0)]] float3 world : TEXCOORD0;
    [[vk::location(1)]] float3 normal : TEXCOORD1;
    [[vk::location(2)]] float view_depth : TEXCOORD2;
};
Varyings vs_main([[vk::location(0)]] float3 position : POSITION, [[vk::location(1)]] float3 normal : NORMAL) {
    Varyings o;
    o.world = position;
    o.normal = normal;
    o.view_depth = -mul(u.view, float4(position, 1.0)).z;
    o.position = mul(u.view_proj, float4(position, 1.0));
    return o;
}
)";
const char* kReceiverHlslPs = R"(
Targets ps_main(Varyings i) {
    Targets o;
    int count = int(u.params.x);
    o.visibility = sk_cascade_shadow(u_cascades, u_compare, u.light_vp, u.split_near, u.split_far, count, i.world,
                                     i.view_depth, u.params.y, u.params.z, true);
    o.world = float4(i.world, 1.0);
    o.normal = float4(normalize(i.normal), float(sk_cascade_by_depth(i.view_depth, u.split_far, count)));
    return o;
}
)";

// The receiver pass in HLSL: the bindings and varyings (with the view depth), the shared targets, the lookup.
std::string receiver_hlsl() { return kReceiverHlsl + std::string(skvk::kReceiverHlslTargets) + kReceiverHlslPs; }

constexpr std::uint32_t kMap = 512, kW = 320, kH = 240, kCascades = 4;

struct Params {
    glm::mat4 view_proj, view, light_vp[4];
    glm::vec4 split_near, split_far, params;
};

struct Result {
    skvk::Agreement agreement;
    float splits[5] = {};
    int per_cascade[4] = {0, 0, 0, 0};
};

Result run(Source lang, bool reversed) {
    skvk::Context& ctx = skvk::vk_test_context();
    skvk::Scope scope(ctx);
    const skvk::BoxScene scene;
    const glm::vec4 light(0.5f, 1.f, 0.3f, 0.f);  // directional, toward the light
    const glm::mat4 view = glm::lookAt(glm::vec3(0.4f, 1.3f, 2.2f), glm::vec3(0.f, 0.f, -1.f), glm::vec3(0.f, 1.f, 0.f));
    glm::mat4 proj = glm::perspectiveRH_ZO(0.9f, float(kW) / float(kH), 0.1f, 50.f);
    if (reversed) proj = skvk::reverse_z() * proj;
    shadowkit::CascadeInput in;
    in.camera_view = view;
    in.camera_proj = proj;
    in.camera_depth = shadowkit::ClipDepth::ZeroToOne;
    in.camera_reversed_z = reversed;
    in.max_distance = 6.f;
    in.light_position = light;
    in.shadow_map_size = kMap;
    in.has_scene_bounds = true;
    in.scene_min = glm::vec3(-scene.ground_half, 0.f, -scene.ground_half);
    in.scene_max = glm::vec3(scene.ground_half, scene.box_c.y + scene.box_h.y, scene.ground_half);
    in.has_caster_bounds = true;
    in.caster_min = in.scene_min;
    in.caster_max = in.scene_max;
    in.light_depth = shadowkit::ClipDepth::ZeroToOne;
    in.light_reversed_z = reversed;
    shadowkit::Cascade cascades[kCascades];
    const shadowkit::CascadeFitResult fit = shadowkit::cascade_fit(in, 0.5f, kCascades, cascades, kCascades);
    REQUIRE_MESSAGE(fit.status == shadowkit::Status::Ok, shadowkit::status_name(fit.status));
    REQUIRE(fit.count == kCascades);

    Params params{};
    params.view_proj = proj * view;  // drawn with a negative-height viewport: upright, GL's matrices
    params.view = view;
    for (std::uint32_t i = 0; i < kCascades; ++i) {
        params.light_vp[i] = cascades[i].view_proj;
        params.split_near[int(i)] = fit.splits[i];
        params.split_far[int(i)] = fit.splits[i + 1];
    }
    params.params = glm::vec4(float(kCascades), 0.1f, 0.f, 0.f);

    std::vector<std::uint32_t> depth_vs, vs, fs;
    const char* vs_entry = "main";
    const char* fs_entry = "main";
    const std::string define = reversed ? "#define SK_REVERSED_Z 1\n" : "";
    if (lang == Source::Glsl) {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_GLSL_DIR) + "/cascades.glsl");
        depth_vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, skvk::kSceneDepthGlsl, "main", "cascades.glsl.depth.vert");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, kReceiverGlslVs, "main", "cascades.glsl.vert");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, "#version 450 core\n" + define + snippet + kReceiverGlslFs,
                                   "main", "cascades.glsl.frag");
    } else {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_HLSL_DIR) + "/cascades.hlsl");
        depth_vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, skvk::kSceneDepthHlsl, "main", "cascades.hlsl.depth.vert");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, snippet + receiver_hlsl(), "vs_main", "cascades.hlsl.vert");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, define + snippet + receiver_hlsl(), "ps_main",
                                   "cascades.hlsl.frag");
        vs_entry = "vs_main";
        fs_entry = "ps_main";
    }

    skvk::Buffer& vb = scope.own<skvk::Buffer>();
    skvk::Buffer& ubo = scope.own<skvk::Buffer>();
    const auto vcount = static_cast<std::uint32_t>(scene.vertices.size());
    REQUIRE(skvk::make_buffer(ctx, sizeof(skvk::SceneVertex) * vcount, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, vb));
    std::memcpy(vb.mapped, scene.vertices.data(), sizeof(skvk::SceneVertex) * vcount);
    REQUIRE(skvk::make_buffer(ctx, sizeof(Params), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, ubo));
    std::memcpy(ubo.mapped, &params, sizeof params);

    // the cascades: one depth array, a render pass per layer (its own 2D view as the attachment)
    skvk::Image& maps = scope.own<skvk::Image>();
    REQUIRE(skvk::make_image(ctx, kMap, kMap, kCascades, VK_FORMAT_D32_SFLOAT,
                             VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT, maps));
    const VkImageLayout map_read = VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL;
    VkRenderPass map_rp = scope.keep(skvk::make_render_pass(ctx, {}, VK_FORMAT_D32_SFLOAT, map_read), vkDestroyRenderPass);
    std::vector<VkFramebuffer> map_fb;
    for (std::uint32_t i = 0; i < kCascades; ++i) map_fb.push_back(scope.keep(skvk::make_framebuffer(ctx, map_rp, {maps.layer_views[i]}, kMap, kMap), vkDestroyFramebuffer));
    VkPipelineLayout map_layout = scope.keep(skvk::make_pipeline_layout(ctx, nullptr, sizeof(glm::mat4)), vkDestroyPipelineLayout);
    skvk::PipelineDesc md = skvk::scene_pipeline(depth_vs, {}, "main", "main", false);
    md.depth_compare = reversed ? VK_COMPARE_OP_GREATER : VK_COMPARE_OP_LESS;
    md.depth_bias = true;  // slope-scaled, as the GL test's glPolygonOffset(1.5, 2); reversed-Z: negative
    md.bias_slope = reversed ? -1.5f : 1.5f;
    md.bias_constant = reversed ? -2.f : 2.f;
    VkPipeline map_pipe = scope.keep(skvk::make_pipeline_checked(ctx, md, map_layout, map_rp), vkDestroyPipeline);

    skvk::ReceiverTargets& rt = scope.own<skvk::ReceiverTargets>();
    skvk::make_receiver_targets(ctx, kW, kH, rt);
    VkSampler sampler = scope.keep(skvk::make_sampler(ctx, VK_FILTER_LINEAR,
                                           reversed ? VK_COMPARE_OP_GREATER_OR_EQUAL : VK_COMPARE_OP_LESS_OR_EQUAL), vkDestroySampler);
    skvk::DescriptorSet& ds = scope.own<skvk::DescriptorSet>();
    skvk::make_lookup_set(ctx, lang, maps.view, map_read, sampler, ubo, ds);
    VkPipelineLayout layout = scope.keep(skvk::make_pipeline_layout(ctx, &ds), vkDestroyPipelineLayout);
    skvk::PipelineDesc pd = skvk::scene_pipeline(vs, fs, vs_entry, fs_entry);
    pd.depth_compare = reversed ? VK_COMPARE_OP_GREATER : VK_COMPARE_OP_LESS;
    pd.color_count = 3;
    pd.cull = VK_CULL_MODE_BACK_BIT;
    pd.front = VK_FRONT_FACE_COUNTER_CLOCKWISE;
    VkPipeline pipe = scope.keep(skvk::make_pipeline_checked(ctx, pd, layout, rt.rp), vkDestroyPipeline);

    VkCommandBuffer cmd = skvk::begin_commands(ctx);
    VkClearValue far{};
    far.depthStencil = {reversed ? 0.f : 1.f, 0};
    for (std::uint32_t i = 0; i < kCascades; ++i)
        skvk::draw_pass(cmd, map_rp, map_fb[i], kMap, kMap, {far}, map_pipe, map_layout, nullptr, &cascades[i].view_proj,
                        vb.buffer, vcount, false);
    VkClearValue zero{};
    skvk::draw_pass(cmd, rt.rp, rt.fb, kW, kH, {zero, zero, zero, far}, pipe, layout, &ds.set, nullptr, vb.buffer, vcount, true);
    REQUIRE(skvk::submit_and_wait(ctx, cmd));

    const skvk::ReceiverImages img = skvk::read_receiver(ctx, rt);
    const std::vector<float>& v_world = img.world;
    const std::vector<float>& v_normal = img.normal;
    Result out;
    std::copy(fit.splits, fit.splits + 5, out.splits);
    out.agreement = skvk::compare_with_ray_cast(scene, light, nullptr, int(kW), int(kH), img.vis, v_world, v_normal);
    for (std::size_t k = 0; k < img.vis.size(); ++k) {
        const int c = int(v_normal[k * 4 + 3]);
        if (v_world[k * 4 + 3] != 0.f && c >= 0 && c < 4) ++out.per_cascade[c];
    }

    return out;
}

void check(Source lang) {
    for (bool reversed : {false, true}) {
        const std::size_t before = skvk::message_count();
        const Result r = run(lang, reversed);
        const skvk::Agreement& a = r.agreement;
        const std::string name = std::string(lang == Source::Glsl ? "GLSL" : "HLSL") + (reversed ? ", reversed-Z" : ", standard depth");
        INFO(name);
        MESSAGE(name << ": compared " << a.compared << " (lit " << a.lit << ", shadowed " << a.shadowed << "), agreement "
                     << a.fraction() << "; pixels per cascade " << r.per_cascade[0] << " " << r.per_cascade[1] << " "
                     << r.per_cascade[2] << " " << r.per_cascade[3] << " (splits " << r.splits[0] << " " << r.splits[1]
                     << " " << r.splits[2] << " " << r.splits[3] << " " << r.splits[4] << ")");
        CHECK(a.compared > int(kW * kH) / 4);
        CHECK(a.shadowed > a.compared / 50);
        CHECK(a.lit > a.compared / 4);
        CHECK(a.fraction() >= 0.995);
        int used = 0;
        for (int c : r.per_cascade) used += c > int(kW * kH) / 100;
        CHECK(used >= 3);
        CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());
    }
}

}  // namespace

TEST_CASE("cascades.glsl on Vulkan: four [0,1] cascades in a depth array, standard and reversed-Z, agree with the ray cast") {
    check(Source::Glsl);
}

TEST_CASE("HLSL cascades.hlsl on Vulkan: four [0,1] cascades in a Texture2DArray, standard and reversed-Z, agree with the ray cast") {
    check(Source::Hlsl);
}
