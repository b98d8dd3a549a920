// shadowkit/infinite_projection.hpp - perspective projections with the far plane at infinity (Everitt-Kilgard P_inf), reversed-Z, window depth and depth resolution
//
// Usage:
//   #include <shadowkit/infinite_projection.hpp>
//   namespace sk = shadowkit;
//   sk::ProjectionDepth depth;                    // far +inf, GL clip depth, no reversed-Z
//   depth.near_z = 0.1f;
//   depth.epsilon = sk::projection_infinite_epsilon_bound(fovy, aspect, depth.clip_depth, depth.reversed_z,
//                                                         sk::DepthFormat::Fixed24).epsilon;
//   sk::ProjectionResult pr = sk::projection_perspective(fovy, aspect, depth);
//   if (pr.status == sk::Status::Ok) glUniformMatrix4fv(loc, 1, GL_FALSE, &pr.matrix[0][0]);
//   sk::ProjectionValue step = sk::projection_depth_resolution(depth, sk::DepthFormat::Float32, 100.0);
//
// Conventions: right-handed eye space (the camera looks down -z), GLM column-major matrices
// (m[column][row]); eye distance d = -z_e > 0; window depth for glDepthRange(0, 1). NDC depth of
// eye distance d is always A + B / d (projection_depth_mapping); every function derives from (A, B).
// Clip depth: ClipDepth::NegativeOneToOne (OpenGL) or ZeroToOne (glClipControl / D3D / Vulkan);
// reversed_z maps the near plane to depth 1 and the far plane (or infinity) to 0 (NDC -1 for GL).
// Results: a struct whose first member is `status`; `Ok` only with finite outputs in their
// documented range; a non-Ok result's `detail` names the offending input and the rule ("near_z: not
// > 0"), a static string, nullptr when Ok. No light, no buffers, no allocation.
// Limits: near_z finite and > 0; far_z > near_z with far / near >= 1.001 (GL) or 1.0005 (ZeroToOne)
// - closer planes make the float32 depth row |A| > 2048 and the near and far planes land off their
// NDC values (near 0.1, far 0.1 + 1 ulp: +0.90 and +2.90), so they give Status::Overflow.
//
// Based on:
//   C. Everitt, M. J. Kilgard, "Practical and Robust Stenciled Shadow Volumes for Hardware-Accelerated
//   Rendering", NVIDIA 2002 (section 3.2.1: P_inf as the limit of glFrustum when Far -> inf; the
//   epsilon-tweaked P_inf of the original paper).
//   J. Blinn, "A Trip Down the Graphics Pipeline: The Homogeneous Perspective Transform", IEEE CG&A 1993.
//   E. Lengyel, "Advanced Stencil Shadow and Penumbral Wedge Rendering", GDC 2005 (viewport depth formula).
//
// MIT License. Copyright (c) shadowkit contributors.
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include <cmath>
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
#ifndef SHADOWKIT_CLIP_DEPTH_DEFINED
#define SHADOWKIT_CLIP_DEPTH_DEFINED
/// Clip-space depth range of the projection: OpenGL [-1,1] or D3D/Vulkan/glClipControl [0,1].
enum class ClipDepth { NegativeOneToOne, ZeroToOne };
#endif
#ifndef SHADOWKIT_DEPTH_FORMAT_DEFINED
#define SHADOWKIT_DEPTH_FORMAT_DEFINED
/// Depth-buffer storage format.
enum class DepthFormat { Float32, Fixed24, Fixed16 };
#endif
/// Depth part of a projection: near and far planes, clip depth, reversed-Z and the
/// Everitt-Kilgard epsilon. The defaults are a usable infinite GL projection with near 0.1.
struct ProjectionDepth {
    float near_z = 0.1f;                                   ///< eye distance of the near plane, finite, > 0
    float far_z = std::numeric_limits<float>::infinity();  ///< > near_z (far / near >= 1.001); +inf: far plane at infinity
    ClipDepth clip_depth = ClipDepth::NegativeOneToOne;
    bool reversed_z = false;                               ///< near -> window depth 1, far (or infinity) -> 0
    /// Everitt-Kilgard tweak, infinite far only: a vertex at infinity (w = 0) lands at NDC depth
    /// 1 - epsilon (reversed: -1 + epsilon, or +epsilon for ZeroToOne) instead of exactly on the far
    /// clip plane. Range [0, 0.5]; 0 with a finite far plane. projection_infinite_epsilon_bound() gives the minimum.
    float epsilon = 0.0f;
};

