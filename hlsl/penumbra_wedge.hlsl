// shadowkit/hlsl/penumbra_wedge.hlsl - soft shadow volumes (Assarsson & Akenine-Moller 2003, Lengyel GDC 2005) in HLSL: the in-wedge test, the signed light coverage of one silhouette edge for a spherical light, and the combine with the hard count.
// stages: vertex, pixel
//
// The HLSL twin of glsl/penumbra_wedge.glsl: the same sk_ functions, arguments and results (its header
// says the passes and the accumulation; shadowkit/penumbra_wedge.hpp has the CPU twin in double).
// The light: `float4 light_position` (a point light, w > 0, center xyz / w) and `float light_radius`.
// Planes are float4 (n, d), inside when dot(n, x) + d >= 0. Matrices `column_major` with mul(M, v)
// (hlsl/shadow_map.hlsl states the rule): sk_wedge_transform_plane takes transpose(inverse(M)).
// Direct3D and Vulkan: rebuild world points with zero_to_one = true (window depth = NDC depth). The
// accumulation target is R16_FLOAT / R32_FLOAT with additive blending (ONE, ONE).
// Compiled in the tests by glslang's HLSL front end to SPIR-V and run on Vulkan; written for DXC
// (shader model 6.0) as well, but not compiled with it here (DXC is not packaged in Debian 12).
// MIT License. Copyright (c) shadowkit contributors.

// Plane moved by a point transform M: pass transpose(inverse(M)).
float4 sk_wedge_transform_plane(float4x4 inverse_transpose, float4 plane) {
    return mul(inverse_transpose, plane);
}

// Lengyel's half-wedge test: the three bounding planes against a homogeneous point.
bool sk_wedge_inside3(float4 p, float4 plane0, float4 plane1, float4 plane2) {
    return dot(p, plane0) >= 0.0 && dot(p, plane1) >= 0.0 && dot(p, plane2) >= 0.0;
}

// Whole wedge: outer_bound, inner_bound, side[0], side[1].
bool sk_wedge_inside4(float4 p, float4 outer_bound, float4 inner_bound, float4 side0, float4 side1) {
    return sk_wedge_inside3(p, outer_bound, side0, side1) && dot(p, inner_bound) >= 0.0;
}

// World position from a window depth (viewport depth range [0, 1]) and NDC xy.
float3 sk_wedge_world_from_depth(float4x4 inv_view_proj, float2 ndc_xy, float window_depth, bool zero_to_one) {
    float z = zero_to_one ? window_depth : window_depth * 2.0 - 1.0;
    float4 w = mul(inv_view_proj, float4(ndc_xy, z, 1.0));
    return w.xyz / w.w;
}

// Signed fraction of the light disk covered behind the edge as seen from p: > 0 outside the hard
// shadow plane, < 0 inside; |result| <= 0.5 (glsl/penumbra_wedge.glsl numbers the steps).
float sk_wedge_edge_coverage(float3 e0, float3 e1, float4 light_position, float light_radius, float3 p) {
    const float BIG = 1.0e30;
    float r = light_radius;
    if (!(r > 0.0) || !(light_position.w > 0.0)) return 0.0;
    float3 c = light_position.xyz / light_position.w;
    float3 d = c - p;
    float D = length(d);
    if (!(D > 0.0)) return 0.0;
    float3 z = d / D;
    float3 q0 = e0 - p;
    float3 q1 = e1 - p;
    float3 np = cross(q0, q1);
    float w0 = dot(q0, z);
    float w1 = dot(q1, z);
    // 1. only the part in front of the emitter occludes
    if (w0 >= D && w1 >= D) return 0.0;
    if (w0 > D || w1 > D) {
        float t = (D - w0) / (w1 - w0);
        float3 qc = q0 + t * (q1 - q0);
        if (w0 > D) { q0 = qc; w0 = D; } else { q1 = qc; w1 = D; }
    }
    if (w0 <= 0.0 && w1 <= 0.0) return 0.0;
    // 2. projected line: signed distance hs from the disk center in light radii
    float3 m = np - dot(np, z) * z;
    float ml = length(m);
    if (!(ml > 0.0)) return 0.0;
    float hs = -dot(np, d) / (r * ml);
    float h = abs(hs);
    if (!(h < 1.0)) return 0.0;
    float s = sqrt(1.0 - h * h);
    float3 tdir = cross(z, m) / ml;
    float N0 = dot(q0, tdir) * D;
    float N1 = dot(q1, tdir) * D;
    float B0 = w0 * r;
    float B1 = w1 * r;
    float lo;
    float hi;
    if (B0 > 0.0 && B1 > 0.0) {
        float l0 = clamp(N0 / B0, -BIG, BIG);
        float l1 = clamp(N1 / B1, -BIG, BIG);
        lo = min(l0, l1);
        hi = max(l0, l1);
    } else {
        float nstar = (B0 * N1 - B1 * N0) / (B0 - B1);
        float lk = B0 > 0.0 ? clamp(N0 / B0, -BIG, BIG) : clamp(N1 / B1, -BIG, BIG);
        if (nstar > 0.0) { lo = lk; hi = BIG; }
        else if (nstar < 0.0) { lo = -BIG; hi = lk; }
        else return 0.0;
    }
    float a = max(lo, -s);
    float b = min(hi, s);
    if (!(a < b)) return 0.0;
    // 3. sector minus triangle, as a fraction of the disk area (HLSL's atan2(y, x) is GLSL's atan(y, x))
    float dl = b - a;
    float theta = h > 0.0 ? atan2(h * dl, h * h + a * b) : (a * b < 0.0 ? 3.14159265 : 0.0);
    float area = max(0.0, (theta - h * dl) * 0.15915494);
    // 4. positive half space of the hard plane adds occlusion
    return hs >= 0.0 ? area : -area;
}

// A&AM: visibility = 1 - clamp(hard count + sum of signed coverages, 0, 1).
float sk_wedge_visibility(float hard_count, float coverage_sum) {
    return 1.0 - saturate(hard_count + coverage_sum);
}
