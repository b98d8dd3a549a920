// shadowkit/pcss.hpp - percentage-closer soft shadows: blocker-search region, average blocker
// depth, penumbra width, PCF filter size, depth linearization, filter clamp and a tap budget.
//
// USAGE
//   #include <shadowkit/pcss.hpp>
//   using namespace shadowkit;
//   PcssLight L;                                   // perspective (spot) light
//   L.size = 0.5f; L.near = 0.1f; L.far = 50.0f; L.frustum_width = 2.0f * std::tan(0.5f * fov);
//   float z_r = linearize_window_depth(receiver_window_z, L.near, L.far, /*reversed_z*/ false);
//   float search_uv = pcss_search_uv(L, z_r);                  // width of the blocker search square
//   // ... read depths in that region, linearize them, then:
//   PcssBlocker b = pcss_average_blocker(depths, count, z_r, /*bias*/ 0.01f);
//   PcssFilter  f = pcss_filter(L, z_r, b, PcssPolicy{});    // f.filter_uv, f.taps; f.status
//   // GLSL: glsl/pcss.glsl takes light_uv_at_near = pcss_light_uv_at_near(L).
//
// Conventions. Perspective light: z is the eye distance along the light's axis, z_n its near
// plane, light.size the world width of the (square or disk) emitter, frustum_width = 2 tan(fov/2)
// (frustum width at unit depth; the shadow map spans that width in uv [0,1]). Directional light:
// light.size is the angular diameter (radians, the sun is ~0.0093), frustum_width the world width of
// the orthographic frustum, z the distance along the light direction from the light's view origin
// (as linearize_ortho_window_depth returns it).
// All "width" values are full widths (diameters); a Poisson disk of unit radius is scaled by width/2.
// Stored depth is "window depth" in [0,1] (what a depth texture returns; glDepthRange(0,1) /
// Vulkan minDepth 0, maxDepth 1), or NDC z with a ClipDepth; reversed-Z is 1 at near, 0 at far.
// The penumbra ratio needs linear depths: (z_r - z_b)/z_b on post-projective values is wrong by
// orders of magnitude (three.js's PCSS example and pboechat/PCSS do that); linearize first.
//
// Based on:
//   R. Fernando, "Percentage-Closer Soft Shadows", SIGGRAPH 2005 sketch.
//   M. Gerlach (Apelles thesis, 2010), eqs. 3.20 (search width), 3.21 (penumbra), 3.22 (filter width).
//   W. Reeves, D. Salesin, R. Cook, "Rendering Antialiased Shadows with Depth Maps", SIGGRAPH 1987 (PCF).
//
// MIT License. Copyright (c) shadowkit contributors.
#pragma once

#include <cmath>
#include <cstddef>
#include <limits>

