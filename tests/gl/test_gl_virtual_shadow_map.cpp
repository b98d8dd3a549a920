// Virtual shadow maps on GL (virtual_shadow_map.hpp + glsl/virtual_shadow_map.glsl), one frame and a
// moved caster, on a ground box with a few boxes under a sun:
//  (a) marking: a G-buffer pass (positions relative to the anchor, normals), then the snippet's
//      sk_vsm_mark in a full-screen pass; the bitmask read back must lie between the pages every
//      pixel surely requests and the pages it may request, both computed on the CPU in double from
//      the read-back positions (a 1e-3 texel and 1e-3 level tolerance covers float vs double);
//  (b) plan + render: vsm_requests_from_bitmask -> vsm_plan; only the listed pages are rendered, each
//      with its own viewport and scissor into a GL_DEPTH_COMPONENT32F atlas, casters culled with
//      vsm_page_casters; then the lookup (sk_vsm_visibility_level) per pixel against a CPU ray cast
//      from the same positions toward the light: >= 99.5% agreement away from shadow and geometry
//      edges, and no pixel left without a page (used level -1);
//  (c) one caster moves: vsm_plan with its old and new bounds; only the listed pages are re-rendered;
//      the kept pool then equals a full re-render of every current page into a fresh atlas, bit for
//      bit; and the move changed at least one page (so the comparison can fail).
//  (d) a pool of half the requests: the plan falls back to coarser pages and the lookup walks up to
//      them: no pixel without a page, >= 99% agreement.
// All of it twice: at the origin and with the scene and camera 1e6 units away (the block's matrices
// and every position relative to the camera).
// What each check catches: a bit layout or level rule that differs from the header's, a wrong
// toroidal offset, slot -> atlas mapping or page matrix, a hole at a page border or a missing
// fallback, a bias that leaves acne, and a page the move touched but the plan did not invalidate.
#include <doctest/doctest.h>

#include <shadowkit/virtual_shadow_map.hpp>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "../vsm_reference.hpp"
#include "gl_test.hpp"

using namespace shadowkit;

namespace {

constexpr int kW = 256, kH = 256;
constexpr float kFovY = 1.0471975512f;  // 60 degrees

struct Box {
    float b[6];  // min xyz, max xyz (world)
};

// 24 vertices (flat normals), 36 indices per box, positions relative to `anchor`.
void box_mesh(const Box& box, const glm::dvec3& anchor, float* pos, float* nrm) {
    static const int faces[6][4][3] = {{{0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}}, {{1, 0, 0}, {1, 0, 1}, {1, 1, 1}, {1, 1, 0}},
                                       {{0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}}, {{0, 1, 0}, {1, 1, 0}, {1, 1, 1}, {0, 1, 1}},
                                       {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {{0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}}};
    static const float normals[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
    for (int f = 0; f < 6; ++f)
        for (int v = 0; v < 4; ++v)
            for (int k = 0; k < 3; ++k) {
                const double w = faces[f][v][k] ? box.b[3 + k] : box.b[k];
                pos[(f * 4 + v) * 3 + k] = float(w - anchor[k]);
                nrm[(f * 4 + v) * 3 + k] = normals[f][k];
            }
}

using vsm_ref::ray_hits;  // the slab test: the ray from p along d hits the box beyond t = 1e-3

std::string snippet() {
    bool ok = false;
    const std::string s = skgl::read_text_file(std::string(SHADOWKIT_GLSL_DIR) + "/virtual_shadow_map.glsl", &ok);
    REQUIRE(ok);
    return s;
}

const char* kFullscreenVS = R"(#version 450 core
void main() { vec2 p = vec2(float((gl_VertexID & 1) * 4 - 1), float((gl_VertexID & 2) * 2 - 1)); gl_Position = vec4(p, 0.0, 1.0); }
)";

const char* kGbufferVS = R"(#version 450 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
uniform mat4 u_view_proj;
out vec3 v_rel;
out vec3 v_normal;
void main() { v_rel = a_position; v_normal = a_normal; gl_Position = u_view_proj * vec4(a_position, 1.0); }
)";
const char* kGbufferFS = R"(#version 450 core
in vec3 v_rel;
in vec3 v_normal;
layout(location = 0) out vec4 o_pos;
layout(location = 1) out vec4 o_normal;
void main() { o_pos = vec4(v_rel, 1.0); o_normal = vec4(v_normal, 0.0); }
)";
const char* kCasterVS = R"(#version 450 core
layout(location = 0) in vec3 a_position;
uniform mat4 u_light_view_proj;
void main() { gl_Position = u_light_view_proj * vec4(a_position, 1.0); }
)";
const char* kCasterFS = "#version 450 core\nvoid main() {}\n";

