// Stencil shadow volumes on Vulkan: glsl/shadow_volume.glsl's and hlsl/shadow_volume.hlsl's
// sk_extrude_shadow_volume in the volume pass, the volume from include/shadowkit/shadow_volume.hpp
// (volume_build_vertices, side quads of every lit triangle's edges, VolumeCapMode::LitOnly caps with
// the dark cap: z-fail), the box of the e2e scene as occluder and a point light. One render pass: the
// scene's depth (reversed-Z, [0, 1]) and G-buffer, then the volumes with two-sided z-fail stencil
// (back faces INCREMENT_AND_WRAP, front faces DECREMENT_AND_WRAP on depth fail, depth writes and
// colour writes off, no culling, counter-clockwise front faces under the negative-height viewport).
// Depth at infinity two ways: shadowkit::projection_perspective_infinite (ClipDepth::ZeroToOne,
// reversed-Z, its Everitt-Kilgard epsilon) without clamping, and a finite far plane (10, just beyond
// the scene) with depthClampEnable (where the device has depthClamp). The stencil read back must be 0 or 1 on every
// receiver pixel, and stencil == 0 (lit) must agree with the CPU ray cast on >= 99.5% of them (the
// e2e test's tolerance). Controls: the two faces' operations swapped give wrapped counts (255); the
// finite far plane without the clamp clips the dark cap and loses shadow.
// Scissor and depth bounds (shadowkit::volume_scissor, Lengyel): the scissor rectangle (GL rows from the
// bottom, turned for the flipped viewport) and the depth bounds, emulated with sk_outside_depth_bounds_at
// on a sampled copy of the scene's depth (lavapipe has no depthBounds feature), or natively with
// vkCmdSetDepthBounds where the device has it: the stencil equals the unculled run's on every pixel,
// the volume fragments that reach the counting fragment stage drop; control: an empty range loses the shadow.
#include <doctest/doctest.h>

#include <shadowkit/infinite_projection.hpp>
#include <shadowkit/shadow_volume.hpp>

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

const char* kScenePush = R"(
layout(push_constant) uniform Push { mat4 view_proj; vec4 light_position; } pc;
)";
const char* kVolumeGlsl = R"(
layout(push_constant) uniform Push { mat4 view_proj; vec4 light_position; } pc;
layout(location = 0) in vec4 a_position;   // (p, 1) or (p, 0): shadowkit::volume_build_vertices
void main() { gl_Position = pc.view_proj * sk_extrude_shadow_volume(a_position, pc.light_position); }
)";
const char* kVolumeHlsl = R"(
struct Push { column_major float4x4 view_proj; float4 light_position; };
[[vk::push_constant]] ConstantBuffer<Push> pc;
float4 vs_volume([[vk::location(0)]] float4 position : POSITION) : SV_Position {
    return mul(pc.view_proj, sk_extrude_shadow_volume(position, pc.light_position));
}
)";

struct PushConstants {
    glm::mat4 view_proj;
    glm::vec4 light_position;
};

constexpr std::uint32_t kW = 320, kH = 240;

// The box as an indexed, closed mesh (counter-clockwise from outside) and its z-fail volume.
struct Volume {
    std::vector<glm::vec4> vertices;
    std::vector<std::uint32_t> indices;
};

Volume build_volume(const skvk::BoxScene& s, glm::vec4 light) {
    // the box's triangles exactly as the scene pass draws them (vertices 6.. of the scene, the same
    // corners, order and diagonals), indexed over its 8 corners: the light caps then rasterize to the
    // very depths of the lit faces they lie on, so the z-fail depth test fails on them as it must
    std::vector<glm::vec3> p;
    std::vector<std::uint32_t> tris;
    for (std::size_t k = 6; k < s.vertices.size(); ++k) {
        const glm::vec3 q = s.vertices[k].position;
        std::size_t i = 0;
        while (i < p.size() && p[i] != q) ++i;
        if (i == p.size()) p.push_back(q);
        tris.push_back(static_cast<std::uint32_t>(i));
    }
    REQUIRE(p.size() == 8);
    std::vector<std::uint8_t> lit(tris.size() / 3);
    std::vector<std::uint32_t> edges;
    for (std::size_t t = 0; t < lit.size(); ++t) {
        const glm::vec3 a = p[tris[3 * t]], b = p[tris[3 * t + 1]], c = p[tris[3 * t + 2]];
        const glm::vec3 n = glm::cross(b - a, c - a);
        lit[t] = glm::dot(n, glm::vec3(light) - light.w * (a + b + c) / 3.f) > 0.f;
        if (!lit[t]) continue;
        for (int e = 0; e < 3; ++e) {  // every lit triangle's edges: shared ones cancel in the count
            edges.push_back(tris[3 * t + std::size_t(e)]);
            edges.push_back(tris[3 * t + std::size_t((e + 1) % 3)]);
        }
    }
    Volume v;
    v.vertices.resize(16);
    REQUIRE(shadowkit::volume_build_vertices(p.data(), 8, v.vertices.data(), v.vertices.size()).status == shadowkit::Status::Ok);
    v.indices.resize(shadowkit::volume_indices_capacity(edges.size(), tris.size()));
    const shadowkit::VolumeBuffer sides =
        shadowkit::volume_build_side_quads(edges.data(), edges.size(), 8, v.indices.data(), v.indices.size());
    REQUIRE(sides.status == shadowkit::Status::Ok);
    const shadowkit::VolumeBuffer caps =
        shadowkit::volume_build_caps(tris.data(), tris.size(), lit.data(), lit.size(), 8, shadowkit::VolumeCapMode::LitOnly, true,
                                     v.indices.data() + sides.count, v.indices.size() - sides.count);
    REQUIRE(caps.status == shadowkit::Status::Ok);
    v.indices.resize(sides.count + caps.count);
    return v;
}

