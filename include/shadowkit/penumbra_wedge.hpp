// shadowkit/penumbra_wedge.hpp - soft shadow volumes: penumbra wedges of silhouette edges for a
// spherical area light (front/back + two side planes, Lengyel's inner and outer half-wedges), the
// analytic per-point light coverage of one silhouette edge, the visibility of a silhouette loop, the
// wedge hull for rasterization and its per-wedge scissor rectangle and depth bounds (clipped to a
// box: the light's range or the receivers' bounds).
//
// Usage (per light, per silhouette edge (e0, e1) seen from the light's center; docs/penumbra_wedge.md
// has a complete GL program):
//   #include <shadowkit/penumbra_wedge.hpp>
//   shadowkit::PenumbraSphereLight L;
//   L.light_position = glm::vec4(center, 1.0f); L.radius = radius;          // a sphere light
//   shadowkit::PenumbraWedge w = shadowkit::penumbra_wedge(e0, e1, L);
//   if (w.status != shadowkit::Status::Ok) ...                               // bad input: see below
//   if (w.skip != shadowkit::PenumbraWedgeSkip::None) continue;              // nothing to draw for it
//   shadowkit::PenumbraWedgeHull hull = shadowkit::penumbra_wedge_hull(w, extent); // 6 verts, 8 tris
//   shadowkit::ScissorParams sp;                      // required: view_proj and viewport
//   sp.view_proj = proj * view; sp.viewport[2] = width; sp.viewport[3] = height;
//   shadowkit::ScissorRect s = shadowkit::penumbra_wedge_scissor_in_box(hull, box_min, box_max, sp);
//   if (!s.visible) continue;   // else glScissor(s.x, s.y, s.width, s.height) + glDepthBoundsEXT
//   // fragment stage (glsl/penumbra_wedge.glsl): receiver point p inside the (half-)wedge planes ->
//   //   buffer += coverage of (e0, e1) at p   (additive float blending, signed)
//   // after all wedges: visibility = 1 - clamp(hard_count + buffer, 0, 1)
//   // CPU reference for one point: penumbra_visibility(endpoints, edge_count, L, p, hard_count)
//   // planes to viewport space for the slides' fragment test:
//   //   glm::mat4 M = penumbra_viewport_transform(sp.viewport, ClipDepth::NegativeOneToOne).matrix * view_proj;
//   //   glm::vec4 pv = penumbra_transform_plane(w.outer_bound, M).plane;  // dot(pv, (x_win, y_win, z_win, 1))
//
// Conventions.
// Lights: a light is its homogeneous position `light_position` = (x, y, z, w), as OpenGL's
// GL_POSITION and Everitt & Kilgard use it. w > 0: a point or spot light at xyz / w. w = 0: a
// directional light at infinity in direction xyz, the direction *toward* the light (its rays travel
// along -xyz). w < 0, (0, 0, 0, 0) and NaN/Inf are rejected with Status::InvalidLight.
//   * The wedges need a sphere light: PenumbraSphereLight = a point light `light_position` (w > 0,
//     center c = xyz / w, evaluated in double) and a `radius` r >= 0 (world units). A directional
//     disk light (the sun: w = 0 with an angular radius) would be the same struct with w = 0 and
//     `radius` read as the angular radius in radians; it is not supported: w = 0 gives
//     Status::InvalidLight. For coverage and visibility the sphere is modelled, as in A&AM, by the
//     disk of radius r through c perpendicular to (c - p) for the receiver point p, uniformly
//     bright; the wedges bound the penumbra of the whole ball, so they are conservative for the disk
//     too. A rectangular light: use penumbra_rect_bounding_sphere (conservative wedges; the coverage
//     is then that of the circumscribed disk).
//   * Silhouette edge (e0, e1): a possible-silhouette edge seen from the light's center, oriented as in
//     its light-facing triangle with counter-clockwise (outward) winding - the order
//     shadowkit/silhouette.hpp emits for light_position. Then the hard shadow plane through c, e0, e1
//     with normal cross(e0 - c, e1 - c) points OUT of the hard shadow volume.
//   * Planes are glm::vec4 (n, d), n unit (double-normalized, stored as float); a point x is INSIDE a
//     plane when dot(n, x) + d >= 0 (Lengyel: negative against any plane = outside). A point is in the
//     wedge when it is inside outer_bound, inner_bound, side[0] and side[1]. hard_plane >= 0 is the
//     OUTER half-wedge (outside the hard shadow: coverage adds occlusion), < 0 the INNER half-wedge
//     (inside the hard shadow: coverage removes occlusion).
//   * Results: every function that validates input returns a struct whose first member is `status`;
//     `Ok` only with finite outputs. A wedge edge to skip is `skip` != None with Status::Ok (not an
//     error); a hull with nothing to draw is `drawable` = false, a scissor with nothing on screen
//     `visible` = false, both with Status::Ok. Errors: NonFinite (NaN/Inf input), InvalidLight (see
//     above), InvalidArgument (radius or padding < 0, extent <= 0, a zero viewport or matrix, a null
//     pointer with a count, a result that no successful call made), Overflow (finite input whose
//     planes or hull are beyond float). A non-Ok result's `detail` names the offending input and
//     the rule ("padding: < 0"), a static string; nullptr when Ok.
//   * Buffers: pointer + count in elements of the pointer's type, stated next to each pointer.
//     Nothing here allocates.
//   * Clip depth: ScissorParams::clip_depth (GL [-1, 1] or zero-to-one) plus reversed_z; depth bounds
//     are window depths for glDepthRange(0, 1). Infinite projections (P_inf) are accepted.
//
// Construction (A&AM 2003 steps A-D; everything in double). (A) The endpoint farther from c is moved
// along its ray from c (toward the light center, not along the edge: moving along the edge would drop
// part of the penumbra) to the nearer endpoint's distance -> apex edge (a0, a1). (B) outer_bound and
// inner_bound are the two planes through the line a0a1 tangent to the ball, ball outside. (C) side[i]
// is the plane through a_i containing the hard plane's normal, tangent to the ball, ball outside and
// a_j inside. (D) penumbra_wedge_hull limits it at a distance along the four edge rays.
// Why it is conservative: every point of the original edge is a_i + k (a_i - c) with k >= 0 or lies on
// a0a1, so it is inside all four planes (each plane passes through an apex and has the ball outside),
// and the set {inside all planes} is closed under x -> x + s (x - y), y in the ball, s >= 0. Hence the
// wedge contains the swept region P(E) = {q + s (q - y) : q on the edge, y in the ball, s >= 0}, and
// penumbra_edge_coverage is non-zero only in P(E).
// Degenerate cases: if the apex line passes through the ball (edge grazing a large close light) the
// planes are built from the original endpoints (shape OriginalEndpoints, same proof); if the edge's
// own line passes through the ball (edge pointing at the light), P(E) is exactly the shadow cone of
// the nearer endpoint and the wedge is the square pyramid around that cone (shape Cone, apex[0] ==
// apex[1]). If rounding defeats all three (never seen in the tests), shape HalfSpace: all four planes
// are the ball's tangent plane facing the edge (conservative, no hull: penumbra_wedge_hull says
// drawable = false). Skips (Status::Ok with `skip`, nothing to draw): e0 == e1 (DegenerateEdge);
// c, e0, e1 collinear (RadialEdge: coverage 0, zero-area hard quad); the segment comes within
// r + 1e-7 max|coordinate| of c, i.e. touches the ball to float input precision (EdgeTouchesLight:
// an occluder inside the emitter, which the method does not model). Errors: NaN/Inf (NonFinite),
// r < 0 or padding < 0 (InvalidArgument), a light that is not a point light (InvalidLight), planes
// beyond float (Overflow). Radius 0: inner_bound = -outer_bound = the hard plane (the hard shadow
// quad's plane; the wedge, inside both, is that plane), coverage 0, visibility 1 - hard count.
//
// Coverage (penumbra_edge_coverage). Frame: z = (c - p)/D, D = |c - p|; the disk at depth D.
//   1. Clip the edge to depth w <= D (only occluders between p and the emitter count).
//   2. The plane through p and the edge, n_p = cross(e0 - p, e1 - p), meets the disk plane in a line at
//      signed distance h_s = -dot(n_p, c - p) / (r |n_p - (n_p.z) z|) from the disk center (in light
//      radii); h_s = dot(cross(e0 - c, e1 - c), p - c) / (...) > 0 exactly when p is outside the hard
//      plane. Position along the line: lambda = dot(q - p, t) D / (dot(q - p, z) r), t the line's unit
//      direction; an endpoint with depth <= 0 sends its end of the projected segment to +-infinity
//      (projective clip instead of a near plane). Intersect with the chord [-s, s], s = sqrt(1 - h^2).
//   3. Clipped ends a < b at distance h = |h_s|: region of the disk beyond the segment inside the
//      angular sector = sector - triangle (Lengyel):  A = (theta - h (b - a)) / (2 pi) of the disk,
//      theta = atan2(h (b - a), h^2 + a b) (the angle subtended by the clipped segment).
//   4. coverage = sign(h_s) * A, sign(0) = +1 (A&AM: p in the positive half space of the hard quad adds
//      occlusion); |coverage| <= 1/2. p at c or on the edge's line: coverage 0 (Ok).
//   This is exact for the disk model: coverage = sign * fraction of disk points x for which the edge
//   meets the triangle (p, c, x). Summed over a closed silhouette loop plus the hard count it equals the
//   occluded fraction exactly whenever the silhouette seen from p equals the one from c (planar
//   polygons, distant lights); otherwise it carries A&AM's single-silhouette error. Double precision
//   inside: ~1e-12 absolute; the float GLSL version ~1e-5.
//
// Scissor and depth bounds (Lengyel). penumbra_wedge_scissor projects the whole hull (after clipping
// it to the near plane); with a large extent it reaches far below the receivers and culls nothing.
// penumbra_wedge_scissor_in_box first clips the hull to a box - the light's range or the receivers'
// bounds: only points in it can receive light - (Sutherland-Hodgman on each hull triangle against
// the six box planes, plus the box corners inside the hull) and projects what is left: the rectangle
// and depth bounds of (hull intersected with box). Empty intersection: visible = false (Ok). A hull
// with an infinite extent (w = 0 vertices) is first cut off beyond the box (its cap moved out until
// every box corner lies inside the cap's planes).
//
// Based on:
//   U. Assarsson, T. Akenine-Moller, "A Geometry-based Soft Shadow Volume Algorithm using Graphics
//   Hardware", SIGGRAPH 2003, and T. Akenine-Moller's SIGGRAPH 2004 course notes (wedge construction
//   steps A-D; visibility = hard count + signed per-edge coverage, "positive half space of Q").
//   E. Lengyel, "Advanced Stencil Shadow and Penumbral Wedge Rendering", GDC 2005 (inner/outer
//   half-wedges with three bounding planes tested in viewport space; occluded area = sector area
//   between the clipped endpoints minus the triangle with the light's center; per-wedge scissor and
//   depth bounds from the wedge clipped to the light's bounds).
//
// MIT License. Copyright (c) shadowkit contributors.
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <limits>

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
#ifndef SHADOWKIT_SCISSOR_DEFINED
#define SHADOWKIT_SCISSOR_DEFINED
/// The camera a scissor rectangle and depth bounds are computed for. Every field is required: the
/// zero matrix and zero viewport of a default-constructed ScissorParams give Status::InvalidArgument.
struct ScissorParams {
    glm::mat4 view_proj = glm::mat4(0.0f);  ///< projection * view, world -> clip (required)
    ClipDepth clip_depth = ClipDepth::NegativeOneToOne;
    bool reversed_z = false;
    int viewport[4] = {0, 0, 0, 0};         ///< x, y, width, height in pixels, as glViewport (required)
};
/// Pixel rectangle and window-depth range that hold every pixel a shadow volume or wedge can touch.
struct ScissorRect {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    bool visible = false;                     ///< false (with Ok): nothing of it is on screen, skip the occluder
    int x = 0, y = 0, width = 0, height = 0;  ///< for glScissor
    float depth_min = 0.0f, depth_max = 1.0f; ///< for glDepthBoundsEXT: window depth, glDepthRange(0, 1)
};
#endif

