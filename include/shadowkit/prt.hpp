// shadowkit/prt.hpp - precomputed radiance transfer (PRT) for diffuse surfaces with shadows.
//
// Per vertex, the spherical-harmonics (SH) projection of visibility x clamped cosine (the "transfer
// vector"), computed from a visibility callback you supply (any ray tracer: the header needs
// none), with stratified sphere samples; projection of an environment into SH; runtime shading as
// one dot product per color channel (here on the CPU, glsl/prt.glsl on the GPU); clustered PCA
// compression. docs/prt.md has complete programs.
//
// Usage:
//   #include <shadowkit/prt.hpp>
//   namespace sk = shadowkit;
//   sk::PrtSamples samples = sk::prt_make_samples(/*order*/ 4, /*strata*/ 32, /*seed*/ 1u);  // once
//   sk::PrtTransferOptions opt;  opt.ray_offset = 1e-4f * scene_size;
//   std::vector<float> T(vertex_count * sk::prt_coefficient_count(4));
//   auto r = sk::prt_compute_transfer(samples, opt, positions, normals, vertex_count,
//       [&](const glm::vec3& o, const glm::vec3& d) { return !my_ray_hits(o, d); },  // true = sky seen
//       T.data(), T.size());                         // or a function pointer + user pointer
//   glm::vec3 env[25];                               // environment radiance L(s) in SH, per frame
//   sk::prt_project_environment(samples, [](const glm::vec3& s) { return sky(s); }, env, 25);
//   glm::vec3 c = albedo_rgb * sk::prt_shade_rgb(4, &T[v * 16], env).value;  // exit radiance at v
//   // GPU: upload T as an SSBO and env as a uniform vec3[25]; glsl/prt.glsl does the dot product.
//   // Optional compression (clustered PCA): 16 clusters x (mean + 4 vectors) instead of 16 floats
//   sk::PrtCpca cp = sk::prt_cpca_compress(4, T.data(), 16, vertex_count, sk::PrtCpcaOptions{});
//   std::vector<glm::vec3> R(cp.clusters * (cp.components + 1));   // per frame, per cluster
//   sk::prt_cpca_project_environment(cp, env, 16, R.data(), R.size());
//   glm::vec3 c2 = albedo_rgb * sk::prt_cpca_shade(cp, R.data(), v).value;   // or all: prt_cpca_shade_mesh
//   // Rotating the environment: rotate env's SH vector (spherical_harmonics.hpp, sh_rotate).
//
// Conventions:
//   * order = number of SH bands, 1 .. kPrtMaxOrder (5); n = order^2 coefficients per vertex.
//     Basis, index l (l + 1) + m and signs are those of spherical_harmonics.hpp (real,
//     orthonormal, no Condon-Shortley phase): vectors from the two headers mix freely. Transfer
//     computed at order 5 truncated to its first k^2 entries is the order-k transfer.
//   * Transfer T_i = (albedo / pi) integral V(p, s) max(n.s, 0) y_i(s) ds, so for a radiance
//     environment L_i = integral L(s) y_i(s) ds the exit radiance is sum_i T_i L_i (a plain albedo
//     of 1 here and the color multiplied at shading time is the usual split).
//   * Shadowed estimator: T = T_unshadowed - (albedo / pi) (4 pi / N) sum_j (1 - V_j) max(n.s_j, 0)
//     y(s_j). T_unshadowed is exact (A_l y_lm(n)); only the occluded part is sampled, which is
//     the same expectation as the course's sum over V_j but with no noise where nothing occludes.
//   * Visibility callback: visible(origin, direction) returns true when the ray origin + t dir,
//     t > 0, escapes to the environment. origin = position + ray_offset * normal; direction is a
//     unit vector in the half-space of the normal. Called from the calling thread only; for
//     parallel precomputation call prt_compute_transfer on disjoint vertex ranges from several
//     threads (the sample set is read-only).
//   * Vertices with a zero normal (a degenerate face fan) get a zero transfer vector and are counted
//     in `degenerate_vertices`; the call still succeeds. A NaN/Inf normal or position is
//     Status::NonFinite.
//   * Buffers are counted in elements of the pointer's type (float for transfer vectors, glm::vec3
//     for RGB environments and colors); results say `count` (elements written; 0 on an error) and
//     `needed`. A null pointer with a non-zero count is Status::InvalidArgument; an output shorter
//     than needed is Status::BufferTooSmall (nothing written). Input arrays whose length follows
//     from other arguments (a transfer vector: order^2 floats; an environment: order^2 vec3) are
//     stated next to the pointer.
//   * Status: NaN/Inf in an input is Status::NonFinite; a finite input whose result does not fit a
//     float is Status::Overflow; `Ok` means every output is finite. A non-Ok result's `detail` names
//     the offending input and the rule ("strata: outside [1, 1024]"), a static string; nullptr when
//     Ok. Functions that allocate say so (prt_make_samples, prt_cpca_compress); shading never allocates.
//   * This header takes no light: the lighting is an environment in SH (a sun is a sharp lobe in it).
//
// Based on:
//   P.-P. Sloan, J. Kautz, J. Snyder, "Precomputed Radiance Transfer for Real-Time Rendering in
//   Dynamic, Low-Frequency Lighting Environments", SIGGRAPH 2002: section 5 (diffuse transfer:
//   unshadowed eq. 5 -> clamped cosine, shadowed eq. 6 with visibility), section 4 (projection).
//   J. Kautz, "Precomputed Radiance Transfer", SIGGRAPH 2004 course #26 "Real-Time Shadowing
//   Techniques" notes: transfer precomputation T_i = (rho / pi) integral V_p(s) max(n.s, 0) y_i(s) ds
//   by Monte Carlo with uniform sphere samples (weights 4 pi / N); shading = dot(T_p, L).
//   R. Ramamoorthi, P. Hanrahan, "An Efficient Representation for Irradiance Environment Maps",
//   SIGGRAPH 2001, eqs. 8-9 (clamped-cosine coefficients A_l, used for the unshadowed transfer).
//   P.-P. Sloan, J. Hall, J. Hart, J. Snyder, "Clustered Principal Components for Precomputed
//   Radiance Transfer", SIGGRAPH 2003 (VQ then PCA per cluster; the course notes' "VQ + PCA":
//   T_p . L = sum_k w_pk (T^k . L), the per-cluster dot products done once per frame).
//
// MIT License. Copyright (c) shadowkit contributors.
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
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

/// Shadowed (visibility callback) or unshadowed (closed form, no rays) diffuse transfer.
enum class PrtMode { Shadowed, Unshadowed };

/// Highest supported order (number of SH bands).
constexpr int kPrtMaxOrder = 5;

/// order^2 for orders 1 .. kPrtMaxOrder, 0 otherwise. Total.
constexpr std::size_t prt_coefficient_count(int order) {
    return (order >= 1 && order <= kPrtMaxOrder) ? static_cast<std::size_t>(order) * static_cast<std::size_t>(order)
                                                 : 0u;
}

