// shadowkit/silhouette.hpp - edge adjacency of a triangle mesh, exact face facing for a light, silhouette edges.
// Plain data in and out (edge adjacency, facing bits, silhouette edges oriented as in their lit face),
// shared by shadow volumes, smoothies and penumbra wedges.
//
// Usage:
//   #include <shadowkit/silhouette.hpp>
//   // once per mesh (allocates; not for the hot path)
//   shadowkit::SilhouetteAdjacency adj = shadowkit::silhouette_build_adjacency(pos, vertex_count, idx, index_count);
//   if (adj.status != shadowkit::Status::Ok) { /* reject the mesh */ }
//   // per light / frame (no allocation: caller-owned buffers, sized once)
//   std::vector<std::uint8_t> lit(adj.face_count());
//   std::vector<std::uint32_t> sil(shadowkit::silhouette_indices_capacity(adj));
//   shadowkit::silhouette_compute_facing(adj, pos, vertex_count, light_position, lit.data(), lit.size());
//   shadowkit::SilhouetteResult r = shadowkit::silhouette_extract(adj, lit.data(), lit.size(), sil.data(),
//                                                                 sil.size(), nullptr, 0);
//   // sil[0, r.count): edges (sil[2i], sil[2i+1]), each oriented as in its lit triangle
//   // rigid meshes (positions fixed): cache the face planes once (allocates), then per frame the
//   // fast path, bit for bit the same facing and edges (3.3-9x faster a frame; docs/benchmarks.md):
//   shadowkit::SilhouettePlanes planes = shadowkit::silhouette_build_planes(adj, pos, vertex_count);
//   shadowkit::silhouette_compute_facing_planes(adj, planes, light_position, lit.data(), lit.size());
//   r = shadowkit::silhouette_extract_planes(adj, planes, lit.data(), lit.size(), sil.data(), sil.size(), nullptr, 0);
//   // or straight to shadow_volume.hpp's side quads, 6 indices per edge, without the edge buffer:
//   std::vector<std::uint32_t> quads(3 * sil.size());
//   r = shadowkit::silhouette_extract_planes_side_quads(adj, planes, lit.data(), lit.size(), quads.data(), quads.size());
//   // the same on several threads, with any job system's parallel_for(n, fn) (see "parallel
//   // silhouettes" below; identical output):
//   std::vector<shadowkit::SilhouetteResult> chunks(16);
//   r = shadowkit::silhouette_extract_parallel(adj, pos, vertex_count, light_position, lit.data(), lit.size(),
//                                              sil.data(), sil.size(), nullptr, 0, chunks.data(),
//                                              chunks.size(), parallel_for);
//
// Conventions:
// Lights: a light is its homogeneous position `light_position` = (x, y, z, w), as OpenGL's
// GL_POSITION and Everitt & Kilgard use it. w > 0: a point or spot light at xyz / w. w = 0: a
// directional light at infinity in direction xyz, the direction *toward* the light (its rays travel
// along -xyz). w < 0, (0, 0, 0, 0) and NaN/Inf are rejected with Status::InvalidLight.
//   * Units: positions and light_position in the same (object) space, any unit. Winding: triangles are
//     counter-clockwise seen from their front (lit) side.
//   * Buffers: every capacity counts elements of its pointer's type (uint8 facing bits, uint32
//     indices: 2 per silhouette edge); results say `count` (elements written, a valid prefix) and
//     `needed` (elements the whole output needs; count == needed when Ok). The adjacency and planes
//     builds allocate; nothing else does, except silhouette_compute (says so). The chunked and
//     parallel extractions use their whole buffers as scratch (elements past `count`, never past a
//     capacity); the serial ones write exactly [0, count).
//   * Results: a non-Ok result's `detail` names the offending input and the rule ("indices: >=
//     vertex_count"), a static string; nullptr when Ok.
//   * Facing (exact). For a kept face (A, B, C) and light_position L = (l, w):
//       d = dot(cross(B - A, C - A), l - w A)      (= w * (plane . L) for the plane through A)
//     with real arithmetic on the float inputs: the sign of d is computed EXACTLY (an orient3d-style
//     predicate: a double-precision filter with a proven error bound, then an exact integer fallback;
//     Shewchuk 1997). The face is LIT (front-facing to the light) iff d > 0. d == 0 - the light in
//     the face's plane (a point light on the face's plane, a directional light parallel to it) or a
//     zero-area face - is NOT lit. Consequences: a point light exactly on a mesh vertex V makes every
//     face incident to V (and to any vertex at the same position) exactly d = 0, so unlit; V is then
//     on no lit face, hence on no silhouette edge and in no LitOnly cap, and shadow_volume.hpp never
//     extrudes it (its extrusion V w - l would be (0, 0, 0, 0)). The facing bit never depends on the
//     rounding, compiler or FMA contraction (the filter's bound holds with or without contraction;
//     -ffast-math reassociation is outside IEEE 754 and voids it). The cached-plane path
//     (silhouette_build_planes) gives the same bits: a float filter with its own proven bound in
//     front of the same exact evaluation ("cached face planes" below).
//   * Edge rule. For an edge {u, v} with incident faces f_i, let s_i = +1 if f_i traverses u -> v and
//     -1 if it traverses v -> u. The silhouette multiplicity is  k = sum over LIT faces of s_i.
//     The edge is emitted |k| times, oriented u -> v if k > 0, v -> u if k < 0 (i.e. as in the lit
//     triangle). Manifold edge (two faces, opposite winding): k = +-1 iff exactly one face is lit -
//     the usual possible-silhouette edge. Boundary edge (one face): emitted iff its face is lit
//     (flag SilhouetteBoundary). Non-manifold edge (> 2 faces, or two faces with the same winding):
//     |k| may be 0, 1, 2, ... (flag SilhouetteNonManifold).
//   * Proof of closure. The volume built from the lit faces (light cap), their extrusions to
//     infinity reversed (dark cap) and the side quads of this edge rule is the sum, as an oriented
//     2-chain, of one closed prism per lit face (face, three side quads, extruded face): interior
//     side quads cancel pairwise exactly when k counts them as above. So it is closed and
//     consistently oriented for ANY mesh (open, non-manifold, badly wound) and ANY facing bits.
//     The Everitt-Kilgard dark cap (unlit faces extruded) gives the same chain whenever
//     sum over ALL faces of s_i = 0 on every edge (closed, consistently wound meshes).
//   * Two-sided rule (silhouette_extract_two_sided, for OPEN meshes). A lit-faces-only volume counts,
//     at a point X, the lit faces crossed by the segment from X to the light; a ray that enters an open
//     mesh through a hole and leaves through back faces crosses none, so X is lit although the mesh
//     blocks it. Two-sided treats every face as an occluder: an unlit face counts as its reverse
//     (which faces the light), k = sum over lit faces of s_i - sum over unlit faces of s_i, emitted as
//     above. The volume (with shadow_volume.hpp's VolumeCapMode::TwoSided caps) is the sum of one closed
//     prism per face, so it is closed for any mesh, and its count at X is the number of faces the
//     segment crosses: X is inside iff the mesh blocks the segment, the test a ray tracer does. A
//     manifold silhouette edge is then emitted twice (once per side), a boundary edge always once, an
//     edge between two unlit faces not at all. Use it when the adjacency has boundary or non-manifold
//     edges (!adj.closed()); on a closed mesh it draws twice the quads for the same shadow.
//   * Welding (SilhouetteAdjacencyOptions::weld_tolerance):
//     < 0 : no welding, vertices are identified by index only;
//     = 0 : (default) vertices with bit-identical positions (+0 == -0) are welded - UV / normal seams;
//     > 0 : greedy weld: in input order, a vertex snaps to the lowest-index representative within
//           Euclidean distance <= tolerance (squared distance evaluated in double), else it becomes a
//           representative. Not transitive: a chain of vertices spaced just under the tolerance is not
//           collapsed into one. Hashed grid with power-of-two cells of 2-4 tolerances, cell
//           coordinates exact in double for any tolerance and magnitude, so it stays O(n) (at most a
//           bounded number of candidates per vertex; `weld_checks` counts them). Welded indices are
//           representatives' input indices, so the input vertex buffer renders unchanged.
//   * Skipped and counted: degenerate faces (two equal welded indices, or an exactly zero cross
//     product, decided exactly like the facing) and duplicate faces (the same cyclic vertex sequence
//     as an earlier face; the same vertices in opposite winding are kept: a two-sided triangle is a
//     closed zero-volume pair). Skipping a zero-area sliver can open a closed mesh (its edges become
//     boundary edges); the edge rule keeps the volume closed anyway.
//   * Statuses: null pointers with non-zero counts, an index count not a multiple of 3, more than
//     2^31 - 1 faces or 2^32 - 2 vertices, a facing buffer or adjacency that does not match, an
//     adjacency whose build failed: InvalidArgument. NaN/Inf positions (all vertex_count of them are
//     checked; per frame, the faces' positions) or tolerance: NonFinite. Indices >= vertex_count:
//     IndexOutOfRange. A bad light_position: InvalidLight. Short buffers: BufferTooSmall with
//     `needed`. Empty meshes are Ok (no faces, no edges).
//
// Based on:
//   C. Everitt, M. J. Kilgard, "Practical and Robust Stenciled Shadow Volumes for Hardware-Accelerated
//   Rendering", NVIDIA 2002, section 3.2.2 (plane . L facing, possible silhouette edges ordered as in
//   the front-facing triangle).
//   J. R. Shewchuk, "Adaptive Precision Floating-Point Arithmetic and Fast Robust Geometric
//   Predicates", Discrete & Computational Geometry 18(3), 1997 (floating-point filter + exact
//   fallback for the sign of a determinant; here the fallback is integer arithmetic, immune to FMA
//   contraction).
//   P. Bergeron, "A General Version of Crow's Shadow Volumes", IEEE CG&A 1986 (open models).
//   The edge-count rule for open / non-manifold edges generalizes the count trick of bgfx's
//   14-shadowvolumes example (side quads emitted |k| times).
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

// SIMD for the cached-plane facing (silhouette_compute_facing_planes): SSE2 on x86 (baseline of
// x86-64), NEON on AArch64, else portable scalar code; define SHADOWKIT_NO_SIMD to force the scalar
// path. Every path gives the same (exact) facing bits.
#if !defined(SHADOWKIT_NO_SIMD) && (defined(__SSE2__) || defined(_M_X64) || (defined(_M_IX86_FP) && _M_IX86_FP >= 2))
#include <emmintrin.h>
#define SHADOWKIT_SIL_SSE2 1
#elif !defined(SHADOWKIT_NO_SIMD) && defined(__ARM_NEON) && defined(__aarch64__)
#include <arm_neon.h>
#define SHADOWKIT_SIL_NEON 1
#endif

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

/// Marks "no second face" in SilhouetteEdge::f1.
constexpr std::uint32_t kSilhouetteNoFace = 0xFFFFFFFFu;

/// Manifold or boundary edge. f0 traverses v0 -> v1; f1 traverses v1 -> v0, or kSilhouetteNoFace (boundary).
struct SilhouetteEdge {
    std::uint32_t v0, v1, f0, f1;
};

/// Non-manifold edge (v0 < v1): faces in SilhouetteAdjacency::nonmanifold_faces[first, first + count),
/// each stored as face | (1u << 31 if the face traverses v1 -> v0).
struct SilhouetteNonManifoldEdge {
    std::uint32_t v0, v1, first, count;
};

/// Options of silhouette_build_adjacency.
struct SilhouetteAdjacencyOptions {
    float weld_tolerance = 0.0f; ///< [position units] < 0: no weld, 0: bit-identical, > 0: greedy (header comment)
};

/// Edge adjacency of a mesh (silhouette_build_adjacency). `status` first; the rest is valid when Ok.
struct SilhouetteAdjacency {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    std::uint32_t vertex_count = 0;                ///< input vertex count
    std::vector<std::uint32_t> remap;              ///< input vertex -> representative (input index)
    std::vector<std::uint32_t> faces;              ///< 3 welded indices per kept face, input winding
    std::vector<std::uint32_t> face_source;        ///< kept face -> input triangle index
    std::vector<SilhouetteEdge> edges;             ///< manifold and boundary edges
    std::vector<SilhouetteNonManifoldEdge> nonmanifold_edges;
    std::vector<std::uint32_t> nonmanifold_faces;
    std::size_t degenerate_triangles = 0;          ///< skipped
    std::size_t duplicate_triangles = 0;           ///< skipped
    std::size_t welded_vertices = 0;               ///< vertices mapped onto another representative
    std::size_t manifold_edges = 0;
    std::size_t boundary_edges = 0;
    std::size_t weld_checks = 0;                   ///< candidate pairs the weld compared (diagnostic: O(n))

    /// Kept faces: the element count of a facing buffer.
    std::size_t face_count() const { return faces.size() / 3; }
    /// True if every edge has exactly two faces with opposite winding (closed 2-manifold).
    bool closed() const { return boundary_edges == 0 && nonmanifold_edges.empty(); }
    /// Most silhouette EDGES any facing can give (each is 2 uint32 elements: see silhouette_indices_capacity).
    std::size_t max_silhouette_edges() const {
        std::size_t n = edges.size();
        for (const SilhouetteNonManifoldEdge& e : nonmanifold_edges) n += e.count;
        return n;
    }
};

/// Silhouette edge flags (one uint8 per emitted edge).
enum SilhouetteFlag : std::uint8_t { SilhouetteBoundary = 1u, SilhouetteNonManifold = 2u };

/// Facing of a mesh's kept faces (silhouette_compute_facing).
struct SilhouetteFacing {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    std::size_t count = 0;     ///< uint8 facing elements written (a chunk: this chunk's faces)
    std::size_t needed = 0;    ///< uint8 elements the facing buffer needs: adj.face_count()
    std::size_t lit_faces = 0; ///< faces with d > 0 among those written
    /// Cached-plane functions only (0 elsewhere): runs of the exact predicate for the faces the float
    /// filter left undecided, at most one per plane class in a row (SilhouettePlanes::plane_class).
    std::size_t exact_evaluations = 0;
};

