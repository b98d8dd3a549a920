// shadowkit/cascades.hpp - cascaded (parallel-split) shadow maps for directional lights: split
// distances, stable per-cascade fits, cascade selection and the blend band between cascades.
//
// Usage:
//   shadowkit::CascadeInput in;
//   in.camera_view = view; in.camera_proj = proj;        // GLM, right-handed, column-major (required)
//   in.max_distance = 300.0f;                           // shadow distance (required for an infinite far)
//   in.light_position = glm::vec4(to_sun, 0.0f);        // directional: w = 0, xyz toward the light (required)
//   in.shadow_map_size = 2048;
//   in.has_scene_bounds = true; in.scene_min = lo; in.scene_max = hi;  // every receiver and caster
//   in.stable_world_depth = true;                       // depth fixed in the world: cached cascades scroll
//   shadowkit::Cascade cascades[4];
//   const shadowkit::CascadeFitResult fit = shadowkit::cascade_fit(in, 0.75f, 4, cascades, 4);
//   if (fit.status == shadowkit::Status::Ok) {
//       // render cascade i with cascades[i].view_proj into layer i of a depth array texture;
//       // in the shader pick the cascade with glsl/cascades.glsl (fit.splits[1..4] as view depths).
//   }
//   // SDSM: fit to what the depth buffer shows (glsl/cascades.glsl's reduction -> window min/max)
//   shadowkit::CascadeSdsmInput sd; sd.camera = in; sd.camera.stable_world_depth = false;
//   const shadowkit::CascadeSdsmRange vr = shadowkit::cascade_sdsm_view_range(proj, depth, reversed, wmin, wmax);
//   sd.view_min = vr.view_min; sd.view_max = vr.view_max;   // if vr.visible
//   sd.world_splits = true;                                 // a dolly moves no pixel across a split
//   static shadowkit::CascadeSdsmResult last;               // last frame's fit: the hysteresis
//   // optional, tighter: cascade_sdsm_splits(sd, &last) -> the bounds reduction -> sd.receiver_bounds
//   last = shadowkit::cascade_sdsm_fit(sd, &last, cascades, 4);  // splits in last.splits
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
// Cascades need a directional light: a point or spot light (w > 0) gives Status::InvalidLight.
// Buffers: cascade_fit's `out_cascades` holds `out_capacity` Cascade elements; it needs
// `cascade_count` (`needed`). Split distances live in the results (at most 16 cascades, 17 splits).
// Map orientation (the roll about the light axis) is a fixed function of the light direction (a
// cascade must not rotate with the camera): the shortest-arc rotation of the frame of a light shining
// straight down (-y: map x = world +x, map y = world -z), continuous for every light direction except
// one shining straight up (+y travel, light_position (0, -1, 0, 0)), around which it spins.
//
// Based on:
//   Zhang, Sun, Xu & Lun 2006, "Parallel-Split Shadow Maps for Large-scale Virtual Environments"
//     (practical split scheme: C_i = lambda C_log + (1 - lambda) C_uni); Engel 2007 "Cascaded Shadow
//     Maps" (ShaderX5); Valient 2008, "Stable Rendering of Cascaded Shadow Maps" (ShaderX6: bounding
//     sphere, texel snapping); Moschig, "Apelles" thesis, eqs. 2.3-2.5 (logarithmic split);
//   Lauritzen, Salvi & Lefohn 2011, "Sample Distribution Shadow Maps" (I3D; SIGGRAPH 2010 course):
//     depth-buffer min/max reduction, log partition of the visible range, tight light-space bounds.
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

/// Stable-fit inputs (directional light). Fields marked (required) default to a value the fit rejects.
struct CascadeInput {
    glm::mat4 camera_view = glm::mat4(0.0f);       ///< world -> camera view, looks down -z (required)
    glm::mat4 camera_proj = glm::mat4(0.0f);       ///< camera projection, near plane in front of the eye (required)
    ClipDepth camera_depth = ClipDepth::NegativeOneToOne;
    bool camera_reversed_z = false;
    /// [Units: wu, view depth] [Limit: >= 0] shadow distance; 0: the projection's far plane (finite).
    float max_distance = 0.0f;
    /// The light, see "Lights:" above; directional only (required: (0, 0, 0, 0) gives InvalidLight).
    glm::vec4 light_position{0.0f};
    std::uint32_t shadow_map_size = 2048;          ///< [Limit: >= 4] texels per side of each cascade
    float radius_quantum = 1.0f / 16.0f;           ///< [Units: wu] [Limit: > 0] sphere radius rounding step
    bool has_caster_bounds = false;                ///< casters: the near plane is pulled back to them
    glm::vec3 caster_min{0.0f};                    ///< [Limit: caster_min <= caster_max]
    glm::vec3 caster_max{0.0f};
    ClipDepth light_depth = ClipDepth::NegativeOneToOne;
    bool light_reversed_z = false;
    /// Scene bounds (every receiver and caster); used by stable_world_depth. [Limit: scene_min <= scene_max]
    bool has_scene_bounds = false;
    glm::vec3 scene_min{0.0f};
    glm::vec3 scene_max{0.0f};
    /// Every cascade's depth range (near and far planes) from the scene bounds (and the caster
    /// bounds) along the light instead of the slice's bounding sphere, so it is fixed in the world: a
    /// camera move then changes a cascade by a whole-texel translation in x/y only (texel_anchor),
    /// which a cached map scrolls (shadow_cache.hpp's shadow_cache_plan: Scroll or Keep); with the
    /// default range every camera move shifts the depth planes (DepthMoved: the whole map rendered).
    /// Costs depth precision: the range spans the whole scene along the light. Needs has_scene_bounds
    /// (else InvalidArgument).
    bool stable_world_depth = false;
};

/// One fitted cascade (the result of cascade_fit_slice, and an element of cascade_fit's output).
struct Cascade {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    glm::mat4 view_proj{1.0f};       ///< world -> cascade clip space
    float split_near = 0.0f;         ///< view-depth range covered by this cascade
    float split_far = 0.0f;
    glm::vec4 sphere{0.0f};          ///< world bounding sphere of the slice (center, rounded radius); SDSM: of its box
    float texel_world_size = 0.0f;   ///< world size of one shadow-map texel (SDSM: the larger of x and y)
    /// Where the map's texel (0, 0) begins on the light's texel grid, anchored at the world origin:
    /// window x of a point = (light-view x) / texel - texel_anchor.x (likewise y); whole numbers for an
    /// even shadow_map_size. A camera move changes them by the whole texels the map moved. For
    /// shadow_cache_plan, rebuild the double matrix's x/y translation exactly from it:
    /// view_proj[3][0] = -2 texel_anchor.x / size - 1 (likewise [3][1]), as for light_frustum.hpp.
    /// (cascade_sdsm_fit: x and y each in texels of its own axis, its box's x0 / texel_x, y0 / texel_y.)
    glm::dvec2 texel_anchor{0.0};
};

/// Split distances of cascade_split_distances: distances[0 .. count] (count + 1 values).
struct CascadeSplits {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    std::uint32_t count = 0;         ///< cascades (distances holds count + 1 values)
    float distances[17] = {};        ///< distances[0] == near, distances[count] == far, strictly increasing
};

/// Result of cascade_fit.
struct CascadeFitResult {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    std::size_t count = 0;           ///< cascades written to out_cascades (a valid prefix)
    std::size_t needed = 0;          ///< cascades the output needs (cascade_count)
    float splits[17] = {};           ///< view depths: cascade i covers [splits[i], splits[i + 1]]
};

/// Result of the cascade selection functions.
struct CascadeIndex {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    int index = -1;                  ///< the cascade; -1 (with Ok): outside every cascade
};

