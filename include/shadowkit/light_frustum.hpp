// shadowkit/light_frustum.hpp - fit a light's view volume to what the camera needs, cull casters.
// "Leave out what the scene does not need": the light volume is fitted to the camera frustum slice
// (optionally clipped to the receivers' view-depth range from a depth reduction) intersected with
// the scene bounds, and casters are kept only if they can throw a shadow into that volume.
//
// Usage:
//   shadowkit::LightFrustumInput in;
//   in.camera_view = view; in.camera_proj = proj;          // GLM, right-handed, column-major (required)
//   in.camera_depth = shadowkit::ClipDepth::NegativeOneToOne;
//   in.max_distance = 500.0f;                             // required when proj has an infinite far plane
//   in.light_position = glm::vec4(to_sun, 0.0f);          // w = 0: direction *toward* the light (required)
//   in.casters = boxes; in.caster_count = n;              // 6 floats per box: min xyz, max xyz
//   in.stable = true; in.shadow_map_size = 2048;          // texel-snapped fit (directional lights)
//   in.stable_world_depth = true;                         // + scene bounds: depth fixed in the world (cached maps)
//   std::vector<std::uint32_t> keep(n);
//   shadowkit::LightFrustumResult r = shadowkit::light_frustum_fit(in, keep.data(), keep.size());
//   if (r.status == shadowkit::Status::Ok && r.visible) { render keep[0 .. r.count) with r.view_proj; }
//
// Conventions: world units; GLM right-handed, column-major matrices; camera view depth d = -z_view > 0.
// The camera projection may be any perspective or orthographic projection with its near plane in front
// of the eye (view depth > 0), in either ClipDepth, reversed-Z or not, with a finite far plane, a far
// plane at infinity, or the epsilon-tweaked infinite projection of infinite_projection.hpp (NDC depth
// +1 (reversed: -1 or 0) lies beyond infinity there); an infinite far plane needs max_distance > 0.
// Lights: a light is its homogeneous position `light_position` = (x, y, z, w), as OpenGL's
// GL_POSITION and Everitt & Kilgard use it. w > 0: a point or spot light at xyz / w. w = 0: a
// directional light at infinity in direction xyz, the direction *toward* the light (its rays travel
// along -xyz). w < 0, (0, 0, 0, 0) and NaN/Inf are rejected with Status::InvalidLight.
// Buffers: `kept_indices` holds `capacity` uint32 elements (caster indices); the result's `needed`
// says how many the whole output needs, `count` how many were written.
// Results: a non-Ok result's `detail` names the offending input and the rule ("camera_proj: near plane
// at or behind the eye"), a static string; nullptr when Ok.
// Map orientation (the roll about the light axis): the tight fits put the camera's view direction,
// projected onto the light's image plane, along the map's +y (continuous in the light direction except
// within a fraction of a degree of the light parallel or anti-parallel to the view, where the map
// rolls about the light axis; exactly parallel: the camera's up vector is +y). The stable fit cannot
// follow the camera (it must not rotate with it): its roll is a fixed function of the light direction,
// the shortest-arc rotation of the frame of a light shining straight down (-y: map x = world +x, map
// y = world -z), continuous for every light direction except one shining straight up (+y travel,
// light_position (0, -1, 0, 0)), around which it spins.
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

#include <cmath>
#include <cstddef>
#include <cstdint>
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

/// Inputs of light_frustum_fit. Fields marked (required) default to a value the fit rejects.
struct LightFrustumInput {
    glm::mat4 camera_view = glm::mat4(0.0f);      ///< world -> camera view, looks down -z (required)
    glm::mat4 camera_proj = glm::mat4(0.0f);      ///< camera projection, near plane in front of the eye (required)
    ClipDepth camera_depth = ClipDepth::NegativeOneToOne;
    bool camera_reversed_z = false;
    /// [Units: wu, view depth] [Limit: >= 0] Far clamp of the shadowed range; 0: the projection's far
    /// plane (then it must be finite). Smaller than the near plane: nothing visible.
    float max_distance = 0.0f;
    /// [Units: wu, view depth] Visible receivers' depth range from a reduction. Both 0: not used;
    /// otherwise 0 < receiver_min_depth <= receiver_max_depth.
    float receiver_min_depth = 0.0f;
    float receiver_max_depth = 0.0f;
    /// Scene bounds (every receiver and caster); used when has_scene_bounds. [Limit: min <= max]
    bool has_scene_bounds = false;
    glm::vec3 scene_min{0.0f};
    glm::vec3 scene_max{0.0f};
    /// The light, see "Lights:" above (required: the default (0, 0, 0, 0) gives Status::InvalidLight).
    glm::vec4 light_position{0.0f};
    /// Caster boxes, 6 floats each (min x,y,z, max x,y,z): `casters` holds 6 * caster_count floats;
    /// nullptr only with caster_count 0. A box with NaN/Inf or min > max is culled and counted as invalid.
    const float* casters = nullptr;
    std::size_t caster_count = 0;
    /// Caster spheres, 4 floats each (center x,y,z, radius >= 0): `caster_spheres` holds
    /// 4 * caster_sphere_count floats; nullptr only with a zero count. Indices continue after the boxes.
    const float* caster_spheres = nullptr;
    std::size_t caster_sphere_count = 0;
    /// Depth convention of the matrix built for the light.
    ClipDepth light_depth = ClipDepth::NegativeOneToOne;
    bool light_reversed_z = false;
    /// Texel-snapped fit, directional lights only (a point light gives Status::InvalidLight): the map's
    /// orientation is fixed per light direction and its origin snapped to whole texels of a
    /// shadow_map_size^2 map (one texel of border kept), so camera rotation leaves the map's texel
    /// grid in place and camera translation moves it by whole texels. The window is a square of side
    /// W = min(2 r, E) (+ one texel each side), texel_world_size = W / (shadow_map_size - 2), with r the
    /// slice's bounding-sphere radius rounded up to radius_quantum (camera-invariant) and, when
    /// has_scene_bounds, E the larger side of the scene box's light-space rectangle (camera-invariant):
    /// a small scene gets the texels of its own size. The window is centered on the sphere's center,
    /// moved the least that makes it cover the bounded receivers.
    bool stable = false;
    /// Stable mode: the depth range (near and far planes) from the scene bounds and every valid
    /// caster instead of the receivers the camera sees, so it is fixed in the world. A camera move then
    /// changes the map by a whole-texel translation in x/y only, which a cached map can scroll
    /// (shadow_cache.hpp); with the default range every camera move shifts the depth planes too
    /// (shadow_cache_plan: DepthMoved, the whole map re-rendered) and the stored depths change with
    /// the camera. Costs depth precision: the range spans the whole scene along the light. Needs
    /// has_scene_bounds (else InvalidArgument); ignored without `stable`.
    bool stable_world_depth = false;
    std::uint32_t shadow_map_size = 2048;         ///< [Limit: >= 4] texels per side (stable mode)
    float radius_quantum = 1.0f / 16.0f;          ///< [Units: wu] [Limit: > 0] stable radius step
    /// Point lights: near plane never closer than point_min_near_ratio * far. [Limit: (0, 1)]
    float point_min_near_ratio = 1e-4f;
};

/// Result of light_frustum_fit.
struct LightFrustumResult {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    bool visible = false;                ///< false (with Ok): the receiver volume is empty; skip the shadow pass
    /// world -> light view. Its eye is in front of every receiver and kept caster (near_z > 0):
    /// -(view * p).z is a positive distance along the light (directional: the eye sits 1% of the
    /// depth range before the near plane), as smoothie.glsl and other linear-depth lookups need.
    glm::mat4 view{1.0f};
    glm::mat4 proj{1.0f};                ///< light projection (ortho for directional, perspective for point)
    glm::mat4 view_proj{1.0f};           ///< proj * view; every receiver point maps into its clip volume
    float near_z = 0.0f;                 ///< [Units: wu] light-view distances of the fitted near/far planes (0 < near_z < far_z)
    float far_z = 0.0f;
    std::size_t count = 0;               ///< caster indices written to kept_indices (<= capacity)
    std::size_t needed = 0;              ///< casters that may shadow the receivers (indices the output needs)
    std::size_t culled_count = 0;        ///< casters proven unable to shadow the receivers (needed + culled = all)
    std::size_t invalid_count = 0;       ///< casters with NaN/Inf or min > max / radius < 0 (culled, counted here)
    float texel_world_size = 0.0f;       ///< stable mode: world size of one texel (W / (shadow_map_size - 2))
    glm::vec4 bounding_sphere{0.0f};     ///< stable mode: (center, rounded radius) of the camera slice
    /// Stable mode: where the map's texel (0, 0) begins on the light's texel grid, which is anchored at
    /// the world origin: window x of a point = (light-view x) / texel - texel_anchor.x (likewise y), so
    /// the world origin lies at window (-texel_anchor.x, -texel_anchor.y). Whole numbers for an even
    /// shadow_map_size (half-integers for an odd one); a camera translation changes them by whole
    /// numbers, the texels the map moved by. What a cached map's scroll offset and the
    /// translation-invariant caster pass of glsl/shadow_cache.glsl (its anchor) need, exact in double.
    glm::dvec2 texel_anchor{0.0};
};

/// World-space corners of the camera slice, see light_frustum_slice_corners.
struct LightFrustumCorners {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    bool visible = false;                ///< false (with Ok): the depth range is empty (corners not written)
    glm::vec3 corners[8] = {};           ///< corner i: bit0 = +x, bit1 = +y, bit2 = far layer
    float near_depth = 0.0f;             ///< view depths of the near and far layers
    float far_depth = 0.0f;
};