// The marking and lookup passes: positions at unit 3, normals at unit 4, the atlas at unit 0.
const char* kMarkFS = R"(
layout(binding = 3) uniform sampler2D u_positions;
uniform float u_pixel_angle;
void main() {
    vec4 p = texelFetch(u_positions, ivec2(gl_FragCoord.xy), 0);
    if (p.w == 0.0) discard;
    sk_vsm_mark(p.xyz, sk_vsm_level_for_footprint(length(p.xyz) * u_pixel_angle, 0.0), 0);
}
)";
const char* kLookupFS = R"(
layout(binding = 0) uniform sampler2D u_atlas;
layout(binding = 3) uniform sampler2D u_positions;
layout(binding = 4) uniform sampler2D u_normals;
uniform float u_pixel_angle;
layout(location = 0) out vec2 o_vis;
void main() {
    vec4 p = texelFetch(u_positions, ivec2(gl_FragCoord.xy), 0);
    if (p.w == 0.0) { o_vis = vec2(1.0, -2.0); return; }
    int level = sk_vsm_level_for_footprint(length(p.xyz) * u_pixel_angle, 0.0);
    int used;
    float v = sk_vsm_visibility_level(u_atlas, p.xyz, texelFetch(u_normals, ivec2(gl_FragCoord.xy), 0).xyz, level, 0, 0.0, used);
    o_vis = vec2(v, float(used));
}
)";

GLuint program(const char* vs, const std::string& fs) {
    std::string log;
    const GLuint p = skgl::compile_program({{GL_VERTEX_SHADER, vs}, {GL_FRAGMENT_SHADER, fs}}, log);
    INFO(log);
    REQUIRE(p != 0);
    return p;
}

struct Scene {
    std::vector<Box> boxes;
    glm::dvec3 anchor;
    GLuint vao = 0, vbo = 0, ibo = 0;
    void upload() {
        std::vector<float> v(boxes.size() * 24 * 6);
        std::vector<std::uint32_t> idx;
        for (std::size_t i = 0; i < boxes.size(); ++i) {
            float pos[72], nrm[72];
            box_mesh(boxes[i], anchor, pos, nrm);
            for (int k = 0; k < 24; ++k)
                for (int c = 0; c < 3; ++c) {
                    v[(i * 24 + std::size_t(k)) * 6 + std::size_t(c)] = pos[k * 3 + c];
                    v[(i * 24 + std::size_t(k)) * 6 + 3 + std::size_t(c)] = nrm[k * 3 + c];
                }
            for (std::uint32_t f = 0; f < 6; ++f)
                for (std::uint32_t t : {0u, 1u, 2u, 0u, 2u, 3u}) idx.push_back(std::uint32_t(i) * 24u + f * 4u + t);
        }
        if (vao == 0) {
            glCreateVertexArrays(1, &vao);
            glCreateBuffers(1, &vbo);
            glCreateBuffers(1, &ibo);
            glNamedBufferStorage(vbo, GLsizeiptr(v.size() * 4), nullptr, GL_DYNAMIC_STORAGE_BIT);
            glNamedBufferStorage(ibo, GLsizeiptr(idx.size() * 4), idx.data(), 0);
            glVertexArrayVertexBuffer(vao, 0, vbo, 0, 24);
            glVertexArrayElementBuffer(vao, ibo);
            for (GLuint a = 0; a < 2; ++a) {
                glEnableVertexArrayAttrib(vao, a);
                glVertexArrayAttribFormat(vao, a, 3, GL_FLOAT, GL_FALSE, a * 12);
                glVertexArrayAttribBinding(vao, a, 0);
            }
        }
        glNamedBufferSubData(vbo, 0, GLsizeiptr(v.size() * 4), v.data());
    }
    void draw(std::size_t i) const {
        glDrawElements(GL_TRIANGLES, 36, GL_UNSIGNED_INT, reinterpret_cast<const void*>(i * 36 * 4));
    }
    void bounds(std::vector<float>& out) const {
        out.clear();
        for (const Box& b : boxes) out.insert(out.end(), b.b, b.b + 6);
    }
};

