// Unit and property tests for shadowkit/shadow_cache.hpp.
// References: closed forms (offsets, exposed border areas, copy regions), a brute-force CPU depth-map
// renderer (ray per texel center against boxes) that is a function of the global texel index, so a
// map scrolled by whole texels is bit-identical to a re-render exactly where the plan is right: the
// cached map updated with the plan must equal the full re-render texel for texel, every frame.
#include <shadowkit/shadow_cache.hpp>

#include <doctest/doctest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

using namespace shadowkit;

namespace {

// ------------------------------------------------------------------ a stable orthographic fit
// The light frame is anchored at the world origin (rotation only); the map's texel (0, 0) is global
// texel (kx, ky); depth s = dot(d, p) is mapped from the world-fixed range [s0, s1] to NDC [-1, 1].
struct Fit {
    glm::dvec3 sx{1, 0, 0}, sy{0, 1, 0}, d{0, 0, -1};
    double t = 0.25;            // texel size, world units
    long long kx = 0, ky = 0;   // global texel index of the map's texel (0, 0)
    double s0 = -50, s1 = 50;   // depth range along d
    int w = 24, h = 24;
};

void basis(const glm::dvec3& dir, Fit& f) {
    f.d = glm::normalize(dir);
    const glm::dvec3 up = std::fabs(f.d.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
    f.sx = glm::normalize(glm::cross(up, f.d));
    f.sy = glm::cross(f.d, f.sx);
}

glm::dmat4 fit_matrix(const Fit& f) {
    glm::dmat4 m(0.0);
    const double ax = 2.0 / (double(f.w) * f.t), ay = 2.0 / (double(f.h) * f.t), az = 2.0 / (f.s1 - f.s0);
    for (int c = 0; c < 3; ++c) {
        m[c][0] = ax * f.sx[c];
        m[c][1] = ay * f.sy[c];
        m[c][2] = az * f.d[c];
    }
    m[3][0] = -2.0 * double(f.kx) / double(f.w) - 1.0;
    m[3][1] = -2.0 * double(f.ky) / double(f.h) - 1.0;
    m[3][2] = -az * f.s0 - 1.0;
    m[3][3] = 1.0;
    return m;
}

// The stable fit of a camera at c: the map centered (to whole texels) on c, depth range snapped to
// multiples of q along d (so it moves only when the camera crosses a multiple of q).
void fit_camera(Fit& f, const glm::dvec3& c, double q, double depth) {
    f.kx = static_cast<long long>(std::floor(glm::dot(f.sx, c) / f.t)) - f.w / 2;
    f.ky = static_cast<long long>(std::floor(glm::dot(f.sy, c) / f.t)) - f.h / 2;
    f.s0 = std::floor(glm::dot(f.d, c) / q) * q - 0.5 * depth;
    f.s1 = f.s0 + depth;
}

struct Box {
    float b[6];
};

// Ray p(s) = o + s * dir against a box: the entry parameter, +inf when missed.
double ray_box(const glm::dvec3& o, const glm::dvec3& dir, const float* b) {
    if (b[0] > b[3] || b[1] > b[4] || b[2] > b[5]) return std::numeric_limits<double>::infinity();
    double s_in = -std::numeric_limits<double>::infinity(), s_out = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
        const double lo = b[a], hi = b[a + 3];
        if (dir[a] == 0.0) {
            if (o[a] < lo || o[a] > hi) return std::numeric_limits<double>::infinity();
            continue;
        }
        double t0 = (lo - o[a]) / dir[a], t1 = (hi - o[a]) / dir[a];
        if (t0 > t1) std::swap(t0, t1);
        s_in = std::max(s_in, t0);
        s_out = std::min(s_out, t1);
    }
    return s_in <= s_out ? s_in : std::numeric_limits<double>::infinity();
}

// Brute-force depth of texel (i, j) of an orthographic fit: a function of the global texel index.
float ortho_texel(const Fit& f, int i, int j, const std::vector<Box>& boxes) {
    const long long gi = f.kx + i, gj = f.ky + j;
    const glm::dvec3 o = (double(gi) + 0.5) * f.t * f.sx + (double(gj) + 0.5) * f.t * f.sy;
    double best = std::numeric_limits<double>::infinity();
    for (const Box& b : boxes) best = std::min(best, ray_box(o, f.d, b.b));
    if (!std::isfinite(best)) return 1.0f;
    return static_cast<float>(2.0 * (best - f.s0) / (f.s1 - f.s0) - 1.0);
}

void render_rect(const Fit& f, const std::vector<Box>& boxes, const ShadowCacheRect& r, std::vector<float>& map) {
    for (int j = r.y; j < r.y + r.height; ++j)
        for (int i = r.x; i < r.x + r.width; ++i) map[std::size_t(j) * std::size_t(f.w) + std::size_t(i)] = ortho_texel(f, i, j, boxes);
}

bool rect_inside(const ShadowCacheRect& r, int w, int h) {
    return r.width > 0 && r.height > 0 && r.x >= 0 && r.y >= 0 && r.x + r.width <= w && r.y + r.height <= h;
}

// Applies a plan to the cached map (copy into a fresh buffer like the second texture of a pair).
void apply_plan(const ShadowCachePlan& p, const ShadowCacheRect* rects, const Fit& f, const std::vector<Box>& boxes,
                std::vector<float>& cached) {
    if (p.action == ShadowCacheAction::Scroll) {
        std::vector<float> next(cached.size(), -7.0f);  // garbage where nothing is copied
        for (int y = 0; y < p.copy.height; ++y)
            for (int x = 0; x < p.copy.width; ++x)
                next[std::size_t(p.copy.dst_y + y) * std::size_t(f.w) + std::size_t(p.copy.dst_x + x)] =
                    cached[std::size_t(p.copy.src_y + y) * std::size_t(f.w) + std::size_t(p.copy.src_x + x)];
        cached.swap(next);
    }
    for (std::size_t r = 0; r < p.count; ++r) render_rect(f, boxes, rects[r], cached);
    // the rectangles are pairwise disjoint: no texel is re-rendered twice
    std::vector<int> hits(cached.size(), 0);
    for (std::size_t r = 0; r < p.count; ++r)
        for (int j = rects[r].y; j < rects[r].y + rects[r].height; ++j)
            for (int i = rects[r].x; i < rects[r].x + rects[r].width; ++i) ++hits[std::size_t(j) * std::size_t(f.w) + std::size_t(i)];
    CHECK(std::count_if(hits.begin(), hits.end(), [](int h) { return h > 1; }) == 0);
}

std::vector<ShadowCacheCaster> casters_of(const std::vector<Box>& prev, const std::vector<Box>& cur) {
    std::vector<ShadowCacheCaster> c(cur.size());
    for (std::size_t i = 0; i < cur.size(); ++i) {
        std::memcpy(c[i].bounds, cur[i].b, sizeof c[i].bounds);
        std::memcpy(c[i].previous_bounds, prev[i].b, sizeof c[i].previous_bounds);
    }
    return c;
}

ShadowCacheMapState state_of(const Fit& f, bool has_content, std::uint64_t settings = 0) {
    ShadowCacheMapState s;
    s.view_proj = fit_matrix(f);
    s.width = f.w;
    s.height = f.h;
    s.settings = settings;
    s.has_content = has_content;
    return s;
}

ShadowCachePlan plan_of(const Fit& a, const Fit& b, std::vector<ShadowCacheRect>& rects) {
    return shadow_cache_plan(state_of(a, true), state_of(b, false), nullptr, 0, rects.data(), rects.size());
}

glm::dvec3 rdir(std::mt19937& rng) {
    std::normal_distribution<double> g(0.0, 1.0);
    glm::dvec3 d;
    do { d = glm::dvec3(g(rng), g(rng), g(rng)); } while (glm::length(d) < 1e-3);
    return glm::normalize(d);
}

glm::dvec3 rotate(const glm::dvec3& v, const glm::dvec3& axis, double angle) {  // Rodrigues
    const glm::dvec3 k = glm::normalize(axis);
    return v * std::cos(angle) + glm::cross(k, v) * std::sin(angle) + k * glm::dot(k, v) * (1.0 - std::cos(angle));
}

}  // namespace

