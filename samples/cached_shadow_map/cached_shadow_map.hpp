// samples/cached_shadow_map/cached_shadow_map.hpp - a shadow map that leaves out the work that did not
// change between frames (shadows over time): what the sample shows and the report measures.
//
// A sun's stable (texel-snapped) light frustum follows the camera (light_frustum.hpp with a depth
// range fixed in the world), and every frame shadow_cache.hpp says what the map still needs: nothing
// (Keep), the footprints of casters that moved (Update), a scroll by whole texels plus the exposed
// border (Scroll: glCopyImageSubData into the other texture of a pair), or everything (Render, with
// the reason). Spot and area lights get the plain frustum around the scene (sk::fit_light): it does not
// follow the camera, so the map is kept until the light or a caster moves. Point lights need a cube map
// (samples/shadow_map): init fails.
//
// A sample folder is what a user copies (the template is samples/shadow_volumes/):
//   cached_shadow_map.hpp  the settings (named once in bind_settings()) and the class
//   cached_shadow_map.cpp  the technique top to bottom: init, update (CPU: fit + plan), render (the
//                          caster pass over the plan's rectangles, then V at the G-buffer's points)
//   main.cpp               the calls
// It uses shadowkit/light_frustum.hpp, shadowkit/shadow_cache.hpp, glsl/shadow_cache.glsl (the
// translation-invariant caster pass), glsl/shadow_map.glsl (the lookup) and the app shell.
// shadowkit-report wraps this class (samples/report/techniques/cached_shadow_map.cpp) and compares the
// kept map with a full re-render texel for texel.
#pragma once

#include <shadowkit/light_frustum.hpp>
#include <shadowkit/shadow_cache.hpp>

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "app.hpp"
#include "gbuffer.hpp"
#include "gl.hpp"
#include "params.hpp"

struct CachedShadowMapSettings {
    /// Directional lights: light_frustum's stable fit (texel-snapped, rotation-invariant: the map moves
    /// by whole texels, so it can be kept and scrolled) or its tight fit (follows the camera's every
    /// move: nothing to keep, every frame a full render).
    enum class Fit { Stable, Tight };
    Fit fit = Fit::Stable;
    bool cache = true;  ///< keep what did not change (shadow_cache_plan); off: render the whole map every frame
    /// The caster pass. invariant: glsl/shadow_cache.glsl writes each texel's depth from its global
    /// texel, so a scrolled map equals a re-render bit for bit; plain: hardware depth with a polygon
    /// offset (cheaper; after a scroll some depths differ from a re-render by a few float steps). Maps
    /// that cannot scroll (perspective, tight) always use the plain pass.
    enum class Pass { Invariant, Plain };
    Pass pass = Pass::Invariant;
    /// Stable fit: the depth range from the scene box (light_frustum's stable_world_depth). Off: from the
    /// receivers the camera sees, which moves with the camera: every move re-renders the whole map.
    bool world_depth = true;
    /// Draw only the casters light_frustum keeps for this camera (the kept set is part of the map's
    /// settings: a caster crossing the culling boundary re-renders the whole map). Off: every caster.
    bool culling = false;
    int size = 2048;  ///< texels per side (<= 2048: the invariant pass draws into a 4096^2 guard viewport)
    /// auto: the caster passes store true depths and V uses glsl/shadow_map.glsl's automatic bias
    /// (sk_shadow_map_visibility_auto, no constant); offset: a slope-scaled offset (2, 2) in the caster
    /// passes and the hardware 2x2 compare, the classic hand-picked bias.
    enum class Bias { Auto, Offset };
    Bias bias = Bias::Auto;
};

