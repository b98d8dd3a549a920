// shadowkit/smoothie.hpp - "smoothies": fake soft shadows from silhouette geometry. Builds the
// smoothie edge quads, corner quads and valence > 2 fans from plain silhouette data, plus the CPU
// side of the alpha remap (eq. 1), the sinusoidal falloff, the per-tap visibility rule and the
// mapping between the smoothie width t and an area light's size. GPU side: glsl/smoothie.glsl.
//
// Usage (once per mesh: the scratch and vertex buffers; per frame: the silhouette, then the build):
//   #include <shadowkit/smoothie.hpp>
//   namespace sk = shadowkit;
//   sk::SmoothieEdges in;                         // silhouette edges, e.g. from silhouette.hpp
//   in.positions = pos; in.position_count = n;    // world space
//   in.edges = sil; in.edge_count = k;            // 2 indices per edge, oriented as in the lit face
//   // no normals needed: edges oriented as silhouette.hpp emits them (the lit face's winding) decide
//   // the outward side; face_normals / outward hints are optional (see "Outward side")
//   sk::SmoothieParams p;  p.t = 0.05f;           // width in light NDC units (see below)
//   std::vector<sk::SmoothieScratch> scratch(sk::smoothie_scratch_capacity(max_k));   // once
//   std::vector<sk::SmoothieVertex> vb(sk::smoothie_vertex_capacity(max_k));          // once
//   sk::SmoothieResult r = sk::smoothie_build(in, light_view_proj, p, scratch.data(), scratch.size(),
//                                             vb.data(), vb.size());
//   // r.count vertices = triangle list; upload and draw with glsl/smoothie.glsl.
//
// Conventions.
// Lights: a light is its homogeneous position `light_position` = (x, y, z, w), as OpenGL's
// GL_POSITION and Everitt & Kilgard use it. w > 0: a point or spot light at xyz / w. w = 0: a
// directional light at infinity in direction xyz, the direction *toward* the light (its rays travel
// along -xyz). w < 0, (0, 0, 0, 0) and NaN/Inf are rejected with Status::InvalidLight.
//   smoothie.hpp takes no light value: the light is the center of projection of light_view_proj
//   (a perspective matrix: a spot or point light at its eye; an orthographic one: a directional light
//   whose rays run along the view axis). Compute the silhouette for that same light, i.e. pass
//   silhouette.hpp the `light_position` (eye, 1) or (direction toward the light, 0) the matrix was
//   built from; the outward side of an edge (see below) relies on it.
//   * Results: functions that validate input return a struct whose first member is `status`; Ok only
//     with finite outputs. Skipped edges are counted in the result (Ok), never errors. Errors:
//     InvalidArgument (a null pointer with a count, t < 0, a singular light matrix, a result no call
//     filled), NonFinite (t or the light matrix NaN/Inf), BufferTooSmall (scratch or vertex buffer too
//     small: `scratch_needed` / `needed` say how many elements), Overflow (a width beyond float). A
//     non-Ok result's `detail` names the offending input and the rule ("t: < 0"), a static string;
//     nullptr when Ok.
//   * Buffers: pointer + capacity in elements of the pointer's type (SmoothieScratch, SmoothieVertex);
//     `count` = vertices written, `needed` = vertices the whole output needs. smoothie_build never
//     allocates: the caller passes per-edge scratch (smoothie_scratch_capacity(edge_count) elements,
//     reused every frame) and the vertex buffer (smoothie_vertex_capacity(edge_count) always
//     suffices; or query with out = nullptr, capacity 0).
//
// Units and construction (used by every function):
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
//     cross(n0, P1 - P0); else - and always when neither face_normals nor outward is given - the
//     edge's own orientation: edges run v0 -> v1 as in their lit face, counter-clockwise about its
//     normal (as silhouette.hpp emits them), so the lit face's interior lies to the left of v0 -> v1
//     seen from the light. In light NDC the lit face keeps that orientation up to one sign per matrix:
//     for the rows R = (0, 1, 3) of light_view_proj and its center of projection E (E_j = (-1)^j times
//     the 3x3 minor of R without column j), orient2d of three projected points (w > 0) has the sign of
//     det(E, a, b, c) = dot(cross(b - a, c - a), E.xyz - E.w a), i.e. of E.w (a finite light) or of
//     E.xyz toward the light (an orthographic matrix: the side of decreasing depth). The sides from
//     hints and normals are the sign of the light-NDC image of that direction (exact Jacobian of the
//     projection at the edge midpoint).
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
//   * Vertex with one kept edge (open chain, or its neighbor was skipped because it is seen end-on):
//     a quarter cap, the sector from n to the edge's continuation; it closes the gap left by an
//     end-on neighbor edge whose two ends project to the same point.
//   * Edges are clipped against the light's near plane (ClipDepth, reversed_z); a clipped end gets
//     no corner. Corners use vertex indices: weld positions first (silhouette.hpp does).
//   * t == 0 produces NO geometry (status Ok, needed 0, no edge examined or counted): the
//     smoothie buffer stays at its clear value and the final pass is exactly the hard shadow test.
//     For t > 0 every edge is counted once: edge_quads + skipped_* (except skipped_corners) = edge_count.
//   * Output: a non-indexed triangle list of SmoothieVertex, counter-clockwise in light NDC
//     (draw with face culling off anyway: mirrored viewports flip it). Edge quads first (6 vertices
//     each), then corners, caps and fans.
//
// Skipped and counted (never NaN in the output, status Ok): out-of-range indices, NaN/Inf positions,
// zero length edges (same index or equal positions), edges entirely in front of the near plane or
// behind the light (w <= 0), edges seen end-on (projecting to a point), edges without a usable outward
// direction, outer vertices that cannot be un-projected (non-finite). Rejected with a status: null
// pointers with non-zero counts (InvalidArgument), t NaN/Inf (NonFinite) or negative
// (InvalidArgument), a NaN/Inf (NonFinite) or singular (InvalidArgument) light matrix, too little
// scratch or vertex room (BufferTooSmall).
//
// Bias (glsl/smoothie.glsl, pass 2 and 3; measured in the report's driver, linear depth r): the umbra
// test r > z + bias with bias = 1e-3 r and the receiver-plane depth gradient (dr_duv), and the
// smoothie-pass discard b > z + 2e-3 b. Why: both buffers store linear depth in float (relative
// error ~1e-7), so what is left is the receiver's own depth across the 2x2 footprint; the gradient
// removes the planar part and 1e-3 r covers curvature and interpolation. Without the gradient
// (dr_duv = 0) the bias must cover the slope over one texel: tan(theta) * (texel size at r), theta
// the angle between the receiver normal and the light direction. The discard bias is larger because
// smoothie fragments lie exactly on the blocker's silhouette, where the map's own depth is that
// blocker's (2e-3 b keeps them in front of it).
//
// t and an area light (the mapping the report uses). For a perspective light with projection scale
// s = P[0][0] = 1 / tan(fov_x / 2), a blocker edge at linear depth b and a receiver plane facing the
// light at depth r > b, the remapped alpha goes 0 -> 1 over an NDC distance t (r - b) / r, i.e. a
// world width on the receiver of
//     W_smoothie = t (r - b) / s.
// A light of width w (diameter) centered on the point light gives a geometric penumbra
//     W_area = w (r - b) / b.
// They agree for every receiver depth iff t = s w / b: t is the light's width as it would appear in
// light NDC if it were placed at the blocker's depth (smoothie_width_for_area_light). The smoothie
// penumbra lies entirely outside the hard shadow (the umbra does not shrink), the area light's is
// centered on it: compare widths, and expect the smoothie edge shifted outwards by W / 2.
// Orthographic (directional) light, s = P[0][0] = 2 / frustum width, depths measured from the
// light's view origin: W_smoothie = t (r - b) / (r s), an angular diameter theta gives
// W = theta (r - b); they agree at one receiver depth r_ref only: t = theta s r_ref.
//
// Based on:
//   E. Chan, F. Durand, "Rendering Fake Soft Shadows with Smoothies", EGSR 2003: section 3 step 3
//   (edges, corners, valence > 2 special case), section 3.1 (eq. 1 remap, corner alpha |v - p|/t,
//   minimum blending, sinusoidal falloff), section 4 (passes).
//   E. Chan, "Rendering Fake Soft Shadows with Smoothies", SIGGRAPH 2004 course #26 "Real-Time Shadowing
//   Techniques" notes (concave silhouette corners omitted; linear depth in the shadow map).
//   E. Haines, "Soft Planar Shadows Using Plateaus", JGT 6(1) 2001 (sinusoidal falloff).
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
#include <limits>
#include <utility>

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