/// Convex volume as at most 64 inward-facing planes (n . x + d >= 0 inside).
struct LightFrustumPlanes {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    int count = 0;                       ///< planes in use
    glm::dvec4 planes[64];
};

namespace detail {

inline bool lf_finite(double v) { return std::isfinite(v); }
inline bool lf_finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
inline bool lf_finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
inline bool lf_finite(const glm::vec4& v) { return lf_finite(glm::vec3(v)) && std::isfinite(v.w); }
inline bool lf_finite(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c)
        if (!lf_finite(m[c])) return false;
    return true;
}
inline bool lf_finite(const glm::dmat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}

/// Maps OpenGL clip z to the requested convention (applied on the left of a GL-style projection).
inline glm::dmat4 lf_depth_convention(ClipDepth cd, bool reversed) {
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

/// The camera's four corner rays in view space: the point on the near plane, a direction away from
/// the eye, the near depth and the far depth of each (+inf for a far plane at infinity).
// Sets `why` (where a non-Ok status came from, a static string) and returns s.
inline Status lf_fail(const char*& why, Status s, const char* what) {
    why = what;
    return s;
}

struct LfRays {
    glm::dvec3 pn[4], dir[4];
    double dn[4] = {0, 0, 0, 0};
    double near_depth = 0.0, far_depth = 0.0;
};

/// Un-projects the corner rays of a projection: the ray through NDC depths zn (near) and
/// zn + (zf - zn) / 64 (finite for every projection, the epsilon-tweaked P_inf with epsilon <= 0.5
/// included). The far plane is found from NDC depth zf: a point there that lies beyond the second
/// point on the ray is a finite far plane; w = 0 or a point behind the eye (the epsilon-tweaked P_inf
/// puts zf beyond infinity) is a far plane at infinity.
inline Status lf_camera_rays(const glm::mat4& proj, ClipDepth cd, bool reversed, LfRays& r, const char*& why) {
    const glm::dmat4 P(proj);
    if (!lf_finite(P)) return lf_fail(why, Status::NonFinite, "camera_proj: NaN or Inf");
    const double det = glm::determinant(P);
    if (!std::isfinite(det) || !(std::fabs(det) > 1e-300)) return lf_fail(why, Status::InvalidArgument, "camera_proj: singular");
    const glm::dmat4 inv = glm::inverse(P);
    if (!lf_finite(inv)) return lf_fail(why, Status::InvalidArgument, "camera_proj: inverse not finite");
    const double lo = (cd == ClipDepth::ZeroToOne) ? 0.0 : -1.0;
    const double zn = reversed ? 1.0 : lo, zf = reversed ? lo : 1.0, zm = zn + (zf - zn) / 64.0;
    r.near_depth = -std::numeric_limits<double>::infinity();
    r.far_depth = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 4; ++i) {
        const double x = (i & 1) ? 1.0 : -1.0, y = (i & 2) ? 1.0 : -1.0;
        const glm::dvec4 hn = inv * glm::dvec4(x, y, zn, 1.0);
        const glm::dvec4 hm = inv * glm::dvec4(x, y, zm, 1.0);
        const glm::dvec4 hf = inv * glm::dvec4(x, y, zf, 1.0);
        const double sn = std::fabs(hn.x) + std::fabs(hn.y) + std::fabs(hn.z);
        const double sm = std::fabs(hm.x) + std::fabs(hm.y) + std::fabs(hm.z);
        if (!(std::fabs(hn.w) > 1e-12 * sn) || !(std::fabs(hn.w) > 1e-300))
            return lf_fail(why, Status::InvalidArgument, "camera_proj: near plane at infinity");
        if (!(std::fabs(hm.w) > 1e-12 * sm) || !(std::fabs(hm.w) > 1e-300))
            return lf_fail(why, Status::InvalidArgument, "camera_proj: near-side depth at infinity");
        r.pn[i] = glm::dvec3(hn) / hn.w;
        const glm::dvec3 pm = glm::dvec3(hm) / hm.w;
        r.dir[i] = pm - r.pn[i];
        r.dn[i] = -r.pn[i].z;
        // near plane in front of the eye, rays going away from it
        if (!(r.dn[i] > 0.0) || !(r.dir[i].z < 0.0) || !lf_finite(r.pn[i]) || !lf_finite(r.dir[i]))
            return lf_fail(why, Status::InvalidArgument, "camera_proj: near plane at or behind the eye");
        const double sf = std::fabs(hf.x) + std::fabs(hf.y) + std::fabs(hf.z);
        double dfar = std::numeric_limits<double>::infinity();
        if (std::fabs(hf.w) > 1e-9 * sf && std::fabs(hf.w) > 1e-300) {
            const glm::dvec3 pf = glm::dvec3(hf) / hf.w;
            const double t = glm::dot(pf - r.pn[i], r.dir[i]) / glm::dot(r.dir[i], r.dir[i]);
            if (t > 1.0 && std::isfinite(pf.z)) dfar = -pf.z;  // else: beyond infinity (epsilon-tweaked)
        }
        r.near_depth = std::fmax(r.near_depth, r.dn[i]);
        r.far_depth = std::fmin(r.far_depth, dfar);
    }
    if (!(r.far_depth > r.near_depth)) return lf_fail(why, Status::InvalidArgument, "camera_proj: far plane not beyond near");
    return Status::Ok;
}

inline glm::dvec3 lf_ray_at(const LfRays& r, int i, double depth) {
    return r.pn[i] + ((depth - r.dn[i]) / -r.dir[i].z) * r.dir[i];
}

/// Camera slice corners in view space (corner i: bit0 = +x, bit1 = +y, bit2 = far layer), between
/// depths d0 = max(near, rmin) and d1 = min(far, max_distance, rmax). visible = false: empty range.
inline Status lf_slice_view(const LightFrustumInput& in, glm::dvec3 out[8], double& d0, double& d1, bool& visible,
                           const char*& why) {
    visible = false;
    if (!std::isfinite(in.max_distance) || !std::isfinite(in.receiver_min_depth) ||
        !std::isfinite(in.receiver_max_depth))
        return lf_fail(why, Status::NonFinite, !std::isfinite(in.max_distance) ? "max_distance: NaN or Inf"
                                               : "receiver_min_depth, receiver_max_depth: NaN or Inf");
    if (in.max_distance < 0.0f) return lf_fail(why, Status::InvalidArgument, "max_distance: < 0");
    const bool use_range = !(in.receiver_min_depth == 0.0f && in.receiver_max_depth == 0.0f);
    if (use_range && !(in.receiver_min_depth > 0.0f && in.receiver_min_depth <= in.receiver_max_depth))
        return lf_fail(why, Status::InvalidArgument, "receiver_min_depth: not in (0, receiver_max_depth]");
    LfRays r;
    const Status st = lf_camera_rays(in.camera_proj, in.camera_depth, in.camera_reversed_z, r, why);
    if (st != Status::Ok) return st;
    double f = r.far_depth;
    if (in.max_distance > 0.0f) f = std::fmin(f, double(in.max_distance));
    else if (std::isinf(f)) return lf_fail(why, Status::InvalidArgument, "max_distance: 0 with an infinite far plane");
    d0 = r.near_depth;
    d1 = f;
    if (use_range) {
        d0 = std::fmax(d0, double(in.receiver_min_depth));
        d1 = std::fmin(d1, double(in.receiver_max_depth));
    }
    if (!(d1 > d0)) return Status::Ok;  // nothing between the planes: not visible
    for (int i = 0; i < 4; ++i) {
        out[i] = lf_ray_at(r, i, d0);
        out[i + 4] = lf_ray_at(r, i, d1);
        if (!lf_finite(out[i]) || !lf_finite(out[i + 4])) return lf_fail(why, Status::Overflow, "camera_proj: a slice corner beyond range");
    }
    visible = true;
    return Status::Ok;
}

inline glm::dvec4 lf_plane_from(const glm::dvec3& n_in, const glm::dvec3& p) {
    const double l = glm::length(n_in);
    const glm::dvec3 n = n_in / l;
    return glm::dvec4(n, -glm::dot(n, p));
}

/// Six inward planes of a hexahedron given by corners in the lf_slice_view order.
inline void lf_hexahedron_planes(const glm::dvec3 c[8], glm::dvec4 out[6]) {
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
        glm::dvec4 pl = lf_plane_from(n, p);
        if (glm::dot(glm::dvec3(pl), centroid) + pl.w < 0.0) pl = -pl;
        out[f] = pl;
    }
}

inline void lf_box_planes(const glm::dvec3& mn, const glm::dvec3& mx, glm::dvec4 out[6]) {
    out[0] = glm::dvec4(1, 0, 0, -mn.x);
    out[1] = glm::dvec4(-1, 0, 0, mx.x);
    out[2] = glm::dvec4(0, 1, 0, -mn.y);
    out[3] = glm::dvec4(0, -1, 0, mx.y);
    out[4] = glm::dvec4(0, 0, 1, -mn.z);
    out[5] = glm::dvec4(0, 0, -1, mx.z);
}

