// shadowkit/prefiltered_shadow.hpp - pre-filtered shadow maps (VSM, ESM, EVSM2/4, MSM) and their storage limits.
// Variance, exponential, exponential-variance and moment (Hamburger and Hausdorff) shadow maps: the
// depth range, the uniforms checked against the texture format, blur kernels and CPU mirrors of the
// GLSL, with the numerics derived below and checked by the unit tests.
//
// USAGE
//   #include <shadowkit/prefiltered_shadow.hpp>
//   using namespace shadowkit;
//   // once per light: the depth range the map encodes (the casters' and receivers' extent along the
//   // light's axis) and the method's uniforms, checked against the moment texture's format
//   PrefilterDepthRange range = prefilter_depth_range(/*near*/ 0.5f, /*far*/ 40.0f);
//   PrefilterSettings s;
//   s.method = PrefilterMethod::Evsm4;
//   s.format = PrefilterFormat::Float16;            // GL_RGBA16F
//   PrefilterUniforms u = prefilter_uniforms(s);    // u.status; exponents below the fp16 limit
//   float w[kPrefilterMaxWeights];
//   PrefilterKernel k = prefilter_blur_weights(PrefilterBlur::Gaussian, /*width texels*/ 7.0f, w, kPrefilterMaxWeights);
//   // GLSL (glsl/prefiltered_shadow.glsl): the moment pass writes
//   //   sk_prefilter_moments(sk_prefilter_depth(eye_distance, range), dt, method, exponents, quantized),
//   // two sk_prefilter_blur passes filter it, the lookup is
//   //   sk_prefilter_visibility(texture(moments, uv), t_receiver, method, params, moment_bias, quantized).
//   // The CPU mirrors (prefilter_moments, prefilter_visibility, ...) compute the same in float.
//   // Soft shadows with contact hardening (VSM, MSM): a mipmapped moment map and the emitter's width
//   PrefilterSoftSettings ss;
//   ss.light_proj = light_proj; ss.light_width = 2.0f; ss.range = range; ss.map_size = 1024;
//   PrefilterSoftUniforms su = prefilter_soft_uniforms(ss);  // su.status; su.params() -> GLSL `soft`
//   //   sk_prefilter_soft_visibility(moments, uv, t_receiver, method, params, moment_bias, quantized, soft, slope)
//
// CONVENTIONS
// - Moment depth t: every method filters a depth t in [0, 1] that grows away from the light and is
//   LINEAR in the eye distance d along the light's axis over the range the map encodes:
//   t = (d - range_near) / (range_far - range_near) (prefilter_depth_range gives scale and offset).
//   A moment pass that has the light-view position computes t from it; one that has only the depth
//   buffer converts window depth with prefilter_window_depth_map (standard or reversed-Z,
//   perspective or orthographic, far plane finite or +inf). Window depth (glDepthRange(0, 1),
//   gl_FragCoord.z) is the same for GL [-1, 1] and zero-to-one clip depth, so ClipDepth does not
//   enter: all four conventions give the same t, and every limit below holds for all of them.
//   Receivers compute t the same way (from the same eye distance) and subtract their depth bias.
// - Storage formats (PrefilterFormat): Float32 (GL_RG32F / GL_RGBA32F), Float16 (GL_RG16F /
//   GL_RGBA16F), Unorm16 (GL_RG16 / GL_RGBA16: VSM, and MSM with the optimized quantization).
// - Lookups (prefilter_vsm, prefilter_esm, ..., prefilter_visibility) are total: any texel contents,
//   NaN and Inf included, give a visibility in [0, 1] (1 = lit). A texel with a non-finite moment
//   counts as lit (it can only come from an overflowed warp: keep exponents within the limits).
// - Buffers: prefilter_blur_weights writes `weights_capacity` float elements.
// - Results: a non-Ok result's `detail` names the offending input and the rule ("far: not > near"),
//   a static string; nullptr when Ok.
// - No function here takes a light: the light's projection enters only through near/far values
//   (prefilter_window_depth_map) and the projection matrices of prefilter_kernel_texels and
//   prefilter_soft_uniforms (with the emitter's width, a separate field).
//
// NUMERICS (derivations; the unit tests check each claim)
// 1. Formats. Float32: largest finite F = 3.4028235e38, a value rounds to Inf from
//    T = (2 - 2^-24) 2^127 = 3.40282357e38 up; unit roundoff u = 2^-24. Float16: F = 65504, T = 65520,
//    u = 2^-11, smallest normal 2^-14. Unorm16: k / 65535, absolute error <= 1 / 131070.
// 2. Largest safe exponent. The moment pass stores ESM: e^(c t); EVSM with the centered warp
//    x = 2t - 1 in [-1, 1]: (e^(c+ x), e^(2 c+ x), -e^(-c- x), e^(-2 c- x)). A normalized filter
//    (weights summing to 1, accumulated in fp32 registers) writes a weighted mean, never above the
//    largest sample; a filter that accumulates N samples in the moment texture itself before
//    normalizing (additive blending, a box sum, a summed-area table, an MSAA sum) writes up to
//    N x the largest sample. The largest sample is at t = 1 for ESM (e^c) and for EVSM's positive
//    pair (e^(2c+)), at t = 0 for the negative pair (e^(2c-)). So every stored value is finite iff
//        N e^(k c) < T,   c_max = ln(T / N) / k,   k = 1 (ESM), 2 (both EVSM warps);
//    N = 1: Float32 ESM 88.72, EVSM 44.36; Float16 ESM 11.090, EVSM 5.545 (the published 42 and 5.54
//    are these with a margin). prefilter_exponent_limit returns the largest float c with
//    N e^(k c) < T: at it the worst texel is finite, one float step above it rounds to Inf (or, on
//    drivers that saturate render-target conversions, such as llvmpipe's fp16, to 65504: wrong
//    either way).
//    Conventions: t is linear and convention-free (above), so the limits are the same for standard and
//    reversed-Z, GL and zero-to-one depth. A user who warps the raw stored depth instead of t changes
//    the domain: GL NDC z in [-1, 1] keeps the overflow side (e^c at +1) but underflows e^-c at -1
//    (Float16: below 2^-14 for c > 9.70, self-shadowing acne near the light); reversed-Z window depth
//    is 1 at the near plane, so e^(c z) puts the largest values on the occluders nearest the light
//    and the test compares in the wrong direction: flip it (t = 1 - z) first.
// 3. Lookup range. ESM: visibility = e^(-c t_r) M with M <= N e^c in fp32 registers: finite. EVSM:
//    Chebyshev in the warped domain with the minimum variance scaled by the warp's slope squared,
//    (2 c w)^2 min_variance, clamped to 1e37, so var + d^2 stays finite or is +Inf (p = 0).
//    Jensen: the positive warp is convex, so a receiver on a plane whose depths spread by sigma
//    (slope x blur width) sees a mean above its own warped depth: lit. The negative warp is
//    concave: its mean falls below the receiver by ~ (2c)^2 |w| sigma^2 / 2 against a spread of
//    2c |w| sigma, so Chebyshev gives p ~ 1 / (1 + c^2 sigma^2): self-shadowing that grows with c-.
//    Hence c- defaults to 5 (p >= 0.94 for sigma <= 0.05) and c+ to the limit. ESM and both warps
//    also need every receiver in the map: a texel left at the clear value t = 1 behind a receiver
//    lights it (ESM by e^(c (1 - t_r))).
// 4. Variance cancellation. var = E[t^2] - E[t]^2 from stored moments: with t in [0, 1] the stored
//    M2 and the product M1^2 each carry a relative error <= u (plus fp32 register rounding), so the
//    computed variance is off by at most 3u (float formats), 3 / 131070 (Unorm16): that floor is
//    prefilter_min_variance: Float32 1.8e-7, Float16 1.5e-3, Unorm16 2.3e-5. VSM adds it (plus
//    4u (M2 + M1^2) for the fp32 arithmetic) to the computed variance rather than flooring with it, and
//    moves the mean by its error, so the bound is never below the lit fraction (a floor applied as
//    max(var, floor) left a cancelled variance just above it too small: 0.651 for a true 0.734).
//    Two surfaces dd apart (half the texels each) have variance (dt / 2)^2, dt = dd / (far - near), so they are told apart
//    above dt = 2 sqrt(3u): 8.5e-4 of the range (Float32), 0.077 (Float16), whatever the scene's
//    scale (1e-3 or 1e5 units) or its distance from the light: t is linear over the encoded range.
//    Window depth of a projection with near / far = 1e-6 instead resolves dz = n dd / d^2 (for
//    d >> n), so beyond d = sqrt(n dd / 8.5e-4) a pair dd apart collapses to one depth: 1 - z_w
//    crowds into [0, n / d], the "everything lost near z = 1" failure. Encode the casters' and
//    receivers' extent (not the projection's planes) as [near, far]. Centering t to [-1, 1] gains
//    nothing for VSM (the variance is shift-invariant, M2 ~ 1 keeps its rounding); EVSM centers to
//    halve the exponent range (item 2).
// 5. MSM. The Hankel matrix B = [1 b1 b2; b1 b2 b3; b2 b3 b4] of a filtered moment vector is
//    positive semi-definite, singular when all samples sit on <= 2 depths. The moment bias
//    b' = (1 - a) b + a (1/2, 1/2, 1/2, 1/2) mixes in half a sample at 0 and half at 1, which makes
//    B' positive definite unless every sample is at 0 or 1 exactly (a cleared texel at t = 1 with
//    nothing else). Where D33 <= 0 anyway (those texels, or rounding) the lookup reads the two depths
//    off the 2x2 system (exact for two-depth texels), and with D22 at or below the bias's own
//    variance a ((b1 - 1/2)^2 + 1/4) (one depth: only rounding goes below it) compares with the
//    mean, so the Cholesky step never divides by zero. Support points within 32 a (+ 4 ulps) of the
//    receiver count as at the receiver, not in front: the solve's rounding moves a depth at t by up
//    to ~1e-5 (Float32, a = 6e-7) and ~2e-4 (Unorm16, a = 3e-5), and without the tolerance a surface
//    read at its own depth came out dark (3,881 of 99,999 single depths, Float32). The bias must
//    dominate the storage error of b and the fp32 arithmetic of the solve: measured on blurred
//    receiver planes (spreads 1e-4 .. 1e-2 of the range, with and without an occluder) against the
//    same bound from the exact moments in double precision (which resolves what rounding hides and
//    has no tolerance), the mean difference is 0.020 at the paper's 6e-7 for Float32 moments and
//    0.017 at its 3e-5 for Unorm16 after the optimized basis transform (Peters & Klein 2015, Sec.
//    4.3: q = A b + (0.035955884801, 0, 0, 0), all q in [0, 1] for t in [0, 1]; A^-1 computed here
//    in double); smaller biases give more (Float32 at 1e-7: 0.029, Unorm16 at 3e-6: 0.069).
//    The Unorm16 round trip b -> q -> 16 bits -> b is off by at most 1.06e-5 computed exactly,
//    1.35e-5 through the float quantize / dequantize (1,000,001 depths t = i / 1e6).
// 6. Kernel width. The blur is uniform over the map; a world width W at eye distance d covers
//    0.5 P[0][0] W / w(d) of uv (w(d) = d for a perspective light, 1 for an orthographic one), times
//    the map size in texels (prefilter_kernel_texels).
// 7. Soft shadows (contact hardening). A perspective map from the emitter's center, emitter width W:
//    blockers at eye distance d_b cast a penumbra W (d_r - d_b) / d_b on a receiver at d_r (PCSS's
//    similar triangles), which covers light_uv (1 / d_b - 1 / d_r) of the map's uv, light_uv =
//    0.5 sqrt|P00 P11| W / -P23. The search region is that width for d_b = near (the range's near end:
//    no caster is closer). A box of K texels (variance K^2 / 12) is matched by a trilinear lookup at
//    mip level L = log2(K / sqrt(3)) (box 2^L * tent 2^L: variance 4^L / 4), so a mipmapped moment
//    map filters any width with two lookups; the mip boxes are aligned to the level's grid (the
//    filter is not shift-invariant: a blocky, trilinear-smoothed penumbra at wide levels), and the
//    pre-blur adds its own width. The blocker depth from the search-region moments: VSM with the
//    non-blockers at t (exact for two depths: p = 1 - a, z_avg = z_b); MSM from the canonical
//    representation through t (exact for two depths up to the moment bias). W = 0 or a receiver at
//    a contact (d_b = d_r) gives level 0: the hard pre-filtered lookup; so does a search that finds
//    no blocker (MSM's bound over a wide mix of depths can miss a small blocker close in front,
//    which level 0 resolves). A receiver plane with depth slope g (t per uv) spreads its own depths
//    by +-g r over a region of half width r, half of them in front of it: the lookup compares
//    t - min(g r, cap) per region (prefilter_receiver_slope; a filtered map cannot bias per tap as
//    PCSS does, so sloped receivers under wide kernels stay its weak spot).
//
// Based on:
//   W. Donnelly, A. Lauritzen, "Variance Shadow Maps", I3D 2006 (eq. 5: Chebyshev's one-sided bound).
//   A. Lauritzen, "Summed-Area Variance Shadow Maps", GPU Gems 3, ch. 8, 2007 (light-bleeding
//     reduction, depth-derivative variance term, minimum variance).
//   T. Annen, T. Mertens, H.-P. Seidel, E. Flerackers, J. Kautz, "Exponential Shadow Maps", GI 2008.
//   A. Lauritzen, M. McCool, "Layered Variance Shadow Maps", GI 2008 (exponential warps, EVSM).
//   C. Peters, R. Klein, "Moment Shadow Mapping", I3D 2015 (Hamburger 4MSM, moment bias, Sec. 4.3
//     optimized quantization, the Hausdorff variant).
//   R. Fernando, "Percentage-Closer Soft Shadows", SIGGRAPH 2005 sketch (the penumbra width).
//   B. Yang, Z. Dong, J. Feng, H.-P. Seidel, J. Kautz, "Variance Soft Shadow Mapping", Pacific
//     Graphics 2010 (the average blocker depth from Chebyshev's bound: mu = p t + (1 - p) z_avg).
//   C. Peters, C. Muenstermann, N. Wetzstein, R. Klein, "Beyond Hard Shadows: Moment Shadow Maps for
//     Single Scattering, Soft Shadows and Translucent Occluders", I3D 2016 (moment soft shadow
//     mapping: blocker search from filtered moments; they filter with summed-area tables and bound
//     the blockers' partial moment, here the mean of the canonical representation's points in front).
//   A. Moschig, "Apelles: A Library for GPU-Based Real-Time Global Illumination", master's thesis, TU
//     Graz (2012), Sec. 2.1.2 (oversampling: VSM, ESM, CSM, layered VSM; light bleeding, Fig. 2.11).
//
// MIT License. Copyright (c) shadowkit contributors.
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
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

