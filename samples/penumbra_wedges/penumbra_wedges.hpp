// samples/penumbra_wedges/penumbra_wedges.hpp - soft shadow volumes with penumbra wedges (Assarsson &
// Akenine-Moller 2003; Lengyel GDC 2005): what the sample shows and the report measures.
//
// The hard shadow of the light's center is the shadow_volumes sample's class (samples/shadow_volumes/),
// used as it is: its CPU stage (silhouettes, scissor rectangles, side quads and caps), its depth and
// stencil passes and its depth-stencil target. This class adds one wedge per silhouette edge: its hull
// drawn into an R32F buffer that shares the volumes' depth-stencil, where each pixel inside the wedge
// adds the edge's signed coverage of a spherical light; the last pass reads the stencil count and the
// sum: V = 1 - clamp(count + sum, 0, 1).
//   penumbra_wedges.hpp  the settings (named once in bind_settings()) and the class
//   penumbra_wedges.cpp  init (once per scene), update (CPU, every frame), render (the GPU passes)
//   main.cpp             the calls
// It uses shadowkit/penumbra_wedge.hpp, glsl/penumbra_wedge.glsl (glsl/shadow_volume.glsl for the
// depth-bounds emulation), the shadow_volumes sample and the app shell (gbuffer.hpp, with the emitter's
// horizon, and gl.hpp).
// shadowkit-report wraps this same class (samples/report/techniques/penumbra_wedges.cpp).
#pragma once

#include <shadowkit/penumbra_wedge.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "app.hpp"
#include "gbuffer.hpp"
#include "gl.hpp"
#include "params.hpp"
#include "shadow_volumes.hpp"

struct PenumbraWedgeSettings {
    /// Per wedge (and per hard volume): its scissor rectangle / its depth bounds, from the hull clipped to
    /// the box of the receivers; a wedge whose clipped hull is empty is not drawn. They never change V.
    bool scissor = true;
    bool depth_bounds = true;
    /// The depth the volumes and the hulls are tested against: the G-buffer's (finite, GL_DEPTH_CLAMP), or
    /// the scene re-drawn with the epsilon-tweaked P_inf (infinite; ShadowVolumeSettings::Projection).
    enum class Projection { Finite, Infinite };
    Projection projection = Projection::Finite;
    /// The wedges need a spherical light: sphere and disk lights give their radius, a square light the
    /// disk of its area (area: the same occlusion in the middle of a penumbra, the lowest error) or its
    /// circumscribed disk (bounding: wedges that hold the square's, but 1.57x too wide penumbrae). Point,
    /// spot and directional lights have none: the hard shadow alone.
    enum class RectLight { Area, Bounding };
    RectLight rect_radius = RectLight::Area;
    /// V times the emitter's fraction above the receiver's tangent plane (app/gbuffer.hpp): light below it
    /// does not arrive, which the casters' silhouettes do not model on the casters' own lit faces.
    bool horizon = true;
    /// The hard volumes per caster: z-fail always, or z-pass where the near plane cannot be in the volume.
    enum class Method { ZFail, Auto };
    Method method = Method::Auto;
    /// Which faces of a hull are drawn: auto (the front faces with GL_LEQUAL; the back faces with GL_GEQUAL
    /// where the hull reaches the near plane, as when the camera is inside the wedge), back (always the
    /// back faces: right too), front (always the front faces, Lengyel's: misses the pixels of a wedge the
    /// camera is inside).
    enum class Faces { Auto, Back, Front };
    Faces faces = Faces::Auto;
    float light_scale = 1.f;  ///< multiplies the wedges' light radius (0: the hard shadow alone)
    /// Open casters (ShadowVolumeSettings::OpenMeshes): the hard volume and the wedges' silhouette from
    /// every face (two_sided: one wedge per edge even where the silhouette has it twice, the hard count
    /// capped at 1 in the combine pass; docs/penumbra_wedge.md) or from the lit faces only (lit_only:
    /// light leaks through holes). lit_only by default: two_sided fixes a bowl (umbra leak 90% -> 8.5%)
    /// but triples the scanned dragon's RMSE (0.0111 -> 0.0351, leak 1.1% -> 17%: its small holes).
    ShadowVolumeSettings::OpenMeshes open_meshes = ShadowVolumeSettings::OpenMeshes::LitOnly;
};

/// The settings by name, once: --param, the panel's widgets and the report's sweeps use these.
inline void bind_settings(app::Params& p, PenumbraWedgeSettings& s) {
    using S = PenumbraWedgeSettings;
    p.toggle("scissor", &s.scissor);
    p.toggle("depth_bounds", &s.depth_bounds);
    p.choice("projection", &s.projection, {{"finite", S::Projection::Finite}, {"infinite", S::Projection::Infinite}});
    p.choice("rect_radius", &s.rect_radius, {{"area", S::RectLight::Area}, {"bounding", S::RectLight::Bounding}});
    p.toggle("horizon", &s.horizon);
    p.choice("method", &s.method, {{"zfail", S::Method::ZFail}, {"auto", S::Method::Auto}});
    p.choice("faces", &s.faces, {{"auto", S::Faces::Auto}, {"back", S::Faces::Back}, {"front", S::Faces::Front}});
    p.number("light_scale", &s.light_scale, 0.0, 4.0);
    p.choice("open_meshes", &s.open_meshes,
             {{"two_sided", ShadowVolumeSettings::OpenMeshes::TwoSided}, {"lit_only", ShadowVolumeSettings::OpenMeshes::LitOnly}});
}

