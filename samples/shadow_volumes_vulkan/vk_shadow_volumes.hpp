// samples/shadow_volumes_vulkan/vk_shadow_volumes.hpp - stenciled shadow volumes on Vulkan: the Vulkan
// twin of samples/shadow_volumes (GL). The same shadowkit calls on the CPU (silhouette.hpp,
// shadow_volume.hpp, infinite_projection.hpp) and the same snippet (glsl/shadow_volume.glsl, compiled
// to SPIR-V by glslang); what changes is how the GPU is told:
//   descriptor set 0, binding 0: one uniform buffer `Frame` (view_proj, light, spot cone), read by the
//     vertex and fragment stages of every pipeline (the GL twin's uniforms)
//   one render pass, one subpass: a colour attachment (cleared, stored: the picture) and a
//     depth-stencil attachment with stencil (D32_SFLOAT_S8_UINT or D24_UNORM_S8_UINT; depth and
//     stencil cleared to 0, stored only for the test's readback)
//   four pipelines drawn in order inside it:
//     1 depth + ambient   the scene: depth test GREATER (reversed-Z), depth writes, ambient colour
//     2 volume sides      the extruded silhouette quads: no colour or depth writes, both faces, two-sided
//                         z-fail stencil (back faces INCREMENT_AND_WRAP, front DECREMENT_AND_WRAP on
//                         depth fail), depth clamp where the device has depthClamp
//     3 volume caps       the same with a constant depth bias away from the eye (the GL twin's polygon
//                         offset: the light cap lies on the caster's lit faces and must fail there)
//     4 lit               the scene again: depth GREATER_OR_EQUAL without writes, stencil EQUAL 0:
//                         ambient + diffuse where no volume surrounds the point
// Conventions (docs/vulkan_and_direct3d.md): clip depth [0, 1] with reversed-Z and the far plane at
// infinity (projection_perspective with ClipDepth::ZeroToOne, the Everitt-Kilgard epsilon), the y flip
// in the viewport (negative height, VK_KHR_maintenance1, core in 1.1): the matrices are the GL twin's
// camera, counter-clockwise stays the front face.
#pragma once

#include <shadowkit/silhouette.hpp>

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "scene.hpp"
#include "vk_harness.hpp"

class VkShadowVolumes {
public:
    /// One caster: adjacency once per scene, this frame's silhouette and volume indices.
    struct Caster {
        std::size_t mesh = 0;
        shadowkit::SilhouetteAdjacency adj;
        shadowkit::SilhouettePlanes planes;
        std::int32_t base_vertex = 0;           ///< first of its 2n vertices (p, 1), (p, 0)
        std::uint32_t index_offset = 0, index_capacity = 0;
        std::vector<std::uint8_t> facing;
        std::vector<std::uint32_t> sil;
        bool two_sided = false;                 ///< open mesh: every face an occluder (silhouette.hpp)
        std::uint32_t side_count = 0, cap_count = 0;
    };

    VkShadowVolumes() = default;
    VkShadowVolumes(const VkShadowVolumes&) = delete;
    VkShadowVolumes& operator=(const VkShadowVolumes&) = delete;
    ~VkShadowVolumes() { release(); }

    /// Once per scene and target format: casters' adjacency, buffers, the depth-stencil image, the
    /// descriptor set, the render pass (colour `color_format`, left in `color_final` after the pass:
    /// TRANSFER_SRC_OPTIMAL headless, PRESENT_SRC_KHR for a swapchain) and the four pipelines.
    bool init(skvk::Context& ctx, const sk::Scene& scene, std::uint32_t width, std::uint32_t height, VkFormat color_format,
              VkImageLayout color_final, std::string& why);
    /// A framebuffer on a colour view of the target's size and our depth-stencil (the caller destroys it).
    VkFramebuffer make_framebuffer(VkImageView color) const;
    /// CPU, every frame: the matrices and the light into the uniform buffer; per caster facing,
    /// silhouette, side quads and z-fail caps into the index buffer (mapped: the previous frame must
    /// have finished). "" or the failing call.
    std::string update(const sk::Scene& scene);
    /// Records the render pass into `cmd` on `fb`.
    void record(VkCommandBuffer cmd, VkFramebuffer fb) const;
    void release();

    const skvk::Image& depth_stencil() const { return ds_; }
    const glm::mat4& view_proj() const { return view_proj_; }  ///< P_inf (reversed, [0, 1]) x view
    const glm::vec4& light() const { return light_; }           ///< homogeneous (w = 0: toward the light)
    const std::vector<Caster>& casters() const { return casters_; }

private:
    bool make_pipelines(std::string& why);
    skvk::Context* ctx_ = nullptr;
    std::uint32_t width_ = 0, height_ = 0;
    std::vector<Caster> casters_;
    std::uint32_t scene_index_count_ = 0;
    glm::mat4 view_proj_{1.f};
    glm::vec4 light_{0.f};
    skvk::Buffer scene_vb_, scene_ib_, volume_vb_, volume_ib_, frame_ubo_;
    skvk::Image ds_;
    skvk::DescriptorSet set_;
    VkRenderPass pass_ = VK_NULL_HANDLE;
    VkPipelineLayout layout_ = VK_NULL_HANDLE;
    VkPipeline depth_pipe_ = VK_NULL_HANDLE, sides_pipe_ = VK_NULL_HANDLE, caps_pipe_ = VK_NULL_HANDLE,
               lit_pipe_ = VK_NULL_HANDLE;
};
