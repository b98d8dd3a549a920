// libFuzzer target for shadowkit/infinite_projection.hpp: every public function with arbitrary
// floats (NaN / Inf / denormals), flags and enum values. Invariants trap on violation: Ok only with
// finite outputs in their documented range; no result says NotRun.
#include <shadowkit/infinite_projection.hpp>

#include "fuzz_input.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

namespace {
namespace sk = shadowkit;
void check_matrix(const sk::ProjectionResult& r, const sk::ProjectionDepth& p) {
    if (r.status == sk::Status::NotRun) __builtin_trap();
    shadowkit_fuzz::check_detail(r);
    if (r.status != sk::Status::Ok) return;
    if (!shadowkit_fuzz::all_finite(r.matrix)) __builtin_trap();
    if (r.matrix[2][3] != -1.0f || r.matrix[3][3] != 0.0f) __builtin_trap();
    // The float32 depth row maps the near plane (and a finite far plane) to within 1e-3 of its NDC value.
    const double lo = p.clip_depth == sk::ClipDepth::ZeroToOne ? 0.0 : -1.0;
    auto ndc = [&](double d) { return (-static_cast<double>(r.matrix[2][2]) * d + static_cast<double>(r.matrix[3][2])) / d; };
    const double n = p.near_z;
    if (std::fabs(ndc(n) - (p.reversed_z ? 1.0 : lo)) > 1e-3) __builtin_trap();
    if (std::isfinite(p.far_z) && std::fabs(ndc(p.far_z) - (p.reversed_z ? lo : 1.0)) > 1e-3) __builtin_trap();
}
void check_value(const sk::ProjectionValue& v) {
    if (v.status == sk::Status::NotRun) __builtin_trap();
    shadowkit_fuzz::check_detail(v);
    if (v.status == sk::Status::Ok) {
        if (!std::isfinite(v.value) || std::fabs(v.value) > static_cast<double>(std::numeric_limits<float>::max())) __builtin_trap();
    } else if (v.value != 0.0) {
        __builtin_trap();
    }
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    shadowkit_fuzz::FuzzInput in(data, size);
    const std::uint8_t flags = in.u8();
    sk::ProjectionDepth p;
    p.near_z = in.f32();
    p.far_z = (flags & 4) ? in.f32() : HUGE_VALF;
    p.clip_depth = (flags & 1) ? sk::ClipDepth::ZeroToOne : sk::ClipDepth::NegativeOneToOne;
    if (flags & 64) p.clip_depth = static_cast<sk::ClipDepth>(in.range(0, 3));
    p.reversed_z = (flags & 2) != 0;
    p.epsilon = (flags & 8) ? in.f32() : 0.0f;
    if (flags & 16) p.far_z = std::nextafter(p.near_z, HUGE_VALF) * (1.0f + static_cast<float>(in.u8()) * 1e-6f);
    const float fovy = in.f32(), aspect = in.f32();
    const float l = in.f32(), r = in.f32(), b = in.f32(), t = in.f32();
    const double dist = (flags & 32) ? static_cast<double>(in.f32()) : in.f64();
    const double window = in.f64();
    const sk::DepthFormat fmt = static_cast<sk::DepthFormat>(in.range(0, 3));  // 3 is invalid on purpose

    const sk::Status vs = sk::projection_validate(p);
    if (vs == sk::Status::NotRun) __builtin_trap();
    check_matrix(sk::projection_perspective(fovy, aspect, p), p);
    check_matrix(sk::projection_frustum(l, r, b, t, p), p);
    {
        sk::ProjectionDepth q = p;
        q.far_z = HUGE_VALF;
        check_matrix(sk::projection_perspective_infinite(fovy, aspect, p.near_z, p.clip_depth, p.reversed_z, p.epsilon), q);
        q = p;
        q.epsilon = 0.0f;
        check_matrix(sk::projection_perspective_finite(fovy, aspect, p.near_z, p.far_z, p.clip_depth, p.reversed_z), q);
    }

    const sk::ProjectionDepthMapping m = sk::projection_depth_mapping(p);
    shadowkit_fuzz::check_detail(m);
    if (m.status != vs) __builtin_trap();
    if (m.status == sk::Status::Ok && (!std::isfinite(m.A) || !std::isfinite(m.B))) __builtin_trap();

    const sk::ProjectionValue w = sk::projection_window_depth(p, dist);
    check_value(w);
    if (w.status == sk::Status::Ok) {
        // Inside the clip range [near, far] the window depth is in [0, 1] (small rounding slack).
        const double N = p.near_z, F = p.far_z;
        if (dist >= N && dist <= F && (w.value < -1e-9 || w.value > 1.0 + 1e-9)) __builtin_trap();
    }
    check_value(sk::projection_ndc_depth(p, dist));
    const sk::ProjectionEyeDistance e = sk::projection_eye_distance_from_window_depth(p, window);
    shadowkit_fuzz::check_detail(e);
    if (e.status == sk::Status::NotRun) __builtin_trap();
    if (e.status == sk::Status::Ok && !e.at_infinity && !(e.value > 0.0 && std::isfinite(e.value))) __builtin_trap();
    if (e.at_infinity && (e.status != sk::Status::Ok || e.value != 0.0)) __builtin_trap();
    const sk::ProjectionValue res = sk::projection_depth_resolution(p, fmt, dist);
    check_value(res);
    if (res.status == sk::Status::Ok && !(res.value > 0.0)) __builtin_trap();
    const sk::ProjectionEpsilonBound eb =
        sk::projection_infinite_epsilon_bound(fovy, aspect, p.clip_depth, p.reversed_z, fmt, in.f32());
    if (eb.status == sk::Status::NotRun) __builtin_trap();
    shadowkit_fuzz::check_detail(eb);
    if (eb.status == sk::Status::Ok) {
        if (!(eb.epsilon >= 0.0f && eb.epsilon <= 0.5f) || eb.epsilon < eb.clip || eb.epsilon < eb.storage) __builtin_trap();
    }
    return 0;
}
