layout(location = 0) in vec4 a_ab;
uniform vec2 u_size;
void main() {
    gl_Position = sk_silmap_edge_vertex(a_ab.xy, a_ab.zw, gl_VertexID, u_size);
}
