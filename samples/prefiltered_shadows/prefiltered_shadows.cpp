// samples/prefiltered_shadows/prefiltered_shadows.cpp - pre-filtered shadow maps, top to bottom:
//   init    the programs: the moment pass, the separable blur, the MSAA resolve and its depth-only pass,
//           the lookup (glsl/prefiltered_shadow.glsl); the V target
//   update  CPU, every frame: the light's frustum (sk::fit_light), the moment depth t over its depth
//           range (prefilter_depth_range), the method's uniforms checked against the texture format
//           (prefilter_uniforms: exponents below the format's overflow limit), the blur's weights
//           (prefilter_blur_weights; its width from the light's penumbra: prefilter_kernel_texels)
//   render  GPU, every frame: 1 every mesh's moments from the light (or its 4x multisampled depth,
//           resolved into moments); 2 the blur, horizontal then vertical; 3 optional mipmaps; 4 V at
//           the G-buffer's points from the filtered moments, times the emitter's horizon; soft=on: the
//           mip levels of the blocker search and of the penumbra (prefilter_soft_uniforms)
// Every mesh goes into the map, receivers too: a filter compares a receiver with its own depth in the
// map (a texel left at the clear value t = 1 behind a receiver lights it, ESM by e^(c (1 - t))).
#include "prefiltered_shadows.hpp"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>

namespace {

namespace skp = shadowkit;

const char* kMomentVS = R"(#version 450 core
layout(location = 0) in vec3 a_position;
uniform mat4 u_light_view_proj;
uniform mat4 u_light_view;
out float v_light_distance;
void main() {
    v_light_distance = -(u_light_view * vec4(a_position, 1.0)).z;
    gl_Position = u_light_view_proj * vec4(a_position, 1.0);
}
)";
// (after the snippet) t from the eye distance along the light's axis, its moments
const char* kMomentFS = R"(
in float v_light_distance;
uniform vec2 u_depth_scale_offset;
uniform int u_method;
uniform vec2 u_exponents;
uniform bool u_quantized;
layout(location = 0) out vec4 o_moments;
void main() {
    float t = sk_prefilter_depth(v_light_distance, u_depth_scale_offset);
    o_moments = sk_prefilter_moments(t, vec2(dFdx(t), dFdy(t)), u_method, u_exponents, u_quantized);
}
)";
const char* kBlurFS = R"(
layout(binding = 0) uniform sampler2D u_src;
uniform ivec2 u_dir;
uniform int u_radius;
uniform float u_weights[SK_PREFILTER_MAX_WEIGHTS];
layout(location = 0) out vec4 o_moments;
void main() { o_moments = sk_prefilter_blur(u_src, ivec2(gl_FragCoord.xy), u_dir, u_radius, u_weights); }
)";
const char* kResolveFS = R"(
layout(binding = 0) uniform sampler2DMS u_depth_ms;
uniform int u_samples;
uniform vec4 u_window_map;
uniform int u_method;
uniform vec2 u_exponents;
uniform bool u_quantized;
layout(location = 0) out vec4 o_moments;
void main() {
    o_moments = sk_prefilter_resolve(u_depth_ms, ivec2(gl_FragCoord.xy), u_samples, u_window_map, u_method, u_exponents,
                                     u_quantized);
}
)";
// V at a G-buffer point (after shadow_map.glsl, the snippet and the emitter's horizon): the receiver's t
// minus its bias against the filtered moments at its uv; outside the map: lit.
const char* kLookup = R"(
layout(binding = 2) uniform sampler2D u_moments;
uniform mat4 u_light_view_proj;
uniform mat4 u_light_view;
uniform vec3 u_light_eye;
uniform vec2 u_depth_scale_offset;
uniform int u_method;
uniform vec4 u_params;
uniform float u_moment_bias;
uniform bool u_quantized;
uniform float u_depth_bias;
uniform float u_slope_bias;
uniform float u_slope_bias_max;
uniform float u_kernel_uv;
uniform bool u_mips;
uniform bool u_soft_on;  // and u_soft = PrefilterSoftUniforms::params()
uniform vec4 u_soft;
// (u, v, t) of a world point
vec3 uvt(vec3 q) {
    return vec3(sk_shadow_coord(u_light_view_proj, q, false).xy, sk_prefilter_depth(-(u_light_view * vec4(q, 1.0)).z, u_depth_scale_offset));
}
float technique_visibility(vec3 p, vec3 n) {
    vec4 c = sk_shadow_coord(u_light_view_proj, p, false);
    if (c.w <= 0.0 || any(lessThan(c.xy, vec2(0.0))) || any(greaterThan(c.xy, vec2(1.0)))) return sk_emitter_horizon(p, n);
    float t = sk_prefilter_depth(-(u_light_view * vec4(p, 1.0)).z, u_depth_scale_offset) - u_depth_bias;
    vec3 d1 = vec3(0.0), d2 = vec3(0.0);  // the receiver plane's (u, v, t) steps (0: no receiver-plane bias)
    if (u_slope_bias > 0.0) {  // two tangent steps (the G-buffer knows the plane)
        vec3 a = abs(n.y) < 0.9 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
        vec3 t1 = normalize(cross(n, a)), t2 = cross(n, t1);
        float h = 1e-2 * max(length(p - u_light_eye), 1e-4);
        vec3 o = uvt(p);
        d1 = uvt(p + h * t1) - o, d2 = uvt(p + h * t2) - o;
    }
    if (u_soft_on)  // the blocker search and the penumbra's filter, each a textureLod of the mip chain
        return sk_prefilter_soft_visibility(u_moments, c.xy, t, u_method, u_params, u_moment_bias, u_quantized, u_soft,
                                            vec2(u_slope_bias * sk_prefilter_receiver_slope(d1, d2), u_slope_bias_max)) *
               sk_emitter_horizon(p, n);
    t -= min(u_slope_bias * sk_prefilter_receiver_bias(d1, d2, u_kernel_uv), u_slope_bias_max);
    vec4 m = u_mips ? texture(u_moments, c.xy) : textureLod(u_moments, c.xy, 0.0);
    return sk_prefilter_visibility(m, t, u_method, u_params, u_moment_bias, u_quantized) * sk_emitter_horizon(p, n);
}
)";

