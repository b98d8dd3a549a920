// shadowkit/hlsl/virtual_shadow_map.hlsl - virtual shadow maps in HLSL: the page-marking pass, the lookup through the page table (automatic bias, PCF across pages, coarser-level fallback) and a debug view
// stages: pixel, compute (sk_vsm_mark writes a UAV: a pixel shader needs Vulkan's fragmentStoresAndAtomics)
//
// The HLSL twin of glsl/virtual_shadow_map.glsl: the same sk_ functions, arguments and results;
// glsl/virtual_shadow_map.glsl says what each input means and the render state of the page passes.
// What differs:
// - The two SSBOs are byte-address buffers, bound where the GLSL binds them:
//   sk_vsm_data (ByteAddressBuffer, read-only) at [[vk::binding(SK_VSM_DATA_BINDING, 0)]] (default 0)
//   and register(SK_VSM_DATA_REGISTER) (default t0): vsm_gpu_block(...) uploaded word for word, the
//   std430 layout of GLSL's SkVsmData (16 mat4 at byte 0, 16 int4 at 1024, layout at 1280, flags at
//   1296, scale at 1312, the page table from 1328);
//   sk_vsm_request_mask (RWByteAddressBuffer, cleared to 0) at [[vk::binding(SK_VSM_MASK_BINDING, 0)]]
//   (default 1) and register(SK_VSM_MASK_REGISTER) (default u1). Define any of them before this file.
// - GLSL's buffer members are read by the accessors sk_vsm_world_to_uv(level), sk_vsm_origin(level),
//   sk_vsm_layout(), sk_vsm_flags(), sk_vsm_scale() and sk_vsm_table(index) (HLSL-only functions).
//   GLM's column-major matrices are read as columns and assembled with transpose: mul(M, v) as everywhere.
// - The atlas is a Texture2D<float> read with Load (no sampler; GLSL's texelFetch).
// Usage:
//   int level = sk_vsm_level_for_footprint(pixel_world_size, 0.0);
//   sk_vsm_mark(rel_pos, level, 0);                                   // marking pass
//   float lit = sk_vsm_visibility(g_atlas, rel_pos, normal, level, 0, 0.0);   // lookup pass
//   float3 debug = sk_vsm_debug_color(rel_pos, level);
// Compiled in the tests by glslang's HLSL front end to SPIR-V and run on Vulkan (marking and lookup,
// tests/vulkan/test_vk_virtual_shadow_map.cpp); written for DXC (shader model 6.0) as well, but DXC
// was not run (it is not packaged in Debian 12).
// MIT License. Copyright (c) shadowkit contributors.

#ifndef SK_VSM_DATA_BINDING
#define SK_VSM_DATA_BINDING 0
#endif
#ifndef SK_VSM_DATA_REGISTER
#define SK_VSM_DATA_REGISTER t0
#endif
#ifndef SK_VSM_MASK_BINDING
#define SK_VSM_MASK_BINDING 1
#endif
#ifndef SK_VSM_MASK_REGISTER
#define SK_VSM_MASK_REGISTER u1
#endif
// virtual_shadow_map.hpp's kVsmMaxLevels, kVsmPageValid, kVsmSlotMask
#define SK_VSM_MAX_LEVELS 16
#define SK_VSM_PAGE_VALID 0x80000000u
#define SK_VSM_SLOT_MASK 0x3FFFFFFFu

[[vk::binding(SK_VSM_DATA_BINDING, 0)]] ByteAddressBuffer sk_vsm_data : register(SK_VSM_DATA_REGISTER);
[[vk::binding(SK_VSM_MASK_BINDING, 0)]] RWByteAddressBuffer sk_vsm_request_mask : register(SK_VSM_MASK_REGISTER);

