// Driver for hlsl/prefiltered_shadow.hlsl: a pixel shader calling every function (the compute-stage
// ones are stage-independent).
[[vk::binding(0, 0)]] Texture2D<float4> g_moments : register(t0);
[[vk::binding(1, 0)]] Texture2DMS<float> g_depth_ms : register(t1);
[[vk::binding(2, 0)]] SamplerState g_trilinear : register(s0);
struct Params {
    float4 params;
    float4 soft;
    float4 window_map;
    float2 scale_offset;
    float2 exponents;
    int method;
    float moment_bias;
    int quantized;
};
[[vk::binding(3, 0)]] ConstantBuffer<Params> g : register(b0);
float4 main(float4 position : SV_Position, float2 uv : TEXCOORD0, float eye_distance : TEXCOORD1) : SV_Target0 {
    float t = sk_prefilter_depth(eye_distance, g.scale_offset);
    bool q = g.quantized != 0;
    float4 m = sk_prefilter_moments(t, float2(ddx(t), ddy(t)), g.method, g.exponents, q);
    float4 m2 = sk_msm_dequantize(sk_msm_quantize(sk_msm_moments(t))) + sk_evsm_moments(t, g.exponents);
    float3 dx = float3(ddx(uv), ddx(t));
    float3 dy = float3(ddy(uv), ddy(t));
    float bias = sk_prefilter_receiver_bias(dx, dy, 0.01);
    float v = sk_prefilter_visibility(g_moments.SampleLevel(g_trilinear, uv, 0.0), t - bias, g.method, g.params, g.moment_bias, q);
    float s = sk_prefilter_soft_visibility(g_moments, g_trilinear, uv, t, g.method, g.params, g.moment_bias, q, g.soft,
                                           float2(sk_prefilter_receiver_slope(dx, dy), 0.01));
    float weights[SK_PREFILTER_MAX_WEIGHTS];
    for (int i = 0; i < SK_PREFILTER_MAX_WEIGHTS; ++i) weights[i] = 1.0 / float(i + 1);
    float4 blur = sk_prefilter_blur(g_moments, int2(position.xy), int2(1, 0), 4, weights);
    float4 resolved = sk_prefilter_resolve(g_depth_ms, int2(position.xy), 4, g.window_map, g.method, g.exponents, q);
    float e = sk_esm_moment(t, g.exponents.x) + sk_prefilter_depth_from_window(position.z, g.window_map) +
              sk_vsm_moments(t, float2(0.0, 0.0)).y;
    return float4(v * s, blur.x + resolved.y, m.x + m2.y, e);
}
