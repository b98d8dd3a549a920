// Driver for glsl/prefiltered_shadow.glsl (compute stage): the blur and the MSAA resolve, one
// invocation per texel, written with imageStore; the lookups compile in compute too.
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) uniform sampler2D u_src;
layout(binding = 1) uniform sampler2DMS u_depth_ms;
layout(rgba32f, binding = 0) writeonly uniform image2D u_dst;
uniform ivec2 u_dir;
uniform int u_radius;
uniform float u_weights[SK_PREFILTER_MAX_WEIGHTS];
uniform vec4 u_window_map;
uniform int u_method;
uniform vec2 u_exponents;
uniform vec4 u_params;
uniform bool u_quantized;
uniform bool u_resolve;
void main() {
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(px, imageSize(u_dst)))) return;
    vec4 m = u_resolve ? sk_prefilter_resolve(u_depth_ms, px, 4, u_window_map, u_method, u_exponents, u_quantized)
                       : sk_prefilter_blur(u_src, px, u_dir, u_radius, u_weights);
    float v = sk_prefilter_visibility(m, 0.5, u_method, u_params, 3e-5, u_quantized);
    imageStore(u_dst, px, m + vec4(0.0 * v));
}