/// Vertices of the intersection of up to 16 half-spaces, by solving every plane triple.
inline int lf_intersect_vertices(const glm::dvec4* planes, int np, double scale, glm::dvec3* out, int cap) {
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
                if (!lf_finite(p)) continue;
                bool inside = true;
                for (int m = 0; m < np && inside; ++m) inside = glm::dot(glm::dvec3(planes[m]), p) + planes[m].w >= -tol;
                if (!inside) continue;
                bool dup = false;
                for (int m = 0; m < n && !dup; ++m) dup = glm::length(out[m] - p) <= tol;
                if (!dup && n < cap) out[n++] = p;
            }
    return n;
}

/// Right-handed look-at in double precision: forward f (unit), up hint u (not parallel to f). The
/// image +y is the part of `up` perpendicular to f.
inline glm::dmat4 lf_look_dir(const glm::dvec3& eye, const glm::dvec3& f, const glm::dvec3& up) {
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

/// Up hint of the stable fit, a function of the light's travel direction f (unit) alone: the
/// shortest-arc rotation taking (0, -1, 0) to f applied to the up vector (0, 0, -1) of a light
/// shining straight down. Continuous except at f = (0, 1, 0) (a light shining straight up).
inline glm::dvec3 lf_stable_up(const glm::dvec3& f) {
    const glm::dvec3 a(0.0, -1.0, 0.0), u0(0.0, 0.0, -1.0);
    const double c1 = 1.0 + glm::dot(a, f);
    if (!(c1 > 1e-12)) return glm::dvec3(0.0, 0.0, 1.0);  // f = +y: the rotation by pi about x
    const glm::dvec3 c = glm::cross(a, f);  // R v = v + c x v + c x (c x v) / (1 + a.f)
    const glm::dvec3 cu = glm::cross(c, u0);
    return u0 + cu + glm::cross(c, cu) / c1;
}

/// Up hint of the tight fits: the camera's view direction `v` projected off the light axis f; near
/// parallel (|v x f| < 1e-9) the camera's up vector `cam_up`; if that fails too, the stable hint.
inline glm::dvec3 lf_view_up(const glm::dvec3& f, const glm::dvec3& v, const glm::dvec3& cam_up) {
    const glm::dvec3 h = v - glm::dot(v, f) * f;
    if (glm::length(h) > 1e-9) return h;
    const glm::dvec3 h2 = cam_up - glm::dot(cam_up, f) * f;
    if (glm::length(h2) > 1e-9) return h2;
    return lf_stable_up(f);
}

#ifndef SHADOWKIT_CONE_AXIS_DEFINED
#define SHADOWKIT_CONE_AXIS_DEFINED
// Shared by light_frustum.hpp and perspective_shadow_maps.hpp, identical in both (hygiene.shared_enums).
/// Nearest point to the origin of the simplex s[0 .. k) (k <= 4): the minimum over its faces of
/// each face's affine nearest point with non-negative barycentric weights (a face's affine solution
/// with a negative weight is not in the simplex; the true minimum lies in some face's relative
/// interior). Keeps in s / k only the points with positive weight. Returns the point.
inline glm::dvec3 cone_simplex_nearest(glm::dvec3 s[4], int& k) {
    glm::dvec3 best(0.0);
    double best2 = std::numeric_limits<double>::infinity();
    int best_mask = 0;
    for (int mask = 1; mask < (1 << k); ++mask) {
        int idx[4], m = 0;
        for (int i = 0; i < k; ++i)
            if (mask & (1 << i)) idx[m++] = i;
        double lambda[4] = {1.0, 0.0, 0.0, 0.0};
        if (m > 1) {
            // p = s0 + sum mu_j (s_j - s0), j = 1 .. m-1: (D^T D) mu = -D^T s0
            const glm::dvec3 s0 = s[idx[0]];
            glm::dvec3 d[3];
            for (int j = 1; j < m; ++j) d[j - 1] = s[idx[j]] - s0;
            const int q = m - 1;
            glm::dmat3 G(1.0);
            glm::dvec3 rhs(0.0);
            for (int a = 0; a < q; ++a) {
                rhs[a] = -glm::dot(d[a], s0);
                for (int b = 0; b < q; ++b) G[b][a] = glm::dot(d[a], d[b]);
            }
            const double det = glm::determinant(G);
            double scale = 1.0;
            for (int a = 0; a < q; ++a) scale *= std::fmax(G[a][a], 1e-300);
            if (!(std::fabs(det) > 1e-12 * scale)) continue;  // a degenerate face: its sub-faces cover it
            const glm::dvec3 mu = glm::inverse(G) * rhs;
            double sum = 0.0;
            for (int j = 0; j < q; ++j) {
                lambda[j + 1] = mu[j];
                sum += mu[j];
            }
            lambda[0] = 1.0 - sum;
        }
        bool inside = true;
        glm::dvec3 p(0.0);
        for (int j = 0; j < m; ++j) {
            inside = inside && lambda[j] >= 0.0;
            p += lambda[j] * s[idx[j]];
        }
        if (!inside) continue;
        const double p2 = glm::dot(p, p);
        if (p2 < best2) {
            best2 = p2;
            best = p;
            best_mask = mask;
        }
    }
    int m = 0;
    for (int i = 0; i < k; ++i)
        if (best_mask & (1 << i)) s[m++] = s[i];
    k = m;
    return best;
}

/// Axis of the narrowest cone around the apex L that holds the points v[0 .. n) (a point light's fit
/// in light_frustum.hpp and perspective_shadow_maps.hpp). With u_i the unit directions from L to the
/// points, that axis maximizes min_i u_i . a, and (duality) it is the direction of the point of the
/// convex hull of the u_i nearest to the origin, found here by Gilbert-Johnson-Keerthi iterations
/// (support point argmin_i u_i . p). That point is unique, so the axis moves continuously with the
/// points (a mean of the points does not: it jumps when a vertex of a clipped volume splits). Zero
/// vector: the origin is in the hull (no cone of half-angle < 90 degrees exists) or a point is at L.
inline glm::dvec3 cone_axis(const glm::dvec3* v, int n, const glm::dvec3& L) {
    if (n <= 0) return glm::dvec3(0.0);
    auto dir = [&](int i) {
        const glm::dvec3 r = v[i] - L;
        const double l = glm::length(r);
        return (l > 0.0 && std::isfinite(l)) ? r / l : glm::dvec3(0.0);
    };
    for (int i = 0; i < n; ++i)
        if (!(glm::length(dir(i)) > 0.0)) return glm::dvec3(0.0);
    glm::dvec3 s[4] = {dir(0), glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0)};
    int k = 1;
    glm::dvec3 p = s[0];
    for (int it = 0; it < 64; ++it) {
        const double p2 = glm::dot(p, p);
        if (!(p2 > 1e-24)) return glm::dvec3(0.0);  // the origin is in the hull
        int w = 0;
        double wd = std::numeric_limits<double>::infinity();
        for (int i = 0; i < n; ++i) {
            const double d = glm::dot(dir(i), p);
            if (d < wd) { wd = d; w = i; }
        }
        if (p2 - wd <= 1e-12 * p2) break;  // no point of the hull is nearer along -p: p is the nearest
        bool present = false;
        for (int j = 0; j < k; ++j) present = present || glm::length(s[j] - dir(w)) == 0.0;
        if (present || k == 4) break;  // no progress possible (rounding)
        s[k++] = dir(w);
        p = cone_simplex_nearest(s, k);
    }
    if (!(glm::dot(p, p) > 1e-24) || !(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))) return glm::dvec3(0.0);
    return glm::normalize(p);
}
#endif  // SHADOWKIT_CONE_AXIS_DEFINED

/// A directional light's view is free to slide along the light's axis. Moves it back so the near
/// plane lies 1% of the depth range in front of the eye (no move when it already does, so the eye
/// moves continuously): every receiver and kept caster then has a positive light depth
/// -(view * p).z, which smoothie.glsl, linear-depth maps and pcss_fit_near_plane read as a distance
/// from the light. A move along the view axis leaves the x and y rows of view_proj (the texel grid)
/// as they were.
inline void lf_eye_behind(glm::dmat4& lview, double& nearp, double& farp) {
    const double margin = 0.01 * (farp - nearp);
    if (!(nearp < margin)) return;
    const double back = margin - nearp;
    lview[3][2] -= back;  // the eye moves back by `back`: every depth grows by it
    nearp += back;
    farp += back;
}

/// The light-view depth range (-z) of a box's 8 corners: (min, max).
inline glm::dvec2 lf_box_light_depths(const glm::dmat4& lview, const glm::dvec3& mn, const glm::dvec3& mx) {
    glm::dvec2 r(std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity());
    for (int c = 0; c < 8; ++c) {
        const double z = -(lview * glm::dvec4((c & 1) ? mx.x : mn.x, (c & 2) ? mx.y : mn.y, (c & 4) ? mx.z : mn.z, 1.0)).z;
        r = glm::dvec2(std::fmin(r.x, z), std::fmax(r.y, z));
    }
    return r;
}

inline glm::dmat4 lf_ortho(double l, double r, double b, double t, double n, double f) {
    glm::dmat4 m(1.0);
    m[0][0] = 2.0 / (r - l);
    m[1][1] = 2.0 / (t - b);
    m[2][2] = -2.0 / (f - n);
    m[3][0] = -(r + l) / (r - l);
    m[3][1] = -(t + b) / (t - b);
    m[3][2] = -(f + n) / (f - n);
    return m;
}

