// shadowkit/shadow_volume.hpp - robust stenciled shadow volumes: side quads, caps, z-pass / z-fail, scissor and depth bounds.
// Side quads extruded to infinity (w = 0), light and dark caps for z-fail, open-mesh handling, the
// per-occluder z-pass / z-fail decision, and the per-occluder scissor rectangle and depth bounds.
// Plain arrays in (positions, silhouette edge index pairs, triangles, per-triangle lit flags); no
// dependency on other shadowkit headers (silhouette.hpp computes the lit flags and edges).
//
// Usage (per light, per occluder; the complete GL path is docs/shadow_volume.md):
//   #include <shadowkit/silhouette.hpp>
//   #include <shadowkit/shadow_volume.hpp>
//   // once per mesh: the 2n-vertex volume buffer (p, 1) then (p, 0); the vertex shader extrudes w = 0
//   std::vector<glm::vec4> vb(2 * n);
//   shadowkit::volume_build_vertices(pos, n, vb.data(), vb.size());
//   std::vector<std::uint32_t> ib(shadowkit::volume_indices_capacity(sil.size(), index_count));
//   // per frame: facing + silhouette (silhouette.hpp), then
//   shadowkit::VolumeNearRect near = shadowkit::volume_near_plane_rect(view, fovy, aspect, near_z);
//   shadowkit::VolumeMethod m = shadowkit::volume_choose_stencil_method_box(near, light_position, bmin, bmax, 1e-4f);
//   std::size_t ns = shadowkit::volume_build_side_quads(sil.data(), r.count, n, ib.data(), ib.size()).count;
//   std::size_t nc = 0;
//   if (m.method == shadowkit::VolumeStencilMethod::ZFail)
//       nc = shadowkit::volume_build_caps(adj.faces.data(), adj.faces.size(), lit.data(), lit.size(), n,
//                                         shadowkit::VolumeCapMode::LitOnly, true, ib.data() + ns, ib.size() - ns).count;
//   shadowkit::ScissorParams sp;                      // every field required
//   sp.view_proj = proj * view;
//   sp.viewport[2] = width; sp.viewport[3] = height;
//   shadowkit::ScissorRect s = shadowkit::volume_scissor(light_position, bmin, bmax, lmin, lmax, sp);
//   if (s.visible) { glScissor(s.x, s.y, s.width, s.height); glDepthBoundsEXT(s.depth_min, s.depth_max); draw; }
//   // every status is checked in the docs; before the lighting pass: glDisable(GL_SCISSOR_TEST)
//
// Conventions:
// Lights: a light is its homogeneous position `light_position` = (x, y, z, w), as OpenGL's
// GL_POSITION and Everitt & Kilgard use it. w > 0: a point or spot light at xyz / w. w = 0: a
// directional light at infinity in direction xyz, the direction *toward* the light (its rays travel
// along -xyz). w < 0, (0, 0, 0, 0) and NaN/Inf are rejected with Status::InvalidLight.
//   * Units: positions, bounds and light_position in one space (world, or object space with the light
//     transformed into it); any unit. Matrices are GLM column-major, right-handed; ClipDepth plus
//     reversed_z say how view_proj maps depth; infinite far planes are accepted.
//   * Buffers: every capacity counts elements of its pointer's type (vec4 vertices, uint32 indices);
//     results say `count` (elements written: a valid prefix of whole vertices / quads / triangles)
//     and `needed` (elements the whole output needs; count == needed when Ok). Nothing allocates.
//   * Vertex layout. Volume index buffers index a 2n-vertex buffer: i in [0, n) is (p_i, 1), i + n is
//     (p_i, 0); the vertex shader maps (p, 0) to (p L.w - L.xyz, 0) (glsl/shadow_volume.glsl). For a
//     directional light all w = 0 vertices become the same point (-L.xyz, 0); side quads then
//     rasterize as triangles and the dark cap has zero area (pass dark_cap = false to skip it). A
//     vertex AT a point light would extrude to (0, 0, 0, 0): with silhouette.hpp's exact facing, its
//     faces are unlit (d == 0) and it is never extruded by side quads or LitOnly caps. Use w = 1 (or
//     a power of two) for point lights: the shader's float product p w of another w can round onto
//     L.xyz for a vertex within an ulp of the light.
//   * Winding. Silhouette edges (a, b) must be oriented as in their light-facing triangle
//     (counter-clockwise front faces). Side quad = triangles (b, a, a+n), (b, a+n, b+n); light cap =
//     lit triangles as given; dark cap per VolumeCapMode. The volume's faces then point outwards;
//     with GL_CCW front faces, the two-sided z-fail recipe is: back faces GL_INCR_WRAP on depth fail,
//     front faces GL_DECR_WRAP on depth fail.
//   * Open meshes (VolumeCapMode::LitOnly, the documented method). The volume is the sum of one closed
//     prism per lit triangle: the triangle, its three side quads, and the triangle extruded to
//     infinity with reversed winding. Side quads of edges shared by lit triangles cancel, which leaves
//     exactly the silhouette.hpp edge rule (k = sum over lit faces of +-1, emitted |k| times). Hence
//     the volume is closed and consistently oriented for any triangle soup, and the z-fail count at a
//     point X equals the number of lit triangles crossed by the segment from X to the light (the ray
//     for a directional light). Limits: triangles act as one-sided occluders (an unlit triangle casts
//     no shadow): on an OPEN mesh a segment that enters through a hole and leaves through back faces
//     crosses no lit face and its point stays lit although the mesh blocks it (a bowl, a box without
//     a lid: 5.9% of a ray-traced umbra lit). VolumeCapMode::TwoSided with silhouette.hpp's
//     silhouette_extract_two_sided fixes that: every triangle adds its prism, an unlit one reversed,
//     so the count is the number of triangles the segment crosses (any facing) and a point is inside
//     iff the mesh blocks its segment to the light - what a ray tracer tests. It costs the unlit
//     faces' caps and a second quad per silhouette edge, so use it exactly when the mesh is open
//     (silhouette.hpp: !adj.closed()); on closed meshes LitOnly gives the same shadow. With TwoSided,
//     keep vertices off a point light (a face through the light's own vertex would be extruded to
//     (0, 0, 0, 0)); a light inside a closed mesh with outward faces sees no lit face and casts nothing
//     (VolumeCapMode::EverittKilgard shadows everything outside instead); the stencil must hold the
//     largest count (8 bits, wrapping). VolumeCapMode::EverittKilgard (dark cap = unlit triangles
//     extruded) is identical for closed, consistently wound meshes with the light strictly outside
//     and is only closed for such meshes (with a light on the surface its dark cap extrudes the
//     light's own vertex to (0, 0, 0, 0): use LitOnly).
//   * Z-pass vs z-fail. Z-pass counts from the near plane, so it is exact iff no point of the
//     near-plane rectangle is in the occluder's shadow, i.e. iff the occluder's bounds miss the convex
//     hull of the light and the near rectangle (the near-plane occlusion pyramid; a prism toward the
//     light for w = 0). The box test is an exact separating-axis test, the sphere test an exact
//     distance test (both in double); touching counts as intersecting; `margin` inflates the bounds
//     for rounding.
//   * Scissor and depth bounds. The occluder's shadow lies in S = {L + t (p - L) : p in box, t >= 1}
//     (for w = 0: p - t L.xyz). S is contained in the intersection of the half-spaces behind the box
//     faces that face the light and the planes through the light (direction) and the box's silhouette
//     edges. That polytope is clipped to the light's bounding box and to the camera near plane, its
//     vertices are enumerated (plane triples) and projected: the scissor rectangle is their pixel
//     bounding box (floor / ceil, clamped to the viewport) and [depth_min, depth_max] their
//     window-depth range (Lengyel: viewport depth of (P row 3 . X) / (P row 4 . X)), rounded outwards
//     in float. visible = false (with Ok) when the polytope is empty: the shadow cannot reach the
//     light's bounds in front of the camera. Scissor and depth bounds are per-occluder state: disable
//     GL_SCISSOR_TEST (and GL_DEPTH_BOUNDS_TEST_EXT) before the lighting pass.
//   * Statuses: null pointers with non-zero counts, counts out of range, a missing (zero) viewport or
//     matrix in ScissorParams, a singular view_proj or view, fovy outside (0, pi), aspect or near_z
//     <= 0, min > max bounds, negative radius or margin, an out-of-range enum: InvalidArgument.
//     NaN/Inf inputs: NonFinite. A bad light_position: InvalidLight. Indices >= vertex_count:
//     IndexOutOfRange. Short buffers: BufferTooSmall with `needed`. Finite inputs whose result is not
//     finite: Overflow. Ok means every output is finite. A non-Ok result's `detail` names the
//     offending input and the rule ("indices: >= vertex_count"), a static string; nullptr when Ok.
//
// Based on:
//   C. Everitt, M. J. Kilgard, "Practical and Robust Stenciled Shadow Volumes for Hardware-Accelerated
//   Rendering", NVIDIA 2002: side quad (B, A, A_inf, B_inf) with X_inf = (X.xyz L.w - L.xyz X.w, 0)
//   (section 3.2.2), caps (3.2.2), z-fail (2.2.3), mixing z-pass and z-fail per occluder (3.4).
//   E. Lengyel, "Advanced Stencil Shadow and Penumbral Wedge Rendering", GDC 2005: per-geometry scissor
//   (bounding pyramid clipped to the light's box, projected) and depth bounds.
//   P. Bergeron, "A General Version of Crow's Shadow Volumes", IEEE CG&A 1986 (open models).
//
// MIT License. Copyright (c) shadowkit contributors.
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <limits>