namespace detail {

/// Sets the detail of a failure and returns its status.
inline Status cs_fail(const char*& why, Status s, const char* what) {
    why = what;
    return s;
}

inline bool cs_finite(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}
inline bool cs_finite(const glm::dmat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}
inline bool cs_finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
inline bool cs_finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
inline bool cs_finite(const glm::vec4& v) { return cs_finite(glm::vec3(v)) && std::isfinite(v.w); }

/// Camera rays of the four frustum edges in view space: point at the near plane, direction, depths.
struct CsRays {
    glm::dvec3 pn[4], dir[4];
    double dn[4] = {0, 0, 0, 0};
    double near_depth = 0.0, far_depth = 0.0;  ///< far_depth may be +inf
};

/// Un-projects the corner rays of a projection: the ray through NDC depths zn (near) and
/// zn + (zf - zn) / 64 (finite for every projection, the epsilon-tweaked P_inf with epsilon <= 0.5
/// included). The far plane is found from NDC depth zf: a point there that lies beyond the second
/// point on the ray is a finite far plane; w = 0 or a point behind the eye (the epsilon-tweaked P_inf
/// puts zf beyond infinity) is a far plane at infinity.
inline Status cs_camera_rays(const glm::mat4& proj, ClipDepth cd, bool reversed, CsRays& r, const char*& why) {
    const glm::dmat4 P(proj);
    if (!cs_finite(P)) return cs_fail(why, Status::NonFinite, "camera_proj: NaN or Inf");
    const double det = glm::determinant(P);
    if (!std::isfinite(det) || !(std::fabs(det) > 1e-300)) return cs_fail(why, Status::InvalidArgument, "camera_proj: singular");
    const glm::dmat4 ip = glm::inverse(P);
    if (!cs_finite(ip)) return cs_fail(why, Status::InvalidArgument, "camera_proj: inverse not finite");
    const double lo = cd == ClipDepth::ZeroToOne ? 0.0 : -1.0;
    const double zn = reversed ? 1.0 : lo, zf = reversed ? lo : 1.0, zm = zn + (zf - zn) / 64.0;
    r.near_depth = -std::numeric_limits<double>::infinity();
    r.far_depth = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 4; ++i) {
        const double x = (i & 1) ? 1.0 : -1.0, y = (i & 2) ? 1.0 : -1.0;
        const glm::dvec4 hn = ip * glm::dvec4(x, y, zn, 1.0), hm = ip * glm::dvec4(x, y, zm, 1.0),
                         hf = ip * glm::dvec4(x, y, zf, 1.0);
        const double sn = std::fabs(hn.x) + std::fabs(hn.y) + std::fabs(hn.z);
        const double sm = std::fabs(hm.x) + std::fabs(hm.y) + std::fabs(hm.z);
        if (!(std::fabs(hn.w) > 1e-12 * sn) || !(std::fabs(hn.w) > 1e-300))
            return cs_fail(why, Status::InvalidArgument, "camera_proj: near plane at infinity");
        if (!(std::fabs(hm.w) > 1e-12 * sm) || !(std::fabs(hm.w) > 1e-300))
            return cs_fail(why, Status::InvalidArgument, "camera_proj: near-side depth at infinity");
        r.pn[i] = glm::dvec3(hn) / hn.w;
        r.dir[i] = glm::dvec3(hm) / hm.w - r.pn[i];
        r.dn[i] = -r.pn[i].z;
        if (!(r.dn[i] > 0.0) || !(r.dir[i].z < 0.0) || !cs_finite(r.pn[i]) || !cs_finite(r.dir[i]))
            return cs_fail(why, Status::InvalidArgument, "camera_proj: near plane at or behind the eye");
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
    if (!(r.far_depth > r.near_depth)) return cs_fail(why, Status::InvalidArgument, "camera_proj: far plane not beyond near");
    return Status::Ok;
}

inline glm::dvec3 cs_corner(const CsRays& r, int i, double depth) {
    return r.pn[i] + ((depth - r.dn[i]) / -r.dir[i].z) * r.dir[i];
}

/// Up hint, a function of the light's travel direction f (unit) alone: the shortest-arc rotation
/// taking (0, -1, 0) to f applied to (0, 0, -1). Continuous except at f = (0, 1, 0).
inline glm::dvec3 cs_stable_up(const glm::dvec3& f) {
    const glm::dvec3 a(0.0, -1.0, 0.0), u0(0.0, 0.0, -1.0);
    const double c1 = 1.0 + glm::dot(a, f);
    if (!(c1 > 1e-12)) return glm::dvec3(0.0, 0.0, 1.0);  // f = +y: the rotation by pi about x
    const glm::dvec3 c = glm::cross(a, f);  // R v = v + c x v + c x (c x v) / (1 + a.f)
    const glm::dvec3 cu = glm::cross(c, u0);
    return u0 + cu + glm::cross(c, cu) / c1;
}

/// Checks the common inputs of the fits: Ok, or the first problem found.
inline Status cs_check_input(const CascadeInput& in, const char*& why) {
    if (!cs_finite(in.camera_view)) return cs_fail(why, Status::NonFinite, "camera_view: NaN or Inf");
    if (!cs_finite(in.camera_proj)) return cs_fail(why, Status::NonFinite, "camera_proj: NaN or Inf");
    if (!cs_finite(in.light_position)) return cs_fail(why, Status::InvalidLight, "light_position: NaN or Inf");
    if (in.light_position.w != 0.0f) return cs_fail(why, Status::InvalidLight, "light_position: w != 0 (cascades need a directional light)");
    if (in.light_position.x == 0.0f && in.light_position.y == 0.0f && in.light_position.z == 0.0f)
        return cs_fail(why, Status::InvalidLight, "light_position: (0, 0, 0, 0)");
    if (!std::isfinite(in.max_distance)) return cs_fail(why, Status::NonFinite, "max_distance: NaN or Inf");
    if (!std::isfinite(in.radius_quantum)) return cs_fail(why, Status::NonFinite, "radius_quantum: NaN or Inf");
    if (in.max_distance < 0.0f) return cs_fail(why, Status::InvalidArgument, "max_distance: < 0");
    if (in.shadow_map_size < 4) return cs_fail(why, Status::InvalidArgument, "shadow_map_size: < 4");
    if (!(in.radius_quantum > 0.0f)) return cs_fail(why, Status::InvalidArgument, "radius_quantum: <= 0");
    if (in.has_caster_bounds) {
        if (!cs_finite(in.caster_min) || !cs_finite(in.caster_max))
            return cs_fail(why, Status::NonFinite, "caster_min, caster_max: NaN or Inf");
        if (in.caster_min.x > in.caster_max.x || in.caster_min.y > in.caster_max.y || in.caster_min.z > in.caster_max.z)
            return cs_fail(why, Status::InvalidArgument, "caster_min: > caster_max");
    }
    if (in.has_scene_bounds) {
        if (!cs_finite(in.scene_min) || !cs_finite(in.scene_max))
            return cs_fail(why, Status::NonFinite, "scene_min, scene_max: NaN or Inf");
        if (in.scene_min.x > in.scene_max.x || in.scene_min.y > in.scene_max.y || in.scene_min.z > in.scene_max.z)
            return cs_fail(why, Status::InvalidArgument, "scene_min: > scene_max");
    }
    if (in.stable_world_depth && !in.has_scene_bounds)
        return cs_fail(why, Status::InvalidArgument, "stable_world_depth: set without has_scene_bounds");
    return Status::Ok;
}

// Light-view distance range [nearp, farp] of one cascade: the slice's sphere (center at light-view
// depth cl_z, radius rad) pulled back to the caster bounds; with stable_world_depth the scene bounds
// and the caster bounds alone (camera-invariant). Padded by 1e-6 of the magnitudes.
inline void cs_depth_range(const CascadeInput& in, const glm::dmat4& lv, double cl_z, double rad, double& nearp,
                           double& farp) {
    nearp = -cl_z - rad;
    farp = -cl_z + rad;
    if (in.stable_world_depth) {
        nearp = std::numeric_limits<double>::infinity();
        farp = -nearp;
    }
    auto extend = [&](const glm::vec3& lo, const glm::vec3& hi, bool far_too) {
        const glm::dvec3 mn(lo), mx(hi);
        for (int c = 0; c < 8; ++c) {
            const glm::dvec3 p((c & 1) ? mx.x : mn.x, (c & 2) ? mx.y : mn.y, (c & 4) ? mx.z : mn.z);
            const double dist = -(lv * glm::dvec4(p, 1.0)).z;
            nearp = std::fmin(nearp, dist);
            if (far_too) farp = std::fmax(farp, dist);
        }
    };
    if (in.stable_world_depth) extend(in.scene_min, in.scene_max, true);
    if (in.has_caster_bounds) extend(in.caster_min, in.caster_max, in.stable_world_depth);
    const double pad = 1e-6 * std::fmax(1.0, std::fabs(nearp) + std::fabs(farp));
    nearp -= pad;
    farp += pad;
}

// What a vertex shader computes must still land inside the cascade: receivers at float world
// positions (each coordinate rounded: off by up to u times the largest), transformed by the float
// matrix in float (a 4-term dot product: error <= 4u sum |m_rj p_j|, plus the term |m_r3| u). The
// slice is the convex hull of its corners pw (world) and the map is affine, so bounding the corners
// bounds every receiver: the exact image of the float matrix plus that error within 0.01 of [-1, 1].
// A slice reaching beyond float range has receivers no float position (and no vertex shader) holds.
// stable_world_depth: the slice's depth may reach beyond the scene, where nothing is (the range holds
// the scene bounds by construction): x/y only.
inline bool cs_float_landing_ok(const CascadeInput& in, const glm::mat4& view_proj, const glm::dvec3 (&pw)[8]) {
    const double zlo = in.light_depth == ClipDepth::ZeroToOne ? 0.0 : -1.0;
    const double uf = 5.9604644775390625e-8;  // 2^-24
    const glm::dmat4 mf(view_proj);
    double pmax = 0.0;
    for (int i = 0; i < 8; ++i)
        pmax = std::fmax(pmax, std::fmax(std::fabs(pw[i].x), std::fmax(std::fabs(pw[i].y), std::fabs(pw[i].z))));
    if (!(pmax <= static_cast<double>(std::numeric_limits<float>::max()))) return false;
    const double ep = uf * pmax;
    for (int i = 0; i < 8; ++i) {
        const glm::dvec4 h = mf * glm::dvec4(pw[i], 1.0);  // the float matrix, exactly (w = 1: orthographic)
        double e[3];
        for (int rr = 0; rr < 3; ++rr) {
            double sabs = 0.0, srow = 0.0;
            for (int j = 0; j < 3; ++j) {
                sabs += std::fabs(mf[j][rr] * pw[i][j]);
                srow += std::fabs(mf[j][rr]);
            }
            e[rr] = srow * ep + 4.0 * uf * (sabs + std::fabs(mf[3][rr]));
        }
        const bool z_ok = in.stable_world_depth || (h.z - e[2] >= zlo - 0.01 && h.z + e[2] <= 1.01);
        if (!(std::fabs(h.x) + e[0] <= 1.01) || !(std::fabs(h.y) + e[1] <= 1.01) || !z_ok) return false;
    }
    return true;
}

}  // namespace detail