namespace shadowkit {

// Shared with other shadowkit headers; the guard lets any of them be included together.
#ifndef SHADOWKIT_CLIP_DEPTH_DEFINED
#define SHADOWKIT_CLIP_DEPTH_DEFINED
/// Clip-space depth range: OpenGL default [-1, 1] or D3D/Vulkan/glClipControl [0, 1].
enum class ClipDepth { NegativeOneToOne, ZeroToOne };
#endif

enum class PcssLightType { Perspective, Directional };

struct PcssLight {
    PcssLightType type = PcssLightType::Perspective;
    float size = 0.0f;           // Perspective: emitter width [world]; Directional: angular diameter [rad]. [Limit: >= 0]
    float near = 0.1f;           // near plane distance [world]. Perspective: > 0
    float far = 100.0f;          // far plane distance [world], > near; +Inf allowed for perspective lights
    float frustum_width = 1.0f;  // Perspective: 2 tan(fov/2); Directional: ortho width [world]. [Limit: > 0]
};

enum class PcssStatus {
    Ok,
    NoBlocker,       // nothing closer than the receiver in the search region: fully lit, skip the filter
    InvalidArgument  // NaN/Inf where a finite value is needed, size < 0, near/far/frustum invalid
};

// ------------------------------------------------------------------------------------------------
// Depth linearization (perspective lights)
// ------------------------------------------------------------------------------------------------

// Window depth (in [0,1]) -> eye distance d along the light's axis.
// Standard: z_w = f (d - n) / (d (f - n))  ->  d = f n / (n + (1 - z_w) (f - n));  f = +Inf: d = n / (1 - z_w).
// Reversed: z_w = n (f - d) / (d (f - n))  ->  d = f n / (n + z_w (f - n));  f = +Inf: d = n / z_w.
// The same for GL ([-1,1] clip) and D3D/Vulkan ([0,1] clip) with the default depth range.
// z_w is clamped to [0,1]; the far end gives f (+Inf with an infinite far plane). NaN -> NaN.
inline float linearize_window_depth(float z_w, float n, float f, bool reversed_z) {
    if (std::isnan(z_w)) return z_w;
    const double z = !(z_w > 0.0f) ? 0.0 : (z_w > 1.0f ? 1.0 : double(z_w));  // -0 -> +0
    const double dn = double(n), df = double(f);
    double d;
    if (std::isinf(df))
        d = reversed_z ? dn / z : dn / (1.0 - z);
    else
        d = reversed_z ? df * dn / (dn + z * (df - dn)) : df * dn / (dn + (1.0 - z) * (df - dn));
    return static_cast<float>(d);
}

// Eye distance d -> window depth, the inverse of linearize_window_depth (d clamped to [n, f]).
inline float delinearize_window_depth(float d, float n, float f, bool reversed_z) {
    if (std::isnan(d)) return d;
    const double dn = double(n), df = double(f);
    const double dd = double(d) < dn ? dn : (double(d) > df ? df : double(d));
    double z;
    if (std::isinf(df))
        z = std::isinf(dd) ? (reversed_z ? 0.0 : 1.0) : (reversed_z ? dn / dd : 1.0 - dn / dd);
    else
        z = reversed_z ? dn * (df - dd) / (dd * (df - dn)) : df * (dd - dn) / (dd * (df - dn));
    return static_cast<float>(z);
}

// NDC z (after the perspective divide) -> eye distance. ZeroToOne: NDC z is the window depth.
// NegativeOneToOne (glm::perspectiveRH_NO, glFrustum): ndc = (f+n)/(f-n) - 2 f n / ((f-n) d), so
// d = 2 f n / ((f + n) - ndc (f - n)), f = +Inf: d = 2 n / (1 - ndc) (computed from ndc directly,
// without the 0.5 ndc + 0.5 step that loses bits near 1). Reversed with NegativeOneToOne means
// ndc_reversed = -ndc (window 1 - z_w); prefer ZeroToOne for reversed-Z.
inline float linearize_ndc_depth(float ndc, float n, float f, ClipDepth clip, bool reversed_z) {
    if (clip == ClipDepth::ZeroToOne) return linearize_window_depth(ndc, n, f, reversed_z);
    if (std::isnan(ndc)) return ndc;
    double z = reversed_z ? -double(ndc) : double(ndc);
    z = z < -1.0 ? -1.0 : (z > 1.0 ? 1.0 : z);
    const double dn = double(n), df = double(f);
    const double d = std::isinf(df) ? 2.0 * dn / (1.0 - z) : 2.0 * df * dn / ((df + dn) - z * (df - dn));
    return static_cast<float>(d);
}

// Orthographic (directional) lights store linear depth: d = n + z_w (f - n) (reversed: z_w -> 1 - z_w).
inline float linearize_ortho_window_depth(float z_w, float n, float f, bool reversed_z) {
    const double z = reversed_z ? 1.0 - double(z_w) : double(z_w);
    return static_cast<float>(double(n) + z * (double(f) - double(n)));
}

// ------------------------------------------------------------------------------------------------
// PCSS geometry (perspective light; widths in world units)
// ------------------------------------------------------------------------------------------------

// Blocker search width on the near plane (Apelles eq. 3.20): w_light (z_r - z_n) / z_r, the
// intersection of the near plane with the pyramid from the receiver to the light (similar
// triangles). 0 when the receiver is at or in front of the near plane.
inline float pcss_search_width(float light_width, float z_r, float z_n) {
    if (!(z_r > z_n)) return std::isnan(z_r) || std::isnan(z_n) ? std::numeric_limits<float>::quiet_NaN() : 0.0f;
    return static_cast<float>(double(light_width) * (double(z_r) - double(z_n)) / double(z_r));
}

// Penumbra width on the receiver (Fernando 2005; Apelles eq. 3.21): w_light (z_r - z_b) / z_b,
// for a planar blocker at z_b and receiver at z_r parallel to the light. 0 when z_b >= z_r
// (blocker at the receiver: contact, hard shadow); +Inf when z_b <= 0 (clamp the filter).
inline float pcss_penumbra_width(float light_width, float z_r, float z_b) {
    if (std::isnan(light_width) || std::isnan(z_r) || std::isnan(z_b)) return std::numeric_limits<float>::quiet_NaN();
    if (!(z_r > z_b) || light_width == 0.0f) return 0.0f;
    if (!(z_b > 0.0f)) return std::numeric_limits<float>::infinity();
    return static_cast<float>(double(light_width) * (double(z_r) - double(z_b)) / double(z_b));
}

// Filter width on the near plane (Apelles eq. 3.22): w_penumbra z_n / z_r. (The thesis's shader
// passes w_penumbra itself to PCF, too wide by z_r / z_n.)
inline float pcss_filter_width(float w_penumbra, float z_r, float z_n) {
    return static_cast<float>(double(w_penumbra) * double(z_n) / double(z_r));
}

// A world width at eye distance z in shadow-map uv: width / (z * frustum_width).
inline float perspective_width_to_uv(float width, float z, float frustum_width) {
    return static_cast<float>(double(width) / (double(z) * double(frustum_width)));
}

// Directional light of angular diameter theta: a blocker at distance h above the receiver casts a
// penumbra 2 tan(theta/2) h wide. Search width = 2 tan(theta/2) (z_r - z_n) (blockers between the
// ortho near plane and the receiver), penumbra = 2 tan(theta/2) (z_r - z_b); in uv both divide by
// the ortho width (no perspective scaling, so the filter width is the penumbra width).
inline float pcss_search_width_directional(float angular_diameter, float z_r, float z_n) {
    if (!(z_r > z_n)) return std::isnan(z_r) || std::isnan(z_n) ? std::numeric_limits<float>::quiet_NaN() : 0.0f;
    return static_cast<float>(2.0 * std::tan(0.5 * double(angular_diameter)) * (double(z_r) - double(z_n)));
}
inline float pcss_penumbra_width_directional(float angular_diameter, float z_r, float z_b) {
    if (std::isnan(angular_diameter) || std::isnan(z_r) || std::isnan(z_b)) return std::numeric_limits<float>::quiet_NaN();
    if (!(z_r > z_b) || angular_diameter == 0.0f) return 0.0f;
    return static_cast<float>(2.0 * std::tan(0.5 * double(angular_diameter)) * (double(z_r) - double(z_b)));
}

namespace pcss_detail {
inline bool valid_light(const PcssLight& L) {
    if (!std::isfinite(L.size) || L.size < 0.0f || !std::isfinite(L.frustum_width) || !(L.frustum_width > 0.0f))
        return false;
    if (!std::isfinite(L.near) || std::isnan(L.far) || !(L.far > L.near)) return false;
    if (L.type == PcssLightType::Perspective) return L.near > 0.0f;
    if (L.type == PcssLightType::Directional) return std::isfinite(L.far) && L.size < 3.14159f;
    return false;
}
}  // namespace pcss_detail

// The light's width in uv measured on the near plane: size / (near * frustum_width) (perspective),
// the uniform `light_uv_at_near` of glsl/pcss.glsl. Directional: 2 tan(theta/2) (far - near) /
// frustum_width, the uniform `light_uv_per_depth` (uv of penumbra per unit of window depth).
// NaN for an invalid light.
inline float pcss_light_uv_at_near(const PcssLight& L) {
    if (!pcss_detail::valid_light(L)) return std::numeric_limits<float>::quiet_NaN();
    if (L.type == PcssLightType::Directional)
        return static_cast<float>(2.0 * std::tan(0.5 * double(L.size)) * (double(L.far) - double(L.near)) /
                                  double(L.frustum_width));
    return static_cast<float>(double(L.size) / (double(L.near) * double(L.frustum_width)));
}

// Width of the blocker search square in uv for a receiver at linear depth z_r.
// Perspective: search_width / (z_n frustum_width); directional: search width / ortho width.
// NaN for an invalid light or NaN depth; 0 for a receiver at or in front of the near plane.
inline float pcss_search_uv(const PcssLight& L, float z_r) {
    if (!pcss_detail::valid_light(L) || std::isnan(z_r)) return std::numeric_limits<float>::quiet_NaN();
    if (std::isinf(z_r)) return 0.0f;
    if (L.type == PcssLightType::Directional)
        return static_cast<float>(double(pcss_search_width_directional(L.size, z_r, L.near)) / double(L.frustum_width));
    return perspective_width_to_uv(pcss_search_width(L.size, z_r, L.near), L.near, L.frustum_width);
}

// ------------------------------------------------------------------------------------------------
// Average blocker
// ------------------------------------------------------------------------------------------------

struct PcssBlocker {
    bool found = false;     // false: no sample closer than z_r - bias (fully lit)
    float average = 0.0f;   // mean linear depth of the blocking samples (valid when found)
    std::size_t count = 0;  // number of blocking samples
};

// Mean of the linear depths closer to the light than the receiver (d < z_r - bias). Samples that
// are NaN, +-Inf or <= 0 (outside the map, cleared texels) are ignored, as is a null array.
inline PcssBlocker pcss_average_blocker(const float* linear_depths, std::size_t n, float z_r, float bias) {
    PcssBlocker b;
    if (linear_depths == nullptr || std::isnan(z_r) || std::isnan(bias)) return b;
    const double limit = double(z_r) - double(bias);
    double sum = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        const float d = linear_depths[i];
        if (!std::isfinite(d) || !(d > 0.0f)) continue;
        if (double(d) < limit) {
            sum += double(d);
            ++b.count;
        }
    }
    if (b.count > 0) {
        b.found = true;
        b.average = static_cast<float>(sum / double(b.count));
    }
    return b;
}

