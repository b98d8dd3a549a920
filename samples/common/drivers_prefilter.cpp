// Drivers for the pre-filtered shadow maps: shadowkit/prefiltered_shadow.hpp on the CPU (depth
// range, uniforms checked against the texture format, blur weights, kernel width) and
// glsl/prefiltered_shadow.glsl on the GPU (moment pass, separable blur, optional MSAA resolve and
// mipmaps, lookup). One technique per method, so each has its own colour on the error-vs-time chart:
// vsm, esm, evsm2, evsm4, msm, msm_hausdorff.
//
// Pipeline per frame (the same a user writes from the snippet's header comment):
// 1. moment pass: every mesh (casters AND receivers: the filters compare a receiver with its own
//    depth in the map; a texel left at the clear value t = 1 behind a receiver lights it, ESM by
//    e^(c (1 - t)), so receivers that cast nothing must be drawn too) into a size x size colour
//    target (format from `format`) with a depth
//    buffer, cleared to PrefilterUniforms::clear_value; the fragment computes t from its eye distance
//    along the light's axis over [znear, zfar] of fit_light (the scene's extent along the light) and
//    writes sk_prefilter_moments (VSM with the depth-derivative term). msaa=4: the meshes' depth into
//    a 4x multisampled depth texture instead, then sk_prefilter_resolve per texel.
// 2. blur: sk_prefilter_blur horizontally into a second texture and vertically back, Gaussian (or
//    box, blur=0) of full width `width` texels (prefilter_blur_weights); width 1 = no blur.
// 3. (mips=1) glGenerateMipmap and trilinear lookups; otherwise bilinear on level 0.
// 4. lookup at the G-buffer points: sk_prefilter_visibility(texture(moments, uv), t - depth_bias) x
//    the emitter's fraction above the tangent plane (as PCF / PCSS do on area lights). depth_bias:
//    a constant (MSM 0.002, others 0) plus, with slope_bias > 0 (off by default), slope_bias x
//    sk_prefilter_receiver_bias of the G-buffer's plane for the blur's radius, capped at
//    slope_bias_max: it removes the self-shadowing of lit faces steep to the light under a wide blur
//    (contact, quick: MSM RMSE 0.060 -> 0.022) but lights the umbra right behind an occluder on a
//    grazing receiver (grazing: 0.071 -> 0.36), so the rows run without it.
// The light: fit_light (spot, rect, disk and sphere lights: a perspective from the light's centre;
// directional: an orthographic fit). Point and line lights are not driven (they need cube maps).
#include <shadowkit/prefiltered_shadow.hpp>

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <string>

#include "driver_util.hpp"

