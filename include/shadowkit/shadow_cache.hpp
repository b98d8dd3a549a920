// shadowkit/shadow_cache.hpp - cached shadow maps: per map (cascade, cube face, spot map) and frame, what must be re-rendered: nothing, the regions moving casters dirtied, a scroll of a texel-snapped cascade plus its exposed border, or the whole map.
//
// Usage (per map and frame; `prev` is the map's state the last time it was rendered):
//   shadowkit::ShadowCacheMapState cur;
//   cur.view_proj = light_view_proj;          // glm::dmat4 world -> clip, the matrix the map is drawn with (double!)
//   cur.width = 2048; cur.height = 2048;      // texels (required)
//   cur.settings = my_settings_hash;          // bias, format, culling, caster set...: any change renders all
//   // or, from any header's float or double matrix: cur = shadowkit::shadow_cache_map_state(m, 2048, 2048, hash);
//   shadowkit::ShadowCacheRect rects[16];
//   const shadowkit::ShadowCachePlan plan = shadowkit::shadow_cache_plan(prev, cur, casters, caster_count, rects, 16);
//   if (plan.status != shadowkit::Status::Ok) { /* bad input: render everything, keep prev.has_content false */ }
//   if (plan.action == shadowkit::ShadowCacheAction::Scroll)   // into the other texture of a ping-pong pair
//       glCopyImageSubData(prev_tex, GL_TEXTURE_2D, 0, plan.copy.src_x, plan.copy.src_y, 0,
//                          cur_tex, GL_TEXTURE_2D, 0, plan.copy.dst_x, plan.copy.dst_y, 0,
//                          plan.copy.width, plan.copy.height, 1);
//   // Keep and Update work in place (cur_tex = prev_tex); Render into either texture.
//   glBindFramebuffer(GL_FRAMEBUFFER, fbo_of(cur_tex)); glViewport(0, 0, 2048, 2048);
//   glEnable(GL_SCISSOR_TEST); glDepthMask(GL_TRUE);
//   for (std::size_t r = 0; r < plan.count; ++r) {      // Keep: none; Render: one, the whole map
//       glScissor(rects[r].x, rects[r].y, rects[r].width, rects[r].height);
//       glClear(GL_DEPTH_BUFFER_BIT);                    // the scissor bounds the clear as well
//       draw_casters();                                  // cull each with shadow_cache_footprint()
//   }
//   glDisable(GL_SCISSOR_TEST);
//   cur.has_content = true; prev = cur;
//
// Conventions:
//   Matrices: glm::dmat4 (double), column-major, world -> clip: the light view-projection the map is
//   rendered with, viewport (0, 0, width, height). Texel (i, j) covers window x in [i, i + 1), y in
//   [j, j + 1); a texel is drawn when its center is covered. Any clip depth convention (GL, zero to
//   one, reversed): depth rows are only compared. Lights enter only through their matrices.
//   Boxes (caster bounds): 6 floats, min x, y, z then max x, y, z, world units. A box with a min
//   greater than its max is empty: the caster is not there (appeared / removed this frame).
//   Rectangles: texels, x, y, width, height as glScissor takes them, inside [0, width) x [0, height).
//   Buffers: counted in elements of the pointer's type; each function says what it needs.
//   Precision: whole-texel motion is certified in double; a float matrix carries 2^-24 relative
//   round-off, which at N texels from the world origin is N * 2^-24 texels (0.38 texel at 1e5
//   world units with 1/64-unit texels): build stable fits in double (see shadow_cache_plan).
//   Per-frame functions never allocate, except shadow_cache_plan when a caster moved (the sweep's
//   scratch, O(moved casters)); Keep, Render and a scroll with no moved caster allocate nothing.
//
// Based on:
//   A. Moschig, "Apelles" master's thesis, TU Graz, sec. 4.1.2 (a shadow map is invalidated only
//     when the map, its light or the geometry inside the light's view volume changes; positional
//     invariance of the vertex shader output across passes).
//   M. Valient 2008, "Stable Rendering of Cascaded Shadow Maps" (ShaderX6): texel-snapped fits
//     move by whole texels.
//   C. Tanner, C. Migdal, M. Jones 1998, "The Clipmap: A Virtual Mipmap" (SIGGRAPH): on a roaming
//     window only the exposed L-shaped border is loaded.
//
// MIT License. Copyright (c) shadowkit contributors.
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace shadowkit {

#ifndef SHADOWKIT_STATUS_DEFINED
#define SHADOWKIT_STATUS_DEFINED
/// shadowkit's release, major * 10000 + minor * 100 + patch (0.1.0), the same in every header. Whichever
/// header comes first defines this block; a header of another release included with it stops the
/// build (the #error after the block) instead of mixing two definitions silently.
#define SHADOWKIT_VERSION 100
/// Outcome of a shadowkit call: one set for every header. `Ok` is the only success. A result that no
/// call has filled says `NotRun`. What a successful call found (no blocker, a fallback, nothing
/// visible, an edge to skip) is a field of its result, never a status.
enum class Status : std::uint8_t {
    NotRun,            ///< a default-constructed result: no call has filled it
    Ok,                ///< success: every output is finite and means what its comment says
    InvalidArgument,   ///< a value outside its documented range (null pointer with a count, size 0, near >= far, ...)
    NonFinite,         ///< NaN or Inf in an input
    IndexOutOfRange,   ///< a mesh index >= the vertex count
    InvalidLight,      ///< light position NaN/Inf, w < 0, or (0, 0, 0, 0)
    BufferTooSmall,    ///< an output buffer is too small; the result's `needed` says how many elements
    Overflow,          ///< finite input whose result is not representable (beyond float, depth steps collapse)
    LightInsideVolume  ///< a point light inside the receivers' bounds: no single frustum holds them (use a cube map)
};
/// The enumerator's name, for logs and test messages.
inline const char* status_name(Status s) {
    switch (s) {
    case Status::NotRun: return "NotRun";
    case Status::Ok: return "Ok";
    case Status::InvalidArgument: return "InvalidArgument";
    case Status::NonFinite: return "NonFinite";
    case Status::IndexOutOfRange: return "IndexOutOfRange";
    case Status::InvalidLight: return "InvalidLight";
    case Status::BufferTooSmall: return "BufferTooSmall";
    case Status::Overflow: return "Overflow";
    case Status::LightInsideVolume: return "LightInsideVolume";
    }
    return "?";
}
#endif
#if !defined(SHADOWKIT_VERSION) || SHADOWKIT_VERSION != 100
#error "shadowkit: headers of two releases included together (this one is 0.1.0, SHADOWKIT_VERSION 100); vendor the headers of one release"
#endif

/// Largest map side shadow_cache_plan accepts, in texels (beyond any GL_MAX_TEXTURE_SIZE).
constexpr int kShadowCacheMaxSize = 65536;
/// The largest departure from a whole-texel translation, in texels, that a scroll may carry: 1/256
/// of a texel, the rasterizers' 8-bit sub-texel grid. When the matrices' own round-off could exceed
/// it, whole-texel motion cannot be certified and the map is re-rendered (PrecisionTooLow).
constexpr double kShadowCacheMaxResidualTexels = 1.0 / 256.0;

/// One map's state in one frame: what its content depends on. Keep the state a map was last rendered
/// with (has_content = true) and pass it as `previous` the next frame.
struct ShadowCacheMapState {
    glm::dmat4 view_proj = glm::dmat4(0.0);  ///< world -> clip, the matrix the map is rendered with (required; the zero matrix is rejected)
    int width = 0;                           ///< texels (required) [Limit: 1 .. kShadowCacheMaxSize]
    int height = 0;                          ///< texels (required) [Limit: 1 .. kShadowCacheMaxSize]
    /// Everything else that affects the map's content, as one value compared for equality: depth
    /// bias, polygon offset, depth format, culling, the set of casters drawn, LOD... (a hash or a
    /// counter the caller bumps). Any change renders the whole map.
    std::uint64_t settings = 0;
    /// `previous` only: the map holds content rendered with this state. False (the default) for the
    /// first frame or after the texture was lost: the whole map is rendered.
    bool has_content = false;
    /// The matrices were computed or stored in float (their entries carry float round-off, 2^-24
    /// relative, instead of double's 2^-53): whole-texel motion is then certified only within about
    /// 2^11 texels of the world origin, beyond it the plan says PrecisionTooLow.
    bool float_matrices = false;
};

/// A map's state from the matrix another header returns, in double (stable fits: light_frustum.hpp's
/// texel_anchor path, cascades.hpp in double) or in float (LightFrustumResult::view_proj,
/// CascadeResult, a glm::mat4 of your own): the float overload widens it exactly and sets
/// float_matrices, so both are accepted alike and the plan certifies whole-texel motion with the
/// round-off the matrix really carries. has_content stays false (set it once the map is rendered).
inline ShadowCacheMapState shadow_cache_map_state(const glm::dmat4& view_proj, int width, int height, std::uint64_t settings = 0) {
    ShadowCacheMapState s;
    s.view_proj = view_proj;
    s.width = width;
    s.height = height;
    s.settings = settings;
    return s;
}
/// The same from a float matrix (float_matrices = true).
inline ShadowCacheMapState shadow_cache_map_state(const glm::mat4& view_proj, int width, int height, std::uint64_t settings = 0) {
    ShadowCacheMapState s = shadow_cache_map_state(glm::dmat4(view_proj), width, height, settings);
    s.float_matrices = true;
    return s;
}

/// A caster's world bounds this frame and last frame (6 floats each: min x, y, z, max x, y, z). A
/// caster that did not move has bounds == previous_bounds and costs one comparison; a box with a
/// min greater than its max is empty (the caster is absent in that frame).
struct ShadowCacheCaster {
    float bounds[6] = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f};           ///< this frame
    float previous_bounds[6] = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f};  ///< last frame (when the map was last rendered)
};

