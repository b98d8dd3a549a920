// libFuzzer target for shadowkit/perspective_shadow_maps.hpp: every method (and warp_matrix with any
// method value), the aliasing error and its measurement, on inputs decoded from raw bytes. Traps on
// Ok with a non-finite or out-of-range output, on a fallback flag without Ok, and on non-finite
// matrices in any result.
#include <shadowkit/perspective_shadow_maps.hpp>

#include "fuzz_input.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>

namespace {

void check_result(const shadowkit::WarpResult& w) {
    using shadowkit_fuzz::all_finite;
    shadowkit_fuzz::check(all_finite(w.light_view_proj) && all_finite(w.depth_view_proj));
    shadowkit_fuzz::check_detail(w);
    if (w.status != shadowkit::Status::Ok) {
        shadowkit_fuzz::check(!w.fallback_uniform && !w.visible && !w.separate_depth);
        return;
    }
    shadowkit_fuzz::check(std::isfinite(w.sin_gamma) && std::isfinite(w.warp_parameter) && w.sin_gamma >= 0.0f &&
                          w.warp_strength >= 0.0f && w.warp_strength <= 1.0f && w.warp_parameter >= 0.0f);
    if (!w.separate_depth) shadowkit_fuzz::check(w.depth_view_proj == w.light_view_proj);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    shadowkit_fuzz::FuzzInput r(data, size);
    const uint8_t flags = r.u8();
    shadowkit::WarpInput in;
    in.camera_view = (flags & 1) ? r.mat4() : r.look_at_view();
    if (flags & 2) {
        in.camera_proj = r.mat4();
    } else if (flags & 128) {
        // a well-formed camera from bytes, so the fits' deep paths run: fovy, near, far (or infinite)
        const float fovy = 0.05f + 0.012f * float(r.u8()), near_z = std::ldexp(1.0f + float(r.u8()) / 64.0f, r.range(-20, 6));
        const float far_z = near_z * (1.0f + std::ldexp(float(r.u8()), r.range(-8, 12)));
        in.camera_proj = (flags & 64) ? glm::infinitePerspective(fovy, 1.0f + r.quantized(0.01f), near_z)
                                      : glm::perspective(fovy, 1.0f + r.quantized(0.01f), near_z, far_z);
        in.camera_proj[2][2] += r.quantized(1e-3f);  // epsilon-tweaked P_inf and friends
    } else {
        in.camera_proj = r.perspective(1.7f, (flags & 64) != 0);
    }
    in.camera_depth = (flags & 4) ? shadowkit::ClipDepth::ZeroToOne : shadowkit::ClipDepth::NegativeOneToOne;
    in.camera_reversed_z = (flags & 8) != 0;
    in.max_distance = r.mostly_within(1000.0f);
    in.receiver_min_depth = r.f32();
    in.receiver_max_depth = r.f32();
    const uint8_t lsel = r.u8();
    if (lsel & 1) in.light_position = r.vec4();
    else if (lsel & 8) in.light_position = glm::vec4(r.vec3(false, 0.5f), (lsel & 4) ? 1.0f : 0.0f);  // quantized
    else in.light_position = glm::vec4(r.vec3(), (lsel & 2) ? r.interesting_f32() : ((lsel & 4) ? 1.0f : 0.0f));
    in.has_scene_bounds = (flags & 32) != 0;
    in.scene_min = (lsel & 16) ? r.vec3(false, 0.5f) : r.vec3();
    in.scene_max = in.scene_min + glm::abs((lsel & 16) ? r.vec3(false, 0.5f) : r.vec3());
    const uint8_t f2 = r.u8();
    in.has_caster_bounds = (f2 & 1) != 0;
    in.caster_min = r.vec3();
    in.caster_max = (f2 & 32) ? in.caster_min + glm::abs(r.vec3()) : r.vec3();
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
    const Fn fns[4] = {shadowkit::warp_uniform_matrix, shadowkit::warp_psm_matrix, shadowkit::warp_lispsm_matrix,
                       shadowkit::warp_tsm_matrix};
    shadowkit::WarpResult last;
    for (Fn fn : fns) {
        last = fn(in);
        check_result(last);
    }
    check_result(shadowkit::warp_matrix(in, static_cast<shadowkit::WarpMethod>(r.u8() % 6)));
    if (f2 & 16) {
        const glm::mat4 m = (f2 & 64) ? r.mat4() : last.light_view_proj;
        const std::uint32_t nx = r.range(0u, 7u), ny = r.range(0u, 7u), nz = r.range(0u, 7u);
        const shadowkit::WarpAliasingStats a =
            shadowkit::warp_measure_aliasing(in, m, r.u8() * 8u, {r.u8() * 4u, r.u8() * 4u}, nx, ny, nz);
        shadowkit_fuzz::check_detail(a);
        if (a.status == shadowkit::Status::Ok)
            shadowkit_fuzz::check(std::isfinite(a.max_error) && std::isfinite(a.mean_error) && a.max_error >= 0.0 &&
                                  a.mean_error >= 0.0 && a.mean_error <= a.max_error * (1.0 + 1e-12) &&
                                  a.undersampled_fraction >= 0.0 && a.undersampled_fraction <= 1.0 &&
                                  std::uint64_t(a.samples) + a.skipped <= std::uint64_t(nx) * ny * nz);
        const glm::vec3 p = r.vec3(), n = r.vec3();
        const shadowkit::WarpAliasingValue e =
            shadowkit::warp_aliasing_error(m, in.camera_proj * in.camera_view, p, n, r.u16(), {r.u16(), r.u16()});
        shadowkit_fuzz::check_detail(e);
        if (e.status == shadowkit::Status::Ok) shadowkit_fuzz::check(std::isfinite(e.value) && e.value >= 0.0);
    }
    return 0;
}