/// Practical split scheme (Zhang et al. 2006): C_i = lambda * n (f/n)^(i/m) + (1 - lambda) * (n + (f - n) i/m)
/// for i = 0..count; distances[0] == near and distances[count] == far exactly, strictly increasing.
/// lambda = 1: logarithmic (Apelles eq. 2.4), lambda = 0: uniform.
/// Status: NonFinite (NaN/Inf; an infinite far plane must be clamped to a shadow distance first),
/// InvalidArgument (near <= 0, far <= near, lambda outside [0, 1], count 0 or > 16), Overflow (fewer
/// floats between near and far than splits).
inline CascadeSplits cascade_split_distances(float near_z, float far_z, float lambda, std::uint32_t count) {
    CascadeSplits out;
    const char* why = !std::isfinite(near_z) ? "near_z: NaN or Inf"
                      : !std::isfinite(far_z)  ? "far_z: NaN or Inf (clamp an infinite far plane to a shadow distance)"
                      : !std::isfinite(lambda)     ? "lambda: NaN or Inf"
                                                   : nullptr;
    if (why) {
        out.status = Status::NonFinite;
        out.detail = why;
        return out;
    }
    why = (count == 0 || count > 16)                ? "count: outside 1..16"
          : !(near_z > 0.0f)                     ? "near_z: <= 0"
          : !(far_z > near_z)                ? "far_z: not beyond near_z"
          : !(lambda >= 0.0f) || !(lambda <= 1.0f)   ? "lambda: outside [0, 1]"
                                                     : nullptr;
    if (why) {
        out.status = Status::InvalidArgument;
        out.detail = why;
        return out;
    }
    const double n = near_z, f = far_z, l = lambda;
    out.distances[0] = near_z;
    float prev = near_z;
    for (std::uint32_t i = 1; i < count; ++i) {
        const double s = double(i) / double(count);
        const double c = l * n * std::pow(f / n, s) + (1.0 - l) * (n + (f - n) * s);
        float v = static_cast<float>(c);
        if (!(v > prev)) v = std::nextafter(prev, far_z);  // strictly increasing even for tiny ranges
        out.distances[i] = v;
        prev = v;
    }
    if (!(prev < far_z)) {  // fewer representable floats than splits
        out = CascadeSplits{};
        out.status = Status::Overflow;
        out.detail = "near_z, far_z: fewer floats between them than splits";
        return out;
    }
    out.distances[count] = far_z;
    out.count = count;
    out.status = Status::Ok;
    return out;
}

/// Stable fit of one cascade covering view depths [split_near, split_far] (clipped to the camera's
/// near and far planes): bounding sphere of the slice (computed in view space, so bitwise invariant
/// to camera rotation and translation), radius rounded up to radius_quantum, the projected world
/// origin snapped to whole texels (one texel of border), near plane pulled back to the caster bounds.
/// Status: NonFinite, InvalidLight (not a directional light), InvalidArgument (camera near plane at
/// or behind the eye, singular matrix, split range empty or outside the camera's, a field outside its
/// [Limit]), Overflow (beyond float, or receivers of the slice at float positions, transformed by the
/// float matrix in float as a vertex shader does, can land more than 0.01 NDC outside the cascade: a
/// slice small against its distance from the world origin, e.g. a few hundredths of a unit at 1e5).
inline Cascade cascade_fit_slice(const CascadeInput& in, float split_near, float split_far) {
    using namespace detail;
    Cascade out;
    const char* why = nullptr;
    auto fail = [&out, &why](Status s, const char* what = nullptr) {
        out = Cascade{};
        out.status = s;
        out.detail = what ? what : why;
        return out;
    };
    const Status cs = cs_check_input(in, why);
    if (cs != Status::Ok) return fail(cs);
    if (!std::isfinite(split_near) || !std::isfinite(split_far)) return fail(Status::NonFinite, "split_near, split_far: NaN or Inf");
    if (!(split_near > 0.0f)) return fail(Status::InvalidArgument, "split_near: <= 0");
    if (!(split_far > split_near)) return fail(Status::InvalidArgument, "split_far: not beyond split_near");
    const glm::dvec3 d = -glm::normalize(glm::dvec3(in.light_position));  // travel direction
    CsRays r;
    const Status st = cs_camera_rays(in.camera_proj, in.camera_depth, in.camera_reversed_z, r, why);
    if (st != Status::Ok) return fail(st);
    const double d0 = std::fmax(double(split_near), r.near_depth);
    const double d1 = std::fmin(double(split_far), r.far_depth);
    if (!(d1 > d0)) return fail(Status::InvalidArgument, "split_near, split_far: outside the camera's near and far planes");
    glm::dvec3 cv[8];
    for (int i = 0; i < 4; ++i) {
        cv[i] = cs_corner(r, i, d0);
        cv[i + 4] = cs_corner(r, i, d1);
    }
    // smallest sphere centered on the segment between the near and far face centers
    const glm::dvec3 nc = (cv[0] + cv[1] + cv[2] + cv[3]) * 0.25, fc = (cv[4] + cv[5] + cv[6] + cv[7]) * 0.25;
    double a2 = 0, b2 = 0;
    for (int i = 0; i < 4; ++i) {
        a2 = std::fmax(a2, glm::dot(cv[i] - nc, cv[i] - nc));
        b2 = std::fmax(b2, glm::dot(cv[i + 4] - fc, cv[i + 4] - fc));
    }
    const double L2 = glm::dot(fc - nc, fc - nc);
    const double t = L2 > 0.0 ? glm::clamp(0.5 + (b2 - a2) / (2.0 * L2), 0.0, 1.0) : 0.5;
    const glm::dvec3 cview = nc + t * (fc - nc);
    double rad = 0.0;
    for (int i = 0; i < 8; ++i) rad = std::fmax(rad, glm::length(cv[i] - cview));
    const double q = in.radius_quantum;
    rad = std::ceil(rad / q) * q;  // constant texel size while the slice shape is constant
    if (!(rad > 0.0) || !std::isfinite(rad)) return fail(Status::Overflow, "camera_proj: the slice's radius beyond double");
    const glm::dmat4 V(in.camera_view);
    const double vdet = glm::determinant(V);
    if (!std::isfinite(vdet) || !(std::fabs(vdet) > 1e-300)) return fail(Status::InvalidArgument, "camera_view: singular");
    const glm::dmat4 iv = glm::inverse(V);
    if (!cs_finite(iv)) return fail(Status::InvalidArgument, "camera_view: inverse not finite");
    const glm::dvec3 cw = glm::dvec3(iv * glm::dvec4(cview, 1.0));
    // light view anchored at the world origin: rotation only, fixed per light direction
    const glm::dvec3 sx = glm::normalize(glm::cross(d, cs_stable_up(d)));
    const glm::dvec3 sy = glm::cross(sx, d);
    glm::dmat4 lv(1.0);
    lv[0][0] = sx.x; lv[1][0] = sx.y; lv[2][0] = sx.z;
    lv[0][1] = sy.x; lv[1][1] = sy.y; lv[2][1] = sy.z;
    lv[0][2] = -d.x; lv[1][2] = -d.y; lv[2][2] = -d.z;
    const glm::dvec3 cl = glm::dvec3(lv * glm::dvec4(cw, 1.0));
    const double S = double(in.shadow_map_size);
    const double texel = 2.0 * rad / (S - 2.0);
    const double half = rad + texel;
    const double kx = std::floor(cl.x / texel), ky = std::floor(cl.y / texel);  // snap to whole texels
    const double cx = kx * texel, cy = ky * texel;
    double nearp = 0.0, farp = 0.0;
    cs_depth_range(in, lv, cl.z, rad, nearp, farp);
    glm::dmat4 pr(1.0);
    pr[0][0] = 1.0 / half;
    pr[1][1] = 1.0 / half;
    pr[2][2] = -2.0 / (farp - nearp);
    pr[3][0] = -cx / half;
    pr[3][1] = -cy / half;
    pr[3][2] = -(farp + nearp) / (farp - nearp);
    glm::dmat4 conv(1.0);
    if (in.light_depth == ClipDepth::ZeroToOne) {
        conv[2][2] = in.light_reversed_z ? -0.5 : 0.5;
        conv[3][2] = 0.5;
    } else if (in.light_reversed_z) {
        conv[2][2] = -1.0;
    }
    const glm::dmat4 m = conv * pr * lv;
    if (!cs_finite(m)) return fail(Status::Overflow, "camera_view, camera_proj: the cascade's matrix beyond double");
    out.view_proj = glm::mat4(m);
    if (!cs_finite(out.view_proj) || !(static_cast<float>(texel) > 0.0f) || !std::isfinite(static_cast<float>(rad)) ||
        !cs_finite(glm::vec3(cw)))
        return fail(Status::Overflow, "camera_view, camera_proj: the cascade beyond float");
    // what a vertex shader computes (float positions, the float matrix) must land inside the cascade
    const glm::dvec3 pw[8] = {glm::dvec3(iv * glm::dvec4(cv[0], 1.0)), glm::dvec3(iv * glm::dvec4(cv[1], 1.0)),
                              glm::dvec3(iv * glm::dvec4(cv[2], 1.0)), glm::dvec3(iv * glm::dvec4(cv[3], 1.0)),
                              glm::dvec3(iv * glm::dvec4(cv[4], 1.0)), glm::dvec3(iv * glm::dvec4(cv[5], 1.0)),
                              glm::dvec3(iv * glm::dvec4(cv[6], 1.0)), glm::dvec3(iv * glm::dvec4(cv[7], 1.0))};
    if (!cs_float_landing_ok(in, out.view_proj, pw))
        return fail(Status::Overflow, "camera_view: the slice too small against its distance from the origin for float");
    out.split_near = split_near;
    out.split_far = split_far;
    out.sphere = glm::vec4(glm::vec3(cw), static_cast<float>(rad));
    out.texel_world_size = static_cast<float>(texel);
    out.texel_anchor = glm::dvec2(kx - 0.5 * S, ky - 0.5 * S);
    out.status = Status::Ok;
    return out;
}

