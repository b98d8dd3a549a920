// shadowkit/glsl/cascades.glsl - cascaded shadow maps: cascade selection, blend band, lookup, SDSM reduction.
// versions: 330, 450
// stages: fragment
//
// Inputs (from shadowkit/cascades.hpp, up to 4 cascades):
//   split_near      vec4   near view depth of cascades 0..3 (CascadeFitResult::splits[0..3])
//   split_far       vec4   far view depth of cascades 0..3 (CascadeFitResult::splits[1..4])
//   spheres[4]      vec4   world bounding spheres (Cascade::sphere) for selection by sphere
//   light_vp[4]     mat4   Cascade::view_proj
//   shadow_maps     sampler2DArrayShadow, layer i = cascade i
//   view_depth      float  positive distance along the camera's view direction (-view-space z)
//   zero_to_one     bool   true if the matrices were built with ClipDepth::ZeroToOne
// No function takes a light: the light (CascadeInput::light_position, w = 0, xyz toward the light)
// is baked into the matrices.
// GL state: shadow_maps is a GL_TEXTURE_2D_ARRAY depth texture with GL_TEXTURE_COMPARE_MODE =
// GL_COMPARE_REF_TO_TEXTURE, GL_TEXTURE_COMPARE_FUNC = GL_LEQUAL (GL_GEQUAL and a negative bias for
// reversed-Z light matrices), GL_LINEAR filtering for a 2x2 hardware PCF (GL_NEAREST: hard), wrap
// GL_CLAMP_TO_EDGE. Render cascade i into layer i (glFramebufferTextureLayer) with its view_proj,
// depth test GL_LESS, depth writes on, no blending. The matrices are an ordinary right-handed view
// and projection: a triangle counter-clockwise seen from the light is counter-clockwise in the map,
// so back-face culling (or front-face culling against acne) works with glFrontFace(GL_CCW).
// Usage: float lit = sk_cascade_shadow(shadow_maps, light_vp, split_near, split_far, count, world_pos,
//        view_depth, 0.1, 0.0005, false);  // blend over the last 10% of each cascade
// Acne: the constant bias alone leaves acne where a cascade's texels are large on the receiver (256^2
// maps: 76-83% of the lit pixels right, docs/composition.md). Offset world_pos by one texel along the
// normal first (Cascade::texel_world_size of the cascade sk_cascade_by_depth selects; inside the blend
// band the next one's), keeping view_depth unchanged: 99.7-100% (docs/cascades.md).
// Filtering: paste glsl/pcf.glsl BEFORE this snippet and sk_cascade_shadow_filtered runs a pcf.glsl
// kernel (box, tent, Poisson, rotated Poisson: SK_CASCADE_KERNEL_*) in each cascade's layer, blended
// over the band like sk_cascade_shadow. Any other filter (pcss.glsl's array overloads, a receiver
// plane, the automatic bias) composes through sk_cascade_pick: it returns the cascade, the next one
// inside the band and the blend weight; read each with the kernel and mix (docs/cascades.md).
// Points outside the selected cascade's map (uv outside [0,1]) and beyond the last split are lit.
// SDSM reduction (sample distribution shadow maps, Lauritzen et al. 2011): the min and max window
// depth of the camera depth buffer's non-background pixels, in full-screen passes into RG32F levels
// (no compute stage needed: GLSL 3.30 too). Pass 1 draws a ceil(W / block) x ceil(H / block) RG32F
// target with sk_sdsm_reduce_depth(depth, ivec2(gl_FragCoord.xy), block, background) (depth: the
// camera's depth texture as sampler2D, compare mode off, GL_NEAREST; background: its clear value,
// 1.0, or 0.0 for reversed-Z); each next pass draws a level block times smaller with
// sk_sdsm_reduce_minmax(previous level, ivec2(gl_FragCoord.xy), block) until it is 1x1; read that
// texel back (or bind it). .x = min, .y = max window depth; (SK_SDSM_EMPTY_MIN, SK_SDSM_EMPTY_MAX)
// when no pixel was a receiver. cascades.hpp's cascade_sdsm_view_range turns it into view depths and
// cascade_sdsm_fit fits the cascades to it. GL state: depth test and blending off, viewport = target.
// Optionally a second reduction, sk_sdsm_reduce_bounds then sk_sdsm_reduce_bounds_level (four RGBA32F
// targets per level, one per cascade), gives each cascade's receiver bounds in light space
// (CascadeSdsmInput::receiver_bounds): tighter maps than the view slices' boxes.
// MIT License. Copyright (c) shadowkit contributors.