// SSE2 (the baseline of x86-64) for volume_build_caps; portable code elsewhere. SHADOWKIT_NO_SIMD
// forces the portable code. Both write the same indices.
#if !defined(SHADOWKIT_NO_SIMD) && (defined(__SSE2__) || defined(_M_X64) || (defined(_M_IX86_FP) && _M_IX86_FP >= 2))
#include <emmintrin.h>
#define SHADOWKIT_SV_SSE2 1
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

/// Elements written to / needed by a volume buffer (vertices: vec4; indices: uint32).
struct VolumeBuffer {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    std::size_t count = 0;  ///< elements written: a valid prefix (whole quads / triangles)
    std::size_t needed = 0; ///< elements the whole output needs (count == needed when Ok)
};

/// A vertex extruded to infinity (volume_extrude_to_infinity).
struct VolumeExtrusion {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    glm::vec4 position = glm::vec4(0.0f); ///< (x, y, z, 0), never (0, 0, 0, 0) when Ok
};

/// Which triangles form the dark cap (the far end of the volume) for z-fail.
enum class VolumeCapMode {
    LitOnly,        ///< dark cap = lit triangles extruded, reversed: closed for any mesh; lit faces occlude
    EverittKilgard, ///< dark cap = unlit triangles extruded: closed meshes with the light outside only (Everitt-Kilgard 3.2.2)
    TwoSided        ///< every face occludes (open meshes): unlit triangles reversed join both caps (header comment)
};

/// Stencil counting method of one occluder.
enum class VolumeStencilMethod { ZPass, ZFail };

/// The z-pass / z-fail decision for one occluder.
struct VolumeMethod {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    VolumeStencilMethod method = VolumeStencilMethod::ZFail; ///< ZFail whenever unsure (and when not Ok)
};

/// World-space corners of the camera's near-plane rectangle (any winding, convex).
struct VolumeNearRect {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    glm::vec3 corners[4] = {glm::vec3(0.0f), glm::vec3(0.0f), glm::vec3(0.0f), glm::vec3(0.0f)};
};

namespace detail {

inline int sv_ctz64(std::uint64_t x) {  // x != 0
#if defined(__GNUC__) || defined(__clang__)
    return __builtin_ctzll(x);
#else
    int n = 0;
    while ((x & 1u) == 0u) { x >>= 1; ++n; }
    return n;
#endif
}

inline bool sv_finite3(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
inline bool sv_valid_light(const glm::vec4& L) {
    if (!(std::isfinite(L.x) && std::isfinite(L.y) && std::isfinite(L.z) && std::isfinite(L.w))) return false;
    if (L.w < 0.0f) return false;
    return !(L.w == 0.0f && L.x == 0.0f && L.y == 0.0f && L.z == 0.0f);
}
inline bool sv_finite_mat(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}
// determinant of a 4x4 matrix in double (Laplace expansion by 2x2 minors)
inline double sv_det4(const glm::mat4& f) {
    double m[4][4];
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) m[r][c] = static_cast<double>(f[c][r]);
    const double s0 = m[0][0] * m[1][1] - m[1][0] * m[0][1], s1 = m[0][0] * m[1][2] - m[1][0] * m[0][2];
    const double s2 = m[0][0] * m[1][3] - m[1][0] * m[0][3], s3 = m[0][1] * m[1][2] - m[1][1] * m[0][2];
    const double s4 = m[0][1] * m[1][3] - m[1][1] * m[0][3], s5 = m[0][2] * m[1][3] - m[1][2] * m[0][3];
    const double c5 = m[2][2] * m[3][3] - m[3][2] * m[2][3], c4 = m[2][1] * m[3][3] - m[3][1] * m[2][3];
    const double c3 = m[2][1] * m[3][2] - m[3][1] * m[2][2], c2 = m[2][0] * m[3][3] - m[3][0] * m[2][3];
    const double c1 = m[2][0] * m[3][2] - m[3][0] * m[2][2], c0 = m[2][0] * m[3][1] - m[3][0] * m[2][1];
    return s0 * c5 - s1 * c4 + s2 * c3 + s3 * c2 - s4 * c1 + s5 * c0;
}

struct SvVec {
    double x, y, z;
};
inline SvVec sv_of(const glm::vec3& v) { return SvVec{v.x, v.y, v.z}; }
inline SvVec operator+(SvVec a, SvVec b) { return SvVec{a.x + b.x, a.y + b.y, a.z + b.z}; }
inline SvVec operator-(SvVec a, SvVec b) { return SvVec{a.x - b.x, a.y - b.y, a.z - b.z}; }
inline SvVec operator*(SvVec a, double s) { return SvVec{a.x * s, a.y * s, a.z * s}; }
inline double sv_dot(SvVec a, SvVec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline SvVec sv_cross(SvVec a, SvVec b) { return SvVec{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline double sv_len2(SvVec a) { return sv_dot(a, a); }
inline double sv_get(const SvVec& v, int i) { return i == 0 ? v.x : (i == 1 ? v.y : v.z); }
inline void sv_set(SvVec& v, int i, double x) {
    if (i == 0) v.x = x;
    else if (i == 1) v.y = x;
    else v.z = x;
}

// Convex polytope for the near-plane occlusion test: up to 8 vertices, face triangles, edge dirs.
struct SvPoly {
    SvVec v[8];
    int nv = 0;
    int tri[12][3];
    int nt = 0;
    SvVec edge[8];
    int ne = 0;
    SvVec normal[6];
    int nn = 0;
};

inline void sv_add_tri(SvPoly& p, int a, int b, int c) {
    p.tri[p.nt][0] = a;
    p.tri[p.nt][1] = b;
    p.tri[p.nt][2] = c;
    ++p.nt;
}

// Builds hull(light, rect) for w > 0, or rect swept toward the light by `reach` for w = 0.
inline SvPoly sv_near_poly(const VolumeNearRect& r, const glm::vec4& L, double reach) {
    SvPoly p;
    for (int i = 0; i < 4; ++i) p.v[i] = sv_of(r.corners[i]);
    p.nv = 4;
    for (int i = 0; i < 4; ++i) p.edge[p.ne++] = p.v[(i + 1) % 4] - p.v[i];
    p.normal[p.nn++] = sv_cross(p.edge[0], p.edge[1]);
    sv_add_tri(p, 0, 1, 2);
    sv_add_tri(p, 0, 2, 3);
    if (L.w > 0.0f) {
        const SvVec l{static_cast<double>(L.x) / L.w, static_cast<double>(L.y) / L.w, static_cast<double>(L.z) / L.w};
        p.v[p.nv++] = l;
        for (int i = 0; i < 4; ++i) {
            p.normal[p.nn++] = sv_cross(p.v[(i + 1) % 4] - p.v[i], l - p.v[i]);
            p.edge[p.ne++] = l - p.v[i];
            sv_add_tri(p, i, (i + 1) % 4, 4);
        }
    } else {
        SvVec d{L.x, L.y, L.z};
        d = d * (1.0 / std::sqrt(sv_len2(d)));
        for (int i = 0; i < 4; ++i) p.v[p.nv++] = p.v[i] + d * reach;
        p.edge[p.ne++] = d;
        for (int i = 0; i < 4; ++i) {
            const int j = (i + 1) % 4;
            p.normal[p.nn++] = sv_cross(p.v[j] - p.v[i], d);
            sv_add_tri(p, i, j, j + 4);
            sv_add_tri(p, i, j + 4, i + 4);
        }
        sv_add_tri(p, 4, 5, 6);
        sv_add_tri(p, 4, 6, 7);
    }
    return p;
}

// Closest point on triangle to point (Ericson, Real-Time Collision Detection 5.1.5), squared distance.
inline double sv_tri_dist2(SvVec p, SvVec a, SvVec b, SvVec c) {
    const SvVec ab = b - a, ac = c - a, ap = p - a;
    const double d1 = sv_dot(ab, ap), d2 = sv_dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return sv_len2(p - a);
    const SvVec bp = p - b;
    const double d3 = sv_dot(ab, bp), d4 = sv_dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return sv_len2(p - b);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) { const double v = d1 / (d1 - d3); return sv_len2(p - (a + ab * v)); }
    const SvVec cp = p - c;
    const double d5 = sv_dot(ab, cp), d6 = sv_dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return sv_len2(p - c);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) { const double w = d2 / (d2 - d6); return sv_len2(p - (a + ac * w)); }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return sv_len2(p - (b + (c - b) * w));
    }
    const double den = va + vb + vc;
    if (!(den != 0.0)) { // degenerate triangle: edges
        double m = sv_len2(p - a);
        const SvVec segs[3][2] = {{a, b}, {b, c}, {c, a}};
        for (const auto& s : segs) {
            const SvVec e = s[1] - s[0];
            const double l = sv_len2(e);
            double t = l > 0 ? sv_dot(p - s[0], e) / l : 0.0;
            t = t < 0 ? 0 : (t > 1 ? 1 : t);
            const double q = sv_len2(p - (s[0] + e * t));
            if (q < m) m = q;
        }
        return m;
    }
    const double v = vb / den, w = vc / den;
    return sv_len2(p - (a + ab * v + ac * w));
}

// common checks of the two stencil-method choices
// `why` receives where a non-Ok status came from (a static string).
inline Status sv_check_method_args(const VolumeNearRect& rect, const glm::vec4& light, const char*& why) {
    for (const glm::vec3& c : rect.corners)
        if (!sv_finite3(c)) return why = "near_rect: a corner NaN or Inf", Status::NonFinite;
    if (rect.status != Status::Ok) return why = "near_rect: status not Ok", Status::InvalidArgument;
    if (!sv_valid_light(light)) return why = "light_position: NaN/Inf, w < 0 or (0, 0, 0, 0)", Status::InvalidLight;
    return Status::Ok;
}

} // namespace detail

