// shadowkit/pcss.hpp - percentage-closer soft shadows: blocker search, penumbra and filter width on linear depth, near-plane fit, tap budget
//
// Usage:
//   #include <shadowkit/pcss.hpp>
//   namespace sk = shadowkit;
//   sk::PcssLight L;                               // a spot light's shadow frustum
//   L.size = 0.5f; L.near_z = 0.1f; L.far_z = 50.0f; L.frustum_width = 2.0f * std::tan(0.5f * fov);
//   // The blocker search is cut at the near plane: put it at the casters (see docs/pcss.md).
//   sk::PcssFit fit = sk::pcss_fit_near_plane(L, light_view, casters_min, casters_max);
//   if (fit.status == sk::Status::Ok) L = fit.light;  // render the map with L.near_z
//   sk::PcssValue uv = sk::pcss_light_uv_at_near(L);  // uniform light_uv_at_near of glsl/pcss.glsl
//   // CPU estimate (what the shader does per pixel):
//   sk::PcssValue z_r = sk::pcss_linearize_window_depth(receiver_window_z, L.near_z, L.far_z, false);
//   sk::PcssBlocker b = sk::pcss_average_blocker(depths, depth_count, z_r.value, /*bias*/ 0.01f);
//   sk::PcssPolicy policy; policy.map_resolution = 2048.0f;
//   sk::PcssFilter f = sk::pcss_filter(L, z_r.value, b, policy);  // f.blocker_found, f.filter_uv, f.taps
//
// Conventions. Perspective light: z is the eye distance along the light's axis, near_z its near
// plane, size the world width of the (square or disk) emitter, frustum_width = 2 tan(fov/2)
// (frustum width at unit depth; the shadow map spans that width in uv [0,1]). Directional light:
// size is the angular diameter (radians, the sun is ~0.0093), frustum_width the world width of the
// orthographic frustum, z the distance along the light direction from the light's view origin (as
// pcss_linearize_ortho_window_depth returns it). PcssLight describes the light's shadow frustum, not
// its position: the light's view matrix (the one the map is rendered with) is passed where a
// position is needed. All "width" values are full widths (diameters); a Poisson disk of unit radius
// is scaled by width/2. Stored depth is window depth in [0,1] (what a depth texture returns;
// glDepthRange(0,1) / Vulkan minDepth 0, maxDepth 1), or NDC z with a ClipDepth; reversed-Z is 1 at
// near, 0 at far. The penumbra ratio needs linear depths: (z_r - z_b)/z_b on post-projective
// values is wrong by orders of magnitude (three.js's PCSS example and pboechat/PCSS do that).
// Results: a struct whose first member is `status`; Ok only with finite outputs in their
// documented range; "no blocker" is `blocker_found = false` with Ok; a non-Ok result's `detail`
// names the offending input and the rule ("z_r: not > 0"), a static string, nullptr when Ok.
// Buffers: pcss_average_blocker reads `count` floats; nothing allocates.
// The search region (Apelles eq. 3.20) is where the pyramid from the receiver to the light crosses
// the near plane: with the near plane far in front of the casters it is needlessly wide (near 0.1,
// receiver 40, a 0.5 light and a 60 degree cone: 4.3 times the whole map) and a fixed number of taps
// misses the blockers. pcss_fit_near_plane moves the near plane to the casters; the search width
// is also clamped to max_filter_uv (glsl/pcss.glsl does the same): a blocker farther from the
// receiver than that could only widen the filter beyond its clamp.
//
// Based on:
//   R. Fernando, "Percentage-Closer Soft Shadows", SIGGRAPH 2005 sketch.
//   A. Moschig, "Apelles: A Library for GPU-Based Real-Time Global Illumination", master's thesis, TU Graz (2012), eqs. 3.20 (search width), 3.21 (penumbra), 3.22 (filter width).
//   W. Reeves, D. Salesin, R. Cook, "Rendering Antialiased Shadows with Depth Maps", SIGGRAPH 1987 (PCF).
//
// MIT License. Copyright (c) shadowkit contributors.
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

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
/// Perspective (spot) or orthographic (directional) shadow frustum.
enum class PcssLightType { Perspective, Directional };

/// The light's shadow frustum as PCSS needs it. near_z, far_z and frustum_width are required (the
/// defaults are rejected); size 0 is the hard-shadow limit.
struct PcssLight {
    PcssLightType type = PcssLightType::Perspective;
    float size = 0.0f;           ///< Perspective: emitter width [world]; Directional: angular diameter [rad] in [0, pi). >= 0
    float near_z = 0.0f;         ///< near plane [world] (required). Perspective: > 0; Directional: any finite value
    float far_z = 0.0f;          ///< far plane [world], > near_z (required); +inf allowed for perspective lights
    float frustum_width = 0.0f;  ///< (required) Perspective: 2 tan(fov/2); Directional: ortho width [world]. > 0
};

/// A scalar result (a width, a distance, a uv extent). `value` is 0 unless status is Ok.
struct PcssValue {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    float value = 0.0f;
};

