// shadowkit/silhouette.hpp - edge adjacency of an indexed triangle mesh, face facing for a
// homogeneous light position and the (possible) silhouette edge list with consistent winding.
// Plain data in and out, shared by shadow volumes, smoothies and penumbra wedges.
//
// Usage:
//   #include <shadowkit/silhouette.hpp>
//   // once per mesh (allocates; not for the hot path)
//   shadowkit::EdgeAdjacency adj = shadowkit::build_edge_adjacency(pos, vertex_count, idx, index_count);
//   if (adj.status != shadowkit::SilhouetteStatus::Ok) { /* reject mesh */ }
//   // per light / frame (no allocation: caller-owned buffers)
//   std::vector<uint8_t> lit(adj.face_count());
//   shadowkit::compute_facing(adj, pos, vertex_count, light /* vec4: w=1 point, w=0 direction */,
//                             lit.data(), lit.size());
//   std::vector<uint32_t> sil(2 * adj.max_silhouette_edges());
//   shadowkit::SilhouetteResult r = shadowkit::extract_silhouette(adj, lit.data(), lit.size(),
//                                                                 sil.data(), nullptr, sil.size() / 2);
//   // sil[2i], sil[2i+1] = edge (a, b) oriented as in its light-facing triangle, r.edge_count edges
//   // the same on several threads, with any job system's parallel_for(n, fn) (see "parallel
//   // silhouettes" below; identical output):
//   std::vector<shadowkit::SilhouetteResult> chunks(16);
//   r = shadowkit::extract_silhouette_parallel(adj, pos, vertex_count, light, lit.data(), lit.size(),
//                                              sil.data(), nullptr, sil.size() / 2, chunks.data(),
//                                              chunks.size(), parallel_for);
//
// Based on:
//   C. Everitt, M. J. Kilgard, "Practical and Robust Stenciled Shadow Volumes for Hardware-Accelerated
//   Rendering", NVIDIA 2002, section 3.2.2 (plane . L facing, possible silhouette edges ordered as in
//   the front-facing triangle).
//   P. Bergeron, "A General Version of Crow's Shadow Volumes", IEEE CG&A 1986 (open models).
//   The edge-count rule for open / non-manifold edges generalises the count trick of bgfx's
//   14-shadowvolumes example (side quads emitted |k| times).
//
// Definitions (used consistently by every function):
//   * Facing. For a kept face (A, B, C) and light L = (x, y, z, w), w >= 0:
//       d = dot(cross(B - A, C - A), L.xyz - w A)      (= w * (plane . L) for the plane through A)
//     evaluated in double from the float inputs. The face is LIT (front-facing to the light) iff
//     d > 0; d == 0 (light in the face's plane, or a zero-area face) counts as not lit. Every edge
//     reads the one bit of each of its faces, so the rule is consistent across faces: whatever the
//     rounding does to a face whose plane contains the light, both edges' quads and the caps see the
//     same bit and the shadow volume stays closed (see the proof below).
//   * Edge rule. For an edge {u, v} with incident faces f_i, let s_i = +1 if f_i traverses u -> v and
//     -1 if it traverses v -> u. The silhouette multiplicity is  k = sum over LIT faces of s_i.
//     The edge is emitted |k| times, oriented u -> v if k > 0, v -> u if k < 0 (i.e. as in the lit
//     triangle). Manifold edge (two faces, opposite winding): k = +-1 iff exactly one face is lit -
//     the usual possible-silhouette edge. Boundary edge (one face): emitted iff its face is lit
//     (flag Boundary). Non-manifold edge (> 2 faces, or two faces with the same winding): |k| may
//     be 0, 1, 2, ... (flag NonManifold).
//   * Proof of closure. The volume built from the lit faces (light cap), their extrusions to
//     infinity reversed (dark cap) and the side quads of this edge rule is the sum, as an oriented
//     2-chain, of one closed prism per lit face (face, three side quads, extruded face): interior
//     side quads cancel pairwise exactly when k counts them as above. So it is closed and
//     consistently oriented for ANY mesh (open, non-manifold, badly wound) and ANY facing bits.
//     The Everitt-Kilgard dark cap (unlit faces extruded) gives the same chain whenever
//     sum over ALL faces of s_i = 0 on every edge (closed, consistently wound meshes).
//
// Welding (AdjacencyOptions::weld_tolerance):
//   < 0 : no welding, vertices are identified by index only;
//   = 0 : (default) vertices with bit-identical positions (+0 == -0) are welded - UV / normal seams;
//   > 0 : greedy hashed-grid weld: in input order, a vertex snaps to the lowest-index representative
//         within Euclidean distance <= tolerance found in the 27 grid cells around it (cell size =
//         tolerance), else it becomes a representative. Not transitive: a chain of vertices spaced
//         just under the tolerance is not collapsed into one. Welded indices are representatives'
//         input indices, so the input vertex buffer can be used for rendering unchanged.
// Skipped and counted: degenerate faces (two equal welded indices, or cross(B - A, C - A) == 0
// exactly in double) and duplicate faces (same cyclic vertex sequence as an earlier face; the same
// vertices in opposite winding are kept: a two-sided triangle is a closed zero-volume pair).
// Skipping a zero-area sliver can open a closed mesh (its edges become boundary edges); the edge rule
// keeps the volume closed anyway. Rejected with a status: out-of-range indices, NaN/Inf positions
// (all vertex_count positions are checked), index count not a multiple of 3, null pointers with
// non-zero counts, more than 2^31 - 1 faces or 2^32 - 2 vertices. Empty meshes are Ok (no edges).
//
// MIT License. Copyright (c) shadowkit contributors.
#pragma once

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <tuple>
#include <unordered_map>
#include <vector>

