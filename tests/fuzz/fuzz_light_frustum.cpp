// libFuzzer target for shadowkit/light_frustum.hpp: light_frustum_fit, light_frustum_fit_casters and light_frustum_slice_corners
// on matrices, light, bounds, casters from raw bytes (NaN/Inf, huge counts clamped by the data size,
// null pointers with counts, cameras with a near plane at or behind the eye, epsilon-tweaked infinite
// projections); traps on Ok with a non-finite output, count > capacity, a write past capacity, Ok for a
// null pointer with a count or a near plane <= 0. Also light_frustum_extruded_planes (hull contains the
// receiver vertices and the light, finite planes for finite input) and the box/sphere predicates
// (receivers never culled, NaN never culls, monotone in size/tol).
#include <shadowkit/light_frustum.hpp>

#include "fuzz_input.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

using shadowkit_fuzz::all_finite;

namespace {

bool finite4(const glm::dvec4& p) {
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) && std::isfinite(p.w);
}
double eval(const glm::dvec4& p, const glm::dvec3& x) { return p.x * x.x + p.y * x.y + p.z * x.z + p.w; }

// Conservative caster tests on a plane set: NaN never culls, a point box equals a zero sphere,
// growing the box / radius / tolerance never turns "may intersect" into "culled", no planes culls nothing.
void check_culling(const shadowkit::LightFrustumPlanes& P, shadowkit_fuzz::FuzzInput& r, bool raw) {
    for (int it = 0; it < 3; ++it) {
        const glm::vec3 mn = r.vec3(raw, 0.25f);
        const glm::vec3 mx = mn + glm::abs(r.vec3(raw, 0.125f));
        const glm::vec3 grow = glm::abs(r.vec3(raw, 0.125f));
        const float rad = r.value(raw, 0.125f);
        const double tol = (r.u8() & 1) ? double(r.interesting_f32()) : double(std::fabs(r.quantized(0.01f)));
        const bool b = shadowkit::light_frustum_box_may_intersect(P, mn, mx, tol);
        const bool s = shadowkit::light_frustum_sphere_may_intersect(P, mn, rad, tol);
        (void)shadowkit::light_frustum_box_may_intersect(P, mn, mx);  // default tolerance
        (void)shadowkit::light_frustum_sphere_may_intersect(P, mn, rad);
        if ((P.count == 0 || P.status != shadowkit::Status::Ok) && (!b || !s)) __builtin_trap();
        // an axis whose extent is undefined (NaN min and max) makes every plane test NaN: never culled
        const bool nan_box = (std::isnan(mn.x) && std::isnan(mx.x)) || (std::isnan(mn.y) && std::isnan(mx.y)) ||
                             (std::isnan(mn.z) && std::isnan(mx.z));
        if (nan_box && !b) __builtin_trap();
        if ((std::isnan(mn.x) || std::isnan(mn.y) || std::isnan(mn.z) || std::isnan(rad)) && !s) __builtin_trap();
        if (!(tol >= 0.0) || !std::isfinite(tol)) continue;
        // a degenerate box and a zero-radius sphere are the same point test
        if (shadowkit::light_frustum_box_may_intersect(P, mn, mn, tol) != shadowkit::light_frustum_sphere_may_intersect(P, mn, 0.0f, tol)) __builtin_trap();
        // monotone: larger tolerance / box / radius keeps a "may intersect"
        if (b && !shadowkit::light_frustum_box_may_intersect(P, mn, mx, 2.0 * tol + 1.0)) __builtin_trap();
        if (s && !shadowkit::light_frustum_sphere_may_intersect(P, mn, rad, 2.0 * tol + 1.0)) __builtin_trap();
        if (b && all_finite(grow) && !shadowkit::light_frustum_box_may_intersect(P, mn - grow, mx + grow, tol)) __builtin_trap();
        if (s && std::isfinite(grow.x) && !shadowkit::light_frustum_sphere_may_intersect(P, mn, rad + grow.x, tol)) __builtin_trap();
        // a box containing the point is kept whenever the point is
        if (shadowkit::light_frustum_box_may_intersect(P, mn, mn, tol) && !shadowkit::light_frustum_box_may_intersect(P, mn, mx, tol)) __builtin_trap();
    }
}