/// The settings by name, once: --param, the panel's widgets and the report's sweeps use these.
inline void bind_settings(app::Params& p, CachedShadowMapSettings& s) {
    using F = CachedShadowMapSettings::Fit;
    using P = CachedShadowMapSettings::Pass;
    p.choice("fit", &s.fit, {{"stable", F::Stable}, {"tight", F::Tight}});
    p.toggle("cache", &s.cache);
    p.choice("pass", &s.pass, {{"invariant", P::Invariant}, {"plain", P::Plain}});
    p.toggle("world_depth", &s.world_depth);
    p.toggle("culling", &s.culling);
    p.choice("size", &s.size, {{"512", 512}, {"1024", 1024}, {"2048", 2048}});
    p.choice("bias", &s.bias, {{"auto", CachedShadowMapSettings::Bias::Auto}, {"offset", CachedShadowMapSettings::Bias::Offset}});
}

class CachedShadowMap {
public:
    CachedShadowMap() = default;
    CachedShadowMap(const CachedShadowMap&) = delete;
    CachedShadowMap& operator=(const CachedShadowMap&) = delete;
    ~CachedShadowMap() { release(); }

    /// The programs and the V target; the map itself is made by the first render (and on a size change).
    bool init(const app::View& v, std::string& why);
    /// CPU, every frame: the light's matrix (the fit to v's camera), the casters' bounds, the plan.
    void update(const app::View& v, const CachedShadowMapSettings& s);
    /// GPU, every frame: render_map(), then render_visibility().
    void render(const app::View& v, const CachedShadowMapSettings& s) {
        render_map(v, s);
        render_visibility(v, s);
    }
    /// The plan applied to the map: a scroll copy, then the caster pass over the plan's rectangles.
    /// Called again without update() it re-renders the same rectangles (the scroll is not repeated).
    void render_map(const app::View& v, const CachedShadowMapSettings& s);
    /// V at the G-buffer's points: the map's compare with the hardware 2x2 filter.
    void render_visibility(const app::View& v, const CachedShadowMapSettings& s);
    /// R32F V at the G-buffer's pixels.
    GLuint visibility() const { return pass_.texture(); }
    /// The first failure of update() (a header's status), "" while all is well.
    const std::string& error() const { return error_; }

    /// Debug view: the map's depths.
    app::DebugImage debug_map() const { return {tex_[cur_], app::DebugImage::Show::Depth}; }
    /// What update() planned for this frame (action, reason, rectangles, texels re-rendered).
    const shadowkit::ShadowCachePlan& plan() const { return plan_; }
    GLuint map() const { return tex_[cur_]; }  ///< the depth texture that holds the map
    int size() const { return size_; }
    const glm::mat4& light_view_proj() const { return light_vp_f_; }  ///< the map's this frame (float)
    std::size_t casters_drawn() const;          ///< casters the caster pass may draw this frame (culling)
    const std::vector<std::uint8_t>& drawn() const { return drawn_; }  ///< per caster mesh: 1 drawn, 0 culled

private:
    void make_map(int size);
    void release();
    std::string error_;
    // per caster mesh: its index, its bounds now and when the map was last rendered, drawn or culled
    std::vector<std::size_t> mesh_;
    std::vector<shadowkit::ShadowCacheCaster> casters_;
    std::vector<float> boxes_;        // the same bounds for light_frustum (6 floats each)
    std::vector<std::uint32_t> kept_;
    std::vector<std::uint8_t> drawn_;
    // this frame
    bool ortho_ = true, invariant_ = false;
    glm::dmat4 light_vp_{1.0};        // what the plan compares (double)
    glm::mat4 light_vp_f_{1.f};       // its float copy: the plain caster pass and the lookup
    glm::mat4 light_global_{1.f};     // the invariant pass: world -> (global texel x, y, window depth)
    glm::ivec2 anchor_{0, 0};         // the global texel of the map's texel (0, 0)
    shadowkit::ShadowCacheMapState previous_, current_;
    shadowkit::ShadowCachePlan plan_;
    std::vector<shadowkit::ShadowCacheRect> rects_;
    // GL
    GLuint tex_[2] = {0, 0}, fbo_[2] = {0, 0};
    int cur_ = 0, size_ = 0;
    bool scrolled_ = false;  // this frame's scroll is done
    GLuint plain_prog_ = 0, invariant_prog_ = 0, vis_prog_ = 0;
    app::VisibilityPass pass_;
};
