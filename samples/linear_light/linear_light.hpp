// samples/linear_light/linear_light.hpp - soft shadows from a line-segment light (Heidrich, Brabec &
// Seidel 2000) and, beside them, N shadow maps sampled along the line: what the sample shows and the
// report measures.
//
// A sample folder is what a user copies (the same shape in every samples/<technique>/):
//   linear_light.hpp  the settings (what the panel edits, named once in bind_settings()) and the class
//   linear_light.cpp  the technique, top to bottom in the order it runs: init (once per scene),
//                     update (CPU, every frame), render (the passes, each with its GL state)
//   main.cpp          the calls: the app shell (samples/app) does the window, the camera G-buffer,
//                     the panel, the timing and the picture
// It uses only shadowkit/linear_light.hpp, glsl/linear_light.glsl and the app shell's scene
// (sk::fit_box_depth), G-buffer and GL helpers. shadowkit-report wraps this same class
// (samples/report/techniques/linear_light.cpp) as linear_light (method=heidrich) and sampled_line
// (method=sampled).
#pragma once

#include <shadowkit/linear_light.hpp>

#include <glm/glm.hpp>

#include <string>
#include <vector>

#include "app.hpp"
#include "gbuffer.hpp"
#include "gl.hpp"
#include "params.hpp"

struct LinearLightSettings {
    /// heidrich: a shadow map at each end of every sub-light and, from the other end's depth
    /// discontinuities, a "skin" that says how much of the line each point sees (the paper);
    /// sampled: `samples` shadow maps at the centers of equal pieces of the line, 2x2 PCF each,
    /// averaged (the brute-force baseline).
    enum class Method { Heidrich, Sampled };
    Method method = Method::Heidrich;
    int size = 512;      ///< texels per side of every shadow map and visibility map
    /// heidrich: the line split into this many sub-lights (segments + 1 maps). 1 is the paper's
    /// method; more fixes thin occluders that hide the middle of the line from points that see both ends.
    int segments = 1;
    /// heidrich: where the skin is built. cpu: from the read-back depth maps, only the discontinuity
    /// cells (linear_light_build_skin); gpu: every cell drawn, the vertex shader finds the skin
    /// (sk_linear_light_skin_vertex), no read-back.
    enum class Skin { Cpu, Gpu };
    Skin skin = Skin::Cpu;
    float threshold = 0.05f;  ///< heidrich: relative depth jump that makes a discontinuity
    int samples = 4;          ///< sampled: shadow maps along the line
    /// method=sampled. auto: true depths in every map and glsl/shadow_map.glsl's automatic bias (its 2x2
    /// lookup per map); offset: a slope-scaled polygon offset (2, 2) in the depth passes.
    /// method=heidrich takes bias=offset: its skins are built from the offset depths, and the automatic
    /// bias at its nearest-texel end tests (sk_auto_filtered_bias, the larger of the two ends') measured
    /// worse on the `linear` scene (RMSE 0.0515 against 0.0450; bias=heidrich_auto keeps it to compare).
    enum class Bias { Auto, Offset, HeidrichAuto };
    Bias bias = Bias::Auto;
};

/// The settings by name, once: --param, the panel's widgets and the report's sweeps use these.
inline void bind_settings(app::Params& p, LinearLightSettings& s) {
    using M = LinearLightSettings::Method;
    using K = LinearLightSettings::Skin;
    p.choice("method", &s.method, {{"heidrich", M::Heidrich}, {"sampled", M::Sampled}});
    p.choice("size", &s.size, {{"256", 256}, {"512", 512}, {"1024", 1024}, {"2048", 2048}});
    p.number("segments", &s.segments, 1, 4);
    p.choice("skin", &s.skin, {{"cpu", K::Cpu}, {"gpu", K::Gpu}});
    p.number("threshold", &s.threshold, 0.0, 1.0);
    p.number("samples", &s.samples, 1, 16);
    p.choice("bias", &s.bias,
             {{"auto", LinearLightSettings::Bias::Auto}, {"offset", LinearLightSettings::Bias::Offset}, {"heidrich_auto", LinearLightSettings::Bias::HeidrichAuto}});
}

