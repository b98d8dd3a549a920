// samples/shadow_volumes_vulkan/frames.cpp - see frames.hpp.
#include "frames.hpp"

#include <cmath>

#include "vk_shadow_volumes.hpp"

sk::Light turned_light(const sk::Scene& base, int frame, int frames) {
    const glm::vec3 center = 0.5f * (base.bounds_min() + base.bounds_max());
    const float ang = 6.2831853f * float(frame) / float(frames);
    const float c = std::cos(ang), s = std::sin(ang);
    auto turn = [&](glm::vec3 v) { return glm::vec3(c * v.x + s * v.z, v.y, -s * v.x + c * v.z); };
    sk::Light L = base.light;
    if (frame > 0) {
        L.position = center + turn(base.light.position - center);
        L.direction = turn(base.light.direction);
    }
    return L;
}

std::string make_context(skvk::Context& ctx, bool& no_device) {
    std::string why = skvk::create_context(ctx, true, no_device);
    if (why.empty()) return why;
    skvk::destroy_context(ctx);  // no validation layer installed: run without it
    const std::vector<const char*> ie = ctx.instance_extensions, de = ctx.device_extensions;
    ctx = skvk::Context{};
    ctx.instance_extensions = ie;
    ctx.device_extensions = de;
    const std::string again = skvk::create_context(ctx, false, no_device);
    return again.empty() ? again : why + "; without the validation layer: " + again;
}

std::string render_headless(skvk::Context& ctx, const sk::Scene& base, int frames, std::uint32_t width,
                            std::uint32_t height, HeadlessFrames& out) {
    std::string why;
    skvk::Image color;
    if (!skvk::make_image(ctx, width, height, 1, VK_FORMAT_R8G8B8A8_UNORM,
                          VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, color))
        return "colour image";
    VkShadowVolumes sv;
    out.scene = base;
    if (!sv.init(ctx, out.scene, width, height, color.format, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, why)) {
        skvk::destroy(ctx, color);
        return why;
    }
    VkFramebuffer fb = sv.make_framebuffer(color.view);
    for (int f = 0; f < frames && why.empty(); ++f) {
        out.scene.light = turned_light(base, f, frames);
        why = sv.update(out.scene);
        if (!why.empty()) break;
        VkCommandBuffer cmd = skvk::begin_commands(ctx);
        sv.record(cmd, fb);
        if (!skvk::submit_and_wait(ctx, cmd)) why = "queue submit failed";
    }
    if (why.empty()) {
        out.width = width;
        out.height = height;
        out.view_proj = sv.view_proj();
        out.light = sv.light();
        // R8G8B8A8 read as bytes: the harness's reader gives floats, so copy through a staging buffer
        skvk::Buffer b;
        const std::size_t n = std::size_t(width) * height * 4;
        if (skvk::make_buffer(ctx, n, VK_BUFFER_USAGE_TRANSFER_DST_BIT, b)) {
            VkCommandBuffer cmd = skvk::begin_commands(ctx);
            VkBufferImageCopy c{};
            c.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
            c.imageExtent = {width, height, 1};
            vkCmdCopyImageToBuffer(cmd, color.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, b.buffer, 1, &c);
            if (skvk::submit_and_wait(ctx, cmd)) {
                const auto* p = static_cast<const std::uint8_t*>(b.mapped);
                out.rgba.assign(p, p + n);
            }
            skvk::destroy(ctx, b);
        }
        out.depth = skvk::read_image(ctx, sv.depth_stencil(), VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL, 1);
        out.stencil = skvk::read_stencil(ctx, sv.depth_stencil(), VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL);
        if (out.rgba.size() != n || out.depth.size() != n / 4 || out.stencil.size() != n / 4) why = "readback failed";
    }
    vkDestroyFramebuffer(ctx.device, fb, nullptr);
    sv.release();
    skvk::destroy(ctx, color);
    return why;
}
