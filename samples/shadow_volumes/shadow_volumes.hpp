// samples/shadow_volumes/shadow_volumes.hpp - robust stenciled shadow volumes (Everitt & Kilgard 2002,
// Lengyel 2002): what the sample shows and the report measures.
//
// A sample folder is what a user copies (this one is the template of every samples/<technique>/):
//   shadow_volumes.hpp  the settings (what the panel edits, named once in bind_settings()) and the class
//   shadow_volumes.cpp  the technique, top to bottom in the order it runs: init (once per scene),
//                       update (CPU, every frame), render (the GPU passes, each with its GL state)
//   main.cpp            the calls: the app shell (samples/app) does the window, the camera G-buffer,
//                       the panel, the timing and the picture
// It uses only shadowkit/silhouette.hpp, shadowkit/shadow_volume.hpp, shadowkit/infinite_projection.hpp,
// glsl/shadow_volume.glsl and the app shell's G-buffer (app/gbuffer.hpp) and GL helpers (app/gl.hpp).
// shadowkit-report wraps this same class (samples/report/techniques/shadow_volumes.cpp): it times
// update() and render(), reads back visibility() and counts the work from casters() and the passes.
#pragma once

#include <shadowkit/shadow_volume.hpp>
#include <shadowkit/silhouette.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "app.hpp"
#include "gbuffer.hpp"
#include "gl.hpp"
#include "params.hpp"

struct ShadowVolumeSettings {
    /// Per caster: z-fail always; z-pass where the camera's near plane cannot be in the caster's
    /// volume (volume_choose_stencil_method_box), else z-fail; z-pass always (wrong wherever the
    /// camera is in a shadow: the report's rows show what the caps of z-fail cost).
    enum class Method { ZFail, Auto, ZPass };
    Method method = Method::Auto;
    bool scissor = true;       ///< draw each volume inside its scissor rectangle (volume_scissor)
    bool depth_bounds = true;  ///< and its depth bounds: GL_EXT_depth_bounds_test, else shadow_volume.glsl's emulation
    /// The depth the volumes are tested against. finite: the G-buffer's own depth and matrix, with
    /// GL_DEPTH_CLAMP keeping the vertices at infinity; infinite: the scene's depth re-drawn with the
    /// epsilon-tweaked P_inf of infinite_projection.hpp (what a renderer with an infinite far plane
    /// has anyway); reversed: the same with reversed-Z zero-to-one depth (glClipControl), which keeps
    /// float32 precision at a near plane of 1e-5.
    enum class Projection { Finite, Infinite, Reversed };
    Projection projection = Projection::Finite;
    /// Casters with boundary or non-manifold edges (SilhouetteAdjacency::closed() false): every face
    /// an occluder (two_sided: silhouette_extract_two_sided + VolumeCapMode::TwoSided, what a ray
    /// tracer tests), or lit faces only (lit_only: light entering through a hole and leaving through
    /// back faces is not stopped). Closed casters always use the lit faces (the same shadow, cheaper).
    enum class OpenMeshes { TwoSided, LitOnly };
    OpenMeshes open_meshes = OpenMeshes::TwoSided;
};

/// The settings by name, once: --param, the panel's widgets and the report's sweeps use these.
inline void bind_settings(app::Params& p, ShadowVolumeSettings& s) {
    using M = ShadowVolumeSettings::Method;
    using P = ShadowVolumeSettings::Projection;
    p.choice("method", &s.method, {{"zfail", M::ZFail}, {"auto", M::Auto}, {"zpass", M::ZPass}});
    p.toggle("scissor", &s.scissor);
    p.toggle("depth_bounds", &s.depth_bounds);
    p.choice("projection", &s.projection, {{"finite", P::Finite}, {"infinite", P::Infinite}, {"reversed", P::Reversed}});
    p.choice("open_meshes", &s.open_meshes,
             {{"two_sided", ShadowVolumeSettings::OpenMeshes::TwoSided}, {"lit_only", ShadowVolumeSettings::OpenMeshes::LitOnly}});
}

