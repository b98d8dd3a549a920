// Driver for glsl/pcss.glsl: declarations and a main() calling every function.
uniform sampler2D u_depth_map;         // same depth texture, compare mode off
uniform sampler2DShadow u_shadow_map;  // compare mode on
uniform sampler2DArray u_depth_maps;         // a depth array (cascades), compare mode off
uniform sampler2DArrayShadow u_shadow_maps;  // the same array, compare mode on
uniform float u_layer;
uniform float u_light_uv_at_near;      // pcss_light_uv_at_near(light)
uniform float u_light_uv_per_depth;    // directional variant
uniform float u_near;
uniform float u_far;                   // <= 0.0: infinite
uniform int u_search_taps;
uniform int u_filter_taps;
uniform float u_max_filter_uv;
uniform bool u_rotate;
in vec4 v_shadow_coord;
out vec4 o_color;
void main() {
    vec3 uvz = v_shadow_coord.xyz / v_shadow_coord.w * 0.5 + 0.5;
    vec3 dx = dFdx(uvz), dy = dFdy(uvz);
    float det = dx.x * dy.y - dx.y * dy.x;
    vec2 g = abs(det) > 0.0 ? vec2(dy.y * dx.z - dx.y * dy.z, dx.x * dy.z - dy.x * dx.z) / det : vec2(0.0);
    float angle = u_rotate ? 6.28318531 * sk_interleaved_gradient_noise(gl_FragCoord.xy) : 0.0;
    float a = sk_pcss(u_depth_map, u_shadow_map, uvz, g, u_light_uv_at_near, u_near, u_far,
                      u_search_taps, u_filter_taps, angle, u_max_filter_uv);
    float b = sk_pcss_directional(u_depth_map, u_shadow_map, uvz, g, u_light_uv_per_depth,
                                  u_search_taps, u_filter_taps, angle, u_max_filter_uv);
    float c = sk_pcss_blocker_window_depth(u_depth_map, uvz, 0.01, u_search_taps, angle)
            + sk_pcss_blocker_window_depth(u_depth_map, uvz, g, 0.01, u_search_taps, angle);
    float d = sk_pcss_filter(u_shadow_map, uvz, g, 0.01, u_filter_taps, angle);
    int t = sk_pcss_tap_budget(0.01, float(textureSize(u_shadow_map, 0).x), 4, 64);
    float z = sk_linearize_depth(uvz.z, u_near, u_far);
    bool closer = sk_depth_closer(c, uvz.z);
    // the array overloads (one layer)
    float aa = sk_pcss(u_depth_maps, u_shadow_maps, u_layer, uvz, g, u_light_uv_at_near, u_near, u_far,
                       u_search_taps, u_filter_taps, angle, u_max_filter_uv);
    float ab = sk_pcss_directional(u_depth_maps, u_shadow_maps, u_layer, uvz, g, u_light_uv_per_depth,
                                   u_search_taps, u_filter_taps, angle, u_max_filter_uv);
    float ac = sk_pcss_blocker_window_depth(u_depth_maps, u_layer, uvz, 0.01, u_search_taps, angle)
             + sk_pcss_blocker_window_depth(u_depth_maps, u_layer, uvz, g, 0.01, u_search_taps, angle);
    float ad = sk_pcss_filter(u_shadow_maps, u_layer, uvz, g, 0.01, u_filter_taps, angle);
    o_color = vec4(a, b, c, d) * float(t) * z * (closer ? 1.0 : 0.5) + vec4(aa, ab, ac, ad);
}
