// glsl/virtual_shadow_map.glsl and hlsl/virtual_shadow_map.hlsl RUN on Vulkan (lavapipe): parts (a), (b)
// and (c) of tests/gl/test_gl_virtual_shadow_map.cpp on its scene (a ground box, five boxes, a low sun),
// with [0, 1] clip depth (VsmLayout::clip_depth = ZeroToOne):
//  (a) marking: sk_vsm_mark in a full-screen fragment pass (the fragmentStoresAndAtomics feature) over
//      the camera's visible positions (relative to the anchor; here from a CPU ray cast per pixel
//      instead of a G-buffer pass), into the request-mask storage buffer; the mask must lie between
//      the pages every pixel surely requests and the pages it may request, computed on the CPU in
//      double (the GL test's rule, a 1e-3 texel and level tolerance);
//  (b) vsm_requests_from_bitmask -> vsm_plan; the listed pages rendered into a D32 atlas, each with
//      its own viewport and scissor, depth clamp on; sk_vsm_visibility_level per pixel against a ray
//      cast toward the light: >= 99.5% agreement away from shadow and geometry edges, no pixel
//      without a page;
//  (c) one caster moves: the new positions marked again, vsm_plan with its old and new bounds, only
//      the listed pages re-rendered into the kept atlas (a render pass that loads it, each page's
//      rectangle cleared); the pool must equal a full re-render of every current page into a fresh
//      atlas bit for bit, the move must have changed at least one page, and the lookup must still
//      agree with the ray cast (>= 99.5%, no pixel without a page).
// At the origin and 1e6 units away (the block's matrices relative to the camera). No validation message.
#include <doctest/doctest.h>

#include <shadowkit/virtual_shadow_map.hpp>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "../vsm_reference.hpp"
#include "vk_harness.hpp"
#include "vk_passes.hpp"

using namespace shadowkit;

namespace {

using skvk::Source;

constexpr int kW = 256, kH = 256;
constexpr double kFovY = 1.0471975512;  // 60 degrees

struct Box {
    double b[6];  // min xyz, max xyz (world)
};

// Slab test from p along d: entering t (>= 1e-3) and the entered face's normal; false when missed.
bool ray_box(const Box& box, const glm::dvec3& p, const glm::dvec3& d, double& t, glm::dvec3& n) {
    double t0 = -1e30, t1 = 1e30;
    int axis = -1;
    for (int k = 0; k < 3; ++k) {
        if (std::fabs(d[k]) < 1e-12) {
            if (p[k] < box.b[k] || p[k] > box.b[3 + k]) return false;
            continue;
        }
        double a = (box.b[k] - p[k]) / d[k], b = (box.b[3 + k] - p[k]) / d[k];
        if (a > b) std::swap(a, b);
        if (a > t0) {
            t0 = a;
            axis = k;
        }
        t1 = std::min(t1, b);
    }
    if (!(t1 >= std::max(t0, 1e-3)) || axis < 0) return false;
    t = t0;
    n = glm::dvec3(0.0);
    n[axis] = d[axis] > 0.0 ? -1.0 : 1.0;
    return true;
}

using vsm_ref::ray_hits;

const char* kMarkGlsl = R"(
layout(set = 0, binding = 3, std430) readonly buffer Pixels { vec4 px[]; };  // position (w = 1: covered), normal
layout(push_constant) uniform Pass { float pixel_angle; int width; } k;
layout(location = 0) out float o_unused;
void main() {
    int i = int(gl_FragCoord.y) * k.width + int(gl_FragCoord.x);
    vec4 p = px[2 * i];
    o_unused = 0.0;
    if (p.w == 0.0) return;
    sk_vsm_mark(p.xyz, sk_vsm_level_for_footprint(length(p.xyz) * k.pixel_angle, 0.0), 0);
}
)";
const char* kLookupGlsl = R"(
layout(set = 0, binding = 2) uniform sampler2D u_atlas;
layout(set = 0, binding = 3, std430) readonly buffer Pixels { vec4 px[]; };
layout(push_constant) uniform Pass { float pixel_angle; int width; } k;
layout(location = 0) out vec2 o_vis;
void main() {
    int i = int(gl_FragCoord.y) * k.width + int(gl_FragCoord.x);
    vec4 p = px[2 * i];
    if (p.w == 0.0) { o_vis = vec2(1.0, -2.0); return; }
    int level = sk_vsm_level_for_footprint(length(p.xyz) * k.pixel_angle, 0.0);
    int used;
    float v = sk_vsm_visibility_level(u_atlas, p.xyz, px[2 * i + 1].xyz, level, 0, 0.0, used);
    o_vis = vec2(v, float(used));
}
)";
const char* kHlsl = R"(
[[vk::binding(2, 0)]] Texture2D<float> u_atlas;
[[vk::binding(3, 0)]] StructuredBuffer<float4> px;
struct Pass { float pixel_angle; int width; };
[[vk::push_constant]] ConstantBuffer<Pass> k;
float ps_mark(float4 position : SV_Position) : SV_Target0 {
    int i = int(position.y) * k.width + int(position.x);
    float4 p = px[2 * i];
    if (p.w == 0.0) return 0.0;
    sk_vsm_mark(p.xyz, sk_vsm_level_for_footprint(length(p.xyz) * k.pixel_angle, 0.0), 0);
    return 0.0;
}
float2 ps_lookup(float4 position : SV_Position) : SV_Target0 {
    int i = int(position.y) * k.width + int(position.x);
    float4 p = px[2 * i];
    if (p.w == 0.0) return float2(1.0, -2.0);
    int level = sk_vsm_level_for_footprint(length(p.xyz) * k.pixel_angle, 0.0);
    int used;
    float v = sk_vsm_visibility_level(u_atlas, p.xyz, px[2 * i + 1].xyz, level, 0, 0.0, used);
    return float2(v, float(used));
}
)";