/// A projection matrix.
struct ProjectionResult {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    glm::mat4 matrix = glm::mat4(0.0f);  ///< finite when Ok; row 3 is (0, 0, -1, 0)
};

/// A scalar result (a depth, a distance). `value` is 0 unless status is Ok.
struct ProjectionValue {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    double value = 0.0;
};

/// An eye distance recovered from a window depth.
struct ProjectionEyeDistance {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    bool at_infinity = false;  ///< true (with Ok): the window depth of infinity (infinite far plane); value is 0
    double value = 0.0;        ///< eye distance, finite and > 0, when Ok and !at_infinity
};

/// NDC depth as a function of eye distance d: ndc(d) = A + B / d.
struct ProjectionDepthMapping {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    double A = 0.0;
    double B = 0.0;
};

/// Epsilon bounds for the tweaked infinite projection (derivation at projection_infinite_epsilon_bound).
struct ProjectionEpsilonBound {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    float clip = 0.0f;    ///< minimum keeping w = 0 vertices inside the clip volume in float32
    float storage = 0.0f; ///< minimum keeping infinity strictly inside the depth clear value
    float epsilon = 0.0f; ///< max(clip, storage), in [0, 0.5] when Ok
};

namespace detail {
inline bool ip_fits_float(double v) {
    return std::isfinite(v) && std::fabs(v) <= static_cast<double>(std::numeric_limits<float>::max());
}
// Largest |A| of the depth row that float32 keeps meaningful: rounding A and B (and evaluating
// A d + B in float) moves NDC by about 2 |A| 2^-24 <= 2.4e-4 at this bound.
constexpr double kIpMaxDepthRowA = 2048.0;
// The (A, B) of a validated ProjectionDepth (no checks).
inline void ip_mapping(const ProjectionDepth& p, double& A, double& B) {
    const double N = static_cast<double>(p.near_z);
    const bool gl = p.clip_depth == ClipDepth::NegativeOneToOne;
    if (std::isinf(p.far_z)) {
        const double e = static_cast<double>(p.epsilon);
        A = 1.0 - e;
        B = gl ? -(2.0 - e) * N : -(1.0 - e) * N;
        if (p.reversed_z) {
            if (gl) { A = -A; B = -B; }          // ndc(inf) = -1 + eps, ndc(N) = 1
            else { A = e; B = (1.0 - e) * N; }   // ndc(inf) = eps,      ndc(N) = 1
        }
    } else {
        const double F = static_cast<double>(p.far_z);
        const double FmN = F - N;
        if (gl) { A = (F + N) / FmN; B = -2.0 * F * N / FmN; }
        else { A = F / FmN; B = -F * N / FmN; }
        if (p.reversed_z) {
            if (gl) { A = -A; B = -B; }
            else { A = -N / FmN; B = F * N / FmN; }  // 1 - ndc
        }
    }
}
// `why` receives where a non-Ok status came from (a static string).
inline Status ip_fail(const char*& why, Status s, const char* what) {
    why = what;
    return s;
}
inline Status ip_check_fov_aspect(float fovy, float aspect, const char*& why) {
    if (!std::isfinite(fovy)) return ip_fail(why, Status::NonFinite, "fovy: NaN or Inf");
    if (!std::isfinite(aspect)) return ip_fail(why, Status::NonFinite, "aspect: NaN or Inf");
    if (!(fovy > 0.0f && static_cast<double>(fovy) < 3.14159265358979323846))
        return ip_fail(why, Status::InvalidArgument, "fovy: outside (0, pi)");
    if (!(aspect > 0.0f)) return ip_fail(why, Status::InvalidArgument, "aspect: not > 0");
    return Status::Ok;
}
// projection_validate, with where a non-Ok status came from.
inline Status ip_validate(const ProjectionDepth& p, const char*& why) {
    if (!std::isfinite(p.near_z)) return ip_fail(why, Status::NonFinite, "near_z: NaN or Inf");
    if (std::isnan(p.far_z) || p.far_z == -std::numeric_limits<float>::infinity())
        return ip_fail(why, Status::NonFinite, "far_z: NaN or -Inf");
    if (!std::isfinite(p.epsilon)) return ip_fail(why, Status::NonFinite, "epsilon: NaN or Inf");
    if (!(p.near_z > 0.0f)) return ip_fail(why, Status::InvalidArgument, "near_z: not > 0");
    if (!(p.far_z > p.near_z)) return ip_fail(why, Status::InvalidArgument, "far_z: not > near_z");
    if (!(p.epsilon >= 0.0f && p.epsilon <= 0.5f)) return ip_fail(why, Status::InvalidArgument, "epsilon: outside [0, 0.5]");
    if (std::isfinite(p.far_z) && p.epsilon != 0.0f)
        return ip_fail(why, Status::InvalidArgument, "epsilon: not 0 with a finite far_z");
    if (p.clip_depth != ClipDepth::NegativeOneToOne && p.clip_depth != ClipDepth::ZeroToOne)
        return ip_fail(why, Status::InvalidArgument, "clip_depth: unknown ClipDepth");
    double A = 0.0, B = 0.0;
    ip_mapping(p, A, B);
    // a subnormal B (near ~1e-38) has too few bits: NDC of near far off
    if (!ip_fits_float(A) || !ip_fits_float(B) || std::fabs(A) > kIpMaxDepthRowA ||
        !(std::fabs(B) >= static_cast<double>(std::numeric_limits<float>::min())))
        return ip_fail(why, Status::Overflow, "far_z: too close to near_z (depth row beyond float), or near_z subnormal");
    return Status::Ok;
}
} // namespace detail