/// Spherical area light: a ball of `radius` around the point light `light_position` (see
/// "Lights" and the sphere-light note in the header comment).
struct PenumbraSphereLight {
    /// The light's center as a homogeneous position, w > 0 (center = xyz / w) (required: the default
    /// (0, 0, 0, 0) is rejected with InvalidLight; so is w = 0, a directional disk light).
    glm::vec4 light_position = glm::vec4(0.0f);
    float radius = 0.0f;  ///< [Units: world] [Limit: >= 0, finite] 0 = the hard shadow exactly
};

/// Why penumbra_wedge skipped an edge (with Status::Ok: nothing to draw for it, not an error).
enum class PenumbraWedgeSkip : std::uint8_t {
    None,            ///< a wedge: draw it
    DegenerateEdge,  ///< e0 == e1: no coverage, no hard quad
    RadialEdge,      ///< c, e0, e1 collinear: coverage 0 everywhere, zero-area hard quad
    EdgeTouchesLight ///< the segment comes within r + 1e-7 max|coordinate| of c (occluder in the emitter)
};

/// How penumbra_wedge built the wedge (header comment: construction and degenerate cases).
enum class PenumbraWedgeShape {
    Equidistant,       ///< A&AM 2003: apex edge with both ends at the nearer endpoint's distance
    OriginalEndpoints, ///< the moved apex line passed through the ball: planes through e0, e1
    Cone,              ///< the edge line passes through the ball: pyramid around the near endpoint's cone
    HalfSpace          ///< numerical last resort: all four planes = one tangent plane of the ball (no hull)
};

/// One penumbra wedge. Planes: inside = dot(n, x) + d >= 0, n unit. Meaningful when status is Ok and
/// skip is None.
struct PenumbraWedge {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    PenumbraWedgeSkip skip = PenumbraWedgeSkip::None; ///< != None (with Ok): skip the edge, planes are zero
    PenumbraWedgeShape shape = PenumbraWedgeShape::Equidistant;
    glm::vec4 outer_bound = glm::vec4(0.0f); ///< tangent plane bounding the outer half-wedge
    glm::vec4 inner_bound = glm::vec4(0.0f); ///< tangent plane bounding the inner half-wedge
    glm::vec4 side[2] = {glm::vec4(0.0f), glm::vec4(0.0f)}; ///< through apex[0] / apex[1]
    glm::vec4 hard_plane = glm::vec4(0.0f);  ///< through c, e0, e1; >= 0 outside the hard shadow
    glm::vec3 apex[2] = {glm::vec3(0.0f), glm::vec3(0.0f)}; ///< the wedge's top edge (moved e0, e1)
    glm::vec3 ray_outer[2] = {glm::vec3(0.0f), glm::vec3(0.0f)}; ///< unit, outer_bound x side[i], away from c
    glm::vec3 ray_inner[2] = {glm::vec3(0.0f), glm::vec3(0.0f)}; ///< unit, inner_bound x side[i], away from c
    glm::vec3 axis = glm::vec3(0.0f);        ///< unit, from c toward the apex edge's midpoint
};

/// Lengyel's half-wedge: the three "outside bounding planes" (the hard plane is left to the depth test).
struct PenumbraHalfWedge {
    glm::vec4 planes[3] = {glm::vec4(0.0f), glm::vec4(0.0f), glm::vec4(0.0f)};
};

/// Closed convex wedge hull for rasterization: vertices 0, 1 = apex[0], apex[1]; 2, 3 = far outer ends
/// of the rays from apex 0, 1; 4, 5 = far inner ends; w = 0 (directions) for an infinite extent.
/// 8 triangles (outer face 2, inner face 2, side faces 1 + 1, cap 2) wound counter-clockwise seen
/// from outside (so GL_CCW front faces are the faces turned to the viewer). Shape Cone: apex 0 == 1 and
/// two triangles are degenerate (zero area, they rasterize nothing).
struct PenumbraWedgeHull {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    /// false (with Ok): nothing to draw - the wedge was skipped (`skip` != None) or has shape HalfSpace
    /// (no finite hull; its penumbra is then lost unless drawn full-screen). vertices/indices are zero.
    bool drawable = false;
    glm::vec4 vertices[6] = {glm::vec4(0.0f), glm::vec4(0.0f), glm::vec4(0.0f),
                             glm::vec4(0.0f), glm::vec4(0.0f), glm::vec4(0.0f)};
    std::uint8_t indices[24] = {}; ///< 8 triangles, 3 indices each, into vertices
};

/// A scalar result of penumbra_wedge.hpp (coverage, visibility).
struct PenumbraValue {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    double value = 0.0;  ///< the quantity the function's comment names (double: the CPU reference)
};

/// A plane result (penumbra_transform_plane).
struct PenumbraPlane {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    glm::vec4 plane = glm::vec4(0.0f);
};

/// A matrix result (penumbra_viewport_transform).
struct PenumbraMatrix {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    glm::mat4 matrix = glm::mat4(1.0f);
};

/// Result of penumbra_rect_bounding_sphere.
struct PenumbraBoundingSphere {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    PenumbraSphereLight light;  ///< the circumscribed sphere light
};

