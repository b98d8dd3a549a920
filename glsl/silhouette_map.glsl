// shadowkit/glsl/silhouette_map.glsl - shadow silhouette maps (Sen, Cammarano & Hanrahan 2003), GPU side.
//
// The silhouette-map rasterization pass (each silhouette edge drawn as a quad widened so that every
// crossed dual-grid texel gets a fragment, the paper's four point cases, the occlusion test) and
// the lookup (non-silhouette pixels: the four depth tests; silhouette pixels: the sector of the
// piecewise-linear boundary through the five silhouette points decides). Same rules and encoding
// as include/shadowkit/silhouette_map.hpp; docs/silhouette_map.md has the whole setup.
// versions: 330, 450
// stages: vertex, fragment
//
// Texel space: t = uv * map_size (depth sample (i, j) at (i + 0.5, j + 0.5)). The silhouette map
// has the depth map's size; its texel (i, j) is the dual cell [i + 0.5, i + 1.5]^2, so the pass
// renders with window coordinates w = t - 0.5 (sk_silmap_edge_vertex does this).
// Inputs (rasterization pass, one instance per edge): the edge's ends a, b in texel space and their
// window depths (silmap_project_edges on the CPU); gl_VertexID 0..5 -> `corner`.
// Uniforms (user-declared, passed in): the depth map as sampler2D (GL_NEAREST, compare mode OFF);
// the silhouette map as sampler2D (RGBA8, GL_NEAREST): rg = point offset in the cell, a = edge
// weight / 255. No light: the light is in the matrix that projected the edges and the depth map.
// GL state of the rasterization pass: an RGBA8 target of the depth map's size cleared to
// (0.5, 0.5, 0, 0); glViewport(0, 0, W, H); blending on with glBlendFuncSeparate(GL_ONE, GL_ZERO,
// GL_ONE, GL_ONE) (rgb: last point wins, a: weights add); depth test, depth writes and culling off.
// Lookup: any pass, both maps bound as above; no blending needed.
//
// Usage:
//   // vertex:   gl_Position = sk_silmap_edge_vertex(a_ab.xy, a_ab.zw, gl_VertexID, u_size);
//   // fragment: vec2 local; float w; if (!sk_silmap_point(gl_FragCoord.xy, v_a, v_b, local, w)) discard;
//   //           if (sk_silmap_occluded(u_depth, ivec2(gl_FragCoord.xy), v_a, v_b, v_za, v_zb, local, 1e-4)) discard;
//   //           o_silmap = vec4(local, 0.0, w / 255.0);
//   // lookup:   float lit = sk_silmap_visibility(u_depth, u_silmap, uv * size, receiver_window_depth, 0.0);
//
// MIT License. Copyright (c) shadowkit contributors.

// Clip position of corner 0..5 of the quad around edge a-b (texel space), extended by one texel at
// both ends and one texel to each side (>= sqrt(2)/2 covers every touched cell).
vec4 sk_silmap_edge_vertex(vec2 a, vec2 b, int corner, vec2 map_size) {
    vec2 d = b - a;
    float len = length(d);
    vec2 dir = len > 0.0 ? d / len : vec2(1.0, 0.0);
    vec2 nrm = vec2(-dir.y, dir.x);
    int c = corner % 6;
    float along = (c == 1 || c == 2 || c == 4) ? 1.0 : 0.0;
    float side = (c == 2 || c == 4 || c == 5) ? 1.0 : -1.0;
    vec2 t = mix(a - dir, b + dir, along) + side * nrm;
    vec2 w = t - 0.5;  // dual grid: window = texel - 0.5
    return vec4(w / map_size * 2.0 - 1.0, 0.0, 1.0);
}

// Diagonal hit of segment p0-p1 against q0-q1 (texel-space offsets in a cell); returns false if parallel or missed.
bool sk_silmap_seg_hit(vec2 p0, vec2 p1, vec2 q0, vec2 q1, out vec2 hit) {
    vec2 r = p1 - p0, s = q1 - q0;
    float den = r.x * s.y - r.y * s.x;
    hit = vec2(0.0);
    if (den == 0.0) return false;
    vec2 qp = q0 - p0;
    float t = (qp.x * s.y - qp.y * s.x) / den;
    float u = (qp.x * r.y - qp.y * r.x) / den;
    if (t < 0.0 || t > 1.0 || u < 0.0 || u > 1.0) return false;
    hit = p0 + t * r;
    return true;
}

// The silhouette point of edge a-b (texel space) in the cell of this fragment: case 1 an endpoint
// inside (a first), case 2 one diagonal hit, case 3 the midpoint of two; false for case 4.
// weight = border crossings = 2 - endpoints inside.
bool sk_silmap_point(vec2 frag_coord, vec2 a, vec2 b, out vec2 local, out float weight) {
    vec2 o = floor(frag_coord) + 0.5;
    vec2 la = a - o, lb = b - o;
    bool ina = all(greaterThanEqual(la, vec2(0.0))) && all(lessThanEqual(la, vec2(1.0)));
    bool inb = all(greaterThanEqual(lb, vec2(0.0))) && all(lessThanEqual(lb, vec2(1.0)));
    local = vec2(0.5);
    weight = 0.0;
    if (ina || inb) {
        local = ina ? la : lb;
        weight = 2.0 - (ina ? 1.0 : 0.0) - (inb ? 1.0 : 0.0);
        return true;
    }
    vec2 h0, h1;
    bool d0 = sk_silmap_seg_hit(la, lb, vec2(0.0), vec2(1.0), h0);
    bool d1 = sk_silmap_seg_hit(la, lb, vec2(1.0, 0.0), vec2(0.0, 1.0), h1);
    if (!d0 && !d1) return false;
    local = clamp(d0 && d1 ? 0.5 * (h0 + h1) : (d0 ? h0 : h1), 0.0, 1.0);
    weight = 2.0;
    return true;
}

