uniform sampler2D u_atlas;
uniform float u_pixel_world;
in vec3 v_rel;
in vec3 v_normal;
out vec4 o_color;
void main() {
    int level = sk_vsm_level_for_footprint(u_pixel_world, 0.0);
    int marked = sk_vsm_mark(v_rel, level, 1);
    int used;
    float a = sk_vsm_visibility_level(u_atlas, v_rel, v_normal, level, 1, 0.0, used);
    float b = sk_vsm_visibility(u_atlas, v_rel, v_normal, level, 0, 0.0);
    vec4 c = sk_vsm_coord(level, v_rel);
    uint e = sk_vsm_entry(level, ivec2(c.xy * float(sk_vsm_layout.y)));
    vec4 g = sk_vsm_plane_gradient(sk_vsm_world_to_uv[level], v_rel, v_normal);
    float eps = sk_vsm_bias_epsilon(g, 1.0 / 1024.0, c.z, 0.0);
    ivec2 p = sk_vsm_physical(level, ivec2(0));
    ivec2 i0;
    vec2 w;
    bool k = sk_vsm_kernel(c.xy, 1024, 0, i0, w);
    float f;
    bool ok = sk_vsm_filter_level(u_atlas, level, c, g, 0, 0.0, f);
    o_color = vec4(sk_vsm_debug_color(v_rel, level) * a * b, float(marked + used + int(e) + p.x + i0.x) + eps + f + (k && ok ? w.x : 0.0));
}
