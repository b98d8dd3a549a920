// Driver for glsl/shadow_volume.glsl, fragment stage (shadow volume pass with emulated depth bounds).
uniform sampler2D u_scene_depth; // copy of the scene depth buffer
uniform vec2 u_depth_bounds;     // (depth_min, depth_max) from shadowkit::volume_scissor
uniform vec4 u_light_position;
layout(location = 0) out vec4 o_color;

void main()
{
    float stored = texelFetch(u_scene_depth, ivec2(gl_FragCoord.xy), 0).r;
    if (sk_outside_depth_bounds(stored, u_depth_bounds)) discard;
    if (sk_outside_depth_bounds_at(u_scene_depth, ivec2(gl_FragCoord.xy), u_depth_bounds)) discard;
    o_color = sk_extrude_shadow_volume(vec4(0.0), u_light_position); // colour writes are masked anyway
}