// The first cascade whose far split is >= view_depth; -1 beyond the last one.
int sk_cascade_by_depth(float view_depth, vec4 split_far, int count)
{
    for (int i = 0; i < 4; ++i) {
        if (i < count && view_depth <= split_far[i]) return i;
    }
    return -1;
}

// The first cascade whose bounding sphere holds world_pos; -1 if none.
int sk_cascade_by_sphere(vec3 world_pos, vec4 spheres[4], int count)
{
    for (int i = 0; i < 4; ++i) {
        vec3 d = world_pos - spheres[i].xyz;
        if (i < count && dot(d, d) <= spheres[i].w * spheres[i].w) return i;
    }
    return -1;
}

// Weight of the next cascade: 0 until the last `band` fraction of [split_near, split_far], 1 at split_far.
float sk_cascade_blend(float view_depth, float split_near, float split_far, float band)
{
    float start = split_far - clamp(band, 0.0, 1.0) * (split_far - split_near);
    return clamp((view_depth - start) / max(split_far - start, 1e-20), 0.0, 1.0);
}

// The cascades a point at view_depth reads: returns the first (-1 beyond the last split: lit);
// `second` = the next cascade inside the blend band (-1 outside it or after the last cascade), `weight`
// its weight in mix(first's value, second's value, weight) (0 when second is -1).
int sk_cascade_pick(float view_depth, vec4 split_near, vec4 split_far, int count, float band, out int second,
                    out float weight)
{
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

// World position -> (u, v, depth) in [0,1] for one cascade (orthographic: w == 1, divide kept).
vec3 sk_cascade_coord(mat4 light_view_proj, vec3 world_pos, bool zero_to_one)
{
    vec4 h = light_view_proj * vec4(world_pos, 1.0);
    vec3 ndc = h.xyz / h.w;
    return vec3(ndc.xy * 0.5 + 0.5, zero_to_one ? ndc.z : ndc.z * 0.5 + 0.5);
}

// One cascade's compare lookup: 1 = lit, 0 = shadowed; outside the map: 1.
float sk_cascade_sample(sampler2DArrayShadow maps, mat4 light_view_proj, int layer, vec3 world_pos, float bias_window,
                        bool zero_to_one)
{
    vec3 c = sk_cascade_coord(light_view_proj, world_pos, zero_to_one);
    if (any(lessThan(c.xy, vec2(0.0))) || any(greaterThan(c.xy, vec2(1.0)))) return 1.0;
    return texture(maps, vec4(c.xy, float(layer), c.z - bias_window));
}

// 1 = lit, 0 = shadowed; blends with the next cascade inside the band.
float sk_cascade_shadow(sampler2DArrayShadow maps, mat4 light_vp[4], vec4 split_near, vec4 split_far, int count,
                        vec3 world_pos, float view_depth, float band, float bias_window, bool zero_to_one)
{
    int j;
    float w;
    int i = sk_cascade_pick(view_depth, split_near, split_far, count, band, j, w);
    if (i < 0) return 1.0;
    float s = sk_cascade_sample(maps, light_vp[i], i, world_pos, bias_window, zero_to_one);
    if (j >= 0) s = mix(s, sk_cascade_sample(maps, light_vp[j], j, world_pos, bias_window, zero_to_one), w);
    return s;
}

// ---- SDSM depth reduction ---------------------------------------------------------------------
const float SK_SDSM_EMPTY_MIN = 2.0;   // a level texel that saw no receiver: (2, -1), outside [0, 1]
const float SK_SDSM_EMPTY_MAX = -1.0;

// First level: (min, max) window depth over the block x block texels of `depth` starting at
// dst_texel * block (texels past the edge skipped), ignoring texels equal to background_depth.
vec2 sk_sdsm_reduce_depth(sampler2D depth, ivec2 dst_texel, int block, float background_depth)
{
    ivec2 size = textureSize(depth, 0);
    vec2 r = vec2(SK_SDSM_EMPTY_MIN, SK_SDSM_EMPTY_MAX);
    for (int y = 0; y < block; ++y) {
        for (int x = 0; x < block; ++x) {
            ivec2 p = dst_texel * block + ivec2(x, y);
            if (p.x >= size.x || p.y >= size.y) continue;
            float d = texelFetch(depth, p, 0).r;
            if (d == background_depth) continue;
            r = vec2(min(r.x, d), max(r.y, d));
        }
    }
    return r;
}

// Next levels: (min of .x, max of .y) over the block x block texels of an RG32F level.
vec2 sk_sdsm_reduce_minmax(sampler2D level, ivec2 dst_texel, int block)
{
    ivec2 size = textureSize(level, 0);
    vec2 r = vec2(SK_SDSM_EMPTY_MIN, SK_SDSM_EMPTY_MAX);
    for (int y = 0; y < block; ++y) {
        for (int x = 0; x < block; ++x) {
            ivec2 p = dst_texel * block + ivec2(x, y);
            if (p.x >= size.x || p.y >= size.y) continue;
            vec2 m = texelFetch(level, p, 0).xy;
            r = vec2(min(r.x, m.x), max(r.y, m.y));
        }
    }
    return r;
}

// Second reduction (SDSM sec. 3.2, optional): each cascade's light-space x/y bounds of the receivers it
// serves, after cascade_sdsm_splits gave this frame's splits. First level: over the block x block
// texels of `depth` from dst_texel * block, each non-background texel's world point (pixel center,
// clip_to_world = inverse(camera proj * view) of the depth buffer's camera, zero_to_one its clip
// depth) goes to the cascade its view depth (world_to_view, the fit camera's view) selects
// (sk_cascade_by_depth with split_far, up to 4 cascades; beyond the last split: the last, so a depth
// buffer of a camera a little off the fit's stays covered) and extends bounds[i] = (x0, y0, x1, y1) in
// world_to_light's x/y (cascades.hpp's cascade_sdsm_light_view). A cascade without a receiver keeps
// (SK_SDSM_EMPTY_BOUND, SK_SDSM_EMPTY_BOUND, -SK_SDSM_EMPTY_BOUND, -SK_SDSM_EMPTY_BOUND): x0 > x1.
// Next levels: sk_sdsm_reduce_bounds_level on each cascade's RGBA32F level.
const float SK_SDSM_EMPTY_BOUND = 3.0e38;

void sk_sdsm_reduce_bounds(sampler2D depth, ivec2 dst_texel, int block, float background_depth, mat4 clip_to_world,
                           mat4 world_to_view, mat4 world_to_light, vec4 split_far, int count, bool zero_to_one,
                           out vec4 bounds[4])
{
    for (int i = 0; i < 4; ++i) bounds[i] = vec4(vec2(SK_SDSM_EMPTY_BOUND), vec2(-SK_SDSM_EMPTY_BOUND));
    ivec2 size = textureSize(depth, 0);
    for (int y = 0; y < block; ++y) {
        for (int x = 0; x < block; ++x) {
            ivec2 p = dst_texel * block + ivec2(x, y);
            if (p.x >= size.x || p.y >= size.y) continue;
            float d = texelFetch(depth, p, 0).r;
            if (d == background_depth) continue;
            vec4 ndc = vec4((vec2(p) + 0.5) / vec2(size) * 2.0 - 1.0, zero_to_one ? d : d * 2.0 - 1.0, 1.0);
            vec4 h = clip_to_world * ndc;
            vec4 w = vec4(h.xyz / h.w, 1.0);
            int i = sk_cascade_by_depth(-(world_to_view * w).z, split_far, count);
            if (i < 0) i = count - 1;  // beyond the last split (a depth buffer of a lagging camera): the last
            vec2 l = (world_to_light * w).xy;
            for (int k = 0; k < 4; ++k)
                if (k == i) bounds[k] = vec4(min(bounds[k].xy, l), max(bounds[k].zw, l));
        }
    }
}

// Next levels of the bounds: (min of .xy, max of .zw) over the block x block texels of one cascade's level.
vec4 sk_sdsm_reduce_bounds_level(sampler2D level, ivec2 dst_texel, int block)
{
    ivec2 size = textureSize(level, 0);
    vec4 r = vec4(vec2(SK_SDSM_EMPTY_BOUND), vec2(-SK_SDSM_EMPTY_BOUND));
    for (int y = 0; y < block; ++y) {
        for (int x = 0; x < block; ++x) {
            ivec2 p = dst_texel * block + ivec2(x, y);
            if (p.x >= size.x || p.y >= size.y) continue;
            vec4 b = texelFetch(level, p, 0);
            r = vec4(min(r.xy, b.xy), max(r.zw, b.zw));
        }
    }
    return r;
}

#ifdef SK_PCF_GLSL
// ---- filtered cascades (needs glsl/pcf.glsl pasted before this snippet) --------------------------
const int SK_CASCADE_KERNEL_HARD = 0;             // sk_pcf_hard: the hardware 2x2
const int SK_CASCADE_KERNEL_BOX = 1;              // sk_pcf_box, radius_texels
const int SK_CASCADE_KERNEL_TENT = 2;             // sk_pcf_tent, radius_texels
const int SK_CASCADE_KERNEL_POISSON = 3;          // sk_pcf_poisson, radius_texels texels, `taps`, `angle`
const int SK_CASCADE_KERNEL_POISSON_ROTATED = 4;  // sk_pcf_poisson_rotated (angle from the pixel's noise)

// One cascade read with a pcf.glsl kernel: uvz = sk_cascade_coord minus bias, no receiver plane
// (screen derivatives are not uniform across the band's branches; compose through sk_cascade_pick
// for one). The radius is in texels of that cascade (its world width grows with the cascade).
float sk_cascade_sample_filtered(sampler2DArrayShadow maps, mat4 light_view_proj, int layer, vec3 world_pos, float bias_window,
                                 bool zero_to_one, int kernel, int radius_texels, int taps, float angle)
{
    vec3 c = sk_cascade_coord(light_view_proj, world_pos, zero_to_one);
    if (any(lessThan(c.xy, vec2(0.0))) || any(greaterThan(c.xy, vec2(1.0)))) return 1.0;
    vec3 uvz = vec3(c.xy, c.z - bias_window);
    float l = float(layer);
    float radius_uv = float(radius_texels) / float(textureSize(maps, 0).x);
    if (kernel == SK_CASCADE_KERNEL_BOX) return sk_pcf_box(maps, l, uvz, vec2(0.0), radius_texels);
    if (kernel == SK_CASCADE_KERNEL_TENT) return sk_pcf_tent(maps, l, uvz, vec2(0.0), radius_texels);
    if (kernel == SK_CASCADE_KERNEL_POISSON) return sk_pcf_poisson(maps, l, uvz, vec2(0.0), radius_uv, taps, angle);
    if (kernel == SK_CASCADE_KERNEL_POISSON_ROTATED) return sk_pcf_poisson_rotated(maps, l, uvz, vec2(0.0), radius_uv, taps);
    return sk_pcf_hard(maps, l, uvz);
}

// sk_cascade_shadow with a pcf.glsl kernel in each cascade's layer, blended over the band.
float sk_cascade_shadow_filtered(sampler2DArrayShadow maps, mat4 light_vp[4], vec4 split_near, vec4 split_far, int count,
                                 vec3 world_pos, float view_depth, float band, float bias_window, bool zero_to_one, int kernel,
                                 int radius_texels, int taps, float angle)
{
    int j;
    float w;
    int i = sk_cascade_pick(view_depth, split_near, split_far, count, band, j, w);
    if (i < 0) return 1.0;
    float s = sk_cascade_sample_filtered(maps, light_vp[i], i, world_pos, bias_window, zero_to_one, kernel, radius_texels, taps,
                                         angle);
    if (j >= 0)
        s = mix(s, sk_cascade_sample_filtered(maps, light_vp[j], j, world_pos, bias_window, zero_to_one, kernel, radius_texels,
                                              taps, angle), w);
    return s;
}
#endif
