// shadowkit/glsl/perspective_shadow_maps.glsl - lookup and map depth for warped shadow maps (uniform, PSM,
// LiSPSM, TSM) built by shadowkit/perspective_shadow_maps.hpp.
// versions: 330, 450
// stages: fragment
//
// Inputs:
//   warp         mat4  WarpResult::light_view_proj (world -> light clip: where a point is in the map)
//   depth_proj   mat4  WarpResult::depth_view_proj (world -> clip whose z / w is the map's depth); equal
//                      to warp except for TSM while it warps (WarpResult::separate_depth)
//   world_pos    vec3  the receiver's world position (interpolated; do NOT interpolate warp * pos from the
//                      vertex stage and divide there: the divide must happen per fragment)
//   shadow_map   sampler2DShadow, GL_TEXTURE_COMPARE_MODE = GL_COMPARE_REF_TO_TEXTURE, compare LEQUAL
//                (GEQUAL for reversed-Z)
//   zero_to_one  bool  true if the matrices were built with ClipDepth::ZeroToOne
// GL state of the shadow pass: depth test LESS (GREATER for reversed-Z), depth writes on, color writes
// off. Every method preserves orientation: keep glFrontFace(GL_CCW); back-face (or front-face) culling
// works as for a plain shadow map. Bias: glPolygonOffset when the map's depth is rasterized
// (separate_depth false); with separate_depth the fragment stage writes
//   gl_FragDepth = sk_warp_map_depth(v_depth_clip, 2.0, 0.0, zero_to_one);
// (v_depth_clip = depth_proj * world position, output by the vertex stage; glPolygonOffset does not
// apply to a written gl_FragDepth, so the slope-scaled offset is computed here).
// Usage (receiver pass): float lit = sk_warp_shadow(shadow_map, warp, depth_proj, world_pos, 0.0005, false);
//   automatic bias (true depths in the map): sk_warp_shadow_auto(shadow_map, warp, inverse_warp, depth_proj,
//                                                                world_pos, world_normal, false, 0.0, 1.0);
// PSM lights behind the viewer use an inverted projection: the matrix already flips depth, so the same
// compare works.
//
// MIT License. Copyright (c) shadowkit contributors.

// xyz = (u, v, depth) in [0,1]; w = 1 if the point is in front of the light's projection and inside the
// map, 0 otherwise (then treat it as lit: the fit guarantees every receiver is inside).
vec4 sk_warp_coord(mat4 warp, mat4 depth_proj, vec3 world_pos, bool zero_to_one)
{
    vec4 h = warp * vec4(world_pos, 1.0);
    vec4 hd = depth_proj * vec4(world_pos, 1.0);
    if (h.w <= 0.0 || hd.w <= 0.0) return vec4(0.0);
    vec2 xy = h.xy / h.w;
    float z = hd.z / hd.w;
    vec3 c = vec3(xy * 0.5 + 0.5, zero_to_one ? z : z * 0.5 + 0.5);
    bool inside = all(greaterThanEqual(c.xy, vec2(0.0))) && all(lessThanEqual(c.xy, vec2(1.0)));
    return vec4(c, inside ? 1.0 : 0.0);
}

// 1 = lit, 0 = shadowed (bias in window depth; negative for reversed-Z).
float sk_warp_shadow(sampler2DShadow shadow_map, mat4 warp, mat4 depth_proj, vec3 world_pos, float bias_window,
                     bool zero_to_one)
{
    vec4 c = sk_warp_coord(warp, depth_proj, world_pos, zero_to_one);
    if (c.w == 0.0) return 1.0;
    return texture(shadow_map, vec3(c.xy, c.z - bias_window));
}

