// A point light's cube map of hardware depth on Vulkan, read by glsl/shadow_map.glsl's and
// hlsl/shadow_map.hlsl's sk_cube_visibility_hardware_depth: the six faces rendered by the rasterizer
// into a cube-compatible VK_FORMAT_D32_SFLOAT image with GL's face matrices (the lookAt frames of the
// GL cube-map convention) and a [0, 1] projection (glm::perspectiveRH_ZO: the same window depth the
// snippet's GL formula computes), with a plain viewport; the e2e scene's CPU ray cast as reference
// (>= 99.5% of the receiver pixels away from shadow edges). Control: the faces drawn with the
// negative-height viewport (the camera's y flip carried over to the cube) are mirrored and disagree.
#include <doctest/doctest.h>

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

const char* kParamsGlsl = R"(
layout(set = 0, binding = 1, std140) uniform Params { mat4 view_proj; vec4 light_position; vec4 planes; } u;
)";
const char* kReceiverGlslFs = R"(
layout(set = 0, binding = 0) uniform samplerCubeShadow u_cube;
void main() {
    o_visibility = sk_cube_visibility_hardware_depth(u_cube, u.light_position, v_world, u.planes.x, u.planes.y, u.planes.z);
    o_world = vec4(v_world, 1.0);
    o_normal = vec4(normalize(v_normal), 0.0);
}
)";
const char* kReceiverHlsl = R"(
struct Params { column_major float4x4 view_proj; float4 light_position; float4 planes; };
[[vk::binding(0, 0)]] TextureCube<float> u_cube;
[[vk::binding(1, 0)]] ConstantBuffer<Params> u;
[[vk::binding(2, 0)]] SamplerComparisonState u_compare;
)";
const char* kReceiverHlslPs = R"(
Targets ps_main(Varyings i) {
    Targets o;
    o.visibility = sk_cube_visibility_hardware_depth(u_cube, u_compare, u.light_position, i.world, u.planes.x, u.planes.y,
                                                     u.planes.z);
    o.world = float4(i.world, 1.0);
    o.normal = float4(normalize(i.normal), 0.0);
    return o;
}
)";

// The receiver pass in HLSL: the bindings, the shared varyings, vertex stage and targets, the lookup.
std::string receiver_hlsl() {
    return kReceiverHlsl + std::string(skvk::kReceiverHlslVs) + skvk::kReceiverHlslTargets + kReceiverHlslPs;
}

constexpr std::uint32_t kFace = 512, kW = 320, kH = 240;
constexpr float kNear = 0.1f, kFar = 20.f;

struct Params {
    glm::mat4 view_proj;
    glm::vec4 light_position, planes;
};

