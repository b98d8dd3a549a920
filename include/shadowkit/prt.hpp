// shadowkit/prt.hpp - precomputed radiance transfer (PRT) for diffuse surfaces with shadows: per
// vertex, the spherical-harmonics (SH) projection of visibility x clamped cosine (the "transfer
// vector"), computed from a visibility callback you supply (any ray tracer: the header needs
// none), with stratified sphere samples; projection of an environment into SH; runtime shading as
// one dot product per colour channel (here on the CPU, glsl/prt.glsl on the GPU).
//
// Usage:
//   #include <shadowkit/prt.hpp>
//   namespace sk = shadowkit;
//   sk::PrtSamples samples;                          // once: 32 x 32 stratified directions + basis
//   sk::prt_make_samples(/*order*/ 4, /*strata*/ 32, /*seed*/ 1u, samples);
//   sk::PrtTransferOptions opt;  opt.ray_offset = 1e-4f * scene_size;
//   std::vector<float> T(vertex_count * sk::prt_coefficient_count(4));
//   auto r = sk::prt_compute_transfer(samples, opt, positions, normals, vertex_count,
//       [&](const glm::vec3& o, const glm::vec3& d) { return !my_ray_hits(o, d); },  // true = sky seen
//       T.data(), T.size());                         // or a function pointer + user pointer
//   glm::vec3 env[25];                               // environment radiance L(s) in SH, per frame
//   sk::prt_project_environment(samples, [](const glm::vec3& s) { return sky(s); }, env, 25);
//   glm::vec3 c = albedo_rgb * sk::prt_shade_rgb(4, &T[v * 16], env);    // exit radiance at vertex v
//   // GPU: upload T as an SSBO and env as a uniform vec3[25]; glsl/prt.glsl does the dot product.
//   // Optional compression (clustered PCA): 16 clusters x (mean + 4 vectors) instead of 16 floats
//   sk::PrtCpca cp;  sk::prt_cpca_compress(4, T.data(), 16, vertex_count, sk::PrtCpcaOptions{}, cp);
//   std::vector<glm::vec3> R(cp.clusters * (cp.components + 1));   // per frame, per cluster
//   sk::prt_cpca_project_environment(cp, env, 16, R.data(), R.size());
//   glm::vec3 c2 = albedo_rgb * sk::prt_cpca_shade(cp, R.data(), v);
//   // Rotating the environment: rotate env's SH vector (spherical_harmonics.hpp, sh_rotate).
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
// Conventions:
//   * order = number of SH bands, 1 .. kPrtMaxOrder (5); n = order^2 coefficients per vertex.
//     Basis, index l (l + 1) + m and signs are those of spherical_harmonics.hpp (real,
//     orthonormal, no Condon-Shortley phase): vectors from the two headers mix freely. Transfer
//     computed at order 5 truncated to its first k^2 entries is the order-k transfer.
//   * Transfer T_i = (albedo / pi) integral V(p, s) max(n.s, 0) y_i(s) ds, so for a radiance
//     environment L_i = integral L(s) y_i(s) ds the exit radiance is sum_i T_i L_i (a plain albedo
//     of 1 here and the colour multiplied at shading time is the usual split).
//   * Shadowed estimator: T = T_unshadowed - (albedo / pi) (4 pi / N) sum_j (1 - V_j) max(n.s_j, 0)
//     y(s_j). T_unshadowed is exact (A_l y_lm(n)); only the occluded part is sampled, which is
//     the same expectation as the course's sum over V_j but with no noise where nothing occludes.
//   * Visibility callback: visible(origin, direction) returns true when the ray origin + t dir,
//     t > 0, escapes to the environment. origin = position + ray_offset * normal; direction is a
//     unit vector in the half-space of the normal. Called from the calling thread only; for
//     parallel precomputation call prt_compute_transfer on disjoint vertex ranges from several
//     threads (the sample set is read-only).
//   * Vertices with a zero or non-finite normal (or a non-finite position in shadowed mode) get
//     a zero transfer vector and are counted in `degenerate_vertices`; the call still succeeds.
//
// MIT License. Copyright (c) shadowkit contributors.
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace shadowkit {

/// Outcome of a PRT call.
enum class PrtStatus {
    Ok,
    InvalidOrder,        ///< order outside 1 .. kPrtMaxOrder, or a sample set of another order
    InvalidSampleCount,  ///< strata outside 1 .. 1024, or an empty sample set
    NullPointer,         ///< a required array or callback is null
    BufferTooSmall,      ///< output shorter than needed; count = needed
    NonFiniteInput,      ///< NaN/Inf (or |x| > 1e30) albedo, offset, radiance or coefficients
    InvalidParameter     ///< compression: zero clusters, components outside 0 .. order^2
};

/// Shadowed (visibility callback) or unshadowed (closed form, no rays) diffuse transfer.
enum class PrtMode { Shadowed, Unshadowed };

constexpr int kPrtMaxOrder = 5;

/// order^2 for orders 1 .. kPrtMaxOrder, 0 otherwise.
constexpr std::size_t prt_coefficient_count(int order) {
    return (order >= 1 && order <= kPrtMaxOrder) ? static_cast<std::size_t>(order) * static_cast<std::size_t>(order)
                                                 : 0u;
}

/// Stratified sphere directions with their SH basis values (built by prt_make_samples).
struct PrtSamples {
    int order = 0;
    std::vector<glm::vec3> directions;  // unit, uniform over the sphere
    std::vector<float> basis;           // directions.size() * order^2, basis[j * n + i] = y_i(s_j)
    double weight = 0.0;                // 4 pi / N
    std::size_t count() const { return directions.size(); }
};

struct PrtTransferOptions {
    PrtMode mode = PrtMode::Shadowed;
    float albedo = 1.0f;       ///< rho in T = (rho / pi) ...; multiply colour at shading time
    float ray_offset = 0.0f;   ///< shadow-ray origin moved along the normal (world units, >= 0)
    /// Optional progress report: called after each vertex with (user, done, total).
    void (*progress)(void* user, std::size_t done, std::size_t total) = nullptr;
    void* progress_user = nullptr;
};

struct PrtTransferResult {
    PrtStatus status = PrtStatus::Ok;
    std::size_t count = 0;                ///< floats written (vertex_count * n), or needed
    std::size_t degenerate_vertices = 0;  ///< zero transfer written (bad normal / position)
    std::uint64_t rays = 0;               ///< visibility callbacks made
};

/// Status and a count (values written or needed).
struct PrtResult {
    PrtStatus status = PrtStatus::Ok;
    std::size_t count = 0;
};

/// Visibility callback: true when the ray escapes (the environment is seen along `direction`).
using PrtVisibilityFn = bool (*)(void* user, const glm::vec3& origin, const glm::vec3& direction);

namespace prt_detail {

constexpr double kPi = 3.14159265358979323846;

inline double factorial(int n) {
    double f = 1.0;
    for (int i = 2; i <= n; ++i) f *= static_cast<double>(i);
    return f;
}

// Real SH basis, same definition as spherical_harmonics.hpp (Legendre recurrence on the
// polynomial part, (x + i y)^m for the azimuthal part; exact at the poles). Unit (x, y, z).
inline void basis(int order, double x, double y, double z, double* out) {
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
            const double k = std::sqrt((2.0 * l + 1.0) / (4.0 * kPi) * factorial(l - m) / factorial(l + m));
            if (m == 0) {
                out[l * (l + 1)] = k * q;
            } else {
                out[l * (l + 1) + m] = sqrt2 * k * q * cm;
                out[l * (l + 1) - m] = sqrt2 * k * q * sm;
            }
        }
    }
}

