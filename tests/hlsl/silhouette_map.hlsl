// Driver for hlsl/silhouette_map.hlsl: a pixel shader calling every function (the vertex-stage one is
// stage-independent arithmetic).
[[vk::binding(0, 0)]] Texture2D<float> g_depth : register(t0);
[[vk::binding(1, 0)]] Texture2D<float4> g_silmap : register(t1);
struct Params {
    float4 ab;
    float2 map_size;
    float2 zab;
};
[[vk::binding(2, 0)]] ConstantBuffer<Params> g : register(b0);
float4 main(float4 position : SV_Position, float2 uv : TEXCOORD0, float receiver_depth : TEXCOORD1) : SV_Target0 {
    float2 local;
    float w;
    if (!sk_silmap_point(position.xy, g.ab.xy, g.ab.zw, local, w)) discard;
    if (sk_silmap_occluded(g_depth, int2(position.xy), g.ab.xy, g.ab.zw, g.zab.x, g.zab.y, local, 1e-4)) discard;
    float4 clip = sk_silmap_edge_vertex(g.ab.xy, g.ab.zw, 3, g.map_size);
    float2 hit;
    bool h = sk_silmap_seg_hit(g.ab.xy, g.ab.zw, float2(0.0, 0.0), float2(1.0, 1.0), hit);
    float lit = sk_silmap_visibility(g_depth, g_silmap, uv * g.map_size, receiver_depth, 0.0);
    return float4(local, w / 255.0, lit + clip.x + (h ? hit.x : 0.0) + sk_silmap_wrap(-1.0));
}