struct Variant {
    Source lang = Source::Glsl;
    bool clamp = false;    ///< finite far plane + depthClampEnable instead of the infinite projection
    bool swapped = false;  ///< control: the faces' stencil operations swapped
    bool clamp_off = false;  ///< control: the finite far plane without depthClampEnable
};

struct Result {
    skvk::Agreement agreement;
    int zero = 0, one = 0, other = 0;  ///< stencil values on receiver pixels
};

VkFormat depth_stencil_format(skvk::Context& ctx) {
    for (VkFormat f : {VK_FORMAT_D32_SFLOAT_S8_UINT, VK_FORMAT_D24_UNORM_S8_UINT}) {
        VkFormatProperties fp;
        vkGetPhysicalDeviceFormatProperties(ctx.physical, f, &fp);
        if (fp.optimalTilingFeatures & VK_FORMAT_FEATURE_DEPTH_STENCIL_ATTACHMENT_BIT) return f;
    }
    return VK_FORMAT_UNDEFINED;
}

Result run(const Variant& v) {
    skvk::Context& ctx = skvk::vk_test_context();
    skvk::Scope scope(ctx);
    const skvk::BoxScene scene;
    const glm::vec4 light(scene.light, 1.f);
    const float fovy = 0.9f, aspect = float(kW) / float(kH);
    shadowkit::ProjectionResult pr;
    if (v.clamp) {
        pr = shadowkit::projection_perspective_finite(fovy, aspect, 0.1f, 10.f, shadowkit::ClipDepth::ZeroToOne, true);
    } else {
        const float eps = shadowkit::projection_infinite_epsilon_bound(fovy, aspect, shadowkit::ClipDepth::ZeroToOne, true,
                                                                       shadowkit::DepthFormat::Float32)
                              .epsilon;
        pr = shadowkit::projection_perspective_infinite(fovy, aspect, 0.1f, shadowkit::ClipDepth::ZeroToOne, true, eps);
    }
    REQUIRE(pr.status == shadowkit::Status::Ok);
    const glm::mat4 view = glm::lookAt(glm::vec3(0.f, 3.5f, 5.f), glm::vec3(0.f, 0.3f, 0.f), glm::vec3(0.f, 1.f, 0.f));
    const PushConstants push{pr.matrix * view, light};
    const Volume volume = build_volume(scene, light);

    std::vector<std::uint32_t> scene_vs, scene_fs, volume_vs;
    scene_vs = skvk::compile_checked(Source::Glsl, VK_SHADER_STAGE_VERTEX_BIT, skvk::receiver_glsl_vs(kScenePush, "pc.view_proj"), "main",
                                     "shadow_volume.scene.vert");
    scene_fs = skvk::compile_checked(Source::Glsl, VK_SHADER_STAGE_FRAGMENT_BIT, skvk::kGbufferGlslFs, "main", "shadow_volume.scene.frag");
    const char* entry = "main";
    if (v.lang == Source::Glsl) {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_GLSL_DIR) + "/shadow_volume.glsl");
        volume_vs = skvk::compile_checked(v.lang, VK_SHADER_STAGE_VERTEX_BIT, "#version 450 core\n" + snippet + kVolumeGlsl,
                                          "main", "shadow_volume.glsl.vert");
    } else {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_HLSL_DIR) + "/shadow_volume.hlsl");
        volume_vs = skvk::compile_checked(v.lang, VK_SHADER_STAGE_VERTEX_BIT, snippet + kVolumeHlsl, "vs_volume",
                                          "shadow_volume.hlsl.vert");
        entry = "vs_volume";
    }

    skvk::Buffer& vb = scope.own<skvk::Buffer>();
    skvk::Buffer& volume_vb = scope.own<skvk::Buffer>();
    skvk::Buffer& volume_ib = scope.own<skvk::Buffer>();
    const auto vcount = static_cast<std::uint32_t>(scene.vertices.size());
    REQUIRE(skvk::make_buffer(ctx, sizeof(skvk::SceneVertex) * vcount, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, vb));
    std::memcpy(vb.mapped, scene.vertices.data(), sizeof(skvk::SceneVertex) * vcount);
    REQUIRE(skvk::make_buffer(ctx, sizeof(glm::vec4) * volume.vertices.size(), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, volume_vb));
    std::memcpy(volume_vb.mapped, volume.vertices.data(), sizeof(glm::vec4) * volume.vertices.size());
    REQUIRE(skvk::make_buffer(ctx, sizeof(std::uint32_t) * volume.indices.size(), VK_BUFFER_USAGE_INDEX_BUFFER_BIT, volume_ib));
    std::memcpy(volume_ib.mapped, volume.indices.data(), sizeof(std::uint32_t) * volume.indices.size());

    const VkFormat ds_format = depth_stencil_format(ctx);
    REQUIRE(ds_format != VK_FORMAT_UNDEFINED);
    skvk::Image& world = scope.own<skvk::Image>();
    skvk::Image& normal = scope.own<skvk::Image>();
    skvk::Image& ds = scope.own<skvk::Image>();
    const VkImageUsageFlags rt = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    REQUIRE(skvk::make_image(ctx, kW, kH, 1, VK_FORMAT_R32G32B32A32_SFLOAT, rt, world));
    REQUIRE(skvk::make_image(ctx, kW, kH, 1, VK_FORMAT_R32G32B32A32_SFLOAT, rt, normal));
    REQUIRE(skvk::make_image(ctx, kW, kH, 1, ds_format,
                             VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, ds));
    VkRenderPass rp = scope.keep(skvk::make_render_pass(ctx, {VK_FORMAT_R32G32B32A32_SFLOAT, VK_FORMAT_R32G32B32A32_SFLOAT}, ds_format,
                                             VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL), vkDestroyRenderPass);
    VkFramebuffer fb = scope.keep(skvk::make_framebuffer(ctx, rp, {world.view, normal.view, ds.view}, kW, kH), vkDestroyFramebuffer);
    VkPipelineLayout layout = scope.keep(skvk::make_pipeline_layout(ctx, nullptr, sizeof(PushConstants)), vkDestroyPipelineLayout);

    skvk::PipelineDesc sd = skvk::scene_pipeline(scene_vs, scene_fs);  // the scene: depth (reversed-Z: GREATER) and G-buffer
    sd.depth_compare = VK_COMPARE_OP_GREATER;
    sd.cull = VK_CULL_MODE_BACK_BIT;
    sd.color_count = 2;
    VkPipeline scene_pipe = scope.keep(skvk::make_pipeline_checked(ctx, sd, layout, rp), vkDestroyPipeline);

    skvk::PipelineDesc vd;  // the volumes: z-fail, two-sided stencil, no depth or colour writes
    vd.vs = volume_vs;
    vd.vs_entry = entry;
    vd.vertex_stride = sizeof(glm::vec4);
    vd.attributes = {{0, 0, VK_FORMAT_R32G32B32A32_SFLOAT, 0}};
    vd.depth_compare = VK_COMPARE_OP_GREATER;
    vd.depth_write = false;
    vd.depth_clamp = v.clamp && !v.clamp_off;
    vd.color_count = 2;
    vd.color_write = false;
    vd.stencil = true;
    const VkStencilOpState inc{VK_STENCIL_OP_KEEP, VK_STENCIL_OP_KEEP, VK_STENCIL_OP_INCREMENT_AND_WRAP, VK_COMPARE_OP_ALWAYS,
                               0xff, 0xff, 0};
    const VkStencilOpState dec{VK_STENCIL_OP_KEEP, VK_STENCIL_OP_KEEP, VK_STENCIL_OP_DECREMENT_AND_WRAP, VK_COMPARE_OP_ALWAYS,
                               0xff, 0xff, 0};
    vd.stencil_back = v.swapped ? dec : inc;
    vd.stencil_front = v.swapped ? inc : dec;
    VkPipeline volume_pipe = scope.keep(skvk::make_pipeline_checked(ctx, vd, layout, rp), vkDestroyPipeline);

    VkCommandBuffer cmd = skvk::begin_commands(ctx);
    VkClearValue clears[3]{};
    clears[2].depthStencil = {0.f, 0};  // reversed-Z: far (and infinity) is 0
    VkRenderPassBeginInfo bi{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    bi.renderPass = rp;
    bi.framebuffer = fb;
    bi.renderArea = {{0, 0}, {kW, kH}};
    bi.clearValueCount = 3;
    bi.pClearValues = clears;
    vkCmdBeginRenderPass(cmd, &bi, VK_SUBPASS_CONTENTS_INLINE);
    const VkViewport vp = skvk::viewport(kW, kH, true);
    const VkRect2D sc{{0, 0}, {kW, kH}};
    vkCmdSetViewport(cmd, 0, 1, &vp);
    vkCmdSetScissor(cmd, 0, 1, &sc);
    vkCmdPushConstants(cmd, layout, VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof push, &push);
    const VkDeviceSize offset = 0;
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, scene_pipe);
    vkCmdBindVertexBuffers(cmd, 0, 1, &vb.buffer, &offset);
    vkCmdDraw(cmd, vcount, 1, 0, 0);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, volume_pipe);
    vkCmdBindVertexBuffers(cmd, 0, 1, &volume_vb.buffer, &offset);
    vkCmdBindIndexBuffer(cmd, volume_ib.buffer, 0, VK_INDEX_TYPE_UINT32);
    vkCmdDrawIndexed(cmd, static_cast<std::uint32_t>(volume.indices.size()), 1, 0, 0, 0);
    vkCmdEndRenderPass(cmd);
    REQUIRE(skvk::submit_and_wait(ctx, cmd));

    const std::vector<float> v_world = skvk::read_image(ctx, world, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 4);
    const std::vector<float> v_normal = skvk::read_image(ctx, normal, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 4);
    const std::vector<std::uint8_t> stencil = skvk::read_stencil(ctx, ds, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    REQUIRE(stencil.size() == std::size_t(kW) * kH);
    std::vector<float> vis(stencil.size());
    Result out;
    for (std::size_t k = 0; k < stencil.size(); ++k) {
        vis[k] = stencil[k] == 0 ? 1.f : 0.f;
        if (v_world[k * 4 + 3] == 0.f) continue;
        (stencil[k] == 0 ? out.zero : stencil[k] == 1 ? out.one : out.other)++;
    }
    out.agreement = skvk::compare_with_ray_cast(scene, light, nullptr, int(kW), int(kH), vis, v_world, v_normal);

    return out;
}

