// shadowkit/light_frustum.hpp - fit a light's view volume to what the camera needs, cull casters.
// "Leave out what the scene does not need": the light volume is fitted to the camera frustum slice
// (optionally clipped to the receivers' view-depth range from a depth reduction) intersected with
// the scene bounds, and casters are kept only if they can throw a shadow into that volume.
//
// Usage:
//   shadowkit::LightFrustumInput in;
//   in.camera_view = view; in.camera_proj = proj;          // GLM, right-handed, column-major
//   in.camera_depth = shadowkit::ClipDepth::NegativeOneToOne;
//   in.max_distance = 500.0f;                             // needed when proj has an infinite far plane
//   in.light = glm::vec4(sun_dir, 0.0f);                  // w = 0: direction the light travels
//   in.casters = boxes; in.caster_count = n;              // 6 floats per box: min xyz, max xyz
//   in.stable = true; in.shadow_map_size = 2048;          // texel-snapped, rotation-invariant fit
//   std::vector<uint32_t> keep(n);
//   shadowkit::LightFrustumResult r = shadowkit::fit_light_frustum(in, keep.data(), keep.size());
//   if (r.status == shadowkit::LightFrustumStatus::Ok) { render keep[0 .. r.kept_count) with r.view_proj; }
//
// Based on:
//   Stamminger & Drettakis 2002, "Perspective Shadow Maps" (sec. 3.2: the volume H = convex hull of
//     the light and the view frustum, intersected with the scene bounds).
//   Brabec, Annen & Seidel 2002, "Practical Shadow Mapping" (fitting the light frustum).
//   Zhang et al. 2006/2009, "Parallel-Split Shadow Maps" and Valient 2008 / Dimitrov 2007 "Cascaded
//     Shadow Maps" (stable fit: bounding sphere, rounded radius, origin snapped to whole texels).
//   Moschig, "Apelles" thesis, sec. 3.5 (light view volume culling: near/far from a depth min/max).
//
// MIT License. Copyright (c) shadowkit contributors.
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

