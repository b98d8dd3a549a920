// glsl/omni_shadow.glsl's and hlsl/omni_shadow.hlsl's distance cube RUN on Vulkan: the six faces of a
// cube-compatible VK_FORMAT_D32_SFLOAT image rendered with GL's face matrices and a plain viewport,
// the fragment stage writing sk_omni_linear_depth (distance / range) as the depth; the receivers read it
// with sk_cube_visibility_distance (hardware compare), sk_cube_visibility_distance_pcf (3 x 3 taps
// across faces) and sk_cube_visibility_distance_manual (a point sampler on the same image), biased by
// sk_omni_bias; the e2e scene's CPU ray cast as reference (>= 99.5% away from shadow edges), no
// validation message. The dual-paraboloid maps (map pass and lookups) run as well: see the section below.
#include <doctest/doctest.h>

#include <shadowkit/infinite_projection.hpp>
#include <shadowkit/omni_shadow.hpp>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "vk_harness.hpp"
#include "vk_passes.hpp"
#include "vk_scene.hpp"

namespace {

using skvk::Source;

// The map pass: the face's matrix and the light in push constants, distance / range as the depth.
const char* kDepthVsGlsl = R"(#version 450 core
layout(push_constant) uniform DepthParams { mat4 face_view_proj; vec4 light_position; vec4 range; } pc;
layout(location = 0) in vec3 a_position;
layout(location = 0) out vec3 v_world;
void main() {
    v_world = a_position;
    gl_Position = pc.face_view_proj * vec4(a_position, 1.0);
}
)";
const char* kDepthFsGlsl = R"(
layout(push_constant) uniform DepthParams { mat4 face_view_proj; vec4 light_position; vec4 range; } pc;
layout(location = 0) in vec3 v_world;
void main() { gl_FragDepth = sk_omni_linear_depth(v_world, pc.light_position, pc.range.x); }
)";
const char* kDepthHlsl = R"(
struct DepthParams { column_major float4x4 face_view_proj; float4 light_position; float4 range; };
[[vk::push_constant]] ConstantBuffer<DepthParams> pc;
struct DepthVaryings {
    float4 position : SV_Position;
    [[vk::location(0)]] float3 world : TEXCOORD0;
};
DepthVaryings vs_depth([[vk::location(0)]] float3 position : POSITION) {
    DepthVaryings o;
    o.world = position;
    o.position = mul(pc.face_view_proj, float4(position, 1.0));
    return o;
}
float ps_depth(DepthVaryings i) : SV_Depth { return sk_omni_linear_depth(i.world, pc.light_position, pc.range.x); }
)";
// params: x = range, y = face size, z = lookup (0 compare, 1 pcf 3 x 3, 2 manual)
const char* kParamsGlsl = R"(
layout(set = 0, binding = 1, std140) uniform Params { mat4 view_proj; vec4 light_position; vec4 params; } u;
)";
const char* kReceiverGlslFs = R"(
layout(set = 0, binding = 0) uniform samplerCubeShadow u_cube;
layout(set = 0, binding = 2) uniform samplerCube u_cube_distance;
void main() {
    vec3 L = sk_omni_light_point(u.light_position) - v_world;
    float d = length(L);
    int mode = int(u.params.z);
    float radius = mode == 1 ? 2.0 * 1.4143 : 1.4143;
    float b = sk_omni_bias(d, dot(normalize(v_normal), L / d), sk_omni_cube_texel_angle(u.params.y), radius, 1.4835,
                           vec2(0.0, 2.38418579e-7));
    if (mode == 0) o_visibility = sk_cube_visibility_distance(u_cube, u.light_position, v_world, u.params.x, b);
    else if (mode == 1) o_visibility = sk_cube_visibility_distance_pcf(u_cube, u.light_position, v_world, u.params.x, b, u.params.y, 1);
    else o_visibility = sk_cube_visibility_distance_manual(u_cube_distance, u.light_position, v_world, u.params.x, b);
    o_world = vec4(v_world, 1.0);
    o_normal = vec4(normalize(v_normal), 0.0);
}
)";
const char* kReceiverHlsl = R"(
struct Params { column_major float4x4 view_proj; float4 light_position; float4 params; };
[[vk::binding(0, 0)]] TextureCube<float> u_cube;
[[vk::binding(1, 0)]] ConstantBuffer<Params> u;
[[vk::binding(2, 0)]] SamplerComparisonState u_compare;
[[vk::binding(3, 0)]] SamplerState u_point;
)";
const char* kReceiverHlslPs = R"(
Targets ps_main(Varyings i) {
    Targets o;
    float3 L = sk_omni_light_point(u.light_position) - i.world;
    float d = length(L);
    int mode = int(u.params.z);
    float radius = mode == 1 ? 2.0 * 1.4143 : 1.4143;
    float b = sk_omni_bias(d, dot(normalize(i.normal), L / d), sk_omni_cube_texel_angle(u.params.y), radius, 1.4835,
                           float2(0.0, 2.38418579e-7));
    if (mode == 0) o.visibility = sk_cube_visibility_distance(u_cube, u_compare, u.light_position, i.world, u.params.x, b);
    else if (mode == 1)
        o.visibility = sk_cube_visibility_distance_pcf(u_cube, u_compare, u.light_position, i.world, u.params.x, b, u.params.y, 1);
    else o.visibility = sk_cube_visibility_distance_manual(u_cube, u_point, u.light_position, i.world, u.params.x, b);
    o.world = float4(i.world, 1.0);
    o.normal = float4(normalize(i.normal), 0.0);
    return o;
}
)";

