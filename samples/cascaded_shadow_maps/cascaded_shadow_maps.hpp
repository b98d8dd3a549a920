// samples/cascaded_shadow_maps/cascaded_shadow_maps.hpp - cascaded (parallel-split) shadow maps for a
// directional light: the camera's depth range cut into up to four slices, each with its own stable
// orthographic map (cascades.hpp: the practical split scheme, texel-snapped fits that do not shimmer), the
// lookup picking the slice by view depth and blending into the next over a band. What the sample shows
// and the report measures.
//
// A sample folder is what a user copies (the same shape in every samples/<technique>/):
//   cascaded_shadow_maps.hpp  the settings (what the panel edits, named once in bind_settings()) and the class
//   cascaded_shadow_maps.cpp  the technique, top to bottom in the order it runs: init (once per scene),
//                             update (CPU, every frame), render (the GPU passes, each with its GL state)
//   main.cpp                  the calls: the app shell (samples/app) does the window, the camera G-buffer,
//                             the panel, the timing and the picture
// It uses only shadowkit/cascades.hpp, glsl/cascades.glsl (with glsl/pcf.glsl and glsl/shadow_map.glsl)
// and the app shell's G-buffer (app/gbuffer.hpp) and GL helpers (app/gl.hpp). shadowkit-report wraps this same class (samples/report/techniques/warp.cpp).
#pragma once

#include <shadowkit/cascades.hpp>
#include <shadowkit/shadow_cache.hpp>

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "app.hpp"
#include "gbuffer.hpp"
#include "gl.hpp"
#include "params.hpp"

struct CascadedShadowMapSettings {
    int size = 1024;             ///< texels per side of each cascade's map
    int count = 4;               ///< cascades (1 to 4)
    float lambda = 0.75f;        ///< split scheme: 0 uniform, 1 logarithmic (Zhang et al. 2006's practical scheme between)
    float band = 0.05f;          ///< blend into the next cascade over this last fraction of each slice (docs/cascades.md: 5% against 10%)
    /// auto (default): shadow_map.glsl's automatic bias on each cascade's layer (each 2x2 texel compared
    /// with the receiver plane's own depth; no polygon offset, nothing to tune). polygon_offset: the
    /// depth pass with glPolygonOffset(2, 2) and sk_cascade_shadow's single compare, plus normal_offset.
    enum class Bias { Auto, PolygonOffset };
    Bias bias = Bias::Auto;
    /// bias=polygon_offset: offset of the lookup point along its normal, in texels of the cascade that
    /// serves it (Cascade::texel_world_size): what a shadow pass without a slope-scaled offset needs
    /// against acne (docs/cascades.md). glPolygonOffset(2, 2) is enough: the normal offset only moves
    /// shadows off their casters (report, outdoor 512: RMSE 0.078 -> 0.095 with 1 texel).
    float normal_offset = 0.f;
    /// 0 (default): the hardware 2x2 compare. 1-4: a (2r+1)^2 tent of radius r texels in each cascade's
    /// layer (pcf.glsl's sampler2DArrayShadow overloads), blended over the band like the 2x2; with
    /// bias=auto the receiver plane comes from the normal (sk_auto_filtered_bias).
    int pcf_radius = 0;
    /// fixed (default): the practical split scheme over the camera's whole depth range, a stable
    /// bounding-sphere map per slice (cascade_fit). sdsm: sample distribution shadow maps
    /// (cascade_sdsm_fit): a min/max reduction of the G-buffer's depth on the GPU (glsl/cascades.glsl,
    /// read back: two floats), the log partition of the visible range, a tight light-space box per
    /// cascade, with the previous frame's fit as hysteresis.
    enum class Fit { Fixed, Sdsm };
    Fit fit = Fit::Fixed;
    /// fit=sdsm: a second reduction gives each cascade's receivers' light-space bounds (SDSM sec. 3.2:
    /// the maps cover what each cascade serves, not its whole view slice; four more floats per cascade
    /// read back). Off: each cascade's box is its view slice's.
    bool receiver_bounds = true;
    /// fit=sdsm: the split scheme over the visible range; 1 (default): the log partition, SDSM's
    /// default (outdoor, 1024: RMSE 0.0254 against 0.0310 at 0.9 and 0.0361 at 0.75).
    float sdsm_lambda = 1.f;
    /// Cached cascades (fit=fixed, size <= 2048; ignored otherwise): each cascade's depth range fixed in
    /// the world (cascade_fit's stable_world_depth), and every frame shadow_cache_plan says per cascade
    /// what of last frame's layer is still right: keep it, scroll it by whole texels and re-render the
    /// exposed border, or re-render the footprints of casters that moved (their old and new ones).
    /// Only those rectangles are drawn (scissored), with glsl/shadow_cache.glsl's translation-invariant
    /// caster pass, so a kept layer equals a full re-render bit for bit. Off (default): every layer whole
    /// every frame with the plain depth pass (docs/cascades.md has the measured trade).
    bool cache = false;
};

