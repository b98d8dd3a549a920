// shadowkit/silhouette_map.hpp - shadow silhouette maps (Sen, Cammarano & Hanrahan 2003), the CPU side.
//
// Projects silhouette edges into the shadow map's texel space, rasterizes them conservatively into
// the dual grid, picks one silhouette point per texel (the paper's four cases), keeps the default
// point (texel center) elsewhere, and reconstructs the shadow boundary at a lookup: the
// piecewise-linear boundary through the neighboring silhouette points splits the texel into four
// sectors and the depth sample of the lookup's sector decides. Texels crossed by two different
// silhouette edges (the paper's known failure) are detected and fall back to the plain shadow-map
// result. GPU side: glsl/silhouette_map.glsl (same rules, same encoding). docs/silhouette_map.md
// has a complete program.
//
// Usage:
//   #include <shadowkit/silhouette_map.hpp>
//   namespace sk = shadowkit;
//   // silhouette edges for the light (e.g. silhouette.hpp: 2 indices per edge), light view-projection
//   std::vector<sk::SilmapEdge> e(edge_count);
//   sk::SilmapProjectResult pr = sk::silmap_project_edges(light_vp, sk::ClipDepth::NegativeOneToOne,
//       {2048, 2048}, pos, vertex_count, edges, edge_count, e.data(), e.size());   // pr.count edges
//   // CPU map (tests, software renderers); the GPU builds the same map with silhouette_map.glsl
//   std::vector<glm::vec2> pts(2048 * 2048); std::vector<uint8_t> wts(2048 * 2048);
//   sk::silmap_build(e.data(), pr.count, {2048, 2048}, depth /*or nullptr*/, 1e-4f,
//                    pts.data(), pts.size(), wts.data(), wts.size());
//   sk::SilmapLookup l = sk::silmap_lookup(pts.data(), wts.data(), depth, {2048, 2048},
//                                          texel_pos, receiver_depth, bias);   // l.status, l.lit
//
// Conventions (used by every function):
//   * Texel space: q = uv * size, uv = window coordinates of the light's projection in [0,1].
//     Depth sample (i, j) of a W x H shadow map sits at (i + 0.5, j + 0.5). W and H are
//     1 .. kSilmapMaxSize (32768); anything else is Status::InvalidArgument.
//   * The silhouette map has W x H texels on the dual grid: texel (i, j) is the cell
//     [i + 0.5, i + 1.5] x [j + 0.5, j + 1.5], whose corners are depth samples (i, j), (i+1, j),
//     (i, j+1), (i+1, j+1). Cells with i = W-1 or j = H-1 lack corners: lookups there, and in the
//     half-texel border strip, give the plain shadow-map result.
//   * A silhouette point is stored as its offset inside its cell, in [0,1]^2; the default point is
//     the cell center (0.5, 0.5). With every point at the default, the reconstruction equals the
//     nearest-sample shadow map (each sector is the region nearest its corner).
//   * Edge weight per texel (the failure detector) = the number of times the silhouette crosses the
//     texel's border: an edge adds 2 minus the number of its endpoints inside the (closed) cell. One
//     silhouette chain through a texel gives 2 however many of its vertices lie inside; two chains
//     (two edges passing near each other, a T-junction) give 3 or more. Weights saturate at 255. A
//     texel with weight > kSilmapFailureWeight (2) holds two different silhouette curves: the
//     paper's known failure. (A closed loop entirely inside one texel gives 0 and is missed.)
//   * Depth: window depth (any monotonic depth works if the depth map uses the same); finite.
//   * Maps are row-major (j * W + i), W * H elements each: the depth map (float), the points
//     (glm::vec2) and the weights (uint8). Buffer sizes are counted in elements of the pointer's
//     type. A null pointer with a non-zero count or capacity is Status::InvalidArgument.
//   * Status: NaN/Inf in any input is Status::NonFinite; `Ok` means every output is finite and in
//     its documented range. What a successful call found (edges culled, fragments occluded, failure
//     texels, a lookup that fell back to the plain map) is a field of its result. A non-Ok result's
//     `detail` names the offending input and the rule ("size: outside 1 .. kSilmapMaxSize"), a
//     static string; nullptr when Ok.
//   * This header takes no light: the light is in the light's view-projection matrix.
//
// Based on:
//   P. Sen, M. Cammarano, P. Hanrahan, "Shadow Silhouette Maps", SIGGRAPH 2003 (sections 3-4:
//   dual grid, silhouette point cases, default point, reconstruction by the depth sample of the
//   sector, conservative edge rasterization, occluded silhouette fragments).
//   P. Sen, "Silhouette Maps", SIGGRAPH 2004 course "Real-Time Shadowing Techniques" notes
//   (point cases 1-4 by the two diagonals; multiple edges in one texel as the known failure).
//
// MIT License. Copyright (c) shadowkit contributors.
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
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

#ifndef SHADOWKIT_CLIP_DEPTH_DEFINED
#define SHADOWKIT_CLIP_DEPTH_DEFINED
/// Clip-space depth range of the projection: OpenGL [-1,1] or D3D/Vulkan/glClipControl [0,1].
enum class ClipDepth { NegativeOneToOne, ZeroToOne };
#endif

