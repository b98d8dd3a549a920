// shadowkit/glsl/smoothie.glsl - smoothies (Chan & Durand, EGSR 2003): linear-depth shadow map,
// smoothie buffer (depth + alpha, minimum blending), final lookup with the eq. 1 remap, the
// sinusoidal falloff and a manual 2x2 bilinear filter of the per-texel results.
// versions: 330, 450
// stages: vertex, fragment
//
// Geometry: the triangle list from shadowkit/smoothie.hpp smoothie_build (SmoothieVertex, 48 bytes:
// vec3 position, float alpha, vec3 silhouette_vertex, float inv_t, vec2 outward, float corner, pad).
// Units: light NDC ([-1,1]); t is in NDC units. Depths are LINEAR: d = -(light_view * p).z, the
// distance from the light along its axis, in every buffer and for the receiver.
// Uniforms (user-declared, passed in): light_view_proj, light_view (mat4); buffer_size (vec2, the
// smoothie buffer's size in pixels, = the shadow map's); the linear shadow map (sampler2D, R32F,
// GL_NEAREST); the smoothie buffer (sampler2D, RG32F: r = depth b, g = alpha; GL_NEAREST).
//
// Passes and GL state:
//  1. Linear shadow map: R32F colour + a depth buffer, glEnable(GL_DEPTH_TEST), GL_LESS, clear colour
//     to 1e30. Vertex: gl_Position = light_view_proj * p; fragment writes sk_smoothie_linear_depth.
//  2. Smoothie buffer, ONE pass: RG32F target cleared to (1e30, 1), glDisable(GL_DEPTH_TEST),
//     glDisable(GL_CULL_FACE), glEnable(GL_BLEND), glBlendEquation(GL_MIN) (blend factors are
//     ignored by GL_MIN): each channel keeps its minimum, i.e. the nearest smoothie depth and the
//     minimum alpha (the paper's minimum blending; its depth-buffer pass + alpha pass give the same
//     pair). Vertex: sk_smoothie_vertex; fragment: discard if sk_smoothie_hidden (the paper discards
//     smoothie pixels behind a blocker), then out vec2 = sk_smoothie_fragment(...). Its frag_coord must
//     have NDC y = -1 at y = 0 (GL, Vulkan's plain viewport); under a Vulkan negative-height viewport
//     pass vec2(gl_FragCoord.x, buffer_size.y - gl_FragCoord.y) (the corners' alpha is wrong otherwise).
//     Variant (paper, Fig. 11): remap in this pass with r = the shadow-map depth under the smoothie,
//     alpha = sk_smoothie_remap(alpha, b, sk_smoothie_shadow_depth_at(...)), and call the final
//     lookup with alpha_is_remapped = true.
//  3. Final: v = sk_smoothie_visibility(shadow_map, smoothie_map, uv, r, dr_duv, bias, false) with
//     the receiver's light uv ([0,1]) and linear depth r; multiply the light's contribution by v.
//     dr_duv = sk_smoothie_depth_gradient(dFdx(uv), dFdy(uv), dFdx(r), dFdy(r)) (receiver-plane
//     depth bias, fragment stage only) or vec2(0.0) for a constant bias only.
// t = 0: draw nothing in pass 2; the buffer stays (1e30, 1) and pass 3 is the hard shadow test.
// Biases (linear depth; smoothie.hpp "Bias" says why): pass 2 discard with bias = 2e-3 * b, pass 3
// with bias = 1e-3 * r and the receiver-plane gradient dr_duv.
// The light is the center of projection of light_view_proj (no light_position here): build the
// silhouette for that same light.
//
// MIT License. Copyright (c) shadowkit contributors.

// Linear depth of a world point: distance from the light along its viewing axis.
float sk_smoothie_linear_depth(mat4 light_view, vec3 world_pos) {
    return -(light_view * vec4(world_pos, 1.0)).z;
}

// Vertex stage of pass 2. Outputs: clip position, linear depth b (interpolate `smooth`), the
// silhouette vertex in light NDC (pass `flat`). Also pass a_alpha `noperspective` (it is affine in
// light screen space), a_inv_t and a_corner `flat`.
void sk_smoothie_vertex(mat4 light_view_proj, mat4 light_view, vec3 position, vec3 silhouette_vertex,
                        out vec4 clip_position, out float linear_depth, out vec2 silhouette_ndc) {
    clip_position = light_view_proj * vec4(position, 1.0);
    linear_depth = sk_smoothie_linear_depth(light_view, position);
    vec4 s = light_view_proj * vec4(silhouette_vertex, 1.0);
    silhouette_ndc = s.xy / s.w;
}

// Light NDC of a fragment of the smoothie buffer (viewport = the whole buffer).
vec2 sk_smoothie_frag_ndc(vec2 frag_coord_xy, vec2 buffer_size) {
    return frag_coord_xy / buffer_size * 2.0 - 1.0;
}

// Smoothie alpha (Chan & Durand 2003 sec. 3.1): edges use the interpolated alpha (distance to the
// edge's line / t); corners, caps and fans use |p - v| / t in light NDC (corner = 1). Clamped to [0,1].
float sk_smoothie_alpha(vec2 frag_ndc, float interpolated_alpha, vec2 silhouette_ndc, float inv_t, float corner) {
    float a = corner > 0.5 ? length(frag_ndc - silhouette_ndc) * inv_t : interpolated_alpha;
    return clamp(a, 0.0, 1.0);
}