/// Silhouette edges (silhouette_extract and the chunked functions).
struct SilhouetteResult {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    std::size_t count = 0;             ///< uint32 elements written to edge_indices (2 per edge, whole edges; side quads: 6)
    std::size_t needed = 0;            ///< uint32 elements the whole silhouette needs (2 per edge; side quads: 6)
    std::size_t boundary_edges = 0;    ///< emitted edges flagged SilhouetteBoundary (whole silhouette)
    std::size_t nonmanifold_edges = 0; ///< emitted edges flagged SilhouetteNonManifold (whole silhouette)
};

/// Exact facing of one triangle (silhouette_face_orientation).
struct SilhouetteOrientation {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    int sign = 0;     ///< sign of d (header comment): +1, 0 or -1, exact
    bool lit = false; ///< sign > 0
};

namespace detail {

inline bool sil_finite(const glm::vec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

inline std::uint32_t sil_float_key(float f) {
    if (f == 0.0f) f = 0.0f; // -0 -> +0
    std::uint32_t u;
    std::memcpy(&u, &f, sizeof u);
    return u;
}

// ------------------------------------------------------------------ exact sign of d
// d = det(A, B, l) + det(B, C, l) + det(C, A, l) - w det(A, B, C)  (expanding cross(B - A, C - A) =
// A x B + B x C + C x A and (A x B + B x C + C x A) . A = det(A, B, C)): 18 products of three floats
// and 6 of four. Each float is m 2^e (integer |m| < 2^24, e in [-149, 104]), so each product is an
// integer < 2^96 times 2^E with E in [-596, 416]: positive and negative products are added exactly
// into two fixed-point integers (bit 0 = 2^-596, 35 limbs of 32 bits) and compared. Integer
// arithmetic only: no rounding, no dependence on FMA contraction or the FPU mode.
constexpr int kSilLimbs = 36;

struct SilFloat {
    std::uint32_t m; // |mantissa|, 0 for +-0
    int e;           // value = +-m 2^e
    bool neg;
};

inline SilFloat sil_decompose(float f) {
    std::uint32_t u;
    std::memcpy(&u, &f, sizeof u);
    const std::uint32_t ex = (u >> 23) & 0xFFu, fr = u & 0x7FFFFFu;
    SilFloat r;
    r.neg = (u >> 31) != 0;
    if (ex == 0) {
        r.m = fr;
        r.e = -149;
    } else {
        r.m = fr | 0x800000u;
        r.e = static_cast<int>(ex) - 150;
    }
    return r;
}

struct SilExactSum {
    std::uint32_t pos[kSilLimbs] = {};
    std::uint32_t neg[kSilLimbs] = {};

    // adds (negative ? -1 : 1) * prod(f[i].m) * 2^(sum f[i].e) for k = 3 or 4 factors
    void add(const SilFloat* const* f, int k, bool negative) {
        std::uint32_t v[4] = {f[0]->m, 0u, 0u, 0u};
        int e = f[0]->e;
        bool s = negative != f[0]->neg;
        for (int i = 1; i < k; ++i) {
            std::uint64_t carry = 0;
            for (int j = 0; j < 3; ++j) {
                const std::uint64_t t = static_cast<std::uint64_t>(v[j]) * f[i]->m + carry;
                v[j] = static_cast<std::uint32_t>(t);
                carry = t >> 32;
            }
            e += f[i]->e;
            s = s != f[i]->neg;
        }
        if ((v[0] | v[1] | v[2]) == 0u) return;
        const int off = e + 596; // >= 0: every factor's e >= -149
        const int limb = off / 32, bit = off % 32;
        std::uint32_t w[4];
        if (bit == 0) {
            w[0] = v[0]; w[1] = v[1]; w[2] = v[2]; w[3] = 0u;
        } else {
            w[0] = v[0] << bit;
            w[1] = (v[1] << bit) | (v[0] >> (32 - bit));
            w[2] = (v[2] << bit) | (v[1] >> (32 - bit));
            w[3] = v[2] >> (32 - bit);
        }
        std::uint32_t* acc = s ? neg : pos;
        std::uint64_t carry = 0;
        for (int j = limb; j < kSilLimbs && (j < limb + 4 || carry != 0); ++j) {
            const std::uint64_t t = static_cast<std::uint64_t>(acc[j]) + (j < limb + 4 ? w[j - limb] : 0u) + carry;
            acc[j] = static_cast<std::uint32_t>(t);
            carry = t >> 32;
        }
    }
    int sign() const {
        for (int j = kSilLimbs - 1; j >= 0; --j) {
            if (pos[j] != neg[j]) return pos[j] > neg[j] ? 1 : -1;
        }
        return 0;
    }
    // pos - neg as a double with relative error < 2^-50 (0 exactly when the sum is 0): the top 96
    // bits of the magnitude (dropped bits < 2^-64 of it), two double roundings, an exact scaling.
    double to_double() const {
        const int sg = sign();
        if (sg == 0) return 0.0;
        const std::uint32_t* big = sg > 0 ? pos : neg;
        const std::uint32_t* small = sg > 0 ? neg : pos;
        std::uint32_t mag[kSilLimbs];
        std::int64_t borrow = 0;
        for (int j = 0; j < kSilLimbs; ++j) {
            std::int64_t t = static_cast<std::int64_t>(big[j]) - static_cast<std::int64_t>(small[j]) - borrow;
            borrow = t < 0 ? 1 : 0;
            if (t < 0) t += std::int64_t(1) << 32;
            mag[j] = static_cast<std::uint32_t>(t);
        }
        int top = kSilLimbs - 1;
        while (mag[top] == 0u) --top;
        double v = 0.0;
        for (int j = top; j >= 0 && j > top - 3; --j) v = v * 4294967296.0 + static_cast<double>(mag[j]);
        const int low = top - 2 > 0 ? top - 2 : 0;
        v = std::ldexp(v, 32 * low - 596);
        return sg > 0 ? v : -v;
    }
};

// adds sign * det(P, Q, R) (times *extra if given): the 6 permutation products
inline void sil_exact_add_det(SilExactSum& s, const SilFloat* P, const SilFloat* Q, const SilFloat* R,
                              const SilFloat* extra, bool negate) {
    static const int perm[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {2, 1, 0}, {1, 0, 2}};
    for (int p = 0; p < 6; ++p) {
        const SilFloat* f[4] = {&P[perm[p][0]], &Q[perm[p][1]], &R[perm[p][2]], extra};
        s.add(f, extra ? 4 : 3, negate != (p >= 3));
    }
}

/// Exact sign of d (header comment) by integer arithmetic; inputs must be finite. The fallback of
/// every facing filter (the per-frame one below and any cached-plane filter built on top).
inline int sil_face_sign_exact(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec4& L) {
    const SilFloat A[3] = {sil_decompose(a.x), sil_decompose(a.y), sil_decompose(a.z)};
    const SilFloat B[3] = {sil_decompose(b.x), sil_decompose(b.y), sil_decompose(b.z)};
    const SilFloat C[3] = {sil_decompose(c.x), sil_decompose(c.y), sil_decompose(c.z)};
    const SilFloat l[3] = {sil_decompose(L.x), sil_decompose(L.y), sil_decompose(L.z)};
    const SilFloat w = sil_decompose(L.w);
    SilExactSum s;
    sil_exact_add_det(s, A, B, l, nullptr, false);
    sil_exact_add_det(s, B, C, l, nullptr, false);
    sil_exact_add_det(s, C, A, l, nullptr, false);
    if (w.m != 0u) sil_exact_add_det(s, A, B, C, &w, true);
    return s.sign();
}

/// Returned by sil_face_sign for NaN/Inf inputs (only ever seen in the fallback branch).
constexpr int kSilNonFinite = 2;

// Filter bound: d computed below as sum over i of (e1_j e2_k - e1_k e2_j) q_i with e1 = B - A,
// e2 = C - A, q = l - w A (w A is exact: float * float fits a double). Every term carries at most 8
// rounding factors (1 + delta), |delta| <= u = 2^-53 (e1, e2, q: one each; products, difference,
// product, two sums), with or without FMA contraction (a fused operation only drops factors). So
// |d_computed - d| <= gamma_8 P with P = sum_i (|e1_j e2_k| + |e1_k e2_j|) |q_i| of the exact values
// (Higham, Accuracy and Stability of Numerical Algorithms, 2nd ed., 3.1), and the computed P is
// >= P (1 - u)^8, so 10 u times the computed P (itself rounded once more) bounds the error:
// 10 u (1 - u)^9 >= gamma_8 = 8 u / (1 - 8 u). No underflow: every nonzero intermediate is a multiple of
// 2^-447 (all floats are multiples of 2^-149); no overflow: |d| < 4e155.
constexpr double kSilFilterBound = 10.0 * 1.1102230246251565e-16; // 10 * 2^-53

// Error-free transformations (Knuth's TwoSum; the product by FMA where the hardware has it, else
// Dekker's split, exact without underflow: every value here is a multiple of 2^-447, far above it).
// Additions and multiplications are separate statements, so FMA contraction cannot fuse them in a
// way that changes a result (a fused a * b + c only arises from an expression that has both).
inline void sil_two_sum(double a, double b, double& s, double& err) {
    s = a + b;
    const double bv = s - a;
    const double av = s - bv;
    err = (a - av) + (b - bv);
}
inline void sil_two_product(double a, double b, double& p, double& err) {
    p = a * b;
#if defined(__FMA__) || defined(__aarch64__) || defined(_M_ARM64)
    err = std::fma(a, b, -p);
#else
    const double split = 134217729.0;  // 2^27 + 1
    const double ca = split * a, cb = split * b;
    const double ah = ca - (ca - a), bh = cb - (cb - b);
    const double al = a - ah, bl = b - bh;
    err = ((ah * bh - p) + ah * bl + al * bh) + al * bl;
#endif
}

/// The adaptive stage between the filter and the integer path: d = n . q exactly in double
/// expansions when e1 = B - A, e2 = C - A, q = l - w A, the six products of n = e1 x e2 and n itself
/// are exact doubles - each difference and product is checked error-free, which holds unless the
/// coordinates span extreme ranges - then each n_i q_i as two doubles (an exact product) and their
/// sum as a non-overlapping expansion (Shewchuk 1997, Grow-Expansion): the sign of its largest
/// component. False: something was not exact (the integer path decides). About 150 flops: a light
/// in the faces' plane (d == 0 for every face) costs a few times the filter, not the integer path.
/// Finite inputs only.
inline bool sil_face_sign_expansion(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec4& L, int& sign) {
    const double A[3] = {a.x, a.y, a.z}, B[3] = {b.x, b.y, b.z}, C[3] = {c.x, c.y, c.z}, l[3] = {L.x, L.y, L.z};
    const double w = L.w;
    double e1[3], e2[3], q[3], err = 0.0, bad = 0.0;
    for (int i = 0; i < 3; ++i) {
        sil_two_sum(B[i], -A[i], e1[i], err);
        bad += std::fabs(err);
        sil_two_sum(C[i], -A[i], e2[i], err);
        bad += std::fabs(err);
        sil_two_sum(l[i], -(w * A[i]), q[i], err);  // w * A[i]: float * float, exact in double
        bad += std::fabs(err);
    }
    if (bad != 0.0) return false;
    static const int J[3] = {1, 2, 0}, K[3] = {2, 0, 1};
    // e1 and e2 with at most 24 significant bits each (they round-trip through float, the usual case):
    // their products have at most 48 and are exact, no error term needed
    bool narrow = true;
    for (int i = 0; i < 3; ++i)
        narrow = narrow && double(static_cast<float>(e1[i])) == e1[i] && double(static_cast<float>(e2[i])) == e2[i];
    double n[3];
    for (int i = 0; i < 3; ++i) {
        double p1 = e1[J[i]] * e2[K[i]], p2 = e1[K[i]] * e2[J[i]], err1 = 0.0, err2 = 0.0;
        if (!narrow) {
            sil_two_product(e1[J[i]], e2[K[i]], p1, err1);
            sil_two_product(e1[K[i]], e2[J[i]], p2, err2);
        }
        sil_two_sum(p1, -p2, n[i], err);
        if (err1 != 0.0 || err2 != 0.0 || err != 0.0) return false;
    }
    double e[6];  // the expansion of n . q, non-overlapping, increasing magnitude, no zeros
    int len = 0;
    for (int i = 0; i < 3; ++i) {
        double parts[2];
        sil_two_product(n[i], q[i], parts[1], parts[0]);
        for (double part : parts) {  // Grow-Expansion with zero elimination: e + part, exactly
            double Q = part;
            int out = 0;
            for (int k = 0; k < len; ++k) {
                double sum = 0.0;
                sil_two_sum(Q, e[k], sum, err);
                Q = sum;
                if (err != 0.0) e[out++] = err;
            }
            if (Q != 0.0) e[out++] = Q;
            len = out;
        }
    }
    sign = len == 0 ? 0 : (e[len - 1] > 0.0 ? 1 : -1);
    return true;
}

/// Exact sign of d (header comment) for finite inputs: a double-precision evaluation whose proven
/// error bound decides almost every face, then the exact expansion stage (sil_face_sign_expansion),
/// the exact integer evaluation for the rest; kSilNonFinite for NaN/Inf inputs.
inline int sil_face_sign(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec4& L) {
    const double ax = a.x, ay = a.y, az = a.z, lw = L.w;
    const double e1x = static_cast<double>(b.x) - ax, e1y = static_cast<double>(b.y) - ay, e1z = static_cast<double>(b.z) - az;
    const double e2x = static_cast<double>(c.x) - ax, e2y = static_cast<double>(c.y) - ay, e2z = static_cast<double>(c.z) - az;
    const double qx = static_cast<double>(L.x) - lw * ax, qy = static_cast<double>(L.y) - lw * ay,
                 qz = static_cast<double>(L.z) - lw * az;
    const double p1 = e1y * e2z, p2 = e1z * e2y, p3 = e1z * e2x, p4 = e1x * e2z, p5 = e1x * e2y, p6 = e1y * e2x;
    const double d = (p1 - p2) * qx + (p3 - p4) * qy + (p5 - p6) * qz;
    const double perm = (std::fabs(p1) + std::fabs(p2)) * std::fabs(qx) + (std::fabs(p3) + std::fabs(p4)) * std::fabs(qy) +
                        (std::fabs(p5) + std::fabs(p6)) * std::fabs(qz);
    const double bound = kSilFilterBound * perm;
    if (d > bound) return 1;
    if (d < -bound) return -1;
    if (perm == 0.0) return 0; // every term exactly 0 (nothing underflows): d == 0
    // NaN/Inf inputs always land here (perm or bound is NaN/Inf, so both tests above are false)
    if (!(sil_finite(a) && sil_finite(b) && sil_finite(c) && std::isfinite(L.x) && std::isfinite(L.y) &&
          std::isfinite(L.z) && std::isfinite(L.w)))
        return kSilNonFinite;
    int sign = 0;
    if (sil_face_sign_expansion(a, b, c, L, sign)) return sign;
    return sil_face_sign_exact(a, b, c, L);
}

/// d (header comment) as a double with relative error <= 2^-30 (exactly 0 iff d == 0) for finite
/// inputs: the filter's value when its bound is below 2^-31 of it, else the exact sum rounded.
inline double sil_face_value(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec4& L) {
    const double ax = a.x, ay = a.y, az = a.z, lw = L.w;
    const double e1x = static_cast<double>(b.x) - ax, e1y = static_cast<double>(b.y) - ay, e1z = static_cast<double>(b.z) - az;
    const double e2x = static_cast<double>(c.x) - ax, e2y = static_cast<double>(c.y) - ay, e2z = static_cast<double>(c.z) - az;
    const double qx = static_cast<double>(L.x) - lw * ax, qy = static_cast<double>(L.y) - lw * ay,
                 qz = static_cast<double>(L.z) - lw * az;
    const double p1 = e1y * e2z, p2 = e1z * e2y, p3 = e1z * e2x, p4 = e1x * e2z, p5 = e1x * e2y, p6 = e1y * e2x;
    const double d = (p1 - p2) * qx + (p3 - p4) * qy + (p5 - p6) * qz;
    const double perm = (std::fabs(p1) + std::fabs(p2)) * std::fabs(qx) + (std::fabs(p3) + std::fabs(p4)) * std::fabs(qy) +
                        (std::fabs(p5) + std::fabs(p6)) * std::fabs(qz);
    if (perm == 0.0) return 0.0;                                   // every term exactly 0
    if (kSilFilterBound * perm <= 0x1p-31 * std::fabs(d)) return d; // |error| <= 2^-31 |d|
    const SilFloat A[3] = {sil_decompose(a.x), sil_decompose(a.y), sil_decompose(a.z)};
    const SilFloat B[3] = {sil_decompose(b.x), sil_decompose(b.y), sil_decompose(b.z)};
    const SilFloat C[3] = {sil_decompose(c.x), sil_decompose(c.y), sil_decompose(c.z)};
    const SilFloat l[3] = {sil_decompose(L.x), sil_decompose(L.y), sil_decompose(L.z)};
    const SilFloat w = sil_decompose(L.w);
    SilExactSum s;
    sil_exact_add_det(s, A, B, l, nullptr, false);
    sil_exact_add_det(s, B, C, l, nullptr, false);
    sil_exact_add_det(s, C, A, l, nullptr, false);
    if (w.m != 0u) sil_exact_add_det(s, A, B, C, &w, true);
    return s.to_double();
}

// Zero-area face: cross(B - A, C - A) == 0 exactly (d == 0 for every light): the three axis
// directions as directional lights give its three components.
inline bool sil_zero_area(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
    return sil_face_sign(a, b, c, glm::vec4(1.0f, 0.0f, 0.0f, 0.0f)) == 0 &&
           sil_face_sign(a, b, c, glm::vec4(0.0f, 1.0f, 0.0f, 0.0f)) == 0 &&
           sil_face_sign(a, b, c, glm::vec4(0.0f, 0.0f, 1.0f, 0.0f)) == 0;
}

// ------------------------------------------------------------------ weld
// Cell coordinates are doubles holding exact integers: x = p / s with s a power of two is exact, and
// floor() of it too. For |x| >= 2^52 a neighbor cell x +- 1 is not needed: another float within the
// tolerance of p on that axis is p itself (p's float spacing is >= 2^28 tolerances there).
struct SilCell {
    double x, y, z;
    bool operator==(const SilCell& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct SilCellHasher {
    std::size_t operator()(const SilCell& c) const {
        std::uint64_t bx, by, bz;
        std::memcpy(&bx, &c.x, sizeof bx);
        std::memcpy(&by, &c.y, sizeof by);
        std::memcpy(&bz, &c.z, sizeof bz);
        std::uint64_t h = bx * 0x9E3779B97F4A7C15ull;
        h ^= by * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
        h ^= bz * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
        return static_cast<std::size_t>(h ^ (h >> 29));
    }
};

inline double sil_cell_coord(float p, double inv_cell) {
    return std::floor(static_cast<double>(p) * inv_cell) + 0.0; // exact; + 0.0 turns -0 into +0
}

inline glm::dvec3 sil_d(const glm::vec3& v) { return glm::dvec3(v.x, v.y, v.z); }

// returns the number of candidate pairs compared
inline std::size_t sil_weld(const glm::vec3* p, std::uint32_t n, float tol, std::vector<std::uint32_t>& remap) {
    remap.resize(n);
    for (std::uint32_t i = 0; i < n; ++i) remap[i] = i;
    if (tol < 0.0f || n == 0) return 0;
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
        return n - 1;
    }
    // cell side s = 2^(k+1) in [2 tol, 4 tol): a pair whose squared distance in double is <= tol^2
    // is closer than s on every axis (rounding moves it by a relative 2^-52 at most), so it lies in
    // neighboring cells; representatives in one cell are > tol apart, so a cell holds few of them.
    int k = 0;
    (void)std::frexp(static_cast<double>(tol), &k); // tol = f 2^k, f in [0.5, 1)
    const double inv = std::ldexp(1.0, -(k + 1));
    const double tol2 = static_cast<double>(tol) * static_cast<double>(tol);
    const double far = 4503599627370496.0; // 2^52
    std::size_t checks = 0;
    std::unordered_map<SilCell, std::vector<std::uint32_t>, SilCellHasher> grid;
    grid.reserve(n);
    for (std::uint32_t i = 0; i < n; ++i) {
        const SilCell c{sil_cell_coord(p[i].x, inv), sil_cell_coord(p[i].y, inv), sil_cell_coord(p[i].z, inv)};
        const int rx = std::fabs(c.x) < far ? 1 : 0, ry = std::fabs(c.y) < far ? 1 : 0, rz = std::fabs(c.z) < far ? 1 : 0;
        std::uint32_t best = kSilhouetteNoFace;
        for (int dx = -rx; dx <= rx; ++dx)
            for (int dy = -ry; dy <= ry; ++dy)
                for (int dz = -rz; dz <= rz; ++dz) {
                    const auto it = grid.find(SilCell{c.x + dx, c.y + dy, c.z + dz});
                    if (it == grid.end()) continue;
                    for (std::uint32_t r : it->second) {
                        ++checks;
                        const glm::dvec3 d = sil_d(p[i]) - sil_d(p[r]);
                        if (r < best && d.x * d.x + d.y * d.y + d.z * d.z <= tol2) best = r;
                    }
                }
        if (best != kSilhouetteNoFace) remap[i] = best;
        else grid[c].push_back(i);
    }
    return checks;
}

} // namespace detail

namespace detail {

// The edges of adj.faces: half-edges sorted by undirected key, then each key's run is a boundary edge
// (one face), a manifold edge (two faces of opposite directions) or a non-manifold edge (the rest).
inline void sil_build_edges(SilhouetteAdjacency& adj) {
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
            adj.edges.push_back(rev ? SilhouetteEdge{hi, lo, f, kSilhouetteNoFace} : SilhouetteEdge{lo, hi, f, kSilhouetteNoFace});
            ++adj.boundary_edges;
        } else if (cnt == 2 && ((half[i].face_dir ^ half[i + 1].face_dir) & 0x80000000u)) {
            // sorted by face_dir: the forward (lo -> hi) face comes first
            adj.edges.push_back(SilhouetteEdge{lo, hi, half[i].face_dir & 0x7FFFFFFFu, half[i + 1].face_dir & 0x7FFFFFFFu});
            ++adj.manifold_edges;
        } else {
            SilhouetteNonManifoldEdge e{lo, hi, static_cast<std::uint32_t>(adj.nonmanifold_faces.size()), static_cast<std::uint32_t>(cnt)};
            for (std::size_t k = i; k < j; ++k) adj.nonmanifold_faces.push_back(half[k].face_dir);
            adj.nonmanifold_edges.push_back(e);
        }
        i = j;
    }
}

} // namespace detail

