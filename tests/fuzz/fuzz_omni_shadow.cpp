// libFuzzer target for shadowkit/omni_shadow.hpp: every public function with inputs decoded from
// raw bytes (floats may be NaN/Inf/denormal, enum values out of range, caster counts up to what
// the data holds, capacities smaller than needed). Invariants checked with __builtin_trap().
#include <shadowkit/omni_shadow.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

namespace {
struct Reader {
    const uint8_t* p;
    size_t n;
    float f() {
        float v = 0.0f;
        if (n >= 4) { std::memcpy(&v, p, 4); p += 4; n -= 4; }
        return v;
    }
    uint8_t b() {
        if (n == 0) return 0;
        const uint8_t v = *p;
        ++p; --n;
        return v;
    }
    uint32_t u32() {
        uint32_t v = 0;
        if (n >= 4) { std::memcpy(&v, p, 4); p += 4; n -= 4; }
        return v;
    }
};
bool fin(float v) { return std::isfinite(v); }
bool fin3(const glm::vec3& v) { return fin(v.x) && fin(v.y) && fin(v.z); }
bool fin_mat(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!fin(m[c][r])) return false;
    return true;
}
void check(bool ok) {
    if (!ok) __builtin_trap();
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    Reader r{data, size};
    const uint8_t flags = r.b();
    // ---- cube matrices
    shadowkit::OmniCubeInput ci;
    ci.light = {r.f(), r.f(), r.f()};
    ci.near_z = r.f();
    ci.far_z = (flags & 1) ? INFINITY : r.f();
    ci.clip_depth = (flags & 2) ? shadowkit::ClipDepth::ZeroToOne : shadowkit::ClipDepth::NegativeOneToOne;
    ci.reversed_z = (flags & 4) != 0;
    const shadowkit::OmniCubeMatrices cm = shadowkit::omni_cube_matrices(ci);
    if (cm.status == shadowkit::OmniStatus::Ok) {
        check(fin_mat(cm.proj));
        for (int f = 0; f < 6; ++f) check(fin_mat(cm.view_proj[f]) && fin_mat(cm.view[f]));
    }
    // ---- face selection and its inverse
    const glm::vec3 d(r.f(), r.f(), r.f());
    const shadowkit::OmniFaceHit h = shadowkit::omni_cube_face(d);
    if (h.status == shadowkit::OmniStatus::Ok) {
        check(static_cast<int>(h.face) <= 5);
        check(h.st.x >= 0.f && h.st.x <= 1.f && h.st.y >= 0.f && h.st.y <= 1.f);
        // exactly one owner under the documented tie rule
        const float ax = std::fabs(d.x), ay = std::fabs(d.y), az = std::fabs(d.z);
        const int axis = (ax >= ay && ax >= az) ? 0 : (ay >= az ? 1 : 2);
        check(static_cast<int>(h.face) / 2 == axis);
        const shadowkit::OmniDirection back = shadowkit::omni_cube_direction(h.face, h.st);
        check(back.status == shadowkit::OmniStatus::Ok && fin3(back.direction));
    } else {
        check(!fin3(d) || (d.x == 0.f && d.y == 0.f && d.z == 0.f));
    }
    const shadowkit::OmniDirection cd = shadowkit::omni_cube_direction(static_cast<shadowkit::OmniCubeFace>(r.b()), {r.f(), r.f()});
    if (cd.status == shadowkit::OmniStatus::Ok) check(fin3(cd.direction));
    (void)shadowkit::omni_cube_face_basis(static_cast<shadowkit::OmniCubeFace>(r.b()));
    const uint32_t map_size = r.u32() % 70000u;
    const float ta = shadowkit::omni_cube_texel_angle(map_size);
    check(fin(ta) && ta >= 0.f);
    // ---- linear depth and bias
    const float dist = r.f(), range = r.f();
    const auto fmt = static_cast<shadowkit::DepthFormat>(r.b() % 3);
    const shadowkit::OmniDepthResult ld = shadowkit::omni_linear_depth(dist, range, fmt);
    if (ld.status == shadowkit::OmniStatus::Ok) check(ld.value >= 0.f && ld.value <= 1.f);
    shadowkit::OmniBiasInput bi;
    bi.distance = dist;
    bi.cos_theta = r.f();
    bi.texel_angle = r.f();
    bi.filter_radius = r.f();
    bi.range = range;
    bi.format = fmt;
    if (flags & 8) bi.max_angle = r.f();
    if (flags & 16) bi.constant = r.f();
    const shadowkit::OmniBiasResult br = shadowkit::omni_distance_bias(bi);
    if (br.status == shadowkit::OmniStatus::Ok) check(fin(br.bias) && br.bias >= 0.f && fin(br.stored_bias));
    // ---- culling: casters from the rest of the data (counts bounded by what the data holds)
    shadowkit::OmniCullInput cu;
    cu.light = ci.light;
    cu.near_z = ci.near_z;
    cu.far_z = ci.far_z;
    const size_t nb = r.b() % 9, ns = r.b() % 9;
    std::vector<float> boxes(6 * nb), spheres(4 * ns);
    for (auto& v : boxes) v = r.f();
    for (auto& v : spheres) v = r.f();
    cu.boxes = nb ? boxes.data() : nullptr;
    cu.box_count = nb;
    cu.spheres = ns ? spheres.data() : nullptr;
    cu.sphere_count = ns;
    const size_t cap = r.b() % 20;
    std::vector<uint8_t> masks(cap + 1, 0xEE);
    const shadowkit::OmniCullResult mr = shadowkit::omni_cull_casters(cu, masks.data(), cap);
    if (mr.status == shadowkit::OmniStatus::Ok || mr.status == shadowkit::OmniStatus::BufferTooSmall) {
        check(mr.caster_count == nb + ns && mr.needed == nb + ns);
        check(mr.draws + mr.draws_saved == 6 * mr.caster_count);
        check(mr.invalid_count <= mr.caster_count);
        check((mr.status == shadowkit::OmniStatus::BufferTooSmall) == (cap < mr.caster_count));
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
    const shadowkit::OmniCullResult lr = shadowkit::omni_cull_face_lists(cu, lists.data(), cap, off);
    if (lr.status == shadowkit::OmniStatus::Ok) {
        check(off[6] == lr.draws && lr.draws <= cap);
        for (size_t k = 0; k < lr.draws; ++k) check(lists[k] < lr.caster_count);
        check(lists[cap] == 0xDEADBEEFu);
    } else if (lr.status == shadowkit::OmniStatus::BufferTooSmall) {
        check(lr.needed > cap);
        check(lists[0] == 0xDEADBEEFu);
    }
    (void)shadowkit::omni_cube_box_mask(cu.light, cu.near_z, cu.far_z, {r.f(), r.f(), r.f()}, {r.f(), r.f(), r.f()});
    (void)shadowkit::omni_cube_sphere_mask(cu.light, cu.near_z, cu.far_z, {r.f(), r.f(), r.f()}, r.f());
    // ---- paraboloid
    const shadowkit::OmniParaboloidFrame fr = shadowkit::omni_paraboloid_frame(cu.light, {r.f(), r.f(), r.f()}, {r.f(), r.f(), r.f()});
    if (fr.status == shadowkit::OmniStatus::Ok) check(fin_mat(fr.view));
    const glm::vec3 pd(r.f(), r.f(), r.f());
    const shadowkit::OmniParaboloidPoint pp = shadowkit::omni_paraboloid_project(pd);
    if (pp.status == shadowkit::OmniStatus::Ok) {
        check(fin(pp.xy.x) && fin(pp.xy.y) && glm::length(pp.xy) <= 1.0001f);
        const shadowkit::OmniDirection back = shadowkit::omni_paraboloid_unproject(pp.hemisphere, pp.xy);
        check(back.status == shadowkit::OmniStatus::Ok && fin3(back.direction));
    }
    const shadowkit::OmniDirection up =
        shadowkit::omni_paraboloid_unproject(static_cast<shadowkit::OmniHemisphere>(r.b() % 3), {r.f(), r.f()});
    if (up.status == shadowkit::OmniStatus::Ok) check(fin3(up.direction) && std::fabs(glm::length(up.direction) - 1.f) < 1e-3f);
    const float pta = shadowkit::omni_paraboloid_texel_angle(map_size, r.f());
    check(fin(pta) && pta >= 0.f);
    const float el = r.f(), ed = r.f(), rad = (flags & 32) ? r.f() : 1.0f;
    const shadowkit::OmniEdgeErrorResult ee = shadowkit::omni_paraboloid_edge_error(el, ed, map_size, rad);
    if (ee.status == shadowkit::OmniStatus::Ok) check(fin(ee.texels) && ee.texels >= 0.f && ee.subtended_angle >= 0.f);
    const shadowkit::OmniEdgeLengthResult ml = shadowkit::omni_paraboloid_max_edge_length(ed, map_size, r.f(), rad);
    if (ml.status == shadowkit::OmniStatus::Ok) check(!std::isnan(ml.length) && ml.length >= 0.f);
    return 0;
}