// The receiver pass in HLSL: the bindings, the shared varyings, vertex stage and targets, the lookup.
std::string receiver_hlsl() {
    return kReceiverHlsl + std::string(skvk::kReceiverHlslVs) + skvk::kReceiverHlslTargets + kReceiverHlslPs;
}

constexpr std::uint32_t kFace = 512, kW = 320, kH = 240;
constexpr float kNear = 0.1f, kFar = 20.f, kRange = 12.f;

struct Params {
    glm::mat4 view_proj;
    glm::vec4 light_position, params;
};
struct DepthPush {
    glm::mat4 face_view_proj;
    glm::vec4 light_position, range;
};

// GL's cube-map face frames (+X, -X, +Y, -Y, +Z, -Z), 90-degree faces in [0, 1] depth.
void face_matrices(glm::vec3 L, glm::mat4 out[6]) {
    const glm::vec3 dir[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    const glm::vec3 up[6] = {{0, -1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0, -1, 0}, {0, -1, 0}};
    const glm::mat4 proj = glm::perspectiveRH_ZO(glm::radians(90.f), 1.f, kNear, kFar);
    for (int f = 0; f < 6; ++f) out[f] = proj * glm::lookAt(L, L + dir[f], up[f]);
}

// Reversed-Z: the faces' matrices from omni_cube_matrices (ZeroToOne, reversed_z; GL's face order and
// orientation), the camera from projection_perspective_finite (ZeroToOne, reversed_z).
void reversed_matrices(glm::vec4 light, glm::mat4 out[6]) {
    shadowkit::OmniCubeInput in;
    in.light_position = light;
    in.near_z = kNear;
    in.far_z = kFar;
    in.clip_depth = shadowkit::ClipDepth::ZeroToOne;
    in.reversed_z = true;
    const shadowkit::OmniCubeMatrices m = shadowkit::omni_cube_matrices(in);
    REQUIRE(m.status == shadowkit::Status::Ok);
    for (int f = 0; f < 6; ++f) out[f] = m.view_proj[f];
}
glm::mat4 reversed_camera() {
    const shadowkit::ProjectionResult p =
        shadowkit::projection_perspective_finite(0.9f, float(kW) / float(kH), 0.1f, 50.f, shadowkit::ClipDepth::ZeroToOne, true);
    REQUIRE(p.status == shadowkit::Status::Ok);
    return p.matrix;
}

skvk::Agreement run(Source lang, int mode, bool reversed = false) {
    skvk::Context& ctx = skvk::vk_test_context();
    skvk::Scope scope(ctx);
    const skvk::BoxScene scene;
    const glm::vec4 light(scene.light, 1.f);
    glm::mat4 faces[6];
    face_matrices(scene.light, faces);
    if (reversed) reversed_matrices(light, faces);
    const glm::mat4 cam = (reversed ? reversed_camera() : glm::perspectiveRH_ZO(0.9f, float(kW) / float(kH), 0.1f, 50.f)) *
                          glm::lookAt(glm::vec3(0.f, 3.5f, 5.f), glm::vec3(0.f, 0.3f, 0.f), glm::vec3(0.f, 1.f, 0.f));
    const Params params{cam, light, glm::vec4(kRange, float(kFace), float(mode), 0.f)};

    std::vector<std::uint32_t> depth_vs, depth_fs, vs, fs;
    const char* entries[4] = {"main", "main", "main", "main"};
    if (lang == Source::Glsl) {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_GLSL_DIR) + "/omni_shadow.glsl");
        depth_vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, kDepthVsGlsl, "main", "omni.glsl.depth.vert");
        depth_fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, "#version 450 core\n" + snippet + kDepthFsGlsl, "main",
                                         "omni.glsl.depth.frag");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, skvk::receiver_glsl_vs(kParamsGlsl), "main", "omni.glsl.vert");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, "#version 450 core\n" + snippet + kParamsGlsl + skvk::kReceiverGlslFsIo + kReceiverGlslFs, "main",
                                   "omni.glsl.frag");
    } else {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_HLSL_DIR) + "/omni_shadow.hlsl");
        depth_vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, snippet + kDepthHlsl, "vs_depth", "omni.hlsl.depth.vert");
        depth_fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, snippet + kDepthHlsl, "ps_depth", "omni.hlsl.depth.frag");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, snippet + receiver_hlsl(), "vs_main", "omni.hlsl.vert");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, snippet + receiver_hlsl(), "ps_main", "omni.hlsl.frag");
        entries[0] = "vs_depth";
        entries[1] = "ps_depth";
        entries[2] = "vs_main";
        entries[3] = "ps_main";
    }

    skvk::Buffer& vb = scope.own<skvk::Buffer>();
    skvk::Buffer& ubo = scope.own<skvk::Buffer>();
    const auto vcount = static_cast<std::uint32_t>(scene.vertices.size());
    REQUIRE(skvk::make_buffer(ctx, sizeof(skvk::SceneVertex) * vcount, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, vb));
    std::memcpy(vb.mapped, scene.vertices.data(), sizeof(skvk::SceneVertex) * vcount);
    REQUIRE(skvk::make_buffer(ctx, sizeof(Params), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, ubo));
    std::memcpy(ubo.mapped, &params, sizeof params);

    skvk::Image& cube = scope.own<skvk::Image>();
    REQUIRE(skvk::make_image(ctx, kFace, kFace, 6, VK_FORMAT_D32_SFLOAT,
                             VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT, cube, false, true));
    const VkImageLayout map_read = VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL;
    VkRenderPass map_rp = scope.keep(skvk::make_render_pass(ctx, {}, VK_FORMAT_D32_SFLOAT, map_read), vkDestroyRenderPass);
    std::vector<VkFramebuffer> map_fb;
    for (int f = 0; f < 6; ++f) map_fb.push_back(scope.keep(skvk::make_framebuffer(ctx, map_rp, {cube.layer_views[std::size_t(f)]}, kFace, kFace), vkDestroyFramebuffer));
    VkPipelineLayout map_layout = scope.keep(skvk::make_pipeline_layout(ctx, nullptr, sizeof(DepthPush), VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT), vkDestroyPipelineLayout);
    // writes distance / range: no rasterized depth, no polygon offset
    skvk::PipelineDesc md = skvk::scene_pipeline(depth_vs, depth_fs, entries[0], entries[1], false);
    VkPipeline map_pipe = scope.keep(skvk::make_pipeline_checked(ctx, md, map_layout, map_rp), vkDestroyPipeline);

    skvk::ReceiverTargets& rt = scope.own<skvk::ReceiverTargets>();
    skvk::make_receiver_targets(ctx, kW, kH, rt);
    VkSampler sampler = scope.keep(skvk::make_sampler(ctx, VK_FILTER_LINEAR, VK_COMPARE_OP_LESS_OR_EQUAL), vkDestroySampler);
    VkSampler point = scope.keep(skvk::make_sampler(ctx, VK_FILTER_NEAREST, VK_COMPARE_OP_NEVER), vkDestroySampler);
    // and the point-sampled cube for the manual lookup: GLSL a second combined sampler at 2, HLSL a sampler at 3
    skvk::DescriptorSet& ds = scope.own<skvk::DescriptorSet>();
    const bool glsl = lang == Source::Glsl;
    skvk::make_lookup_set(ctx, lang, cube.view, map_read, sampler, ubo, ds,
                          {{glsl ? 2u : 3u, glsl ? VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER : VK_DESCRIPTOR_TYPE_SAMPLER,
                            VK_SHADER_STAGE_FRAGMENT_BIT}});
    if (glsl)
        skvk::write_image(ctx, ds, 2, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, cube.view, point, map_read);
    else
        skvk::write_sampler(ctx, ds, 3, point);
    VkPipelineLayout layout = scope.keep(skvk::make_pipeline_layout(ctx, &ds), vkDestroyPipelineLayout);
    skvk::PipelineDesc pd = skvk::scene_pipeline(vs, fs, entries[2], entries[3]);
    pd.color_count = 3;
    pd.cull = VK_CULL_MODE_BACK_BIT;
    if (reversed) pd.depth_compare = VK_COMPARE_OP_GREATER;
    VkPipeline pipe = scope.keep(skvk::make_pipeline_checked(ctx, pd, layout, rt.rp), vkDestroyPipeline);

    VkCommandBuffer cmd = skvk::begin_commands(ctx);
    VkClearValue far{};
    far.depthStencil = {1.f, 0};
    for (int f = 0; f < 6; ++f) {
        const DepthPush push{faces[f], light, glm::vec4(kRange)};
        skvk::draw_pass(cmd, map_rp, map_fb[std::size_t(f)], kFace, kFace, {far}, map_pipe, map_layout, nullptr, &push, vb.buffer,
                        vcount, false, sizeof push, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT);
    }
    VkClearValue zero{}, cam_far = far;
    if (reversed) cam_far.depthStencil.depth = 0.f;
    skvk::draw_pass(cmd, rt.rp, rt.fb, kW, kH, {zero, zero, zero, cam_far}, pipe, layout, &ds.set, nullptr, vb.buffer, vcount, true);
    REQUIRE(skvk::submit_and_wait(ctx, cmd));

    const skvk::Agreement a = skvk::receiver_agreement(ctx, rt, scene, light);

    return a;
}

