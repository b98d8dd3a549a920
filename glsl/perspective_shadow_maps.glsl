// shadowkit/glsl/perspective_shadow_maps.glsl - lookup for warped shadow maps (PSM, LiSPSM, TSM,
// uniform) built by shadowkit/perspective_shadow_maps.hpp.
// versions: 330, 450
// stages: fragment
//
// Inputs:
//   warp        mat4  WarpResult::light_view_proj (world -> light clip space)
//   worldPos    vec3  the receiver's world position (interpolated; do NOT interpolate warp * pos
//                     from the vertex stage and divide there: the divide must happen per fragment)
//   shadowMap   sampler2DShadow with compare mode on (LESS/LEQUAL; GREATER for reversed-Z)
//   zeroToOne   bool  true if the matrix was built with ClipDepth::ZeroToOne
// Usage: float lit = sk_warp_shadow(shadowMap, warp, worldPos, 0.0005, false);
// Post-perspective lookup: project by the warp matrix, perspective divide, map to [0,1] uv/depth.
// PSM lights behind the viewer use an inverted projection: the matrix already flips depth, so the
// same compare works.

// xyz = (u, v, depth) in [0,1]; w = 1 if the point is in front of the light's projection and inside
// the map, 0 otherwise (then treat as lit: the fit guarantees every receiver is inside).
vec4 sk_warp_coord(mat4 warp, vec3 worldPos, bool zeroToOne)
{
    vec4 h = warp * vec4(worldPos, 1.0);
    if (h.w <= 0.0) return vec4(0.0);
    vec3 ndc = h.xyz / h.w;
    vec3 c = vec3(ndc.xy * 0.5 + 0.5, zeroToOne ? ndc.z : ndc.z * 0.5 + 0.5);
    bool inside = all(greaterThanEqual(c.xy, vec2(0.0))) && all(lessThanEqual(c.xy, vec2(1.0)));
    return vec4(c, inside ? 1.0 : 0.0);
}

// 1 = lit, 0 = shadowed.
float sk_warp_shadow(sampler2DShadow shadowMap, mat4 warp, vec3 worldPos, float bias, bool zeroToOne)
{
    vec4 c = sk_warp_coord(warp, worldPos, zeroToOne);
    if (c.w == 0.0) return 1.0;
    return texture(shadowMap, vec3(c.xy, c.z - bias));
}
