// samples/virtual_shadow_maps/virtual_shadow_maps.hpp - virtual shadow maps for the sun: clipmap levels of
// a 16k virtual map each, cut into pages; only the pages the visible pixels request are rendered into a
// physical pool (one depth atlas) and kept across frames until a caster moves, the window scrolls past
// them or a more recently requested page needs their slot (virtual_shadow_map.hpp,
// glsl/virtual_shadow_map.glsl). What the sample shows and the report measures.
//
// A sample folder is what a user copies (the same shape in every samples/<technique>/):
//   virtual_shadow_maps.hpp  the settings (what the panel edits, named once in bind_settings()) and the class
//   virtual_shadow_maps.cpp  the technique, top to bottom in the order it runs: init (once per scene),
//                            update (CPU, every frame), render (the GPU passes, each with its GL state)
//   main.cpp                 the calls: the app shell (samples/app) does the window, the camera G-buffer,
//                            the panel, the timing and the picture
// It uses only shadowkit/virtual_shadow_map.hpp, glsl/virtual_shadow_map.glsl and the app shell's
// G-buffer (app/gbuffer.hpp) and GL helpers (app/gl.hpp). shadowkit-report wraps this same class
// (samples/report/techniques/virtual_shadow_maps.cpp).
#pragma once

#include <shadowkit/virtual_shadow_map.hpp>

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "app.hpp"
#include "gbuffer.hpp"
#include "gl.hpp"
#include "params.hpp"

struct VirtualShadowMapSettings {
    int page_texels = 128;        ///< side of a page in texels
    int virtual_texels = 16384;   ///< side of each level's virtual map in texels
    /// clipmap levels; the coarsest covers 2^k times the scene's diagonal, k >= 1 the least that gives its
    /// texels a quarter of a pixel at that distance (the finest level is the coarsest's / 2^(levels - 1))
    int levels = 16;
    int pool_pages = 1024;        ///< physical pages in the pool (1024 pages of 128^2 float32: 64 MiB)
    /// added to log2(pixel footprint / level 0's texel) before rounding down: 0 picks the coarsest level
    /// whose texels are no larger than the pixel's footprint (distance x pixel angle). -2 (default):
    /// texels up to a quarter of it: a sun's texel lies stretched on a receiver by 1 / cos of the light's
    /// angle, so at 0 most pixels see texels larger than themselves (report, outdoor --quick: RMSE
    /// 0.036, undersampled 96% at 0; 0.026, 18% at -1; 0.023, 0% at -2, 240 pages)
    float lod_bias = -2.f;
    int pcf_radius = 0;           ///< 0: the 2x2 bilinear compare; r: a (2r+1)-texel box, across pages
};

/// The settings by name, once: --param, the panel's widgets and the report's sweeps use these.
inline void bind_settings(app::Params& p, VirtualShadowMapSettings& s) {
    p.choice("page_texels", &s.page_texels, {{"32", 32}, {"64", 64}, {"128", 128}, {"256", 256}});
    p.choice("virtual_texels", &s.virtual_texels, {{"4096", 4096}, {"8192", 8192}, {"16384", 16384}});
    p.number("levels", &s.levels, 1, 16);
    p.choice("pool_pages", &s.pool_pages, {{"16", 16}, {"64", 64}, {"128", 128}, {"256", 256}, {"512", 512}, {"1024", 1024}, {"2048", 2048}});
    p.number("lod_bias", &s.lod_bias, -2.0, 4.0);
    p.number("pcf_radius", &s.pcf_radius, 0, 3);
}