class PenumbraWedges {
public:
    /// One wedge as update() built it.
    struct Wedge {
        bool visible = true;       ///< its hull clipped to the receivers is not empty (true without scissor and depth bounds)
        bool back = false;         ///< drawn with its hull's back faces (GL_GEQUAL)
        shadowkit::ScissorRect sc; ///< its scissor rectangle and depth bounds (scissor or depth_bounds on)
    };

    PenumbraWedges() = default;
    PenumbraWedges(const PenumbraWedges&) = delete;
    PenumbraWedges& operator=(const PenumbraWedges&) = delete;
    ~PenumbraWedges() { release(); }

    /// The volumes' init, the wedge buffers (one wedge per possible silhouette edge), programs, targets.
    bool init(const app::View& v, std::string& why);
    /// CPU, every frame: the volumes' stage, then a wedge, its hull, scissor and faces per silhouette edge.
    void update(const app::View& v, const PenumbraWedgeSettings& s);
    /// GPU, every frame: the volumes' depth and stencil, the wedges' coverage, V.
    void render(const app::View& v, const PenumbraWedgeSettings& s);
    /// R32F V at the G-buffer's pixels.
    GLuint visibility() const { return pass_.texture(); }
    /// The first failure of update() (a header's status), "" while all is well.
    const std::string& error() const { return error_; }

    /// Debug view: every wedge's hull (its eight triangles) in orange lines over the picture.
    app::DebugImage debug_hulls();

    // The wedge pass in its pieces, as render() runs them (the report counts and times draw_hulls under the
    // pass's state), and what the class found.
    void begin_wedge_pass(const app::View& v, const PenumbraWedgeSettings& s) const;
    void draw_hulls(const PenumbraWedgeSettings& s) const;
    void end_wedge_pass() const;
    const ShadowVolumes& volumes() const { return volumes_; }
    const std::vector<Wedge>& wedges() const { return wedges_; }
    /// Silhouette edges without a wedge: penumbra_wedge skipped them, or their hull is not drawable.
    std::size_t edges_without_wedge() const { return skipped_; }
    std::size_t silhouette_edges() const { return silhouette_edges_; }  ///< of every caster (with a light radius)
    float light_radius() const { return sphere_.radius; }
    std::size_t wedge_capacity() const { return capacity_; }
    GLuint wedge_buffer() const { return ssbo_; }  ///< per wedge 7 vec4: planes (outer, inner, side 0, 1), e0, e1, depth bounds
    /// The depth bounds are GL_EXT_depth_bounds_test's (the finite projection), else glsl/shadow_volume.glsl's emulation.
    bool native_depth_bounds(const PenumbraWedgeSettings& s) const {
        return s.depth_bounds && s.projection == PenumbraWedgeSettings::Projection::Finite && volumes_.native_depth_bounds();
    }

private:
    void add_wedge(const glm::vec3& e0, const glm::vec3& e1, const PenumbraWedgeSettings& s);
    void release();
    ShadowVolumes volumes_;               // the hard shadow of the light's center
    ShadowVolumeSettings volume_settings_;
    std::string error_;
    std::size_t capacity_ = 0;            // wedges: every caster's most silhouette edges
    std::vector<std::uint8_t> facing_;    // a culled caster's facing and silhouette (the volumes skip it)
    std::vector<std::uint32_t> sil_;
    bool any_two_sided_ = false;  ///< this frame: a caster's hard volume and silhouette are two-sided
    // this frame
    shadowkit::PenumbraSphereLight sphere_;
    glm::mat4 cam_vp_{1.f}, cam_view_{1.f};  // the G-buffer's camera
    float znear_ = 0.f;
    std::size_t skipped_ = 0, silhouette_edges_ = 0, front_ = 0, back_ = 0;  // front_, back_: visible wedges per face group
    std::vector<Wedge> wedges_;
    std::vector<glm::vec4> gpu_wedges_;    // 7 per wedge (wedge_buffer())
    std::vector<glm::vec4> hull_vertices_; // 6 per wedge
    std::vector<std::uint32_t> hull_ids_;  // the wedge of each hull vertex
    std::vector<std::uint8_t> hull_local_; // 24 per wedge: penumbra_wedge_hull's indices
    std::vector<std::uint32_t> order_;         // the wedges in draw order: front faces, back faces, culled
    std::vector<std::uint32_t> hull_indices_;  // 24 per wedge, in that order
    // GL
    GLuint vao_ = 0, vbo_ = 0, ids_ = 0, ibo_ = 0, ssbo_ = 0;
    GLuint wedge_prog_ = 0, combine_prog_ = 0, wire_prog_ = 0;
    skgl::Target coverage_;     // R32F coverage sum, with the volumes' depth-stencil attached
    app::VisibilityPass pass_;  // R32F V
    skgl::Target wire_view_;
};
