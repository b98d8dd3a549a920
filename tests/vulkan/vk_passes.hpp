// Helpers the Vulkan tests share (doctest assertions inside): reading a snippet, compiling a stage to
// SPIR-V with glslang and checking it with spirv-val, and recording one render pass that draws a
// vertex buffer with a viewport (y flipped or not).
#pragma once

#include <doctest/doctest.h>

#include <glm/glm.hpp>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "vk_harness.hpp"

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

}  // namespace skvk
