// samples/cascaded_shadow_maps/cascaded_shadow_maps.cpp - cascaded shadow maps, top to bottom:
//   init    once per scene: the casters' bounds, the programs, the V target
//   update  CPU, every frame: cascade_fit cuts the camera's depth range at the practical split
//           distances and fits each slice a stable orthographic map (its near plane pulled back to the
//           casters between the sun and the slice)
//   render  GPU, every frame: 1 the casters' depth into each cascade's layer of one depth array
//           (bias=polygon_offset: with a slope-scaled offset); 2 V at the G-buffer's points: the
//           cascade the view depth selects (blended into the next over the band), with the automatic
//           bias of glsl/shadow_map.glsl (the default) or the offset's single compare, optionally the
//           point moved along its normal; pcf_radius > 0: a tent of that radius in texels in each layer
//           (pcf.glsl's array overloads) instead of the single 2x2 compare
//   fit=sdsm  update first reduces the G-buffer's depth to its min/max (glsl/cascades.glsl's
//           sk_sdsm_reduce_depth / sk_sdsm_reduce_minmax, blocks of 8, read back: two floats; a stall a
//           renderer would hide by reading last frame's), then cascade_sdsm_fit fits the cascades to
//           that range with last frame's fit as hysteresis (world_splits: the interior splits stay
//           on their world planes while the camera does not turn); render is the same
//   cache=on  cached cascades (the section "Cached cascades" below): update fits with the depth range
//           fixed in the world and plans each cascade (shadow_cache_plan); render scrolls the layers
//           that moved and re-renders only the planned rectangles, with the translation-invariant
//           caster pass of glsl/shadow_cache.glsl
#include "cascaded_shadow_maps.hpp"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>

namespace {

// What both lookups read: the cascade array at unit 2, the matrices, the splits (each cascade's near
// and far view depth), the blend band and the camera's view (the view depth selects the cascade).
const char* kCascadeInputs = R"(
layout(binding = 2) uniform sampler2DArrayShadow u_cascades;
uniform mat4 u_cascade_vp[4];
uniform vec4 u_split_near;
uniform vec4 u_split_far;
uniform int u_count;
uniform float u_band;
uniform mat4 u_camera_view;
uniform int u_pcf_radius;  // 0: the hardware 2x2; r: pcf.glsl's (2r+1)^2 tent in each cascade's layer
)";
// bias=polygon_offset's lookup (after glsl/pcf.glsl and glsl/cascades.glsl: the tent of radius 0 is
// one tap, sk_cascade_shadow's compare). The normal offset is in texels of the
// cascade that serves p, of the next one inside the blend band (the larger: both are read there); the
// depth pass's slope-scaled offset already keeps acne away, so it is 0 by default.
const char* kLookup = R"(
uniform float u_texel[4];       // Cascade::texel_world_size
uniform float u_normal_offset;  // texels
float technique_visibility(vec3 p, vec3 n) {
    float view_depth = -(u_camera_view * vec4(p, 1.0)).z;
    int i = sk_cascade_by_depth(view_depth, u_split_far, u_count);
    if (i < 0) return 1.0;  // beyond the last split: lit
    bool band = sk_cascade_blend(view_depth, u_split_near[i], u_split_far[i], u_band) > 0.0 && i + 1 < u_count;
    p += n * (u_normal_offset * u_texel[band ? i + 1 : i]);
    return sk_cascade_shadow_filtered(u_cascades, u_cascade_vp, u_split_near, u_split_far, u_count, p, view_depth,
                                      u_band, 0.0, false, SK_CASCADE_KERNEL_TENT, u_pcf_radius, 0, 0.0);
}
)";

// bias=auto: the same selection and blend, each cascade read with shadow_map.glsl's automatic bias on
// its layer (outside a cascade's map: lit, as sk_cascade_sample); the array is float32 (depth_step 0).
// pcf_radius > 0: the tent with the receiver plane from the normal and shadow_map.glsl's bias for
// filtered kernels (sk_auto_filtered_bias).
const char* kLookupAuto = R"(
float cascade_visibility(int i, vec3 p, vec3 n) {
    if (u_pcf_radius <= 0) return sk_shadow_map_visibility_auto(u_cascades, float(i), u_cascade_vp[i], p, n, false, 0.0, 1.0);
    vec4 c = sk_shadow_coord(u_cascade_vp[i], p, false);
    if (c.w <= 0.0 || any(lessThan(c.xy, vec2(0.0))) || any(greaterThan(c.xy, vec2(1.0))) || c.z > 1.0 || c.z < 0.0)
        return 1.0;
    vec4 g = sk_plane_depth_gradient(u_cascade_vp[i], p, n, false);
    if (g.z == 0.0) return 1.0;  // edge-on, as the automatic bias
    float b = sk_auto_filtered_bias(g, 1.0 / vec2(textureSize(u_cascades, 0).xy), c.z, 0.0);
    return sk_pcf_tent(u_cascades, float(i), vec3(c.xy, c.z - b), g.xy, u_pcf_radius);
}
float technique_visibility(vec3 p, vec3 n) {
    float view_depth = -(u_camera_view * vec4(p, 1.0)).z;
    int i = sk_cascade_by_depth(view_depth, u_split_far, u_count);
    if (i < 0) return 1.0;  // beyond the last split: lit
    float v = cascade_visibility(i, p, n);
    float w = sk_cascade_blend(view_depth, u_split_near[i], u_split_far[i], u_band);
    if (w > 0.0 && i + 1 < u_count) v = mix(v, cascade_visibility(i + 1, p, n), w);
    return v;
}
)";