// Clamped-cosine band coefficient A_l (Ramamoorthi & Hanrahan 2001, eqs. 8-9).
inline double clamped_cosine(int l) {
    if (l == 0) return kPi;
    if (l == 1) return 2.0 * kPi / 3.0;
    if (l % 2 == 1) return 0.0;
    const double sign = ((l / 2 - 1) % 2 == 0) ? 1.0 : -1.0;
    const double half = factorial(l / 2);
    return 2.0 * kPi * sign / (static_cast<double>(l + 2) * static_cast<double>(l - 1)) * factorial(l) /
           (std::pow(2.0, l) * half * half);
}

inline bool unit(const glm::vec3& v, glm::dvec3& out) {
    glm::dvec3 d(v);
    if (!std::isfinite(d.x) || !std::isfinite(d.y) || !std::isfinite(d.z)) return false;
    const double big = std::fmax(std::fabs(d.x), std::fmax(std::fabs(d.y), std::fabs(d.z)));
    if (!(big > 0.0)) return false;
    d /= big;
    out = d / std::sqrt(glm::dot(d, d));
    return true;
}

inline bool finite3(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

inline std::uint32_t hash(std::uint32_t v) {  // lowbias32 (C. Wellons)
    v ^= v >> 16;
    v *= 0x7feb352du;
    v ^= v >> 15;
    v *= 0x846ca68bu;
    v ^= v >> 16;
    return v;
}

}  // namespace prt_detail