/// Checks a ProjectionDepth: NonFinite for NaN near, far or epsilon (or an infinite near /
/// epsilon, a far of -inf); InvalidArgument for near <= 0, far <= near, epsilon outside [0, 0.5]
/// or != 0 with a finite far plane, an unknown clip_depth; Overflow when the depth row cannot be
/// represented in float32 (|A| > 2048: far / near < 1.001 for GL, < 1.0005 for ZeroToOne; an
/// entry beyond float range; |B| below FLT_MIN, i.e. near ~1e-38 and less). Ok otherwise.
inline Status projection_validate(const ProjectionDepth& p) {
    const char* why = nullptr;
    return detail::ip_validate(p, why);
}

/// Coefficients of ndc(d) = A + B / d (computed in double); status as projection_validate.
///   finite, GL   : A = (F+N)/(F-N), B = -2FN/(F-N)   (glFrustum row 3; Everitt-Kilgard eq. for P)
///   finite, ZO   : A = F/(F-N),     B = -FN/(F-N)
///   infinite, GL : A = 1 - eps,     B = -(2 - eps) N (limit Far -> inf, Everitt-Kilgard P_inf, tweaked)
///   infinite, ZO : A = 1 - eps,     B = -(1 - eps) N
///   reversed-Z   : GL: ndc -> -ndc; ZO: ndc -> 1 - ndc (eps then measured from -1 resp. 0)
inline ProjectionDepthMapping projection_depth_mapping(const ProjectionDepth& p) {
    ProjectionDepthMapping m;
    m.status = detail::ip_validate(p, m.detail);
    if (m.status != Status::Ok) return m;
    detail::ip_mapping(p, m.A, m.B);
    return m;
}

/// Off-center frustum (glFrustum-style x/y: left/right/bottom/top on the near plane) with the depth
/// behavior of `depth`. Row 3 of the matrix is (0, 0, -A, B) so that z_c / w_c = A + B / d.
/// NonFinite for a NaN/Inf side, InvalidArgument for left >= right or bottom >= top, Overflow when an
/// entry is beyond float range or rounds to 0; otherwise the status of projection_validate(depth).
inline ProjectionResult projection_frustum(float left, float right, float bottom, float top, const ProjectionDepth& depth) {
    ProjectionResult r;
    const ProjectionDepthMapping m = projection_depth_mapping(depth);
    if (m.status != Status::Ok) { r.status = m.status; r.detail = m.detail; return r; }
    if (!(std::isfinite(left) && std::isfinite(right) && std::isfinite(bottom) && std::isfinite(top))) {
        r.status = Status::NonFinite;
        r.detail = !(std::isfinite(left) && std::isfinite(right)) ? "left, right: NaN or Inf" : "bottom, top: NaN or Inf";
        return r;
    }
    if (!(left < right) || !(bottom < top)) {
        r.status = Status::InvalidArgument;
        r.detail = !(left < right) ? "right: not > left" : "top: not > bottom";
        return r;
    }
    const double N = static_cast<double>(depth.near_z);
    const double l = left, rt = right, b = bottom, t = top;
    const double m00 = 2.0 * N / (rt - l), m11 = 2.0 * N / (t - b);
    const double m20 = (rt + l) / (rt - l), m21 = (t + b) / (t - b);
    if (!detail::ip_fits_float(m00) || !detail::ip_fits_float(m11) || !detail::ip_fits_float(m20) ||
        !detail::ip_fits_float(m21) || static_cast<float>(m00) == 0.0f || static_cast<float>(m11) == 0.0f) {
        r.status = Status::Overflow;
        r.detail = "left, right, bottom, top: a matrix entry beyond float or 0";
        return r;
    }
    r.matrix[0][0] = static_cast<float>(m00);
    r.matrix[1][1] = static_cast<float>(m11);
    r.matrix[2][0] = static_cast<float>(m20);
    r.matrix[2][1] = static_cast<float>(m21);
    r.matrix[2][2] = static_cast<float>(-m.A);
    r.matrix[2][3] = -1.0f;
    r.matrix[3][2] = static_cast<float>(m.B);
    r.status = Status::Ok;
    return r;
}