// The SDSM reduction's passes (glsl/cascades.glsl): the depth buffer (unit 0, background 1.0: the
// G-buffer is cleared to 1 with GL_LESS) to blocks of 8, then each level to blocks of 8, down to 1x1.
const char* kReduceFirst = R"(
layout(binding = 0) uniform sampler2D u_src;
out vec2 o_minmax;
void main() { o_minmax = sk_sdsm_reduce_depth(u_src, ivec2(gl_FragCoord.xy), 8, 1.0); }
)";
const char* kReduceNext = R"(
layout(binding = 0) uniform sampler2D u_src;
out vec2 o_minmax;
void main() { o_minmax = sk_sdsm_reduce_minmax(u_src, ivec2(gl_FragCoord.xy), 8); }
)";

// The second reduction (receiver bounds per cascade): the G-buffer's depth to blocks of 8 into four
// RGBA32F targets, then each level's four to blocks of 8, down to 1x1.
const char* kBoundsFirst = R"(
layout(binding = 0) uniform sampler2D u_src;
uniform mat4 u_clip_to_world;
uniform mat4 u_world_to_view;
uniform mat4 u_world_to_light;
uniform vec4 u_split_far;
uniform int u_count;
layout(location = 0) out vec4 o_b0;
layout(location = 1) out vec4 o_b1;
layout(location = 2) out vec4 o_b2;
layout(location = 3) out vec4 o_b3;
void main() {
    vec4 b[4];
    sk_sdsm_reduce_bounds(u_src, ivec2(gl_FragCoord.xy), 8, 1.0, u_clip_to_world, u_world_to_view, u_world_to_light,
                          u_split_far, u_count, false, b);
    o_b0 = b[0]; o_b1 = b[1]; o_b2 = b[2]; o_b3 = b[3];
}
)";
const char* kBoundsNext = R"(
layout(binding = 0) uniform sampler2D u_l0;
layout(binding = 1) uniform sampler2D u_l1;
layout(binding = 2) uniform sampler2D u_l2;
layout(binding = 3) uniform sampler2D u_l3;
layout(location = 0) out vec4 o_b0;
layout(location = 1) out vec4 o_b1;
layout(location = 2) out vec4 o_b2;
layout(location = 3) out vec4 o_b3;
void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    o_b0 = sk_sdsm_reduce_bounds_level(u_l0, p, 8);
    o_b1 = sk_sdsm_reduce_bounds_level(u_l1, p, 8);
    o_b2 = sk_sdsm_reduce_bounds_level(u_l2, p, 8);
    o_b3 = sk_sdsm_reduce_bounds_level(u_l3, p, 8);
}
)";

// cache=on: the translation-invariant caster pass (glsl/shadow_cache.glsl, as samples/cached_shadow_map):
// the vertex in the cascade's global texel space (no anchor: the same bits every frame), exact
// whole-texel window positions, each texel's depth from its global texel on the triangle's plane;
// bias=polygon_offset adds a slope-scaled offset like glPolygonOffset(2, 2).
const char* kInvariantVS = R"(#version 450 core
layout(location = 0) in vec3 a_position;
uniform mat4 u_light_global;
out vec3 v_global;
void main() {
    v_global = (u_light_global * vec4(a_position, 1.0)).xyz;
    gl_Position = vec4(0.0);
}
)";
const char* kInvariantGS = R"(
layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;
in vec3 v_global[];
uniform ivec2 u_viewport_anchor;
uniform vec2 u_viewport_size;
flat out vec3 g_plane;
flat out vec2 g_origin;
void main() {
    vec3 plane;
    vec2 origin;
    if (!sk_shadow_cache_plane(v_global[0], v_global[1], v_global[2], plane, origin)) return;
    for (int i = 0; i < 3; ++i) {
        g_plane = plane;
        g_origin = origin;
        gl_Position = sk_shadow_cache_position(v_global[i].xy, u_viewport_anchor, u_viewport_size);
        EmitVertex();
    }
    EndPrimitive();
}
)";
const char* kInvariantFS = R"(
flat in vec3 g_plane;
flat in vec2 g_origin;
uniform ivec2 u_anchor;
uniform bool u_offset;
void main() {
    float d = sk_shadow_cache_depth(g_plane, g_origin, gl_FragCoord.xy, u_anchor);
    gl_FragDepth = u_offset ? min(d + sk_shadow_cache_depth_offset(g_plane, 2.0, 2.4e-7), 1.0) : d;
}
)";
constexpr int kGuardViewport = 4096;  // the invariant pass's viewport: the layer plus a guard band

}  // namespace