// Accessors of the data block (GLSL reads these as buffer members).
float4x4 sk_vsm_world_to_uv(int level) {  // (world - anchor) -> (u, v, clip z, w)
    uint o = uint(level) * 64u;
    return transpose(float4x4(asfloat(sk_vsm_data.Load4(o)), asfloat(sk_vsm_data.Load4(o + 16u)),
                              asfloat(sk_vsm_data.Load4(o + 32u)), asfloat(sk_vsm_data.Load4(o + 48u))));
}
int4 sk_vsm_origin(int level) { return asint(sk_vsm_data.Load4(1024u + uint(level) * 16u)); }  // origin_mod_x, _y
int4 sk_vsm_layout() { return asint(sk_vsm_data.Load4(1280u)); }  // level_count, pages_per_side, page_texels, pool_columns
int4 sk_vsm_flags() { return asint(sk_vsm_data.Load4(1296u)); }   // zero_to_one, reversed_z, directional, 0
float4 sk_vsm_scale() { return asfloat(sk_vsm_data.Load4(1312u)); }  // level 0's texel in world units
uint sk_vsm_table(int index) { return sk_vsm_data.Load(1328u + uint(index) * 4u); }

// The coarsest level whose texels are no larger than `footprint_world`, clamped to [0, level_count).
int sk_vsm_level_for_footprint(float footprint_world, float lod_bias) {
    float texel0 = sk_vsm_scale().x;
    if (!(texel0 > 0.0) || !(footprint_world > 0.0)) return 0;
    float l = floor(log2(footprint_world / texel0) + lod_bias);
    return int(clamp(l, 0.0, float(sk_vsm_layout().x - 1)));
}

// Window coordinates of rel_pos on `level`: (u, v) in [0, 1), window depth, clip w.
float4 sk_vsm_coord(int level, float3 rel_pos) {
    float4 h = mul(sk_vsm_world_to_uv(level), float4(rel_pos, 1.0));
    float3 c = h.xyz / h.w;
    return float4(c.xy, sk_vsm_flags().x != 0 ? c.z : c.z * 0.5 + 0.5, h.w);
}

// The page-table entry of page `page` (on the window) of `level`: toroidal addressing.
uint sk_vsm_entry(int level, int2 page) {
    int n = sk_vsm_layout().y;
    int2 t = (page + sk_vsm_origin(level).xy) % n;
    return sk_vsm_table((level * n + t.y) * n + t.x);
}

// The kernel's texel rectangle: first texel `i0`, bilinear fraction `w`; false when a tap leaves the window.
bool sk_vsm_kernel(float2 uv, int size, int radius, out int2 i0, out float2 w) {
    float2 f = uv * float(size) - 0.5;
    float2 b = floor(f);
    w = f - b;
    i0 = int2(b) - radius;
    return all(i0 >= 0) && all(i0 + 2 * radius + 1 < size);
}

// Marking: from `level` up, the first level whose window holds the kernel's texels; sets the bits of
// the pages under them (InterlockedOr after a plain read). Returns the level marked, -1 outside.
int sk_vsm_mark(float3 rel_pos, int level, int radius) {
    int4 lay = sk_vsm_layout();
    int n = lay.y, pt = lay.z;
    for (int l = max(level, 0); l < lay.x; ++l) {
        float4 c = sk_vsm_coord(l, rel_pos);
        int2 i0;
        float2 w;
        if (!(c.w > 0.0) || !sk_vsm_kernel(c.xy, n * pt, radius, i0, w)) continue;
        int2 p0 = i0 / pt, p1 = (i0 + 2 * radius + 1) / pt;
        for (int y = p0.y; y <= p1.y; ++y)
            for (int x = p0.x; x <= p1.x; ++x) {
                uint bit = uint((l * n + y) * n + x);
                uint b = 1u << (bit & 31u);
                uint address = (bit >> 5u) * 4u;
                if ((sk_vsm_request_mask.Load(address) & b) == 0u) sk_vsm_request_mask.InterlockedOr(address, b);
            }
        return l;
    }
    return -1;
}

