// shadowkit/linear_light.hpp - soft shadows from a line-segment light (Heidrich et al. 2000), the CPU side.
//
// The light is sampled at its two endpoints with shadow maps; between them the visible fraction is
// interpolated with a visibility map per endpoint, made by triangulating the depth discontinuities
// of the OTHER endpoint's shadow map into "skin" polygons (vertex value 0 on the occluder, 1 on the
// receiver), warping them into this endpoint's view and Gouraud-shading them. Lit regions keep the
// default visibility 0.5 per endpoint, so V = lit_a * v_a + lit_b * v_b (the paper's shade()). Also
// the exact visible fraction of the segment from a point for box occluders (1D interval
// arithmetic), the reference of the tests. GPU side: glsl/linear_light.glsl (skin vertex stage,
// lookups). docs/linear_light.md has a complete program.
//
// Usage:
//   #include <shadowkit/linear_light.hpp>
//   namespace sk = shadowkit;
//   sk::LinearLightSegment L = sk::linear_light_segment(center, direction, length);  // L.end_a, L.end_b
//   glm::vec3 ends[3];
//   sk::linear_light_subdivide(L, 2, ends, 3);    // 2 sub-lights: 3 endpoints, 3 shadow maps
//   // per endpoint shadow map (linear distances dist[W*H], world positions pos[W*H]):
//   std::vector<sk::LinearLightSkinVertex> skin(sk::linear_light_skin_capacity(W, H));
//   sk::LinearLightSkinResult s = sk::linear_light_build_skin(pos, dist, W, H, 0.05f, skin.data(), skin.size());
//   // draw s.count vertices with the other endpoint's view-projection into its visibility map
//   float v = sk::linear_light_shade(lit_a, vis_a, lit_b, vis_b);
//   // exact reference for boxes:
//   sk::LinearLightBox box{{-1, 0, -1}, {1, 1, 1}};
//   sk::LinearLightFraction f = sk::linear_light_visible_fraction(p, n, L.end_a, L.end_b, &box, 1);
//
// Conventions (used by every function):
//   * World space, right-handed, GLM. The light is the segment L(t) = end_a + t (end_b - end_a),
//     t in [0, 1]. A zero-length segment is a point light: every function then gives the
//     point-light result exactly.
// Lights: a light is its homogeneous position `light_position` = (x, y, z, w), as OpenGL's
// GL_POSITION and Everitt & Kilgard use it. w > 0: a point or spot light at xyz / w. w = 0: a
// directional light at infinity in direction xyz, the direction *toward* the light (its rays travel
// along -xyz). w < 0, (0, 0, 0, 0) and NaN/Inf are rejected with Status::InvalidLight.
//   * This header's light is a segment, not a light_position: its two endpoints `end_a`, `end_b`
//     (world positions, finite) or its center, direction and length (linear_light_segment). A point
//     light at light_position (w > 0) is the zero-length segment at xyz / w; a directional light
//     (w = 0) has no linear-light form. The GLSL snippet's per-endpoint lookup takes each endpoint
//     as a point light `vec4 light_position` (w = 1).
//   * Parameters: discontinuity threshold (relative, >= 0, default 0.05): adjacent shadow-map samples
//     with linear distances d0 < d1 form a discontinuity when d1 > d0 * (1 + threshold). Too small:
//     skins on sloped receivers (false penumbrae); too large: skins missed behind low occluders.
//     Subdivision k >= 1: the light is split into k linear lights (k + 1 shadow maps, 2k visibility
//     maps) when thin occluders hide the middle of the light from a point that sees both ends (the
//     paper's undersampling failure); V = mean over the sub-lights. min_fraction (exact reference,
//     in [0, 1), default 1e-4): rays start this fraction of the way from the receiver to the light
//     sample, so a receiver on an occluder's face does not occlude itself.
//   * Buffers are counted in elements of the pointer's type; results of buffer-filling functions
//     say `count` (elements written, a valid prefix) and `needed`. A null pointer with a non-zero
//     count or capacity is Status::InvalidArgument. No function allocates.
//   * Status: NaN/Inf in any input is Status::NonFinite; a finite input whose result does not fit a
//     float is Status::Overflow; `Ok` means every output is finite and in its documented range. A
//     non-Ok result's `detail` names the offending input and the rule ("length: < 0"), a static
//     string; nullptr when Ok.
//
// Based on:
//   W. Heidrich, S. Brabec, H.-P. Seidel, "Soft Shadow Maps for Linear Lights", Eurographics
//   Rendering Workshop 2000 (sec. 3: visibility map, skin polygons from the depth discontinuities
//   warped to the other sample point, Gouraud shading black on the occluder / white on the receiver,
//   default visibility 0.5, shade(); sec. 4: hardware passes; sec. 5: subdividing the light when
//   neither endpoint sees it). Course notes: SIGGRAPH 2004 "Real-Time Shadowing Techniques".
//
// MIT License. Copyright (c) shadowkit contributors.
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

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