namespace shadowkit {

#ifndef SHADOWKIT_CLIP_DEPTH_DEFINED
#define SHADOWKIT_CLIP_DEPTH_DEFINED
/// Depth range of normalized device coordinates: OpenGL [-1,1] or D3D/Vulkan/GL-clip-control [0,1].
enum class ClipDepth { NegativeOneToOne, ZeroToOne };
#endif

enum class LightFrustumStatus {
    Ok,
    InvalidInput,        ///< NaN/Inf in a matrix, the light or the bounds; singular projection/view
    InfiniteFar,         ///< projection has an infinite far plane and max_distance <= 0
    EmptyReceivers,      ///< the clipped camera slice does not meet the scene bounds (nothing to shadow)
    LightInsideVolume,   ///< point light inside (or too close around) the receiver volume: use a cube map
    BufferTooSmall       ///< matrices valid; kept_count > capacity, only `capacity` indices written
};

/// Inputs. Zero/default values mean "not used" where stated. Units: world units unless noted.
struct LightFrustumInput {
    glm::mat4 camera_view{1.0f};                  ///< world -> camera view (right-handed, looks down -z)
    glm::mat4 camera_proj{1.0f};                  ///< camera projection (perspective or ortho; may be infinite)
    ClipDepth camera_depth = ClipDepth::NegativeOneToOne;
    bool camera_reversed_z = false;
    /// [Units: wu, view depth] [Limit: >= 0] Far clamp. 0: use the projection's far plane (must be finite).
    float max_distance = 0.0f;
    /// [Units: wu, view depth] Visible receivers' depth range from a reduction; used when max > min > 0.
    float receiver_min_depth = 0.0f;
    float receiver_max_depth = 0.0f;
    /// Scene bounds (all receivers and casters); used when has_scene_bounds.
    bool has_scene_bounds = false;
    glm::vec3 scene_min{0.0f};
    glm::vec3 scene_max{0.0f};
    /// w == 0: directional, xyz = direction the light travels. w != 0: point/spot light at xyz / w.
    glm::vec4 light{0.0f, -1.0f, 0.0f, 0.0f};
    /// Caster boxes, 6 floats each (min x,y,z, max x,y,z); optional.
    const float* casters = nullptr;
    std::size_t caster_count = 0;
    /// Caster spheres, 4 floats each (center x,y,z, radius); indices continue after the boxes.
    const float* caster_spheres = nullptr;
    std::size_t caster_sphere_count = 0;
    /// Depth convention of the matrix built for the light.
    ClipDepth light_depth = ClipDepth::NegativeOneToOne;
    bool light_reversed_z = false;
    /// Directional lights only: bounding-sphere fit, radius rounded up to radius_quantum, projected
    /// world origin snapped to whole texels of a shadow_map_size^2 map (one texel of border kept).
    bool stable = false;
    std::uint32_t shadow_map_size = 2048;         ///< [Limit: >= 4] texels per side (stable mode)
    float radius_quantum = 1.0f / 16.0f;          ///< [Units: wu] [Limit: > 0] stable radius step
    /// Point lights: near plane never closer than point_min_near_ratio * far.
    float point_min_near_ratio = 1e-4f;
};

struct LightFrustumResult {
    LightFrustumStatus status = LightFrustumStatus::InvalidInput;
    glm::mat4 view{1.0f};                ///< world -> light view
    glm::mat4 proj{1.0f};                ///< light projection (ortho for directional, perspective for point)
    glm::mat4 view_proj{1.0f};           ///< proj * view
    float near_plane = 0.0f;             ///< light-view distances of the fitted near/far planes
    float far_plane = 0.0f;
    std::size_t kept_count = 0;          ///< casters that may shadow the receivers (indices written)
    std::size_t culled_count = 0;        ///< casters proven unable to shadow the receivers
    std::size_t invalid_count = 0;       ///< casters with NaN/Inf or min > max (culled, counted here)
    float texel_world_size = 0.0f;       ///< stable mode: world size of one texel
    glm::vec4 bounding_sphere{0.0f};     ///< stable mode: (center, rounded radius) of the slice
};

/// Convex volume as at most 64 inward-facing planes (n . x + d >= 0 inside).
struct LightFrustumPlanes {
    glm::dvec4 planes[64];
    int count = 0;
};

namespace lf_detail {

inline bool finite(double v) { return std::isfinite(v); }
inline bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
inline bool finite(const glm::vec4& v) { return finite(glm::vec3(v)) && std::isfinite(v.w); }
inline bool finite(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c)
        if (!finite(m[c])) return false;
    return true;
}
inline bool finite(const glm::dmat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}

/// NDC depth of the near and far planes for a convention.
inline void ndc_near_far(ClipDepth cd, bool reversed, double& zn, double& zf) {
    const double lo = (cd == ClipDepth::ZeroToOne) ? 0.0 : -1.0;
    zn = reversed ? 1.0 : lo;
    zf = reversed ? lo : 1.0;
}

/// Maps OpenGL clip z to the requested convention (applied on the left of a GL-style projection).
inline glm::dmat4 depth_convention(ClipDepth cd, bool reversed) {
    glm::dmat4 m(1.0);
    if (cd == ClipDepth::ZeroToOne) {
        // z' = 0.5 z + 0.5 w (reversed: z' = w - z')
        m[2][2] = reversed ? -0.5 : 0.5;
        m[3][2] = 0.5;
    } else if (reversed) {
        m[2][2] = -1.0;
    }
    return m;
}

/// Camera slice corners in view space. Corner i: bit0 = +x, bit1 = +y, bit2 = far layer.
/// Depths are positive distances along the view direction. Returns a LightFrustumStatus.
inline LightFrustumStatus slice_corners_view(const glm::mat4& proj, ClipDepth cd, bool reversed,
                                             double max_distance, double rmin, double rmax,
                                             glm::dvec3 out[8], double& d0_out, double& d1_out) {
    const glm::dmat4 P(proj);
    if (!finite(P) || !finite(max_distance) || !finite(rmin) || !finite(rmax)) return LightFrustumStatus::InvalidInput;
    const double det = glm::determinant(P);
    if (!std::isfinite(det) || std::fabs(det) < 1e-300) return LightFrustumStatus::InvalidInput;
    const glm::dmat4 inv = glm::inverse(P);
    if (!finite(inv)) return LightFrustumStatus::InvalidInput;
    double zn = 0, zf = 0;
    ndc_near_far(cd, reversed, zn, zf);
    glm::dvec3 pn[4], dir[4];
    double dn[4], dfar[4];
    bool infinite = false;
    for (int i = 0; i < 4; ++i) {
        const double x = (i & 1) ? 1.0 : -1.0, y = (i & 2) ? 1.0 : -1.0;
        const glm::dvec4 hn = inv * glm::dvec4(x, y, zn, 1.0);
        const glm::dvec4 hf = inv * glm::dvec4(x, y, zf, 1.0);
        const double sn = std::fabs(hn.x) + std::fabs(hn.y) + std::fabs(hn.z);
        if (!(std::fabs(hn.w) > 1e-12 * sn) || std::fabs(hn.w) < 1e-300) return LightFrustumStatus::InvalidInput;
        pn[i] = glm::dvec3(hn) / hn.w;
        const double sf = std::fabs(hf.x) + std::fabs(hf.y) + std::fabs(hf.z);
        if (std::fabs(hf.w) > 1e-9 * sf && std::fabs(hf.w) > 1e-300) {
            const glm::dvec3 pf = glm::dvec3(hf) / hf.w;
            dir[i] = pf - pn[i];
            dfar[i] = -pf.z;
        } else {
            dir[i] = glm::dvec3(hf);
            if (dir[i].z > 0.0) dir[i] = -dir[i];
            dfar[i] = std::numeric_limits<double>::infinity();
            infinite = true;
        }
        dn[i] = -pn[i].z;
        if (!(dir[i].z < 0.0) || !finite(dn[i])) return LightFrustumStatus::InvalidInput;
    }
    double nearest = dn[0], farthest = dfar[0];
    for (int i = 1; i < 4; ++i) {
        nearest = std::fmax(nearest, dn[i]);
        farthest = std::fmin(farthest, dfar[i]);
    }
    if (max_distance > 0.0) farthest = std::fmin(farthest, max_distance);
    else if (infinite) return LightFrustumStatus::InfiniteFar;
    double d0 = nearest, d1 = farthest;
    if (rmax > rmin && rmin > 0.0) {
        d0 = std::fmax(d0, rmin);
        d1 = std::fmin(d1, rmax);
    }
    if (!(d1 > d0) || !finite(d1 - d0)) return LightFrustumStatus::EmptyReceivers;
    for (int i = 0; i < 4; ++i) {
        const double t0 = (d0 - dn[i]) / -dir[i].z, t1 = (d1 - dn[i]) / -dir[i].z;
        out[i] = pn[i] + t0 * dir[i];
        out[i + 4] = pn[i] + t1 * dir[i];
    }
    d0_out = d0;
    d1_out = d1;
    return LightFrustumStatus::Ok;
}

inline glm::dvec4 plane_from(const glm::dvec3& n_in, const glm::dvec3& p) {
    const double l = glm::length(n_in);
    const glm::dvec3 n = n_in / l;
    return glm::dvec4(n, -glm::dot(n, p));
}

/// Six inward planes of a hexahedron given by corners in the slice_corners_view order.
inline void hexahedron_planes(const glm::dvec3 c[8], glm::dvec4 out[6]) {
    constexpr int faces[6][4] = {{0, 1, 3, 2}, {4, 5, 7, 6}, {0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 3, 7, 6}};
    glm::dvec3 centroid(0.0);
    for (int i = 0; i < 8; ++i) centroid += c[i];
    centroid /= 8.0;
    for (int f = 0; f < 6; ++f) {
        const glm::dvec3 a = c[faces[f][0]], b = c[faces[f][1]], cc = c[faces[f][2]], d = c[faces[f][3]];
        glm::dvec3 n = glm::cross(cc - a, d - b);  // diagonals: robust for (near-)degenerate quads
        if (glm::dot(n, n) == 0.0) n = glm::cross(b - a, d - a);
        if (glm::dot(n, n) == 0.0) n = glm::dvec3(0.0, 0.0, 1.0);
        const glm::dvec3 p = (a + b + cc + d) * 0.25;
        glm::dvec4 pl = plane_from(n, p);
        if (glm::dot(glm::dvec3(pl), centroid) + pl.w < 0.0) pl = -pl;
        out[f] = pl;
    }
}

inline void box_planes(const glm::dvec3& mn, const glm::dvec3& mx, glm::dvec4 out[6]) {
    out[0] = glm::dvec4(1, 0, 0, -mn.x);
    out[1] = glm::dvec4(-1, 0, 0, mx.x);
    out[2] = glm::dvec4(0, 1, 0, -mn.y);
    out[3] = glm::dvec4(0, -1, 0, mx.y);
    out[4] = glm::dvec4(0, 0, 1, -mn.z);
    out[5] = glm::dvec4(0, 0, -1, mx.z);
}

/// Vertices of the intersection of up to 16 half-spaces, by solving every plane triple.
inline int intersect_vertices(const glm::dvec4* planes, int np, double scale, glm::dvec3* out, int cap) {
    int n = 0;
    const double tol = 1e-9 * scale;
    for (int i = 0; i < np; ++i)
        for (int j = i + 1; j < np; ++j)
            for (int k = j + 1; k < np; ++k) {
                const glm::dvec3 a(planes[i]), b(planes[j]), c(planes[k]);
                const glm::dvec3 bc = glm::cross(b, c);
                const double det = glm::dot(a, bc);
                if (std::fabs(det) < 1e-12) continue;
                const glm::dvec3 p = (-planes[i].w * bc - planes[j].w * glm::cross(c, a) - planes[k].w * glm::cross(a, b)) / det;
                if (!finite(p.x) || !finite(p.y) || !finite(p.z)) continue;
                bool inside = true;
                for (int m = 0; m < np && inside; ++m) inside = glm::dot(glm::dvec3(planes[m]), p) + planes[m].w >= -tol;
                if (!inside) continue;
                bool dup = false;
                for (int m = 0; m < n && !dup; ++m) dup = glm::length(out[m] - p) <= tol;
                if (!dup && n < cap) out[n++] = p;
            }
    return n;
}

inline glm::dvec3 any_perpendicular_up(const glm::dvec3& d) {
    // the world axis least aligned with d: fixed per light direction (stable under camera motion)
    const glm::dvec3 ax = glm::abs(d);
    if (ax.y <= ax.x && ax.y <= ax.z) return glm::dvec3(0, 1, 0);
    if (ax.z <= ax.x) return glm::dvec3(0, 0, 1);
    return glm::dvec3(1, 0, 0);
}

/// Right-handed look-at in double precision: forward f (unit), up hint u (not parallel to f).
inline glm::dmat4 look_dir(const glm::dvec3& eye, const glm::dvec3& f, const glm::dvec3& up) {
    const glm::dvec3 s = glm::normalize(glm::cross(f, up));
    const glm::dvec3 u = glm::cross(s, f);
    glm::dmat4 m(1.0);
    m[0][0] = s.x; m[1][0] = s.y; m[2][0] = s.z;
    m[0][1] = u.x; m[1][1] = u.y; m[2][1] = u.z;
    m[0][2] = -f.x; m[1][2] = -f.y; m[2][2] = -f.z;
    m[3][0] = -glm::dot(s, eye);
    m[3][1] = -glm::dot(u, eye);
    m[3][2] = glm::dot(f, eye);
    return m;
}

inline glm::dmat4 ortho(double l, double r, double b, double t, double n, double f) {
    glm::dmat4 m(1.0);
    m[0][0] = 2.0 / (r - l);
    m[1][1] = 2.0 / (t - b);
    m[2][2] = -2.0 / (f - n);
    m[3][0] = -(r + l) / (r - l);
    m[3][1] = -(t + b) / (t - b);
    m[3][2] = -(f + n) / (f - n);
    return m;
}

inline glm::dmat4 frustum(double l, double r, double b, double t, double n, double f) {
    glm::dmat4 m(0.0);
    m[0][0] = 2.0 * n / (r - l);
    m[1][1] = 2.0 * n / (t - b);
    m[2][0] = (r + l) / (r - l);
    m[2][1] = (t + b) / (t - b);
    m[2][2] = -(f + n) / (f - n);
    m[2][3] = -1.0;
    m[3][2] = -2.0 * f * n / (f - n);
    return m;
}

inline bool valid_box(const float* b) {
    for (int i = 0; i < 6; ++i)
        if (!std::isfinite(b[i])) return false;
    return b[0] <= b[3] && b[1] <= b[4] && b[2] <= b[5];
}
inline bool valid_sphere(const float* s) {
    for (int i = 0; i < 4; ++i)
        if (!std::isfinite(s[i])) return false;
    return s[3] >= 0.0f;
}

}  // namespace lf_detail

