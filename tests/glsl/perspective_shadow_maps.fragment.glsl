// Driver for glsl/perspective_shadow_maps.glsl (fragment stage): calls every function.
uniform sampler2DShadow uShadowMap;
uniform mat4 uWarp;
in vec3 vWorldPos;
out vec4 fragColor;

void main()
{
    vec4 c = sk_warp_coord(uWarp, vWorldPos, true);
    float lit = sk_warp_shadow(uShadowMap, uWarp, vWorldPos, 0.0005, false);
    fragColor = vec4(lit, c.xyz);
}
