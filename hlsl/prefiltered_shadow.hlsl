// shadowkit/hlsl/prefiltered_shadow.hlsl - pre-filtered shadow maps in HLSL: moment pass, blur, MSAA resolve, lookups (VSM, ESM, EVSM2/4, MSM Hamburger and Hausdorff).
// stages: pixel, compute
//
// The HLSL twin of glsl/prefiltered_shadow.glsl: the same sk_ functions, arguments, results and
// arithmetic (its header says the passes, the formats and the numerics; shadowkit/prefiltered_shadow.hpp
// mirrors the lookups on the CPU and computes the uniforms). Differences: the moment map is a
// Texture2D<float4>; the soft lookup takes a SamplerState (trilinear, clamp) right after it, the blur
// reads with Load, the MSAA resolve takes a Texture2DMS<float>. Direct3D and Vulkan: the window-depth
// map of prefilter_window_depth_map with ClipDepth::ZeroToOne.
// Compiled in the tests by glslang's HLSL front end to SPIR-V and the lookups run on Vulkan; written
// for DXC (shader model 6.0) as well, but not compiled with it here (DXC is not packaged in Debian 12).
// MIT License. Copyright (c) shadowkit contributors.

#ifndef SK_PREFILTER_MAX_WEIGHTS
#define SK_PREFILTER_MAX_WEIGHTS 33
#endif

// ---------------------------------------------------------------------------------------- helpers
// x clamped to [lo, hi]; NaN -> lo.
float sk_pf_clamp(float x, float lo, float hi) {
    if (!(x >= lo)) return lo;
    return x > hi ? hi : x;
}
// t sanitized: NaN -> 1, clamped to [0, 1]
float sk_pf_depth(float t) {
    if (!(t >= 0.0)) return isnan(t) ? 1.0 : 0.0;
    return t > 1.0 ? 1.0 : t;
}
bool sk_pf_finite(float4 m) {
    return !any(isnan(m)) && !any(isinf(m));
}
float sk_pf_moment(float x) {
    if (isnan(x) || isinf(x)) return 0.0;
    return clamp(x, -1e6, 1e6);
}

// ---------------------------------------------------------------------------------------- depth
// t = d * scale + offset, clamped to [0, 1] (NaN -> 1).
float sk_prefilter_depth(float eye_distance, float2 scale_offset) {
    return sk_pf_depth(eye_distance * scale_offset.x + scale_offset.y);
}
// t = (c.x + c.y z_w) / (c.z + c.w z_w), clamped to [0, 1] (NaN -> 1).
float sk_prefilter_depth_from_window(float z_w, float4 c) {
    return sk_pf_depth((c.x + c.y * z_w) / (c.z + c.w * z_w));
}

