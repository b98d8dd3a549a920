// libFuzzer target for shadowkit/infinite_projection.hpp: every public function with arbitrary
// floats (NaN / Inf / denormals) and flags. Invariants trap on violation.
#include <shadowkit/infinite_projection.hpp>

#include "fuzz_input.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>

namespace {
void check_matrix(const shadowkit::ProjectionResult& r) {
    if (r.status != shadowkit::ProjectionStatus::Ok) return;
    if (!shadowkit_fuzz::all_finite(r.matrix)) __builtin_trap();
    if (r.matrix[2][3] != -1.0f || r.matrix[3][3] != 0.0f) __builtin_trap();
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    namespace sk = shadowkit;
    shadowkit_fuzz::FuzzInput in(data, size);
    const std::uint8_t flags = in.u8();
    sk::DepthParams p;
    p.near_z = in.f32();
    p.far_z = (flags & 4) ? in.f32() : HUGE_VALF;
    p.clip_depth = (flags & 1) ? sk::ClipDepth::ZeroToOne : sk::ClipDepth::NegativeOneToOne;
    p.reversed_z = (flags & 2) != 0;
    p.epsilon = (flags & 8) ? in.f32() : 0.0f;
    const float fovy = in.f32(), aspect = in.f32();
    const float l = in.f32(), r = in.f32(), b = in.f32(), t = in.f32();
    const double dist = in.f64(), window = in.f64();
    const sk::DepthFormat fmt = static_cast<sk::DepthFormat>(in.range(0, 2));

    const sk::ProjectionStatus vs = sk::validate(p);
    check_matrix(sk::perspective(fovy, aspect, p));
    check_matrix(sk::frustum(l, r, b, t, p));
    check_matrix(sk::perspective_infinite(fovy, aspect, p.near_z, p.clip_depth, p.reversed_z, p.epsilon));
    check_matrix(sk::perspective_finite(fovy, aspect, p.near_z, p.far_z, p.clip_depth, p.reversed_z));

    const sk::DepthMapping m = sk::depth_mapping(p);
    if (m.status == sk::ProjectionStatus::Ok && (!std::isfinite(m.A) || !std::isfinite(m.B))) __builtin_trap();
    if (vs != sk::ProjectionStatus::Ok && m.status == sk::ProjectionStatus::Ok) __builtin_trap();

    const sk::DepthValue w = sk::window_depth(p, dist);
    if (w.status == sk::ProjectionStatus::Ok) {
        if (std::isnan(w.value)) __builtin_trap();
        // Inside the clip range [near, far] the window depth is in [0, 1] (small rounding slack).
        const double N = p.near_z, F = p.far_z;
        if (dist >= N && dist <= F && (w.value < -1e-9 || w.value > 1.0 + 1e-9)) __builtin_trap();
    } else if (!std::isnan(w.value)) {
        __builtin_trap();
    }
    const sk::DepthValue nd = sk::ndc_depth(p, dist);
    if (nd.status == sk::ProjectionStatus::Ok && std::isnan(nd.value)) __builtin_trap();
    const sk::DepthValue e = sk::eye_distance_from_window_depth(p, window);
    if (e.status == sk::ProjectionStatus::Ok && !(e.value > 0.0)) __builtin_trap();
    const sk::DepthValue res = sk::depth_resolution(p, fmt, dist);
    if (res.status == sk::ProjectionStatus::Ok && !(res.value > 0.0)) __builtin_trap();
    const sk::EpsilonBound eb = sk::infinite_epsilon_bound(fovy, aspect, p.clip_depth, p.reversed_z, fmt, in.f32());
    if (eb.status == sk::ProjectionStatus::Ok) {
        if (!(eb.epsilon >= 0.0f && eb.epsilon <= 0.5f) || eb.epsilon < eb.clip || eb.epsilon < eb.storage) __builtin_trap();
    }
    return 0;
}