/// The pre-filtered methods; the values are the `method` codes of glsl/prefiltered_shadow.glsl.
enum class PrefilterMethod : std::uint8_t {
    Vsm = 0,          ///< (t, t^2), Chebyshev's one-sided bound
    Esm = 1,          ///< e^(c t)
    Evsm2 = 2,        ///< (e^(c x), e^(2 c x)), x = 2t - 1
    Evsm4 = 3,        ///< Evsm2 plus the negative warp (-e^(-c- x), e^(-2 c- x))
    Msm = 4,          ///< (t, t^2, t^3, t^4), Hamburger 4MSM
    MsmHausdorff = 5  ///< the same moments, reconstruction on [0, 1] (the Hausdorff moment problem)
};

/// Storage format of the moment texture.
enum class PrefilterFormat : std::uint8_t {
    Float32 = 0,  ///< GL_RG32F / GL_RGBA32F
    Float16 = 1,  ///< GL_RG16F / GL_RGBA16F
    Unorm16 = 2   ///< GL_RG16 / GL_RGBA16 (VSM; MSM with the optimized quantization)
};

/// Blur kernel shape.
enum class PrefilterBlur : std::uint8_t {
    Box = 0,      ///< equal weights over 2r + 1 texels
    Gaussian = 1  ///< exp(-i^2 / (2 sigma^2)), sigma = width / 6, r = floor(3 sigma)
};

/// Largest blur radius (texels) of prefilter_blur_weights and sk_prefilter_blur.
constexpr int kPrefilterMaxRadius = 32;
/// Weights a kernel of the largest radius needs (center plus one side).
constexpr std::size_t kPrefilterMaxWeights = 33;
/// The optimized MSM quantization's offset of the first component (Peters & Klein 2015, Sec. 4.3).
/// It is not a 16-bit code (x 65535 = 2356.37): the moments of t = 0 (q = (offset, 0, 0, 0)) are stored
/// 5.6e-6 off in q0 and come back as b1 = -1.25e-6, so a receiver at t = 0 with moment bias 0 is
/// shadowed by its own depth; the Unorm16 default bias (3e-5) lights it (unit-tested).
constexpr float kPrefilterMsmOffset = 0.035955884801f;

namespace detail {
/// t sanitized: NaN -> 1, clamped to [0, 1].
inline float pf_clamp_depth(float t) {
    if (!(t >= 0.0f)) return std::isnan(t) ? 1.0f : 0.0f;
    return t > 1.0f ? 1.0f : t;
}
/// x sanitized: NaN -> lo, clamped to [lo, hi].
inline float pf_clamp(float x, float lo, float hi) {
    if (!(x >= lo)) return lo;
    return x > hi ? hi : x;
}
/// A moment for the quantization: NaN/Inf -> 0, clamped to [-1e6, 1e6].
inline float pf_clamp_moment(float x) {
    if (!std::isfinite(x)) return 0.0f;
    return x < -1e6f ? -1e6f : (x > 1e6f ? 1e6f : x);
}
inline bool pf_finite(const glm::vec4& m) {
    return std::isfinite(m.x) && std::isfinite(m.y) && std::isfinite(m.z) && std::isfinite(m.w);
}
/// Largest ESM exponent the float32 pass can evaluate at all (e^c <= FLT_MAX); EVSM's is half.
constexpr float pf_max_esm_exponent = 88.72283f;
constexpr float pf_max_evsm_exponent = 44.36141f;
}  // namespace detail

// ------------------------------------------------------------------------------------------------
// Depth
// ------------------------------------------------------------------------------------------------

/// The linear map from eye distance d to moment depth t = d * scale + offset.
struct PrefilterDepthRange {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    float scale = 0.0f;   ///< 1 / (far_z - near_z)
    float offset = 0.0f;  ///< -near_z / (far_z - near_z)
    float near_z = 0.0f;  ///< [Units: wu] near_z, as given (offset can underflow: -1e-60 for [1e-30, 1e30]); 0 if not set
    float far_z = 0.0f;   ///< [Units: wu] far_z, as given; 0 if not set
};

/// The map of eye distances [near_z, far_z] (the range the shadow map encodes: the casters' and
/// receivers' extent along the light's axis, not necessarily the projection's planes) to t in [0, 1].
/// NonFinite for NaN/Inf, InvalidArgument for near_z < 0 or far_z <= near_z, Overflow when far_z - near_z is
/// below the float spacing of far_z (t would have no resolution) or 1 / (far_z - near_z) overflows.
inline PrefilterDepthRange prefilter_depth_range(float near_z, float far_z) {
    PrefilterDepthRange r;
    if (!std::isfinite(near_z) || !std::isfinite(far_z)) {
        r.status = Status::NonFinite;
        r.detail = !std::isfinite(near_z) ? "near_z: NaN or Inf" : "far_z: NaN or Inf";
        return r;
    }
    if (near_z < 0.0f || !(far_z > near_z)) {
        r.status = Status::InvalidArgument;
        r.detail = near_z < 0.0f ? "near_z: < 0" : "far_z: not > near_z";
        return r;
    }
    const double span = double(far_z) - double(near_z);
    const double scale = 1.0 / span;
    if (!(span > 4.0 * double(std::nextafter(far_z, std::numeric_limits<float>::infinity()) - far_z)) ||
        !(scale < double(std::numeric_limits<float>::max()))) {
        r.status = Status::Overflow;
        r.detail = "far_z: far_z - near_z below 4 float steps of far_z";
        return r;
    }
    r.scale = static_cast<float>(scale);
    r.offset = static_cast<float>(-double(near_z) * scale);
    r.near_z = near_z;
    r.far_z = far_z;
    r.status = Status::Ok;
    return r;
}

/// Moment depth of an eye distance (mirror of sk_prefilter_depth): d * scale + offset clamped to
/// [0, 1]. Total: NaN gives 1 (the far end: unoccluded), any range values give a t in [0, 1].
inline float prefilter_depth(float eye_distance, const PrefilterDepthRange& r) {
    const float t = eye_distance * r.scale + r.offset;
    if (!(t >= 0.0f)) return std::isnan(t) ? 1.0f : 0.0f;
    return t > 1.0f ? 1.0f : t;
}

/// Largest error in t that prefilter_window_depth_map accepts (Overflow above it): well below the
/// 8.5e-4 at which two surfaces are told apart in Float32 (NUMERICS item 4).
constexpr float kPrefilterWindowTolerance = 1e-4f;

/// Coefficients c of t = (c.x + c.y z_w) / (c.z + c.w z_w), window depth z_w -> moment depth.
struct PrefilterWindowMap {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    glm::vec4 coefficients{0.0f};
};

