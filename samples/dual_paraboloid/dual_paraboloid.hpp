// samples/dual_paraboloid/dual_paraboloid.hpp - a point light's shadows from a dual-paraboloid map
// (Brabec et al. 2002; omni_shadow.hpp): two layers, each a hemisphere around the light projected
// onto a paraboloid in the vertex shader. Straight edges become curves in such a map, which the
// rasterizer draws as straight chords: the casters are tessellated until the chords stay within `tess`
// texels of the curves (omni_paraboloid_max_edge_length). What the sample shows and the report measures.
// The cube map of the same header is samples/omni_shadows/.
//
// A sample folder is what a user copies (the same shape in every samples/<technique>/):
//   dual_paraboloid.hpp  the settings (what the panel edits, named once in bind_settings()) and the class
//   dual_paraboloid.cpp  the technique, top to bottom in the order it runs: init (once per scene),
//                        update (CPU, every frame), render (the GPU passes, each with its GL state)
//   main.cpp             the calls: the app shell (samples/app) does the window, the camera G-buffer,
//                        the panel, the timing and the picture
// It uses only shadowkit/omni_shadow.hpp, glsl/omni_shadow.glsl and the app shell's G-buffer
// (app/gbuffer.hpp) and GL helpers (app/gl.hpp). shadowkit-report wraps this same class
// (samples/report/techniques/omni.cpp).
#pragma once

#include <glm/glm.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "app.hpp"
#include "gbuffer.hpp"
#include "gl.hpp"
#include "params.hpp"

struct DualParaboloidSettings {
    /// Texels per side of each paraboloid. sqrt(3) times a cube face's gives the cube's texel count
    /// (2 s^2 = 6 c^2): 443, 887, 1774 for faces of 256, 512, 1024.
    int size = 887;
    /// The casters' chords may leave the paraboloid's curves by this many texels
    /// (omni_paraboloid_edge_error); 0: the meshes as they are.
    float tess = 1.f;
    int pcf = 0;  ///< 0: one hardware 2x2 compare; r: (2r + 1)^2 of them (sk_dp_shadow_pcf), across the rim
};

/// The settings by name, once: --param, the panel's widgets and the report's sweeps use these.
inline void bind_settings(app::Params& p, DualParaboloidSettings& s) {
    p.number("size", &s.size, 16, 8192);
    p.number("tess", &s.tess, 0.0, 64.0);
    p.number("pcf", &s.pcf, 0, 4);
}

class DualParaboloid {
public:
    DualParaboloid() = default;
    DualParaboloid(const DualParaboloid&) = delete;
    DualParaboloid& operator=(const DualParaboloid&) = delete;
    ~DualParaboloid() { release(); }

    /// The programs and the V target.
    bool init(const app::View& v, std::string& why);
    /// CPU, every frame: the range of the stored distance, the paraboloids' frame, and the casters
    /// tessellated again when the light or the settings changed (tessellate()).
    void update(const app::View& v, const DualParaboloidSettings& s);
    /// GPU, every frame: the distances into both paraboloids, then V at the G-buffer's points.
    void render(const app::View& v, const DualParaboloidSettings& s);
    /// R32F V at the G-buffer's pixels.
    GLuint visibility() const { return pass_.texture(); }
    /// Why update() found no map (a header's status: the sun is InvalidLight), "" while all is well.
    /// V is 1 (lit) meanwhile.
    const std::string& error() const { return error_; }

    /// Debug views: the stored distances of the paraboloid around the frame's +y (0) and -y (1).
    app::DebugImage debug_layer(int i) const { return {layer_view_[i], app::DebugImage::Show::Depth}; }

    /// The casters subdivided for this light and settings, uploaded (update() calls it when needed).
    void tessellate(const app::View& v, const DualParaboloidSettings& s);
    /// Distance from p to the triangle abc (the caster's nearest point: where its curves bend most).
    static float distance_to_triangle(glm::vec3 p, glm::vec3 a, glm::vec3 b, glm::vec3 c);
    static constexpr float kMargin = 0.1f;  ///< each layer is drawn to 0.1 beyond its rim (clip distance)
    /// The largest map radius drawn, at the margin: sqrt((1 + margin) / (1 - margin)).
    static float max_radius();
    // What update() built, for the report's counters.
    int subdivision() const { return max_n_; }   ///< the finest n of the n x n subdivisions
    std::size_t triangles() const { return triangles_; }  ///< the tessellated casters' triangles (per layer)
    std::size_t draws() const { return meshes_.size(); }  ///< caster meshes drawn per layer
    int size() const { return size_; }                    ///< texels per side as rendered last

private:
    void make_maps(int size);
    void release();
    std::string error_;
    // this frame
    glm::mat4 frame_{1.f};
    float range_ = 0.f;
    glm::vec3 tess_light_{NAN};  // the light, size and tess the meshes were tessellated for
    int tess_size_ = 0;
    float tess_tess_ = -1.f;
    std::vector<skgl::GpuMesh> meshes_;
    std::size_t triangles_ = 0;
    int max_n_ = 1;
    // GL
    int size_ = 0;
    GLuint maps_ = 0, fbo_[2] = {0, 0}, layer_view_[2] = {0, 0};
    GLuint depth_prog_ = 0, vis_prog_ = 0;
    app::VisibilityPass pass_;
};
