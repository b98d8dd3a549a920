// shadowkit/hlsl/pcf.hlsl - percentage-closer filtering kernels in HLSL: box, tent, Poisson and rotated Poisson, each with an optional receiver-plane depth bias
// stages: pixel (sk_receiver_plane_depth_bias: pixel only; the rest any stage)
//
// The HLSL twin of glsl/pcf.glsl: the same sk_ functions, arguments, taps, weights and order; the map
// is a Texture2D<float> (or a Texture2DArray<float> followed by `float layer`) with its
// SamplerComparisonState passed next to it. glsl/pcf.glsl says what each argument means.
// Differences from the GLSL: sk_pcf_poisson_rotated takes the pixel position (SV_Position.xy in a
// pixel shader) as its last argument, because HLSL functions cannot read it; a tap array of your own
// (SK_POISSON_TAPS / SK_POISSON_TAP_COUNT defined before this file) is a `static const float2
// NAME[N] = { ... };` (shadowkit/poisson_disk.hpp's poisson_to_glsl writes the GLSL form only).
// Sampler state: ComparisonFunc LESS_EQUAL (GREATER_EQUAL reversed-Z), linear filter (each tap a
// hardware 2x2 compare), clamp addressing. Taps with uv outside [0,1] count as lit.
// Matrices: none here; hlsl/shadow_map.hlsl states the one rule (column_major, mul(M, v)).
// Usage:
//   float2 g = sk_receiver_plane_depth_bias(uvz);   // pixel shader, uniform control flow (ddx/ddy)
//   float lit = sk_pcf_poisson_rotated(g_shadow_map, g_compare, uvz, g, 3.0 / 2048.0, 16, position.xy);
//   float lit = sk_pcf_tent(g_cascades, g_compare, float(i), uvz, g, 2);   // layer i of a depth array
// Compiled in the tests by glslang's HLSL front end to SPIR-V and run on Vulkan; written for DXC
// (shader model 6.0) as well, but not compiled with it here (DXC is not packaged in Debian 12).
// Based on Reeves et al. 1987 (PCF), Isidoro 2006 (receiver plane depth bias), Jimenez 2014
// (interleaved gradient noise).
// MIT License. Copyright (c) shadowkit contributors.

#define SK_PCF_HLSL 1

#ifndef SK_POISSON_DISK64_DEFINED
#define SK_POISSON_DISK64_DEFINED
// The 64 points of glsl/pcf.glsl's sk_poisson_disk64 (the same values, the same order).
static const float2 sk_poisson_disk64[64] = {
    float2(0.667273045, 0.596935987), float2(-0.974912941, 0.140261471),
    float2(-0.00817528274, -0.737295032), float2(-0.357976198, 0.743402183),
    float2(0.810684562, -0.55637908), float2(-0.36176604, -0.220403671),
    float2(0.919741094, -0.0295969304), float2(-0.899047136, -0.401866853),
    float2(-0.35729304, 0.256965429), float2(-0.823843956, 0.556563199),
    float2(-0.442809522, -0.788640141), float2(-0.00385137554, 0.00996741187),
    float2(0.496161342, -0.789134264), float2(0.307677567, 0.479340941),
    float2(0.0261630546, -0.361821979), float2(0.649081528, 0.19646357),
    float2(-0.0496209897, 0.569143891), float2(0.493515879, -0.423292518),
    float2(-0.666885555, 0.217370793), float2(0.90251708, 0.411130309),
    float2(0.23290506, 0.758692503), float2(0.249936044, -0.941124558),
    float2(0.311741292, -0.203952923), float2(0.519844234, 0.84039098),
    float2(-0.496722907, -0.457896143), float2(-0.926848173, -0.135281667),
    float2(-0.00672815274, 0.26900959), float2(-0.0590348318, -0.987052143),
    float2(0.721485615, -0.162640795), float2(-0.248856291, 0.0319613107),
    float2(-0.301116526, -0.580681205), float2(-0.111001909, 0.789575696),
    float2(-0.5985865, 0.553151011), float2(-0.584493697, -0.211627632),
    float2(0.192017213, 0.171763808), float2(-0.137889117, -0.174055114),
    float2(0.254576564, -0.729208648), float2(-0.365630656, 0.529652059),
    float2(-0.630011797, 0.0149271172), float2(-0.925787508, 0.337520659),
    float2(-0.24114193, -0.896481395), float2(0.935237825, -0.222696722),
    float2(0.574212909, 0.0197216701), float2(-0.0712009072, -0.548193455),
    float2(0.359571993, 0.289480388), float2(0.530840635, -0.209503949),
    float2(-0.68105185, 0.722644687), float2(0.10657119, 0.892661333),
    float2(0.083066918, -0.177033007), float2(0.503817022, 0.491984129),
    float2(-0.727698088, -0.454516619), float2(0.694889069, -0.689536989),
    float2(0.688220203, 0.412640005), float2(0.419547528, -0.584399879),
    float2(-0.268478572, 0.900935829), float2(0.125276238, 0.576343596),
    float2(0.389038563, -0.0452882573), float2(-0.474447995, 0.118304528),
    float2(-0.713988602, 0.392602742), float2(0.811533272, 0.118944764),
    float2(0.107297376, -0.526566327), float2(-0.0845918506, 0.963354111),
    float2(0.375263661, 0.646681547), float2(-0.322467238, -0.398355454)
};