void check(Source lang) {
    const char* names[3] = {"compare", "pcf 3 x 3", "manual (point sampler)"};
    for (int mode = 0; mode < 3; ++mode) {
        const std::size_t before = skvk::message_count();
        const skvk::Agreement a = run(lang, mode);
        const std::string name = std::string(lang == Source::Glsl ? "GLSL" : "HLSL") + " distance cube, " + names[mode];
        INFO(name);
        MESSAGE(name << ": compared " << a.compared << " (lit " << a.lit << ", shadowed " << a.shadowed << "), agreement "
                     << a.fraction());
        CHECK(a.compared > int(kW * kH) / 4);
        CHECK(a.shadowed > a.compared / 50);
        CHECK(a.fraction() >= 0.995);
        CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());
    }
}


// ------------------------------------------------------------------------------ dual paraboloid
// The GL test's (c) on the e2e scene: both paraboloid maps in the two layers of one D32 array (887^2
// texels each, the texel count of a 512^2 cube), the map pass's vertex stage writing
// sk_dp_clip_position (zero_to_one) and sk_dp_clip_distance (margin 0.1, the shaderClipDistance
// feature), its fragment stage sk_omni_linear_depth, the casters (box and floor) tessellated so their
// chords stay within `tess` texels (omni_paraboloid_max_edge_length, the sample's uniform n x n split);
// the frame's axis horizontal and perpendicular to the light-to-box direction, so the rim runs through
// the box and its shadow. Lookups sk_dp_shadow and sk_dp_shadow_pcf (3 x 3, across the rim) biased
// with sk_omni_bias at sk_dp_texel_angle. References: the map against a CPU ray cast per texel centre
// (direction from omni_paraboloid_unproject), and the lookup against the e2e ray cast.
constexpr std::uint32_t kDp = 887;
constexpr float kMargin = 0.1f;

