// glsl/cascades.glsl's and hlsl/cascades.hlsl's SDSM reduction RUN on Vulkan (lavapipe), as
// tests/gl/test_gl_sdsm_reduction.cpp runs it on GL: sk_sdsm_reduce_depth on a VK_FORMAT_D32_SFLOAT
// depth image, then sk_sdsm_reduce_minmax level by level (R32G32_SFLOAT targets) down to 1x1, against
// the CPU min/max of the same non-background depths, which must be EQUAL (min and max are exact in
// float; texelFetch / Load of a D32 / RG32F texel returns the stored float). Odd sizes (partial blocks
// at the edges), blocks of 2 to 16, background 1.0 and 0.0 (reversed-Z), one receiver in the far
// corner, and an all-background buffer (the empty marker). Then the second reduction
// (sk_sdsm_reduce_bounds, sk_sdsm_reduce_bounds_level: four RGBA32F targets per level) against the
// CPU's per-cascade light-space bounds (double, pixels within 1e-3 of a split left out), within 1e-3
// world units, as the GL test. No validation message.
#include <doctest/doctest.h>

#include <shadowkit/cascades.hpp>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "vk_harness.hpp"
#include "vk_passes.hpp"

namespace {

using skvk::Source;

const char* kFirstGlsl = R"(
layout(set = 0, binding = 0) uniform sampler2D u_src;
layout(push_constant) uniform Step { int block; float background; } k;
layout(location = 0) out vec2 o_minmax;
void main() { o_minmax = sk_sdsm_reduce_depth(u_src, ivec2(gl_FragCoord.xy), k.block, k.background); }
)";
const char* kNextGlsl = R"(
layout(set = 0, binding = 0) uniform sampler2D u_src;
layout(push_constant) uniform Step { int block; float background; } k;
layout(location = 0) out vec2 o_minmax;
void main() { o_minmax = sk_sdsm_reduce_minmax(u_src, ivec2(gl_FragCoord.xy), k.block); }
)";
const char* kHlsl = R"(
[[vk::binding(0, 0)]] Texture2D<float> u_depth;
[[vk::binding(0, 0)]] Texture2D<float2> u_level;
struct Step { int block; float background; };
[[vk::push_constant]] ConstantBuffer<Step> k;
float2 ps_first(float4 position : SV_Position) : SV_Target0 {
    return sk_sdsm_reduce_depth(u_depth, int2(position.xy), k.block, k.background);
}
float2 ps_next(float4 position : SV_Position) : SV_Target0 {
    return sk_sdsm_reduce_minmax(u_level, int2(position.xy), k.block);
}
)";

// The second reduction: four RGBA32F targets per level (one per cascade).
const char* kBoundsFirstGlsl = R"(
layout(set = 0, binding = 0) uniform sampler2D u_src;
layout(set = 0, binding = 1, std140) uniform Bounds { mat4 clip_to_world; mat4 world_to_view; mat4 world_to_light;
                                                       vec4 split_far; int count; } u;
