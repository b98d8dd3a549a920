// shadowkit/spherical_harmonics.hpp - real spherical harmonics (SH) up to order 5 for low-frequency lighting.
//
// Basis evaluation by the associated-Legendre recurrence, projection of sampled functions,
// reconstruction at a direction, rotation of coefficient vectors (Ivanic-Ruedenberg recursion,
// every band up to 4, reflections included), convolution with zonal kernels such as the clamped
// cosine, and stratified sphere samples. The PRT side (transfer vectors) is prt.hpp; docs/prt.md
// has complete programs for both.
//
// Usage:
//   #include <shadowkit/spherical_harmonics.hpp>
//   namespace sk = shadowkit;
//   const int order = 3;                                      // 3 bands = 9 coefficients
//   std::vector<glm::vec3> dirs(64 * 64);                     // stratified, jittered, deterministic
//   sk::sh_stratified_directions(64, 1u, dirs.data(), dirs.size());
//   std::vector<float> f(dirs.size());  for (...) f[j] = radiance(dirs[j]);
//   float c[25];
//   sk::sh_project(order, dirs.data(), f.data(), nullptr, dirs.size(), c, 25);  // weights 4 pi / N
//   sk::SHRotation rot = sk::sh_make_rotation(order, glm::mat3(R));  // R: any rotation; rot.status
//   sk::sh_rotate(rot, c, 25, c, 25);                         // now c holds f(R^T s): f turned by R
//   float e[25];  sk::sh_convolve_clamped_cosine(order, c, 25, e, 25);  // irradiance coefficients
//   float E = sk::sh_reconstruct(order, e, 25, normal).value;  // = integral f(s) max(n.s, 0) ds
//
// Conventions (used by every function):
//   * "order" is the number of bands: order n uses bands l = 0 .. n-1 and n^2 coefficients.
//     Valid orders are 1 .. 5 (kSHMaxOrder); anything else is Status::InvalidArgument.
//   * Coefficient i = l (l + 1) + m, m = -l .. l (sh_index). Real, orthonormal over the unit sphere
//     (integral of y_i y_j over the sphere = delta_ij), WITHOUT the Condon-Shortley phase:
//     y_{1,-1} = c y, y_{1,0} = c z, y_{1,1} = c x with c = sqrt(3 / (4 pi)); in general
//     y_{l,m>0} = sqrt2 K_l^m P_l^m(z) cos(m phi), y_{l,m<0} = sqrt2 K_l^|m| P_l^|m|(z) sin(|m| phi),
//     y_{l,0} = K_l^0 P_l^0(z), K_l^m = sqrt((2l+1)/(4 pi) (l-m)!/(l+m)!), theta measured from +z.
//     (x + i y)^m replaces sin^m(theta) e^{i m phi}, so no atan2 and no division by sin(theta): the
//     evaluation is exact at the poles.
//   * Directions need not be unit length (they are normalized in double precision); a zero
//     direction is Status::InvalidArgument, a NaN or Inf component Status::NonFinite.
//   * Arrays are pointer + count, in elements of the pointer's type (Real, or glm::vec3 for RGB). A
//     result's `count` is the number of values written (order^2 when Ok, 0 otherwise) and `needed`
//     the number the output needs (order^2). A null array is Status::InvalidArgument; an input or
//     output array shorter than the order needs is Status::BufferTooSmall (nothing written).
//     Functions are templates over float and double (Real); internally everything is evaluated in
//     double. Input and output may alias (rotation, convolution work on a copy). No function
//     allocates.
//   * Status: NaN/Inf in an input (coefficients, kernel, samples, matrix) is Status::NonFinite; a
//     finite result too large for Real (float) is Status::Overflow (outputs zeroed), never Inf; `Ok`
//     means every output is finite. A non-Ok result's `detail` names the offending input and the
//     rule ("order: outside 1 .. kSHMaxOrder"), a static string; nullptr when Ok.
//   * Rotation: sh_rotate with the rotation built from R turns the function by R: the output
//     represents g(s) = f(R^T s), so a lobe around direction d moves to R d. R must be orthogonal
//     (tolerance 1e-3 on R^T R - I, else Status::InvalidArgument); det R = -1 (a reflection) is
//     allowed.
//   * This header takes no light (an environment is an SH coefficient vector).
//
// Based on:
//   P.-P. Sloan, J. Kautz, J. Snyder, "Precomputed Radiance Transfer for Real-Time Rendering in
//   Dynamic, Low-Frequency Lighting Environments", SIGGRAPH 2002 (section 4: projection eq. 1,
//   reconstruction, rotation as a linear map per band).
//   J. Kautz, "Precomputed Radiance Transfer", SIGGRAPH 2004 course #26 "Real-Time Shadowing
//   Techniques" notes (SH background: projection, reconstruction, integration as a dot product).
//   J. Ivanic, K. Ruedenberg, "Rotation Matrices for Real Spherical Harmonics. Direct
//   Determination by Recursion", J. Phys. Chem. 100(15), 1996, tables 1-2 (+ 1998 erratum).
//   R. Ramamoorthi, P. Hanrahan, "An Efficient Representation for Irradiance Environment Maps",
//   SIGGRAPH 2001, eqs. 7-9 (clamped-cosine coefficients A_l).
//   R. Green, "Spherical Harmonic Lighting: The Gritty Details", GDC 2003 (Legendre recurrence).
//
// MIT License. Copyright (c) shadowkit contributors.
#pragma once