// The texture format of `channels` moments in `f`.
GLenum texture_format(int channels, skp::PrefilterFormat f) {
    const bool f16 = f == skp::PrefilterFormat::Float16, u16 = f == skp::PrefilterFormat::Unorm16;
    if (channels == 1) return f16 ? GL_R16F : (u16 ? GL_R16 : GL_R32F);
    if (channels == 2) return f16 ? GL_RG16F : (u16 ? GL_RG16 : GL_RG32F);
    return f16 ? GL_RGBA16F : (u16 ? GL_RGBA16 : GL_RGBA32F);
}

std::string failed(const char* what, skp::Status st) { return std::string(what) + ": " + skp::status_name(st); }

}  // namespace

bool PrefilteredShadows::init(const app::View& v, std::string& why) {
    release();
    const std::string snippet = app::load_snippet("prefiltered_shadow", why);
    const std::string shadow_map = app::load_snippet("shadow_map", why);
    if (snippet.empty() || shadow_map.empty()) return false;
    const std::string head = "#version 450 core\n" + snippet + "\n";
    const std::string full_vs = app::fullscreen_vertex_shader();
    moment_prog_ = skgl::compile_program({{GL_VERTEX_SHADER, kMomentVS}, {GL_FRAGMENT_SHADER, head + kMomentFS}}, why);
    blur_prog_ = skgl::compile_program({{GL_VERTEX_SHADER, full_vs}, {GL_FRAGMENT_SHADER, head + kBlurFS}}, why);
    resolve_prog_ = skgl::compile_program({{GL_VERTEX_SHADER, full_vs}, {GL_FRAGMENT_SHADER, head + kResolveFS}}, why);
    depth_prog_ = skgl::depth_only_program(why);  // gl_Position = u_light_view_proj * a_position, no color
    vis_prog_ = app::compile_visibility_program(shadow_map + "\n" + snippet + "\n" + app::emitter_horizon_glsl(), kLookup, why);
    if (!moment_prog_ || !blur_prog_ || !resolve_prog_ || !depth_prog_ || !vis_prog_) return false;
    glGenVertexArrays(1, &vao_);  // the full-screen triangle's (empty)
    return pass_.init(v.width, v.height, why);
}

