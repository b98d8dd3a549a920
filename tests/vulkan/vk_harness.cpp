// The Vulkan harness of the `vulkan` and `hlsl` tests: see vk_harness.hpp.
#include "vk_harness.hpp"

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include <unistd.h>

namespace skvk {

namespace {

std::size_t g_messages = 0;
std::size_t g_expected = 0;  // provoked on purpose by a test that checks the messenger
std::string g_text;

VKAPI_ATTR VkBool32 VKAPI_CALL on_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                          VkDebugUtilsMessageTypeFlagsEXT, const VkDebugUtilsMessengerCallbackDataEXT* data,
                                          void*) {
    if (severity < VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) return VK_FALSE;
    if (++g_messages <= 20) {
        g_text += (severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) ? "error: " : "warning: ";
        g_text += data && data->pMessage ? data->pMessage : "?";
        g_text += '\n';
    }
    return VK_FALSE;
}

bool has_layer(const char* name) {
    std::uint32_t n = 0;
    vkEnumerateInstanceLayerProperties(&n, nullptr);
    std::vector<VkLayerProperties> layers(n);
    vkEnumerateInstanceLayerProperties(&n, layers.data());
    for (const auto& l : layers)
        if (std::strcmp(l.layerName, name) == 0) return true;
    return false;
}

int memory_type(const Context& ctx, std::uint32_t bits, VkMemoryPropertyFlags want) {
    VkPhysicalDeviceMemoryProperties mp;
    vkGetPhysicalDeviceMemoryProperties(ctx.physical, &mp);
    for (std::uint32_t i = 0; i < mp.memoryTypeCount; ++i)
        if ((bits & (1u << i)) && (mp.memoryTypes[i].propertyFlags & want) == want) return static_cast<int>(i);
    return -1;
}

bool pick_device(Context& ctx, std::string& why) {
    std::uint32_t n = 0;
    vkEnumeratePhysicalDevices(ctx.instance, &n, nullptr);
    std::vector<VkPhysicalDevice> devices(n);
    vkEnumeratePhysicalDevices(ctx.instance, &n, devices.data());
    for (VkPhysicalDevice d : devices) {
        VkPhysicalDeviceProperties p;
        vkGetPhysicalDeviceProperties(d, &p);
        if (p.apiVersion < VK_API_VERSION_1_1) continue;
        std::uint32_t qn = 0;
        vkGetPhysicalDeviceQueueFamilyProperties(d, &qn, nullptr);
        std::vector<VkQueueFamilyProperties> q(qn);
        vkGetPhysicalDeviceQueueFamilyProperties(d, &qn, q.data());
        for (std::uint32_t i = 0; i < qn; ++i)
            if (q[i].queueFlags & VK_QUEUE_GRAPHICS_BIT) {
                ctx.physical = d;
                ctx.queue_family = i;
                ctx.device_name = p.deviceName;
                return true;
            }
    }
    why = "no Vulkan 1.1 device with a graphics queue (" + std::to_string(n) +
          " devices; Debian: mesa-vulkan-drivers for lavapipe)";
    return false;
}

}  // namespace

std::size_t message_count() { return g_messages; }
std::size_t unexpected_message_count() { return g_messages - g_expected; }
void expect_messages(std::size_t n) { g_expected += n; }
std::string messages() { return g_text; }

