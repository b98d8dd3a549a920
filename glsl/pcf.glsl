// shadowkit/glsl/pcf.glsl - percentage-closer filtering kernels: box, tent, Poisson and rotated Poisson, each with an optional receiver-plane depth bias
// versions: 330, 450
// stages: fragment
//
// Inputs (per call):
//   sm      sampler2DShadow: the shadow map, a depth texture; or a sampler2DArrayShadow followed by
//           `float layer` (cascades, a depth array): every kernel has both overloads, with the same
//           arithmetic (a layer of an array gives the values of the same depths in a 2D map).
//   uvz     shadow coordinate: xy in [0,1] uv, z the (already biased) window depth of the receiver
//           (sk_shadow_coord in shadow_map.glsl gives it).
//   dz_duv  receiver-plane depth gradient from sk_receiver_plane_depth_bias(uvz) (screen derivatives)
//           or sk_receiver_plane_gradient(step1, step2) (two uvz steps along the plane), or vec2(0.0) to
//           disable it. Each tap at uv offset o then compares with z + dot(dz_duv, o).
// Uniforms: none required. Taps with uv outside [0,1] count as lit.
// GL state: the map's GL_TEXTURE_COMPARE_MODE = GL_COMPARE_REF_TO_TEXTURE, compare func GL_LEQUAL
// (GL_GEQUAL for reversed-Z), GL_LINEAR filtering so each tap is a hardware 2x2 bilinear compare
// (GL_NEAREST works, with harder steps); no blending or culling needed by the lookups.
// Taps: the Poisson kernels read SK_POISSON_TAPS[0 .. SK_POISSON_TAP_COUNT), by default the built-in
// 64-point disk sk_poisson_disk64. A generated array (shadowkit/poisson_disk.hpp poisson_to_glsl)
// under any other name compiles next to it; emitted with PoissonGlsl::ArrayForSnippets before this
// snippet, it replaces it. pcss.glsl shares the block (guarded), so both may be pasted.
// Usage:
//   vec2 g = sk_receiver_plane_depth_bias(uvz);          // call in uniform control flow (dFdx)
//   float lit = sk_pcf_poisson(sm, uvz, g, 3.0 / 2048.0, 16,
//                              6.2831853 * sk_interleaved_gradient_noise(gl_FragCoord.xy));
//   float lit = sk_pcf_tent(cascades, float(i), uvz, g, 2);   // layer i of a depth array
//   box: (2r+1)^2 taps; tent: (2r+1)^2 taps weighted (r+1-|i|)(r+1-|j|); Poisson: `taps` in
//   1..SK_POISSON_TAP_COUNT, rotated by `angle` (0.0: unrotated; per-pixel noise turns banding into noise).
// Cascades: glsl/cascades.glsl's sk_cascade_shadow_filtered (paste this snippet first) runs these
// kernels in the cascade array with the blend band; sk_cascade_pick composes any other.
// Based on Reeves et al. 1987 (PCF), Isidoro 2006 (receiver plane depth bias), Jimenez 2014
// (interleaved gradient noise).
// MIT License. Copyright (c) shadowkit contributors.

// Tells glsl/cascades.glsl (pasted after this) that the kernels exist: it then adds
// sk_cascade_shadow_filtered.
#define SK_PCF_GLSL 1