inline glm::dmat4 lf_frustum(double l, double r, double b, double t, double n, double f) {
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

inline bool lf_valid_box(const float* b) {
    for (int i = 0; i < 6; ++i)
        if (!std::isfinite(b[i])) return false;
    return b[0] <= b[3] && b[1] <= b[4] && b[2] <= b[5];
}
inline bool lf_valid_sphere(const float* s) {
    for (int i = 0; i < 4; ++i)
        if (!std::isfinite(s[i])) return false;
    return s[3] >= 0.0f;
}

/// Validates a light position: Ok, or InvalidLight for NaN/Inf, w < 0 and (0, 0, 0, 0).
inline Status lf_check_light(const glm::vec4& l, const char*& why) {
    if (!lf_finite(l)) return lf_fail(why, Status::InvalidLight, "light_position: NaN or Inf");
    if (l.w < 0.0f) return lf_fail(why, Status::InvalidLight, "light_position: w < 0");
    if (l.w == 0.0f && l.x == 0.0f && l.y == 0.0f && l.z == 0.0f) return lf_fail(why, Status::InvalidLight, "light_position: (0, 0, 0, 0)");
    return Status::Ok;
}

/// Plane set of the receiver volume extruded towards the light; `toward` is the unit direction
/// toward a directional light, `pos` the position of a point light.
inline LightFrustumPlanes lf_extruded_planes(const glm::dvec3* receiver_vertices, int vertex_count,
                                             const glm::dvec4* receiver_planes, int plane_count, bool directional,
                                             const glm::dvec3& toward, const glm::dvec3& pos) {
    LightFrustumPlanes out;
    out.status = Status::Ok;
    if (vertex_count <= 0) return out;
    const glm::dvec3 L = pos;
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
            int npos = 0, nneg = 0;
            for (int k = 0; k < vertex_count; ++k) {
                const double s = glm::dot(n, receiver_vertices[k]) + d;
                if (s > tol) ++npos;
                else if (s < -tol) ++nneg;
            }
            if (npos > 0 && nneg > 0) continue;
            glm::dvec4 pl(n, d);
            if (nneg > 0) pl = -pl;
            if (npos == 0 && nneg == 0) continue;  // all vertices coplanar with the light: no side
            bool dup = false;
            for (int k = 0; k < out.count && !dup; ++k)
                dup = glm::dot(glm::dvec3(out.planes[k]), glm::dvec3(pl)) > 1.0 - 1e-12 &&
                      std::fabs(out.planes[k].w - pl.w) <= tol;
            if (!dup && out.count < 64) out.planes[out.count++] = pl;
        }
    return out;
}

inline bool lf_box_may_intersect(const LightFrustumPlanes& p, const glm::vec3& mn, const glm::vec3& mx, double tol) {
    for (int i = 0; i < p.count && i < 64; ++i) {
        const glm::dvec4 pl = p.planes[i];
        const glm::dvec3 v(pl.x >= 0 ? mx.x : mn.x, pl.y >= 0 ? mx.y : mn.y, pl.z >= 0 ? mx.z : mn.z);
        if (glm::dot(glm::dvec3(pl), v) + pl.w < -tol) return false;
    }
    return true;
}

inline bool lf_sphere_may_intersect(const LightFrustumPlanes& p, const glm::vec3& c, float r, double tol) {
    for (int i = 0; i < p.count && i < 64; ++i) {
        const glm::dvec4 pl = p.planes[i];
        if (glm::dot(glm::dvec3(pl), glm::dvec3(c)) + pl.w < -double(r) - tol) return false;
    }
    return true;
}

/// Does the float matrix put every point within `tol` of its clip volume (w > 0)? The check that
/// float precision (huge coordinates against a small fitted extent) has not broken the fit.
inline bool lf_maps_inside(const glm::mat4& m, const glm::dvec3* pts, int n, ClipDepth cd, double tol) {
    const double zlo = cd == ClipDepth::ZeroToOne ? 0.0 : -1.0;
    for (int i = 0; i < n; ++i) {
        const glm::vec4 hf = m * glm::vec4(glm::vec3(pts[i]), 1.0f);
        const glm::dvec4 h(hf);
        if (!(h.w > 0.0) || !std::isfinite(h.x + h.y + h.z + h.w)) return false;
        const double x = h.x / h.w, y = h.y / h.w, z = h.z / h.w;
        if (!(std::fabs(x) <= 1.0 + tol) || !(std::fabs(y) <= 1.0 + tol) || !(z >= zlo - tol) || !(z <= 1.0 + tol))
            return false;
    }
    return true;
}

// Step 1 of light_frustum_fit: the arguments. Ok or the status to return.
inline Status lf_fit_check_inputs(const LightFrustumInput& in, const std::uint32_t* kept_indices, std::size_t capacity,
                                  const char*& why) {
    if (!in.casters && in.caster_count > 0) return lf_fail(why, Status::InvalidArgument, "casters: null with caster_count > 0");
    if (!in.caster_spheres && in.caster_sphere_count > 0)
        return lf_fail(why, Status::InvalidArgument, "caster_spheres: null with caster_sphere_count > 0");
    if (!kept_indices && capacity > 0) return lf_fail(why, Status::InvalidArgument, "kept_indices: null with capacity > 0");
    constexpr std::size_t kMaxCasters = 0xFFFFFFFFu;  // indices are uint32
    if (in.caster_count > kMaxCasters || in.caster_sphere_count > kMaxCasters - in.caster_count)
        return lf_fail(why, Status::InvalidArgument, "caster_count + caster_sphere_count: beyond uint32 indices");
    if (!lf_finite(in.camera_view)) return lf_fail(why, Status::NonFinite, "camera_view: NaN or Inf");
    if (!lf_finite(in.camera_proj)) return lf_fail(why, Status::NonFinite, "camera_proj: NaN or Inf");
    const Status ls = lf_check_light(in.light_position, why);
    if (ls != Status::Ok) return ls;
    if (in.has_scene_bounds) {
        if (!lf_finite(in.scene_min) || !lf_finite(in.scene_max))
            return lf_fail(why, Status::NonFinite, "scene_min, scene_max: NaN or Inf");
        if (in.scene_min.x > in.scene_max.x || in.scene_min.y > in.scene_max.y || in.scene_min.z > in.scene_max.z)
            return lf_fail(why, Status::InvalidArgument, "scene_min: > scene_max");
    }
    if (!std::isfinite(in.radius_quantum)) return lf_fail(why, Status::NonFinite, "radius_quantum: NaN or Inf");
    if (!std::isfinite(in.point_min_near_ratio)) return lf_fail(why, Status::NonFinite, "point_min_near_ratio: NaN or Inf");
    if (in.shadow_map_size < 4) return lf_fail(why, Status::InvalidArgument, "shadow_map_size: < 4");
    if (!(in.radius_quantum > 0.0f)) return lf_fail(why, Status::InvalidArgument, "radius_quantum: not > 0");
    if (!(in.point_min_near_ratio > 0.0f) || !(in.point_min_near_ratio < 1.0f))
        return lf_fail(why, Status::InvalidArgument, "point_min_near_ratio: outside (0, 1)");
    const bool directional = in.light_position.w == 0.0f;
    if (in.stable && !directional)  // stable fit: directional lights only
        return lf_fail(why, Status::InvalidLight, "light_position: a point light with stable = true");
    if (in.stable && in.stable_world_depth && !in.has_scene_bounds)
        return lf_fail(why, Status::InvalidArgument, "stable_world_depth: without has_scene_bounds");
    return Status::Ok;
}

// The receiver volume of light_frustum_fit: the camera slice (view and world space), clipped by the
// scene box when there is one, as planes and vertices.
struct LfReceivers {
    glm::dmat4 iv;           // camera view -> world
    glm::dvec3 cv[8], cw[8]; // slice corners in view and world space
    glm::dvec3 cam_fwd, cam_up;
    glm::dvec4 planes[12];
    int np = 6;
    double scale = 1.0;
    glm::dvec3 verts[64];
    int nv = 0;
};

// Step 2 of light_frustum_fit: the receiver volume. Ok with visible = false when it is empty.
inline Status lf_receiver_volume(const LightFrustumInput& in, LfReceivers& R, bool& visible, const char*& why) {
    double d0 = 0, d1 = 0;
    visible = false;
    const Status ss = lf_slice_view(in, R.cv, d0, d1, visible, why);
    if (ss != Status::Ok || !visible) return ss;
    for (int i = 0; i < 8; ++i) {
        R.cw[i] = glm::dvec3(R.iv * glm::dvec4(R.cv[i], 1.0));
        if (!lf_finite(R.cw[i])) return lf_fail(why, Status::Overflow, "camera_view: a slice corner beyond range");
    }
    // camera axes in world space (for the tight fits' orientation)
    R.cam_fwd = glm::dvec3(R.iv * glm::dvec4(0.0, 0.0, -1.0, 0.0));
    R.cam_up = glm::dvec3(R.iv * glm::dvec4(0.0, 1.0, 0.0, 0.0));
    R.cam_fwd = glm::length(R.cam_fwd) > 0.0 ? glm::normalize(R.cam_fwd) : glm::dvec3(0.0);
    R.cam_up = glm::length(R.cam_up) > 0.0 ? glm::normalize(R.cam_up) : glm::dvec3(0.0);
    lf_hexahedron_planes(R.cw, R.planes);
    R.np = 6;
    R.scale = 1.0;
    for (int i = 0; i < 8; ++i) R.scale = std::fmax(R.scale, glm::length(R.cw[i]));
    if (in.has_scene_bounds) {
        lf_box_planes(glm::dvec3(in.scene_min), glm::dvec3(in.scene_max), R.planes + 6);
        R.np = 12;
        R.scale = std::fmax(R.scale, std::fmax(glm::length(glm::dvec3(in.scene_min)), glm::length(glm::dvec3(in.scene_max))));
    }
    R.nv = 0;
    if (R.np == 6) {
        for (int i = 0; i < 8; ++i) R.verts[R.nv++] = R.cw[i];
    } else {
        R.nv = lf_intersect_vertices(R.planes, R.np, R.scale, R.verts, 64);
        if (R.nv == 0) visible = false;
    }
    return Status::Ok;
}

