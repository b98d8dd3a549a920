// libFuzzer target for include/shadowkit/shadow_bias.hpp: every function with decoded vectors,
// depths, formats and metrics (NaN/Inf included); invariants trap on violation.
#include <shadowkit/shadow_bias.hpp>

#include "fuzz_input.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>

using shadowkit_fuzz::all_finite;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace shadowkit;
    shadowkit_fuzz::FuzzInput r(data, size);
    const DepthFormat fmt = static_cast<DepthFormat>(r.range(0, 2));
    const DepthMetric metric = static_cast<DepthMetric>(r.range(0, 3));
    const double v = r.f64(), dist = r.f64(), n = r.f64(), f = r.f64();
    const float a = r.f32(), b = r.f32(), c = r.f32(), e = r.f32();
    const glm::vec3 p = r.vec3(), nrm = r.vec3(), l = r.vec3(), dx = r.vec3(), dy = r.vec3();
    const bool rev = r.boolean();

    const double q = quantize_depth(fmt, v);
    if (!std::isnan(v) && fmt != DepthFormat::Float32 && !(q >= 0.0 && q <= 1.0)) __builtin_trap();
    const double st = depth_format_step(fmt, v);
    if (!std::isnan(v) && !(st > 0.0)) __builtin_trap();
    (void)depth_format_bits(fmt);
    (void)depth_metric_value(metric, dist, n, f);
    (void)depth_metric_slope(metric, dist, n, f);
    const double res = depth_metric_resolution(metric, fmt, dist, n, f);
    if (!std::isnan(res) && !(res >= 0.0)) __builtin_trap();
    (void)texel_world_size_perspective(a, b, c);
    (void)texel_world_size_ortho(a, b);
    (void)shadow_test_lit(a, b, c, rev);

    const float tn = light_tan_angle(nrm, l);
    if (!std::isnan(tn) && tn < 0.0f) __builtin_trap();
    const DepthGradient g = plane_depth_gradient(nrm, dx, dy, l);
    if (g.ok && !(std::isfinite(g.dz_duv.x) && std::isfinite(g.dz_duv.y))) __builtin_trap();
    const float delta = texel_depth_delta(g.dz_duv, a);
    if (std::isfinite(a) && a >= 0.0f && g.ok && std::isfinite(delta) && delta < 0.0f) __builtin_trap();
    const float sb = slope_scaled_bias(a, tn, b, c, e);
    if (std::isfinite(a) && std::isfinite(b) && std::isfinite(c) && std::isfinite(e) && tn >= 0.0f && a >= 0.0f &&
        b >= 0.0f && e >= 0.0f && !std::isnan(sb) && sb < c - 1e-30f)
        __builtin_trap();
    const double r_ = polygon_offset_r(fmt, a);
    if (!std::isnan(a) && !(r_ > 0.0)) __builtin_trap();
    (void)polygon_offset(a, b, c, e, fmt, a, rev);
    (void)polygon_offset_units_for_world_bias(v, metric, fmt, dist, n, f);

    const glm::vec3 off = normal_offset_position(p, nrm, l, a, b);
    if (all_finite(p) && std::isfinite(a * b) && std::fabs(a * b) < 1e30f && !all_finite(off)) __builtin_trap();
    if (!all_finite(nrm) || !all_finite(l)) {
        if (!(off == p) && !(std::isnan(p.x) || std::isnan(p.y) || std::isnan(p.z))) __builtin_trap();
    }

    const ReceiverPlaneGradient rp = receiver_plane_depth_gradient(dx, dy);
    if (rp.ok && !(std::isfinite(rp.dz_duv.x) && std::isfinite(rp.dz_duv.y))) __builtin_trap();
    (void)receiver_plane_depth(a, rp.dz_duv, glm::vec2(b, c));
    const float tb = receiver_plane_texel_bias(rp.dz_duv, glm::vec2(std::fabs(b), std::fabs(c)));
    if (!std::isnan(tb) && tb < 0.0f) __builtin_trap();

    const float sd = second_depth_value(a, b, e);
    if (!std::isnan(a) && !std::isnan(b) && !std::isnan(e) && std::isfinite(a) && std::isfinite(b) && e >= 0.0f) {
        const float lo = a < b ? a : b, hi = a < b ? b : a;
        if (!(sd >= lo && sd <= hi)) __builtin_trap();
    }
    return 0;
}
