// shadowkit/contact_shadow.hpp - contact (screen-space) shadows: a short march toward the light in the camera's depth buffer, the CPU mirror of glsl/contact_shadow.glsl
//
// Usage:
//   #include <shadowkit/contact_shadow.hpp>
//   namespace sk = shadowkit;
//   sk::ContactShadowParams p;
//   p.length_world = 0.25f;                                  // (required) march length, view units
//   p.depth_format = sk::DepthFormat::Fixed24;               // the camera depth buffer's format
//   sk::ContactShadowResult c = sk::contact_shadow_march(depth, depth_capacity, width, height,
//                                                        proj, view_pos, view * light_world, p);
//   if (c.status == sk::Status::Ok) v = v_shadow_map * c.visibility;   // compose with any shadow map
//   // the pixel-aligned march (the GLSL's sk_contact_shadow_aligned, 2.2-3.4x cheaper on llvmpipe):
//   sk::ContactShadowResult a = sk::contact_shadow_march_aligned(depth, depth_capacity, width, height,
//                                                                proj, view_pos, view * light_world, p);
//   sk::ContactShadowDerived d = sk::contact_shadow_derive(width, height, proj, view_pos, light_view, p);
//   // d.steps, d.bias_world, d.thickness_world, d.depth_step_window: what the march uses here
//
// Conventions. Space: every position and the light are in the camera's VIEW space (right-handed,
// the camera looks down -z); "world" lengths are view-space lengths (a view matrix is rigid, so
// they are world lengths). `proj` is the camera projection (view -> clip) the depth buffer was
// rendered with: perspective, infinite-far (P_inf, far = +inf) or orthographic, GL [-1, 1] or
// zero-to-one clip depth (`clip_depth`), `reversed_z`; its z and w rows must depend on view z only
// (m[0][2] = m[1][2] = m[0][3] = m[1][3] = 0, as every glm/infinite_projection.hpp matrix).
// Buffers: `depth` holds `depth_capacity` float elements; it needs width * height (`needed`):
// window depth in [0, 1] (glDepthRange(0, 1)), row-major, row 0 at the bottom (glReadPixels order,
// texelFetch's y); sample k of a row at pixel center (k + 0.5) / width. Values outside [0, 1],
// NaN and the clear value (1; reversed-Z 0: the background) are "no surface" there. The buffer is
// read, never written; nothing allocates.
// Lights: a light is its homogeneous position `light_position` = (x, y, z, w), as OpenGL's
// GL_POSITION and Everitt & Kilgard use it. w > 0: a point or spot light at xyz / w. w = 0: a
// directional light at infinity in direction xyz, the direction *toward* the light (its rays travel
// along -xyz). w < 0, (0, 0, 0, 0) and NaN/Inf are rejected with Status::InvalidLight.
// Here `light_position` is in view space (view * light_world; for w = 0 the view rotation turns the
// direction). A point light at the receiver has no direction: Status::InvalidLight.
// Results: a struct whose first member is `status`; `Ok` only with finite outputs in their range;
// "the ray left the screen / stayed inside its own pixel" is an outcome (fewer or no steps), never an
// error; a non-Ok result's `detail` names the offending input and the rule ("length_world: not > 0"), a
// static string, nullptr when Ok. Arithmetic: float, operation for operation the GLSL's, so a GL test
// compares them.
//
// The march (and the derivation of every number contact_shadow_derive returns):
//   1. Ray: from the receiver P0 along D = normalize(to light), length L = min(length_world, distance
//      to a point light). Clip space C(t) = proj * (P0 + t L D) is affine in t, so the segment is
//      clipped exactly in clip space against the near plane (z >= -w; z >= 0 zero-to-one; z <= w
//      reversed-Z), w > 0, and the screen (|x| <= w, |y| <= w): a ray toward the camera, behind it,
//      or off screen ends where it leaves the visible frustum.
//   2. Screen: the clipped segment is a straight screen segment of `projected_pixels`; it is sampled
//      uniformly in screen space, one sample per pixel up to `max_steps`, starting one pixel from the
//      receiver (its own pixel holds no occluder); samples outside the hull of the pixel centers
//      (the outer half pixel, where bilinear would extrapolate) are skipped. 1/w is affine in screen space, so the ray's view
//      depth at screen fraction u is exact: t = u w0 / ((1 - u) w1 + u w0) (perspective-correct
//      interpolation, Heckbert & Moreton 1991).
//   3. Depth: the buffer is read bilinearly (4 texels, clamp to edge). The window depth of a plane
//      is affine in screen space (that is why rasterizers interpolate it), so on a plane the bilinear
//      value is the plane's depth at the sample: no self-occlusion from a sample off pixel centers,
//      at any light angle. Window depth -> view z: ndc = (a z + b) / (c z + d) with a = m[2][2],
//      b = m[3][2], c = m[2][3], d = m[3][3], so z = (b - ndc d) / (ndc c - a).
//   4. Hit: the sample is occluded when the buffer's surface is in front of the ray by more than
//      `bias` and less than `thickness`: bias < dist_ray - dist_buffer < thickness (dist = -z).
// Derived, not tuned: bias = 4 depth steps of the format at the buffer's depth, in view distance:
//   d(window)/dz = s (a d - b c) / (c z + d)^2 (s = 1/2 for GL clip depth, 1 for zero-to-one), so one
//   window step dw is dz = dw w^2 / (s |a d - b c|) with w = c z + d; for a GL perspective camera
//   (|a d - b c| = 2 f n / (f - n), w = distance) that is dz = dw d^2 (f - n) / (f n) ~ dw d^2 / n
//   (Akeley & Su, "Minimum triangle separation for correct z-buffer occlusion", 2006). dw = the
//   format's step (1 / (2^24 - 1), 1 / (2^16 - 1) for UNORM 24 / 16, 0 for float32) + 2^-22 |window|
//   (float32 storage and the shader's three lerps: 4 ulp of a window depth in [0.5, 1)).
//   thickness: `thickness_world` or, 0, the march length L: an occluder more than one march length in
//   front of the ray is not a contact occluder (the shadow map has it); +inf = every surface solid.
//   steps: ceil(projected_pixels) clamped to [1, max_steps]; start: 1 pixel from the receiver.
//
// Based on:
//   Bend Studio, "Bend Studio's screen space shadows" (Days Gone), SIGGRAPH 2023
//   Advances in Real-Time Rendering: screen-space march from each pixel toward the light.
//   Unreal Engine "Contact Shadows", Godot 4 and Unity HDRP contact shadows (short march, length and
//   thickness as parameters, composed with the shadow map).
//   K. Akeley, J. Su, "Minimum triangle separation for correct z-buffer occlusion", Graphics Hardware 2006.
//   P. Heckbert, H. Moreton, "Interpolation for polygon texture mapping and shading", 1991.
//
// MIT License. Copyright (c) shadowkit contributors.
#pragma once

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

