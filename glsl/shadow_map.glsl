// shadowkit/glsl/shadow_map.glsl - plain shadow-map lookups (Williams 1978): the shadow coordinate, a spot/directional map and a point light's cube map, with a depth bias
// versions: 330, 450
// stages: fragment
//
// Inputs: the world-space position of the shaded point; the light's view-projection matrix (the
// one the map was rendered with); `bias`, in window-depth units, subtracted from the receiver's
// depth before the compare (added with SK_REVERSED_Z): 0.0 for none. A window-depth bias is a
// world bias times the depth metric's slope (shadowkit/shadow_bias.hpp: bias_depth_metric_slope;
// bias_depth_metric_resolution is the smallest useful one); for a perspective light the same
// window bias is a world bias growing with the distance squared, so pair a small constant with
// normal offset (bias_normal_offset_position: look the map up at world_pos + normal * offset) or
// with glPolygonOffset when rendering the map (bias_polygon_offset). docs/shadow_map.md has numbers.
// zero_to_one: true when the projection was built for glClipControl(..., GL_ZERO_TO_ONE).
// Defines: SK_REVERSED_Z before this snippet for reversed-Z maps (1 at near, compare GL_GEQUAL).
// Lights: sk_cube_visibility_hardware_depth takes `vec4 light_position` as the shadowkit headers do
// (w > 0: a point light at xyz / w; a cube map needs a point light: other w give 1.0, lit).
// Cubes: sk_cube_visibility_hardware_depth reads a cube of window depth (perspective faces). A cube of
// distance / range (omni_shadow.glsl) needs omni_shadow.glsl's sk_cube_visibility_distance.
// Uniforms: none required (pass the values above).
// GL state: the map is a depth texture (GL_DEPTH_COMPONENT24 / 32F) rendered with depth test
// GL_LESS (GL_GREATER reversed) and cleared to 1 (reversed: 0); sampled as sampler2DShadow /
// samplerCubeShadow with GL_TEXTURE_COMPARE_MODE = GL_COMPARE_REF_TO_TEXTURE, GL_TEXTURE_COMPARE_FUNC
// GL_LEQUAL (GL_GEQUAL reversed-Z), GL_LINEAR for the hardware 2x2 percentage-closer filter
// (GL_NEAREST: one texel, hard), GL_CLAMP_TO_EDGE; GL_TEXTURE_CUBE_MAP_SEAMLESS for cube maps.
// Returns 1 = lit, 0 = shadowed (fractions at the 2x2 filter's edges); points outside the light
// frustum get `outside`.
// Automatic bias (the default; shadowkit/shadow_bias.hpp bias_auto_lookup is its CPU mirror and
// derivation): sk_shadow_map_visibility_auto takes the receiver's world normal instead of a bias. It
// compares each of the 2x2 filter's four texel centres with the receiver plane's own depth there
// (the plane's window-depth gradient comes from the normal through the light's projection), so it
// needs no slope-scaled bias and no polygon offset; what is left is `depth_step`, the map format's
// window-depth step (1/65535 for 16-bit, 1/16777215 for 24-bit, 0.0 for float32: float rounding is
// added either way). No constant depends on the scene. Render the map WITHOUT glPolygonOffset.
// Usage:
//   float v = sk_shadow_map_visibility(u_shadow_map, u_light_view_proj, world_pos, false, 1e-4, 1.0);
//   float v = sk_shadow_map_visibility_auto(u_shadow_map, u_light_view_proj, world_pos, world_normal,
//                                           false, 0.0, 1.0);   // float32 map, automatic bias
//   float v = sk_cube_visibility_hardware_depth_auto(u_cube, light_position, world_pos, world_normal,
//                                                    near_z, far_z, 0.0);   // a point light's cube
// MIT License. Copyright (c) shadowkit contributors.

// Shadow-map coordinates (uv in [0,1], depth in window space) of a world point, and clip w.
vec4 sk_shadow_coord(mat4 light_view_proj, vec3 world_pos, bool zero_to_one) {
    vec4 clip = light_view_proj * vec4(world_pos, 1.0);
    vec3 ndc = clip.xyz / clip.w;
    vec3 win = vec3(ndc.xy * 0.5 + 0.5, zero_to_one ? ndc.z : ndc.z * 0.5 + 0.5);
    return vec4(win, clip.w);
}