std::string create_context(Context& ctx, bool want_validation, bool& no_device) {
    no_device = true;
    const char* layer = "VK_LAYER_KHRONOS_validation";
    if (want_validation && !has_layer(layer))
        return "VK_LAYER_KHRONOS_validation not found (Debian: vulkan-validationlayers)";
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "shadowkit-tests";
    app.apiVersion = VK_API_VERSION_1_1;
    const char* ext = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
    VkDebugUtilsMessengerCreateInfoEXT mi{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    mi.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    mi.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                     VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    mi.pfnUserCallback = on_message;
    VkInstanceCreateInfo ci{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    ci.pApplicationInfo = &app;
    std::vector<const char*> exts = ctx.instance_extensions;
    if (want_validation) {
        ci.enabledLayerCount = 1;
        ci.ppEnabledLayerNames = &layer;
        exts.push_back(ext);
        ci.pNext = &mi;  // instance creation and destruction are watched too
    }
    ci.enabledExtensionCount = static_cast<std::uint32_t>(exts.size());
    ci.ppEnabledExtensionNames = exts.empty() ? nullptr : exts.data();
    VkResult r = vkCreateInstance(&ci, nullptr, &ctx.instance);
    if (r != VK_SUCCESS) return "vkCreateInstance failed (" + std::to_string(r) + "): no Vulkan driver (Debian: mesa-vulkan-drivers)";
    ctx.validation = want_validation;
    if (want_validation) {
        auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(ctx.instance, "vkCreateDebugUtilsMessengerEXT"));
        if (!create || create(ctx.instance, &mi, nullptr, &ctx.messenger) != VK_SUCCESS) return "no debug-utils messenger";
    }
    std::string why;
    if (!pick_device(ctx, why)) return why;
    no_device = false;
    vkGetPhysicalDeviceFeatures(ctx.physical, &ctx.supported);
    ctx.enabled.depthClamp = ctx.supported.depthClamp;
    ctx.enabled.depthBounds = ctx.supported.depthBounds;
    ctx.enabled.geometryShader = ctx.supported.geometryShader;
    ctx.enabled.fragmentStoresAndAtomics = ctx.supported.fragmentStoresAndAtomics;  // virtual_shadow_map marking
    ctx.enabled.shaderClipDistance = ctx.supported.shaderClipDistance;  // omni_shadow: the dual-paraboloid map pass
    const float priority = 1.f;
    VkDeviceQueueCreateInfo qi{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    qi.queueFamilyIndex = ctx.queue_family;
    qi.queueCount = 1;
    qi.pQueuePriorities = &priority;
    VkDeviceCreateInfo di{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    di.queueCreateInfoCount = 1;
    di.pQueueCreateInfos = &qi;
    di.pEnabledFeatures = &ctx.enabled;
    di.enabledExtensionCount = static_cast<std::uint32_t>(ctx.device_extensions.size());
    di.ppEnabledExtensionNames = ctx.device_extensions.empty() ? nullptr : ctx.device_extensions.data();
    if (vkCreateDevice(ctx.physical, &di, nullptr, &ctx.device) != VK_SUCCESS) return "vkCreateDevice failed";
    vkGetDeviceQueue(ctx.device, ctx.queue_family, 0, &ctx.queue);
    VkCommandPoolCreateInfo pi{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pi.queueFamilyIndex = ctx.queue_family;
    pi.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    if (vkCreateCommandPool(ctx.device, &pi, nullptr, &ctx.pool) != VK_SUCCESS) return "vkCreateCommandPool failed";
    return {};
}

void destroy_context(Context& ctx) {
    if (ctx.device) {
        vkDeviceWaitIdle(ctx.device);
        if (ctx.pool) vkDestroyCommandPool(ctx.device, ctx.pool, nullptr);
        vkDestroyDevice(ctx.device, nullptr);
    }
    if (ctx.messenger) {
        auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(ctx.instance, "vkDestroyDebugUtilsMessengerEXT"));
        if (destroy) destroy(ctx.instance, ctx.messenger, nullptr);
    }
    if (ctx.instance) vkDestroyInstance(ctx.instance, nullptr);
    ctx = Context{};
}

// ---------------------------------------------------------------------------------------- SPIR-V
namespace {
struct GlslangProcess {
    GlslangProcess() { glslang::InitializeProcess(); }
    ~GlslangProcess() { glslang::FinalizeProcess(); }
};
}  // namespace

std::string compile_spirv(Source src, VkShaderStageFlagBits stage, const std::string& text, const char* entry,
                          std::vector<std::uint32_t>& spirv) {
    static const GlslangProcess process;
    EShLanguage lang = EShLangVertex;
    if (stage == VK_SHADER_STAGE_FRAGMENT_BIT) lang = EShLangFragment;
    if (stage == VK_SHADER_STAGE_GEOMETRY_BIT) lang = EShLangGeometry;
    if (stage == VK_SHADER_STAGE_COMPUTE_BIT) lang = EShLangCompute;
    const bool hlsl = src == Source::Hlsl;
    glslang::TShader shader(lang);
    const char* t = text.c_str();
    shader.setStrings(&t, 1);
    shader.setEntryPoint(entry);
    shader.setSourceEntryPoint(entry);
    shader.setEnvInput(hlsl ? glslang::EShSourceHlsl : glslang::EShSourceGlsl, lang, glslang::EShClientVulkan, 100);
    shader.setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_1);
    shader.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_3);
    int flags = EShMsgSpvRules | EShMsgVulkanRules;
    if (hlsl) flags |= EShMsgReadHlsl;
    const auto messages = static_cast<EShMessages>(flags);
    if (!shader.parse(GetDefaultResources(), hlsl ? 100 : 450, ECoreProfile, false, false, messages))
        return std::string("compile: ") + shader.getInfoLog();
    glslang::TProgram program;
    program.addShader(&shader);
    if (!program.link(messages)) return std::string("link: ") + program.getInfoLog();
    if (!program.mapIO()) return std::string("mapIO: ") + program.getInfoLog();
    glslang::SpvOptions opt;
    // HLSL: SPIRV-Tools' legalization, as glslangValidator runs it (textures passed as arguments;
    // with glslang 12 the unlegalized modules validated and ran the same)
    opt.disableOptimizer = !hlsl;
    spv::SpvBuildLogger logger;
    spirv.clear();
    glslang::GlslangToSpv(*program.getIntermediate(lang), spirv, &logger, &opt);
    if (spirv.empty()) return "no SPIR-V: " + logger.getAllMessages();
    return {};
}

std::string spirv_val(const std::vector<std::uint32_t>& spirv, const std::string& path, bool& validated) {
    validated = false;
    // CTest runs the GLSL and HLSL variants of one test at once and both write the scene's shared
    // stages under one name: each process writes and checks its own file, then renames it into place
    // (rename is atomic), so no process ever reads another's half-written binary.
    const std::string own = path + "." + std::to_string(static_cast<long>(getpid())) + ".tmp";
    std::ofstream(own, std::ios::binary)
        .write(reinterpret_cast<const char*>(spirv.data()), static_cast<std::streamsize>(spirv.size() * 4));
    std::string result;
    if (std::system("spirv-val --version > /dev/null 2>&1") == 0) {
        validated = true;
        const std::string cmd = "spirv-val --target-env vulkan1.1 '" + own + "'";
        if (std::system(cmd.c_str()) != 0) result = "spirv-val rejects " + path;
    }
    std::rename(own.c_str(), path.c_str());
    return result;
}

// ---------------------------------------------------------------------------------------- resources
bool make_buffer(Context& ctx, VkDeviceSize size, VkBufferUsageFlags usage, Buffer& b) {
    VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    bi.size = size;
    bi.usage = usage;
    if (vkCreateBuffer(ctx.device, &bi, nullptr, &b.buffer) != VK_SUCCESS) return false;
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(ctx.device, b.buffer, &req);
    const int type = memory_type(ctx, req.memoryTypeBits, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    if (type < 0) return false;
    VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    ai.allocationSize = req.size;
    ai.memoryTypeIndex = static_cast<std::uint32_t>(type);
    if (vkAllocateMemory(ctx.device, &ai, nullptr, &b.memory) != VK_SUCCESS) return false;
    vkBindBufferMemory(ctx.device, b.buffer, b.memory, 0);
    b.size = size;
    return vkMapMemory(ctx.device, b.memory, 0, size, 0, &b.mapped) == VK_SUCCESS;
}

void destroy(Context& ctx, Buffer& b) {
    if (b.buffer) vkDestroyBuffer(ctx.device, b.buffer, nullptr);
    if (b.memory) vkFreeMemory(ctx.device, b.memory, nullptr);
    b = Buffer{};
}

namespace {
VkImageAspectFlags aspect_of(VkFormat f) {
    switch (f) {
    case VK_FORMAT_D16_UNORM:
    case VK_FORMAT_D32_SFLOAT:
    case VK_FORMAT_X8_D24_UNORM_PACK32: return VK_IMAGE_ASPECT_DEPTH_BIT;
    case VK_FORMAT_D24_UNORM_S8_UINT:
    case VK_FORMAT_D32_SFLOAT_S8_UINT: return VK_IMAGE_ASPECT_DEPTH_BIT | VK_IMAGE_ASPECT_STENCIL_BIT;
    default: return VK_IMAGE_ASPECT_COLOR_BIT;
    }
}

VkImageView make_view(Context& ctx, const Image& img, VkImageViewType type, std::uint32_t base, std::uint32_t count) {
    VkImageViewCreateInfo vi{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    vi.image = img.image;
    vi.viewType = type;
    vi.format = img.format;
    // a sampled depth-stencil view reads depth only; render targets take both aspects
    vi.subresourceRange = {img.aspect, 0, 1, base, count};
    VkImageView v = VK_NULL_HANDLE;
    vkCreateImageView(ctx.device, &vi, nullptr, &v);
    return v;
}
}  // namespace

bool make_image(Context& ctx, std::uint32_t w, std::uint32_t h, std::uint32_t layers, VkFormat format,
                VkImageUsageFlags usage, Image& img, bool array_view, bool cube) {
    VkImageCreateInfo ii{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    if (cube) ii.flags = VK_IMAGE_CREATE_CUBE_COMPATIBLE_BIT;
    ii.imageType = VK_IMAGE_TYPE_2D;
    ii.format = format;
    ii.extent = {w, h, 1};
    ii.mipLevels = 1;
    ii.arrayLayers = layers;
    ii.samples = VK_SAMPLE_COUNT_1_BIT;
    ii.tiling = VK_IMAGE_TILING_OPTIMAL;
    ii.usage = usage;
    ii.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    if (vkCreateImage(ctx.device, &ii, nullptr, &img.image) != VK_SUCCESS) return false;
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(ctx.device, img.image, &req);
    const int type = memory_type(ctx, req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    if (type < 0) return false;
    VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    ai.allocationSize = req.size;
    ai.memoryTypeIndex = static_cast<std::uint32_t>(type);
    if (vkAllocateMemory(ctx.device, &ai, nullptr, &img.memory) != VK_SUCCESS) return false;
    vkBindImageMemory(ctx.device, img.image, img.memory, 0);
    img.format = format;
    img.aspect = aspect_of(format);
    img.width = w;
    img.height = h;
    img.layers = layers;
    const bool arr = layers > 1 || array_view;
    img.view = make_view(ctx, img, cube ? VK_IMAGE_VIEW_TYPE_CUBE : arr ? VK_IMAGE_VIEW_TYPE_2D_ARRAY : VK_IMAGE_VIEW_TYPE_2D,
                         0, layers);
    if (arr)
        for (std::uint32_t l = 0; l < layers; ++l) img.layer_views.push_back(make_view(ctx, img, VK_IMAGE_VIEW_TYPE_2D, l, 1));
    return img.view != VK_NULL_HANDLE;
}

void destroy(Context& ctx, Image& img) {
    for (VkImageView v : img.layer_views) vkDestroyImageView(ctx.device, v, nullptr);
    if (img.view) vkDestroyImageView(ctx.device, img.view, nullptr);
    if (img.image) vkDestroyImage(ctx.device, img.image, nullptr);
    if (img.memory) vkFreeMemory(ctx.device, img.memory, nullptr);
    img = Image{};
}

VkCommandBuffer begin_commands(Context& ctx) {
    VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.commandPool = ctx.pool;
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 1;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    vkAllocateCommandBuffers(ctx.device, &ai, &cmd);
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    vkBeginCommandBuffer(cmd, &bi);
    return cmd;
}

bool submit_and_wait(Context& ctx, VkCommandBuffer cmd) {
    vkEndCommandBuffer(cmd);
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cmd;
    const bool ok = vkQueueSubmit(ctx.queue, 1, &si, VK_NULL_HANDLE) == VK_SUCCESS && vkQueueWaitIdle(ctx.queue) == VK_SUCCESS;
    vkFreeCommandBuffers(ctx.device, ctx.pool, 1, &cmd);
    return ok;
}

void pass_dependencies(VkSubpassDependency (&dep)[2]) {
    // before: earlier passes' shader reads and copies of these images; after: this pass's writes are
    // visible to later fragment shaders (a shadow map) and transfers (readback)
    const VkPipelineStageFlags attach = VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT |
                                        VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    const VkAccessFlags writes = VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    dep[0] = VkSubpassDependency{};
    dep[0].srcSubpass = VK_SUBPASS_EXTERNAL;
    dep[0].dstSubpass = 0;
    dep[0].srcStageMask = VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
    dep[0].dstStageMask = attach;
    dep[0].srcAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT;
    dep[0].dstAccessMask = writes | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT;
    dep[1] = VkSubpassDependency{};
    dep[1].srcSubpass = 0;
    dep[1].dstSubpass = VK_SUBPASS_EXTERNAL;
    dep[1].srcStageMask = attach;
    dep[1].dstStageMask = VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
    dep[1].srcAccessMask = writes;
    dep[1].dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT;
}

VkRenderPass make_render_pass(Context& ctx, const std::vector<VkFormat>& colors, VkFormat depth, VkImageLayout depth_final) {
    std::vector<VkAttachmentDescription> att;
    std::vector<VkAttachmentReference> refs;
    for (VkFormat f : colors) {
        VkAttachmentDescription a{};
        a.format = f;
        a.samples = VK_SAMPLE_COUNT_1_BIT;
        a.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
        a.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
        a.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
        a.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
        a.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
        a.finalLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
        refs.push_back({static_cast<std::uint32_t>(att.size()), VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL});
        att.push_back(a);
    }
    VkAttachmentReference dref{static_cast<std::uint32_t>(att.size()), VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
    if (depth != VK_FORMAT_UNDEFINED) {
        VkAttachmentDescription a{};
        a.format = depth;
        a.samples = VK_SAMPLE_COUNT_1_BIT;
        a.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
        a.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
        const bool stencil = aspect_of(depth) & VK_IMAGE_ASPECT_STENCIL_BIT;
        a.stencilLoadOp = stencil ? VK_ATTACHMENT_LOAD_OP_CLEAR : VK_ATTACHMENT_LOAD_OP_DONT_CARE;
        a.stencilStoreOp = stencil ? VK_ATTACHMENT_STORE_OP_STORE : VK_ATTACHMENT_STORE_OP_DONT_CARE;
        a.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
        a.finalLayout = depth_final;
        att.push_back(a);
    }
    VkSubpassDescription sp{};
    sp.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    sp.colorAttachmentCount = static_cast<std::uint32_t>(refs.size());
    sp.pColorAttachments = refs.data();
    sp.pDepthStencilAttachment = depth != VK_FORMAT_UNDEFINED ? &dref : nullptr;
    VkSubpassDependency dep[2];
    pass_dependencies(dep);
    VkRenderPassCreateInfo ri{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
    ri.attachmentCount = static_cast<std::uint32_t>(att.size());
    ri.pAttachments = att.data();
    ri.subpassCount = 1;
    ri.pSubpasses = &sp;
    ri.dependencyCount = 2;
    ri.pDependencies = dep;
    VkRenderPass rp = VK_NULL_HANDLE;
    vkCreateRenderPass(ctx.device, &ri, nullptr, &rp);
    return rp;
}

VkFramebuffer make_framebuffer(Context& ctx, VkRenderPass rp, const std::vector<VkImageView>& views, std::uint32_t w,
                               std::uint32_t h) {
    VkFramebufferCreateInfo fi{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
    fi.renderPass = rp;
    fi.attachmentCount = static_cast<std::uint32_t>(views.size());
    fi.pAttachments = views.data();
    fi.width = w;
    fi.height = h;
    fi.layers = 1;
    VkFramebuffer fb = VK_NULL_HANDLE;
    vkCreateFramebuffer(ctx.device, &fi, nullptr, &fb);
    return fb;
}

namespace {
VkShaderModule make_module(Context& ctx, const std::vector<std::uint32_t>& code) {
    VkShaderModuleCreateInfo mi{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    mi.codeSize = code.size() * 4;
    mi.pCode = code.data();
    VkShaderModule m = VK_NULL_HANDLE;
    vkCreateShaderModule(ctx.device, &mi, nullptr, &m);
    return m;
}
}  // namespace

VkPipeline make_pipeline(Context& ctx, const PipelineDesc& d, VkPipelineLayout layout, VkRenderPass rp, std::string& why) {
    VkPipelineShaderStageCreateInfo stages[3]{};
    std::uint32_t nstages = 0;
    VkShaderModule vs = make_module(ctx, d.vs), gs = VK_NULL_HANDLE, fs = VK_NULL_HANDLE;
    stages[nstages++] = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0, VK_SHADER_STAGE_VERTEX_BIT, vs, d.vs_entry, nullptr};
    if (!d.gs.empty()) {
        gs = make_module(ctx, d.gs);
        stages[nstages++] = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0, VK_SHADER_STAGE_GEOMETRY_BIT, gs, d.gs_entry, nullptr};
    }
    if (!d.fs.empty()) {
        fs = make_module(ctx, d.fs);
        stages[nstages++] = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0, VK_SHADER_STAGE_FRAGMENT_BIT, fs, d.fs_entry, nullptr};
    }
    VkVertexInputBindingDescription vb{0, d.vertex_stride, VK_VERTEX_INPUT_RATE_VERTEX};
    VkPipelineVertexInputStateCreateInfo vi{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    vi.vertexBindingDescriptionCount = d.attributes.empty() ? 0u : 1u;  // none: positions from gl_VertexIndex
    vi.pVertexBindingDescriptions = &vb;
    vi.vertexAttributeDescriptionCount = static_cast<std::uint32_t>(d.attributes.size());
    vi.pVertexAttributeDescriptions = d.attributes.data();
    VkPipelineInputAssemblyStateCreateInfo ia{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
    ia.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
    VkPipelineViewportStateCreateInfo vp{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
    vp.viewportCount = 1;
    vp.scissorCount = 1;
    VkPipelineRasterizationStateCreateInfo rs{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    rs.depthClampEnable = d.depth_clamp ? VK_TRUE : VK_FALSE;
    rs.polygonMode = VK_POLYGON_MODE_FILL;
    rs.cullMode = d.cull;
    rs.frontFace = d.front;
    rs.depthBiasEnable = d.depth_bias ? VK_TRUE : VK_FALSE;
    rs.depthBiasConstantFactor = d.bias_constant;
    rs.depthBiasSlopeFactor = d.bias_slope;
    rs.lineWidth = 1.f;
    VkPipelineMultisampleStateCreateInfo ms{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
    ms.rasterizationSamples = d.samples;
    VkPipelineDepthStencilStateCreateInfo ds{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
    ds.depthTestEnable = d.depth_test ? VK_TRUE : VK_FALSE;
    ds.depthWriteEnable = d.depth_write ? VK_TRUE : VK_FALSE;
    ds.depthCompareOp = d.depth_compare;
    ds.stencilTestEnable = d.stencil ? VK_TRUE : VK_FALSE;
    ds.front = d.stencil_front;
    ds.back = d.stencil_back;
    ds.maxDepthBounds = 1.f;
    ds.depthBoundsTestEnable = d.depth_bounds ? VK_TRUE : VK_FALSE;
    std::vector<VkPipelineColorBlendAttachmentState> blend(d.color_count);
    for (auto& b : blend) {
        b.blendEnable = d.blend ? VK_TRUE : VK_FALSE;
        b.colorBlendOp = b.alphaBlendOp = d.blend_op;
        b.srcColorBlendFactor = d.blend_src;
        b.dstColorBlendFactor = d.blend_dst;
        b.srcAlphaBlendFactor = d.blend_src_alpha;
        b.dstAlphaBlendFactor = d.blend_dst_alpha;
        b.colorWriteMask = d.color_write ? (VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT |
                                            VK_COLOR_COMPONENT_A_BIT)
                                         : 0u;
    }
    VkPipelineColorBlendStateCreateInfo cb{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
    cb.attachmentCount = d.color_count;
    cb.pAttachments = blend.data();
    const VkDynamicState dyn[3] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR, VK_DYNAMIC_STATE_DEPTH_BOUNDS};
    VkPipelineDynamicStateCreateInfo dy{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
    dy.dynamicStateCount = d.depth_bounds ? 3u : 2u;
    dy.pDynamicStates = dyn;
    VkGraphicsPipelineCreateInfo pi{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
    pi.stageCount = nstages;
    pi.pStages = stages;
    pi.pVertexInputState = &vi;
    pi.pInputAssemblyState = &ia;
    pi.pViewportState = &vp;
    pi.pRasterizationState = &rs;
    pi.pMultisampleState = &ms;
    pi.pDepthStencilState = &ds;
    pi.pColorBlendState = &cb;
    pi.pDynamicState = &dy;
    pi.layout = layout;
    pi.renderPass = rp;
    VkPipeline p = VK_NULL_HANDLE;
    const VkResult r = vkCreateGraphicsPipelines(ctx.device, VK_NULL_HANDLE, 1, &pi, nullptr, &p);
    if (r != VK_SUCCESS) why = "vkCreateGraphicsPipelines failed (" + std::to_string(r) + ")";
    vkDestroyShaderModule(ctx.device, vs, nullptr);
    if (fs) vkDestroyShaderModule(ctx.device, fs, nullptr);
    if (gs) vkDestroyShaderModule(ctx.device, gs, nullptr);
    return p;
}

bool make_descriptor_set(Context& ctx, const std::vector<Binding>& bindings, DescriptorSet& ds) {
    std::vector<VkDescriptorSetLayoutBinding> lb;
    std::vector<VkDescriptorPoolSize> sizes;
    for (const Binding& b : bindings) {
        lb.push_back({b.binding, b.type, 1, b.stages, nullptr});
        sizes.push_back({b.type, 1});
    }
    VkDescriptorSetLayoutCreateInfo li{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    li.bindingCount = static_cast<std::uint32_t>(lb.size());
    li.pBindings = lb.data();
    if (vkCreateDescriptorSetLayout(ctx.device, &li, nullptr, &ds.layout) != VK_SUCCESS) return false;
    VkDescriptorPoolCreateInfo pi{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    pi.maxSets = 1;
    pi.poolSizeCount = static_cast<std::uint32_t>(sizes.size());
    pi.pPoolSizes = sizes.data();
    if (vkCreateDescriptorPool(ctx.device, &pi, nullptr, &ds.pool) != VK_SUCCESS) return false;
    VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    ai.descriptorPool = ds.pool;
    ai.descriptorSetCount = 1;
    ai.pSetLayouts = &ds.layout;
    return vkAllocateDescriptorSets(ctx.device, &ai, &ds.set) == VK_SUCCESS;
}

void write_image(Context& ctx, DescriptorSet& ds, std::uint32_t binding, VkDescriptorType type, VkImageView view,
                 VkSampler sampler, VkImageLayout layout) {
    VkDescriptorImageInfo ii{sampler, view, layout};
    VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    w.dstSet = ds.set;
    w.dstBinding = binding;
    w.descriptorCount = 1;
    w.descriptorType = type;
    w.pImageInfo = &ii;
    vkUpdateDescriptorSets(ctx.device, 1, &w, 0, nullptr);
}

void write_sampler(Context& ctx, DescriptorSet& ds, std::uint32_t binding, VkSampler sampler) {
    write_image(ctx, ds, binding, VK_DESCRIPTOR_TYPE_SAMPLER, VK_NULL_HANDLE, sampler, VK_IMAGE_LAYOUT_UNDEFINED);
}

void write_buffer(Context& ctx, DescriptorSet& ds, std::uint32_t binding, const Buffer& b, VkDescriptorType type) {
    VkDescriptorBufferInfo bi{b.buffer, 0, b.size};
    VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    w.dstSet = ds.set;
    w.dstBinding = binding;
    w.descriptorCount = 1;
    w.descriptorType = type;
    w.pBufferInfo = &bi;
    vkUpdateDescriptorSets(ctx.device, 1, &w, 0, nullptr);
}

void destroy(Context& ctx, DescriptorSet& ds) {
    if (ds.pool) vkDestroyDescriptorPool(ctx.device, ds.pool, nullptr);
    if (ds.layout) vkDestroyDescriptorSetLayout(ctx.device, ds.layout, nullptr);
    ds = DescriptorSet{};
}

VkSampler make_sampler(Context& ctx, VkFilter filter, VkCompareOp compare) {
    VkSamplerCreateInfo si{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    si.magFilter = filter;
    si.minFilter = filter;
    si.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
    si.addressModeU = si.addressModeV = si.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    si.compareEnable = compare != VK_COMPARE_OP_NEVER ? VK_TRUE : VK_FALSE;
    si.compareOp = compare;
    si.maxLod = 0.f;
    si.borderColor = VK_BORDER_COLOR_FLOAT_OPAQUE_WHITE;
    VkSampler s = VK_NULL_HANDLE;
    vkCreateSampler(ctx.device, &si, nullptr, &s);
    return s;
}

void transition(VkCommandBuffer cmd, const Image& img, VkImageLayout from, VkImageLayout to) {
    VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
    b.srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT;
    b.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
    b.oldLayout = from;
    b.newLayout = to;
    b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = img.image;
    b.subresourceRange = {img.aspect, 0, 1, 0, img.layers};
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 0, nullptr, 0, nullptr,
                         1, &b);
}

std::vector<float> read_image(Context& ctx, const Image& img, VkImageLayout layout, std::uint32_t components,
                              std::uint32_t layer) {
    const std::size_t n = std::size_t(img.width) * img.height * components;
    Buffer b;
    std::vector<float> out;
    if (!make_buffer(ctx, n * sizeof(float), VK_BUFFER_USAGE_TRANSFER_DST_BIT, b)) return out;
    VkCommandBuffer cmd = begin_commands(ctx);
    if (layout != VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL) transition(cmd, img, layout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    VkBufferImageCopy c{};
    const VkImageAspectFlags aspect = (img.aspect & VK_IMAGE_ASPECT_DEPTH_BIT) ? VkImageAspectFlags(VK_IMAGE_ASPECT_DEPTH_BIT) : img.aspect;
    c.imageSubresource = {aspect, 0, layer, 1};
    c.imageExtent = {img.width, img.height, 1};
    vkCmdCopyImageToBuffer(cmd, img.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, b.buffer, 1, &c);
    if (layout != VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL) transition(cmd, img, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, layout);
    if (submit_and_wait(ctx, cmd)) {
        out.resize(n);
        std::memcpy(out.data(), b.mapped, n * sizeof(float));
    }
    destroy(ctx, b);
    return out;
}

std::vector<std::uint8_t> read_stencil(Context& ctx, const Image& img, VkImageLayout layout) {
    const std::size_t n = std::size_t(img.width) * img.height;
    Buffer b;
    std::vector<std::uint8_t> out;
    if (!(img.aspect & VK_IMAGE_ASPECT_STENCIL_BIT) || !make_buffer(ctx, n, VK_BUFFER_USAGE_TRANSFER_DST_BIT, b)) return out;
    VkCommandBuffer cmd = begin_commands(ctx);
    if (layout != VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL) transition(cmd, img, layout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    VkBufferImageCopy c{};
    c.imageSubresource = {VK_IMAGE_ASPECT_STENCIL_BIT, 0, 0, 1};
    c.imageExtent = {img.width, img.height, 1};
    vkCmdCopyImageToBuffer(cmd, img.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, b.buffer, 1, &c);
    if (layout != VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL) transition(cmd, img, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, layout);
    if (submit_and_wait(ctx, cmd)) {
        out.resize(n);
        std::memcpy(out.data(), b.mapped, n);
    }
    destroy(ctx, b);
    return out;
}

bool upload_image(Context& ctx, const Image& img, const std::vector<float>& data, VkImageLayout final_layout) {
    const std::size_t n = std::size_t(img.width) * img.height * img.layers;
    if (data.size() % n != 0 || data.empty()) return false;
    Buffer b;
    if (!make_buffer(ctx, data.size() * sizeof(float), VK_BUFFER_USAGE_TRANSFER_SRC_BIT, b)) return false;
    std::memcpy(b.mapped, data.data(), data.size() * sizeof(float));
    VkCommandBuffer cmd = begin_commands(ctx);
    transition(cmd, img, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    VkBufferImageCopy c{};
    const VkImageAspectFlags aspect = (img.aspect & VK_IMAGE_ASPECT_DEPTH_BIT) ? VkImageAspectFlags(VK_IMAGE_ASPECT_DEPTH_BIT) : img.aspect;
    c.imageSubresource = {aspect, 0, 0, img.layers};
    c.imageExtent = {img.width, img.height, 1};
    vkCmdCopyBufferToImage(cmd, b.buffer, img.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &c);
    transition(cmd, img, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, final_layout);
    const bool ok = submit_and_wait(ctx, cmd);
    destroy(ctx, b);
    return ok;
}

VkViewport viewport(std::uint32_t w, std::uint32_t h, bool flip_y) {
    const float fw = static_cast<float>(w), fh = static_cast<float>(h);
    return flip_y ? VkViewport{0.f, fh, fw, -fh, 0.f, 1.f} : VkViewport{0.f, 0.f, fw, fh, 0.f, 1.f};
}

}  // namespace skvk
