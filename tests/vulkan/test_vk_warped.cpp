// glsl/perspective_shadow_maps.glsl and hlsl/perspective_shadow_maps.hlsl RUN on Vulkan: LiSPSM and
// TSM matrices from shadowkit/perspective_shadow_maps.hpp (ClipDepth::ZeroToOne, standard and
// reversed-Z, a directional light) for the e2e scene; the map pass draws with the warp (LiSPSM:
// slope-scaled depth bias; TSM with separate depth: the fragment stage writes sk_warp_map_depth), the
// camera pass (negative-height viewport) calls sk_warp_shadow; every receiver pixel is compared with
// the CPU ray cast toward the light (>= 99.5% away from shadow edges, the e2e test's tolerance), with
// no validation message.
#include <doctest/doctest.h>

#include <shadowkit/perspective_shadow_maps.hpp>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <cstring>
#include <string>
#include <vector>

#include "vk_harness.hpp"
#include "vk_passes.hpp"
#include "vk_scene.hpp"

namespace {

using skvk::Source;

// The map pass: position through the warp; depth_clip for TSM's separate depth.
const char* kDepthVsGlsl = R"(#version 450 core
layout(push_constant) uniform DepthParams { mat4 warp; mat4 depth_proj; } pc;
layout(location = 0) in vec3 a_position;
layout(location = 0) out vec4 v_depth_clip;
void main() {
    v_depth_clip = pc.depth_proj * vec4(a_position, 1.0);
    gl_Position = pc.warp * vec4(a_position, 1.0);
}
)";
const char* kDepthFsGlsl = R"(
layout(location = 0) in vec4 v_depth_clip;
void main() {
    gl_FragDepth = sk_warp_map_depth(v_depth_clip, SK_TEST_SLOPE, 0.0, true);  // 2 (reversed-Z: -2); 0: true depths
}
)";
const char* kDepthHlsl = R"(
struct DepthParams { column_major float4x4 warp; column_major float4x4 depth_proj; };
[[vk::push_constant]] ConstantBuffer<DepthParams> pc;
struct DepthVaryings {
    float4 position : SV_Position;
    [[vk::location(0)]] float4 depth_clip : TEXCOORD0;
};
DepthVaryings vs_depth([[vk::location(0)]] float3 position : POSITION) {
    DepthVaryings o;
    o.depth_clip = mul(pc.depth_proj, float4(position, 1.0));
    o.position = mul(pc.warp, float4(position, 1.0));
    return o;
}
float ps_depth(DepthVaryings i) : SV_Depth {
    return sk_warp_map_depth(i.depth_clip, SK_TEST_SLOPE, 0.0, true);  // 2 (reversed-Z: -2); 0: true depths
}
)";

const char* kParamsGlsl = R"(
layout(set = 0, binding = 1, std140) uniform Params { mat4 view_proj; mat4 warp; mat4 depth_proj; mat4 warp_inverse; } u;
)";
const char* kReceiverGlslFs = R"(
layout(set = 0, binding = 0) uniform sampler2DShadow u_map;
void main() {
#ifdef SK_TEST_AUTO
    o_visibility = sk_warp_shadow_auto(u_map, u.warp, u.warp_inverse, u.depth_proj, v_world, v_normal, true, 0.0, 1.0);
#else
    o_visibility = sk_warp_shadow(u_map, u.warp, u.depth_proj, v_world, 0.0, true);
#endif
    o_world = vec4(v_world, 1.0);
    o_normal = vec4(normalize(v_normal), 0.0);
}
)";
const char* kReceiverHlsl = R"(
struct Params {
    column_major float4x4 view_proj; column_major float4x4 warp; column_major float4x4 depth_proj;
    column_major float4x4 warp_inverse;
};
[[vk::binding(0, 0)]] Texture2D<float> u_map;
[[vk::binding(1, 0)]] ConstantBuffer<Params> u;
[[vk::binding(2, 0)]] SamplerComparisonState u_compare;
)";
const char* kReceiverHlslPs = R"(
Targets ps_main(Varyings i) {
    Targets o;
#ifdef SK_TEST_AUTO
    o.visibility = sk_warp_shadow_auto(u_map, u_compare, u.warp, u.warp_inverse, u.depth_proj, i.world, i.normal, true, 0.0, 1.0);
#else
    o.visibility = sk_warp_shadow(u_map, u_compare, u.warp, u.depth_proj, i.world, 0.0, true);
#endif
    o.world = float4(i.world, 1.0);
    o.normal = float4(normalize(i.normal), 0.0);
    return o;
}
)";