void PrefilteredShadows::update(const app::View& v, const PrefilteredShadowSettings& s) {
    const sk::Scene& scene = *v.scene;
    const sk::Light& L = v.light();
    error_.clear();
    if (L.type == sk::LightType::Point || L.type == sk::LightType::Linear) {
        error_ = "pre-filtered maps here need a spot, rect, disk, sphere or directional light (one 2D map)";
        return;
    }
    // the light's frustum around the scene: a perspective from its center, or an orthographic box
    lm_ = s.fit_casters ? sk::fit_light_to_casters(scene, true) : sk::fit_light(scene);
    // t = (d - near) / (far - near) along the light's axis; the same t from a depth buffer (MSAA resolve)
    range_ = skp::prefilter_depth_range(lm_.znear, lm_.zfar);
    window_map_ = skp::prefilter_window_depth_map(lm_.znear, lm_.zfar, lm_.perspective, false, range_);
    // the method's uniforms, checked against the format (exponents below its overflow limit)
    const bool msm = s.method == skp::PrefilterMethod::Msm || s.method == skp::PrefilterMethod::MsmHausdorff;
    using F = PrefilteredShadowSettings::Format;
    format_ = s.format == F::Float16   ? skp::PrefilterFormat::Float16
              : s.format == F::Unorm16 ? skp::PrefilterFormat::Unorm16
              : s.format == F::Auto && msm ? skp::PrefilterFormat::Unorm16
                                           : skp::PrefilterFormat::Float32;
    skp::PrefilterSettings ps;
    ps.method = s.method;
    ps.format = format_;
    const skp::PrefilterExponent limit = skp::prefilter_exponent_limit(s.method, format_, 1);
    ps.exponent_positive = limit.status == skp::Status::Ok ? static_cast<float>(s.exponent_fraction * double(limit.exponent)) : -1.f;
    ps.exponent_negative = s.exponent_negative;
    ps.bleed_reduction = s.bleed_reduction;
    ps.min_variance = s.min_variance_scale * skp::prefilter_min_variance(format_);
    ps.moment_bias = s.moment_bias_scale * skp::prefilter_msm_moment_bias(format_);
    u_ = skp::prefilter_uniforms(ps);
    // the blur: its width in texels, or the light's penumbra there: the emitter's width x (z_r - z_b) / z_b
    // for a blocker halfway down the casters and a receiver at the far end, in texels of this map
    float width = s.blur_texels;
    const float light_width = !L.is_area() ? 0.f : (L.type == sk::LightType::Rect ? L.size : 2.f * L.size);
    if (s.blur_from_light && !s.soft) {
        width = 1.f;  // no blur for a light without area
        float zmin = INFINITY, zmax = -INFINITY;
        for (const sk::Mesh& m : scene.meshes)
            if (m.caster)
                for (const glm::vec3& p : m.positions) {
                    const float z = -(lm_.view * glm::vec4(p, 1.f)).z;
                    zmin = std::min(zmin, z);
                    zmax = std::max(zmax, z);
                }
        const float zb = 0.5f * (zmin + zmax), zr = lm_.zfar / 1.01f;
        const bool emitter = L.is_area() && L.type != sk::LightType::Directional;
        if (emitter && lm_.perspective && zb > 0.f && zr > zb) {
            const skp::PrefilterKernelWidth k = skp::prefilter_kernel_texels(lm_.proj, light_width * (zr - zb) / zb, zr, s.size, s.size);
            if (k.status == skp::Status::Ok) width = std::clamp(std::round(10.f * k.texels.x) / 10.f, 1.f, 65.f);
        }
    }
    kernel_ = skp::prefilter_blur_weights(s.blur, width, weights_, skp::kPrefilterMaxWeights);
    // soft: the map's projection (from the emitter's center), the emitter's width, the range and map size
    soft_ = s.soft ? skp::prefilter_soft_uniforms({lm_.proj, light_width, range_, s.size}) : skp::PrefilterSoftUniforms{};
    if (range_.status != skp::Status::Ok) error_ = failed("prefilter_depth_range", range_.status);
    else if (u_.status != skp::Status::Ok) error_ = failed("prefilter_uniforms", u_.status);
    else if (kernel_.status != skp::Status::Ok) error_ = failed("prefilter_blur_weights", kernel_.status);
    else if (window_map_.status != skp::Status::Ok) error_ = failed("prefilter_window_depth_map", window_map_.status);
    else if (s.soft && soft_.status != skp::Status::Ok) error_ = failed("prefilter_soft_uniforms (soft needs a perspective map)", soft_.status);
}