/// What the last frames did (the panel's and the report's counters).
struct VirtualShadowMapStats {
    std::size_t requested = 0;   ///< distinct pages the visible pixels requested (last frame)
    std::size_t rendered = 0;    ///< pages rendered last frame (newly allocated + stale re-rendered)
    std::size_t evicted = 0;     ///< least recently requested pages evicted last frame
    std::size_t kept = 0;        ///< requested pages already resident and current (not rendered)
    std::size_t fallback = 0;    ///< requests that fell back to a coarser level (pool too small)
    std::size_t resident = 0;    ///< pages in the pool after the last frame
    std::size_t first_frame_rendered = 0;  ///< pages the first frame after init rendered (a cold pool)
    std::size_t triangles_drawn = 0;       ///< triangles drawn into pages last frame
    std::size_t first_frame_triangles = 0; ///< triangles the first frame after init drew
    std::size_t frames = 0;      ///< frames rendered since init
};

class VirtualShadowMaps {
public:
    VirtualShadowMaps() = default;
    VirtualShadowMaps(const VirtualShadowMaps&) = delete;
    VirtualShadowMaps& operator=(const VirtualShadowMaps&) = delete;
    ~VirtualShadowMaps() { release(); }

    /// The casters' bounds, the programs, the V target. The pool is made by the first render.
    bool init(const app::View& v, std::string& why);
    /// CPU, every frame: the light and the camera of this frame (the plan needs the GPU's requests:
    /// it runs inside render()).
    void update(const app::View& v, const VirtualShadowMapSettings& s);
    /// Every frame: 1 mark (GPU) and read the request bitmask back, 2 plan (CPU, vsm_plan), 3 render
    /// the listed pages into the pool, 4 V at the G-buffer's points through the page table.
    void render(const app::View& v, const VirtualShadowMapSettings& s);
    /// R32F V at the G-buffer's pixels.
    GLuint visibility() const { return pass_.texture(); }
    /// Why there are no shadows ("" while all is well): the light is not the sun. V is 1 meanwhile.
    const std::string& error() const { return error_; }

    /// Debug views: the physical pool's depths, and each pixel's level and page borders (RGBA overlay).
    app::DebugImage debug_pool() const { return {atlas_, app::DebugImage::Show::Depth}; }
    app::DebugImage debug_pages();

    const VirtualShadowMapStats& stats() const { return stats_; }
    const shadowkit::VsmState& state() const { return state_; }
    std::int64_t pool_bytes() const { return std::int64_t(state_.layout.pool_pages) * state_.layout.page_texels * state_.layout.page_texels * 4; }
    /// World size of one G-buffer pixel per unit of distance (2 tan(fovy / 2) / height).
    float pixel_angle() const { return pixel_angle_; }

private:
    bool make_pool(const VirtualShadowMapSettings& s);
    void mark(const app::View& v, const VirtualShadowMapSettings& s);
    void render_pages(const app::View& v, std::size_t count);
    void upload_block();
    void release();

    std::string error_;
    shadowkit::VsmState state_;
    shadowkit::VsmFrame frame_;
    VirtualShadowMapSettings made_{};            // the settings the pool was made with
    bool have_pool_ = false;
    float diag_ = 1.f, pixel_angle_ = 0.f;
    glm::dvec3 anchor_{0.0};
    glm::vec3 eye_{0.f};
    std::vector<float> caster_boxes_;            // 6 floats per caster mesh
    std::vector<std::size_t> caster_mesh_;       // the mesh of each box
    std::vector<shadowkit::VsmPageRender> pages_;
    std::vector<shadowkit::VsmPageRequest> requests_;
    std::vector<std::uint32_t> mask_, block_, first_, counts_, indices_;
    VirtualShadowMapStats stats_;
    GLuint atlas_ = 0, atlas_fbo_ = 0, data_ssbo_ = 0, mask_ssbo_ = 0, empty_vao_ = 0;
    GLuint depth_prog_ = 0, mark_prog_ = 0, vis_prog_ = 0, debug_prog_ = 0;
    app::VisibilityPass pass_;
    skgl::Target debug_;                         // RGBA8: sk_vsm_debug_color over the picture
    GLuint debug_positions_ = 0;                 // the last frame's G-buffer positions
    VirtualShadowMapSettings last_settings_{};
};
