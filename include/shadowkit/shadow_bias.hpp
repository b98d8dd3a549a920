// shadowkit/shadow_bias.hpp - shadow-map depth bias (slope-scaled, polygon offset, normal offset, receiver plane, second depth) and depth precision
//
// Usage:
//   #include <shadowkit/shadow_bias.hpp>
//   namespace sk = shadowkit;
//   sk::BiasValue t = sk::bias_texel_world_size_perspective(dist, fov_y, 2048.0f);  // one texel [world]
//   sk::BiasTanAngle a = sk::bias_light_tan_angle(normal, to_light);                 // tan(angle(normal, light))
//   if (t.status == sk::Status::Ok && a.status == sk::Status::Ok && a.faces_light) {
//       sk::BiasValue b = sk::bias_slope_scaled(t.value, a.value);                  // depth bias [world]
//       sk::BiasPosition q = sk::bias_normal_offset_position(p, normal, to_light, t.value, 0.75f);  // or offset the lookup
//   }
//   sk::BiasReceiverPlane g = sk::bias_receiver_plane_depth_gradient(dFdx_uvz, dFdy_uvz);  // per pixel
//   sk::BiasDepthValue step = sk::bias_depth_metric_resolution(sk::BiasDepthMetric::PostProjective,
//                                                              sk::DepthFormat::Fixed24, 40.0, 0.1, 100.0);
//   // The automatic bias (no constant to tune; glsl/shadow_map.glsl sk_shadow_map_visibility_auto):
//   sk::BiasAutoLookup a = sk::bias_auto_lookup(light_view_proj, sk::ClipDepth::NegativeOneToOne, false,
//                                               world_pos, world_normal, glm::ivec2(2048), sk::DepthFormat::Float32);
//   float lit = sk::bias_auto_visibility(a, stored_depth_at_the_four_taps, false, 1.0f);
//
// Conventions. Units: "world" values are distances in the light's depth metric (eye distance along
// the light's axis, or distance to the light); "window" values are stored depth in [0, 1]
// (glDepthRange(0, 1)); uv offsets are in shadow-map uv [0, 1].
// Lights: a light is its homogeneous position `light_position` = (x, y, z, w), as OpenGL's
// GL_POSITION and Everitt & Kilgard use it. w > 0: a point or spot light at xyz / w. w = 0: a
// directional light at infinity in direction xyz, the direction *toward* the light (its rays travel
// along -xyz). w < 0, (0, 0, 0, 0) and NaN/Inf are rejected with Status::InvalidLight.
// This header takes no light itself: `to_light` is the direction from the receiver p toward the
// light, light_position.xyz / w - p (w > 0) or light_position.xyz (w = 0); its length is free.
// Normals need not be unit length. Results: a struct whose first member is `status`; `Ok`
// only with finite outputs in their documented range; outcomes (a surface facing away, an edge-on
// plane, a singular receiver Jacobian) are fields with Ok. Functions marked "total:" take any
// input. No buffers, no allocation. A non-Ok result's `detail` names the offending input and the rule
// ("fov: outside (0, pi)"), a static string; nullptr when Ok.
//
// Based on:
//   L. Williams, "Casting curved shadows on curved surfaces", SIGGRAPH 1978.
//   Y. Wang, S. Molnar, "Second-Depth Shadow Mapping", UNC TR94-019, 1994 (midpoint depth).
//   OpenGL 4.6 core spec, Sec. 14.6.5 "Depth Offset" (o = m * factor + r * units).
//   J. Isidoro, "Shadow Mapping: GPU-based Tips and Techniques", GDC 2006 (receiver plane depth bias).
//   D. Holbert, "Saying Goodbye to Shadow Acne", GDC 2011 poster (normal offset).
//   A. Moschig, "Apelles: A Library for GPU-Based Real-Time Global Illumination", master's thesis, TU Graz (2012): distance to the light as a linear depth metric.
//   H. Dou, Y. Yan, E. Kerzner, Z. Dai, C. Wyman, "Adaptive Depth Bias for Shadow Maps", JCGT 3(4), 2014
//     (the bias from the receiver's tangent plane at the texel's sample, plus a precision term).
//
// MIT License. Copyright (c) shadowkit contributors.
#pragma once

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cmath>
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
#ifndef SHADOWKIT_DEPTH_FORMAT_DEFINED
#define SHADOWKIT_DEPTH_FORMAT_DEFINED
/// Depth-buffer storage format.
enum class DepthFormat { Float32, Fixed24, Fixed16 };
#endif
/// What the shadow map stores as depth.
enum class BiasDepthMetric {
    PostProjective,          ///< window depth of a perspective light, 0 at near, 1 at far (far may be +inf)
    PostProjectiveReversed,  ///< reversed-Z: 1 at near, 0 at far (far may be +inf)
    LinearNormalized,        ///< (d - near) / (far - near): orthographic lights, or linear depth written by the shader
    LinearDistance           ///< d itself (e.g. distance to the light in an R32F target); Float32 only
};

/// A scalar result in world or uv units. `value` is 0 unless status is Ok.
struct BiasValue {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    float value = 0.0f;
};

/// A depth-precision result (steps, slopes, offsets: double keeps 2^-24 steps exact). 0 unless Ok.
struct BiasDepthValue {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    double value = 0.0;
};

/// tan of the angle between a surface normal and the direction to the light.
struct BiasTanAngle {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    bool faces_light = false;  ///< false (with Ok): the surface faces away from the light or contains its direction; value 0
    float value = 0.0f;        ///< tan(theta) >= 0 when faces_light
};

/// Depth gradient of a plane in a light's image plane.
struct BiasDepthGradient {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    bool edge_on = false;   ///< true (with Ok): the plane (nearly) contains the light direction, the gradient is beyond float; dz_duv 0
    glm::vec2 dz_duv{0.0f}; ///< (dz/du, dz/dv), depth units per world unit on the light's image plane
};

/// Receiver-plane depth gradient from screen-space derivatives.
struct BiasReceiverPlane {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    bool singular = false;  ///< true (with Ok): the uv Jacobian is singular (seen edge-on); dz_duv 0: fall back to slope-scaled bias
    glm::vec2 dz_duv{0.0f}; ///< (dz/du, dz/dv) in window depth per uv
};

/// An offset lookup position.
struct BiasPosition {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    glm::vec3 position{0.0f};
};

namespace detail {
inline bool bias_fits_float(double v) {
    return std::isfinite(v) && std::fabs(v) <= static_cast<double>(std::numeric_limits<float>::max());
}
inline bool bias_finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
inline bool bias_finite(glm::vec2 v) { return std::isfinite(v.x) && std::isfinite(v.y); }
inline bool bias_valid_format(DepthFormat f) {
    return f == DepthFormat::Float32 || f == DepthFormat::Fixed24 || f == DepthFormat::Fixed16;
}
inline BiasValue bias_float(double v) {
    BiasValue r;
    if (!bias_fits_float(v)) { r.status = Status::Overflow; r.detail = "result: beyond float range"; return r; }
    r.value = static_cast<float>(v);
    r.status = Status::Ok;
    return r;
}
inline BiasDepthValue bias_double(double v) {
    BiasDepthValue r;
    if (!bias_fits_float(v)) { r.status = Status::Overflow; r.detail = "result: beyond float range"; return r; }
    r.value = v;
    r.status = Status::Ok;
    return r;
}
// The metric's domain: n finite > 0, f > n (+inf allowed except LinearNormalized), d finite > 0.
// `detail` receives where a non-Ok status came from (a static string).
inline Status bias_check_metric(BiasDepthMetric m, double d, double n, double f, const char*& detail) {
    if (std::isnan(d) || std::isnan(n) || std::isnan(f) || std::isinf(d) || std::isinf(n) ||
        f == -std::numeric_limits<double>::infinity()) {
        detail = std::isnan(d) || std::isinf(d) ? "d: NaN or Inf" : (std::isnan(n) || std::isinf(n) ? "n: NaN or Inf" : "f: NaN or -Inf");
        return Status::NonFinite;
    }
    if (!(n > 0.0) || !(f > n) || !(d > 0.0)) {
        detail = !(n > 0.0) ? "n: not > 0" : (!(f > n) ? "f: not > n" : "d: not > 0");
        return Status::InvalidArgument;
    }
    switch (m) {
    case BiasDepthMetric::PostProjective:
    case BiasDepthMetric::PostProjectiveReversed:
    case BiasDepthMetric::LinearDistance: return Status::Ok;
    case BiasDepthMetric::LinearNormalized:
        if (!std::isinf(f)) return Status::Ok;
        detail = "f: +inf with LinearNormalized";
        return Status::InvalidArgument;
    }
    detail = "m: unknown BiasDepthMetric";
    return Status::InvalidArgument;
}
inline double bias_metric_value(BiasDepthMetric m, double d, double n, double f) {
    switch (m) {
    case BiasDepthMetric::PostProjective: return std::isinf(f) ? 1.0 - n / d : f * (d - n) / (d * (f - n));
    case BiasDepthMetric::PostProjectiveReversed: return std::isinf(f) ? n / d : n * (f - d) / (d * (f - n));
    case BiasDepthMetric::LinearNormalized: return (d - n) / (f - n);
    case BiasDepthMetric::LinearDistance: return d;
    }
    return 0.0;
}
inline double bias_metric_slope(BiasDepthMetric m, double d, double n, double f) {
    switch (m) {
    case BiasDepthMetric::PostProjective:
    case BiasDepthMetric::PostProjectiveReversed:
        return std::isinf(f) ? n / d / d : f * n / d / d / (f - n);
    case BiasDepthMetric::LinearNormalized: return 1.0 / (f - n);
    case BiasDepthMetric::LinearDistance: return 1.0;
    }
    return 0.0;
}
inline double bias_format_step(DepthFormat f, double v) {
    if (f == DepthFormat::Fixed24) return 1.0 / 16777215.0;
    if (f == DepthFormat::Fixed16) return 1.0 / 65535.0;
    const float x = static_cast<float>(std::fabs(v));
    return static_cast<double>(std::nextafter(x, std::numeric_limits<float>::infinity())) - static_cast<double>(x);
}
} // namespace detail