/// A linear light: the segment from end_a to end_b (linear_light_segment).
struct LinearLightSegment {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    glm::vec3 end_a{0.f}, end_b{0.f};  ///< endpoints (world); equal for a zero-length (point) light
    bool is_point = false;             ///< zero length (or shorter than float resolution at the center): a point light
};

/// Axis-aligned box occluder (min and max corners, lo <= hi per axis).
struct LinearLightBox {
    glm::vec3 lo{0.f}, hi{0.f};
};

/// A closed parameter interval [t0, t1] of the segment; empty when !(t0 <= t1).
struct LinearLightInterval {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    float t0 = 1.f, t1 = 0.f;  ///< within [0, 1] when not empty
    bool empty() const { return !(t0 <= t1); }
};

/// Result of linear_light_visible_fraction.
struct LinearLightFraction {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    float fraction = 0.f;  ///< visible fraction of the segment in [0, 1] (point light: 0 or 1)
};

/// Result of linear_light_subdivide.
struct LinearLightSubdivideResult {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    std::size_t count = 0;   ///< endpoints written (a valid prefix; == needed when Ok)
    std::size_t needed = 0;  ///< endpoints of k sub-lights: k + 1
};

/// Default per-endpoint visibility of completely lit regions (paper sec. 3: 0.5 + 0.5 = 1).
constexpr float kLinearLightDefaultVisibility = 0.5f;

