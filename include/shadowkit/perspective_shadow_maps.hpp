// shadowkit/perspective_shadow_maps.hpp - warped shadow-map matrices (uniform, PSM, LiSPSM, TSM) that
// change continuously with the camera and the light, and the perspective aliasing error to compare them.
//
// Usage:
//   #include <shadowkit/perspective_shadow_maps.hpp>
//   shadowkit::WarpInput in;
//   in.camera_view = view; in.camera_proj = proj;          // GLM; finite, infinite or epsilon-tweaked far
//   in.max_distance = 200.0f;                             // required when the far plane is infinite
//   in.light_position = glm::vec4(to_sun, 0.0f);          // w = 0: the direction toward the light
//   in.has_scene_bounds = true; in.scene_min = lo; in.scene_max = hi;   // receivers (and casters)
//   shadowkit::WarpResult w = shadowkit::warp_lispsm_matrix(in);       // or warp_uniform/psm/tsm_matrix
//   if (w.status == shadowkit::Status::Ok && w.visible) {
//       // shadow pass: draw the casters with w.light_view_proj, glFrontFace(GL_CCW) as for any map.
//       // TSM (w.separate_depth): write gl_FragDepth = sk_warp_map_depth(w.depth_view_proj * p, ...)
//       // (Martin & Tan's undistorted depth). Lookup: sk_warp_shadow(map, w.light_view_proj,
//       // w.depth_view_proj, world_pos, bias, false) from glsl/perspective_shadow_maps.glsl.
//   }
//   shadowkit::WarpAliasingStats a = shadowkit::warp_measure_aliasing(in, w.light_view_proj, 2048, {1920, 1080}, 32, 32, 32);
//
// Conventions:
// Units: world units [wu]. Matrices are GLM (column-major), right-handed; the camera looks down -z.
// Lights: a light is its homogeneous position `light_position` = (x, y, z, w), as OpenGL's
// GL_POSITION and Everitt & Kilgard use it. w > 0: a point or spot light at xyz / w. w = 0: a
// directional light at infinity in direction xyz, the direction *toward* the light (its rays travel
// along -xyz). w < 0, (0, 0, 0, 0) and NaN/Inf are rejected with Status::InvalidLight.
// Camera: any projection whose near plane is in front of the eye (near > 0): finite far, far = +inf,
//   the epsilon-tweaked P_inf of infinite_projection.hpp (its NDC far plane un-projects behind the eye:
//   such a far plane counts as infinite), GL or zero-to-one clip depth, reversed-Z. `max_distance`
//   clamps the far plane and is required when it is infinite. A near plane at or behind the eye, near
//   >= far and a singular matrix give Status::InvalidArgument.
// Results: a non-Ok result's `detail` names the offending input and the rule ("camera_proj: near plane
//   at or behind the eye"), a static string; nullptr when Ok.
// Clip depth: `light_depth` / `light_reversed_z` choose the depth convention of the matrices built.
//   Points nearer the light get smaller depth (larger with reversed_z) for every method, including
//   PSM's inverted (light-sink) case, so the usual LESS (GREATER) compare works.
// Winding: every method preserves orientation. A triangle whose front side faces the light is
//   counter-clockwise in the light's window, as with glm::lookAt * glm::ortho / glm::perspective:
//   det(light_view_proj) < 0 (> 0 with light_reversed_z). Keep glFrontFace(GL_CCW) in the shadow pass;
//   culling back (or front) faces there works as for a plain shadow map, for every method and light.
// TSM depth: `light_view_proj` alone is a valid map (x, y and depth), but its depth is warped by the
//   trapezoid (compressed by up to eta / (eta + lambda) at the far end). `depth_view_proj` is the
//   light's own post-perspective depth, as Martin & Tan keep it (their TSM recipe writes it per
//   fragment): render the map with gl_FragDepth from it (sk_warp_map_depth) and compare against it
//   (`separate_depth`); in the report this cuts TSM's misclassified pixels 7 to 10 times at 512^2
//   (docs/perspective_shadow_maps.md). For the other methods both matrices are equal.
// Continuity: for a fixed scene and camera, every matrix is a continuous function of the light
//   (no jumps at the LiSPSM fade, the TSM fallback, PSM's slide-back or its light-sink switch),
//   except within 0.5 degree of the light being parallel or anti-parallel to the view's center line
//   (directional: its direction; point light: the light on or near that line). There the map's roll
//   about the light axis is free: it follows the center line projected onto the map, which turns half
//   a turn as the light passes through the view direction (exactly parallel: the camera's up vector),
//   so the image may rotate by up to 180 degrees within that cone. Measured on random scenes with
//   0.002 degree steps: receiver points move < 0.01 NDC per step outside it (tests/unit). The fits
//   use only quantities that also move continuously with the camera (bounding-box centers and
//   extents, a point light's narrowest-cone axis; never means of vertex lists), but camera sweeps are
//   not measured.
// Point lights: every fit aims at the axis of the narrowest cone around the light holding the
//   receivers (and their extension toward it), as light_frustum.hpp does, centered on their angular
//   extent; LightInsideVolume only when no frustum of half-angle < ~89.4 degrees holds them. The
//   receivers' extension toward a point light stops at max(distance to the casters' box, 1e-4 x the
//   farthest receiver's distance): with the light inside the casters' box, casters nearer the light
//   than 1e-4 x that distance lie outside every fit (PSM, LiSPSM, TSM and the uniform fit alike).
//   Keep such casters out of the box (a light's own fixture) or use a cube map.
// Buffers: none; no call allocates.
//
// Based on:
//   Stamminger & Drettakis 2002, "Perspective Shadow Maps" (post-perspective light; directional
//     lights become point lights; slide-back of the virtual camera), Kozlov 2004, "Perspective Shadow
//     Maps: Care and Feeding" (GPU Gems, ch. 14: lights behind the viewer as inverted projections).
//   Wimmer, Scherzer & Purgathofer 2004, "Light Space Perspective Shadow Maps" (n_opt, falloff).
//   Martin & Tan 2004, "Anti-aliasing and Continuity with Trapezoidal Shadow Maps" (80% rule, the
//     trapezoid transformation N_T, depth from the light's post-perspective space).
//   Lloyd et al. 2006/2008, "Warping and Partitioning for Low Error Shadow Maps" (aliasing metric, the
//     general LiSPSM n_opt; with the virtual near/far planes of filament's ShadowMap::applyLISPSM);
//     Moschig, "Apelles" thesis, eq. 3.17 (dp/ds = (z_n / z) (dz / ds) cos(alpha)).
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

/// The four fits of this header (for warp_matrix).
enum class WarpMethod { Uniform, Psm, Lispsm, Tsm };

/// LiSPSM's warp distance n_opt. Lloyd: Lloyd et al. 2006's general n_opt (eta = 0): the near distance
/// z_n is used as is, with filament's virtual near and far planes. Wimmer: Wimmer et al.'s reference code,
/// z_n / sin(gamma) (shadowkit 0.1.0 before issue 25): a weaker warp as the light nears the view direction.
enum class LispsmNOpt { Lloyd, Wimmer };

/// Tuning. The values below are the defaults; every field is checked (InvalidArgument outside its limit).
struct WarpOptions {
    /// LiSPSM: multiplies n_opt (> 1 weaker warp, < 1 stronger). [Limit: > 0]
    float lispsm_n_scale = 1.0f;
    /// LiSPSM: below this sin(gamma) (gamma: angle between the view and the light) the warp is off
    /// (uniform); between it and 1.5 times it the warp fades out continuously (n -> infinity). filament
    /// uses 0.02 (~1.15 deg). [Limit: 0 <= x < 0.5]
    float lispsm_min_sin_gamma = 0.02f;
    /// TSM: at |cos gamma| >= this the fit is uniform (DagorEngine: 0.95); the warp fades out over the
    /// 0.05 below it. [Limit: 0.05 < x <= 1]
    float tsm_max_abs_cos_gamma = 0.95f;
    /// TSM: view depth [wu] of the focus point; <= 0: sqrt(near * far) of the receivers' depth range.
    float tsm_focus_depth = 0.0f;
    /// TSM: fraction of the map given to the region in front of the focus point (the 80% rule). [Limit: 0 < x < 1]
    float tsm_focus_ratio = 0.8f;
    /// PSM: the virtual camera's near plane is at least this fraction of the body's depth range. [Limit: >= 0]
    float psm_min_near_fraction = 0.02f;
    /// PSM: extra slide-back [wu] on top of what keeps all casters in front of the virtual camera. [Limit: >= 0]
    float psm_slide_back = 0.0f;
    /// PSM: the largest half-angle of the post-perspective light frustum. Where the light would need a
    /// wider one (light near the view direction), the virtual camera slides back further, which
    /// weakens the warp continuously instead of switching to the uniform fit. [Limit: 1 < x < 89]
    float psm_max_half_angle_deg = 80.0f;
    /// LiSPSM: which n_opt (docs/perspective_shadow_maps.md, "LiSPSM near the view direction").
    LispsmNOpt lispsm_n_opt = LispsmNOpt::Lloyd;
    /// LiSPSM (Lloyd only): virtual near plane [wu]: the near distance under the square root is at least
    /// this (filament's shadowNearHint, 1 m); 0: none. Receivers nearer than it get less resolution. [Limit: >= 0]
    float lispsm_virtual_near = 1.0f;
    /// LiSPSM (Lloyd only): virtual far plane [wu]: the far distance under the square root is at most
    /// this (filament's shadowFarHint, 100 m); 0: none. [Limit: >= 0]
    float lispsm_virtual_far = 100.0f;
};