/// Splits the camera range [near, min(far, max_distance)] with the practical scheme and fits every
/// cascade. out_cascades holds out_capacity Cascade elements (nullptr only with 0); it needs
/// cascade_count (`needed`); the result's `splits` has cascade_count + 1 distances.
/// Status: BufferTooSmall (out_capacity < cascade_count: nothing written), InvalidArgument
/// (cascade_count 0 or > 16, infinite far plane with max_distance 0, max_distance below the near
/// plane, ...), and the statuses of cascade_split_distances and cascade_fit_slice (`count` cascades
/// before the failing one are valid).
inline CascadeFitResult cascade_fit(const CascadeInput& in, float lambda, std::uint32_t cascade_count,
                                    Cascade* out_cascades, std::size_t out_capacity) {
    using namespace detail;
    CascadeFitResult res;
    const char* why = nullptr;
    auto fail = [&res, &why](Status s, const char* what = nullptr) {
        res.status = s;
        res.detail = what ? what : why;
        return res;
    };
    if (!out_cascades && out_capacity > 0) return fail(Status::InvalidArgument, "out_cascades: null with out_capacity > 0");
    if (cascade_count == 0 || cascade_count > 16) return fail(Status::InvalidArgument, "cascade_count: outside 1..16");
    res.needed = cascade_count;
    const Status cs = cs_check_input(in, why);
    if (cs != Status::Ok) return fail(cs);
    if (!std::isfinite(lambda)) return fail(Status::NonFinite, "lambda: NaN or Inf");
    if (out_capacity < cascade_count) return fail(Status::BufferTooSmall, "out_capacity: below cascade_count");
    CsRays r;
    const Status st = cs_camera_rays(in.camera_proj, in.camera_depth, in.camera_reversed_z, r, why);
    if (st != Status::Ok) return fail(st);
    double f = r.far_depth;
    if (in.max_distance > 0.0f) f = std::fmin(f, double(in.max_distance));
    else if (std::isinf(f)) return fail(Status::InvalidArgument, "max_distance: 0 with an infinite far plane");
    const float nf = static_cast<float>(r.near_depth), ff = static_cast<float>(f);
    if (!std::isfinite(nf) || !std::isfinite(ff)) return fail(Status::Overflow, "camera_proj: near or far depth beyond float");
    const CascadeSplits sp = cascade_split_distances(nf, ff, lambda, cascade_count);
    if (sp.status != Status::Ok) return fail(sp.status, sp.detail);
    for (std::uint32_t i = 0; i <= cascade_count; ++i) res.splits[i] = sp.distances[i];
    for (std::uint32_t i = 0; i < cascade_count; ++i) {
        out_cascades[i] = cascade_fit_slice(in, sp.distances[i], sp.distances[i + 1]);
        if (out_cascades[i].status != Status::Ok) return fail(out_cascades[i].status, out_cascades[i].detail);
        res.count = i + 1;
    }
    res.status = Status::Ok;
    return res;
}

// ---- Sample distribution shadow maps (SDSM) ------------------------------------------------------
// Lauritzen, Salvi & Lefohn 2011, "Sample Distribution Shadow Maps" (I3D): the cascades cover only the
// view depths a depth-buffer reduction found visible (sec. 3: min/max of the depth buffer, then a
// logarithmic partition of [z_min, z_max], their default), each fitted tightly in light space (sec. 3.2).

/// The view-depth range of the visible receivers, converted from what glsl/cascades.glsl's reduction
/// (sk_sdsm_reduce_depth / sk_sdsm_reduce_minmax) leaves in its last 1x1 level: the min and max window
/// depth of every pixel that is not background.
struct CascadeSdsmRange {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    bool visible = false;   ///< false (with Ok): the reduction found no receiver (its empty marker)
    float view_min = 0.0f;  ///< [Units: wu, view depth d = -z_view > 0] nearest visible receiver
    float view_max = 0.0f;  ///< farthest visible receiver (>= view_min)
};

/// The empty marker of the reduction: a level with no receiver pixel holds (2, -1) (window depths
/// outside [0, 1]); SK_SDSM_EMPTY_MIN / SK_SDSM_EMPTY_MAX in glsl/cascades.glsl.
constexpr float kCascadeSdsmEmptyMin = 2.0f;
constexpr float kCascadeSdsmEmptyMax = -1.0f;

/// SDSM fit inputs. Fields marked (required) default to a value the fit rejects.
struct CascadeSdsmInput {
    /// Camera, light, map size, caster bounds and the light's depth convention, as for cascade_fit.
    /// Not used here: radius_quantum, scene bounds; stable_world_depth must be false (InvalidArgument).
    /// max_distance > 0 clamps the visible range's far end (0: no clamp; an infinite far plane is fine).
    CascadeInput camera;
    /// [Units: wu, view depth] [Limit: 0 < view_min <= view_max] the visible receivers' depth range:
    /// a CascadeSdsmRange, or a CPU min/max over the receivers' view depths (required). Clamped to the
    /// camera's near and far planes.
    float view_min = 0.0f;
    float view_max = 0.0f;
    std::uint32_t cascade_count = 4;  ///< [Limit: 1..16]
    /// [Limit: 0..1] split scheme over [z_min, z_max]: 1 (default) the logarithmic partition (SDSM's
    /// default), below 1 Zhang et al.'s practical blend with the uniform one.
    float lambda = 1.0f;
    /// [Limit: 1..64] the visible range is snapped outward to powers of 2^(1 / range_steps_per_octave)
    /// (a split moves only when z_min or z_max crosses a step; kept while within two steps: hysteresis).
    float range_steps_per_octave = 8.0f;
    /// [Limit: 0..0.5] each cascade's box is padded by this fraction of its extent on every side when
    /// it is built; later frames keep its size while the tight box still fits in it (whole-texel moves
    /// of an unchanged grid) and keep it bit-identical while the tight box stays inside it: the
    /// hysteresis against flicker. A box that must grow takes a quarter of its extent more; one whose
    /// tight box is much smaller (by half its extent beyond the margins) shrinks.
    float margin = 1.0f / 16.0f;
    /// Optional (nullptr: each cascade's whole view slice): cascade_count bounds (x0, y0, x1, y1) of
    /// the visible receivers of each cascade in the frame of cascade_sdsm_light_view (SDSM sec. 3.2's
    /// second reduction: sk_sdsm_reduce_bounds, each pixel in the cascade its view depth selects with
    /// the splits cascade_sdsm_splits gives for this same input). A cascade's box is its slice's box
    /// cut to these; x0 > x1 or y0 > y1 (the reduction's empty marker): no receiver, the slice's box.
    const glm::vec4* receiver_bounds = nullptr;
    /// Interior splits anchored in the world (default false: splits fixed in view depth): while the camera has not turned since
    /// `previous` (its view matrix's rotation entries within 1e-5 of the same), each interior split moves with
    /// the camera's travel along its view axis, so it stays on the same world plane and every visible
    /// point keeps its cascade (a point crossing a split changes texel size: flicker), while the shifted
    /// splits stay within four range steps of the log partition (a dolly keeps every box). The splits
    /// then follow the camera's travel: a small forward move changes them (not the boxes).
    bool world_splits = false;
};

