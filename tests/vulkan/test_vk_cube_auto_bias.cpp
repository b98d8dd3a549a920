// glsl/shadow_map.glsl's and hlsl/shadow_map.hlsl's sk_cube_visibility_hardware_depth_auto RUN on Vulkan
// (lavapipe): the automatic bias on a point light's cube of hardware depth, on the GL test's closed-form
// cube (tests/cube_auto_scene.hpp: the room, the sphere, the light off centre, 8,192 receivers on the
// walls and the sphere, a third of them within two texels of a face seam) uploaded into a
// cube-compatible VK_FORMAT_D32_SFLOAT image, read through a LESS_OR_EQUAL comparison sampler with
// NEAREST and with LINEAR filtering. The same bounds as the GL test: no lit receiver shadowed (acne
// 0) and at most 0.5% misclassified against the exact ray test, with either filter; the control, the
// plain lookup with a constant window bias of 2e-6, acnes. No validation message.
#include <doctest/doctest.h>

#include <glm/glm.hpp>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "../cube_auto_scene.hpp"
#include "vk_harness.hpp"
#include "vk_passes.hpp"

namespace {

using skvk::Source;

const char* kGlsl = R"(
layout(set = 0, binding = 0) uniform samplerCubeShadow u_cube;
layout(set = 0, binding = 1, std430) readonly buffer Receivers { vec4 r[]; };  // position, normal
layout(push_constant) uniform Case { vec4 light; int mode; float bias_window; } k;  // mode 0 auto, 1 constant
layout(location = 0) out float o_value;
void main() {
    int i = int(gl_FragCoord.x);
    vec3 p = r[2 * i].xyz, n = r[2 * i + 1].xyz;
    o_value = k.mode == 0 ? sk_cube_visibility_hardware_depth_auto(u_cube, k.light, p, n, 0.1, 20.0, 0.0)
                          : sk_cube_visibility_hardware_depth(u_cube, k.light, p, 0.1, 20.0, k.bias_window);
}
)";
const char* kHlsl = R"(
[[vk::binding(0, 0)]] TextureCube<float> u_cube;
[[vk::binding(1, 0)]] StructuredBuffer<float4> r;
[[vk::binding(2, 0)]] SamplerComparisonState u_compare;
struct Case { float4 light; int mode; float bias_window; };
[[vk::push_constant]] ConstantBuffer<Case> k;
float ps_main(float4 position : SV_Position) : SV_Target0 {
    int i = int(position.x);
    float3 p = r[2 * i].xyz, n = r[2 * i + 1].xyz;
    return k.mode == 0 ? sk_cube_visibility_hardware_depth_auto(u_cube, u_compare, k.light, p, n, 0.1, 20.0, 0.0)
                       : sk_cube_visibility_hardware_depth(u_cube, u_compare, k.light, p, 0.1, 20.0, k.bias_window);
}
)";

struct CasePush {
    glm::vec4 light;
    std::int32_t mode;
    float bias_window;
};

struct Score {
    int acne = 0, leak = 0, wrong = 0, acne_wall = 0, acne_sphere = 0;
};