/// Homogeneous extrusion of p to infinity away from light_position (Everitt-Kilgard 3.2.2):
/// (p.xyz L.w - L.xyz p.w, 0); for p.w = 1 and a point light the direction p - L. The CPU twin of
/// sk_extrude_shadow_volume. NonFinite (p), InvalidLight, Overflow (a component beyond float), and
/// InvalidArgument when p is AT the light (the result would be (0, 0, 0, 0): no direction).
inline VolumeExtrusion volume_extrude_to_infinity(const glm::vec4& p, const glm::vec4& light_position) {
    VolumeExtrusion r;
    const glm::vec4& L = light_position;
    if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) && std::isfinite(p.w))) {
        r.status = Status::NonFinite;
        r.detail = "p: NaN or Inf";
        return r;
    }
    if (!detail::sv_valid_light(L)) { r.status = Status::InvalidLight; r.detail = "light_position: NaN/Inf, w < 0 or (0, 0, 0, 0)"; return r; }
    r.position = glm::vec4(p.x * L.w - L.x * p.w, p.y * L.w - L.y * p.w, p.z * L.w - L.z * p.w, 0.0f);
    if (!detail::sv_finite3(glm::vec3(r.position))) {
        r.status = Status::Overflow;
        r.detail = "p: extruded position beyond float";
        r.position = glm::vec4(0.0f);
        return r;
    }
    r.status = (r.position.x == 0.0f && r.position.y == 0.0f && r.position.z == 0.0f) ? Status::InvalidArgument : Status::Ok;
    r.detail = r.status == Status::Ok ? nullptr : "p: at the light position (no extrusion direction)";
    return r;
}

/// The volume vertex buffer: out[i] = (p_i, 1), out[n + i] = (p_i, 0), n = vertex_count <= 2^31 - 1.
/// `positions` holds vertex_count glm::vec3. `out` holds out_capacity glm::vec4 elements; it needs
/// 2 * vertex_count (`needed`); a short buffer gets its first out_capacity elements (BufferTooSmall).
inline VolumeBuffer volume_build_vertices(const glm::vec3* positions, std::size_t vertex_count, glm::vec4* out,
                                          std::size_t out_capacity) {
    VolumeBuffer r;
    if ((vertex_count > 0 && positions == nullptr) || (out_capacity > 0 && out == nullptr) || vertex_count > 0x7FFFFFFFull) {
        r.status = Status::InvalidArgument;
        r.detail = vertex_count > 0 && positions == nullptr ? "positions: null with vertex_count > 0"
                   : (out_capacity > 0 && out == nullptr ? "out: null with out_capacity > 0" : "vertex_count: > 2^31 - 1");
        return r;
    }
    for (std::size_t i = 0; i < vertex_count; ++i)
        if (!detail::sv_finite3(positions[i])) { r.status = Status::NonFinite; r.detail = "positions: NaN or Inf"; return r; }
    r.needed = 2 * vertex_count;
    for (std::size_t i = 0; i < vertex_count; ++i) {
        if (i < out_capacity) out[i] = glm::vec4(positions[i], 1.0f);
        if (vertex_count + i < out_capacity) out[vertex_count + i] = glm::vec4(positions[i], 0.0f);
    }
    r.count = r.needed < out_capacity ? r.needed : out_capacity;
    r.status = r.count < r.needed ? Status::BufferTooSmall : Status::Ok;
    r.detail = r.count < r.needed ? "out_capacity: below needed (see needed)" : nullptr;
    return r;
}

