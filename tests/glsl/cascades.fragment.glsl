// Driver for glsl/cascades.glsl (fragment stage): declarations and a main() calling every function.
uniform sampler2DArrayShadow uShadowMaps;
uniform mat4 uLightVP[4];
uniform vec4 uSpheres[4];
uniform vec4 uSplitNear;
uniform vec4 uSplitFar;
uniform int uCount;
in vec3 vWorldPos;
in float vViewDepth;
out vec4 fragColor;

void main()
{
    int a = sk_cascade_by_depth(vViewDepth, uSplitFar, uCount);
    int b = sk_cascade_by_sphere(vWorldPos, uSpheres, uCount);
    float w = sk_cascade_blend(vViewDepth, uSplitNear.x, uSplitFar.x, 0.1);
    vec3 c = sk_cascade_coord(uLightVP[0], vWorldPos, false);
    float s0 = sk_cascade_sample(uShadowMaps, uLightVP[0], 0, vWorldPos, 0.0005, true);
    float s = sk_cascade_shadow(uShadowMaps, uLightVP, uSplitNear, uSplitFar, uCount, vWorldPos, vViewDepth, 0.1, 0.0005, false);
    fragColor = vec4(s * s0, w + c.x, float(a + b), 1.0);
}
