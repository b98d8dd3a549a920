// shadowkit/shadow_volume.hpp - robust stenciled shadow volumes: side quads extruded to infinity
// (w = 0), light and dark caps for z-fail, open-mesh handling, the z-pass / z-fail decision, and
// per-object scissor rectangle and depth bounds. Plain arrays in (positions, silhouette edge index
// pairs, triangles, per-triangle lit flags); no dependency on other shadowkit headers.
//
// Usage (per light, per occluder; silhouette + lit flags e.g. from shadowkit/silhouette.hpp):
//   #include <shadowkit/shadow_volume.hpp>
//   // vertex buffer once per mesh: 2n vec4, (p, 1) then (p, 0); the vertex shader extrudes w = 0
//   shadowkit::build_volume_vertices(pos, n, vbo4.data(), vbo4.size());
//   shadowkit::MethodResult m = shadowkit::choose_stencil_method_box(
//       shadowkit::near_plane_rect(view, fovy, aspect, near_z), light, bmin, bmax, 1e-4f);
//   std::size_t ns = shadowkit::build_side_quads(sil.data(), sil_edges, n, ib.data(), ib.size()).count;
//   std::size_t nc = 0;
//   if (m.method == shadowkit::StencilMethod::ZFail)
//       nc = shadowkit::build_caps(tris, tri_count, lit, n, shadowkit::CapMode::LitOnly, true,
//                                  ib.data() + ns, ib.size() - ns).count;
//   shadowkit::ScissorResult s = shadowkit::shadow_volume_scissor(light, bmin, bmax, lmin, lmax, sp);
//   if (!s.visible) skip; else glScissor(s.x, s.y, s.width, s.height), glDepthBoundsEXT(s.depth_min, s.depth_max);
//
// Based on:
//   C. Everitt, M. J. Kilgard, "Practical and Robust Stenciled Shadow Volumes for Hardware-Accelerated
//   Rendering", NVIDIA 2002: side quad (B, A, A_inf, B_inf) with X_inf = (X.xyz L.w - L.xyz X.w, 0)
//   (section 3.2.2), caps (3.2.2), z-fail (2.2.3), mixing z-pass and z-fail per occluder (3.4).
//   E. Lengyel, "Advanced Stencil Shadow and Penumbral Wedge Rendering", GDC 2005: per-geometry scissor
//   (bounding pyramid clipped to the light's box, projected) and depth bounds.
//   P. Bergeron, "A General Version of Crow's Shadow Volumes", IEEE CG&A 1986 (open models).
//
// Vertex layout. Volume index buffers index a 2n-vertex buffer: i in [0, n) is (p_i, 1), i + n is
// (p_i, 0); the vertex shader maps (p, 0) to (p L.w - L.xyz, 0) (glsl/shadow_volume.glsl). For a
// directional light all w = 0 vertices become the same point (-L.xyz, 0); side quads then rasterise
// as triangles and the dark cap has zero area (pass dark_cap = false to skip it).
//
// Orientation. Silhouette edges (a, b) must be oriented as in their light-facing triangle
// (counter-clockwise front faces). Side quad = triangles (b, a, a+n), (b, a+n, b+n); light cap = lit
// triangles as given; dark cap per CapMode. The volume's faces then point outwards; with GL_CCW front
// faces, the two-sided z-fail recipe is: back faces GL_INCR_WRAP on depth fail, front faces
// GL_DECR_WRAP on depth fail.
//
// Open meshes (CapMode::LitOnly, the documented method). The volume is the sum of one closed prism per
// lit triangle: the triangle, its three side quads, and the triangle extruded to infinity with
// reversed winding. Side quads of edges shared by lit triangles cancel, which leaves exactly the
// silhouette.hpp edge rule (k = sum over lit faces of +-1, emitted |k| times). Hence the volume is
// closed and consistently oriented for any triangle soup, and the z-fail count at a point X equals the
// number of lit triangles crossed by the segment from X to the light (the ray for a directional
// light). Limits: triangles act as one-sided occluders (an unlit triangle casts no shadow, so a
// single-sided open surface seen from its back casts none - make such surfaces two-sided); a light
// inside a closed mesh with outward faces sees no lit face and casts nothing (CapMode::EverittKilgard
// shadows everything outside instead); the stencil must hold the largest count (8 bits, wrapping).
// CapMode::EverittKilgard (dark cap = unlit triangles extruded) is identical for closed, consistently
// wound meshes with the light outside and is only closed for such meshes.
//
// Z-pass vs z-fail. Z-pass counts from the near plane, so it is exact iff no point of the near-plane
// rectangle is in the occluder's shadow, i.e. iff the occluder's bounds miss the convex hull of the
// light and the near rectangle (the near-plane occlusion pyramid; a prism toward the light for w = 0).
// The box test is an exact separating-axis test, the sphere test an exact distance test (both in
// double); touching counts as intersecting; `margin` inflates the bounds for rounding.
//
// Scissor and depth bounds. The occluder's shadow lies in S = {L + t (p - L) : p in box, t >= 1}
// (for w = 0: p - t L.xyz). S is contained in the intersection of the half-spaces behind the box faces
// that face the light and the planes through the light (direction) and the box's silhouette edges.
// That polytope is clipped to the light's bounding box and to the camera near plane, its vertices
// are enumerated (plane triples) and projected: the scissor rectangle is their pixel bounding box
// (floor / ceil, clamped to the viewport) and [depth_min, depth_max] their window-depth range (Lengyel:
// viewport depth of (P row 3 . X) / (P row 4 . X)), rounded outwards in float. visible = false when
// the polytope is empty (the shadow cannot reach the light's bounds in front of the camera).
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