/// One cascade's bounds in the light's view frame (rotation only, a fixed function of the light
/// direction, origin at the world origin: cascade_sdsm_light_view): x/y across the light, depth =
/// distance along the light. The x and y extents are rounded separately (texels need not be square).
struct CascadeSdsmBox {
    double x0 = 0.0, y0 = 0.0, x1 = 0.0, y1 = 0.0;
    double near_dist = 0.0, far_dist = 0.0;
};

/// The light frame of the SDSM boxes (world -> light view, a rotation), for the bounds reduction.
struct CascadeSdsmLightView {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    glm::mat4 view{1.0f};  ///< world -> light frame: x/y across the light, -z along its travel
};

/// Result of cascade_sdsm_fit; also the state the next frame's call reads (`previous`).
struct CascadeSdsmResult {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    std::size_t count = 0;          ///< cascades written to out_cascades (a valid prefix)
    std::size_t needed = 0;         ///< cascades the output needs (cascade_count)
    bool visible = false;           ///< false (with Ok): the clamped range is empty, nothing written (count 0)
    float range_min = 0.0f;         ///< the snapped visible range the splits cut: splits[0], splits[count]
    float range_max = 0.0f;
    float splits[17] = {};          ///< view depths: cascade i covers [splits[i], splits[i + 1]]
    CascadeSdsmBox boxes[16];       ///< each cascade's light-space bounds (what its view_proj maps to the map)
    std::uint32_t rebuilt = 0;      ///< bit i: cascade i's box was rebuilt (0: every box kept from `previous`)
    glm::vec4 light_position{0.0f}; ///< the light and map size the boxes belong to (a different one
    std::uint32_t shadow_map_size = 0;  ///< in the next call ignores `previous`)
    glm::mat4 camera_view{1.0f};    ///< the camera the splits were cut for (world_splits)
};

