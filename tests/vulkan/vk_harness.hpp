// A small headless Vulkan 1.1 harness for the tests of labels `vulkan` and `hlsl` (Mesa's lavapipe in
// CI): one device and queue, VK_LAYER_KHRONOS_validation with a debug-utils messenger that counts every
// warning and error (a test fails on any), offscreen images, render passes, pipelines from SPIR-V that
// glslang makes in process (GLSL or HLSL source), descriptor sets, readback to the CPU, and a Scope
// that destroys what a test case made (in reverse order, also when a REQUIRE throws out of the case).
// The process-wide context is made by vk_main.cpp before any test runs: no Vulkan device gives exit 77
// (CTest: skipped), or a failure where SHADOWKIT_REQUIRE_GL=1 is set (as in CI).
#pragma once

#include <vulkan/vulkan.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace skvk {

struct Context {
    VkInstance instance = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
    VkPhysicalDevice physical = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;
    std::uint32_t queue_family = 0;
    VkCommandPool pool = VK_NULL_HANDLE;
    VkPhysicalDeviceFeatures supported{};  ///< what the device offers (depthClamp, depthBounds, ...)
    VkPhysicalDeviceFeatures enabled{};    ///< what the harness turned on
    std::string device_name;
    bool validation = false;               ///< VK_LAYER_KHRONOS_validation is on
    /// Extensions a caller asks for beyond the harness's own, set before create_context (a window:
    /// glfwGetRequiredInstanceExtensions and VK_KHR_swapchain; samples/shadow_volumes_vulkan).
    std::vector<const char*> instance_extensions, device_extensions;
};

/// The process-wide context (vk_main.cpp).
Context& vk_test_context();

/// Makes the context. Returns "" or why not; `no_device` is true when the reason is a missing
/// loader, driver or layer (a skip where allowed) rather than an error.
std::string create_context(Context& ctx, bool want_validation, bool& no_device);
void destroy_context(Context& ctx);

/// Warning and error messages the debug-utils messenger received since the process started.
std::size_t message_count();
/// Messages a test provoked on purpose (to show the count works) are declared with expect_messages
/// and not held against the run.
std::size_t unexpected_message_count();
void expect_messages(std::size_t n);
/// Their text (the first 20).
std::string messages();

// ---------------------------------------------------------------------------------------- SPIR-V
enum class Source { Glsl, Hlsl };
/// Compiles one stage to SPIR-V 1.3 for Vulkan 1.1 with glslang (GLSL: #version in the text; HLSL:
/// `entry` is the entry point, legalized by SPIRV-Tools as glslangValidator does). "" or the log.
std::string compile_spirv(Source lang, VkShaderStageFlagBits stage, const std::string& text, const char* entry,
                          std::vector<std::uint32_t>& spirv);
/// Writes the module to `path` and runs `spirv-val --target-env vulkan1.1` on it: "" or why not
/// ("" also when spirv-val is not installed: `validated` says whether it ran).
std::string spirv_val(const std::vector<std::uint32_t>& spirv, const std::string& path, bool& validated);

// ---------------------------------------------------------------------------------------- resources
struct Buffer {
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    void* mapped = nullptr;  ///< host-visible, coherent, mapped for its lifetime
    VkDeviceSize size = 0;
};
bool make_buffer(Context& ctx, VkDeviceSize size, VkBufferUsageFlags usage, Buffer& b);
void destroy(Context& ctx, Buffer& b);

struct Image {
    VkImage image = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;        ///< all layers (2D, 2D_ARRAY when layers > 1 or array_view, or CUBE)
    std::vector<VkImageView> layer_views;     ///< one 2D view per layer (render targets of a layered map)
    VkFormat format = VK_FORMAT_UNDEFINED;
    VkImageAspectFlags aspect = 0;
    std::uint32_t width = 0, height = 0, layers = 1;
};
/// `cube`: six layers, cube-compatible, `view` a cube view (faces +X, -X, +Y, -Y, +Z, -Z in layer_views).
bool make_image(Context& ctx, std::uint32_t w, std::uint32_t h, std::uint32_t layers, VkFormat format,
                VkImageUsageFlags usage, Image& img, bool array_view = false, bool cube = false);
void destroy(Context& ctx, Image& img);

/// A one-time command buffer, begun; submit_and_wait ends, submits, waits for and frees it.
VkCommandBuffer begin_commands(Context& ctx);
bool submit_and_wait(Context& ctx, VkCommandBuffer cmd);