/// Builds the edge adjacency of a triangle list (allocates; once per mesh / topology change).
/// `positions` holds vertex_count glm::vec3; `indices` holds index_count uint32 (3 per triangle).
/// Statuses: header comment. Empty input is Ok.
inline SilhouetteAdjacency silhouette_build_adjacency(const glm::vec3* positions, std::size_t vertex_count,
                                                      const std::uint32_t* indices, std::size_t index_count,
                                                      const SilhouetteAdjacencyOptions& options = SilhouetteAdjacencyOptions()) {
    SilhouetteAdjacency adj;
    if ((vertex_count > 0 && positions == nullptr) || (index_count > 0 && indices == nullptr) || index_count % 3 != 0 ||
        vertex_count > 0xFFFFFFFEull || index_count / 3 > 0x7FFFFFFFull) {
        adj.status = Status::InvalidArgument;
        adj.detail = vertex_count > 0 && positions == nullptr ? "positions: null with vertex_count > 0"
                     : (index_count > 0 && indices == nullptr ? "indices: null with index_count > 0"
                     : (index_count % 3 != 0 ? "index_count: not a multiple of 3"
                     : (vertex_count > 0xFFFFFFFEull ? "vertex_count: > 2^32 - 2" : "index_count: more than 2^31 - 1 triangles")));
        return adj;
    }
    if (!std::isfinite(options.weld_tolerance)) { adj.status = Status::NonFinite; adj.detail = "weld_tolerance: NaN or Inf"; return adj; }
    for (std::size_t i = 0; i < vertex_count; ++i)
        if (!detail::sil_finite(positions[i])) { adj.status = Status::NonFinite; adj.detail = "positions: NaN or Inf"; return adj; }
    for (std::size_t i = 0; i < index_count; ++i)
        if (indices[i] >= vertex_count) { adj.status = Status::IndexOutOfRange; adj.detail = "indices: >= vertex_count"; return adj; }

    const std::uint32_t n = static_cast<std::uint32_t>(vertex_count);
    adj.vertex_count = n;
    adj.weld_checks = detail::sil_weld(positions, n, options.weld_tolerance, adj.remap);
    for (std::uint32_t i = 0; i < n; ++i) adj.welded_vertices += adj.remap[i] != i;

    // Faces: weld, drop degenerate, then duplicates (first occurrence in input order wins).
    const std::size_t tri_count = index_count / 3;
    struct Cand { std::uint32_t a, b, c, src; };
    std::vector<Cand> cand;
    cand.reserve(tri_count);
    for (std::size_t t = 0; t < tri_count; ++t) {
        const std::uint32_t a = adj.remap[indices[3 * t]], b = adj.remap[indices[3 * t + 1]], c = adj.remap[indices[3 * t + 2]];
        if (a == b || b == c || a == c) { ++adj.degenerate_triangles; continue; }
        if (detail::sil_zero_area(positions[a], positions[b], positions[c])) { ++adj.degenerate_triangles; continue; }
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

    detail::sil_build_edges(adj);
    adj.status = Status::Ok;
    return adj;
}

/// Total: true iff light_position is a valid light (finite, w >= 0, not (0, 0, 0, 0)).
inline bool silhouette_valid_light(const glm::vec4& light_position) {
    const glm::vec4& L = light_position;
    if (!(std::isfinite(L.x) && std::isfinite(L.y) && std::isfinite(L.z) && std::isfinite(L.w))) return false;
    if (L.w < 0.0f) return false;
    return !(L.w == 0.0f && L.x == 0.0f && L.y == 0.0f && L.z == 0.0f);
}

/// Total: uint32 elements a silhouette buffer needs for any facing (2 per edge): size edge_indices with it.
inline std::size_t silhouette_indices_capacity(const SilhouetteAdjacency& adj) { return 2 * adj.max_silhouette_edges(); }

/// Exact facing of one triangle (a, b, c) for light_position: the sign of d (header comment), lit iff
/// d > 0. NonFinite for NaN/Inf corners, InvalidLight for a bad light.
inline SilhouetteOrientation silhouette_face_orientation(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c,
                                                         const glm::vec4& light_position) {
    SilhouetteOrientation r;
    if (!detail::sil_finite(a) || !detail::sil_finite(b) || !detail::sil_finite(c)) {
        r.status = Status::NonFinite;
        r.detail = !detail::sil_finite(a) ? "a: NaN or Inf" : (!detail::sil_finite(b) ? "b: NaN or Inf" : "c: NaN or Inf");
        return r;
    }
    if (!silhouette_valid_light(light_position)) { r.status = Status::InvalidLight; r.detail = "light_position: NaN/Inf, w < 0 or (0, 0, 0, 0)"; return r; }
    r.sign = detail::sil_face_sign(a, b, c, light_position);
    r.lit = r.sign > 0;
    r.status = Status::Ok;
    return r;
}

namespace detail {

// facing[i] for kept faces [begin, end); returns the lit count, sets bad on NaN/Inf positions
inline std::size_t sil_facing_range(const SilhouetteAdjacency& adj, const glm::vec3* positions, const glm::vec4& light,
                                    std::uint8_t* facing, std::size_t begin, std::size_t end, bool& bad) {
    const std::uint32_t* f = adj.faces.data();
    std::size_t lit_faces = 0;
    bool nonfinite = false;
    for (std::size_t i = begin; i < end; ++i) {
        const int s = sil_face_sign(positions[f[3 * i]], positions[f[3 * i + 1]], positions[f[3 * i + 2]], light);
        const std::uint8_t lit = s == 1 ? 1u : 0u;
        nonfinite |= s == kSilNonFinite;
        facing[i] = lit;
        lit_faces += lit;
    }
    bad = nonfinite;
    return lit_faces;
}

// Sets `why` (where a non-Ok status came from, a static string) and returns s.
inline Status sil_fail(const char*& why, Status s, const char* what) {
    why = what;
    return s;
}
inline Status sil_check_facing_args(const SilhouetteAdjacency& adj, const glm::vec3* positions, std::size_t vertex_count,
                                    const glm::vec4& light, const std::uint8_t* facing, std::size_t capacity,
                                    const char*& why) {
    const Status ia = Status::InvalidArgument;
    if (adj.status != Status::Ok) return sil_fail(why, ia, "adj: status not Ok");
    if (vertex_count != adj.vertex_count) return sil_fail(why, ia, "vertex_count: not adj.vertex_count");
    if (vertex_count > 0 && positions == nullptr) return sil_fail(why, ia, "positions: null with vertex_count > 0");
    if (capacity > 0 && facing == nullptr) return sil_fail(why, ia, "facing: null with capacity > 0");
    if (!silhouette_valid_light(light)) return sil_fail(why, Status::InvalidLight, "light_position: NaN/Inf, w < 0 or (0, 0, 0, 0)");
    if (capacity < adj.face_count()) return sil_fail(why, Status::BufferTooSmall, "facing_capacity: below needed (see needed)");
    return Status::Ok;
}

// Silhouette of the manifold / boundary edges [begin, end) (and the non-manifold edges if
// `nonmanifold`) into out[0, 2 room); adds to r (needed, boundary / non-manifold counts), returns the
// number of edges found.
inline std::size_t sil_extract_range(const SilhouetteAdjacency& adj, const std::uint8_t* facing, std::uint32_t* edge_indices,
                                     std::uint8_t* edge_flags, std::size_t room, std::size_t begin, std::size_t end,
                                     bool nonmanifold, SilhouetteResult& r) {
    std::size_t n = 0;
    auto emit = [&](std::uint32_t a, std::uint32_t b, std::uint8_t flags) {
        if (n < room) {
            edge_indices[2 * n] = a;
            edge_indices[2 * n + 1] = b;
            if (edge_flags) edge_flags[n] = flags;
        }
        ++n;
    };
    const SilhouetteEdge* e = adj.edges.data();
    for (std::size_t i = begin; i < end; ++i) {
        const SilhouetteEdge& E = e[i];
        const bool l0 = facing[E.f0] != 0;
        if (E.f1 == kSilhouetteNoFace) {
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
        for (const SilhouetteNonManifoldEdge& E : adj.nonmanifold_edges) {
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
    r.needed += 2 * n;
    return n;
}

// First item of chunk c when n items are split into `count` balanced chunks (no overflow).
inline std::size_t sil_chunk_begin(std::size_t n, std::size_t c, std::size_t count) {
    return (n / count) * c + std::min(c, n % count);
}

// Common checks of the extraction functions' buffers.
inline Status sil_check_extract_args(const SilhouetteAdjacency& adj, const std::uint8_t* facing, std::size_t facing_count,
                                     const std::uint32_t* edge_indices, std::size_t edge_indices_capacity,
                                     const std::uint8_t* edge_flags, std::size_t edge_flags_capacity, const char*& why) {
    const Status ia = Status::InvalidArgument;
    if (adj.status != Status::Ok) return sil_fail(why, ia, "adj: status not Ok");
    const std::size_t fc = adj.face_count();
    if (facing_count != fc) return sil_fail(why, ia, "facing_count: not adj.face_count()");
    if (fc > 0 && facing == nullptr) return sil_fail(why, ia, "facing: null");
    if (edge_indices_capacity > 0 && edge_indices == nullptr) return sil_fail(why, ia, "edge_indices: null with a capacity > 0");
    if (edge_flags_capacity > 0 && edge_flags == nullptr) return sil_fail(why, ia, "edge_flags: null with edge_flags_capacity > 0");
    return Status::Ok;
}

}  // namespace detail

/// Writes facing[f] = 1 if kept face f is lit by light_position (exact sign of d > 0), else 0.
/// `positions` holds vertex_count glm::vec3: the buffer the adjacency was built from, or a deformed
/// copy with the same count (NaN/Inf in a face's corner: NonFinite). `facing` holds facing_capacity
/// uint8 elements; it needs adj.face_count() (`needed`).
inline SilhouetteFacing silhouette_compute_facing(const SilhouetteAdjacency& adj, const glm::vec3* positions,
                                                  std::size_t vertex_count, const glm::vec4& light_position,
                                                  std::uint8_t* facing, std::size_t facing_capacity) {
    SilhouetteFacing r;
    r.needed = adj.face_count();
    r.status = detail::sil_check_facing_args(adj, positions, vertex_count, light_position, facing, facing_capacity, r.detail);
    if (r.status != Status::Ok) return r;
    bool bad = false;
    r.lit_faces = detail::sil_facing_range(adj, positions, light_position, facing, 0, r.needed, bad);
    r.count = r.needed;
    if (bad) {
        r.status = Status::NonFinite;
        r.detail = "positions: NaN or Inf at a face's vertex";
    }
    return r;
}

/// Single linear pass over the edges: the silhouette of the facing bits (edge rule, header comment).
/// `facing` holds facing_count uint8 elements (= adj.face_count()). `edge_indices` holds
/// edge_indices_capacity uint32 elements; it needs 2 per edge (`needed`; at most
/// silhouette_indices_capacity(adj)). `edge_flags` (optional, nullptr with 0) holds
/// edge_flags_capacity uint8 elements, one SilhouetteFlag mask per edge: it needs needed / 2.
/// Short buffers: the first whole edges that fit both are written (`count`), BufferTooSmall.
inline SilhouetteResult silhouette_extract(const SilhouetteAdjacency& adj, const std::uint8_t* facing, std::size_t facing_count,
                                           std::uint32_t* edge_indices, std::size_t edge_indices_capacity,
                                           std::uint8_t* edge_flags, std::size_t edge_flags_capacity) {
    SilhouetteResult r;
    r.status = detail::sil_check_extract_args(adj, facing, facing_count, edge_indices, edge_indices_capacity, edge_flags,
                                              edge_flags_capacity, r.detail);
    if (r.status != Status::Ok) return r;
    std::size_t room = edge_indices_capacity / 2;
    if (edge_flags && edge_flags_capacity < room) room = edge_flags_capacity;
    const std::size_t n = detail::sil_extract_range(adj, facing, edge_indices, edge_flags, room, 0, adj.edges.size(), true, r);
    r.count = 2 * (n < room ? n : room);
    if (r.count < r.needed) {
        r.status = Status::BufferTooSmall;
        r.detail = "edge_indices_capacity or edge_flags_capacity: below needed (see needed)";
    }
    return r;
}

/// uint32 elements silhouette_extract_two_sided may need for any facing: 2 per edge, each manifold edge
/// at most twice, each boundary edge once, each non-manifold edge at most its face count.
inline std::size_t silhouette_two_sided_indices_capacity(const SilhouetteAdjacency& adj) {
    std::size_t n = 2 * adj.manifold_edges + adj.boundary_edges;
    for (const SilhouetteNonManifoldEdge& e : adj.nonmanifold_edges) n += e.count;
    return 2 * n;
}

/// The two-sided silhouette (header comment, "Two-sided rule"): every face an occluder, an unlit one
/// taken reversed. Same buffers, flags, checks and results as silhouette_extract; edge_indices needs
/// at most silhouette_two_sided_indices_capacity(adj). Feed it to volume_build_side_quads and build
/// the caps with VolumeCapMode::TwoSided from the same facing. Single pass, scalar.
inline SilhouetteResult silhouette_extract_two_sided(const SilhouetteAdjacency& adj, const std::uint8_t* facing,
                                                     std::size_t facing_count, std::uint32_t* edge_indices,
                                                     std::size_t edge_indices_capacity, std::uint8_t* edge_flags,
                                                     std::size_t edge_flags_capacity) {
    SilhouetteResult r;
    r.status = detail::sil_check_extract_args(adj, facing, facing_count, edge_indices, edge_indices_capacity, edge_flags,
                                              edge_flags_capacity, r.detail);
    if (r.status != Status::Ok) return r;
    std::size_t room = edge_indices_capacity / 2, n = 0;
    if (edge_flags && edge_flags_capacity < room) room = edge_flags_capacity;
    auto emit = [&](std::uint32_t a, std::uint32_t b, long k, std::uint8_t flags) {  // |k| times, u -> v if k > 0
        for (long m = 0; m < (k < 0 ? -k : k); ++m, ++n) {
            if (n >= room) continue;
            edge_indices[2 * n] = k > 0 ? a : b;
            edge_indices[2 * n + 1] = k > 0 ? b : a;
            if (edge_flags) edge_flags[n] = flags;
        }
    };
    for (const SilhouetteEdge& E : adj.edges) {  // f0 traverses v0 -> v1 (s = +1), f1 v1 -> v0 (s = -1)
        const long k0 = facing[E.f0] ? 1 : -1;
        if (E.f1 == kSilhouetteNoFace) {
            emit(E.v0, E.v1, k0, SilhouetteBoundary);
            ++r.boundary_edges;
            continue;
        }
        emit(E.v0, E.v1, k0 - (facing[E.f1] ? 1 : -1), 0);
    }
    for (const SilhouetteNonManifoldEdge& E : adj.nonmanifold_edges) {
        long k = 0;
        for (std::uint32_t j = 0; j < E.count; ++j) {
            const std::uint32_t fd = adj.nonmanifold_faces[E.first + j];
            const long s = (fd & 0x80000000u) ? -1 : 1;
            k += facing[fd & 0x7FFFFFFFu] ? s : -s;
        }
        emit(E.v0, E.v1, k, SilhouetteNonManifold);
        r.nonmanifold_edges += static_cast<std::size_t>(k < 0 ? -k : k);
    }
    r.needed = 2 * n;
    r.count = 2 * (n < room ? n : room);
    if (r.count < r.needed) {
        r.status = Status::BufferTooSmall;
        r.detail = "edge_indices_capacity or edge_flags_capacity: below needed (see needed)";
    }
    return r;
}

// ------------------------------------------------------------------ parallel silhouettes (chunks)
// The same facing + silhouette split into `chunk_count` chunks that may run concurrently on any job
// system (shadowkit starts no threads and allocates nothing here):
//   1. silhouette_compute_facing_chunk(c) for every chunk c   (faces split evenly; writes facing[])
//   2. barrier (a chunk's edges read the facing of any face)
//   3. silhouette_extract_chunk(c) for every chunk c          (edges split evenly; the last chunk also
//      takes the non-manifold edges). Chunk c writes its edges from uint32 element
//      silhouette_chunk_offset(c) of a buffer of silhouette_indices_capacity(adj) elements (each
//      manifold or boundary edge emits at most one, so the chunks never overlap); its flags from
//      element silhouette_chunk_offset(c) / 2 of the flags buffer
//   4. silhouette_compact_chunks: moves the chunks together (serial, O(silhouette))
// The result (edges, order, flags, counts) is identical to silhouette_extract's for any chunk_count.
// silhouette_extract_parallel does the four steps with a caller's parallel_for(n, fn), which must
// call fn(i) once for each i in [0, n) and return when all have finished.

/// Facing of the kept faces of chunk `chunk` of `chunk_count` (same rule, buffers and checks as
/// silhouette_compute_facing; count / lit_faces are this chunk's). chunk_count >= 1, chunk < chunk_count.
inline SilhouetteFacing silhouette_compute_facing_chunk(const SilhouetteAdjacency& adj, const glm::vec3* positions,
                                                        std::size_t vertex_count, const glm::vec4& light_position,
                                                        std::uint8_t* facing, std::size_t facing_capacity, std::size_t chunk,
                                                        std::size_t chunk_count) {
    SilhouetteFacing r;
    r.needed = adj.face_count();
    if (chunk_count == 0 || chunk >= chunk_count) { r.status = Status::InvalidArgument; r.detail = chunk_count == 0 ? "chunk_count: 0" : "chunk: >= chunk_count"; return r; }
    r.status = detail::sil_check_facing_args(adj, positions, vertex_count, light_position, facing, facing_capacity, r.detail);
    if (r.status != Status::Ok) return r;
    const std::size_t fc = adj.face_count();
    const std::size_t b = detail::sil_chunk_begin(fc, chunk, chunk_count), e = detail::sil_chunk_begin(fc, chunk + 1, chunk_count);
    bool bad = false;
    r.lit_faces = detail::sil_facing_range(adj, positions, light_position, facing, b, e, bad);
    r.count = e - b;
    if (bad) {
        r.status = Status::NonFinite;
        r.detail = "positions: NaN or Inf at a face's vertex";
    }
    return r;
}

/// Total: the uint32 element of edge_indices at which chunk `chunk` of `chunk_count` writes its
/// silhouette edges (even; its flags start at half of it); 0 for chunk >= chunk_count or chunk_count 0.
inline std::size_t silhouette_chunk_offset(const SilhouetteAdjacency& adj, std::size_t chunk, std::size_t chunk_count) {
    if (chunk_count == 0 || chunk >= chunk_count) return 0;
    return 2 * detail::sil_chunk_begin(adj.edges.size(), chunk, chunk_count);
}

/// Silhouette edges of chunk `chunk` of `chunk_count`, written from element silhouette_chunk_offset()
/// on (count / needed: this chunk's elements). edge_indices_capacity must be >=
/// silhouette_indices_capacity(adj), edge_flags (optional) >= half of it, else BufferTooSmall and
/// nothing is written; facing must be complete (every chunk's facing has finished).
inline SilhouetteResult silhouette_extract_chunk(const SilhouetteAdjacency& adj, const std::uint8_t* facing,
                                                 std::size_t facing_count, std::uint32_t* edge_indices,
                                                 std::size_t edge_indices_capacity, std::uint8_t* edge_flags,
                                                 std::size_t edge_flags_capacity, std::size_t chunk, std::size_t chunk_count) {
    SilhouetteResult r;
    if (chunk_count == 0 || chunk >= chunk_count) { r.status = Status::InvalidArgument; r.detail = chunk_count == 0 ? "chunk_count: 0" : "chunk: >= chunk_count"; return r; }
    r.status = detail::sil_check_extract_args(adj, facing, facing_count, edge_indices, edge_indices_capacity, edge_flags,
                                              edge_flags_capacity, r.detail);
    if (r.status != Status::Ok) return r;
    const std::size_t max_edges = adj.max_silhouette_edges();
    if (edge_indices_capacity / 2 < max_edges || (edge_flags && edge_flags_capacity < max_edges)) {
        r.status = Status::BufferTooSmall;
        r.detail = "edge_indices_capacity or edge_flags_capacity: below silhouette_indices_capacity(adj)";
        return r;
    }
    const std::size_t ec = adj.edges.size();
    const std::size_t b = detail::sil_chunk_begin(ec, chunk, chunk_count), e = detail::sil_chunk_begin(ec, chunk + 1, chunk_count);
    // this chunk's room: up to the next chunk's offset, the last chunk up to the capacity
    const std::size_t room = chunk + 1 == chunk_count ? max_edges - b : e - b;
    const std::size_t n = detail::sil_extract_range(adj, facing, edge_indices + 2 * b, edge_flags ? edge_flags + b : nullptr,
                                                    room, b, e, chunk + 1 == chunk_count, r);
    r.count = 2 * n;
    return r;
}

/// Moves the chunks' edges (and flags) together so that the buffers hold the silhouette exactly as
/// silhouette_extract writes it; returns the totals (the first failing chunk's status, if any).
/// `chunks` holds chunk_count results of silhouette_extract_chunk; buffers as there.
inline SilhouetteResult silhouette_compact_chunks(const SilhouetteAdjacency& adj, const SilhouetteResult* chunks,
                                                  std::size_t chunk_count, std::uint32_t* edge_indices,
                                                  std::size_t edge_indices_capacity, std::uint8_t* edge_flags,
                                                  std::size_t edge_flags_capacity) {
    SilhouetteResult r;
    if (chunk_count == 0 || chunks == nullptr || adj.status != Status::Ok || (edge_indices_capacity > 0 && edge_indices == nullptr) ||
        (edge_flags_capacity > 0 && edge_flags == nullptr)) {
        r.status = Status::InvalidArgument;
        r.detail = chunk_count == 0 ? "chunk_count: 0"
                   : (chunks == nullptr ? "chunks: null"
                   : (adj.status != Status::Ok ? "adj: status not Ok"
                   : (edge_indices_capacity > 0 && edge_indices == nullptr ? "edge_indices: null with a capacity > 0"
                                                                            : "edge_flags: null with edge_flags_capacity > 0")));
        return r;
    }
    for (std::size_t c = 0; c < chunk_count; ++c)
        if (chunks[c].status != Status::Ok) {
            r.status = chunks[c].status;
            r.detail = chunks[c].detail != nullptr ? chunks[c].detail : "chunks: a status not Ok";
            return r;
        }
    const std::size_t cap = 2 * adj.max_silhouette_edges();
    if (edge_indices_capacity < cap || (edge_flags && edge_flags_capacity < cap / 2)) {
        r.status = Status::BufferTooSmall;
        r.detail = "edge_indices_capacity or edge_flags_capacity: below silhouette_indices_capacity(adj)";
        return r;
    }
    // a chunk cannot have more edges than its room (results that do are not silhouette_extract_chunk's)
    for (std::size_t c = 0; c < chunk_count; ++c) {
        const std::size_t off = silhouette_chunk_offset(adj, c, chunk_count);
        const std::size_t room = c + 1 == chunk_count ? cap - off : silhouette_chunk_offset(adj, c + 1, chunk_count) - off;
        if (chunks[c].count > room || chunks[c].count % 2 != 0 || chunks[c].count != chunks[c].needed) {
            r.status = Status::InvalidArgument;
            r.detail = "chunks: a count that silhouette_extract_chunk cannot give";
            return r;
        }
    }
    std::size_t n = 0;
    for (std::size_t c = 0; c < chunk_count; ++c) {
        const std::size_t off = silhouette_chunk_offset(adj, c, chunk_count), k = chunks[c].count;
        if (off != n && k > 0) {  // off >= n: moving down, ranges may overlap
            std::memmove(edge_indices + n, edge_indices + off, k * sizeof(std::uint32_t));
            if (edge_flags) std::memmove(edge_flags + n / 2, edge_flags + off / 2, k / 2);
        }
        n += k;
        r.boundary_edges += chunks[c].boundary_edges;
        r.nonmanifold_edges += chunks[c].nonmanifold_edges;
    }
    r.count = r.needed = n;
    r.status = Status::Ok;
    return r;
}

/// Facing + silhouette on a caller's job system: parallel_for(chunk_count, fn) (see above), with
/// caller-provided buffers: `facing` (facing_capacity uint8, needs adj.face_count()), `edge_indices`
/// (edge_indices_capacity uint32, needs silhouette_indices_capacity(adj)), `edge_flags` (optional,
/// edge_flags_capacity uint8, needs half of that) and `chunk_results` (chunk_count results).
/// Same output as silhouette_compute_facing + silhouette_extract.
template <class ParallelFor>
inline SilhouetteResult silhouette_extract_parallel(const SilhouetteAdjacency& adj, const glm::vec3* positions,
                                                    std::size_t vertex_count, const glm::vec4& light_position,
                                                    std::uint8_t* facing, std::size_t facing_capacity,
                                                    std::uint32_t* edge_indices, std::size_t edge_indices_capacity,
                                                    std::uint8_t* edge_flags, std::size_t edge_flags_capacity,
                                                    SilhouetteResult* chunk_results, std::size_t chunk_count,
                                                    ParallelFor&& parallel_for) {
    SilhouetteResult r;
    if (chunk_count == 0 || chunk_results == nullptr) {
        r.status = Status::InvalidArgument;
        r.detail = chunk_count == 0 ? "chunk_count: 0" : "chunk_results: null";
        return r;
    }
    // validate once, so that no chunk can fail on its arguments
    r.status = detail::sil_check_facing_args(adj, positions, vertex_count, light_position, facing, facing_capacity, r.detail);
    if (r.status != Status::Ok) return r;
    const std::size_t fc = adj.face_count();
    r.status = detail::sil_check_extract_args(adj, facing, fc, edge_indices, edge_indices_capacity, edge_flags, edge_flags_capacity,
                                              r.detail);
    if (r.status != Status::Ok) return r;
    const std::size_t cap = silhouette_indices_capacity(adj);
    if (edge_indices_capacity < cap || (edge_flags && edge_flags_capacity < cap / 2)) {
        r.status = Status::BufferTooSmall;
        r.detail = "edge_indices_capacity or edge_flags_capacity: below needed (see needed)";
        r.needed = cap;
        return r;
    }
    for (std::size_t c = 0; c < chunk_count; ++c) chunk_results[c] = SilhouetteResult{};
    parallel_for(chunk_count, [&](std::size_t c) {
        bool bad = false;
        detail::sil_facing_range(adj, positions, light_position, facing, detail::sil_chunk_begin(fc, c, chunk_count),
                                 detail::sil_chunk_begin(fc, c + 1, chunk_count), bad);
        if (bad) {
            chunk_results[c].status = Status::NonFinite;
            chunk_results[c].detail = "positions: NaN or Inf at a face's vertex";
        }
    });
    for (std::size_t c = 0; c < chunk_count; ++c)
        if (chunk_results[c].status == Status::NonFinite) {
            r.status = Status::NonFinite;
            r.detail = "positions: NaN or Inf at a face's vertex";
            return r;
        }
    parallel_for(chunk_count, [&](std::size_t c) {
        chunk_results[c] = silhouette_extract_chunk(adj, facing, fc, edge_indices, edge_indices_capacity, edge_flags,
                                                    edge_flags_capacity, c, chunk_count);
    });
    return silhouette_compact_chunks(adj, chunk_results, chunk_count, edge_indices, edge_indices_capacity, edge_flags,
                                     edge_flags_capacity);
}

// ------------------------------------------------------------------ cached face planes (rigid meshes)
// The fast path for a mesh whose positions do not change: silhouette_build_planes stores, once, each
// kept face's plane in float, and per frame the facing is one 4-term float dot product per face
// (SIMD), decided by a proven error bound; the few faces inside the bound fall back to the exact
// path above. The facing bits are identical to silhouette_compute_facing's.
//
// The arithmetic. Local frame: O (float, the center of the positions' bounds) and R = 2^k >= their
// half extent. For a face with exact n = cross(B - A, C - A) and c = n . (O - A) (both d of the
// header comment, for the lights (e_x, 0), (e_y, 0), (e_z, 0) and (O, 1)), and a light (l, w):
//     d = n . (l - w O) + (c / R) (w R) = P . L*,   P = (n, c / R),  L* = (l - w O, w R).
// Setup: P to relative 2^-30 per component (sil_face_value: filter or exact), scaled by a power of
// two to max |P_i| in [1, 2), rounded to float: |P_f,i - P_i| <= r |P_f,i| with r < 1.02 * 2^-24 (a
// face with a non-zero component below 2^-126 after scaling stores P_f = 0: it is always decided
// exactly). Per frame: L* in double (w O_i and w R exact, one rounding in l - w O), scaled by a
// power of two to max in [1, 2), rounded to float: |L_f,i - L*_i| <= r_L |L_f,i| + 2^-126 (r_L <
// 1.0001 * 2^-24; the absolute term covers subnormals and flush-to-zero). The float dot product
// (any order, with or without FMA: at most 4 roundings per term) is within gamma_4 S + 2^-123 of
// sum P_f,i L_f,i, S = sum |P_f,i L_f,i| <= 2 ||L_f||_1. So with positive scale factors s:
//     |d_float - s d| <= (gamma_4 + r + r_L + r r_L) S + 2^-121 < 12.2 * 2^-24 ||L_f||_1 + 2^-121
// and ||L_f||_1 >= 1, so bound = 2^-20 ||L_f||_1 (float; 16 against 12.2) decides: d_float > bound
// -> lit, d_float < -bound -> not lit, else the exact path (which also gets every d == 0 face).
// Checked by tests/unit/test_silhouette_planes.cpp ("the float filter's error bound"): the error
// against a long double evaluation stays below 12.2 * 2^-24 ||L_f||_1 in both summation orders (at
// most 4.9 seen on x86-64, 3.8 on AArch64 with NEON under qemu: hygiene.aarch64_neon).

/// Cached face planes of a rigid mesh for the fast exact facing (silhouette_build_planes: allocates,
/// once per mesh). `status` first; the rest is valid when Ok. Built for one adjacency and one
/// positions buffer: pass the same adjacency to the *_planes functions (the counts are checked).
struct SilhouettePlanes {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    std::uint32_t vertex_count = 0;            ///< the adjacency's vertex count
    glm::vec3 origin = glm::vec3(0.0f);        ///< O: local frame center (header comment above)
    double scale = 1.0;                        ///< R: a power of two >= the positions' half extent
    std::vector<float> plane_x, plane_y, plane_z, plane_w; ///< per kept face: P_f (structure of arrays)
    std::vector<glm::vec3> positions;          ///< copy of the positions: the exact fallback reads them
    std::vector<std::uint64_t> edge_faces;     ///< per adjacency edge: f0 | f1 << 32 (a boundary edge: f1 = f0)
    std::vector<std::uint8_t> edge_boundary;   ///< per 8 adjacency edges: bit j set if edge 8 k + j is a boundary edge
    std::vector<std::uint32_t> edge_vertices;  ///< 2 per adjacency edge: v0, v1
    std::size_t exact_faces = 0;               ///< faces stored as P_f = 0: always decided by the exact path
    /// Per kept face: the smallest index of a face in exactly the same plane, reached through edges
    /// whose two faces are exactly coplanar (the face itself when none), | 1u << 31 when that face's
    /// normal points the other way. Faces of one plane have d of one sign (opposite when flipped),
    /// so the exact stage runs once per plane, not once per face, when the filter leaves a whole
    /// plane undecided (a light in a flat region's plane).
    std::vector<std::uint32_t> plane_class;

    /// Kept faces (= the adjacency's face_count()).
    std::size_t face_count() const { return plane_x.size(); }
};

namespace detail {

inline int sil_ctz64(std::uint64_t x) {
#if defined(__GNUC__) || defined(__clang__)
    return __builtin_ctzll(x);
#else
    int n = 0;
    while ((x & 1u) == 0u) { x >>= 1; ++n; }
    return n;
#endif
}

// The light in the planes' frame (header comment above): out[4] = L_f, *bound = 2^-20 ||L_f||_1.
inline void sil_planes_light(const SilhouettePlanes& pl, const glm::vec4& L, float* out, float* bound) {
    const double w = L.w;
    const double q[4] = {static_cast<double>(L.x) - w * static_cast<double>(pl.origin.x),
                         static_cast<double>(L.y) - w * static_cast<double>(pl.origin.y),
                         static_cast<double>(L.z) - w * static_cast<double>(pl.origin.z), w * pl.scale};
    double m = 0.0;
    for (double v : q) m = std::fmax(m, std::fabs(v));
    int ex = 0;
    (void)std::frexp(m, &ex); // m = f 2^ex, f in [0.5, 1): scaled max in [1, 2)
    float sum = 0.0f;
    for (int i = 0; i < 4; ++i) {
        out[i] = static_cast<float>(std::ldexp(q[i], 1 - ex));
        sum += std::fabs(out[i]);
    }
    *bound = sum * 0x1p-20f;
}

// facing[f] for kept faces f in [begin, end) from the cached planes; returns the lit count and
// adds the exact predicate's runs to *exact_runs (when not null).
inline std::size_t sil_planes_facing_range(const SilhouetteAdjacency& adj, const SilhouettePlanes& pl, const glm::vec4& light,
                                           std::uint8_t* facing, std::size_t begin, std::size_t end,
                                           std::size_t* exact_runs_out = nullptr) {
    std::size_t exact_runs = 0;
    float Lf[4], bound = 0.0f;
    sil_planes_light(pl, light, Lf, &bound);
    const float* px = pl.plane_x.data();
    const float* py = pl.plane_y.data();
    const float* pz = pl.plane_z.data();
    const float* pw = pl.plane_w.data();
    const std::uint32_t* fi = adj.faces.data();
    const glm::vec3* pos = pl.positions.data();
    const std::uint32_t* cls = pl.plane_class.data();
    std::uint32_t memo_class = 0xFFFFFFFFu;  // the last plane class decided exactly, and its d's sign
    int memo_sign = 0;
    auto exact = [&](std::size_t f) -> std::uint8_t {
        const std::uint32_t c = cls[f] & 0x7FFFFFFFu;
        if (c != memo_class) {  // faces of one plane class share d's sign (flipped: the opposite)
            memo_sign = sil_face_sign(pos[fi[3 * std::size_t(c)]], pos[fi[3 * std::size_t(c) + 1]], pos[fi[3 * std::size_t(c) + 2]], light);
            memo_class = c;
            ++exact_runs;
        }
        return (cls[f] & 0x80000000u ? -memo_sign : memo_sign) == 1 ? 1u : 0u;
    };
    std::size_t lit = 0, i = begin;
#if defined(SHADOWKIT_SIL_SSE2)
    {
        const __m128 lx = _mm_set1_ps(Lf[0]), ly = _mm_set1_ps(Lf[1]), lz = _mm_set1_ps(Lf[2]), lw = _mm_set1_ps(Lf[3]);
        const __m128 bp = _mm_set1_ps(bound), bn = _mm_set1_ps(-bound);
        const __m128i one = _mm_set1_epi8(1), zero = _mm_setzero_si128();
        __m128i acc = _mm_setzero_si128();
        for (; i + 16 <= end; i += 16) {
            __m128i g[4];
            int decided = 0;
            for (int k = 0; k < 4; ++k) {
                const std::size_t j = i + 4 * static_cast<std::size_t>(k);
                const __m128 d = _mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_loadu_ps(px + j), lx), _mm_mul_ps(_mm_loadu_ps(py + j), ly)),
                                            _mm_add_ps(_mm_mul_ps(_mm_loadu_ps(pz + j), lz), _mm_mul_ps(_mm_loadu_ps(pw + j), lw)));
                const __m128 gt = _mm_cmpgt_ps(d, bp);
                decided |= _mm_movemask_ps(_mm_or_ps(gt, _mm_cmplt_ps(d, bn))) << (4 * k);
                g[k] = _mm_castps_si128(gt);
            }
            const __m128i bytes = _mm_and_si128(_mm_packs_epi16(_mm_packs_epi32(g[0], g[1]), _mm_packs_epi32(g[2], g[3])), one);
            _mm_storeu_si128(reinterpret_cast<__m128i*>(facing + i), bytes);
            acc = _mm_add_epi64(acc, _mm_sad_epu8(bytes, zero));
            if (decided != 0xFFFF) {
                for (int k = 0; k < 16; ++k)
                    if (!((decided >> k) & 1)) {
                        const std::uint8_t v = exact(i + static_cast<std::size_t>(k));
                        facing[i + static_cast<std::size_t>(k)] = v;
                        lit += v;
                    }
            }
        }
        alignas(16) std::uint64_t sums[2];
        _mm_store_si128(reinterpret_cast<__m128i*>(sums), acc);
        lit += static_cast<std::size_t>(sums[0] + sums[1]);
    }
#elif defined(SHADOWKIT_SIL_NEON)
    {
        const float32x4_t lx = vdupq_n_f32(Lf[0]), ly = vdupq_n_f32(Lf[1]), lz = vdupq_n_f32(Lf[2]), lw = vdupq_n_f32(Lf[3]);
        const float32x4_t bp = vdupq_n_f32(bound), bn = vdupq_n_f32(-bound);
        for (; i + 16 <= end; i += 16) {
            uint16x4_t g[4], u[4];
            for (int k = 0; k < 4; ++k) {
                const std::size_t j = i + 4 * static_cast<std::size_t>(k);
                const float32x4_t d = vaddq_f32(vaddq_f32(vmulq_f32(vld1q_f32(px + j), lx), vmulq_f32(vld1q_f32(py + j), ly)),
                                                vaddq_f32(vmulq_f32(vld1q_f32(pz + j), lz), vmulq_f32(vld1q_f32(pw + j), lw)));
                const uint32x4_t gt = vcgtq_f32(d, bp);
                g[k] = vmovn_u32(gt);
                u[k] = vmovn_u32(vmvnq_u32(vorrq_u32(gt, vcltq_f32(d, bn))));
            }
            const uint8x16_t bytes = vandq_u8(vcombine_u8(vmovn_u16(vcombine_u16(g[0], g[1])), vmovn_u16(vcombine_u16(g[2], g[3]))),
                                              vdupq_n_u8(1));
            const uint8x16_t undecided = vcombine_u8(vmovn_u16(vcombine_u16(u[0], u[1])), vmovn_u16(vcombine_u16(u[2], u[3])));
            vst1q_u8(facing + i, bytes);
            lit += vaddvq_u8(bytes);
            if (vmaxvq_u8(undecided) != 0) {
                for (std::size_t k = 0; k < 16; ++k)
                    if (!(facing[i + k] != 0)) {
                        const float d = px[i + k] * Lf[0] + py[i + k] * Lf[1] + pz[i + k] * Lf[2] + pw[i + k] * Lf[3];
                        if (!(d < -bound)) {
                            const std::uint8_t v = exact(i + k);
                            facing[i + k] = v;
                            lit += v;
                        }
                    }
            }
        }
    }
#endif
    for (; i < end; ++i) {
        const float d = px[i] * Lf[0] + py[i] * Lf[1] + pz[i] * Lf[2] + pw[i] * Lf[3];
        const std::uint8_t v = d > bound ? 1u : (d < -bound ? 0u : exact(i));
        facing[i] = v;
        lit += v;
    }
    if (exact_runs_out) *exact_runs_out += exact_runs;
    return lit;
}

inline Status sil_check_planes(const SilhouetteAdjacency& adj, const SilhouettePlanes& pl, const char*& why) {
    if (adj.status != Status::Ok) return sil_fail(why, Status::InvalidArgument, "adj: status not Ok");
    if (pl.status != Status::Ok) return sil_fail(why, Status::InvalidArgument, "planes: status not Ok");
    if (pl.vertex_count != adj.vertex_count ||
        pl.face_count() != adj.face_count() || pl.edge_faces.size() != adj.edges.size() ||
        pl.edge_boundary.size() != (adj.edges.size() + 7) / 8 ||
        pl.edge_vertices.size() != 2 * adj.edges.size() || pl.positions.size() != adj.vertex_count ||
        pl.plane_y.size() != pl.face_count() || pl.plane_z.size() != pl.face_count() || pl.plane_w.size() != pl.face_count() ||
        pl.plane_class.size() != pl.face_count())
        return sil_fail(why, Status::InvalidArgument, "planes: not built from adj (silhouette_build_planes)");
    return Status::Ok;
}

inline Status sil_check_planes_facing_args(const SilhouetteAdjacency& adj, const SilhouettePlanes& pl, const glm::vec4& light,
                                           const std::uint8_t* facing, std::size_t capacity, const char*& why) {
    if (sil_check_planes(adj, pl, why) != Status::Ok) return Status::InvalidArgument;
    if (capacity > 0 && facing == nullptr) return sil_fail(why, Status::InvalidArgument, "facing: null with capacity > 0");
    if (!silhouette_valid_light(light)) return sil_fail(why, Status::InvalidLight, "light_position: NaN/Inf, w < 0 or (0, 0, 0, 0)");
    if (capacity < adj.face_count()) return sil_fail(why, Status::BufferTooSmall, "facing_capacity: below needed (see needed)");
    return Status::Ok;
}

// Non-manifold edges (edge rule): emit(a, b) for each emitted edge, in order (|k| times each).
template <class Emit>
inline void sil_nonmanifold_each(const SilhouetteAdjacency& adj, const std::uint8_t* facing, Emit&& emit) {
    for (const SilhouetteNonManifoldEdge& E : adj.nonmanifold_edges) {
        long k = 0;
        for (std::uint32_t j = 0; j < E.count; ++j) {
            const std::uint32_t fd = adj.nonmanifold_faces[E.first + j];
            if (facing[fd & 0x7FFFFFFFu]) k += (fd & 0x80000000u) ? -1 : 1;
        }
        for (long m = 0; m < (k < 0 ? -k : k); ++m) emit(k > 0 ? E.v0 : E.v1, k > 0 ? E.v1 : E.v0);
    }
}

// bit j = (byte j of x != 0), for the 8 bytes of x
inline std::uint64_t sil_byte_bits(std::uint64_t x) {
    const std::uint64_t y = ((((x & 0x7F7F7F7F7F7F7F7Full) + 0x7F7F7F7F7F7F7F7Full) | x) >> 7) & 0x0101010101010101ull;
    return (y * 0x0102040810204080ull) >> 56;  // bit 8 j -> bit 56 + j, no carries
}

inline int sil_popcount64(std::uint64_t x) {
    x = x - ((x >> 1) & 0x5555555555555555ull);
    x = (x & 0x3333333333333333ull) + ((x >> 2) & 0x3333333333333333ull);
    x = (x + (x >> 4)) & 0x0F0F0F0F0F0F0F0Full;
    return static_cast<int>((x * 0x0101010101010101ull) >> 56);
}

// The facing bytes of 8 edges' faces: byte j of a = facing[f0], of b = facing[f1] of edge ef[j].
inline void sil_gather8(const std::uint64_t* ef, const std::uint8_t* facing, std::uint64_t& a, std::uint64_t& b) {
    a = 0;
    b = 0;
    for (unsigned j = 0; j < 8; ++j) {
        const std::uint64_t x = ef[j];
        a |= static_cast<std::uint64_t>(facing[static_cast<std::uint32_t>(x)]) << (8 * j);
        b |= static_cast<std::uint64_t>(facing[static_cast<std::uint32_t>(x >> 32)]) << (8 * j);
    }
}

// The 64 edges i0 .. i0 + 63 (i0 % 8 == 0, i0 + 64 <= edge count): returns the silhouette bits (bit
// j: edge i0 + j is a silhouette edge), lit0 bit j: its face f0 is lit. Branch-free.
inline std::uint64_t sil_planes_group(const SilhouettePlanes& pl, const std::uint8_t* facing, std::size_t i0, std::uint64_t& lit0) {
    const std::uint64_t* ef = pl.edge_faces.data() + i0;
    std::uint64_t l0 = 0, l1 = 0;
    for (unsigned k = 0; k < 64; k += 16) {
        std::uint64_t a0, b0, a1, b1;
        sil_gather8(ef + k, facing, a0, b0);
        sil_gather8(ef + k + 8, facing, a1, b1);
#if defined(SHADOWKIT_SIL_SSE2)
        const __m128i z = _mm_setzero_si128();
        const __m128i A = _mm_set_epi64x(static_cast<long long>(a1), static_cast<long long>(a0));
        const __m128i B = _mm_set_epi64x(static_cast<long long>(b1), static_cast<long long>(b0));
        l0 |= static_cast<std::uint64_t>(static_cast<std::uint32_t>(_mm_movemask_epi8(_mm_cmpeq_epi8(A, z))) ^ 0xFFFFu) << k;
        l1 |= static_cast<std::uint64_t>(static_cast<std::uint32_t>(_mm_movemask_epi8(_mm_cmpeq_epi8(B, z))) ^ 0xFFFFu) << k;
#else
        l0 |= (sil_byte_bits(a0) | sil_byte_bits(a1) << 8) << k;
        l1 |= (sil_byte_bits(b0) | sil_byte_bits(b1) << 8) << k;
#endif
    }
    std::uint64_t bnd;
    std::memcpy(&bnd, pl.edge_boundary.data() + i0 / 8, sizeof bnd);  // bit j: edge i0 + j is a boundary edge
    lit0 = l0;
    return ((l0 ^ l1) & ~bnd) | (l0 & bnd);  // a boundary edge (f1 = f0): s = l0
}

// The vertex pair v (v0, v1 in memory order) oriented as in the lit face: as loaded if lit0 (0 / 1),
// else swapped. Arithmetic, never a branch.
inline std::uint64_t sil_orient(std::uint64_t v, std::uint64_t lit0) {
    const std::uint64_t sw = v >> 32 | v << 32;
    return sw ^ ((v ^ sw) & (std::uint64_t(0) - lit0));
}

// Edge (a, b) = w (memory order) written at edge slot n: the pair (a, b) at out[2 n], or with Quads
// the side quad (b, a, a + nv, b, a + nv, b + nv) at out[6 n] (volume_build_side_quads' layout).
// Writes exactly those elements.
template <bool Quads>
inline void sil_put_edge(std::uint32_t* out, std::size_t n, std::uint64_t w, std::uint32_t nv) {
    if (!Quads) {
        std::memcpy(out + 2 * n, &w, sizeof w);
        return;
    }
#if defined(SHADOWKIT_SIL_SSE2)
#if defined(__x86_64__) || defined(_M_X64)
    const __m128i v = _mm_cvtsi64_si128(static_cast<long long>(w));  // a b 0 0
#else
    const __m128i v = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(&w));
#endif
    const __m128i t = _mm_unpacklo_epi64(v, _mm_add_epi32(v, _mm_set1_epi32(static_cast<int>(nv))));  // a b a+n b+n
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + 6 * n), _mm_shuffle_epi32(t, _MM_SHUFFLE(1, 2, 0, 1)));  // b a a+n b
    _mm_storel_epi64(reinterpret_cast<__m128i*>(out + 6 * n + 4), _mm_unpackhi_epi64(t, t));                // a+n b+n
