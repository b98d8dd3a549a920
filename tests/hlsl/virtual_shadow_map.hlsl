// Driver for hlsl/virtual_shadow_map.hlsl: a pixel shader calling every function (the snippet binds
// its two buffers at 0 and 1; the atlas here at 2).
[[vk::binding(2, 0)]] Texture2D<float> g_atlas : register(t2);
float4 main(float4 position : SV_Position, float3 rel_pos : TEXCOORD0, float3 normal : TEXCOORD1) : SV_Target0 {
    int level = sk_vsm_level_for_footprint(0.05, 0.0);
    int marked = sk_vsm_mark(rel_pos, level, 1);
    int used;
    float a = sk_vsm_visibility_level(g_atlas, rel_pos, normal, level, 1, 0.0, used);
    float b = sk_vsm_visibility(g_atlas, rel_pos, normal, level, 0, 0.0);
    float3 debug = sk_vsm_debug_color(rel_pos, level);
    return float4(debug * a * b, float(marked + used));
}