/// Symmetric perspective (gluPerspective-style): fovy is the full vertical angle in radians, in
/// (0, pi); aspect = width / height, finite and > 0. NonFinite for NaN fovy or NaN/Inf aspect,
/// InvalidArgument outside those ranges, Overflow when cot(fovy / 2) / aspect is beyond float range
/// or rounds to 0; otherwise the status of projection_validate(depth).
inline ProjectionResult projection_perspective(float fovy, float aspect, const ProjectionDepth& depth) {
    ProjectionResult r;
    const Status s = detail::ip_validate(depth, r.detail);
    if (s != Status::Ok) { r.status = s; return r; }
    r.status = detail::ip_check_fov_aspect(fovy, aspect, r.detail);
    if (r.status != Status::Ok) return r;
    const double t = std::tan(0.5 * static_cast<double>(fovy));
    const double m11 = 1.0 / t;
    const double m00 = m11 / static_cast<double>(aspect);
    if (!detail::ip_fits_float(m00) || !detail::ip_fits_float(m11) || !(static_cast<float>(m00) > 0.0f) ||
        !(static_cast<float>(m11) > 0.0f)) {
        r.status = Status::Overflow;
        r.detail = "fovy, aspect: a matrix entry beyond float or 0";
        return r;
    }
    double A = 0.0, B = 0.0;
    detail::ip_mapping(depth, A, B);
    r.matrix[0][0] = static_cast<float>(m00);
    r.matrix[1][1] = static_cast<float>(m11);
    r.matrix[2][2] = static_cast<float>(-A);
    r.matrix[2][3] = -1.0f;
    r.matrix[3][2] = static_cast<float>(B);
    return r;
}

/// Convenience: infinite far plane (Everitt-Kilgard P_inf), optional epsilon tweak.
inline ProjectionResult projection_perspective_infinite(float fovy, float aspect, float near_z,
                                                        ClipDepth clip = ClipDepth::NegativeOneToOne,
                                                        bool reversed_z = false, float epsilon = 0.0f) {
    ProjectionDepth d;
    d.near_z = near_z;
    d.far_z = std::numeric_limits<float>::infinity();
    d.clip_depth = clip;
    d.reversed_z = reversed_z;
    d.epsilon = epsilon;
    return projection_perspective(fovy, aspect, d);
}

/// Convenience: finite far plane (equals glm::perspectiveRH_NO / _ZO when not reversed).
inline ProjectionResult projection_perspective_finite(float fovy, float aspect, float near_z, float far_z,
                                                      ClipDepth clip = ClipDepth::NegativeOneToOne,
                                                      bool reversed_z = false) {
    ProjectionDepth d;
    d.near_z = near_z;
    d.far_z = far_z;
    d.clip_depth = clip;
    d.reversed_z = reversed_z;
    return projection_perspective(fovy, aspect, d);
}

