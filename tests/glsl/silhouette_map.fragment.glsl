uniform sampler2D u_depth;
uniform sampler2D u_silmap;
uniform vec4 u_ab;
uniform vec2 u_z;
uniform vec3 u_lookup;
layout(location = 0) out vec4 o_color;
void main() {
    vec2 local;
    float w;
    vec2 hit;
    bool any_hit = sk_silmap_seg_hit(u_ab.xy, u_ab.zw, vec2(0.0), vec2(1.0), hit);
    if (!sk_silmap_point(gl_FragCoord.xy, u_ab.xy, u_ab.zw, local, w)) discard;
    if (sk_silmap_occluded(u_depth, ivec2(gl_FragCoord.xy), u_ab.xy, u_ab.zw, u_z.x, u_z.y, local, 1e-4)) discard;
    float v = sk_silmap_visibility(u_depth, u_silmap, u_lookup.xy, u_lookup.z, 0.0) + sk_silmap_wrap(w);
    o_color = vec4(local, w / 255.0, v + (any_hit ? hit.x : 0.0));
}
