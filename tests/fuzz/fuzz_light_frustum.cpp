// libFuzzer target for shadowkit/light_frustum.hpp: matrices, light, bounds, casters from raw bytes
// (NaN/Inf, huge counts clamped by the data size); checks counts and finite output when Ok.
#include <shadowkit/light_frustum.hpp>

#include "fuzz_input.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

using shadowkit_fuzz::all_finite;

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
    return 0;
}
