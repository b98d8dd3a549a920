// Unit tests for shadowkit/virtual_shadow_map.hpp: page snapping, the page-table invariants (no two
// virtual pages on one physical page, every requested page mapped or reported), LRU eviction order,
// invalidation by moved casters against a brute force over pages (through each page's own matrix),
// the degradation of a too-small pool through a CPU emulation of the lookup, stiff cases, and a
// property test of thousands of seeded frames against a brute-force model (std::map, sorted LRU).
#include <shadowkit/virtual_shadow_map.hpp>

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <random>
#include <set>
#include <tuple>
#include <vector>

using namespace shadowkit;

namespace {

using Key = std::tuple<int, std::int64_t, std::int64_t>;  // level, absolute page x, y

VsmLayout small_layout(int levels, int pool, int pages_per_side = 8) {
    VsmLayout L;
    L.page_texels = 8;
    L.virtual_texels = 8 * pages_per_side;
    L.level_count = levels;
    L.pool_pages = pool;
    L.level0_extent_world = 16.0;
    L.depth_range_world = 1000.0;
    return L;
}

VsmFrame sun_frame(const glm::dvec3& cam, const glm::vec4& light = glm::vec4(0.3f, 1.0f, 0.2f, 0.0f)) {
    VsmFrame f;
    f.camera_position = cam;
    f.light_position = light;
    return f;
}

// Every invariant of the table and pool, checked from the data alone.
void check_table(const VsmState& s) {
    const int n = s.pages_per_side;
    std::set<std::uint32_t> slots;
    std::size_t nonzero = 0;
    for (int l = 0; l < s.layout.level_count; ++l)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const std::uint32_t t = s.page_table[vsm_table_index(s, std::uint32_t(l), std::uint32_t(x), std::uint32_t(y))];
                if (t == 0u) continue;
                ++nonzero;
                REQUIRE(((t & kVsmPageValid) != 0) != ((t & kVsmPageAllocated) != 0));
                const std::uint32_t slot = t & kVsmSlotMask;
                REQUIRE(slot < s.slots.size());
                REQUIRE(slots.insert(slot).second);  // no two virtual pages on one physical page
                const VsmSlot& e = s.slots[slot];
                REQUIRE(e.resident);
                REQUIRE(int(e.level) == l);
                REQUIRE(e.x == s.origin_x[l] + x);
                REQUIRE(e.y == s.origin_y[l] + y);
            }
    std::size_t resident = 0;
    for (const VsmSlot& e : s.slots) resident += e.resident ? 1 : 0;
    REQUIRE(resident == nonzero);
    REQUIRE(resident + s.free_count == s.slots.size());
}

std::uint32_t entry_of(const VsmState& s, int l, std::int64_t ax, std::int64_t ay) {
    const std::int64_t x = ax - s.origin_x[l], y = ay - s.origin_y[l];
    if (x < 0 || y < 0 || x >= s.pages_per_side || y >= s.pages_per_side) return 0u;
    return s.page_table[vsm_table_index(s, std::uint32_t(l), std::uint32_t(x), std::uint32_t(y))];
}

// The GPU marking pass, emulated: the page of `level` that holds world point p (through the level's
// lookup matrix, not the planner's snapping).
bool mark(const VsmState& s, int level, const glm::dvec3& p, VsmPageRequest& q) {
    const glm::dvec4 h = s.levels[level].world_to_uv * glm::dvec4(p, 1.0);
    const double u = h.x / h.w * s.pages_per_side, v = h.y / h.w * s.pages_per_side;
    if (!(u >= 0.0 && v >= 0.0 && u < s.pages_per_side && v < s.pages_per_side)) return false;
    q.level = std::uint32_t(level);
    q.x = std::uint32_t(std::floor(u));
    q.y = std::uint32_t(std::floor(v));
    return true;
}

// The lookup the docs prescribe, emulated: from `level` up, the first entry with kVsmPageValid on
// the page holding p (toroidal column / row from origin_mod). Returns the level found or -1.
int lookup(const VsmState& s, int level, const glm::dvec3& p, std::uint32_t& slot) {
    const int n = s.pages_per_side;
    for (int l = level; l < s.layout.level_count; ++l) {
        const glm::dvec4 h = s.levels[l].world_to_uv * glm::dvec4(p, 1.0);
        const double u = h.x / h.w * n, v = h.y / h.w * n;
        if (!(u >= 0.0 && v >= 0.0 && u < n && v < n)) return -1;  // outside a coarser window: impossible by construction
        const int px = int(std::floor(u)), py = int(std::floor(v));
        const int col = (px + s.levels[l].origin_mod_x) % n, row = (py + s.levels[l].origin_mod_y) % n;
        const std::uint32_t t = s.page_table[std::size_t(l) * std::size_t(n * n) + std::size_t(row * n + col)];
        if (t & kVsmPageValid) {
            slot = t & kVsmSlotMask;
            return l;
        }
    }
    return -1;
}

bool box_overlaps_page(const glm::dmat4& page_vp, const float* b) {
    double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
    for (int c = 0; c < 8; ++c) {
        const glm::dvec4 h = page_vp * glm::dvec4(b[(c & 1) ? 3 : 0], b[(c & 2) ? 4 : 1], b[(c & 4) ? 5 : 2], 1.0);
        for (int k = 0; k < 2; ++k) {
            lo[k] = std::min(lo[k], h[k] / h.w);
            hi[k] = std::max(hi[k], h[k] / h.w);
        }
    }
    return hi[0] >= -1.0 && lo[0] < 1.0 && hi[1] >= -1.0 && lo[1] < 1.0;
}

std::vector<VsmPageRender> page_buffer(const VsmLayout& L) { return std::vector<VsmPageRender>(std::size_t(L.pool_pages)); }

}  // namespace

