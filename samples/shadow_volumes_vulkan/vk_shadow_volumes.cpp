// samples/shadow_volumes_vulkan/vk_shadow_volumes.cpp - stenciled shadow volumes on Vulkan, top to bottom:
//   init    once per scene: casters' adjacency and face planes, the buffers, the depth-stencil image,
//           the descriptor set, the render pass, the four pipelines
//   update  CPU, every frame: P_inf (reversed-Z, [0, 1]), the light, per caster the silhouette, the
//           side quads and the z-fail caps (the same shadowkit calls as samples/shadow_volumes)
//   record  GPU, every frame: one render pass, four pipelines (depth + ambient, volume sides, volume
//           caps, lit where stencil == 0)
// The Vulkan plumbing (images, buffers, SPIR-V, pipeline state structs) is the test harness's
// tests/vulkan/vk_harness.hpp; what a Vulkan user decides is written out here.
#include "vk_shadow_volumes.hpp"

#include <shadowkit/infinite_projection.hpp>
#include <shadowkit/shadow_volume.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <tuple>

#include "gbuffer.hpp"  // app::load_snippet: glsl/shadow_volume.glsl, as the GL twin loads it

namespace {

// Descriptor set 0, binding 0: the frame's uniform buffer, the same block in every stage (std140).
struct FrameUniforms {
    glm::mat4 view_proj;        ///< P_inf (reversed-Z, [0, 1]) x view: scene and volumes alike
    glm::vec4 light_position;   ///< homogeneous: (p, 1) point, spot and area lights (center); (-dir, 0) sun
    glm::vec4 spot;             ///< xyz: where a spot light shines, w: cos of its half angle (-2: no cone)
};
#define SK_FRAME_BLOCK                                                                                   \
    "layout(set = 0, binding = 0) uniform Frame { mat4 view_proj; vec4 light_position; vec4 spot; } u;\n"

// The scene, drawn twice (depth + ambient, then lit) with this one vertex shader module: the same
// positions give the same depths, so the lit pass's GREATER_OR_EQUAL test passes on the visible surface.
const char* kSceneVs = "#version 450 core\n" SK_FRAME_BLOCK R"(
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
const char* kAmbientFs = R"(#version 450 core
layout(location = 0) in vec3 v_world;   // declared: the vertex shader's outputs are consumed
layout(location = 1) in vec3 v_normal;
layout(location = 0) out vec4 o_color;
void main() { o_color = vec4(0.12, 0.12, 0.14, 1.0); }
)";
const char* kLitFs = "#version 450 core\n" SK_FRAME_BLOCK R"(
layout(location = 0) in vec3 v_world;
layout(location = 1) in vec3 v_normal;
layout(location = 0) out vec4 o_color;
void main() {
    vec3 l = u.light_position.w == 0.0 ? normalize(u.light_position.xyz) : normalize(u.light_position.xyz - v_world);
    float cone = dot(-l, u.spot.xyz) >= u.spot.w ? 1.0 : 0.0;
    float diffuse = max(dot(normalize(v_normal), l), 0.0) * cone;
    o_color = vec4(vec3(0.12, 0.12, 0.14) + vec3(0.85, 0.82, 0.74) * diffuse, 1.0);
}
)";
// The volumes: (p, 1) and (p, 0) vertices, the w = 0 ones sent to infinity by the snippet.
const char* kVolumeVs = SK_FRAME_BLOCK R"(
layout(location = 0) in vec4 a_position;
void main() { gl_Position = u.view_proj * sk_extrude_shadow_volume(a_position, u.light_position); }
)";

struct SceneVertex {
    glm::vec3 position, normal;
};

bool failed(shadowkit::Status st, const char* what, std::string& why) {
    if (st == shadowkit::Status::Ok) return false;
    why = std::string(what) + ": " + shadowkit::status_name(st);
    return true;
}