TEST_CASE("shadow_cache: statuses for bad input, NaN/Inf, null pointers, BufferTooSmall") {
    Fit f;
    ShadowCacheRect rects[4];
    const ShadowCacheMapState ok = state_of(f, true);
    CHECK(ShadowCachePlan{}.status == Status::NotRun);
    CHECK(shadow_cache_plan(ok, ok, nullptr, 0, rects, 4).status == Status::Ok);
    // required fields: a default-constructed current state is rejected
    CHECK(shadow_cache_plan(ok, ShadowCacheMapState{}, nullptr, 0, rects, 4).status == Status::InvalidArgument);
    ShadowCacheMapState zero = ok;
    zero.view_proj = glm::dmat4(0.0);
    CHECK(shadow_cache_plan(ok, zero, nullptr, 0, rects, 4).status == Status::InvalidArgument);
    CHECK(shadow_cache_plan(zero, ok, nullptr, 0, rects, 4).status == Status::InvalidArgument);  // previous with content
    zero.has_content = false;  // a previous without content is not read
    CHECK(shadow_cache_plan(zero, ok, nullptr, 0, rects, 4).reason == ShadowCacheReason::NoContent);
    for (int bad : {0, -3, kShadowCacheMaxSize + 1}) {
        ShadowCacheMapState s = ok;
        s.width = bad;
        CHECK(shadow_cache_plan(ok, s, nullptr, 0, rects, 4).status == Status::InvalidArgument);
        CHECK(shadow_cache_plan(s, ok, nullptr, 0, rects, 4).status == Status::InvalidArgument);
    }
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    for (double v : {nan, inf, -inf}) {
        for (int e = 0; e < 16; ++e) {
            ShadowCacheMapState s = ok;
            s.view_proj[e / 4][e % 4] = v;
            CHECK(shadow_cache_plan(ok, s, nullptr, 0, rects, 4).status == Status::NonFinite);
            CHECK(shadow_cache_plan(s, ok, nullptr, 0, rects, 4).status == Status::NonFinite);
            CHECK(shadow_cache_footprint(s.view_proj, 8, 8, Box{{0, 0, 0, 1, 1, 1}}.b).status == Status::NonFinite);
        }
        for (int e = 0; e < 12; ++e) {
            ShadowCacheCaster c;
            (e < 6 ? c.bounds[e] : c.previous_bounds[e - 6]) = static_cast<float>(v);
            const ShadowCachePlan p = shadow_cache_plan(ok, ok, &c, 1, rects, 4);
            CHECK(p.status == Status::NonFinite);
            CHECK(p.count == 0);
        }
    }
    CHECK(shadow_cache_plan(ok, ok, nullptr, 2, rects, 4).status == Status::InvalidArgument);
    CHECK(shadow_cache_plan(ok, ok, nullptr, 0, nullptr, 4).status == Status::InvalidArgument);
    // capacity 0: a plan that writes nothing is Ok, one that needs a rectangle says so
    CHECK(shadow_cache_plan(ok, ok, nullptr, 0, nullptr, 0).status == Status::Ok);
    const ShadowCachePlan small = shadow_cache_plan(ShadowCacheMapState{}, ok, nullptr, 0, nullptr, 0);
    CHECK(small.status == Status::BufferTooSmall);
    CHECK(small.needed == 1);
    CHECK(small.count == 0);
    // footprint
    CHECK(shadow_cache_footprint(ok.view_proj, 8, 8, nullptr).status == Status::InvalidArgument);
    CHECK(shadow_cache_footprint(glm::dmat4(0.0), 8, 8, Box{{0, 0, 0, 1, 1, 1}}.b).status == Status::InvalidArgument);
    CHECK(shadow_cache_footprint(ok.view_proj, 0, 8, Box{{0, 0, 0, 1, 1, 1}}.b).status == Status::InvalidArgument);
    const ShadowCacheFootprint empty = shadow_cache_footprint(ok.view_proj, 8, 8, Box{{1, 0, 0, 0, 1, 1}}.b);
    CHECK(empty.status == Status::Ok);
    CHECK_FALSE(empty.visible);
    // finite input whose projection is beyond double
    glm::dmat4 huge = ok.view_proj;
    huge[0][0] = 1e300;
    CHECK(shadow_cache_footprint(huge, 8, 8, Box{{-3e38f, 0, 0, 3e38f, 1, 1}}.b).status == Status::Overflow);
    // a singular affine map has no volume: its motion cannot be judged
    ShadowCacheMapState sing = ok;
    sing.view_proj[0][2] = sing.view_proj[1][2] = sing.view_proj[2][2] = 0.0;
    sing.view_proj[3][0] += 2.0 / 24.0;  // not identical to previous
    ShadowCacheMapState sing_prev = ok;
    sing_prev.view_proj[0][2] = sing_prev.view_proj[1][2] = sing_prev.view_proj[2][2] = 0.0;
    CHECK(shadow_cache_plan(sing_prev, sing, nullptr, 0, rects, 4).status == Status::InvalidArgument);
    CHECK(std::string(status_name(Status::Overflow)) == "Overflow");
    CHECK(std::string(shadow_cache_reason_name(ShadowCacheReason::DepthMoved)) == "DepthMoved");
    CHECK(std::string(shadow_cache_action_name(ShadowCacheAction::Scroll)) == "Scroll");
    CHECK(shadow_cache_rect_capacity(0) == 2);
    CHECK(shadow_cache_rect_capacity(5) == 12);
    CHECK(shadow_cache_rect_capacity(std::numeric_limits<std::size_t>::max()) == std::numeric_limits<std::size_t>::max());
}

TEST_CASE("shadow_cache: invalidation follows the map's light, settings and size (Apelles sec. 4.1.2)") {
    Fit f;
    basis(glm::dvec3(0.3, -1.0, 0.2), f);
    std::vector<ShadowCacheRect> rects(8);
    const ShadowCacheMapState a = state_of(f, true, 7);
    ShadowCacheMapState b = state_of(f, false, 7);
    ShadowCachePlan p = shadow_cache_plan(a, b, nullptr, 0, rects.data(), rects.size());
    CHECK(p.status == Status::Ok);
    CHECK(p.action == ShadowCacheAction::Keep);
    CHECK(p.count == 0);
    CHECK(p.texels == 0);
    b.settings = 8;
    p = shadow_cache_plan(a, b, nullptr, 0, rects.data(), rects.size());
    CHECK(p.action == ShadowCacheAction::Render);
    CHECK(p.reason == ShadowCacheReason::SettingsChanged);
    REQUIRE(p.count == 1);
    CHECK(rects[0].x == 0);
    CHECK(rects[0].y == 0);
    CHECK(rects[0].width == f.w);
    CHECK(rects[0].height == f.h);
    CHECK(p.texels == std::uint64_t(f.w * f.h));
    b = state_of(f, false, 7);
    b.width = 32;
    CHECK(shadow_cache_plan(a, b, nullptr, 0, rects.data(), rects.size()).reason == ShadowCacheReason::SizeChanged);
    // a caster moving far away from the map: nothing to do; into the map: Update
    ShadowCacheCaster c;
    const float far_box[6] = {1000, 1000, 1000, 1001, 1001, 1001};
    std::memcpy(c.previous_bounds, far_box, sizeof far_box);
    std::memcpy(c.bounds, far_box, sizeof far_box);
    c.bounds[0] += 1.0f;
    c.bounds[3] += 1.0f;
    p = shadow_cache_plan(a, state_of(f, false, 7), &c, 1, rects.data(), rects.size());
    CHECK(p.action == ShadowCacheAction::Keep);
    const float near_box[6] = {-0.5f, -0.5f, -0.5f, 0.5f, 0.5f, 0.5f};
    std::memcpy(c.bounds, near_box, sizeof near_box);
    p = shadow_cache_plan(a, state_of(f, false, 7), &c, 1, rects.data(), rects.size());
    CHECK(p.action == ShadowCacheAction::Update);
    CHECK(p.count == 1);
    CHECK(p.texels > 0);
    CHECK(p.texels < std::uint64_t(f.w * f.h));
    // perspective maps: unchanged -> Keep / Update, any change -> Render
    const glm::dmat4 spot = glm::perspective(1.0, 1.0, 0.5, 50.0) * glm::lookAt(glm::dvec3(0, 10, 0), glm::dvec3(0), glm::dvec3(0, 0, 1));
    ShadowCacheMapState sa;
    sa.view_proj = spot;
    sa.width = sa.height = 64;
    sa.has_content = true;
    ShadowCacheMapState sb = sa;
    CHECK(shadow_cache_plan(sa, sb, &c, 1, rects.data(), rects.size()).action == ShadowCacheAction::Update);
    sb.view_proj = glm::perspective(1.0, 1.0, 0.5, 50.0) *
                   glm::lookAt(glm::dvec3(0, 10, 1e-9), glm::dvec3(0), glm::dvec3(0, 0, 1));
    p = shadow_cache_plan(sa, sb, &c, 1, rects.data(), rects.size());
    CHECK(p.action == ShadowCacheAction::Render);
    CHECK(p.reason == ShadowCacheReason::ProjectionChanged);
}