/// World-space corners of the camera frustum between view depths [max(near, depth_min),
/// min(far, max_distance, depth_max)]. Corner i: bit0 = +x, bit1 = +y, bit2 = far layer.
/// depth_min/depth_max are used only when depth_max > depth_min > 0. Handles GL/zero-to-one depth,
/// reversed-Z and infinite far planes (then max_distance > 0 is required).
inline LightFrustumStatus camera_slice_corners(const glm::mat4& view, const glm::mat4& proj, ClipDepth depth,
                                               bool reversed_z, float max_distance, float depth_min,
                                               float depth_max, glm::vec3 out_corners[8]) {
    if (!lf_detail::finite(view)) return LightFrustumStatus::InvalidInput;
    glm::dvec3 c[8];
    double d0 = 0, d1 = 0;
    const LightFrustumStatus st = lf_detail::slice_corners_view(proj, depth, reversed_z, max_distance, depth_min,
                                                                depth_max, c, d0, d1);
    if (st != LightFrustumStatus::Ok) return st;
    const glm::dmat4 V(view);
    if (std::fabs(glm::determinant(V)) < 1e-300) return LightFrustumStatus::InvalidInput;
    const glm::dmat4 iv = glm::inverse(V);
    for (int i = 0; i < 8; ++i) {
        out_corners[i] = glm::vec3(glm::dvec3(iv * glm::dvec4(c[i], 1.0)));
        if (!lf_detail::finite(out_corners[i])) return LightFrustumStatus::InvalidInput;  // float overflow
    }
    return LightFrustumStatus::Ok;
}