bool CascadedShadowMaps::init(const app::View& v, std::string& why) {
    release();
    caster_lo_ = glm::vec3(INFINITY);  // an empty box when nothing casts
    caster_hi_ = glm::vec3(-INFINITY);
    sk::caster_bounds(*v.scene, caster_lo_, caster_hi_);
    const std::string snippet = app::load_snippet("cascades", why);
    if (snippet.empty()) return false;
    const std::string shadow_map = app::load_snippet("shadow_map", why);  // the automatic bias
    if (shadow_map.empty()) return false;
    const std::string pcf = app::load_snippet("pcf", why);  // the tent of pcf_radius (array overloads)
    if (pcf.empty()) return false;
    depth_prog_ = skgl::depth_only_program(why);  // gl_Position = u_light_view_proj * a_position, no color
    vis_prog_ = app::compile_visibility_program(pcf + "\n" + snippet, std::string(kCascadeInputs) + kLookup, why);
    vis_auto_prog_ = app::compile_visibility_program(pcf + "\n" + shadow_map + "\n" + snippet,
                                                     std::string(kCascadeInputs) + kLookupAuto, why);
    reduce_first_ = app::compile_fullscreen_program("#version 450 core\n" + snippet + kReduceFirst, why);
    reduce_next_ = app::compile_fullscreen_program("#version 450 core\n" + snippet + kReduceNext, why);
    bounds_first_ = app::compile_fullscreen_program("#version 450 core\n" + snippet + kBoundsFirst, why);
    bounds_next_ = app::compile_fullscreen_program("#version 450 core\n" + snippet + kBoundsNext, why);
    const std::string cache_glsl = app::load_snippet("shadow_cache", why);
    if (cache_glsl.empty()) return false;
    const std::string head = "#version 450 core\n" + cache_glsl;
    invariant_prog_ = skgl::compile_program(
        {{GL_VERTEX_SHADER, kInvariantVS}, {GL_GEOMETRY_SHADER, head + kInvariantGS}, {GL_FRAGMENT_SHADER, head + kInvariantFS}}, why);
    if (!depth_prog_ || !vis_prog_ || !vis_auto_prog_ || !reduce_first_ || !reduce_next_ || !bounds_first_ || !bounds_next_ ||
        !invariant_prog_)
        return false;
    for (std::size_t i = 0; i < v.scene->meshes.size(); ++i)  // cache=on: the casters, each with its box
        if (v.gpu->caster[i] && !v.scene->meshes[i].positions.empty()) cache_mesh_.push_back(i);
    cache_casters_.assign(cache_mesh_.size(), shadowkit::ShadowCacheCaster{});
    for (auto& r : rects_) r.resize(shadowkit::shadow_cache_rect_capacity(cache_mesh_.size()));
    invalidate_cache();
    glGenVertexArrays(1, &reduce_vao_);
    return pass_.init(v.width, v.height, why);
}

void CascadedShadowMaps::update(const app::View& v, const CascadedShadowMapSettings& s) {
    const sk::Light& L = v.light();
    shadowkit::CascadeInput in;
    in.camera_view = v.view;
    in.camera_proj = v.proj;  // its far plane ends the last cascade (max_distance could end them sooner)
    // the sun as one vec4: w = 0, xyz toward it; any other light is refused (InvalidLight)
    in.light_position = L.homogeneous_position();
    in.shadow_map_size = static_cast<std::uint32_t>(s.size);
    in.has_caster_bounds = true;
    in.caster_min = caster_lo_;
    in.caster_max = caster_hi_;
    const auto count = static_cast<std::uint32_t>(s.count);
    error_.clear();
    nothing_visible_ = false;
    cache_on_ = false;
    if (s.fit == CascadedShadowMapSettings::Fit::Sdsm) {
        invalidate_cache();  // the SDSM fits follow what is visible: nothing to keep
        update_sdsm(v, s, in);
        return;
    }
    const bool cache = s.cache && s.size <= 2048;  // the invariant pass's guard viewport is 4096
    if (cache) {  // cached cascades: the depth range from the scene box, fixed in the world
        in.has_scene_bounds = true;
        in.scene_min = v.scene->bounds_min();
        in.scene_max = v.scene->bounds_max();
        in.stable_world_depth = true;
    }
    fit_ = shadowkit::cascade_fit(in, s.lambda, count, cascades_, 4);
    if (fit_.status != shadowkit::Status::Ok) {
        error_ = std::string("cascade_fit status ") + shadowkit::status_name(fit_.status) +
                 (fit_.status == shadowkit::Status::InvalidLight ? " (cascades need a directional light)" : "");
        invalidate_cache();
        return;
    }
    if (!cache) {
        invalidate_cache();  // the plain pass's layers are not the invariant pass's: start over when cache=on
        return;
    }
    cache_on_ = true;
    cache_caster_bounds(v);
    cache_plan(s);
}

