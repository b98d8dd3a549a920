// samples/pcss/pcss.hpp - soft shadows from one shadow map: percentage-closer soft shadows (Fernando
// 2005) and percentage-closer filtering (Reeves et al. 1987) with a fixed kernel, and the depth bias
// every lookup needs (shadow_bias.hpp's methods side by side): what the sample shows and the report
// measures.
//
// A sample folder is what a user copies (the same shape in every samples/<technique>/):
//   pcss.hpp   the settings (what the panel edits, named once in bind_settings()) and the class
//   pcss.cpp   the technique, top to bottom in the order it runs: init (once per scene), update (CPU,
//              every frame), render (the GPU passes, each with its GL state)
//   main.cpp   the calls: the app shell (samples/app) does the window, the camera G-buffer, the
//              panel, the timing and the picture
// It uses shadowkit/pcss.hpp (the near plane at the casters, the light's width in the map), glsl/
// shadow_map.glsl, glsl/pcf.glsl, glsl/pcss.glsl and the app shell's scene (sk::fit_light), G-buffer
// (app/gbuffer.hpp: the V pass, the emitter's horizon) and GL helpers (app/gl.hpp). shadowkit-report
// wraps this same class (samples/report/techniques/soft_shadows.cpp) as "pcf", "pcss" and "bias" (the
// depth-bias study: a report-only sweep of this class's bias settings, scored for acne and
// peter-panning).
//
// The model: an area light seen as a spot light at its center (one perspective map) plus its width.
// Spot, rect, disk and sphere lights; point, directional and line lights need other maps (update()
// says so in error()).
#pragma once

#include <glm/glm.hpp>

#include <string>

#include "app.hpp"
#include "gbuffer.hpp"
#include "gl.hpp"
#include "params.hpp"

struct PcssSettings {
    /// How the map is read around the receiver's point: hard (one hardware 2x2 compare), box or tent
    /// ((2r+1)^2 taps, r = radius_texels), poisson (`taps` of a Poisson disk of radius radius_texels),
    /// pcss (a blocker search, the penumbra's width from the average blocker depth, a Poisson filter of
    /// that width: `taps` + `taps`).
    enum class Filter { Hard, Box, Tent, Poisson, Pcss };
    Filter filter = Filter::Pcss;
    int taps = 32;                   ///< poisson, pcss: Poisson taps (pcss: the search and the filter each)
    bool rotate = true;              ///< poisson, pcss: the disk turned per pixel (interleaved gradient noise)
    float radius_texels = 2.f;       ///< box, tent: r (whole texels); poisson: the disk's radius
    bool radius_from_light = false;  ///< instead: half the penumbra of a blocker halfway down the casters (to 0.1 texel)
    int size = 2048;                 ///< texels per side of the map
    enum class Depth { Float32, Unorm24 };
    Depth depth = Depth::Float32;    ///< GL_DEPTH_COMPONENT32F or GL_DEPTH_COMPONENT24
    bool fit_near = true;            ///< the light's near plane at the casters (pcss_fit_near_plane): PCSS's search is cut there
    /// The map around the casters and their penumbra (sk::fit_light_to_casters) instead of the scene: off
    /// by default - measured (--quick, 256x192): PCSS 64+64 on the bunny 0.0216 -> 0.0174, on `stack`
    /// hard 0.0131 -> 0.0087, but on `overlap` 0.029 -> 0.052 (the blocker search clipped at the map's edge)
    bool fit_casters = false;
    /// The depth bias of the lookup (no polygon offset in the map): auto (the default: shadow_map.glsl's
    /// automatic bias, nothing to tune - the hard filter compares each 2x2 texel with the receiver plane's
    /// own depth, the kernels apply the plane per tap with sk_auto_filtered_bias); none; constant (world
    /// units along the light's axis); slope_scaled (texel size x min(tan theta, 10) x slope_scale);
    /// normal_offset (the point moved along its normal by texel size x sin theta x normal_offset);
    /// receiver_plane (every tap compares with the receiver's plane, lowered by plane_margin texels of
    /// its slope).
    enum class Bias { None, Constant, SlopeScaled, NormalOffset, ReceiverPlane, Auto };
    Bias bias = Bias::Auto;
    float plane_margin = 1.f;   ///< receiver_plane: texels of plane slope (+ 2e-6 window depth)
    float constant_bias = 0.01f;  ///< constant: world units
    float slope_scale = 1.5f;   ///< slope_scaled
    float normal_offset = 1.5f; ///< normal_offset: texels
    /// Multiply V by the emitter's fraction above the receiver's tangent plane (area lights: what the
    /// map from the light's center cannot see; app::emitter_horizon_glsl).
    bool horizon = true;
};

