// libFuzzer target for shadowkit/omni_shadow.hpp: every public function with inputs decoded from
// raw bytes (floats may be NaN/Inf/denormal, enum values out of range, caster counts up to what
// the data holds, capacities smaller than needed, null buffers with capacities). Invariants checked
// with __builtin_trap(): Status::Ok only with finite outputs in their documented ranges (issue 19),
// count <= capacity, nothing written past a capacity.
#include <shadowkit/omni_shadow.hpp>

#include "fuzz_input.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

using shadowkit_fuzz::all_finite;
using shadowkit_fuzz::check;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    shadowkit_fuzz::FuzzInput r(data, size);
    const uint8_t flags = r.u8();
    // ---- cube matrices
    shadowkit::OmniCubeInput ci;
    ci.light_position = glm::vec4(r.vec3(), (flags & 64) ? r.f32() : 1.0f);
    ci.near_z = r.f32();
    ci.far_z = (flags & 1) ? INFINITY : r.f32();
    ci.clip_depth = (flags & 2) ? shadowkit::ClipDepth::ZeroToOne : shadowkit::ClipDepth::NegativeOneToOne;
    ci.reversed_z = (flags & 4) != 0;
    const shadowkit::OmniCubeMatrices cm = shadowkit::omni_cube_matrices(ci);
    shadowkit_fuzz::check_detail(cm);
    if (cm.status == shadowkit::Status::Ok) {
        check(all_finite(cm.proj));
        for (int f = 0; f < 6; ++f) check(all_finite(cm.view_proj[f]) && all_finite(cm.view[f]));
        check(ci.light_position.w > 0.f);  // point lights only
        // the float matrix maps near and far to their NDC depths (issue 19: near 1, far 1 + ulp -> -2)
        const bool zo = ci.clip_depth == shadowkit::ClipDepth::ZeroToOne;
        const double zn = zo ? (ci.reversed_z ? 1 : 0) : (ci.reversed_z ? 1 : -1);
        const double zf = zo ? (ci.reversed_z ? 0 : 1) : (ci.reversed_z ? -1 : 1);
        const double a = cm.proj[2][2], b = cm.proj[3][2];
        check(std::fabs(-a + b / double(ci.near_z) - zn) <= 1e-4);
        check(std::fabs((std::isinf(ci.far_z) ? -a : -a + b / double(ci.far_z)) - zf) <= 1e-4);
    }
    // ---- face selection and its inverse
    const glm::vec3 d = r.vec3();
    const shadowkit::OmniFaceHit h = shadowkit::omni_cube_face(d);
    shadowkit_fuzz::check_detail(h);
    if (h.status == shadowkit::Status::Ok) {
        check(static_cast<int>(h.face) <= 5);
        check(h.st.x >= 0.f && h.st.x <= 1.f && h.st.y >= 0.f && h.st.y <= 1.f);
        // exactly one owner under the documented tie rule
        const float ax = std::fabs(d.x), ay = std::fabs(d.y), az = std::fabs(d.z);
        const int axis = (ax >= ay && ax >= az) ? 0 : (ay >= az ? 1 : 2);
        check(static_cast<int>(h.face) / 2 == axis);
        const shadowkit::OmniDirection back = shadowkit::omni_cube_direction(h.face, h.st);
        shadowkit_fuzz::check_detail(back);
        check(back.status == shadowkit::Status::Ok && all_finite(back.direction));
    } else {
        check(!all_finite(d) || (d.x == 0.f && d.y == 0.f && d.z == 0.f));
    }
    const shadowkit::OmniDirection cd = shadowkit::omni_cube_direction(static_cast<shadowkit::OmniCubeFace>(r.u8()), r.vec2());
    shadowkit_fuzz::check_detail(cd);
    if (cd.status == shadowkit::Status::Ok) check(all_finite(cd.direction));
    (void)shadowkit::omni_cube_face_basis(static_cast<shadowkit::OmniCubeFace>(r.u8()));
    const uint32_t map_size = r.range<uint32_t>(0, 69999);
    const shadowkit::OmniValue ta = shadowkit::omni_cube_texel_angle(map_size);
    shadowkit_fuzz::check_detail(ta);
    check((ta.status == shadowkit::Status::Ok) == (map_size != 0));
    if (ta.status == shadowkit::Status::Ok) check(all_finite(ta.value) && ta.value > 0.f);
    // ---- linear depth and bias
    const float dist = r.f32(), range = r.f32();
    const auto fmt = static_cast<shadowkit::DepthFormat>(r.range(0, 2));
    const shadowkit::OmniDepthResult ld = shadowkit::omni_linear_depth(dist, range, fmt);
    shadowkit_fuzz::check_detail(ld);
    if (ld.status == shadowkit::Status::Ok) check(ld.value >= 0.f && ld.value <= 1.f);
    shadowkit::OmniBiasInput bi;
    bi.distance = dist;
    bi.cos_theta = r.f32();
    bi.texel_angle = r.f32();
    bi.filter_radius = r.f32();
    bi.range = range;
    bi.format = fmt;
    if (flags & 8) bi.max_angle = r.f32();
    if (flags & 16) bi.constant = r.f32();
    const shadowkit::OmniBiasResult br = shadowkit::omni_distance_bias(bi);
    shadowkit_fuzz::check_detail(br);
    if (br.status == shadowkit::Status::Ok) check(all_finite(br.bias_world) && br.bias_world >= 0.f && all_finite(br.bias_stored));
    if (ld.status == shadowkit::Status::Ok) check(all_finite(ld.value));
    // ---- culling: casters from the rest of the data (counts bounded by what the data holds)
    shadowkit::OmniCullInput cu;
    cu.light_position = ci.light_position;
    cu.near_z = ci.near_z;
    cu.far_z = ci.far_z;
    const size_t nb = r.size(8), ns = r.size(8);
    std::vector<float> boxes(6 * nb), spheres(4 * ns);
    for (auto& v : boxes) v = r.f32();
    for (auto& v : spheres) v = r.f32();
    cu.boxes = nb ? boxes.data() : nullptr;
    cu.box_count = nb;
    cu.spheres = ns ? spheres.data() : nullptr;
    cu.sphere_count = ns;
    const size_t cap = r.size(19);
    const bool null_out = (flags & 128) != 0;  // null buffers with a capacity: InvalidArgument
    std::vector<uint8_t> masks(cap + 1, 0xEE);
    const shadowkit::OmniCullResult mr = shadowkit::omni_cull_casters(cu, null_out ? nullptr : masks.data(), cap);
    shadowkit_fuzz::check_detail(mr);
    if (null_out && cap > 0) check(mr.status == shadowkit::Status::InvalidArgument);
    if (mr.status == shadowkit::Status::Ok || mr.status == shadowkit::Status::BufferTooSmall) {
        check(mr.caster_count == nb + ns && mr.needed == nb + ns);
        check(mr.count <= cap && mr.count == std::min(cap, mr.needed));
        check(mr.draws + mr.draws_saved == 6 * mr.caster_count);
        check(mr.invalid_count <= mr.caster_count);
        check((mr.status == shadowkit::Status::BufferTooSmall) == (cap < mr.caster_count));
        check(masks[cap] == 0xEE);  // nothing past the capacity
        size_t sum = 0;
        for (size_t i = 0; i < std::min(cap, mr.caster_count); ++i) {
            check((masks[i] & ~shadowkit::omni_all_faces_mask) == 0);
            for (int f = 0; f < 6; ++f) sum += (masks[i] >> f) & 1u;
        }
        if (cap >= mr.caster_count) check(sum == mr.draws);
    }
    std::vector<uint32_t> lists(cap + 1, 0xDEADBEEFu);
    size_t off[7] = {};
    const shadowkit::OmniCullResult lr = shadowkit::omni_cull_face_lists(cu, null_out ? nullptr : lists.data(), cap, off);
    shadowkit_fuzz::check_detail(lr);
    if (null_out && cap > 0) check(lr.status == shadowkit::Status::InvalidArgument);
    if (lr.status == shadowkit::Status::Ok) {
        check(off[6] == lr.draws && lr.draws <= cap && lr.count == lr.draws);
        for (size_t k = 0; k < lr.draws; ++k) check(lists[k] < lr.caster_count);
        check(lists[cap] == 0xDEADBEEFu);
    } else if (lr.status == shadowkit::Status::BufferTooSmall) {
        check(lr.needed > cap && lr.count == 0);
        check(lists[0] == 0xDEADBEEFu);
    }
    check((shadowkit::omni_cube_box_mask(cu.light_position, cu.near_z, cu.far_z, r.vec3(), r.vec3()) &
           ~shadowkit::omni_all_faces_mask) == 0);
    check((shadowkit::omni_cube_sphere_mask(cu.light_position, cu.near_z, cu.far_z, r.vec3(), r.f32()) &
           ~shadowkit::omni_all_faces_mask) == 0);
    // ---- paraboloid
    const shadowkit::OmniParaboloidFrame fr = shadowkit::omni_paraboloid_frame(cu.light_position, r.vec3(), r.vec3());
    shadowkit_fuzz::check_detail(fr);
    if (fr.status == shadowkit::Status::Ok) check(all_finite(fr.view));
    const glm::vec3 pd = r.vec3();
    const shadowkit::OmniParaboloidPoint pp = shadowkit::omni_paraboloid_project(pd);
    shadowkit_fuzz::check_detail(pp);
    if (pp.status == shadowkit::Status::Ok) {
        check(all_finite(pp.xy.x) && all_finite(pp.xy.y) && glm::length(pp.xy) <= 1.0001f);
        const shadowkit::OmniDirection back = shadowkit::omni_paraboloid_unproject(pp.hemisphere, pp.xy);
        shadowkit_fuzz::check_detail(back);
        check(back.status == shadowkit::Status::Ok && all_finite(back.direction));
    }
    const shadowkit::OmniDirection up =
        shadowkit::omni_paraboloid_unproject(static_cast<shadowkit::OmniHemisphere>(r.range(0, 2)), r.vec2());
    shadowkit_fuzz::check_detail(up);
    if (up.status == shadowkit::Status::Ok) check(all_finite(up.direction) && std::fabs(glm::length(up.direction) - 1.f) < 1e-3f);
    const shadowkit::OmniValue pta = shadowkit::omni_paraboloid_texel_angle(map_size, r.f32());
    shadowkit_fuzz::check_detail(pta);
    if (pta.status == shadowkit::Status::Ok) check(all_finite(pta.value) && pta.value >= 0.f && map_size != 0);
    const float el = r.f32(), ed = r.f32(), rad = (flags & 32) ? r.f32() : 1.0f;
    const shadowkit::OmniEdgeErrorResult ee = shadowkit::omni_paraboloid_edge_error(el, ed, map_size, rad);
    shadowkit_fuzz::check_detail(ee);
    if (ee.status == shadowkit::Status::Ok) check(all_finite(ee.texels) && ee.texels >= 0.f && ee.subtended_angle >= 0.f);
    const shadowkit::OmniEdgeLengthResult ml = shadowkit::omni_paraboloid_max_edge_length(ed, map_size, r.f32(), rad);
    shadowkit_fuzz::check_detail(ml);
    if (ml.status == shadowkit::Status::Ok) check(all_finite(ml.length) && ml.length >= 0.f);  // was +inf with Ok
    return 0;
}