/// Stratified sphere directions with their SH basis values (built by prt_make_samples).
struct PrtSamples {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    int order = 0;
    std::vector<glm::vec3> directions;  ///< unit, uniform over the sphere
    std::vector<float> basis;           ///< directions.size() * order^2, basis[j * n + i] = y_i(s_j)
    double weight = 0.0;                ///< 4 pi / N
    std::size_t count() const { return directions.size(); }
};

/// Options of prt_compute_transfer.
struct PrtTransferOptions {
    PrtMode mode = PrtMode::Shadowed;
    float albedo = 1.0f;       ///< rho in T = (rho / pi) ...; |albedo| <= 1e30; multiply color at shading time
    float ray_offset = 0.0f;   ///< shadow-ray origin moved along the normal (world units, >= 0; 0 when the callback handles self-hits)
    /// Optional progress report: called after each vertex with (user, done, total).
    void (*progress)(void* user, std::size_t done, std::size_t total) = nullptr;
    void* progress_user = nullptr;
};

/// Result of prt_compute_transfer.
struct PrtTransferResult {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    std::size_t count = 0;                ///< floats written (vertex_count * n when Ok, else 0)
    std::size_t needed = 0;               ///< floats the output needs (vertex_count * n)
    std::size_t degenerate_vertices = 0;  ///< zero transfer written (zero normal)
    std::uint64_t rays = 0;               ///< visibility callbacks made
};

/// Status, values written and values the output needs.
struct PrtResult {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    std::size_t count = 0;   ///< elements written (== needed when Ok, 0 otherwise)
    std::size_t needed = 0;  ///< elements the output needs
};

/// A scalar shading result.
struct PrtValue {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    float value = 0.0f;  ///< finite when Ok, 0 otherwise
};

/// An RGB shading result (exit radiance).
struct PrtRgbValue {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    glm::vec3 value{0.0f};  ///< finite when Ok, 0 otherwise
};

/// Visibility callback: true when the ray escapes (the environment is seen along `direction`).
using PrtVisibilityFn = bool (*)(void* user, const glm::vec3& origin, const glm::vec3& direction);

namespace detail {

constexpr double prt_pi = 3.14159265358979323846;

inline double prt_factorial(int n) {
    double f = 1.0;
    for (int i = 2; i <= n; ++i) f *= static_cast<double>(i);
    return f;
}

// Real SH basis, same definition as spherical_harmonics.hpp (Legendre recurrence on the
// polynomial part, (x + i y)^m for the azimuthal part; exact at the poles). Unit (x, y, z).
inline void prt_basis(int order, double x, double y, double z, double* out) {
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
            const double k = std::sqrt((2.0 * l + 1.0) / (4.0 * prt_pi) * prt_factorial(l - m) / prt_factorial(l + m));
            if (m == 0) {
                out[l * (l + 1)] = k * q;
            } else {
                out[l * (l + 1) + m] = sqrt2 * k * q * cm;
                out[l * (l + 1) - m] = sqrt2 * k * q * sm;
            }
        }
    }
}

// Clamped-cosine band coefficient A_l (Ramamoorthi & Hanrahan 2001, eqs. 8-9), l < kPrtMaxOrder.
inline double prt_clamped_cosine(int l) {
    if (l == 0) return prt_pi;
    if (l == 1) return 2.0 * prt_pi / 3.0;
    if (l % 2 == 1) return 0.0;
    const double sign = ((l / 2 - 1) % 2 == 0) ? 1.0 : -1.0;
    const double half = prt_factorial(l / 2);
    return 2.0 * prt_pi * sign / (static_cast<double>(l + 2) * static_cast<double>(l - 1)) * prt_factorial(l) /
           (std::pow(2.0, l) * half * half);
}

inline bool prt_finite3(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Unit direction in double: false for a zero or non-finite vector.
inline bool prt_unit(const glm::vec3& v, glm::dvec3& out) {
    glm::dvec3 d(v);
    if (!std::isfinite(d.x) || !std::isfinite(d.y) || !std::isfinite(d.z)) return false;
    const double big = std::fmax(std::fabs(d.x), std::fmax(std::fabs(d.y), std::fabs(d.z)));
    if (!(big > 0.0)) return false;
    d /= big;
    out = d / std::sqrt(glm::dot(d, d));
    return true;
}

inline bool prt_fits(double v) { return std::fabs(v) <= static_cast<double>(std::numeric_limits<float>::max()); }

inline std::uint32_t prt_hash(std::uint32_t v) {  // lowbias32 (C. Wellons)
    v ^= v >> 16;
    v *= 0x7feb352du;
    v ^= v >> 15;
    v *= 0x846ca68bu;
    v ^= v >> 16;
    return v;
}

// True when every component of v[0 .. n) is finite: an OR over the exponent bits (a float is
// NaN/Inf exactly when its exponent bits are all ones), which vectorizes.
inline bool prt_all_finite(const glm::vec3* v, std::size_t n) {
    const float* f = &v[0].x;
    std::uint32_t any = 0;
    for (std::size_t i = 0; i < 3 * n; ++i) {
        std::uint32_t bits;
        std::memcpy(&bits, f + i, sizeof bits);
        any |= ((bits & 0x7f800000u) + 0x00800000u) & 0x80000000u;
    }
    return any == 0;
}

// `why`: where a non-Ok status came from (a static string; nullptr with Ok).
inline PrtResult prt_result(Status s, std::size_t count, std::size_t needed, const char* why) {
    PrtResult r;
    r.status = s;
    r.detail = why;
    r.count = count;
    r.needed = needed;
    return r;
}

inline PrtTransferResult prt_transfer_result(Status s, std::size_t needed, const char* why) {
    PrtTransferResult r;
    r.status = s;
    r.detail = why;
    r.needed = needed;
    return r;
}

// sum_i t[i] env[i] in float (the hot path); when that is not finite, NonFinite for NaN/Inf input,
// else the sum in double: Ok if it fits a float, Overflow if not.
inline PrtRgbValue prt_dot_rgb(std::size_t n, const float* t, const glm::vec3* env) {
    PrtRgbValue r;
    glm::vec3 c(0.0f);
    for (std::size_t i = 0; i < n; ++i) c += t[i] * env[i];
    if (prt_finite3(c)) {
        r.status = Status::Ok;
        r.value = c;
        return r;
    }
    glm::dvec3 d(0.0);
    for (std::size_t i = 0; i < n; ++i) {
        if (!std::isfinite(t[i]) || !prt_finite3(env[i])) {
            r.status = Status::NonFinite;
            r.detail = !std::isfinite(t[i]) ? "transfer: NaN or Inf" : "env: NaN or Inf";
            return r;
        }
        d += static_cast<double>(t[i]) * glm::dvec3(env[i]);
    }
    if (!prt_fits(d.x) || !prt_fits(d.y) || !prt_fits(d.z)) {
        r.status = Status::Overflow;
        r.detail = "value: beyond float range";
        return r;
    }
    r.status = Status::Ok;
    r.value = glm::vec3(d);
    return r;
}

}  // namespace detail