#else
    std::uint32_t ab[2];
    std::memcpy(ab, &w, sizeof w);
    std::uint32_t* o = out + 6 * n;
    o[0] = ab[1]; o[1] = ab[0]; o[2] = ab[0] + nv;
    o[3] = ab[1]; o[4] = ab[0] + nv; o[5] = ab[1] + nv;
#endif
}

// sil_extract_range on the planes' edge layout: edges [begin, end) (and the non-manifold edges if
// `nonmanifold`) into out[0, room) edge slots, as pairs (2 uint32 per slot) or side quads (Quads: 6
// per slot, vertex offset nv); flags (pairs only) into edge_flags. Adds to r (needed in elements,
// boundary / non-manifold counts) and returns the number of edges found. 64 edges at a time: a
// branch-free pass gathers their faces' facing bytes (one 8-byte load of the face pair per edge),
// 16 edges' bytes at once become bits (SSE2 compare + movemask, else a multiply), s = l0 xor l1 (a
// boundary edge: s = l0); then only the silhouette edges are visited (lowest set bit first), each
// loads its vertex pair, orients it arithmetically and writes exactly its own elements. One loop exit
// per 64 edges is the only data-dependent branch.
template <bool Quads>
inline std::size_t sil_planes_extract_impl(const SilhouetteAdjacency& adj, const SilhouettePlanes& pl, const std::uint8_t* facing,
                                           std::uint32_t* out, std::uint8_t* edge_flags, std::size_t room, std::size_t begin,
                                           std::size_t end, bool nonmanifold, std::uint32_t nv, SilhouetteResult& r) {
    const std::uint64_t* ef = pl.edge_faces.data();
    const std::uint32_t* ev = pl.edge_vertices.data();
    const std::uint8_t* eb = pl.edge_boundary.data();
    std::size_t n = 0, boundary = 0;
    auto load = [&](std::size_t i) {
        std::uint64_t v;
        std::memcpy(&v, ev + 2 * i, sizeof v);  // v0, v1 in memory order
        return v;
    };
    auto emit = [&](std::uint64_t w, std::uint32_t bb) {  // with the room check
        if (n < room) {
            sil_put_edge<Quads>(out, n, w, nv);
            if (!Quads && edge_flags) edge_flags[n] = static_cast<std::uint8_t>(bb);  // SilhouetteBoundary == 1
        }
        ++n;
    };
    auto single = [&](std::size_t i) {
        const std::uint64_t x = ef[i];
        const std::uint32_t bb = (eb[i / 8] >> (i % 8)) & 1u;
        const bool l0 = facing[static_cast<std::uint32_t>(x)] != 0;
        const bool l1 = bb == 0 && facing[static_cast<std::uint32_t>(x >> 32)] != 0;
        if (l0 == l1) return;
        emit(sil_orient(load(i), l0 ? 1u : 0u), bb);
        boundary += bb;
    };
    std::size_t i0 = begin;
    for (; i0 < end && (i0 % 8) != 0; ++i0) single(i0);  // the boundary bytes cover edges 8 k .. 8 k + 7
    for (; i0 + 64 <= end; i0 += 64) {
        std::uint64_t l0 = 0;
        std::uint64_t s = sil_planes_group(pl, facing, i0, l0);
        if (s == 0) continue;
        std::uint64_t bnd;
        std::memcpy(&bnd, eb + i0 / 8, sizeof bnd);
        if (bnd != 0) boundary += static_cast<std::size_t>(sil_popcount64(s & bnd));
        if (n + 64 <= room) {  // every edge of the group fits
            if (!Quads && edge_flags) {
                for (; s != 0; s &= s - 1) {
                    const int j = sil_ctz64(s);
                    sil_put_edge<false>(out, n, sil_orient(load(i0 + static_cast<std::size_t>(j)), (l0 >> j) & 1u), nv);
                    edge_flags[n] = static_cast<std::uint8_t>((bnd >> j) & 1u);
                    ++n;
                }
            } else {
                for (; s != 0; s &= s - 1) {
                    const int j = sil_ctz64(s);
                    sil_put_edge<Quads>(out, n, sil_orient(load(i0 + static_cast<std::size_t>(j)), (l0 >> j) & 1u), nv);
                    ++n;
                }
            }
        } else {
            for (; s != 0; s &= s - 1) {
                const int j = sil_ctz64(s);
                emit(sil_orient(load(i0 + static_cast<std::size_t>(j)), (l0 >> j) & 1u), static_cast<std::uint32_t>((bnd >> j) & 1u));
            }
        }
    }
    for (; i0 < end; ++i0) single(i0);
    r.boundary_edges += boundary;
    if (nonmanifold)
        sil_nonmanifold_each(adj, facing, [&](std::uint32_t a, std::uint32_t b) {
            const std::uint32_t ab[2] = {a, b};
            std::uint64_t w;
            std::memcpy(&w, ab, sizeof w);
            emit(w, SilhouetteNonManifold);
            ++r.nonmanifold_edges;
        });
    r.needed += (Quads ? 6 : 2) * n;
    return n;
}

