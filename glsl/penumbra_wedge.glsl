// shadowkit/glsl/penumbra_wedge.glsl - soft shadow volumes (Assarsson & Akenine-Moller 2003, Lengyel
// GDC 2005): the in-wedge test against the wedge's planes, the signed light coverage of one
// silhouette edge for a spherical light (same math as shadowkit/penumbra_wedge.hpp), and the final
// combine with the hard shadow (stencil) count.
// versions: 330, 450
// stages: vertex, fragment
//
// Inputs (per wedge, from the CPU: shadowkit::penumbra_wedge): the silhouette edge e0, e1 (world, as
// seen from the light's center, oriented as in its light-facing triangle), the sphere light as in
// the C++ header: `vec4 light_position` (a point light, w > 0, center xyz / w; w = 0 is not
// supported) and `float light_radius`,
// the wedge planes (vec4 (n, d), inside when dot(n, x) + d >= 0), either in world space or moved to
// viewport space with penumbra_transform_plane(plane, viewport * view_proj) - or in the vertex stage
// with sk_wedge_transform_plane(transpose(inverse(world_to_viewport)), plane), passed on as flat
// outputs (Lengyel's texcoords 0-2).
// Fragment stage: rasterize the front faces of the wedge hull (penumbra_wedge_hull, 8 triangles;
// back faces with GL_GEQUAL where the camera is inside the hull or the hull crosses the near plane);
// for the pixel, rebuild the receiver point from the depth buffer copy (viewport point
// (gl_FragCoord.xy, depth, 1) for the plane test, world point for the coverage), reject it with
// sk_wedge_inside4 / sk_wedge_inside3, and output sk_wedge_edge_coverage.
// Accumulation: additive blending into a signed float target (R16F/R32F; glBlendFunc(GL_ONE, GL_ONE),
// GL_FUNC_ADD), cleared to 0 and first filled with the hard shadow volume counts (+1 back / -1 front
// faces in z-fail, or the stencil copied to the float target). Outer half-wedges add (coverage > 0),
// inner half-wedges subtract (coverage < 0): the sign is part of the coverage, so one pass over whole
// wedges needs no separate subtractive buffer. Finally sk_wedge_visibility(buffer, 0.0) (or
// (stencil, sum) if kept separately) gives the light visibility multiplying the light's contribution.
// GL state of the wedge pass: the scene's depth in the depth buffer (a depth pre-pass), GL_DEPTH_TEST
// with GL_LEQUAL (front faces) and glDepthMask(GL_FALSE); GL_CULL_FACE with glCullFace(GL_BACK) and
// glFrontFace(GL_CCW) (the hull's winding); GL_DEPTH_CLAMP for a finite projection whose far plane
// cuts the hull; the per-wedge glScissor rectangle inside glEnable(GL_SCISSOR_TEST) (disable it
// before the combine pass); additive blending as above. The receiver depth the fragment reads must
// be a texture (a copy of the depth buffer or a G-buffer), not the attachment being tested.
// Precision: float; ~1e-5 absolute for scenes of unit scale (the CPU version runs in double).
//
// Usage:
//   vec4 vp = vec4(gl_FragCoord.xy, texelFetch(u_depth, ivec2(gl_FragCoord.xy), 0).r, 1.0);
//   if (!sk_wedge_inside3(vp, v_plane0, v_plane1, v_plane2)) discard;
//   vec3 p = sk_wedge_world_from_depth(u_inv_view_proj, ndc_xy, vp.z, false);
//   o_coverage = sk_wedge_edge_coverage(u_e0, u_e1, u_light_position, u_light_radius, p);
//
// MIT License. Copyright (c) shadowkit contributors.

// Plane moved by a point transform M: pass transpose(inverse(M)).
vec4 sk_wedge_transform_plane(mat4 inverse_transpose, vec4 plane) {
    return inverse_transpose * plane;
}

// Lengyel's half-wedge test: the three bounding planes against a homogeneous point
// (viewport-space (x_win, y_win, z_win, 1) with viewport-space planes, or (world, 1) with world planes).
bool sk_wedge_inside3(vec4 p, vec4 plane0, vec4 plane1, vec4 plane2) {
    return dot(p, plane0) >= 0.0 && dot(p, plane1) >= 0.0 && dot(p, plane2) >= 0.0;
}