// ------------------------------------------------------------------------------------------------
// Filter clamp and tap budget
// ------------------------------------------------------------------------------------------------

// Clamps a filter width (uv) into [min_uv, max_uv]; NaN -> min_uv (hard shadow), +Inf -> max_uv.
inline float pcss_clamp_filter(float filter_uv, float min_uv, float max_uv) {
    if (std::isnan(filter_uv)) return min_uv;
    if (filter_uv > max_uv) return max_uv;
    if (filter_uv < min_uv) return min_uv;
    return filter_uv;
}

// Tap budget: enough taps to put one tap per `texels_per_tap` x `texels_per_tap` texels of the
// filter disk, ceil(pi (D/2)^2 / s^2) for a filter of diameter D texels, clamped to
// [min_taps, max_taps]. A filter narrower than one texel gets min_taps (a hard 2x2 compare is
// enough). NaN -> min_taps, +Inf -> max_taps; min_taps < 1 is raised to 1, max_taps < min_taps to
// min_taps. Monotone non-decreasing in D. Same policy as sk_pcss_tap_budget in glsl/pcss.glsl.
inline int pcss_tap_budget(float filter_texels, int min_taps, int max_taps, float texels_per_tap = 1.0f) {
    const int lo = min_taps < 1 ? 1 : min_taps;
    const int hi = max_taps < lo ? lo : max_taps;
    if (std::isnan(filter_texels) || !(filter_texels > 1.0f)) return lo;
    const double s = std::isfinite(texels_per_tap) && texels_per_tap > 0.0f ? double(texels_per_tap) : 1.0;
    const double r = 0.5 * double(filter_texels) / s;
    const double want = std::ceil(3.14159265358979323846 * r * r);
    if (!(want < double(hi))) return hi;
    return want < double(lo) ? lo : static_cast<int>(want);
}

