// Driver for hlsl/penumbra_wedge.hlsl: a pixel shader calling every function.
[[vk::binding(0, 0)]] Texture2D<float> g_depth : register(t0);
struct Params {
    column_major float4x4 inv_view_proj;
    column_major float4x4 inverse_transpose;
    float4 light_position;
    float4 e0;
    float4 e1;
    float4 planes[4];
    float light_radius;
};
[[vk::binding(1, 0)]] ConstantBuffer<Params> g : register(b0);
float4 main(float4 position : SV_Position, float2 ndc : TEXCOORD0) : SV_Target0 {
    float4 vp = float4(position.xy, g_depth.Load(int3(int2(position.xy), 0)), 1.0);
    if (!sk_wedge_inside3(vp, g.planes[0], g.planes[1], g.planes[2])) discard;
    bool in4 = sk_wedge_inside4(vp, g.planes[0], g.planes[1], g.planes[2], sk_wedge_transform_plane(g.inverse_transpose, g.planes[3]));
    float3 p = sk_wedge_world_from_depth(g.inv_view_proj, ndc, vp.z, true);
    float c = sk_wedge_edge_coverage(g.e0.xyz, g.e1.xyz, g.light_position, g.light_radius, p);
    return float4(c, sk_wedge_visibility(1.0, c), in4 ? 1.0 : 0.0, 0.0);
}
