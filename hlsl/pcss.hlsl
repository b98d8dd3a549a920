// shadowkit/hlsl/pcss.hlsl - percentage-closer soft shadows in HLSL: blocker search with a point sampler, penumbra estimate on linear depths, Poisson PCF through a SamplerComparisonState
// stages: pixel (and any other: every read is SampleLevel / SampleCmpLevelZero)
//
// The HLSL twin of glsl/pcss.glsl: the same sk_ functions, arguments, taps and formulas (glsl/pcss.glsl
// says what each argument means and the formulas). One Texture2D<float> (or Texture2DArray<float>
// followed by `float layer` after the samplers) is read through two samplers passed next to it:
// `depth_sampler`, a SamplerState with point filtering (the blocker search reads stored depths), and
// `cmp`, a SamplerComparisonState (LESS_EQUAL, GREATER_EQUAL with SK_REVERSED_Z defined before this
// file; linear filter) for the filter; clamp addressing. GLSL's two views of one map become one
// texture and two samplers. Defines: SK_REVERSED_Z; SK_POISSON_TAPS / SK_POISSON_TAP_COUNT as in
// hlsl/pcf.hlsl (shares the guarded Poisson block with it: both may be included). One helper more than
// the GLSL: sk_pcss_tap_offset, the rotated Poisson tap (GLSL writes mat2(c, s, -s, c) * tap inline).
// Usage:
//   float lit = sk_pcss(g_map, g_point, g_compare, uvz, float2(0.0, 0.0), g_light_uv_at_near, g_near, g_far, 16, 16,
//                       6.2831853 * sk_interleaved_gradient_noise(position.xy), 0.05);
// Compiled in the tests by glslang's HLSL front end to SPIR-V and run on Vulkan; written for DXC
// (shader model 6.0) as well, but not compiled with it here (DXC is not packaged in Debian 12).
// Based on Fernando 2005 (PCSS) and the Apelles thesis, eqs. 3.20-3.22.
// MIT License. Copyright (c) shadowkit contributors.

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

// Window depth -> eye distance for a perspective light (far <= 0.0: infinite far plane).
float sk_linearize_depth(float z_w, float near_z, float far_z) {
    float z = saturate(z_w);
#ifdef SK_REVERSED_Z
    if (far_z <= 0.0) return near_z / max(z, 1e-30);
    return far_z * near_z / (near_z + z * (far_z - near_z));
#else
    if (far_z <= 0.0) return near_z / max(1.0 - z, 1e-30);
    return far_z * near_z / (far_z - z * (far_z - near_z));
#endif
}

// True when stored window depth a is closer to the light than b.
bool sk_depth_closer(float a, float b) {
#ifdef SK_REVERSED_Z
    return a > b;
#else
    return a < b;
#endif
}

// Poisson tap i of `taps` rotated by (c, s) = (cos, sin) of the angle, scaled by `radius`.
float2 sk_pcss_tap_offset(int i, float c, float s, float radius) {
    float2 q = SK_POISSON_TAPS[i];
    return float2(c * q.x - s * q.y, s * q.x + c * q.y) * radius;
}

// Average window depth of the blockers among `taps` Poisson samples of a disk of diameter
// search_uv; -1.0 when there is none (receiver plane dz_duv per tap, as in GLSL).
float sk_pcss_blocker_window_depth(Texture2D<float> depth_map, SamplerState depth_sampler, float3 uvz, float2 dz_duv,
                                   float search_uv, int taps, float angle) {
    int n = clamp(taps, 1, SK_POISSON_TAP_COUNT);
    float c = cos(angle);
    float s = sin(angle);
    float sum = 0.0;
    float count = 0.0;
    for (int i = 0; i < n; ++i) {
        float2 o = sk_pcss_tap_offset(i, c, s, 0.5 * search_uv);
        float2 uv = uvz.xy + o;
        if (any(uv < 0.0) || any(uv > 1.0)) continue;
        float d = depth_map.SampleLevel(depth_sampler, uv, 0.0);
        if (sk_depth_closer(d, uvz.z + dot(dz_duv, o))) {
            sum += d;
            count += 1.0;
        }
    }
    return count > 0.0 ? sum / count : -1.0;
}

// The search without a receiver plane (every tap compares with uvz.z).
float sk_pcss_blocker_window_depth(Texture2D<float> depth_map, SamplerState depth_sampler, float3 uvz, float search_uv,
                                   int taps, float angle) {
    return sk_pcss_blocker_window_depth(depth_map, depth_sampler, uvz, float2(0.0, 0.0), search_uv, taps, angle);
}