/// The window-depth -> t map of a light projection with planes proj_near_z, proj_far_z (proj_far_z may be
/// +inf for a perspective light) into the range r. Perspective, standard: z_w = f (d - n) / (d (f - n)),
/// so 1 / d = 1/n + (1/f - 1/n) z_w; reversed-Z: 1 / d = 1/f + (1/n - 1/f) z_w; orthographic:
/// d = n + (f - n) z_w (reversed: f - (f - n) z_w). Window depth is glDepthRange(0, 1) depth, the
/// same for GL [-1, 1] and zero-to-one clip depth. NonFinite / InvalidArgument for bad planes
/// (perspective: 0 < near < far; orthographic: finite near < far) or a range whose status is not Ok.
/// Overflow: coefficients beyond float, or depth steps that collapse: over the distances the range
/// and the projection share, t from the float window depth (rounded by the depth buffer) through the
/// float map could be off by more than kPrefilterWindowTolerance. A standard perspective map does so
/// from far / near ~ 1e3 (window depth crowds near 1: [0.1, 1e4] was off by 0.006); reversed-Z keeps
/// t to ~1e-7 for any far / near, +inf included.
inline PrefilterWindowMap prefilter_window_depth_map(float proj_near_z, float proj_far_z, bool perspective, bool reversed_z,
                                                     const PrefilterDepthRange& r) {
    PrefilterWindowMap m;
    if (r.status != Status::Ok) {
        m.status = Status::InvalidArgument;
        m.detail = "r: status not Ok";
        return m;
    }
    if (std::isnan(proj_near_z) || std::isnan(proj_far_z) || !std::isfinite(proj_near_z) ||
        (!perspective && !std::isfinite(proj_far_z))) {
        m.status = Status::NonFinite;
        m.detail = !std::isfinite(proj_near_z) ? "proj_near_z: NaN or Inf" : "proj_far_z: NaN (or Inf, orthographic)";
        return m;
    }
    if (!(proj_far_z > proj_near_z) || (perspective && !(proj_near_z > 0.0f))) {
        m.status = Status::InvalidArgument;
        m.detail = !(proj_far_z > proj_near_z) ? "proj_far_z: not > proj_near_z" : "proj_near_z: not > 0 (perspective)";
        return m;
    }
    const double n = double(proj_near_z), f = double(proj_far_z), s = double(r.scale), o = double(r.offset);
    glm::dvec4 c;
    if (perspective) {
        const double inv_f = std::isinf(f) ? 0.0 : 1.0 / f;
        const double alpha = reversed_z ? inv_f : 1.0 / n;
        const double beta = reversed_z ? 1.0 / n - inv_f : inv_f - 1.0 / n;
        c = glm::dvec4(s + o * alpha, o * beta, alpha, beta);
    } else {
        c = reversed_z ? glm::dvec4(s * f + o, -s * (f - n), 1.0, 0.0) : glm::dvec4(s * n + o, s * (f - n), 1.0, 0.0);
    }
    for (int i = 0; i < 4; ++i)
        if (!(std::abs(c[i]) < double(std::numeric_limits<float>::max()))) {
            m.status = Status::Overflow;
            m.detail = "coefficients: beyond float range";
            return m;
        }
    m.coefficients = glm::vec4(c);
    // Depth steps: t is only as good as the window depth the buffer holds (rounded to float: off by
    // up to 2^-24 z_w, at least FLT_MIN) times dt/dz_w, plus the float coefficients and the float evaluation of the
    // ratio (a standard perspective map cancels near z_w = 1: c.z ~ -c.w ~ 1 / n). Bounded at both ends
    // of the distances the range and the projection share (the error grows monotonically toward
    // one of them); above kPrefilterWindowTolerance the map cannot keep t: Overflow.
    const double u = 5.9604644775390625e-8;
    const double d_lo = std::fmax(n, -o / s), d_hi = std::fmin(f, (1.0 - o) / s);
    double worst = 0.0;
    const double ends[2] = {d_lo, d_hi};
    for (const double d : ends) {
        if (!(d > 0.0) || !std::isfinite(d)) continue;
        double z, dd_dz;  // window depth of d and its inverse slope
        if (perspective) {
            const double inv_f = std::isinf(f) ? 0.0 : 1.0 / f, span = 1.0 / n - inv_f;
            z = reversed_z ? (1.0 / d - inv_f) / span : (1.0 / n - 1.0 / d) / span;
            dd_dz = d * d * span;
        } else {
            z = reversed_z ? (f - d) / (f - n) : (d - n) / (f - n);
            dd_dz = f - n;
        }
        const double t_exact = s * d + o;
        const glm::dvec4 cf(m.coefficients);  // the float coefficients, exactly
        const double num = cf.x + cf.y * z, den = cf.z + cf.w * z;
        const double eval = 3.0 * u * ((std::abs(cf.x) + std::abs(cf.y * z)) + std::abs(t_exact) * (std::abs(cf.z) + std::abs(cf.w * z))) / std::abs(den);
        // the stored depth's rounding: 2^-24 z_w, and never finer than FLT_MIN (a depth buffer may flush
        // subnormal depths to 0: a range 8e34 from a reversed-Z light stores z_w ~ 5e-45)
        const double z_step = std::fmax(u * std::abs(z), 1.1754943508222875e-38);
        const double err = s * dd_dz * z_step + std::abs(num / den - t_exact) + eval + u;
        worst = std::isnan(err) ? std::numeric_limits<double>::infinity() : std::fmax(worst, err);
    }
    if (!(worst <= double(kPrefilterWindowTolerance))) {
        m.coefficients = glm::vec4(0.0f);
        m.status = Status::Overflow;
        m.detail = "proj_near_z, proj_far_z: window depth cannot keep t within kPrefilterWindowTolerance";
        return m;
    }
    m.status = Status::Ok;
    return m;
}

/// Moment depth of a window depth (mirror of sk_prefilter_depth_from_window). Total: the result is
/// clamped to [0, 1]; NaN (a NaN depth, a zero denominator) gives 1.
inline float prefilter_depth_from_window(float z_w, const glm::vec4& c) {
    const float t = (c.x + c.y * z_w) / (c.z + c.w * z_w);
    return detail::pf_clamp_depth(t);
}

// ------------------------------------------------------------------------------------------------
// Storage and limits
// ------------------------------------------------------------------------------------------------

/// A value as the moment texture stores it.
struct PrefilterStored {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    float value = 0.0f;  ///< the stored value; +-Inf with Status::Overflow
};

/// Rounds v to what `format` stores (round to nearest even; Unorm16 clamps to [0, 1] and rounds to
/// k / 65535). A value that rounds beyond the format's largest finite number gives Overflow (value
/// +-Inf, as the GPU would store it); NaN/Inf input gives NonFinite.
inline PrefilterStored prefilter_store(double v, PrefilterFormat format) {
    PrefilterStored s;
    if (!std::isfinite(v)) {
        s.status = Status::NonFinite;
        s.detail = "v: NaN or Inf";
        s.value = static_cast<float>(v);
        return s;
    }
    const double inf = double(std::numeric_limits<float>::infinity());
    if (format == PrefilterFormat::Unorm16) {
        const double c = v < 0.0 ? 0.0 : (v > 1.0 ? 1.0 : v);
        s.value = static_cast<float>(std::nearbyint(c * 65535.0) / 65535.0);
        s.status = Status::Ok;
        return s;
    }
    if (format == PrefilterFormat::Float16) {
        const double a = std::abs(v);
        if (a >= 65520.0) {
            s.value = static_cast<float>(v < 0.0 ? -inf : inf);
            s.status = Status::Overflow;
            s.detail = "v: beyond half float range";
            return s;
        }
        // spacing of half floats near a: 2^(e - 10), e = max(floor(log2 a), -14)
        int e = a > 0.0 ? static_cast<int>(std::floor(std::log2(a))) : -14;
        if (a > 0.0 && std::ldexp(1.0, e) > a) --e;  // log2 rounding at powers of two
        if (a > 0.0 && std::ldexp(1.0, e + 1) <= a) ++e;
        if (e < -14) e = -14;
        const double q = std::ldexp(1.0, e - 10);
        const double r = std::nearbyint(a / q) * q;  // a / q is exact (power of two)
        s.value = static_cast<float>(v < 0.0 ? -r : r);
        s.status = Status::Ok;
        return s;
    }
    const float f = static_cast<float>(v);  // IEEE round to nearest even, Inf beyond the threshold
    s.value = f;
    s.status = std::isinf(f) ? Status::Overflow : Status::Ok;
    s.detail = std::isinf(f) ? "v: beyond float range" : nullptr;
    return s;
}

/// The largest exponent of an exponential warp.
struct PrefilterExponent {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    float exponent = 0.0f;     ///< largest float c with N e^(k c) below the format's overflow threshold
    double worst_value = 0.0;  ///< N e^(k c) at that c: the largest value the moment texture receives
};

/// Largest exponent c of `method` (Esm: k = 1; Evsm2 / Evsm4: k = 2, the same for c+ and c-) such
/// that N = accumulated_samples samples of the largest warped moment, summed, still round to a
/// finite value in `format` (NUMERICS item 2: c_max = ln(T / N) / k). At the returned c the worst
/// texel is finite; at the next float above it rounds to Inf. accumulated_samples is 1 for a filter
/// that normalizes in registers, the number of samples summed in the texture otherwise.
/// InvalidArgument: a method without a warp, Unorm16 (warps need float storage), N = 0. Overflow:
/// N alone (c = 0) already exceeds the format.
inline PrefilterExponent prefilter_exponent_limit(PrefilterMethod method, PrefilterFormat format,
                                                  std::uint32_t accumulated_samples) {
    PrefilterExponent r;
    const bool warp = method == PrefilterMethod::Esm || method == PrefilterMethod::Evsm2 || method == PrefilterMethod::Evsm4;
    if (!warp || accumulated_samples == 0u ||
        (format != PrefilterFormat::Float32 && format != PrefilterFormat::Float16)) {
        r.status = Status::InvalidArgument;
        r.detail = !warp ? "method: not ESM or EVSM" : (accumulated_samples == 0u ? "accumulated_samples: 0" : "format: not Float32 or Float16");
        return r;
    }
    const double T = format == PrefilterFormat::Float16 ? 65520.0 : 340282356779733661637539395458142568448.0;
    const double N = double(accumulated_samples);
    const double k = method == PrefilterMethod::Esm ? 1.0 : 2.0;
    if (!(N < T)) {
        r.status = Status::Overflow;
        r.detail = "accumulated_samples: at or above the format's overflow threshold";
        return r;
    }
    auto worst = [&](float c) { return N * std::exp(k * double(c)); };
    float c = static_cast<float>(std::log(T / N) / k);
    const float up = std::numeric_limits<float>::infinity();
    while (c > 0.0f && !(worst(c) < T)) c = std::nextafter(c, 0.0f);
    while (worst(std::nextafter(c, up)) < T) c = std::nextafter(c, up);
    r.exponent = c;
    r.worst_value = worst(c);
    r.status = Status::Ok;
    return r;
}

/// Minimum variance (in t^2 units) that covers the storage error of (t, t^2) in `format`
/// (NUMERICS item 4): 3u for the float formats, 3 / 131070 for Unorm16. Total: an out-of-range
/// enum value gives the Float16 floor (the largest).
inline float prefilter_min_variance(PrefilterFormat format) {
    switch (format) {
    case PrefilterFormat::Float32: return 3.0f * 5.9604645e-8f;  // 3 * 2^-24
    case PrefilterFormat::Unorm16: return 3.0f / 131070.0f;
    case PrefilterFormat::Float16: break;
    }
    return 3.0f * 4.8828125e-4f;  // 3 * 2^-11
}

/// The MSM moment bias for moments stored in `format` (NUMERICS item 5): Float32 6e-7, Unorm16 with
/// the optimized quantization 3e-5 (Peters & Klein 2015; the unit test measures the smallest that
/// works and checks both lie above it). Float16 MSM is not supported (prefilter_uniforms rejects it):
/// total, it returns the Unorm16 value.
inline float prefilter_msm_moment_bias(PrefilterFormat format) {
    return format == PrefilterFormat::Float32 ? 6e-7f : 3e-5f;
}

// ------------------------------------------------------------------------------------------------
// Moment generation (mirrors of the GLSL moment pass)
// ------------------------------------------------------------------------------------------------


/// VSM moments (t, t^2 + 0.25 (dt_dx^2 + dt_dy^2)) of a fragment at moment depth t with screen
/// derivatives dt_dx, dt_dy (GPU Gems 3 ch. 8: the plane's spread over the pixel, 3x the variance
/// (dt_dx^2 + dt_dy^2) / 12 of a plane over a uniform pixel footprint: a margin against acne). Total:
/// t as prefilter_depth clamps it; non-finite derivatives count as 0; the derivative term is
/// clamped to [0, 1].
inline glm::vec2 prefilter_vsm_moments(float t, float dt_dx, float dt_dy) {
    const float z = detail::pf_clamp_depth(t);
    const float dx = std::isfinite(dt_dx) ? dt_dx : 0.0f, dy = std::isfinite(dt_dy) ? dt_dy : 0.0f;
    float extra = 0.25f * (dx * dx + dy * dy);
    extra = detail::pf_clamp(extra, 0.0f, 1.0f);
    return glm::vec2(z, z * z + extra);
}