TEST_CASE("vsm_state_init validates the layout") {
    VsmState s;
    VsmLayout L = small_layout(3, 10);
    CHECK(vsm_state_init(L, s).status == Status::Ok);
    CHECK(s.pages_per_side == 8);
    CHECK(s.page_table.size() == 3u * 64u);
    VsmLayout bad = L;
    bad.level0_extent_world = 0.0;  // required
    CHECK(vsm_state_init(bad, s).status == Status::InvalidArgument);
    bad = L; bad.virtual_texels = 8 * 8 + 4;
    CHECK(vsm_state_init(bad, s).status == Status::InvalidArgument);
    bad = L; bad.level_count = 17;
    CHECK(vsm_state_init(bad, s).status == Status::InvalidArgument);
    bad = L; bad.level_count = 0;
    CHECK(vsm_state_init(bad, s).status == Status::InvalidArgument);
    bad = L; bad.pool_pages = 0;
    CHECK(vsm_state_init(bad, s).status == Status::InvalidArgument);
    bad = L; bad.level0_extent_world = 1e-300;  // its page matrices would overflow double
    CHECK(vsm_state_init(bad, s).status == Status::InvalidArgument);
    bad = L; bad.depth_range_world = 1e31;
    CHECK(vsm_state_init(bad, s).status == Status::InvalidArgument);
    bad = L; bad.level0_extent_world = std::nan("");
    CHECK(vsm_state_init(bad, s).status == Status::NonFinite);
    bad = L; bad.virtual_texels = 8;  // one page per side: no clipmap nesting
    CHECK(vsm_state_init(bad, s).status == Status::InvalidArgument);
    VsmLayout def;  // the defaults: 16k virtual, 128-texel pages, 16 levels
    def.level0_extent_world = 64.0;
    const VsmInit r = vsm_state_init(def, s);
    CHECK(r.status == Status::Ok);
    CHECK(s.pages_per_side == 128);
    CHECK(r.table_entries == 16u * 128u * 128u);
}

TEST_CASE("vsm_plan rejects bad frames and leaves the state unchanged") {
    VsmState s;
    const VsmLayout L = small_layout(2, 4);
    REQUIRE(vsm_state_init(L, s).status == Status::Ok);
    auto pages = page_buffer(L);
    VsmFrame f = sun_frame(glm::dvec3(0.0));
    VsmPageRequest q{0, 1, 1};
    f.requests = &q;
    f.request_count = 1;
    VsmFrame g = f;
    g.light_position = glm::vec4(0.0f);
    CHECK(vsm_plan(s, g, pages.data(), pages.size()).status == Status::InvalidLight);
    g = f; g.light_position.w = -1.0f;
    CHECK(vsm_plan(s, g, pages.data(), pages.size()).status == Status::InvalidLight);
    g = f; g.camera_position.x = INFINITY;
    CHECK(vsm_plan(s, g, pages.data(), pages.size()).status == Status::NonFinite);
    VsmPageRequest far{0, 8, 0};
    g = f; g.requests = &far;
    CHECK(vsm_plan(s, g, pages.data(), pages.size()).status == Status::IndexOutOfRange);
    VsmPageRequest lvl{2, 0, 0};
    g = f; g.requests = &lvl;
    CHECK(vsm_plan(s, g, pages.data(), pages.size()).status == Status::IndexOutOfRange);
    CHECK(vsm_plan(s, f, pages.data(), 3).status == Status::InvalidArgument);  // needs pool_pages
    g = f; g.camera_position = glm::dvec3(0.0, 1e19, 0.0);  // 1e16 depth ranges along the light: not exact
    CHECK(vsm_plan(s, g, pages.data(), pages.size()).status == Status::Overflow);
    g = f; g.camera_position = glm::dvec3(1e17, 0.0, 0.0);  // 5e16 level-0 pages from the origin
    CHECK(vsm_plan(s, g, pages.data(), pages.size()).status == Status::Overflow);
    g = f; g.requests = nullptr;
    CHECK(vsm_plan(s, g, pages.data(), pages.size()).status == Status::InvalidArgument);
    g = f; g.light_position = glm::vec4(0, 5, 0, 1);  // a spot needs a direction, a cone and 1 level
    CHECK(vsm_plan(s, g, pages.data(), pages.size()).status == Status::InvalidLight);
    CHECK(s.frame == 0u);
    CHECK(s.free_count == 4u);
}

TEST_CASE("snapping: a move of less than a page keeps every page, a move of one page shifts by one page") {
    for (const double base : {0.0, 1.0e6}) {
        CAPTURE(base);
        VsmState s;
        VsmLayout L = small_layout(4, 256);
        REQUIRE(vsm_state_init(L, s).status == Status::Ok);
        auto pages = page_buffer(L);
        const glm::vec4 light(0.3f, 1.0f, 0.2f, 0.0f);
        glm::dvec3 ax, ay, az;
        {  // the light basis, from the state after one plan
            VsmFrame f0 = sun_frame(glm::dvec3(base, 0.0, base), light);
            REQUIRE(vsm_plan(s, f0, pages.data(), pages.size()).status == Status::Ok);
            ax = s.axis_x; ay = s.axis_y; az = s.axis_z;
            CHECK(std::fabs(glm::dot(ax, ay)) < 1e-12);
            CHECK(glm::length(glm::cross(az, glm::normalize(glm::dvec3(light)))) < 1e-12);
        }
        // the camera at the center of its level-0 page
        const double P0 = L.level0_extent_world / 8.0;
        const glm::dvec3 start(base, 0.0, base);
        const double u0 = (std::floor(glm::dot(start, ax) / P0) + 0.5) * P0 - glm::dot(start, ax);
        const double v0 = (std::floor(glm::dot(start, ay) / P0) + 0.5) * P0 - glm::dot(start, ay);
        const glm::dvec3 cam = start + u0 * ax + v0 * ay;
        // request every page of every level around 9 world points near the camera
        std::vector<glm::dvec3> points;
        for (int i = -1; i <= 1; ++i)
            for (int j = -1; j <= 1; ++j) points.push_back(cam + (0.9 * P0 * i) * ax + (0.9 * P0 * j) * ay);
        VsmFrame f = sun_frame(cam, light);
        auto request_all = [&](std::vector<VsmPageRequest>& out) {
            out.clear();
            for (int l = 0; l < 4; ++l)
                for (const glm::dvec3& p : points) {
                    VsmPageRequest q;
                    REQUIRE(mark(s, l, p, q));
                    out.push_back(q);
                }
        };
        std::vector<VsmPageRequest> req;
        REQUIRE(vsm_plan(s, f, pages.data(), pages.size()).status == Status::Ok);  // place the levels on cam
        // the camera lies in page n/2 of every level (centered window)
        for (int l = 0; l < 4; ++l) {
            VsmPageRequest q;
            REQUIRE(mark(s, l, cam, q));
            CHECK(q.x == 4u);
            CHECK(q.y == 4u);
        }
        request_all(req);
        f.requests = req.data();
        f.request_count = req.size();
        VsmPlan p = vsm_plan(s, f, pages.data(), pages.size());
        REQUIRE(p.status == Status::Ok);
        const std::size_t distinct = p.requested;
        CHECK(p.allocated == distinct);
        check_table(s);
        std::int64_t ox[4], oy[4];
        for (int l = 0; l < 4; ++l) { ox[l] = s.origin_x[l]; oy[l] = s.origin_y[l]; }
        // less than a page (0.49 of a level-0 page in any direction): nothing scrolls, nothing renders
        for (const glm::dvec2 d : {glm::dvec2(0.49, 0.0), glm::dvec2(-0.49, 0.3), glm::dvec2(0.2, -0.49)}) {
            f.camera_position = cam + (d.x * P0) * ax + (d.y * P0) * ay + 3.0 * az;  // along the light too
            request_all(req);
            p = vsm_plan(s, f, pages.data(), pages.size());
            REQUIRE(p.status == Status::Ok);
            CHECK(p.kept == distinct);
            CHECK(p.count == 0u);
            CHECK(p.scrolled_out == 0u);
            for (int l = 0; l < 4; ++l) {
                CHECK(s.origin_x[l] == ox[l]);
                CHECK(s.origin_y[l] == oy[l]);
            }
        }
        // one level-0 page along x: level 0 shifts by exactly one page; the same world pages are kept
        f.camera_position = cam + P0 * ax;
        // marking runs with the windows of this frame: plan once with no requests to place, then mark
        f.request_count = 0;
        p = vsm_plan(s, f, pages.data(), pages.size());
        REQUIRE(p.status == Status::Ok);
        CHECK(s.origin_x[0] == ox[0] + 1);
        CHECK(s.origin_y[0] == oy[0]);
        for (int l = 1; l < 4; ++l) {  // coarser levels: the camera's page center moved by P0 = P_l / 2^l
            const std::int64_t expect = std::int64_t(std::floor(glm::dot(f.camera_position, ax) / (P0 * std::ldexp(1.0, l)))) - 4;
            CHECK(s.origin_x[l] == expect);
        }
        CHECK(p.scrolled_out == 0u);  // the points' pages are 1 page from the center: still on the window
        request_all(req);
        f.requests = req.data();
        f.request_count = req.size();
        p = vsm_plan(s, f, pages.data(), pages.size());
        REQUIRE(p.status == Status::Ok);
        CHECK(p.kept == distinct);
        CHECK(p.count == 0u);
        check_table(s);
    }
}