inline std::size_t sil_planes_extract_range(const SilhouetteAdjacency& adj, const SilhouettePlanes& pl, const std::uint8_t* facing,
                                            std::uint32_t* edge_indices, std::uint8_t* edge_flags, std::size_t room,
                                            std::size_t begin, std::size_t end, bool nonmanifold, SilhouetteResult& r) {
    return sil_planes_extract_impl<false>(adj, pl, facing, edge_indices, edge_flags, room, begin, end, nonmanifold, 0u, r);
}

// Union-find root with path halving (build time only).
inline std::uint32_t sil_class_root(std::vector<std::uint32_t>& parent, std::uint32_t f) {
    while (parent[f] != f) {
        parent[f] = parent[parent[f]];
        f = parent[f];
    }
    return f;
}

// SilhouettePlanes::plane_class: faces joined across every manifold edge whose two faces are exactly
// coplanar (the far vertex of f1 exactly on f0's plane: sil_face_sign == 0), each class's root its
// smallest face; flipped when the normals (relative 2^-30, exactly parallel: the sign is safe) oppose.
// normals: each kept face's cross product, as silhouette_build_planes computed it for the plane.
inline void sil_planes_classes(const SilhouetteAdjacency& adj, const glm::vec3* positions, const std::vector<glm::dvec3>& normals,
                               SilhouettePlanes& pl) {
    const std::size_t fc = adj.face_count();
    std::vector<std::uint32_t> parent(fc);
    for (std::size_t f = 0; f < fc; ++f) parent[f] = static_cast<std::uint32_t>(f);
    const std::uint32_t* fi = adj.faces.data();
    for (const SilhouetteEdge& e : adj.edges) {
        if (e.f1 == kSilhouetteNoFace || e.f0 == e.f1) continue;
        std::uint32_t far = fi[3 * std::size_t(e.f1)];
        for (int k = 1; k < 3; ++k) {
            const std::uint32_t v = fi[3 * std::size_t(e.f1) + std::size_t(k)];
            if (far == e.v0 || far == e.v1) far = v;
        }
        const glm::vec3* A = positions;
        if (sil_face_sign(A[fi[3 * std::size_t(e.f0)]], A[fi[3 * std::size_t(e.f0) + 1]], A[fi[3 * std::size_t(e.f0) + 2]],
                          glm::vec4(A[far], 1.0f)) != 0)
            continue;
        const std::uint32_t r0 = sil_class_root(parent, e.f0), r1 = sil_class_root(parent, e.f1);
        if (r0 < r1) parent[r1] = r0;
        else if (r1 < r0) parent[r0] = r1;
    }
    pl.plane_class.resize(fc);
    for (std::size_t f = 0; f < fc; ++f) {
        const std::uint32_t r = sil_class_root(parent, static_cast<std::uint32_t>(f));
        const glm::dvec3 &a = normals[f], &b = normals[r];
        const bool flip = r != f && a.x * b.x + a.y * b.y + a.z * b.z < 0.0;
        pl.plane_class[f] = r | (flip ? 0x80000000u : 0u);
    }
}

} // namespace detail