namespace shadowkit {

#ifndef SHADOWKIT_CLIP_DEPTH_DEFINED
#define SHADOWKIT_CLIP_DEPTH_DEFINED
/// Clip-space depth range: OpenGL default [-1, 1] or D3D/Vulkan/glClipControl [0, 1].
enum class ClipDepth { NegativeOneToOne, ZeroToOne };
#endif

enum class VolumeStatus {
    Ok,
    InvalidArgument, ///< null pointer with non-zero count, counts too large, bad viewport
    IndexOutOfRange, ///< an index >= vertex_count
    NonFinite,       ///< NaN / Inf in positions, matrices or bounds
    InvalidLight,    ///< light not finite, w < 0 or (0, 0, 0, 0)
    InvalidBounds,   ///< min > max, negative radius
    BufferTooSmall   ///< output truncated; `count` is the size needed
};

/// Number of elements written / needed (written = min(count, capacity)).
struct VolumeCount {
    VolumeStatus status = VolumeStatus::Ok;
    std::size_t count = 0;
};

enum class CapMode {
    LitOnly,       ///< dark cap = lit triangles extruded, reversed: closed for any mesh (open meshes)
    EverittKilgard ///< dark cap = unlit triangles extruded: closed meshes only (Everitt-Kilgard 3.2.2)
};

enum class StencilMethod { ZPass, ZFail };

struct MethodResult {
    VolumeStatus status = VolumeStatus::Ok;
    StencilMethod method = StencilMethod::ZFail; ///< ZFail whenever unsure
};

/// World-space corners of the near-plane rectangle (any winding, convex).
struct NearPlaneRect {
    glm::vec3 corners[4];
};

struct ScissorParams {
    glm::mat4 view_proj = glm::mat4(1.0f); ///< projection * view (world -> clip)
    ClipDepth clip_depth = ClipDepth::NegativeOneToOne;
    bool reversed_z = false;
    int viewport[4] = {0, 0, 1, 1};        ///< x, y, width, height (pixels)
};

struct ScissorResult {
    VolumeStatus status = VolumeStatus::Ok;
    bool visible = false;          ///< false: the volume cannot touch a pixel (skip the occluder)
    int x = 0, y = 0, width = 0, height = 0;
    float depth_min = 0.0f, depth_max = 1.0f; ///< window depth, glDepthRange(0, 1)
};

namespace detail {

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

struct SvVec {
    double x, y, z;
};
inline SvVec sv(const glm::vec3& v) { return SvVec{v.x, v.y, v.z}; }
inline SvVec operator+(SvVec a, SvVec b) { return SvVec{a.x + b.x, a.y + b.y, a.z + b.z}; }
inline SvVec operator-(SvVec a, SvVec b) { return SvVec{a.x - b.x, a.y - b.y, a.z - b.z}; }
inline SvVec operator*(SvVec a, double s) { return SvVec{a.x * s, a.y * s, a.z * s}; }
inline double dot(SvVec a, SvVec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline SvVec cross(SvVec a, SvVec b) { return SvVec{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline double len2(SvVec a) { return dot(a, a); }
inline double get(const SvVec& v, int i) { return i == 0 ? v.x : (i == 1 ? v.y : v.z); }
inline void set(SvVec& v, int i, double x) {
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
inline SvPoly sv_near_poly(const NearPlaneRect& r, const glm::vec4& L, double reach) {
    SvPoly p;
    for (int i = 0; i < 4; ++i) p.v[i] = sv(r.corners[i]);
    p.nv = 4;
    for (int i = 0; i < 4; ++i) p.edge[p.ne++] = p.v[(i + 1) % 4] - p.v[i];
    p.normal[p.nn++] = cross(p.edge[0], p.edge[1]);
    sv_add_tri(p, 0, 1, 2);
    sv_add_tri(p, 0, 2, 3);
    if (L.w > 0.0f) {
        const SvVec l{static_cast<double>(L.x) / L.w, static_cast<double>(L.y) / L.w, static_cast<double>(L.z) / L.w};
        p.v[p.nv++] = l;
        for (int i = 0; i < 4; ++i) {
            p.normal[p.nn++] = cross(p.v[(i + 1) % 4] - p.v[i], l - p.v[i]);
            p.edge[p.ne++] = l - p.v[i];
            sv_add_tri(p, i, (i + 1) % 4, 4);
        }
    } else {
        SvVec d{L.x, L.y, L.z};
        d = d * (1.0 / std::sqrt(len2(d)));
        for (int i = 0; i < 4; ++i) p.v[p.nv++] = p.v[i] + d * reach;
        p.edge[p.ne++] = d;
        for (int i = 0; i < 4; ++i) {
            const int j = (i + 1) % 4;
            p.normal[p.nn++] = cross(p.v[j] - p.v[i], d);
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
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return len2(p - a);
    const SvVec bp = p - b;
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return len2(p - b);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) { const double v = d1 / (d1 - d3); return len2(p - (a + ab * v)); }
    const SvVec cp = p - c;
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return len2(p - c);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) { const double w = d2 / (d2 - d6); return len2(p - (a + ac * w)); }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return len2(p - (b + (c - b) * w));
    }
    const double den = va + vb + vc;
    if (!(den != 0.0)) { // degenerate triangle: edges
        double m = len2(p - a);
        const SvVec segs[3][2] = {{a, b}, {b, c}, {c, a}};
        for (const auto& s : segs) {
            const SvVec e = s[1] - s[0];
            const double l = len2(e);
            double t = l > 0 ? dot(p - s[0], e) / l : 0.0;
            t = t < 0 ? 0 : (t > 1 ? 1 : t);
            const double q = len2(p - (s[0] + e * t));
            if (q < m) m = q;
        }
        return m;
    }
    const double v = vb / den, w = vc / den;
    return len2(p - (a + ab * v + ac * w));
}

} // namespace detail

/// Homogeneous extrusion to infinity away from the light (Everitt-Kilgard 3.2.2):
/// (p.xyz L.w - L.xyz p.w, 0). For p.w = 1 and a point light this is the direction p - L.
inline glm::vec4 extrude_to_infinity(const glm::vec4& p, const glm::vec4& L) {
    return glm::vec4(p.x * L.w - L.x * p.w, p.y * L.w - L.y * p.w, p.z * L.w - L.z * p.w, 0.0f);
}

/// Fills out[0, n) = (p, 1) and out[n, 2n) = (p, 0). capacity in vec4; count = 2n.
inline VolumeCount build_volume_vertices(const glm::vec3* positions, std::size_t vertex_count, glm::vec4* out,
                                         std::size_t capacity) {
    VolumeCount r;
    if ((vertex_count > 0 && positions == nullptr) || (capacity > 0 && out == nullptr) ||
        vertex_count > 0x7FFFFFFFull) {
        r.status = VolumeStatus::InvalidArgument;
        return r;
    }
    for (std::size_t i = 0; i < vertex_count; ++i)
        if (!detail::sv_finite3(positions[i])) { r.status = VolumeStatus::NonFinite; return r; }
    r.count = 2 * vertex_count;
    for (std::size_t i = 0; i < vertex_count; ++i) {
        if (i < capacity) out[i] = glm::vec4(positions[i], 1.0f);
        if (vertex_count + i < capacity) out[vertex_count + i] = glm::vec4(positions[i], 0.0f);
    }
    if (r.count > capacity) r.status = VolumeStatus::BufferTooSmall;
    return r;
}

/// Side quads: for each silhouette edge (a, b) = (edges[2e], edges[2e+1]) the triangles
/// (b, a, a + n) and (b, a + n, b + n), n = vertex_count. 6 indices per edge.
inline VolumeCount build_side_quads(const std::uint32_t* edges, std::size_t edge_count, std::size_t vertex_count,
                                    std::uint32_t* out, std::size_t capacity) {
    VolumeCount r;
    if ((edge_count > 0 && edges == nullptr) || (capacity > 0 && out == nullptr) || vertex_count > 0x7FFFFFFFull ||
        edge_count > (std::numeric_limits<std::size_t>::max() / 8)) {
        r.status = VolumeStatus::InvalidArgument;
        return r;
    }
    for (std::size_t i = 0; i < 2 * edge_count; ++i)
        if (edges[i] >= vertex_count) { r.status = VolumeStatus::IndexOutOfRange; return r; }
    const std::uint32_t n = static_cast<std::uint32_t>(vertex_count);
    r.count = 6 * edge_count;
    const std::size_t full = capacity / 6 < edge_count ? capacity / 6 : edge_count;
    for (std::size_t e = 0; e < full; ++e) {
        const std::uint32_t a = edges[2 * e], b = edges[2 * e + 1];
        std::uint32_t* o = out + 6 * e;
        o[0] = b; o[1] = a; o[2] = a + n;
        o[3] = b; o[4] = a + n; o[5] = b + n;
    }
    if (r.count > capacity) r.status = VolumeStatus::BufferTooSmall;
    return r;
}

/// Light cap (lit triangles, as given) and, if dark_cap, the dark cap (CapMode) for z-fail.
/// triangles: 3 indices per triangle; lit: one flag per triangle (non-zero = light-facing).
inline VolumeCount build_caps(const std::uint32_t* triangles, std::size_t triangle_count, const std::uint8_t* lit,
                              std::size_t vertex_count, CapMode mode, bool dark_cap, std::uint32_t* out,
                              std::size_t capacity) {
    VolumeCount r;
    if ((triangle_count > 0 && (triangles == nullptr || lit == nullptr)) || (capacity > 0 && out == nullptr) ||
        vertex_count > 0x7FFFFFFFull || triangle_count > (std::numeric_limits<std::size_t>::max() / 8)) {
        r.status = VolumeStatus::InvalidArgument;
        return r;
    }
    for (std::size_t i = 0; i < 3 * triangle_count; ++i)
        if (triangles[i] >= vertex_count) { r.status = VolumeStatus::IndexOutOfRange; return r; }
    const std::uint32_t n = static_cast<std::uint32_t>(vertex_count);
    std::size_t k = 0;
    auto put = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        if (k + 3 <= capacity) { out[k] = a; out[k + 1] = b; out[k + 2] = c; }
        k += 3;
    };
    for (std::size_t t = 0; t < triangle_count; ++t) {
        const std::uint32_t a = triangles[3 * t], b = triangles[3 * t + 1], c = triangles[3 * t + 2];
        if (lit[t]) {
            put(a, b, c);
            if (dark_cap && mode == CapMode::LitOnly) put(a + n, c + n, b + n);
        } else if (dark_cap && mode == CapMode::EverittKilgard) {
            put(a + n, b + n, c + n);
        }
    }
    r.count = k;
    if (k > capacity) r.status = VolumeStatus::BufferTooSmall;
    return r;
}

/// Near-plane rectangle from a view matrix (world -> eye, right-handed, looking down -z) and a
/// symmetric perspective (fovy full vertical angle, radians). Computed in double.
inline NearPlaneRect near_plane_rect(const glm::mat4& view, float fovy, float aspect, float near_z) {
    NearPlaneRect r;
    const glm::dmat4 inv = glm::inverse(glm::dmat4(view));
    const double t = static_cast<double>(near_z) * std::tan(0.5 * static_cast<double>(fovy));
    const double s = t * static_cast<double>(aspect);
    const double xs[4] = {-s, s, s, -s}, ys[4] = {-t, -t, t, t};
    for (int i = 0; i < 4; ++i) {
        const glm::dvec4 w = inv * glm::dvec4(xs[i], ys[i], -static_cast<double>(near_z), 1.0);
        r.corners[i] = glm::vec3(static_cast<float>(w.x / w.w), static_cast<float>(w.y / w.w), static_cast<float>(w.z / w.w));
    }
    return r;
}

/// Near-plane rectangle from the inverse of projection * view (any perspective projection).
inline NearPlaneRect near_plane_rect_from_inverse(const glm::mat4& inverse_view_proj, ClipDepth clip, bool reversed_z) {
    NearPlaneRect r;
    const glm::dmat4 inv(inverse_view_proj);
    const double zn = reversed_z ? 1.0 : (clip == ClipDepth::NegativeOneToOne ? -1.0 : 0.0);
    const double xs[4] = {-1, 1, 1, -1}, ys[4] = {-1, -1, 1, 1};
    for (int i = 0; i < 4; ++i) {
        const glm::dvec4 w = inv * glm::dvec4(xs[i], ys[i], zn, 1.0);
        r.corners[i] = glm::vec3(static_cast<float>(w.x / w.w), static_cast<float>(w.y / w.w), static_cast<float>(w.z / w.w));
    }
    return r;
}

/// Z-pass is safe iff the box [bmin - margin, bmax + margin] misses hull(light, near rectangle)
/// (exact separating-axis test in double). Otherwise (or on touching) ZFail.
inline MethodResult choose_stencil_method_box(const NearPlaneRect& rect, const glm::vec4& light, const glm::vec3& bmin,
                                              const glm::vec3& bmax, float margin = 0.0f) {
    MethodResult m;
    for (const glm::vec3& c : rect.corners)
        if (!detail::sv_finite3(c)) { m.status = VolumeStatus::NonFinite; return m; }
    if (!detail::sv_valid_light(light)) { m.status = VolumeStatus::InvalidLight; return m; }
    if (!detail::sv_finite3(bmin) || !detail::sv_finite3(bmax) || !std::isfinite(margin)) { m.status = VolumeStatus::NonFinite; return m; }
    if (!(bmin.x <= bmax.x && bmin.y <= bmax.y && bmin.z <= bmax.z) || margin < 0.0f) { m.status = VolumeStatus::InvalidBounds; return m; }
    using namespace detail;
    const SvVec lo = sv(bmin) - SvVec{margin, margin, margin}, hi = sv(bmax) + SvVec{margin, margin, margin};
    // Reach for w = 0: beyond it no point of the swept rectangle can be within the box.
    double reach = 0.0;
    {
        const SvVec c = (lo + hi) * 0.5;
        double far2 = 0.0;
        for (int i = 0; i < 4; ++i) far2 = std::fmax(far2, len2(sv(rect.corners[i]) - c));
        reach = 2.0 * (std::sqrt(far2) + std::sqrt(len2(hi - lo))) + 1.0;
    }
    const SvPoly p = sv_near_poly(rect, light, reach);
    SvVec axes[6 + 3 + 24];
    int na = 0;
    for (int i = 0; i < p.nn; ++i) axes[na++] = p.normal[i];
    const SvVec box_axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (const SvVec& a : box_axes) axes[na++] = a;
    for (int i = 0; i < p.ne; ++i)
        for (const SvVec& a : box_axes) axes[na++] = cross(p.edge[i], a);
    const SvVec bc = (lo + hi) * 0.5, bh = (hi - lo) * 0.5;
    for (int k = 0; k < na; ++k) {
        const SvVec a = axes[k];
        const double l2 = len2(a);
        if (!(l2 > 0.0) || !std::isfinite(l2)) continue;
        double pmin = std::numeric_limits<double>::infinity(), pmax = -pmin;
        for (int i = 0; i < p.nv; ++i) {
            const double d = dot(a, p.v[i]);
            pmin = std::fmin(pmin, d);
            pmax = std::fmax(pmax, d);
        }
        const double c = dot(a, bc);
        const double r = std::fabs(a.x) * bh.x + std::fabs(a.y) * bh.y + std::fabs(a.z) * bh.z;
        if (c + r < pmin || c - r > pmax) { m.method = StencilMethod::ZPass; return m; }
    }
    m.method = StencilMethod::ZFail;
    return m;
}

/// Sphere version: ZPass iff the distance from `center` to hull(light, near rectangle) exceeds
/// radius + margin (exact distance to the polytope's boundary triangles, inside test by planes).
inline MethodResult choose_stencil_method_sphere(const NearPlaneRect& rect, const glm::vec4& light,
                                                 const glm::vec3& center, float radius, float margin = 0.0f) {
    MethodResult m;
    for (const glm::vec3& c : rect.corners)
        if (!detail::sv_finite3(c)) { m.status = VolumeStatus::NonFinite; return m; }
    if (!detail::sv_valid_light(light)) { m.status = VolumeStatus::InvalidLight; return m; }
    if (!detail::sv_finite3(center) || !std::isfinite(radius) || !std::isfinite(margin)) { m.status = VolumeStatus::NonFinite; return m; }
    if (radius < 0.0f || margin < 0.0f) { m.status = VolumeStatus::InvalidBounds; return m; }
    using namespace detail;
    const SvVec c = sv(center);
    const double rr = static_cast<double>(radius) + static_cast<double>(margin);
    double far2 = 0.0;
    for (int i = 0; i < 4; ++i) far2 = std::fmax(far2, len2(sv(rect.corners[i]) - c));
    const SvPoly p = sv_near_poly(rect, light, 2.0 * (std::sqrt(far2) + rr) + 1.0);
    // Inside test: only for a solid polytope; planes oriented outwards via the centroid.
    SvVec cen{0, 0, 0};
    for (int i = 0; i < p.nv; ++i) cen = cen + p.v[i];
    cen = cen * (1.0 / p.nv);
    bool inside = true;
    int solid_planes = 0;
    for (int t = 0; t < p.nt && inside; ++t) {
        const SvVec a = p.v[p.tri[t][0]];
        SvVec nrm = cross(p.v[p.tri[t][1]] - a, p.v[p.tri[t][2]] - a);
        const double l = std::sqrt(len2(nrm));
        if (!(l > 0.0)) continue;
        nrm = nrm * (1.0 / l);
        const double sc = dot(nrm, cen - a);
        if (std::fabs(sc) <= 1e-12 * std::sqrt(far2 + 1.0)) continue; // flat polytope face
        ++solid_planes;
        if (sc > 0) nrm = nrm * -1.0;
        if (dot(nrm, c - a) > 0.0) inside = false;
    }
    if (inside && solid_planes >= 4) { m.method = StencilMethod::ZFail; return m; }
    double best = std::numeric_limits<double>::infinity();
    for (int t = 0; t < p.nt; ++t)
        best = std::fmin(best, sv_tri_dist2(c, p.v[p.tri[t][0]], p.v[p.tri[t][1]], p.v[p.tri[t][2]]));
    m.method = best <= rr * rr ? StencilMethod::ZFail : StencilMethod::ZPass;
    return m;
}

/// Per-object scissor rectangle and depth bounds (Lengyel), see the header comment.
/// obj_min/max: occluder bounds; light_min/max: the light's bounding box (finite; everything that
/// can receive this light's shadows lies inside).
inline ScissorResult shadow_volume_scissor(const glm::vec4& light, const glm::vec3& obj_min, const glm::vec3& obj_max,
                                           const glm::vec3& light_min, const glm::vec3& light_max,
                                           const ScissorParams& params) {
    using namespace detail;
    ScissorResult res;
    if (!sv_valid_light(light)) { res.status = VolumeStatus::InvalidLight; return res; }
    if (!sv_finite3(obj_min) || !sv_finite3(obj_max) || !sv_finite3(light_min) || !sv_finite3(light_max) ||
        !sv_finite_mat(params.view_proj)) {
        res.status = VolumeStatus::NonFinite;
        return res;
    }
    if (!(obj_min.x <= obj_max.x && obj_min.y <= obj_max.y && obj_min.z <= obj_max.z) ||
        !(light_min.x <= light_max.x && light_min.y <= light_max.y && light_min.z <= light_max.z)) {
        res.status = VolumeStatus::InvalidBounds;
        return res;
    }
    const int* vp = params.viewport;
    if (vp[2] <= 0 || vp[3] <= 0 || vp[0] > std::numeric_limits<int>::max() - vp[2] ||
        vp[1] > std::numeric_limits<int>::max() - vp[3]) {
        res.status = VolumeStatus::InvalidArgument;
        return res;
    }
    // Half-spaces n . X <= d.
    struct Plane { SvVec n; double d; };
    Plane pl[6 + 1 + 3 + 6];
    int np = 0;
    const SvVec lmin = sv(light_min), lmax = sv(light_max);
    pl[np++] = {SvVec{1, 0, 0}, lmax.x};
    pl[np++] = {SvVec{-1, 0, 0}, -lmin.x};
    pl[np++] = {SvVec{0, 1, 0}, lmax.y};
    pl[np++] = {SvVec{0, -1, 0}, -lmin.y};
    pl[np++] = {SvVec{0, 0, 1}, lmax.z};
    pl[np++] = {SvVec{0, 0, -1}, -lmin.z};
    // Camera near plane from the clip-space rows of view_proj: in front of it <=> g . (X, 1) >= 0.
    const glm::dmat4 M(params.view_proj);
    auto row = [&](int r) { return glm::dvec4(M[0][r], M[1][r], M[2][r], M[3][r]); };
    glm::dvec4 g;
    if (params.reversed_z) g = row(3) - row(2);
    else if (params.clip_depth == ClipDepth::NegativeOneToOne) g = row(3) + row(2);
    else g = row(2);
    pl[np++] = {SvVec{-g.x, -g.y, -g.z}, g.w};
    // Shadow region of the occluder box.
    const SvVec bmin = sv(obj_min), bmax = sv(obj_max), bc = (bmin + bmax) * 0.5;
    const bool point = light.w > 0.0f;
    const SvVec L = point ? SvVec{static_cast<double>(light.x) / light.w, static_cast<double>(light.y) / light.w,
                                  static_cast<double>(light.z) / light.w}
                          : SvVec{light.x, light.y, light.z};
    const bool light_inside = point && L.x >= bmin.x && L.x <= bmax.x && L.y >= bmin.y && L.y <= bmax.y &&
                              L.z >= bmin.z && L.z <= bmax.z;
    double scale = 1.0;
    for (double v : {lmin.x, lmin.y, lmin.z, lmax.x, lmax.y, lmax.z, bmin.x, bmin.y, bmin.z, bmax.x, bmax.y, bmax.z})
        scale = std::fmax(scale, std::fabs(v));
    if (point) scale = std::fmax(scale, std::fmax(std::fabs(L.x), std::fmax(std::fabs(L.y), std::fabs(L.z))));
    if (!light_inside) {
        // Box faces: index 2*axis + (0: min side, 1: max side); outward normal +-e_axis.
        bool facing[6];
        for (int f = 0; f < 6; ++f) {
            const int ax = f / 2;
            const double sgn = (f & 1) ? 1.0 : -1.0;
            const double off = (f & 1) ? get(bmax, ax) : get(bmin, ax);
            const double lc = get(L, ax);
            facing[f] = point ? sgn * (lc - off) > 0.0 : sgn * lc > 0.0;
            if (facing[f] && np < 16) {
                SvVec n{0, 0, 0};
                set(n, ax, sgn);
                pl[np++] = {n, sgn * off};
            }
        }
        // Silhouette edges: 12 box edges, each between two faces (axes a != b) along axis c.
        Plane sil[12];
        int ns = 0;
        for (int c = 0; c < 3; ++c) {
            const int a = (c + 1) % 3, b = (c + 2) % 3;
            for (int sa = 0; sa < 2; ++sa)
                for (int sb = 0; sb < 2; ++sb) {
                    if (facing[2 * a + sa] == facing[2 * b + sb]) continue;
                    SvVec p0 = bmin, p1;
                    set(p0, a, sa ? get(bmax, a) : get(bmin, a));
                    set(p0, b, sb ? get(bmax, b) : get(bmin, b));
                    p1 = p0;
                    set(p0, c, get(bmin, c));
                    set(p1, c, get(bmax, c));
                    const SvVec e = p1 - p0;
                    SvVec n = point ? cross(e, L - p0) : cross(e, L);
                    const double nl = std::sqrt(len2(n));
                    if (!(nl > 0.0) || len2(e) == 0.0) continue;
                    n = n * (1.0 / nl);
                    double d = dot(n, p0);
                    if (dot(n, bc) > d) { n = n * -1.0; d = -d; }
                    // keep only if every box corner is inside (guards against rounding)
                    bool ok = true;
                    for (int k = 0; k < 8 && ok; ++k) {
                        const SvVec q{(k & 1) ? bmax.x : bmin.x, (k & 2) ? bmax.y : bmin.y, (k & 4) ? bmax.z : bmin.z};
                        ok = dot(n, q) <= d + 1e-12 * scale;
                    }
                    if (ok) sil[ns++] = {n, d};
                }
        }
        for (int s = 0; s < ns && np < 16; ++s) pl[np++] = sil[s];
    }
    // Vertex enumeration: all plane triples, keep points satisfying every half-space.
    const double tol = 1e-9 * scale;
    bool any = false;
    double xmin = std::numeric_limits<double>::infinity(), xmax = -xmin, ymin = xmin, ymax = -xmin, zmin = xmin, zmax = -xmin;
    for (int i = 0; i < np; ++i)
        for (int j = i + 1; j < np; ++j)
            for (int k = j + 1; k < np; ++k) {
                const SvVec a = pl[i].n, b = pl[j].n, c = pl[k].n;
                const SvVec bxc = cross(b, c);
                const double det = dot(a, bxc);
                if (std::fabs(det) < 1e-12) continue;
                const SvVec X = (bxc * pl[i].d + cross(c, a) * pl[j].d + cross(a, b) * pl[k].d) * (1.0 / det);
                if (!(std::isfinite(X.x) && std::isfinite(X.y) && std::isfinite(X.z))) continue;
                bool in = true;
                for (int q = 0; q < np && in; ++q) in = dot(pl[q].n, X) <= pl[q].d + tol;
                if (!in) continue;
                const glm::dvec4 clip = M * glm::dvec4(X.x, X.y, X.z, 1.0);
                if (!(clip.w > 0.0)) continue; // on/behind the eye plane: only possible within tol
                any = true;
                const double nx = clip.x / clip.w, ny = clip.y / clip.w, nz = clip.z / clip.w;
                xmin = std::fmin(xmin, nx); xmax = std::fmax(xmax, nx);
                ymin = std::fmin(ymin, ny); ymax = std::fmax(ymax, ny);
                zmin = std::fmin(zmin, nz); zmax = std::fmax(zmax, nz);
            }
    if (!any) { res.visible = false; res.width = res.height = 0; return res; }
    auto clampd = [](double v, double lo, double hi) { return v < lo ? lo : (v > hi ? hi : v); };
    const double px0 = vp[0] + (clampd(xmin, -1.0, 1.0) + 1.0) * 0.5 * vp[2];
    const double px1 = vp[0] + (clampd(xmax, -1.0, 1.0) + 1.0) * 0.5 * vp[2];
    const double py0 = vp[1] + (clampd(ymin, -1.0, 1.0) + 1.0) * 0.5 * vp[3];
    const double py1 = vp[1] + (clampd(ymax, -1.0, 1.0) + 1.0) * 0.5 * vp[3];
    if (xmin > 1.0 || xmax < -1.0 || ymin > 1.0 || ymax < -1.0) { res.visible = false; return res; }
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
    const double w0 = gl ? 0.5 * zmin + 0.5 : zmin, w1 = gl ? 0.5 * zmax + 0.5 : zmax;
    float dmin = static_cast<float>(clampd(w0, 0.0, 1.0)), dmax = static_cast<float>(clampd(w1, 0.0, 1.0));
    dmin = std::nextafter(dmin, -1.0f);
    dmax = std::nextafter(dmax, 2.0f);
    res.depth_min = dmin < 0.0f ? 0.0f : dmin;
    res.depth_max = dmax > 1.0f ? 1.0f : dmax;
    res.visible = true;
    return res;
}

} // namespace shadowkit
