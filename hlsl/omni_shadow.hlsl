// shadowkit/hlsl/omni_shadow.hlsl - omnidirectional (point-light) shadow lookups in HLSL: cube maps storing the linear distance to the light (Gerasimov 2004) and dual-paraboloid maps (Brabec, Annen & Seidel 2002).
// stages: vertex (sk_dp_clip_position, sk_dp_clip_distance), pixel (the rest; any stage works)
//
// The HLSL twin of glsl/omni_shadow.glsl: the same sk_ functions, arguments and results (its header
// says the storage, bias and seams). Every map holds distance_to_light / range: the depth pass's pixel
// shader returns SV_Depth = sk_omni_linear_depth(world, light, range). Cubes are TextureCube<float>
// read through a SamplerComparisonState (LESS_EQUAL, linear) or, for the manual compare, a
// SamplerState (point) passed next to them; the dual paraboloid is a two-layer Texture2DArray<float>
// whose passes write SV_Position = sk_dp_clip_position(...) and SV_ClipDistance0 =
// sk_dp_clip_distance(...). Cube faces: GL's face frames (omni_cube_matrices) drawn with a plain
// viewport into layer f of a cube-compatible image (docs/vulkan_and_direct3d.md, "Cube maps").
// Matrices (dp_view) `column_major` with mul(M, v) (hlsl/shadow_map.hlsl states the rule).
// Compiled in the tests by glslang's HLSL front end to SPIR-V (the cube lookups and both dual-paraboloid passes also run on Vulkan);
// written for DXC (shader model 6.0) as well, but not compiled with it here (not in Debian 12).
// MIT License. Copyright (c) shadowkit contributors.

// Position of a point light given as float4 light_position (w > 0).
float3 sk_omni_light_point(float4 light_position) {
    return light_position.xyz / light_position.w;
}

// Stored value of the depth pass (return it as SV_Depth).
float sk_omni_linear_depth(float3 world_pos, float4 light_position, float range) {
    return saturate(length(world_pos - sk_omni_light_point(light_position)) / range);
}

// Receiver bias in world units (omni_distance_bias); storage = (absolute, relative to d).
float sk_omni_bias(float d, float cos_theta, float texel_angle, float filter_radius, float max_angle, float2 storage) {
    float theta = min(acos(saturate(cos_theta)), max_angle);
    float alpha = filter_radius * texel_angle;
    float g = d * (1.0 - cos(theta) / cos(max(theta - alpha, 0.0)));
    return max(g, 0.0) + storage.x + storage.y * d;
}

// ----------------------------------------------------------------------------------------- cube

// Largest angle one texel of a size^2 face subtends (2 / size).
float sk_omni_cube_texel_angle(float size) { return 2.0 / size; }

// Hardware compare on the distance cube (linear filter: 2x2 PCF across seams).
float sk_cube_visibility_distance(TextureCube<float> shadow_map, SamplerComparisonState cmp, float4 light_position,
                                  float3 world_pos, float range, float bias_world) {
    float3 d = world_pos - sk_omni_light_point(light_position);
    return shadow_map.SampleCmpLevelZero(cmp, d, (length(d) - bias_world) / range);
}

// Manual compare: the same cube through a point SamplerState, or an R32_FLOAT cube of distance / range.
float sk_cube_visibility_distance_manual(TextureCube<float> distance_map, SamplerState point_sampler, float4 light_position,
                                         float3 world_pos, float range, float bias_world) {
    float3 d = world_pos - sk_omni_light_point(light_position);
    float stored = distance_map.SampleLevel(point_sampler, d, 0.0);
    return (length(d) - bias_world) / range <= stored ? 1.0 : 0.0;
}

// Tangents (s and t directions) of the face a direction is looked up in (x before y before z), and
// the major-axis magnitude.
void sk_omni_cube_tangents(float3 d, out float3 t_s, out float3 t_t, out float major) {
    float3 a = abs(d);
    if (a.x >= a.y && a.x >= a.z) {
        major = a.x;
        t_s = float3(0.0, 0.0, -sign(d.x));
        t_t = float3(0.0, -1.0, 0.0);
    } else if (a.y >= a.z) {
        major = a.y;
        t_s = float3(1.0, 0.0, 0.0);
        t_t = float3(0.0, 0.0, sign(d.y));
    } else {
        major = a.z;
        t_s = float3(sign(d.z), 0.0, 0.0);
        t_t = float3(0.0, -1.0, 0.0);
    }
}