// ------------------------------------------------------------------------------------------------
// Depth formats
// ------------------------------------------------------------------------------------------------

/// Bits of a fixed-point format. total: 24 (Fixed24), 16 (Fixed16), 0 for Float32 and any other value.
inline int bias_depth_format_bits(DepthFormat f) {
    return f == DepthFormat::Fixed24 ? 24 : (f == DepthFormat::Fixed16 ? 16 : 0);
}

/// The value the format stores for v: UNORM n clamps to [0, 1] and rounds to k / (2^n - 1);
/// Float32 rounds to float. NonFinite for NaN/Inf v, InvalidArgument for an unknown format,
/// Overflow for |v| beyond float (Float32).
inline BiasDepthValue bias_quantize_depth(DepthFormat f, double v) {
    BiasDepthValue r;
    if (!std::isfinite(v)) { r.status = Status::NonFinite; r.detail = "v: NaN or Inf"; return r; }
    if (!detail::bias_valid_format(f)) { r.status = Status::InvalidArgument; r.detail = "f: unknown DepthFormat"; return r; }
    const int bits = bias_depth_format_bits(f);
    if (bits == 0) return detail::bias_double(static_cast<double>(static_cast<float>(v)));
    const double scale = std::ldexp(1.0, bits) - 1.0;
    const double c = v < 0.0 ? 0.0 : (v > 1.0 ? 1.0 : v);
    return detail::bias_double(std::round(c * scale) / scale);
}

/// Spacing between the stored value nearest to v and the next one above it: 1 / (2^n - 1) for
/// UNORM n, the float32 ulp of |v| for Float32 (the smallest subnormal at 0). Ok: value > 0.
/// NonFinite for NaN/Inf v, InvalidArgument for an unknown format, Overflow at |v| >= FLT_MAX.
inline BiasDepthValue bias_depth_format_step(DepthFormat f, double v) {
    BiasDepthValue r;
    if (!std::isfinite(v)) { r.status = Status::NonFinite; r.detail = "v: NaN or Inf"; return r; }
    if (!detail::bias_valid_format(f)) { r.status = Status::InvalidArgument; r.detail = "f: unknown DepthFormat"; return r; }
    return detail::bias_double(detail::bias_format_step(f, v));
}

// ------------------------------------------------------------------------------------------------
// Depth metric and precision
// ------------------------------------------------------------------------------------------------

/// Stored value of the metric at eye distance d (along the light's axis for PostProjective*).
/// PostProjective: z_w = f (d - n) / (d (f - n)), = 1 - n/d for f = +inf (GL [-1,1] and [0,1] clip
/// depth give the same window depth with glDepthRange(0,1)). PostProjectiveReversed: z_w =
/// n (f - d) / (d (f - n)), = n / d for f = +inf. Domain: n finite > 0, f > n (+inf allowed except
/// LinearNormalized), d finite > 0 (d outside [n, f] gives values outside [0, 1]). NonFinite for
/// NaN/Inf (other than f = +inf), InvalidArgument outside the domain or for an unknown metric,
/// Overflow beyond float range.
inline BiasDepthValue bias_depth_metric_value(BiasDepthMetric m, double d, double n, double f) {
    BiasDepthValue r;
    r.status = detail::bias_check_metric(m, d, n, f, r.detail);
    if (r.status != Status::Ok) return r;
    return detail::bias_double(detail::bias_metric_value(m, d, n, f));
}

/// |d value / d distance| of the metric at distance d: PostProjective(Reversed) f n / (d^2 (f - n))
/// (n / d^2 for f = +inf); LinearNormalized 1 / (f - n); LinearDistance 1. Domain and statuses as
/// bias_depth_metric_value; Overflow also when the slope underflows to 0.
inline BiasDepthValue bias_depth_metric_slope(BiasDepthMetric m, double d, double n, double f) {
    BiasDepthValue r;
    r.status = detail::bias_check_metric(m, d, n, f, r.detail);
    if (r.status != Status::Ok) return r;
    const double s = detail::bias_metric_slope(m, d, n, f);
    if (!(s > 0.0)) { r.status = Status::Overflow; r.detail = "d: slope underflows to 0"; return r; }
    return detail::bias_double(s);
}

/// Bias units. Every bias parameter of the kit's headers and snippets names its unit: `_window`
/// (the window depth a map stores: the PostProjective metrics, or LinearNormalized for an
/// orthographic light: shadow_map.glsl, cascades.glsl, perspective_shadow_maps.glsl, linear_light.glsl,
/// silhouette_map.glsl), `_world` (world units along the light ray: omni_shadow.glsl, normal offset),
/// `_stored` (omni's distance / range), `_linear` (light-view distance: smoothie.glsl, pcss's blocker
/// depths), `moment_bias` (MSM's moment mix; the pre-filtered maps' receiver bias is in their depth t,
/// LinearNormalized over the light's range). This converts a world-unit bias at distance d from the
/// light into metric m's units: bias_world times the metric's slope at d (first order; bias_depth_metric_slope).
/// Statuses as bias_depth_metric_slope; InvalidArgument for a negative or NaN bias_world.
inline BiasDepthValue bias_window_from_world(double bias_world, BiasDepthMetric m, double d, double n, double f) {
    BiasDepthValue r;
    if (!(bias_world >= 0.0) || std::isinf(bias_world)) {
        r.status = std::isnan(bias_world) || std::isinf(bias_world) ? Status::NonFinite : Status::InvalidArgument;
        r.detail = r.status == Status::NonFinite ? "bias_world: NaN or Inf" : "bias_world: < 0";
        return r;
    }
    const BiasDepthValue s = bias_depth_metric_slope(m, d, n, f);
    if (s.status != Status::Ok) {
        r.status = s.status;
        r.detail = s.detail;
        return r;
    }
    return detail::bias_double(bias_world * s.value);
}

/// The inverse: a bias in metric m's units (window depth, t, or distance) at distance d, in world
/// units along the light ray: bias / the metric's slope at d. Statuses as bias_window_from_world.
inline BiasDepthValue bias_world_from_window(double bias_window, BiasDepthMetric m, double d, double n, double f) {
    BiasDepthValue r;
    if (!(bias_window >= 0.0) || std::isinf(bias_window)) {
        r.status = std::isnan(bias_window) || std::isinf(bias_window) ? Status::NonFinite : Status::InvalidArgument;
        r.detail = r.status == Status::NonFinite ? "bias_window: NaN or Inf" : "bias_window: < 0";
        return r;
    }
    const BiasDepthValue s = bias_depth_metric_slope(m, d, n, f);
    if (s.status != Status::Ok) {
        r.status = s.status;
        r.detail = s.detail;
        return r;
    }
    return detail::bias_double(bias_window / s.value);
}