// The casters against the receiver volume extruded towards the light (`hull`).
struct LfCasterCull {
    const LightFrustumInput& in;
    LightFrustumPlanes hull;
    double ctol;
    bool directional;

    bool box_kept(std::size_t i) const {
        const float* b = in.casters + 6 * i;
        return lf_box_may_intersect(hull, glm::vec3(b[0], b[1], b[2]), glm::vec3(b[3], b[4], b[5]), ctol);
    }
    bool sphere_kept(std::size_t i) const {
        const float* s = in.caster_spheres + 4 * i;
        return lf_sphere_may_intersect(hull, glm::vec3(s[0], s[1], s[2]), s[3], ctol);
    }
    // depth (along the light's view axis) of the nearest kept caster / the scene bounds
    double min_depth(const glm::dmat4& lv) const {
        const std::size_t nb = in.caster_count, ns = in.caster_sphere_count;
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
                if (!lf_valid_box(b) || !box_kept(i)) continue;
                box_depth(glm::dvec3(b[0], b[1], b[2]), glm::dvec3(b[3], b[4], b[5]));
            }
            for (std::size_t i = 0; i < ns; ++i) {
                const float* s = in.caster_spheres + 4 * i;
                if (!lf_valid_sphere(s) || !sphere_kept(i)) continue;
                const glm::dvec3 c(s[0], s[1], s[2]);
                if (directional) m = std::fmin(m, -(lv * glm::dvec4(c, 1.0)).z - double(s[3]));
                else box_depth(c - double(s[3]), c + double(s[3]));
            }
        } else if (in.has_scene_bounds) {
            box_depth(glm::dvec3(in.scene_min), glm::dvec3(in.scene_max));
        }
        return m;
    }
};

// Step 3 of light_frustum_fit: cull the casters, write the kept indices (up to capacity), count the
// culled and invalid ones in res. Returns the number kept.
inline std::size_t lf_cull_casters(const LfCasterCull& cull, std::uint32_t* kept_indices, std::size_t capacity,
                                   LightFrustumResult& res) {
    const LightFrustumInput& in = cull.in;
    const std::size_t nb = in.caster_count, ns = in.caster_sphere_count;
    std::size_t kept = 0;
    for (std::size_t i = 0; i < nb; ++i) {
        if (!lf_valid_box(in.casters + 6 * i)) { ++res.invalid_count; ++res.culled_count; continue; }
        if (cull.box_kept(i)) {
            if (kept < capacity) kept_indices[kept] = static_cast<std::uint32_t>(i);
            ++kept;
        } else {
            ++res.culled_count;
        }
    }
    for (std::size_t i = 0; i < ns; ++i) {
        if (!lf_valid_sphere(in.caster_spheres + 4 * i)) { ++res.invalid_count; ++res.culled_count; continue; }
        if (cull.sphere_kept(i)) {
            if (kept < capacity) kept_indices[kept] = static_cast<std::uint32_t>(nb + i);
            ++kept;
        } else {
            ++res.culled_count;
        }
    }
    return kept;
}

// The light's fitted view, projection (before the depth convention) and depth range.
struct LfLightFit {
    glm::dmat4 view{1.0}, proj{1.0};
    double nearp = 0, farp = 0;
};

// Light depth range [near, far] of the scene box and every valid caster (kept or not), none of which
// depends on the camera: the stable fit's world-fixed depth.
inline glm::dvec2 lf_world_depth_range(const LightFrustumInput& in, const glm::dmat4& lview) {
    glm::dvec2 zr = lf_box_light_depths(lview, glm::dvec3(in.scene_min), glm::dvec3(in.scene_max));
    for (std::size_t i = 0; i < in.caster_count; ++i) {
        const float* b = in.casters + 6 * i;
        if (!lf_valid_box(b)) continue;
        const glm::dvec2 z = lf_box_light_depths(lview, glm::dvec3(b[0], b[1], b[2]), glm::dvec3(b[3], b[4], b[5]));
        zr = glm::dvec2(std::fmin(zr.x, z.x), std::fmax(zr.y, z.y));
    }
    for (std::size_t i = 0; i < in.caster_sphere_count; ++i) {
        const float* sp = in.caster_spheres + 4 * i;
        if (!lf_valid_sphere(sp)) continue;
        const double z = -(lview * glm::dvec4(double(sp[0]), double(sp[1]), double(sp[2]), 1.0)).z;
        zr = glm::dvec2(std::fmin(zr.x, z - double(sp[3])), std::fmax(zr.y, z + double(sp[3])));
    }
    return zr;
}

// Step 4a of light_frustum_fit, directional stable: a sphere around the slice with a quantized
// radius, an origin-anchored light view and a window snapped to whole texels.
inline Status lf_fit_directional_stable(const LightFrustumInput& in, const LfReceivers& R, const LfCasterCull& cull,
                                        const glm::dvec3& d, LfLightFit& F, LightFrustumResult& res, const char*& why) {
    const glm::dvec3* cv = R.cv;
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
    if (!(r > 0.0) || !lf_finite(r)) return lf_fail(why, Status::Overflow, "radius_quantum: bounding radius not finite");
    const glm::dmat4 lview = lf_look_dir(glm::dvec3(0.0), d, lf_stable_up(d));  // origin-anchored, fixed per light
    const glm::dvec3 cl = glm::dvec3(lview * R.iv * glm::dvec4(center_v, 1.0));
    // window side W: the sphere's diameter, or the scene box's light-space extent if smaller
    double W = 2.0 * r;
    if (in.has_scene_bounds) {
        glm::dvec3 bmn(std::numeric_limits<double>::infinity()), bmx(-std::numeric_limits<double>::infinity());
        for (int c = 0; c < 8; ++c) {
            const glm::dvec3 p((c & 1) ? in.scene_max.x : in.scene_min.x, (c & 2) ? in.scene_max.y : in.scene_min.y,
                               (c & 4) ? in.scene_max.z : in.scene_min.z);
            const glm::dvec3 pl = glm::dvec3(lview * glm::dvec4(p, 1.0));
            bmn = glm::min(bmn, pl);
            bmx = glm::max(bmx, pl);
        }
        W = std::fmin(W, std::fmax(std::fmax(bmx.x - bmn.x, bmx.y - bmn.y), 2.0 * r * 1e-6));
    }
    // the receivers' light-space rectangle: the window must cover it (it does: W >= its extent)
    glm::dvec3 rmn(std::numeric_limits<double>::infinity()), rmx(-std::numeric_limits<double>::infinity());
    for (int i = 0; i < R.nv; ++i) {
        const glm::dvec3 p = glm::dvec3(lview * glm::dvec4(R.verts[i], 1.0));
        rmn = glm::min(rmn, p);
        rmx = glm::max(rmx, p);
    }
    // the sphere's center, moved the least that makes the window cover [lo, hi] (continuous
    // in the light direction and the camera)
    auto place = [&](double p, double lo, double hi) {
        const double a = hi - 0.5 * W, b = lo + 0.5 * W;  // centers whose window covers [lo, hi]
        return a <= b ? glm::clamp(p, a, b) : 0.5 * (a + b);
    };
    const double S = double(in.shadow_map_size);
    const double texel = W / (S - 2.0);  // one texel of border on each side
    const double half = 0.5 * W + texel;
    const double kx = std::floor(place(cl.x, rmn.x, rmx.x) / texel);  // the snap: whole texels
    const double ky = std::floor(place(cl.y, rmn.y, rmx.y) / texel);
    const double cx = kx * texel, cy = ky * texel;
    double nearp = 0, farp = 0;
    if (in.has_scene_bounds && in.stable_world_depth) {
        const glm::dvec2 zr = lf_world_depth_range(in, lview);
        nearp = zr.x;
        farp = zr.y;
    } else if (in.has_scene_bounds) {  // depth: the bounded receivers
        farp = -rmn.z;
        nearp = std::fmin(-rmx.z, cull.min_depth(lview));
    } else {
        farp = -cl.z + r;
        nearp = std::fmin(-cl.z - r, cull.min_depth(lview));
    }
    const double pad = 1e-6 * std::fmax(1.0, std::fabs(farp) + std::fabs(nearp));
    nearp -= pad;
    farp += pad;
    F.view = lview;
    lf_eye_behind(F.view, nearp, farp);
    F.proj = lf_ortho(cx - half, cx + half, cy - half, cy + half, nearp, farp);
    F.nearp = nearp;
    F.farp = farp;
    res.texel_world_size = static_cast<float>(texel);
    res.texel_anchor = glm::dvec2(kx - 0.5 * S, ky - 0.5 * S);  // (cx - half) / texel
    res.bounding_sphere = glm::vec4(glm::vec3(glm::dvec3(R.iv * glm::dvec4(center_v, 1.0))), static_cast<float>(r));
    if (!(res.texel_world_size > 0.0f) || !lf_finite(res.bounding_sphere))
        return lf_fail(why, Status::Overflow, "shadow_map_size: texel size or bounding sphere beyond float");
    return Status::Ok;
}