/// ESM moment e^(c t). Total: t clamped to [0, 1] (NaN -> 1), c clamped to [0, 88.72] (NaN -> 0),
/// so the result is finite in float; whether it fits the storage format is prefilter_exponent_limit's.
inline float prefilter_esm_moment(float t, float c) {
    return std::exp(detail::pf_clamp(c, 0.0f, detail::pf_max_esm_exponent) * detail::pf_clamp_depth(t));
}

/// EVSM moments (e^(c+ x), e^(2 c+ x), -e^(-c- x), e^(-2 c- x)), x = 2t - 1. Total: t clamped to
/// [0, 1] (NaN -> 1), exponents clamped to [0, 44.36] (NaN -> 0).
inline glm::vec4 prefilter_evsm_moments(float t, float c_pos, float c_neg) {
    const float x = 2.0f * detail::pf_clamp_depth(t) - 1.0f;
    const float p = std::exp(detail::pf_clamp(c_pos, 0.0f, detail::pf_max_evsm_exponent) * x);
    const float n = -std::exp(-detail::pf_clamp(c_neg, 0.0f, detail::pf_max_evsm_exponent) * x);
    return glm::vec4(p, p * p, n, n * n);
}

/// MSM power moments (t, t^2, t^3, t^4). Total: t clamped to [0, 1] (NaN -> 1).
inline glm::vec4 prefilter_msm_moments(float t) {
    const float z = detail::pf_clamp_depth(t);
    const float z2 = z * z;
    return glm::vec4(z, z2, z2 * z, z2 * z2);
}

/// The optimized 16-bit quantization of MSM moments (Peters & Klein 2015, Sec. 4.3): q = A b + (o, 0,
/// 0, 0); every q lies in [0, 1] for moments of depths in [0, 1] (store in GL_RGBA16). The map is
/// affine, so filtering q (blur, bilinear, mipmaps) equals quantizing the filtered b. Total: non-finite
/// components count as 0, the others are clamped to [-1e6, 1e6].
inline glm::vec4 prefilter_msm_quantize(const glm::vec4& moments) {
    const float b1 = detail::pf_clamp_moment(moments.x), b2 = detail::pf_clamp_moment(moments.y);
    const float b3 = detail::pf_clamp_moment(moments.z), b4 = detail::pf_clamp_moment(moments.w);
    return glm::vec4(-2.07224649f * b1 + 32.23703778f * b2 - 68.571074599f * b3 + 39.3703274134f * b4 + kPrefilterMsmOffset,
                     13.7948857237f * b1 - 59.4683975703f * b2 + 82.0359750338f * b3 - 35.364903257f * b4,
                     0.105877704f * b1 - 1.9077466311f * b2 + 9.3496555107f * b3 - 6.6543490743f * b4,
                     9.7924062118f * b1 - 33.7652110555f * b2 + 47.9456096605f * b3 - 23.9728048165f * b4);
}

/// Inverse of prefilter_msm_quantize: b = A^-1 (q - (o, 0, 0, 0)) (A^-1 computed in double from the
/// paper's A). Total: non-finite components count as 0, the others are clamped to [-1e6, 1e6].
inline glm::vec4 prefilter_msm_dequantize(const glm::vec4& q) {
    const float q0 = detail::pf_clamp_moment(q.x) - kPrefilterMsmOffset, q1 = detail::pf_clamp_moment(q.y);
    const float q2 = detail::pf_clamp_moment(q.z), q3 = detail::pf_clamp_moment(q.w);
    return glm::vec4(0.22277441459f * q0 + 0.0771972860781f * q1 + 0.792698663656f * q2 + 0.0319417554614f * q3,
                     0.154967926116f * q0 + 0.139462942654f * q1 + 0.796341583786f * q2 - 0.172282317302f * q3,
                     0.145198894564f * q0 + 0.212020215683f * q1 + 0.725869446385f * q2 - 0.275801481149f * q3,
                     0.163127442991f * q0 + 0.259143226644f * q1 + 0.653909249674f * q2 - 0.337613173406f * q3);
}

// ------------------------------------------------------------------------------------------------
// Lookups (mirrors of the GLSL; total: any input gives a visibility in [0, 1])
// ------------------------------------------------------------------------------------------------

namespace detail {
/// Chebyshev's one-sided bound P(z >= x) <= var / (var + (x - mean)^2) for x > mean (Donnelly &
/// Lauritzen 2006, eq. 5); 1 for x <= mean. var >= min_var >= 0; var = 0 gives 0 behind the mean.
inline float pf_chebyshev(float mean, float m2, float x, float min_var) {
    if (x <= mean) return 1.0f;
    float var = m2 - mean * mean;
    if (!(var >= min_var)) var = min_var;
    if (!(var > 0.0f)) return 0.0f;
    const float d = x - mean;
    const float p = var / (var + d * d);
    return p >= 0.0f ? (p > 1.0f ? 1.0f : p) : 0.0f;
}
/// VSM's bound made conservative in float: the mean and variance computed from stored moments of
/// depths in [0, 1] are off by at most EM and EV, so the bound with the mean moved EM toward x and
/// the variance raised by EV is never below Chebyshev's bound of the exact moments, hence never
/// below the lit fraction. EV = min_var + 4 u (m2 + mean^2), EM = min_var / 3 + 4 u |mean| (u =
/// 2^-24): min_var = 3 u_format bounds the storage error (NUMERICS item 4, the mean's is u_format
/// = min_var / 3); the u terms cover the fp32 arithmetic of the moment pass, the filter's
/// normalized sum and this lookup (measured: 1 u (m2 + mean^2) was needed over random two- and
/// three-depth texels in every format; without it Float32 was below the lit fraction by up to
/// 0.007). min_var = 0: exact moments assumed (plain Chebyshev, no margin).
inline float pf_vsm_bound(float mean, float m2, float x, float min_var) {
    if (!(min_var > 0.0f)) return pf_chebyshev(mean, m2, x, 0.0f);
    const float u = 5.9604645e-8f;
    const float em = min_var / 3.0f + 4.0f * u * std::fabs(mean);
    if (x <= mean + em) return 1.0f;
    float var = m2 - mean * mean;
    if (!(var >= 0.0f)) var = 0.0f;
    var += min_var + 4.0f * u * (std::fabs(m2) + mean * mean);
    const float d = x - mean - em;
    const float p = var / (var + d * d);
    return p >= 0.0f ? (p > 1.0f ? 1.0f : p) : 0.0f;
}
/// The light-bleeding reduction: linstep(amount, 1, p) (Lauritzen 2007); amount clamped to [0, 0.999].
inline float pf_linstep(float amount, float p) {
    const float a = pf_clamp(amount, 0.0f, 0.999f);
    const float v = (p - a) / (1.0f - a);
    return v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f;
}
/// Depths within this distance of the receiver count as at the receiver, not in front of it, for
/// moment bias a (clamped): the solve's rounding moves a support point at t by up to ~1e-5 (Float32
/// moments, a = 6e-7) and ~2e-4 (Unorm16 with the quantization, a = 3e-5), measured over the
/// single-depth texels t = i / 1e5 and two-depth texels; 32 a covers both with a margin, plus a few
/// ulps of t. Without it a surface at its own depth read rounding noise as an occluder.
inline float pf_msm_root_tolerance(float a) {
    return 32.0f * a + 4.0f * 5.9604645e-8f;
}
/// Largest D22 = b2 - b1^2 of biased moments b that one depth explains: the bias's own variance
/// (half of a at 0 and half at 1 mixed with one depth, mean b1: a / 4 + a (1 - a)(z - 1/2)^2 ~
/// a ((b1 - 1/2)^2 + 1/4)). Exact moments of any texel have at least that; below it only rounding
/// can put D22, and the variance it leaves the texel's depths is none: one depth.
inline float pf_msm_one_depth_variance(const glm::vec4& b, float a) {
    return a * ((b.x - 0.5f) * (b.x - 0.5f) + 0.25f);
}
/// Shadow of a texel whose Hankel matrix is singular (D33 <= 0): its depths are (numerically) two,
/// x1 and x2, the roots of x^2 - l32 x + (l32 b1 - b2) (the polynomial orthogonal to 1 and x), with
/// weights (x2 - b1) / (x2 - x1) and (b1 - x1) / (x2 - x1); G = the weight of those in front of z.
/// Falls back to a compare with the mean when that is not finite.
inline float pf_two_depths_shadow(const glm::vec4& b, float z, float l32, float tol) {
    const float a0 = l32 * b.x - b.y;
    float disc = l32 * l32 - 4.0f * a0;
    if (!(disc > 0.0f)) disc = 0.0f;
    const float s = std::sqrt(disc);
    const float x1 = 0.5f * (l32 - s), x2 = 0.5f * (l32 + s);
    const float w1 = (x2 - b.x) / (x2 - x1);
    const float zt = z - tol;  // depths within tol of z are at z: not in front
    float g = (x1 < zt ? w1 : 0.0f) + (x2 < zt ? 1.0f - w1 : 0.0f);
    if (!(g >= -1e30f && g <= 1e30f)) g = zt > b.x ? 1.0f : 0.0f;
    return g < 0.0f ? 0.0f : (g > 1.0f ? 1.0f : g);
}
/// Shadow intensity lower bound (0 lit .. 1 shadowed) of biased moments b at depth z, Hamburger.
/// z2, z3: the two other support points (z2 <= z3, both 0 after a fallback); solved: false when a
/// fallback was taken (one or two depths, or a root at infinity). moment_bias: the bias a mixed into
/// b (clamped to [0, 1]); support points within pf_msm_root_tolerance(a) of z count as at z, not in
/// front, and D22 at or below pf_msm_one_depth_variance (rounding below the bias's own variance) is
/// one depth.
inline float pf_msm_hamburger_shadow(const glm::vec4& b, float z, float& z2, float& z3, bool& solved, float moment_bias) {
    solved = false;
    const float a = pf_clamp(moment_bias, 0.0f, 1.0f), tol = pf_msm_root_tolerance(a);
    z2 = z3 = 0.0f;
    const float zt = z - tol;
    const float d22 = b.y - b.x * b.x;  // b2 - b1^2: variance
    if (!(d22 > pf_msm_one_depth_variance(b, a))) return zt > b.x ? 1.0f : 0.0f;  // one depth: a plain compare
    const float l32d22 = b.z - b.x * b.y;  // b3 - b1 b2
    const float l32 = l32d22 / d22;
    const float d33 = (b.w - b.y * b.y) - l32d22 * l32;  // b4 - b2^2 - (b3 - b1 b2)^2 / d22
    if (!(d33 > 0.0f)) return pf_two_depths_shadow(b, z, l32, tol);  // two depths: read them off
    // solve B c = (1, z, z^2) with B = L D L^T (L = [1 0 0; b1 1 0; b2 l32 1], D = diag(1, d22, d33))
    const float y2 = z - b.x;
    const float y3 = z * z - b.y - l32 * y2;
    const float c3 = y3 / d33;
    const float c2 = y2 / d22 - l32 * c3;
    const float c1 = 1.0f - b.x * c2 - b.y * c3;
    // the other two support points: roots of c1 + c2 x + c3 x^2 (real for a positive definite B)
    float disc = c2 * c2 - 4.0f * c1 * c3;
    if (!(disc > 0.0f)) disc = 0.0f;
    const float s = std::sqrt(disc);
    const float q = -0.5f * (c2 + (c2 >= 0.0f ? s : -s));
    const float r1 = q / c3, r2 = c1 / q;
    if (std::isnan(r1) || std::isnan(r2)) return pf_two_depths_shadow(b, z, l32, tol);
    z2 = r1 < r2 ? r1 : r2;
    z3 = r1 < r2 ? r2 : r1;
    float g;
    if (zt <= z2)
        g = 0.0f;
    else if (zt <= z3)  // weight of the support point z2 (Lagrange: E[(x - z)(x - z3)] / ((z2 - z)(z2 - z3)))
        g = (z * z3 - b.x * (z + z3) + b.y) / ((z3 - z2) * (z - z2));
    else  // 1 - weight of the support point z
        g = 1.0f - (z2 * z3 - b.x * (z2 + z3) + b.y) / ((z - z2) * (z - z3));
    if (!(g >= -1e30f && g <= 1e30f)) return pf_two_depths_shadow(b, z, l32, tol);  // NaN / Inf: a root at infinity
    solved = true;
    return g < 0.0f ? 0.0f : (g > 1.0f ? 1.0f : g);
}
/// The biased moments: mix(b, (1/2, 1/2, 1/2, 1/2), a), a clamped to [0, 1] (NaN -> 0).
inline glm::vec4 pf_msm_bias(const glm::vec4& b, float a) {
    const float k = pf_clamp(a, 0.0f, 1.0f);
    return (1.0f - k) * b + k * glm::vec4(0.5f);
}
}  // namespace detail

