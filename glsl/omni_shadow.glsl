// shadowkit/glsl/omni_shadow.glsl - omnidirectional (point-light) shadow lookups: cube shadow maps
// storing the linear distance to the light (Gerasimov 2004) and dual-paraboloid shadow maps
// (Brabec, Annen & Seidel 2002). Companion of include/shadowkit/omni_shadow.hpp.
// versions: 330, 450
// stages: vertex, fragment
//
// Storage: every map holds stored = distance_to_light / range (NOT window depth: a cube rendered with
// ordinary perspective faces is read with shadow_map.glsl's sk_cube_visibility_hardware_depth) (depth pass fragment stage:
// gl_FragDepth = sk_omni_linear_depth(world, light, range)); GL_TEXTURE_COMPARE_MODE =
// GL_COMPARE_REF_TO_TEXTURE, GL_LEQUAL, GL_LINEAR filtering for the hardware 2x2 compare.
// Cube: render face f with omni_cube_matrices().view_proj[f] into GL_TEXTURE_CUBE_MAP_POSITIVE_X + f,
// enable GL_TEXTURE_CUBE_MAP_SEAMLESS. Dual paraboloid: a 2-layer depth array (layer 0 front =
// +z of the paraboloid frame, layer 1 back), two passes whose vertex stage writes
// gl_Position = sk_dp_clip_position(...) and gl_ClipDistance[0] = sk_dp_clip_distance(...)
// (enable GL_CLIP_DISTANCE0); tessellate casters (omni_paraboloid_max_edge_length).
// Inputs: world-space point (and for the bias its normal); uniforms the user declares and passes:
// the light as `vec4 light_position` (the C++ header's convention: a point light, w > 0, at
// xyz / w; omnidirectional maps take no directional light), range, bias terms, the paraboloid frame
// matrix (omni_paraboloid_frame().view).
// GL state: depth pass GL_DEPTH_TEST with GL_LESS writing gl_FragDepth, culling off (or back faces,
// the maps store the nearest surface either way); lookups need GL_TEXTURE_COMPARE_MODE =
// GL_COMPARE_REF_TO_TEXTURE with GL_LEQUAL for the Shadow samplers, GL_NONE for the manual compare.
// Seams: cube taps are directions, so a tap past a face edge reads the neighbor face; paraboloid
// taps past the rim (r > 1) continue into the other map at xy / r^2.
//
// Usage (fragment stage):
//   vec3 L = u_light_position.xyz / u_light_position.w - p; float d = length(L);
//   float b = sk_omni_bias(d, dot(n, L / d), sk_omni_cube_texel_angle(u_size), 1.4143, 1.4835, u_storage);
//   float v = sk_cube_visibility_distance(u_cube, u_light_position, p, u_range, b);   // 1 lit, 0 shadowed
//
// MIT License. Copyright (c) shadowkit contributors.

// Position of a point light given as vec4 light_position (w > 0).
vec3 sk_omni_light_point(vec4 light_position) {
    return light_position.xyz / light_position.w;
}

// Stored value of the depth pass (write to gl_FragDepth).
float sk_omni_linear_depth(vec3 world_pos, vec4 light_position, float range) {
    return clamp(length(world_pos - sk_omni_light_point(light_position)) / range, 0.0, 1.0);
}

// Receiver bias in world units (omni_distance_bias): a plane at distance d, angle theta to the light,
// is stored at d cos(theta) / cos(theta') along texel rays theta' within alpha = filter_radius *
// texel_angle; the smallest is at theta' = max(theta - alpha, 0). storage = (absolute, relative to d):
// Float32 (0, 2^-22), Fixed24 (2 range / (2^24 - 1), 0), Fixed16 (2 range / 65535, 0).
float sk_omni_bias(float d, float cos_theta, float texel_angle, float filter_radius, float max_angle, vec2 storage) {
    float theta = min(acos(clamp(cos_theta, 0.0, 1.0)), max_angle);
    float alpha = filter_radius * texel_angle;
    float g = d * (1.0 - cos(theta) / cos(max(theta - alpha, 0.0)));
    return max(g, 0.0) + storage.x + storage.y * d;
}

// ----------------------------------------------------------------------------------------- cube

