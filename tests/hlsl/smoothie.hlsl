// Driver for hlsl/smoothie.hlsl: a pixel shader calling every function (the vertex-stage one is
// stage-independent arithmetic).
[[vk::binding(0, 0)]] Texture2D<float> g_shadow_map : register(t0);
[[vk::binding(1, 0)]] Texture2D<float2> g_smoothie_map : register(t1);
struct Params {
    column_major float4x4 light_view_proj;
    column_major float4x4 light_view;
    float2 buffer_size;
};
[[vk::binding(2, 0)]] ConstantBuffer<Params> g : register(b0);
float4 main(float4 position : SV_Position, float3 world : TEXCOORD0, float alpha : TEXCOORD1) : SV_Target0 {
    float4 clip;
    float b;
    float2 sil;
    sk_smoothie_vertex(g.light_view_proj, g.light_view, world, world + 1.0, clip, b, sil);
    if (sk_smoothie_hidden(g_shadow_map, position.xy, b, 2e-3 * b)) discard;
    float2 o = sk_smoothie_fragment(position.xy, g.buffer_size, alpha, sil, 4.0, 0.0, b);
    float2 uv = clip.xy / clip.w * 0.5 + 0.5;
    float r = sk_smoothie_linear_depth(g.light_view, world);
    float2 dr = sk_smoothie_depth_gradient(ddx(uv), ddy(uv), ddx(r), ddy(r));
    float v = sk_smoothie_visibility(g_shadow_map, g_smoothie_map, uv, r, dr, 1e-3 * r, false);
    return float4(o, v, sk_smoothie_remap(alpha, b, r) + sk_smoothie_falloff(alpha));
}
