// glsl/pcf.glsl and hlsl/pcf.hlsl RUN on Vulkan: every kernel (box, tent, Poisson, rotated Poisson,
// hard), the 2D and the depth-array overloads, against the CPU emulation of
// tests/gl/test_gl_soft_shadows.cpp (pcf_reference.hpp: the same taps with the hardware 2x2 bilinear
// compare in double) with its tolerance (1e-5 on lavapipe / llvmpipe, 5e-3 on other drivers) and its
// exact check at texel centres. The map: a 64 x 64 VK_FORMAT_D32_SFLOAT array of two layers, layer 0
// all zeros (everything shadowed) and layer 1 the GL test's step edge and random field; the 2D
// kernels read layer 1 through a 2D view, the array kernels through the array view with layer = 1.0.
// The lookups come from a storage buffer, the kernel's settings from push constants; one pixel per
// lookup. Reversed-Z runs the same: the map stored as 1 - z, receivers at 1 - z with the plane's
// gradient negated, a GREATER_OR_EQUAL comparison sampler, against the same (standard) reference.
#include <doctest/doctest.h>

#include <glm/glm.hpp>

#include <cmath>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>
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
layout(set = 0, binding = 1) uniform sampler2DArrayShadow u_sm_array;
layout(set = 0, binding = 2, std430) readonly buffer Lookups { vec4 lookup[]; };  // uvz, then dz_duv
layout(push_constant) uniform Kernel { int kernel; int r; int taps; int array; float radius_uv; float angle; } k;
layout(location = 0) out float o_value;
void main() {
    int i = int(gl_FragCoord.x);
    vec3 uvz = lookup[2 * i].xyz;
    vec2 g = lookup[2 * i + 1].xy;
    if (k.array == 0) {
        if (k.kernel == 0) o_value = sk_pcf_box(u_sm, uvz, g, k.r);
        else if (k.kernel == 1) o_value = sk_pcf_tent(u_sm, uvz, g, k.r);
        else if (k.kernel == 2) o_value = sk_pcf_poisson(u_sm, uvz, g, k.radius_uv, k.taps, k.angle);
        else if (k.kernel == 3) o_value = sk_pcf_poisson_rotated(u_sm, uvz, g, k.radius_uv, k.taps);
        else o_value = sk_pcf_hard(u_sm, uvz);
    } else {
        if (k.kernel == 0) o_value = sk_pcf_box(u_sm_array, 1.0, uvz, g, k.r);
        else if (k.kernel == 1) o_value = sk_pcf_tent(u_sm_array, 1.0, uvz, g, k.r);
        else if (k.kernel == 2) o_value = sk_pcf_poisson(u_sm_array, 1.0, uvz, g, k.radius_uv, k.taps, k.angle);
        else if (k.kernel == 3) o_value = sk_pcf_poisson_rotated(u_sm_array, 1.0, uvz, g, k.radius_uv, k.taps);
        else o_value = sk_pcf_hard(u_sm_array, 1.0, uvz);
    }
}
)";
const char* kKernelHlsl = R"(
[[vk::binding(0, 0)]] Texture2D<float> u_sm;
[[vk::binding(1, 0)]] Texture2DArray<float> u_sm_array;
[[vk::binding(2, 0)]] StructuredBuffer<float4> lookup;   // uvz, then dz_duv
[[vk::binding(3, 0)]] SamplerComparisonState u_cmp;
struct Kernel { int kernel; int r; int taps; int array; float radius_uv; float angle; };
[[vk::push_constant]] ConstantBuffer<Kernel> k;
float ps_main(float4 position : SV_Position) : SV_Target0 {
    int i = int(position.x);
    float3 uvz = lookup[2 * i].xyz;
    float2 g = lookup[2 * i + 1].xy;
    if (k.array == 0) {
        if (k.kernel == 0) return sk_pcf_box(u_sm, u_cmp, uvz, g, k.r);
        if (k.kernel == 1) return sk_pcf_tent(u_sm, u_cmp, uvz, g, k.r);
        if (k.kernel == 2) return sk_pcf_poisson(u_sm, u_cmp, uvz, g, k.radius_uv, k.taps, k.angle);
        if (k.kernel == 3) return sk_pcf_poisson_rotated(u_sm, u_cmp, uvz, g, k.radius_uv, k.taps, position.xy);
        return sk_pcf_hard(u_sm, u_cmp, uvz);
    }
    if (k.kernel == 0) return sk_pcf_box(u_sm_array, u_cmp, 1.0, uvz, g, k.r);
    if (k.kernel == 1) return sk_pcf_tent(u_sm_array, u_cmp, 1.0, uvz, g, k.r);
    if (k.kernel == 2) return sk_pcf_poisson(u_sm_array, u_cmp, 1.0, uvz, g, k.radius_uv, k.taps, k.angle);
    if (k.kernel == 3) return sk_pcf_poisson_rotated(u_sm_array, u_cmp, 1.0, uvz, g, k.radius_uv, k.taps, position.xy);
    return sk_pcf_hard(u_sm_array, u_cmp, 1.0, uvz);
}
)";