// fit=sdsm: the G-buffer depth's min/max -> view depths (the G-buffer camera's projection) ->
// cascade_sdsm_fit on the fit camera, last frame's result as `previous`; the splits into fit_.
void CascadedShadowMaps::update_sdsm(const app::View& v, const CascadedShadowMapSettings& s,
                                     const shadowkit::CascadeInput& in) {
    float wmin = 0.f, wmax = 0.f;
    reduce_depth(v, wmin, wmax);
    const shadowkit::CascadeSdsmRange r =
        shadowkit::cascade_sdsm_view_range(v.gpu->proj, shadowkit::ClipDepth::NegativeOneToOne, false, wmin, wmax);
    fit_ = shadowkit::CascadeFitResult{};
    if (r.status != shadowkit::Status::Ok) {
        error_ = std::string("cascade_sdsm_view_range status ") + shadowkit::status_name(r.status);
        return;
    }
    nothing_visible_ = !r.visible;
    if (!r.visible) return;
    shadowkit::CascadeSdsmInput sd;
    sd.camera = in;
    sd.view_min = r.view_min;
    sd.view_max = r.view_max;
    sd.cascade_count = static_cast<std::uint32_t>(s.count);
    sd.lambda = s.sdsm_lambda;
    sd.world_splits = true;  // interior splits stay on their world planes while the camera does not turn
    glm::vec4 bounds[4];
    if (s.receiver_bounds) {  // this frame's splits first, then the receivers of each cascade
        const shadowkit::CascadeSdsmResult sp = shadowkit::cascade_sdsm_splits(sd, &sdsm_);
        if (sp.status == shadowkit::Status::Ok && sp.visible && reduce_bounds(v, sp.splits, s.count, bounds))
            sd.receiver_bounds = bounds;
    }
    sdsm_ = shadowkit::cascade_sdsm_fit(sd, &sdsm_, cascades_, 4);
    fit_.status = sdsm_.status;
    fit_.count = sdsm_.count;
    fit_.needed = sdsm_.needed;
    std::copy(sdsm_.splits, sdsm_.splits + 17, fit_.splits);
    nothing_visible_ = sdsm_.status == shadowkit::Status::Ok && !sdsm_.visible;
    if (sdsm_.status != shadowkit::Status::Ok)
        error_ = std::string("cascade_sdsm_fit status ") + shadowkit::status_name(sdsm_.status) +
                 (sdsm_.status == shadowkit::Status::InvalidLight ? " (cascades need a directional light)" : "");
}

// The reduction: full-screen passes into RG32F levels of ceil(size / 8), the G-buffer's depth first.
bool CascadedShadowMaps::reduce_depth(const app::View& v, float& window_min, float& window_max) {
    if (reduce_w_ != v.gpu->width || reduce_h_ != v.gpu->height) {
        for (skgl::Target& t : reduce_levels_) skgl::destroy_target(t);
        int w = v.gpu->width, h = v.gpu->height;
        std::string why;
        for (int i = 0; i < 8 && (i == 0 || w > 1 || h > 1); ++i) {
            w = (w + 7) / 8;
            h = (h + 7) / 8;
            if (!skgl::make_target(reduce_levels_[i], w, h, {GL_RG32F}, 0, why)) return false;
            skgl::set_nearest_clamped(reduce_levels_[i].color[0]);
        }
        reduce_w_ = v.gpu->width;
        reduce_h_ = v.gpu->height;
    }
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glBindVertexArray(reduce_vao_);
    GLuint src = v.gpu->gbuffer.depth;
    int last = 0;
    for (int i = 0; i < 8 && reduce_levels_[i].fbo; ++i) {
        glBindFramebuffer(GL_FRAMEBUFFER, reduce_levels_[i].fbo);
        glViewport(0, 0, reduce_levels_[i].width, reduce_levels_[i].height);
        glUseProgram(i == 0 ? reduce_first_ : reduce_next_);
        glBindTextureUnit(0, src);
        glDrawArrays(GL_TRIANGLES, 0, 3);
        src = reduce_levels_[i].color[0];
        last = i;
    }
    float mm[2] = {shadowkit::kCascadeSdsmEmptyMin, shadowkit::kCascadeSdsmEmptyMax};
    glBindFramebuffer(GL_FRAMEBUFFER, reduce_levels_[last].fbo);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glReadPixels(0, 0, 1, 1, GL_RG, GL_FLOAT, mm);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    window_min = mm[0];
    window_max = mm[1];
    return true;
}