// Interleaved gradient noise (Jimenez 2014) in [0,1) from a pixel position (SV_Position.xy).
float sk_interleaved_gradient_noise(float2 pixel) {
    return frac(52.9829189 * frac(dot(pixel, float2(0.06711056, 0.00583715))));
}
#endif
#ifndef SK_POISSON_TAPS
#define SK_POISSON_TAPS sk_poisson_disk64
#define SK_POISSON_TAP_COUNT 64
#endif
#ifndef SK_POISSON_TAP_COUNT
#error "SK_POISSON_TAPS needs SK_POISSON_TAP_COUNT, the length of its array"
#endif

// Receiver-plane depth gradient (dz/du, dz/dv) from two steps of uvz along the receiver's plane
// (Isidoro 2006); float2(0, 0) when singular.
float2 sk_receiver_plane_gradient(float3 step1, float3 step2) {
    float det = step1.x * step2.y - step1.y * step2.x;
    float scale = (abs(step1.x) + abs(step1.y)) * (abs(step2.x) + abs(step2.y));
    if (!(abs(det) > 1e-7 * scale)) return float2(0.0, 0.0);
    return float2(step2.y * step1.z - step1.y * step2.z, step1.x * step2.z - step2.x * step1.z) / det;
}

// The same from screen-space derivatives of uvz (pixel shader, uniform control flow).
float2 sk_receiver_plane_depth_bias(float3 uvz) {
    return sk_receiver_plane_gradient(ddx(uvz), ddy(uvz));
}

// One hardware-compare tap at a uv offset, with the receiver plane applied; outside the map: lit.
float sk_pcf_tap(Texture2D<float> sm, SamplerComparisonState cmp, float3 uvz, float2 dz_duv, float2 offset_uv) {
    float2 uv = uvz.xy + offset_uv;
    if (any(uv < 0.0) || any(uv > 1.0)) return 1.0;
    return sm.SampleCmpLevelZero(cmp, uv, uvz.z + dot(dz_duv, offset_uv));
}

// Hard shadow: one tap (a bilinear 2x2 compare with a linear filter).
float sk_pcf_hard(Texture2D<float> sm, SamplerComparisonState cmp, float3 uvz) {
    return sk_pcf_tap(sm, cmp, uvz, float2(0.0, 0.0), float2(0.0, 0.0));
}

// Box: (2r+1)^2 taps one texel apart, equal weights. r is clamped to [0, 8].
float sk_pcf_box(Texture2D<float> sm, SamplerComparisonState cmp, float3 uvz, float2 dz_duv, int radius_texels) {
    int r = clamp(radius_texels, 0, 8);
    float w, h;
    sm.GetDimensions(w, h);
    float2 texel = 1.0 / float2(w, h);
    float sum = 0.0;
    for (int j = -r; j <= r; ++j)
        for (int i = -r; i <= r; ++i)
            sum += sk_pcf_tap(sm, cmp, uvz, dz_duv, float2(float(i), float(j)) * texel);
    float n = float(2 * r + 1);
    return sum / (n * n);
}

// Tent: (2r+1)^2 bilinear taps weighted (r+1-|i|)(r+1-|j|). r is clamped to [0, 8].
float sk_pcf_tent(Texture2D<float> sm, SamplerComparisonState cmp, float3 uvz, float2 dz_duv, int radius_texels) {
    int r = clamp(radius_texels, 0, 8);
    float w, h;
    sm.GetDimensions(w, h);
    float2 texel = 1.0 / float2(w, h);
    float sum = 0.0;
    float wsum = 0.0;
    for (int j = -r; j <= r; ++j)
        for (int i = -r; i <= r; ++i) {
            float wt = float(r + 1 - abs(i)) * float(r + 1 - abs(j));
            sum += wt * sk_pcf_tap(sm, cmp, uvz, dz_duv, float2(float(i), float(j)) * texel);
            wsum += wt;
        }
    return sum / wsum;
}