TEST_CASE("shadow_cache: whole-texel translations give the closed-form offset, copy region and border") {
    std::mt19937 rng(18);
    std::uniform_int_distribution<int> size(2, 4096);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    std::vector<ShadowCacheRect> rects(2);
    int scrolls = 0;
    for (int it = 0; it < 4000; ++it) {
        Fit a;
        basis(rdir(rng), a);
        a.w = size(rng);
        a.h = (it % 3 == 0) ? a.w : size(rng);
        a.t = std::pow(10.0, -3.0 + 4.0 * u01(rng));
        a.kx = static_cast<long long>(std::floor((u01(rng) - 0.5) * 2e5));
        a.ky = static_cast<long long>(std::floor((u01(rng) - 0.5) * 2e5));
        Fit b = a;
        const int dx = static_cast<int>(std::floor((u01(rng) - 0.5) * 2.2 * a.w));
        const int dy = (it % 5 == 0) ? 0 : static_cast<int>(std::floor((u01(rng) - 0.5) * 2.2 * a.h));
        b.kx += dx;
        b.ky += dy;
        const ShadowCachePlan p = plan_of(a, b, rects);
        REQUIRE(p.status == Status::Ok);
        CHECK(p.count <= rects.size());
        const int ox = -dx, oy = -dy;  // a world point lands dx texels further left in the new map
        if (dx == 0 && dy == 0) {
            CHECK(p.action == ShadowCacheAction::Keep);
            continue;
        }
        if (std::abs(dx) >= a.w || std::abs(dy) >= a.h) {
            CHECK(p.action == ShadowCacheAction::Render);
            CHECK(p.reason == ShadowCacheReason::MovedOffMap);
            continue;
        }
        const std::uint64_t ax = std::uint64_t(std::abs(ox)), ay = std::uint64_t(std::abs(oy));
        const std::uint64_t border = ax * std::uint64_t(a.h) + ay * std::uint64_t(a.w) - ax * ay;
        if (border >= std::uint64_t(a.w) * std::uint64_t(a.h)) {
            CHECK(p.reason == ShadowCacheReason::DirtyCoversMap);
            continue;
        }
        REQUIRE(p.action == ShadowCacheAction::Scroll);
        ++scrolls;
        CHECK(p.offset_x == ox);
        CHECK(p.offset_y == oy);
        CHECK(p.residual_texels <= p.tolerance_texels);
        CHECK(p.texels == border);
        CHECK(p.copy.width == a.w - int(ax));
        CHECK(p.copy.height == a.h - int(ay));
        CHECK(p.copy.dst_x - p.copy.src_x == ox);
        CHECK(p.copy.dst_y - p.copy.src_y == oy);
        for (std::size_t r = 0; r < p.count; ++r) CHECK(rect_inside(rects[r], a.w, a.h));
        // copied and re-rendered regions partition the map
        CHECK(p.texels + std::uint64_t(p.copy.width) * std::uint64_t(p.copy.height) == std::uint64_t(a.w) * std::uint64_t(a.h));
    }
    CHECK(scrolls > 1500);
}

TEST_CASE("shadow_cache: sub-texel, depth and rotated motion render the whole map") {
    std::mt19937 rng(180);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    std::vector<ShadowCacheRect> rects(4);
    for (int it = 0; it < 3000; ++it) {
        Fit a;
        basis(rdir(rng), a);
        a.w = a.h = 2048;
        a.t = 1.0 / 64.0;
        a.kx = static_cast<long long>(std::floor((u01(rng) - 0.5) * 1e4));
        a.ky = static_cast<long long>(std::floor((u01(rng) - 0.5) * 1e4));
        // sub-texel: the anchor moves by a fraction of a texel (not a stable fit)
        {
            ShadowCacheMapState s = state_of(a, false);
            const double frac = 0.001 + 0.998 * u01(rng);
            s.view_proj[3][0] += 2.0 * frac / double(a.w);
            const ShadowCachePlan p = shadow_cache_plan(state_of(a, true), s, nullptr, 0, rects.data(), rects.size());
            CHECK(p.reason == ShadowCacheReason::SubTexelMotion);
            CHECK(p.residual_texels == doctest::Approx(std::min(frac, 1.0 - frac)).epsilon(1e-6));
        }
        // depth: the range moves along the light axis
        {
            Fit b = a;
            const double dz = (u01(rng) < 0.5 ? -1.0 : 1.0) * std::pow(10.0, -6.0 + 7.0 * u01(rng));
            b.s0 += dz;
            b.s1 += dz;
            CHECK(plan_of(a, b, rects).reason == ShadowCacheReason::DepthMoved);
            b.kx += 3;  // and in x: still depth
            CHECK(plan_of(a, b, rects).reason == ShadowCacheReason::DepthMoved);
        }
        // rotation of the light by 1e-7 rad: points of the map move by ~1e-7 * (distance from the
        // origin-anchored light frame) / texel, far above the round-off bound: must invalidate
        {
            Fit b = a;
            const glm::dvec3 axis = rdir(rng);
            b.sx = rotate(a.sx, axis, 1e-7);
            b.sy = rotate(a.sy, axis, 1e-7);
            b.d = rotate(a.d, axis, 1e-7);
            const ShadowCachePlan p = plan_of(a, b, rects);
            CHECK(p.reason == ShadowCacheReason::ProjectionChanged);
            CHECK(p.residual_texels > 1e3 * p.tolerance_texels);
        }
        // a texel size change (the fit grew)
        {
            Fit b = a;
            b.t *= 1.0 + 1e-9;
            CHECK(plan_of(a, b, rects).reason == ShadowCacheReason::ProjectionChanged);
        }
    }
}

TEST_CASE("shadow_cache: the 1e-7 rad turn, closed form of its displacement") {
    // Light straight down (d = -y), map centered at the origin: 2048 texels of 1/64 -> 32 units wide,
    // depth range [-50, 50]. A turn by theta about z moves the volume's corners (|p| up to
    // sqrt(16^2 + 16^2 + 50^2)) in map x by theta * (their distance along the light) / texel at most.
    Fit a;
    basis(glm::dvec3(0, -1, 0), a);
    a.w = a.h = 2048;
    a.t = 1.0 / 64.0;
    a.kx = a.ky = -1024;
    Fit b = a;
    const double theta = 1e-7;
    b.sx = rotate(a.sx, glm::dvec3(0, 0, 1), theta);
    b.sy = rotate(a.sy, glm::dvec3(0, 0, 1), theta);
    b.d = rotate(a.d, glm::dvec3(0, 0, 1), theta);
    std::vector<ShadowCacheRect> rects(4);
    const ShadowCachePlan p = plan_of(a, b, rects);
    CHECK(p.action == ShadowCacheAction::Render);
    CHECK(p.reason == ShadowCacheReason::ProjectionChanged);
    // x of a point moves by theta * (its coordinate along d, up to 50) / t = 3.2e-4 texel at most
    CHECK(p.residual_texels <= theta * (50.0 + 16.0) / a.t * 1.01);
    CHECK(p.residual_texels >= theta * 50.0 / a.t * 0.5);
    CHECK(p.tolerance_texels < 1e-9);
}