struct PassPush {
    float pixel_angle;
    std::int32_t width;
};

// Compiles the four stages of one language: fullscreen vertex, caster vertex, mark, lookup.
struct Modules {
    std::vector<std::uint32_t> vs, caster, mark, lookup;
    const char* entries[3] = {"main", "main", "main"};  // vs, mark, lookup
};
Modules compile(Source lang) {
    Modules m;
    // the caster stage is GLSL in both runs; its .spv named per run (the two CTest runs go in parallel
    // and would write and spirv-val the same file at once)
    m.caster = skvk::compile_checked(Source::Glsl, VK_SHADER_STAGE_VERTEX_BIT, skvk::kSceneDepthGlsl, "main",
                                     lang == Source::Glsl ? "vsm.glsl.caster.vert" : "vsm.hlsl.caster.vert");
    if (lang == Source::Glsl) {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_GLSL_DIR) + "/virtual_shadow_map.glsl");
        m.vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, skvk::kFullscreenGlsl, "main", "vsm.glsl.vert");
        m.mark = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, "#version 450 core\n" + snippet + kMarkGlsl, "main",
                                       "vsm.glsl.mark.frag");
        m.lookup = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, "#version 450 core\n" + snippet + kLookupGlsl, "main",
                                         "vsm.glsl.lookup.frag");
        return m;
    }
    const std::string snippet = skvk::read_text(std::string(SHADOWKIT_HLSL_DIR) + "/virtual_shadow_map.hlsl");
    m.vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, snippet + skvk::kFullscreenHlsl + kHlsl, "vs_main", "vsm.hlsl.vert");
    m.mark = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, snippet + skvk::kFullscreenHlsl + kHlsl, "ps_mark", "vsm.hlsl.mark.frag");
    m.lookup = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, snippet + skvk::kFullscreenHlsl + kHlsl, "ps_lookup", "vsm.hlsl.lookup.frag");
    m.entries[0] = "vs_main";
    m.entries[1] = "ps_mark";
    m.entries[2] = "ps_lookup";
    return m;
}