/// A texel rectangle, as glScissor takes it.
struct ShadowCacheRect {
    int x = 0, y = 0, width = 0, height = 0;
};

/// A region copy, as glCopyImageSubData takes it: source texels [src_x, src_x + width) x [src_y,
/// src_y + height) of the previous content go to [dst_x, dst_x + width) x [dst_y, dst_y + height).
struct ShadowCacheCopy {
    int src_x = 0, src_y = 0, dst_x = 0, dst_y = 0, width = 0, height = 0;
};

/// What to do with a map this frame.
enum class ShadowCacheAction : std::uint8_t {
    Keep,    ///< nothing: the map is still right (count 0)
    Update,  ///< re-render the rectangles in place (moving casters); the rest is still right
    Scroll,  ///< copy the previous content by (offset_x, offset_y) texels (`copy`), then re-render the rectangles
    Render   ///< re-render the whole map (one rectangle: the map); `reason` says why
};

/// Why a map is rendered whole (ShadowCacheAction::Render), or None.
enum class ShadowCacheReason : std::uint8_t {
    None,             ///< Keep, Update or Scroll
    NoContent,        ///< previous.has_content is false (first frame, lost texture)
    SizeChanged,      ///< width or height differ
    SettingsChanged,  ///< `settings` differ
    ProjectionChanged,///< not a translation of last frame's map: the light turned (even by 1e-7 rad), the fit was resized, a perspective map moved
    DepthMoved,       ///< a translation along the light's depth axis: every stored depth would need an offset (no copy applies one; see shadow_cache_plan)
    SubTexelMotion,   ///< a translation in x/y by a fraction of a texel: the texel grid moved
    MovedOffMap,      ///< a whole-texel translation of at least the map's width or height: nothing to copy
    PrecisionTooLow,  ///< the matrices' round-off (far from the origin, float_matrices) exceeds kShadowCacheMaxResidualTexels: whole texels cannot be certified
    DirtyCoversMap    ///< the rectangles to re-render would cover at least the whole map's area
};

/// The plan for one map (shadow_cache_plan).
struct ShadowCachePlan {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    ShadowCacheAction action = ShadowCacheAction::Render;
    ShadowCacheReason reason = ShadowCacheReason::None;
    /// Scroll: the same world point lands offset_x, offset_y texels further in this frame's map
    /// (texel (i, j) now holds what texel (i - offset_x, j - offset_y) held). 0 otherwise.
    int offset_x = 0, offset_y = 0;
    ShadowCacheCopy copy;            ///< Scroll: the region to copy (what stays on the map); zero otherwise
    std::size_t count = 0;           ///< rectangles written to `rects` (a valid prefix)
    std::size_t needed = 0;          ///< rectangles the plan needs: count when Ok; 1 with BufferTooSmall
    std::size_t unmerged = 0;        ///< footprint rectangles (border strips, old and new footprints) before the cover was built
    /// The rectangles are pairwise disjoint. merged false: their union is exactly the union of the
    /// footprints; true: rect_capacity was too small for that, and footprints were merged into a
    /// larger cover (more texels re-rendered, still disjoint).
    bool merged = false;
    std::uint64_t texels = 0;        ///< sum of the rectangles' areas (= the area of their union): the texels re-rendered (0 for Keep)
    /// Largest departure from a whole-texel translation of last frame's map over the map's volume, in
    /// texels (0 when the matrices are identical; a diagnostic of the motion test).
    double residual_texels = 0.0;
    double tolerance_texels = 0.0;   ///< the round-off bound the residual was tested against
};

/// Where a box's shadow can land on a map (shadow_cache_footprint).
struct ShadowCacheFootprint {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    bool visible = false;            ///< false (with Ok): the box cannot reach the map (empty, beside it, behind a perspective light)
    ShadowCacheRect rect;            ///< visible: every texel whose center lies within one texel of the box's projection
};

