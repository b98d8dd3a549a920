// Driver for glsl/shadow_volume.glsl, vertex stage.
layout(location = 0) in vec4 a_position; // (p, 1) or (p, 0) from shadowkit::volume_build_vertices
uniform mat4 u_mvp;
uniform vec4 u_light_position; // object space
uniform sampler2D u_scene_depth;
uniform vec2 u_depth_bounds;
out float v_flag;

void main()
{
    gl_Position = u_mvp * sk_extrude_shadow_volume(a_position, u_light_position);
    bool o1 = sk_outside_depth_bounds(0.5, u_depth_bounds);
    bool o2 = sk_outside_depth_bounds_at(u_scene_depth, ivec2(0), u_depth_bounds);
    v_flag = (o1 || o2) ? 1.0 : 0.0;
}
