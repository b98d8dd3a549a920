// shadowkit/glsl/linear_light.glsl - soft shadows from a line-segment light (Heidrich et al. 2000), GPU side.
//
// The skin pass (depth discontinuities of one endpoint's shadow map triangulated, warped into the
// other endpoint's view, Gouraud 0 on the occluder / 1 on the receiver, MIN-blended into that
// endpoint's visibility map) and the lookup V = sum over the two endpoints of lit * (visibility-map
// value, or the default 0.5 where no skin covers). Same rules as include/shadowkit/linear_light.hpp
// (linear_light_skin_cell, linear_light_shade); docs/linear_light.md has the whole setup.
// versions: 330, 450
// stages: vertex, fragment
//
// Lights: a light is its homogeneous position `light_position` = (x, y, z, w), as OpenGL's
// GL_POSITION and Everitt & Kilgard use it. w > 0: a point or spot light at xyz / w. w = 0: a
// directional light at infinity in direction xyz, the direction *toward* the light (its rays travel
// along -xyz). w < 0, (0, 0, 0, 0) and NaN/Inf are rejected with Status::InvalidLight.
// Here the light is a segment: sk_linear_light_visibility takes its endpoints end_a, end_b (world
// positions), and sk_linear_light_endpoint takes one endpoint as a point light
// `vec4 light_position` = (end, 1.0) (GLSL cannot return a status: pass a valid one).
//
// Shadow maps: perspective depth maps (GL clip depth, window depth in [0,1]) with known near/far,
// sampled as sampler2D (GL_NEAREST, compare mode OFF), polygon offset in the depth pass.
// Visibility maps: RGBA32F, cleared to (1, 1, 1, 1); skin pass with glEnable(GL_BLEND),
// glBlendEquation(GL_MIN), depth test and culling off; r = smallest skin value, g = 0 where a skin
// covers the texel, b = the nearest skin's window depth. A skin value applies only to receivers
// behind the skin (the penumbra it spans); points in front of it (the occluder's own lit faces)
// keep the default 0.5.
// Skin pass: draw 6 * (W - 1) * (H - 1) vertices without attributes (gl_VertexID); every vertex
// computes its cell; triangles that are not skin collapse to a point outside the view.
// Parameters: threshold = relative linear-depth jump of a discontinuity (0.05 default); bias =
// window-depth bias of the endpoint depth tests (0 with polygon offset).
//
// Usage:
//   // skin vertex: gl_Position = sk_linear_light_skin_vertex(u_other_depth, u_other_inv_vp, u_other_near,
//   //                  u_other_far, u_this_vp, 0.05, gl_VertexID, v_value);   (out: noperspective float)
//   // skin fragment: o_vis = sk_linear_light_skin_output(v_value, gl_FragCoord.z);
//   // (or build the skin on the CPU with linear_light_build_skin and draw it with the view_proj)
//   // lookup: float V = sk_linear_light_visibility(u_depth_a, u_vis_a, u_vp_a, u_end_a,
//   //                                              u_depth_b, u_vis_b, u_vp_b, u_end_b, p, n, 0.0);
//
// MIT License. Copyright (c) shadowkit contributors.

// Linear distance along the view axis from a window depth of a GL perspective projection.
float sk_linear_light_depth(float window_z, float near_z, float far_z) {
    float z = window_z * 2.0 - 1.0;
    return 2.0 * near_z * far_z / (far_z + near_z - z * (far_z - near_z));
}