TEST_CASE("LRU: the least recently requested page is evicted first") {
    VsmState s;
    const VsmLayout L = small_layout(1, 3);
    REQUIRE(vsm_state_init(L, s).status == Status::Ok);
    auto pages = page_buffer(L);
    VsmFrame f = sun_frame(glm::dvec3(0.0));
    const VsmPageRequest A{0, 0, 0}, B{0, 1, 0}, C{0, 2, 0}, D{0, 3, 0}, E{0, 4, 0};
    auto run = [&](VsmPageRequest q) {
        f.requests = &q;
        f.request_count = 1;
        const VsmPlan p = vsm_plan(s, f, pages.data(), pages.size());
        REQUIRE(p.status == Status::Ok);
        check_table(s);
        return p;
    };
    auto resident = [&](VsmPageRequest q) {
        return (s.page_table[vsm_table_index(s, q.level, q.x, q.y)] & kVsmPageValid) != 0;
    };
    run(A); run(B); run(C);
    CHECK(run(A).kept == 1u);  // A most recent: order B, C, A
    VsmPlan p = run(D);
    CHECK(p.evicted == 1u);
    CHECK(!resident(B));
    CHECK(resident(A));
    CHECK(resident(C));
    p = run(E);
    CHECK(p.evicted == 1u);
    CHECK(!resident(C));
    CHECK(resident(A));
    CHECK(resident(D));
    p = run(B);
    CHECK(!resident(A));  // A (frame 4) older than D (5) and E (6)
    CHECK(resident(D));
    CHECK(resident(E));
    CHECK(p.allocated == 1u);
    CHECK(p.count == 1u);
}

TEST_CASE("a moved caster makes stale exactly the resident pages its old and new bounds overlap") {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> U(-30.0f, 30.0f), S(0.2f, 6.0f);
    for (int trial = 0; trial < 60; ++trial) {
        VsmState s;
        const VsmLayout L = small_layout(3, 3 * 64);
        REQUIRE(vsm_state_init(L, s).status == Status::Ok);
        auto pages = page_buffer(L);
        VsmFrame f = sun_frame(glm::dvec3(1.5, 0.0, -2.0), trial % 2 ? glm::vec4(0.3f, 1.0f, 0.2f, 0.0f) : glm::vec4(-1.0f, 0.05f, 0.4f, 0.0f));
        std::vector<VsmPageRequest> all;
        for (std::uint32_t l = 0; l < 3; ++l)
            for (std::uint32_t y = 0; y < 8; ++y)
                for (std::uint32_t x = 0; x < 8; ++x)
                    if ((std::uint32_t(rng()) & 3u) != 0u) all.push_back(VsmPageRequest{l, x, y});
        f.requests = all.data();
        f.request_count = all.size();
        REQUIRE(vsm_plan(s, f, pages.data(), pages.size()).status == Status::Ok);
        // the page matrices of every resident page, recorded before the move
        std::map<Key, glm::dmat4> mats;
        for (std::size_t i = 0; i < all.size(); ++i) {
            const VsmSlot& e = s.slots[s.page_table[vsm_table_index(s, all[i].level, all[i].x, all[i].y)] & kVsmSlotMask];
            mats[Key(int(e.level), e.x, e.y)] = glm::dmat4(0.0);
        }
        // page matrices: from the first plan's list (every page was rendered once)
        // (re-derived here from each rendered page)
        VsmCasterMove m;
        const float c0[3] = {U(rng), U(rng) * 0.2f, U(rng)}, c1[3] = {c0[0] + U(rng) * 0.1f, c0[1], c0[2] + U(rng) * 0.1f};
        for (int k = 0; k < 3; ++k) {
            const float h = S(rng);
            m.previous_bounds[k] = c0[k] - h; m.previous_bounds[k + 3] = c0[k] + h;
            m.bounds[k] = c1[k] - h; m.bounds[k + 3] = c1[k] + h;
        }
        if (trial % 7 == 3) m.bounds[0] = m.bounds[3] + 1.0f;  // removed: only the old bounds count
        f.moved_casters = &m;
        f.moved_caster_count = 1;
        f.request_count = 0;
        const VsmPlan p = vsm_plan(s, f, pages.data(), pages.size());
        REQUIRE(p.status == Status::Ok);
        check_table(s);
        // brute force: every page of every level, through the page's own world -> clip matrix
        std::size_t expect = 0;
        for (const auto& kv : mats) {
            const int l = std::get<0>(kv.first);
            const std::int64_t x = std::get<1>(kv.first), y = std::get<2>(kv.first);
            const glm::dmat4 vp = detail::vsm_page_matrix(s, l, x, y);
            const bool hit = box_overlaps_page(vp, m.previous_bounds) ||
                             (!detail::vsm_box_empty(m.bounds) && box_overlaps_page(vp, m.bounds));
            const std::uint32_t t = entry_of(s, l, x, y);
            REQUIRE(t != 0u);
            CHECK(((t & kVsmPageAllocated) != 0) == hit);
            expect += hit ? 1 : 0;
        }
        CHECK(p.invalidated == expect);
        // requesting everything again re-renders exactly the stale pages, in place
        f.requests = all.data();
        f.request_count = all.size();
        f.moved_caster_count = 0;
        const VsmPlan q = vsm_plan(s, f, pages.data(), pages.size());
        CHECK(q.rerendered == expect);
        CHECK(q.count == expect);
        CHECK(q.allocated == 0u);
        for (std::size_t i = 0; i < q.count; ++i) CHECK((box_overlaps_page(pages[i].view_proj, m.previous_bounds) ||
                                                        box_overlaps_page(pages[i].view_proj, m.bounds)));
    }
}