namespace detail {

inline bool sc_finite(const glm::dmat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}

inline bool sc_zero(const glm::dmat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (m[c][r] != 0.0) return false;
    return true;
}

inline bool sc_identical(const glm::dmat4& a, const glm::dmat4& b) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!(a[c][r] == b[c][r])) return false;
    return true;
}

/// Row 3 (clip w) is (0, 0, 0, w33) with w33 > 0: an orthographic (parallel) map.
inline bool sc_affine(const glm::dmat4& m) { return m[0][3] == 0.0 && m[1][3] == 0.0 && m[2][3] == 0.0 && m[3][3] > 0.0; }

inline bool sc_box_finite(const float* b) {
    for (int i = 0; i < 6; ++i)
        if (!std::isfinite(b[i])) return false;
    return true;
}

inline bool sc_box_empty(const float* b) { return b[0] > b[3] || b[1] > b[4] || b[2] > b[5]; }

inline bool sc_box_same(const float* a, const float* b) {
    for (int i = 0; i < 6; ++i)
        if (!(a[i] == b[i])) return false;
    return true;
}

inline bool sc_size_ok(int w, int h) { return w >= 1 && h >= 1 && w <= kShadowCacheMaxSize && h <= kShadowCacheMaxSize; }

inline std::uint64_t sc_area(const ShadowCacheRect& r) {
    return static_cast<std::uint64_t>(r.width) * static_cast<std::uint64_t>(r.height);
}

inline ShadowCacheRect sc_union(const ShadowCacheRect& a, const ShadowCacheRect& b) {
    const int x0 = a.x < b.x ? a.x : b.x, y0 = a.y < b.y ? a.y : b.y;
    const int x1 = a.x + a.width > b.x + b.width ? a.x + a.width : b.x + b.width;
    const int y1 = a.y + a.height > b.y + b.height ? a.y + a.height : b.y + b.height;
    return ShadowCacheRect{x0, y0, x1 - x0, y1 - y0};
}

/// The union of a and b is exactly their bounding rectangle: one contains the other, or they share
/// their extent in one axis and overlap or touch in the other.
inline bool sc_union_is_rect(const ShadowCacheRect& a, const ShadowCacheRect& b) {
    const ShadowCacheRect u = sc_union(a, b);
    const bool same_x = a.x == b.x && a.width == b.width, same_y = a.y == b.y && a.height == b.height;
    const bool touch_x = a.x <= b.x + b.width && b.x <= a.x + a.width;
    const bool touch_y = a.y <= b.y + b.height && b.y <= a.y + a.height;
    const bool contains = sc_area(u) == sc_area(a) || sc_area(u) == sc_area(b);
    return contains || (same_y && touch_x) || (same_x && touch_y);
}

/// Clamps a window coordinate (double, maybe huge) to [lo, hi] and converts it.
inline int sc_clamp_int(double v, int lo, int hi) {
    if (!(v > double(lo))) return lo;  // NaN -> lo (never reached: inputs are finite)
    if (v >= double(hi)) return hi;
    return static_cast<int>(v);
}

/// Footprint of a non-empty, finite box under m on a w x h map: false when it cannot reach the map.
/// Orthographic maps and perspective boxes in front of the light (clip w > 0 at all 8 corners)
/// project exactly; a box that straddles w = 0 is culled only by the side planes, else it may
/// cover the whole map. Depth (near/far) never culls: with depth clamp, geometry in front of the
/// near plane is drawn. Returns Overflow through `overflow` for non-finite projections.
inline bool sc_footprint(const glm::dmat4& m, int w, int h, const float* b, ShadowCacheRect& out, bool& overflow) {
    overflow = false;
    glm::dvec4 c[8];
    int behind = 0;  // corners with clip w <= 0
    int out_l = 0, out_r = 0, out_b = 0, out_t = 0;
    for (int k = 0; k < 8; ++k) {
        const glm::dvec4 p((k & 1) ? double(b[3]) : double(b[0]), (k & 2) ? double(b[4]) : double(b[1]),
                           (k & 4) ? double(b[5]) : double(b[2]), 1.0);
        c[k] = m * p;
        if (!std::isfinite(c[k].x) || !std::isfinite(c[k].y) || !std::isfinite(c[k].w)) {
            overflow = true;
            return false;
        }
        if (!(c[k].w > 0.0)) ++behind;
        if (c[k].x < -c[k].w) ++out_l;
        if (c[k].x > c[k].w) ++out_r;
        if (c[k].y < -c[k].w) ++out_b;
        if (c[k].y > c[k].w) ++out_t;
    }
    if (behind == 8) return false;  // GL clips w <= 0 (-w <= x <= w is empty)
    if (out_l == 8 || out_r == 8 || out_b == 8 || out_t == 8) return false;  // beyond one side plane
    double x0 = 0.0, x1 = double(w), y0 = 0.0, y1 = double(h);
    if (behind == 0) {
        x0 = y0 = std::numeric_limits<double>::infinity();
        x1 = y1 = -std::numeric_limits<double>::infinity();
        for (int k = 0; k < 8; ++k) {
            const double x = (c[k].x / c[k].w + 1.0) * 0.5 * double(w);
            const double y = (c[k].y / c[k].w + 1.0) * 0.5 * double(h);
            if (!std::isfinite(x) || !std::isfinite(y)) {
                overflow = true;
                return false;
            }
            x0 = std::fmin(x0, x);
            x1 = std::fmax(x1, x);
            y0 = std::fmin(y0, y);
            y1 = std::fmax(y1, y);
        }
    }
    // texels whose center i + 0.5 lies in [x0 - 1, x1 + 1]: i in [ceil(x0 - 1.5), floor(x1 + 0.5)]
    const int i0 = sc_clamp_int(std::ceil(x0 - 1.5), 0, w), i1 = sc_clamp_int(std::floor(x1 + 0.5) + 1.0, 0, w);
    const int j0 = sc_clamp_int(std::ceil(y0 - 1.5), 0, h), j1 = sc_clamp_int(std::floor(y1 + 0.5) + 1.0, 0, h);
    if (i1 <= i0 || j1 <= j0) return false;
    out = ShadowCacheRect{i0, j0, i1 - i0, j1 - j0};
    return true;
}

/// Disjoint cover of a set of texel rectangles: a sweep in y over the union's cross-section (a set
/// of x runs, kept in a segment tree over the rectangles' distinct x edges). A run that does not
/// change is one output rectangle from the y it appeared to the y it changed (maximal vertical
/// extension), so the output is the union exactly, as pairwise disjoint rectangles; disjoint inputs
/// come out unchanged. O((m + k) log m) for m inputs and k outputs; stops (false) as soon as more
/// than `cap` rectangles would be needed. Scratch: O(m) elements, kept between calls.
struct sc_sweep {
    struct Event {
        int y, v, l, r;  // v = +1 (start) / -1 (end); [l, r): elementary x intervals
    };
    std::vector<int> xs, rank, slot, cnt, open_y;
    std::vector<unsigned char> any, all;  // per node: some / every elementary interval below is covered
    std::vector<Event> events;
    std::vector<std::pair<int, int>> old_runs, new_runs;
    int elems = 0;  // elementary intervals: [xs[e], xs[e + 1]), e < elems