/// The paper's silhouette point cases (course notes, "Silhouette Point Algorithm").
enum class SilmapCase {
    VertexInside,      ///< case 1: an endpoint lies in the cell: the endpoint itself
    OneIntersection,   ///< case 2: the edge crosses one diagonal: that intersection
    TwoIntersections,  ///< case 3: the edge crosses both diagonals: the midpoint of the two
    NoIntersection     ///< case 4: conservative fragment the edge misses: nothing written
};

/// A silhouette edge in texel space with window depths at its ends.
struct SilmapEdge {
    glm::vec2 a{0.f}, b{0.f};          ///< ends in texel space
    float depth_a = 0.f, depth_b = 0.f; ///< window depths at a and b
};

/// Result of silmap_project_edges.
struct SilmapProjectResult {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    std::size_t count = 0;   ///< edges written to `out` (a valid prefix; == needed when Ok)
    std::size_t needed = 0;  ///< edges the whole output needs (edge_count minus `culled`)
    std::size_t culled = 0;  ///< edges with nothing in front of the light or inside the guard band (not an error)
};

/// The silhouette point of one edge in one cell (silmap_select_point).
struct SilmapPoint {
    SilmapCase kase = SilmapCase::NoIntersection;
    glm::vec2 local{0.5f};    ///< offset in the cell, [0,1]^2 (the default (0.5, 0.5) for NoIntersection)
    int weight = 0;           ///< edge weight this edge adds to the cell, 0 .. 2 (see the header)
};

/// Result of silmap_rasterize_edge.
struct SilmapRasterResult {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    std::size_t count = 0;   ///< cells written to `out` (a valid prefix; == needed when Ok)
    std::size_t needed = 0;  ///< cells the edge touches (0: it misses the map, with Ok)
};

/// Result of silmap_build.
struct SilmapBuildResult {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    std::size_t count = 0;             ///< texels written to each of points and weights (W * H when Ok, else 0)
    std::size_t needed = 0;            ///< texels each output buffer needs (W * H)
    std::size_t fragments = 0;         ///< rasterized fragments with a silhouette point (cases 1-3)
    std::size_t points_written = 0;    ///< cases 1-3 (overwrites included)
    std::size_t occluded = 0;          ///< fragments discarded by the depth tests (occluded or casting no shadow)
    std::size_t failure_texels = 0;    ///< texels with weight > kSilmapFailureWeight
};

/// Result of a lookup (silmap_reconstruct, silmap_lookup).
struct SilmapLookup {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    bool lit = false;               ///< the answer (valid when status is Ok)
    bool silhouette_pixel = false;  ///< the four depth tests disagree (the silhouette map decides)
    bool fallback = false;          ///< failure texel, border or degenerate sectors: plain result used (with Ok)
    int corner = 0;                 ///< deciding depth sample: 0 (i,j), 1 (i+1,j), 2 (i,j+1), 3 (i+1,j+1)
};

/// Result of silmap_plain_lookup.
struct SilmapPlainLookup {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    bool lit = false;  ///< the nearest depth sample's test (valid when status is Ok)
};

/// Texels with an accumulated edge weight above this hold two different silhouette edges.
constexpr int kSilmapFailureWeight = 2;
/// Largest supported map side (texel coordinates stay exact in float).
constexpr std::uint32_t kSilmapMaxSize = 32768u;
/// Guard band of silmap_project_edges in NDC units: edges are clipped to |x|, |y|, |z| <= this * w,
/// so every projected coordinate is finite (the map itself is |x|, |y| <= w).
constexpr double kSilmapGuardBand = 1048576.0;