TEST_CASE("each page's matrix maps exactly its page: the lookup's page and the render's agree") {
    VsmState s;
    const VsmLayout L = small_layout(5, 5 * 64);
    REQUIRE(vsm_state_init(L, s).status == Status::Ok);
    auto pages = page_buffer(L);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    for (const glm::vec4 light : {glm::vec4(0.3f, 1.0f, 0.2f, 0.0f), glm::vec4(0, 1, 0, 0), glm::vec4(0, -1, 0, 0),
                                  glm::vec4(1.0f, 1e-4f, 0.0f, 0.0f), glm::vec4(0, 0, 1, 0)}) {
        for (const double base : {0.0, 1.0e6, -3.0e5}) {
            const glm::dvec3 cam(base, 10.0, base * 0.5);
            VsmFrame f = sun_frame(cam, light);
            std::vector<VsmPageRequest> req;
            std::vector<std::pair<int, glm::dvec3>> pts;
            REQUIRE(vsm_plan(s, f, pages.data(), pages.size()).status == Status::Ok);
            for (int i = 0; i < 200; ++i) {
                const int l = int(std::uint32_t(rng()) % 5u);
                const double r = 16.0 * std::ldexp(1.0, l) * 0.45;
                const glm::dvec3 p = cam + glm::dvec3(U(rng) * r, U(rng) * r, U(rng) * r) * 0.5;
                VsmPageRequest q;
                if (!mark(s, l, p, q)) continue;
                req.push_back(q);
                pts.emplace_back(l, p);
            }
            f.requests = req.data();
            f.request_count = req.size();
            const VsmPlan pl = vsm_plan(s, f, pages.data(), pages.size());
            REQUIRE(pl.status == Status::Ok);
            check_table(s);
            for (const auto& lp : pts) {
                std::uint32_t slot = 0;
                REQUIRE(lookup(s, lp.first, lp.second, slot) == lp.first);
                const VsmSlot& e = s.slots[slot];
                const glm::dvec4 h = detail::vsm_page_matrix(s, int(e.level), e.x, e.y) * glm::dvec4(lp.second, 1.0);
                CHECK(h.x >= -1.0 - 1e-9);
                CHECK(h.x <= 1.0 + 1e-9);
                CHECK(h.y >= -1.0 - 1e-9);
                CHECK(h.y <= 1.0 + 1e-9);
                CHECK(h.z >= -1.0);  // within the depth range around the camera
                CHECK(h.z <= 1.0);
            }
        }
    }
}

TEST_CASE("pool too small: BufferTooSmall with the pages needed, finest levels fall back, never a hole") {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    for (const int pool : {1, 2, 5, 17, 40}) {
        for (const int levels : {1, 3, 6}) {
          for (const glm::dvec3 cam : {glm::dvec3(3.0, 0.0, 4.0), glm::dvec3(-37.0, 1.0, -53.0), glm::dvec3(-1e6, 0.0, 2e5)}) {
            CAPTURE(pool);
            CAPTURE(levels);
            VsmState s;
            const VsmLayout L = small_layout(levels, pool);
            REQUIRE(vsm_state_init(L, s).status == Status::Ok);
            auto pages = page_buffer(L);
            VsmFrame f = sun_frame(cam);
            REQUIRE(vsm_plan(s, f, pages.data(), pages.size()).status == Status::Ok);
            std::vector<VsmPageRequest> req;
            std::vector<std::pair<int, glm::dvec3>> pts;
            std::set<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>> distinct;
            for (int i = 0; i < 60; ++i) {
                const int l = int(std::uint32_t(rng()) % std::uint32_t(levels));
                // points near the camera (the coarsest level's requests stay few, as a view's do)
                const glm::dvec3 p = cam + glm::dvec3(U(rng), U(rng), U(rng)) * (3.0 * std::ldexp(1.0, l));
                VsmPageRequest q;
                REQUIRE(mark(s, l, p, q));
                req.push_back(q);
                pts.emplace_back(l, p);
                distinct.insert(std::make_tuple(q.level, q.x, q.y));
            }
            f.requests = req.data();
            f.request_count = req.size();
            const VsmPlan p = vsm_plan(s, f, pages.data(), pages.size());
            CHECK(p.needed == distinct.size());
            CHECK(p.status == (distinct.size() > std::size_t(pool) ? Status::BufferTooSmall : Status::Ok));
            check_table(s);
            CHECK(p.count <= std::size_t(pool));
            std::size_t holes = 0, own = 0;
            for (const auto& lp : pts) {
                std::uint32_t slot = 0;
                const int found = lookup(s, lp.first, lp.second, slot);
                if (found < 0) { ++holes; continue; }
                CHECK(found >= lp.first);
                // a fresh state: the chain is mapped at the point's level, or (finer than the finest
                // level kept) at the finest level kept or the next coarser one
                if (lp.first > p.finest_level) CHECK(found == lp.first);
                else CHECK((found == p.finest_level || found == p.finest_level + 1));
                if (found == lp.first) ++own;
                // the page found holds the point
                const VsmSlot& e = s.slots[slot];
                const glm::dvec4 h = detail::vsm_page_matrix(s, int(e.level), e.x, e.y) * glm::dvec4(lp.second, 1.0);
                CHECK(std::fabs(h.x) <= 1.0 + 1e-9);
                CHECK(std::fabs(h.y) <= 1.0 + 1e-9);
            }
            if (p.unmapped == 0) CHECK(holes == 0u);
            else CHECK(p.finest_level == levels - 1);  // holes only once everything fell to the coarsest level
            if (p.status == Status::Ok) CHECK(own == pts.size());
            if (p.status == Status::BufferTooSmall) CHECK((p.fallback > 0 || p.unmapped > 0));
            // the fallback goes page by page: a too-small pool is used to its last page
            if (p.status == Status::BufferTooSmall) CHECK(p.count == std::size_t(pool));
          }
        }
    }
}

