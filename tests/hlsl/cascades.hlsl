// Driver for hlsl/cascades.hlsl (with hlsl/pcf.hlsl: the filtered lookups exist only after it, so the
// compile check pastes pcf.hlsl first when a driver asks for it with the line below).
// needs: pcf
[[vk::binding(0, 0)]] Texture2DArray<float> g_cascades : register(t0);
[[vk::binding(1, 0)]] SamplerComparisonState g_compare : register(s0);
struct Params {
    column_major float4x4 light_vp[4];
    float4 split_near;
    float4 split_far;
    float4 spheres[4];
    int count;
};
[[vk::binding(2, 0)]] ConstantBuffer<Params> g : register(b0);
[[vk::binding(3, 0)]] Texture2D<float> g_depth : register(t1);
[[vk::binding(4, 0)]] Texture2D<float2> g_level : register(t2);
[[vk::binding(5, 0)]] Texture2D<float4> g_bounds_level : register(t3);
float4 main(float4 position : SV_Position, float3 world : TEXCOORD0, float view_depth : TEXCOORD1) : SV_Target0 {
    int second;
    float weight;
    int i = sk_cascade_pick(view_depth, g.split_near, g.split_far, g.count, 0.1, second, weight);
    int k = sk_cascade_by_sphere(world, g.spheres, g.count);
    float a = sk_cascade_shadow(g_cascades, g_compare, g.light_vp, g.split_near, g.split_far, g.count, world, view_depth,
                                0.1, 5e-4, true);
    float b = sk_cascade_sample(g_cascades, g_compare, g.light_vp[1], 1, world, 5e-4, true);
    float c = sk_cascade_shadow_filtered(g_cascades, g_compare, g.light_vp, g.split_near, g.split_far, g.count, world,
                                         view_depth, 0.1, 5e-4, true, SK_CASCADE_KERNEL_TENT, 2, 16, 0.0, position.xy);
    float d = sk_cascade_sample_filtered(g_cascades, g_compare, g.light_vp[2], 2, world, 5e-4, true,
                                         SK_CASCADE_KERNEL_POISSON_ROTATED, 3, 16, 0.0, position.xy);
    float3 uvz = sk_cascade_coord(g.light_vp[0], world, true);
    int2 texel = int2(position.xy);
    float2 r0 = sk_sdsm_reduce_depth(g_depth, texel, 8, 1.0);
    float2 r1 = sk_sdsm_reduce_minmax(g_level, texel, 4);
    float4 bounds[4];
    sk_sdsm_reduce_bounds(g_depth, texel, 8, 1.0, g.light_vp[0], g.light_vp[1], g.light_vp[2], g.split_far, g.count, true,
                          bounds);
    float4 b1 = sk_sdsm_reduce_bounds_level(g_bounds_level, texel, 4);
    return float4(a * b + r0.x + bounds[1].x, c * d + r1.y + b1.w, float(i + k + second) * weight, uvz.z);
}
