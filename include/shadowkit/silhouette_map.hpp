// shadowkit/silhouette_map.hpp - shadow silhouette maps: the CPU side of Sen, Cammarano & Hanrahan
// (2003). Projects silhouette edges into the shadow map's texel space, rasterizes them
// conservatively into the dual grid, picks one silhouette point per texel (the paper's four cases),
// keeps the default point (texel centre) elsewhere, and reconstructs the shadow boundary at a
// lookup: the piecewise-linear boundary through the neighbouring silhouette points splits the texel
// into four sectors and the depth sample of the lookup's sector decides. Texels crossed by two
// different silhouette edges (the paper's known failure) are detected and fall back to the plain
// shadow-map result. GPU side: glsl/silhouette_map.glsl (same rules, same encoding).
//
// Usage:
//   #include <shadowkit/silhouette_map.hpp>
//   namespace sk = shadowkit;
//   // silhouette edges for the light (e.g. silhouette.hpp: 2 indices per edge), light view-projection
//   std::vector<sk::SilmapEdge> e(edge_count);
//   sk::SilmapProjectResult pr = sk::silmap_project_edges(light_vp, sk::ClipDepth::NegativeOneToOne,
//       {2048, 2048}, pos, vertex_count, edges, edge_count, e.data(), e.size());
//   // CPU map (tests, software renderers); the GPU builds the same map with silhouette_map.glsl
//   std::vector<glm::vec2> pts(2048 * 2048); std::vector<uint8_t> cnt(2048 * 2048);
//   sk::silmap_build(e.data(), pr.written, {2048, 2048}, depth /*or nullptr*/, 1e-4f,
//                    pts.data(), cnt.data(), pts.size());
//   sk::SilmapLookup l = sk::silmap_lookup(pts.data(), cnt.data(), depth, {2048, 2048},
//                                          texel_pos, receiver_depth, bias);   // l.lit
//
// Based on:
//   P. Sen, M. Cammarano, P. Hanrahan, "Shadow Silhouette Maps", SIGGRAPH 2003 (sections 3-4:
//   dual grid, silhouette point cases, default point, reconstruction by the depth sample of the
//   sector, conservative edge rasterization, occluded silhouette fragments).
//   P. Sen, "Silhouette Maps", SIGGRAPH 2004 course "Real-Time Shadowing Techniques" notes
//   (point cases 1-4 by the two diagonals; multiple edges in one texel as the known failure).
//
// Conventions (used by every function):
//   * Texel space: q = uv * size, uv = window coordinates of the light's projection in [0,1].
//     Depth sample (i, j) of a W x H shadow map sits at (i + 0.5, j + 0.5).
//   * The silhouette map has W x H texels on the dual grid: texel (i, j) is the cell
//     [i + 0.5, i + 1.5] x [j + 0.5, j + 1.5], whose corners are depth samples (i, j), (i+1, j),
//     (i, j+1), (i+1, j+1). Cells with i = W-1 or j = H-1 lack corners: lookups there, and in the
//     half-texel border strip, give the plain shadow-map result.
//   * A silhouette point is stored as its offset inside its cell, in [0,1]^2; the default point is
//     the cell centre (0.5, 0.5). With every point at the default, the reconstruction equals the
//     nearest-sample shadow map (each sector is the region nearest its corner).
//   * Edge weight per texel (the failure detector) = the number of times the silhouette crosses the
//     texel's border: an edge adds 2 minus the number of its endpoints inside the (closed) cell. One
//     silhouette chain through a texel gives 2 however many of its vertices lie inside; two chains
//     (two edges passing near each other, a T-junction) give 3 or more. Weights saturate at 255. A
//     texel with weight > kSilmapFailureWeight (2) holds two different silhouette curves: the
//     paper's known failure. (A closed loop entirely inside one texel gives 0 and is missed.)
//   * Depth: window depth in [0, 1] (any monotonic depth works if the depth map uses the same).
//
// MIT License. Copyright (c) shadowkit contributors.
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace shadowkit {

#ifndef SHADOWKIT_CLIP_DEPTH_DEFINED
#define SHADOWKIT_CLIP_DEPTH_DEFINED
/// Clip-space depth range of the projection: OpenGL [-1,1] or D3D/Vulkan/glClipControl [0,1].
enum class ClipDepth { NegativeOneToOne, ZeroToOne };
#endif

enum class SilmapStatus {
    Ok,
    InvalidArgument,   ///< null pointer with a non-zero count, zero map size, size > 2^15
    IndexOutOfRange,   ///< an edge index >= vertex_count (edge skipped, counted)
    NonFinite,         ///< NaN/Inf input (the offending item is skipped)
    BufferTooSmall     ///< output truncated; the needed count is reported
};

/// The paper's silhouette point cases (course notes, "Silhouette Point Algorithm").
enum class SilmapCase {
    VertexInside,      ///< case 1: an endpoint lies in the cell: the endpoint itself
    OneIntersection,   ///< case 2: the edge crosses one diagonal: that intersection
    TwoIntersections,  ///< case 3: the edge crosses both diagonals: the midpoint of the two
    NoIntersection     ///< case 4: conservative fragment the edge misses: nothing written
};

/// A silhouette edge in texel space with window depths at its ends.
struct SilmapEdge {
    glm::vec2 a{0.f}, b{0.f};
    float depth_a = 0.f, depth_b = 0.f;
};

struct SilmapProjectResult {
    SilmapStatus status = SilmapStatus::Ok;
    std::size_t needed = 0;   ///< edges produced (written = min(needed, capacity))
    std::size_t written = 0;
    std::size_t skipped = 0;  ///< behind the light (w <= 0 at both ends), bad index or NaN
};

struct SilmapPoint {
    SilmapCase kase = SilmapCase::NoIntersection;
    glm::vec2 local{0.5f};    ///< offset in the cell, [0,1]^2 (valid unless NoIntersection)
    int weight = 0;           ///< edge weight this edge adds to the cell (see the header)
};

struct SilmapBuildResult {
    SilmapStatus status = SilmapStatus::Ok;
    std::size_t needed = 0;            ///< texels needed in the output buffers (W * H)
    std::size_t fragments = 0;         ///< rasterized fragments with a silhouette point (cases 1-3)
    std::size_t points_written = 0;    ///< cases 1-3 (overwrites included)
    std::size_t occluded = 0;          ///< fragments discarded by the depth tests (occluded or casting no shadow)
    std::size_t failure_texels = 0;    ///< texels with weight > kSilmapFailureWeight
    std::size_t skipped_edges = 0;     ///< NaN edges
};

struct SilmapLookup {
    bool lit = true;
    bool silhouette_pixel = false;  ///< the four depth tests disagree (the silhouette map decides)
    bool fallback = false;          ///< failure texel, border or degenerate sectors: plain result used
    int corner = 0;                 ///< deciding depth sample: 0 (i,j), 1 (i+1,j), 2 (i,j+1), 3 (i+1,j+1)
};

/// Texels with an accumulated edge weight above this hold two different silhouette edges.
constexpr int kSilmapFailureWeight = 2;
/// Largest supported map side (texel coordinates stay exact in float).
constexpr std::uint32_t kSilmapMaxSize = 32768u;

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

}  // namespace detail

