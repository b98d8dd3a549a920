// Driver for glsl/omni_shadow.glsl, vertex stage: the dual-paraboloid depth pass's vertex shader,
// plus calls of the remaining functions so that every one compiles in this stage.
layout(location = 0) in vec3 a_position;
uniform mat4 u_dp_view;
uniform float u_side;
uniform float u_range;
uniform vec4 u_light_position;
uniform samplerCubeShadow u_cube;
uniform samplerCube u_cube_distance;
uniform sampler2DArrayShadow u_dp;
out vec3 v_world;
out float v_checks;
void main() {
    gl_Position = sk_dp_clip_position(u_dp_view, a_position, u_side, u_range, false);
    gl_ClipDistance[0] = sk_dp_clip_distance(u_dp_view, a_position, u_side, 0.1);
    v_world = a_position;
    vec3 ts, tt;
    float major;
    sk_omni_cube_tangents(a_position, ts, tt, major);
    vec3 m = sk_dp_project(normalize(a_position + vec3(1e-3)));
    vec3 d = sk_dp_direction(m.xy, m.z);
    vec4 c = sk_dp_coord(u_dp_view, a_position);
    float b = sk_omni_bias(2.0, 0.5, sk_omni_cube_texel_angle(512.0), 1.4143, 1.4835, vec2(0.0, 2.4e-7));
    float b2 = sk_dp_texel_angle(724.0, c.w);
    v_checks = sk_omni_linear_depth(a_position, u_light_position, u_range) + b + b2 + major + ts.x + tt.y + d.z + c.x
             + sk_cube_visibility_distance(u_cube, u_light_position, a_position, u_range, b)
             + sk_cube_visibility_distance_manual(u_cube_distance, u_light_position, a_position, u_range, b)
             + sk_cube_visibility_distance_pcf(u_cube, u_light_position, a_position, u_range, b, 512.0, 1)
             + sk_dp_shadow(u_dp, u_dp_view, a_position, u_range, b)
             + sk_dp_shadow_pcf(u_dp, u_dp_view, a_position, u_range, b, 724.0, 1);
}