/// World-space depth resolution at distance d: the distance between adjacent stored values,
/// step(format, value(d)) / slope(d) (first order). This is the smallest useful constant bias.
/// - PostProjective, UNORM n: d^2 (f - n) / (f n (2^n - 1)): grows with d^2, so far receivers need
///   a much larger constant bias than near ones (acne far away, peter-panning near).
/// - PostProjective, Float32: values crowd near 1, ulp(1) = 6e-8 is no better than 24-bit UNORM.
/// - PostProjectiveReversed, Float32: z_w ~ n/d and ulp(z_w) ~ z_w 2^-23, so dd ~ d 2^-23: a
///   relative precision of 2^-24..2^-23 at every distance (even with f = +inf), the best choice.
/// - LinearNormalized, UNORM n: uniform (f - n) / (2^n - 1).  LinearDistance (float32): ulp(d).
/// Ok: value finite, > 0. Domain as bias_depth_metric_value plus d in [n, f]; InvalidArgument also
/// for LinearDistance with a UNORM format or an unknown format; Overflow beyond float range.
inline BiasDepthValue bias_depth_metric_resolution(BiasDepthMetric m, DepthFormat fmt, double d, double n, double f) {
    BiasDepthValue r;
    r.status = detail::bias_check_metric(m, d, n, f, r.detail);
    if (r.status != Status::Ok) return r;
    if (!(d >= n && d <= f) || !detail::bias_valid_format(fmt) ||
        (m == BiasDepthMetric::LinearDistance && fmt != DepthFormat::Float32)) {
        r.status = Status::InvalidArgument;
        r.detail = !(d >= n && d <= f) ? "d: outside [n, f]"
                   : (!detail::bias_valid_format(fmt) ? "fmt: unknown DepthFormat" : "fmt: UNORM with LinearDistance");
        return r;
    }
    const double slope = detail::bias_metric_slope(m, d, n, f);
    const double v = detail::bias_format_step(fmt, detail::bias_metric_value(m, d, n, f)) / slope;
    if (!(slope > 0.0) || !(v > 0.0)) { r.status = Status::Overflow; r.detail = "d: slope or step underflows to 0"; return r; }
    return detail::bias_double(v);
}

/// World-space size of one shadow-map texel at eye distance d along a perspective light's axis:
/// 2 d tan(fov/2) / resolution. (Off axis the texel footprint on a plane facing the light grows by
/// 1/cos^2 of the off-axis angle; use the orthographic version with the local width if needed.)
/// d finite >= 0, fov the full angle in radians in (0, pi), resolution (texels across the map)
/// finite > 0. NonFinite for NaN/Inf, InvalidArgument outside those ranges (fov = float(pi) is
/// above pi), Overflow beyond float range.
inline BiasValue bias_texel_world_size_perspective(float d, float fov, float resolution) {
    BiasValue r;
    if (!std::isfinite(d) || !std::isfinite(fov) || !std::isfinite(resolution)) {
        r.status = Status::NonFinite;
        r.detail = !std::isfinite(d) ? "d: NaN or Inf" : (!std::isfinite(fov) ? "fov: NaN or Inf" : "resolution: NaN or Inf");
        return r;
    }
    if (!(d >= 0.0f) || !(fov > 0.0f && static_cast<double>(fov) < 3.14159265358979323846) || !(resolution > 0.0f)) {
        r.status = Status::InvalidArgument;
        r.detail = !(d >= 0.0f) ? "d: < 0" : (!(resolution > 0.0f) ? "resolution: not > 0" : "fov: outside (0, pi)");
        return r;
    }
    return detail::bias_float(2.0 * static_cast<double>(d) * std::tan(0.5 * static_cast<double>(fov)) /
                              static_cast<double>(resolution));
}

/// World-space size of one texel of an orthographic light of width `width` (finite >= 0):
/// width / resolution (finite > 0). Statuses as bias_texel_world_size_perspective.
inline BiasValue bias_texel_world_size_ortho(float width, float resolution) {
    BiasValue r;
    if (!std::isfinite(width) || !std::isfinite(resolution)) {
        r.status = Status::NonFinite;
        r.detail = !std::isfinite(width) ? "width: NaN or Inf" : "resolution: NaN or Inf";
        return r;
    }
    if (!(width >= 0.0f) || !(resolution > 0.0f)) {
        r.status = Status::InvalidArgument;
        r.detail = !(width >= 0.0f) ? "width: < 0" : "resolution: not > 0";
        return r;
    }
    return detail::bias_float(static_cast<double>(width) / static_cast<double>(resolution));
}

// ------------------------------------------------------------------------------------------------
// Constant bias and the comparison
// ------------------------------------------------------------------------------------------------

/// The shadow test with a constant bias: lit when receiver - bias <= stored (reversed-Z:
/// receiver + bias >= stored). total: any NaN gives false (shadowed).
/// Fails: a constant bias large enough for grazing surfaces (depth changes by texel * tan(theta)
/// across a texel) pushes shadows away from their casters (peter-panning) and lets thin casters
/// leak light; one small enough to keep contact shadows gives acne on sloped surfaces. It must at
/// least cover bias_depth_metric_resolution() at the receiver's distance.
inline bool bias_shadow_test_lit(float receiver, float stored, float bias, bool reversed_z) {
    return reversed_z ? receiver + bias >= stored : receiver - bias <= stored;
}

// ------------------------------------------------------------------------------------------------
// Slope-scaled bias
// ------------------------------------------------------------------------------------------------

/// tan of the angle theta between the surface normal and the direction to the light:
/// |n x l| / (n . l), computed in double (any finite scale, 1e-45 to 3e38 components).
/// faces_light = false (with Ok, value 0) when n . l <= 0: the surface faces away or contains the
/// light direction (N.L = 0 there: no bias helps, shade it dark). NonFinite for NaN/Inf components,
/// InvalidArgument for a zero vector, Overflow when tan exceeds FLT_MAX (n . l < ~3e-39 |n| |l|).
inline BiasTanAngle bias_light_tan_angle(glm::vec3 normal, glm::vec3 to_light) {
    BiasTanAngle r;
    if (!detail::bias_finite(normal) || !detail::bias_finite(to_light)) {
        r.status = Status::NonFinite;
        r.detail = !detail::bias_finite(normal) ? "normal: NaN or Inf" : "to_light: NaN or Inf";
        return r;
    }
    const glm::dvec3 n(normal), l(to_light);
    if (glm::dot(n, n) == 0.0 || glm::dot(l, l) == 0.0) {
        r.status = Status::InvalidArgument;
        r.detail = glm::dot(n, n) == 0.0 ? "normal: zero" : "to_light: zero";
        return r;
    }
    // Scale both to a max component of 1 first: squares of 3e38 or 1e-45 stay normal in double.
    const glm::dvec3 nn = n / std::fmax(std::fabs(n.x), std::fmax(std::fabs(n.y), std::fabs(n.z)));
    const glm::dvec3 ll = l / std::fmax(std::fabs(l.x), std::fmax(std::fabs(l.y), std::fabs(l.z)));
    const double c = glm::dot(nn, ll);
    r.status = Status::Ok;
    if (!(c > 0.0)) return r;
    const double t = glm::length(glm::cross(nn, ll)) / c;
    if (!detail::bias_fits_float(t)) { r.status = Status::Overflow; r.detail = "result: tan beyond float range"; return r; }
    r.faces_light = true;
    r.value = static_cast<float>(t);
    return r;
}