TEST_CASE("stiff: 0 requests, pool of 1, level counts 1 and 16, light parallel to view and grazing") {
    for (const int levels : {1, 16}) {
        VsmState s;
        VsmLayout L = small_layout(levels, 1, 4);
        REQUIRE(vsm_state_init(L, s).status == Status::Ok);
        auto pages = page_buffer(L);
        VsmFrame f = sun_frame(glm::dvec3(0.0, 0.0, 0.0), glm::vec4(0.0f, 0.0f, 1.0f, 0.0f));  // along a view down -z
        VsmPlan p = vsm_plan(s, f, pages.data(), pages.size());
        CHECK(p.status == Status::Ok);
        CHECK(p.count == 0u);
        CHECK(p.finest_level == levels);
        VsmPageRequest q[3] = {{0, 1, 2}, {0, 1, 2}, {std::uint32_t(levels - 1), 3, 3}};
        f.requests = q;
        f.request_count = 3;
        p = vsm_plan(s, f, pages.data(), pages.size());
        if (levels == 1) {
            CHECK(p.needed == 2u);
            CHECK(p.status == Status::BufferTooSmall);
            CHECK(p.count == 1u);
            CHECK(p.unmapped == 1u);
        } else {
            CHECK(p.needed == 2u);
            CHECK(p.status == Status::BufferTooSmall);
            // level 0's page fell back level by level to the coarsest, where two pages remain for one slot
            CHECK(p.fallback == 1u);
            CHECK(p.unmapped == 1u);
            CHECK(p.finest_level == 15);
            CHECK(p.count == 1u);
            CHECK(pages[0].level == 15u);
        }
        check_table(s);
        // grazing light, far from the origin
        f.light_position = glm::vec4(1.0f, 1e-6f, 0.0f, 0.0f);
        f.camera_position = glm::dvec3(1e6, 2.0, -1e6);
        p = vsm_plan(s, f, pages.data(), pages.size());
        CHECK((p.status == Status::Ok || p.status == Status::BufferTooSmall));
        CHECK(p.everything_invalidated);  // the light changed
        check_table(s);
    }
}

TEST_CASE("spot light: one virtual map whose pages tile the spot's projection") {
    VsmState s;
    VsmLayout L = small_layout(1, 64);
    L.spot_near_world = 0.5;
    L.spot_far_world = 100.0;
    REQUIRE(vsm_state_init(L, s).status == Status::Ok);
    auto pages = page_buffer(L);
    VsmFrame f;
    f.light_position = glm::vec4(2.0f, 10.0f, 1.0f, 1.0f);
    f.spot_direction = glm::vec3(0.1f, -1.0f, 0.05f);
    f.spot_cone_half_angle_radians = 0.6f;
    std::vector<VsmPageRequest> all;
    for (std::uint32_t y = 0; y < 8; ++y)
        for (std::uint32_t x = 0; x < 8; ++x) all.push_back(VsmPageRequest{0, x, y});
    f.requests = all.data();
    f.request_count = all.size();
    const VsmPlan p = vsm_plan(s, f, pages.data(), pages.size());
    REQUIRE(p.status == Status::Ok);
    REQUIRE(p.count == 64u);
    check_table(s);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> U(-3.0, 3.0);
    int inside = 0;
    for (int i = 0; i < 500; ++i) {
        const glm::dvec3 pt(2.0 + U(rng), U(rng), 1.0 + U(rng));
        const glm::dvec4 h = s.spot_view_proj * glm::dvec4(pt, 1.0);
        if (!(h.w > 0.0) || std::fabs(h.x / h.w) >= 1.0 || std::fabs(h.y / h.w) >= 1.0) continue;
        ++inside;
        int hits = 0;
        for (std::size_t k = 0; k < p.count; ++k) {
            const glm::dvec4 c = pages[k].view_proj * glm::dvec4(pt, 1.0);
            if (c.x >= -c.w && c.x < c.w && c.y >= -c.w && c.y < c.w) ++hits;
            CHECK(std::fabs(c.z / c.w - h.z / h.w) < 1e-9);  // depth untouched by the crop
        }
        CHECK(hits == 1);
    }
    CHECK(inside > 100);
}

TEST_CASE("vsm_page_casters lists exactly the casters whose boxes overlap each page") {
    std::mt19937 rng(21);
    std::uniform_real_distribution<float> U(-20.0f, 20.0f), S(0.1f, 5.0f);
    VsmState s;
    const VsmLayout L = small_layout(3, 3 * 64);
    REQUIRE(vsm_state_init(L, s).status == Status::Ok);
    auto pages = page_buffer(L);
    VsmFrame f = sun_frame(glm::dvec3(-1.0, 0.0, 2.5));
    std::vector<VsmPageRequest> req;
    for (std::uint32_t l = 0; l < 3; ++l)
        for (std::uint32_t y = 0; y < 8; ++y)
            for (std::uint32_t x = 0; x < 8; ++x)
                if (std::uint32_t(rng()) % 3u) req.push_back(VsmPageRequest{l, x, y});
    f.requests = req.data();
    f.request_count = req.size();
    const VsmPlan p = vsm_plan(s, f, pages.data(), pages.size());
    REQUIRE(p.status == Status::Ok);
    std::vector<float> boxes;
    for (int c = 0; c < 40; ++c) {
        const float x = U(rng), y = U(rng) * 0.1f, z = U(rng), h = S(rng);
        const float b[6] = {x - h, y - h, z - h, x + h, y + h, z + h};
        boxes.insert(boxes.end(), b, b + 6);
    }
    boxes[6 * 5] = boxes[6 * 5 + 3] + 1.0f;  // an empty box: never listed
    std::vector<std::uint32_t> first(p.count), counts(p.count), idx(4);
    VsmPageCasters r = vsm_page_casters(s, pages.data(), p.count, boxes.data(), 40, first.data(), counts.data(), idx.data(), idx.size());
    REQUIRE(r.status == Status::BufferTooSmall);
    idx.resize(r.needed);
    r = vsm_page_casters(s, pages.data(), p.count, boxes.data(), 40, first.data(), counts.data(), idx.data(), idx.size());
    REQUIRE(r.status == Status::Ok);
    for (std::size_t i = 0; i < p.count; ++i) {
        std::set<std::uint32_t> got(idx.begin() + first[i], idx.begin() + first[i] + counts[i]), want;
        for (std::uint32_t c = 0; c < 40; ++c)
            if (!detail::vsm_box_empty(&boxes[6 * c]) && box_overlaps_page(pages[i].view_proj, &boxes[6 * c])) want.insert(c);
        CHECK(got == want);
        CHECK(got.size() == counts[i]);
    }
    // a list that is not the last plan's is rejected
    VsmPageRender fake = pages[0];
    fake.slot = pages[0].slot == 0 ? 1u : 0u;
    CHECK(vsm_page_casters(s, &fake, 1, boxes.data(), 40, first.data(), counts.data(), idx.data(), idx.size()).status ==
          Status::InvalidArgument);
}