class ShadowVolumes {
public:
    /// One caster mesh: its adjacency (once per scene) and what update() found for it this frame.
    struct Caster {
        std::size_t mesh = 0;                   ///< index into Scene::meshes
        shadowkit::SilhouetteAdjacency adj;     ///< edges and faces (silhouette_build_adjacency)
        shadowkit::SilhouettePlanes planes;     ///< face planes, cached: the mesh is rigid
        glm::vec3 lo{0.f}, hi{0.f};             ///< bounds
        GLint base_vertex = 0;                  ///< first of its 2n vertices (p, 1), (p, 0) in the vertex buffer
        std::size_t index_offset = 0, index_capacity = 0;  ///< its range of the index buffer
        std::vector<std::uint8_t> facing;       ///< per face: lit by the light
        std::vector<std::uint32_t> sil;         ///< silhouette edges (2 indices each)
        // this frame
        bool visible = true;                    ///< false: its scissor rectangle is empty, not drawn
        bool zfail = true;
        bool two_sided = false;                 ///< this update's volume: every face (open caster, open_meshes two_sided)
        std::size_t sil_edges = 0, side_count = 0, cap_count = 0;  ///< edges; indices of sides and caps
        shadowkit::ScissorRect sc;              ///< scissor rectangle and depth bounds (scissor or depth_bounds on)
    };

    ShadowVolumes() = default;
    ShadowVolumes(const ShadowVolumes&) = delete;
    ShadowVolumes& operator=(const ShadowVolumes&) = delete;
    ~ShadowVolumes() { release(); }

    /// Adjacency and face planes of every caster, the extruded vertex buffer, the programs, the target.
    bool init(const app::View& v, std::string& why);
    /// CPU, every frame: per caster scissor, facing, silhouette, z-pass / z-fail, side quads and caps.
    void update(const app::View& v, const ShadowVolumeSettings& s);
    /// GPU, every frame: scene depth, the volumes into the stencil, V = (stencil == 0).
    void render(const app::View& v, const ShadowVolumeSettings& s);
    /// render() without its last pass: the scene's depth and each point's count of volumes in the stencil of
    /// target().target.depth (what a technique built on the volumes reads; samples/penumbra_wedges/).
    void render_stencil(const app::View& v, const ShadowVolumeSettings& s);
    /// R32F V at the G-buffer's pixels.
    GLuint visibility() const { return pass_.texture(); }
    /// The first failure of update() (a header's status), "" while all is well.
    const std::string& error() const { return error_; }

    // Debug views: the stencil counts (the number of volumes around each point); the scissor
    // rectangles over the picture (red: z-fail caster, green: z-pass caster).
    app::DebugImage debug_stencil() const { return {pass_.target.depth, app::DebugImage::Show::Stencil}; }
    app::DebugImage debug_scissor();

    // The pieces of the volume pass, as render() runs them (the report counts the fill of draw_volumes
    // under its own state), and what the class found.
    void begin_volume_state(const ShadowVolumeSettings& s) const;
    void draw_volumes(const ShadowVolumeSettings& s) const;
    void end_volume_state() const;
    /// One object's culling (Lengyel): its scissor rectangle (`scissor`) and its depth bounds with
    /// GL_EXT_depth_bounds_test (`native_bounds`); the caller disables both after its last object.
    static void set_scissor_and_depth_bounds(const shadowkit::ScissorRect& sc, bool scissor, bool native_bounds);
    const std::vector<Caster>& casters() const { return casters_; }
    const app::VisibilityPass& target() const { return pass_; }  ///< R32F V + DEPTH32F_STENCIL8
    bool native_depth_bounds() const { return native_bounds_; }  ///< GL_EXT_depth_bounds_test is there
    float projection_epsilon() const { return epsilon_; }        ///< of the infinite projections (0: finite)
    const glm::mat4& volume_view_proj() const { return volume_vp_; }  ///< the matrix of the volumes and the depth
    /// The box of everything that can receive this light's shadows (update(): the scene, a spot light's
    /// cut to its cone), which the scissor rectangles are clipped to.
    glm::vec3 receiver_min() const { return receiver_lo_; }
    glm::vec3 receiver_max() const { return receiver_hi_; }
    std::size_t vertex_count() const { return vertex_count_; }
    std::size_t index_capacity() const { return indices_.size(); }

private:
    void release();
    std::vector<Caster> casters_;
    std::vector<std::uint32_t> indices_;  // every caster's index range, written by update()
    std::size_t vertex_count_ = 0;
    std::string error_;
    // this frame
    glm::vec4 light_{0.f};
    glm::mat4 volume_vp_{1.f};
    glm::vec3 receiver_lo_{0.f}, receiver_hi_{0.f};
    float epsilon_ = 0.f;
    GLuint gbuffer_depth_ = 0;  // the G-buffer's depth texture: what the depth-bounds emulation reads
    // GL
    GLuint vao_ = 0, vbo_ = 0, ibo_ = 0;
    GLuint volume_prog_ = 0, volume_bounds_prog_ = 0, depth_prog_ = 0, vis_prog_ = 0;
    bool native_bounds_ = false;
    app::VisibilityPass pass_;  // R32F V and our own depth-stencil (the G-buffer's format: blits need it)
    skgl::Target scissor_view_;
};