void check(Source lang) {
    skvk::Context& ctx = skvk::vk_test_context();
    for (bool clamp : {false, true}) {
        if (clamp && !ctx.enabled.depthClamp) {
            MESSAGE("the device has no depthClamp: the clamped variant is not run");
            continue;
        }
        Variant v;
        v.lang = lang;
        v.clamp = clamp;
        const std::size_t before = skvk::message_count();
        const Result r = run(v);
        const std::string name = std::string(lang == Source::Glsl ? "GLSL" : "HLSL") +
                                 (clamp ? ", finite far + depth clamp" : ", infinite reversed-Z [0,1] projection");
        INFO(name);
        MESSAGE(name << ": stencil 0 / 1 / other on receiver pixels " << r.zero << " / " << r.one << " / " << r.other
                     << "; compared " << r.agreement.compared << " (shadowed " << r.agreement.shadowed << "), agreement "
                     << r.agreement.fraction());
        CHECK(r.other == 0);
        CHECK(r.one > 1000);
        CHECK(r.agreement.compared > int(kW * kH) / 4);
        CHECK(r.agreement.shadowed > r.agreement.compared / 50);
        CHECK(r.agreement.fraction() >= 0.995);
        CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());
    }
}


// ------------------------------------------------------------------ scissor and depth bounds
// Lengyel's per-occluder scissor rectangle and depth bounds (shadowkit::volume_scissor for the box and
// the receivers' box, the camera's reversed-Z [0, 1] matrix). Two passes: the G-buffer with the scene's
// depth in a sampled D32 image, then the scene's depth again, and the volume with a fragment stage that
// counts its fragments (an atomic in a storage buffer). Depth bounds emulated (lavapipe: depthBounds 0):
// sk_outside_depth_bounds_at on the first pass's depth discards; native: depthBoundsTestEnable with
// vkCmdSetDepthBounds (where the device has the feature). The stencil must equal the unculled run's on
// every pixel and the fragments must not grow.
enum class Bounds { Off, Emulated, Native, Wrong };  // Wrong: the control, emulated with an empty range