/// NDC depth of eye distance d (d > 0; d = +inf: the depth of a w = 0 vertex). Distances inside
/// [near, far] give [-1, 1] (GL) or [0, 1] (ZeroToOne); closer ones lie below that range (clipped).
/// NonFinite for NaN d, InvalidArgument for d <= 0, Overflow when the value is beyond float range
/// (d far below the near plane, e.g. 1e-310 with near 0.1); otherwise the status of projection_validate(p).
inline ProjectionValue projection_ndc_depth(const ProjectionDepth& p, double eye_distance) {
    ProjectionValue v;
    const ProjectionDepthMapping m = projection_depth_mapping(p);
    if (m.status != Status::Ok) { v.status = m.status; v.detail = m.detail; return v; }
    if (std::isnan(eye_distance)) { v.status = Status::NonFinite; v.detail = "eye_distance: NaN"; return v; }
    if (!(eye_distance > 0.0)) { v.status = Status::InvalidArgument; v.detail = "eye_distance: not > 0"; return v; }
    const double value = std::isinf(eye_distance) ? m.A : m.A + m.B / eye_distance;
    if (!detail::ip_fits_float(value)) { v.status = Status::Overflow; v.detail = "eye_distance: the depth is beyond float"; return v; }
    v.value = value;
    v.status = Status::Ok;
    return v;
}

/// Window depth for glDepthRange(0, 1): GL 0.5 ndc + 0.5, ZeroToOne ndc (Lengyel's viewport depth
/// with dmin = 0, dmax = 1). In [0, 1] for d in [near, far]; statuses as projection_ndc_depth.
inline ProjectionValue projection_window_depth(const ProjectionDepth& p, double eye_distance) {
    ProjectionValue v = projection_ndc_depth(p, eye_distance);
    if (v.status == Status::Ok && p.clip_depth == ClipDepth::NegativeOneToOne) v.value = 0.5 * v.value + 0.5;
    return v;
}

/// Inverse of projection_window_depth: the eye distance whose window depth is `window`, in [0, 1].
/// at_infinity (with Ok) for the window depth of infinity. NonFinite for NaN window,
/// InvalidArgument for a window outside [0, 1] or outside the mapped range (beyond the depth of
/// infinity of a tweaked projection), Overflow for a distance beyond float range.
inline ProjectionEyeDistance projection_eye_distance_from_window_depth(const ProjectionDepth& p, double window) {
    ProjectionEyeDistance v;
    const ProjectionDepthMapping m = projection_depth_mapping(p);
    if (m.status != Status::Ok) { v.status = m.status; v.detail = m.detail; return v; }
    if (std::isnan(window)) { v.status = Status::NonFinite; v.detail = "window: NaN"; return v; }
    if (!(window >= 0.0 && window <= 1.0)) { v.status = Status::InvalidArgument; v.detail = "window: outside [0, 1]"; return v; }
    const double ndc = p.clip_depth == ClipDepth::NegativeOneToOne ? 2.0 * window - 1.0 : window;
    const double den = ndc - m.A;
    if (den == 0.0) {
        if (!std::isinf(p.far_z)) {  // not reached: A is outside [0, 1] for finite far
            v.status = Status::InvalidArgument;
            v.detail = "window: the depth of infinity with a finite far_z";
            return v;
        }
        v.at_infinity = true;
        v.status = Status::Ok;
        return v;
    }
    const double d = m.B / den;
    if (!(d > 0.0)) { v.status = Status::InvalidArgument; v.detail = "window: beyond the depth of infinity"; return v; }
    if (!detail::ip_fits_float(d)) { v.status = Status::Overflow; v.detail = "window: the distance is beyond float"; return v; }
    v.value = d;
    v.status = Status::Ok;
    return v;
}

namespace detail {
// Gap between x (a float32 value) and the next representable float32 away from zero... or toward
// zero when x is at the top of [0, 1]: the spacing of the grid the value is stored on.
inline double ip_float_gap(double x) {
    const float f = static_cast<float>(x);
    const float up = std::nextafter(f, std::numeric_limits<float>::infinity());
    const float dn = std::nextafter(f, -std::numeric_limits<float>::infinity());
    if (f >= 1.0f) return static_cast<double>(f) - static_cast<double>(dn);
    return static_cast<double>(up) - static_cast<double>(f);
}
} // namespace detail

