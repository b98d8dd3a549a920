// samples/prefiltered_shadows/prefiltered_shadows.hpp - pre-filtered shadow maps: variance (VSM),
// exponential (ESM), exponential-variance (EVSM2 / EVSM4) and moment shadow maps (MSM, Hamburger and
// Hausdorff): the map stores moments of the depth, which a blur filters like any image; the lookup
// bounds the lit fraction from the filtered moments. What the sample shows and the report measures.
//
// A sample folder is what a user copies (the same shape in every samples/<technique>/):
//   prefiltered_shadows.hpp  the settings (what the panel edits, named once in bind_settings()) and the class
//   prefiltered_shadows.cpp  the technique, top to bottom in the order it runs: init (once per scene),
//                            update (CPU, every frame), render (the GPU passes, each with its GL state)
//   main.cpp                 the calls: the app shell (samples/app) does the window, the camera
//                            G-buffer, the panel, the timing and the picture
// It uses shadowkit/prefiltered_shadow.hpp (the depth range, the uniforms checked against the texture
// format, the blur weights, the kernel's width from world units), glsl/prefiltered_shadow.glsl,
// glsl/shadow_map.glsl and the app shell's scene (sk::fit_light), G-buffer (app/gbuffer.hpp: the V
// pass, the emitter's horizon) and GL helpers (app/gl.hpp). shadowkit-report wraps this same class
// (samples/report/techniques/prefiltered_shadows.cpp) as "vsm", "esm", "evsm2", "evsm4", "msm" and
// "msm_hausdorff": one row colour per method, and the soft lookup (soft=on) as "vsm_soft" and "msm_soft".
// Spot, rect, disk and sphere lights (a perspective map from the light's center) and directional lights
// (an orthographic map); point and line lights need cube maps (update() says so in error()).
#pragma once

#include <shadowkit/prefiltered_shadow.hpp>

#include <glm/glm.hpp>

#include <string>

#include "app.hpp"
#include "gbuffer.hpp"
#include "gl.hpp"
#include "params.hpp"

struct PrefilteredShadowSettings {
    shadowkit::PrefilterMethod method = shadowkit::PrefilterMethod::Msm;
    /// The moment texture: auto (MSM: 16-bit unorm with the optimized quantization; the others float32),
    /// float32, float16, unorm16 (prefilter_uniforms refuses what a method cannot store: a warp in
    /// unorm16, MSM in float16).
    enum class Format { Auto, Float32, Float16, Unorm16 };
    Format format = Format::Auto;
    int size = 1024;                ///< texels per side of the moment map
    shadowkit::PrefilterBlur blur = shadowkit::PrefilterBlur::Gaussian;
    float blur_texels = 3.f;        ///< the blur's full width (1: none)
    /// Instead: the light's penumbra (a blocker halfway down the casters, on the far receiver). Off by
    /// default: a blur that wide bleeds light into the umbra at every contact (umbra leak on the scanned
    /// meshes 10 to 36% against 0.4 to 2.6% with 3 texels); soft=on is the soft lookup that follows the penumbra.
    bool blur_from_light = false;
    double exponent_fraction = 0.99;  ///< ESM c, EVSM c+: this fraction of prefilter_exponent_limit (above 1: Overflow)
    float exponent_negative = 5.f;  ///< EVSM4 c-
    float bleed_reduction = 0.f;    ///< VSM, EVSM, MSM: light-bleeding reduction (linstep), [0, 1)
    float min_variance_scale = 1.f; ///< VSM, EVSM: x prefilter_min_variance(format)
    float moment_bias_scale = 1.f;  ///< MSM: x prefilter_msm_moment_bias(format)
    float depth_bias = 0.002f;      ///< t units off the receiver's depth (MSM needs ~0.002; the others work with 0)
    /// x sk_prefilter_receiver_bias of the receiver's plane for the blur's radius, capped at slope_bias_max:
    /// removes the self-shadowing of lit faces steep to the light under a wide blur, but lights the umbra
    /// right behind an occluder on a grazing receiver (0: off).
    float slope_bias = 0.f;
    float slope_bias_max = 1.f;
    bool mips = false;  ///< glGenerateMipmap and trilinear lookups (bilinear on level 0 without)
    bool msaa = false;  ///< the meshes' depth 4x multisampled, resolved into moments (sk_prefilter_resolve)
    /// Soft shadows with contact hardening (VSM, MSM; the others: the hard lookup): mipmaps on, the blur
    /// blur_texels wide, the penumbra's width from the blocker depth the moments give (sk_prefilter_soft_visibility)
    bool soft = false;
    /// The map around the casters and their penumbra (sk::fit_light_to_casters) instead of the scene.
    bool fit_casters = true;
};