struct KernelParams {
    std::int32_t kernel, r, taps, array;
    float radius_uv, angle;
};

struct KernelCase {
    const char* name;
    int kernel, r, taps;
    double radius_texels, angle;
};

struct Lookup {
    glm::vec3 uvz;
    glm::vec2 g;
};

void run_kernels(Source lang, bool reversed = false) {
    skvk::Context& ctx = skvk::vk_test_context();
    skvk::Scope scope(ctx);
    const std::size_t messages_before = skvk::message_count();
    const std::string glsl = read_text(std::string(SHADOWKIT_GLSL_DIR) + "/pcf.glsl");
    const auto disk = parse_poisson(glsl);  // the GLSL's taps: the HLSL must hold the same
    REQUIRE(disk.size() == 64);
    std::vector<std::uint32_t> vs, fs;
    const char* vs_entry = "main";
    const char* fs_entry = "main";
    if (lang == Source::Glsl) {
        vs = compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, skvk::kFullscreenGlsl, "main", "pcf.glsl.vert");
        fs = compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, "#version 450 core\n" + glsl + kKernelGlsl, "main",
                             reversed ? "pcf_rz.glsl.frag" : "pcf.glsl.frag");
    } else {
        const std::string hlsl = read_text(std::string(SHADOWKIT_HLSL_DIR) + "/pcf.hlsl");
        vs = compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, hlsl + skvk::kFullscreenHlsl + kKernelHlsl, "vs_main", "pcf.hlsl.vert");
        fs = compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, hlsl + skvk::kFullscreenHlsl + kKernelHlsl, "ps_main", "pcf.hlsl.frag");
        vs_entry = "vs_main";
        fs_entry = "ps_main";
    }

    // the GL test's map: left half a diagonal step edge (0.25 | 0.75), right half a random field
    DepthTexture tex;
    tex.w = tex.h = 64;
    std::mt19937 rng(1234);
    std::uniform_real_distribution<float> U(0.1f, 0.95f);
    tex.d.resize(64 * 64);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x)
            tex.d[static_cast<std::size_t>(y * 64 + x)] = x < 32 ? (2 * x + y < 70 ? 0.25f : 0.75f) : U(rng);
    std::vector<float> layers(64 * 64, 0.f);  // layer 0: zeros (a lookup of the wrong layer is shadowed)
    layers.insert(layers.end(), tex.d.begin(), tex.d.end());
    if (reversed)  // reversed-Z: window depth 1 - z (exact for the map's values), compare GREATER_OR_EQUAL
        for (float& v : layers) v = 1.f - v;
    skvk::Image& map = scope.own<skvk::Image>();
    REQUIRE(skvk::make_image(ctx, 64, 64, 2, VK_FORMAT_D32_SFLOAT, VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT, map));
    // uploaded, never rendered: SHADER_READ_ONLY (DEPTH_STENCIL_READ_ONLY needs attachment usage; the
    // validation layer caught that here)
    const VkImageLayout map_read = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    REQUIRE(skvk::upload_image(ctx, map, layers, map_read));

    // the GL test's lookups: random (half with a receiver-plane gradient), at texel centres, outside
    std::vector<Lookup> pts;
    std::uniform_real_distribution<float> Uuv(0.12f, 0.88f), Uz(0.2f, 0.85f), Ug(-1.f, 1.f);
    for (int i = 0; i < 768; ++i) {
        Lookup l{{Uuv(rng), Uuv(rng), Uz(rng)}, {0.f, 0.f}};
        if (i % 2) l.g = {Ug(rng), Ug(rng)};
        pts.push_back(l);
    }
    const std::size_t first_centre = pts.size();
    for (int i = 0; i < 192; ++i) {
        const int x = 8 + static_cast<int>(rng() % 48), y = 8 + static_cast<int>(rng() % 48);
        pts.push_back({{(float(x) + 0.5f) / 64.f, (float(y) + 0.5f) / 64.f, i % 2 ? 0.5f : Uz(rng)}, {0.f, 0.f}});
    }
    const std::size_t first_outside = pts.size();
    for (int i = 0; i < 64; ++i) {
        const float far_uv = 1.5f + 0.01f * float(i);
        pts.push_back({{i % 2 ? far_uv : -far_uv + 1.f, i % 3 ? 0.5f : far_uv, 0.99f}, {0.f, 0.f}});
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

    VkSampler sampler = scope.keep(
        skvk::make_sampler(ctx, VK_FILTER_LINEAR, reversed ? VK_COMPARE_OP_GREATER_OR_EQUAL : VK_COMPARE_OP_LESS_OR_EQUAL), vkDestroySampler);
    skvk::DescriptorSet& ds = scope.own<skvk::DescriptorSet>();
    const VkShaderStageFlags frag = VK_SHADER_STAGE_FRAGMENT_BIT;
    if (lang == Source::Glsl) {
        REQUIRE(skvk::make_descriptor_set(ctx, {{0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, frag},
                                                {1, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, frag},
                                                {2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, frag}}, ds));
        skvk::write_image(ctx, ds, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, map.layer_views[1], sampler, map_read);
        skvk::write_image(ctx, ds, 1, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, map.view, sampler, map_read);
    } else {
        REQUIRE(skvk::make_descriptor_set(ctx, {{0, VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, frag},
                                                {1, VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, frag},
                                                {2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, frag},
                                                {3, VK_DESCRIPTOR_TYPE_SAMPLER, frag}}, ds));
        skvk::write_image(ctx, ds, 0, VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, map.layer_views[1], VK_NULL_HANDLE, map_read);
        skvk::write_image(ctx, ds, 1, VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, map.view, VK_NULL_HANDLE, map_read);
        skvk::write_sampler(ctx, ds, 3, sampler);
    }
    skvk::write_buffer(ctx, ds, 2, lookups, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
    skvk::RowPass& row = scope.own<skvk::RowPass>();
    skvk::make_row_pass(ctx, vs, fs, vs_entry, fs_entry, ds, M, row, VK_FORMAT_R32_SFLOAT, 1, sizeof(KernelParams));

    const KernelCase cases[] = {
        {"box r=1", 0, 1, 0, 0, 0},          {"box r=2", 0, 2, 0, 0, 0},          {"box r=3", 0, 3, 0, 0, 0},
        {"tent r=1", 1, 1, 0, 0, 0},         {"tent r=3", 1, 3, 0, 0, 0},         {"poisson 16", 2, 0, 16, 4.0, 0.0},
        {"poisson 32 angle 0.7", 2, 0, 32, 3.0, 0.7}, {"poisson 64", 2, 0, 64, 5.0, 0.0},
        {"rotated 16", 3, 0, 16, 4.0, 0},    {"rotated 64", 3, 0, 64, 2.5, 0},    {"hard", 4, 0, 0, 0, 0},
    };
    const bool lavapipe = ctx.device_name.find("llvmpipe") != std::string::npos;
    for (int array = 0; array <= 1; ++array)
        for (const KernelCase& kc : cases) {
            const KernelParams kp{kc.kernel, kc.r, kc.taps, array, float(kc.radius_texels / 64.0), float(kc.angle)};
            const std::vector<float> gpu = skvk::draw_row(ctx, row, ds, &kp);
            REQUIRE(gpu.size() == pts.size());
            double max_err = 0, max_centre_err = 0;
            int partial = 0, outside_lit = 0;
            for (std::size_t i = 0; i < pts.size(); ++i) {
                const glm::dvec3 uvz(pts[i].uvz);
                const glm::dvec2 g(pts[i].g);
                double cpu = 0;
                switch (kc.kernel) {
                case 0: cpu = cpu_box(tex, uvz, g, kc.r, false); break;
                case 1: cpu = cpu_box(tex, uvz, g, kc.r, true); break;
                case 2: cpu = cpu_poisson(tex, disk, uvz, g, kc.radius_texels / 64.0, kc.taps, kc.angle); break;
                case 3:
                    cpu = cpu_poisson(tex, disk, uvz, g, kc.radius_texels / 64.0, kc.taps,
                                      6.28318531 * double(ign(float(i) + 0.5f, 0.5f)));
                    break;
                default: cpu = cpu_tap(tex, uvz, g, glm::dvec2(0)); break;
                }
                if (i >= first_outside) {
                    outside_lit += gpu[i] == 1.0f;  // all taps outside the map: lit, exactly
                    continue;
                }
                if (cpu > 0.02 && cpu < 0.98) ++partial;
                max_err = std::max(max_err, std::abs(double(gpu[i]) - cpu));
                if (i >= first_centre && kc.kernel == 0) {
                    const int n = (2 * kc.r + 1) * (2 * kc.r + 1);
                    const float exact = float(std::lround(cpu * n)) / float(n);
                    max_centre_err = std::max(max_centre_err, std::abs(double(gpu[i]) - double(exact)));
                }
            }
            const std::string name = std::string(lang == Source::Glsl ? "GLSL " : "HLSL ") + (reversed ? "reversed-Z " : "") + kc.name +
                                     (array ? " (array, layer 1)" : " (2D)");
            INFO(name);
            MESSAGE(name << ": max |GPU - CPU| = " << max_err << " over "
                    << first_outside << " lookups (" << partial << " strictly between 0 and 1)"
                    << (kc.kernel == 0 ? ", at texel centres " + std::to_string(max_centre_err) : std::string()));
            CHECK(partial > 50);
            CHECK(outside_lit == int(pts.size() - first_outside));
            CHECK(max_err < (lavapipe ? 1e-5 : 5e-3));
            if (kc.kernel == 0) CHECK(max_centre_err == 0.0);
        }
    CHECK_MESSAGE(skvk::message_count() == messages_before, skvk::messages());
}

}  // namespace

TEST_CASE("pcf.glsl on Vulkan: every kernel, 2D and array, equals the CPU emulation of the 2x2 compare") {
    run_kernels(Source::Glsl);
}

TEST_CASE("HLSL pcf.hlsl on Vulkan: every kernel, 2D and array, equals the CPU emulation of the 2x2 compare") {
    run_kernels(Source::Hlsl);
}

TEST_CASE("reversed-Z pcf.glsl on Vulkan: every kernel on the map stored as 1 - z, GREATER_OR_EQUAL, equals the same emulation") {
    run_kernels(Source::Glsl, true);
}

TEST_CASE("HLSL reversed-Z pcf.hlsl on Vulkan: every kernel on the map stored as 1 - z, GREATER_OR_EQUAL, equals the same emulation") {
    run_kernels(Source::Hlsl, true);
}