namespace sk {

namespace {

const char* kMethodNames[6] = {"vsm", "esm", "evsm2", "evsm4", "msm", "msm_hausdorff"};

bool prefilter_light(const Light& L) {
    return L.type == LightType::Spot || L.type == LightType::Directional || L.type == LightType::Rect ||
           L.type == LightType::Disk || L.type == LightType::Sphere;
}

bool area_emitter(const Light& L) {
    return L.is_area() && (L.type == LightType::Rect || L.type == LightType::Disk || L.type == LightType::Sphere);
}

// The blur width that matches the light's penumbra (world units, converted to texels with
// prefilter_kernel_texels): the emitter's width x (z_r - z_b) / z_b for a blocker at the middle of
// the casters' extent along the light's axis and a receiver at the far end of the scene, measured
// there; 1 (no blur) for lights without area. Clamped to [1, 65] texels.
float penumbra_width_texels(const Scene& s, const LightMatrices& lm, int size) {
    const Light& L = s.light;
    if (!area_emitter(L) || !lm.perspective) return 1.f;
    const float light_width = L.type == LightType::Rect ? L.size : 2.f * L.size;
    float zmin = INFINITY, zmax = -INFINITY;
    for (const auto& m : s.meshes) {
        if (!m.caster) continue;
        for (const auto& p : m.positions) {
            const float z = -(lm.view * glm::vec4(p, 1.f)).z;
            zmin = std::min(zmin, z);
            zmax = std::max(zmax, z);
        }
    }
    const float zb = 0.5f * (zmin + zmax), zr = lm.zfar / 1.01f;
    if (!(zb > 0.f) || !(zr > zb)) return 1.f;
    const shadowkit::PrefilterKernelWidth k =
        shadowkit::prefilter_kernel_texels(lm.proj, light_width * (zr - zb) / zb, zr, size, size);
    if (k.status != shadowkit::Status::Ok) return 1.f;
    return std::clamp(std::round(10.f * k.texels.x) / 10.f, 1.f, 65.f);
}

GLenum texture_format(int channels, shadowkit::PrefilterFormat f) {
    using shadowkit::PrefilterFormat;
    if (channels == 1) return f == PrefilterFormat::Float16 ? GL_R16F : (f == PrefilterFormat::Unorm16 ? GL_R16 : GL_R32F);
    if (channels == 2) return f == PrefilterFormat::Float16 ? GL_RG16F : (f == PrefilterFormat::Unorm16 ? GL_RG16 : GL_RG32F);
    return f == PrefilterFormat::Float16 ? GL_RGBA16F : (f == PrefilterFormat::Unorm16 ? GL_RGBA16 : GL_RGBA32F);
}

int format_bytes(shadowkit::PrefilterFormat f) { return f == shadowkit::PrefilterFormat::Float32 ? 4 : 2; }

const char* kMomentVS = R"(
layout(location = 0) in vec3 a_position;
uniform mat4 u_light_view_proj;
uniform mat4 u_light_view;
out float v_light_distance;
void main() {
    v_light_distance = -(u_light_view * vec4(a_position, 1.0)).z;
    gl_Position = u_light_view_proj * vec4(a_position, 1.0);
}
)";

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

const char* kLookupBody = R"(
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
// (u, v, t) of a world point
vec3 skd_uvt(vec3 q) {
    return vec3(sk_shadow_coord(u_light_view_proj, q, false).xy, sk_prefilter_depth(-(u_light_view * vec4(q, 1.0)).z, u_depth_scale_offset));
}
float technique_visibility(vec3 p, vec3 n) {
    vec4 c = sk_shadow_coord(u_light_view_proj, p, false);
    if (c.w <= 0.0 || any(lessThan(c.xy, vec2(0.0))) || any(greaterThan(c.xy, vec2(1.0)))) return sk_emitter_horizon(p, n);
    float t = sk_prefilter_depth(-(u_light_view * vec4(p, 1.0)).z, u_depth_scale_offset) - u_depth_bias;
    if (u_slope_bias > 0.0) {  // the receiver plane's (u, v, t) at two tangent steps (the G-buffer knows the plane)
        vec3 a = abs(n.y) < 0.9 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
        vec3 t1 = normalize(cross(n, a)), t2 = cross(n, t1);
        float h = 1e-2 * max(length(p - u_light_eye), 1e-4);
        vec3 o = skd_uvt(p);
        t -= min(u_slope_bias * sk_prefilter_receiver_bias(skd_uvt(p + h * t1) - o, skd_uvt(p + h * t2) - o, u_kernel_uv), u_slope_bias_max);
    }
    vec4 m = u_mips ? texture(u_moments, c.xy) : textureLod(u_moments, c.xy, 0.0);
    return sk_prefilter_visibility(m, t, u_method, u_params, u_moment_bias, u_quantized) * sk_emitter_horizon(p, n);
}
)";

std::string fs_head() { return "#version 450 core\n"; }

GLuint compile_fs(const std::string& snippet, const char* body, std::string& log) {
    return skgl::compile_program({{GL_VERTEX_SHADER, fullscreen_vertex_shader()},
                                  {GL_FRAGMENT_SHADER, fs_head() + snippet + "\n" + body}},
                                 log);
}