/// Plane set of the receiver volume extruded towards the light (convex hull of the volume and the
/// light position, or the volume swept along -direction for a directional light). receiver_vertices:
/// the receiver volume's vertices; receiver_planes: its inward planes (n . x + d >= 0 inside), any
/// superset of its facets. A box or sphere outside one of the output planes cannot shadow the volume.
inline LightFrustumPlanes extruded_volume_planes(const glm::dvec3* receiver_vertices, int vertex_count,
                                                 const glm::dvec4* receiver_planes, int plane_count,
                                                 const glm::dvec4& light) {
    LightFrustumPlanes out;
    if (vertex_count <= 0) return out;
    const bool directional = light.w == 0.0;
    const glm::dvec3 L = directional ? glm::dvec3(0.0) : glm::dvec3(light) / light.w;
    const glm::dvec3 toward = directional ? -glm::normalize(glm::dvec3(light)) : glm::dvec3(0.0);
    double scale = 1.0;
    for (int i = 0; i < vertex_count; ++i) scale = std::fmax(scale, glm::length(receiver_vertices[i]));
    if (!directional) scale = std::fmax(scale, glm::length(L));
    const double tol = 1e-9 * scale;
    // (a) the volume's own planes that do not face the light (the sweep does not cross them)
    for (int i = 0; i < plane_count && out.count < 64; ++i) {
        const glm::dvec4 p = receiver_planes[i];
        const double facing = directional ? glm::dot(glm::dvec3(p), toward) : glm::dot(glm::dvec3(p), L) + p.w;
        if (facing >= -tol) out.planes[out.count++] = p;  // light on the inner side: plane bounds the hull
    }
    // (b) silhouette planes: through an edge (pair of vertices) and the light, supporting all vertices
    for (int i = 0; i < vertex_count; ++i)
        for (int j = i + 1; j < vertex_count; ++j) {
            const glm::dvec3 e = receiver_vertices[j] - receiver_vertices[i];
            const glm::dvec3 w = directional ? toward : (L - receiver_vertices[i]);
            glm::dvec3 n = glm::cross(e, w);
            const double nl = glm::length(n);
            if (!(nl > 1e-12 * glm::length(e) * glm::length(w)) || nl == 0.0) continue;
            n /= nl;
            const double d = -glm::dot(n, receiver_vertices[i]);
            int pos = 0, neg = 0;
            for (int k = 0; k < vertex_count; ++k) {
                const double s = glm::dot(n, receiver_vertices[k]) + d;
                if (s > tol) ++pos;
                else if (s < -tol) ++neg;
            }
            if (pos > 0 && neg > 0) continue;
            glm::dvec4 pl(n, d);
            if (neg > 0) pl = -pl;
            if (pos == 0 && neg == 0) continue;  // all vertices coplanar with the light: no side
            bool dup = false;
            for (int k = 0; k < out.count && !dup; ++k)
                dup = glm::dot(glm::dvec3(out.planes[k]), glm::dvec3(pl)) > 1.0 - 1e-12 &&
                      std::fabs(out.planes[k].w - pl.w) <= tol;
            if (!dup && out.count < 64) out.planes[out.count++] = pl;
        }
    return out;
}