// Largest angle one texel of a size^2 face subtends (2 / size).
float sk_omni_cube_texel_angle(float size) { return 2.0 / size; }

// ---- cube lookups: each name says what the cube holds -------------------------------------------
// sk_cube_visibility_distance*: a cube storing distance / range (this snippet's depth pass). A cube
// of hardware depth (six perspective faces, window depth) is read with shadow_map.glsl's
// sk_cube_visibility_hardware_depth instead: each on the other's map compiles and is wrong.
// The old names (sk_omni_cube_shadow, _manual, sk_omni_cube_pcf) fail to compile, naming the new one.
#define sk_omni_cube_shadow sk_omni_cube_shadow_renamed_to_sk_cube_visibility_distance
#define sk_omni_cube_shadow_manual sk_omni_cube_shadow_manual_renamed_to_sk_cube_visibility_distance_manual
#define sk_omni_cube_pcf sk_omni_cube_pcf_renamed_to_sk_cube_visibility_distance_pcf

// Hardware compare: samplerCubeShadow on the distance cube (GL_LINEAR: 2x2 PCF across seams).
float sk_cube_visibility_distance(samplerCubeShadow shadow_map, vec4 light_position, vec3 world_pos, float range, float bias_world) {
    vec3 d = world_pos - sk_omni_light_point(light_position);
    return texture(shadow_map, vec4(d, (length(d) - bias_world) / range));
}

// Manual compare: samplerCube on the same texture with compare mode NONE (GL_NEAREST), or an R32F
// colour cube holding distance / range.
float sk_cube_visibility_distance_manual(samplerCube distance_map, vec4 light_position, vec3 world_pos, float range, float bias_world) {
    vec3 d = world_pos - sk_omni_light_point(light_position);
    float stored = texture(distance_map, d).r;
    return (length(d) - bias_world) / range <= stored ? 1.0 : 0.0;
}

// Tangents (s and t directions) of the face a direction is looked up in, same tie rule as
// omni_cube_face (x before y before z), and the major-axis magnitude.
void sk_omni_cube_tangents(vec3 d, out vec3 t_s, out vec3 t_t, out float major) {
    vec3 a = abs(d);
    if (a.x >= a.y && a.x >= a.z) {
        major = a.x;
        t_s = vec3(0.0, 0.0, -sign(d.x));
        t_t = vec3(0.0, -1.0, 0.0);
    } else if (a.y >= a.z) {
        major = a.y;
        t_s = vec3(1.0, 0.0, 0.0);
        t_t = vec3(0.0, 0.0, sign(d.y));
    } else {
        major = a.z;
        t_s = vec3(sign(d.z), 0.0, 0.0);
        t_t = vec3(0.0, -1.0, 0.0);
    }
}

// (2 radius + 1)^2 hardware-compare taps one texel apart in the face plane; each tap is a
// direction, so taps beyond a face edge land on the neighbor face (seams handled by the cube
// lookup). Bias with filter_radius = (radius + 1) * 1.4143.
float sk_cube_visibility_distance_pcf(samplerCubeShadow shadow_map, vec4 light_position, vec3 world_pos, float range,
                                      float bias_world, float size, int radius) {
    vec3 d = world_pos - sk_omni_light_point(light_position);
    float ref = (length(d) - bias_world) / range;
    vec3 ts, tt;
    float major;
    sk_omni_cube_tangents(d, ts, tt, major);
    float step_len = 2.0 * major / size;
    float sum = 0.0;
    float n = 0.0;
    for (int j = -radius; j <= radius; ++j)
        for (int i = -radius; i <= radius; ++i) {
            vec3 tap = d + (float(i) * ts + float(j) * tt) * step_len;
            sum += texture(shadow_map, vec4(tap, ref));
            n += 1.0;
        }
    return sum / max(n, 1.0);
}

// ------------------------------------------------------------------------------ dual paraboloid

