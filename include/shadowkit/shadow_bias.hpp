// shadowkit/shadow_bias.hpp - depth bias for shadow maps: constant, slope-scaled (and its
// glPolygonOffset equivalent), normal offset, receiver-plane depth bias, the depth metric and the
// precision each metric/format gives at a distance, and second-depth (midpoint) shadow maps.
//
// USAGE
//   #include <shadowkit/shadow_bias.hpp>
//   using namespace shadowkit;
//   float t   = texel_world_size_perspective(dist, fov_y, 2048);       // world size of one texel
//   float tn  = light_tan_angle(normal, to_light);                     // tan(angle(normal, light))
//   float b   = slope_scaled_bias(t, tn);                              // world-space depth bias
//   glm::vec3 q = normal_offset_position(p, normal, to_light, t, 0.75f);  // or: offset the lookup
//   ReceiverPlaneGradient g = receiver_plane_depth_gradient(dFdx_uvz, dFdy_uvz);
//   float z_tap = receiver_plane_depth(uvz.z, g.dz_duv, tap_offset_uv);  // per PCF tap
//   float units = polygon_offset(/*factor*/1.0f, /*units*/2.0f, dzdx, dzdy, DepthFormat::Fixed24, zmax);
//   double dd = depth_metric_resolution(DepthMetric::PostProjective, DepthFormat::Fixed24, 40.0, 0.1, 100.0);
//
// Units: "world" values are distances in the light's depth metric (eye distance along the light's
// axis, or distance to the light); "window" values are stored depth in [0,1].
//
// Based on:
//   L. Williams, "Casting curved shadows on curved surfaces", SIGGRAPH 1978.
//   Y. Wang, S. Molnar, "Second-Depth Shadow Mapping", UNC TR94-019, 1994 (midpoint depth).
//   OpenGL 4.6 core spec, Sec. 14.6.5 "Depth Offset" (o = m * factor + r * units).
//   J. Isidoro, "Shadow Mapping: GPU-based Tips and Techniques", GDC 2006 (receiver plane depth bias).
//   D. Holbert, "Saying Goodbye to Shadow Acne", GDC 2011 poster (normal offset).
//   M. Gerlach (Apelles thesis, 2010): distance to the light as a linear depth metric.
//
// MIT License. Copyright (c) shadowkit contributors.
#pragma once

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <cstdint>
#include <limits>