namespace detail {

inline bool silmap_finite(glm::vec2 v) { return std::isfinite(v.x) && std::isfinite(v.y); }

// Segment p0-p1 against segment q0-q1 (proper or touching intersection); t along p.
inline bool silmap_seg_intersect(glm::vec2 p0, glm::vec2 p1, glm::vec2 q0, glm::vec2 q1, glm::vec2& hit) {
    const glm::dvec2 r(double(p1.x) - p0.x, double(p1.y) - p0.y), s(double(q1.x) - q0.x, double(q1.y) - q0.y);
    const double den = r.x * s.y - r.y * s.x;
    if (den == 0.0) return false;  // parallel (collinear overlap with a diagonal: the endpoints decide)
    const glm::dvec2 qp(double(q0.x) - p0.x, double(q0.y) - p0.y);
    const double t = (qp.x * s.y - qp.y * s.x) / den;
    const double u = (qp.x * r.y - qp.y * r.x) / den;
    if (t < 0.0 || t > 1.0 || u < 0.0 || u > 1.0) return false;
    hit = glm::vec2(float(double(p0.x) + t * r.x), float(double(p0.y) + t * r.y));
    return true;
}

inline bool silmap_in_unit(glm::vec2 p) { return p.x >= 0.f && p.x <= 1.f && p.y >= 0.f && p.y <= 1.f; }

// Liang-Barsky clip of a segment to [lo, hi]^2; false if nothing is left.
inline bool silmap_clip(glm::dvec2& a, glm::dvec2& b, glm::dvec2 lo, glm::dvec2 hi) {
    double t0 = 0.0, t1 = 1.0;
    const glm::dvec2 d = b - a;
    for (int k = 0; k < 2; ++k) {
        const double p[2] = {-d[k], d[k]};
        const double q[2] = {a[k] - lo[k], hi[k] - a[k]};
        for (int m = 0; m < 2; ++m) {
            if (p[m] == 0.0) {
                if (q[m] < 0.0) return false;
                continue;
            }
            const double r = q[m] / p[m];
            if (p[m] < 0.0) t0 = std::max(t0, r);
            else t1 = std::min(t1, r);
        }
    }
    if (t0 > t1) return false;
    const glm::dvec2 a0 = a;
    // with huge endpoints (1e30 apart) a0 + t * d cancels badly; the clipped points are clamped back
    a = glm::clamp(a0 + t0 * d, lo, hi);
    b = glm::clamp(a0 + t1 * d, lo, hi);
    return true;
}

inline float silmap_wrap_angle(float a) {
    const float two_pi = 6.28318530717958647692f;
    while (a < 0.f) a += two_pi;
    while (a >= two_pi) a -= two_pi;
    return a;
}

inline bool silmap_size_ok(glm::uvec2 size) {
    return size.x != 0 && size.y != 0 && size.x <= kSilmapMaxSize && size.y <= kSilmapMaxSize;
}

// Clips the homogeneous segment ca-cb to the guard plane side * c[axis] <= g * c.w (axis 0..2,
// side +-1); false if nothing is left. Points already inside stay bit-identical; a clipped point
// gets c[axis] = side * g * w exactly (a + t (b - a) cancels for 1e38-long edges).
inline bool silmap_clip_guard(glm::dvec4& ca, glm::dvec4& cb, int axis, double side, double g) {
    const double fa = g * ca.w - side * ca[axis], fb = g * cb.w - side * cb[axis];
    if (fa >= 0.0 && fb >= 0.0) return true;
    if (fa < 0.0 && fb < 0.0) return false;
    const double t = fa / (fa - fb);
    glm::dvec4 c = ca + t * (cb - ca);
    c[axis] = side * g * c.w;
    if (fa < 0.0) ca = c;
    else cb = c;
    return true;
}

}  // namespace detail