TEST_CASE("vsm_relative_matrix keeps whole texels at 1e6 where a float world matrix does not") {
    VsmState s;
    VsmLayout L = small_layout(2, 16);
    L.page_texels = 128;
    L.virtual_texels = 8 * 128;
    REQUIRE(vsm_state_init(L, s).status == Status::Ok);
    auto pages = page_buffer(L);
    const glm::dvec3 cam(1.0e6, 5.0, -1.0e6);
    VsmFrame f = sun_frame(cam);
    VsmPageRequest q{0, 4, 4};
    f.requests = &q;
    f.request_count = 1;
    REQUIRE(vsm_plan(s, f, pages.data(), pages.size()).status == Status::Ok);
    const glm::dmat4 m = pages[0].view_proj;
    const VsmMatrix rel = vsm_relative_matrix(m, cam);
    REQUIRE(rel.status == Status::Ok);
    const glm::dvec3 p = cam + glm::dvec3(0.3, -0.2, 0.1);
    const glm::dvec4 exact = m * glm::dvec4(p, 1.0);
    const glm::vec4 fr = rel.matrix * glm::vec4(glm::vec3(p - cam), 1.0f);
    const double texel = 2.0 / double(L.page_texels);  // one texel in NDC
    CHECK(std::fabs(double(fr.x) - exact.x) < 0.01 * texel);
    CHECK(std::fabs(double(fr.y) - exact.y) < 0.01 * texel);
    const glm::vec4 naive = glm::mat4(m) * glm::vec4(glm::vec3(p), 1.0f);
    CHECK(std::fabs(double(naive.x) - exact.x) > 0.1 * texel);  // why the relative matrix exists
    CHECK(vsm_relative_matrix(m, glm::dvec3(NAN, 0, 0)).status == Status::NonFinite);
}