/// Once per rigid mesh (allocates): the cached face planes of `adj`'s kept faces for the fast exact
/// facing, and the adjacency's edges in the layout the fast extraction reads. `positions` holds
/// vertex_count glm::vec3: the buffer the adjacency was built from (its count; NaN/Inf: NonFinite).
/// A failed adjacency: InvalidArgument. Positions that change later need a new call (or the
/// per-frame silhouette_compute_facing, which takes fresh positions).
inline SilhouettePlanes silhouette_build_planes(const SilhouetteAdjacency& adj, const glm::vec3* positions, std::size_t vertex_count) {
    SilhouettePlanes pl;
    if (adj.status != Status::Ok || vertex_count != adj.vertex_count || (vertex_count > 0 && positions == nullptr)) {
        pl.status = Status::InvalidArgument;
        pl.detail = adj.status != Status::Ok ? "adj: status not Ok"
                    : (vertex_count != adj.vertex_count ? "vertex_count: not adj.vertex_count" : "positions: null with vertex_count > 0");
        return pl;
    }
    for (std::size_t i = 0; i < vertex_count; ++i)
        if (!detail::sil_finite(positions[i])) { pl.status = Status::NonFinite; pl.detail = "positions: NaN or Inf"; return pl; }
    pl.vertex_count = adj.vertex_count;
    pl.positions.assign(positions, positions + vertex_count);
    glm::vec3 lo(0.0f), hi(0.0f);
    if (vertex_count > 0) {
        lo = hi = positions[0];
        for (std::size_t i = 1; i < vertex_count; ++i) {
            lo = glm::vec3(std::fmin(lo.x, positions[i].x), std::fmin(lo.y, positions[i].y), std::fmin(lo.z, positions[i].z));
            hi = glm::vec3(std::fmax(hi.x, positions[i].x), std::fmax(hi.y, positions[i].y), std::fmax(hi.z, positions[i].z));
        }
    }
    // O: the bounds' center (any float works; this one keeps |A - O| small); R >= the half extent
    pl.origin = glm::vec3(static_cast<float>(0.5 * (static_cast<double>(lo.x) + hi.x)),
                          static_cast<float>(0.5 * (static_cast<double>(lo.y) + hi.y)),
                          static_cast<float>(0.5 * (static_cast<double>(lo.z) + hi.z)));
    double half = 0.0;
    for (int k = 0; k < 3; ++k)
        half = std::fmax(half, std::fmax(std::fabs(static_cast<double>(hi[k]) - pl.origin[k]),
                                         std::fabs(static_cast<double>(lo[k]) - pl.origin[k])));
    int ex = 0;
    if (half > 0.0) (void)std::frexp(half, &ex);  // half < 2^ex
    pl.scale = std::ldexp(1.0, ex);
    const std::size_t fc = adj.face_count();
    pl.plane_x.resize(fc);
    pl.plane_y.resize(fc);
    pl.plane_z.resize(fc);
    pl.plane_w.resize(fc);
    const glm::vec4 axes[3] = {glm::vec4(1.0f, 0.0f, 0.0f, 0.0f), glm::vec4(0.0f, 1.0f, 0.0f, 0.0f), glm::vec4(0.0f, 0.0f, 1.0f, 0.0f)};
    const glm::vec4 center(pl.origin, 1.0f);
    std::vector<glm::dvec3> normals(fc);  // the planes' normals, for the plane classes
    for (std::size_t f = 0; f < fc; ++f) {
        const glm::vec3& A = positions[adj.faces[3 * f]];
        const glm::vec3& B = positions[adj.faces[3 * f + 1]];
        const glm::vec3& C = positions[adj.faces[3 * f + 2]];
        const double P[4] = {detail::sil_face_value(A, B, C, axes[0]), detail::sil_face_value(A, B, C, axes[1]),
                             detail::sil_face_value(A, B, C, axes[2]), detail::sil_face_value(A, B, C, center) / pl.scale};
        normals[f] = glm::dvec3(P[0], P[1], P[2]);
        double m = 0.0;
        for (double v : P) m = std::fmax(m, std::fabs(v));
        float out[4] = {0.0f, 0.0f, 0.0f, 0.0f};
        bool exact_only = !(m > 0.0);  // cannot happen for a kept face (non-zero cross product)
        if (!exact_only) {
            (void)std::frexp(m, &ex);
            for (int k = 0; k < 4; ++k) {
                out[k] = static_cast<float>(std::ldexp(P[k], 1 - ex));
                if (P[k] != 0.0 && !(std::fabs(out[k]) >= 0x1p-126f)) exact_only = true;  // subnormal: not relative
            }
        }
        if (exact_only) {
            out[0] = out[1] = out[2] = out[3] = 0.0f;  // d_float = 0: always inside the bound
            ++pl.exact_faces;
        }
        pl.plane_x[f] = out[0];
        pl.plane_y[f] = out[1];
        pl.plane_z[f] = out[2];
        pl.plane_w[f] = out[3];
    }
    detail::sil_planes_classes(adj, positions, normals, pl);
    pl.edge_faces.resize(adj.edges.size());
    pl.edge_boundary.assign((adj.edges.size() + 7) / 8, 0);
    pl.edge_vertices.resize(2 * adj.edges.size());
    for (std::size_t i = 0; i < adj.edges.size(); ++i) {
        const SilhouetteEdge& E = adj.edges[i];
        const bool boundary = E.f1 == kSilhouetteNoFace;
        pl.edge_faces[i] = static_cast<std::uint64_t>(E.f0) | static_cast<std::uint64_t>(boundary ? E.f0 : E.f1) << 32;
        if (boundary) pl.edge_boundary[i / 8] = static_cast<std::uint8_t>(pl.edge_boundary[i / 8] | (1u << (i % 8)));
        pl.edge_vertices[2 * i] = E.v0;
        pl.edge_vertices[2 * i + 1] = E.v1;
    }
    pl.status = Status::Ok;
    return pl;
}