/// SH basis values y_i(dir), i < order^2 (same as sh_evaluate in spherical_harmonics.hpp). `out`
/// holds capacity floats; it needs order^2. A zero direction (InvalidArgument) or a non-finite one
/// (NonFinite) writes zeros.
inline PrtResult prt_sh_basis(int order, const glm::vec3& dir, float* out, std::size_t capacity) {
    const std::size_t n = prt_coefficient_count(order);
    if (n == 0) return detail::prt_result(Status::InvalidArgument, 0, 0, "order: outside 1 .. 5");
    if (!out) return detail::prt_result(Status::InvalidArgument, 0, n, "out: null");
    if (capacity < n) return detail::prt_result(Status::BufferTooSmall, 0, n, "capacity: below needed (see needed)");
    glm::dvec3 d;
    if (!detail::prt_unit(dir, d)) {
        for (std::size_t i = 0; i < n; ++i) out[i] = 0.0f;
        return detail::prt_result(detail::prt_finite3(dir) ? Status::InvalidArgument : Status::NonFinite, 0, n,
                                  detail::prt_finite3(dir) ? "dir: zero vector" : "dir: NaN or Inf");
    }
    double b[25];
    detail::prt_basis(order, d.x, d.y, d.z, b);
    for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<float>(b[i]);
    return detail::prt_result(Status::Ok, n, n, nullptr);
}

/// strata^2 stratified jittered uniform sphere directions (course notes: theta = 2 acos(sqrt(1 - x)),
/// phi = 2 pi y on the unit square, i.e. z = 1 - 2x, one jittered sample per cell) and their basis
/// values. Deterministic for a seed on every platform. Allocates. Errors (the returned set's
/// status, empty set): InvalidArgument (order outside 1 .. kPrtMaxOrder, strata outside 1 .. 1024).
inline PrtSamples prt_make_samples(int order, int strata, std::uint32_t seed) {
    PrtSamples out;
    const std::size_t n = prt_coefficient_count(order);
    if (n == 0 || strata < 1 || strata > 1024) {
        out.status = Status::InvalidArgument;
        out.detail = n == 0 ? "order: outside 1 .. 5" : "strata: outside [1, 1024]";
        return out;
    }
    const std::size_t count = static_cast<std::size_t>(strata) * static_cast<std::size_t>(strata);
    out.order = order;
    out.directions.resize(count);
    out.basis.resize(count * n);
    out.weight = 4.0 * detail::prt_pi / static_cast<double>(count);
    const double inv = 1.0 / static_cast<double>(strata);
    double b[25];
    std::size_t k = 0;
    for (int i = 0; i < strata; ++i)
        for (int j = 0; j < strata; ++j, ++k) {
            const std::uint32_t h1 = detail::prt_hash(static_cast<std::uint32_t>(k) * 2u + detail::prt_hash(seed));
            const std::uint32_t h2 = detail::prt_hash(h1 ^ 0x9e3779b9u);
            const double u = (static_cast<double>(i) + static_cast<double>(h1 >> 8) * (1.0 / 16777216.0)) * inv;
            const double v = (static_cast<double>(j) + static_cast<double>(h2 >> 8) * (1.0 / 16777216.0)) * inv;
            const double z = 1.0 - 2.0 * u, r = std::sqrt(std::fmax(0.0, 1.0 - z * z)), phi = 2.0 * detail::prt_pi * v;
            out.directions[k] = glm::vec3(glm::dvec3(r * std::cos(phi), r * std::sin(phi), z));
            glm::dvec3 d;  // basis of the stored (float) direction, renormalized
            if (!detail::prt_unit(out.directions[k], d)) d = glm::dvec3(0.0, 0.0, 1.0);
            detail::prt_basis(order, d.x, d.y, d.z, b);
            for (std::size_t c = 0; c < n; ++c) out.basis[k * n + c] = static_cast<float>(b[c]);
        }
    out.status = Status::Ok;
    return out;
}

/// Shadowed (or unshadowed) diffuse transfer vectors of vertex_count vertices into
/// out[v * n + i] (Sloan et al. 2002 eq. 6; course notes' Monte Carlo estimator, see the header
/// comment for the control variate). `visible` is any callable bool(const glm::vec3& origin,
/// const glm::vec3& dir); it is not called in Unshadowed mode. `positions` and `normals` hold
/// vertex_count glm::vec3 elements (positions may be null in Unshadowed mode); `out` holds capacity
/// floats; it needs vertex_count * order^2 (`needed`).
/// Errors (nothing written, count 0): InvalidArgument (samples whose status is not Ok or that do
/// not hold order^2 basis values per direction, a mode that is not an enumerator, |albedo| > 1e30,
/// ray_offset < 0, a null array with vertex_count > 0), NonFinite (albedo, ray_offset, a normal or
/// a position), Overflow (position + ray_offset * normal not finite), BufferTooSmall.
template <class Visible>
inline PrtTransferResult prt_compute_transfer(const PrtSamples& samples, const PrtTransferOptions& opt,
                                              const glm::vec3* positions, const glm::vec3* normals,
                                              std::size_t vertex_count, Visible&& visible, float* out,
                                              std::size_t capacity) {
    const std::size_t n = prt_coefficient_count(samples.order);
    const bool shadowed = opt.mode == PrtMode::Shadowed;
    if (samples.status != Status::Ok || n == 0 || (opt.mode != PrtMode::Shadowed && opt.mode != PrtMode::Unshadowed))
        return detail::prt_transfer_result(Status::InvalidArgument, 0,
                                           samples.status != Status::Ok || n == 0 ? "samples: status not Ok" : "mode: unknown PrtMode");
    if (shadowed && (samples.count() == 0 || samples.basis.size() != samples.count() * n))
        return detail::prt_transfer_result(Status::InvalidArgument, 0, "samples: no directions or basis (Shadowed)");
    if (!std::isfinite(opt.albedo) || !std::isfinite(opt.ray_offset))
        return detail::prt_transfer_result(Status::NonFinite, 0, !std::isfinite(opt.albedo) ? "albedo: NaN or Inf" : "ray_offset: NaN or Inf");
    if (std::fabs(opt.albedo) > 1e30f || opt.ray_offset < 0.0f)
        return detail::prt_transfer_result(Status::InvalidArgument, 0, opt.ray_offset < 0.0f ? "ray_offset: < 0" : "albedo: |albedo| > 1e30");
    if (vertex_count > std::numeric_limits<std::size_t>::max() / n)
        return detail::prt_transfer_result(Status::InvalidArgument, 0, "vertex_count: too large");
    PrtTransferResult res;
    res.needed = vertex_count * n;
    if (vertex_count == 0) {
        res.status = Status::Ok;
        return res;
    }
    if (!normals || !out || (shadowed && !positions))
        return detail::prt_transfer_result(Status::InvalidArgument, res.needed,
                                           !normals ? "normals: null" : (!out ? "out: null" : "positions: null (Shadowed)"));
    if (capacity < res.needed) return detail::prt_transfer_result(Status::BufferTooSmall, res.needed, "capacity: below needed (see needed)");
    // validate every vertex before any ray is cast
    for (std::size_t v = 0; v < vertex_count; ++v) {
        if (!detail::prt_finite3(normals[v]) || (shadowed && !detail::prt_finite3(positions[v])))
            return detail::prt_transfer_result(Status::NonFinite, res.needed,
                                               !detail::prt_finite3(normals[v]) ? "normals: NaN or Inf" : "positions: NaN or Inf");
        glm::dvec3 nrm;
        if (shadowed && detail::prt_unit(normals[v], nrm) &&
            !detail::prt_finite3(positions[v] + opt.ray_offset * glm::vec3(nrm)))
            return detail::prt_transfer_result(Status::Overflow, res.needed, "positions, ray_offset: the ray origin beyond float");
    }
    const double scale = static_cast<double>(opt.albedo) / detail::prt_pi;
    double t[25], b[25];
    for (std::size_t v = 0; v < vertex_count; ++v) {
        float* dst = out + v * n;
        glm::dvec3 nrm;
        if (!detail::prt_unit(normals[v], nrm)) {  // zero normal (finite: checked above)
            for (std::size_t i = 0; i < n; ++i) dst[i] = 0.0f;
            ++res.degenerate_vertices;
            if (opt.progress) opt.progress(opt.progress_user, v + 1, vertex_count);
            continue;
        }
        // unshadowed part, exact: (rho / pi) A_l y_lm(n) (Sloan et al. 2002 eq. 5 in SH)
        detail::prt_basis(samples.order, nrm.x, nrm.y, nrm.z, b);
        for (int l = 0; l < samples.order; ++l) {
            const double a = scale * detail::prt_clamped_cosine(l);
            for (int m = -l; m <= l; ++m) t[l * (l + 1) + m] = a * b[l * (l + 1) + m];
        }
        if (shadowed) {
            const glm::vec3 nf(nrm);
            const glm::vec3 origin = positions[v] + opt.ray_offset * nf;
            double occ[25] = {};
            for (std::size_t j = 0; j < samples.count(); ++j) {
                const glm::vec3& s = samples.directions[j];
                const double c = static_cast<double>(s.x) * nrm.x + static_cast<double>(s.y) * nrm.y +
                                 static_cast<double>(s.z) * nrm.z;
                if (!(c > 0.0)) continue;
                ++res.rays;
                if (visible(origin, s)) continue;
                const float* y = &samples.basis[j * n];
                for (std::size_t i = 0; i < n; ++i) occ[i] += c * static_cast<double>(y[i]);
            }
            for (std::size_t i = 0; i < n; ++i) t[i] -= scale * samples.weight * occ[i];
        }
        for (std::size_t i = 0; i < n; ++i) dst[i] = static_cast<float>(t[i]);
        if (opt.progress) opt.progress(opt.progress_user, v + 1, vertex_count);
    }
    res.count = res.needed;
    res.status = Status::Ok;
    return res;
}

