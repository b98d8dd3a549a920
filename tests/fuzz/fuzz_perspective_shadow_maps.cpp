// libFuzzer target for shadowkit/perspective_shadow_maps.hpp: every method and the aliasing metric
// on inputs decoded from raw bytes; Ok results must be finite, errors finite too.
#include <shadowkit/perspective_shadow_maps.hpp>

#include "fuzz_input.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    shadowkit_fuzz::FuzzInput r(data, size);
    const uint8_t flags = r.u8();
    shadowkit::WarpInput in;
    in.camera_view = (flags & 1) ? r.mat4() : r.look_at_view();
    in.camera_proj = (flags & 2) ? r.mat4() : r.perspective(1.7f, (flags & 64) != 0);
    in.camera_depth = (flags & 4) ? shadowkit::ClipDepth::ZeroToOne : shadowkit::ClipDepth::NegativeOneToOne;
    in.camera_reversed_z = (flags & 8) != 0;
    in.max_distance = r.f32();
    in.receiver_min_depth = r.f32();
    in.receiver_max_depth = r.f32();
    in.light = glm::vec4(r.vec3(), (flags & 16) ? r.f32() : 0.0f);
    in.has_scene_bounds = (flags & 32) != 0;
    in.scene_min = r.vec3();
    in.scene_max = in.scene_min + glm::abs(r.vec3());
    const uint8_t f2 = r.u8();
    in.has_caster_bounds = (f2 & 1) != 0;
    in.caster_min = r.vec3();
    in.caster_max = r.vec3();
    in.light_depth = (f2 & 2) ? shadowkit::ClipDepth::ZeroToOne : shadowkit::ClipDepth::NegativeOneToOne;
    in.light_reversed_z = (f2 & 4) != 0;
    if (f2 & 8) {
        in.options.lispsm_n_scale = r.f32();
        in.options.lispsm_min_sin_gamma = r.f32();
        in.options.tsm_max_abs_cos_gamma = r.f32();
        in.options.tsm_focus_depth = r.f32();
        in.options.tsm_focus_ratio = r.f32();
        in.options.psm_min_near_fraction = r.f32();
        in.options.psm_slide_back = r.f32();
        in.options.psm_max_half_angle_deg = r.f32();
    }
    using Fn = shadowkit::WarpResult (*)(const shadowkit::WarpInput&);
    const Fn fns[4] = {shadowkit::uniform_shadow_matrix, shadowkit::psm_shadow_matrix, shadowkit::lispsm_shadow_matrix,
                       shadowkit::tsm_shadow_matrix};
    for (Fn fn : fns) {
        const shadowkit::WarpResult w = fn(in);
        if (!shadowkit_fuzz::all_finite(w.light_view_proj)) __builtin_trap();
        if (w.status != shadowkit::WarpStatus::Ok && w.fallback_uniform) __builtin_trap();
        if (!std::isfinite(w.sin_gamma) || !std::isfinite(w.warp_parameter)) __builtin_trap();
    }
    if (f2 & 16) {
        const shadowkit::WarpResult w = shadowkit::lispsm_shadow_matrix(in);
        const shadowkit::AliasingStats a =
            shadowkit::measure_perspective_aliasing(in, w.light_view_proj, r.u8() * 8u, {r.u8() * 4u, r.u8() * 4u},
                                                    r.range(0u, 7u), r.range(0u, 7u), r.range(0u, 7u));
        if (std::isnan(a.max_error) || std::isnan(a.mean_error) || a.undersampled_fraction < 0.0 || a.undersampled_fraction > 1.0) __builtin_trap();
        const double e = shadowkit::perspective_aliasing_error(w.light_view_proj, in.camera_proj * in.camera_view,
                                                               r.vec3(), r.vec3(), 1024, {640, 480});
        if (std::isnan(e) || e < 0.0) __builtin_trap();
    }
    return 0;
}