struct Gpu {
    GLuint gbuffer_prog = 0, caster_prog = 0, mark_prog = 0, lookup_prog = 0, empty_vao = 0;
    GLuint data_ssbo = 0, mask_ssbo = 0, atlas = 0, atlas_fbo = 0;
    skgl::Target gbuffer, vis;
    int atlas_size = 0;
};

void render_pages(const VsmState& vsm, const Scene& scene, const Gpu& g, GLuint fbo, const VsmPageRender* pages, std::size_t count,
                  bool cull) {
    std::vector<float> bounds;
    scene.bounds(bounds);
    std::vector<std::uint32_t> first(count + 1), counts(count + 1), idx(count * scene.boxes.size() + 1);
    if (cull) {
        const VsmPageCasters pc = vsm_page_casters(vsm, pages, count, bounds.data(), scene.boxes.size(), first.data(),
                                                   counts.data(), idx.data(), idx.size());
        REQUIRE(pc.status == Status::Ok);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glUseProgram(g.caster_prog);
    glBindVertexArray(scene.vao);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glEnable(GL_DEPTH_CLAMP);
    glEnable(GL_SCISSOR_TEST);
    glDisable(GL_CULL_FACE);
    const GLint loc = glGetUniformLocation(g.caster_prog, "u_light_view_proj");
    const int pt = vsm.layout.page_texels;
    for (std::size_t i = 0; i < count; ++i) {
        glViewport(pages[i].atlas_x, pages[i].atlas_y, pt, pt);
        glScissor(pages[i].atlas_x, pages[i].atlas_y, pt, pt);
        glClearDepth(1.0);
        glClear(GL_DEPTH_BUFFER_BIT);
        const VsmMatrix m = vsm_relative_matrix(pages[i].view_proj, scene.anchor);
        REQUIRE(m.status == Status::Ok);
        glUniformMatrix4fv(loc, 1, GL_FALSE, glm::value_ptr(m.matrix));
        if (cull)
            for (std::uint32_t k = 0; k < counts[i]; ++k) scene.draw(idx[first[i] + k]);
        else
            for (std::size_t b = 0; b < scene.boxes.size(); ++b) scene.draw(b);
    }
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_DEPTH_CLAMP);
}

GLuint make_atlas(int size, GLuint& fbo) {
    GLuint tex = skgl::make_depth_texture(GL_TEXTURE_2D, size, 1, GL_NEAREST, GL_CLAMP_TO_EDGE);
    skgl::set_depth_compare(tex, false, false);
    skgl::make_depth_framebuffers(GL_TEXTURE_2D, tex, 1, &fbo);
    return tex;
}

std::vector<std::uint32_t> read_atlas(GLuint tex, int size) {
    std::vector<float> f(std::size_t(size) * std::size_t(size));
    glGetTextureImage(tex, 0, GL_DEPTH_COMPONENT, GL_FLOAT, GLsizei(f.size() * 4), f.data());
    std::vector<std::uint32_t> u(f.size());
    std::memcpy(u.data(), f.data(), f.size() * 4);
    return u;
}

