// Driver for hlsl/pcf.hlsl: declarations and a pixel shader calling every function.
[[vk::binding(0, 0)]] Texture2D<float> g_shadow_map : register(t0);
[[vk::binding(1, 0)]] Texture2DArray<float> g_shadow_maps : register(t1);
[[vk::binding(2, 0)]] SamplerComparisonState g_compare : register(s0);
struct Params {
    float layer;
    float radius_uv;
    int taps;
    int radius_texels;
};
[[vk::binding(3, 0)]] ConstantBuffer<Params> g : register(b0);
float4 main(float4 position : SV_Position, float4 shadow_coord : TEXCOORD0) : SV_Target0 {
    float3 uvz = shadow_coord.xyz / shadow_coord.w * float3(0.5, -0.5, 1.0) + float3(0.5, 0.5, 0.0);
    float2 grad = sk_receiver_plane_depth_bias(uvz);
    float2 grad2 = sk_receiver_plane_gradient(ddx(uvz), ddy(uvz));
    float noise = sk_interleaved_gradient_noise(position.xy);
    float a = sk_pcf_hard(g_shadow_map, g_compare, uvz);
    float b = sk_pcf_box(g_shadow_map, g_compare, uvz, grad, g.radius_texels);
    float c = sk_pcf_tent(g_shadow_map, g_compare, uvz, grad2, g.radius_texels);
    float d = sk_pcf_poisson(g_shadow_map, g_compare, uvz, grad, g.radius_uv, g.taps, 6.28318531 * noise);
    float e = sk_pcf_poisson_rotated(g_shadow_map, g_compare, uvz, grad, g.radius_uv, g.taps, position.xy);
    float f = sk_pcf_tap(g_shadow_map, g_compare, uvz, grad, float2(0.0, 0.0));
    float a2 = sk_pcf_hard(g_shadow_maps, g_compare, g.layer, uvz);
    float b2 = sk_pcf_box(g_shadow_maps, g_compare, g.layer, uvz, grad, g.radius_texels);
    float c2 = sk_pcf_tent(g_shadow_maps, g_compare, g.layer, uvz, grad, g.radius_texels);
    float d2 = sk_pcf_poisson(g_shadow_maps, g_compare, g.layer, uvz, grad, g.radius_uv, g.taps, 0.0);
    float e2 = sk_pcf_poisson_rotated(g_shadow_maps, g_compare, g.layer, uvz, grad, g.radius_uv, g.taps, position.xy);
    float f2 = sk_pcf_tap(g_shadow_maps, g_compare, g.layer, uvz, grad, float2(0.0, 0.0));
    return float4(a * b * c, d * e * f, a2 * b2 * c2, d2 * e2 * f2 + sk_poisson_disk64[63].x);
}