// ---------------------------------------------------------------------------------------- moments
// VSM (t, t^2 + 0.25 |dt|^2): the derivative term (clamped to [0, 1]) covers the plane's spread.
float2 sk_vsm_moments(float t, float2 dt) {
    float z = sk_pf_depth(t);
    float2 d = float2(isnan(dt.x) || isinf(dt.x) ? 0.0 : dt.x, isnan(dt.y) || isinf(dt.y) ? 0.0 : dt.y);
    float extra = sk_pf_clamp(0.25 * dot(d, d), 0.0, 1.0);
    return float2(z, z * z + extra);
}
// ESM e^(c t), c clamped to [0, 88.72].
float sk_esm_moment(float t, float c) {
    return exp(sk_pf_clamp(c, 0.0, 88.72283) * sk_pf_depth(t));
}
// EVSM (e^(c+ x), e^(2 c+ x), -e^(-c- x), e^(-2 c- x)), x = 2t - 1, exponents clamped to [0, 44.36].
float4 sk_evsm_moments(float t, float2 c) {
    float x = 2.0 * sk_pf_depth(t) - 1.0;
    float p = exp(sk_pf_clamp(c.x, 0.0, 44.36141) * x);
    float n = -exp(-sk_pf_clamp(c.y, 0.0, 44.36141) * x);
    return float4(p, p * p, n, n * n);
}
// MSM power moments (t, t^2, t^3, t^4).
float4 sk_msm_moments(float t) {
    float z = sk_pf_depth(t);
    float z2 = z * z;
    return float4(z, z2, z2 * z, z2 * z2);
}
// Peters & Klein 2015, Sec. 4.3: q = A b + (0.035955884801, 0, 0, 0), every q in [0, 1].
float4 sk_msm_quantize(float4 b) {
    b = float4(sk_pf_moment(b.x), sk_pf_moment(b.y), sk_pf_moment(b.z), sk_pf_moment(b.w));
    return float4(-2.07224649 * b.x + 32.23703778 * b.y - 68.571074599 * b.z + 39.3703274134 * b.w + 0.035955884801,
                13.7948857237 * b.x - 59.4683975703 * b.y + 82.0359750338 * b.z - 35.364903257 * b.w,
                0.105877704 * b.x - 1.9077466311 * b.y + 9.3496555107 * b.z - 6.6543490743 * b.w,
                9.7924062118 * b.x - 33.7652110555 * b.y + 47.9456096605 * b.z - 23.9728048165 * b.w);
}
// b = A^-1 (q - (0.035955884801, 0, 0, 0)).
float4 sk_msm_dequantize(float4 q) {
    q = float4(sk_pf_moment(q.x) - 0.035955884801, sk_pf_moment(q.y), sk_pf_moment(q.z), sk_pf_moment(q.w));
    return float4(0.22277441459 * q.x + 0.0771972860781 * q.y + 0.792698663656 * q.z + 0.0319417554614 * q.w,
                0.154967926116 * q.x + 0.139462942654 * q.y + 0.796341583786 * q.z - 0.172282317302 * q.w,
                0.145198894564 * q.x + 0.212020215683 * q.y + 0.725869446385 * q.z - 0.275801481149 * q.w,
                0.163127442991 * q.x + 0.259143226644 * q.y + 0.653909249674 * q.z - 0.337613173406 * q.w);
}
// The moments of `method` for a fragment at t (VSM: xy; ESM: x; EVSM2: xy; EVSM4, MSM: xyzw).
float4 sk_prefilter_moments(float t, float2 dt, int method, float2 exponents, bool quantized) {
    if (method == 1) return float4(sk_esm_moment(t, exponents.x), 0.0, 0.0, 0.0);
    if (method == 2) return float4(sk_evsm_moments(t, float2(exponents.x, 0.0)).xy, 0.0, 0.0);
    if (method == 3) return sk_evsm_moments(t, exponents);
    if (method == 4 || method == 5) {
        float4 b = sk_msm_moments(t);
        return quantized ? sk_msm_quantize(b) : b;
    }
    return float4(sk_vsm_moments(t, dt), 0.0, 0.0);
}

// ---------------------------------------------------------------------------------------- lookups
// Chebyshev's one-sided bound (Donnelly & Lauritzen 2006, eq. 5), variance raised to min_var.
float sk_pf_chebyshev(float mean, float m2, float x, float min_var) {
    if (x <= mean) return 1.0;
    float var = m2 - mean * mean;
    if (!(var >= min_var)) var = min_var;
    if (!(var > 0.0)) return 0.0;
    float d = x - mean;
    float p = var / (var + d * d);
    return p >= 0.0 ? (p > 1.0 ? 1.0 : p) : 0.0;
}
// VSM's bound made conservative in float (prefiltered_shadow.hpp, pf_vsm_bound): the mean moved
// min_var / 3 + 4u |mean| toward x, the variance max(m2 - mean^2, 0) raised by min_var + 4u (m2 + mean^2),
// u = 2^-24: the storage error (min_var = 3 u_format) and the fp32 arithmetic, so never below the lit
// fraction. min_var = 0: plain Chebyshev.
float sk_pf_vsm_bound(float mean, float m2, float x, float min_var) {
    if (!(min_var > 0.0)) return sk_pf_chebyshev(mean, m2, x, 0.0);
    const float u = 5.9604645e-8;
    float em = min_var / 3.0 + 4.0 * u * abs(mean);
    if (x <= mean + em) return 1.0;
    float var = m2 - mean * mean;
    if (!(var >= 0.0)) var = 0.0;
    var += min_var + 4.0 * u * (abs(m2) + mean * mean);
    float d = x - mean - em;
    float p = var / (var + d * d);
    return p >= 0.0 ? (p > 1.0 ? 1.0 : p) : 0.0;
}
// Light-bleeding reduction linstep(amount, 1, p) (Lauritzen 2007), amount in [0, 0.999].
float sk_pf_linstep(float amount, float p) {
    float a = sk_pf_clamp(amount, 0.0, 0.999);
    float v = (p - a) / (1.0 - a);
    return v > 0.0 ? (v < 1.0 ? v : 1.0) : 0.0;
}