    // A cover-count segment tree (the area-of-union tree): cnt[node] counts the rectangles covering
    // the node's whole range, never pushed down; an interval is covered when a node on its path is.
    void apply(int node, int lo, int hi, int l, int r, int v) {
        if (r <= lo || hi <= l) return;
        const int mid = (lo + hi) / 2;
        if (l <= lo && hi <= r) {
            cnt[std::size_t(node)] += v;
        } else {
            apply(2 * node, lo, mid, l, r, v);
            apply(2 * node + 1, mid, hi, l, r, v);
        }
        const std::size_t n = std::size_t(node);
        if (cnt[n] > 0) any[n] = all[n] = 1;
        else if (hi - lo == 1) any[n] = all[n] = 0;
        else {
            any[n] = any[2 * n] | any[2 * n + 1];
            all[n] = all[2 * n] & all[2 * n + 1];
        }
    }
    /// First covered e in [p, lim); elems if none.
    int next_covered(int node, int lo, int hi, int p, int lim) const {
        if (hi <= p || lo >= lim || !any[std::size_t(node)]) return elems;
        if (cnt[std::size_t(node)] > 0) return lo > p ? lo : p;
        const int mid = (lo + hi) / 2;
        const int a = next_covered(2 * node, lo, mid, p, lim);
        return a != elems ? a : next_covered(2 * node + 1, mid, hi, p, lim);
    }
    /// First uncovered e >= p; elems if none.
    int next_uncovered(int node, int lo, int hi, int p) const {
        if (hi <= p || all[std::size_t(node)]) return elems;
        if (hi - lo == 1) return lo;
        const int mid = (lo + hi) / 2;
        const int a = next_uncovered(2 * node, lo, mid, p);
        return a != elems ? a : next_uncovered(2 * node + 1, mid, hi, p);
    }
    /// Last uncovered e < p; -1 if none.
    int prev_uncovered(int node, int lo, int hi, int p) const {
        if (lo >= p || all[std::size_t(node)]) return -1;
        if (hi - lo == 1) return lo;
        const int mid = (lo + hi) / 2;
        const int b = prev_uncovered(2 * node + 1, mid, hi, p);
        return b != -1 ? b : prev_uncovered(2 * node, lo, mid, p);
    }
    /// The runs [s, e) (maximal covered elementary ranges) that meet [a, b).
    void runs(int a, int b, std::vector<std::pair<int, int>>& out) const {
        out.clear();
        const int z = prev_uncovered(1, 0, elems, a + 1);  // a itself uncovered: z == a
        int s = z == a ? next_covered(1, 0, elems, a, b) : z + 1;
        while (s < b) {
            const int e = next_uncovered(1, 0, elems, s);
            out.emplace_back(s, e);
            s = e < b ? next_covered(1, 0, elems, e, b) : elems;
        }
    }
    bool emit(int s, int e, int y, ShadowCacheRect* out, std::size_t cap, std::size_t& count) {
        if (y > open_y[s]) {
            if (count == cap) return false;
            out[count++] = ShadowCacheRect{xs[s], open_y[s], xs[e] - xs[s], y - open_y[s]};
        }
        return true;
    }
    /// One event: close the runs near [l, r) that it changes, open the new ones.
    bool event(const Event& ev, ShadowCacheRect* out, std::size_t cap, std::size_t& count) {
        const int a = ev.l > 0 ? ev.l - 1 : 0, b = ev.r < elems ? ev.r + 1 : elems;
        if (ev.v > 0) {
            if (next_covered(1, 0, elems, a, b) == elems) {
                // a start in empty surroundings (disjoint footprints): one new run, nothing closes
                apply(1, 0, elems, ev.l, ev.r, ev.v);
                open_y[std::size_t(ev.l)] = ev.y;
                return true;
            }
            if (next_uncovered(1, 0, elems, a) >= b) {
                apply(1, 0, elems, ev.l, ev.r, ev.v);  // inside a run (piled footprints): nothing changes
                return true;
            }
        }
        runs(a, b, old_runs);
        apply(1, 0, elems, ev.l, ev.r, ev.v);
        if (ev.v < 0 && old_runs.size() == 1 && next_uncovered(1, 0, elems, a) >= b) return true;  // still inside it
        if (next_covered(1, 0, elems, a, b) == elems) new_runs.clear();  // an end that empties its surroundings
        else runs(a, b, new_runs);
        std::size_t i = 0, j = 0;
        while (i < old_runs.size() || j < new_runs.size()) {
            if (i < old_runs.size() && j < new_runs.size() && old_runs[i] == new_runs[j]) {
                ++i, ++j;  // unchanged: stays open
            } else if (j == new_runs.size() || (i < old_runs.size() && old_runs[i].first <= new_runs[j].first)) {
                if (!emit(old_runs[i].first, old_runs[i].second, ev.y, out, cap, count)) return false;
                ++i;
            } else {
                open_y[std::size_t(new_runs[j].first)] = ev.y;
                ++j;
            }
        }
        return true;
    }
    /// The disjoint cover of in[0, m) into out[0, count); false if it needs more than cap. The x
    /// edges are compressed and the events ordered by counting (coordinates lie in [0, 65536]).
    bool run(const ShadowCacheRect* in, std::size_t m, ShadowCacheRect* out, std::size_t cap, std::size_t& count) {
        count = 0;
        int max_x = 0, max_y = 0;
        for (std::size_t i = 0; i < m; ++i) {
            max_x = std::max(max_x, in[i].x + in[i].width);
            max_y = std::max(max_y, in[i].y + in[i].height);
        }
        xs.assign(std::size_t(max_x) + 1, 0);  // first a mark per x edge, then its rank
        for (std::size_t i = 0; i < m; ++i) xs[std::size_t(in[i].x)] = xs[std::size_t(in[i].x + in[i].width)] = 1;
        rank.assign(xs.size(), 0);
        int k = 0;
        for (std::size_t x = 0; x < xs.size(); ++x)
            if (xs[x] != 0) {
                rank[x] = k;
                xs[std::size_t(k++)] = int(x);
            }
        xs.resize(std::size_t(k));
        elems = k - 1;
        if (elems < 1) return true;
        // events by y, starts before ends at the same y (a run that only grows and shrinks back
        // within one y is not split); a counting sort on 2 y + (end), stable
        slot.assign(2 * std::size_t(max_y) + 3, 0);
        for (std::size_t i = 0; i < m; ++i) {
            ++slot[2 * std::size_t(in[i].y) + 1];
            ++slot[2 * std::size_t(in[i].y + in[i].height) + 2];
        }
        for (std::size_t j = 1; j < slot.size(); ++j) slot[j] += slot[j - 1];
        events.resize(2 * m);
        for (std::size_t i = 0; i < m; ++i) {
            const int l = rank[std::size_t(in[i].x)], r = rank[std::size_t(in[i].x + in[i].width)];
            events[std::size_t(slot[2 * std::size_t(in[i].y)]++)] = Event{in[i].y, +1, l, r};
            events[std::size_t(slot[2 * std::size_t(in[i].y + in[i].height) + 1]++)] = Event{in[i].y + in[i].height, -1, l, r};
        }
        const std::size_t nodes = 4 * std::size_t(elems);
        cnt.assign(nodes, 0);
        any.assign(nodes, 0);
        all.assign(nodes, 0);
        open_y.assign(xs.size(), 0);
        for (const Event& ev : events)
            if (!event(ev, out, cap, count)) return false;
        return true;
    }
};

