layout(location = 0) in vec3 a_position;
uniform mat4 u_mvp;
uniform vec3 u_env[25];
uniform int u_count;
out vec3 v_radiance;
void main() {
    float t[25];
    for (int i = 0; i < 25; ++i) t[i] = sk_prt_transfer[gl_VertexID * 25 + i];
    v_radiance = sk_prt_shade_vertex(gl_VertexID, 25, u_count, u_env) + 0.0 * sk_prt_dot(t, u_env, u_count);
    gl_Position = u_mvp * vec4(a_position, 1.0);
}