#include <glm/glm.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>

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

/// Highest supported order (number of bands) and the coefficient count at that order.
constexpr int kSHMaxOrder = 5;
constexpr std::size_t kSHMaxCoefficients = 25;

/// True for orders 1 .. kSHMaxOrder. Total.
constexpr bool sh_order_valid(int order) { return order >= 1 && order <= kSHMaxOrder; }

/// order^2 for a valid order, 0 otherwise. Total.
constexpr std::size_t sh_coefficient_count(int order) {
    return sh_order_valid(order) ? static_cast<std::size_t>(order) * static_cast<std::size_t>(order) : 0u;
}

/// Index of y_{l,m} in a coefficient vector: l (l + 1) + m, for 0 <= l < kSHMaxOrder and
/// -l <= m <= l (the formula only: no check).
constexpr int sh_index(int l, int m) { return l * (l + 1) + m; }

/// Status, the number of values written and the number the output needs.
struct SHResult {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    std::size_t count = 0;   ///< values written (order^2 when Ok, 0 otherwise)
    std::size_t needed = 0;  ///< values the output needs (order^2; 0 for an invalid order)
};

/// Status and a scalar value (0 unless status is Ok).
template <typename Real>
struct SHValue {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    Real value = Real(0);
};

/// Per-band rotation matrices of one rotation (block diagonal), built by sh_make_rotation.
/// Band l is a (2l+1) x (2l+1) row-major block at offset l (2l-1) (2l+1) / 3.
struct SHRotation {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    int order = 0;
    double band[165] = {};  ///< sum over l = 0..4 of (2l+1)^2
};

namespace detail {

constexpr double sh_pi = 3.14159265358979323846;

// Keeps a parameter out of template argument deduction (so nullptr can be passed for weights).
template <typename T>
struct sh_identity {
    using type = T;
};

inline double sh_factorial(int n) {
    double f = 1.0;
    for (int i = 2; i <= n; ++i) f *= static_cast<double>(i);
    return f;
}

// K_l^m = sqrt((2l+1)/(4 pi) (l-|m|)!/(l+|m|)!) (Sloan et al. 2002 / Green 2003 normalization).
inline double sh_normalization(int l, int m) {
    const int am = m < 0 ? -m : m;
    return std::sqrt((2.0 * l + 1.0) / (4.0 * sh_pi) * sh_factorial(l - am) / sh_factorial(l + am));
}

// Unit direction in double: Ok, NonFinite (NaN/Inf component) or InvalidArgument (zero).
template <typename Real, glm::qualifier Q>
inline Status sh_unit_direction(const glm::vec<3, Real, Q>& d, double& x, double& y, double& z) {
    x = static_cast<double>(d.x);
    y = static_cast<double>(d.y);
    z = static_cast<double>(d.z);
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) return Status::NonFinite;
    // scale by the largest component first: 1e-300 or 1e300 components neither under- nor overflow
    const double big = std::fmax(std::fabs(x), std::fmax(std::fabs(y), std::fabs(z)));
    if (!(big > 0.0)) return Status::InvalidArgument;
    x /= big;
    y /= big;
    z /= big;
    const double len = std::sqrt(x * x + y * y + z * z);
    x /= len;
    y /= len;
    z /= len;
    return Status::Ok;
}

// Real SH basis at a unit direction, n = order^2 values. Associated Legendre recurrence on the
// polynomial part Q_l^m(z) = P_l^m(z) / sin^m(theta) (Green 2003, the three-term rule in l):
//   Q_m^m = (2m-1)!!,  Q_{m+1}^m = (2m+1) z Q_m^m,  (l-m) Q_l^m = (2l-1) z Q_{l-1}^m - (l+m-1) Q_{l-2}^m,
// times sin^m(theta) {cos, sin}(m phi) = {Re, Im} (x + i y)^m.
inline void sh_basis(int order, double x, double y, double z, double* out) {
    const double sqrt2 = 1.41421356237309504880;
    double cm = 1.0, sm = 0.0, pmm = 1.0;
    for (int m = 0; m < order; ++m) {
        if (m > 0) {
            const double c = cm * x - sm * y;
            sm = cm * y + sm * x;
            cm = c;
            pmm *= static_cast<double>(2 * m - 1);
        }
        double q2 = 0.0, q1 = 0.0;
        for (int l = m; l < order; ++l) {
            double q;
            if (l == m)
                q = pmm;
            else if (l == m + 1)
                q = z * static_cast<double>(2 * m + 1) * pmm;
            else
                q = (static_cast<double>(2 * l - 1) * z * q1 - static_cast<double>(l + m - 1) * q2) /
                    static_cast<double>(l - m);
            q2 = q1;
            q1 = q;
            const double k = sh_normalization(l, m);
            if (m == 0) {
                out[sh_index(l, 0)] = k * q;
            } else {
                out[sh_index(l, m)] = sqrt2 * k * q * cm;
                out[sh_index(l, -m)] = sqrt2 * k * q * sm;
            }
        }
    }
}