VkFormat depth_stencil_format(const skvk::Context& ctx) {
    for (VkFormat f : {VK_FORMAT_D32_SFLOAT_S8_UINT, VK_FORMAT_D24_UNORM_S8_UINT}) {
        VkFormatProperties fp;
        vkGetPhysicalDeviceFormatProperties(ctx.physical, f, &fp);
        if (fp.optimalTilingFeatures & VK_FORMAT_FEATURE_DEPTH_STENCIL_ATTACHMENT_BIT) return f;
    }
    return VK_FORMAT_UNDEFINED;
}

// The render pass: what each attachment holds before and after, and one subpass using both.
VkRenderPass make_render_pass(skvk::Context& ctx, VkFormat color, VkImageLayout color_final, VkFormat depth_stencil) {
    VkAttachmentDescription att[2]{};
    att[0].format = color;  // the picture: cleared, stored, handed on in color_final
    att[0].samples = VK_SAMPLE_COUNT_1_BIT;
    att[0].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    att[0].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    att[0].stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    att[0].stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    att[0].initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    att[0].finalLayout = color_final;
    att[1].format = depth_stencil;  // depth cleared to 0 (reversed-Z: infinity), stencil cleared to 0
    att[1].samples = VK_SAMPLE_COUNT_1_BIT;
    att[1].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    att[1].storeOp = VK_ATTACHMENT_STORE_OP_STORE;          // a renderer would say DONT_CARE; the test reads them
    att[1].stencilLoadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;     // the counts start at 0 every frame
    att[1].stencilStoreOp = VK_ATTACHMENT_STORE_OP_STORE;
    att[1].initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    att[1].finalLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
    const VkAttachmentReference color_ref{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    const VkAttachmentReference ds_ref{1, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
    VkSubpassDescription sub{};
    sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    sub.colorAttachmentCount = 1;
    sub.pColorAttachments = &color_ref;
    sub.pDepthStencilAttachment = &ds_ref;
    // the previous frame's (or the swapchain's) use of the attachments before this pass writes them
    VkSubpassDependency dep{};
    dep.srcSubpass = VK_SUBPASS_EXTERNAL;
    dep.dstSubpass = 0;
    dep.srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
    dep.dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT;
    dep.dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
    VkRenderPassCreateInfo ci{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
    ci.attachmentCount = 2;
    ci.pAttachments = att;
    ci.subpassCount = 1;
    ci.pSubpasses = &sub;
    ci.dependencyCount = 1;
    ci.pDependencies = &dep;
    VkRenderPass rp = VK_NULL_HANDLE;
    return vkCreateRenderPass(ctx.device, &ci, nullptr, &rp) == VK_SUCCESS ? rp : VK_NULL_HANDLE;
}

template <class T>
bool upload(skvk::Context& ctx, const std::vector<T>& data, VkBufferUsageFlags usage, skvk::Buffer& b) {
    const VkDeviceSize size = std::max<VkDeviceSize>(sizeof(T) * data.size(), 16);
    if (!skvk::make_buffer(ctx, size, usage, b)) return false;
    if (!data.empty()) std::memcpy(b.mapped, data.data(), sizeof(T) * data.size());
    return true;
}

}  // namespace

bool VkShadowVolumes::init(skvk::Context& ctx, const sk::Scene& scene, std::uint32_t width, std::uint32_t height,
                           VkFormat color_format, VkImageLayout color_final, std::string& why) {
    release();
    ctx_ = &ctx;
    width_ = width;
    height_ = height;
    // the scene: every mesh in one interleaved vertex buffer and one index buffer
    std::vector<SceneVertex> sv;
    std::vector<std::uint32_t> si;
    for (const sk::Mesh& m : scene.meshes) {
        const auto base = static_cast<std::uint32_t>(sv.size());
        for (std::size_t k = 0; k < m.positions.size(); ++k) sv.push_back({m.positions[k], m.normals[k]});
        for (std::uint32_t i : m.indices) si.push_back(base + i);
    }
    scene_index_count_ = static_cast<std::uint32_t>(si.size());
    // the casters (as the GL twin's init): adjacency, face planes, room for this frame's volume
    std::vector<glm::vec4> vv;
    std::uint32_t indices = 0;
    for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
        const sk::Mesh& m = scene.meshes[i];
        if (!m.caster || m.indices.empty()) continue;
        Caster c;
        c.mesh = i;
        c.adj = shadowkit::silhouette_build_adjacency(m.positions.data(), m.positions.size(), m.indices.data(), m.indices.size());
        if (failed(c.adj.status, "silhouette_build_adjacency", why)) return false;
        c.planes = shadowkit::silhouette_build_planes(c.adj, m.positions.data(), m.positions.size());
        if (failed(c.planes.status, "silhouette_build_planes", why)) return false;
        c.base_vertex = static_cast<std::int32_t>(vv.size());
        vv.resize(vv.size() + 2 * m.positions.size());
        if (failed(shadowkit::volume_build_vertices(m.positions.data(), m.positions.size(), vv.data() + c.base_vertex,
                                                    2 * m.positions.size())
                       .status,
                   "volume_build_vertices", why))
            return false;
        c.facing.assign(c.adj.face_count(), 0);
        c.sil.assign(c.adj.closed() ? shadowkit::silhouette_indices_capacity(c.adj)
                                    : shadowkit::silhouette_two_sided_indices_capacity(c.adj), 0);
        c.index_capacity = static_cast<std::uint32_t>(3 * c.sil.size() + 6 * c.adj.face_count());  // sides + both caps
        c.index_offset = indices;
        indices += c.index_capacity;
        casters_.push_back(std::move(c));
    }
    const VkBufferUsageFlags vb = VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, ib = VK_BUFFER_USAGE_INDEX_BUFFER_BIT;
    if (!upload(ctx, sv, vb, scene_vb_) || !upload(ctx, si, ib, scene_ib_) || !upload(ctx, vv, vb, volume_vb_) ||
        !upload(ctx, std::vector<std::uint32_t>(std::max<std::uint32_t>(indices, 1)), ib, volume_ib_) ||
        !skvk::make_buffer(ctx, sizeof(FrameUniforms), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, frame_ubo_)) {
        why = "buffer allocation failed";
        return false;
    }
    // the depth-stencil attachment: a format with stencil (the counts)
    const VkFormat ds_format = depth_stencil_format(ctx);
    if (ds_format == VK_FORMAT_UNDEFINED ||
        !skvk::make_image(ctx, width, height, 1, ds_format,
                          VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, ds_)) {
        why = "no depth-stencil image (D32_SFLOAT_S8_UINT or D24_UNORM_S8_UINT)";
        return false;
    }
    // the descriptor set layout: set 0 = {binding 0: uniform buffer Frame, vertex + fragment}
    if (!skvk::make_descriptor_set(ctx, {{0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT}},
                                   set_)) {
        why = "descriptor set";
        return false;
    }
    skvk::write_buffer(ctx, set_, 0, frame_ubo_);
    VkPipelineLayoutCreateInfo li{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    li.setLayoutCount = 1;
    li.pSetLayouts = &set_.layout;
    if (vkCreatePipelineLayout(ctx.device, &li, nullptr, &layout_) != VK_SUCCESS) {
        why = "pipeline layout";
        return false;
    }
    pass_ = make_render_pass(ctx, color_format, color_final, ds_format);
    if (!pass_) {
        why = "render pass";
        return false;
    }
    return make_pipelines(why);
}

// The four pipelines. Shared: the y-flipping viewport (dynamic), counter-clockwise front faces.
bool VkShadowVolumes::make_pipelines(std::string& why) {
    skvk::Context& ctx = *ctx_;
    const std::string snippet = app::load_snippet("shadow_volume", why);
    if (snippet.empty()) return false;
    std::vector<std::uint32_t> scene_vs, ambient_fs, lit_fs, volume_vs;
    for (auto [spirv, stage, text] :
         {std::tuple{&scene_vs, VK_SHADER_STAGE_VERTEX_BIT, std::string(kSceneVs)},
          std::tuple{&ambient_fs, VK_SHADER_STAGE_FRAGMENT_BIT, std::string(kAmbientFs)},
          std::tuple{&lit_fs, VK_SHADER_STAGE_FRAGMENT_BIT, std::string(kLitFs)},
          std::tuple{&volume_vs, VK_SHADER_STAGE_VERTEX_BIT, "#version 450 core\n" + snippet + "\n" + kVolumeVs}}) {
        const std::string log = skvk::compile_spirv(skvk::Source::Glsl, stage, text, "main", *spirv);
        if (!log.empty()) {
            why = "glslang: " + log;
            return false;
        }
    }
    // 1 depth + ambient: reversed-Z (GREATER, cleared to 0), depth writes
    skvk::PipelineDesc scene;
    scene.vs = scene_vs;
    scene.fs = ambient_fs;
    scene.vertex_stride = sizeof(SceneVertex);
    scene.attributes = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0}, {1, 0, VK_FORMAT_R32G32B32_SFLOAT, 12}};
    scene.depth_compare = VK_COMPARE_OP_GREATER;
    scene.color_count = 1;
    depth_pipe_ = skvk::make_pipeline(ctx, scene, layout_, pass_, why);
    // 4 lit: the same vertices, depth equal or nearer without writes, only where the stencil is 0
    skvk::PipelineDesc lit = scene;
    lit.fs = lit_fs;
    lit.depth_compare = VK_COMPARE_OP_GREATER_OR_EQUAL;
    lit.depth_write = false;
    lit.stencil = true;
    lit.stencil_front = lit.stencil_back = {VK_STENCIL_OP_KEEP, VK_STENCIL_OP_KEEP, VK_STENCIL_OP_KEEP, VK_COMPARE_OP_EQUAL,
                                            0xff, 0x00, 0};
    lit_pipe_ = skvk::make_pipeline(ctx, lit, layout_, pass_, why);
    // 2 volume sides: no colour or depth writes, both faces, two-sided z-fail stencil
    // (Everitt & Kilgard 2002: count the volume's faces behind the scene, back +1, front -1, wrapping)
    skvk::PipelineDesc vol;
    vol.vs = volume_vs;  // no fragment shader: depth and stencil only
    vol.vertex_stride = sizeof(glm::vec4);
    vol.attributes = {{0, 0, VK_FORMAT_R32G32B32A32_SFLOAT, 0}};
    vol.depth_compare = VK_COMPARE_OP_GREATER;
    vol.depth_write = false;
    vol.depth_clamp = ctx.enabled.depthClamp != VK_FALSE;  // a safety net: P_inf puts w = 0 at depth epsilon
    vol.color_count = 1;
    vol.color_write = false;
    vol.cull = VK_CULL_MODE_NONE;
    vol.stencil = true;
    vol.stencil_back = {VK_STENCIL_OP_KEEP, VK_STENCIL_OP_KEEP, VK_STENCIL_OP_INCREMENT_AND_WRAP, VK_COMPARE_OP_ALWAYS, 0xff, 0xff, 0};
    vol.stencil_front = {VK_STENCIL_OP_KEEP, VK_STENCIL_OP_KEEP, VK_STENCIL_OP_DECREMENT_AND_WRAP, VK_COMPARE_OP_ALWAYS, 0xff, 0xff, 0};
    sides_pipe_ = skvk::make_pipeline(ctx, vol, layout_, pass_, why);
    // 3 volume caps: the same, pushed away from the eye (reversed-Z: a negative bias), the GL twin's
    // glPolygonOffset(0, -8): the light cap lies on the lit faces and must count as behind them
    skvk::PipelineDesc caps = vol;
    caps.depth_bias = true;
    caps.bias_constant = -8.f;
    caps_pipe_ = skvk::make_pipeline(ctx, caps, layout_, pass_, why);
    return depth_pipe_ && lit_pipe_ && sides_pipe_ && caps_pipe_;
}

