// Driver for hlsl/omni_shadow.hlsl: a pixel shader calling every function (the vertex-stage ones are
// stage-independent arithmetic).
[[vk::binding(0, 0)]] TextureCube<float> g_cube : register(t0);
[[vk::binding(1, 0)]] Texture2DArray<float> g_paraboloid : register(t1);
[[vk::binding(2, 0)]] SamplerComparisonState g_compare : register(s0);
[[vk::binding(3, 0)]] SamplerState g_point : register(s1);
struct Params {
    column_major float4x4 dp_view;
    float4 light_position;
    float range;
    float size;
};
[[vk::binding(4, 0)]] ConstantBuffer<Params> g : register(b0);
float4 main(float4 position : SV_Position, float3 world : TEXCOORD0, float3 normal : TEXCOORD1) : SV_Target0 {
    float3 L = sk_omni_light_point(g.light_position) - world;
    float d = length(L);
    float b = sk_omni_bias(d, dot(normalize(normal), L / d), sk_omni_cube_texel_angle(g.size), 1.4143, 1.4835,
                           float2(0.0, 2.38418579e-7));
    float a = sk_cube_visibility_distance(g_cube, g_compare, g.light_position, world, g.range, b);
    float m = sk_cube_visibility_distance_manual(g_cube, g_point, g.light_position, world, g.range, b);
    float p = sk_cube_visibility_distance_pcf(g_cube, g_compare, g.light_position, world, g.range, b, g.size, 1);
    float4 clip = sk_dp_clip_position(g.dp_view, world, 1.0, g.range, true);
    float cd = sk_dp_clip_distance(g.dp_view, world, -1.0, 0.1);
    float3 dir = sk_dp_direction(sk_dp_project(normalize(world)).xy, 0.0);
    float4 coord = sk_dp_coord(g.dp_view, world);
    float s = sk_dp_shadow(g_paraboloid, g_compare, g.dp_view, world, g.range, b) +
              sk_dp_shadow_pcf(g_paraboloid, g_compare, g.dp_view, world, g.range, b, g.size, 1) +
              sk_dp_texel_angle(g.size, coord.w);
    return float4(a * m * p, s + cd, clip.z + dir.x + sk_omni_linear_depth(world, g.light_position, g.range), coord.x);
}