// The second reduction: the same level sizes as reduce_depth (made there), four RGBA32F targets each.
bool CascadedShadowMaps::reduce_bounds(const app::View& v, const float* splits, int count, glm::vec4* bounds) {
    const shadowkit::CascadeSdsmLightView lv = shadowkit::cascade_sdsm_light_view(
        glm::vec4(-glm::normalize(v.light().direction), 0.f));
    if (lv.status != shadowkit::Status::Ok) return false;
    std::string why;
    for (int i = 0; i < 8 && reduce_levels_[i].fbo; ++i)
        if (!bounds_levels_[i].fbo || bounds_levels_[i].width != reduce_levels_[i].width ||
            bounds_levels_[i].height != reduce_levels_[i].height) {
            skgl::destroy_target(bounds_levels_[i]);
            if (!skgl::make_target(bounds_levels_[i], reduce_levels_[i].width, reduce_levels_[i].height,
                                   {GL_RGBA32F, GL_RGBA32F, GL_RGBA32F, GL_RGBA32F}, 0, why))
                return false;
            for (GLuint t : bounds_levels_[i].color) skgl::set_nearest_clamped(t);
        }
    const GLenum bufs[4] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2, GL_COLOR_ATTACHMENT3};
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glBindVertexArray(reduce_vao_);
    int last = 0;
    for (int i = 0; i < 8 && reduce_levels_[i].fbo; ++i) {
        glBindFramebuffer(GL_FRAMEBUFFER, bounds_levels_[i].fbo);
        glDrawBuffers(4, bufs);
        glViewport(0, 0, bounds_levels_[i].width, bounds_levels_[i].height);
        const GLuint prog = i == 0 ? bounds_first_ : bounds_next_;
        glUseProgram(prog);
        if (i == 0) {
            glBindTextureUnit(0, v.gpu->gbuffer.depth);
            const glm::mat4 c2w = glm::inverse(v.gpu->proj * v.gpu->view);
            glUniformMatrix4fv(glGetUniformLocation(prog, "u_clip_to_world"), 1, GL_FALSE, glm::value_ptr(c2w));
            glUniformMatrix4fv(glGetUniformLocation(prog, "u_world_to_view"), 1, GL_FALSE, glm::value_ptr(v.view));
            glUniformMatrix4fv(glGetUniformLocation(prog, "u_world_to_light"), 1, GL_FALSE, glm::value_ptr(lv.view));
            glUniform4f(glGetUniformLocation(prog, "u_split_far"), splits[1], splits[std::min(count, 2)],
                        splits[std::min(count, 3)], splits[std::min(count, 4)]);
            glUniform1i(glGetUniformLocation(prog, "u_count"), count);
        } else {
            for (int k = 0; k < 4; ++k) glBindTextureUnit(static_cast<GLuint>(k), bounds_levels_[i - 1].color[static_cast<std::size_t>(k)]);
        }
        glDrawArrays(GL_TRIANGLES, 0, 3);
        last = i;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, bounds_levels_[last].fbo);
    for (int k = 0; k < count; ++k) {
        glReadBuffer(bufs[k]);
        glReadPixels(0, 0, 1, 1, GL_RGBA, GL_FLOAT, &bounds[k].x);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return true;
}

// One depth layer per cascade, compared in hardware (sampler2DArrayShadow: GL_LEQUAL, GL_LINEAR for
// a 2x2 PCF), clamped at the edges; a framebuffer per layer, and a 2D view of each for the debug views.
void CascadedShadowMaps::make_maps(int size, int count) {
    if (maps_) glDeleteTextures(1, &maps_);
    if (layer_view_[0]) glDeleteTextures(4, layer_view_);
    if (fbo_[0]) glDeleteFramebuffers(4, fbo_);
    std::fill(fbo_, fbo_ + 4, 0u);
    std::fill(layer_view_, layer_view_ + 4, 0u);
    maps_ = skgl::make_depth_texture(GL_TEXTURE_2D_ARRAY, size, count, GL_LINEAR, GL_CLAMP_TO_EDGE);
    if (scratch_) glDeleteTextures(1, &scratch_);
    glCreateTextures(GL_TEXTURE_2D, 1, &scratch_);  // cache=on: a scroll copies through it
    glTextureStorage2D(scratch_, 1, GL_DEPTH_COMPONENT32F, size, size);
    skgl::make_depth_framebuffers(GL_TEXTURE_2D_ARRAY, maps_, count, fbo_);
    glGenTextures(count, layer_view_);
    for (int i = 0; i < count; ++i)
        glTextureView(layer_view_[i], GL_TEXTURE_2D, maps_, GL_DEPTH_COMPONENT32F, 0, 1, static_cast<GLuint>(i), 1);
    size_ = size;
    layers_ = count;
}