// Lit fraction of world_pos: one compare of the biased receiver depth (2x2 with GL_LINEAR).
float sk_shadow_map_visibility(sampler2DShadow shadow_map, mat4 light_view_proj, vec3 world_pos,
                               bool zero_to_one, float bias_window, float outside) {
    vec4 c = sk_shadow_coord(light_view_proj, world_pos, zero_to_one);
    if (c.w <= 0.0 || any(lessThan(c.xy, vec2(0.0))) || any(greaterThan(c.xy, vec2(1.0))) || c.z > 1.0 || c.z < 0.0)
        return outside;
#ifdef SK_REVERSED_Z
    return texture(shadow_map, vec3(c.xy, c.z + bias_window));
#else
    return texture(shadow_map, vec3(c.xy, c.z - bias_window));
#endif
}

// Cube shadow map of HARDWARE DEPTH: a point light's cube rendered with six 90-degree perspective
// faces sharing near/far (GL clip depth, not reversed), each texel the face's window depth. A cube
// storing distance / range (omni_shadow.glsl's depth pass) is read with omni_shadow.glsl's
// sk_cube_visibility_distance instead: this function on that map compiles and is wrong almost
// everywhere. (Its old name sk_cube_shadow_visibility fails to compile, naming this one.) The
// reference depth is the face's window depth of the major-axis distance,
// ndc_z = (f + n)/(f - n) - 2 f n / ((f - n) d) (glFrustum's P[2][2], P[2][3]), minus `bias_window`.
#define sk_cube_shadow_visibility sk_cube_shadow_visibility_renamed_to_sk_cube_visibility_hardware_depth
float sk_cube_visibility_hardware_depth(samplerCubeShadow shadow_map, vec4 light_position, vec3 world_pos,
                                        float near_z, float far_z, float bias_window) {
    if (!(light_position.w > 0.0)) return 1.0;
    vec3 d = world_pos - light_position.xyz / light_position.w;
    float major = max(abs(d.x), max(abs(d.y), abs(d.z)));
    float f = far_z;
    float n = near_z;
    float ndc_z = (f + n) / (f - n) - 2.0 * f * n / ((f - n) * major);
    return texture(shadow_map, vec4(d, ndc_z * 0.5 + 0.5 - bias_window));
}

// ---- automatic bias ----------------------------------------------------------------------------
// Window-depth gradient (dz/du, dz/dv) of the plane through world_pos with normal `normal` in the map
// of light_view_proj: the receiver plane of Isidoro 2006, from the normal instead of screen
// derivatives (no error across silhouettes, any stage). The Jacobian of (uv, z) at world_pos is the
// quotient rule d(c_i / c_w)/dp = (row_i - ndc_i row_w) / c_w, applied to two tangents of the plane;
// the 2x2 solve gives dz/duv. .z: the solve's conditioning |det| / scale in (0, 1], 0 when the plane
// (nearly) contains the light ray through world_pos (edge-on: no finite gradient; .xy = 0). .w: the
// window depth that 4 float ulps of world_pos's coordinates move it by (a G-buffer's position is
// rounded: 2^-21 |p|_1 |dz/dp|_1), part of the margin.
vec4 sk_plane_depth_gradient(mat4 light_view_proj, vec3 world_pos, vec3 normal, bool zero_to_one) {
    vec4 c = light_view_proj * vec4(world_pos, 1.0);
    vec3 ndc = c.xyz / c.w;
    vec3 rw = vec3(light_view_proj[0][3], light_view_proj[1][3], light_view_proj[2][3]);
    vec3 jx = (vec3(light_view_proj[0][0], light_view_proj[1][0], light_view_proj[2][0]) - ndc.x * rw) / c.w;
    vec3 jy = (vec3(light_view_proj[0][1], light_view_proj[1][1], light_view_proj[2][1]) - ndc.y * rw) / c.w;
    vec3 jz = (vec3(light_view_proj[0][2], light_view_proj[1][2], light_view_proj[2][2]) - ndc.z * rw) / c.w;
    float zs = zero_to_one ? 1.0 : 0.5;
    vec3 ap = abs(world_pos);
    vec3 ajz = abs(jz);
    float pos_err = 4.76837158e-7 * (ap.x + ap.y + ap.z) * (ajz.x + ajz.y + ajz.z) * zs;
    vec3 n = normalize(normal);
    vec3 an = abs(n);
    vec3 axis = an.x <= an.y && an.x <= an.z ? vec3(1.0, 0.0, 0.0) : (an.y <= an.z ? vec3(0.0, 1.0, 0.0) : vec3(0.0, 0.0, 1.0));
    vec3 t1 = normalize(cross(n, axis));
    vec3 t2 = cross(n, t1);
    vec3 s1 = vec3(0.5 * dot(jx, t1), 0.5 * dot(jy, t1), zs * dot(jz, t1));
    vec3 s2 = vec3(0.5 * dot(jx, t2), 0.5 * dot(jy, t2), zs * dot(jz, t2));
    float det = s1.x * s2.y - s1.y * s2.x;
    float scale = (abs(s1.x) + abs(s1.y)) * (abs(s2.x) + abs(s2.y));
    float cond = scale > 0.0 ? abs(det) / scale : 0.0;
    if (!(cond > 1e-4)) return vec4(0.0, 0.0, 0.0, pos_err);
    return vec4((s2.y * s1.z - s1.y * s2.z) / det, (s1.x * s2.z - s2.x * s1.z) / det, cond, pos_err);
}

