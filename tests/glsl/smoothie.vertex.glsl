// Driver for glsl/smoothie.glsl, vertex stage: pass 2's vertex shader (SmoothieVertex layout),
// plus calls of the remaining functions so that every one compiles in this stage. Links with
// tests/glsl/smoothie.fragment.glsl into the pass-2 program.
layout(location = 0) in vec3 a_position;
layout(location = 1) in float a_alpha;
layout(location = 2) in vec3 a_silhouette;
layout(location = 3) in float a_inv_t;
layout(location = 4) in vec2 a_outward;
layout(location = 5) in float a_corner;
uniform mat4 u_light_view_proj;
uniform mat4 u_light_view;
uniform vec2 u_buffer_size;
uniform sampler2D u_linear_shadow_map;
uniform sampler2D u_smoothie_map;
noperspective out float v_alpha;
smooth out float v_depth;
flat out vec2 v_silhouette_ndc;
flat out float v_inv_t;
flat out float v_corner;
out vec3 v_world;
out float v_checks;
void main() {
    vec4 clip;
    sk_smoothie_vertex(u_light_view_proj, u_light_view, a_position, a_silhouette, clip, v_depth, v_silhouette_ndc);
    gl_Position = clip;
    v_world = a_position;
    v_alpha = a_alpha;
    v_inv_t = a_inv_t;
    v_corner = a_corner + 0.0 * a_outward.x;
    vec2 ndc = sk_smoothie_frag_ndc(vec2(1.0), u_buffer_size);
    float a = sk_smoothie_alpha(ndc, a_alpha, v_silhouette_ndc, a_inv_t, a_corner);
    vec2 o = sk_smoothie_fragment(vec2(1.0), u_buffer_size, a_alpha, v_silhouette_ndc, a_inv_t, a_corner, v_depth);
    bool h = sk_smoothie_hidden(u_linear_shadow_map, vec2(1.0), v_depth, 0.01);
    float z = sk_smoothie_shadow_depth_at(u_linear_shadow_map, vec2(1.0));
    vec2 g = sk_smoothie_depth_gradient(vec2(1.0, 0.0), vec2(0.0, 1.0), 0.5, 0.25);
    float t = sk_smoothie_tap(2.0, z, o, 0.01, false);
    float vis = sk_smoothie_visibility(u_linear_shadow_map, u_smoothie_map, vec2(0.5), 3.0, g, 0.01, false);
    float d = sk_smoothie_linear_depth(u_light_view, a_position);
    v_checks = a + sk_smoothie_remap(a, 1.0, 2.0) + sk_smoothie_falloff(a) + (h ? 1.0 : 0.0) + t + vis + d;
}
