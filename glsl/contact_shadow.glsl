// shadowkit/glsl/contact_shadow.glsl - contact (screen-space) shadows: a short march toward the light in the camera's depth buffer
// versions: 330, 450
// stages: fragment
//
// Inputs: `camera_depth`, the camera's depth texture (window depth, as rendered: GL_DEPTH_COMPONENT24
// / 32F / 16); `proj`, the camera projection it was rendered with (view -> clip; perspective,
// infinite-far or orthographic; its z and w rows depend on view z only); `view_pos`, the receiver's
// view-space position (reconstructed from the same depth, or from the G-buffer);
// `light_position`, the light in VIEW space (view * light_world), shadowkit's convention: w > 0 a
// point light at xyz / w, w = 0 a direction toward the light; `length_world`, the march length in
// view units; `max_steps` in [1, 256] (one sample per pixel of the projected ray up to this);
// `thickness_world` (0: the march length; +inf: every surface solid); `depth_step`, the depth
// format's window step (1.0 / 16777215.0 UNORM24, 1.0 / 65535.0 UNORM16, 0.0 float32: the
// `depth_step_window` of contact_shadow_derive); `zero_to_one` for glClipControl(..., GL_ZERO_TO_ONE);
// `jitter` in [0, 1) (per-pixel noise, e.g. interleaved gradient noise; 0.0 for none).
// Defines: SK_REVERSED_Z before this snippet for a reversed-Z depth buffer (1 at near).
// Uniforms: none required (pass the values above).
// GL state: `camera_depth` is sampled with texelFetch (level 0, no filtering, no compare:
// GL_TEXTURE_COMPARE_MODE = GL_NONE); it must not be the bound depth attachment of the pass that
// reads it (draw the full-screen pass with depth test and depth writes off, or into another target).
// No blending or culling needed. No derivatives: the functions work in any stage (a compute shader
// with 8 x 8 groups and sk_contact_view_position is how tests/gl/test_gl_contact_shadow.cpp times it).
// Returns 1 = lit, 0 = a sample hit an occluder. Bad input never gives NaN: NaN/Inf in proj,
// view_pos or the light, w < 0 or (0, 0, 0, 0), a point light at the receiver, length_world NaN or
// <= 0, a receiver behind the near plane or off screen, or a projection whose depth does not vary
// all return 1.0 (lit); max_steps is clamped to [1, 256]; thickness_world NaN or <= 0 means the
// march length; jitter NaN gives 0, else clamped to [0, 0.999]; depth texels outside [0, 1] or
// equal to the clear value (1; 0 with SK_REVERSED_Z: the background) are no surface. The CPU mirror
// (shadowkit/contact_shadow.hpp, contact_shadow_march) does the same arithmetic and reports those
// cases as statuses; its header comment derives bias, steps and start.
// Two marches with these inputs and outputs: sk_contact_shadow (one bilinear sample per pixel of the
// ray, compared in view distance: the reference) and sk_contact_shadow_aligned (samples on whole
// pixels of the ray's major axis, every ceil(pixels / max_steps), two texels each, compared in window
// depth: 2.2-3.4x cheaper on llvmpipe; its mirror is contact_shadow_march_aligned; the comment above
// sk_contact_aligned_setup below describes it). docs/contact_shadow.md measures both.
// Usage:
//   float vc = sk_contact_shadow_aligned(u_depth, u_proj, view_pos, u_view_light, 0.25, 8, 0.0,
//                                        1.0 / 16777215.0, false, sk_contact_noise(gl_FragCoord.xy));
//   float v = v_shadow_map * vc;   // compose with any shadow-map technique
// MIT License. Copyright (c) shadowkit contributors.

// Interleaved gradient noise in [0, 1) (Jimenez 2014), a per-pixel jitter for the march.
float sk_contact_noise(vec2 pixel) {
    return fract(52.9829189 * fract(dot(pixel, vec2(0.06711056, 0.00583715))));
}

bool sk_contact_finite(float x) { return abs(x) <= 3.402823e38; }  // false for NaN and Inf

float sk_contact_near(vec4 c, bool zero_to_one) {
#ifdef SK_REVERSED_Z
    return c.w - c.z;
#else
    return zero_to_one ? c.z : c.z + c.w;
#endif
}

