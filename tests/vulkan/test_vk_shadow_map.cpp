// glsl/shadow_map.glsl and hlsl/shadow_map.hlsl RUN on Vulkan (lavapipe in CI), against the CPU ray
// cast of tests/gl/test_gl_shadow_map_e2e.cpp with its tolerance (>= 99.5% of receiver pixels away
// from shadow edges agree). The light's matrix is shadowkit::light_frustum_fit's with
// ClipDepth::ZeroToOne, standard and reversed-Z; Vulkan's y-down NDC is met both ways, a
// negative-height viewport and a projection flip, in the map pass and the camera pass; the lookups
// are sk_shadow_map_visibility (slope-scaled depth bias in the map pass) and
// sk_shadow_map_visibility_auto (no bias). Each source is compiled to SPIR-V by glslang and checked by
// spirv-val; the validation layer must report nothing. A control: a map drawn with the viewport flip
// but looked up with the unflipped matrix disagrees (the y rule is what makes the others pass).
#include <doctest/doctest.h>

#include <shadowkit/light_frustum.hpp>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "vk_harness.hpp"
#include "vk_passes.hpp"
#include "vk_scene.hpp"

namespace {

using skvk::Source;
using skvk::compile_checked;
using skvk::read_text;

// ---------------------------------------------------------------------------------------- drivers
// The map pass: position only, the matrix in push constants.

// The receiver pass: visibility + G-buffer (world position, normal); the map at binding 0 (GLSL: a
// combined image sampler; HLSL: a texture at 0 and its comparison sampler at 2), the matrices in a
// uniform buffer at binding 1.
const char* kParamsGlsl = R"(
layout(set = 0, binding = 1, std140) uniform Params { mat4 view_proj; mat4 light_view_proj; vec4 mode; } u;
)";
const char* kReceiverGlslFs = R"(
layout(set = 0, binding = 0) uniform sampler2DShadow u_shadow_map;
void main() {
    o_visibility = u.mode.x > 0.5
        ? sk_shadow_map_visibility_auto(u_shadow_map, u.light_view_proj, v_world, v_normal, true, 0.0, 0.0)
        : sk_shadow_map_visibility(u_shadow_map, u.light_view_proj, v_world, true, 0.0, 0.0);
    o_world = vec4(v_world, 1.0);
    o_normal = vec4(normalize(v_normal), 0.0);
}
)";
const char* kReceiverHlsl = R"(
struct Params { column_major float4x4 view_proj; column_major float4x4 light_view_proj; float4 mode; };
[[vk::binding(0, 0)]] Texture2D<float> u_shadow_map;
[[vk::binding(1, 0)]] ConstantBuffer<Params> u;
[[vk::binding(2, 0)]] SamplerComparisonState u_compare;
)";
const char* kReceiverHlslPs = R"(
Targets ps_main(Varyings i) {
    Targets o;
    o.visibility = u.mode.x > 0.5
        ? sk_shadow_map_visibility_auto(u_shadow_map, u_compare, u.light_view_proj, i.world, i.normal, true, 0.0, 0.0)
        : sk_shadow_map_visibility(u_shadow_map, u_compare, u.light_view_proj, i.world, true, 0.0, 0.0);
    o.world = float4(i.world, 1.0);
    o.normal = float4(normalize(i.normal), 0.0);
    return o;
}
)";

// ---------------------------------------------------------------------------------------- one run
enum class YFlip { Viewport, Projection };

struct Variant {
    Source lang = Source::Glsl;
    bool reversed = false;
    YFlip flip = YFlip::Viewport;
    bool auto_bias = false;
    bool wrong_lookup = false;  ///< control: the viewport-flipped map looked up with the unflipped matrix
};

std::string name_of(const Variant& v) {
    std::string s = v.lang == Source::Glsl ? "GLSL" : "HLSL";
    s += v.reversed ? ", reversed-Z" : ", standard depth";
    s += v.flip == YFlip::Viewport ? ", viewport flip" : ", projection flip";
    s += v.auto_bias ? ", automatic bias" : ", depth bias";
    if (v.wrong_lookup) s += ", unflipped lookup (control)";
    return s;
}

constexpr std::uint32_t kMap = 1024, kW = 320, kH = 240;

glm::mat4 flip_y() {
    glm::mat4 f(1.f);
    f[1][1] = -1.f;
    return f;
}