/// The light with its near plane moved to the casters (pcss_fit_near_plane).
struct PcssFit {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    bool raised = false;   ///< false (with Ok): the casters reach the given near plane (or lie beyond far); near_z unchanged
    PcssLight light;       ///< the input light, near_z raised to the casters when `raised`
    float caster_near_z = 0.0f;  ///< nearest depth of the casters' box along the light axis (may be <= 0: behind the light)
};

/// Blocker estimate of one receiver (pcss_average_blocker).
struct PcssBlocker {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    bool blocker_found = false;    ///< false (with Ok): no sample closer than z_r - bias: fully lit
    float average = 0.0f;          ///< mean linear depth of the blocking samples (when blocker_found)
    std::size_t blocker_count = 0; ///< number of blocking samples
};

/// How pcss_filter turns a penumbra into a PCF filter.
struct PcssPolicy {
    float min_filter_uv = 0.0f;     ///< lower clamp of the filter width (0: contact shadows stay hard). >= 0
    float max_filter_uv = 0.05f;    ///< upper clamp of the filter and the search width (large penumbrae cost taps and leak). > 0
    float map_resolution = 0.0f;    ///< shadow-map texels across uv [0,1] (required, > 0)
    int min_taps = 1;
    int max_taps = 64;
    float texels_per_tap = 1.0f;    ///< > 0
};

/// The PCF filter for one receiver (pcss_filter).
struct PcssFilter {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    bool blocker_found = false;   ///< false (with Ok): fully lit, skip the filter (filter_uv 0, taps 0)
    float search_uv = 0.0f;       ///< blocker search width (uv), clamped to max_filter_uv
    float blocker_depth = 0.0f;   ///< average blocker depth (linear), when blocker_found
    float penumbra_width = 0.0f;  ///< on the receiver [world] (Perspective) or along it (Directional), before the clamp
    float filter_uv = 0.0f;       ///< clamped PCF width (uv), in [min_filter_uv, max_filter_uv] when blocker_found
    int taps = 0;                 ///< tap budget for filter_uv, in [min_taps, max_taps] when blocker_found
};

namespace detail {
inline bool pcss_fits_float(double v) {
    return std::isfinite(v) && std::fabs(v) <= static_cast<double>(std::numeric_limits<float>::max());
}
inline PcssValue pcss_value(double v) {
    PcssValue r;
    if (!pcss_fits_float(v)) { r.status = Status::Overflow; r.detail = "value: beyond float range"; return r; }
    r.value = static_cast<float>(v);
    r.status = Status::Ok;
    return r;
}
// `why`: where the status came from, a static string.
inline PcssValue pcss_error(Status s, const char* why) {
    PcssValue r;
    r.status = s;
    r.detail = why;
    return r;
}
inline Status pcss_fail(const char*& why, Status s, const char* what) {
    why = what;
    return s;
}
// Perspective planes: near finite > 0, far > near (+inf allowed).
inline Status pcss_check_planes(float n, float f, const char*& why) {
    if (!std::isfinite(n)) return pcss_fail(why, Status::NonFinite, "near_z: NaN or Inf");
    if (std::isnan(f) || f == -std::numeric_limits<float>::infinity()) return pcss_fail(why, Status::NonFinite, "far_z: NaN or -Inf");
    if (!(n > 0.0f)) return pcss_fail(why, Status::InvalidArgument, "near_z: not > 0");
    if (!(f > n)) return pcss_fail(why, Status::InvalidArgument, "far_z: not > near_z");
    return Status::Ok;
}
// pcss_validate_light, with where a non-Ok status came from.
inline Status pcss_check_light(const PcssLight& L, const char*& why) {
    if (!std::isfinite(L.size)) return pcss_fail(why, Status::NonFinite, "size: NaN or Inf");
    if (!std::isfinite(L.near_z)) return pcss_fail(why, Status::NonFinite, "near_z: NaN or Inf");
    if (!std::isfinite(L.frustum_width)) return pcss_fail(why, Status::NonFinite, "frustum_width: NaN or Inf");
    if (std::isnan(L.far_z) || L.far_z == -std::numeric_limits<float>::infinity())
        return pcss_fail(why, Status::NonFinite, "far_z: NaN or -Inf");
    if (L.size < 0.0f) return pcss_fail(why, Status::InvalidArgument, "size: < 0");
    if (!(L.frustum_width > 0.0f)) return pcss_fail(why, Status::InvalidArgument, "frustum_width: not > 0");
    if (!(L.far_z > L.near_z)) return pcss_fail(why, Status::InvalidArgument, "far_z: not > near_z");
    if (L.type == PcssLightType::Perspective)
        return L.near_z > 0.0f ? Status::Ok : pcss_fail(why, Status::InvalidArgument, "near_z: not > 0 (perspective)");
    if (L.type == PcssLightType::Directional) {
        if (std::isinf(L.far_z)) return pcss_fail(why, Status::NonFinite, "far_z: +inf (directional)");
        return static_cast<double>(L.size) < 3.14159265358979323846
                   ? Status::Ok
                   : pcss_fail(why, Status::InvalidArgument, "size: angular diameter not < pi (directional)");
    }
    return pcss_fail(why, Status::InvalidArgument, "type: unknown PcssLightType");
}
} // namespace detail