/// Depth resolution: the eye-space distance between adjacent representable depth values at eye
/// distance d, to first order  delta_d = delta_w / |dw/dd|,  dw/dd = -s B / d^2  (s = 1/2 for GL).
/// delta_w is the larger of
///   - the storage step of `format` at w(d): 1/(2^n - 1) for n-bit fixed, the float32 spacing at w
///     for Float32 (tiny near 0, 2^-24 just below 1),
///   - the float32 step of the NDC value the pipeline computes before the viewport transform (times
///     1/2 for GL): for GL clip depth NDC near -1 or +1 has steps of 2^-24, which is why reversed-Z
///     with GL's [-1, 1] gains nothing and reversed-Z needs ZeroToOne (glClipControl) + Float32.
/// Ok: value finite and > 0. NonFinite for NaN/Inf d, InvalidArgument for d outside [near, far]
/// or an unknown format, Overflow when the step is beyond float range; else projection_validate(p).
inline ProjectionValue projection_depth_resolution(const ProjectionDepth& p, DepthFormat format, double eye_distance) {
    ProjectionValue v;
    const ProjectionDepthMapping m = projection_depth_mapping(p);
    if (m.status != Status::Ok) { v.status = m.status; v.detail = m.detail; return v; }
    if (!std::isfinite(eye_distance)) { v.status = Status::NonFinite; v.detail = "eye_distance: NaN or Inf"; return v; }
    if (!(eye_distance > 0.0)) { v.status = Status::InvalidArgument; v.detail = "eye_distance: not > 0"; return v; }
    const bool gl = p.clip_depth == ClipDepth::NegativeOneToOne;
    const double s = gl ? 0.5 : 1.0;
    const double ndc = m.A + m.B / eye_distance;
    double w = gl ? 0.5 * ndc + 0.5 : ndc;
    // Only distances inside the depth range [near, far] have a stored depth (slack for rounding).
    if (!(w >= -1e-12 && w <= 1.0 + 1e-12)) { v.status = Status::InvalidArgument; v.detail = "eye_distance: outside [near_z, far_z]"; return v; }
    w = w < 0.0 ? 0.0 : (w > 1.0 ? 1.0 : w);
    double step = 0.0;
    switch (format) {
    case DepthFormat::Float32: step = detail::ip_float_gap(w); break;
    case DepthFormat::Fixed24: step = 1.0 / 16777215.0; break;
    case DepthFormat::Fixed16: step = 1.0 / 65535.0; break;
    default: v.status = Status::InvalidArgument; v.detail = "format: unknown DepthFormat"; return v;
    }
    const double ndc_step = s * detail::ip_float_gap(std::fabs(ndc));
    if (ndc_step > step) step = ndc_step;
    const double slope = std::fabs(s * m.B) / eye_distance / eye_distance;
    const double value = step / slope;
    if (!(slope > 0.0) || !detail::ip_fits_float(value) || !(value > 0.0)) {
        v.status = Status::Overflow;
        v.detail = "eye_distance: the step is beyond float";
        return v;
    }
    v.value = value;
    v.status = Status::Ok;
    return v;
}