template <typename Real>
inline bool sh_all_finite(const Real* p, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i)
        if (!std::isfinite(static_cast<double>(p[i]))) return false;
    return true;
}

// Stores n doubles as Real; false (and zeros) if one does not fit (float overflow).
template <typename Real>
inline bool sh_store(const double* v, std::size_t n, Real* out) {
    for (std::size_t i = 0; i < n; ++i)
        if (!std::isfinite(static_cast<double>(static_cast<Real>(v[i])))) {
            for (std::size_t k = 0; k < n; ++k) out[k] = Real(0);
            return false;
        }
    for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<Real>(v[i]);
    return true;
}

template <typename Real>
inline bool sh_fits(double v) {
    return std::isfinite(v) && std::isfinite(static_cast<double>(static_cast<Real>(v)));
}

inline int sh_band_offset(int l) { return l * (2 * l - 1) * (2 * l + 1) / 3; }

// Element (m, n) of band l, m, n in -l .. l.
inline double& sh_at(SHRotation& r, int l, int m, int n) {
    return r.band[sh_band_offset(l) + (m + l) * (2 * l + 1) + (n + l)];
}
inline double sh_get(const SHRotation& r, int l, int m, int n) {
    if (m < -l || m > l || n < -l || n > l) return 0.0;
    return r.band[sh_band_offset(l) + (m + l) * (2 * l + 1) + (n + l)];
}

// Ivanic & Ruedenberg 1996, table 2 (with the 1998 erratum): the P helper.
inline double sh_ir_p(const SHRotation& r, int i, int a, int b, int l) {
    if (b == l) return sh_get(r, 1, i, 1) * sh_get(r, l - 1, a, l - 1) - sh_get(r, 1, i, -1) * sh_get(r, l - 1, a, -l + 1);
    if (b == -l) return sh_get(r, 1, i, 1) * sh_get(r, l - 1, a, -l + 1) + sh_get(r, 1, i, -1) * sh_get(r, l - 1, a, l - 1);
    return sh_get(r, 1, i, 0) * sh_get(r, l - 1, a, b);
}

// Ivanic & Ruedenberg 1996, table 2: U, V, W terms of band l from bands 1 and l-1.
inline double sh_ir_u(const SHRotation& r, int m, int n, int l) { return sh_ir_p(r, 0, m, n, l); }
inline double sh_ir_v(const SHRotation& r, int m, int n, int l) {
    if (m == 0) return sh_ir_p(r, 1, 1, n, l) + sh_ir_p(r, -1, -1, n, l);
    if (m > 0) {
        const double d = m == 1 ? 1.0 : 0.0;
        return sh_ir_p(r, 1, m - 1, n, l) * std::sqrt(1.0 + d) - sh_ir_p(r, -1, -m + 1, n, l) * (1.0 - d);
    }
    const double d = m == -1 ? 1.0 : 0.0;
    return sh_ir_p(r, 1, m + 1, n, l) * (1.0 - d) + sh_ir_p(r, -1, -m - 1, n, l) * std::sqrt(1.0 + d);
}
inline double sh_ir_w(const SHRotation& r, int m, int n, int l) {
    if (m > 0) return sh_ir_p(r, 1, m + 1, n, l) + sh_ir_p(r, -1, -m - 1, n, l);
    if (m < 0) return sh_ir_p(r, 1, m - 1, n, l) - sh_ir_p(r, -1, -m + 1, n, l);
    return 0.0;
}

// `why`: where a non-Ok status came from (a static string; nullptr with Ok).
inline SHResult sh_result(Status s, std::size_t count, std::size_t needed, const char* why) {
    SHResult r;
    r.status = s;
    r.detail = why;
    r.count = count;
    r.needed = needed;
    return r;
}

template <typename Real>
inline SHValue<Real> sh_value(Status s, Real v, const char* why) {
    SHValue<Real> r;
    r.status = s;
    r.detail = why;
    r.value = v;
    return r;
}

}  // namespace detail

