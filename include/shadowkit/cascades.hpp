// shadowkit/cascades.hpp - cascaded (parallel-split) shadow maps for directional lights: split
// distances, stable per-cascade fits, cascade selection and the blend band between cascades.
//
// Usage:
//   shadowkit::CascadeInput in;
//   in.camera_view = view; in.camera_proj = proj;        // GLM, right-handed, column-major
//   in.max_distance = 300.0f;                           // shadow distance (required for infinite far)
//   in.light_dir = sun_dir;                             // direction the light travels
//   in.shadow_map_size = 2048;
//   shadowkit::Cascade cascades[4];
//   float splits[5];
//   if (shadowkit::fit_cascades(in, 0.75f, 4, cascades, splits) == shadowkit::CascadeStatus::Ok) {
//       // render cascade i with cascades[i].view_proj into layer i of a depth array texture;
//       // in the shader pick the cascade with glsl/cascades.glsl (splits[1..4] as view depths).
//   }
//
// Based on:
//   Zhang, Sun, Xu & Lun 2006, "Parallel-Split Shadow Maps for Large-scale Virtual Environments"
//     (practical split scheme: C_i = lambda C_log + (1 - lambda) C_uni); Engel 2007 "Cascaded Shadow
//     Maps" (ShaderX5); Valient 2008, "Stable Rendering of Cascaded Shadow Maps" (ShaderX6: bounding
//     sphere, texel snapping); Moschig, "Apelles" thesis, eqs. 2.3-2.5 (logarithmic split).
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

enum class CascadeStatus {
    Ok,
    InvalidInput,   ///< NaN/Inf, near <= 0, far <= near, lambda outside [0,1], count 0 or > 16, ...
    InfiniteFar     ///< the projection's far plane is infinite and max_distance <= 0
};

/// Stable-fit inputs (directional light).
struct CascadeInput {
    glm::mat4 camera_view{1.0f};
    glm::mat4 camera_proj{1.0f};
    ClipDepth camera_depth = ClipDepth::NegativeOneToOne;
    bool camera_reversed_z = false;
    float max_distance = 0.0f;                     ///< [wu] shadow distance; 0: the projection's far plane
    glm::vec3 light_dir{0.0f, -1.0f, 0.0f};        ///< direction the light travels
    std::uint32_t shadow_map_size = 2048;          ///< [Limit: >= 4] texels per side of each cascade
    float radius_quantum = 1.0f / 16.0f;           ///< [wu] [Limit: > 0] sphere radius rounding step
    bool has_caster_bounds = false;                ///< casters: the near plane is pulled back to them
    glm::vec3 caster_min{0.0f};
    glm::vec3 caster_max{0.0f};
    ClipDepth light_depth = ClipDepth::NegativeOneToOne;
    bool light_reversed_z = false;
};

struct Cascade {
    glm::mat4 view_proj{1.0f};       ///< world -> cascade clip space
    float split_near = 0.0f;         ///< view-depth range covered by this cascade
    float split_far = 0.0f;
    glm::vec4 sphere{0.0f};          ///< world bounding sphere of the slice (center, rounded radius)
    float texel_world_size = 0.0f;   ///< world size of one shadow-map texel
};