/// Checks a PcssLight: NonFinite for NaN/Inf size, near_z or frustum_width, a NaN or -inf far_z, or
/// an infinite far_z of a directional light; InvalidArgument for size < 0, frustum_width <= 0,
/// far_z <= near_z, a perspective near_z <= 0, a directional size >= pi, an unknown type. Ok otherwise.
inline Status pcss_validate_light(const PcssLight& L) {
    const char* why = nullptr;
    return detail::pcss_check_light(L, why);
}

// ------------------------------------------------------------------------------------------------
// Depth linearization
// ------------------------------------------------------------------------------------------------

/// Window depth (clamped to [0,1]) -> eye distance d along a perspective light's axis.
/// Standard: z_w = f (d - n) / (d (f - n))  ->  d = f n / (n + (1 - z_w) (f - n));  f = +inf: d = n / (1 - z_w).
/// Reversed: z_w = n (f - d) / (d (f - n))  ->  d = f n / (n + z_w (f - n));  f = +inf: d = n / z_w.
/// The same for GL ([-1,1] clip) and D3D/Vulkan ([0,1] clip) with the default depth range. Ok: d in
/// [n, f]. NonFinite for NaN/Inf z_w or bad planes (as pcss_validate_light), InvalidArgument for
/// near_z <= 0 or far_z <= near_z, Overflow for the window depth of infinity (f = +inf: a cleared
/// texel, no surface) or a distance beyond float.
inline PcssValue pcss_linearize_window_depth(float z_w, float near_z, float far_z, bool reversed_z) {
    const char* why = nullptr;
    const Status s = detail::pcss_check_planes(near_z, far_z, why);
    if (s != Status::Ok) return detail::pcss_error(s, why);
    if (!std::isfinite(z_w)) return detail::pcss_error(Status::NonFinite, "z_w: NaN or Inf");
    const double z = !(z_w > 0.0f) ? 0.0 : (z_w > 1.0f ? 1.0 : static_cast<double>(z_w));  // -0 -> +0
    const double dn = static_cast<double>(near_z), df = static_cast<double>(far_z);
    double d;
    if (std::isinf(df))
        d = reversed_z ? dn / z : dn / (1.0 - z);
    else
        d = reversed_z ? df * dn / (dn + z * (df - dn)) : df * dn / (dn + (1.0 - z) * (df - dn));
    return detail::pcss_value(d);
}

/// Eye distance d (clamped to [n, f]; +inf is the far plane or infinity) -> window depth in [0,1],
/// the inverse of pcss_linearize_window_depth. NonFinite for NaN or -inf d; planes as there.
inline PcssValue pcss_delinearize_window_depth(float d, float near_z, float far_z, bool reversed_z) {
    const char* why = nullptr;
    const Status s = detail::pcss_check_planes(near_z, far_z, why);
    if (s != Status::Ok) return detail::pcss_error(s, why);
    if (std::isnan(d) || d == -std::numeric_limits<float>::infinity()) return detail::pcss_error(Status::NonFinite, "d: NaN or -Inf");
    const double dn = static_cast<double>(near_z), df = static_cast<double>(far_z);
    const double dd = static_cast<double>(d) < dn ? dn : (static_cast<double>(d) > df ? df : static_cast<double>(d));
    double z;
    if (std::isinf(df))
        z = std::isinf(dd) ? (reversed_z ? 0.0 : 1.0) : (reversed_z ? dn / dd : 1.0 - dn / dd);
    else
        z = reversed_z ? dn * (df - dd) / (dd * (df - dn)) : df * (dd - dn) / (dd * (df - dn));
    return detail::pcss_value(z < 0.0 ? 0.0 : (z > 1.0 ? 1.0 : z));
}

/// NDC z (after the perspective divide, clamped to the clip range) -> eye distance. ZeroToOne: NDC z
/// is the window depth. NegativeOneToOne (glm::perspectiveRH_NO, glFrustum): ndc = (f+n)/(f-n) -
/// 2 f n / ((f-n) d), so d = 2 f n / ((f + n) - ndc (f - n)), f = +inf: d = 2 n / (1 - ndc) (computed
/// from ndc directly, without the 0.5 ndc + 0.5 step that loses bits near 1). Reversed with
/// NegativeOneToOne means ndc_reversed = -ndc; prefer ZeroToOne for reversed-Z. Statuses as
/// pcss_linearize_window_depth; InvalidArgument for an unknown clip depth.
inline PcssValue pcss_linearize_ndc_depth(float ndc, float near_z, float far_z, ClipDepth clip, bool reversed_z) {
    if (clip == ClipDepth::ZeroToOne) return pcss_linearize_window_depth(ndc, near_z, far_z, reversed_z);
    if (clip != ClipDepth::NegativeOneToOne) return detail::pcss_error(Status::InvalidArgument, "clip: unknown ClipDepth");
    const char* why = nullptr;
    const Status s = detail::pcss_check_planes(near_z, far_z, why);
    if (s != Status::Ok) return detail::pcss_error(s, why);
    if (!std::isfinite(ndc)) return detail::pcss_error(Status::NonFinite, "ndc: NaN or Inf");
    double z = reversed_z ? -static_cast<double>(ndc) : static_cast<double>(ndc);
    z = z < -1.0 ? -1.0 : (z > 1.0 ? 1.0 : z);
    const double dn = static_cast<double>(near_z), df = static_cast<double>(far_z);
    const double d = std::isinf(df) ? 2.0 * dn / (1.0 - z) : 2.0 * df * dn / ((df + dn) - z * (df - dn));
    return detail::pcss_value(d);
}

