uniform mat4 u_view_proj;
uniform mat4 u_world_to_viewport_inv_t;
uniform vec4 u_bound;
uniform vec4 u_side0;
uniform vec4 u_side1;
uniform vec3 u_e0;
uniform vec3 u_e1;
uniform vec4 u_light_position;
uniform float u_light_radius;
in vec4 a_position; // wedge hull vertex, w = 0 for an infinite extent
flat out vec4 v_plane0;
flat out vec4 v_plane1;
flat out vec4 v_plane2;
out float v_debug;
void main() {
    v_plane0 = sk_wedge_transform_plane(u_world_to_viewport_inv_t, u_bound);
    v_plane1 = sk_wedge_transform_plane(u_world_to_viewport_inv_t, u_side0);
    v_plane2 = sk_wedge_transform_plane(u_world_to_viewport_inv_t, u_side1);
    vec3 p = sk_wedge_world_from_depth(mat4(1.0), vec2(0.0), 0.5, true);
    bool inside = sk_wedge_inside4(vec4(p, 1.0), u_bound, u_bound, u_side0, u_side1) &&
                  sk_wedge_inside3(vec4(p, 1.0), u_bound, u_side0, u_side1);
    float c = sk_wedge_edge_coverage(u_e0, u_e1, u_light_position, u_light_radius, p);
    v_debug = inside ? sk_wedge_visibility(0.0, c) : 0.0;
    gl_Position = u_view_proj * a_position;
}