/// Real SH basis y_i(dir), i < order^2. `out` holds capacity Real elements; it needs order^2.
/// A zero (InvalidArgument) or non-finite (NonFinite) direction writes zeros.
template <typename Real, glm::qualifier Q>
inline SHResult sh_evaluate(int order, const glm::vec<3, Real, Q>& dir, Real* out, std::size_t capacity) {
    if (!sh_order_valid(order)) return detail::sh_result(Status::InvalidArgument, 0, 0, "order: outside 1 .. kSHMaxOrder");
    const std::size_t n = sh_coefficient_count(order);
    if (!out) return detail::sh_result(Status::InvalidArgument, 0, n, "out: null");
    if (capacity < n) return detail::sh_result(Status::BufferTooSmall, 0, n, "capacity: below needed (see needed)");
    double x, y, z;
    const Status ds = detail::sh_unit_direction(dir, x, y, z);
    if (ds != Status::Ok) {
        for (std::size_t i = 0; i < n; ++i) out[i] = Real(0);
        return detail::sh_result(ds, 0, n, ds == Status::NonFinite ? "dir: NaN or Inf" : "dir: zero vector");
    }
    double b[kSHMaxCoefficients];
    detail::sh_basis(order, x, y, z, b);
    for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<Real>(b[i]);
    return detail::sh_result(Status::Ok, n, n, nullptr);
}

/// Reconstruction sum_i c_i y_i(dir) of a coefficient vector (Sloan et al. 2002, section 4).
/// `coeffs` holds count Real elements (>= order^2).
template <typename Real, glm::qualifier Q>
inline SHValue<Real> sh_reconstruct(int order, const Real* coeffs, std::size_t count, const glm::vec<3, Real, Q>& dir) {
    if (!sh_order_valid(order)) return detail::sh_value(Status::InvalidArgument, Real(0), "order: outside 1 .. kSHMaxOrder");
    const std::size_t n = sh_coefficient_count(order);
    if (!coeffs) return detail::sh_value(Status::InvalidArgument, Real(0), "coeffs: null");
    if (count < n) return detail::sh_value(Status::BufferTooSmall, Real(0), "count: below order^2");
    double x, y, z;
    const Status ds = detail::sh_unit_direction(dir, x, y, z);
    if (ds != Status::Ok) return detail::sh_value(ds, Real(0), ds == Status::NonFinite ? "dir: NaN or Inf" : "dir: zero vector");
    if (!detail::sh_all_finite(coeffs, n)) return detail::sh_value(Status::NonFinite, Real(0), "coeffs: NaN or Inf");
    double b[kSHMaxCoefficients];
    detail::sh_basis(order, x, y, z, b);
    double s = 0.0;
    for (std::size_t i = 0; i < n; ++i) s += static_cast<double>(coeffs[i]) * b[i];
    if (!detail::sh_fits<Real>(s)) return detail::sh_value(Status::Overflow, Real(0), "value: beyond Real range");
    return detail::sh_value(Status::Ok, static_cast<Real>(s), nullptr);
}

/// Projection c_i = sum_j w_j f(s_j) y_i(s_j) of sampled values (course notes: f_i = integral f y_i,
/// evaluated numerically). `dirs`, `values` and `weights` hold sample_count elements each;
/// weights == nullptr means uniform sphere samples, w_j = 4 pi / N. `out` holds capacity Real
/// elements; it needs order^2. No samples give zeros (Ok). A sample with a zero direction
/// (InvalidArgument) or a non-finite direction, value or weight (NonFinite) gives zeros.
template <typename Real, glm::qualifier Q>
inline SHResult sh_project(int order, const glm::vec<3, Real, Q>* dirs, const Real* values,
                           const typename detail::sh_identity<Real>::type* weights, std::size_t sample_count, Real* out,
                           std::size_t capacity) {
    if (!sh_order_valid(order)) return detail::sh_result(Status::InvalidArgument, 0, 0, "order: outside 1 .. kSHMaxOrder");
    const std::size_t n = sh_coefficient_count(order);
    if (!out) return detail::sh_result(Status::InvalidArgument, 0, n, "out: null");
    if (capacity < n) return detail::sh_result(Status::BufferTooSmall, 0, n, "capacity: below needed (see needed)");
    for (std::size_t i = 0; i < n; ++i) out[i] = Real(0);
    if (sample_count == 0) return detail::sh_result(Status::Ok, n, n, nullptr);
    if (!dirs || !values) return detail::sh_result(Status::InvalidArgument, 0, n, !dirs ? "dirs: null" : "values: null");
    double acc[kSHMaxCoefficients] = {};
    const double uniform = 4.0 * detail::sh_pi / static_cast<double>(sample_count);
    double b[kSHMaxCoefficients];
    for (std::size_t j = 0; j < sample_count; ++j) {
        double x, y, z;
        const double f = static_cast<double>(values[j]);
        const double w = weights ? static_cast<double>(weights[j]) : uniform;
        const Status ds = detail::sh_unit_direction(dirs[j], x, y, z);
        if (ds == Status::Ok && (!std::isfinite(f) || !std::isfinite(w)))
            return detail::sh_result(Status::NonFinite, 0, n, !std::isfinite(f) ? "values: NaN or Inf" : "weights: NaN or Inf");
        if (ds != Status::Ok) return detail::sh_result(ds, 0, n, ds == Status::NonFinite ? "dirs: NaN or Inf" : "dirs: zero vector");
        detail::sh_basis(order, x, y, z, b);
        for (std::size_t i = 0; i < n; ++i) acc[i] += w * f * b[i];
    }
    for (std::size_t i = 0; i < n; ++i)
        if (!std::isfinite(acc[i])) return detail::sh_result(Status::Overflow, 0, n, "out: a coefficient beyond double");
    if (!detail::sh_store(acc, n, out)) return detail::sh_result(Status::Overflow, 0, n, "out: a coefficient beyond Real range");
    return detail::sh_result(Status::Ok, n, n, nullptr);
}

