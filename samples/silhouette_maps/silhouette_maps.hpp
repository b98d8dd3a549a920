// samples/silhouette_maps/silhouette_maps.hpp - shadow silhouette maps (Sen, Cammarano & Hanrahan 2003)
// and, beside them, the plain shadow map of the same memory: what the sample shows and the report measures.
//
// A sample folder is what a user copies (the same shape in every samples/<technique>/):
//   silhouette_maps.hpp  the settings (what the panel edits, named once in bind_settings()) and the class
//   silhouette_maps.cpp  the technique, top to bottom in the order it runs: init (once per scene),
//                        update (CPU, every frame), render (the GPU passes, each with its GL state)
//   main.cpp             the calls: the app shell (samples/app) does the window, the camera G-buffer,
//                        the panel, the timing and the picture
// It uses only shadowkit/silhouette.hpp, shadowkit/silhouette_map.hpp, glsl/silhouette_map.glsl (and
// glsl/shadow_map.glsl for the plain map) and the app shell's scene (sk::fit_light), G-buffer and GL
// helpers. shadowkit-report wraps this same class (samples/report/techniques/silhouette_maps.cpp).
#pragma once

#include <shadowkit/silhouette.hpp>
#include <shadowkit/silhouette_map.hpp>

#include <glm/glm.hpp>

#include <string>
#include <vector>

#include "app.hpp"
#include "gbuffer.hpp"
#include "gl.hpp"
#include "params.hpp"

struct SilhouetteMapSettings {
    /// silhouette: an N x N depth map plus an N x N RGBA8 map of silhouette points (8 bytes a texel);
    /// plain: the plain 2x2-PCF shadow map of the same memory, side round(sqrt(2) N) (4 bytes a texel):
    /// what the silhouette map competes with.
    enum class Map { Silhouette, Plain };
    Map map = Map::Silhouette;
    int size = 512;                 ///< N, texels per side of the silhouette map (and of its depth map)
    float occlusion_bias = 2e-4f;   ///< window depth: a silhouette point behind the depth map's occluder is dropped
};

/// The settings by name, once: --param, the panel's widgets and the report's sweeps use these.
inline void bind_settings(app::Params& p, SilhouetteMapSettings& s) {
    using M = SilhouetteMapSettings::Map;
    p.choice("map", &s.map, {{"silhouette", M::Silhouette}, {"plain", M::Plain}});
    p.choice("size", &s.size, {{"128", 128}, {"256", 256}, {"512", 512}, {"1024", 1024}, {"2048", 2048}});
    p.number("occlusion_bias", &s.occlusion_bias, 0.0, 0.01);
}

class SilhouetteMap {
public:
    SilhouetteMap() = default;
    SilhouetteMap(const SilhouetteMap&) = delete;
    SilhouetteMap& operator=(const SilhouetteMap&) = delete;
    ~SilhouetteMap() { release(); }

    /// Adjacency of every caster, the programs, the edge buffer, the V target. Spot and area lights
    /// only: the map needs a perspective frustum that holds the scene (point and directional: false).
    bool init(const app::View& v, std::string& why);
    /// CPU, every frame: the light's frustum (sk::fit_light), each caster's silhouette for the light,
    /// its edges projected into the map's texel space (silmap_project_edges).
    void update(const app::View& v, const SilhouetteMapSettings& s);
    /// GPU, every frame: the depth map, the silhouette map (edges as quads), V at the G-buffer's points.
    void render(const app::View& v, const SilhouetteMapSettings& s);
    /// R32F V at the G-buffer's pixels.
    GLuint visibility() const { return pass_.texture(); }
    /// The first failure of update() (a header's status), "" while all is well.
    const std::string& error() const { return error_; }

    // Debug views: the light's depth map; the silhouette points (red: the point's x in its texel, 0.5
    // where there is none).
    app::DebugImage debug_depth() const { return {depth_.depth, app::DebugImage::Show::Depth}; }
    app::DebugImage debug_silhouette() const {
        return {silmap_.color.empty() ? 0u : silmap_.color[0], app::DebugImage::Show::Value};
    }

    // What the class found (the report counts from these).
    int map_side() const { return depth_.width; }                  ///< the depth map's side as rendered last
    std::size_t edge_count() const { return edge_count_; }         ///< projected silhouette edges this frame
    const skgl::Target& silhouette_target() const { return silmap_; }  ///< RGBA8 (empty for the plain map)

private:
    void make_maps(const SilhouetteMapSettings& s);
    void release();
    struct Caster {
        std::size_t mesh = 0;
        shadowkit::SilhouetteAdjacency adj;
        std::vector<std::uint8_t> facing;
        std::vector<std::uint32_t> sil;
    };
    std::vector<Caster> casters_;
    std::vector<shadowkit::SilmapEdge> edges_;
    std::vector<float> edge_vertices_;  // per edge: a.xy, b.xy, depth_a, depth_b
    std::size_t edge_count_ = 0;
    glm::mat4 light_vp_{1.f};
    std::string error_;
    SilhouetteMapSettings built_;  // the settings the maps were made for
    bool have_maps_ = false;
    // GL
    skgl::Target depth_, silmap_;
    GLuint vao_ = 0, vbo_ = 0;
    GLuint depth_prog_ = 0, edge_prog_ = 0, vis_prog_ = 0, plain_prog_ = 0;
    app::VisibilityPass pass_;
};