float sk_contact_depth_bilinear(sampler2D camera_depth, ivec2 size, vec2 uv) {
    float x = uv.x * float(size.x) - 0.5;
    float y = uv.y * float(size.y) - 0.5;
    if (!(x >= 0.0 && x <= float(size.x - 1) && y >= 0.0 && y <= float(size.y - 1))) return -1.0;  // outside the pixel centers
    float fx0 = floor(x);
    float fy0 = floor(y);
    float fx = x - fx0;
    float fy = y - fy0;
    int x0 = int(fx0);
    int y0 = int(fy0);
    int xa = clamp(x0, 0, size.x - 1);
    int xb = clamp(x0 + 1, 0, size.x - 1);
    int ya = clamp(y0, 0, size.y - 1);
    int yb = clamp(y0 + 1, 0, size.y - 1);
    float d00 = texelFetch(camera_depth, ivec2(xa, ya), 0).r;
    float d10 = texelFetch(camera_depth, ivec2(xb, ya), 0).r;
    float d01 = texelFetch(camera_depth, ivec2(xa, yb), 0).r;
    float d11 = texelFetch(camera_depth, ivec2(xb, yb), 0).r;
    if (!(d00 >= 0.0 && d00 <= 1.0 && d10 >= 0.0 && d10 <= 1.0 && d01 >= 0.0 && d01 <= 1.0 && d11 >= 0.0 && d11 <= 1.0))
        return -1.0;  // no surface
#ifdef SK_REVERSED_Z
    if (d00 == 0.0 || d10 == 0.0 || d01 == 0.0 || d11 == 0.0) return -1.0;  // background (the clear value)
#else
    if (d00 == 1.0 || d10 == 1.0 || d01 == 1.0 || d11 == 1.0) return -1.0;  // background (the clear value)
#endif
    float lo = d00 + (d10 - d00) * fx;
    float hi = d01 + (d11 - d01) * fx;
    return lo + (hi - lo) * fy;
}

// The march's ray clipped to what the camera sees: from view_pos toward the light for
// min(length_world, distance to a point light), cut at the near plane, w = 0 and the screen edges.
// c0, c1: its clip-space ends; z1: the view z of its end. False (nothing to march: lit) for the bad
// inputs listed in the header comment (the length is checked by the caller) and a receiver behind
// the near plane or off screen.
bool sk_contact_clip_ray(mat4 proj, vec3 view_pos, vec4 light_position, float length_world, bool zero_to_one,
                         out vec4 c0, out vec4 c1, out float z1) {
    c0 = vec4(0.0);
    c1 = vec4(0.0);
    z1 = 0.0;
    vec4 L = light_position;
    if (!(sk_contact_finite(L.x) && sk_contact_finite(L.y) && sk_contact_finite(L.z) && sk_contact_finite(L.w)) ||
        L.w < 0.0 || all(equal(L, vec4(0.0))))
        return false;
    if (!(sk_contact_finite(view_pos.x) && sk_contact_finite(view_pos.y) && sk_contact_finite(view_pos.z))) return false;
    vec3 to_light = L.xyz;
    if (L.w > 0.0) to_light = L.xyz / L.w - view_pos;
    float m = max(abs(to_light.x), max(abs(to_light.y), abs(to_light.z)));
    if (!(m > 0.0) || !sk_contact_finite(m)) return false;
    vec3 scaled = to_light / m;
    float sl = sqrt(scaled.x * scaled.x + scaled.y * scaled.y + scaled.z * scaled.z);
    vec3 dir = scaled / sl;
    float len = length_world;
    if (L.w > 0.0) len = min(len, m * sl);
    vec3 p1 = view_pos + dir * len;
    c0 = proj * vec4(view_pos, 1.0);
    c1 = proj * vec4(p1, 1.0);
    float f0[6] = float[6](sk_contact_near(c0, zero_to_one), c0.w, c0.w - c0.x, c0.w + c0.x, c0.w - c0.y, c0.w + c0.y);
    float f1[6] = float[6](sk_contact_near(c1, zero_to_one), c1.w, c1.w - c1.x, c1.w + c1.x, c1.w - c1.y, c1.w + c1.y);
    if (!(f0[0] > 0.0) || !(f0[1] > 0.0) || !(f0[2] >= 0.0) || !(f0[3] >= 0.0) || !(f0[4] >= 0.0) || !(f0[5] >= 0.0))
        return false;  // the receiver is behind the near plane or off screen
    float t_end = 1.0;
    for (int k = 0; k < 6; ++k)
        if (f1[k] < 0.0) t_end = min(t_end, f0[k] / (f0[k] - f1[k]));
    c1 = c0 + (c1 - c0) * t_end;
    z1 = view_pos.z + (p1.z - view_pos.z) * t_end;
    return true;
}