struct Camera {
    glm::mat4 view, proj;
};
Camera camera(bool reversed) {
    Camera c;
    c.view = glm::lookAt(glm::vec3(0.f, 3.5f, 5.f), glm::vec3(0.f, 0.3f, 0.f), glm::vec3(0.f, 1.f, 0.f));
    c.proj = glm::perspectiveRH_ZO(0.9f, float(kW) / float(kH), 0.1f, 50.f);
    if (reversed) c.proj = skvk::reverse_z() * c.proj;
    return c;
}

// The light's matrix from the headers: the point light's frustum fitted to the camera's view of the
// scene, in [0, 1] depth (reversed or not).
glm::mat4 light_matrix(const skvk::BoxScene& s, const Camera& cam, bool reversed) {
    shadowkit::LightFrustumInput in;
    in.camera_view = cam.view;
    in.camera_proj = cam.proj;
    in.camera_depth = shadowkit::ClipDepth::ZeroToOne;
    in.camera_reversed_z = reversed;
    in.has_scene_bounds = true;
    in.scene_min = glm::vec3(-s.ground_half, 0.f, -s.ground_half);
    in.scene_max = glm::vec3(s.ground_half, s.box_c.y + s.box_h.y, s.ground_half);
    in.light_position = glm::vec4(s.light, 1.f);
    const glm::vec3 lo = s.box_c - s.box_h, hi = s.box_c + s.box_h;
    const float boxes[12] = {lo.x, lo.y, lo.z, hi.x, hi.y, hi.z, -3.f, 0.f, -3.f, 3.f, 0.f, 3.f};
    in.casters = boxes;
    in.caster_count = 2;
    in.light_depth = shadowkit::ClipDepth::ZeroToOne;
    in.light_reversed_z = reversed;
    std::uint32_t keep[2];
    const shadowkit::LightFrustumResult r = shadowkit::light_frustum_fit(in, keep, 2);
    REQUIRE_MESSAGE(r.status == shadowkit::Status::Ok, shadowkit::status_name(r.status));
    REQUIRE(r.visible);
    CHECK(r.count == 2);
    return r.view_proj;
}

struct Shaders {
    std::vector<std::uint32_t> depth_vs, vs, fs;
    const char* vs_entry = "main";
    const char* fs_entry = "main";
};

Shaders shaders(Source lang, bool reversed) {
    const std::string define = reversed ? "#define SK_REVERSED_Z 1\n" : "";
    const std::string tag = std::string(reversed ? "reversed" : "standard");
    Shaders s;
    if (lang == Source::Glsl) {
        const std::string snippet = read_text(std::string(SHADOWKIT_GLSL_DIR) + "/shadow_map.glsl");
        s.depth_vs = compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, skvk::kSceneDepthGlsl, "main", "shadow_map.glsl.depth.vert");
        s.vs = compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, skvk::receiver_glsl_vs(kParamsGlsl), "main", "shadow_map.glsl.vert");
        s.fs = compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT,
                               "#version 450 core\n" + define + snippet + kParamsGlsl + skvk::kReceiverGlslFsIo + kReceiverGlslFs,
                               "main", "shadow_map.glsl." + tag + ".frag");
    } else {
        const std::string snippet = read_text(std::string(SHADOWKIT_HLSL_DIR) + "/shadow_map.hlsl");
        s.depth_vs = compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, skvk::kSceneDepthHlsl, "main", "shadow_map.hlsl.depth.vert");
        const std::string receiver = kReceiverHlsl + std::string(skvk::kReceiverHlslVs) + skvk::kReceiverHlslTargets + kReceiverHlslPs;
        s.vs = compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, snippet + receiver, "vs_main", "shadow_map.hlsl.vert");
        s.fs = compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, define + snippet + receiver, "ps_main",
                               "shadow_map.hlsl." + tag + ".frag");
        s.vs_entry = "vs_main";
        s.fs_entry = "ps_main";
    }
    return s;
}

struct RunResult {
    skvk::Agreement agreement;
    int upright_checked = 0, upright_ok = 0;  ///< probe points found where the upright image has them
    std::size_t covered = 0;                  ///< pixels with geometry
};