/// Depth gradient (dz/du, dz/dv) of a plane with normal n seen by an orthographic light with
/// orthonormal basis (right, up, forward = the direction the light's rays travel; depth grows along
/// forward), in depth units per world unit on the light's image plane: -(n.right)/(n.forward),
/// -(n.up)/(n.forward). Its length is tan(theta). edge_on (with Ok) when the plane contains the light
/// direction (n.forward = 0, or a gradient beyond float). NonFinite for NaN/Inf, InvalidArgument for
/// a zero normal or forward.
inline BiasDepthGradient bias_plane_depth_gradient(glm::vec3 normal, glm::vec3 right, glm::vec3 up, glm::vec3 forward) {
    BiasDepthGradient g;
    if (!detail::bias_finite(normal) || !detail::bias_finite(right) || !detail::bias_finite(up) ||
        !detail::bias_finite(forward)) {
        g.status = Status::NonFinite;
        g.detail = !detail::bias_finite(normal) ? "normal: NaN or Inf"
                   : (!detail::bias_finite(right) ? "right: NaN or Inf"
                                                  : (!detail::bias_finite(up) ? "up: NaN or Inf" : "forward: NaN or Inf"));
        return g;
    }
    const glm::dvec3 n(normal), f(forward);
    if (glm::dot(n, n) == 0.0 || glm::dot(f, f) == 0.0) {
        g.status = Status::InvalidArgument;
        g.detail = glm::dot(n, n) == 0.0 ? "normal: zero" : "forward: zero";
        return g;
    }
    g.status = Status::Ok;
    const double nf = glm::dot(n, f);
    const double gu = -glm::dot(n, glm::dvec3(right)) / nf, gv = -glm::dot(n, glm::dvec3(up)) / nf;
    if (nf == 0.0 || !detail::bias_fits_float(gu) || !detail::bias_fits_float(gv)) {
        g.edge_on = true;
        return g;
    }
    g.dz_duv = glm::vec2(static_cast<float>(gu), static_cast<float>(gv));
    return g;
}

/// Exact largest depth difference between a texel's center and any point of that texel on a plane
/// with depth gradient g: texel/2 * (|g.x| + |g.y|) (the maximum of a linear function on a square is
/// at a corner). This is what a bias must cover to avoid acne with nearest (1-tap) lookups.
/// texel_world finite >= 0. NonFinite for NaN/Inf, InvalidArgument for texel_world < 0, Overflow.
inline BiasValue bias_texel_depth_delta(glm::vec2 dz_duv, float texel_world) {
    BiasValue r;
    if (!detail::bias_finite(dz_duv) || !std::isfinite(texel_world)) {
        r.status = Status::NonFinite;
        r.detail = !detail::bias_finite(dz_duv) ? "dz_duv: NaN or Inf" : "texel_world: NaN or Inf";
        return r;
    }
    if (!(texel_world >= 0.0f)) { r.status = Status::InvalidArgument; r.detail = "texel_world: < 0"; return r; }
    return detail::bias_float(0.5 * static_cast<double>(texel_world) *
                              (std::fabs(static_cast<double>(dz_duv.x)) + std::fabs(static_cast<double>(dz_duv.y))));
}

/// Slope-scaled bias: constant + slope_scale * texel_world * min(tan(theta), max_tan) [world].
/// With slope_scale >= sqrt(2)/2 it covers bias_texel_depth_delta() for every plane orientation
/// (|g.x| + |g.y| <= sqrt(2) |g|, |g| = tan(theta)); a PCF kernel of radius R texels needs
/// slope_scale >= (R + sqrt(2)/2) because taps compare one receiver depth with distant texels.
/// Inputs: texel_world, slope_scale, constant finite >= 0; tan_theta >= 0 (+inf allowed: clamped);
/// max_tan finite > 0. NonFinite for NaN (or Inf other than tan_theta = +inf), InvalidArgument
/// outside the ranges, Overflow beyond float range.
/// Fails: tan(theta) -> inf at grazing angles, so it must be clamped (max_tan); at the clamp acne
/// returns on surfaces nearly parallel to the light (usually hidden by N.L shading), and large
/// scales push contact shadows away (peter-panning) and leak light under thin casters.
inline BiasValue bias_slope_scaled(float texel_world, float tan_theta, float slope_scale = 0.70710678f,
                                   float constant = 0.0f, float max_tan = 10.0f) {
    BiasValue r;
    if (!std::isfinite(texel_world) || std::isnan(tan_theta) || tan_theta == -std::numeric_limits<float>::infinity() ||
        !std::isfinite(slope_scale) || !std::isfinite(constant) || !std::isfinite(max_tan)) {
        r.status = Status::NonFinite;
        r.detail = !std::isfinite(texel_world) ? "texel_world: NaN or Inf"
                   : (std::isnan(tan_theta) || tan_theta == -std::numeric_limits<float>::infinity() ? "tan_theta: NaN or -Inf"
                   : (!std::isfinite(slope_scale) ? "slope_scale: NaN or Inf"
                   : (!std::isfinite(constant) ? "constant: NaN or Inf" : "max_tan: NaN or Inf")));
        return r;
    }
    if (!(texel_world >= 0.0f) || !(tan_theta >= 0.0f) || !(slope_scale >= 0.0f) || !(constant >= 0.0f) ||
        !(max_tan > 0.0f)) {
        r.status = Status::InvalidArgument;
        r.detail = !(texel_world >= 0.0f) ? "texel_world: < 0"
                   : (!(tan_theta >= 0.0f) ? "tan_theta: < 0"
                   : (!(slope_scale >= 0.0f) ? "slope_scale: < 0" : (!(constant >= 0.0f) ? "constant: < 0" : "max_tan: not > 0")));
        return r;
    }
    const double t = tan_theta > max_tan ? static_cast<double>(max_tan) : static_cast<double>(tan_theta);
    return detail::bias_float(static_cast<double>(constant) +
                              static_cast<double>(slope_scale) * static_cast<double>(texel_world) * t);
}

/// Minimum resolvable difference r of glPolygonOffset / Vulkan depthBiasConstantFactor:
/// UNORM n: 2^-n; Float32: 2^(e - 23) with e the exponent of the largest |z| of the primitive
/// (z = m 2^e, 1 <= m < 2), 2^-149 for z = 0 (the spec leaves it open). NonFinite for NaN/Inf
/// max_window_z, InvalidArgument for an unknown format.
inline BiasDepthValue bias_polygon_offset_r(DepthFormat f, float max_window_z) {
    BiasDepthValue r;
    if (!std::isfinite(max_window_z)) { r.status = Status::NonFinite; r.detail = "max_window_z: NaN or Inf"; return r; }
    if (!detail::bias_valid_format(f)) { r.status = Status::InvalidArgument; r.detail = "f: unknown DepthFormat"; return r; }
    const int bits = bias_depth_format_bits(f);
    r.status = Status::Ok;
    if (bits != 0) { r.value = std::ldexp(1.0, -bits); return r; }
    const float z = std::fabs(max_window_z);
    if (z == 0.0f) { r.value = std::ldexp(1.0, -149); return r; }
    int e = 0;
    (void)std::frexp(z, &e);  // z = m' 2^e with 0.5 <= m' < 1
    r.value = std::ldexp(1.0, (e - 1) - 23);
    return r;
}

/// glPolygonOffset(factor, units) as the rasterizer applies it (GL 4.6 eq. 14.8):
/// o = m * factor + r * units, with m = sqrt(dzdx^2 + dzdy^2) (exact_m) or its allowed
/// approximation max(|dzdx|, |dzdy|), dz/dx, dz/dy the window-depth slope per shadow-map pixel.
/// Equivalence with bias_slope_scaled: for an orthographic light (LinearNormalized) a plane has
/// m_exact = texel_world * tan(theta) / (f - n), so factor = slope_scale reproduces it with exact m;
/// a driver using max() needs factor = slope_scale * sqrt(2) to be safe.
/// NonFinite for NaN/Inf, InvalidArgument for an unknown format, Overflow beyond float range.
inline BiasDepthValue bias_polygon_offset(float factor, float units, float dzdx, float dzdy, DepthFormat f,
                                          float max_window_z, bool exact_m = false) {
    BiasDepthValue r;
    if (!std::isfinite(factor) || !std::isfinite(units) || !std::isfinite(dzdx) || !std::isfinite(dzdy)) {
        r.status = Status::NonFinite;
        r.detail = !std::isfinite(factor) ? "factor: NaN or Inf"
                   : (!std::isfinite(units) ? "units: NaN or Inf" : (!std::isfinite(dzdx) ? "dzdx: NaN or Inf" : "dzdy: NaN or Inf"));
        return r;
    }
    const BiasDepthValue rr = bias_polygon_offset_r(f, max_window_z);
    if (rr.status != Status::Ok) { r.status = rr.status; r.detail = rr.detail; return r; }
    const double ax = std::fabs(static_cast<double>(dzdx)), ay = std::fabs(static_cast<double>(dzdy));
    const double m = exact_m ? std::sqrt(ax * ax + ay * ay) : (ax > ay ? ax : ay);
    return detail::bias_double(m * static_cast<double>(factor) + rr.value * static_cast<double>(units));
}