// extruded_volume_planes on (0) a box receiver with its 6 inward planes, (1) a point cloud with no
// planes, (2) raw vertices and raw planes (NaN/Inf, counts <= 0, null with zero counts).
void extruded_volume_and_culling(shadowkit_fuzz::FuzzInput& r) {
    const uint8_t m = r.u8();
    const int kind = (m & 3) % 3;
    const bool raw = (m & 4) != 0;
    glm::dvec3 verts[12];
    glm::dvec4 planes[8];
    int nv = 0, np = 0;
    glm::vec3 bmin(0.0f), bmax(0.0f);
    if (kind == 0) {
        bmin = r.vec3(raw, 0.25f);
        bmax = bmin + glm::abs(r.vec3(raw, 0.125f));
        for (int i = 0; i < 8; ++i)
            verts[i] = glm::dvec3((i & 1) ? bmax.x : bmin.x, (i & 2) ? bmax.y : bmin.y, (i & 4) ? bmax.z : bmin.z);
        nv = 8;
        const glm::dvec3 lo(bmin), hi(bmax);
        planes[0] = glm::dvec4(1, 0, 0, -lo.x);
        planes[1] = glm::dvec4(-1, 0, 0, hi.x);
        planes[2] = glm::dvec4(0, 1, 0, -lo.y);
        planes[3] = glm::dvec4(0, -1, 0, hi.y);
        planes[4] = glm::dvec4(0, 0, 1, -lo.z);
        planes[5] = glm::dvec4(0, 0, -1, hi.z);
        np = 6;
    } else if (kind == 1) {
        nv = r.range(1, 12);
        for (int i = 0; i < nv; ++i) verts[i] = glm::dvec3(r.vec3(raw, 0.25f));
    } else {
        nv = r.range(-3, 12);
        np = r.range(-3, 8);
        for (int i = 0; i < nv; ++i) verts[i] = glm::dvec3(r.vec3(raw, 0.25f));
        for (int i = 0; i < np; ++i) planes[i] = glm::dvec4(glm::dvec3(r.vec3(raw, 0.25f)), double(r.value(raw, 0.25f)));
    }
    const glm::vec4 lf(r.vec3(raw, 0.25f), (m & 8) ? 0.0f : ((m & 16) ? r.value(raw, 0.25f) : 1.0f));
    const glm::dvec4 light(lf);
    // negative counts: a null pointer with a count (must be InvalidArgument)
    const bool null_verts = nv < 0, null_planes = np < 0;
    const std::size_t vcount = null_verts ? std::size_t(-nv) : std::size_t(nv), pcount = null_planes ? std::size_t(-np) : std::size_t(np);
    const shadowkit::LightFrustumPlanes H = shadowkit::light_frustum_extruded_planes(
        (nv > 0 && !null_verts) ? verts : nullptr, vcount, (np > 0 && !null_planes) ? planes : nullptr, pcount, lf);
    if (H.count < 0 || H.count > 64) __builtin_trap();
    shadowkit_fuzz::check_detail(H);
    if ((null_verts || null_planes) && H.status == shadowkit::Status::Ok) __builtin_trap();
    if (H.status != shadowkit::Status::Ok && H.count != 0) __builtin_trap();
    if (nv <= 0 && H.count != 0) __builtin_trap();
    const bool light_ok = std::isfinite(lf.x) && std::isfinite(lf.y) && std::isfinite(lf.z) && std::isfinite(lf.w) &&
                          lf.w >= 0.0f && !(lf.w == 0.0f && lf.x == 0.0f && lf.y == 0.0f && lf.z == 0.0f);
    if (!light_ok && H.status == shadowkit::Status::Ok) __builtin_trap();  // InvalidLight
    if (H.status == shadowkit::Status::Ok)
        for (int k = 0; k < H.count; ++k)
            if (!finite4(H.planes[k])) __builtin_trap();

    bool finite_in = light_ok && H.status == shadowkit::Status::Ok;
    for (int i = 0; i < nv; ++i) finite_in = finite_in && finite4(glm::dvec4(verts[i], 1.0));
    for (int i = 0; i < np; ++i) finite_in = finite_in && finite4(planes[i]);
    if (finite_in && nv > 0) {
        for (int k = 0; k < H.count; ++k)
            if (!finite4(H.planes[k])) __builtin_trap();
        if (kind != 2) {  // the input planes (if any) bound the vertices: the extruded hull contains them
            const bool directional = light.w == 0.0;
            const glm::dvec3 L = directional ? glm::dvec3(0.0) : glm::dvec3(light) / light.w;
            double scale = 1.0;
            for (int i = 0; i < nv; ++i) scale = std::fmax(scale, glm::length(verts[i]));
            if (!directional) scale = std::fmax(scale, glm::length(L));
            const glm::dvec3 toward = directional ? glm::normalize(glm::dvec3(light)) : glm::dvec3(0.0);
            for (int k = 0; k < H.count; ++k) {
                const glm::dvec4& P = H.planes[k];
                for (int i = 0; i < nv; ++i) {
                    if (eval(P, verts[i]) < -1e-6 * scale) __builtin_trap();
                    // swept toward the light (directional) by `scale`
                    if (directional && eval(P, verts[i] + scale * toward) < -(1e-3 * scale + 2e-9 * scale * scale))
                        __builtin_trap();
                }
                if (!directional && eval(P, L) < -1e-3 * scale) __builtin_trap();  // the hull includes the light
            }
            // receivers themselves are never culled
            const double ctol = 1e-6 * scale;
            for (int i = 0; i < nv; ++i) {
                const glm::vec3 v(verts[i]);
                if (!shadowkit::light_frustum_box_may_intersect(H, v, v, ctol)) __builtin_trap();
                if (!shadowkit::light_frustum_sphere_may_intersect(H, v, 0.0f, ctol)) __builtin_trap();
            }
            if (kind == 0 && !shadowkit::light_frustum_box_may_intersect(H, bmin, bmax, ctol)) __builtin_trap();
        }
    }
    check_culling(H, r, raw);
    // an arbitrary plane set (NaN/Inf planes, any count 0..64)
    shadowkit::LightFrustumPlanes A;
    A.status = shadowkit::Status::Ok;
    A.count = r.range(0, 64);
    for (int k = 0; k < A.count; ++k) A.planes[k] = glm::dvec4(glm::dvec3(r.vec3(raw, 0.25f)), double(r.value(raw, 0.25f)));
    check_culling(A, r, raw);
}

