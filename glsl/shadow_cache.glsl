// shadowkit/glsl/shadow_cache.glsl - a translation-invariant caster pass for cached (scrolled) shadow maps: depth written from the global texel, so a map scrolled by whole texels is bit-identical to a re-render
// versions: 450
// stages: geometry, fragment
//
// Why: a map copied by whole texels (shadow_cache.hpp, ShadowCacheAction::Scroll) equals a
// re-render only if the rasterizer gives the same value to the same world point after the
// translation. The plain pass (gl_Position = light_view_proj * p, hardware depth) does not, bit for
// bit: a triangle's depth plane is evaluated from the framebuffer origin, so a translated triangle
// rounds differently (llvmpipe: up to 8 float steps of depth at 1% to 50% of the texels), and a
// float transform of arbitrary coordinates or a triangle clipped at the map's border moves edges by
// rounding (rare coverage flips). Behind a depth bias that is harmless; where bit-identical caches
// matter (tests, lockstep replays, checksums) use this pass:
//   vertex:   v_global = (u_light_global * vec4(position, 1.0)).xyz, where u_light_global is the
//             map's matrix without its anchor: world -> (global texel x, global texel y, window
//             depth in [0, 1]). It does not depend on the camera: a vertex gives the same bits
//             every frame.
//   geometry: per triangle sk_shadow_cache_plane() (emit nothing when false: edge-on), then per
//             vertex gl_Position = sk_shadow_cache_position(v_global[i].xy, viewport_anchor,
//             viewport_size), the plane and origin as flat outputs.
//   fragment: gl_FragDepth = sk_shadow_cache_depth(plane, origin, gl_FragCoord.xy, anchor)
//             (+ sk_shadow_cache_depth_offset() for a slope-scaled bias: glPolygonOffset does not
//             apply to a written depth).
// Uniforms (user-declared, passed in): anchor = the global texel of the map's texel (0, 0) (what
// the stable fit snaps); a guard band G around the map: glViewport(-G, -G, V, V) with V = map size
// + 2 G a power of two <= 4096, viewport_anchor = anchor - G, viewport_size = V. Triangles are then
// clipped G texels outside the map instead of at its border (a clipped edge is a rounded one).
// GL state: depth test on (GL_LESS), depth writes on, a GL_DEPTH_COMPONENT32F map, scissor for the
// plan's rectangles (window coordinates of the map, unaffected by the viewport). Clip z is 0: near
// and far never clip and depth is clamped to [0, 1] (as with GL_DEPTH_CLAMP).
// Exact when: vertices lie inside the viewport (|window| < V <= 2^12 texels: 12 integer + 12
// fractional bits in a float) and |global texel| < 2^22. Accuracy (not exactness) far from the
// world origin: N texels away the float global coordinate sits on a grid of N * 2^-24 texels (1/16
// texel at N = 2^20), and shapes are rounded to it (the same way every frame); rebase
// u_light_global on a world point near the camera, a whole number of texels away, and render the
// maps whole when it changes.
// MIT License. Copyright (c) shadowkit contributors.

// A global texel coordinate on a 2^-12 texel grid (finer than the rasterizers' 8-bit sub-texel grid):
// subtracting an integer anchor from it is then exact.
vec2 sk_shadow_cache_quantize(vec2 global_texel) {
    return floor(global_texel * 4096.0 + 0.5) * (1.0 / 4096.0);
}

// Clip position of a vertex at `global_texel` in a viewport of viewport_size texels whose texel
// (0, 0) is global texel viewport_anchor. Exact: the window position is quantize(global_texel) -
// viewport_anchor, a whole-texel translation of a fixed position (viewport_size a power of two).
vec4 sk_shadow_cache_position(vec2 global_texel, ivec2 viewport_anchor, vec2 viewport_size) {
    vec2 window = sk_shadow_cache_quantize(global_texel) - vec2(viewport_anchor);
    return vec4(window * (2.0 / viewport_size) - 1.0, 0.0, 1.0);
}

// The depth plane of a triangle in global texel space: depth = plane.x + plane.y * (x - origin.x)
// + plane.z * (y - origin.y). False for an edge-on triangle (it covers no texel center).
bool sk_shadow_cache_plane(vec3 g0, vec3 g1, vec3 g2, out vec3 plane, out vec2 origin) {
    vec3 e1 = g1 - g0, e2 = g2 - g0;
    float det = e1.x * e2.y - e2.x * e1.y;
    origin = g0.xy;
    plane = vec3(g0.z, 0.0, 0.0);
    if (det == 0.0) return false;
    plane.y = (e1.z * e2.y - e2.z * e1.y) / det;
    plane.z = (e2.z * e1.x - e1.z * e2.x) / det;
    return !(isinf(plane.y) || isinf(plane.z) || isnan(plane.y) || isnan(plane.z));
}

// Window depth at a fragment, from the global texel of its center: the same bits for the same world
// texel whatever the anchor (frag_coord + anchor is exact), clamped to [0, 1].
float sk_shadow_cache_depth(vec3 plane, vec2 origin, vec2 frag_coord, ivec2 anchor) {
    vec2 g = frag_coord + vec2(anchor);
    return clamp(plane.x + plane.y * (g.x - origin.x) + plane.z * (g.y - origin.y), 0.0, 1.0);
}

// A slope-scaled depth offset like glPolygonOffset(factor, ...) with `constant` in depth units:
// factor * max(|d depth / dx|, |d depth / dy|) + constant (per triangle, so translation-invariant).
float sk_shadow_cache_depth_offset(vec3 plane, float factor, float constant) {
    return factor * max(abs(plane.y), abs(plane.z)) + constant;
}