/// The fast exact facing of a rigid mesh: facing[f] = 1 if kept face f is lit by light_position,
/// else 0, bit for bit silhouette_compute_facing's (for the positions `planes` was built from).
/// No allocation. `planes` from silhouette_build_planes(adj, ...) (else InvalidArgument). `facing`
/// holds facing_capacity uint8 elements; it needs adj.face_count() (`needed`).
inline SilhouetteFacing silhouette_compute_facing_planes(const SilhouetteAdjacency& adj, const SilhouettePlanes& planes,
                                                         const glm::vec4& light_position, std::uint8_t* facing,
                                                         std::size_t facing_capacity) {
    SilhouetteFacing r;
    r.needed = adj.face_count();
    r.status = detail::sil_check_planes_facing_args(adj, planes, light_position, facing, facing_capacity, r.detail);
    if (r.status != Status::Ok) return r;
    r.lit_faces = detail::sil_planes_facing_range(adj, planes, light_position, facing, 0, r.needed, &r.exact_evaluations);
    r.count = r.needed;
    return r;
}

/// silhouette_compute_facing_planes for chunk `chunk` of `chunk_count` (faces split as in
/// silhouette_compute_facing_chunk; count / lit_faces are this chunk's). chunk < chunk_count.
inline SilhouetteFacing silhouette_compute_facing_planes_chunk(const SilhouetteAdjacency& adj, const SilhouettePlanes& planes,
                                                               const glm::vec4& light_position, std::uint8_t* facing,
                                                               std::size_t facing_capacity, std::size_t chunk,
                                                               std::size_t chunk_count) {
    SilhouetteFacing r;
    r.needed = adj.face_count();
    if (chunk_count == 0 || chunk >= chunk_count) { r.status = Status::InvalidArgument; r.detail = chunk_count == 0 ? "chunk_count: 0" : "chunk: >= chunk_count"; return r; }
    r.status = detail::sil_check_planes_facing_args(adj, planes, light_position, facing, facing_capacity, r.detail);
    if (r.status != Status::Ok) return r;
    const std::size_t fc = adj.face_count();
    const std::size_t b = detail::sil_chunk_begin(fc, chunk, chunk_count), e = detail::sil_chunk_begin(fc, chunk + 1, chunk_count);
    r.lit_faces = detail::sil_planes_facing_range(adj, planes, light_position, facing, b, e, &r.exact_evaluations);
    r.count = e - b;
    return r;
}