TEST_CASE("property: thousands of seeded frames against a brute-force model") {
    struct Model {
        std::int64_t ox[4] = {}, oy[4] = {};
        std::map<Key, std::pair<std::uint64_t, bool>> res;  // page -> (LRU rank, stale)
        bool placed = false;
        double depth_center = 0.0;
    };
    int frames = 0, degraded = 0, evictions = 0, invalidations = 0, scrolls = 0;
    for (std::uint32_t seed = 1; seed <= 40; ++seed) {
        std::mt19937 rng(seed);
        const int levels = 1 + int(std::uint32_t(rng()) % 4u);
        const int pool = 1 + int(std::uint32_t(rng()) % 48u);
        VsmState s;
        const VsmLayout L = small_layout(levels, pool);
        REQUIRE(vsm_state_init(L, s).status == Status::Ok);
        auto pages = page_buffer(L);
        Model M;
        std::uint64_t rank = 0;
        glm::dvec3 cam(double(int(std::uint32_t(rng()) % 100u)) * 7.3, 0.0, 3.1);
        const glm::vec4 light = seed % 3 ? glm::vec4(0.3f, 1.0f, 0.2f, 0.0f) : glm::vec4(-0.7f, 0.3f, 0.5f, 0.0f);
        std::uniform_real_distribution<double> U(-1.0, 1.0);
        std::uniform_real_distribution<float> B(-25.0f, 25.0f), H(0.1f, 4.0f);
        for (int frame = 0; frame < 200; ++frame, ++frames) {
            // camera: still, a sub-page step, or a few pages (sometimes a jump), some along the light
            const std::uint32_t mv = std::uint32_t(rng()) % 8u;
            if (mv >= 4) cam += glm::dvec3(U(rng), U(rng) * 0.2, U(rng)) * (mv == 7 ? 60.0 : 2.5);
            if (mv == 3) cam.y += 300.0 * U(rng);  // may step the depth center
            VsmFrame f = sun_frame(cam, light);
            // requests relative to this frame's windows: computed by the model from the camera
            if (frame == 0) {
                REQUIRE(vsm_plan(s, f, pages.data(), pages.size()).status == Status::Ok);
                for (int l = 0; l < levels; ++l) { M.ox[l] = s.origin_x[l]; M.oy[l] = s.origin_y[l]; }
                M.placed = true;
                M.depth_center = s.depth_center;
            }
            std::int64_t nx[4], ny[4];
            for (int l = 0; l < levels; ++l) {
                const double P = 16.0 * std::ldexp(1.0, l) / 8.0;
                nx[l] = std::int64_t(std::floor(glm::dot(cam, s.axis_x) / P)) - 4;
                ny[l] = std::int64_t(std::floor(glm::dot(cam, s.axis_y) / P)) - 4;
            }
            const double step = 500.0;
            const double dc = step * std::floor(glm::dot(cam, s.axis_z) / step + 0.5);
            std::vector<VsmPageRequest> req;
            const std::size_t nreq = std::uint32_t(rng()) % 5u == 0 ? 0u : std::uint32_t(rng()) % 40u;
            for (std::size_t i = 0; i < nreq; ++i) {
                const std::uint32_t l = std::uint32_t(rng()) % std::uint32_t(levels);
                // clustered near the center, as a view's pages are
                req.push_back(VsmPageRequest{l, 2u + std::uint32_t(rng()) % 4u, 2u + std::uint32_t(rng()) % 4u});
            }
            std::vector<VsmCasterMove> moves(std::uint32_t(rng()) % 3u);
            for (VsmCasterMove& m : moves) {
                const float c[3] = {B(rng), B(rng) * 0.1f, B(rng)};
                for (int k = 0; k < 3; ++k) {
                    const float h = H(rng);
                    m.previous_bounds[k] = c[k] - h; m.previous_bounds[k + 3] = c[k] + h;
                    m.bounds[k] = c[k] + 1.0f - h; m.bounds[k + 3] = c[k] + 1.0f + h;
                }
            }
            f.requests = req.data();
            f.request_count = req.size();
            f.moved_casters = moves.data();
            f.moved_caster_count = moves.size();
            // ---- the model: scroll, depth step, invalidation, requests, LRU
            std::size_t m_scrolled = 0, m_invalid = 0;
            for (auto it = M.res.begin(); it != M.res.end();) {
                const int l = std::get<0>(it->first);
                const std::int64_t x = std::get<1>(it->first), y = std::get<2>(it->first);
                if (x < nx[l] || x >= nx[l] + 8 || y < ny[l] || y >= ny[l] + 8) { it = M.res.erase(it); ++m_scrolled; }
                else ++it;
            }
            if (dc != M.depth_center)
                for (auto& kv : M.res) kv.second.second = true;
            M.depth_center = dc;
            for (int l = 0; l < levels; ++l) { M.ox[l] = nx[l]; M.oy[l] = ny[l]; }
            VsmState sc = s;  // page matrices of the new frame: the depth center placed in a copy
            sc.depth_center = dc;
            for (auto& kv : M.res) {
                const glm::dmat4 vp = detail::vsm_page_matrix(sc, std::get<0>(kv.first), std::get<1>(kv.first), std::get<2>(kv.first));
                bool hit = false;
                for (const VsmCasterMove& m : moves) hit = hit || box_overlaps_page(vp, m.previous_bounds) || box_overlaps_page(vp, m.bounds);
                if (hit && !kv.second.second) { kv.second.second = true; ++m_invalid; }
            }
            std::vector<Key> wanted;
            std::set<Key> wanted_set;
            for (const VsmPageRequest& q : req) {
                const Key k(int(q.level), nx[q.level] + q.x, ny[q.level] + q.y);
                if (wanted_set.insert(k).second) wanted.push_back(k);
            }
            const VsmPlan p = vsm_plan(s, f, pages.data(), pages.size());
            check_table(s);
            CHECK(p.needed == wanted.size());
            CHECK(p.scrolled_out == m_scrolled);
            if (dc == s.depth_center && !p.everything_invalidated) CHECK(p.invalidated == m_invalid);
            scrolls += int(p.scrolled_out);
            invalidations += int(p.invalidated);
            for (int l = 0; l < levels; ++l) {
                CHECK(s.origin_x[l] == nx[l]);
                CHECK(s.origin_y[l] == ny[l]);
            }
            if (wanted.size() > std::size_t(pool)) {
                CHECK(p.status == Status::BufferTooSmall);
                ++degraded;
                // resynchronize the model from the table (the degradation is checked by its own test)
                M.res.clear();
                for (std::uint32_t i = s.lru_tail; i != kVsmNone; i = s.slots[i].prev) {
                    const VsmSlot& e = s.slots[i];
                    const bool stale = (entry_of(s, int(e.level), e.x, e.y) & kVsmPageValid) == 0;
                    M.res[Key(int(e.level), e.x, e.y)] = std::make_pair(++rank, stale);
                }
                continue;
            }
            REQUIRE(p.status == Status::Ok);
            // expected: kept = resident and current; rendered = the others; evicted = the least recently requested
            std::size_t kept = 0, rer = 0;
            std::set<Key> render;
            for (const Key& k : wanted) {
                auto it = M.res.find(k);
                if (it != M.res.end() && !it->second.second) ++kept;
                else { render.insert(k); if (it != M.res.end()) ++rer; }
            }
            // ranks: resident requested pages first (request order), then the new ones
            for (const Key& k : wanted) {
                auto it = M.res.find(k);
                if (it != M.res.end()) { it->second.first = ++rank; it->second.second = false; }
            }
            std::size_t evicted = 0;
            for (const Key& k : wanted) {
                if (M.res.count(k)) continue;
                if (M.res.size() == std::size_t(pool)) {
                    auto victim = M.res.end();
                    for (auto it = M.res.begin(); it != M.res.end(); ++it)
                        if (!wanted_set.count(it->first) && (victim == M.res.end() || it->second.first < victim->second.first)) victim = it;
                    REQUIRE(victim != M.res.end());
                    M.res.erase(victim);
                    ++evicted;
                }
                M.res[k] = std::make_pair(++rank, false);
            }
            CHECK(p.kept == kept);
            CHECK(p.rerendered == rer);
            CHECK(p.evicted == evicted);
            CHECK(p.count == render.size());
            evictions += int(evicted);
            std::set<Key> listed;
            for (std::size_t i = 0; i < p.count; ++i) {
                const Key k(int(pages[i].level), nx[pages[i].level] + pages[i].x, ny[pages[i].level] + pages[i].y);
                listed.insert(k);
                CHECK(s.slots[pages[i].slot].x == std::get<1>(k));
            }
            CHECK(listed == render);
            // the table holds exactly the model's pages, current ones valid
            std::size_t resident = 0;
            for (const VsmSlot& e : s.slots) resident += e.resident ? 1 : 0;
            CHECK(resident == M.res.size());
            for (const auto& kv : M.res) {
                const std::uint32_t t = entry_of(s, std::get<0>(kv.first), std::get<1>(kv.first), std::get<2>(kv.first));
                CHECK(t != 0u);
                CHECK(((t & kVsmPageValid) != 0) == !kv.second.second);
            }
        }
    }
    CHECK(frames == 8000);
    // the random frames reached every path
    CHECK(degraded > 50);
    CHECK(evictions > 50);
    CHECK(invalidations > 50);
    CHECK(scrolls > 50);
}

TEST_CASE("vsm_requests_from_bitmask: one request per set bit, in the window's page order") {
    VsmState s;
    const VsmLayout L = small_layout(3, 8);
    REQUIRE(vsm_state_init(L, s).status == Status::Ok);
    REQUIRE(vsm_bitmask_words(s) == 6u);  // 3 * 64 bits
    std::vector<std::uint32_t> mask(6, 0u);
    std::mt19937 rng(9);
    std::set<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>> want;
    for (int i = 0; i < 40; ++i) {
        const std::uint32_t l = std::uint32_t(rng()) % 3u, x = std::uint32_t(rng()) % 8u, y = std::uint32_t(rng()) % 8u;
        const std::uint32_t bit = (l * 8u + y) * 8u + x;
        mask[bit / 32u] |= 1u << (bit % 32u);
        want.insert(std::make_tuple(l, x, y));
    }
    std::vector<VsmPageRequest> out(want.size());
    VsmRequestList r = vsm_requests_from_bitmask(s, mask.data(), mask.size(), out.data(), 3);
    CHECK(r.status == Status::BufferTooSmall);
    CHECK(r.needed == want.size());
    CHECK(r.count == 3u);
    r = vsm_requests_from_bitmask(s, mask.data(), mask.size(), out.data(), out.size());
    REQUIRE(r.status == Status::Ok);
    std::set<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>> got;
    for (const VsmPageRequest& q : out) got.insert(std::make_tuple(q.level, q.x, q.y));
    CHECK(got == want);
    CHECK(vsm_requests_from_bitmask(s, mask.data(), 5, out.data(), out.size()).status == Status::InvalidArgument);
}