const char* kBoundsGlsl = R"(
layout(push_constant) uniform Push { mat4 view_proj; vec4 light_position; vec4 bounds; } pc;
#ifdef SK_SCENE_VS
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 0) out vec3 v_world;
layout(location = 1) out vec3 v_normal;
void main() {
    v_world = a_position;
    v_normal = a_normal;
    gl_Position = pc.view_proj * vec4(a_position, 1.0);
}
#else
layout(set = 0, binding = 0) uniform sampler2D u_scene_depth;  // the first pass's depth (a copy: not the attachment)
layout(set = 0, binding = 1, std430) buffer Count { uint fragments; };
void main() {
    if (sk_outside_depth_bounds_at(u_scene_depth, ivec2(gl_FragCoord.xy), pc.bounds.xy)) discard;
    atomicAdd(fragments, 1u);
}
#endif
)";
const char* kBoundsHlsl = R"(
struct BoundsPush { column_major float4x4 view_proj; float4 light_position; float4 bounds; };
[[vk::push_constant]] ConstantBuffer<BoundsPush> bpc;
[[vk::binding(0, 0)]] Texture2D<float> u_scene_depth;
[[vk::binding(1, 0)]] RWByteAddressBuffer u_count;
struct SceneOut { float4 position : SV_Position; [[vk::location(0)]] float3 world : WORLD; [[vk::location(1)]] float3 normal : NORMAL; };
SceneOut vs_scene([[vk::location(0)]] float3 position : POSITION, [[vk::location(1)]] float3 normal : NORMAL) {
    SceneOut o;
    o.world = position;
    o.normal = normal;
    o.position = mul(bpc.view_proj, float4(position, 1.0));
    return o;
}
float4 vs_bounds_volume([[vk::location(0)]] float4 position : POSITION) : SV_Position {
    return mul(bpc.view_proj, sk_extrude_shadow_volume(position, bpc.light_position));
}
void ps_bounds(float4 position : SV_Position) {
    if (sk_outside_depth_bounds_at(u_scene_depth, int2(position.xy), bpc.bounds.xy)) discard;
    uint before;
    u_count.InterlockedAdd(0, 1u, before);
}
)";