// Poisson disk: `taps` (clamped to 1..SK_POISSON_TAP_COUNT) points of SK_POISSON_TAPS scaled to
// radius_uv and rotated by `angle` radians. radius_uv <= 0 or taps == 1 is the hard shadow.
float sk_pcf_poisson(Texture2D<float> sm, SamplerComparisonState cmp, float3 uvz, float2 dz_duv, float radius_uv, int taps,
                     float angle) {
    int n = clamp(taps, 1, SK_POISSON_TAP_COUNT);
    if (!(radius_uv > 0.0) || n == 1) return sk_pcf_tap(sm, cmp, uvz, dz_duv, float2(0.0, 0.0));
    float c = cos(angle);
    float s = sin(angle);
    float sum = 0.0;
    for (int i = 0; i < n; ++i) {
        float2 q = SK_POISSON_TAPS[i];
        sum += sk_pcf_tap(sm, cmp, uvz, dz_duv, float2(c * q.x - s * q.y, s * q.x + c * q.y) * radius_uv);
    }
    return sum / float(n);
}

// Rotated Poisson: the angle from interleaved gradient noise at `pixel` (SV_Position.xy).
float sk_pcf_poisson_rotated(Texture2D<float> sm, SamplerComparisonState cmp, float3 uvz, float2 dz_duv, float radius_uv,
                             int taps, float2 pixel) {
    return sk_pcf_poisson(sm, cmp, uvz, dz_duv, radius_uv, taps, 6.28318531 * sk_interleaved_gradient_noise(pixel));
}

// ---- depth arrays: the same kernels on one layer of a Texture2DArray<float> ----------------------

float sk_pcf_tap(Texture2DArray<float> sm, SamplerComparisonState cmp, float layer, float3 uvz, float2 dz_duv,
                 float2 offset_uv) {
    float2 uv = uvz.xy + offset_uv;
    if (any(uv < 0.0) || any(uv > 1.0)) return 1.0;
    return sm.SampleCmpLevelZero(cmp, float3(uv, layer), uvz.z + dot(dz_duv, offset_uv));
}

float sk_pcf_hard(Texture2DArray<float> sm, SamplerComparisonState cmp, float layer, float3 uvz) {
    return sk_pcf_tap(sm, cmp, layer, uvz, float2(0.0, 0.0), float2(0.0, 0.0));
}

float sk_pcf_box(Texture2DArray<float> sm, SamplerComparisonState cmp, float layer, float3 uvz, float2 dz_duv,
                 int radius_texels) {
    int r = clamp(radius_texels, 0, 8);
    float w, h, layers;
    sm.GetDimensions(w, h, layers);
    float2 texel = 1.0 / float2(w, h);
    float sum = 0.0;
    for (int j = -r; j <= r; ++j)
        for (int i = -r; i <= r; ++i)
            sum += sk_pcf_tap(sm, cmp, layer, uvz, dz_duv, float2(float(i), float(j)) * texel);
    float n = float(2 * r + 1);
    return sum / (n * n);
}

float sk_pcf_tent(Texture2DArray<float> sm, SamplerComparisonState cmp, float layer, float3 uvz, float2 dz_duv,
                  int radius_texels) {
    int r = clamp(radius_texels, 0, 8);
    float w, h, layers;
    sm.GetDimensions(w, h, layers);
    float2 texel = 1.0 / float2(w, h);
    float sum = 0.0;
    float wsum = 0.0;
    for (int j = -r; j <= r; ++j)
        for (int i = -r; i <= r; ++i) {
            float wt = float(r + 1 - abs(i)) * float(r + 1 - abs(j));
            sum += wt * sk_pcf_tap(sm, cmp, layer, uvz, dz_duv, float2(float(i), float(j)) * texel);
            wsum += wt;
        }
    return sum / wsum;
}

float sk_pcf_poisson(Texture2DArray<float> sm, SamplerComparisonState cmp, float layer, float3 uvz, float2 dz_duv,
                     float radius_uv, int taps, float angle) {
    int n = clamp(taps, 1, SK_POISSON_TAP_COUNT);
    if (!(radius_uv > 0.0) || n == 1) return sk_pcf_tap(sm, cmp, layer, uvz, dz_duv, float2(0.0, 0.0));
    float c = cos(angle);
    float s = sin(angle);
    float sum = 0.0;
    for (int i = 0; i < n; ++i) {
        float2 q = SK_POISSON_TAPS[i];
        sum += sk_pcf_tap(sm, cmp, layer, uvz, dz_duv, float2(c * q.x - s * q.y, s * q.x + c * q.y) * radius_uv);
    }
    return sum / float(n);
}

float sk_pcf_poisson_rotated(Texture2DArray<float> sm, SamplerComparisonState cmp, float layer, float3 uvz, float2 dz_duv,
                             float radius_uv, int taps, float2 pixel) {
    return sk_pcf_poisson(sm, cmp, layer, uvz, dz_duv, radius_uv, taps, 6.28318531 * sk_interleaved_gradient_noise(pixel));
}
