// samples/virtual_shadow_maps/virtual_shadow_maps.cpp - virtual shadow maps, top to bottom:
//   init    once per scene: each caster mesh's bounds (for the per-page culling), the programs, the V target
//   update  CPU, every frame: the sun and the camera of this frame (the clipmap levels center on it)
//   render  every frame: 1 mark: a full-screen pass over the G-buffer sets the bit of every page the
//           pixel's lookup will read (sk_vsm_mark: the level from the pixel's footprint), read back;
//           2 plan (CPU, vsm_plan): keep the resident pages, give the new ones a slot, list them;
//           3 render only the listed pages, each into its own viewport of the depth atlas, with the
//           casters vsm_page_casters lists for it; 4 V at the G-buffer's points: sk_vsm_visibility walks
//           the page table (a coarser level where a page is missing) and compares with the receiver
//           plane's depth (the automatic bias: no polygon offset)
#include "virtual_shadow_maps.hpp"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>

namespace {

// The marking pass: the G-buffer's positions at unit 0 (w: 0 background), the anchor (the camera: the
// snippet's positions are relative to it), the footprint's pixel angle, the level bias and the PCF radius
// (the kernel's pages are marked too).
const char* kMark = R"(
layout(binding = 0) uniform sampler2D u_gbuf_position;
uniform vec3 u_anchor;
uniform vec3 u_eye;  // the G-buffer's camera: the footprint is its pixel's
uniform float u_pixel_angle;
uniform float u_lod_bias;
uniform int u_pcf_radius;
void main() {
    vec4 p = texelFetch(u_gbuf_position, ivec2(gl_FragCoord.xy), 0);
    if (p.w == 0.0) discard;
    vec3 rel = p.xyz - u_anchor;
    sk_vsm_mark(rel, sk_vsm_level_for_footprint(length(p.xyz - u_eye) * u_pixel_angle, u_lod_bias), u_pcf_radius);
}
)";

// V: the physical pool at unit 2 (a depth texture read raw), the same level rule as the marking.
const char* kLookup = R"(
layout(binding = 2) uniform sampler2D u_pool;
uniform vec3 u_anchor;
uniform vec3 u_eye;
uniform float u_pixel_angle;
uniform float u_lod_bias;
uniform int u_pcf_radius;
float technique_visibility(vec3 p, vec3 n) {
    vec3 rel = p - u_anchor;
    int level = sk_vsm_level_for_footprint(length(p - u_eye) * u_pixel_angle, u_lod_bias);
    return sk_vsm_visibility(u_pool, rel, n, level, u_pcf_radius, 0.0);  // float32 pool: depth_step 0
}
)";

// The debug view: level hue and page borders over the picture (background: transparent).
const char* kDebug = R"(
layout(binding = 0) uniform sampler2D u_gbuf_position;
uniform vec3 u_anchor;
uniform vec3 u_eye;
uniform float u_pixel_angle;
uniform float u_lod_bias;
layout(location = 0) out vec4 o_color;
void main() {
    vec4 p = texelFetch(u_gbuf_position, ivec2(gl_FragCoord.xy), 0);
    if (p.w == 0.0) { o_color = vec4(0.0); return; }
    vec3 rel = p.xyz - u_anchor;
    o_color = vec4(sk_vsm_debug_color(rel, sk_vsm_level_for_footprint(length(p.xyz - u_eye) * u_pixel_angle, u_lod_bias)), 0.7);
}
)";

void set_level_uniforms(GLuint prog, const glm::dvec3& anchor, const glm::vec3& eye, float pixel_angle,
                        const VirtualShadowMapSettings& s) {
    glUniform3f(glGetUniformLocation(prog, "u_anchor"), float(anchor.x), float(anchor.y), float(anchor.z));
    glUniform3fv(glGetUniformLocation(prog, "u_eye"), 1, glm::value_ptr(eye));
    glUniform1f(glGetUniformLocation(prog, "u_pixel_angle"), pixel_angle);
    glUniform1f(glGetUniformLocation(prog, "u_lod_bias"), s.lod_bias);
    glUniform1i(glGetUniformLocation(prog, "u_pcf_radius"), s.pcf_radius);
}

}  // namespace