/// Orthographic (directional) lights store linear depth: d = n + z_w (f - n) with z_w clamped to
/// [0,1] (reversed: z_w -> 1 - z_w). near_z, far_z finite, far_z > near_z. NonFinite for NaN/Inf,
/// InvalidArgument for far_z <= near_z, Overflow beyond float.
inline PcssValue pcss_linearize_ortho_window_depth(float z_w, float near_z, float far_z, bool reversed_z) {
    if (!std::isfinite(z_w) || !std::isfinite(near_z) || !std::isfinite(far_z))
        return detail::pcss_error(Status::NonFinite, !std::isfinite(z_w) ? "z_w: NaN or Inf"
                                                     : (!std::isfinite(near_z) ? "near_z: NaN or Inf" : "far_z: NaN or Inf"));
    if (!(far_z > near_z)) return detail::pcss_error(Status::InvalidArgument, "far_z: not > near_z");
    const double zc = z_w < 0.0f ? 0.0 : (z_w > 1.0f ? 1.0 : static_cast<double>(z_w));
    const double z = reversed_z ? 1.0 - zc : zc;
    return detail::pcss_value(static_cast<double>(near_z) + z * (static_cast<double>(far_z) - static_cast<double>(near_z)));
}

// ------------------------------------------------------------------------------------------------
// PCSS geometry (perspective light; widths in world units)
// ------------------------------------------------------------------------------------------------

/// Blocker search width on the near plane (Apelles eq. 3.20): w_light (z_r - z_n) / z_r, the
/// intersection of the near plane with the pyramid from the receiver to the light (similar
/// triangles); 0 when the receiver is at or in front of the near plane. light_width finite >= 0,
/// z_r, z_n finite > 0. NonFinite for NaN/Inf, InvalidArgument outside the ranges.
inline PcssValue pcss_search_width(float light_width, float z_r, float z_n) {
    if (!std::isfinite(light_width) || !std::isfinite(z_r) || !std::isfinite(z_n))
        return detail::pcss_error(Status::NonFinite, !std::isfinite(light_width) ? "light_width: NaN or Inf"
                                                     : (!std::isfinite(z_r) ? "z_r: NaN or Inf" : "z_n: NaN or Inf"));
    if (!(light_width >= 0.0f) || !(z_r > 0.0f) || !(z_n > 0.0f))
        return detail::pcss_error(Status::InvalidArgument, !(light_width >= 0.0f) ? "light_width: < 0" : (!(z_r > 0.0f) ? "z_r: not > 0" : "z_n: not > 0"));
    if (!(z_r > z_n)) return detail::pcss_value(0.0);
    return detail::pcss_value(static_cast<double>(light_width) * (static_cast<double>(z_r) - static_cast<double>(z_n)) /
                              static_cast<double>(z_r));
}

/// Penumbra width on the receiver (Fernando 2005; Apelles eq. 3.21): w_light (z_r - z_b) / z_b,
/// for a planar blocker at z_b and receiver at z_r parallel to the light; 0 when z_b >= z_r
/// (blocker at the receiver: contact, hard shadow). light_width finite >= 0, z_r, z_b finite > 0.
/// NonFinite for NaN/Inf, InvalidArgument outside the ranges, Overflow beyond float (z_b -> 0).
inline PcssValue pcss_penumbra_width(float light_width, float z_r, float z_b) {
    if (!std::isfinite(light_width) || !std::isfinite(z_r) || !std::isfinite(z_b))
        return detail::pcss_error(Status::NonFinite, !std::isfinite(light_width) ? "light_width: NaN or Inf"
                                                     : (!std::isfinite(z_r) ? "z_r: NaN or Inf" : "z_b: NaN or Inf"));
    if (!(light_width >= 0.0f) || !(z_r > 0.0f) || !(z_b > 0.0f))
        return detail::pcss_error(Status::InvalidArgument, !(light_width >= 0.0f) ? "light_width: < 0" : (!(z_r > 0.0f) ? "z_r: not > 0" : "z_b: not > 0"));
    if (!(z_r > z_b) || light_width == 0.0f) return detail::pcss_value(0.0);
    return detail::pcss_value(static_cast<double>(light_width) * (static_cast<double>(z_r) - static_cast<double>(z_b)) /
                              static_cast<double>(z_b));
}