layout(location = 0) out vec4 o_b0;
layout(location = 1) out vec4 o_b1;
layout(location = 2) out vec4 o_b2;
layout(location = 3) out vec4 o_b3;
void main() {
    vec4 b[4];
    sk_sdsm_reduce_bounds(u_src, ivec2(gl_FragCoord.xy), 4, 1.0, u.clip_to_world, u.world_to_view, u.world_to_light,
                          u.split_far, u.count, true, b);
    o_b0 = b[0]; o_b1 = b[1]; o_b2 = b[2]; o_b3 = b[3];
}
)";
const char* kBoundsNextGlsl = R"(
layout(set = 0, binding = 2) uniform sampler2D u_l[4];
layout(location = 0) out vec4 o_b0;
layout(location = 1) out vec4 o_b1;
layout(location = 2) out vec4 o_b2;
layout(location = 3) out vec4 o_b3;
void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    o_b0 = sk_sdsm_reduce_bounds_level(u_l[0], p, 4);
    o_b1 = sk_sdsm_reduce_bounds_level(u_l[1], p, 4);
    o_b2 = sk_sdsm_reduce_bounds_level(u_l[2], p, 4);
    o_b3 = sk_sdsm_reduce_bounds_level(u_l[3], p, 4);
}
)";
const char* kBoundsHlsl = R"(
struct Bounds {
    column_major float4x4 clip_to_world; column_major float4x4 world_to_view; column_major float4x4 world_to_light;
    float4 split_far; int count;
};
[[vk::binding(0, 0)]] Texture2D<float> u_src;
[[vk::binding(1, 0)]] ConstantBuffer<Bounds> u;
[[vk::binding(2, 0)]] Texture2D<float4> u_l[4];
struct Out {
    float4 b0 : SV_Target0;
    float4 b1 : SV_Target1;
    float4 b2 : SV_Target2;
    float4 b3 : SV_Target3;
};
Out ps_first(float4 position : SV_Position) {
    float4 b[4];
    sk_sdsm_reduce_bounds(u_src, int2(position.xy), 4, 1.0, u.clip_to_world, u.world_to_view, u.world_to_light, u.split_far,
                          u.count, true, b);
    Out o;
    o.b0 = b[0]; o.b1 = b[1]; o.b2 = b[2]; o.b3 = b[3];
    return o;
}
Out ps_next(float4 position : SV_Position) {
    int2 p = int2(position.xy);
    Out o;
    o.b0 = sk_sdsm_reduce_bounds_level(u_l[0], p, 4);
    o.b1 = sk_sdsm_reduce_bounds_level(u_l[1], p, 4);
    o.b2 = sk_sdsm_reduce_bounds_level(u_l[2], p, 4);
    o.b3 = sk_sdsm_reduce_bounds_level(u_l[3], p, 4);
    return o;
}
)";

struct StepPush {
    std::int32_t block;
    float background;
};

// The two reduction pipelines of one language (render pass: one RG32F target).
struct Reducer {
    skvk::Context& ctx;
    Source lang;
    skvk::Scope scope;  ///< everything below; declared first, so destroyed last
    VkRenderPass rp = VK_NULL_HANDLE;
    VkSampler nearest = VK_NULL_HANDLE;
    VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VkPipeline first = VK_NULL_HANDLE, next = VK_NULL_HANDLE;
    skvk::DescriptorSet& proto = scope.own<skvk::DescriptorSet>();  // owns set_layout