/// The settings by name, once: --param, the panel's widgets and the report's sweeps use these.
inline void bind_settings(app::Params& p, PrefilteredShadowSettings& s) {
    using M = shadowkit::PrefilterMethod;
    using F = PrefilteredShadowSettings::Format;
    p.choice("method", &s.method,
             {{"msm", M::Msm}, {"msm_hausdorff", M::MsmHausdorff}, {"vsm", M::Vsm}, {"esm", M::Esm}, {"evsm2", M::Evsm2},
              {"evsm4", M::Evsm4}});
    p.choice("format", &s.format, {{"auto", F::Auto}, {"float32", F::Float32}, {"float16", F::Float16}, {"unorm16", F::Unorm16}});
    p.choice("size", &s.size, {{"256", 256}, {"512", 512}, {"1024", 1024}, {"2048", 2048}, {"4096", 4096}});
    p.choice("blur", &s.blur, {{"gaussian", shadowkit::PrefilterBlur::Gaussian}, {"box", shadowkit::PrefilterBlur::Box}});
    p.number("blur_texels", &s.blur_texels, 1.0, 65.0);
    p.toggle("blur_from_light", &s.blur_from_light);
    p.number("exponent_fraction", &s.exponent_fraction, 0.0, 1.5);
    p.number("exponent_negative", &s.exponent_negative, 0.0, 44.0);
    p.number("bleed_reduction", &s.bleed_reduction, 0.0, 0.99);
    p.number("min_variance_scale", &s.min_variance_scale, 0.0, 100.0);
    p.number("moment_bias_scale", &s.moment_bias_scale, 0.0, 100.0);
    p.number("depth_bias", &s.depth_bias, 0.0, 0.05);
    p.number("slope_bias", &s.slope_bias, 0.0, 4.0);
    p.number("slope_bias_max", &s.slope_bias_max, 0.0, 1.0);
    p.toggle("mips", &s.mips);
    p.toggle("msaa", &s.msaa);
    p.toggle("soft", &s.soft);
    p.toggle("fit_casters", &s.fit_casters);
}

class PrefilteredShadows {
public:
    PrefilteredShadows() = default;
    PrefilteredShadows(const PrefilteredShadows&) = delete;
    PrefilteredShadows& operator=(const PrefilteredShadows&) = delete;
    ~PrefilteredShadows() { release(); }

    /// The programs (moment pass, blur, MSAA resolve and its depth pass, lookup) and the V target.
    bool init(const app::View& v, std::string& why);
    /// CPU, every frame: the light's frustum, the depth range, the uniforms for the format, the blur weights.
    void update(const app::View& v, const PrefilteredShadowSettings& s);
    /// GPU, every frame: the moment pass, the blur (two passes), the mipmaps, V at the G-buffer's points.
    void render(const app::View& v, const PrefilteredShadowSettings& s);
    /// R32F V at the G-buffer's pixels.
    GLuint visibility() const { return pass_.texture(); }
    /// Why update() or render() cannot work for this light or these settings (a header's status, a
    /// target GL refused); "" while all is well.
    const std::string& error() const { return error_; }

    /// Debug view: the filtered moment map's first moment (light space).
    app::DebugImage debug_moments() const { return {moments_.color.empty() ? 0u : moments_.color[0], app::DebugImage::Show::Value}; }
    GLuint moments() const { return moments_.color.empty() ? 0u : moments_.color[0]; }
    int size() const { return size_; }  ///< of the moment map as rendered last
    const shadowkit::PrefilterUniforms& uniforms() const { return u_; }   ///< of the last update()
    const shadowkit::PrefilterKernel& kernel() const { return kernel_; }  ///< of the last update()
    shadowkit::PrefilterFormat format() const { return format_; }         ///< the resolved format
    const shadowkit::PrefilterSoftUniforms& soft() const { return soft_; } ///< of the last update() (NotRun: soft off)

private:
    void make_maps(const PrefilteredShadowSettings& s);
    void fullscreen(GLuint prog, const skgl::Target& dst) const;
    void release();
    std::string error_;
    // this frame
    sk::LightMatrices lm_;
    shadowkit::PrefilterFormat format_ = shadowkit::PrefilterFormat::Float32;
    shadowkit::PrefilterDepthRange range_;
    shadowkit::PrefilterUniforms u_;
    shadowkit::PrefilterWindowMap window_map_;
    shadowkit::PrefilterKernel kernel_;
    shadowkit::PrefilterSoftUniforms soft_;
    float weights_[shadowkit::kPrefilterMaxWeights] = {};
    // GL: the moments (+ depth), the blur's intermediate, the multisampled depth
    int size_ = 0;
    GLenum texture_format_ = 0;
    bool mips_ = false, msaa_ = false;
    skgl::Target moments_, blurred_;
    GLuint ms_depth_ = 0, ms_fbo_ = 0, vao_ = 0;
    GLuint moment_prog_ = 0, blur_prog_ = 0, resolve_prog_ = 0, depth_prog_ = 0, vis_prog_ = 0;
    app::VisibilityPass pass_;
};