/// VSM visibility: Chebyshev's bound made conservative in float (the variance raised by
/// min_variance plus the fp32 rounding, the mean moved by its storage error: never below the lit
/// fraction of the texel's depths; detail::pf_vsm_bound), then the light-bleeding reduction
/// linstep(bleed_reduction, 1, p). Total: non-finite moments give 1, NaN t
/// gives 1, min_variance clamped to [0, 1] (NaN -> 0), bleed_reduction to [0, 0.999] (NaN -> 0).
inline float prefilter_vsm(const glm::vec2& moments, float t, float min_variance, float bleed_reduction) {
    if (!std::isfinite(moments.x) || !std::isfinite(moments.y) || std::isnan(t)) return 1.0f;
    const float p = detail::pf_vsm_bound(moments.x, moments.y, t, detail::pf_clamp(min_variance, 0.0f, 1.0f));
    return detail::pf_linstep(bleed_reduction, p);
}

/// ESM visibility min(1, e^(-c t) M) (Annen et al. 2008), c clamped to [0, 88.72] (NaN -> 0).
/// Total: a non-finite moment or NaN t gives 1, a negative one 0.
inline float prefilter_esm(float moment, float t, float c) {
    if (!std::isfinite(moment) || std::isnan(t)) return 1.0f;
    const float cc = detail::pf_clamp(c, 0.0f, detail::pf_max_esm_exponent);
    const float v = std::exp(-cc * detail::pf_clamp(t, -1.0f, 2.0f)) * moment;
    return v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f;
}

/// EVSM visibility (Lauritzen & McCool 2008): Chebyshev on the positive warp (moments.xy), and with
/// use_negative also on the negative warp (moments.zw), the minimum of both after the bleeding
/// reduction. min_variance is in t^2 units, scaled by the warp's squared slope (2 c w)^2.
/// Total: as prefilter_vsm; exponents clamped to [0, 44.36] (NaN -> 0).
inline float prefilter_evsm(const glm::vec4& moments, float t, float c_pos, float c_neg, bool use_negative,
                            float min_variance, float bleed_reduction) {
    if (!detail::pf_finite(moments) || std::isnan(t)) return 1.0f;
    const float x = 2.0f * detail::pf_clamp_depth(t) - 1.0f;
    const float mv = detail::pf_clamp(min_variance, 0.0f, 1.0f);
    const float cp = detail::pf_clamp(c_pos, 0.0f, detail::pf_max_evsm_exponent);
    const float wp = std::exp(cp * x);
    float sp = 2.0f * cp * wp;
    float vp = detail::pf_clamp(mv * sp * sp, 0.0f, 1e37f);
    float v = detail::pf_linstep(bleed_reduction, detail::pf_chebyshev(moments.x, moments.y, wp, vp));
    if (use_negative) {
        const float cn = detail::pf_clamp(c_neg, 0.0f, detail::pf_max_evsm_exponent);
        const float wn = -std::exp(-cn * x);
        const float sn = 2.0f * cn * wn;
        const float vn = detail::pf_clamp(mv * sn * sn, 0.0f, 1e37f);
        const float n = detail::pf_linstep(bleed_reduction, detail::pf_chebyshev(moments.z, moments.w, wn, vn));
        v = n < v ? n : v;
    }
    return v;
}

/// MSM visibility 1 - G, G the sharpest lower bound of the fraction of depths in front of t given
/// the four moments (Peters & Klein 2015, Algorithm 2, Hamburger: distributions on the real line),
/// after the moment bias mix(b, 1/2, moment_bias) and the bleeding reduction. `moments` are power
/// moments, or the optimized quantization's q with quantized = true. Degenerate texels (one or two
/// depths) fall back to a depth compare / the two-moment bound (NUMERICS item 5). Total: non-finite
/// moments or NaN t give 1; moment_bias clamped to [0, 1].
inline float prefilter_msm(const glm::vec4& moments, float t, float moment_bias, bool quantized, float bleed_reduction) {
    if (!detail::pf_finite(moments) || std::isnan(t)) return 1.0f;
    const glm::vec4 b = detail::pf_msm_bias(quantized ? prefilter_msm_dequantize(moments) : moments, moment_bias);
    float z2, z3;
    bool solved;
    const float g = detail::pf_msm_hamburger_shadow(b, detail::pf_clamp(t, -1.0f, 2.0f), z2, z3, solved, moment_bias);
    return detail::pf_linstep(bleed_reduction, 1.0f - g);
}

/// MSM visibility with the Hausdorff reconstruction: the sharpest lower bound over distributions on
/// [0, 1]. Equal to prefilter_msm when the Hamburger support points lie in [0, 1]; otherwise the
/// canonical representation through t with the end points, {0, t, z_free, 1}, where
/// E[x (x - t)(x - 1)(x - z_free)] = 0 gives z_free = E[x^2 (x - t)(x - 1)] / E[x (x - t)(x - 1)], and
/// G = w(0) + (z_free < t ? w(z_free) : 0) (weights by Lagrange interpolation). Never darker than
/// prefilter_msm. Total as prefilter_msm.
inline float prefilter_msm_hausdorff(const glm::vec4& moments, float t, float moment_bias, bool quantized,
                                     float bleed_reduction) {
    if (!detail::pf_finite(moments) || std::isnan(t)) return 1.0f;
    const glm::vec4 b = detail::pf_msm_bias(quantized ? prefilter_msm_dequantize(moments) : moments, moment_bias);
    const float z = detail::pf_clamp(t, -1.0f, 2.0f);
    float z2, z3;
    bool solved;
    const float tol = detail::pf_msm_root_tolerance(detail::pf_clamp(moment_bias, 0.0f, 1.0f));
    float g = detail::pf_msm_hamburger_shadow(b, z, z2, z3, solved, moment_bias);
    if (solved && (z2 < 0.0f || z3 > 1.0f) && z > tol && z < 1.0f) {  // z <= tol: nothing on [0, 1] is more than tol in front
        const float e3 = b.z - (1.0f + z) * b.y + z * b.x;  // E[x (x - z)(x - 1)]
        const float e4 = b.w - (1.0f + z) * b.z + z * b.y;  // E[x^2 (x - z)(x - 1)]
        const float zf = e4 / e3;
        // w(0) = E[(x - z)(x - zf)(x - 1)] / ((0 - z)(0 - zf)(0 - 1))
        const float e0 = b.z - (z + zf + 1.0f) * b.y + (z * zf + z + zf) * b.x - z * zf;
        float h = -e0 / (z * zf);
        if (zf < z - tol) h += e3 / (zf * (zf - z) * (zf - 1.0f));  // w(zf) = E[x (x - z)(x - 1)] / (zf (zf - z)(zf - 1))
        if (h >= -1e30f && h <= 1e30f) {
            h = h < 0.0f ? 0.0f : (h > 1.0f ? 1.0f : h);
            g = h > g ? h : g;  // the [0, 1] bound is never below the real-line one
        }
    }
    return detail::pf_linstep(bleed_reduction, 1.0f - g);
}

// ------------------------------------------------------------------------------------------------
// Settings -> uniforms, and the method-generic mirrors
// ------------------------------------------------------------------------------------------------

/// What a pre-filtered shadow map is set up with. Negative values of exponent_positive,
/// exponent_negative, min_variance and moment_bias mean "the format's default".
struct PrefilterSettings {
    PrefilterMethod method = PrefilterMethod::Vsm;
    PrefilterFormat format = PrefilterFormat::Float32;
    float exponent_positive = -1.0f;         ///< ESM c, EVSM c+ (< 0: 99% of prefilter_exponent_limit)
    float exponent_negative = -1.0f;         ///< EVSM4 c- (< 0: 5, or 99% of the limit if lower; NUMERICS item 3)
    std::uint32_t accumulated_samples = 1u;  ///< samples summed in the texture before normalizing (NUMERICS 2)
    float min_variance = -1.0f;              ///< VSM / EVSM, t^2 units (< 0: prefilter_min_variance(format))
    float bleed_reduction = 0.0f;            ///< linstep amount in [0, 1): 0 off, 0.2-0.4 typical
    float moment_bias = -1.0f;               ///< MSM (< 0: prefilter_msm_moment_bias(format))
};

/// The values the snippet's uniforms take (sk_prefilter_moments / sk_prefilter_visibility).
struct PrefilterUniforms {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    PrefilterMethod method = PrefilterMethod::Vsm;
    int method_code = 0;                ///< `method` of the GLSL functions
    glm::vec2 exponents{0.0f};          ///< (c+, c-)
    float min_variance = 0.0f;
    float bleed_reduction = 0.0f;
    float moment_bias = 0.0f;
    bool quantized = false;             ///< MSM in Unorm16: the optimized quantization on
    int channels = 0;                   ///< texture channels the method needs (1, 2 or 4)
    glm::vec4 clear_value{0.0f};        ///< the moments of t = 1 (nothing there): glClearBufferfv value
    glm::vec4 params() const { return glm::vec4(exponents.x, exponents.y, min_variance, bleed_reduction); }
};

inline glm::vec4 prefilter_moments(float t, const glm::vec2& dt, const PrefilterUniforms& u);