/// Projects the silhouette edges (2 indices per edge into positions) with the light's
/// view-projection into texel space. Edges are clipped against w > 1e-6 * max(|w|) first (an edge
/// with both ends behind the light is skipped). Caller buffer of `capacity` edges.
inline SilmapProjectResult silmap_project_edges(const glm::mat4& light_view_proj, ClipDepth clip_depth, glm::uvec2 size,
                                                const glm::vec3* positions, std::size_t vertex_count,
                                                const std::uint32_t* edges, std::size_t edge_count, SilmapEdge* out,
                                                std::size_t capacity) {
    SilmapProjectResult r;
    if ((edge_count && !edges) || (vertex_count && !positions) || (capacity && !out) || size.x == 0 || size.y == 0 ||
        size.x > kSilmapMaxSize || size.y > kSilmapMaxSize) {
        r.status = SilmapStatus::InvalidArgument;
        return r;
    }
    const glm::dvec2 sz(size.x, size.y);
    for (std::size_t e = 0; e < edge_count; ++e) {
        const std::uint32_t ia = edges[2 * e], ib = edges[2 * e + 1];
        if (ia >= vertex_count || ib >= vertex_count) {
            ++r.skipped;
            if (r.status == SilmapStatus::Ok) r.status = SilmapStatus::IndexOutOfRange;
            continue;
        }
        glm::dvec4 ca = glm::dmat4(light_view_proj) * glm::dvec4(glm::dvec3(positions[ia]), 1.0);
        glm::dvec4 cb = glm::dmat4(light_view_proj) * glm::dvec4(glm::dvec3(positions[ib]), 1.0);
        bool finite = true;
        for (int k = 0; k < 4; ++k) finite = finite && std::isfinite(ca[k]) && std::isfinite(cb[k]);
        if (!finite) {
            ++r.skipped;
            if (r.status == SilmapStatus::Ok) r.status = SilmapStatus::NonFinite;
            continue;
        }
        const double wmin = 1e-6 * std::max(std::abs(ca.w), std::abs(cb.w));
        if (ca.w <= wmin && cb.w <= wmin) {
            ++r.skipped;
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
        auto to_texel = [&](const glm::dvec4& c, glm::vec2& q, float& depth) {
            const double nz = c.z / c.w;
            q = glm::vec2(float((c.x / c.w * 0.5 + 0.5) * sz.x), float((c.y / c.w * 0.5 + 0.5) * sz.y));
            depth = float(clip_depth == ClipDepth::ZeroToOne ? nz : nz * 0.5 + 0.5);
        };
        SilmapEdge se;
        to_texel(ca, se.a, se.depth_a);
        to_texel(cb, se.b, se.depth_b);
        if (!detail::silmap_finite(se.a) || !detail::silmap_finite(se.b) || !std::isfinite(se.depth_a) ||
            !std::isfinite(se.depth_b)) {
            ++r.skipped;
            continue;
        }
        if (r.needed < capacity) out[r.needed] = se;
        ++r.needed;
    }
    r.written = std::min(r.needed, capacity);
    if (r.needed > capacity) r.status = SilmapStatus::BufferTooSmall;
    return r;
}

/// The paper's silhouette point for one edge and one cell (cell (i, j) = dual-grid texel, see the
/// header). Case 1: an endpoint in the cell (closed square; a first, then b); else the edge is
/// tested against the cell's two diagonals: one hit (case 2) or the midpoint of two (case 3);
/// no hit is case 4. Weight: 2 minus the endpoints inside (border crossings).
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
    r.weight = 2;
    return r;
}