/// The settings by name, once: --param, the panel's widgets and the report's sweeps use these.
inline void bind_settings(app::Params& p, PcssSettings& s) {
    using F = PcssSettings::Filter;
    using B = PcssSettings::Bias;
    p.choice("filter", &s.filter, {{"pcss", F::Pcss}, {"hard", F::Hard}, {"box", F::Box}, {"tent", F::Tent}, {"poisson", F::Poisson}});
    p.number("taps", &s.taps, 1, 64);
    p.toggle("rotate", &s.rotate);
    p.number("radius_texels", &s.radius_texels, 0.5, 32.0);
    p.toggle("radius_from_light", &s.radius_from_light);
    p.choice("size", &s.size, {{"512", 512}, {"1024", 1024}, {"2048", 2048}, {"4096", 4096}});
    p.choice("depth", &s.depth, {{"float32", PcssSettings::Depth::Float32}, {"unorm24", PcssSettings::Depth::Unorm24}});
    p.toggle("fit_near", &s.fit_near);
    p.toggle("fit_casters", &s.fit_casters);
    p.choice("bias", &s.bias,
             {{"auto", B::Auto}, {"receiver_plane", B::ReceiverPlane}, {"none", B::None}, {"constant", B::Constant},
              {"slope_scaled", B::SlopeScaled}, {"normal_offset", B::NormalOffset}});
    p.number("plane_margin", &s.plane_margin, 0.0, 8.0);
    p.number("constant_bias", &s.constant_bias, 0.0, 1.0);
    p.number("slope_scale", &s.slope_scale, 0.0, 16.0);
    p.number("normal_offset", &s.normal_offset, 0.0, 16.0);
    p.toggle("horizon", &s.horizon);
}

class Pcss {
public:
    Pcss() = default;
    Pcss(const Pcss&) = delete;
    Pcss& operator=(const Pcss&) = delete;
    ~Pcss() { release(); }

    /// The snippets, the depth program, the two samplers of the map, the V target, the casters' bounds.
    bool init(const app::View& v, std::string& why);
    /// CPU, every frame: the light's frustum (its near plane at the casters), PCSS's light width in the
    /// map, a PCF radius from the light.
    void update(const app::View& v, const PcssSettings& s);
    /// GPU, every frame: the casters' depth from the light, then V at the G-buffer's points.
    void render(const app::View& v, const PcssSettings& s);
    /// R32F V at the G-buffer's pixels.
    GLuint visibility() const { return pass_.texture(); }
    /// Why update() or render() cannot work for this light or these settings (a program that did not
    /// compile); "" while all is well.
    const std::string& error() const { return error_; }

    /// Debug view: the map's depths.
    app::DebugImage debug_depth() const { return {map_, app::DebugImage::Show::Depth}; }
    GLuint map() const { return map_; }
    int size() const { return size_; }                  ///< of the map as rendered last
    glm::mat4 light_view_proj() const { return light_proj_ * light_view_; }  ///< the map's, as rendered last
    float radius_texels() const { return radius_texels_; }  ///< the PCF radius update() chose

private:
    void make_map(int size, PcssSettings::Depth depth);
    bool make_program(const PcssSettings& s);
    void release();
    std::string error_;
    std::string snippets_;  // shadow_map.glsl + pcf.glsl + pcss.glsl + the emitter's horizon
    glm::vec3 casters_lo_{0.f}, casters_hi_{0.f};
    // this frame: the light's frustum
    glm::mat4 light_view_{1.f}, light_proj_{1.f};
    float near_ = 0.f, far_ = 0.f, tan_half_ = 1.f, light_uv_at_near_ = 0.f, radius_texels_ = 0.f;
    // GL
    int size_ = 0;
    PcssSettings::Depth depth_ = PcssSettings::Depth::Float32;
    GLuint map_ = 0, fbo_ = 0, raw_sampler_ = 0, compare_sampler_ = 0;
    GLuint depth_prog_ = 0, vis_prog_ = 0;
    std::string vis_defines_;  // the settings vis_prog_ was compiled for
    app::VisibilityPass pass_;
};
