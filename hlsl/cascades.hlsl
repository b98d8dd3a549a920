// shadowkit/hlsl/cascades.hlsl - cascaded shadow maps in HLSL: cascade selection, blend band, lookup in a Texture2DArray.
// stages: pixel (and any other: every compare is SampleCmpLevelZero)
//
// The HLSL twin of glsl/cascades.glsl: the same sk_ functions, arguments and results (up to 4
// cascades from shadowkit/cascades.hpp: split_near = CascadeFitResult::splits[0..3], split_far =
// splits[1..4], light_vp[i] = Cascade::view_proj, view_depth = -view-space z). The maps are one
// Texture2DArray<float>, layer i = cascade i, read through a SamplerComparisonState passed next to it
// (ComparisonFunc LESS_EQUAL; GREATER_EQUAL and a negative bias for reversed-Z light matrices; linear
// filter for the hardware 2x2; clamp addressing). glsl/cascades.glsl says the rest (acne and the
// normal offset, filtering, what is lit).
// Matrices: `column_major float4x4 light_vp[4]` in the constant buffer, GLM's data as it is, and
// mul(M, v) (hlsl/shadow_map.hlsl states the rule). Vulkan / Direct3D: build the cascades with
// ClipDepth::ZeroToOne and pass zero_to_one = true. The lookup matrix is the one the layer was drawn
// with when the map pass uses a plain viewport; with a negative-height viewport (or in Direct3D) pass
// flip_y * view_proj, flip_y = diag(1, -1, 1, 1) (docs/vulkan_and_direct3d.md).
// Filtering: include hlsl/pcf.hlsl BEFORE this file and sk_cascade_shadow_filtered runs its kernels
// in each cascade's layer (SK_CASCADE_KERNEL_*); the rotated Poisson kernel then needs the pixel
// position (SV_Position.xy), the last argument of the filtered functions.
// SDSM (sk_sdsm_*): the depth reduction's passes, each a pixel shader reading the previous level with
// Load (glsl/cascades.glsl says the passes and what cascades.hpp does with the result).
// Usage: float lit = sk_cascade_shadow(g_cascades, g_compare, g.light_vp, g.split_near, g.split_far, g.count,
//        world_pos, view_depth, 0.1, 0.0005, true);  // blend over the last 10% of each cascade
// Compiled in the tests by glslang's HLSL front end to SPIR-V and run on Vulkan; written for DXC
// (shader model 6.0) as well, but not compiled with it here (DXC is not packaged in Debian 12).
// MIT License. Copyright (c) shadowkit contributors.

// The first cascade whose far split is >= view_depth; -1 beyond the last one.
int sk_cascade_by_depth(float view_depth, float4 split_far, int count) {
    [unroll] for (int i = 0; i < 4; ++i) {
        if (i < count && view_depth <= split_far[i]) return i;
    }
    return -1;
}

// The first cascade whose bounding sphere holds world_pos; -1 if none.
int sk_cascade_by_sphere(float3 world_pos, float4 spheres[4], int count) {
    [unroll] for (int i = 0; i < 4; ++i) {
        float3 d = world_pos - spheres[i].xyz;
        if (i < count && dot(d, d) <= spheres[i].w * spheres[i].w) return i;
    }
    return -1;
}

// Weight of the next cascade: 0 until the last `band` fraction of [split_near, split_far], 1 at split_far.
float sk_cascade_blend(float view_depth, float split_near, float split_far, float band) {
    float start = split_far - saturate(band) * (split_far - split_near);
    return saturate((view_depth - start) / max(split_far - start, 1e-20));
}

// The cascades a point at view_depth reads: the first (-1 beyond the last split: lit), `second` the
// next inside the blend band (-1 outside it), `weight` its weight in lerp(first, second, weight).
int sk_cascade_pick(float view_depth, float4 split_near, float4 split_far, int count, float band, out int second,
                    out float weight) {
    second = -1;
    weight = 0.0;
    int i = sk_cascade_by_depth(view_depth, split_far, count);
    if (i < 0) return -1;
    float w = sk_cascade_blend(view_depth, split_near[i], split_far[i], band);
    if (w > 0.0 && i + 1 < count) {
        second = i + 1;
        weight = w;
    }
    return i;
}

// World position -> (u, v, depth) in [0,1] for one cascade.
float3 sk_cascade_coord(float4x4 light_view_proj, float3 world_pos, bool zero_to_one) {
    float4 h = mul(light_view_proj, float4(world_pos, 1.0));
    float3 ndc = h.xyz / h.w;
    return float3(ndc.xy * 0.5 + 0.5, zero_to_one ? ndc.z : ndc.z * 0.5 + 0.5);
}

