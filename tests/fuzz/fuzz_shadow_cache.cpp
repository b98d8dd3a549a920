// libFuzzer target for shadowkit/shadow_cache.hpp: shadow_cache_plan and shadow_cache_footprint on
// map states, casters and capacities decoded from raw bytes (raw doubles with NaN/Inf and huge values,
// or stable-fit-like matrices moved by integer / fractional texels so the scroll path is reached).
// Traps on: Ok with a non-finite output, count > capacity, count != needed with Ok, a rectangle or a
// copy region outside the map, texels that are not the rectangles' area, two rectangles that overlap,
// a moved caster's footprint an Update leaves uncovered, an action whose outputs
// contradict it (Keep with rectangles, Render without the whole map, offsets without Scroll).
#include <shadowkit/shadow_cache.hpp>

#include "fuzz_input.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>

using shadowkit_fuzz::FuzzInput;
using shadowkit_fuzz::check;
using shadowkit_fuzz::check_detail;

namespace {

// A matrix: raw doubles, or an orthographic stable-fit-like matrix (raw direction, texel size,
// anchor) optionally turned into a perspective one.
glm::dmat4 decode_matrix(FuzzInput& r, int w, int h, double shift_x, double shift_y, const glm::dmat4* base) {
    const std::uint8_t mode = r.u8() % 4;
    if (mode == 0) {
        glm::dmat4 m;
        for (int c = 0; c < 4; ++c)
            for (int k = 0; k < 4; ++k) m[c][k] = r.f64();
        return m;
    }
    if (base != nullptr && mode != 3) {  // last frame's matrix moved in NDC x/y (and maybe depth)
        glm::dmat4 m = *base;
        m[3][0] += 2.0 * shift_x / double(w > 0 ? w : 1);
        m[3][1] += 2.0 * shift_y / double(h > 0 ? h : 1);
        if (mode == 2) m[3][2] += double(r.mostly_within(1.0f));
        return m;
    }
    const glm::dvec3 d(r.mostly_within(2.0f), r.mostly_within(2.0f), r.mostly_within(2.0f));
    const double t = std::fabs(double(r.mostly_within(4.0f))) + 1e-6;
    const double ax = double(r.i32()), ay = double(r.i32());
    glm::dmat4 m(0.0);
    const double len = glm::length(d);
    const glm::dvec3 dn = len > 0.0 && std::isfinite(len) ? d / len : glm::dvec3(0, 0, -1);
    const glm::dvec3 up = std::fabs(dn.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
    const glm::dvec3 sx = glm::normalize(glm::cross(up, dn)), sy = glm::cross(dn, sx);
    const double kx = 2.0 / (double(w > 0 ? w : 1) * t), ky = 2.0 / (double(h > 0 ? h : 1) * t);
    for (int c = 0; c < 3; ++c) {
        m[c][0] = kx * sx[c];
        m[c][1] = ky * sy[c];
        m[c][2] = 0.01 * dn[c];
    }
    m[3][0] = -2.0 * ax / double(w > 0 ? w : 1) - 1.0;
    m[3][1] = -2.0 * ay / double(h > 0 ? h : 1) - 1.0;
    m[3][3] = 1.0;
    if (mode == 3 && (r.u8() & 1)) {  // perspective: w row from z
        m[0][3] = -dn.x;
        m[1][3] = -dn.y;
        m[2][3] = -dn.z;
        m[3][3] = double(r.mostly_within(10.0f));
    }
    return m;
}

void decode_box(FuzzInput& r, bool raw, float* b) {
    for (int i = 0; i < 6; ++i) b[i] = raw ? r.f32() : r.quantized(0.25f);
}

std::int64_t intersection(const shadowkit::ShadowCacheRect& a, const shadowkit::ShadowCacheRect& b) {
    const std::int64_t x0 = a.x > b.x ? a.x : b.x, y0 = a.y > b.y ? a.y : b.y;
    const std::int64_t x1 = std::int64_t(a.x) + a.width < std::int64_t(b.x) + b.width ? std::int64_t(a.x) + a.width : std::int64_t(b.x) + b.width;
    const std::int64_t y1 = std::int64_t(a.y) + a.height < std::int64_t(b.y) + b.height ? std::int64_t(a.y) + a.height : std::int64_t(b.y) + b.height;
    return x1 > x0 && y1 > y0 ? (x1 - x0) * (y1 - y0) : 0;
}

bool overlap(const shadowkit::ShadowCacheRect& a, const shadowkit::ShadowCacheRect& b) { return intersection(a, b) > 0; }

// q lies inside the union of disjoint rectangles: the areas of its intersections add up to its own.
bool covered(const shadowkit::ShadowCacheRect& q, const shadowkit::ShadowCacheRect* rects, std::size_t count) {
    std::int64_t sum = 0;
    for (std::size_t i = 0; i < count; ++i) sum += intersection(q, rects[i]);
    return sum == std::int64_t(q.width) * q.height;
}

bool inside(const shadowkit::ShadowCacheRect& q, int w, int h) {
    return q.width > 0 && q.height > 0 && q.x >= 0 && q.y >= 0 && q.x <= w - q.width && q.y <= h - q.height;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    FuzzInput r(data, size);
    const std::uint8_t flags = r.u8();
    shadowkit::ShadowCacheMapState prev, cur;
    const bool small = (flags & 1) != 0;
    cur.width = small ? r.range<int>(-1, 40) : r.range<int>(-2, 70000);
    cur.height = (flags & 2) ? cur.width : (small ? r.range<int>(-1, 40) : r.range<int>(-2, 70000));
    prev.width = (flags & 4) ? r.range<int>(-1, 40) : cur.width;
    prev.height = (flags & 4) ? r.range<int>(-1, 40) : cur.height;
    prev.has_content = (flags & 8) != 0;
    prev.settings = r.u8() & 3;
    cur.settings = (flags & 16) ? r.u8() & 3 : prev.settings;
    prev.float_matrices = (flags & 32) != 0;
    cur.float_matrices = (flags & 64) != 0;
    prev.view_proj = decode_matrix(r, prev.width, prev.height, 0.0, 0.0, nullptr);
    // this frame: a whole-texel shift (most often), a fraction, or a fresh matrix
    const double sx = (r.u8() & 1) ? double(r.range<int>(-80, 80)) : double(r.mostly_within(100.0f));
    const double sy = (r.u8() & 1) ? double(r.range<int>(-80, 80)) : double(r.mostly_within(100.0f));
    cur.view_proj = decode_matrix(r, cur.width, cur.height, sx, sy, &prev.view_proj);

    shadowkit::ShadowCacheCaster casters[24];
    const std::size_t caster_count = r.range<std::size_t>(0, 24);
    const bool raw_boxes = (flags & 128) != 0;
    for (std::size_t i = 0; i < caster_count; ++i) {
        decode_box(r, raw_boxes, casters[i].previous_bounds);
        if (r.u8() & 1) {
            for (int k = 0; k < 6; ++k) casters[i].bounds[k] = casters[i].previous_bounds[k];
        } else {
            decode_box(r, raw_boxes, casters[i].bounds);
        }
    }
    shadowkit::ShadowCacheRect rects[16];
    const std::size_t cap = r.range<std::size_t>(0, 16);
    const bool null_casters = (r.u8() % 16) == 0;
    const shadowkit::ShadowCachePlan p = shadowkit::shadow_cache_plan(
        prev, cur, null_casters ? nullptr : casters, caster_count, cap == 0 && (flags & 2) ? nullptr : rects, cap);
    check(p.count <= cap);
    check_detail(p);
    if (p.status == shadowkit::Status::Ok) {
        const int w = cur.width, h = cur.height;
        check(w >= 1 && h >= 1);
        check(p.count == p.needed);
        check(std::isfinite(p.residual_texels) && std::isfinite(p.tolerance_texels));
        check(p.residual_texels >= 0.0 && p.tolerance_texels >= 0.0);
        std::uint64_t area = 0;
        for (std::size_t i = 0; i < p.count; ++i) {
            check(inside(rects[i], w, h));
            area += std::uint64_t(rects[i].width) * std::uint64_t(rects[i].height);
        }
        check(area == p.texels);
        // the rectangles are pairwise disjoint (no texel re-rendered twice; texels = their union's area)
        for (std::size_t i = 0; i < p.count; ++i)
            for (std::size_t j = i + 1; j < p.count; ++j) check(!overlap(rects[i], rects[j]));
        // Update: every moved caster's old and new footprint is covered (contained in the union)
        if (p.action == shadowkit::ShadowCacheAction::Update && !null_casters)
            for (std::size_t i = 0; i < caster_count; ++i)
                for (const float* b : {casters[i].previous_bounds, casters[i].bounds}) {
                    bool same = true;
                    for (int k = 0; k < 6; ++k) same = same && casters[i].bounds[k] == casters[i].previous_bounds[k];
                    if (same) continue;
                    const shadowkit::ShadowCacheFootprint fp = shadowkit::shadow_cache_footprint(cur.view_proj, w, h, b);
                    if (fp.status == shadowkit::Status::Ok && fp.visible) check(covered(fp.rect, rects, p.count));
                }
        const std::uint64_t map = std::uint64_t(w) * std::uint64_t(h);
        switch (p.action) {
        case shadowkit::ShadowCacheAction::Keep:
            check(p.count == 0 && p.reason == shadowkit::ShadowCacheReason::None);
            check(p.offset_x == 0 && p.offset_y == 0);
            break;
        case shadowkit::ShadowCacheAction::Update:
            check(p.count >= 1 && p.texels < map && p.offset_x == 0 && p.offset_y == 0);
            break;
        case shadowkit::ShadowCacheAction::Scroll: {
            check(p.offset_x != 0 || p.offset_y != 0);
            check(p.offset_x > -w && p.offset_x < w && p.offset_y > -h && p.offset_y < h);
            check(p.count >= 1 && p.texels < map);
            const shadowkit::ShadowCacheCopy& c = p.copy;
            check(c.width >= 1 && c.height >= 1);
            check(c.dst_x - c.src_x == p.offset_x && c.dst_y - c.src_y == p.offset_y);
            check(inside(shadowkit::ShadowCacheRect{c.src_x, c.src_y, c.width, c.height}, w, h));
            check(inside(shadowkit::ShadowCacheRect{c.dst_x, c.dst_y, c.width, c.height}, w, h));
            check(p.residual_texels <= p.tolerance_texels && p.tolerance_texels <= shadowkit::kShadowCacheMaxResidualTexels);
            break;
        }
        case shadowkit::ShadowCacheAction::Render:
            check(p.count == 1 && p.texels == map && p.reason != shadowkit::ShadowCacheReason::None);
            check(rects[0].x == 0 && rects[0].y == 0 && rects[0].width == w && rects[0].height == h);
            break;
        }
    } else if (p.status == shadowkit::Status::BufferTooSmall) {
        check(cap == 0 && p.needed == 1 && p.count == 0);
    } else {
        check(p.count == 0);
    }

    // footprints of the decoded boxes on this frame's map
    for (std::size_t i = 0; i < caster_count; ++i) {
        const shadowkit::ShadowCacheFootprint fp = shadowkit::shadow_cache_footprint(
            cur.view_proj, cur.width, cur.height, (r.u8() % 32) == 0 ? nullptr : casters[i].bounds);
        if (fp.status == shadowkit::Status::Ok && fp.visible) check(inside(fp.rect, cur.width, cur.height));
        if (fp.status != shadowkit::Status::Ok) check(!fp.visible);
        check_detail(fp);
    }
    check(shadowkit::shadow_cache_rect_capacity(caster_count) == 2 + 2 * caster_count);
    return 0;
}