// Every layer whole: cleared, then every caster drawn with the cascade's matrix (the plain pass).
void CascadedShadowMaps::render_layers(const app::View& v, const CascadedShadowMapSettings& s, bool ok) {
    const bool automatic = s.bias == CascadedShadowMapSettings::Bias::Auto;
    glUseProgram(depth_prog_);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glClearDepth(1.0);
    if (!automatic) {
        glEnable(GL_POLYGON_OFFSET_FILL);
        glPolygonOffset(2.f, 2.f);
    }
    for (int i = 0; i < layers_; ++i) {
        glBindFramebuffer(GL_FRAMEBUFFER, fbo_[i]);
        glViewport(0, 0, size_, size_);
        glClear(GL_DEPTH_BUFFER_BIT);
        if (!ok) continue;
        glUniformMatrix4fv(glGetUniformLocation(depth_prog_, "u_light_view_proj"), 1, GL_FALSE, glm::value_ptr(cascades_[i].view_proj));
        for (std::size_t m = 0; m < v.gpu->meshes.size(); ++m)
            if (v.gpu->caster[m]) skgl::draw_mesh(v.gpu->meshes[m]);
    }
    glDisable(GL_POLYGON_OFFSET_FILL);
}

void CascadedShadowMaps::render(const app::View& v, const CascadedShadowMapSettings& s) {
    if (s.size != size_ || s.count != layers_) make_maps(s.size, s.count);
    const bool ok = error_.empty();

    const bool automatic = s.bias == CascadedShadowMapSettings::Bias::Auto;
    glm::mat4 vps[4];
    float texel[4] = {0.f, 0.f, 0.f, 0.f};
    for (int i = 0; i < layers_ && ok; ++i) {
        vps[i] = cascades_[i].view_proj;
        texel[i] = cascades_[i].texel_world_size;
    }

    // 1. The casters' depth into each cascade's layer with its matrix: depth test GL_LESS, cleared to
    //    the far plane; bias=polygon_offset: polygon offset (2, 2) (the automatic bias compares with the
    //    true depths). No cascades (a light that is not the sun): empty maps.
    //    cache=on: per cascade the plan's scroll, then only its rectangles (cached cascades, below).
    if (cache_on_ && ok) {
        for (int i = 0; i < layers_; ++i) {
            cache_scroll(i);
            cache_rerender(v, s, i);
        }
        cache_done();
    } else {
        render_layers(v, s, ok);
    }
    // 2. V at the G-buffer's points: the matrices, the splits as each cascade's near and far view depth.
    const float* sp = fit_.splits;
    const GLuint prog = automatic ? vis_auto_prog_ : vis_prog_;
    glUseProgram(prog);
    app::set_light_uniforms(prog, v.light());
    glUniformMatrix4fv(glGetUniformLocation(prog, "u_cascade_vp"), 4, GL_FALSE, glm::value_ptr(vps[0]));
    glUniform4f(glGetUniformLocation(prog, "u_split_near"), sp[0], sp[1], sp[2], sp[3]);
    glUniform4f(glGetUniformLocation(prog, "u_split_far"), sp[1], sp[2], sp[3], sp[4]);
    glUniform1i(glGetUniformLocation(prog, "u_count"), ok && !nothing_visible_ ? layers_ : 0);
    glUniform1f(glGetUniformLocation(prog, "u_band"), s.band);
    glUniform1i(glGetUniformLocation(prog, "u_pcf_radius"), s.pcf_radius);
    glUniformMatrix4fv(glGetUniformLocation(prog, "u_camera_view"), 1, GL_FALSE, glm::value_ptr(v.view));
    if (!automatic) {
        glUniform1fv(glGetUniformLocation(prog, "u_texel"), 4, texel);
        glUniform1f(glGetUniformLocation(prog, "u_normal_offset"), s.normal_offset);
    }
    pass_.draw(prog, *v.gpu, GL_TEXTURE_2D_ARRAY, maps_);
}