// Contact-shadow visibility (1 lit, 0 occluded) of the receiver at view_pos: one sample per pixel of
// the projected ray (up to max_steps), from one pixel past the receiver to the end of the ray
// clipped to the near plane and the screen; a sample is occluded when the depth buffer's surface is
// in front of the ray by more than 4 depth steps (bias) and less than the thickness.
float sk_contact_shadow(sampler2D camera_depth, mat4 proj, vec3 view_pos, vec4 light_position,
                        float length_world, int max_steps, float thickness_world, float depth_step,
                        bool zero_to_one, float jitter) {
    if (!(length_world > 0.0) || !sk_contact_finite(length_world)) return 1.0;
    int steps_max = clamp(max_steps, 1, 256);
    float thickness = (thickness_world > 0.0) ? thickness_world : length_world;
    float jit = (jitter >= 0.0) ? min(jitter, 0.999) : 0.0;
    float a = proj[2][2];
    float b = proj[3][2];
    float c = proj[2][3];
    float d = proj[3][3];
    float det = a * d - b * c;
    if (!sk_contact_finite(det) || det == 0.0) return 1.0;
    float inv_sdet = 1.0 / ((zero_to_one ? 1.0 : 0.5) * abs(det));
    if (!sk_contact_finite(inv_sdet)) return 1.0;
    vec4 c0, c1;
    float z1;
    if (!sk_contact_clip_ray(proj, view_pos, light_position, length_world, zero_to_one, c0, c1, z1)) return 1.0;
    float z0 = view_pos.z;
    vec2 uv0 = vec2(c0.x / c0.w, c0.y / c0.w) * 0.5 + 0.5;
    vec2 uv1 = vec2(c1.x / c1.w, c1.y / c1.w) * 0.5 + 0.5;
    ivec2 size = textureSize(camera_depth, 0);
    vec2 px = (uv1 - uv0) * vec2(size);
    float pixels = sqrt(px.x * px.x + px.y * px.y);
    if (!(pixels > 1.0) || !sk_contact_finite(pixels)) return 1.0;  // the ray stays in its own pixel
    float u_start = 1.0 / pixels;
    int steps = int(min(ceil(pixels), float(steps_max)));
    for (int i = 0; i < steps; ++i) {
        float u = u_start + (1.0 - u_start) * (float(i) + 1.0 - jit) / float(steps);
        vec2 uv = uv0 + (uv1 - uv0) * u;
        float t = u * c0.w / ((1.0 - u) * c1.w + u * c0.w);
        float dist_ray = -(z0 + (z1 - z0) * t);
        float win = sk_contact_depth_bilinear(camera_depth, size, uv);
        if (win < 0.0) continue;
        float ndc = zero_to_one ? win : win * 2.0 - 1.0;
        float z_buf = (b - ndc * d) / (ndc * c - a);
        float w_buf = c * z_buf + d;
        float bias = 4.0 * (depth_step + 2.38418579e-7 * abs(win)) * (w_buf * w_buf) * inv_sdet;
        float delta = dist_ray + z_buf;
        if (delta > bias && delta < thickness) return 0.0;
    }
    return 1.0;
}

// View-space position of the pixel center `pixel` whose window depth is `win` (inv_proj = inverse(proj)).
vec3 sk_contact_view_position(mat4 inv_proj, ivec2 size, ivec2 pixel, float win, bool zero_to_one) {
    vec2 ndc_xy = (vec2(pixel) + 0.5) / vec2(size) * 2.0 - 1.0;
    float ndc_z = zero_to_one ? win : win * 2.0 - 1.0;
    vec4 v = inv_proj * vec4(ndc_xy, ndc_z, 1.0);
    return v.xyz / v.w;
}

// ---- The pixel-aligned march (sk_contact_shadow_aligned): the same ray, sampled on pixel centers.
// Samples sit on whole pixels of the ray's major screen axis (x where |dx| >= |dy|, else y), every
// `stride` pixels, stride = ceil(major length / max_steps); each reads the two texels of that pixel
// column (row) around the ray and interpolates along the minor axis (exact on a plane: window depth
// is affine in screen space), and compares in window depth: the ray's window depth and 1/w are affine
// in screen space along the ray, so sample k's are a start plus k steps (no division per sample); the
// bias is 4 depth steps at the buffer's texels (sk_contact_shadow's 4 steps, not converted to view
// units) and the thickness is thickness_world * d(window)/dz at the ray's depth (s |a d - b c| / w^2).
// The ray is clipped at the near plane and w = 0 only: samples off screen read no surface.

