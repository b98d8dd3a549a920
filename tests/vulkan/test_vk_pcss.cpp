// glsl/pcss.glsl and hlsl/pcss.hlsl RUN on Vulkan: sk_pcss on the synthetic 128 x 128 map of
// tests/gl/test_gl_soft_shadows.cpp (a floor at 0.95, blockers at 0.6 and 0.3, a strip at the near
// plane) against its CPU evaluation (pcf_reference.hpp's cpu_pcss: blocker search with nearest reads,
// linear depths, Poisson PCF with the emulated 2x2 compare) and its tolerance (at most 0.5% of the
// lookups off by more than 1e-4: a tap whose stored depth ties the receiver may flip), plus two stiff
// cases that must stay finite and in [0, 1]; the 2D functions read layer 1 of a two-layer
// VK_FORMAT_D32_SFLOAT array through 2D views, the array overloads the array view with layer = 1.0
// (layer 0 holds zeros). One image, two samplers: a point sampler for the blocker search and a
// comparison sampler (LESS_OR_EQUAL, linear) for the filter. Reversed-Z runs the same with
// SK_REVERSED_Z defined: the map stored as 1 - z (a perspective light's reversed window depth for the
// same planes), receivers at 1 - z with the plane's gradient negated, GREATER_OR_EQUAL, against the
// same (standard) reference.
#include <doctest/doctest.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "../gl/pcf_reference.hpp"
#include "vk_harness.hpp"
#include "vk_passes.hpp"

namespace {

using skvk::Source;
using skvk::compile_checked;
using skvk::read_text;
using namespace pcfref;

const char* kKernelGlsl = R"(
layout(set = 0, binding = 0) uniform sampler2DShadow u_sm;
layout(set = 0, binding = 1) uniform sampler2D u_depth;
layout(set = 0, binding = 2) uniform sampler2DArrayShadow u_sm_array;
layout(set = 0, binding = 3) uniform sampler2DArray u_depth_array;
layout(set = 0, binding = 4, std430) readonly buffer Lookups { vec4 lookup[]; };  // uvz, then dz_duv
layout(push_constant) uniform Case { float light_uv; float near_plane; float far_plane; float angle; float max_w; int taps; int array; } k;
layout(location = 0) out float o_value;
void main() {
    int i = int(gl_FragCoord.x);
    vec3 uvz = lookup[2 * i].xyz;
    vec2 g = lookup[2 * i + 1].xy;
    if (k.array == 0)
        o_value = sk_pcss(u_depth, u_sm, uvz, g, k.light_uv, k.near_plane, k.far_plane, k.taps, k.taps, k.angle, k.max_w);
    else
        o_value = sk_pcss(u_depth_array, u_sm_array, 1.0, uvz, g, k.light_uv, k.near_plane, k.far_plane, k.taps, k.taps,
                          k.angle, k.max_w);
}
)";
const char* kKernelHlsl = R"(
[[vk::binding(0, 0)]] Texture2D<float> u_map;
[[vk::binding(1, 0)]] Texture2DArray<float> u_maps;
[[vk::binding(2, 0)]] SamplerComparisonState u_cmp;
[[vk::binding(3, 0)]] SamplerState u_point;
[[vk::binding(4, 0)]] StructuredBuffer<float4> lookup;   // uvz, then dz_duv
struct Case { float light_uv; float near_plane; float far_plane; float angle; float max_w; int taps; int array; };
[[vk::push_constant]] ConstantBuffer<Case> k;
float ps_main(float4 position : SV_Position) : SV_Target0 {
    int i = int(position.x);
    float3 uvz = lookup[2 * i].xyz;
    float2 g = lookup[2 * i + 1].xy;
    if (k.array == 0)
        return sk_pcss(u_map, u_point, u_cmp, uvz, g, k.light_uv, k.near_plane, k.far_plane, k.taps, k.taps, k.angle, k.max_w);
    return sk_pcss(u_maps, u_point, u_cmp, 1.0, uvz, g, k.light_uv, k.near_plane, k.far_plane, k.taps, k.taps, k.angle,
                   k.max_w);
}
)";

struct CaseParams {
    float light_uv, near_plane, far_plane, angle, max_w;
    std::int32_t taps, array;
};

struct Lookup {
    glm::vec3 uvz;
    glm::vec2 g;
};

