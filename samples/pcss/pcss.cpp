// samples/pcss/pcss.cpp - PCSS and PCF on one shadow map, top to bottom:
//   init    the snippets (shadow_map.glsl, pcf.glsl, pcss.glsl), the depth-only program, two sampler
//           objects of the one map (compare off for PCSS's blocker search, compare on + GL_LINEAR for the
//           filter's taps: each a hardware 2x2 percentage-closer compare), the V target
//   update  CPU, every frame: the light's frustum around the scene (sk::fit_light: a perspective from
//           the light's center), its near plane moved to the casters (pcss_fit_near_plane: PCSS's
//           blocker search is cut at the near plane), the light's width in the map's uv on the near
//           plane (pcss_light_uv_at_near); for PCF a radius from the light's penumbra
//   render  GPU, every frame: 1 the casters' depth from the light (no polygon offset: the lookup
//           biases); 2 V at the G-buffer's points: the bias, then the filter (the program for these
//           settings, compiled when they change)
// The G-buffer knows each point's plane (position and normal), so the receiver-plane bias takes the
// plane's depth gradient in the map from two tangent points (pcf.glsl's sk_receiver_plane_gradient;
// sk_receiver_plane_depth_bias, its dFdx/dFdy form, would straddle silhouettes in a deferred pass).
#include "pcss.hpp"

#include <shadowkit/pcss.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>

namespace {

namespace skp = shadowkit;

// The lookup's helpers, after the snippets: the shadow coordinate, the light's window depth at an eye
// distance, the receiver plane's depth gradient and its bias.
const char* kHelpers = R"(
layout(binding = 2) uniform sampler2D u_depth;     // the map, compare off: PCSS's blocker search
layout(binding = 3) uniform sampler2DShadow u_map; // the map, compare on: one 2x2 compare per tap
uniform mat4 u_light_view_proj;
uniform mat4 u_light_view;
uniform vec3 u_light_eye;
uniform float u_near;
uniform float u_far;
uniform float u_texel_uv;    // 1 / map size
uniform float u_tan_half;    // tan(fov / 2) of the light's frustum
uniform float u_margin;      // receiver plane: texels of plane slope
uniform float u_const_bias;  // receiver plane: window depth
uniform float u_depth_step;  // the automatic bias: the map format's window-depth step (0: float32)
// (uv, window z) of p in the map; uv = -1 when p is behind the light
vec3 shadow_uvz(mat4 vp, vec3 p) {
    vec4 c = sk_shadow_coord(vp, p, false);
    return c.w > 0.0 ? c.xyz : vec3(-1.0, -1.0, 0.0);
}
// the light's window depth at eye distance d
float window_depth(float d) { return u_far * (d - u_near) / (d * (u_far - u_near)); }
// dz/duv of the plane (p, n) in the map: two tangent steps, solved by pcf.glsl's
// sk_receiver_plane_gradient (the G-buffer knows the plane: no dFdx/dFdy across silhouettes;
// window z is affine in uv on a plane under a perspective, so the step's size does not matter)
vec2 plane_gradient(mat4 vp, vec3 eye, vec3 p, vec3 n) {
    vec3 a = abs(n.y) < 0.9 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
    vec3 t1 = normalize(cross(n, a));
    vec3 t2 = cross(n, t1);
    float h = 0.01 * max(length(p - eye), 1e-4);
    vec3 z0 = sk_shadow_coord(vp, p, false).xyz;
    vec3 d1 = sk_shadow_coord(vp, p + h * t1, false).xyz - z0;
    vec3 d2 = sk_shadow_coord(vp, p + h * t2, false).xyz - z0;
    return sk_receiver_plane_gradient(d1, d2);
}
// the receiver's depth lowered by `margin` texels of the plane's slope (a 2x2 compare reads texel
// centers up to a texel away) and a constant
vec3 plane_bias(vec3 uvz, vec2 g, float texel_uv) {
    uvz.z -= u_margin * texel_uv * (abs(g.x) + abs(g.y)) + u_const_bias;
    return uvz;
}
)";