// Timing as the soft-shadow drivers do it: warm-up (at least two runs), then the median over
// ctx.frames runs, fewer when a frame is slow (the timed runs stay within ~0.4 s), never fewer than 3.
double time_frames(const RunContext& ctx, const std::function<void()>& frame, int& frames_used) {
    double last = 0.0;
    for (int i = 0; i < std::max(ctx.warmup, 2); ++i) {
        const auto t0 = Clock::now();
        frame();
        glFinish();
        last = ms_since(t0);
        if (i >= 1 && last > 100.0) break;
    }
    frames_used = ctx.frames;
    if (ctx.frames > 3 && last > 0.0) frames_used = std::clamp(static_cast<int>(400.0 / last), 3, ctx.frames);
    return skgl::median_frame_ms(frame, 0, frames_used);
}

void uniform_matrix(GLuint p, const char* n, const glm::mat4& m) {
    glUniformMatrix4fv(glGetUniformLocation(p, n), 1, GL_FALSE, glm::value_ptr(m));
}

class PrefilteredTechnique final : public Technique {
public:
    explicit PrefilteredTechnique(shadowkit::PrefilterMethod m) : method_(m) {}
    std::string name() const override { return kMethodNames[static_cast<int>(method_)]; }
    std::string description() const override {
        static const char* what[6] = {"variance shadow map (t, t^2), Chebyshev bound",
                                      "exponential shadow map e^(c t)",
                                      "exponential variance shadow map, positive warp",
                                      "exponential variance shadow map, both warps",
                                      "moment shadow map, Hamburger 4MSM",
                                      "moment shadow map, Hausdorff reconstruction on [0, 1]"};
        return std::string(what[static_cast<int>(method_)]) +
               " (prefiltered_shadow.hpp + glsl/prefiltered_shadow.glsl): map size x Gaussian blur width (texels: 3, and "
               "the light's penumbra from world units); "
               "format 0 RGBA32F / 1 RGBA16F / 2 RGBA16 (" +
               (is_msm() ? "default 2, quantized" : "default 0") + ")";
    }
    bool hard() const override { return false; }
    std::vector<std::pair<std::string, double>> live_params() const override {
        // exponent: c+ as a fraction of prefilter_exponent_limit (above 1: Overflow, the row fails);
        // exponent_neg: EVSM4's c- (< 0: the header's default 5); min_variance and moment_bias: multiples
        // of the format's defaults (prefilter_min_variance, prefilter_msm_moment_bias)
        return {{"format", default_format()}, {"exponent", 0.99},   {"exponent_neg", -1.0}, {"bleed", 0.0},
                {"min_variance", 1.0},        {"moment_bias", 1.0}, {"depth_bias", default_depth_bias()},
                {"slope_bias", 0.0},          {"slope_bias_max", 1.0},      {"blur", 1.0},
                {"mips", 0.0},                {"msaa", 0.0}};
    }
    std::vector<ParamSet> sweep(const Scene& scene, bool quick) const override {
        if (!prefilter_light(scene.light) || scene.name == "linear") return {};
        // map size x blur width: 1024 with a 3-texel blur and with the width of the light's penumbra
        // (world units, in texels of that map); 2048 with a 3-texel blur for VSM and MSM, one per
        // family (a penumbra-wide blur of 2048^2 texels takes ~2 s a frame on llvmpipe, and every
        // 2048 row ~2 s of the full report's budget); --quick: the penumbra row
        std::vector<ParamSet> out;
        const double pw = double(penumbra_width_texels(scene, fit_light(scene), 1024));
        if (!quick) {
            out.push_back(ParamSet{{{"size", 1024.0}, {"width", 3.0}}});
            if (method_ == shadowkit::PrefilterMethod::Vsm || method_ == shadowkit::PrefilterMethod::Msm)
                out.push_back(ParamSet{{{"size", 2048.0}, {"width", 3.0}}});
        }
        out.push_back(ParamSet{{{"size", 1024.0}, {"width", pw}}});
        return out;
    }
    RunResult run(const RunContext& ctx, const ParamSet& params) override;

private:
    shadowkit::PrefilterMethod method_;
    bool is_msm() const {
        return method_ == shadowkit::PrefilterMethod::Msm || method_ == shadowkit::PrefilterMethod::MsmHausdorff;
    }
    double default_format() const { return is_msm() ? 2.0 : 0.0; }
    double default_depth_bias() const { return is_msm() ? 0.002 : 0.0; }
};

