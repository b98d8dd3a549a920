// libFuzzer target for shadowkit/perspective_shadow_maps.hpp: every method and the aliasing metric
// on inputs decoded from raw bytes; Ok results must be finite, errors finite too.
#include <shadowkit/perspective_shadow_maps.hpp>

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
bool finite_mat(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    Reader r{data, size};
    const uint8_t flags = r.b();
    shadowkit::WarpInput in;
    if (flags & 1) {
        for (int c = 0; c < 4; ++c)
            for (int k = 0; k < 4; ++k) in.camera_view[c][k] = r.f();
    } else {
        const glm::vec3 pos(r.f(), r.f(), r.f()), fwd(r.f(), r.f(), r.f());
        const float l = glm::length(fwd);
        if (l > 1e-6f && std::isfinite(l) && std::isfinite(glm::length(pos))) {
            const glm::vec3 f = fwd / l;
            in.camera_view = glm::lookAt(pos, pos + f, std::fabs(f.y) > 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0));
        }
    }
    if (flags & 2) {
        for (int c = 0; c < 4; ++c)
            for (int k = 0; k < 4; ++k) in.camera_proj[c][k] = r.f();
    } else {
        const float fovy = r.f(), n = r.f(), fa = r.f();
        in.camera_proj = (flags & 64) ? glm::infinitePerspective(fovy, 1.7f, n) : glm::perspective(fovy, 1.7f, n, fa);
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
    in.has_caster_bounds = (f2 & 1) != 0;
    in.caster_min = glm::vec3(r.f(), r.f(), r.f());
    in.caster_max = glm::vec3(r.f(), r.f(), r.f());
    in.light_depth = (f2 & 2) ? shadowkit::ClipDepth::ZeroToOne : shadowkit::ClipDepth::NegativeOneToOne;
    in.light_reversed_z = (f2 & 4) != 0;
    if (f2 & 8) {
        in.options.lispsm_n_scale = r.f();
        in.options.lispsm_min_sin_gamma = r.f();
        in.options.tsm_max_abs_cos_gamma = r.f();
        in.options.tsm_focus_depth = r.f();
        in.options.tsm_focus_ratio = r.f();
        in.options.psm_min_near_fraction = r.f();
        in.options.psm_slide_back = r.f();
        in.options.psm_max_half_angle_deg = r.f();
    }
    using Fn = shadowkit::WarpResult (*)(const shadowkit::WarpInput&);
    const Fn fns[4] = {shadowkit::uniform_shadow_matrix, shadowkit::psm_shadow_matrix, shadowkit::lispsm_shadow_matrix,
                       shadowkit::tsm_shadow_matrix};
    for (Fn fn : fns) {
        const shadowkit::WarpResult w = fn(in);
        if (!finite_mat(w.light_view_proj)) __builtin_trap();
        if (w.status != shadowkit::WarpStatus::Ok && w.fallback_uniform) __builtin_trap();
        if (!std::isfinite(w.sin_gamma) || !std::isfinite(w.warp_parameter)) __builtin_trap();
    }
    if (f2 & 16) {
        const shadowkit::WarpResult w = shadowkit::lispsm_shadow_matrix(in);
        const shadowkit::AliasingStats a =
            shadowkit::measure_perspective_aliasing(in, w.light_view_proj, r.b() * 8u, {r.b() * 4u, r.b() * 4u}, r.b() % 8u, r.b() % 8u, r.b() % 8u);
        if (std::isnan(a.max_error) || std::isnan(a.mean_error) || a.undersampled_fraction < 0.0 || a.undersampled_fraction > 1.0) __builtin_trap();
        const double e = shadowkit::perspective_aliasing_error(w.light_view_proj, in.camera_proj * in.camera_view,
                                                               glm::vec3(r.f(), r.f(), r.f()), glm::vec3(r.f(), r.f(), r.f()),
                                                               1024, {640, 480});
        if (std::isnan(e) || e < 0.0) __builtin_trap();
    }
    return 0;
}
