uniform sampler2D u_other_depth;
uniform mat4 u_other_inv_vp;
uniform mat4 u_this_vp;
uniform vec2 u_near_far;
noperspective out float v_value;
void main() {
    gl_Position = sk_linear_light_skin_vertex(u_other_depth, u_other_inv_vp, u_near_far.x, u_near_far.y, u_this_vp,
                                              0.05, gl_VertexID, v_value);
    v_value += sk_linear_light_depth(0.5, u_near_far.x, u_near_far.y) * 0.0;
}