namespace detail {

/// SDSM size hysteresis (cs_sdsm_axis): a box axis that must grow takes kSdsmGrow of its tight extent
/// more than it needs; one is kept until it exceeds its need by kSdsmShrink of the tight extent.
constexpr double kSdsmGrow = 0.25;
constexpr double kSdsmShrink = 0.5;

/// Rounds v > 0 up to a multiple of 1/32 of its power of two (at most 3.125% larger): few distinct
/// lengths, each with a short binary fraction (b1 - b0 exact).
inline double cs_sdsm_round_up(double v) {
    const double step = std::ldexp(1.0, std::ilogb(v) - 5);
    return std::ceil(v / step) * step;
}

/// The light's view frame (rotation only): the stable fit's, anchored at the world origin.
inline glm::dmat4 cs_light_view(const glm::vec4& light_position) {
    const glm::dvec3 d = -glm::normalize(glm::dvec3(light_position));  // travel direction
    const glm::dvec3 sx = glm::normalize(glm::cross(d, cs_stable_up(d)));
    const glm::dvec3 sy = glm::cross(sx, d);
    glm::dmat4 lv(1.0);
    lv[0][0] = sx.x; lv[1][0] = sx.y; lv[2][0] = sx.z;
    lv[0][1] = sy.x; lv[1][1] = sy.y; lv[2][1] = sy.z;
    lv[0][2] = -d.x; lv[1][2] = -d.y; lv[2][2] = -d.z;
    return lv;
}

/// Checks the SDSM-specific inputs (after cs_check_input): Ok or the first problem.
inline Status cs_sdsm_check(const CascadeSdsmInput& in, const char*& why) {
    if (!std::isfinite(in.view_min)) return cs_fail(why, Status::NonFinite, "view_min: NaN or Inf");
    if (!std::isfinite(in.view_max)) return cs_fail(why, Status::NonFinite, "view_max: NaN or Inf");
    if (!std::isfinite(in.lambda)) return cs_fail(why, Status::NonFinite, "lambda: NaN or Inf");
    if (!std::isfinite(in.range_steps_per_octave)) return cs_fail(why, Status::NonFinite, "range_steps_per_octave: NaN or Inf");
    if (!std::isfinite(in.margin)) return cs_fail(why, Status::NonFinite, "margin: NaN or Inf");
    if (in.camera.stable_world_depth)
        return cs_fail(why, Status::InvalidArgument, "camera.stable_world_depth: set (SDSM's depth range follows the view)");
    if (!(in.view_min > 0.0f)) return cs_fail(why, Status::InvalidArgument, "view_min: <= 0");
    if (!(in.view_max >= in.view_min)) return cs_fail(why, Status::InvalidArgument, "view_max: below view_min");
    if (!(in.lambda >= 0.0f) || !(in.lambda <= 1.0f)) return cs_fail(why, Status::InvalidArgument, "lambda: outside [0, 1]");
    if (!(in.range_steps_per_octave >= 1.0f) || !(in.range_steps_per_octave <= 64.0f))
        return cs_fail(why, Status::InvalidArgument, "range_steps_per_octave: outside [1, 64]");
    if (!(in.margin >= 0.0f) || !(in.margin <= 0.5f)) return cs_fail(why, Status::InvalidArgument, "margin: outside [0, 0.5]");
    if (in.receiver_bounds)
        for (std::uint32_t i = 0; i < in.cascade_count && i < 16; ++i)
            if (!cs_finite(in.receiver_bounds[i])) return cs_fail(why, Status::NonFinite, "receiver_bounds: NaN or Inf");
    return Status::Ok;
}

/// The visible range [zmin, zmax] snapped outward to powers of r = 2^(1/steps) (SDSM sec. 3's log
/// partition is scale-free, so is the grid), keeping the previous end while it still covers and is
/// within two steps (hysteresis).
inline void cs_sdsm_snap_range(double zmin, double zmax, double steps, const CascadeSdsmResult* prev, double& lo,
                               double& hi) {
    const double klo = std::floor(std::log2(zmin) * steps), khi = std::ceil(std::log2(zmax) * steps);
    lo = std::exp2(klo / steps);  // exact at whole octaves
    hi = std::exp2(khi / steps);
    if (lo > zmin) lo = std::exp2((klo - 1.0) / steps);  // log2/exp2 rounding
    if (hi < zmax) hi = std::exp2((khi + 1.0) / steps);
    if (!(hi > lo)) hi = lo * std::exp2(1.0 / steps);  // a zero range: one step
    const double r2 = std::exp2(2.0 / steps);
    if (prev) {
        const double plo = prev->range_min, phi = prev->range_max;
        if (plo <= zmin && zmin < plo * r2 && phi > plo) lo = plo;
        if (phi >= zmax && zmax > phi / r2 && phi > lo) hi = phi;
    }
}

/// Tight light-space box of the view slice [d0, d1] (its 8 corners, SDSM sec. 3.2), the near side
/// pulled back to the caster bounds, cut to the receiver bounds rb (nullptr: none), padded by the
/// float error of a vertex shader at that magnitude. pw receives the (unpadded) box's world corners.
inline CascadeSdsmBox cs_sdsm_tight_box(const CascadeInput& in, const CsRays& r, const glm::dmat4& iv,
                                        const glm::dmat4& lv, double d0, double d1, const glm::vec4* rb,
                                        glm::dvec3 (&pw)[8]) {
    CascadeSdsmBox b;
    b.x0 = b.y0 = b.near_dist = std::numeric_limits<double>::infinity();
    b.x1 = b.y1 = b.far_dist = -b.x0;
    double mag = 0.0;
    for (int i = 0; i < 8; ++i) {
        pw[i] = glm::dvec3(iv * glm::dvec4(cs_corner(r, i & 3, i < 4 ? d0 : d1), 1.0));
        const glm::dvec3 l = glm::dvec3(lv * glm::dvec4(pw[i], 1.0));
        b.x0 = std::fmin(b.x0, l.x); b.x1 = std::fmax(b.x1, l.x);
        b.y0 = std::fmin(b.y0, l.y); b.y1 = std::fmax(b.y1, l.y);
        b.near_dist = std::fmin(b.near_dist, -l.z); b.far_dist = std::fmax(b.far_dist, -l.z);
        mag = std::fmax(mag, std::fmax(std::fabs(pw[i].x), std::fmax(std::fabs(pw[i].y), std::fabs(pw[i].z))));
    }
    if (in.has_caster_bounds)
        for (int c = 0; c < 8; ++c) {
            const glm::dvec3 p((c & 1) ? in.caster_max.x : in.caster_min.x, (c & 2) ? in.caster_max.y : in.caster_min.y,
                               (c & 4) ? in.caster_max.z : in.caster_min.z);
            b.near_dist = std::fmin(b.near_dist, -(lv * glm::dvec4(p, 1.0)).z);
        }
    if (rb && rb->x <= rb->z && rb->y <= rb->w) {  // cut to the receivers (SDSM sec. 3.2), within the slice
        b.x0 = std::fmax(b.x0, double(rb->x)); b.x1 = std::fmin(b.x1, double(rb->z));
        b.y0 = std::fmax(b.y0, double(rb->y)); b.y1 = std::fmin(b.y1, double(rb->w));
        if (b.x1 < b.x0) b.x0 = b.x1 = 0.5 * (b.x0 + b.x1);  // receivers beyond the slice (float rounding)
        if (b.y1 < b.y0) b.y0 = b.y1 = 0.5 * (b.y0 + b.y1);
    }
    const double pad = 16.0 * 5.9604644775390625e-8 * mag;  // 16 u |p|: float positions, float matrix
    for (int i = 0; i < 8; ++i)  // the box's corners bound every receiver in it: what the landing check reads
        pw[i] = glm::dvec3(glm::transpose(lv) * glm::dvec4((i & 1) ? b.x1 : b.x0, (i & 2) ? b.y1 : b.y0,
                                                           -((i & 4) ? b.far_dist : b.near_dist), 0.0));
    b.x0 -= pad; b.y0 -= pad; b.near_dist -= pad;
    b.x1 += pad; b.y1 += pad; b.far_dist += pad;
    return b;
}

/// Length of a box axis for the tight extent e grown by `grow` (a fraction, on both sides together):
/// rounded up (cs_sdsm_round_up) with one texel of border on each side.
inline double cs_sdsm_len(double e, double grow, double S) {
    return cs_sdsm_round_up(std::fmax(e * (1.0 + grow), 1e-30) * S / (S - 2.0));
}

/// One axis of the box: its length and its start on the origin-anchored texel grid. The length is
/// the size hysteresis: the previous length (prev = {p0, p1}; nullptr: none) is kept while it still
/// holds the tight extent [t0, t1] with a texel of border on each side and is not much larger (at
/// most cs_sdsm_len of kSdsmShrink beyond the margins); a box that must grow takes kSdsmGrow of its
/// extent beyond the margins, one that is much too large shrinks to `need` (the margins alone). The
/// start is kept while the kept length covers [t0, t1]; else the box is centred on it and snapped to
/// whole texels (Valient 2008's stable snapping: an unchanged length moves by whole texels of an
/// unchanged grid, which leaves a static scene's shadows where they were). Returns whether the axis
/// is prev's, bit for bit.
inline bool cs_sdsm_axis(double t0, double t1, double m, double S, const double* prev, double& b0, double& b1) {
    const double e = t1 - t0, need = cs_sdsm_len(e, 2.0 * m, S);
    double len = need;
    if (prev) {
        const double pl = prev[1] - prev[0];
        if (pl >= std::fmax(e, 1e-30) * S / (S - 2.0) * (1.0 - 1e-12) && pl <= cs_sdsm_len(e, 2.0 * m + kSdsmShrink, S) * (1.0 + 1e-12)) {
            if (prev[0] <= t0 && prev[1] >= t1) {
                b0 = prev[0];
                b1 = prev[1];
                return true;
            }
            len = pl;  // b1 - b0 rounds
        } else if (pl < need) {
            len = cs_sdsm_len(e, 2.0 * m + kSdsmGrow, S);
        }
    }
    const double texel = len / S;
    b0 = std::floor((0.5 * (t0 + t1) - 0.5 * len) / texel) * texel;
    b1 = b0 + len;
    return false;
}

/// The box a cascade is rendered with: each axis by cs_sdsm_axis, the depth range kept while it holds
/// t and is not much larger (within 4 margins and steps), else snapped outward to 1/8 of its power of
/// two. `kept` says whether the whole box is `prev`'s, bit for bit (its slice's splits may have moved:
/// world_splits; the box holds the new slice's tight box either way).
inline CascadeSdsmBox cs_sdsm_box(const CascadeSdsmBox& t, const CascadeSdsmBox* prev, double m,
                                  double S, bool& kept) {
    const double dd = t.far_dist - t.near_dist;
    const double dstep = std::ldexp(1.0, std::ilogb(std::fmax(dd * (1.0 + 2.0 * m), 1e-30)) - 3);
    const bool depth_ok = prev && prev->near_dist <= t.near_dist && prev->far_dist >= t.far_dist &&
                          prev->far_dist - prev->near_dist <= dd * (1.0 + 4.0 * m) + 4.0 * dstep;
    CascadeSdsmBox b;
    const double px[2] = {prev ? prev->x0 : 0.0, prev ? prev->x1 : 0.0};
    const double py[2] = {prev ? prev->y0 : 0.0, prev ? prev->y1 : 0.0};
    const bool kx = cs_sdsm_axis(t.x0, t.x1, m, S, prev ? px : nullptr, b.x0, b.x1);
    const bool ky = cs_sdsm_axis(t.y0, t.y1, m, S, prev ? py : nullptr, b.y0, b.y1);
    kept = kx && ky && depth_ok;
    if (depth_ok) {
        b.near_dist = prev->near_dist;
        b.far_dist = prev->far_dist;
        return b;
    }
    b.near_dist = std::floor((t.near_dist - m * dd) / dstep) * dstep;
    b.far_dist = std::ceil((t.far_dist + m * dd) / dstep) * dstep;
    if (!(b.far_dist > b.near_dist)) b.far_dist = b.near_dist + dstep;
    return b;
}

/// The cascade of box b: its matrix (light view, orthographic box, the light's clip convention), the
/// texel size and anchor, the box's circumscribed sphere. Overflow when the float matrix does not map
/// the slice's corners pw inside (cs_float_landing_ok).
inline Cascade cs_sdsm_cascade(const CascadeInput& in, const glm::dmat4& lv, const CascadeSdsmBox& b,
                               const glm::dvec3 (&pw)[8]) {
    Cascade out;
    const double ex = b.x1 - b.x0, ey = b.y1 - b.y0, dz = b.far_dist - b.near_dist, S = double(in.shadow_map_size);
    glm::dmat4 pr(1.0);
    pr[0][0] = 2.0 / ex;
    pr[1][1] = 2.0 / ey;
    pr[2][2] = -2.0 / dz;
    pr[3][0] = -(b.x0 + b.x1) / ex;
    pr[3][1] = -(b.y0 + b.y1) / ey;
    pr[3][2] = -(b.far_dist + b.near_dist) / dz;
    glm::dmat4 conv(1.0);
    if (in.light_depth == ClipDepth::ZeroToOne) {
        conv[2][2] = in.light_reversed_z ? -0.5 : 0.5;
        conv[3][2] = 0.5;
    } else if (in.light_reversed_z) {
        conv[2][2] = -1.0;
    }
    const glm::dmat4 m = conv * pr * lv;
    out.view_proj = glm::mat4(m);
    const double tx = ex / S, ty = ey / S, texel = std::fmax(tx, ty);
    const glm::dvec3 cl(0.5 * (b.x0 + b.x1), 0.5 * (b.y0 + b.y1), -0.5 * (b.near_dist + b.far_dist));
    const glm::dvec3 cw = glm::dvec3(glm::transpose(lv) * glm::dvec4(cl, 0.0));  // lv is a rotation
    const double rad = 0.5 * std::sqrt(ex * ex + ey * ey + dz * dz);
    if (!cs_finite(m) || !cs_finite(out.view_proj) || !(static_cast<float>(texel) > 0.0f) ||
        !std::isfinite(static_cast<float>(rad)) || !cs_finite(glm::vec3(cw)) || !cs_float_landing_ok(in, out.view_proj, pw)) {
        out = Cascade{};
        out.status = Status::Overflow;
        out.detail = "camera_view: the cascade beyond float, or too small against its distance from the origin";
        return out;
    }
    out.sphere = glm::vec4(glm::vec3(cw), static_cast<float>(rad));
    out.texel_world_size = static_cast<float>(texel);
    out.texel_anchor = glm::dvec2(std::round(b.x0 / tx), std::round(b.y0 / ty));
    out.status = Status::Ok;
    return out;
}

}  // namespace detail

