uniform sampler2D u_depth_a;
uniform sampler2D u_vis_a;
uniform sampler2D u_depth_b;
uniform sampler2D u_vis_b;
uniform mat4 u_vp_a;
uniform mat4 u_vp_b;
uniform vec3 u_end_a;
uniform vec3 u_end_b;
noperspective in float v_value;
in vec3 v_p;
in vec3 v_n;
layout(location = 0) out vec4 o_color;
void main() {
    float V = sk_linear_light_visibility(u_depth_a, u_vis_a, u_vp_a, u_end_a, u_depth_b, u_vis_b, u_vp_b, u_end_b,
                                         v_p, v_n, 0.0);
    float e = sk_linear_light_endpoint(u_depth_a, u_vis_a, u_vp_a, vec4(u_end_a, 1.0), v_p, v_n, 0.0);
    o_color = sk_linear_light_skin_output(v_value, gl_FragCoord.z) + vec4(V, e + sk_linear_light_depth(0.5, 0.1, 10.0), 0.0, 0.0);
}
