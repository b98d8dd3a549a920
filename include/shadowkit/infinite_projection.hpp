// shadowkit/infinite_projection.hpp - perspective projections with the far plane at infinity
// (plain and epsilon-tweaked), finite-far references, GL and zero-to-one clip depth, reversed-Z,
// window depth of an eye distance and depth-buffer resolution per depth format.
//
// Usage:
//   #include <shadowkit/infinite_projection.hpp>
//   shadowkit::DepthParams dp;                    // near 0.1, far +inf, GL clip depth, no reversed-Z
//   dp.near_z = 0.1f;
//   dp.epsilon = shadowkit::infinite_epsilon_bound(fovy, aspect, dp.clip_depth, dp.reversed_z,
//                                                  shadowkit::DepthFormat::Fixed24).epsilon;
//   shadowkit::ProjectionResult pr = shadowkit::perspective(fovy, aspect, dp);
//   if (pr.status == shadowkit::ProjectionStatus::Ok) glUniformMatrix4fv(loc, 1, GL_FALSE, &pr.matrix[0][0]);
//   double r = shadowkit::depth_resolution(dp, shadowkit::DepthFormat::Float32, 100.0).value;
//
// Based on:
//   C. Everitt, M. J. Kilgard, "Practical and Robust Stenciled Shadow Volumes for Hardware-Accelerated
//   Rendering", NVIDIA 2002 (section 3.2.1: P_inf as the limit of glFrustum when Far -> inf; the
//   epsilon-tweaked P_inf of the original paper).
//   J. Blinn, "A Trip Down the Graphics Pipeline: The Homogeneous Perspective Transform", IEEE CG&A 1993.
//   E. Lengyel, "Advanced Stencil Shadow and Penumbral Wedge Rendering", GDC 2005 (viewport depth formula).
//   Reversed-Z: depth 1 at the near plane, 0 (or -1 in NDC) at the far plane / at infinity.
//
// Conventions: right-handed eye space (the camera looks down -z), GLM column-major matrices
// (m[column][row]), eye distance d = -z_e > 0, window depth for glDepthRange(0, 1).
// NDC depth of eye distance d is always A + B / d; every function below derives from (A, B).
//
// MIT License. Copyright (c) shadowkit contributors.
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include <cmath>
#include <cstdint>
#include <limits>

