// Driver for glsl/pcf.glsl: declarations and a main() calling every function.
uniform sampler2DShadow u_shadow_map;  // depth texture, compare mode on, GL_LINEAR
uniform sampler2DArrayShadow u_shadow_maps;  // a depth array (cascades), compare mode on
uniform float u_layer;
uniform float u_radius_uv;             // Poisson radius in uv
uniform int u_taps;                    // Poisson taps, 1..64
uniform int u_radius_texels;           // box / tent radius
in vec4 v_shadow_coord;                // light clip-space position of the fragment
out vec4 o_color;
void main() {
    vec3 uvz = v_shadow_coord.xyz / v_shadow_coord.w * 0.5 + 0.5;
    vec2 g = sk_receiver_plane_depth_bias(uvz);
    float noise = sk_interleaved_gradient_noise(gl_FragCoord.xy);
    float a = sk_pcf_hard(u_shadow_map, uvz);
    float b = sk_pcf_box(u_shadow_map, uvz, g, u_radius_texels);
    float c = sk_pcf_tent(u_shadow_map, uvz, vec2(0.0), u_radius_texels);
    float d = sk_pcf_poisson(u_shadow_map, uvz, g, u_radius_uv, u_taps, 6.28318531 * noise);
    float e = sk_pcf_poisson_rotated(u_shadow_map, uvz, g, u_radius_uv, u_taps);
    float f = sk_pcf_tap(u_shadow_map, uvz, g, vec2(0.0));
    // the array overloads (one layer)
    float aa = sk_pcf_hard(u_shadow_maps, u_layer, uvz);
    float ab = sk_pcf_box(u_shadow_maps, u_layer, uvz, g, u_radius_texels);
    float ac = sk_pcf_tent(u_shadow_maps, u_layer, uvz, vec2(0.0), u_radius_texels);
    float ad = sk_pcf_poisson(u_shadow_maps, u_layer, uvz, g, u_radius_uv, u_taps, 6.28318531 * noise);
    float ae = sk_pcf_poisson_rotated(u_shadow_maps, u_layer, uvz, g, u_radius_uv, u_taps);
    float af = sk_pcf_tap(u_shadow_maps, u_layer, uvz, g, vec2(0.0));
    o_color = vec4(a, b, c, d) * e * f + vec4(SK_POISSON_TAPS[SK_POISSON_TAP_COUNT - 1], 0.0, 0.0)
            + vec4(aa, ab, ac, ad) * ae * af;
}