/// Morton key of a rectangle's center (16 bits per axis): neighbours on the map, neighbours in the key.
inline std::uint32_t sc_morton(const ShadowCacheRect& r) {
    std::uint32_t key = 0;
    const std::uint32_t x = std::uint32_t(r.x + r.width / 2) & 0xffffu, y = std::uint32_t(r.y + r.height / 2) & 0xffffu;
    for (int b = 0; b < 16; ++b) key |= (((x >> b) & 1u) << (2 * b)) | (((y >> b) & 1u) << (2 * b + 1));
    return key;
}

/// Shrinks a rectangle list for a capacity its disjoint cover overflowed: sorted in Morton order of
/// the centers, each consecutive pair whose bounding rectangle is no larger than the two together
/// (a free merge: no more texels than drawing both) becomes that rectangle; when that shortens the
/// list by less than a quarter, every pair does (the list halves). O(m log m).
inline void sc_merge_pairs(std::vector<ShadowCacheRect>& v, std::vector<ShadowCacheRect>& tmp) {
    std::sort(v.begin(), v.end(), [](const ShadowCacheRect& a, const ShadowCacheRect& b) { return sc_morton(a) < sc_morton(b); });
    for (int forced = 0; forced < 2; ++forced) {
        tmp.clear();
        for (std::size_t i = 0; i < v.size();) {
            const ShadowCacheRect u = i + 1 < v.size() ? sc_union(v[i], v[i + 1]) : v[i];
            if (i + 1 < v.size() && (forced != 0 || sc_area(u) <= sc_area(v[i]) + sc_area(v[i + 1]))) {
                tmp.push_back(u);
                i += 2;
            } else {
                tmp.push_back(v[i++]);
            }
        }
        if (forced != 0 || 4 * tmp.size() <= 3 * v.size()) break;
    }
    v.swap(tmp);
}

/// The cover of the footprints `fp` in out[0, count) (cap >= 1): their union as disjoint rectangles
/// when that fits in cap (merged false); else neighbouring footprints are merged (sc_merge_pairs)
/// and the union of the merged list is tried again, until it fits (merged true: a larger cover,
/// still disjoint). O(m log m) per round; each round shortens the list by a quarter or more.
inline void sc_cover(std::vector<ShadowCacheRect>& fp, ShadowCacheRect* out, std::size_t cap, std::size_t& count,
                     bool& merged) {
    merged = false;
    count = 0;
    if (fp.size() == 1) {
        out[count++] = fp[0];
        return;
    }
    sc_sweep sweep;
    std::vector<ShadowCacheRect> tmp;
    while (!sweep.run(fp.data(), fp.size(), out, cap, count)) {
        merged = true;
        sc_merge_pairs(fp, tmp);
    }
}

/// The 8 corners of an affine map's volume (NDC cube [-1, 1]^3) in world space; false if the map's
/// 3x3 part is singular or the corners are not finite.
inline bool sc_volume_corners(const glm::dmat4& m, glm::dvec3 out[8]) {
    const double det = glm::determinant(m);
    if (!std::isfinite(det) || det == 0.0) return false;
    const glm::dmat4 inv = glm::inverse(m);
    for (int k = 0; k < 8; ++k) {
        const glm::dvec4 p = inv * glm::dvec4((k & 1) ? 1.0 : -1.0, (k & 2) ? 1.0 : -1.0, (k & 4) ? 1.0 : -1.0, 1.0);
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) || !std::isfinite(p.w) || !(p.w != 0.0))
            return false;
        out[k] = glm::dvec3(p) / p.w;
        if (!std::isfinite(out[k].x) || !std::isfinite(out[k].y) || !std::isfinite(out[k].z)) return false;
    }
    return true;
}

/// Sum of |terms| of row r of m applied to p (the scale of its round-off).
inline double sc_row_magnitude(const glm::dmat4& m, int r, const glm::dvec3& p) {
    return std::fabs(m[0][r] * p.x) + std::fabs(m[1][r] * p.y) + std::fabs(m[2][r] * p.z) + std::fabs(m[3][r]);
}

inline double sc_row(const glm::dmat4& m, int r, const glm::dvec3& p) {
    return m[0][r] * p.x + m[1][r] * p.y + m[2][r] * p.z + m[3][r];
}

