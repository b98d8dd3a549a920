// Driver for glsl/shadow_map.glsl: declarations and a main() calling every function.
uniform sampler2DShadow u_sm;
uniform sampler2DArrayShadow u_sm_array;
uniform samplerCubeShadow u_cube;
uniform mat4 u_light_vp;
uniform vec4 u_light_position;   // w = 1: a point light
uniform float u_bias;            // window-depth units
uniform float u_depth_step;      // the map format's window-depth step (0: float32)
in vec3 v_world;
in vec3 v_normal;
out vec4 o_color;
void main() {
    vec4 c = sk_shadow_coord(u_light_vp, v_world, false);
    float a = sk_shadow_map_visibility(u_sm, u_light_vp, v_world, true, u_bias, 1.0);
    float b = sk_cube_visibility_hardware_depth(u_cube, u_light_position, v_world, 0.05, 20.0, u_bias);
    float d = sk_shadow_map_visibility_auto(u_sm, u_light_vp, v_world, v_normal, false, u_depth_step, 1.0);
    float e = sk_shadow_map_visibility_auto(u_sm_array, 2.0, u_light_vp, v_world, v_normal, true, u_depth_step, 1.0);
    vec4 g = sk_plane_depth_gradient(u_light_vp, v_world, v_normal, false);
    float f = sk_auto_filtered_bias(g, vec2(1.0 / 2048.0), c.z, u_depth_step);
    float h = sk_cube_visibility_hardware_depth_auto(u_cube, u_light_position, v_world, v_normal, 0.05, 20.0, u_depth_step);
    o_color = vec4(a + d, b + e + h, c.z + f, 1.0);
}