struct BoundsPush {
    glm::mat4 view_proj;
    glm::vec4 light_position, bounds;
};

struct BoundsResult {
    std::vector<std::uint8_t> stencil;
    std::vector<float> world, normal;
    std::uint32_t fragments = 0;
    shadowkit::ScissorRect sc;
};

struct BoundsShaders {
    std::vector<std::uint32_t> scene_vs, scene_fs, volume_vs, volume_fs;
    const char *scene_entry = "main", *volume_entry = "main", *fs_entry = "main";
};
BoundsShaders compile_bounds_shaders(Source lang) {
    BoundsShaders b;
    const VkShaderStageFlagBits V = VK_SHADER_STAGE_VERTEX_BIT, F = VK_SHADER_STAGE_FRAGMENT_BIT;
    b.scene_fs = skvk::compile_checked(Source::Glsl, F, skvk::kGbufferGlslFs, "main", "shadow_volume.bounds.scene.frag");
    if (lang == Source::Glsl) {
        const std::string head = "#version 450 core\n" + skvk::read_text(std::string(SHADOWKIT_GLSL_DIR) + "/shadow_volume.glsl");
        b.scene_vs = skvk::compile_checked(lang, V, head + "#define SK_SCENE_VS 1\n" + kBoundsGlsl, "main", "shadow_volume.bounds.glsl.scene.vert");
        b.volume_vs = skvk::compile_checked(lang, V, head + kVolumeGlsl, "main", "shadow_volume.bounds.glsl.vert");
        b.volume_fs = skvk::compile_checked(lang, F, head + kBoundsGlsl, "main", "shadow_volume.bounds.glsl.frag");
    } else {
        const std::string head = skvk::read_text(std::string(SHADOWKIT_HLSL_DIR) + "/shadow_volume.hlsl");
        b.scene_vs = skvk::compile_checked(lang, V, head + kBoundsHlsl, "vs_scene", "shadow_volume.bounds.hlsl.scene.vert");
        b.volume_vs = skvk::compile_checked(lang, V, head + kBoundsHlsl, "vs_bounds_volume", "shadow_volume.bounds.hlsl.vert");
        b.volume_fs = skvk::compile_checked(lang, F, head + kBoundsHlsl, "ps_bounds", "shadow_volume.bounds.hlsl.frag");
        b.scene_entry = "vs_scene";
        b.volume_entry = "vs_bounds_volume";
        b.fs_entry = "ps_bounds";
    }
    return b;
}

struct BoundsPipelines {
    VkPipeline gbuffer = VK_NULL_HANDLE, depth = VK_NULL_HANDLE, volume = VK_NULL_HANDLE;
};
/// The three pipelines, handed to `scope`.
BoundsPipelines make_bounds_pipelines(skvk::Context& ctx, skvk::Scope& scope, const BoundsShaders& sh, VkPipelineLayout layout, VkRenderPass gbuffer_rp,
                                      VkRenderPass main_rp, bool native) {
    BoundsPipelines p;
    std::string why;
    // the scene: reversed-Z depth (GREATER), back faces culled
    skvk::PipelineDesc sd = skvk::scene_pipeline(sh.scene_vs, sh.scene_fs, sh.scene_entry);
    sd.depth_compare = VK_COMPARE_OP_GREATER;
    sd.cull = VK_CULL_MODE_BACK_BIT;
    sd.color_count = 2;
    p.gbuffer = scope.keep(skvk::make_pipeline(ctx, sd, layout, gbuffer_rp, why), vkDestroyPipeline);
    sd.fs.clear();  // the same depth again, no colour
    sd.color_count = 0;
    p.depth = scope.keep(skvk::make_pipeline(ctx, sd, layout, main_rp, why), vkDestroyPipeline);
    skvk::PipelineDesc vd;  // z-fail, two-sided stencil, the counting fragment stage
    vd.vs = sh.volume_vs;
    vd.vs_entry = sh.volume_entry;
    vd.fs = sh.volume_fs;
    vd.fs_entry = sh.fs_entry;
    vd.vertex_stride = sizeof(glm::vec4);
    vd.attributes = {{0, 0, VK_FORMAT_R32G32B32A32_SFLOAT, 0}};
    vd.depth_compare = VK_COMPARE_OP_GREATER;
    vd.depth_write = false;
    vd.stencil = true;
    vd.stencil_back = {VK_STENCIL_OP_KEEP, VK_STENCIL_OP_KEEP, VK_STENCIL_OP_INCREMENT_AND_WRAP, VK_COMPARE_OP_ALWAYS, 0xff, 0xff, 0};
    vd.stencil_front = {VK_STENCIL_OP_KEEP, VK_STENCIL_OP_KEEP, VK_STENCIL_OP_DECREMENT_AND_WRAP, VK_COMPARE_OP_ALWAYS, 0xff, 0xff, 0};
    vd.depth_bounds = native;
    p.volume = scope.keep(skvk::make_pipeline(ctx, vd, layout, main_rp, why), vkDestroyPipeline);
    for (VkPipeline q : {p.gbuffer, p.depth, p.volume}) REQUIRE_MESSAGE(q != VK_NULL_HANDLE, why);
    return p;
}