namespace detail {

inline bool pw_finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
inline glm::dvec3 pw_d(const glm::vec3& v) { return glm::dvec3(v.x, v.y, v.z); }
inline double pw_dot(const glm::dvec3& a, const glm::dvec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline glm::dvec3 pw_cross(const glm::dvec3& a, const glm::dvec3& b) {
    return glm::dvec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
inline double pw_len(const glm::dvec3& a) { return std::sqrt(pw_dot(a, a)); }
inline glm::vec4 pw_plane_f(const glm::dvec3& n, const glm::dvec3& through) {
    return glm::vec4(static_cast<float>(n.x), static_cast<float>(n.y), static_cast<float>(n.z),
                     static_cast<float>(-pw_dot(n, through)));
}
inline double pw_eval(const glm::dvec3& n, const glm::dvec3& through, const glm::dvec3& x) {
    return pw_dot(n, x - through);
}

// The two planes through the line (a, unit t) tangent to the ball (c, r), ball on the negative side:
// n = -(cos v + / - sin w), cos = r / h (A&AM step B). False when the line passes through the ball.
inline bool pw_tangent_planes(const glm::dvec3& a, const glm::dvec3& t, const glm::dvec3& c, double r,
                              glm::dvec3& na, glm::dvec3& nb) {
    const glm::dvec3 ca = c - a;
    const double h = pw_len(pw_cross(ca, t)); // distance from c to the line (no cancellation)
    if (!(h > 0.0) || !(h >= r)) return false;
    glm::dvec3 v = ca - pw_dot(ca, t) * t;
    v -= pw_dot(v, t) * t; // second Gram-Schmidt pass for lines nearly through c
    const double vl = pw_len(v);
    if (!(vl > 0.0)) return false;
    const glm::dvec3 vh = v / vl;
    glm::dvec3 w = pw_cross(t, vh);
    const double wl = pw_len(w);
    if (!(wl > 0.0)) return false;
    w /= wl;
    const double cs = std::min(1.0, r / h);
    const double sn = std::sqrt(std::max(0.0, 1.0 - cs * cs));
    na = -(cs * vh + sn * w);
    nb = -(cs * vh - sn * w);
    na /= pw_len(na);
    nb /= pw_len(nb);
    return std::isfinite(na.x + na.y + na.z + nb.x + nb.y + nb.z);
}

struct PwBuild {
    glm::dvec3 a[2], n_outer, n_inner, n_side[2], r_outer[2], r_inner[2], axis;
};

inline bool pw_ray(const glm::dvec3& n1, const glm::dvec3& n2, const glm::dvec3& away, glm::dvec3& out) {
    glm::dvec3 u = pw_cross(n1, n2);
    const double l = pw_len(u);
    if (!(l > 1e-12)) return false;
    u /= l;
    if (pw_dot(u, away) < 0.0) u = -u;
    out = u;
    return true;
}

// Finishes a build: rays, axis and a self-check that the rays stay inside the other planes (the hull
// then is the wedge; otherwise the caller falls back to the next construction).
inline bool pw_finish(PwBuild& b, const glm::dvec3& c, double scale) {
    for (int i = 0; i < 2; ++i) {
        const glm::dvec3 away = b.a[i] - c;
        if (!pw_ray(b.n_outer, b.n_side[i], away, b.r_outer[i])) return false;
        if (!pw_ray(b.n_inner, b.n_side[i], away, b.r_inner[i])) return false;
    }
    glm::dvec3 ax = 0.5 * (b.a[0] + b.a[1]) - c;
    const double al = pw_len(ax);
    if (!(al > 0.0)) return false;
    b.axis = ax / al;
    const double tol = -1e-7 * scale;
    for (int i = 0; i < 2; ++i) {
        const glm::dvec3 po = b.a[i] + scale * b.r_outer[i], pi = b.a[i] + scale * b.r_inner[i];
        const glm::dvec3* ns[4] = {&b.n_outer, &b.n_inner, &b.n_side[0], &b.n_side[1]};
        const glm::dvec3 through[4] = {b.a[0], b.a[0], b.a[0], b.a[1]};
        for (int k = 0; k < 4; ++k) {
            if (pw_eval(*ns[k], through[k], po) < tol) return false;
            if (pw_eval(*ns[k], through[k], pi) < tol) return false;
        }
    }
    return true;
}

inline void pw_assign_bounds(PwBuild& b, const glm::dvec3& na, const glm::dvec3& nb, const glm::dvec3& nhat) {
    // The outer half-wedge lies between the hard plane and the plane whose inward normal points back
    // toward the hard shadow (dot(n, nhat) < 0).
    if (pw_dot(na, nhat) <= pw_dot(nb, nhat)) {
        b.n_outer = na;
        b.n_inner = nb;
    } else {
        b.n_outer = nb;
        b.n_inner = na;
    }
}

// Steps B and C for the apex edge (a0, a1).
inline bool pw_build_edge(const glm::dvec3& a0, const glm::dvec3& a1, const glm::dvec3& c, double r,
                          const glm::dvec3& nhat, double scale, PwBuild& b) {
    const glm::dvec3 ad = a1 - a0;
    const double len = pw_len(ad);
    if (!(len > 0.0)) return false;
    glm::dvec3 na, nb;
    if (!pw_tangent_planes(a0, ad / len, c, r, na, nb)) return false;
    b.a[0] = a0;
    b.a[1] = a1;
    pw_assign_bounds(b, na, nb, nhat);
    for (int i = 0; i < 2; ++i) {
        const glm::dvec3& ai = b.a[i];
        const glm::dvec3& aj = b.a[1 - i];
        glm::dvec3 s0, s1;
        if (!pw_tangent_planes(ai, nhat, c, r, s0, s1)) return false;
        const double d0 = pw_dot(s0, aj - ai), d1 = pw_dot(s1, aj - ai);
        const glm::dvec3 s = d0 >= d1 ? s0 : s1;
        if (!(std::max(d0, d1) > -1e-9 * len)) return false;
        b.n_side[i] = s;
    }
    return pw_finish(b, c, scale);
}

// Edge line through the ball: square pyramid around the shadow cone of the near endpoint `a`.
inline bool pw_build_cone(const glm::dvec3& a, const glm::dvec3& edge_dir, const glm::dvec3& c, double r,
                          const glm::dvec3& nhat, PwBuild& b) {
    const glm::dvec3 z = a - c;
    const double R = pw_len(z);
    if (!(R > r)) return false;
    glm::dvec3 x = pw_cross(nhat, z / R);
    const double xl = pw_len(x);
    if (!(xl > 0.0)) return false;
    x /= xl;
    if (pw_dot(x, edge_dir) < 0.0) x = -x;
    glm::dvec3 na, nb, s0, s1;
    if (!pw_tangent_planes(a, x, c, r, na, nb)) return false;
    if (!pw_tangent_planes(a, nhat, c, r, s0, s1)) return false;
    b.a[0] = a;
    b.a[1] = a;
    pw_assign_bounds(b, na, nb, nhat);
    // side[0] keeps the e1 direction inside, side[1] the e0 direction.
    if (pw_dot(s0, x) >= pw_dot(s1, x)) {
        b.n_side[0] = s0;
        b.n_side[1] = s1;
    } else {
        b.n_side[0] = s1;
        b.n_side[1] = s0;
    }
    for (int i = 0; i < 2; ++i) {
        if (!pw_ray(b.n_outer, b.n_side[i], z, b.r_outer[i])) return false;
        if (!pw_ray(b.n_inner, b.n_side[i], z, b.r_inner[i])) return false;
    }
    b.axis = z / R;
    return true;
}

// Coordinates near FLT_MAX can overflow the float plane offsets: report them as Overflow.
inline PenumbraWedge pw_check_finite(const PenumbraWedge& W) {
    const glm::vec4 pl[5] = {W.outer_bound, W.inner_bound, W.side[0], W.side[1], W.hard_plane};
    bool ok = true;
    for (const glm::vec4& p : pl) ok = ok && std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) && std::isfinite(p.w);
    for (int i = 0; i < 2; ++i)
        ok = ok && pw_finite(W.apex[i]) && pw_finite(W.ray_outer[i]) && pw_finite(W.ray_inner[i]);
    ok = ok && pw_finite(W.axis);
    if (ok) return W;
    PenumbraWedge bad;
    bad.status = Status::Overflow;
    bad.detail = "e0, e1: the wedge's planes or rays beyond float";
    return bad;
}

// The sphere light's center (double) and radius: InvalidLight unless a point light (w > 0, finite,
// not all zero), NonFinite for a NaN/Inf radius, InvalidArgument for r < 0, Overflow for a center
// xyz / w beyond float.
// `why` receives where a non-Ok status came from (a static string).
inline Status pw_light(const PenumbraSphereLight& L, glm::dvec3& c, double& r, const char*& why) {
    const glm::vec4& q = L.light_position;
    if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z) || !std::isfinite(q.w))
        return why = "light_position: NaN or Inf", Status::InvalidLight;
    if (!(q.w > 0.0f)) return why = "light_position: w <= 0 (a point light is needed)", Status::InvalidLight;
    if (!std::isfinite(L.radius)) return why = "radius: NaN or Inf", Status::NonFinite;
    if (!(L.radius >= 0.0f)) return why = "radius: < 0", Status::InvalidArgument;
    const double w = q.w;
    c = glm::dvec3(q.x / w, q.y / w, q.z / w);
    const double fmax = static_cast<double>(std::numeric_limits<float>::max());
    if (!(std::fabs(c.x) <= fmax && std::fabs(c.y) <= fmax && std::fabs(c.z) <= fmax))
        return why = "light_position: xyz / w beyond float", Status::Overflow;
    r = L.radius;
    return Status::Ok;
}

