// shadowkit/perspective_shadow_maps.hpp - warped shadow-map matrices: uniform, PSM, LiSPSM, TSM,
// and the perspective aliasing error dp/ds to compare them.
//
// Usage:
//   shadowkit::WarpInput in;
//   in.camera_view = view; in.camera_proj = proj;         // GLM, right-handed, column-major
//   in.max_distance = 200.0f;                            // clamp for an infinite far plane
//   in.light = glm::vec4(sun_dir, 0.0f);                 // w = 0: direction the light travels
//   in.has_scene_bounds = true; in.scene_min = lo; in.scene_max = hi;   // receivers and casters
//   shadowkit::WarpResult w = shadowkit::lispsm_shadow_matrix(in);      // or psm_/tsm_/uniform_
//   if (w.status == shadowkit::WarpStatus::Ok) {
//       // render casters with w.light_view_proj; in the receiver pass project the world position with
//       // the same matrix, divide by w, map to [0,1] (glsl/perspective_shadow_maps.glsl) and compare.
//       // w.fallback_uniform says the warp degenerated to a uniform (orthographic) fit.
//   }
//   shadowkit::AliasingStats a = shadowkit::measure_perspective_aliasing(in, w.light_view_proj, 2048, {1920, 1080}, 32, 32, 32);
//
// Based on:
//   Stamminger & Drettakis 2002, "Perspective Shadow Maps" (post-perspective light; directional
//     lights become point lights; slide-back of the virtual camera), Kozlov 2004, "Perspective Shadow
//     Maps: Care and Feeding" (GPU Gems, ch. 14: lights behind the viewer as inverted projections).
//   Wimmer, Scherzer & Purgathofer 2004, "Light Space Perspective Shadow Maps" (n_opt, falloff).
//   Martin & Tan 2004, "Anti-aliasing and Continuity with Trapezoidal Shadow Maps" (80% rule).
//   Lloyd et al. 2006/2008, "Warping and Partitioning for Low Error Shadow Maps" (aliasing metric);
//     Moschig, "Apelles" thesis, eq. 3.17 (dp/ds = (z_n / z) (dz / ds) cos(alpha)).
//
// Conventions: every matrix maps world space to the light's clip space with the requested depth
// convention; points closer to the light get smaller depth (larger with reversed_z), so the usual
// LESS (GREATER) depth test works for every method, including PSM's inverted (light-sink) case.
//
// MIT License. Copyright (c) shadowkit contributors.
#pragma once

#include <glm/glm.hpp>

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

enum class WarpStatus {
    Ok,
    InvalidInput,       ///< NaN/Inf, singular matrices, zero light direction, bad options
    InfiniteFar,        ///< infinite far plane and max_distance <= 0
    EmptyReceivers,     ///< the camera slice does not meet the scene bounds
    LightInsideVolume   ///< point light inside/around the receiver volume: no single frustum fits
};

/// Tuning. Zero-initialised fields are NOT defaults: construct with WarpOptions{} to get these.
struct WarpOptions {
    /// LiSPSM: multiplies n_opt (> 1 weaker warp, < 1 stronger). [Limit: > 0]
    float lispsm_n_scale = 1.0f;
    /// LiSPSM: below this sin(gamma) (angle between view and light) the warp is off (uniform). Between
    /// it and twice it the warp fades out continuously (n -> infinity). filament uses 0.02 (~1.15 deg).
    float lispsm_min_sin_gamma = 0.02f;
    /// TSM: at |cos gamma| >= this the fit is uniform (DagorEngine: 0.95); the warp fades out over
    /// the 0.05 below it.
    float tsm_max_abs_cos_gamma = 0.95f;
    /// TSM: view depth [wu] of the focus point; <= 0: sqrt(near * far) of the receiver slice (measured
    /// to keep the max aliasing error near its minimum for far/near from 10 to 1000).
    float tsm_focus_depth = 0.0f;
    /// TSM: fraction of the map given to the region in front of the focus point (the 80% rule).
    float tsm_focus_ratio = 0.8f;
    /// PSM: virtual camera near plane >= this fraction of the body's depth range (slide-back).
    float psm_min_near_fraction = 0.02f;
    /// PSM: extra slide-back [wu] on top of what keeps all casters in front of the virtual camera.
    float psm_slide_back = 0.0f;
    /// PSM: if the post-perspective light frustum needs a half-angle wider than this, fall back.
    float psm_max_half_angle_deg = 80.0f;
};

/// Same inputs for every method.
struct WarpInput {
    glm::mat4 camera_view{1.0f};
    glm::mat4 camera_proj{1.0f};
    ClipDepth camera_depth = ClipDepth::NegativeOneToOne;
    bool camera_reversed_z = false;
    float max_distance = 0.0f;        ///< [wu] far clamp; required for infinite projections
    float receiver_min_depth = 0.0f;  ///< [wu] visible receivers' view-depth range, used when max > min > 0
    float receiver_max_depth = 0.0f;
    glm::vec4 light{0.0f, -1.0f, 0.0f, 0.0f};  ///< w == 0: travel direction; else point light at xyz / w
    bool has_scene_bounds = false;    ///< receivers are clipped to these bounds
    glm::vec3 scene_min{0.0f};
    glm::vec3 scene_max{0.0f};
    bool has_caster_bounds = false;   ///< all casters; the volume is extended towards the light to reach
    glm::vec3 caster_min{0.0f};       ///< them (scene bounds are used when absent)
    glm::vec3 caster_max{0.0f};
    ClipDepth light_depth = ClipDepth::NegativeOneToOne;
    bool light_reversed_z = false;
    WarpOptions options{};
};