// The automatic bias's margin in window depth at receiver depth z (shadow_bias.hpp bias_auto_epsilon,
// where it is derived): two steps of the map's format, float rounding of the depths (2^-21 of |z|,
// plus 2^-21 for standard depth, whose transform rounds at the scale of 1), twice the receiver
// position's rounding (g.w), and over one texel of the plane's slope |g| texel: 1/8 for the creases
// of tessellated meshes, plus the float error of the extrapolation (2^-20 + 2^-22 / conditioning).
// g: sk_plane_depth_gradient.
float sk_auto_bias_epsilon(vec4 g, vec2 texel_uv, float z, float depth_step) {
#ifdef SK_REVERSED_Z
    float float_term = 4.76837158e-7 * abs(z) + 1.17549435e-38;
#else
    float float_term = 4.76837158e-7 * (1.0 + abs(z));
#endif
    float plane = abs(g.x) * texel_uv.x + abs(g.y) * texel_uv.y;
    return 2.0 * max(depth_step, 0.0) + float_term + 2.0 * g.w + plane * (0.125 + 9.53674316e-7 + 2.38418579e-7 / max(g.z, 1e-4));
}

// The four taps of the automatic bias: the texel centres around c.xy (c from sk_shadow_coord) in a
// map of `size` texels, their bilinear weights, and the reference depth of each: the receiver plane's
// depth at that centre minus epsilon (plus with SK_REVERSED_Z), clamped to [0, 1]. tap_uv: (i, j),
// (i+1, j), (i, j+1), (i+1, j+1).
void sk_auto_bias_taps(vec4 c, vec4 g, vec2 size, float depth_step, out vec2 tap_uv[4], out vec4 tap_z, out vec4 weight) {
    vec2 texel = 1.0 / size;
    vec2 f = c.xy * size - 0.5;
    vec2 i0 = floor(f);
    vec2 w = f - i0;
    float eps = sk_auto_bias_epsilon(g, texel, c.z, depth_step);
    for (int k = 0; k < 4; ++k) {
        vec2 centre = (i0 + vec2(float(k & 1), float(k >> 1)) + 0.5) * texel;
        tap_uv[k] = centre;
        float zp = c.z + dot(g.xy, centre - c.xy);
#ifdef SK_REVERSED_Z
        tap_z[k] = clamp(zp + eps, 0.0, 1.0);
#else
        tap_z[k] = clamp(zp - eps, 0.0, 1.0);
#endif
    }
    weight = vec4((1.0 - w.x) * (1.0 - w.y), w.x * (1.0 - w.y), (1.0 - w.x) * w.y, w.x * w.y);
}

// The automatic bias's lookup of world_pos in a map of `size` texels: true with its four taps, or
// false when no compare is needed, with `v` the value then (behind the light or outside the map:
// `outside`; an edge-on receiver: 1.0).
bool sk_auto_bias_lookup(mat4 light_view_proj, vec3 world_pos, vec3 normal, bool zero_to_one, vec2 size, float depth_step,
                         float outside, out float v, out vec2 uv[4], out vec4 z, out vec4 w) {
    vec4 c = sk_shadow_coord(light_view_proj, world_pos, zero_to_one);
    v = outside;
    if (c.w <= 0.0 || any(lessThan(c.xy, vec2(0.0))) || any(greaterThan(c.xy, vec2(1.0))) || c.z > 1.0 || c.z < 0.0)
        return false;
    vec4 g = sk_plane_depth_gradient(light_view_proj, world_pos, normal, zero_to_one);
    v = 1.0;
    if (g.z == 0.0) return false;
    sk_auto_bias_taps(c, g, size, depth_step, uv, z, w);
    return true;
}