namespace shadowkit {

// Shared with other shadowkit headers; the guards let any of them be included together.
#ifndef SHADOWKIT_CLIP_DEPTH_DEFINED
#define SHADOWKIT_CLIP_DEPTH_DEFINED
/// Clip-space depth range: OpenGL default [-1, 1] or D3D/Vulkan/glClipControl [0, 1].
enum class ClipDepth { NegativeOneToOne, ZeroToOne };
#endif
#ifndef SHADOWKIT_DEPTH_FORMAT_DEFINED
#define SHADOWKIT_DEPTH_FORMAT_DEFINED
/// Depth-buffer storage formats (DEPTH_COMPONENT32F, DEPTH24 / DEPTH24_STENCIL8, DEPTH_COMPONENT16).
enum class DepthFormat { Float32, Fixed24, Fixed16 };
#endif

// What the shadow map stores as depth.
enum class DepthMetric {
    PostProjective,          // window depth of a perspective light, 0 at near, 1 at far (far may be +Inf)
    PostProjectiveReversed,  // reversed-Z: 1 at near, 0 at far (far may be +Inf)
    LinearNormalized,        // (d - near) / (far - near): orthographic lights, or linear depth written by the shader
    LinearDistance           // d itself (e.g. distance to the light in an R32F target); Float32 only
};

// ------------------------------------------------------------------------------------------------
// Depth formats
// ------------------------------------------------------------------------------------------------

// Number of bits of a fixed-point format (0 for Float32).
inline int depth_format_bits(DepthFormat f) {
    return f == DepthFormat::Fixed24 ? 24 : (f == DepthFormat::Fixed16 ? 16 : 0);
}

// Rounds a value to what the format stores: UNORM n clamps to [0,1] and rounds to k / (2^n - 1);
// Float32 rounds to float. NaN stays NaN.
inline double quantize_depth(DepthFormat f, double v) {
    if (std::isnan(v)) return v;
    const int bits = depth_format_bits(f);
    if (bits == 0) return double(static_cast<float>(v));
    const double scale = std::ldexp(1.0, bits) - 1.0;
    const double c = v < 0.0 ? 0.0 : (v > 1.0 ? 1.0 : v);
    return std::round(c * scale) / scale;
}

// Spacing between the stored value nearest to v and the next one above it: 1 / (2^n - 1) for UNORM n,
// the float32 ulp of v for Float32 (v > 0; the smallest subnormal at 0). NaN for NaN.
inline double depth_format_step(DepthFormat f, double v) {
    if (std::isnan(v)) return v;
    const int bits = depth_format_bits(f);
    if (bits != 0) return 1.0 / (std::ldexp(1.0, bits) - 1.0);
    const float x = static_cast<float>(std::fabs(v));
    if (std::isinf(x)) return std::numeric_limits<double>::infinity();
    return double(std::nextafter(x, std::numeric_limits<float>::infinity())) - double(x);
}

// ------------------------------------------------------------------------------------------------
// Depth metric and precision
// ------------------------------------------------------------------------------------------------

// Stored value of the metric for an eye distance d (d along the light's axis for PostProjective*).
// PostProjective: z_w = f (d - n) / (d (f - n)), = 1 - n/d for f = +Inf (GL [-1,1] and [0,1] clip
// depth give the same window depth with glDepthRange(0,1); GL's 0.5 ndc + 0.5 loses bits near 1).
// PostProjectiveReversed: z_w = n (f - d) / (d (f - n)), = n / d for f = +Inf.
inline double depth_metric_value(DepthMetric m, double d, double n, double f) {
    switch (m) {
    case DepthMetric::PostProjective:
        return std::isinf(f) ? 1.0 - n / d : f * (d - n) / (d * (f - n));
    case DepthMetric::PostProjectiveReversed:
        return std::isinf(f) ? n / d : n * (f - d) / (d * (f - n));
    case DepthMetric::LinearNormalized:
        return (d - n) / (f - n);
    case DepthMetric::LinearDistance:
        return d;
    }
    return std::numeric_limits<double>::quiet_NaN();
}

// |d value / d distance| of the metric at distance d.
// PostProjective(Reversed): f n / (d^2 (f - n)) (n / d^2 for f = +Inf); LinearNormalized: 1/(f - n);
// LinearDistance: 1.
inline double depth_metric_slope(DepthMetric m, double d, double n, double f) {
    switch (m) {
    case DepthMetric::PostProjective:
    case DepthMetric::PostProjectiveReversed:
        return std::isinf(f) ? n / (d * d) : f * n / (d * d * (f - n));
    case DepthMetric::LinearNormalized:
        return 1.0 / (f - n);
    case DepthMetric::LinearDistance:
        return 1.0;
    }
    return std::numeric_limits<double>::quiet_NaN();
}

// World-space depth resolution at distance d: the distance between adjacent stored values,
// step(format, value(d)) / slope(d) (first order). This is the smallest useful constant bias.
// - PostProjective, UNORM n: d^2 (f - n) / (f n (2^n - 1)): grows with d^2, so far receivers need
//   a much larger constant bias than near ones (acne far away, peter-panning near).
// - PostProjective, Float32: values crowd near 1, ulp(1) = 6e-8 is no better than 24-bit UNORM.
// - PostProjectiveReversed, Float32: z_w ~ n/d and ulp(z_w) ~ z_w 2^-23, so dd ~ d 2^-23: a
//   relative precision of 2^-24..2^-23 at every distance (even with f = +Inf), the best choice.
// - LinearNormalized, UNORM n: uniform (f - n) / (2^n - 1).  LinearDistance (float32): ulp(d).
// Returns NaN when the inputs are invalid (d, n <= 0, f <= n, d outside [n, f], LinearDistance with
// a UNORM format, NaN anywhere).
inline double depth_metric_resolution(DepthMetric m, DepthFormat fmt, double d, double n, double f) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    if (!(n > 0.0) || !(f > n) || !(d >= n) || !(d <= f) || std::isinf(d) || std::isinf(n)) return nan;
    if (std::isinf(f) && (m == DepthMetric::LinearNormalized)) return nan;
    if (m == DepthMetric::LinearDistance && fmt != DepthFormat::Float32) return nan;
    const double v = depth_metric_value(m, d, n, f);
    return depth_format_step(fmt, v) / depth_metric_slope(m, d, n, f);
}

