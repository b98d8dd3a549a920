// shadowkit/glsl/shadow_map.glsl - plain shadow-map lookups (Williams 1978): the shadow coordinate, a spot/directional map and a point light's cube map, with a depth bias
// versions: 330, 450
// stages: fragment
//
// Inputs: the world-space position of the shaded point; the light's view-projection matrix (the
// one the map was rendered with); `bias`, in window-depth units, subtracted from the receiver's
// depth before the compare (added with SK_REVERSED_Z): 0.0 for none. A window-depth bias is a
// world bias times the depth metric's slope (shadowkit/shadow_bias.hpp: bias_depth_metric_slope;
// bias_depth_metric_resolution is the smallest useful one); for a perspective light the same
// window bias is a world bias growing with the distance squared, so pair a small constant with
// normal offset (bias_normal_offset_position: look the map up at world_pos + normal * offset) or
// with glPolygonOffset when rendering the map (bias_polygon_offset). docs/shadow_map.md has numbers.
// zero_to_one: true when the projection was built for glClipControl(..., GL_ZERO_TO_ONE).
// Defines: SK_REVERSED_Z before this snippet for reversed-Z maps (1 at near, compare GL_GEQUAL).
// Lights: sk_cube_shadow_visibility takes `vec4 light_position` as the shadowkit headers do (w > 0:
// a point light at xyz / w; a cube map needs a point light: other w give 1.0, lit).
// Uniforms: none required (pass the values above).
// GL state: the map is a depth texture (GL_DEPTH_COMPONENT24 / 32F) rendered with depth test
// GL_LESS (GL_GREATER reversed) and cleared to 1 (reversed: 0); sampled as sampler2DShadow /
// samplerCubeShadow with GL_TEXTURE_COMPARE_MODE = GL_COMPARE_REF_TO_TEXTURE, GL_TEXTURE_COMPARE_FUNC
// GL_LEQUAL (GL_GEQUAL reversed-Z), GL_LINEAR for the hardware 2x2 percentage-closer filter
// (GL_NEAREST: one texel, hard), GL_CLAMP_TO_EDGE; GL_TEXTURE_CUBE_MAP_SEAMLESS for cube maps.
// Returns 1 = lit, 0 = shadowed (fractions at the 2x2 filter's edges); points outside the light
// frustum get `outside`.
// Usage:
//   float v = sk_shadow_map_visibility(u_shadow_map, u_light_view_proj, world_pos, false, 1e-4, 1.0);
// MIT License. Copyright (c) shadowkit contributors.

// Shadow-map coordinates (uv in [0,1], depth in window space) of a world point, and clip w.
vec4 sk_shadow_coord(mat4 light_view_proj, vec3 world_pos, bool zero_to_one) {
    vec4 clip = light_view_proj * vec4(world_pos, 1.0);
    vec3 ndc = clip.xyz / clip.w;
    vec3 win = vec3(ndc.xy * 0.5 + 0.5, zero_to_one ? ndc.z : ndc.z * 0.5 + 0.5);
    return vec4(win, clip.w);
}

// Lit fraction of world_pos: one compare of the biased receiver depth (2x2 with GL_LINEAR).
float sk_shadow_map_visibility(sampler2DShadow shadow_map, mat4 light_view_proj, vec3 world_pos,
                               bool zero_to_one, float bias, float outside) {
    vec4 c = sk_shadow_coord(light_view_proj, world_pos, zero_to_one);
    if (c.w <= 0.0 || any(lessThan(c.xy, vec2(0.0))) || any(greaterThan(c.xy, vec2(1.0))) || c.z > 1.0 || c.z < 0.0)
        return outside;
#ifdef SK_REVERSED_Z
    return texture(shadow_map, vec3(c.xy, c.z + bias));
#else
    return texture(shadow_map, vec3(c.xy, c.z - bias));
#endif
}

// Cube shadow map of a point light rendered with six 90-degree perspective faces sharing
// near/far (GL clip depth, not reversed): the reference depth is the face's window depth of the
// major-axis distance, ndc_z = (f + n)/(f - n) - 2 f n / ((f - n) d) (glFrustum's P[2][2], P[2][3]),
// minus `bias` (window units).
float sk_cube_shadow_visibility(samplerCubeShadow shadow_map, vec4 light_position, vec3 world_pos,
                                float near_plane, float far_plane, float bias) {
    if (!(light_position.w > 0.0)) return 1.0;
    vec3 d = world_pos - light_position.xyz / light_position.w;
    float major = max(abs(d.x), max(abs(d.y), abs(d.z)));
    float f = far_plane;
    float n = near_plane;
    float ndc_z = (f + n) / (f - n) - 2.0 * f * n / ((f - n) * major);
    return texture(shadow_map, vec4(d, ndc_z * 0.5 + 0.5 - bias));
}