RunResult run(const Variant& v) {
    skvk::Context& ctx = skvk::vk_test_context();
    skvk::Scope scope(ctx);
    const skvk::BoxScene scene;
    const Camera cam = camera(v.reversed);
    const glm::mat4 light_vp = light_matrix(scene, cam, v.reversed);
    const bool vflip = v.flip == YFlip::Viewport;
    // what the map pass draws with, and what the lookup gets: the matrix whose NDC y maps to the
    // map's rows as stored (v = y * 0.5 + 0.5): a viewport-flipped map needs flip_y * light_vp
    const glm::mat4 map_vp = vflip ? light_vp : flip_y() * light_vp;
    const glm::mat4 lookup_vp = v.wrong_lookup ? light_vp : flip_y() * light_vp;
    const glm::mat4 cam_vp = (vflip ? glm::mat4(1.f) : flip_y()) * cam.proj * cam.view;
    const Shaders sh = shaders(v.lang, v.reversed);

    skvk::Buffer& vb = scope.own<skvk::Buffer>();
    skvk::Buffer& ubo = scope.own<skvk::Buffer>();
    const auto vcount = static_cast<std::uint32_t>(scene.vertices.size());
    REQUIRE(skvk::make_buffer(ctx, sizeof(skvk::SceneVertex) * vcount, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, vb));
    std::memcpy(vb.mapped, scene.vertices.data(), sizeof(skvk::SceneVertex) * vcount);
    struct Params {
        glm::mat4 view_proj, light_view_proj;
        glm::vec4 mode;
    } params{cam_vp, lookup_vp, glm::vec4(v.auto_bias ? 1.f : 0.f, 0.f, 0.f, 0.f)};
    REQUIRE(skvk::make_buffer(ctx, sizeof(Params), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, ubo));
    std::memcpy(ubo.mapped, &params, sizeof params);

    // map pass: depth only, D32_SFLOAT, cleared to the far value, slope-scaled bias for the plain lookup
    skvk::Image& map = scope.own<skvk::Image>();
    REQUIRE(skvk::make_image(ctx, kMap, kMap, 1, VK_FORMAT_D32_SFLOAT,
                             VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT, map));
    const VkImageLayout map_read = VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL;
    VkRenderPass map_rp = scope.keep(skvk::make_render_pass(ctx, {}, VK_FORMAT_D32_SFLOAT, map_read), vkDestroyRenderPass);
    VkFramebuffer map_fb = scope.keep(skvk::make_framebuffer(ctx, map_rp, {map.view}, kMap, kMap), vkDestroyFramebuffer);
    VkPipelineLayout map_layout = scope.keep(skvk::make_pipeline_layout(ctx, nullptr, sizeof(glm::mat4)), vkDestroyPipelineLayout);
    skvk::PipelineDesc md = skvk::scene_pipeline(sh.depth_vs, {}, "main", "main", false);
    md.depth_compare = v.reversed ? VK_COMPARE_OP_GREATER : VK_COMPARE_OP_LESS;
    md.depth_bias = !v.auto_bias;  // the GL test's glPolygonOffset(1.5, 2); reversed-Z pushes the other way
    md.bias_slope = v.reversed ? -1.5f : 1.5f;
    md.bias_constant = v.reversed ? -2.f : 2.f;
    VkPipeline map_pipe = scope.keep(skvk::make_pipeline_checked(ctx, md, map_layout, map_rp), vkDestroyPipeline);

    // receiver pass: visibility R32F, world and normal RGBA32F, depth D32_SFLOAT
    skvk::ReceiverTargets& rt = scope.own<skvk::ReceiverTargets>();
    skvk::make_receiver_targets(ctx, kW, kH, rt);
    // the comparison sampler: LEQUAL (GEQUAL reversed), linear: the hardware 2x2 filter, as on GL
    VkSampler sampler = scope.keep(skvk::make_sampler(ctx, VK_FILTER_LINEAR,
                                           v.reversed ? VK_COMPARE_OP_GREATER_OR_EQUAL : VK_COMPARE_OP_LESS_OR_EQUAL), vkDestroySampler);
    skvk::DescriptorSet& ds = scope.own<skvk::DescriptorSet>();
    skvk::make_lookup_set(ctx, v.lang, map.view, map_read, sampler, ubo, ds);
    VkPipelineLayout layout = scope.keep(skvk::make_pipeline_layout(ctx, &ds), vkDestroyPipelineLayout);
    skvk::PipelineDesc pd = skvk::scene_pipeline(sh.vs, sh.fs, sh.vs_entry, sh.fs_entry);
    pd.depth_compare = v.reversed ? VK_COMPARE_OP_GREATER : VK_COMPARE_OP_LESS;
    pd.color_count = 3;
    // back faces culled, GL's counter-clockwise front faces: both flips draw the upright image, so both
    // keep them (measured: VK_FRONT_FACE_CLOCKWISE with the projection flip culled the visible faces,
    // 112 receiver pixels left of 41,338); only the unflipped GL matrix (an upside-down image) needs CW
    pd.cull = VK_CULL_MODE_BACK_BIT;
    pd.front = VK_FRONT_FACE_COUNTER_CLOCKWISE;
    VkPipeline pipe = scope.keep(skvk::make_pipeline_checked(ctx, pd, layout, rt.rp), vkDestroyPipeline);

    VkCommandBuffer cmd = skvk::begin_commands(ctx);
    VkClearValue far{};
    far.depthStencil = {v.reversed ? 0.f : 1.f, 0};
    skvk::draw_pass(cmd, map_rp, map_fb, kMap, kMap, {far}, map_pipe, map_layout, nullptr, &map_vp, vb.buffer, vcount, vflip);
    VkClearValue zero{};
    skvk::draw_pass(cmd, rt.rp, rt.fb, kW, kH, {zero, zero, zero, far}, pipe, layout, &ds.set, nullptr, vb.buffer, vcount, vflip);
    REQUIRE(skvk::submit_and_wait(ctx, cmd));

    const skvk::ReceiverImages img = skvk::read_receiver(ctx, rt);
    const std::vector<float>& v_vis = img.vis;
    const std::vector<float>& v_world = img.world;

    RunResult out;
    out.agreement = skvk::compare_with_ray_cast(scene, glm::vec4(scene.light, 1.f), &light_vp, int(kW), int(kH), v_vis,
                                                 v_world, img.normal);
    for (std::size_t k = 0; k < v_vis.size(); ++k) out.covered += v_world[k * 4 + 3] != 0.f;
    // upright: probe points projected with the GL convention (window y up) must be found at row
    // h - 1 - y of the read-back image (row 0 = top, as a presented image shows it)
    const glm::mat4 gl_vp = cam.proj * cam.view;
    for (const glm::vec3 p : {glm::vec3(0.f, 1.1f, 0.f), glm::vec3(-2.f, 0.f, 1.f), glm::vec3(2.f, 0.f, -2.f),
                              glm::vec3(0.5f, 0.f, 2.5f)}) {
        const glm::vec4 c = gl_vp * glm::vec4(p, 1.f);
        const int x = int((c.x / c.w * 0.5f + 0.5f) * float(kW)), y_up = int((c.y / c.w * 0.5f + 0.5f) * float(kH));
        const auto k = static_cast<std::size_t>((int(kH) - 1 - y_up) * int(kW) + x);
        ++out.upright_checked;
        const glm::vec3 got(v_world[k * 4], v_world[k * 4 + 1], v_world[k * 4 + 2]);
        out.upright_ok += v_world[k * 4 + 3] != 0.f && glm::length(got - p) < 0.1f;
    }

    return out;
}