// The receiver plane's window-depth gradient (dz/du, dz/dv) in level uv units (Isidoro 2006); .z the
// solve's conditioning (0: edge-on), .w the window depth of 4 float ulps of rel_pos.
// m[r][c] is GLSL's m[c][r]: row 3 is (m[3][0], m[3][1], m[3][2]).
float4 sk_vsm_plane_gradient(float4x4 m, float3 rel_pos, float3 normal) {
    float4 c = mul(m, float4(rel_pos, 1.0));
    float3 q = c.xyz / c.w;
    float3 rw = m[3].xyz;
    float3 ju = (m[0].xyz - q.x * rw) / c.w;
    float3 jv = (m[1].xyz - q.y * rw) / c.w;
    float3 jz = (m[2].xyz - q.z * rw) / c.w;
    float zs = sk_vsm_flags().x != 0 ? 1.0 : 0.5;
    float3 ap = abs(rel_pos);
    float3 ajz = abs(jz);
    float pos_err = 4.76837158e-7 * (ap.x + ap.y + ap.z) * (ajz.x + ajz.y + ajz.z) * zs;
    float3 n = normalize(normal);
    float3 an = abs(n);
    float3 axis = an.x <= an.y && an.x <= an.z ? float3(1.0, 0.0, 0.0) : (an.y <= an.z ? float3(0.0, 1.0, 0.0) : float3(0.0, 0.0, 1.0));
    float3 t1 = normalize(cross(n, axis));
    float3 t2 = cross(n, t1);
    float3 s1 = float3(dot(ju, t1), dot(jv, t1), zs * dot(jz, t1));
    float3 s2 = float3(dot(ju, t2), dot(jv, t2), zs * dot(jz, t2));
    float det = s1.x * s2.y - s1.y * s2.x;
    float scale = (abs(s1.x) + abs(s1.y)) * (abs(s2.x) + abs(s2.y));
    float cond = scale > 0.0 ? abs(det) / scale : 0.0;
    if (!(cond > 1e-4)) return float4(0.0, 0.0, 0.0, pos_err);
    return float4((s2.y * s1.z - s1.y * s2.z) / det, (s1.x * s2.z - s2.x * s1.z) / det, cond, pos_err);
}

// The automatic bias's margin (shadow_bias.hpp bias_auto_epsilon).
float sk_vsm_bias_epsilon(float4 g, float texel_uv, float z, float depth_step) {
    float float_term = sk_vsm_flags().y != 0 ? 4.76837158e-7 * abs(z) + 1.17549435e-38 : 4.76837158e-7 * (1.0 + abs(z));
    float plane = (abs(g.x) + abs(g.y)) * texel_uv;
    return 2.0 * max(depth_step, 0.0) + float_term + 2.0 * g.w + plane * (0.125 + 9.53674316e-7 + 2.38418579e-7 / max(g.z, 1e-4));
}

// The physical texel of virtual texel t of `level`, or (-1, -1) when its page is not current.
int2 sk_vsm_physical(int level, int2 t) {
    int4 lay = sk_vsm_layout();
    int pt = lay.z, cols = lay.w;
    uint e = sk_vsm_entry(level, t / pt);
    if ((e & SK_VSM_PAGE_VALID) == 0u) return int2(-1, -1);
    int slot = int(e & SK_VSM_SLOT_MASK);
    return int2(slot % cols, slot / cols) * pt + t % pt;
}

