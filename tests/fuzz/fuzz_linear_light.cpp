// libFuzzer target for include/shadowkit/linear_light.hpp: light centre/direction/length, receiver
// point and normal, boxes, subdivision counts, shadow-map samples for the skin and capacities
// decoded from bytes (NaN/Inf possible). Invariants trap: fractions in [0,1], counts <= capacity,
// skin values 0/1, zero length gives 0 or 1; build_skin agrees with linear_light_skin_cell per cell;
// is_discontinuity is symmetric and matches max > min (1 + t); a skin cell has an occluder corner
// (nearest, value 0) and a receiver corner (farthest, value 1).
#include <shadowkit/linear_light.hpp>

#include "fuzz_input.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace {

// linear_light_is_discontinuity and linear_light_skin_cell against their doc comments.
void skin_cell_and_discontinuity(shadowkit_fuzz::FuzzInput& r, bool raw) {
    namespace sk = shadowkit;
    const uint8_t sel = r.u8();
    float d[4];
    for (float& x : d) x = (sel & 1) ? r.interesting_f32() : r.value(raw, 0.25f);
    const float thr = (sel & 2) ? r.interesting_f32() : r.value(raw, 1.0f / 64.0f);
    // pairwise discontinuities
    for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b) {
            const float d0 = d[a], d1 = d[b];
            const bool disc = sk::linear_light_is_discontinuity(d0, d1, thr);
            if (disc != sk::linear_light_is_discontinuity(d1, d0, thr)) __builtin_trap();  // symmetric
            const bool valid = d0 > 0.f && d1 > 0.f && std::isfinite(d0) && std::isfinite(d1) && thr >= 0.f;
            if (disc && (!valid || d0 == d1)) __builtin_trap();  // non-finite/non-positive never form one
            if (!valid || !std::isfinite(thr)) continue;
            // max > min * (1 + threshold), checked in double where the margin exceeds float rounding
            // (normal min: relative rounding error; denormals round absolutely)
            const double lo = std::min(double(d0), double(d1)), hi = std::max(double(d0), double(d1));
            const double bound = lo * (1.0 + double(thr));
            if (lo >= double(std::numeric_limits<float>::min())) {
                if (hi > bound * (1.0 + 1e-6) && !disc) __builtin_trap();
                if (hi * (1.0 + 1e-6) < bound && disc) __builtin_trap();
            }
            // a smaller threshold keeps a discontinuity
            if (disc && !sk::linear_light_is_discontinuity(d0, d1, 0.5f * thr)) __builtin_trap();
        }
    int tri[2][3] = {{-1, -1, -1}, {-1, -1, -1}};
    float val[4] = {-1.f, -1.f, -1.f, -1.f};
    const int nt = sk::linear_light_skin_cell(d, thr, tri, val);
    if (nt != 0 && nt != 2) __builtin_trap();
    bool all_ok = true;
    int ilo = 0, ihi = 0;
    for (int k = 0; k < 4; ++k) {
        all_ok = all_ok && d[k] > 0.f && std::isfinite(d[k]);
        if (d[k] < d[ilo]) ilo = k;
        if (d[k] > d[ihi]) ihi = k;
    }
    const bool expect = all_ok && sk::linear_light_is_discontinuity(d[ilo], d[ihi], thr);
    if ((nt == 2) != expect) __builtin_trap();
    if (nt == 2) {
        static const int cand[2][3] = {{0, 1, 3}, {0, 3, 2}};
        for (int t = 0; t < 2; ++t)
            for (int k = 0; k < 3; ++k)
                if (tri[t][k] != cand[t][k]) __builtin_trap();
        // nearer than the midpoint of the extremes: occluder (0); farther: receiver (1) (corners
        // within float rounding of the midpoint may go either way)
        const double mid = 0.5 * (double(d[ilo]) + double(d[ihi]));
        for (int k = 0; k < 4; ++k) {
            if (val[k] != 0.f && val[k] != 1.f) __builtin_trap();
            if (double(d[k]) < mid * (1.0 - 1e-6) && val[k] != 0.f) __builtin_trap();
            if (double(d[k]) > mid * (1.0 + 1e-6) && val[k] != 1.f) __builtin_trap();
        }
        // the nearest corner is occluder and the farthest receiver: a discontinuity cell has both
        if (val[ilo] != 0.f || val[ihi] != 1.f) __builtin_trap();
    }
}

}  // namespace

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
    // build_skin is the per-cell skin_cell over the cells with four finite positions
    if (sr.status != sk::LinearLightStatus::InvalidArgument && W >= 2 && H >= 2) {
        size_t cells = 0, v = 0;
        for (uint32_t j = 0; j + 1 < H; ++j)
            for (uint32_t i = 0; i + 1 < W; ++i) {
                const size_t q[4] = {size_t(j) * W + i, size_t(j) * W + i + 1, size_t(j + 1) * W + i, size_t(j + 1) * W + i + 1};
                if (!shadowkit_fuzz::all_finite(pos[q[0]]) || !shadowkit_fuzz::all_finite(pos[q[1]]) ||
                    !shadowkit_fuzz::all_finite(pos[q[2]]) || !shadowkit_fuzz::all_finite(pos[q[3]]))
                    continue;
                const float d[4] = {dist[q[0]], dist[q[1]], dist[q[2]], dist[q[3]]};
                int tri[2][3];
                float val[4];
                const int nt = sk::linear_light_skin_cell(d, thr, tri, val);
                if (nt) ++cells;
                for (int t = 0; t < nt; ++t)
                    for (int e = 0; e < 3; ++e, ++v)
                        if (v < sr.written && (skin[v].value != val[tri[t][e]] || skin[v].position != pos[q[tri[t][e]]]))
                            __builtin_trap();
            }
        if (cells != sr.cells || v != sr.needed) __builtin_trap();
    }
    skin_cell_and_discontinuity(r, raw);
    return 0;
}