float sk_vsm_visibility(float2 moments, float t, float min_variance, float bleed_reduction) {
    if (!sk_pf_finite(float4(moments, 0.0, 0.0)) || isnan(t)) return 1.0;
    float p = sk_pf_vsm_bound(moments.x, moments.y, t, sk_pf_clamp(min_variance, 0.0, 1.0));
    return sk_pf_linstep(bleed_reduction, p);
}

float sk_esm_visibility(float moment, float t, float c) {
    if (isnan(moment) || isinf(moment) || isnan(t)) return 1.0;
    float v = exp(-sk_pf_clamp(c, 0.0, 88.72283) * sk_pf_clamp(t, -1.0, 2.0)) * moment;
    return v > 0.0 ? (v < 1.0 ? v : 1.0) : 0.0;
}

float sk_evsm_visibility(float4 moments, float t, float2 c, bool use_negative, float min_variance, float bleed_reduction) {
    if (!sk_pf_finite(moments) || isnan(t)) return 1.0;
    float x = 2.0 * sk_pf_depth(t) - 1.0;
    float mv = sk_pf_clamp(min_variance, 0.0, 1.0);
    float cp = sk_pf_clamp(c.x, 0.0, 44.36141);
    float wp = exp(cp * x);
    float sp = 2.0 * cp * wp;
    float v = sk_pf_linstep(bleed_reduction, sk_pf_chebyshev(moments.x, moments.y, wp, sk_pf_clamp(mv * sp * sp, 0.0, 1e37)));
    if (use_negative) {
        float cn = sk_pf_clamp(c.y, 0.0, 44.36141);
        float wn = -exp(-cn * x);
        float sn = 2.0 * cn * wn;
        float n = sk_pf_linstep(bleed_reduction, sk_pf_chebyshev(moments.z, moments.w, wn, sk_pf_clamp(mv * sn * sn, 0.0, 1e37)));
        v = min(v, n);
    }
    return v;
}

