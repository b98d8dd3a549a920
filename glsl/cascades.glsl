// shadowkit/glsl/cascades.glsl - cascaded shadow maps: cascade selection, blend band, lookup.
// versions: 330, 450
// stages: fragment
//
// Inputs (from shadowkit/cascades.hpp, up to 4 cascades):
//   splitFar      vec4   far view depth of cascades 0..3 (splits[1..4] of fit_cascades)
//   splitNear     vec4   near view depth of cascades 0..3 (splits[0..3])
//   spheres[4]    vec4   world bounding spheres (Cascade::sphere) for selection by sphere
//   lightVP[4]    mat4   Cascade::view_proj
//   shadowMaps    sampler2DArrayShadow, layer i = cascade i (compare mode on)
//   viewDepth     float  positive distance along the camera's view direction (-view-space z)
//   zeroToOne     bool   true if the matrices were built with ClipDepth::ZeroToOne
// Usage: float lit = sk_cascade_shadow(shadowMaps, lightVP, splitNear, splitFar, count, worldPos,
//        viewDepth, 0.1, 0.0005, false);  // blend over the last 10% of each cascade
// Reversed-Z light matrices need a GREATER compare func on the sampler and a negative bias.

int sk_cascade_by_depth(float viewDepth, vec4 splitFar, int count)
{
    for (int i = 0; i < 4; ++i) {
        if (i < count && viewDepth <= splitFar[i]) return i;
    }
    return -1;
}

int sk_cascade_by_sphere(vec3 worldPos, vec4 spheres[4], int count)
{
    for (int i = 0; i < 4; ++i) {
        vec3 d = worldPos - spheres[i].xyz;
        if (i < count && dot(d, d) <= spheres[i].w * spheres[i].w) return i;
    }
    return -1;
}

// Weight of the next cascade: 0 until the last `band` fraction of [splitNear, splitFar], 1 at splitFar.
float sk_cascade_blend(float viewDepth, float splitNear, float splitFar, float band)
{
    float start = splitFar - clamp(band, 0.0, 1.0) * (splitFar - splitNear);
    return clamp((viewDepth - start) / max(splitFar - start, 1e-20), 0.0, 1.0);
}

// World position -> (u, v, depth) in [0,1] for one cascade (orthographic: w == 1, divide kept).
vec3 sk_cascade_coord(mat4 lightViewProj, vec3 worldPos, bool zeroToOne)
{
    vec4 h = lightViewProj * vec4(worldPos, 1.0);
    vec3 ndc = h.xyz / h.w;
    return vec3(ndc.xy * 0.5 + 0.5, zeroToOne ? ndc.z : ndc.z * 0.5 + 0.5);
}

float sk_cascade_sample(sampler2DArrayShadow maps, mat4 lightViewProj, int layer, vec3 worldPos, float bias, bool zeroToOne)
{
    vec3 c = sk_cascade_coord(lightViewProj, worldPos, zeroToOne);
    if (any(lessThan(c.xy, vec2(0.0))) || any(greaterThan(c.xy, vec2(1.0)))) return 1.0;
    return texture(maps, vec4(c.xy, float(layer), c.z - bias));
}

// 1 = lit, 0 = shadowed; blends with the next cascade inside the band.
float sk_cascade_shadow(sampler2DArrayShadow maps, mat4 lightVP[4], vec4 splitNear, vec4 splitFar, int count,
                        vec3 worldPos, float viewDepth, float band, float bias, bool zeroToOne)
{
    int i = sk_cascade_by_depth(viewDepth, splitFar, count);
    if (i < 0) return 1.0;
    float s = sk_cascade_sample(maps, lightVP[i], i, worldPos, bias, zeroToOne);
    float w = sk_cascade_blend(viewDepth, splitNear[i], splitFar[i], band);
    if (w > 0.0 && i + 1 < count) {
        float s2 = sk_cascade_sample(maps, lightVP[i + 1], i + 1, worldPos, bias, zeroToOne);
        s = mix(s, s2, w);
    }
    return s;
}