void check_all_variants(Source lang) {
    for (bool reversed : {false, true})
        for (YFlip flip : {YFlip::Viewport, YFlip::Projection})
            for (bool auto_bias : {false, true}) {
                Variant v;
                v.lang = lang;
                v.reversed = reversed;
                v.flip = flip;
                v.auto_bias = auto_bias;
                const std::size_t before = skvk::message_count();
                const RunResult r = run(v);
                const skvk::Agreement& a = r.agreement;
                INFO(name_of(v));
                MESSAGE(name_of(v) << ": compared " << a.compared << " (lit " << a.lit << ", shadowed " << a.shadowed
                                   << "), agreement " << a.fraction() << ", upright probes " << r.upright_ok << "/"
                                   << r.upright_checked);
                CHECK(a.compared > int(kW * kH) / 4);
                CHECK(a.shadowed > a.compared / 50);
                CHECK(a.lit > a.compared / 4);
                CHECK(a.fraction() >= 0.995);
                CHECK(r.upright_ok == r.upright_checked);
                CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());
            }
}

// skvk::Scope's own test: what it destroys, and in which order, recorded by stand-ins for vkDestroy*
// and for a harness struct's destroy (numbers, not Vulkan objects).
std::vector<std::uint64_t> g_destroyed;

template <class H>
H fake_handle(std::uint64_t v) {  // a handle's bits, whatever C++ type the handle is (pointer or uint64_t)
    static_assert(sizeof(H) <= sizeof v, "a handle is at most 64 bits");
    H h{};
    std::memcpy(&h, &v, sizeof h);
    return h;
}
VKAPI_ATTR void VKAPI_CALL record_sampler(VkDevice, VkSampler h, const VkAllocationCallbacks*) {
    std::uint64_t v = 0;
    std::memcpy(&v, &h, sizeof h);
    g_destroyed.push_back(v);
}
struct Recorded {
    std::uint64_t id = 0;
};
void destroy(skvk::Context&, Recorded& r) { g_destroyed.push_back(1000 + r.id); }

}  // namespace