// V at a G-buffer point: where it falls in the map, the bias, the filter; times the emitter's horizon.
// FILTER: 0 hard, 1 box, 2 tent, 3 poisson, 4 pcss; BIAS: 0 none, 1 constant, 2 slope-scaled, 3 normal
// offset, 4 receiver plane, 5 automatic; ROTATE 0/1 (the #defines in front of the snippets).
const char* kLookup = R"(
uniform int u_radius_texels;
uniform float u_radius_uv;
uniform int u_taps;
uniform float u_light_uv_at_near;
uniform float u_max_filter_uv;
uniform float u_constant_bias;
uniform float u_slope_scale;
uniform float u_normal_offset;
float technique_visibility(vec3 p, vec3 n) {
    vec3 l = normalize(u_light_eye - p);
    float c = dot(n, l);
    float s = sqrt(max(0.0, 1.0 - c * c));   // sin and cos of the light's angle to the normal
    float texel_world = 2.0 * max(-(u_light_view * vec4(p, 1.0)).z, 0.0) * u_tan_half * u_texel_uv;
    vec3 q = p;
#if BIAS == 3
    q = p + n * (u_normal_offset * texel_world * s);   // shadow_bias.hpp: bias_normal_offset_position
#endif
    vec3 uvz = shadow_uvz(u_light_view_proj, q);
    if (uvz.x < -0.5) return 1.0;
    float dq = -(u_light_view * vec4(q, 1.0)).z;
    vec2 g = vec2(0.0);
#if BIAS == 1
    uvz.z = window_depth(dq - u_constant_bias);
#elif BIAS == 2
    float tan_t = c > 0.0 ? s / c : 1e30;
    uvz.z = window_depth(dq - u_slope_scale * texel_world * min(tan_t, 10.0));   // bias_slope_scaled
#elif BIAS == 4
    g = plane_gradient(u_light_view_proj, u_light_eye, p, n);
    uvz = plane_bias(uvz, g, u_texel_uv);
#elif BIAS == 5
    // shadow_map.glsl's automatic bias: the plane from the normal (edge-on: g = 0); the kernels' taps
    // (one hardware 2x2 each) need one texel of its slope more than the hard lookup, which compares
    // texel by texel
    vec4 ga = sk_plane_depth_gradient(u_light_view_proj, p, n, false);
    g = ga.xy;
    uvz.z -= sk_auto_filtered_bias(ga, vec2(u_texel_uv), uvz.z, u_depth_step);
#endif
#if FILTER == 0 && BIAS == 5
    float v = sk_shadow_map_visibility_auto(u_map, u_light_view_proj, p, n, false, u_depth_step, 1.0);
#elif FILTER == 0
    float v = sk_pcf_hard(u_map, uvz);
#elif FILTER == 1
    float v = sk_pcf_box(u_map, uvz, g, u_radius_texels);
#elif FILTER == 2
    float v = sk_pcf_tent(u_map, uvz, g, u_radius_texels);
#elif FILTER == 3 && ROTATE
    float v = sk_pcf_poisson_rotated(u_map, uvz, g, u_radius_uv, u_taps);
#elif FILTER == 3
    float v = sk_pcf_poisson(u_map, uvz, g, u_radius_uv, u_taps, 0.0);
#else
#if ROTATE
    float angle = 6.28318531 * sk_interleaved_gradient_noise(gl_FragCoord.xy);
#else
    float angle = 0.0;
#endif
    float v = sk_pcss(u_depth, u_map, uvz, g, u_light_uv_at_near, u_near, u_far, u_taps, u_taps, angle, u_max_filter_uv);
#endif
    return v * sk_emitter_horizon(p, n);
}
)";

bool perspective_light(const sk::Light& L) {
    return L.type == sk::LightType::Spot || L.type == sk::LightType::Rect || L.type == sk::LightType::Disk ||
           L.type == sk::LightType::Sphere;
}

// The emitter's width as PcssLight::size wants it (rect edge, disk and sphere diameter); 0 without area.
float light_width(const sk::Light& L) {
    if (!L.is_area() || !perspective_light(L)) return 0.f;
    return L.type == sk::LightType::Rect ? L.size : 2.f * L.size;
}