// Signed distance-like value of a point against a plane (inside >= 0), evaluated in double.
inline double pw_plane_eval(const glm::vec4& plane, const glm::vec3& p) {
    return static_cast<double>(plane.x) * p.x + static_cast<double>(plane.y) * p.y +
           static_cast<double>(plane.z) * p.z + static_cast<double>(plane.w);
}

// Signed coverage of the edge (e0, e1) at p for the disk (c, r), r > 0, all finite (header comment:
// projective clip to the disk, sector minus triangle, A&AM / Lengyel).
inline double pw_coverage(const glm::dvec3& e0, const glm::dvec3& e1, const glm::dvec3& c, double r, const glm::dvec3& p) {
    const glm::dvec3 d = c - p;
    const double D = pw_len(d);
    if (!(D > 0.0) || !std::isfinite(D)) return 0.0;
    const glm::dvec3 z = d / D;
    glm::dvec3 q0 = e0 - p, q1 = e1 - p;
    const glm::dvec3 np = pw_cross(q0, q1); // plane through p and the edge
    double w0 = pw_dot(q0, z), w1 = pw_dot(q1, z);
    // 1. only the part between p's depth plane... and the emitter (depth <= D) occludes
    if (w0 >= D && w1 >= D) return 0.0;
    if (w0 > D || w1 > D) {
        const double t = (D - w0) / (w1 - w0);
        const glm::dvec3 qc = q0 + t * (q1 - q0);
        if (w0 > D) { q0 = qc; w0 = D; } else { q1 = qc; w1 = D; }
    }
    if (w0 <= 0.0 && w1 <= 0.0) return 0.0;
    // 2. projected line: normal m in the disk plane, signed distance hs (light radii)
    const glm::dvec3 m = np - pw_dot(np, z) * z;
    const double ml = pw_len(m);
    if (!(ml > 0.0) || !std::isfinite(ml)) return 0.0;
    const double hs = -pw_dot(np, d) / (r * ml); // Lengyel/A&AM: > 0 outside the hard plane
    if (!std::isfinite(hs)) return 0.0;
    const double h = std::fabs(hs);
    if (h >= 1.0) return 0.0;
    const double s = std::sqrt(1.0 - h * h);
    const glm::dvec3 t = pw_cross(z, m) / ml; // unit direction of the projected line
    const double N0 = pw_dot(q0, t) * D, N1 = pw_dot(q1, t) * D;
    const double B0 = w0 * r, B1 = w1 * r; // lambda = N / B (homogeneous position along the line)
    const double inf = std::numeric_limits<double>::infinity();
    double lo, hi;
    if (B0 > 0.0 && B1 > 0.0) {
        const double l0 = N0 / B0, l1 = N1 / B1;
        lo = std::min(l0, l1);
        hi = std::max(l0, l1);
    } else {
        // one end behind p: its side of the projection runs to infinity in the direction of N at
        // the depth-0 crossing, N* = (B0 N1 - B1 N0) / (B0 - B1).
        const double nstar = (B0 * N1 - B1 * N0) / (B0 - B1);
        const double lk = B0 > 0.0 ? N0 / B0 : N1 / B1;
        if (nstar > 0.0) { lo = lk; hi = inf; }
        else if (nstar < 0.0) { lo = -inf; hi = lk; }
        else return 0.0; // the edge passes through p
    }
    const double a = std::max(lo, -s), bb = std::min(hi, s);
    if (!(a < bb)) return 0.0;
    // 3. sector minus triangle (Lengyel; A&AM's coverage), as a fraction of the disk area pi
    const double dl = bb - a;
    const double theta = std::atan2(h * dl, h * h + a * bb);
    const double area = std::max(0.0, (theta - h * dl) / (2.0 * 3.14159265358979323846));
    if (!std::isfinite(area)) return 0.0;
    // 4. sign: positive half space of the hard plane adds occlusion
    return hs >= 0.0 ? std::min(area, 0.5) : -std::min(area, 0.5);
}

// The cap quad (2, 3, 5, 4) of a hull need not be planar: the split along the diagonal that keeps the
// hull convex (the fourth vertex below the first triangle's plane, seen from outside).
inline void pw_cap_split(const glm::dvec3 v[6], const glm::dvec3& centroid, int cap[6]) {
    const int first[6] = {2, 3, 5, 2, 5, 4};
    std::copy(first, first + 6, cap);
    glm::dvec3 n = pw_cross(v[3] - v[2], v[5] - v[2]);
    if (pw_dot(n, v[2] - centroid) < 0.0) n = -n;
    if (pw_dot(n, v[4] - v[2]) > 0.0) { // 4 above (2, 3, 5): use the other diagonal
        const int alt[6] = {2, 3, 4, 3, 5, 4};
        std::copy(alt, alt + 6, cap);
    }
}

// Most points pw_clip_hull_box can produce: 8 triangles clipped by 6 planes (<= 9 vertices each)
// plus the 8 box corners.
constexpr std::size_t pw_clip_max = 8 * 9 + 8;

