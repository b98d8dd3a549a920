// shadowkit/glsl/virtual_shadow_map.glsl - virtual shadow maps: the page-marking pass, the lookup through the page table (automatic bias, PCF across pages, coarser-level fallback) and a debug view
// versions: 450
// stages: fragment, compute
//
// Inputs (shadowkit/virtual_shadow_map.hpp fills them; docs/virtual_shadow_map.md has the frame):
//   SkVsmData, an SSBO at binding SK_VSM_DATA_BINDING (define it before this snippet to move it;
//     default 0), read-only: upload vsm_gpu_block(state, anchor, ...) word for word after each
//     vsm_plan. It holds per level the window's world -> (u, v, clip z, w) matrix relative to
//     `anchor` (float), the page table's toroidal offsets, the layout (level count, pages per side,
//     page texels, pool columns), the flags (zero-to-one clip depth, reversed Z, directional) and
//     level 0's texel size in world units, then the page table: kVsmPageValid (bit 31) | slot for a
//     current page, anything else is missing.
//   SkVsmRequestMask, an SSBO at binding SK_VSM_MASK_BINDING (default 1), cleared to 0 before the
//     marking pass: bit (level * n + y) * n + x of the level's window, n = pages per side, word =
//     bit / 32 (vsm_bitmask_words; vsm_requests_from_bitmask turns it into vsm_plan's requests).
//   rel_pos: the receiver's world position minus `anchor` (the point vsm_gpu_block was given);
//   normal: its geometric world normal (any length, either side), for the automatic bias;
//   level: the finest level the pixel wants (sk_vsm_level_for_footprint);
//   radius: PCF radius in texels of that level (0: the 2x2 bilinear filter; r: a (2r+1)-texel box
//     filtered bilinearly, (2r+2)^2 compares); mark and look up with the same radius;
//   depth_step: the atlas format's window-depth step (0.0 for float32: float rounding is added).
//   atlas: the physical pool, a depth texture read raw (sampler2D, compare mode OFF, unit 0).
// No function takes a light: the light is baked into the matrices (vsm_plan's VsmFrame).
// GL state: the atlas is GL_DEPTH_COMPONENT32F of (pool_columns * page_texels) x (rows * page_texels)
// texels, GL_TEXTURE_COMPARE_MODE = GL_NONE, GL_NEAREST (read with texelFetch). Each listed page is
// rendered with glViewport and glScissor = (atlas_x, atlas_y, page_texels, page_texels), scissor test
// on, depth cleared to 1 (reversed Z: 0), depth test GL_LESS (GL_GREATER), GL_DEPTH_CLAMP on, no
// polygon offset (the lookup's receiver plane is the bias), the casters drawn with
// vsm_relative_matrix(page.view_proj, anchor) on (position - anchor). Marking: any pass that has
// the visible pixels' positions (a deferred G-buffer pass, a compute pass over the depth buffer, or
// the scene drawn again with GL_EQUAL depth and early fragment tests), then
// glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT) before reading the mask back.
// Usage:
//   int level = sk_vsm_level_for_footprint(pixel_world_size, 0.0);   // e.g. distance * 2 tan(fov/2) / height
//   sk_vsm_mark(rel_pos, level, 0);                                  // marking pass
//   float lit = sk_vsm_visibility(u_atlas, rel_pos, normal, level, 0, 0.0);   // lookup pass
//   vec3 debug = sk_vsm_debug_color(rel_pos, level);                 // level hue, page borders dark
// Returns 1 = lit, 0 = shadowed; a point outside every level's window is lit; a point whose page is
// missing on every level (a pool smaller than the coarsest level's requests) is shadowed.
// MIT License. Copyright (c) shadowkit contributors.

#ifndef SK_VSM_DATA_BINDING
#define SK_VSM_DATA_BINDING 0
#endif
#ifndef SK_VSM_MASK_BINDING
#define SK_VSM_MASK_BINDING 1
#endif
// virtual_shadow_map.hpp's kVsmMaxLevels, kVsmPageValid, kVsmSlotMask (test_glsl_twins compares them)
#define SK_VSM_MAX_LEVELS 16
#define SK_VSM_PAGE_VALID 0x80000000u
#define SK_VSM_SLOT_MASK 0x3FFFFFFFu