/// Conservative rasterization of an edge into the dual grid: every cell (i, j) in
/// [0, W-1] x [0, H-1] whose closed square the segment touches (a supercover, widened by
/// `margin` texels, 1e-4 by default, against rounding). Writes cells to `out` (capacity entries)
/// and returns how many there are (all of them are counted even when truncated). Long edges are
/// clipped to the map first, so the work is bounded by the cells the map has along the edge.
inline std::size_t silmap_rasterize_edge(glm::vec2 a, glm::vec2 b, glm::uvec2 size, glm::ivec2* out,
                                         std::size_t capacity, float margin = 1e-4f) {
    if (!detail::silmap_finite(a) || !detail::silmap_finite(b) || size.x == 0 || size.y == 0 ||
        size.x > kSilmapMaxSize || size.y > kSilmapMaxSize || !(margin >= 0.f) || !(margin < 1.f))
        return 0;
    if (capacity && !out) capacity = 0;
    // cells cover [0.5, W + 0.5] x [0.5, H + 0.5]
    const double m = margin;
    glm::dvec2 p0(a), p1(b);
    if (!detail::silmap_clip(p0, p1, glm::dvec2(0.5 - m), glm::dvec2(double(size.x) + 0.5 + m, double(size.y) + 0.5 + m)))
        return 0;
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
            if (n < capacity) out[n] = glm::ivec2(cx, cy);
            ++n;
        }
    }
    return n;
}

