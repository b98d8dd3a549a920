// Driver for glsl/omni_shadow.glsl, fragment stage: a depth pass writing the linear distance and a
// lighting pass with every lookup (cube hardware / manual / PCF, paraboloid hardware / PCF).
uniform vec4 u_light_position;
uniform float u_range;
uniform float u_size;
uniform mat4 u_dp_view;
uniform vec2 u_storage;
uniform samplerCubeShadow u_cube;
uniform samplerCube u_cube_distance;
uniform sampler2DArrayShadow u_dp;
in vec3 v_world;
in vec3 v_normal;
out vec4 o_color;
void main() {
    gl_FragDepth = sk_omni_linear_depth(v_world, u_light_position, u_range);
    vec3 L = sk_omni_light_point(u_light_position) - v_world;
    float d = length(L);
    float cos_t = dot(normalize(v_normal), L / d);
    float b = sk_omni_bias(d, cos_t, sk_omni_cube_texel_angle(u_size), 1.4143, 1.4835, u_storage);
    vec4 c = sk_dp_coord(u_dp_view, v_world);
    float bd = sk_omni_bias(d, cos_t, sk_dp_texel_angle(u_size, c.w), 2.8286, 1.4835, u_storage);
    float a0 = sk_cube_visibility_distance(u_cube, u_light_position, v_world, u_range, b);
    float a1 = sk_cube_visibility_distance_manual(u_cube_distance, u_light_position, v_world, u_range, b);
    float a2 = sk_cube_visibility_distance_pcf(u_cube, u_light_position, v_world, u_range, b, u_size, 1);
    float a3 = sk_dp_shadow(u_dp, u_dp_view, v_world, u_range, bd);
    float a4 = sk_dp_shadow_pcf(u_dp, u_dp_view, v_world, u_range, bd, u_size, 1);
    vec3 ts, tt;
    float major;
    sk_omni_cube_tangents(L, ts, tt, major);
    vec3 m = sk_dp_project(normalize(-L));
    vec3 dir = sk_dp_direction(m.xy, m.z);
    vec4 clip = sk_dp_clip_position(u_dp_view, v_world, 1.0, u_range, true);
    float cd = sk_dp_clip_distance(u_dp_view, v_world, -1.0, 0.1);
    o_color = vec4(a0 + a1, a2 + a3, a4 + major + ts.x + tt.y, dir.z + clip.x + cd);
}