namespace shadowkit {

#ifndef SHADOWKIT_STATUS_DEFINED
#define SHADOWKIT_STATUS_DEFINED
/// shadowkit's release, major * 10000 + minor * 100 + patch (0.1.0), the same in every header. Whichever
/// header comes first defines this block; a header of another release included with it stops the
/// build (the #error after the block) instead of mixing two definitions silently.
#define SHADOWKIT_VERSION 100
/// Outcome of a shadowkit call: one set for every header. `Ok` is the only success. A result that no
/// call has filled says `NotRun`. What a successful call found (no blocker, a fallback, nothing
/// visible, an edge to skip) is a field of its result, never a status.
enum class Status : std::uint8_t {
    NotRun,            ///< a default-constructed result: no call has filled it
    Ok,                ///< success: every output is finite and means what its comment says
    InvalidArgument,   ///< a value outside its documented range (null pointer with a count, size 0, near >= far, ...)
    NonFinite,         ///< NaN or Inf in an input
    IndexOutOfRange,   ///< a mesh index >= the vertex count
    InvalidLight,      ///< light position NaN/Inf, w < 0, or (0, 0, 0, 0)
    BufferTooSmall,    ///< an output buffer is too small; the result's `needed` says how many elements
    Overflow,          ///< finite input whose result is not representable (beyond float, depth steps collapse)
    LightInsideVolume  ///< a point light inside the receivers' bounds: no single frustum holds them (use a cube map)
};
/// The enumerator's name, for logs and test messages.
inline const char* status_name(Status s) {
    switch (s) {
    case Status::NotRun: return "NotRun";
    case Status::Ok: return "Ok";
    case Status::InvalidArgument: return "InvalidArgument";
    case Status::NonFinite: return "NonFinite";
    case Status::IndexOutOfRange: return "IndexOutOfRange";
    case Status::InvalidLight: return "InvalidLight";
    case Status::BufferTooSmall: return "BufferTooSmall";
    case Status::Overflow: return "Overflow";
    case Status::LightInsideVolume: return "LightInsideVolume";
    }
    return "?";
}
#endif
#if !defined(SHADOWKIT_VERSION) || SHADOWKIT_VERSION != 100
#error "shadowkit: headers of two releases included together (this one is 0.1.0, SHADOWKIT_VERSION 100); vendor the headers of one release"
#endif
#ifndef SHADOWKIT_CLIP_DEPTH_DEFINED
#define SHADOWKIT_CLIP_DEPTH_DEFINED
/// Clip-space depth range of the projection: OpenGL [-1,1] or D3D/Vulkan/glClipControl [0,1].
enum class ClipDepth { NegativeOneToOne, ZeroToOne };
#endif
#ifndef SHADOWKIT_DEPTH_FORMAT_DEFINED
#define SHADOWKIT_DEPTH_FORMAT_DEFINED
/// Depth-buffer storage format.
enum class DepthFormat { Float32, Fixed24, Fixed16 };
#endif

/// The most samples one march takes (`max_steps` range is [1, kContactShadowMaxSteps]).
constexpr int kContactShadowMaxSteps = 256;

/// What the march needs besides the depth buffer and the camera.
struct ContactShadowParams {
    float length_world = 0.0f;     ///< march length toward the light, view units, finite > 0 (required: 0 is rejected)
    int max_steps = 16;            ///< most samples, one per pixel of the projected ray up to this; [1, 256]
    float thickness_world = 0.0f;  ///< assumed occluder thickness, view units, >= 0; 0: derive (= length_world); +inf: solid
    float jitter = 0.0f;           ///< [0, 1): shifts every sample back by jitter steps (per-pixel noise); 0: none
    DepthFormat depth_format = DepthFormat::Fixed24;  ///< the camera depth buffer's format (sets the bias)
    ClipDepth clip_depth = ClipDepth::NegativeOneToOne;
    bool reversed_z = false;       ///< the depth buffer is reversed-Z (1 at near, GL_GREATER)
};

/// The parameters a user does not tune, for one receiver (the header comment derives each).
struct ContactShadowDerived {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    int steps = 0;                  ///< samples the march takes: ceil(projected_pixels) in [1, max_steps]; 0: the ray stays in its own pixel
    float projected_pixels = 0.0f;  ///< screen length of the clipped ray, pixels (>= 0)
    float start_offset_pixels = 0.0f; ///< first sample's distance from the receiver, pixels (1)
    float march_length_world = 0.0f;  ///< length of the ray after the point-light cut and the near/screen clip (>= 0)
    float thickness_world = 0.0f;   ///< the thickness used (> 0, may be +inf only if given +inf)
    float bias_world = 0.0f;        ///< the depth tolerance at the receiver's depth, view units (>= 0)
    float depth_step_window = 0.0f; ///< the format's window-depth step (2^-24 / 2^-16 UNORM; 0 float32): the GLSL's `depth_step`
};

/// The march's outcome at one receiver. Non-Ok results keep visibility 1 (a failed call never darkens).
struct ContactShadowResult {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    float visibility = 1.0f;        ///< 0: a sample hit an occluder, 1: lit by this test (compose: V = V_map * visibility)
    bool hit = false;               ///< true (with Ok): an occluder was found; visibility 0
    float hit_distance_world = 0.0f;///< distance from the receiver along the ray to the first hit, view units (0 without a hit)
    int steps = 0;                  ///< samples taken (the derived count; 0: the ray stayed in its own pixel)
    std::size_t needed = 0;         ///< depth elements the call needs (width * height), set with BufferTooSmall and Ok
};

namespace detail {
inline bool cts_finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
inline bool cts_finite(glm::vec4 v) { return cts_finite(glm::vec3(v)) && std::isfinite(v.w); }
inline bool cts_finite(const glm::mat4& m) { return cts_finite(m[0]) && cts_finite(m[1]) && cts_finite(m[2]) && cts_finite(m[3]); }
inline float cts_format_step(DepthFormat f) {
    if (f == DepthFormat::Fixed24) return 1.0f / 16777215.0f;
    if (f == DepthFormat::Fixed16) return 1.0f / 65535.0f;
    return 0.0f;
}
// The near-plane and w >= 0 functions of a clip point: positive inside.
inline float cts_near(glm::vec4 c, bool zero_to_one, bool reversed_z) {
    return reversed_z ? c.w - c.z : (zero_to_one ? c.z : c.z + c.w);
}
// Everything the march needs before it reads the buffer (the GLSL computes the same, same order).
struct CtsSetup {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    glm::vec2 uv0{0.0f}, uv1{0.0f};  // screen endpoints of the clipped ray
    float w0 = 0.0f, w1 = 0.0f;      // clip w at the endpoints
    float z0 = 0.0f, z1 = 0.0f;      // view z at the endpoints
    float length = 0.0f;             // clipped 3D length
    float pixels = 0.0f;             // screen length in pixels
    float u_start = 1.0f;            // screen fraction of the first sample's base
    int steps = 0;
    float a = 0.0f, b = 0.0f, c = 0.0f, d = 0.0f, inv_sdet = 0.0f;  // z/w rows; 1 / (s |a d - b c|)
    float thickness = 0.0f;
    float depth_step = 0.0f;
    float bias0 = 0.0f;              // bias at the receiver's depth
};
// bias at a depth whose clip w is `w` and window depth `win` (header comment: 4 steps).
inline float cts_bias(float depth_step, float win, float w, float inv_sdet) {
    const float dw = depth_step + 2.38418579e-7f * std::fabs(win);  // 2^-22: 4 float32 ulp in [0.5, 1)
    return 4.0f * dw * (w * w) * inv_sdet;
}
// Where cts_setup's NonFinite / InvalidArgument came from (the first failing input, in its order).
inline const char* cts_nonfinite_why(const glm::mat4& proj, glm::vec3 view_pos, const ContactShadowParams& p) {
    if (!std::isfinite(p.length_world)) return "length_world: NaN or Inf";
    if (std::isnan(p.thickness_world)) return "thickness_world: NaN";
    if (!std::isfinite(p.jitter)) return "jitter: NaN or Inf";
    return !cts_finite(proj) ? "proj: NaN or Inf" : (!cts_finite(view_pos) ? "view_pos: NaN or Inf" : nullptr);
}
inline const char* cts_invalid_why(int width, int height, const ContactShadowParams& p) {
    if (width <= 0 || height <= 0) return "width, height: not > 0";
    if (!(p.length_world > 0.0f)) return "length_world: not > 0";
    if (p.max_steps < 1 || p.max_steps > kContactShadowMaxSteps) return "max_steps: outside [1, 256]";
    if (!(p.thickness_world >= 0.0f)) return "thickness_world: < 0";
    if (!(p.jitter >= 0.0f && p.jitter < 1.0f)) return "jitter: outside [0, 1)";
    if (!(p.depth_format == DepthFormat::Float32 || p.depth_format == DepthFormat::Fixed24 || p.depth_format == DepthFormat::Fixed16))
        return "depth_format: unknown DepthFormat";
    if (p.clip_depth != ClipDepth::ZeroToOne && p.clip_depth != ClipDepth::NegativeOneToOne) return "clip_depth: unknown ClipDepth";
    return "proj: not a projection (x, y feed z or w)";
}
inline CtsSetup cts_setup(int width, int height, const glm::mat4& proj, glm::vec3 view_pos, glm::vec4 light_position,
                        const ContactShadowParams& p) {
    CtsSetup s;
    if (!std::isfinite(p.length_world) || std::isnan(p.thickness_world) || !std::isfinite(p.jitter) ||
        !cts_finite(proj) || !cts_finite(view_pos)) {
        s.status = Status::NonFinite;
        s.detail = cts_nonfinite_why(proj, view_pos, p);
        return s;
    }
    const bool zo = p.clip_depth == ClipDepth::ZeroToOne;
    if (width <= 0 || height <= 0 || !(p.length_world > 0.0f) || p.max_steps < 1 || p.max_steps > kContactShadowMaxSteps ||
        !(p.thickness_world >= 0.0f) || !(p.jitter >= 0.0f && p.jitter < 1.0f) ||
        !(p.depth_format == DepthFormat::Float32 || p.depth_format == DepthFormat::Fixed24 || p.depth_format == DepthFormat::Fixed16) ||
        !(zo || p.clip_depth == ClipDepth::NegativeOneToOne) ||
        proj[0][2] != 0.0f || proj[1][2] != 0.0f || proj[0][3] != 0.0f || proj[1][3] != 0.0f) {
        s.status = Status::InvalidArgument;
        s.detail = cts_invalid_why(width, height, p);
        return s;
    }
    s.a = proj[2][2];
    s.b = proj[3][2];
    s.c = proj[2][3];
    s.d = proj[3][3];
    const float det = s.a * s.d - s.b * s.c;  // d(ndc)/dz = det / w^2
    if (!std::isfinite(det)) { s.status = Status::Overflow; s.detail = "proj: depth rows' determinant beyond float"; return s; }
    if (det == 0.0f) { s.status = Status::InvalidArgument; s.detail = "proj: singular depth rows"; return s; }
    s.inv_sdet = 1.0f / ((zo ? 1.0f : 0.5f) * std::fabs(det));
    if (!std::isfinite(s.inv_sdet)) { s.status = Status::Overflow; s.detail = "proj: depth rows' determinant too small"; return s; }
    // the light
    const glm::vec4 L = light_position;
    if (!cts_finite(L) || L.w < 0.0f || (L.x == 0.0f && L.y == 0.0f && L.z == 0.0f && L.w == 0.0f)) {
        s.status = Status::InvalidLight;
        s.detail = !cts_finite(L) ? "light_position: NaN or Inf" : (L.w < 0.0f ? "light_position: w < 0" : "light_position: (0, 0, 0, 0)");
        return s;
    }
    glm::vec3 to_light = glm::vec3(L);
    if (L.w > 0.0f) {
        const glm::vec3 lp = glm::vec3(L) / L.w;
        if (!cts_finite(lp)) { s.status = Status::Overflow; s.detail = "light_position: xyz / w beyond float"; return s; }
        to_light = lp - view_pos;
        if (!cts_finite(to_light)) { s.status = Status::Overflow; s.detail = "light_position: direction beyond float"; return s; }
    }
    const float m = std::fmax(std::fabs(to_light.x), std::fmax(std::fabs(to_light.y), std::fabs(to_light.z)));
    if (!(m > 0.0f)) { s.status = Status::InvalidLight; s.detail = "light_position: at the receiver (no direction)"; return s; }
    const glm::vec3 scaled = to_light / m;
    const float sl = std::sqrt(scaled.x * scaled.x + scaled.y * scaled.y + scaled.z * scaled.z);
    const glm::vec3 dir = scaled / sl;
    float len = p.length_world;
    if (L.w > 0.0f) len = std::fmin(len, m * sl);  // never march past a point light
    if (!std::isfinite(len)) { s.status = Status::Overflow; s.detail = "length_world: march length beyond float"; return s; }
    const glm::vec3 p1 = view_pos + dir * len;
    const glm::vec4 c0 = proj * glm::vec4(view_pos, 1.0f);
    glm::vec4 c1 = proj * glm::vec4(p1, 1.0f);
    if (!cts_finite(p1) || !cts_finite(c0) || !cts_finite(c1)) { s.status = Status::Overflow; s.detail = "view_pos: clip coordinates beyond float"; return s; }
    // the receiver must be visible: in front of the near plane, w > 0, on screen
    const float f0[6] = {cts_near(c0, zo, p.reversed_z), c0.w, c0.w - c0.x, c0.w + c0.x, c0.w - c0.y, c0.w + c0.y};
    const float f1[6] = {cts_near(c1, zo, p.reversed_z), c1.w, c1.w - c1.x, c1.w + c1.x, c1.w - c1.y, c1.w + c1.y};
    if (!(f0[0] > 0.0f) || !(f0[1] > 0.0f) || !(f0[2] >= 0.0f) || !(f0[3] >= 0.0f) || !(f0[4] >= 0.0f) || !(f0[5] >= 0.0f)) {
        s.status = Status::InvalidArgument;
        s.detail = "view_pos: not visible (behind the near plane or off screen)";
        return s;
    }
    float t_end = 1.0f;
    for (int k = 0; k < 6; ++k)
        if (f1[k] < 0.0f) t_end = std::fmin(t_end, f0[k] / (f0[k] - f1[k]));
    c1 = c0 + (c1 - c0) * t_end;
    s.w0 = c0.w;
    s.w1 = c1.w;
    s.z0 = view_pos.z;
    s.z1 = view_pos.z + (p1.z - view_pos.z) * t_end;
    s.length = len * t_end;
    s.uv0 = glm::vec2(c0.x / c0.w, c0.y / c0.w) * 0.5f + 0.5f;
    s.uv1 = glm::vec2(c1.x / c1.w, c1.y / c1.w) * 0.5f + 0.5f;
    const glm::vec2 px = (s.uv1 - s.uv0) * glm::vec2(static_cast<float>(width), static_cast<float>(height));
    s.pixels = std::sqrt(px.x * px.x + px.y * px.y);
    s.thickness = p.thickness_world > 0.0f ? p.thickness_world : p.length_world;
    s.depth_step = cts_format_step(p.depth_format);
    if (s.pixels > 1.0f) {  // else (NaN too: w1 = 0 at the clip) the ray stays in its own pixel: no samples
        s.u_start = 1.0f / s.pixels;
        s.steps = static_cast<int>(std::fmin(std::ceil(s.pixels), static_cast<float>(p.max_steps)));
    } else {
        s.pixels = std::isfinite(s.pixels) ? s.pixels : 0.0f;
    }
    // the bias at the receiver's own depth: ndc = (a z + b) / (c z + d), w = c z + d
    const float wr = s.c * view_pos.z + s.d;
    const float ndc0 = (s.a * view_pos.z + s.b) / wr;
    s.bias0 = cts_bias(s.depth_step, zo ? ndc0 : ndc0 * 0.5f + 0.5f, wr, s.inv_sdet);
    if (!std::isfinite(s.length) || !std::isfinite(s.pixels) || !std::isfinite(s.bias0)) {
        s.status = Status::Overflow;
        s.detail = "proj, view_pos: march length, pixels or bias beyond float";
        return s;
    }
    s.status = Status::Ok;
    return s;
}
// Bilinear window depth at uv; NaN outside the hull of the pixel centers (there bilinear is not
// exact on a plane: no sample), when a texel is outside [0, 1] or NaN, or when a texel is the
// clear value `clear` (1, reversed-Z 0: the background): no surface there.
inline float cts_depth_bilinear(const float* depth, int width, int height, glm::vec2 uv, float clear) {
    const float x = uv.x * static_cast<float>(width) - 0.5f;
    const float y = uv.y * static_cast<float>(height) - 0.5f;
    if (!(x >= 0.0f && x <= static_cast<float>(width - 1) && y >= 0.0f && y <= static_cast<float>(height - 1)))
        return std::numeric_limits<float>::quiet_NaN();
    const float fx0 = std::floor(x), fy0 = std::floor(y);
    const float fx = x - fx0, fy = y - fy0;
    const int x0 = static_cast<int>(fx0), y0 = static_cast<int>(fy0);
    auto clampi = [](int v, int hi) { return v < 0 ? 0 : (v > hi ? hi : v); };
    const int xa = clampi(x0, width - 1), xb = clampi(x0 + 1, width - 1);
    const int ya = clampi(y0, height - 1), yb = clampi(y0 + 1, height - 1);
    const std::size_t w = static_cast<std::size_t>(width);
    const float d00 = depth[static_cast<std::size_t>(ya) * w + static_cast<std::size_t>(xa)];
    const float d10 = depth[static_cast<std::size_t>(ya) * w + static_cast<std::size_t>(xb)];
    const float d01 = depth[static_cast<std::size_t>(yb) * w + static_cast<std::size_t>(xa)];
    const float d11 = depth[static_cast<std::size_t>(yb) * w + static_cast<std::size_t>(xb)];
    if (!(d00 >= 0.0f && d00 <= 1.0f && d10 >= 0.0f && d10 <= 1.0f && d01 >= 0.0f && d01 <= 1.0f && d11 >= 0.0f && d11 <= 1.0f))
        return std::numeric_limits<float>::quiet_NaN();
    if (d00 == clear || d10 == clear || d01 == clear || d11 == clear) return std::numeric_limits<float>::quiet_NaN();
    const float lo = d00 + (d10 - d00) * fx;
    const float hi = d01 + (d11 - d01) * fx;
    return lo + (hi - lo) * fy;
}
} // namespace detail

/// The derived parameters (bias, thickness, step count, start offset, clipped length) for the
/// receiver `view_pos` seen through `proj` on a width x height depth buffer, lit by `light_position`
/// (view space). Same validation as contact_shadow_march, without the buffer: NonFinite for NaN/Inf
/// in params, proj or view_pos; InvalidArgument for width or height <= 0, length_world <= 0,
/// max_steps outside [1, 256], thickness_world < 0, jitter outside [0, 1), an unknown enum, a
/// projection whose z/w rows depend on x or y or whose depth does not vary (a d - b c = 0), and a
/// receiver not in front of the near plane or off screen; InvalidLight for the light (and a point
/// light at the receiver); Overflow when finite input overflows float.
inline ContactShadowDerived contact_shadow_derive(int width, int height, const glm::mat4& proj, glm::vec3 view_pos,
                                                  glm::vec4 light_position, const ContactShadowParams& params) {
    ContactShadowDerived r;
    const detail::CtsSetup s = detail::cts_setup(width, height, proj, view_pos, light_position, params);
    if (s.status != Status::Ok) { r.status = s.status; r.detail = s.detail; return r; }
    r.steps = s.steps;
    r.projected_pixels = s.pixels;
    r.start_offset_pixels = 1.0f;
    r.march_length_world = s.length;
    r.thickness_world = s.thickness;
    r.bias_world = s.bias0;
    r.depth_step_window = s.depth_step;
    r.status = Status::Ok;
    return r;
}

/// Contact-shadow visibility of the receiver `view_pos` (view space, the point the depth buffer
/// shows at its pixel): marches from it toward `light_position` (view space) in the camera depth
/// buffer `depth` (window depth, width x height, row 0 at the bottom, rendered with `proj`), the
/// same arithmetic as sk_contact_shadow in glsl/contact_shadow.glsl. `depth` holds `depth_capacity`
/// float elements; it needs width * height (`needed`). Statuses: those of contact_shadow_derive,
/// plus InvalidArgument for a null `depth` and BufferTooSmall (with `needed`) for depth_capacity <
/// width * height. Ok: visibility is exactly 0 (hit) or 1. No allocation.
inline ContactShadowResult contact_shadow_march(const float* depth, std::size_t depth_capacity, int width, int height,
                                                const glm::mat4& proj, glm::vec3 view_pos, glm::vec4 light_position,
                                                const ContactShadowParams& params) {
    ContactShadowResult r;
    const detail::CtsSetup s = detail::cts_setup(width, height, proj, view_pos, light_position, params);
    if (s.status != Status::Ok) { r.status = s.status; r.detail = s.detail; return r; }
    r.needed = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    if (depth == nullptr) { r.status = Status::InvalidArgument; r.detail = "depth: null"; return r; }
    if (depth_capacity < r.needed) { r.status = Status::BufferTooSmall; r.detail = "depth_capacity: below width * height (see needed)"; return r; }
    const bool zo = params.clip_depth == ClipDepth::ZeroToOne;
    for (int i = 0; i < s.steps; ++i) {
        // screen fraction of sample i: from one pixel past the receiver to the clipped end
        const float u = s.u_start + (1.0f - s.u_start) * (static_cast<float>(i) + 1.0f - params.jitter) / static_cast<float>(s.steps);
        const glm::vec2 uv = s.uv0 + (s.uv1 - s.uv0) * u;
        const float t = u * s.w0 / ((1.0f - u) * s.w1 + u * s.w0);  // perspective-correct fraction of the 3D ray
        const float dist_ray = -(s.z0 + (s.z1 - s.z0) * t);
        const float win = detail::cts_depth_bilinear(depth, width, height, uv, params.reversed_z ? 0.0f : 1.0f);
        const float ndc = zo ? win : win * 2.0f - 1.0f;
        const float z_buf = (s.b - ndc * s.d) / (ndc * s.c - s.a);
        const float w_buf = s.c * z_buf + s.d;
        const float bias = detail::cts_bias(s.depth_step, win, w_buf, s.inv_sdet);
        const float delta = dist_ray + z_buf;  // dist_ray - dist_buffer, dist = -z
        if (delta > bias && delta < s.thickness) {  // NaN (no surface, w = 0) compares false: no hit
            r.hit = true;
            r.visibility = 0.0f;
            r.hit_distance_world = s.length * t;
            break;
        }
    }
    r.steps = s.steps;
    r.status = Status::Ok;
    return r;
}

namespace detail {
// The pixel-aligned march's state (sk_contact_aligned_setup in the GLSL; the same float arithmetic,
// operation for operation). Sample k (0 .. count - 1) is at texel-index position p + k dp.
struct CtsAligned {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    glm::vec2 p{0.0f}, dp{0.0f};      // first sample (whole pixel along the major axis), one step
    float win = 0.0f, dwin = 0.0f;    // the ray's window depth at the first sample, per step
    float iw = 0.0f, diw = 0.0f;      // the ray's 1 / clip w at the first sample, per step
    float thick_k = 0.0f;             // thickness * s |a d - b c|
    float bias_k = 0.0f;              // 4 depth steps
    bool xmajor = true;               // x is the major axis (the minor axis is y)
    int count = 0;                    // samples (0: nothing to march)
    float u1 = 0.0f, du = 0.0f;       // screen fraction of the first sample, of one step
    float w0 = 0.0f, w1 = 0.0f, length = 0.0f;  // clip w at the ends, the clipped 3D length
};
inline CtsAligned cts_aligned_setup(int width, int height, const glm::mat4& proj, glm::vec3 view_pos,
                                    glm::vec4 light_position, const ContactShadowParams& p) {
    CtsAligned r;
    const CtsSetup s = cts_setup(width, height, proj, view_pos, light_position, p);  // validation, statuses
    r.status = s.status;
    r.detail = s.detail;
    if (s.status != Status::Ok) return r;
    const bool zo = p.clip_depth == ClipDepth::ZeroToOne;
    const float det = proj[2][2] * proj[3][3] - proj[3][2] * proj[2][3];
    const glm::vec4 L = light_position;
    const glm::vec3 to_light = L.w > 0.0f ? glm::vec3(L) * (1.0f / L.w) - view_pos : glm::vec3(L);
    const float m = std::fmax(std::fabs(to_light.x), std::fmax(std::fabs(to_light.y), std::fabs(to_light.z)));
    const glm::vec3 scaled = to_light * (1.0f / m);
    const float sl = std::sqrt(scaled.x * scaled.x + scaled.y * scaled.y + scaled.z * scaled.z);
    const float len = L.w > 0.0f ? std::fmin(p.length_world, m * sl) : p.length_world;
    const glm::vec4 c0 = proj * glm::vec4(view_pos, 1.0f);
    glm::vec4 c1 = c0 + proj * glm::vec4(scaled * (len / sl), 0.0f);
    const float f0 = cts_near(c0, zo, p.reversed_z), f1 = cts_near(c1, zo, p.reversed_z);
    float t_end = f1 < 0.0f ? f0 / (f0 - f1) : 1.0f;  // near plane and w = 0 only
    if (c1.w < 0.0f) t_end = std::fmin(t_end, c0.w / (c0.w - c1.w));
    c1 = c0 + (c1 - c0) * t_end;
    const float iw0 = 1.0f / c0.w, iw1 = 1.0f / c1.w;
    const glm::vec2 fs(static_cast<float>(width), static_cast<float>(height));
    const glm::vec2 q0 = (glm::vec2(c0.x, c0.y) * iw0 * 0.5f + 0.5f) * fs - 0.5f;
    const glm::vec2 dq = (glm::vec2(c1.x, c1.y) * iw1 * 0.5f + 0.5f) * fs - 0.5f - q0;
    const float win0 = zo ? c0.z * iw0 : c0.z * iw0 * 0.5f + 0.5f;
    const float dwin = (zo ? c1.z * iw1 : c1.z * iw1 * 0.5f + 0.5f) - win0;
    const float diw = iw1 - iw0;
    r.xmajor = std::fabs(dq.x) >= std::fabs(dq.y);
    const float qm = r.xmajor ? q0.x : q0.y, dm = r.xmajor ? dq.x : dq.y, n = std::fabs(dm);
    r.w0 = c0.w;
    r.w1 = c1.w;
    r.length = len * t_end;
    if (!(n >= 1.0f) || !std::isfinite(n) || !std::isfinite(dq.x + dq.y) || !std::isfinite(dwin) || !std::isfinite(diw))
        return r;  // the ray stays within a pixel of its receiver: no samples (Ok, lit)
    const float base = std::floor(qm + 0.5f);
    const float sgn = dm > 0.0f ? 1.0f : -1.0f;
    const float e = (qm - base) * sgn;
    const float stride = std::fmax(std::ceil(n / static_cast<float>(p.max_steps)), 1.0f);
    const float jit = std::fmin(p.jitter, 0.999f);
    const float shift = std::fmin(std::floor(jit * stride), stride - 1.0f);
    const float q = (n + e + shift) / stride;  // in [0.5, max_steps + 1) but for overflow (inf: max_steps)
    r.count = q < static_cast<float>(p.max_steps) ? static_cast<int>(std::floor(q)) : p.max_steps;
    const float inv_dm = 1.0f / dm;
    const float j1 = base + sgn * (stride - shift);
    r.u1 = (j1 - qm) * inv_dm;
    r.du = sgn * stride * inv_dm;
    r.p = r.xmajor ? glm::vec2(j1, q0.y + dq.y * r.u1) : glm::vec2(q0.x + dq.x * r.u1, j1);
    r.dp = r.xmajor ? glm::vec2(sgn * stride, dq.y * r.du) : glm::vec2(dq.x * r.du, sgn * stride);
    r.win = win0 + dwin * r.u1;
    r.dwin = dwin * r.du;
    r.iw = iw0 + diw * r.u1;
    r.diw = diw * r.du;
    const float thickness = p.thickness_world > 0.0f ? p.thickness_world : p.length_world;
    r.thick_k = thickness * ((zo ? 1.0f : 0.5f) * std::fabs(det));
    r.bias_k = 4.0f * s.depth_step;
    return r;
}
// Sample k of the aligned march (sk_contact_aligned_sample): true on a hit.
inline bool cts_aligned_sample(const float* depth, int width, int height, const CtsAligned& r, float k, bool reversed_z) {
    const glm::vec2 p = r.p + r.dp * k;
    if (!(p.x >= 0.0f && p.y >= 0.0f && p.x <= static_cast<float>(width - 1) && p.y <= static_cast<float>(height - 1)))
        return false;
    const float flx = std::floor(p.x), fly = std::floor(p.y);
    const int x0 = static_cast<int>(flx), y0 = static_cast<int>(fly);
    const int x1 = r.xmajor ? x0 : std::min(x0 + 1, width - 1);
    const int y1 = r.xmajor ? std::min(y0 + 1, height - 1) : y0;
    const float f = r.xmajor ? p.y - fly : p.x - flx;
    const std::size_t w = static_cast<std::size_t>(width);
    const float d0 = depth[static_cast<std::size_t>(y0) * w + static_cast<std::size_t>(x0)];
    const float d1 = depth[static_cast<std::size_t>(y1) * w + static_cast<std::size_t>(x1)];
    const float win_buf = d0 + (d1 - d0) * f;
    const float win_ray = r.win + r.dwin * k;
    const float iw = r.iw + r.diw * k;
    const float diff = reversed_z ? win_buf - win_ray : win_ray - win_buf;
    const bool surface = reversed_z ? (d0 > 0.0f && d0 <= 1.0f && d1 > 0.0f && d1 <= 1.0f)
                                    : (d0 >= 0.0f && d0 < 1.0f && d1 >= 0.0f && d1 < 1.0f);
    return surface && diff > r.bias_k + 9.53674316e-7f * win_buf && diff < r.thick_k * (iw * iw);
}
} // namespace detail

/// Contact-shadow visibility with the pixel-aligned march, the CPU mirror of
/// sk_contact_shadow_aligned (glsl/contact_shadow.glsl; docs/contact_shadow.md measures it against
/// contact_shadow_march). Same inputs, statuses and result as contact_shadow_march; what differs is
/// where it samples and how it compares (the GLSL's comment derives it): samples on whole pixels of
/// the ray's major screen axis, every stride = ceil(major pixels / max_steps) pixels, starting at the
/// first pixel past the receiver's (moved back int(jitter * stride) pixels); the depth of the two
/// texels around the ray in that column (row), interpolated along the minor axis (exact on planes);
/// a hit when bias < window_ray - window_buffer < thickness * d(window)/dz at the ray's depth, bias =
/// 4 depth steps + 2^-20 window (reversed-Z: the difference the other way). The ray is clipped at the
/// near plane and w = 0 only; samples off screen find no surface. `steps` = the samples it takes,
/// `hit_distance_world` the hit sample's distance along the 3D ray. No allocation.
inline ContactShadowResult contact_shadow_march_aligned(const float* depth, std::size_t depth_capacity, int width, int height,
                                                        const glm::mat4& proj, glm::vec3 view_pos, glm::vec4 light_position,
                                                        const ContactShadowParams& params) {
    ContactShadowResult res;
    const detail::CtsAligned r = detail::cts_aligned_setup(width, height, proj, view_pos, light_position, params);
    if (r.status != Status::Ok) { res.status = r.status; res.detail = r.detail; return res; }
    res.needed = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    if (depth == nullptr) { res.status = Status::InvalidArgument; res.detail = "depth: null"; return res; }
    if (depth_capacity < res.needed) {
        res.status = Status::BufferTooSmall;
        res.detail = "depth_capacity: below width * height (see needed)";
        return res;
    }
    for (int k = 0; k < r.count; ++k) {
        if (!detail::cts_aligned_sample(depth, width, height, r, static_cast<float>(k), params.reversed_z)) continue;
        const float u = r.u1 + r.du * static_cast<float>(k);  // screen fraction -> 3D fraction (1/w affine)
        const float t = u * r.w0 / ((1.0f - u) * r.w1 + u * r.w0);
        res.hit = true;
        res.visibility = 0.0f;
        res.hit_distance_world = std::isfinite(t) ? std::fmax(r.length * t, 0.0f) : 0.0f;
        break;
    }
    res.steps = r.count;
    res.status = Status::Ok;
    return res;
}

} // namespace shadowkit
