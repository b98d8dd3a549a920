// shadowkit/hlsl/contact_shadow.hlsl - contact (screen-space) shadows in HLSL: a short march toward the light in the camera's depth buffer
// stages: pixel (and any other: no derivatives; a compute shader works)
//
// The HLSL twin of glsl/contact_shadow.glsl: the same sk_ functions, arguments, results and arithmetic
// (its header says each input, the bad-input rules and the two marches; shadowkit/contact_shadow.hpp's
// contact_shadow_march and contact_shadow_march_aligned are the CPU mirrors). `camera_depth` is a
// Texture2D<float> read with Load (no sampler); `proj` the projection it was rendered with,
// `column_major`, mul(M, v) (hlsl/shadow_map.hlsl states the rule; GLSL's proj[c][r] is proj[r][c]
// here). Direct3D and Vulkan: zero_to_one = true; SK_REVERSED_Z before this file for a reversed-Z
// buffer. The depth buffer's rows must run with the projection's NDC y (v = ndc.y * 0.5 + 0.5): in
// Vulkan with a negative-height viewport, pass flip_y * proj (and its inverse), flip_y = diag(1, -1,
// 1, 1), as for a shadow map (docs/vulkan_and_direct3d.md).
// Compiled in the tests by glslang's HLSL front end to SPIR-V and run on Vulkan; written for DXC
// (shader model 6.0) as well, but not compiled with it here (DXC is not packaged in Debian 12).
// MIT License. Copyright (c) shadowkit contributors.

// Interleaved gradient noise in [0, 1) (Jimenez 2014), a per-pixel jitter for the march.
float sk_contact_noise(float2 pixel) {
    return frac(52.9829189 * frac(dot(pixel, float2(0.06711056, 0.00583715))));
}

bool sk_contact_finite(float x) { return abs(x) <= 3.402823e38; }  // false for NaN and Inf

float sk_contact_near(float4 c, bool zero_to_one) {
#ifdef SK_REVERSED_Z
    return c.w - c.z;
#else
    return zero_to_one ? c.z : c.z + c.w;
#endif
}