layout(std430, binding = SK_VSM_DATA_BINDING) readonly buffer SkVsmData {
    mat4 sk_vsm_world_to_uv[SK_VSM_MAX_LEVELS];  // (world - anchor) -> (u, v, clip z, w); u / w in [0, 1) over the window
    ivec4 sk_vsm_level[SK_VSM_MAX_LEVELS];       // origin_mod_x, origin_mod_y, 0, 0
    ivec4 sk_vsm_layout;                         // level_count, pages_per_side, page_texels, pool_columns
    ivec4 sk_vsm_flags;                          // zero_to_one, reversed_z, directional, 0
    vec4 sk_vsm_scale;                           // level 0's texel in world units, 0, 0, 0
    uint sk_vsm_page_table[];                    // level_count * n * n entries (vsm_table_index)
};

layout(std430, binding = SK_VSM_MASK_BINDING) buffer SkVsmRequestMask {
    uint sk_vsm_request_mask[];
};

// The coarsest level whose texels are no larger than `footprint_world` (a pixel's size on the
// receiver, world units): floor(log2(footprint / level 0's texel) + lod_bias), clamped to [0,
// level_count). lod_bias 1: texels up to twice the pixel (a quarter of the pages). A spot light has
// one level: 0.
int sk_vsm_level_for_footprint(float footprint_world, float lod_bias) {
    float texel0 = sk_vsm_scale.x;
    if (!(texel0 > 0.0) || !(footprint_world > 0.0)) return 0;
    float l = floor(log2(footprint_world / texel0) + lod_bias);
    return int(clamp(l, 0.0, float(sk_vsm_layout.x - 1)));
}

// Window coordinates of rel_pos on `level`: (u, v) in [0, 1) over the window, the window depth (as
// the atlas stores it), clip w (> 0 in front of a spot light).
vec4 sk_vsm_coord(int level, vec3 rel_pos) {
    vec4 h = sk_vsm_world_to_uv[level] * vec4(rel_pos, 1.0);
    vec3 c = h.xyz / h.w;
    return vec4(c.xy, sk_vsm_flags.x != 0 ? c.z : c.z * 0.5 + 0.5, h.w);
}

// The page-table entry of page `page` (on the window) of `level`: toroidal addressing.
uint sk_vsm_entry(int level, ivec2 page) {
    int n = sk_vsm_layout.y;
    ivec2 t = (page + sk_vsm_level[level].xy) % n;
    return sk_vsm_page_table[(level * n + t.y) * n + t.x];
}

// The kernel's texel rectangle on a level of `size` texels: first texel `i0`, bilinear fraction `w`;
// taps i0 .. i0 + 2 radius + 1 on each axis. False when any tap leaves the window.
bool sk_vsm_kernel(vec2 uv, int size, int radius, out ivec2 i0, out vec2 w) {
    vec2 f = uv * float(size) - 0.5;
    vec2 b = floor(f);
    w = f - b;
    i0 = ivec2(b) - radius;
    return all(greaterThanEqual(i0, ivec2(0))) && all(lessThan(i0 + 2 * radius + 1, ivec2(size)));
}

// Marking: from `level` up, the first level whose window holds the kernel's texels; sets the bits of
// the pages those texels lie on (1, 2 or 4 pages; atomicOr after a plain read). Returns the level
// marked, -1 when no window holds the point.
int sk_vsm_mark(vec3 rel_pos, int level, int radius) {
    int n = sk_vsm_layout.y, pt = sk_vsm_layout.z;
    for (int l = max(level, 0); l < sk_vsm_layout.x; ++l) {
        vec4 c = sk_vsm_coord(l, rel_pos);
        ivec2 i0;
        vec2 w;
        if (!(c.w > 0.0) || !sk_vsm_kernel(c.xy, n * pt, radius, i0, w)) continue;
        ivec2 p0 = i0 / pt, p1 = (i0 + 2 * radius + 1) / pt;
        for (int y = p0.y; y <= p1.y; ++y)
            for (int x = p0.x; x <= p1.x; ++x) {
                uint bit = uint((l * n + y) * n + x);
                uint b = 1u << (bit & 31u);
                if ((sk_vsm_request_mask[bit >> 5u] & b) == 0u) atomicOr(sk_vsm_request_mask[bit >> 5u], b);
            }
        return l;
    }
    return -1;
}