constexpr std::uint32_t kMap = 1024, kW = 320, kH = 240;

struct Params {
    glm::mat4 view_proj, warp, depth_proj, warp_inverse;
};

// Plain: the map with the slope-scaled bias (TSM: sk_warp_map_depth's slope 2), sk_warp_shadow, LINEAR;
// Auto: the map's true depths (slope 0), sk_warp_shadow_auto, NEAREST (as the GL check in
// tests/docs/gl_warp.cpp); NoBias: the true depths and sk_warp_shadow with bias 0 (the control: acne).
enum class Mode { Plain, Auto, NoBias };
struct DepthPush {
    glm::mat4 warp, depth_proj;
};

struct Shaders {
    std::vector<std::uint32_t> depth_vs, depth_fs, vs, fs;
    const char* entries[4] = {"main", "main", "main", "main"};
};

Shaders shaders(Source lang, bool reversed, bool write_depth, Mode mode) {
    const std::string define = std::string(reversed ? "#define SK_REVERSED_Z 1\n" : "") + "#define SK_TEST_SLOPE " +
                               (mode != Mode::Plain ? "0.0" : reversed ? "-2.0" : "2.0") + "\n";
    const std::string lookup = mode == Mode::Auto ? "#define SK_TEST_AUTO 1\n" : "";
    Shaders s;
    if (lang == Source::Glsl) {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_GLSL_DIR) + "/perspective_shadow_maps.glsl");
        s.depth_vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, kDepthVsGlsl, "main", "warped.glsl.depth.vert");
        if (write_depth)
            s.depth_fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, "#version 450 core\n" + define + snippet + kDepthFsGlsl,
                                               "main", "warped.glsl.depth.frag");
        s.vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, skvk::receiver_glsl_vs(kParamsGlsl), "main", "warped.glsl.vert");
        s.fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT,
                                     "#version 450 core\n" + lookup + snippet + kParamsGlsl + skvk::kReceiverGlslFsIo + kReceiverGlslFs,
                                     "main", "warped.glsl.frag");
        return s;
    }
    const std::string snippet = skvk::read_text(std::string(SHADOWKIT_HLSL_DIR) + "/perspective_shadow_maps.hlsl");
    s.depth_vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, define + snippet + kDepthHlsl, "vs_depth", "warped.hlsl.depth.vert");
    if (write_depth)
        s.depth_fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, define + snippet + kDepthHlsl, "ps_depth",
                                           "warped.hlsl.depth.frag");
    const std::string receiver = kReceiverHlsl + std::string(skvk::kReceiverHlslVs) + skvk::kReceiverHlslTargets + kReceiverHlslPs;
    s.vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, snippet + receiver, "vs_main", "warped.hlsl.vert");
    s.fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, lookup + snippet + receiver, "ps_main", "warped.hlsl.frag");
    s.entries[0] = "vs_depth";
    s.entries[1] = "ps_depth";
    s.entries[2] = "vs_main";
    s.entries[3] = "ps_main";
    return s;
}

struct Result {
    skvk::Agreement agreement;
    bool separate_depth = false;
    float warp_strength = 0.f;
};