namespace shadowkit {

enum class SilhouetteStatus {
    Ok,
    InvalidArgument,        ///< null pointer with a non-zero count, or size mismatch with the adjacency
    IndexCountNotMultipleOf3,
    IndexOutOfRange,        ///< an index >= vertex_count
    NonFinitePosition,      ///< a position with NaN or Inf
    InvalidTolerance,       ///< weld tolerance NaN or +Inf
    TooLarge,               ///< more than 2^31 - 1 faces or 2^32 - 2 vertices
    InvalidLight,           ///< light not finite, w < 0, or (0, 0, 0, 0)
    InvalidAdjacency,       ///< the adjacency passed in was not built successfully
    BufferTooSmall          ///< output truncated; the needed count is reported
};

/// Marks "no second face" in AdjacencyEdge::f1.
constexpr std::uint32_t kNoFace = 0xFFFFFFFFu;

/// Manifold or boundary edge. f0 traverses v0 -> v1; f1 traverses v1 -> v0, or kNoFace (boundary).
struct AdjacencyEdge {
    std::uint32_t v0, v1, f0, f1;
};

/// Non-manifold edge (v0 < v1): faces in EdgeAdjacency::nonmanifold_faces[first, first + count),
/// each stored as face | (1u << 31 if the face traverses v1 -> v0).
struct NonManifoldEdge {
    std::uint32_t v0, v1, first, count;
};

struct AdjacencyOptions {
    float weld_tolerance = 0.0f; ///< [Units: position units] see the header comment; < 0 disables
};

struct EdgeAdjacency {
    SilhouetteStatus status = SilhouetteStatus::Ok;
    std::uint32_t vertex_count = 0;                ///< input vertex count
    std::vector<std::uint32_t> remap;              ///< input vertex -> representative (input index)
    std::vector<std::uint32_t> faces;              ///< 3 welded indices per kept face, input winding
    std::vector<std::uint32_t> face_source;        ///< kept face -> input triangle index
    std::vector<AdjacencyEdge> edges;              ///< manifold and boundary edges
    std::vector<NonManifoldEdge> nonmanifold_edges;
    std::vector<std::uint32_t> nonmanifold_faces;
    std::size_t degenerate_triangles = 0;          ///< skipped
    std::size_t duplicate_triangles = 0;           ///< skipped
    std::size_t welded_vertices = 0;               ///< vertices mapped onto another representative
    std::size_t manifold_edges = 0;
    std::size_t boundary_edges = 0;