/// Projects silhouette edges with the light's view-projection into texel space (window
/// coordinates times `size`), with window depths for `clip_depth`.
/// `positions` holds vertex_count glm::vec3 elements; `edges` holds 2 * edge_count uint32 indices
/// into positions (2 per edge); `out` holds out_capacity SilmapEdge elements; it needs one per edge
/// that is not culled (`needed`, at most edge_count).
/// Each edge is clipped in clip space to w >= 1e-6 * max(|w_a|, |w_b|) (in front of the light) and
/// to the guard band |x|, |y|, |z| <= kSilmapGuardBand * w; an edge with nothing left is culled
/// (counted in `culled`, with Ok). Every written coordinate is finite.
/// Errors: InvalidArgument (size outside 1 .. kSilmapMaxSize, a clip_depth that is not an
/// enumerator, a null pointer with a non-zero count), NonFinite (a non-finite matrix or referenced
/// position), IndexOutOfRange (an index >= vertex_count): nothing is written (count 0).
/// BufferTooSmall: the first out_capacity edges are written (count), `needed` says how many.
inline SilmapProjectResult silmap_project_edges(const glm::mat4& light_view_proj, ClipDepth clip_depth, glm::uvec2 size,
                                                const glm::vec3* positions, std::size_t vertex_count,
                                                const std::uint32_t* edges, std::size_t edge_count, SilmapEdge* out,
                                                std::size_t out_capacity) {
    SilmapProjectResult r;
    if ((edge_count && !edges) || (vertex_count && !positions) || (out_capacity && !out) ||
        !detail::silmap_size_ok(size) ||
        (clip_depth != ClipDepth::NegativeOneToOne && clip_depth != ClipDepth::ZeroToOne)) {
        r.status = Status::InvalidArgument;
        r.detail = edge_count && !edges ? "edges: null with edge_count > 0"
                   : (vertex_count && !positions ? "positions: null with vertex_count > 0"
                   : (out_capacity && !out ? "out: null with out_capacity > 0"
                   : (!detail::silmap_size_ok(size) ? "size: outside 1 .. kSilmapMaxSize" : "clip_depth: unknown ClipDepth")));
        return r;
    }
    for (int c = 0; c < 4; ++c)
        for (int k = 0; k < 4; ++k)
            if (!std::isfinite(light_view_proj[c][k])) {
                r.status = Status::NonFinite;
                r.detail = "light_view_proj: NaN or Inf";
                return r;
            }
    // validate every referenced vertex before writing anything
    for (std::size_t e = 0; e < 2 * edge_count; ++e) {
        if (edges[e] >= vertex_count) {
            r.status = Status::IndexOutOfRange;
            r.detail = "edges: an index >= vertex_count";
            return r;
        }
        const glm::vec3& p = positions[edges[e]];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
            r.status = Status::NonFinite;
            r.detail = "positions: NaN or Inf";
            return r;
        }
    }
    const glm::dvec2 sz(size.x, size.y);
    const glm::dmat4 m(light_view_proj);
    const double g = kSilmapGuardBand;
    for (std::size_t e = 0; e < edge_count; ++e) {
        glm::dvec4 ca = m * glm::dvec4(glm::dvec3(positions[edges[2 * e]]), 1.0);
        glm::dvec4 cb = m * glm::dvec4(glm::dvec3(positions[edges[2 * e + 1]]), 1.0);
        const double wmin = 1e-6 * std::max(std::abs(ca.w), std::abs(cb.w));
        if (ca.w <= wmin && cb.w <= wmin) {
            ++r.culled;
            continue;
        }
        if (ca.w <= wmin || cb.w <= wmin) {  // clip against w = wmin
            const double t = (wmin - ca.w) / (cb.w - ca.w);
            const glm::dvec4 c = ca + t * (cb - ca);
            if (ca.w <= wmin) ca = c;
            else cb = c;
            ca.w = std::max(ca.w, wmin);
            cb.w = std::max(cb.w, wmin);
        }
        // guard band: -g w <= x, y, z <= g w (keeps x / w, y / w, z / w finite and bounded)
        bool keep = true;
        for (int k = 0; k < 3 && keep; ++k)
            keep = detail::silmap_clip_guard(ca, cb, k, -1.0, g) && detail::silmap_clip_guard(ca, cb, k, 1.0, g);
        if (!keep || !(ca.w > 0.0) || !(cb.w > 0.0)) {
            ++r.culled;
            continue;
        }
        auto to_texel = [&](const glm::dvec4& c, glm::vec2& q, float& depth) {
            const double nz = glm::clamp(c.z / c.w, -g, g);
            q = glm::vec2(float((glm::clamp(c.x / c.w, -g, g) * 0.5 + 0.5) * sz.x),
                          float((glm::clamp(c.y / c.w, -g, g) * 0.5 + 0.5) * sz.y));
            depth = float(clip_depth == ClipDepth::ZeroToOne ? nz : nz * 0.5 + 0.5);
        };
        SilmapEdge se;
        to_texel(ca, se.a, se.depth_a);
        to_texel(cb, se.b, se.depth_b);
        if (r.needed < out_capacity) out[r.needed] = se;
        ++r.needed;
    }
    r.count = std::min(r.needed, out_capacity);
    r.status = r.needed > out_capacity ? Status::BufferTooSmall : Status::Ok;
    r.detail = r.needed > out_capacity ? "out_capacity: below needed (see needed)" : nullptr;
    return r;
}

/// The paper's silhouette point for one edge (ends a, b in texel space) and one cell (cell (i, j) =
/// dual-grid texel, see the header). Case 1: an endpoint in the cell (closed square; a first, then
/// b); else the edge is tested against the cell's two diagonals: one hit (case 2) or the midpoint of
/// two (case 3); no hit is case 4. Weight: 2 minus the endpoints inside (border crossings).
/// Total: any input, NaN and Inf included, gives `local` in [0,1]^2 and `weight` in 0 .. 2; a
/// non-finite end gives NoIntersection (weight 0, local (0.5, 0.5)).
inline SilmapPoint silmap_select_point(glm::vec2 a, glm::vec2 b, glm::ivec2 cell) {
    SilmapPoint r;
    if (!detail::silmap_finite(a) || !detail::silmap_finite(b)) return r;
    const glm::vec2 o(float(cell.x) + 0.5f, float(cell.y) + 0.5f);
    const glm::vec2 la = a - o, lb = b - o;
    const bool ina = detail::silmap_in_unit(la), inb = detail::silmap_in_unit(lb);
    if (ina || inb) {
        r.kase = SilmapCase::VertexInside;
        r.local = ina ? la : lb;
        r.weight = 2 - (ina ? 1 : 0) - (inb ? 1 : 0);  // border crossings of this edge
        return r;
    }
    glm::vec2 h0, h1;
    const bool d0 = detail::silmap_seg_intersect(la, lb, glm::vec2(0.f, 0.f), glm::vec2(1.f, 1.f), h0);
    const bool d1 = detail::silmap_seg_intersect(la, lb, glm::vec2(1.f, 0.f), glm::vec2(0.f, 1.f), h1);
    if (d0 && d1) {
        r.kase = SilmapCase::TwoIntersections;
        r.local = 0.5f * (h0 + h1);
    } else if (d0 || d1) {
        r.kase = SilmapCase::OneIntersection;
        r.local = d0 ? h0 : h1;
    } else {
        return r;
    }
    r.local = glm::clamp(r.local, glm::vec2(0.f), glm::vec2(1.f));
    if (!detail::silmap_finite(r.local)) r.local = glm::vec2(0.5f);  // overflow in the hit of a huge edge
    r.weight = 2;
    return r;
}