/// Function-pointer form: visible(user, origin, direction). A null `visible` in Shadowed mode is
/// InvalidArgument.
inline PrtTransferResult prt_compute_transfer(const PrtSamples& samples, const PrtTransferOptions& opt,
                                              const glm::vec3* positions, const glm::vec3* normals,
                                              std::size_t vertex_count, PrtVisibilityFn visible, void* user,
                                              float* out, std::size_t capacity) {
    if (!visible && opt.mode == PrtMode::Shadowed)
        return detail::prt_transfer_result(Status::InvalidArgument, prt_coefficient_count(samples.order) * vertex_count,
                                           "visible: null (Shadowed)");
    return prt_compute_transfer(
        samples, opt, positions, normals, vertex_count,
        [visible, user](const glm::vec3& o, const glm::vec3& d) { return visible(user, o, d); }, out, capacity);
}

/// Projects an environment's radiance into SH with the sample set: out[i] = (4 pi / N) sum_j
/// L(s_j) y_i(s_j). `radiance` is any callable glm::vec3(const glm::vec3& dir). `out` holds
/// capacity glm::vec3 elements; it needs order^2. Errors (zeros written): InvalidArgument (samples
/// whose status is not Ok or inconsistent, out null), NonFinite (a radiance value), Overflow (a
/// coefficient does not fit a float), BufferTooSmall.
template <class Radiance>
inline PrtResult prt_project_environment(const PrtSamples& samples, Radiance&& radiance, glm::vec3* out,
                                         std::size_t capacity) {
    const std::size_t n = prt_coefficient_count(samples.order);
    if (samples.status != Status::Ok || n == 0 || samples.count() == 0 || samples.basis.size() != samples.count() * n)
        return detail::prt_result(Status::InvalidArgument, 0, n, "samples: status not Ok (or no directions)");
    if (!out) return detail::prt_result(Status::InvalidArgument, 0, n, "out: null");
    if (capacity < n) return detail::prt_result(Status::BufferTooSmall, 0, n, "capacity: below needed (see needed)");
    glm::dvec3 acc[25] = {};
    for (std::size_t j = 0; j < samples.count(); ++j) {
        const glm::vec3 L = radiance(samples.directions[j]);
        if (!detail::prt_finite3(L)) {
            for (std::size_t i = 0; i < n; ++i) out[i] = glm::vec3(0.0f);
            return detail::prt_result(Status::NonFinite, 0, n, "radiance: NaN or Inf");
        }
        for (std::size_t i = 0; i < n; ++i) acc[i] += static_cast<double>(samples.basis[j * n + i]) * glm::dvec3(L);
    }
    for (std::size_t i = 0; i < n; ++i) {
        out[i] = glm::vec3(acc[i] * samples.weight);
        if (!detail::prt_finite3(out[i])) {  // finite radiance too large for float
            for (std::size_t k = 0; k < n; ++k) out[k] = glm::vec3(0.0f);
            return detail::prt_result(Status::Overflow, 0, n, "radiance: a coefficient beyond float");
        }
    }
    return detail::prt_result(Status::Ok, n, n, nullptr);
}

/// Exit radiance at one vertex: sum_i T_i L_i per channel (course notes: shading = dot product).
/// `transfer` holds order^2 floats, `env` order^2 glm::vec3. Errors (value 0): InvalidArgument
/// (invalid order, a null pointer), NonFinite (NaN/Inf in transfer or env), Overflow (the sum does
/// not fit a float). The float dot product is the hot path; inputs are checked only when its
/// result is not finite.
inline PrtRgbValue prt_shade_rgb(int order, const float* transfer, const glm::vec3* env) {
    const std::size_t n = prt_coefficient_count(order);
    if (n == 0 || !transfer || !env) {
        PrtRgbValue r;
        r.status = Status::InvalidArgument;
        r.detail = n == 0 ? "order: outside 1 .. 5" : (!transfer ? "transfer: null" : "env: null");
        return r;
    }
    return detail::prt_dot_rgb(n, transfer, env);
}