    Reducer(skvk::Context& c, Source l) : ctx(c), lang(l), scope(c) {
        const bool glsl = lang == Source::Glsl;
        std::vector<std::uint32_t> vs, fs0, fs1;
        if (glsl) {
            const std::string snippet = skvk::read_text(std::string(SHADOWKIT_GLSL_DIR) + "/cascades.glsl");
            vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, skvk::kFullscreenGlsl, "main", "sdsm.glsl.vert");
            fs0 = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, "#version 450 core\n" + snippet + kFirstGlsl, "main",
                                        "sdsm.glsl.first.frag");
            fs1 = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, "#version 450 core\n" + snippet + kNextGlsl, "main",
                                        "sdsm.glsl.next.frag");
        } else {
            const std::string snippet = skvk::read_text(std::string(SHADOWKIT_HLSL_DIR) + "/cascades.hlsl");
            vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, snippet + skvk::kFullscreenHlsl + kHlsl, "vs_main", "sdsm.hlsl.vert");
            fs0 = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, snippet + skvk::kFullscreenHlsl + kHlsl, "ps_first", "sdsm.hlsl.first.frag");
            fs1 = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, snippet + skvk::kFullscreenHlsl + kHlsl, "ps_next", "sdsm.hlsl.next.frag");
        }
        rp = scope.keep(skvk::make_render_pass(ctx, {VK_FORMAT_R32G32_SFLOAT}, VK_FORMAT_UNDEFINED, VK_IMAGE_LAYOUT_UNDEFINED),
                        vkDestroyRenderPass);
        nearest = scope.keep(skvk::make_sampler(ctx, VK_FILTER_NEAREST, VK_COMPARE_OP_NEVER), vkDestroySampler);
        REQUIRE(skvk::make_descriptor_set(ctx, {{0, texture_type(), VK_SHADER_STAGE_FRAGMENT_BIT}}, proto));
        layout = scope.keep(skvk::make_pipeline_layout(ctx, &proto, sizeof(StepPush), VK_SHADER_STAGE_FRAGMENT_BIT), vkDestroyPipelineLayout);
        skvk::PipelineDesc pd;
        pd.vs = vs;
        pd.vs_entry = glsl ? "main" : "vs_main";
        pd.depth_test = pd.depth_write = false;
        pd.color_count = 1;
        pd.fs = fs0;
        pd.fs_entry = glsl ? "main" : "ps_first";
        first = scope.keep(skvk::make_pipeline_checked(ctx, pd, layout, rp), vkDestroyPipeline);
        pd.fs = fs1;
        pd.fs_entry = glsl ? "main" : "ps_next";
        next = scope.keep(skvk::make_pipeline_checked(ctx, pd, layout, rp), vkDestroyPipeline);
    }
    Reducer(const Reducer&) = delete;
    Reducer& operator=(const Reducer&) = delete;
    VkDescriptorType texture_type() const {
        return skvk::texture_type(lang);
    }

    // All passes over the w x h depths in one command buffer; the 1x1 level's (min, max).
    glm::vec2 reduce(const std::vector<float>& d, std::uint32_t w, std::uint32_t h, int block, float background) {
        const VkImageLayout read = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
        skvk::Scope local(ctx);  // this call's images, framebuffers and sets
        skvk::Image& depth = local.own<skvk::Image>();
        REQUIRE(skvk::make_image(ctx, w, h, 1, VK_FORMAT_D32_SFLOAT, VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT, depth));
        REQUIRE(skvk::upload_image(ctx, depth, d, read));
        auto& levels = local.own<std::vector<skvk::Image>>();
        std::vector<VkFramebuffer> fbs;
        auto& sets = local.own<std::vector<skvk::DescriptorSet>>();
        levels.reserve(16);
        sets.reserve(16);
        const auto b = static_cast<std::uint32_t>(block);
        while (levels.empty() || w > 1 || h > 1) {
            w = (w + b - 1) / b;
            h = (h + b - 1) / b;
            levels.emplace_back();
            REQUIRE(skvk::make_image(ctx, w, h, 1, VK_FORMAT_R32G32_SFLOAT,
                                     VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                                     levels.back()));
            fbs.push_back(local.keep(skvk::make_framebuffer(ctx, rp, {levels.back().view}, w, h), vkDestroyFramebuffer));
            sets.emplace_back();
            REQUIRE(skvk::make_descriptor_set(ctx, {{0, texture_type(), VK_SHADER_STAGE_FRAGMENT_BIT}}, sets.back()));
            const VkImageView src = levels.size() == 1 ? depth.view : levels[levels.size() - 2].view;
            skvk::write_image(ctx, sets.back(), 0, texture_type(), src, lang == Source::Glsl ? nearest : VK_NULL_HANDLE, read);
        }
        VkCommandBuffer cmd = skvk::begin_commands(ctx);
        const StepPush push{block, background};
        VkClearValue zero{};
        for (std::size_t i = 0; i < levels.size(); ++i) {
            skvk::draw_pass(cmd, rp, fbs[i], levels[i].width, levels[i].height, {zero}, i == 0 ? first : next, layout, &sets[i].set,
                            &push, VK_NULL_HANDLE, 3, false, sizeof push, VK_SHADER_STAGE_FRAGMENT_BIT);
            if (i + 1 < levels.size()) skvk::transition(cmd, levels[i], VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, read);
        }
        REQUIRE(skvk::submit_and_wait(ctx, cmd));
        const std::vector<float> out = skvk::read_image(ctx, levels.back(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 2);
        REQUIRE(out.size() == 2);
        return {out[0], out[1]};
    }
};

