// Driver for glsl/cascades.glsl (fragment stage): declarations and a main() calling every function.
uniform sampler2DArrayShadow u_shadow_maps;
uniform mat4 u_light_vp[4];
uniform vec4 u_spheres[4];
uniform vec4 u_split_near;
uniform vec4 u_split_far;
uniform int u_count;
uniform sampler2D u_depth;
uniform sampler2D u_level;
in vec3 v_world_pos;
in float v_view_depth;
out vec4 frag_color;

void main()
{
    int a = sk_cascade_by_depth(v_view_depth, u_split_far, u_count);
    int b = sk_cascade_by_sphere(v_world_pos, u_spheres, u_count);
    float w = sk_cascade_blend(v_view_depth, u_split_near.x, u_split_far.x, 0.1);
    vec3 c = sk_cascade_coord(u_light_vp[0], v_world_pos, false);
    float s0 = sk_cascade_sample(u_shadow_maps, u_light_vp[0], 0, v_world_pos, 0.0005, true);
    float s = sk_cascade_shadow(u_shadow_maps, u_light_vp, u_split_near, u_split_far, u_count, v_world_pos, v_view_depth, 0.1, 0.0005, false);
    int second;
    float weight;
    int first = sk_cascade_pick(v_view_depth, u_split_near, u_split_far, u_count, 0.1, second, weight);
    // sk_cascade_shadow_filtered / sk_cascade_sample_filtered exist only after glsl/pcf.glsl
    // (tests/test_glsl_snippets.cpp compiles pcf.glsl + cascades.glsl with a driver calling them)
    vec2 r0 = sk_sdsm_reduce_depth(u_depth, ivec2(gl_FragCoord.xy), 8, 1.0);
    vec2 r1 = sk_sdsm_reduce_minmax(u_level, ivec2(gl_FragCoord.xy), 8);
    vec4 bounds[4];
    sk_sdsm_reduce_bounds(u_depth, ivec2(gl_FragCoord.xy), 8, 1.0, u_light_vp[0], u_light_vp[1], u_light_vp[2], u_split_far,
                          u_count, false, bounds);
    vec4 b1 = sk_sdsm_reduce_bounds_level(u_level, ivec2(gl_FragCoord.xy), 8);
    frag_color = vec4(s * s0 + r0.x + bounds[0].x, w + c.x + weight + r1.y + b1.z, float(a + b + first + second), 1.0);
}
