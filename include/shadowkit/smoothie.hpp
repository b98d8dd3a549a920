// shadowkit/smoothie.hpp - "smoothies": fake soft shadows from silhouette geometry. Builds the
// smoothie edge quads, corner quads and valence > 2 fans from plain silhouette data, plus the CPU
// side of the alpha remap (eq. 1), the sinusoidal falloff, the per-tap visibility rule and the
// mapping between the smoothie width t and an area light's size. GPU side: glsl/smoothie.glsl.
//
// Usage:
//   #include <shadowkit/smoothie.hpp>
//   namespace sk = shadowkit;
//   sk::SmoothieEdges in;                         // silhouette edges, e.g. from silhouette.hpp
//   in.positions = pos; in.position_count = n;    // world space
//   in.edges = sil; in.edge_count = k;            // 2 indices per edge, oriented as in face_normals[2i]
//   in.face_normals = fn;                         // 2 per edge (second = (0,0,0) for a boundary edge)
//   sk::SmoothieParams p;  p.t = 0.05f;           // width in light NDC units (see below)
//   std::vector<sk::SmoothieVertex> vb(sk::smoothie_vertex_capacity(k));
//   sk::SmoothieResult r = sk::build_smoothies(in, light_view_proj, p, vb.data(), vb.size());
//   // r.vertices_written vertices = triangle list; upload and draw with glsl/smoothie.glsl.
//
// Based on:
//   E. Chan, F. Durand, "Rendering Fake Soft Shadows with Smoothies", EGSR 2003: section 3 step 3
//   (edges, corners, valence > 2 special case), section 3.1 (eq. 1 remap, corner alpha |v - p|/t,
//   minimum blending, sinusoidal falloff), section 4 (passes).
//   E. Chan, "Rendering Fake Soft Shadows with Smoothies", SIGGRAPH 2004 course #26 "Real-Time Shadowing
//   Techniques" notes (concave silhouette corners omitted; linear depth in the shadow map).
//   E. Haines, "Soft Planar Shadows Using Plateaus", JGT 6(1) 2001 (sinusoidal falloff).
//
// Units and conventions (used by every function):
//   * t is measured in light NDC units: the light's image spans [-1, 1], i.e. 2 units wide. (A
//     width in shadow-map uv [0, 1] is t / 2.) The paper's useful range 0.02 .. 0.2 applies.
//   * Light NDC = clip.xy / clip.w of light_view_proj * (p, 1); column-major, right-handed (GLM).
//   * Linear depth: the distance from the light along its axis, -(light_view * p).z, the same
//     quantity in the shadow map, the smoothie buffer and the receiver (glsl/smoothie.glsl).
//     Eq. 1 uses the ratio b / r, which is the same for the axial and the Euclidean distance of
//     points on one light ray, so either works if used everywhere.
//   * Edge quad: the silhouette edge P0 P1 plus outer vertices O0, O1 whose light NDC is that of
//     P0, P1 moved by exactly t along the unit outward perpendicular n of the projected edge, at
//     the same clip w and clip z as P0, P1 (same light-space depth), then un-projected. In light
//     NDC it is a t-wide rectangle; alpha = (NDC distance to the edge's line) / t, 0 on the
//     silhouette, 1 at the outer side, exact under screen-linear (noperspective) interpolation.
//   * Outward side: away from the occluder's interior as seen from the light. Found per edge from
//     (in this order) the hint outward[i] (any world direction pointing out of the occluder at the
//     edge); else the sum of the two unit face normals (a closed mesh's faces at a silhouette edge
//     both project to the interior side, their normals' sum points away from it); else (boundary
//     edge, or an ambiguous sum) the winding of face 0: the interior of face 0 is on the side of
//     cross(n0, P1 - P0), so edges must run v0 -> v1 as in face 0, counter-clockwise about n0 (as
//     silhouette.hpp emits them, oriented as in the lit face). The side is the sign of the
//     light-NDC image of that direction (exact Jacobian of the projection at the edge midpoint).
//   * Corners. Around a silhouette vertex v the kept edges are sorted by the angle of their light-NDC
//     direction u_i away from v; the sector between angularly consecutive edges j, j+1 is exterior
//     when n_j turns counter-clockwise from u_j into it and n_j+1 clockwise from u_j+1 into it. An
//     exterior sector wider than 180 degrees (a convex turn) leaves a gap between the edge quads'
//     outer vertices v + t n_j and v + t n_j+1; it is filled by two quads (v, v + t n_j, m1, v + t b)
//     and (v, v + t b, m2, v + t n_j+1), b = the sector's middle direction, m = intersection of the
//     tangents at the arc ends, so the circular sector of radius t is covered. The outer vertices
//     shared with the edge quads are bit-identical. Alpha = |p - v| / t in light NDC (fragment stage),
//     clamped. Concave turns (exterior sector <= 180 degrees) need no corner: the edge quads overlap
//     and minimum blending keeps the smaller alpha (Chan's course notes omit them too). For valence 2
//     this is the paper's corner; for valence > 2 (two blockers touching at a vertex, a pinched mesh)
//     it fills every exterior gap. The paper's special case (the unit average n_a of the outward
//     normals and a fan from each v + t n_i to v + t n_a, split at the middle direction) is used when
//     the sectors are inconsistent (normals contradicting each other) or if params.paper_fans is set;
//     it covers the gaps in the cases tested but also draws corner geometry over the blockers'
//     interior (overdraw only: receivers behind the blocker's interior are in its umbra anyway).
//   * Vertex with one kept edge (open chain, or its neighbour was skipped because it is seen end-on):
//     a quarter cap, the sector from n to the edge's continuation; it closes the gap left by an
//     end-on neighbour edge whose two ends project to the same point.
//   * Edges are clipped against the light's near plane (ClipDepth, reversed_z); a clipped end gets
//     no corner. Corners use vertex indices: weld positions first (silhouette.hpp does).
//   * t == 0 produces NO geometry (status Ok, vertex_count 0, no edge examined or counted): the
//     smoothie buffer stays at its clear value and the final pass is exactly the hard shadow test.
//     For t > 0 every edge is counted once: edge_quads + skipped_* (except skipped_corners) = edge_count.
//   * Output: a non-indexed triangle list of SmoothieVertex, counter-clockwise in light NDC
//     (draw with face culling off anyway: mirrored viewports flip it). Edge quads first (6 vertices
//     each), then corners, caps and fans.
//
// Skipped and counted (never NaN in the output): out-of-range indices, NaN/Inf positions, zero
// length edges (same index or equal positions), edges entirely in front of the near plane or behind
// the light (w <= 0), edges seen end-on (projecting to a point), edges without a usable outward
// direction, outer vertices that cannot be un-projected (non-finite). Rejected with a status: null
// pointers with non-zero counts, neither normals nor hints, t NaN/Inf/negative, a non-finite or
// singular light matrix.
//
// t and an area light (the mapping the report uses). For a perspective light with projection scale
// s = P[0][0] = 1 / tan(fov_x / 2), a blocker edge at linear depth b and a receiver plane facing the
// light at depth r > b, the remapped alpha goes 0 -> 1 over an NDC distance t (r - b) / r, i.e. a
// world width on the receiver of
//     W_smoothie = t (r - b) / s.
// A light of width w (diameter) centred on the point light gives a geometric penumbra
//     W_area = w (r - b) / b.
// They agree for every receiver depth iff t = s w / b: t is the light's width as it would appear in
// light NDC if it were placed at the blocker's depth (smoothie_width_for_area_light). The smoothie
// penumbra lies entirely outside the hard shadow (the umbra does not shrink), the area light's is
// centred on it: compare widths, and expect the smoothie edge shifted outwards by W / 2.
// Orthographic (directional) light, s = P[0][0] = 2 / frustum width, depths measured from the
// light's view origin: W_smoothie = t (r - b) / (r s), an angular diameter theta gives
// W = theta (r - b); they agree at one receiver depth r_ref only: t = theta s r_ref.
//
// MIT License. Copyright (c) shadowkit contributors.
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <utility>
#include <vector>

