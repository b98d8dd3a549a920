uniform sampler2DShadow u_sm;
uniform samplerCubeShadow u_cube;
uniform mat4 u_light_vp;
in vec3 v_world;
out vec4 o_color;
void main() {
    vec4 c = sk_shadow_coord(u_light_vp, v_world, false);
    float a = sk_shadow_map_visibility(u_sm, u_light_vp, v_world, true, 1.0);
    float b = sk_cube_shadow_visibility(u_cube, vec3(0.0, 2.0, 0.0), v_world, 0.05, 20.0);
    o_color = vec4(a, b, c.z, 1.0);
}