// ---------------------------------------------------------------------------------------------------
// Cached cascades (cache=on). A sun's cascades follow the camera, but with the depth range fixed in
// the world (update: stable_world_depth) a camera move only translates each cascade by whole texels
// of its own grid (Cascade::texel_anchor), and shadow_cache_plan can tell per cascade what of last
// frame's layer is still right. Five small steps:
//   update  A cache_caster_bounds  each caster's box this frame (a renderer with moving objects takes
//                                  them from its transforms; here the positions as uploaded)
//           B cache_plan           per cascade: its matrix in double with the x/y translation rebuilt
//                                  from texel_anchor (what the plan certifies), the invariant pass's
//                                  matrix, and the plan against what the layer holds
//   render  C cache_scroll         Scroll: what stays on the layer, moved by whole texels (through a
//                                  scratch texture: a copy within one image must not overlap)
//           D cache_rerender       the plan's rectangles (the exposed border, the old and new footprints
//                                  of casters that moved; Render: the whole layer) cleared and drawn
//                                  with the translation-invariant pass, scissored
//           E cache_done           the layers now hold this frame: its states and boxes are "previous"

void CascadedShadowMaps::cache_caster_bounds(const app::View& v) {
    for (std::size_t i = 0; i < cache_mesh_.size(); ++i) {
        glm::vec3 lo(INFINITY), hi(-INFINITY);
        for (const glm::vec3& p : v.scene->meshes[cache_mesh_[i]].positions) {
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
        const float b[6] = {lo.x, lo.y, lo.z, hi.x, hi.y, hi.z};
        std::copy(b, b + 6, cache_casters_[i].bounds);
    }
}

void CascadedShadowMaps::cache_plan(const CascadedShadowMapSettings& s) {
    if (s.size != size_ || s.count != layers_) invalidate_cache();  // render() makes new layers
    const double S = double(s.size);
    const std::uint64_t settings = s.bias == CascadedShadowMapSettings::Bias::Auto ? 1u : 2u;  // what the pass writes
    scrolled_ = false;
    for (int i = 0; i < s.count; ++i) {
        // the matrix the layer is rendered with: x/y translation exactly from the anchor (docs/cascades.md)
        const shadowkit::Cascade& c = cascades_[i];
        glm::dmat4 vp(c.view_proj);
        vp[3][0] = -2.0 * c.texel_anchor.x / S - 1.0;
        vp[3][1] = -2.0 * c.texel_anchor.y / S - 1.0;
        cache_vp_[i] = vp;
        cascades_[i].view_proj = glm::mat4(vp);  // the lookup reads the same matrix
        cache_anchor_[i] = glm::ivec2(glm::dvec2(c.texel_anchor));
        // the invariant pass: world -> (global texel x, y, window depth), the same bits every frame
        glm::dmat4 g(0.0);
        for (int k = 0; k < 4; ++k) {
            g[k][0] = 0.5 * S * vp[k][0];
            g[k][1] = 0.5 * S * vp[k][1];
            g[k][2] = 0.5 * vp[k][2];
        }
        g[3][0] += 0.5 * S + double(cache_anchor_[i].x);  // = 0: the grid is anchored at the world origin
        g[3][1] += 0.5 * S + double(cache_anchor_[i].y);
        g[3][2] += 0.5;
        g[3][3] = 1.0;
        cache_global_[i] = glm::mat4(g);
        // the plan: this frame's state against the one the layer was last rendered with
        current_[i] = shadowkit::ShadowCacheMapState{};
        current_[i].view_proj = vp;
        current_[i].width = current_[i].height = s.size;
        current_[i].settings = settings;
        plan_[i] = shadowkit::shadow_cache_plan(previous_[i], current_[i], cache_casters_.data(), cache_casters_.size(),
                                                rects_[i].data(), rects_[i].size());
        if (plan_[i].status != shadowkit::Status::Ok && error_.empty())
            error_ = std::string("shadow_cache_plan status ") + shadowkit::status_name(plan_[i].status);
    }
}

void CascadedShadowMaps::cache_scroll(int i) {
    if (plan_[i].action != shadowkit::ShadowCacheAction::Scroll || scrolled_) return;  // once per update()
    const shadowkit::ShadowCacheCopy& c = plan_[i].copy;
    glCopyImageSubData(maps_, GL_TEXTURE_2D_ARRAY, 0, c.src_x, c.src_y, i, scratch_, GL_TEXTURE_2D, 0, 0, 0, 0, c.width,
                       c.height, 1);
    glCopyImageSubData(scratch_, GL_TEXTURE_2D, 0, 0, 0, 0, maps_, GL_TEXTURE_2D_ARRAY, 0, c.dst_x, c.dst_y, i, c.width,
                       c.height, 1);
}

void CascadedShadowMaps::cache_rerender(const app::View& v, const CascadedShadowMapSettings& s, int i) {
    const shadowkit::ShadowCachePlan& plan = plan_[i];
    if (plan.count == 0) return;  // Keep
    const int S = size_, guard = (kGuardViewport - S) / 2;
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_[i]);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);  // a scissored clear needs the writes
    glClearDepth(1.0);
    glViewport(-guard, -guard, kGuardViewport, kGuardViewport);  // triangles clipped far outside the layer
    glUseProgram(invariant_prog_);
    const glm::ivec2 a = cache_anchor_[i];
    glUniformMatrix4fv(glGetUniformLocation(invariant_prog_, "u_light_global"), 1, GL_FALSE, glm::value_ptr(cache_global_[i]));
    glUniform2i(glGetUniformLocation(invariant_prog_, "u_anchor"), a.x, a.y);
    glUniform2i(glGetUniformLocation(invariant_prog_, "u_viewport_anchor"), a.x - guard, a.y - guard);
    glUniform2f(glGetUniformLocation(invariant_prog_, "u_viewport_size"), float(kGuardViewport), float(kGuardViewport));
    glUniform1i(glGetUniformLocation(invariant_prog_, "u_offset"), s.bias == CascadedShadowMapSettings::Bias::Auto ? 0 : 1);
    glEnable(GL_SCISSOR_TEST);
    for (std::size_t k = 0; k < plan.count; ++k) {
        const shadowkit::ShadowCacheRect& r = rects_[i][k];
        glScissor(r.x, r.y, r.width, r.height);
        glClear(GL_DEPTH_BUFFER_BIT);
        for (std::size_t m = 0; m < cache_mesh_.size(); ++m) {  // the casters whose footprint meets r
            const shadowkit::ShadowCacheFootprint f = shadowkit::shadow_cache_footprint(cache_vp_[i], S, S, cache_casters_[m].bounds);
            if (f.status != shadowkit::Status::Ok || !f.visible) continue;
            if (f.rect.x >= r.x + r.width || r.x >= f.rect.x + f.rect.width || f.rect.y >= r.y + r.height ||
                r.y >= f.rect.y + f.rect.height)
                continue;
            skgl::draw_mesh(v.gpu->meshes[cache_mesh_[m]]);
        }
    }
    glDisable(GL_SCISSOR_TEST);
}

