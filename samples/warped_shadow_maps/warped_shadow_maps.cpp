// samples/warped_shadow_maps/warped_shadow_maps.cpp - a fitted or warped shadow map, top to bottom:
//   init    once per scene: every mesh's bounds (the fit's caster boxes), the programs, the V target
//   update  CPU, every frame: the receivers the light can reach (the scene box, cut to a spot light's
//           cone), then the light's matrix: light_frustum_fit (fitted, with the casters it keeps) or
//           warp_matrix (uniform, PSM, LiSPSM, TSM: the map follows the camera's perspective)
//   render  GPU, every frame: 1 the casters' depth into the map with that matrix (bias=offset: a
//           slope-scaled offset; TSM: its x, y warped, its depth the light's own, written per fragment
//           with the offset); 2 V at the G-buffer's points through the same matrices: bias=auto (the
//           default) glsl/shadow_map.glsl's automatic bias, else one hardware compare (2x2 PCF)
// Spot and area lights are point lights at their center here; directional lights are orthographic fits
// (fitted, uniform) or warped in the light's space.
#include "warped_shadow_maps.hpp"

#include <shadowkit/light_frustum.hpp>
#include <shadowkit/perspective_shadow_maps.hpp>

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>

namespace {

// The depth pass: positions through the light's matrix (skgl::depth_only_program); TSM also passes the
// light's undistorted clip position, whose depth the fragment writes with the slope-scaled offset of
// glPolygonOffset(2, 2) computed in the shader (sk_warp_map_depth: polygon offset does not apply to
// gl_FragDepth).
const char* kTsmDepthVS = R"(#version 450 core
layout(location = 0) in vec3 a_position;
uniform mat4 u_light_view_proj;
uniform mat4 u_depth_proj;
out vec4 v_depth_clip;
void main() {
    gl_Position = u_light_view_proj * vec4(a_position, 1.0);
    v_depth_clip = u_depth_proj * vec4(a_position, 1.0);
}
)";
const char* kTsmDepthFS = R"(
in vec4 v_depth_clip;
uniform float u_slope_scale;   // 2 (bias=offset), 0 (bias=auto: the true depths)
void main() { gl_FragDepth = sk_warp_map_depth(v_depth_clip, u_slope_scale, 0.0, false); }
)";
// V's lookup (after glsl/perspective_shadow_maps.glsl and glsl/shadow_map.glsl): x, y through u_warp,
// the compare depth through u_depth_proj (the same matrix for every method but TSM). The map is bound
// at unit 2. u_auto (bias=auto): the automatic bias, four compares at texel centres, each against the
// receiver plane's depth there: through the one matrix (shadow_map.glsl), or for TSM's separate depth
// along each texel's light ray (sk_warp_shadow_auto, with the warp's inverse); else the hardware 2x2
// compare of the offset depths.
const char* kLookup = R"(
layout(binding = 2) uniform sampler2DShadow u_shadow_map;
uniform mat4 u_warp;
uniform mat4 u_warp_inverse;
uniform mat4 u_depth_proj;
uniform bool u_auto;
uniform bool u_separate_depth;
float technique_visibility(vec3 p, vec3 n) {
    if (u_auto && u_separate_depth)
        return sk_warp_shadow_auto(u_shadow_map, u_warp, u_warp_inverse, u_depth_proj, p, n, false, 0.0, 1.0);
    if (u_auto) return sk_shadow_map_visibility_auto(u_shadow_map, u_warp, p, n, false, 0.0, 1.0);
    return sk_warp_shadow(u_shadow_map, u_warp, u_depth_proj, p, 0.0, false);
}
)";

// Box around a spot light's cone: the apex and the cap disk at the farthest corner of lo..hi (half
// angle at most 1.5 rad). Receivers outside the cone are unlit anyway: the map leaves them out.
void cut_to_spot_cone(const sk::Light& L, glm::vec3& lo, glm::vec3& hi) {
    float far_d = 0.f;
    for (int i = 0; i < 8; ++i)
        far_d = std::max(far_d, glm::length(glm::vec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z) - L.position));
    const glm::vec3 d = glm::normalize(L.direction), cap = L.position + d * far_d;
    const float r = far_d * std::tan(std::min(L.spot_half_angle, 1.5f));
    const glm::vec3 ext = r * glm::sqrt(glm::max(glm::vec3(0.f), 1.f - d * d));  // the cap disk's extent per axis
    lo = glm::max(lo, glm::min(L.position, cap - ext));
    hi = glm::min(hi, glm::max(L.position, cap + ext));
}

}  // namespace

