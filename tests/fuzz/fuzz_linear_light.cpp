// libFuzzer target for include/shadowkit/linear_light.hpp: light centre/direction/length, receiver
// point and normal, boxes, subdivision counts, shadow-map samples for the skin and capacities
// decoded from bytes (NaN/Inf possible). Invariants trap: fractions in [0,1], counts <= capacity,
// skin values 0/1, zero length gives 0 or 1.
#include <shadowkit/linear_light.hpp>

#include "fuzz_input.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    namespace sk = shadowkit;
    shadowkit_fuzz::FuzzInput r(data, size);
    const uint8_t mode = r.u8();
    const bool raw = (mode & 1) != 0;
    const glm::vec3 c = r.vec3(raw, 0.1f), dir = r.vec3(raw, 0.1f);
    const float len = (mode & 2) ? 0.f : r.value(raw, 0.05f);
    const sk::LinearLightSegment s = sk::linear_light_segment(c, dir, len);
    if (s.status == sk::LinearLightStatus::Ok && len == 0.f && !(s.point && s.a == s.b)) __builtin_trap();
    const uint32_t k = r.range<uint32_t>(0, 8);
    glm::vec3 ends[9];
    const size_t cap = r.size(9);
    const size_t need = sk::linear_light_subdivide(s, k, ends, cap);
    if (s.status == sk::LinearLightStatus::Ok && k > 0 && need != k + 1) __builtin_trap();
    const size_t nb = r.size(5);
    std::vector<sk::LinearLightBox> boxes(nb);
    for (auto& b : boxes) {
        b.lo = r.vec3(raw, 0.1f);
        b.hi = b.lo + glm::abs(r.vec3(raw, 0.05f));
    }
    for (int it = 0; it < 4; ++it) {
        const glm::vec3 p = r.vec3(raw, 0.1f), n = r.vec3(raw, 0.1f);
        const glm::vec3 a = (mode & 4) ? s.a : r.vec3(raw, 0.1f), b = (mode & 4) ? s.b : r.vec3(raw, 0.1f);
        const float mf = (mode & 8) ? r.value(raw, 0.01f) : 1e-4f;
        const sk::LinearLightFraction f = sk::linear_light_visible_fraction(p, n, a, b, boxes.data(), boxes.size(), mf);
        if (f.status == sk::LinearLightStatus::Ok) {
            if (!(f.fraction >= 0.f && f.fraction <= 1.f)) __builtin_trap();
            if (a == b && f.fraction != 0.f && f.fraction != 1.f) __builtin_trap();
        }
        for (const auto& bx : boxes) {
            const sk::LinearLightInterval I = sk::linear_light_box_interval(p, a, b, bx, mf);
            if (!I.empty() && !(I.t0 >= 0.f && I.t1 <= 1.f)) __builtin_trap();
        }
        const sk::LinearLightInterval T = sk::linear_light_tangent_interval(p, n, a, b);
        if (!T.empty() && !(T.t0 >= 0.f && T.t1 <= 1.f)) __builtin_trap();
        const float v = sk::linear_light_shade(it & 1, r.value(raw, 0.01f), it & 2, r.value(raw, 0.01f));
        if (!(v >= 0.f && v <= 2.f)) __builtin_trap();
    }
    // skin from a small map
    const uint32_t W = r.range<uint32_t>(0, 8), H = r.range<uint32_t>(0, 8);
    std::vector<glm::vec3> pos(size_t(W) * H);
    std::vector<float> dist(size_t(W) * H);
    for (size_t i = 0; i < pos.size(); ++i) {
        pos[i] = r.vec3(raw, 0.1f);
        dist[i] = r.value(raw, 0.05f);
    }
    const float thr = r.value(raw, 0.01f);
    const size_t scap = (mode & 16) ? r.size(31) : sk::linear_light_skin_capacity(W, H);
    std::vector<sk::LinearLightSkinVertex> skin(scap);
    const sk::LinearLightSkinResult sr =
        sk::linear_light_build_skin(pos.data(), dist.data(), W, H, thr, skin.data(), skin.size());
    if (sr.written > scap || sr.written > sr.needed || sr.needed % 3 != 0) __builtin_trap();
    if (sr.needed > sk::linear_light_skin_capacity(W, H)) __builtin_trap();
    for (size_t i = 0; i < sr.written; ++i)
        if (skin[i].value != 0.f && skin[i].value != 1.f) __builtin_trap();
    return 0;
}
