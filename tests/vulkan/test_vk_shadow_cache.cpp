// glsl/shadow_cache.glsl and hlsl/shadow_cache.hlsl RUN on Vulkan: the translation-invariant caster
// pass (vertex: global texel space; geometry: sk_shadow_cache_plane and sk_shadow_cache_position in a
// guard viewport (-G, -G, V, V); fragment: sk_shadow_cache_depth as the depth) renders the e2e scene
// into a 256 x 256 VK_FORMAT_D32_SFLOAT map at anchor A and again at A + (5, 3) texels: the overlap
// must be bit-identical (what a scrolled cache needs, as the GL test checks), more than a quarter of the
// texels covered. Control: the same overlap compared one texel off is not identical. No validation
// message.
#include <doctest/doctest.h>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "vk_harness.hpp"
#include "vk_passes.hpp"
#include "vk_scene.hpp"

namespace {

using skvk::Source;

const char* kVsGlsl = R"(#version 450 core
layout(push_constant) uniform Pass { mat4 light_global; ivec2 anchor; ivec2 viewport_anchor; vec2 viewport_size; } pc;
layout(location = 0) in vec3 a_position;
layout(location = 0) out vec3 v_global;
void main() {
    v_global = (pc.light_global * vec4(a_position, 1.0)).xyz;
    gl_Position = vec4(0.0, 0.0, 0.0, 1.0);
}
)";
const char* kGsGlsl = R"(
layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;
layout(push_constant) uniform Pass { mat4 light_global; ivec2 anchor; ivec2 viewport_anchor; vec2 viewport_size; } pc;
layout(location = 0) in vec3 v_global[];
layout(location = 0) flat out vec3 g_plane;
layout(location = 1) flat out vec2 g_origin;
void main() {
    vec3 plane;
    vec2 origin;
    if (!sk_shadow_cache_plane(v_global[0], v_global[1], v_global[2], plane, origin)) return;
    for (int i = 0; i < 3; ++i) {
        g_plane = plane;
        g_origin = origin;
        gl_Position = sk_shadow_cache_position(v_global[i].xy, pc.viewport_anchor, pc.viewport_size);
        EmitVertex();
    }
    EndPrimitive();
}
)";
const char* kFsGlsl = R"(
layout(push_constant) uniform Pass { mat4 light_global; ivec2 anchor; ivec2 viewport_anchor; vec2 viewport_size; } pc;
layout(location = 0) flat in vec3 g_plane;
layout(location = 1) flat in vec2 g_origin;
void main() { gl_FragDepth = sk_shadow_cache_depth(g_plane, g_origin, gl_FragCoord.xy, pc.anchor); }
)";
const char* kPassHlsl = R"(
struct Pass { column_major float4x4 light_global; int2 anchor; int2 viewport_anchor; float2 viewport_size; };
[[vk::push_constant]] ConstantBuffer<Pass> pc;
struct VsOut {
    float4 position : SV_Position;
    [[vk::location(0)]] float3 global : TEXCOORD0;
};
VsOut vs_main([[vk::location(0)]] float3 position : POSITION) {
    VsOut o;
    o.global = mul(pc.light_global, float4(position, 1.0)).xyz;
    o.position = float4(0.0, 0.0, 0.0, 1.0);
    return o;
}
struct GsOut {
    float4 position : SV_Position;
    [[vk::location(0)]] nointerpolation float3 plane : TEXCOORD0;
    [[vk::location(1)]] nointerpolation float2 origin : TEXCOORD1;
};
[maxvertexcount(3)]
void gs_main(triangle VsOut v[3], inout TriangleStream<GsOut> stream) {
    float3 plane;
    float2 origin;
    if (!sk_shadow_cache_plane(v[0].global, v[1].global, v[2].global, plane, origin)) return;
    for (int i = 0; i < 3; ++i) {
        GsOut o;
        o.plane = plane;
        o.origin = origin;
        o.position = sk_shadow_cache_position(v[i].global.xy, pc.viewport_anchor, pc.viewport_size);
        stream.Append(o);
    }
    stream.RestartStrip();
}
float ps_main(GsOut i) : SV_Depth { return sk_shadow_cache_depth(i.plane, i.origin, i.position.xy, pc.anchor); }
)";