// One cascade's compare lookup: 1 = lit, 0 = shadowed; outside the map: 1.
float sk_cascade_sample(Texture2DArray<float> maps, SamplerComparisonState cmp, float4x4 light_view_proj, int layer,
                        float3 world_pos, float bias_window, bool zero_to_one) {
    float3 c = sk_cascade_coord(light_view_proj, world_pos, zero_to_one);
    if (any(c.xy < 0.0) || any(c.xy > 1.0)) return 1.0;
    return maps.SampleCmpLevelZero(cmp, float3(c.xy, float(layer)), c.z - bias_window);
}

// 1 = lit, 0 = shadowed; blends with the next cascade inside the band.
float sk_cascade_shadow(Texture2DArray<float> maps, SamplerComparisonState cmp, float4x4 light_vp[4], float4 split_near,
                        float4 split_far, int count, float3 world_pos, float view_depth, float band, float bias_window,
                        bool zero_to_one) {
    int j;
    float w;
    int i = sk_cascade_pick(view_depth, split_near, split_far, count, band, j, w);
    if (i < 0) return 1.0;
    float s = sk_cascade_sample(maps, cmp, light_vp[i], i, world_pos, bias_window, zero_to_one);
    if (j >= 0) s = lerp(s, sk_cascade_sample(maps, cmp, light_vp[j], j, world_pos, bias_window, zero_to_one), w);
    return s;
}

// ---- SDSM depth reduction (glsl/cascades.glsl says the passes) --------------------------------------
// Each pass is a pixel shader over its target with dst_texel = int2(position.xy) (SV_Position); the
// depth buffer is read with Load (a Texture2D<float> view of it, no sampler), the levels are RG32F /
// RGBA32F render targets read the same way. Bit-exact min / max: no filtering anywhere.
static const float SK_SDSM_EMPTY_MIN = 2.0;   // a level texel that saw no receiver: (2, -1), outside [0, 1]
static const float SK_SDSM_EMPTY_MAX = -1.0;

// First level: (min, max) window depth over the block x block texels of `depth` starting at
// dst_texel * block (texels past the edge skipped), ignoring texels equal to background_depth.
float2 sk_sdsm_reduce_depth(Texture2D<float> depth, int2 dst_texel, int block, float background_depth) {
    uint width, height;
    depth.GetDimensions(width, height);
    int2 size = int2(width, height);
    float2 r = float2(SK_SDSM_EMPTY_MIN, SK_SDSM_EMPTY_MAX);
    for (int y = 0; y < block; ++y) {
        for (int x = 0; x < block; ++x) {
            int2 p = dst_texel * block + int2(x, y);
            if (p.x >= size.x || p.y >= size.y) continue;
            float d = depth.Load(int3(p, 0));
            if (d == background_depth) continue;
            r = float2(min(r.x, d), max(r.y, d));
        }
    }
    return r;
}

// Next levels: (min of .x, max of .y) over the block x block texels of an RG32F level.
float2 sk_sdsm_reduce_minmax(Texture2D<float2> level, int2 dst_texel, int block) {
    uint width, height;
    level.GetDimensions(width, height);
    int2 size = int2(width, height);
    float2 r = float2(SK_SDSM_EMPTY_MIN, SK_SDSM_EMPTY_MAX);
    for (int y = 0; y < block; ++y) {
        for (int x = 0; x < block; ++x) {
            int2 p = dst_texel * block + int2(x, y);
            if (p.x >= size.x || p.y >= size.y) continue;
            float2 m = level.Load(int3(p, 0));
            r = float2(min(r.x, m.x), max(r.y, m.y));
        }
    }
    return r;
}

// Second reduction (SDSM sec. 3.2, optional): each cascade's light-space x/y bounds of its receivers
// (glsl/cascades.glsl states the arguments). bounds[i] = (x0, y0, x1, y1); an empty cascade keeps
// (SK_SDSM_EMPTY_BOUND, SK_SDSM_EMPTY_BOUND, -SK_SDSM_EMPTY_BOUND, -SK_SDSM_EMPTY_BOUND).
static const float SK_SDSM_EMPTY_BOUND = 3.0e38;

void sk_sdsm_reduce_bounds(Texture2D<float> depth, int2 dst_texel, int block, float background_depth,
                           float4x4 clip_to_world, float4x4 world_to_view, float4x4 world_to_light, float4 split_far,
                           int count, bool zero_to_one, out float4 bounds[4]) {
    [unroll] for (int i = 0; i < 4; ++i)
        bounds[i] = float4(SK_SDSM_EMPTY_BOUND, SK_SDSM_EMPTY_BOUND, -SK_SDSM_EMPTY_BOUND, -SK_SDSM_EMPTY_BOUND);
    uint width, height;
    depth.GetDimensions(width, height);
    int2 size = int2(width, height);
    for (int y = 0; y < block; ++y) {
        for (int x = 0; x < block; ++x) {
            int2 p = dst_texel * block + int2(x, y);
            if (p.x >= size.x || p.y >= size.y) continue;
            float d = depth.Load(int3(p, 0));
            if (d == background_depth) continue;
            float4 ndc = float4((float2(p) + 0.5) / float2(size) * 2.0 - 1.0, zero_to_one ? d : d * 2.0 - 1.0, 1.0);
            float4 h = mul(clip_to_world, ndc);
            float4 wp = float4(h.xyz / h.w, 1.0);
            int c = sk_cascade_by_depth(-mul(world_to_view, wp).z, split_far, count);
            if (c < 0) c = count - 1;  // beyond the last split (a depth buffer of a lagging camera): the last
            float2 l = mul(world_to_light, wp).xy;
            [unroll] for (int k = 0; k < 4; ++k)
                if (k == c) bounds[k] = float4(min(bounds[k].xy, l), max(bounds[k].zw, l));
        }
    }
}