/// Same inputs for every method.
struct WarpInput {
    glm::mat4 camera_view = glm::mat4(0.0f);  ///< world -> camera view (required: the zero matrix is rejected)
    glm::mat4 camera_proj = glm::mat4(0.0f);  ///< camera view -> clip (required), see "Camera" above
    ClipDepth camera_depth = ClipDepth::NegativeOneToOne;
    bool camera_reversed_z = false;
    float max_distance = 0.0f;        ///< [wu] view-depth clamp of the far plane; 0: none. Required (> 0) when the far plane is infinite. [Limit: >= 0]
    float receiver_min_depth = 0.0f;  ///< [wu] visible receivers' view-depth range, used when max > min > 0
    float receiver_max_depth = 0.0f;
    glm::vec4 light_position = glm::vec4(0.0f);  ///< see "Lights" above (required: (0, 0, 0, 0) is rejected)
    bool has_scene_bounds = false;    ///< receivers are clipped to these bounds (world AABB)
    glm::vec3 scene_min = glm::vec3(0.0f);
    glm::vec3 scene_max = glm::vec3(0.0f);
    bool has_caster_bounds = false;   ///< all casters (world AABB); the volume is extended towards the
    glm::vec3 caster_min = glm::vec3(0.0f);  ///< light to reach them (scene bounds are used when absent)
    glm::vec3 caster_max = glm::vec3(0.0f);
    ClipDepth light_depth = ClipDepth::NegativeOneToOne;  ///< depth convention of the matrices built
    bool light_reversed_z = false;
    WarpOptions options{};
};

/// A fitted shadow map. `visible = false` (with Ok): the camera's receiver slice misses the scene
/// bounds, nothing needs a shadow (the matrices are then the identity).
struct WarpResult {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    bool visible = false;             ///< false (with Ok): no receivers in view, skip the shadow pass
    glm::mat4 light_view_proj = glm::mat4(1.0f);  ///< world -> light clip space (render casters, look up receivers)
    glm::mat4 depth_view_proj = glm::mat4(1.0f);  ///< world -> clip whose z / w is the map's undistorted depth (TSM: the unwarped light)
    bool separate_depth = false;      ///< true: depth_view_proj differs from light_view_proj (TSM while it warps)
    bool fallback_uniform = false;    ///< the method degenerated to a uniform fit (light ~ parallel to the view)
    float warp_strength = 0.0f;       ///< 1: the full warp, 0: uniform; LiSPSM and TSM fade, PSM slides back
    float sin_gamma = 0.0f;           ///< sin of the angle between the view's center line and the light
    float warp_parameter = 0.0f;      ///< LiSPSM n [wu], TSM eta [light NDC], PSM slide-back [wu]; 0 when not warping
};

/// warp_aliasing_error's value: screen pixels per shadow-map texel along the worst direction.
struct WarpAliasingValue {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    double value = 0.0;  ///< >= 0; > 1: undersampled (a texel covers more than a pixel)
};

/// warp_measure_aliasing's statistics over the samples that have a value.
struct WarpAliasingStats {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    double max_error = 0.0;             ///< max over samples of the texel footprint in screen pixels
    double mean_error = 0.0;
    double undersampled_fraction = 0.0; ///< fraction of samples with error > 1 (a texel covers > 1 pixel)
    std::uint32_t samples = 0;          ///< samples with a value
    std::uint32_t skipped = 0;          ///< samples without one (behind the camera or light, edge-on)
};

