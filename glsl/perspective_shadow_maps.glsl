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
float sk_warp_shadow(sampler2DShadow shadow_map, mat4 warp, mat4 depth_proj, vec3 world_pos, float bias,
                     bool zero_to_one)
{
    vec4 c = sk_warp_coord(warp, depth_proj, world_pos, zero_to_one);
    if (c.w == 0.0) return 1.0;
    return texture(shadow_map, vec3(c.xy, c.z - bias));
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