// GL's cube-map face frames (+X, -X, +Y, -Y, +Z, -Z), 90-degree faces in [0, 1] depth.
void face_matrices(glm::vec3 L, glm::mat4 out[6]) {
    const glm::vec3 dir[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    const glm::vec3 up[6] = {{0, -1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0, -1, 0}, {0, -1, 0}};
    const glm::mat4 proj = glm::perspectiveRH_ZO(glm::radians(90.f), 1.f, kNear, kFar);
    for (int f = 0; f < 6; ++f) out[f] = proj * glm::lookAt(L, L + dir[f], up[f]);
}

skvk::Agreement run(Source lang, bool flipped_faces) {
    skvk::Context& ctx = skvk::vk_test_context();
    skvk::Scope scope(ctx);
    const skvk::BoxScene scene;
    const glm::vec4 light(scene.light, 1.f);
    glm::mat4 faces[6];
    face_matrices(scene.light, faces);
    const glm::mat4 cam = glm::perspectiveRH_ZO(0.9f, float(kW) / float(kH), 0.1f, 50.f) *
                          glm::lookAt(glm::vec3(0.f, 3.5f, 5.f), glm::vec3(0.f, 0.3f, 0.f), glm::vec3(0.f, 1.f, 0.f));
    const Params params{cam, light, glm::vec4(kNear, kFar, 1e-4f, 0.f)};

    std::vector<std::uint32_t> depth_vs, vs, fs;
    const char* vs_entry = "main";
    const char* fs_entry = "main";
    depth_vs = skvk::compile_checked(Source::Glsl, VK_SHADER_STAGE_VERTEX_BIT, skvk::kSceneDepthGlsl, "main", "cube.depth.vert");
    if (lang == Source::Glsl) {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_GLSL_DIR) + "/shadow_map.glsl");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, skvk::receiver_glsl_vs(kParamsGlsl), "main", "cube.glsl.vert");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT,
                                   "#version 450 core\n" + snippet + kParamsGlsl + skvk::kReceiverGlslFsIo + kReceiverGlslFs, "main",
                                   "cube.glsl.frag");
    } else {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_HLSL_DIR) + "/shadow_map.hlsl");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, snippet + receiver_hlsl(), "vs_main", "cube.hlsl.vert");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, snippet + receiver_hlsl(), "ps_main", "cube.hlsl.frag");
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

    skvk::Image& cube = scope.own<skvk::Image>();
    REQUIRE(skvk::make_image(ctx, kFace, kFace, 6, VK_FORMAT_D32_SFLOAT,
                             VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT, cube, false, true));
    const VkImageLayout map_read = VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL;
    VkRenderPass map_rp = scope.keep(skvk::make_render_pass(ctx, {}, VK_FORMAT_D32_SFLOAT, map_read), vkDestroyRenderPass);
    std::vector<VkFramebuffer> map_fb;
    for (int f = 0; f < 6; ++f) map_fb.push_back(scope.keep(skvk::make_framebuffer(ctx, map_rp, {cube.layer_views[std::size_t(f)]}, kFace, kFace), vkDestroyFramebuffer));
    VkPipelineLayout map_layout = scope.keep(skvk::make_pipeline_layout(ctx, nullptr, sizeof(glm::mat4)), vkDestroyPipelineLayout);
    skvk::PipelineDesc md = skvk::scene_pipeline(depth_vs, {}, "main", "main", false);
    md.depth_bias = true;
    md.bias_slope = 1.5f;
    md.bias_constant = 2.f;
    VkPipeline map_pipe = scope.keep(skvk::make_pipeline_checked(ctx, md, map_layout, map_rp), vkDestroyPipeline);

    skvk::ReceiverTargets& rt = scope.own<skvk::ReceiverTargets>();
    skvk::make_receiver_targets(ctx, kW, kH, rt);
    VkSampler sampler = scope.keep(skvk::make_sampler(ctx, VK_FILTER_LINEAR, VK_COMPARE_OP_LESS_OR_EQUAL), vkDestroySampler);
    skvk::DescriptorSet& ds = scope.own<skvk::DescriptorSet>();
    skvk::make_lookup_set(ctx, lang, cube.view, map_read, sampler, ubo, ds);
    VkPipelineLayout layout = scope.keep(skvk::make_pipeline_layout(ctx, &ds), vkDestroyPipelineLayout);
    skvk::PipelineDesc pd = skvk::scene_pipeline(vs, fs, vs_entry, fs_entry);
    pd.color_count = 3;
    pd.cull = VK_CULL_MODE_BACK_BIT;
    VkPipeline pipe = scope.keep(skvk::make_pipeline_checked(ctx, pd, layout, rt.rp), vkDestroyPipeline);

    VkCommandBuffer cmd = skvk::begin_commands(ctx);
    VkClearValue far{};
    far.depthStencil = {1.f, 0};
    for (int f = 0; f < 6; ++f)
        skvk::draw_pass(cmd, map_rp, map_fb[std::size_t(f)], kFace, kFace, {far}, map_pipe, map_layout, nullptr, &faces[f],
                        vb.buffer, vcount, flipped_faces);
    VkClearValue zero{};
    skvk::draw_pass(cmd, rt.rp, rt.fb, kW, kH, {zero, zero, zero, far}, pipe, layout, &ds.set, nullptr, vb.buffer, vcount, true);
    REQUIRE(skvk::submit_and_wait(ctx, cmd));

    const skvk::Agreement a = skvk::receiver_agreement(ctx, rt, scene, light);

    return a;
}

void check(Source lang) {
    const std::size_t before = skvk::message_count();
    const skvk::Agreement a = run(lang, false);
    MESSAGE((lang == Source::Glsl ? "GLSL" : "HLSL") << " cube: compared " << a.compared << " (lit " << a.lit << ", shadowed "
                                                    << a.shadowed << "), agreement " << a.fraction());
    CHECK(a.compared > int(kW * kH) / 4);
    CHECK(a.shadowed > a.compared / 50);
    CHECK(a.fraction() >= 0.995);
    CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());
}

}  // namespace

TEST_CASE("shadow_map.glsl's cube lookup on Vulkan: GL's face matrices, [0,1] faces, plain viewport agree with the ray cast") {
    check(Source::Glsl);
}

TEST_CASE("cube faces on Vulkan, control: drawn with the negative-height viewport they are mirrored and disagree") {
    const skvk::Agreement a = run(Source::Glsl, true);
    MESSAGE("faces drawn y-flipped: agreement " << a.fraction() << " of " << a.compared);
    CHECK(a.fraction() < 0.95);
}

TEST_CASE("HLSL shadow_map.hlsl's cube lookup on Vulkan: GL's face matrices, [0,1] faces, plain viewport agree with the ray cast") {
    check(Source::Hlsl);
}