bool VirtualShadowMaps::init(const app::View& v, std::string& why) {
    release();
    caster_boxes_.clear();
    caster_mesh_.clear();
    for (std::size_t m = 0; m < v.scene->meshes.size(); ++m) {
        const sk::Mesh& mesh = v.scene->meshes[m];
        if (!mesh.caster || mesh.positions.empty()) continue;
        glm::vec3 lo(INFINITY), hi(-INFINITY);
        for (const glm::vec3& p : mesh.positions) { lo = glm::min(lo, p); hi = glm::max(hi, p); }
        caster_boxes_.insert(caster_boxes_.end(), {lo.x, lo.y, lo.z, hi.x, hi.y, hi.z});
        caster_mesh_.push_back(m);
    }
    diag_ = std::max(glm::length(v.scene->bounds_max() - v.scene->bounds_min()), 1e-3f);
    const std::string snippet = app::load_snippet("virtual_shadow_map", why);
    if (snippet.empty()) return false;
    depth_prog_ = skgl::depth_only_program(why);  // gl_Position = u_light_view_proj * a_position, no color
    mark_prog_ = app::compile_fullscreen_program("#version 450 core\n" + snippet + kMark, why);
    debug_prog_ = app::compile_fullscreen_program("#version 450 core\n" + snippet + kDebug, why);
    vis_prog_ = app::compile_visibility_program(snippet, kLookup, why);
    if (!depth_prog_ || !mark_prog_ || !debug_prog_ || !vis_prog_) return false;
    glCreateVertexArrays(1, &empty_vao_);
    if (!skgl::make_target(debug_, v.width, v.height, {GL_RGBA8}, 0, why)) return false;
    return pass_.init(v.width, v.height, why);
}

void VirtualShadowMaps::update(const app::View& v, const VirtualShadowMapSettings&) {
    const sk::Light& L = v.light();
    error_.clear();
    if (L.type != sk::LightType::Directional) error_ = "virtual shadow maps here take the sun (a directional light)";
    frame_ = shadowkit::VsmFrame();
    frame_.camera_position = glm::dvec3(v.camera.eye);
    frame_.light_position = glm::vec4(-glm::normalize(L.direction), 0.f);  // w = 0, xyz toward the sun
    anchor_ = frame_.camera_position;
    // the G-buffer's pixel footprint: its camera's eye and pixel angle (the pixels are its; the report's
    // temporal rows move the fit camera, which the levels center on, and keep the G-buffer)
    eye_ = v.gpu->camera.eye;
    pixel_angle_ = 2.f * std::tan(0.5f * v.gpu->camera.fovy) / float(std::max(v.gpu->height, 1));
}