namespace detail {

inline bool ll_finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

inline bool ll_fits_float(const glm::dvec3& v) {
    const double m = double(std::numeric_limits<float>::max());
    return std::fabs(v.x) <= m && std::fabs(v.y) <= m && std::fabs(v.z) <= m;
}

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

// The box interval without validation (inputs checked by the caller).
inline LinearLightInterval ll_box_interval(glm::vec3 p, glm::vec3 a, glm::vec3 b, const LinearLightBox& box,
                                           float min_fraction) {
    LinearLightInterval r;
    r.status = Status::Ok;
    const double u0 = double(min_fraction);
    const glm::dvec3 P(p), A(a), D = glm::dvec3(b) - glm::dvec3(a);
    if (D == glm::dvec3(0.0)) {  // point light: all or nothing
        if (ll_segment_hits_box(P, A, glm::dvec3(box.lo), glm::dvec3(box.hi), u0)) {
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
        n = ll_clip(poly, n, P[k] - double(box.lo[k]), AP[k], D[k], tmp);
        if (n == 0) break;
        n = ll_clip(tmp, n, double(box.hi[k]) - P[k], -AP[k], -D[k], poly);
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

inline bool ll_box_ok(const LinearLightBox& b) { return b.lo.x <= b.hi.x && b.lo.y <= b.hi.y && b.lo.z <= b.hi.z; }

}  // namespace detail

/// The light from its center, direction (any length, not zero when length > 0) and length >= 0:
/// end_a = center - direction * length / 2, end_b = center + direction * length / 2 (computed in
/// double). Length 0 gives end_a == end_b == center (is_point). Errors: NonFinite (NaN/Inf in
/// center, direction or length), InvalidArgument (length < 0, zero direction with length > 0),
/// Overflow (an endpoint or end_b - end_a does not fit a float).
inline LinearLightSegment linear_light_segment(glm::vec3 center, glm::vec3 direction, float length) {
    LinearLightSegment s;
    if (!detail::ll_finite(center) || !detail::ll_finite(direction) || !std::isfinite(length)) {
        s.status = Status::NonFinite;
        s.detail = !detail::ll_finite(center) ? "center: NaN or Inf" : (!detail::ll_finite(direction) ? "direction: NaN or Inf" : "length: NaN or Inf");
        return s;
    }
    if (length < 0.f) {
        s.status = Status::InvalidArgument;
        s.detail = "length: < 0";
        return s;
    }
    if (length == 0.f) {
        s.end_a = s.end_b = center;
        s.is_point = true;
        s.status = Status::Ok;
        return s;
    }
    const double dl = std::sqrt(double(direction.x) * direction.x + double(direction.y) * direction.y +
                                double(direction.z) * direction.z);
    if (!(dl > 0.0)) {
        s.status = Status::InvalidArgument;
        s.detail = "direction: zero with length > 0";
        return s;
    }
    const glm::dvec3 h = glm::dvec3(direction) * (0.5 * double(length) / dl);
    const glm::dvec3 a = glm::dvec3(center) - h, b = glm::dvec3(center) + h;
    if (!detail::ll_fits_float(a) || !detail::ll_fits_float(b) ||
        !detail::ll_fits_float(glm::dvec3(glm::vec3(b)) - glm::dvec3(glm::vec3(a)))) {
        s.status = Status::Overflow;
        s.detail = "center, length: an endpoint beyond float";
        return s;
    }
    s.end_a = glm::vec3(a);
    s.end_b = glm::vec3(b);
    if (!detail::ll_finite(s.end_a) || !detail::ll_finite(s.end_b) || !detail::ll_finite(s.end_b - s.end_a)) {
        s.status = Status::Overflow;  // rounding to float reached Inf
        s.detail = "center, length: an endpoint beyond float";
        return s;
    }
    s.is_point = s.end_a == s.end_b;
    s.status = Status::Ok;
    return s;
}

/// Endpoints of k >= 1 equal sub-lights: k + 1 points end_a, ..., end_b (exact ends).
/// `out` holds out_capacity glm::vec3 elements; it needs k + 1 (`needed`). Errors: InvalidArgument
/// (k = 0, a segment whose status is not Ok, out null with out_capacity > 0), NonFinite (an endpoint
/// of a hand-made segment). BufferTooSmall: the first out_capacity endpoints are written.
inline LinearLightSubdivideResult linear_light_subdivide(const LinearLightSegment& segment, std::uint32_t k,
                                                         glm::vec3* out, std::size_t out_capacity) {
    LinearLightSubdivideResult r;
    if (k == 0 || segment.status != Status::Ok || (out_capacity && !out)) {
        r.status = Status::InvalidArgument;
        r.detail = k == 0 ? "k: 0" : (segment.status != Status::Ok ? "segment: status not Ok" : "out: null with out_capacity > 0");
        return r;
    }
    if (!detail::ll_finite(segment.end_a) || !detail::ll_finite(segment.end_b)) {
        r.status = Status::NonFinite;
        r.detail = "segment: an endpoint NaN or Inf";
        return r;
    }
    r.needed = std::size_t(k) + 1;
    r.count = std::min(r.needed, out_capacity);
    for (std::size_t i = 0; i < r.count; ++i) {
        if (i == 0) out[i] = segment.end_a;
        else if (i == k) out[i] = segment.end_b;
        else
            out[i] = glm::vec3(glm::dvec3(segment.end_a) +
                               (glm::dvec3(segment.end_b) - glm::dvec3(segment.end_a)) * (double(i) / double(k)));
    }
    r.status = r.count < r.needed ? Status::BufferTooSmall : Status::Ok;
    r.detail = r.count < r.needed ? "out_capacity: below k + 1 (see needed)" : nullptr;
    return r;
}

/// The parameters t of the light points L(t) = end_a + t (end_b - end_a) whose ray from p (starting
/// min_fraction of the way) hits the box: an interval, because the box is convex. Closed form:
/// with u = s and w = s t the ray point p + u (end_a - p) + w (end_b - end_a) is linear in (u, w),
/// so the box is six half-planes on the triangle min_fraction <= u <= 1, 0 <= w <= u; the interval
/// is the range of t = w / u over the clipped polygon's vertices (projection of the box onto the
/// line from p, as 1D interval arithmetic). Empty (with Ok) when the box is not hit.
/// Errors: NonFinite (any input), InvalidArgument (min_fraction outside [0, 1), box.lo > box.hi).
inline LinearLightInterval linear_light_box_interval(glm::vec3 p, glm::vec3 end_a, glm::vec3 end_b,
                                                     const LinearLightBox& box, float min_fraction = 1e-4f) {
    LinearLightInterval r;
    if (!detail::ll_finite(p) || !detail::ll_finite(end_a) || !detail::ll_finite(end_b) || !detail::ll_finite(box.lo) ||
        !detail::ll_finite(box.hi) || !std::isfinite(min_fraction)) {
        r.status = Status::NonFinite;
        r.detail = !detail::ll_finite(p) ? "p: NaN or Inf"
                   : (!detail::ll_finite(end_a) || !detail::ll_finite(end_b) ? "end_a, end_b: NaN or Inf"
                   : (!std::isfinite(min_fraction) ? "min_fraction: NaN or Inf" : "box: NaN or Inf"));
        return r;
    }
    if (!(min_fraction >= 0.f && min_fraction < 1.f) || !detail::ll_box_ok(box)) {
        r.status = Status::InvalidArgument;
        r.detail = !(min_fraction >= 0.f && min_fraction < 1.f) ? "min_fraction: outside [0, 1)" : "box: lo > hi";
        return r;
    }
    return detail::ll_box_interval(p, end_a, end_b, box, min_fraction);
}

/// The t-range of the segment strictly above the receiver's tangent plane (n . (L(t) - p) > 0),
/// as a closed interval (its measure is what matters). n = (0,0,0) disables the test (the whole
/// segment). Errors: NonFinite (any input).
inline LinearLightInterval linear_light_tangent_interval(glm::vec3 p, glm::vec3 n, glm::vec3 end_a, glm::vec3 end_b) {
    LinearLightInterval r;
    if (!detail::ll_finite(p) || !detail::ll_finite(n) || !detail::ll_finite(end_a) || !detail::ll_finite(end_b)) {
        r.status = Status::NonFinite;
        r.detail = !detail::ll_finite(p) ? "p: NaN or Inf" : (!detail::ll_finite(n) ? "n: NaN or Inf" : "end_a, end_b: NaN or Inf");
        return r;
    }
    r.status = Status::Ok;
    if (n == glm::vec3(0.f)) {
        r.t0 = 0.f;
        r.t1 = 1.f;
        return r;
    }
    const double f0 = glm::dot(glm::dvec3(n), glm::dvec3(end_a) - glm::dvec3(p));
    const double f1 = glm::dot(glm::dvec3(n), glm::dvec3(end_b) - glm::dvec3(p));
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
/// the boxes as occluders: measure(tangent interval minus the union of the boxes' intervals), by a
/// sweep over the intervals' ends (exact for any box_count; no allocation: the first 64 intervals
/// are cached on the stack, more are recomputed per step, O(box_count^2) box clips then).
/// Zero-length segment: 1 if the point light is visible (above the tangent plane, not hidden),
/// else 0 - the point-light result. `boxes` holds box_count LinearLightBox elements.
/// Errors: InvalidArgument (boxes null with box_count > 0, min_fraction outside [0, 1), a box with
/// lo > hi), NonFinite (any input).
inline LinearLightFraction linear_light_visible_fraction(glm::vec3 p, glm::vec3 n, glm::vec3 end_a, glm::vec3 end_b,
                                                         const LinearLightBox* boxes, std::size_t box_count,
                                                         float min_fraction = 1e-4f) {
    LinearLightFraction f;
    if (box_count && !boxes) {
        f.status = Status::InvalidArgument;
        f.detail = "boxes: null with box_count > 0";
        return f;
    }
    if (!detail::ll_finite(p) || !detail::ll_finite(n) || !detail::ll_finite(end_a) || !detail::ll_finite(end_b) ||
        !std::isfinite(min_fraction)) {
        f.status = Status::NonFinite;
        f.detail = !detail::ll_finite(p) ? "p: NaN or Inf"
                   : (!detail::ll_finite(n) ? "n: NaN or Inf"
                   : (!std::isfinite(min_fraction) ? "min_fraction: NaN or Inf" : "end_a, end_b: NaN or Inf"));
        return f;
    }
    if (!(min_fraction >= 0.f && min_fraction < 1.f)) {
        f.status = Status::InvalidArgument;
        f.detail = "min_fraction: outside [0, 1)";
        return f;
    }
    for (std::size_t i = 0; i < box_count; ++i) {
        if (!detail::ll_finite(boxes[i].lo) || !detail::ll_finite(boxes[i].hi)) {
            f.status = Status::NonFinite;
            f.detail = "boxes: NaN or Inf";
            return f;
        }
        if (!detail::ll_box_ok(boxes[i])) {
            f.status = Status::InvalidArgument;
            f.detail = "boxes: lo > hi";
            return f;
        }
    }
    f.status = Status::Ok;
    const LinearLightInterval H = linear_light_tangent_interval(p, n, end_a, end_b);
    if (end_a == end_b) {
        if (H.empty() || (n != glm::vec3(0.f) && !(glm::dot(glm::dvec3(n), glm::dvec3(end_a) - glm::dvec3(p)) > 0.0)))
            return f;
        for (std::size_t i = 0; i < box_count; ++i)
            if (!detail::ll_box_interval(p, end_a, end_b, boxes[i], min_fraction).empty()) return f;
        f.fraction = 1.f;
        return f;
    }
    if (H.empty()) return f;
    // visible measure = H minus the union of the occluded intervals: sweep t from H.t0 to H.t1,
    // jumping over covered stretches and adding the gaps
    constexpr std::size_t kCache = 64;
    double c0[kCache], c1[kCache];
    const std::size_t cached = std::min(box_count, kCache);
    for (std::size_t i = 0; i < cached; ++i) {
        const LinearLightInterval O = detail::ll_box_interval(p, end_a, end_b, boxes[i], min_fraction);
        c0[i] = O.empty() ? 2.0 : double(O.t0);
        c1[i] = O.empty() ? -1.0 : double(O.t1);
    }
    auto interval = [&](std::size_t i, double& t0, double& t1) {
        if (i < cached) {
            t0 = c0[i];
            t1 = c1[i];
            return;
        }
        const LinearLightInterval O = detail::ll_box_interval(p, end_a, end_b, boxes[i], min_fraction);
        t0 = O.empty() ? 2.0 : double(O.t0);
        t1 = O.empty() ? -1.0 : double(O.t1);
    };
    const double end = double(H.t1);
    double t = double(H.t0), visible = 0.0;
    while (t < end) {
        double reach = t, next = end;
        for (std::size_t i = 0; i < box_count; ++i) {
            double t0, t1;
            interval(i, t0, t1);
            if (t0 <= t && t1 > reach) reach = t1;          // covers t: jump to its end
            else if (t0 > t && t0 < next) next = t0;        // the next occluded stretch starts here
        }
        if (reach > t) {
            t = reach;
            continue;
        }
        visible += next - t;
        t = next;
    }
    f.fraction = float(std::min(std::max(visible, 0.0), 1.0));
    return f;
}

/// The paper's shade() with illum = 1: each endpoint contributes its visibility-map value where its
/// shadow-map test passes (default kLinearLightDefaultVisibility where no skin covers the point).
/// Total: each visibility is clamped to [0, 1] and a NaN/Inf one counts as the default 0.5; the
/// result is in [0, 2] (glsl/linear_light.glsl clamps the sum to [0, 1]).
inline float linear_light_shade(bool lit_a, float vis_a, bool lit_b, float vis_b) {
    const float va = std::isfinite(vis_a) ? std::min(std::max(vis_a, 0.f), 1.f) : kLinearLightDefaultVisibility;
    const float vb = std::isfinite(vis_b) ? std::min(std::max(vis_b, 0.f), 1.f) : kLinearLightDefaultVisibility;
    return (lit_a ? va : 0.f) + (lit_b ? vb : 0.f);
}

/// Depth discontinuity between two adjacent shadow-map samples (linear distances from the light):
/// max > min * (1 + threshold). Total: non-finite or non-positive distances and a negative or NaN
/// threshold never form one (false).
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

/// Skin triangles of one 2x2 cell (linear_light_skin_cell).
struct LinearLightSkinCell {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    int triangle_count = 0;        ///< 0 (no discontinuity) or 2
    int triangles[2][3] = {};      ///< corner indices of each triangle
    float value[4] = {};           ///< per corner: 0 occluder, 1 receiver
};

/// Result of linear_light_build_skin.
struct LinearLightSkinResult {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    std::size_t count = 0;   ///< vertices written (a valid prefix; == needed when Ok)
    std::size_t needed = 0;  ///< vertices of the whole skin (3 per triangle)
    std::size_t cells = 0;   ///< 2x2 sample cells that hold a discontinuity
};

/// Skin triangulation of one 2x2 cell of samples, corners 0 (i,j), 1 (i+1,j), 2 (i,j+1),
/// 3 (i+1,j+1) with linear distances distances[c] (> 0). A cell is a discontinuity cell when its
/// largest distance exceeds its smallest by the threshold (>= 0); corners nearer than the midpoint
/// of the two are occluder (value 0), the others receiver (value 1). Both triangles (0,1,3) and
/// (0,3,2) of a discontinuity cell are emitted, so the skin of a staircase outline is one
/// continuous surface (dropping the one-class triangles leaves gaps where the default 0.5 shows
/// through as bands). Errors: NonFinite (a distance or the threshold), InvalidArgument (a distance
/// <= 0, threshold < 0).
inline LinearLightSkinCell linear_light_skin_cell(glm::vec4 distances, float threshold) {
    LinearLightSkinCell r;
    if (!std::isfinite(threshold) || !std::isfinite(distances.x) || !std::isfinite(distances.y) ||
        !std::isfinite(distances.z) || !std::isfinite(distances.w)) {
        r.status = Status::NonFinite;
        r.detail = !std::isfinite(threshold) ? "threshold: NaN or Inf" : "distances: NaN or Inf";
        return r;
    }
    float lo = distances[0], hi = distances[0];
    for (int k = 0; k < 4; ++k) {
        if (!(distances[k] > 0.f)) {
            r.status = Status::InvalidArgument;
            r.detail = "distances: not > 0";
            return r;
        }
        lo = std::min(lo, distances[k]);
        hi = std::max(hi, distances[k]);
    }
    if (!(threshold >= 0.f)) {
        r.status = Status::InvalidArgument;
        r.detail = "threshold: < 0";
        return r;
    }
    r.status = Status::Ok;
    if (!linear_light_is_discontinuity(lo, hi, threshold)) return r;
    // midpoint in double: 0.5f * (lo + hi) overflows near FLT_MAX and rounds onto hi for adjacent
    // floats, which left a cell with no receiver corner (found by fuzz_linear_light)
    const double mid = 0.5 * (static_cast<double>(lo) + static_cast<double>(hi));
    for (int k = 0; k < 4; ++k) r.value[k] = static_cast<double>(distances[k]) < mid ? 0.f : 1.f;
    static const int cand[2][3] = {{0, 1, 3}, {0, 3, 2}};
    for (int t = 0; t < 2; ++t)
        for (int k = 0; k < 3; ++k) r.triangles[t][k] = cand[t][k];
    r.triangle_count = 2;
    return r;
}

/// Vertices needed in the worst case for a width x height map: 6 per 2x2 cell. Total: 0 below
/// 2 x 2, saturates at SIZE_MAX.
inline std::size_t linear_light_skin_capacity(std::uint32_t width, std::uint32_t height) {
    if (width < 2 || height < 2) return 0;
    const std::size_t cw = std::size_t(width - 1), ch = std::size_t(height - 1);
    const std::size_t max = std::numeric_limits<std::size_t>::max();
    if (cw > max / ch || cw * ch > max / 6) return max;
    return cw * ch * 6;
}

/// Skin polygons of a shadow map (paper sec. 3, "triangulate depth discontinuities"): triangles per
/// linear_light_skin_cell. Draw them with the other endpoint's view-projection, Gouraud-shaded by
/// `value` (screen-space linear: the paper's linear approximation of the rational falloff), with
/// MIN blending into a visibility map cleared to "no skin" (see glsl/linear_light.glsl).
/// `positions` (world positions of the samples) and `distances` (linear distances from the light,
/// > 0) hold width * height elements each, row-major; `out` holds out_capacity
/// LinearLightSkinVertex elements; it needs 6 per discontinuity cell (`needed`, at most
/// linear_light_skin_capacity(width, height)). Maps below 2 x 2 have no cells (Ok, needed 0).
/// Errors (count 0): InvalidArgument (a null map with width * height > 0, out null with
/// out_capacity > 0, threshold < 0, a distance <= 0), NonFinite (threshold, a position or a
/// distance). BufferTooSmall: the first out_capacity vertices are written.
inline LinearLightSkinResult linear_light_build_skin(const glm::vec3* positions, const float* distances,
                                                     std::uint32_t width, std::uint32_t height, float threshold,
                                                     LinearLightSkinVertex* out, std::size_t out_capacity) {
    LinearLightSkinResult r;
    if ((width && height && (!positions || !distances)) || (out_capacity && !out)) {
        r.status = Status::InvalidArgument;
        r.detail = width && height && !positions ? "positions: null with width * height > 0"
                   : (width && height && !distances ? "distances: null with width * height > 0" : "out: null with out_capacity > 0");
        return r;
    }
    if (!std::isfinite(threshold)) {
        r.status = Status::NonFinite;
        r.detail = "threshold: NaN or Inf";
        return r;
    }
    if (!(threshold >= 0.f)) {
        r.status = Status::InvalidArgument;
        r.detail = "threshold: < 0";
        return r;
    }
    if (width < 2 || height < 2) {
        r.status = Status::Ok;
        return r;
    }
    for (std::uint32_t j = 0; j + 1 < height; ++j)
        for (std::uint32_t i = 0; i + 1 < width; ++i) {
            const std::size_t k[4] = {std::size_t(j) * width + i, std::size_t(j) * width + i + 1,
                                      std::size_t(j + 1) * width + i, std::size_t(j + 1) * width + i + 1};
            for (std::size_t c : k)
                if (!detail::ll_finite(positions[c])) {
                    r = LinearLightSkinResult{};
                    r.status = Status::NonFinite;
                    r.detail = "positions: NaN or Inf";
                    return r;
                }
            const LinearLightSkinCell cell =
                linear_light_skin_cell(glm::vec4(distances[k[0]], distances[k[1]], distances[k[2]], distances[k[3]]),
                                       threshold);
            if (cell.status != Status::Ok) {
                r = LinearLightSkinResult{};
                r.status = cell.status;
                r.detail = cell.detail;
                return r;
            }
            if (cell.triangle_count) ++r.cells;
            for (int t = 0; t < cell.triangle_count; ++t)
                for (int v = 0; v < 3; ++v) {
                    const int c = cell.triangles[t][v];
                    if (r.needed < out_capacity) out[r.needed] = {positions[k[c]], cell.value[c]};
                    ++r.needed;
                }
        }
    r.count = std::min(r.needed, out_capacity);
    r.status = r.needed > out_capacity ? Status::BufferTooSmall : Status::Ok;
    r.detail = r.needed > out_capacity ? "out_capacity: below needed (see needed)" : nullptr;
    return r;
}

}  // namespace shadowkit