// A depth-only render pass that keeps the atlas (load and store, `held` before and after): pages
// re-rendered into it clear their own rectangles.
VkRenderPass atlas_load_pass(skvk::Context& ctx, VkImageLayout held) {
    VkAttachmentDescription a{};
    a.format = VK_FORMAT_D32_SFLOAT;
    a.samples = VK_SAMPLE_COUNT_1_BIT;
    a.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
    a.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    a.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    a.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    a.initialLayout = held;
    a.finalLayout = held;
    VkAttachmentReference ref{0, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
    VkSubpassDescription sp{};
    sp.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    sp.pDepthStencilAttachment = &ref;
    // the harness's dependencies (a pipeline made for its render pass must be compatible)
    VkSubpassDependency dep[2];
    skvk::pass_dependencies(dep);
    VkRenderPassCreateInfo ri{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
    ri.attachmentCount = 1;
    ri.pAttachments = &a;
    ri.subpassCount = 1;
    ri.pSubpasses = &sp;
    ri.dependencyCount = 2;
    ri.pDependencies = dep;
    VkRenderPass rp = VK_NULL_HANDLE;
    vkCreateRenderPass(ctx.device, &ri, nullptr, &rp);
    return rp;
}

void run_scene(Source lang, const glm::dvec3& offset) {
    skvk::Context& ctx = skvk::vk_test_context();
    skvk::Scope scope(ctx);
    REQUIRE(ctx.enabled.fragmentStoresAndAtomics);
    REQUIRE(ctx.enabled.depthClamp);
    const std::size_t before = skvk::message_count();
    const bool glsl = lang == Source::Glsl;
    std::vector<Box> boxes = {{{-60.0, -1.0, -60.0, 60.0, 0.0, 60.0}},  // ground (top at y = 0)
                              {{-2.0, 0.0, -3.0, 0.0, 2.5, -1.0}},      // boxes on it
                              {{1.5, 0.0, -6.0, 2.5, 4.0, -5.0}},
                              {{-5.0, 0.0, -10.0, -3.0, 1.0, -7.0}},
                              {{3.0, 0.5, 0.0, 4.0, 1.5, 1.0}},  // floating: its shadow is detached
                              {{-1.0, 0.0, -25.0, 6.0, 6.0, -20.0}}};
    for (Box& b : boxes)
        for (int k = 0; k < 6; ++k) b.b[k] = double(float(b.b[k] + offset[k % 3]));  // the float bounds the renderer draws
    const glm::dvec3 camera = offset + glm::dvec3(0.25, 5.0, 9.0), target = offset + glm::dvec3(0.0, 0.0, -6.0);
    const glm::vec4 light(0.35f, 0.55f, -0.6f, 0.0f);
    const glm::dvec3 to_light = glm::normalize(glm::dvec3(light));
    const float pixel_angle = float(2.0 * std::tan(0.5 * kFovY) / kH);

    // the camera's visible points by a ray per pixel (relative to the camera, the anchor), and the truth
    const glm::dmat4 view = glm::lookAt(glm::dvec3(0.0), target - camera, glm::dvec3(0, 1, 0));
    const glm::dmat3 to_world = glm::transpose(glm::dmat3(view));
    std::vector<glm::vec4> px(2 * std::size_t(kW) * kH, glm::vec4(0.f));
    std::vector<int> truth(std::size_t(kW) * kH, -1);
    const double th = std::tan(0.5 * kFovY);
    auto cast_pixels = [&] {
        std::fill(px.begin(), px.end(), glm::vec4(0.f));
        std::fill(truth.begin(), truth.end(), -1);
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x) {
                const glm::dvec3 d =
                    glm::normalize(to_world * glm::dvec3(((x + 0.5) / kW * 2.0 - 1.0) * th, ((y + 0.5) / kH * 2.0 - 1.0) * th, -1.0));
                double best = 1e30;
                glm::dvec3 bn(0.0);
                for (const Box& b : boxes) {
                    double t = 0;
                    glm::dvec3 n;
                    if (ray_box(b, camera, d, t, n) && t < best) best = t, bn = n;
                }
                if (best > 300.0) continue;
                const std::size_t i = std::size_t(y) * kW + std::size_t(x);
                px[2 * i] = glm::vec4(glm::vec3(best * d), 1.f);
                px[2 * i + 1] = glm::vec4(glm::vec3(bn), 0.f);
                const glm::dvec3 p = camera + glm::dvec3(glm::vec3(best * d));
                bool hit = false;
                for (const Box& b : boxes) hit = hit || ray_hits(b, p, to_light);
                truth[i] = hit ? 0 : 1;
            }
    };
    cast_pixels();

    VsmLayout layout = vsm_ref::test_layout();
    layout.clip_depth = ClipDepth::ZeroToOne;
    VsmState vsm;
    REQUIRE(vsm_state_init(layout, vsm).status == Status::Ok);
    std::vector<VsmPageRender> pages(std::size_t(layout.pool_pages));
    VsmFrame f;
    f.camera_position = camera;
    f.light_position = light;
    REQUIRE(vsm_plan(vsm, f, pages.data(), pages.size()).status == Status::Ok);  // place the windows

    // buffers: the data block (binding 0), the request mask (1), the pixels (3)
    const Modules mod = compile(lang);
    skvk::Buffer& data = scope.own<skvk::Buffer>();
    skvk::Buffer& mask = scope.own<skvk::Buffer>();
    skvk::Buffer& pixels = scope.own<skvk::Buffer>();
    skvk::Buffer& vb = scope.own<skvk::Buffer>();
    REQUIRE(skvk::make_buffer(ctx, vsm_gpu_block_words(vsm) * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, data));
    const std::size_t words = vsm_bitmask_words(vsm);
    REQUIRE(skvk::make_buffer(ctx, words * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, mask));
    REQUIRE(skvk::make_buffer(ctx, px.size() * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, pixels));
    std::memcpy(pixels.mapped, px.data(), px.size() * sizeof(glm::vec4));
    auto upload_block = [&] {
        std::vector<std::uint32_t> block(vsm_gpu_block_words(vsm));
        REQUIRE(vsm_gpu_block(vsm, camera, block.data(), block.size()).status == Status::Ok);
        std::memcpy(data.mapped, block.data(), block.size() * 4);
    };
    // casters: 36 vertices per box, relative to the anchor
    std::vector<glm::vec3> tris;
    static const int q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}};
    auto build_casters = [&] {
        tris.clear();
        for (const Box& b : boxes) {
            glm::vec3 c[8];
            for (int k = 0; k < 8; ++k)
                c[k] = glm::vec3(glm::dvec3(k & 1 ? b.b[3] : b.b[0], k & 2 ? b.b[4] : b.b[1], k & 4 ? b.b[5] : b.b[2]) - camera);
            for (const auto& fq : q)
                for (int v : {0, 1, 2, 0, 2, 3}) tris.push_back(c[fq[v]]);
        }
    };
    build_casters();
    REQUIRE(skvk::make_buffer(ctx, tris.size() * sizeof(glm::vec3), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, vb));
    std::memcpy(vb.mapped, tris.data(), tris.size() * sizeof(glm::vec3));

    // ---- (a) marking
    const VkShaderStageFlags frag = VK_SHADER_STAGE_FRAGMENT_BIT;
    const VkDescriptorType sbuf = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    const VkDescriptorType tex = skvk::texture_type(lang);
    skvk::DescriptorSet& mark_set = scope.own<skvk::DescriptorSet>();
    skvk::DescriptorSet& look_set = scope.own<skvk::DescriptorSet>();
    REQUIRE(skvk::make_descriptor_set(ctx, {{0, sbuf, frag}, {1, sbuf, frag}, {3, sbuf, frag}}, mark_set));
    REQUIRE(skvk::make_descriptor_set(ctx, {{0, sbuf, frag}, {1, sbuf, frag}, {2, tex, frag}, {3, sbuf, frag}}, look_set));
    for (skvk::DescriptorSet* s : {&mark_set, &look_set}) {
        skvk::write_buffer(ctx, *s, 0, data, sbuf);
        skvk::write_buffer(ctx, *s, 1, mask, sbuf);
        skvk::write_buffer(ctx, *s, 3, pixels, sbuf);
    }
    skvk::Image& dummy = scope.own<skvk::Image>();
    skvk::Image& vis = scope.own<skvk::Image>();
    const VkImageUsageFlags rt = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    REQUIRE(skvk::make_image(ctx, kW, kH, 1, VK_FORMAT_R32_SFLOAT, rt, dummy));
    REQUIRE(skvk::make_image(ctx, kW, kH, 1, VK_FORMAT_R32G32_SFLOAT, rt, vis));
    VkRenderPass mark_rp = scope.keep(skvk::make_render_pass(ctx, {VK_FORMAT_R32_SFLOAT}, VK_FORMAT_UNDEFINED, VK_IMAGE_LAYOUT_UNDEFINED), vkDestroyRenderPass);
    VkRenderPass look_rp = scope.keep(skvk::make_render_pass(ctx, {VK_FORMAT_R32G32_SFLOAT}, VK_FORMAT_UNDEFINED, VK_IMAGE_LAYOUT_UNDEFINED), vkDestroyRenderPass);
    VkFramebuffer mark_fb = scope.keep(skvk::make_framebuffer(ctx, mark_rp, {dummy.view}, kW, kH), vkDestroyFramebuffer);
    VkFramebuffer look_fb = scope.keep(skvk::make_framebuffer(ctx, look_rp, {vis.view}, kW, kH), vkDestroyFramebuffer);
    VkPipelineLayout mark_layout = scope.keep(skvk::make_pipeline_layout(ctx, &mark_set, sizeof(PassPush), frag), vkDestroyPipelineLayout);
    VkPipelineLayout look_layout = scope.keep(skvk::make_pipeline_layout(ctx, &look_set, sizeof(PassPush), frag), vkDestroyPipelineLayout);
    skvk::PipelineDesc pd;
    pd.vs = mod.vs;
    pd.vs_entry = mod.entries[0];
    pd.depth_test = pd.depth_write = false;
    pd.color_count = 1;
    pd.fs = mod.mark;
    pd.fs_entry = mod.entries[1];
    VkPipeline mark_pipe = scope.keep(skvk::make_pipeline_checked(ctx, pd, mark_layout, mark_rp), vkDestroyPipeline);
    pd.fs = mod.lookup;
    pd.fs_entry = mod.entries[2];
    VkPipeline look_pipe = scope.keep(skvk::make_pipeline_checked(ctx, pd, look_layout, look_rp), vkDestroyPipeline);
    const PassPush push{pixel_angle, kW};
    VkClearValue zero{};

    auto mark_pass = [&] {
        upload_block();
        std::memset(mask.mapped, 0, words * 4);
        VkCommandBuffer mc = skvk::begin_commands(ctx);
        skvk::draw_pass(mc, mark_rp, mark_fb, kW, kH, {zero}, mark_pipe, mark_layout, &mark_set.set, &push, VK_NULL_HANDLE, 3, false,
                        sizeof push, frag);
        VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
        mb.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
        vkCmdPipelineBarrier(mc, VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &mb, 0, nullptr, 0, nullptr);
        REQUIRE(skvk::submit_and_wait(ctx, mc));
        std::vector<std::uint32_t> m(words);
        std::memcpy(m.data(), mask.mapped, words * 4);
        return m;
    };
    const std::vector<std::uint32_t> bitmask = mark_pass();

    const std::size_t bits = std::size_t(layout.level_count) * std::size_t(vsm.pages_per_side * vsm.pages_per_side);
    std::vector<glm::dvec3> rel;  // the covered pixels' positions relative to the camera
    for (std::size_t i = 0; i < std::size_t(kW) * kH; ++i)
        if (px[2 * i].w != 0.f) rel.emplace_back(px[2 * i]);
    const auto [covered, gpu_set, sure_n, maybe_n, missing, extra] = vsm_ref::mark_tally(vsm, camera, pixel_angle, rel, bitmask);
    const std::string name = std::string(glsl ? "GLSL" : "HLSL") + (offset == glm::dvec3(0.0) ? " at the origin" : " 1e6 away");
    INFO(name);
    MESSAGE(name << " marking: " << covered << " pixels, GPU set " << gpu_set << " page bits; CPU sure " << sure_n << ", maybe "
                 << maybe_n << "; missing " << missing << ", extra " << extra);
    CHECK(covered > std::size_t(kW * kH / 2));
    CHECK(missing == 0);
    CHECK(extra == 0);
    CHECK(sure_n > 20);
    CHECK(maybe_n - sure_n <= sure_n / 10);

    // ---- (b) plan, render the listed pages, look up
    std::vector<VsmPageRequest> req(bits);
    const VsmRequestList rl = vsm_requests_from_bitmask(vsm, bitmask.data(), bitmask.size(), req.data(), req.size());
    REQUIRE(rl.status == Status::Ok);
    f.requests = req.data();
    f.request_count = rl.count;
    const VsmPlan plan = vsm_plan(vsm, f, pages.data(), pages.size());
    REQUIRE(plan.status == Status::Ok);
    CHECK(plan.count == rl.count);
    upload_block();

    const auto atlas_size = std::uint32_t(vsm.layout.pool_columns * layout.page_texels);
    const auto atlas_rows = std::uint32_t((layout.pool_pages + vsm.layout.pool_columns - 1) / vsm.layout.pool_columns * layout.page_texels);
    skvk::Image& atlas = scope.own<skvk::Image>();
    REQUIRE(skvk::make_image(ctx, atlas_size, atlas_rows, 1, VK_FORMAT_D32_SFLOAT,
                             VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                             atlas));
    const VkImageLayout atlas_read = VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL;
    VkRenderPass atlas_rp = scope.keep(skvk::make_render_pass(ctx, {}, VK_FORMAT_D32_SFLOAT, atlas_read), vkDestroyRenderPass);
    VkFramebuffer atlas_fb = scope.keep(skvk::make_framebuffer(ctx, atlas_rp, {atlas.view}, atlas_size, atlas_rows), vkDestroyFramebuffer);
    VkPipelineLayout caster_layout = scope.keep(skvk::make_pipeline_layout(ctx, nullptr, sizeof(glm::mat4)), vkDestroyPipelineLayout);
    skvk::PipelineDesc cd;
    cd.vs = mod.caster;
    cd.vertex_stride = sizeof(glm::vec3);
    cd.attributes = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0}};
    cd.depth_compare = VK_COMPARE_OP_LESS;
    cd.depth_clamp = true;
    VkPipeline caster_pipe = scope.keep(skvk::make_pipeline_checked(ctx, cd, caster_layout, atlas_rp), vkDestroyPipeline);
    VkSampler nearest = scope.keep(skvk::make_sampler(ctx, VK_FILTER_NEAREST, VK_COMPARE_OP_NEVER), vkDestroySampler);
    skvk::write_image(ctx, look_set, 2, tex, atlas.view, glsl ? nearest : VK_NULL_HANDLE, atlas_read);

    // the listed pages, each with its own viewport and scissor (clear_each: its rectangle cleared first)
    const auto pt = float(layout.page_texels);
    auto draw_pages = [&](VkCommandBuffer c, const VsmPageRender* pg, std::size_t count, bool clear_each) {
        vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_GRAPHICS, caster_pipe);
        const VkDeviceSize vb_offset = 0;
        vkCmdBindVertexBuffers(c, 0, 1, &vb.buffer, &vb_offset);
        for (std::size_t i = 0; i < count; ++i) {
            // a plain viewport: NDC y = -1 at row atlas_y, as GL's glViewport puts it at texel row atlas_y
            const VkViewport vp{float(pg[i].atlas_x), float(pg[i].atlas_y), pt, pt, 0.f, 1.f};
            const VkRect2D sc{{pg[i].atlas_x, pg[i].atlas_y}, {std::uint32_t(pt), std::uint32_t(pt)}};
            vkCmdSetViewport(c, 0, 1, &vp);
            vkCmdSetScissor(c, 0, 1, &sc);
            if (clear_each) {
                VkClearAttachment ca{VK_IMAGE_ASPECT_DEPTH_BIT, 0, {}};
                ca.clearValue.depthStencil = {1.f, 0};
                const VkClearRect cr{sc, 0, 1};
                vkCmdClearAttachments(c, 1, &ca, 1, &cr);
            }
            const VsmMatrix m = vsm_relative_matrix(pg[i].view_proj, camera);
            REQUIRE(m.status == Status::Ok);
            vkCmdPushConstants(c, caster_layout, VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(glm::mat4), &m.matrix);
            vkCmdDraw(c, std::uint32_t(tris.size()), 1, 0, 0);
        }
    };
    VkCommandBuffer cmd = skvk::begin_commands(ctx);
    VkClearValue far{};
    far.depthStencil = {1.f, 0};  // the whole atlas cleared: every page of it is rendered this frame
    VkRenderPassBeginInfo bi{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    bi.renderPass = atlas_rp;
    bi.framebuffer = atlas_fb;
    bi.renderArea = {{0, 0}, {atlas_size, atlas_rows}};
    bi.clearValueCount = 1;
    bi.pClearValues = &far;
    vkCmdBeginRenderPass(cmd, &bi, VK_SUBPASS_CONTENTS_INLINE);
    draw_pages(cmd, pages.data(), plan.count, false);
    vkCmdEndRenderPass(cmd);
    skvk::draw_pass(cmd, look_rp, look_fb, kW, kH, {zero}, look_pipe, look_layout, &look_set.set, &push, VK_NULL_HANDLE, 3, false,
                    sizeof push, frag);
    REQUIRE(skvk::submit_and_wait(ctx, cmd));
    const std::vector<float> v = skvk::read_image(ctx, vis, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 2);
    REQUIRE(v.size() == std::size_t(kW) * kH * 2);

    // agreement away from shadow and geometry edges (5x5 of one truth and one normal), as the GL test
    std::size_t counted = 0, agree = 0, holes = 0, lit = 0;
    auto agreement_of = [&](const std::vector<float>& vv) {
        counted = agree = holes = lit = 0;
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x) {
                const std::size_t i = std::size_t(y) * kW + std::size_t(x);
                if (truth[i] < 0) continue;
                holes += vv[i * 2 + 1] < 0.0f;
                bool edge = false;
                for (int dy = -2; dy <= 2 && !edge; ++dy)
                    for (int dx = -2; dx <= 2 && !edge; ++dx) {
                        const int xx = x + dx, yy = y + dy;
                        if (xx < 0 || yy < 0 || xx >= kW || yy >= kH) {
                            edge = true;
                            break;
                        }
                        const std::size_t j = std::size_t(yy) * kW + std::size_t(xx);
                        edge = truth[j] != truth[i] || px[2 * j + 1] != px[2 * i + 1];
                    }
                if (edge) continue;
                ++counted;
                lit += std::size_t(truth[i]);
                agree += (vv[i * 2] > 0.5f) == (truth[i] == 1);
            }
        return double(agree) / double(std::max<std::size_t>(counted, 1));
    };
    const double agreement = agreement_of(v);
    MESSAGE(name << " lookup: " << plan.count << " pages rendered, " << counted << " pixels away from edges (" << lit
                 << " lit), agreement " << agreement << ", pixels without a page " << holes);
    CHECK(counted > std::size_t(kW * kH / 4));
    CHECK(lit > counted / 4);
    CHECK(counted - lit > counted / 20);
    CHECK(agreement >= 0.995);
    CHECK(holes == 0);

    // ---- (c) move one caster, invalidate, re-render the listed pages only (into the kept atlas: a
    // render pass that loads it, each page's rectangle cleared), then compare the pool with a full
    // re-render of every current page into a fresh atlas, bit for bit
    auto bits_of = [&](const skvk::Image& img) {
        const std::vector<float> d = skvk::read_image(ctx, img, atlas_read, 1);
        std::vector<std::uint32_t> u(d.size());
        std::memcpy(u.data(), d.data(), d.size() * 4);
        return u;
    };
    const std::vector<std::uint32_t> atlas_before = bits_of(atlas);
    VsmCasterMove move;
    for (int k = 0; k < 6; ++k) move.previous_bounds[k] = float(boxes[2].b[k]);
    for (int k : {0, 3}) boxes[2].b[k] = double(float(boxes[2].b[k]) + 1.25f);
    for (int k : {2, 5}) boxes[2].b[k] = double(float(boxes[2].b[k]) - 0.5f);
    for (int k = 0; k < 6; ++k) move.bounds[k] = float(boxes[2].b[k]);
    build_casters();
    std::memcpy(vb.mapped, tris.data(), tris.size() * sizeof(glm::vec3));
    cast_pixels();
    std::memcpy(pixels.mapped, px.data(), px.size() * sizeof(glm::vec4));
    const std::vector<std::uint32_t> bitmask2 = mark_pass();
    const VsmRequestList rl2 = vsm_requests_from_bitmask(vsm, bitmask2.data(), bitmask2.size(), req.data(), req.size());
    REQUIRE(rl2.status == Status::Ok);
    f.requests = req.data();
    f.request_count = rl2.count;
    f.moved_casters = &move;
    f.moved_caster_count = 1;
    const VsmPlan plan2 = vsm_plan(vsm, f, pages.data(), pages.size());
    REQUIRE(plan2.status == Status::Ok);
    VkRenderPass load_rp = scope.keep(atlas_load_pass(ctx, atlas_read), vkDestroyRenderPass);
    VkFramebuffer load_fb = scope.keep(skvk::make_framebuffer(ctx, load_rp, {atlas.view}, atlas_size, atlas_rows), vkDestroyFramebuffer);
    cmd = skvk::begin_commands(ctx);
    bi.renderPass = load_rp;
    bi.framebuffer = load_fb;
    bi.clearValueCount = 0;
    bi.pClearValues = nullptr;
    vkCmdBeginRenderPass(cmd, &bi, VK_SUBPASS_CONTENTS_INLINE);
    draw_pages(cmd, pages.data(), plan2.count, true);
    vkCmdEndRenderPass(cmd);
    REQUIRE(skvk::submit_and_wait(ctx, cmd));
    const std::vector<std::uint32_t> kept = bits_of(atlas);
    // the full re-render: every current page into a fresh atlas (cleared whole)
    std::vector<VsmPageRender> all;
    for (std::uint32_t sl = 0; sl < std::uint32_t(layout.pool_pages); ++sl) {
        const VsmSlotPage sp = vsm_slot_page(vsm, sl);
        REQUIRE(sp.status == Status::Ok);
        if (sp.resident && sp.current) all.push_back(sp.page);
    }
    skvk::Image& full = scope.own<skvk::Image>();
    REQUIRE(skvk::make_image(ctx, atlas_size, atlas_rows, 1, VK_FORMAT_D32_SFLOAT,
                             VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                             full));
    VkFramebuffer full_fb = scope.keep(skvk::make_framebuffer(ctx, atlas_rp, {full.view}, atlas_size, atlas_rows), vkDestroyFramebuffer);
    cmd = skvk::begin_commands(ctx);
    bi.renderPass = atlas_rp;
    bi.framebuffer = full_fb;
    bi.clearValueCount = 1;
    bi.pClearValues = &far;
    vkCmdBeginRenderPass(cmd, &bi, VK_SUBPASS_CONTENTS_INLINE);
    draw_pages(cmd, all.data(), all.size(), false);
    vkCmdEndRenderPass(cmd);
    REQUIRE(skvk::submit_and_wait(ctx, cmd));
    const std::vector<std::uint32_t> ref = bits_of(full);
    std::size_t differing_pages = 0, changed_by_move = 0;
    for (const VsmPageRender& pg : all) {
        bool differs = false, changed = false;
        for (int y = 0; y < layout.page_texels; ++y)
            for (int x = 0; x < layout.page_texels; ++x) {
                const std::size_t i = std::size_t(pg.atlas_y + y) * atlas_size + std::size_t(pg.atlas_x + x);
                differs = differs || kept[i] != ref[i];
                changed = changed || atlas_before[i] != ref[i];
            }
        differing_pages += differs;
        changed_by_move += changed;
    }
    MESSAGE(name << " moved caster: " << plan2.invalidated << " pages invalidated, " << plan2.rerendered << " re-rendered, "
                 << plan2.allocated << " newly allocated, of " << all.size() << " current pages; " << changed_by_move
                 << " pages differ from the frame before, " << differing_pages << " from the full re-render");
    CHECK(differing_pages == 0);
    CHECK(changed_by_move > 0);
    CHECK(plan2.rerendered > 0);
    CHECK(plan2.count < all.size() / 2);
    // the lookup after the move agrees with the ray cast as well
    upload_block();
    cmd = skvk::begin_commands(ctx);
    skvk::draw_pass(cmd, look_rp, look_fb, kW, kH, {zero}, look_pipe, look_layout, &look_set.set, &push, VK_NULL_HANDLE, 3, false,
                    sizeof push, frag);
    REQUIRE(skvk::submit_and_wait(ctx, cmd));
    const double agreement2 = agreement_of(skvk::read_image(ctx, vis, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 2));
    MESSAGE(name << " after the move: agreement " << agreement2 << " over " << counted << " pixels, pixels without a page " << holes);
    CHECK(agreement2 >= 0.995);
    CHECK(holes == 0);
    CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());
}

}  // namespace

TEST_CASE("virtual_shadow_map.glsl on Vulkan: marks match the CPU, lookup matches a ray cast, a moved caster re-renders its pages") {
    run_scene(Source::Glsl, glm::dvec3(0.0));
    run_scene(Source::Glsl, glm::dvec3(1.0e6, 0.0, -1.0e6));
}

TEST_CASE("HLSL virtual_shadow_map.hlsl on Vulkan: marks match the CPU, lookup matches a ray cast, a moved caster re-renders its pages") {
    run_scene(Source::Hlsl, glm::dvec3(0.0));
    run_scene(Source::Hlsl, glm::dvec3(1.0e6, 0.0, -1.0e6));
}