/// Side quads: for each silhouette edge (a, b) = (edge_indices[2e], edge_indices[2e + 1]) the triangles
/// (b, a, a + n) and (b, a + n, b + n), n = vertex_count <= 2^31 - 1. `edge_indices` holds
/// edge_index_count uint32 elements (even: 2 per edge, as silhouette_extract writes them). `out`
/// holds out_capacity uint32 elements; it needs 3 * edge_index_count (6 per edge, `needed`); a
/// short buffer gets the whole quads that fit (BufferTooSmall). The index check shares the pass with
/// the writes: with IndexOutOfRange out's contents are unspecified.
inline VolumeBuffer volume_build_side_quads(const std::uint32_t* edge_indices, std::size_t edge_index_count,
                                            std::size_t vertex_count, std::uint32_t* out, std::size_t out_capacity) {
    VolumeBuffer r;
    if ((edge_index_count > 0 && edge_indices == nullptr) || (out_capacity > 0 && out == nullptr) || edge_index_count % 2 != 0 ||
        vertex_count > 0x7FFFFFFFull || edge_index_count > (std::numeric_limits<std::size_t>::max() / 4)) {
        r.status = Status::InvalidArgument;
        r.detail = edge_index_count > 0 && edge_indices == nullptr ? "edge_indices: null with edge_index_count > 0"
                   : (out_capacity > 0 && out == nullptr ? "out: null with out_capacity > 0"
                   : (edge_index_count % 2 != 0 ? "edge_index_count: odd"
                   : (vertex_count > 0x7FFFFFFFull ? "vertex_count: > 2^31 - 1" : "edge_index_count: too large")));
        return r;
    }
    const std::uint32_t n = static_cast<std::uint32_t>(vertex_count);
    const std::size_t edges = edge_index_count / 2;
    const std::size_t full = out_capacity / 6 < edges ? out_capacity / 6 : edges;
    bool bad = false;  // the index check, fused with the writes (one pass over the edges)
    std::size_t e = 0;
#if defined(SHADOWKIT_SV_SSE2)
    if (n > 0) {
        const __m128i sign = _mm_set1_epi32(static_cast<int>(0x80000000u)), nv = _mm_set1_epi32(static_cast<int>(n));
        const __m128i lim = _mm_xor_si128(nv, sign);
        __m128i ok = _mm_set1_epi32(-1);
        for (; e < full; ++e) {
            const __m128i v = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(edge_indices + 2 * e));  // a b 0 0
            ok = _mm_and_si128(ok, _mm_cmplt_epi32(_mm_xor_si128(v, sign), lim));
            const __m128i t = _mm_unpacklo_epi64(v, _mm_add_epi32(v, nv));                              // a b a+n b+n
            _mm_storeu_si128(reinterpret_cast<__m128i*>(out + 6 * e), _mm_shuffle_epi32(t, _MM_SHUFFLE(1, 2, 0, 1)));  // b a a+n b
            _mm_storel_epi64(reinterpret_cast<__m128i*>(out + 6 * e + 4), _mm_unpackhi_epi64(t, t));               // a+n b+n
        }
        bad = _mm_movemask_epi8(ok) != 0xFFFF;
    }
#endif
    for (; e < full; ++e) {
        const std::uint32_t a = edge_indices[2 * e], b = edge_indices[2 * e + 1];
        bad |= (a >= n) | (b >= n);
        std::uint32_t* o = out + 6 * e;
        o[0] = b; o[1] = a; o[2] = a + n;
        o[3] = b; o[4] = a + n; o[5] = b + n;
    }
    for (std::size_t i = 2 * full; i < edge_index_count; ++i) bad |= edge_indices[i] >= n;
    if (bad) { r.status = Status::IndexOutOfRange; r.detail = "indices: >= vertex_count"; return r; }
    r.needed = 6 * edges;
    r.count = 6 * full;
    r.status = r.count < r.needed ? Status::BufferTooSmall : Status::Ok;
    r.detail = r.count < r.needed ? "out_capacity: below needed (see needed)" : nullptr;
    return r;
}

namespace detail {
// VolumeCapMode::TwoSided: every triangle, an unlit one reversed (a, c, b); light cap then (if
// dark_cap) the same triangle extruded and reversed. Arguments checked by volume_build_caps.
inline VolumeBuffer sv_build_caps_two_sided(const std::uint32_t* indices, const std::uint8_t* lit, std::size_t tris,
                                            std::size_t vertex_count, bool dark_cap, std::uint32_t* out, std::size_t out_capacity) {
    VolumeBuffer r;
    const std::uint32_t n = static_cast<std::uint32_t>(vertex_count);
    std::size_t k = 0;
    for (std::size_t t = 0; t < tris; ++t) {
        const std::uint32_t a = indices[3 * t], b0 = indices[3 * t + 1], c0 = indices[3 * t + 2];
        if (a >= n || b0 >= n || c0 >= n) { r.status = Status::IndexOutOfRange; r.detail = "indices: >= vertex_count"; return r; }
        const std::uint32_t b = lit[t] ? b0 : c0, c = lit[t] ? c0 : b0;
        const std::uint32_t tri[6] = {a, b, c, a + n, c + n, b + n};
        for (std::size_t j = 0; j < (dark_cap ? 6u : 3u); j += 3, k += 3)
            if (k + 3 <= out_capacity) { out[k] = tri[j]; out[k + 1] = tri[j + 1]; out[k + 2] = tri[j + 2]; }
    }
    r.needed = k;
    r.count = k <= out_capacity ? k : (out_capacity / 3) * 3;
    r.status = r.count < r.needed ? Status::BufferTooSmall : Status::Ok;
    r.detail = r.count < r.needed ? "out_capacity: below needed (see needed)" : nullptr;
    return r;
}
// Where volume_build_caps' InvalidArgument came from (the first failing argument, in its order).
inline const char* sv_caps_why(const std::uint32_t* indices, std::size_t index_count, const std::uint8_t* lit,
                               std::size_t lit_count, std::size_t vertex_count, const std::uint32_t* out, std::size_t out_capacity) {
    if (index_count > 0 && indices == nullptr) return "indices: null with index_count > 0";
    if (lit_count > 0 && lit == nullptr) return "lit: null with lit_count > 0";
    if (out_capacity > 0 && out == nullptr) return "out: null with out_capacity > 0";
    if (index_count % 3 != 0) return "index_count: not a multiple of 3";
    if (lit_count != index_count / 3) return "lit_count: not index_count / 3";
    if (vertex_count > 0x7FFFFFFFull) return "vertex_count: > 2^31 - 1";
    return index_count > (std::numeric_limits<std::size_t>::max() / 4) ? "index_count: too large" : "mode: unknown VolumeCapMode";
}
// volume_build_caps' last triangles [t, tris) (a buffer near its end): whole triangles while they fit,
// then only counted in k. Returns true if an index is out of range.
inline bool sv_caps_rest(const std::uint32_t* indices, const std::uint8_t* lit, std::size_t tris, std::uint32_t n, bool lit_only,
                         bool dark_cap, std::uint32_t* out, std::size_t out_capacity, std::size_t t, std::size_t& k) {
    bool bad = false;
    auto put = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        if (k + 3 <= out_capacity) { out[k] = a; out[k + 1] = b; out[k + 2] = c; }
        k += 3;
    };
    for (; t < tris; ++t) {
        const std::uint32_t a = indices[3 * t], b = indices[3 * t + 1], c = indices[3 * t + 2];
        bad |= (a >= n) | (b >= n) | (c >= n);
        if (lit[t]) {
            put(a, b, c);
            if (dark_cap && lit_only) put(a + n, c + n, b + n);
        } else if (dark_cap && !lit_only) {
            put(a + n, b + n, c + n);
        }
    }
    return bad;
}
}  // namespace detail