BoundsResult run_bounds(Source lang, bool scissor, Bounds bounds) {
    skvk::Context& ctx = skvk::vk_test_context();
    skvk::Scope scope(ctx);
    const skvk::BoxScene scene;
    const glm::vec4 light(scene.light, 1.f);
    const float fovy = 0.9f, aspect = float(kW) / float(kH);
    const float eps = shadowkit::projection_infinite_epsilon_bound(fovy, aspect, shadowkit::ClipDepth::ZeroToOne, true,
                                                                   shadowkit::DepthFormat::Float32).epsilon;
    const shadowkit::ProjectionResult pr =
        shadowkit::projection_perspective_infinite(fovy, aspect, 0.1f, shadowkit::ClipDepth::ZeroToOne, true, eps);
    REQUIRE(pr.status == shadowkit::Status::Ok);
    const glm::mat4 view = glm::lookAt(glm::vec3(0.f, 3.5f, 5.f), glm::vec3(0.f, 0.3f, 0.f), glm::vec3(0.f, 1.f, 0.f));
    BoundsResult out;
    shadowkit::ScissorParams sp;
    sp.view_proj = pr.matrix * view;
    sp.clip_depth = shadowkit::ClipDepth::ZeroToOne;
    sp.reversed_z = true;
    sp.viewport[2] = int(kW);
    sp.viewport[3] = int(kH);
    const glm::vec3 g(scene.ground_half, scene.box_c.y + scene.box_h.y, scene.ground_half);  // every receiver in the box
    out.sc = shadowkit::volume_scissor(light, scene.box_c - scene.box_h, scene.box_c + scene.box_h, glm::vec3(-g.x, 0.f, -g.z), g, sp);
    REQUIRE(out.sc.status == shadowkit::Status::Ok);
    REQUIRE(out.sc.visible);
    const glm::vec2 range = bounds == Bounds::Off    ? glm::vec2(-1.f, 2.f)
                            : bounds == Bounds::Wrong ? glm::vec2(out.sc.depth_max, out.sc.depth_max) - 1e-3f
                                                      : glm::vec2(out.sc.depth_min, out.sc.depth_max);
    const BoundsPush push{sp.view_proj, light, glm::vec4(bounds == Bounds::Native ? glm::vec2(-1.f, 2.f) : range, 0.f, 0.f)};
    const Volume volume = build_volume(scene, light);
    const BoundsShaders sh = compile_bounds_shaders(lang);

    const VkFormat dsf = depth_stencil_format(ctx);
    REQUIRE(dsf != VK_FORMAT_UNDEFINED);
    skvk::Image& world = scope.own<skvk::Image>();
    skvk::Image& normal = scope.own<skvk::Image>();
    skvk::Image& scene_depth = scope.own<skvk::Image>();
    skvk::Image& ds = scope.own<skvk::Image>();
    const VkImageUsageFlags rt = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    REQUIRE(skvk::make_image(ctx, kW, kH, 1, VK_FORMAT_R32G32B32A32_SFLOAT, rt, world));
    REQUIRE(skvk::make_image(ctx, kW, kH, 1, VK_FORMAT_R32G32B32A32_SFLOAT, rt, normal));
    REQUIRE(skvk::make_image(ctx, kW, kH, 1, VK_FORMAT_D32_SFLOAT,
                             VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT, scene_depth));
    REQUIRE(skvk::make_image(ctx, kW, kH, 1, dsf, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, ds));
    VkRenderPass gbuffer_rp = scope.keep(skvk::make_render_pass(ctx, {VK_FORMAT_R32G32B32A32_SFLOAT, VK_FORMAT_R32G32B32A32_SFLOAT},
                                                     VK_FORMAT_D32_SFLOAT, VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL), vkDestroyRenderPass);
    VkRenderPass main_rp = scope.keep(skvk::make_render_pass(ctx, {}, dsf, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL), vkDestroyRenderPass);
    VkFramebuffer gbuffer_fb = scope.keep(skvk::make_framebuffer(ctx, gbuffer_rp, {world.view, normal.view, scene_depth.view}, kW, kH), vkDestroyFramebuffer);
    VkFramebuffer main_fb = scope.keep(skvk::make_framebuffer(ctx, main_rp, {ds.view}, kW, kH), vkDestroyFramebuffer);
    skvk::Buffer& vb = scope.own<skvk::Buffer>();
    skvk::Buffer& volume_vb = scope.own<skvk::Buffer>();
    skvk::Buffer& volume_ib = scope.own<skvk::Buffer>();
    skvk::Buffer& counter = scope.own<skvk::Buffer>();
    const auto vcount = static_cast<std::uint32_t>(scene.vertices.size());
    REQUIRE(skvk::make_buffer(ctx, sizeof(skvk::SceneVertex) * vcount, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, vb));
    std::memcpy(vb.mapped, scene.vertices.data(), sizeof(skvk::SceneVertex) * vcount);
    REQUIRE(skvk::make_buffer(ctx, sizeof(glm::vec4) * volume.vertices.size(), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, volume_vb));
    std::memcpy(volume_vb.mapped, volume.vertices.data(), sizeof(glm::vec4) * volume.vertices.size());
    REQUIRE(skvk::make_buffer(ctx, sizeof(std::uint32_t) * volume.indices.size(), VK_BUFFER_USAGE_INDEX_BUFFER_BIT, volume_ib));
    std::memcpy(volume_ib.mapped, volume.indices.data(), sizeof(std::uint32_t) * volume.indices.size());
    REQUIRE(skvk::make_buffer(ctx, 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, counter));
    std::memset(counter.mapped, 0, 16);
    const VkDescriptorType tex = skvk::texture_type(lang);
    VkSampler nearest = scope.keep(skvk::make_sampler(ctx, VK_FILTER_NEAREST, VK_COMPARE_OP_NEVER), vkDestroySampler);
    skvk::DescriptorSet& set = scope.own<skvk::DescriptorSet>();
    REQUIRE(skvk::make_descriptor_set(ctx, {{0, tex, VK_SHADER_STAGE_FRAGMENT_BIT},
                                            {1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_FRAGMENT_BIT}}, set));
    skvk::write_image(ctx, set, 0, tex, scene_depth.view, lang == Source::Glsl ? nearest : VK_NULL_HANDLE,
                      VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL);
    skvk::write_buffer(ctx, set, 1, counter, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
    const VkShaderStageFlags push_stages = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
    VkPipelineLayout layout = scope.keep(skvk::make_pipeline_layout(ctx, &set, sizeof(BoundsPush), push_stages), vkDestroyPipelineLayout);
    const BoundsPipelines p = make_bounds_pipelines(ctx, scope, sh, layout, gbuffer_rp, main_rp, bounds == Bounds::Native);

    VkCommandBuffer cmd = skvk::begin_commands(ctx);
    const VkDeviceSize offset = 0;
    VkClearValue zero{}, ds_clear{};
    ds_clear.depthStencil = {0.f, 0};  // reversed-Z: far (and infinity) is 0
    const VkViewport vp = skvk::viewport(kW, kH, true);
    const VkRect2D full{{0, 0}, {kW, kH}};
    for (int pass = 0; pass < 2; ++pass) {
        const std::vector<VkClearValue> clears = pass == 0 ? std::vector<VkClearValue>{zero, zero, ds_clear} : std::vector<VkClearValue>{ds_clear};
        VkRenderPassBeginInfo bi{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
        bi.renderPass = pass == 0 ? gbuffer_rp : main_rp;
        bi.framebuffer = pass == 0 ? gbuffer_fb : main_fb;
        bi.renderArea = full;
        bi.clearValueCount = static_cast<std::uint32_t>(clears.size());
        bi.pClearValues = clears.data();
        vkCmdBeginRenderPass(cmd, &bi, VK_SUBPASS_CONTENTS_INLINE);
        vkCmdSetViewport(cmd, 0, 1, &vp);
        vkCmdSetScissor(cmd, 0, 1, &full);
        vkCmdPushConstants(cmd, layout, push_stages, 0, sizeof push, &push);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pass == 0 ? p.gbuffer : p.depth);
        vkCmdBindVertexBuffers(cmd, 0, 1, &vb.buffer, &offset);
        vkCmdDraw(cmd, vcount, 1, 0, 0);
        if (pass == 1) {
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p.volume);
            vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout, 0, 1, &set.set, 0, nullptr);
            if (scissor) {  // glScissor's rectangle counts rows from the bottom; the flipped viewport puts GL's row 0 last
                const VkRect2D sc{{out.sc.x, int(kH) - out.sc.y - out.sc.height},
                                  {std::uint32_t(out.sc.width), std::uint32_t(out.sc.height)}};
                vkCmdSetScissor(cmd, 0, 1, &sc);
            }
            if (bounds == Bounds::Native) vkCmdSetDepthBounds(cmd, range.x, range.y);
            vkCmdBindVertexBuffers(cmd, 0, 1, &volume_vb.buffer, &offset);
            vkCmdBindIndexBuffer(cmd, volume_ib.buffer, 0, VK_INDEX_TYPE_UINT32);
            vkCmdDrawIndexed(cmd, static_cast<std::uint32_t>(volume.indices.size()), 1, 0, 0, 0);
        }
        vkCmdEndRenderPass(cmd);
    }
    REQUIRE(skvk::submit_and_wait(ctx, cmd));
    out.world = skvk::read_image(ctx, world, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 4);
    out.normal = skvk::read_image(ctx, normal, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 4);
    out.stencil = skvk::read_stencil(ctx, ds, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    std::memcpy(&out.fragments, counter.mapped, sizeof out.fragments);

    return out;
}

