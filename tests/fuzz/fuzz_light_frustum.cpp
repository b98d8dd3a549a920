// libFuzzer target for shadowkit/light_frustum.hpp: matrices, light, bounds, casters from raw bytes
// (NaN/Inf, huge counts clamped by the data size); checks counts and finite output when Ok.
#include <shadowkit/light_frustum.hpp>

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
};
bool finite_mat(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}
glm::mat4 read_mat(Reader& r, int mode) {
    // mode 0: raw 16 floats; otherwise a well-formed camera from 6 floats (keeps coverage deep)
    if (mode == 0) {
        glm::mat4 m;
        for (int c = 0; c < 4; ++c)
            for (int k = 0; k < 4; ++k) m[c][k] = r.f();
        return m;
    }
    const glm::vec3 pos(r.f(), r.f(), r.f());
    const glm::vec3 fwd(r.f(), r.f(), r.f());
    if (!(glm::length(fwd) > 1e-6f) || !std::isfinite(glm::length(fwd)) || !std::isfinite(glm::length(pos))) return glm::mat4(1.0f);
    const glm::vec3 f = glm::normalize(fwd);
    return glm::lookAt(pos, pos + f, std::fabs(f.y) > 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0));
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    Reader r{data, size};
    const uint8_t flags = r.b();
    shadowkit::LightFrustumInput in;
    in.camera_view = read_mat(r, flags & 1);
    if (flags & 2) {
        for (int c = 0; c < 4; ++c)
            for (int k = 0; k < 4; ++k) in.camera_proj[c][k] = r.f();
    } else {
        const float fovy = r.f(), n = r.f(), fa = r.f();
        in.camera_proj = (flags & 64) ? glm::infinitePerspective(fovy, 1.3f, n) : glm::perspective(fovy, 1.3f, n, fa);
    }
    in.camera_depth = (flags & 4) ? shadowkit::ClipDepth::ZeroToOne : shadowkit::ClipDepth::NegativeOneToOne;
    in.camera_reversed_z = (flags & 8) != 0;
    in.max_distance = r.f();
    in.receiver_min_depth = r.f();
    in.receiver_max_depth = r.f();
    in.light = glm::vec4(r.f(), r.f(), r.f(), (flags & 16) ? r.f() : 0.0f);
    in.has_scene_bounds = (flags & 32) != 0;
    in.scene_min = glm::vec3(r.f(), r.f(), r.f());
    in.scene_max = in.scene_min + glm::vec3(std::fabs(r.f()), std::fabs(r.f()), std::fabs(r.f()));
    const uint8_t f2 = r.b();
    in.stable = (f2 & 1) != 0;
    in.shadow_map_size = static_cast<uint32_t>(r.b()) * 16u;
    in.radius_quantum = r.f();
    in.light_depth = (f2 & 2) ? shadowkit::ClipDepth::ZeroToOne : shadowkit::ClipDepth::NegativeOneToOne;
    in.light_reversed_z = (f2 & 4) != 0;
    in.point_min_near_ratio = (f2 & 8) ? r.f() : 1e-4f;
    const size_t nb = r.b() % 32, ns = r.b() % 8;
    std::vector<float> boxes(nb * 6), spheres(ns * 4);
    for (float& v : boxes) v = r.f();
    for (float& v : spheres) v = r.f();
    in.casters = nb ? boxes.data() : nullptr;
    in.caster_count = nb;
    in.caster_spheres = ns ? spheres.data() : nullptr;
    in.caster_sphere_count = ns;
    const size_t cap = r.b() % 48;
    std::vector<uint32_t> keep(cap + 1, 0xFFFFFFFFu);
    const shadowkit::LightFrustumResult res = shadowkit::fit_light_frustum(in, keep.data(), cap);
    if (keep[cap] != 0xFFFFFFFFu) __builtin_trap();  // wrote past capacity
    if (res.status == shadowkit::LightFrustumStatus::Ok || res.status == shadowkit::LightFrustumStatus::BufferTooSmall) {
        if (!finite_mat(res.view_proj) || !finite_mat(res.view) || !finite_mat(res.proj)) __builtin_trap();
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
            if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z)) {
                // float overflow of a finite double corner is the only way here: allowed only for huge input
                if (std::fabs(in.max_distance) < 1e30f) __builtin_trap();
            }
    }
    return 0;
}