const char* kDpMapGlsl = R"(
layout(push_constant) uniform MapParams { mat4 dp_view; vec4 light_position; vec4 params; } pc;  // side, range, margin
#ifdef SK_MAP_VS
layout(location = 0) in vec3 a_position;
layout(location = 0) out vec3 v_world;
out gl_PerVertex { vec4 gl_Position; float gl_ClipDistance[1]; };
void main() {
    v_world = a_position;
    gl_Position = sk_dp_clip_position(pc.dp_view, a_position, pc.params.x, pc.params.y, true);
    gl_ClipDistance[0] = sk_dp_clip_distance(pc.dp_view, a_position, pc.params.x, pc.params.z);
}
#else
layout(location = 0) in vec3 v_world;
void main() { gl_FragDepth = sk_omni_linear_depth(v_world, pc.light_position, pc.params.y); }
#endif
)";
const char* kDpMapHlsl = R"(
struct MapParams { column_major float4x4 dp_view; float4 light_position; float4 params; };
[[vk::push_constant]] ConstantBuffer<MapParams> mp;
struct MapVaryings {
    float4 position : SV_Position;
    [[vk::location(0)]] float3 world : TEXCOORD0;
    float clip : SV_ClipDistance0;
};
MapVaryings vs_map([[vk::location(0)]] float3 position : POSITION) {
    MapVaryings o;
    o.world = position;
    o.position = sk_dp_clip_position(mp.dp_view, position, mp.params.x, mp.params.y, true);
    o.clip = sk_dp_clip_distance(mp.dp_view, position, mp.params.x, mp.params.z);
    return o;
}
float ps_map(MapVaryings i) : SV_Depth { return sk_omni_linear_depth(i.world, mp.light_position, mp.params.y); }
)";
// params: x = range, y = map size, z = tess (texels), w = pcf radius; storage: (absolute, relative)
const char* kDpParamsGlsl = R"(
layout(set = 0, binding = 0) uniform sampler2DArrayShadow u_dp;
layout(set = 0, binding = 1, std140) uniform Params { mat4 view_proj; mat4 dp_view; vec4 light_position; vec4 params; vec4 storage; } u;
)";
const char* kDpReceiverGlsl = R"(
void main() {
    vec3 L = sk_omni_light_point(u.light_position) - v_world;
    float d = length(L);
    vec4 c = sk_dp_coord(u.dp_view, v_world);
    int pcf = int(u.params.w);
    float radius = float(pcf + 1) * 1.4143 + u.params.z;
    float b = sk_omni_bias(d, dot(normalize(v_normal), L / d), sk_dp_texel_angle(u.params.y, c.w), radius, 1.4835, u.storage.xy);
    o_visibility = pcf > 0 ? sk_dp_shadow_pcf(u_dp, u.dp_view, v_world, u.params.x, b, u.params.y, pcf)
                           : sk_dp_shadow(u_dp, u.dp_view, v_world, u.params.x, b);
    o_world = vec4(v_world, 1.0);
    o_normal = vec4(normalize(v_normal), 0.0);
}
)";
const char* kDpReceiverHlsl = R"(
struct DpParams { column_major float4x4 view_proj; column_major float4x4 dp_view; float4 light_position; float4 params; float4 storage; };
[[vk::binding(0, 0)]] Texture2DArray<float> u_dp;
[[vk::binding(1, 0)]] ConstantBuffer<DpParams> u;
[[vk::binding(2, 0)]] SamplerComparisonState u_compare;
)";
const char* kDpReceiverHlslPs = R"(
Targets ps_receiver(Varyings i) {
    Targets o;
    float3 L = sk_omni_light_point(u.light_position) - i.world;
    float d = length(L);
    float4 c = sk_dp_coord(u.dp_view, i.world);
    int pcf = int(u.params.w);
    float radius = float(pcf + 1) * 1.4143 + u.params.z;
    float b = sk_omni_bias(d, dot(normalize(i.normal), L / d), sk_dp_texel_angle(u.params.y, c.w), radius, 1.4835, u.storage.xy);
    o.visibility = pcf > 0 ? sk_dp_shadow_pcf(u_dp, u_compare, u.dp_view, i.world, u.params.x, b, u.params.y, pcf)
                           : sk_dp_shadow(u_dp, u_compare, u.dp_view, i.world, u.params.x, b);
    o.world = float4(i.world, 1.0);
    o.normal = float4(normalize(i.normal), 0.0);
    return o;
}
)";