// (2 radius + 1)^2 hardware-compare taps one texel apart in the face plane (taps past a face edge
// read the neighbour face). Bias with filter_radius = (radius + 1) * 1.4143.
float sk_cube_visibility_distance_pcf(TextureCube<float> shadow_map, SamplerComparisonState cmp, float4 light_position,
                                      float3 world_pos, float range, float bias_world, float size, int radius) {
    float3 d = world_pos - sk_omni_light_point(light_position);
    float ref = (length(d) - bias_world) / range;
    float3 ts, tt;
    float major;
    sk_omni_cube_tangents(d, ts, tt, major);
    float step_len = 2.0 * major / size;
    float sum = 0.0;
    float n = 0.0;
    for (int j = -radius; j <= radius; ++j)
        for (int i = -radius; i <= radius; ++i) {
            float3 tap = d + (float(i) * ts + float(j) * tt) * step_len;
            sum += shadow_map.SampleCmpLevelZero(cmp, tap, ref);
            n += 1.0;
        }
    return sum / max(n, 1.0);
}

// ------------------------------------------------------------------------------ dual paraboloid

// Vertex stage: clip position in paraboloid map `side` (+1 front, -1 back) of a world vertex;
// xy = n.xy / (1 + n.z) (Brabec et al. 2002), depth = distance / range, w = 1.
float4 sk_dp_clip_position(float4x4 dp_view, float3 world_pos, float side, float range, bool zero_to_one) {
    float3 q = mul(dp_view, float4(world_pos, 1.0)).xyz;
    float dist = length(q);
    float3 n = q / max(dist, 1e-30);
    n.z *= side;
    float2 xy = n.xy / max(1.0 + n.z, 1e-6);
    float z = dist / range;
    return float4(xy, zero_to_one ? z : 2.0 * z - 1.0, 1.0);
}

// Vertex stage: SV_ClipDistance0; keeps the hemisphere plus a margin (n.z >= -margin).
float sk_dp_clip_distance(float4x4 dp_view, float3 world_pos, float side, float margin) {
    float3 q = mul(dp_view, float4(world_pos, 1.0)).xyz;
    return side * q.z / max(length(q), 1e-30) + margin;
}

// Map point of a unit direction in the frame: xy, and layer 0 (front, z >= 0) or 1 (back).
float3 sk_dp_project(float3 n) {
    bool front = n.z >= 0.0;
    return float3(n.xy / (1.0 + abs(n.z)), front ? 0.0 : 1.0);
}

// Inverse (omni_paraboloid_unproject): unit direction of map point xy in layer 0/1.
float3 sk_dp_direction(float2 xy, float layer) {
    float r2 = dot(xy, xy);
    float3 d = float3(2.0 * xy, 1.0 - r2) / (1.0 + r2);
    return layer < 0.5 ? d : float3(d.xy, -d.z);
}

// Largest angle one texel of a size^2 paraboloid map subtends at map radius r.
float sk_dp_texel_angle(float size, float r) {
    float texel = 2.0 / size;
    float rr = max(abs(r) - 2.0 * texel, 0.0);
    return texel * 2.0 / (1.0 + rr * rr);
}

// Texture coordinates (u, v, layer) and map radius of a world point.
float4 sk_dp_coord(float4x4 dp_view, float3 world_pos) {
    float3 q = mul(dp_view, float4(world_pos, 1.0)).xyz;
    float3 m = sk_dp_project(q / max(length(q), 1e-30));
    return float4(m.xy * 0.5 + 0.5, m.z, length(m.xy));
}

// Hardware compare (linear filter: 2x2 PCF). The light is the frame's origin (dp_view).
float sk_dp_shadow(Texture2DArray<float> shadow_map, SamplerComparisonState cmp, float4x4 dp_view, float3 world_pos,
                   float range, float bias_world) {
    float3 q = mul(dp_view, float4(world_pos, 1.0)).xyz;
    float dist = length(q);
    float3 m = sk_dp_project(q / max(dist, 1e-30));
    return shadow_map.SampleCmpLevelZero(cmp, float3(m.xy * 0.5 + 0.5, m.z), (dist - bias_world) / range);
}

// (2 radius + 1)^2 taps one texel apart in the map; a tap past the rim (r > 1) reads the other map
// at xy / r^2. Bias with filter_radius = (radius + 1) * 1.4143.
float sk_dp_shadow_pcf(Texture2DArray<float> shadow_map, SamplerComparisonState cmp, float4x4 dp_view, float3 world_pos,
                       float range, float bias_world, float size, int radius) {
    float3 q = mul(dp_view, float4(world_pos, 1.0)).xyz;
    float dist = length(q);
    float3 m = sk_dp_project(q / max(dist, 1e-30));
    float ref = (dist - bias_world) / range;
    float texel = 2.0 / size;
    float sum = 0.0;
    float n = 0.0;
    for (int j = -radius; j <= radius; ++j)
        for (int i = -radius; i <= radius; ++i) {
            float2 t = m.xy + float2(float(i), float(j)) * texel;
            float layer = m.z;
            float r2 = dot(t, t);
            if (r2 > 1.0) {
                t /= r2;
                layer = 1.0 - layer;
            }
            sum += shadow_map.SampleCmpLevelZero(cmp, float3(t * 0.5 + 0.5, layer), ref);
            n += 1.0;
        }
    return sum / max(n, 1.0);
}