/// Light cap (lit triangles, as given) and, if dark_cap, the dark cap (VolumeCapMode) for z-fail.
/// TwoSided: every triangle (an unlit one reversed) in the light cap and, if dark_cap, extruded in
/// the dark cap: 3 or 6 elements per triangle; pair it with silhouette_extract_two_sided.
/// `indices` holds index_count uint32 elements (3 per triangle); `lit` holds lit_count uint8 flags,
/// one per triangle (lit_count == index_count / 3; non-zero = light-facing, e.g. silhouette.hpp's
/// facing of the adjacency's faces). Any sub-range of triangles works (chunks). `out` holds
/// out_capacity uint32 elements; it needs 3 per lit triangle plus 3 per dark-cap triangle (at most
/// 2 * index_count, `needed`); a short buffer gets the whole triangles that fit (BufferTooSmall).
/// An out-of-range `mode` is InvalidArgument. One branch-free pass (SSE2 where available): up to 7
/// elements past `count` (never past out_capacity) may be overwritten, and with IndexOutOfRange
/// (checked in the same pass) out's contents are unspecified.
inline VolumeBuffer volume_build_caps(const std::uint32_t* indices, std::size_t index_count, const std::uint8_t* lit,
                                      std::size_t lit_count, std::size_t vertex_count, VolumeCapMode mode, bool dark_cap,
                                      std::uint32_t* out, std::size_t out_capacity) {
    VolumeBuffer r;
    if ((index_count > 0 && indices == nullptr) || (lit_count > 0 && lit == nullptr) || (out_capacity > 0 && out == nullptr) ||
        index_count % 3 != 0 || lit_count != index_count / 3 || vertex_count > 0x7FFFFFFFull ||
        index_count > (std::numeric_limits<std::size_t>::max() / 4) ||
        (mode != VolumeCapMode::LitOnly && mode != VolumeCapMode::EverittKilgard && mode != VolumeCapMode::TwoSided)) {
        r.status = Status::InvalidArgument;
        r.detail = detail::sv_caps_why(indices, index_count, lit, lit_count, vertex_count, out, out_capacity);
        return r;
    }
    if (mode == VolumeCapMode::TwoSided) return detail::sv_build_caps_two_sided(indices, lit, lit_count, vertex_count, dark_cap, out, out_capacity);
    const std::uint32_t n = static_cast<std::uint32_t>(vertex_count);
    const bool lit_only = mode == VolumeCapMode::LitOnly;
    std::size_t k = 0, t = 0;
    bool bad = false;  // the index check, fused with the writes (one pass over the triangles)
    // Branch-free while there is room: every triangle's indices are written, k advances by what the
    // triangle contributes (the next triangle overwrites the rest).
#if defined(SHADOWKIT_SV_SSE2)
    if (n > 0) {
        const __m128i sign = _mm_set1_epi32(static_cast<int>(0x80000000u)), nv = _mm_set1_epi32(static_cast<int>(n));
        const __m128i lim = _mm_xor_si128(nv, sign);
        __m128i ok = _mm_set1_epi32(-1);
        const std::size_t lit_step = lit_only && dark_cap ? 6 : 3, dark_step = !lit_only && dark_cap ? 3 : 0;
        const std::size_t lit_extra = lit_step - dark_step;
        if (lit_only || !dark_cap) {
            // Only lit triangles write: 64 triangles at a time, their lit flags become bits (four 16-byte
            // compares), their 192 indices are checked (48 16-byte loads), then only the lit ones are
            // visited (lowest bit first). One loop exit per 64 triangles is the only data-dependent
            // branch; a lit pattern of any shape (coherent on a smooth mesh, random on a noisy one)
            // costs the same. t + 65 <= count: triangle t + 63's 16-byte load reads one index further.
            const __m128i zero = _mm_setzero_si128();
            for (; t + 65 <= lit_count && k + 6 * 64 + 8 <= out_capacity; t += 64) {
                std::uint64_t bits = 0;
                for (unsigned q = 0; q < 4; ++q) {
                    const __m128i f = _mm_loadu_si128(reinterpret_cast<const __m128i*>(lit + t + 16 * q));
                    bits |= static_cast<std::uint64_t>(static_cast<std::uint32_t>(_mm_movemask_epi8(_mm_cmpeq_epi8(f, zero))) ^ 0xFFFFu)
                            << (16 * q);
                }
                const std::uint32_t* ip = indices + 3 * t;
                for (unsigned q = 0; q < 48; ++q) {
                    const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(ip + 4 * q));
                    ok = _mm_and_si128(ok, _mm_cmplt_epi32(_mm_xor_si128(v, sign), lim));
                }
                for (; bits != 0; bits &= bits - 1) {
                    const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(ip + 3 * static_cast<std::size_t>(detail::sv_ctz64(bits))));
                    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + k), v);  // a b c (x)
                    if (lit_only && dark_cap)
                        _mm_storeu_si128(reinterpret_cast<__m128i*>(out + k + 3),
                                         _mm_shuffle_epi32(_mm_add_epi32(v, nv), _MM_SHUFFLE(3, 1, 2, 0)));  // a+n c+n b+n (x)
                    k += lit_step;
                }
            }
        }
        // 16-byte loads: triangle t's three indices and the next one's first (in range: t + 2 <= count).
        // The lit flag enters as a mask (l = 0 or all ones), never as a branch or a select a compiler may
        // turn into one: a random lit pattern (a noisy mesh) would mispredict on every other triangle.
        for (; t + 2 <= lit_count && k + 7 <= out_capacity; ++t) {
            const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(indices + 3 * t));
            ok = _mm_and_si128(ok, _mm_cmplt_epi32(_mm_xor_si128(v, sign), lim));
            const __m128i vn = _mm_add_epi32(v, nv);
            const std::size_t l = std::size_t(0) - static_cast<std::size_t>(lit[t] != 0);
            if (lit_only) {
                _mm_storeu_si128(reinterpret_cast<__m128i*>(out + k), v);  // a b c (x)
                _mm_storeu_si128(reinterpret_cast<__m128i*>(out + k + 3), _mm_shuffle_epi32(vn, _MM_SHUFFLE(3, 1, 2, 0))); // a+n c+n b+n (x)
            } else {  // lit: v, else v + n
                const __m128i lm = _mm_set1_epi32(static_cast<int>(static_cast<std::uint32_t>(l)));
                _mm_storeu_si128(reinterpret_cast<__m128i*>(out + k), _mm_add_epi32(v, _mm_andnot_si128(lm, nv)));
            }
            k += dark_step + (lit_extra & l);
        }
        bad = _mm_movemask_epi8(ok) != 0xFFFF;
    }
#endif
    {
        const std::size_t lit_step = lit_only && dark_cap ? 6 : 3, dark_step = !lit_only && dark_cap ? 3 : 0;
        for (; t < lit_count && k + 6 <= out_capacity; ++t) {  // the same, scalar (masks, no branch)
            const std::uint32_t a = indices[3 * t], b = indices[3 * t + 1], c = indices[3 * t + 2];
            bad |= (a >= n) | (b >= n) | (c >= n);
            const std::size_t l = std::size_t(0) - static_cast<std::size_t>(lit[t] != 0);
            std::uint32_t* o = out + k;
            if (lit_only) {
                o[0] = a; o[1] = b; o[2] = c;
                o[3] = a + n; o[4] = c + n; o[5] = b + n;
            } else {  // lit: a b c, else + n
                const std::uint32_t add = n & ~static_cast<std::uint32_t>(l);
                o[0] = a + add; o[1] = b + add; o[2] = c + add;
            }
            k += dark_step + ((lit_step - dark_step) & l);
        }
    }
    bad |= detail::sv_caps_rest(indices, lit, lit_count, n, lit_only, dark_cap, out, out_capacity, t, k);
    if (bad) { r.status = Status::IndexOutOfRange; r.detail = "indices: >= vertex_count"; return r; }
    r.needed = k;
    r.count = k <= out_capacity ? k : (out_capacity / 3) * 3;
    r.status = r.count < r.needed ? Status::BufferTooSmall : Status::Ok;
    r.detail = r.count < r.needed ? "out_capacity: below needed (see needed)" : nullptr;
    return r;
}

/// Total: uint32 elements an index buffer needs for the side quads of any silhouette of
/// `silhouette_index_capacity` elements (silhouette_indices_capacity) plus the caps of `index_count`
/// mesh indices: 3 * silhouette_index_capacity + 2 * index_count (saturates at SIZE_MAX).
inline std::size_t volume_indices_capacity(std::size_t silhouette_index_capacity, std::size_t index_count) {
    const std::size_t m = std::numeric_limits<std::size_t>::max();
    if (silhouette_index_capacity > m / 6 || index_count > m / 6) return m;
    return 3 * silhouette_index_capacity + 2 * index_count;
}

