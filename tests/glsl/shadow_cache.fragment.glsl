flat in vec3 g_plane;
flat in vec2 g_origin;
uniform ivec2 u_anchor;
void main() {
    vec2 q = sk_shadow_cache_quantize(gl_FragCoord.xy);
    gl_FragDepth = sk_shadow_cache_depth(g_plane, g_origin, gl_FragCoord.xy, u_anchor) +
                   sk_shadow_cache_depth_offset(g_plane, 1.5, 0.0) + 0.0 * q.x;
}