// Skin vertex `vertex_id` (6 per 2x2 cell of the other endpoint's W x H map: triangles (0,1,3) and
// (0,3,2) of corners 0 (i,j), 1 (i+1,j), 2 (i,j+1), 3 (i+1,j+1)). Both kept when the cell's
// linear depths jump by more than `threshold` (nearer than the cell's mid distance = occluder,
// value 0; else receiver, value 1). Returns the clip position in this endpoint's view
// (view_proj) or a collapsed point outside the view.
vec4 sk_linear_light_skin_vertex(sampler2D other_depth, mat4 other_inv_view_proj, float other_near, float other_far,
                                 mat4 view_proj, float threshold, int vertex_id, out float value) {
    ivec2 sz = textureSize(other_depth, 0);
    int cells_x = max(sz.x - 1, 1);
    int cell_id = vertex_id / 6;
    int tri = (vertex_id % 6) / 3;
    int k = vertex_id % 3;
    ivec2 cell = ivec2(cell_id % cells_x, cell_id / cells_x);
    value = 0.0;
    vec4 outside = vec4(2.0, 2.0, 2.0, 1.0);
    if (cell.y >= sz.y - 1) return outside;
    float zw[4];
    float d[4];
    float lo = 1e30, hi = 0.0;
    for (int c = 0; c < 4; ++c) {
        zw[c] = texelFetch(other_depth, cell + ivec2(c & 1, c >> 1), 0).r;
        d[c] = sk_linear_light_depth(zw[c], other_near, other_far);
        lo = min(lo, d[c]);
        hi = max(hi, d[c]);
    }
    if (!(lo > 0.0) || !(hi > lo * (1.0 + threshold))) return outside;
    float mid = 0.5 * (lo + hi);
    int c0 = 0, c1 = tri == 0 ? 1 : 3, c2 = tri == 0 ? 3 : 2;
    int corner = k == 0 ? c0 : (k == 1 ? c1 : c2);
    value = d[corner] > mid ? 1.0 : 0.0;
    vec2 uv = (vec2(cell + ivec2(corner & 1, corner >> 1)) + 0.5) / vec2(sz);
    vec4 w = other_inv_view_proj * vec4(uv * 2.0 - 1.0, zw[corner] * 2.0 - 1.0, 1.0);
    return view_proj * vec4(w.xyz / w.w, 1.0);
}

// Skin fragment output for MIN blending into the RGBA visibility map; frag_depth = gl_FragCoord.z.
vec4 sk_linear_light_skin_output(float value, float frag_depth) { return vec4(clamp(value, 0.0, 1.0), 0.0, frag_depth, 0.0); }

// One endpoint's term for the point light `light_position` (the endpoint, w = 1; w = 0 for a
// directional endpoint): 0 if the point fails the depth test or faces away, else the visibility
// map value (0.5 where no skin covers). Points outside the endpoint's frustum count as lit.
float sk_linear_light_endpoint(sampler2D depth_map, sampler2D vis_map, mat4 view_proj, vec4 light_position, vec3 p,
                               vec3 n, float bias_window) {
    if (dot(n, light_position.xyz - p * light_position.w) <= 0.0) return 0.0;
    vec4 c = view_proj * vec4(p, 1.0);
    if (c.w <= 0.0) return 0.5;
    vec3 w = c.xyz / c.w * 0.5 + 0.5;
    if (any(lessThan(w.xy, vec2(0.0))) || any(greaterThan(w.xy, vec2(1.0)))) return 0.5;
    ivec2 sz = textureSize(depth_map, 0);
    ivec2 ij = clamp(ivec2(w.xy * vec2(sz)), ivec2(0), sz - 1);
    if (w.z > texelFetch(depth_map, ij, 0).r + bias_window) return 0.0;
    vec3 v = texelFetch(vis_map, ij, 0).rgb;
    return (v.g < 0.5 && w.z >= v.b - 1e-6) ? v.r : 0.5;
}

// The paper's shade() for one linear light (endpoints end_a and end_b, world positions), in [0, 1].
float sk_linear_light_visibility(sampler2D depth_a, sampler2D vis_a, mat4 view_proj_a, vec3 end_a,
                                 sampler2D depth_b, sampler2D vis_b, mat4 view_proj_b, vec3 end_b, vec3 p, vec3 n,
                                 float bias_window) {
    return clamp(sk_linear_light_endpoint(depth_a, vis_a, view_proj_a, vec4(end_a, 1.0), p, n, bias_window) +
                     sk_linear_light_endpoint(depth_b, vis_b, view_proj_b, vec4(end_b, 1.0), p, n, bias_window),
                 0.0, 1.0);
}
