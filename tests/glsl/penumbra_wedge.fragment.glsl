uniform sampler2D u_depth;
uniform mat4 u_inv_view_proj;
uniform vec4 u_outer_bound;
uniform vec4 u_inner_bound;
uniform vec4 u_side0;
uniform vec4 u_side1;
uniform vec3 u_e0;
uniform vec3 u_e1;
uniform vec4 u_light_position;
uniform float u_light_radius;
uniform vec2 u_viewport_size;
flat in vec4 v_plane0;
flat in vec4 v_plane1;
flat in vec4 v_plane2;
out vec4 o_coverage;
void main() {
    float depth = texelFetch(u_depth, ivec2(gl_FragCoord.xy), 0).r;
    vec4 vp = vec4(gl_FragCoord.xy, depth, 1.0);
    if (!sk_wedge_inside3(vp, v_plane0, v_plane1, v_plane2)) discard;
    vec2 ndc = gl_FragCoord.xy / u_viewport_size * 2.0 - 1.0;
    vec3 p = sk_wedge_world_from_depth(u_inv_view_proj, ndc, depth, false);
    if (!sk_wedge_inside4(vec4(p, 1.0), u_outer_bound, u_inner_bound, u_side0, u_side1)) discard;
    float c = sk_wedge_edge_coverage(u_e0, u_e1, u_light_position, u_light_radius, p);
    vec4 unused = sk_wedge_transform_plane(mat4(1.0), u_side0);
    o_coverage = vec4(c, sk_wedge_visibility(0.0, c), unused.x * 0.0, 1.0);
}
