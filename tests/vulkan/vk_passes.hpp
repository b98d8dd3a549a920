// Helpers the Vulkan tests share (doctest assertions inside): reading a snippet, compiling a stage to
// SPIR-V with glslang and checking it with spirv-val, recording one render pass that draws a vertex
// buffer with a viewport (y flipped or not), pipeline layouts, the scene's pipeline description, the
// receiver pass's descriptor set, targets and read-back, and the lookup-row pass (a fullscreen
// triangle into an M x 1 target, one lookup a pixel).
#pragma once

#include <doctest/doctest.h>

#include <glm/glm.hpp>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "vk_harness.hpp"
#include "vk_scene.hpp"

namespace skvk {

inline std::string read_text(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    std::ostringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

/// Compiles one stage (REQUIREs success), writes SHADOWKIT_VK_SPIRV_DIR/<spv_name>.spv and CHECKs spirv-val on it.
inline std::vector<std::uint32_t> compile_checked(Source lang, VkShaderStageFlagBits stage, const std::string& text,
                                                  const char* entry, const std::string& spv_name) {
    std::vector<std::uint32_t> spirv;
    const std::string err = compile_spirv(lang, stage, text, entry, spirv);
    REQUIRE_MESSAGE(err.empty(), spv_name << ": " << err);
    bool validated = false;
    const std::string val = spirv_val(spirv, std::string(SHADOWKIT_VK_SPIRV_DIR) + "/" + spv_name + ".spv", validated);
    CHECK_MESSAGE(val.empty(), val);
    return spirv;
}

/// Records one render pass drawing `count` vertices of `vb` (nullptr: none bound) with `pipe`, the
/// whole target as viewport (negative height when `flip`), an optional descriptor set and optional
/// push constants (`push_bytes` of `push` for `push_stages`: one matrix for the vertex stage by default).
inline void draw_pass(VkCommandBuffer cmd, VkRenderPass rp, VkFramebuffer fb, std::uint32_t w, std::uint32_t h,
                      const std::vector<VkClearValue>& clears, VkPipeline pipe, VkPipelineLayout layout,
                      const VkDescriptorSet* set, const void* push, VkBuffer vb, std::uint32_t count, bool flip,
                      std::uint32_t push_bytes = sizeof(glm::mat4),
                      VkShaderStageFlags push_stages = VK_SHADER_STAGE_VERTEX_BIT) {
    VkRenderPassBeginInfo bi{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    bi.renderPass = rp;
    bi.framebuffer = fb;
    bi.renderArea = {{0, 0}, {w, h}};
    bi.clearValueCount = static_cast<std::uint32_t>(clears.size());
    bi.pClearValues = clears.data();
    vkCmdBeginRenderPass(cmd, &bi, VK_SUBPASS_CONTENTS_INLINE);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipe);
    const VkViewport vp = viewport(w, h, flip);
    const VkRect2D sc{{0, 0}, {w, h}};
    vkCmdSetViewport(cmd, 0, 1, &vp);
    vkCmdSetScissor(cmd, 0, 1, &sc);
    if (set) vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout, 0, 1, set, 0, nullptr);
    if (push) vkCmdPushConstants(cmd, layout, push_stages, 0, push_bytes, push);
    if (vb) {
        const VkDeviceSize offset = 0;
        vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &offset);
    }
    vkCmdDraw(cmd, count, 1, 0, 0);
    vkCmdEndRenderPass(cmd);
}