struct DpParams {
    glm::mat4 view_proj, dp_view;
    glm::vec4 light_position, params, storage;
};
struct MapPush {
    glm::mat4 dp_view;
    glm::vec4 light_position, params;
};

bool lex_less(const glm::vec3& a, const glm::vec3& b) {
    if (a.x != b.x) return a.x < b.x;
    if (a.y != b.y) return a.y < b.y;
    return a.z < b.z;
}

// samples/dual_paraboloid's split: every triangle into n x n, the points from its corners sorted
// lexicographically (a shared edge splits at the same points from both sides: watertight).
void subdivide(const std::vector<skvk::SceneVertex>& tris, int n, std::vector<glm::vec3>& out) {
    for (std::size_t t = 0; t + 2 < tris.size(); t += 3) {
        glm::vec3 v[3] = {tris[t].position, tris[t + 1].position, tris[t + 2].position};
        std::sort(v, v + 3, lex_less);
        auto at = [&](int i, int j) {
            const double wa = i, wb = j, wc = n - i - j;
            return glm::vec3((wa * glm::dvec3(v[0]) + wb * glm::dvec3(v[1]) + wc * glm::dvec3(v[2])) / double(n));
        };
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n - i; ++j) {
                for (const glm::vec3& q : {at(i, j), at(i + 1, j), at(i, j + 1)}) out.push_back(q);
                if (j + 1 < n - i)
                    for (const glm::vec3& q : {at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)}) out.push_back(q);
            }
    }
}

// The casters (floor: vertices 0-5, box: the rest), each split with one n from the shortest distance of
// the light to the mesh's box (a lower bound of every triangle's distance) and its longest edge.
std::vector<glm::vec3> dp_casters(const skvk::BoxScene& s, float tess, std::size_t& triangles) {
    std::vector<glm::vec3> out;
    const float max_radius = std::sqrt((1.f + kMargin) / (1.f - kMargin));
    for (int mesh = 0; mesh < 2; ++mesh) {
        const std::vector<skvk::SceneVertex> tris(s.vertices.begin() + (mesh ? 6 : 0), mesh ? s.vertices.end() : s.vertices.begin() + 6);
        glm::vec3 lo(1e30f), hi(-1e30f);
        float longest = 0.f;
        for (std::size_t k = 0; k < tris.size(); ++k) {
            lo = glm::min(lo, tris[k].position);
            hi = glm::max(hi, tris[k].position);
            longest = std::max(longest, glm::length(tris[k].position - tris[k - k % 3 + (k % 3 + 1) % 3].position));
        }
        int n = 1;
        if (tess > 0.f) {
            const float dist = glm::length(glm::clamp(s.light, lo, hi) - s.light);
            const shadowkit::OmniEdgeLengthResult ml = shadowkit::omni_paraboloid_max_edge_length(dist, kDp, tess, max_radius);
            REQUIRE(ml.status == shadowkit::Status::Ok);
            n = std::min(256, int(std::ceil(longest / ml.length)));
        }
        subdivide(tris, n, out);
    }
    triangles = out.size() / 3;
    return out;
}

