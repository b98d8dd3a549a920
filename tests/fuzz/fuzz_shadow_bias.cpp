// libFuzzer target for include/shadowkit/shadow_bias.hpp: every public function with decoded
// vectors, depths, formats and metrics (NaN/Inf and invalid enum values included). Invariants trap
// on violation: no result says NotRun; Ok only with finite outputs in their documented range.
#include <shadowkit/shadow_bias.hpp>

#include "fuzz_input.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

using shadowkit_fuzz::all_finite;

namespace {
using namespace shadowkit;
bool fits(double v) { return std::isfinite(v) && std::fabs(v) <= double(std::numeric_limits<float>::max()); }
void check(const BiasValue& r) {
    if (r.status == Status::NotRun) __builtin_trap();
    shadowkit_fuzz::check_detail(r);
    if (r.status == Status::Ok ? !std::isfinite(r.value) : r.value != 0.0f) __builtin_trap();
}
void check(const BiasDepthValue& r) {
    if (r.status == Status::NotRun) __builtin_trap();
    shadowkit_fuzz::check_detail(r);
    if (r.status == Status::Ok ? !fits(r.value) : r.value != 0.0) __builtin_trap();
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    shadowkit_fuzz::FuzzInput r(data, size);
    const DepthFormat fmt = static_cast<DepthFormat>(r.range(0, 3));          // 3: invalid
    const BiasDepthMetric metric = static_cast<BiasDepthMetric>(r.range(0, 4));  // 4: invalid
    const double v = r.f64(), dist = r.f64(), n = r.f64(), f = r.f64();
    const float a = r.f32(), b = r.f32(), c = r.f32(), e = r.f32();
    const glm::vec3 p = r.vec3(), nrm = r.vec3(), l = r.vec3(), dx = r.vec3(), dy = r.vec3();
    const bool rev = r.boolean();

    const BiasDepthValue q = bias_quantize_depth(fmt, v);
    check(q);
    if (q.status == Status::Ok && fmt != DepthFormat::Float32 && !(q.value >= 0.0 && q.value <= 1.0)) __builtin_trap();
    const BiasDepthValue st = bias_depth_format_step(fmt, v);
    check(st);
    if (st.status == Status::Ok && !(st.value > 0.0)) __builtin_trap();
    const int bits = bias_depth_format_bits(fmt);
    if (bits != 0 && bits != 16 && bits != 24) __builtin_trap();
    check(bias_depth_metric_value(metric, dist, n, f));
    const BiasDepthValue sl = bias_depth_metric_slope(metric, dist, n, f);
    check(sl);
    if (sl.status == Status::Ok && !(sl.value > 0.0)) __builtin_trap();
    // the unit converters: Ok only where the slope is, non-negative, and a round trip within 1e-6
    const BiasDepthValue bw = bias_window_from_world(double(a), metric, dist, n, f);
    check(bw);
    if (bw.status == Status::Ok && (sl.status != Status::Ok || !(bw.value >= 0.0))) __builtin_trap();
    if (bw.status == Status::Ok && bw.value > 1e-290 && bw.value < 1e30) {  // (double subnormals lose the relative precision)
        const BiasDepthValue back = bias_world_from_window(bw.value, metric, dist, n, f);
        if (back.status == Status::Ok && !(std::fabs(back.value - double(a)) <= 1e-6 * std::fabs(double(a)) + 1e-300)) __builtin_trap();
    }
    const BiasDepthValue res = bias_depth_metric_resolution(metric, fmt, dist, n, f);
    check(res);
    if (res.status == Status::Ok && !(res.value > 0.0)) __builtin_trap();
    const BiasValue tw = bias_texel_world_size_perspective(a, b, c);
    check(tw);
    if (tw.status == Status::Ok && tw.value < 0.0f) __builtin_trap();
    const BiasValue to = bias_texel_world_size_ortho(a, b);
    check(to);
    if (to.status == Status::Ok && to.value < 0.0f) __builtin_trap();
    (void)bias_shadow_test_lit(a, b, c, rev);

    const BiasTanAngle tn = bias_light_tan_angle(nrm, l);
    if (tn.status == Status::NotRun) __builtin_trap();
    shadowkit_fuzz::check_detail(tn);
    if (tn.status == Status::Ok) {
        if (!std::isfinite(tn.value) || tn.value < 0.0f) __builtin_trap();
        if (!tn.faces_light && tn.value != 0.0f) __builtin_trap();
    }
    const BiasDepthGradient g = bias_plane_depth_gradient(nrm, dx, dy, l);
    if (g.status == Status::NotRun) __builtin_trap();
    shadowkit_fuzz::check_detail(g);
    if (g.status == Status::Ok && !(std::isfinite(g.dz_duv.x) && std::isfinite(g.dz_duv.y))) __builtin_trap();
    if (g.edge_on && g.dz_duv != glm::vec2(0.0f)) __builtin_trap();
    const BiasValue delta = bias_texel_depth_delta(g.dz_duv, a);
    check(delta);
    if (delta.status == Status::Ok && delta.value < 0.0f) __builtin_trap();
    const BiasValue sb = bias_slope_scaled(a, tn.value, b, c, e);
    check(sb);
    if (sb.status == Status::Ok && sb.value < c) __builtin_trap();  // never below the constant
    const BiasValue sb2 = bias_slope_scaled(a, b, c, e);
    check(sb2);
    const BiasDepthValue r_ = bias_polygon_offset_r(fmt, a);
    check(r_);
    if (r_.status == Status::Ok && !(r_.value > 0.0)) __builtin_trap();
    check(bias_polygon_offset(a, b, c, e, fmt, a, rev));
    check(bias_polygon_offset_units_for_world_bias(v, metric, fmt, dist, n, f));

    const BiasPosition off = bias_normal_offset_position(p, nrm, l, a, b);
    if (off.status == Status::NotRun) __builtin_trap();
    shadowkit_fuzz::check_detail(off);
    if (off.status == Status::Ok && !all_finite(off.position)) __builtin_trap();

    const BiasReceiverPlane rp = bias_receiver_plane_depth_gradient(dx, dy);
    if (rp.status == Status::NotRun) __builtin_trap();
    shadowkit_fuzz::check_detail(rp);
    if (rp.status == Status::Ok && !(std::isfinite(rp.dz_duv.x) && std::isfinite(rp.dz_duv.y))) __builtin_trap();
    if (rp.singular && rp.dz_duv != glm::vec2(0.0f)) __builtin_trap();
    check(bias_receiver_plane_depth(a, rp.dz_duv, glm::vec2(b, c)));
    const BiasValue tb = bias_receiver_plane_texel_bias(rp.dz_duv, glm::vec2(std::fabs(b), std::fabs(c)));
    check(tb);
    if (tb.status == Status::Ok && tb.value < 0.0f) __builtin_trap();

    const BiasValue sd = bias_second_depth_value(a, b, e);
    check(sd);
    if (sd.status == Status::Ok) {
        const float lo = a < b ? a : b, hi = a < b ? b : a;
        if (!(sd.value >= lo && sd.value <= hi)) __builtin_trap();
    }

    // the automatic bias: a fuzzer-chosen (often invalid) matrix, point, normal, map size and format
    const glm::mat4 m = r.boolean() ? r.mat4() : r.perspective(1.0f, false) * r.look_at_view();
    const ClipDepth clip = static_cast<ClipDepth>(r.range(0, 2));  // 2: invalid
    const glm::ivec2 map_size(static_cast<int>(r.range(0, 5000)) - 2, static_cast<int>(r.range(0, 5000)) - 2);
    const BiasPlaneGradient pg = bias_plane_gradient(m, clip, p, nrm);
    if (pg.status == Status::NotRun) __builtin_trap();
    shadowkit_fuzz::check_detail(pg);
    if (pg.status == Status::Ok) {
        if (!all_finite(pg.coord) || !std::isfinite(pg.dz_duv.x) || !std::isfinite(pg.dz_duv.y)) __builtin_trap();
        if (!(pg.position_error >= 0.0f) || !std::isfinite(pg.position_error)) __builtin_trap();
        if (pg.edge_on ? (pg.dz_duv != glm::vec2(0.0f) || pg.conditioning != 0.0f)
                       : !(pg.conditioning > 1e-4f && pg.conditioning <= 1.0f))
            __builtin_trap();
    }
    const BiasAutoLookup al = bias_auto_lookup(m, clip, rev, p, nrm, map_size, fmt);
    if (al.status == Status::NotRun) __builtin_trap();
    shadowkit_fuzz::check_detail(al);
    if (al.status == Status::Ok && !al.outside && !al.edge_on) {
        float wsum = 0.0f;
        for (int k = 0; k < 4; ++k) {
            if (!(al.tap_depth[k] >= 0.0f && al.tap_depth[k] <= 1.0f)) __builtin_trap();
            if (!(al.tap_weight[k] >= 0.0f && al.tap_weight[k] <= 1.0f)) __builtin_trap();
            if (!std::isfinite(al.tap_uv[k].x) || !std::isfinite(al.tap_uv[k].y)) __builtin_trap();
            wsum += al.tap_weight[k];
        }
        if (!(std::fabs(wsum - 1.0f) <= 1e-4f) || !(al.epsilon > 0.0f) || !std::isfinite(al.epsilon)) __builtin_trap();
        // the promise, at the lookup's own point: stored depths equal to the plane's at each tap are lit
        float stored[4];
        for (int k = 0; k < 4; ++k) stored[k] = rev ? al.tap_depth[k] - al.epsilon : al.tap_depth[k] + al.epsilon;
        const float vis = bias_auto_visibility(al, stored, rev, 1.0f);
        if (!(vis >= 0.0f && vis <= 1.0f)) __builtin_trap();
    }
    const float stored4[4] = {a, b, c, e};
    const float vis = bias_auto_visibility(al, stored4, rev, e);  // total: any input
    if (!(vis >= 0.0f && vis <= 1.0f)) __builtin_trap();
    const BiasValue ab = bias_auto_filtered(glm::vec2(a, b), c, std::fabs(e), glm::vec2(std::fabs(e), std::fabs(a)), b, std::fabs(c), rev);
    check(ab);
    if (ab.status == Status::Ok && !(ab.value > 0.0f)) __builtin_trap();
    return 0;
}