TEST_CASE("shadow_cache: stiff camera paths: 1e-6 and 1e6 translations, far from the origin (1e5)") {
    std::vector<ShadowCacheRect> rects(8);
    Fit f;
    basis(glm::dvec3(0.4, -1.0, 0.3), f);
    f.w = f.h = 2048;
    f.t = 1.0 / 64.0;
    const double q = 64.0, depth = 200.0;
    for (double base : {0.0, 1e5, -1e5}) {
        CAPTURE(base);
        // camera at a texel center of the anchor grid, so a 1e-6 move cannot cross a texel line
        const glm::dvec3 c0(base, 3.0, base);
        const glm::dvec3 c = (std::floor(glm::dot(f.sx, c0) / f.t) + 0.5) * f.t * f.sx +
                       (std::floor(glm::dot(f.sy, c0) / f.t) + 0.5) * f.t * f.sy + (std::floor(glm::dot(f.d, c0) / q) + 0.5) * q * f.d;
        Fit a = f, b = f;
        fit_camera(a, c, q, depth);
        // 1e-6 along every axis: same fit, bit-identical matrix -> Keep
        fit_camera(b, c + glm::dvec3(1e-6, -1e-6, 1e-6), q, depth);
        ShadowCachePlan p = plan_of(a, b, rects);
        CHECK(p.action == ShadowCacheAction::Keep);
        // whole texels sideways: Scroll by the closed-form offset, residual at round-off level
        fit_camera(b, c + 5.0 * f.t * f.sx - 3.0 * f.t * f.sy, q, depth);
        p = plan_of(a, b, rects);
        REQUIRE(p.action == ShadowCacheAction::Scroll);
        CHECK(p.offset_x == -5);
        CHECK(p.offset_y == 3);
        CHECK(p.texels == std::uint64_t(5 * 2048 + 3 * 2048 - 15));
        CHECK(p.tolerance_texels < 1e-6);  // double at 1e5: ~1e-9 texel (N * 64 * 2^-53)
        CHECK(p.residual_texels <= p.tolerance_texels);
        // 1e6 units: off the map
        fit_camera(b, c + glm::dvec3(1e6, 0, 0), q, depth);
        p = plan_of(a, b, rects);
        CHECK(p.action == ShadowCacheAction::Render);
        CHECK((p.reason == ShadowCacheReason::MovedOffMap || p.reason == ShadowCacheReason::DepthMoved));
        fit_camera(b, c + 1e6 * f.sx, q, depth);  // purely sideways: the depth range stays
        CHECK(plan_of(a, b, rects).reason == ShadowCacheReason::MovedOffMap);
    }
}

TEST_CASE("shadow_cache: float texel snapping fails at 1e5, double holds (precision of the snap)") {
    // The cascades-style snap: texel = 2 r / (S - 2) (not a power of two), the light-space center
    // snapped to floor(x / texel) * texel, the NDC translation -x_snapped / half. In float, at
    // x ~ 1e5 the snapped center is off the texel grid by up to ulp(1e5) / 2 / texel texels, and
    // the translation term (~6e3 NDC) by ulp(6e3) / 2 * S / 2 texels: far beyond the 1/256
    // sub-texel step. In double both stay below 1e-6 texel.
    const double r = 20.0, S = 2048.0, texel = 2.0 * r / (S - 2.0), half = r + texel;
    const float texel_f = static_cast<float>(texel), half_f = static_cast<float>(half);
    std::mt19937 rng(1805);
    std::uniform_real_distribution<double> jitter(0.0, 10.0);
    double worst_f = 0.0, worst_d = 0.0, worst_ndc_f = 0.0;
    for (int it = 0; it < 2000; ++it) {
        const double x = 1e5 + jitter(rng);
        const float xf = static_cast<float>(x);
        const float snapped_f = std::floor(xf / texel_f) * texel_f;
        const double snapped_d = std::floor(x / texel) * texel;
        const double off_f = double(snapped_f) / texel, off_d = snapped_d / texel;
        worst_f = std::max(worst_f, std::fabs(off_f - std::round(off_f)));
        worst_d = std::max(worst_d, std::fabs(off_d - std::round(off_d)));
        const float ndc_f = -snapped_f / half_f;
        const double ndc_exact = -std::round(off_d) * texel / half;
        worst_ndc_f = std::max(worst_ndc_f, std::fabs(double(ndc_f) - ndc_exact) * S / 2.0);
    }
    MESSAGE("float snap off the texel grid by " << worst_f << " texel, float translation by " << worst_ndc_f
                                                << " texel; double snap by " << worst_d);
    CHECK(worst_f > 1.0 / 256.0);
    CHECK(worst_ndc_f > 1.0 / 256.0);
    CHECK(worst_d < 1e-6);

    // The plan. A cascades-style fit (linear rows sx / half, translation -snapped / half) 1e5 units
    // from the origin, the camera moved by exactly 4 texels: built in double -> Scroll by -4. Stored
    // in float, its translation (~5e3 NDC) has a grid of ulp(5e3) = 2^-11 NDC = 0.5 texel, and clip x
    // is a sum of terms of ~5e3: a world point lands up to ~0.25 texel (N * 2^-24, N = 5e6 texels from
    // the origin) away from where the double matrix puts it (shown below). Whether two such float
    // frames still differ by exactly whole texels depends on the GPU's evaluation order and binade
    // crossings, which the plan cannot see: declared float_matrices, it says PrecisionTooLow.
    Fit a;
    basis(glm::dvec3(0.4, -1.0, 0.3), a);
    a.w = a.h = 2048;
    auto cascade_like = [&](double x, double y, bool in_float) {
        glm::dmat4 m(0.0);
        for (int c = 0; c < 3; ++c) {
            m[c][0] = a.sx[c] / half;
            m[c][1] = a.sy[c] / half;
            m[c][2] = 2.0 / 20.0 * a.d[c];
        }
        m[3][2] = 0.25;
        m[3][3] = 1.0;
        if (in_float) {
            const float xf = static_cast<float>(x), yf = static_cast<float>(y);
            m[3][0] = double(-(std::floor(xf / texel_f) * texel_f) / half_f);
            m[3][1] = double(-(std::floor(yf / texel_f) * texel_f) / half_f);
            m = glm::dmat4(glm::mat4(m));
        } else {
            m[3][0] = -(std::floor(x / texel) * texel) / half;
            m[3][1] = -(std::floor(y / texel) * texel) / half;
        }
        return m;
    };
    std::vector<ShadowCacheRect> rects(8);
    int double_scrolls = 0;
    double eval_f = 0.0, eval_d = 0.0;
    for (int it = 0; it < 200; ++it) {
        const double x = 1e5 + jitter(rng), y = -1e5 + jitter(rng);
        ShadowCacheMapState sa, sb;
        sa.width = sa.height = sb.width = sb.height = 2048;
        sa.has_content = true;
        sa.view_proj = cascade_like(x, y, false);
        sb.view_proj = cascade_like(x + 4.0 * texel, y, false);
        ShadowCachePlan p = shadow_cache_plan(sa, sb, nullptr, 0, rects.data(), rects.size());
        if (p.action == ShadowCacheAction::Scroll && p.offset_x == -4 && p.offset_y == 0) ++double_scrolls;
        CHECK(p.tolerance_texels < 1e-6);
        // where a world point inside the map lands in both frames, evaluated as a GPU would (float)
        // and in double: the difference must be the whole-texel offset -4
        const glm::mat4 fa(sa.view_proj), fb(sb.view_proj);
        for (int k = 0; k < 16; ++k) {
            const glm::dvec3 pw = (x + 5.0 * (jitter(rng) - 5.0)) * a.sx + (y + 5.0 * (jitter(rng) - 5.0)) * a.sy + jitter(rng) * a.d;
            const glm::vec4 pf(glm::vec3(pw), 1.0f);
            const double xb = (sb.view_proj * glm::dvec4(pw, 1.0)).x;  // reference: double matrix, double point
            eval_f = std::max(eval_f, std::fabs(double((fb * pf).x) - xb) * 1024.0);
            const double da = (sa.view_proj * glm::dvec4(pw, 1.0)).x;
            eval_d = std::max(eval_d, std::fabs((xb - da) * 1024.0 + 4.0));
            (void)fa;
        }
        sa.view_proj = cascade_like(x, y, true);
        sb.view_proj = cascade_like(x + 4.0 * texel, y, true);
        sa.float_matrices = true;
        p = shadow_cache_plan(sa, sb, nullptr, 0, rects.data(), rects.size());
        CHECK(p.reason == ShadowCacheReason::PrecisionTooLow);
        CHECK(p.tolerance_texels > 1.0 / 256.0);
    }
    MESSAGE("at 1e5, a world point lands " << eval_f << " texel off in a float evaluation; its move between the frames departs from the 4-texel offset by "
            << eval_d << " texel in double");
    CHECK(double_scrolls == 200);
    CHECK(eval_f > 1.0 / 256.0);
    CHECK(eval_d < 1e-6);
    // Near the origin a float map (declared) still scrolls: within ~2^11 texels of it
    {
        ShadowCacheMapState sa, sb;
        sa.width = sa.height = sb.width = sb.height = 2048;
        sa.has_content = true;
        sa.float_matrices = sb.float_matrices = true;
        sa.view_proj = cascade_like(3.0, -2.0, true);
        sb.view_proj = cascade_like(3.0 + 4.0 * texel, -2.0, true);
        const ShadowCachePlan p = shadow_cache_plan(sa, sb, nullptr, 0, rects.data(), rects.size());
        CHECK(p.action == ShadowCacheAction::Scroll);
        CHECK(p.offset_x == -4);
        CHECK(p.tolerance_texels < 1.0 / 256.0);
    }
}