/// Scalar form of prt_shade_rgb: `transfer` and `env` hold order^2 floats each.
inline PrtValue prt_shade(int order, const float* transfer, const float* env) {
    PrtValue r;
    const std::size_t n = prt_coefficient_count(order);
    if (n == 0 || !transfer || !env) {
        r.status = Status::InvalidArgument;
        r.detail = n == 0 ? "order: outside 1 .. 5" : (!transfer ? "transfer: null" : "env: null");
        return r;
    }
    float c = 0.0f;
    for (std::size_t i = 0; i < n; ++i) c += transfer[i] * env[i];
    if (std::isfinite(c)) {
        r.status = Status::Ok;
        r.value = c;
        return r;
    }
    double d = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        if (!std::isfinite(transfer[i]) || !std::isfinite(env[i])) {
            r.status = Status::NonFinite;
            r.detail = !std::isfinite(transfer[i]) ? "transfer: NaN or Inf" : "env: NaN or Inf";
            return r;
        }
        d += static_cast<double>(transfer[i]) * static_cast<double>(env[i]);
    }
    if (!detail::prt_fits(d)) {
        r.status = Status::Overflow;
        r.detail = "value: beyond float range";
        return r;
    }
    r.status = Status::Ok;
    r.value = static_cast<float>(d);
    return r;
}

/// Shades vertex_count vertices whose transfer vectors are stored with `stride` floats each
/// (stride >= order^2; a transfer computed at a higher order may be shaded at a lower one).
/// `transfers` holds (vertex_count - 1) * stride + order^2 floats, `env` order^2 glm::vec3; `out`
/// holds capacity glm::vec3 elements; it needs vertex_count. Errors (count 0): InvalidArgument
/// (invalid order, stride < order^2, a null pointer with vertex_count > 0), NonFinite (NaN/Inf in
/// env or a transfer vector), Overflow (a vertex's radiance does not fit a float), BufferTooSmall
/// (nothing written).
inline PrtResult prt_shade_mesh(int order, const float* transfers, std::size_t stride, std::size_t vertex_count,
                                const glm::vec3* env, glm::vec3* out, std::size_t capacity) {
    const std::size_t n = prt_coefficient_count(order);
    if (n == 0 || stride < n)
        return detail::prt_result(Status::InvalidArgument, 0, vertex_count, n == 0 ? "order: outside 1 .. 5" : "stride: below order^2");
    if (vertex_count == 0) return detail::prt_result(Status::Ok, 0, 0, nullptr);
    if (!transfers || !env || !out)
        return detail::prt_result(Status::InvalidArgument, 0, vertex_count, !transfers ? "transfers: null" : (!env ? "env: null" : "out: null"));
    if (capacity < vertex_count) return detail::prt_result(Status::BufferTooSmall, 0, vertex_count, "capacity: below vertex_count (see needed)");
    for (std::size_t i = 0; i < n; ++i)
        if (!detail::prt_finite3(env[i])) return detail::prt_result(Status::NonFinite, 0, vertex_count, "env: NaN or Inf");
    // hot path: the float dot products, then one branch-free finiteness pass over the output;
    // vertices that came out non-finite are classified (NaN input or overflow) one by one
    for (std::size_t v = 0; v < vertex_count; ++v) {
        const float* t = transfers + v * stride;
        glm::vec3 c(0.0f);
        for (std::size_t i = 0; i < n; ++i) c += t[i] * env[i];
        out[v] = c;
    }
    if (!detail::prt_all_finite(out, vertex_count))
        for (std::size_t v = 0; v < vertex_count; ++v) {
            if (detail::prt_finite3(out[v])) continue;
            const PrtRgbValue c = detail::prt_dot_rgb(n, transfers + v * stride, env);
            if (c.status != Status::Ok) return detail::prt_result(c.status, 0, vertex_count, c.detail);
            out[v] = c.value;
        }
    return detail::prt_result(Status::Ok, vertex_count, vertex_count, nullptr);
}

// ---------------------------------------------------------------- clustered PCA compression

/// Clustered PCA of transfer vectors (Sloan et al. 2003): every vertex p belongs to one cluster c
/// and T_p ~ mean_c + sum_k w_pk basis_ck, k < components (orthonormal basis per cluster).
struct PrtCpca {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    int order = 0;
    int components = 0;                     ///< PCA vectors per cluster (besides the mean)
    std::size_t clusters = 0;
    std::vector<float> means;               ///< clusters * n
    std::vector<float> bases;               ///< (clusters * components) * n, cluster-major
    std::vector<std::uint32_t> cluster_of;  ///< per vertex
    std::vector<float> weights;             ///< vertex_count * components
    double rms_error = 0.0;                 ///< RMS over vertices of |T_p - reconstruction| (L2 norm)
    std::size_t vertex_count() const { return cluster_of.size(); }
};

/// Options of prt_cpca_compress.
struct PrtCpcaOptions {
    std::size_t clusters = 16;   ///< >= 1, clamped to the vertex count
    int components = 4;          ///< 0 .. order^2 (0 = plain vector quantization)
    int iterations = 12;         ///< >= 0 k-means (Lloyd) iterations after a farthest-point start
    std::uint32_t seed = 1;      ///< picks the first center; the rest is deterministic
};

namespace detail {

// Eigen-decomposition of a symmetric n x n matrix a (row-major, destroyed) by cyclic Jacobi
// rotations; eigenvalues in w, eigenvectors in the columns of v.
inline void prt_jacobi_eigen(int n, double* a, double* w, double* v) {
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) v[i * n + j] = i == j ? 1.0 : 0.0;
    for (int sweep = 0; sweep < 64; ++sweep) {
        double off = 0.0, norm = 0.0;
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) {
                norm += a[i * n + j] * a[i * n + j];
                if (i != j) off += a[i * n + j] * a[i * n + j];
            }
        if (!(off > 1e-30 * norm)) break;
        for (int p = 0; p < n; ++p)
            for (int q = p + 1; q < n; ++q) {
                const double apq = a[p * n + q];
                if (apq == 0.0) continue;
                const double theta = (a[q * n + q] - a[p * n + p]) / (2.0 * apq);
                const double t = (theta >= 0.0 ? 1.0 : -1.0) / (std::fabs(theta) + std::sqrt(theta * theta + 1.0));
                const double c = 1.0 / std::sqrt(t * t + 1.0), sn = t * c;
                for (int k = 0; k < n; ++k) {  // columns p, q
                    const double akp = a[k * n + p], akq = a[k * n + q];
                    a[k * n + p] = c * akp - sn * akq;
                    a[k * n + q] = sn * akp + c * akq;
                }
                for (int k = 0; k < n; ++k) {  // rows p, q
                    const double apk = a[p * n + k], aqk = a[q * n + k];
                    a[p * n + k] = c * apk - sn * aqk;
                    a[q * n + k] = sn * apk + c * aqk;
                }
                for (int k = 0; k < n; ++k) {
                    const double vkp = v[k * n + p], vkq = v[k * n + q];
                    v[k * n + p] = c * vkp - sn * vkq;
                    v[k * n + q] = sn * vkp + c * vkq;
                }
            }
    }
    for (int i = 0; i < n; ++i) w[i] = a[i * n + i];
}