// CPU reference: min and max of the values that are not `background`; the empty marker without any.
glm::vec2 cpu_minmax(const std::vector<float>& d, float background) {
    glm::vec2 r(shadowkit::kCascadeSdsmEmptyMin, shadowkit::kCascadeSdsmEmptyMax);
    for (float v : d)
        if (v != background) r = glm::vec2(std::min(r.x, v), std::max(r.y, v));
    return r;
}

void check_minmax(Source lang) {
    skvk::Context& ctx = skvk::vk_test_context();
    const std::size_t before = skvk::message_count();
    Reducer red(ctx, lang);
    std::mt19937 rng(25);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const std::uint32_t sizes[][2] = {{301, 173}, {64, 64}, {1, 1}, {17, 1}, {1000, 3}, {513, 257}};
    int cases = 0, equal = 0;
    for (const auto& s : sizes)
        for (int block : {2, 4, 8, 16})
            for (float background : {1.0f, 0.0f}) {
                std::vector<float> d(static_cast<std::size_t>(s[0]) * s[1]);
                const float lo = 0.2f * u(rng), hi = 0.8f + 0.2f * u(rng);
                for (float& v : d) v = u(rng) < 0.3f ? background : lo + (hi - lo) * u(rng);
                d[0] = 0.5f;  // at least one receiver
                const glm::vec2 g = red.reduce(d, s[0], s[1], block, background);
                const glm::vec2 c = cpu_minmax(d, background);
                INFO((lang == Source::Glsl ? "GLSL" : "HLSL") << " size " << s[0] << "x" << s[1] << " block " << block
                                                              << " background " << background);
                CHECK(g.x == c.x);
                CHECK(g.y == c.y);
                equal += g == c;
                ++cases;
            }
    CHECK(cases == 48);
    // one receiver in the far corner (the last partial block of every level), then nothing but background
    std::vector<float> d(250 * 131, 1.0f);
    d.back() = 0.123456789f;
    glm::vec2 g = red.reduce(d, 250, 131, 8, 1.0f);
    CHECK(g.x == 0.123456789f);
    CHECK(g.y == 0.123456789f);
    std::fill(d.begin(), d.end(), 1.0f);
    g = red.reduce(d, 250, 131, 8, 1.0f);
    CHECK(g.x == shadowkit::kCascadeSdsmEmptyMin);
    CHECK(g.y == shadowkit::kCascadeSdsmEmptyMax);
    MESSAGE((lang == Source::Glsl ? "GLSL" : "HLSL") << " on Vulkan: " << equal << " of " << cases
                                                     << " random depth buffers reduce to the CPU's min and max exactly");
    CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());
}

struct BoundsUbo {
    glm::mat4 clip_to_world, world_to_view, world_to_light;
    glm::vec4 split_far;
    std::int32_t count;
    std::int32_t pad[3];
};

