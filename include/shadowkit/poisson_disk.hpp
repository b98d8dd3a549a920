// shadowkit/poisson_disk.hpp - Poisson-disk sample sets for shadow filtering kernels (Bridson, weighted sample elimination) and their GLSL arrays
//
// Usage:
//   #include <shadowkit/poisson_disk.hpp>
//   namespace sk = shadowkit;
//   glm::vec2 taps[32];
//   sk::PoissonResult r = sk::poisson_eliminate(sk::PoissonDomain{}, 32, /*seed*/ 1, taps, 32);  // exactly 32 in the unit disk
//   // r.status == sk::Status::Ok, r.count == 32, r.radius == min pairwise distance
//   std::vector<glm::vec2> pts(sk::poisson_bridson_capacity(sk::PoissonDomain{}, 0.3f));
//   sk::PoissonResult b = sk::poisson_bridson(sk::PoissonDomain{}, 0.3f, 7, pts.data(), pts.size());  // radius-driven
//   char text[4096];  // const vec2 MY_TAPS[32] = ...; plus the #defines that make glsl/pcf.glsl and pcss.glsl use it
//   sk::PoissonGlslResult g = sk::poisson_to_glsl(taps, 32, "MY_TAPS", sk::PoissonGlsl::ArrayForSnippets, text, sizeof text);
//   sk::PoissonValue rho = sk::poisson_normalized_radius(sk::PoissonDomain{}, taps, 32);  // d_min / d_max
//
// Conventions. Domains (PoissonShape): Disk = unit disk |p| <= 1; Square = [-1,1]^2 (side 2, the
// disk's bounding square, so kernels stay centered); Annulus = inner_radius <= |p| <= 1.
// Every generator is deterministic from its 64-bit seed: it uses its own splitmix64 stream and its
// own float conversion, never <random>'s distributions, so sets are identical across standard
// libraries. Buffers: output goes to a caller buffer, a pointer followed by its capacity in elements
// of the pointer's type (glm::vec2 points; chars for poisson_to_glsl). The result's `count` is what
// was written (a valid prefix) and `needed` what the whole output needs; too small a buffer gives
// Status::BufferTooSmall (the call is repeatable: same seed, same set). The generators allocate
// their work memory (grids, candidate lists) with std::vector: call them once, at setup, not per
// frame. Results: a struct whose first member is `status`; Ok only with finite outputs; a non-Ok
// result's `detail` names the offending input and the rule ("radius: not > 0"), a static string,
// nullptr when Ok.
// GLSL: glsl/pcf.glsl and glsl/pcss.glsl have a built-in 64-tap disk (sk_poisson_disk64); a
// generated array with any other name compiles next to it, and the snippets use it when
// SK_POISSON_TAPS / SK_POISSON_TAP_COUNT name it before the snippet (PoissonGlsl::ArrayForSnippets).
//
// Based on:
//   R. Bridson, "Fast Poisson Disk Sampling in Arbitrary Dimensions", SIGGRAPH 2007 sketch.
//   C. Yuksel, "Sample Elimination for Generating Poisson Disk Sample Sets", Eurographics 2015.
//   A. Lagae, P. Dutre, "A Comparison of Methods for Generating Poisson Disk Distributions",
//     CGF 27(1), 2008 (normalized radius rho = d_min / d_max, d_max = sqrt(2A / (sqrt(3) N))).
//
// MIT License. Copyright (c) shadowkit contributors.
#pragma once

#include <glm/vec2.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
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

/// Shape of the sampling domain.
enum class PoissonShape { Disk, Square, Annulus };

/// Sampling domain. The default is the unit disk.
struct PoissonDomain {
    PoissonShape shape = PoissonShape::Disk;
    float inner_radius = 0.0f;  ///< Annulus only, in [0, 0.99]
};

/// Result of a generator (points written to the caller's buffer).
struct PoissonResult {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    std::size_t count = 0;   ///< points written to the caller buffer (a valid prefix)
    std::size_t needed = 0;  ///< points the full set has (== count when Ok)
    float radius = 0.0f;     ///< Bridson: the radius asked for (all pairs are >= it); elimination: the
                             ///< minimum pairwise distance of the written set (0 for fewer than 2 points)
};

/// A scalar result (an area, a distance, a ratio). `value` is 0 unless status is Ok.
struct PoissonValue {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    float value = 0.0f;
};

/// What poisson_to_glsl emits.
enum class PoissonGlsl {
    Array,            ///< `const vec2 NAME[N] = vec2[N](...);` only
    ArrayForSnippets  ///< the array, then `#define SK_POISSON_TAPS NAME` and `#define SK_POISSON_TAP_COUNT N`:
                      ///< pasted before glsl/pcf.glsl / pcss.glsl, their Poisson kernels use it
};

/// Result of poisson_to_glsl: chars of GLSL text.
struct PoissonGlslResult {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    std::size_t count = 0;   ///< chars written to `out`, the terminating NUL included (a valid, NUL-terminated prefix)
    std::size_t needed = 0;  ///< chars the whole text needs, the terminating NUL included (== count when Ok)
};

/// Upper limit on the size of any generated set (bounds memory and time).
constexpr std::size_t kPoissonMaxPoints = std::size_t(1) << 16;