/// The `units` argument that makes r * units equal a world-space depth bias at distance d for the
/// metric: world_bias * slope(d) / r. Since the post-projective slope falls with 1/d^2, a fixed
/// `units` is a bias that grows with d^2 in world space. world_bias finite; the metric's domain as
/// bias_depth_metric_value; NonFinite / InvalidArgument / Overflow accordingly.
inline BiasDepthValue bias_polygon_offset_units_for_world_bias(double world_bias, BiasDepthMetric m, DepthFormat fmt,
                                                               double d, double n, double f) {
    BiasDepthValue r;
    if (!std::isfinite(world_bias)) { r.status = Status::NonFinite; r.detail = "world_bias: NaN or Inf"; return r; }
    const BiasDepthValue v = bias_depth_metric_value(m, d, n, f);
    if (v.status != Status::Ok) { r.status = v.status; r.detail = v.detail; return r; }
    const BiasDepthValue rr = bias_polygon_offset_r(fmt, static_cast<float>(v.value));
    if (rr.status != Status::Ok) { r.status = rr.status; r.detail = rr.status == Status::InvalidArgument ? "fmt: unknown DepthFormat" : rr.detail; return r; }
    return detail::bias_double(world_bias * detail::bias_metric_slope(m, d, n, f) / rr.value);
}

// ------------------------------------------------------------------------------------------------
// Normal offset
// ------------------------------------------------------------------------------------------------

/// Normal-offset shadows: look the shadow map up at p + n * (scale * texel_world * sin(theta)),
/// n the unit normal, theta the angle between n and to_light. The offset point sits delta =
/// scale * t * sin(theta) above the plane, i.e. delta / cos(theta) = scale * t * tan(theta) in depth
/// along the light ray: the same margin as bias_slope_scaled with the same scale, without a depth
/// bias (no acne for scale >= sqrt(2)/2), and it moves the lookup sideways by delta * sin(theta),
/// which is why it stays small where light hits head-on. The offset is along the normal on either
/// side of the light. Exact for orthographic lights; a perspective light stores depth along its axis,
/// which changes across a texel by up to texel * sin(a) cos(a) even on a surface facing the light
/// (a: its angle off the light's axis), where sin(theta) = 0 gives no margin: add a constant offset
/// of half a texel or more (docs/shadow_map.md measures it). Inputs: p, normal, to_light finite; normal, to_light nonzero; texel_world,
/// scale finite >= 0. NonFinite, InvalidArgument accordingly; Overflow beyond float range.
/// Fails: the lateral shift moves shadow edges (visible on thin or contact geometry), lookups at
/// silhouettes cross to the other side of thin walls (light leaks), and it needs a correct normal.
inline BiasPosition bias_normal_offset_position(glm::vec3 p, glm::vec3 normal, glm::vec3 to_light, float texel_world,
                                                float scale) {
    BiasPosition r;
    if (!detail::bias_finite(p) || !detail::bias_finite(normal) || !detail::bias_finite(to_light) ||
        !std::isfinite(texel_world) || !std::isfinite(scale)) {
        r.status = Status::NonFinite;
        r.detail = !detail::bias_finite(p) ? "p: NaN or Inf"
                   : (!detail::bias_finite(normal) ? "normal: NaN or Inf"
                   : (!detail::bias_finite(to_light) ? "to_light: NaN or Inf"
                   : (!std::isfinite(texel_world) ? "texel_world: NaN or Inf" : "scale: NaN or Inf")));
        return r;
    }
    if (!(texel_world >= 0.0f) || !(scale >= 0.0f)) {
        r.status = Status::InvalidArgument;
        r.detail = !(texel_world >= 0.0f) ? "texel_world: < 0" : "scale: < 0";
        return r;
    }
    const glm::dvec3 n0(normal), l0(to_light);
    if (glm::dot(n0, n0) == 0.0 || glm::dot(l0, l0) == 0.0) {
        r.status = Status::InvalidArgument;
        r.detail = glm::dot(n0, n0) == 0.0 ? "normal: zero" : "to_light: zero";
        return r;
    }
    const glm::dvec3 nn = n0 / std::fmax(std::fabs(n0.x), std::fmax(std::fabs(n0.y), std::fabs(n0.z)));
    const glm::dvec3 ll = l0 / std::fmax(std::fabs(l0.x), std::fmax(std::fabs(l0.y), std::fabs(l0.z)));
    const glm::dvec3 n = nn / glm::length(nn), l = ll / glm::length(ll);
    const double s = glm::length(glm::cross(n, l));  // sin(theta), in [0, 1]
    const glm::dvec3 q = glm::dvec3(p) + n * (static_cast<double>(scale) * static_cast<double>(texel_world) * s);
    if (!detail::bias_fits_float(q.x) || !detail::bias_fits_float(q.y) || !detail::bias_fits_float(q.z)) {
        r.status = Status::Overflow;
        r.detail = "position: beyond float range";
        return r;
    }
    r.position = glm::vec3(q);
    r.status = Status::Ok;
    return r;
}

// ------------------------------------------------------------------------------------------------
// Receiver plane depth bias
// ------------------------------------------------------------------------------------------------

/// Receiver plane depth bias (Isidoro 2006): from the screen-space derivatives of the shadow
/// coordinate (u, v, z) solve
///   [du/dx dv/dx] [dz/du]   [dz/dx]
///   [du/dy dv/dy] [dz/dv] = [dz/dy]
/// so each PCF tap at uv offset o compares with z + dot(dz_duv, o) instead of z. Exact for a planar
/// receiver whenever z is affine in (u, v) on it: post-projective depth of any light, and linear
/// depth of an orthographic light (not distance-to-light of a perspective light: approximate there).
/// singular (with Ok, dz_duv 0) when |det| <= 1e-7 (|du/dx| + |dv/dx|)(|du/dy| + |dv/dy|): the
/// surface is seen edge-on from the camera or the light; fall back to slope-scaled bias.
/// NonFinite for NaN/Inf, Overflow for a gradient beyond float range.
/// Fails: receivers that are not planar across the kernel (curved, creases, silhouettes: the 2x2
/// pixel-quad derivatives straddle two surfaces).
inline BiasReceiverPlane bias_receiver_plane_depth_gradient(glm::vec3 duvz_dx, glm::vec3 duvz_dy) {
    BiasReceiverPlane g;
    if (!detail::bias_finite(duvz_dx) || !detail::bias_finite(duvz_dy)) {
        g.status = Status::NonFinite;
        g.detail = !detail::bias_finite(duvz_dx) ? "duvz_dx: NaN or Inf" : "duvz_dy: NaN or Inf";
        return g;
    }
    const double a = duvz_dx.x, b = duvz_dx.y, c = duvz_dy.x, d = duvz_dy.y;
    const double det = a * d - b * c;
    const double scale = (std::fabs(a) + std::fabs(b)) * (std::fabs(c) + std::fabs(d));
    g.status = Status::Ok;
    if (!(std::fabs(det) > 1e-7 * scale) || !(scale > 0.0)) {
        g.singular = true;
        return g;
    }
    const double zx = duvz_dx.z, zy = duvz_dy.z;
    const double gu = (d * zx - b * zy) / det, gv = (a * zy - c * zx) / det;
    if (!detail::bias_fits_float(gu) || !detail::bias_fits_float(gv)) {
        g.status = Status::Overflow;
        g.detail = "dz_duv: beyond float range";
        return g;
    }
    g.dz_duv = glm::vec2(static_cast<float>(gu), static_cast<float>(gv));
    return g;
}

/// Receiver depth at a tap offset (in uv) from the fragment: z + dz/du * o.x + dz/dv * o.y.
/// NonFinite for NaN/Inf, Overflow beyond float range.
inline BiasValue bias_receiver_plane_depth(float z, glm::vec2 dz_duv, glm::vec2 offset_uv) {
    BiasValue r;
    if (!std::isfinite(z) || !detail::bias_finite(dz_duv) || !detail::bias_finite(offset_uv)) {
        r.status = Status::NonFinite;
        r.detail = !std::isfinite(z) ? "z: NaN or Inf" : (!detail::bias_finite(dz_duv) ? "dz_duv: NaN or Inf" : "offset_uv: NaN or Inf");
        return r;
    }
    return detail::bias_float(static_cast<double>(z) + static_cast<double>(dz_duv.x) * static_cast<double>(offset_uv.x) +
                              static_cast<double>(dz_duv.y) * static_cast<double>(offset_uv.y));
}

