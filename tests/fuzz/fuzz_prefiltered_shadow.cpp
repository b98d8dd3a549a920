// libFuzzer target for include/shadowkit/prefiltered_shadow.hpp: every public function with decoded
// depths, ranges, formats, settings, moment vectors and buffers (NaN/Inf, huge values, out-of-range
// enums included). Traps on: a status Ok with a non-finite or out-of-range output, count > capacity
// or count != needed with Ok, a lookup outside [0, 1], a total function with a non-finite output,
// an exponent limit whose worst texel overflows or whose next float does not; the soft lookup's
// uniforms, blocker, penumbra and levels out of range, a soft visibility outside [0, 1].
#include <shadowkit/prefiltered_shadow.hpp>

#include "fuzz_input.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>

using shadowkit_fuzz::all_finite;
using shadowkit_fuzz::check;

namespace {
bool unit(float v) { return v >= 0.0f && v <= 1.0f; }
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace shadowkit;
    shadowkit_fuzz::FuzzInput r(data, size);
    const auto method = static_cast<PrefilterMethod>(r.range(0, 6));
    const auto format = static_cast<PrefilterFormat>(r.range(0, 3));
    const bool raw = r.boolean();

    // ---- depth range and maps
    const float n = r.value(raw, 0.25f), f = r.value(raw, 0.25f);
    const PrefilterDepthRange range = prefilter_depth_range(n, f);
    shadowkit_fuzz::check_detail(range);
    if (range.status == Status::Ok) check(std::isfinite(range.scale) && std::isfinite(range.offset) && range.scale > 0.0f);
    const float d = r.f32();
    check(unit(prefilter_depth(d, range)));
    check(unit(prefilter_depth(d, PrefilterDepthRange{})));
    const float pn = r.value(raw, 0.25f), pf = r.boolean() ? INFINITY : r.value(raw, 0.25f);
    const bool persp = r.boolean(), rev = r.boolean();
    const PrefilterWindowMap wm = prefilter_window_depth_map(pn, pf, persp, rev, range);
    shadowkit_fuzz::check_detail(wm);
    if (wm.status == Status::Ok) check(all_finite(wm.coefficients));
    const float zw = r.f32();
    if (wm.status == Status::Ok && persp && pn >= 1e-6f && range.scale < 1e30f) {
        // item 4: an Ok map keeps t of the window depth the buffer holds within its tolerance (a
        // distance inside the range and the projection, window depth in double rounded to float)
        const double dl = std::fmax(double(pn), -double(range.offset) / double(range.scale));
        const double dh = std::fmin(double(pf), (1.0 - double(range.offset)) / double(range.scale));
        const double fr = std::isfinite(zw) ? std::fabs(std::fmod(double(zw), 1.0)) : 0.5;
        const double dd = dl + (dh - dl) * fr;
        if (dh > dl && dd > 0.0 && std::isfinite(dd)) {
            const double inv_f = std::isinf(pf) ? 0.0 : 1.0 / double(pf), span = 1.0 / double(pn) - inv_f;
            const double z = rev ? (1.0 / dd - inv_f) / span : (1.0 / double(pn) - 1.0 / dd) / span;
            const double t_true = dd * double(range.scale) + double(range.offset);
            check(std::fabs(double(prefilter_depth_from_window(static_cast<float>(z), wm.coefficients)) - t_true) <=
                  2.0 * double(kPrefilterWindowTolerance) + 1e-5 * std::fabs(t_true));
        }
    }
    check(unit(prefilter_depth_from_window(zw, wm.coefficients)));
    check(unit(prefilter_depth_from_window(zw, r.vec4())));

    // ---- storage and limits
    const double v = r.f64();
    const PrefilterStored st = prefilter_store(v, format);
    shadowkit_fuzz::check_detail(st);
    if (st.status == Status::Ok) {
        check(std::isfinite(st.value));
        if (format == PrefilterFormat::Unorm16) check(unit(st.value));
        if (format == PrefilterFormat::Float16) check(std::fabs(st.value) <= 65504.0f);
    }
    const std::uint32_t N = r.u32();
    const PrefilterExponent lim = prefilter_exponent_limit(method, format, N);
    shadowkit_fuzz::check_detail(lim);
    if (lim.status == Status::Ok) {
        check(std::isfinite(lim.exponent) && lim.exponent >= 0.0f && std::isfinite(lim.worst_value));
        const double k = method == PrefilterMethod::Esm ? 1.0 : 2.0;
        check(prefilter_store(double(N) * std::exp(k * double(lim.exponent)), format).status == Status::Ok);
        check(prefilter_store(double(N) * std::exp(k * double(std::nextafter(lim.exponent, INFINITY))), format).status ==
              Status::Overflow);
    }
    check(std::isfinite(prefilter_min_variance(format)) && prefilter_min_variance(format) > 0.0f);
    check(std::isfinite(prefilter_msm_moment_bias(format)));