// Step 4b of light_frustum_fit, directional tight: the receiver volume's light-space box, the view
// oriented by the camera.
inline void lf_fit_directional_tight(const LfReceivers& R, const LfCasterCull& cull, const glm::dvec3& d, LfLightFit& F) {
    glm::dvec3 c(0.0);
    for (int i = 0; i < R.nv; ++i) c += R.verts[i];
    c /= double(R.nv);
    F.view = lf_look_dir(c, d, lf_view_up(d, R.cam_fwd, R.cam_up));
    glm::dvec3 mn(std::numeric_limits<double>::infinity()), mx(-std::numeric_limits<double>::infinity());
    for (int i = 0; i < R.nv; ++i) {
        const glm::dvec3 p = glm::dvec3(F.view * glm::dvec4(R.verts[i], 1.0));
        mn = glm::min(mn, p);
        mx = glm::max(mx, p);
    }
    F.farp = -mn.z;
    F.nearp = std::fmin(-mx.z, cull.min_depth(F.view));
    const double pad = 1e-6 * std::fmax(R.scale, 1e-30);
    F.nearp -= pad;
    F.farp += pad;
    lf_eye_behind(F.view, F.nearp, F.farp);
    F.proj = lf_ortho(mn.x - pad, mx.x + pad, mn.y - pad, mx.y + pad, F.nearp, F.farp);
}

// Step 4c of light_frustum_fit, point and spot lights: the narrowest cone around the light holding
// the receiver volume's vertices (a mean of the vertices put near receivers beyond 89.4 degrees for a
// light just above wide receivers) and the perspective window around them.
inline Status lf_fit_point(const LightFrustumInput& in, const LfReceivers& R, const LfCasterCull& cull,
                           const glm::dvec3& L, LfLightFit& F, const char*& why) {
    const glm::dvec3 f = cone_axis(R.verts, R.nv, L);
    if (!(glm::length(f) > 0.0))
        return lf_fail(why, Status::LightInsideVolume, "light_position: inside the receiver volume");
    F.view = lf_look_dir(L, f, lf_view_up(f, R.cam_fwd, R.cam_up));
    double xl = 1e300, xr = -1e300, yb = 1e300, yt = -1e300, dmin = 1e300, dmax = 0;
    for (int i = 0; i < R.nv; ++i) {
        const glm::dvec3 p = glm::dvec3(F.view * glm::dvec4(R.verts[i], 1.0));
        const double dep = -p.z;
        const double lat = std::fmax(std::fabs(p.x), std::fabs(p.y));
        if (!(dep > 1e-9 * R.scale) || lat > 100.0 * dep)  // > ~89.4 deg
            return lf_fail(why, Status::LightInsideVolume, "light_position: a receiver > 89.4 degrees off every axis");
        xl = std::fmin(xl, p.x / dep); xr = std::fmax(xr, p.x / dep);
        yb = std::fmin(yb, p.y / dep); yt = std::fmax(yt, p.y / dep);
        dmin = std::fmin(dmin, dep); dmax = std::fmax(dmax, dep);
    }
    double farp = dmax * (1.0 + 1e-6);
    double nearp = std::fmin(dmin, cull.min_depth(F.view)) * (1.0 - 1e-6);
    nearp = std::fmax(nearp, farp * double(in.point_min_near_ratio));
    if (!(farp > nearp)) farp = nearp * 2.0;
    const double pad = 1e-6 * std::fmax(1.0, xr - xl + yt - yb);
    F.proj = lf_frustum((xl - pad) * nearp, (xr + pad) * nearp, (yb - pad) * nearp, (yt + pad) * nearp, nearp, farp);
    F.nearp = nearp;
    F.farp = farp;
    return Status::Ok;
}

}  // namespace detail

/// World-space corners of the camera slice between view depths [max(near, receiver_min_depth),
/// min(far, max_distance, receiver_max_depth)], from the camera fields of `in` (camera_view,
/// camera_proj, camera_depth, camera_reversed_z, max_distance, receiver_min/max_depth; nothing else is
/// read). Corner i: bit0 = +x, bit1 = +y, bit2 = far layer. Status: NonFinite (NaN/Inf),
/// InvalidArgument (singular matrix, near plane at or behind the eye, infinite far plane with
/// max_distance 0, negative max_distance, bad receiver range), Overflow (a corner beyond float);
/// Ok with visible = false when the depth range is empty.
inline LightFrustumCorners light_frustum_slice_corners(const LightFrustumInput& in) {
    LightFrustumCorners res;
    if (!detail::lf_finite(in.camera_view)) { res.status = Status::NonFinite; res.detail = "camera_view: NaN or Inf"; return res; }
    glm::dvec3 c[8];
    double d0 = 0, d1 = 0;
    bool visible = false;
    res.status = detail::lf_slice_view(in, c, d0, d1, visible, res.detail);
    if (res.status != Status::Ok) return res;
    if (!visible) return res;
    const glm::dmat4 V(in.camera_view);
    const double det = glm::determinant(V);
    if (!std::isfinite(det) || !(std::fabs(det) > 1e-300)) {
        res.status = Status::InvalidArgument;
        res.detail = "camera_view: singular";
        return res;
    }
    const glm::dmat4 iv = glm::inverse(V);
    for (int i = 0; i < 8; ++i) {
        res.corners[i] = glm::vec3(glm::dvec3(iv * glm::dvec4(c[i], 1.0)));
        if (!detail::lf_finite(res.corners[i])) {
            res.status = Status::Overflow;  // float overflow
            res.detail = "corners: beyond float range";
            for (glm::vec3& k : res.corners) k = glm::vec3(0.0f);
            return res;
        }
    }
    res.near_depth = static_cast<float>(d0);
    res.far_depth = static_cast<float>(d1);
    if (!std::isfinite(res.near_depth) || !std::isfinite(res.far_depth)) {
        res.status = Status::Overflow;
        res.detail = "near_depth, far_depth: beyond float range";
        return res;
    }
    res.visible = true;
    return res;
}

/// Plane set of the receiver volume extruded towards the light (convex hull of the volume and the
/// light position, or the volume swept toward a directional light). receiver_vertices: the volume's
/// vertex_count vertices (nullptr only with 0); receiver_planes: its plane_count inward planes
/// (n . x + d >= 0 inside), any superset of its facets (nullptr only with 0). Counts [Limit: <= 64].
/// A box or sphere outside one of the output planes cannot shadow the volume. More than 64 planes are
/// dropped (conservative: fewer planes cull less). Status: InvalidArgument (null with a count, count
/// > 64), NonFinite (NaN/Inf in a vertex or plane), InvalidLight.
inline LightFrustumPlanes light_frustum_extruded_planes(const glm::dvec3* receiver_vertices, std::size_t vertex_count,
                                                        const glm::dvec4* receiver_planes, std::size_t plane_count,
                                                        const glm::vec4& light_position) {
    LightFrustumPlanes out;
    if ((!receiver_vertices && vertex_count > 0) || (!receiver_planes && plane_count > 0) || vertex_count > 64 ||
        plane_count > 64) {
        out.status = Status::InvalidArgument;
        out.detail = !receiver_vertices && vertex_count > 0 ? "receiver_vertices: null with vertex_count > 0"
                     : (!receiver_planes && plane_count > 0 ? "receiver_planes: null with plane_count > 0"
                     : (vertex_count > 64 ? "vertex_count: > 64" : "plane_count: > 64"));
        return out;
    }
    out.status = detail::lf_check_light(light_position, out.detail);
    if (out.status != Status::Ok) return out;
    for (std::size_t i = 0; i < vertex_count; ++i)
        if (!detail::lf_finite(receiver_vertices[i])) {
            out.status = Status::NonFinite;
            out.detail = "receiver_vertices: NaN or Inf";
            return out;
        }
    for (std::size_t i = 0; i < plane_count; ++i)
        if (!detail::lf_finite(glm::dvec3(receiver_planes[i])) || !std::isfinite(receiver_planes[i].w)) {
            out.status = Status::NonFinite;
            out.detail = "receiver_planes: NaN or Inf";
            return out;
        }
    const bool directional = light_position.w == 0.0f;
    const glm::dvec3 xyz(light_position);
    const glm::dvec3 toward = directional ? glm::normalize(xyz) : glm::dvec3(0.0);
    const glm::dvec3 pos = directional ? glm::dvec3(0.0) : xyz / double(light_position.w);
    if (!detail::lf_finite(pos)) { out.status = Status::Overflow; out.detail = "light_position: xyz / w beyond range"; return out; }
    out = detail::lf_extruded_planes(receiver_vertices, int(vertex_count), receiver_planes, int(plane_count),
                                     directional, toward, pos);
    for (int k = 0; k < out.count; ++k)
        if (!detail::lf_finite(glm::dvec3(out.planes[k])) || !std::isfinite(out.planes[k].w)) {
            out.count = 0;
            out.status = Status::Overflow;
            out.detail = "planes: beyond range";
            return out;
        }
    return out;
}

/// Conservative box test against a plane set. Total: false only if the box is entirely outside one
/// plane (by more than tol); NaN never culls; a plane set whose status is not Ok culls nothing.
inline bool light_frustum_box_may_intersect(const LightFrustumPlanes& p, const glm::vec3& mn, const glm::vec3& mx,
                                            double tol = 0.0) {
    if (p.status != Status::Ok) return true;
    return detail::lf_box_may_intersect(p, mn, mx, tol);
}