/// A pipeline layout of one descriptor set layout (VK_NULL_HANDLE: none) and, when `push_bytes` > 0,
/// one push-constant range of that size for `push_stages` (REQUIREs success).
inline VkPipelineLayout make_pipeline_layout_from(Context& ctx, VkDescriptorSetLayout set_layout, std::uint32_t push_bytes = 0,
                                                  VkShaderStageFlags push_stages = VK_SHADER_STAGE_VERTEX_BIT) {
    const VkPushConstantRange range{push_stages, 0, push_bytes};
    VkPipelineLayoutCreateInfo li{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    if (set_layout != VK_NULL_HANDLE) {
        li.setLayoutCount = 1;
        li.pSetLayouts = &set_layout;
    }
    if (push_bytes > 0) {
        li.pushConstantRangeCount = 1;
        li.pPushConstantRanges = &range;
    }
    VkPipelineLayout layout = VK_NULL_HANDLE;
    REQUIRE(vkCreatePipelineLayout(ctx.device, &li, nullptr, &layout) == VK_SUCCESS);
    return layout;
}
/// The same with `set`'s layout (nullptr: no set).
inline VkPipelineLayout make_pipeline_layout(Context& ctx, const DescriptorSet* set, std::uint32_t push_bytes = 0,
                                             VkShaderStageFlags push_stages = VK_SHADER_STAGE_VERTEX_BIT) {
    return make_pipeline_layout_from(ctx, set ? set->layout : VK_NULL_HANDLE, push_bytes, push_stages);
}

/// The descriptor type of a texture the shader samples: GLSL's samplers are combined image samplers,
/// HLSL's textures sampled images (their samplers bound apart).
inline VkDescriptorType texture_type(Source lang) {
    return lang == Source::Glsl ? VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER : VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE;
}

/// The receiver pass's descriptor set: the map `view` (in `layout`) at binding 0 (GLSL: a combined
/// image sampler with `sampler`; HLSL: a sampled image, and `sampler` at binding 2) and `ubo` at
/// binding 1 (vertex and fragment stages); `extra` bindings are added to the layout (the caller
/// writes them). REQUIREs success.
inline void make_lookup_set(Context& ctx, Source lang, VkImageView view, VkImageLayout layout, VkSampler sampler,
                            const Buffer& ubo, DescriptorSet& ds, const std::vector<Binding>& extra = {}) {
    const VkShaderStageFlags frag = VK_SHADER_STAGE_FRAGMENT_BIT, both = VK_SHADER_STAGE_VERTEX_BIT | frag;
    const bool glsl = lang == Source::Glsl;
    std::vector<Binding> b = {{0, texture_type(lang), frag}, {1, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, both}};
    if (!glsl) b.push_back({2, VK_DESCRIPTOR_TYPE_SAMPLER, frag});
    b.insert(b.end(), extra.begin(), extra.end());
    REQUIRE(make_descriptor_set(ctx, b, ds));
    write_image(ctx, ds, 0, texture_type(lang), view, glsl ? sampler : VK_NULL_HANDLE, layout);
    if (!glsl) write_sampler(ctx, ds, 2, sampler);
    write_buffer(ctx, ds, 1, ubo);
}

/// A pipeline drawing the scene's vertex buffer (SceneVertex: position at location 0, and the normal
/// at location 1 when `normals`); `fs` empty: depth only. The rest is PipelineDesc's defaults.
inline PipelineDesc scene_pipeline(const std::vector<std::uint32_t>& vs, const std::vector<std::uint32_t>& fs,
                                   const char* vs_entry = "main", const char* fs_entry = "main", bool normals = true) {
    PipelineDesc d;
    d.vs = vs;
    d.fs = fs;
    d.vs_entry = vs_entry;
    d.fs_entry = fs_entry;
    d.vertex_stride = sizeof(SceneVertex);
    d.attributes = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0}};
    if (normals) d.attributes.push_back({1, 0, VK_FORMAT_R32G32B32_SFLOAT, 12});
    return d;
}

/// make_pipeline that REQUIREs a pipeline (the reason as the message).
inline VkPipeline make_pipeline_checked(Context& ctx, const PipelineDesc& d, VkPipelineLayout layout, VkRenderPass rp) {
    std::string why;
    VkPipeline pipe = make_pipeline(ctx, d, layout, rp, why);
    REQUIRE_MESSAGE(pipe != VK_NULL_HANDLE, why);
    return pipe;
}

/// The receiver pass's targets, w x h: visibility R32F, world point and normal RGBA32F (kReceiver*'s
/// three outputs), a D32 depth buffer, their render pass and framebuffer.
struct ReceiverTargets {
    Image vis, world, normal, depth;
    VkRenderPass rp = VK_NULL_HANDLE;
    VkFramebuffer fb = VK_NULL_HANDLE;
    std::uint32_t w = 0, h = 0;
};
inline void make_receiver_targets(Context& ctx, std::uint32_t w, std::uint32_t h, ReceiverTargets& t) {
    const VkImageUsageFlags rt = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    REQUIRE(make_image(ctx, w, h, 1, VK_FORMAT_R32_SFLOAT, rt, t.vis));
    REQUIRE(make_image(ctx, w, h, 1, VK_FORMAT_R32G32B32A32_SFLOAT, rt, t.world));
    REQUIRE(make_image(ctx, w, h, 1, VK_FORMAT_R32G32B32A32_SFLOAT, rt, t.normal));
    REQUIRE(make_image(ctx, w, h, 1, VK_FORMAT_D32_SFLOAT, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, t.depth));
    t.rp = make_render_pass(ctx, {VK_FORMAT_R32_SFLOAT, VK_FORMAT_R32G32B32A32_SFLOAT, VK_FORMAT_R32G32B32A32_SFLOAT},
                            VK_FORMAT_D32_SFLOAT, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL);
    t.fb = make_framebuffer(ctx, t.rp, {t.vis.view, t.world.view, t.normal.view, t.depth.view}, w, h);
    t.w = w;
    t.h = h;
}
inline void destroy(Context& ctx, ReceiverTargets& t) {
    vkDestroyFramebuffer(ctx.device, t.fb, nullptr);
    vkDestroyRenderPass(ctx.device, t.rp, nullptr);
    destroy(ctx, t.vis);
    destroy(ctx, t.world);
    destroy(ctx, t.normal);
    destroy(ctx, t.depth);
    t.fb = VK_NULL_HANDLE;
    t.rp = VK_NULL_HANDLE;
}