/// Checks the settings against the format and resolves the defaults. InvalidArgument: an unknown
/// method or format, an ESM / EVSM exponent_positive of 0 (e^(0 t) = 1: no shadow at all), a warp in Unorm16, MSM in Float16 (use Unorm16 with the quantization, or
/// Float32), accumulated_samples = 0, bleed_reduction outside [0, 1), min_variance > 1, moment_bias
/// > 1; NonFinite: a NaN/Inf setting; Overflow: an exponent above prefilter_exponent_limit (the
/// worst texel would be Inf).
inline PrefilterUniforms prefilter_uniforms(const PrefilterSettings& s) {
    PrefilterUniforms u;
    if (std::isnan(s.exponent_positive) || std::isinf(s.exponent_positive) || std::isnan(s.exponent_negative) ||
        std::isinf(s.exponent_negative) || !std::isfinite(s.min_variance) || !std::isfinite(s.bleed_reduction) ||
        !std::isfinite(s.moment_bias)) {
        u.status = Status::NonFinite;
        u.detail = std::isnan(s.exponent_positive) || std::isinf(s.exponent_positive) ? "exponent_positive: NaN or Inf"
                   : (std::isnan(s.exponent_negative) || std::isinf(s.exponent_negative) ? "exponent_negative: NaN or Inf"
                   : (!std::isfinite(s.min_variance) ? "min_variance: NaN or Inf"
                   : (!std::isfinite(s.bleed_reduction) ? "bleed_reduction: NaN or Inf" : "moment_bias: NaN or Inf")));
        return u;
    }
    const auto m = static_cast<int>(s.method);
    const auto f = static_cast<int>(s.format);
    const bool warp = s.method == PrefilterMethod::Esm || s.method == PrefilterMethod::Evsm2 || s.method == PrefilterMethod::Evsm4;
    const bool msm = s.method == PrefilterMethod::Msm || s.method == PrefilterMethod::MsmHausdorff;
    if (m < 0 || m > 5 || f < 0 || f > 2 || s.accumulated_samples == 0u || (warp && s.format == PrefilterFormat::Unorm16) ||
        (warp && s.exponent_positive == 0.0f) ||
        (msm && s.format == PrefilterFormat::Float16) || s.bleed_reduction < 0.0f || !(s.bleed_reduction < 1.0f) ||
        s.min_variance > 1.0f || s.moment_bias > 1.0f) {
        u.status = Status::InvalidArgument;
        u.detail = m < 0 || m > 5 ? "method: unknown PrefilterMethod"
                   : (f < 0 || f > 2 ? "format: unknown PrefilterFormat"
                   : (s.accumulated_samples == 0u ? "accumulated_samples: 0"
                   : (warp && s.format == PrefilterFormat::Unorm16 ? "format: Unorm16 with ESM / EVSM"
                   : (warp && s.exponent_positive == 0.0f ? "exponent_positive: 0 with ESM / EVSM"
                   : (msm && s.format == PrefilterFormat::Float16 ? "format: Float16 with MSM"
                   : (s.bleed_reduction < 0.0f || !(s.bleed_reduction < 1.0f) ? "bleed_reduction: outside [0, 1)"
                   : (s.min_variance > 1.0f ? "min_variance: > 1" : "moment_bias: > 1")))))));
        return u;
    }
    u.method = s.method;
    u.method_code = m;
    u.bleed_reduction = s.bleed_reduction;
    u.min_variance = s.min_variance < 0.0f ? prefilter_min_variance(s.format) : s.min_variance;
    u.moment_bias = msm ? (s.moment_bias < 0.0f ? prefilter_msm_moment_bias(s.format) : s.moment_bias) : 0.0f;
    u.quantized = msm && s.format == PrefilterFormat::Unorm16;
    if (warp) {
        const PrefilterExponent lim = prefilter_exponent_limit(s.method, s.format, s.accumulated_samples);
        if (lim.status != Status::Ok) {
            u.status = lim.status;
            u.detail = lim.detail;
            return u;
        }
        const float c_pos = s.exponent_positive < 0.0f ? 0.99f * lim.exponent : s.exponent_positive;
        const float c_neg_default = 0.99f * lim.exponent < 5.0f ? 0.99f * lim.exponent : 5.0f;
        const float c_neg = s.method != PrefilterMethod::Evsm4 ? 0.0f
                            : (s.exponent_negative < 0.0f ? c_neg_default : s.exponent_negative);
        if (c_pos > lim.exponent || c_neg > lim.exponent) {
            u.status = Status::Overflow;
            u.detail = c_pos > lim.exponent ? "exponent_positive: above prefilter_exponent_limit"
                                            : "exponent_negative: above prefilter_exponent_limit";
            return u;
        }
        u.exponents = glm::vec2(c_pos, c_neg);
    }
    switch (s.method) {
    case PrefilterMethod::Vsm: u.channels = 2; break;
    case PrefilterMethod::Esm: u.channels = 1; break;
    case PrefilterMethod::Evsm2: u.channels = 2; break;
    default: u.channels = 4; break;
    }
    u.status = Status::Ok;
    u.clear_value = prefilter_moments(1.0f, glm::vec2(0.0f), u);
    return u;
}

/// The moments the snippet's moment pass writes for a fragment at moment depth t (mirror of
/// sk_prefilter_moments): VSM (t, t^2 + derivative term, 0, 0), ESM (e^(c t), 0, 0, 0), EVSM2 /
/// EVSM4 the warps (EVSM2: zw = 0), MSM the power moments or their quantization. Total (as the
/// per-method functions); a uniforms struct whose status is not Ok gives the VSM moments.
inline glm::vec4 prefilter_moments(float t, const glm::vec2& dt, const PrefilterUniforms& u) {
    switch (u.status == Status::Ok ? u.method : PrefilterMethod::Vsm) {
    case PrefilterMethod::Esm: return glm::vec4(prefilter_esm_moment(t, u.exponents.x), 0.0f, 0.0f, 0.0f);
    case PrefilterMethod::Evsm2: {
        const glm::vec4 e = prefilter_evsm_moments(t, u.exponents.x, 0.0f);
        return glm::vec4(e.x, e.y, 0.0f, 0.0f);
    }
    case PrefilterMethod::Evsm4: return prefilter_evsm_moments(t, u.exponents.x, u.exponents.y);
    case PrefilterMethod::Msm:
    case PrefilterMethod::MsmHausdorff: {
        const glm::vec4 b = prefilter_msm_moments(t);
        return u.quantized ? prefilter_msm_quantize(b) : b;
    }
    case PrefilterMethod::Vsm: break;
    }
    const glm::vec2 v = prefilter_vsm_moments(t, dt.x, dt.y);
    return glm::vec4(v.x, v.y, 0.0f, 0.0f);
}

/// Visibility of a receiver at moment depth t (already biased) from filtered moments (mirror of
/// sk_prefilter_visibility). Total: in [0, 1] for any moments and t; a uniforms struct whose status
/// is not Ok gives 1.
inline float prefilter_visibility(const glm::vec4& moments, float t, const PrefilterUniforms& u) {
    if (u.status != Status::Ok) return 1.0f;
    switch (u.method) {
    case PrefilterMethod::Vsm: return prefilter_vsm(glm::vec2(moments), t, u.min_variance, u.bleed_reduction);
    case PrefilterMethod::Esm: return prefilter_esm(moments.x, t, u.exponents.x);
    case PrefilterMethod::Evsm2:
        return prefilter_evsm(glm::vec4(moments.x, moments.y, 0.0f, 0.0f), t, u.exponents.x, 0.0f, false, u.min_variance,
                              u.bleed_reduction);
    case PrefilterMethod::Evsm4:
        return prefilter_evsm(moments, t, u.exponents.x, u.exponents.y, true, u.min_variance, u.bleed_reduction);
    case PrefilterMethod::Msm: return prefilter_msm(moments, t, u.moment_bias, u.quantized, u.bleed_reduction);
    case PrefilterMethod::MsmHausdorff:
        return prefilter_msm_hausdorff(moments, t, u.moment_bias, u.quantized, u.bleed_reduction);
    }
    return 1.0f;
}

/// Receiver-plane depth bias for a filtered lookup (mirror of sk_prefilter_receiver_bias): a receiver
/// on a plane tilted against the light has depths spread over the filter region, half of them in
/// front of it; every method then shadows it partly (MSM and EVSM's negative warp most). Shifting the
/// receiver by the plane's depth change across the kernel, r (|dt/du| + |dt/dv|), removes that.
/// duvt_dx, duvt_dy: the changes of (u, v, t) between two neighbouring points of the receiver plane
/// (screen derivatives, or two tangent steps), which give dt/duv by a 2x2 solve (Isidoro 2006);
/// kernel_radius_uv: the blur's radius (plus one texel for the bilinear tap) in uv. Total: 0 for a
/// plane seen edge-on from the light (singular solve) or non-finite input; clamped to [0, 1].
inline float prefilter_receiver_bias(const glm::vec3& duvt_dx, const glm::vec3& duvt_dy, float kernel_radius_uv) {
    const float det = duvt_dx.x * duvt_dy.y - duvt_dx.y * duvt_dy.x;
    const float scale = (std::fabs(duvt_dx.x) + std::fabs(duvt_dx.y)) * (std::fabs(duvt_dy.x) + std::fabs(duvt_dy.y));
    if (!(std::fabs(det) > 1e-7f * scale) || !(std::fabs(det) > 0.0f)) return 0.0f;
    const float gx = (duvt_dy.y * duvt_dx.z - duvt_dx.y * duvt_dy.z) / det;
    const float gy = (duvt_dx.x * duvt_dy.z - duvt_dy.x * duvt_dx.z) / det;
    const float b = detail::pf_clamp(kernel_radius_uv, 0.0f, 1.0f) * (std::fabs(gx) + std::fabs(gy));
    return detail::pf_clamp(b, 0.0f, 1.0f);
}

// ------------------------------------------------------------------------------------------------
// Filtering
// ------------------------------------------------------------------------------------------------

/// A separable blur kernel.
struct PrefilterKernel {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    int radius = 0;          ///< taps -radius .. radius per pass
    std::size_t count = 0;   ///< weights written (radius + 1: center, then offsets 1 .. radius)
    std::size_t needed = 0;  ///< weights the kernel needs (radius + 1)
};

/// One-sided weights of a separable kernel of full width `width_texels` (Box: radius
/// round((width - 1) / 2), equal weights; Gaussian: sigma = width / 6, radius floor(3 sigma)),
/// normalized so weights[0] + 2 sum_{i >= 1} weights[i] = 1. `weights` holds `weights_capacity`
/// float elements; it needs radius + 1 (`needed`, at most kPrefilterMaxWeights). width <= 1 gives
/// radius 0 (weights[0] = 1: no blur). NonFinite: NaN/Inf width; InvalidArgument: width < 0,
/// a radius above kPrefilterMaxRadius, a null buffer with capacity > 0, an unknown shape;
/// BufferTooSmall: capacity < needed (count = 0).
inline PrefilterKernel prefilter_blur_weights(PrefilterBlur shape, float width_texels, float* weights,
                                              std::size_t weights_capacity) {
    PrefilterKernel k;
    if (!std::isfinite(width_texels)) {
        k.status = Status::NonFinite;
        k.detail = "width_texels: NaN or Inf";
        return k;
    }
    if (width_texels < 0.0f || (weights == nullptr && weights_capacity > 0) ||
        (shape != PrefilterBlur::Box && shape != PrefilterBlur::Gaussian) || width_texels > 2.0f * kPrefilterMaxRadius + 1.0f) {
        k.status = Status::InvalidArgument;
        k.detail = width_texels < 0.0f ? "width_texels: < 0"
                   : (weights == nullptr && weights_capacity > 0 ? "weights: null with weights_capacity > 0"
                   : (shape != PrefilterBlur::Box && shape != PrefilterBlur::Gaussian ? "shape: unknown PrefilterBlur"
                                                                                        : "width_texels: > 2 kPrefilterMaxRadius + 1"));
        return k;
    }
    const double sigma = double(width_texels) / 6.0;
    int r = 0;
    if (width_texels > 1.0f)
        r = shape == PrefilterBlur::Box ? static_cast<int>(std::lround((double(width_texels) - 1.0) * 0.5))
                                        : static_cast<int>(std::floor(3.0 * sigma + 1e-9));
    if (r > kPrefilterMaxRadius) {
        k.status = Status::InvalidArgument;
        k.detail = "width_texels: radius above kPrefilterMaxRadius";
        return k;
    }
    k.radius = r;
    k.needed = static_cast<std::size_t>(r) + 1u;
    if (weights_capacity < k.needed) {
        k.status = Status::BufferTooSmall;
        k.detail = "weights_capacity: below needed (see needed)";
        return k;
    }
    double w[kPrefilterMaxWeights];
    double sum = 0.0;
    for (int i = 0; i <= r; ++i) {
        w[i] = shape == PrefilterBlur::Box || r == 0 ? 1.0 : std::exp(-double(i) * double(i) / (2.0 * sigma * sigma));
        sum += i == 0 ? w[i] : 2.0 * w[i];
    }
    for (int i = 0; i <= r; ++i) weights[i] = static_cast<float>(w[i] / sum);
    k.count = k.needed;
    k.status = Status::Ok;
    return k;
}