namespace detail {

// splitmix64 (Steele, Lea, Flood 2014): a tiny, well-mixed, portable stream.
struct pd_rng {
    std::uint64_t state;
    std::uint64_t next() {
        std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    double uniform() { return double(next() >> 11) * (1.0 / 9007199254740992.0); }  // [0,1)
};

constexpr double kPdPi = 3.14159265358979323846;

inline bool pd_valid_domain(PoissonDomain d) {
    if (d.shape == PoissonShape::Disk || d.shape == PoissonShape::Square) return true;
    if (d.shape == PoissonShape::Annulus)
        return std::isfinite(d.inner_radius) && d.inner_radius >= 0.0f && d.inner_radius <= 0.99f;
    return false;
}

inline bool pd_contains(PoissonDomain d, double x, double y) {
    if (!std::isfinite(x) || !std::isfinite(y)) return false;
    if (d.shape == PoissonShape::Square) return x >= -1.0 && x <= 1.0 && y >= -1.0 && y <= 1.0;
    const double r2 = x * x + y * y;
    if (r2 > 1.0) return false;
    if (d.shape == PoissonShape::Annulus) {
        const double ri = double(d.inner_radius);
        return r2 >= ri * ri;
    }
    return true;
}

inline double pd_area(PoissonDomain d) {
    if (d.shape == PoissonShape::Square) return 4.0;
    if (d.shape == PoissonShape::Annulus) {
        const double ri = double(d.inner_radius);
        return kPdPi * (1.0 - ri * ri);
    }
    return kPdPi;
}

// A uniformly distributed point of the domain, already rounded to float and inside it.
inline glm::vec2 pd_uniform_point(PoissonDomain d, pd_rng& rng) {
    for (;;) {
        double x, y;
        if (d.shape == PoissonShape::Square) {
            x = 2.0 * rng.uniform() - 1.0;
            y = 2.0 * rng.uniform() - 1.0;
        } else {
            const double ri = d.shape == PoissonShape::Annulus ? double(d.inner_radius) : 0.0;
            const double rr = std::sqrt(ri * ri + rng.uniform() * (1.0 - ri * ri));  // uniform in area
            const double a = 2.0 * kPdPi * rng.uniform();
            x = rr * std::cos(a);
            y = rr * std::sin(a);
        }
        const glm::vec2 p(static_cast<float>(x), static_cast<float>(y));
        if (pd_contains(d, double(p.x), double(p.y))) return p;
    }
}

inline double pd_dist2(glm::vec2 a, glm::vec2 b) {
    const double dx = double(a.x) - double(b.x), dy = double(a.y) - double(b.y);
    return dx * dx + dy * dy;
}

// Uniform background grid over [-1,1]^2.
struct pd_grid {
    double cell = 1.0;
    int dim = 1;
    int cell_of(double v) const {
        const double c = std::floor((v + 1.0) / cell);  // clamp before the cast: no UB for any v
        return !(c > 0.0) ? 0 : (c >= double(dim) ? dim - 1 : static_cast<int>(c));
    }
    void init(double cell_size) {
        cell = cell_size;
        const double cells = std::ceil(2.0 / cell_size);
        dim = cells < 1.0 ? 1 : static_cast<int>(cells);
    }
};

// Indexed binary max-heap on double keys; ties broken by the smaller index (deterministic).
struct pd_max_heap {
    std::vector<double> key;
    std::vector<std::uint32_t> heap, pos;
    bool less(std::uint32_t a, std::uint32_t b) const {  // a below b
        return key[a] < key[b] || (key[a] == key[b] && a > b);
    }
    void swap_at(std::size_t i, std::size_t j) {
        const std::uint32_t t = heap[i];
        heap[i] = heap[j];
        heap[j] = t;
        pos[heap[i]] = static_cast<std::uint32_t>(i);
        pos[heap[j]] = static_cast<std::uint32_t>(j);
    }
    void down(std::size_t i) {
        const std::size_t n = heap.size();
        for (;;) {
            std::size_t l = 2 * i + 1, r = l + 1, m = i;
            if (l < n && less(heap[m], heap[l])) m = l;
            if (r < n && less(heap[m], heap[r])) m = r;
            if (m == i) return;
            swap_at(i, m);
            i = m;
        }
    }
    void build() {
        heap.resize(key.size());
        pos.resize(key.size());
        for (std::size_t i = 0; i < key.size(); ++i) {
            heap[i] = static_cast<std::uint32_t>(i);
            pos[i] = static_cast<std::uint32_t>(i);
        }
        for (std::size_t i = heap.size() / 2; i-- > 0;) down(i);
    }
    std::uint32_t pop() {
        const std::uint32_t top = heap[0];
        swap_at(0, heap.size() - 1);
        heap.pop_back();
        pos[top] = std::numeric_limits<std::uint32_t>::max();
        if (!heap.empty()) down(0);
        return top;
    }
    void decrease(std::uint32_t item, double new_key) {
        key[item] = new_key;
        if (pos[item] != std::numeric_limits<std::uint32_t>::max()) down(pos[item]);
    }
};

// Yuksel 2015, eq. (1)-(2): weight w_ij = (1 - d_hat / (2 r_max))^alpha, d_hat = max(d, 2 r_min)
// (weight limiting, Sec. 3.3: r_min = r_max (1 - (N/M)^gamma) beta, gamma = 1.5, beta = 0.65).
// Eliminates pts (in place semantics) down to `target`; returns the alive flags and the
// elimination order (first eliminated first).
inline void pd_eliminate(const std::vector<glm::vec2>& pts, std::size_t target, double area_,
                      bool weight_limiting, std::vector<std::uint8_t>& alive,
                      std::vector<std::uint32_t>& order) {
    const std::size_t m = pts.size();
    alive.assign(m, 1);
    order.clear();
    if (target >= m) return;
    const double r_max = std::sqrt(area_ / (2.0 * std::sqrt(3.0) * double(target)));  // Yuksel eq. (5)
    const double d_lim = 2.0 * r_max;
    double r_min = 0.0;
    if (weight_limiting)
        r_min = r_max * (1.0 - std::pow(double(target) / double(m), 1.5)) * 0.65;
    auto weight = [&](double d) {  // alpha = 8
        const double dh = d < 2.0 * r_min ? 2.0 * r_min : d;
        const double t = 1.0 - dh / d_lim, t2 = t * t, t4 = t2 * t2;
        return t4 * t4;
    };
    // Neighbour lists (CSR) through a grid of cell size 2 r_max.
    pd_grid g;
    g.init(d_lim);
    const std::size_t cells = std::size_t(g.dim) * std::size_t(g.dim);
    std::vector<std::uint32_t> cstart(cells + 1, 0), citems(m);
    std::vector<std::uint32_t> pcell(m);
    for (std::size_t i = 0; i < m; ++i) {
        pcell[i] = static_cast<std::uint32_t>(std::size_t(g.cell_of(double(pts[i].y))) * std::size_t(g.dim) +
                                              std::size_t(g.cell_of(double(pts[i].x))));
        ++cstart[pcell[i] + 1];
    }
    for (std::size_t c = 0; c < cells; ++c) cstart[c + 1] += cstart[c];
    {
        std::vector<std::uint32_t> fill(cstart.begin(), cstart.end() - 1);
        for (std::size_t i = 0; i < m; ++i) citems[fill[pcell[i]]++] = static_cast<std::uint32_t>(i);
    }
    std::vector<std::uint32_t> nstart(m + 1, 0), nitems;
    std::vector<double> nweight;
    pd_max_heap heap;
    heap.key.assign(m, 0.0);
    for (std::size_t i = 0; i < m; ++i) {
        const int cx = g.cell_of(double(pts[i].x)), cy = g.cell_of(double(pts[i].y));
        for (int y = cy - 1; y <= cy + 1; ++y) {
            if (y < 0 || y >= g.dim) continue;
            for (int x = cx - 1; x <= cx + 1; ++x) {
                if (x < 0 || x >= g.dim) continue;
                const std::size_t c = std::size_t(y) * std::size_t(g.dim) + std::size_t(x);
                for (std::uint32_t k = cstart[c]; k < cstart[c + 1]; ++k) {
                    const std::uint32_t j = citems[k];
                    if (j == i) continue;
                    const double d = std::sqrt(pd_dist2(pts[i], pts[j]));
                    if (d < d_lim) {
                        const double w = weight(d);
                        nitems.push_back(j);
                        nweight.push_back(w);
                        heap.key[i] += w;
                    }
                }
            }
        }
        nstart[i + 1] = static_cast<std::uint32_t>(nitems.size());
    }
    heap.build();
    std::size_t left = m;
    while (left > target) {
        const std::uint32_t e = heap.pop();
        alive[e] = 0;
        order.push_back(e);
        --left;
        for (std::uint32_t k = nstart[e]; k < nstart[e + 1]; ++k) {
            const std::uint32_t j = nitems[k];
            if (alive[j]) heap.decrease(j, heap.key[j] - nweight[k]);
        }
    }
}

// Squared minimum pairwise distance: grid search with cell size `cell`, exact whenever the result
// is below `cell`; brute force otherwise.
inline double pd_min_dist2(const std::vector<glm::vec2>& pts, double cell_size) {
    const std::size_t n = pts.size();
    double best = std::numeric_limits<double>::infinity();
    if (n < 2) return best;
    pd_grid g;
    g.init(cell_size);
    const std::size_t cells = std::size_t(g.dim) * std::size_t(g.dim);
    if (cells <= 4 * n + 16) {
        std::vector<std::int32_t> head(cells, -1), next(n, -1);
        for (std::size_t i = 0; i < n; ++i) {
            const std::size_t c = std::size_t(g.cell_of(double(pts[i].y))) * std::size_t(g.dim) +
                                  std::size_t(g.cell_of(double(pts[i].x)));
            next[i] = head[c];
            head[c] = static_cast<std::int32_t>(i);
        }
        for (std::size_t i = 0; i < n; ++i) {
            const int cx = g.cell_of(double(pts[i].x)), cy = g.cell_of(double(pts[i].y));
            for (int y = cy - 1; y <= cy + 1; ++y) {
                if (y < 0 || y >= g.dim) continue;
                for (int x = cx - 1; x <= cx + 1; ++x) {
                    if (x < 0 || x >= g.dim) continue;
                    for (std::int32_t j = head[std::size_t(y) * std::size_t(g.dim) + std::size_t(x)]; j >= 0;
                         j = next[std::size_t(j)])
                        if (std::size_t(j) != i) {
                            const double q = pd_dist2(pts[i], pts[std::size_t(j)]);
                            if (q < best) best = q;
                        }
                }
            }
        }
        if (best < cell_size * cell_size) return best;
    }
    best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j) {
            const double q = pd_dist2(pts[i], pts[j]);
            if (q < best) best = q;
        }
    return best;
}

}  // namespace detail

