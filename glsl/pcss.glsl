// shadowkit/glsl/pcss.glsl - percentage-closer soft shadows: blocker search on a depth sampler2D, penumbra estimate on linear depths, Poisson PCF through a sampler2DShadow
// versions: 330, 450
// stages: fragment
//
// Inputs (per call):
//   depth_map  sampler2D view of the shadow map (compare mode off, nearest).
//   sm         sampler2DShadow view of the same map (compare mode on).
//   Depth arrays (cascades): every function has an overload taking sampler2DArray depth_maps,
//   sampler2DArrayShadow sm (two views or two sampler objects of one GL_TEXTURE_2D_ARRAY) and a
//   `float layer` after the samplers; the blocker search reads textureLod(depth_maps,
//   vec3(uv, layer), 0.0).r where the 2D version reads textureLod(depth_map, uv, 0.0).r, the rest is
//   the same arithmetic. Per cascade, light_uv_per_depth changes with the cascade's width and depth
//   range (docs/cascades.md, "Filtering").
//   uvz        shadow coordinate: uv in [0,1], z the receiver's (biased) window depth.
//   dz_duv     receiver-plane gradient (sk_receiver_plane_depth_bias in pcf.glsl) or vec2(0.0); each
//              blocker-search and filter tap at uv offset o compares with uvz.z + dot(dz_duv, o).
//   light_uv_at_near  perspective light: light width / (near * 2 tan(fov/2)), the light's width in uv
//              measured on the near plane (shadowkit::pcss_light_uv_at_near). Directional light
//              (sk_pcss_directional): light_uv_per_depth = 2 tan(theta/2) (far - near) / ortho width.
//   near_z, far_z  the light's clip planes (far_z <= 0.0 means an infinite far plane). Put the near plane at
//              the casters (shadowkit::pcss_fit_near_plane): the blocker search is cut there.
//   search_taps, filter_taps  Poisson taps (1..SK_POISSON_TAP_COUNT) for the blocker search and the filter.
//   angle      rotation of the Poisson disk (0.0 unrotated; 6.2831853 * noise for rotated).
//   max_filter_uv  clamp of the filter width and of the search width (uv), e.g. 0.05: a blocker
//              farther than that from the receiver could only widen the filter beyond its clamp.
// Uniforms: none required (pass the values above). Defines: SK_REVERSED_Z before this snippet for
// reversed-Z depth (1 at near); SK_POISSON_TAPS / SK_POISSON_TAP_COUNT as in pcf.glsl.
// GL state: bind the map twice with two sampler objects (GL 3.3): depth_map with
// GL_TEXTURE_COMPARE_MODE = GL_NONE and GL_NEAREST, sm with GL_COMPARE_REF_TO_TEXTURE, GL_LEQUAL
// (GL_GEQUAL for reversed-Z) and GL_LINEAR; GL_CLAMP_TO_BORDER with border depth 1 (reversed: 0).
// Taps with uv outside [0,1] are ignored by the blocker search and count as lit in the filter.
// A search region narrower than one texel (light size 0, receiver at the near plane) returns the
// single 2x2 hardware compare texture(sm, uvz): PCSS reduces exactly to the hard shadow.
// Usage:
//   float lit = sk_pcss(depth_map, sm, uvz, vec2(0.0), u_light_uv_at_near, u_near, u_far, 16, 16,
//                       6.2831853 * sk_interleaved_gradient_noise(gl_FragCoord.xy), 0.05);
// Formulas (Fernando 2005; Apelles thesis eqs. 3.20-3.22), all on linear depths z:
//   search width = min(light_uv_at_near (z_r - near) / z_r, max_filter_uv)
//   filter width = light_uv_at_near (z_r - z_b) / z_b * near / z_r   (the penumbra on the near plane)
// MIT License. Copyright (c) shadowkit contributors.

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

// Window depth -> eye distance for a perspective light (far_z <= 0.0: infinite far plane).
float sk_linearize_depth(float z_w, float near_z, float far_z) {
    float z = clamp(z_w, 0.0, 1.0);
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

// Average window depth of the blockers among `taps` Poisson samples of a disk of diameter
// search_uv; -1.0 when there is none. With the receiver plane dz_duv, the tap at uv offset o
// compares with uvz.z + dot(dz_duv, o), so a receiver tilted towards the light does not find
// itself as a blocker (vec2(0.0): compare every tap with uvz.z).
float sk_pcss_blocker_window_depth(sampler2D depth_map, vec3 uvz, vec2 dz_duv, float search_uv, int taps, float angle) {
    int n = clamp(taps, 1, SK_POISSON_TAP_COUNT);
    float c = cos(angle);
    float s = sin(angle);
    mat2 rot = mat2(c, s, -s, c);
    float sum = 0.0;
    float count = 0.0;
    for (int i = 0; i < n; ++i) {
        vec2 o = rot * SK_POISSON_TAPS[i] * (0.5 * search_uv);
        vec2 uv = uvz.xy + o;
        if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) continue;
        float d = textureLod(depth_map, uv, 0.0).r;
        if (sk_depth_closer(d, uvz.z + dot(dz_duv, o))) {
            sum += d;
            count += 1.0;
        }
    }
    return count > 0.0 ? sum / count : -1.0;
}