/// Silhouette edges as plain arrays. Pointers are borrowed for the call.
struct SmoothieEdges {
    /// `positions` holds position_count glm::vec3 elements: world-space vertex positions (null only
    /// with position_count 0).
    const glm::vec3* positions = nullptr;
    std::size_t position_count = 0;
    /// `edges` holds 2 * edge_count uint32 elements: (v0, v1) per edge, oriented as in its lit face
    /// (silhouette.hpp's order; header comment "Outward side"); null only with edge_count 0.
    const std::uint32_t* edges = nullptr;
    std::size_t edge_count = 0;               ///< number of edges (not indices)
    /// Optional (null: the edges' winding decides): holds 2 * edge_count glm::vec3 elements: [2i]
    /// normal of the face that runs v0 -> v1 counter-clockwise (the lit face from silhouette.hpp),
    /// [2i+1] the other face's normal or (0,0,0) for a boundary edge. Zero/NaN normals are ignored.
    const glm::vec3* face_normals = nullptr;
    /// Optional (null: unused): holds edge_count glm::vec3 elements: a world direction pointing away
    /// from the occluder at the edge. Used before the normals when finite and non-zero.
    const glm::vec3* outward = nullptr;
};

/// Parameters of smoothie_build.
struct SmoothieParams {
    float t = 0.0f;  ///< smoothie width [Units: light NDC, image = 2 wide] [Limit: finite, >= 0]; 0 = no geometry
    ClipDepth clip_depth = ClipDepth::NegativeOneToOne;  ///< of light_view_proj (for near-plane clipping)
    bool reversed_z = false;                             ///< near plane maps to depth 1 (ZeroToOne) / +1
    /// Vertices with > 2 silhouette edges: false (default) = sector rule (fills exactly the convex
    /// gaps, see the header comment), falling back to the averaged fan only for inconsistent
    /// normals; true = always the paper's averaged-normal fan (12 vertices per edge at the vertex).
    bool paper_fans = false;
};