namespace detail {
inline PoissonValue pd_value(double v) {
    PoissonValue r;
    if (!std::isfinite(v) || std::fabs(v) > double(std::numeric_limits<float>::max())) {
        r.status = Status::Overflow;
        r.detail = "value: beyond float range";
        return r;
    }
    r.value = static_cast<float>(v);
    r.status = Status::Ok;
    return r;
}
// `why`: where the status came from, a static string.
inline PoissonValue pd_error(Status s, const char* why) {
    PoissonValue r;
    r.status = s;
    r.detail = why;
    return r;
}
// A point array: null only with n == 0, every coordinate finite. `why` receives the detail.
inline Status pd_check_points(const glm::vec2* pts, std::size_t n, const char*& why) {
    if (pts == nullptr && n > 0) return why = "pts: null with n > 0", Status::InvalidArgument;
    for (std::size_t i = 0; i < n; ++i)
        if (!std::isfinite(pts[i].x) || !std::isfinite(pts[i].y)) return why = "pts: NaN or Inf", Status::NonFinite;
    return Status::Ok;
}
// Why a domain is invalid (pd_valid_domain false).
inline const char* pd_domain_why(PoissonDomain d) {
    return d.shape == PoissonShape::Annulus ? "inner_radius: outside [0, 0.99]" : "shape: unknown PoissonShape";
}
}  // namespace detail

/// Area of the domain (pi, 4, or pi (1 - r_i^2)). InvalidArgument for an unknown shape or an
/// inner radius outside [0, 0.99] (NonFinite when NaN/Inf).
inline PoissonValue poisson_domain_area(PoissonDomain d) {
    if (d.shape == PoissonShape::Annulus && !std::isfinite(d.inner_radius))
        return detail::pd_error(Status::NonFinite, "inner_radius: NaN or Inf");
    if (!detail::pd_valid_domain(d)) return detail::pd_error(Status::InvalidArgument, detail::pd_domain_why(d));
    return detail::pd_value(detail::pd_area(d));
}

/// True when p lies in the (closed) domain. total: false for NaN/Inf or an invalid domain.
inline bool poisson_domain_contains(PoissonDomain d, glm::vec2 p) {
    return detail::pd_valid_domain(d) && detail::pd_contains(d, double(p.x), double(p.y));
}

/// Densest-packing distance for n points on area A (Lagae & Dutre 2008, eq. 2):
/// d_max = sqrt(2 A / (sqrt(3) n)), the spacing of a hexagonal lattice with n points per area A.
/// InvalidArgument for n == 0 or an invalid domain (NonFinite for a NaN/Inf inner radius).
inline PoissonValue poisson_packing_distance(PoissonDomain d, std::size_t n) {
    const PoissonValue a = poisson_domain_area(d);
    if (a.status != Status::Ok) return a;
    if (n == 0) return detail::pd_error(Status::InvalidArgument, "n: 0");
    return detail::pd_value(std::sqrt(2.0 * detail::pd_area(d) / (std::sqrt(3.0) * double(n))));
}