/// Filter width on the near plane (Apelles eq. 3.22): w_penumbra z_n / z_r. (The thesis's shader
/// passes w_penumbra itself to PCF, too wide by z_r / z_n.) w_penumbra finite >= 0, z_r, z_n finite
/// > 0. NonFinite for NaN/Inf, InvalidArgument outside the ranges, Overflow beyond float.
inline PcssValue pcss_filter_width(float w_penumbra, float z_r, float z_n) {
    if (!std::isfinite(w_penumbra) || !std::isfinite(z_r) || !std::isfinite(z_n))
        return detail::pcss_error(Status::NonFinite, !std::isfinite(w_penumbra) ? "w_penumbra: NaN or Inf"
                                                     : (!std::isfinite(z_r) ? "z_r: NaN or Inf" : "z_n: NaN or Inf"));
    if (!(w_penumbra >= 0.0f) || !(z_r > 0.0f) || !(z_n > 0.0f))
        return detail::pcss_error(Status::InvalidArgument, !(w_penumbra >= 0.0f) ? "w_penumbra: < 0" : (!(z_r > 0.0f) ? "z_r: not > 0" : "z_n: not > 0"));
    return detail::pcss_value(static_cast<double>(w_penumbra) * static_cast<double>(z_n) / static_cast<double>(z_r));
}

/// A world width at eye distance z of a perspective light, in shadow-map uv: width / (z frustum_width).
/// width finite >= 0, z and frustum_width finite > 0. NonFinite, InvalidArgument, Overflow accordingly.
inline PcssValue pcss_width_to_uv(float width, float z, float frustum_width) {
    if (!std::isfinite(width) || !std::isfinite(z) || !std::isfinite(frustum_width))
        return detail::pcss_error(Status::NonFinite, !std::isfinite(width) ? "width: NaN or Inf"
                                                     : (!std::isfinite(z) ? "z: NaN or Inf" : "frustum_width: NaN or Inf"));
    if (!(width >= 0.0f) || !(z > 0.0f) || !(frustum_width > 0.0f))
        return detail::pcss_error(Status::InvalidArgument, !(width >= 0.0f) ? "width: < 0" : (!(z > 0.0f) ? "z: not > 0" : "frustum_width: not > 0"));
    return detail::pcss_value(static_cast<double>(width) / (static_cast<double>(z) * static_cast<double>(frustum_width)));
}

/// Directional light of angular diameter theta: a blocker at distance h above the receiver casts a
/// penumbra 2 tan(theta/2) h wide. Search width = 2 tan(theta/2) (z_r - z_n) (blockers between the
/// ortho near plane and the receiver; 0 when z_r <= z_n); in uv it divides by the ortho width (no
/// perspective scaling, so the filter width is the penumbra width). angular_diameter in [0, pi),
/// z_r, z_n finite. NonFinite for NaN/Inf, InvalidArgument outside, Overflow beyond float.
inline PcssValue pcss_search_width_directional(float angular_diameter, float z_r, float z_n) {
    if (!std::isfinite(angular_diameter) || !std::isfinite(z_r) || !std::isfinite(z_n))
        return detail::pcss_error(Status::NonFinite, !std::isfinite(angular_diameter) ? "angular_diameter: NaN or Inf"
                                                     : (!std::isfinite(z_r) ? "z_r: NaN or Inf" : "z_n: NaN or Inf"));
    if (!(angular_diameter >= 0.0f && static_cast<double>(angular_diameter) < 3.14159265358979323846))
        return detail::pcss_error(Status::InvalidArgument, "angular_diameter: outside [0, pi)");
    if (!(z_r > z_n)) return detail::pcss_value(0.0);
    return detail::pcss_value(2.0 * std::tan(0.5 * static_cast<double>(angular_diameter)) *
                              (static_cast<double>(z_r) - static_cast<double>(z_n)));
}

/// Directional penumbra 2 tan(theta/2) (z_r - z_b), 0 when z_b >= z_r. Ranges and statuses as
/// pcss_search_width_directional.
inline PcssValue pcss_penumbra_width_directional(float angular_diameter, float z_r, float z_b) {
    return pcss_search_width_directional(angular_diameter, z_r, z_b);
}

/// The light's width in uv measured on the near plane: size / (near_z frustum_width) (perspective),
/// the uniform `light_uv_at_near` of glsl/pcss.glsl. Directional: 2 tan(theta/2) (far_z - near_z) /
/// frustum_width, the uniform `light_uv_per_depth` (uv of penumbra per unit of window depth).
/// Statuses of pcss_validate_light; Overflow beyond float.
inline PcssValue pcss_light_uv_at_near(const PcssLight& L) {
    const char* why = nullptr;
    const Status s = detail::pcss_check_light(L, why);
    if (s != Status::Ok) return detail::pcss_error(s, why);
    if (L.type == PcssLightType::Directional)
        return detail::pcss_value(2.0 * std::tan(0.5 * static_cast<double>(L.size)) *
                                  (static_cast<double>(L.far_z) - static_cast<double>(L.near_z)) /
                                  static_cast<double>(L.frustum_width));
    return detail::pcss_value(static_cast<double>(L.size) / (static_cast<double>(L.near_z) * static_cast<double>(L.frustum_width)));
}