namespace csm_detail {

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
inline bool fin(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

/// Camera rays of the four frustum edges in view space: point at the near plane, direction, depths.
struct Rays {
    glm::dvec3 pn[4], dir[4];
    double dn[4] = {0, 0, 0, 0};
    double near_depth = 0.0, far_depth = 0.0;  ///< far_depth may be +inf
};

inline CascadeStatus camera_rays(const glm::mat4& proj, ClipDepth cd, bool reversed, Rays& r) {
    const glm::dmat4 P(proj);
    if (!fin(P)) return CascadeStatus::InvalidInput;
    const double det = glm::determinant(P);
    if (!std::isfinite(det) || std::fabs(det) < 1e-300) return CascadeStatus::InvalidInput;
    const glm::dmat4 ip = glm::inverse(P);
    if (!fin(ip)) return CascadeStatus::InvalidInput;
    const double lo = cd == ClipDepth::ZeroToOne ? 0.0 : -1.0;
    const double zn = reversed ? 1.0 : lo, zf = reversed ? lo : 1.0;
    r.near_depth = -1e300;
    r.far_depth = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 4; ++i) {
        const double x = (i & 1) ? 1.0 : -1.0, y = (i & 2) ? 1.0 : -1.0;
        const glm::dvec4 hn = ip * glm::dvec4(x, y, zn, 1.0), hf = ip * glm::dvec4(x, y, zf, 1.0);
        const double sn = std::fabs(hn.x) + std::fabs(hn.y) + std::fabs(hn.z);
        if (!(std::fabs(hn.w) > 1e-12 * sn) || std::fabs(hn.w) < 1e-300) return CascadeStatus::InvalidInput;
        r.pn[i] = glm::dvec3(hn) / hn.w;
        const double sf = std::fabs(hf.x) + std::fabs(hf.y) + std::fabs(hf.z);
        if (std::fabs(hf.w) > 1e-9 * sf && std::fabs(hf.w) > 1e-300) {
            const glm::dvec3 pf = glm::dvec3(hf) / hf.w;
            r.dir[i] = pf - r.pn[i];
            r.far_depth = std::fmin(r.far_depth, -pf.z);
        } else {
            r.dir[i] = glm::dvec3(hf);
            if (r.dir[i].z > 0.0) r.dir[i] = -r.dir[i];
        }
        r.dn[i] = -r.pn[i].z;
        if (!(r.dir[i].z < 0.0) || !std::isfinite(r.dn[i])) return CascadeStatus::InvalidInput;
        r.near_depth = std::fmax(r.near_depth, r.dn[i]);
    }
    return CascadeStatus::Ok;
}

inline glm::dvec3 corner(const Rays& r, int i, double depth) {
    return r.pn[i] + ((depth - r.dn[i]) / -r.dir[i].z) * r.dir[i];
}

inline glm::dvec3 perp_axis(const glm::dvec3& d) {
    const glm::dvec3 a = glm::abs(d);
    if (a.y <= a.x && a.y <= a.z) return glm::dvec3(0, 1, 0);
    if (a.z <= a.x) return glm::dvec3(0, 0, 1);
    return glm::dvec3(1, 0, 0);
}

}  // namespace csm_detail

/// Practical split scheme (Zhang et al. 2006): C_i = lambda * n (f/n)^(i/m) + (1 - lambda) * (n + (f - n) i/m)
/// for i = 0..count; writes count + 1 distances; out[0] == near and out[count] == far exactly.
/// lambda = 1: logarithmic (Apelles eq. 2.4), lambda = 0: uniform.
inline CascadeStatus cascade_split_distances(float near_plane, float far_plane, float lambda, std::uint32_t count,
                                             float* out) {
    if (!out || count == 0 || count > 16 || !std::isfinite(near_plane) || !std::isfinite(lambda) ||
        !(near_plane > 0.0f) || !(lambda >= 0.0f) || !(lambda <= 1.0f))
        return CascadeStatus::InvalidInput;
    if (std::isinf(far_plane) && far_plane > 0.0f) return CascadeStatus::InfiniteFar;
    if (!std::isfinite(far_plane) || !(far_plane > near_plane)) return CascadeStatus::InvalidInput;
    const double n = near_plane, f = far_plane, l = lambda;
    out[0] = near_plane;
    float prev = near_plane;
    for (std::uint32_t i = 1; i < count; ++i) {
        const double s = double(i) / double(count);
        const double c = l * n * std::pow(f / n, s) + (1.0 - l) * (n + (f - n) * s);
        float v = static_cast<float>(c);
        if (!(v > prev)) v = std::nextafter(prev, far_plane);  // strictly increasing even for tiny ranges
        out[i] = v;
        prev = v;
    }
    if (!(prev < far_plane)) return CascadeStatus::InvalidInput;  // fewer representable floats than splits
    out[count] = far_plane;
    return CascadeStatus::Ok;
}

