// Driver for hlsl/prt.hlsl: a pixel shader calling both functions.
struct Params {
    float3 env[25];
    int count;
};
[[vk::binding(1, 0)]] ConstantBuffer<Params> g : register(b0);
float4 main(float4 position : SV_Position, nointerpolation int index : TEXCOORD0) : SV_Target0 {
    float t[25];
    for (int i = 0; i < 25; ++i) t[i] = sk_prt_transfer[index * 25 + i];
    float3 c = sk_prt_shade_vertex(index, 25, g.count, g.env) + sk_prt_dot(t, g.env, g.count);
    return float4(c, 1.0);
}