/// Conservative rasterization of an edge (ends a, b in texel space) into the dual grid: every cell
/// (i, j) in [0, W-1] x [0, H-1] whose closed square the segment touches (a supercover, widened by
/// `margin` texels, 0 <= margin < 1, 1e-4 by default, against rounding). Long edges are clipped to
/// the map first, so the work is bounded by the cells the map has along the edge.
/// `out` holds out_capacity glm::ivec2 elements; it needs one per touched cell (`needed`; 0 when the
/// edge misses the map, with Ok). Errors: NonFinite (a or b), InvalidArgument (size outside
/// 1 .. kSilmapMaxSize, margin outside [0, 1) or NaN, out null with out_capacity > 0).
/// BufferTooSmall: the first out_capacity cells are written (count).
inline SilmapRasterResult silmap_rasterize_edge(glm::vec2 a, glm::vec2 b, glm::uvec2 size, glm::ivec2* out,
                                                std::size_t out_capacity, float margin = 1e-4f) {
    SilmapRasterResult r;
    if (!detail::silmap_finite(a) || !detail::silmap_finite(b)) {
        r.status = Status::NonFinite;
        r.detail = !detail::silmap_finite(a) ? "a: NaN or Inf" : "b: NaN or Inf";
        return r;
    }
    if (!detail::silmap_size_ok(size) || !(margin >= 0.f) || !(margin < 1.f) || (out_capacity && !out)) {
        r.status = Status::InvalidArgument;
        r.detail = !detail::silmap_size_ok(size) ? "size: outside 1 .. kSilmapMaxSize"
                   : (!(margin >= 0.f) || !(margin < 1.f) ? "margin: outside [0, 1)" : "out: null with out_capacity > 0");
        return r;
    }
    // cells cover [0.5, W + 0.5] x [0.5, H + 0.5]
    const double m = margin;
    glm::dvec2 p0(a), p1(b);
    if (!detail::silmap_clip(p0, p1, glm::dvec2(0.5 - m), glm::dvec2(double(size.x) + 0.5 + m, double(size.y) + 0.5 + m))) {
        r.status = Status::Ok;
        return r;
    }
    if (p0.x > p1.x) std::swap(p0, p1);
    std::size_t n = 0;
    const int W = int(size.x), H = int(size.y);
    const int cx0 = std::max(0, int(std::floor(p0.x - 0.5 - m))), cx1 = std::min(W - 1, int(std::floor(p1.x - 0.5 + m)));
    for (int cx = cx0; cx <= cx1; ++cx) {
        // the part of the segment over the column [cx + 0.5 - m, cx + 1.5 + m]
        const double xa = std::max(p0.x, double(cx) + 0.5 - m), xb = std::min(p1.x, double(cx) + 1.5 + m);
        double ya, yb;
        if (p1.x - p0.x > 0.0) {
            const double s = (p1.y - p0.y) / (p1.x - p0.x);
            ya = p0.y + (xa - p0.x) * s;
            yb = p0.y + (xb - p0.x) * s;
        } else {
            ya = p0.y;
            yb = p1.y;
        }
        if (ya > yb) std::swap(ya, yb);
        // a near-vertical segment has a huge slope; rounding in xa/xb must not push y off the segment
        ya = std::max(ya, std::min(p0.y, p1.y));
        yb = std::min(yb, std::max(p0.y, p1.y));
        const int cy0 = std::max(0, int(std::floor(ya - 0.5 - m))), cy1 = std::min(H - 1, int(std::floor(yb - 0.5 + m)));
        for (int cy = cy0; cy <= cy1; ++cy) {
            if (n < out_capacity) out[n] = glm::ivec2(cx, cy);
            ++n;
        }
    }
    r.needed = n;
    r.count = std::min(n, out_capacity);
    r.status = n > out_capacity ? Status::BufferTooSmall : Status::Ok;
    r.detail = n > out_capacity ? "out_capacity: below needed (see needed)" : nullptr;
    return r;
}