/// A render pass with `colors` (cleared, then TRANSFER_SRC_OPTIMAL) and an optional depth or
/// depth-stencil attachment (VK_FORMAT_UNDEFINED: none; cleared, then `depth_final`).
/// The two subpass dependencies of every render pass the harness makes (earlier shader reads and
/// copies before, later fragment-shader reads and transfers after); a render pass made elsewhere
/// with them stays compatible with the harness's pipelines.
void pass_dependencies(VkSubpassDependency (&dep)[2]);
VkRenderPass make_render_pass(Context& ctx, const std::vector<VkFormat>& colors, VkFormat depth, VkImageLayout depth_final);
VkFramebuffer make_framebuffer(Context& ctx, VkRenderPass rp, const std::vector<VkImageView>& views, std::uint32_t w,
                               std::uint32_t h);

/// A graphics pipeline: triangle lists from one interleaved vertex buffer, dynamic viewport and scissor.
struct PipelineDesc {
    std::vector<std::uint32_t> vs, fs;  ///< fs empty: depth only
    std::vector<std::uint32_t> gs;      ///< optional geometry stage (the geometryShader feature)
    const char* vs_entry = "main";
    const char* gs_entry = "main";
    const char* fs_entry = "main";
    std::uint32_t vertex_stride = 0;
    std::vector<VkVertexInputAttributeDescription> attributes;
    bool depth_test = true, depth_write = true;
    VkCompareOp depth_compare = VK_COMPARE_OP_LESS;
    bool depth_bias = false;
    float bias_constant = 0.f, bias_slope = 0.f;
    bool depth_clamp = false;
    VkCullModeFlags cull = VK_CULL_MODE_NONE;
    VkFrontFace front = VK_FRONT_FACE_COUNTER_CLOCKWISE;
    std::uint32_t color_count = 0;
    bool color_write = true;
    bool blend = false;                            ///< blending on every colour attachment with blend_op (MIN/MAX ignore the factors)
    VkBlendOp blend_op = VK_BLEND_OP_ADD;
    VkBlendFactor blend_src = VK_BLEND_FACTOR_ONE, blend_dst = VK_BLEND_FACTOR_ONE;              ///< rgb
    VkBlendFactor blend_src_alpha = VK_BLEND_FACTOR_ONE, blend_dst_alpha = VK_BLEND_FACTOR_ONE;  ///< a
    bool stencil = false;                          ///< stencil test with the two faces below
    VkStencilOpState stencil_front{}, stencil_back{};
    VkSampleCountFlagBits samples = VK_SAMPLE_COUNT_1_BIT;  ///< rasterization samples (the render pass's)
    bool depth_bounds = false; ///< depthBoundsTestEnable, bounds set with vkCmdSetDepthBounds (dynamic; the depthBounds feature)
};
VkPipeline make_pipeline(Context& ctx, const PipelineDesc& d, VkPipelineLayout layout, VkRenderPass rp, std::string& why);

/// A shader module's worth of descriptors: one set, each binding given by type and stages.
struct Binding {
    std::uint32_t binding;
    VkDescriptorType type;
    VkShaderStageFlags stages;
};
struct DescriptorSet {
    VkDescriptorSetLayout layout = VK_NULL_HANDLE;
    VkDescriptorPool pool = VK_NULL_HANDLE;
    VkDescriptorSet set = VK_NULL_HANDLE;
};
bool make_descriptor_set(Context& ctx, const std::vector<Binding>& bindings, DescriptorSet& ds);
void write_image(Context& ctx, DescriptorSet& ds, std::uint32_t binding, VkDescriptorType type, VkImageView view,
                 VkSampler sampler, VkImageLayout layout);
void write_sampler(Context& ctx, DescriptorSet& ds, std::uint32_t binding, VkSampler sampler);
void write_buffer(Context& ctx, DescriptorSet& ds, std::uint32_t binding, const Buffer& b,
                  VkDescriptorType type = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER);
void destroy(Context& ctx, DescriptorSet& ds);

/// A sampler clamped to the edge; `compare` != VK_COMPARE_OP_NEVER makes it a comparison sampler
/// (GL_TEXTURE_COMPARE_MODE on, with that function).
VkSampler make_sampler(Context& ctx, VkFilter filter, VkCompareOp compare);

/// Image layout transition of all layers (a pipeline barrier recorded into cmd).
void transition(VkCommandBuffer cmd, const Image& img, VkImageLayout from, VkImageLayout to);