namespace shadowkit {

#ifndef SHADOWKIT_CLIP_DEPTH_DEFINED
#define SHADOWKIT_CLIP_DEPTH_DEFINED
/// Clip-space depth range: OpenGL default [-1, 1] or D3D/Vulkan/glClipControl [0, 1].
enum class ClipDepth { NegativeOneToOne, ZeroToOne };
#endif

#ifndef SHADOWKIT_DEPTH_FORMAT_DEFINED
#define SHADOWKIT_DEPTH_FORMAT_DEFINED
/// Depth-buffer storage formats (DEPTH_COMPONENT32F, DEPTH24 / DEPTH24_STENCIL8, DEPTH_COMPONENT16).
enum class DepthFormat { Float32, Fixed24, Fixed16 };
#endif

enum class ProjectionStatus {
    Ok,
    InvalidNear,     ///< near_z not finite or <= 0
    InvalidFar,      ///< far_z NaN, <= near_z (+inf is allowed: far plane at infinity)
    InvalidFov,      ///< fovy not in (0, pi) or NaN
    InvalidAspect,   ///< aspect not finite or <= 0
    InvalidFrustum,  ///< left >= right, bottom >= top or not finite
    InvalidEpsilon,  ///< epsilon not in [0, 0.5], or != 0 with a finite far plane
    InvalidDistance, ///< eye distance / window depth argument outside the valid domain
    Overflow         ///< a matrix entry or result is not representable as a finite float
};

/// Depth part of a projection. Zero-initialising is not valid (near 0); the defaults are usable.
struct DepthParams {
    float near_z = 0.1f;                                      ///< [Units: eye] [Limit: > 0]
    float far_z = std::numeric_limits<float>::infinity();    ///< [Limit: > near_z]; +inf = infinite far
    ClipDepth clip_depth = ClipDepth::NegativeOneToOne;
    bool reversed_z = false;                                  ///< near -> window depth 1, far -> 0
    /// Everitt-Kilgard tweak, infinite far only: a vertex at infinity (w = 0) lands at NDC depth
    /// 1 - epsilon (reversed: -1 + epsilon, or +epsilon for ZeroToOne) instead of exactly on the far
    /// clip plane. [Limit: 0 <= epsilon <= 0.5] See infinite_epsilon_bound() for the minimum.
    float epsilon = 0.0f;
};

struct ProjectionResult {
    ProjectionStatus status = ProjectionStatus::Ok;
    glm::mat4 matrix = glm::mat4(0.0f);
};

/// Value with a status (the value is NaN when status != Ok).
struct DepthValue {
    ProjectionStatus status = ProjectionStatus::Ok;
    double value = std::numeric_limits<double>::quiet_NaN();
};

/// NDC depth as a function of eye distance d: ndc(d) = A + B / d.
struct DepthMapping {
    ProjectionStatus status = ProjectionStatus::Ok;
    double A = 0.0;
    double B = 0.0;
};

/// Epsilon bounds for the tweaked infinite projection (see the derivation at infinite_epsilon_bound).
struct EpsilonBound {
    ProjectionStatus status = ProjectionStatus::Ok;
    float clip = 0.0f;    ///< minimum keeping w = 0 vertices inside the clip volume in float32
    float storage = 0.0f; ///< minimum keeping infinity strictly inside the depth clear value
    float epsilon = 0.0f; ///< max(clip, storage)
};

namespace detail {
inline bool ip_finite(double v) { return std::isfinite(v); }
inline bool ip_fits_float(double v) {
    return std::isfinite(v) && std::fabs(v) <= static_cast<double>(std::numeric_limits<float>::max());
}
} // namespace detail

/// Checks a DepthParams. Ok or the first problem found.
inline ProjectionStatus validate(const DepthParams& p) {
    if (!(std::isfinite(p.near_z) && p.near_z > 0.0f)) return ProjectionStatus::InvalidNear;
    if (std::isnan(p.far_z) || !(p.far_z > p.near_z)) return ProjectionStatus::InvalidFar;
    if (!(p.epsilon >= 0.0f && p.epsilon <= 0.5f)) return ProjectionStatus::InvalidEpsilon;
    if (std::isfinite(p.far_z) && p.epsilon != 0.0f) return ProjectionStatus::InvalidEpsilon;
    return ProjectionStatus::Ok;
}

/// Coefficients of ndc(d) = A + B / d (computed in double).
///   finite, GL   : A = (F+N)/(F-N), B = -2FN/(F-N)   (glFrustum row 3; Everitt-Kilgard eq. for P)
///   finite, ZO   : A = F/(F-N),     B = -FN/(F-N)
///   infinite, GL : A = 1 - eps,     B = -(2 - eps) N (limit Far -> inf, Everitt-Kilgard P_inf, tweaked)
///   infinite, ZO : A = 1 - eps,     B = -(1 - eps) N
///   reversed-Z   : GL: ndc -> -ndc; ZO: ndc -> 1 - ndc (eps then measured from -1 resp. 0)
inline DepthMapping depth_mapping(const DepthParams& p) {
    DepthMapping m;
    m.status = validate(p);
    if (m.status != ProjectionStatus::Ok) return m;
    const double N = static_cast<double>(p.near_z);
    const bool gl = p.clip_depth == ClipDepth::NegativeOneToOne;
    double A = 0.0, B = 0.0;
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
    if (!detail::ip_fits_float(A) || !detail::ip_fits_float(B)) { m.status = ProjectionStatus::Overflow; return m; }
    m.A = A;
    m.B = B;
    return m;
}

/// Off-centre frustum (glFrustum-style x/y; left/right/bottom/top on the near plane) with the depth
/// behaviour of `depth`. Row 3 of the matrix is (0, 0, -A, B) so that z_c / w_c = A + B / d.
inline ProjectionResult frustum(float left, float right, float bottom, float top, const DepthParams& depth) {
    ProjectionResult r;
    const DepthMapping m = depth_mapping(depth);
    if (m.status != ProjectionStatus::Ok) { r.status = m.status; return r; }
    if (!(std::isfinite(left) && std::isfinite(right) && std::isfinite(bottom) && std::isfinite(top)) ||
        !(left < right) || !(bottom < top)) {
        r.status = ProjectionStatus::InvalidFrustum;
        return r;
    }
    const double N = static_cast<double>(depth.near_z);
    const double l = left, rt = right, b = bottom, t = top;
    const double m00 = 2.0 * N / (rt - l), m11 = 2.0 * N / (t - b);
    const double m20 = (rt + l) / (rt - l), m21 = (t + b) / (t - b);
    if (!detail::ip_fits_float(m00) || !detail::ip_fits_float(m11) || !detail::ip_fits_float(m20) ||
        !detail::ip_fits_float(m21)) {
        r.status = ProjectionStatus::Overflow;
        return r;
    }
    r.matrix[0][0] = static_cast<float>(m00);
    r.matrix[1][1] = static_cast<float>(m11);
    r.matrix[2][0] = static_cast<float>(m20);
    r.matrix[2][1] = static_cast<float>(m21);
    r.matrix[2][2] = static_cast<float>(-m.A);
    r.matrix[2][3] = -1.0f;
    r.matrix[3][2] = static_cast<float>(m.B);
    return r;
}

/// Symmetric perspective (gluPerspective-style): fovy is the full vertical angle in radians, (0, pi).
inline ProjectionResult perspective(float fovy, float aspect, const DepthParams& depth) {
    ProjectionResult r;
    const ProjectionStatus s = validate(depth);
    if (s != ProjectionStatus::Ok) { r.status = s; return r; }
    if (!(fovy > 0.0f && static_cast<double>(fovy) < 3.14159265358979323846)) {
        r.status = ProjectionStatus::InvalidFov;
        return r;
    }
    if (!(std::isfinite(aspect) && aspect > 0.0f)) { r.status = ProjectionStatus::InvalidAspect; return r; }
    const double t = std::tan(0.5 * static_cast<double>(fovy));
    const double m11 = 1.0 / t;
    const double m00 = m11 / static_cast<double>(aspect);
    if (!detail::ip_fits_float(m00) || !detail::ip_fits_float(m11) || !(m00 > 0.0) || !(m11 > 0.0)) {
        r.status = ProjectionStatus::Overflow;
        return r;
    }
    const DepthMapping m = depth_mapping(depth);
    if (m.status != ProjectionStatus::Ok) { r.status = m.status; return r; }
    r.matrix[0][0] = static_cast<float>(m00);
    r.matrix[1][1] = static_cast<float>(m11);
    r.matrix[2][2] = static_cast<float>(-m.A);
    r.matrix[2][3] = -1.0f;
    r.matrix[3][2] = static_cast<float>(m.B);
    if (r.matrix[0][0] == 0.0f || r.matrix[1][1] == 0.0f) r.status = ProjectionStatus::Overflow; // underflow
    return r;
}

/// Convenience: infinite far plane (Everitt-Kilgard P_inf), optional epsilon tweak.
inline ProjectionResult perspective_infinite(float fovy, float aspect, float near_z,
                                             ClipDepth clip = ClipDepth::NegativeOneToOne,
                                             bool reversed_z = false, float epsilon = 0.0f) {
    DepthParams d;
    d.near_z = near_z;
    d.far_z = std::numeric_limits<float>::infinity();
    d.clip_depth = clip;
    d.reversed_z = reversed_z;
    d.epsilon = epsilon;
    return perspective(fovy, aspect, d);
}

/// Convenience: finite far plane (equals glm::perspectiveRH_NO / _ZO when not reversed).
inline ProjectionResult perspective_finite(float fovy, float aspect, float near_z, float far_z,
                                           ClipDepth clip = ClipDepth::NegativeOneToOne,
                                           bool reversed_z = false) {
    DepthParams d;
    d.near_z = near_z;
    d.far_z = far_z;
    d.clip_depth = clip;
    d.reversed_z = reversed_z;
    return perspective(fovy, aspect, d);
}

/// NDC depth of eye distance d > 0 (d = +inf allowed: the depth of a w = 0 vertex).
inline DepthValue ndc_depth(const DepthParams& p, double eye_distance) {
    DepthValue v;
    const DepthMapping m = depth_mapping(p);
    if (m.status != ProjectionStatus::Ok) { v.status = m.status; return v; }
    if (!(eye_distance > 0.0)) { v.status = ProjectionStatus::InvalidDistance; return v; }
    v.value = std::isinf(eye_distance) ? m.A : m.A + m.B / eye_distance;
    return v;
}

/// Window depth in [0, 1] for glDepthRange(0, 1): GL: 0.5 ndc + 0.5, ZeroToOne: ndc.
/// (Lengyel's viewport depth d = (dmax - dmin)/2 * ndc + (dmax + dmin)/2 with dmin = 0, dmax = 1.)
inline DepthValue window_depth(const DepthParams& p, double eye_distance) {
    DepthValue v = ndc_depth(p, eye_distance);
    if (v.status == ProjectionStatus::Ok && p.clip_depth == ClipDepth::NegativeOneToOne)
        v.value = 0.5 * v.value + 0.5;
    return v;
}

/// Inverse of window_depth: the eye distance whose window depth is `window` (+inf for the depth of
/// infinity; InvalidDistance for window outside [0, 1] or outside the mapped range).
inline DepthValue eye_distance_from_window_depth(const DepthParams& p, double window) {
    DepthValue v;
    const DepthMapping m = depth_mapping(p);
    if (m.status != ProjectionStatus::Ok) { v.status = m.status; return v; }
    if (!(window >= 0.0 && window <= 1.0)) { v.status = ProjectionStatus::InvalidDistance; return v; }
    const double ndc = p.clip_depth == ClipDepth::NegativeOneToOne ? 2.0 * window - 1.0 : window;
    const double den = ndc - m.A;
    if (den == 0.0) { v.value = std::numeric_limits<double>::infinity(); return v; }
    const double d = m.B / den;
    if (!(d > 0.0)) { v.status = ProjectionStatus::InvalidDistance; return v; }
    v.value = d;
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
/// distance d (InvalidDistance unless near <= d <= far), to first order  delta_d = delta_w / |dw/dd|,  dw/dd = -s B / d^2  (s = 1/2 for GL).
/// delta_w is the larger of
///   - the storage step of `format` at w(d): 1/(2^n - 1) for n-bit fixed, the float32 spacing at w
///     for Float32 (tiny near 0, 2^-24 just below 1),
///   - the float32 step of the NDC value the pipeline computes before the viewport transform (times
///     1/2 for GL): for GL clip depth NDC near -1 or +1 has steps of 2^-24, which is why reversed-Z
///     with GL's [-1, 1] gains nothing and reversed-Z needs ZeroToOne (glClipControl) + Float32.
inline DepthValue depth_resolution(const DepthParams& p, DepthFormat format, double eye_distance) {
    DepthValue v;
    const DepthMapping m = depth_mapping(p);
    if (m.status != ProjectionStatus::Ok) { v.status = m.status; return v; }
    if (!(eye_distance > 0.0) || !std::isfinite(eye_distance)) { v.status = ProjectionStatus::InvalidDistance; return v; }
    const bool gl = p.clip_depth == ClipDepth::NegativeOneToOne;
    const double s = gl ? 0.5 : 1.0;
    const double ndc = m.A + m.B / eye_distance;
    double w = gl ? 0.5 * ndc + 0.5 : ndc;
    // Only distances inside the depth range [near, far] have a stored depth (slack for rounding).
    if (!(w >= -1e-12 && w <= 1.0 + 1e-12)) { v.status = ProjectionStatus::InvalidDistance; return v; }
    w = w < 0.0 ? 0.0 : (w > 1.0 ? 1.0 : w);
    double step = 0.0;
    switch (format) {
    case DepthFormat::Float32: step = detail::ip_float_gap(w); break;
    case DepthFormat::Fixed24: step = 1.0 / 16777215.0; break;
    case DepthFormat::Fixed16: step = 1.0 / 65535.0; break;
    }
    const double ndc_step = s * detail::ip_float_gap(std::fabs(ndc));
    if (ndc_step > step) step = ndc_step;
    const double slope = std::fabs(s * m.B) / (eye_distance * eye_distance);
    if (!(slope > 0.0)) { v.value = std::numeric_limits<double>::infinity(); return v; }
    v.value = step / slope;
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
inline EpsilonBound infinite_epsilon_bound(float fovy, float aspect, ClipDepth clip, bool reversed_z,
                                           DepthFormat format, float ulps_per_op = 1.0f) {
    EpsilonBound e;
    if (!(fovy > 0.0f && static_cast<double>(fovy) < 3.14159265358979323846)) { e.status = ProjectionStatus::InvalidFov; return e; }
    if (!(std::isfinite(aspect) && aspect > 0.0f)) { e.status = ProjectionStatus::InvalidAspect; return e; }
    if (!(std::isfinite(ulps_per_op) && ulps_per_op >= 0.0f && ulps_per_op <= 1.0e6f)) {
        e.status = ProjectionStatus::InvalidEpsilon;
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
    }
    // Round up to float so that the stored epsilon is never below the bound.
    auto up = [](double x) {
        float f = static_cast<float>(x);
        if (static_cast<double>(f) < x) f = std::nextafter(f, 1.0f);
        return f;
    };
    e.clip = up(clip_bound);
    e.storage = up(storage);
    e.epsilon = e.clip > e.storage ? e.clip : e.storage;
    if (!(e.epsilon <= 0.5f)) e.status = ProjectionStatus::InvalidEpsilon; // absurd ulps_per_op
    return e;
}

} // namespace shadowkit
