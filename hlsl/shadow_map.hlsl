// shadowkit/hlsl/shadow_map.hlsl - plain shadow-map lookups (Williams 1978) in HLSL: the shadow coordinate, a spot/directional map and a point light's cube map, with a depth bias
// stages: pixel (and any other: every compare is SampleCmpLevelZero)
//
// The HLSL twin of glsl/shadow_map.glsl: the same sk_ functions, arguments and results; the map is a
// Texture2D<float> (TextureCube<float>, Texture2DArray<float>) read through a SamplerComparisonState
// passed next to it. Comments here say only what differs; glsl/shadow_map.glsl says what each
// argument means (bias in window-depth units, the automatic bias, `outside`).
// Matrices (one rule for every hlsl/ snippet): the matrices are GLM's, column-major, uploaded as
// they are. Declare them `column_major float4x4` in the constant buffer (or compile with -Zpc / DXC's
// default, which is column-major too) and multiply `mul(M, v)`: then mul(M, v) is GLM's M * v.
// Elements: HLSL indexes rows first, so GLSL's m[c][r] (column c, row r) is HLSL's m[r][c].
// Depth range: Direct3D and Vulkan clip depth is [0, 1]: pass zero_to_one = true for matrices built
// with ClipDepth::ZeroToOne (light_frustum.hpp, cascades.hpp). Define SK_REVERSED_Z before this file
// for reversed-Z maps (1 at near, compare GREATER_EQUAL).
// Texture y: uv = ndc.xy * 0.5 + 0.5, v growing with NDC y, as in GLSL. In Vulkan that is the map as
// rendered with a plain viewport and the lookup matrix it was rendered with; a map rendered with a
// negative-height viewport (or in Direct3D, whose viewport maps NDC y up to row 0) is looked up with
// flip_y * light_view_proj, flip_y = diag(1, -1, 1, 1). docs/vulkan_and_direct3d.md has the why.
// Sampler state: ComparisonFunc LESS_EQUAL (GREATER_EQUAL reversed-Z), linear min/mag filter for the
// hardware 2x2 percentage-closer filter (point: one texel, hard), clamp addressing. Depth formats:
// D32_FLOAT (Vulkan VK_FORMAT_D32_SFLOAT), D24_UNORM_S8_UINT or D16_UNORM, read as R32_FLOAT /
// R24_UNORM_X8_TYPELESS / R16_UNORM in Direct3D.
// Returns 1 = lit, 0 = shadowed (fractions at the 2x2 filter's edges); points outside the light
// frustum get `outside`.
// Usage:
//   float v = sk_shadow_map_visibility(g_shadow_map, g_compare, g_light_view_proj, world_pos, true, 1e-4, 1.0);
//   float v = sk_shadow_map_visibility_auto(g_shadow_map, g_compare, g_light_view_proj, world_pos, world_normal,
//                                           true, 0.0, 1.0);   // float32 map, automatic bias
//   float v = sk_cube_visibility_hardware_depth_auto(g_cube, g_compare, light_position, world_pos, world_normal,
//                                                    near_z, far_z, 0.0);   // a point light's cube
// Compiled in the tests by glslang's HLSL front end to SPIR-V and run on Vulkan; written for DXC
// (shader model 6.0) and FXC (5.0) as well, but not compiled with them here (DXC is not packaged in
// Debian 12).
// MIT License. Copyright (c) shadowkit contributors.

// Shadow-map coordinates (uv in [0,1], depth in window space) of a world point, and clip w.
float4 sk_shadow_coord(float4x4 light_view_proj, float3 world_pos, bool zero_to_one) {
    float4 clip = mul(light_view_proj, float4(world_pos, 1.0));
    float3 ndc = clip.xyz / clip.w;
    float3 win = float3(ndc.xy * 0.5 + 0.5, zero_to_one ? ndc.z : ndc.z * 0.5 + 0.5);
    return float4(win, clip.w);
}

// Lit fraction of world_pos: one compare of the biased receiver depth (2x2 with a linear filter).
float sk_shadow_map_visibility(Texture2D<float> shadow_map, SamplerComparisonState cmp, float4x4 light_view_proj,
                               float3 world_pos, bool zero_to_one, float bias_window, float outside) {
    float4 c = sk_shadow_coord(light_view_proj, world_pos, zero_to_one);
    if (c.w <= 0.0 || any(c.xy < 0.0) || any(c.xy > 1.0) || c.z > 1.0 || c.z < 0.0)
        return outside;
#ifdef SK_REVERSED_Z
    return shadow_map.SampleCmpLevelZero(cmp, c.xy, c.z + bias_window);
#else
    return shadow_map.SampleCmpLevelZero(cmp, c.xy, c.z - bias_window);
#endif
}