// The search without a receiver plane (every tap compares with uvz.z).
float sk_pcss_blocker_window_depth(sampler2D depth_map, vec3 uvz, float search_uv, int taps, float angle) {
    return sk_pcss_blocker_window_depth(depth_map, uvz, vec2(0.0), search_uv, taps, angle);
}

// Filter taps for a filter of width filter_uv on a map of map_texels texels: ceil(pi (D/2)^2) for
// D = filter_uv * map_texels, clamped to [min_taps, max_taps] (shadowkit::pcss_tap_budget).
int sk_pcss_tap_budget(float filter_uv, float map_texels, int min_taps, int max_taps) {
    int lo = max(min_taps, 1);
    int hi = max(max_taps, lo);
    float d = filter_uv * map_texels;
    if (!(d > 1.0)) return lo;
    float want = ceil(3.14159265 * 0.25 * d * d);
    if (!(want < float(hi))) return hi;
    return max(int(want), lo);
}

// Poisson PCF with hardware compare (same as sk_pcf_poisson in pcf.glsl, local copy).
float sk_pcss_filter(sampler2DShadow sm, vec3 uvz, vec2 dz_duv, float width_uv, int taps, float angle) {
    int n = clamp(taps, 1, SK_POISSON_TAP_COUNT);
    float radius = 0.5 * width_uv;
    if (!(radius > 0.0) || n == 1) {
        if (any(lessThan(uvz.xy, vec2(0.0))) || any(greaterThan(uvz.xy, vec2(1.0)))) return 1.0;
        return texture(sm, uvz);
    }
    float c = cos(angle);
    float s = sin(angle);
    mat2 rot = mat2(c, s, -s, c);
    float sum = 0.0;
    for (int i = 0; i < n; ++i) {
        vec2 o = rot * SK_POISSON_TAPS[i] * radius;
        vec2 uv = uvz.xy + o;
        if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) {
            sum += 1.0;
            continue;
        }
        sum += texture(sm, vec3(uv, uvz.z + dot(dz_duv, o)));
    }
    return sum / float(n);
}

// PCSS for a perspective (spot) light. Returns the lit fraction in [0,1].
float sk_pcss(sampler2D depth_map, sampler2DShadow sm, vec3 uvz, vec2 dz_duv, float light_uv_at_near,
              float near_z, float far_z, int search_taps, int filter_taps, float angle, float max_filter_uv) {
    float z_r = sk_linearize_depth(uvz.z, near_z, far_z);
    // the pyramid from the receiver to the light cut at the near plane, clamped like the filter
    float search_uv = min(light_uv_at_near * max(z_r - near_z, 0.0) / z_r, max_filter_uv);
    // a search region narrower than a texel (light size 0, receiver at the near plane) cannot see
    // what the 2x2 compare sees: return that compare, the exact hard-shadow limit
    if (!(search_uv * float(textureSize(depth_map, 0).x) > 1.0)) return sk_pcss_filter(sm, uvz, dz_duv, 0.0, 1, angle);
    float b = sk_pcss_blocker_window_depth(depth_map, uvz, dz_duv, search_uv, search_taps, angle);
    if (b < 0.0) return 1.0;
    float z_b = max(sk_linearize_depth(b, near_z, far_z), 1e-30);
    float w = light_uv_at_near * max(z_r - z_b, 0.0) / z_b * near_z / z_r;
    w = clamp(w, 0.0, max_filter_uv);
    return sk_pcss_filter(sm, uvz, dz_duv, w, filter_taps, angle);
}

// PCSS for a directional (orthographic) light: window depth is linear, so the search width is
// light_uv_per_depth * (window depth from the near plane) and the filter width
// light_uv_per_depth * (z_r - z_b) in window units.
float sk_pcss_directional(sampler2D depth_map, sampler2DShadow sm, vec3 uvz, vec2 dz_duv, float light_uv_per_depth,
                          int search_taps, int filter_taps, float angle, float max_filter_uv) {
#ifdef SK_REVERSED_Z
    float z_r = 1.0 - uvz.z;
#else
    float z_r = uvz.z;
#endif
    float search_uv = min(light_uv_per_depth * max(z_r, 0.0), max_filter_uv);
    if (!(search_uv * float(textureSize(depth_map, 0).x) > 1.0)) return sk_pcss_filter(sm, uvz, dz_duv, 0.0, 1, angle);
    float b = sk_pcss_blocker_window_depth(depth_map, uvz, dz_duv, search_uv, search_taps, angle);
    if (b < 0.0) return 1.0;
#ifdef SK_REVERSED_Z
    float z_b = 1.0 - b;
#else
    float z_b = b;
#endif
    float w = clamp(light_uv_per_depth * max(z_r - z_b, 0.0), 0.0, max_filter_uv);
    return sk_pcss_filter(sm, uvz, dz_duv, w, filter_taps, angle);
}