/// Copies layer `layer` of a colour or depth image in layout `layout` (TRANSFER_SRC_OPTIMAL for
/// render targets) to floats: `components` floats per texel, row 0 = the image's first row.
std::vector<float> read_image(Context& ctx, const Image& img, VkImageLayout layout, std::uint32_t components,
                              std::uint32_t layer = 0);

/// The stencil aspect of a depth-stencil image (one byte per texel, row 0 first).
std::vector<std::uint8_t> read_stencil(Context& ctx, const Image& img, VkImageLayout layout);

/// Fills every layer of an image made with TRANSFER_DST usage from floats (one per texel for a
/// depth or one-channel format, layers one after the other), leaving it in `final_layout`.
bool upload_image(Context& ctx, const Image& img, const std::vector<float>& data, VkImageLayout final_layout);

/// Viewport helpers: the whole target, y flipped with a negative height (VK_KHR_maintenance1,
/// core in Vulkan 1.1) when `flip_y`.
VkViewport viewport(std::uint32_t w, std::uint32_t h, bool flip_y);

// ---------------------------------------------------------------------------------------- Scope
/// What a test case makes, destroyed when the case's Scope goes out of scope, also when a REQUIRE
/// throws out of the case: everything handed to it, last handed first (a pipeline before its layout
/// and render pass, a framebuffer before its images, a descriptor set before the buffer it reads).
/// Design: the Scope OWNS the harness's structs, so no object can be gone before the Scope's destructor
/// runs whatever the order of declarations: `skvk::Image& map = scope.own<skvk::Image>();` returns a
/// reference (stable until the Scope dies) to a value-initialized object the Scope holds, to be filled by
/// make_image and friends; it is destroyed with the `destroy(Context&, T&)` of its type (found by ADL:
/// Buffer, Image, DescriptorSet, and vk_passes.hpp's RowPass and ReceiverTargets), or, for a
/// std::vector or std::array of them, each element last to first. Raw handles go through keep(), which
/// takes the handle and its vkDestroy* function and returns the handle (VK_NULL_HANDLE is not recorded):
/// `VkPipeline pipe = scope.keep(make_pipeline_checked(ctx, pd, layout, rp), vkDestroyPipeline);`.
/// A case that re-creates things in a loop uses one Scope per iteration. The destructor waits for the
/// device to be idle first (a REQUIRE may throw with work in flight).
class Scope {
public:
    explicit Scope(Context& ctx) : ctx_(&ctx) {}
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;
    ~Scope() {
        if (undo_.empty()) return;
        vkDeviceWaitIdle(ctx_->device);
        for (auto it = undo_.rbegin(); it != undo_.rend(); ++it) (*it)();
    }

    /// `h`, destroyed with `destroy_fn(device, h, nullptr)` (the template does not need Vulkan's handle
    /// types to be distinct C++ types: on 32-bit builds they are all uint64_t).
    template <class H>
    H keep(H h, void(VKAPI_PTR* destroy_fn)(VkDevice, H, const VkAllocationCallbacks*)) {
        if (h != VK_NULL_HANDLE) {
            VkDevice device = ctx_->device;
            undo_.emplace_back([device, h, destroy_fn]() { destroy_fn(device, h, nullptr); });
        }
        return h;
    }

    /// A default object of type T (Buffer, Image, DescriptorSet, RowPass, ReceiverTargets, or a
    /// std::vector / std::array of them, `args` passed to its constructor) that the Scope owns and
    /// destroys.
    template <class T, class... Args>
    T& own(Args&&... args) {
        auto obj = std::make_shared<T>(std::forward<Args>(args)...);
        Context* c = ctx_;
        undo_.emplace_back([c, obj]() { destroy_owned(*c, *obj); });
        return *obj;
    }

private:
    template <class T>
    static void destroy_owned(Context& c, T& obj) {
        destroy(c, obj);
    }
    template <class T>
    static void destroy_owned(Context& c, std::vector<T>& v) {
        for (auto it = v.rbegin(); it != v.rend(); ++it) destroy(c, *it);
    }
    template <class T, std::size_t N>
    static void destroy_owned(Context& c, std::array<T, N>& v) {
        for (auto it = v.rbegin(); it != v.rend(); ++it) destroy(c, *it);
    }

    Context* ctx_;
    std::vector<std::function<void()>> undo_;
};

}  // namespace skvk