// The CPU side as the GL test builds it, for a [0, 1] clip-depth camera (glm::perspectiveRH_ZO).
struct BoundsScene {
    std::uint32_t w = 203, h = 117;
    std::vector<float> d;
    glm::dvec4 cpu[4];
    BoundsUbo ubo{};
    shadowkit::CascadeSdsmInput in;
    int used[4] = {0, 0, 0, 0};
    BoundsScene() {
        const double n = 0.5, f = 50.0;
        const glm::mat4 V = glm::lookAt(glm::vec3(3, 2, 5), glm::vec3(0, 0, -10), glm::vec3(0, 1, 0));
        const glm::mat4 P = glm::perspectiveRH_ZO(0.9f, float(w) / float(h), float(n), float(f));
        in.camera.camera_view = V;
        in.camera.camera_proj = P;
        in.camera.camera_depth = shadowkit::ClipDepth::ZeroToOne;
        in.camera.light_position = glm::vec4(glm::normalize(glm::vec3(-0.85f, 0.5f, -0.15f)), 0.0f);
        in.view_min = 1.0f;
        in.view_max = 40.0f;
        const shadowkit::CascadeSdsmResult sp = shadowkit::cascade_sdsm_splits(in, nullptr);
        REQUIRE(sp.status == shadowkit::Status::Ok);
        const shadowkit::CascadeSdsmLightView lv = shadowkit::cascade_sdsm_light_view(in.camera.light_position);
        REQUIRE(lv.status == shadowkit::Status::Ok);
        const glm::dmat4 c2wd = glm::inverse(glm::dmat4(P) * glm::dmat4(V)), Vd(V), Ld(lv.view);
        ubo = BoundsUbo{glm::mat4(c2wd), V, lv.view, glm::vec4(sp.splits[1], sp.splits[2], sp.splits[3], sp.splits[4]), 4, {0, 0, 0}};
        std::mt19937 rng(99);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        d.assign(std::size_t(w) * h, 1.0f);
        for (glm::dvec4& b : cpu) b = glm::dvec4(1e300, 1e300, -1e300, -1e300);
        for (std::uint32_t y = 0; y < h; ++y)
            for (std::uint32_t x = 0; x < w; ++x) {
                float& dv = d[std::size_t(y) * w + x];
                if (u(rng) < 0.33) continue;
                const double z = std::pow(40.0, u(rng));  // view depth
                dv = static_cast<float>(f / (f - n) - f * n / ((f - n) * z));  // perspectiveRH_ZO's window depth
                const glm::dvec4 hw = c2wd * glm::dvec4((x + 0.5) / w * 2.0 - 1.0, (y + 0.5) / h * 2.0 - 1.0, double(dv), 1.0);
                const glm::dvec4 pw(glm::dvec3(hw) / hw.w, 1.0);
                const double vd = -(Vd * pw).z;
                bool near_split = false;
                int c = 3;
                for (int i = 3; i >= 0; --i) {
                    near_split = near_split || std::fabs(vd - double(sp.splits[i + 1])) < 1e-3 * vd;
                    if (vd <= double(sp.splits[i + 1])) c = i;
                }
                if (near_split) {
                    dv = 1.0f;
                    continue;
                }
                const glm::dvec4 l = Ld * pw;
                cpu[c] = glm::dvec4(std::min(cpu[c].x, l.x), std::min(cpu[c].y, l.y), std::max(cpu[c].z, l.x), std::max(cpu[c].w, l.y));
                ++used[c];
            }
    }
};

