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
// Usage:
//   float vc = sk_contact_shadow(u_depth, u_proj, view_pos, u_view_light, 0.25, 16, 0.0,
//                                1.0 / 16777215.0, false, sk_contact_noise(gl_FragCoord.xy));
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
    vec4 L = light_position;
    if (!(sk_contact_finite(L.x) && sk_contact_finite(L.y) && sk_contact_finite(L.z) && sk_contact_finite(L.w)) ||
        L.w < 0.0 || all(equal(L, vec4(0.0))))
        return 1.0;
    if (!(sk_contact_finite(view_pos.x) && sk_contact_finite(view_pos.y) && sk_contact_finite(view_pos.z))) return 1.0;
    vec3 to_light = L.xyz;
    if (L.w > 0.0) to_light = L.xyz / L.w - view_pos;
    float m = max(abs(to_light.x), max(abs(to_light.y), abs(to_light.z)));
    if (!(m > 0.0) || !sk_contact_finite(m)) return 1.0;
    vec3 scaled = to_light / m;
    float sl = sqrt(scaled.x * scaled.x + scaled.y * scaled.y + scaled.z * scaled.z);
    vec3 dir = scaled / sl;
    float len = length_world;
    if (L.w > 0.0) len = min(len, m * sl);
    vec3 p1 = view_pos + dir * len;
    vec4 c0 = proj * vec4(view_pos, 1.0);
    vec4 c1 = proj * vec4(p1, 1.0);
    float f0[6] = float[6](sk_contact_near(c0, zero_to_one), c0.w, c0.w - c0.x, c0.w + c0.x, c0.w - c0.y, c0.w + c0.y);
    float f1[6] = float[6](sk_contact_near(c1, zero_to_one), c1.w, c1.w - c1.x, c1.w + c1.x, c1.w - c1.y, c1.w + c1.y);
    if (!(f0[0] > 0.0) || !(f0[1] > 0.0) || !(f0[2] >= 0.0) || !(f0[3] >= 0.0) || !(f0[4] >= 0.0) || !(f0[5] >= 0.0))
        return 1.0;  // the receiver is behind the near plane or off screen
    float t_end = 1.0;
    for (int k = 0; k < 6; ++k)
        if (f1[k] < 0.0) t_end = min(t_end, f0[k] / (f0[k] - f1[k]));
    c1 = c0 + (c1 - c0) * t_end;
    float z0 = view_pos.z;
    float z1 = view_pos.z + (p1.z - view_pos.z) * t_end;
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