/// RGB projection: out[i] = sum_j w_j rgb_j y_i(s_j); same rules as sh_project (`values` and `out`
/// in glm::vec3 elements).
template <typename Real, glm::qualifier Q>
inline SHResult sh_project_rgb(int order, const glm::vec<3, Real, Q>* dirs, const glm::vec<3, Real, Q>* values,
                               const typename detail::sh_identity<Real>::type* weights, std::size_t sample_count,
                               glm::vec<3, Real, Q>* out, std::size_t capacity) {
    if (!sh_order_valid(order)) return detail::sh_result(Status::InvalidArgument, 0, 0, "order: outside 1 .. kSHMaxOrder");
    const std::size_t n = sh_coefficient_count(order);
    if (!out) return detail::sh_result(Status::InvalidArgument, 0, n, "out: null");
    if (capacity < n) return detail::sh_result(Status::BufferTooSmall, 0, n, "capacity: below needed (see needed)");
    for (std::size_t i = 0; i < n; ++i) out[i] = glm::vec<3, Real, Q>(Real(0));
    if (sample_count == 0) return detail::sh_result(Status::Ok, n, n, nullptr);
    if (!dirs || !values) return detail::sh_result(Status::InvalidArgument, 0, n, !dirs ? "dirs: null" : "values: null");
    glm::dvec3 acc[kSHMaxCoefficients] = {};
    const double uniform = 4.0 * detail::sh_pi / static_cast<double>(sample_count);
    double b[kSHMaxCoefficients];
    for (std::size_t j = 0; j < sample_count; ++j) {
        double x, y, z;
        const glm::dvec3 f(static_cast<double>(values[j].x), static_cast<double>(values[j].y),
                           static_cast<double>(values[j].z));
        const double w = weights ? static_cast<double>(weights[j]) : uniform;
        const Status ds = detail::sh_unit_direction(dirs[j], x, y, z);
        if (ds == Status::Ok && (!std::isfinite(f.x) || !std::isfinite(f.y) || !std::isfinite(f.z) || !std::isfinite(w)))
            return detail::sh_result(Status::NonFinite, 0, n, "values, weights: NaN or Inf");
        if (ds != Status::Ok) return detail::sh_result(ds, 0, n, ds == Status::NonFinite ? "dirs: NaN or Inf" : "dirs: zero vector");
        detail::sh_basis(order, x, y, z, b);
        for (std::size_t i = 0; i < n; ++i) acc[i] += (w * b[i]) * f;
    }
    for (std::size_t i = 0; i < n; ++i)
        if (!detail::sh_fits<Real>(acc[i].x) || !detail::sh_fits<Real>(acc[i].y) || !detail::sh_fits<Real>(acc[i].z))
            return detail::sh_result(Status::Overflow, 0, n, "out: a coefficient beyond Real range");
    for (std::size_t i = 0; i < n; ++i) out[i] = glm::vec<3, Real, Q>(acc[i]);
    return detail::sh_result(Status::Ok, n, n, nullptr);
}

