// Driver for glsl/contact_shadow.glsl: declarations and a main() calling every function.
uniform sampler2D u_depth;          // the camera's depth texture, compare mode off
uniform mat4 u_proj;                // camera projection (view -> clip)
uniform mat4 u_inv_proj;            // inverse(u_proj)
uniform vec4 u_view_light;          // light in view space (w = 0: direction toward the light)
uniform float u_length;             // march length, view units
uniform int u_steps;
uniform float u_depth_step;         // 1.0 / 16777215.0 for GL_DEPTH_COMPONENT24
out vec4 o_color;
void main() {
    ivec2 size = textureSize(u_depth, 0);
    ivec2 px = ivec2(gl_FragCoord.xy);
    float win = texelFetch(u_depth, px, 0).r;
    vec3 view_pos = sk_contact_view_position(u_inv_proj, size, px, win, false);
    float vc = sk_contact_shadow(u_depth, u_proj, view_pos, u_view_light, u_length, u_steps, 0.0, u_depth_step,
                                 false, sk_contact_noise(gl_FragCoord.xy));
    float va = sk_contact_shadow_aligned(u_depth, u_proj, view_pos, u_view_light, u_length, u_steps, 0.0, u_depth_step,
                                         false, sk_contact_noise(gl_FragCoord.xy));
    o_color = vec4(vc, va, vc, 1.0);
}
