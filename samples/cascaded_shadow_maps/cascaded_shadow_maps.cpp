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
    if (!depth_prog_ || !vis_prog_ || !vis_auto_prog_) return false;
    return pass_.init(v.width, v.height, why);
}

void CascadedShadowMaps::update(const app::View& v, const CascadedShadowMapSettings& s) {
    const sk::Light& L = v.light();
    shadowkit::CascadeInput in;
    in.camera_view = v.view;
    in.camera_proj = v.proj;  // its far plane ends the last cascade (max_distance could end them sooner)
    // the sun as one vec4: w = 0, xyz toward it; any other light is refused (InvalidLight)
    in.light_position = L.type == sk::LightType::Directional ? glm::vec4(-glm::normalize(L.direction), 0.f)
                                                             : glm::vec4(L.position, 1.f);
    in.shadow_map_size = static_cast<std::uint32_t>(s.size);
    in.has_caster_bounds = true;
    in.caster_min = caster_lo_;
    in.caster_max = caster_hi_;
    const auto count = static_cast<std::uint32_t>(s.count);
    fit_ = shadowkit::cascade_fit(in, s.lambda, count, cascades_, 4);
    error_.clear();
    if (fit_.status != shadowkit::Status::Ok)
        error_ = std::string("cascade_fit status ") + shadowkit::status_name(fit_.status) +
                 (fit_.status == shadowkit::Status::InvalidLight ? " (cascades need a directional light)" : "");
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
    skgl::make_depth_framebuffers(GL_TEXTURE_2D_ARRAY, maps_, count, fbo_);
    glGenTextures(count, layer_view_);
    for (int i = 0; i < count; ++i)
        glTextureView(layer_view_[i], GL_TEXTURE_2D, maps_, GL_DEPTH_COMPONENT32F, 0, 1, static_cast<GLuint>(i), 1);
    size_ = size;
    layers_ = count;
}

void CascadedShadowMaps::render(const app::View& v, const CascadedShadowMapSettings& s) {
    if (s.size != size_ || s.count != layers_) make_maps(s.size, s.count);
    const bool ok = error_.empty();

    const bool automatic = s.bias == CascadedShadowMapSettings::Bias::Auto;

    // 1. The casters' depth into each cascade's layer with its matrix: depth test GL_LESS, cleared to
    //    the far plane; bias=polygon_offset: polygon offset (2, 2) (the automatic bias compares with the
    //    true depths). No cascades (a light that is not the sun): empty maps.
    glUseProgram(depth_prog_);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glClearDepth(1.0);
    if (!automatic) {
        glEnable(GL_POLYGON_OFFSET_FILL);
        glPolygonOffset(2.f, 2.f);
    }
    glm::mat4 vps[4];
    float texel[4] = {0.f, 0.f, 0.f, 0.f};
    for (int i = 0; i < layers_; ++i) {
        glBindFramebuffer(GL_FRAMEBUFFER, fbo_[i]);
        glViewport(0, 0, size_, size_);
        glClear(GL_DEPTH_BUFFER_BIT);
        if (!ok) continue;
        vps[i] = cascades_[i].view_proj;
        texel[i] = cascades_[i].texel_world_size;
        glUniformMatrix4fv(glGetUniformLocation(depth_prog_, "u_light_view_proj"), 1, GL_FALSE, glm::value_ptr(vps[i]));
        for (std::size_t m = 0; m < v.gpu->meshes.size(); ++m)
            if (v.gpu->caster[m]) skgl::draw_mesh(v.gpu->meshes[m]);
    }
    glDisable(GL_POLYGON_OFFSET_FILL);

    // 2. V at the G-buffer's points: the matrices, the splits as each cascade's near and far view depth.
    const float* sp = fit_.splits;
    const GLuint prog = automatic ? vis_auto_prog_ : vis_prog_;
    glUseProgram(prog);
    app::set_light_uniforms(prog, v.light());
    glUniformMatrix4fv(glGetUniformLocation(prog, "u_cascade_vp"), 4, GL_FALSE, glm::value_ptr(vps[0]));
    glUniform4f(glGetUniformLocation(prog, "u_split_near"), sp[0], sp[1], sp[2], sp[3]);
    glUniform4f(glGetUniformLocation(prog, "u_split_far"), sp[1], sp[2], sp[3], sp[4]);
    glUniform1i(glGetUniformLocation(prog, "u_count"), ok ? layers_ : 0);
    glUniform1f(glGetUniformLocation(prog, "u_band"), s.band);
    glUniform1i(glGetUniformLocation(prog, "u_pcf_radius"), s.pcf_radius);
    glUniformMatrix4fv(glGetUniformLocation(prog, "u_camera_view"), 1, GL_FALSE, glm::value_ptr(v.view));
    if (!automatic) {
        glUniform1fv(glGetUniformLocation(prog, "u_texel"), 4, texel);
        glUniform1f(glGetUniformLocation(prog, "u_normal_offset"), s.normal_offset);
    }
    pass_.draw(prog, *v.gpu, GL_TEXTURE_2D_ARRAY, maps_);
}

void CascadedShadowMaps::release() {  // (no GL call without objects: the App may have no context)
    if (maps_) glDeleteTextures(1, &maps_);
    if (layer_view_[0]) glDeleteTextures(4, layer_view_);
    if (fbo_[0]) glDeleteFramebuffers(4, fbo_);
    if (depth_prog_) glDeleteProgram(depth_prog_);
    if (vis_prog_) glDeleteProgram(vis_prog_);
    if (vis_auto_prog_) glDeleteProgram(vis_auto_prog_);
    maps_ = depth_prog_ = vis_prog_ = vis_auto_prog_ = 0;
    std::fill(fbo_, fbo_ + 4, 0u);
    std::fill(layer_view_, layer_view_ + 4, 0u);
    size_ = layers_ = 0;
    error_.clear();
}
