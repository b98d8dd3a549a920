// shadowkit/hlsl/prt.hlsl - precomputed radiance transfer shading in HLSL: one dot product per color channel.
// stages: vertex, pixel
//
// The HLSL twin of glsl/prt.glsl: the same sk_ functions, arguments and results (Sloan, Kautz &
// Snyder 2002; include/shadowkit/prt.hpp prt_shade_rgb is the CPU twin; docs/prt.md the setup).
// Transfer vectors: a StructuredBuffer<float> of tightly packed floats, `stride` per vertex, declared
// below at [[vk::binding(SK_PRT_TRANSFER_BINDING, 0)]] (default 0) and register(SK_PRT_TRANSFER_REGISTER)
// (default t0); define either before this file to move it. Upload prt_compute_transfer's
// std::vector<float> as is. Environment: `float3 env[25]` from your constant buffer (16-byte array
// stride in HLSL constant buffers and std140 alike), prt_project_environment's coefficients.
// count = order * order (1, 4, 9, 16, 25).
// Compiled in the tests by glslang's HLSL front end to SPIR-V and run on Vulkan; written for DXC
// (shader model 6.0) as well, but not compiled with it here (DXC is not packaged in Debian 12).
// MIT License. Copyright (c) shadowkit contributors.

#ifndef SK_PRT_TRANSFER_BINDING
#define SK_PRT_TRANSFER_BINDING 0
#endif
#ifndef SK_PRT_TRANSFER_REGISTER
#define SK_PRT_TRANSFER_REGISTER t0
#endif

[[vk::binding(SK_PRT_TRANSFER_BINDING, 0)]] StructuredBuffer<float> sk_prt_transfer : register(SK_PRT_TRANSFER_REGISTER);

// sum over i < count of t[i] * env[i] (count clamped to 0..25).
float3 sk_prt_dot(float t[25], float3 env[25], int count) {
    float3 c = float3(0.0, 0.0, 0.0);
    int n = clamp(count, 0, 25);
    for (int i = 0; i < n; ++i) c += t[i] * env[i];
    return c;
}

// Exit radiance of vertex (or texel) `index` whose transfer vector starts at index * stride.
float3 sk_prt_shade_vertex(int index, int stride, int count, float3 env[25]) {
    float3 c = float3(0.0, 0.0, 0.0);
    int n = clamp(count, 0, min(stride, 25));
    int base = index * stride;
    for (int i = 0; i < n; ++i) c += sk_prt_transfer[base + i] * env[i];
    return c;
}