inline double prt_dist2(const float* a, const double* b, std::size_t n) {
    double d = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        const double e = static_cast<double>(a[i]) - b[i];
        d += e * e;
    }
    return d;
}

}  // namespace detail

namespace detail {

// Every used value finite (else NonFinite) with magnitude <= 1e30 (else InvalidArgument).
inline Status prt_cpca_check_values(const float* transfers, std::size_t stride, std::size_t n, std::size_t vertex_count,
                                    const char*& why) {
    for (std::size_t v = 0; v < vertex_count; ++v)
        for (std::size_t i = 0; i < n; ++i) {
            const float x = transfers[v * stride + i];
            if (!std::isfinite(x)) {
                return why = "transfers: NaN or Inf", Status::NonFinite;
            }
            if (!(std::fabs(x) <= 1e30f)) {
                return why = "transfers: |value| > 1e30", Status::InvalidArgument;
            }
        }
    return Status::Ok;
}

// Where prt_cpca_compress's InvalidArgument came from (the first failing argument, in its order).
inline const char* prt_cpca_why(std::size_t n, std::size_t stride, const PrtCpcaOptions& opt, std::size_t vertex_count,
                                const float* transfers) {
    if (n == 0) return "order: outside 1 .. 5";
    if (stride < n) return "stride: below order^2";
    if (opt.clusters == 0) return "clusters: 0";
    if (opt.components < 0 || static_cast<std::size_t>(opt.components) > n) return "components: outside [0, order^2]";
    if (opt.iterations < 0) return "iterations: < 0";
    if (vertex_count == 0) return "vertex_count: 0";
    return !transfers ? "transfers: null" : "vertex_count: too large";
}
// VQ (Sloan et al. 2003): farthest-point initialization from a seeded first center, then Lloyd
// iterations; an empty cluster restarts at the worst-represented vertex. K centers of n doubles.
inline void prt_cpca_vq(const float* transfers, std::size_t stride, std::size_t n, std::size_t vertex_count, std::size_t K,
                        const PrtCpcaOptions& opt, std::vector<double>& center, std::vector<std::uint32_t>& assign) {
    auto vec = [&](std::size_t v) { return transfers + v * stride; };
    center.assign(K * n, 0.0);
    std::vector<double> best(vertex_count, 0.0);
    assign.assign(vertex_count, 0u);
    {
        std::size_t first = prt_hash(opt.seed) % vertex_count;
        for (std::size_t i = 0; i < n; ++i) center[i] = static_cast<double>(vec(first)[i]);
        for (std::size_t v = 0; v < vertex_count; ++v) best[v] = prt_dist2(vec(v), center.data(), n);
        for (std::size_t k = 1; k < K; ++k) {
            std::size_t far = 0;
            for (std::size_t v = 1; v < vertex_count; ++v)
                if (best[v] > best[far]) far = v;
            for (std::size_t i = 0; i < n; ++i) center[k * n + i] = static_cast<double>(vec(far)[i]);
            for (std::size_t v = 0; v < vertex_count; ++v) {
                const double d = prt_dist2(vec(v), &center[k * n], n);
                if (d < best[v]) {
                    best[v] = d;
                    assign[v] = static_cast<std::uint32_t>(k);
                }
            }
        }
    }
    std::vector<std::size_t> members(K, 0);
    for (int it = 0; it <= opt.iterations; ++it) {
        if (it > 0) {
            bool changed = false;
            for (std::size_t v = 0; v < vertex_count; ++v) {
                std::uint32_t arg = assign[v];
                double bd = prt_dist2(vec(v), &center[arg * n], n);
                for (std::size_t k = 0; k < K; ++k) {
                    const double d = prt_dist2(vec(v), &center[k * n], n);
                    if (d < bd) {
                        bd = d;
                        arg = static_cast<std::uint32_t>(k);
                    }
                }
                changed = changed || arg != assign[v];
                assign[v] = arg;
                best[v] = bd;
            }
            if (!changed) break;
        }
        std::fill(center.begin(), center.end(), 0.0);
        std::fill(members.begin(), members.end(), std::size_t(0));
        for (std::size_t v = 0; v < vertex_count; ++v) {
            ++members[assign[v]];
            for (std::size_t i = 0; i < n; ++i) center[assign[v] * n + i] += static_cast<double>(vec(v)[i]);
        }
        for (std::size_t k = 0; k < K; ++k) {
            if (members[k] == 0) {  // empty cluster: restart it at the worst-represented vertex
                std::size_t far = 0;
                for (std::size_t v = 1; v < vertex_count; ++v)
                    if (best[v] > best[far]) far = v;
                best[far] = 0.0;
                for (std::size_t i = 0; i < n; ++i) center[k * n + i] = static_cast<double>(vec(far)[i]);
                continue;
            }
            for (std::size_t i = 0; i < n; ++i) center[k * n + i] /= static_cast<double>(members[k]);
        }
    }

}

// PCA per cluster: the mean and the C leading eigenvectors of the covariance about it (out.means, out.bases).
inline void prt_cpca_cluster_pca(const float* transfers, std::size_t stride, std::size_t n, std::size_t vertex_count, std::size_t K,
                                 std::size_t C, const std::vector<double>& center, const std::vector<std::uint32_t>& assign,
                                 PrtCpca& out) {
    auto vec = [&](std::size_t v) { return transfers + v * stride; };
    std::vector<double> cov(n * n), evec(n * n), eval(n);
    std::vector<std::size_t> order_idx(n);
    for (std::size_t k = 0; k < K; ++k) {
        for (std::size_t i = 0; i < n; ++i) out.means[k * n + i] = static_cast<float>(center[k * n + i]);
        if (C == 0) continue;
        std::fill(cov.begin(), cov.end(), 0.0);
        for (std::size_t v = 0; v < vertex_count; ++v) {
            if (assign[v] != k) continue;
            for (std::size_t i = 0; i < n; ++i) {
                const double di = static_cast<double>(vec(v)[i]) - center[k * n + i];
                for (std::size_t j = i; j < n; ++j) cov[i * n + j] += di * (static_cast<double>(vec(v)[j]) - center[k * n + j]);
            }
        }
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = 0; j < i; ++j) cov[i * n + j] = cov[j * n + i];
        prt_jacobi_eigen(static_cast<int>(n), cov.data(), eval.data(), evec.data());
        for (std::size_t i = 0; i < n; ++i) order_idx[i] = i;
        for (std::size_t i = 0; i < n; ++i)  // selection sort, descending eigenvalue
            for (std::size_t j = i + 1; j < n; ++j)
                if (eval[order_idx[j]] > eval[order_idx[i]]) {
                    const std::size_t t = order_idx[i];
                    order_idx[i] = order_idx[j];
                    order_idx[j] = t;
                }
        for (std::size_t c = 0; c < C; ++c)
            for (std::size_t i = 0; i < n; ++i)
                out.bases[(k * C + c) * n + i] = static_cast<float>(evec[i * n + order_idx[c]]);
    }
}

