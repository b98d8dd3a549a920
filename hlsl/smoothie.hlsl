// shadowkit/hlsl/smoothie.hlsl - smoothies (Chan & Durand, EGSR 2003) in HLSL: linear-depth shadow map, smoothie buffer (depth + alpha, minimum blending), final lookup with the eq. 1 remap, the sinusoidal falloff and a manual 2x2 bilinear filter.
// stages: vertex, pixel
//
// The HLSL twin of glsl/smoothie.glsl: the same sk_ functions, arguments and results; its header says
// the three passes, the geometry (shadowkit/smoothie.hpp smoothie_build) and the biases. The maps are
// Texture2D<float> (linear shadow map, R32_FLOAT) and Texture2D<float2> (smoothie buffer, R32G32_FLOAT,
// MIN blending: BlendOp MIN in Direct3D, VK_BLEND_OP_MIN in Vulkan), read with Load (no sampler).
// Matrices `column_major` with mul(M, v) (hlsl/shadow_map.hlsl states the rule). frag_coord_xy is
// SV_Position.xy (the pixel centre, as gl_FragCoord.xy). Draw the shadow map and the smoothie buffer
// with the same viewport. sk_smoothie_frag_ndc takes frag_coord / buffer_size * 2 - 1 as the light NDC
// (NDC y = -1 at pixel row 0: Vulkan's plain viewport); where y runs the other way (a negative-height
// viewport, which maps NDC y as Direct3D's does) pass float2(x, buffer_size.y - y) to
// sk_smoothie_fragment, the fetches keeping SV_Position.xy (measured on Vulkan: the corners' alpha is
// off by 0.93 otherwise, exact with it).
// Compiled in the tests by glslang's HLSL front end to SPIR-V and its three passes run on Vulkan;
// written for DXC (shader model 6.0) as well, but not compiled with it here (not in Debian 12).
// MIT License. Copyright (c) shadowkit contributors.

// Linear depth of a world point: distance from the light along its viewing axis.
float sk_smoothie_linear_depth(float4x4 light_view, float3 world_pos) {
    return -mul(light_view, float4(world_pos, 1.0)).z;
}

// Vertex stage of pass 2: clip position, linear depth b, the silhouette vertex in light NDC.
void sk_smoothie_vertex(float4x4 light_view_proj, float4x4 light_view, float3 position, float3 silhouette_vertex,
                        out float4 clip_position, out float linear_depth, out float2 silhouette_ndc) {
    clip_position = mul(light_view_proj, float4(position, 1.0));
    linear_depth = sk_smoothie_linear_depth(light_view, position);
    float4 s = mul(light_view_proj, float4(silhouette_vertex, 1.0));
    silhouette_ndc = s.xy / s.w;
}

// Light NDC of a pixel of the smoothie buffer (viewport = the whole buffer).
float2 sk_smoothie_frag_ndc(float2 frag_coord_xy, float2 buffer_size) {
    return frag_coord_xy / buffer_size * 2.0 - 1.0;
}

// Smoothie alpha (sec. 3.1): edges the interpolated alpha, corners |p - v| / t. Clamped to [0,1].
float sk_smoothie_alpha(float2 frag_ndc, float interpolated_alpha, float2 silhouette_ndc, float inv_t, float corner) {
    float a = corner > 0.5 ? length(frag_ndc - silhouette_ndc) * inv_t : interpolated_alpha;
    return saturate(a);
}

// Linear shadow-map depth at this smoothie-buffer pixel (same resolution as the shadow map).
float sk_smoothie_shadow_depth_at(Texture2D<float> linear_shadow_map, float2 frag_coord_xy) {
    uint w, h;
    linear_shadow_map.GetDimensions(w, h);
    int2 p = clamp(int2(frag_coord_xy), int2(0, 0), int2(w, h) - 1);
    return linear_shadow_map.Load(int3(p, 0));
}

