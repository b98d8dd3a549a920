// libFuzzer target for shadowkit/cascades.hpp: split distances, fits, selection and blend weights on
// inputs decoded from raw bytes; checks monotonic splits, exact ends and finite matrices when Ok.
#include <shadowkit/cascades.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

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
};
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    Reader r{data, size};
    const uint8_t flags = r.b();
    // split distances
    const float n = r.f(), f = r.f(), lambda = r.f();
    const uint32_t count = r.b() % 20u;
    float s[21];
    if (shadowkit::cascade_split_distances(n, f, lambda, count, s) == shadowkit::CascadeStatus::Ok) {
        if (count == 0 || count > 16) __builtin_trap();
        if (s[0] != n || s[count] != f) __builtin_trap();
        for (uint32_t i = 0; i < count; ++i)
            if (!(s[i] < s[i + 1])) __builtin_trap();
        const int sel = shadowkit::select_cascade_by_depth(r.f(), s, count);
        if (sel < -1 || sel >= int(count)) __builtin_trap();
    }
    // fits
    shadowkit::CascadeInput in;
    if (flags & 1) {
        for (int c = 0; c < 4; ++c)
            for (int k = 0; k < 4; ++k) in.camera_view[c][k] = r.f();
    } else {
        const glm::vec3 pos(r.f(), r.f(), r.f()), fwd(r.f(), r.f(), r.f());
        const float l = glm::length(fwd);
        if (l > 1e-6f && std::isfinite(l) && std::isfinite(glm::length(pos))) {
            const glm::vec3 fw = fwd / l;
            in.camera_view = glm::lookAt(pos, pos + fw, std::fabs(fw.y) > 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0));
        }
    }
    if (flags & 2) {
        for (int c = 0; c < 4; ++c)
            for (int k = 0; k < 4; ++k) in.camera_proj[c][k] = r.f();
    } else {
        const float fovy = r.f(), cn = r.f(), cf = r.f();
        in.camera_proj = (flags & 4) ? glm::infinitePerspective(fovy, 1.5f, cn) : glm::perspective(fovy, 1.5f, cn, cf);
    }
    in.camera_reversed_z = (flags & 8) != 0;
    in.camera_depth = (flags & 16) ? shadowkit::ClipDepth::ZeroToOne : shadowkit::ClipDepth::NegativeOneToOne;
    in.max_distance = r.f();
    in.light_dir = glm::vec3(r.f(), r.f(), r.f());
    in.shadow_map_size = uint32_t(r.b()) * 32u;
    in.radius_quantum = (flags & 32) ? r.f() : 1.0f / 16.0f;
    in.has_caster_bounds = (flags & 64) != 0;
    in.caster_min = glm::vec3(r.f(), r.f(), r.f());
    in.caster_max = glm::vec3(r.f(), r.f(), r.f());
    in.light_depth = (flags & 128) ? shadowkit::ClipDepth::ZeroToOne : shadowkit::ClipDepth::NegativeOneToOne;
    shadowkit::Cascade c[16];
    float splits[17];
    const uint32_t cc = 1u + r.b() % 16u;
    if (shadowkit::fit_cascades(in, r.f(), cc, c, splits) == shadowkit::CascadeStatus::Ok) {
        for (uint32_t i = 0; i < cc; ++i) {
            for (int a = 0; a < 4; ++a)
                for (int k = 0; k < 4; ++k)
                    if (!std::isfinite(c[i].view_proj[a][k])) __builtin_trap();
            if (!(splits[i] < splits[i + 1])) __builtin_trap();
            if (!(c[i].sphere.w > 0.0f) || !(c[i].texel_world_size > 0.0f)) __builtin_trap();
        }
        const int sel = shadowkit::select_cascade_by_sphere(glm::vec3(r.f(), r.f(), r.f()), c, cc);
        if (sel < -1 || sel >= int(cc)) __builtin_trap();
    }
    const float w = shadowkit::cascade_blend_weight(r.f(), r.f(), r.f(), r.f());
    if (!(w >= 0.0f && w <= 1.0f)) __builtin_trap();
    return 0;
}