/// SH basis values y_i(dir), i < order^2 (same as sh_evaluate in spherical_harmonics.hpp). A zero
/// or non-finite direction writes zeros and returns NonFiniteInput.
inline PrtResult prt_sh_basis(int order, const glm::vec3& dir, float* out, std::size_t capacity) {
    const std::size_t n = prt_coefficient_count(order);
    if (n == 0) return {PrtStatus::InvalidOrder, 0};
    if (!out) return {PrtStatus::NullPointer, n};
    if (capacity < n) return {PrtStatus::BufferTooSmall, n};
    glm::dvec3 d;
    if (!prt_detail::unit(dir, d)) {
        for (std::size_t i = 0; i < n; ++i) out[i] = 0.0f;
        return {PrtStatus::NonFiniteInput, 0};
    }
    double b[25];
    prt_detail::basis(order, d.x, d.y, d.z, b);
    for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<float>(b[i]);
    return {PrtStatus::Ok, n};
}

/// strata^2 stratified jittered uniform sphere directions (course notes: theta = 2 acos(sqrt(1 - x)),
/// phi = 2 pi y on the unit square, i.e. z = 1 - 2x, one jittered sample per cell) and their basis
/// values. Deterministic for a seed on every platform. strata 1 .. 1024.
inline PrtStatus prt_make_samples(int order, int strata, std::uint32_t seed, PrtSamples& out) {
    out = PrtSamples{};
    const std::size_t n = prt_coefficient_count(order);
    if (n == 0) return PrtStatus::InvalidOrder;
    if (strata < 1 || strata > 1024) return PrtStatus::InvalidSampleCount;
    const std::size_t count = static_cast<std::size_t>(strata) * static_cast<std::size_t>(strata);
    out.order = order;
    out.directions.resize(count);
    out.basis.resize(count * n);
    out.weight = 4.0 * prt_detail::kPi / static_cast<double>(count);
    const double inv = 1.0 / static_cast<double>(strata);
    double b[25];
    std::size_t k = 0;
    for (int i = 0; i < strata; ++i)
        for (int j = 0; j < strata; ++j, ++k) {
            const std::uint32_t h1 = prt_detail::hash(static_cast<std::uint32_t>(k) * 2u + prt_detail::hash(seed));
            const std::uint32_t h2 = prt_detail::hash(h1 ^ 0x9e3779b9u);
            const double u = (static_cast<double>(i) + static_cast<double>(h1 >> 8) * (1.0 / 16777216.0)) * inv;
            const double v = (static_cast<double>(j) + static_cast<double>(h2 >> 8) * (1.0 / 16777216.0)) * inv;
            const double z = 1.0 - 2.0 * u, r = std::sqrt(std::fmax(0.0, 1.0 - z * z)), phi = 2.0 * prt_detail::kPi * v;
            out.directions[k] = glm::vec3(glm::dvec3(r * std::cos(phi), r * std::sin(phi), z));
            glm::dvec3 d;  // basis of the stored (float) direction, renormalised
            if (!prt_detail::unit(out.directions[k], d)) d = glm::dvec3(0.0, 0.0, 1.0);
            prt_detail::basis(order, d.x, d.y, d.z, b);
            for (std::size_t c = 0; c < n; ++c) out.basis[k * n + c] = static_cast<float>(b[c]);
        }
    return PrtStatus::Ok;
}

