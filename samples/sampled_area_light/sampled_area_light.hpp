// samples/sampled_area_light/sampled_area_light.hpp - an area light as N spot lights: N shadow maps from
// Poisson points on the emitter, each looked up with the hardware 2x2 compare, averaged (Apelles'
// SampledAreaLight; Heckbert & Herf 1997 accumulate the same way). Slow and simple: it converges to the
// area light's true shadow as N grows (the report's "sampled_area"), the baseline of PCSS, smoothies and
// penumbra wedges.
//
// A sample folder is what a user copies (the same shape in every samples/<technique>/):
//   sampled_area_light.hpp  the settings (what the panel edits, named once in bind_settings()) and the class
//   sampled_area_light.cpp  the technique, top to bottom in the order it runs: init (once per scene),
//                           update (CPU, every frame), render (the GPU passes, each with its GL state)
//   main.cpp                the calls: the app shell (samples/app) does the window, the camera
//                           G-buffer, the panel, the timing and the picture
// It uses shadowkit/poisson_disk.hpp (the points on the emitter), glsl/shadow_map.glsl and the app
// shell's scene (sk::fit_light), G-buffer (app/gbuffer.hpp) and GL helpers (app/gl.hpp). shadowkit-report
// wraps this same class (samples/report/techniques/soft_shadows.cpp, "sampled_area").
// Spot, rect, disk and sphere lights (a spot light has no area: N equal maps).
#pragma once

#include <glm/glm.hpp>

#include <string>
#include <vector>

#include "app.hpp"
#include "gbuffer.hpp"
#include "gl.hpp"
#include "params.hpp"

struct SampledAreaLightSettings {
    int maps = 16;    ///< N: shadow maps, one per point on the emitter (the first N of a progressive Poisson set)
    int size = 1024;  ///< texels per side of each map
    bool fit_casters = true;  ///< each map's frustum fits the casters' bounds (off: the scene's frustum, fit_light)
};

/// The settings by name, once: --param, the panel's widgets and the report's sweeps use these.
inline void bind_settings(app::Params& p, SampledAreaLightSettings& s) {
    p.number("maps", &s.maps, 1, 256);
    p.choice("size", &s.size, {{"512", 512}, {"1024", 1024}, {"2048", 2048}});
    p.toggle("fit_casters", &s.fit_casters);
}

class SampledAreaLight {
public:
    static constexpr int kMaxMaps = 256;  ///< points in the Poisson set
    static constexpr int kBatch = 16;     ///< at most this many maps rendered into the depth array before each V pass

    SampledAreaLight() = default;
    SampledAreaLight(const SampledAreaLight&) = delete;
    SampledAreaLight& operator=(const SampledAreaLight&) = delete;
    ~SampledAreaLight() { release(); }

    /// The Poisson points on the emitter's shape (once), the programs, the sampler, the V target.
    bool init(const app::View& v, std::string& why);
    /// CPU, every frame: the light's frustum, the N points on the emitter and their maps' view-projections.
    void update(const app::View& v, const SampledAreaLightSettings& s);
    /// GPU, every frame: 16 maps at a time into a depth array, then their lookups added into V.
    void render(const app::View& v, const SampledAreaLightSettings& s);
    /// R32F V at the G-buffer's pixels.
    GLuint visibility() const { return pass_.texture(); }
    /// Why update() cannot work for this light; "" while all is well.
    const std::string& error() const { return error_; }

    /// Debug view: the first map's depths.
    app::DebugImage debug_first_map() const { return {first_map_, app::DebugImage::Show::Depth}; }
    int maps() const { return static_cast<int>(vps_.size()); }  ///< N of the last update()
    int size() const { return size_; }                           ///< of each map as rendered last
    int layers() const { return layers_; }                       ///< of the depth array: min(N, kBatch)

private:
    void make_maps(int size, int layers);
    static glm::mat4 caster_fit(glm::vec3 lo, glm::vec3 hi, glm::vec3 slo, glm::vec3 shi, const glm::mat4& view,
                                const glm::mat4& fallback);
    void release();
    std::string error_;
    glm::vec2 points_[kMaxMaps];         // the emitter's Poisson points, in [-1, 1]^2 (square) or the unit disk
    std::vector<glm::vec3> positions_;   // this frame: the N points on the emitter
    std::vector<glm::mat4> vps_;         // and their maps' view-projections
    // GL
    int size_ = 0, layers_ = 0;  // of the depth array: min(N, kBatch) layers
    GLuint maps_ = 0, first_map_ = 0, fbo_[kBatch] = {}, sampler_ = 0;
    GLuint depth_prog_ = 0, vis_prog_ = 0;
    app::VisibilityPass pass_;
};