// Depths within this distance of the receiver count as at it, not in front (moment bias a): the
// solve's rounding error, 32 a plus a few ulps (prefiltered_shadow.hpp, pf_msm_root_tolerance).
float sk_pf_msm_root_tolerance(float a) {
    return 32.0 * a + 4.0 * 5.9604645e-8;
}
// Largest D22 one depth explains: the bias's own variance a ((b1 - 1/2)^2 + 1/4) (pf_msm_one_depth_variance).
float sk_pf_msm_one_depth_variance(float4 b, float a) {
    return a * ((b.x - 0.5) * (b.x - 0.5) + 0.25);
}
// Shadow of a texel with a singular Hankel matrix: its two depths, roots of x^2 - l32 x + (l32 b1 - b2).
float sk_pf_two_depths_shadow(float4 b, float z, float l32, float tol) {
    float a0 = l32 * b.x - b.y;
    float disc = l32 * l32 - 4.0 * a0;
    if (!(disc > 0.0)) disc = 0.0;
    float s = sqrt(disc);
    float x1 = 0.5 * (l32 - s), x2 = 0.5 * (l32 + s);
    float w1 = (x2 - b.x) / (x2 - x1);
    float zt = z - tol;  // depths within tol of z are at z: not in front
    float g = (x1 < zt ? w1 : 0.0) + (x2 < zt ? 1.0 - w1 : 0.0);
    if (!(g >= -1e30 && g <= 1e30)) g = zt > b.x ? 1.0 : 0.0;
    return g < 0.0 ? 0.0 : (g > 1.0 ? 1.0 : g);
}
// Hamburger 4MSM (Peters & Klein 2015, Algorithm 2): the sharpest lower bound G of the shadow from
// biased moments b (moment bias a); z23 receives the two other support points, solved = false on a
// fallback. Support points within sk_pf_msm_root_tolerance(a) of z count as at z.
float sk_pf_msm_hamburger(float4 b, float z, float moment_bias, out float2 z23, out bool solved) {
    solved = false;
    z23 = float2(0.0, 0.0);
    float a = sk_pf_clamp(moment_bias, 0.0, 1.0), tol = sk_pf_msm_root_tolerance(a), zt = z - tol;
    float d22 = b.y - b.x * b.x;
    if (!(d22 > sk_pf_msm_one_depth_variance(b, a))) return zt > b.x ? 1.0 : 0.0;
    float l32d22 = b.z - b.x * b.y;
    float l32 = l32d22 / d22;
    float d33 = (b.w - b.y * b.y) - l32d22 * l32;
    if (!(d33 > 0.0)) return sk_pf_two_depths_shadow(b, z, l32, tol);
    float y2 = z - b.x;
    float y3 = z * z - b.y - l32 * y2;
    float c3 = y3 / d33;
    float c2 = y2 / d22 - l32 * c3;
    float c1 = 1.0 - b.x * c2 - b.y * c3;
    float disc = c2 * c2 - 4.0 * c1 * c3;
    if (!(disc > 0.0)) disc = 0.0;
    float s = sqrt(disc);
    float q = -0.5 * (c2 + (c2 >= 0.0 ? s : -s));
    float r1 = q / c3, r2 = c1 / q;
    if (isnan(r1) || isnan(r2)) return sk_pf_two_depths_shadow(b, z, l32, tol);
    float z2 = min(r1, r2), z3 = max(r1, r2);
    z23 = float2(z2, z3);
    float g;
    if (zt <= z2) g = 0.0;
    else if (zt <= z3) g = (z * z3 - b.x * (z + z3) + b.y) / ((z3 - z2) * (z - z2));
    else g = 1.0 - (z2 * z3 - b.x * (z2 + z3) + b.y) / ((z - z2) * (z - z3));
    if (!(g >= -1e30 && g <= 1e30)) return sk_pf_two_depths_shadow(b, z, l32, tol);
    solved = true;
    return g < 0.0 ? 0.0 : (g > 1.0 ? 1.0 : g);
}
float4 sk_pf_msm_prepare(float4 moments, float moment_bias, bool quantized) {
    float4 b = quantized ? sk_msm_dequantize(moments) : moments;
    float k = sk_pf_clamp(moment_bias, 0.0, 1.0);
    return (1.0 - k) * b + k * float4(0.5, 0.5, 0.5, 0.5);
}

float sk_msm_visibility(float4 moments, float t, float moment_bias, bool quantized, float bleed_reduction) {
    if (!sk_pf_finite(moments) || isnan(t)) return 1.0;
    float2 z23;
    bool solved;
    float g = sk_pf_msm_hamburger(sk_pf_msm_prepare(moments, moment_bias, quantized), sk_pf_clamp(t, -1.0, 2.0), moment_bias, z23, solved);
    return sk_pf_linstep(bleed_reduction, 1.0 - g);
}