/// Shadowed (or unshadowed) diffuse transfer vectors of vertex_count vertices into
/// out[v * n + i] (Sloan et al. 2002 eq. 6; course notes' Monte Carlo estimator, see the header
/// comment for the control variate). `visible` is any callable bool(const glm::vec3& origin,
/// const glm::vec3& dir); it is not called in Unshadowed mode (positions may then be null).
template <class Visible>
inline PrtTransferResult prt_compute_transfer(const PrtSamples& samples, const PrtTransferOptions& opt,
                                              const glm::vec3* positions, const glm::vec3* normals,
                                              std::size_t vertex_count, Visible&& visible, float* out,
                                              std::size_t capacity) {
    PrtTransferResult res;
    const std::size_t n = prt_coefficient_count(samples.order);
    if (n == 0) return {PrtStatus::InvalidOrder, 0, 0, 0};
    const bool shadowed = opt.mode == PrtMode::Shadowed;
    if (shadowed && (samples.count() == 0 || samples.basis.size() != samples.count() * n))
        return {PrtStatus::InvalidSampleCount, 0, 0, 0};
    if (!std::isfinite(opt.albedo) || !std::isfinite(opt.ray_offset) || std::fabs(opt.albedo) > 1e30f)
        return {PrtStatus::NonFiniteInput, 0, 0, 0};
    if (vertex_count > static_cast<std::size_t>(-1) / n) return {PrtStatus::BufferTooSmall, static_cast<std::size_t>(-1), 0, 0};
    res.count = vertex_count * n;
    if (vertex_count == 0) return res;
    if (!normals || !out || (shadowed && !positions)) return {PrtStatus::NullPointer, res.count, 0, 0};
    if (capacity < res.count) return {PrtStatus::BufferTooSmall, res.count, 0, 0};
    const double scale = static_cast<double>(opt.albedo) / prt_detail::kPi;
    double t[25], b[25];
    for (std::size_t v = 0; v < vertex_count; ++v) {
        float* dst = out + v * n;
        glm::dvec3 nrm;
        if (!prt_detail::unit(normals[v], nrm) || (shadowed && !prt_detail::finite3(positions[v]))) {
            for (std::size_t i = 0; i < n; ++i) dst[i] = 0.0f;
            ++res.degenerate_vertices;
            if (opt.progress) opt.progress(opt.progress_user, v + 1, vertex_count);
            continue;
        }
        // unshadowed part, exact: (rho / pi) A_l y_lm(n) (Sloan et al. 2002 eq. 5 in SH)
        prt_detail::basis(samples.order, nrm.x, nrm.y, nrm.z, b);
        for (int l = 0; l < samples.order; ++l) {
            const double a = scale * prt_detail::clamped_cosine(l);
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
    return res;
}

/// Function-pointer form: visible(user, origin, direction).
inline PrtTransferResult prt_compute_transfer(const PrtSamples& samples, const PrtTransferOptions& opt,
                                              const glm::vec3* positions, const glm::vec3* normals,
                                              std::size_t vertex_count, PrtVisibilityFn visible, void* user,
                                              float* out, std::size_t capacity) {
    if (!visible && opt.mode == PrtMode::Shadowed)
        return {PrtStatus::NullPointer, prt_coefficient_count(samples.order) * vertex_count, 0, 0};
    return prt_compute_transfer(
        samples, opt, positions, normals, vertex_count,
        [visible, user](const glm::vec3& o, const glm::vec3& d) { return visible(user, o, d); }, out, capacity);
}

/// Projects an environment's radiance into SH with the sample set: out[i] = (4 pi / N) sum_j
/// L(s_j) y_i(s_j). `radiance` is any callable glm::vec3(const glm::vec3& dir). A non-finite
/// radiance gives NonFiniteInput and zeros.
template <class Radiance>
inline PrtResult prt_project_environment(const PrtSamples& samples, Radiance&& radiance, glm::vec3* out,
                                         std::size_t capacity) {
    const std::size_t n = prt_coefficient_count(samples.order);
    if (n == 0) return {PrtStatus::InvalidOrder, 0};
    if (samples.count() == 0 || samples.basis.size() != samples.count() * n) return {PrtStatus::InvalidSampleCount, 0};
    if (!out) return {PrtStatus::NullPointer, n};
    if (capacity < n) return {PrtStatus::BufferTooSmall, n};
    glm::dvec3 acc[25] = {};
    for (std::size_t j = 0; j < samples.count(); ++j) {
        const glm::vec3 L = radiance(samples.directions[j]);
        if (!prt_detail::finite3(L)) {
            for (std::size_t i = 0; i < n; ++i) out[i] = glm::vec3(0.0f);
            return {PrtStatus::NonFiniteInput, 0};
        }
        for (std::size_t i = 0; i < n; ++i) acc[i] += static_cast<double>(samples.basis[j * n + i]) * glm::dvec3(L);
    }
    for (std::size_t i = 0; i < n; ++i) {
        out[i] = glm::vec3(acc[i] * samples.weight);
        if (!prt_detail::finite3(out[i])) {  // finite radiance too large for float
            for (std::size_t k = 0; k < n; ++k) out[k] = glm::vec3(0.0f);
            return {PrtStatus::NonFiniteInput, 0};
        }
    }
    return {PrtStatus::Ok, n};
}

/// Exit radiance at one vertex: sum_i T_i L_i per channel (course notes: shading = dot product).
/// Hot path, no validation beyond the order (invalid order gives 0).
inline glm::vec3 prt_shade_rgb(int order, const float* transfer, const glm::vec3* env) {
    const std::size_t n = prt_coefficient_count(order);
    glm::vec3 c(0.0f);
    if (n == 0 || !transfer || !env) return c;
    for (std::size_t i = 0; i < n; ++i) c += transfer[i] * env[i];
    return c;
}

/// Scalar form of prt_shade_rgb.
inline float prt_shade(int order, const float* transfer, const float* env) {
    const std::size_t n = prt_coefficient_count(order);
    float c = 0.0f;
    if (n == 0 || !transfer || !env) return c;
    for (std::size_t i = 0; i < n; ++i) c += transfer[i] * env[i];
    return c;
}

/// Shades vertex_count vertices whose transfer vectors are stored with `stride` floats each
/// (>= order^2; a transfer computed at a higher order may be shaded at a lower one). NaN in a
/// transfer vector gives NaN for that vertex only.
inline PrtResult prt_shade_mesh(int order, const float* transfers, std::size_t stride, std::size_t vertex_count,
                                const glm::vec3* env, glm::vec3* out, std::size_t capacity) {
    const std::size_t n = prt_coefficient_count(order);
    if (n == 0) return {PrtStatus::InvalidOrder, 0};
    if (stride < n) return {PrtStatus::BufferTooSmall, n};
    if (vertex_count == 0) return {PrtStatus::Ok, 0};
    if (!transfers || !env || !out) return {PrtStatus::NullPointer, vertex_count};
    if (capacity < vertex_count) return {PrtStatus::BufferTooSmall, vertex_count};
    for (std::size_t i = 0; i < n; ++i)
        if (!prt_detail::finite3(env[i])) return {PrtStatus::NonFiniteInput, 0};
    for (std::size_t v = 0; v < vertex_count; ++v) out[v] = prt_shade_rgb(order, transfers + v * stride, env);
    return {PrtStatus::Ok, vertex_count};
}

// ---------------------------------------------------------------- clustered PCA compression

/// Clustered PCA of transfer vectors (Sloan et al. 2003): every vertex p belongs to one cluster c
/// and T_p ~ mean_c + sum_k w_pk basis_ck, k < components (orthonormal basis per cluster).
struct PrtCpca {
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

struct PrtCpcaOptions {
    std::size_t clusters = 16;   ///< clamped to the vertex count
    int components = 4;          ///< 0 .. order^2 (0 = plain vector quantisation)
    int iterations = 12;         ///< k-means (Lloyd) iterations after a farthest-point start
    std::uint32_t seed = 1;      ///< picks the first centre; the rest is deterministic
};

namespace prt_detail {

// Eigen-decomposition of a symmetric n x n matrix a (row-major, destroyed) by cyclic Jacobi
// rotations; eigenvalues in w, eigenvectors in the columns of v.
inline void jacobi_eigen(int n, double* a, double* w, double* v) {
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

inline double dist2(const float* a, const double* b, std::size_t n) {
    double d = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        const double e = static_cast<double>(a[i]) - b[i];
        d += e * e;
    }
    return d;
}

}  // namespace prt_detail

/// Compresses vertex_count transfer vectors (stride floats apart, the first order^2 used) by
/// clustered PCA: k-means on the vectors (VQ), then per cluster the mean and the `components`
/// leading principal directions of the covariance (Sloan et al. 2003, course notes "VQ + PCA").
/// Values must be finite and below 1e30 in magnitude (NonFiniteInput otherwise).
inline PrtStatus prt_cpca_compress(int order, const float* transfers, std::size_t stride, std::size_t vertex_count,
                                   const PrtCpcaOptions& opt, PrtCpca& out) {
    out = PrtCpca{};
    const std::size_t n = prt_coefficient_count(order);
    if (n == 0) return PrtStatus::InvalidOrder;
    if (stride < n) return PrtStatus::BufferTooSmall;
    if (opt.clusters == 0 || opt.components < 0 || static_cast<std::size_t>(opt.components) > n)
        return PrtStatus::InvalidParameter;
    if (vertex_count == 0) return PrtStatus::InvalidSampleCount;
    if (!transfers) return PrtStatus::NullPointer;
    if (vertex_count > static_cast<std::size_t>(-1) / stride) return PrtStatus::BufferTooSmall;
    for (std::size_t v = 0; v < vertex_count; ++v)
        for (std::size_t i = 0; i < n; ++i)
            if (!(std::fabs(transfers[v * stride + i]) <= 1e30f)) return PrtStatus::NonFiniteInput;
    const std::size_t K = opt.clusters < vertex_count ? opt.clusters : vertex_count;
    const std::size_t C = static_cast<std::size_t>(opt.components);
    auto vec = [&](std::size_t v) { return transfers + v * stride; };

    // VQ: farthest-point initialisation from a seeded first centre, then Lloyd iterations.
    std::vector<double> centre(K * n, 0.0);
    std::vector<double> best(vertex_count, 0.0);
    std::vector<std::uint32_t> assign(vertex_count, 0u);
    {
        std::size_t first = prt_detail::hash(opt.seed) % vertex_count;
        for (std::size_t i = 0; i < n; ++i) centre[i] = static_cast<double>(vec(first)[i]);
        for (std::size_t v = 0; v < vertex_count; ++v) best[v] = prt_detail::dist2(vec(v), centre.data(), n);
        for (std::size_t k = 1; k < K; ++k) {
            std::size_t far = 0;
            for (std::size_t v = 1; v < vertex_count; ++v)
                if (best[v] > best[far]) far = v;
            for (std::size_t i = 0; i < n; ++i) centre[k * n + i] = static_cast<double>(vec(far)[i]);
            for (std::size_t v = 0; v < vertex_count; ++v) {
                const double d = prt_detail::dist2(vec(v), &centre[k * n], n);
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
                double bd = prt_detail::dist2(vec(v), &centre[arg * n], n);
                for (std::size_t k = 0; k < K; ++k) {
                    const double d = prt_detail::dist2(vec(v), &centre[k * n], n);
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
        std::fill(centre.begin(), centre.end(), 0.0);
        std::fill(members.begin(), members.end(), std::size_t(0));
        for (std::size_t v = 0; v < vertex_count; ++v) {
            ++members[assign[v]];
            for (std::size_t i = 0; i < n; ++i) centre[assign[v] * n + i] += static_cast<double>(vec(v)[i]);
        }
        for (std::size_t k = 0; k < K; ++k) {
            if (members[k] == 0) {  // empty cluster: restart it at the worst-represented vertex
                std::size_t far = 0;
                for (std::size_t v = 1; v < vertex_count; ++v)
                    if (best[v] > best[far]) far = v;
                best[far] = 0.0;
                for (std::size_t i = 0; i < n; ++i) centre[k * n + i] = static_cast<double>(vec(far)[i]);
                continue;
            }
            for (std::size_t i = 0; i < n; ++i) centre[k * n + i] /= static_cast<double>(members[k]);
        }
    }

    // PCA per cluster: leading eigenvectors of the covariance about the mean.
    out.order = order;
    out.components = opt.components;
    out.clusters = K;
    out.means.assign(K * n, 0.0f);
    out.bases.assign(K * C * n, 0.0f);
    out.cluster_of = assign;
    out.weights.assign(vertex_count * C, 0.0f);
    std::vector<double> cov(n * n), evec(n * n), eval(n);
    std::vector<std::size_t> order_idx(n);
    for (std::size_t k = 0; k < K; ++k) {
        for (std::size_t i = 0; i < n; ++i) out.means[k * n + i] = static_cast<float>(centre[k * n + i]);
        if (C == 0) continue;
        std::fill(cov.begin(), cov.end(), 0.0);
        for (std::size_t v = 0; v < vertex_count; ++v) {
            if (assign[v] != k) continue;
            for (std::size_t i = 0; i < n; ++i) {
                const double di = static_cast<double>(vec(v)[i]) - centre[k * n + i];
                for (std::size_t j = i; j < n; ++j) cov[i * n + j] += di * (static_cast<double>(vec(v)[j]) - centre[k * n + j]);
            }
        }
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = 0; j < i; ++j) cov[i * n + j] = cov[j * n + i];
        prt_detail::jacobi_eigen(static_cast<int>(n), cov.data(), eval.data(), evec.data());
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
    // weights and the reconstruction error
    double se = 0.0;
    std::vector<double> rec(n);
    for (std::size_t v = 0; v < vertex_count; ++v) {
        const std::size_t k = assign[v];
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
    out.rms_error = std::sqrt(se / static_cast<double>(vertex_count));
    return PrtStatus::Ok;
}

/// Decompressed transfer vector of one vertex (order^2 floats).
inline PrtResult prt_cpca_reconstruct(const PrtCpca& cp, std::size_t vertex, float* out, std::size_t capacity) {
    const std::size_t n = prt_coefficient_count(cp.order);
    if (n == 0) return {PrtStatus::InvalidOrder, 0};
    if (vertex >= cp.vertex_count()) return {PrtStatus::InvalidParameter, 0};
    if (!out) return {PrtStatus::NullPointer, n};
    if (capacity < n) return {PrtStatus::BufferTooSmall, n};
    const std::size_t k = cp.cluster_of[vertex], C = static_cast<std::size_t>(cp.components);
    for (std::size_t i = 0; i < n; ++i) out[i] = cp.means[k * n + i];
    for (std::size_t c = 0; c < C; ++c)
        for (std::size_t i = 0; i < n; ++i) out[i] += cp.weights[vertex * C + c] * cp.bases[(k * C + c) * n + i];
    return {PrtStatus::Ok, n};
}

/// Per-frame projections of the environment onto every cluster's mean and basis vectors:
/// out[k * (components + 1)] = mean_k . L, out[k * (components + 1) + 1 + c] = basis_kc . L
/// (RGB; course notes: R^k computed on the CPU). env has at least order^2 entries (env_count).
inline PrtResult prt_cpca_project_environment(const PrtCpca& cp, const glm::vec3* env, std::size_t env_count,
                                              glm::vec3* out, std::size_t capacity) {
    const std::size_t n = prt_coefficient_count(cp.order);
    if (n == 0) return {PrtStatus::InvalidOrder, 0};
    const std::size_t C = static_cast<std::size_t>(cp.components), need = cp.clusters * (C + 1);
    if (!env || !out) return {PrtStatus::NullPointer, need};
    if (env_count < n || capacity < need) return {PrtStatus::BufferTooSmall, need};
    for (std::size_t i = 0; i < n; ++i)
        if (!prt_detail::finite3(env[i])) return {PrtStatus::NonFiniteInput, 0};
    for (std::size_t k = 0; k < cp.clusters; ++k) {
        out[k * (C + 1)] = prt_shade_rgb(cp.order, &cp.means[k * n], env);
        for (std::size_t c = 0; c < C; ++c) out[k * (C + 1) + 1 + c] = prt_shade_rgb(cp.order, &cp.bases[(k * C + c) * n], env);
    }
    return {PrtStatus::Ok, need};
}

/// Exit radiance of one vertex from the per-cluster projections: R_k0 + sum_c w_pc R_kc.
/// Out-of-range vertex gives 0.
inline glm::vec3 prt_cpca_shade(const PrtCpca& cp, const glm::vec3* projected, std::size_t vertex) {
    if (!projected || vertex >= cp.vertex_count()) return glm::vec3(0.0f);
    const std::size_t k = cp.cluster_of[vertex], C = static_cast<std::size_t>(cp.components);
    glm::vec3 c = projected[k * (C + 1)];
    for (std::size_t j = 0; j < C; ++j) c += cp.weights[vertex * C + j] * projected[k * (C + 1) + 1 + j];
    return c;
}

}  // namespace shadowkit
