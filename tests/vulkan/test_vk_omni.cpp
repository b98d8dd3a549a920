// glsl/omni_shadow.glsl's and hlsl/omni_shadow.hlsl's distance cube RUN on Vulkan: the six faces of a
// cube-compatible VK_FORMAT_D32_SFLOAT image rendered with GL's face matrices and a plain viewport,
// the fragment stage writing sk_omni_linear_depth (distance / range) as the depth; the receivers read it
// with sk_cube_visibility_distance (hardware compare), sk_cube_visibility_distance_pcf (3 x 3 taps
// across faces) and sk_cube_visibility_distance_manual (a point sampler on the same image), biased by
// sk_omni_bias; the e2e scene's CPU ray cast as reference (>= 99.5% away from shadow edges), no
// validation message. (The dual-paraboloid functions are compiled by hlsl.snippets_compile, not run.)
#include <doctest/doctest.h>

#include <shadowkit/infinite_projection.hpp>
#include <shadowkit/omni_shadow.hpp>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <cstring>
#include <string>
#include <vector>

#include "vk_harness.hpp"
#include "vk_passes.hpp"
#include "vk_scene.hpp"

namespace {

using skvk::Source;

// The map pass: the face's matrix and the light in push constants, distance / range as the depth.
const char* kDepthVsGlsl = R"(#version 450 core
layout(push_constant) uniform DepthParams { mat4 face_view_proj; vec4 light_position; vec4 range; } pc;
layout(location = 0) in vec3 a_position;
layout(location = 0) out vec3 v_world;
void main() {
    v_world = a_position;
    gl_Position = pc.face_view_proj * vec4(a_position, 1.0);
}
)";
const char* kDepthFsGlsl = R"(
layout(push_constant) uniform DepthParams { mat4 face_view_proj; vec4 light_position; vec4 range; } pc;
layout(location = 0) in vec3 v_world;
void main() { gl_FragDepth = sk_omni_linear_depth(v_world, pc.light_position, pc.range.x); }
)";
const char* kDepthHlsl = R"(
struct DepthParams { column_major float4x4 face_view_proj; float4 light_position; float4 range; };
[[vk::push_constant]] ConstantBuffer<DepthParams> pc;
struct DepthVaryings {
    float4 position : SV_Position;
    [[vk::location(0)]] float3 world : TEXCOORD0;
};
DepthVaryings vs_depth([[vk::location(0)]] float3 position : POSITION) {
    DepthVaryings o;
    o.world = position;
    o.position = mul(pc.face_view_proj, float4(position, 1.0));
    return o;
}
float ps_depth(DepthVaryings i) : SV_Depth { return sk_omni_linear_depth(i.world, pc.light_position, pc.range.x); }
)";
// params: x = range, y = face size, z = lookup (0 compare, 1 pcf 3 x 3, 2 manual)
const char* kReceiverGlslVs = R"(#version 450 core
layout(set = 0, binding = 1, std140) uniform Params { mat4 view_proj; vec4 light_position; vec4 params; } u;
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 0) out vec3 v_world;
layout(location = 1) out vec3 v_normal;
void main() {
    v_world = a_position;
    v_normal = a_normal;
    gl_Position = u.view_proj * vec4(a_position, 1.0);
}
)";
const char* kReceiverGlslFs = R"(
layout(set = 0, binding = 0) uniform samplerCubeShadow u_cube;
layout(set = 0, binding = 1, std140) uniform Params { mat4 view_proj; vec4 light_position; vec4 params; } u;
layout(set = 0, binding = 2) uniform samplerCube u_cube_distance;
layout(location = 0) in vec3 v_world;
layout(location = 1) in vec3 v_normal;
layout(location = 0) out float o_visibility;
layout(location = 1) out vec4 o_world;
layout(location = 2) out vec4 o_normal;
void main() {
    vec3 L = sk_omni_light_point(u.light_position) - v_world;
    float d = length(L);
    int mode = int(u.params.z);
    float radius = mode == 1 ? 2.0 * 1.4143 : 1.4143;
    float b = sk_omni_bias(d, dot(normalize(v_normal), L / d), sk_omni_cube_texel_angle(u.params.y), radius, 1.4835,
                           vec2(0.0, 2.38418579e-7));
    if (mode == 0) o_visibility = sk_cube_visibility_distance(u_cube, u.light_position, v_world, u.params.x, b);
    else if (mode == 1) o_visibility = sk_cube_visibility_distance_pcf(u_cube, u.light_position, v_world, u.params.x, b, u.params.y, 1);
    else o_visibility = sk_cube_visibility_distance_manual(u_cube_distance, u.light_position, v_world, u.params.x, b);
    o_world = vec4(v_world, 1.0);
    o_normal = vec4(normalize(v_normal), 0.0);
}
)";
const char* kReceiverHlsl = R"(
struct Params { column_major float4x4 view_proj; float4 light_position; float4 params; };
[[vk::binding(0, 0)]] TextureCube<float> u_cube;
[[vk::binding(1, 0)]] ConstantBuffer<Params> u;
[[vk::binding(2, 0)]] SamplerComparisonState u_compare;
[[vk::binding(3, 0)]] SamplerState u_point;
struct Varyings {
    float4 position : SV_Position;
    [[vk::location(0)]] float3 world : TEXCOORD0;
    [[vk::location(1)]] float3 normal : TEXCOORD1;
};
Varyings vs_main([[vk::location(0)]] float3 position : POSITION, [[vk::location(1)]] float3 normal : NORMAL) {
    Varyings o;
    o.world = position;
    o.normal = normal;
    o.position = mul(u.view_proj, float4(position, 1.0));
    return o;
}
struct Targets {
    [[vk::location(0)]] float visibility : SV_Target0;
    [[vk::location(1)]] float4 world : SV_Target1;
    [[vk::location(2)]] float4 normal : SV_Target2;
};
Targets ps_main(Varyings i) {
    Targets o;
    float3 L = sk_omni_light_point(u.light_position) - i.world;
    float d = length(L);
    int mode = int(u.params.z);
    float radius = mode == 1 ? 2.0 * 1.4143 : 1.4143;
    float b = sk_omni_bias(d, dot(normalize(i.normal), L / d), sk_omni_cube_texel_angle(u.params.y), radius, 1.4835,
                           float2(0.0, 2.38418579e-7));
    if (mode == 0) o.visibility = sk_cube_visibility_distance(u_cube, u_compare, u.light_position, i.world, u.params.x, b);
    else if (mode == 1)
        o.visibility = sk_cube_visibility_distance_pcf(u_cube, u_compare, u.light_position, i.world, u.params.x, b, u.params.y, 1);
    else o.visibility = sk_cube_visibility_distance_manual(u_cube, u_point, u.light_position, i.world, u.params.x, b);
    o.world = float4(i.world, 1.0);
    o.normal = float4(normalize(i.normal), 0.0);
    return o;
}
)";