// Each vertex's weights on its cluster's basis; returns the summed squared reconstruction error.
inline double prt_cpca_weights(const float* transfers, std::size_t stride, std::size_t n, std::size_t vertex_count, std::size_t C,
                               PrtCpca& out) {
    auto vec = [&](std::size_t v) { return transfers + v * stride; };
    double se = 0.0;
    std::vector<double> rec(n);
    for (std::size_t v = 0; v < vertex_count; ++v) {
        const std::size_t k = out.cluster_of[v];
        for (std::size_t i = 0; i < n; ++i) rec[i] = static_cast<double>(out.means[k * n + i]);
        for (std::size_t c = 0; c < C; ++c) {
            const float* b = &out.bases[(k * C + c) * n];
            double w = 0.0;
            for (std::size_t i = 0; i < n; ++i)
                w += (static_cast<double>(vec(v)[i]) - static_cast<double>(out.means[k * n + i])) * static_cast<double>(b[i]);
            out.weights[v * C + c] = static_cast<float>(w);
            for (std::size_t i = 0; i < n; ++i) rec[i] += static_cast<double>(out.weights[v * C + c]) * static_cast<double>(b[i]);
        }
        for (std::size_t i = 0; i < n; ++i) se += (rec[i] - static_cast<double>(vec(v)[i])) * (rec[i] - static_cast<double>(vec(v)[i]));
    }
    return se;
}

}  // namespace detail

/// Compresses vertex_count transfer vectors (stride floats apart, the first order^2 used) by
/// clustered PCA: k-means on the vectors (VQ), then per cluster the mean and the `components`
/// leading principal directions of the covariance (Sloan et al. 2003, course notes "VQ + PCA").
/// `transfers` holds (vertex_count - 1) * stride + order^2 floats, each finite with magnitude
/// <= 1e30. Allocates. Errors (the returned compression's status, empty): InvalidArgument (invalid
/// order, stride < order^2, vertex_count 0, transfers null, clusters 0, components outside
/// 0 .. order^2, iterations < 0, a value with magnitude > 1e30), NonFinite (NaN/Inf in a transfer
/// vector).
inline PrtCpca prt_cpca_compress(int order, const float* transfers, std::size_t stride, std::size_t vertex_count,
                                 const PrtCpcaOptions& opt) {
    PrtCpca out;
    const std::size_t n = prt_coefficient_count(order);
    if (n == 0 || stride < n || opt.clusters == 0 || opt.components < 0 ||
        static_cast<std::size_t>(opt.components) > n || opt.iterations < 0 || vertex_count == 0 || !transfers ||
        vertex_count > std::numeric_limits<std::size_t>::max() / stride) {
        out.status = Status::InvalidArgument;
        out.detail = detail::prt_cpca_why(n, stride, opt, vertex_count, transfers);
        return out;
    }
    const Status vs = detail::prt_cpca_check_values(transfers, stride, n, vertex_count, out.detail);
    if (vs != Status::Ok) {
        out.status = vs;
        return out;
    }
    const std::size_t K = opt.clusters < vertex_count ? opt.clusters : vertex_count;
    const std::size_t C = static_cast<std::size_t>(opt.components);
    std::vector<double> center;
    std::vector<std::uint32_t> assign;
    detail::prt_cpca_vq(transfers, stride, n, vertex_count, K, opt, center, assign);
    out.order = order;
    out.components = opt.components;
    out.clusters = K;
    out.means.assign(K * n, 0.0f);
    out.bases.assign(K * C * n, 0.0f);
    out.cluster_of = assign;
    out.weights.assign(vertex_count * C, 0.0f);
    detail::prt_cpca_cluster_pca(transfers, stride, n, vertex_count, K, C, center, assign, out);
    const double se = detail::prt_cpca_weights(transfers, stride, n, vertex_count, C, out);
    out.rms_error = std::sqrt(se / static_cast<double>(vertex_count));
    out.status = Status::Ok;
    return out;
}

namespace detail {

// A compression that prt_cpca_compress returned with Ok (sizes consistent).
inline bool prt_cpca_ok(const PrtCpca& cp) {
    const std::size_t n = prt_coefficient_count(cp.order);
    if (cp.status != Status::Ok || n == 0 || cp.components < 0 || static_cast<std::size_t>(cp.components) > n)
        return false;
    const std::size_t C = static_cast<std::size_t>(cp.components);
    return cp.means.size() == cp.clusters * n && cp.bases.size() == cp.clusters * C * n &&
           cp.weights.size() == cp.cluster_of.size() * C;
}

}  // namespace detail

/// Decompressed transfer vector of one vertex. `out` holds capacity floats; it needs order^2.
/// Errors (nothing written): InvalidArgument (a compression whose status is not Ok or whose sizes
/// disagree, out null), IndexOutOfRange (vertex >= vertex_count(), or a cluster id >= clusters),
/// BufferTooSmall, Overflow (a coefficient does not fit a float).
inline PrtResult prt_cpca_reconstruct(const PrtCpca& cp, std::size_t vertex, float* out, std::size_t capacity) {
    if (!detail::prt_cpca_ok(cp)) return detail::prt_result(Status::InvalidArgument, 0, 0, "cp: status not Ok (or inconsistent)");
    const std::size_t n = prt_coefficient_count(cp.order);
    if (vertex >= cp.vertex_count() || cp.cluster_of[vertex] >= cp.clusters)
        return detail::prt_result(Status::IndexOutOfRange, 0, n, "vertex: >= vertex_count (or its cluster out of range)");
    if (!out) return detail::prt_result(Status::InvalidArgument, 0, n, "out: null");
    if (capacity < n) return detail::prt_result(Status::BufferTooSmall, 0, n, "capacity: below needed (see needed)");
    const std::size_t k = cp.cluster_of[vertex], C = static_cast<std::size_t>(cp.components);
    double acc[25];
    for (std::size_t i = 0; i < n; ++i) acc[i] = static_cast<double>(cp.means[k * n + i]);
    for (std::size_t c = 0; c < C; ++c)
        for (std::size_t i = 0; i < n; ++i)
            acc[i] += static_cast<double>(cp.weights[vertex * C + c]) * static_cast<double>(cp.bases[(k * C + c) * n + i]);
    for (std::size_t i = 0; i < n; ++i)
        if (!detail::prt_fits(acc[i]))
            return detail::prt_result(std::isnan(acc[i]) ? Status::NonFinite : Status::Overflow, 0, n,
                                      std::isnan(acc[i]) ? "cp: a NaN coefficient" : "out: a coefficient beyond float");
    for (std::size_t i = 0; i < n; ++i) out[i] = cp.means[k * n + i];
    for (std::size_t c = 0; c < C; ++c)
        for (std::size_t i = 0; i < n; ++i) out[i] += cp.weights[vertex * C + c] * cp.bases[(k * C + c) * n + i];
    for (std::size_t i = 0; i < n; ++i)
        if (!std::isfinite(out[i])) out[i] = static_cast<float>(acc[i]);  // float rounding past FLT_MAX
    return detail::prt_result(Status::Ok, n, n, nullptr);
}