// The Hausdorff variant: where the Hamburger support points leave [0, 1], the representation
// {0, t, z_free, 1} (z_free = E[x^2 (x - t)(x - 1)] / E[x (x - t)(x - 1)]) gives the bound on [0, 1].
float sk_msm_hausdorff_visibility(float4 moments, float t, float moment_bias, bool quantized, float bleed_reduction) {
    if (!sk_pf_finite(moments) || isnan(t)) return 1.0;
    float4 b = sk_pf_msm_prepare(moments, moment_bias, quantized);
    float z = sk_pf_clamp(t, -1.0, 2.0);
    float2 z23;
    bool solved;
    float tol = sk_pf_msm_root_tolerance(sk_pf_clamp(moment_bias, 0.0, 1.0));
    float g = sk_pf_msm_hamburger(b, z, moment_bias, z23, solved);
    if (solved && (z23.x < 0.0 || z23.y > 1.0) && z > tol && z < 1.0) {  // z <= tol: nothing on [0, 1] is more than tol in front
        float e3 = b.z - (1.0 + z) * b.y + z * b.x;
        float e4 = b.w - (1.0 + z) * b.z + z * b.y;
        float zf = e4 / e3;
        float e0 = b.z - (z + zf + 1.0) * b.y + (z * zf + z + zf) * b.x - z * zf;
        float h = -e0 / (z * zf);
        if (zf < z - tol) h += e3 / (zf * (zf - z) * (zf - 1.0));
        if (h >= -1e30 && h <= 1e30) g = max(g, clamp(h, 0.0, 1.0));
    }
    return sk_pf_linstep(bleed_reduction, 1.0 - g);
}

// Visibility (1 lit) of a receiver at moment depth t (depth bias already subtracted) from filtered
// moments; params = (c+, c-, min_variance, bleed_reduction).
float sk_prefilter_visibility(float4 moments, float t, int method, float4 params, float moment_bias, bool quantized) {
    if (method == 1) return sk_esm_visibility(moments.x, t, params.x);
    if (method == 2) return sk_evsm_visibility(float4(moments.xy, 0.0, 0.0), t, params.xy, false, params.z, params.w);
    if (method == 3) return sk_evsm_visibility(moments, t, params.xy, true, params.z, params.w);
    if (method == 4) return sk_msm_visibility(moments, t, moment_bias, quantized, params.w);
    if (method == 5) return sk_msm_hausdorff_visibility(moments, t, moment_bias, quantized, params.w);
    return sk_vsm_visibility(moments.xy, t, params.z, params.w);
}

// Receiver-plane depth bias (Isidoro 2006) for a filtered lookup: the plane's depth change across the
// kernel, kernel_radius_uv (|dt/du| + |dt/dv|), dt/duv solved from two neighbouring steps of (u, v, t)
// (float3(dFdx(uv), dFdx(t)), float3(dFdy(uv), dFdy(t)), or two tangent steps in a deferred pass).
// Subtract it from t: a receiver tilted against the light otherwise shadows itself (its depths spread
// over the filter region, half of them in front). 0 for a singular solve; clamped to [0, 1].
float sk_prefilter_receiver_bias(float3 duvt_dx, float3 duvt_dy, float kernel_radius_uv) {
    float det = duvt_dx.x * duvt_dy.y - duvt_dx.y * duvt_dy.x;
    float scale = (abs(duvt_dx.x) + abs(duvt_dx.y)) * (abs(duvt_dy.x) + abs(duvt_dy.y));
    if (!(abs(det) > 1e-7 * scale) || !(abs(det) > 0.0)) return 0.0;
    float gx = (duvt_dy.y * duvt_dx.z - duvt_dx.y * duvt_dy.z) / det;
    float gy = (duvt_dx.x * duvt_dy.z - duvt_dy.x * duvt_dx.z) / det;
    float b = sk_pf_clamp(kernel_radius_uv, 0.0, 1.0) * (abs(gx) + abs(gy));
    return sk_pf_clamp(b, 0.0, 1.0);
}