constexpr std::uint32_t kFace = 512, kW = 320, kH = 240;
constexpr float kNear = 0.1f, kFar = 20.f, kRange = 12.f;

struct Params {
    glm::mat4 view_proj;
    glm::vec4 light_position, params;
};
struct DepthPush {
    glm::mat4 face_view_proj;
    glm::vec4 light_position, range;
};

// GL's cube-map face frames (+X, -X, +Y, -Y, +Z, -Z), 90-degree faces in [0, 1] depth.
void face_matrices(glm::vec3 L, glm::mat4 out[6]) {
    const glm::vec3 dir[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    const glm::vec3 up[6] = {{0, -1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0, -1, 0}, {0, -1, 0}};
    const glm::mat4 proj = glm::perspectiveRH_ZO(glm::radians(90.f), 1.f, kNear, kFar);
    for (int f = 0; f < 6; ++f) out[f] = proj * glm::lookAt(L, L + dir[f], up[f]);
}

// Reversed-Z: the faces' matrices from omni_cube_matrices (ZeroToOne, reversed_z; GL's face order and
// orientation), the camera from projection_perspective_finite (ZeroToOne, reversed_z).
void reversed_matrices(glm::vec4 light, glm::mat4 out[6]) {
    shadowkit::OmniCubeInput in;
    in.light_position = light;
    in.near_z = kNear;
    in.far_z = kFar;
    in.clip_depth = shadowkit::ClipDepth::ZeroToOne;
    in.reversed_z = true;
    const shadowkit::OmniCubeMatrices m = shadowkit::omni_cube_matrices(in);
    REQUIRE(m.status == shadowkit::Status::Ok);
    for (int f = 0; f < 6; ++f) out[f] = m.view_proj[f];
}
glm::mat4 reversed_camera() {
    const shadowkit::ProjectionResult p =
        shadowkit::projection_perspective_finite(0.9f, float(kW) / float(kH), 0.1f, 50.f, shadowkit::ClipDepth::ZeroToOne, true);
    REQUIRE(p.status == shadowkit::Status::Ok);
    return p.matrix;
}

skvk::Agreement run(Source lang, int mode, bool reversed = false) {
    skvk::Context& ctx = skvk::vk_test_context();
    const skvk::BoxScene scene;
    const glm::vec4 light(scene.light, 1.f);
    glm::mat4 faces[6];
    face_matrices(scene.light, faces);
    if (reversed) reversed_matrices(light, faces);
    const glm::mat4 cam = (reversed ? reversed_camera() : glm::perspectiveRH_ZO(0.9f, float(kW) / float(kH), 0.1f, 50.f)) *
                          glm::lookAt(glm::vec3(0.f, 3.5f, 5.f), glm::vec3(0.f, 0.3f, 0.f), glm::vec3(0.f, 1.f, 0.f));
    const Params params{cam, light, glm::vec4(kRange, float(kFace), float(mode), 0.f)};

    std::vector<std::uint32_t> depth_vs, depth_fs, vs, fs;
    const char* entries[4] = {"main", "main", "main", "main"};
    if (lang == Source::Glsl) {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_GLSL_DIR) + "/omni_shadow.glsl");
        depth_vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, kDepthVsGlsl, "main", "omni.glsl.depth.vert");
        depth_fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, "#version 450 core\n" + snippet + kDepthFsGlsl, "main",
                                         "omni.glsl.depth.frag");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, kReceiverGlslVs, "main", "omni.glsl.vert");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, "#version 450 core\n" + snippet + kReceiverGlslFs, "main",
                                   "omni.glsl.frag");
    } else {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_HLSL_DIR) + "/omni_shadow.hlsl");
        depth_vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, snippet + kDepthHlsl, "vs_depth", "omni.hlsl.depth.vert");
        depth_fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, snippet + kDepthHlsl, "ps_depth", "omni.hlsl.depth.frag");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, snippet + kReceiverHlsl, "vs_main", "omni.hlsl.vert");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, snippet + kReceiverHlsl, "ps_main", "omni.hlsl.frag");
        entries[0] = "vs_depth";
        entries[1] = "ps_depth";
        entries[2] = "vs_main";
        entries[3] = "ps_main";
    }

    skvk::Buffer vb, ubo;
    const auto vcount = static_cast<std::uint32_t>(scene.vertices.size());
    REQUIRE(skvk::make_buffer(ctx, sizeof(skvk::SceneVertex) * vcount, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, vb));
    std::memcpy(vb.mapped, scene.vertices.data(), sizeof(skvk::SceneVertex) * vcount);
    REQUIRE(skvk::make_buffer(ctx, sizeof(Params), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, ubo));
    std::memcpy(ubo.mapped, &params, sizeof params);

    skvk::Image cube, vis, world, normal, depth;
    REQUIRE(skvk::make_image(ctx, kFace, kFace, 6, VK_FORMAT_D32_SFLOAT,
                             VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT, cube, false, true));
    const VkImageLayout map_read = VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL;
    VkRenderPass map_rp = skvk::make_render_pass(ctx, {}, VK_FORMAT_D32_SFLOAT, map_read);
    std::vector<VkFramebuffer> map_fb;
    for (int f = 0; f < 6; ++f) map_fb.push_back(skvk::make_framebuffer(ctx, map_rp, {cube.layer_views[std::size_t(f)]}, kFace, kFace));
    VkPushConstantRange range{VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(DepthPush)};
    VkPipelineLayoutCreateInfo li{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    li.pushConstantRangeCount = 1;
    li.pPushConstantRanges = &range;
    VkPipelineLayout map_layout = VK_NULL_HANDLE;
    REQUIRE(vkCreatePipelineLayout(ctx.device, &li, nullptr, &map_layout) == VK_SUCCESS);
    skvk::PipelineDesc md;
    md.vs = depth_vs;
    md.fs = depth_fs;  // writes distance / range: no rasterized depth, no polygon offset
    md.vs_entry = entries[0];
    md.fs_entry = entries[1];
    md.vertex_stride = sizeof(skvk::SceneVertex);
    md.attributes = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0}};
    std::string why;
    VkPipeline map_pipe = skvk::make_pipeline(ctx, md, map_layout, map_rp, why);
    REQUIRE_MESSAGE(map_pipe != VK_NULL_HANDLE, why);

    const VkImageUsageFlags rt = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    REQUIRE(skvk::make_image(ctx, kW, kH, 1, VK_FORMAT_R32_SFLOAT, rt, vis));
    REQUIRE(skvk::make_image(ctx, kW, kH, 1, VK_FORMAT_R32G32B32A32_SFLOAT, rt, world));
    REQUIRE(skvk::make_image(ctx, kW, kH, 1, VK_FORMAT_R32G32B32A32_SFLOAT, rt, normal));
    REQUIRE(skvk::make_image(ctx, kW, kH, 1, VK_FORMAT_D32_SFLOAT, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, depth));
    VkRenderPass rp = skvk::make_render_pass(
        ctx, {VK_FORMAT_R32_SFLOAT, VK_FORMAT_R32G32B32A32_SFLOAT, VK_FORMAT_R32G32B32A32_SFLOAT}, VK_FORMAT_D32_SFLOAT,
        VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL);
    VkFramebuffer fb = skvk::make_framebuffer(ctx, rp, {vis.view, world.view, normal.view, depth.view}, kW, kH);
    VkSampler sampler = skvk::make_sampler(ctx, VK_FILTER_LINEAR, VK_COMPARE_OP_LESS_OR_EQUAL);
    VkSampler point = skvk::make_sampler(ctx, VK_FILTER_NEAREST, VK_COMPARE_OP_NEVER);
    skvk::DescriptorSet ds;
    const VkShaderStageFlags both = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
    if (lang == Source::Glsl) {
        REQUIRE(skvk::make_descriptor_set(ctx, {{0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VK_SHADER_STAGE_FRAGMENT_BIT},
                                                {1, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, both},
                                                {2, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VK_SHADER_STAGE_FRAGMENT_BIT}}, ds));
        skvk::write_image(ctx, ds, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, cube.view, sampler, map_read);
        skvk::write_image(ctx, ds, 2, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, cube.view, point, map_read);
    } else {
        REQUIRE(skvk::make_descriptor_set(ctx, {{0, VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, VK_SHADER_STAGE_FRAGMENT_BIT},
                                                {1, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, both},
                                                {2, VK_DESCRIPTOR_TYPE_SAMPLER, VK_SHADER_STAGE_FRAGMENT_BIT},
                                                {3, VK_DESCRIPTOR_TYPE_SAMPLER, VK_SHADER_STAGE_FRAGMENT_BIT}}, ds));
        skvk::write_image(ctx, ds, 0, VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, cube.view, VK_NULL_HANDLE, map_read);
        skvk::write_sampler(ctx, ds, 2, sampler);
        skvk::write_sampler(ctx, ds, 3, point);
    }
    skvk::write_buffer(ctx, ds, 1, ubo);
    li = VkPipelineLayoutCreateInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    li.setLayoutCount = 1;
    li.pSetLayouts = &ds.layout;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    REQUIRE(vkCreatePipelineLayout(ctx.device, &li, nullptr, &layout) == VK_SUCCESS);
    skvk::PipelineDesc pd;
    pd.vs = vs;
    pd.fs = fs;
    pd.vs_entry = entries[2];
    pd.fs_entry = entries[3];
    pd.vertex_stride = sizeof(skvk::SceneVertex);
    pd.attributes = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0}, {1, 0, VK_FORMAT_R32G32B32_SFLOAT, 12}};
    pd.color_count = 3;
    pd.cull = VK_CULL_MODE_BACK_BIT;
    if (reversed) pd.depth_compare = VK_COMPARE_OP_GREATER;
    VkPipeline pipe = skvk::make_pipeline(ctx, pd, layout, rp, why);
    REQUIRE_MESSAGE(pipe != VK_NULL_HANDLE, why);

    VkCommandBuffer cmd = skvk::begin_commands(ctx);
    VkClearValue far{};
    far.depthStencil = {1.f, 0};
    for (int f = 0; f < 6; ++f) {
        const DepthPush push{faces[f], light, glm::vec4(kRange)};
        skvk::draw_pass(cmd, map_rp, map_fb[std::size_t(f)], kFace, kFace, {far}, map_pipe, map_layout, nullptr, &push, vb.buffer,
                        vcount, false, sizeof push, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT);
    }
    VkClearValue zero{}, cam_far = far;
    if (reversed) cam_far.depthStencil.depth = 0.f;
    skvk::draw_pass(cmd, rp, fb, kW, kH, {zero, zero, zero, cam_far}, pipe, layout, &ds.set, nullptr, vb.buffer, vcount, true);
    REQUIRE(skvk::submit_and_wait(ctx, cmd));

    const std::vector<float> v_vis = skvk::read_image(ctx, vis, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 1);
    const std::vector<float> v_world = skvk::read_image(ctx, world, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 4);
    const std::vector<float> v_normal = skvk::read_image(ctx, normal, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 4);
    REQUIRE(v_vis.size() == std::size_t(kW) * kH);
    const skvk::Agreement a = skvk::compare_with_ray_cast(scene, light, nullptr, int(kW), int(kH), v_vis, v_world, v_normal);

    vkDestroyPipeline(ctx.device, pipe, nullptr);
    vkDestroyPipeline(ctx.device, map_pipe, nullptr);
    vkDestroyPipelineLayout(ctx.device, layout, nullptr);
    vkDestroyPipelineLayout(ctx.device, map_layout, nullptr);
    vkDestroySampler(ctx.device, sampler, nullptr);
    vkDestroySampler(ctx.device, point, nullptr);
    vkDestroyFramebuffer(ctx.device, fb, nullptr);
    for (VkFramebuffer f : map_fb) vkDestroyFramebuffer(ctx.device, f, nullptr);
    vkDestroyRenderPass(ctx.device, rp, nullptr);
    vkDestroyRenderPass(ctx.device, map_rp, nullptr);
    skvk::destroy(ctx, ds);
    for (skvk::Image* i : {&cube, &vis, &world, &normal, &depth}) skvk::destroy(ctx, *i);
    skvk::destroy(ctx, vb);
    skvk::destroy(ctx, ubo);
    return a;
}