/// strata^2 stratified, jittered directions, uniform over the sphere (equal-area map
/// z = 1 - 2u, phi = 2 pi v of the strata x strata grid; the course notes' uniform map with one
/// jittered sample per cell). Deterministic for a seed (own integer hash, no <random>
/// distribution, so equal on every platform). strata must be 1 .. 4096 (else InvalidArgument).
/// `out` holds capacity glm::vec3 elements; it needs strata^2.
template <typename Real, glm::qualifier Q>
inline SHResult sh_stratified_directions(int strata, std::uint32_t seed, glm::vec<3, Real, Q>* out,
                                         std::size_t capacity) {
    if (strata < 1 || strata > 4096) return detail::sh_result(Status::InvalidArgument, 0, 0, "strata: outside [1, 4096]");
    const std::size_t n = static_cast<std::size_t>(strata) * static_cast<std::size_t>(strata);
    if (!out) return detail::sh_result(Status::InvalidArgument, 0, n, "out: null");
    if (capacity < n) return detail::sh_result(Status::BufferTooSmall, 0, n, "capacity: below needed (see needed)");
    auto hash = [](std::uint32_t v) {  // lowbias32 (C. Wellons)
        v ^= v >> 16;
        v *= 0x7feb352du;
        v ^= v >> 15;
        v *= 0x846ca68bu;
        v ^= v >> 16;
        return v;
    };
    const double inv = 1.0 / static_cast<double>(strata);
    std::size_t k = 0;
    for (int i = 0; i < strata; ++i)
        for (int j = 0; j < strata; ++j, ++k) {
            const std::uint32_t h1 = hash(static_cast<std::uint32_t>(k) * 2u + hash(seed));
            const std::uint32_t h2 = hash(h1 ^ 0x9e3779b9u);
            const double ju = static_cast<double>(h1 >> 8) * (1.0 / 16777216.0);
            const double jv = static_cast<double>(h2 >> 8) * (1.0 / 16777216.0);
            const double u = (static_cast<double>(i) + ju) * inv, v = (static_cast<double>(j) + jv) * inv;
            const double z = 1.0 - 2.0 * u;
            const double r = std::sqrt(std::fmax(0.0, 1.0 - z * z));
            const double phi = 2.0 * detail::sh_pi * v;
            out[k] = glm::vec<3, Real, Q>(static_cast<Real>(r * std::cos(phi)), static_cast<Real>(r * std::sin(phi)),
                                          static_cast<Real>(z));
        }
    return detail::sh_result(Status::Ok, n, n, nullptr);
}

/// Builds the per-band rotation matrices of R (column-major GLM, acting on directions) for
/// sh_rotate. Band 1 is R itself in (y, z, x) order; bands 2+ follow Ivanic & Ruedenberg's
/// recursion. A reflection (det R < 0) is handled as the rotation -R times the parity (-1)^l.
/// Errors (the returned rotation's status): InvalidArgument (invalid order, R not orthogonal within
/// 1e-3), NonFinite (NaN/Inf in R).
template <typename Real, glm::qualifier Q>
inline SHRotation sh_make_rotation(int order, const glm::mat<3, 3, Real, Q>& R) {
    SHRotation out;
    if (!sh_order_valid(order)) {
        out.status = Status::InvalidArgument;
        out.detail = "order: outside 1 .. kSHMaxOrder";
        return out;
    }
    glm::dmat3 r(R);
    for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 3; ++k)
            if (!std::isfinite(r[c][k])) {
                out.status = Status::NonFinite;
                out.detail = "R: NaN or Inf";
                return out;
            }
    const glm::dmat3 rtr = glm::transpose(r) * r;
    for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 3; ++k)
            if (!(std::fabs(rtr[c][k] - (c == k ? 1.0 : 0.0)) <= 1e-3)) {
                out.status = Status::InvalidArgument;
                out.detail = "R: not orthonormal (R^T R - I beyond 1e-3)";
                return out;
            }
    const bool reflect = glm::determinant(r) < 0.0;
    if (reflect) r = -r;
    out.order = order;
    detail::sh_at(out, 0, 0, 0) = 1.0;
    if (order >= 2) {
        // band-1 index m = -1, 0, 1 -> coordinate y, z, x; element (m, n) = R(row p(m), column p(n))
        const int p[3] = {1, 2, 0};
        for (int m = -1; m <= 1; ++m)
            for (int n = -1; n <= 1; ++n) detail::sh_at(out, 1, m, n) = r[p[n + 1]][p[m + 1]];
    }
    for (int l = 2; l < order; ++l)
        for (int m = -l; m <= l; ++m)
            for (int n = -l; n <= l; ++n) {
                // Ivanic & Ruedenberg 1996, table 1: u, v, w coefficients.
                const int am = m < 0 ? -m : m, an = n < 0 ? -n : n;
                const double d = m == 0 ? 1.0 : 0.0;
                const double denom = an == l ? 2.0 * l * (2.0 * l - 1.0) : static_cast<double>((l + n) * (l - n));
                double u = std::sqrt(static_cast<double>((l + m) * (l - m)) / denom);
                double v = 0.5 * std::sqrt((1.0 + d) * static_cast<double>((l + am - 1) * (l + am)) / denom) * (1.0 - 2.0 * d);
                double w = -0.5 * std::sqrt(static_cast<double>((l - am - 1) * (l - am)) / denom) * (1.0 - d);
                if (u != 0.0) u *= detail::sh_ir_u(out, m, n, l);
                if (v != 0.0) v *= detail::sh_ir_v(out, m, n, l);
                if (w != 0.0) w *= detail::sh_ir_w(out, m, n, l);
                detail::sh_at(out, l, m, n) = u + v + w;
            }
    if (reflect)
        for (int l = 1; l < order; l += 2)
            for (int m = -l; m <= l; ++m)
                for (int n = -l; n <= l; ++n) detail::sh_at(out, l, m, n) = -detail::sh_at(out, l, m, n);
    out.status = Status::Ok;
    return out;
}

