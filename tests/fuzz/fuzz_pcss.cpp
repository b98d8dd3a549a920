// libFuzzer target for include/shadowkit/pcss.hpp: lights, depths, view matrices, caster boxes,
// blocker samples and policies decoded from bytes (NaN/Inf and invalid enum values included).
// Invariants trap on violation: no result says NotRun; Ok only with finite outputs in range.
#include <shadowkit/pcss.hpp>

#include "fuzz_input.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace {
using namespace shadowkit;
void check(const PcssValue& v) {
    if (v.status == Status::NotRun) __builtin_trap();
    shadowkit_fuzz::check_detail(v);
    if (v.status == Status::Ok ? !std::isfinite(v.value) : v.value != 0.0f) __builtin_trap();
}
void check_nonneg(const PcssValue& v) {
    check(v);
    if (v.status == Status::Ok && v.value < 0.0f) __builtin_trap();
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    shadowkit_fuzz::FuzzInput r(data, size);
    PcssLight L;
    L.type = static_cast<PcssLightType>(r.range(0, 2));  // 2: invalid
    L.size = r.f32();
    L.near_z = r.f32();
    L.far_z = r.f32();
    L.frustum_width = r.f32();
    const float z_r = r.f32();
    const float z_w = r.f32();
    const float bias = r.f32();
    const uint8_t flags = r.u8();
    const bool reversed = flags & 1;
    PcssPolicy pol;
    pol.map_resolution = 2048.0f;
    if (flags & 2) {
        pol.min_filter_uv = r.f32();
        pol.max_filter_uv = r.f32();
        pol.map_resolution = r.f32();
        pol.min_taps = r.i32();
        pol.max_taps = r.i32();
        pol.texels_per_tap = r.f32();
    }
    glm::mat4 view(1.0f);
    glm::vec3 lo(0.0f), hi(1.0f);
    if (flags & 8) {
        view = r.mat4();
        lo = r.vec3();
        hi = r.vec3();
    } else {
        view = glm::lookAt(r.vec3(), glm::vec3(0.0f), glm::vec3(0.0f, 1.0f, 0.0f));
        lo = glm::vec3(r.i8(), r.i8(), r.i8()) * 0.25f;
        hi = lo + glm::vec3(r.u8(), r.u8(), r.u8()) * 0.25f;
    }
    const ClipDepth clip = static_cast<ClipDepth>(r.range(0, 2));
    std::vector<float> samples;
    while (r.remaining() >= 4 && samples.size() < 256) samples.push_back(r.f32());

    const Status vs = pcss_validate_light(L);
    if (vs == Status::NotRun) __builtin_trap();

    // Linearization: valid planes and a finite window depth give a distance in [n, f].
    const PcssValue lin = pcss_linearize_window_depth(z_w, L.near_z, L.far_z, reversed);
    check(lin);
    if (lin.status == Status::Ok) {
        if (lin.value < L.near_z * (1.0f - 1e-5f) || lin.value > L.far_z * (1.0f + 1e-5f)) __builtin_trap();
        const PcssValue back = pcss_delinearize_window_depth(lin.value, L.near_z, L.far_z, reversed);
        check(back);
        if (back.status != Status::Ok || back.value < 0.0f || back.value > 1.0f) __builtin_trap();
    }
    check(pcss_delinearize_window_depth(z_r, L.near_z, L.far_z, reversed));
    check(pcss_linearize_ndc_depth(z_w, L.near_z, L.far_z, clip, reversed));
    check(pcss_linearize_ortho_window_depth(z_w, L.near_z, L.far_z, reversed));

    check_nonneg(pcss_search_width(L.size, z_r, L.near_z));
    const PcssValue pen = pcss_penumbra_width(L.size, z_r, bias);
    check_nonneg(pen);
    check_nonneg(pcss_filter_width(pen.value, z_r, L.near_z));
    check_nonneg(pcss_width_to_uv(L.size, z_r, L.frustum_width));
    check_nonneg(pcss_search_width_directional(L.size, z_r, L.near_z));
    check_nonneg(pcss_penumbra_width_directional(L.size, z_r, bias));
    const PcssValue luv = pcss_light_uv_at_near(L);
    check_nonneg(luv);
    if (vs != Status::Ok && luv.status != vs) __builtin_trap();
    check_nonneg(pcss_search_uv(L, z_r));
    check_nonneg(pcss_penumbra_width_from_window_depth(L.size, z_w, bias, L.near_z, L.far_z, reversed));

    const PcssFit fit = pcss_fit_near_plane(L, view, lo, hi);
    if (fit.status == Status::NotRun) __builtin_trap();
    shadowkit_fuzz::check_detail(fit);
    if (fit.status == Status::Ok) {
        if (pcss_validate_light(fit.light) != Status::Ok) __builtin_trap();
        if (fit.light.near_z < L.near_z || !std::isfinite(fit.caster_near_z)) __builtin_trap();
        if (!fit.raised && fit.light.near_z != L.near_z) __builtin_trap();
    }

    const PcssBlocker b = pcss_average_blocker(samples.data(), samples.size(), z_r, bias);
    if (b.status == Status::NotRun) __builtin_trap();
    shadowkit_fuzz::check_detail(b);
    if (b.blocker_found) {
        if (b.status != Status::Ok || b.blocker_count == 0 || b.blocker_count > samples.size() ||
            !std::isfinite(b.average) || !(b.average > 0.0f))
            __builtin_trap();
    } else if (b.blocker_count != 0) {
        __builtin_trap();
    }
    if (pcss_average_blocker(nullptr, samples.size() + 1, z_r, bias).status == Status::Ok) __builtin_trap();

    const PcssValue cl = pcss_clamp_filter(z_r, pol.min_filter_uv, pol.max_filter_uv);
    check(cl);
    if (cl.status == Status::Ok && !(cl.value >= pol.min_filter_uv && cl.value <= pol.max_filter_uv)) __builtin_trap();
    const int t = pcss_tap_budget(z_r, pol.min_taps, pol.max_taps, pol.texels_per_tap);
    const int lo_t = pol.min_taps < 1 ? 1 : pol.min_taps, hi_t = pol.max_taps < lo_t ? lo_t : pol.max_taps;
    if (t < lo_t || t > hi_t) __builtin_trap();

    PcssBlocker fake;
    fake.status = (flags & 16) ? Status::Ok : Status::NotRun;
    fake.blocker_found = (flags & 4) != 0;
    fake.average = bias;
    fake.blocker_count = 1;
    for (const PcssBlocker& bb : {b, fake}) {
        const PcssFilter f = pcss_filter(L, z_r, bb, pol);
        if (f.status == Status::NotRun) __builtin_trap();
        shadowkit_fuzz::check_detail(f);
        if (f.status == Status::Ok) {
            if (!std::isfinite(f.search_uv) || f.search_uv < 0.0f || f.search_uv > pol.max_filter_uv) __builtin_trap();
            if (f.blocker_found) {
                if (!bb.blocker_found) __builtin_trap();
                if (!std::isfinite(f.filter_uv) || f.filter_uv < pol.min_filter_uv || f.filter_uv > pol.max_filter_uv)
                    __builtin_trap();
                if (f.taps < lo_t || f.taps > hi_t) __builtin_trap();
                if (!std::isfinite(f.penumbra_width) || f.penumbra_width < 0.0f) __builtin_trap();
                if (!std::isfinite(f.blocker_depth)) __builtin_trap();
                if (L.size == 0.0f && f.filter_uv != pol.min_filter_uv) __builtin_trap();  // hard shadow
            } else if (bb.blocker_found || f.taps != 0 || f.filter_uv != 0.0f) {
                __builtin_trap();
            }
        } else if (f.blocker_found || f.taps != 0) {
            __builtin_trap();
        }
    }
    return 0;
}
