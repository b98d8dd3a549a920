// shadowkit/glsl/shadow_map.glsl - plain shadow-map lookups (Williams 1978), hard or with the
// hardware's 2x2 percentage-closer filter (bilinear compare: set GL_LINEAR on the depth texture).
// versions: 330, 450
// stages: fragment
//
// Inputs: world-space position of the shaded point; the light's view-projection matrix (the one
// the shadow map was rendered with).
// Uniforms (user-declared, passed in): sampler2DShadow with GL_TEXTURE_COMPARE_MODE =
// GL_COMPARE_REF_TO_TEXTURE and GL_LEQUAL; samplerCubeShadow for point lights.
// zero_to_one: pass true when the projection was built for glClipControl(..., GL_ZERO_TO_ONE).
// Returns 1 = lit, 0 = shadowed; points outside the light frustum get `outside`.
//
// Usage:
//   float v = sk_shadow_map_visibility(u_shadow_map, u_light_view_proj, world_pos, false, 1.0);

// Shadow-map coordinates (uv in [0,1], depth in window space) of a world point.
vec4 sk_shadow_coord(mat4 light_view_proj, vec3 world_pos, bool zero_to_one) {
    vec4 clip = light_view_proj * vec4(world_pos, 1.0);
    vec3 ndc = clip.xyz / clip.w;
    vec3 win = vec3(ndc.xy * 0.5 + 0.5, zero_to_one ? ndc.z : ndc.z * 0.5 + 0.5);
    return vec4(win, clip.w);
}

float sk_shadow_map_visibility(sampler2DShadow shadow_map, mat4 light_view_proj, vec3 world_pos,
                               bool zero_to_one, float outside) {
    vec4 c = sk_shadow_coord(light_view_proj, world_pos, zero_to_one);
    if (c.w <= 0.0 || any(lessThan(c.xy, vec2(0.0))) || any(greaterThan(c.xy, vec2(1.0))) || c.z > 1.0)
        return outside;
    return texture(shadow_map, c.xyz);
}

// Cube shadow map of a point light rendered with six 90-degree perspective faces sharing
// near/far (GL clip depth): the reference depth is the face's window depth of the major-axis
// distance, ndc_z = (f + n)/(f - n) - 2 f n / ((f - n) d) (glFrustum's P[2][2], P[2][3]).
float sk_cube_shadow_visibility(samplerCubeShadow shadow_map, vec3 light_pos, vec3 world_pos,
                                float near_plane, float far_plane) {
    vec3 d = world_pos - light_pos;
    float major = max(abs(d.x), max(abs(d.y), abs(d.z)));
    float f = far_plane, n = near_plane;
    float ndc_z = (f + n) / (f - n) - 2.0 * f * n / ((f - n) * major);
    return texture(shadow_map, vec4(d, ndc_z * 0.5 + 0.5));
}
