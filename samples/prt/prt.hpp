// samples/prt/prt.hpp - precomputed radiance transfer (Sloan, Kautz & Snyder 2002): soft shadows and
// interreflection-free ambient lighting from an environment, one dot product per vertex.
//
// A sample folder is what a user copies (the same shape in every samples/<technique>/):
//   prt.hpp        the settings (what the panel edits, named once in bind_settings()) and the class
//   prt.cpp        the technique, top to bottom in the order it runs: init (once per scene),
//                  precompute (CPU + Embree, when the sampling changes), update (CPU, every frame),
//                  render (the GPU pass with its GL state)
//   main.cpp       the calls: the app shell (samples/app) does the window, the camera, the panel, the
//                  timing and the picture
//   prt_scene.hpp  the prt scene (a lumpy blob and a box over a finely tessellated floor), its sky + sun
//                  environment and the Embree visibility callback; the report's PRT section uses it too
// Unlike the shadow samples, PRT shades the picture itself (no light, no V): the App shows color().
// It uses only shadowkit/prt.hpp, shadowkit/spherical_harmonics.hpp, glsl/prt.glsl and the app shell.
#pragma once

#include <shadowkit/prt.hpp>

#include <glm/glm.hpp>

#include <string>
#include <vector>

#include "app.hpp"
#include "gl.hpp"
#include "params.hpp"
#include "prt_scene.hpp"
#include "scene.hpp"

struct PrtSettings {
    int order = 5;             ///< SH bands used when shading (1..5; the transfer is computed at 5)
    int strata = 32;           ///< precomputation: strata^2 stratified directions per vertex
    bool shadows = true;       ///< shadowed transfer (visibility in the integral) or unshadowed (cosine only)
    float yaw = 0.f;           ///< degrees: the environment turned about the vertical axis (and with the light)
    float pitch = 0.f;         ///< degrees: then about the x axis
    float exposure = 0.8f;     ///< tone mapping 1 - exp(-exposure x radiance)
};

/// The settings by name, once: --param, the panel's widgets.
inline void bind_settings(app::Params& p, PrtSettings& s) {
    p.number("order", &s.order, 1, 5);
    p.choice("strata", &s.strata, {{"4", 4}, {"8", 8}, {"16", 16}, {"32", 32}, {"64", 64}});
    p.toggle("shadows", &s.shadows);
    p.number("yaw", &s.yaw, -180.0, 180.0);
    p.number("pitch", &s.pitch, -90.0, 90.0);
    p.number("exposure", &s.exposure, 0.05, 4.0);
}

/// The app shell's scene of samples/prt: prt_scene.hpp's floor, blob and box as three meshes (their
/// albedos are the class's first three colors), the camera of the old sample, a directional light
/// along the environment's sun (the App turns it: the environment turns with it).
sk::Scene prt_app_scene();

class Prt {
public:
    Prt() = default;
    Prt(const Prt&) = delete;
    Prt& operator=(const Prt&) = delete;
    ~Prt() { release(); }

    /// The scene's meshes as one vertex buffer (position, albedo), the environment in SH, the program,
    /// the color target. false: no vertex-stage storage buffers, a mesh without normals.
    bool init(const app::View& v, std::string& why);
    /// CPU + Embree, when `strata` changed (or on the first call): every vertex's transfer vectors,
    /// shadowed and unshadowed, uploaded as two storage buffers. Seconds, not a per-frame step.
    void precompute(const app::View& v, const PrtSettings& s);
    /// CPU, every frame: the environment's SH turned by yaw (plus the light's turn about the
    /// vertical) and pitch (sh_rotate).
    void update(const app::View& v, const PrtSettings& s);
    /// GPU, every frame: the meshes, each vertex's radiance = albedo x dot(transfer, environment).
    void render(const app::View& v, const PrtSettings& s);
    /// RGBA8 picture at the G-buffer's size.
    GLuint color() const { return target_.color.empty() ? 0u : target_.color[0]; }
    /// Debug view (draws it into the picture): ambient occlusion, the shadowed transfer's band 0 under
    /// a constant white environment (grey, stretched).
    app::DebugImage debug_occlusion(const app::View& v);
    /// The first failure of precompute() or update(), "" while all is well.
    const std::string& error() const { return error_; }

    std::size_t vertex_count() const { return mesh_.positions.size(); }
    double transfer_seconds() const { return seconds_; }  ///< the last precompute()

private:
    void draw(const app::View& v, const glm::vec3* env, int count, bool shadows, float exposure);
    void release();
    skprt::PrtScene mesh_;         // every mesh of the scene in one (positions, normals, albedo, indices)
    std::vector<glm::vec3> env_;   // the environment's 25 SH coefficients (RGB), unrotated
    std::vector<glm::vec3> env_rotated_;
    float base_azimuth_ = 0.f;     // of the light at init
    int strata_ = 0;               // of the transfer in the storage buffers (0: none yet)
    double seconds_ = 0.0;
    std::string error_;
    // GL
    GLuint program_ = 0, vao_ = 0, vbo_ = 0, ibo_ = 0, ssbo_[2] = {0, 0};
    skgl::Target target_;
};
