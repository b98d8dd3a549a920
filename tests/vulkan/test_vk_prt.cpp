// glsl/prt.glsl and hlsl/prt.hlsl RUN on Vulkan: sk_prt_shade_vertex (transfer vectors from the
// snippet's storage buffer at binding 0, stride 25) and sk_prt_dot (the same vector copied into an
// array) for 512 random vertices and environments at every order (count 1, 4, 9, 16, 25), one pixel
// per vertex, against the dot product in double on the CPU (the closed form prt_shade_rgb computes):
// relative error below 1e-5, no validation message.
#include <doctest/doctest.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "vk_harness.hpp"
#include "vk_passes.hpp"

namespace {

using skvk::Source;

const char* kShadeGlsl = R"(
layout(set = 0, binding = 1, std140) uniform Env { vec3 env[25]; ivec4 count; } u;
layout(location = 0) out vec4 o_value;   // rgb: sk_prt_shade_vertex; a: sk_prt_dot's red
void main() {
    int index = int(gl_FragCoord.x);
    float t[25];
    for (int i = 0; i < 25; ++i) t[i] = sk_prt_transfer[index * 25 + i];
    vec3 a = sk_prt_shade_vertex(index, 25, u.count.x, u.env);
    vec3 b = sk_prt_dot(t, u.env, u.count.x);
    o_value = vec4(a, b.r);
}
)";
const char* kShadeHlsl = R"(
struct Env { float3 env[25]; int4 count; };
[[vk::binding(1, 0)]] ConstantBuffer<Env> u;
float4 ps_main(float4 position : SV_Position) : SV_Target0 {
    int index = int(position.x);
    float t[25];
    for (int i = 0; i < 25; ++i) t[i] = sk_prt_transfer[index * 25 + i];
    float3 a = sk_prt_shade_vertex(index, 25, u.count.x, u.env);
    float3 b = sk_prt_dot(t, u.env, u.count.x);
    return float4(a, b.r);
}
)";

struct EnvBlock {
    glm::vec4 env[25];  // std140 / HLSL constant-buffer vec3 arrays: 16-byte stride
    glm::ivec4 count;
};

void run_prt(Source lang) {
    skvk::Context& ctx = skvk::vk_test_context();
    skvk::Scope scope(ctx);
    const std::size_t before = skvk::message_count();
    std::vector<std::uint32_t> vs, fs;
    const char* vs_entry = "main";
    const char* fs_entry = "main";
    if (lang == Source::Glsl) {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_GLSL_DIR) + "/prt.glsl");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, skvk::kFullscreenGlsl, "main", "prt.glsl.vert");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, "#version 450 core\n" + snippet + kShadeGlsl, "main",
                                   "prt.glsl.frag");
    } else {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_HLSL_DIR) + "/prt.hlsl");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, snippet + skvk::kFullscreenHlsl + kShadeHlsl, "vs_main", "prt.hlsl.vert");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, snippet + skvk::kFullscreenHlsl + kShadeHlsl, "ps_main", "prt.hlsl.frag");
        vs_entry = "vs_main";
        fs_entry = "ps_main";
    }
    constexpr std::uint32_t M = 512;
    std::mt19937 rng(2002);
    std::uniform_real_distribution<float> U(-1.f, 1.f);
    std::vector<float> transfer(std::size_t(M) * 25);
    for (float& t : transfer) t = U(rng);
    skvk::Buffer& ssbo = scope.own<skvk::Buffer>();
    skvk::Buffer& ubo = scope.own<skvk::Buffer>();
    REQUIRE(skvk::make_buffer(ctx, transfer.size() * sizeof(float), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, ssbo));
    std::memcpy(ssbo.mapped, transfer.data(), transfer.size() * sizeof(float));
    REQUIRE(skvk::make_buffer(ctx, sizeof(EnvBlock), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, ubo));
    skvk::DescriptorSet& ds = scope.own<skvk::DescriptorSet>();
    REQUIRE(skvk::make_descriptor_set(ctx, {{0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_FRAGMENT_BIT},
                                            {1, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, VK_SHADER_STAGE_FRAGMENT_BIT}}, ds));
    skvk::write_buffer(ctx, ds, 0, ssbo, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
    skvk::write_buffer(ctx, ds, 1, ubo);
    skvk::RowPass& row = scope.own<skvk::RowPass>();
    skvk::make_row_pass(ctx, vs, fs, vs_entry, fs_entry, ds, M, row, VK_FORMAT_R32G32B32A32_SFLOAT, 4);

    for (int order = 1; order <= 5; ++order) {
        EnvBlock env{};
        for (auto& e : env.env) e = glm::vec4(U(rng), U(rng), U(rng), 0.f);
        env.count = glm::ivec4(order * order, 0, 0, 0);
        std::memcpy(ubo.mapped, &env, sizeof env);
        const std::vector<float> gpu = skvk::draw_row(ctx, row, ds);
        double max_rel = 0;
        for (std::uint32_t v = 0; v < M; ++v) {
            glm::dvec3 cpu(0.0);
            double scale = 0;
            for (int i = 0; i < order * order; ++i) {
                const double t = transfer[std::size_t(v) * 25 + std::size_t(i)];
                cpu += t * glm::dvec3(env.env[i]);
                scale += std::abs(t) * glm::length(glm::dvec3(env.env[i]));
            }
            for (int c = 0; c < 3; ++c)
                max_rel = std::max(max_rel, std::abs(double(gpu[v * 4 + std::uint32_t(c)]) - cpu[c]) / std::max(scale, 1e-30));
            max_rel = std::max(max_rel, std::abs(double(gpu[v * 4 + 3]) - cpu.x) / std::max(scale, 1e-30));
        }
        MESSAGE((lang == Source::Glsl ? "GLSL" : "HLSL") << " order " << order << ": max |GPU - CPU| / sum |t||L| = " << max_rel);
        CHECK(max_rel < 1e-5);
    }
    CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());
}

}  // namespace

TEST_CASE("prt.glsl on Vulkan: sk_prt_shade_vertex and sk_prt_dot equal the CPU dot product at every order") {
    run_prt(Source::Glsl);
}

TEST_CASE("HLSL prt.hlsl on Vulkan: sk_prt_shade_vertex and sk_prt_dot equal the CPU dot product at every order") {
    run_prt(Source::Hlsl);
}