// ---------------------------------------------------------------------------------------- soft shadows
// Contact hardening from a mipmapped moment map (VSM, MSM; prefiltered_shadow.hpp NUMERICS item 7):
// `soft` = PrefilterSoftUniforms::params() = (light_uv, distance_scale, distance_offset, map_size).
// (fraction, depth) of the blockers in front of t: VSM after Yang et al. 2010 (mu = p t + (1 - p) z_avg),
// MSM the canonical representation's support points in front of t (after Peters et al. 2016).
float2 sk_prefilter_soft_blocker(float4 moments, float t, int method, float4 params, float moment_bias, bool quantized) {
    float z = sk_pf_clamp(t, 0.0, 1.0);
    if (!sk_pf_finite(moments) || isnan(t) || !(method == 0 || method == 4 || method == 5)) return float2(0.0, z);
    float frac = 0.0, depth = z, min_share = 1e-3;
    if (method == 0) {
        float p = sk_pf_vsm_bound(moments.x, moments.y, z, sk_pf_clamp(params.z, 0.0, 1.0));
        frac = 1.0 - p;
        if (frac > 0.0) depth = (moments.x - p * z) / frac;
    } else {
        float4 b = sk_pf_msm_prepare(moments, moment_bias, quantized);
        min_share = max(min_share, moment_bias);  // the bias's half sample at 0: a phantom blocker on every texel
        float d22 = b.y - b.x * b.x;
        float ab = sk_pf_clamp(moment_bias, 0.0, 1.0), zt = z - sk_pf_msm_root_tolerance(ab);
        if (!(d22 > sk_pf_msm_one_depth_variance(b, ab))) {
            if (zt > b.x) { frac = 1.0; depth = b.x; }
        } else {
            float2 z23;
            bool solved;
            float g = sk_pf_msm_hamburger(b, z, moment_bias, z23, solved);
            if (solved) {
                frac = g;
                if (zt <= z23.y) depth = z23.x;
                else if (g > 0.0) depth = (b.x - (1.0 - g) * z) / g;  // E[x; x < z] = b1 - w(z) z
            } else {  // two depths x1 <= x2
                float l32 = (b.z - b.x * b.y) / d22;
                float disc = l32 * l32 - 4.0 * (l32 * b.x - b.y);
                if (!(disc > 0.0)) disc = 0.0;
                float s = sqrt(disc), x1 = 0.5 * (l32 - s), x2 = 0.5 * (l32 + s);
                float w1 = (x2 - b.x) / (x2 - x1);
                if (x2 < zt) { frac = 1.0; depth = b.x; }
                else if (x1 < zt && w1 >= 0.0 && w1 <= 1.0) { frac = w1; depth = x1; }
                else if (!(w1 >= 0.0 && w1 <= 1.0) && zt > b.x) { frac = 1.0; depth = b.x; }
            }
        }
    }
    if (!(frac > min_share) || !(depth <= 1e30 && depth >= -1e30)) return float2(0.0, z);
    return float2(min(frac, 1.0), sk_pf_clamp(depth, 0.0, z));
}
// Penumbra width in uv of blockers at t_front on a receiver at t_receiver: light_uv (1/d_b - 1/d_r)
// (similar triangles, Fernando 2005; Apelles eq. 3.21); t_front = 0: the blocker-search region. In [0, 1].
float sk_prefilter_soft_width(float t_receiver, float t_front, float4 soft) {
    if (isnan(t_receiver)) return 0.0;
    float tr = sk_pf_clamp(t_receiver, 0.0, 1.0), tb = sk_pf_clamp(t_front, 0.0, tr);
    float dr = tr * soft.y + soft.z, db = tb * soft.y + soft.z;
    return sk_pf_clamp(soft.x * (1.0 / db - 1.0 / dr), 0.0, 1.0);
}
// Mip level whose trilinear lookup has the variance of a box of width_uv: log2(K / sqrt(3)), K in
// texels, clamped to [0, log2(map_size)].
float sk_prefilter_soft_level_of(float width_uv, float4 soft) {
    float k = width_uv * soft.w * 0.57735027;
    if (!(k > 1.0)) return 0.0;
    return min(log2(k), log2(max(soft.w, 1.0)));
}
// |dt/du| + |dt/dv| of the receiver plane (the 2x2 solve of sk_prefilter_receiver_bias without a
// radius), for the soft lookup's per-pixel kernels. 0 for a singular solve; clamped to [0, 1e6].
float sk_prefilter_receiver_slope(float3 duvt_dx, float3 duvt_dy) {
    float det = duvt_dx.x * duvt_dy.y - duvt_dx.y * duvt_dy.x;
    float scale = (abs(duvt_dx.x) + abs(duvt_dx.y)) * (abs(duvt_dy.x) + abs(duvt_dy.y));
    if (!(abs(det) > 1e-7 * scale) || !(abs(det) > 0.0)) return 0.0;
    float gx = (duvt_dy.y * duvt_dx.z - duvt_dx.y * duvt_dy.z) / det;
    float gy = (duvt_dx.x * duvt_dy.z - duvt_dy.x * duvt_dx.z) / det;
    return sk_pf_clamp(abs(gx) + abs(gy), 0.0, 1e6);
}
// Soft visibility (1 lit) with contact hardening: the moments over the search region (SampleLevel at
// its level), the average blocker depth, the moments over that depth's penumbra (no blocker found:
// level 0, the hard lookup), the method's lookup. The map needs every mip level (glGenerateMipmap,
// GL_LINEAR_MIPMAP_LINEAR). light_uv 0, ESM and EVSM: the hard lookup at level 0. t: the receiver's
// depth minus its bias; receiver_slope = (sk_prefilter_receiver_slope, cap): each step compares
// t - min(slope * half its width in uv, cap) ((0, 0): none).
float sk_prefilter_soft_visibility(Texture2D<float4> moments, SamplerState moment_sampler, float2 uv, float t, int method, float4 params, float moment_bias,
                                   bool quantized, float4 soft, float2 receiver_slope) {
    if (!(soft.x > 0.0) || !(method == 0 || method == 4 || method == 5))
        return sk_prefilter_visibility(moments.SampleLevel(moment_sampler, uv, 0.0), t, method, params, moment_bias, quantized);
    float slope = sk_pf_clamp(receiver_slope.x, 0.0, 1e6), cap = sk_pf_clamp(receiver_slope.y, 0.0, 1.0);
    float ws = sk_prefilter_soft_width(t, 0.0, soft);
    float2 b = sk_prefilter_soft_blocker(moments.SampleLevel(moment_sampler, uv, sk_prefilter_soft_level_of(ws, soft)),
                                       t - min(slope * 0.5 * ws, cap), method, params, moment_bias, quantized);
    float wf = b.x > 0.0 ? sk_prefilter_soft_width(t, b.y, soft) : 0.0;
    return sk_prefilter_visibility(moments.SampleLevel(moment_sampler, uv, sk_prefilter_soft_level_of(wf, soft)),
                                   t - min(slope * 0.5 * wf, cap), method, params, moment_bias, quantized);
}

