// Driver for hlsl/shadow_map.hlsl: declarations and a pixel shader calling every function.
[[vk::binding(0, 0)]] Texture2D<float> g_shadow_map : register(t0);
[[vk::binding(1, 0)]] Texture2DArray<float> g_shadow_maps : register(t1);
[[vk::binding(2, 0)]] TextureCube<float> g_cube : register(t2);
[[vk::binding(3, 0)]] SamplerComparisonState g_compare : register(s0);
struct Params {
    column_major float4x4 light_view_proj;
    float4 light_position;
    float layer;
};
[[vk::binding(4, 0)]] ConstantBuffer<Params> g : register(b0);
float4 main(float4 position : SV_Position, float3 world : TEXCOORD0, float3 normal : TEXCOORD1) : SV_Target0 {
    float4 c = sk_shadow_coord(g.light_view_proj, world, true);
    float a = sk_shadow_map_visibility(g_shadow_map, g_compare, g.light_view_proj, world, true, 1e-4, 1.0);
    float b = sk_shadow_map_visibility_auto(g_shadow_map, g_compare, g.light_view_proj, world, normal, true, 0.0, 1.0);
    float d = sk_shadow_map_visibility_auto(g_shadow_maps, g_compare, g.layer, g.light_view_proj, world, normal, true,
                                            1.0 / 16777215.0, 1.0);
    float e = sk_cube_visibility_hardware_depth(g_cube, g_compare, g.light_position, world, 0.1, 50.0, 1e-4);
    float4 grad = sk_plane_depth_gradient(g.light_view_proj, world, normal, true);
    float f = sk_auto_filtered_bias(grad, float2(1.0 / 2048.0, 1.0 / 2048.0), c.z, 0.0);
    float h = sk_cube_visibility_hardware_depth_auto(g_cube, g_compare, g.light_position, world, normal, 0.1, 50.0, 0.0);
    float3 fwd, right, up;
    sk_cube_face_frame(world - g.light_position.xyz, fwd, right, up);
    float4 face = sk_shadow_coord(sk_cube_face_view_proj(g.light_position.xyz, fwd, right, up, 0.1, 50.0), world, false);
    return float4(a * b, d * e * h, f + face.z, c.w);
}