/// Conservative sphere test against a plane set. Total: false only if the sphere is entirely
/// outside one plane (by more than tol); NaN never culls; a plane set whose status is not Ok culls nothing.
inline bool light_frustum_sphere_may_intersect(const LightFrustumPlanes& p, const glm::vec3& c, float r,
                                               double tol = 0.0) {
    if (p.status != Status::Ok) return true;
    return detail::lf_sphere_may_intersect(p, c, r, tol);
}

/// Fits the light's view/projection to the receiver volume (camera slice, clipped to the receiver
/// depth range and the scene bounds) and the casters that can shadow it, and culls the casters.
/// kept_indices holds `capacity` uint32 elements (nullptr only with capacity 0); it needs `needed`
/// (the kept casters: boxes numbered 0.., spheres numbered from caster_count on). Writes
/// kept_indices[0 .. count).
/// Status: Ok (visible = false: the receiver volume is empty, every caster culled, nothing to draw);
/// BufferTooSmall (the matrices are valid, `count` = capacity indices written, `needed` more are
/// kept); InvalidArgument (null pointer with a count, camera near plane at or behind the eye, singular
/// matrix, infinite far plane with max_distance 0, a parameter outside its [Limit], stable with
/// stable_world_depth but no scene bounds); NonFinite;
/// InvalidLight (see "Lights:"; also a point light with stable = true); LightInsideVolume (point
/// light inside the receiver volume, or so close that every frustum axis leaves a receiver > 89.4
/// degrees off it - the axis is that of the narrowest cone holding the receivers: use a cube map); Overflow (a float
/// matrix cannot place the receivers within 0.01 NDC of its clip volume: coordinates far too large
/// for the fitted extent).
inline LightFrustumResult light_frustum_fit(const LightFrustumInput& in, std::uint32_t* kept_indices,
                                            std::size_t capacity) {
    using namespace detail;
    LightFrustumResult res;
    auto fail = [&res](Status s, const char* why) {
        res.status = s;
        res.detail = why;
        return res;
    };
    const char* why = nullptr;
    const Status vs = lf_fit_check_inputs(in, kept_indices, capacity, why);
    if (vs != Status::Ok) return fail(vs, why);
    const bool directional = in.light_position.w == 0.0f;
    const glm::dvec3 lxyz(in.light_position);
    const glm::dvec3 toward = directional ? glm::normalize(lxyz) : glm::dvec3(0.0);
    const glm::dvec3 Lpos = directional ? glm::dvec3(0.0) : lxyz / double(in.light_position.w);
    if (!lf_finite(toward) || !lf_finite(Lpos)) return fail(Status::Overflow, "light_position: direction or xyz / w beyond range");
    const glm::dmat4 V(in.camera_view);
    const double vdet = glm::determinant(V);
    if (!std::isfinite(vdet) || !(std::fabs(vdet) > 1e-300)) return fail(Status::InvalidArgument, "camera_view: singular");
    LfReceivers R;
    R.iv = glm::inverse(V);
    if (!lf_finite(R.iv)) return fail(Status::InvalidArgument, "camera_view: inverse not finite");

    // --- receiver volume: camera slice (view space -> world), optionally clipped by the scene box
    bool visible = false;
    const Status rs = lf_receiver_volume(in, R, visible, why);
    if (rs != Status::Ok) return fail(rs, why);
    if (!visible) {  // nothing to draw: every caster culled
        res.status = Status::Ok;
        res.visible = false;
        res.culled_count = in.caster_count + in.caster_sphere_count;
        for (std::size_t i = 0; i < in.caster_count; ++i)
            if (!lf_valid_box(in.casters + 6 * i)) ++res.invalid_count;
        for (std::size_t i = 0; i < in.caster_sphere_count; ++i)
            if (!lf_valid_sphere(in.caster_spheres + 4 * i)) ++res.invalid_count;
        return res;
    }

    // --- caster culling against the receiver volume extruded towards the light
    const LfCasterCull cull{in, lf_extruded_planes(R.verts, R.nv, R.planes, R.np, directional, toward, Lpos),
                            1e-7 * R.scale, directional};
    const std::size_t kept = lf_cull_casters(cull, kept_indices, capacity, res);

    // --- the light's view and projection
    LfLightFit F;
    Status fs = Status::Ok;
    if (directional && in.stable)
        fs = lf_fit_directional_stable(in, R, cull, -toward, F, res, why);  // -toward: the light view's forward axis
    else if (directional)
        lf_fit_directional_tight(R, cull, -toward, F);
    else
        fs = lf_fit_point(in, R, cull, Lpos, F, why);
    if (fs != Status::Ok) return fail(fs, why);

    // --- the depth convention, and the float matrices checked against the receivers
    const glm::dmat4 lview = F.view;
    const glm::dmat4 lproj = lf_depth_convention(in.light_depth, in.light_reversed_z) * F.proj;
    const glm::dmat4 vp = lproj * lview;
    if (!lf_finite(vp) || !lf_finite(lview) || !lf_finite(lproj)) return fail(Status::Overflow, "view_proj: beyond range");
    res.view = glm::mat4(lview);
    res.proj = glm::mat4(lproj);
    res.view_proj = glm::mat4(vp);
    res.near_z = static_cast<float>(F.nearp);
    res.far_z = static_cast<float>(F.farp);
    // a fresh result: the matrices just written must not reach the caller with a failure
    const char* overflow =
        !(res.near_z > 0.0f && res.near_z < res.far_z)  // a near plane of point_min_near_ratio * far under float's range
            ? "near_z: 0 < near < far does not hold in float (receivers too close to the light)"
        : (!lf_finite(res.view_proj) || !lf_finite(res.view) || !lf_finite(res.proj) || !std::isfinite(res.far_z) ||
           !lf_maps_inside(res.view_proj, R.verts, R.nv, in.light_depth, 1e-2))
            ? "view_proj: the float matrix cannot place the receivers (coordinates too large)"
            : nullptr;
    if (overflow) {
        LightFrustumResult bad;
        bad.status = Status::Overflow;
        bad.detail = overflow;
        return bad;
    }
    res.visible = true;
    res.needed = kept;
    res.count = kept < capacity ? kept : capacity;
    res.status = kept > capacity ? Status::BufferTooSmall : Status::Ok;
    res.detail = kept > capacity ? "capacity: below needed (see needed)" : nullptr;
    return res;
}

/// Inputs of light_frustum_fit_casters. Fields marked (required) default to a value the fit rejects.
struct LightCasterFitInput {
    /// The light, see "Lights:" above (required: the default (0, 0, 0, 0) gives Status::InvalidLight).
    glm::vec4 light_position{0.0f};
    /// The casters' bounding box (the union of every caster), world units (required: min <= max).
    glm::vec3 caster_min{0.0f};
    glm::vec3 caster_max{-1.0f};
    /// Every receiver (the scene's bounding box): the map's depth range reaches its farthest point
    /// (required: min <= max).
    glm::vec3 receiver_min{0.0f};
    glm::vec3 receiver_max{-1.0f};
    /// [Units: wu] [Limit: >= 0] A point light's emitter radius (an area light around light_position):
    /// the cone widens by the penumbra it throws past the casters. 0: a hard shadow's cone.
    float emitter_radius_world = 0.0f;
    /// [Units: rad] [Limit: (0, 1.5]] The widest perspective half angle; casters that need a wider
    /// cone (or surround the light) give LightInsideVolume: use a cube map or the light's own cone.
    float max_half_angle_radians = 1.4f;
    /// Point lights: near plane never closer than min_near_ratio * far. [Limit: (0, 1)]
    float min_near_ratio = 2e-3f;
    /// Depth convention of the matrix built for the light.
    ClipDepth light_depth = ClipDepth::NegativeOneToOne;
    bool light_reversed_z = false;
};