// Cube shadow map of HARDWARE DEPTH (six 90-degree perspective faces sharing near/far, GL clip depth
// [-1, 1] as in glsl/shadow_map.glsl, not reversed): the reference is the face's window depth of the
// major-axis distance, ndc_z = (f + n)/(f - n) - 2 f n / ((f - n) d), minus `bias`. Point lights only
// (light_position.w > 0; others give 1.0, lit).
float sk_cube_visibility_hardware_depth(TextureCube<float> shadow_map, SamplerComparisonState cmp, float4 light_position,
                                        float3 world_pos, float near_z, float far_z, float bias_window) {
    if (!(light_position.w > 0.0)) return 1.0;
    float3 d = world_pos - light_position.xyz / light_position.w;
    float major = max(abs(d.x), max(abs(d.y), abs(d.z)));
    float f = far_z;
    float n = near_z;
    float ndc_z = (f + n) / (f - n) - 2.0 * f * n / ((f - n) * major);
    return shadow_map.SampleCmpLevelZero(cmp, d, ndc_z * 0.5 + 0.5 - bias_window);
}

// ---- automatic bias (glsl/shadow_map.glsl explains each step) ------------------------------------
// Window-depth gradient (dz/du, dz/dv) of the receiver plane in the map of light_view_proj; .z its
// conditioning (0: edge-on), .w the window depth 4 float ulps of world_pos move it by.
float4 sk_plane_depth_gradient(float4x4 light_view_proj, float3 world_pos, float3 normal, bool zero_to_one) {
    float4 c = mul(light_view_proj, float4(world_pos, 1.0));
    float3 ndc = c.xyz / c.w;
    float3 rw = light_view_proj[3].xyz;  // row 3 (GLSL: m[0][3], m[1][3], m[2][3])
    float3 jx = (light_view_proj[0].xyz - ndc.x * rw) / c.w;
    float3 jy = (light_view_proj[1].xyz - ndc.y * rw) / c.w;
    float3 jz = (light_view_proj[2].xyz - ndc.z * rw) / c.w;
    float zs = zero_to_one ? 1.0 : 0.5;
    float3 ap = abs(world_pos);
    float3 ajz = abs(jz);
    float pos_err = 4.76837158e-7 * (ap.x + ap.y + ap.z) * (ajz.x + ajz.y + ajz.z) * zs;
    float3 n = normalize(normal);
    float3 an = abs(n);
    float3 axis = an.x <= an.y && an.x <= an.z ? float3(1.0, 0.0, 0.0) : (an.y <= an.z ? float3(0.0, 1.0, 0.0) : float3(0.0, 0.0, 1.0));
    float3 t1 = normalize(cross(n, axis));
    float3 t2 = cross(n, t1);
    float3 s1 = float3(0.5 * dot(jx, t1), 0.5 * dot(jy, t1), zs * dot(jz, t1));
    float3 s2 = float3(0.5 * dot(jx, t2), 0.5 * dot(jy, t2), zs * dot(jz, t2));
    float det = s1.x * s2.y - s1.y * s2.x;
    float scale = (abs(s1.x) + abs(s1.y)) * (abs(s2.x) + abs(s2.y));
    float cond = scale > 0.0 ? abs(det) / scale : 0.0;
    if (!(cond > 1e-4)) return float4(0.0, 0.0, 0.0, pos_err);
    return float4((s2.y * s1.z - s1.y * s2.z) / det, (s1.x * s2.z - s2.x * s1.z) / det, cond, pos_err);
}

// The automatic bias's margin in window depth at receiver depth z (shadow_bias.hpp bias_auto_epsilon).
float sk_auto_bias_epsilon(float4 g, float2 texel_uv, float z, float depth_step) {
#ifdef SK_REVERSED_Z
    float float_term = 4.76837158e-7 * abs(z) + 1.17549435e-38;
#else
    float float_term = 4.76837158e-7 * (1.0 + abs(z));
#endif
    float plane = abs(g.x) * texel_uv.x + abs(g.y) * texel_uv.y;
    return 2.0 * max(depth_step, 0.0) + float_term + 2.0 * g.w + plane * (0.125 + 9.53674316e-7 + 2.38418579e-7 / max(g.z, 1e-4));
}