// The aligned march's state for one receiver (sk_contact_aligned_setup fills it). Sample k (0 ..
// count - 1) is at texel-index position p + k dp (pixel (i, j)'s center at (i, j)).
struct SkContactAligned {
    vec2 p;          // the first sample: a whole pixel along the major axis, fractional along the minor
    vec2 dp;         // one step: +-stride along the major axis, the ray's change along the minor
    float win;       // the ray's window depth at the first sample
    float dwin;      // its change per step
    float iw;        // the ray's 1 / clip w at the first sample
    float diw;       // its change per step
    float thick_k;   // thickness * s |a d - b c|: the thickness in window depth is thick_k * (1/w)^2
    float bias_k;    // 4 depth_step: the bias is bias_k + 2^-20 |window|
    ivec2 minor;     // the minor axis: (0, 1) when x is the major axis, else (1, 0)
    int count;       // samples
};

// The aligned march's ray in clip space: c0 at the receiver, c1 its end, clipped at the near plane
// and w = 0 only. False (lit) for the bad inputs of the header comment and a receiver behind the near
// plane or off screen.
bool sk_contact_aligned_ray(mat4 proj, vec3 view_pos, vec4 light_position, float length_world, bool zero_to_one,
                            out vec4 c0, out vec4 c1) {
    c0 = proj * vec4(view_pos, 1.0);
    c1 = c0;
    vec4 L = light_position;
    if (!(sk_contact_finite(L.x) && sk_contact_finite(L.y) && sk_contact_finite(L.z) && sk_contact_finite(L.w)) ||
        L.w < 0.0 || all(equal(L, vec4(0.0))))
        return false;
    if (!(sk_contact_finite(view_pos.x) && sk_contact_finite(view_pos.y) && sk_contact_finite(view_pos.z))) return false;
    vec3 to_light = L.w > 0.0 ? L.xyz * (1.0 / L.w) - view_pos : L.xyz;
    float m = max(abs(to_light.x), max(abs(to_light.y), abs(to_light.z)));
    if (!(m > 0.0) || !sk_contact_finite(m)) return false;
    vec3 scaled = to_light * (1.0 / m);
    float sl = sqrt(dot(scaled, scaled));
    float len = L.w > 0.0 ? min(length_world, m * sl) : length_world;
    c1 = c0 + proj * vec4(scaled * (len / sl), 0.0);
    float f0 = sk_contact_near(c0, zero_to_one);
    float f1 = sk_contact_near(c1, zero_to_one);
    if (!(f0 > 0.0) || !(c0.w > 0.0) || !(abs(c0.x) <= c0.w) || !(abs(c0.y) <= c0.w))
        return false;  // the receiver is behind the near plane or off screen
    float t_end = f1 < 0.0 ? f0 / (f0 - f1) : 1.0;
    if (c1.w < 0.0) t_end = min(t_end, c0.w / (c0.w - c1.w));
    c1 = c0 + (c1 - c0) * t_end;
    return true;
}