/// Motion of an affine map between two frames (shadow_cache_plan's whole-texel test): Ok with
/// reason None and the offset in (ox, oy) when `cur` is `prev` moved by whole texels in x/y (0, 0
/// when identical); a reason to render whole otherwise; InvalidArgument / Overflow for a singular
/// matrix or a difference beyond double. Fills res.residual_texels and res.tolerance_texels.
inline Status sc_map_motion(const ShadowCacheMapState& previous, const ShadowCacheMapState& current, ShadowCachePlan& res,
                            ShadowCacheReason& reason, int& ox, int& oy, const char*& why) {
    const glm::dmat4& A = previous.view_proj;
    const glm::dmat4& B = current.view_proj;
    const int W = current.width, H = current.height;
    reason = ShadowCacheReason::None;
    ox = oy = 0;
    if (sc_identical(A, B)) return Status::Ok;
    if (!sc_affine(A) || !sc_affine(B)) {
        reason = ShadowCacheReason::ProjectionChanged;
        return Status::Ok;
    }
    const glm::dmat4 An = A / A[3][3], Bn = B / B[3][3];  // clip w = 1 everywhere
    glm::dvec3 corner[8];
    if (!sc_volume_corners(Bn, corner)) {  // singular 3x3: no map volume
        why = "current.view_proj: singular (no map volume)";
        return Status::InvalidArgument;
    }
    const double u = (previous.float_matrices || current.float_matrices) ? std::ldexp(1.0, -24) : std::ldexp(1.0, -53);
    // per row (x, y, z): the difference at the corners and its round-off scale
    double dmin[3], dmax[3], scale[3];
    for (int r = 0; r < 3; ++r) {
        dmin[r] = std::numeric_limits<double>::infinity();
        dmax[r] = -std::numeric_limits<double>::infinity();
        double sa = 0.0, sb = 0.0;
        for (int k = 0; k < 8; ++k) {
            const double d = sc_row(Bn, r, corner[k]) - sc_row(An, r, corner[k]);
            dmin[r] = std::fmin(dmin[r], d);
            dmax[r] = std::fmax(dmax[r], d);
            sa = std::fmax(sa, sc_row_magnitude(An, r, corner[k]));
            sb = std::fmax(sb, sc_row_magnitude(Bn, r, corner[k]));
        }
        scale[r] = 8.0 * u * (sa + sb);
        if (!std::isfinite(dmin[r]) || !std::isfinite(dmax[r]) || !std::isfinite(scale[r])) {
            why = "previous.view_proj, current.view_proj: their difference beyond double";
            return Status::Overflow;
        }
    }
    // NDC -> texels (x, y); depth stays in NDC
    const double half[2] = {0.5 * double(W), 0.5 * double(H)};
    const double tol_x = scale[0] * half[0], tol_y = scale[1] * half[1];
    res.tolerance_texels = std::fmax(tol_x, tol_y);
    const double cx = 0.5 * (dmin[0] + dmax[0]) * half[0], cy = 0.5 * (dmin[1] + dmax[1]) * half[1];
    const double rx = std::round(cx), ry = std::round(cy);
    const double res_x = std::fmax(std::fabs(dmin[0] * half[0] - rx), std::fabs(dmax[0] * half[0] - rx));
    const double res_y = std::fmax(std::fabs(dmin[1] * half[1] - ry), std::fabs(dmax[1] * half[1] - ry));
    res.residual_texels = std::fmax(res_x, res_y);
    if (!std::isfinite(res.residual_texels)) {
        why = "previous.view_proj, current.view_proj: their difference beyond double";
        return Status::Overflow;
    }
    // linear parts: the spread of the difference over the volume (a rotation or scale)
    const double spread_x = (dmax[0] - dmin[0]) * half[0], spread_y = (dmax[1] - dmin[1]) * half[1];
    if (res.tolerance_texels > kShadowCacheMaxResidualTexels) reason = ShadowCacheReason::PrecisionTooLow;
    else if (spread_x > 2.0 * tol_x || spread_y > 2.0 * tol_y || dmax[2] - dmin[2] > 2.0 * scale[2])
        reason = ShadowCacheReason::ProjectionChanged;
    else if (std::fmax(std::fabs(dmin[2]), std::fabs(dmax[2])) > scale[2]) reason = ShadowCacheReason::DepthMoved;
    else if (res_x > tol_x || res_y > tol_y) reason = ShadowCacheReason::SubTexelMotion;
    else if (std::fabs(rx) >= double(W) || std::fabs(ry) >= double(H)) reason = ShadowCacheReason::MovedOffMap;
    else {
        ox = static_cast<int>(rx);
        oy = static_cast<int>(ry);
    }
    return Status::Ok;
}

/// shadow_cache_plan's validation: Ok, or the first problem with its detail in `why`.
inline Status sc_check_plan_input(const ShadowCacheMapState& previous, const ShadowCacheMapState& current,
                                  const ShadowCacheCaster* casters, std::size_t caster_count, const ShadowCacheRect* rects,
                                  std::size_t rect_capacity, const char*& why) {
    auto fail = [&why](Status s, const char* what) {
        why = what;
        return s;
    };
    if (casters == nullptr && caster_count != 0) return fail(Status::InvalidArgument, "casters: null with caster_count > 0");
    if (rects == nullptr && rect_capacity != 0) return fail(Status::InvalidArgument, "rects: null with rect_capacity > 0");
    if (!sc_size_ok(current.width, current.height))
        return fail(Status::InvalidArgument, "current.width, current.height: outside 1..kShadowCacheMaxSize");
    if (!sc_finite(current.view_proj)) return fail(Status::NonFinite, "current.view_proj: NaN or Inf");
    if (sc_zero(current.view_proj)) return fail(Status::InvalidArgument, "current.view_proj: all zero");
    for (std::size_t i = 0; i < caster_count; ++i)
        if (!sc_box_finite(casters[i].bounds) || !sc_box_finite(casters[i].previous_bounds))
            return fail(Status::NonFinite, "casters: NaN or Inf in bounds or previous_bounds");
    if (previous.has_content) {
        if (!sc_size_ok(previous.width, previous.height))
            return fail(Status::InvalidArgument, "previous.width, previous.height: outside 1..kShadowCacheMaxSize");
        if (!sc_finite(previous.view_proj)) return fail(Status::NonFinite, "previous.view_proj: NaN or Inf");
        if (sc_zero(previous.view_proj)) return fail(Status::InvalidArgument, "previous.view_proj: all zero");
    }
    return Status::Ok;
}

/// The exposed border of a W x H map scrolled by (ox, oy): at most two disjoint strips into out
/// (their count returned); fills res.copy and the offsets when the map moved.
inline std::size_t sc_strips(int W, int H, int ox, int oy, ShadowCachePlan& res, ShadowCacheRect out[2]) {
    if (ox == 0 && oy == 0) return 0;
    std::size_t n = 0;
    const int ax = ox < 0 ? -ox : ox, ay = oy < 0 ? -oy : oy;
    const int sx = ox > 0 ? 0 : W - ax;  // exposed columns [sx, sx + ax)
    const int sy = oy > 0 ? 0 : H - ay;  // exposed rows [sy, sy + ay)
    if (ax > 0) out[n++] = ShadowCacheRect{sx, 0, ax, H};
    if (ay > 0 && W - ax > 0) out[n++] = ShadowCacheRect{ox > 0 ? ax : 0, sy, W - ax, ay};
    res.copy = ShadowCacheCopy{ox > 0 ? 0 : ax, oy > 0 ? 0 : ay, ox > 0 ? ax : 0, oy > 0 ? ay : 0, W - ax, H - ay};
    res.offset_x = ox;
    res.offset_y = oy;
    return n;
}