/// Conservative box test against a plane set: false only if the box is entirely outside one plane.
inline bool box_may_intersect(const LightFrustumPlanes& p, const glm::vec3& mn, const glm::vec3& mx, double tol = 0.0) {
    for (int i = 0; i < p.count; ++i) {
        const glm::dvec4 pl = p.planes[i];
        const glm::dvec3 v(pl.x >= 0 ? mx.x : mn.x, pl.y >= 0 ? mx.y : mn.y, pl.z >= 0 ? mx.z : mn.z);
        if (glm::dot(glm::dvec3(pl), v) + pl.w < -tol) return false;
    }
    return true;
}

/// Conservative sphere test against a plane set.
inline bool sphere_may_intersect(const LightFrustumPlanes& p, const glm::vec3& c, float r, double tol = 0.0) {
    for (int i = 0; i < p.count; ++i) {
        const glm::dvec4 pl = p.planes[i];
        if (glm::dot(glm::dvec3(pl), glm::dvec3(c)) + pl.w < -double(r) - tol) return false;
    }
    return true;
}

/// Fits the light's view/projection to the receiver volume (camera slice, clipped to the receiver
/// depth range and the scene bounds) and the casters that can shadow it; writes the indices of kept
/// casters (boxes first, then spheres numbered from caster_count) into kept_indices[0..capacity).
/// kept_count always reports the number needed; status BufferTooSmall if it exceeds capacity.
inline LightFrustumResult fit_light_frustum(const LightFrustumInput& in, std::uint32_t* kept_indices,
                                            std::size_t capacity) {
    using namespace lf_detail;
    LightFrustumResult res;
    if (!finite(in.camera_view) || !finite(in.camera_proj) || !finite(in.light) || !std::isfinite(in.max_distance) ||
        !std::isfinite(in.receiver_min_depth) || !std::isfinite(in.receiver_max_depth) ||
        !std::isfinite(in.radius_quantum) || !std::isfinite(in.point_min_near_ratio))
        return res;
    if (in.has_scene_bounds && (!finite(in.scene_min) || !finite(in.scene_max) || in.scene_min.x > in.scene_max.x ||
                                in.scene_min.y > in.scene_max.y || in.scene_min.z > in.scene_max.z))
        return res;
    const bool directional = in.light.w == 0.0f;
    const glm::dvec3 lxyz(in.light);
    if (directional && !(glm::length(lxyz) > 0.0)) return res;
    if (in.stable && directional && (in.shadow_map_size < 4 || !(in.radius_quantum > 0.0f))) return res;
    const glm::dvec4 light = directional ? glm::dvec4(glm::normalize(lxyz), 0.0) : glm::dvec4(lxyz / double(in.light.w), 1.0);
    if (!directional && !finite(light.x + light.y + light.z)) return res;

    // --- receiver volume: camera slice (view space -> world), optionally clipped by the scene box
    glm::dvec3 cv[8];
    double d0 = 0, d1 = 0;
    res.status = slice_corners_view(in.camera_proj, in.camera_depth, in.camera_reversed_z, in.max_distance,
                                    in.receiver_min_depth, in.receiver_max_depth, cv, d0, d1);
    if (res.status != LightFrustumStatus::Ok) return res;
    res.status = LightFrustumStatus::InvalidInput;
    const glm::dmat4 V(in.camera_view);
    const double vdet = glm::determinant(V);
    if (!std::isfinite(vdet) || std::fabs(vdet) < 1e-300) return res;
    const glm::dmat4 iv = glm::inverse(V);
    glm::dvec3 cw[8];
    for (int i = 0; i < 8; ++i) cw[i] = glm::dvec3(iv * glm::dvec4(cv[i], 1.0));
    for (int i = 0; i < 8; ++i)
        if (!finite(cw[i].x + cw[i].y + cw[i].z)) return res;
    glm::dvec4 planes[12];
    hexahedron_planes(cw, planes);
    int np = 6;
    double scale = 1.0;
    for (int i = 0; i < 8; ++i) scale = std::fmax(scale, glm::length(cw[i]));
    if (in.has_scene_bounds) {
        box_planes(glm::dvec3(in.scene_min), glm::dvec3(in.scene_max), planes + 6);
        np = 12;
        scale = std::fmax(scale, std::fmax(glm::length(glm::dvec3(in.scene_min)), glm::length(glm::dvec3(in.scene_max))));
    }
    glm::dvec3 verts[64];
    int nv = 0;
    if (np == 6) {
        for (int i = 0; i < 8; ++i) verts[nv++] = cw[i];
    } else {
        nv = intersect_vertices(planes, np, scale, verts, 64);
        if (nv == 0) {
            res.status = LightFrustumStatus::EmptyReceivers;
            res.culled_count = in.caster_count + in.caster_sphere_count;
            return res;
        }
    }

    // --- caster culling against the receiver volume extruded towards the light
    const LightFrustumPlanes hull = extruded_volume_planes(verts, nv, planes, np, light);
    const double ctol = 1e-7 * scale;
    std::size_t kept = 0;
    const std::size_t nb = in.casters ? in.caster_count : 0, ns = in.caster_spheres ? in.caster_sphere_count : 0;
    for (std::size_t i = 0; i < nb; ++i) {
        const float* b = in.casters + 6 * i;
        if (!valid_box(b)) { ++res.invalid_count; ++res.culled_count; continue; }
        if (box_may_intersect(hull, glm::vec3(b[0], b[1], b[2]), glm::vec3(b[3], b[4], b[5]), ctol)) {
            if (kept < capacity && kept_indices) kept_indices[kept] = static_cast<std::uint32_t>(i);
            ++kept;
        } else {
            ++res.culled_count;
        }
    }
    for (std::size_t i = 0; i < ns; ++i) {
        const float* s = in.caster_spheres + 4 * i;
        if (!valid_sphere(s)) { ++res.invalid_count; ++res.culled_count; continue; }
        if (sphere_may_intersect(hull, glm::vec3(s[0], s[1], s[2]), s[3], ctol)) {
            if (kept < capacity && kept_indices) kept_indices[kept] = static_cast<std::uint32_t>(nb + i);
            ++kept;
        } else {
            ++res.culled_count;
        }
    }
    res.kept_count = kept;

    // depth (along the light's view axis) of the nearest kept caster / the scene bounds
    auto caster_min_depth = [&](const glm::dmat4& lv) {
        double m = std::numeric_limits<double>::infinity();
        auto box_depth = [&](const glm::dvec3& mn, const glm::dvec3& mx) {
            for (int c = 0; c < 8; ++c) {
                const glm::dvec3 p((c & 1) ? mx.x : mn.x, (c & 2) ? mx.y : mn.y, (c & 4) ? mx.z : mn.z);
                m = std::fmin(m, -(lv * glm::dvec4(p, 1.0)).z);
            }
        };
        if (nb + ns > 0) {
            for (std::size_t i = 0; i < nb; ++i) {
                const float* b = in.casters + 6 * i;
                if (!valid_box(b) || !box_may_intersect(hull, glm::vec3(b[0], b[1], b[2]), glm::vec3(b[3], b[4], b[5]), ctol)) continue;
                box_depth(glm::dvec3(b[0], b[1], b[2]), glm::dvec3(b[3], b[4], b[5]));
            }
            for (std::size_t i = 0; i < ns; ++i) {
                const float* s = in.caster_spheres + 4 * i;
                if (!valid_sphere(s) || !sphere_may_intersect(hull, glm::vec3(s[0], s[1], s[2]), s[3], ctol)) continue;
                const glm::dvec3 c(s[0], s[1], s[2]);
                if (directional) m = std::fmin(m, -(lv * glm::dvec4(c, 1.0)).z - double(s[3]));
                else box_depth(c - double(s[3]), c + double(s[3]));
            }
        } else if (in.has_scene_bounds) {
            box_depth(glm::dvec3(in.scene_min), glm::dvec3(in.scene_max));
        }
        return m;
    };

    glm::dmat4 lview(1.0), lproj(1.0);
    double nearp = 0, farp = 0;
    if (directional) {
        const glm::dvec3 d(light);
        const glm::dvec3 up = any_perpendicular_up(d);
        if (in.stable) {
            // sphere of the slice computed in view space: bitwise invariant to camera rotation/translation
            const glm::dvec3 nc = (cv[0] + cv[1] + cv[2] + cv[3]) * 0.25, fc = (cv[4] + cv[5] + cv[6] + cv[7]) * 0.25;
            double a2 = 0, b2 = 0;
            for (int i = 0; i < 4; ++i) {
                a2 = std::fmax(a2, glm::dot(cv[i] - nc, cv[i] - nc));
                b2 = std::fmax(b2, glm::dot(cv[i + 4] - fc, cv[i + 4] - fc));
            }
            const double L2 = glm::dot(fc - nc, fc - nc);
            const double t = L2 > 0.0 ? glm::clamp(0.5 + (b2 - a2) / (2.0 * L2), 0.0, 1.0) : 0.5;
            const glm::dvec3 center_v = nc + t * (fc - nc);
            double r = 0.0;
            for (int i = 0; i < 8; ++i) r = std::fmax(r, glm::length(cv[i] - center_v));
            const double q = in.radius_quantum;
            r = std::ceil(r / q) * q;  // MJP/Valient: rounded radius -> constant texel size
            if (!(r > 0.0) || !finite(r)) return res;
            const double S = double(in.shadow_map_size);
            const double texel = 2.0 * r / (S - 2.0);  // one texel of border on each side
            const double half = r + texel;
            lview = look_dir(glm::dvec3(0.0), d, up);  // origin-anchored: the world origin is a texel corner
            const glm::dvec3 cl = glm::dvec3(lview * iv * glm::dvec4(center_v, 1.0));
            const double cx = std::floor(cl.x / texel) * texel, cy = std::floor(cl.y / texel) * texel;
            farp = -cl.z + r;
            nearp = std::fmin(-cl.z - r, caster_min_depth(lview));
            const double pad = 1e-6 * std::fmax(1.0, std::fabs(farp) + std::fabs(nearp));
            lproj = ortho(cx - half, cx + half, cy - half, cy + half, nearp - pad, farp + pad);
            nearp -= pad;
            farp += pad;
            res.texel_world_size = static_cast<float>(texel);
            res.bounding_sphere = glm::vec4(glm::vec3(glm::dvec3(iv * glm::dvec4(center_v, 1.0))), static_cast<float>(r));
        } else {
            glm::dvec3 c(0.0);
            for (int i = 0; i < nv; ++i) c += verts[i];
            c /= double(nv);
            lview = look_dir(c, d, up);
            glm::dvec3 mn(std::numeric_limits<double>::infinity()), mx(-std::numeric_limits<double>::infinity());
            for (int i = 0; i < nv; ++i) {
                const glm::dvec3 p = glm::dvec3(lview * glm::dvec4(verts[i], 1.0));
                mn = glm::min(mn, p);
                mx = glm::max(mx, p);
            }
            farp = -mn.z;
            nearp = std::fmin(-mx.z, caster_min_depth(lview));
            const double pad = 1e-6 * std::fmax(scale, 1e-30);
            lproj = ortho(mn.x - pad, mx.x + pad, mn.y - pad, mx.y + pad, nearp - pad, farp + pad);
            nearp -= pad;
            farp += pad;
        }
    } else {
        const glm::dvec3 L(light);
        glm::dvec3 c(0.0);
        for (int i = 0; i < nv; ++i) c += verts[i];
        c /= double(nv);
        const glm::dvec3 axis = c - L;
        const double al = glm::length(axis);
        res.status = LightFrustumStatus::LightInsideVolume;
        if (!(al > 1e-9 * scale)) return res;
        const glm::dvec3 f = axis / al;
        lview = look_dir(L, f, any_perpendicular_up(f));
        double xl = 1e300, xr = -1e300, yb = 1e300, yt = -1e300, dmin = 1e300, dmax = 0;
        for (int i = 0; i < nv; ++i) {
            const glm::dvec3 p = glm::dvec3(lview * glm::dvec4(verts[i], 1.0));
            const double dep = -p.z;
            const double lat = std::fmax(std::fabs(p.x), std::fabs(p.y));
            if (!(dep > 1e-9 * scale) || lat > 100.0 * dep) return res;  // > ~89.4 degrees off axis
            xl = std::fmin(xl, p.x / dep); xr = std::fmax(xr, p.x / dep);
            yb = std::fmin(yb, p.y / dep); yt = std::fmax(yt, p.y / dep);
            dmin = std::fmin(dmin, dep); dmax = std::fmax(dmax, dep);
        }
        farp = dmax * (1.0 + 1e-6);
        nearp = std::fmin(dmin, caster_min_depth(lview)) * (1.0 - 1e-6);
        nearp = std::fmax(nearp, farp * std::fmax(double(in.point_min_near_ratio), 1e-7));
        if (!(farp > nearp)) farp = nearp * 2.0;
        const double pad = 1e-6 * std::fmax(1.0, xr - xl + yt - yb);
        lproj = frustum((xl - pad) * nearp, (xr + pad) * nearp, (yb - pad) * nearp, (yt + pad) * nearp, nearp, farp);
    }
    lproj = depth_convention(in.light_depth, in.light_reversed_z) * lproj;
    const glm::dmat4 vp = lproj * lview;
    if (!finite(vp)) { res.status = LightFrustumStatus::InvalidInput; return res; }
    res.view = glm::mat4(lview);
    res.proj = glm::mat4(lproj);
    res.view_proj = glm::mat4(vp);
    res.near_plane = static_cast<float>(nearp);
    res.far_plane = static_cast<float>(farp);
    if (!finite(res.view_proj) || !finite(res.view) || !finite(res.proj) || !std::isfinite(res.near_plane) ||
        !std::isfinite(res.far_plane)) {
        res.status = LightFrustumStatus::InvalidInput;
        res.view = res.proj = res.view_proj = glm::mat4(1.0f);
        return res;
    }
    res.status = kept > capacity ? LightFrustumStatus::BufferTooSmall : LightFrustumStatus::Ok;
    return res;
}

}  // namespace shadowkit
