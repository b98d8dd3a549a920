// Driver for glsl/perspective_shadow_maps.glsl (fragment stage): calls every function.
uniform sampler2DShadow u_shadow_map;
uniform mat4 u_warp;
uniform mat4 u_depth_proj;
uniform mat4 u_warp_inverse;
in vec3 v_normal;
in vec3 v_world_pos;
in vec4 v_depth_clip;
out vec4 frag_color;

void main()
{
    vec4 c = sk_warp_coord(u_warp, u_depth_proj, v_world_pos, true);
    float lit = sk_warp_shadow(u_shadow_map, u_warp, u_depth_proj, v_world_pos, 0.0005, false);
    gl_FragDepth = sk_warp_map_depth(v_depth_clip, 2.0, 0.0, false);
    float lit_auto = sk_warp_shadow_auto(u_shadow_map, u_warp, u_warp_inverse, u_depth_proj, v_world_pos, v_normal, false, 0.0, 1.0);
    frag_color = vec4(lit + lit_auto, c.xyz);
}