/// Near-plane rectangle from a view matrix (world -> eye, right-handed, looking down -z; invertible)
/// and a symmetric perspective: fovy (full vertical angle, radians) in (0, pi), aspect > 0, near_z > 0.
/// Computed in double. Else InvalidArgument (NaN/Inf: NonFinite); Overflow if a corner is not finite.
inline VolumeNearRect volume_near_plane_rect(const glm::mat4& view, float fovy, float aspect, float near_z) {
    VolumeNearRect r;
    if (!detail::sv_finite_mat(view) || !std::isfinite(fovy) || !std::isfinite(aspect) || !std::isfinite(near_z)) {
        r.status = Status::NonFinite;
        r.detail = !detail::sv_finite_mat(view) ? "view: NaN or Inf"
                   : (!std::isfinite(fovy) ? "fovy: NaN or Inf" : (!std::isfinite(aspect) ? "aspect: NaN or Inf" : "near_z: NaN or Inf"));
        return r;
    }
    if (!(fovy > 0.0f && static_cast<double>(fovy) < 3.141592653589793) || !(aspect > 0.0f) || !(near_z > 0.0f) ||
        detail::sv_det4(view) == 0.0) {
        r.status = Status::InvalidArgument;
        r.detail = !(fovy > 0.0f && static_cast<double>(fovy) < 3.141592653589793) ? "fovy: outside (0, pi)"
                   : (!(aspect > 0.0f) ? "aspect: not > 0" : (!(near_z > 0.0f) ? "near_z: not > 0" : "view: singular"));
        return r;
    }
    const glm::dmat4 inv = glm::inverse(glm::dmat4(view));
    const double t = static_cast<double>(near_z) * std::tan(0.5 * static_cast<double>(fovy));
    const double s = t * static_cast<double>(aspect);
    const double xs[4] = {-s, s, s, -s}, ys[4] = {-t, -t, t, t};
    for (int i = 0; i < 4; ++i) {
        const glm::dvec4 w = inv * glm::dvec4(xs[i], ys[i], -static_cast<double>(near_z), 1.0);
        r.corners[i] = glm::vec3(static_cast<float>(w.x / w.w), static_cast<float>(w.y / w.w), static_cast<float>(w.z / w.w));
        if (!detail::sv_finite3(r.corners[i])) { r.status = Status::Overflow; r.detail = "corners: beyond float range"; return r; }
    }
    r.status = Status::Ok;
    return r;
}

/// Near-plane rectangle from the inverse of projection * view (any perspective projection, infinite
/// far included): the clip-space near face (z = -1, or 0, or 1 when reversed_z) un-projected.
/// NonFinite for NaN/Inf; InvalidArgument for an out-of-range clip_depth or a corner with w <= 0.
inline VolumeNearRect volume_near_plane_rect_from_inverse(const glm::mat4& inverse_view_proj, ClipDepth clip_depth,
                                                          bool reversed_z) {
    VolumeNearRect r;
    if (!detail::sv_finite_mat(inverse_view_proj)) { r.status = Status::NonFinite; r.detail = "inverse_view_proj: NaN or Inf"; return r; }
    if (clip_depth != ClipDepth::NegativeOneToOne && clip_depth != ClipDepth::ZeroToOne) {
        r.status = Status::InvalidArgument;
        r.detail = "clip_depth: unknown ClipDepth";
        return r;
    }
    const glm::dmat4 inv(inverse_view_proj);
    const double zn = reversed_z ? 1.0 : (clip_depth == ClipDepth::NegativeOneToOne ? -1.0 : 0.0);
    const double xs[4] = {-1, 1, 1, -1}, ys[4] = {-1, -1, 1, 1};
    for (int i = 0; i < 4; ++i) {
        const glm::dvec4 w = inv * glm::dvec4(xs[i], ys[i], zn, 1.0);
        if (!(w.w > 0.0)) { r.status = Status::InvalidArgument; r.detail = "inverse_view_proj: a near corner at or behind the eye (w <= 0)"; return r; }
        r.corners[i] = glm::vec3(static_cast<float>(w.x / w.w), static_cast<float>(w.y / w.w), static_cast<float>(w.z / w.w));
        if (!detail::sv_finite3(r.corners[i])) { r.status = Status::Overflow; r.detail = "corners: beyond float range"; return r; }
    }
    r.status = Status::Ok;
    return r;
}

/// Z-pass is safe iff the box [box_min - margin, box_max + margin] misses hull(light, near rectangle)
/// (exact separating-axis test in double). Otherwise (or on touching) ZFail. near_rect must be Ok
/// (from volume_near_plane_rect*), else InvalidArgument; box_min <= box_max, margin >= 0.
inline VolumeMethod volume_choose_stencil_method_box(const VolumeNearRect& near_rect, const glm::vec4& light_position,
                                                     const glm::vec3& box_min, const glm::vec3& box_max, float margin = 0.0f) {
    VolumeMethod m;
    m.status = detail::sv_check_method_args(near_rect, light_position, m.detail);
    if (m.status != Status::Ok) return m;
    if (!detail::sv_finite3(box_min) || !detail::sv_finite3(box_max) || !std::isfinite(margin)) {
        m.status = Status::NonFinite;
        m.detail = !detail::sv_finite3(box_min) || !detail::sv_finite3(box_max) ? "box_min, box_max: NaN or Inf" : "margin: NaN or Inf";
        return m;
    }
    if (!(box_min.x <= box_max.x && box_min.y <= box_max.y && box_min.z <= box_max.z) || margin < 0.0f) {
        m.status = Status::InvalidArgument;
        m.detail = margin < 0.0f ? "margin: < 0" : "box_min: > box_max";
        return m;
    }
    using namespace detail;
    const SvVec lo = sv_of(box_min) - SvVec{margin, margin, margin}, hi = sv_of(box_max) + SvVec{margin, margin, margin};
    // Reach for w = 0: beyond it no point of the swept rectangle can be within the box.
    double reach = 0.0;
    {
        const SvVec c = (lo + hi) * 0.5;
        double far2 = 0.0;
        for (int i = 0; i < 4; ++i) {  // not std::fmax: aarch64 GCC 12.2 -O2 crashes vectorizing that reduction
            const double d2 = sv_len2(sv_of(near_rect.corners[i]) - c);
            far2 = d2 > far2 ? d2 : far2;
        }
        reach = 2.0 * (std::sqrt(far2) + std::sqrt(sv_len2(hi - lo))) + 1.0;
    }
    const SvPoly p = sv_near_poly(near_rect, light_position, reach);
    SvVec axes[6 + 3 + 24];
    int na = 0;
    for (int i = 0; i < p.nn; ++i) axes[na++] = p.normal[i];
    const SvVec box_axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (const SvVec& a : box_axes) axes[na++] = a;
    for (int i = 0; i < p.ne; ++i)
        for (const SvVec& a : box_axes) axes[na++] = sv_cross(p.edge[i], a);
    const SvVec bc = (lo + hi) * 0.5, bh = (hi - lo) * 0.5;
    m.status = Status::Ok;
    for (int k = 0; k < na; ++k) {
        const SvVec a = axes[k];
        const double l2 = sv_len2(a);
        if (!(l2 > 0.0) || !std::isfinite(l2)) continue;
        double pmin = std::numeric_limits<double>::infinity(), pmax = -pmin;
        for (int i = 0; i < p.nv; ++i) {
            const double d = sv_dot(a, p.v[i]);
            pmin = std::fmin(pmin, d);
            pmax = std::fmax(pmax, d);
        }
        const double c = sv_dot(a, bc);
        const double r = std::fabs(a.x) * bh.x + std::fabs(a.y) * bh.y + std::fabs(a.z) * bh.z;
        if (c + r < pmin || c - r > pmax) { m.method = VolumeStencilMethod::ZPass; return m; }
    }
    m.method = VolumeStencilMethod::ZFail;
    return m;
}