/// Per-frame projections of the environment onto every cluster's mean and basis vectors:
/// out[k * (components + 1)] = mean_k . L, out[k * (components + 1) + 1 + c] = basis_kc . L
/// (RGB; course notes: R^k computed on the CPU). `env` holds env_count glm::vec3 (>= order^2);
/// `out` holds capacity glm::vec3 elements; it needs clusters * (components + 1). Errors (count 0):
/// InvalidArgument (a compression whose status is not Ok, a null pointer), BufferTooSmall (env or
/// out), NonFinite (NaN/Inf in env), Overflow (a projection does not fit a float).
inline PrtResult prt_cpca_project_environment(const PrtCpca& cp, const glm::vec3* env, std::size_t env_count,
                                              glm::vec3* out, std::size_t capacity) {
    if (!detail::prt_cpca_ok(cp)) return detail::prt_result(Status::InvalidArgument, 0, 0, "cp: status not Ok (or inconsistent)");
    const std::size_t n = prt_coefficient_count(cp.order);
    const std::size_t C = static_cast<std::size_t>(cp.components), need = cp.clusters * (C + 1);
    if (!env || !out) return detail::prt_result(Status::InvalidArgument, 0, need, !env ? "env: null" : "out: null");
    if (env_count < n || capacity < need)
        return detail::prt_result(Status::BufferTooSmall, 0, need, env_count < n ? "env_count: below order^2" : "capacity: below needed (see needed)");
    for (std::size_t i = 0; i < n; ++i)
        if (!detail::prt_finite3(env[i])) return detail::prt_result(Status::NonFinite, 0, need, "env: NaN or Inf");
    for (std::size_t k = 0; k < cp.clusters; ++k)
        for (std::size_t c = 0; c <= C; ++c) {
            const float* vec = c == 0 ? &cp.means[k * n] : &cp.bases[(k * C + c - 1) * n];
            const PrtRgbValue p = detail::prt_dot_rgb(n, vec, env);
            if (p.status != Status::Ok) return detail::prt_result(p.status, 0, need, p.detail);
            out[k * (C + 1) + c] = p.value;
        }
    return detail::prt_result(Status::Ok, need, need, nullptr);
}

/// Exit radiance of one vertex from the per-cluster projections: R_k0 + sum_c w_pc R_kc.
/// `projected` holds clusters * (components + 1) glm::vec3 (prt_cpca_project_environment).
/// Errors (value 0): InvalidArgument (a compression whose status is not Ok, projected null),
/// IndexOutOfRange (vertex >= vertex_count(), or a cluster id >= clusters), NonFinite (NaN/Inf in
/// the projections used), Overflow (the radiance does not fit a float).
inline PrtRgbValue prt_cpca_shade(const PrtCpca& cp, const glm::vec3* projected, std::size_t vertex) {
    PrtRgbValue r;
    // per-vertex hot path: only the checks that keep the reads in bounds
    if (cp.status != Status::Ok || !projected || cp.components < 0) {
        r.status = Status::InvalidArgument;
        r.detail = !projected ? "projected: null" : "cp: status not Ok";
        return r;
    }
    const std::size_t C = static_cast<std::size_t>(cp.components);
    if (vertex >= cp.cluster_of.size() || cp.cluster_of[vertex] >= cp.clusters || (vertex + 1) * C > cp.weights.size()) {
        r.status = Status::IndexOutOfRange;
        r.detail = "vertex: >= vertex_count (or its cluster out of range)";
        return r;
    }
    const std::size_t k = cp.cluster_of[vertex];
    glm::vec3 c = projected[k * (C + 1)];
    for (std::size_t j = 0; j < C; ++j) c += cp.weights[vertex * C + j] * projected[k * (C + 1) + 1 + j];
    if (detail::prt_finite3(c)) {
        r.status = Status::Ok;
        r.value = c;
        return r;
    }
    glm::dvec3 d(projected[k * (C + 1)]);
    for (std::size_t j = 0; j <= C; ++j)
        if (!detail::prt_finite3(projected[k * (C + 1) + j])) {
            r.status = Status::NonFinite;
            r.detail = "projected: NaN or Inf";
            return r;
        }
    for (std::size_t j = 0; j < C; ++j)
        d += static_cast<double>(cp.weights[vertex * C + j]) * glm::dvec3(projected[k * (C + 1) + 1 + j]);
    if (!detail::prt_fits(d.x) || !detail::prt_fits(d.y) || !detail::prt_fits(d.z)) {
        r.status = Status::Overflow;
        r.detail = "value: beyond float range";
        return r;
    }
    r.status = Status::Ok;
    r.value = glm::vec3(d);
    return r;
}

/// Exit radiance of every vertex from the per-cluster projections (prt_cpca_shade for vertices
/// 0 .. vertex_count() - 1, validated once). `projected` holds clusters * (components + 1)
/// glm::vec3 (prt_cpca_project_environment); `out` holds capacity glm::vec3 elements; it needs
/// vertex_count(). Errors (count 0): InvalidArgument (a compression whose status is not Ok or whose
/// sizes disagree, a null pointer), IndexOutOfRange (a cluster id >= clusters), BufferTooSmall
/// (nothing written), NonFinite (NaN/Inf in the projections used), Overflow (a radiance does not
/// fit a float).
inline PrtResult prt_cpca_shade_mesh(const PrtCpca& cp, const glm::vec3* projected, glm::vec3* out,
                                     std::size_t capacity) {
    if (!detail::prt_cpca_ok(cp) || !projected || !out)
        return detail::prt_result(Status::InvalidArgument, 0, 0,
                                  !detail::prt_cpca_ok(cp) ? "cp: status not Ok (or inconsistent)" : (!projected ? "projected: null" : "out: null"));
    const std::size_t V = cp.vertex_count(), C = static_cast<std::size_t>(cp.components);
    if (capacity < V) return detail::prt_result(Status::BufferTooSmall, 0, V, "capacity: below vertex_count() (see needed)");
    for (std::size_t v = 0; v < V; ++v)
        if (cp.cluster_of[v] >= cp.clusters) return detail::prt_result(Status::IndexOutOfRange, 0, V, "cp: a cluster index out of range");
    for (std::size_t v = 0; v < V; ++v) {
        const glm::vec3* p = projected + cp.cluster_of[v] * (C + 1);
        const float* w = cp.weights.data() + v * C;
        glm::vec3 c = p[0];
        for (std::size_t j = 0; j < C; ++j) c += w[j] * p[1 + j];
        out[v] = c;
    }
    if (!detail::prt_all_finite(out, V))
        for (std::size_t v = 0; v < V; ++v) {
            if (detail::prt_finite3(out[v])) continue;
            const PrtRgbValue c = prt_cpca_shade(cp, projected, v);
            if (c.status != Status::Ok) return detail::prt_result(c.status, 0, V, c.detail);
            out[v] = c.value;
        }
    return detail::prt_result(Status::Ok, V, V, nullptr);
}

}  // namespace shadowkit
