// libFuzzer target for shadowkit/cascades.hpp: split distances, fits, selection and blend weights on
// inputs decoded from raw bytes; checks monotonic splits, exact ends and finite matrices when Ok.
#include <shadowkit/cascades.hpp>

#include "fuzz_input.hpp"

#include <cstddef>
#include <cstdint>

using shadowkit_fuzz::FuzzInput;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    FuzzInput r(data, size);
    const uint8_t flags = r.u8();
    // split distances
    const float n = r.f32(), f = r.f32(), lambda = r.f32();
    const uint32_t count = r.range<uint32_t>(0, 19);
    float s[21];
    if (shadowkit::cascade_split_distances(n, f, lambda, count, s) == shadowkit::CascadeStatus::Ok) {
        if (count == 0 || count > 16) __builtin_trap();
        if (s[0] != n || s[count] != f) __builtin_trap();
        for (uint32_t i = 0; i < count; ++i)
            if (!(s[i] < s[i + 1])) __builtin_trap();
        const int sel = shadowkit::select_cascade_by_depth(r.f32(), s, count);
        if (sel < -1 || sel >= int(count)) __builtin_trap();
    }
    // fits
    shadowkit::CascadeInput in;
    in.camera_view = (flags & 1) ? r.mat4() : r.look_at_view();
    in.camera_proj = (flags & 2) ? r.mat4() : r.perspective(1.5f, (flags & 4) != 0);
    in.camera_reversed_z = (flags & 8) != 0;
    in.camera_depth = (flags & 16) ? shadowkit::ClipDepth::ZeroToOne : shadowkit::ClipDepth::NegativeOneToOne;
    in.max_distance = r.f32();
    in.light_dir = r.vec3();
    in.shadow_map_size = uint32_t(r.u8()) * 32u;
    in.radius_quantum = (flags & 32) ? r.f32() : 1.0f / 16.0f;
    in.has_caster_bounds = (flags & 64) != 0;
    in.caster_min = r.vec3();
    in.caster_max = r.vec3();
    in.light_depth = (flags & 128) ? shadowkit::ClipDepth::ZeroToOne : shadowkit::ClipDepth::NegativeOneToOne;
    shadowkit::Cascade c[16];
    float splits[17];
    const uint32_t cc = r.range<uint32_t>(1, 16);
    if (shadowkit::fit_cascades(in, r.f32(), cc, c, splits) == shadowkit::CascadeStatus::Ok) {
        for (uint32_t i = 0; i < cc; ++i) {
            if (!shadowkit_fuzz::all_finite(c[i].view_proj)) __builtin_trap();
            if (!(splits[i] < splits[i + 1])) __builtin_trap();
            if (!(c[i].sphere.w > 0.0f) || !(c[i].texel_world_size > 0.0f)) __builtin_trap();
        }
        const int sel = shadowkit::select_cascade_by_sphere(r.vec3(), c, cc);
        if (sel < -1 || sel >= int(cc)) __builtin_trap();
    }
    const float w = shadowkit::cascade_blend_weight(r.f32(), r.f32(), r.f32(), r.f32());
    if (!(w >= 0.0f && w <= 1.0f)) __builtin_trap();
    return 0;
}