/// Sphere version: ZPass iff the distance from `center` to hull(light, near rectangle) exceeds
/// radius + margin (exact distance to the polytope's boundary triangles, inside test by planes).
/// near_rect must be Ok, radius >= 0, margin >= 0.
inline VolumeMethod volume_choose_stencil_method_sphere(const VolumeNearRect& near_rect, const glm::vec4& light_position,
                                                        const glm::vec3& center, float radius, float margin = 0.0f) {
    VolumeMethod m;
    m.status = detail::sv_check_method_args(near_rect, light_position, m.detail);
    if (m.status != Status::Ok) return m;
    if (!detail::sv_finite3(center) || !std::isfinite(radius) || !std::isfinite(margin)) {
        m.status = Status::NonFinite;
        m.detail = !detail::sv_finite3(center) ? "center: NaN or Inf" : (!std::isfinite(radius) ? "radius: NaN or Inf" : "margin: NaN or Inf");
        return m;
    }
    if (radius < 0.0f || margin < 0.0f) { m.status = Status::InvalidArgument; m.detail = radius < 0.0f ? "radius: < 0" : "margin: < 0"; return m; }
    using namespace detail;
    const SvVec c = sv_of(center);
    const double rr = static_cast<double>(radius) + static_cast<double>(margin);
    double far2 = 0.0;
    for (int i = 0; i < 4; ++i) {  // not std::fmax: aarch64 GCC 12.2 -O2 crashes vectorizing that reduction
        const double d2 = sv_len2(sv_of(near_rect.corners[i]) - c);
        far2 = d2 > far2 ? d2 : far2;
    }
    const SvPoly p = sv_near_poly(near_rect, light_position, 2.0 * (std::sqrt(far2) + rr) + 1.0);
    // Inside test: only for a solid polytope; planes oriented outwards via the centroid.
    SvVec cen{0, 0, 0};
    for (int i = 0; i < p.nv; ++i) cen = cen + p.v[i];
    cen = cen * (1.0 / p.nv);
    bool inside = true;
    int solid_planes = 0;
    for (int t = 0; t < p.nt && inside; ++t) {
        const SvVec a = p.v[p.tri[t][0]];
        SvVec nrm = sv_cross(p.v[p.tri[t][1]] - a, p.v[p.tri[t][2]] - a);
        const double l = std::sqrt(sv_len2(nrm));
        if (!(l > 0.0)) continue;
        nrm = nrm * (1.0 / l);
        const double sc = sv_dot(nrm, cen - a);
        if (std::fabs(sc) <= 1e-12 * std::sqrt(far2 + 1.0)) continue; // flat polytope face
        ++solid_planes;
        if (sc > 0) nrm = nrm * -1.0;
        if (sv_dot(nrm, c - a) > 0.0) inside = false;
    }
    m.status = Status::Ok;
    if (inside && solid_planes >= 4) { m.method = VolumeStencilMethod::ZFail; return m; }
    double best = std::numeric_limits<double>::infinity();
    for (int t = 0; t < p.nt; ++t)
        best = std::fmin(best, sv_tri_dist2(c, p.v[p.tri[t][0]], p.v[p.tri[t][1]], p.v[p.tri[t][2]]));
    m.method = best <= rr * rr ? VolumeStencilMethod::ZFail : VolumeStencilMethod::ZPass;
    return m;
}