// Whole wedge: outer_bound, inner_bound, side[0], side[1].
bool sk_wedge_inside4(vec4 p, vec4 outer_bound, vec4 inner_bound, vec4 side0, vec4 side1) {
    return sk_wedge_inside3(p, outer_bound, side0, side1) && dot(p, inner_bound) >= 0.0;
}

// World position from a window depth (glDepthRange(0, 1)) and NDC xy.
vec3 sk_wedge_world_from_depth(mat4 inv_view_proj, vec2 ndc_xy, float window_depth, bool zero_to_one) {
    float z = zero_to_one ? window_depth : window_depth * 2.0 - 1.0;
    vec4 w = inv_view_proj * vec4(ndc_xy, z, 1.0);
    return w.xyz / w.w;
}

// Signed fraction of the light disk (radius light_radius through the center c = light_position.xyz /
// light_position.w, facing p) covered behind the edge as seen from p: > 0 outside the hard shadow
// plane (adds occlusion), < 0 inside; |result| <= 0.5. Projective clip of the edge to the disk, then
// sector minus triangle (Lengyel; A&AM coverage).
float sk_wedge_edge_coverage(vec3 e0, vec3 e1, vec4 light_position, float light_radius, vec3 p) {
    const float BIG = 1.0e30;
    float r = light_radius;
    if (!(r > 0.0) || !(light_position.w > 0.0)) return 0.0;
    vec3 c = light_position.xyz / light_position.w;
    vec3 d = c - p;
    float D = length(d);
    if (!(D > 0.0)) return 0.0;
    vec3 z = d / D;
    vec3 q0 = e0 - p;
    vec3 q1 = e1 - p;
    vec3 np = cross(q0, q1);
    float w0 = dot(q0, z);
    float w1 = dot(q1, z);
    // 1. only the part in front of the emitter occludes
    if (w0 >= D && w1 >= D) return 0.0;
    if (w0 > D || w1 > D) {
        float t = (D - w0) / (w1 - w0);
        vec3 qc = q0 + t * (q1 - q0);
        if (w0 > D) { q0 = qc; w0 = D; } else { q1 = qc; w1 = D; }
    }
    if (w0 <= 0.0 && w1 <= 0.0) return 0.0;
    // 2. projected line: signed distance hs from the disk center in light radii
    vec3 m = np - dot(np, z) * z;
    float ml = length(m);
    if (!(ml > 0.0)) return 0.0;
    float hs = -dot(np, d) / (r * ml);
    float h = abs(hs);
    if (!(h < 1.0)) return 0.0;
    float s = sqrt(1.0 - h * h);
    vec3 tdir = cross(z, m) / ml;
    float N0 = dot(q0, tdir) * D;
    float N1 = dot(q1, tdir) * D;
    float B0 = w0 * r;
    float B1 = w1 * r;
    float lo;
    float hi;
    if (B0 > 0.0 && B1 > 0.0) {
        float l0 = clamp(N0 / B0, -BIG, BIG);
        float l1 = clamp(N1 / B1, -BIG, BIG);
        lo = min(l0, l1);
        hi = max(l0, l1);
    } else {
        float nstar = (B0 * N1 - B1 * N0) / (B0 - B1);
        float lk = B0 > 0.0 ? clamp(N0 / B0, -BIG, BIG) : clamp(N1 / B1, -BIG, BIG);
        if (nstar > 0.0) { lo = lk; hi = BIG; }
        else if (nstar < 0.0) { lo = -BIG; hi = lk; }
        else return 0.0;
    }
    float a = max(lo, -s);
    float b = min(hi, s);
    if (!(a < b)) return 0.0;
    // 3. sector minus triangle, as a fraction of the disk area
    float dl = b - a;
    float theta = h > 0.0 ? atan(h * dl, h * h + a * b) : (a * b < 0.0 ? 3.14159265 : 0.0);
    float area = max(0.0, (theta - h * dl) * 0.15915494);
    // 4. positive half space of the hard plane adds occlusion
    return hs >= 0.0 ? area : -area;
}

// A&AM: visibility = 1 - clamp(hard count + sum of signed coverages, 0, 1).
float sk_wedge_visibility(float hard_count, float coverage_sum) {
    return 1.0 - clamp(hard_count + coverage_sum, 0.0, 1.0);
}