// Nearest hit of the ray o + t d (d unit) on the floor quad or the box, or +inf.
float ray_scene(const skvk::BoxScene& s, glm::vec3 o, glm::vec3 d) {
    float best = std::numeric_limits<float>::infinity();
    if (d.y < 0.f) {
        const float t = -o.y / d.y;
        const glm::vec3 p = o + t * d;
        if (std::abs(p.x) <= s.ground_half && std::abs(p.z) <= s.ground_half) best = t;
    }
    const glm::vec3 lo = s.box_c - s.box_h, hi = s.box_c + s.box_h;
    float t0 = 0.f, t1 = best;
    for (int a = 0; a < 3; ++a) {
        if (std::abs(d[a]) < 1e-12f) {
            if (o[a] < lo[a] || o[a] > hi[a]) return best;
            continue;
        }
        float ta = (lo[a] - o[a]) / d[a], tb = (hi[a] - o[a]) / d[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    return t0 <= t1 ? t0 : best;
}

struct DpResult {
    skvk::Agreement agreement;
    std::size_t triangles = 0, map_texels = 0, map_off = 0;  ///< texels inside the disks; those outside their 3 x 3 bounds
    std::size_t map_hits[2] = {0, 0};                        ///< texels per layer whose ray hits a caster
    double map_median = 0.0;                                 ///< median |stored - ray cast| over the hits
};

struct DpShaders {
    std::vector<std::uint32_t> map_vs, map_fs, vs, fs;
    const char *map_vs_entry = "main", *map_fs_entry = "main", *vs_entry = "main", *fs_entry = "main";
};
DpShaders compile_dp(Source lang) {
    DpShaders s;
    const VkShaderStageFlagBits V = VK_SHADER_STAGE_VERTEX_BIT, F = VK_SHADER_STAGE_FRAGMENT_BIT;
    if (lang == Source::Glsl) {
        const std::string head = "#version 450 core\n" + skvk::read_text(std::string(SHADOWKIT_GLSL_DIR) + "/omni_shadow.glsl");
        s.map_vs = skvk::compile_checked(lang, V, head + "#define SK_MAP_VS 1\n" + kDpMapGlsl, "main", "omni.dp.glsl.map.vert");
        s.map_fs = skvk::compile_checked(lang, F, head + kDpMapGlsl, "main", "omni.dp.glsl.map.frag");
        s.vs = skvk::compile_checked(lang, V, skvk::receiver_glsl_vs(kDpParamsGlsl), "main", "omni.dp.glsl.vert");
        s.fs = skvk::compile_checked(lang, F, head + kDpParamsGlsl + skvk::kReceiverGlslFsIo + kDpReceiverGlsl, "main",
                                     "omni.dp.glsl.frag");
    } else {
        const std::string head = skvk::read_text(std::string(SHADOWKIT_HLSL_DIR) + "/omni_shadow.hlsl");
        s.map_vs = skvk::compile_checked(lang, V, head + kDpMapHlsl, "vs_map", "omni.dp.hlsl.map.vert");
        s.map_fs = skvk::compile_checked(lang, F, head + kDpMapHlsl, "ps_map", "omni.dp.hlsl.map.frag");
        const std::string receiver = kDpReceiverHlsl + std::string(skvk::kReceiverHlslVs) + skvk::kReceiverHlslTargets + kDpReceiverHlslPs;
        s.vs = skvk::compile_checked(lang, V, head + receiver, "vs_main", "omni.dp.hlsl.vert");
        s.fs = skvk::compile_checked(lang, F, head + receiver, "ps_receiver", "omni.dp.hlsl.frag");
        s.map_vs_entry = "vs_map";
        s.map_fs_entry = "ps_map";
        s.vs_entry = "vs_main";
        s.fs_entry = "ps_receiver";
    }
    return s;
}

// Every texel centre: its direction (omni_paraboloid_unproject) into the world, the nearest caster,
// expected = min(t / range, 1). The map's chords stay within `tess` = 1 texel of the curved images, so a
// texel inside a disk (r <= 1 - 4 texels) must hold a value between the smallest and the largest
// expected value of its 3 x 3 texels (a silhouette texel may hold either surface), +- 1e-5.
void check_map(const skvk::BoxScene& s, const glm::mat4& frame, float range, const std::vector<float> layers[2], DpResult& r) {
    const glm::mat3 to_world = glm::transpose(glm::mat3(frame));  // the frame's rotation is orthonormal
    std::vector<float> expect(std::size_t(kDp) * kDp);
    std::vector<float> diffs;
    for (int layer = 0; layer < 2; ++layer) {
        const auto h = layer == 0 ? shadowkit::OmniHemisphere::Front : shadowkit::OmniHemisphere::Back;
        auto xy_of = [](std::uint32_t i, std::uint32_t j) {
            return glm::vec2((float(i) + 0.5f) / float(kDp) * 2.f - 1.f, (float(j) + 0.5f) / float(kDp) * 2.f - 1.f);
        };
        for (std::uint32_t j = 0; j < kDp; ++j)
            for (std::uint32_t i = 0; i < kDp; ++i) {
                const shadowkit::OmniDirection od = shadowkit::omni_paraboloid_unproject(h, xy_of(i, j));
                REQUIRE(od.status == shadowkit::Status::Ok);
                expect[std::size_t(j) * kDp + i] = std::min(ray_scene(s, s.light, glm::normalize(to_world * od.direction)) / range, 1.f);
            }
        for (std::uint32_t j = 1; j + 1 < kDp; ++j)
            for (std::uint32_t i = 1; i + 1 < kDp; ++i) {
                if (glm::length(xy_of(i, j)) > 1.f - 8.f / float(kDp)) continue;
                const std::size_t k = std::size_t(j) * kDp + i;
                float lo = 2.f, hi = -1.f;
                for (int dj = -1; dj <= 1; ++dj)
                    for (int di = -1; di <= 1; ++di) {
                        const float e = expect[std::size_t(int(k) + dj * int(kDp) + di)];
                        lo = std::min(lo, e);
                        hi = std::max(hi, e);
                    }
                const float stored = layers[layer][k];
                ++r.map_texels;
                r.map_off += stored < lo - 1e-5f || stored > hi + 1e-5f;
                if (expect[k] < 1.f) {
                    ++r.map_hits[layer];
                    diffs.push_back(std::abs(stored - expect[k]));
                }
            }
    }
    REQUIRE(!diffs.empty());
    std::nth_element(diffs.begin(), diffs.begin() + std::ptrdiff_t(diffs.size() / 2), diffs.end());
    r.map_median = diffs[diffs.size() / 2];
}

DpResult run_dp(Source lang, float tess, int pcf, bool map_check) {
    skvk::Context& ctx = skvk::vk_test_context();
    skvk::Scope scope(ctx);
    const skvk::BoxScene scene;
    const glm::vec4 light(scene.light, 1.f);
    // the frame: light at the origin, the axis horizontal and perpendicular to the light-to-box direction
    const glm::vec3 to_box = scene.box_c - scene.light;
    const shadowkit::OmniParaboloidFrame fr =
        shadowkit::omni_paraboloid_frame(light, glm::normalize(glm::vec3(-to_box.z, 0.f, to_box.x)), {0.f, 1.f, 0.f});
    REQUIRE(fr.status == shadowkit::Status::Ok);
    float range = 0.f;
    for (int i = 0; i < 8; ++i) {
        const glm::vec3 c((i & 1) ? 3.f : -3.f, (i & 2) ? 1.1f : 0.f, (i & 4) ? 3.f : -3.f);
        range = std::max(range, glm::length(c - scene.light));
    }
    range *= 1.01f;
    DpResult out;
    const std::vector<glm::vec3> casters = dp_casters(scene, tess, out.triangles);
    const glm::mat4 cam = glm::perspectiveRH_ZO(0.9f, float(kW) / float(kH), 0.1f, 50.f) *
                          glm::lookAt(glm::vec3(0.f, 3.5f, 5.f), glm::vec3(0.f, 0.3f, 0.f), glm::vec3(0.f, 1.f, 0.f));
    const DpParams params{cam, fr.view, light, glm::vec4(range, float(kDp), tess, float(pcf)),
                          glm::vec4(1e-5f * range, 2.3841858e-7f, 0.f, 0.f)};  // the sample's storage terms (2^-22)
    const DpShaders sh = compile_dp(lang);

    skvk::Buffer& cvb = scope.own<skvk::Buffer>();
    skvk::Buffer& vb = scope.own<skvk::Buffer>();
    skvk::Buffer& ubo = scope.own<skvk::Buffer>();
    const auto ccount = static_cast<std::uint32_t>(casters.size()), vcount = static_cast<std::uint32_t>(scene.vertices.size());
    REQUIRE(skvk::make_buffer(ctx, sizeof(glm::vec3) * ccount, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, cvb));
    std::memcpy(cvb.mapped, casters.data(), sizeof(glm::vec3) * ccount);
    REQUIRE(skvk::make_buffer(ctx, sizeof(skvk::SceneVertex) * vcount, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, vb));
    std::memcpy(vb.mapped, scene.vertices.data(), sizeof(skvk::SceneVertex) * vcount);
    REQUIRE(skvk::make_buffer(ctx, sizeof(DpParams), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, ubo));
    std::memcpy(ubo.mapped, &params, sizeof params);

    // 1. both maps: distance / range, depth test LESS, cleared to 1, no culling, the other hemisphere clipped
    skvk::Image& maps = scope.own<skvk::Image>();
    REQUIRE(skvk::make_image(ctx, kDp, kDp, 2, VK_FORMAT_D32_SFLOAT,
                             VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                             maps, true));
    const VkImageLayout map_read = VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL;
    VkRenderPass map_rp = scope.keep(skvk::make_render_pass(ctx, {}, VK_FORMAT_D32_SFLOAT, map_read), vkDestroyRenderPass);
    VkFramebuffer map_fb[2];
    for (std::size_t l = 0; l < 2; ++l) map_fb[l] = scope.keep(skvk::make_framebuffer(ctx, map_rp, {maps.layer_views[l]}, kDp, kDp), vkDestroyFramebuffer);
    VkPipelineLayout map_layout = scope.keep(skvk::make_pipeline_layout(ctx, nullptr, sizeof(MapPush), VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT), vkDestroyPipelineLayout);
    skvk::PipelineDesc md;
    md.vs = sh.map_vs;
    md.fs = sh.map_fs;
    md.vs_entry = sh.map_vs_entry;
    md.fs_entry = sh.map_fs_entry;
    md.vertex_stride = sizeof(glm::vec3);
    md.attributes = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0}};
    VkPipeline map_pipe = scope.keep(skvk::make_pipeline_checked(ctx, md, map_layout, map_rp), vkDestroyPipeline);

    // 2. the receivers: V, world point and normal
    skvk::ReceiverTargets& rt = scope.own<skvk::ReceiverTargets>();
    skvk::make_receiver_targets(ctx, kW, kH, rt);
    VkSampler sampler = scope.keep(skvk::make_sampler(ctx, VK_FILTER_LINEAR, VK_COMPARE_OP_LESS_OR_EQUAL), vkDestroySampler);
    skvk::DescriptorSet& ds = scope.own<skvk::DescriptorSet>();
    skvk::make_lookup_set(ctx, lang, maps.view, map_read, sampler, ubo, ds);
    VkPipelineLayout layout = scope.keep(skvk::make_pipeline_layout(ctx, &ds), vkDestroyPipelineLayout);
    skvk::PipelineDesc pd = skvk::scene_pipeline(sh.vs, sh.fs, sh.vs_entry, sh.fs_entry);
    pd.color_count = 3;
    pd.cull = VK_CULL_MODE_BACK_BIT;
    VkPipeline pipe = scope.keep(skvk::make_pipeline_checked(ctx, pd, layout, rt.rp), vkDestroyPipeline);

    VkCommandBuffer cmd = skvk::begin_commands(ctx);
    VkClearValue far{}, zero{};
    far.depthStencil = {1.f, 0};
    for (int l = 0; l < 2; ++l) {  // layer 0 the front paraboloid (side +1), layer 1 the back (-1); a plain viewport
        const MapPush push{fr.view, light, glm::vec4(l == 0 ? 1.f : -1.f, range, kMargin, 0.f)};
        skvk::draw_pass(cmd, map_rp, map_fb[l], kDp, kDp, {far}, map_pipe, map_layout, nullptr, &push, cvb.buffer, ccount, false,
                        sizeof push, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT);
    }
    skvk::draw_pass(cmd, rt.rp, rt.fb, kW, kH, {zero, zero, zero, far}, pipe, layout, &ds.set, nullptr, vb.buffer, vcount, true);
    REQUIRE(skvk::submit_and_wait(ctx, cmd));

    out.agreement = skvk::receiver_agreement(ctx, rt, scene, light);
    if (map_check) {
        const std::vector<float> layers[2] = {skvk::read_image(ctx, maps, map_read, 1, 0), skvk::read_image(ctx, maps, map_read, 1, 1)};
        REQUIRE(layers[0].size() == std::size_t(kDp) * kDp);
        check_map(scene, fr.view, range, layers, out);
    }

    return out;
}