// Vertices of (finite convex hull v[6], triangles idx[24]) intersected with the box [lo, hi]:
// every hull triangle clipped against the six box planes (Sutherland-Hodgman: hull vertices in the
// box, hull edges x box faces, box edges x hull faces) plus the box corners inside the hull (face
// planes oriented away from the centroid; degenerate triangles ignored). Their convex hull is the
// intersection. Returns the count written to out (<= pw_clip_max).
inline std::size_t pw_clip_hull_box(const glm::dvec3 v[6], const std::uint8_t idx[24], const glm::dvec3& lo,
                                    const glm::dvec3& hi, glm::vec4* out) {
    std::size_t n = 0;
    glm::dvec3 centroid(0.0);
    for (int i = 0; i < 6; ++i) centroid += v[i] / 6.0;
    glm::dvec3 fn[8];
    double fd[8];
    for (int t = 0; t < 8; ++t) {
        const glm::dvec3 a = v[idx[3 * t]], b = v[idx[3 * t + 1]], c = v[idx[3 * t + 2]];
        fn[t] = pw_cross(b - a, c - a);
        if (pw_dot(fn[t], a - centroid) < 0.0) fn[t] = -fn[t];  // outward (the hull is convex)
        fd[t] = -pw_dot(fn[t], a);
        glm::dvec3 poly[10], tmp[10];
        int pn = 3;
        poly[0] = a;
        poly[1] = b;
        poly[2] = c;
        for (int k = 0; k < 6 && pn > 0; ++k) {
            const int ax = k / 2;
            const bool upper = (k % 2) == 1;
            const double lim = upper ? hi[ax] : lo[ax];
            int tn = 0;
            for (int i = 0; i < pn; ++i) {
                const glm::dvec3& P = poly[i];
                const glm::dvec3& Q = poly[(i + 1) % pn];
                const bool ip = upper ? P[ax] <= lim : P[ax] >= lim;
                const bool iq = upper ? Q[ax] <= lim : Q[ax] >= lim;
                if (ip && tn < 10) tmp[tn++] = P;
                if (ip != iq && tn < 10) {
                    const double s = (lim - P[ax]) / (Q[ax] - P[ax]);
                    glm::dvec3 X = P + s * (Q - P);
                    X[ax] = lim;
                    tmp[tn++] = X;
                }
            }
            pn = tn;
            for (int i = 0; i < pn; ++i) poly[i] = tmp[i];
        }
        for (int i = 0; i < pn && n < pw_clip_max; ++i) out[n++] = glm::vec4(glm::vec3(poly[i]), 1.0f);
    }
    for (int i = 0; i < 8 && n < pw_clip_max; ++i) {
        const glm::dvec3 q((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
        bool in = true;
        for (int t = 0; t < 8 && in; ++t) {
            const double l = pw_len(fn[t]);
            if (l > 0.0) in = pw_dot(fn[t], q) + fd[t] <= 1e-6 * l * (1.0 + pw_len(q) + pw_len(centroid));
        }
        if (in) out[n++] = glm::vec4(glm::vec3(q), 1.0f);
    }
    return n;
}

} // namespace detail

/// Circumscribed sphere of a rectangular light (center light_position, a point light w > 0, and two
/// half-axis vectors): wedges built for it are conservative for the rectangle. Coverage with it is that
/// of the circumscribed disk. Statuses: InvalidLight (not a point light), NonFinite (NaN/Inf half
/// axes), Overflow (a radius beyond float).
inline PenumbraBoundingSphere penumbra_rect_bounding_sphere(const glm::vec4& light_position, glm::vec3 half_u,
                                                           glm::vec3 half_v) {
    PenumbraBoundingSphere R;
    PenumbraSphereLight probe;
    probe.light_position = light_position;
    glm::dvec3 c;
    double r0 = 0.0;
    R.status = detail::pw_light(probe, c, r0, R.detail);
    if (R.status != Status::Ok) return R;
    if (!detail::pw_finite(half_u) || !detail::pw_finite(half_v)) {
        R.status = Status::NonFinite;
        R.detail = !detail::pw_finite(half_u) ? "half_u: NaN or Inf" : "half_v: NaN or Inf";
        return R;
    }
    const glm::dvec3 u = detail::pw_d(half_u), v = detail::pw_d(half_v);
    const double r = std::max(detail::pw_len(u + v), detail::pw_len(u - v));
    R.light.light_position = light_position;
    // round up so that the float radius still encloses the corners
    R.light.radius = std::nextafter(static_cast<float>(r), std::numeric_limits<float>::infinity());
    if (!std::isfinite(R.light.radius)) {
        R.light.radius = 0.0f;
        R.status = Status::Overflow;
        R.detail = "half_u, half_v: radius beyond float";
        return R;
    }
    R.status = Status::Ok;
    return R;
}

namespace detail {

// The edge (E0, E1) meets the light's ball, within float input precision (1e-7 of the coordinates'
// size); the closest point is parametrised from the nearer endpoint (no cancellation for a huge far one).
inline bool pw_edge_touches_light(const glm::dvec3& E0, const glm::dvec3& E1, const glm::dvec3& c, double r) {
    const glm::dvec3 ed = E1 - E0;
    const bool zero_near = pw_len(E0 - c) <= pw_len(E1 - c);
    const glm::dvec3 En = zero_near ? E0 : E1, dn = zero_near ? ed : -ed;
    const double t = std::min(1.0, std::max(0.0, pw_dot(c - En, dn) / pw_dot(ed, ed)));
    const glm::dvec3 closest = En + t * dn;
    const double slack = 1e-7 * std::max({pw_len(c), pw_len(E0), pw_len(E1), r});
    return pw_len(c - closest) <= r + slack || pw_len(E0 - c) <= r + slack || pw_len(E1 - c) <= r + slack;
}

// The wedge's numerical last resort: the half-space beyond the ball's tangent plane at the direction
// of the edge's closest point; it contains P(E) for any edge outside the ball. `padding` moves every
// bounding plane outward, here too.
inline PenumbraWedge pw_half_space_wedge(const glm::dvec3& E0, const glm::dvec3& E1, const glm::dvec3& c, double r,
                                         const glm::dvec3& nhat, float padding) {
    PenumbraWedge W;
    const glm::dvec3 ed = E1 - E0;
    const bool zero_near = pw_len(E0 - c) <= pw_len(E1 - c);
    const glm::dvec3 En = zero_near ? E0 : E1, dn = zero_near ? ed : -ed;
    const double t = std::min(1.0, std::max(0.0, pw_dot(c - En, dn) / pw_dot(ed, ed)));
    glm::dvec3 u = En + t * dn - c;
    u /= pw_len(u);
    const glm::dvec3 through = c + r * u;
    W.shape = PenumbraWedgeShape::HalfSpace;
    W.outer_bound = W.inner_bound = W.side[0] = W.side[1] = pw_plane_f(u, through);
    W.outer_bound.w += padding;
    W.inner_bound.w += padding;
    W.side[0].w += padding;
    W.side[1].w += padding;
    W.hard_plane = pw_plane_f(nhat, c);
    W.apex[0] = W.apex[1] = glm::vec3(through);
    W.ray_outer[0] = W.ray_outer[1] = W.ray_inner[0] = W.ray_inner[1] = glm::vec3(u);
    W.axis = glm::vec3(u);
    W.status = Status::Ok;
    return pw_check_finite(W);
}

}  // namespace detail

/// Penumbra wedge of the silhouette edge (e0, e1) for a sphere light (A&AM 2003, steps A-C).
/// `padding` [world, >= 0] moves every bounding plane outward (absorbs float rounding of far geometry).
/// Skipped edges (Ok, `skip` != None) and errors: see the header comment.
inline PenumbraWedge penumbra_wedge(glm::vec3 e0, glm::vec3 e1, const PenumbraSphereLight& light,
                                    float padding = 0.0f) {
    using namespace detail;
    PenumbraWedge W;
    glm::dvec3 c;
    double r = 0.0;
    W.status = pw_light(light, c, r, W.detail);
    if (W.status != Status::Ok) return W;
    W.status = Status::NotRun;
    if (!pw_finite(e0) || !pw_finite(e1) || !std::isfinite(padding)) {
        W.status = Status::NonFinite;
        W.detail = !pw_finite(e0) ? "e0: NaN or Inf" : (!pw_finite(e1) ? "e1: NaN or Inf" : "padding: NaN or Inf");
        return W;
    }
    if (!(padding >= 0.0f)) {
        W.status = Status::InvalidArgument;
        W.detail = "padding: < 0";
        return W;
    }
    const glm::dvec3 E0 = pw_d(e0), E1 = pw_d(e1);
    const glm::dvec3 ed = E1 - E0;
    const double el2 = pw_dot(ed, ed);
    if (!(el2 > 0.0)) {
        W.status = Status::Ok;
        W.skip = PenumbraWedgeSkip::DegenerateEdge;
        return W;
    }
    if (pw_edge_touches_light(E0, E1, c, r)) {
        W.status = Status::Ok;
        W.skip = PenumbraWedgeSkip::EdgeTouchesLight;
        return W;
    }
    // = cross(e0 - c, e1 - c), but e1 - c cancels against e0 - c for an edge far shorter than its
    // distance to the light (the plane then missed the edge; found by fuzz_penumbra_wedge)
    const glm::dvec3 nh = pw_cross(E0 - c, ed);
    const double nl = pw_len(nh);
    if (!std::isfinite(nl)) {
        W.status = Status::Overflow;
        W.detail = "e0, e1: the edge plane's normal beyond double";
        return W;
    }
    if (!(nl > 0.0)) {
        W.status = Status::Ok;
        W.skip = PenumbraWedgeSkip::RadialEdge;
        return W;
    }
    const glm::dvec3 nhat = nh / nl;
    const double R0 = pw_len(E0 - c), R1 = pw_len(E1 - c);
    const double scale = std::max(R0, R1);
    // Step A: move the farther endpoint toward the light center to the nearer one's distance.
    glm::dvec3 a0 = E0, a1 = E1;
    if (R0 > R1) a0 = c + (E0 - c) * (R1 / R0);
    else if (R1 > R0) a1 = c + (E1 - c) * (R0 / R1);
    PwBuild b{};
    // distance from c to the edge's own line (decides between the two fallbacks)
    const glm::dvec3 ce = c - E0;
    const double hE = pw_len(ce - (pw_dot(ce, ed) / el2) * ed);
    if (pw_build_edge(a0, a1, c, r, nhat, scale, b)) {
        W.shape = PenumbraWedgeShape::Equidistant;
    } else if (hE >= r && pw_build_edge(E0, E1, c, r, nhat, scale, b)) {
        W.shape = PenumbraWedgeShape::OriginalEndpoints;
    } else if (hE < r && pw_build_cone(R0 <= R1 ? E0 : E1, ed, c, r, nhat, b)) {
        W.shape = PenumbraWedgeShape::Cone;
    } else {
        return pw_half_space_wedge(E0, E1, c, r, nhat, padding);  // numerical last resort (not met in the tests)
    }
    const float pad = padding;
    W.outer_bound = pw_plane_f(b.n_outer, b.a[0]);
    W.inner_bound = pw_plane_f(b.n_inner, b.a[0]);
    W.side[0] = pw_plane_f(b.n_side[0], b.a[0]);
    W.side[1] = pw_plane_f(b.n_side[1], b.a[1]);
    W.outer_bound.w += pad;
    W.inner_bound.w += pad;
    W.side[0].w += pad;
    W.side[1].w += pad;
    W.hard_plane = pw_plane_f(nhat, c);
    for (int i = 0; i < 2; ++i) {
        W.apex[i] = glm::vec3(b.a[i]);
        W.ray_outer[i] = glm::vec3(b.r_outer[i]);
        W.ray_inner[i] = glm::vec3(b.r_inner[i]);
    }
    W.axis = glm::vec3(b.axis);
    W.status = Status::Ok;
    return pw_check_finite(W);
}

/// True when p is inside all four bounding planes (each >= -tolerance). Total: false for a wedge that
/// is not Ok or is skipped, and for NaN input.
inline bool penumbra_point_in_wedge(const glm::vec3& p, const PenumbraWedge& w, float tolerance = 0.0f) {
    if (w.status != Status::Ok || w.skip != PenumbraWedgeSkip::None) return false;
    const double t = -static_cast<double>(tolerance);
    return detail::pw_plane_eval(w.outer_bound, p) >= t && detail::pw_plane_eval(w.inner_bound, p) >= t &&
           detail::pw_plane_eval(w.side[0], p) >= t && detail::pw_plane_eval(w.side[1], p) >= t;
}

/// Lengyel's outer half-wedge (outside the hard shadow): outer_bound, side[0], side[1]. Total: copies
/// the planes (zero planes for a skipped or failed wedge).
inline PenumbraHalfWedge penumbra_outer_half_wedge(const PenumbraWedge& w) {
    PenumbraHalfWedge h;
    h.planes[0] = w.outer_bound;
    h.planes[1] = w.side[0];
    h.planes[2] = w.side[1];
    return h;
}

/// Lengyel's inner half-wedge (inside the hard shadow): inner_bound, side[0], side[1]. Total, as above.
inline PenumbraHalfWedge penumbra_inner_half_wedge(const PenumbraWedge& w) {
    PenumbraHalfWedge h;
    h.planes[0] = w.inner_bound;
    h.planes[1] = w.side[0];
    h.planes[2] = w.side[1];
    return h;
}

/// Point in a half-wedge: its three planes and the hard plane (>= 0 for the outer, <= 0 for the
/// inner), each within `tolerance`. Total, as penumbra_point_in_wedge.
inline bool penumbra_point_in_half_wedge(const glm::vec3& p, const PenumbraWedge& w, bool outer, float tolerance = 0.0f) {
    if (!penumbra_point_in_wedge(p, w, tolerance)) return false;
    const double h = detail::pw_plane_eval(w.hard_plane, p);
    return outer ? h >= -static_cast<double>(tolerance) : h <= static_cast<double>(tolerance);
}

/// Plane transformed by a point transform M (x' = M x): inverse(M)^T * plane, so that
/// dot(plane', M x) = dot(plane, x). For a projective M (e.g. world -> viewport), dividing the point by
/// its w > 0 keeps the sign. Statuses: NonFinite (NaN/Inf in plane or M), InvalidArgument (M
/// singular), Overflow (a result beyond float).
inline PenumbraPlane penumbra_transform_plane(const glm::vec4& plane, const glm::mat4& M) {
    PenumbraPlane R;
    glm::dmat4 m(M);
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            if (!std::isfinite(m[i][j])) {
                R.status = Status::NonFinite;
                R.detail = "M: NaN or Inf";
                return R;
            }
    if (!std::isfinite(plane.x) || !std::isfinite(plane.y) || !std::isfinite(plane.z) || !std::isfinite(plane.w)) {
        R.status = Status::NonFinite;
        R.detail = "plane: NaN or Inf";
        return R;
    }
    // Cofactor expansion in double; inverse^T = cofactor matrix / det.
    double a[4][4];
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) a[i][j] = m[j][i]; // a[row][col]
    double cof[4][4];
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            double sm[3][3];
            int si = 0;
            for (int r = 0; r < 4; ++r) {
                if (r == i) continue;
                int sj = 0;
                for (int k = 0; k < 4; ++k) {
                    if (k == j) continue;
                    sm[si][sj++] = a[r][k];
                }
                ++si;
            }
            const double minor = sm[0][0] * (sm[1][1] * sm[2][2] - sm[1][2] * sm[2][1]) -
                                 sm[0][1] * (sm[1][0] * sm[2][2] - sm[1][2] * sm[2][0]) +
                                 sm[0][2] * (sm[1][0] * sm[2][1] - sm[1][1] * sm[2][0]);
            cof[i][j] = ((i + j) % 2 == 0 ? 1.0 : -1.0) * minor;
        }
    double det = 0.0;
    for (int j = 0; j < 4; ++j) det += a[0][j] * cof[0][j];
    if (!std::isfinite(det)) {
        R.status = Status::Overflow;
        R.detail = "M: determinant beyond double";
        return R;
    }
    if (!(std::fabs(det) > 0.0)) {
        R.status = Status::InvalidArgument;
        R.detail = "M: singular";
        return R;
    }
    // inverse(A)^T = cof / det (row-major indices); apply to the plane column vector.
    const double pl[4] = {plane.x, plane.y, plane.z, plane.w};
    double out[4];
    for (int i = 0; i < 4; ++i) {
        double sum = 0.0;
        for (int j = 0; j < 4; ++j) sum += cof[i][j] * pl[j];
        out[i] = sum / det;
    }
    R.plane = glm::vec4(static_cast<float>(out[0]), static_cast<float>(out[1]), static_cast<float>(out[2]),
                        static_cast<float>(out[3]));
    if (!std::isfinite(R.plane.x) || !std::isfinite(R.plane.y) || !std::isfinite(R.plane.z) || !std::isfinite(R.plane.w)) {
        R.plane = glm::vec4(0.0f);
        R.status = Status::Overflow;
        R.detail = "plane: the transformed plane beyond float";
        return R;
    }
    R.status = Status::Ok;
    return R;
}