// World-space size of one shadow-map texel at eye distance d along a perspective light's axis:
// 2 d tan(fov/2) / resolution. (Off axis the texel footprint on a plane facing the light grows by
// 1/cos^2 of the off-axis angle; use the orthographic version with the local width if needed.)
inline float texel_world_size_perspective(float d, float fov, float resolution) {
    return 2.0f * d * std::tan(0.5f * fov) / resolution;
}

// World-space size of one texel of an orthographic light of width `width`: width / resolution.
inline float texel_world_size_ortho(float width, float resolution) { return width / resolution; }

// ------------------------------------------------------------------------------------------------
// Constant bias and the comparison
// ------------------------------------------------------------------------------------------------

// The shadow test with a constant bias: lit when receiver - bias <= stored (reversed-Z:
// receiver + bias >= stored). Any NaN -> false (shadowed).
// Fails: a constant bias large enough for grazing surfaces (depth changes by texel * tan(theta)
// across a texel) pushes shadows away from their casters (peter-panning) and lets thin casters
// leak light; one small enough to keep contact shadows gives acne on sloped surfaces. It must at
// least cover depth_metric_resolution() at the receiver's distance.
inline bool shadow_test_lit(float receiver, float stored, float bias, bool reversed_z) {
    return reversed_z ? receiver + bias >= stored : receiver - bias <= stored;
}

// ------------------------------------------------------------------------------------------------
// Slope-scaled bias
// ------------------------------------------------------------------------------------------------

// tan of the angle theta between the surface normal and the direction to the light,
// sqrt(1 - c^2) / c with c = dot(n, l) of the normalized vectors. +Inf when the surface faces away
// or contains the light direction (c <= 0); NaN for zero-length or NaN vectors.
inline float light_tan_angle(glm::vec3 normal, glm::vec3 to_light) {
    const float ln = glm::length(normal), ll = glm::length(to_light);
    if (!(ln > 0.0f) || !(ll > 0.0f) || std::isinf(ln) || std::isinf(ll)) return std::numeric_limits<float>::quiet_NaN();
    const double c = double(glm::dot(normal, to_light)) / (double(ln) * double(ll));
    if (std::isnan(c)) return std::numeric_limits<float>::quiet_NaN();
    if (c <= 0.0) return std::numeric_limits<float>::infinity();
    const double cc = c > 1.0 ? 1.0 : c;
    return static_cast<float>(std::sqrt(1.0 - cc * cc) / cc);
}

// Depth gradient (dz/du, dz/dv) of a plane with normal n seen by an orthographic light with
// orthonormal basis (right, up, forward = direction light travels; depth grows along forward),
// in depth units per world unit on the light's image plane: -(n.right)/(n.forward), -(n.up)/(n.forward).
// Its length is tan(theta). ok == false when the plane contains the light direction (n.forward == 0).
struct DepthGradient {
    bool ok = false;
    glm::vec2 dz_duv{0.0f};
};
inline DepthGradient plane_depth_gradient(glm::vec3 normal, glm::vec3 right, glm::vec3 up, glm::vec3 forward) {
    DepthGradient g;
    const float nf = glm::dot(normal, forward);
    if (!(std::fabs(nf) > 0.0f) || !std::isfinite(nf)) return g;
    g.dz_duv = glm::vec2(-glm::dot(normal, right) / nf, -glm::dot(normal, up) / nf);
    g.ok = std::isfinite(g.dz_duv.x) && std::isfinite(g.dz_duv.y);
    return g;
}

// Exact largest depth difference between a texel's centre and any point of that texel on a plane
// with depth gradient g: texel/2 * (|g.x| + |g.y|) (the maximum of a linear function on a square is
// at a corner). This is what a bias must cover to avoid acne with nearest (1-tap) lookups.
inline float texel_depth_delta(glm::vec2 dz_duv, float texel_world) {
    return 0.5f * texel_world * (std::fabs(dz_duv.x) + std::fabs(dz_duv.y));
}

// Slope-scaled bias: constant + slope_scale * texel_world * min(tan(theta), max_tan).
// With slope_scale >= sqrt(2)/2 it covers texel_depth_delta() for every plane orientation
// (|g.x| + |g.y| <= sqrt(2) |g|, |g| = tan(theta)); a PCF kernel of radius R texels needs
// slope_scale >= (R + sqrt(2)/2) because taps compare one receiver depth with distant texels.
// Fails: tan(theta) -> Inf at grazing angles, so it must be clamped (max_tan); at the clamp acne
// returns on surfaces nearly parallel to the light (usually hidden by N.L shading), and large
// scales push contact shadows away (peter-panning) and leak light under thin casters.
inline float slope_scaled_bias(float texel_world, float tan_theta, float slope_scale = 0.70710678f,
                               float constant = 0.0f, float max_tan = 10.0f) {
    const float t = tan_theta > max_tan ? max_tan : tan_theta;
    return constant + slope_scale * texel_world * t;
}

