// Driver for glsl/prefiltered_shadow.glsl (fragment stage): declarations and a main() calling every function.
uniform sampler2D u_moments;
uniform sampler2DMS u_depth_ms;
uniform vec2 u_depth_scale_offset;   // prefilter_depth_range
uniform vec4 u_window_map;           // prefilter_window_depth_map
uniform int u_method;
uniform vec2 u_exponents;
uniform vec4 u_params;
uniform float u_moment_bias;
uniform bool u_quantized;
uniform float u_weights[SK_PREFILTER_MAX_WEIGHTS];
uniform int u_radius;
uniform vec4 u_soft;                 // prefilter_soft_uniforms(...).params()
in float v_light_distance;
in vec2 v_uv;
out vec4 o_color;
void main() {
    float t = sk_prefilter_depth(v_light_distance, u_depth_scale_offset);
    float tw = sk_prefilter_depth_from_window(gl_FragCoord.z, u_window_map)
             - sk_prefilter_receiver_bias(vec3(dFdx(v_uv), dFdx(t)), vec3(dFdy(v_uv), dFdy(t)), 0.01);
    vec4 m = sk_prefilter_moments(t, vec2(dFdx(t), dFdy(t)), u_method, u_exponents, u_quantized);
    vec2 vm = sk_vsm_moments(t, vec2(dFdx(t), dFdy(t)));
    float em = sk_esm_moment(t, u_exponents.x);
    vec4 ev = sk_evsm_moments(t, u_exponents);
    vec4 mm = sk_msm_dequantize(sk_msm_quantize(sk_msm_moments(t)));
    vec4 f = texture(u_moments, v_uv);
    float a = sk_prefilter_visibility(f, tw, u_method, u_params, u_moment_bias, u_quantized);
    float b = sk_vsm_visibility(f.xy, t, u_params.z, u_params.w) * sk_esm_visibility(f.x, t, u_exponents.x);
    float c = sk_evsm_visibility(f, t, u_exponents, true, u_params.z, u_params.w);
    float d = sk_msm_visibility(f, t, u_moment_bias, u_quantized, u_params.w) *
              sk_msm_hausdorff_visibility(f, t, u_moment_bias, u_quantized, u_params.w);
    vec4 blur = sk_prefilter_blur(u_moments, ivec2(gl_FragCoord.xy), ivec2(1, 0), u_radius, u_weights);
    vec4 res = sk_prefilter_resolve(u_depth_ms, ivec2(gl_FragCoord.xy), 4, u_window_map, u_method, u_exponents, u_quantized);
    vec2 blk = sk_prefilter_soft_blocker(f, t, u_method, u_params, u_moment_bias, u_quantized);
    float pw = sk_prefilter_soft_level_of(sk_prefilter_soft_width(t, blk.y, u_soft), u_soft);
    float slope = sk_prefilter_receiver_slope(vec3(dFdx(v_uv), dFdx(t)), vec3(dFdy(v_uv), dFdy(t)));
    float sv = sk_prefilter_soft_visibility(u_moments, v_uv, tw, u_method, u_params, u_moment_bias, u_quantized, u_soft,
                                            vec2(slope, 0.02));
    o_color = m + vec4(vm, em, 0.0) + ev + mm + vec4(a, b, c, d) + blur + res + vec4(blk, pw, sv);
}