/// Width of the blocker search square in uv for a receiver at linear depth z_r (not clamped; see
/// pcss_filter for the clamp). Perspective: search width / (near_z frustum_width); directional:
/// search width / ortho width; 0 for a receiver at or in front of the near plane. z_r finite
/// (perspective: > 0). Statuses of pcss_validate_light, NonFinite / InvalidArgument for z_r,
/// Overflow beyond float.
inline PcssValue pcss_search_uv(const PcssLight& L, float z_r) {
    const char* why = nullptr;
    const Status s = detail::pcss_check_light(L, why);
    if (s != Status::Ok) return detail::pcss_error(s, why);
    if (!std::isfinite(z_r)) return detail::pcss_error(Status::NonFinite, "z_r: NaN or Inf");
    if (L.type == PcssLightType::Directional) {
        const PcssValue w = pcss_search_width_directional(L.size, z_r, L.near_z);
        if (w.status != Status::Ok) return w;
        return detail::pcss_value(static_cast<double>(w.value) / static_cast<double>(L.frustum_width));
    }
    if (!(z_r > 0.0f)) return detail::pcss_error(Status::InvalidArgument, "z_r: not > 0");
    if (!(z_r > L.near_z)) return detail::pcss_value(0.0);
    return detail::pcss_value(static_cast<double>(L.size) * (static_cast<double>(z_r) - static_cast<double>(L.near_z)) /
                              (static_cast<double>(z_r) * static_cast<double>(L.near_z) * static_cast<double>(L.frustum_width)));
}

/// Moves the light's near plane to its casters: the blocker search is cut where the
/// receiver-to-light pyramid crosses the near plane, and no blocker lies in front of the nearest
/// caster, so near_z = that depth gives the smallest search region that still holds every blocker
/// (and the best depth precision). Depth of the casters' axis-aligned box (casters_min, casters_max,
/// world space) is the nearest of its 8 corners through light_view (the view matrix the map is
/// rendered with; the light looks down -z; depth = -z). Perspective: near_z = 0.99 x that depth;
/// directional: that depth minus 1% of (far_z - depth). The near plane is only ever raised (raised =
/// false with Ok when the casters reach the given near plane, lie behind the light or beyond far).
/// Render the shadow map with the returned near_z, and pass it to glsl/pcss.glsl.
/// Statuses of pcss_validate_light; NonFinite for a NaN/Inf in the matrix or box; InvalidArgument
/// for a singular light_view (the zero matrix, a rank-deficient 3x3 part) or casters_min > casters_max
/// in a coordinate.
inline PcssFit pcss_fit_near_plane(const PcssLight& L, const glm::mat4& light_view, glm::vec3 casters_min,
                                   glm::vec3 casters_max) {
    PcssFit fit;
    fit.light = L;
    fit.status = detail::pcss_check_light(L, fit.detail);
    if (fit.status != Status::Ok) return fit;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(light_view[c][r])) { fit.status = Status::NonFinite; fit.detail = "light_view: NaN or Inf"; return fit; }
    {  // a view matrix is invertible: a zero or rank-deficient upper 3x3 maps casters onto a plane or a point
        double a[3][3], len2[3] = {0.0, 0.0, 0.0};
        for (int c = 0; c < 3; ++c)
            for (int r = 0; r < 3; ++r) {
                a[c][r] = static_cast<double>(light_view[c][r]);
                len2[c] += a[c][r] * a[c][r];
            }
        const double det = a[0][0] * (a[1][1] * a[2][2] - a[2][1] * a[1][2]) - a[1][0] * (a[0][1] * a[2][2] - a[2][1] * a[0][2]) +
                           a[2][0] * (a[0][1] * a[1][2] - a[1][1] * a[0][2]);
        if (!(std::fabs(det) > 1e-12 * std::sqrt(len2[0] * len2[1] * len2[2]))) {
            fit.status = Status::InvalidArgument;
            fit.detail = "light_view: singular upper 3x3";
            return fit;
        }
    }
    for (int i = 0; i < 3; ++i) {
        if (!std::isfinite(casters_min[i]) || !std::isfinite(casters_max[i])) {
            fit.status = Status::NonFinite;
            fit.detail = !std::isfinite(casters_min[i]) ? "casters_min: NaN or Inf" : "casters_max: NaN or Inf";
            return fit;
        }
        if (!(casters_min[i] <= casters_max[i])) { fit.status = Status::InvalidArgument; fit.detail = "casters_min: > casters_max"; return fit; }
    }
    double nearest = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 8; ++i) {
        const glm::dvec4 p((i & 1) ? casters_max.x : casters_min.x, (i & 2) ? casters_max.y : casters_min.y,
                           (i & 4) ? casters_max.z : casters_min.z, 1.0);
        const double depth = -(glm::dmat4(light_view) * p).z;
        if (depth < nearest) nearest = depth;
    }
    if (!detail::pcss_fits_float(nearest)) { fit.status = Status::Overflow; fit.detail = "casters_min, casters_max: depth beyond float"; return fit; }
    fit.caster_near_z = static_cast<float>(nearest);
    const double n = static_cast<double>(L.near_z), f = static_cast<double>(L.far_z);
    const double candidate = L.type == PcssLightType::Perspective ? 0.99 * nearest : nearest - 0.01 * (f - nearest);
    const float c = static_cast<float>(candidate);
    if (candidate > n && nearest < f && c > L.near_z && c < L.far_z) {
        fit.light.near_z = c;
        fit.raised = true;
    }
    return fit;
}