#ifndef SK_POISSON_DISK64_DEFINED
#define SK_POISSON_DISK64_DEFINED
// 64 points of the unit disk, weighted sample elimination (shadowkit/poisson_disk.hpp:
// poisson_eliminate(PoissonDomain{}, 64, /*seed*/ 1, ...), progressive order, emitted by
// poisson_to_glsl). Any prefix of length k is itself a Poisson set (normalized radius of the
// prefixes 8/16/32/64: 0.80/0.74/0.68/0.74), so `taps` may be any count in 1..64.
const vec2 sk_poisson_disk64[64] = vec2[64](
    vec2(0.667273045, 0.596935987),
    vec2(-0.974912941, 0.140261471),
    vec2(-0.00817528274, -0.737295032),
    vec2(-0.357976198, 0.743402183),
    vec2(0.810684562, -0.55637908),
    vec2(-0.36176604, -0.220403671),
    vec2(0.919741094, -0.0295969304),
    vec2(-0.899047136, -0.401866853),
    vec2(-0.35729304, 0.256965429),
    vec2(-0.823843956, 0.556563199),
    vec2(-0.442809522, -0.788640141),
    vec2(-0.00385137554, 0.00996741187),
    vec2(0.496161342, -0.789134264),
    vec2(0.307677567, 0.479340941),
    vec2(0.0261630546, -0.361821979),
    vec2(0.649081528, 0.19646357),
    vec2(-0.0496209897, 0.569143891),
    vec2(0.493515879, -0.423292518),
    vec2(-0.666885555, 0.217370793),
    vec2(0.90251708, 0.411130309),
    vec2(0.23290506, 0.758692503),
    vec2(0.249936044, -0.941124558),
    vec2(0.311741292, -0.203952923),
    vec2(0.519844234, 0.84039098),
    vec2(-0.496722907, -0.457896143),
    vec2(-0.926848173, -0.135281667),
    vec2(-0.00672815274, 0.26900959),
    vec2(-0.0590348318, -0.987052143),
    vec2(0.721485615, -0.162640795),
    vec2(-0.248856291, 0.0319613107),
    vec2(-0.301116526, -0.580681205),
    vec2(-0.111001909, 0.789575696),
    vec2(-0.5985865, 0.553151011),
    vec2(-0.584493697, -0.211627632),
    vec2(0.192017213, 0.171763808),
    vec2(-0.137889117, -0.174055114),
    vec2(0.254576564, -0.729208648),
    vec2(-0.365630656, 0.529652059),
    vec2(-0.630011797, 0.0149271172),
    vec2(-0.925787508, 0.337520659),
    vec2(-0.24114193, -0.896481395),
    vec2(0.935237825, -0.222696722),
    vec2(0.574212909, 0.0197216701),
    vec2(-0.0712009072, -0.548193455),
    vec2(0.359571993, 0.289480388),
    vec2(0.530840635, -0.209503949),
    vec2(-0.68105185, 0.722644687),
    vec2(0.10657119, 0.892661333),
    vec2(0.083066918, -0.177033007),
    vec2(0.503817022, 0.491984129),
    vec2(-0.727698088, -0.454516619),
    vec2(0.694889069, -0.689536989),
    vec2(0.688220203, 0.412640005),
    vec2(0.419547528, -0.584399879),
    vec2(-0.268478572, 0.900935829),
    vec2(0.125276238, 0.576343596),
    vec2(0.389038563, -0.0452882573),
    vec2(-0.474447995, 0.118304528),
    vec2(-0.713988602, 0.392602742),
    vec2(0.811533272, 0.118944764),
    vec2(0.107297376, -0.526566327),
    vec2(-0.0845918506, 0.963354111),
    vec2(0.375263661, 0.646681547),
    vec2(-0.322467238, -0.398355454));

// Interleaved gradient noise (Jimenez 2014) in [0,1) from a pixel position (gl_FragCoord.xy).
float sk_interleaved_gradient_noise(vec2 pixel) {
    return fract(52.9829189 * fract(dot(pixel, vec2(0.06711056, 0.00583715))));
}
#endif
// The tap array of the Poisson kernels: the built-in disk, or your own (poisson_to_glsl with
// PoissonGlsl::ArrayForSnippets emits `#define SK_POISSON_TAPS NAME` and SK_POISSON_TAP_COUNT).
#ifndef SK_POISSON_TAPS
#define SK_POISSON_TAPS sk_poisson_disk64
#define SK_POISSON_TAP_COUNT 64
#endif
#ifndef SK_POISSON_TAP_COUNT
#error "SK_POISSON_TAPS needs SK_POISSON_TAP_COUNT, the length of its array"
#endif