void check_dp(Source lang) {
    skvk::Context& ctx = skvk::vk_test_context();
    REQUIRE_MESSAGE(ctx.enabled.shaderClipDistance, "the map pass's clip distance needs the shaderClipDistance feature");
    const std::string name = std::string(lang == Source::Glsl ? "GLSL" : "HLSL") + " dual paraboloid " + std::to_string(kDp);
    double tess1 = 0.0;
    for (const auto& [tess, pcf] : {std::pair{1.f, 0}, std::pair{1.f, 1}, std::pair{0.f, 0}}) {
        const std::size_t before = skvk::message_count();
        const DpResult r = run_dp(lang, tess, pcf, pcf == 0);
        const std::string what = name + ", tess " + std::to_string(int(tess)) + (pcf ? ", 3 x 3 PCF" : ", 2 x 2 compare");
        INFO(what);
        MESSAGE(what << ": " << r.triangles << " caster triangles; compared " << r.agreement.compared << " (lit " << r.agreement.lit
                     << ", shadowed " << r.agreement.shadowed << "), agreement " << r.agreement.fraction());
        CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());
        CHECK(r.agreement.compared > int(kW * kH) / 4);
        CHECK(r.agreement.shadowed > r.agreement.compared / 50);
        if (r.map_texels) {
            MESSAGE("  maps against the per-texel ray cast: " << r.map_texels << " texels inside the disks (caster hits: front "
                                                              << r.map_hits[0] << ", back " << r.map_hits[1]
                                                              << "), median |stored - cast| over the hits " << r.map_median
                                                              << ", texels outside their 3 x 3 neighbours' range: " << r.map_off);
            CHECK(r.map_hits[0] > 10000);
            CHECK(r.map_hits[1] > 10000);
            if (tess > 0.f) CHECK(r.map_off <= r.map_texels / 10000);
            else CHECK(r.map_off > r.map_texels / 1000);  // the control: untessellated chords cut through the maps
        }
        if (tess > 0.f) {
            CHECK(r.agreement.fraction() >= 0.99);  // the GL test's budget: 1% misclassified
            if (pcf == 0) tess1 = r.agreement.fraction();
        } else {
            CHECK(r.agreement.fraction() < tess1);  // untessellated chords: worse
        }
    }
}

}  // namespace