// Vertex stage: clip position in paraboloid map `side` (+1 front, -1 back) of a world vertex;
// xy = n.xy / (1 + n.z) (Brabec et al. 2002), depth = distance / range, w = 1 (no perspective).
vec4 sk_dp_clip_position(mat4 dp_view, vec3 world_pos, float side, float range, bool zero_to_one) {
    vec3 q = (dp_view * vec4(world_pos, 1.0)).xyz;
    float dist = length(q);
    vec3 n = q / max(dist, 1e-30);
    n.z *= side;
    vec2 xy = n.xy / max(1.0 + n.z, 1e-6);
    float z = dist / range;
    return vec4(xy, zero_to_one ? z : 2.0 * z - 1.0, 1.0);
}

// Vertex stage: gl_ClipDistance[0]; keeps the hemisphere plus a margin (n.z >= -margin; 0.1 keeps
// map radius up to 1.1, enough for bilinear taps at the rim of maps >= 64 texels).
float sk_dp_clip_distance(mat4 dp_view, vec3 world_pos, float side, float margin) {
    vec3 q = (dp_view * vec4(world_pos, 1.0)).xyz;
    return side * q.z / max(length(q), 1e-30) + margin;
}

// Map point of a unit direction in the frame: xy, and layer 0 (front, z >= 0) or 1 (back).
vec3 sk_dp_project(vec3 n) {
    bool front = n.z >= 0.0;
    return vec3(n.xy / (1.0 + abs(n.z)), front ? 0.0 : 1.0);
}

// Inverse (omni_paraboloid_unproject): unit direction of map point xy in layer 0/1; r > 1 continues
// into the other hemisphere.
vec3 sk_dp_direction(vec2 xy, float layer) {
    float r2 = dot(xy, xy);
    vec3 d = vec3(2.0 * xy, 1.0 - r2) / (1.0 + r2);
    return layer < 0.5 ? d : vec3(d.xy, -d.z);
}

// Largest angle one texel of a size^2 paraboloid map subtends at map radius r (4 / size at the
// center, 2 / size at the rim; omni_paraboloid_texel_angle).
float sk_dp_texel_angle(float size, float r) {
    float texel = 2.0 / size;
    float rr = max(abs(r) - 2.0 * texel, 0.0);
    return texel * 2.0 / (1.0 + rr * rr);
}

// Texture coordinates (u, v, layer) and map radius of a world point.
vec4 sk_dp_coord(mat4 dp_view, vec3 world_pos) {
    vec3 q = (dp_view * vec4(world_pos, 1.0)).xyz;
    vec3 m = sk_dp_project(q / max(length(q), 1e-30));
    return vec4(m.xy * 0.5 + 0.5, m.z, length(m.xy));
}

// Hardware compare (GL_LINEAR: 2x2 PCF). The light is the frame's origin (dp_view).
float sk_dp_shadow(sampler2DArrayShadow shadow_map, mat4 dp_view, vec3 world_pos, float range, float bias_world) {
    vec3 q = (dp_view * vec4(world_pos, 1.0)).xyz;
    float dist = length(q);
    vec3 m = sk_dp_project(q / max(dist, 1e-30));
    return texture(shadow_map, vec4(m.xy * 0.5 + 0.5, m.z, (dist - bias_world) / range));
}

// (2 radius + 1)^2 taps one texel apart in the map; a tap past the rim (r > 1) reads the other map
// at xy / r^2 (the same direction). Bias with filter_radius = (radius + 1) * 1.4143.
float sk_dp_shadow_pcf(sampler2DArrayShadow shadow_map, mat4 dp_view, vec3 world_pos, float range, float bias_world,
                       float size, int radius) {
    vec3 q = (dp_view * vec4(world_pos, 1.0)).xyz;
    float dist = length(q);
    vec3 m = sk_dp_project(q / max(dist, 1e-30));
    float ref = (dist - bias_world) / range;
    float texel = 2.0 / size;
    float sum = 0.0;
    float n = 0.0;
    for (int j = -radius; j <= radius; ++j)
        for (int i = -radius; i <= radius; ++i) {
            vec2 t = m.xy + vec2(float(i), float(j)) * texel;
            float layer = m.z;
            float r2 = dot(t, t);
            if (r2 > 1.0) {
                t /= r2;
                layer = 1.0 - layer;
            }
            sum += texture(shadow_map, vec4(t * 0.5 + 0.5, layer, ref));
            n += 1.0;
        }
    return sum / max(n, 1.0);
}