namespace detail {

inline bool lf_box_ok(const glm::vec3& mn, const glm::vec3& mx) {
    return lf_finite(mn) && lf_finite(mx) && mn.x <= mx.x && mn.y <= mx.y && mn.z <= mx.z;
}

inline Status lf_caster_fit_check(const LightCasterFitInput& in, const char*& why) {
    const Status nf = Status::NonFinite, ia = Status::InvalidArgument;
    if (!lf_finite(in.caster_min) || !lf_finite(in.caster_max)) return lf_fail(why, nf, "caster_min, caster_max: NaN or Inf");
    if (!lf_finite(in.receiver_min) || !lf_finite(in.receiver_max))
        return lf_fail(why, nf, "receiver_min, receiver_max: NaN or Inf");
    if (!std::isfinite(in.emitter_radius_world)) return lf_fail(why, nf, "emitter_radius_world: NaN or Inf");
    if (!std::isfinite(in.max_half_angle_radians)) return lf_fail(why, nf, "max_half_angle_radians: NaN or Inf");
    if (!std::isfinite(in.min_near_ratio)) return lf_fail(why, nf, "min_near_ratio: NaN or Inf");
    if (!lf_box_ok(in.caster_min, in.caster_max)) return lf_fail(why, ia, "caster_min: > caster_max");
    if (!lf_box_ok(in.receiver_min, in.receiver_max)) return lf_fail(why, ia, "receiver_min: > receiver_max");
    if (!(in.emitter_radius_world >= 0.0f)) return lf_fail(why, ia, "emitter_radius_world: < 0");
    if (!(in.max_half_angle_radians > 0.0f && in.max_half_angle_radians <= 1.5f))
        return lf_fail(why, ia, "max_half_angle_radians: outside (0, 1.5]");
    if (!(in.min_near_ratio > 0.0f && in.min_near_ratio < 1.0f)) return lf_fail(why, ia, "min_near_ratio: outside (0, 1)");
    if (in.light_depth != ClipDepth::NegativeOneToOne && in.light_depth != ClipDepth::ZeroToOne)
        return lf_fail(why, ia, "light_depth: unknown ClipDepth");
    return lf_check_light(in.light_position, why);
}

// Directional: the view along the light, an orthographic box whose x/y is the casters' light-space
// rectangle and whose depth spans the receivers' box (a caster outside it still writes its depth).
inline void lf_caster_fit_directional(const LightCasterFitInput& in, const glm::dvec3& f, LfLightFit& F) {
    const glm::dvec3 rmn(in.receiver_min), rmx(in.receiver_max), cmn(in.caster_min), cmx(in.caster_max);
    F.view = lf_look_dir(0.5 * (rmn + rmx), f, lf_stable_up(f));
    glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (int c = 0; c < 8; ++c) {
        const glm::dvec4 v = F.view * glm::dvec4((c & 1) ? cmx.x : cmn.x, (c & 2) ? cmx.y : cmn.y, (c & 4) ? cmx.z : cmn.z, 1.0);
        lo = glm::min(lo, glm::dvec2(v)), hi = glm::max(hi, glm::dvec2(v));
    }
    const glm::dvec2 dr = lf_box_light_depths(F.view, rmn, rmx), dc = lf_box_light_depths(F.view, cmn, cmx);
    const double pad = 1e-3 * std::fmax(glm::length(rmx - rmn), 1e-30);
    F.nearp = std::fmin(dr.x, dc.x) - pad;
    F.farp = std::fmax(dr.y, dc.y) + pad;
    for (int k = 0; k < 2; ++k)  // a caster box edge-on to the light keeps a window of at least `pad`
        if (!(hi[k] - lo[k] >= pad)) {
            const double m = 0.5 * (lo[k] + hi[k]);
            lo[k] = m - 0.5 * pad;
            hi[k] = m + 0.5 * pad;
        }
    // the float matrix's rounding (a box far from the origin): 1e-4 of the window plus 64 float ulps
    // of the largest coordinate, so the casters' corners map inside [-1, 1] through the float matrix
    double big = 0.0;
    for (int k = 0; k < 3; ++k)
        big = std::fmax(big, std::fmax(std::fmax(std::fabs(rmn[k]), std::fabs(rmx[k])), std::fmax(std::fabs(cmn[k]), std::fabs(cmx[k]))));
    for (int k = 0; k < 2; ++k) {
        const double m = 1e-4 * (hi[k] - lo[k]) + 64.0 * 5.9604644775390625e-8 * big;
        lo[k] -= m;
        hi[k] += m;
    }
    lf_eye_behind(F.view, F.nearp, F.farp);
    F.proj = lf_ortho(lo.x, hi.x, lo.y, hi.y, F.nearp, F.farp);
}

// Point: the view from the light toward the casters' box center, the cone just wide enough for its
// corners (2% margin) plus the emitter's penumbra seen from the nearest corner (atan(r / z_min)); near
// 0.9 of the nearest caster corner, far 1.01 of the farthest receiver corner.
inline Status lf_caster_fit_point(const LightCasterFitInput& in, const glm::dvec3& L, LfLightFit& F, const char*& why) {
    const glm::dvec3 rmn(in.receiver_min), rmx(in.receiver_max), cmn(in.caster_min), cmx(in.caster_max);
    const glm::dvec3 axis = 0.5 * (cmn + cmx) - L;
    const double len = glm::length(axis);
    if (!(len > 0.0) || !std::isfinite(len))
        return lf_fail(why, Status::LightInsideVolume, "light_position: at the casters' box center");
    const glm::dvec3 f = axis / len;
    F.view = lf_look_dir(L, f, lf_stable_up(f));
    double tan_max = 0.0, zmin = std::numeric_limits<double>::infinity();
    for (int c = 0; c < 8; ++c) {
        const glm::dvec4 v = F.view * glm::dvec4((c & 1) ? cmx.x : cmn.x, (c & 2) ? cmx.y : cmn.y, (c & 4) ? cmx.z : cmn.z, 1.0);
        if (!(-v.z > 1e-9 * len))  // a corner beside or behind the light
            return lf_fail(why, Status::LightInsideVolume, "light_position: a caster corner beside or behind the light");
        tan_max = std::fmax(tan_max, std::fmax(std::fabs(v.x), std::fabs(v.y)) / -v.z);
        zmin = std::fmin(zmin, -v.z);
    }
    // the float matrix must see every corner in front of the light: a distance near float's subnormal
    // range rounds clip w to 0 (a box 1e-44 from a light at the origin)
    if (!(zmin >= 1e-30))
        return lf_fail(why, Status::LightInsideVolume, "caster_min, caster_max: a corner closer to the light than 1e-30 (float cannot hold it in front)");
    // + 64 float ulps of the largest coordinate over z_min: the float matrix's rounding (a tiny box far away)
    double big = glm::length(L);
    for (int k = 0; k < 3; ++k) big = std::fmax(big, std::fmax(std::fabs(cmn[k]), std::fabs(cmx[k])));
    const double half = std::atan(1.02 * tan_max + double(in.emitter_radius_world) / zmin + 64.0 * 5.9604644775390625e-8 * big / zmin);
    if (!(half <= double(in.max_half_angle_radians)))
        return lf_fail(why, Status::LightInsideVolume, "max_half_angle_radians: the casters need a wider cone");
    const glm::dvec2 dr = lf_box_light_depths(F.view, rmn, rmx);
    F.farp = 1.01 * std::fmax(dr.y, zmin);
    F.nearp = std::fmax(0.9 * zmin, double(in.min_near_ratio) * F.farp);
    if (!(F.nearp < F.farp)) return lf_fail(why, Status::Overflow, "receiver_min, receiver_max: near not below far");
    const double t = F.nearp * std::tan(half);
    F.proj = lf_frustum(-t, t, -t, t, F.nearp, F.farp);
    return Status::Ok;
}

}  // namespace detail

/// A light's map around its casters, deep enough for every receiver: what a scene needs when the
/// casters cover less than the light sees (a spot or area light over a few objects, a sun over a
/// small scene), with no camera involved (Brabec, Annen & Seidel 2002, sec. 3: fit the light frustum
/// to the objects that can cast; a receiver outside the casters' cone is lit, so the map need not
/// hold it). Directional light: an orthographic box along the light, its x/y the casters' box
/// across the light, its depth the receivers' and casters' range. Point light: a perspective cone
/// from the light toward the casters' box center, just wide enough for the box (+2%) and, with
/// emitter_radius_world > 0, the penumbra an emitter of that radius throws past them; near plane at
/// 0.9 of the nearest caster corner (never closer than min_near_ratio * far), far plane 1.01 of the
/// farthest receiver corner. The roll about the light axis is the stable fit's (a function of the
/// direction alone). Result: view, proj, view_proj, near_z, far_z, visible = true (no caster
/// culling: count, needed stay 0). Statuses: InvalidLight; NonFinite / InvalidArgument (a box with min
/// > max, a limit outside its range); LightInsideVolume: a point light inside or beside the casters'
/// box (a corner at or behind its position, or closer to it than 1e-30) or a cone wider than
/// max_half_angle_radians (use a cube map, or the light's own cone); Overflow: a matrix that is not
/// finite in float.
inline LightFrustumResult light_frustum_fit_casters(const LightCasterFitInput& in) {
    using namespace detail;
    LightFrustumResult res;
    res.status = lf_caster_fit_check(in, res.detail);
    if (res.status != Status::Ok) return res;
    const bool directional = in.light_position.w == 0.0f;
    const glm::dvec3 lxyz(in.light_position);
    LfLightFit F;
    if (directional) {
        const glm::dvec3 f = -glm::normalize(lxyz);  // the light view's forward axis: where the rays travel
        if (!lf_finite(f)) return res.status = Status::Overflow, res.detail = "light_position: direction beyond range", res;
        lf_caster_fit_directional(in, f, F);
    } else {
        const glm::dvec3 L = lxyz / double(in.light_position.w);
        if (!lf_finite(L)) return res.status = Status::Overflow, res.detail = "light_position: xyz / w beyond range", res;
        const Status s = lf_caster_fit_point(in, L, F, res.detail);
        if (s != Status::Ok) return res.status = s, res;
    }
    const glm::dmat4 lproj = lf_depth_convention(in.light_depth, in.light_reversed_z) * F.proj;
    res.view = glm::mat4(F.view);
    res.proj = glm::mat4(lproj);
    res.view_proj = glm::mat4(lproj * F.view);
    res.near_z = static_cast<float>(F.nearp);
    res.far_z = static_cast<float>(F.farp);
    if (!lf_finite(res.view_proj) || !lf_finite(res.view) || !lf_finite(res.proj) || !std::isfinite(res.near_z) ||
        !std::isfinite(res.far_z) || !(res.near_z > 0.0f && res.near_z < res.far_z)) {
        LightFrustumResult bad;
        bad.status = Status::Overflow;
        bad.detail = "view_proj: not finite in float, or 0 < near_z < far_z does not hold in float";
        return bad;
    }
    res.visible = true;
    res.status = Status::Ok;
    return res;
}

}  // namespace shadowkit