/// The rectangles to re-render on a W x H map scrolled by (ox, oy) (0, 0: in place): the exposed
/// border (at most two strips) and the footprints (this frame's matrix B) of the old and new bounds
/// of every caster that moved, into `fp` (a caster's two as one when their union is a rectangle);
/// fills res.copy, the offsets and res.unmerged (all of them). False: a footprint overflowed.
inline bool sc_footprints(const glm::dmat4& B, int W, int H, int ox, int oy, const ShadowCacheCaster* casters,
                          std::size_t caster_count, ShadowCachePlan& res, std::vector<ShadowCacheRect>& fp) {
    ShadowCacheRect strips[2];
    res.unmerged = sc_strips(W, H, ox, oy, res, strips);
    fp.assign(strips, strips + res.unmerged);
    for (std::size_t i = 0; i < caster_count; ++i) {
        const ShadowCacheCaster& c = casters[i];
        if (sc_box_same(c.bounds, c.previous_bounds)) continue;
        const std::size_t first = fp.size();
        for (const float* b : {c.previous_bounds, c.bounds}) {
            if (sc_box_empty(b)) continue;
            ShadowCacheRect r;
            bool overflow = false;
            if (sc_footprint(B, W, H, b, r, overflow)) {
                fp.push_back(r);
                ++res.unmerged;
            }
            if (overflow) return false;
        }
        // old and new footprint whose union is one rectangle (a move along one map axis, or one
        // inside the other): that rectangle, exactly (half the sweep's events for such casters)
        if (fp.size() == first + 2 && sc_union_is_rect(fp[first], fp[first + 1])) {
            fp[first] = sc_union(fp[first], fp[first + 1]);
            fp.pop_back();
        }
    }
    return true;
}

}  // namespace detail

/// Rectangles shadow_cache_plan may need before merging for `caster_count` casters (2 border strips
/// + the old and the new footprint of each): total: 2 + 2 * caster_count, saturated at SIZE_MAX.
inline std::size_t shadow_cache_rect_capacity(std::size_t caster_count) {
    const std::size_t max = std::numeric_limits<std::size_t>::max();
    if (caster_count > (max - 2) / 2) return max;
    return 2 + 2 * caster_count;
}

/// Where the shadow of a box (`bounds`: 6 floats, min x, y, z, max x, y, z) can land on a map drawn
/// with `view_proj` at width x height texels: every texel whose center lies within one texel of the
/// box's projection (a margin for the GPU's float transform and its sub-texel snapping). Use it to
/// cull the casters drawn into each rectangle of a plan. `visible` is false (with Ok) for an empty
/// box, one beside the map or one behind a perspective light; near and far planes never cull (depth
/// clamp draws what lies in front of the near plane). A perspective box that straddles the light's
/// plane (clip w = 0) gets the whole map.
/// Errors: NonFinite (NaN/Inf in view_proj or bounds), InvalidArgument (null bounds, zero matrix,
/// size outside 1..kShadowCacheMaxSize), Overflow (a projected corner beyond double).
inline ShadowCacheFootprint shadow_cache_footprint(const glm::dmat4& view_proj, int width, int height, const float* bounds) {
    using namespace detail;
    ShadowCacheFootprint res;
    auto fail = [&res](Status s, const char* why) {
        res.status = s;
        res.detail = why;
        return res;
    };
    if (bounds == nullptr) return fail(Status::InvalidArgument, "bounds: null");
    if (!sc_size_ok(width, height)) return fail(Status::InvalidArgument, "width, height: outside 1..kShadowCacheMaxSize");
    if (!sc_finite(view_proj)) return fail(Status::NonFinite, "view_proj: NaN or Inf");
    if (!sc_box_finite(bounds)) return fail(Status::NonFinite, "bounds: NaN or Inf");
    if (sc_zero(view_proj)) return fail(Status::InvalidArgument, "view_proj: all zero");
    res.status = Status::Ok;
    if (sc_box_empty(bounds)) return res;
    bool overflow = false;
    res.visible = sc_footprint(view_proj, width, height, bounds, res.rect, overflow);
    if (overflow) {
        res = ShadowCacheFootprint{};
        res.status = Status::Overflow;
        res.detail = "bounds: a projected corner beyond double";
    }
    return res;
}

/// shadow_cache_footprint for a float matrix (widened exactly to double).
inline ShadowCacheFootprint shadow_cache_footprint(const glm::mat4& view_proj, int width, int height, const float* bounds) {
    return shadow_cache_footprint(glm::dmat4(view_proj), width, height, bounds);
}