/// NDC -> window transform (x, y in pixels, z in [0, 1] for glDepthRange(0, 1)) for a viewport
/// (x, y, width, height) as glViewport takes it (ScissorParams::viewport). Multiply by view_proj to
/// get the world -> viewport transform for penumbra_transform_plane. `viewport` holds 4 int
/// elements; width or height <= 0, a null pointer, or |values| > 2^30 -> InvalidArgument.
inline PenumbraMatrix penumbra_viewport_transform(const int viewport[4], ClipDepth clip_depth) {
    PenumbraMatrix R;
    const int lim = 1 << 30;
    if (viewport == nullptr || viewport[2] <= 0 || viewport[3] <= 0 || viewport[2] > lim || viewport[3] > lim ||
        viewport[0] > lim || viewport[0] < -lim || viewport[1] > lim || viewport[1] < -lim) {
        R.status = Status::InvalidArgument;
        R.detail = viewport == nullptr ? "viewport: null" : "viewport: no width / height, or beyond 2^30";
        return R;
    }
    glm::mat4 V(1.0f);
    V[0][0] = 0.5f * static_cast<float>(viewport[2]);
    V[1][1] = 0.5f * static_cast<float>(viewport[3]);
    V[3][0] = static_cast<float>(viewport[0]) + 0.5f * static_cast<float>(viewport[2]);
    V[3][1] = static_cast<float>(viewport[1]) + 0.5f * static_cast<float>(viewport[3]);
    if (clip_depth == ClipDepth::NegativeOneToOne) {
        V[2][2] = 0.5f;
        V[3][2] = 0.5f;
    }
    R.matrix = V;
    R.status = Status::Ok;
    return R;
}

/// Signed light coverage of one silhouette edge at receiver point p (see the header comment:
/// projective clip to the disk, sector minus triangle, A&AM / Lengyel), value in [-1/2, 1/2], double
/// precision. Radius 0, p at the light's center or on the edge's line: 0 (Ok). Statuses: the light's
/// (InvalidLight, NonFinite, InvalidArgument, Overflow), NonFinite for NaN/Inf e0, e1 or p.
inline PenumbraValue penumbra_edge_coverage(glm::vec3 e0, glm::vec3 e1, const PenumbraSphereLight& light, glm::vec3 p) {
    using namespace detail;
    PenumbraValue R;
    glm::dvec3 c;
    double r = 0.0;
    R.status = pw_light(light, c, r, R.detail);
    if (R.status != Status::Ok) return R;
    if (!pw_finite(e0) || !pw_finite(e1) || !pw_finite(p)) {
        R.status = Status::NonFinite;
        R.detail = !pw_finite(e0) ? "e0: NaN or Inf" : (!pw_finite(e1) ? "e1: NaN or Inf" : "p: NaN or Inf");
        return R;
    }
    R.value = r > 0.0 ? pw_coverage(pw_d(e0), pw_d(e1), c, r, pw_d(p)) : 0.0;
    return R;
}

