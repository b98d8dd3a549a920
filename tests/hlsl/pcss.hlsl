// Driver for hlsl/pcss.hlsl: a pixel shader calling every function (2D and array overloads).
[[vk::binding(0, 0)]] Texture2D<float> g_map : register(t0);
[[vk::binding(1, 0)]] Texture2DArray<float> g_maps : register(t1);
[[vk::binding(2, 0)]] SamplerState g_point : register(s0);
[[vk::binding(3, 0)]] SamplerComparisonState g_compare : register(s1);
struct Params {
    float light_uv;
    float near_plane;
    float far_plane;
    float layer;
};
[[vk::binding(4, 0)]] ConstantBuffer<Params> g : register(b0);
float4 main(float4 position : SV_Position, float3 uvz : TEXCOORD0) : SV_Target0 {
    float2 zero = float2(0.0, 0.0);
    float angle = 6.2831853 * sk_interleaved_gradient_noise(position.xy);
    float a = sk_pcss(g_map, g_point, g_compare, uvz, zero, g.light_uv, g.near_plane, g.far_plane, 16, 16, angle, 0.05);
    float b = sk_pcss_directional(g_map, g_point, g_compare, uvz, zero, g.light_uv, 16, 16, angle, 0.05);
    float c = sk_pcss_blocker_window_depth(g_map, g_point, uvz, 0.01, 16, angle) +
              sk_pcss_filter(g_map, g_compare, uvz, zero, 0.01, 16, angle) + float(sk_pcss_tap_budget(0.01, 2048.0, 4, 64)) +
              sk_linearize_depth(uvz.z, g.near_plane, g.far_plane) + float(sk_depth_closer(uvz.z, 0.5));
    float d = sk_pcss(g_maps, g_point, g_compare, g.layer, uvz, zero, g.light_uv, g.near_plane, g.far_plane, 16, 16, angle, 0.05) +
              sk_pcss_directional(g_maps, g_point, g_compare, g.layer, uvz, zero, g.light_uv, 16, 16, angle, 0.05) +
              sk_pcss_blocker_window_depth(g_maps, g_point, g.layer, uvz, 0.01, 16, angle) +
              sk_pcss_filter(g_maps, g_compare, g.layer, uvz, zero, 0.01, 16, angle);
    return float4(a, b, c, d);
}