/// Applies a rotation built by sh_make_rotation: out represents f(R^T s) (see the header
/// comment). `in` holds in_count and `out` capacity Real elements; each needs order^2. `in` and
/// `out` may be the same array. A rotation whose status is not Ok is InvalidArgument.
template <typename Real>
inline SHResult sh_rotate(const SHRotation& rot, const Real* in, std::size_t in_count, Real* out, std::size_t capacity) {
    if (rot.status != Status::Ok || !sh_order_valid(rot.order))
        return detail::sh_result(Status::InvalidArgument, 0, 0, "rot: status not Ok");
    const std::size_t n = sh_coefficient_count(rot.order);
    if (!in || !out) return detail::sh_result(Status::InvalidArgument, 0, n, !in ? "in: null" : "out: null");
    if (in_count < n || capacity < n)
        return detail::sh_result(Status::BufferTooSmall, 0, n, in_count < n ? "in_count: below order^2" : "capacity: below needed (see needed)");
    if (!detail::sh_all_finite(in, n)) return detail::sh_result(Status::NonFinite, 0, n, "in: NaN or Inf");
    double src[kSHMaxCoefficients];
    for (std::size_t i = 0; i < n; ++i) src[i] = static_cast<double>(in[i]);
    double dst[kSHMaxCoefficients];
    for (int l = 0; l < rot.order; ++l)
        for (int m = -l; m <= l; ++m) {
            double s = 0.0;
            for (int k = -l; k <= l; ++k) s += detail::sh_get(rot, l, m, k) * src[sh_index(l, k)];
            dst[sh_index(l, m)] = s;
        }
    if (!detail::sh_store(dst, n, out)) return detail::sh_result(Status::Overflow, 0, n, "out: a coefficient beyond Real range");
    return detail::sh_result(Status::Ok, n, n, nullptr);
}

/// Convenience: builds the rotation of R and applies it (one call per vector; build once with
/// sh_make_rotation for RGB or many vectors). Errors of either step.
template <typename Real, glm::qualifier Q>
inline SHResult sh_rotate(int order, const glm::mat<3, 3, Real, Q>& R, const Real* in, std::size_t in_count, Real* out,
                          std::size_t capacity) {
    const SHRotation rot = sh_make_rotation(order, R);
    if (rot.status != Status::Ok) return detail::sh_result(rot.status, 0, sh_coefficient_count(order), rot.detail);
    return sh_rotate(rot, in, in_count, out, capacity);
}

/// A_l, the band-l coefficient of the clamped cosine max(cos theta, 0) in Funk-Hecke form
/// (Ramamoorthi & Hanrahan 2001, eqs. 8-9): A_0 = pi, A_1 = 2 pi / 3, A_l = 0 for odd l > 1,
/// A_l = 2 pi (-1)^(l/2 - 1) / ((l + 2)(l - 1)) * l! / (2^l ((l/2)!)^2) for even l. Then
/// integral f(s) max(n.s, 0) ds = sum_lm A_l f_lm y_lm(n). Total: negative l gives 0; every l
/// gives a finite value in [-pi / 4, pi] (large even l by lgamma instead of factorials).
inline double sh_clamped_cosine_band(int l) {
    if (l < 0) return 0.0;
    if (l == 0) return detail::sh_pi;
    if (l == 1) return 2.0 * detail::sh_pi / 3.0;
    if (l % 2 == 1) return 0.0;
    const double sign = ((l / 2 - 1) % 2 == 0) ? 1.0 : -1.0;
    const double lead = 2.0 * detail::sh_pi * sign / ((static_cast<double>(l) + 2.0) * (static_cast<double>(l) - 1.0));
    if (l <= 64) {
        const double half = detail::sh_factorial(l / 2);
        return lead * detail::sh_factorial(l) / (std::pow(2.0, l) * half * half);
    }
    // l! / (2^l ((l/2)!)^2) = C(l, l/2) / 2^l, in (0, 1]: its logarithm by lgamma
    const double dl = static_cast<double>(l), h = static_cast<double>(l / 2);
    return lead * std::exp(std::lgamma(dl + 1.0) - 2.0 * std::lgamma(h + 1.0) - dl * std::log(2.0));
}

