// Driver for glsl/shadow_map.glsl: declarations and a main() calling every function.
uniform sampler2DShadow u_sm;
uniform samplerCubeShadow u_cube;
uniform mat4 u_light_vp;
uniform vec4 u_light_position;   // w = 1: a point light
uniform float u_bias;            // window-depth units
in vec3 v_world;
out vec4 o_color;
void main() {
    vec4 c = sk_shadow_coord(u_light_vp, v_world, false);
    float a = sk_shadow_map_visibility(u_sm, u_light_vp, v_world, true, u_bias, 1.0);
    float b = sk_cube_shadow_visibility(u_cube, u_light_position, v_world, 0.05, 20.0, u_bias);
    o_color = vec4(a, b, c.z, 1.0);
}