namespace shadowkit {

#ifndef SHADOWKIT_CLIP_DEPTH_DEFINED
#define SHADOWKIT_CLIP_DEPTH_DEFINED
/// Clip-space depth range of the projection: OpenGL [-1,1] or D3D/Vulkan/glClipControl [0,1].
enum class ClipDepth { NegativeOneToOne, ZeroToOne };
#endif

enum class SmoothieStatus {
    Ok,
    InvalidArgument,  ///< null pointer with a non-zero count, no normals and no hints, t NaN/Inf/< 0
    InvalidMatrix,    ///< light_view_proj not finite or singular
    BufferTooSmall    ///< output truncated to whole triangles; vertex_count is the needed count
};

/// Silhouette edges as plain arrays. Pointers are borrowed for the call.
struct SmoothieEdges {
    const glm::vec3* positions = nullptr;     ///< world-space vertex positions
    std::size_t position_count = 0;
    const std::uint32_t* edges = nullptr;     ///< 2 indices per edge (v0, v1)
    std::size_t edge_count = 0;               ///< number of edges (the array holds 2 * edge_count)
    /// Optional, 2 per edge: [2i] normal of the face that runs v0 -> v1 counter-clockwise (the lit
    /// face from silhouette.hpp), [2i+1] the other face's normal or (0,0,0) for a boundary edge.
    /// Any length; zero/NaN normals are ignored.
    const glm::vec3* face_normals = nullptr;
    /// Optional, 1 per edge: a world direction pointing away from the occluder at the edge. Used
    /// before the normals when finite and non-zero.
    const glm::vec3* outward = nullptr;
};

struct SmoothieParams {
    float t = 0.0f;  ///< smoothie width [Units: light NDC, image = 2 wide] [Limit: finite, >= 0]; 0 = no geometry
    ClipDepth clip_depth = ClipDepth::NegativeOneToOne;  ///< of light_view_proj (for near-plane clipping)
    bool reversed_z = false;                             ///< near plane maps to depth 1 (ZeroToOne) / +1
    /// Vertices with > 2 silhouette edges: false (default) = sector rule (fills exactly the convex
    /// gaps, see the header comment), falling back to the averaged fan only for inconsistent
    /// normals; true = always the paper's averaged-normal fan (12 vertices per edge at the vertex).
    bool paper_fans = false;
};

/// One vertex of the smoothie triangle list (48 bytes, no padding surprises: 12 floats).
struct SmoothieVertex {
    glm::vec3 position;           ///< world position
    float alpha;                  ///< alpha at this vertex: edges 0 (silhouette) / 1 (outer); corners min(1, |p - v|/t)
    glm::vec3 silhouette_vertex;  ///< world position of the silhouette vertex this vertex belongs to
    float inv_t;                  ///< 1 / t
    glm::vec2 outward;            ///< unit light-NDC direction: edges the edge's outward normal; corners (p - v)/|p - v| (0 at v)
    float corner;                 ///< 0 = edge quad (interpolate alpha noperspective), 1 = corner / cap / fan (alpha = |p - v| / t)
    float reserved;               ///< 0
};
static_assert(sizeof(SmoothieVertex) == 12 * sizeof(float), "SmoothieVertex must be 12 tightly packed floats");

struct SmoothieResult {
    SmoothieStatus status = SmoothieStatus::Ok;
    std::size_t vertex_count = 0;      ///< vertices needed (3 per triangle)
    std::size_t vertices_written = 0;  ///< min(vertex_count, capacity) rounded down to whole triangles
    std::size_t edge_quads = 0;        ///< edges that produced a quad (6 vertices each, written first)
    std::size_t corners = 0;           ///< gaps filled at convex turns (12 vertices each), any valence
    std::size_t concave_turns = 0;     ///< exterior sectors <= 180 degrees (edge quads overlap: no corner)
    std::size_t caps = 0;              ///< valence-1 quarter caps (6 vertices each)
    std::size_t multi_vertices = 0;    ///< vertices with > 2 kept silhouette edges
    std::size_t fans = 0;              ///< vertices given the averaged-normal fan (12 vertices per edge)
    std::size_t clipped_edges = 0;     ///< edges cut by the near plane (kept)
    std::size_t skipped_invalid = 0;   ///< out-of-range index, NaN/Inf position, zero length
    std::size_t skipped_behind = 0;    ///< entirely in front of the near plane / behind the light
    std::size_t skipped_end_on = 0;    ///< projects to a point in light NDC
    std::size_t skipped_no_outward = 0;///< no usable hint / normals, or the side is ambiguous
    std::size_t skipped_unprojectable = 0; ///< edges whose outer vertex could not be un-projected
    std::size_t skipped_corners = 0;   ///< corners / caps / fans dropped: a vertex could not be un-projected
};

/// Upper bound on build_smoothies' vertex_count for edge_count edges (6 per edge + 12 per endpoint).
inline std::size_t smoothie_vertex_capacity(std::size_t edge_count) {
    const std::size_t lim = static_cast<std::size_t>(-1) / 30u;
    return edge_count > lim ? static_cast<std::size_t>(-1) : 30u * edge_count;
}

// ------------------------------------------------------------------------------------------------
// Alpha remap, falloff, visibility rule, t <-> light size
// ------------------------------------------------------------------------------------------------

/// Chan & Durand 2003 eq. 1: alpha' = clamp(alpha / (1 - b/r), 0, 1), b = linear depth of the
/// smoothie, r = linear depth of the receiver (both from the light). b/r >= 1 (the receiver is in
/// front of the smoothie) -> 1. Evaluated as alpha r / (r - b) in double. alpha is clamped to
/// [0,1] first; NaN inputs, r <= 0 or b < 0 -> 1 (no smoothie effect).
inline float smoothie_remap_alpha(float alpha, float b, float r) {
    if (std::isnan(alpha) || std::isnan(b) || std::isnan(r) || !(r > 0.0f) || b < 0.0f) return 1.0f;
    const double a = alpha < 0.0f ? 0.0 : (alpha > 1.0f ? 1.0 : static_cast<double>(alpha));
    const double rd = static_cast<double>(r), bd = static_cast<double>(b);
    if (!(bd < rd)) return 1.0f;  // b/r >= 1 (also r = +Inf with b = +Inf)
    if (std::isinf(rd)) return static_cast<float>(a);  // b/r -> 0
    const double d = rd - bd;
    const double v = a * rd / d;
    return v >= 1.0 ? 1.0f : static_cast<float>(v);
}

/// Sinusoidal falloff (Haines 2001, used by Chan & Durand 2003 section 3.1): s(a) = sin^2(pi a / 2)
/// for a in [0,1] (clamped; NaN -> 1). s(0) = 0, s(1) = 1, s(1 - a) = 1 - s(a), s' = 0 at both ends.
inline float smoothie_falloff(float a) {
    if (std::isnan(a) || a >= 1.0f) return 1.0f;
    if (a <= 0.0f) return 0.0f;
    const double s = std::sin(1.5707963267948966 * static_cast<double>(a));
    return static_cast<float>(s * s);
}

/// One tap of the final pass (the GLSL sk_smoothie_visibility does this at 4 texels and filters):
/// receiver linear depth r, shadow-map linear depth z, smoothie buffer (depth b, raw alpha).
/// r > z + bias -> 0 (umbra); else r > b -> falloff(remap(alpha, b, r)); else 1.
/// With the cleared smoothie buffer (b = +huge, alpha = 1) this is exactly the hard test.
inline float smoothie_visibility_tap(float r, float z, float b, float alpha, float bias) {
    if (r > z + bias) return 0.0f;
    if (r > b) return smoothie_falloff(smoothie_remap_alpha(alpha, b, r));
    return 1.0f;
}

/// t (light NDC) that makes the smoothie penumbra as wide as the geometric penumbra of a light of
/// width light_width (world) for a blocker at linear depth b: t = s w / b, s = P[0][0] of the
/// light's projection (1/tan(fov_x/2)). Invalid input (non-finite, b <= 0, w < 0, s <= 0) -> 0.
inline float smoothie_width_for_area_light(float light_width, float b, float proj_scale) {
    if (!std::isfinite(light_width) || !std::isfinite(b) || !std::isfinite(proj_scale) || light_width < 0.0f ||
        !(b > 0.0f) || !(proj_scale > 0.0f))
        return 0.0f;
    const double t = static_cast<double>(proj_scale) * static_cast<double>(light_width) / static_cast<double>(b);
    return t > 3.0e38 ? 3.0e38f : static_cast<float>(t);
}

/// Inverse of smoothie_width_for_area_light: w = t b / s. Invalid input -> 0.
inline float smoothie_area_light_width(float t, float b, float proj_scale) {
    if (!std::isfinite(t) || !std::isfinite(b) || !std::isfinite(proj_scale) || t < 0.0f || !(b > 0.0f) ||
        !(proj_scale > 0.0f))
        return 0.0f;
    const double w = static_cast<double>(t) * static_cast<double>(b) / static_cast<double>(proj_scale);
    return w > 3.0e38 ? 3.0e38f : static_cast<float>(w);
}

/// World width over which the remapped alpha goes 0 -> 1 on a receiver plane facing a perspective
/// light at linear depth r, cast by a smoothie at depth b: t (r - b) / s (0 when r <= b or invalid).
inline float smoothie_penumbra_width(float t, float b, float r, float proj_scale) {
    if (!std::isfinite(t) || !std::isfinite(b) || !std::isfinite(r) || !std::isfinite(proj_scale) || t < 0.0f ||
        !(proj_scale > 0.0f) || !(r > b))
        return 0.0f;
    const double w = static_cast<double>(t) * (static_cast<double>(r) - static_cast<double>(b)) / static_cast<double>(proj_scale);
    return w > 3.0e38 ? 3.0e38f : static_cast<float>(w);
}

// ------------------------------------------------------------------------------------------------
// Geometry
// ------------------------------------------------------------------------------------------------

namespace detail {

struct SmoothieEdgeInfo {
    glm::dvec3 P[2];   // world (after near clipping)
    glm::dvec4 C[2];   // clip
    glm::dvec2 A[2];   // light NDC
    glm::dvec2 n;      // unit outward normal in light NDC
};

struct SmoothieEnd {
    std::uint32_t vertex;
    std::uint32_t edge;  // index into the kept-edge list
    std::uint32_t end;   // 0 or 1
};

struct SmoothieV {
    glm::dvec3 world;
    glm::dvec2 ndc;
    double alpha;
    glm::dvec3 sil;
    glm::dvec2 out;
    float corner;
};

inline bool smoothie_finite3(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
inline bool smoothie_finite3d(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

inline glm::dvec3 smoothie_d(const glm::vec3& v) { return glm::dvec3(v.x, v.y, v.z); }

inline glm::dvec4 smoothie_mul(const glm::dmat4& m, const glm::dvec3& p) {
    return m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3];
}

// Signed distance to the near plane in clip space (>= 0: kept).
inline double smoothie_near_dist(const glm::dvec4& c, ClipDepth cd, bool reversed) {
    if (reversed) return c.w - c.z;
    return cd == ClipDepth::ZeroToOne ? c.z : c.z + c.w;
}

inline double smoothie_len(const glm::dvec2& v) { return std::sqrt(v.x * v.x + v.y * v.y); }
inline double smoothie_cross(const glm::dvec2& a, const glm::dvec2& b) { return a.x * b.y - a.y * b.x; }

struct SmoothieBuilder {
    glm::dmat4 inv;
    double t = 0.0;
    float inv_t = 0.0f;
    SmoothieVertex* out = nullptr;
    std::size_t capacity = 0;
    std::size_t count = 0;    // vertices produced (needed)
    std::size_t written = 0;  // vertices written
    bool full = false;

    // World point with light NDC = NDC(P) + delta at the same clip z and w as P (C = M (P, 1)).
    bool unproject(const glm::dvec3& P, const glm::dvec4& C, const glm::dvec2& delta, glm::dvec3& o) const {
        const glm::dvec4 h = glm::dvec4(P, 1.0) + C.w * (delta.x * inv[0] + delta.y * inv[1]);
        if (!(h.w > 0.0) || !std::isfinite(h.w)) return false;
        o = glm::dvec3(h) / h.w;
        if (!smoothie_finite3d(o)) return false;
        const glm::vec3 f(static_cast<float>(o.x), static_cast<float>(o.y), static_cast<float>(o.z));
        return smoothie_finite3(f);
    }

    void put(const SmoothieV& v, std::size_t i) {
        SmoothieVertex& o = out[i];
        o.position = glm::vec3(static_cast<float>(v.world.x), static_cast<float>(v.world.y), static_cast<float>(v.world.z));
        o.alpha = static_cast<float>(v.alpha < 0.0 ? 0.0 : (v.alpha > 1.0 ? 1.0 : v.alpha));
        o.silhouette_vertex = glm::vec3(static_cast<float>(v.sil.x), static_cast<float>(v.sil.y), static_cast<float>(v.sil.z));
        o.inv_t = inv_t;
        o.outward = glm::vec2(static_cast<float>(v.out.x), static_cast<float>(v.out.y));
        o.corner = v.corner;
        o.reserved = 0.0f;
    }

    void tri(const SmoothieV& a, const SmoothieV& b, const SmoothieV& c) {
        const bool ccw = smoothie_cross(b.ndc - a.ndc, c.ndc - a.ndc) >= 0.0;
        count += 3;
        if (full || out == nullptr || written + 3 > capacity) {
            full = true;
            return;
        }
        put(a, written);
        put(ccw ? b : c, written + 1);
        put(ccw ? c : b, written + 2);
        written += 3;
    }

    // Corner vertex at NDC offset d (length ~t or more) from the silhouette vertex.
    bool corner_vertex(const glm::dvec3& P, const glm::dvec4& C, const glm::dvec2& ndc_v, const glm::dvec2& d,
                       SmoothieV& v) const {
        if (!unproject(P, C, d, v.world)) return false;
        v.ndc = ndc_v + d;
        const double len = smoothie_len(d);
        v.alpha = len / t;
        v.sil = P;
        v.out = len > 0.0 ? d / len : glm::dvec2(0.0);
        v.corner = 1.0f;
        return true;
    }

    // Sector from unit direction dA to unit direction dB (angle <= 90 degrees, dot >= 0): quad
    // (v, v + t dA, v + t m, v + t dB), m = tangent intersection. Vertices computed into q[0..3].
    bool wedge(const glm::dvec3& P, const glm::dvec4& C, const glm::dvec2& ndc_v, const glm::dvec2& dA,
               const glm::dvec2& dB, SmoothieV q[4]) const {
        const double c = dA.x * dB.x + dA.y * dB.y;
        const double den = 1.0 + (c < 0.0 ? 0.0 : c);
        const glm::dvec2 m = (dA + dB) / den;
        q[0].world = P;
        q[0].ndc = ndc_v;
        q[0].alpha = 0.0;
        q[0].sil = P;
        q[0].out = glm::dvec2(0.0);
        q[0].corner = 1.0f;
        return corner_vertex(P, C, ndc_v, t * dA, q[1]) && corner_vertex(P, C, ndc_v, t * m, q[2]) &&
               corner_vertex(P, C, ndc_v, t * dB, q[3]);
    }
    void emit_wedge(const SmoothieV q[4]) {
        tri(q[0], q[1], q[2]);
        tri(q[0], q[2], q[3]);
    }
};

inline glm::dvec2 smoothie_unit(const glm::dvec2& v) {
    const double l = smoothie_len(v);
    return l > 0.0 ? v / l : glm::dvec2(0.0);
}

// Unit direction between unit a and unit b (the short way); for a == -b, a rotated by +90 degrees.
inline glm::dvec2 smoothie_mid(const glm::dvec2& a, const glm::dvec2& b) {
    const glm::dvec2 s = a + b;
    if (smoothie_len(s) > 1e-9) return smoothie_unit(s);
    return glm::dvec2(-a.y, a.x);
}

}  // namespace detail

/// Builds the smoothie triangle list (see the header comment for the construction and units).
/// out may be null (capacity 0) to query vertex_count; smoothie_vertex_capacity(edge_count) always
/// suffices. Allocates O(edge_count) scratch memory.
inline SmoothieResult build_smoothies(const SmoothieEdges& in, const glm::mat4& light_view_proj,
                                      const SmoothieParams& params, SmoothieVertex* out, std::size_t capacity) {
    using namespace detail;
    SmoothieResult res;
    if ((in.positions == nullptr && in.position_count != 0) || (in.edges == nullptr && in.edge_count != 0) ||
        (out == nullptr && capacity != 0) || !std::isfinite(params.t) || params.t < 0.0f ||
        (in.edge_count != 0 && in.face_normals == nullptr && in.outward == nullptr)) {
        res.status = SmoothieStatus::InvalidArgument;
        return res;
    }
    glm::dmat4 M;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) {
            const float v = light_view_proj[c][r];
            if (!std::isfinite(v)) {
                res.status = SmoothieStatus::InvalidMatrix;
                return res;
            }
            M[c][r] = static_cast<double>(v);
        }
    const double det = glm::determinant(M);
    SmoothieBuilder B;
    B.inv = glm::inverse(M);
    bool inv_ok = std::isfinite(det) && det != 0.0;
    for (int c = 0; c < 4 && inv_ok; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(B.inv[c][r])) inv_ok = false;
    if (!inv_ok) {
        res.status = SmoothieStatus::InvalidMatrix;
        return res;
    }
    if (params.t == 0.0f || in.edge_count == 0) return res;  // t = 0: no geometry (hard shadows), nothing counted

