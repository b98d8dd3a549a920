// Driver for hlsl/shadow_cache.hlsl: a pixel shader calling every function (the geometry-stage ones
// are stage-independent arithmetic).
struct Params {
    int2 anchor;
    int2 viewport_anchor;
    float2 viewport_size;
};
[[vk::binding(0, 0)]] ConstantBuffer<Params> g : register(b0);
struct Output {
    float4 color : SV_Target0;
    float depth : SV_Depth;
};
Output main(float4 position : SV_Position, float3 g0 : TEXCOORD0, float3 g1 : TEXCOORD1, float3 g2 : TEXCOORD2) {
    Output o;
    float3 plane;
    float2 origin;
    bool ok = sk_shadow_cache_plane(g0, g1, g2, plane, origin);
    float4 clip = sk_shadow_cache_position(g0.xy, g.viewport_anchor, g.viewport_size);
    o.color = float4(clip.xy, ok ? 1.0 : 0.0, sk_shadow_cache_quantize(g1.xy).x);
    o.depth = sk_shadow_cache_depth(plane, origin, position.xy, g.anchor) + sk_shadow_cache_depth_offset(plane, 2.0, 0.0);
    return o;
}
