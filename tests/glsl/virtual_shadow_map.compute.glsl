layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 3) uniform sampler2D u_positions;
uniform float u_pixel_angle;
void main() {
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    vec4 p = texelFetch(u_positions, px, 0);
    if (p.w == 0.0) return;
    sk_vsm_mark(p.xyz, sk_vsm_level_for_footprint(length(p.xyz) * u_pixel_angle, 0.0), 0);
}