// Filter taps for a filter of width filter_uv on a map of map_texels texels (shadowkit::pcss_tap_budget).
int sk_pcss_tap_budget(float filter_uv, float map_texels, int min_taps, int max_taps) {
    int lo = max(min_taps, 1);
    int hi = max(max_taps, lo);
    float d = filter_uv * map_texels;
    if (!(d > 1.0)) return lo;
    float want = ceil(3.14159265 * 0.25 * d * d);
    if (!(want < float(hi))) return hi;
    return max(int(want), lo);
}

// Poisson PCF with hardware compare (sk_pcf_poisson of hlsl/pcf.hlsl, local copy).
float sk_pcss_filter(Texture2D<float> sm, SamplerComparisonState cmp, float3 uvz, float2 dz_duv, float width_uv, int taps,
                     float angle) {
    int n = clamp(taps, 1, SK_POISSON_TAP_COUNT);
    float radius = 0.5 * width_uv;
    if (!(radius > 0.0) || n == 1) {
        if (any(uvz.xy < 0.0) || any(uvz.xy > 1.0)) return 1.0;
        return sm.SampleCmpLevelZero(cmp, uvz.xy, uvz.z);
    }
    float c = cos(angle);
    float s = sin(angle);
    float sum = 0.0;
    for (int i = 0; i < n; ++i) {
        float2 o = sk_pcss_tap_offset(i, c, s, radius);
        float2 uv = uvz.xy + o;
        if (any(uv < 0.0) || any(uv > 1.0)) {
            sum += 1.0;
            continue;
        }
        sum += sm.SampleCmpLevelZero(cmp, uv, uvz.z + dot(dz_duv, o));
    }
    return sum / float(n);
}

// PCSS for a perspective (spot) light. Returns the lit fraction in [0,1].
float sk_pcss(Texture2D<float> map, SamplerState depth_sampler, SamplerComparisonState cmp, float3 uvz, float2 dz_duv,
              float light_uv_at_near, float near_z, float far_z, int search_taps, int filter_taps, float angle,
              float max_filter_uv) {
    float z_r = sk_linearize_depth(uvz.z, near_z, far_z);
    float search_uv = min(light_uv_at_near * max(z_r - near_z, 0.0) / z_r, max_filter_uv);
    float width, height;
    map.GetDimensions(width, height);
    if (!(search_uv * width > 1.0)) return sk_pcss_filter(map, cmp, uvz, dz_duv, 0.0, 1, angle);
    float b = sk_pcss_blocker_window_depth(map, depth_sampler, uvz, dz_duv, search_uv, search_taps, angle);
    if (b < 0.0) return 1.0;
    float z_b = max(sk_linearize_depth(b, near_z, far_z), 1e-30);
    float w = light_uv_at_near * max(z_r - z_b, 0.0) / z_b * near_z / z_r;
    w = clamp(w, 0.0, max_filter_uv);
    return sk_pcss_filter(map, cmp, uvz, dz_duv, w, filter_taps, angle);
}

// PCSS for a directional (orthographic) light: window depth is linear.
float sk_pcss_directional(Texture2D<float> map, SamplerState depth_sampler, SamplerComparisonState cmp, float3 uvz,
                          float2 dz_duv, float light_uv_per_depth, int search_taps, int filter_taps, float angle,
                          float max_filter_uv) {
#ifdef SK_REVERSED_Z
    float z_r = 1.0 - uvz.z;
#else
    float z_r = uvz.z;
#endif
    float search_uv = min(light_uv_per_depth * max(z_r, 0.0), max_filter_uv);
    float width, height;
    map.GetDimensions(width, height);
    if (!(search_uv * width > 1.0)) return sk_pcss_filter(map, cmp, uvz, dz_duv, 0.0, 1, angle);
    float b = sk_pcss_blocker_window_depth(map, depth_sampler, uvz, dz_duv, search_uv, search_taps, angle);
    if (b < 0.0) return 1.0;
#ifdef SK_REVERSED_Z
    float z_b = 1.0 - b;
#else
    float z_b = b;
#endif
    float w = clamp(light_uv_per_depth * max(z_r - z_b, 0.0), 0.0, max_filter_uv);
    return sk_pcss_filter(map, cmp, uvz, dz_duv, w, filter_taps, angle);
}

// ---- depth arrays: the same functions on one layer (cascades) ------------------------------------