// Fills the aligned march's state; false when there is nothing to march (lit): the bad inputs of the
// header comment, and a ray shorter than one pixel along its major axis. The first sample is the
// first pixel past the receiver's along the major axis, moved back by int(jitter * stride) pixels.
bool sk_contact_aligned_setup(ivec2 size, mat4 proj, vec3 view_pos, vec4 light_position, float length_world,
                              int max_steps, float thickness_world, float depth_step, bool zero_to_one,
                              float jitter, out SkContactAligned r) {
    r = SkContactAligned(vec2(0.0), vec2(0.0), 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, ivec2(0, 1), 0);
    if (!(length_world > 0.0) || !sk_contact_finite(length_world)) return false;
    float det = proj[2][2] * proj[3][3] - proj[3][2] * proj[2][3];
    if (!sk_contact_finite(det) || det == 0.0) return false;
    vec4 c0, c1;
    if (!sk_contact_aligned_ray(proj, view_pos, light_position, length_world, zero_to_one, c0, c1)) return false;
    float iw0 = 1.0 / c0.w;
    float iw1 = 1.0 / c1.w;
    vec2 fs = vec2(size);
    vec2 q0 = (c0.xy * iw0 * 0.5 + 0.5) * fs - 0.5;
    vec2 dq = (c1.xy * iw1 * 0.5 + 0.5) * fs - 0.5 - q0;
    float win0 = zero_to_one ? c0.z * iw0 : c0.z * iw0 * 0.5 + 0.5;
    float dwin = (zero_to_one ? c1.z * iw1 : c1.z * iw1 * 0.5 + 0.5) - win0;
    float diw = iw1 - iw0;
    bool xmajor = abs(dq.x) >= abs(dq.y);
    float qm = xmajor ? q0.x : q0.y;
    float dm = xmajor ? dq.x : dq.y;
    float n = abs(dm);
    if (!(n >= 1.0) || !sk_contact_finite(n) || !sk_contact_finite(dq.x + dq.y) || !sk_contact_finite(dwin) ||
        !sk_contact_finite(diw))
        return false;  // the ray stays within a pixel of its receiver (or w -> 0 at its clipped end)
    int steps_max = clamp(max_steps, 1, 256);
    float base = floor(qm + 0.5);             // the receiver's pixel along the major axis
    float sgn = dm > 0.0 ? 1.0 : -1.0;
    float e = (qm - base) * sgn;              // the receiver past its pixel's center, [-0.5, 0.5]
    float stride = max(ceil(n / float(steps_max)), 1.0);
    float jit = (jitter >= 0.0) ? min(jitter, 0.999) : 0.0;
    float shift = min(floor(jit * stride), stride - 1.0);
    float q = (n + e + shift) / stride;  // in [0.5, steps_max + 1) but for overflow (inf: steps_max)
    r.count = q < float(steps_max) ? int(floor(q)) : steps_max;
    float inv_dm = 1.0 / dm;
    float j1 = base + sgn * (stride - shift);  // the first sample's pixel along the major axis
    float u1 = (j1 - qm) * inv_dm;             // its fraction of the ray
    float du = sgn * stride * inv_dm;          // one step's
    r.p = xmajor ? vec2(j1, q0.y + dq.y * u1) : vec2(q0.x + dq.x * u1, j1);
    r.dp = xmajor ? vec2(sgn * stride, dq.y * du) : vec2(dq.x * du, sgn * stride);
    r.win = win0 + dwin * u1;
    r.dwin = dwin * du;
    r.iw = iw0 + diw * u1;
    r.diw = diw * du;
    float thickness = (thickness_world > 0.0) ? thickness_world : length_world;
    r.thick_k = thickness * ((zero_to_one ? 1.0 : 0.5) * abs(det));
    r.bias_k = 4.0 * depth_step;
    r.minor = xmajor ? ivec2(0, 1) : ivec2(1, 0);
    return r.count > 0;
}

// Sample k: the window depth of the two texels of its column (row) around the ray, interpolated
// along the minor axis, is in front of the ray by more than 4 depth steps and less than the
// thickness. No hit outside the pixel centers, for texels outside [0, 1] and at the clear value.
bool sk_contact_aligned_sample(sampler2D camera_depth, ivec2 size, SkContactAligned r, float k) {
    vec2 p = r.p + r.dp * k;
    if (!(p.x >= 0.0 && p.y >= 0.0 && p.x <= float(size.x - 1) && p.y <= float(size.y - 1))) return false;
    vec2 fl = floor(p);
    ivec2 t0 = ivec2(fl);
    ivec2 t1 = min(t0 + r.minor, size - 1);
    float f = r.minor.y == 1 ? p.y - fl.y : p.x - fl.x;
    float d0 = texelFetch(camera_depth, t0, 0).r;
    float d1 = texelFetch(camera_depth, t1, 0).r;
    float win_buf = d0 + (d1 - d0) * f;
    float win_ray = r.win + r.dwin * k;
    float iw = r.iw + r.diw * k;
#ifdef SK_REVERSED_Z
    float diff = win_buf - win_ray;
    bool surface = d0 > 0.0 && d0 <= 1.0 && d1 > 0.0 && d1 <= 1.0;  // not the background (0), not NaN
#else
    float diff = win_ray - win_buf;
    bool surface = d0 >= 0.0 && d0 < 1.0 && d1 >= 0.0 && d1 < 1.0;  // not the background (1), not NaN
#endif
    return surface && diff > r.bias_k + 9.53674316e-7 * win_buf && diff < r.thick_k * (iw * iw);
}

// Contact-shadow visibility (1 lit, 0 occluded) with the pixel-aligned march: the inputs, outputs and
// clamps of sk_contact_shadow; at most max_steps samples, two texel reads each.
float sk_contact_shadow_aligned(sampler2D camera_depth, mat4 proj, vec3 view_pos, vec4 light_position,
                                float length_world, int max_steps, float thickness_world, float depth_step,
                                bool zero_to_one, float jitter) {
    ivec2 size = textureSize(camera_depth, 0);
    SkContactAligned r;
    if (!sk_contact_aligned_setup(size, proj, view_pos, light_position, length_world, max_steps, thickness_world,
                                  depth_step, zero_to_one, jitter, r))
        return 1.0;
    for (int k = 0; k < r.count; ++k)
        if (sk_contact_aligned_sample(camera_depth, size, r, float(k))) return 0.0;
    return 1.0;
}