/// Converts the reduction's last level (min and max window depth of the non-background pixels, in
/// glDepthRange(0, 1)) to view depths with the camera projection the depth buffer was drawn with (any
/// projection cascade_fit accepts; reversed-Z: the smallest window depth is the farthest).
/// (kCascadeSdsmEmptyMin, kCascadeSdsmEmptyMax): visible = false with Ok.
/// Status: NonFinite (NaN/Inf, a singular projection), InvalidArgument (a depth outside [0, 1],
/// window_min > window_max, a depth at or behind the eye or beyond infinity).
inline CascadeSdsmRange cascade_sdsm_view_range(const glm::mat4& camera_proj, ClipDepth camera_depth, bool reversed_z,
                                                float window_min, float window_max) {
    CascadeSdsmRange out;
    if (!std::isfinite(window_min) || !std::isfinite(window_max) || !detail::cs_finite(camera_proj)) {
        out.status = Status::NonFinite;
        out.detail = !detail::cs_finite(camera_proj) ? "camera_proj: NaN or Inf" : "window_min, window_max: NaN or Inf";
        return out;
    }
    if (window_min == kCascadeSdsmEmptyMin && window_max == kCascadeSdsmEmptyMax) {
        out.status = Status::Ok;
        return out;
    }
    if (!(window_min >= 0.0f) || !(window_max <= 1.0f) || !(window_min <= window_max)) {
        out.status = Status::InvalidArgument;
        out.detail = !(window_min <= window_max) ? "window_min: > window_max" : "window_min, window_max: outside [0, 1]";
        return out;
    }
    const glm::dmat4 ip = glm::inverse(glm::dmat4(camera_proj));
    if (!detail::cs_finite(ip)) {
        out.status = Status::NonFinite;
        out.detail = "camera_proj: singular";
        return out;
    }
    double d[2];
    const float w[2] = {window_min, window_max};
    for (int i = 0; i < 2; ++i) {
        const double z = camera_depth == ClipDepth::ZeroToOne ? double(w[i]) : 2.0 * double(w[i]) - 1.0;
        const glm::dvec4 h = ip * glm::dvec4(0.0, 0.0, z, 1.0);  // the depth of an NDC z is the same over the screen
        d[i] = -h.z / h.w;
        if (!(std::fabs(h.w) > 0.0) || !std::isfinite(d[i]) || !(d[i] > 0.0)) {
            out.status = Status::InvalidArgument;
            out.detail = "window_min, window_max: a depth at or behind the eye or at infinity";
            return out;
        }
    }
    (void)reversed_z;  // the order follows from the projection itself
    const double lo = std::fmin(d[0], d[1]), hi = std::fmax(d[0], d[1]);
    out.view_min = static_cast<float>(lo);
    out.view_max = static_cast<float>(hi);
    if (!std::isfinite(out.view_max) || !(out.view_min > 0.0f)) {
        out = CascadeSdsmRange{};
        out.status = Status::Overflow;
        out.detail = "window_min, window_max: a view depth beyond float";
        return out;
    }
    out.visible = true;
    out.status = Status::Ok;
    return out;
}

namespace detail {

/// CascadeSdsmInput::world_splits: with the camera unturned since `prev` (rotation entries within 1e-5:
/// lookAt's float rounding along a dolly), every view depth changes by
/// the same c = the view translation's z change (d = -(R p + T).z), so prev's interior splits plus c lie
/// on prev's world planes; they replace res's log-partition splits when they stay increasing inside
/// (range_min, range_max) and within four steps of the range grid of the log partition's.
inline void cs_sdsm_world_splits(const CascadeSdsmInput& in, const CascadeSdsmResult& prev, CascadeSdsmResult& res) {
    const glm::mat4& a = prev.camera_view;
    const glm::mat4& b = in.camera.camera_view;
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r)
            if (!(std::fabs(double(a[c][r]) - double(b[c][r])) <= 1e-5)) return;  // turned: not the same view-depth planes
    const double shift = double(a[3][2]) - double(b[3][2]);
    const double tol = 4.0 / double(in.range_steps_per_octave);  // half an octave at the default 8 steps
    const std::uint32_t n = in.cascade_count;
    float out[17];
    float last = res.splits[0];
    for (std::uint32_t i = 1; i < n; ++i) {
        out[i] = static_cast<float>(double(prev.splits[i]) + shift);
        if (!(out[i] > last) || !(std::fabs(std::log2(double(out[i]) / double(res.splits[i]))) <= tol)) return;
        last = out[i];
    }
    if (!(res.splits[n] > last)) return;
    for (std::uint32_t i = 1; i < n; ++i) res.splits[i] = out[i];
}

/// What cascade_sdsm_splits and cascade_sdsm_fit share: validation, the camera, the previous fit it
/// may keep, the clamped and snapped visible range and its splits (res.splits, range_min/max).
/// Returns Ok with res.visible false when the clamped range is empty.
inline Status cs_sdsm_prepare(const CascadeSdsmInput& in, const CascadeSdsmResult* previous, CsRays& r,
                              glm::dmat4& iv, const CascadeSdsmResult*& prev, CascadeSdsmResult& res, const char*& why) {
    if (in.cascade_count == 0 || in.cascade_count > 16) return cs_fail(why, Status::InvalidArgument, "cascade_count: outside 1..16");
    res.needed = in.cascade_count;
    Status st = cs_check_input(in.camera, why);
    if (st == Status::Ok) st = cs_sdsm_check(in, why);
    if (st != Status::Ok) return st;
    st = cs_camera_rays(in.camera.camera_proj, in.camera.camera_depth, in.camera.camera_reversed_z, r, why);
    if (st != Status::Ok) return st;
    const glm::dmat4 V(in.camera.camera_view);
    const double vdet = glm::determinant(V);
    if (!std::isfinite(vdet) || !(std::fabs(vdet) > 1e-300)) return cs_fail(why, Status::InvalidArgument, "camera.camera_view: singular");
    iv = glm::inverse(V);
    if (!cs_finite(iv)) return cs_fail(why, Status::InvalidArgument, "camera.camera_view: inverse not finite");
    res.light_position = in.camera.light_position;
    res.shadow_map_size = in.camera.shadow_map_size;
    const bool same = previous && previous->status == Status::Ok && previous->visible &&
                      previous->light_position == in.camera.light_position &&
                      previous->shadow_map_size == in.camera.shadow_map_size && previous->needed == in.cascade_count;
    prev = same ? previous : nullptr;
    double far = r.far_depth;
    if (in.camera.max_distance > 0.0f) far = std::fmin(far, double(in.camera.max_distance));
    const double zmin = std::fmax(double(in.view_min), r.near_depth), zmax = std::fmin(double(in.view_max), far);
    res.visible = zmax >= zmin;  // else everything visible lies beyond the shadow distance
    if (!res.visible) return Status::Ok;
    double lo = 0.0, hi = 0.0;
    cs_sdsm_snap_range(zmin, zmax, double(in.range_steps_per_octave), prev, lo, hi);
    const CascadeSplits sp = cascade_split_distances(static_cast<float>(lo), static_cast<float>(hi), in.lambda,
                                                     in.cascade_count);
    if (sp.status != Status::Ok) {
        why = sp.status == Status::NonFinite ? "view_min, view_max: the snapped range beyond float" : sp.detail;
        return sp.status == Status::NonFinite ? Status::Overflow : sp.status;
    }
    res.range_min = sp.distances[0];
    res.range_max = sp.distances[in.cascade_count];
    for (std::uint32_t i = 0; i <= in.cascade_count; ++i) res.splits[i] = sp.distances[i];
    res.camera_view = in.camera.camera_view;
    if (prev && in.world_splits) cs_sdsm_world_splits(in, *prev, res);
    return Status::Ok;
}

}  // namespace detail

/// The light frame of the SDSM boxes and of CascadeSdsmInput::receiver_bounds (world -> light view:
/// the rotation the stable fit uses, a fixed function of the light direction). Status: InvalidLight
/// (not a directional light, NaN/Inf, zero).
inline CascadeSdsmLightView cascade_sdsm_light_view(const glm::vec4& light_position) {
    CascadeSdsmLightView out;
    if (!detail::cs_finite(light_position) || light_position.w != 0.0f ||
        (light_position.x == 0.0f && light_position.y == 0.0f && light_position.z == 0.0f)) {
        out.status = Status::InvalidLight;
        out.detail = !detail::cs_finite(light_position) ? "light_position: NaN or Inf"
                     : light_position.w != 0.0f       ? "light_position: w != 0 (SDSM needs a directional light)"
                                                      : "light_position: (0, 0, 0, 0)";
        return out;
    }
    out.view = glm::mat4(detail::cs_light_view(light_position));
    out.status = Status::Ok;
    return out;
}

