// libFuzzer target for shadowkit/shadow_volume.hpp: arbitrary positions, edges, triangles, lit flags,
// capacities, cap modes, lights, bounds, cameras, matrices and viewports. Invariants trap on
// violation: Ok only with finite outputs in range, count <= capacity, count == needed when Ok,
// nothing written past a capacity, never Ok for out-of-range input; caps of up to 700 triangles
// (the writer's 64-triangle groups) equal a plain reference.
#include <shadowkit/shadow_volume.hpp>

#include "fuzz_input.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    namespace sk = shadowkit;
    shadowkit_fuzz::FuzzInput in(data, size);
    const std::uint8_t mode = in.u8();
    const std::size_t nv = in.size(31), ne = in.size(79), nt = in.size(39), cap = in.size(255);
    std::vector<glm::vec3> pos(nv);
    for (auto& v : pos) v = in.vec3();
    std::vector<std::uint32_t> edges(ne), tris(3 * nt);
    for (auto& e : edges) e = (mode & 1) ? in.u32() : in.range<std::uint32_t>(0, static_cast<std::uint32_t>(nv));
    for (auto& t : tris) t = (mode & 1) ? in.u32() : in.range<std::uint32_t>(0, static_cast<std::uint32_t>(nv));
    std::vector<std::uint8_t> lit(nt);
    for (auto& l : lit) l = in.u8();

    std::vector<glm::vec4> vb(cap + 1, glm::vec4(-7.0f));
    const sk::VolumeBuffer rv = sk::volume_build_vertices(nv ? pos.data() : nullptr, nv, vb.data(), cap);
    shadowkit_fuzz::check_detail(rv);
    if (vb[cap] != glm::vec4(-7.0f)) __builtin_trap();
    if (rv.count > cap || rv.status == sk::Status::NotRun) __builtin_trap();
    if (rv.status == sk::Status::Ok || rv.status == sk::Status::BufferTooSmall) {
        if (rv.needed != 2 * nv || (rv.status == sk::Status::Ok) != (rv.count == rv.needed)) __builtin_trap();
        for (std::size_t k = 0; k < rv.count; ++k)
            if (!shadowkit_fuzz::all_finite(vb[k]) || (vb[k].w != 0.0f && vb[k].w != 1.0f)) __builtin_trap();
    }
    if (nv > 0 && sk::volume_build_vertices(nullptr, nv, vb.data(), cap).status != sk::Status::InvalidArgument) __builtin_trap();

    std::vector<std::uint32_t> ib(cap + 1, 0xDEADBEEFu);
    const sk::VolumeBuffer rs = sk::volume_build_side_quads(ne ? edges.data() : nullptr, ne, nv, ib.data(), cap);
    shadowkit_fuzz::check_detail(rs);
    if (ib[cap] != 0xDEADBEEFu || rs.count > cap) __builtin_trap();
    if (rs.status == sk::Status::Ok || rs.status == sk::Status::BufferTooSmall) {
        if (ne % 2 != 0 || rs.needed != 3 * ne || rs.count % 6 != 0 || (rs.status == sk::Status::Ok) != (rs.count == rs.needed))
            __builtin_trap();
        for (std::size_t k = 0; k < rs.count; ++k)
            if (ib[k] >= 2 * nv) __builtin_trap();
    } else if (ne % 2 == 0 && rs.status == sk::Status::InvalidArgument && nv <= 0x7FFFFFFF) {
        __builtin_trap();  // an even count of in-range arguments is never invalid
    }
    if (ne > 0 && sk::volume_build_side_quads(nullptr, ne, nv, ib.data(), cap).status != sk::Status::InvalidArgument) __builtin_trap();
    std::fill(ib.begin(), ib.end(), 0xDEADBEEFu);
    const std::uint8_t cm_byte = in.u8();
    const sk::VolumeCapMode cm = (cm_byte & 3) == 3 ? static_cast<sk::VolumeCapMode>(3 + (cm_byte >> 2))  // past TwoSided
                                 : (cm_byte & 3) == 2 ? sk::VolumeCapMode::TwoSided
                                                      : ((mode & 2) ? sk::VolumeCapMode::EverittKilgard : sk::VolumeCapMode::LitOnly);
    const std::size_t lit_count = (cm_byte & 4) ? in.size(nt + 1) : nt;
    const sk::VolumeBuffer rc = sk::volume_build_caps(nt ? tris.data() : nullptr, 3 * nt, lit_count ? lit.data() : nullptr, lit_count,
                                                      nv, cm, (mode & 4) != 0, ib.data(), cap);
    shadowkit_fuzz::check_detail(rc);
    if (ib[cap] != 0xDEADBEEFu || rc.count > cap) __builtin_trap();
    if (rc.status == sk::Status::Ok || rc.status == sk::Status::BufferTooSmall) {
        if ((cm_byte & 3) == 3 || lit_count != nt) __builtin_trap();  // out-of-range mode / count: never Ok
        if (rc.needed % 3 != 0 || rc.needed > 6 * nt || rc.count % 3 != 0 || (rc.status == sk::Status::Ok) != (rc.count == rc.needed))
            __builtin_trap();
        for (std::size_t k = 0; k < rc.count; ++k)
            if (ib[k] >= 2 * nv) __builtin_trap();
    }

    // many triangles (the caps writer's 64-triangle groups): against a plain reference (whole
    // triangles while they fit), any capacity, indices and lit bytes from a generator seeded by the
    // input (lit in runs or random, sometimes an index out of range), both modes, with and without
    // the dark cap
    {
        const std::size_t nt2 = in.size(700);
        const std::uint32_t nv2 = 1u + static_cast<std::uint32_t>(in.size(300));
        std::uint32_t seed = in.u32();
        auto next = [&seed] {
            seed = seed * 1664525u + 1013904223u;
            return seed >> 8;
        };
        const std::uint8_t style = in.u8();
        std::vector<std::uint32_t> t2(3 * nt2);
        for (auto& t : t2) t = ((style & 1) && next() % 997 == 0) ? nv2 + next() % 3 : next() % nv2;
        std::vector<std::uint8_t> l2(nt2);
        bool run = false;
        for (auto& l : l2) {
            if (next() % 29 == 0) run = !run;
            l = static_cast<std::uint8_t>((style & 2) ? (run ? 1u : 0u) : next() % 3);
        }
        const bool ek = (style & 4) != 0, dark = (style & 8) != 0, two = (style & 32) != 0;
        bool bad = false;
        for (std::uint32_t t : t2) bad |= t >= nv2;
        std::vector<std::uint32_t> ref;
        for (std::size_t t = 0; t < nt2; ++t) {
            const std::uint32_t a = t2[3 * t], b = t2[3 * t + 1], c = t2[3 * t + 2];
            if (two) {  // every triangle, an unlit one reversed; its extrusion reversed again
                const std::uint32_t p = l2[t] ? b : c, q = l2[t] ? c : b;
                ref.insert(ref.end(), {a, p, q});
                if (dark) ref.insert(ref.end(), {a + nv2, q + nv2, p + nv2});
                continue;
            }
            if (l2[t]) {
                ref.insert(ref.end(), {a, b, c});
                if (dark && !ek) ref.insert(ref.end(), {a + nv2, c + nv2, b + nv2});
            } else if (dark && ek) {
                ref.insert(ref.end(), {a + nv2, b + nv2, c + nv2});
            }
        }
        const std::size_t cap2 = (style & 16) ? in.size(2 * t2.size() + 8) : 2 * t2.size() + 8;
        std::vector<std::uint32_t> o2(cap2 + 1, 0xDEADBEEFu);
        const sk::VolumeBuffer r2 = sk::volume_build_caps(t2.data(), t2.size(), l2.data(), nt2, nv2,
                                                          two  ? sk::VolumeCapMode::TwoSided
                                                          : ek ? sk::VolumeCapMode::EverittKilgard
                                                               : sk::VolumeCapMode::LitOnly,
                                                          dark, o2.data(), cap2);
        shadowkit_fuzz::check_detail(r2);
        if (o2[cap2] != 0xDEADBEEFu) __builtin_trap();
        if (bad) {
            if (r2.status != sk::Status::IndexOutOfRange) __builtin_trap();
        } else {
            const std::size_t want = std::min(ref.size(), cap2 / 3 * 3);
            if (r2.needed != ref.size() || r2.count != want || (r2.status == sk::Status::Ok) != (want == ref.size()) ||
                (r2.status != sk::Status::Ok && r2.status != sk::Status::BufferTooSmall))
                __builtin_trap();
            if (!std::equal(ref.begin(), ref.begin() + static_cast<std::ptrdiff_t>(want), o2.begin())) __builtin_trap();
        }
    }

    glm::vec4 L(in.vec3(), (mode & 8) ? 0.0f : in.f32());
    if ((mode & 0x30) == 0x30 && nv > 0) L = glm::vec4(pos[0], 1.0f);  // the light on a vertex
    const bool light_ok = shadowkit_fuzz::all_finite(L) && L.w >= 0.0f && !(L.x == 0.0f && L.y == 0.0f && L.z == 0.0f && L.w == 0.0f);
    sk::VolumeNearRect rect;
    if (mode & 32) {
        rect = sk::volume_near_plane_rect((mode & 64) ? in.mat4() : in.look_at_view(), in.f32(), in.f32(), in.f32());
        shadowkit_fuzz::check_detail(rect);
        if (rect.status == sk::Status::Ok)
            for (const glm::vec3& c : rect.corners)
                if (!shadowkit_fuzz::all_finite(c)) __builtin_trap();
    } else {  // a hand-made rectangle (any corners, any status): the choices must still check it
        for (auto& c : rect.corners) c = in.vec3();
        rect.status = (in.u8() & 1) ? sk::Status::Ok : sk::Status::NotRun;
    }
    bool rect_finite = true;
    for (const glm::vec3& c : rect.corners) rect_finite = rect_finite && shadowkit_fuzz::all_finite(c);
    const glm::vec3 bmin = in.vec3(), bmax = in.vec3();
    const float margin = (mode & 16) ? in.f32() : 0.0f;
    const sk::VolumeMethod mb = sk::volume_choose_stencil_method_box(rect, L, bmin, bmax, margin);
    shadowkit_fuzz::check_detail(mb);
    if (mb.status != sk::Status::Ok && mb.method != sk::VolumeStencilMethod::ZFail) __builtin_trap();
    if (mb.status == sk::Status::Ok && (rect.status != sk::Status::Ok || !rect_finite || !light_ok || !(bmin.x <= bmax.x && bmin.y <= bmax.y && bmin.z <= bmax.z) ||
                                        !(margin >= 0.0f) || !std::isfinite(margin)))
        __builtin_trap();
    const float radius = in.f32();
    const sk::VolumeMethod ms = sk::volume_choose_stencil_method_sphere(rect, L, bmin, radius, margin);
    shadowkit_fuzz::check_detail(ms);
    if (ms.status != sk::Status::Ok && ms.method != sk::VolumeStencilMethod::ZFail) __builtin_trap();
    if (ms.status == sk::Status::Ok && (rect.status != sk::Status::Ok || !rect_finite || !light_ok || !(radius >= 0.0f) || !std::isfinite(radius)))
        __builtin_trap();

    // near plane from a camera: documented ranges only
    {
        const glm::mat4 view = (mode & 64) ? in.mat4() : glm::mat4(1.0f);
        const float fovy = in.f32(), aspect = in.f32(), near_z = in.f32();
        const sk::VolumeNearRect r = sk::volume_near_plane_rect(view, fovy, aspect, near_z);
        shadowkit_fuzz::check_detail(r);
        if (r.status == sk::Status::Ok) {
            if (!(fovy > 0.0f && fovy < 3.1415927f && aspect > 0.0f && near_z > 0.0f) || !std::isfinite(aspect) || !std::isfinite(near_z))
                __builtin_trap();
            for (const glm::vec3& c : r.corners)
                if (!shadowkit_fuzz::all_finite(c)) __builtin_trap();
        }
        const sk::VolumeNearRect ri = sk::volume_near_plane_rect_from_inverse(
            view, (mode & 64) ? sk::ClipDepth::ZeroToOne : sk::ClipDepth::NegativeOneToOne, (mode & 128) != 0);
        shadowkit_fuzz::check_detail(ri);
        if (ri.status == sk::Status::Ok)
            for (const glm::vec3& c : ri.corners)
                if (!shadowkit_fuzz::all_finite(c)) __builtin_trap();
    }

    sk::ScissorParams sp;
    const std::uint8_t ssel = in.u8();
    if (ssel & 1) sp.view_proj = in.mat4();  // else the default (zero, required): never Ok
    sp.clip_depth = (mode & 64) ? sk::ClipDepth::ZeroToOne : sk::ClipDepth::NegativeOneToOne;
    sp.reversed_z = (mode & 128) != 0;
    if (ssel & 2)
        for (int& v : sp.viewport) v = in.i32();
    const glm::vec3 lmin = in.vec3(), lmax = in.vec3();
    const sk::ScissorRect s = sk::volume_scissor(L, bmin, bmax, lmin, lmax, sp);
    shadowkit_fuzz::check_detail(s);
    if (s.status == sk::Status::NotRun) __builtin_trap();
    if (s.status == sk::Status::Ok) {
        if (!(ssel & 1) || !(ssel & 2) || !light_ok) __builtin_trap();
        if (!(s.depth_min >= 0.0f && s.depth_max <= 1.0f && s.depth_min <= s.depth_max)) __builtin_trap();
        if (s.visible) {
            const long long x0 = sp.viewport[0], y0 = sp.viewport[1];
            if (s.width <= 0 || s.height <= 0) __builtin_trap();
            if (s.x < x0 || s.y < y0 || static_cast<long long>(s.x) + s.width > x0 + sp.viewport[2] ||
                static_cast<long long>(s.y) + s.height > y0 + sp.viewport[3])
                __builtin_trap();
        }
    } else if (s.visible) {
        __builtin_trap();
    }
    const glm::vec4 p(bmin, (mode & 2) ? 1.0f : in.f32());
    const sk::VolumeExtrusion x = sk::volume_extrude_to_infinity(p, L);
    shadowkit_fuzz::check_detail(x);
    if (x.status == sk::Status::Ok) {
        if (!shadowkit_fuzz::all_finite(x.position) || x.position.w != 0.0f || !light_ok) __builtin_trap();
        if (x.position.x == 0.0f && x.position.y == 0.0f && x.position.z == 0.0f) __builtin_trap();
    }
    (void)sk::volume_indices_capacity(static_cast<std::size_t>(in.u64()), static_cast<std::size_t>(in.u64()));
    return 0;
}