// ---------------------------------------------------------------------------------------- filtering
// One pass of the separable blur at texel px along dir ((1, 0) or (0, 1)): sum over i in
// [-radius, radius] of weights[|i|] * texel(px + i dir), coordinates clamped to the map.
float4 sk_prefilter_blur(Texture2D<float4> src, int2 px, int2 dir, int radius, float weights[SK_PREFILTER_MAX_WEIGHTS]) {
    uint w, h;
    src.GetDimensions(w, h);
    int2 last = int2(w, h) - int2(1, 1);
    int r = clamp(radius, 0, SK_PREFILTER_MAX_WEIGHTS - 1);
    float4 sum = weights[0] * src.Load(int3(clamp(px, int2(0, 0), last), 0));
    for (int i = 1; i <= r; ++i) {
        sum += weights[i] * (src.Load(int3(clamp(px + i * dir, int2(0, 0), last), 0)) +
                             src.Load(int3(clamp(px - i * dir, int2(0, 0), last), 0)));
    }
    return sum;
}

// MSAA resolve into moments: the mean over the samples of the moments of each sample's depth
// (window depth -> t through window_map). No derivative term: the samples carry the spread.
float4 sk_prefilter_resolve(Texture2DMS<float> depth_ms, int2 px, int samples, float4 window_map, int method, float2 exponents,
                          bool quantized) {
    float4 sum = float4(0.0, 0.0, 0.0, 0.0);
    int n = max(samples, 1);
    for (int s = 0; s < n; ++s) {
        float t = sk_prefilter_depth_from_window(depth_ms.Load(px, s), window_map);
        sum += sk_prefilter_moments(t, float2(0.0, 0.0), method, exponents, false);
    }
    float4 m = sum / float(n);
    return (method == 4 || method == 5) && quantized ? sk_msm_quantize(m) : m;
}