// ------------------------------------------------------------------------------------------------
// Whole estimate
// ------------------------------------------------------------------------------------------------

struct PcssPolicy {
    float min_filter_uv = 0.0f;     // lower clamp of the filter width (0: contact shadows stay hard)
    float max_filter_uv = 0.05f;    // upper clamp (large penumbrae cost taps and leak; [Limit: > 0])
    float map_resolution = 2048.0f; // shadow-map texels across uv [0,1]
    int min_taps = 1;
    int max_taps = 64;
    float texels_per_tap = 1.0f;
};

struct PcssFilter {
    PcssStatus status = PcssStatus::InvalidArgument;
    float search_uv = 0.0f;       // blocker search width (uv)
    float blocker_depth = 0.0f;   // average blocker depth (linear), when found
    float penumbra_width = 0.0f;  // on the receiver [world]; may be +Inf before the clamp
    float filter_uv = 0.0f;       // clamped PCF width (uv); 0 when NoBlocker
    int taps = 0;                 // tap budget for filter_uv; 0 when NoBlocker
};

// Penumbra -> filter for a receiver at linear depth z_r and the blocker estimate b (from
// pcss_average_blocker). Light size 0 gives filter_uv == min_filter_uv exactly (a hard shadow with
// the default 0), a blocker at the receiver gives 0 penumbra, a blocker depth tending to 0 an
// infinite penumbra clamped to max_filter_uv: filter_uv and taps are finite and in range whenever
// status is Ok (penumbra_width may be +Inf, search_uv may overflow for extreme light parameters).
inline PcssFilter pcss_filter(const PcssLight& L, float z_r, const PcssBlocker& b, const PcssPolicy& p = PcssPolicy{}) {
    PcssFilter out;
    if (!pcss_detail::valid_light(L) || !std::isfinite(z_r) || !(z_r > 0.0f || L.type == PcssLightType::Directional) ||
        !std::isfinite(p.min_filter_uv) || !std::isfinite(p.max_filter_uv) || p.min_filter_uv < 0.0f ||
        !(p.max_filter_uv >= p.min_filter_uv) || !std::isfinite(p.map_resolution) || !(p.map_resolution > 0.0f))
        return out;
    out.search_uv = pcss_search_uv(L, z_r);
    if (!b.found) {
        out.status = PcssStatus::NoBlocker;
        return out;
    }
    if (!std::isfinite(b.average)) return out;  // status stays InvalidArgument
    out.blocker_depth = b.average;
    float filter;
    if (L.type == PcssLightType::Directional) {
        out.penumbra_width = pcss_penumbra_width_directional(L.size, z_r, b.average);
        filter = static_cast<float>(double(out.penumbra_width) / double(L.frustum_width));
    } else {
        out.penumbra_width = pcss_penumbra_width(L.size, z_r, b.average);
        // eq. 3.22 then near-plane width -> uv; equal to w_penumbra / (z_r frustum_width).
        filter = perspective_width_to_uv(pcss_filter_width(out.penumbra_width, z_r, L.near), L.near, L.frustum_width);
    }
    out.filter_uv = pcss_clamp_filter(filter, p.min_filter_uv, p.max_filter_uv);
    out.taps = pcss_tap_budget(out.filter_uv * p.map_resolution, p.min_taps, p.max_taps, p.texels_per_tap);
    out.status = PcssStatus::Ok;
    return out;
}

// Penumbra width from two window depths of a perspective light: linearizes both first, then
// eq. 3.21. (Using the window depths directly in (z_r - z_b) / z_b is the three.js bug.)
inline float pcss_penumbra_width_from_window_depth(float light_width, float receiver_window, float blocker_window,
                                                   float n, float f, bool reversed_z) {
    return pcss_penumbra_width(light_width, linearize_window_depth(receiver_window, n, f, reversed_z),
                               linearize_window_depth(blocker_window, n, f, reversed_z));
}

}  // namespace shadowkit