/// Upper bound on the number of points any set with minimum distance `radius` can have in the domain:
/// disks of radius r/2 around the points are disjoint and lie in the domain dilated by r/2, so
/// n <= area(dilated) / (pi r^2 / 4). Use it to size the buffer for poisson_bridson (in glm::vec2
/// elements). total: 0 for an invalid radius or domain; saturates at kPoissonMaxPoints + 1.
inline std::size_t poisson_bridson_capacity(PoissonDomain d, float radius) {
    if (!detail::pd_valid_domain(d) || !std::isfinite(radius) || !(radius > 0.0f)) return 0;
    const double r = double(radius), h = 0.5 * r;
    const double dil = d.shape == PoissonShape::Square ? 4.0 + 8.0 * h + detail::kPdPi * h * h
                                                       : detail::kPdPi * (1.0 + h) * (1.0 + h);
    const double n = std::floor(dil / (detail::kPdPi * h * h)) + 1.0;
    if (!(n <= double(kPoissonMaxPoints))) return kPoissonMaxPoints + 1;
    return static_cast<std::size_t>(n);
}

/// Options for Bridson's generator. The defaults are the recommended setting.
struct PoissonBridsonOptions {
    int attempts = 30;      ///< k candidates per active point (Bridson 2007), in [1, 1000]
    bool fill_gaps = true;  ///< after the dart throwing, one pass over a lattice of spacing r/4 adds
                            ///< any further point that fits, so the set is maximal up to that lattice:
                            ///< every domain point is within r + r*sqrt(2)/4 of a sample.
};

/// Bridson's O(n) dart throwing: every pair of the returned points is at least `radius` apart
/// (checked in double on the float coordinates, so the property holds exactly for the floats you
/// get), every point is inside the domain. The count is whatever fits.
/// `out` holds `out_capacity` glm::vec2 points; it needs `needed` of them, at most
/// poisson_bridson_capacity(d, radius). Too small: BufferTooSmall, the first out_capacity points
/// written (count) and `needed` the full count. NonFinite for a NaN/Inf radius, InvalidArgument for
/// radius <= 0, an invalid domain or options, null `out` with out_capacity > 0, or a radius whose
/// capacity bound exceeds kPoissonMaxPoints (no work done). Allocates its work memory.
inline PoissonResult poisson_bridson(PoissonDomain d, float radius, std::uint64_t seed, glm::vec2* out,
                                     std::size_t out_capacity, PoissonBridsonOptions opt = PoissonBridsonOptions{}) {
    using namespace detail;
    PoissonResult res;
    const std::size_t capacity = out_capacity;
    if (!std::isfinite(radius) || (d.shape == PoissonShape::Annulus && !std::isfinite(d.inner_radius))) {
        res.status = Status::NonFinite;
        res.detail = !std::isfinite(radius) ? "radius: NaN or Inf" : "inner_radius: NaN or Inf";
        return res;
    }
    if (!pd_valid_domain(d) || !(radius > 0.0f) || (out == nullptr && capacity > 0) || opt.attempts < 1 ||
        opt.attempts > 1000 || poisson_bridson_capacity(d, radius) > kPoissonMaxPoints) {
        res.status = Status::InvalidArgument;
        res.detail = !pd_valid_domain(d) ? pd_domain_why(d)
                     : (!(radius > 0.0f) ? "radius: not > 0"
                     : (out == nullptr && capacity > 0 ? "out: null with out_capacity > 0"
                     : (opt.attempts < 1 || opt.attempts > 1000 ? "attempts: outside [1, 1000]" : "radius: too small (beyond kPoissonMaxPoints)")));
        return res;
    }
    res.radius = radius;
    const double r = double(radius);
    // Acceptance threshold slightly above r^2 so that the test in double on float coordinates
    // leaves room for any reasonable re-evaluation of the distance by the caller.
    const double r2 = r * r * (1.0 + 1e-9);
    pd_rng rng{seed};
    pd_grid g;
    g.init(r / std::sqrt(2.0));
    std::vector<std::int32_t> cell(std::size_t(g.dim) * std::size_t(g.dim), -1);
    std::vector<glm::vec2> pts;
    std::vector<std::uint32_t> active;
    auto fits = [&](glm::vec2 p) {
        if (!pd_contains(d, double(p.x), double(p.y))) return false;
        const int cx = g.cell_of(double(p.x)), cy = g.cell_of(double(p.y));
        if (cell[std::size_t(cy) * std::size_t(g.dim) + std::size_t(cx)] >= 0) return false;
        for (int y = cy - 2; y <= cy + 2; ++y) {
            if (y < 0 || y >= g.dim) continue;
            for (int x = cx - 2; x <= cx + 2; ++x) {
                if (x < 0 || x >= g.dim) continue;
                const std::int32_t k = cell[std::size_t(y) * std::size_t(g.dim) + std::size_t(x)];
                if (k >= 0 && pd_dist2(pts[std::size_t(k)], p) < r2) return false;
            }
        }
        return true;
    };
    auto add = [&](glm::vec2 p) {
        const int cx = g.cell_of(double(p.x)), cy = g.cell_of(double(p.y));
        cell[std::size_t(cy) * std::size_t(g.dim) + std::size_t(cx)] = static_cast<std::int32_t>(pts.size());
        active.push_back(static_cast<std::uint32_t>(pts.size()));
        pts.push_back(p);
    };
    // Two points in one grid cell would be closer than r (cell diagonal == r): the grid needs at
    // most one entry per cell, which `fits` enforces explicitly.
    auto throw_darts = [&]() {
        while (!active.empty()) {
            const std::size_t ai = static_cast<std::size_t>(rng.uniform() * double(active.size()));
            const std::size_t slot = ai < active.size() ? ai : active.size() - 1;
            const glm::vec2 c = pts[active[slot]];
            bool found = false;
            for (int a = 0; a < opt.attempts && !found; ++a) {
                const double rr = std::sqrt(r * r + rng.uniform() * 3.0 * r * r);  // uniform in [r, 2r] annulus
                const double ang = 2.0 * kPdPi * rng.uniform();
                const glm::vec2 p(static_cast<float>(double(c.x) + rr * std::cos(ang)),
                                  static_cast<float>(double(c.y) + rr * std::sin(ang)));
                if (fits(p)) {
                    add(p);
                    found = true;
                }
            }
            if (!found) {
                active[slot] = active.back();
                active.pop_back();
            }
        }
    };
    add(pd_uniform_point(d, rng));
    throw_darts();
    if (opt.fill_gaps) {
        const double h = r / 4.0;
        const int dim = static_cast<int>(std::ceil(2.0 / h));
        for (int y = 0; y < dim; ++y) {
            for (int x = 0; x < dim; ++x) {
                for (int t = 0; t < 2; ++t) {
                    const glm::vec2 p(static_cast<float>(-1.0 + (double(x) + rng.uniform()) * h),
                                      static_cast<float>(-1.0 + (double(y) + rng.uniform()) * h));
                    if (fits(p)) {
                        add(p);
                        throw_darts();  // grow from the new point too
                        break;
                    }
                }
            }
        }
    }
    res.needed = pts.size();
    res.count = pts.size() < capacity ? pts.size() : capacity;
    for (std::size_t i = 0; i < res.count; ++i) out[i] = pts[i];
    res.status = res.count == res.needed ? Status::Ok : Status::BufferTooSmall;
    res.detail = res.count == res.needed ? nullptr : "out_capacity: below needed (see needed)";
    return res;
}