// The lookup on one level: true when the page holding the point is current there, with the lit
// fraction in `v` (glsl/virtual_shadow_map.glsl says how the taps read neighbour pages).
bool sk_vsm_filter_level(Texture2D<float> atlas, int l, float4 c, float4 g, int radius, float depth_step, out float v) {
    int4 lay = sk_vsm_layout();
    int pt = lay.z, size = lay.y * pt;
    bool reversed = sk_vsm_flags().y != 0;
    int2 i0;
    float2 w;
    v = 0.0;
    if (!(c.w > 0.0) || !sk_vsm_kernel(c.xy, size, radius, i0, w)) return false;
    int2 home = int2(c.xy * float(size)) / pt;
    if (sk_vsm_physical(l, home * pt).x < 0) return false;
    float eps = sk_vsm_bias_epsilon(g, 1.0 / float(size), c.z, depth_step);
    int taps = 2 * radius + 2;
    float sum = 0.0;
    for (int j = 0; j < taps; ++j)
        for (int i = 0; i < taps; ++i) {
            int2 t = i0 + int2(i, j);
            int2 p = sk_vsm_physical(l, t);
            if (p.x < 0) {
                t = clamp(t, home * pt, home * pt + pt - 1);
                p = sk_vsm_physical(l, t);
            }
            float2 centre = (float2(t) + 0.5) / float(size);
            float zp = c.z + dot(g.xy, centre - c.xy);
            float d = atlas.Load(int3(p, 0));
            float wx = i == 0 ? 1.0 - w.x : (i == taps - 1 ? w.x : 1.0);
            float wy = j == 0 ? 1.0 - w.y : (j == taps - 1 ? w.y : 1.0);
            bool lit = reversed ? clamp(zp + eps, 0.0, 1.0) >= d : clamp(zp - eps, 0.0, 1.0) <= d;
            sum += lit ? wx * wy : 0.0;
        }
    float box = float(2 * radius + 1);
    v = sum / (box * box);
    return true;
}

// Lit fraction of rel_pos from `level` up (glsl/virtual_shadow_map.glsl: the fallback); `used_level`
// the level read, -1 outside every window (1.0) or when no level has the pages (0.0). Edge-on: lit.
float sk_vsm_visibility_level(Texture2D<float> atlas, float3 rel_pos, float3 normal, int level, int radius,
                              float depth_step, out int used_level) {
    used_level = -1;
    bool inside = false;
    int4 lay = sk_vsm_layout();
    for (int l = max(level, 0); l < lay.x; ++l) {
        float4 c = sk_vsm_coord(l, rel_pos);
        int2 i0;
        float2 w;
        if (!(c.w > 0.0) || !sk_vsm_kernel(c.xy, lay.y * lay.z, radius, i0, w)) continue;
        inside = true;
        float4 g = sk_vsm_plane_gradient(sk_vsm_world_to_uv(l), rel_pos, normal);
        if (g.z == 0.0) {
            used_level = l;
            return 1.0;
        }
        float v;
        if (sk_vsm_filter_level(atlas, l, c, g, radius, depth_step, v)) {
            used_level = l;
            return v;
        }
    }
    return inside ? 0.0 : 1.0;
}

float sk_vsm_visibility(Texture2D<float> atlas, float3 rel_pos, float3 normal, int level, int radius, float depth_step) {
    int used;
    return sk_vsm_visibility_level(atlas, rel_pos, normal, level, radius, depth_step, used);
}

// Debug view: a hue per level (repeating every 6), page borders dark, white where no level has the
// page, grey outside every window.
float3 sk_vsm_debug_color(float3 rel_pos, int level) {
    int4 lay = sk_vsm_layout();
    int n = lay.y, pt = lay.z;
    bool inside = false;
    for (int l = max(level, 0); l < lay.x; ++l) {
        float4 c = sk_vsm_coord(l, rel_pos);
        if (!(c.w > 0.0) || any(c.xy < 0.0) || any(c.xy >= 1.0)) continue;
        inside = true;
        int2 t = int2(c.xy * float(n * pt));
        if ((sk_vsm_entry(l, t / pt) & SK_VSM_PAGE_VALID) == 0u) continue;
        float h = float(l % 6) / 6.0;
        float3 hue = saturate(abs(frac(h + float3(0.0, 2.0 / 3.0, 1.0 / 3.0)) * 6.0 - 3.0) - 1.0);
        int2 in_page = t % pt;
        bool border = any(in_page == 0) || any(in_page == pt - 1);
        return lerp(float3(0.25, 0.25, 0.25), hue, 0.75) * (border ? 0.35 : 1.0);
    }
    return inside ? float3(1.0, 1.0, 1.0) : float3(0.5, 0.5, 0.5);
}