// Minimum resolvable difference r of glPolygonOffset / Vulkan depthBiasConstantFactor:
// UNORM n: 2^-n; Float32: 2^(e - 23) with e the exponent of the largest |z| of the primitive
// (z = m 2^e, 1 <= m < 2). Returns NaN for NaN, 2^-149 for z == 0 (the spec leaves it open).
inline double polygon_offset_r(DepthFormat f, float max_window_z) {
    const int bits = depth_format_bits(f);
    if (bits != 0) return std::ldexp(1.0, -bits);
    if (std::isnan(max_window_z)) return std::numeric_limits<double>::quiet_NaN();
    const float z = std::fabs(max_window_z);
    if (z == 0.0f) return std::ldexp(1.0, -149);
    if (std::isinf(z)) return std::numeric_limits<double>::infinity();
    int e = 0;
    (void)std::frexp(z, &e);  // z = m' 2^e with 0.5 <= m' < 1
    return std::ldexp(1.0, (e - 1) - 23);
}

// glPolygonOffset(factor, units) as the rasterizer applies it (GL 4.6 eq. 14.8):
// o = m * factor + r * units, with m = sqrt(dzdx^2 + dzdy^2) (exact_m) or its allowed
// approximation max(|dzdx|, |dzdy|), dz/dx, dz/dy the window-depth slope per shadow-map pixel.
// Equivalence with slope_scaled_bias: for an orthographic light (LinearNormalized) a plane has
// m_exact = texel_world * tan(theta) / (f - n), so factor = slope_scale reproduces it with exact m;
// a driver using max() needs factor = slope_scale * sqrt(2) to be safe.
inline double polygon_offset(float factor, float units, float dzdx, float dzdy, DepthFormat f, float max_window_z,
                             bool exact_m = false) {
    const double ax = std::fabs(double(dzdx)), ay = std::fabs(double(dzdy));
    const double m = exact_m ? std::sqrt(ax * ax + ay * ay) : (ax > ay ? ax : ay);
    return m * double(factor) + polygon_offset_r(f, max_window_z) * double(units);
}

// The `units` argument that makes r * units equal a world-space depth bias at distance d for the
// given metric: world_bias * slope(d) / r. Since the post-projective slope falls with 1/d^2, a
// fixed `units` is a bias that grows with d^2 in world space.
inline double polygon_offset_units_for_world_bias(double world_bias, DepthMetric m, DepthFormat fmt, double d,
                                                  double n, double f) {
    const double v = depth_metric_value(m, d, n, f);
    return world_bias * depth_metric_slope(m, d, n, f) / polygon_offset_r(fmt, static_cast<float>(v));
}

// ------------------------------------------------------------------------------------------------
// Normal offset
// ------------------------------------------------------------------------------------------------

// Normal-offset shadows: look the shadow map up at p + n * (scale * texel_world * sin(theta)).
// The offset point sits delta = scale * t * sin(theta) above the plane, i.e. delta / cos(theta) =
// scale * t * tan(theta) in depth along the light ray: the same margin as slope_scaled_bias with
// the same scale, without a depth bias (no acne for scale >= sqrt(2)/2), and it moves the lookup
// sideways by delta * sin(theta), which is why it stays small where light hits head-on.
// Fails: the lateral shift moves shadow edges (visible on thin or contact geometry), lookups at
// silhouettes cross to the other side of thin walls (light leaks), and needs a correct normal.
// Returns p unchanged when a vector is degenerate or the surface faces away (sin undefined).
inline glm::vec3 normal_offset_position(glm::vec3 p, glm::vec3 normal, glm::vec3 to_light, float texel_world,
                                        float scale) {
    const float ln = glm::length(normal), ll = glm::length(to_light);
    if (!(ln > 0.0f) || !(ll > 0.0f) || !std::isfinite(ln) || !std::isfinite(ll)) return p;
    const glm::vec3 n = normal / ln;
    const float c = glm::dot(n, to_light / ll);
    if (!std::isfinite(c)) return p;
    const float cc = c > 1.0f ? 1.0f : (c < -1.0f ? -1.0f : c);
    const float s = std::sqrt(1.0f - cc * cc);
    return p + n * (scale * texel_world * s);
}