    // ---- settings -> uniforms
    PrefilterSettings s;
    s.method = method;
    s.format = format;
    s.exponent_positive = r.mostly_within(100.0f);
    s.exponent_negative = r.mostly_within(100.0f);
    s.accumulated_samples = r.range<std::uint32_t>(0u, 100000u);
    s.min_variance = r.mostly_within(2.0f);
    s.bleed_reduction = r.mostly_within(2.0f);
    s.moment_bias = r.mostly_within(2.0f);
    const PrefilterUniforms u = prefilter_uniforms(s);
    shadowkit_fuzz::check_detail(u);
    if (u.status == Status::Ok) {
        check(all_finite(u.exponents) && std::isfinite(u.min_variance) && std::isfinite(u.bleed_reduction) &&
              std::isfinite(u.moment_bias) && all_finite(u.params()));
        check(u.channels == 1 || u.channels == 2 || u.channels == 4);
        check(u.method_code >= 0 && u.method_code <= 5);
        // the clear value of the map is finite in the format
        const glm::vec4 clear = prefilter_moments(1.0f, glm::vec2(0.0f), u);
        for (int c = 0; c < 4; ++c) check(prefilter_store(double(clear[c]), format).status == Status::Ok);
    }

    // ---- per-texel mirrors (total)
    const float t = r.f32(), a = r.f32(), b = r.f32(), c = r.f32(), e = r.f32();
    const glm::vec4 m = r.vec4();
    check(all_finite(prefilter_moments(t, glm::vec2(a, b), u)));
    check(all_finite(prefilter_vsm_moments(t, a, b)));
    check(std::isfinite(prefilter_esm_moment(t, c)));
    check(all_finite(prefilter_evsm_moments(t, c, e)));
    check(all_finite(prefilter_msm_moments(t)));
    check(all_finite(prefilter_msm_quantize(m)));
    check(all_finite(prefilter_msm_dequantize(m)));
    check(unit(prefilter_visibility(m, t, u)));
    check(unit(prefilter_vsm(glm::vec2(m), t, a, b)));
    check(unit(prefilter_esm(m.x, t, c)));
    check(unit(prefilter_evsm(m, t, c, e, r.boolean(), a, b)));
    const bool q = r.boolean();
    check(unit(prefilter_msm(m, t, a, q, b)));
    check(unit(prefilter_msm_hausdorff(m, t, a, q, b)));
    check(unit(prefilter_receiver_bias(r.vec3(), r.vec3(), r.f32())));
    // moment vectors of a real (two-depth) texel, stored in the format: still in [0, 1]
    const float t0 = r.f32(), t1 = r.f32(), w = r.f32();
    if (u.status == Status::Ok) {
        const float ww = std::isfinite(w) ? std::fabs(std::fmod(w, 1.0f)) : 0.5f;
        glm::vec4 mix = ww * prefilter_moments(t0, glm::vec2(0.0f), u) + (1.0f - ww) * prefilter_moments(t1, glm::vec2(0.0f), u);
        for (int k = 0; k < 4; ++k) mix[k] = prefilter_store(double(mix[k]), format).value;
        check(unit(prefilter_visibility(mix, t, u)));
    }