void run_cube_auto(Source lang) {
    skvk::Context& ctx = skvk::vk_test_context();
    skvk::Scope scope(ctx);
    const std::size_t before = skvk::message_count();
    const bool glsl = lang == Source::Glsl;
    std::vector<std::uint32_t> vs, fs;
    if (glsl) {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_GLSL_DIR) + "/shadow_map.glsl");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, skvk::kFullscreenGlsl, "main", "cube_auto.glsl.vert");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, "#version 450 core\n" + snippet + kGlsl, "main",
                                   "cube_auto.glsl.frag");
    } else {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_HLSL_DIR) + "/shadow_map.hlsl");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, snippet + skvk::kFullscreenHlsl + kHlsl, "vs_main", "cube_auto.hlsl.vert");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, snippet + skvk::kFullscreenHlsl + kHlsl, "ps_main", "cube_auto.hlsl.frag");
    }
    constexpr int n = 256;
    constexpr int M = 8192;
    const cube_auto::Receivers rc = cube_auto::make_receivers(M, n);
    REQUIRE(rc.used > M / 2);
    REQUIRE(rc.seam > 500);
    std::vector<glm::vec4> data(2 * M);
    for (std::size_t i = 0; i < std::size_t(M); ++i) {
        data[2 * i] = glm::vec4(rc.pts[4 * i], rc.pts[4 * i + 1], rc.pts[4 * i + 2], 1.f);
        data[2 * i + 1] = glm::vec4(rc.nrm[4 * i], rc.nrm[4 * i + 1], rc.nrm[4 * i + 2], 0.f);
    }
    skvk::Buffer& ssbo = scope.own<skvk::Buffer>();
    REQUIRE(skvk::make_buffer(ctx, data.size() * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, ssbo));
    std::memcpy(ssbo.mapped, data.data(), data.size() * sizeof(glm::vec4));
    skvk::Image& cube = scope.own<skvk::Image>();
    REQUIRE(skvk::make_image(ctx, n, n, 6, VK_FORMAT_D32_SFLOAT, VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT, cube,
                             false, true));
    const VkImageLayout read = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;  // uploaded, never rendered
    REQUIRE(skvk::upload_image(ctx, cube, cube_auto::cube_faces(n), read));
    VkSampler nearest = scope.keep(skvk::make_sampler(ctx, VK_FILTER_NEAREST, VK_COMPARE_OP_LESS_OR_EQUAL), vkDestroySampler);
    VkSampler linear = scope.keep(skvk::make_sampler(ctx, VK_FILTER_LINEAR, VK_COMPARE_OP_LESS_OR_EQUAL), vkDestroySampler);
    const VkShaderStageFlags frag = VK_SHADER_STAGE_FRAGMENT_BIT;
    const VkDescriptorType tex = skvk::texture_type(lang);
    std::vector<skvk::Binding> bindings = {{0, tex, frag}, {1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, frag}};
    if (!glsl) bindings.push_back({2, VK_DESCRIPTOR_TYPE_SAMPLER, frag});
    auto& sets = scope.own<std::array<skvk::DescriptorSet, 2>>();  // NEAREST, LINEAR
    for (int s = 0; s < 2; ++s) {
        const VkSampler smp = s == 0 ? nearest : linear;
        REQUIRE(skvk::make_descriptor_set(ctx, bindings, sets[s]));
        skvk::write_image(ctx, sets[s], 0, tex, cube.view, glsl ? smp : VK_NULL_HANDLE, read);
        skvk::write_buffer(ctx, sets[s], 1, ssbo, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
        if (!glsl) skvk::write_sampler(ctx, sets[s], 2, smp);
    }
    skvk::RowPass& row = scope.own<skvk::RowPass>();
    skvk::make_row_pass(ctx, vs, fs, glsl ? "main" : "vs_main", glsl ? "main" : "ps_main", sets[0], M, row, VK_FORMAT_R32_SFLOAT, 1,
                        sizeof(CasePush));

    auto run = [&](int mode, float bias_window, int filter) {
        const CasePush cp{glm::vec4(glm::vec3(cube_auto::kLight), 1.f), mode, bias_window};
        const std::vector<float> v = skvk::draw_row(ctx, row, sets[filter], &cp);
        Score s;
        for (std::size_t i = 0; i < std::size_t(M); ++i) {
            if (!rc.use[i]) continue;
            REQUIRE(std::isfinite(v[i]));
            if (rc.truth[i] == 1 && v[i] < 0.5f) {
                ++s.acne;
                ++(rc.kind[i] ? s.acne_sphere : s.acne_wall);
            }
            if (rc.truth[i] == 0 && v[i] > 0.5f) ++s.leak;
        }
        s.wrong = s.acne + s.leak;
        return s;
    };
    const Score a = run(0, 0.f, 0), al = run(0, 0.f, 1), small = run(1, 2e-6f, 1), large = run(1, 2e-4f, 1);
    MESSAGE((glsl ? "GLSL" : "HLSL") << " on Vulkan: " << rc.used << " receivers (" << rc.lit << " lit, " << rc.seam
                                     << " within two texels of a face seam): automatic bias acne " << a.acne << " (walls "
                                     << a.acne_wall << ", sphere " << a.acne_sphere << "), leak " << a.leak << " (LINEAR: acne "
                                     << al.acne << ", leak " << al.leak << "); constant window bias 2e-6: acne " << small.acne
                                     << " leak " << small.leak << "; 2e-4: acne " << large.acne << " leak " << large.leak);
    CHECK(a.acne == 0);
    CHECK(al.acne == 0);
    CHECK(double(a.wrong) / rc.used <= 0.005);
    CHECK(double(al.wrong) / rc.used <= 0.005);
    CHECK(small.acne > 0);  // the control: a small constant acnes at grazing walls
    CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());
}

}  // namespace

TEST_CASE("shadow_map.glsl on Vulkan: sk_cube_visibility_hardware_depth_auto, no acne on the closed-form cube, seams included") {
    run_cube_auto(Source::Glsl);
}

TEST_CASE("HLSL shadow_map.hlsl on Vulkan: sk_cube_visibility_hardware_depth_auto, no acne on the closed-form cube, seams included") {
    run_cube_auto(Source::Hlsl);
}
