[[vk::binding(0, 0)]] Texture2D<float> g_map;
[[vk::binding(1, 0)]] SamplerComparisonState g_compare;
float4 main(float4 position : SV_Position) : SV_Target0 { return sk_broken(g_map, g_compare, position.xy).xxxx; }