void check(Source lang) {
    const char* names[3] = {"compare", "pcf 3 x 3", "manual (point sampler)"};
    for (int mode = 0; mode < 3; ++mode) {
        const std::size_t before = skvk::message_count();
        const skvk::Agreement a = run(lang, mode);
        const std::string name = std::string(lang == Source::Glsl ? "GLSL" : "HLSL") + " distance cube, " + names[mode];
        INFO(name);
        MESSAGE(name << ": compared " << a.compared << " (lit " << a.lit << ", shadowed " << a.shadowed << "), agreement "
                     << a.fraction());
        CHECK(a.compared > int(kW * kH) / 4);
        CHECK(a.shadowed > a.compared / 50);
        CHECK(a.fraction() >= 0.995);
        CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());
    }
}

}  // namespace

TEST_CASE("omni_shadow.glsl's distance cube on Vulkan: compare, pcf and manual lookups agree with the ray cast") {
    check(Source::Glsl);
}

TEST_CASE("HLSL omni_shadow.hlsl's distance cube on Vulkan: compare, pcf and manual lookups agree with the ray cast") {
    check(Source::Hlsl);
}

// Reversed-Z: the faces drawn with omni_cube_matrices' [0, 1] reversed-Z matrices and the camera with
// a reversed-Z [0, 1] projection (depth cleared to 0, GREATER). The cube itself stores distance / range
// written by the fragment stage, whatever the projection's depth: its map pass keeps LESS and a clear
// of 1, and the lookups (which compare distances) take no reversed-Z parameter.
namespace {
void check_reversed(Source lang) {
    const char* names[3] = {"compare", "pcf 3 x 3", "manual (point sampler)"};
    for (int mode = 0; mode < 3; ++mode) {
        const std::size_t before = skvk::message_count();
        const skvk::Agreement a = run(lang, mode, true);
        const std::string name = std::string(lang == Source::Glsl ? "GLSL" : "HLSL") + " reversed-Z distance cube, " + names[mode];
        INFO(name);
        MESSAGE(name << ": compared " << a.compared << " (lit " << a.lit << ", shadowed " << a.shadowed << "), agreement "
                     << a.fraction());
        CHECK(a.compared > int(kW * kH) / 4);
        CHECK(a.shadowed > a.compared / 50);
        CHECK(a.fraction() >= 0.995);
        CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());
    }
}
}  // namespace

TEST_CASE("reversed-Z omni_shadow.glsl's distance cube on Vulkan: reversed faces and camera, lookups agree with the ray cast") {
    check_reversed(Source::Glsl);
}

TEST_CASE("HLSL reversed-Z omni_shadow.hlsl's distance cube on Vulkan: reversed faces and camera, lookups agree with the ray cast") {
    check_reversed(Source::Hlsl);
}