// The moment map (size x size, the format's channels; with a depth buffer unless MSAA; mipmapped on
// request), the blur's intermediate of the same format, and for MSAA a 4x multisampled depth texture.
void PrefilteredShadows::make_maps(const PrefilteredShadowSettings& s) {
    skgl::destroy_target(moments_);
    skgl::destroy_target(blurred_);
    if (ms_fbo_) glDeleteFramebuffers(1, &ms_fbo_);
    if (ms_depth_) glDeleteTextures(1, &ms_depth_);
    ms_fbo_ = ms_depth_ = 0;
    size_ = s.size;
    texture_format_ = texture_format(u_.channels, format_);
    mips_ = s.mips || s.soft;
    msaa_ = s.msaa;
    if (!skgl::make_target(moments_, size_, size_, {texture_format_}, msaa_ ? 0 : GL_DEPTH_COMPONENT32F, error_) ||
        !skgl::make_target(blurred_, size_, size_, {texture_format_}, 0, error_))
        return;
    if (mips_) {  // every level (make_target allocates one): a new texture in its place
        const int levels = 1 + static_cast<int>(std::floor(std::log2(double(size_))));
        glDeleteTextures(1, &moments_.color[0]);
        glGenTextures(1, &moments_.color[0]);
        glBindTexture(GL_TEXTURE_2D, moments_.color[0]);
        glTexStorage2D(GL_TEXTURE_2D, levels, texture_format_, size_, size_);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        glBindFramebuffer(GL_FRAMEBUFFER, moments_.fbo);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, moments_.color[0], 0);
    }
    // the lookup filters the moments: bilinear, or trilinear over the mipmaps
    glBindTexture(GL_TEXTURE_2D, moments_.color[0]);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, mips_ ? GL_LINEAR_MIPMAP_LINEAR : GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    if (msaa_) {
        glGenTextures(1, &ms_depth_);
        glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, ms_depth_);
        glTexStorage2DMultisample(GL_TEXTURE_2D_MULTISAMPLE, 4, GL_DEPTH_COMPONENT32F, size_, size_, GL_TRUE);
        glGenFramebuffers(1, &ms_fbo_);
        glBindFramebuffer(GL_FRAMEBUFFER, ms_fbo_);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D_MULTISAMPLE, ms_depth_, 0);
        glDrawBuffer(GL_NONE);
        glReadBuffer(GL_NONE);
    }
}