// Next levels of the bounds: (min of .xy, max of .zw) over the block x block texels of one cascade's level.
float4 sk_sdsm_reduce_bounds_level(Texture2D<float4> level, int2 dst_texel, int block) {
    uint width, height;
    level.GetDimensions(width, height);
    int2 size = int2(width, height);
    float4 r = float4(SK_SDSM_EMPTY_BOUND, SK_SDSM_EMPTY_BOUND, -SK_SDSM_EMPTY_BOUND, -SK_SDSM_EMPTY_BOUND);
    for (int y = 0; y < block; ++y) {
        for (int x = 0; x < block; ++x) {
            int2 p = dst_texel * block + int2(x, y);
            if (p.x >= size.x || p.y >= size.y) continue;
            float4 b = level.Load(int3(p, 0));
            r = float4(min(r.xy, b.xy), max(r.zw, b.zw));
        }
    }
    return r;
}

#ifdef SK_PCF_HLSL
// ---- filtered cascades (needs hlsl/pcf.hlsl included before this file) --------------------------
static const int SK_CASCADE_KERNEL_HARD = 0;             // sk_pcf_hard: the hardware 2x2
static const int SK_CASCADE_KERNEL_BOX = 1;              // sk_pcf_box, radius_texels
static const int SK_CASCADE_KERNEL_TENT = 2;             // sk_pcf_tent, radius_texels
static const int SK_CASCADE_KERNEL_POISSON = 3;          // sk_pcf_poisson, radius_texels texels, `taps`, `angle`
static const int SK_CASCADE_KERNEL_POISSON_ROTATED = 4;  // sk_pcf_poisson_rotated (angle from `pixel`'s noise)

// One cascade read with a pcf.hlsl kernel (no receiver plane; radius in texels of that cascade).
float sk_cascade_sample_filtered(Texture2DArray<float> maps, SamplerComparisonState cmp, float4x4 light_view_proj,
                                 int layer, float3 world_pos, float bias_window, bool zero_to_one, int kernel, int radius_texels,
                                 int taps, float angle, float2 pixel) {
    float3 c = sk_cascade_coord(light_view_proj, world_pos, zero_to_one);
    if (any(c.xy < 0.0) || any(c.xy > 1.0)) return 1.0;
    float3 uvz = float3(c.xy, c.z - bias_window);
    float l = float(layer);
    float width, height, layers;
    maps.GetDimensions(width, height, layers);
    float radius_uv = float(radius_texels) / width;
    float2 g = float2(0.0, 0.0);
    if (kernel == SK_CASCADE_KERNEL_BOX) return sk_pcf_box(maps, cmp, l, uvz, g, radius_texels);
    if (kernel == SK_CASCADE_KERNEL_TENT) return sk_pcf_tent(maps, cmp, l, uvz, g, radius_texels);
    if (kernel == SK_CASCADE_KERNEL_POISSON) return sk_pcf_poisson(maps, cmp, l, uvz, g, radius_uv, taps, angle);
    if (kernel == SK_CASCADE_KERNEL_POISSON_ROTATED) return sk_pcf_poisson_rotated(maps, cmp, l, uvz, g, radius_uv, taps, pixel);
    return sk_pcf_hard(maps, cmp, l, uvz);
}

// sk_cascade_shadow with a pcf.hlsl kernel in each cascade's layer, blended over the band.
float sk_cascade_shadow_filtered(Texture2DArray<float> maps, SamplerComparisonState cmp, float4x4 light_vp[4],
                                 float4 split_near, float4 split_far, int count, float3 world_pos, float view_depth,
                                 float band, float bias_window, bool zero_to_one, int kernel, int radius_texels, int taps,
                                 float angle, float2 pixel) {
    int j;
    float w;
    int i = sk_cascade_pick(view_depth, split_near, split_far, count, band, j, w);
    if (i < 0) return 1.0;
    float s = sk_cascade_sample_filtered(maps, cmp, light_vp[i], i, world_pos, bias_window, zero_to_one, kernel, radius_texels,
                                         taps, angle, pixel);
    if (j >= 0)
        s = lerp(s, sk_cascade_sample_filtered(maps, cmp, light_vp[j], j, world_pos, bias_window, zero_to_one, kernel,
                                               radius_texels, taps, angle, pixel), w);
    return s;
}
#endif