/// Builds the silhouette map on the CPU: points (offsets, default (0.5, 0.5)) and edge weights per
/// texel, row-major (j * W + i). Edges are processed in order; a later point overwrites an earlier
/// one (the paper's rule). With `depth` (the window-depth map) a fragment whose edge depth at the
/// point is behind all four neighboring depth samples by more than `depth_bias` is occluded and
/// discarded (the paper's occlusion test); so is one with no sample behind the edge by more than
/// `depth_bias`: the edge casts no shadow there (a contact edge such as a box's bottom edge on the
/// floor), and its point would only bend the boundary at a depth crease, where the four depth tests
/// disagree for reasons other than a shadow. Does not allocate.
/// `edges` holds edge_count SilmapEdge elements; `depth` holds W * H floats, or is null (no
/// occlusion test); `points` holds points_capacity glm::vec2 and `weights` weights_capacity uint8
/// elements; each needs W * H (`needed`).
/// Errors: InvalidArgument (size outside 1 .. kSilmapMaxSize, edges null with edge_count > 0, a null
/// output), NonFinite (an edge or depth_bias not finite), BufferTooSmall (a capacity < W * H):
/// nothing is written (count 0).
inline SilmapBuildResult silmap_build(const SilmapEdge* edges, std::size_t edge_count, glm::uvec2 size, const float* depth,
                                      float depth_bias, glm::vec2* points, std::size_t points_capacity,
                                      std::uint8_t* weights, std::size_t weights_capacity) {
    SilmapBuildResult r;
    if ((edge_count && !edges) || !detail::silmap_size_ok(size) || !points || !weights) {
        r.status = Status::InvalidArgument;
        r.detail = edge_count && !edges ? "edges: null with edge_count > 0"
                   : (!detail::silmap_size_ok(size) ? "size: outside 1 .. kSilmapMaxSize" : (!points ? "points: null" : "weights: null"));
        return r;
    }
    r.needed = std::size_t(size.x) * std::size_t(size.y);
    if (!std::isfinite(depth_bias)) {
        r.status = Status::NonFinite;
        r.detail = "depth_bias: NaN or Inf";
        return r;
    }
    for (std::size_t e = 0; e < edge_count; ++e) {
        const SilmapEdge& E = edges[e];
        if (!detail::silmap_finite(E.a) || !detail::silmap_finite(E.b) || !std::isfinite(E.depth_a) ||
            !std::isfinite(E.depth_b)) {
            r.status = Status::NonFinite;
            r.detail = "edges: NaN or Inf";
            return r;
        }
    }
    if (points_capacity < r.needed || weights_capacity < r.needed) {
        r.status = Status::BufferTooSmall;
        r.detail = points_capacity < r.needed ? "points_capacity: below size.x * size.y (see needed)"
                                              : "weights_capacity: below size.x * size.y (see needed)";
        return r;
    }
    for (std::size_t k = 0; k < r.needed; ++k) {
        points[k] = glm::vec2(0.5f);
        weights[k] = 0;
    }
    const int W = int(size.x), H = int(size.y);
    glm::ivec2 cells[256];
    for (std::size_t e = 0; e < edge_count; ++e) {
        const SilmapEdge& E = edges[e];
        // clip to the map (plus a texel), then rasterize in pieces of at most 64 texels so a fixed
        // cell buffer suffices (no allocation); a cell shared by two pieces is written by the piece
        // that contains its point only
        glm::dvec2 c0(E.a), c1(E.b);
        if (!detail::silmap_clip(c0, c1, glm::dvec2(-0.5), glm::dvec2(double(W) + 1.5, double(H) + 1.5))) continue;
        const glm::vec2 ca(c0), cb(c1), cd = cb - ca;
        const float cdd = glm::dot(cd, cd);
        const int pieces = std::max(1, int(std::ceil(std::sqrt(double(cdd)) / 64.0)));
        const glm::vec2 ed = E.b - E.a;
        const float edd = glm::dot(ed, ed);
        for (int pc = 0; pc < pieces; ++pc) {
            const float t0 = float(pc) / float(pieces), t1 = float(pc + 1) / float(pieces);
            const glm::vec2 pa = ca + cd * t0, pb = pc + 1 == pieces ? cb : ca + cd * t1;
            // <= 64-texel pieces touch far fewer than 256 cells: count == needed
            const SilmapRasterResult rr = silmap_rasterize_edge(pa, pb, size, cells, 256);
            for (std::size_t c = 0; c < rr.count; ++c) {
                const glm::ivec2 cell = cells[c];
                const SilmapPoint sp = silmap_select_point(E.a, E.b, cell);
                if (sp.kase == SilmapCase::NoIntersection) continue;
                const glm::vec2 q = glm::vec2(float(cell.x) + 0.5f, float(cell.y) + 0.5f) + sp.local;
                if (pieces > 1) {
                    const float tc = cdd > 0.f ? glm::dot(q - ca, cd) / cdd : 0.f;
                    const bool owns = (tc >= t0 || pc == 0) && (tc < t1 || pc + 1 == pieces);
                    if (!owns) continue;
                }
                ++r.fragments;
                const std::size_t k = std::size_t(cell.y) * std::size_t(W) + std::size_t(cell.x);
                if (depth) {
                    const float tp = edd > 0.f ? glm::clamp(glm::dot(q - E.a, ed) / edd, 0.f, 1.f) : 0.f;
                    const float ze = E.depth_a + (E.depth_b - E.depth_a) * tp;
                    bool behind_all = true, casts = false;
                    for (int s = 0; s < 4; ++s) {
                        const int ix = std::min(cell.x + (s & 1), W - 1), iy = std::min(cell.y + (s >> 1), H - 1);
                        const float zs = depth[std::size_t(iy) * std::size_t(W) + std::size_t(ix)];
                        if (!(ze > zs + depth_bias)) behind_all = false;
                        if (zs > ze + depth_bias) casts = true;
                    }
                    if (behind_all || !casts) {
                        ++r.occluded;
                        continue;
                    }
                }
                points[k] = sp.local;
                weights[k] = std::uint8_t(std::min(255, int(weights[k]) + sp.weight));
                ++r.points_written;
            }
        }
    }
    for (std::size_t k = 0; k < r.needed; ++k)
        if (weights[k] > kSilmapFailureWeight) ++r.failure_texels;
    r.count = r.needed;
    r.status = Status::Ok;
    return r;
}