// The farthest surface along the light's axis (the ground under the light); -1 when it meets nothing.
float farthest_axis_hit(const sk::Scene& s, glm::vec3 o, glm::vec3 d) {
    float best = -1.f;
    for (const auto& m : s.meshes)
        for (std::size_t i = 0; i + 2 < m.indices.size(); i += 3) {  // Moller-Trumbore
            const glm::vec3 a = m.positions[m.indices[i]], b = m.positions[m.indices[i + 1]], c = m.positions[m.indices[i + 2]];
            const glm::vec3 e1 = b - a, e2 = c - a, pv = glm::cross(d, e2);
            const float det = glm::dot(e1, pv);
            if (std::abs(det) < 1e-12f) continue;
            const float inv = 1.f / det;
            const glm::vec3 tv = o - a;
            const float u = glm::dot(tv, pv) * inv;
            if (u < 0.f || u > 1.f) continue;
            const glm::vec3 qv = glm::cross(tv, e1);
            const float v = glm::dot(d, qv) * inv;
            if (v < 0.f || u + v > 1.f) continue;
            const float t = glm::dot(e2, qv) * inv;
            if (t > 0.f) best = std::max(best, t);
        }
    return best;
}

}  // namespace

bool Pcss::init(const app::View& v, std::string& why) {
    release();
    for (const char* name : {"shadow_map", "pcf", "pcss"}) {
        const std::string text = app::load_snippet(name, why);
        if (text.empty()) return false;
        snippets_ += text + "\n";
    }
    snippets_ += std::string(kHelpers) + app::emitter_horizon_glsl();
    depth_prog_ = skgl::depth_only_program(why);  // gl_Position = u_light_view_proj * a_position, no color
    if (!depth_prog_) return false;
    // one map, two views: depth values (nearest, compare off) and the 2x2 compare (linear, GL_LEQUAL);
    // outside the map the border's far depth: lit
    const float border[4] = {1.f, 1.f, 1.f, 1.f};
    glGenSamplers(1, &raw_sampler_);
    glGenSamplers(1, &compare_sampler_);
    for (GLuint smp : {raw_sampler_, compare_sampler_}) {
        glSamplerParameteri(smp, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_BORDER);
        glSamplerParameteri(smp, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_BORDER);
        glSamplerParameterfv(smp, GL_TEXTURE_BORDER_COLOR, border);
    }
    glSamplerParameteri(raw_sampler_, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glSamplerParameteri(raw_sampler_, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glSamplerParameteri(raw_sampler_, GL_TEXTURE_COMPARE_MODE, GL_NONE);
    glSamplerParameteri(compare_sampler_, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glSamplerParameteri(compare_sampler_, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glSamplerParameteri(compare_sampler_, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glSamplerParameteri(compare_sampler_, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    // the casters' bounds: where pcss_fit_near_plane puts the near plane
    casters_lo_ = glm::vec3(INFINITY);  // an empty box when nothing casts
    casters_hi_ = glm::vec3(-INFINITY);
    sk::caster_bounds(*v.scene, casters_lo_, casters_hi_);
    return pass_.init(v.width, v.height, why);
}

void Pcss::update(const app::View& v, const PcssSettings& s) {
    const sk::Scene& scene = *v.scene;
    const sk::Light& L = v.light();
    error_.clear();
    if (!perspective_light(L)) {
        error_ = "PCF / PCSS need a spot, rect, disk or sphere light (one perspective map from the light's center)";
        return;
    }
    // the light's frustum from its center around the casters, widened by their penumbra (the scene's
    // with fit_casters=off)
    const sk::LightMatrices lm = s.fit_casters ? sk::fit_light_to_casters(scene, true) : sk::fit_light(scene);
    light_view_ = lm.view;
    light_proj_ = lm.proj;
    near_ = lm.znear;
    far_ = lm.zfar;
    tan_half_ = 1.f / lm.proj[1][1];
    skp::PcssLight pl;
    pl.type = skp::PcssLightType::Perspective;
    pl.size = light_width(L);
    pl.near_z = near_;
    pl.far_z = far_;
    pl.frustum_width = 2.f * tan_half_;
    // its near plane at the casters: the blocker search covers the pyramid from the receiver to the light
    // cut at the near plane, and the map gets its best depth precision
    if (s.fit_near) {
        const skp::PcssFit fit = skp::pcss_fit_near_plane(pl, light_view_, casters_lo_, casters_hi_);
        if (fit.status == skp::Status::Ok && fit.raised) {
            near_ = pl.near_z = fit.light.near_z;
            light_proj_ = glm::perspective(2.f * std::atan(tan_half_), 1.f, near_, far_);
        }
    }
    // PCSS: the light's width in uv on the near plane (the snippet's search and penumbra scale)
    if (s.filter == PcssSettings::Filter::Pcss) {
        const skp::PcssValue uv = skp::pcss_light_uv_at_near(pl);
        if (uv.status != skp::Status::Ok) {
            error_ = std::string("pcss_light_uv_at_near: ") + skp::status_name(uv.status);
            return;
        }
        light_uv_at_near_ = uv.value;
    }
    // PCF's radius from the light: half the penumbra (pcss_penumbra_width, in texels) of a blocker halfway
    // down the casters' depth along the light's axis, on what that axis meets last (the ground); [1, 32]
    radius_texels_ = s.radius_texels;
    if (s.radius_from_light) {
        float r = 2.f;  // a light without area: 2 texels
        float zmin = INFINITY, zmax = -INFINITY;
        for (const sk::Mesh& m : scene.meshes)
            if (m.caster)
                for (const glm::vec3& p : m.positions) {
                    const float z = -(lm.view * glm::vec4(p, 1.f)).z;
                    zmin = std::min(zmin, z);
                    zmax = std::max(zmax, z);
                }
        const glm::vec3 axis = -glm::normalize(glm::vec3(glm::inverse(lm.view)[2]));
        const float zb = 0.5f * (zmin + zmax), zr = std::max(farthest_axis_hit(scene, L.position, axis), zmax);
        const skp::PcssValue w = skp::pcss_penumbra_width(pl.size, zr, zb);
        const skp::PcssValue uv = skp::pcss_width_to_uv(w.value, zr, 2.f * tan_half_);
        if (pl.size > 0.f && zmax >= zmin && zmin > 0.f && w.status == skp::Status::Ok && uv.status == skp::Status::Ok)
            r = std::clamp(0.5f * uv.value * float(s.size), 1.f, 32.f);
        radius_texels_ = float(std::round(10.0 * double(r)) / 10.0);
    }
}

// A size x size depth texture and its framebuffer (depth only). No texture state: the samplers decide.
void Pcss::make_map(int size, PcssSettings::Depth depth) {
    if (map_) glDeleteTextures(1, &map_);
    if (fbo_) glDeleteFramebuffers(1, &fbo_);
    glGenTextures(1, &map_);
    glBindTexture(GL_TEXTURE_2D, map_);
    glTexStorage2D(GL_TEXTURE_2D, 1, depth == PcssSettings::Depth::Unorm24 ? GL_DEPTH_COMPONENT24 : GL_DEPTH_COMPONENT32F,
                   size, size);
    skgl::make_depth_framebuffers(GL_TEXTURE_2D, map_, 1, &fbo_);
    size_ = size;
    depth_ = depth;
}

// The V program for the filter, the bias and the rotation: #defines in front of the snippets.
bool Pcss::make_program(const PcssSettings& s) {
    const std::string defines = "#define FILTER " + std::to_string(static_cast<int>(s.filter)) + "\n#define BIAS " +
                                std::to_string(static_cast<int>(s.bias)) + "\n#define ROTATE " + (s.rotate ? "1" : "0") + "\n";
    if (vis_prog_ && defines == vis_defines_) return true;
    if (vis_prog_) glDeleteProgram(vis_prog_);
    vis_prog_ = app::compile_visibility_program(defines + snippets_, kLookup, error_);
    vis_defines_ = defines;
    return vis_prog_ != 0;
}

void Pcss::render(const app::View& v, const PcssSettings& s) {
    if (!error_.empty()) return;
    if (s.size != size_ || s.depth != depth_) make_map(s.size, s.depth);
    if (!make_program(s)) return;
    const glm::mat4 light_vp = light_proj_ * light_view_;

    // 1. The casters' depth from the light: depth test GL_LESS, cleared to the far plane, both faces,
    //    no polygon offset (the lookup biases).
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glViewport(0, 0, size_, size_);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glDisable(GL_POLYGON_OFFSET_FILL);
    glClearDepth(1.0);
    glClear(GL_DEPTH_BUFFER_BIT);
    glUseProgram(depth_prog_);
    glUniformMatrix4fv(glGetUniformLocation(depth_prog_, "u_light_view_proj"), 1, GL_FALSE, glm::value_ptr(light_vp));
    for (std::size_t i = 0; i < v.gpu->meshes.size(); ++i)
        if (v.gpu->caster[i]) skgl::draw_mesh(v.gpu->meshes[i]);

    // 2. V at the G-buffer's points: the map at unit 2 as depths, at unit 3 as 2x2 compares.
    const GLuint p = vis_prog_;
    const sk::Light& L = v.light();
    glUseProgram(p);
    app::set_light_uniforms(p, L);
    app::set_emitter_uniforms(p, L, s.horizon && L.is_area());  // rect, disk, sphere of nonzero size
    const auto loc = [p](const char* name) { return glGetUniformLocation(p, name); };
    glUniformMatrix4fv(loc("u_light_view_proj"), 1, GL_FALSE, glm::value_ptr(light_vp));
    glUniformMatrix4fv(loc("u_light_view"), 1, GL_FALSE, glm::value_ptr(light_view_));
    glUniform3fv(loc("u_light_eye"), 1, glm::value_ptr(L.position));
    glUniform1f(loc("u_near"), near_);
    glUniform1f(loc("u_far"), far_);
    glUniform1f(loc("u_texel_uv"), 1.f / float(size_));
    glUniform1f(loc("u_tan_half"), tan_half_);
    glUniform1f(loc("u_margin"), s.plane_margin);
    glUniform1f(loc("u_const_bias"), 2e-6f);  // float32 rounding of the G-buffer's positions and the map's depths
    glUniform1f(loc("u_depth_step"), s.depth == PcssSettings::Depth::Unorm24 ? float(1.0 / 16777215.0) : 0.0f);  // the automatic bias
    glUniform1f(loc("u_constant_bias"), s.constant_bias);
    glUniform1f(loc("u_slope_scale"), s.slope_scale);
    glUniform1f(loc("u_normal_offset"), s.normal_offset);
    glUniform1i(loc("u_radius_texels"), static_cast<int>(std::lround(radius_texels_)));
    glUniform1f(loc("u_radius_uv"), radius_texels_ / float(size_));
    glUniform1i(loc("u_taps"), s.taps);
    glUniform1f(loc("u_light_uv_at_near"), light_uv_at_near_);
    glUniform1f(loc("u_max_filter_uv"), skp::PcssPolicy{}.max_filter_uv);
    glActiveTexture(GL_TEXTURE2);
    glBindTexture(GL_TEXTURE_2D, map_);
    glBindSampler(2, raw_sampler_);
    glActiveTexture(GL_TEXTURE3);
    glBindTexture(GL_TEXTURE_2D, map_);
    glBindSampler(3, compare_sampler_);
    pass_.draw(p, *v.gpu);
    glBindSampler(2, 0);
    glBindSampler(3, 0);
}

void Pcss::release() {  // (no GL call without objects: the App may have no context)
    if (map_) glDeleteTextures(1, &map_);
    if (fbo_) glDeleteFramebuffers(1, &fbo_);
    if (raw_sampler_) glDeleteSamplers(1, &raw_sampler_);
    if (compare_sampler_) glDeleteSamplers(1, &compare_sampler_);
    if (depth_prog_) glDeleteProgram(depth_prog_);
    if (vis_prog_) glDeleteProgram(vis_prog_);
    map_ = fbo_ = raw_sampler_ = compare_sampler_ = depth_prog_ = vis_prog_ = 0;
    size_ = 0;
    snippets_.clear();
    vis_defines_.clear();
    error_.clear();
}