/// A world width in shadow-map texels.
struct PrefilterKernelWidth {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    glm::vec2 texels{0.0f};  ///< along the map's x and y
};

/// Texels that a world width covers at eye distance `eye_distance` from a light with projection
/// `light_proj` (glm, right-handed: view z = -d) on a map_width x map_height map: the uv width is
/// 0.5 |P[0][0]| W / w (x) and 0.5 |P[1][1]| W / w (y), w = P[2][3] (-d) + P[3][3] the clip w at that
/// distance (d for a perspective light, 1 for an orthographic one), times the map size. Any glm
/// projection works (infinite far planes too). Feed the result to prefilter_blur_weights (a
/// perspective light's blur is uniform in texels: evaluate at the receivers' typical distance).
/// NonFinite: NaN/Inf input; InvalidArgument: world_width < 0, map size <= 0, clip w <= 0 at that
/// distance; Overflow: a result beyond float.
inline PrefilterKernelWidth prefilter_kernel_texels(const glm::mat4& light_proj, float world_width, float eye_distance,
                                                    int map_width, int map_height) {
    PrefilterKernelWidth r;
    bool finite = std::isfinite(world_width) && std::isfinite(eye_distance);
    for (int c = 0; c < 4; ++c)
        for (int i = 0; i < 4; ++i) finite = finite && std::isfinite(light_proj[c][i]);
    if (!finite) {
        r.status = Status::NonFinite;
        r.detail = !std::isfinite(world_width) ? "world_width: NaN or Inf"
                   : (!std::isfinite(eye_distance) ? "eye_distance: NaN or Inf" : "light_proj: NaN or Inf");
        return r;
    }
    const double w = -double(light_proj[2][3]) * double(eye_distance) + double(light_proj[3][3]);
    if (world_width < 0.0f || map_width <= 0 || map_height <= 0 || !(w > 0.0)) {
        r.status = Status::InvalidArgument;
        r.detail = world_width < 0.0f ? "world_width: < 0"
                   : (map_width <= 0 ? "map_width: not > 0"
                   : (map_height <= 0 ? "map_height: not > 0" : "eye_distance: at or behind the light (clip w <= 0)"));
        return r;
    }
    const double tx = 0.5 * std::abs(double(light_proj[0][0])) * double(world_width) / w * double(map_width);
    const double ty = 0.5 * std::abs(double(light_proj[1][1])) * double(world_width) / w * double(map_height);
    if (!(tx < double(std::numeric_limits<float>::max())) || !(ty < double(std::numeric_limits<float>::max()))) {
        r.status = Status::Overflow;
        r.detail = "texels: beyond float range";
        return r;
    }
    r.texels = glm::vec2(static_cast<float>(tx), static_cast<float>(ty));
    r.status = Status::Ok;
    return r;
}

// ------------------------------------------------------------------------------------------------
// Soft shadows with contact hardening (NUMERICS item 7)
// ------------------------------------------------------------------------------------------------

/// What the soft lookup needs besides the method's uniforms: the map's perspective projection, the
/// emitter's width and the depth range the map encodes. Every field is required.
struct PrefilterSoftSettings {
    glm::mat4 light_proj = glm::mat4(0.0f);  ///< the map's perspective projection, from the emitter's center (required)
    float light_width = -1.0f;               ///< the emitter's width in world units, >= 0 (required; 0: the hard lookup)
    PrefilterDepthRange range;               ///< prefilter_depth_range of the map (required: status Ok, near > 0)
    int map_size = 0;                        ///< texels per side of the square moment map, mipmapped to 1x1 (required)
};

/// The soft lookup's uniforms: `params()` is the `soft` vec4 of sk_prefilter_soft_visibility.
struct PrefilterSoftUniforms {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    float light_uv = 0.0f;         ///< 0.5 sqrt|P[0][0] P[1][1]| light_width / -P[2][3]: the emitter's uv width x unit distance
    float light_width = 0.0f;      ///< world units
    float distance_scale = 0.0f;   ///< eye distance d = t * distance_scale + distance_offset
    float distance_offset = 0.0f;  ///< (the inverse of the depth range: d(0) = near, d(1) = far)
    float map_size = 0.0f;         ///< texels per side
    float max_level = 0.0f;        ///< log2(map_size): the 1x1 level
    glm::vec4 params() const { return glm::vec4(light_uv, distance_scale, distance_offset, map_size); }
};

/// Checks the soft settings. NonFinite: NaN/Inf in light_proj or light_width; InvalidArgument: a
/// projection that is not perspective (P[3][3] != 0 or P[2][3] >= 0: an orthographic map has no
/// emitter size here), light_width < 0 (the default), a range whose status is not Ok or whose near
/// end is 0 (blockers at distance 0 make every penumbra infinite), map_size <= 0 (the default) or
/// not a power of two (the mip chain halves it down to 1); Overflow: light_uv beyond float.
inline PrefilterSoftUniforms prefilter_soft_uniforms(const PrefilterSoftSettings& s) {
    PrefilterSoftUniforms u;
    bool finite = std::isfinite(s.light_width);
    for (int c = 0; c < 4; ++c)
        for (int i = 0; i < 4; ++i) finite = finite && std::isfinite(s.light_proj[c][i]);
    if (!finite) {
        u.status = Status::NonFinite;
        u.detail = !std::isfinite(s.light_width) ? "light_width: NaN or Inf" : "light_proj: NaN or Inf";
        return u;
    }
    const double p23 = double(s.light_proj[2][3]);
    const double ds = s.range.status == Status::Ok && s.range.scale > 0.0f ? 1.0 / double(s.range.scale) : 0.0;
    // the range's near end as given (its offset underflows for tiny near / far ratios: [1e-30, 1e30]
    // has offset -1e-60, 0 in float); a range built by hand has only scale and offset
    const double near = s.range.near_z > 0.0f ? double(s.range.near_z) : -double(s.range.offset) * ds;
    const bool pow2 = s.map_size > 0 && (s.map_size & (s.map_size - 1)) == 0;
    if (s.light_proj[3][3] != 0.0f || !(p23 < 0.0) || s.light_width < 0.0f || !(ds > 0.0) || !(near > 0.0) || !pow2) {
        u.status = Status::InvalidArgument;
        u.detail = s.light_proj[3][3] != 0.0f || !(p23 < 0.0) ? "light_proj: not a perspective projection"
                   : (s.light_width < 0.0f ? "light_width: < 0"
                   : (!(ds > 0.0) ? "range: status not Ok or scale not > 0"
                   : (!(near > 0.0) ? "range: near not > 0" : "map_size: not a power of two")));
        return u;
    }
    const double luv = 0.5 * std::sqrt(std::abs(double(s.light_proj[0][0]) * double(s.light_proj[1][1]))) *
                       double(s.light_width) / -p23;
    if (!(luv < double(std::numeric_limits<float>::max())) || !(ds < double(std::numeric_limits<float>::max()))) {
        u.status = Status::Overflow;
        u.detail = !(luv < double(std::numeric_limits<float>::max())) ? "light_width: light_uv beyond float range"
                                                                      : "range: 1 / scale beyond float range";
        return u;
    }
    u.light_uv = static_cast<float>(luv);
    u.light_width = s.light_width;
    u.distance_scale = static_cast<float>(ds);
    u.distance_offset = static_cast<float>(near);
    u.map_size = static_cast<float>(s.map_size);
    u.max_level = static_cast<float>(std::log2(double(s.map_size)));
    u.status = Status::Ok;
    return u;
}

/// The average blocker depth in front of a receiver, estimated from one filtered moment texel.
struct PrefilterBlocker {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    bool blocker_found = false;  ///< false (with Ok): nothing in front of t in this texel (lit)
    float depth = 0.0f;          ///< average blocker depth in t units, in [0, t] (t when none is found)
    float fraction = 0.0f;       ///< the blockers' share of the texel, in [0, 1]
};

/// Blockers covering at most this share of the search region (or, MSM, at most the moment bias,
/// which puts half of its weight at depth 0 on every texel) are not blockers: no blocker found.
constexpr float kPrefilterSoftMinBlocker = 1e-3f;

namespace detail {
/// The blockers of moments b in front of z as (fraction, mean depth): VSM (Yang et al. 2010, VSSM:
/// the non-blockers sit at z, mean = p z + (1 - p) z_avg with p = Chebyshev's bound); MSM from the
/// canonical representation through z (after Peters et al. 2016: the support points in front of z
/// are the blockers); the two-depth and one-depth fallbacks read them off. Exact for a two-depth texel.
inline glm::vec2 pf_soft_blocker(const glm::vec4& moments, float t, const PrefilterUniforms& u) {
    const float z = pf_clamp(t, 0.0f, 1.0f);
    if (!pf_finite(moments) || std::isnan(t)) return glm::vec2(0.0f, z);
    float frac = 0.0f, depth = z;
    if (u.method == PrefilterMethod::Vsm) {
        const float p = pf_vsm_bound(moments.x, moments.y, z, pf_clamp(u.min_variance, 0.0f, 1.0f));
        frac = 1.0f - p;
        if (frac > 0.0f) depth = (moments.x - p * z) / frac;  // Yang et al. 2010: mu = p z + (1 - p) z_avg
    } else {
        const glm::vec4 b = pf_msm_bias(u.quantized ? prefilter_msm_dequantize(moments) : moments, u.moment_bias);
        const float d22 = b.y - b.x * b.x;
        const float tol = pf_msm_root_tolerance(pf_clamp(u.moment_bias, 0.0f, 1.0f)), zt = z - tol;
        if (!(d22 > pf_msm_one_depth_variance(b, pf_clamp(u.moment_bias, 0.0f, 1.0f)))) {  // one depth
            if (zt > b.x) frac = 1.0f, depth = b.x;
        } else {
            float z2, z3;
            bool solved;
            const float g = pf_msm_hamburger_shadow(b, z, z2, z3, solved, u.moment_bias);
            if (solved) {
                frac = g;
                if (zt <= z3) depth = z2;  // the one support point in front of z
                else if (g > 0.0f) depth = (b.x - (1.0f - g) * z) / g;  // E[x; x < z] = b1 - w(z) z
            } else {  // two depths x1 <= x2 (D33 <= 0): the ones in front of z
                const float l32 = (b.z - b.x * b.y) / d22;
                float disc = l32 * l32 - 4.0f * (l32 * b.x - b.y);
                if (!(disc > 0.0f)) disc = 0.0f;
                const float s = std::sqrt(disc), x1 = 0.5f * (l32 - s), x2 = 0.5f * (l32 + s);
                const float w1 = (x2 - b.x) / (x2 - x1);
                if (x2 < zt) frac = 1.0f, depth = b.x;
                else if (x1 < zt && w1 >= 0.0f && w1 <= 1.0f) frac = w1, depth = x1;
                else if (!(w1 >= 0.0f && w1 <= 1.0f) && zt > b.x) frac = 1.0f, depth = b.x;  // NaN weight: the mean
            }
        }
    }
    // the moment bias puts a/2 of a sample at 0 (a phantom blocker on every texel): ignore shares below it
    const float min_share = u.method == PrefilterMethod::Vsm ? kPrefilterSoftMinBlocker
                                                         : (u.moment_bias > kPrefilterSoftMinBlocker ? u.moment_bias : kPrefilterSoftMinBlocker);
    if (!(frac > min_share) || !(depth <= 1e30f && depth >= -1e30f)) return glm::vec2(0.0f, z);
    return glm::vec2(frac > 1.0f ? 1.0f : frac, pf_clamp(depth, 0.0f, z));
}
}  // namespace detail