class LinearLight {
public:
    static constexpr int kMaxSegments = 4, kMaxSamples = 16;

    LinearLight() = default;
    LinearLight(const LinearLight&) = delete;
    LinearLight& operator=(const LinearLight&) = delete;
    ~LinearLight() { release(); }

    /// The programs and the V target. A linear light, or any light with a position (a point there:
    /// the hard shadow); a directional light has none (false).
    bool init(const app::View& v, std::string& why);
    /// CPU, every frame: the segment, its sub-lights, a perspective frustum from every map's point.
    void update(const app::View& v, const LinearLightSettings& s);
    /// Every frame: the three steps below in order (what the report times as one).
    void render(const app::View& v, const LinearLightSettings& s) {
        render_depth_maps(v, s);
        build_skins(s);
        render_visibility(v, s);
    }
    /// GPU: the depth map from each end of each sub-light (sampled: from each sample).
    void render_depth_maps(const app::View& v, const LinearLightSettings& s);
    /// CPU (heidrich, skin=cpu): each depth map read back, unprojected, its discontinuities triangulated.
    void build_skins(const LinearLightSettings& s);
    /// GPU: the skins into the visibility maps (heidrich), then V at the G-buffer's points.
    void render_visibility(const app::View& v, const LinearLightSettings& s);
    /// R32F V at the G-buffer's pixels.
    GLuint visibility() const { return pass_.texture(); }
    /// The first failure of update() or build_skins() (a header's status), "" while all is well.
    const std::string& error() const { return error_; }

    // Debug views: the depth map of the line's first end (sampled: of the first sample); that end's
    // visibility map (heidrich; red: the skin's value, 1 where no skin covers).
    app::DebugImage debug_depth() const {
        return {maps_.empty() ? array_view_ : maps_[0].depth, app::DebugImage::Show::Depth};
    }
    app::DebugImage debug_skin() const {
        return {vmaps_.empty() ? 0u : vmaps_[0].color[0], app::DebugImage::Show::Value};
    }

    // What the class found (the report counts from these).
    bool point() const { return seg_.is_point; }             ///< a zero-length line: one map, its depth test
    int sub_lights() const { return k_; }                    ///< heidrich: segments (1 for a point)
    std::size_t map_count() const { return views_.size(); }  ///< depth maps (or samples) this frame
    std::size_t visibility_map_count() const { return vmaps_.size(); }
    std::size_t skin_vertices() const;                       ///< skin=cpu: the vertices of all skins
    int map_size() const { return size_; }

private:
    struct EndpointView {
        glm::vec3 pos{0.f};
        glm::mat4 vp{1.f}, inv_vp{1.f};
        float znear = 0.f, zfar = 0.f;
    };
    void make_maps(const LinearLightSettings& s);
    void draw_skin(std::size_t from, std::size_t into, const LinearLightSettings& s);
    void release();
    shadowkit::LinearLightSegment seg_;
    int k_ = 1;
    std::vector<EndpointView> views_;
    std::vector<std::vector<shadowkit::LinearLightSkinVertex>> skins_;  // skin=cpu: per depth map
    std::vector<float> depth_, distance_;
    std::vector<glm::vec3> position_;
    std::string error_;
    // GL
    int size_ = 0;
    LinearLightSettings::Method made_method_ = LinearLightSettings::Method::Heidrich;
    std::size_t made_points_ = 0;             // the maps were made for this many points
    std::vector<skgl::Target> maps_, vmaps_;  // heidrich: depth maps, RGBA32F visibility maps
    GLuint array_ = 0, array_fbo_ = 0;        // sampled: a depth-compare array, one layer per sample
    GLuint array_view_ = 0;                   // its layer 0 as a 2D texture (the debug view)
    GLuint empty_vao_ = 0, skin_vao_ = 0, skin_vbo_ = 0;
    GLuint depth_prog_ = 0, skin_gpu_prog_ = 0, skin_cpu_prog_ = 0, vis_prog_ = 0, sampled_prog_ = 0;
    app::VisibilityPass pass_;
};