constexpr std::uint32_t kMap = 256, kViewport = 512;
constexpr int kGuard = int(kViewport - kMap) / 2;

struct PassConstants {
    glm::mat4 light_global;
    glm::ivec2 anchor, viewport_anchor;
    glm::vec2 viewport_size;
};

// world -> (global texel x, global texel y, window depth in [0, 1]) of an orthographic light toward
// (0.5, 1, 0.3): texels of 1/32 world unit, depth over 12 units along the light.
glm::mat4 light_global() {
    const glm::vec3 L = glm::normalize(glm::vec3(0.5f, 1.f, 0.3f));
    const glm::mat4 view = glm::lookAt(6.f * L, glm::vec3(0.f), glm::vec3(0.f, 0.f, -1.f));
    glm::mat4 s(1.f);
    s[0][0] = 32.f;
    s[1][1] = 32.f;
    s[2][2] = -1.f / 12.f;  // depth = -z_view / 12, the eye 6 units before the origin
    return s * view;
}

std::vector<float> render(Source lang, glm::ivec2 anchor) {
    skvk::Context& ctx = skvk::vk_test_context();
    skvk::Scope scope(ctx);
    const skvk::BoxScene scene;
    std::vector<std::uint32_t> vs, gs, fs;
    const char* entries[3] = {"main", "main", "main"};
    if (lang == Source::Glsl) {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_GLSL_DIR) + "/shadow_cache.glsl");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, kVsGlsl, "main", "shadow_cache.glsl.vert");
        gs = skvk::compile_checked(lang, VK_SHADER_STAGE_GEOMETRY_BIT, "#version 450 core\n" + snippet + kGsGlsl, "main",
                                   "shadow_cache.glsl.geom");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, "#version 450 core\n" + snippet + kFsGlsl, "main",
                                   "shadow_cache.glsl.frag");
    } else {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_HLSL_DIR) + "/shadow_cache.hlsl");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, snippet + kPassHlsl, "vs_main", "shadow_cache.hlsl.vert");
        gs = skvk::compile_checked(lang, VK_SHADER_STAGE_GEOMETRY_BIT, snippet + kPassHlsl, "gs_main", "shadow_cache.hlsl.geom");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, snippet + kPassHlsl, "ps_main", "shadow_cache.hlsl.frag");
        entries[0] = "vs_main";
        entries[1] = "gs_main";
        entries[2] = "ps_main";
    }
    skvk::Buffer& vb = scope.own<skvk::Buffer>();
    const auto vcount = static_cast<std::uint32_t>(scene.vertices.size());
    REQUIRE(skvk::make_buffer(ctx, sizeof(skvk::SceneVertex) * vcount, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, vb));
    std::memcpy(vb.mapped, scene.vertices.data(), sizeof(skvk::SceneVertex) * vcount);
    skvk::Image& map = scope.own<skvk::Image>();
    REQUIRE(skvk::make_image(ctx, kMap, kMap, 1, VK_FORMAT_D32_SFLOAT,
                             VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, map));
    VkRenderPass rp = scope.keep(skvk::make_render_pass(ctx, {}, VK_FORMAT_D32_SFLOAT, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL), vkDestroyRenderPass);
    VkFramebuffer fb = scope.keep(skvk::make_framebuffer(ctx, rp, {map.view}, kMap, kMap), vkDestroyFramebuffer);
    const VkShaderStageFlags stages = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_GEOMETRY_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
    VkPipelineLayout layout = scope.keep(skvk::make_pipeline_layout(ctx, nullptr, sizeof(PassConstants), stages), vkDestroyPipelineLayout);
    skvk::PipelineDesc pd = skvk::scene_pipeline(vs, fs, entries[0], entries[2], false);
    pd.gs = gs;
    pd.gs_entry = entries[1];
    VkPipeline pipe = scope.keep(skvk::make_pipeline_checked(ctx, pd, layout, rp), vkDestroyPipeline);

    const PassConstants pc{light_global(), anchor, anchor - glm::ivec2(kGuard), glm::vec2(float(kViewport))};
    VkCommandBuffer cmd = skvk::begin_commands(ctx);
    VkClearValue far{};
    far.depthStencil = {1.f, 0};
    VkRenderPassBeginInfo bi{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    bi.renderPass = rp;
    bi.framebuffer = fb;
    bi.renderArea = {{0, 0}, {kMap, kMap}};
    bi.clearValueCount = 1;
    bi.pClearValues = &far;
    vkCmdBeginRenderPass(cmd, &bi, VK_SUBPASS_CONTENTS_INLINE);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipe);
    // the guard viewport: the map's texel (0, 0) at the viewport's texel (G, G); the scissor is the map
    const VkViewport vp{float(-kGuard), float(-kGuard), float(kViewport), float(kViewport), 0.f, 1.f};
    const VkRect2D sc{{0, 0}, {kMap, kMap}};
    vkCmdSetViewport(cmd, 0, 1, &vp);
    vkCmdSetScissor(cmd, 0, 1, &sc);
    vkCmdPushConstants(cmd, layout, stages, 0, sizeof pc, &pc);
    const VkDeviceSize offset = 0;
    vkCmdBindVertexBuffers(cmd, 0, 1, &vb.buffer, &offset);
    vkCmdDraw(cmd, vcount, 1, 0, 0);
    vkCmdEndRenderPass(cmd);
    REQUIRE(skvk::submit_and_wait(ctx, cmd));
    std::vector<float> depth = skvk::read_image(ctx, map, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 1);

    return depth;
}