TEST_CASE("shadow_cache: footprints hold every texel a box covers (brute force, ortho and perspective)") {
    std::mt19937 rng(1808);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    int visible = 0, behind_light = 0;
    for (int it = 0; it < 3000; ++it) {
        const int w = 8 + int(rng() % 40), h = 8 + int(rng() % 40);
        glm::dmat4 m;
        bool persp = it % 2 == 1;
        glm::dvec3 light(0.0);
        glm::dvec3 o(0.0), d(0.0);
        Fit f;
        if (!persp) {
            basis(rdir(rng), f);
            f.w = w;
            f.h = h;
            f.t = 0.1 + u01(rng);
            f.kx = -w / 2 + int(rng() % 7) - 3;
            f.ky = -h / 2 + int(rng() % 7) - 3;
            m = fit_matrix(f);
        } else {
            light = glm::dvec3(u01(rng) - 0.5, 4.0 + u01(rng), u01(rng) - 0.5) * 2.0;
            const glm::dvec3 up = std::fabs(light.x) < std::fabs(light.z) ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 0, 1);
            m = glm::perspective(0.5 + 1.5 * u01(rng), double(w) / double(h), 0.5, 100.0) * glm::lookAt(light, glm::dvec3(0), up);
        }
        Box box;
        const glm::dvec3 c = glm::dvec3(u01(rng) - 0.5, u01(rng) - 0.5, u01(rng) - 0.5) * (persp ? 16.0 : 2.0 * double(std::max(w, h)) * f.t);
        const glm::dvec3 e = glm::dvec3(u01(rng), u01(rng), u01(rng)) * (persp ? 3.0 : 0.5 * double(std::max(w, h)) * f.t) + 1e-3;
        for (int a = 0; a < 3; ++a) {
            box.b[a] = static_cast<float>(c[a] - e[a]);
            box.b[a + 3] = static_cast<float>(c[a] + e[a]);
        }
        if (persp && it % 10 == 1) {  // around the light: straddles its plane
            for (int a = 0; a < 3; ++a) {
                box.b[a] = static_cast<float>(light[a] - 0.5);
                box.b[a + 3] = static_cast<float>(light[a] + 0.5);
            }
        }
        const ShadowCacheFootprint fp = shadow_cache_footprint(m, w, h, box.b);
        REQUIRE(fp.status == Status::Ok);
        if (fp.visible) {
            ++visible;
            CHECK(rect_inside(fp.rect, w, h));
        }
        if (persp && it % 10 == 1) {
            ++behind_light;
            CHECK(fp.visible);
            CHECK(fp.rect.width == w);
            CHECK(fp.rect.height == h);
        }
        const glm::dmat4 inv = glm::inverse(m);
        int missed = 0;
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) {
                bool hit = false;
                if (!persp) {
                    hit = std::isfinite(ray_box((double(f.kx + i) + 0.5) * f.t * f.sx + (double(f.ky + j) + 0.5) * f.t * f.sy, f.d, box.b));
                } else {
                    const double nx = (i + 0.5) / w * 2.0 - 1.0, ny = (j + 0.5) / h * 2.0 - 1.0;
                    const glm::dvec4 pn = inv * glm::dvec4(nx, ny, -1.0, 1.0), pf = inv * glm::dvec4(nx, ny, 1.0, 1.0);
                    const glm::dvec3 a = glm::dvec3(pn) / pn.w, b = glm::dvec3(pf) / pf.w;
                    // the whole ray from the light (depth clamp draws what lies before the near plane)
                    const double s = ray_box(light, b - a, box.b);
                    hit = std::isfinite(s) && s >= 0.0;
                    // a box that contains the light covers every direction
                    if (box.b[0] <= light.x && light.x <= box.b[3] && box.b[1] <= light.y && light.y <= box.b[4] &&
                        box.b[2] <= light.z && light.z <= box.b[5])
                        hit = true;
                }
                if (hit && (!fp.visible || i < fp.rect.x || i >= fp.rect.x + fp.rect.width || j < fp.rect.y ||
                            j >= fp.rect.y + fp.rect.height))
                    ++missed;
            }
        CHECK(missed == 0);
    }
    CHECK(visible > 1000);
    CHECK(behind_light > 100);
}

TEST_CASE("shadow_cache: boxes touching the map's border") {
    Fit f;
    basis(glm::dvec3(0, -1, 0), f);  // sx = +x or -x, sy along z: exact texel lines
    f.t = 0.25;
    f.w = f.h = 16;
    f.kx = f.ky = -8;
    const glm::dmat4 m = fit_matrix(f);
    // the world x of the map's left edge (window x = 0) and right edge (window x = 16)
    const double x_left = double(f.kx) * f.t, x_right = double(f.kx + f.w) * f.t;
    // a box spanning [a, b] along sx, [-0.5, 0.5] along sy and [-1, 1] along d (the basis is a signed
    // permutation of the world axes, so the box is axis-aligned)
    auto box_x = [&](double a, double b) {
        Box bx{{1e30f, 1e30f, 1e30f, -1e30f, -1e30f, -1e30f}};
        for (int k = 0; k < 8; ++k) {
            const glm::dvec3 p = ((k & 1) ? b : a) * f.sx + ((k & 2) ? 0.5 : -0.5) * f.sy + ((k & 4) ? 1.0 : -1.0) * f.d;
            for (int c = 0; c < 3; ++c) {
                bx.b[c] = std::min(bx.b[c], static_cast<float>(p[c]));
                bx.b[c + 3] = std::max(bx.b[c + 3], static_cast<float>(p[c]));
            }
        }
        return bx;
    };
    // ending exactly on the left edge (from outside): its texels are all outside, but the margin keeps
    // column 0 (a center within one texel of the edge)
    ShadowCacheFootprint fp = shadow_cache_footprint(m, f.w, f.h, box_x(x_left - 2.0, x_left).b);
    REQUIRE(fp.status == Status::Ok);
    CHECK(fp.visible);
    CHECK(fp.rect.x == 0);
    CHECK(fp.rect.width == 1);
    // starting exactly on the right edge: the last column
    fp = shadow_cache_footprint(m, f.w, f.h, box_x(x_right, x_right + 3.0).b);
    CHECK(fp.visible);
    CHECK(fp.rect.x == f.w - 1);
    CHECK(fp.rect.width == 1);
    // more than 1.5 texels outside: not visible
    fp = shadow_cache_footprint(m, f.w, f.h, box_x(x_right + 1.6 * f.t, x_right + 3.0).b);
    CHECK_FALSE(fp.visible);
    // spanning the whole map and beyond: clipped to the map
    fp = shadow_cache_footprint(m, f.w, f.h, box_x(x_left - 10.0, x_right + 10.0).b);
    CHECK(fp.rect.x == 0);
    CHECK(fp.rect.width == f.w);
    // a caster sliding along the border: the brute-force compare stays exact
    std::vector<Box> boxes{box_x(x_left - 1.0, x_left), box_x(x_right - 0.3, x_right)};
    std::vector<float> cached(std::size_t(f.w * f.h)), full(cached.size());
    render_rect(f, boxes, ShadowCacheRect{0, 0, f.w, f.h}, cached);
    std::vector<ShadowCacheRect> rects(4);
    for (int step = 0; step < 12; ++step) {
        std::vector<Box> next = boxes;
        const double s = (step % 2 ? -1.0 : 1.0) * f.t * 0.5 * (step + 1);
        next[0] = box_x(x_left - 1.0 + s, x_left + s);
        next[1] = box_x(x_right - 0.3 - s, x_right - s);
        const std::vector<ShadowCacheCaster> cs = casters_of(boxes, next);
        const ShadowCachePlan p =
            shadow_cache_plan(state_of(f, true), state_of(f, false), cs.data(), cs.size(), rects.data(), rects.size());
        REQUIRE(p.status == Status::Ok);
        apply_plan(p, rects.data(), f, next, cached);
        render_rect(f, next, ShadowCacheRect{0, 0, f.w, f.h}, full);
        CHECK(cached == full);
        boxes = next;
    }
}