// The receiver plane's window-depth gradient (dz/du, dz/dv) in level uv units at rel_pos through
// matrix m (Isidoro 2006; shadow_map.glsl's sk_plane_depth_gradient with uv rows): .z the solve's
// conditioning (0: edge-on, no gradient), .w the window depth of 4 float ulps of rel_pos.
vec4 sk_vsm_plane_gradient(mat4 m, vec3 rel_pos, vec3 normal) {
    vec4 c = m * vec4(rel_pos, 1.0);
    vec3 q = c.xyz / c.w;
    vec3 rw = vec3(m[0][3], m[1][3], m[2][3]);
    vec3 ju = (vec3(m[0][0], m[1][0], m[2][0]) - q.x * rw) / c.w;
    vec3 jv = (vec3(m[0][1], m[1][1], m[2][1]) - q.y * rw) / c.w;
    vec3 jz = (vec3(m[0][2], m[1][2], m[2][2]) - q.z * rw) / c.w;
    float zs = sk_vsm_flags.x != 0 ? 1.0 : 0.5;
    vec3 ap = abs(rel_pos);
    vec3 ajz = abs(jz);
    float pos_err = 4.76837158e-7 * (ap.x + ap.y + ap.z) * (ajz.x + ajz.y + ajz.z) * zs;
    vec3 n = normalize(normal);
    vec3 an = abs(n);
    vec3 axis = an.x <= an.y && an.x <= an.z ? vec3(1.0, 0.0, 0.0) : (an.y <= an.z ? vec3(0.0, 1.0, 0.0) : vec3(0.0, 0.0, 1.0));
    vec3 t1 = normalize(cross(n, axis));
    vec3 t2 = cross(n, t1);
    vec3 s1 = vec3(dot(ju, t1), dot(jv, t1), zs * dot(jz, t1));
    vec3 s2 = vec3(dot(ju, t2), dot(jv, t2), zs * dot(jz, t2));
    float det = s1.x * s2.y - s1.y * s2.x;
    float scale = (abs(s1.x) + abs(s1.y)) * (abs(s2.x) + abs(s2.y));
    float cond = scale > 0.0 ? abs(det) / scale : 0.0;
    if (!(cond > 1e-4)) return vec4(0.0, 0.0, 0.0, pos_err);
    return vec4((s2.y * s1.z - s1.y * s2.z) / det, (s1.x * s2.z - s2.x * s1.z) / det, cond, pos_err);
}

// The automatic bias's margin (shadow_map.glsl's sk_auto_bias_epsilon, shadow_bias.hpp
// bias_auto_epsilon): format steps, float rounding, position rounding, 1/8 texel of plane slope.
float sk_vsm_bias_epsilon(vec4 g, float texel_uv, float z, float depth_step) {
    float float_term = sk_vsm_flags.y != 0 ? 4.76837158e-7 * abs(z) + 1.17549435e-38 : 4.76837158e-7 * (1.0 + abs(z));
    float plane = (abs(g.x) + abs(g.y)) * texel_uv;
    return 2.0 * max(depth_step, 0.0) + float_term + 2.0 * g.w + plane * (0.125 + 9.53674316e-7 + 2.38418579e-7 / max(g.z, 1e-4));
}

// The physical texel of virtual texel t of `level`, or (-1, -1) when its page is not current.
ivec2 sk_vsm_physical(int level, ivec2 t) {
    int pt = sk_vsm_layout.z, cols = sk_vsm_layout.w;
    uint e = sk_vsm_entry(level, t / pt);
    if ((e & SK_VSM_PAGE_VALID) == 0u) return ivec2(-1);
    int slot = int(e & SK_VSM_SLOT_MASK);
    return ivec2(slot % cols, slot / cols) * pt + t % pt;
}