/// Options for weighted sample elimination. The defaults are the recommended setting.
struct PoissonEliminationOptions {
    int candidate_factor = 5;     ///< M = factor * N uniform candidates (Yuksel uses 5), in [2, 64]
    bool weight_limiting = true;  ///< Yuksel 2015 Sec. 3.3 (gamma 1.5, beta 0.65)
    bool progressive = true;      ///< order the output so that every prefix is itself well spread
                                  ///< (Yuksel 2015 Sec. 5: eliminate N -> N/2 -> ..., the removed go last)
};

/// Weighted sample elimination (Yuksel 2015): exactly `count` points in the domain, deterministic
/// from `seed`. r_max = sqrt(A / (2 sqrt(3) N)), weights (1 - d/(2 r_max))^8.
/// `out` holds `out_capacity` glm::vec2 points; it needs `count` (`needed`). count == 0: Ok,
/// nothing written. out_capacity < count: BufferTooSmall with needed = count (nothing generated or
/// written). InvalidArgument for count > kPoissonMaxPoints, an invalid domain or options, null
/// `out` with out_capacity > 0 (NonFinite for a NaN/Inf inner radius). res.radius is the minimum
/// pairwise distance of the set (0 for count < 2). Allocates its work memory.
inline PoissonResult poisson_eliminate(PoissonDomain d, std::size_t count, std::uint64_t seed, glm::vec2* out,
                                       std::size_t out_capacity, PoissonEliminationOptions opt = PoissonEliminationOptions{}) {
    using namespace detail;
    PoissonResult res;
    const std::size_t capacity = out_capacity;
    if (d.shape == PoissonShape::Annulus && !std::isfinite(d.inner_radius)) {
        res.status = Status::NonFinite;
        res.detail = "inner_radius: NaN or Inf";
        return res;
    }
    if (!pd_valid_domain(d) || (out == nullptr && capacity > 0) || opt.candidate_factor < 2 ||
        opt.candidate_factor > 64 || count > kPoissonMaxPoints) {
        res.status = Status::InvalidArgument;
        res.detail = !pd_valid_domain(d) ? pd_domain_why(d)
                     : (out == nullptr && capacity > 0 ? "out: null with out_capacity > 0"
                     : (opt.candidate_factor < 2 || opt.candidate_factor > 64 ? "candidate_factor: outside [2, 64]" : "count: > kPoissonMaxPoints"));
        return res;
    }
    res.needed = count;
    if (capacity < count) {
        res.status = Status::BufferTooSmall;
        res.detail = "out_capacity: below count (see needed)";
        return res;
    }
    res.status = Status::Ok;
    if (count == 0) return res;
    pd_rng rng{seed};
    std::vector<glm::vec2> cand(count * std::size_t(opt.candidate_factor));
    for (glm::vec2& p : cand) p = pd_uniform_point(d, rng);
    const double a = pd_area(d);
    std::vector<std::uint8_t> alive;
    std::vector<std::uint32_t> order;
    pd_eliminate(cand, count, a, opt.weight_limiting, alive, order);
    std::vector<glm::vec2> set;
    set.reserve(count);
    for (std::size_t i = 0; i < cand.size(); ++i)
        if (alive[i]) set.push_back(cand[i]);
    if (opt.progressive) {
        // Positions [t, n) receive the samples removed when going from n to t = n/2, the last removed
        // first, so the prefix of length t is the set a direct elimination to t would keep.
        std::vector<glm::vec2> sorted(set.size());
        std::size_t n = set.size();
        std::vector<glm::vec2> cur = set;
        while (n > 1) {
            const std::size_t t = n / 2;
            pd_eliminate(cur, t, a, opt.weight_limiting, alive, order);
            for (std::size_t k = 0; k < order.size(); ++k) sorted[n - 1 - k] = cur[order[k]];
            std::vector<glm::vec2> next;
            next.reserve(t);
            for (std::size_t i = 0; i < cur.size(); ++i)
                if (alive[i]) next.push_back(cur[i]);
            cur.swap(next);
            n = t;
        }
        sorted[0] = cur[0];
        set.swap(sorted);
    }
    for (std::size_t i = 0; i < set.size(); ++i) out[i] = set[i];
    res.count = count;
    if (count < 2) return res;
    res.radius = static_cast<float>(std::sqrt(pd_min_dist2(set, 1.5 * std::sqrt(2.0 * a / (std::sqrt(3.0) * double(count))))));
    return res;
}

/// Minimum pairwise distance, brute force O(n^2) in double. `pts` holds n points (null only with
/// n == 0). InvalidArgument for n < 2 or null pts, NonFinite for a NaN/Inf coordinate, Overflow
/// beyond float.
inline PoissonValue poisson_min_distance(const glm::vec2* pts, std::size_t n) {
    const char* why = nullptr;
    const Status s = detail::pd_check_points(pts, n, why);
    if (s != Status::Ok) return detail::pd_error(s, why);
    if (n < 2) return detail::pd_error(Status::InvalidArgument, "n: < 2");
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j) {
            const double q = detail::pd_dist2(pts[i], pts[j]);
            if (q < best) best = q;
        }
    return detail::pd_value(std::sqrt(best));
}

/// Normalized radius rho = d_min / d_max (Lagae & Dutre 2008). Dart throwing reaches about 0.75,
/// hexagonal packing is 1 (bounded domains with few points can exceed 1: points sit on the
/// boundary). Statuses of poisson_min_distance and poisson_packing_distance.
inline PoissonValue poisson_normalized_radius(PoissonDomain d, const glm::vec2* pts, std::size_t n) {
    const PoissonValue dmax = poisson_packing_distance(d, n);
    if (dmax.status != Status::Ok) return dmax;
    const PoissonValue dmin = poisson_min_distance(pts, n);
    if (dmin.status != Status::Ok) return dmin;
    return detail::pd_value(double(dmin.value) / double(dmax.value));
}