void check_bounds(Source lang) {
    skvk::Context& ctx = skvk::vk_test_context();
    skvk::Scope scope(ctx);
    const std::size_t before = skvk::message_count();
    const bool glsl = lang == Source::Glsl;
    const BoundsScene sc;
    for (int c = 0; c < 4; ++c) REQUIRE(sc.used[c] > 10);
    std::vector<std::uint32_t> vs, fs0, fs1;
    if (glsl) {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_GLSL_DIR) + "/cascades.glsl");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, skvk::kFullscreenGlsl, "main", "sdsm_bounds.glsl.vert");
        fs0 = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, "#version 450 core\n" + snippet + kBoundsFirstGlsl, "main",
                                    "sdsm_bounds.glsl.first.frag");
        fs1 = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, "#version 450 core\n" + snippet + kBoundsNextGlsl, "main",
                                    "sdsm_bounds.glsl.next.frag");
    } else {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_HLSL_DIR) + "/cascades.hlsl");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, snippet + skvk::kFullscreenHlsl + kBoundsHlsl, "vs_main", "sdsm_bounds.hlsl.vert");
        fs0 = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, snippet + skvk::kFullscreenHlsl + kBoundsHlsl, "ps_first", "sdsm_bounds.hlsl.first.frag");
        fs1 = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, snippet + skvk::kFullscreenHlsl + kBoundsHlsl, "ps_next", "sdsm_bounds.hlsl.next.frag");
    }
    const VkFormat rgba = VK_FORMAT_R32G32B32A32_SFLOAT;
    VkRenderPass rp =
        scope.keep(skvk::make_render_pass(ctx, {rgba, rgba, rgba, rgba}, VK_FORMAT_UNDEFINED, VK_IMAGE_LAYOUT_UNDEFINED), vkDestroyRenderPass);
    VkSampler nearest = scope.keep(skvk::make_sampler(ctx, VK_FILTER_NEAREST, VK_COMPARE_OP_NEVER), vkDestroySampler);
    const VkDescriptorType tex = skvk::texture_type(lang);
    const VkShaderStageFlags frag = VK_SHADER_STAGE_FRAGMENT_BIT;
    // binding 2 is an array of four: one Binding per element is not what the layout needs, so the
    // next levels use their own set layout below
    const std::vector<skvk::Binding> first_bindings = {{0, tex, frag}, {1, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, frag}};
    skvk::Buffer& ubo = scope.own<skvk::Buffer>();
    REQUIRE(skvk::make_buffer(ctx, sizeof(BoundsUbo), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, ubo));
    std::memcpy(ubo.mapped, &sc.ubo, sizeof sc.ubo);
    const VkImageLayout read = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    skvk::Image& depth = scope.own<skvk::Image>();
    REQUIRE(skvk::make_image(ctx, sc.w, sc.h, 1, VK_FORMAT_D32_SFLOAT, VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT, depth));
    REQUIRE(skvk::upload_image(ctx, depth, sc.d, read));

    // set layout of the next levels: binding 2, four textures
    VkDescriptorSetLayoutBinding lb{2, tex, 4, frag, nullptr};
    VkDescriptorSetLayoutCreateInfo lci{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    lci.bindingCount = 1;
    lci.pBindings = &lb;
    VkDescriptorSetLayout next_layout = VK_NULL_HANDLE;
    REQUIRE(vkCreateDescriptorSetLayout(ctx.device, &lci, nullptr, &next_layout) == VK_SUCCESS);
    scope.keep(next_layout, vkDestroyDescriptorSetLayout);
    VkDescriptorPoolSize ps{tex, 4 * 16};
    VkDescriptorPoolCreateInfo pci{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    pci.maxSets = 16;
    pci.poolSizeCount = 1;
    pci.pPoolSizes = &ps;
    VkDescriptorPool pool = VK_NULL_HANDLE;
    REQUIRE(vkCreateDescriptorPool(ctx.device, &pci, nullptr, &pool) == VK_SUCCESS);
    scope.keep(pool, vkDestroyDescriptorPool);  // frees the next levels' sets with it

    skvk::DescriptorSet& first_set = scope.own<skvk::DescriptorSet>();
    REQUIRE(skvk::make_descriptor_set(ctx, first_bindings, first_set));
    skvk::write_image(ctx, first_set, 0, tex, depth.view, glsl ? nearest : VK_NULL_HANDLE, read);
    skvk::write_buffer(ctx, first_set, 1, ubo);
    VkPipelineLayout layouts[2] = {VK_NULL_HANDLE, VK_NULL_HANDLE};
    VkPipeline pipes[2] = {VK_NULL_HANDLE, VK_NULL_HANDLE};
    for (int k = 0; k < 2; ++k) {
        layouts[k] = scope.keep(skvk::make_pipeline_layout_from(ctx, k == 0 ? first_set.layout : next_layout), vkDestroyPipelineLayout);
        skvk::PipelineDesc pd;
        pd.vs = vs;
        pd.fs = k == 0 ? fs0 : fs1;
        pd.vs_entry = glsl ? "main" : "vs_main";
        pd.fs_entry = glsl ? "main" : (k == 0 ? "ps_first" : "ps_next");
        pd.depth_test = pd.depth_write = false;
        pd.color_count = 4;
        pipes[k] = scope.keep(skvk::make_pipeline_checked(ctx, pd, layouts[k], rp), vkDestroyPipeline);
    }
    // levels: four images each (the Scope's), 4x4 blocks down to 1x1
    struct Level {
        std::array<skvk::Image, 4>& b;
        VkFramebuffer fb = VK_NULL_HANDLE;
        VkDescriptorSet set = VK_NULL_HANDLE;  // the previous level's four images (next levels)
    };
    std::vector<Level> levels;
    levels.reserve(16);
    std::uint32_t lw = sc.w, lh = sc.h;
    while (levels.empty() || lw > 1 || lh > 1) {
        lw = (lw + 3) / 4;
        lh = (lh + 3) / 4;
        levels.push_back(Level{scope.own<std::array<skvk::Image, 4>>()});
        Level& L = levels.back();
        for (skvk::Image& im : L.b)
            REQUIRE(skvk::make_image(ctx, lw, lh, 1, rgba,
                                     VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, im));
        L.fb = scope.keep(skvk::make_framebuffer(ctx, rp, {L.b[0].view, L.b[1].view, L.b[2].view, L.b[3].view}, lw, lh),
                          vkDestroyFramebuffer);
        if (levels.size() > 1) {
            VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
            ai.descriptorPool = pool;
            ai.descriptorSetCount = 1;
            ai.pSetLayouts = &next_layout;
            REQUIRE(vkAllocateDescriptorSets(ctx.device, &ai, &L.set) == VK_SUCCESS);
            const Level& prev = levels[levels.size() - 2];
            VkDescriptorImageInfo ii[4];
            for (int k = 0; k < 4; ++k) ii[k] = {glsl ? nearest : VK_NULL_HANDLE, prev.b[k].view, read};
            VkWriteDescriptorSet wr{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
            wr.dstSet = L.set;
            wr.dstBinding = 2;
            wr.descriptorCount = 4;
            wr.descriptorType = tex;
            wr.pImageInfo = ii;
            vkUpdateDescriptorSets(ctx.device, 1, &wr, 0, nullptr);
        }
    }
    VkCommandBuffer cmd = skvk::begin_commands(ctx);
    VkClearValue zero{};
    for (std::size_t i = 0; i < levels.size(); ++i) {
        const Level& L = levels[i];
        skvk::draw_pass(cmd, rp, L.fb, L.b[0].width, L.b[0].height, {zero, zero, zero, zero}, pipes[i == 0 ? 0 : 1],
                        layouts[i == 0 ? 0 : 1], i == 0 ? &first_set.set : &L.set, nullptr, VK_NULL_HANDLE, 3, false);
        if (i + 1 < levels.size())
            for (const skvk::Image& im : L.b) skvk::transition(cmd, im, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, read);
    }
    REQUIRE(skvk::submit_and_wait(ctx, cmd));
    glm::vec4 gpu[4];
    double max_err = 0.0;
    for (int c = 0; c < 4; ++c) {
        const std::vector<float> v = skvk::read_image(ctx, levels.back().b[c], VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 4);
        REQUIRE(v.size() == 4);
        gpu[c] = glm::vec4(v[0], v[1], v[2], v[3]);
        INFO("cascade " << c);
        for (int k = 0; k < 4; ++k) {
            const double e = std::fabs(double(gpu[c][k]) - sc.cpu[c][k]);
            max_err = std::max(max_err, e);
            CHECK(e < 1e-3);
        }
    }
    MESSAGE((glsl ? "GLSL" : "HLSL") << " on Vulkan: per-cascade light-space bounds (" << sc.used[0] << ", " << sc.used[1] << ", "
                                     << sc.used[2] << ", " << sc.used[3] << " pixels) within " << max_err << " of the CPU's");
    CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());
}

}  // namespace

TEST_CASE("cascades.glsl on Vulkan: the SDSM reduction's min/max equals the CPU's exactly") { check_minmax(Source::Glsl); }

TEST_CASE("HLSL cascades.hlsl on Vulkan: the SDSM reduction's min/max equals the CPU's exactly") { check_minmax(Source::Hlsl); }

TEST_CASE("cascades.glsl on Vulkan: the SDSM bounds reduction equals the CPU's per-cascade light-space bounds") {
    check_bounds(Source::Glsl);
}

TEST_CASE("HLSL cascades.hlsl on Vulkan: the SDSM bounds reduction equals the CPU's per-cascade light-space bounds") {
    check_bounds(Source::Hlsl);
}