// True if the smoothie pixel at linear depth b lies behind a blocker (discard it).
bool sk_smoothie_hidden(Texture2D<float> linear_shadow_map, float2 frag_coord_xy, float b, float bias_linear) {
    return b > sk_smoothie_shadow_depth_at(linear_shadow_map, frag_coord_xy) + bias_linear;
}

// Chan & Durand 2003 eq. 1: alpha' = clamp(alpha r / (r - b)); b/r >= 1 or r <= 0 -> 1.
float sk_smoothie_remap(float alpha, float b, float r) {
    if (!(r > 0.0) || !(b < r)) return 1.0;
    return saturate(saturate(alpha) * r / (r - b));
}

// Sinusoidal falloff (Haines 2001): s(a) = sin^2(pi a / 2), a clamped to [0,1].
float sk_smoothie_falloff(float a) {
    float s = sin(1.5707963267948966 * saturate(a));
    return s * s;
}

// Pass 2 output: (linear depth b, alpha) for the MIN-blended smoothie buffer.
float2 sk_smoothie_fragment(float2 frag_coord_xy, float2 buffer_size, float interpolated_alpha, float2 silhouette_ndc,
                            float inv_t, float corner, float linear_depth) {
    float2 ndc = sk_smoothie_frag_ndc(frag_coord_xy, buffer_size);
    return float2(linear_depth, sk_smoothie_alpha(ndc, interpolated_alpha, silhouette_ndc, inv_t, corner));
}

// Receiver-plane depth gradient dr/duv from screen derivatives; float2(0, 0) where singular.
float2 sk_smoothie_depth_gradient(float2 duv_dx, float2 duv_dy, float dr_dx, float dr_dy) {
    float det = duv_dx.x * duv_dy.y - duv_dx.y * duv_dy.x;
    if (abs(det) < 1e-20) return float2(0.0, 0.0);
    return float2(dr_dx * duv_dy.y - dr_dy * duv_dx.y, dr_dy * duv_dx.x - dr_dx * duv_dy.x) / det;
}

// One tap: umbra (0), penumbra (falloff of the remapped alpha), lit (1).
float sk_smoothie_tap(float r, float z, float2 smoothie, float bias_linear, bool alpha_is_remapped) {
    if (r > z + bias_linear) return 0.0;
    if (r > smoothie.x)
        return sk_smoothie_falloff(alpha_is_remapped ? smoothie.y : sk_smoothie_remap(smoothie.y, smoothie.x, r));
    return 1.0;
}

// Final lookup: visibility in [0,1] of a receiver at light uv and linear depth r: the four texels
// around uv tested and filtered bilinearly. Outside [0,1]^2 or r <= 0 -> 1.
float sk_smoothie_visibility(Texture2D<float> shadow_map, Texture2D<float2> smoothie_map, float2 uv, float r, float2 dr_duv,
                             float bias_linear, bool alpha_is_remapped) {
    if (!(r > 0.0) || any(uv < 0.0) || any(uv > 1.0)) return 1.0;
    uint w, h;
    shadow_map.GetDimensions(w, h);
    int2 size = int2(w, h);
    float2 fsize = float2(size);
    float2 st = uv * fsize - 0.5;
    float2 base = floor(st);
    float2 f = st - base;
    int2 i0 = int2(base);
    float v[4];
    [unroll] for (int k = 0; k < 4; ++k) {
        int2 texel = clamp(i0 + int2(k & 1, k >> 1), int2(0, 0), size - 1);
        float2 uv_tap = (float2(texel) + 0.5) / fsize;
        float r_tap = r + dot(dr_duv, uv_tap - uv);
        float z = shadow_map.Load(int3(texel, 0));
        float2 s = smoothie_map.Load(int3(texel, 0));
        v[k] = sk_smoothie_tap(r_tap, z, s, bias_linear, alpha_is_remapped);
    }
    return lerp(lerp(v[0], v[1], f.x), lerp(v[2], v[3], f.x), f.y);
}