// Receiver-plane depth gradient (dz/du, dz/dv) from two steps of uvz along the receiver's plane
// (Isidoro 2006): solves [du1 dv1; du2 dv2] (dz/du, dz/dv) = (dz1, dz2). vec2(0.0) when singular.
// Any stage: a deferred pass steps along the G-buffer's plane (two tangents, through sk_shadow_coord),
// which has no derivatives across silhouettes.
vec2 sk_receiver_plane_gradient(vec3 step1, vec3 step2) {
    float det = step1.x * step2.y - step1.y * step2.x;
    float scale = (abs(step1.x) + abs(step1.y)) * (abs(step2.x) + abs(step2.y));
    if (!(abs(det) > 1e-7 * scale)) return vec2(0.0);
    return vec2(step2.y * step1.z - step1.y * step2.z, step1.x * step2.z - step2.x * step1.z) / det;
}

// The same from screen-space derivatives of uvz. Fragment stage only; call it outside non-uniform
// control flow.
vec2 sk_receiver_plane_depth_bias(vec3 uvz) {
    return sk_receiver_plane_gradient(dFdx(uvz), dFdy(uvz));
}

// One hardware-compare tap at a uv offset, with the receiver plane applied; outside the map: lit.
float sk_pcf_tap(sampler2DShadow sm, vec3 uvz, vec2 dz_duv, vec2 offset_uv) {
    vec2 uv = uvz.xy + offset_uv;
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return 1.0;
    return texture(sm, vec3(uv, uvz.z + dot(dz_duv, offset_uv)));
}

// Hard shadow: one tap (a bilinear 2x2 compare with GL_LINEAR).
float sk_pcf_hard(sampler2DShadow sm, vec3 uvz) {
    return sk_pcf_tap(sm, uvz, vec2(0.0), vec2(0.0));
}

// Box: (2r+1)^2 taps one texel apart, equal weights. r is clamped to [0, 8].
float sk_pcf_box(sampler2DShadow sm, vec3 uvz, vec2 dz_duv, int radius_texels) {
    int r = clamp(radius_texels, 0, 8);
    vec2 texel = 1.0 / vec2(textureSize(sm, 0));
    float sum = 0.0;
    for (int j = -r; j <= r; ++j)
        for (int i = -r; i <= r; ++i)
            sum += sk_pcf_tap(sm, uvz, dz_duv, vec2(float(i), float(j)) * texel);
    float n = float(2 * r + 1);
    return sum / (n * n);
}

// Tent: (2r+1)^2 bilinear taps weighted (r+1-|i|)(r+1-|j|): a separable tent of radius r+1 texels
// convolved with the hardware's 1-texel bilinear tent. r is clamped to [0, 8].
float sk_pcf_tent(sampler2DShadow sm, vec3 uvz, vec2 dz_duv, int radius_texels) {
    int r = clamp(radius_texels, 0, 8);
    vec2 texel = 1.0 / vec2(textureSize(sm, 0));
    float sum = 0.0;
    float wsum = 0.0;
    for (int j = -r; j <= r; ++j)
        for (int i = -r; i <= r; ++i) {
            float w = float(r + 1 - abs(i)) * float(r + 1 - abs(j));
            sum += w * sk_pcf_tap(sm, uvz, dz_duv, vec2(float(i), float(j)) * texel);
            wsum += w;
        }
    return sum / wsum;
}

// Poisson disk: `taps` (clamped to 1..SK_POISSON_TAP_COUNT) points of SK_POISSON_TAPS scaled to radius_uv and
// rotated by `angle` radians (0.0: unrotated). radius_uv <= 0 or taps == 1 is the hard shadow.
float sk_pcf_poisson(sampler2DShadow sm, vec3 uvz, vec2 dz_duv, float radius_uv, int taps, float angle) {
    int n = clamp(taps, 1, SK_POISSON_TAP_COUNT);
    if (!(radius_uv > 0.0) || n == 1) return sk_pcf_tap(sm, uvz, dz_duv, vec2(0.0));
    float c = cos(angle);
    float s = sin(angle);
    mat2 rot = mat2(c, s, -s, c);
    float sum = 0.0;
    for (int i = 0; i < n; ++i)
        sum += sk_pcf_tap(sm, uvz, dz_duv, rot * SK_POISSON_TAPS[i] * radius_uv);
    return sum / float(n);
}

