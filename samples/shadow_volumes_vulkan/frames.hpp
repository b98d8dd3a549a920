// samples/shadow_volumes_vulkan/frames.hpp - the plumbing around the technique (vk_shadow_volumes.hpp):
// the Vulkan context, the GL twin's headless light turn, and N frames into an offscreen image read back
// to the CPU (what main.cpp writes as PNG and the test compares with a CPU ray cast).
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "scene.hpp"
#include "vk_harness.hpp"

/// The app shell's headless rule (samples/app/app.cpp): frame k of N turns the light 360 k / N degrees
/// about the vertical axis through the scene's center.
sk::Light turned_light(const sk::Scene& base, int frame, int frames);

/// The Vulkan 1.1 context: the validation layer when it is installed (`validation` says), the extra
/// extensions in ctx (a window's) before the call. "" or why not; `no_device` as skvk::create_context.
std::string make_context(skvk::Context& ctx, bool& no_device);

struct HeadlessFrames {
    std::uint32_t width = 0, height = 0;
    std::vector<std::uint8_t> rgba;      ///< the last frame, row 0 at the top
    std::vector<float> depth;            ///< its depth (reversed-Z, 0 = nothing drawn), row 0 at the top
    std::vector<std::uint8_t> stencil;   ///< its stencil: the count of volumes around each pixel's point
    sk::Scene scene;                     ///< the scene as drawn in the last frame (its light turned)
    glm::mat4 view_proj{1.f};            ///< the last frame's matrix
    glm::vec4 light{0.f};                ///< the last frame's homogeneous light
};

/// N frames of `base` through VkShadowVolumes into an R8G8B8A8 image, each waited for; the last read back.
std::string render_headless(skvk::Context& ctx, const sk::Scene& base, int frames, std::uint32_t width,
                            std::uint32_t height, HeadlessFrames& out);
