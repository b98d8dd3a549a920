// libFuzzer target for shadowkit/shadow_volume.hpp: arbitrary positions, edges, triangles, lit flags,
// capacities, lights, bounds, matrices and viewports. Invariants trap on violation.
#include <shadowkit/shadow_volume.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

namespace {
struct Reader {
    const std::uint8_t* p;
    std::size_t n;
    float f() {
        float v = 0.0f;
        if (n >= 4) { std::memcpy(&v, p, 4); p += 4; n -= 4; }
        return v;
    }
    std::uint32_t u() {
        std::uint32_t v = 0;
        if (n >= 4) { std::memcpy(&v, p, 4); p += 4; n -= 4; }
        return v;
    }
    std::uint8_t b() {
        if (!n) return 0;
        --n;
        return *p++;
    }
    glm::vec3 v3() { return glm::vec3(f(), f(), f()); }
};
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    namespace sk = shadowkit;
    Reader in{data, size};
    const std::uint8_t mode = in.b();
    const std::size_t nv = in.b() % 32, ne = in.b() % 40, nt = in.b() % 40, cap = in.b();
    std::vector<glm::vec3> pos(nv);
    for (auto& v : pos) v = in.v3();
    std::vector<std::uint32_t> edges(2 * ne), tris(3 * nt);
    for (auto& e : edges) e = (mode & 1) ? in.u() : static_cast<std::uint32_t>(in.b() % (nv + 1));
    for (auto& t : tris) t = (mode & 1) ? in.u() : static_cast<std::uint32_t>(in.b() % (nv + 1));
    std::vector<std::uint8_t> lit(nt);
    for (auto& l : lit) l = in.b();

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

    const glm::vec4 L(in.f(), in.f(), in.f(), (mode & 8) ? 0.0f : in.f());
    sk::NearPlaneRect rect;
    for (auto& c : rect.corners) c = in.v3();
    const glm::vec3 bmin = in.v3(), bmax = in.v3();
    const float margin = (mode & 16) ? in.f() : 0.0f;
    const sk::MethodResult mb = sk::choose_stencil_method_box(rect, L, bmin, bmax, margin);
    if (mb.status != sk::VolumeStatus::Ok && mb.method != sk::StencilMethod::ZFail) __builtin_trap();
    const sk::MethodResult ms = sk::choose_stencil_method_sphere(rect, L, bmin, in.f(), margin);
    if (ms.status != sk::VolumeStatus::Ok && ms.method != sk::StencilMethod::ZFail) __builtin_trap();

    glm::mat4 view(1.0f);
    for (int c = 0; c < 4; ++c)
        for (int k = 0; k < 4; ++k) view[c][k] = (mode & 32) ? in.f() : view[c][k];
    (void)sk::near_plane_rect(view, in.f(), in.f(), in.f());
    (void)sk::near_plane_rect_from_inverse(view, (mode & 64) ? sk::ClipDepth::ZeroToOne : sk::ClipDepth::NegativeOneToOne, (mode & 128) != 0);

    sk::ScissorParams sp;
    for (int c = 0; c < 4; ++c)
        for (int k = 0; k < 4; ++k) sp.view_proj[c][k] = in.f();
    sp.clip_depth = (mode & 64) ? sk::ClipDepth::ZeroToOne : sk::ClipDepth::NegativeOneToOne;
    sp.reversed_z = (mode & 128) != 0;
    for (int& v : sp.viewport) v = static_cast<int>(in.u());
    const glm::vec3 lmin = in.v3(), lmax = in.v3();
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