// G-buffer of the scene from the camera (anchor = camera position).
void gbuffer_pass(const Scene& scene, const Gpu& g, const glm::dvec3& target) {
    const glm::mat4 view = glm::lookAt(glm::vec3(0.0f), glm::vec3(target - scene.anchor), glm::vec3(0, 1, 0));
    const glm::mat4 vp = glm::perspective(kFovY, float(kW) / float(kH), 0.05f, 300.0f) * view;
    glBindFramebuffer(GL_FRAMEBUFFER, g.gbuffer.fbo);
    glViewport(0, 0, kW, kH);
    glClearColor(0, 0, 0, 0);
    glClearDepth(1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glUseProgram(g.gbuffer_prog);
    glUniformMatrix4fv(glGetUniformLocation(g.gbuffer_prog, "u_view_proj"), 1, GL_FALSE, glm::value_ptr(vp));
    glBindVertexArray(scene.vao);
    for (std::size_t b = 0; b < scene.boxes.size(); ++b) scene.draw(b);
}

void upload_block(const VsmState& vsm, const Scene& scene, const Gpu& g) {
    std::vector<std::uint32_t> block(vsm_gpu_block_words(vsm));
    const VsmGpuBlock r = vsm_gpu_block(vsm, scene.anchor, block.data(), block.size());
    REQUIRE(r.status == Status::Ok);
    glNamedBufferSubData(g.data_ssbo, 0, GLsizeiptr(block.size() * 4), block.data());
}

// Marks on the GPU; returns the mask read back.
std::vector<std::uint32_t> mark_pass(const VsmState& vsm, const Gpu& g, float pixel_angle) {
    const std::size_t words = vsm_bitmask_words(vsm);
    const std::uint32_t zero = 0;
    glClearNamedBufferData(g.mask_ssbo, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    glBindFramebuffer(GL_FRAMEBUFFER, g.vis.fbo);
    glViewport(0, 0, kW, kH);
    glDisable(GL_DEPTH_TEST);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glUseProgram(g.mark_prog);
    glUniform1f(glGetUniformLocation(g.mark_prog, "u_pixel_angle"), pixel_angle);
    glBindTextureUnit(3, g.gbuffer.color[0]);
    glBindVertexArray(g.empty_vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<std::uint32_t> mask(words);
    glGetNamedBufferSubData(g.mask_ssbo, 0, GLsizeiptr(words * 4), mask.data());
    return mask;
}

struct Agreement {
    std::size_t counted = 0, agree = 0, holes = 0, lit = 0;
};

// The lookup (vis: visibility, used level per pixel) against a ray cast toward the light from the
// G-buffer's positions, over pixels whose 5x5 neighbourhood has one truth and one normal.
Agreement agree_with_ray_cast(const Scene& scene, const glm::dvec3& camera, const glm::dvec3& to_light, const std::vector<float>& pos,
                              const std::vector<float>& nrm, const std::vector<float>& vis) {
    Agreement r;
    std::vector<int> truth(std::size_t(kW * kH), -1);
    for (int i = 0; i < kW * kH; ++i) {
        if (pos[std::size_t(i) * 4 + 3] == 0.0f) continue;
        const glm::dvec3 p = camera + glm::dvec3(pos[std::size_t(i) * 4], pos[std::size_t(i) * 4 + 1], pos[std::size_t(i) * 4 + 2]);
        bool hit = false;
        for (const Box& b : scene.boxes) hit = hit || ray_hits(b, p, to_light);
        truth[std::size_t(i)] = hit ? 0 : 1;
    }
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const std::size_t i = std::size_t(y * kW + x);
            if (truth[i] < 0) continue;
            r.holes += vis[i * 2 + 1] < 0.0f;
            bool edge = false;
            for (int dy = -2; dy <= 2 && !edge; ++dy)
                for (int dx = -2; dx <= 2 && !edge; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    if (xx < 0 || yy < 0 || xx >= kW || yy >= kH) { edge = true; break; }
                    const std::size_t j = std::size_t(yy * kW + xx);
                    edge = truth[j] != truth[i] || nrm[j * 4] != nrm[i * 4] || nrm[j * 4 + 1] != nrm[i * 4 + 1] ||
                           nrm[j * 4 + 2] != nrm[i * 4 + 2];
                }
            if (edge) continue;
            ++r.counted;
            r.lit += truth[i];
            r.agree += (vis[i * 2] > 0.5f) == (truth[i] == 1);
        }
    return r;
}

// The whole check on the scene moved by `offset` (world units; the boxes' float bounds round there,
// and the renderer, the plan and the ray cast all use those rounded bounds).
void run_scene(const glm::dvec3& offset) {
    gl_test_context();
    Scene scene;
    scene.boxes = {{{-60.0f, -1.0f, -60.0f, 60.0f, 0.0f, 60.0f}},   // ground (top at y = 0)
                   {{-2.0f, 0.0f, -3.0f, 0.0f, 2.5f, -1.0f}},       // boxes on it
                   {{1.5f, 0.0f, -6.0f, 2.5f, 4.0f, -5.0f}},
                   {{-5.0f, 0.0f, -10.0f, -3.0f, 1.0f, -7.0f}},
                   {{3.0f, 0.5f, 0.0f, 4.0f, 1.5f, 1.0f}},           // floating: its shadow is detached
                   {{-1.0f, 0.0f, -25.0f, 6.0f, 6.0f, -20.0f}}};
    for (Box& b : scene.boxes)
        for (int k = 0; k < 6; ++k) b.b[k] = float(double(b.b[k]) + offset[k % 3]);
    const glm::dvec3 camera = offset + glm::dvec3(0.25, 5.0, 9.0), target = offset + glm::dvec3(0.0, 0.0, -6.0);
    scene.anchor = camera;
    scene.upload();
    const glm::vec4 light(0.35f, 0.55f, -0.6f, 0.0f);  // a low sun behind the boxes: long shadows toward the camera
    const glm::dvec3 to_light = glm::normalize(glm::dvec3(light));
    const float pixel_angle = 2.0f * std::tan(0.5f * kFovY) / float(kH);

    VsmLayout layout = vsm_ref::test_layout();
    VsmState vsm;
    REQUIRE(vsm_state_init(layout, vsm).status == Status::Ok);
    std::vector<VsmPageRender> pages(std::size_t(layout.pool_pages));
    VsmFrame f;
    f.camera_position = camera;
    f.light_position = light;
    REQUIRE(vsm_plan(vsm, f, pages.data(), pages.size()).status == Status::Ok);  // place the windows

    Gpu g;
    std::string why;
    REQUIRE(skgl::make_target(g.gbuffer, kW, kH, {GL_RGBA32F, GL_RGBA32F}, GL_DEPTH_COMPONENT32F, why));
    REQUIRE(skgl::make_target(g.vis, kW, kH, {GL_RG32F}, 0, why));
    g.gbuffer_prog = program(kGbufferVS, kGbufferFS);
    g.caster_prog = program(kCasterVS, kCasterFS);
    const std::string snip = snippet();
    g.mark_prog = program(kFullscreenVS, "#version 450 core\n" + snip + kMarkFS);
    g.lookup_prog = program(kFullscreenVS, "#version 450 core\n" + snip + kLookupFS);
    glCreateVertexArrays(1, &g.empty_vao);
    glCreateBuffers(1, &g.data_ssbo);
    glCreateBuffers(1, &g.mask_ssbo);
    glNamedBufferStorage(g.data_ssbo, GLsizeiptr(vsm_gpu_block_words(vsm) * 4), nullptr, GL_DYNAMIC_STORAGE_BIT);
    glNamedBufferStorage(g.mask_ssbo, GLsizeiptr(vsm_bitmask_words(vsm) * 4), nullptr, GL_DYNAMIC_STORAGE_BIT);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, g.data_ssbo);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, g.mask_ssbo);
    g.atlas_size = vsm.layout.pool_columns * layout.page_texels;
    g.atlas = make_atlas(g.atlas_size, g.atlas_fbo);

    // ---- (a) marking
    gbuffer_pass(scene, g, target);
    upload_block(vsm, scene, g);
    const std::vector<std::uint32_t> mask = mark_pass(vsm, g, pixel_angle);
    const std::vector<float> pos = skgl::read_color_float(g.gbuffer, 0, 4);
    const std::vector<float> nrm = skgl::read_color_float(g.gbuffer, 1, 4);
    const std::size_t bits = std::size_t(layout.level_count) * std::size_t(vsm.pages_per_side * vsm.pages_per_side);
    std::vector<glm::dvec3> rel;  // the covered pixels' positions relative to the camera
    for (int i = 0; i < kW * kH; ++i)
        if (pos[std::size_t(i) * 4 + 3] != 0.0f) rel.emplace_back(pos[std::size_t(i) * 4], pos[std::size_t(i) * 4 + 1], pos[std::size_t(i) * 4 + 2]);
    const auto [covered, gpu_set, sure_n, maybe_n, missing, extra] = vsm_ref::mark_tally(vsm, camera, pixel_angle, rel, mask);
    MESSAGE("marking: ", covered, " pixels, GPU set ", gpu_set, " page bits; CPU sure ", sure_n, ", maybe ", maybe_n);
    CHECK(covered > std::size_t(kW * kH / 2));
    CHECK(missing == 0);
    CHECK(extra == 0);
    CHECK(sure_n > 20);
    CHECK(maybe_n - sure_n <= sure_n / 10);

    // ---- (b) plan, render the listed pages, look up
    std::vector<VsmPageRequest> req(bits);
    const VsmRequestList rl = vsm_requests_from_bitmask(vsm, mask.data(), mask.size(), req.data(), req.size());
    REQUIRE(rl.status == Status::Ok);
    f.requests = req.data();
    f.request_count = rl.count;
    const VsmPlan plan = vsm_plan(vsm, f, pages.data(), pages.size());
    REQUIRE(plan.status == Status::Ok);
    CHECK(plan.count == rl.count);
    render_pages(vsm, scene, g, g.atlas_fbo, pages.data(), plan.count, true);
    upload_block(vsm, scene, g);

    auto lookup = [&](std::vector<float>& vis) {
        glBindFramebuffer(GL_FRAMEBUFFER, g.vis.fbo);
        glViewport(0, 0, kW, kH);
        glDisable(GL_DEPTH_TEST);
        glUseProgram(g.lookup_prog);
        glUniform1f(glGetUniformLocation(g.lookup_prog, "u_pixel_angle"), pixel_angle);
        glBindTextureUnit(0, g.atlas);
        glBindTextureUnit(3, g.gbuffer.color[0]);
        glBindTextureUnit(4, g.gbuffer.color[1]);
        glBindVertexArray(g.empty_vao);
        glDrawArrays(GL_TRIANGLES, 0, 3);
        vis = skgl::read_color_float(g.vis, 0, 2);
    };
    std::vector<float> vis;
    lookup(vis);
    const Agreement ag = agree_with_ray_cast(scene, camera, to_light, pos, nrm, vis);
    const std::size_t counted = ag.counted, lit_n = ag.lit, holes = ag.holes, agree = ag.agree;
    const double agreement = double(agree) / double(std::max<std::size_t>(counted, 1));
    MESSAGE("lookup: ", plan.count, " pages rendered, ", counted, " pixels away from edges (", lit_n, " lit), agreement ",
            agreement, ", pixels without a page ", holes);
    CHECK(counted > std::size_t(kW * kH / 4));
    CHECK(lit_n > counted / 4);
    CHECK(counted - lit_n > counted / 20);
    CHECK(agreement >= 0.995);
    CHECK(holes == 0);

    // ---- (c) move one caster, invalidate, re-render the listed pages only
    const std::vector<std::uint32_t> before = read_atlas(g.atlas, g.atlas_size);
    VsmCasterMove move;
    std::memcpy(move.previous_bounds, scene.boxes[2].b, sizeof(move.previous_bounds));
    scene.boxes[2].b[0] += 1.25f;
    scene.boxes[2].b[3] += 1.25f;
    scene.boxes[2].b[2] -= 0.5f;
    scene.boxes[2].b[5] -= 0.5f;
    std::memcpy(move.bounds, scene.boxes[2].b, sizeof(move.bounds));
    scene.upload();
    gbuffer_pass(scene, g, target);
    const std::vector<std::uint32_t> mask2 = mark_pass(vsm, g, pixel_angle);
    const VsmRequestList rl2 = vsm_requests_from_bitmask(vsm, mask2.data(), mask2.size(), req.data(), req.size());
    REQUIRE(rl2.status == Status::Ok);
    f.requests = req.data();
    f.request_count = rl2.count;
    f.moved_casters = &move;
    f.moved_caster_count = 1;
    const VsmPlan plan2 = vsm_plan(vsm, f, pages.data(), pages.size());
    REQUIRE(plan2.status == Status::Ok);
    render_pages(vsm, scene, g, g.atlas_fbo, pages.data(), plan2.count, true);
    const std::vector<std::uint32_t> kept = read_atlas(g.atlas, g.atlas_size);

    // the full re-render: every current page into a fresh atlas, all casters, no culling
    GLuint full_fbo = 0;
    const GLuint full = make_atlas(g.atlas_size, full_fbo);
    std::vector<VsmPageRender> all;
    for (std::uint32_t s = 0; s < std::uint32_t(layout.pool_pages); ++s) {
        const VsmSlotPage sp = vsm_slot_page(vsm, s);
        REQUIRE(sp.status == Status::Ok);
        if (sp.resident && sp.current) all.push_back(sp.page);
    }
    render_pages(vsm, scene, g, full_fbo, all.data(), all.size(), false);
    const std::vector<std::uint32_t> ref = read_atlas(full, g.atlas_size);
    std::size_t differing_pages = 0, changed_by_move = 0;
    const int pt = layout.page_texels;
    for (const VsmPageRender& p : all) {
        bool differs = false, changed = false;
        for (int y = 0; y < pt; ++y)
            for (int x = 0; x < pt; ++x) {
                const std::size_t i = std::size_t(p.atlas_y + y) * std::size_t(g.atlas_size) + std::size_t(p.atlas_x + x);
                differs = differs || kept[i] != ref[i];
                changed = changed || before[i] != ref[i];
            }
        differing_pages += differs;
        changed_by_move += changed;
    }
    MESSAGE("moved caster: ", plan2.invalidated, " pages invalidated, ", plan2.rerendered, " re-rendered, ", plan2.allocated,
            " newly allocated, of ", all.size(), " current pages; ", changed_by_move, " pages differ from the frame before");
    CHECK(differing_pages == 0);
    CHECK(changed_by_move > 0);
    CHECK(plan2.rerendered > 0);
    CHECK(plan2.count < all.size() / 2);

    // the lookup after the move agrees with the ray cast as well
    std::vector<float> vis2;
    upload_block(vsm, scene, g);
    lookup(vis2);
    const std::vector<float> pos2 = skgl::read_color_float(g.gbuffer, 0, 4);
    const std::vector<float> nrm2 = skgl::read_color_float(g.gbuffer, 1, 4);
    const Agreement ag2 = agree_with_ray_cast(scene, camera, to_light, pos2, nrm2, vis2);
    MESSAGE("after the move: agreement ", double(ag2.agree) / double(std::max<std::size_t>(ag2.counted, 1)), " over ", ag2.counted,
            " pixels, pixels without a page ", ag2.holes);
    CHECK(double(ag2.agree) >= 0.995 * double(ag2.counted));
    CHECK(ag2.holes == 0);

    // ---- (d) a pool of half the requested pages: the plan falls back to coarser pages, the lookup
    // walks up to them through the table: no pixel without a page, coarser texels
    VsmLayout small = layout;
    small.pool_pages = int(rl2.count / 2);
    VsmState vsm_small;
    REQUIRE(vsm_state_init(small, vsm_small).status == Status::Ok);
    VsmFrame fs = f;
    fs.moved_casters = nullptr;
    fs.moved_caster_count = 0;
    const VsmPlan plan_small = vsm_plan(vsm_small, fs, pages.data(), pages.size());
    REQUIRE(plan_small.status == Status::BufferTooSmall);
    CHECK(plan_small.fallback > 0);
    CHECK(plan_small.unmapped == 0);
    render_pages(vsm_small, scene, g, g.atlas_fbo, pages.data(), plan_small.count, true);
    upload_block(vsm_small, scene, g);
    std::vector<float> vis3;
    lookup(vis3);
    const Agreement ag3 = agree_with_ray_cast(scene, camera, to_light, pos2, nrm2, vis3);
    std::size_t coarser = 0;
    for (std::size_t i = 0; i < vis3.size() / 2; ++i) coarser += vis3[i * 2 + 1] > vis2[i * 2 + 1];
    MESSAGE("pool of ", small.pool_pages, " pages: ", plan_small.fallback, " requests fell back, ", coarser,
            " pixels on a coarser level, agreement ", double(ag3.agree) / double(std::max<std::size_t>(ag3.counted, 1)),
            ", pixels without a page ", ag3.holes);
    CHECK(ag3.holes == 0);
    CHECK(coarser > 1000);
    CHECK(double(ag3.agree) >= 0.99 * double(ag3.counted));
    CHECK(skgl::gl_error_string().empty());
}

}  // namespace

TEST_CASE("virtual shadow map on GL: GPU marks match the CPU, the lookup matches a ray cast, a moved caster re-renders only its pages") {
    run_scene(glm::dvec3(0.0));
}

TEST_CASE("virtual shadow map on GL, 1e6 units from the origin: the camera-relative block keeps the same agreement") {
    run_scene(glm::dvec3(1.0e6, 0.0, -1.0e6));
}
