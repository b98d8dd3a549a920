// shadowkit/linear_light.hpp - soft shadows from a linear (line-segment) light: the CPU side of
// Heidrich, Brabec & Seidel (2000). The light is sampled at its two endpoints with shadow maps;
// between them the visible fraction is interpolated with a visibility map per endpoint, made by
// triangulating the depth discontinuities of the OTHER endpoint's shadow map into "skin" polygons
// (vertex value 0 on the occluder, 1 on the receiver), warping them into this endpoint's view and
// Gouraud-shading them. Lit regions keep the default visibility 0.5 per endpoint, so
// V = lit_a * v_a + lit_b * v_b (the paper's shade()). Also the exact visible fraction of the
// segment from a point for box occluders (1D interval arithmetic), the reference of the tests.
// GPU side: glsl/linear_light.glsl (skin vertex stage, lookups).
//
// Usage:
//   #include <shadowkit/linear_light.hpp>
//   namespace sk = shadowkit;
//   sk::LinearLightSegment L = sk::linear_light_segment(center, direction, length);  // L.a, L.b
//   glm::vec3 ends[3]; sk::linear_light_subdivide(L, 2, ends, 3);  // 2 sub-lights, 3 shadow maps
//   // per endpoint shadow map (linear distances dist[W*H], world positions pos[W*H]):
//   std::vector<sk::LinearLightSkinVertex> skin(sk::linear_light_skin_capacity(W, H));
//   sk::LinearLightSkinResult s = sk::linear_light_build_skin(pos, dist, W, H, 0.05f, skin.data(), skin.size());
//   // draw s.written vertices with the other endpoint's view-projection into its visibility map
//   float v = sk::linear_light_shade(lit_a, vis_a, lit_b, vis_b);
//   // exact reference for boxes:
//   sk::LinearLightBox box{{-1, 0, -1}, {1, 1, 1}};
//   sk::LinearLightFraction f = sk::linear_light_visible_fraction(p, n, L.a, L.b, &box, 1);
//
// Based on:
//   W. Heidrich, S. Brabec, H.-P. Seidel, "Soft Shadow Maps for Linear Lights", Eurographics
//   Rendering Workshop 2000 (sec. 3: visibility map, skin polygons from the depth discontinuities
//   warped to the other sample point, Gouraud shading black on the occluder / white on the receiver,
//   default visibility 0.5, shade(); sec. 4: hardware passes; sec. 5: subdividing the light when
//   neither endpoint sees it). Course notes: SIGGRAPH 2004 "Real-Time Shadowing Techniques".
//
// Parameters (all documented where they appear):
//   * discontinuity threshold (relative, default 0.05): adjacent shadow-map samples with linear
//     distances d0 < d1 form a discontinuity when d1 > d0 * (1 + threshold). Too small: skins on
//     sloped receivers (false penumbrae); too large: skins missed behind low occluders.
//   * subdivision k: the light is split into k linear lights (k + 1 shadow maps, 2k visibility
//     maps) when thin occluders hide the middle of the light from a point that sees both ends
//     (the paper's undersampling failure); V = mean over the sub-lights.
//   * min_fraction (exact reference): rays start this fraction of the way from the receiver to the
//     light sample (default 1e-4), so a receiver on an occluder's face does not occlude itself.
//
// Conventions: world space, right-handed, GLM. The segment is a + t (b - a), t in [0, 1]. A
// zero-length segment is a point light: every function then gives the point-light result exactly.
//
// MIT License. Copyright (c) shadowkit contributors.
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace shadowkit {

enum class LinearLightStatus {
    Ok,
    InvalidArgument,  ///< NaN/Inf input, negative length, zero direction with length > 0, null buffers
    BufferTooSmall    ///< output truncated; the needed count is reported
};

struct LinearLightSegment {
    LinearLightStatus status = LinearLightStatus::Ok;
    glm::vec3 a{0.f}, b{0.f};  ///< endpoints; a == b for a zero-length (point) light
    bool point = false;        ///< zero length: use the point-light path
};

/// Axis-aligned box occluder (min, max corners).
struct LinearLightBox {
    glm::vec3 lo{0.f}, hi{0.f};
};

/// A closed parameter interval [t0, t1] on the segment; empty when !(t0 <= t1).
struct LinearLightInterval {
    float t0 = 1.f, t1 = 0.f;
    bool empty() const { return !(t0 <= t1); }
};

struct LinearLightFraction {
    LinearLightStatus status = LinearLightStatus::Ok;
    float fraction = 0.f;  ///< visible fraction of the segment in [0, 1] (point light: 0 or 1)
};

/// Default per-endpoint visibility of completely lit regions (paper sec. 3: 0.5 + 0.5 = 1).
constexpr float kLinearLightDefaultVisibility = 0.5f;

/// The light from its centre, direction (any length) and length. Length 0 gives a == b == center.
inline LinearLightSegment linear_light_segment(glm::vec3 center, glm::vec3 direction, float length) {
    LinearLightSegment s;
    const bool finite = std::isfinite(center.x) && std::isfinite(center.y) && std::isfinite(center.z) &&
                        std::isfinite(length);
    if (!finite || length < 0.f) {
        s.status = LinearLightStatus::InvalidArgument;
        return s;
    }
    s.a = s.b = center;
    if (length == 0.f) {
        s.point = true;
        return s;
    }
    const double dl = std::sqrt(double(direction.x) * direction.x + double(direction.y) * direction.y +
                                double(direction.z) * direction.z);
    if (!(dl > 0.0) || !std::isfinite(dl)) {
        s.status = LinearLightStatus::InvalidArgument;
        return s;
    }
    const glm::dvec3 h = glm::dvec3(direction) * (0.5 * double(length) / dl);
    s.a = glm::vec3(glm::dvec3(center) - h);
    s.b = glm::vec3(glm::dvec3(center) + h);
    s.point = s.a == s.b;
    return s;
}

/// Endpoints of k equal sub-lights: k + 1 points a, ..., b (exact ends). Returns the count needed.
inline std::size_t linear_light_subdivide(const LinearLightSegment& s, std::uint32_t k, glm::vec3* out, std::size_t capacity) {
    if (k == 0 || s.status != LinearLightStatus::Ok) return 0;
    const std::size_t need = std::size_t(k) + 1;
    if (!out) return need;
    for (std::size_t i = 0; i < std::min(need, capacity); ++i) {
        if (i == 0) out[i] = s.a;
        else if (i == k) out[i] = s.b;
        else out[i] = glm::vec3(glm::dvec3(s.a) + (glm::dvec3(s.b) - glm::dvec3(s.a)) * (double(i) / double(k)));
    }
    return need;
}

namespace detail {

inline bool ll_finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Sutherland-Hodgman clip of a convex polygon (u, w) against c0 + cu u + cw w >= 0.
inline int ll_clip(const glm::dvec2* in, int n, double c0, double cu, double cw, glm::dvec2* out) {
    int m = 0;
    for (int i = 0; i < n; ++i) {
        const glm::dvec2 P = in[i], Q = in[(i + 1) % n];
        const double fp = c0 + cu * P.x + cw * P.y, fq = c0 + cu * Q.x + cw * Q.y;
        if (fp >= 0.0) out[m++] = P;
        if ((fp >= 0.0) != (fq >= 0.0)) {
            const double t = fp / (fp - fq);
            out[m++] = P + t * (Q - P);
        }
    }
    return m;
}

// Segment p -> q against a box (slab test) for s in [s0, 1].
inline bool ll_segment_hits_box(glm::dvec3 p, glm::dvec3 q, glm::dvec3 lo, glm::dvec3 hi, double s0) {
    const glm::dvec3 d = q - p;
    double t0 = s0, t1 = 1.0;
    for (int k = 0; k < 3; ++k) {
        if (d[k] == 0.0) {
            if (p[k] < lo[k] || p[k] > hi[k]) return false;
            continue;
        }
        double ta = (lo[k] - p[k]) / d[k], tb = (hi[k] - p[k]) / d[k];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
        if (t0 > t1) return false;
    }
    return true;
}

}  // namespace detail

/// The parameters t of the light points L(t) = a + t (b - a) whose ray from p (starting
/// min_fraction of the way) hits the box: an interval, because the box is convex. Closed form:
/// with u = s and w = s t the ray point p + u (a - p) + w (b - a) is linear in (u, w), so the box
/// is six half-planes on the triangle min_fraction <= u <= 1, 0 <= w <= u; the interval is the
/// range of t = w / u over the clipped polygon's vertices (projection of the box onto the line
/// from p, as 1D interval arithmetic). Empty when the box is not hit or input is not finite.
inline LinearLightInterval linear_light_box_interval(glm::vec3 p, glm::vec3 a, glm::vec3 b, const LinearLightBox& box,
                                                     float min_fraction = 1e-4f) {
    LinearLightInterval r;
    if (!detail::ll_finite(p) || !detail::ll_finite(a) || !detail::ll_finite(b) || !detail::ll_finite(box.lo) ||
        !detail::ll_finite(box.hi) || !std::isfinite(min_fraction))
        return r;
    const double u0 = std::min(std::max(double(min_fraction), 0.0), 1.0);
    const glm::dvec3 P(p), A(a), D = glm::dvec3(b) - glm::dvec3(a);
    if (D == glm::dvec3(0.0)) {  // point light: all or nothing
        if (detail::ll_segment_hits_box(P, A, glm::dvec3(box.lo), glm::dvec3(box.hi), u0)) {
            r.t0 = 0.f;
            r.t1 = 1.f;
        }
        return r;
    }
    glm::dvec2 poly[16], tmp[16];
    int n = 4;
    poly[0] = {u0, 0.0};
    poly[1] = {1.0, 0.0};
    poly[2] = {1.0, 1.0};
    poly[3] = {u0, u0};
    const glm::dvec3 AP = A - P;
    for (int k = 0; k < 3 && n > 0; ++k) {
        // p_k + u AP_k + w D_k >= lo_k  and  <= hi_k
        n = detail::ll_clip(poly, n, P[k] - double(box.lo[k]), AP[k], D[k], tmp);
        if (n == 0) break;
        n = detail::ll_clip(tmp, n, double(box.hi[k]) - P[k], -AP[k], -D[k], poly);
    }
    if (n == 0) return r;
    double tmin = 1e300, tmax = -1e300;
    for (int i = 0; i < n; ++i) {
        const double t = poly[i].x > 0.0 ? poly[i].y / poly[i].x : 0.0;
        tmin = std::min(tmin, t);
        tmax = std::max(tmax, t);
    }
    r.t0 = float(std::min(std::max(tmin, 0.0), 1.0));
    r.t1 = float(std::min(std::max(tmax, 0.0), 1.0));
    return r;
}

/// The t-range of the segment strictly above the receiver's tangent plane (n . (L(t) - p) > 0),
/// as a closed interval (its measure is what matters). n = (0,0,0) disables the test.
inline LinearLightInterval linear_light_tangent_interval(glm::vec3 p, glm::vec3 n, glm::vec3 a, glm::vec3 b) {
    LinearLightInterval r;
    if (!detail::ll_finite(p) || !detail::ll_finite(n) || !detail::ll_finite(a) || !detail::ll_finite(b)) return r;
    if (n == glm::vec3(0.f)) {
        r.t0 = 0.f;
        r.t1 = 1.f;
        return r;
    }
    const double f0 = glm::dot(glm::dvec3(n), glm::dvec3(a) - glm::dvec3(p));
    const double f1 = glm::dot(glm::dvec3(n), glm::dvec3(b) - glm::dvec3(p));
    if (f0 > 0.0 && f1 > 0.0) { r.t0 = 0.f; r.t1 = 1.f; }
    else if (f0 <= 0.0 && f1 <= 0.0) { /* empty */ }
    else {
        const double tz = f0 / (f0 - f1);  // zero crossing
        if (f0 > 0.0) { r.t0 = 0.f; r.t1 = float(tz); }
        else { r.t0 = float(tz); r.t1 = 1.f; }
    }
    return r;
}

/// Exact visible fraction of the segment from p with normal n (n = 0: no tangent-plane test) and
/// the boxes as occluders: measure(tangent interval minus the union of the boxes' intervals).
/// Zero-length segment: 1 if the point light is visible (above the tangent plane, not hidden),
/// else 0 - the point-light result. The union is merged in place of a 64-interval stack buffer;
/// more boxes are processed in chunks (exact: intervals are merged incrementally).
inline LinearLightFraction linear_light_visible_fraction(glm::vec3 p, glm::vec3 n, glm::vec3 a, glm::vec3 b,
                                                         const LinearLightBox* boxes, std::size_t count,
                                                         float min_fraction = 1e-4f) {
    LinearLightFraction f;
    if ((count && !boxes) || !detail::ll_finite(p) || !detail::ll_finite(n) || !detail::ll_finite(a) ||
        !detail::ll_finite(b) || !std::isfinite(min_fraction)) {
        f.status = LinearLightStatus::InvalidArgument;
        return f;
    }
    const LinearLightInterval H = linear_light_tangent_interval(p, n, a, b);
    if (a == b) {
        if (H.empty() || (n != glm::vec3(0.f) && !(glm::dot(glm::dvec3(n), glm::dvec3(a) - glm::dvec3(p)) > 0.0))) return f;
        for (std::size_t i = 0; i < count; ++i)
            if (!linear_light_box_interval(p, a, b, boxes[i], min_fraction).empty()) return f;
        f.fraction = 1.f;
        return f;
    }
    if (H.empty()) return f;
    // visible set = H minus union of occluded intervals; keep it as a sorted list of disjoint intervals
    double vis[2 * 65];
    int nv = 1;
    vis[0] = H.t0;
    vis[1] = H.t1;
    for (std::size_t i = 0; i < count && nv > 0; ++i) {
        const LinearLightInterval O = linear_light_box_interval(p, a, b, boxes[i], min_fraction);
        if (O.empty()) continue;
        double out[2 * 65];
        int no = 0;
        for (int k = 0; k < nv; ++k) {
            const double s0 = vis[2 * k], s1 = vis[2 * k + 1];
            if (O.t1 <= s0 || O.t0 >= s1) {  // no overlap
                out[2 * no] = s0; out[2 * no + 1] = s1; ++no;
                continue;
            }
            if (s0 < O.t0 && no < 64) { out[2 * no] = s0; out[2 * no + 1] = O.t0; ++no; }
            if (O.t1 < s1 && no < 64) { out[2 * no] = O.t1; out[2 * no + 1] = s1; ++no; }
        }
        nv = no;
        std::copy(out, out + 2 * no, vis);
    }
    double sum = 0.0;
    for (int k = 0; k < nv; ++k) sum += vis[2 * k + 1] - vis[2 * k];
    f.fraction = float(std::min(std::max(sum, 0.0), 1.0));
    return f;
}

/// The paper's shade() with illum = 1: each endpoint contributes its visibility-map value where its
/// shadow-map test passes (default kLinearLightDefaultVisibility where no skin covers the point).
inline float linear_light_shade(bool lit_a, float vis_a, bool lit_b, float vis_b) {
    const float va = std::isfinite(vis_a) ? std::min(std::max(vis_a, 0.f), 1.f) : kLinearLightDefaultVisibility;
    const float vb = std::isfinite(vis_b) ? std::min(std::max(vis_b, 0.f), 1.f) : kLinearLightDefaultVisibility;
    return (lit_a ? va : 0.f) + (lit_b ? vb : 0.f);
}

/// Depth discontinuity between two adjacent shadow-map samples (linear distances from the light):
/// max > min * (1 + threshold). Non-finite or non-positive distances never form one.
inline bool linear_light_is_discontinuity(float d0, float d1, float threshold) {
    if (!(d0 > 0.f) || !(d1 > 0.f) || !std::isfinite(d0) || !std::isfinite(d1) || !(threshold >= 0.f)) return false;
    return std::max(d0, d1) > std::min(d0, d1) * (1.f + threshold);
}

/// One skin vertex: world position (unprojected shadow-map sample) and its Gouraud value
/// (0 on the occluder side of the discontinuity, 1 on the receiver side).
struct LinearLightSkinVertex {
    glm::vec3 position{0.f};
    float value = 0.f;
};

struct LinearLightSkinResult {
    LinearLightStatus status = LinearLightStatus::Ok;
    std::size_t needed = 0;   ///< vertices (3 per triangle)
    std::size_t written = 0;  ///< min(needed, capacity)
    std::size_t cells = 0;    ///< 2x2 sample cells that hold a discontinuity
};

/// Skin triangulation of one 2x2 cell of samples, corners 0 (i,j), 1 (i+1,j), 2 (i,j+1),
/// 3 (i+1,j+1) with linear distances d[4]. A cell is a discontinuity cell when its largest distance
/// exceeds its smallest by the threshold; corners nearer than the midpoint of the two are occluder
/// (value 0), the others receiver (value 1). Both triangles (0,1,3) and (0,3,2) of a discontinuity
/// cell are emitted, so the skin of a staircase outline is one continuous surface (dropping the
/// one-class triangles leaves gaps where the default 0.5 shows through as bands).
/// Returns the number of triangles (0 or 2); tri[t][k] = corner index, value[c] per corner.
inline int linear_light_skin_cell(const float d[4], float threshold, int tri[2][3], float value[4]) {
    float lo = d[0], hi = d[0];
    for (int k = 0; k < 4; ++k) {
        if (!(d[k] > 0.f) || !std::isfinite(d[k])) return 0;
        lo = std::min(lo, d[k]);
        hi = std::max(hi, d[k]);
    }
    if (!linear_light_is_discontinuity(lo, hi, threshold)) return 0;
    // midpoint in double: 0.5f * (lo + hi) overflows near FLT_MAX and rounds onto hi for adjacent
    // floats, which left a cell with no receiver corner (found by fuzz_linear_light)
    const double mid = 0.5 * (static_cast<double>(lo) + static_cast<double>(hi));
    for (int k = 0; k < 4; ++k) value[k] = static_cast<double>(d[k]) < mid ? 0.f : 1.f;
    static const int cand[2][3] = {{0, 1, 3}, {0, 3, 2}};
    for (int t = 0; t < 2; ++t)
        for (int k = 0; k < 3; ++k) tri[t][k] = cand[t][k];
    return 2;
}

/// Vertices needed in the worst case for a W x H map: 6 per 2x2 cell.
inline std::size_t linear_light_skin_capacity(std::uint32_t w, std::uint32_t h) {
    return w < 2 || h < 2 ? 0 : std::size_t(w - 1) * std::size_t(h - 1) * 6;
}

/// Skin polygons of a shadow map (paper sec. 3, "triangulate depth discontinuities"): positions
/// (W*H world positions of the samples, row-major) and linear distances; triangles per
/// linear_light_skin_cell. Draw them with the other endpoint's view-projection, Gouraud-shaded by
/// `value` (screen-space linear: the paper's linear approximation of the rational falloff), with
/// MIN blending into a visibility map cleared to "no skin" (see glsl/linear_light.glsl).
inline LinearLightSkinResult linear_light_build_skin(const glm::vec3* positions, const float* dist, std::uint32_t w,
                                                     std::uint32_t h, float threshold, LinearLightSkinVertex* out,
                                                     std::size_t capacity) {
    LinearLightSkinResult r;
    if ((w && h && (!positions || !dist)) || (capacity && !out) || !(threshold >= 0.f) || !std::isfinite(threshold)) {
        r.status = LinearLightStatus::InvalidArgument;
        return r;
    }
    if (w < 2 || h < 2) return r;
    for (std::uint32_t j = 0; j + 1 < h; ++j)
        for (std::uint32_t i = 0; i + 1 < w; ++i) {
            const std::size_t k[4] = {std::size_t(j) * w + i, std::size_t(j) * w + i + 1, std::size_t(j + 1) * w + i,
                                      std::size_t(j + 1) * w + i + 1};
            bool finite = true;
            for (std::size_t c : k) finite = finite && detail::ll_finite(positions[c]);
            if (!finite) continue;
            const float d[4] = {dist[k[0]], dist[k[1]], dist[k[2]], dist[k[3]]};
            int tri[2][3];
            float value[4];
            const int nt = linear_light_skin_cell(d, threshold, tri, value);
            if (nt) ++r.cells;
            for (int t = 0; t < nt; ++t)
                for (int v = 0; v < 3; ++v) {
                    if (r.needed < capacity) out[r.needed] = {positions[k[tri[t][v]]], value[tri[t][v]]};
                    ++r.needed;
                }
        }
    r.written = std::min(r.needed, capacity);
    if (r.needed > capacity) r.status = LinearLightStatus::BufferTooSmall;
    return r;
}

}  // namespace shadowkit