// Lit fraction of world_pos with the automatic bias: the 2x2 bilinear filter done as four compares at
// texel centres, each against the receiver plane's depth there. `normal`: the receiver's geometric
// world normal (any length, either side). Points outside the map (or behind the light) get `outside`;
// an edge-on receiver (its plane contains the light ray: N.L = 0) gets 1.0. Any filter mode works
// (the taps sit on texel centres); GL_NEAREST is cheapest.
float sk_shadow_map_visibility_auto(sampler2DShadow shadow_map, mat4 light_view_proj, vec3 world_pos, vec3 normal,
                                    bool zero_to_one, float depth_step, float outside) {
    float v;
    vec2 uv[4];
    vec4 z, w;
    if (!sk_auto_bias_lookup(light_view_proj, world_pos, normal, zero_to_one, vec2(textureSize(shadow_map, 0)), depth_step,
                             outside, v, uv, z, w))
        return v;
    return w.x * texture(shadow_map, vec3(uv[0], z.x)) + w.y * texture(shadow_map, vec3(uv[1], z.y)) +
           w.z * texture(shadow_map, vec3(uv[2], z.z)) + w.w * texture(shadow_map, vec3(uv[3], z.w));
}

// The same for one layer of a depth array (sampled area lights, cascades).
float sk_shadow_map_visibility_auto(sampler2DArrayShadow shadow_maps, float layer, mat4 light_view_proj, vec3 world_pos,
                                    vec3 normal, bool zero_to_one, float depth_step, float outside) {
    float v;
    vec2 uv[4];
    vec4 z, w;
    if (!sk_auto_bias_lookup(light_view_proj, world_pos, normal, zero_to_one, vec2(textureSize(shadow_maps, 0).xy),
                             depth_step, outside, v, uv, z, w))
        return v;
    return w.x * texture(shadow_maps, vec4(uv[0], layer, z.x)) + w.y * texture(shadow_maps, vec4(uv[1], layer, z.y)) +
           w.z * texture(shadow_maps, vec4(uv[2], layer, z.z)) + w.w * texture(shadow_maps, vec4(uv[3], layer, z.w));
}

// ---- automatic bias for a cube of hardware depth ----------------------------------------------------
// The face a direction d is read from (GL 4.5 spec 8.13: the major axis) as the frame its 90-degree
// face was rendered with: lookAt(L, L + fwd, hint), hints (0, -1, 0) for +-x and +-z, (0, 0, +-1) for
// +-y; right = NDC +x (texture s), up = NDC +y (texture t).
void sk_cube_face_frame(vec3 d, out vec3 fwd, out vec3 right, out vec3 up) {
    vec3 a = abs(d);
    vec3 hint = vec3(0.0, -1.0, 0.0);
    if (a.x >= a.y && a.x >= a.z) {
        fwd = vec3(d.x >= 0.0 ? 1.0 : -1.0, 0.0, 0.0);
    } else if (a.y >= a.z) {
        fwd = vec3(0.0, d.y >= 0.0 ? 1.0 : -1.0, 0.0);
        hint = vec3(0.0, 0.0, fwd.y);
    } else {
        fwd = vec3(0.0, 0.0, d.z >= 0.0 ? 1.0 : -1.0);
    }
    right = cross(fwd, hint);
    up = cross(right, fwd);
}

// The view-projection of that face: perspective(90 degrees, 1, near, far) * lookAt (GL clip depth).
mat4 sk_cube_face_view_proj(vec3 light, vec3 fwd, vec3 right, vec3 up, float near_z, float far_z) {
    float a = -(far_z + near_z) / (far_z - near_z), b = -2.0 * far_z * near_z / (far_z - near_z);
    // rows of P * V: x = right . (p - L), y = up . (p - L), z = -a fwd . (p - L) + b, w = fwd . (p - L)
    return mat4(vec4(right.x, up.x, -a * fwd.x, fwd.x), vec4(right.y, up.y, -a * fwd.y, fwd.y),
                vec4(right.z, up.z, -a * fwd.z, fwd.z),
                vec4(-dot(right, light), -dot(up, light), a * dot(fwd, light) + b, -dot(fwd, light)));
}