    B.t = static_cast<double>(params.t);
    B.inv_t = 1.0f / params.t;
    if (!std::isfinite(B.inv_t)) B.inv_t = 3.0e38f;  // subnormal t
    B.out = out;
    B.capacity = capacity;

    std::vector<SmoothieEdgeInfo> kept;
    std::vector<SmoothieEnd> ends;
    kept.reserve(in.edge_count);
    ends.reserve(2 * in.edge_count);

    for (std::size_t e = 0; e < in.edge_count; ++e) {
        const std::uint32_t i0 = in.edges[2 * e], i1 = in.edges[2 * e + 1];
        if (i0 >= in.position_count || i1 >= in.position_count || i0 == i1) {
            ++res.skipped_invalid;
            continue;
        }
        const glm::vec3 f0 = in.positions[i0], f1 = in.positions[i1];
        if (!smoothie_finite3(f0) || !smoothie_finite3(f1) || f0 == f1) {
            ++res.skipped_invalid;
            continue;
        }
        SmoothieEdgeInfo E;
        E.P[0] = smoothie_d(f0);
        E.P[1] = smoothie_d(f1);
        E.C[0] = smoothie_mul(M, E.P[0]);
        E.C[1] = smoothie_mul(M, E.P[1]);
        bool whole[2] = {true, true};
        {  // near-plane clipping
            const double d0 = smoothie_near_dist(E.C[0], params.clip_depth, params.reversed_z);
            const double d1 = smoothie_near_dist(E.C[1], params.clip_depth, params.reversed_z);
            if (!(d0 >= 0.0) && !(d1 >= 0.0)) {
                ++res.skipped_behind;
                continue;
            }
            if (!(d0 >= 0.0) || !(d1 >= 0.0)) {
                const int k = d0 >= 0.0 ? 1 : 0;  // the end to move
                const double s = d0 / (d0 - d1);  // in (0, 1)
                E.P[k] = E.P[0] + s * (E.P[1] - E.P[0]);
                E.C[k] = E.C[0] + s * (E.C[1] - E.C[0]);
                whole[k] = false;
                ++res.clipped_edges;
            }
        }
        if (!(E.C[0].w > 0.0) || !(E.C[1].w > 0.0) || !smoothie_finite3d(E.P[0]) || !smoothie_finite3d(E.P[1])) {
            ++res.skipped_behind;
            continue;
        }
        E.A[0] = glm::dvec2(E.C[0]) / E.C[0].w;
        E.A[1] = glm::dvec2(E.C[1]) / E.C[1].w;
        const glm::dvec2 ed = E.A[1] - E.A[0];
        const double L = smoothie_len(ed);
        const double scale = std::max({1.0, std::fabs(E.A[0].x), std::fabs(E.A[0].y), std::fabs(E.A[1].x), std::fabs(E.A[1].y)});
        if (!std::isfinite(L) || !(L > 1e-12 * scale)) {
            ++res.skipped_end_on;
            continue;
        }
        const glm::dvec2 perp(-ed.y / L, ed.x / L);
        // Outward side: sign of the light-NDC image of a world direction h at the edge midpoint.
        const glm::dvec4 Cm = 0.5 * (E.C[0] + E.C[1]);
        auto side = [&](const glm::dvec3& h) -> double {
            const glm::dvec4 dc = M[0] * h.x + M[1] * h.y + M[2] * h.z;  // M (h, 0)
            const glm::dvec2 j(dc.x * Cm.w - Cm.x * dc.w, dc.y * Cm.w - Cm.y * dc.w);
            const double jl = smoothie_len(j);
            if (!std::isfinite(jl) || !(jl > 0.0)) return 0.0;
            const double s = (perp.x * j.x + perp.y * j.y) / jl;
            return std::fabs(s) > 1e-9 ? s : 0.0;
        };
        auto unit3 = [](const glm::vec3& v, glm::dvec3& u) -> bool {
            if (!smoothie_finite3(v)) return false;
            const glm::dvec3 d = smoothie_d(v);
            const double l = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
            if (!(l > 0.0) || !std::isfinite(l)) return false;
            u = d / l;
            return true;
        };
        double s = 0.0;
        glm::dvec3 h, n0, n1;
        if (in.outward != nullptr && unit3(in.outward[e], h)) s = side(h);
        if (s == 0.0 && in.face_normals != nullptr) {
            const bool has0 = unit3(in.face_normals[2 * e], n0);
            const bool has1 = unit3(in.face_normals[2 * e + 1], n1);
            if (has0 && has1) s = side(n0 + n1);
            if (s == 0.0 && has0) {
                const glm::dvec3 ev = smoothie_d(f1) - smoothie_d(f0);
                s = -side(glm::cross(n0, ev));  // interior of face 0 lies along cross(n0, v1 - v0)
            }
        }
        if (s == 0.0) {
            ++res.skipped_no_outward;
            continue;
        }
        E.n = s > 0.0 ? perp : -perp;
        glm::dvec3 O[2];
        if (!B.unproject(E.P[0], E.C[0], B.t * E.n, O[0]) || !B.unproject(E.P[1], E.C[1], B.t * E.n, O[1])) {
            ++res.skipped_unprojectable;
            continue;
        }
        SmoothieV vi[2], vo[2];
        for (int k = 0; k < 2; ++k) {
            vi[k] = SmoothieV{E.P[k], E.A[k], 0.0, E.P[k], E.n, 0.0f};
            vo[k] = SmoothieV{O[k], E.A[k] + B.t * E.n, 1.0, E.P[k], E.n, 0.0f};
        }
        B.tri(vi[0], vi[1], vo[1]);
        B.tri(vi[0], vo[1], vo[0]);
        ++res.edge_quads;
        const std::uint32_t idx = static_cast<std::uint32_t>(kept.size());
        kept.push_back(E);
        if (whole[0]) ends.push_back(SmoothieEnd{i0, idx, 0u});
        if (whole[1]) ends.push_back(SmoothieEnd{i1, idx, 1u});
    }