TEST_CASE("shadow_cache: merging keeps a conservative cover within any capacity") {
    std::mt19937 rng(99);
    for (int it = 0; it < 2000; ++it) {
        Fit f;
        basis(glm::dvec3(0, -1, 0), f);
        f.w = f.h = 32;
        f.t = 0.25;
        f.kx = f.ky = -16;
        const std::size_t n = 1 + rng() % 12;
        std::vector<ShadowCacheCaster> cs(n);
        std::uniform_real_distribution<float> pos(-5.0f, 5.0f), ext(0.01f, 1.5f);
        for (auto& c : cs)
            for (float* b : {c.bounds, c.previous_bounds}) {
                const float x = pos(rng), z = pos(rng), e = ext(rng), g = ext(rng);
                const float v[6] = {x - e, -1.0f, z - g, x + e, 1.0f, z + g};
                std::memcpy(b, v, sizeof v);
            }
        const std::size_t cap = 1 + rng() % 6;
        std::vector<ShadowCacheRect> merged(cap), all(shadow_cache_rect_capacity(n));
        const ShadowCacheMapState s = state_of(f, true);
        const ShadowCachePlan pm = shadow_cache_plan(s, s, cs.data(), n, merged.data(), cap);
        const ShadowCachePlan pa = shadow_cache_plan(s, s, cs.data(), n, all.data(), all.size());
        REQUIRE(pm.status == Status::Ok);
        REQUIRE(pa.status == Status::Ok);
        CHECK(pm.count <= cap);
        CHECK(pm.count == pm.needed);
        CHECK(pa.unmerged <= shadow_cache_rect_capacity(n));
        if (pm.action != ShadowCacheAction::Render && pa.action != ShadowCacheAction::Render)
            CHECK(pm.unmerged == pa.unmerged);  // Render (DirtyCoversMap) has one rectangle
        // every texel of every footprint is covered by the merged list (or the map renders whole)
        auto covered = [](const ShadowCacheRect* r, std::size_t count, int i, int j) {
            for (std::size_t k = 0; k < count; ++k)
                if (i >= r[k].x && i < r[k].x + r[k].width && j >= r[k].y && j < r[k].y + r[k].height) return true;
            return false;
        };
        for (const auto& c : cs)
            for (const float* b : {c.bounds, c.previous_bounds}) {
                const ShadowCacheFootprint fp = shadow_cache_footprint(s.view_proj, f.w, f.h, b);
                if (!fp.visible) continue;
                for (int j = fp.rect.y; j < fp.rect.y + fp.rect.height; ++j)
                    for (int i = fp.rect.x; i < fp.rect.x + fp.rect.width; ++i) {
                        CHECK(covered(merged.data(), pm.count, i, j));
                        CHECK(covered(all.data(), pa.count, i, j));
                    }
            }
    }
}

TEST_CASE("shadow_cache: property: along random camera paths with moving casters the cached map equals a full re-render") {
    // 400 seeded paths x 12 frames: camera steps from 1e-6 to several map widths, the depth range
    // snapped along the light (it moves when the camera crosses a multiple of q), casters that move
    // by sub-texel to large steps, appear and vanish; now and then a settings change or a light turn
    // (1e-7 or 0.05 rad). Every frame the cached map, updated with the plan, must equal the full
    // re-render bit for bit; any rectangle the plan leaves out or any wrong offset shows.
    std::mt19937 rng(20181);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    int counts[4] = {0, 0, 0, 0};
    int reasons[10] = {};
    int frames = 0, mismatched_frames = 0;
    double rerendered = 0.0;
    for (int path = 0; path < 400; ++path) {
        Fit f;
        basis(rdir(rng), f);
        f.w = 16 + int(rng() % 17);
        f.h = 16 + int(rng() % 17);
        f.t = 0.125 + 0.25 * u01(rng);
        const double q = 4.0, depth = 60.0;
        glm::dvec3 cam(u01(rng) * 4 - 2, u01(rng) * 4 - 2, u01(rng) * 4 - 2);
        fit_camera(f, cam, q, depth);
        std::vector<Box> boxes(10);
        for (Box& b : boxes) {
            const glm::dvec3 c = cam + glm::dvec3(u01(rng) - 0.5, u01(rng) - 0.5, u01(rng) - 0.5) * 8.0;
            const glm::dvec3 e = glm::dvec3(u01(rng), u01(rng), u01(rng)) * 1.2 + 0.05;
            for (int a = 0; a < 3; ++a) {
                b.b[a] = static_cast<float>(c[a] - e[a]);
                b.b[a + 3] = static_cast<float>(c[a] + e[a]);
            }
        }
        std::uint64_t settings = 1;
        ShadowCacheMapState prev = state_of(f, false, settings);
        prev.has_content = false;
        std::vector<float> cached(std::size_t(f.w * f.h), 0.0f), full(cached.size());
        const std::size_t caps[6] = {1, 2, 3, 5, 8, 64};
        glm::dvec3 back(0.0);
        for (int frame = 0; frame < 12; ++frame) {
            // camera step
            const double kind = u01(rng);
            double step = 0.0;
            if (kind < 0.2) step = 1e-6;
            else if (kind < 0.45) step = 0.3 * f.t * u01(rng);
            else if (kind < 0.8) step = f.t * (1.0 + 4.0 * u01(rng));
            else if (kind < 0.95) step = 1.0 + 3.0 * u01(rng);
            else step = 1e6;
            glm::dvec3 dir = rdir(rng);
            if (u01(rng) < 0.5) dir = glm::normalize(dir - glm::dot(dir, f.d) * f.d);  // sideways: depth stays
            cam += step * dir + back;
            back = step >= 1e6 ? -step * dir : glm::dvec3(0.0);  // a 1e6 jump comes back the next frame
            Fit nf = f;
            const double ev = u01(rng);
            if (ev < 0.03) {
                const glm::dvec3 axis = rdir(rng);
                const double ang = u01(rng) < 0.5 ? 1e-7 : 0.05;
                nf.sx = rotate(f.sx, axis, ang);
                nf.sy = rotate(f.sy, axis, ang);
                nf.d = rotate(f.d, axis, ang);
            } else if (ev < 0.05) {
                ++settings;
            }
            fit_camera(nf, cam, q, depth);
            // casters
            std::vector<Box> next = boxes;
            if (u01(rng) < 0.7) {
                for (std::size_t i = 0; i < next.size(); ++i) {
                    if (i < 4) continue;  // static
                    const double r = u01(rng);
                    if (r < 0.4) continue;
                    if (r < 0.45) {  // vanish / appear
                        if (next[i].b[0] > next[i].b[3]) {
                            const glm::dvec3 c = cam + glm::dvec3(u01(rng) - 0.5, u01(rng) - 0.5, u01(rng) - 0.5) * 6.0;
                            for (int a = 0; a < 3; ++a) {
                                next[i].b[a] = static_cast<float>(c[a] - 0.4);
                                next[i].b[a + 3] = static_cast<float>(c[a] + 0.4);
                            }
                        } else {
                            next[i].b[0] = 1.0f;
                            next[i].b[3] = -1.0f;
                        }
                        continue;
                    }
                    if (next[i].b[0] > next[i].b[3]) continue;
                    const double mag = r < 0.7 ? 1e-3 : (r < 0.9 ? 0.3 : 3.0);
                    const glm::dvec3 mv = rdir(rng) * mag;
                    for (int a = 0; a < 3; ++a) {
                        next[i].b[a] += static_cast<float>(mv[a]);
                        next[i].b[a + 3] += static_cast<float>(mv[a]);
                    }
                }
            }
            const std::vector<ShadowCacheCaster> cs = casters_of(boxes, next);
            const std::size_t cap = caps[rng() % 6];
            std::vector<ShadowCacheRect> rects(cap);
            const ShadowCacheMapState cur = state_of(nf, false, settings);
            const ShadowCachePlan p = shadow_cache_plan(prev, cur, cs.data(), cs.size(), rects.data(), cap);
            REQUIRE(p.status == Status::Ok);
            REQUIRE(p.count <= cap);
            for (std::size_t r = 0; r < p.count; ++r) REQUIRE(rect_inside(rects[r], nf.w, nf.h));
            ++counts[int(p.action)];
            ++reasons[int(p.reason)];
            if (p.action == ShadowCacheAction::Keep) CHECK(p.texels == 0);
            apply_plan(p, rects.data(), nf, next, cached);
            render_rect(nf, next, ShadowCacheRect{0, 0, nf.w, nf.h}, full);
            ++frames;
            if (cached != full) ++mismatched_frames;
            rerendered += double(p.texels) / double(nf.w * nf.h);
            prev = cur;
            prev.has_content = true;
            f = nf;
            boxes = next;
        }
    }
    MESSAGE("frames " << frames << ": keep " << counts[0] << ", update " << counts[1] << ", scroll " << counts[2]
                      << ", render " << counts[3] << "; mean fraction re-rendered " << rerendered / frames);
    CHECK(mismatched_frames == 0);
    CHECK(counts[0] > 100);
    CHECK(counts[1] > 100);
    CHECK(counts[2] > 500);
    CHECK(counts[3] > 100);
    CHECK(reasons[int(ShadowCacheReason::DepthMoved)] > 10);
    CHECK(reasons[int(ShadowCacheReason::ProjectionChanged)] > 10);
    CHECK(reasons[int(ShadowCacheReason::MovedOffMap)] > 10);
    CHECK(reasons[int(ShadowCacheReason::SettingsChanged)] > 10);
}