std::size_t stencil_different(const BoundsResult& a, const BoundsResult& b) {
    std::size_t n = 0;
    for (std::size_t k = 0; k < a.stencil.size(); ++k) n += a.stencil[k] != b.stencil[k];
    return n;
}

double ray_cast_agreement(const BoundsResult& r) {
    const skvk::BoxScene scene;
    std::vector<float> vis(r.stencil.size());
    for (std::size_t k = 0; k < vis.size(); ++k) vis[k] = r.stencil[k] == 0 ? 1.f : 0.f;
    return skvk::compare_with_ray_cast(scene, glm::vec4(scene.light, 1.f), nullptr, int(kW), int(kH), vis, r.world, r.normal).fraction();
}

void check_bounds(Source lang) {
    skvk::Context& ctx = skvk::vk_test_context();
    REQUIRE_MESSAGE(ctx.enabled.fragmentStoresAndAtomics, "the fragment counter needs fragmentStoresAndAtomics");
    const std::string name = lang == Source::Glsl ? "GLSL" : "HLSL";
    const std::size_t before = skvk::message_count();
    const BoundsResult base = run_bounds(lang, false, Bounds::Off);
    REQUIRE(base.stencil.size() == std::size_t(kW) * kH);
    const double base_agree = ray_cast_agreement(base);
    MESSAGE(name << ": volume_scissor x " << base.sc.x << " y " << base.sc.y << " " << base.sc.width << " x " << base.sc.height
                 << ", depth bounds [" << base.sc.depth_min << ", " << base.sc.depth_max << "]; unculled: " << base.fragments
                 << " volume fragments, ray-cast agreement " << base_agree);
    CHECK(base_agree >= 0.995);
    std::vector<Bounds> modes{Bounds::Emulated};
    if (ctx.enabled.depthBounds)
        modes.push_back(Bounds::Native);
    else
        MESSAGE("the device has no depthBounds feature (lavapipe): vkCmdSetDepthBounds is not run, the emulation "
                "(sk_outside_depth_bounds_at) is");
    for (const Bounds mode : modes)
        for (auto [sc, db] : {std::pair{true, false}, std::pair{false, true}, std::pair{true, true}}) {
            const BoundsResult r = run_bounds(lang, sc, db ? mode : Bounds::Off);
            const std::size_t diff = stencil_different(base, r);
            const std::string what = name + ", scissor " + (sc ? "on" : "off") + ", depth bounds " +
                                     (db ? (mode == Bounds::Native ? "native" : "emulated") : "off");
            INFO(what);
            MESSAGE(what << ": stencil different from the unculled run on " << diff << " pixels; volume fragments " << r.fragments
                         << " of " << base.fragments);
            CHECK(diff == 0);
            if (mode == Bounds::Native && db) continue;  // the test follows the fragment stage: its count is not cut
            CHECK(r.fragments <= base.fragments);
            if (sc && db) CHECK(r.fragments < base.fragments * 9 / 10);
        }
    // the control: an empty range discards the volume everywhere (the emulation really runs)
    const BoundsResult wrong = run_bounds(lang, false, Bounds::Wrong);
    const double wrong_agree = ray_cast_agreement(wrong);
    MESSAGE(name << ", control, emulated bounds with an empty range: stencil different on " << stencil_different(base, wrong)
                 << " pixels, volume fragments " << wrong.fragments << ", ray-cast agreement " << wrong_agree);
    CHECK(stencil_different(base, wrong) > 1000);
    CHECK(wrong_agree < 0.99);
    CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());
}

}  // namespace