// ------------------------------------------------------------------------------------------------
// Receiver plane depth bias
// ------------------------------------------------------------------------------------------------

// Receiver plane depth bias (Isidoro 2006): from the screen-space derivatives of the shadow
// coordinate (u, v, z) solve
//   [du/dx dv/dx] [dz/du]   [dz/dx]
//   [du/dy dv/dy] [dz/dv] = [dz/dy]
// so each PCF tap at uv offset o compares with z + dot(dz_duv, o) instead of z. Exact for a planar
// receiver whenever z is affine in (u, v) on it: post-projective depth of any light, and linear
// depth of an orthographic light (not distance-to-light of a perspective light: approximate there).
// Fails: receivers that are not planar across the kernel (curved, creases, silhouettes: the 2x2
// pixel-quad derivatives straddle two surfaces), and when the uv Jacobian is singular (surface
// seen edge-on from the camera or the light). ok == false then; fall back to slope-scaled bias.
struct ReceiverPlaneGradient {
    bool ok = false;
    glm::vec2 dz_duv{0.0f};
};
inline ReceiverPlaneGradient receiver_plane_depth_gradient(glm::vec3 duvz_dx, glm::vec3 duvz_dy) {
    ReceiverPlaneGradient g;
    const double a = duvz_dx.x, b = duvz_dx.y, c = duvz_dy.x, d = duvz_dy.y;
    const double det = a * d - b * c;
    const double scale = (std::fabs(a) + std::fabs(b)) * (std::fabs(c) + std::fabs(d));
    if (!std::isfinite(det) || !std::isfinite(scale) || !(std::fabs(det) > 1e-7 * scale)) return g;
    const double zx = duvz_dx.z, zy = duvz_dy.z;
    const double gu = (d * zx - b * zy) / det, gv = (a * zy - c * zx) / det;
    if (!std::isfinite(gu) || !std::isfinite(gv)) return g;
    g.dz_duv = glm::vec2(static_cast<float>(gu), static_cast<float>(gv));
    g.ok = std::isfinite(g.dz_duv.x) && std::isfinite(g.dz_duv.y);
    return g;
}

// Receiver depth at a tap offset (in uv) from the fragment: z + dz/du * o.x + dz/dv * o.y.
inline float receiver_plane_depth(float z, glm::vec2 dz_duv, glm::vec2 offset_uv) {
    return z + dz_duv.x * offset_uv.x + dz_duv.y * offset_uv.y;
}

// The bias receiver-plane depth still needs: the stored depth is the depth at the texel centre,
// the tap position is anywhere in the texel, so up to texel/2 (|dz/du| + |dz/dv|) (texel in uv).
inline float receiver_plane_texel_bias(glm::vec2 dz_duv, glm::vec2 texel_uv) {
    return 0.5f * (std::fabs(dz_duv.x) * texel_uv.x + std::fabs(dz_duv.y) * texel_uv.y);
}

// ------------------------------------------------------------------------------------------------
// Second-depth (midpoint) shadow maps
// ------------------------------------------------------------------------------------------------

// Wang & Molnar 1994 / Woo 1992: store the midpoint of the first and second surfaces seen from the
// light, z1 + (z2 - z1)/2. Lit front faces then pass with margin (z2 - z1)/2 and the first shadowed
// surface behind fails with the same margin, without a bias tuned to slope.
// Guidance and failure cases: needs closed (watertight) casters; with no second surface (open
// mesh, single-sided quad, z2 = far/Inf) the midpoint is far behind the caster and everything
// behind it within that range is lit -> light leaks: cap the midpoint at z1 + max_offset. Thin
// objects (z2 - z1 below the depth resolution) bring acne back; a receiver lying inside a caster's
// thickness (contact) may be lit (peter-panning of up to (z2 - z1)/2). NaN in -> NaN out.
inline float second_depth_value(float z1, float z2, float max_offset = std::numeric_limits<float>::infinity()) {
    if (std::isnan(z1) || std::isnan(z2) || std::isnan(max_offset)) return std::numeric_limits<float>::quiet_NaN();
    const float lo = z1 < z2 ? z1 : z2, hi = z1 < z2 ? z2 : z1;
    const double mid = double(lo) + 0.5 * (double(hi) - double(lo));
    const double cap = double(lo) + double(max_offset);
    return static_cast<float>(mid < cap ? mid : cap);
}

}  // namespace shadowkit