/// Per-edge working memory of smoothie_build, owned by the caller and reused every frame (no
/// allocation in the build): smoothie_scratch_capacity(edge_count) elements. Contents are the
/// builder's (no meaning between calls).
struct SmoothieScratch {
    glm::dvec3 world[2];         ///< the kept edge's ends (after near-plane clipping)
    glm::dvec4 clip[2];          ///< their clip coordinates
    glm::dvec2 ndc[2];           ///< their light NDC
    glm::dvec2 normal;           ///< unit outward normal in light NDC
    double angle[2];             ///< angle of the edge's direction away from each end
    std::uint32_t vertex[2];     ///< input vertex index of each end
    std::uint32_t sorted_end[2]; ///< sort area: 2 end ids per kept edge (edge * 2 + end)
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

/// Result of smoothie_build. The counters are complete whenever status is Ok or the vertex buffer
/// was too small.
struct SmoothieResult {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    std::size_t count = 0;             ///< vertices written: min(needed, capacity) rounded down to whole triangles
    std::size_t needed = 0;            ///< vertices the whole output needs (3 per triangle)
    std::size_t scratch_needed = 0;    ///< SmoothieScratch elements the call needs (edge_count; 0 for t = 0)
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

/// Upper bound on smoothie_build's `needed` for edge_count edges (6 per edge + 12 per endpoint), in
/// SmoothieVertex elements. Total: SIZE_MAX when 30 * edge_count does not fit.
inline std::size_t smoothie_vertex_capacity(std::size_t edge_count) {
    const std::size_t lim = static_cast<std::size_t>(-1) / 30u;
    return edge_count > lim ? static_cast<std::size_t>(-1) : 30u * edge_count;
}

/// SmoothieScratch elements smoothie_build needs for edge_count edges (one per edge). Total.
inline std::size_t smoothie_scratch_capacity(std::size_t edge_count) { return edge_count; }

/// A scalar result of smoothie.hpp (widths).
struct SmoothieValue {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    float value = 0.0f;  ///< the quantity the function's comment names
};

// ------------------------------------------------------------------------------------------------
// Alpha remap, falloff, visibility rule, t <-> light size
// ------------------------------------------------------------------------------------------------

/// Chan & Durand 2003 eq. 1: alpha' = clamp(alpha / (1 - b/r), 0, 1), b = linear depth of the
/// smoothie, r = linear depth of the receiver (both from the light). b/r >= 1 (the receiver is in
/// front of the smoothie) -> 1. Evaluated as alpha r / (r - b) in double. alpha is clamped to
/// [0,1] first; NaN inputs, r <= 0 or b < 0 -> 1 (no smoothie effect). Total: every input gives a
/// value in [0, 1].
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
/// Total: [0, 1] for every input.
inline float smoothie_falloff(float a) {
    if (std::isnan(a) || a >= 1.0f) return 1.0f;
    if (a <= 0.0f) return 0.0f;
    const double s = std::sin(1.5707963267948966 * static_cast<double>(a));
    return static_cast<float>(s * s);
}

/// One tap of the final pass (the GLSL sk_smoothie_visibility does this at 4 texels and filters):
/// receiver linear depth r, shadow-map linear depth z, smoothie buffer (depth b, raw alpha).
/// r > z + bias -> 0 (umbra); else r > b -> falloff(remap(alpha, b, r)); else 1.
/// With the cleared smoothie buffer (b = +huge, alpha = 1) this is exactly the hard test. Total: [0, 1]
/// for every input (NaN comparisons are false: 1).
inline float smoothie_visibility_tap(float r, float z, float b, float alpha, float bias) {
    if (r > z + bias) return 0.0f;
    if (r > b) return smoothie_falloff(smoothie_remap_alpha(alpha, b, r));
    return 1.0f;
}

/// t (light NDC) that makes the smoothie penumbra as wide as the geometric penumbra of a light of
/// width light_width (world) for a blocker at linear depth b: t = s w / b, s = P[0][0] of the
/// light's projection (1/tan(fov_x/2)). Statuses: NonFinite (NaN/Inf input), InvalidArgument (b <= 0,
/// w < 0, s <= 0), Overflow (t beyond float).
inline SmoothieValue smoothie_width_for_area_light(float light_width, float b, float proj_scale) {
    SmoothieValue v;
    if (!std::isfinite(light_width) || !std::isfinite(b) || !std::isfinite(proj_scale)) {
        v.status = Status::NonFinite;
        v.detail = !std::isfinite(light_width) ? "light_width: NaN or Inf" : (!std::isfinite(b) ? "b: NaN or Inf" : "proj_scale: NaN or Inf");
        return v;
    }
    if (light_width < 0.0f || !(b > 0.0f) || !(proj_scale > 0.0f)) {
        v.status = Status::InvalidArgument;
        v.detail = light_width < 0.0f ? "light_width: < 0" : (!(b > 0.0f) ? "b: not > 0" : "proj_scale: not > 0");
        return v;
    }
    const double t = static_cast<double>(proj_scale) * static_cast<double>(light_width) / static_cast<double>(b);
    if (!(t <= static_cast<double>(std::numeric_limits<float>::max()))) {
        v.status = Status::Overflow;
        v.detail = "value: beyond float range";
        return v;
    }
    v.value = static_cast<float>(t);
    v.status = Status::Ok;
    return v;
}

/// Inverse of smoothie_width_for_area_light: w = t b / s. Statuses as there (t < 0: InvalidArgument).
inline SmoothieValue smoothie_area_light_width(float t, float b, float proj_scale) {
    SmoothieValue v;
    if (!std::isfinite(t) || !std::isfinite(b) || !std::isfinite(proj_scale)) {
        v.status = Status::NonFinite;
        v.detail = !std::isfinite(t) ? "t: NaN or Inf" : (!std::isfinite(b) ? "b: NaN or Inf" : "proj_scale: NaN or Inf");
        return v;
    }
    if (t < 0.0f || !(b > 0.0f) || !(proj_scale > 0.0f)) {
        v.status = Status::InvalidArgument;
        v.detail = t < 0.0f ? "t: < 0" : (!(b > 0.0f) ? "b: not > 0" : "proj_scale: not > 0");
        return v;
    }
    const double w = static_cast<double>(t) * static_cast<double>(b) / static_cast<double>(proj_scale);
    if (!(w <= static_cast<double>(std::numeric_limits<float>::max()))) {
        v.status = Status::Overflow;
        v.detail = "value: beyond float range";
        return v;
    }
    v.value = static_cast<float>(w);
    v.status = Status::Ok;
    return v;
}

/// World width over which the remapped alpha goes 0 -> 1 on a receiver plane facing a perspective
/// light at linear depth r, cast by a smoothie at depth b: t (r - b) / s; 0 when r <= b (the receiver
/// is in front of the smoothie: no penumbra). Statuses: NonFinite (NaN/Inf input), InvalidArgument
/// (t < 0, s <= 0), Overflow (a width beyond float).
inline SmoothieValue smoothie_penumbra_width(float t, float b, float r, float proj_scale) {
    SmoothieValue v;
    if (!std::isfinite(t) || !std::isfinite(b) || !std::isfinite(r) || !std::isfinite(proj_scale)) {
        v.status = Status::NonFinite;
        v.detail = !std::isfinite(t) ? "t: NaN or Inf"
                   : (!std::isfinite(b) ? "b: NaN or Inf" : (!std::isfinite(r) ? "r: NaN or Inf" : "proj_scale: NaN or Inf"));
        return v;
    }
    if (t < 0.0f || !(proj_scale > 0.0f)) {
        v.status = Status::InvalidArgument;
        v.detail = t < 0.0f ? "t: < 0" : "proj_scale: not > 0";
        return v;
    }
    const double w = r > b ? static_cast<double>(t) * (static_cast<double>(r) - static_cast<double>(b)) /
                                 static_cast<double>(proj_scale)
                           : 0.0;
    if (!(w <= static_cast<double>(std::numeric_limits<float>::max()))) {
        v.status = Status::Overflow;
        v.detail = "value: beyond float range";
        return v;
    }
    v.value = static_cast<float>(w);
    v.status = Status::Ok;
    return v;
}

// ------------------------------------------------------------------------------------------------
// Geometry
// ------------------------------------------------------------------------------------------------

namespace detail {

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

// Heapsort of n elements through less(i, j) and swap(i, j) (no allocation; the scratch's sort area is
// strided, so std::sort's contiguous iterators do not fit).
template <class Less, class Swap>
void smoothie_heapsort(std::size_t n, Less&& less, Swap&& swap) {
    auto sift = [&](std::size_t root, std::size_t end) {
        for (;;) {
            std::size_t child = 2 * root + 1;
            if (child >= end) return;
            if (child + 1 < end && less(child, child + 1)) ++child;
            if (!less(root, child)) return;
            swap(root, child);
            root = child;
        }
    };
    if (n < 2) return;
    for (std::size_t i = n / 2; i-- > 0;) sift(i, n);
    for (std::size_t end = n - 1; end > 0; --end) {
        swap(0, end);
        sift(0, end);
    }
}

// Sign with which a face lit by the center of projection of M (counter-clockwise about its normal)
// appears in light NDC: +1 counter-clockwise, -1 clockwise, 0 undecided (header comment "Outward
// side"). E = the homogeneous center (null vector of rows 0, 1, 3): E_j = (-1)^j minor_j.
inline int smoothie_winding_sign(const glm::dmat4& M, ClipDepth cd, bool reversed) {
    double R[3][4];
    const int rows[3] = {0, 1, 3};
    for (int i = 0; i < 3; ++i)
        for (int c = 0; c < 4; ++c) R[i][c] = M[c][rows[i]];
    double E[4];
    for (int j = 0; j < 4; ++j) {
        int cols[3], k = 0;
        for (int c = 0; c < 4; ++c)
            if (c != j) cols[k++] = c;
        const double m = R[0][cols[0]] * (R[1][cols[1]] * R[2][cols[2]] - R[1][cols[2]] * R[2][cols[1]]) -
                         R[0][cols[1]] * (R[1][cols[0]] * R[2][cols[2]] - R[1][cols[2]] * R[2][cols[0]]) +
                         R[0][cols[2]] * (R[1][cols[0]] * R[2][cols[1]] - R[1][cols[1]] * R[2][cols[0]]);
        E[j] = (j % 2 == 0 ? 1.0 : -1.0) * m;
    }
    const double exyz = std::sqrt(E[0] * E[0] + E[1] * E[1] + E[2] * E[2]);
    if (!std::isfinite(exyz) || !std::isfinite(E[3])) return 0;
    if (std::fabs(E[3]) > 1e-12 * exyz) return E[3] > 0.0 ? 1 : -1;  // a finite center: E = k (p, 1), k = E.w
    // orthographic: E = k (d, 0) with d toward the light, where depth decreases (increases if reversed)
    (void)cd;
    const double dz = E[0] * M[0][2] + E[1] * M[1][2] + E[2] * M[2][2];  // dot(E.xyz, gradient of clip z)
    const double toward = reversed ? dz : -dz;
    if (!(std::fabs(toward) > 1e-12 * exyz * std::sqrt(M[0][2] * M[0][2] + M[1][2] * M[1][2] + M[2][2] * M[2][2])))
        return 0;
    return toward > 0.0 ? 1 : -1;
}

// Step 1 of smoothie_build: check the arguments and take the light matrix and its inverse in
// double. Returns false with res.status set when the build ends here (an error, or nothing to draw).
inline bool smoothie_check_inputs(const SmoothieEdges& in, const glm::mat4& light_view_proj,
                                  const SmoothieParams& params, const SmoothieScratch* scratch,
                                  std::size_t scratch_capacity, const SmoothieVertex* out, std::size_t capacity,
                                  glm::dmat4& M, glm::dmat4& inv, SmoothieResult& res) {
    if ((in.positions == nullptr && in.position_count != 0) || (in.edges == nullptr && in.edge_count != 0) ||
        (out == nullptr && capacity != 0) || (scratch == nullptr && scratch_capacity != 0)) {
        res.status = Status::InvalidArgument;
        res.detail = in.positions == nullptr && in.position_count != 0 ? "positions: null with position_count > 0"
                     : (in.edges == nullptr && in.edge_count != 0 ? "edges: null with edge_count > 0"
                     : (out == nullptr && capacity != 0 ? "out: null with capacity > 0" : "scratch: null with scratch_capacity > 0"));
        return false;
    }
    if (!std::isfinite(params.t)) {
        res.status = Status::NonFinite;
        res.detail = "t: NaN or Inf";
        return false;
    }
    if (params.t < 0.0f) {
        res.status = Status::InvalidArgument;
        res.detail = "t: < 0";
        return false;
    }
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) {
            const float v = light_view_proj[c][r];
            if (!std::isfinite(v)) {
                res.status = Status::NonFinite;
                res.detail = "light_view_proj: NaN or Inf";
                return false;
            }
            M[c][r] = static_cast<double>(v);
        }
    const double det = glm::determinant(M);
    inv = glm::inverse(M);
    bool inv_ok = std::isfinite(det) && det != 0.0;
    for (int c = 0; c < 4 && inv_ok; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(inv[c][r])) inv_ok = false;
    if (!inv_ok) {
        res.status = Status::InvalidArgument;
        res.detail = "light_view_proj: singular";
        return false;
    }
    if (params.t == 0.0f || in.edge_count == 0) {  // t = 0: no geometry (hard shadows), nothing counted
        res.status = Status::Ok;
        return false;
    }
    res.scratch_needed = smoothie_scratch_capacity(in.edge_count);
    if (scratch_capacity < res.scratch_needed) {
        res.status = Status::BufferTooSmall;
        res.detail = "scratch_capacity: below scratch_needed";
        return false;
    }
    return true;
}

// The outward side (+1 / -1 along perp, 0 when unknown) of edge e, whose ends are E.clip in light
// clip space: from the edge's outward direction, else its face normals, else the winding.
inline double smoothie_outward_sign(const SmoothieEdges& in, std::size_t e, const glm::dmat4& M,
                                    const SmoothieScratch& E, const glm::dvec2& perp, int winding) {
    // Outward side: sign of the light-NDC image of a world direction h at the edge midpoint.
    const glm::dvec4 Cm = 0.5 * (E.clip[0] + E.clip[1]);
    auto side = [&](const glm::dvec3& h) -> double {
        const glm::dvec4 dc = M[0] * h.x + M[1] * h.y + M[2] * h.z;  // M (h, 0)
        const glm::dvec2 j(dc.x * Cm.w - Cm.x * dc.w, dc.y * Cm.w - Cm.y * dc.w);
        const double jl = smoothie_len(j);
        if (!std::isfinite(jl) || !(jl > 0.0)) return 0.0;
        const double sd = (perp.x * j.x + perp.y * j.y) / jl;
        return std::fabs(sd) > 1e-9 ? sd : 0.0;
    };
    auto unit3 = [](const glm::vec3& v, glm::dvec3& u) -> bool {
        if (!smoothie_finite3(v)) return false;
        const glm::dvec3 d = smoothie_d(v);
        const double l = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
        if (!(l > 0.0) || !std::isfinite(l)) return false;
        u = d / l;
        return true;
    };
    double sgn = 0.0;
    glm::dvec3 h(0.0), n0(0.0), n1(0.0);
    if (in.outward != nullptr && unit3(in.outward[e], h)) sgn = side(h);
    if (sgn == 0.0 && in.face_normals != nullptr) {
        const bool has0 = unit3(in.face_normals[2 * e], n0);
        const bool has1 = unit3(in.face_normals[2 * e + 1], n1);
        if (has0 && has1) sgn = side(n0 + n1);
        if (sgn == 0.0 && has0) {
            const std::uint32_t i0 = in.edges[2 * e], i1 = in.edges[2 * e + 1];
            const glm::dvec3 ev = smoothie_d(in.positions[i1]) - smoothie_d(in.positions[i0]);
            sgn = -side(glm::cross(n0, ev));  // interior of face 0 lies along cross(n0, v1 - v0)
        }
    }
    // the edge's own orientation: the lit face's interior is left of v0 -> v1 when lit faces
    // appear counter-clockwise in light NDC (winding > 0), so outward is right (-perp)
    if (sgn == 0.0) sgn = -static_cast<double>(winding);
    return sgn;
}

// Step 2 of smoothie_build, one edge: validate, clip to the near plane, find its outward normal in
// light NDC and emit its quad. Fills E and whole[] (ends not moved by clipping); false (counted
// in res) when the edge is skipped.
inline bool smoothie_edge_quad(const SmoothieEdges& in, std::size_t e, const glm::dmat4& M,
                               const SmoothieParams& params, int winding, SmoothieBuilder& B, SmoothieScratch& E,
                               bool whole[2], SmoothieResult& res) {
    const std::uint32_t i0 = in.edges[2 * e], i1 = in.edges[2 * e + 1];
    if (i0 >= in.position_count || i1 >= in.position_count || i0 == i1) {
        ++res.skipped_invalid;
        return false;
    }
    const glm::vec3 f0 = in.positions[i0], f1 = in.positions[i1];
    if (!smoothie_finite3(f0) || !smoothie_finite3(f1) || f0 == f1) {
        ++res.skipped_invalid;
        return false;
    }
    E.world[0] = smoothie_d(f0);
    E.world[1] = smoothie_d(f1);
    E.clip[0] = smoothie_mul(M, E.world[0]);
    E.clip[1] = smoothie_mul(M, E.world[1]);
    whole[0] = whole[1] = true;
    {  // near-plane clipping
        const double d0 = smoothie_near_dist(E.clip[0], params.clip_depth, params.reversed_z);
        const double d1 = smoothie_near_dist(E.clip[1], params.clip_depth, params.reversed_z);
        if (!(d0 >= 0.0) && !(d1 >= 0.0)) {
            ++res.skipped_behind;
            return false;
        }
        if (!(d0 >= 0.0) || !(d1 >= 0.0)) {
            const int k = d0 >= 0.0 ? 1 : 0;  // the end to move
            const double sp = d0 / (d0 - d1);  // in (0, 1)
            E.world[k] = E.world[0] + sp * (E.world[1] - E.world[0]);
            E.clip[k] = E.clip[0] + sp * (E.clip[1] - E.clip[0]);
            whole[k] = false;
            ++res.clipped_edges;
        }
    }
    if (!(E.clip[0].w > 0.0) || !(E.clip[1].w > 0.0) || !smoothie_finite3d(E.world[0]) || !smoothie_finite3d(E.world[1])) {
        ++res.skipped_behind;
        return false;
    }
    E.ndc[0] = glm::dvec2(E.clip[0]) / E.clip[0].w;
    E.ndc[1] = glm::dvec2(E.clip[1]) / E.clip[1].w;
    const glm::dvec2 ed = E.ndc[1] - E.ndc[0];
    const double L = smoothie_len(ed);
    const double scale = std::max({1.0, std::fabs(E.ndc[0].x), std::fabs(E.ndc[0].y), std::fabs(E.ndc[1].x), std::fabs(E.ndc[1].y)});
    if (!std::isfinite(L) || !(L > 1e-12 * scale)) {
        ++res.skipped_end_on;
        return false;
    }
    const glm::dvec2 perp(-ed.y / L, ed.x / L);  // left of v0 -> v1 in light NDC
    const double sgn = smoothie_outward_sign(in, e, M, E, perp, winding);
    if (sgn == 0.0) {
        ++res.skipped_no_outward;
        return false;
    }
    E.normal = sgn > 0.0 ? perp : -perp;
    glm::dvec3 O[2];
    if (!B.unproject(E.world[0], E.clip[0], B.t * E.normal, O[0]) || !B.unproject(E.world[1], E.clip[1], B.t * E.normal, O[1])) {
        ++res.skipped_unprojectable;
        return false;
    }
    SmoothieV vi[2], vo[2];
    for (int k = 0; k < 2; ++k) {
        vi[k] = SmoothieV{E.world[k], E.ndc[k], 0.0, E.world[k], E.normal, 0.0f};
        vo[k] = SmoothieV{O[k], E.ndc[k] + B.t * E.normal, 1.0, E.world[k], E.normal, 0.0f};
    }
    B.tri(vi[0], vi[1], vo[1]);
    B.tri(vi[0], vo[1], vo[0]);
    ++res.edge_quads;
    E.vertex[0] = i0;
    E.vertex[1] = i1;
    return true;
}

// The kept edges' ends in the scratch: end id = 2 * kept edge + end; the sort area holds ids.
struct SmoothieEnds {
    SmoothieScratch* scratch;
    std::uint32_t& at(std::size_t j) const { return scratch[j / 2].sorted_end[j % 2]; }
    std::uint32_t vertex_of(std::uint32_t id) const { return scratch[id / 2].vertex[id % 2]; }
    const SmoothieScratch& edge_of(std::uint32_t id) const { return scratch[id / 2]; }
    glm::dvec2 away(std::uint32_t id) const {  // unit NDC direction from v along the edge of end id
        const SmoothieScratch& E = edge_of(id);
        return smoothie_unit(E.ndc[1 - id % 2] - E.ndc[id % 2]);
    }
    glm::dvec2 normal(std::uint32_t id) const { return edge_of(id).normal; }
    double angle(std::uint32_t id) const { return scratch[id / 2].angle[id % 2]; }
};

// Step 2 of smoothie_build: one quad per usable edge; the kept edges go to scratch[0, kept) and
// their unclipped ends to the sort area (n_ends of them). Returns kept.
inline std::size_t smoothie_edge_quads(const SmoothieEdges& in, const glm::dmat4& M, const SmoothieParams& params,
                                       int winding, SmoothieBuilder& B, const SmoothieEnds& ends,
                                       std::size_t& n_ends, SmoothieResult& res) {
    std::size_t kept = 0;
    n_ends = 0;
    for (std::size_t e = 0; e < in.edge_count; ++e) {
        bool whole[2];
        if (!smoothie_edge_quad(in, e, M, params, winding, B, ends.scratch[kept], whole, res)) continue;
        const std::uint32_t idx = static_cast<std::uint32_t>(kept);
        ++kept;
        for (std::uint32_t k = 0; k < 2; ++k)
            if (whole[k]) {
                ends.at(n_ends) = 2u * idx + k;
                ++n_ends;
            }
    }
    return kept;
}

// Step 3 of smoothie_build: ends grouped by vertex, then by (edge, end).
inline void smoothie_sort_ends(const SmoothieEnds& ends, std::size_t n_ends) {
    smoothie_heapsort(
        n_ends,
        [&](std::size_t a, std::size_t b) {
            const std::uint32_t ia = ends.at(a), ib = ends.at(b);
            const std::uint32_t va = ends.vertex_of(ia), vb = ends.vertex_of(ib);
            return va != vb ? va < vb : ia < ib;
        },
        [&](std::size_t a, std::size_t b) { std::swap(ends.at(a), ends.at(b)); });
}

// Where the ends [g, h) of one silhouette vertex meet: the vertex's world position, clip position and NDC.
struct SmoothieJoint {
    std::size_t g, h;
    glm::dvec3 P;
    glm::dvec4 C;
    glm::dvec2 V;
};

// Step 4a: the exterior sectors around a vertex whose edges are consistent. Sector j (from u_j to
// u_j+1, counter-clockwise in light NDC) is exterior if n_j turns counter-clockwise from u_j into it
// and n_j+1 turns clockwise from u_j+1 into it, interior if neither. An exterior sector wider than
// 180 degrees leaves a gap of (angle - 180) between the two quads' outer edges: fill it from n_j
// through the sector's middle direction to n_j+1. `order(j)` is the j-th end by angle.
template <class Order>
void smoothie_fill_sectors(const SmoothieEnds& ends, const SmoothieJoint& J, Order&& order, SmoothieBuilder& B,
                           SmoothieResult& res) {
    const std::size_t k = J.h - J.g;
    SmoothieV q[4], q2[4];
    bool ok = true;
    std::size_t fills = 0, turns = 0;
    for (int pass = 0; pass < 2 && ok; ++pass) {  // pass 0: check, pass 1: emit
        for (std::size_t j = 0; j < k; ++j) {
            const std::uint32_t i0s = order(j), i1s = order((j + 1) % k);
            const glm::dvec2 u0 = ends.away(i0s);
            if (!(smoothie_cross(u0, ends.normal(i0s)) > 0.0)) continue;  // interior sector
            double theta = ends.angle(i1s) - ends.angle(i0s);
            if (j + 1 == k) theta += 6.283185307179586;
            if (!(theta > 3.141592653589793 + 1e-12)) {
                if (pass == 0) ++turns;
                continue;
            }
            const double hth = 0.5 * theta;
            const glm::dvec2 mid(u0.x * std::cos(hth) - u0.y * std::sin(hth), u0.x * std::sin(hth) + u0.y * std::cos(hth));
            const glm::dvec2 bm = smoothie_unit(mid);
            if (!B.wedge(J.P, J.C, J.V, ends.normal(i0s), bm, q) || !B.wedge(J.P, J.C, J.V, bm, ends.normal(i1s), q2)) {
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
}

// Step 4b, the paper's special case for inconsistent vertices: the unit average n_a of the outward
// normals, and a fan from each v + t n_i to v + t n_a (split at the middle direction), in (edge, end) order.
inline void smoothie_paper_fan(const SmoothieEnds& ends, const SmoothieJoint& J, const glm::dvec2& fallback,
                               SmoothieBuilder& B, SmoothieResult& res) {
    const std::size_t g = J.g, h = J.h, k = h - g;
    SmoothieV q[4], q2[4];
    smoothie_heapsort(
        k, [&](std::size_t a, std::size_t b) { return ends.at(g + a) < ends.at(g + b); },
        [&](std::size_t a, std::size_t b) { std::swap(ends.at(g + a), ends.at(g + b)); });
    glm::dvec2 sum(0.0);
    for (std::size_t i = g; i < h; ++i) sum += ends.normal(ends.at(i));
    const glm::dvec2 na = smoothie_len(sum) > 1e-9 * static_cast<double>(k) ? smoothie_unit(sum) : fallback;
    bool ok = true;
    for (std::size_t i = g; i < h && ok; ++i) {
        const glm::dvec2 mid = smoothie_mid(ends.normal(ends.at(i)), na);
        ok = B.wedge(J.P, J.C, J.V, ends.normal(ends.at(i)), mid, q) && B.wedge(J.P, J.C, J.V, mid, na, q2);
    }
    if (ok) {
        for (std::size_t i = g; i < h; ++i) {
            const glm::dvec2 mid = smoothie_mid(ends.normal(ends.at(i)), na);
            B.wedge(J.P, J.C, J.V, ends.normal(ends.at(i)), mid, q);
            B.wedge(J.P, J.C, J.V, mid, na, q2);
            B.emit_wedge(q);
            B.emit_wedge(q2);
        }
        ++res.fans;
    } else {
        ++res.skipped_corners;
    }
}

// Step 4 of smoothie_build, one vertex (the ends [g, h) of the sorted area): a cap for a lone end,
// else sector fills when the edges' outward sides are consistent, else the paper's fan.
inline void smoothie_join_vertex(const SmoothieEnds& ends, std::size_t g, std::size_t h, const SmoothieParams& params,
                                 SmoothieBuilder& B, SmoothieResult& res) {
    const std::size_t k = h - g;
    const std::uint32_t id0 = ends.at(g);
    const SmoothieScratch& E0 = ends.edge_of(id0);
    const unsigned j0 = id0 % 2;
    const SmoothieJoint J{g, h, E0.world[j0], E0.clip[j0], E0.ndc[j0]};
    if (k > 2) ++res.multi_vertices;
    if (k == 1) {
        SmoothieV q[4];
        if (B.wedge(J.P, J.C, J.V, E0.normal, smoothie_unit(-ends.away(id0)), q)) {
            B.emit_wedge(q);
            ++res.caps;
        } else {
            ++res.skipped_corners;
        }
        return;
    }
    for (std::size_t i = g; i < h; ++i) {
        const std::uint32_t id = ends.at(i);
        const glm::dvec2 u = ends.away(id);
        ends.scratch[id / 2].angle[id % 2] = std::atan2(u.y, u.x);
    }
    // this group's ids sorted by (angle, id): order[j] = at(g + j)
    smoothie_heapsort(
        k,
        [&](std::size_t a, std::size_t b) {
            const std::uint32_t ia = ends.at(g + a), ib = ends.at(g + b);
            const double aa = ends.angle(ia), ab = ends.angle(ib);
            return aa != ab ? aa < ab : ia < ib;
        },
        [&](std::size_t a, std::size_t b) { std::swap(ends.at(g + a), ends.at(g + b)); });
    auto order = [&](std::size_t j) { return ends.at(g + j); };
    bool consistent = !params.paper_fans || k == 2;
    for (std::size_t j = 0; j < k && consistent; ++j) {
        const std::uint32_t i0s = order(j), i1s = order((j + 1) % k);
        const bool a = smoothie_cross(ends.away(i0s), ends.normal(i0s)) > 0.0;
        const bool c = smoothie_cross(ends.away(i1s), ends.normal(i1s)) < 0.0;
        if (a != c) consistent = false;
    }
    if (consistent)
        smoothie_fill_sectors(ends, J, order, B, res);
    else
        smoothie_paper_fan(ends, J, E0.normal, B, res);
}

}  // namespace detail

/// Builds the smoothie triangle list (see the header comment for the construction and units).
/// `scratch` holds scratch_capacity SmoothieScratch elements; it needs
/// smoothie_scratch_capacity(edge_count) = edge_count (`scratch_needed`), reused every frame.
/// `out` holds capacity SmoothieVertex elements; it needs `needed` (at most
/// smoothie_vertex_capacity(edge_count)); out = nullptr with capacity 0 is a size query (status
/// BufferTooSmall when anything would be drawn, with `needed` set). Too little scratch:
/// BufferTooSmall with scratch_needed set and nothing else computed. Never allocates.
inline SmoothieResult smoothie_build(const SmoothieEdges& in, const glm::mat4& light_view_proj,
                                     const SmoothieParams& params, SmoothieScratch* scratch,
                                     std::size_t scratch_capacity, SmoothieVertex* out, std::size_t capacity) {
    using namespace detail;
    SmoothieResult res;
    glm::dmat4 M;
    SmoothieBuilder B;
    if (!smoothie_check_inputs(in, light_view_proj, params, scratch, scratch_capacity, out, capacity, M, B.inv, res))
        return res;
    const int winding = smoothie_winding_sign(M, params.clip_depth, params.reversed_z);
    B.t = static_cast<double>(params.t);
    B.inv_t = 1.0f / params.t;
    if (!std::isfinite(B.inv_t)) B.inv_t = 3.0e38f;  // subnormal t
    B.out = out;
    B.capacity = capacity;

    const SmoothieEnds ends{scratch};
    std::size_t n_ends = 0;
    smoothie_edge_quads(in, M, params, winding, B, ends, n_ends, res);  // one quad per edge
    smoothie_sort_ends(ends, n_ends);                                    // ends grouped by vertex
    for (std::size_t g = 0; g < n_ends;) {                               // caps, corner fills, fans
        std::size_t h = g;
        const std::uint32_t vg = ends.vertex_of(ends.at(g));
        while (h < n_ends && ends.vertex_of(ends.at(h)) == vg) ++h;
        smoothie_join_vertex(ends, g, h, params, B, res);
        g = h;
    }

    res.needed = B.count;
    res.count = B.written;
    res.status = B.full ? Status::BufferTooSmall : Status::Ok;
    res.detail = B.full ? "capacity: below needed (see needed)" : nullptr;
    return res;
}

}  // namespace shadowkit