/// silhouette_extract on the planes' edge layout: the same edges, order, flags and counts, faster
/// (reads 8 bytes per edge, and the vertices of silhouette edges only). Buffers as silhouette_extract.
inline SilhouetteResult silhouette_extract_planes(const SilhouetteAdjacency& adj, const SilhouettePlanes& planes,
                                                  const std::uint8_t* facing, std::size_t facing_count,
                                                  std::uint32_t* edge_indices, std::size_t edge_indices_capacity,
                                                  std::uint8_t* edge_flags, std::size_t edge_flags_capacity) {
    SilhouetteResult r;
    r.status = detail::sil_check_extract_args(adj, facing, facing_count, edge_indices, edge_indices_capacity, edge_flags,
                                              edge_flags_capacity, r.detail);
    if (r.status == Status::Ok) r.status = detail::sil_check_planes(adj, planes, r.detail);
    if (r.status != Status::Ok) return r;
    std::size_t room = edge_indices_capacity / 2;
    if (edge_flags && edge_flags_capacity < room) room = edge_flags_capacity;
    const std::size_t n =
        detail::sil_planes_extract_range(adj, planes, facing, edge_indices, edge_flags, room, 0, adj.edges.size(), true, r);
    r.count = 2 * (n < room ? n : room);
    if (r.count < r.needed) {
        r.status = Status::BufferTooSmall;
        r.detail = "edge_indices_capacity or edge_flags_capacity: below needed (see needed)";
    }
    return r;
}

/// The side quads of the silhouette in one pass, for shadow_volume.hpp: for each edge (a, b) that
/// silhouette_extract_planes finds, in its order, the six indices (b, a, a + n, b, a + n, b + n), n =
/// adj.vertex_count: byte for byte what volume_build_side_quads(edges, count, n, ...) writes for
/// those edges (the 2n-vertex volume buffer of volume_build_vertices: i is (p_i, 1), i + n is
/// (p_i, 0)), without the intermediate edge buffer and its second pass. `out` holds out_capacity
/// uint32 elements; it needs 6 per silhouette edge (at most 3 * silhouette_indices_capacity(adj),
/// `needed`); a short buffer gets the whole quads that fit (BufferTooSmall). count / needed are
/// uint32 elements (6 per edge); boundary_edges / nonmanifold_edges as silhouette_extract. No flags,
/// no allocation; writes only out[0, count). adj.vertex_count > 2^31 - 1: InvalidArgument.
inline SilhouetteResult silhouette_extract_planes_side_quads(const SilhouetteAdjacency& adj, const SilhouettePlanes& planes,
                                                             const std::uint8_t* facing, std::size_t facing_count, std::uint32_t* out,
                                                             std::size_t out_capacity) {
    SilhouetteResult r;
    r.status = detail::sil_check_extract_args(adj, facing, facing_count, out, out_capacity, nullptr, 0, r.detail);
    if (r.status == Status::Ok) r.status = detail::sil_check_planes(adj, planes, r.detail);
    if (r.status == Status::Ok && adj.vertex_count > 0x7FFFFFFFu) {
        r.status = Status::InvalidArgument;
        r.detail = "adj: vertex_count > 2^31 - 1 (side quads index 2 n vertices)";
    }
    if (r.status != Status::Ok) return r;
    const std::size_t room = out_capacity / 6;
    const std::size_t n = detail::sil_planes_extract_impl<true>(adj, planes, facing, out, nullptr, room, 0, adj.edges.size(), true,
                                                                adj.vertex_count, r);
    r.count = 6 * (n < room ? n : room);
    if (r.count < r.needed) {
        r.status = Status::BufferTooSmall;
        r.detail = "out_capacity: below needed (see needed)";
    }
    return r;
}

/// silhouette_extract_chunk on the planes' edge layout (same offsets, rooms and results).
inline SilhouetteResult silhouette_extract_planes_chunk(const SilhouetteAdjacency& adj, const SilhouettePlanes& planes,
                                                        const std::uint8_t* facing, std::size_t facing_count,
                                                        std::uint32_t* edge_indices, std::size_t edge_indices_capacity,
                                                        std::uint8_t* edge_flags, std::size_t edge_flags_capacity,
                                                        std::size_t chunk, std::size_t chunk_count) {
    SilhouetteResult r;
    if (chunk_count == 0 || chunk >= chunk_count) { r.status = Status::InvalidArgument; r.detail = chunk_count == 0 ? "chunk_count: 0" : "chunk: >= chunk_count"; return r; }
    r.status = detail::sil_check_extract_args(adj, facing, facing_count, edge_indices, edge_indices_capacity, edge_flags,
                                              edge_flags_capacity, r.detail);
    if (r.status == Status::Ok) r.status = detail::sil_check_planes(adj, planes, r.detail);
    if (r.status != Status::Ok) return r;
    const std::size_t max_edges = adj.max_silhouette_edges();
    if (edge_indices_capacity / 2 < max_edges || (edge_flags && edge_flags_capacity < max_edges)) {
        r.status = Status::BufferTooSmall;
        r.detail = "edge_indices_capacity or edge_flags_capacity: below silhouette_indices_capacity(adj)";
        return r;
    }
    const std::size_t ec = adj.edges.size();
    const std::size_t b = detail::sil_chunk_begin(ec, chunk, chunk_count), e = detail::sil_chunk_begin(ec, chunk + 1, chunk_count);
    const std::size_t room = chunk + 1 == chunk_count ? max_edges - b : e - b;
    const std::size_t n = detail::sil_planes_extract_range(adj, planes, facing, edge_indices + 2 * b,
                                                           edge_flags ? edge_flags + b : nullptr, room, b, e,
                                                           chunk + 1 == chunk_count, r);
    r.count = 2 * n;
    return r;
}

/// silhouette_extract_parallel for a rigid mesh: the cached-plane facing and the fast extraction in
/// chunks on a caller's parallel_for, then silhouette_compact_chunks. Buffers as there; the output
/// is identical to silhouette_compute_facing + silhouette_extract.
template <class ParallelFor>
inline SilhouetteResult silhouette_extract_parallel_planes(const SilhouetteAdjacency& adj, const SilhouettePlanes& planes,
                                                           const glm::vec4& light_position, std::uint8_t* facing,
                                                           std::size_t facing_capacity, std::uint32_t* edge_indices,
                                                           std::size_t edge_indices_capacity, std::uint8_t* edge_flags,
                                                           std::size_t edge_flags_capacity, SilhouetteResult* chunk_results,
                                                           std::size_t chunk_count, ParallelFor&& parallel_for) {
    SilhouetteResult r;
    if (chunk_count == 0 || chunk_results == nullptr) {
        r.status = Status::InvalidArgument;
        r.detail = chunk_count == 0 ? "chunk_count: 0" : "chunk_results: null";
        return r;
    }
    r.status = detail::sil_check_planes_facing_args(adj, planes, light_position, facing, facing_capacity, r.detail);
    if (r.status != Status::Ok) return r;
    const std::size_t fc = adj.face_count();
    r.status = detail::sil_check_extract_args(adj, facing, fc, edge_indices, edge_indices_capacity, edge_flags, edge_flags_capacity,
                                              r.detail);
    if (r.status != Status::Ok) return r;
    const std::size_t cap = silhouette_indices_capacity(adj);
    if (edge_indices_capacity < cap || (edge_flags && edge_flags_capacity < cap / 2)) {
        r.status = Status::BufferTooSmall;
        r.detail = "edge_indices_capacity or edge_flags_capacity: below needed (see needed)";
        r.needed = cap;
        return r;
    }
    for (std::size_t c = 0; c < chunk_count; ++c) chunk_results[c] = SilhouetteResult{};
    parallel_for(chunk_count, [&](std::size_t c) {
        detail::sil_planes_facing_range(adj, planes, light_position, facing, detail::sil_chunk_begin(fc, c, chunk_count),
                                        detail::sil_chunk_begin(fc, c + 1, chunk_count));
    });
    parallel_for(chunk_count, [&](std::size_t c) {
        chunk_results[c] = silhouette_extract_planes_chunk(adj, planes, facing, fc, edge_indices, edge_indices_capacity, edge_flags,
                                                           edge_flags_capacity, c, chunk_count);
    });
    return silhouette_compact_chunks(adj, chunk_results, chunk_count, edge_indices, edge_indices_capacity, edge_flags,
                                     edge_flags_capacity);
}

/// Facing, silhouette edges (2 uint32 per edge) and their flags, in vectors (silhouette_compute).
struct Silhouette {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    std::vector<std::uint8_t> facing;   ///< adj.face_count() bits
    std::vector<std::uint32_t> indices; ///< 2 per edge, oriented as in the lit face
    std::vector<std::uint8_t> flags;    ///< one SilhouetteFlag mask per edge
};

/// Convenience (allocates): silhouette_compute_facing + silhouette_extract into vectors.
inline Silhouette silhouette_compute(const SilhouetteAdjacency& adj, const glm::vec3* positions, std::size_t vertex_count,
                                     const glm::vec4& light_position) {
    Silhouette s;
    s.facing.resize(adj.face_count());
    const SilhouetteFacing fr = silhouette_compute_facing(adj, positions, vertex_count, light_position, s.facing.data(), s.facing.size());
    if (fr.status != Status::Ok) { s.status = fr.status; s.detail = fr.detail; s.facing.clear(); return s; }
    const std::size_t cap = silhouette_indices_capacity(adj);
    s.indices.resize(cap);
    s.flags.resize(cap / 2);
    const SilhouetteResult r = silhouette_extract(adj, s.facing.data(), s.facing.size(), s.indices.data(), s.indices.size(),
                                                  s.flags.data(), s.flags.size());
    s.status = r.status;
    s.detail = r.detail;
    s.indices.resize(r.count);
    s.flags.resize(r.count / 2);
    return s;
}

} // namespace shadowkit