/// Minimum epsilon for the tweaked infinite projection.
///
/// Derivation (clip bound). A w = 0 vertex x (a direction) reaches clip space either as P (V x) or as
/// (P V) x in float32, u = 2^-24, each operation with relative error <= k u (k = ulps_per_op; 1 for
/// IEEE round-to-nearest, which GLSL 4.x and D3D10+ require for + and *). The depth row of P is
/// (0, 0, c, B) with c = -(1 - eps) (reversed GL: c = 1 - eps) and the w row (0, 0, -1, 0); for an
/// affine V (rigid + uniform scale) the rows of P V are c V_2 and -V_2, so w_c = -V_2.x needs one
/// 3-term dot product (error <= 3ku S) and z_c one rounding of c V_2 plus the same dot (<= 4ku S),
/// with S = sum |V_i2 x_i| <= |x| |V_2|. The true values are z = (1 - eps) w, so z_c <= w_c holds if
///     eps * w >= 7 k u S   <=>   eps >= 7 k u kappa,   kappa = S / w <= 1 / cos(theta),
/// theta the angle between x and the view axis. Inside the frustum theta <= theta_max with
/// 1/cos(theta_max) = sqrt(1 + tan^2(fovy/2) (1 + aspect^2)). Rounding c itself costs one more u:
///     clip bound = (7 k kappa + 1) u        (P(Vx) alone would need only k u).
/// For fovy = 90 deg, aspect 1, k = 1: kappa = sqrt(3), bound = 13.1 u = 7.8e-7 (Everitt and Kilgard
/// used a similar few-ulp margin). Reversed-Z ZeroToOne has c = -eps, so z_c = eps w (1 +- 4ku kappa)
/// stays >= 0 and <= w for any eps in [0, 0.5]: its clip bound is 0 (infinity maps to exactly 0).
/// With eps = 0 the non-reversed rows are exactly c = -1, so IEEE hardware keeps w = 0 vertices on
/// the far plane exactly; the bound protects pipelines that round P V or fold in other transforms.
///
/// Storage bound. Depth is cleared to 1 (reversed: 0); the vertex at infinity must store strictly
/// inside that value, i.e. the window gap g (GL: eps/2, ZeroToOne: eps) must be at least one storage
/// step: n-bit fixed: g >= 1/(2^n - 1) -> eps >= 2/(2^n-1) (GL) or 1/(2^n-1) (ZO): 24-bit GL
/// 1.19e-7, 24-bit ZO 5.96e-8, 16-bit GL 3.05e-5. Float32, not reversed: 1 - g must round below 1,
/// g >= 2^-24 -> eps >= 2^-23 (GL) / 2^-24 (ZO). Float32 reversed: GL needs -1 + eps != -1 in float
/// (eps >= 2^-24); ZeroToOne only needs eps >= FLT_MIN (normal, not flushed).
///
/// fovy in (0, pi), aspect > 0, ulps_per_op in [0, 1e6] (NonFinite for NaN/Inf, InvalidArgument
/// outside, or for an unknown clip depth or format, or a bound above 0.5).
inline ProjectionEpsilonBound projection_infinite_epsilon_bound(float fovy, float aspect, ClipDepth clip, bool reversed_z,
                                                                DepthFormat format, float ulps_per_op = 1.0f) {
    ProjectionEpsilonBound e;
    e.status = detail::ip_check_fov_aspect(fovy, aspect, e.detail);
    if (e.status != Status::Ok) return e;
    if (!std::isfinite(ulps_per_op)) { e.status = Status::NonFinite; e.detail = "ulps_per_op: NaN or Inf"; return e; }
    if (!(ulps_per_op >= 0.0f && ulps_per_op <= 1.0e6f) ||
        (clip != ClipDepth::NegativeOneToOne && clip != ClipDepth::ZeroToOne)) {
        e.status = Status::InvalidArgument;
        e.detail = !(ulps_per_op >= 0.0f && ulps_per_op <= 1.0e6f) ? "ulps_per_op: outside [0, 1e6]" : "clip: unknown ClipDepth";
        return e;
    }
    const double u = 1.0 / 16777216.0; // 2^-24
    const double t = std::tan(0.5 * static_cast<double>(fovy));
    const double a = static_cast<double>(aspect);
    const double kappa = std::sqrt(1.0 + t * t * (1.0 + a * a));
    const bool gl = clip == ClipDepth::NegativeOneToOne;
    double clip_bound = (7.0 * static_cast<double>(ulps_per_op) * kappa + 1.0) * u;
    if (reversed_z && !gl) clip_bound = 0.0;
    const double gap_scale = gl ? 2.0 : 1.0; // eps = gap_scale * window gap
    double storage = 0.0;
    switch (format) {
    case DepthFormat::Fixed24: storage = gap_scale / 16777215.0; break;
    case DepthFormat::Fixed16: storage = gap_scale / 65535.0; break;
    case DepthFormat::Float32:
        if (!reversed_z) storage = gap_scale * u;
        else storage = gl ? u : static_cast<double>(std::numeric_limits<float>::min());
        break;
    default: e.status = Status::InvalidArgument; e.detail = "format: unknown DepthFormat"; return e;
    }
    // Round up to float so that the stored epsilon is never below the bound.
    auto up = [](double x) {
        if (!(x <= 1.0)) return 1.0f;  // beyond any valid epsilon (absurd ulps_per_op, huge kappa)
        float f = static_cast<float>(x);
        if (static_cast<double>(f) < x) f = std::nextafter(f, 1.0f);
        return f;
    };
    e.clip = up(clip_bound);
    e.storage = up(storage);
    e.epsilon = e.clip > e.storage ? e.clip : e.storage;
    if (!(e.epsilon <= 0.5f)) {
        e.status = Status::InvalidArgument;
        e.detail = "ulps_per_op, fovy, aspect: the bound is above 0.5";
        e.clip = e.storage = e.epsilon = 0.0f;
    }
    return e;
}

} // namespace shadowkit