// ---- depth arrays: the same functions on one layer (cascades) ------------------------------------

// Blocker search in layer `layer` of a depth array (compare mode off, nearest).
float sk_pcss_blocker_window_depth(sampler2DArray depth_maps, float layer, vec3 uvz, vec2 dz_duv, float search_uv, int taps,
                                   float angle) {
    int n = clamp(taps, 1, SK_POISSON_TAP_COUNT);
    float c = cos(angle);
    float s = sin(angle);
    mat2 rot = mat2(c, s, -s, c);
    float sum = 0.0;
    float count = 0.0;
    for (int i = 0; i < n; ++i) {
        vec2 o = rot * SK_POISSON_TAPS[i] * (0.5 * search_uv);
        vec2 uv = uvz.xy + o;
        if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) continue;
        float d = textureLod(depth_maps, vec3(uv, layer), 0.0).r;
        if (sk_depth_closer(d, uvz.z + dot(dz_duv, o))) {
            sum += d;
            count += 1.0;
        }
    }
    return count > 0.0 ? sum / count : -1.0;
}

// The array search without a receiver plane.
float sk_pcss_blocker_window_depth(sampler2DArray depth_maps, float layer, vec3 uvz, float search_uv, int taps, float angle) {
    return sk_pcss_blocker_window_depth(depth_maps, layer, uvz, vec2(0.0), search_uv, taps, angle);
}

// Poisson PCF in one layer of a compare-mode depth array.
float sk_pcss_filter(sampler2DArrayShadow sm, float layer, vec3 uvz, vec2 dz_duv, float width_uv, int taps, float angle) {
    int n = clamp(taps, 1, SK_POISSON_TAP_COUNT);
    float radius = 0.5 * width_uv;
    if (!(radius > 0.0) || n == 1) {
        if (any(lessThan(uvz.xy, vec2(0.0))) || any(greaterThan(uvz.xy, vec2(1.0)))) return 1.0;
        return texture(sm, vec4(uvz.xy, layer, uvz.z));
    }
    float c = cos(angle);
    float s = sin(angle);
    mat2 rot = mat2(c, s, -s, c);
    float sum = 0.0;
    for (int i = 0; i < n; ++i) {
        vec2 o = rot * SK_POISSON_TAPS[i] * radius;
        vec2 uv = uvz.xy + o;
        if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) {
            sum += 1.0;
            continue;
        }
        sum += texture(sm, vec4(uv, layer, uvz.z + dot(dz_duv, o)));
    }
    return sum / float(n);
}

// PCSS for a perspective light in one layer (an array of spot maps).
float sk_pcss(sampler2DArray depth_maps, sampler2DArrayShadow sm, float layer, vec3 uvz, vec2 dz_duv, float light_uv_at_near,
              float near_z, float far_z, int search_taps, int filter_taps, float angle, float max_filter_uv) {
    float z_r = sk_linearize_depth(uvz.z, near_z, far_z);
    float search_uv = min(light_uv_at_near * max(z_r - near_z, 0.0) / z_r, max_filter_uv);
    if (!(search_uv * float(textureSize(depth_maps, 0).x) > 1.0)) return sk_pcss_filter(sm, layer, uvz, dz_duv, 0.0, 1, angle);
    float b = sk_pcss_blocker_window_depth(depth_maps, layer, uvz, dz_duv, search_uv, search_taps, angle);
    if (b < 0.0) return 1.0;
    float z_b = max(sk_linearize_depth(b, near_z, far_z), 1e-30);
    float w = light_uv_at_near * max(z_r - z_b, 0.0) / z_b * near_z / z_r;
    w = clamp(w, 0.0, max_filter_uv);
    return sk_pcss_filter(sm, layer, uvz, dz_duv, w, filter_taps, angle);
}

// PCSS for a directional light in one layer (a cascade: light_uv_per_depth of that cascade).
float sk_pcss_directional(sampler2DArray depth_maps, sampler2DArrayShadow sm, float layer, vec3 uvz, vec2 dz_duv,
                          float light_uv_per_depth, int search_taps, int filter_taps, float angle, float max_filter_uv) {
#ifdef SK_REVERSED_Z
    float z_r = 1.0 - uvz.z;
#else
    float z_r = uvz.z;
#endif
    float search_uv = min(light_uv_per_depth * max(z_r, 0.0), max_filter_uv);
    if (!(search_uv * float(textureSize(depth_maps, 0).x) > 1.0)) return sk_pcss_filter(sm, layer, uvz, dz_duv, 0.0, 1, angle);
    float b = sk_pcss_blocker_window_depth(depth_maps, layer, uvz, dz_duv, search_uv, search_taps, angle);
    if (b < 0.0) return 1.0;
#ifdef SK_REVERSED_Z
    float z_b = 1.0 - b;
#else
    float z_b = b;
#endif
    float w = clamp(light_uv_per_depth * max(z_r - z_b, 0.0), 0.0, max_filter_uv);
    return sk_pcss_filter(sm, layer, uvz, dz_duv, w, filter_taps, angle);
}