namespace detail {

constexpr int wp_kMaxRecv = 64;
constexpr double wp_kPi = 3.14159265358979323846;

inline bool wp_fin(double v) { return std::isfinite(v); }
inline bool wp_fin(const glm::dvec3& v) { return wp_fin(v.x) && wp_fin(v.y) && wp_fin(v.z); }
inline bool wp_fin(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
inline bool wp_fin(const glm::vec4& v) { return wp_fin(glm::vec3(v)) && std::isfinite(v.w); }
inline bool wp_fin(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c)
        if (!wp_fin(m[c])) return false;
    return true;
}
inline bool wp_fin(const glm::dmat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}

inline glm::dmat4 wp_depth_convention(ClipDepth cd, bool reversed) {
    glm::dmat4 m(1.0);
    if (cd == ClipDepth::ZeroToOne) {
        m[2][2] = reversed ? -0.5 : 0.5;
        m[3][2] = 0.5;
    } else if (reversed) {
        m[2][2] = -1.0;
    }
    return m;
}

/// Right-handed view looking along unit f with up (not parallel to f), like glm::lookAt.
inline glm::dmat4 wp_look_dir(const glm::dvec3& eye, const glm::dvec3& f, const glm::dvec3& up) {
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

/// A unit vector perpendicular to unit d.
inline glm::dvec3 wp_perp(const glm::dvec3& d) {
    const glm::dvec3 a = glm::abs(d);
    const glm::dvec3 axis = (a.x <= a.y && a.x <= a.z) ? glm::dvec3(1, 0, 0) : (a.y <= a.z ? glm::dvec3(0, 1, 0) : glm::dvec3(0, 0, 1));
    return glm::normalize(axis - glm::dot(axis, d) * d);
}

/// Ortho box -> [-1,1]^3 (GL), x/y/z given as ranges of view x, view y and depth (= -view z).
inline glm::dmat4 wp_ortho_box(const glm::dvec3& mn, const glm::dvec3& mx) {
    glm::dmat4 m(1.0);
    m[0][0] = 2.0 / (mx.x - mn.x);
    m[1][1] = 2.0 / (mx.y - mn.y);
    m[2][2] = 2.0 / (mx.z - mn.z);
    m[3][0] = -(mx.x + mn.x) / (mx.x - mn.x);
    m[3][1] = -(mx.y + mn.y) / (mx.y - mn.y);
    m[3][2] = -(mx.z + mn.z) / (mx.z - mn.z);
    return m;
}

/// Negates z (view z <-> depth, or NDC z of a post-perspective space made right-handed).
inline glm::dmat4 wp_flip_z() {
    glm::dmat4 m(1.0);
    m[2][2] = -1.0;
    return m;
}

inline glm::dmat4 wp_frustum(double l, double r, double b, double t, double n, double f) {
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

inline glm::dvec3 wp_project(const glm::dmat4& m, const glm::dvec3& p) {
    const glm::dvec4 h = m * glm::dvec4(p, 1.0);
    return glm::dvec3(h) / h.w;
}

/// Grows each axis of a box by its own extent times rel, so a thin axis is never swamped by a wide
/// one's pad (issue 14.2); at least 1e-9 of that axis' magnitude or of `unit` (the space's typical
/// coordinate), so a degenerate box never gives a matrix beyond float.
inline void wp_pad_box(glm::dvec3& mn, glm::dvec3& mx, double rel, double unit) {
    for (int i = 0; i < 3; ++i) {
        const double mag = std::fmax(unit, std::fmax(std::fabs(mn[i]), std::fabs(mx[i])));
        const double pad = std::fmax((mx[i] - mn[i]) * rel, 1e-9 * mag);
        mn[i] -= pad;
        mx[i] += pad;
    }
}

inline double wp_smooth01(double x) {
    x = glm::clamp(x, 0.0, 1.0);
    return x * x * (3.0 - 2.0 * x);
}

/// Center of the points' bounding box: unlike their mean it does not move when a vertex of the
/// receiver volume splits into coincident ones, so the fits built on it stay continuous.
inline glm::dvec3 wp_center(const glm::dvec3* p, int n) {
    glm::dvec3 mn(p[0]), mx(p[0]);
    for (int i = 1; i < n; ++i) {
        mn = glm::min(mn, p[i]);
        mx = glm::max(mx, p[i]);
    }
    return 0.5 * (mn + mx);
}

/// Everything the methods share: the receiver volume and the body (receivers extended towards the light).
struct wp_Setup {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    bool visible = false;
    bool directional = true;
    glm::dvec3 d{0.0};        ///< directional: unit direction the light travels (-xyz)
    glm::dvec3 L{0.0};        ///< point light position
    glm::dvec3 eye{0.0};
    glm::dvec3 vdir{0.0};     ///< unit direction of the view's center line (near center -> far center)
    glm::dvec3 cam_up{0.0};   ///< camera up, orthogonal to vdir
    glm::dvec3 cw[8];         ///< receiver slice corners (near 0..3, far 4..7) at view depths d0, d1
    glm::dvec3 nc{0.0}, fc{0.0}, mc{0.0};  ///< center line at d0, d1 and halfway
    glm::dvec3 c_org{0.0}, c_dir{0.0};     ///< center line (world): c_org + depth * c_dir
    double d0 = 0, d1 = 0;    ///< receivers' view-depth range
    double cam_d0 = 0, cam_d1 = 0;  ///< the camera slice's view-depth range (d0, d1 lie within it)
    glm::dmat4 view{1.0};     ///< world -> camera view
    glm::dvec3 recv[wp_kMaxRecv];
    int nrecv = 0;
    glm::dvec3 body[2 * wp_kMaxRecv];
    int nbody = 0;
    double scale = 1.0;
};

inline glm::dvec3 wp_toward_light(const wp_Setup& s, const glm::dvec3& p) {
    return s.directional ? -s.d : glm::normalize(s.L - p);
}

inline bool wp_options_ok(const WarpOptions& o) {
    return o.lispsm_n_scale > 0.0f && o.lispsm_min_sin_gamma >= 0.0f && o.lispsm_min_sin_gamma < 0.5f &&
           o.tsm_max_abs_cos_gamma > 0.05f && o.tsm_max_abs_cos_gamma <= 1.0f && o.tsm_focus_ratio > 0.0f &&
           o.tsm_focus_ratio < 1.0f && o.psm_min_near_fraction >= 0.0f && o.psm_slide_back >= 0.0f &&
           o.psm_max_half_angle_deg > 1.0f && o.psm_max_half_angle_deg < 89.0f;
}

// Step 1 of wp_prepare: finite inputs, the light, the options and the boxes. False when the
// preparation ends here (s.status says why; InvalidArgument is left set for the next steps).
inline bool wp_check_inputs(const WarpInput& in, wp_Setup& s) {
    const WarpOptions& o = in.options;
    auto ff = [](float v) { return std::isfinite(v); };
    const bool opts_finite = ff(o.lispsm_n_scale) && ff(o.lispsm_min_sin_gamma) && ff(o.tsm_max_abs_cos_gamma) &&
                             ff(o.tsm_focus_depth) && ff(o.tsm_focus_ratio) && ff(o.psm_min_near_fraction) &&
                             ff(o.psm_slide_back) && ff(o.psm_max_half_angle_deg);
    if (!wp_fin(in.camera_view) || !wp_fin(in.camera_proj) || !ff(in.max_distance) || !ff(in.receiver_min_depth) ||
        !ff(in.receiver_max_depth) || !opts_finite || (in.has_scene_bounds && !(wp_fin(in.scene_min) && wp_fin(in.scene_max))) ||
        (in.has_caster_bounds && !(wp_fin(in.caster_min) && wp_fin(in.caster_max)))) {
        s.status = Status::NonFinite;
        s.detail = !wp_fin(in.camera_view) ? "camera_view: NaN or Inf"
                   : (!wp_fin(in.camera_proj) ? "camera_proj: NaN or Inf"
                   : (!ff(in.max_distance) ? "max_distance: NaN or Inf"
                   : (!ff(in.receiver_min_depth) || !ff(in.receiver_max_depth) ? "receiver_min_depth, receiver_max_depth: NaN or Inf"
                   : (!opts_finite ? "options: NaN or Inf"
                   : (in.has_scene_bounds && !(wp_fin(in.scene_min) && wp_fin(in.scene_max)) ? "scene_min, scene_max: NaN or Inf"
                                                                                              : "caster_min, caster_max: NaN or Inf")))));
        return false;
    }
    // the light
    const glm::vec4 lp = in.light_position;
    if (!wp_fin(lp) || lp.w < 0.0f || (lp.x == 0.0f && lp.y == 0.0f && lp.z == 0.0f && lp.w == 0.0f)) {
        s.status = Status::InvalidLight;
        s.detail = !wp_fin(lp) ? "light_position: NaN or Inf" : (lp.w < 0.0f ? "light_position: w < 0" : "light_position: (0, 0, 0, 0)");
        return false;
    }
    s.directional = lp.w == 0.0f;
    if (s.directional) {
        const glm::dvec3 t(lp);
        const double tl = glm::length(t);
        if (!(tl > 0.0) || !wp_fin(tl)) {
            s.status = Status::InvalidLight;
            s.detail = "light_position: direction length not finite";
            return false;
        }
        s.d = -(t / tl);
    } else {
        s.L = glm::dvec3(lp) / double(lp.w);
        if (!wp_fin(glm::vec3(s.L))) {  // xyz / w beyond float
            s.status = Status::InvalidLight;
            s.detail = "light_position: xyz / w beyond float";
            return false;
        }
    }
    s.status = Status::InvalidArgument;
    if (!wp_options_ok(o)) return s.detail = "options: a field outside its [Limit]", false;
    if (!(in.max_distance >= 0.0f)) return s.detail = "max_distance: < 0", false;
    auto box_ok = [](const glm::vec3& a, const glm::vec3& b) { return a.x <= b.x && a.y <= b.y && a.z <= b.z; };
    if (in.has_scene_bounds && !box_ok(in.scene_min, in.scene_max)) return s.detail = "scene_min: > scene_max", false;
    if (in.has_caster_bounds && !box_ok(in.caster_min, in.caster_max)) return s.detail = "caster_min: > caster_max", false;
    return true;
}

// The camera as wp_prepare sees it: the near-plane corners pn (view space), the corner rays dir, their
// view depths dn, the slice's depth range [d0, d1], and view <-> world.
struct wp_Camera {
    glm::dmat4 V{1.0}, iv{1.0};
    glm::dvec3 pn[4], dir[4];
    double dn[4] = {0, 0, 0, 0};
    double d0 = 0, d1 = 0;
    glm::dvec3 corner_at(int i, double dep) const { return pn[i] + ((dep - dn[i]) / -dir[i].z) * dir[i]; }
    glm::dvec3 to_world(const glm::dvec3& p) const { return glm::dvec3(iv * glm::dvec4(p, 1.0)); }
};

// Step 2 of wp_prepare: un-project the near plane, a point a quarter of the NDC depth range further (in
// front of the eye for every projection this header accepts, P_inf with epsilon <= 0.5 included)
// and the far plane, which counts as infinite when it un-projects to infinity or behind the eye; clamp
// the depth range by max_distance and the receiver range. False when the preparation ends here
// (s.status InvalidArgument, or Ok with visible = false for an empty range).
inline bool wp_camera_slice(const WarpInput& in, wp_Camera& C, wp_Setup& s) {
    const glm::dmat4 P(in.camera_proj);
    C.V = glm::dmat4(in.camera_view);
    const double pdet = glm::determinant(P), vdet = glm::determinant(C.V);
    if (!wp_fin(pdet) || !(std::fabs(pdet) > 1e-300) || !wp_fin(vdet) || !(std::fabs(vdet) > 1e-300))
        return s.detail = !wp_fin(pdet) || !(std::fabs(pdet) > 1e-300) ? "camera_proj: singular" : "camera_view: singular", false;
    const glm::dmat4 ip = glm::inverse(P);
    C.iv = glm::inverse(C.V);
    if (!wp_fin(ip) || !wp_fin(C.iv))
        return s.detail = !wp_fin(ip) ? "camera_proj: inverse not finite" : "camera_view: inverse not finite", false;
    const double lo = in.camera_depth == ClipDepth::ZeroToOne ? 0.0 : -1.0;
    const double zn = in.camera_reversed_z ? 1.0 : lo, zf = in.camera_reversed_z ? lo : 1.0;
    const double zq = zn + 0.25 * (zf - zn);
    double dfar[4];
    bool infinite = false;
    for (int i = 0; i < 4; ++i) {
        const double x = (i & 1) ? 1.0 : -1.0, y = (i & 2) ? 1.0 : -1.0;
        const glm::dvec4 hn = ip * glm::dvec4(x, y, zn, 1.0), hq = ip * glm::dvec4(x, y, zq, 1.0),
                         hf = ip * glm::dvec4(x, y, zf, 1.0);
        auto mag = [](const glm::dvec4& h) { return std::fabs(h.x) + std::fabs(h.y) + std::fabs(h.z); };
        if (!(std::fabs(hn.w) > 1e-12 * mag(hn)) || !(std::fabs(hq.w) > 1e-12 * mag(hq)) || hn.w * hq.w <= 0.0)
            return s.detail = "camera_proj: near plane at infinity or split by the eye", false;
        C.pn[i] = glm::dvec3(hn) / hn.w;
        const glm::dvec3 pq = glm::dvec3(hq) / hq.w;
        C.dir[i] = pq - C.pn[i];
        C.dn[i] = -C.pn[i].z;
        if (!wp_fin(C.pn[i]) || !wp_fin(C.dir[i]) || !(C.dir[i].z < 0.0) || !(C.dn[i] > 0.0))
            return s.detail = "camera_proj: near plane at or behind the eye", false;
        dfar[i] = std::numeric_limits<double>::infinity();
        if (hf.w * hn.w > 0.0 && std::fabs(hf.w) > 1e-12 * mag(hf)) {
            const glm::dvec3 pf = glm::dvec3(hf) / hf.w;
            if (wp_fin(pf) && glm::dot(pf - C.pn[i], C.dir[i]) > glm::dot(C.dir[i], C.dir[i])) dfar[i] = -pf.z;
        }
        if (!wp_fin(dfar[i])) infinite = true;
    }
    double d0 = C.dn[0], d1 = dfar[0];
    for (int i = 1; i < 4; ++i) {
        d0 = std::fmax(d0, C.dn[i]);
        d1 = std::fmin(d1, dfar[i]);
    }
    if (in.max_distance > 0.0f) d1 = std::fmin(d1, double(in.max_distance));
    else if (infinite) return s.detail = "max_distance: 0 with an infinite far plane", false;
    if (!(d1 > d0) || !wp_fin(d1))  // near >= far (or the clamp in front of the near plane)
        return s.detail = "max_distance: in front of the near plane (or near >= far)", false;
    if (in.receiver_max_depth > in.receiver_min_depth && in.receiver_min_depth > 0.0f) {
        d0 = std::fmax(d0, double(in.receiver_min_depth));
        d1 = std::fmin(d1, double(in.receiver_max_depth));
    }
    C.d0 = d0;
    C.d1 = d1;
    s.status = Status::Ok;
    return d1 > d0;  // else visible = false
}

// Step 3 of wp_prepare: the slice's world corners cw, the view's center line (the corner rays'
// average: world point at view depth t is c_org + t c_dir), the eye and the camera's up. False with
// s.status Overflow when they leave double range.
inline bool wp_center_line(const wp_Camera& C, glm::dvec3 cw[8], wp_Setup& s) {
    for (int i = 0; i < 4; ++i) {
        cw[i] = C.to_world(C.corner_at(i, C.d0));
        cw[i + 4] = C.to_world(C.corner_at(i, C.d1));
    }
    for (int i = 0; i < 8; ++i)
        if (!wp_fin(cw[i])) { s.status = Status::Overflow; s.detail = "camera_view: a slice corner beyond range"; return false; }
    {
        const glm::dvec3 a = (cw[0] + cw[1] + cw[2] + cw[3]) * 0.25, b = (cw[4] + cw[5] + cw[6] + cw[7]) * 0.25;
        s.c_dir = (b - a) / (C.d1 - C.d0);
        s.c_org = a - C.d0 * s.c_dir;
        if (!(glm::length(s.c_dir) > 0.0) || !wp_fin(s.c_dir) || !wp_fin(s.c_org)) {
            s.status = Status::Overflow;
            s.detail = "camera_view: the view's center line beyond range";
            return false;
        }
        s.vdir = glm::normalize(s.c_dir);
    }
    s.eye = glm::dvec3(C.iv[3]);
    {
        glm::dvec3 up = glm::dvec3(C.iv[1]);
        up -= glm::dot(up, s.vdir) * s.vdir;
        s.cam_up = glm::length(up) > 1e-9 * glm::length(glm::dvec3(C.iv[1])) ? glm::normalize(up) : wp_perp(s.vdir);
    }
    if (!wp_fin(s.eye) || !wp_fin(s.cam_up)) { s.status = Status::Overflow; s.detail = "camera_view: eye or up beyond range"; return false; }
    for (int i = 0; i < 8; ++i) s.scale = std::fmax(s.scale, glm::length(cw[i]));
    return true;
}

// Step 4 of wp_prepare: the receiver volume's vertices s.recv: the slice, intersected with the scene
// box (vertices from plane triples).
inline void wp_receiver_vertices(const WarpInput& in, const glm::dvec3 cw[8], wp_Setup& s) {
    if (!in.has_scene_bounds) {
        for (int i = 0; i < 8; ++i) s.recv[s.nrecv++] = cw[i];
        return;
    }
    glm::dvec4 pl[12];
    constexpr int faces[6][4] = {{0, 1, 3, 2}, {4, 5, 7, 6}, {0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 3, 7, 6}};
    const glm::dvec3 ctr = (cw[0] + cw[7]) * 0.5;
    for (int f = 0; f < 6; ++f) {
        const glm::dvec3 a = cw[faces[f][0]], b = cw[faces[f][1]], c = cw[faces[f][2]], e = cw[faces[f][3]];
        glm::dvec3 n = glm::cross(c - a, e - b);
        if (glm::dot(n, n) == 0.0) n = glm::dvec3(0, 0, 1);
        n = glm::normalize(n);
        glm::dvec4 p(n, -glm::dot(n, (a + b + c + e) * 0.25));
        if (glm::dot(glm::dvec3(p), ctr) + p.w < 0.0) p = -p;
        pl[f] = p;
    }
    const glm::dvec3 mn(in.scene_min), mx(in.scene_max);
    pl[6] = glm::dvec4(1, 0, 0, -mn.x); pl[7] = glm::dvec4(-1, 0, 0, mx.x);
    pl[8] = glm::dvec4(0, 1, 0, -mn.y); pl[9] = glm::dvec4(0, -1, 0, mx.y);
    pl[10] = glm::dvec4(0, 0, 1, -mn.z); pl[11] = glm::dvec4(0, 0, -1, mx.z);
    s.scale = std::fmax(s.scale, std::fmax(glm::length(mn), glm::length(mx)));
    const double tol = 1e-9 * s.scale;
    for (int i = 0; i < 12; ++i)
        for (int j = i + 1; j < 12; ++j)
            for (int k = j + 1; k < 12; ++k) {
                const glm::dvec3 a(pl[i]), b(pl[j]), c(pl[k]);
                const glm::dvec3 bc = glm::cross(b, c);
                const double det = glm::dot(a, bc);
                if (std::fabs(det) < 1e-12) continue;
                const glm::dvec3 p = (-pl[i].w * bc - pl[j].w * glm::cross(c, a) - pl[k].w * glm::cross(a, b)) / det;
                if (!wp_fin(p)) continue;
                bool inside = true;
                for (int m = 0; m < 12 && inside; ++m) inside = glm::dot(glm::dvec3(pl[m]), p) + pl[m].w >= -tol;
                if (!inside) continue;
                bool dup = false;
                for (int m = 0; m < s.nrecv && !dup; ++m) dup = glm::length(s.recv[m] - p) <= tol;
                if (!dup && s.nrecv < wp_kMaxRecv) s.recv[s.nrecv++] = p;
            }
}

// Step 5 of wp_prepare: the receivers' own view-depth range (the TSM paper's focused frustum) and the
// slice between those depths (s.cw, s.nc, s.fc, s.mc).
inline void wp_focus_slice(const wp_Camera& C, wp_Setup& s) {
    double r0 = 1e300, r1 = -1e300;
    for (int i = 0; i < s.nrecv; ++i) {
        const double dep = -(C.V * glm::dvec4(s.recv[i], 1.0)).z;
        r0 = std::fmin(r0, dep);
        r1 = std::fmax(r1, dep);
    }
    s.cam_d0 = C.d0;
    s.cam_d1 = C.d1;
    s.view = C.V;
    s.d0 = glm::clamp(r0, C.d0, C.d1);
    s.d1 = glm::clamp(r1, s.d0, C.d1);
    for (int i = 0; i < 4; ++i) {
        s.cw[i] = C.to_world(C.corner_at(i, s.d0));
        s.cw[i + 4] = C.to_world(C.corner_at(i, s.d1));
    }
    s.nc = s.c_org + s.d0 * s.c_dir;
    s.fc = s.c_org + s.d1 * s.c_dir;
    s.mc = (s.nc + s.fc) * 0.5;
}

// Step 6 of wp_prepare: the body s.body: the receivers plus their extension towards the light up to
// the caster bounds (or the scene bounds).
inline void wp_body(const WarpInput& in, wp_Setup& s) {
    for (int i = 0; i < s.nrecv; ++i) s.body[s.nbody++] = s.recv[i];
    const bool hc = in.has_caster_bounds || in.has_scene_bounds;
    const glm::dvec3 cmn = in.has_caster_bounds ? glm::dvec3(in.caster_min) : glm::dvec3(in.scene_min);
    const glm::dvec3 cmx = in.has_caster_bounds ? glm::dvec3(in.caster_max) : glm::dvec3(in.scene_max);
    if (!hc) return;
    s.scale = std::fmax(s.scale, std::fmax(glm::length(cmn), glm::length(cmx)));
    if (s.directional) {
        const glm::dvec3 t = -s.d;
        double top = -1e300, low = 1e300;
        for (int c = 0; c < 8; ++c) {
            const glm::dvec3 p((c & 1) ? cmx.x : cmn.x, (c & 2) ? cmx.y : cmn.y, (c & 4) ? cmx.z : cmn.z);
            top = std::fmax(top, glm::dot(p, t));
        }
        for (int i = 0; i < s.nrecv; ++i) low = std::fmin(low, glm::dot(s.recv[i], t));
        const double h = top - low;
        if (h > 0.0)
            for (int i = 0; i < s.nrecv; ++i) s.body[s.nbody++] = s.recv[i] + h * t;
    } else {
        // nearest distance from the light to the caster box
        const glm::dvec3 q = glm::clamp(s.L, cmn, cmx);
        const double dmin = glm::length(q - s.L);
        double dmax = 0.0;
        for (int i = 0; i < s.nrecv; ++i) dmax = std::fmax(dmax, glm::length(s.recv[i] - s.L));
        const double dd = std::fmax(dmin, 1e-4 * dmax);
        for (int i = 0; i < s.nrecv; ++i) {
            const glm::dvec3 r = s.recv[i] - s.L;
            const double l = glm::length(r);
            if (l > dd) s.body[s.nbody++] = s.L + r * (dd / l);
        }
    }
}

inline wp_Setup wp_prepare(const WarpInput& in) {
    wp_Setup s;
    if (!wp_check_inputs(in, s)) return s;     // finite inputs, the light, the options
    wp_Camera C;
    if (!wp_camera_slice(in, C, s)) return s;  // the camera's depth range (visible = false when empty)
    glm::dvec3 cw[8];
    if (!wp_center_line(C, cw, s)) return s;   // the slice's corners, center line, eye, up
    wp_receiver_vertices(in, cw, s);           // the slice within the scene box
    if (s.nrecv == 0) return s;                // Ok, visible = false
    wp_focus_slice(C, s);                      // the receivers' own depth range
    wp_body(in, s);                            // the receivers swept towards the light
    for (int i = 0; i < s.nbody; ++i)
        if (!wp_fin(s.body[i])) { s.status = Status::Overflow; s.detail = "light_position: the body swept to the light beyond range"; return s; }
    s.visible = true;
    return s;
}

/// The map's "up" (image +y) for a view along unit f of a light whose unit direction towards the
/// view's center line is `to_line`: the image of the center line (direction v) is vertical and points
/// from near to far. Continuous except where the light lies on the center line (to_line ~ +-v); there
/// the projection of `ref` (the camera's up) is used.
inline glm::dvec3 wp_up(const glm::dvec3& f, const glm::dvec3& to_line, const glm::dvec3& v, const glm::dvec3& ref) {
    const glm::dvec3 n = glm::cross(to_line, v);
    const glm::dvec3 up = glm::cross(n, f);
    const double ln = glm::length(n), lu = glm::length(up);
    if (ln > 1e-12 && lu > 1e-9 * ln && wp_fin(up)) return up / lu;
    const glm::dvec3 r = ref - glm::dot(ref, f) * f;
    return glm::length(r) > 1e-9 ? glm::normalize(r) : wp_perp(f);
}

/// Uniform (orthographic) fit of points along travel direction d (unit) with the given up (unit, _|_ d).
/// Returns GL clip, depth increasing along d.
inline glm::dmat4 wp_ortho_fit(const glm::dvec3* pts, int n, const glm::dvec3& d, const glm::dvec3& up, double unit) {
    const glm::dmat4 lv = wp_look_dir(wp_center(pts, n), d, up);
    glm::dvec3 mn(1e300), mx(-1e300);
    for (int i = 0; i < n; ++i) {
        glm::dvec3 p = glm::dvec3(lv * glm::dvec4(pts[i], 1.0));
        p.z = -p.z;
        mn = glm::min(mn, p);
        mx = glm::max(mx, p);
    }
    wp_pad_box(mn, mx, 1e-7, unit);
    return wp_ortho_box(mn, mx) * wp_flip_z() * lv;
}

/// Perspective fit from S along unit axis f with up (unit, _|_ f) around pts. Fails (false) when a
/// point is not in front of S or a tangent exceeds max_tan. invert: depth decreasing with distance
/// (a post-perspective light sink), mirrored in x to keep the orientation. *tan_used: largest |tangent|.
inline bool wp_persp_fit(const glm::dvec3* pts, int n, const glm::dvec3& S, const glm::dvec3& f, const glm::dvec3& up,
                         double max_tan, bool invert, glm::dmat4& out, double* tan_used = nullptr) {
    const glm::dmat4 lv = wp_look_dir(S, f, up);
    double xl = 1e300, xr = -1e300, yb = 1e300, yt = -1e300, dn = 1e300, df = 0.0, al = 0.0;
    for (int i = 0; i < n; ++i) al = std::fmax(al, glm::length(pts[i] - S));
    for (int i = 0; i < n; ++i) {
        const glm::dvec3 p = glm::dvec3(lv * glm::dvec4(pts[i], 1.0));
        const double dep = -p.z;
        if (!(dep > 1e-12 * al)) return false;
        const double x = p.x / dep, y = p.y / dep;
        xl = std::fmin(xl, x); xr = std::fmax(xr, x);
        yb = std::fmin(yb, y); yt = std::fmax(yt, y);
        dn = std::fmin(dn, dep); df = std::fmax(df, dep);
    }
    const double tmax = std::fmax(std::fmax(-xl, xr), std::fmax(-yb, yt));
    if (tan_used) *tan_used = tmax;
    if (!(tmax <= max_tan)) return false;
    glm::dvec3 mn(xl, yb, dn), mx(xr, yt, df);
    wp_pad_box(mn, mx, 1e-7, 1e-6);  // tangents (the depth is set below)
    mn.z = dn * (1.0 - 1e-7);
    mx.z = std::fmax(df * (1.0 + 1e-7), mn.z * (1.0 + 1e-6));
    glm::dmat4 p = wp_frustum(mn.x * mn.z, mx.x * mn.z, mn.y * mn.z, mx.y * mn.z, mn.z, mx.z);
    if (invert) {
        // inverted projection for a post-perspective light sink (Kozlov 2004): depth decreases with
        // distance; negating x as well keeps the orientation (and continuity through infinity)
        for (int col = 0; col < 4; ++col) {
            p[col][2] = -p[col][2];
            p[col][0] = -p[col][0];
        }
    }
    out = p * lv;
    return wp_fin(out);
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

/// Axis of a perspective fit from S: start at the axis of the narrowest cone holding the points
/// (cone_axis, as light_frustum.hpp aims a point light), then twice through the middle of their
/// angular extents (a nearly symmetric frustum, so no resolution is spent off to one side). Every
/// step moves continuously with the points (a unique nearest point, bounding extents; never means).
/// Before issue 13's follow-up the start was the points' box center, which for a light just above
/// wide receivers lies below their top, so the far receivers came out beside or behind it.
inline glm::dvec3 wp_persp_axis(const glm::dvec3* pts, int n, const glm::dvec3& S, const glm::dvec3& to_line,
                                const glm::dvec3& v, const glm::dvec3& ref) {
    glm::dvec3 f = cone_axis(pts, n, S);
    if (!(glm::length(f) > 0.0)) return glm::dvec3(0.0);
    for (int it = 0; it < 2; ++it) {
        const glm::dvec3 up = wp_up(f, to_line, v, ref);
        const glm::dvec3 sx = glm::cross(f, up);
        double xl = 1e300, xr = -1e300, yb = 1e300, yt = -1e300;
        for (int i = 0; i < n; ++i) {
            const glm::dvec3 r = pts[i] - S;
            const double dep = glm::dot(r, f);
            if (!(dep > 1e-9 * glm::length(r))) return f;  // a point beside or behind: keep this axis
            const double ax = std::atan2(glm::dot(r, sx), dep), ay = std::atan2(glm::dot(r, up), dep);
            xl = std::fmin(xl, ax); xr = std::fmax(xr, ax);
            yb = std::fmin(yb, ay); yt = std::fmax(yt, ay);
        }
        const glm::dvec3 g = f + std::tan(0.5 * (xl + xr)) * sx + std::tan(0.5 * (yb + yt)) * up;
        if (!(glm::length(g) > 0.0) || !wp_fin(g)) return f;
        f = glm::normalize(g);
    }
    return f;
}

/// The point-light uniform fit: axis from wp_persp_axis, up from the view's center line.
inline bool wp_point_fit(const wp_Setup& s, double max_tan, glm::dmat4& out) {
    const glm::dvec3 ml = s.mc - s.L;
    const glm::dvec3 to_line = glm::length(ml) > 0.0 ? glm::normalize(ml) : s.vdir;
    const glm::dvec3 f = wp_persp_axis(s.body, s.nbody, s.L, to_line, s.vdir, s.cam_up);
    if (!(glm::length(f) > 0.0)) return false;
    return wp_persp_fit(s.body, s.nbody, s.L, f, wp_up(f, to_line, s.vdir, s.cam_up), max_tan, false, out);
}

/// Base uniform fit in world space: ortho along d (directional) or perspective from L (point).
inline bool wp_uniform_world(const wp_Setup& s, glm::dmat4& out) {
    if (s.directional) {
        out = wp_ortho_fit(s.body, s.nbody, s.d, wp_up(s.d, s.d, s.vdir, s.cam_up), s.scale);
        return wp_fin(out);
    }
    return wp_point_fit(s, 100.0, out);  // up to ~89.4 degrees
}

inline WarpResult wp_fail(Status st, const char* why) {
    WarpResult r;
    r.status = st;
    r.detail = why;
    return r;
}

inline float wp_to_float(double v) {
    const double lim = double(std::numeric_limits<float>::max());
    return static_cast<float>(wp_fin(v) ? glm::clamp(v, -lim, lim) : 0.0);
}

/// The result with the depth convention applied; Overflow when a matrix is not finite in float.
inline WarpResult wp_finish(const WarpInput& in, const glm::dmat4& m, const glm::dmat4& depth_m, bool separate,
                            bool fallback, double strength, double sin_gamma, double param) {
    WarpResult r;
    const glm::dmat4 conv = wp_depth_convention(in.light_depth, in.light_reversed_z);
    const glm::dmat4 f = conv * m, g = conv * depth_m;
    const glm::mat4 ff(f), gf(g);
    if (!wp_fin(f) || !wp_fin(ff) || !wp_fin(g) || !wp_fin(gf)) return wp_fail(Status::Overflow, "light_view_proj: not finite in float");
    r.status = Status::Ok;
    r.visible = true;
    r.light_view_proj = ff;
    r.depth_view_proj = separate ? gf : ff;
    r.separate_depth = separate;
    r.warp_strength = wp_to_float(glm::clamp(strength, 0.0, 1.0));
    r.fallback_uniform = fallback;
    r.sin_gamma = wp_to_float(sin_gamma);
    r.warp_parameter = wp_to_float(param);
    return r;
}

inline WarpResult wp_not_visible() {
    WarpResult r;
    r.status = Status::Ok;
    r.visible = false;
    return r;
}

/// sin/cos of the angle between the view's center line and the light direction (towards the line).
inline void wp_gamma(const wp_Setup& s, double& sin_g, double& cos_g) {
    glm::dvec3 d = s.d;
    if (!s.directional) {
        const glm::dvec3 ml = s.mc - s.L;
        d = glm::length(ml) > 0.0 ? glm::normalize(ml) : s.vdir;
    }
    cos_g = glm::clamp(glm::dot(s.vdir, d), -1.0, 1.0);
    sin_g = glm::length(glm::cross(s.vdir, d));
}

/// The LiSPSM n_opt options: NonFinite or InvalidArgument outside their limits.
inline Status wp_lispsm_options_status(const WarpOptions& o) {
    if (!std::isfinite(o.lispsm_virtual_near) || !std::isfinite(o.lispsm_virtual_far)) return Status::NonFinite;
    const bool known = o.lispsm_n_opt == LispsmNOpt::Lloyd || o.lispsm_n_opt == LispsmNOpt::Wimmer;
    return known && o.lispsm_virtual_near >= 0.0f && o.lispsm_virtual_far >= 0.0f ? Status::Ok : Status::InvalidArgument;
}

// The result of a LiSPSM option that wp_lispsm_options_status rejects, with its detail.
inline WarpResult wp_lispsm_options_fail(Status st) {
    return wp_fail(st, st == Status::NonFinite ? "options.lispsm_virtual_near / _far: NaN or Inf"
                                               : "options: lispsm_n_opt unknown or lispsm_virtual_near / _far < 0");
}

/// LiSPSM's 1 / n [1/wu] (n: the warp distance) for the body spanning D [wu] across the light; 0 (no
/// warp) where n is unbounded.
inline double wp_lispsm_kappa(const WarpOptions& o, const wp_Setup& s, double D, double sin_g) {
    if (o.lispsm_n_opt == LispsmNOpt::Wimmer) {
        // Wimmer et al. 2004, sec. 5: n = (z_n' + sqrt(z_n' z_f')) / sin(gamma), z_n' = z_n / sin(gamma), z_f' = z_n' + D sin(gamma)
        const double zn = s.d0 / sin_g, zf = zn + D * sin_g;
        return sin_g / (zn + std::sqrt(zn * zf));
    }
    // z_n, z_f: the view-depth range of the receivers swept towards the light (filament's receiver
    // volume reaches the casters), within the camera's slice
    double b0 = 1e300, b1 = -1e300;
    for (int i = 0; i < s.nbody; ++i) {
        const double dep = -(s.view * glm::dvec4(s.body[i], 1.0)).z;
        b0 = std::fmin(b0, dep);
        b1 = std::fmax(b1, dep);
    }
    const double z_n = glm::clamp(b0, s.cam_d0, s.d0), z_f = glm::clamp(b1, s.d1, s.cam_d1);
    // Lloyd et al. 2006 (thesis sec. 5.1.2.2, eta = 0): n = (z_0 + sqrt(z_0 z_1)) / sin(gamma), z_0 = z_n,
    // z_1 = z_0 + D sin(gamma); under the root z_0 >= the virtual near v_n and z_1 <= the virtual far
    // (filament's ShadowMap::applyLISPSM), and n >= dz / (2 - 3 dz / (z_f - z_n)), dz = v_n - z_n, which
    // grows without bound (kappa -> 0, continuously) as dz reaches 2/3 of the receivers' depth range.
    const double vn = double(o.lispsm_virtual_near), vf = double(o.lispsm_virtual_far);
    const double z1 = z_n + D * sin_g;
    const double r0 = std::fmax(z_n, vn), r1 = std::fmax(0.0, vf > 0.0 ? std::fmin(std::fmin(z_f, vf), z1) : z1);
    const double n0 = (z_n + std::sqrt(r0 * r1)) / sin_g;
    const double dz = std::fmax(0.0, vn - z_n), range = std::fmax(z_f - z_n, 1e-300);
    const double den = 2.0 - 3.0 * dz / range;  // 1 / n1 = den / dz
    const double k0 = n0 > 0.0 ? 1.0 / n0 : 0.0, k1 = dz > 0.0 ? std::fmax(0.0, den) / dz : k0;
    return std::fmin(k0, k1);
}

}  // namespace detail

/// Uniform (standard) shadow map fitted to the receiver volume extended towards the light:
/// orthographic for directional lights, perspective for point lights (LightInsideVolume when the
/// light is inside or around the receivers). Its roll follows the view's center line (see "Continuity").
inline WarpResult warp_uniform_matrix(const WarpInput& in) {
    using namespace detail;
    const wp_Setup s = wp_prepare(in);
    if (s.status != Status::Ok) return wp_fail(s.status, s.detail);
    if (!s.visible) return wp_not_visible();
    glm::dmat4 m;
    if (!wp_uniform_world(s, m)) return wp_fail(Status::LightInsideVolume, "light_position: inside the receivers' body (no frustum holds it)");
    double sg, cg;
    wp_gamma(s, sg, cg);
    return wp_finish(in, m, m, false, false, 0.0, sg, 0.0);
}

/// Light Space Perspective Shadow Maps (Wimmer et al. 2004): a perspective warp whose axis is the view
/// direction projected perpendicular to the light (a point light is first made directional in its own
/// post-perspective space), strength n_opt. The warp fades out (n -> infinity, continuously) as
/// sin(gamma) goes from 1.5 * lispsm_min_sin_gamma down to lispsm_min_sin_gamma.
inline WarpResult warp_lispsm_matrix(const WarpInput& in) {
    using namespace detail;
    if (const Status ost = wp_lispsm_options_status(in.options); ost != Status::Ok) return wp_lispsm_options_fail(ost);
    const wp_Setup s = wp_prepare(in);
    if (s.status != Status::Ok) return wp_fail(s.status, s.detail);
    if (!s.visible) return wp_not_visible();
    double sg_w, cg_w;
    wp_gamma(s, sg_w, cg_w);
    glm::dmat4 base(1.0);  // world -> a right-handed space where the light is directional along d
    glm::dvec3 d = s.d, v = s.vdir, ref = s.cam_up;
    glm::dvec3 pts[2 * wp_kMaxRecv] = {};
    bool line_ok = true;
    if (s.directional) {
        for (int i = 0; i < s.nbody; ++i) pts[i] = s.body[i];
    } else {
        // point light: its own post-perspective space (z negated: right-handed) makes it directional
        glm::dmat4 U;
        if (!wp_point_fit(s, 100.0, U)) return wp_fail(Status::LightInsideVolume, "light_position: inside the receivers' body (no frustum holds it)");
        base = wp_flip_z() * U;
        for (int i = 0; i < s.nbody; ++i) pts[i] = wp_project(base, s.body[i]);
        d = glm::dvec3(0, 0, -1);
        ref = glm::dvec3(0, 1, 0);
        // the center line's direction there: the derivative of the projection at mc along vdir
        const glm::dvec4 h = base * glm::dvec4(s.mc, 1.0), dh = base * glm::dvec4(s.vdir, 0.0);
        if (h.w > 1e-12 * glm::length(glm::dvec3(h))) {
            v = (glm::dvec3(dh) - glm::dvec3(h) / h.w * dh.w) / h.w;
            line_ok = glm::length(v) > 0.0 && wp_fin(v);
            if (line_ok) v = glm::normalize(v);
        } else {
            line_ok = false;
        }
    }
    const glm::dvec3 vp = v - glm::dot(v, d) * d;
    const double sg = line_ok ? glm::length(vp) : 0.0;
    const double s0 = double(in.options.lispsm_min_sin_gamma);
    constexpr double kLispsmFade = 0.5;  // the warp fades in over sin(gamma) in [s0, (1 + kLispsmFade) s0]
    const double fade = !(sg > 0.0) || !wp_fin(sg) ? 0.0 : (s0 > 0.0 ? wp_smooth01((sg - s0) / (kLispsmFade * s0)) : 1.0);
    const glm::dvec3 up = wp_up(d, d, line_ok ? v : ref, ref);
    // light-space frame: x lateral, y along the warp axis (view direction projected), z against the
    // light; origin at the receivers' near center on the view's center line (the warp's lateral center)
    glm::dvec3 origin = s.nc;
    if (!s.directional) {
        const glm::dvec4 h = base * glm::dvec4(s.nc, 1.0);
        origin = h.w > 0.0 ? glm::dvec3(h) / h.w : wp_center(pts, s.nbody);
    }
    const glm::dmat4 lv = wp_look_dir(origin, d, up);
    double ymin = 1e300, ymax = -1e300;
    for (int i = 0; i < s.nbody; ++i) {
        const double y = (lv * glm::dvec4(pts[i], 1.0)).y;
        ymin = std::fmin(ymin, y);
        ymax = std::fmax(ymax, y);
    }
    const double D = ymax - ymin;
    // n_opt (wp_lispsm_kappa: Lloyd et al. 2006 or Wimmer et al. 2004), computed in world units and carried
    // to the warp space as the ratio n / D (the warp is scale invariant).
    double Dw = D;
    if (!s.directional) {
        const glm::dvec3 dw = glm::normalize(s.mc - s.L);
        glm::dvec3 vpw = s.vdir - glm::dot(s.vdir, dw) * dw;
        vpw = glm::length(vpw) > 1e-12 ? glm::normalize(vpw) : s.cam_up;
        double a = 1e300, b = -1e300;
        for (int i = 0; i < s.nbody; ++i) {
            a = std::fmin(a, glm::dot(s.body[i], vpw));
            b = std::fmax(b, glm::dot(s.body[i], vpw));
        }
        Dw = b - a;
    }
    const double sgn = s.directional ? sg : sg_w;
    double n_world = 0.0, kappa = 0.0;
    if (fade > 0.0 && sgn > 0.0 && Dw > 0.0 && D > 1e-12 * s.scale) {
        const double k = wp_lispsm_kappa(in.options, s, Dw, sgn);
        n_world = k > 0.0 ? double(in.options.lispsm_n_scale) / k : 0.0;
        const double n = n_world * (D / Dw);  // in the warp space
        if (n > 0.0 && wp_fin(n)) kappa = fade / n;
    }
    // The warp in a form that stays exact as n -> infinity (kappa = 1/n -> 0: the uniform fit): with
    // t = y - ymin in [0, D], w = 1 + kappa t, y_ndc = (alpha t - 1) / w, alpha = (2 + kappa D) / D, the
    // same projective map as the frustum with near n and far n + D along the warp axis.
    const double Dp = std::fmax(D, 1e-300);
    const double alpha = (2.0 + kappa * Dp) / Dp;
    glm::dmat4 W(0.0);  // (X, Y, Z, 1) -> (X, alpha t - 1, Z, 1 + kappa t)
    W[0][0] = 1.0;
    W[1][1] = alpha;
    W[3][1] = -alpha * ymin - 1.0;
    W[2][2] = 1.0;
    W[1][3] = kappa;
    W[3][3] = 1.0 - kappa * ymin;
    const glm::dmat4 WL = W * lv;
    glm::dvec3 mn(1e300), mx(-1e300);
    for (int i = 0; i < s.nbody; ++i) {
        glm::dvec3 p = wp_project(WL, pts[i]);
        p.z = -p.z;  // depth: away from the light
        mn = glm::min(mn, p);
        mx = glm::max(mx, p);
    }
    wp_pad_box(mn, mx, 1e-7, s.directional ? s.scale : 1.0);
    const glm::dmat4 m = wp_ortho_box(mn, mx) * wp_flip_z() * WL * base;
    return wp_finish(in, m, m, false, !(kappa > 0.0), kappa > 0.0 ? fade : 0.0, sg_w, kappa > 0.0 ? n_world / fade : 0.0);
}

/// Trapezoidal Shadow Maps (Martin & Tan 2004): the receivers' hull in the uniform light's
/// post-perspective space bounded by a trapezoid (top and base perpendicular to the view's center
/// line, sides through the projection point q; the 80% rule picks q), mapped to the unit square. The
/// warp fades out as |cos gamma| goes from tsm_max_abs_cos_gamma - 0.05 up to tsm_max_abs_cos_gamma.
/// depth_view_proj is the uniform light's (undistorted) depth; see "TSM depth".
inline WarpResult warp_tsm_matrix(const WarpInput& in) {
    using namespace detail;
    const wp_Setup s = wp_prepare(in);
    if (s.status != Status::Ok) return wp_fail(s.status, s.detail);
    if (!s.visible) return wp_not_visible();
    glm::dmat4 U;
    if (!wp_uniform_world(s, U)) return wp_fail(Status::LightInsideVolume, "light_position: inside the receivers' body (no frustum holds it)");
    double sg, cg;
    wp_gamma(s, sg, cg);
    const double cmax = double(in.options.tsm_max_abs_cos_gamma);
    double fade = wp_smooth01((cmax - std::fabs(cg)) / 0.05);
    // the receivers in U's NDC; U's +y is the center line's image (see wp_up), so the trapezoid's axis
    // is the y axis and its apex lies on the center line's image x = xc
    double tmin = 1e300, tmax = -1e300;
    glm::dvec2 p2[wp_kMaxRecv] = {};
    for (int i = 0; i < s.nrecv; ++i) {
        p2[i] = glm::dvec2(wp_project(U, s.recv[i]));
        tmin = std::fmin(tmin, p2[i].y);
        tmax = std::fmax(tmax, p2[i].y);
    }
    {
        const double pad = std::fmax((tmax - tmin) * 1e-7, 1e-9);
        tmin -= pad;
        tmax += pad;
    }
    const double lambda = tmax - tmin;
    double xc = 0.0, kappa = 0.0;
    const glm::dvec4 hm = U * glm::dvec4(s.mc, 1.0);
    double fdep = double(in.options.tsm_focus_depth);
    if (!(fdep > 0.0)) fdep = std::sqrt(s.d0 * s.d1);
    fdep = glm::clamp(fdep, s.d0, s.d1);
    const glm::dvec4 hf = U * glm::dvec4(s.c_org + fdep * s.c_dir, 1.0);
    if (fade > 0.0 && hm.w > 0.0 && hf.w > 0.0 && lambda > 0.0) {
        xc = hm.x / hm.w;
        const double delta = glm::clamp(hf.y / hf.w - tmin, 0.0, lambda);
        // Martin & Tan 2004, sec. 6: the focus point maps to xi = 2 ratio - 1 (the 80% line). With the
        // apex at distance eta before the top, kappa = 1 / eta = (lambda (1 + xi) - 2 delta) / (lambda delta (1 - xi)).
        const double xi = 2.0 * double(in.options.tsm_focus_ratio) - 1.0;
        const double k0 = delta > 0.0 ? (lambda * (1.0 + xi) - 2.0 * delta) / (lambda * delta * (1.0 - xi)) : 1e300;
        kappa = glm::clamp(k0, 0.0, 1e3 / lambda) * fade;  // eta >= 1e-3 lambda
        if (!wp_fin(kappa) || !wp_fin(xc)) kappa = 0.0;
    }
    if (!(kappa > 0.0)) {
        fade = 0.0;
        kappa = 0.0;
        xc = 0.0;
    }
    // N_T acting on U's clip vector (X, Y, Z, W), with t = Y/W - tmin: w_T = W (1 + kappa t),
    // y_T = W (alpha t - 1), alpha = (2 + kappa lambda) / lambda (the map of [0, lambda] onto [-1, 1] with
    // its pole at t = -eta), x_T = ((X/W - xc) - mid (1 + kappa t)) / half * W; z_T = Z. Exact for
    // kappa -> 0 (then it is U), determinant (alpha + kappa) / half > 0 (no mirror).
    const double alpha = (2.0 + kappa * lambda) / lambda;
    double rmin = 1e300, rmax = -1e300;
    for (int i = 0; i < s.nrecv; ++i) {
        const double r = (p2[i].x - xc) / (1.0 + kappa * (p2[i].y - tmin));
        rmin = std::fmin(rmin, r);
        rmax = std::fmax(rmax, r);
    }
    const double rmid = 0.5 * (rmin + rmax);
    const double rhalf = std::fmax(0.5 * (rmax - rmin) * (1.0 + 1e-7), 1e-9);
    const glm::dvec4 wrow(0.0, kappa, 0.0, 1.0 - kappa * tmin);
    const glm::dvec4 yrow(0.0, alpha, 0.0, -alpha * tmin - 1.0);
    const glm::dvec4 xrow = (glm::dvec4(1.0, 0.0, 0.0, -xc) - rmid * wrow) / rhalf;
    const glm::dvec4 zrow(0.0, 0.0, 1.0, 0.0);
    glm::dmat4 N(0.0);
    for (int c = 0; c < 4; ++c) {
        N[c][0] = xrow[c];
        N[c][1] = yrow[c];
        N[c][2] = zrow[c];
        N[c][3] = wrow[c];
    }
    const bool warps = kappa > 0.0;
    return wp_finish(in, N * U, U, warps, !warps, fade, sg, warps ? 1.0 / kappa : 0.0);
}

namespace detail {

struct WpPsmEval {
    bool ok = false;
    double tan_used = 1e300;
    glm::dmat4 M{1.0};
};

// The virtual camera's rotation: -z along the center line, y the camera's up.
inline glm::dmat4 wp_psm_rotation(const wp_Setup& s) {
    const glm::dvec3 zax = -s.vdir, yax = s.cam_up, xax = glm::cross(yax, zax);
    glm::dmat4 R(1.0);
    for (int c = 0; c < 3; ++c) {
        R[c][0] = xax[c];
        R[c][1] = yax[c];
        R[c][2] = zax[c];
    }
    return R;
}

// One PSM for slide-back `slide` of the virtual camera (rotation R, light Lw): the matrix, and the
// largest tangent the light frustum needs (ok = false: no frustum within max_tan holds the body).
inline WpPsmEval wp_psm_eval(const wp_Setup& s, const glm::dmat4& R, const glm::dvec4& Lw, double slide, double max_tan) {
    WpPsmEval e;
    const glm::dvec3 veye = s.eye - slide * s.vdir;
    glm::dmat4 Vv = R;
    Vv[3] = glm::dvec4(-glm::dvec3(R * glm::dvec4(veye, 0.0)), 1.0);
    double xl = 1e300, xr = -1e300, yb = 1e300, yt = -1e300, dn = 1e300, df = 0.0;
    for (int i = 0; i < s.nbody; ++i) {
        const glm::dvec3 p = glm::dvec3(Vv * glm::dvec4(s.body[i], 1.0));
        const double dep = -p.z;
        if (!(dep > 0.0)) return e;
        xl = std::fmin(xl, p.x / dep); xr = std::fmax(xr, p.x / dep);
        yb = std::fmin(yb, p.y / dep); yt = std::fmax(yt, p.y / dep);
        dn = std::fmin(dn, dep); df = std::fmax(df, dep);
    }
    glm::dvec3 mn(xl, yb, 0.0), mx(xr, yt, 0.0);
    wp_pad_box(mn, mx, 1e-7, 1e-6);  // tangents
    dn *= 1.0 - 1e-7;
    df = std::fmax(df * (1.0 + 1e-7), dn * (1.0 + 1e-6));
    // world -> virtual post-perspective space, z negated (right-handed: near at +1, far at -1)
    const glm::dmat4 PP = wp_flip_z() * wp_frustum(mn.x * dn, mx.x * dn, mn.y * dn, mx.y * dn, dn, df) * Vv;
    if (!wp_fin(PP)) return e;
    glm::dvec3 pts[2 * wp_kMaxRecv] = {};
    for (int i = 0; i < s.nbody; ++i) {
        pts[i] = wp_project(PP, s.body[i]);
        if (!wp_fin(pts[i])) return e;
    }
    const glm::dvec3 c = wp_center(pts, s.nbody);
    double rad = 0.0;
    for (int i = 0; i < s.nbody; ++i) rad = std::fmax(rad, glm::length(pts[i] - c));
    rad = std::fmax(rad, 1e-12);
    // the center line there: the line through m along v (x, y constant: it is the camera axis)
    const glm::dvec3 m = wp_project(PP, s.eye + s.vdir * (0.5 * (dn + df) - slide));
    const glm::dvec3 v(0.0, 0.0, -1.0);
    const glm::dvec4 Lh = PP * Lw;
    const double lxyz = glm::length(glm::dvec3(Lh));
    if (std::fabs(Lh.w) * 1e4 * rad <= lxyz) {
        // post-perspective light (nearly) at infinity: an orthographic fit along its direction
        const glm::dvec3 p0 = s.body[0];
        const double eps = 1e-4 * std::fmax(s.d1 - s.d0, 1e-12);
        const glm::dvec3 tdir = wp_project(PP, p0 + wp_toward_light(s, p0) * eps) - wp_project(PP, p0);
        if (!(glm::length(tdir) > 0.0) || !wp_fin(tdir)) return e;
        const glm::dvec3 travel = -glm::normalize(tdir);
        e.M = wp_ortho_fit(pts, s.nbody, travel, wp_up(travel, travel, v, glm::dvec3(0, 1, 0)), 1.0) * PP;
        e.tan_used = 0.0;
        e.ok = wp_fin(e.M);
        return e;
    }
    const glm::dvec3 S = glm::dvec3(Lh) / Lh.w;
    const bool sink = Lh.w < 0.0;
    // the axis of the narrowest cone around S holding the body, refined (as the world-space point fits)
    const glm::dvec3 f0 = cone_axis(pts, s.nbody, S);
    if (!(glm::length(f0) > 0.0)) return e;
    const glm::dvec3 ms = m - S;
    const glm::dvec3 to_line = glm::length(ms) > 0.0 ? glm::normalize(ms) : f0;
    const glm::dvec3 f = wp_persp_axis(pts, s.nbody, S, to_line, v, glm::dvec3(0, 1, 0));
    glm::dmat4 LF;
    if (!wp_persp_fit(pts, s.nbody, S, f, wp_up(f, to_line, v, glm::dvec3(0, 1, 0)), max_tan, sink, LF, &e.tan_used))
        return e;
    e.M = LF * PP;
    e.ok = wp_fin(e.M);
    return e;
}

// The slide-back: s_min when the light frustum fits there within tan_t, else the smallest that fits
// (s_min + range 4^k, then bisected on the last octave), else the farthest with a frustum up to
// ~89.4 degrees. `slide` gets the slide-back used.
inline WpPsmEval wp_psm_slide(const wp_Setup& s, const glm::dmat4& R, const glm::dvec4& Lw, double s_min, double range,
                              double tan_t, double& slide) {
    slide = s_min;
    WpPsmEval best = wp_psm_eval(s, R, Lw, s_min, tan_t);
    if (!best.ok) {
        // slide back until the light frustum fits: s = s_min + range * 4^k, then bisect on the last octave
        const int kmax = 7;  // up to 4^7 = 16384 body depths: still a well-conditioned float matrix
        double lo = s_min, hi = -1.0;
        WpPsmEval ehi;
        for (int k = 0; k <= kmax; ++k) {
            const double sk = s_min + range * std::pow(4.0, double(k));
            ehi = wp_psm_eval(s, R, Lw, sk, tan_t);
            if (ehi.ok) {
                hi = sk;
                break;
            }
            lo = sk;
        }
        if (hi > 0.0) {
            for (int it = 0; it < 30; ++it) {
                const double mid = lo == s_min ? 0.5 * (lo + hi) : std::sqrt(lo * hi);
                const WpPsmEval em = wp_psm_eval(s, R, Lw, mid, tan_t);
                if (em.ok) {
                    hi = mid;
                    ehi = em;
                } else {
                    lo = mid;
                }
            }
            slide = hi;
            best = ehi;
        } else {
            // even the farthest virtual camera needs a wider frustum: keep it, up to ~89.4 degrees
            slide = s_min + range * std::pow(4.0, double(kmax));
            best = wp_psm_eval(s, R, Lw, slide, 100.0);
        }
    }
    return best;
}

}  // namespace detail

/// Perspective Shadow Maps (Stamminger & Drettakis 2002) in the post-perspective space of a virtual
/// camera (the view's center line, slid back until every body point is in front of it). A light
/// whose post-perspective image has w < 0 (behind the viewer) is a light sink: inverted depth (Kozlov
/// 2004). Where the post-perspective light frustum would need a half-angle above
/// psm_max_half_angle_deg (the light near the view direction), the virtual camera slides back further:
/// the warp weakens continuously towards an orthographic fit instead of switching to it.
inline WarpResult warp_psm_matrix(const WarpInput& in) {
    using namespace detail;
    const wp_Setup s = wp_prepare(in);
    if (s.status != Status::Ok) return wp_fail(s.status, s.detail);
    if (!s.visible) return wp_not_visible();
    double sg, cg;
    wp_gamma(s, sg, cg);
    const glm::dmat4 R = wp_psm_rotation(s);
    double zmin = 1e300, zmax = -1e300;
    for (int i = 0; i < s.nbody; ++i) {
        const double z = glm::dot(s.body[i] - s.eye, s.vdir);
        zmin = std::fmin(zmin, z);
        zmax = std::fmax(zmax, z);
    }
    const double range = std::fmax(zmax - zmin, 1e-12 * s.scale);
    const double nv = std::fmax(std::fmax(s.d0, double(in.options.psm_min_near_fraction) * range), 1e-12 * s.scale);
    const double s_min = std::fmax(0.0, nv - zmin) + double(in.options.psm_slide_back);
    const glm::dvec4 Lw = s.directional ? glm::dvec4(-s.d, 0.0) : glm::dvec4(s.L, 1.0);
    const double tan_t = std::tan(double(in.options.psm_max_half_angle_deg) * wp_kPi / 180.0);
    double slide = s_min;
    const WpPsmEval best = wp_psm_slide(s, R, Lw, s_min, range, tan_t, slide);
    if (!best.ok) {
        glm::dmat4 U;
        if (!wp_uniform_world(s, U)) return wp_fail(Status::LightInsideVolume, "light_position: inside the receivers' body (no frustum holds it)");
        return wp_finish(in, U, U, false, true, 0.0, sg, 0.0);
    }
    const double strength = (s_min + range) / (slide + range);
    return wp_finish(in, best.M, best.M, false, false, strength, sg, slide);
}

/// The method's matrix (warp_uniform_matrix, warp_psm_matrix, warp_lispsm_matrix, warp_tsm_matrix);
/// InvalidArgument for a value outside WarpMethod.
inline WarpResult warp_matrix(const WarpInput& in, WarpMethod method) {
    switch (method) {
    case WarpMethod::Uniform: return warp_uniform_matrix(in);
    case WarpMethod::Psm: return warp_psm_matrix(in);
    case WarpMethod::Lispsm: return warp_lispsm_matrix(in);
    case WarpMethod::Tsm: return warp_tsm_matrix(in);
    }
    return detail::wp_fail(Status::InvalidArgument, "method: unknown WarpMethod");
}

/// Perspective aliasing error at a world point on a surface with the given normal: the largest
/// singular value of d(screen pixels) / d(shadow-map texels) restricted to the surface's tangent
/// plane, i.e. how many screen pixels one shadow-map texel covers along its worst direction (Lloyd et
/// al. 2006; the directional-light form is Apelles eq. 3.17, dp/ds = (z_n/z)(dz/ds) cos(alpha)).
/// NonFinite: NaN/Inf input. InvalidArgument: zero normal, map size 0, an empty viewport, or the point
/// not in front of the camera and the light (clip w <= 0). Overflow: the surface is edge-on to the
/// light (a texel stretched without bound) or the value is not finite.
inline WarpAliasingValue warp_aliasing_error(const glm::mat4& light_view_proj, const glm::mat4& camera_view_proj,
                                             const glm::vec3& world_pos, const glm::vec3& normal,
                                             std::uint32_t shadow_map_size, const glm::uvec2& viewport) {
    using namespace detail;
    WarpAliasingValue out;
    if (!wp_fin(light_view_proj) || !wp_fin(camera_view_proj) || !wp_fin(world_pos) || !wp_fin(normal)) {
        out.status = Status::NonFinite;
        out.detail = !wp_fin(light_view_proj) ? "light_view_proj: NaN or Inf"
                     : (!wp_fin(camera_view_proj) ? "camera_view_proj: NaN or Inf"
                     : (!wp_fin(world_pos) ? "world_pos: NaN or Inf" : "normal: NaN or Inf"));
        return out;
    }
    const glm::dmat4 Lm(light_view_proj), Cm(camera_view_proj);
    const glm::dvec3 x(world_pos);
    glm::dvec3 n(normal);
    out.status = Status::InvalidArgument;
    if (!(glm::length(n) > 0.0) || shadow_map_size == 0 || viewport.x == 0 || viewport.y == 0) {
        out.detail = !(glm::length(n) > 0.0) ? "normal: zero" : (shadow_map_size == 0 ? "shadow_map_size: 0" : "viewport: empty");
        return out;
    }
    n = glm::normalize(n);
    const glm::dvec3 t1 = wp_perp(n);
    const glm::dvec3 t2 = glm::cross(n, t1);
    // Jacobian of a projective map (pixels per world unit) along the two tangents
    auto jac = [&](const glm::dmat4& m, double sx, double sy, glm::dmat2& J) {
        const glm::dvec4 h = m * glm::dvec4(x, 1.0);
        if (!(h.w > 0.0)) return false;
        const glm::dvec2 p = glm::dvec2(h) / h.w;
        for (int k = 0; k < 2; ++k) {
            const glm::dvec4 dh = m * glm::dvec4(k == 0 ? t1 : t2, 0.0);
            const glm::dvec2 dp = (glm::dvec2(dh) - p * dh.w) / h.w;
            J[k] = glm::dvec2(dp.x * sx, dp.y * sy);
        }
        return true;
    };
    glm::dmat2 A, B;  // columns: derivative along t1, t2
    if (!jac(Lm, 0.5 * shadow_map_size, 0.5 * shadow_map_size, A)) return out.detail = "world_pos: behind the light (clip w <= 0)", out;
    if (!jac(Cm, 0.5 * viewport.x, 0.5 * viewport.y, B)) return out.detail = "world_pos: behind the camera (clip w <= 0)", out;
    out.status = Status::Overflow;
    const double det = glm::determinant(A);
    if (!(std::fabs(det) > 0.0) || !wp_fin(det)) return out.detail = "normal: the surface is edge-on to the light", out;
    const glm::dmat2 J = B * glm::inverse(A);  // pixels per texel
    // largest singular value of a 2x2 matrix
    const double a = J[0][0], b = J[1][0], c = J[0][1], d = J[1][1];
    const double s1 = a * a + b * b + c * c + d * d;
    const double s2 = std::sqrt(std::fmax(0.0, (a * a + b * b - c * c - d * d) * (a * a + b * b - c * c - d * d) +
                                                   4.0 * (a * c + b * d) * (a * c + b * d)));
    const double sv = std::sqrt(std::fmax(0.0, 0.5 * (s1 + s2)));
    if (!wp_fin(sv)) return out.detail = "value: not finite", out;
    out.status = Status::Ok;
    out.value = sv;
    return out;
}

/// Samples the receiver volume (nx * ny positions across the view x nz log-spaced view depths,
/// points outside the scene bounds skipped) on surfaces facing the light, and reports the aliasing
/// error statistics of light_view_proj for a shadow_map_size^2 map and a viewport of the given size.
/// nx, ny, nz are clamped to 256. Statuses: those of the fits (wp_prepare) and InvalidArgument for a
/// zero count, size or viewport; Ok with samples = 0 when nothing is visible.
inline WarpAliasingStats warp_measure_aliasing(const WarpInput& in, const glm::mat4& light_view_proj,
                                               std::uint32_t shadow_map_size, const glm::uvec2& viewport,
                                               std::uint32_t nx, std::uint32_t ny, std::uint32_t nz) {
    using namespace detail;
    WarpAliasingStats st;
    const wp_Setup s = wp_prepare(in);
    if (s.status != Status::Ok) {
        st.status = s.status;
        st.detail = s.detail;
        return st;
    }
    if (!wp_fin(light_view_proj)) {
        st.status = Status::NonFinite;
        st.detail = "light_view_proj: NaN or Inf";
        return st;
    }
    if (nx == 0 || ny == 0 || nz == 0 || shadow_map_size == 0 || viewport.x == 0 || viewport.y == 0) {
        st.status = Status::InvalidArgument;
        st.detail = nx == 0 || ny == 0 || nz == 0 ? "nx, ny, nz: 0" : (shadow_map_size == 0 ? "shadow_map_size: 0" : "viewport: empty");
        return st;
    }
    st.status = Status::Ok;
    if (!s.visible) return st;
    nx = nx > 256 ? 256 : nx;
    ny = ny > 256 ? 256 : ny;
    nz = nz > 256 ? 256 : nz;
    const glm::mat4 cvp = in.camera_proj * in.camera_view;
    double sum = 0.0;
    std::uint64_t under = 0, count = 0, skipped = 0;
    for (std::uint32_t k = 0; k < nz; ++k) {
        const double dep = nz == 1 || !(s.d1 > s.d0) ? s.d0 : s.d0 * std::pow(s.d1 / s.d0, double(k) / double(nz - 1));
        const double t = s.d1 > s.d0 ? glm::clamp((dep - s.d0) / (s.d1 - s.d0), 0.0, 1.0) : 0.0;
        for (std::uint32_t j = 0; j < ny; ++j)
            for (std::uint32_t i = 0; i < nx; ++i) {
                const double u = (i + 0.5) / nx, v = (j + 0.5) / ny;
                auto bil = [&](int o) {
                    return glm::mix(glm::mix(s.cw[o], s.cw[o + 1], u), glm::mix(s.cw[o + 2], s.cw[o + 3], u), v);
                };
                const glm::dvec3 p = glm::mix(bil(0), bil(4), t);
                if (in.has_scene_bounds && (p.x < in.scene_min.x || p.y < in.scene_min.y || p.z < in.scene_min.z ||
                                            p.x > in.scene_max.x || p.y > in.scene_max.y || p.z > in.scene_max.z))
                    continue;
                const glm::dvec3 nrm = wp_toward_light(s, p);
                const WarpAliasingValue e = warp_aliasing_error(light_view_proj, cvp, glm::vec3(p), glm::vec3(nrm),
                                                                shadow_map_size, viewport);
                if (e.status != Status::Ok) {
                    ++skipped;
                    continue;
                }
                ++count;
                if (e.value > 1.0) ++under;
                st.max_error = std::fmax(st.max_error, e.value);
                sum += e.value;
            }
    }
    st.samples = static_cast<std::uint32_t>(count);
    st.skipped = static_cast<std::uint32_t>(skipped);
    if (count > 0) {
        st.mean_error = sum / double(count);
        st.undersampled_fraction = double(under) / double(count);
    }
    if (!wp_fin(st.mean_error) || !wp_fin(st.max_error)) {
        WarpAliasingStats o;
        o.status = Status::Overflow;
        o.detail = "mean_error, max_error: not finite";
        return o;
    }
    return st;
}

}  // namespace shadowkit