// The paper's occlusion test: the edge's depth at the point is behind all four depth samples
// around the cell (corners (i, j) .. (i+1, j+1)) by more than bias. Also true when no sample lies
// behind the edge by more than bias: the edge casts no shadow there (a contact edge, e.g. a box's
// bottom edge on the floor), and its point would only bend the boundary of a depth crease.
bool sk_silmap_occluded(sampler2D depth_map, ivec2 cell, vec2 a, vec2 b, float za, float zb, vec2 local, float bias_window) {
    ivec2 sz = textureSize(depth_map, 0);
    vec2 q = vec2(cell) + 0.5 + local;
    vec2 d = b - a;
    float dd = dot(d, d);
    float t = dd > 0.0 ? clamp(dot(q - a, d) / dd, 0.0, 1.0) : 0.0;
    float ze = mix(za, zb, t);
    bool behind = true, casts = false;
    for (int s = 0; s < 4; ++s) {
        ivec2 ij = min(cell + ivec2(s & 1, s >> 1), sz - 1);
        float zs = texelFetch(depth_map, ij, 0).r;
        if (!(ze > zs + bias_window)) behind = false;
        if (zs > ze + bias_window) casts = true;
    }
    return behind || !casts;
}

// An angle wrapped to [0, 2 pi).
float sk_silmap_wrap(float a) {
    const float two_pi = 6.28318530718;
    return a - two_pi * floor(a / two_pi);
}

// 1 = lit, 0 = shadowed at texel-space position `texel` for a receiver of window depth
// receiver_depth: nearest-sample result at the border and in failure texels (weight > 2), the four
// depth tests where they agree, else the sector of the silhouette-point boundary.
float sk_silmap_visibility(sampler2D depth_map, sampler2D silmap, vec2 texel, float receiver_depth, float bias_window) {
    ivec2 sz = textureSize(depth_map, 0);
    vec2 s = texel - 0.5;
    ivec2 cell = ivec2(floor(s));
    vec2 local = s - vec2(cell);
    ivec2 nearest_ij = clamp(ivec2(floor(texel)), ivec2(0), sz - 1);
    float plain = receiver_depth <= texelFetch(depth_map, nearest_ij, 0).r + bias_window ? 1.0 : 0.0;
    if (cell.x < 0 || cell.y < 0 || cell.x > sz.x - 2 || cell.y > sz.y - 2) return plain;
    float lit[4];
    for (int k = 0; k < 4; ++k)
        lit[k] = receiver_depth <= texelFetch(depth_map, cell + ivec2(k & 1, k >> 1), 0).r + bias_window ? 1.0 : 0.0;
    float sum = lit[0] + lit[1] + lit[2] + lit[3];
    if (sum == 0.0 || sum == 4.0) return lit[0];
    vec4 c = texelFetch(silmap, cell, 0);
    if (c.a * 255.0 > 2.5) return plain;  // two silhouette curves in this texel: the known failure
    vec2 center_point = c.rg;
    vec2 nb[4];
    nb[0] = texelFetch(silmap, min(cell + ivec2(1, 0), sz - 1), 0).rg + vec2(1.0, 0.0);
    nb[1] = texelFetch(silmap, min(cell + ivec2(0, 1), sz - 1), 0).rg + vec2(0.0, 1.0);
    nb[2] = texelFetch(silmap, max(cell - ivec2(1, 0), ivec2(0)), 0).rg - vec2(1.0, 0.0);
    nb[3] = texelFetch(silmap, max(cell - ivec2(0, 1), ivec2(0)), 0).rg - vec2(0.0, 1.0);
    float ang[4];
    for (int k = 0; k < 4; ++k) {
        vec2 d = nb[k] - center_point;
        if (d == vec2(0.0)) return plain;
        ang[k] = atan(d.y, d.x);
    }
    vec2 ds = local - center_point;
    if (ds == vec2(0.0)) return plain;
    float a_top = sk_silmap_wrap(ang[1] - ang[0]), a_left = sk_silmap_wrap(ang[2] - ang[0]),
          a_bottom = sk_silmap_wrap(ang[3] - ang[0]);
    if (!(a_top > 0.0 && a_top < a_left && a_left < a_bottom)) return plain;
    float as = sk_silmap_wrap(atan(ds.y, ds.x) - ang[0]);
    int corner = as < a_top ? 3 : (as < a_left ? 2 : (as < a_bottom ? 0 : 1));
    return lit[corner];
}
