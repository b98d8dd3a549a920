// shadowkit/hlsl/linear_light.hlsl - soft shadows from a line-segment light (Heidrich et al. 2000) in HLSL, GPU side: the skin pass and the lookup.
// stages: vertex (sk_linear_light_skin_vertex), pixel (the rest)
//
// The HLSL twin of glsl/linear_light.glsl: the same sk_ functions, arguments and results; its header
// says the passes (skin triangulation, MIN blending into the RGBA32F visibility maps) and what each
// value means (include/shadowkit/linear_light.hpp is the CPU side).
// Lights: a light is its homogeneous position `light_position` = (x, y, z, w), as OpenGL's
// GL_POSITION and Everitt & Kilgard use it. w > 0: a point or spot light at xyz / w. w = 0: a
// directional light at infinity in direction xyz, the direction *toward* the light (its rays travel
// along -xyz). w < 0, (0, 0, 0, 0) and NaN/Inf are rejected with Status::InvalidLight.
// Here the light is a segment: sk_linear_light_visibility takes its endpoints end_a, end_b, and
// sk_linear_light_endpoint one endpoint as a point light (end, 1.0) (HLSL cannot return a status:
// pass a valid one).
// Depth convention: like the GLSL, these functions take the endpoints' GL-style matrices ([-1, 1] clip
// depth, window depth = ndc * 0.5 + 0.5). On Direct3D / Vulkan render the endpoint depth maps with the
// [0, 1] projection of the same planes (glm::perspectiveRH_ZO: the same window depth) and pass the GL
// matrix (glm::perspectiveRH_NO) here; the skin vertex takes this end's [0, 1] view_proj (its window
// depth is what the skin stores) and the other end's GL matrix inverted. Maps: depth Texture2D<float>
// and visibility Texture2D<float4>, read with Load. Matrices `column_major` with mul(M, v)
// (hlsl/shadow_map.hlsl states the rule). The skin vertex takes SV_VertexID.
// Compiled in the tests by glslang's HLSL front end to SPIR-V and its passes run on Vulkan; written
// for DXC (shader model 6.0) as well, but not compiled with it here (DXC is not packaged in Debian 12).
// MIT License. Copyright (c) shadowkit contributors.

// Linear distance along the view axis from a window depth of a GL perspective projection.
float sk_linear_light_depth(float window_z, float near_z, float far_z) {
    float z = window_z * 2.0 - 1.0;
    return 2.0 * near_z * far_z / (far_z + near_z - z * (far_z - near_z));
}

// Skin vertex `vertex_id` (6 per 2x2 cell of the other endpoint's W x H map); the clip position in
// this endpoint's view (view_proj) or a collapsed point outside the view (glsl/linear_light.glsl).
float4 sk_linear_light_skin_vertex(Texture2D<float> other_depth, float4x4 other_inv_view_proj, float other_near,
                                   float other_far, float4x4 view_proj, float threshold, int vertex_id, out float value) {
    uint sw, sh;
    other_depth.GetDimensions(sw, sh);
    int2 sz = int2(sw, sh);
    int cells_x = max(sz.x - 1, 1);
    int cell_id = vertex_id / 6;
    int tri = (vertex_id % 6) / 3;
    int k = vertex_id % 3;
    int2 cell = int2(cell_id % cells_x, cell_id / cells_x);
    value = 0.0;
    float4 outside = float4(2.0, 2.0, 2.0, 1.0);
    if (cell.y >= sz.y - 1) return outside;
    float zw[4];
    float d[4];
    float lo = 1e30;
    float hi = 0.0;
    [unroll] for (int c = 0; c < 4; ++c) {
        zw[c] = other_depth.Load(int3(cell + int2(c & 1, c >> 1), 0));
        d[c] = sk_linear_light_depth(zw[c], other_near, other_far);
        lo = min(lo, d[c]);
        hi = max(hi, d[c]);
    }
    if (!(lo > 0.0) || !(hi > lo * (1.0 + threshold))) return outside;
    float mid = 0.5 * (lo + hi);
    int c0 = 0;
    int c1 = tri == 0 ? 1 : 3;
    int c2 = tri == 0 ? 3 : 2;
    int corner = k == 0 ? c0 : (k == 1 ? c1 : c2);
    value = d[corner] > mid ? 1.0 : 0.0;
    float2 uv = (float2(cell + int2(corner & 1, corner >> 1)) + 0.5) / float2(sz);
    float4 w = mul(other_inv_view_proj, float4(uv * 2.0 - 1.0, zw[corner] * 2.0 - 1.0, 1.0));
    return mul(view_proj, float4(w.xyz / w.w, 1.0));
}

// Skin pixel output for MIN blending into the RGBA visibility map; frag_depth = SV_Position.z.
float4 sk_linear_light_skin_output(float value, float frag_depth) { return float4(saturate(value), 0.0, frag_depth, 0.0); }

// One endpoint's term for the point light `light_position` (the endpoint, w = 1): 0 if the point
// fails the depth test or faces away, else the visibility-map value (0.5 where no skin covers).
// Points outside the endpoint's frustum count as lit (0.5).
float sk_linear_light_endpoint(Texture2D<float> depth_map, Texture2D<float4> vis_map, float4x4 view_proj,
                               float4 light_position, float3 p, float3 n, float bias_window) {
    if (dot(n, light_position.xyz - p * light_position.w) <= 0.0) return 0.0;
    float4 c = mul(view_proj, float4(p, 1.0));
    if (c.w <= 0.0) return 0.5;
    float3 w = c.xyz / c.w * 0.5 + 0.5;
    if (any(w.xy < 0.0) || any(w.xy > 1.0)) return 0.5;
    uint sw, sh;
    depth_map.GetDimensions(sw, sh);
    int2 sz = int2(sw, sh);
    int2 ij = clamp(int2(w.xy * float2(sz)), int2(0, 0), sz - 1);
    if (w.z > depth_map.Load(int3(ij, 0)) + bias_window) return 0.0;
    float3 v = vis_map.Load(int3(ij, 0)).rgb;
    return (v.g < 0.5 && w.z >= v.b - 1e-6) ? v.r : 0.5;
}

// The paper's shade() for one linear light (endpoints end_a and end_b, world positions), in [0, 1].
float sk_linear_light_visibility(Texture2D<float> depth_a, Texture2D<float4> vis_a, float4x4 view_proj_a, float3 end_a,
                                 Texture2D<float> depth_b, Texture2D<float4> vis_b, float4x4 view_proj_b, float3 end_b,
                                 float3 p, float3 n, float bias_window) {
    return saturate(sk_linear_light_endpoint(depth_a, vis_a, view_proj_a, float4(end_a, 1.0), p, n, bias_window) +
                    sk_linear_light_endpoint(depth_b, vis_b, view_proj_b, float4(end_b, 1.0), p, n, bias_window));
}