Result run(Source lang, shadowkit::WarpMethod method, bool reversed, Mode mode = Mode::Plain) {
    skvk::Context& ctx = skvk::vk_test_context();
    skvk::Scope scope(ctx);
    const skvk::BoxScene scene;
    const glm::vec4 light(0.5f, 1.f, 0.3f, 0.f);
    const glm::mat4 view = glm::lookAt(glm::vec3(0.4f, 1.3f, 2.2f), glm::vec3(0.f, 0.f, -1.f), glm::vec3(0.f, 1.f, 0.f));
    glm::mat4 proj = glm::perspectiveRH_ZO(0.9f, float(kW) / float(kH), 0.1f, 50.f);
    if (reversed) proj = skvk::reverse_z() * proj;
    shadowkit::WarpInput in;
    in.camera_view = view;
    in.camera_proj = proj;
    in.camera_depth = shadowkit::ClipDepth::ZeroToOne;
    in.camera_reversed_z = reversed;
    in.max_distance = 8.f;
    in.light_position = light;
    in.has_scene_bounds = true;
    in.scene_min = glm::vec3(-scene.ground_half, 0.f, -scene.ground_half);
    in.scene_max = glm::vec3(scene.ground_half, scene.box_c.y + scene.box_h.y, scene.ground_half);
    in.light_depth = shadowkit::ClipDepth::ZeroToOne;
    in.light_reversed_z = reversed;
    const shadowkit::WarpResult w =
        method == shadowkit::WarpMethod::Tsm ? shadowkit::warp_tsm_matrix(in) : shadowkit::warp_lispsm_matrix(in);
    REQUIRE_MESSAGE(w.status == shadowkit::Status::Ok, shadowkit::status_name(w.status));
    REQUIRE(w.visible);
    const glm::mat4 warp_inverse(glm::inverse(glm::dmat4(w.light_view_proj)));  // in double, as the snippet asks
    const Params params{proj * view, w.light_view_proj, w.depth_view_proj, warp_inverse};
    const DepthPush push{w.light_view_proj, w.depth_view_proj};
    const Shaders sh = shaders(lang, reversed, w.separate_depth, mode);

    skvk::Buffer& vb = scope.own<skvk::Buffer>();
    skvk::Buffer& ubo = scope.own<skvk::Buffer>();
    const auto vcount = static_cast<std::uint32_t>(scene.vertices.size());
    REQUIRE(skvk::make_buffer(ctx, sizeof(skvk::SceneVertex) * vcount, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, vb));
    std::memcpy(vb.mapped, scene.vertices.data(), sizeof(skvk::SceneVertex) * vcount);
    REQUIRE(skvk::make_buffer(ctx, sizeof(Params), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, ubo));
    std::memcpy(ubo.mapped, &params, sizeof params);

    skvk::Image& map = scope.own<skvk::Image>();
    REQUIRE(skvk::make_image(ctx, kMap, kMap, 1, VK_FORMAT_D32_SFLOAT,
                             VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT, map));
    const VkImageLayout map_read = VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL;
    VkRenderPass map_rp = scope.keep(skvk::make_render_pass(ctx, {}, VK_FORMAT_D32_SFLOAT, map_read), vkDestroyRenderPass);
    VkFramebuffer map_fb = scope.keep(skvk::make_framebuffer(ctx, map_rp, {map.view}, kMap, kMap), vkDestroyFramebuffer);
    VkPipelineLayout map_layout = scope.keep(skvk::make_pipeline_layout(ctx, nullptr, sizeof(DepthPush)), vkDestroyPipelineLayout);
    // TSM with separate depth: the fragment stage writes the depth (and its bias)
    skvk::PipelineDesc md = skvk::scene_pipeline(sh.depth_vs, sh.depth_fs, sh.entries[0], sh.entries[1], false);
    md.depth_compare = reversed ? VK_COMPARE_OP_GREATER : VK_COMPARE_OP_LESS;
    md.depth_bias = !w.separate_depth;  // rasterized depth: the GL test's glPolygonOffset(1.5, 2)
    md.bias_slope = reversed ? -1.5f : 1.5f;
    md.bias_constant = reversed ? -2.f : 2.f;
    VkPipeline map_pipe = scope.keep(skvk::make_pipeline_checked(ctx, md, map_layout, map_rp), vkDestroyPipeline);

    skvk::ReceiverTargets& rt = scope.own<skvk::ReceiverTargets>();
    skvk::make_receiver_targets(ctx, kW, kH, rt);
    VkSampler sampler = scope.keep(skvk::make_sampler(ctx, mode == Mode::Plain ? VK_FILTER_LINEAR : VK_FILTER_NEAREST,
                                           reversed ? VK_COMPARE_OP_GREATER_OR_EQUAL : VK_COMPARE_OP_LESS_OR_EQUAL), vkDestroySampler);
    skvk::DescriptorSet& ds = scope.own<skvk::DescriptorSet>();
    skvk::make_lookup_set(ctx, lang, map.view, map_read, sampler, ubo, ds);
    VkPipelineLayout layout = scope.keep(skvk::make_pipeline_layout(ctx, &ds), vkDestroyPipelineLayout);
    skvk::PipelineDesc pd = skvk::scene_pipeline(sh.vs, sh.fs, sh.entries[2], sh.entries[3]);
    pd.depth_compare = reversed ? VK_COMPARE_OP_GREATER : VK_COMPARE_OP_LESS;
    pd.color_count = 3;
    pd.cull = VK_CULL_MODE_BACK_BIT;
    VkPipeline pipe = scope.keep(skvk::make_pipeline_checked(ctx, pd, layout, rt.rp), vkDestroyPipeline);

    VkCommandBuffer cmd = skvk::begin_commands(ctx);
    VkClearValue far{};
    far.depthStencil = {reversed ? 0.f : 1.f, 0};
    skvk::draw_pass(cmd, map_rp, map_fb, kMap, kMap, {far}, map_pipe, map_layout, nullptr, &push, vb.buffer, vcount, false,
                    sizeof push);
    VkClearValue zero{};
    skvk::draw_pass(cmd, rt.rp, rt.fb, kW, kH, {zero, zero, zero, far}, pipe, layout, &ds.set, nullptr, vb.buffer, vcount, true);
    REQUIRE(skvk::submit_and_wait(ctx, cmd));

    Result out;
    out.agreement = skvk::receiver_agreement(ctx, rt, scene, light);
    out.separate_depth = w.separate_depth;
    out.warp_strength = w.warp_strength;

    return out;
}

