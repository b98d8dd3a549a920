// samples/warped_shadow_maps/warped_shadow_maps.hpp - one shadow map whose texels are spent where the
// camera needs them: fitted tightly to what the camera sees (light_frustum.hpp, with caster culling), or
// warped by the camera's perspective (perspective_shadow_maps.hpp: uniform, PSM, LiSPSM, TSM). What the
// sample shows and the report measures.
//
// A sample folder is what a user copies (the same shape in every samples/<technique>/):
//   warped_shadow_maps.hpp  the settings (what the panel edits, named once in bind_settings()) and the class
//   warped_shadow_maps.cpp  the technique, top to bottom in the order it runs: init (once per scene),
//                           update (CPU, every frame), render (the GPU passes, each with its GL state)
//   main.cpp                the calls: the app shell (samples/app) does the window, the camera G-buffer,
//                           the panel, the timing and the picture
// It uses only shadowkit/light_frustum.hpp, shadowkit/perspective_shadow_maps.hpp,
// glsl/perspective_shadow_maps.glsl and the app shell's G-buffer (app/gbuffer.hpp) and GL helpers
// (app/gl.hpp). shadowkit-report wraps this same class (samples/report/techniques/warp.cpp).
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "app.hpp"
#include "gbuffer.hpp"
#include "gl.hpp"
#include "params.hpp"

struct WarpedShadowMapSettings {
    /// fitted: light_frustum_fit, the light's frustum around the receivers the camera sees, casters that
    /// cannot shadow them culled; uniform: warp_uniform_matrix (the same idea, no culling); psm, lispsm,
    /// tsm: the perspective warps (Stamminger & Drettakis 2002, Wimmer et al. 2004, Martin & Tan 2004:
    /// TSM writes the light's undistorted depth per fragment).
    enum class Method { Fitted, Uniform, Psm, Lispsm, Tsm };
    Method method = Method::Lispsm;
    int size = 1024;  ///< texels per side of the map
    /// auto: true depths in the map and glsl/shadow_map.glsl's automatic bias through the warp's matrix
    /// (sk_shadow_map_visibility_auto: the receiver plane's depth at each of the 2x2 filter's texel
    /// centres, no constant); offset: a slope-scaled offset (2, 2) in the depth pass and the hardware
    /// 2x2 compare. TSM (its depth from a second matrix) takes perspective_shadow_maps.glsl's
    /// sk_warp_shadow_auto: the plane's depth along each texel centre's light ray, through both matrices.
    enum class Bias { Auto, Offset };
    Bias bias = Bias::Auto;
};

/// The settings by name, once: --param, the panel's widgets and the report's sweeps use these.
inline void bind_settings(app::Params& p, WarpedShadowMapSettings& s) {
    using M = WarpedShadowMapSettings::Method;
    p.choice("method", &s.method,
             {{"fitted", M::Fitted}, {"uniform", M::Uniform}, {"psm", M::Psm}, {"lispsm", M::Lispsm}, {"tsm", M::Tsm}});
    p.choice("size", &s.size, {{"256", 256}, {"512", 512}, {"1024", 1024}, {"2048", 2048}, {"4096", 4096}});
    p.choice("bias", &s.bias, {{"auto", WarpedShadowMapSettings::Bias::Auto}, {"offset", WarpedShadowMapSettings::Bias::Offset}});
}

class WarpedShadowMaps {
public:
    WarpedShadowMaps() = default;
    WarpedShadowMaps(const WarpedShadowMaps&) = delete;
    WarpedShadowMaps& operator=(const WarpedShadowMaps&) = delete;
    ~WarpedShadowMaps() { release(); }

    /// The meshes' bounds, the programs and the V target.
    bool init(const app::View& v, std::string& why);
    /// CPU, every frame: the light's matrix (and for `fitted` the casters to draw).
    void update(const app::View& v, const WarpedShadowMapSettings& s);
    /// GPU, every frame: the casters' depth into the map, then V at the G-buffer's points.
    void render(const app::View& v, const WarpedShadowMapSettings& s);
    /// R32F V at the G-buffer's pixels.
    GLuint visibility() const { return pass_.texture(); }
    /// Why update() found no matrix (a header's status: a point light inside the scene is
    /// LightInsideVolume, use a cube map), "" while all is well. V is 1 (lit) meanwhile.
    const std::string& error() const { return error_; }

    // Debug views: the map's depths; the texel density at each lit receiver pixel, screen pixels per
    // shadow-map texel (warp_aliasing_error) in false colour: blue oversampled (1/4), green 1, red
    // undersampled (4 and more), log scale.
    app::DebugImage debug_depth() const { return {map_, app::DebugImage::Show::Depth}; }
    app::DebugImage debug_texel_density(const app::View& v);

    // What update() found, for the report's counters and metrics.
    const glm::mat4& light_view_proj() const { return light_vp_; }
    bool fallback_uniform() const { return fallback_; }                   ///< the warp fell back to the uniform fit
    bool drawn(std::size_t mesh) const { return caster_[mesh] && keep_[mesh]; }  ///< drawn into the map this frame
    int size() const { return size_; }  ///< texels per side of the map as rendered last

private:
    void make_map(int size);
    void release();
    std::vector<float> boxes_;           // every mesh's bounds, 6 floats each (light_frustum_fit's casters)
    std::vector<std::uint8_t> caster_;   // Mesh::caster
    std::vector<std::uint8_t> keep_;     // per mesh: may shadow the receivers (all 1 unless fitted)
    glm::vec3 caster_lo_{0.f}, caster_hi_{0.f};
    std::string error_;
    // this frame
    bool visible_ = false;               // false: nothing in view needs a shadow (or no matrix): empty map
    bool fallback_ = false;
    bool separate_depth_ = false;        // TSM: gl_FragDepth from depth_vp_
    glm::mat4 light_vp_{1.f}, depth_vp_{1.f};
    glm::mat4 warp_inverse_{1.f};       // inverse(light_vp_) (computed in double): sk_warp_shadow_auto's unprojection
    // GL
    int size_ = 0;
    GLuint map_ = 0, fbo_ = 0;
    GLuint depth_prog_ = 0, tsm_depth_prog_ = 0, vis_prog_ = 0;
    app::VisibilityPass pass_;
    skgl::Target density_;  // the texel-density view (RGBA8)
};