TEST_CASE("shadow_cache: property: a spot light's map with moving casters (Update) equals a full re-render") {
    std::mt19937 rng(4242);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    int updates = 0, keeps = 0, mismatched = 0;
    for (int path = 0; path < 150; ++path) {
        const int w = 16 + int(rng() % 16), h = 16 + int(rng() % 16);
        const glm::dvec3 light(u01(rng) * 2 - 1, 6.0 + u01(rng), u01(rng) * 2 - 1);
        const glm::dmat4 m = glm::perspective(1.2, double(w) / double(h), 0.5, 40.0) *
                             glm::lookAt(light, glm::dvec3(0), glm::dvec3(0, 0, 1));
        const glm::dmat4 inv = glm::inverse(m);
        auto texel = [&](int i, int j, const std::vector<Box>& boxes) {
            const double nx = (i + 0.5) / w * 2.0 - 1.0, ny = (j + 0.5) / h * 2.0 - 1.0;
            const glm::dvec4 pf = inv * glm::dvec4(nx, ny, 1.0, 1.0);
            const glm::dvec3 dir = glm::dvec3(pf) / pf.w - light;
            double best = std::numeric_limits<double>::infinity();
            for (const Box& b : boxes) {
                const double s = ray_box(light, dir, b.b);
                if (s >= 0.0) best = std::min(best, s);
            }
            return std::isfinite(best) ? static_cast<float>(best) : 1.0f;
        };
        auto render = [&](const std::vector<Box>& boxes, const ShadowCacheRect& r, std::vector<float>& map) {
            for (int j = r.y; j < r.y + r.height; ++j)
                for (int i = r.x; i < r.x + r.width; ++i) map[std::size_t(j * w + i)] = texel(i, j, boxes);
        };
        std::vector<Box> boxes(8);
        for (Box& b : boxes) {
            const glm::dvec3 c(u01(rng) * 8 - 4, u01(rng) * 4 - 1, u01(rng) * 8 - 4);
            const double e = 0.2 + 0.6 * u01(rng);
            for (int a = 0; a < 3; ++a) {
                b.b[a] = static_cast<float>(c[a] - e);
                b.b[a + 3] = static_cast<float>(c[a] + e);
            }
        }
        std::vector<float> cached(std::size_t(w * h)), full(cached.size());
        render(boxes, ShadowCacheRect{0, 0, w, h}, cached);
        ShadowCacheMapState st;
        st.view_proj = m;
        st.width = w;
        st.height = h;
        st.has_content = true;
        std::vector<ShadowCacheRect> rects(1 + rng() % 6);
        for (int frame = 0; frame < 10; ++frame) {
            std::vector<Box> next = boxes;
            for (std::size_t i = 0; i < next.size(); ++i) {
                if (u01(rng) < 0.7) continue;
                const glm::dvec3 mv = rdir(rng) * (u01(rng) < 0.5 ? 0.02 : 1.5);
                for (int a = 0; a < 3; ++a) {
                    next[i].b[a] += static_cast<float>(mv[a]);
                    next[i].b[a + 3] += static_cast<float>(mv[a]);
                }
            }
            if (frame == 5) {  // a caster around the light: straddles its plane -> whole map
                for (int a = 0; a < 3; ++a) {
                    next[0].b[a] = static_cast<float>(light[a] - 0.3);
                    next[0].b[a + 3] = static_cast<float>(light[a] + 0.3);
                }
            }
            const std::vector<ShadowCacheCaster> cs = casters_of(boxes, next);
            const ShadowCachePlan p = shadow_cache_plan(st, st, cs.data(), cs.size(), rects.data(), rects.size());
            REQUIRE(p.status == Status::Ok);
            CHECK(p.action != ShadowCacheAction::Scroll);
            if (p.action == ShadowCacheAction::Update) ++updates;
            if (p.action == ShadowCacheAction::Keep) ++keeps;
            for (std::size_t r = 0; r < p.count; ++r) render(next, rects[r], cached);
            render(next, ShadowCacheRect{0, 0, w, h}, full);
            if (cached != full) ++mismatched;
            boxes = next;
        }
    }
    CHECK(mismatched == 0);
    CHECK(updates > 300);
    CHECK(keeps > 5);
}

// ------------------------------------------------------------------ the cover: disjoint, exact union
namespace {

// Brute force over the texel grid: the footprints' union (fp), the plan's rectangles (hits per
// texel). Checks: rectangles inside the map and pairwise disjoint (no texel hit twice), every
// footprint texel covered, texels = the number of texels the rectangles cover; not merged: the
// rectangles cover exactly the footprints' union. Returns the union's area of the footprints.
std::uint64_t check_cover(const ShadowCachePlan& p, const ShadowCacheRect* rects, const std::vector<ShadowCacheRect>& fps,
                          int w, int h) {
    std::vector<unsigned char> in_fp(std::size_t(w) * std::size_t(h), 0);
    std::vector<int> hits(in_fp.size(), 0);
    for (const ShadowCacheRect& r : fps)
        for (int j = r.y; j < r.y + r.height; ++j)
            for (int i = r.x; i < r.x + r.width; ++i) in_fp[std::size_t(j) * std::size_t(w) + std::size_t(i)] = 1;
    for (std::size_t k = 0; k < p.count; ++k) {
        REQUIRE(rect_inside(rects[k], w, h));
        for (int j = rects[k].y; j < rects[k].y + rects[k].height; ++j)
            for (int i = rects[k].x; i < rects[k].x + rects[k].width; ++i) ++hits[std::size_t(j) * std::size_t(w) + std::size_t(i)];
    }
    std::uint64_t union_fp = 0, covered = 0;
    int twice = 0, missed = 0, extra = 0;
    for (std::size_t t = 0; t < in_fp.size(); ++t) {
        union_fp += in_fp[t];
        covered += hits[t] > 0 ? 1u : 0u;
        twice += hits[t] > 1 ? 1 : 0;
        missed += in_fp[t] && hits[t] == 0 ? 1 : 0;
        extra += !in_fp[t] && hits[t] > 0 ? 1 : 0;
    }
    CHECK(twice == 0);
    CHECK(missed == 0);
    CHECK(p.texels == covered);
    if (!p.merged) CHECK(extra == 0);
    return union_fp;
}

// A box on the y = 0 ground of a top-down 64 x 64 fit (texel 0.25, centered on the origin).
Fit top_down(int size) {
    Fit f;
    basis(glm::dvec3(0, -1, 0), f);
    f.w = f.h = size;
    f.t = 0.25;
    f.kx = f.ky = -size / 2;
    return f;
}

Box flat_box(float x0, float z0, float x1, float z1) { return Box{{x0, -1.0f, z0, x1, 1.0f, z1}}; }

std::vector<ShadowCacheRect> footprints_of(const Fit& f, const std::vector<ShadowCacheCaster>& cs) {
    std::vector<ShadowCacheRect> out;
    const glm::dmat4 m = fit_matrix(f);
    for (const ShadowCacheCaster& c : cs) {
        if (std::memcmp(c.bounds, c.previous_bounds, sizeof c.bounds) == 0) continue;
        for (const float* b : {c.previous_bounds, c.bounds}) {
            const ShadowCacheFootprint fp = shadow_cache_footprint(m, f.w, f.h, b);
            REQUIRE(fp.status == Status::Ok);
            if (fp.visible) out.push_back(fp.rect);
        }
    }
    return out;
}

}  // namespace