struct WarpResult {
    glm::mat4 light_view_proj{1.0f};  ///< world -> light clip space (render casters, look up receivers)
    bool fallback_uniform = false;    ///< the method degenerated to the uniform fit
    WarpStatus status = WarpStatus::InvalidInput;
    float sin_gamma = 0.0f;           ///< sin of the angle between view and light direction
    float warp_parameter = 0.0f;      ///< LiSPSM n, TSM eta, PSM slide-back distance (world or NDC units)
};

struct AliasingStats {
    double max_error = 0.0;             ///< max over samples of the texel footprint in screen pixels
    double mean_error = 0.0;
    double undersampled_fraction = 0.0; ///< fraction of samples with error > 1 (a texel covers > 1 pixel)
    std::uint32_t samples = 0;
};

namespace psm_detail {

inline bool fin(double v) { return std::isfinite(v); }
inline bool fin(const glm::dvec3& v) { return fin(v.x) && fin(v.y) && fin(v.z); }
inline bool fin(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}
inline bool fin(const glm::dmat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}

inline glm::dmat4 depth_convention(ClipDepth cd, bool reversed) {
    glm::dmat4 m(1.0);
    if (cd == ClipDepth::ZeroToOne) {
        m[2][2] = reversed ? -0.5 : 0.5;
        m[3][2] = 0.5;
    } else if (reversed) {
        m[2][2] = -1.0;
    }
    return m;
}

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

inline glm::dvec3 perp_axis(const glm::dvec3& d) {
    const glm::dvec3 a = glm::abs(d);
    if (a.y <= a.x && a.y <= a.z) return glm::dvec3(0, 1, 0);
    if (a.z <= a.x) return glm::dvec3(0, 0, 1);
    return glm::dvec3(1, 0, 0);
}

/// Ortho box -> [-1,1]^3 (GL), x/y/z given as ranges of view x, view y and depth (= -view z).
inline glm::dmat4 ortho_box(const glm::dvec3& mn, const glm::dvec3& mx) {
    glm::dmat4 m(1.0);
    m[0][0] = 2.0 / (mx.x - mn.x);
    m[1][1] = 2.0 / (mx.y - mn.y);
    m[2][2] = 2.0 / (mx.z - mn.z);
    m[3][0] = -(mx.x + mn.x) / (mx.x - mn.x);
    m[3][1] = -(mx.y + mn.y) / (mx.y - mn.y);
    m[3][2] = -(mx.z + mn.z) / (mx.z - mn.z);
    return m;
}

/// Negates view z (so depth = distance along the view direction).
inline glm::dmat4 flip_z() {
    glm::dmat4 m(1.0);
    m[2][2] = -1.0;
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

inline glm::dvec3 project(const glm::dmat4& m, const glm::dvec3& p) {
    const glm::dvec4 h = m * glm::dvec4(p, 1.0);
    return glm::dvec3(h) / h.w;
}

/// Grows a degenerate (zero-size) range so a fit never divides by zero.
inline void pad_box(glm::dvec3& mn, glm::dvec3& mx, double rel) {
    double ext = 0.0, mag = 0.0;
    for (int i = 0; i < 3; ++i) {
        ext = std::fmax(ext, mx[i] - mn[i]);
        mag = std::fmax(mag, std::fmax(std::fabs(mn[i]), std::fabs(mx[i])));
    }
    const double pad = std::fmax(std::fmax(ext * rel, 1e-9 * mag), 1e-9);  // matrix entries stay < ~1e9
    mn -= glm::dvec3(pad);
    mx += glm::dvec3(pad);
}

constexpr int kMaxRecv = 64;

/// Everything the methods share: the receiver volume, the body extended towards the light.
struct Setup {
    WarpStatus status = WarpStatus::InvalidInput;
    bool directional = true;
    glm::dvec3 d{0.0};       ///< directional: unit travel direction
    glm::dvec3 L{0.0};       ///< point light position
    glm::dvec3 eye{0.0}, vdir{0.0};
    glm::dmat3 cam_rot{1.0}; ///< world -> view rotation
    glm::dvec3 cw[8];        ///< slice corners (world)
    glm::dvec3 nc{0.0}, fc{0.0};  ///< slice near/far centers (world)
    double d0 = 0, d1 = 0;
    glm::dvec3 recv[kMaxRecv];
    int nrecv = 0;
    glm::dvec3 body[2 * kMaxRecv];
    int nbody = 0;
    double scale = 1.0;
};

inline glm::dvec3 toward_light(const Setup& s, const glm::dvec3& p) {
    return s.directional ? -s.d : glm::normalize(s.L - p);
}

inline Setup prepare(const WarpInput& in) {
    Setup s;
    const WarpOptions& o = in.options;
    auto ff = [](float v) { return std::isfinite(v); };
    if (!fin(in.camera_view) || !fin(in.camera_proj) || !ff(in.light.x) || !ff(in.light.y) || !ff(in.light.z) ||
        !ff(in.light.w) || !ff(in.max_distance) || !ff(in.receiver_min_depth) || !ff(in.receiver_max_depth))
        return s;
    if (!(o.lispsm_n_scale > 0.0f) || !ff(o.lispsm_n_scale) || !(o.lispsm_min_sin_gamma >= 0.0f) ||
        !(o.lispsm_min_sin_gamma < 0.5f) || !(o.tsm_max_abs_cos_gamma > 0.05f) || !(o.tsm_max_abs_cos_gamma <= 1.0f) ||
        !ff(o.tsm_focus_depth) || !(o.tsm_focus_ratio > 0.0f) || !(o.tsm_focus_ratio < 1.0f) || !(o.psm_min_near_fraction >= 0.0f) ||
        !ff(o.psm_min_near_fraction) || !(o.psm_slide_back >= 0.0f) || !ff(o.psm_slide_back) ||
        !(o.psm_max_half_angle_deg > 1.0f) || !(o.psm_max_half_angle_deg < 89.0f))
        return s;
    auto box_ok = [&](const glm::vec3& a, const glm::vec3& b) {
        return ff(a.x) && ff(a.y) && ff(a.z) && ff(b.x) && ff(b.y) && ff(b.z) && a.x <= b.x && a.y <= b.y && a.z <= b.z;
    };
    if (in.has_scene_bounds && !box_ok(in.scene_min, in.scene_max)) return s;
    if (in.has_caster_bounds && !box_ok(in.caster_min, in.caster_max)) return s;
    s.directional = in.light.w == 0.0f;
    if (s.directional) {
        const glm::dvec3 d(in.light);
        if (!(glm::length(d) > 0.0)) return s;
        s.d = glm::normalize(d);
    } else {
        s.L = glm::dvec3(in.light) / double(in.light.w);
        if (!fin(s.L)) return s;
    }
    // camera slice in view space
    const glm::dmat4 P(in.camera_proj), V(in.camera_view);
    const double pdet = glm::determinant(P), vdet = glm::determinant(V);
    if (!fin(pdet) || std::fabs(pdet) < 1e-300 || !fin(vdet) || std::fabs(vdet) < 1e-300) return s;
    const glm::dmat4 ip = glm::inverse(P), iv = glm::inverse(V);
    if (!fin(ip) || !fin(iv)) return s;
    const double lo = in.camera_depth == ClipDepth::ZeroToOne ? 0.0 : -1.0;
    const double zn = in.camera_reversed_z ? 1.0 : lo, zf = in.camera_reversed_z ? lo : 1.0;
    glm::dvec3 pn[4], dir[4];
    double dn[4], dfar[4];
    bool infinite = false;
    for (int i = 0; i < 4; ++i) {
        const double x = (i & 1) ? 1.0 : -1.0, y = (i & 2) ? 1.0 : -1.0;
        const glm::dvec4 hn = ip * glm::dvec4(x, y, zn, 1.0), hf = ip * glm::dvec4(x, y, zf, 1.0);
        const double sn = std::fabs(hn.x) + std::fabs(hn.y) + std::fabs(hn.z);
        if (!(std::fabs(hn.w) > 1e-12 * sn) || std::fabs(hn.w) < 1e-300) return s;
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
        if (!(dir[i].z < 0.0) || !fin(dn[i])) return s;
    }
    double d0 = dn[0], d1 = dfar[0];
    for (int i = 1; i < 4; ++i) {
        d0 = std::fmax(d0, dn[i]);
        d1 = std::fmin(d1, dfar[i]);
    }
    if (in.max_distance > 0.0f) d1 = std::fmin(d1, double(in.max_distance));
    else if (infinite) { s.status = WarpStatus::InfiniteFar; return s; }
    if (in.receiver_max_depth > in.receiver_min_depth && in.receiver_min_depth > 0.0f) {
        d0 = std::fmax(d0, double(in.receiver_min_depth));
        d1 = std::fmin(d1, double(in.receiver_max_depth));
    }
    if (!(d1 > d0) || !fin(d1 - d0)) { s.status = WarpStatus::EmptyReceivers; return s; }
    s.d0 = d0;
    s.d1 = d1;
    for (int i = 0; i < 4; ++i) {
        const glm::dvec3 a = pn[i] + ((d0 - dn[i]) / -dir[i].z) * dir[i];
        const glm::dvec3 b = pn[i] + ((d1 - dn[i]) / -dir[i].z) * dir[i];
        s.cw[i] = glm::dvec3(iv * glm::dvec4(a, 1.0));
        s.cw[i + 4] = glm::dvec3(iv * glm::dvec4(b, 1.0));
    }
    for (int i = 0; i < 8; ++i)
        if (!fin(s.cw[i])) return s;
    s.eye = glm::dvec3(iv[3]);
    s.cam_rot = glm::dmat3(V);
    s.vdir = -glm::normalize(glm::dvec3(iv[2]));
    s.nc = (s.cw[0] + s.cw[1] + s.cw[2] + s.cw[3]) * 0.25;
    s.fc = (s.cw[4] + s.cw[5] + s.cw[6] + s.cw[7]) * 0.25;
    if (!fin(s.eye) || !fin(s.vdir)) return s;
    for (int i = 0; i < 8; ++i) s.scale = std::fmax(s.scale, glm::length(s.cw[i]));

    // receiver volume: slice, intersected with the scene box (vertices from plane triples)
    if (!in.has_scene_bounds) {
        for (int i = 0; i < 8; ++i) s.recv[s.nrecv++] = s.cw[i];
    } else {
        glm::dvec4 pl[12];
        constexpr int faces[6][4] = {{0, 1, 3, 2}, {4, 5, 7, 6}, {0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 3, 7, 6}};
        const glm::dvec3 ctr = (s.nc + s.fc) * 0.5;
        for (int f = 0; f < 6; ++f) {
            const glm::dvec3 a = s.cw[faces[f][0]], b = s.cw[faces[f][1]], c = s.cw[faces[f][2]], e = s.cw[faces[f][3]];
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
                    if (!fin(p)) continue;
                    bool inside = true;
                    for (int m = 0; m < 12 && inside; ++m) inside = glm::dot(glm::dvec3(pl[m]), p) + pl[m].w >= -tol;
                    if (!inside) continue;
                    bool dup = false;
                    for (int m = 0; m < s.nrecv && !dup; ++m) dup = glm::length(s.recv[m] - p) <= tol;
                    if (!dup && s.nrecv < kMaxRecv) s.recv[s.nrecv++] = p;
                }
        if (s.nrecv == 0) { s.status = WarpStatus::EmptyReceivers; return s; }
    }
    // body: receivers plus their extension towards the light up to the caster bounds
    for (int i = 0; i < s.nrecv; ++i) s.body[s.nbody++] = s.recv[i];
    const bool hc = in.has_caster_bounds || in.has_scene_bounds;
    const glm::dvec3 cmn = in.has_caster_bounds ? glm::dvec3(in.caster_min) : glm::dvec3(in.scene_min);
    const glm::dvec3 cmx = in.has_caster_bounds ? glm::dvec3(in.caster_max) : glm::dvec3(in.scene_max);
    if (hc) {
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
    s.status = WarpStatus::Ok;
    return s;
}

/// Uniform fit of points (already in a space where the light is directional along d) in the frame
/// whose image y axis is `up` (projected perpendicular to d). Returns GL clip, depth along d.
inline glm::dmat4 ortho_fit(const glm::dvec3* pts, int n, const glm::dvec3& d, const glm::dvec3& up_hint) {
    glm::dvec3 up = up_hint - glm::dot(up_hint, d) * d;
    if (!(glm::length(up) > 1e-9)) up = perp_axis(d);
    glm::dvec3 c(0.0);
    for (int i = 0; i < n; ++i) c += pts[i];
    c /= double(n);
    const glm::dmat4 lv = look_dir(c, d, glm::normalize(up));
    glm::dvec3 mn(1e300), mx(-1e300);
    for (int i = 0; i < n; ++i) {
        glm::dvec3 p = glm::dvec3(lv * glm::dvec4(pts[i], 1.0));
        p.z = -p.z;
        mn = glm::min(mn, p);
        mx = glm::max(mx, p);
    }
    pad_box(mn, mx, 1e-7);
    return ortho_box(mn, mx) * flip_z() * lv;
}

/// Perspective fit from point S looking at pts (all in front). Returns false if impossible or wider
/// than max_tan (tangent of the half-angle). invert: depth decreasing with distance (light sink).
inline bool persp_fit(const glm::dvec3* pts, int n, const glm::dvec3& S, double max_tan, bool invert, glm::dmat4& out) {
    glm::dvec3 c(0.0);
    for (int i = 0; i < n; ++i) c += pts[i];
    c /= double(n);
    const glm::dvec3 ax = c - S;
    const double al = glm::length(ax);
    if (!(al > 0.0) || !fin(al)) return false;
    const glm::dvec3 f = ax / al;
    const glm::dmat4 lv = look_dir(S, f, perp_axis(f));
    double xl = 1e300, xr = -1e300, yb = 1e300, yt = -1e300, dn = 1e300, df = 0.0;
    for (int i = 0; i < n; ++i) {
        const glm::dvec3 p = glm::dvec3(lv * glm::dvec4(pts[i], 1.0));
        const double dep = -p.z;
        if (!(dep > 1e-12 * al)) return false;
        const double x = p.x / dep, y = p.y / dep;
        if (std::fabs(x) > max_tan || std::fabs(y) > max_tan) return false;
        xl = std::fmin(xl, x); xr = std::fmax(xr, x);
        yb = std::fmin(yb, y); yt = std::fmax(yt, y);
        dn = std::fmin(dn, dep); df = std::fmax(df, dep);
    }
    const double padx = std::fmax((xr - xl) * 1e-7, 1e-12), pady = std::fmax((yt - yb) * 1e-7, 1e-12);
    dn *= (1.0 - 1e-7);
    df = std::fmax(df * (1.0 + 1e-7), dn * (1.0 + 1e-6));
    glm::dmat4 p = frustum((xl - padx) * dn, (xr + padx) * dn, (yb - pady) * dn, (yt + pady) * dn, dn, df);
    if (invert) {
        // inverted projection for a post-perspective light sink: depth decreases with distance
        for (int col = 0; col < 4; ++col) p[col][2] = -p[col][2];
    }
    out = p * lv;
    return fin(out);
}

/// Base uniform fit in world space: ortho along d (directional) or perspective from L (point).
inline bool uniform_world(const Setup& s, glm::dmat4& out) {
    if (s.directional) {
        out = ortho_fit(s.body, s.nbody, s.d, s.vdir);
        return fin(out);
    }
    return persp_fit(s.body, s.nbody, s.L, 100.0, false, out);  // up to ~89.4 degrees
}

inline WarpResult finish(const WarpInput& in, const glm::dmat4& m, bool fallback, double sin_gamma, double param) {
    WarpResult r;
    const glm::dmat4 f = depth_convention(in.light_depth, in.light_reversed_z) * m;
    r.light_view_proj = glm::mat4(f);
    if (!fin(f) || !fin(r.light_view_proj)) {
        r.light_view_proj = glm::mat4(1.0f);
        r.status = WarpStatus::InvalidInput;
        return r;
    }
    r.status = WarpStatus::Ok;
    r.fallback_uniform = fallback;
    auto to_float = [](double v) {
        const double lim = double(std::numeric_limits<float>::max());
        return static_cast<float>(fin(v) ? glm::clamp(v, -lim, lim) : 0.0);
    };
    r.sin_gamma = to_float(sin_gamma);
    r.warp_parameter = to_float(param);
    return r;
}

inline WarpResult fail(WarpStatus st) {
    WarpResult r;
    r.status = st;
    return r;
}

inline double smooth01(double x) {
    x = glm::clamp(x, 0.0, 1.0);
    return x * x * (3.0 - 2.0 * x);
}

/// sin/cos of the angle between the view direction and the light direction (towards the slice).
inline void gamma_of(const Setup& s, double& sin_g, double& cos_g) {
    const glm::dvec3 d = s.directional ? s.d : glm::normalize((s.nc + s.fc) * 0.5 - s.L);
    cos_g = glm::clamp(glm::dot(s.vdir, d), -1.0, 1.0);
    sin_g = glm::length(glm::cross(s.vdir, d));
}

}  // namespace psm_detail

/// Uniform (standard) shadow map fitted to the receiver volume extended towards the light:
/// orthographic for directional lights, perspective for point lights.
inline WarpResult uniform_shadow_matrix(const WarpInput& in) {
    using namespace psm_detail;
    const Setup s = prepare(in);
    if (s.status != WarpStatus::Ok) return fail(s.status);
    glm::dmat4 m;
    if (!uniform_world(s, m)) return fail(WarpStatus::LightInsideVolume);
    double sg, cg;
    gamma_of(s, sg, cg);
    return finish(in, m, false, sg, 0.0);
}

/// Light Space Perspective Shadow Maps (Wimmer et al. 2004). A perspective warp whose axis is
/// perpendicular to the light (so the light stays directional), strength from n_opt.
inline WarpResult lispsm_shadow_matrix(const WarpInput& in) {
    using namespace psm_detail;
    const Setup s = prepare(in);
    if (s.status != WarpStatus::Ok) return fail(s.status);
    glm::dmat4 base(1.0);  // world -> space where the light is directional
    glm::dvec3 d = s.d;
    glm::dvec3 pts[2 * kMaxRecv];
    glm::dvec3 nc = s.nc, fc = s.fc;
    if (s.directional) {
        for (int i = 0; i < s.nbody; ++i) pts[i] = s.body[i];
    } else {
        // point light: its own post-perspective space turns it into a directional light along +z
        if (!persp_fit(s.body, s.nbody, s.L, 100.0, false, base)) return fail(WarpStatus::LightInsideVolume);
        for (int i = 0; i < s.nbody; ++i) pts[i] = project(base, s.body[i]);
        nc = project(base, s.nc);
        fc = project(base, s.fc);
        d = glm::dvec3(0, 0, 1);
    }
    double sg_w, cg_w;
    gamma_of(s, sg_w, cg_w);
    const glm::dvec3 v = glm::normalize(fc - nc);
    const glm::dvec3 vp = v - glm::dot(v, d) * d;
    const double sg = glm::length(vp);
    const double s0 = double(in.options.lispsm_min_sin_gamma);
    const double fade = s0 > 0.0 ? smooth01((sg - s0) / s0) : (sg > 0.0 ? 1.0 : 0.0);
    const glm::dvec3 up = sg > 1e-9 ? vp / sg : perp_axis(d);
    if (!(fade > 0.0) || !fin(sg)) {
        const glm::dmat4 m = ortho_fit(pts, s.nbody, d, up) * base;
        return finish(in, m, true, sg_w, 0.0);
    }
    // light-space frame: x lateral, y along the view direction projected perpendicular to the light
    // (the warp axis), z against the light; origin at the slice's near center (the eye's lateral spot)
    const glm::dmat4 lv = look_dir(nc, d, up);
    double ymin = 1e300, ymax = -1e300;
    for (int i = 0; i < s.nbody; ++i) {
        const double y = (lv * glm::dvec4(pts[i], 1.0)).y;
        ymin = std::fmin(ymin, y);
        ymax = std::fmax(ymax, y);
    }
    const double D = ymax - ymin;
    // n_opt (Wimmer et al. 2004, sec. 5): n = (z_n' + sqrt(z_n' z_f')) / sin(gamma), z_n' = z_n / sin(gamma),
    // z_f' = z_n' + D sin(gamma); equals z_n + sqrt(z_n z_f) for gamma = 90 deg. Computed in world units
    // and carried to the warp space as the ratio n / D (the warp is scale invariant).
    double Dw = D;
    if (!s.directional) {
        // world extent of the body along the world warp axis
        const glm::dvec3 dw = glm::normalize((s.nc + s.fc) * 0.5 - s.L);
        glm::dvec3 vpw = s.vdir - glm::dot(s.vdir, dw) * dw;
        vpw = glm::length(vpw) > 1e-12 ? glm::normalize(vpw) : perp_axis(dw);
        double a = 1e300, b = -1e300;
        for (int i = 0; i < s.nbody; ++i) {
            a = std::fmin(a, glm::dot(s.body[i], vpw));
            b = std::fmax(b, glm::dot(s.body[i], vpw));
        }
        Dw = b - a;
    }
    const double sgn = s.directional ? sg : std::fmax(sg_w, 1e-9);
    const double zn = s.d0 / sgn;
    const double zf = zn + Dw * sgn;
    double n_world = (zn + std::sqrt(zn * zf)) / sgn;
    n_world *= double(in.options.lispsm_n_scale) / fade;  // falloff: n -> infinity as the warp fades out
    const double n = (Dw > 0.0 && D > 0.0) ? n_world * (D / Dw) : 0.0;
    if (!(D > 1e-12 * s.scale) || !(n > 0.0) || !fin(n) || n > 1e7 * D) {
        const glm::dmat4 m = ortho_fit(pts, s.nbody, d, up) * base;
        return finish(in, m, true, sg_w, fin(n) ? n : 0.0);
    }
    const double f = n + D;
    const double c0 = ymin - n;  // projection center on the warp axis
    glm::dmat4 W(0.0);           // (X, Y, Z) -> (X, y_ndc * Y', Z, Y'), Y' = Y - c0
    W[0][0] = 1.0;
    W[1][1] = (f + n) / (f - n);
    W[3][1] = -(f + n) / (f - n) * c0 - 2.0 * f * n / (f - n);
    W[2][2] = 1.0;
    W[1][3] = 1.0;
    W[3][3] = -c0;
    const glm::dmat4 WL = W * lv;
    glm::dvec3 mn(1e300), mx(-1e300);
    for (int i = 0; i < s.nbody; ++i) {
        glm::dvec3 p = project(WL, pts[i]);
        p.z = -p.z;  // depth: away from the light
        mn = glm::min(mn, p);
        mx = glm::max(mx, p);
    }
    pad_box(mn, mx, 1e-7);
    const glm::dmat4 m = ortho_box(mn, mx) * flip_z() * WL * base;
    return finish(in, m, false, sg_w, n);
}

/// Trapezoidal Shadow Maps (Martin & Tan 2004): the receiver volume's hull in the uniform light's
/// post-perspective space bounded by a trapezoid (top/base orthogonal to the projected view center
/// line, sides through the projection point q), mapped to the unit square; the 80% rule picks q.
inline WarpResult tsm_shadow_matrix(const WarpInput& in) {
    using namespace psm_detail;
    const Setup s = prepare(in);
    if (s.status != WarpStatus::Ok) return fail(s.status);
    glm::dmat4 U;
    if (!uniform_world(s, U)) return fail(WarpStatus::LightInsideVolume);
    double sg, cg;
    gamma_of(s, sg, cg);
    const double cmax = double(in.options.tsm_max_abs_cos_gamma);
    const double fade = smooth01((cmax - std::fabs(cg)) / 0.05);
    if (!(fade > 0.0)) return finish(in, U, true, sg, 0.0);
    // 2D points in light NDC
    glm::dvec2 p2[kMaxRecv];
    for (int i = 0; i < s.nrecv; ++i) p2[i] = glm::dvec2(project(U, s.recv[i]));
    const glm::dvec2 pn(project(U, s.nc)), pf(project(U, s.fc));
    const glm::dvec2 cl = pf - pn;
    const double cll = glm::length(cl);
    if (!(cll > 1e-9) || !fin(cll)) return finish(in, U, true, sg, 0.0);
    const glm::dvec2 u = cl / cll, up(-u.y, u.x);
    double tmin = 1e300, tmax = -1e300;
    for (int i = 0; i < s.nrecv; ++i) {
        const double t = glm::dot(p2[i] - pn, u);
        tmin = std::fmin(tmin, t);
        tmax = std::fmax(tmax, t);
    }
    const double lambda = tmax - tmin;
    if (!(lambda > 1e-9)) return finish(in, U, true, sg, 0.0);
    // focus point on the view center line, at a view depth (default: geometric mean of near and far)
    double fdep = double(in.options.tsm_focus_depth);
    if (!(fdep > 0.0)) fdep = std::sqrt(s.d0 * s.d1);
    fdep = glm::clamp(fdep, s.d0, s.d1);
    const glm::dvec3 fw = s.nc + (s.fc - s.nc) * ((fdep - s.d0) / (s.d1 - s.d0));
    const double delta = glm::clamp(glm::dot(glm::dvec2(project(U, fw)) - pn, u) - tmin, 0.0, lambda);
    // Martin & Tan 2004, sec. 4: the focus point maps to xi (80% line): with y(top) = -1, y(base) = +1,
    // xi = 2 ratio - 1 and eta = lambda delta (1 - xi) / (lambda (1 + xi) - 2 delta).
    const double xi = 2.0 * double(in.options.tsm_focus_ratio) - 1.0;
    const double den = lambda * (1.0 + xi) - 2.0 * delta;
    double eta = den > 1e-12 * lambda ? lambda * delta * (1.0 - xi) / den : 1e7 * lambda;
    eta = std::fmax(eta, 1e-3 * lambda);
    eta /= fade;  // fade to a rectangle (uniform) towards the fallback threshold
    if (!fin(eta) || eta > 1e7 * lambda) return finish(in, U, true, sg, fin(eta) ? eta : 0.0);
    const glm::dvec2 q = pn + (tmin - eta) * u;
    double rmin = 1e300, rmax = -1e300;
    for (int i = 0; i < s.nrecv; ++i) {
        const glm::dvec2 w = p2[i] - q;
        const double r = glm::dot(w, up) / glm::dot(w, u);
        rmin = std::fmin(rmin, r);
        rmax = std::fmax(rmax, r);
    }
    const double rmid = 0.5 * (rmin + rmax);
    double rhalf = 0.5 * (rmax - rmin);
    if (!(rhalf > 1e-12)) rhalf = 1e-12;
    const double nn = eta, ff = eta + lambda;
    // rows acting on the uniform light's clip vector (x, y, z, w)
    const glm::dvec4 brow(u.x, u.y, 0.0, -glm::dot(q, u));
    const glm::dvec4 arow(up.x, up.y, 0.0, -glm::dot(q, up));
    const glm::dvec4 xrow = (arow - rmid * brow) / rhalf;
    const glm::dvec4 yrow = brow * ((ff + nn) / (ff - nn)) + glm::dvec4(0, 0, 0, -2.0 * ff * nn / (ff - nn));
    const glm::dvec4 zrow(0.0, 0.0, nn * (1.0 - 1e-9), 0.0);  // z / b stays in [-1,1] since b >= eta
    glm::dmat4 N(0.0);
    for (int c = 0; c < 4; ++c) {
        N[c][0] = xrow[c];
        N[c][1] = yrow[c];
        N[c][2] = zrow[c];
        N[c][3] = brow[c];
    }
    return finish(in, N * U, false, sg, eta);
}

/// Perspective Shadow Maps (Stamminger & Drettakis 2002) in the post-perspective space of a virtual
/// camera slid back until the whole body (receivers and casters) is in front of it. A light whose
/// post-perspective image has w < 0 (behind the viewer) is a light sink: inverted depth (Kozlov 2004).
inline WarpResult psm_shadow_matrix(const WarpInput& in) {
    using namespace psm_detail;
    const Setup s = prepare(in);
    if (s.status != WarpStatus::Ok) return fail(s.status);
    double sg, cg;
    gamma_of(s, sg, cg);
    auto uniform_fallback = [&](double param) {
        glm::dmat4 U;
        if (!uniform_world(s, U)) return fail(WarpStatus::LightInsideVolume);
        return finish(in, U, true, sg, param);
    };
    // virtual camera: same orientation, eye slid back along -view so that every body point has
    // view depth >= n_v (slide-back; the body includes the casters towards the light)
    double zmin = 1e300, zmax = -1e300;
    for (int i = 0; i < s.nbody; ++i) {
        const double z = glm::dot(s.body[i] - s.eye, s.vdir);
        zmin = std::fmin(zmin, z);
        zmax = std::fmax(zmax, z);
    }
    const double range = zmax - zmin;
    const double nv = std::fmax(std::fmax(s.d0, double(in.options.psm_min_near_fraction) * range), 1e-12 * s.scale);
    const double slide = std::fmax(0.0, nv - zmin) + double(in.options.psm_slide_back);
    const glm::dvec3 veye = s.eye - slide * s.vdir;
    glm::dmat4 Vv(s.cam_rot);
    Vv[3] = glm::dvec4(-(s.cam_rot * veye), 1.0);
    double xl = 1e300, xr = -1e300, yb = 1e300, yt = -1e300, dn = 1e300, df = 0.0;
    for (int i = 0; i < s.nbody; ++i) {
        const glm::dvec3 p = glm::dvec3(Vv * glm::dvec4(s.body[i], 1.0));
        const double dep = -p.z;
        if (!(dep > 0.0)) return uniform_fallback(slide);
        xl = std::fmin(xl, p.x / dep); xr = std::fmax(xr, p.x / dep);
        yb = std::fmin(yb, p.y / dep); yt = std::fmax(yt, p.y / dep);
        dn = std::fmin(dn, dep); df = std::fmax(df, dep);
    }
    dn *= 1.0 - 1e-7;
    df = std::fmax(df * (1.0 + 1e-7), dn * (1.0 + 1e-6));
    const double px = std::fmax((xr - xl) * 1e-7, 1e-12), py = std::fmax((yt - yb) * 1e-7, 1e-12);
    const glm::dmat4 Pv = frustum((xl - px) * dn, (xr + px) * dn, (yb - py) * dn, (yt + py) * dn, dn, df);
    const glm::dmat4 PP = Pv * Vv;  // world -> virtual post-perspective (clip)
    if (!fin(PP)) return uniform_fallback(slide);
    glm::dvec3 pts[2 * kMaxRecv];
    glm::dvec3 c(0.0);
    for (int i = 0; i < s.nbody; ++i) {
        pts[i] = project(PP, s.body[i]);
        if (!fin(pts[i])) return uniform_fallback(slide);
        c += pts[i];
    }
    c /= double(s.nbody);
    double rad = 0.0;
    for (int i = 0; i < s.nbody; ++i) rad = std::fmax(rad, glm::length(pts[i] - c));
    rad = std::fmax(rad, 1e-12);
    // the light in post-perspective space (a directional light becomes a point on the infinity plane)
    const glm::dvec4 Lh = s.directional ? PP * glm::dvec4(-s.d, 0.0) : PP * glm::dvec4(s.L, 1.0);
    const double lxyz = glm::length(glm::dvec3(Lh));
    glm::dmat4 M;
    if (std::fabs(Lh.w) * 1e4 * rad <= lxyz) {
        // post-perspective light (nearly) at infinity: parallel light there; direction from a pair
        const glm::dvec3 p0 = s.body[0];
        const double eps = 1e-4 * std::fmax(s.d1 - s.d0, 1e-12);
        const glm::dvec3 p1 = p0 + toward_light(s, p0) * eps;
        glm::dvec3 tdir = project(PP, p1) - project(PP, p0);
        if (!(glm::length(tdir) > 0.0) || !fin(tdir)) return uniform_fallback(slide);
        const glm::dvec3 travel = -glm::normalize(tdir);
        M = ortho_fit(pts, s.nbody, travel, glm::dvec3(0, 1, 0)) * PP;
    } else {
        const glm::dvec3 S = glm::dvec3(Lh) / Lh.w;
        const bool sink = Lh.w < 0.0;
        const double max_tan = std::tan(double(in.options.psm_max_half_angle_deg) * 3.14159265358979323846 / 180.0);
        glm::dmat4 LF;
        if (!persp_fit(pts, s.nbody, S, max_tan, sink, LF)) return uniform_fallback(slide);
        M = LF * PP;
    }
    if (!fin(M)) return uniform_fallback(slide);
    return finish(in, M, false, sg, slide);
}

/// Perspective aliasing error at a world point on a surface with the given normal: the largest
/// singular value of d(screen pixels) / d(shadow-map texels) restricted to the surface's tangent
/// plane, i.e. how many screen pixels one shadow-map texel covers along its worst direction (Lloyd et
/// al. 2006; the directional-light form is Apelles eq. 3.17, dp/ds = (z_n/z)(dz/ds) cos(alpha)).
/// > 1: undersampled. Returns +infinity when either mapping is singular or the point is behind.
inline double perspective_aliasing_error(const glm::mat4& light_view_proj, const glm::mat4& camera_view_proj,
                                         const glm::vec3& world_pos, const glm::vec3& normal,
                                         std::uint32_t shadow_map_size, const glm::uvec2& viewport) {
    using namespace psm_detail;
    const double inf = std::numeric_limits<double>::infinity();
    const glm::dmat4 Lm(light_view_proj), Cm(camera_view_proj);
    const glm::dvec3 x(world_pos);
    glm::dvec3 n(normal);
    if (!fin(Lm) || !fin(Cm) || !fin(x) || !fin(n) || !(glm::length(n) > 0.0)) return inf;
    n = glm::normalize(n);
    const glm::dvec3 t1 = glm::normalize(glm::cross(n, perp_axis(n)));
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
    if (!jac(Lm, 0.5 * shadow_map_size, 0.5 * shadow_map_size, A)) return inf;
    if (!jac(Cm, 0.5 * viewport.x, 0.5 * viewport.y, B)) return inf;
    const double det = glm::determinant(A);
    if (!(std::fabs(det) > 0.0) || !fin(det)) return inf;
    const glm::dmat2 J = B * glm::inverse(A);  // pixels per texel
    // largest singular value of a 2x2 matrix
    const double a = J[0][0], b = J[1][0], c = J[0][1], d = J[1][1];
    const double s1 = a * a + b * b + c * c + d * d;
    const double s2 = std::sqrt(std::fmax(0.0, (a * a + b * b - c * c - d * d) * (a * a + b * b - c * c - d * d) +
                                                   4.0 * (a * c + b * d) * (a * c + b * d)));
    const double sv = std::sqrt(std::fmax(0.0, 0.5 * (s1 + s2)));
    return fin(sv) ? sv : inf;
}

/// Samples the receiver volume (nx * ny screen positions x nz log-spaced view depths, points outside
/// the scene bounds skipped) on surfaces facing the light, and reports the aliasing error statistics
/// of light_view_proj for a shadow_map_size^2 map and a viewport of the given size.
inline AliasingStats measure_perspective_aliasing(const WarpInput& in, const glm::mat4& light_view_proj,
                                                  std::uint32_t shadow_map_size, const glm::uvec2& viewport,
                                                  std::uint32_t nx, std::uint32_t ny, std::uint32_t nz) {
    using namespace psm_detail;
    AliasingStats st;
    const Setup s = prepare(in);
    if (s.status != WarpStatus::Ok || nx == 0 || ny == 0 || nz == 0) return st;
    nx = nx > 4096 ? 4096 : nx;
    ny = ny > 4096 ? 4096 : ny;
    nz = nz > 4096 ? 4096 : nz;
    const glm::mat4 cvp = in.camera_proj * in.camera_view;
    double sum = 0.0;
    std::uint64_t under = 0, count = 0;
    for (std::uint32_t k = 0; k < nz; ++k) {
        const double dep = nz == 1 ? s.d0 : s.d0 * std::pow(s.d1 / s.d0, double(k) / double(nz - 1));
        const double t = glm::clamp((dep - s.d0) / (s.d1 - s.d0), 0.0, 1.0);
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
                const glm::dvec3 nrm = toward_light(s, p);
                const double e = perspective_aliasing_error(light_view_proj, cvp, glm::vec3(p), glm::vec3(nrm),
                                                            shadow_map_size, viewport);
                ++count;
                if (e > 1.0) ++under;
                st.max_error = std::fmax(st.max_error, e);
                sum += fin(e) ? e : 0.0;
            }
    }
    st.samples = static_cast<std::uint32_t>(count);
    if (count > 0) {
        st.mean_error = sum / double(count);
        st.undersampled_fraction = double(under) / double(count);
    }
    return st;
}

}  // namespace shadowkit
