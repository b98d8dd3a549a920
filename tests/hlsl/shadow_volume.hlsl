// Driver for hlsl/shadow_volume.hlsl: a pixel shader calling the depth-bounds emulation and, as the
// vertex shader would, the extrusion (the function is stage-independent).
[[vk::binding(0, 0)]] Texture2D<float> g_scene_depth : register(t0);
struct Params {
    column_major float4x4 view_proj;
    float4 light_position;
    float2 bounds;
};
[[vk::binding(1, 0)]] ConstantBuffer<Params> g : register(b0);
float4 main(float4 position : SV_Position, float4 volume_vertex : TEXCOORD0) : SV_Target0 {
    if (sk_outside_depth_bounds_at(g_scene_depth, int2(position.xy), g.bounds)) discard;
    float4 clip = mul(g.view_proj, sk_extrude_shadow_volume(volume_vertex, g.light_position));
    return float4(clip.xy, float(sk_outside_depth_bounds(position.z, g.bounds)), 1.0);
}
