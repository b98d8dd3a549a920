// libFuzzer target for include/shadowkit/smoothie.hpp: silhouette edges (positions, indices, face
// normals, outward hints), light matrices (raw floats or a perspective/ortho light built from the
// bytes), t, clip conventions and capacities decoded from bytes (NaN/Inf, out-of-range indices and
// shared vertices included); the scalar helpers get raw floats. Invariants trap on violation:
// Status::Ok only with finite outputs (issue 19), count <= capacity, nothing written past a capacity,
// the scratch and vertex sizes reported exactly.
#include <shadowkit/smoothie.hpp>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>

#include "fuzz_input.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

namespace {
bool finite_vertex(const shadowkit::SmoothieVertex& v) {
    const float* f = &v.position.x;
    for (int k = 0; k < 12; ++k)
        if (!std::isfinite(f[k])) return false;
    return true;
}

void check_unit(float x) {
    if (!(x >= 0.0f && x <= 1.0f)) __builtin_trap();
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace shadowkit;
    shadowkit_fuzz::FuzzInput r(data, size);
    const uint8_t flags = r.u8();
    const uint8_t flags2 = r.u8();
    const bool raw_pos = flags & 1, raw_matrix = flags & 2, raw_t = flags & 4, raw_idx = flags & 8;
    const bool with_normals = !(flags & 16), with_hints = flags & 32, ortho = flags & 64;

    // scalar helpers
    {
        const float a = r.f32(), b = r.f32(), rr = r.f32(), z = r.f32(), bias = r.f32();
        check_unit(smoothie_remap_alpha(a, b, rr));
        check_unit(smoothie_falloff(a));
        check_unit(smoothie_visibility_tap(rr, z, b, a, bias));
        const SmoothieValue w = smoothie_width_for_area_light(a, b, rr), t2 = smoothie_area_light_width(a, b, rr),
                            pw = smoothie_penumbra_width(a, b, rr, z);
        for (const SmoothieValue* v : {&w, &t2, &pw}) {
            if (v->status == Status::NotRun) __builtin_trap();
            shadowkit_fuzz::check_detail(*v);
            if (v->status == Status::Ok && !(std::isfinite(v->value) && v->value >= 0.0f)) __builtin_trap();
        }
        if (std::isfinite(a) && a >= 0.0f && a <= 1.0f && std::isfinite(b) && std::isfinite(rr) && b >= 0.0f && b < rr &&
            rr > 0.0f && smoothie_remap_alpha(a, b, rr) < a * (1.0f - 1e-6f))
            __builtin_trap();  // eq. 1 never darkens: alpha / (1 - b/r) >= alpha
    }

    SmoothieParams prm;
    prm.clip_depth = (flags2 & 1) ? ClipDepth::ZeroToOne : ClipDepth::NegativeOneToOne;
    prm.reversed_z = flags2 & 2;
    prm.paper_fans = flags2 & 4;
    prm.t = raw_t ? r.f32() : static_cast<float>(r.u8()) / 256.0f;

    glm::mat4 M(1.0f);
    if (raw_matrix) {
        M = r.mat4();
    } else {
        glm::vec3 eye = r.vec3(false, 0.25f);
        eye.z += 12.0f;
        const float fov = 0.2f + static_cast<float>(r.u8()) / 100.0f;
        glm::mat4 P = ortho ? glm::ortho(-8.0f, 8.0f, -8.0f, 8.0f, 0.5f, 60.0f) : glm::perspective(fov, 1.0f, 0.5f, 60.0f);
        if (prm.clip_depth == ClipDepth::ZeroToOne)
            P = ortho ? glm::orthoRH_ZO(-8.0f, 8.0f, -8.0f, 8.0f, 0.5f, 60.0f) : glm::perspectiveRH_ZO(fov, 1.0f, 0.5f, 60.0f);
        M = P * glm::lookAt(eye, glm::vec3(0.0f), glm::vec3(0.0f, 1.0f, 0.0f));
    }

    const size_t np = r.size(32);
    const size_t ne = r.size(64);
    std::vector<glm::vec3> pos(np);
    for (auto& p : pos) p = r.vec3(raw_pos, 0.0625f);
    std::vector<std::uint32_t> idx(2 * ne);
    for (auto& i : idx) i = raw_idx ? r.u32() : r.range<std::uint32_t>(0, static_cast<std::uint32_t>(np + 1));
    std::vector<glm::vec3> normals(2 * ne), hints(ne);
    for (auto& n : normals) n = r.vec3(raw_pos, 0.01f);
    for (auto& h : hints) h = r.vec3(raw_pos, 0.01f);
    const size_t cap = r.size(4095);
    const bool short_scratch = (flags2 & 8) != 0, null_scratch = (flags2 & 16) != 0;
    const size_t scap = short_scratch && ne > 0 ? r.size(ne - 1) : ne;
    SmoothieEdges in;
    in.positions = pos.empty() ? nullptr : pos.data();
    in.position_count = np;
    in.edges = idx.empty() ? nullptr : idx.data();
    in.edge_count = ne;
    in.face_normals = with_normals && ne ? normals.data() : nullptr;
    in.outward = with_hints && ne ? hints.data() : nullptr;

    std::vector<SmoothieVertex> out(cap + 1);
    std::memset(static_cast<void*>(out.data()), 0, out.size() * sizeof(SmoothieVertex));
    std::vector<SmoothieScratch> scratch(scap + 1);
    SmoothieScratch* sp = null_scratch ? nullptr : scratch.data();
    const SmoothieResult q = smoothie_build(in, M, prm, sp, scap, nullptr, 0);
    const SmoothieResult res = smoothie_build(in, M, prm, sp, scap, cap ? out.data() : nullptr, cap);
    if (res.status == Status::NotRun) __builtin_trap();
    shadowkit_fuzz::check_detail(q);
    shadowkit_fuzz::check_detail(res);
    if (null_scratch && scap > 0 && res.status != Status::InvalidArgument) __builtin_trap();  // null with a capacity
    const bool scratch_short = res.scratch_needed > scap;
    if (res.scratch_needed > smoothie_scratch_capacity(ne)) __builtin_trap();  // the size query covers it
    if (scratch_short && res.status != Status::BufferTooSmall) __builtin_trap();
    if (res.status != q.status && !(q.status == Status::BufferTooSmall || res.status == Status::BufferTooSmall))
        __builtin_trap();
    if ((res.status == Status::Ok || res.status == Status::BufferTooSmall) && !scratch_short) {
        if (res.needed != q.needed) __builtin_trap();            // deterministic, capacity-independent
        if (res.scratch_needed != (prm.t > 0.0f && ne > 0 ? ne : 0)) __builtin_trap();
        if (res.count > cap || res.count % 3 != 0) __builtin_trap();
        if (res.needed > smoothie_vertex_capacity(ne)) __builtin_trap();
        if (res.needed % 3 != 0) __builtin_trap();
        if (res.status == Status::Ok && res.count != res.needed) __builtin_trap();
        if (res.status == Status::BufferTooSmall && res.count != cap / 3 * 3) __builtin_trap();
        if (prm.t == 0.0f && res.needed != 0) __builtin_trap();        // t = 0: hard shadows, no geometry
        if (prm.t > 0.0f && res.edge_quads + res.skipped_invalid + res.skipped_behind + res.skipped_end_on + res.skipped_no_outward +
                res.skipped_unprojectable != ne)
            __builtin_trap();  // every edge is accounted for
        for (size_t k = 0; k < res.count; ++k) {
            const SmoothieVertex& v = out[k];
            if (!finite_vertex(v)) __builtin_trap();
            check_unit(v.alpha);
            if (v.corner != 0.0f && v.corner != 1.0f) __builtin_trap();
            if (v.reserved != 0.0f || !(v.inv_t > 0.0f)) __builtin_trap();
        }
        if (out[cap].position.x != 0.0f || out[cap].alpha != 0.0f) __builtin_trap();  // nothing past capacity
    }
    return 0;
}