// A camera projection: raw 16 floats; glm's perspective (near may be <= 0); or an epsilon-tweaked
// infinite projection (Everitt-Kilgard P_inf, GL or zero-to-one, optionally reversed) from raw values.
glm::mat4 camera_projection(shadowkit_fuzz::FuzzInput& r, uint8_t mode, shadowkit::ClipDepth& cd, bool& rev,
                            bool& near_bad) {
    near_bad = false;
    if (mode == 0) return r.mat4();
    const float fovy = r.f32(), aspect = r.f32(), n = r.f32(), f = r.f32();
    if (mode == 1) {
        near_bad = std::isfinite(n) && n <= 0.0f;
        cd = shadowkit::ClipDepth::NegativeOneToOne;
        rev = false;
        return glm::perspective(fovy, 1.3f, n, f);  // a fixed aspect: glm asserts on aspect == epsilon
    }
    const float eps = std::fabs(std::fmod(f, 0.5f));  // NaN stays NaN
    const double t = 1.0 / std::tan(0.5 * double(fovy));
    glm::mat4 m(0.0f);
    m[0][0] = float(t / double(aspect));
    m[1][1] = float(t);
    m[2][3] = -1.0f;
    const bool zo = cd == shadowkit::ClipDepth::ZeroToOne;
    double A = 1.0 - double(eps), B = zo ? -(1.0 - double(eps)) * double(n) : -(2.0 - double(eps)) * double(n);
    if (rev) {
        if (zo) { A = double(eps); B = (1.0 - double(eps)) * double(n); }
        else { A = -A; B = -B; }
    }
    m[2][2] = float(-A);
    m[3][2] = float(B);
    near_bad = std::isfinite(n) && n <= 0.0f;
    return m;
}

}  // namespace