// The four taps of the automatic bias around c.xy in a map of `size` texels: texel centres (i, j),
// (i+1, j), (i, j+1), (i+1, j+1), the receiver plane's depth at each minus epsilon (plus reversed),
// and their bilinear weights.
void sk_auto_bias_taps(float4 c, float4 g, float2 size, float depth_step, out float2 tap_uv[4], out float4 tap_z,
                       out float4 weight) {
    float2 texel = 1.0 / size;
    float2 f = c.xy * size - 0.5;
    float2 i0 = floor(f);
    float2 w = f - i0;
    float eps = sk_auto_bias_epsilon(g, texel, c.z, depth_step);
    [unroll] for (int k = 0; k < 4; ++k) {
        float2 centre = (i0 + float2(float(k & 1), float(k >> 1)) + 0.5) * texel;
        tap_uv[k] = centre;
        float zp = c.z + dot(g.xy, centre - c.xy);
#ifdef SK_REVERSED_Z
        tap_z[k] = saturate(zp + eps);
#else
        tap_z[k] = saturate(zp - eps);
#endif
    }
    weight = float4((1.0 - w.x) * (1.0 - w.y), w.x * (1.0 - w.y), (1.0 - w.x) * w.y, w.x * w.y);
}

// true with the four taps, or false with `v` the value when no compare is needed (outside: `outside`;
// edge-on: 1.0).
bool sk_auto_bias_lookup(float4x4 light_view_proj, float3 world_pos, float3 normal, bool zero_to_one, float2 size,
                         float depth_step, float outside, out float v, out float2 uv[4], out float4 z, out float4 w) {
    float4 c = sk_shadow_coord(light_view_proj, world_pos, zero_to_one);
    v = outside;
    uv[0] = uv[1] = uv[2] = uv[3] = float2(0.0, 0.0);
    z = float4(0.0, 0.0, 0.0, 0.0);
    w = float4(0.0, 0.0, 0.0, 0.0);
    if (c.w <= 0.0 || any(c.xy < 0.0) || any(c.xy > 1.0) || c.z > 1.0 || c.z < 0.0)
        return false;
    float4 g = sk_plane_depth_gradient(light_view_proj, world_pos, normal, zero_to_one);
    v = 1.0;
    if (g.z == 0.0) return false;
    sk_auto_bias_taps(c, g, size, depth_step, uv, z, w);
    return true;
}

// Lit fraction of world_pos with the automatic bias (four compares at texel centres, each against the
// receiver plane's depth there). `normal`: the receiver's geometric world normal. Any filter works.
float sk_shadow_map_visibility_auto(Texture2D<float> shadow_map, SamplerComparisonState cmp, float4x4 light_view_proj,
                                    float3 world_pos, float3 normal, bool zero_to_one, float depth_step, float outside) {
    float v;
    float2 uv[4];
    float4 z, w;
    float width, height;
    shadow_map.GetDimensions(width, height);
    if (!sk_auto_bias_lookup(light_view_proj, world_pos, normal, zero_to_one, float2(width, height), depth_step, outside,
                             v, uv, z, w))
        return v;
    return w.x * shadow_map.SampleCmpLevelZero(cmp, uv[0], z.x) + w.y * shadow_map.SampleCmpLevelZero(cmp, uv[1], z.y) +
           w.z * shadow_map.SampleCmpLevelZero(cmp, uv[2], z.z) + w.w * shadow_map.SampleCmpLevelZero(cmp, uv[3], z.w);
}

// The same for one layer of a depth array (sampled area lights, cascades).
float sk_shadow_map_visibility_auto(Texture2DArray<float> shadow_maps, SamplerComparisonState cmp, float layer,
                                    float4x4 light_view_proj, float3 world_pos, float3 normal, bool zero_to_one,
                                    float depth_step, float outside) {
    float v;
    float2 uv[4];
    float4 z, w;
    float width, height, layers;
    shadow_maps.GetDimensions(width, height, layers);
    if (!sk_auto_bias_lookup(light_view_proj, world_pos, normal, zero_to_one, float2(width, height), depth_step, outside,
                             v, uv, z, w))
        return v;
    return w.x * shadow_maps.SampleCmpLevelZero(cmp, float3(uv[0], layer), z.x) +
           w.y * shadow_maps.SampleCmpLevelZero(cmp, float3(uv[1], layer), z.y) +
           w.z * shadow_maps.SampleCmpLevelZero(cmp, float3(uv[2], layer), z.z) +
           w.w * shadow_maps.SampleCmpLevelZero(cmp, float3(uv[3], layer), z.w);
}

// A point light's cube face for direction d (GL / Vulkan cube-map face selection and orientation):
// fwd the face's axis, right and up its +s and +t directions. Ties go to x, then y, as the hardware.
void sk_cube_face_frame(float3 d, out float3 fwd, out float3 right, out float3 up) {
    float3 a = abs(d);
    float3 hint = float3(0.0, -1.0, 0.0);
    if (a.x >= a.y && a.x >= a.z) {
        fwd = float3(d.x >= 0.0 ? 1.0 : -1.0, 0.0, 0.0);
    } else if (a.y >= a.z) {
        fwd = float3(0.0, d.y >= 0.0 ? 1.0 : -1.0, 0.0);
        hint = float3(0.0, 0.0, fwd.y);
    } else {
        fwd = float3(0.0, 0.0, d.z >= 0.0 ? 1.0 : -1.0);
    }
    right = cross(fwd, hint);
    up = cross(right, fwd);
}

