// shadowkit/hlsl/silhouette_map.hlsl - silhouette maps (Sen, Cammarano & Hanrahan 2003) in HLSL: the silhouette-point pass and the lookup that bends the shadow boundary through the stored points.
// stages: vertex (sk_silmap_edge_vertex), pixel (the rest)
//
// The HLSL twin of glsl/silhouette_map.glsl: the same sk_ functions, arguments and results; its header
// says the texel space (t = uv * map_size, the silhouette map on the dual grid), the rasterization
// pass's state and the blending. The depth map is a Texture2D<float> (window depth) and the silhouette
// map a Texture2D<float4> (R8G8B8A8_UNORM: rg = point offset in the cell, a = edge weight / 255), both
// read with Load (no sampler). frag_coord is SV_Position.xy (the pixel centre, as gl_FragCoord.xy).
// HLSL's atan2(y, x) is GLSL's atan(y, x).
// Compiled in the tests by glslang's HLSL front end to SPIR-V and its passes run on Vulkan; written
// for DXC (shader model 6.0) as well, but not compiled with it here (DXC is not packaged in Debian 12).
// MIT License. Copyright (c) shadowkit contributors.

// Clip position of corner 0..5 of the quad around edge a-b (texel space), extended by one texel at
// both ends and one texel to each side.
float4 sk_silmap_edge_vertex(float2 a, float2 b, int corner, float2 map_size) {
    float2 d = b - a;
    float len = length(d);
    float2 dir = len > 0.0 ? d / len : float2(1.0, 0.0);
    float2 nrm = float2(-dir.y, dir.x);
    int c = corner % 6;
    float along = (c == 1 || c == 2 || c == 4) ? 1.0 : 0.0;
    float side = (c == 2 || c == 4 || c == 5) ? 1.0 : -1.0;
    float2 t = lerp(a - dir, b + dir, along) + side * nrm;
    float2 w = t - 0.5;  // dual grid: window = texel - 0.5
    return float4(w / map_size * 2.0 - 1.0, 0.0, 1.0);
}

// Diagonal hit of segment p0-p1 against q0-q1; false if parallel or missed.
bool sk_silmap_seg_hit(float2 p0, float2 p1, float2 q0, float2 q1, out float2 hit) {
    float2 r = p1 - p0;
    float2 s = q1 - q0;
    float den = r.x * s.y - r.y * s.x;
    hit = float2(0.0, 0.0);
    if (den == 0.0) return false;
    float2 qp = q0 - p0;
    float t = (qp.x * s.y - qp.y * s.x) / den;
    float u = (qp.x * r.y - qp.y * r.x) / den;
    if (t < 0.0 || t > 1.0 || u < 0.0 || u > 1.0) return false;
    hit = p0 + t * r;
    return true;
}

// The silhouette point of edge a-b in the cell of this pixel (an endpoint inside, one diagonal hit,
// or the midpoint of two); false otherwise. weight = border crossings = 2 - endpoints inside.
bool sk_silmap_point(float2 frag_coord, float2 a, float2 b, out float2 local, out float weight) {
    float2 o = floor(frag_coord) + 0.5;
    float2 la = a - o;
    float2 lb = b - o;
    bool ina = all(la >= 0.0) && all(la <= 1.0);
    bool inb = all(lb >= 0.0) && all(lb <= 1.0);
    local = float2(0.5, 0.5);
    weight = 0.0;
    if (ina || inb) {
        local = ina ? la : lb;
        weight = 2.0 - (ina ? 1.0 : 0.0) - (inb ? 1.0 : 0.0);
        return true;
    }
    float2 h0, h1;
    bool d0 = sk_silmap_seg_hit(la, lb, float2(0.0, 0.0), float2(1.0, 1.0), h0);
    bool d1 = sk_silmap_seg_hit(la, lb, float2(1.0, 0.0), float2(0.0, 1.0), h1);
    if (!d0 && !d1) return false;
    local = saturate(d0 && d1 ? 0.5 * (h0 + h1) : (d0 ? h0 : h1));
    weight = 2.0;
    return true;
}

