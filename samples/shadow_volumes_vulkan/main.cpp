// Sample: stenciled shadow volumes on Vulkan, the twin of samples/shadow_volumes (GL). The technique,
// its descriptor set, render pass and pipelines are vk_shadow_volumes.hpp/.cpp; this file is the frame
// loop: headless into an offscreen image (written as PNG) or windowed on a GLFW swapchain.
//   sample_shadow_volumes_vulkan [--api vulkan] [--scene NAME] [--headless [OUT.png]] [--out OUT.png]
//                                [--window] [--frames N] [--size WxH] [--help]
// Headless: N frames (default 1), the light turning 360/N degrees a frame as in the GL sample, the last
// one written; exit 77 without a Vulkan device (1 with SHADOWKIT_REQUIRE_GL set), 1 on any
// validation-layer warning or error. Windowed: until closed (the light turning a degree a frame), or N
// frames with --frames (the light turning as headless); with --window, --out saves the last presented
// swapchain image (the test compares it with the headless picture).
#include <vulkan/vulkan.h>
#if SHADOWKIT_VK_SAMPLE_GLFW
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>  // after vulkan.h: declares glfwCreateWindowSurface
#endif
#include <stb_image_write.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <utility>
#include <string>
#include <vector>

#include "frames.hpp"
#include "vk_shadow_volumes.hpp"