// Texels of the overlap where map b (anchor + shift) differs bitwise from map a read `shift` + `off` on.
std::size_t differing(const std::vector<float>& a, const std::vector<float>& b, glm::ivec2 shift, glm::ivec2 off,
                      std::size_t& compared) {
    std::size_t n = 0;
    compared = 0;
    const int m = int(kMap);
    for (int j = 0; j + shift.y + off.y < m; ++j)
        for (int i = 0; i + shift.x + off.x < m; ++i) {
            const float va = a[std::size_t((j + shift.y + off.y) * m + i + shift.x + off.x)];
            const float vb = b[std::size_t(j * m + i)];
            ++compared;
            n += std::memcmp(&va, &vb, sizeof va) != 0;
        }
    return n;
}

void check(Source lang) {
    skvk::Context& ctx = skvk::vk_test_context();
    REQUIRE_MESSAGE(ctx.enabled.geometryShader, "the device has no geometryShader");
    const std::size_t before = skvk::message_count();
    const glm::ivec2 anchor(-128, -120), shift(5, 3);
    const std::vector<float> a = render(lang, anchor), b = render(lang, anchor + shift);
    REQUIRE(a.size() == std::size_t(kMap) * kMap);
    std::size_t covered = 0;
    for (float d : a) covered += d < 1.f;
    std::size_t compared = 0, control_compared = 0;
    const std::size_t diff = differing(a, b, shift, glm::ivec2(0), compared);
    const std::size_t control = differing(a, b, shift, glm::ivec2(1, 0), control_compared);
    MESSAGE((lang == Source::Glsl ? "GLSL" : "HLSL") << ": covered " << covered << " of " << a.size() << "; scrolled by (5, 3): "
                                                    << diff << " of " << compared << " overlap texels differ; one texel off: "
                                                    << control << " differ");
    CHECK(covered > a.size() / 4);
    CHECK(diff == 0);
    CHECK(control > compared / 100);
    CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());
}

}  // namespace

TEST_CASE("shadow_cache.glsl on Vulkan: the invariant pass gives bit-identical maps under a whole-texel scroll") {
    check(Source::Glsl);
}

TEST_CASE("HLSL shadow_cache.hlsl on Vulkan: the invariant pass gives bit-identical maps under a whole-texel scroll") {
    check(Source::Hlsl);
}
