layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;
in vec3 v_global[];
uniform ivec2 u_viewport_anchor;
uniform vec2 u_viewport_size;
flat out vec3 g_plane;
flat out vec2 g_origin;
void main() {
    vec3 plane;
    vec2 origin;
    if (!sk_shadow_cache_plane(v_global[0], v_global[1], v_global[2], plane, origin)) return;
    for (int i = 0; i < 3; ++i) {
        g_plane = plane;
        g_origin = origin;
        gl_Position = sk_shadow_cache_position(v_global[i].xy, u_viewport_anchor, u_viewport_size);
        EmitVertex();
    }
    EndPrimitive();
}