// ------------------------------------------------------------------------------------------------
// Average blocker
// ------------------------------------------------------------------------------------------------

/// Mean of the linear depths closer to the light than the receiver (d < z_r - bias).
/// `linear_depths` holds `count` floats (read only; null only with count 0): the depths of the
/// search taps, linearized. Samples that are NaN, +-Inf or <= 0 (outside the map, cleared texels)
/// are ignored. blocker_found = false (with Ok) when none blocks. NonFinite for NaN/Inf z_r or bias,
/// InvalidArgument for a null array with count > 0.
inline PcssBlocker pcss_average_blocker(const float* linear_depths, std::size_t count, float z_r, float bias) {
    PcssBlocker b;
    if (!std::isfinite(z_r) || !std::isfinite(bias)) {
        b.status = Status::NonFinite;
        b.detail = !std::isfinite(z_r) ? "z_r: NaN or Inf" : "bias: NaN or Inf";
        return b;
    }
    if (linear_depths == nullptr && count > 0) { b.status = Status::InvalidArgument; b.detail = "linear_depths: null with count > 0"; return b; }
    const double limit = static_cast<double>(z_r) - static_cast<double>(bias);
    double sum = 0.0;
    for (std::size_t i = 0; i < count; ++i) {
        const float d = linear_depths[i];
        if (!std::isfinite(d) || !(d > 0.0f)) continue;
        if (static_cast<double>(d) < limit) {
            sum += static_cast<double>(d);
            ++b.blocker_count;
        }
    }
    if (b.blocker_count > 0) {
        b.blocker_found = true;
        b.average = static_cast<float>(sum / static_cast<double>(b.blocker_count));
    }
    b.status = Status::Ok;
    return b;
}

// ------------------------------------------------------------------------------------------------
// Filter clamp and tap budget
// ------------------------------------------------------------------------------------------------

/// Clamps a filter width (uv) into [min_uv, max_uv]; NaN filter_uv -> min_uv (hard shadow), +inf ->
/// max_uv. min_uv, max_uv finite with 0 <= min_uv <= max_uv (NonFinite / InvalidArgument otherwise).
inline PcssValue pcss_clamp_filter(float filter_uv, float min_uv, float max_uv) {
    if (!std::isfinite(min_uv) || !std::isfinite(max_uv))
        return detail::pcss_error(Status::NonFinite, !std::isfinite(min_uv) ? "min_uv: NaN or Inf" : "max_uv: NaN or Inf");
    if (!(min_uv >= 0.0f) || !(max_uv >= min_uv))
        return detail::pcss_error(Status::InvalidArgument, !(min_uv >= 0.0f) ? "min_uv: < 0" : "max_uv: < min_uv");
    if (std::isnan(filter_uv) || filter_uv < min_uv) return detail::pcss_value(static_cast<double>(min_uv));
    if (filter_uv > max_uv) return detail::pcss_value(static_cast<double>(max_uv));
    return detail::pcss_value(static_cast<double>(filter_uv));
}

/// Tap budget: enough taps to put one tap per `texels_per_tap` x `texels_per_tap` texels of the
/// filter disk, ceil(pi (D/2)^2 / s^2) for a filter of diameter D texels, clamped to
/// [max(min_taps, 1), max(max_taps, min_taps, 1)]. total: a filter narrower than one texel, NaN or
/// negative gets the lower bound, +inf the upper; a NaN, Inf or non-positive texels_per_tap counts
/// as 1. Monotone non-decreasing in D. Same policy as sk_pcss_tap_budget in glsl/pcss.glsl.
inline int pcss_tap_budget(float filter_texels, int min_taps, int max_taps, float texels_per_tap = 1.0f) {
    const int lo = min_taps < 1 ? 1 : min_taps;
    const int hi = max_taps < lo ? lo : max_taps;
    if (std::isnan(filter_texels) || !(filter_texels > 1.0f)) return lo;
    const double s = std::isfinite(texels_per_tap) && texels_per_tap > 0.0f ? static_cast<double>(texels_per_tap) : 1.0;
    const double r = 0.5 * static_cast<double>(filter_texels) / s;
    const double want = std::ceil(3.14159265358979323846 * r * r);
    if (!(want < static_cast<double>(hi))) return hi;
    return want < static_cast<double>(lo) ? lo : static_cast<int>(want);
}

// ------------------------------------------------------------------------------------------------
// Whole estimate
// ------------------------------------------------------------------------------------------------