void check(Source lang) {
    for (shadowkit::WarpMethod m : {shadowkit::WarpMethod::Lispsm, shadowkit::WarpMethod::Tsm})
        for (bool reversed : {false, true}) {
            const std::size_t before = skvk::message_count();
            const Result r = run(lang, m, reversed);
            const skvk::Agreement& a = r.agreement;
            const std::string name = std::string(lang == Source::Glsl ? "GLSL " : "HLSL ") +
                                     (m == shadowkit::WarpMethod::Tsm ? "TSM" : "LiSPSM") +
                                     (reversed ? ", reversed-Z" : ", standard depth");
            INFO(name);
            MESSAGE(name << " (warp strength " << r.warp_strength << std::string(r.separate_depth ? ", separate depth" : "")
                         << "): compared " << a.compared << " (lit " << a.lit << ", shadowed " << a.shadowed << "), agreement "
                         << a.fraction());
            CHECK(r.warp_strength > 0.1f);  // the warp is really on
            if (m == shadowkit::WarpMethod::Tsm) CHECK(r.separate_depth);  // sk_warp_map_depth writes the depth
            CHECK(a.compared > int(kW * kH) / 4);
            CHECK(a.shadowed > a.compared / 50);
            CHECK(a.fraction() >= 0.995);
            CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());
        }
}


// sk_warp_shadow_auto on TSM's separate depth (true depths, no offset), the GL check's bounds
// (tests/docs/gl_warp.cpp): >= 99.5% agree, at most 0.2% of the lit pixels dark; the same true depths
// read without a bias acne (the control). Standard depth only: sk_warp_shadow_auto has no reversed-Z path.
void check_auto(Source lang) {
    const std::size_t before = skvk::message_count();
    const Result a = run(lang, shadowkit::WarpMethod::Tsm, false, Mode::Auto);
    const Result none = run(lang, shadowkit::WarpMethod::Tsm, false, Mode::NoBias);
    const std::string name = std::string(lang == Source::Glsl ? "GLSL" : "HLSL") + " TSM, true depths";
    INFO(name);
    MESSAGE(name << ": sk_warp_shadow_auto compared " << a.agreement.compared << " (lit " << a.agreement.lit << ", shadowed "
                 << a.agreement.shadowed << "), agreement " << a.agreement.fraction() << ", lit pixels dark " << a.agreement.acne
                 << "; no bias: agreement " << none.agreement.fraction() << ", lit pixels dark " << none.agreement.acne);
    CHECK(a.separate_depth);
    CHECK(a.agreement.compared > int(kW * kH) / 4);
    CHECK(a.agreement.shadowed > a.agreement.compared / 50);
    CHECK(a.agreement.fraction() >= 0.995);
    CHECK(double(a.agreement.acne) <= 0.002 * double(a.agreement.lit));
    CHECK(none.agreement.acne > a.agreement.lit / 100);  // the control: the true depths without a bias acne
    CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());
}

}  // namespace

TEST_CASE("perspective_shadow_maps.glsl on Vulkan: sk_warp_shadow_auto on TSM's true depths, no acne, matches the ray cast") {
    check_auto(Source::Glsl);
}

TEST_CASE("HLSL perspective_shadow_maps.hlsl on Vulkan: sk_warp_shadow_auto on TSM's true depths, no acne, matches the ray cast") {
    check_auto(Source::Hlsl);
}

TEST_CASE("perspective_shadow_maps.glsl on Vulkan: LiSPSM and TSM in [0,1] depth, standard and reversed-Z, match the ray cast") {
    check(Source::Glsl);
}

TEST_CASE("HLSL perspective_shadow_maps.hlsl on Vulkan: LiSPSM and TSM in [0,1] depth, standard and reversed-Z, match the ray cast") {
    check(Source::Hlsl);
}
