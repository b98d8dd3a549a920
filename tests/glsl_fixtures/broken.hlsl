// A broken HLSL snippet (fixture): the compile check must fail on it.
float sk_broken(Texture2D<float> m, SamplerComparisonState c, float2 uv) {
    return m.SampleCmpLevelZero(c, uv, 0.5)  // missing semicolon
}