/// The receiver pass read back: visibility (1 float a pixel), world point and normal (4 each).
struct ReceiverImages {
    std::vector<float> vis, world, normal;
};
inline ReceiverImages read_receiver(Context& ctx, const ReceiverTargets& t) {
    ReceiverImages r;
    r.vis = read_image(ctx, t.vis, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 1);
    r.world = read_image(ctx, t.world, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 4);
    r.normal = read_image(ctx, t.normal, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 4);
    REQUIRE(r.vis.size() == std::size_t(t.w) * t.h);
    return r;
}

/// read_receiver, then compare_with_ray_cast on it (`frustum`: the spot light's matrix, or nullptr).
inline Agreement receiver_agreement(Context& ctx, const ReceiverTargets& t, const BoxScene& s, glm::vec4 light,
                                    const glm::mat4* frustum = nullptr) {
    const ReceiverImages r = read_receiver(ctx, t);
    return compare_with_ray_cast(s, light, frustum, int(t.w), int(t.h), r.vis, r.world, r.normal);
}

/// A fullscreen triangle's vertex stage (three vertices, no vertex buffer): GLSL, and HLSL's `vs_main`.
inline constexpr const char* kFullscreenGlsl = R"(#version 450 core
void main() {
    vec2 p = vec2(float((gl_VertexIndex << 1) & 2), float(gl_VertexIndex & 2));
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
)";
inline constexpr const char* kFullscreenHlsl = R"(
float4 vs_main(uint id : SV_VertexID) : SV_Position {
    float2 p = float2(float((id << 1) & 2), float(id & 2));
    return float4(p * 2.0 - 1.0, 0.0, 1.0);
}
)";

/// The lookup-row pass: the fullscreen triangle into an M x 1 colour target (no depth), the fragment
/// stage evaluating lookup gl_FragCoord.x; its pipeline layout has one set (`set_layout`'s) and, when
/// `push_bytes` > 0, push constants for the fragment stage.
struct RowPass {
    Image target;
    VkRenderPass rp = VK_NULL_HANDLE;
    VkFramebuffer fb = VK_NULL_HANDLE;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VkPipeline pipe = VK_NULL_HANDLE;
    std::uint32_t M = 0, components = 1, push_bytes = 0;
};
/// Makes it (REQUIREs every step): `components` floats a texel of `format`.
inline void make_row_pass(Context& ctx, const std::vector<std::uint32_t>& vs, const std::vector<std::uint32_t>& fs,
                          const char* vs_entry, const char* fs_entry, const DescriptorSet& set_layout, std::uint32_t M,
                          RowPass& r, VkFormat format = VK_FORMAT_R32_SFLOAT, std::uint32_t components = 1,
                          std::uint32_t push_bytes = 0) {
    REQUIRE(make_image(ctx, M, 1, 1, format, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, r.target));
    r.rp = make_render_pass(ctx, {format}, VK_FORMAT_UNDEFINED, VK_IMAGE_LAYOUT_UNDEFINED);
    r.fb = make_framebuffer(ctx, r.rp, {r.target.view}, M, 1);
    r.layout = make_pipeline_layout(ctx, &set_layout, push_bytes, VK_SHADER_STAGE_FRAGMENT_BIT);
    PipelineDesc pd;
    pd.vs = vs;
    pd.fs = fs;
    pd.vs_entry = vs_entry;
    pd.fs_entry = fs_entry;
    pd.depth_test = pd.depth_write = false;
    pd.color_count = 1;
    r.pipe = make_pipeline_checked(ctx, pd, r.layout, r.rp);
    r.M = M;
    r.components = components;
    r.push_bytes = push_bytes;
}
/// One draw with descriptor set `set` (and `push`: push_bytes of push constants), read back
/// (REQUIREs M * components floats).
inline std::vector<float> draw_row(Context& ctx, const RowPass& r, const DescriptorSet& set, const void* push = nullptr) {
    VkCommandBuffer cmd = begin_commands(ctx);
    VkClearValue zero{};
    draw_pass(cmd, r.rp, r.fb, r.M, 1, {zero}, r.pipe, r.layout, &set.set, push, VK_NULL_HANDLE, 3, false, r.push_bytes,
              VK_SHADER_STAGE_FRAGMENT_BIT);
    REQUIRE(submit_and_wait(ctx, cmd));
    std::vector<float> v = read_image(ctx, r.target, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, r.components);
    REQUIRE(v.size() == std::size_t(r.M) * r.components);
    return v;
}
inline void destroy(Context& ctx, RowPass& r) {
    vkDestroyPipeline(ctx.device, r.pipe, nullptr);
    vkDestroyPipelineLayout(ctx.device, r.layout, nullptr);
    vkDestroyFramebuffer(ctx.device, r.fb, nullptr);
    vkDestroyRenderPass(ctx.device, r.rp, nullptr);
    destroy(ctx, r.target);
    r = RowPass{};
}

}  // namespace skvk
