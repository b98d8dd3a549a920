// libFuzzer target for include/shadowkit/pcss.hpp: lights, depths, blocker samples and policies
// decoded from bytes (NaN/Inf included); invariants trap on violation.
#include <shadowkit/pcss.hpp>

#include "fuzz_input.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace shadowkit;
    shadowkit_fuzz::FuzzInput r(data, size);
    PcssLight L;
    L.type = r.boolean() ? PcssLightType::Directional : PcssLightType::Perspective;
    L.size = r.f32();
    L.near = r.f32();
    L.far = r.f32();
    L.frustum_width = r.f32();
    const float z_r = r.f32();
    const float z_w = r.f32();
    const float bias = r.f32();
    const uint8_t flags = r.u8();
    const bool reversed = flags & 1;
    PcssPolicy pol;
    if (flags & 2) {
        pol.min_filter_uv = r.f32();
        pol.max_filter_uv = r.f32();
        pol.map_resolution = r.f32();
        pol.min_taps = r.i32();
        pol.max_taps = r.i32();
        pol.texels_per_tap = r.f32();
    }
    std::vector<float> samples;
    while (r.remaining() >= 4 && samples.size() < 256) samples.push_back(r.f32());

    // Linearization: valid planes and a window depth in [0,1] give a distance in [n, f].
    const float lin = linearize_window_depth(z_w, L.near, L.far, reversed);
    const bool planes_ok = std::isfinite(L.near) && L.near > 0.0f && L.far > L.near;
    if (planes_ok && !std::isnan(z_w)) {
        if (std::isnan(lin)) __builtin_trap();
        if (lin < L.near * (1.0f - 1e-5f) || lin > L.far * (1.0f + 1e-5f)) __builtin_trap();
        const float back = delinearize_window_depth(lin, L.near, L.far, reversed);
        if (std::isnan(back) || back < -1e-6f || back > 1.0f + 1e-6f) __builtin_trap();
    }
    (void)linearize_ndc_depth(z_w, L.near, L.far, ClipDepth::NegativeOneToOne, reversed);
    (void)linearize_ndc_depth(z_w, L.near, L.far, ClipDepth::ZeroToOne, reversed);
    (void)linearize_ortho_window_depth(z_w, L.near, L.far, reversed);

    (void)pcss_search_width(L.size, z_r, L.near);
    const float pen = pcss_penumbra_width(L.size, z_r, bias);
    if (!std::isnan(pen) && pen < 0.0f && L.size >= 0.0f) __builtin_trap();
    (void)pcss_filter_width(pen, z_r, L.near);
    (void)perspective_width_to_uv(L.size, z_r, L.frustum_width);
    (void)pcss_search_width_directional(L.size, z_r, L.near);
    (void)pcss_penumbra_width_directional(L.size, z_r, bias);
    (void)pcss_light_uv_at_near(L);
    (void)pcss_search_uv(L, z_r);
    (void)pcss_penumbra_width_from_window_depth(L.size, z_w, bias, L.near, L.far, reversed);

    const PcssBlocker b = pcss_average_blocker(samples.data(), samples.size(), z_r, bias);
    if (b.found) {
        if (b.count == 0 || b.count > samples.size() || !std::isfinite(b.average) || !(b.average > 0.0f)) __builtin_trap();
    } else if (b.count != 0) {
        __builtin_trap();
    }

    const float cl = pcss_clamp_filter(z_r, pol.min_filter_uv, pol.max_filter_uv);
    if (pol.min_filter_uv <= pol.max_filter_uv && !(cl >= pol.min_filter_uv && cl <= pol.max_filter_uv)) __builtin_trap();
    const int t = pcss_tap_budget(z_r, pol.min_taps, pol.max_taps, pol.texels_per_tap);
    const int lo = pol.min_taps < 1 ? 1 : pol.min_taps, hi = pol.max_taps < lo ? lo : pol.max_taps;
    if (t < lo || t > hi) __builtin_trap();

    PcssBlocker fake;
    fake.found = (flags & 4) != 0;
    fake.average = bias;
    fake.count = 1;
    for (const PcssBlocker& bb : {b, fake}) {
        const PcssFilter f = pcss_filter(L, z_r, bb, pol);
        if (f.status == PcssStatus::Ok) {
            if (!std::isfinite(f.filter_uv) || f.filter_uv < pol.min_filter_uv || f.filter_uv > pol.max_filter_uv)
                __builtin_trap();
            if (f.taps < lo || f.taps > hi) __builtin_trap();
            if (std::isnan(f.penumbra_width) || f.penumbra_width < 0.0f) __builtin_trap();
            if (L.size == 0.0f && f.filter_uv != pol.min_filter_uv) __builtin_trap();  // hard shadow
        } else if (f.status == PcssStatus::NoBlocker) {
            if (bb.found || f.taps != 0) __builtin_trap();
        }
    }
    return 0;
}
