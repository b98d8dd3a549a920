// Driver for hlsl/perspective_shadow_maps.hlsl: a pixel shader calling every function.
[[vk::binding(0, 0)]] Texture2D<float> g_shadow_map : register(t0);
[[vk::binding(1, 0)]] SamplerComparisonState g_compare : register(s0);
struct Params {
    column_major float4x4 warp;
    column_major float4x4 depth_proj;
    column_major float4x4 warp_inverse;
};
[[vk::binding(2, 0)]] ConstantBuffer<Params> g : register(b0);
struct Output {
    float4 color : SV_Target0;
    float depth : SV_Depth;
};
Output main(float4 position : SV_Position, float3 world : TEXCOORD0, float4 depth_clip : TEXCOORD1,
            float3 normal : TEXCOORD2) {
    Output o;
    float4 c = sk_warp_coord(g.warp, g.depth_proj, world, true);
    float lit = sk_warp_shadow(g_shadow_map, g_compare, g.warp, g.depth_proj, world, 5e-4, true);
    float lit_auto = sk_warp_shadow_auto(g_shadow_map, g_compare, g.warp, g.warp_inverse, g.depth_proj, world, normal, true,
                                         0.0, 1.0);
    o.color = float4(lit * lit_auto, c.xyz);
    o.depth = sk_warp_map_depth(depth_clip, 2.0, 0.0, true);
    return o;
}
