// libFuzzer target for include/shadowkit/linear_light.hpp: light center/direction/length, receiver
// point and normal, boxes, subdivision counts, shadow-map samples for the skin and capacities
// decoded from bytes (NaN/Inf possible). Calls every public function. Invariants trap: Status::Ok
// only with finite outputs (endpoints and their difference, fractions in [0,1], intervals in
// [0,1]), NaN input never Ok, counts <= capacity and == needed when Ok, skin values 0/1, zero
// length gives 0 or 1; build_skin agrees with linear_light_skin_cell per cell; is_discontinuity is
// symmetric and matches max > min (1 + t); a skin cell has an occluder corner (nearest, value 0)
// and a receiver corner (farthest, value 1); the total functions (shade, is_discontinuity,
// skin_capacity) stay in their documented ranges.
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
    const sk::LinearLightSkinCell cell = sk::linear_light_skin_cell(glm::vec4(d[0], d[1], d[2], d[3]), thr);
    shadowkit_fuzz::check_detail(cell);
    const int nt = cell.triangle_count;
    const float* val = cell.value;
    if (nt != 0 && nt != 2) __builtin_trap();
    bool all_ok = true, all_finite = std::isfinite(thr);
    int ilo = 0, ihi = 0;
    for (int k = 0; k < 4; ++k) {
        all_ok = all_ok && d[k] > 0.f && std::isfinite(d[k]);
        all_finite = all_finite && std::isfinite(d[k]);
        if (d[k] < d[ilo]) ilo = k;
        if (d[k] > d[ihi]) ihi = k;
    }
    const sk::Status expect_status = !all_finite ? sk::Status::NonFinite
                                     : (!all_ok || !(thr >= 0.f)) ? sk::Status::InvalidArgument
                                                                  : sk::Status::Ok;
    if (cell.status != expect_status) __builtin_trap();
    if (cell.status != sk::Status::Ok && nt != 0) __builtin_trap();
    const bool expect = cell.status == sk::Status::Ok && sk::linear_light_is_discontinuity(d[ilo], d[ihi], thr);
    if ((nt == 2) != expect) __builtin_trap();
    if (nt == 2) {
        static const int cand[2][3] = {{0, 1, 3}, {0, 3, 2}};
        for (int t = 0; t < 2; ++t)
            for (int k = 0; k < 3; ++k)
                if (cell.triangles[t][k] != cand[t][k]) __builtin_trap();
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
    using St = sk::Status;
    using shadowkit_fuzz::all_finite;
    shadowkit_fuzz::FuzzInput r(data, size);
    const uint8_t mode = r.u8();
    const bool raw = (mode & 1) != 0;
    const glm::vec3 c = r.vec3(raw, 0.1f), dir = r.vec3(raw, 0.1f);
    const float len = (mode & 2) ? 0.f : r.value(raw, 0.05f);
    const sk::LinearLightSegment s = sk::linear_light_segment(c, dir, len);
    shadowkit_fuzz::check_detail(s);
    if (s.status == St::NotRun) __builtin_trap();
    if (s.status == St::Ok) {
        if (!all_finite(c) || !all_finite(dir) || !std::isfinite(len) || len < 0.f) __builtin_trap();
        if (!all_finite(s.end_a) || !all_finite(s.end_b) || !all_finite(s.end_b - s.end_a)) __builtin_trap();
        if (len == 0.f && !(s.is_point && s.end_a == s.end_b && s.end_a == c)) __builtin_trap();
        if (s.is_point != (s.end_a == s.end_b)) __builtin_trap();
    }
    const uint32_t k = r.range<uint32_t>(0, 8);
    glm::vec3 ends[9];
    const size_t cap = r.size(9);
    const sk::LinearLightSubdivideResult sd = sk::linear_light_subdivide(s, k, ends, cap);
    shadowkit_fuzz::check_detail(sd);
    if (sd.count > cap || sd.count > sd.needed) __builtin_trap();
    if (sd.status == St::Ok || sd.status == St::BufferTooSmall) {
        if (s.status != St::Ok || k == 0 || sd.needed != k + 1) __builtin_trap();
        if ((sd.status == St::Ok) != (sd.count == sd.needed)) __builtin_trap();
        for (size_t i = 0; i < sd.count; ++i)
            if (!all_finite(ends[i])) __builtin_trap();
    } else if (sd.count != 0) {
        __builtin_trap();
    }
    const size_t nb = (mode & 64) ? r.size(80) : r.size(5);
    std::vector<sk::LinearLightBox> boxes(nb);
    for (auto& b : boxes) {
        b.lo = r.vec3(raw, 0.1f);
        b.hi = (mode & 32) ? r.vec3(raw, 0.1f) : b.lo + glm::abs(r.vec3(raw, 0.05f));
    }
    for (int it = 0; it < 4; ++it) {
        const glm::vec3 p = r.vec3(raw, 0.1f), n = r.vec3(raw, 0.1f);
        const glm::vec3 a = (mode & 4) ? s.end_a : r.vec3(raw, 0.1f), b = (mode & 4) ? s.end_b : r.vec3(raw, 0.1f);
        const float mf = (mode & 8) ? r.value(raw, 0.01f) : 1e-4f;
        bool finite_in = all_finite(p) && all_finite(n) && all_finite(a) && all_finite(b) && std::isfinite(mf);
        for (const auto& bx : boxes) finite_in = finite_in && all_finite(bx.lo) && all_finite(bx.hi);
        const sk::LinearLightFraction f = sk::linear_light_visible_fraction(p, n, a, b, boxes.data(), boxes.size(), mf);
        shadowkit_fuzz::check_detail(f);
        if (f.status == St::NotRun || (!finite_in && f.status == St::Ok)) __builtin_trap();
        if (f.status == St::Ok) {
            if (!(f.fraction >= 0.f && f.fraction <= 1.f)) __builtin_trap();
            if (a == b && f.fraction != 0.f && f.fraction != 1.f) __builtin_trap();
        }
        for (const auto& bx : boxes) {
            const sk::LinearLightInterval I = sk::linear_light_box_interval(p, a, b, bx, mf);
            shadowkit_fuzz::check_detail(I);
            if (I.status == St::Ok && !I.empty() && !(I.t0 >= 0.f && I.t1 <= 1.f)) __builtin_trap();
            if (I.status == St::Ok && !(all_finite(p) && all_finite(a) && all_finite(b) && all_finite(bx.lo) &&
                                        all_finite(bx.hi) && std::isfinite(mf)))
                __builtin_trap();
            if (f.status == St::Ok && I.status != St::Ok) __builtin_trap();  // the fraction validated every box
        }
        const sk::LinearLightInterval T = sk::linear_light_tangent_interval(p, n, a, b);
        shadowkit_fuzz::check_detail(T);
        if (T.status == St::Ok && !T.empty() && !(T.t0 >= 0.f && T.t1 <= 1.f)) __builtin_trap();
        if ((T.status == St::Ok) != (all_finite(p) && all_finite(n) && all_finite(a) && all_finite(b))) __builtin_trap();
        const float v = sk::linear_light_shade(it & 1, r.value(raw, 0.01f), it & 2, r.value(raw, 0.01f));
        if (!(v >= 0.f && v <= 2.f)) __builtin_trap();  // total: [0, 2]
    }
    // skin from a small map
    const uint32_t W = r.range<uint32_t>(0, 8), H = r.range<uint32_t>(0, 8);
    std::vector<glm::vec3> pos(size_t(W) * H);
    std::vector<float> dist(size_t(W) * H);
    for (size_t i = 0; i < pos.size(); ++i) {
        pos[i] = r.vec3(raw, 0.1f);
        dist[i] = r.value(raw, 0.05f);
        if (mode & 128) dist[i] = std::fabs(dist[i]) + 0.01f;  // positive: the Ok path (no extra bytes read)
    }
    const float thr = r.value(raw, 0.01f);
    const size_t scap = (mode & 16) ? r.size(31) : sk::linear_light_skin_capacity(W, H);
    std::vector<sk::LinearLightSkinVertex> skin(scap);
    const sk::LinearLightSkinResult sr =
        sk::linear_light_build_skin(pos.data(), dist.data(), W, H, thr, skin.data(), skin.size());
    shadowkit_fuzz::check_detail(sr);
    if (sr.status == St::NotRun || sr.count > scap || sr.count > sr.needed || sr.needed % 3 != 0) __builtin_trap();
    if (sr.needed > sk::linear_light_skin_capacity(W, H)) __builtin_trap();
    if (sr.status == St::Ok && sr.count != sr.needed) __builtin_trap();
    if (sr.status != St::Ok && sr.status != St::BufferTooSmall && sr.count != 0) __builtin_trap();
    for (size_t i = 0; i < sr.count; ++i)
        if ((skin[i].value != 0.f && skin[i].value != 1.f) || !all_finite(skin[i].position)) __builtin_trap();
    // build_skin is the per-cell skin_cell over every cell; Ok only with every sample finite
    if (W >= 2 && H >= 2) {
        size_t cells = 0, v = 0;
        St expect = std::isfinite(thr) ? (thr >= 0.f ? St::Ok : St::InvalidArgument) : St::NonFinite;
        for (uint32_t j = 0; j + 1 < H && expect == St::Ok; ++j)
            for (uint32_t i = 0; i + 1 < W && expect == St::Ok; ++i) {
                const size_t q[4] = {size_t(j) * W + i, size_t(j) * W + i + 1, size_t(j + 1) * W + i, size_t(j + 1) * W + i + 1};
                if (!all_finite(pos[q[0]]) || !all_finite(pos[q[1]]) || !all_finite(pos[q[2]]) || !all_finite(pos[q[3]])) {
                    expect = St::NonFinite;
                    break;
                }
                const sk::LinearLightSkinCell cell =
                    sk::linear_light_skin_cell(glm::vec4(dist[q[0]], dist[q[1]], dist[q[2]], dist[q[3]]), thr);
                shadowkit_fuzz::check_detail(cell);
                if (cell.status != St::Ok) {
                    expect = cell.status;
                    break;
                }
                if (cell.triangle_count) ++cells;
                for (int t = 0; t < cell.triangle_count; ++t)
                    for (int e = 0; e < 3; ++e, ++v) {
                        const int corner = cell.triangles[t][e];
                        if (v < sr.count && (skin[v].value != cell.value[corner] || skin[v].position != pos[q[corner]]))
                            __builtin_trap();
                    }
            }
        if (expect == St::Ok) {
            if (sr.status != (v > scap ? St::BufferTooSmall : St::Ok)) __builtin_trap();
            if (cells != sr.cells || v != sr.needed) __builtin_trap();
        } else if (sr.status != expect) {
            __builtin_trap();
        }
    }
    skin_cell_and_discontinuity(r, raw);
    // total: saturating capacity
    const uint32_t bw = r.u32(), bh = r.u32();
    const size_t bc = sk::linear_light_skin_capacity(bw, bh);
    if (bw >= 2 && bh >= 2 && bc == 0) __builtin_trap();
    return 0;
}