/// Visibility of the light from p for one occluder: V = 1 - clamp(hard_count + sum of the edges'
/// coverages, 0, 1) (A&AM), value in [0, 1]. `endpoints` holds 2 * edge_count glm::vec3 elements:
/// endpoints[2i], endpoints[2i+1] = silhouette edge i (as seen from the light's center, oriented as
/// in its light-facing triangle); hard_count = the stencil count at p (number of hard shadow volumes
/// containing p). Statuses: InvalidArgument (null endpoints with edge_count > 0), NonFinite (NaN/Inf
/// in an endpoint or p), and the light's.
inline PenumbraValue penumbra_visibility(const glm::vec3* endpoints, std::size_t edge_count,
                                         const PenumbraSphereLight& light, glm::vec3 p, int hard_count) {
    using namespace detail;
    PenumbraValue R;
    glm::dvec3 c;
    double r = 0.0;
    R.status = pw_light(light, c, r, R.detail);
    if (R.status != Status::Ok) return R;
    if (!endpoints && edge_count > 0) {
        R.status = Status::InvalidArgument;
        R.detail = "endpoints: null with edge_count > 0";
        return R;
    }
    if (!pw_finite(p)) {
        R.status = Status::NonFinite;
        R.detail = "p: NaN or Inf";
        return R;
    }
    for (std::size_t i = 0; i < 2 * edge_count; ++i)
        if (!pw_finite(endpoints[i])) {
            R.status = Status::NonFinite;
            R.detail = "endpoints: NaN or Inf";
            return R;
        }
    double sum = static_cast<double>(hard_count);
    if (r > 0.0)
        for (std::size_t i = 0; i < edge_count; ++i)
            sum += pw_coverage(pw_d(endpoints[2 * i]), pw_d(endpoints[2 * i + 1]), c, r, pw_d(p));
    R.value = 1.0 - std::min(1.0, std::max(0.0, sum));
    R.status = Status::Ok;
    return R;
}

/// Wedge hull (A&AM step D, the limited extension): far vertices at distance `extent` [world, > 0]
/// along the four edge rays; extent = +Inf gives w = 0 far vertices (directions) for an infinite
/// projection. The hull is convex and lies inside the wedge; it covers the wedge up to distance
/// extent * min(cos) from the apex. Ok with drawable = false for a skipped wedge and shape HalfSpace.
/// Statuses: InvalidArgument (a wedge that is not Ok, extent <= 0), NonFinite (extent NaN), Overflow
/// (far vertices beyond float).
inline PenumbraWedgeHull penumbra_wedge_hull(const PenumbraWedge& w, float extent) {
    using namespace detail;
    PenumbraWedgeHull H;
    if (w.status != Status::Ok) {
        H.status = Status::InvalidArgument;
        H.detail = "w: status not Ok";
        return H;
    }
    if (std::isnan(extent)) {
        H.status = Status::NonFinite;
        H.detail = "extent: NaN";
        return H;
    }
    if (!(extent > 0.0f)) {
        H.status = Status::InvalidArgument;
        H.detail = "extent: not > 0";
        return H;
    }
    if (w.skip != PenumbraWedgeSkip::None || w.shape == PenumbraWedgeShape::HalfSpace) {
        H.status = Status::Ok;
        return H;
    }
    const bool infinite = std::isinf(extent);
    const glm::dvec3 a[2] = {pw_d(w.apex[0]), pw_d(w.apex[1])};
    // orientation is decided on a finite stand-in when the extent is infinite
    const double ext = infinite ? std::max(1.0, pw_len(a[1] - a[0])) : static_cast<double>(extent);
    const glm::dvec3 ro[2] = {pw_d(w.ray_outer[0]), pw_d(w.ray_outer[1])};
    const glm::dvec3 ri[2] = {pw_d(w.ray_inner[0]), pw_d(w.ray_inner[1])};
    glm::dvec3 v[6];
    v[0] = a[0];
    v[1] = a[1];
    for (int i = 0; i < 2; ++i) {
        v[2 + i] = a[i] + ext * ro[i];
        v[4 + i] = a[i] + ext * ri[i];
    }
    glm::dvec3 centroid(0.0);
    for (const glm::dvec3& x : v) centroid += x / 6.0;
    int cap[6];
    pw_cap_split(v, centroid, cap);
    // faces with their outward normals (inside normals negated); the cap faces away from the centroid
    const glm::dvec3 out_outer = -glm::dvec3(w.outer_bound), out_inner = -glm::dvec3(w.inner_bound);
    const glm::dvec3 out_s0 = -glm::dvec3(w.side[0]), out_s1 = -glm::dvec3(w.side[1]);
    const int tris[8][3] = {{0, 1, 3}, {0, 3, 2}, {0, 1, 5}, {0, 5, 4}, {0, 2, 4}, {1, 3, 5},
                            {cap[0], cap[1], cap[2]}, {cap[3], cap[4], cap[5]}};
    for (int t = 0; t < 8; ++t) {
        int i = tris[t][0], j = tris[t][1], k = tris[t][2];
        const glm::dvec3 n = pw_cross(v[j] - v[i], v[k] - v[i]);
        const glm::dvec3 out = t < 2 ? out_outer : t < 4 ? out_inner : t == 4 ? out_s0 : t == 5 ? out_s1
                                                                                             : (v[i] + v[j] + v[k]) / 3.0 - centroid;
        if (pw_dot(n, out) < 0.0) std::swap(j, k);
        H.indices[3 * t + 0] = static_cast<std::uint8_t>(i);
        H.indices[3 * t + 1] = static_cast<std::uint8_t>(j);
        H.indices[3 * t + 2] = static_cast<std::uint8_t>(k);
    }
    for (int i = 0; i < 6; ++i) {
        if (infinite && i >= 2) {
            const glm::dvec3 dir = i < 4 ? ro[i - 2] : ri[i - 4];
            H.vertices[i] = glm::vec4(glm::vec3(dir), 0.0f);
        } else {
            H.vertices[i] = glm::vec4(glm::vec3(v[i]), 1.0f);
        }
        if (!std::isfinite(H.vertices[i].x) || !std::isfinite(H.vertices[i].y) || !std::isfinite(H.vertices[i].z)) {
            PenumbraWedgeHull bad;
            bad.status = Status::Overflow;
            bad.detail = "extent: a hull vertex beyond float";
            return bad;
        }
    }
    H.drawable = true;
    H.status = Status::Ok;
    return H;
}