void run_pcss(Source lang, bool reversed = false) {
    skvk::Context& ctx = skvk::vk_test_context();
    skvk::Scope scope(ctx);
    const std::size_t messages_before = skvk::message_count();
    const auto disk = parse_poisson(read_text(std::string(SHADOWKIT_GLSL_DIR) + "/pcf.glsl"));
    REQUIRE(disk.size() == 64);
    std::vector<std::uint32_t> vs, fs;
    const char* vs_entry = "main";
    const char* fs_entry = "main";
    if (lang == Source::Glsl) {
        const std::string pcss = std::string(reversed ? "#define SK_REVERSED_Z 1\n" : "") +
                                 read_text(std::string(SHADOWKIT_GLSL_DIR) + "/pcss.glsl");
        vs = compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, skvk::kFullscreenGlsl, "main", "pcss.glsl.vert");
        fs = compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, "#version 450 core\n" + pcss + kKernelGlsl, "main",
                             reversed ? "pcss_rz.glsl.frag" : "pcss.glsl.frag");
    } else {
        const std::string pcss = std::string(reversed ? "#define SK_REVERSED_Z 1\n" : "") +
                                 read_text(std::string(SHADOWKIT_HLSL_DIR) + "/pcss.hlsl");
        vs = compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, pcss + skvk::kFullscreenHlsl + kKernelHlsl, "vs_main", "pcss.hlsl.vert");
        fs = compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, pcss + skvk::kFullscreenHlsl + kKernelHlsl, "ps_main",
                             reversed ? "pcss_rz.hlsl.frag" : "pcss.hlsl.frag");
        vs_entry = "vs_main";
        fs_entry = "ps_main";
    }

    // the GL test's map: a floor at 0.95, blockers at 0.6 and 0.3, a strip at 0.0 (the near plane)
    DepthTexture tex;
    tex.w = tex.h = 128;
    tex.d.assign(128 * 128, 0.95f);
    for (int y = 0; y < 128; ++y)
        for (int x = 0; x < 128; ++x) {
            float& d = tex.d[static_cast<std::size_t>(y * 128 + x)];
            if (x >= 30 && x < 60 && y >= 40 && y < 90) d = 0.6f;
            if (x >= 70 && x < 100 && y >= 20 && y < 60) d = 0.3f;
            if (x >= 100 && y >= 90 && y < 100) d = 0.0f;
        }
    std::vector<float> layers(128 * 128, 0.f);
    layers.insert(layers.end(), tex.d.begin(), tex.d.end());
    if (reversed)  // reversed-Z: a perspective light's reversed window depth is 1 - z (same planes)
        for (float& v : layers) v = 1.f - v;
    skvk::Image& map = scope.own<skvk::Image>();
    REQUIRE(skvk::make_image(ctx, 128, 128, 2, VK_FORMAT_D32_SFLOAT, VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT, map));
    const VkImageLayout map_read = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    REQUIRE(skvk::upload_image(ctx, map, layers, map_read));

    std::mt19937 rng(99);
    std::uniform_real_distribution<float> Uuv(0.05f, 0.95f), Ug(-0.3f, 0.3f);
    std::vector<Lookup> pts;
    for (int i = 0; i < 1024; ++i) {
        Lookup l{{Uuv(rng), Uuv(rng), i % 5 == 0 ? 0.7f : 0.94f}, {0.f, 0.f}};
        if (i % 2) l.g = {Ug(rng), Ug(rng)};
        if (i % 17 == 0) l.uvz.z = 0.f;  // receiver at the near plane
        pts.push_back(l);
    }
    const auto M = static_cast<std::uint32_t>(pts.size());
    skvk::Buffer& lookups = scope.own<skvk::Buffer>();
    REQUIRE(skvk::make_buffer(ctx, M * 2 * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, lookups));
    auto* dst = static_cast<glm::vec4*>(lookups.mapped);
    for (std::size_t i = 0; i < pts.size(); ++i) {
        dst[2 * i] = glm::vec4(pts[i].uvz, 0.f);
        dst[2 * i + 1] = glm::vec4(pts[i].g, 0.f, 0.f);
        if (reversed) {  // the receiver at 1 - z, its plane's gradient negated; the CPU reference stays standard
            dst[2 * i].z = 1.f - pts[i].uvz.z;
            dst[2 * i + 1] = -dst[2 * i + 1];
        }
    }

    VkSampler compare = scope.keep(
        skvk::make_sampler(ctx, VK_FILTER_LINEAR, reversed ? VK_COMPARE_OP_GREATER_OR_EQUAL : VK_COMPARE_OP_LESS_OR_EQUAL), vkDestroySampler);
    VkSampler point = scope.keep(skvk::make_sampler(ctx, VK_FILTER_NEAREST, VK_COMPARE_OP_NEVER), vkDestroySampler);
    skvk::DescriptorSet& ds = scope.own<skvk::DescriptorSet>();
    const VkShaderStageFlags frag = VK_SHADER_STAGE_FRAGMENT_BIT;
    const VkDescriptorType cis = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, img = VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE;
    if (lang == Source::Glsl) {  // one image, four combined image samplers: 2D / array views, compare / point
        REQUIRE(skvk::make_descriptor_set(ctx, {{0, cis, frag}, {1, cis, frag}, {2, cis, frag}, {3, cis, frag},
                                                {4, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, frag}}, ds));
        skvk::write_image(ctx, ds, 0, cis, map.layer_views[1], compare, map_read);
        skvk::write_image(ctx, ds, 1, cis, map.layer_views[1], point, map_read);
        skvk::write_image(ctx, ds, 2, cis, map.view, compare, map_read);
        skvk::write_image(ctx, ds, 3, cis, map.view, point, map_read);
    } else {  // two views and two samplers
        REQUIRE(skvk::make_descriptor_set(ctx, {{0, img, frag}, {1, img, frag}, {2, VK_DESCRIPTOR_TYPE_SAMPLER, frag},
                                                {3, VK_DESCRIPTOR_TYPE_SAMPLER, frag}, {4, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, frag}},
                                          ds));
        skvk::write_image(ctx, ds, 0, img, map.layer_views[1], VK_NULL_HANDLE, map_read);
        skvk::write_image(ctx, ds, 1, img, map.view, VK_NULL_HANDLE, map_read);
        skvk::write_sampler(ctx, ds, 2, compare);
        skvk::write_sampler(ctx, ds, 3, point);
    }
    skvk::write_buffer(ctx, ds, 4, lookups, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
    skvk::RowPass& row = scope.own<skvk::RowPass>();
    skvk::make_row_pass(ctx, vs, fs, vs_entry, fs_entry, ds, M, row, VK_FORMAT_R32_SFLOAT, 1, sizeof(CaseParams));

    struct Case {
        const char* name;
        double light_uv, n, f, max_w, angle;
        int taps;
        bool compare;  // compare with the CPU evaluation (else: only finiteness and range)
    };
    const Case cases[] = {
        {"light 0.2, 16 taps", 0.2, 1.0, 10.0, 0.05, 0.0, 16, true},
        {"light 0.2, 64 taps, rotated 1.1", 0.2, 1.0, 10.0, 0.05, 1.1, 64, true},
        {"light 1.0 (clamped filter)", 1.0, 1.0, 10.0, 0.03, 0.4, 32, true},
        {"light size 0", 0.0, 1.0, 10.0, 0.05, 0.0, 32, true},
        {"light 1e6: every search tap outside the map", 1e6, 1.0, 10.0, 0.05, 0.0, 32, true},
        {"near 1e-5, far 1e5: blocker depth -> 0", 0.5, 1e-5, 1e5, 0.05, 0.3, 32, false},
        {"infinite far plane", 0.2, 0.5, 0.0, 0.05, 0.3, 32, false},
    };
    for (int array = 0; array <= 1; ++array)
        for (const Case& c : cases) {
            const CaseParams cp{float(c.light_uv), float(c.n), float(c.f), float(c.angle), float(c.max_w), c.taps, array};
            const std::vector<float> gpu = skvk::draw_row(ctx, row, ds, &cp);
            REQUIRE(gpu.size() == pts.size());
            std::size_t off = 0, partial = 0, bad = 0;
            double max_err = 0;
            for (std::size_t i = 0; i < pts.size(); ++i) {
                if (!(gpu[i] >= 0.f && gpu[i] <= 1.f)) ++bad;  // NaN fails too
                if (gpu[i] > 0.01f && gpu[i] < 0.99f) ++partial;
                if (!c.compare) continue;
                const double cpu = cpu_pcss(tex, disk, glm::dvec3(pts[i].uvz), glm::dvec2(pts[i].g), c.light_uv, c.n, c.f, c.taps,
                                            c.angle, c.max_w);
                const double e = std::abs(double(gpu[i]) - cpu);
                max_err = std::max(max_err, e);
                if (e > 1e-4) ++off;
            }
            const std::string name = std::string(lang == Source::Glsl ? "GLSL " : "HLSL ") + (reversed ? "reversed-Z " : "") + c.name +
                                     (array ? " (array, layer 1)" : " (2D)");
            INFO(name);
            MESSAGE(name << ": " << partial << " partial lookups, " << off << " of " << M << " differ from the CPU by > 1e-4 (max "
                         << max_err << ")");
            CHECK(bad == 0);
            if (c.compare) CHECK(off <= pts.size() / 200);
        }
    CHECK_MESSAGE(skvk::message_count() == messages_before, skvk::messages());
}

}  // namespace

TEST_CASE("pcss.glsl on Vulkan: sk_pcss, 2D and array, equals its CPU evaluation on the synthetic map") {
    run_pcss(Source::Glsl);
}

TEST_CASE("HLSL pcss.hlsl on Vulkan: sk_pcss, 2D and array, equals its CPU evaluation on the synthetic map") {
    run_pcss(Source::Hlsl);
}

TEST_CASE("reversed-Z pcss.glsl on Vulkan: SK_REVERSED_Z, the map as 1 - z, GREATER_OR_EQUAL: equals the same CPU evaluation") {
    run_pcss(Source::Glsl, true);
}

TEST_CASE("HLSL reversed-Z pcss.hlsl on Vulkan: SK_REVERSED_Z, the map as 1 - z, GREATER_OR_EQUAL: equals the same evaluation") {
    run_pcss(Source::Hlsl, true);
}
