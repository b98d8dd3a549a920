// Driver for hlsl/linear_light.hlsl: a pixel shader calling every function (the vertex-stage one is
// stage-independent).
[[vk::binding(0, 0)]] Texture2D<float> g_depth_a : register(t0);
[[vk::binding(1, 0)]] Texture2D<float4> g_vis_a : register(t1);
[[vk::binding(2, 0)]] Texture2D<float> g_depth_b : register(t2);
[[vk::binding(3, 0)]] Texture2D<float4> g_vis_b : register(t3);
struct Params {
    column_major float4x4 vp_a;
    column_major float4x4 vp_b;
    column_major float4x4 inv_vp_b;
    float4 end_a;
    float4 end_b;
};
[[vk::binding(4, 0)]] ConstantBuffer<Params> g : register(b0);
float4 main(float4 position : SV_Position, float3 p : TEXCOORD0, float3 n : TEXCOORD1, nointerpolation int id : TEXCOORD2)
    : SV_Target0 {
    float value;
    float4 skin = sk_linear_light_skin_vertex(g_depth_b, g.inv_vp_b, 0.1, 20.0, g.vp_a, 0.05, id, value);
    float v = sk_linear_light_visibility(g_depth_a, g_vis_a, g.vp_a, g.end_a.xyz, g_depth_b, g_vis_b, g.vp_b, g.end_b.xyz, p, n,
                                         0.0);
    float4 o = sk_linear_light_skin_output(value, position.z);
    return float4(v, skin.x, o.r, sk_linear_light_depth(position.z, 0.1, 20.0));
}
