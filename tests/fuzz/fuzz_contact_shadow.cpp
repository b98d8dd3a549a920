// libFuzzer target for include/shadowkit/contact_shadow.hpp: contact_shadow_derive,
// contact_shadow_march and contact_shadow_march_aligned (the same status, the same invariants but the
// step count, which derive describes for contact_shadow_march only) with a fuzzer-chosen depth buffer (raw floats: NaN, Inf, outside [0, 1]),
// sizes and capacities (the buffer is never smaller than the capacity claimed), projections (a
// GL/zero-to-one, reversed, infinite or raw matrix), receivers, lights and params (raw bits or
// mostly-sane values, invalid enums). Invariants trap on violation: no result says NotRun; Ok only
// with visibility exactly 0 or 1, hit == (visibility == 0), finite distances within the march
// length, steps in [0, max_steps]; non-Ok with visibility 1 and no hit; the buffer is never read
// beyond its capacity (ASan) and BufferTooSmall says `needed` = width * height.
#include <shadowkit/contact_shadow.hpp>

#include "fuzz_input.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

using shadowkit_fuzz::check;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace shadowkit;
    shadowkit_fuzz::FuzzInput r(data, size);
    const bool raw = r.boolean();
    const int width = r.range(-2, 40), height = r.range(-2, 40);
    const std::size_t cells = width > 0 && height > 0 ? std::size_t(width) * std::size_t(height) : 0;
    const std::size_t capacity = r.boolean() ? cells : r.size(cells + 4);
    std::vector<float> depth(capacity);
    const int fill = r.range(0, 3);
    for (std::size_t k = 0; k < capacity; ++k) {
        switch (fill) {
        case 0: depth[k] = r.f32(); break;                                      // raw bits
        case 1: depth[k] = float(r.u16()) / 65535.0f; break;                    // [0, 1]
        case 2: depth[k] = 1.0f - float(r.u8()) / 4096.0f; break;               // near the far plane
        default: depth[k] = (k % 7 == 0) ? r.interesting_f32() : 0.5f; break;
        }
    }
    const bool null_depth = r.range(0, 15) == 0;

    glm::mat4 proj;
    const int pk = r.range(0, 3);
    if (pk == 0) {
        proj = r.mat4();
    } else {
        const float fovy = raw ? r.f32() : 0.2f + float(r.u8()) / 100.0f;
        const float n = raw ? r.f32() : std::ldexp(1.0f, -int(r.range(0, 20)));
        const float aspect = width > 0 && height > 0 ? float(width) / float(height) : 1.0f;
        proj = pk == 1 ? glm::infinitePerspective(fovy, aspect, n) : glm::perspective(fovy, aspect, n, n * (1.0f + float(r.u16())));
        if (pk == 3) proj = glm::ortho(-1.0f, 1.0f, -1.0f, 1.0f, n, 10.0f);
    }
    ContactShadowParams p;
    p.length_world = raw ? r.f32() : r.mostly_within(4.0f);
    p.max_steps = r.range(-1, 300);
    p.thickness_world = raw ? r.f32() : (r.boolean() ? 0.0f : r.interesting_f32());
    p.jitter = raw ? r.f32() : float(r.u8()) / 256.0f;
    p.depth_format = static_cast<DepthFormat>(r.range(0, 3));
    p.clip_depth = static_cast<ClipDepth>(r.range(0, 2));
    p.reversed_z = r.boolean();
    const glm::vec3 vp = raw ? r.vec3() : glm::vec3(r.quantized(0.01f), r.quantized(0.01f), -std::fabs(r.quantized(0.05f)) - 0.001f);
    const glm::vec4 light = raw ? r.vec4() : glm::vec4(r.quantized(0.1f), r.quantized(0.1f), r.quantized(0.1f), float(r.range(0, 2)) * 0.5f);

    const ContactShadowDerived d = contact_shadow_derive(width, height, proj, vp, light, p);
    check(d.status != Status::NotRun);
    shadowkit_fuzz::check_detail(d);
    if (d.status == Status::Ok) {
        check(d.steps >= 0 && d.steps <= p.max_steps && d.steps <= kContactShadowMaxSteps);
        check(std::isfinite(d.projected_pixels) && d.projected_pixels >= 0.0f);
        check(std::isfinite(d.march_length_world) && d.march_length_world >= 0.0f && d.march_length_world <= p.length_world);
        check(std::isfinite(d.bias_world) && d.bias_world >= 0.0f);
        check(d.thickness_world > 0.0f && !std::isnan(d.thickness_world));
        check(std::isfinite(d.depth_step_window) && d.depth_step_window >= 0.0f);
    }
    const ContactShadowResult m = contact_shadow_march(null_depth ? nullptr : depth.data(), capacity, width, height, proj, vp, light, p);
    check(m.status != Status::NotRun);
    shadowkit_fuzz::check_detail(m);
    if (m.status == Status::Ok) {
        check(m.visibility == 0.0f || m.visibility == 1.0f);
        check(m.hit == (m.visibility == 0.0f));
        check(std::isfinite(m.hit_distance_world) && m.hit_distance_world >= 0.0f);
        check(m.steps >= 0 && m.steps <= p.max_steps);
        check(m.needed == cells && capacity >= cells);
        check(d.status == Status::Ok && d.steps == m.steps);
        check(m.hit_distance_world <= d.march_length_world * 1.0001f + 1e-30f);
    } else {
        check(m.visibility == 1.0f && !m.hit);
        if (m.status == Status::BufferTooSmall) check(m.needed == cells && capacity < cells);
    }
    const ContactShadowResult a =
        contact_shadow_march_aligned(null_depth ? nullptr : depth.data(), capacity, width, height, proj, vp, light, p);
    check(a.status == m.status);
    shadowkit_fuzz::check_detail(a);
    if (a.status == Status::Ok) {
        check(a.visibility == 0.0f || a.visibility == 1.0f);
        check(a.hit == (a.visibility == 0.0f));
        check(std::isfinite(a.hit_distance_world) && a.hit_distance_world >= 0.0f);
        check(a.hit_distance_world <= p.length_world * 1.001f);
        check(a.steps >= 0 && a.steps <= p.max_steps);
        check(a.needed == cells);
    } else {
        check(a.visibility == 1.0f && !a.hit);
    }
    return 0;
}