TEST_CASE("shadow_cache: two crossing casters give disjoint rectangles, texels = the area of their union") {
    // Two casters appear (previous bounds empty): a long bar along one map axis and one along the
    // other, crossing in the middle (the (15, 30, 34, 4) and (30, 15, 4, 34) shape).
    const Fit f = top_down(64);
    const Box none{{1.0f, 1.0f, 1.0f, 0.0f, 0.0f, 0.0f}};  // min > max: absent last frame
    const std::vector<Box> prev{none, none}, cur{flat_box(-4.0f, -0.4f, 4.0f, 0.4f), flat_box(-0.4f, -4.0f, 0.4f, 4.0f)};
    const std::vector<ShadowCacheCaster> cs = casters_of(prev, cur);
    const std::vector<ShadowCacheRect> fps = footprints_of(f, cs);
    REQUIRE(fps.size() == 2);
    const ShadowCacheRect& a = fps[0];
    const ShadowCacheRect& b = fps[1];
    // they cross: each spans the other's extent in one axis and lies within it in the other
    const bool a_wide = a.width > a.height;
    const ShadowCacheRect& wide = a_wide ? a : b;
    const ShadowCacheRect& tall = a_wide ? b : a;
    REQUIRE(wide.x < tall.x);
    REQUIRE(wide.x + wide.width > tall.x + tall.width);
    REQUIRE(tall.y < wide.y);
    REQUIRE(tall.y + tall.height > wide.y + wide.height);
    // closed form: the area of the union of a cross
    const std::uint64_t cross = std::uint64_t(wide.width) * wide.height + std::uint64_t(tall.width) * tall.height -
                                std::uint64_t(tall.width) * wide.height;
    const ShadowCacheMapState s = state_of(f, true);
    std::vector<ShadowCacheRect> rects(shadow_cache_rect_capacity(2));
    const ShadowCachePlan p = shadow_cache_plan(s, s, cs.data(), cs.size(), rects.data(), rects.size());
    REQUIRE(p.status == Status::Ok);
    CHECK(p.action == ShadowCacheAction::Update);
    CHECK_FALSE(p.merged);
    CHECK(p.count == 3);  // the bar across, the other bar's two arms
    CHECK(p.unmerged == 2);
    CHECK(p.texels == cross);
    CHECK(check_cover(p, rects.data(), fps, f.w, f.h) == cross);
    // a capacity of 2 cannot hold the cross: one bounding rectangle (merged), still a cover
    const ShadowCachePlan q = shadow_cache_plan(s, s, cs.data(), cs.size(), rects.data(), 2);
    REQUIRE(q.status == Status::Ok);
    CHECK(q.merged);
    CHECK(q.count == 1);
    CHECK(q.texels == std::uint64_t(wide.width) * tall.height);
    check_cover(q, rects.data(), fps, f.w, f.h);
}

TEST_CASE("shadow_cache: property: the cover is disjoint, covers every moved caster, texels = brute-force union area") {
    // 3000 seeded configurations: 1..40 casters on maps of 16..96 texels (boxes, long bars across
    // the map, absent / appearing / unmoved casters), capacities from 1 to one that never merges.
    std::mt19937 rng(2727);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    int exact = 0, merged = 0, renders = 0;
    for (int it = 0; it < 3000; ++it) {
        const Fit f = top_down(16 + int(rng() % 81));
        const float half = float(f.w) * float(f.t) * 0.6f;
        const std::size_t n = 1 + rng() % 40;
        std::vector<Box> prev(n), cur(n);
        auto random_box = [&](Box& b) {
            const float kind = u01(rng);
            const float x = (2.0f * u01(rng) - 1.0f) * half, z = (2.0f * u01(rng) - 1.0f) * half;
            float ex = 0.05f + 0.75f * u01(rng), ez = 0.05f + 0.75f * u01(rng);
            if (kind < 0.15f) ex = half;       // a bar across the map in x
            else if (kind < 0.3f) ez = half;   // in z
            b = flat_box(x - ex, z - ez, x + ex, z + ez);
            if (kind > 0.95f) b = Box{{1.0f, 1.0f, 1.0f, 0.0f, 0.0f, 0.0f}};  // absent
        };
        for (std::size_t i = 0; i < n; ++i) {
            random_box(prev[i]);
            if (u01(rng) < 0.2f) cur[i] = prev[i];  // did not move
            else random_box(cur[i]);
        }
        const std::vector<ShadowCacheCaster> cs = casters_of(prev, cur);
        const std::vector<ShadowCacheRect> fps = footprints_of(f, cs);
        const std::size_t never_merges = (2 * fps.size() + 1) * (2 * fps.size() + 1);  // cells of the edges' grid
        const std::size_t caps[5] = {1, 1 + rng() % 4, 1 + rng() % 16, shadow_cache_rect_capacity(n), never_merges};
        const std::size_t cap = caps[rng() % 5];
        std::vector<ShadowCacheRect> rects(cap);
        const ShadowCacheMapState s = state_of(f, true);
        const ShadowCachePlan p = shadow_cache_plan(s, s, cs.data(), n, rects.data(), cap);
        REQUIRE(p.status == Status::Ok);
        CHECK(p.count <= cap);
        if (p.action == ShadowCacheAction::Render) {
            ++renders;
            CHECK(p.reason == ShadowCacheReason::DirtyCoversMap);
            CHECK(p.texels == std::uint64_t(f.w) * std::uint64_t(f.h));
            continue;
        }
        CHECK(p.action == (fps.empty() ? ShadowCacheAction::Keep : ShadowCacheAction::Update));
        CHECK(p.unmerged == fps.size());
        if (cap == never_merges) CHECK_FALSE(p.merged);
        (p.merged ? merged : exact) += 1;
        const std::uint64_t union_fp = check_cover(p, rects.data(), fps, f.w, f.h);
        if (!p.merged) CHECK(p.texels == union_fp);
        else CHECK(p.texels >= union_fp);
    }
    MESSAGE("configurations: exact ", exact, ", merged to fit ", merged, ", whole map ", renders);
    CHECK(exact > 1000);
    CHECK(merged > 300);
}

TEST_CASE("shadow_cache_map_state: float and double matrices accepted alike (issue #25 item 5)") {
    // A sun's orthographic map of 1-unit texels (256 x 256) moved by 3 texels in x: built in double,
    // the plan certifies the scroll anywhere; handed over as the glm::mat4 other headers return, the
    // float overload marks float_matrices and the same plan certifies it near the origin and says
    // PrecisionTooLow far from it (2^-24 relative round-off: at 1e6 units that is 0.06 texel, beyond
    // the 1/256 a scroll may carry), instead of scrolling on a matrix it cannot trust.
    const int n = 256;
    for (double origin : {0.0, 1e6}) {
        auto ortho = [&](double x0) {
            return glm::dmat4(glm::ortho(x0, x0 + n, origin, origin + n, -10.0, 10.0));
        };
        const glm::dmat4 A = ortho(origin), B = ortho(origin + 3.0);
        std::vector<ShadowCacheRect> rects(4);
        for (int as_float = 0; as_float < 2; ++as_float) {
            ShadowCacheMapState prev = as_float ? shadow_cache_map_state(glm::mat4(A), n, n, 7) : shadow_cache_map_state(A, n, n, 7);
            const ShadowCacheMapState cur = as_float ? shadow_cache_map_state(glm::mat4(B), n, n, 7) : shadow_cache_map_state(B, n, n, 7);
            CHECK(cur.float_matrices == (as_float == 1));
            CHECK(!cur.has_content);
            prev.has_content = true;
            const ShadowCachePlan p = shadow_cache_plan(prev, cur, nullptr, 0, rects.data(), rects.size());
            REQUIRE(p.status == Status::Ok);
            INFO("origin " << origin << (as_float ? " float" : " double"));
            if (as_float && origin > 0.0) {
                CHECK(p.action == ShadowCacheAction::Render);
                CHECK(p.reason == ShadowCacheReason::PrecisionTooLow);
            } else {
                CHECK(p.action == ShadowCacheAction::Scroll);
                CHECK(p.offset_x == -3);
                CHECK(p.offset_y == 0);
            }
        }
        // the footprint of a box through either matrix type
        const float box[6] = {float(origin) + 10.0f, float(origin) + 20.0f, -1.0f, float(origin) + 30.5f, float(origin) + 40.0f, 1.0f};
        const ShadowCacheFootprint fd = shadow_cache_footprint(A, n, n, box), ff = shadow_cache_footprint(glm::mat4(A), n, n, box);
        REQUIRE(fd.status == Status::Ok);
        REQUIRE(ff.status == Status::Ok);
        if (origin == 0.0) {
            CHECK(ff.rect.x == fd.rect.x);
            CHECK(ff.rect.width == fd.rect.width);
            CHECK(ff.rect.y == fd.rect.y);
            CHECK(ff.rect.height == fd.rect.height);
        }
    }
}