// A full-screen triangle into dst (viewport = the map), no depth test, no blending.
void PrefilteredShadows::fullscreen(GLuint prog, const skgl::Target& dst) const {
    glBindFramebuffer(GL_FRAMEBUFFER, dst.fbo);
    glViewport(0, 0, size_, size_);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glUseProgram(prog);
    glBindVertexArray(vao_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
}

void PrefilteredShadows::render(const app::View& v, const PrefilteredShadowSettings& s) {
    if (!error_.empty()) return;
    if (s.size != size_ || texture_format(u_.channels, format_) != texture_format_ || (s.mips || s.soft) != mips_ || s.msaa != msaa_)
        make_maps(s);
    if (!error_.empty()) return;
    const glm::mat4 vp = lm_.proj * lm_.view;

    // 1. The moments of every mesh from the light: depth test GL_LESS, no culling, blending or polygon
    //    offset, cleared to the moments of t = 1 (nothing there). MSAA: the depth of 4 samples a texel,
    //    then per texel the mean of the samples' moments (sk_prefilter_resolve).
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glDisable(GL_POLYGON_OFFSET_FILL);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glClearDepth(1.0);
    if (msaa_) {
        glBindFramebuffer(GL_FRAMEBUFFER, ms_fbo_);
        glViewport(0, 0, size_, size_);
        glClear(GL_DEPTH_BUFFER_BIT);
        glUseProgram(depth_prog_);
        glUniformMatrix4fv(glGetUniformLocation(depth_prog_, "u_light_view_proj"), 1, GL_FALSE, glm::value_ptr(vp));
        for (const skgl::GpuMesh& mesh : v.gpu->meshes) skgl::draw_mesh(mesh);
        glUseProgram(resolve_prog_);
        glUniform1i(glGetUniformLocation(resolve_prog_, "u_samples"), 4);
        glUniform4fv(glGetUniformLocation(resolve_prog_, "u_window_map"), 1, glm::value_ptr(window_map_.coefficients));
        glUniform1i(glGetUniformLocation(resolve_prog_, "u_method"), u_.method_code);
        glUniform2fv(glGetUniformLocation(resolve_prog_, "u_exponents"), 1, glm::value_ptr(u_.exponents));
        glUniform1i(glGetUniformLocation(resolve_prog_, "u_quantized"), u_.quantized ? 1 : 0);
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, ms_depth_);
        fullscreen(resolve_prog_, moments_);
    } else {
        glBindFramebuffer(GL_FRAMEBUFFER, moments_.fbo);
        glViewport(0, 0, size_, size_);
        glClearBufferfv(GL_COLOR, 0, glm::value_ptr(u_.clear_value));
        glClear(GL_DEPTH_BUFFER_BIT);
        glUseProgram(moment_prog_);
        glUniformMatrix4fv(glGetUniformLocation(moment_prog_, "u_light_view_proj"), 1, GL_FALSE, glm::value_ptr(vp));
        glUniformMatrix4fv(glGetUniformLocation(moment_prog_, "u_light_view"), 1, GL_FALSE, glm::value_ptr(lm_.view));
        glUniform2f(glGetUniformLocation(moment_prog_, "u_depth_scale_offset"), range_.scale, range_.offset);
        glUniform1i(glGetUniformLocation(moment_prog_, "u_method"), u_.method_code);
        glUniform2fv(glGetUniformLocation(moment_prog_, "u_exponents"), 1, glm::value_ptr(u_.exponents));
        glUniform1i(glGetUniformLocation(moment_prog_, "u_quantized"), u_.quantized ? 1 : 0);
        for (const skgl::GpuMesh& mesh : v.gpu->meshes) skgl::draw_mesh(mesh);
    }

    // 2. The blur: horizontal into the intermediate, vertical back (texelFetch, clamped to the map).
    if (kernel_.radius > 0) {
        glUseProgram(blur_prog_);
        glUniform1i(glGetUniformLocation(blur_prog_, "u_radius"), kernel_.radius);
        glUniform1fv(glGetUniformLocation(blur_prog_, "u_weights"), static_cast<GLsizei>(kernel_.count), weights_);
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(GL_TEXTURE_2D, moments_.color[0]);
        glUniform2i(glGetUniformLocation(blur_prog_, "u_dir"), 1, 0);
        fullscreen(blur_prog_, blurred_);
        glBindTexture(GL_TEXTURE_2D, blurred_.color[0]);
        glUniform2i(glGetUniformLocation(blur_prog_, "u_dir"), 0, 1);
        fullscreen(blur_prog_, moments_);
    }
    // 3. Mipmaps of the moments: any hardware filter of moments is a valid filtered texel.
    if (mips_) {
        glBindTexture(GL_TEXTURE_2D, moments_.color[0]);
        glGenerateMipmap(GL_TEXTURE_2D);
    }
    glBindVertexArray(0);

    // 4. V at the G-buffer's points: the filtered moments at unit 2.
    const GLuint p = vis_prog_;
    const sk::Light& L = v.light();
    glUseProgram(p);
    app::set_light_uniforms(p, L);
    app::set_emitter_uniforms(p, L, L.is_area());  // rect, disk, sphere of nonzero size (no line lights here)
    const auto loc = [p](const char* name) { return glGetUniformLocation(p, name); };
    glUniformMatrix4fv(loc("u_light_view_proj"), 1, GL_FALSE, glm::value_ptr(vp));
    glUniformMatrix4fv(loc("u_light_view"), 1, GL_FALSE, glm::value_ptr(lm_.view));
    glUniform3fv(loc("u_light_eye"), 1, glm::value_ptr(glm::vec3(glm::inverse(lm_.view)[3])));
    glUniform2f(loc("u_depth_scale_offset"), range_.scale, range_.offset);
    glUniform1i(loc("u_method"), u_.method_code);
    glUniform4fv(loc("u_params"), 1, glm::value_ptr(u_.params()));
    glUniform1f(loc("u_moment_bias"), u_.moment_bias);
    glUniform1i(loc("u_quantized"), u_.quantized ? 1 : 0);
    glUniform1f(loc("u_depth_bias"), s.depth_bias);
    glUniform1f(loc("u_slope_bias"), s.slope_bias);
    glUniform1f(loc("u_slope_bias_max"), s.slope_bias_max);
    glUniform1f(loc("u_kernel_uv"), float(kernel_.radius + 1) / float(size_));
    glUniform1i(loc("u_mips"), mips_ ? 1 : 0);
    glUniform1i(loc("u_soft_on"), soft_.status == skp::Status::Ok ? 1 : 0);
    glUniform4fv(loc("u_soft"), 1, glm::value_ptr(soft_.params()));
    pass_.draw(p, *v.gpu, GL_TEXTURE_2D, moments_.color[0]);
}

void PrefilteredShadows::release() {  // (no GL call without objects: the App may have no context)
    skgl::destroy_target(moments_);
    skgl::destroy_target(blurred_);
    if (ms_fbo_) glDeleteFramebuffers(1, &ms_fbo_);
    if (ms_depth_) glDeleteTextures(1, &ms_depth_);
    if (vao_) glDeleteVertexArrays(1, &vao_);
    for (GLuint* prog : {&moment_prog_, &blur_prog_, &resolve_prog_, &depth_prog_, &vis_prog_}) {
        if (*prog) glDeleteProgram(*prog);
        *prog = 0;
    }
    ms_fbo_ = ms_depth_ = vao_ = 0;
    size_ = 0;
    texture_format_ = 0;
}
