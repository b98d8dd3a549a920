// shadowkit/hlsl/perspective_shadow_maps.hlsl - lookup and map depth for warped shadow maps (uniform, PSM, LiSPSM, TSM) in HLSL.
// stages: pixel (sk_warp_map_depth: pixel only; the others any stage)
//
// The HLSL twin of glsl/perspective_shadow_maps.glsl: the same sk_ functions, arguments and results for
// the matrices of shadowkit/perspective_shadow_maps.hpp (warp = WarpResult::light_view_proj,
// depth_proj = WarpResult::depth_view_proj); glsl/perspective_shadow_maps.glsl says the rest. The map
// is a Texture2D<float> with its SamplerComparisonState (LESS_EQUAL, GREATER_EQUAL for reversed-Z).
// Matrices `column_major` with mul(M, v) (hlsl/shadow_map.hlsl states the rule); Direct3D and Vulkan
// build them with ClipDepth::ZeroToOne (zero_to_one = true).
// TSM's separate depth: the shadow pass's pixel shader returns SV_Depth = sk_warp_map_depth(depth_clip,
// 2.0, 0.0, true) (depth_clip = depth_proj * world position from the vertex stage; reversed-Z: -2.0).
// Automatic bias (true depths in the map, standard depth only): sk_warp_shadow_auto(g_map, g_compare, warp,
// warp_inverse, depth_proj, world_pos, world_normal, true, 0.0, 1.0), warp_inverse = inverse(warp) in double.
// Compiled in the tests by glslang's HLSL front end to SPIR-V and run on Vulkan; written for DXC
// (shader model 6.0) as well, but not compiled with it here (DXC is not packaged in Debian 12).
// MIT License. Copyright (c) shadowkit contributors.

// xyz = (u, v, depth) in [0,1]; w = 1 if the point is in front of the light's projection and inside
// the map, 0 otherwise (then treat it as lit).
float4 sk_warp_coord(float4x4 warp, float4x4 depth_proj, float3 world_pos, bool zero_to_one) {
    float4 h = mul(warp, float4(world_pos, 1.0));
    float4 hd = mul(depth_proj, float4(world_pos, 1.0));
    if (h.w <= 0.0 || hd.w <= 0.0) return float4(0.0, 0.0, 0.0, 0.0);
    float2 xy = h.xy / h.w;
    float z = hd.z / hd.w;
    float3 c = float3(xy * 0.5 + 0.5, zero_to_one ? z : z * 0.5 + 0.5);
    bool inside = all(c.xy >= 0.0) && all(c.xy <= 1.0);
    return float4(c, inside ? 1.0 : 0.0);
}

// 1 = lit, 0 = shadowed (bias in window depth; negative for reversed-Z).
float sk_warp_shadow(Texture2D<float> shadow_map, SamplerComparisonState cmp, float4x4 warp, float4x4 depth_proj,
                     float3 world_pos, float bias_window, bool zero_to_one) {
    float4 c = sk_warp_coord(warp, depth_proj, world_pos, zero_to_one);
    if (c.w == 0.0) return 1.0;
    return shadow_map.SampleCmpLevelZero(cmp, c.xy, c.z - bias_window);
}

// The automatic bias for any warp, TSM's separate depth included (render the map's true depths:
// sk_warp_map_depth(depth_clip, 0.0, 0.0, ...) for TSM). Four compares at the texel centres around the
// lookup, each against the receiver plane's depth there: the light ray through the texel centre
// (warp_inverse unprojects it at two depths) meets the plane through world_pos with `normal`, and
// depth_proj gives that point's depth (Isidoro 2006's receiver plane through TSM's two matrices);
// the margin as glsl/perspective_shadow_maps.glsl states it. warp_inverse: inverse(warp), in double
// on the CPU. Returns 1 lit .. 0 shadowed; `outside` where the point is not in the map; 1.0 edge-on.
// depth_proj[r][c] is GLSL's depth_proj[c][r] (rows 2 and 3 below).
float sk_warp_shadow_auto(Texture2D<float> shadow_map, SamplerComparisonState cmp, float4x4 warp, float4x4 warp_inverse,
                          float4x4 depth_proj, float3 world_pos, float3 normal, bool zero_to_one, float depth_step,
                          float outside) {
    float4 c = sk_warp_coord(warp, depth_proj, world_pos, zero_to_one);
    if (c.w == 0.0) return outside;
    float3 n = normalize(normal);
    float width, height;
    shadow_map.GetDimensions(width, height);
    float2 size = float2(width, height);
    float2 f = c.xy * size - 0.5;
    float2 i0 = floor(f);
    float2 w = f - i0;
    float zn = zero_to_one ? 0.0 : -1.0;
    float4 z;
    [unroll] for (int k = 0; k < 4; ++k) {
        float2 ndc = ((i0 + float2(float(k & 1), float(k >> 1)) + 0.5) / size) * 2.0 - 1.0;
        float4 a = mul(warp_inverse, float4(ndc, zn, 1.0)), b = mul(warp_inverse, float4(ndc, 1.0, 1.0));
        float3 x0 = a.xyz / a.w, x1 = b.xyz / b.w;
        float den = dot(n, x1 - x0);
        float t = den != 0.0 ? dot(n, world_pos - x0) / den : 0.0;
        float4 hd = mul(depth_proj, float4(x0 + t * (x1 - x0), 1.0));
        float zk = hd.z / hd.w;
        zk = zero_to_one ? zk : zk * 0.5 + 0.5;
        z[k] = den != 0.0 && hd.w > 0.0 && abs(zk) < 3.0e38 ? zk : c.z;  // edge-on to that ray: the point's own depth
    }
    // the margin: format steps, float rounding of depths and position, 1/8 texel of the plane's slope
    float4 hp = mul(depth_proj, float4(world_pos, 1.0));
    float3 rz = depth_proj[2].xyz, rw = depth_proj[3].xyz;
    float3 jz = abs(rz - (hp.z / hp.w) * rw) / abs(hp.w) * (zero_to_one ? 1.0 : 0.5);
    float3 ap = abs(world_pos);
    float pos_err = exp2(-21.0) * (ap.x + ap.y + ap.z) * (jz.x + jz.y + jz.z);
    float slope = abs(z.y - z.x) + abs(z.z - z.x);
    float eps = 2.0 * max(depth_step, 0.0) + exp2(-21.0) * (1.0 + abs(c.z)) + 2.0 * pos_err + 0.125 * slope;
    float4 weight = float4((1.0 - w.x) * (1.0 - w.y), w.x * (1.0 - w.y), (1.0 - w.x) * w.y, w.x * w.y);
    float v = 0.0;
    [unroll] for (int j = 0; j < 4; ++j) {
        float2 uv = (i0 + float2(float(j & 1), float(j >> 1)) + 0.5) / size;
        v += weight[j] * shadow_map.SampleCmpLevelZero(cmp, uv, clamp(z[j] - eps, 0.0, 1.0));
    }
    return v;
}

// The window depth to write to SV_Depth in the shadow pass with separate_depth, plus slope_scale times
// its largest screen-space slope and constant_bias (both negative for reversed-Z), clamped to [0, 1].
float sk_warp_map_depth(float4 depth_clip, float slope_scale, float constant_bias, bool zero_to_one) {
    float z = depth_clip.z / depth_clip.w;
    float window_z = zero_to_one ? z : z * 0.5 + 0.5;
    float slope = max(abs(ddx(window_z)), abs(ddy(window_z)));
    return saturate(window_z + slope_scale * slope + constant_bias);
}