// The view-projection of that face: perspective(90 degrees, 1, near, far) * lookAt (GL clip depth).
// float4x4(...) takes ROWS in HLSL (GLSL's mat4(...) takes columns): the same matrix, mul(M, v).
float4x4 sk_cube_face_view_proj(float3 light, float3 fwd, float3 right, float3 up, float near_z, float far_z) {
    float a = -(far_z + near_z) / (far_z - near_z), b = -2.0 * far_z * near_z / (far_z - near_z);
    return float4x4(float4(right, -dot(right, light)), float4(up, -dot(up, light)),
                    float4(-a * fwd, a * dot(fwd, light) + b), float4(fwd, -dot(fwd, light)));
}

// Lit fraction of world_pos in a cube of hardware depth with the automatic bias (glsl/shadow_map.glsl
// says how: four compares at the face's texel centres, each against the receiver plane's window depth
// there, taps past the face's edge read from the neighbouring face with that face's plane depth).
// `normal`: the receiver's geometric world normal; depth_step: the cube's format step (0.0 float32).
// Cube rendered as sk_cube_visibility_hardware_depth's (GL clip depth, not reversed, no depth bias).
float sk_cube_visibility_hardware_depth_auto(TextureCube<float> shadow_map, SamplerComparisonState cmp, float4 light_position,
                                             float3 world_pos, float3 normal, float near_z, float far_z,
                                             float depth_step) {
    if (!(light_position.w > 0.0)) return 1.0;
    float3 light = light_position.xyz / light_position.w;
    float3 d = world_pos - light;
    if (all(d == 0.0)) return 1.0;
    float3 fwd, right, up;
    sk_cube_face_frame(d, fwd, right, up);
    float4x4 vp = sk_cube_face_view_proj(light, fwd, right, up, near_z, far_z);
    float4 c = sk_shadow_coord(vp, world_pos, false);
    float4 g = sk_plane_depth_gradient(vp, world_pos, normal, false);
    if (g.z == 0.0) return 1.0;  // edge-on receiver
    float width, height;
    shadow_map.GetDimensions(width, height);
    float2 size = float2(width, height);
    float2 texel = 1.0 / size;
    float eps = sk_auto_bias_epsilon(g, texel, c.z, depth_step);
    float2 f = c.xy * size - 0.5;
    float2 i0 = floor(f);
    float2 w = f - i0;
    float4 weight = float4((1.0 - w.x) * (1.0 - w.y), w.x * (1.0 - w.y), (1.0 - w.x) * w.y, w.x * w.y);
    float3 n = normalize(normal);
    float nd = dot(n, d);
    float zf = (far_z + near_z) / (far_z - near_z), zg = 2.0 * far_z * near_z / (far_z - near_z);
    float v = 0.0;
    [unroll] for (int k = 0; k < 4; ++k) {
        float2 centre = (i0 + float2(float(k & 1), float(k >> 1)) + 0.5) * texel;
        float3 dir = fwd + (2.0 * centre.x - 1.0) * right + (2.0 * centre.y - 1.0) * up;
        float z = c.z + dot(g.xy, centre - c.xy);  // in this face: the plane's depth is linear in (s, t)
        if (any(centre < 0.0) || any(centre > 1.0)) {
            // past the edge: the neighbouring face's texel centre and the plane's depth along it there
            float3 f2, r2, u2;
            sk_cube_face_frame(dir, f2, r2, u2);
            float2 st = (float2(dot(dir, r2), dot(dir, u2)) / dot(dir, f2)) * 0.5 + 0.5;
            st = (min(floor(st * size), size - 1.0) + 0.5) / size;
            dir = f2 + (2.0 * st.x - 1.0) * r2 + (2.0 * st.y - 1.0) * u2;
            float t = nd / dot(n, dir);  // dir's component along f2 is 1: the plane point's major-axis distance
            if (t > 0.0 && t < 3.0e38) z = 0.5 * (zf - zg / t) + 0.5;
        }
        v += weight[k] * shadow_map.SampleCmpLevelZero(cmp, dir, clamp(z - eps, 0.0, 1.0));
    }
    return v;
}

// For filtered kernels (hlsl/pcf.hlsl): one texel of the plane's slope plus the precision margin
// (shadow_bias.hpp bias_auto_filtered). Subtract it from uvz.z (add with SK_REVERSED_Z).
float sk_auto_filtered_bias(float4 g, float2 texel_uv, float z, float depth_step) {
    return abs(g.x) * texel_uv.x + abs(g.y) * texel_uv.y + sk_auto_bias_epsilon(g, texel_uv, z, depth_step);
}
