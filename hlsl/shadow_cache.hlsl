// shadowkit/hlsl/shadow_cache.hlsl - a translation-invariant caster pass for cached (scrolled) shadow maps in HLSL: depth written from the global texel, so a map scrolled by whole texels is bit-identical to a re-render.
// stages: geometry, pixel
//
// The HLSL twin of glsl/shadow_cache.glsl: the same sk_ functions, arguments and results (its header
// says why and the exactness limits). The pass: the vertex stage outputs global = mul(light_global,
// float4(position, 1.0)).xyz (the map's matrix without its anchor, `column_major`); a geometry shader
// ([maxvertexcount(3)], TriangleStream) calls sk_shadow_cache_plane per triangle (no output when it is
// false) and emits SV_Position = sk_shadow_cache_position(global.xy, viewport_anchor, viewport_size)
// with the plane and origin as nointerpolation outputs; the pixel shader returns SV_Depth =
// sk_shadow_cache_depth(plane, origin, position.xy, anchor) (SV_Position.xy is the pixel centre, as
// gl_FragCoord.xy). Viewport: (-G, -G, V, V) with a plain (positive) height, V = map + 2 G a power of
// two <= 4096; scissor the map. Row j of the map is then global texel y = anchor.y + j in Vulkan as in
// GL (Direct3D's viewport puts NDC y = +1 at row 0: there the rows run the other way, and a lookup
// needs flip_y as for any map, docs/vulkan_and_direct3d.md).
// Compiled in the tests by glslang's HLSL front end to SPIR-V and run on Vulkan; written for DXC
// (shader model 6.0) as well, but not compiled with it here (DXC is not packaged in Debian 12).
// MIT License. Copyright (c) shadowkit contributors.

// A global texel coordinate on a 2^-12 texel grid: subtracting an integer anchor from it is exact.
float2 sk_shadow_cache_quantize(float2 global_texel) {
    return floor(global_texel * 4096.0 + 0.5) * (1.0 / 4096.0);
}

// Clip position of a vertex at `global_texel` in a viewport of viewport_size texels whose texel
// (0, 0) is global texel viewport_anchor (exact: a whole-texel translation of a fixed position).
float4 sk_shadow_cache_position(float2 global_texel, int2 viewport_anchor, float2 viewport_size) {
    float2 window = sk_shadow_cache_quantize(global_texel) - float2(viewport_anchor);
    return float4(window * (2.0 / viewport_size) - 1.0, 0.0, 1.0);
}

// The depth plane of a triangle in global texel space: depth = plane.x + plane.y * (x - origin.x)
// + plane.z * (y - origin.y). False for an edge-on triangle.
bool sk_shadow_cache_plane(float3 g0, float3 g1, float3 g2, out float3 plane, out float2 origin) {
    float3 e1 = g1 - g0;
    float3 e2 = g2 - g0;
    float det = e1.x * e2.y - e2.x * e1.y;
    origin = g0.xy;
    plane = float3(g0.z, 0.0, 0.0);
    if (det == 0.0) return false;
    plane.y = (e1.z * e2.y - e2.z * e1.y) / det;
    plane.z = (e2.z * e1.x - e1.z * e2.x) / det;
    return !(isinf(plane.y) || isinf(plane.z) || isnan(plane.y) || isnan(plane.z));
}

// Window depth at a pixel, from the global texel of its centre, clamped to [0, 1].
float sk_shadow_cache_depth(float3 plane, float2 origin, float2 frag_coord, int2 anchor) {
    float2 g = frag_coord + float2(anchor);
    return saturate(plane.x + plane.y * (g.x - origin.x) + plane.z * (g.y - origin.y));
}

// A slope-scaled depth offset like a rasterizer depth bias, `constant` in depth units (per triangle).
float sk_shadow_cache_depth_offset(float3 plane, float factor, float constant) {
    return factor * max(abs(plane.y), abs(plane.z)) + constant;
}
