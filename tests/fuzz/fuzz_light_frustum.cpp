// libFuzzer target for shadowkit/light_frustum.hpp: matrices, light, bounds, casters from raw bytes
// (NaN/Inf, huge counts clamped by the data size); checks counts and finite output when Ok. Also
// extruded_volume_planes (hull contains the receiver vertices and the light, finite planes for finite
// input) and box/sphere_may_intersect (receivers never culled, NaN never culls, monotone in size/tol).
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
        const bool b = shadowkit::box_may_intersect(P, mn, mx, tol);
        const bool s = shadowkit::sphere_may_intersect(P, mn, rad, tol);
        (void)shadowkit::box_may_intersect(P, mn, mx);  // default tolerance
        (void)shadowkit::sphere_may_intersect(P, mn, rad);
        if (P.count == 0 && (!b || !s)) __builtin_trap();
        // an axis whose extent is undefined (NaN min and max) makes every plane test NaN: never culled
        const bool nan_box = (std::isnan(mn.x) && std::isnan(mx.x)) || (std::isnan(mn.y) && std::isnan(mx.y)) ||
                             (std::isnan(mn.z) && std::isnan(mx.z));
        if (nan_box && !b) __builtin_trap();
        if ((std::isnan(mn.x) || std::isnan(mn.y) || std::isnan(mn.z) || std::isnan(rad)) && !s) __builtin_trap();
        if (!(tol >= 0.0) || !std::isfinite(tol)) continue;
        // a degenerate box and a zero-radius sphere are the same point test
        if (shadowkit::box_may_intersect(P, mn, mn, tol) != shadowkit::sphere_may_intersect(P, mn, 0.0f, tol)) __builtin_trap();
        // monotone: larger tolerance / box / radius keeps a "may intersect"
        if (b && !shadowkit::box_may_intersect(P, mn, mx, 2.0 * tol + 1.0)) __builtin_trap();
        if (s && !shadowkit::sphere_may_intersect(P, mn, rad, 2.0 * tol + 1.0)) __builtin_trap();
        if (b && all_finite(grow) && !shadowkit::box_may_intersect(P, mn - grow, mx + grow, tol)) __builtin_trap();
        if (s && std::isfinite(grow.x) && !shadowkit::sphere_may_intersect(P, mn, rad + grow.x, tol)) __builtin_trap();
        // a box containing the point is kept whenever the point is
        if (shadowkit::box_may_intersect(P, mn, mn, tol) && !shadowkit::box_may_intersect(P, mn, mx, tol)) __builtin_trap();
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
    const shadowkit::LightFrustumPlanes H =
        shadowkit::extruded_volume_planes(nv > 0 ? verts : nullptr, nv, np > 0 ? planes : nullptr, np, light);
    if (H.count < 0 || H.count > 64) __builtin_trap();
    if (nv <= 0 && H.count != 0) __builtin_trap();

    bool finite_in = finite4(light) && !(light.w == 0.0 && light.x == 0.0 && light.y == 0.0 && light.z == 0.0);
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
            const glm::dvec3 toward = directional ? -glm::normalize(glm::dvec3(light)) : glm::dvec3(0.0);
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
                if (!shadowkit::box_may_intersect(H, v, v, ctol)) __builtin_trap();
                if (!shadowkit::sphere_may_intersect(H, v, 0.0f, ctol)) __builtin_trap();
            }
            if (kind == 0 && !shadowkit::box_may_intersect(H, bmin, bmax, ctol)) __builtin_trap();
        }
    }
    check_culling(H, r, raw);
    // an arbitrary plane set (NaN/Inf planes, any count 0..64)
    shadowkit::LightFrustumPlanes A;
    A.count = r.range(0, 64);
    for (int k = 0; k < A.count; ++k) A.planes[k] = glm::dvec4(glm::dvec3(r.vec3(raw, 0.25f)), double(r.value(raw, 0.25f)));
    check_culling(A, r, raw);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    shadowkit_fuzz::FuzzInput r(data, size);
    const uint8_t flags = r.u8();
    shadowkit::LightFrustumInput in;
    // raw 16 floats, or a well-formed camera from 6 floats (keeps coverage deep)
    in.camera_view = (flags & 1) ? r.look_at_view() : r.mat4();
    in.camera_proj = (flags & 2) ? r.mat4() : r.perspective(1.3f, (flags & 64) != 0);
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
    in.stable = (f2 & 1) != 0;
    in.shadow_map_size = static_cast<uint32_t>(r.u8()) * 16u;
    in.radius_quantum = r.f32();
    in.light_depth = (f2 & 2) ? shadowkit::ClipDepth::ZeroToOne : shadowkit::ClipDepth::NegativeOneToOne;
    in.light_reversed_z = (f2 & 4) != 0;
    in.point_min_near_ratio = (f2 & 8) ? r.f32() : 1e-4f;
    const size_t nb = r.size(31), ns = r.size(7);
    std::vector<float> boxes(nb * 6), spheres(ns * 4);
    for (float& v : boxes) v = r.f32();
    for (float& v : spheres) v = r.f32();
    in.casters = nb ? boxes.data() : nullptr;
    in.caster_count = nb;
    in.caster_spheres = ns ? spheres.data() : nullptr;
    in.caster_sphere_count = ns;
    const size_t cap = r.size(47);
    std::vector<uint32_t> keep(cap + 1, 0xFFFFFFFFu);
    const shadowkit::LightFrustumResult res = shadowkit::fit_light_frustum(in, keep.data(), cap);
    if (keep[cap] != 0xFFFFFFFFu) __builtin_trap();  // wrote past capacity
    if (res.status == shadowkit::LightFrustumStatus::Ok || res.status == shadowkit::LightFrustumStatus::BufferTooSmall) {
        if (!all_finite(res.view_proj) || !all_finite(res.view) || !all_finite(res.proj)) __builtin_trap();
        if (res.kept_count + res.culled_count != nb + ns) __builtin_trap();
        if ((res.status == shadowkit::LightFrustumStatus::Ok) != (res.kept_count <= cap)) __builtin_trap();
        for (size_t i = 0; i < res.kept_count && i < cap; ++i)
            if (keep[i] >= nb + ns) __builtin_trap();
    }
    glm::vec3 corners[8];
    if (shadowkit::camera_slice_corners(in.camera_view, in.camera_proj, in.camera_depth, in.camera_reversed_z,
                                        in.max_distance, in.receiver_min_depth, in.receiver_max_depth, corners) ==
        shadowkit::LightFrustumStatus::Ok) {
        for (const glm::vec3& c : corners)
            if (!all_finite(c)) {
                // float overflow of a finite double corner is the only way here: allowed only for huge input
                if (std::fabs(in.max_distance) < 1e30f) __builtin_trap();
            }
    }
    extruded_volume_and_culling(r);
    return 0;
}
