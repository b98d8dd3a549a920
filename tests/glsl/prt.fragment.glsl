in vec3 v_radiance;
flat in int v_index;
uniform vec3 u_env[25];
uniform int u_count;
layout(location = 0) out vec4 o_color;
void main() {
    float t[25];
    for (int i = 0; i < 25; ++i) t[i] = float(i == 0);
    vec3 c = v_radiance + sk_prt_shade_vertex(v_index, 25, u_count, u_env) * 0.0 + sk_prt_dot(t, u_env, u_count) * 0.0;
    o_color = vec4(c, 1.0);
}
