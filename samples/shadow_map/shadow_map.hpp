// samples/shadow_map/shadow_map.hpp - the plain shadow map (Williams 1978) with the hardware 2x2
// percentage-closer filter: the kit's baseline, what the sample shows and the report measures.
//
// A sample folder is what a user copies (the same shape in every samples/<technique>/):
//   shadow_map.hpp  the settings (what the panel edits, named once in bind_settings()) and the class
//   shadow_map.cpp  the technique, top to bottom in the order it runs: init (once per scene),
//                   update (CPU, every frame), render (the GPU passes, each with its GL state)
//   main.cpp        the calls: the app shell (samples/app) does the window, the camera G-buffer,
//                   the panel, the timing and the picture
// It uses only include/shadowkit/light_frustum.hpp (light_frustum_fit_casters: the light's frustum
// around the casters), glsl/shadow_map.glsl (its automatic bias: sk_shadow_map_visibility_auto),
// glsl/contact_shadow.glsl (contact=on) and the app shell's scene, G-buffer (app/gbuffer.hpp) and GL helpers (app/gl.hpp). shadowkit-report wraps
// this same class (samples/report/techniques/shadow_map.cpp).
#pragma once

#include <glm/glm.hpp>

#include <string>

#include "app.hpp"
#include "gbuffer.hpp"
#include "gl.hpp"
#include "params.hpp"

struct ShadowMapSettings {
    enum class Bias { Auto, PolygonOffset };
    int size = 2048;            ///< texels per side (of each of the six cube faces for a point light)
    bool hardware_pcf = true;   ///< the 2x2 percentage-closer filter; off: the nearest texel, hard 0 / 1
    /// auto (default): sk_shadow_map_visibility_auto, each of the 2x2 texels compared with the receiver
    /// plane's own depth (from the G-buffer normal), no polygon offset, nothing to tune (2D maps; a
    /// point light's cube map keeps the polygon offset). polygon_offset: glPolygonOffset(offset_factor,
    /// offset_units) in the depth pass, the classic slope-scaled bias with hand-picked constants.
    Bias bias = Bias::Auto;
    bool fit_casters = true;    ///< the map fits the casters (shadowkit::light_frustum_fit_casters); off: the whole scene (sk::fit_light)
    float offset_factor = 2.f;  ///< glPolygonOffset(factor, units) of the depth pass (bias=polygon_offset, cube maps)
    float offset_units = 2.f;
    /// Contact shadows (glsl/contact_shadow.glsl): V times a march toward the light in the camera's depth
    /// buffer, contact_pixels long on screen (the length of screen-space shadows in engines): the
    /// occlusion near contacts that the map's bias and its 2x2 filter lose.
    bool contact = false;
    float contact_pixels = 16.f;  ///< the march's length: this many camera pixels' world size at the receiver
};

/// The settings by name, once: --param, the panel's widgets and the report's sweeps use these.
inline void bind_settings(app::Params& p, ShadowMapSettings& s) {
    p.choice("size", &s.size, {{"256", 256}, {"512", 512}, {"1024", 1024}, {"2048", 2048}, {"4096", 4096}});
    p.toggle("hardware_pcf", &s.hardware_pcf);
    p.choice("bias", &s.bias, {{"auto", ShadowMapSettings::Bias::Auto}, {"polygon_offset", ShadowMapSettings::Bias::PolygonOffset}});
    p.number("offset_factor", &s.offset_factor, 0.0, 8.0);
    p.number("offset_units", &s.offset_units, 0.0, 64.0);
    p.toggle("fit_casters", &s.fit_casters);
    p.toggle("contact", &s.contact);
    p.number("contact_pixels", &s.contact_pixels, 1.0, 256.0);
}

class ShadowMap {
public:
    ShadowMap() = default;
    ShadowMap(const ShadowMap&) = delete;
    ShadowMap& operator=(const ShadowMap&) = delete;
    ~ShadowMap() { release(); }

    /// The programs and the V target; a point light gets a cube map, every other light one 2D map.
    bool init(const app::View& v, std::string& why);
    /// CPU, every frame: the light's view-projection (the six faces' for a cube map).
    void update(const app::View& v, const ShadowMapSettings& s);
    /// GPU, every frame: the depth pass into the map, then V at the G-buffer's points.
    void render(const app::View& v, const ShadowMapSettings& s);
    /// R32F V at the G-buffer's pixels.
    GLuint visibility() const { return pass_.texture(); }

    /// Debug view: the 2D map's depths (none for a cube map).
    app::DebugImage debug_depth() const { return {cube_ ? 0u : map_, app::DebugImage::Show::Depth}; }
    bool cube() const { return cube_; }
    int size() const { return size_; }  ///< texels per side of the map (per face) as rendered last
    const glm::mat4& light_view_proj() const { return light_vp_[0]; }  ///< the 2D map's (a cube map: face 0's)

private:
    void make_map(int size);
    bool make_visibility_program(const ShadowMapSettings& s, std::string& why);
    void release();
    bool cube_ = false;
    int size_ = 0;
    glm::mat4 light_vp_[6];        // one 2D map: [0]; a cube map: the six faces
    float near_ = 0.f, far_ = 0.f;  // the cube faces' depth range
    GLuint map_ = 0, fbo_[6] = {0, 0, 0, 0, 0, 0};
    GLuint depth_prog_ = 0, vis_prog_ = 0;
    int vis_variant_ = -1;  // the bias and contact setting the V program was compiled for (its lookup differs)
    std::string snippet_;
    app::VisibilityPass pass_;
};