TEST_CASE("omni_shadow.glsl's distance cube on Vulkan: compare, pcf and manual lookups agree with the ray cast") {
    check(Source::Glsl);
}

TEST_CASE("HLSL omni_shadow.hlsl's distance cube on Vulkan: compare, pcf and manual lookups agree with the ray cast") {
    check(Source::Hlsl);
}

// Reversed-Z: the faces drawn with omni_cube_matrices' [0, 1] reversed-Z matrices and the camera with
// a reversed-Z [0, 1] projection (depth cleared to 0, GREATER). The cube itself stores distance / range
// written by the fragment stage, whatever the projection's depth: its map pass keeps LESS and a clear
// of 1, and the lookups (which compare distances) take no reversed-Z parameter.
namespace {
void check_reversed(Source lang) {
    const char* names[3] = {"compare", "pcf 3 x 3", "manual (point sampler)"};
    for (int mode = 0; mode < 3; ++mode) {
        const std::size_t before = skvk::message_count();
        const skvk::Agreement a = run(lang, mode, true);
        const std::string name = std::string(lang == Source::Glsl ? "GLSL" : "HLSL") + " reversed-Z distance cube, " + names[mode];
        INFO(name);
        MESSAGE(name << ": compared " << a.compared << " (lit " << a.lit << ", shadowed " << a.shadowed << "), agreement "
                     << a.fraction());
        CHECK(a.compared > int(kW * kH) / 4);
        CHECK(a.shadowed > a.compared / 50);
        CHECK(a.fraction() >= 0.995);
        CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());
    }
}
}  // namespace

TEST_CASE("reversed-Z omni_shadow.glsl's distance cube on Vulkan: reversed faces and camera, lookups agree with the ray cast") {
    check_reversed(Source::Glsl);
}

TEST_CASE("HLSL reversed-Z omni_shadow.hlsl's distance cube on Vulkan: reversed faces and camera, lookups agree with the ray cast") {
    check_reversed(Source::Hlsl);
}

TEST_CASE("omni_shadow.glsl's dual-paraboloid maps on Vulkan: map pass against a per-texel ray cast, lookups against the ray cast") {
    check_dp(Source::Glsl);
}

TEST_CASE("HLSL omni_shadow.hlsl's dual-paraboloid maps on Vulkan: map pass against a per-texel ray cast, lookups against the ray cast") {
    check_dp(Source::Hlsl);
}