namespace {

struct Options {
    std::string scene = "stack", out;
    bool headless = false, window = false;  // window: --out saves the last presented image instead
    int frames = 0;
    std::uint32_t width = 640, height = 480;
};

int usage(const char* msg) {
    std::string scenes;
    for (const std::string& n : sk::builtin_scene_names()) scenes += (scenes.empty() ? "" : ", ") + n;
    std::fprintf(stderr, "%s\nusage: sample_shadow_volumes_vulkan [--api vulkan] [--scene NAME] [--headless [OUT.png]] "
                         "[--out OUT.png] [--window] [--frames N] [--size WxH]\nscenes: %s\n", msg, scenes.c_str());
    return 2;
}

int no_device_exit(const std::string& why) {
    const char* req = std::getenv("SHADOWKIT_REQUIRE_GL");
    const bool required = req && *req && std::strcmp(req, "0") != 0;
    std::fprintf(stderr, "no Vulkan device: %s\n", why.c_str());
    return required ? 1 : 77;
}

int validation_exit(int rc) {
    const std::size_t n = skvk::message_count();
    std::printf("validation-layer warnings and errors: %zu\n", n);
    if (n) std::printf("%s", skvk::messages().c_str());
    return n ? 1 : rc;
}

int run_headless(const Options& o, const sk::Scene& scene) {
    skvk::Context ctx;
    bool no_device = false;
    const std::string why = make_context(ctx, no_device);
    if (!why.empty()) {
        skvk::destroy_context(ctx);
        return no_device ? no_device_exit(why) : (std::fprintf(stderr, "%s\n", why.c_str()), 1);
    }
    HeadlessFrames f;
    const std::string err = render_headless(ctx, scene, o.frames, o.width, o.height, f);
    const std::string device = ctx.device_name;
    const bool validation = ctx.validation;
    skvk::destroy_context(ctx);
    if (!err.empty()) return std::fprintf(stderr, "%s\n", err.c_str()), 1;
    if (!stbi_write_png(o.out.c_str(), int(o.width), int(o.height), 4, f.rgba.data(), int(o.width) * 4))
        return std::fprintf(stderr, "cannot write %s\n", o.out.c_str()), 1;
    std::printf("shadow volumes (Vulkan, %s%s) on %s, %d frames -> %s\n", device.c_str(),
                validation ? ", validation layer on" : "", scene.name.c_str(), o.frames, o.out.c_str());
    return validation_exit(0);
}

#if SHADOWKIT_VK_SAMPLE_GLFW
// The window: a GLFW surface (VK_KHR_surface + the platform's, from glfwGetRequiredInstanceExtensions),
// a FIFO swapchain, one framebuffer per swapchain image, one frame in flight.
struct Swapchain {
    VkSwapchainKHR chain = VK_NULL_HANDLE;
    VkFormat format = VK_FORMAT_UNDEFINED;
    VkExtent2D extent{};
    std::vector<VkImage> images;
    std::vector<VkImageView> views;
    std::vector<VkFramebuffer> framebuffers;
    std::vector<VkSemaphore> rendered;  // one per image: presentation waits on it
};

std::string make_swapchain(skvk::Context& ctx, VkSurfaceKHR surface, std::uint32_t w, std::uint32_t h, Swapchain& sc) {
    VkBool32 present = VK_FALSE;
    vkGetPhysicalDeviceSurfaceSupportKHR(ctx.physical, ctx.queue_family, surface, &present);
    if (!present) return "the graphics queue cannot present to this window";
    VkSurfaceCapabilitiesKHR caps;
    vkGetPhysicalDeviceSurfaceCapabilitiesKHR(ctx.physical, surface, &caps);
    std::uint32_t n = 0;
    vkGetPhysicalDeviceSurfaceFormatsKHR(ctx.physical, surface, &n, nullptr);
    std::vector<VkSurfaceFormatKHR> formats(n);
    vkGetPhysicalDeviceSurfaceFormatsKHR(ctx.physical, surface, &n, formats.data());
    if (formats.empty()) return "no surface format";
    VkSurfaceFormatKHR fmt = formats[0];
    for (const VkSurfaceFormatKHR& f : formats)
        if (f.format == VK_FORMAT_B8G8R8A8_UNORM) fmt = f;  // the headless picture's values, unconverted
    sc.format = fmt.format;
    sc.extent = caps.currentExtent.width != 0xFFFFFFFFu ? caps.currentExtent : VkExtent2D{w, h};
    VkSwapchainCreateInfoKHR ci{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
    ci.surface = surface;
    ci.minImageCount = caps.maxImageCount ? std::min(caps.minImageCount + 1, caps.maxImageCount) : caps.minImageCount + 1;
    ci.imageFormat = fmt.format;
    ci.imageColorSpace = fmt.colorSpace;
    ci.imageExtent = sc.extent;
    ci.imageArrayLayers = 1;
    ci.imageUsage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | (caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
    ci.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
    ci.preTransform = caps.currentTransform;
    ci.compositeAlpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
    ci.presentMode = VK_PRESENT_MODE_FIFO_KHR;  // always there
    ci.clipped = VK_TRUE;
    if (vkCreateSwapchainKHR(ctx.device, &ci, nullptr, &sc.chain) != VK_SUCCESS) return "vkCreateSwapchainKHR failed";
    vkGetSwapchainImagesKHR(ctx.device, sc.chain, &n, nullptr);
    sc.images.resize(n);
    vkGetSwapchainImagesKHR(ctx.device, sc.chain, &n, sc.images.data());
    for (VkImage img : sc.images) {
        VkImageViewCreateInfo vi{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
        vi.image = img;
        vi.viewType = VK_IMAGE_VIEW_TYPE_2D;
        vi.format = sc.format;
        vi.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        VkImageView v = VK_NULL_HANDLE;
        vkCreateImageView(ctx.device, &vi, nullptr, &v);
        sc.views.push_back(v);
        VkSemaphoreCreateInfo si{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        VkSemaphore s = VK_NULL_HANDLE;
        vkCreateSemaphore(ctx.device, &si, nullptr, &s);
        sc.rendered.push_back(s);
    }
    return {};
}

void destroy_swapchain(skvk::Context& ctx, Swapchain& sc) {
    for (VkFramebuffer f : sc.framebuffers) vkDestroyFramebuffer(ctx.device, f, nullptr);
    for (VkImageView v : sc.views) vkDestroyImageView(ctx.device, v, nullptr);
    for (VkSemaphore s : sc.rendered) vkDestroySemaphore(ctx.device, s, nullptr);
    if (sc.chain) vkDestroySwapchainKHR(ctx.device, sc.chain, nullptr);
    sc = Swapchain{};
}

// The last presented image (PRESENT_SRC_KHR) copied out, BGRA swizzled to RGBA, written as PNG.
std::string save_swapchain_image(skvk::Context& ctx, const Swapchain& sc, std::uint32_t image, const std::string& path) {
    const std::uint32_t w = sc.extent.width, h = sc.extent.height;
    skvk::Buffer b;
    if (!skvk::make_buffer(ctx, VkDeviceSize(w) * h * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT, b)) return "readback buffer";
    skvk::Image img;  // the harness's transition() on the swapchain's image
    img.image = sc.images[image];
    img.aspect = VK_IMAGE_ASPECT_COLOR_BIT;
    VkCommandBuffer cmd = skvk::begin_commands(ctx);
    skvk::transition(cmd, img, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    VkBufferImageCopy c{};
    c.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    c.imageExtent = {w, h, 1};
    vkCmdCopyImageToBuffer(cmd, img.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, b.buffer, 1, &c);
    skvk::transition(cmd, img, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR);
    std::string why = skvk::submit_and_wait(ctx, cmd) ? "" : "readback submit failed";
    std::vector<std::uint8_t> px(static_cast<const std::uint8_t*>(b.mapped), static_cast<const std::uint8_t*>(b.mapped) + std::size_t(w) * h * 4);
    skvk::destroy(ctx, b);
    if (sc.format == VK_FORMAT_B8G8R8A8_UNORM || sc.format == VK_FORMAT_B8G8R8A8_SRGB)
        for (std::size_t k = 0; k < px.size(); k += 4) std::swap(px[k], px[k + 2]);
    if (why.empty() && !stbi_write_png(path.c_str(), int(w), int(h), 4, px.data(), int(w) * 4)) why = "cannot write " + path;
    return why;
}

// Every frame: wait for the last one (the technique's buffers are mapped), update, acquire, record,
// submit (waiting for the image at the colour-output stage), present.
std::string window_loop(skvk::Context& ctx, GLFWwindow* win, VkSurfaceKHR surface, const Options& o, sk::Scene& scene) {
    Swapchain sc;
    std::string why = make_swapchain(ctx, surface, o.width, o.height, sc);
    VkShadowVolumes sv;
    if (why.empty() && !sv.init(ctx, scene, sc.extent.width, sc.extent.height, sc.format, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, why))
        why = why.empty() ? "init failed" : why;
    for (VkImageView v : sc.views)
        if (why.empty()) sc.framebuffers.push_back(sv.make_framebuffer(v));
    VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.commandPool = ctx.pool;
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 1;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    vkAllocateCommandBuffers(ctx.device, &ai, &cmd);
    VkSemaphoreCreateInfo si{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    VkSemaphore acquired = VK_NULL_HANDLE;
    vkCreateSemaphore(ctx.device, &si, nullptr, &acquired);
    VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    fi.flags = VK_FENCE_CREATE_SIGNALED_BIT;
    VkFence done = VK_NULL_HANDLE;
    vkCreateFence(ctx.device, &fi, nullptr, &done);
    const sk::Scene base = scene;
    std::uint32_t last = 0;
    for (int frame = 0; why.empty() && !glfwWindowShouldClose(win) && (o.frames == 0 || frame < o.frames); ++frame) {
        glfwPollEvents();
        vkWaitForFences(ctx.device, 1, &done, VK_TRUE, UINT64_MAX);
        scene.light = o.frames ? turned_light(base, frame, o.frames) : turned_light(base, frame % 360, 360);
        why = sv.update(scene);
        if (!why.empty()) break;
        std::uint32_t image = 0;
        const VkResult got = vkAcquireNextImageKHR(ctx.device, sc.chain, UINT64_MAX, acquired, VK_NULL_HANDLE, &image);
        if (got != VK_SUCCESS && got != VK_SUBOPTIMAL_KHR) {  // suboptimal: still presentable
            why = "vkAcquireNextImageKHR failed (window resized? the sample keeps its first size)";
            break;
        }
        vkResetFences(ctx.device, 1, &done);
        vkResetCommandBuffer(cmd, 0);
        VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
        vkBeginCommandBuffer(cmd, &bi);
        sv.record(cmd, sc.framebuffers[image]);
        vkEndCommandBuffer(cmd);
        const VkPipelineStageFlags wait_stage = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
        VkSubmitInfo s{VK_STRUCTURE_TYPE_SUBMIT_INFO};
        s.waitSemaphoreCount = 1;
        s.pWaitSemaphores = &acquired;
        s.pWaitDstStageMask = &wait_stage;
        s.commandBufferCount = 1;
        s.pCommandBuffers = &cmd;
        s.signalSemaphoreCount = 1;
        s.pSignalSemaphores = &sc.rendered[image];
        if (vkQueueSubmit(ctx.queue, 1, &s, done) != VK_SUCCESS) why = "vkQueueSubmit failed";
        VkPresentInfoKHR pi{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
        pi.waitSemaphoreCount = 1;
        pi.pWaitSemaphores = &sc.rendered[image];
        pi.swapchainCount = 1;
        pi.pSwapchains = &sc.chain;
        pi.pImageIndices = &image;
        const VkResult shown = why.empty() ? vkQueuePresentKHR(ctx.queue, &pi) : VK_SUCCESS;
        if (shown != VK_SUCCESS && shown != VK_SUBOPTIMAL_KHR) why = "vkQueuePresentKHR failed";
        last = image;
    }
    vkDeviceWaitIdle(ctx.device);
    if (why.empty() && !o.out.empty()) why = save_swapchain_image(ctx, sc, last, o.out);
    vkDestroyFence(ctx.device, done, nullptr);
    vkDestroySemaphore(ctx.device, acquired, nullptr);
    vkFreeCommandBuffers(ctx.device, ctx.pool, 1, &cmd);
    sv.release();
    destroy_swapchain(ctx, sc);
    return why;
}

int run_window(const Options& o, sk::Scene& scene) {
    if (!glfwInit()) return std::fprintf(stderr, "glfwInit failed (no display? use --headless or xvfb-run)\n"), 1;
    if (!glfwVulkanSupported()) {
        glfwTerminate();
        return no_device_exit("GLFW finds no Vulkan loader");
    }
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);  // Vulkan draws: no GL context
    glfwWindowHint(GLFW_RESIZABLE, GLFW_FALSE);
    GLFWwindow* win = glfwCreateWindow(int(o.width), int(o.height), "shadow volumes (Vulkan)", nullptr, nullptr);
    skvk::Context ctx;
    std::uint32_t n = 0;
    const char** ext = glfwGetRequiredInstanceExtensions(&n);
    ctx.instance_extensions.assign(ext, ext + n);
    ctx.device_extensions = {VK_KHR_SWAPCHAIN_EXTENSION_NAME};
    bool no_device = false;
    std::string why = win ? make_context(ctx, no_device) : "glfwCreateWindow failed";
    VkSurfaceKHR surface = VK_NULL_HANDLE;
    if (why.empty() && glfwCreateWindowSurface(ctx.instance, win, nullptr, &surface) != VK_SUCCESS)
        why = "glfwCreateWindowSurface failed";
    if (why.empty()) why = window_loop(ctx, win, surface, o, scene);
    if (surface) vkDestroySurfaceKHR(ctx.instance, surface, nullptr);
    const bool validation = ctx.validation;
    skvk::destroy_context(ctx);
    if (win) glfwDestroyWindow(win);
    glfwTerminate();
    if (!why.empty()) return no_device ? no_device_exit(why) : (std::fprintf(stderr, "%s\n", why.c_str()), 1);
    std::printf("shadow volumes (Vulkan, window%s) on %s\n", validation ? ", validation layer on" : "", scene.name.c_str());
    return validation_exit(0);
}
#endif

}  // namespace

int main(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const bool has_value = i + 1 < argc && argv[i + 1][0] != '-';
        if (a == "--help") {
            usage("shadow volumes on Vulkan (the GL twin: sample_shadow_volumes)");
            return 0;
        } else if (a == "--api") {
            if (!has_value || std::string(argv[++i]) != "vulkan") return usage("--api: this sample is the Vulkan one (vulkan)");
        } else if (a == "--scene" && has_value) {
            o.scene = argv[++i];
        } else if (a == "--headless") {
            o.headless = true;
            if (has_value) o.out = argv[++i];
        } else if (a == "--out" && has_value) {
            o.out = argv[++i];
        } else if (a == "--window") {
            o.window = true;
        } else if (a == "--frames" && has_value && std::atoi(argv[i + 1]) > 0) {
            o.frames = std::atoi(argv[++i]);
        } else if (a == "--size" && has_value &&
                   std::sscanf(argv[i + 1], "%ux%u", &o.width, &o.height) == 2 && o.width && o.height) {
            ++i;
        } else {
            return usage(("bad option '" + a + "'").c_str());
        }
    }
    sk::Scene scene;
    if (!sk::make_builtin_scene(o.scene, scene)) return usage(("unknown scene '" + o.scene + "'").c_str());
    if (!o.out.empty() && !o.window) o.headless = true;
    if (o.headless) {
        if (o.out.empty()) o.out = "shot.png";
        if (o.frames == 0) o.frames = 1;
        return run_headless(o, scene);
    }
#if SHADOWKIT_VK_SAMPLE_GLFW
    return run_window(o, scene);
#else
    return usage("built without GLFW: use --headless");
#endif
}
