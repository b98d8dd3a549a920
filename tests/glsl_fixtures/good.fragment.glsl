out vec4 o_color;
void main() { o_color = vec4(sk_fixture_square(0.5)); }