/// Builds the silhouette map on the CPU: points (offsets, default (0.5, 0.5)) and edge weights per
/// texel, W * H each, row-major (j * W + i). Edges are processed in order; a later point
/// overwrites an earlier one (the paper's rule). With `depth` (the W x H window-depth map,
/// row-major) a fragment whose edge depth at the point is behind all four neighbouring depth
/// samples by more than `depth_bias` is occluded and discarded (the paper's occlusion test); so is
/// one with no sample behind the edge by more than `depth_bias`: the edge casts no shadow there (a
/// contact edge such as a box's bottom edge on the floor), and its point would only bend the
/// boundary at a depth crease, where the four depth tests disagree for reasons other than a shadow.
inline SilmapBuildResult silmap_build(const SilmapEdge* edges, std::size_t edge_count, glm::uvec2 size, const float* depth,
                                      float depth_bias, glm::vec2* points, std::uint8_t* weights, std::size_t capacity) {
    SilmapBuildResult r;
    if ((edge_count && !edges) || size.x == 0 || size.y == 0 || size.x > kSilmapMaxSize || size.y > kSilmapMaxSize) {
        r.status = SilmapStatus::InvalidArgument;
        return r;
    }
    r.needed = std::size_t(size.x) * std::size_t(size.y);
    if (capacity < r.needed || !points || !weights) {
        r.status = SilmapStatus::BufferTooSmall;
        return r;
    }
    if (!std::isfinite(depth_bias)) depth_bias = 0.f;
    for (std::size_t k = 0; k < r.needed; ++k) {
        points[k] = glm::vec2(0.5f);
        weights[k] = 0;
    }
    const int W = int(size.x), H = int(size.y);
    glm::ivec2 cells[256];
    for (std::size_t e = 0; e < edge_count; ++e) {
        const SilmapEdge& E = edges[e];
        if (!detail::silmap_finite(E.a) || !detail::silmap_finite(E.b) || !std::isfinite(E.depth_a) ||
            !std::isfinite(E.depth_b)) {
            ++r.skipped_edges;
            r.status = SilmapStatus::NonFinite;
            continue;
        }
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
            const std::size_t nc = silmap_rasterize_edge(pa, pb, size, cells, 256);
            if (nc > 256) r.status = SilmapStatus::BufferTooSmall;  // cannot happen for <= 64-texel pieces
            for (std::size_t c = 0; c < std::min<std::size_t>(nc, 256); ++c) {
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
    return r;
}

/// The reconstruction rule for one cell. `local`: lookup position in the cell ([0,1]^2 inside);
/// `center`: the cell's silhouette point; `right, top, left, bottom`: the neighbour cells'
/// points, each in its own cell's offsets (this function shifts them by +-1). corner_lit[c]: the
/// depth test of corner c (0 (0,0), 1 (1,0), 2 (0,1), 3 (1,1)). The segments from the centre point
/// to the four neighbour points split the cell into four sectors, one per corner; the lookup takes
/// its sector's depth test (Sen et al. 2003, sec. 3.3). If the four tests agree that is the answer
/// (non-silhouette pixel). Degenerate sectors (a neighbour point on the centre point, or the four
/// segments not in counter-clockwise order right, top, left, bottom) use the nearest corner.
inline SilmapLookup silmap_reconstruct(glm::vec2 local, glm::vec2 center, glm::vec2 right, glm::vec2 top,
                                       glm::vec2 left, glm::vec2 bottom, const bool corner_lit[4]) {
    SilmapLookup r;
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
    bool ok = detail::silmap_finite(local) && detail::silmap_finite(center);
    float ang[4] = {0.f, 0.f, 0.f, 0.f};
    for (int k = 0; k < 4 && ok; ++k) {
        const glm::vec2 d = nb[k] - center;
        if (!detail::silmap_finite(d) || (d.x == 0.f && d.y == 0.f)) ok = false;
        else ang[k] = std::atan2(d.y, d.x);
    }
    const glm::vec2 ds = local - center;
    if (ok && ds.x == 0.f && ds.y == 0.f) ok = false;
    if (ok) {
        const float aT = detail::silmap_wrap_angle(ang[1] - ang[0]), aL = detail::silmap_wrap_angle(ang[2] - ang[0]),
                    aB = detail::silmap_wrap_angle(ang[3] - ang[0]);
        if (!(aT > 0.f && aT < aL && aL < aB)) ok = false;
        if (ok) {
            const float as = detail::silmap_wrap_angle(std::atan2(ds.y, ds.x) - ang[0]);
            const int c = as < aT ? 3 : (as < aL ? 2 : (as < aB ? 0 : 1));
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

/// Full lookup on CPU data: the shadow map (window depth, W x H row-major), the silhouette map
/// (points and weights from silmap_build) and a receiver at texel position `q` with window depth
/// `receiver_depth`; a depth sample passes when receiver_depth <= sample + bias. Failure texels
/// (weight > kSilmapFailureWeight), the border cells and non-finite input give the plain
/// (nearest-sample) shadow-map result with fallback = true.
inline SilmapLookup silmap_lookup(const glm::vec2* points, const std::uint8_t* weights, const float* depth,
                                  glm::uvec2 size, glm::vec2 q, float receiver_depth, float bias) {
    SilmapLookup r;
    if (!points || !weights || !depth || size.x == 0 || size.y == 0 || size.x > kSilmapMaxSize ||
        size.y > kSilmapMaxSize || !detail::silmap_finite(q) || !std::isfinite(receiver_depth)) {
        r.fallback = true;
        return r;
    }
    if (!std::isfinite(bias)) bias = 0.f;
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

/// Nearest-sample (plain) shadow-map result at texel position q, for comparisons.
inline bool silmap_plain_lookup(const float* depth, glm::uvec2 size, glm::vec2 q, float receiver_depth, float bias) {
    if (!depth || size.x == 0 || size.y == 0 || !detail::silmap_finite(q) || !std::isfinite(receiver_depth)) return true;
    const int ix = std::min(std::max(int(std::floor(std::max(std::min(q.x, 1e9f), -1e9f))), 0), int(size.x) - 1);
    const int iy = std::min(std::max(int(std::floor(std::max(std::min(q.y, 1e9f), -1e9f))), 0), int(size.y) - 1);
    return receiver_depth <= depth[std::size_t(iy) * size.x + std::size_t(ix)] + (std::isfinite(bias) ? bias : 0.f);
}

/// Bytes per texel of the GPU encoding used by glsl/silhouette_map.glsl: a 32-bit depth map plus an
/// RGBA8 silhouette map (RG = point offset in 1/255 steps, A = edge weight / 255). A plain shadow
/// map of equal memory has side round(side * sqrt(8 / 4)).
constexpr int kSilmapBytesPerTexel = 8;

}  // namespace shadowkit