    std::size_t face_count() const { return faces.size() / 3; }
    /// True if every edge has exactly two faces with opposite winding (closed 2-manifold).
    bool closed() const { return boundary_edges == 0 && nonmanifold_edges.empty(); }
    /// Upper bound of extract_silhouette's edge count for any facing.
    std::size_t max_silhouette_edges() const {
        std::size_t n = edges.size();
        for (const NonManifoldEdge& e : nonmanifold_edges) n += e.count;
        return n;
    }
};

/// Silhouette edge flags (per emitted edge).
enum SilhouetteFlag : std::uint8_t { SilhouetteBoundary = 1u, SilhouetteNonManifold = 2u };

struct FacingResult {
    SilhouetteStatus status = SilhouetteStatus::Ok;
    std::size_t face_count = 0; ///< entries needed in the facing buffer
    std::size_t lit_faces = 0;
};

struct SilhouetteResult {
    SilhouetteStatus status = SilhouetteStatus::Ok;
    std::size_t edge_count = 0;   ///< edges needed (each is 2 indices); written = min(edge_count, capacity)
    std::size_t boundary_edges = 0;
    std::size_t nonmanifold_edges = 0;
};

namespace detail {

inline bool sil_finite(const glm::vec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

inline std::uint32_t sil_float_key(float f) {
    if (f == 0.0f) f = 0.0f; // -0 -> +0
    std::uint32_t u;
    std::memcpy(&u, &f, sizeof u);
    return u;
}

struct SilCell {
    std::int64_t x, y, z;
    bool operator==(const SilCell& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct SilCellHasher {
    std::size_t operator()(const SilCell& c) const {
        std::uint64_t h = static_cast<std::uint64_t>(c.x) * 0x9E3779B97F4A7C15ull;
        h ^= static_cast<std::uint64_t>(c.y) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
        h ^= static_cast<std::uint64_t>(c.z) * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
        return static_cast<std::size_t>(h ^ (h >> 29));
    }
};

inline std::int64_t sil_cell_coord(float p, double inv_cell) {
    double c = std::floor(static_cast<double>(p) * inv_cell);
    const double lim = 1.0e18;
    if (c > lim) c = lim;
    if (c < -lim) c = -lim;
    return static_cast<std::int64_t>(c);
}

inline glm::dvec3 sil_d(const glm::vec3& v) { return glm::dvec3(v.x, v.y, v.z); }

// cross(B - A, C - A) in double.
inline glm::dvec3 sil_normal(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
    const glm::dvec3 A = sil_d(a), e1 = sil_d(b) - A, e2 = sil_d(c) - A;
    return glm::dvec3(e1.y * e2.z - e1.z * e2.y, e1.z * e2.x - e1.x * e2.z, e1.x * e2.y - e1.y * e2.x);
}

inline void sil_weld(const glm::vec3* p, std::uint32_t n, float tol, std::vector<std::uint32_t>& remap) {
    remap.resize(n);
    for (std::uint32_t i = 0; i < n; ++i) remap[i] = i;
    if (tol < 0.0f || n == 0) return;
    if (tol == 0.0f) {
        std::vector<std::uint32_t> order(n);
        for (std::uint32_t i = 0; i < n; ++i) order[i] = i;
        auto key = [p](std::uint32_t i) {
            return std::make_tuple(sil_float_key(p[i].x), sil_float_key(p[i].y), sil_float_key(p[i].z), i);
        };
        std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return key(a) < key(b); });
        std::uint32_t rep = order[0];
        for (std::uint32_t k = 1; k < n; ++k) {
            const std::uint32_t i = order[k];
            const bool same = sil_float_key(p[i].x) == sil_float_key(p[rep].x) &&
                              sil_float_key(p[i].y) == sil_float_key(p[rep].y) &&
                              sil_float_key(p[i].z) == sil_float_key(p[rep].z);
            if (same) remap[i] = rep; // rep is the lowest index of its group (sorted by index last)
            else rep = i;
        }
        return;
    }
    const double inv = 1.0 / static_cast<double>(tol);
    const double tol2 = static_cast<double>(tol) * static_cast<double>(tol);
    std::unordered_map<SilCell, std::vector<std::uint32_t>, SilCellHasher> grid;
    grid.reserve(n);
    for (std::uint32_t i = 0; i < n; ++i) {
        const SilCell c{sil_cell_coord(p[i].x, inv), sil_cell_coord(p[i].y, inv), sil_cell_coord(p[i].z, inv)};
        std::uint32_t best = kNoFace;
        for (int dx = -1; dx <= 1; ++dx)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dz = -1; dz <= 1; ++dz) {
                    const auto it = grid.find(SilCell{c.x + dx, c.y + dy, c.z + dz});
                    if (it == grid.end()) continue;
                    for (std::uint32_t r : it->second) {
                        const glm::dvec3 d = sil_d(p[i]) - sil_d(p[r]);
                        if (r < best && d.x * d.x + d.y * d.y + d.z * d.z <= tol2) best = r;
                    }
                }
        if (best != kNoFace) remap[i] = best;
        else grid[c].push_back(i);
    }
}

} // namespace detail

/// Builds edge adjacency (allocates; call once per mesh / topology change).
/// positions: vertex_count glm::vec3; indices: index_count uint32 (triangle list).
inline EdgeAdjacency build_edge_adjacency(const glm::vec3* positions, std::size_t vertex_count,
                                          const std::uint32_t* indices, std::size_t index_count,
                                          const AdjacencyOptions& options = AdjacencyOptions()) {
    EdgeAdjacency adj;
    if ((vertex_count > 0 && positions == nullptr) || (index_count > 0 && indices == nullptr)) {
        adj.status = SilhouetteStatus::InvalidArgument;
        return adj;
    }
    if (index_count % 3 != 0) { adj.status = SilhouetteStatus::IndexCountNotMultipleOf3; return adj; }
    if (vertex_count > 0xFFFFFFFEull || index_count / 3 > 0x7FFFFFFFull) { adj.status = SilhouetteStatus::TooLarge; return adj; }
    if (std::isnan(options.weld_tolerance) || std::isinf(options.weld_tolerance)) {
        adj.status = SilhouetteStatus::InvalidTolerance;
        return adj;
    }
    for (std::size_t i = 0; i < vertex_count; ++i)
        if (!detail::sil_finite(positions[i])) { adj.status = SilhouetteStatus::NonFinitePosition; return adj; }
    for (std::size_t i = 0; i < index_count; ++i)
        if (indices[i] >= vertex_count) { adj.status = SilhouetteStatus::IndexOutOfRange; return adj; }

    const std::uint32_t n = static_cast<std::uint32_t>(vertex_count);
    adj.vertex_count = n;
    detail::sil_weld(positions, n, options.weld_tolerance, adj.remap);
    for (std::uint32_t i = 0; i < n; ++i) adj.welded_vertices += adj.remap[i] != i;

    // Faces: weld, drop degenerate, then duplicates (first occurrence in input order wins).
    const std::size_t tri_count = index_count / 3;
    struct Cand { std::uint32_t a, b, c, src; };
    std::vector<Cand> cand;
    cand.reserve(tri_count);
    for (std::size_t t = 0; t < tri_count; ++t) {
        const std::uint32_t a = adj.remap[indices[3 * t]], b = adj.remap[indices[3 * t + 1]], c = adj.remap[indices[3 * t + 2]];
        if (a == b || b == c || a == c) { ++adj.degenerate_triangles; continue; }
        const glm::dvec3 nrm = detail::sil_normal(positions[a], positions[b], positions[c]);
        if (nrm.x == 0.0 && nrm.y == 0.0 && nrm.z == 0.0) { ++adj.degenerate_triangles; continue; }
        // canonical rotation: smallest index first (keeps the cyclic order = winding)
        Cand k{a, b, c, static_cast<std::uint32_t>(t)};
        if (b < a && b < c) k = Cand{b, c, a, k.src};
        else if (c < a && c < b) k = Cand{c, a, b, k.src};
        cand.push_back(k);
    }
    std::vector<std::uint32_t> order(cand.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<std::uint32_t>(i);
    std::sort(order.begin(), order.end(), [&](std::uint32_t x, std::uint32_t y) {
        const Cand& p = cand[x];
        const Cand& q = cand[y];
        if (p.a != q.a) return p.a < q.a;
        if (p.b != q.b) return p.b < q.b;
        if (p.c != q.c) return p.c < q.c;
        return p.src < q.src;
    });
    std::vector<std::uint8_t> keep(cand.size(), 1);
    for (std::size_t i = 1; i < order.size(); ++i) {
        const Cand& p = cand[order[i - 1]];
        const Cand& q = cand[order[i]];
        if (p.a == q.a && p.b == q.b && p.c == q.c) { keep[order[i]] = 0; ++adj.duplicate_triangles; }
    }
    adj.faces.reserve(3 * cand.size());
    adj.face_source.reserve(cand.size());
    for (std::size_t i = 0; i < cand.size(); ++i) {
        if (!keep[i]) continue;
        const std::uint32_t t = cand[i].src;
        // original rotation (so faces[] reads like the input triangle)
        adj.faces.push_back(adj.remap[indices[3 * static_cast<std::size_t>(t)]]);
        adj.faces.push_back(adj.remap[indices[3 * static_cast<std::size_t>(t) + 1]]);
        adj.faces.push_back(adj.remap[indices[3 * static_cast<std::size_t>(t) + 2]]);
        adj.face_source.push_back(t);
    }

    // Half-edges sorted by undirected key.
    struct Half { std::uint64_t key; std::uint32_t face_dir; };
    const std::size_t fc = adj.face_source.size();
    std::vector<Half> half;
    half.reserve(3 * fc);
    for (std::size_t f = 0; f < fc; ++f)
        for (int j = 0; j < 3; ++j) {
            const std::uint32_t u = adj.faces[3 * f + static_cast<std::size_t>(j)];
            const std::uint32_t v = adj.faces[3 * f + static_cast<std::size_t>((j + 1) % 3)];
            const std::uint32_t lo = u < v ? u : v, hi = u < v ? v : u;
            half.push_back(Half{(static_cast<std::uint64_t>(lo) << 32) | hi,
                                static_cast<std::uint32_t>(f) | (u > v ? 0x80000000u : 0u)});
        }
    std::sort(half.begin(), half.end(), [](const Half& x, const Half& y) {
        return x.key != y.key ? x.key < y.key : x.face_dir < y.face_dir;
    });
    adj.edges.reserve(half.size() / 2 + 1);
    for (std::size_t i = 0; i < half.size();) {
        std::size_t j = i + 1;
        while (j < half.size() && half[j].key == half[i].key) ++j;
        const std::uint32_t lo = static_cast<std::uint32_t>(half[i].key >> 32);
        const std::uint32_t hi = static_cast<std::uint32_t>(half[i].key & 0xFFFFFFFFu);
        const std::size_t cnt = j - i;
        if (cnt == 1) {
            const bool rev = (half[i].face_dir & 0x80000000u) != 0;
            const std::uint32_t f = half[i].face_dir & 0x7FFFFFFFu;
            adj.edges.push_back(rev ? AdjacencyEdge{hi, lo, f, kNoFace} : AdjacencyEdge{lo, hi, f, kNoFace});
            ++adj.boundary_edges;
        } else if (cnt == 2 && ((half[i].face_dir ^ half[i + 1].face_dir) & 0x80000000u)) {
            // sorted by face_dir: the forward (lo -> hi) face comes first
            adj.edges.push_back(AdjacencyEdge{lo, hi, half[i].face_dir & 0x7FFFFFFFu, half[i + 1].face_dir & 0x7FFFFFFFu});
            ++adj.manifold_edges;
        } else {
            NonManifoldEdge e{lo, hi, static_cast<std::uint32_t>(adj.nonmanifold_faces.size()), static_cast<std::uint32_t>(cnt)};
            for (std::size_t k = i; k < j; ++k) adj.nonmanifold_faces.push_back(half[k].face_dir);
            adj.nonmanifold_edges.push_back(e);
        }
        i = j;
    }
    return adj;
}

/// Validates a homogeneous light position: finite, w >= 0, not (0, 0, 0, 0).
inline bool valid_light(const glm::vec4& L) {
    if (!(std::isfinite(L.x) && std::isfinite(L.y) && std::isfinite(L.z) && std::isfinite(L.w))) return false;
    if (L.w < 0.0f) return false;
    return !(L.w == 0.0f && L.x == 0.0f && L.y == 0.0f && L.z == 0.0f);
}

/// Facing of one triangle (the rule of the header comment): > 0 lit, <= 0 not lit. Double precision.
inline double face_light_distance(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec4& L) {
    const glm::dvec3 nrm = detail::sil_normal(a, b, c);
    const double w = L.w;
    const glm::dvec3 d(static_cast<double>(L.x) - w * a.x, static_cast<double>(L.y) - w * a.y, static_cast<double>(L.z) - w * a.z);
    return nrm.x * d.x + nrm.y * d.y + nrm.z * d.z;
}

namespace detail {

// facing[i] for kept faces [begin, end); returns the lit count
inline std::size_t sil_facing_range(const EdgeAdjacency& adj, const glm::vec3* positions, const glm::vec4& light,
                                    std::uint8_t* facing, std::size_t begin, std::size_t end) {
    const std::uint32_t* f = adj.faces.data();
    std::size_t lit_faces = 0;
    for (std::size_t i = begin; i < end; ++i) {
        const double d = face_light_distance(positions[f[3 * i]], positions[f[3 * i + 1]], positions[f[3 * i + 2]], light);
        const std::uint8_t lit = d > 0.0 ? 1u : 0u;
        facing[i] = lit;
        lit_faces += lit;
    }
    return lit_faces;
}

inline SilhouetteStatus sil_check_facing_args(const EdgeAdjacency& adj, const glm::vec3* positions,
                                              std::size_t vertex_count, const glm::vec4& light, const std::uint8_t* facing,
                                              std::size_t capacity) {
    if (adj.status != SilhouetteStatus::Ok) return SilhouetteStatus::InvalidAdjacency;
    if (vertex_count != adj.vertex_count || (vertex_count > 0 && positions == nullptr) || (capacity > 0 && facing == nullptr))
        return SilhouetteStatus::InvalidArgument;
    if (!valid_light(light)) return SilhouetteStatus::InvalidLight;
    if (capacity < adj.face_count()) return SilhouetteStatus::BufferTooSmall;
    return SilhouetteStatus::Ok;
}

// Silhouette of the manifold / boundary edges [begin, end) (and the non-manifold edges if
// `nonmanifold`) into out[0, capacity) edges; adds to r's counts, r.edge_count = edges needed.
inline void sil_extract_range(const EdgeAdjacency& adj, const std::uint8_t* facing, std::uint32_t* edge_indices,
                              std::uint8_t* edge_flags, std::size_t capacity, std::size_t begin, std::size_t end,
                              bool nonmanifold, SilhouetteResult& r) {
    std::size_t n = 0;
    auto emit = [&](std::uint32_t a, std::uint32_t b, std::uint8_t flags) {
        if (n < capacity) {
            edge_indices[2 * n] = a;
            edge_indices[2 * n + 1] = b;
            if (edge_flags) edge_flags[n] = flags;
        }
        ++n;
    };
    const AdjacencyEdge* e = adj.edges.data();
    for (std::size_t i = begin; i < end; ++i) {
        const AdjacencyEdge& E = e[i];
        const bool l0 = facing[E.f0] != 0;
        if (E.f1 == kNoFace) {
            if (l0) { emit(E.v0, E.v1, SilhouetteBoundary); ++r.boundary_edges; }
            continue;
        }
        const bool l1 = facing[E.f1] != 0;
        if (l0 != l1) {
            if (l0) emit(E.v0, E.v1, 0);
            else emit(E.v1, E.v0, 0);
        }
    }
    if (nonmanifold) {
        for (const NonManifoldEdge& E : adj.nonmanifold_edges) {
            long k = 0;
            for (std::uint32_t j = 0; j < E.count; ++j) {
                const std::uint32_t fd = adj.nonmanifold_faces[E.first + j];
                if (facing[fd & 0x7FFFFFFFu]) k += (fd & 0x80000000u) ? -1 : 1;
            }
            for (long m = 0; m < (k < 0 ? -k : k); ++m) {
                if (k > 0) emit(E.v0, E.v1, SilhouetteNonManifold);
                else emit(E.v1, E.v0, SilhouetteNonManifold);
                ++r.nonmanifold_edges;
            }
        }
    }
    r.edge_count += n;
}

// First item of chunk c when n items are split into `count` balanced chunks (no overflow).
inline std::size_t sil_chunk_begin(std::size_t n, std::size_t c, std::size_t count) {
    return (n / count) * c + std::min(c, n % count);
}

}  // namespace detail

/// Writes facing[f] = 1 if kept face f is lit by `light`, else 0. positions must be the buffer the
/// adjacency was built from (vertex_count checked). Needs capacity >= adj.face_count().
inline FacingResult compute_facing(const EdgeAdjacency& adj, const glm::vec3* positions, std::size_t vertex_count,
                                   const glm::vec4& light, std::uint8_t* facing, std::size_t capacity) {
    FacingResult r;
    r.face_count = adj.face_count();
    r.status = detail::sil_check_facing_args(adj, positions, vertex_count, light, facing, capacity);
    if (r.status != SilhouetteStatus::Ok) return r;
    r.lit_faces = detail::sil_facing_range(adj, positions, light, facing, 0, r.face_count);
    return r;
}

/// Single linear pass over the edges. Writes edge_count edges, 2 indices each, to edge_indices
/// (capacity in edges; edge_flags optional, one SilhouetteFlag mask per edge). Edges are oriented as
/// in the lit face and repeated |k| times (header comment). If capacity is too small, the first
/// `capacity` edges are written, status = BufferTooSmall and edge_count is the number needed.
inline SilhouetteResult extract_silhouette(const EdgeAdjacency& adj, const std::uint8_t* facing, std::size_t facing_count,
                                           std::uint32_t* edge_indices, std::uint8_t* edge_flags,
                                           std::size_t capacity) {
    SilhouetteResult r;
    if (adj.status != SilhouetteStatus::Ok) { r.status = SilhouetteStatus::InvalidAdjacency; return r; }
    const std::size_t fc = adj.face_count();
    if (facing_count != fc || (fc > 0 && facing == nullptr) || (capacity > 0 && edge_indices == nullptr)) {
        r.status = SilhouetteStatus::InvalidArgument;
        return r;
    }
    detail::sil_extract_range(adj, facing, edge_indices, edge_flags, capacity, 0, adj.edges.size(), true, r);
    if (r.edge_count > capacity) r.status = SilhouetteStatus::BufferTooSmall;
    return r;
}

// ------------------------------------------------------------------ parallel silhouettes (chunks)
// The same facing + silhouette split into `chunk_count` chunks that may run concurrently on any job
// system (shadowkit starts no threads and allocates nothing here):
//   1. compute_facing_chunk(c) for every chunk c           (faces split evenly; writes facing[])
//   2. barrier (a chunk's edges read the facing of any face)
//   3. extract_silhouette_chunk(c) for every chunk c       (edges split evenly; the last chunk also
//      takes the non-manifold edges). Chunk c writes its edges at edge silhouette_chunk_offset(c) of
//      a buffer with room for adj.max_silhouette_edges() edges (each manifold or boundary edge emits
//      at most one, so the chunks never overlap)
//   4. compact_silhouette_chunks: moves the chunks together (serial, O(silhouette))
// The result (edges, order, flags, counts) is identical to extract_silhouette's for any chunk_count.
// extract_silhouette_parallel does the four steps with a caller's parallel_for(n, fn), which must
// call fn(i) once for each i in [0, n) and return when all have finished.

/// Facing of the kept faces of chunk `chunk` of `chunk_count` (same rule and checks as
/// compute_facing; face_count / lit_faces are this chunk's). chunk_count >= 1, chunk < chunk_count.
inline FacingResult compute_facing_chunk(const EdgeAdjacency& adj, const glm::vec3* positions, std::size_t vertex_count,
                                         const glm::vec4& light, std::uint8_t* facing, std::size_t capacity,
                                         std::size_t chunk, std::size_t chunk_count) {
    FacingResult r;
    if (chunk_count == 0 || chunk >= chunk_count) { r.status = SilhouetteStatus::InvalidArgument; return r; }
    r.status = detail::sil_check_facing_args(adj, positions, vertex_count, light, facing, capacity);
    if (r.status != SilhouetteStatus::Ok) return r;
    const std::size_t fc = adj.face_count();
    const std::size_t b = detail::sil_chunk_begin(fc, chunk, chunk_count), e = detail::sil_chunk_begin(fc, chunk + 1, chunk_count);
    r.face_count = e - b;
    r.lit_faces = detail::sil_facing_range(adj, positions, light, facing, b, e);
    return r;
}

/// Edge offset at which chunk `chunk` of `chunk_count` writes its silhouette edges (0 for invalid
/// arguments).
inline std::size_t silhouette_chunk_offset(const EdgeAdjacency& adj, std::size_t chunk, std::size_t chunk_count) {
    if (chunk_count == 0 || chunk >= chunk_count) return 0;
    return detail::sil_chunk_begin(adj.edges.size(), chunk, chunk_count);
}

/// Silhouette edges of chunk `chunk` of `chunk_count`, written from edge silhouette_chunk_offset()
/// on. capacity (in edges) must be >= adj.max_silhouette_edges(), else BufferTooSmall and nothing
/// is written; facing must be complete (every chunk's compute_facing_chunk has finished).
inline SilhouetteResult extract_silhouette_chunk(const EdgeAdjacency& adj, const std::uint8_t* facing,
                                                 std::size_t facing_count, std::uint32_t* edge_indices,
                                                 std::uint8_t* edge_flags, std::size_t capacity, std::size_t chunk,
                                                 std::size_t chunk_count) {
    SilhouetteResult r;
    if (chunk_count == 0 || chunk >= chunk_count) { r.status = SilhouetteStatus::InvalidArgument; return r; }
    if (adj.status != SilhouetteStatus::Ok) { r.status = SilhouetteStatus::InvalidAdjacency; return r; }
    const std::size_t fc = adj.face_count();
    if (facing_count != fc || (fc > 0 && facing == nullptr) || (capacity > 0 && edge_indices == nullptr)) {
        r.status = SilhouetteStatus::InvalidArgument;
        return r;
    }
    if (capacity < adj.max_silhouette_edges()) { r.status = SilhouetteStatus::BufferTooSmall; return r; }
    const std::size_t ec = adj.edges.size();
    const std::size_t b = detail::sil_chunk_begin(ec, chunk, chunk_count), e = detail::sil_chunk_begin(ec, chunk + 1, chunk_count);
    // this chunk's room: up to the next chunk's offset, the last chunk up to the capacity
    const std::size_t room = chunk + 1 == chunk_count ? capacity - b : e - b;
    detail::sil_extract_range(adj, facing, edge_indices + 2 * b, edge_flags ? edge_flags + b : nullptr, room, b, e,
                              chunk + 1 == chunk_count, r);
    return r;
}

/// Moves the chunks' edges (and flags) together so that the buffer holds the silhouette exactly as
/// extract_silhouette writes it; returns the totals (first failing chunk status, if any).
inline SilhouetteResult compact_silhouette_chunks(const EdgeAdjacency& adj, const SilhouetteResult* chunks,
                                                  std::size_t chunk_count, std::uint32_t* edge_indices,
                                                  std::uint8_t* edge_flags, std::size_t capacity) {
    SilhouetteResult r;
    if (chunk_count == 0 || chunks == nullptr || (capacity > 0 && edge_indices == nullptr)) {
        r.status = SilhouetteStatus::InvalidArgument;
        return r;
    }
    for (std::size_t c = 0; c < chunk_count; ++c)
        if (chunks[c].status != SilhouetteStatus::Ok) { r.status = chunks[c].status; return r; }
    if (capacity < adj.max_silhouette_edges()) { r.status = SilhouetteStatus::BufferTooSmall; return r; }
    // a chunk cannot have more edges than its room (results that do are not extract_silhouette_chunk's)
    for (std::size_t c = 0; c < chunk_count; ++c) {
        const std::size_t off = silhouette_chunk_offset(adj, c, chunk_count);
        const std::size_t room = c + 1 == chunk_count ? capacity - off : silhouette_chunk_offset(adj, c + 1, chunk_count) - off;
        if (chunks[c].edge_count > room) { r.status = SilhouetteStatus::InvalidArgument; return r; }
    }
    std::size_t n = 0;
    for (std::size_t c = 0; c < chunk_count; ++c) {
        const std::size_t off = silhouette_chunk_offset(adj, c, chunk_count), k = chunks[c].edge_count;
        if (off != n && k > 0) {  // off >= n: moving down, ranges may overlap
            std::memmove(edge_indices + 2 * n, edge_indices + 2 * off, 2 * k * sizeof(std::uint32_t));
            if (edge_flags) std::memmove(edge_flags + n, edge_flags + off, k);
        }
        n += k;
        r.boundary_edges += chunks[c].boundary_edges;
        r.nonmanifold_edges += chunks[c].nonmanifold_edges;
    }
    r.edge_count = n;
    return r;
}

/// Facing + silhouette on a caller's job system: parallel_for(chunk_count, fn) (see above), with
/// caller-provided buffers: facing (adj.face_count()), edge_indices / edge_flags (capacity >=
/// adj.max_silhouette_edges() edges; flags optional) and chunk_results (chunk_count entries).
/// Same output as compute_facing + extract_silhouette.
template <class ParallelFor>
inline SilhouetteResult extract_silhouette_parallel(const EdgeAdjacency& adj, const glm::vec3* positions,
                                                    std::size_t vertex_count, const glm::vec4& light, std::uint8_t* facing,
                                                    std::size_t facing_capacity, std::uint32_t* edge_indices,
                                                    std::uint8_t* edge_flags, std::size_t capacity,
                                                    SilhouetteResult* chunk_results, std::size_t chunk_count,
                                                    ParallelFor&& parallel_for) {
    SilhouetteResult r;
    if (chunk_count == 0 || chunk_results == nullptr) { r.status = SilhouetteStatus::InvalidArgument; return r; }
    // validate once, so that no chunk can fail and the facing pass needs no per-chunk results
    r.status = detail::sil_check_facing_args(adj, positions, vertex_count, light, facing, facing_capacity);
    if (r.status != SilhouetteStatus::Ok) return r;
    if (capacity > 0 && edge_indices == nullptr) { r.status = SilhouetteStatus::InvalidArgument; return r; }
    if (capacity < adj.max_silhouette_edges()) { r.status = SilhouetteStatus::BufferTooSmall; return r; }
    const std::size_t fc = adj.face_count();
    parallel_for(chunk_count, [&](std::size_t c) {
        detail::sil_facing_range(adj, positions, light, facing, detail::sil_chunk_begin(fc, c, chunk_count),
                                 detail::sil_chunk_begin(fc, c + 1, chunk_count));
    });
    parallel_for(chunk_count, [&](std::size_t c) {
        chunk_results[c] = extract_silhouette_chunk(adj, facing, fc, edge_indices, edge_flags, capacity, c, chunk_count);
    });
    return compact_silhouette_chunks(adj, chunk_results, chunk_count, edge_indices, edge_flags, capacity);
}

/// Convenience (allocates): facing + silhouette into vectors. indices holds 2 per edge.
struct Silhouette {
    SilhouetteStatus status = SilhouetteStatus::Ok;
    std::vector<std::uint8_t> facing;
    std::vector<std::uint32_t> indices;
    std::vector<std::uint8_t> flags;
};

inline Silhouette extract_silhouette(const EdgeAdjacency& adj, const glm::vec3* positions, std::size_t vertex_count,
                                     const glm::vec4& light) {
    Silhouette s;
    s.facing.resize(adj.face_count());
    const FacingResult fr = compute_facing(adj, positions, vertex_count, light, s.facing.data(), s.facing.size());
    if (fr.status != SilhouetteStatus::Ok) { s.status = fr.status; s.facing.clear(); return s; }
    const std::size_t cap = adj.max_silhouette_edges();
    s.indices.resize(2 * cap);
    s.flags.resize(cap);
    const SilhouetteResult r = extract_silhouette(adj, s.facing.data(), s.facing.size(), s.indices.data(), s.flags.data(), cap);
    s.status = r.status;
    s.indices.resize(2 * (r.edge_count < cap ? r.edge_count : cap));
    s.flags.resize(r.edge_count < cap ? r.edge_count : cap);
    return s;
}

} // namespace shadowkit