namespace detail {
inline double pd_nearest(const glm::vec2* pts, std::size_t n, double x, double y) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < n; ++i) {
        const double dx = x - double(pts[i].x), dy = y - double(pts[i].y);
        const double q = dx * dx + dy * dy;
        if (q < best) best = q;
    }
    return best;
}
}  // namespace detail

/// Coverage radius: the radius of the largest empty circle whose center lies in the domain
/// (max over c in domain of min_i |c - p_i|), computed exactly by brute force: the maximum is at a
/// Voronoi vertex (circumcenter of a triple) inside the domain, where a Voronoi edge (pair bisector)
/// crosses the boundary, at a square corner, or at the boundary point of a circle farthest from a
/// sample. O(n^4) time, intended for kernels (n <= a few hundred). `pts` holds n points.
/// InvalidArgument for n == 0, null pts or an invalid domain; NonFinite for a NaN/Inf coordinate.
inline PoissonValue poisson_coverage_radius(PoissonDomain d, const glm::vec2* pts, std::size_t n) {
    using namespace detail;
    const PoissonValue a = poisson_domain_area(d);
    if (a.status != Status::Ok) return a;
    const char* why = nullptr;
    const Status ps = pd_check_points(pts, n, why);
    if (ps != Status::Ok) return pd_error(ps, why);
    if (n == 0) return pd_error(Status::InvalidArgument, "n: 0");
    double best = 0.0;
    auto eval = [&](double x, double y) {
        const double q = pd_nearest(pts, n, x, y);
        if (q > best) best = q;
    };
    const bool square = d.shape == PoissonShape::Square;
    const double ri = d.shape == PoissonShape::Annulus ? double(d.inner_radius) : 0.0;
    const double tol = 1e-12;
    auto inside = [&](double x, double y) {
        if (square) return x >= -1.0 - tol && x <= 1.0 + tol && y >= -1.0 - tol && y <= 1.0 + tol;
        const double r2 = x * x + y * y;
        return r2 <= 1.0 + tol && r2 >= ri * ri - tol;
    };
    if (square) {
        eval(-1, -1); eval(1, -1); eval(-1, 1); eval(1, 1);
    } else {
        eval(1, 0);
        for (std::size_t i = 0; i < n; ++i) {
            const double px = double(pts[i].x), py = double(pts[i].y), l = std::sqrt(px * px + py * py);
            if (l > 0) {
                eval(-px / l, -py / l);
                if (ri > 0) eval(-ri * px / l, -ri * py / l);
            }
        }
        if (ri > 0) eval(ri, 0);
    }
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = i + 1; j < n; ++j) {
            // Bisector: points m + t * dir.
            const double ax = double(pts[i].x), ay = double(pts[i].y), bx = double(pts[j].x), by = double(pts[j].y);
            const double mx = 0.5 * (ax + bx), my = 0.5 * (ay + by);
            const double dx = -(by - ay), dy = bx - ax;
            if (dx == 0 && dy == 0) continue;
            if (square) {
                for (int s = -1; s <= 1; s += 2) {
                    if (dx != 0) {
                        const double t = (double(s) - mx) / dx, y = my + t * dy;
                        if (y >= -1 && y <= 1) eval(double(s), y);
                    }
                    if (dy != 0) {
                        const double t = (double(s) - my) / dy, x = mx + t * dx;
                        if (x >= -1 && x <= 1) eval(x, double(s));
                    }
                }
            } else {
                const double circles[2] = {1.0, ri};
                for (int c = 0; c < (ri > 0 ? 2 : 1); ++c) {
                    const double R = circles[c];
                    // |m + t dir|^2 = R^2
                    const double qa = dx * dx + dy * dy, qb = 2 * (mx * dx + my * dy), qc = mx * mx + my * my - R * R;
                    const double disc = qb * qb - 4 * qa * qc;
                    if (disc < 0) continue;
                    const double sq = std::sqrt(disc);
                    for (int s = -1; s <= 1; s += 2) {
                        const double t = (-qb + double(s) * sq) / (2 * qa);
                        double x = mx + t * dx, y = my + t * dy;
                        const double l = std::sqrt(x * x + y * y);
                        if (l > 0) { x *= R / l; y *= R / l; }
                        eval(x, y);
                    }
                }
            }
            for (std::size_t k = j + 1; k < n; ++k) {
                const double cx_ = double(pts[k].x), cy_ = double(pts[k].y);
                const double bxr = bx - ax, byr = by - ay, cxr = cx_ - ax, cyr = cy_ - ay;
                const double den = 2.0 * (bxr * cyr - byr * cxr);
                if (den == 0) continue;
                const double b2 = bxr * bxr + byr * byr, c2 = cxr * cxr + cyr * cyr;
                const double ux = (cyr * b2 - byr * c2) / den, uy = (bxr * c2 - cxr * b2) / den;
                const double x = ax + ux, y = ay + uy;
                if (inside(x, y)) eval(x, y);
            }
        }
    }
    return pd_value(std::sqrt(best));
}

/// Coverage radius estimated on a resolution x resolution lattice of centers over [-1,1]^2 (those
/// inside the domain). A lower bound of the exact value, within about 2/resolution of it.
/// O(resolution^2 n); resolution is clamped to [2, 4096]. `pts` holds n points. Statuses as
/// poisson_coverage_radius.
inline PoissonValue poisson_coverage_radius_grid(PoissonDomain d, const glm::vec2* pts, std::size_t n, int resolution) {
    using namespace detail;
    const PoissonValue a = poisson_domain_area(d);
    if (a.status != Status::Ok) return a;
    const char* why = nullptr;
    const Status ps = pd_check_points(pts, n, why);
    if (ps != Status::Ok) return pd_error(ps, why);
    if (n == 0) return pd_error(Status::InvalidArgument, "n: 0");
    const int res = resolution < 2 ? 2 : (resolution > 4096 ? 4096 : resolution);
    double best = 0.0;
    for (int y = 0; y < res; ++y)
        for (int x = 0; x < res; ++x) {
            const double px = -1.0 + 2.0 * double(x) / double(res - 1), py = -1.0 + 2.0 * double(y) / double(res - 1);
            if (!pd_contains(d, px, py)) continue;
            const double q = pd_nearest(pts, n, px, py);
            if (q > best) best = q;
        }
    return pd_value(std::sqrt(best));
}