    std::sort(ends.begin(), ends.end(), [](const SmoothieEnd& a, const SmoothieEnd& b) {
        return a.vertex != b.vertex ? a.vertex < b.vertex : (a.edge != b.edge ? a.edge < b.edge : a.end < b.end);
    });

    SmoothieV q[4], q2[4];
    std::vector<std::pair<double, std::uint32_t>> order;  // (angle of u_i, end slot)
    for (std::size_t g = 0; g < ends.size();) {
        std::size_t h = g;
        while (h < ends.size() && ends[h].vertex == ends[g].vertex) ++h;
        const std::size_t k = h - g;
        const SmoothieEdgeInfo& E0 = kept[ends[g].edge];
        const unsigned j0 = ends[g].end;
        const glm::dvec3 P = E0.P[j0];
        const glm::dvec4 C = E0.C[j0];
        const glm::dvec2 V = E0.A[j0];
        auto away = [&](std::size_t i) {  // unit NDC direction from v along the edge of end slot i
            const SmoothieEdgeInfo& E = kept[ends[i].edge];
            return smoothie_unit(E.A[1 - ends[i].end] - E.A[ends[i].end]);
        };
        auto normal = [&](std::size_t i) { return kept[ends[i].edge].n; };
        if (k > 2) ++res.multi_vertices;
        if (k == 1) {
            if (B.wedge(P, C, V, E0.n, smoothie_unit(-away(g)), q)) {
                B.emit_wedge(q);
                ++res.caps;
            } else {
                ++res.skipped_corners;
            }
            g = h;
            continue;
        }
        // Sectors around v between angularly consecutive edges (counter-clockwise in light NDC).
        // Sector j (from u_j to u_j+1) is exterior if n_j turns counter-clockwise from u_j into it and
        // n_j+1 turns clockwise from u_j+1 into it, interior if neither, inconsistent otherwise.
        // An exterior sector wider than 180 degrees leaves a gap of (angle - 180) between the two
        // quads' outer edges: fill it from n_j through the sector's middle direction to n_j+1.
        order.clear();
        for (std::size_t i = g; i < h; ++i) {
            const glm::dvec2 u = away(i);
            order.emplace_back(std::atan2(u.y, u.x), static_cast<std::uint32_t>(i));
        }
        std::sort(order.begin(), order.end());
        bool consistent = !params.paper_fans || k == 2;
        for (std::size_t j = 0; j < k && consistent; ++j) {
            const std::size_t i0s = order[j].second, i1s = order[(j + 1) % k].second;
            const bool a = smoothie_cross(away(i0s), normal(i0s)) > 0.0;
            const bool c = smoothie_cross(away(i1s), normal(i1s)) < 0.0;
            if (a != c) consistent = false;
        }
        if (consistent) {
            bool ok = true;
            std::size_t fills = 0, turns = 0;
            for (int pass = 0; pass < 2 && ok; ++pass) {  // pass 0: check, pass 1: emit
                for (std::size_t j = 0; j < k; ++j) {
                    const std::size_t i0s = order[j].second, i1s = order[(j + 1) % k].second;
                    const glm::dvec2 u0 = away(i0s);
                    if (!(smoothie_cross(u0, normal(i0s)) > 0.0)) continue;  // interior sector
                    double theta = order[(j + 1) % k].first - order[j].first;
                    if (j + 1 == k) theta += 6.283185307179586;
                    if (!(theta > 3.141592653589793 + 1e-12)) {
                        if (pass == 0) ++turns;
                        continue;
                    }
                    const double hth = 0.5 * theta;
                    const glm::dvec2 mid(u0.x * std::cos(hth) - u0.y * std::sin(hth), u0.x * std::sin(hth) + u0.y * std::cos(hth));
                    const glm::dvec2 b = smoothie_unit(mid);
                    if (!B.wedge(P, C, V, normal(i0s), b, q) || !B.wedge(P, C, V, b, normal(i1s), q2)) {
                        ok = false;
                        break;
                    }
                    if (pass == 1) {
                        B.emit_wedge(q);
                        B.emit_wedge(q2);
                    } else {
                        ++fills;
                    }
                }
            }
            if (ok) {
                res.corners += fills;
                res.concave_turns += turns;
            } else {
                ++res.skipped_corners;
            }
        } else {
            // Paper's special case: the unit average n_a of the outward normals, and a fan from each
            // v + t n_i to v + t n_a (split at the middle direction).
            glm::dvec2 sum(0.0);
            for (std::size_t i = g; i < h; ++i) sum += normal(i);
            const glm::dvec2 na = smoothie_len(sum) > 1e-9 * static_cast<double>(k) ? smoothie_unit(sum) : E0.n;
            bool ok = true;
            for (std::size_t i = g; i < h && ok; ++i) {
                const glm::dvec2 mid = smoothie_mid(normal(i), na);
                ok = B.wedge(P, C, V, normal(i), mid, q) && B.wedge(P, C, V, mid, na, q2);
            }
            if (ok) {
                for (std::size_t i = g; i < h; ++i) {
                    const glm::dvec2 mid = smoothie_mid(normal(i), na);
                    B.wedge(P, C, V, normal(i), mid, q);
                    B.wedge(P, C, V, mid, na, q2);
                    B.emit_wedge(q);
                    B.emit_wedge(q2);
                }
                ++res.fans;
            } else {
                ++res.skipped_corners;
            }
        }
        g = h;
    }

    res.vertex_count = B.count;
    res.vertices_written = B.written;
    if (B.full) res.status = SmoothieStatus::BufferTooSmall;
    return res;
}

}  // namespace shadowkit