namespace detail {

// Step 1 of volume_scissor: the arguments. Ok or the status to return.
inline Status sv_scissor_check(const glm::vec4& light, const glm::vec3& box_min, const glm::vec3& box_max,
                               const glm::vec3& light_min, const glm::vec3& light_max, const ScissorParams& params,
                               const char*& why) {
    if (!sv_valid_light(light)) return why = "light_position: NaN/Inf, w < 0 or (0, 0, 0, 0)", Status::InvalidLight;
    if (!sv_finite3(box_min) || !sv_finite3(box_max) || !sv_finite3(light_min) || !sv_finite3(light_max) ||
        !sv_finite_mat(params.view_proj)) {
        why = !sv_finite3(box_min) || !sv_finite3(box_max) ? "box_min, box_max: NaN or Inf"
              : (!sv_finite3(light_min) || !sv_finite3(light_max) ? "light_min, light_max: NaN or Inf" : "view_proj: NaN or Inf");
        return Status::NonFinite;
    }
    const int* vp = params.viewport;
    if (!(box_min.x <= box_max.x && box_min.y <= box_max.y && box_min.z <= box_max.z) ||
        !(light_min.x <= light_max.x && light_min.y <= light_max.y && light_min.z <= light_max.z) || vp[2] <= 0 ||
        vp[3] <= 0 || vp[0] > std::numeric_limits<int>::max() - vp[2] || vp[1] > std::numeric_limits<int>::max() - vp[3] ||
        (params.clip_depth != ClipDepth::NegativeOneToOne && params.clip_depth != ClipDepth::ZeroToOne) ||
        sv_det4(params.view_proj) == 0.0) {
        why = !(box_min.x <= box_max.x && box_min.y <= box_max.y && box_min.z <= box_max.z) ? "box_min: > box_max"
              : (!(light_min.x <= light_max.x && light_min.y <= light_max.y && light_min.z <= light_max.z) ? "light_min: > light_max"
              : (vp[2] <= 0 || vp[3] <= 0 || vp[0] > std::numeric_limits<int>::max() - vp[2] ||
                         vp[1] > std::numeric_limits<int>::max() - vp[3]
                     ? "viewport: no width / height, or beyond int"
                     : (params.clip_depth != ClipDepth::NegativeOneToOne && params.clip_depth != ClipDepth::ZeroToOne
                            ? "clip_depth: unknown ClipDepth"
                            : "view_proj: singular (or the zero default)")));
        return Status::InvalidArgument;
    }
    return Status::Ok;
}

// The occluder's shadow region as half-spaces n . X <= d (at most 16) and the coordinates' scale.
struct SvRegion {
    struct Plane { SvVec n; double d; };
    Plane pl[6 + 1 + 3 + 6];
    int np = 0;
    double scale = 1.0;
};

// Step 2a: the box faces facing the light and the planes through its silhouette edges and the light
// (the light outside the box); appended to R.
inline void sv_box_shadow_planes(const SvVec& bmin, const SvVec& bmax, const SvVec& L, bool point, SvRegion& R) {
    const SvVec bc = (bmin + bmax) * 0.5;
    // Box faces: index 2*axis + (0: min side, 1: max side); outward normal +-e_axis.
    bool facing[6];
    for (int f = 0; f < 6; ++f) {
        const int ax = f / 2;
        const double sgn = (f & 1) ? 1.0 : -1.0;
        const double off = (f & 1) ? sv_get(bmax, ax) : sv_get(bmin, ax);
        const double lc = sv_get(L, ax);
        facing[f] = point ? sgn * (lc - off) > 0.0 : sgn * lc > 0.0;
        if (facing[f] && R.np < 16) {
            SvVec n{0, 0, 0};
            sv_set(n, ax, sgn);
            R.pl[R.np++] = {n, sgn * off};
        }
    }
    // Silhouette edges: 12 box edges, each between two faces (axes a != b) along axis c.
    SvRegion::Plane sil[12];
    int ns = 0;
    for (int c = 0; c < 3; ++c) {
        const int a = (c + 1) % 3, b = (c + 2) % 3;
        for (int sa = 0; sa < 2; ++sa)
            for (int sb = 0; sb < 2; ++sb) {
                if (facing[2 * a + sa] == facing[2 * b + sb]) continue;
                SvVec p0 = bmin, p1;
                sv_set(p0, a, sa ? sv_get(bmax, a) : sv_get(bmin, a));
                sv_set(p0, b, sb ? sv_get(bmax, b) : sv_get(bmin, b));
                p1 = p0;
                sv_set(p0, c, sv_get(bmin, c));
                sv_set(p1, c, sv_get(bmax, c));
                const SvVec e = p1 - p0;
                SvVec n = point ? sv_cross(e, L - p0) : sv_cross(e, L);
                const double nl = std::sqrt(sv_len2(n));
                if (!(nl > 0.0) || sv_len2(e) == 0.0) continue;
                n = n * (1.0 / nl);
                double d = sv_dot(n, p0);
                if (sv_dot(n, bc) > d) { n = n * -1.0; d = -d; }
                // keep only if every box corner is inside (guards against rounding)
                bool ok = true;
                for (int k = 0; k < 8 && ok; ++k) {
                    const SvVec q{(k & 1) ? bmax.x : bmin.x, (k & 2) ? bmax.y : bmin.y, (k & 4) ? bmax.z : bmin.z};
                    ok = sv_dot(n, q) <= d + 1e-12 * R.scale;
                }
                if (ok) sil[ns++] = {n, d};
            }
    }
    for (int s = 0; s < ns && R.np < 16; ++s) R.pl[R.np++] = sil[s];
}

// Step 2 of volume_scissor: the shadow region: the light's box, in front of the camera's near plane,
// and (the light outside the occluder box) behind the box's lit faces, within its silhouette planes.
inline SvRegion sv_shadow_region(const glm::vec4& light, const glm::vec3& box_min, const glm::vec3& box_max,
                                 const glm::vec3& light_min, const glm::vec3& light_max, const glm::dmat4& M,
                                 const ScissorParams& params) {
    SvRegion R;
    const SvVec lmin = sv_of(light_min), lmax = sv_of(light_max);
    R.pl[R.np++] = {SvVec{1, 0, 0}, lmax.x};
    R.pl[R.np++] = {SvVec{-1, 0, 0}, -lmin.x};
    R.pl[R.np++] = {SvVec{0, 1, 0}, lmax.y};
    R.pl[R.np++] = {SvVec{0, -1, 0}, -lmin.y};
    R.pl[R.np++] = {SvVec{0, 0, 1}, lmax.z};
    R.pl[R.np++] = {SvVec{0, 0, -1}, -lmin.z};
    // Camera near plane from the clip-space rows of view_proj: in front of it <=> g . (X, 1) >= 0.
    auto row = [&](int r) { return glm::dvec4(M[0][r], M[1][r], M[2][r], M[3][r]); };
    glm::dvec4 g;
    if (params.reversed_z) g = row(3) - row(2);
    else if (params.clip_depth == ClipDepth::NegativeOneToOne) g = row(3) + row(2);
    else g = row(2);
    R.pl[R.np++] = {SvVec{-g.x, -g.y, -g.z}, g.w};
    // Shadow region of the occluder box.
    const SvVec bmin = sv_of(box_min), bmax = sv_of(box_max);
    const bool point = light.w > 0.0f;
    const SvVec L = point ? SvVec{static_cast<double>(light.x) / light.w, static_cast<double>(light.y) / light.w,
                                  static_cast<double>(light.z) / light.w}
                          : SvVec{light.x, light.y, light.z};
    const bool light_inside = point && L.x >= bmin.x && L.x <= bmax.x && L.y >= bmin.y && L.y <= bmax.y &&
                              L.z >= bmin.z && L.z <= bmax.z;
    for (double v : {lmin.x, lmin.y, lmin.z, lmax.x, lmax.y, lmax.z, bmin.x, bmin.y, bmin.z, bmax.x, bmax.y, bmax.z})
        R.scale = std::fmax(R.scale, std::fabs(v));
    if (point) R.scale = std::fmax(R.scale, std::fmax(std::fabs(L.x), std::fmax(std::fabs(L.y), std::fabs(L.z))));
    if (!light_inside) sv_box_shadow_planes(bmin, bmax, L, point, R);
    return R;
}

// The NDC bounds of a region's vertices in front of the eye.
struct SvNdcBox {
    bool any = false;
    double xmin = std::numeric_limits<double>::infinity(), xmax = -std::numeric_limits<double>::infinity();
    double ymin = std::numeric_limits<double>::infinity(), ymax = -std::numeric_limits<double>::infinity();
    double zmin = std::numeric_limits<double>::infinity(), zmax = -std::numeric_limits<double>::infinity();
};

// Step 3 of volume_scissor: vertex enumeration: all plane triples, keep points satisfying every
// half-space, and bound their NDC.
inline SvNdcBox sv_region_ndc_bounds(const SvRegion& R, const glm::dmat4& M) {
    SvNdcBox b;
    const double tol = 1e-9 * R.scale;
    const SvRegion::Plane* pl = R.pl;
    const int np = R.np;
    for (int i = 0; i < np; ++i)
        for (int j = i + 1; j < np; ++j)
            for (int k = j + 1; k < np; ++k) {
                const SvVec a = pl[i].n, bb = pl[j].n, c = pl[k].n;
                const SvVec bxc = sv_cross(bb, c);
                const double det = sv_dot(a, bxc);
                if (std::fabs(det) < 1e-12) continue;
                const SvVec X = (bxc * pl[i].d + sv_cross(c, a) * pl[j].d + sv_cross(a, bb) * pl[k].d) * (1.0 / det);
                if (!(std::isfinite(X.x) && std::isfinite(X.y) && std::isfinite(X.z))) continue;
                bool in = true;
                for (int q = 0; q < np && in; ++q) in = sv_dot(pl[q].n, X) <= pl[q].d + tol;
                if (!in) continue;
                const glm::dvec4 clip = M * glm::dvec4(X.x, X.y, X.z, 1.0);
                if (!(clip.w > 0.0)) continue; // on/behind the eye plane: only possible within tol
                b.any = true;
                const double nx = clip.x / clip.w, ny = clip.y / clip.w, nz = clip.z / clip.w;
                b.xmin = std::fmin(b.xmin, nx); b.xmax = std::fmax(b.xmax, nx);
                b.ymin = std::fmin(b.ymin, ny); b.ymax = std::fmax(b.ymax, ny);
                b.zmin = std::fmin(b.zmin, nz); b.zmax = std::fmax(b.zmax, nz);
            }
    return b;
}

// Step 4 of volume_scissor: the NDC bounds to whole viewport pixels and padded depth bounds.
inline void sv_scissor_from_ndc(const SvNdcBox& b, const ScissorParams& params, ScissorRect& res) {
    const int* vp = params.viewport;
    auto clampd = [](double v, double lo, double hi) { return v < lo ? lo : (v > hi ? hi : v); };
    const double px0 = vp[0] + (clampd(b.xmin, -1.0, 1.0) + 1.0) * 0.5 * vp[2];
    const double px1 = vp[0] + (clampd(b.xmax, -1.0, 1.0) + 1.0) * 0.5 * vp[2];
    const double py0 = vp[1] + (clampd(b.ymin, -1.0, 1.0) + 1.0) * 0.5 * vp[3];
    const double py1 = vp[1] + (clampd(b.ymax, -1.0, 1.0) + 1.0) * 0.5 * vp[3];
    if (b.xmin > 1.0 || b.xmax < -1.0 || b.ymin > 1.0 || b.ymax < -1.0) { res.visible = false; return; }
    const int ix0 = static_cast<int>(std::floor(px0)), ix1 = static_cast<int>(std::ceil(px1));
    const int iy0 = static_cast<int>(std::floor(py0)), iy1 = static_cast<int>(std::ceil(py1));
    res.x = ix0;
    res.y = iy0;
    res.width = ix1 - ix0;
    res.height = iy1 - iy0;
    if (res.width <= 0 || res.height <= 0) {
        // zero-area projection: keep one pixel row/column so touching fragments are kept
        if (res.width <= 0) { res.width = 1; if (res.x >= vp[0] + vp[2]) res.x = vp[0] + vp[2] - 1; }
        if (res.height <= 0) { res.height = 1; if (res.y >= vp[1] + vp[3]) res.y = vp[1] + vp[3] - 1; }
    }
    const bool gl = params.clip_depth == ClipDepth::NegativeOneToOne;
    const double w0 = gl ? 0.5 * b.zmin + 0.5 : b.zmin, w1 = gl ? 0.5 * b.zmax + 0.5 : b.zmax;
    float dmin = static_cast<float>(clampd(w0, 0.0, 1.0)), dmax = static_cast<float>(clampd(w1, 0.0, 1.0));
    dmin = std::nextafter(dmin, -1.0f);
    dmax = std::nextafter(dmax, 2.0f);
    res.depth_min = dmin < 0.0f ? 0.0f : dmin;
    res.depth_max = dmax > 1.0f ? 1.0f : dmax;
    res.visible = true;
}

} // namespace detail

/// Per-occluder scissor rectangle and depth bounds (Lengyel), see the header comment.
/// box_min/max: occluder bounds; light_min/max: the light's bounding box (finite; everything that can
/// receive this light's shadows lies inside). params: every field required (a zero or singular
/// view_proj, or a viewport without width / height, is InvalidArgument).
inline ScissorRect volume_scissor(const glm::vec4& light_position, const glm::vec3& box_min, const glm::vec3& box_max,
                                  const glm::vec3& light_min, const glm::vec3& light_max, const ScissorParams& params) {
    using namespace detail;
    ScissorRect res;
    res.status = sv_scissor_check(light_position, box_min, box_max, light_min, light_max, params, res.detail);
    if (res.status != Status::Ok) return res;
    const glm::dmat4 M(params.view_proj);
    const SvRegion R = sv_shadow_region(light_position, box_min, box_max, light_min, light_max, M, params);
    const SvNdcBox b = sv_region_ndc_bounds(R, M);
    if (!b.any) { res.visible = false; res.width = res.height = 0; return res; }
    sv_scissor_from_ndc(b, params, res);
    return res;
}

} // namespace shadowkit