/// Penumbra -> filter for a receiver at linear depth z_r and the blocker estimate b (an Ok result
/// of pcss_average_blocker). Light size 0 gives filter_uv == min_filter_uv exactly (a hard shadow
/// with the default 0), a blocker at the receiver gives 0 penumbra, a blocker depth tending to 0 a
/// penumbra clamped to max_filter_uv. No blocker: Ok with blocker_found = false, filter_uv 0, taps 0.
/// search_uv is min(pcss_search_uv, max_filter_uv). Statuses of pcss_validate_light; NonFinite for a
/// NaN/Inf z_r; InvalidArgument for z_r <= 0 (perspective), a b that is not Ok, a blocker depth that
/// is not finite (or <= 0 for a perspective light), a policy outside its ranges; Overflow when the
/// penumbra is beyond float.
inline PcssFilter pcss_filter(const PcssLight& L, float z_r, const PcssBlocker& b, const PcssPolicy& p) {
    PcssFilter out;
    out.status = detail::pcss_check_light(L, out.detail);
    if (out.status != Status::Ok) return out;
    if (!std::isfinite(z_r) || !std::isfinite(p.min_filter_uv) || !std::isfinite(p.max_filter_uv) ||
        !std::isfinite(p.map_resolution) || !std::isfinite(p.texels_per_tap)) {
        out.status = Status::NonFinite;
        out.detail = !std::isfinite(z_r) ? "z_r: NaN or Inf"
                     : (!std::isfinite(p.min_filter_uv) ? "min_filter_uv: NaN or Inf"
                     : (!std::isfinite(p.max_filter_uv) ? "max_filter_uv: NaN or Inf"
                     : (!std::isfinite(p.map_resolution) ? "map_resolution: NaN or Inf" : "texels_per_tap: NaN or Inf")));
        return out;
    }
    const bool persp = L.type == PcssLightType::Perspective;
    if ((persp && !(z_r > 0.0f)) || p.min_filter_uv < 0.0f || !(p.max_filter_uv >= p.min_filter_uv) ||
        !(p.max_filter_uv > 0.0f) || !(p.map_resolution > 0.0f) || !(p.texels_per_tap > 0.0f) || b.status != Status::Ok) {
        out.status = Status::InvalidArgument;
        out.detail = persp && !(z_r > 0.0f) ? "z_r: not > 0"
                     : (p.min_filter_uv < 0.0f ? "min_filter_uv: < 0"
                     : (!(p.max_filter_uv >= p.min_filter_uv) || !(p.max_filter_uv > 0.0f) ? "max_filter_uv: not > 0 or < min_filter_uv"
                     : (!(p.map_resolution > 0.0f) ? "map_resolution: not > 0"
                     : (!(p.texels_per_tap > 0.0f) ? "texels_per_tap: not > 0" : "b: status not Ok"))));
        return out;
    }
    const PcssValue search = pcss_search_uv(L, z_r);
    if (search.status != Status::Ok) { out.status = search.status; out.detail = search.detail; return out; }
    out.search_uv = search.value < p.max_filter_uv ? search.value : p.max_filter_uv;
    if (!b.blocker_found) return out;  // Ok, fully lit
    if (!std::isfinite(b.average) || (persp && !(b.average > 0.0f))) {
        out = PcssFilter{};
        out.status = Status::InvalidArgument;
        out.detail = "b: average not finite (or not > 0, perspective)";
        return out;
    }
    double filter;
    if (persp) {
        const PcssValue pen = pcss_penumbra_width(L.size, z_r, b.average);
        if (pen.status != Status::Ok) { out = PcssFilter{}; out.status = pen.status; out.detail = pen.detail; return out; }
        out.penumbra_width = pen.value;
        // eq. 3.22 then near-plane width -> uv; equal to w_penumbra / (z_r frustum_width).
        filter = static_cast<double>(pen.value) / (static_cast<double>(z_r) * static_cast<double>(L.frustum_width));
    } else {
        const PcssValue pen = pcss_penumbra_width_directional(L.size, z_r, b.average);
        if (pen.status != Status::Ok) { out = PcssFilter{}; out.status = pen.status; out.detail = pen.detail; return out; }
        out.penumbra_width = pen.value;
        filter = static_cast<double>(pen.value) / static_cast<double>(L.frustum_width);
    }
    out.blocker_found = true;
    out.blocker_depth = b.average;
    const double lo = static_cast<double>(p.min_filter_uv), hi = static_cast<double>(p.max_filter_uv);
    out.filter_uv = static_cast<float>(filter < lo ? lo : (filter > hi ? hi : filter));
    out.taps = pcss_tap_budget(out.filter_uv * p.map_resolution, p.min_taps, p.max_taps, p.texels_per_tap);
    return out;
}

/// Penumbra width from two window depths of a perspective light: linearizes both first, then
/// eq. 3.21. (Using the window depths directly in (z_r - z_b) / z_b is the three.js bug.) Statuses
/// of pcss_linearize_window_depth and pcss_penumbra_width.
inline PcssValue pcss_penumbra_width_from_window_depth(float light_width, float receiver_window, float blocker_window,
                                                       float near_z, float far_z, bool reversed_z) {
    const PcssValue zr = pcss_linearize_window_depth(receiver_window, near_z, far_z, reversed_z);
    if (zr.status != Status::Ok) return zr;
    const PcssValue zb = pcss_linearize_window_depth(blocker_window, near_z, far_z, reversed_z);
    if (zb.status != Status::Ok) return zb;
    return pcss_penumbra_width(light_width, zr.value, zb.value);
}

} // namespace shadowkit