/// The bias receiver-plane depth still needs: the stored depth is the depth at the texel center,
/// the tap position is anywhere in the texel, so up to texel/2 (|dz/du| + |dz/dv|) (texel_uv: the
/// texel size in uv, >= 0). NonFinite for NaN/Inf, InvalidArgument for a negative texel, Overflow.
inline BiasValue bias_receiver_plane_texel_bias(glm::vec2 dz_duv, glm::vec2 texel_uv) {
    BiasValue r;
    if (!detail::bias_finite(dz_duv) || !detail::bias_finite(texel_uv)) {
        r.status = Status::NonFinite;
        r.detail = !detail::bias_finite(dz_duv) ? "dz_duv: NaN or Inf" : "texel_uv: NaN or Inf";
        return r;
    }
    if (!(texel_uv.x >= 0.0f) || !(texel_uv.y >= 0.0f)) { r.status = Status::InvalidArgument; r.detail = "texel_uv: < 0"; return r; }
    return detail::bias_float(0.5 * (std::fabs(static_cast<double>(dz_duv.x)) * static_cast<double>(texel_uv.x) +
                                     std::fabs(static_cast<double>(dz_duv.y)) * static_cast<double>(texel_uv.y)));
}

// ------------------------------------------------------------------------------------------------
// Second-depth (midpoint) shadow maps
// ------------------------------------------------------------------------------------------------

/// Wang & Molnar 1994 / Woo 1992: store the midpoint of the first and second surfaces seen from the
/// light, lo + min((hi - lo) / 2, max_offset) with lo, hi the smaller and larger of z1, z2. Lit front
/// faces then pass with margin (z2 - z1)/2 and the first shadowed surface behind fails with the same
/// margin, without a bias tuned to slope. The smaller depth must be finite; the larger may be +inf
/// (no second surface) when max_offset is finite; max_offset >= 0 (+inf: no cap). NonFinite for NaN
/// or a -inf / infinite smaller depth, InvalidArgument for max_offset < 0 or an uncapped +inf,
/// Overflow beyond float range.
/// Guidance and failure cases: needs closed (watertight) casters; with no second surface (open
/// mesh, single-sided quad, z2 = far or +inf) the midpoint is far behind the caster and everything
/// behind it within that range is lit -> light leaks: cap the midpoint at z1 + max_offset. Thin
/// objects (z2 - z1 below the depth resolution) bring acne back; a receiver lying inside a caster's
/// thickness (contact) may be lit (peter-panning of up to (z2 - z1)/2).
inline BiasValue bias_second_depth_value(float z1, float z2, float max_offset = std::numeric_limits<float>::infinity()) {
    BiasValue r;
    const float lo = z1 < z2 ? z1 : z2, hi = z1 < z2 ? z2 : z1;
    if (std::isnan(z1) || std::isnan(z2) || std::isnan(max_offset) || !std::isfinite(lo) ||
        max_offset == -std::numeric_limits<float>::infinity()) {
        r.status = Status::NonFinite;
        r.detail = std::isnan(z1) || std::isnan(z2) ? "z1, z2: NaN" : (std::isnan(max_offset) ? "max_offset: NaN"
                   : (!std::isfinite(lo) ? "z1, z2: the smaller is Inf" : "max_offset: -Inf"));
        return r;
    }
    if (!(max_offset >= 0.0f) || (std::isinf(hi) && std::isinf(max_offset))) {
        r.status = Status::InvalidArgument;
        r.detail = !(max_offset >= 0.0f) ? "max_offset: < 0" : "max_offset: +inf with an infinite z1 or z2";
        return r;
    }
    const double half = std::isinf(hi) ? std::numeric_limits<double>::infinity()
                                        : 0.5 * (static_cast<double>(hi) - static_cast<double>(lo));
    const double cap = static_cast<double>(max_offset);
    return detail::bias_float(static_cast<double>(lo) + (half < cap ? half : cap));
}

// ------------------------------------------------------------------------------------------------
// Automatic bias: no constant to tune
// ------------------------------------------------------------------------------------------------
//
// Derivation. A shadow map stores, at each texel centre c, the depth of the first surface along the
// light ray through c. The 2x2 percentage-closer filter at a receiver's shadow coordinate uv reads the
// four texel centres c_k around uv (each less than one texel away per axis). When the receiver is the
// plane (p, n), its own depth at c_k is z + g . (c_k - uv) exactly, g = dz/duv the plane's window-depth
// gradient: window depth is affine in uv on a plane under any projective map (Isidoro 2006). So each
// tap compared with the plane's depth at its own centre needs no slope term at all - the classic
// slope-scaled and receiver-plane biases add |g| times up to a texel to every tap instead, which is
// what lets a caster that close to the receiver through (peter-panning, leaks on fine geometry). g
// comes from the normal: the Jacobian of (uv, z) at p (quotient rule, d(c_i / c_w)/dp = (row_i -
// ndc_i row_w) / c_w) applied to two tangents of the plane, then the 2x2 solve of Isidoro's eq.; no
// screen derivatives (they straddle silhouettes in a deferred pass). What remains is the margin
// epsilon of bias_auto_epsilon, in window depth:
//   2 step(format)                      the stored and the compared value each round to the format,
//   2^-21 (|z| + 1) (|z| reversed-Z)    float rounding of the receiver's transform and the rasterizer,
//   2 x 2^-21 |p|_1 |dz/dp|_1           the receiver's position is itself rounded (a G-buffer's, or the
//                                       interpolated world position: a few ulps of its coordinates),
//   |g| texel (1/8 + 2^-20 + 2^-22/rc)  the extrapolation over one texel: 1/8 texel of slope for the
//                                       creases of tessellated meshes (a concave neighbour facet rises
//                                       toward the light within the texel), and the float error of g,
//                                       which grows as 1/rc, rc = |det| / scale the solve's conditioning.
// Nothing depends on the scene: texel size, format and plane are inputs. Measured (docs/shadow_map.md):
// on the `stack` scene 512^2 one texel, 0.00018 misclassified against 0.0015 for glPolygonOffset(2, 2);
// on the Stanford bunny the sampled area light converges (64 maps: RMSE 0.0098 against the wedges'
// 0.0087; 0.0246 with the 1-texel receiver-plane bias). Fails: receivers that are not planar within a
// texel beyond the 1/8 allowance (sharp concave creases show acne along the crease), and an edge-on
// receiver (its plane contains the light ray: edge_on, lit - N.L = 0 shades it dark anyway).

/// The receiver plane's window-depth gradient in a shadow map, from the surface normal.
struct BiasPlaneGradient {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    bool edge_on = false;     ///< true (with Ok): the plane (nearly) contains the light ray through p (conditioning <= 1e-4); dz_duv 0
    glm::vec4 coord{0.0f};    ///< (u, v, window z, clip w) of p, as sk_shadow_coord
    glm::vec2 dz_duv{0.0f};   ///< window depth per uv
    float conditioning = 0.0f;  ///< |det| / scale of the tangent solve, in (1e-4, 1]; 0 when edge_on
    /// Window depth that 4 float ulps of world_pos's coordinates move it by: 2^-21 |p|_1 |dz/dp|_1 (a
    /// G-buffer's position is rounded; part of the margin). >= 0, also when edge_on.
    float position_error = 0.0f;
};

/// The automatic bias's lookup: the 2x2 filter as four compares at texel centres.
struct BiasAutoLookup {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    bool outside = false;       ///< true (with Ok): p is behind the light or outside the map (uv or window z outside [0, 1]): no compare
    bool edge_on = false;       ///< true (with Ok): the plane contains the light ray through p: no compare, lit
    glm::vec4 coord{0.0f};      ///< (u, v, window z, clip w) of p
    glm::vec2 dz_duv{0.0f};     ///< the receiver plane's window depth per uv
    float epsilon = 0.0f;       ///< the precision margin, window depth (> 0 when compared)
    glm::vec2 tap_uv[4]{};      ///< texel centres (i, j), (i+1, j), (i, j+1), (i+1, j+1) in uv
    float tap_depth[4]{};       ///< reference of each compare: plane depth at the centre - epsilon (+ reversed-Z), clamped to [0, 1]
    float tap_weight[4]{};      ///< bilinear weights, each in [0, 1], sum 1
};