TEST_CASE("vsm_gpu_block: the std430 words the snippet reads, matrices relative to the anchor") {
    VsmLayout layout;
    layout.page_texels = 16;
    layout.virtual_texels = 256;
    layout.level_count = 5;
    layout.level0_extent_world = 8.0;
    layout.pool_pages = 50;
    VsmState s;
    REQUIRE(vsm_state_init(layout, s).status == Status::Ok);
    std::vector<std::uint32_t> block(vsm_gpu_block_words(s));
    CHECK(block.size() == 332 + 5 * 16 * 16);
    CHECK(vsm_gpu_block(s, glm::dvec3(0.0), block.data(), block.size()).status == Status::InvalidArgument);  // no plan yet
    const glm::dvec3 camera(1.0e6 + 0.3, 2.0, -3.0e5);
    std::vector<VsmPageRequest> req = {{0, 7, 8}, {2, 3, 4}};
    std::vector<VsmPageRender> pages(50);
    VsmFrame f;
    f.camera_position = camera;
    f.light_position = glm::vec4(0.3f, 1.0f, -0.2f, 0.0f);
    f.requests = req.data();
    f.request_count = req.size();
    REQUIRE(vsm_plan(s, f, pages.data(), pages.size()).status == Status::Ok);
    const VsmGpuBlock small = vsm_gpu_block(s, camera, block.data(), 100);
    CHECK(small.status == Status::BufferTooSmall);
    CHECK(small.needed == block.size());
    CHECK(vsm_gpu_block(s, camera, nullptr, 5).status == Status::InvalidArgument);
    const VsmGpuBlock r = vsm_gpu_block(s, camera, block.data(), block.size());
    REQUIRE(r.status == Status::Ok);
    CHECK(r.count == block.size());
    auto as_float = [&](std::size_t i) { float v; std::memcpy(&v, &block[i], 4); return v; };
    // a point near the camera: the block's float matrix on (p - camera) gives the level's (u, v) in double
    const glm::dvec3 p = camera + glm::dvec3(3.25, -2.0, 1.5);
    for (int l = 0; l < 5; ++l) {
        glm::mat4 m;
        for (int c = 0; c < 4; ++c)
            for (int k = 0; k < 4; ++k) m[c][k] = as_float(std::size_t(l * 16 + c * 4 + k));
        const glm::vec4 h = m * glm::vec4(glm::vec3(p - camera), 1.0f);
        const glm::dvec4 e = s.levels[l].world_to_uv * glm::dvec4(p, 1.0);
        CHECK(std::fabs(double(h.x / h.w) - e.x / e.w) < 1e-6);
        CHECK(std::fabs(double(h.y / h.w) - e.y / e.w) < 1e-6);
        CHECK(int(block[256 + 4 * std::size_t(l)]) == s.levels[l].origin_mod_x);
        CHECK(int(block[257 + 4 * std::size_t(l)]) == s.levels[l].origin_mod_y);
    }
    for (std::size_t i = 5 * 16; i < 256; ++i) CHECK(block[i] == 0u);  // unused levels
    CHECK(block[320] == 5u);
    CHECK(block[321] == 16u);
    CHECK(block[322] == 16u);
    CHECK(block[323] == std::uint32_t(s.layout.pool_columns));
    CHECK(block[324] == 0u);  // GL clip depth
    CHECK(block[325] == 0u);
    CHECK(block[326] == 1u);  // directional
    CHECK(as_float(328) == doctest::Approx(8.0 / 256.0));
    for (std::size_t i = 0; i < s.page_table.size(); ++i) CHECK(block[332 + i] == s.page_table[i]);
    // the requested pages' entries are valid in the block, at vsm_table_index
    for (const VsmPageRequest& q : req) CHECK((block[332 + vsm_table_index(s, q.level, q.x, q.y)] & kVsmPageValid) != 0u);
}

TEST_CASE("vsm_slot_page: the page each slot holds, current or stale, with the matrix vsm_plan listed") {
    VsmLayout layout;
    layout.page_texels = 16;
    layout.virtual_texels = 256;
    layout.level_count = 4;
    layout.level0_extent_world = 8.0;
    layout.pool_pages = 10;
    VsmState s;
    REQUIRE(vsm_state_init(layout, s).status == Status::Ok);
    CHECK(vsm_slot_page(s, 0).status == Status::InvalidArgument);  // no plan yet
    std::vector<VsmPageRequest> req = {{0, 8, 8}, {1, 8, 8}, {3, 2, 9}};
    std::vector<VsmPageRender> pages(10);
    VsmFrame f;
    f.light_position = glm::vec4(0.0f, 1.0f, 0.0f, 0.0f);
    f.requests = req.data();
    f.request_count = req.size();
    const VsmPlan plan = vsm_plan(s, f, pages.data(), pages.size());
    REQUIRE(plan.count == 3);
    CHECK(vsm_slot_page(s, 10).status == Status::InvalidArgument);
    std::size_t resident = 0;
    for (std::uint32_t slot = 0; slot < 10; ++slot) {
        const VsmSlotPage sp = vsm_slot_page(s, slot);
        REQUIRE(sp.status == Status::Ok);
        resident += sp.resident;
        if (!sp.resident) continue;
        CHECK(sp.current);
        CHECK(sp.on_window);
        bool found = false;
        for (std::size_t i = 0; i < plan.count; ++i)
            if (pages[i].slot == slot) {
                found = true;
                CHECK(sp.page.level == pages[i].level);
                CHECK(sp.page.x == pages[i].x);
                CHECK(sp.page.y == pages[i].y);
                CHECK(sp.page.atlas_x == pages[i].atlas_x);
                CHECK(sp.page.atlas_y == pages[i].atlas_y);
                CHECK(sp.page.view_proj == pages[i].view_proj);
            }
        CHECK(found);
    }
    CHECK(resident == 3);
    // a caster over page (0, 8, 8) makes it (and its parents) stale: not current, still resident. Light
    // straight down: the map's x is world z, its y world x; level 0's pages are 0.5 wide and the window
    // starts 8 pages below the camera's (at 0), so page (8, 8) is world x, z in [0, 0.5)
    VsmCasterMove mv;
    const float box[6] = {0.1f, 0.0f, 0.1f, 0.2f, 1.0f, 0.2f};
    std::memcpy(mv.previous_bounds, box, sizeof(box));
    std::memcpy(mv.bounds, mv.previous_bounds, sizeof(mv.bounds));
    f.requests = nullptr;
    f.request_count = 0;
    f.moved_casters = &mv;
    f.moved_caster_count = 1;
    const VsmPlan p2 = vsm_plan(s, f, pages.data(), pages.size());
    REQUIRE(p2.status == Status::Ok);
    std::size_t stale = 0;
    for (std::uint32_t slot = 0; slot < 10; ++slot) {
        const VsmSlotPage sp = vsm_slot_page(s, slot);
        if (sp.resident && !sp.current) ++stale;
    }
    CHECK(stale == p2.invalidated);
    CHECK(stale > 0);
}