// Linear shadow-map depth at this smoothie-buffer pixel (same resolution as the shadow map).
float sk_smoothie_shadow_depth_at(sampler2D linear_shadow_map, vec2 frag_coord_xy) {
    ivec2 size = textureSize(linear_shadow_map, 0);
    ivec2 p = clamp(ivec2(frag_coord_xy), ivec2(0), size - 1);
    return texelFetch(linear_shadow_map, p, 0).r;
}

// True if the smoothie fragment at linear depth b lies behind a blocker (discard it).
bool sk_smoothie_hidden(sampler2D linear_shadow_map, vec2 frag_coord_xy, float b, float bias_linear) {
    return b > sk_smoothie_shadow_depth_at(linear_shadow_map, frag_coord_xy) + bias_linear;
}

// Chan & Durand 2003 eq. 1: alpha' = clamp(alpha / (1 - b/r)) = clamp(alpha r / (r - b));
// b/r >= 1 (receiver in front of the smoothie) or r <= 0 -> 1.
float sk_smoothie_remap(float alpha, float b, float r) {
    if (!(r > 0.0) || !(b < r)) return 1.0;
    return clamp(clamp(alpha, 0.0, 1.0) * r / (r - b), 0.0, 1.0);
}

// Sinusoidal falloff (Haines 2001): s(a) = sin^2(pi a / 2), a clamped to [0,1].
float sk_smoothie_falloff(float a) {
    float s = sin(1.5707963267948966 * clamp(a, 0.0, 1.0));
    return s * s;
}

// Pass 2 output: (linear depth b, alpha) for the GL_MIN-blended RG32F smoothie buffer.
vec2 sk_smoothie_fragment(vec2 frag_coord_xy, vec2 buffer_size, float interpolated_alpha, vec2 silhouette_ndc,
                          float inv_t, float corner, float linear_depth) {
    vec2 ndc = sk_smoothie_frag_ndc(frag_coord_xy, buffer_size);
    return vec2(linear_depth, sk_smoothie_alpha(ndc, interpolated_alpha, silhouette_ndc, inv_t, corner));
}

// Receiver-plane depth gradient dr/duv from screen derivatives (pass dFdx/dFdy of the receiver's
// light uv and linear depth r). Returns vec2(0) where the uv footprint is singular.
vec2 sk_smoothie_depth_gradient(vec2 duv_dx, vec2 duv_dy, float dr_dx, float dr_dy) {
    float det = duv_dx.x * duv_dy.y - duv_dx.y * duv_dy.x;
    if (abs(det) < 1e-20) return vec2(0.0);
    // Solve [duv_dx; duv_dy] g = (dr_dx, dr_dy).
    return vec2(dr_dx * duv_dy.y - dr_dy * duv_dx.y, dr_dy * duv_dx.x - dr_dx * duv_dy.x) / det;
}

// One tap: umbra (0), penumbra (falloff of the remapped alpha), lit (1).
float sk_smoothie_tap(float r, float z, vec2 smoothie, float bias_linear, bool alpha_is_remapped) {
    if (r > z + bias_linear) return 0.0;
    if (r > smoothie.x)
        return sk_smoothie_falloff(alpha_is_remapped ? smoothie.y : sk_smoothie_remap(smoothie.y, smoothie.x, r));
    return 1.0;
}

// Final lookup: visibility in [0,1] of a receiver at light uv (in [0,1]) and linear depth r. The
// four texels around uv are tested (both buffers at the same resolution, texelFetch) and the
// results filtered bilinearly (Chan & Durand 2003 sec. 3, step 5). The receiver depth is moved
// to each texel centre along its plane (dr_duv) before the comparisons; bias is a linear-depth
// offset for the umbra test. Outside [0,1]^2 or r <= 0 -> 1.
float sk_smoothie_visibility(sampler2D shadow_map, sampler2D smoothie_map, vec2 uv, float r, vec2 dr_duv, float bias_linear,
                             bool alpha_is_remapped) {
    if (!(r > 0.0) || any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return 1.0;
    ivec2 size = textureSize(shadow_map, 0);
    vec2 fsize = vec2(size);
    vec2 st = uv * fsize - 0.5;
    vec2 base = floor(st);
    vec2 f = st - base;
    ivec2 i0 = ivec2(base);
    float v[4];
    for (int k = 0; k < 4; ++k) {
        ivec2 texel = clamp(i0 + ivec2(k & 1, k >> 1), ivec2(0), size - 1);
        vec2 uv_tap = (vec2(texel) + 0.5) / fsize;
        float r_tap = r + dot(dr_duv, uv_tap - uv);
        float z = texelFetch(shadow_map, texel, 0).r;
        vec2 s = texelFetch(smoothie_map, texel, 0).rg;
        v[k] = sk_smoothie_tap(r_tap, z, s, bias_linear, alpha_is_remapped);
    }
    return mix(mix(v[0], v[1], f.x), mix(v[2], v[3], f.x), f.y);
}