bool WarpedShadowMaps::init(const app::View& v, std::string& why) {
    release();
    const sk::Scene& scene = *v.scene;
    caster_lo_ = glm::vec3(INFINITY);
    caster_hi_ = glm::vec3(-INFINITY);
    for (const sk::Mesh& m : scene.meshes) {
        glm::vec3 lo(INFINITY), hi(-INFINITY);
        for (const glm::vec3& p : m.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
        boxes_.insert(boxes_.end(), {lo.x, lo.y, lo.z, hi.x, hi.y, hi.z});
        caster_.push_back(m.caster ? 1 : 0);
        if (m.caster) caster_lo_ = glm::min(caster_lo_, lo), caster_hi_ = glm::max(caster_hi_, hi);
    }
    keep_.assign(scene.meshes.size(), 1);
    const std::string snippet = app::load_snippet("perspective_shadow_maps", why);
    const std::string map_snippet = app::load_snippet("shadow_map", why);
    if (snippet.empty() || map_snippet.empty()) return false;
    depth_prog_ = skgl::depth_only_program(why);  // gl_Position = u_light_view_proj * a_position, no color
    tsm_depth_prog_ = skgl::compile_program(
        {{GL_VERTEX_SHADER, kTsmDepthVS}, {GL_FRAGMENT_SHADER, "#version 450 core\n" + snippet + kTsmDepthFS}}, why);
    vis_prog_ = app::compile_visibility_program(snippet + map_snippet, kLookup, why);
    if (!depth_prog_ || !tsm_depth_prog_ || !vis_prog_) return false;
    return pass_.init(v.width, v.height, why);
}

void WarpedShadowMaps::update(const app::View& v, const WarpedShadowMapSettings& s) {
    using M = WarpedShadowMapSettings::Method;
    const sk::Light& L = v.light();
    error_.clear();
    visible_ = fallback_ = separate_depth_ = false;
    std::fill(keep_.begin(), keep_.end(), std::uint8_t(1));
    // the receivers the light can reach; the light as one vec4 (w = 0: the direction toward it)
    glm::vec3 lo = v.scene->bounds_min(), hi = v.scene->bounds_max();
    if (L.type == sk::LightType::Spot) cut_to_spot_cone(L, lo, hi);
    const glm::vec4 light = L.homogeneous_position();
    if (s.method == M::Fitted) {
        // the light's frustum around the receivers in the camera's view, and the casters that can shadow them
        shadowkit::LightFrustumInput in;
        in.camera_view = v.view;
        in.camera_proj = v.proj;
        in.has_scene_bounds = true;
        in.scene_min = lo;
        in.scene_max = hi;
        in.light_position = light;
        in.casters = boxes_.data();
        in.caster_count = boxes_.size() / 6;
        in.shadow_map_size = static_cast<std::uint32_t>(s.size);
        std::vector<std::uint32_t> kept(in.caster_count);
        const shadowkit::LightFrustumResult r = shadowkit::light_frustum_fit(in, kept.data(), kept.size());
        if (r.status != shadowkit::Status::Ok) {
            error_ = std::string("light_frustum_fit status ") + shadowkit::status_name(r.status);
            return;
        }
        std::fill(keep_.begin(), keep_.end(), std::uint8_t(0));
        for (std::size_t k = 0; k < r.count; ++k) keep_[kept[k]] = 1;
        visible_ = r.visible;
        light_vp_ = depth_vp_ = r.view_proj;
        return;
    }
    // a warp: the receivers, extended toward the light up to the casters' bounds
    shadowkit::WarpInput in;
    in.camera_view = v.view;
    in.camera_proj = v.proj;
    in.light_position = light;
    in.has_scene_bounds = true;
    in.scene_min = lo;
    in.scene_max = hi;
    in.has_caster_bounds = true;
    in.caster_min = caster_lo_;
    in.caster_max = caster_hi_;
    const shadowkit::WarpMethod method = s.method == M::Uniform ? shadowkit::WarpMethod::Uniform
                                         : s.method == M::Psm   ? shadowkit::WarpMethod::Psm
                                         : s.method == M::Lispsm ? shadowkit::WarpMethod::Lispsm
                                                                 : shadowkit::WarpMethod::Tsm;
    const shadowkit::WarpResult w = shadowkit::warp_matrix(in, method);
    if (w.status != shadowkit::Status::Ok) {
        error_ = std::string("warp status ") + shadowkit::status_name(w.status);
        return;
    }
    visible_ = w.visible;  // false: no receiver in view needs a shadow
    light_vp_ = w.light_view_proj;
    depth_vp_ = w.depth_view_proj;  // = light_view_proj but for TSM
    warp_inverse_ = glm::mat4(glm::inverse(glm::dmat4(w.light_view_proj)));  // in double: the TSM lookup unprojects texel centres
    separate_depth_ = w.separate_depth;
    fallback_ = w.fallback_uniform;
}

// A size x size depth texture that compares (sampler2DShadow): GL_LEQUAL against the receiver's depth,
// GL_LINEAR for the hardware 2x2 filter; the border is the far depth (outside the map: lit).
void WarpedShadowMaps::make_map(int size) {
    if (map_) glDeleteTextures(1, &map_);
    if (fbo_) glDeleteFramebuffers(1, &fbo_);
    map_ = skgl::make_depth_texture(GL_TEXTURE_2D, size, 1, GL_LINEAR, GL_CLAMP_TO_BORDER);
    skgl::make_depth_framebuffers(GL_TEXTURE_2D, map_, 1, &fbo_);
    size_ = size;
}

void WarpedShadowMaps::render(const app::View& v, const WarpedShadowMapSettings& s) {
    if (s.size != size_) make_map(s.size);
    const bool automatic = s.bias == WarpedShadowMapSettings::Bias::Auto;

    // 1. The casters' depth from the light: depth test GL_LESS, cleared to the far plane; bias=offset
    //    (and TSM) a polygon offset (2, 2) against acne, bias=auto the true depths. TSM: gl_FragDepth
    //    from the unwarped light's depth (the same offset, in the shader). Nothing in view, or no
    //    matrix: the map stays empty (all lit).
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glViewport(0, 0, size_, size_);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glClearDepth(1.0);
    glClear(GL_DEPTH_BUFFER_BIT);
    if (visible_ && error_.empty()) {
        const GLuint prog = separate_depth_ ? tsm_depth_prog_ : depth_prog_;
        glUseProgram(prog);
        glUniformMatrix4fv(glGetUniformLocation(prog, "u_light_view_proj"), 1, GL_FALSE, glm::value_ptr(light_vp_));
        if (separate_depth_) {
            glUniformMatrix4fv(glGetUniformLocation(prog, "u_depth_proj"), 1, GL_FALSE, glm::value_ptr(depth_vp_));
            glUniform1f(glGetUniformLocation(prog, "u_slope_scale"), automatic ? 0.f : 2.f);
        }
        if (!automatic && !separate_depth_) {  // (TSM's written depth carries its offset itself)
            glEnable(GL_POLYGON_OFFSET_FILL);
            glPolygonOffset(2.f, 2.f);
        }
        for (std::size_t i = 0; i < v.gpu->meshes.size(); ++i)
            if (drawn(i)) skgl::draw_mesh(v.gpu->meshes[i]);
        glDisable(GL_POLYGON_OFFSET_FILL);
    }

    // 2. V at the G-buffer's points: the map's compare through u_warp (x, y) and u_depth_proj (depth).
    glUseProgram(vis_prog_);
    app::set_light_uniforms(vis_prog_, v.light());
    glUniformMatrix4fv(glGetUniformLocation(vis_prog_, "u_warp"), 1, GL_FALSE, glm::value_ptr(light_vp_));
    glUniformMatrix4fv(glGetUniformLocation(vis_prog_, "u_depth_proj"), 1, GL_FALSE, glm::value_ptr(depth_vp_));
    glUniform1i(glGetUniformLocation(vis_prog_, "u_auto"), automatic ? 1 : 0);
    glUniform1i(glGetUniformLocation(vis_prog_, "u_separate_depth"), separate_depth_ ? 1 : 0);
    glUniformMatrix4fv(glGetUniformLocation(vis_prog_, "u_warp_inverse"), 1, GL_FALSE, glm::value_ptr(warp_inverse_));
    pass_.draw(vis_prog_, *v.gpu, GL_TEXTURE_2D, map_);
}

// The texel-density view, on the CPU: the G-buffer's points and normals read back, then at each
// receiver facing the light warp_aliasing_error (screen pixels per map texel along the worst direction).
app::DebugImage WarpedShadowMaps::debug_texel_density(const app::View& v) {
    const int W = v.width, H = v.height;
    const std::size_t n = static_cast<std::size_t>(W) * static_cast<std::size_t>(H);
    std::vector<glm::vec4> pos(n), nrm(n);
    const auto bytes = static_cast<GLsizei>(n * sizeof(glm::vec4));
    glGetTextureImage(v.gpu->gbuffer.color[0], 0, GL_RGBA, GL_FLOAT, bytes, pos.data());
    glGetTextureImage(v.gpu->gbuffer.color[1], 0, GL_RGBA, GL_FLOAT, bytes, nrm.data());
    std::vector<std::uint8_t> rgba(4 * n, 0);  // alpha 0: the shaded picture shows through
    const sk::Light& L = v.light();
    for (std::size_t k = 0; k < n && visible_ && error_.empty(); ++k) {
        const glm::vec3 p(pos[k]), nn(nrm[k]);
        const glm::vec3 l = L.type == sk::LightType::Directional ? -glm::normalize(L.direction) : glm::normalize(L.position - p);
        if (pos[k].w != 1.f || glm::dot(nn, l) <= 0.f) continue;  // not a receiver facing the light
        const shadowkit::WarpAliasingValue e = shadowkit::warp_aliasing_error(
            light_vp_, v.proj * v.view, p, nn, static_cast<std::uint32_t>(size_), glm::uvec2(unsigned(W), unsigned(H)));
        if (e.status != shadowkit::Status::Ok || !(e.value > 0.0)) continue;
        const double t = std::clamp(std::log2(e.value) / 2.0, -1.0, 1.0);  // -1: 1/4 pixel a texel, 0: 1, +1: 4
        const double red = t > 0 ? t : 0.0, blue = t < 0 ? -t : 0.0, green = 1.0 - std::abs(t);
        rgba[4 * k] = static_cast<std::uint8_t>(std::lround(255.0 * red));
        rgba[4 * k + 1] = static_cast<std::uint8_t>(std::lround(255.0 * green));
        rgba[4 * k + 2] = static_cast<std::uint8_t>(std::lround(255.0 * blue));
        rgba[4 * k + 3] = 255;
    }
    std::string why;
    if (density_.width != W || density_.height != H) {
        skgl::destroy_target(density_);
        if (!skgl::make_target(density_, W, H, {GL_RGBA8}, 0, why)) return {};
    }
    glTextureSubImage2D(density_.color[0], 0, 0, 0, W, H, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    return {density_.color[0], app::DebugImage::Show::Overlay};
}

void WarpedShadowMaps::release() {  // (no GL call without objects: the App may have no context)
    if (map_) glDeleteTextures(1, &map_);
    if (fbo_) glDeleteFramebuffers(1, &fbo_);
    for (GLuint p : {depth_prog_, tsm_depth_prog_, vis_prog_})
        if (p) glDeleteProgram(p);
    map_ = fbo_ = depth_prog_ = tsm_depth_prog_ = vis_prog_ = 0;
    size_ = 0;
    skgl::destroy_target(density_);
    boxes_.clear();
    caster_.clear();
    keep_.clear();
    error_.clear();
}
