// samples/smoothies/smoothies.hpp - smoothies (Chan & Durand 2003, "Rendering Fake Soft Shadows with
// Smoothies"): what the sample shows and the report measures.
//
// A hard shadow map of linear light depths plus, per silhouette edge seen from the light's center, a
// "smoothie": a quad of width t (light NDC) hanging outward from the edge, whose alpha rises from 0 at the
// edge to 1 at its outer side. Receivers outside the blockers' map footprint but under a smoothie get
// V = the smoothie's alpha remapped by the blocker-receiver distance (eq. 1): a penumbra that grows with
// (r - b) / b, wholly outside the hard shadow (the umbra never shrinks).
//   smoothies.hpp  the settings (named once in bind_settings()) and the class
//   smoothies.cpp  init (once per scene), update (CPU, every frame), render (the GPU passes)
//   main.cpp       the calls
// It uses shadowkit/silhouette.hpp, shadowkit/smoothie.hpp, glsl/smoothie.glsl and the app shell's scene
// (sk::fit_light: the light's frustum around the scene), G-buffer (app/gbuffer.hpp) and GL helpers
// (app/gl.hpp). shadowkit-report wraps this same class (samples/report/techniques/smoothies.cpp).
#pragma once

#include <shadowkit/silhouette.hpp>
#include <shadowkit/smoothie.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "app.hpp"
#include "gbuffer.hpp"
#include "gl.hpp"
#include "params.hpp"

struct SmoothieSettings {
    /// The smoothie width t in light NDC: from the light (t = s w / b, smoothie_width_for_area_light, with s
    /// the light projection's x scale, w the emitter's width and b the median light depth of the silhouette
    /// vertices: the typical blocker; 0 for lights without area and for a directional light's orthographic
    /// map), or the number `t` (0: no smoothies, the hard 2x2 test on the linear map).
    bool t_from_light = true;
    float t = 0.05f;
    int size = 1024;  ///< texels per side of the shadow map and of the smoothie buffer
    /// Where eq. 1 remaps alpha: in the smoothie pass, each smoothie against the map's depth under it (the
    /// paper's; GL_MIN then keeps the smallest remapped alpha, and every mesh goes into the map); or in the
    /// final pass with the receiver's depth (casters only in the map; where a near and a far smoothie
    /// overlap the buffer's minima of depth and alpha can come from different smoothies).
    enum class Remap { SmoothiePass, FinalPass };
    Remap remap = Remap::SmoothiePass;
};

/// The settings by name, once: --param, the panel's widgets and the report's sweeps use these.
inline void bind_settings(app::Params& p, SmoothieSettings& s) {
    p.toggle("t_from_light", &s.t_from_light);
    p.number("t", &s.t, 0.0, 1.0);
    p.choice("size", &s.size, {{"256", 256}, {"512", 512}, {"1024", 1024}, {"2048", 2048}, {"4096", 4096}});
    p.choice("remap", &s.remap, {{"smoothie_pass", SmoothieSettings::Remap::SmoothiePass},
                                 {"final_pass", SmoothieSettings::Remap::FinalPass}});
}

class Smoothies {
public:
    /// One caster mesh: its adjacency (once per scene) and what update() found for it this frame.
    struct Caster {
        std::size_t mesh = 0;                              ///< index into Scene::meshes
        shadowkit::SilhouetteAdjacency adj;                ///< edges and faces (silhouette_build_adjacency)
        std::vector<std::uint8_t> facing;                  ///< per face: lit by the light's center
        std::vector<std::uint32_t> sil;                    ///< silhouette edges (2 indices each)
        std::vector<shadowkit::SmoothieScratch> scratch;   ///< smoothie_build's per-edge scratch
        // this frame
        std::size_t sil_edges = 0;
        std::size_t first = 0;                             ///< its smoothies' first vertex in the vertex buffer
        shadowkit::SmoothieResult built;                   ///< its smoothies (built.count vertices from `first`)
    };

    Smoothies() = default;
    Smoothies(const Smoothies&) = delete;
    Smoothies& operator=(const Smoothies&) = delete;
    ~Smoothies() { release(); }

    /// Adjacency of every caster, the smoothie vertex buffer (the worst case), the programs, the V target.
    /// Point lights are refused: a smoothie buffer is one light frustum.
    bool init(const app::View& v, std::string& why);
    /// CPU, every frame: the light frustum, each caster's silhouette, t, the smoothies (smoothie_build).
    void update(const app::View& v, const SmoothieSettings& s);
    /// GPU, every frame: the linear depth map, the smoothie buffer (GL_MIN), V at the G-buffer's points.
    void render(const app::View& v, const SmoothieSettings& s);
    /// R32F V at the G-buffer's pixels.
    GLuint visibility() const { return pass_.texture(); }
    /// The first failure of update() (a header's status), "" while all is well.
    const std::string& error() const { return error_; }

    /// Debug views of the smoothie buffer (light space): alpha (0 on a silhouette, 1 at a smoothie's outer
    /// side and where there is none) and depth b (the blocker's light depth; none: not shown).
    app::DebugImage debug_alpha() { return debug_channel(1); }
    app::DebugImage debug_depth() { return debug_channel(0); }

    // What the class found (the report counts from these).
    const std::vector<Caster>& casters() const { return casters_; }
    float t() const { return t_; }                   ///< the width used this frame (light NDC)
    float b_median() const { return b_median_; }     ///< the median silhouette depth t came from (0: t was given)
    std::size_t vertex_count() const { return vertex_count_; }       ///< smoothie vertices this frame (3 a triangle)
    std::size_t vertex_capacity() const { return vertices_.size(); }
    int size() const { return size_; }               ///< texels per side as rendered last

private:
    void make_targets(int size);
    app::DebugImage debug_channel(int channel);
    void release();
    std::vector<Caster> casters_;
    std::vector<shadowkit::SmoothieVertex> vertices_;  // the casters' smoothies one after the other (update())
    std::size_t vertex_count_ = 0;
    std::string error_;
    // this frame
    glm::mat4 light_view_{1.f}, light_vp_{1.f};
    float t_ = 0.f, b_median_ = 0.f;
    std::vector<float> depths_;  // the silhouette vertices' light depths (t from the light)
    // GL
    int size_ = 0;
    skgl::Target map_, buffer_, debug_;  // linear depth map (R32F + depth), smoothie buffer (RG32F), a debug channel
    GLuint vao_ = 0, vbo_ = 0, depth_prog_ = 0, smoothie_prog_ = 0, vis_prog_ = 0, debug_prog_ = 0;
    app::VisibilityPass pass_;
};