// The automatic bias for any warp, TSM's separate depth included (no constant, no polygon offset:
// render the map's true depths, sk_warp_map_depth(v_depth_clip, 0.0, 0.0, ...) for TSM). The 2x2
// filter as four compares at the texel centres around the lookup, each against the receiver plane's
// own depth there: the light ray through the texel centre (warp_inverse unprojects it at two depths)
// meets the plane through world_pos with `normal`, and depth_proj gives that point's depth (Isidoro
// 2006's receiver plane, taken through TSM's two matrices exactly instead of linearly). Margin: two
// steps of the map's format (depth_step: 0.0 for float32), float rounding of the depths (2^-21 (1 +
// |z|)) and of world_pos (2^-21 |p|_1 |dz/dp|_1), and 1/8 texel of the plane's slope for creases.
// warp_inverse: inverse(warp), in double on the CPU (WarpResult::light_view_proj's inverse).
// Returns 1 lit .. 0 shadowed; `outside` where the point is not in the map; 1.0 edge-on.
float sk_warp_shadow_auto(sampler2DShadow shadow_map, mat4 warp, mat4 warp_inverse, mat4 depth_proj, vec3 world_pos,
                          vec3 normal, bool zero_to_one, float depth_step, float outside)
{
    vec4 c = sk_warp_coord(warp, depth_proj, world_pos, zero_to_one);
    if (c.w == 0.0) return outside;
    vec3 n = normalize(normal);
    vec2 size = vec2(textureSize(shadow_map, 0));
    vec2 f = c.xy * size - 0.5;
    vec2 i0 = floor(f);
    vec2 w = f - i0;
    float zn = zero_to_one ? 0.0 : -1.0;
    vec4 z;
    for (int k = 0; k < 4; ++k) {
        vec2 ndc = ((i0 + vec2(float(k & 1), float(k >> 1)) + 0.5) / size) * 2.0 - 1.0;
        vec4 a = warp_inverse * vec4(ndc, zn, 1.0), b = warp_inverse * vec4(ndc, 1.0, 1.0);
        vec3 x0 = a.xyz / a.w, x1 = b.xyz / b.w;
        float den = dot(n, x1 - x0);
        float t = den != 0.0 ? dot(n, world_pos - x0) / den : 0.0;
        vec4 hd = depth_proj * vec4(x0 + t * (x1 - x0), 1.0);
        float zk = hd.z / hd.w;
        zk = zero_to_one ? zk : zk * 0.5 + 0.5;
        z[k] = den != 0.0 && hd.w > 0.0 && abs(zk) < 3.0e38 ? zk : c.z;  // edge-on to that ray: the point's own depth
    }
    // the margin: format steps, float rounding of depths and position, 1/8 texel of the plane's slope
    vec4 hp = depth_proj * vec4(world_pos, 1.0);
    vec3 rz = vec3(depth_proj[0][2], depth_proj[1][2], depth_proj[2][2]), rw = vec3(depth_proj[0][3], depth_proj[1][3], depth_proj[2][3]);
    vec3 jz = abs(rz - (hp.z / hp.w) * rw) / abs(hp.w) * (zero_to_one ? 1.0 : 0.5);
    vec3 ap = abs(world_pos);
    float pos_err = exp2(-21.0) * (ap.x + ap.y + ap.z) * (jz.x + jz.y + jz.z);
    float slope = abs(z.y - z.x) + abs(z.z - z.x);
    float eps = 2.0 * max(depth_step, 0.0) + exp2(-21.0) * (1.0 + abs(c.z)) + 2.0 * pos_err + 0.125 * slope;
    vec4 weight = vec4((1.0 - w.x) * (1.0 - w.y), w.x * (1.0 - w.y), (1.0 - w.x) * w.y, w.x * w.y);
    float v = 0.0;
    for (int k = 0; k < 4; ++k) {
        vec2 uv = (i0 + vec2(float(k & 1), float(k >> 1)) + 0.5) / size;
        v += weight[k] * texture(shadow_map, vec3(uv, clamp(z[k] - eps, 0.0, 1.0)));
    }
    return v;
}

// Shadow pass with separate_depth (Martin & Tan's TSM depth): the window depth to write to
// gl_FragDepth from depth_clip = depth_proj * world position (interpolated from the vertex stage:
// perspective-correct, hence exact), plus slope_scale times its largest screen-space slope and
// constant_bias (both negative for reversed-Z), clamped to [0, 1].
float sk_warp_map_depth(vec4 depth_clip, float slope_scale, float constant_bias, bool zero_to_one)
{
    float z = depth_clip.z / depth_clip.w;
    float window_z = zero_to_one ? z : z * 0.5 + 0.5;
    float slope = max(abs(dFdx(window_z)), abs(dFdy(window_z)));
    return clamp(window_z + slope_scale * slope + constant_bias, 0.0, 1.0);
}