/// The settings by name, once: --param, the panel's widgets and the report's sweeps use these.
inline void bind_settings(app::Params& p, CascadedShadowMapSettings& s) {
    p.choice("size", &s.size, {{"256", 256}, {"512", 512}, {"1024", 1024}, {"2048", 2048}, {"4096", 4096}});
    p.number("count", &s.count, 1, 4);
    p.number("lambda", &s.lambda, 0.0, 1.0);
    p.number("band", &s.band, 0.0, 0.5);
    p.choice("bias", &s.bias, {{"auto", CascadedShadowMapSettings::Bias::Auto},
                               {"polygon_offset", CascadedShadowMapSettings::Bias::PolygonOffset}});
    p.number("normal_offset", &s.normal_offset, 0.0, 4.0);
    p.number("pcf_radius", &s.pcf_radius, 0, 4);
    p.choice("fit", &s.fit, {{"fixed", CascadedShadowMapSettings::Fit::Fixed}, {"sdsm", CascadedShadowMapSettings::Fit::Sdsm}});
    p.toggle("receiver_bounds", &s.receiver_bounds);
    p.number("sdsm_lambda", &s.sdsm_lambda, 0.0, 1.0);
    p.toggle("cache", &s.cache);
}

class CascadedShadowMaps {
public:
    CascadedShadowMaps() = default;
    CascadedShadowMaps(const CascadedShadowMaps&) = delete;
    CascadedShadowMaps& operator=(const CascadedShadowMaps&) = delete;
    ~CascadedShadowMaps() { release(); }

    /// The casters' bounds, the programs and the V target.
    bool init(const app::View& v, std::string& why);
    /// CPU, every frame: the splits and each cascade's matrix (cascade_fit).
    void update(const app::View& v, const CascadedShadowMapSettings& s);
    /// GPU, every frame: the casters' depth into each cascade's layer, then V at the G-buffer's points.
    void render(const app::View& v, const CascadedShadowMapSettings& s);
    /// R32F V at the G-buffer's pixels.
    GLuint visibility() const { return pass_.texture(); }
    /// Why update() found no cascades (cascade_fit's status: InvalidLight for a point, spot or area
    /// light), "" while all is well. V is 1 (lit) meanwhile.
    const std::string& error() const { return error_; }

    /// Debug view: the depths of cascade i's map (none beyond the count).
    app::DebugImage debug_layer(int i) const { return {i < layers_ ? layer_view_[i] : 0u, app::DebugImage::Show::Depth}; }

    // What update() found, for the report's counters and metrics.
    const shadowkit::Cascade& cascade(int i) const { return cascades_[i]; }
    const float* splits() const { return fit_.splits; }  ///< view depths: cascade i covers [splits[i], splits[i + 1]]
    int count() const { return layers_; }                 ///< cascades as rendered last
    int size() const { return size_; }                    ///< texels per side of each map as rendered last
    GLuint maps() const { return maps_; }                 ///< the depth array: layer i is cascade i