namespace detail {
// GLSL 4.60 keywords and words reserved for future use (GLSL spec 3.6), which no identifier may be.
inline bool pd_glsl_reserved(const char* name, std::size_t len) {
    static const char* const kWords[] = {
        "active", "asm", "atomic_uint", "attribute", "bool", "break", "buffer", "bvec2", "bvec3", "bvec4", "case",
        "cast", "centroid", "class", "coherent", "common", "const", "continue", "default", "discard", "dmat2",
        "dmat2x2", "dmat2x3", "dmat2x4", "dmat3", "dmat3x2", "dmat3x3", "dmat3x4", "dmat4", "dmat4x2", "dmat4x3",
        "dmat4x4", "do", "double", "dvec2", "dvec3", "dvec4", "else", "enum", "extern", "external", "false",
        "filter", "fixed", "flat", "float", "for", "fvec2", "fvec3", "fvec4", "goto", "half", "highp", "hvec2",
        "hvec3", "hvec4", "if", "iimage1D", "iimage1DArray", "iimage2D", "iimage2DArray", "iimage2DMS",
        "iimage2DMSArray", "iimage2DRect", "iimage3D", "iimageBuffer", "iimageCube", "iimageCubeArray", "image1D",
        "image1DArray", "image2D", "image2DArray", "image2DMS", "image2DMSArray", "image2DRect", "image3D",
        "imageBuffer", "imageCube", "imageCubeArray", "in", "inline", "inout", "input", "int", "interface",
        "invariant", "isampler1D", "isampler1DArray", "isampler2D", "isampler2DArray", "isampler2DMS",
        "isampler2DMSArray", "isampler2DRect", "isampler3D", "isamplerBuffer", "isamplerCube", "isamplerCubeArray",
        "ivec2", "ivec3", "ivec4", "layout", "long", "lowp", "mat2", "mat2x2", "mat2x3", "mat2x4", "mat3", "mat3x2",
        "mat3x3", "mat3x4", "mat4", "mat4x2", "mat4x3", "mat4x4", "mediump", "namespace", "noinline",
        "noperspective", "out", "output", "partition", "patch", "precise", "precision", "public", "readonly",
        "resource", "restrict", "return", "sample", "sampler1D", "sampler1DArray", "sampler1DArrayShadow",
        "sampler1DShadow", "sampler2D", "sampler2DArray", "sampler2DArrayShadow", "sampler2DMS",
        "sampler2DMSArray", "sampler2DRect", "sampler2DRectShadow", "sampler2DShadow", "sampler3D",
        "sampler3DRect", "samplerBuffer", "samplerCube", "samplerCubeArray", "samplerCubeArrayShadow",
        "samplerCubeShadow", "shared", "short", "sizeof", "smooth", "static", "struct", "subroutine", "superp",
        "switch", "template", "this", "true", "typedef", "uimage1D", "uimage1DArray", "uimage2D", "uimage2DArray",
        "uimage2DMS", "uimage2DMSArray", "uimage2DRect", "uimage3D", "uimageBuffer", "uimageCube",
        "uimageCubeArray", "uint", "uniform", "union", "unsigned", "usampler1D", "usampler1DArray", "usampler2D",
        "usampler2DArray", "usampler2DMS", "usampler2DMSArray", "usampler2DRect", "usampler3D", "usamplerBuffer",
        "usamplerCube", "usamplerCubeArray", "using", "uvec2", "uvec3", "uvec4", "varying", "vec2", "vec3", "vec4",
        "void", "volatile", "while", "writeonly"};
    for (const char* w : kWords) {
        std::size_t k = 0;
        while (k < len && w[k] != '\0' && w[k] == name[k]) ++k;
        if (k == len && w[k] == '\0') return true;
    }
    return false;
}
// main and the built-in function names of GLSL 4.50 (spec chapter 8, compatibility-profile texture
// functions included) and 4.60's invocation votes: a global array of that name hides the function
// for every snippet pasted after it.
inline bool pd_glsl_builtin(const char* name, std::size_t len) {
    static const char* const kNames[] = {
        "main", "radians", "degrees", "sin", "cos", "tan", "asin", "acos", "atan", "sinh", "cosh", "tanh", "asinh",
        "acosh", "atanh", "pow", "exp", "log", "exp2", "log2", "sqrt", "inversesqrt", "abs", "sign", "floor",
        "trunc", "round", "roundEven", "ceil", "fract", "mod", "modf", "min", "max", "clamp", "mix", "step",
        "smoothstep", "isnan", "isinf", "floatBitsToInt", "floatBitsToUint", "intBitsToFloat", "uintBitsToFloat",
        "fma", "frexp", "ldexp", "packUnorm2x16", "packSnorm2x16", "packUnorm4x8", "packSnorm4x8",
        "unpackUnorm2x16", "unpackSnorm2x16", "unpackUnorm4x8", "unpackSnorm4x8", "packHalf2x16", "unpackHalf2x16",
        "packDouble2x32", "unpackDouble2x32", "length", "distance", "dot", "cross", "normalize", "ftransform",
        "faceforward", "reflect", "refract", "matrixCompMult", "outerProduct", "transpose", "determinant",
        "inverse", "lessThan", "lessThanEqual", "greaterThan", "greaterThanEqual", "equal", "notEqual", "any",
        "all", "not", "uaddCarry", "usubBorrow", "umulExtended", "imulExtended", "bitfieldExtract",
        "bitfieldInsert", "bitfieldReverse", "bitCount", "findLSB", "findMSB", "textureSize", "textureQueryLod",
        "textureQueryLevels", "textureSamples", "texture", "textureProj", "textureLod", "textureOffset",
        "texelFetch", "texelFetchOffset", "textureProjOffset", "textureLodOffset", "textureProjLod",
        "textureProjLodOffset", "textureGrad", "textureGradOffset", "textureProjGrad", "textureProjGradOffset",
        "textureGather", "textureGatherOffset", "textureGatherOffsets", "texture1D", "texture1DProj",
        "texture1DLod", "texture1DProjLod", "texture2D", "texture2DProj", "texture2DLod", "texture2DProjLod",
        "texture3D", "texture3DProj", "texture3DLod", "texture3DProjLod", "textureCube", "textureCubeLod",
        "shadow1D", "shadow2D", "shadow1DProj", "shadow2DProj", "shadow1DLod", "shadow2DLod", "shadow1DProjLod",
        "shadow2DProjLod", "atomicCounterIncrement", "atomicCounterDecrement", "atomicCounter", "atomicAdd",
        "atomicMin", "atomicMax", "atomicAnd", "atomicOr", "atomicXor", "atomicExchange", "atomicCompSwap",
        "imageSize", "imageSamples", "imageLoad", "imageStore", "imageAtomicAdd", "imageAtomicMin",
        "imageAtomicMax", "imageAtomicAnd", "imageAtomicOr", "imageAtomicXor", "imageAtomicExchange",
        "imageAtomicCompSwap", "EmitStreamVertex", "EndStreamPrimitive", "EmitVertex", "EndPrimitive", "dFdx",
        "dFdy", "dFdxFine", "dFdyFine", "dFdxCoarse", "dFdyCoarse", "fwidth", "fwidthFine", "fwidthCoarse",
        "interpolateAtCentroid", "interpolateAtSample", "interpolateAtOffset", "noise1", "noise2", "noise3",
        "noise4", "barrier", "memoryBarrier", "memoryBarrierAtomicCounter", "memoryBarrierBuffer",
        "memoryBarrierShared", "memoryBarrierImage", "groupMemoryBarrier", "anyInvocation", "allInvocations",
        "allInvocationsEqual"};
    for (const char* w : kNames) {
        std::size_t k = 0;
        while (k < len && w[k] != '\0' && w[k] == name[k]) ++k;
        if (k == len && w[k] == '\0') return true;
    }
    return false;
}
}  // namespace detail