// light_frustum_fit_casters: raw or well-formed boxes, lights and limits; Ok means finite matrices,
// 0 < near < far, and every caster box corner inside the clip volume through the float view_proj
// (for boxes the fuzzer keeps within 1e4 of the origin; the float rounding is the fit's own margin).
void caster_fit(shadowkit_fuzz::FuzzInput& r) {
    const uint8_t f = r.u8();
    const bool raw = (f & 1) != 0;
    shadowkit::LightCasterFitInput in;
    in.caster_min = r.vec3(raw, 8.0f);
    in.caster_max = in.caster_min + ((f & 2) ? r.vec3(raw, 4.0f) : glm::abs(r.vec3(raw, 4.0f)));
    in.receiver_min = glm::min(in.caster_min, r.vec3(raw, 16.0f));
    in.receiver_max = glm::max(in.caster_max, r.vec3(raw, 16.0f));
    in.light_position = (f & 4) ? glm::vec4(r.vec3(raw, 32.0f), 1.0f) : glm::vec4(r.vec3(raw, 1.0f), (f & 8) ? r.f32() : 0.0f);
    in.emitter_radius_world = (f & 16) ? r.f32() : std::fabs(r.value(false, 1.0f));
    if (f & 32) in.max_half_angle_radians = r.f32();
    if (f & 64) in.min_near_ratio = r.f32();
    in.light_depth = (f & 128) ? shadowkit::ClipDepth::ZeroToOne : shadowkit::ClipDepth::NegativeOneToOne;
    in.light_reversed_z = r.boolean();
    const shadowkit::LightFrustumResult res = shadowkit::light_frustum_fit_casters(in);
    shadowkit_fuzz::check_detail(res);
    const glm::vec4 L = in.light_position;
    const bool light_bad = !all_finite(L) || L.w < 0.0f || (L.w == 0.0f && L.x == 0.0f && L.y == 0.0f && L.z == 0.0f);
    if (res.status != shadowkit::Status::Ok) return;
    if (light_bad) __builtin_trap();
    if (!all_finite(res.view_proj) || !all_finite(res.view) || !all_finite(res.proj)) __builtin_trap();
    if (!(res.near_z > 0.0f && res.near_z < res.far_z) || !res.visible) __builtin_trap();
    if (!(in.caster_min.x <= in.caster_max.x && in.caster_min.y <= in.caster_max.y && in.caster_min.z <= in.caster_max.z))
        __builtin_trap();
    float big = 0.0f;
    for (int k = 0; k < 3; ++k) big = std::fmax(big, std::fmax(std::fabs(in.caster_min[k]), std::fabs(in.caster_max[k])));
    if (!(big < 1e4f)) return;
    for (int c = 0; c < 8; ++c) {
        const glm::vec4 p((c & 1) ? in.caster_max.x : in.caster_min.x, (c & 2) ? in.caster_max.y : in.caster_min.y,
                          (c & 4) ? in.caster_max.z : in.caster_min.z, 1.0f);
        const glm::vec4 q = res.view_proj * p;
        if (!(q.w > 0.0f)) __builtin_trap();
        if (!(std::fabs(q.x) <= q.w * 1.0001f && std::fabs(q.y) <= q.w * 1.0001f)) __builtin_trap();
    }
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    shadowkit_fuzz::FuzzInput r(data, size);
    const uint8_t flags = r.u8();
    const uint8_t f2 = r.u8();
    shadowkit::LightFrustumInput in;
    // raw 16 floats, or a well-formed camera from 6 floats (keeps coverage deep)
    in.camera_view = (flags & 1) ? r.look_at_view() : r.mat4();
    in.camera_depth = (flags & 4) ? shadowkit::ClipDepth::ZeroToOne : shadowkit::ClipDepth::NegativeOneToOne;
    in.camera_reversed_z = (flags & 8) != 0;
    bool near_bad = false;
    in.camera_proj = camera_projection(r, uint8_t(((flags >> 1) & 1) | ((f2 >> 5) & 2)) % 3, in.camera_depth,
                                       in.camera_reversed_z, near_bad);
    in.max_distance = (f2 & 16) ? r.interesting_f32() : r.f32();
    in.receiver_min_depth = r.f32();
    in.receiver_max_depth = r.f32();
    if (flags & 64) in.receiver_min_depth = in.receiver_max_depth = 0.0f;
    in.light_position = glm::vec4(r.vec3(), (flags & 16) ? r.f32() : 0.0f);
    in.has_scene_bounds = (flags & 32) != 0;
    in.scene_min = r.vec3();
    in.scene_max = in.scene_min + glm::abs(r.vec3());
    in.stable = (f2 & 1) != 0;
    in.shadow_map_size = static_cast<uint32_t>(r.u8()) * 16u;
    in.radius_quantum = (f2 & 128) ? 1.0f / 16.0f : r.f32();
    in.light_depth = (f2 & 2) ? shadowkit::ClipDepth::ZeroToOne : shadowkit::ClipDepth::NegativeOneToOne;
    in.light_reversed_z = (f2 & 4) != 0;
    in.point_min_near_ratio = (f2 & 8) ? r.f32() : 1e-4f;
    const size_t nb = r.size(31), ns = r.size(7);
    std::vector<float> boxes(nb * 6), spheres(ns * 4);
    for (float& v : boxes) v = r.f32();
    for (float& v : spheres) v = r.f32();
    const uint8_t f3 = r.u8();
    if (f3 & 8) in.light_position = glm::vec4(r.vec3(false, 4.0f), 1.0f);  // a well-formed point light
    const bool null_casters = (f3 & 1) && nb > 0, null_spheres = (f3 & 2) && ns > 0;
    in.casters = (nb && !null_casters) ? boxes.data() : nullptr;
    in.caster_count = nb;
    in.caster_spheres = (ns && !null_spheres) ? spheres.data() : nullptr;
    in.caster_sphere_count = ns;
    in.stable_world_depth = (f3 & 16) != 0;  // issue 18: the depth range fixed in the world (needs scene bounds)
    const size_t cap = r.size(47);
    const bool null_keep = (f3 & 4) && cap > 0;
    std::vector<uint32_t> keep(cap + 1, 0xFFFFFFFFu);
    const shadowkit::LightFrustumResult res = shadowkit::light_frustum_fit(in, null_keep ? nullptr : keep.data(), cap);
    const shadowkit::Status st = res.status;
    shadowkit_fuzz::check_detail(res);
    if (keep[cap] != 0xFFFFFFFFu) __builtin_trap();  // wrote past capacity
    if (res.count > cap) __builtin_trap();
    if ((null_casters || null_spheres || null_keep) && st != shadowkit::Status::InvalidArgument) __builtin_trap();
    if (near_bad && (st == shadowkit::Status::Ok || st == shadowkit::Status::BufferTooSmall)) __builtin_trap();
    const glm::vec4 L = in.light_position;
    const bool light_bad = !all_finite(L) || L.w < 0.0f || (L.w == 0.0f && L.x == 0.0f && L.y == 0.0f && L.z == 0.0f);
    if (light_bad && (st == shadowkit::Status::Ok || st == shadowkit::Status::BufferTooSmall)) __builtin_trap();
    if (st == shadowkit::Status::Ok || st == shadowkit::Status::BufferTooSmall) {
        if (!all_finite(res.view_proj) || !all_finite(res.view) || !all_finite(res.proj)) __builtin_trap();
        if (!std::isfinite(res.near_z) || !std::isfinite(res.far_z) || !std::isfinite(res.texel_world_size) ||
            !all_finite(res.bounding_sphere))
            __builtin_trap();
        if (res.needed + res.culled_count != nb + ns) __builtin_trap();
        if (res.invalid_count > res.culled_count) __builtin_trap();
        if ((st == shadowkit::Status::Ok) != (res.needed <= cap)) __builtin_trap();
        if (res.count != (res.needed < cap ? res.needed : cap)) __builtin_trap();
        if (!res.visible && (res.needed != 0 || st != shadowkit::Status::Ok)) __builtin_trap();
        if (res.visible && in.stable && !(res.texel_world_size > 0.0f)) __builtin_trap();
        if (in.stable && in.stable_world_depth && !in.has_scene_bounds) __builtin_trap();  // must be InvalidArgument
        // the stable fit's anchor: finite and whole (shadow_map_size is a multiple of 16 here)
        if (!std::isfinite(res.texel_anchor.x) || !std::isfinite(res.texel_anchor.y) ||
            res.texel_anchor.x != std::floor(res.texel_anchor.x) || res.texel_anchor.y != std::floor(res.texel_anchor.y))
            __builtin_trap();
        // the light's eye in front of everything (issue 13: linear light depths must be positive)
        if (res.visible && !(res.near_z > 0.0f && res.far_z > res.near_z)) __builtin_trap();
        for (size_t i = 0; i < res.count; ++i)
            if (keep[i] >= nb + ns) __builtin_trap();
    } else if (res.count != 0) {
        __builtin_trap();
    }
    const shadowkit::LightFrustumCorners corners = shadowkit::light_frustum_slice_corners(in);
    shadowkit_fuzz::check_detail(corners);
    if (near_bad && corners.status == shadowkit::Status::Ok) __builtin_trap();
    if (corners.status == shadowkit::Status::Ok && corners.visible) {
        for (const glm::vec3& c : corners.corners)
            if (!all_finite(c)) __builtin_trap();
        if (!std::isfinite(corners.near_depth) || !std::isfinite(corners.far_depth) ||
            !(corners.far_depth >= corners.near_depth))
            __builtin_trap();
    }
    // the fit and the corners agree on visibility for the camera-only part
    if (st == shadowkit::Status::Ok && res.visible && !in.has_scene_bounds && corners.status == shadowkit::Status::Ok &&
        !corners.visible)
        __builtin_trap();
    extruded_volume_and_culling(r);
    caster_fit(r);
    return 0;
}