// The pool (a GL_DEPTH_COMPONENT32F atlas of pool_columns x rows pages, read raw: compare mode off,
// GL_NEAREST), the GPU block and the request bitmask (SSBOs at bindings 0 and 1), the CPU state.
bool VirtualShadowMaps::make_pool(const VirtualShadowMapSettings& s) {
    shadowkit::VsmLayout layout;
    layout.page_texels = s.page_texels;
    layout.virtual_texels = s.virtual_texels;
    layout.level_count = s.levels;
    layout.pool_pages = s.pool_pages;
    // the coarsest level covers 2^k times the scene's diagonal (k >= 1, power-of-two steps keep one texel
    // grid whatever the viewport): the least k that gives its texels a quarter of a pixel at twice the
    // diagonal. A small scene seen whole then finds its level below the coarsest (with twice the
    // diagonal alone, every pixel sat on the coarsest level, and a pool smaller than its pages left holes)
    const double reach = 2.0 * double(diag_);
    const double wanted = 0.25 * double(s.virtual_texels) * reach * double(pixel_angle_);
    const double coarsest = reach * std::exp2(std::ceil(std::log2(std::max(wanted / reach, 1.0))));  // 2 diagonals x 2^k
    layout.level0_extent_world = coarsest / std::ldexp(1.0, s.levels - 1);
    layout.depth_range_world = 2.0 * double(diag_);
    if (shadowkit::vsm_state_init(layout, state_).status != shadowkit::Status::Ok) return false;
    const int cols = state_.layout.pool_columns, rows = (s.pool_pages + cols - 1) / cols;
    if (atlas_) glDeleteTextures(1, &atlas_);
    if (atlas_fbo_) glDeleteFramebuffers(1, &atlas_fbo_);
    glCreateTextures(GL_TEXTURE_2D, 1, &atlas_);
    glTextureStorage2D(atlas_, 1, GL_DEPTH_COMPONENT32F, cols * s.page_texels, rows * s.page_texels);
    glTextureParameteri(atlas_, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(atlas_, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTextureParameteri(atlas_, GL_TEXTURE_COMPARE_MODE, GL_NONE);
    glCreateFramebuffers(1, &atlas_fbo_);
    glNamedFramebufferTexture(atlas_fbo_, GL_DEPTH_ATTACHMENT, atlas_, 0);
    glNamedFramebufferDrawBuffer(atlas_fbo_, GL_NONE);
    glNamedFramebufferReadBuffer(atlas_fbo_, GL_NONE);
    if (data_ssbo_) glDeleteBuffers(1, &data_ssbo_);
    if (mask_ssbo_) glDeleteBuffers(1, &mask_ssbo_);
    block_.assign(shadowkit::vsm_gpu_block_words(state_), 0u);
    mask_.assign(shadowkit::vsm_bitmask_words(state_), 0u);
    glCreateBuffers(1, &data_ssbo_);
    glNamedBufferStorage(data_ssbo_, GLsizeiptr(block_.size() * 4), nullptr, GL_DYNAMIC_STORAGE_BIT);
    glCreateBuffers(1, &mask_ssbo_);
    glNamedBufferStorage(mask_ssbo_, GLsizeiptr(mask_.size() * 4), nullptr, GL_DYNAMIC_STORAGE_BIT);
    const std::size_t pages = std::size_t(s.pool_pages);
    pages_.assign(pages, shadowkit::VsmPageRender());
    requests_.assign(std::size_t(s.levels) * std::size_t(state_.pages_per_side) * std::size_t(state_.pages_per_side),
                     shadowkit::VsmPageRequest());
    first_.assign(pages, 0u);
    counts_.assign(pages, 0u);
    indices_.assign(pages * std::max<std::size_t>(caster_mesh_.size(), 1), 0u);
    made_ = s;
    have_pool_ = true;
    stats_ = VirtualShadowMapStats();
    return true;
}

void VirtualShadowMaps::upload_block() {
    if (shadowkit::vsm_gpu_block(state_, anchor_, block_.data(), block_.size()).status == shadowkit::Status::Ok)
        glNamedBufferSubData(data_ssbo_, 0, GLsizeiptr(block_.size() * 4), block_.data());
}

// 1. Marking: a full-screen pass over the G-buffer, no colour writes, no depth test; each covered
//    pixel sets its pages' bits with atomicOr; the bitmask is read back after a barrier.
void VirtualShadowMaps::mark(const app::View& v, const VirtualShadowMapSettings& s) {
    const std::uint32_t zero = 0;
    glClearNamedBufferData(mask_ssbo_, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, data_ssbo_);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, mask_ssbo_);
    glBindFramebuffer(GL_FRAMEBUFFER, debug_.fbo);
    glViewport(0, 0, v.width, v.height);
    app::begin_fullscreen_pass();
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glUseProgram(mark_prog_);
    set_level_uniforms(mark_prog_, anchor_, eye_, pixel_angle_, s);
    glBindTextureUnit(0, v.gpu->gbuffer.color[0]);
    glBindVertexArray(empty_vao_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(mask_ssbo_, 0, GLsizeiptr(mask_.size() * 4), mask_.data());
}

// 3. The listed pages: viewport and scissor = the page's square of the atlas, depth cleared to 1,
//    GL_LESS, depth clamp (casters beyond the page's depth range still occlude), no polygon offset;
//    each page draws only the caster meshes vsm_page_casters lists for it.
void VirtualShadowMaps::render_pages(const app::View& v, std::size_t count) {
    stats_.triangles_drawn = 0;
    if (count == 0) return;
    const shadowkit::VsmPageCasters pc =
        shadowkit::vsm_page_casters(state_, pages_.data(), count, caster_boxes_.data(), caster_mesh_.size(), first_.data(),
                                    counts_.data(), indices_.data(), indices_.size());
    const bool culled = pc.status == shadowkit::Status::Ok;
    glBindFramebuffer(GL_FRAMEBUFFER, atlas_fbo_);
    glUseProgram(depth_prog_);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glEnable(GL_DEPTH_CLAMP);
    glEnable(GL_SCISSOR_TEST);
    glClearDepth(1.0);
    const GLint loc = glGetUniformLocation(depth_prog_, "u_light_view_proj");
    const int pt = state_.layout.page_texels;
    for (std::size_t i = 0; i < count; ++i) {
        const shadowkit::VsmPageRender& p = pages_[i];
        glViewport(p.atlas_x, p.atlas_y, pt, pt);
        glScissor(p.atlas_x, p.atlas_y, pt, pt);
        glClear(GL_DEPTH_BUFFER_BIT);
        // the meshes are in world units near the origin: the matrix relative to the origin
        const shadowkit::VsmMatrix m = shadowkit::vsm_relative_matrix(p.view_proj, glm::dvec3(0.0));
        if (m.status != shadowkit::Status::Ok) continue;
        glUniformMatrix4fv(loc, 1, GL_FALSE, glm::value_ptr(m.matrix));
        const std::size_t n = culled ? counts_[i] : caster_mesh_.size();
        for (std::size_t k = 0; k < n; ++k) {
            const std::size_t mesh = caster_mesh_[culled ? indices_[first_[i] + k] : k];
            skgl::draw_mesh(v.gpu->meshes[mesh]);
            stats_.triangles_drawn += std::size_t(v.gpu->meshes[mesh].index_count / 3);
        }
    }
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_DEPTH_CLAMP);
}

// The debug view, drawn only when shown: the last frame's G-buffer, block and settings.
app::DebugImage VirtualShadowMaps::debug_pages() {
    if (!debug_prog_ || debug_.color.empty() || !have_pool_ || debug_positions_ == 0) return {};
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, data_ssbo_);
    glBindFramebuffer(GL_FRAMEBUFFER, debug_.fbo);
    glViewport(0, 0, debug_.width, debug_.height);
    app::begin_fullscreen_pass();
    glUseProgram(debug_prog_);
    set_level_uniforms(debug_prog_, anchor_, eye_, pixel_angle_, last_settings_);
    glBindTextureUnit(0, debug_positions_);
    glBindVertexArray(empty_vao_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    return {debug_.color[0], app::DebugImage::Show::Overlay};
}

void VirtualShadowMaps::render(const app::View& v, const VirtualShadowMapSettings& s) {
    const bool same = have_pool_ && made_.page_texels == s.page_texels && made_.virtual_texels == s.virtual_texels &&
                      made_.levels == s.levels && made_.pool_pages == s.pool_pages;
    if (!same && !make_pool(s)) error_ = "vsm_state_init refused the layout";
    if (!error_.empty()) {  // no sun: V = 1 (the light rules still shade the back faces)
        glBindFramebuffer(GL_FRAMEBUFFER, pass_.target.fbo);
        glClearColor(1.f, 1.f, 1.f, 1.f);
        glClear(GL_COLOR_BUFFER_BIT);
        return;
    }
    // this frame's windows (a plan without requests places the levels), then mark with them
    shadowkit::VsmFrame place = frame_;
    shadowkit::vsm_plan(state_, place, pages_.data(), pages_.size());
    upload_block();
    mark(v, s);
    // 2. plan: the requests from the bitmask
    const shadowkit::VsmRequestList rl =
        shadowkit::vsm_requests_from_bitmask(state_, mask_.data(), mask_.size(), requests_.data(), requests_.size());
    frame_.requests = requests_.data();
    frame_.request_count = rl.count;
    const shadowkit::VsmPlan plan = shadowkit::vsm_plan(state_, frame_, pages_.data(), pages_.size());
    const bool planned = plan.status == shadowkit::Status::Ok || plan.status == shadowkit::Status::BufferTooSmall;
    render_pages(v, planned ? plan.count : 0);
    stats_.requested = plan.requested;
    stats_.rendered = planned ? plan.count : 0;
    stats_.evicted = plan.evicted;
    stats_.kept = plan.kept;
    stats_.fallback = plan.fallback;
    stats_.resident = state_.slots.size() - state_.free_count;
    if (stats_.frames++ == 0) {
        stats_.first_frame_rendered = stats_.rendered;
        stats_.first_frame_triangles = stats_.triangles_drawn;
    }
    // 4. V through the page table
    upload_block();
    glUseProgram(vis_prog_);
    app::set_light_uniforms(vis_prog_, v.light());
    set_level_uniforms(vis_prog_, anchor_, eye_, pixel_angle_, s);
    pass_.draw(vis_prog_, *v.gpu, GL_TEXTURE_2D, atlas_);
    debug_positions_ = v.gpu->gbuffer.color[0];
    last_settings_ = s;
}

void VirtualShadowMaps::release() {  // (no GL call without objects: the App may have no context)
    if (atlas_) glDeleteTextures(1, &atlas_);
    if (atlas_fbo_) glDeleteFramebuffers(1, &atlas_fbo_);
    if (data_ssbo_) glDeleteBuffers(1, &data_ssbo_);
    if (mask_ssbo_) glDeleteBuffers(1, &mask_ssbo_);
    if (empty_vao_) glDeleteVertexArrays(1, &empty_vao_);
    for (GLuint* p : {&depth_prog_, &mark_prog_, &vis_prog_, &debug_prog_})
        if (*p) glDeleteProgram(*p);
    if (debug_.fbo) skgl::destroy_target(debug_);
    atlas_ = atlas_fbo_ = data_ssbo_ = mask_ssbo_ = empty_vao_ = 0;
    depth_prog_ = mark_prog_ = vis_prog_ = debug_prog_ = 0;
    have_pool_ = false;
    error_.clear();
}