float sk_pcss_blocker_window_depth(Texture2DArray<float> depth_maps, SamplerState depth_sampler, float layer, float3 uvz,
                                   float2 dz_duv, float search_uv, int taps, float angle) {
    int n = clamp(taps, 1, SK_POISSON_TAP_COUNT);
    float c = cos(angle);
    float s = sin(angle);
    float sum = 0.0;
    float count = 0.0;
    for (int i = 0; i < n; ++i) {
        float2 o = sk_pcss_tap_offset(i, c, s, 0.5 * search_uv);
        float2 uv = uvz.xy + o;
        if (any(uv < 0.0) || any(uv > 1.0)) continue;
        float d = depth_maps.SampleLevel(depth_sampler, float3(uv, layer), 0.0);
        if (sk_depth_closer(d, uvz.z + dot(dz_duv, o))) {
            sum += d;
            count += 1.0;
        }
    }
    return count > 0.0 ? sum / count : -1.0;
}

float sk_pcss_blocker_window_depth(Texture2DArray<float> depth_maps, SamplerState depth_sampler, float layer, float3 uvz,
                                   float search_uv, int taps, float angle) {
    return sk_pcss_blocker_window_depth(depth_maps, depth_sampler, layer, uvz, float2(0.0, 0.0), search_uv, taps, angle);
}

float sk_pcss_filter(Texture2DArray<float> sm, SamplerComparisonState cmp, float layer, float3 uvz, float2 dz_duv,
                     float width_uv, int taps, float angle) {
    int n = clamp(taps, 1, SK_POISSON_TAP_COUNT);
    float radius = 0.5 * width_uv;
    if (!(radius > 0.0) || n == 1) {
        if (any(uvz.xy < 0.0) || any(uvz.xy > 1.0)) return 1.0;
        return sm.SampleCmpLevelZero(cmp, float3(uvz.xy, layer), uvz.z);
    }
    float c = cos(angle);
    float s = sin(angle);
    float sum = 0.0;
    for (int i = 0; i < n; ++i) {
        float2 o = sk_pcss_tap_offset(i, c, s, radius);
        float2 uv = uvz.xy + o;
        if (any(uv < 0.0) || any(uv > 1.0)) {
            sum += 1.0;
            continue;
        }
        sum += sm.SampleCmpLevelZero(cmp, float3(uv, layer), uvz.z + dot(dz_duv, o));
    }
    return sum / float(n);
}

float sk_pcss(Texture2DArray<float> maps, SamplerState depth_sampler, SamplerComparisonState cmp, float layer, float3 uvz,
              float2 dz_duv, float light_uv_at_near, float near_z, float far_z, int search_taps, int filter_taps,
              float angle, float max_filter_uv) {
    float z_r = sk_linearize_depth(uvz.z, near_z, far_z);
    float search_uv = min(light_uv_at_near * max(z_r - near_z, 0.0) / z_r, max_filter_uv);
    float width, height, layers;
    maps.GetDimensions(width, height, layers);
    if (!(search_uv * width > 1.0)) return sk_pcss_filter(maps, cmp, layer, uvz, dz_duv, 0.0, 1, angle);
    float b = sk_pcss_blocker_window_depth(maps, depth_sampler, layer, uvz, dz_duv, search_uv, search_taps, angle);
    if (b < 0.0) return 1.0;
    float z_b = max(sk_linearize_depth(b, near_z, far_z), 1e-30);
    float w = light_uv_at_near * max(z_r - z_b, 0.0) / z_b * near_z / z_r;
    w = clamp(w, 0.0, max_filter_uv);
    return sk_pcss_filter(maps, cmp, layer, uvz, dz_duv, w, filter_taps, angle);
}

float sk_pcss_directional(Texture2DArray<float> maps, SamplerState depth_sampler, SamplerComparisonState cmp, float layer,
                          float3 uvz, float2 dz_duv, float light_uv_per_depth, int search_taps, int filter_taps, float angle,
                          float max_filter_uv) {
#ifdef SK_REVERSED_Z
    float z_r = 1.0 - uvz.z;
#else
    float z_r = uvz.z;
#endif
    float search_uv = min(light_uv_per_depth * max(z_r, 0.0), max_filter_uv);
    float width, height, layers;
    maps.GetDimensions(width, height, layers);
    if (!(search_uv * width > 1.0)) return sk_pcss_filter(maps, cmp, layer, uvz, dz_duv, 0.0, 1, angle);
    float b = sk_pcss_blocker_window_depth(maps, depth_sampler, layer, uvz, dz_duv, search_uv, search_taps, angle);
    if (b < 0.0) return 1.0;
#ifdef SK_REVERSED_Z
    float z_b = 1.0 - b;
#else
    float z_b = b;
#endif
    float w = clamp(light_uv_per_depth * max(z_r - z_b, 0.0), 0.0, max_filter_uv);
    return sk_pcss_filter(maps, cmp, layer, uvz, dz_duv, w, filter_taps, angle);
}