// Lit fraction of world_pos in a cube of hardware depth with the automatic bias: the face's 2x2
// filter done as four compares at texel centres, each against the receiver plane's own window depth
// there (sk_shadow_map_visibility_auto on the face the point falls in). A tap past the face's edge is
// read from the neighbouring face: its reference is the plane's depth along that tap's direction in
// that face (the major axis of the plane point the tap's ray meets), so the seams keep the bias.
// `normal`: the receiver's geometric world normal; depth_step: the cube's format step (0.0 float32).
// Cube rendered as sk_cube_visibility_hardware_depth's (GL clip depth, not reversed, no polygon offset).
float sk_cube_visibility_hardware_depth_auto(samplerCubeShadow shadow_map, vec4 light_position, vec3 world_pos, vec3 normal,
                                             float near_z, float far_z, float depth_step) {
    if (!(light_position.w > 0.0)) return 1.0;
    vec3 light = light_position.xyz / light_position.w;
    vec3 d = world_pos - light;
    if (d == vec3(0.0)) return 1.0;
    vec3 fwd, right, up;
    sk_cube_face_frame(d, fwd, right, up);
    mat4 vp = sk_cube_face_view_proj(light, fwd, right, up, near_z, far_z);
    vec4 c = sk_shadow_coord(vp, world_pos, false);
    vec4 g = sk_plane_depth_gradient(vp, world_pos, normal, false);
    if (g.z == 0.0) return 1.0;  // edge-on receiver
    vec2 size = vec2(textureSize(shadow_map, 0));
    vec2 texel = 1.0 / size;
    float eps = sk_auto_bias_epsilon(g, texel, c.z, depth_step);
    vec2 f = c.xy * size - 0.5;
    vec2 i0 = floor(f);
    vec2 w = f - i0;
    vec4 weight = vec4((1.0 - w.x) * (1.0 - w.y), w.x * (1.0 - w.y), (1.0 - w.x) * w.y, w.x * w.y);
    vec3 n = normalize(normal);
    float nd = dot(n, d);
    float zf = (far_z + near_z) / (far_z - near_z), zg = 2.0 * far_z * near_z / (far_z - near_z);
    float v = 0.0;
    for (int k = 0; k < 4; ++k) {
        vec2 centre = (i0 + vec2(float(k & 1), float(k >> 1)) + 0.5) * texel;
        vec3 dir = fwd + (2.0 * centre.x - 1.0) * right + (2.0 * centre.y - 1.0) * up;
        float z = c.z + dot(g.xy, centre - c.xy);  // in this face: the plane's depth is linear in (s, t)
        if (any(lessThan(centre, vec2(0.0))) || any(greaterThan(centre, vec2(1.0)))) {
            // past the edge: the neighbouring face's texel centre the tap falls in, and the plane's
            // window depth along it in that face (the major axis of the plane point on that ray)
            vec3 f2, r2, u2;
            sk_cube_face_frame(dir, f2, r2, u2);
            vec2 st = (vec2(dot(dir, r2), dot(dir, u2)) / dot(dir, f2)) * 0.5 + 0.5;
            st = (min(floor(st * size), size - 1.0) + 0.5) / size;
            dir = f2 + (2.0 * st.x - 1.0) * r2 + (2.0 * st.y - 1.0) * u2;
            float t = nd / dot(n, dir);  // dir's component along f2 is 1: t is the plane point's major-axis distance
            if (t > 0.0 && t < 3.0e38) z = 0.5 * (zf - zg / t) + 0.5;
        }
        v += weight[k] * texture(shadow_map, vec4(dir, clamp(z - eps, 0.0, 1.0)));
    }
    return v;
}

// For filtered kernels (pcf.glsl with GL_LINEAR taps, pcss.glsl): each tap applies the receiver plane
// at its offset, but its hardware 2x2 reads texel centres up to one texel away with one reference, so
// it needs one texel of the plane's slope plus the precision margin (shadow_bias.hpp bias_auto_filtered).
// Subtract it from uvz.z (add with SK_REVERSED_Z) and pass g.xy as dz_duv.
float sk_auto_filtered_bias(vec4 g, vec2 texel_uv, float z, float depth_step) {
    return abs(g.x) * texel_uv.x + abs(g.y) * texel_uv.y + sk_auto_bias_epsilon(g, texel_uv, z, depth_step);
}
