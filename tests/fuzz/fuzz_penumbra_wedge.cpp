// libFuzzer target for shadowkit/penumbra_wedge.hpp: edges, lights, receiver points, extents and
// matrices decoded from raw float bits (NaN, Inf, denormals, huge values all reachable).
// Invariants (trap on violation): Status::Ok only with finite outputs (issue 19); Ok wedges have
// finite unit-normal planes and contain their own edge endpoints and apex (relative tolerance);
// skipped and failed wedges are never "inside" and have no drawable hull; coverage is finite with
// |c| <= 1/2; visibility is in [0, 1]; hulls are finite with indices < 6; scissor rectangles (whole
// hull, hull clipped to a box, raw points) lie in the viewport with 0 <= depth_min <= depth_max <= 1,
// a zero viewport is never Ok; the plane evaluation (detail::pw_plane_eval): hard plane through c,
// e0, e1, bounding planes tangent to the ball moved out by the padding, penumbra_point_in_(half_)wedge
// = its plane tests, finite and linear in the plane for finite input.
#include <shadowkit/penumbra_wedge.hpp>

#include "fuzz_input.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace {
using shadowkit_fuzz::all_finite;

// mostly "reasonable" values (|x| < 100) so the deep paths are reached, raw bits otherwise
float g(shadowkit_fuzz::FuzzInput& in) { return in.mostly_within(100.0f); }
glm::vec3 v3(shadowkit_fuzz::FuzzInput& in) {
    const float a = g(in), b = g(in), c = g(in);
    return glm::vec3(a, b, c);
}
double mag(const glm::vec3& v) { return std::sqrt(double(v.x) * v.x + double(v.y) * v.y + double(v.z) * v.z); }
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    shadowkit_fuzz::FuzzInput R(data, size);
    const glm::vec3 e0 = v3(R), e1 = v3(R);
    // (the byte layout of the first reads is kept so that the regression inputs mean what they meant;
    // other light encodings are decoded from the end of the input, below)
    shadowkit::PenumbraSphereLight L;
    const glm::vec3 center = v3(R);
    L.light_position = glm::vec4(center, 1.0f);
    L.radius = g(R);
    const glm::vec3 p = v3(R);
    const float pad = g(R);
    const float extent = g(R);

    const shadowkit::PenumbraWedge w = shadowkit::penumbra_wedge(e0, e1, L, pad);
    shadowkit_fuzz::check_detail(w);
    const bool light_ok = all_finite(center) && std::isfinite(L.radius) && L.radius >= 0.0f;
    if (w.status == shadowkit::Status::Ok && !light_ok) __builtin_trap();
    if (w.status == shadowkit::Status::Ok && w.skip == shadowkit::PenumbraWedgeSkip::None) {
        const glm::vec4 pl[5] = {w.outer_bound, w.inner_bound, w.side[0], w.side[1], w.hard_plane};
        for (const glm::vec4& q : pl) {
            if (!all_finite(q)) __builtin_trap();
            const double nl = mag(glm::vec3(q));
            if (std::fabs(nl - 1.0) > 1e-3) __builtin_trap();
        }
        for (int i = 0; i < 2; ++i)
            if (!all_finite(w.apex[i]) || !all_finite(w.ray_outer[i]) || !all_finite(w.ray_inner[i])) __builtin_trap();
        // conservative: the edge and the apex are inside (tolerance relative to the coordinates)
        const double scale = std::max({mag(e0), mag(e1), mag(center), double(L.radius), 1.0});
        const float tol = static_cast<float>(1e-4 * scale);
        if (scale < 1e30) {
            if (!shadowkit::penumbra_point_in_wedge(e0, w, tol) || !shadowkit::penumbra_point_in_wedge(e1, w, tol)) __builtin_trap();
            if (!shadowkit::penumbra_point_in_wedge(w.apex[0], w, tol) || !shadowkit::penumbra_point_in_wedge(w.apex[1], w, tol))
                __builtin_trap();
        }
    } else {
        if (shadowkit::penumbra_point_in_wedge(p, w, 1.0f)) __builtin_trap();
        if (shadowkit::penumbra_wedge_hull(w, 1.0f).drawable) __builtin_trap();
        if (w.status == shadowkit::Status::NotRun) __builtin_trap();
    }
    (void)shadowkit::penumbra_point_in_half_wedge(p, w, true, 0.0f);
    (void)shadowkit::penumbra_point_in_half_wedge(p, w, false, 0.0f);
    const shadowkit::PenumbraHalfWedge ho = shadowkit::penumbra_outer_half_wedge(w);
    const shadowkit::PenumbraHalfWedge hi = shadowkit::penumbra_inner_half_wedge(w);
    (void)ho;
    (void)hi;

    const shadowkit::PenumbraValue cv = shadowkit::penumbra_edge_coverage(e0, e1, L, p);
    shadowkit_fuzz::check_detail(cv);
    if (cv.status == shadowkit::Status::Ok && (!std::isfinite(cv.value) || std::fabs(cv.value) > 0.5 + 1e-12)) __builtin_trap();
    if (cv.status == shadowkit::Status::NotRun) __builtin_trap();
    if (cv.status == shadowkit::Status::Ok && (!light_ok || !all_finite(e0) || !all_finite(e1) || !all_finite(p))) __builtin_trap();
    const glm::vec3 ends[4] = {e0, e1, e1, p};
    const shadowkit::PenumbraValue v = shadowkit::penumbra_visibility(ends, 2, L, p, R.range(-4, 4));
    shadowkit_fuzz::check_detail(v);
    if (v.status == shadowkit::Status::Ok && !(v.value >= 0.0 && v.value <= 1.0)) __builtin_trap();

    const shadowkit::PenumbraWedgeHull h = shadowkit::penumbra_wedge_hull(w, extent);
    shadowkit_fuzz::check_detail(h);
    if (h.drawable && h.status != shadowkit::Status::Ok) __builtin_trap();
    if (h.status == shadowkit::Status::Ok) {
        for (const glm::vec4& x : h.vertices)
            if (!all_finite(x)) __builtin_trap();
        for (uint8_t idx : h.indices)
            if (idx >= 6) __builtin_trap();
    }
    shadowkit::ScissorParams sp;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) sp.view_proj[c][r] = g(R);
    sp.clip_depth = R.boolean() ? shadowkit::ClipDepth::ZeroToOne : shadowkit::ClipDepth::NegativeOneToOne;
    sp.reversed_z = R.boolean();
    for (int k = 0; k < 4; ++k) sp.viewport[k] = R.range(-4999, 4999);
    const shadowkit::ScissorRect s = shadowkit::penumbra_wedge_scissor(h, sp);
    shadowkit_fuzz::check_detail(s);
    const glm::vec4 raw[3] = {glm::vec4(e0, 1.0f), glm::vec4(e1, g(R)), glm::vec4(p, 0.0f)};
    const shadowkit::ScissorRect s2 = shadowkit::penumbra_points_scissor(raw, 3, sp);
    shadowkit_fuzz::check_detail(s2);
    const glm::vec3 b0 = v3(R), b1 = v3(R);
    const shadowkit::ScissorRect s3 = shadowkit::penumbra_wedge_scissor_in_box(h, glm::min(b0, b1), glm::max(b0, b1), sp);
    shadowkit_fuzz::check_detail(s3);
    for (const shadowkit::ScissorRect* q : {&s, &s2, &s3}) {
        if (q->status == shadowkit::Status::NotRun) __builtin_trap();
        if (q->status == shadowkit::Status::Ok && (sp.viewport[2] <= 0 || sp.viewport[3] <= 0)) __builtin_trap();
        if (q->visible && q->status != shadowkit::Status::Ok) __builtin_trap();
        if (!q->visible) continue;
        if (q->width < 1 || q->height < 1) __builtin_trap();
        if (q->x < sp.viewport[0] || q->y < sp.viewport[1]) __builtin_trap();
        if (q->x + q->width > sp.viewport[0] + sp.viewport[2] || q->y + q->height > sp.viewport[1] + sp.viewport[3]) __builtin_trap();
        if (!(q->depth_min >= 0.0f && q->depth_min <= q->depth_max && q->depth_max <= 1.0f)) __builtin_trap();
    }
    const shadowkit::PenumbraPlane tp = shadowkit::penumbra_transform_plane(w.outer_bound, sp.view_proj);
    shadowkit_fuzz::check_detail(tp);
    if (tp.status == shadowkit::Status::Ok && !all_finite(tp.plane)) __builtin_trap();
    const shadowkit::PenumbraMatrix vt = shadowkit::penumbra_viewport_transform(sp.viewport, sp.clip_depth);
    shadowkit_fuzz::check_detail(vt);
    if (vt.status == shadowkit::Status::Ok && (!all_finite(vt.matrix) || sp.viewport[2] <= 0 || sp.viewport[3] <= 0)) __builtin_trap();
    const shadowkit::PenumbraBoundingSphere rl = shadowkit::penumbra_rect_bounding_sphere(L.light_position, e1, p);
    shadowkit_fuzz::check_detail(rl);
    if (rl.status == shadowkit::Status::Ok && (!std::isfinite(rl.light.radius) || rl.light.radius < 0.0f)) __builtin_trap();

    // the plane evaluation: the inside test (>= 0) of every wedge plane
    if (w.status == shadowkit::Status::Ok && w.skip == shadowkit::PenumbraWedgeSkip::None) {
        const double scale = std::max({mag(e0), mag(e1), mag(center), double(L.radius), double(pad), 1.0});
        const double tol = 1e-4 * scale;
        if (scale < 1e30) {
            // hard plane through c, e0, e1
            for (const glm::vec3& q : {center, e0, e1})
                if (std::fabs(shadowkit::detail::pw_plane_eval(w.hard_plane, q)) > tol) __builtin_trap();
            // the four bounding planes are tangent to the ball (ball outside), moved outward by the padding
            for (const glm::vec4& q : {w.outer_bound, w.inner_bound, w.side[0], w.side[1]}) {
                const double c = shadowkit::detail::pw_plane_eval(q, center);
                if (std::fabs(c - (double(pad) - double(L.radius))) > tol) __builtin_trap();
            }
        }
        // point_in_wedge / point_in_half_wedge are the documented plane_eval tests
        const float t = std::fabs(g(R));
        if (std::isfinite(t)) {
            const double mt = -double(t);
            const bool inside = shadowkit::detail::pw_plane_eval(w.outer_bound, p) >= mt &&
                                shadowkit::detail::pw_plane_eval(w.inner_bound, p) >= mt &&
                                shadowkit::detail::pw_plane_eval(w.side[0], p) >= mt &&
                                shadowkit::detail::pw_plane_eval(w.side[1], p) >= mt;
            if (shadowkit::penumbra_point_in_wedge(p, w, t) != inside) __builtin_trap();
            const double hv = shadowkit::detail::pw_plane_eval(w.hard_plane, p);
            if (shadowkit::penumbra_point_in_half_wedge(p, w, true, t) != (inside && hv >= mt)) __builtin_trap();
            if (shadowkit::penumbra_point_in_half_wedge(p, w, false, t) != (inside && hv <= double(t))) __builtin_trap();
            if (inside && !std::isnan(hv) && !shadowkit::penumbra_point_in_half_wedge(p, w, true, t) &&
                !shadowkit::penumbra_point_in_half_wedge(p, w, false, t))
                __builtin_trap();  // a point in the wedge is in one of its halves
        }
    }
    // arbitrary planes and points (NaN/Inf): finite for finite input; linear in the plane
    for (int it = 0; it < 2; ++it) {
        const bool rawbits = R.boolean();
        const glm::vec4 pl = rawbits ? glm::vec4(R.f32(), R.f32(), R.f32(), R.f32()) : glm::vec4(v3(R), g(R));
        const glm::vec3 x = rawbits ? R.vec3() : v3(R);
        const double e = shadowkit::detail::pw_plane_eval(pl, x);
        if (!all_finite(pl) || !all_finite(x)) continue;
        if (!std::isfinite(e)) __builtin_trap();
        if (shadowkit::detail::pw_plane_eval(-pl, x) != -e) __builtin_trap();  // exact: negation commutes with rounding
        const glm::vec4 pl2 = 2.0f * pl;
        if (all_finite(pl2) && shadowkit::detail::pw_plane_eval(pl2, x) != 2.0 * e) __builtin_trap();
        if (shadowkit::detail::pw_plane_eval(pl, glm::vec3(0.0f)) != double(pl.w)) __builtin_trap();
        // error of the double evaluation against an exact-ish long double one
        const long double ref = static_cast<long double>(pl.x) * x.x + static_cast<long double>(pl.y) * x.y +
                                static_cast<long double>(pl.z) * x.z + static_cast<long double>(pl.w);
        const long double m = std::fabs(static_cast<long double>(pl.x) * x.x) + std::fabs(static_cast<long double>(pl.y) * x.y) +
                              std::fabs(static_cast<long double>(pl.z) * x.z) + std::fabs(static_cast<long double>(pl.w));
        if (std::fabs(static_cast<long double>(e) - ref) > 1e-15L * m) __builtin_trap();
    }
    // other light encodings (w = 2: the same light; w = 0: a directional disk light, unsupported;
    // raw w) and a null endpoint pointer with a count
    {
        const uint8_t lk = R.u8();
        shadowkit::PenumbraSphereLight L2 = L;
        const float lw = (lk & 3) == 0 ? 2.0f : (lk & 3) == 1 ? 0.0f : (lk & 3) == 2 ? -1.0f : R.f32();
        L2.light_position = glm::vec4(lw == 2.0f ? 2.0f * center : center, lw);
        const bool ok2 = light_ok && (lw == 2.0f ? all_finite(2.0f * center) : lw > 0.0f);
        const shadowkit::PenumbraWedge w2 = shadowkit::penumbra_wedge(e0, e1, L2, pad);
        shadowkit_fuzz::check_detail(w2);
        if (w2.status == shadowkit::Status::Ok && !ok2) __builtin_trap();
        if (lw <= 0.0f && w2.status != shadowkit::Status::InvalidLight) __builtin_trap();
        const shadowkit::PenumbraValue c2 = shadowkit::penumbra_edge_coverage(e0, e1, L2, p);
        shadowkit_fuzz::check_detail(c2);
        if (c2.status == shadowkit::Status::Ok && (!ok2 || !std::isfinite(c2.value) || std::fabs(c2.value) > 0.5 + 1e-12))
            __builtin_trap();
        if (lw == 2.0f && c2.status == shadowkit::Status::Ok && cv.status == shadowkit::Status::Ok &&
            std::fabs(c2.value - cv.value) > 1e-6)
            __builtin_trap();  // the same light
        const shadowkit::PenumbraValue v2 = shadowkit::penumbra_visibility((lk & 4) ? nullptr : ends, 2, L2, p, 0);
        shadowkit_fuzz::check_detail(v2);
        if ((lk & 4) && v2.status == shadowkit::Status::Ok) __builtin_trap();  // null with a count: never Ok
        if (v2.status == shadowkit::Status::Ok && !(v2.value >= 0.0 && v2.value <= 1.0)) __builtin_trap();
    }
    return 0;
}