namespace detail {
inline bool bias_finite(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}
inline glm::vec4 bias_coord(const glm::mat4& m, glm::vec3 p, bool zero_to_one) {  // sk_shadow_coord, in float
    const glm::vec4 c = m * glm::vec4(p, 1.0f);
    const glm::vec3 ndc = glm::vec3(c) / c.w;
    return glm::vec4(ndc.x * 0.5f + 0.5f, ndc.y * 0.5f + 0.5f, zero_to_one ? ndc.z : ndc.z * 0.5f + 0.5f, c.w);
}
}  // namespace detail

/// Window-depth gradient of the plane through world_pos with normal `normal` (any length, either
/// side) in the map of light_view_proj (GL column-major, the matrix the map was rendered with; clip
/// as it was built): the float arithmetic of glsl/shadow_map.glsl sk_plane_depth_gradient. The
/// tangents are n x a, n x (n x a) with a the axis of n's smallest component. edge_on (with Ok,
/// dz_duv 0) when the solve's conditioning |det| / scale <= 1e-4. NonFinite for NaN/Inf inputs,
/// InvalidArgument for a zero normal or clip w <= 0 at world_pos (behind the light), Overflow for a
/// transform, coordinate or gradient beyond float range.
inline BiasPlaneGradient bias_plane_gradient(const glm::mat4& light_view_proj, ClipDepth clip, glm::vec3 world_pos,
                                             glm::vec3 normal) {
    BiasPlaneGradient r;
    if (!detail::bias_finite(light_view_proj) || !detail::bias_finite(world_pos) || !detail::bias_finite(normal)) {
        r.status = Status::NonFinite;
        r.detail = !detail::bias_finite(light_view_proj) ? "light_view_proj: NaN or Inf"
                   : (!detail::bias_finite(world_pos) ? "world_pos: NaN or Inf" : "normal: NaN or Inf");
        return r;
    }
    const double nl = std::sqrt(static_cast<double>(normal.x) * normal.x + static_cast<double>(normal.y) * normal.y +
                                static_cast<double>(normal.z) * normal.z);
    if (!(nl > 0.0) || (clip != ClipDepth::NegativeOneToOne && clip != ClipDepth::ZeroToOne)) {
        r.status = Status::InvalidArgument;
        r.detail = !(nl > 0.0) ? "normal: zero" : "clip: unknown ClipDepth";
        return r;
    }
    const glm::mat4& m = light_view_proj;
    const glm::vec4 c = m * glm::vec4(world_pos, 1.0f);
    if (!(c.w > 0.0f) || !std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z) || !std::isfinite(c.w)) {
        r.status = c.w > 0.0f ? Status::Overflow : Status::InvalidArgument;
        r.detail = c.w > 0.0f ? "world_pos: clip coordinates beyond float" : "world_pos: behind the light (clip w <= 0)";
        return r;
    }
    const bool z01 = clip == ClipDepth::ZeroToOne;
    r.coord = detail::bias_coord(m, world_pos, z01);
    if (!detail::bias_finite(glm::vec3(r.coord))) {  // c / w beyond float (w tiny)
        r = BiasPlaneGradient{};
        r.status = Status::Overflow;
        r.detail = "world_pos: c / w beyond float";
        return r;
    }
    const glm::vec3 ndc = glm::vec3(c) / c.w;
    const glm::vec3 rw(m[0][3], m[1][3], m[2][3]);
    const glm::vec3 jx = (glm::vec3(m[0][0], m[1][0], m[2][0]) - ndc.x * rw) / c.w;  // d ndc_i/dp (quotient rule)
    const glm::vec3 jy = (glm::vec3(m[0][1], m[1][1], m[2][1]) - ndc.y * rw) / c.w;
    const glm::vec3 jz = (glm::vec3(m[0][2], m[1][2], m[2][2]) - ndc.z * rw) / c.w;
    const float zs = z01 ? 1.0f : 0.5f;
    const glm::vec3 ap = glm::abs(world_pos), ajz = glm::abs(jz);
    const float pos_err = 4.76837158e-7f * (ap.x + ap.y + ap.z) * (ajz.x + ajz.y + ajz.z) * zs;
    if (!std::isfinite(pos_err)) {
        r = BiasPlaneGradient{};
        r.status = Status::Overflow;
        r.detail = "world_pos: position error beyond float";
        return r;
    }
    r.position_error = pos_err;
    const glm::vec3 n = glm::vec3(glm::dvec3(normal) / nl);
    const glm::vec3 an = glm::abs(n);
    const glm::vec3 axis = an.x <= an.y && an.x <= an.z ? glm::vec3(1.0f, 0.0f, 0.0f)
                                                        : (an.y <= an.z ? glm::vec3(0.0f, 1.0f, 0.0f) : glm::vec3(0.0f, 0.0f, 1.0f));
    const glm::vec3 t1 = glm::normalize(glm::cross(n, axis));
    const glm::vec3 t2 = glm::cross(n, t1);
    const glm::vec3 s1(0.5f * glm::dot(jx, t1), 0.5f * glm::dot(jy, t1), zs * glm::dot(jz, t1));
    const glm::vec3 s2(0.5f * glm::dot(jx, t2), 0.5f * glm::dot(jy, t2), zs * glm::dot(jz, t2));
    const float det = s1.x * s2.y - s1.y * s2.x;
    const float scale = (std::fabs(s1.x) + std::fabs(s1.y)) * (std::fabs(s2.x) + std::fabs(s2.y));
    const float cond = scale > 0.0f ? std::fabs(det) / scale : 0.0f;
    r.status = Status::Ok;
    if (!(cond > 1e-4f) || !std::isfinite(cond)) {
        r.edge_on = true;
        return r;
    }
    const float gu = (s2.y * s1.z - s1.y * s2.z) / det, gv = (s1.x * s2.z - s2.x * s1.z) / det;
    if (!std::isfinite(gu) || !std::isfinite(gv)) {
        r = BiasPlaneGradient{};
        r.status = Status::Overflow;
        r.detail = "dz_duv: beyond float range";
        return r;
    }
    r.dz_duv = glm::vec2(gu, gv);
    r.conditioning = cond;
    return r;
}

/// The window-depth step of a map format, the `depth_step` of the snippet's automatic bias:
/// 1 / 65535 (Fixed16), 1 / 16777215 (Fixed24), 0 for Float32 (its rounding is in the float term).
/// InvalidArgument for an unknown format.
inline BiasValue bias_auto_depth_step(DepthFormat f) {
    BiasValue r;
    if (!detail::bias_valid_format(f)) { r.status = Status::InvalidArgument; r.detail = "f: unknown DepthFormat"; return r; }
    r.value = f == DepthFormat::Fixed16 ? static_cast<float>(1.0 / 65535.0)
                                        : (f == DepthFormat::Fixed24 ? static_cast<float>(1.0 / 16777215.0) : 0.0f);
    r.status = Status::Ok;
    return r;
}

/// The automatic bias's precision margin (window depth) at receiver depth z for a plane of gradient
/// dz_duv, conditioning rc and position error (bias_plane_gradient) in a map of texel size texel_uv:
/// the derivation above, in the float arithmetic of sk_auto_bias_epsilon. z, dz_duv finite; texel_uv
/// finite > 0; conditioning finite in (0, 1]; position_error and depth_step finite >= 0
/// (bias_auto_depth_step). NonFinite, InvalidArgument accordingly, Overflow beyond float range.
inline BiasValue bias_auto_epsilon(glm::vec2 dz_duv, float conditioning, float position_error, glm::vec2 texel_uv, float z,
                                   float depth_step, bool reversed_z) {
    BiasValue r;
    if (!detail::bias_finite(dz_duv) || !detail::bias_finite(texel_uv) || !std::isfinite(z) ||
        !std::isfinite(conditioning) || !std::isfinite(depth_step) || !std::isfinite(position_error)) {
        r.status = Status::NonFinite;
        r.detail = !detail::bias_finite(dz_duv) ? "dz_duv: NaN or Inf"
                   : (!detail::bias_finite(texel_uv) ? "texel_uv: NaN or Inf"
                   : (!std::isfinite(z) ? "z: NaN or Inf"
                   : (!std::isfinite(conditioning) ? "conditioning: NaN or Inf"
                   : (!std::isfinite(depth_step) ? "depth_step: NaN or Inf" : "position_error: NaN or Inf"))));
        return r;
    }
    if (!(texel_uv.x > 0.0f) || !(texel_uv.y > 0.0f) || !(conditioning > 0.0f) || conditioning > 1.0f ||
        !(depth_step >= 0.0f) || !(position_error >= 0.0f)) {
        r.status = Status::InvalidArgument;
        r.detail = !(texel_uv.x > 0.0f) || !(texel_uv.y > 0.0f) ? "texel_uv: not > 0"
                   : (!(conditioning > 0.0f) || conditioning > 1.0f ? "conditioning: outside (0, 1]"
                   : (!(depth_step >= 0.0f) ? "depth_step: < 0" : "position_error: < 0"));
        return r;
    }
    const float float_term = reversed_z ? 4.76837158e-7f * std::fabs(z) + 1.17549435e-38f : 4.76837158e-7f * (1.0f + std::fabs(z));
    const float plane = std::fabs(dz_duv.x) * texel_uv.x + std::fabs(dz_duv.y) * texel_uv.y;
    const float cond = conditioning > 1e-4f ? conditioning : 1e-4f;
    const float e = 2.0f * depth_step + float_term + 2.0f * position_error + plane * (0.125f + 9.53674316e-7f + 2.38418579e-7f / cond);
    if (!std::isfinite(e)) { r.status = Status::Overflow; r.detail = "epsilon: beyond float range"; return r; }
    r.value = e;
    r.status = Status::Ok;
    return r;
}