VkFramebuffer VkShadowVolumes::make_framebuffer(VkImageView color) const {
    return skvk::make_framebuffer(*ctx_, pass_, {color, ds_.view}, width_, height_);
}

std::string VkShadowVolumes::update(const sk::Scene& scene) {
    std::string why;
    const sk::Camera& cam = scene.camera;
    const float aspect = float(width_) / float(height_);
    // P_inf in [0, 1] with reversed-Z (infinite_projection.hpp; Everitt & Kilgard's epsilon keeps the
    // vertices at infinity inside the clip volume)
    shadowkit::ProjectionDepth dp;
    dp.near_z = cam.znear;
    dp.far_z = std::numeric_limits<float>::infinity();
    dp.clip_depth = shadowkit::ClipDepth::ZeroToOne;
    dp.reversed_z = true;
    const shadowkit::ProjectionEpsilonBound eb = shadowkit::projection_infinite_epsilon_bound(
        cam.fovy, aspect, dp.clip_depth, true, shadowkit::DepthFormat::Float32);
    if (failed(eb.status, "projection_infinite_epsilon_bound", why)) return why;
    dp.epsilon = eb.epsilon;
    const shadowkit::ProjectionResult pr = shadowkit::projection_perspective(cam.fovy, aspect, dp);
    if (failed(pr.status, "projection_perspective", why)) return why;
    view_proj_ = pr.matrix * cam.view();
    const sk::Light& L = scene.light;
    light_ = L.homogeneous_position();
    if (!shadowkit::silhouette_valid_light(light_)) return "invalid light";
    FrameUniforms fu{view_proj_, light_, glm::vec4(glm::normalize(L.direction), -2.f)};
    if (L.type == sk::LightType::Spot) fu.spot.w = std::cos(L.spot_half_angle);
    std::memcpy(frame_ubo_.mapped, &fu, sizeof fu);

    // per caster (the GL twin's update, z-fail always): facing, silhouette, side quads, caps
    auto* out_base = static_cast<std::uint32_t*>(volume_ib_.mapped);
    for (Caster& c : casters_) {
        const sk::Mesh& m = scene.meshes[c.mesh];
        c.two_sided = !c.adj.closed();
        c.side_count = c.cap_count = 0;
        const shadowkit::SilhouetteFacing fr =
            shadowkit::silhouette_compute_facing_planes(c.adj, c.planes, light_, c.facing.data(), c.facing.size());
        if (failed(fr.status, "silhouette_compute_facing_planes", why)) return why;
        const shadowkit::SilhouetteResult sr =
            c.two_sided ? shadowkit::silhouette_extract_two_sided(c.adj, c.facing.data(), c.facing.size(), c.sil.data(),
                                                                   c.sil.size(), nullptr, 0)
                        : shadowkit::silhouette_extract_planes(c.adj, c.planes, c.facing.data(), c.facing.size(), c.sil.data(),
                                                               c.sil.size(), nullptr, 0);
        if (failed(sr.status, "silhouette_extract", why)) return why;
        std::uint32_t* out = out_base + c.index_offset;
        const shadowkit::VolumeBuffer sq =
            shadowkit::volume_build_side_quads(c.sil.data(), sr.count, m.positions.size(), out, c.index_capacity);
        if (failed(sq.status, "volume_build_side_quads", why)) return why;
        const shadowkit::VolumeBuffer cp = shadowkit::volume_build_caps(
            c.adj.faces.data(), c.adj.faces.size(), c.facing.data(), c.facing.size(), m.positions.size(),
            c.two_sided ? shadowkit::VolumeCapMode::TwoSided : shadowkit::VolumeCapMode::LitOnly, light_.w > 0.f,
            out + sq.count, c.index_capacity - sq.count);
        if (failed(cp.status, "volume_build_caps", why)) return why;
        c.side_count = static_cast<std::uint32_t>(sq.count);
        c.cap_count = static_cast<std::uint32_t>(cp.count);
    }
    return {};
}