void CascadedShadowMaps::cache_done() {
    scrolled_ = true;
    for (int i = 0; i < layers_; ++i) {
        previous_[i] = current_[i];
        previous_[i].has_content = true;
    }
    for (shadowkit::ShadowCacheCaster& c : cache_casters_) std::copy(c.bounds, c.bounds + 6, c.previous_bounds);
}

std::uint64_t CascadedShadowMaps::texels_rerendered() const {
    if (!cache_on_) return std::uint64_t(layers_) * std::uint64_t(size_) * std::uint64_t(size_);
    std::uint64_t n = 0;
    for (int i = 0; i < layers_; ++i) n += plan_[i].texels;
    return n;
}

void CascadedShadowMaps::release() {  // (no GL call without objects: the App may have no context)
    if (maps_) glDeleteTextures(1, &maps_);
    if (layer_view_[0]) glDeleteTextures(4, layer_view_);
    if (fbo_[0]) glDeleteFramebuffers(4, fbo_);
    if (depth_prog_) glDeleteProgram(depth_prog_);
    if (vis_prog_) glDeleteProgram(vis_prog_);
    if (vis_auto_prog_) glDeleteProgram(vis_auto_prog_);
    if (reduce_first_) glDeleteProgram(reduce_first_);
    if (reduce_next_) glDeleteProgram(reduce_next_);
    if (bounds_first_) glDeleteProgram(bounds_first_);
    if (bounds_next_) glDeleteProgram(bounds_next_);
    if (invariant_prog_) glDeleteProgram(invariant_prog_);
    if (scratch_) glDeleteTextures(1, &scratch_);
    invariant_prog_ = scratch_ = 0;
    cache_mesh_.clear();
    cache_casters_.clear();
    cache_on_ = false;
    for (skgl::Target& t : bounds_levels_) skgl::destroy_target(t);
    bounds_first_ = bounds_next_ = 0;
    if (reduce_vao_) glDeleteVertexArrays(1, &reduce_vao_);
    for (skgl::Target& t : reduce_levels_) skgl::destroy_target(t);
    maps_ = depth_prog_ = vis_prog_ = vis_auto_prog_ = reduce_first_ = reduce_next_ = reduce_vao_ = 0;
    reduce_w_ = reduce_h_ = 0;
    sdsm_ = shadowkit::CascadeSdsmResult{};
    std::fill(fbo_, fbo_ + 4, 0u);
    std::fill(layer_view_, layer_view_ + 4, 0u);
    size_ = layers_ = 0;
    error_.clear();
}