/// Scissor rectangle and depth bounds of the convex hull of homogeneous points (w >= 0; w = 0 are
/// points at infinity) after clipping to the near plane (O(count^2) work): every pixel/depth the hull
/// can produce lies inside (Lengyel: 40-45% faster wedge passes with per-geometry scissor + depth
/// bounds). `points` holds `count` glm::vec4 elements. count 0, or everything behind the near plane:
/// visible = false (Ok). Statuses: InvalidArgument (a zero or negative viewport size, |viewport| >
/// 2^30, a zero or singular view_proj, null points with count > 0, a point with w < 0), NonFinite
/// (NaN/Inf in view_proj or a point).
inline ScissorRect penumbra_points_scissor(const glm::vec4* points, std::size_t count, const ScissorParams& sp) {
    ScissorRect S;
    const int lim = 1 << 30;
    if (sp.viewport[2] <= 0 || sp.viewport[3] <= 0 || sp.viewport[2] > lim || sp.viewport[3] > lim ||
        std::abs(sp.viewport[0]) > lim || std::abs(sp.viewport[1]) > lim || (!points && count > 0)) {
        S.status = Status::InvalidArgument;
        S.detail = !points && count > 0 ? "points: null with count > 0" : "viewport: no width / height, or beyond 2^30";
        return S;
    }
    const glm::dmat4 VP(sp.view_proj);
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            if (!std::isfinite(VP[i][j])) {
                S.status = Status::NonFinite;
                S.detail = "view_proj: NaN or Inf";
                return S;
            }
    const double det = glm::determinant(VP);
    if (!(std::fabs(det) > 0.0) || !std::isfinite(det)) {  // the zero matrix of a default ScissorParams
        S.status = Status::InvalidArgument;
        S.detail = "view_proj: singular (or the zero default)";
        return S;
    }
    for (std::size_t i = 0; i < count; ++i) {
        const glm::vec4& P = points[i];
        if (!std::isfinite(P.x) || !std::isfinite(P.y) || !std::isfinite(P.z) || !std::isfinite(P.w)) {
            S.status = Status::NonFinite;
            S.detail = "points: NaN or Inf";
            return S;
        }
        if (P.w < 0.0f) {
            S.status = Status::InvalidArgument;
            S.detail = "points: w < 0";
            return S;
        }
    }
    S.status = Status::Ok;
    if (count == 0) return S;
    auto near_dist = [&](const glm::dvec4& c) {
        if (sp.reversed_z) return c.w - c.z;
        return sp.clip_depth == ClipDepth::NegativeOneToOne ? c.z + c.w : c.z;
    };
    double xmin = std::numeric_limits<double>::infinity(), xmax = -xmin, ymin = xmin, ymax = -xmin;
    double zmin = xmin, zmax = -xmin;
    bool any = false, full = false;
    auto add = [&](const glm::dvec4& c) {
        if (!(c.w > 0.0)) { full = true; return; } // degenerate projection: be conservative
        const double x = c.x / c.w, y = c.y / c.w, z = c.z / c.w;
        if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) { full = true; return; }
        any = true;
        xmin = std::min(xmin, x); xmax = std::max(xmax, x);
        ymin = std::min(ymin, y); ymax = std::max(ymax, y);
        const double wz = sp.clip_depth == ClipDepth::NegativeOneToOne ? 0.5 * z + 0.5 : z;
        zmin = std::min(zmin, wz); zmax = std::max(zmax, wz);
    };
    // clipped hull vertices = points in front + near-plane crossings of every pair (O(count^2))
    for (std::size_t i = 0; i < count; ++i) {
        const glm::dvec4 ci = VP * glm::dvec4(points[i]);
        const double ni = near_dist(ci);
        if (ni >= 0.0) add(ci);
        for (std::size_t j = i + 1; j < count; ++j) {
            const glm::dvec4 cj = VP * glm::dvec4(points[j]);
            const double nj = near_dist(cj);
            if ((ni >= 0.0) != (nj >= 0.0)) add(ci + (ni / (ni - nj)) * (cj - ci));
        }
    }
    if (!any && !full) return S; // entirely behind the near plane
    const double vx = sp.viewport[0], vy = sp.viewport[1], vw = sp.viewport[2], vh = sp.viewport[3];
    if (full) { xmin = -1.0; xmax = 1.0; ymin = -1.0; ymax = 1.0; zmin = 0.0; zmax = 1.0; }
    xmin = std::max(xmin, -1.0); xmax = std::min(xmax, 1.0);
    ymin = std::max(ymin, -1.0); ymax = std::min(ymax, 1.0);
    zmin = std::max(zmin, 0.0); zmax = std::min(zmax, 1.0);
    if (!(xmin <= xmax) || !(ymin <= ymax) || !(zmin <= zmax)) return S;
    double px0 = std::floor(vx + (0.5 * xmin + 0.5) * vw), px1 = std::ceil(vx + (0.5 * xmax + 0.5) * vw);
    double py0 = std::floor(vy + (0.5 * ymin + 0.5) * vh), py1 = std::ceil(vy + (0.5 * ymax + 0.5) * vh);
    // at least one pixel, inside the viewport
    if (px1 - px0 < 1.0) { if (px0 >= vx + vw) px0 = vx + vw - 1.0; px1 = px0 + 1.0; }
    if (py1 - py0 < 1.0) { if (py0 >= vy + vh) py0 = vy + vh - 1.0; py1 = py0 + 1.0; }
    S.x = static_cast<int>(px0);
    S.y = static_cast<int>(py0);
    S.width = static_cast<int>(px1 - px0);
    S.height = static_cast<int>(py1 - py0);
    S.depth_min = static_cast<float>(zmin);
    S.depth_max = static_cast<float>(zmax);
    // round the float depth bounds outward
    if (static_cast<double>(S.depth_min) > zmin) S.depth_min = std::nextafter(S.depth_min, -1.0f);
    if (static_cast<double>(S.depth_max) < zmax) S.depth_max = std::nextafter(S.depth_max, 2.0f);
    S.depth_min = std::max(S.depth_min, 0.0f);
    S.depth_max = std::min(S.depth_max, 1.0f);
    S.visible = true;
    return S;
}

/// Scissor rectangle and depth bounds of a whole wedge hull (penumbra_points_scissor of its six
/// vertices). A hull with nothing to draw (drawable = false): visible = false (Ok); a hull that is not
/// Ok: InvalidArgument. With a large extent this culls little: prefer penumbra_wedge_scissor_in_box.
inline ScissorRect penumbra_wedge_scissor(const PenumbraWedgeHull& hull, const ScissorParams& sp) {
    if (hull.status != Status::Ok) {
        ScissorRect S;
        S.status = Status::InvalidArgument;
        S.detail = "hull: status not Ok";
        return S;
    }
    if (!hull.drawable) {
        ScissorRect S = penumbra_points_scissor(nullptr, 0, sp);  // validates sp, visible = false
        return S;
    }
    return penumbra_points_scissor(hull.vertices, 6, sp);
}

/// Scissor rectangle and depth bounds of (wedge hull intersected with the box [box_min, box_max]),
/// Lengyel's clip to the light's bounds: pass the light's range box or the receivers' bounding box
/// (only points in it can receive light). See "Scissor and depth bounds" in the header comment. The
/// hull outside the box: visible = false (Ok). Statuses: as penumbra_wedge_scissor, plus NonFinite
/// (NaN/Inf box) and InvalidArgument (box_min > box_max in a coordinate).
inline ScissorRect penumbra_wedge_scissor_in_box(const PenumbraWedgeHull& hull, const glm::vec3& box_min,
                                                 const glm::vec3& box_max, const ScissorParams& sp) {
    using namespace detail;
    ScissorRect S = penumbra_points_scissor(nullptr, 0, sp);  // validates sp
    if (S.status != Status::Ok) return S;
    if (hull.status != Status::Ok) {
        S.status = Status::InvalidArgument;
        S.detail = "hull: status not Ok";
        return S;
    }
    if (!pw_finite(box_min) || !pw_finite(box_max)) {
        S.status = Status::NonFinite;
        S.detail = "box_min, box_max: NaN or Inf";
        return S;
    }
    if (box_min.x > box_max.x || box_min.y > box_max.y || box_min.z > box_max.z) {
        S.status = Status::InvalidArgument;
        S.detail = "box_min: > box_max";
        return S;
    }
    if (!hull.drawable) return S;
    const glm::dvec3 lo = pw_d(box_min), hi = pw_d(box_max);
    glm::dvec3 v[6];
    std::uint8_t idx[24];
    std::copy(hull.indices, hull.indices + 24, idx);
    bool infinite = false;
    for (int i = 0; i < 6; ++i) {
        v[i] = glm::dvec3(hull.vertices[i]);
        if (hull.vertices[i].w == 0.0f) infinite = true;
        else if (hull.vertices[i].w != 1.0f) v[i] /= static_cast<double>(hull.vertices[i].w);
    }
    if (infinite) {
        // w = 0 far vertices (directions from apex 0 / 1): cut the hull off beyond the box. The cap's
        // planes must leave every box corner inside; double the extent until they do.
        glm::dvec3 corner[8];
        double ext = 1.0;
        for (int i = 0; i < 8; ++i) {
            corner[i] = glm::dvec3((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
            ext = std::max({ext, pw_len(corner[i] - v[0]), pw_len(corner[i] - v[1])});
        }
        const glm::dvec3 dir[4] = {glm::dvec3(hull.vertices[2]), glm::dvec3(hull.vertices[3]), glm::dvec3(hull.vertices[4]),
                                   glm::dvec3(hull.vertices[5])};
        bool covered = false;
        for (int it = 0; it < 64 && !covered && std::isfinite(ext); ++it, ext *= 2.0) {
            for (int i = 2; i < 6; ++i) {
                const glm::dvec3 base = hull.vertices[i].w == 0.0f ? v[(i - 2) % 2] : glm::dvec3(0.0);
                v[i] = hull.vertices[i].w == 0.0f ? base + ext * dir[i - 2] : glm::dvec3(hull.vertices[i]) / double(hull.vertices[i].w);
            }
            glm::dvec3 centroid(0.0);
            for (const glm::dvec3& x : v) centroid += x / 6.0;
            int cap[6];
            pw_cap_split(v, centroid, cap);
            for (int k = 0; k < 6; ++k) idx[18 + k] = static_cast<std::uint8_t>(cap[k]);
            covered = true;
            for (int t = 0; t < 2 && covered; ++t) {
                const glm::dvec3 a = v[cap[3 * t]], b = v[cap[3 * t + 1]], c = v[cap[3 * t + 2]];
                glm::dvec3 n = pw_cross(b - a, c - a);
                if (pw_dot(n, a - centroid) < 0.0) n = -n;
                for (const glm::dvec3& q : corner)
                    if (pw_dot(n, q - a) > 0.0) covered = false;
            }
        }
        if (!covered) return penumbra_wedge_scissor(hull, sp);  // conservative: the whole hull
    }
    glm::vec4 pts[pw_clip_max];
    const std::size_t n = pw_clip_hull_box(v, idx, lo, hi, pts);
    return penumbra_points_scissor(pts, n, sp);
}

} // namespace shadowkit