/// The splits cascade_sdsm_fit will use for the same input and `previous` (the range is snapped and
/// kept the same way), for the second reduction (receiver bounds per cascade) before the fit: only
/// `status`, `visible`, `needed`, `range_min`, `range_max` and `splits` are filled. receiver_bounds
/// is not read. Status: as cascade_sdsm_fit's validation.
inline CascadeSdsmResult cascade_sdsm_splits(const CascadeSdsmInput& in, const CascadeSdsmResult* previous) {
    CascadeSdsmResult res;
    CascadeSdsmInput plain = in;
    plain.receiver_bounds = nullptr;
    detail::CsRays r;
    glm::dmat4 iv(1.0);
    const CascadeSdsmResult* prev = nullptr;
    const char* why = nullptr;
    const Status st = detail::cs_sdsm_prepare(plain, previous, r, iv, prev, res, why);
    if (st != Status::Ok) {
        res = CascadeSdsmResult{};
        res.status = st;
        res.detail = why;
        return res;
    }
    res.status = Status::Ok;
    return res;
}

/// Sample distribution shadow maps (Lauritzen et al. 2011): splits cut the visible range [view_min,
/// view_max] (clamped to the camera, snapped outward to powers of 2^(1/range_steps_per_octave)) with
/// the log partition (lambda 1); each cascade's map is the tight light-space box of its view slice
/// (cut to receiver_bounds when given; depth from the slice with its near side pulled back to the
/// caster bounds), grown by the margin, each extent rounded up to 1/32 of its power of two plus a
/// texel of border, snapped to whole texels of the origin-anchored grid. `previous` (nullptr: none; a
/// result of another light, map size or cascade count is ignored) is last frame's result: its range
/// ends are kept while they still cover, each box's size while the tight box fits in it (a box grows
/// only when it must, by a quarter more, and shrinks only when much too large: a resize moves filtered
/// edges) and its place while it covers (hysteresis), so a small camera move changes nothing, bit for
/// bit, and a larger one moves boxes by whole texels. out_cascades holds out_capacity Cascade elements (nullptr only with 0); it needs
/// cascade_count (`needed`). Every visible point of a slice (within its receiver bounds) maps inside
/// its cascade through the float matrix, in float.
/// Status: BufferTooSmall, NonFinite, InvalidLight (not a directional light), InvalidArgument (a field
/// outside its [Limit], a camera cascade_fit rejects), Overflow (beyond float; a slice too small
/// against its distance from the origin), with `count` valid cascades before the failing one.
inline CascadeSdsmResult cascade_sdsm_fit(const CascadeSdsmInput& in, const CascadeSdsmResult* previous,
                                          Cascade* out_cascades, std::size_t out_capacity) {
    using namespace detail;
    CascadeSdsmResult res;
    const char* why = nullptr;
    auto fail = [&res, &why](Status s, const char* what = nullptr) {
        res.status = s;
        res.detail = what ? what : why;
        res.visible = false;
        return res;
    };
    if (!out_cascades && out_capacity > 0) return fail(Status::InvalidArgument, "out_cascades: null with out_capacity > 0");
    CsRays r;
    glm::dmat4 iv(1.0);
    const CascadeSdsmResult* prev = nullptr;
    const Status st = cs_sdsm_prepare(in, previous, r, iv, prev, res, why);
    if (st != Status::Ok) return fail(st);
    if (out_capacity < in.cascade_count) return fail(Status::BufferTooSmall, "out_capacity: below cascade_count");
    if (!res.visible) {
        res.status = Status::Ok;
        return res;
    }
    const glm::dmat4 lv = cs_light_view(in.camera.light_position);
    const double S = double(in.camera.shadow_map_size);
    for (std::uint32_t i = 0; i < in.cascade_count; ++i) {
        glm::dvec3 pw[8];
        const CascadeSdsmBox t = cs_sdsm_tight_box(in.camera, r, iv, lv, double(res.splits[i]), double(res.splits[i + 1]),
                                                   in.receiver_bounds ? in.receiver_bounds + i : nullptr, pw);
        bool kept = false;
        res.boxes[i] = cs_sdsm_box(t, prev ? &prev->boxes[i] : nullptr, double(in.margin), S, kept);
        if (!kept) res.rebuilt |= 1u << i;
        out_cascades[i] = cs_sdsm_cascade(in.camera, lv, res.boxes[i], pw);
        if (out_cascades[i].status != Status::Ok) return fail(out_cascades[i].status, out_cascades[i].detail);
        out_cascades[i].split_near = res.splits[i];
        out_cascades[i].split_far = res.splits[i + 1];
        res.count = i + 1;
    }
    res.status = Status::Ok;
    return res;
}

/// Cascade covering a view depth: the first i with view_depth <= splits[i + 1]. splits holds
/// count + 1 floats (cascade_fit's `splits`, or CascadeSplits::distances), strictly increasing.
/// index -1 (with Ok): before splits[0] or beyond splits[count]. Status: InvalidArgument (nullptr,
/// count 0 or > 16, splits not finite and increasing), NonFinite (view_depth NaN/Inf).
inline CascadeIndex cascade_select_by_depth(float view_depth, const float* splits, std::uint32_t count) {
    CascadeIndex res;
    if (!splits || count == 0 || count > 16) {
        res.status = Status::InvalidArgument;
        res.detail = !splits ? "splits: null" : "count: outside 1..16";
        return res;
    }
    for (std::uint32_t i = 0; i <= count; ++i)
        if (!std::isfinite(splits[i]) || (i > 0 && !(splits[i] > splits[i - 1]))) {
            res.status = Status::InvalidArgument;
            res.detail = "splits: not finite and strictly increasing";
            return res;
        }
    if (!std::isfinite(view_depth)) {
        res.status = Status::NonFinite;
        res.detail = "view_depth: NaN or Inf";
        return res;
    }
    res.status = Status::Ok;
    if (!(view_depth >= splits[0])) return res;
    for (std::uint32_t i = 0; i < count; ++i)
        if (view_depth <= splits[i + 1]) {
            res.index = static_cast<int>(i);
            return res;
        }
    return res;
}

/// First cascade whose bounding sphere contains the world point (tighter at rotation than depth
/// selection: uses the whole sphere the stable fit covers). cascades holds count elements, each with
/// status Ok. index -1 (with Ok): in no sphere. Status: InvalidArgument (nullptr, count 0 or > 16, a
/// cascade not Ok), NonFinite (NaN/Inf in world_pos).
inline CascadeIndex cascade_select_by_sphere(const glm::vec3& world_pos, const Cascade* cascades, std::uint32_t count) {
    CascadeIndex res;
    if (!cascades || count == 0 || count > 16) {
        res.status = Status::InvalidArgument;
        res.detail = !cascades ? "cascades: null" : "count: outside 1..16";
        return res;
    }
    for (std::uint32_t i = 0; i < count; ++i)
        if (cascades[i].status != Status::Ok || !detail::cs_finite(cascades[i].sphere)) {
            res.status = Status::InvalidArgument;
            res.detail = "cascades: one not Ok or with a non-finite sphere";
            return res;
        }
    if (!detail::cs_finite(world_pos)) {
        res.status = Status::NonFinite;
        res.detail = "world_pos: NaN or Inf";
        return res;
    }
    res.status = Status::Ok;
    for (std::uint32_t i = 0; i < count; ++i) {
        const glm::dvec3 d = glm::dvec3(world_pos) - glm::dvec3(glm::vec3(cascades[i].sphere));
        const double r = double(cascades[i].sphere.w);
        if (glm::dot(d, d) <= r * r) {
            res.index = static_cast<int>(i);
            return res;
        }
    }
    return res;
}

/// Weight of the next cascade in the blend band: 0 until the last band_fraction of [split_near,
/// split_far], rising linearly to 1 at split_far. Total: in [0, 1]; NaN/Inf input, an empty range
/// (split_far <= split_near) or band_fraction <= 0 give 0; band_fraction > 1 counts as 1.
inline float cascade_blend_weight(float view_depth, float split_near, float split_far, float band_fraction) {
    if (!std::isfinite(view_depth) || !std::isfinite(split_near) || !std::isfinite(split_far) ||
        !std::isfinite(band_fraction) || !(split_far > split_near) || !(band_fraction > 0.0f))
        return 0.0f;
    const float b = band_fraction > 1.0f ? 1.0f : band_fraction;
    double w;
    if (std::isfinite(split_far - split_near)) {
        const float start = split_far - b * (split_far - split_near);
        const float den = split_far - start;
        if (!(den > 0.0f)) return view_depth >= split_far ? 1.0f : 0.0f;  // band narrower than a float step
        w = double(view_depth - start) / double(den);
    } else {  // the range overflows float: same formula in double
        const double start = double(split_far) - double(b) * (double(split_far) - double(split_near));
        w = (double(view_depth) - start) / (double(split_far) - start);
    }
    return w > 0.0 ? (w < 1.0 ? static_cast<float>(w) : 1.0f) : 0.0f;  // NaN -> 0
}

}  // namespace shadowkit
