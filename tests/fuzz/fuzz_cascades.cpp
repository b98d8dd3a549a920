// libFuzzer target for shadowkit/cascades.hpp: cascade_split_distances, cascade_fit, cascade_fit_slice, the SDSM fit,
// cascade_select_by_depth / _by_sphere and cascade_blend_weight on inputs decoded from raw bytes (NaN/Inf,
// null outputs with a capacity, near planes at or behind the eye, epsilon-tweaked infinite projections).
// Traps on Ok with a non-finite output or a broken invariant (monotonic splits, exact ends, count <=
// capacity, index in range), on Ok for a null pointer with a count, a point light or a near plane <= 0,
// or stable_world_depth without scene bounds.
#include <shadowkit/cascades.hpp>

#include "fuzz_input.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>

using shadowkit_fuzz::FuzzInput;
using shadowkit_fuzz::all_finite;
using shadowkit_fuzz::check_detail;

namespace {

// raw matrix, glm perspective (near may be <= 0), or an epsilon-tweaked infinite projection
// (glm's GL perspective is read as GL, not reversed: with near < 0 and a tiny far it is a valid
// reversed-Z projection, so near_bad holds only for the convention it was built for)
glm::mat4 camera_projection(FuzzInput& r, int mode, shadowkit::ClipDepth& cd, bool& rev, bool& near_bad) {
    near_bad = false;
    if (mode == 0) return r.mat4();
    const float fovy = r.f32(), n = r.f32(), f = r.f32();
    near_bad = std::isfinite(n) && n <= 0.0f;
    if (mode == 1) {
        cd = shadowkit::ClipDepth::NegativeOneToOne;
        rev = false;
        return glm::perspective(fovy, 1.5f, n, f);
    }
    const double eps = std::fabs(std::fmod(double(f), 0.5));
    const double t = 1.0 / std::tan(0.5 * double(fovy));
    glm::mat4 m(0.0f);
    m[0][0] = float(t / 1.5);
    m[1][1] = float(t);
    m[2][3] = -1.0f;
    const bool zo = cd == shadowkit::ClipDepth::ZeroToOne;
    double A = 1.0 - eps, B = zo ? -(1.0 - eps) * double(n) : -(2.0 - eps) * double(n);
    if (rev) {
        if (zo) { A = eps; B = (1.0 - eps) * double(n); }
        else { A = -A; B = -B; }
    }
    m[2][2] = float(-A);
    m[3][2] = float(B);
    return m;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    FuzzInput r(data, size);
    const uint8_t flags = r.u8();
    const uint8_t f2 = r.u8();
    // split distances
    const float n = r.f32(), f = r.f32(), lambda = r.f32();
    const uint32_t count = r.range<uint32_t>(0, 19);
    const shadowkit::CascadeSplits sp = shadowkit::cascade_split_distances(n, f, lambda, count);
    check_detail(sp);
    if (sp.status == shadowkit::Status::Ok) {
        if (count == 0 || count > 16 || sp.count != count) __builtin_trap();
        if (sp.distances[0] != n || sp.distances[count] != f) __builtin_trap();
        for (uint32_t i = 0; i < count; ++i)
            if (!(sp.distances[i] < sp.distances[i + 1])) __builtin_trap();
        const shadowkit::CascadeIndex sel = shadowkit::cascade_select_by_depth(r.f32(), sp.distances, count);
        check_detail(sel);
        if (sel.status == shadowkit::Status::Ok && (sel.index < -1 || sel.index >= int(count))) __builtin_trap();
    } else if (sp.count != 0) {
        __builtin_trap();
    }
    // selection on raw splits (not increasing, NaN, null)
    {
        float raw_splits[17];
        for (float& v : raw_splits) v = r.f32();
        const uint32_t rc = r.range<uint32_t>(0, 17);
        const shadowkit::CascadeIndex sel = shadowkit::cascade_select_by_depth(r.f32(), (f2 & 1) ? nullptr : raw_splits, rc > 16 ? 16 : rc);
        check_detail(sel);
        if ((f2 & 1) && sel.status == shadowkit::Status::Ok) __builtin_trap();
        if (sel.status == shadowkit::Status::Ok && (sel.index < -1 || sel.index >= int(rc))) __builtin_trap();
        if (sel.status != shadowkit::Status::Ok && sel.index != -1) __builtin_trap();
    }
    // fits
    shadowkit::CascadeInput in;
    in.camera_view = (flags & 1) ? r.mat4() : r.look_at_view();
    in.camera_reversed_z = (flags & 8) != 0;
    in.camera_depth = (flags & 16) ? shadowkit::ClipDepth::ZeroToOne : shadowkit::ClipDepth::NegativeOneToOne;
    bool near_bad = false;
    in.camera_proj = camera_projection(r, ((flags >> 1) & 3) % 3, in.camera_depth, in.camera_reversed_z, near_bad);
    in.max_distance = (f2 & 2) ? r.interesting_f32() : r.f32();
    in.light_position = glm::vec4(r.vec3(), (f2 & 4) ? r.f32() : 0.0f);
    in.shadow_map_size = uint32_t(r.u8()) * 32u;
    in.radius_quantum = (flags & 32) ? r.f32() : 1.0f / 16.0f;
    in.has_caster_bounds = (flags & 64) != 0;
    in.caster_min = r.vec3();
    in.caster_max = (f2 & 8) ? in.caster_min + glm::abs(r.vec3()) : r.vec3();
    in.light_depth = (flags & 128) ? shadowkit::ClipDepth::ZeroToOne : shadowkit::ClipDepth::NegativeOneToOne;
    in.light_reversed_z = (f2 & 16) != 0;
    const glm::vec4 L = in.light_position;
    const bool light_bad = !all_finite(L) || L.w != 0.0f || (L.x == 0.0f && L.y == 0.0f && L.z == 0.0f);
    shadowkit::Cascade c[17];
    const uint32_t cc = r.range<uint32_t>(0, 17);
    const size_t cap = (f2 & 32) ? r.size(17) : 16;
    const bool null_out = (f2 & 64) != 0 && cap > 0;
    const shadowkit::CascadeFitResult fit = shadowkit::cascade_fit(in, r.f32(), cc, null_out ? nullptr : c, cap);
    check_detail(fit);
    if (fit.count > cap || fit.count > cc) __builtin_trap();
    if (null_out && fit.status != shadowkit::Status::InvalidArgument) __builtin_trap();
    if (fit.status == shadowkit::Status::Ok) {
        if (light_bad || near_bad) __builtin_trap();
        if (fit.count != cc || fit.needed != cc) __builtin_trap();
        for (uint32_t i = 0; i < cc; ++i) {
            if (c[i].status != shadowkit::Status::Ok) __builtin_trap();
            if (!all_finite(c[i].view_proj) || !all_finite(c[i].sphere)) __builtin_trap();
            if (!std::isfinite(fit.splits[i]) || !(fit.splits[i] < fit.splits[i + 1])) __builtin_trap();
            if (!(c[i].sphere.w > 0.0f) || !(c[i].texel_world_size > 0.0f) || !std::isfinite(c[i].texel_world_size))
                __builtin_trap();
        }
        const shadowkit::CascadeIndex sel = shadowkit::cascade_select_by_sphere(r.vec3(), c, cc);
        check_detail(sel);
        if (sel.status == shadowkit::Status::Ok && (sel.index < -1 || sel.index >= int(cc))) __builtin_trap();
        const shadowkit::CascadeIndex sd = shadowkit::cascade_select_by_depth(r.f32(), fit.splits, cc);
        check_detail(sd);
        if (sd.status == shadowkit::Status::Ok && (sd.index < -1 || sd.index >= int(cc))) __builtin_trap();
    }
    // one slice with raw split depths
    const shadowkit::Cascade one = shadowkit::cascade_fit_slice(in, r.f32(), r.f32());
    check_detail(one);
    if (one.status == shadowkit::Status::Ok) {
        if (light_bad || near_bad) __builtin_trap();
        if (!all_finite(one.view_proj) || !all_finite(one.sphere) || !(one.texel_world_size > 0.0f) ||
            !std::isfinite(one.texel_world_size) || !(one.split_far > one.split_near))
            __builtin_trap();
        // issue #27 item 3: receivers at float positions (the slice's corners and center rounded to
        // float) through the float matrix, in float as a vertex shader, land within 0.01 NDC
        shadowkit::detail::CsRays rays;
        const char* why = nullptr;
        if (shadowkit::detail::cs_camera_rays(in.camera_proj, in.camera_depth, in.camera_reversed_z, rays, why) != shadowkit::Status::Ok)
            __builtin_trap();
        const double d0 = std::fmax(double(one.split_near), rays.near_depth), d1 = std::fmin(double(one.split_far), rays.far_depth);
        const glm::dmat4 iv = glm::inverse(glm::dmat4(in.camera_view));
        glm::dvec3 pts[9];
        pts[8] = glm::dvec3(0.0);
        for (int i = 0; i < 8; ++i) {
            pts[i] = glm::dvec3(iv * glm::dvec4(shadowkit::detail::cs_corner(rays, i & 3, (i & 4) ? d1 : d0), 1.0));
            pts[8] += pts[i] * 0.125;
        }
        const float zlo = in.light_depth == shadowkit::ClipDepth::ZeroToOne ? 0.0f : -1.0f;
        for (const glm::dvec3& p : pts) {
            const glm::vec4 h = one.view_proj * glm::vec4(glm::vec3(p), 1.0f);
            const float x = h.x / h.w, y = h.y / h.w, z = h.z / h.w;
            if (!(std::fabs(x) <= 1.0101f && std::fabs(y) <= 1.0101f && z >= zlo - 0.0101f && z <= 1.0101f)) __builtin_trap();
        }
    }
    // selection by sphere on raw cascades
    {
        shadowkit::Cascade rc[2];
        rc[0].status = rc[1].status = (f2 & 128) ? shadowkit::Status::Ok : shadowkit::Status::NotRun;
        rc[0].sphere = r.vec4();
        rc[1].sphere = r.vec4();
        const shadowkit::CascadeIndex s = shadowkit::cascade_select_by_sphere(r.vec3(), rc, r.range<uint32_t>(0, 2));
        check_detail(s);
        if (s.status == shadowkit::Status::Ok && (s.index < -1 || s.index > 1)) __builtin_trap();
    }
    const float w = shadowkit::cascade_blend_weight(r.f32(), r.f32(), r.f32(), r.f32());
    if (!(w >= 0.0f && w <= 1.0f)) __builtin_trap();
    // issue 25: the world-fixed depth range (decoded last, so earlier inputs keep their meaning). Ok
    // needs scene bounds and a valid light and camera; the anchor is finite and whole for an even size.
    {
        const uint8_t f3 = r.u8();
        in.stable_world_depth = (f3 & 1) != 0;
        in.has_scene_bounds = (f3 & 2) != 0;
        in.scene_min = r.vec3();
        in.scene_max = (f3 & 4) ? in.scene_min + glm::abs(r.vec3()) : r.vec3();
        shadowkit::Cascade wc[4];
        const shadowkit::CascadeFitResult wf = shadowkit::cascade_fit(in, r.f32(), 4, wc, 4);
        check_detail(wf);
        if (wf.status == shadowkit::Status::Ok) {
            if (light_bad || near_bad) __builtin_trap();
            if (in.stable_world_depth && !in.has_scene_bounds) __builtin_trap();
            for (const shadowkit::Cascade& c4 : wc) {
                if (!all_finite(c4.view_proj) || !std::isfinite(c4.texel_anchor.x) || !std::isfinite(c4.texel_anchor.y))
                    __builtin_trap();
                if (in.shadow_map_size % 2 == 0 &&
                    (c4.texel_anchor.x != std::floor(c4.texel_anchor.x) || c4.texel_anchor.y != std::floor(c4.texel_anchor.y)))
                    __builtin_trap();
            }
        }
    }
    // SDSM (decoded last): view range, splits, light view and the fit with raw receiver bounds and a
    // raw previous result. Ok: finite matrices, splits increasing and covering the clamped range,
    // count == cascade_count when visible, and a second call with its own result kept every box.
    {
        const uint8_t f4 = r.u8();
        const shadowkit::CascadeSdsmRange vr = shadowkit::cascade_sdsm_view_range(in.camera_proj, in.camera_depth,
                                                                                 in.camera_reversed_z, r.f32(), r.f32());
        check_detail(vr);
        if (vr.status == shadowkit::Status::Ok && vr.visible &&
            (!std::isfinite(vr.view_min) || !(vr.view_min > 0.0f) || !(vr.view_max >= vr.view_min)))
            __builtin_trap();
        shadowkit::CascadeSdsmInput sd;
        sd.camera = in;
        sd.view_min = (f4 & 1) && vr.visible ? vr.view_min : r.f32();
        sd.view_max = (f4 & 1) && vr.visible ? vr.view_max : r.f32();
        sd.cascade_count = r.range<uint32_t>(0, 17);
        sd.lambda = (f4 & 2) ? r.f32() : 1.0f;
        sd.margin = (f4 & 4) ? r.f32() : 0.125f;
        sd.range_steps_per_octave = (f4 & 8) ? r.f32() : 8.0f;
        glm::vec4 rb[16];
        for (glm::vec4& v : rb) v = r.vec4();
        sd.receiver_bounds = (f4 & 16) ? rb : nullptr;
        sd.world_splits = (f4 & 64) != 0;
        shadowkit::CascadeSdsmResult prev;
        prev.status = (f4 & 32) ? shadowkit::Status::Ok : shadowkit::Status::NotRun;
        prev.visible = true;
        prev.needed = sd.cascade_count;
        prev.light_position = in.light_position;
        prev.shadow_map_size = in.shadow_map_size;
        prev.range_min = r.f32();
        prev.range_max = r.f32();
        for (float& x : prev.splits) x = r.f32();
        for (shadowkit::CascadeSdsmBox& b : prev.boxes) {
            const glm::vec3 lo = r.vec3(), hi = r.vec3();
            b.x0 = lo.x; b.y0 = lo.y; b.near_dist = lo.z;
            b.x1 = hi.x; b.y1 = hi.y; b.far_dist = hi.z;
        }
        const shadowkit::CascadeSdsmResult sp = shadowkit::cascade_sdsm_splits(sd, &prev);
        check_detail(sp);
        shadowkit::Cascade sc[16];
        const shadowkit::CascadeSdsmResult fr = shadowkit::cascade_sdsm_fit(sd, &prev, sc, 16);
        check_detail(fr);
        if (fr.count > 16 || (fr.status == shadowkit::Status::Ok && fr.visible && fr.count != sd.cascade_count)) __builtin_trap();
        if (fr.status == shadowkit::Status::Ok) {
            if (light_bad || near_bad || sp.status != shadowkit::Status::Ok) __builtin_trap();
            for (uint32_t i = 0; i < fr.count; ++i) {
                if (!all_finite(sc[i].view_proj) || !(sc[i].texel_world_size > 0.0f) || !(fr.splits[i] < fr.splits[i + 1]))
                    __builtin_trap();
                if (fr.splits[i] != sp.splits[i]) __builtin_trap();
            }
            if (fr.visible && !(sd.receiver_bounds)) {
                shadowkit::Cascade sc2[16];
                const shadowkit::CascadeSdsmResult again = shadowkit::cascade_sdsm_fit(sd, &fr, sc2, 16);
                check_detail(again);
                if (again.status != shadowkit::Status::Ok || again.rebuilt != 0) __builtin_trap();
            }
        }
        const shadowkit::CascadeSdsmLightView lv = shadowkit::cascade_sdsm_light_view(r.vec4());
        check_detail(lv);
        if (lv.status == shadowkit::Status::Ok && !all_finite(lv.view)) __builtin_trap();
    }
    return 0;
}