RunResult PrefilteredTechnique::run(const RunContext& ctx, const ParamSet& params) {
    using namespace shadowkit;
    const Scene& scene = ctx.scene;
    if (!prefilter_light(scene.light)) return RunResult::failure("needs a spot, area or directional light (one 2D map)");
    const int size = std::clamp(static_cast<int>(params.get("size", 1024)), 16, 8192);
    const float width = static_cast<float>(params.get("width", 5));
    const int fmt = std::clamp(static_cast<int>(params.get("format", default_format())), 0, 2);
    const bool box = params.get("blur", 1) == 0.0;
    const bool mips = params.get("mips", 0) != 0.0;
    const int msaa = params.get("msaa", 0) != 0.0 ? 4 : 0;
    const float depth_bias = static_cast<float>(params.get("depth_bias", default_depth_bias()));
    const float slope_bias = static_cast<float>(params.get("slope_bias", 0.0));
    RunResult r;
    // ---- CPU: light, depth range, uniforms, kernel (the per-frame CPU work, timed)
    LightMatrices lm;
    PrefilterDepthRange range;
    PrefilterUniforms u;
    PrefilterWindowMap wmap;
    float weights[kPrefilterMaxWeights] = {};
    PrefilterKernel kernel;
    PrefilterSettings s;
    s.method = method_;
    s.format = static_cast<PrefilterFormat>(fmt);
    const PrefilterExponent limit = prefilter_exponent_limit(method_, s.format, 1);
    s.exponent_positive =
        limit.status == Status::Ok ? static_cast<float>(params.get("exponent", 0.99) * double(limit.exponent)) : -1.0f;
    s.exponent_negative = static_cast<float>(params.get("exponent_neg", -1.0));
    s.bleed_reduction = static_cast<float>(params.get("bleed", 0.0));
    s.min_variance = static_cast<float>(params.get("min_variance", 1.0)) * prefilter_min_variance(s.format);
    s.moment_bias = static_cast<float>(params.get("moment_bias", 1.0)) * prefilter_msm_moment_bias(s.format);
    std::vector<double> cpu;
    for (int i = 0; i < 5; ++i) {
        const auto t0 = Clock::now();
        lm = fit_light(scene);
        range = prefilter_depth_range(lm.znear, lm.zfar);
        u = prefilter_uniforms(s);
        wmap = prefilter_window_depth_map(lm.znear, lm.zfar, lm.perspective, false, range);
        kernel = prefilter_blur_weights(box ? PrefilterBlur::Box : PrefilterBlur::Gaussian, width, weights, kPrefilterMaxWeights);
        cpu.push_back(ms_since(t0));
    }
    r.cpu_ms = median_of(cpu);
    if (range.status != Status::Ok) return RunResult::failure(std::string("prefilter_depth_range: ") + status_name(range.status));
    if (u.status != Status::Ok) return RunResult::failure(std::string("prefilter_uniforms: ") + status_name(u.status));
    if (kernel.status != Status::Ok) return RunResult::failure(std::string("prefilter_blur_weights: ") + status_name(kernel.status));
    if (wmap.status != Status::Ok) return RunResult::failure(std::string("prefilter_window_depth_map: ") + status_name(wmap.status));
    const glm::mat4 vp = lm.proj * lm.view;

    // ---- GL resources
    std::string why;
    const std::string snippet = load_snippet("prefiltered_shadow", why);
    const std::string shadow_map = load_snippet("shadow_map", why);
    if (snippet.empty() || shadow_map.empty()) return RunResult::failure(why);
    const GLenum tex_format = texture_format(u.channels, s.format);
    skgl::Target a, b;  // a: moments (+ depth), b: the blur's intermediate
    if (!skgl::make_target(a, size, size, {tex_format}, msaa ? 0 : GL_DEPTH_COMPONENT32F, why) ||
        !skgl::make_target(b, size, size, {tex_format}, 0, why))
        return RunResult::failure(why);
    std::string log;
    const GLuint moment_prog = skgl::compile_program(
        {{GL_VERTEX_SHADER, fs_head() + kMomentVS}, {GL_FRAGMENT_SHADER, fs_head() + snippet + "\n" + kMomentFS}}, log);
    const GLuint blur_prog = compile_fs(snippet, kBlurFS, log);
    const GLuint resolve_prog = msaa ? compile_fs(snippet, kResolveFS, log) : 0;
    const GLuint depth_prog = msaa ? compile_depth_only_program(log) : 0;
    const GLuint vis_prog =
        compile_visibility_program(shadow_map + "\n" + snippet + "\n" + emitter_horizon_glsl(), kLookupBody, log);
    GLuint ms_tex = 0, ms_fbo = 0;
    auto release = [&] {
        skgl::destroy_target(a);
        skgl::destroy_target(b);
        if (ms_fbo) glDeleteFramebuffers(1, &ms_fbo);
        if (ms_tex) glDeleteTextures(1, &ms_tex);
    };
    if (!moment_prog || !blur_prog || !vis_prog || (msaa && (!resolve_prog || !depth_prog))) {
        const RunResult fail = RunResult::failure(log);
        return finish_run(fail, {moment_prog, blur_prog, resolve_prog, depth_prog, vis_prog}, release);
    }
    if (msaa) {
        glGenTextures(1, &ms_tex);
        glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, ms_tex);
        glTexStorage2DMultisample(GL_TEXTURE_2D_MULTISAMPLE, msaa, GL_DEPTH_COMPONENT32F, size, size, GL_TRUE);
        glGenFramebuffers(1, &ms_fbo);
        glBindFramebuffer(GL_FRAMEBUFFER, ms_fbo);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D_MULTISAMPLE, ms_tex, 0);
        glDrawBuffer(GL_NONE);
        glReadBuffer(GL_NONE);
    }
    // uniforms
    glUseProgram(moment_prog);
    uniform_matrix(moment_prog, "u_light_view_proj", vp);
    uniform_matrix(moment_prog, "u_light_view", lm.view);
    glUniform2f(glGetUniformLocation(moment_prog, "u_depth_scale_offset"), range.scale, range.offset);
    glUniform1i(glGetUniformLocation(moment_prog, "u_method"), u.method_code);
    glUniform2fv(glGetUniformLocation(moment_prog, "u_exponents"), 1, glm::value_ptr(u.exponents));
    glUniform1i(glGetUniformLocation(moment_prog, "u_quantized"), u.quantized ? 1 : 0);
    glUseProgram(blur_prog);
    glUniform1i(glGetUniformLocation(blur_prog, "u_radius"), kernel.radius);
    glUniform1fv(glGetUniformLocation(blur_prog, "u_weights"), static_cast<GLsizei>(kernel.count), weights);
    if (msaa) {
        glUseProgram(resolve_prog);
        glUniform1i(glGetUniformLocation(resolve_prog, "u_samples"), msaa);
        glUniform4fv(glGetUniformLocation(resolve_prog, "u_window_map"), 1, glm::value_ptr(wmap.coefficients));
        glUniform1i(glGetUniformLocation(resolve_prog, "u_method"), u.method_code);
        glUniform2fv(glGetUniformLocation(resolve_prog, "u_exponents"), 1, glm::value_ptr(u.exponents));
        glUniform1i(glGetUniformLocation(resolve_prog, "u_quantized"), u.quantized ? 1 : 0);
        glUseProgram(depth_prog);
        uniform_matrix(depth_prog, "u_light_view_proj", vp);
    }
    glUseProgram(vis_prog);
    set_light_uniforms(vis_prog, scene.light);
    set_emitter_uniforms(vis_prog, scene.light, area_emitter(scene.light));
    glUseProgram(vis_prog);
    uniform_matrix(vis_prog, "u_light_view_proj", vp);
    uniform_matrix(vis_prog, "u_light_view", lm.view);
    glUniform2f(glGetUniformLocation(vis_prog, "u_depth_scale_offset"), range.scale, range.offset);
    glUniform1i(glGetUniformLocation(vis_prog, "u_method"), u.method_code);
    glUniform4fv(glGetUniformLocation(vis_prog, "u_params"), 1, glm::value_ptr(u.params()));
    glUniform1f(glGetUniformLocation(vis_prog, "u_moment_bias"), u.moment_bias);
    glUniform1i(glGetUniformLocation(vis_prog, "u_quantized"), u.quantized ? 1 : 0);
    glUniform1f(glGetUniformLocation(vis_prog, "u_depth_bias"), depth_bias);
    glUniform1f(glGetUniformLocation(vis_prog, "u_slope_bias"), slope_bias);
    glUniform1f(glGetUniformLocation(vis_prog, "u_slope_bias_max"), static_cast<float>(params.get("slope_bias_max", 1.0)));
    glUniform1f(glGetUniformLocation(vis_prog, "u_kernel_uv"), float(kernel.radius + 1) / float(size));
    const glm::vec3 light_eye = glm::vec3(glm::inverse(lm.view)[3]);
    glUniform3fv(glGetUniformLocation(vis_prog, "u_light_eye"), 1, glm::value_ptr(light_eye));
    glUniform1i(glGetUniformLocation(vis_prog, "u_mips"), mips ? 1 : 0);
    // the moment texture: mipmapped storage when asked (make_target allocates one level: re-create it)
    if (mips) {
        const int levels = 1 + static_cast<int>(std::floor(std::log2(double(size))));
        GLuint tex = 0;
        glGenTextures(1, &tex);
        glBindTexture(GL_TEXTURE_2D, tex);
        glTexStorage2D(GL_TEXTURE_2D, levels, tex_format, size, size);
        glBindFramebuffer(GL_FRAMEBUFFER, a.fbo);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex, 0);
        glDeleteTextures(1, &a.color[0]);
        a.color[0] = tex;
    }
    glBindTexture(GL_TEXTURE_2D, a.color[0]);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, mips ? GL_LINEAR_MIPMAP_LINEAR : GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    VisibilityPass pass;
    if (!pass.init(ctx.gpu.width, ctx.gpu.height, why)) {
        const RunResult fail = RunResult::failure(why);
        return finish_run(fail, {moment_prog, blur_prog, resolve_prog, depth_prog, vis_prog}, release);
    }
    GLuint vao = 0;
    glGenVertexArrays(1, &vao);
    const glm::vec4 clear = prefilter_moments(1.0f, glm::vec2(0.0f), u);
    auto fullscreen = [&](GLuint prog, const skgl::Target& dst) {
        glBindFramebuffer(GL_FRAMEBUFFER, dst.fbo);
        glViewport(0, 0, size, size);
        glDisable(GL_DEPTH_TEST);
        glDisable(GL_BLEND);
        glUseProgram(prog);
        glBindVertexArray(vao);
        glDrawArrays(GL_TRIANGLES, 0, 3);
    };
    auto moment_pass = [&] {
        glDisable(GL_CULL_FACE);
        glDisable(GL_BLEND);
        glDisable(GL_POLYGON_OFFSET_FILL);
        if (msaa) {
            glBindFramebuffer(GL_FRAMEBUFFER, ms_fbo);
            glViewport(0, 0, size, size);
            glEnable(GL_DEPTH_TEST);
            glDepthFunc(GL_LESS);
            glDepthMask(GL_TRUE);
            glClear(GL_DEPTH_BUFFER_BIT);
            glUseProgram(depth_prog);
            for (const auto& mesh : ctx.gpu.meshes) skgl::draw_mesh(mesh);
            glActiveTexture(GL_TEXTURE0);
            glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, ms_tex);
            fullscreen(resolve_prog, a);
            return;
        }
        glBindFramebuffer(GL_FRAMEBUFFER, a.fbo);
        glViewport(0, 0, size, size);
        glClearBufferfv(GL_COLOR, 0, glm::value_ptr(clear));
        glClearDepth(1.0);
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        glDepthMask(GL_TRUE);
        glClear(GL_DEPTH_BUFFER_BIT);
        glUseProgram(moment_prog);
        for (const auto& mesh : ctx.gpu.meshes) skgl::draw_mesh(mesh);
    };
    auto frame = [&] {
        moment_pass();
        if (kernel.radius > 0) {
            glUseProgram(blur_prog);
            glActiveTexture(GL_TEXTURE0);
            glBindTexture(GL_TEXTURE_2D, a.color[0]);
            glUniform2i(glGetUniformLocation(blur_prog, "u_dir"), 1, 0);
            fullscreen(blur_prog, b);
            glBindTexture(GL_TEXTURE_2D, b.color[0]);
            glUniform2i(glGetUniformLocation(blur_prog, "u_dir"), 0, 1);
            fullscreen(blur_prog, a);
        }
        if (mips) {
            glBindTexture(GL_TEXTURE_2D, a.color[0]);
            glGenerateMipmap(GL_TEXTURE_2D);
        }
        glBindVertexArray(0);
        pass.draw(vis_prog, ctx.gpu, GL_TEXTURE_2D, a.color[0]);
    };
    r.gpu_ms = time_frames(ctx, frame, r.frames);
    std::size_t triangles = 0;
    for (const auto& mesh : ctx.gpu.meshes) triangles += static_cast<std::size_t>(mesh.index_count) / 3u;
    r.visibility = skgl::read_color_float(pass.target, 0, 1);
    const std::int64_t texel_bytes = std::int64_t(u.channels) * format_bytes(s.format);
    const std::int64_t texels = std::int64_t(size) * size;
    r.gpu_bytes = texels * (2 * texel_bytes + 4 * std::max(msaa, 1)) + (mips ? texels * texel_bytes / 3 : 0);
    r.work = {{"shadow_map_texels", double(size) * size},
              {"blur_taps_per_texel", kernel.radius > 0 ? 2.0 * (2 * kernel.radius + 1) : 0.0},
              {"kernel_radius", double(kernel.radius)},
              {"exponent", double(u.exponents.x)},
              {"triangles_drawn", double(triangles)}};
    if (ctx.debug_images) {
        const std::vector<float> m = skgl::read_color_float(a, 0, 4);
        r.debug.push_back(grey_debug_image(std::string(kMethodNames[static_cast<int>(method_)]) + " moment 1 (light space)",
                                           size, size, m, 4, 0, 1e37f));
        if (u.channels > 1)
            r.debug.push_back(grey_debug_image("moment 2 (light space)", size, size, m, 4, 1, 1e37f));
        if (u.channels > 2) r.debug.push_back(grey_debug_image("moment 3 (light space)", size, size, m, 4, 2, 1e37f));
    }
    glDeleteVertexArrays(1, &vao);
    return finish_run(std::move(r), {moment_prog, blur_prog, resolve_prog, depth_prog, vis_prog}, release);
}

}  // namespace

void add_prefilter_techniques(std::vector<std::unique_ptr<Technique>>& out) {
    using shadowkit::PrefilterMethod;
    for (PrefilterMethod m : {PrefilterMethod::Vsm, PrefilterMethod::Esm, PrefilterMethod::Evsm2, PrefilterMethod::Evsm4,
                              PrefilterMethod::Msm, PrefilterMethod::MsmHausdorff})
        out.push_back(std::make_unique<PrefilteredTechnique>(m));
}

}  // namespace sk