// Rotated Poisson: the angle from interleaved gradient noise at this pixel (fragment stage).
float sk_pcf_poisson_rotated(sampler2DShadow sm, vec3 uvz, vec2 dz_duv, float radius_uv, int taps) {
    return sk_pcf_poisson(sm, uvz, dz_duv, radius_uv, taps,
                          6.28318531 * sk_interleaved_gradient_noise(gl_FragCoord.xy));
}

// ---- depth arrays: the same kernels on one layer of a sampler2DArrayShadow ----------------------
// Each is the 2D kernel above with texture(sm, vec4(uv, layer, ref)) for texture(sm, vec3(uv, ref))
// and textureSize(sm, 0).xy for the map's size: identical taps, weights and order.

// One hardware-compare tap at a uv offset in layer `layer`, with the receiver plane; outside: lit.
float sk_pcf_tap(sampler2DArrayShadow sm, float layer, vec3 uvz, vec2 dz_duv, vec2 offset_uv) {
    vec2 uv = uvz.xy + offset_uv;
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return 1.0;
    return texture(sm, vec4(uv, layer, uvz.z + dot(dz_duv, offset_uv)));
}

// Hard shadow in one layer.
float sk_pcf_hard(sampler2DArrayShadow sm, float layer, vec3 uvz) {
    return sk_pcf_tap(sm, layer, uvz, vec2(0.0), vec2(0.0));
}

// Box in one layer: (2r+1)^2 taps one texel apart. r is clamped to [0, 8].
float sk_pcf_box(sampler2DArrayShadow sm, float layer, vec3 uvz, vec2 dz_duv, int radius_texels) {
    int r = clamp(radius_texels, 0, 8);
    vec2 texel = 1.0 / vec2(textureSize(sm, 0).xy);
    float sum = 0.0;
    for (int j = -r; j <= r; ++j)
        for (int i = -r; i <= r; ++i)
            sum += sk_pcf_tap(sm, layer, uvz, dz_duv, vec2(float(i), float(j)) * texel);
    float n = float(2 * r + 1);
    return sum / (n * n);
}

// Tent in one layer: (2r+1)^2 taps weighted (r+1-|i|)(r+1-|j|). r is clamped to [0, 8].
float sk_pcf_tent(sampler2DArrayShadow sm, float layer, vec3 uvz, vec2 dz_duv, int radius_texels) {
    int r = clamp(radius_texels, 0, 8);
    vec2 texel = 1.0 / vec2(textureSize(sm, 0).xy);
    float sum = 0.0;
    float wsum = 0.0;
    for (int j = -r; j <= r; ++j)
        for (int i = -r; i <= r; ++i) {
            float w = float(r + 1 - abs(i)) * float(r + 1 - abs(j));
            sum += w * sk_pcf_tap(sm, layer, uvz, dz_duv, vec2(float(i), float(j)) * texel);
            wsum += w;
        }
    return sum / wsum;
}

// Poisson disk in one layer (see the 2D version).
float sk_pcf_poisson(sampler2DArrayShadow sm, float layer, vec3 uvz, vec2 dz_duv, float radius_uv, int taps,
                     float angle) {
    int n = clamp(taps, 1, SK_POISSON_TAP_COUNT);
    if (!(radius_uv > 0.0) || n == 1) return sk_pcf_tap(sm, layer, uvz, dz_duv, vec2(0.0));
    float c = cos(angle);
    float s = sin(angle);
    mat2 rot = mat2(c, s, -s, c);
    float sum = 0.0;
    for (int i = 0; i < n; ++i)
        sum += sk_pcf_tap(sm, layer, uvz, dz_duv, rot * SK_POISSON_TAPS[i] * radius_uv);
    return sum / float(n);
}

// Rotated Poisson in one layer: the angle from interleaved gradient noise at this pixel.
float sk_pcf_poisson_rotated(sampler2DArrayShadow sm, float layer, vec3 uvz, vec2 dz_duv, float radius_uv, int taps) {
    return sk_pcf_poisson(sm, layer, uvz, dz_duv, radius_uv, taps,
                          6.28318531 * sk_interleaved_gradient_noise(gl_FragCoord.xy));
}
