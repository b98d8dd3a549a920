// Driver for glsl/smoothie.glsl, fragment stage: pass 1 (linear depth), pass 2 (smoothie buffer,
// RG32F with glBlendEquation(GL_MIN)) and pass 3 (final lookup) selected by u_pass, so that every
// function of the snippet is called.
noperspective in float v_alpha;
smooth in float v_depth;
flat in vec2 v_silhouette_ndc;
flat in float v_inv_t;
flat in float v_corner;
in vec3 v_world;
uniform int u_pass;
uniform mat4 u_light_view_proj;
uniform mat4 u_light_view;
uniform vec2 u_buffer_size;
uniform float u_bias;
uniform sampler2D u_linear_shadow_map;
uniform sampler2D u_smoothie_map;
out vec4 o_color;
void main() {
    if (u_pass == 1) {
        o_color = vec4(sk_smoothie_linear_depth(u_light_view, v_world), 0.0, 0.0, 1.0);
    } else if (u_pass == 2) {
        if (sk_smoothie_hidden(u_linear_shadow_map, gl_FragCoord.xy, v_depth, u_bias)) discard;
        vec2 o = sk_smoothie_fragment(gl_FragCoord.xy, u_buffer_size, v_alpha, v_silhouette_ndc, v_inv_t, v_corner, v_depth);
        o_color = vec4(o, 0.0, 1.0);
    } else if (u_pass == 4) {  // paper variant: remap in the smoothie pass
        vec2 ndc = sk_smoothie_frag_ndc(gl_FragCoord.xy, u_buffer_size);
        float a = sk_smoothie_alpha(ndc, v_alpha, v_silhouette_ndc, v_inv_t, v_corner);
        float z = sk_smoothie_shadow_depth_at(u_linear_shadow_map, gl_FragCoord.xy);
        o_color = vec4(v_depth, sk_smoothie_remap(a, v_depth, z), 0.0, 1.0);
    } else {
        vec4 c = u_light_view_proj * vec4(v_world, 1.0);
        vec2 uv = c.xy / c.w * 0.5 + 0.5;
        float r = sk_smoothie_linear_depth(u_light_view, v_world);
        vec2 g = sk_smoothie_depth_gradient(dFdx(uv), dFdy(uv), dFdx(r), dFdy(r));
        float v = sk_smoothie_visibility(u_linear_shadow_map, u_smoothie_map, uv, r, g, u_bias, false);
        float t = sk_smoothie_tap(r, 1.0, vec2(0.5, 0.5), u_bias, true);
        o_color = vec4(v, t, sk_smoothie_falloff(v), 1.0);
    }
}