// The paper's occlusion test (glsl/silhouette_map.glsl says when it is true).
bool sk_silmap_occluded(Texture2D<float> depth_map, int2 cell, float2 a, float2 b, float za, float zb, float2 local,
                        float bias_window) {
    uint w, h;
    depth_map.GetDimensions(w, h);
    int2 sz = int2(w, h);
    float2 q = float2(cell) + 0.5 + local;
    float2 d = b - a;
    float dd = dot(d, d);
    float t = dd > 0.0 ? saturate(dot(q - a, d) / dd) : 0.0;
    float ze = lerp(za, zb, t);
    bool behind = true;
    bool casts = false;
    [unroll] for (int s = 0; s < 4; ++s) {
        int2 ij = min(cell + int2(s & 1, s >> 1), sz - 1);
        float zs = depth_map.Load(int3(ij, 0));
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

// 1 = lit, 0 = shadowed at texel-space position `texel` for a receiver of window depth receiver_depth.
float sk_silmap_visibility(Texture2D<float> depth_map, Texture2D<float4> silmap, float2 texel, float receiver_depth,
                           float bias_window) {
    uint w, h;
    depth_map.GetDimensions(w, h);
    int2 sz = int2(w, h);
    float2 s = texel - 0.5;
    int2 cell = int2(floor(s));
    float2 local = s - float2(cell);
    int2 nearest_ij = clamp(int2(floor(texel)), int2(0, 0), sz - 1);
    float plain = receiver_depth <= depth_map.Load(int3(nearest_ij, 0)) + bias_window ? 1.0 : 0.0;
    if (cell.x < 0 || cell.y < 0 || cell.x > sz.x - 2 || cell.y > sz.y - 2) return plain;
    float lit[4];
    [unroll] for (int k = 0; k < 4; ++k)
        lit[k] = receiver_depth <= depth_map.Load(int3(cell + int2(k & 1, k >> 1), 0)) + bias_window ? 1.0 : 0.0;
    float sum = lit[0] + lit[1] + lit[2] + lit[3];
    if (sum == 0.0 || sum == 4.0) return lit[0];
    float4 c = silmap.Load(int3(cell, 0));
    if (c.a * 255.0 > 2.5) return plain;  // two silhouette curves in this texel: the known failure
    float2 center_point = c.rg;
    float2 nb[4];
    nb[0] = silmap.Load(int3(min(cell + int2(1, 0), sz - 1), 0)).rg + float2(1.0, 0.0);
    nb[1] = silmap.Load(int3(min(cell + int2(0, 1), sz - 1), 0)).rg + float2(0.0, 1.0);
    nb[2] = silmap.Load(int3(max(cell - int2(1, 0), int2(0, 0)), 0)).rg - float2(1.0, 0.0);
    nb[3] = silmap.Load(int3(max(cell - int2(0, 1), int2(0, 0)), 0)).rg - float2(0.0, 1.0);
    float ang[4];
    [unroll] for (int j = 0; j < 4; ++j) {
        float2 d = nb[j] - center_point;
        if (all(d == 0.0)) return plain;
        ang[j] = atan2(d.y, d.x);
    }
    float2 ds = local - center_point;
    if (all(ds == 0.0)) return plain;
    float a_top = sk_silmap_wrap(ang[1] - ang[0]);
    float a_left = sk_silmap_wrap(ang[2] - ang[0]);
    float a_bottom = sk_silmap_wrap(ang[3] - ang[0]);
    if (!(a_top > 0.0 && a_top < a_left && a_left < a_bottom)) return plain;
    float as = sk_silmap_wrap(atan2(ds.y, ds.x) - ang[0]);
    int corner = as < a_top ? 3 : (as < a_left ? 2 : (as < a_bottom ? 0 : 1));
    return lit[corner];
}