TEST_CASE("shadow_map.glsl on Vulkan: [0,1] depth, reversed-Z, both y flips, both biases agree with the ray cast") {
    MESSAGE("device: " << skvk::vk_test_context().device_name);
    check_all_variants(Source::Glsl);
}

TEST_CASE("shadow_map.glsl on Vulkan, control: a viewport-flipped map read with the unflipped matrix disagrees") {
    Variant v;
    v.wrong_lookup = true;
    const RunResult r = run(v);
    MESSAGE(name_of(v) << ": agreement " << r.agreement.fraction() << " of " << r.agreement.compared);
    CHECK(r.agreement.compared > int(kW * kH) / 4);
    CHECK(r.agreement.fraction() < 0.95);
}

TEST_CASE("the validation layer's messages are counted (the zero-message check can fail)") {
    skvk::Context& ctx = skvk::vk_test_context();
    REQUIRE(ctx.validation);
    const std::size_t before = skvk::message_count();
    // anisotropic filtering without the samplerAnisotropy feature enabled: a valid-usage error
    VkSamplerCreateInfo si{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    si.anisotropyEnable = VK_TRUE;
    si.maxAnisotropy = 4.f;
    VkSampler s = VK_NULL_HANDLE;
    vkCreateSampler(ctx.device, &si, nullptr, &s);
    if (s) vkDestroySampler(ctx.device, s, nullptr);
    const std::size_t provoked = skvk::message_count() - before;
    MESSAGE("messages for the misused sampler: " << provoked);
    CHECK(provoked >= 1);
    skvk::expect_messages(provoked);
}

TEST_CASE("skvk::Scope destroys what it was handed, last handed first, skipping VK_NULL_HANDLE, also when an exception leaves") {
    skvk::Context& ctx = skvk::vk_test_context();
    g_destroyed.clear();
    {
        skvk::Scope scope(ctx);
        CHECK(scope.keep(fake_handle<VkSampler>(1), record_sampler) == fake_handle<VkSampler>(1));
        scope.own<Recorded>().id = 2;
        const VkSampler none = VK_NULL_HANDLE;
        scope.keep(none, record_sampler);
        auto& v = scope.own<std::vector<Recorded>>(2);
        v[0].id = 3;
        v[1].id = 4;
        scope.keep(fake_handle<VkSampler>(5), record_sampler);
        CHECK(g_destroyed.empty());
    }
    CHECK(g_destroyed == std::vector<std::uint64_t>{5, 1004, 1003, 1002, 1});
    // an exception (a failed REQUIRE throws one) leaving the Scope's block: destroyed all the same; the
    // real sampler and buffer would show as objects left at vkDestroyDevice in the run's message count
    g_destroyed.clear();
    const std::size_t before = skvk::message_count();
    try {
        skvk::Scope scope(ctx);
        scope.keep(fake_handle<VkSampler>(6), record_sampler);
        const VkSampler real = scope.keep(skvk::make_sampler(ctx, VK_FILTER_NEAREST, VK_COMPARE_OP_NEVER), vkDestroySampler);
        REQUIRE(real != VK_NULL_HANDLE);
        skvk::Buffer& b = scope.own<skvk::Buffer>();
        REQUIRE(skvk::make_buffer(ctx, 256, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, b));
        scope.own<Recorded>().id = 7;
        throw std::runtime_error("leaving the block");
    } catch (const std::runtime_error&) {
    }
    CHECK(g_destroyed == std::vector<std::uint64_t>{1007, 6});
    CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());
}

TEST_CASE("HLSL shadow_map.hlsl on Vulkan: [0,1] depth, reversed-Z, both y flips, both biases agree with the ray cast") {
    check_all_variants(Source::Hlsl);
}
