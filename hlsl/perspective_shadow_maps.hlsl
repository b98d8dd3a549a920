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
                     float3 world_pos, float bias, bool zero_to_one) {
    float4 c = sk_warp_coord(warp, depth_proj, world_pos, zero_to_one);
    if (c.w == 0.0) return 1.0;
    return shadow_map.SampleCmpLevelZero(cmp, c.xy, c.z - bias);
}

// The window depth to write to SV_Depth in the shadow pass with separate_depth, plus slope_scale times
// its largest screen-space slope and constant_bias (both negative for reversed-Z), clamped to [0, 1].
float sk_warp_map_depth(float4 depth_clip, float slope_scale, float constant_bias, bool zero_to_one) {
    float z = depth_clip.z / depth_clip.w;
    float window_z = zero_to_one ? z : z * 0.5 + 0.5;
    float slope = max(abs(ddx(window_z)), abs(ddy(window_z)));
    return saturate(window_z + slope_scale * slope + constant_bias);
}