void VkShadowVolumes::record(VkCommandBuffer cmd, VkFramebuffer fb) const {
    VkClearValue clears[2]{};
    clears[0].color = {{0.05f, 0.05f, 0.07f, 1.f}};
    clears[1].depthStencil = {0.f, 0};  // reversed-Z: 0 is infinitely far; no volume counted yet
    VkRenderPassBeginInfo bi{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    bi.renderPass = pass_;
    bi.framebuffer = fb;
    bi.renderArea = {{0, 0}, {width_, height_}};
    bi.clearValueCount = 2;
    bi.pClearValues = clears;
    vkCmdBeginRenderPass(cmd, &bi, VK_SUBPASS_CONTENTS_INLINE);
    const VkViewport vp = skvk::viewport(width_, height_, true);  // negative height: NDC y up, as on GL
    const VkRect2D sc{{0, 0}, {width_, height_}};
    vkCmdSetViewport(cmd, 0, 1, &vp);
    vkCmdSetScissor(cmd, 0, 1, &sc);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_, 0, 1, &set_.set, 0, nullptr);
    const VkDeviceSize zero = 0;
    // 1 depth + ambient
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, depth_pipe_);
    vkCmdBindVertexBuffers(cmd, 0, 1, &scene_vb_.buffer, &zero);
    vkCmdBindIndexBuffer(cmd, scene_ib_.buffer, 0, VK_INDEX_TYPE_UINT32);
    vkCmdDrawIndexed(cmd, scene_index_count_, 1, 0, 0, 0);
    // 2 and 3: every caster's sides, then every caster's caps, into the stencil
    vkCmdBindVertexBuffers(cmd, 0, 1, &volume_vb_.buffer, &zero);
    vkCmdBindIndexBuffer(cmd, volume_ib_.buffer, 0, VK_INDEX_TYPE_UINT32);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, sides_pipe_);
    for (const Caster& c : casters_)
        if (c.side_count) vkCmdDrawIndexed(cmd, c.side_count, 1, c.index_offset, c.base_vertex, 0);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, caps_pipe_);
    for (const Caster& c : casters_)
        if (c.cap_count) vkCmdDrawIndexed(cmd, c.cap_count, 1, c.index_offset + c.side_count, c.base_vertex, 0);
    // 4 lit where stencil == 0
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, lit_pipe_);
    vkCmdBindVertexBuffers(cmd, 0, 1, &scene_vb_.buffer, &zero);
    vkCmdBindIndexBuffer(cmd, scene_ib_.buffer, 0, VK_INDEX_TYPE_UINT32);
    vkCmdDrawIndexed(cmd, scene_index_count_, 1, 0, 0, 0);
    vkCmdEndRenderPass(cmd);
}

void VkShadowVolumes::release() {
    if (!ctx_) return;
    skvk::Context& ctx = *ctx_;
    vkDeviceWaitIdle(ctx.device);
    for (VkPipeline p : {depth_pipe_, sides_pipe_, caps_pipe_, lit_pipe_})
        if (p) vkDestroyPipeline(ctx.device, p, nullptr);
    depth_pipe_ = sides_pipe_ = caps_pipe_ = lit_pipe_ = VK_NULL_HANDLE;
    if (layout_) vkDestroyPipelineLayout(ctx.device, layout_, nullptr);
    if (pass_) vkDestroyRenderPass(ctx.device, pass_, nullptr);
    layout_ = VK_NULL_HANDLE;
    pass_ = VK_NULL_HANDLE;
    skvk::destroy(ctx, set_);
    skvk::destroy(ctx, ds_);
    for (skvk::Buffer* b : {&scene_vb_, &scene_ib_, &volume_vb_, &volume_ib_, &frame_ubo_}) skvk::destroy(ctx, *b);
    casters_.clear();
    ctx_ = nullptr;
}