/// The average depth of the blockers in front of a receiver at moment depth t (already biased), from
/// the moments filtered over the blocker-search region (mirror of sk_prefilter_soft_blocker). VSM:
/// Chebyshev's p with the non-blockers at t, z_avg = (E[z] - p t) / (1 - p) (Yang et al. 2010); MSM / MSM Hausdorff: the canonical representation through t of the biased moments
/// (after Peters et al. 2016): its support points in front of t, averaged by weight. For a texel of
/// two depths z1 < z2 MSM is exact up to its moment bias for any t; VSM only for t = z2 (below it p is
/// not the blockers' share: 0.1 at 0.2 over 0.8 gives 0.181 at t = z2 - 0.002, 0.092 at z2 - 0.01). A share at or
/// below kPrefilterSoftMinBlocker (MSM: or the moment bias) is no blocker. Ok for any moments and t (a non-finite moment
/// or NaN t: no blocker). InvalidArgument: uniforms whose status is not Ok, or ESM / EVSM (no
/// blocker estimate here: their soft lookup is the hard one).
inline PrefilterBlocker prefilter_soft_blocker(const glm::vec4& moments, float t, const PrefilterUniforms& u) {
    PrefilterBlocker r;
    if (u.status != Status::Ok || !(u.method == PrefilterMethod::Vsm || u.method == PrefilterMethod::Msm ||
                                    u.method == PrefilterMethod::MsmHausdorff)) {
        r.status = Status::InvalidArgument;
        r.detail = u.status != Status::Ok ? "u: status not Ok" : "u: method not VSM or MSM";
        return r;
    }
    const glm::vec2 b = detail::pf_soft_blocker(moments, t, u);
    r.blocker_found = b.x > 0.0f;
    r.fraction = b.x;
    r.depth = b.y;
    r.status = Status::Ok;
    return r;
}

/// Mip level of the moment map whose trilinear lookup filters like a box of full width `width_uv`
/// (uv units) (mirror of sk_prefilter_soft_level_of): a box of K texels has variance K^2 / 12, a
/// bilinear lookup at level L a box of 2^L texels convolved with a tent of 2^L: variance 4^L / 4, so
/// L = log2(K / sqrt(3)). Total: clamped to [0, max_level]; NaN or uniforms not Ok give 0.
inline float prefilter_soft_level_of(float width_uv, const PrefilterSoftUniforms& s) {
    if (s.status != Status::Ok || !(width_uv > 0.0f)) return 0.0f;
    const float k = width_uv * s.map_size * 0.57735027f;  // K / sqrt(3)
    if (!(k > 1.0f)) return 0.0f;
    const float l = std::log2(k);
    return l < s.max_level ? l : s.max_level;
}

/// Full width of the penumbra in uv that blockers at moment depth t_front cast on a receiver at
/// t_receiver (mirror of sk_prefilter_soft_width): similar triangles, w = W (d_r - d_b) / d_b at the
/// receiver (Fernando 2005; Apelles eq. 3.21), in the map's uv at d_r: light_uv (1 / d_b - 1 / d_r). With
/// t_front = 0 (the range's near end: the nearest a caster can be) it is the blocker-search region.
/// Total: t's clamped to [0, 1] (NaN t_receiver: 0, NaN t_front: 0), t_front > t_receiver gives 0,
/// clamped to [0, 1] (a region wider than the map); uniforms not Ok give 0.
inline float prefilter_soft_width(float t_receiver, float t_front, const PrefilterSoftUniforms& s) {
    if (s.status != Status::Ok || std::isnan(t_receiver)) return 0.0f;
    const float tr = detail::pf_clamp(t_receiver, 0.0f, 1.0f), tb = detail::pf_clamp(t_front, 0.0f, tr);
    const float dr = tr * s.distance_scale + s.distance_offset, db = tb * s.distance_scale + s.distance_offset;
    const float w = s.light_uv * (1.0f / db - 1.0f / dr);
    return detail::pf_clamp(w, 0.0f, 1.0f);
}

/// The penumbra a blocker casts on a receiver.
struct PrefilterPenumbra {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    float width_world = 0.0f;  ///< full width at the receiver, world units: W (d_r - d_b) / d_b
    float width_uv = 0.0f;     ///< the same in the map's uv, in [0, 1] (prefilter_soft_width)
    float level = 0.0f;        ///< the mip level that filters it, in [0, max_level] (prefilter_soft_level_of)
};

/// The penumbra of blockers at moment depth t_blocker on a receiver at t_receiver (Fernando 2005;
/// Apelles eq. 3.21). NonFinite: NaN/Inf t; InvalidArgument: uniforms not Ok, t outside [0, 1], t_blocker >
/// t_receiver; Overflow: a world width beyond float.
inline PrefilterPenumbra prefilter_soft_penumbra(float t_receiver, float t_blocker, const PrefilterSoftUniforms& s) {
    PrefilterPenumbra r;
    if (!std::isfinite(t_receiver) || !std::isfinite(t_blocker)) {
        r.status = Status::NonFinite;
        r.detail = !std::isfinite(t_receiver) ? "t_receiver: NaN or Inf" : "t_blocker: NaN or Inf";
        return r;
    }
    if (s.status != Status::Ok || t_receiver < 0.0f || t_receiver > 1.0f || t_blocker < 0.0f || t_blocker > t_receiver) {
        r.status = Status::InvalidArgument;
        r.detail = s.status != Status::Ok ? "s: status not Ok"
                   : (t_receiver < 0.0f || t_receiver > 1.0f ? "t_receiver: outside [0, 1]" : "t_blocker: outside [0, t_receiver]");
        return r;
    }
    const double dr = double(t_receiver) * s.distance_scale + s.distance_offset;
    const double db = double(t_blocker) * s.distance_scale + s.distance_offset;
    const double w = double(s.light_width) * (dr - db) / db;
    if (!(w < double(std::numeric_limits<float>::max()))) {
        r.status = Status::Overflow;
        r.detail = "width_world: beyond float range";
        return r;
    }
    r.width_world = static_cast<float>(w);
    r.width_uv = prefilter_soft_width(t_receiver, t_blocker, s);
    r.level = prefilter_soft_level_of(r.width_uv, s);
    r.status = Status::Ok;
    return r;
}

/// The receiver plane's depth slope |dt/du| + |dt/dv| (mirror of sk_prefilter_receiver_slope): the
/// same 2x2 solve as prefilter_receiver_bias (Isidoro 2006) without a kernel radius, for the soft
/// lookup, whose kernel changes per pixel. Total: 0 for a singular solve or non-finite input,
/// clamped to [0, 1e6].
inline float prefilter_receiver_slope(const glm::vec3& duvt_dx, const glm::vec3& duvt_dy) {
    const float det = duvt_dx.x * duvt_dy.y - duvt_dx.y * duvt_dy.x;
    const float scale = (std::fabs(duvt_dx.x) + std::fabs(duvt_dx.y)) * (std::fabs(duvt_dy.x) + std::fabs(duvt_dy.y));
    if (!(std::fabs(det) > 1e-7f * scale) || !(std::fabs(det) > 0.0f)) return 0.0f;
    const float gx = (duvt_dy.y * duvt_dx.z - duvt_dx.y * duvt_dy.z) / det;
    const float gy = (duvt_dx.x * duvt_dy.z - duvt_dy.x * duvt_dx.z) / det;
    return detail::pf_clamp(std::fabs(gx) + std::fabs(gy), 0.0f, 1e6f);
}

/// Soft visibility with contact hardening (mirror of sk_prefilter_soft_visibility): 1. the moments
/// over the blocker-search region (the penumbra of a blocker at the range's near end) at mip level
/// L_s; 2. the average blocker depth from them (prefilter_soft_blocker); 3. the moments over the
/// penumbra of that depth (its level L_p <= L_s), or, with no blocker found, level 0 (the hard
/// lookup: a search region's moments can hide a small blocker close in front, which level 0 still
/// resolves); 4. prefilter_visibility of those. `sample_level(level)` returns the moment map's
/// trilinear lookup at the receiver's uv at that (fractional) level: textureLod(moments, uv, level).
/// receiver_slope = (slope, cap): each step compares t - min(slope r, cap), r the half width of its
/// region in uv, slope = prefilter_receiver_slope of the receiver plane (0, 0: no receiver-plane
/// bias; a lit face steep to the light otherwise shadows itself under a wide kernel; the cap keeps
/// umbrae right behind occluders on grazing receivers dark). light_width 0, ESM and EVSM give the
/// hard lookup prefilter_visibility(sample_level(0), t, u). Total: in [0, 1] for any samples (NaN/Inf
/// included); uniforms `u` not Ok give 1, `s` not Ok the hard lookup; NaN slopes count as 0.
template <class SampleLevel>
inline float prefilter_soft_visibility(SampleLevel&& sample_level, float t, const PrefilterUniforms& u,
                                       const PrefilterSoftUniforms& s, const glm::vec2& receiver_slope = glm::vec2(0.0f)) {
    if (u.status != Status::Ok) return 1.0f;
    const bool soft = s.status == Status::Ok && s.light_uv > 0.0f &&
                      (u.method == PrefilterMethod::Vsm || u.method == PrefilterMethod::Msm || u.method == PrefilterMethod::MsmHausdorff);
    if (!soft) return prefilter_visibility(sample_level(0.0f), t, u);
    const float slope = detail::pf_clamp(receiver_slope.x, 0.0f, 1e6f), cap = detail::pf_clamp(receiver_slope.y, 0.0f, 1.0f);
    auto biased = [&](float width_uv) {
        const float b = slope * 0.5f * width_uv;
        return t - (b < cap ? b : cap);
    };
    const float ws = prefilter_soft_width(t, 0.0f, s);
    const glm::vec2 b = detail::pf_soft_blocker(sample_level(prefilter_soft_level_of(ws, s)), biased(ws), u);
    const float wf = b.x > 0.0f ? prefilter_soft_width(t, b.y, s) : 0.0f;
    return prefilter_visibility(sample_level(prefilter_soft_level_of(wf, s)), biased(wf), u);
}

}  // namespace shadowkit
