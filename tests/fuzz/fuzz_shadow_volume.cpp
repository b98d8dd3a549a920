// libFuzzer target for shadowkit/shadow_volume.hpp: arbitrary positions, edges, triangles, lit flags,
// capacities, lights, bounds, matrices and viewports. Invariants trap on violation.
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
    const std::size_t nv = in.size(31), ne = in.size(39), nt = in.size(39), cap = in.size(255);
    std::vector<glm::vec3> pos(nv);
    for (auto& v : pos) v = in.vec3();
    std::vector<std::uint32_t> edges(2 * ne), tris(3 * nt);
    for (auto& e : edges) e = (mode & 1) ? in.u32() : in.range<std::uint32_t>(0, static_cast<std::uint32_t>(nv));
    for (auto& t : tris) t = (mode & 1) ? in.u32() : in.range<std::uint32_t>(0, static_cast<std::uint32_t>(nv));
    std::vector<std::uint8_t> lit(nt);
    for (auto& l : lit) l = in.u8();

    std::vector<glm::vec4> vb(cap + 1, glm::vec4(-7.0f));
    const sk::VolumeCount rv = sk::build_volume_vertices(nv ? pos.data() : nullptr, nv, vb.data(), cap);
    if (vb[cap] != glm::vec4(-7.0f)) __builtin_trap();
    if (rv.status == sk::VolumeStatus::Ok && rv.count != 2 * nv) __builtin_trap();

    std::vector<std::uint32_t> ib(cap + 1, 0xDEADBEEFu);
    const sk::VolumeCount rs = sk::build_side_quads(ne ? edges.data() : nullptr, ne, nv, ib.data(), cap);
    if (ib[cap] != 0xDEADBEEFu) __builtin_trap();
    if (rs.status == sk::VolumeStatus::Ok || rs.status == sk::VolumeStatus::BufferTooSmall) {
        if (rs.count != 6 * ne) __builtin_trap();
        for (std::size_t k = 0; k < (rs.count < cap ? rs.count : (cap / 6) * 6); ++k)
            if (ib[k] >= 2 * nv) __builtin_trap();
    }
    std::fill(ib.begin(), ib.end(), 0xDEADBEEFu);
    const sk::CapMode cm = (mode & 2) ? sk::CapMode::EverittKilgard : sk::CapMode::LitOnly;
    const sk::VolumeCount rc = sk::build_caps(nt ? tris.data() : nullptr, nt, nt ? lit.data() : nullptr, nv, cm, (mode & 4) != 0, ib.data(), cap);
    if (ib[cap] != 0xDEADBEEFu) __builtin_trap();
    if (rc.status == sk::VolumeStatus::Ok || rc.status == sk::VolumeStatus::BufferTooSmall) {
        if (rc.count % 3 != 0 || rc.count > 6 * nt) __builtin_trap();
        for (std::size_t k = 0; k < (rc.count < cap ? rc.count : (cap / 3) * 3); ++k)
            if (ib[k] >= 2 * nv) __builtin_trap();
    }

    const glm::vec4 L(in.vec3(), (mode & 8) ? 0.0f : in.f32());
    sk::NearPlaneRect rect;
    for (auto& c : rect.corners) c = in.vec3();
    const glm::vec3 bmin = in.vec3(), bmax = in.vec3();
    const float margin = (mode & 16) ? in.f32() : 0.0f;
    const sk::MethodResult mb = sk::choose_stencil_method_box(rect, L, bmin, bmax, margin);
    if (mb.status != sk::VolumeStatus::Ok && mb.method != sk::StencilMethod::ZFail) __builtin_trap();
    const sk::MethodResult ms = sk::choose_stencil_method_sphere(rect, L, bmin, in.f32(), margin);
    if (ms.status != sk::VolumeStatus::Ok && ms.method != sk::StencilMethod::ZFail) __builtin_trap();

    const glm::mat4 view = (mode & 32) ? in.mat4() : glm::mat4(1.0f);
    (void)sk::near_plane_rect(view, in.f32(), in.f32(), in.f32());
    (void)sk::near_plane_rect_from_inverse(view, (mode & 64) ? sk::ClipDepth::ZeroToOne : sk::ClipDepth::NegativeOneToOne, (mode & 128) != 0);

    sk::ScissorParams sp;
    sp.view_proj = in.mat4();
    sp.clip_depth = (mode & 64) ? sk::ClipDepth::ZeroToOne : sk::ClipDepth::NegativeOneToOne;
    sp.reversed_z = (mode & 128) != 0;
    for (int& v : sp.viewport) v = in.i32();
    const glm::vec3 lmin = in.vec3(), lmax = in.vec3();
    const sk::ScissorResult s = sk::shadow_volume_scissor(L, bmin, bmax, lmin, lmax, sp);
    if (s.status == sk::VolumeStatus::Ok && s.visible) {
        const long long x0 = sp.viewport[0], y0 = sp.viewport[1];
        if (s.width <= 0 || s.height <= 0) __builtin_trap();
        if (s.x < x0 || s.y < y0 || static_cast<long long>(s.x) + s.width > x0 + sp.viewport[2] ||
            static_cast<long long>(s.y) + s.height > y0 + sp.viewport[3]) __builtin_trap();
        if (!(s.depth_min >= 0.0f && s.depth_max <= 1.0f && s.depth_min <= s.depth_max)) __builtin_trap();
    }
    const glm::vec4 x = sk::extrude_to_infinity(glm::vec4(bmin, 1.0f), L);
    if (x.w != 0.0f) __builtin_trap();
    return 0;
}