/// The reconstruction rule for one cell. `local`: lookup position in the cell ([0,1]^2 inside);
/// `center`: the cell's silhouette point; `right, top, left, bottom`: the neighbor cells'
/// points, each in its own cell's offsets (this function shifts them by +-1). corner_lit holds 4
/// bools: the depth test of corner c (0 (0,0), 1 (1,0), 2 (0,1), 3 (1,1)). The segments from the
/// center point to the four neighbor points split the cell into four sectors, one per corner; the
/// lookup takes its sector's depth test (Sen et al. 2003, sec. 3.3). If the four tests agree that
/// is the answer (non-silhouette pixel). Degenerate sectors (a neighbor point on the center point,
/// or the four segments not in counter-clockwise order right, top, left, bottom) use the nearest
/// corner (fallback = true, with Ok). Errors: InvalidArgument (corner_lit null), NonFinite (a point
/// or `local` not finite).
inline SilmapLookup silmap_reconstruct(glm::vec2 local, glm::vec2 center, glm::vec2 right, glm::vec2 top,
                                       glm::vec2 left, glm::vec2 bottom, const bool corner_lit[4]) {
    SilmapLookup r;
    if (!corner_lit) {
        r.status = Status::InvalidArgument;
        r.detail = "corner_lit: null";
        return r;
    }
    if (!detail::silmap_finite(local) || !detail::silmap_finite(center) || !detail::silmap_finite(right) ||
        !detail::silmap_finite(top) || !detail::silmap_finite(left) || !detail::silmap_finite(bottom)) {
        r.status = Status::NonFinite;
        r.detail = !detail::silmap_finite(local) ? "local: NaN or Inf" : "center, right, top, left, bottom: NaN or Inf";
        return r;
    }
    r.status = Status::Ok;
    const int nearest = (local.x >= 0.5f ? 1 : 0) + (local.y >= 0.5f ? 2 : 0);
    const bool all_lit = corner_lit[0] && corner_lit[1] && corner_lit[2] && corner_lit[3];
    const bool none_lit = !corner_lit[0] && !corner_lit[1] && !corner_lit[2] && !corner_lit[3];
    if (all_lit || none_lit) {
        r.lit = all_lit;
        r.corner = nearest;
        return r;
    }
    r.silhouette_pixel = true;
    const glm::vec2 nb[4] = {right + glm::vec2(1.f, 0.f), top + glm::vec2(0.f, 1.f), left - glm::vec2(1.f, 0.f),
                             bottom - glm::vec2(0.f, 1.f)};
    bool ok = true;
    float ang[4] = {0.f, 0.f, 0.f, 0.f};
    for (int k = 0; k < 4 && ok; ++k) {
        const glm::vec2 d = nb[k] - center;
        if (!detail::silmap_finite(d) || (d.x == 0.f && d.y == 0.f)) ok = false;
        else ang[k] = std::atan2(d.y, d.x);
    }
    const glm::vec2 ds = local - center;
    if (ok && (!detail::silmap_finite(ds) || (ds.x == 0.f && ds.y == 0.f))) ok = false;
    if (ok) {
        const float a_top = detail::silmap_wrap_angle(ang[1] - ang[0]),
                    a_left = detail::silmap_wrap_angle(ang[2] - ang[0]),
                    a_bottom = detail::silmap_wrap_angle(ang[3] - ang[0]);
        if (!(a_top > 0.f && a_top < a_left && a_left < a_bottom)) ok = false;
        if (ok) {
            const float as = detail::silmap_wrap_angle(std::atan2(ds.y, ds.x) - ang[0]);
            const int c = as < a_top ? 3 : (as < a_left ? 2 : (as < a_bottom ? 0 : 1));
            r.corner = c;
            r.lit = corner_lit[c];
            return r;
        }
    }
    r.fallback = true;
    r.corner = nearest;
    r.lit = corner_lit[nearest];
    return r;
}