/// The plan for one map this frame: what to copy and which texel rectangles to clear and re-render
/// so that the map equals a full re-render with `current`.
///
/// - Render (the whole map, one rectangle) when `previous` has no content, the size or the settings
///   changed, or the map is not last frame's map moved by whole texels in x/y (`reason`).
/// - Keep when the projection is unchanged and no caster that moved reaches the map.
/// - Update when the projection is unchanged: the rectangles cover the old and the new footprint
///   (this frame's matrix) of every caster whose bounds changed.
/// - Scroll when an orthographic map (clip w row (0, 0, 0, w33 > 0), a stable cascade) moved by whole
///   texels in x/y and not in depth: copy `copy` from the previous content (a second texture:
///   glCopyImageSubData's regions must not overlap within one image), then re-render the exposed
///   border (at most two strips) and the moved casters' footprints.
///
/// Whole-texel test (in double): the difference of the two maps at the 8 corners of this frame's
/// map volume (its NDC cube in world space) must be one integer texel translation in x/y and zero in
/// depth, up to the round-off bound tolerance_texels = 8 u (S_prev + S_cur) * size / 2 per axis,
/// where S is the largest sum of |terms| of the row over those corners and u the unit round-off
/// (2^-53, or 2^-24 with float_matrices): 8 u per matrix covers its entries' rounding (a product
/// chain in that precision) plus the 4-term evaluation. For a map N texels from the world origin
/// that is ~32 u N texels. A larger residual is a change (a 1e-7 rad turn moves the points of a
/// 2048-texel map by 1e-4 texel or more: ProjectionChanged). If the bound itself exceeds
/// kShadowCacheMaxResidualTexels the answer is PrecisionTooLow: with double that is ~2^40 texels
/// from the world origin, with float ~2^11 (so a float fit 1e5 units away cannot scroll).
/// Depth: for an orthographic light window depth is linear, so a translation along the light axis
/// adds one constant to every stored depth. A depth copy (glCopyImageSubData, a blit) cannot add
/// it, a shader pass that does is not bit-identical to re-rendering (rounding of a z + b + c vs
/// a z + (b + c), fixed-point steps) and the near/far planes would clip different casters: a depth
/// translation renders the whole map (DepthMoved). Keep a cascade's depth range fixed in the world
/// (e.g. from the scene's bounds along the light: cascades.hpp's and light_frustum.hpp's
/// stable_world_depth) so camera motion only moves it in x/y.
/// Perspective maps (spot lights, cube faces) never scroll: any change of the matrix renders.
///
/// `casters`: caster_count entries (null allowed when 0); only those whose bounds changed count.
/// `rects` holds rect_capacity ShadowCacheRect elements. The footprints (`unmerged`, at most
/// shadow_cache_rect_capacity(caster_count)) may overlap; the plan writes their union as pairwise
/// disjoint rectangles (no texel re-rendered twice; `texels` is the union's area): disjoint
/// footprints come out as they are, overlapping ones split (two crossing bars give three). When that
/// needs more than rect_capacity (shadow_cache_rect_capacity(caster_count) holds the footprints,
/// not always their split), neighbouring footprints are merged into their bounding rectangles, the
/// free merges first (no larger than the pair), until the union of the merged set fits (`merged`: a
/// conservative cover, still disjoint); any capacity >= 1 works. Keep writes none, Render one. When the rectangles would cover
/// the whole map the plan is Render (DirtyCoversMap). Cost: O((m + count) log m) for m footprints (a
/// sweep in y over the union's x runs), times O(log m) rounds when merging; scratch O(m), allocated.
/// Errors: InvalidArgument (current.view_proj zero, a size outside 1..kShadowCacheMaxSize, null
/// casters with a count, null rects with a capacity, the same for previous when has_content),
/// NonFinite (NaN/Inf in a matrix or bounds), BufferTooSmall (rect_capacity 0 and a rectangle to
/// write; needed = 1), Overflow (a projection beyond double).
inline ShadowCachePlan shadow_cache_plan(const ShadowCacheMapState& previous, const ShadowCacheMapState& current,
                                         const ShadowCacheCaster* casters, std::size_t caster_count,
                                         ShadowCacheRect* rects, std::size_t rect_capacity) {
    using namespace detail;
    ShadowCachePlan res;
    auto fail = [&res](Status s, const char* why) {
        res = ShadowCachePlan{};
        res.status = s;
        res.detail = why;
        return res;
    };
    const char* invalid = nullptr;
    const Status valid = sc_check_plan_input(previous, current, casters, caster_count, rects, rect_capacity, invalid);
    if (valid != Status::Ok) return fail(valid, invalid);
    const int W = current.width, H = current.height;
    const ShadowCacheRect whole{0, 0, W, H};
    const std::uint64_t map_area = sc_area(whole);
    auto render = [&](ShadowCacheReason why) {
        const double resid = res.residual_texels, tol = res.tolerance_texels;
        res = ShadowCachePlan{};
        res.reason = why;
        res.residual_texels = resid;
        res.tolerance_texels = tol;
        res.action = ShadowCacheAction::Render;
        res.unmerged = 1;
        res.needed = 1;
        if (rect_capacity == 0) {
            res.status = Status::BufferTooSmall;
            res.detail = "rect_capacity: 0 with a rectangle to write";
            return res;
        }
        rects[0] = whole;
        res.count = 1;
        res.texels = map_area;
        res.status = Status::Ok;
        return res;
    };
    if (!previous.has_content) return render(ShadowCacheReason::NoContent);
    if (previous.width != W || previous.height != H) return render(ShadowCacheReason::SizeChanged);
    if (previous.settings != current.settings) return render(ShadowCacheReason::SettingsChanged);

    // ---- motion of the map
    ShadowCacheReason why = ShadowCacheReason::None;
    int ox = 0, oy = 0;
    const char* motion_detail = nullptr;
    const Status motion = sc_map_motion(previous, current, res, why, ox, oy, motion_detail);
    if (motion != Status::Ok) return fail(motion, motion_detail);
    if (why != ShadowCacheReason::None) return render(why);

    // ---- rectangles: the footprints, then their disjoint cover (no allocation when no caster moved:
    // the border strips are disjoint already)
    std::vector<ShadowCacheRect> fp;
    bool moved = false;
    for (std::size_t i = 0; i < caster_count && !moved; ++i) moved = !sc_box_same(casters[i].bounds, casters[i].previous_bounds);
    ShadowCacheRect strips[2];
    const std::size_t strip_count = moved ? 0 : sc_strips(W, H, ox, oy, res, strips);
    if (moved && !sc_footprints(current.view_proj, W, H, ox, oy, casters, caster_count, res, fp)) return fail(Status::Overflow, "casters: a footprint beyond double");
    if (!moved) res.unmerged = strip_count;
    const std::size_t m = moved ? fp.size() : strip_count;
    const bool scroll = ox != 0 || oy != 0;
    res.action = scroll ? ShadowCacheAction::Scroll : (m == 0 ? ShadowCacheAction::Keep : ShadowCacheAction::Update);
    res.reason = ShadowCacheReason::None;
    res.status = Status::Ok;
    if (m == 0) return res;
    if (rect_capacity == 0) {  // BufferTooSmall, unless the footprints alone cover the map's area
        std::uint64_t fp_area = 0;
        for (std::size_t i = 0; i < m; ++i) fp_area += sc_area(moved ? fp[i] : strips[i]);
        if (fp_area >= map_area) return render(ShadowCacheReason::DirtyCoversMap);
        res.status = Status::BufferTooSmall;
        res.detail = "rect_capacity: 0 with a rectangle to write";
        res.action = ShadowCacheAction::Render;
        res.copy = ShadowCacheCopy{};
        res.offset_x = res.offset_y = 0;
        res.needed = 1;
        return res;
    }
    if (moved) {
        sc_cover(fp, rects, rect_capacity, res.count, res.merged);
    } else {  // the strips are disjoint: as they are, or their bounding rectangle in a capacity of 1
        res.merged = m > rect_capacity;
        if (res.merged) rects[0] = sc_union(strips[0], strips[1]);
        else std::copy(strips, strips + m, rects);
        res.count = res.merged ? 1 : m;
    }
    for (std::size_t i = 0; i < res.count; ++i) res.texels += sc_area(rects[i]);
    if (res.texels >= map_area) return render(ShadowCacheReason::DirtyCoversMap);
    res.needed = res.count;
    return res;
}

/// The reason's name, for logs and test messages.
inline const char* shadow_cache_reason_name(ShadowCacheReason r) {
    switch (r) {
    case ShadowCacheReason::None: return "None";
    case ShadowCacheReason::NoContent: return "NoContent";
    case ShadowCacheReason::SizeChanged: return "SizeChanged";
    case ShadowCacheReason::SettingsChanged: return "SettingsChanged";
    case ShadowCacheReason::ProjectionChanged: return "ProjectionChanged";
    case ShadowCacheReason::DepthMoved: return "DepthMoved";
    case ShadowCacheReason::SubTexelMotion: return "SubTexelMotion";
    case ShadowCacheReason::MovedOffMap: return "MovedOffMap";
    case ShadowCacheReason::PrecisionTooLow: return "PrecisionTooLow";
    case ShadowCacheReason::DirtyCoversMap: return "DirtyCoversMap";
    }
    return "?";
}

/// The action's name, for logs and test messages.
inline const char* shadow_cache_action_name(ShadowCacheAction a) {
    switch (a) {
    case ShadowCacheAction::Keep: return "Keep";
    case ShadowCacheAction::Update: return "Update";
    case ShadowCacheAction::Scroll: return "Scroll";
    case ShadowCacheAction::Render: return "Render";
    }
    return "?";
}

}  // namespace shadowkit