// The lookup on one level: true when the page holding the point is current there, with the lit
// fraction in `v`. A tap on a neighbour page reads it through the table; where that page is not
// current the tap is clamped into the point's own page (the kernel stays inside it). Each tap
// compares the atlas depth with the receiver plane's depth at the tap's centre minus the margin
// (plus with reversed Z).
bool sk_vsm_filter_level(sampler2D atlas, int l, vec4 c, vec4 g, int radius, float depth_step, out float v) {
    int pt = sk_vsm_layout.z, size = sk_vsm_layout.y * pt;
    ivec2 i0;
    vec2 w;
    v = 0.0;
    if (!(c.w > 0.0) || !sk_vsm_kernel(c.xy, size, radius, i0, w)) return false;
    ivec2 home = ivec2(c.xy * float(size)) / pt;
    if (sk_vsm_physical(l, home * pt).x < 0) return false;
    float eps = sk_vsm_bias_epsilon(g, 1.0 / float(size), c.z, depth_step);
    int taps = 2 * radius + 2;
    float sum = 0.0;
    for (int j = 0; j < taps; ++j)
        for (int i = 0; i < taps; ++i) {
            ivec2 t = i0 + ivec2(i, j);
            ivec2 p = sk_vsm_physical(l, t);
            if (p.x < 0) {
                t = clamp(t, home * pt, home * pt + pt - 1);
                p = sk_vsm_physical(l, t);
            }
            vec2 centre = (vec2(t) + 0.5) / float(size);
            float zp = c.z + dot(g.xy, centre - c.xy);
            float d = texelFetch(atlas, p, 0).r;
            float wx = i == 0 ? 1.0 - w.x : (i == taps - 1 ? w.x : 1.0);
            float wy = j == 0 ? 1.0 - w.y : (j == taps - 1 ? w.y : 1.0);
            bool lit = sk_vsm_flags.y != 0 ? clamp(zp + eps, 0.0, 1.0) >= d : clamp(zp - eps, 0.0, 1.0) <= d;
            sum += lit ? wx * wy : 0.0;
        }
    float box = float(2 * radius + 1);
    v = sum / (box * box);
    return true;
}

// Lit fraction of rel_pos: from `level` up, the first level whose window holds the kernel and whose
// page holding the point is current (a neighbour page under the kernel is read through the table,
// or the kernel is clamped into the point's page where it is missing; a missing page of the point
// sends the lookup one level coarser, where vsm_plan keeps the parent of every fallen-back page:
// never a hole). `used_level` is that level, -1 outside every
// window (1.0, lit) or when no level has the pages (0.0, shadowed). An edge-on receiver (its plane
// holds the light ray) is lit.
float sk_vsm_visibility_level(sampler2D atlas, vec3 rel_pos, vec3 normal, int level, int radius, float depth_step,
                              out int used_level) {
    used_level = -1;
    bool inside = false;
    for (int l = max(level, 0); l < sk_vsm_layout.x; ++l) {
        vec4 c = sk_vsm_coord(l, rel_pos);
        ivec2 i0;
        vec2 w;
        if (!(c.w > 0.0) || !sk_vsm_kernel(c.xy, sk_vsm_layout.y * sk_vsm_layout.z, radius, i0, w)) continue;
        inside = true;
        vec4 g = sk_vsm_plane_gradient(sk_vsm_world_to_uv[l], rel_pos, normal);
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

float sk_vsm_visibility(sampler2D atlas, vec3 rel_pos, vec3 normal, int level, int radius, float depth_step) {
    int used;
    return sk_vsm_visibility_level(atlas, rel_pos, normal, level, radius, depth_step, used);
}

// Debug view: the level the 2x2 lookup would use (a hue per level, repeating every 6), darkened on the
// texel rows at page borders, white where no level has the page, grey outside every window.
vec3 sk_vsm_debug_color(vec3 rel_pos, int level) {
    int n = sk_vsm_layout.y, pt = sk_vsm_layout.z;
    bool inside = false;
    for (int l = max(level, 0); l < sk_vsm_layout.x; ++l) {
        vec4 c = sk_vsm_coord(l, rel_pos);
        if (!(c.w > 0.0) || any(lessThan(c.xy, vec2(0.0))) || any(greaterThanEqual(c.xy, vec2(1.0)))) continue;
        inside = true;
        ivec2 t = ivec2(c.xy * float(n * pt));
        if ((sk_vsm_entry(l, t / pt) & SK_VSM_PAGE_VALID) == 0u) continue;
        float h = float(l % 6) / 6.0;
        vec3 hue = clamp(abs(fract(h + vec3(0.0, 2.0 / 3.0, 1.0 / 3.0)) * 6.0 - 3.0) - 1.0, 0.0, 1.0);
        ivec2 in_page = t % pt;
        bool border = any(equal(in_page, ivec2(0))) || any(equal(in_page, ivec2(pt - 1)));
        return mix(vec3(0.25), hue, 0.75) * (border ? 0.35 : 1.0);
    }
    return inside ? vec3(1.0) : vec3(0.5);
}
