// shadowkit/glsl/prt.glsl - precomputed radiance transfer shading: one dot product per color channel.
//
// Exit radiance = dot(transfer vector, environment SH coefficients) per color channel (Sloan, Kautz
// & Snyder 2002; Kautz, SIGGRAPH 2004 course notes). Same rules as include/shadowkit/prt.hpp
// (prt_shade_rgb); docs/prt.md has the whole setup.
// versions: 450
// stages: vertex, fragment
//
// Inputs:
//   transfer vectors: an SSBO of tightly packed floats, `stride` floats per vertex (stride >= the
//     number of coefficients used; a transfer computed at order 5 has stride 25 and can be shaded
//     at any order 1..5), declared below at binding SK_PRT_TRANSFER_BINDING (define it before
//     this snippet to move it; default 0). Upload the std::vector<float> from
//     prt_compute_transfer as is (std430 float arrays have no padding).
//   environment: uniform vec3 u_env[25] (the driver / your shader declares it), the SH projection
//     of the environment's radiance (prt_project_environment, rotated on the CPU with sh_rotate
//     when the environment turns); coefficients past `count` are ignored.
//   count = order * order (1, 4, 9, 16, 25).
// No light: the lighting is the environment in SH.
// GL state: the SSBO bound with glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SK_PRT_TRANSFER_BINDING,
// buffer) (GL 4.3+; vertex-stage SSBOs need GL_MAX_VERTEX_SHADER_STORAGE_BLOCKS >= 1); nothing else
// (ordinary depth test, no blending).
//
// Usage (vertex stage, Gouraud; the dot product is linear, so interpolating the color equals
// interpolating the transfer vector):
//   v_radiance = u_albedo * sk_prt_shade_vertex(gl_VertexID, 25, u_order * u_order, u_env);
// Fragment stage: the same function (e.g. with a per-texel index), or sk_prt_dot on transfer
// coefficients from anywhere else.
//
// MIT License. Copyright (c) shadowkit contributors.

#ifndef SK_PRT_TRANSFER_BINDING
#define SK_PRT_TRANSFER_BINDING 0
#endif

layout(std430, binding = SK_PRT_TRANSFER_BINDING) readonly buffer SkPrtTransfer {
    float sk_prt_transfer[];
};

// sum over i < count of t[i] * env[i] (count clamped to 0..25).
vec3 sk_prt_dot(float t[25], vec3 env[25], int count) {
    vec3 c = vec3(0.0);
    int n = clamp(count, 0, 25);
    for (int i = 0; i < n; ++i) c += t[i] * env[i];
    return c;
}

// Exit radiance of vertex (or texel) `index` whose transfer vector starts at index * stride.
vec3 sk_prt_shade_vertex(int index, int stride, int count, vec3 env[25]) {
    vec3 c = vec3(0.0);
    int n = clamp(count, 0, min(stride, 25));
    int base = index * stride;
    for (int i = 0; i < n; ++i) c += sk_prt_transfer[base + i] * env[i];
    return c;
}