/// The automatic bias's lookup of world_pos (normal: the receiver's geometric normal, any length,
/// either side) in a map of map_size texels rendered with light_view_proj WITHOUT polygon offset:
/// the float arithmetic of sk_auto_bias_taps. map_size >= 1 per axis; format a DepthFormat.
/// NonFinite for NaN/Inf inputs, InvalidArgument for a zero normal, a map size < 1 or an unknown
/// clip depth or format; Overflow when the transform, gradient or margin is beyond float. Behind the light or
/// outside the map: outside (with Ok); edge-on plane: edge_on (with Ok).
inline BiasAutoLookup bias_auto_lookup(const glm::mat4& light_view_proj, ClipDepth clip, bool reversed_z, glm::vec3 world_pos,
                                       glm::vec3 normal, glm::ivec2 map_size, DepthFormat format) {
    BiasAutoLookup a;
    if (map_size.x < 1 || map_size.y < 1 || !detail::bias_valid_format(format)) {
        a.status = Status::InvalidArgument;
        a.detail = map_size.x < 1 || map_size.y < 1 ? "map_size: < 1" : "format: unknown DepthFormat";
        return a;
    }
    if (!detail::bias_finite(light_view_proj) || !detail::bias_finite(world_pos) || !detail::bias_finite(normal)) {
        a.status = Status::NonFinite;
        a.detail = !detail::bias_finite(light_view_proj) ? "light_view_proj: NaN or Inf"
                   : (!detail::bias_finite(world_pos) ? "world_pos: NaN or Inf" : "normal: NaN or Inf");
        return a;
    }
    const glm::vec4 c = light_view_proj * glm::vec4(world_pos, 1.0f);
    const bool z01 = clip == ClipDepth::ZeroToOne;
    const glm::vec4 coord = c.w > 0.0f ? detail::bias_coord(light_view_proj, world_pos, z01) : glm::vec4(0.0f);
    if (!detail::bias_finite(glm::vec3(c)) || !std::isfinite(c.w) || !detail::bias_finite(glm::vec3(coord))) {
        a.status = Status::Overflow;  // the transform or c / w beyond float
        a.detail = "world_pos: clip coordinates or c / w beyond float";
        return a;
    }
    if (!(c.w > 0.0f) || !(coord.x >= 0.0f && coord.x <= 1.0f && coord.y >= 0.0f && coord.y <= 1.0f && coord.z >= 0.0f &&
                           coord.z <= 1.0f)) {
        if (clip != ClipDepth::NegativeOneToOne && clip != ClipDepth::ZeroToOne) {
            a.status = Status::InvalidArgument;
            a.detail = "clip: unknown ClipDepth";
            return a;
        }
        if (glm::dot(normal, normal) == 0.0f) { a.status = Status::InvalidArgument; a.detail = "normal: zero"; return a; }
        a.outside = true;
        a.coord = coord;
        a.status = Status::Ok;
        return a;
    }
    const BiasPlaneGradient g = bias_plane_gradient(light_view_proj, clip, world_pos, normal);
    if (g.status != Status::Ok) { a.status = g.status; a.detail = g.detail; return a; }
    a.coord = g.coord;
    if (g.edge_on) { a.edge_on = true; a.status = Status::Ok; return a; }
    const glm::vec2 size(static_cast<float>(map_size.x), static_cast<float>(map_size.y));
    const glm::vec2 texel = 1.0f / size;
    const BiasValue dstep = bias_auto_depth_step(format);
    const BiasValue eps = bias_auto_epsilon(g.dz_duv, g.conditioning, g.position_error, texel, g.coord.z, dstep.value, reversed_z);
    if (eps.status != Status::Ok) { a.status = eps.status; a.detail = eps.detail; return a; }
    const glm::vec2 f = glm::vec2(g.coord) * size - 0.5f;
    const glm::vec2 i0(std::floor(f.x), std::floor(f.y));
    const glm::vec2 w = f - i0;
    for (int k = 0; k < 4; ++k) {
        const glm::vec2 centre = (i0 + glm::vec2(static_cast<float>(k & 1), static_cast<float>(k >> 1)) + 0.5f) * texel;
        a.tap_uv[k] = centre;
        const float zp = g.coord.z + glm::dot(g.dz_duv, centre - glm::vec2(g.coord));
        const float ref = reversed_z ? zp + eps.value : zp - eps.value;
        if (!std::isfinite(ref)) {
            a = BiasAutoLookup{};
            a.status = Status::Overflow;
            a.detail = "tap_depth: beyond float range";
            return a;
        }
        a.tap_depth[k] = ref < 0.0f ? 0.0f : (ref > 1.0f ? 1.0f : ref);
    }
    a.tap_weight[0] = (1.0f - w.x) * (1.0f - w.y);
    a.tap_weight[1] = w.x * (1.0f - w.y);
    a.tap_weight[2] = (1.0f - w.x) * w.y;
    a.tap_weight[3] = w.x * w.y;
    a.dz_duv = g.dz_duv;
    a.epsilon = eps.value;
    a.status = Status::Ok;
    return a;
}

/// The lit fraction sk_shadow_map_visibility_auto returns, from the map's stored depths at the four
/// taps (stored[k] at tap_uv[k]; a texel outside the map: the border's far depth). A tap is lit when
/// tap_depth <= stored (reversed-Z: >=), GL_LEQUAL / GL_GEQUAL. total: a result that is not Ok gives
/// 0; outside gives outside_value; edge_on gives 1; a NaN stored depth counts as shadowed; the result
/// is in [0, 1] (outside_value clamped).
inline float bias_auto_visibility(const BiasAutoLookup& a, const float stored[4], bool reversed_z, float outside_value) {
    if (a.status != Status::Ok || stored == nullptr) return 0.0f;
    if (a.outside) return outside_value >= 0.0f ? (outside_value <= 1.0f ? outside_value : 1.0f) : 0.0f;
    if (a.edge_on) return 1.0f;
    float v = 0.0f;
    for (int k = 0; k < 4; ++k) {
        const bool lit = reversed_z ? a.tap_depth[k] >= stored[k] : a.tap_depth[k] <= stored[k];
        v += lit ? a.tap_weight[k] : 0.0f;
    }
    return v < 0.0f ? 0.0f : (v > 1.0f ? 1.0f : v);
}

/// The bias one filtered tap needs (pcf.glsl kernels with GL_LINEAR, pcss.glsl: each tap applies the
/// receiver plane at its offset but its hardware 2x2 reads texel centres up to one texel away with one
/// reference): one texel of the plane's slope plus bias_auto_epsilon (sk_auto_filtered_bias).
/// Inputs and statuses as bias_auto_epsilon.
inline BiasValue bias_auto_filtered(glm::vec2 dz_duv, float conditioning, float position_error, glm::vec2 texel_uv, float z,
                                    float depth_step, bool reversed_z) {
    const BiasValue e = bias_auto_epsilon(dz_duv, conditioning, position_error, texel_uv, z, depth_step, reversed_z);
    if (e.status != Status::Ok) return e;
    return detail::bias_float(static_cast<double>(std::fabs(dz_duv.x)) * texel_uv.x +
                              static_cast<double>(std::fabs(dz_duv.y)) * texel_uv.y + static_cast<double>(e.value));
}

} // namespace shadowkit