/// Stable fit of one cascade covering view depths [split_near, split_far]: bounding sphere of the
/// slice (computed in view space, so bitwise invariant to camera rotation and translation), radius
/// rounded up to radius_quantum, the projected world origin snapped to whole texels (one texel of
/// border), near plane pulled back to the caster bounds.
inline CascadeStatus fit_cascade(const CascadeInput& in, float split_near, float split_far, Cascade& out) {
    using namespace csm_detail;
    out = Cascade{};
    if (!fin(in.camera_view) || !fin(in.light_dir) || !std::isfinite(split_near) || !std::isfinite(split_far) ||
        !(split_far > split_near) || in.shadow_map_size < 4 || !std::isfinite(in.radius_quantum) ||
        !(in.radius_quantum > 0.0f))
        return CascadeStatus::InvalidInput;
    if (in.has_caster_bounds && (!fin(in.caster_min) || !fin(in.caster_max))) return CascadeStatus::InvalidInput;
    const glm::dvec3 ld(in.light_dir);
    if (!(glm::length(ld) > 0.0)) return CascadeStatus::InvalidInput;
    const glm::dvec3 d = glm::normalize(ld);
    Rays r;
    const CascadeStatus st = camera_rays(in.camera_proj, in.camera_depth, in.camera_reversed_z, r);
    if (st != CascadeStatus::Ok) return st;
    const double d0 = std::fmax(double(split_near), r.near_depth);
    const double d1 = std::fmin(double(split_far), r.far_depth);
    if (!(d1 > d0)) return CascadeStatus::InvalidInput;
    glm::dvec3 cv[8];
    for (int i = 0; i < 4; ++i) {
        cv[i] = corner(r, i, d0);
        cv[i + 4] = corner(r, i, d1);
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
    if (!(rad > 0.0) || !std::isfinite(rad)) return CascadeStatus::InvalidInput;
    const glm::dmat4 V(in.camera_view);
    const double vdet = glm::determinant(V);
    if (!std::isfinite(vdet) || std::fabs(vdet) < 1e-300) return CascadeStatus::InvalidInput;
    const glm::dvec3 cw = glm::dvec3(glm::inverse(V) * glm::dvec4(cview, 1.0));
    // light view anchored at the world origin: rotation only, fixed per light direction
    const glm::dvec3 up = perp_axis(d);
    const glm::dvec3 sx = glm::normalize(glm::cross(d, up));
    const glm::dvec3 sy = glm::cross(sx, d);
    glm::dmat4 lv(1.0);
    lv[0][0] = sx.x; lv[1][0] = sx.y; lv[2][0] = sx.z;
    lv[0][1] = sy.x; lv[1][1] = sy.y; lv[2][1] = sy.z;
    lv[0][2] = -d.x; lv[1][2] = -d.y; lv[2][2] = -d.z;
    const glm::dvec3 cl = glm::dvec3(lv * glm::dvec4(cw, 1.0));
    const double S = double(in.shadow_map_size);
    const double texel = 2.0 * rad / (S - 2.0);
    const double half = rad + texel;
    const double cx = std::floor(cl.x / texel) * texel, cy = std::floor(cl.y / texel) * texel;  // snap
    double nearp = -cl.z - rad, farp = -cl.z + rad;
    if (in.has_caster_bounds) {
        const glm::dvec3 mn(in.caster_min), mx(in.caster_max);
        for (int c = 0; c < 8; ++c) {
            const glm::dvec3 p((c & 1) ? mx.x : mn.x, (c & 2) ? mx.y : mn.y, (c & 4) ? mx.z : mn.z);
            nearp = std::fmin(nearp, -(lv * glm::dvec4(p, 1.0)).z);
        }
    }
    const double pad = 1e-6 * std::fmax(1.0, std::fabs(nearp) + std::fabs(farp));
    nearp -= pad;
    farp += pad;
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
    if (!fin(m)) return CascadeStatus::InvalidInput;
    out.view_proj = glm::mat4(m);
    if (!fin(out.view_proj)) {
        out = Cascade{};
        return CascadeStatus::InvalidInput;
    }
    if (!(static_cast<float>(texel) > 0.0f) || !std::isfinite(static_cast<float>(rad)) || !fin(glm::vec3(cw))) {
        out = Cascade{};
        return CascadeStatus::InvalidInput;  // outside float range
    }
    out.split_near = split_near;
    out.split_far = split_far;
    out.sphere = glm::vec4(glm::vec3(cw), static_cast<float>(rad));
    out.texel_world_size = static_cast<float>(texel);
    return CascadeStatus::Ok;
}

/// Splits the camera range [near, min(far, max_distance)] with the practical scheme and fits every
/// cascade. out_cascades: count entries; out_splits (optional): count + 1 distances.
inline CascadeStatus fit_cascades(const CascadeInput& in, float lambda, std::uint32_t count, Cascade* out_cascades,
                                  float* out_splits) {
    using namespace csm_detail;
    if (!out_cascades || count == 0 || count > 16 || !std::isfinite(in.max_distance)) return CascadeStatus::InvalidInput;
    Rays r;
    const CascadeStatus st = camera_rays(in.camera_proj, in.camera_depth, in.camera_reversed_z, r);
    if (st != CascadeStatus::Ok) return st;
    double f = r.far_depth;
    if (in.max_distance > 0.0f) f = std::fmin(f, double(in.max_distance));
    else if (std::isinf(f)) return CascadeStatus::InfiniteFar;
    float splits[17];
    const CascadeStatus ss = cascade_split_distances(static_cast<float>(r.near_depth), static_cast<float>(f), lambda, count, splits);
    if (ss != CascadeStatus::Ok) return ss;
    for (std::uint32_t i = 0; i < count; ++i) {
        const CascadeStatus cs = fit_cascade(in, splits[i], splits[i + 1], out_cascades[i]);
        if (cs != CascadeStatus::Ok) return cs;
    }
    if (out_splits)
        for (std::uint32_t i = 0; i <= count; ++i) out_splits[i] = splits[i];
    return CascadeStatus::Ok;
}

/// Cascade covering a view depth: the first i with depth <= splits[i + 1] (splits: count + 1 values
/// from cascade_split_distances). -1 if before splits[0], beyond splits[count], or NaN.
inline int select_cascade_by_depth(float view_depth, const float* splits, std::uint32_t count) {
    if (!splits || count == 0 || !(view_depth >= splits[0])) return -1;
    for (std::uint32_t i = 0; i < count; ++i)
        if (view_depth <= splits[i + 1]) return static_cast<int>(i);
    return -1;
}

/// First cascade whose bounding sphere contains the world point (tighter at rotation than depth
/// selection: uses the whole sphere the stable fit covers). -1 if none.
inline int select_cascade_by_sphere(const glm::vec3& world_pos, const Cascade* cascades, std::uint32_t count) {
    if (!cascades || !csm_detail::fin(world_pos)) return -1;
    for (std::uint32_t i = 0; i < count; ++i) {
        const glm::vec3 d = world_pos - glm::vec3(cascades[i].sphere);
        if (glm::dot(d, d) <= cascades[i].sphere.w * cascades[i].sphere.w) return static_cast<int>(i);
    }
    return -1;
}

/// Weight of the next cascade in the blend band: 0 until the last band_fraction of [split_near,
/// split_far], rising linearly to 1 at split_far. band_fraction in [0,1]; NaN input gives 0.
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