/// Writes `const vec2 NAME[N] = vec2[N](vec2(x, y), ...);\n` with 9 significant digits (round-trips
/// float exactly), always with a '.' or exponent so every literal is a float; with
/// PoissonGlsl::ArrayForSnippets also `#define SK_POISSON_TAPS NAME\n#define SK_POISSON_TAP_COUNT N\n`
/// (paste it before glsl/pcf.glsl and glsl/pcss.glsl: their Poisson kernels then read NAME; emit it
/// for one array only). Any other name compiles next to the snippets' built-in sk_poisson_disk64.
/// `out` holds `out_capacity` chars; the text needs `needed` chars, the terminating NUL included.
/// `out` is always NUL-terminated when out_capacity > 0 (count chars written, the NUL included).
/// `pts` holds n points. Status: InvalidArgument for n == 0 (GLSL has no empty arrays), null pts,
/// null `out` with out_capacity > 0, or a name that is not a GLSL identifier of 1..256 chars: a
/// keyword or reserved word (float, if, sampler2D, ...), main or a built-in function name (texture,
/// textureSize, sin, ...: GLSL 4.50 chapter 8), a name with "__" or starting with "gl_"
/// (reserved by GLSL) or "sk_" (the snippets' own), an unknown mode; NonFinite for a NaN/Inf
/// coordinate; BufferTooSmall when out_capacity < needed (a truncated prefix is written).
inline PoissonGlslResult poisson_to_glsl(const glm::vec2* pts, std::size_t n, const char* name, PoissonGlsl mode,
                                         char* out, std::size_t out_capacity) {
    PoissonGlslResult res;
    const std::size_t capacity = out_capacity;
    if (pts == nullptr || n == 0 || name == nullptr || (out == nullptr && capacity > 0) ||
        (mode != PoissonGlsl::Array && mode != PoissonGlsl::ArrayForSnippets)) {
        res.status = Status::InvalidArgument;
        res.detail = pts == nullptr ? "pts: null"
                     : (n == 0 ? "n: 0"
                     : (name == nullptr ? "name: null"
                     : (out == nullptr && capacity > 0 ? "out: null with out_capacity > 0" : "mode: unknown PoissonGlsl")));
        return res;
    }
    {
        std::size_t len = 0;
        for (; name[len] != '\0' && len <= 256; ++len) {
            const char c = name[len];
            const bool alpha = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
            const bool digit = c >= '0' && c <= '9';
            const bool double_underscore = c == '_' && len > 0 && name[len - 1] == '_';
            if (!(alpha || (digit && len > 0)) || double_underscore) {
                res.status = Status::InvalidArgument;
                res.detail = "name: not a GLSL identifier (or has \"__\")";
                return res;
            }
        }
        if (len == 0 || len > 256 || (len >= 3 && ((name[0] == 'g' && name[1] == 'l' && name[2] == '_') ||
                                                   (name[0] == 's' && name[1] == 'k' && name[2] == '_'))) ||
            detail::pd_glsl_reserved(name, len) || detail::pd_glsl_builtin(name, len)) {
            res.status = Status::InvalidArgument;
            res.detail = "name: empty, too long, gl_ / sk_ prefix, or a GLSL keyword or built-in";
            return res;
        }
    }
    const Status ps = detail::pd_check_points(pts, n, res.detail);
    if (ps != Status::Ok) {
        res.status = ps;
        return res;
    }
    std::size_t pos = 0;
    auto put = [&](const char* s) {
        for (; *s; ++s, ++pos)
            if (pos + 1 < capacity) out[pos] = *s;
    };
    auto put_float = [&](float v) {
        char buf[48];
        std::snprintf(buf, sizeof buf, "%.9g", double(v));
        bool has_point = false;
        for (char* c = buf; *c; ++c) {
            if (*c == ',') *c = '.';  // a locale with a decimal comma
            if (*c == '.' || *c == 'e' || *c == 'E') has_point = true;
        }
        put(buf);
        if (!has_point) put(".0");
    };
    char num[32];
    std::snprintf(num, sizeof num, "%zu", n);
    put("const vec2 ");
    put(name);
    put("[");
    put(num);
    put("] = vec2[");
    put(num);
    put("](");
    for (std::size_t i = 0; i < n; ++i) {
        put(i == 0 ? "\n    vec2(" : ",\n    vec2(");
        put_float(pts[i].x);
        put(", ");
        put_float(pts[i].y);
        put(")");
    }
    put(");\n");
    if (mode == PoissonGlsl::ArrayForSnippets) {
        put("#define SK_POISSON_TAPS ");
        put(name);
        put("\n#define SK_POISSON_TAP_COUNT ");
        put(num);
        put("\n");
    }
    if (capacity > 0) out[pos < capacity ? pos : capacity - 1] = '\0';
    res.needed = pos + 1;
    res.count = res.needed < capacity ? res.needed : capacity;
    res.status = res.needed <= capacity ? Status::Ok : Status::BufferTooSmall;
    res.detail = res.needed <= capacity ? nullptr : "out_capacity: below needed (see needed)";
    return res;
}

}  // namespace shadowkit