    // ---- filtering
    const auto shape = static_cast<PrefilterBlur>(r.range(0, 2));
    const float width = r.value(raw, 0.5f);
    float weights[kPrefilterMaxWeights + 1];
    const std::size_t cap = r.size(kPrefilterMaxWeights + 1);
    const PrefilterKernel k = prefilter_blur_weights(shape, width, r.boolean() ? nullptr : weights, cap);
    shadowkit_fuzz::check_detail(k);
    check(k.count <= cap);
    if (k.status == Status::Ok) {
        check(k.count == k.needed && k.count == static_cast<std::size_t>(k.radius) + 1u && k.radius <= kPrefilterMaxRadius);
        double sum = weights[0];
        for (int i = 1; i <= k.radius; ++i) sum += 2.0 * double(weights[i]);
        for (int i = 0; i <= k.radius; ++i) check(std::isfinite(weights[i]) && weights[i] >= 0.0f);
        check(std::fabs(sum - 1.0) < 1e-4);
    }
    const glm::mat4 P = r.boolean() ? r.perspective(1.0f, r.boolean()) : r.mat4();
    const PrefilterKernelWidth kw = prefilter_kernel_texels(P, r.f32(), r.f32(), r.i32(), r.i32());
    shadowkit_fuzz::check_detail(kw);
    if (kw.status == Status::Ok) check(all_finite(kw.texels) && kw.texels.x >= 0.0f && kw.texels.y >= 0.0f);
    // ---- soft shadows
    PrefilterSoftSettings ss;
    ss.light_proj = r.boolean() ? r.perspective(1.0f, r.boolean()) : r.mat4();
    ss.light_width = r.value(raw, 1.0f);
    ss.range = r.boolean() ? range : prefilter_depth_range(r.value(raw, 0.25f), r.value(raw, 0.25f));
    ss.map_size = r.boolean() ? (1 << r.range(0, 14)) : r.i32();
    const PrefilterSoftUniforms su = prefilter_soft_uniforms(ss);
    shadowkit_fuzz::check_detail(su);
    if (su.status == Status::Ok)
        check(all_finite(su.params()) && std::isfinite(su.max_level) && su.light_uv >= 0.0f && su.distance_offset > 0.0f &&
              su.distance_scale > 0.0f);
    const PrefilterSoftUniforms& sx = r.boolean() ? su : PrefilterSoftUniforms{};
    const PrefilterBlocker bl = prefilter_soft_blocker(m, t, u);
    shadowkit_fuzz::check_detail(bl);
    if (bl.status == Status::Ok) check(unit(bl.fraction) && unit(bl.depth) && (bl.blocker_found == (bl.fraction > 0.0f)));
    const float tr = r.f32(), tb = r.f32();
    const PrefilterPenumbra pen = prefilter_soft_penumbra(tr, tb, sx);
    shadowkit_fuzz::check_detail(pen);
    if (pen.status == Status::Ok)
        check(std::isfinite(pen.width_world) && pen.width_world >= 0.0f && unit(pen.width_uv) && pen.level >= 0.0f &&
              pen.level <= sx.max_level);
    check(unit(prefilter_soft_width(tr, tb, sx)));
    const float lv = prefilter_soft_level_of(r.f32(), sx);
    check(std::isfinite(lv) && lv >= 0.0f && lv <= (sx.status == Status::Ok ? sx.max_level : 0.0f));
    const glm::vec4 m2 = r.vec4();
    const float sv = prefilter_soft_visibility([&](float level) {
        check(std::isfinite(level) && level >= 0.0f);
        return level > 0.0f ? m2 : m;
    }, t, u, sx, glm::vec2(r.f32(), r.f32()));
    check(unit(sv));
    const float sl = prefilter_receiver_slope(r.vec3(), r.vec3());
    check(std::isfinite(sl) && sl >= 0.0f && sl <= 1e6f);
    // ---- bound properties (issue #27)
    // item 1: MSM with the Float32 defaults lights a one-depth texel read at its own depth
    {
        const float t1 = r.f32();
        const float z = std::isfinite(t1) ? std::fabs(std::fmod(t1, 1.0f)) : 0.5f;
        PrefilterSettings ms;
        ms.method = r.boolean() ? PrefilterMethod::Msm : PrefilterMethod::MsmHausdorff;
        ms.format = PrefilterFormat::Float32;
        const PrefilterUniforms mu = prefilter_uniforms(ms);
        check(mu.status == Status::Ok);
        check(prefilter_visibility(prefilter_moments(z, glm::vec2(0.0f), mu), z, mu) >= 0.999f);
    }
    // item 2: VSM (default uniforms of any format) is never below the true lit fraction of a texel of
    // two or three depths, moments summed in fp32 and stored in the format
    {
        PrefilterSettings vs;
        vs.format = static_cast<PrefilterFormat>(r.range(0, 2));
        const PrefilterUniforms vu = prefilter_uniforms(vs);
        check(vu.status == Status::Ok);
        const int k = r.boolean() ? 3 : 2;
        float z[3], w[3], sw = 0.0f;
        for (int i = 0; i < k; ++i) {
            const float zi = r.f32(), wi = r.f32();
            z[i] = std::isfinite(zi) ? std::fabs(std::fmod(zi, 1.0f)) : 1.0f;
            w[i] = 0.05f + (std::isfinite(wi) ? std::fabs(std::fmod(wi, 1.0f)) : 0.5f);
            sw += w[i];
        }
        glm::vec2 vm(0.0f);
        for (int i = 0; i < k; ++i) vm += (w[i] / sw) * prefilter_vsm_moments(z[i], 0.0f, 0.0f);
        vm = glm::vec2(prefilter_store(double(vm.x), vs.format).value, prefilter_store(double(vm.y), vs.format).value);
        for (int j = 0; j < k; ++j) {
            long double num = 0.0L, den = 0.0L;
            for (int i = 0; i < k; ++i) {
                den += (long double)(w[i] / sw);
                if (z[i] >= z[j]) num += (long double)(w[i] / sw);
            }
            check(double(prefilter_visibility(glm::vec4(vm, 0.0f, 0.0f), z[j], vu)) >= double(num / den));
        }
    }
    (void)status_name(static_cast<Status>(r.u8()));
    return 0;
}