float sk_contact_depth_bilinear(Texture2D<float> camera_depth, int2 size, float2 uv) {
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
    float d00 = camera_depth.Load(int3(xa, ya, 0));
    float d10 = camera_depth.Load(int3(xb, ya, 0));
    float d01 = camera_depth.Load(int3(xa, yb, 0));
    float d11 = camera_depth.Load(int3(xb, yb, 0));
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
bool sk_contact_clip_ray(float4x4 proj, float3 view_pos, float4 light_position, float length_world, bool zero_to_one,
                         out float4 c0, out float4 c1, out float z1) {
    c0 = float4(0.0, 0.0, 0.0, 0.0);
    c1 = float4(0.0, 0.0, 0.0, 0.0);
    z1 = 0.0;
    float4 L = light_position;
    if (!(sk_contact_finite(L.x) && sk_contact_finite(L.y) && sk_contact_finite(L.z) && sk_contact_finite(L.w)) ||
        L.w < 0.0 || all(L == 0.0))
        return false;
    if (!(sk_contact_finite(view_pos.x) && sk_contact_finite(view_pos.y) && sk_contact_finite(view_pos.z))) return false;
    float3 to_light = L.xyz;
    if (L.w > 0.0) to_light = L.xyz / L.w - view_pos;
    float m = max(abs(to_light.x), max(abs(to_light.y), abs(to_light.z)));
    if (!(m > 0.0) || !sk_contact_finite(m)) return false;
    float3 scaled = to_light / m;
    float sl = sqrt(scaled.x * scaled.x + scaled.y * scaled.y + scaled.z * scaled.z);
    float3 dir = scaled / sl;
    float len = length_world;
    if (L.w > 0.0) len = min(len, m * sl);
    float3 p1 = view_pos + dir * len;
    c0 = mul(proj, float4(view_pos, 1.0));
    c1 = mul(proj, float4(p1, 1.0));
    float f0[6] = {sk_contact_near(c0, zero_to_one), c0.w, c0.w - c0.x, c0.w + c0.x, c0.w - c0.y, c0.w + c0.y};
    float f1[6] = {sk_contact_near(c1, zero_to_one), c1.w, c1.w - c1.x, c1.w + c1.x, c1.w - c1.y, c1.w + c1.y};
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
float sk_contact_shadow(Texture2D<float> camera_depth, float4x4 proj, float3 view_pos, float4 light_position,
                        float length_world, int max_steps, float thickness_world, float depth_step,
                        bool zero_to_one, float jitter) {
    if (!(length_world > 0.0) || !sk_contact_finite(length_world)) return 1.0;
    int steps_max = clamp(max_steps, 1, 256);
    float thickness = (thickness_world > 0.0) ? thickness_world : length_world;
    float jit = (jitter >= 0.0) ? min(jitter, 0.999) : 0.0;
    float a = proj[2][2];
    float b = proj[2][3];  // GLSL proj[3][2]: HLSL indexes rows first
    float c = proj[3][2];  // GLSL proj[2][3]
    float d = proj[3][3];
    float det = a * d - b * c;
    if (!sk_contact_finite(det) || det == 0.0) return 1.0;
    float inv_sdet = 1.0 / ((zero_to_one ? 1.0 : 0.5) * abs(det));
    if (!sk_contact_finite(inv_sdet)) return 1.0;
    float4 c0, c1;
    float z1;
    if (!sk_contact_clip_ray(proj, view_pos, light_position, length_world, zero_to_one, c0, c1, z1)) return 1.0;
    float z0 = view_pos.z;
    float2 uv0 = float2(c0.x / c0.w, c0.y / c0.w) * 0.5 + 0.5;
    float2 uv1 = float2(c1.x / c1.w, c1.y / c1.w) * 0.5 + 0.5;
    uint size_w, size_h;
    camera_depth.GetDimensions(size_w, size_h);
    int2 size = int2(size_w, size_h);
    float2 px = (uv1 - uv0) * float2(size);
    float pixels = sqrt(px.x * px.x + px.y * px.y);
    if (!(pixels > 1.0) || !sk_contact_finite(pixels)) return 1.0;  // the ray stays in its own pixel
    float u_start = 1.0 / pixels;
    int steps = int(min(ceil(pixels), float(steps_max)));
    for (int i = 0; i < steps; ++i) {
        float u = u_start + (1.0 - u_start) * (float(i) + 1.0 - jit) / float(steps);
        float2 uv = uv0 + (uv1 - uv0) * u;
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
float3 sk_contact_view_position(float4x4 inv_proj, int2 size, int2 pixel, float win, bool zero_to_one) {
    float2 ndc_xy = (float2(pixel) + 0.5) / float2(size) * 2.0 - 1.0;
    float ndc_z = zero_to_one ? win : win * 2.0 - 1.0;
    float4 v = mul(inv_proj, float4(ndc_xy, ndc_z, 1.0));
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
    float2 p;        // the first sample: a whole pixel along the major axis, fractional along the minor
    float2 dp;       // one step: +-stride along the major axis, the ray's change along the minor
    float win;       // the ray's window depth at the first sample
    float dwin;      // its change per step
    float iw;        // the ray's 1 / clip w at the first sample
    float diw;       // its change per step
    float thick_k;   // thickness * s |a d - b c|: the thickness in window depth is thick_k * (1/w)^2
    float bias_k;    // 4 depth_step: the bias is bias_k + 2^-20 |window|
    int2 minor;      // the minor axis: (0, 1) when x is the major axis, else (1, 0)
    int count;       // samples
};

// The aligned march's ray in clip space: c0 at the receiver, c1 its end, clipped at the near plane
// and w = 0 only. False (lit) for the bad inputs of the header comment and a receiver behind the near
// plane or off screen.
bool sk_contact_aligned_ray(float4x4 proj, float3 view_pos, float4 light_position, float length_world, bool zero_to_one,
                            out float4 c0, out float4 c1) {
    c0 = mul(proj, float4(view_pos, 1.0));
    c1 = c0;
    float4 L = light_position;
    if (!(sk_contact_finite(L.x) && sk_contact_finite(L.y) && sk_contact_finite(L.z) && sk_contact_finite(L.w)) ||
        L.w < 0.0 || all(L == 0.0))
        return false;
    if (!(sk_contact_finite(view_pos.x) && sk_contact_finite(view_pos.y) && sk_contact_finite(view_pos.z))) return false;
    float3 to_light = L.w > 0.0 ? L.xyz * (1.0 / L.w) - view_pos : L.xyz;
    float m = max(abs(to_light.x), max(abs(to_light.y), abs(to_light.z)));
    if (!(m > 0.0) || !sk_contact_finite(m)) return false;
    float3 scaled = to_light * (1.0 / m);
    float sl = sqrt(dot(scaled, scaled));
    float len = L.w > 0.0 ? min(length_world, m * sl) : length_world;
    c1 = c0 + mul(proj, float4(scaled * (len / sl), 0.0));
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
bool sk_contact_aligned_setup(int2 size, float4x4 proj, float3 view_pos, float4 light_position, float length_world,
                              int max_steps, float thickness_world, float depth_step, bool zero_to_one,
                              float jitter, out SkContactAligned r) {
    r = (SkContactAligned)0;
    r.minor = int2(0, 1);
    if (!(length_world > 0.0) || !sk_contact_finite(length_world)) return false;
    float det = proj[2][2] * proj[3][3] - proj[2][3] * proj[3][2];
    if (!sk_contact_finite(det) || det == 0.0) return false;
    float4 c0, c1;
    if (!sk_contact_aligned_ray(proj, view_pos, light_position, length_world, zero_to_one, c0, c1)) return false;
    float iw0 = 1.0 / c0.w;
    float iw1 = 1.0 / c1.w;
    float2 fs = float2(size);
    float2 q0 = (c0.xy * iw0 * 0.5 + 0.5) * fs - 0.5;
    float2 dq = (c1.xy * iw1 * 0.5 + 0.5) * fs - 0.5 - q0;
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
    r.p = xmajor ? float2(j1, q0.y + dq.y * u1) : float2(q0.x + dq.x * u1, j1);
    r.dp = xmajor ? float2(sgn * stride, dq.y * du) : float2(dq.x * du, sgn * stride);
    r.win = win0 + dwin * u1;
    r.dwin = dwin * du;
    r.iw = iw0 + diw * u1;
    r.diw = diw * du;
    float thickness = (thickness_world > 0.0) ? thickness_world : length_world;
    r.thick_k = thickness * ((zero_to_one ? 1.0 : 0.5) * abs(det));
    r.bias_k = 4.0 * depth_step;
    r.minor = xmajor ? int2(0, 1) : int2(1, 0);
    return r.count > 0;
}

// Sample k: the window depth of the two texels of its column (row) around the ray, interpolated
// along the minor axis, is in front of the ray by more than 4 depth steps and less than the
// thickness. No hit outside the pixel centers, for texels outside [0, 1] and at the clear value.
bool sk_contact_aligned_sample(Texture2D<float> camera_depth, int2 size, SkContactAligned r, float k) {
    float2 p = r.p + r.dp * k;
    if (!(p.x >= 0.0 && p.y >= 0.0 && p.x <= float(size.x - 1) && p.y <= float(size.y - 1))) return false;
    float2 fl = floor(p);
    int2 t0 = int2(fl);
    int2 t1 = min(t0 + r.minor, size - 1);
    float f = r.minor.y == 1 ? p.y - fl.y : p.x - fl.x;
    float d0 = camera_depth.Load(int3(t0, 0));
    float d1 = camera_depth.Load(int3(t1, 0));
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
float sk_contact_shadow_aligned(Texture2D<float> camera_depth, float4x4 proj, float3 view_pos, float4 light_position,
                                float length_world, int max_steps, float thickness_world, float depth_step,
                                bool zero_to_one, float jitter) {
    uint size_w, size_h;
    camera_depth.GetDimensions(size_w, size_h);
    int2 size = int2(size_w, size_h);
    SkContactAligned r;
    if (!sk_contact_aligned_setup(size, proj, view_pos, light_position, length_world, max_steps, thickness_world,
                                  depth_step, zero_to_one, jitter, r))
        return 1.0;
    for (int k = 0; k < r.count; ++k)
        if (sk_contact_aligned_sample(camera_depth, size, r, float(k))) return 0.0;
    return 1.0;
}