    // cache=on: what update() planned for each cascade this frame (Keep / Update / Scroll / Render).
    bool cache_active() const { return cache_on_; }       ///< cache=on took effect this frame (fit=fixed, size <= 2048)
    const shadowkit::ShadowCachePlan& plan(int i) const { return plan_[i]; }
    std::uint64_t texels_rerendered() const;              ///< this frame, all cascades (cache off: all of them)
    /// Forget what the layers hold: the next update() plans a whole render of every cascade (what a
    /// renderer does after loading a level; the tests use it for the full re-render to compare with).
    void invalidate_cache() { for (auto& p : previous_) p.has_content = false; }

private:
    void make_maps(int size, int count);
    /// fit=sdsm: the G-buffer depth's min/max window depth (glsl/cascades.glsl's reduction, read back).
    bool reduce_depth(const app::View& v, float& window_min, float& window_max);
    /// fit=sdsm, receiver_bounds: each cascade's receivers' light-space bounds (x0, y0, x1, y1).
    bool reduce_bounds(const app::View& v, const float* splits, int count, glm::vec4* bounds);
    void update_sdsm(const app::View& v, const CascadedShadowMapSettings& s, const shadowkit::CascadeInput& in);
    void render_layers(const app::View& v, const CascadedShadowMapSettings& s, bool ok);  // every layer whole
    void release();
    // cache=on, in the order they run (cascaded_shadow_maps.cpp, "Cached cascades")
    void cache_caster_bounds(const app::View& v);                         // update: each caster's box this frame
    void cache_plan(const CascadedShadowMapSettings& s);                  // update: a plan per cascade
    void cache_scroll(int i);                                             // render: layer i moved by whole texels
    void cache_rerender(const app::View& v, const CascadedShadowMapSettings& s, int i);  // render: the planned rectangles
    void cache_done();                                                    // render: the layers hold this frame
    glm::vec3 caster_lo_{0.f}, caster_hi_{0.f};
    std::string error_;
    shadowkit::Cascade cascades_[4];
    shadowkit::CascadeFitResult fit_;
    shadowkit::CascadeSdsmResult sdsm_;  ///< fit=sdsm: last frame's fit (the hysteresis)
    bool nothing_visible_ = false;       ///< fit=sdsm found no receiver: no cascade, V = 1
    GLuint reduce_first_ = 0, reduce_next_ = 0, reduce_vao_ = 0;
    skgl::Target reduce_levels_[8];
    GLuint bounds_first_ = 0, bounds_next_ = 0;
    skgl::Target bounds_levels_[8];  ///< four RGBA32F targets each: one per cascade
    int reduce_w_ = 0, reduce_h_ = 0;
    int size_ = 0, layers_ = 0;
    GLuint maps_ = 0, fbo_[4] = {0, 0, 0, 0}, layer_view_[4] = {0, 0, 0, 0};
    GLuint depth_prog_ = 0, vis_prog_ = 0, vis_auto_prog_ = 0;  // V: bias=polygon_offset, bias=auto
    // cache=on
    bool cache_on_ = false, scrolled_ = false;  // scrolled_: this update()'s scrolls are done
    std::vector<std::size_t> cache_mesh_;                 // the caster meshes
    std::vector<shadowkit::ShadowCacheCaster> cache_casters_;  // their boxes now and when last rendered
    glm::dmat4 cache_vp_[4];                              // each cascade's matrix as the plan compares it (double)
    glm::mat4 cache_global_[4];                           // world -> (global texel x, y, window depth)
    glm::ivec2 cache_anchor_[4];                          // the global texel of each layer's texel (0, 0)
    shadowkit::ShadowCacheMapState previous_[4], current_[4];
    shadowkit::ShadowCachePlan plan_[4];
    std::vector<shadowkit::ShadowCacheRect> rects_[4];
    GLuint scratch_ = 0;                                  // one layer's size: a scroll copies through it
    GLuint invariant_prog_ = 0;                           // glsl/shadow_cache.glsl's caster pass
    app::VisibilityPass pass_;
};