/// Full lookup on CPU data: the shadow map `depth` (window depth), the silhouette map `points` and
/// `weights` (from silmap_build), W * H elements each, and a receiver at texel position `q` with
/// window depth `receiver_depth`; a depth sample passes when receiver_depth <= sample + bias.
/// Failure texels (weight > kSilmapFailureWeight), the border cells and lookups outside the map
/// give the plain (nearest-sample, clamped to the map) shadow-map result with fallback = true and
/// Ok. Errors: InvalidArgument (a null map, size outside 1 .. kSilmapMaxSize), NonFinite (q,
/// receiver_depth or bias not finite).
inline SilmapLookup silmap_lookup(const glm::vec2* points, const std::uint8_t* weights, const float* depth,
                                  glm::uvec2 size, glm::vec2 q, float receiver_depth, float bias) {
    SilmapLookup r;
    if (!points || !weights || !depth || !detail::silmap_size_ok(size)) {
        r.status = Status::InvalidArgument;
        r.detail = !points ? "points: null" : (!weights ? "weights: null" : (!depth ? "depth: null" : "size: outside 1 .. kSilmapMaxSize"));
        return r;
    }
    if (!detail::silmap_finite(q) || !std::isfinite(receiver_depth) || !std::isfinite(bias)) {
        r.status = Status::NonFinite;
        r.detail = !detail::silmap_finite(q) ? "q: NaN or Inf" : (!std::isfinite(receiver_depth) ? "receiver_depth: NaN or Inf" : "bias: NaN or Inf");
        return r;
    }
    r.status = Status::Ok;
    const int W = int(size.x), H = int(size.y);
    auto test = [&](int ix, int iy) {
        ix = std::min(std::max(ix, 0), W - 1);
        iy = std::min(std::max(iy, 0), H - 1);
        return receiver_depth <= depth[std::size_t(iy) * std::size_t(W) + std::size_t(ix)] + bias;
    };
    // clamped before any float -> int conversion (a lookup far outside the map is a border lookup)
    const glm::vec2 qc = glm::clamp(q, glm::vec2(-1.f), glm::vec2(float(W) + 1.f, float(H) + 1.f));
    const glm::vec2 s = qc - glm::vec2(0.5f);
    const glm::ivec2 cell(int(std::floor(s.x)), int(std::floor(s.y)));
    const glm::vec2 local = s - glm::vec2(cell);
    if (cell.x < 0 || cell.y < 0 || cell.x > W - 2 || cell.y > H - 2) {
        r.fallback = true;
        r.lit = test(int(std::floor(qc.x)), int(std::floor(qc.y)));
        return r;
    }
    const bool lit[4] = {test(cell.x, cell.y), test(cell.x + 1, cell.y), test(cell.x, cell.y + 1),
                         test(cell.x + 1, cell.y + 1)};
    auto at = [&](int ix, int iy) -> std::size_t {
        ix = std::min(std::max(ix, 0), W - 1);
        iy = std::min(std::max(iy, 0), H - 1);
        return std::size_t(iy) * std::size_t(W) + std::size_t(ix);
    };
    const std::size_t k = at(cell.x, cell.y);
    if (weights[k] > kSilmapFailureWeight) {
        const int nearest = (local.x >= 0.5f ? 1 : 0) + (local.y >= 0.5f ? 2 : 0);
        r.lit = lit[nearest];
        r.corner = nearest;
        r.fallback = true;
        r.silhouette_pixel = !(lit[0] == lit[1] && lit[1] == lit[2] && lit[2] == lit[3]);
        return r;
    }
    return silmap_reconstruct(local, points[k], points[at(cell.x + 1, cell.y)], points[at(cell.x, cell.y + 1)],
                              points[at(cell.x - 1, cell.y)], points[at(cell.x, cell.y - 1)], lit);
}

/// Nearest-sample (plain) shadow-map result at texel position q, for comparisons: `depth` holds
/// W * H floats; a lookup outside the map takes the nearest border sample. Errors: InvalidArgument
/// (depth null, size outside 1 .. kSilmapMaxSize), NonFinite (q, receiver_depth or bias).
inline SilmapPlainLookup silmap_plain_lookup(const float* depth, glm::uvec2 size, glm::vec2 q, float receiver_depth,
                                             float bias) {
    SilmapPlainLookup r;
    if (!depth || !detail::silmap_size_ok(size)) {
        r.status = Status::InvalidArgument;
        r.detail = !depth ? "depth: null" : "size: outside 1 .. kSilmapMaxSize";
        return r;
    }
    if (!detail::silmap_finite(q) || !std::isfinite(receiver_depth) || !std::isfinite(bias)) {
        r.status = Status::NonFinite;
        r.detail = !detail::silmap_finite(q) ? "q: NaN or Inf" : (!std::isfinite(receiver_depth) ? "receiver_depth: NaN or Inf" : "bias: NaN or Inf");
        return r;
    }
    const int ix = std::min(std::max(int(std::floor(std::max(std::min(q.x, 1e9f), -1e9f))), 0), int(size.x) - 1);
    const int iy = std::min(std::max(int(std::floor(std::max(std::min(q.y, 1e9f), -1e9f))), 0), int(size.y) - 1);
    r.lit = receiver_depth <= depth[std::size_t(iy) * size.x + std::size_t(ix)] + bias;
    r.status = Status::Ok;
    return r;
}

/// Bytes per texel of the GPU encoding used by glsl/silhouette_map.glsl: a 32-bit depth map plus an
/// RGBA8 silhouette map (RG = point offset in 1/255 steps, A = edge weight / 255). A plain shadow
/// map of equal memory has side round(side * sqrt(8 / 4)).
constexpr int kSilmapBytesPerTexel = 8;

}  // namespace shadowkit