/// Convolution with a kernel symmetric about +z, given by its SH coefficients zonal[l] (the
/// coefficient of y_{l,0}, l < order): out_lm = sqrt(4 pi / (2l + 1)) zonal[l] in_lm (Funk-Hecke).
/// The output represents (f * h)(n) = integral f(s) h(n.s) ds. `zonal` holds zonal_count Real
/// elements (>= order), `in` in_count and `out` capacity (each >= order^2).
template <typename Real>
inline SHResult sh_convolve_zonal(int order, const Real* zonal, std::size_t zonal_count, const Real* in,
                                  std::size_t in_count, Real* out, std::size_t capacity) {
    if (!sh_order_valid(order)) return detail::sh_result(Status::InvalidArgument, 0, 0, "order: outside 1 .. kSHMaxOrder");
    const std::size_t n = sh_coefficient_count(order);
    if (!zonal || !in || !out) return detail::sh_result(Status::InvalidArgument, 0, n, !zonal ? "zonal: null" : (!in ? "in: null" : "out: null"));
    if (zonal_count < static_cast<std::size_t>(order) || in_count < n || capacity < n)
        return detail::sh_result(Status::BufferTooSmall, 0, n,
                                 zonal_count < static_cast<std::size_t>(order) ? "zonal_count: below order"
                                 : (in_count < n ? "in_count: below order^2" : "capacity: below needed (see needed)"));
    if (!detail::sh_all_finite(in, n) || !detail::sh_all_finite(zonal, static_cast<std::size_t>(order)))
        return detail::sh_result(Status::NonFinite, 0, n, !detail::sh_all_finite(in, n) ? "in: NaN or Inf" : "zonal: NaN or Inf");
    double k[kSHMaxOrder];
    for (int l = 0; l < order; ++l)
        k[l] = std::sqrt(4.0 * detail::sh_pi / (2.0 * l + 1.0)) * static_cast<double>(zonal[l]);
    double dst[kSHMaxCoefficients];
    for (int l = 0; l < order; ++l)
        for (int m = -l; m <= l; ++m) dst[sh_index(l, m)] = k[l] * static_cast<double>(in[sh_index(l, m)]);
    if (!detail::sh_store(dst, n, out)) return detail::sh_result(Status::Overflow, 0, n, "out: a coefficient beyond Real range");
    return detail::sh_result(Status::Ok, n, n, nullptr);
}

/// Convolution with the clamped cosine: out_lm = A_l in_lm (sh_clamped_cosine_band). For a
/// radiance environment `in`, out reconstructs irradiance E(n) = integral L(s) max(n.s, 0) ds;
/// diffuse exit radiance is albedo / pi * E. `in` holds in_count and `out` capacity Real elements
/// (each >= order^2).
template <typename Real>
inline SHResult sh_convolve_clamped_cosine(int order, const Real* in, std::size_t in_count, Real* out,
                                           std::size_t capacity) {
    if (!sh_order_valid(order)) return detail::sh_result(Status::InvalidArgument, 0, 0, "order: outside 1 .. kSHMaxOrder");
    const std::size_t n = sh_coefficient_count(order);
    if (!in || !out) return detail::sh_result(Status::InvalidArgument, 0, n, !in ? "in: null" : "out: null");
    if (in_count < n || capacity < n)
        return detail::sh_result(Status::BufferTooSmall, 0, n, in_count < n ? "in_count: below order^2" : "capacity: below needed (see needed)");
    if (!detail::sh_all_finite(in, n)) return detail::sh_result(Status::NonFinite, 0, n, "in: NaN or Inf");
    double dst[kSHMaxCoefficients];
    for (int l = 0; l < order; ++l) {
        const double a = sh_clamped_cosine_band(l);
        for (int m = -l; m <= l; ++m) dst[sh_index(l, m)] = a * static_cast<double>(in[sh_index(l, m)]);
    }
    if (!detail::sh_store(dst, n, out)) return detail::sh_result(Status::Overflow, 0, n, "out: a coefficient beyond Real range");
    return detail::sh_result(Status::Ok, n, n, nullptr);
}

/// Integral of the product of two band-limited functions = dot product of their coefficients
/// (course notes, "Integration"). `a` holds a_count and `b` b_count Real elements (>= order^2).
/// Non-finite input gives NonFinite and value 0.
template <typename Real>
inline SHValue<Real> sh_dot(int order, const Real* a, std::size_t a_count, const Real* b, std::size_t b_count) {
    if (!sh_order_valid(order)) return detail::sh_value(Status::InvalidArgument, Real(0), "order: outside 1 .. kSHMaxOrder");
    const std::size_t n = sh_coefficient_count(order);
    if (!a || !b) return detail::sh_value(Status::InvalidArgument, Real(0), !a ? "a: null" : "b: null");
    if (a_count < n || b_count < n)
        return detail::sh_value(Status::BufferTooSmall, Real(0), a_count < n ? "a_count: below order^2" : "b_count: below order^2");
    if (!detail::sh_all_finite(a, n) || !detail::sh_all_finite(b, n))
        return detail::sh_value(Status::NonFinite, Real(0), !detail::sh_all_finite(a, n) ? "a: NaN or Inf" : "b: NaN or Inf");
    double s = 0.0;
    for (std::size_t i = 0; i < n; ++i) s += static_cast<double>(a[i]) * static_cast<double>(b[i]);
    if (!detail::sh_fits<Real>(s)) return detail::sh_value(Status::Overflow, Real(0), "value: beyond Real range");
    return detail::sh_value(Status::Ok, static_cast<Real>(s), nullptr);
}

}  // namespace shadowkit
