// Driver for hlsl/contact_shadow.hlsl: a pixel shader calling every function.
[[vk::binding(0, 0)]] Texture2D<float> g_depth : register(t0);
struct Params {
    column_major float4x4 proj;
    column_major float4x4 inv_proj;
    float4 view_light;
    float length_world;
    int steps;
};
[[vk::binding(1, 0)]] ConstantBuffer<Params> g : register(b0);
float4 main(float4 position : SV_Position) : SV_Target0 {
    uint w, h;
    g_depth.GetDimensions(w, h);
    int2 size = int2(w, h);
    int2 px = int2(position.xy);
    float win = g_depth.Load(int3(px, 0));
    float3 view_pos = sk_contact_view_position(g.inv_proj, size, px, win, true);
    float jitter = sk_contact_noise(position.xy);
    float a = sk_contact_shadow(g_depth, g.proj, view_pos, g.view_light, g.length_world, g.steps, 0.0, 0.0, true, jitter);
    float b = sk_contact_shadow_aligned(g_depth, g.proj, view_pos, g.view_light, g.length_world, g.steps, 0.0, 0.0, true,
                                        jitter);
    float4 c0, c1;
    float z1;
    bool clipped = sk_contact_clip_ray(g.proj, view_pos, g.view_light, g.length_world, true, c0, c1, z1);
    bool aligned = sk_contact_aligned_ray(g.proj, view_pos, g.view_light, g.length_world, true, c0, c1);
    SkContactAligned r;
    bool setup = sk_contact_aligned_setup(size, g.proj, view_pos, g.view_light, g.length_world, g.steps, 0.0, 0.0, true,
                                          jitter, r);
    bool hit = setup && sk_contact_aligned_sample(g_depth, size, r, 0.0);
    float bil = sk_contact_depth_bilinear(g_depth, size, position.xy / float2(size));
    float n = sk_contact_near(c0, true) + (sk_contact_finite(z1) ? 1.0 : 0.0);
    return float4(a * b, clipped && aligned ? 1.0 : 0.0, hit ? bil : n, 1.0);
}