TEST_CASE("shadow_volume.glsl on Vulkan: z-fail stencil volumes, infinite reversed-Z and depth clamp, match the ray cast") {
    MESSAGE("depthClamp " << skvk::vk_test_context().supported.depthClamp << ", depthBounds "
                          << skvk::vk_test_context().supported.depthBounds);
    check(Source::Glsl);
}

TEST_CASE("shadow_volume.glsl on Vulkan, controls: swapped stencil operations wrap, a finite far plane without clamp loses shadow") {
    Variant v;
    v.swapped = true;
    const Result r = run(v);
    MESSAGE("swapped: stencil 0 / 1 / other " << r.zero << " / " << r.one << " / " << r.other);
    CHECK(r.other > 1000);
    Variant f;
    f.clamp = true;
    f.clamp_off = true;
    const Result c = run(f);
    MESSAGE("finite far plane without depth clamp: agreement " << c.agreement.fraction() << " (the far parts of the volumes, "
            "dark cap included, are clipped)");
    CHECK(c.agreement.fraction() < 0.99);
}

TEST_CASE("HLSL shadow_volume.hlsl on Vulkan: z-fail stencil volumes, infinite reversed-Z and depth clamp, match the ray cast") {
    check(Source::Hlsl);
}

TEST_CASE("shadow_volume.glsl on Vulkan: scissor and depth bounds (emulated; native where the device has them) leave the stencil unchanged") {
    check_bounds(Source::Glsl);
}

TEST_CASE("HLSL shadow_volume.hlsl on Vulkan: scissor and depth bounds (emulated; native where the device has them) leave the stencil unchanged") {
    check_bounds(Source::Hlsl);
}
