// Unit and property tests for the SDSM fit of shadowkit/cascades.hpp (cascade_sdsm_view_range,
// cascade_sdsm_fit). References: closed-form frustum slices under a light shining straight down, the
// closed-form window depth of a perspective projection, and visible points pushed through the float
// matrix in float (what a vertex shader computes), checked against the cascade the view depth selects.
#include <shadowkit/cascades.hpp>
#include <shadowkit/infinite_projection.hpp>

#include <doctest/doctest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

using namespace shadowkit;

namespace {

glm::vec3 rdir(std::mt19937& rng) {
    std::normal_distribution<float> g(0.0f, 1.0f);
    glm::vec3 d;
    do { d = glm::vec3(g(rng), g(rng), g(rng)); } while (glm::length(d) < 1e-3f);
    return glm::normalize(d);
}

glm::mat4 look(const glm::vec3& p, const glm::vec3& f) {
    return glm::lookAt(p, p + f, std::fabs(f.y) > 0.99f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0));
}

// A visible point: NDC (sx, sy) across a symmetric perspective camera at view depth dep, in float world
// coordinates (what a G-buffer holds).
glm::vec3 visible_point(const glm::mat4& view, double fovy, double aspect, double dep, double sx, double sy) {
    const double ty = std::tan(0.5 * fovy), tx = ty * aspect;
    const glm::dvec3 pv(sx * tx * dep, sy * ty * dep, -dep);
    return glm::vec3(glm::inverse(glm::dmat4(view)) * glm::dvec4(pv, 1.0));
}

// The shader's test: the float matrix times the float position in float lands inside the cascade's
// clip box (x, y in [-1, 1], z in the light's depth range).
bool lands_inside(const glm::mat4& vp, const glm::vec3& p, ClipDepth cd) {
    const glm::vec4 h = vp * glm::vec4(p, 1.0f);
    const float lo = cd == ClipDepth::ZeroToOne ? 0.0f : -1.0f;
    return std::fabs(h.x) <= 1.0f && std::fabs(h.y) <= 1.0f && h.z >= lo && h.z <= 1.0f && h.w == 1.0f;
}

bool same_bits(const CascadeSdsmResult& a, const Cascade* ca, const CascadeSdsmResult& b, const Cascade* cb) {
    if (a.count != b.count || std::memcmp(a.splits, b.splits, sizeof(a.splits)) != 0) return false;
    for (std::size_t i = 0; i < a.count; ++i)
        if (std::memcmp(&ca[i].view_proj, &cb[i].view_proj, sizeof(glm::mat4)) != 0) return false;
    return true;
}

struct Config {
    CascadeSdsmInput in;
    double fovy = 1.0, aspect = 1.5;
};

Config random_config(std::mt19937& rng, double pos_scale) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    Config c;
    c.fovy = 0.3 + 1.5 * u(rng);
    c.aspect = 0.5 + 1.5 * u(rng);
    const float n = static_cast<float>(std::pow(10.0, -3.0 + 3.0 * u(rng)));
    const float f = n * static_cast<float>(std::pow(10.0, 1.0 + 4.0 * u(rng)));
    const glm::vec3 eye = (glm::vec3(static_cast<float>(u(rng)), static_cast<float>(u(rng)), static_cast<float>(u(rng))) -
                           0.5f) * static_cast<float>(2.0 * pos_scale);
    c.in.camera.camera_view = look(eye, rdir(rng));
    c.in.camera.camera_proj = glm::perspective(static_cast<float>(c.fovy), static_cast<float>(c.aspect), n, f);
    c.in.camera.light_position = glm::vec4(rdir(rng), 0.0f);
    const std::uint32_t sizes[] = {64, 256, 1024, 2048, 4096};
    c.in.camera.shadow_map_size = sizes[rng() % 5];
    const double a = n * std::pow(double(f) / n, u(rng)), b = n * std::pow(double(f) / n, u(rng));
    c.in.view_min = static_cast<float>(std::fmin(a, b));
    c.in.view_max = static_cast<float>(std::fmax(a, b));
    c.in.cascade_count = 1 + static_cast<std::uint32_t>(rng() % 8);
    c.in.lambda = u(rng) < 0.5 ? 1.0f : static_cast<float>(u(rng));
    c.in.margin = rng() % 4 == 0 ? 0.0f : static_cast<float>(0.25 * u(rng));  // 0: the texel border alone
    return c;
}

// Every one of `samples` random visible points (depth in [view_min, view_max]) lands inside the
// cascade cascade_select_by_depth picks for it. Returns the number that do not.
int count_outside(const Config& c, const CascadeSdsmResult& r, const Cascade* cs, std::mt19937& rng, int samples) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int bad = 0;
    const double lo = c.in.view_min, hi = c.in.view_max;
    for (int k = 0; k < samples; ++k) {
        const double t = k < 2 ? double(k) : u(rng);  // the range's two ends, then random
        const double dep = lo * std::pow(hi / lo, t);
        const double sx = k < 2 ? 1.0 : 2.0 * u(rng) - 1.0, sy = k < 2 ? -1.0 : 2.0 * u(rng) - 1.0;
        const glm::vec3 p = visible_point(c.in.camera.camera_view, c.fovy, c.aspect, dep, sx, sy);
        const float vd = -(c.in.camera.camera_view * glm::vec4(p, 1.0f)).z;
        int i = cascade_select_by_depth(vd, r.splits, static_cast<std::uint32_t>(r.count)).index;
        if (i < 0) i = vd < r.splits[0] ? 0 : static_cast<int>(r.count) - 1;  // float rounding of the view depth
        if (!lands_inside(cs[i].view_proj, p, c.in.camera.light_depth)) ++bad;
    }
    return bad;
}

}  // namespace

TEST_CASE("sdsm: view range from window depth, closed form") {
    const float n = 0.1f, f = 100.0f;
    const glm::mat4 P = glm::perspective(1.0f, 1.0f, n, f);  // GL clip depth
    // window depth of view depth d: w = ((f + n) / (f - n) - 2 f n / ((f - n) d) + 1) / 2
    auto wd = [&](double d) {
        return static_cast<float>((((double(f) + n) / (double(f) - n)) - 2.0 * f * n / ((double(f) - n) * d) + 1.0) * 0.5);
    };
    const CascadeSdsmRange r = cascade_sdsm_view_range(P, ClipDepth::NegativeOneToOne, false, wd(2.0), wd(40.0));
    REQUIRE(r.status == Status::Ok);
    CHECK(r.visible);
    CHECK(r.view_min == doctest::Approx(2.0).epsilon(1e-4));
    CHECK(r.view_max == doctest::Approx(40.0).epsilon(1e-3));
    // reversed-Z zero-to-one: window depth n / d (far at infinity); the smallest window depth is the farthest
    const ProjectionResult ri = projection_perspective_infinite(1.0f, 1.0f, n, ClipDepth::ZeroToOne, true, 0.0f);
    REQUIRE(ri.status == Status::Ok);
    const CascadeSdsmRange rr = cascade_sdsm_view_range(ri.matrix, ClipDepth::ZeroToOne, true, float(n / 50.0), float(n / 2.0));
    REQUIRE(rr.status == Status::Ok);
    CHECK(rr.view_min == doctest::Approx(2.0).epsilon(1e-5));
    CHECK(rr.view_max == doctest::Approx(50.0).epsilon(1e-5));
    const CascadeSdsmRange e = cascade_sdsm_view_range(P, ClipDepth::NegativeOneToOne, false, kCascadeSdsmEmptyMin,
                                                       kCascadeSdsmEmptyMax);
    CHECK(e.status == Status::Ok);
    CHECK_FALSE(e.visible);
    CHECK(cascade_sdsm_view_range(P, ClipDepth::NegativeOneToOne, false, 0.6f, 0.5f).status == Status::InvalidArgument);
    CHECK(cascade_sdsm_view_range(P, ClipDepth::NegativeOneToOne, false, -0.1f, 0.5f).status == Status::InvalidArgument);
    CHECK(cascade_sdsm_view_range(P, ClipDepth::NegativeOneToOne, false, std::nanf(""), 0.5f).status == Status::NonFinite);
    // window depth 0 of a reversed P_inf is infinity itself: no finite view depth
    CHECK(cascade_sdsm_view_range(ri.matrix, ClipDepth::ZeroToOne, true, 0.0f, 0.5f).status == Status::InvalidArgument);
}

TEST_CASE("sdsm: closed form under a light shining straight down") {
    // camera at the origin looking down -z, 90 degrees, square; light straight down: map x = world x,
    // map y = world -z, distance along the light = -world y. Slice [d0, d1]: x in [-d1, d1], y in
    // [d0, d1], depth in [-d1, d1].
    CascadeSdsmInput in;
    in.camera.camera_view = glm::mat4(1.0f);
    in.camera.camera_proj = glm::perspective(glm::radians(90.0f), 1.0f, 0.5f, 100.0f);
    in.camera.light_position = glm::vec4(0, 1, 0, 0);
    in.camera.shadow_map_size = 1024;
    in.view_min = 2.0f;
    in.view_max = 32.0f;
    in.margin = 1.0f / 16.0f;
    Cascade cs[4];
    const CascadeSdsmResult r = cascade_sdsm_fit(in, nullptr, cs, 4);
    REQUIRE(r.status == Status::Ok);
    REQUIRE(r.count == 4);
    // whole octaves are on the 2^(1/8) grid: the log partition of [2, 32] is 2, 4, 8, 16, 32
    const float want[5] = {2, 4, 8, 16, 32};
    for (int i = 0; i < 5; ++i) CHECK(r.splits[i] == doctest::Approx(want[i]).epsilon(1e-6));
    // cascade 0, slice [2, 4]: x extent 8 (1 + 2/16) * 1024 / 1022 = 9.018 -> a multiple of 0.25 (2^3 / 32):
    // 9.25; y extent 2 (1 + 2/16) * 1024 / 1022 = 2.254 -> a multiple of 0.0625 (2^1 / 32): 2.3125
    const CascadeSdsmBox& b = r.boxes[0];
    CHECK(b.x1 - b.x0 == 9.25);
    CHECK(b.y1 - b.y0 == 2.3125);
    CHECK(b.x0 == -4.625);                    // centered on x = 0: -4.625 / (9.25 / 1024) = -512 texels
    CHECK(b.y0 == 816.0 * 2.3125 / 1024.0);   // centered on y = 3: 1.84375 / (2.3125 / 1024) = 816.4 texels, floored
    CHECK(b.near_dist == -5.0);       // [-4, 4] grown by 8 / 16, snapped to 1 (2^3 / 8 of 9)
    CHECK(b.far_dist == 5.0);
    CHECK(cs[0].texel_world_size == doctest::Approx(9.25 / 1024.0));  // the larger axis
    CHECK(cs[0].texel_anchor.x == -512.0);
    CHECK(cs[0].texel_anchor.y == 816.0);
    // the matrix maps the box's corners to the clip box's corners: world (x, y, z) = (x0, -near, -y0) -> (-1, -1, -1)
    const glm::dvec4 c0 = glm::dmat4(cs[0].view_proj) * glm::dvec4(-4.625, 5.0, -b.y0, 1.0);
    CHECK(c0.x == doctest::Approx(-1.0));
    CHECK(c0.y == doctest::Approx(-1.0));
    CHECK(c0.z == doctest::Approx(-1.0));
    const glm::dvec4 c1 = glm::dmat4(cs[0].view_proj) * glm::dvec4(4.625, -5.0, -b.y1, 1.0);
    CHECK(c1.x == doctest::Approx(1.0));
    CHECK(c1.y == doctest::Approx(1.0));
    CHECK(c1.z == doctest::Approx(1.0));
    // under half the texel of the fixed practical split over the camera's whole range (its first
    // cascade covers [0.5, 7.75], in a sphere of radius 11: texel 22 / 1022)
    CascadeInput fixed = in.camera;
    Cascade fc[4];
    REQUIRE(cascade_fit(fixed, 0.75f, 4, fc, 4).status == Status::Ok);
    CHECK(fc[0].texel_world_size == doctest::Approx(22.0 / 1022.0));
    CHECK(cs[0].texel_world_size < 0.5f * fc[0].texel_world_size);
}

TEST_CASE("sdsm: validation") {
    CascadeSdsmInput in;
    in.camera.camera_view = glm::mat4(1.0f);
    in.camera.camera_proj = glm::perspective(1.0f, 1.0f, 0.5f, 100.0f);
    in.camera.light_position = glm::vec4(0.2f, 1, 0.1f, 0);
    in.view_min = 1.0f;
    in.view_max = 10.0f;
    Cascade cs[16];
    CHECK(cascade_sdsm_fit(in, nullptr, cs, 16).status == Status::Ok);
    auto with = [&](auto edit) {
        CascadeSdsmInput b = in;
        edit(b);
        return cascade_sdsm_fit(b, nullptr, cs, 16).status;
    };
    CHECK(with([](CascadeSdsmInput& b) { b.view_min = std::nanf(""); }) == Status::NonFinite);
    CHECK(with([](CascadeSdsmInput& b) { b.view_max = INFINITY; }) == Status::NonFinite);
    CHECK(with([](CascadeSdsmInput& b) { b.view_min = 20.0f; }) == Status::InvalidArgument);  // min > max
    CHECK(with([](CascadeSdsmInput& b) { b.view_min = 0.0f; }) == Status::InvalidArgument);
    CHECK(with([](CascadeSdsmInput& b) { b.view_min = -1.0f; }) == Status::InvalidArgument);
    CHECK(with([](CascadeSdsmInput& b) { b.lambda = 1.5f; }) == Status::InvalidArgument);
    CHECK(with([](CascadeSdsmInput& b) { b.margin = -0.1f; }) == Status::InvalidArgument);
    CHECK(with([](CascadeSdsmInput& b) { b.range_steps_per_octave = 0.5f; }) == Status::InvalidArgument);
    CHECK(with([](CascadeSdsmInput& b) { b.cascade_count = 0; }) == Status::InvalidArgument);
    CHECK(with([](CascadeSdsmInput& b) { b.cascade_count = 17; }) == Status::InvalidArgument);
    CHECK(with([](CascadeSdsmInput& b) { b.camera.light_position = glm::vec4(0, 5, 0, 1); }) == Status::InvalidLight);
    CHECK(with([](CascadeSdsmInput& b) { b.camera.light_position = glm::vec4(0.0f); }) == Status::InvalidLight);
    CHECK(with([](CascadeSdsmInput& b) { b.camera.camera_proj = glm::mat4(0.0f); }) == Status::InvalidArgument);
    CHECK(with([](CascadeSdsmInput& b) { b.camera.stable_world_depth = true; b.camera.has_scene_bounds = true; }) ==
          Status::InvalidArgument);
    CHECK(cascade_sdsm_fit(in, nullptr, cs, 3).status == Status::BufferTooSmall);
    CHECK(cascade_sdsm_fit(in, nullptr, nullptr, 4).status == Status::InvalidArgument);
    // zero range: one step of the range grid, Ok
    CascadeSdsmInput z = in;
    z.view_min = z.view_max = 3.0f;
    const CascadeSdsmResult rz = cascade_sdsm_fit(z, nullptr, cs, 16);
    REQUIRE(rz.status == Status::Ok);
    CHECK(rz.range_min <= 3.0f);
    CHECK(rz.range_max >= 3.0f);
    CHECK(rz.range_max > rz.range_min);
    // everything visible beyond the shadow distance: nothing to fit, Ok
    CascadeSdsmInput far = in;
    far.camera.max_distance = 0.75f;
    const CascadeSdsmResult rf = cascade_sdsm_fit(far, nullptr, cs, 16);
    CHECK(rf.status == Status::Ok);
    CHECK_FALSE(rf.visible);
    CHECK(rf.count == 0);
}

TEST_CASE("sdsm: property: every visible point lands inside its cascade, in float (4000 configurations)") {
    std::mt19937 rng(2511);
    int fits = 0, bad = 0, overflow = 0;
    for (int k = 0; k < 4000; ++k) {
        const Config c = random_config(rng, k % 2 ? 100.0 : 1.0);
        Cascade cs[16];
        const CascadeSdsmResult r = cascade_sdsm_fit(c.in, nullptr, cs, 16);
        if (r.status == Status::Overflow) { ++overflow; continue; }
        REQUIRE(r.status == Status::Ok);
        REQUIRE(r.visible);
        ++fits;
        CHECK(r.range_min <= c.in.view_min);
        CHECK(r.range_max >= c.in.view_max);
        for (std::size_t i = 0; i < r.count; ++i) CHECK(r.splits[i + 1] > r.splits[i]);
        bad += count_outside(c, r, cs, rng, 64);
    }
    CHECK(bad == 0);
    CHECK(fits > 3900);  // Overflow only for slices tiny against their distance from the origin
    MESSAGE("fits " << fits << ", overflow " << overflow);
}

TEST_CASE("sdsm: hysteresis: a camera move below the step keeps the fit bit-identical; a large one rebuilds") {
    std::mt19937 rng(77);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int kept = 0, rebuilt_big = 0, runs = 0;
    for (int k = 0; k < 1000; ++k) {
        Config c = random_config(rng, 50.0);
        c.in.margin = 1.0f / 16.0f;
        Cascade a[16], b[16];
        const CascadeSdsmResult ra = cascade_sdsm_fit(c.in, nullptr, a, 16);
        if (ra.status != Status::Ok) continue;
        ++runs;
        // a translation of 1/10 of the margin of the smallest extent (x, y or depth) of any box, the
        // range ends moved inward within a step
        double e0 = std::numeric_limits<double>::infinity();
        for (std::size_t i = 0; i < ra.count; ++i)
            e0 = std::fmin(e0, std::fmin(ra.boxes[i].x1 - ra.boxes[i].x0,
                                         std::fmin(ra.boxes[i].y1 - ra.boxes[i].y0, ra.boxes[i].far_dist - ra.boxes[i].near_dist)));
        const glm::vec3 move = rdir(rng) * static_cast<float>(0.1 * c.in.margin * e0 / 1.25);
        Config m = c;
        m.in.camera.camera_view = c.in.camera.camera_view * glm::translate(glm::mat4(1.0f), -move);
        const double step = std::exp2(1.0 / double(c.in.range_steps_per_octave)) - 1.0;
        m.in.view_min = std::fmin(c.in.view_max, static_cast<float>(c.in.view_min * (1.0 + 0.3 * step * u(rng))));
        m.in.view_max = std::fmax(m.in.view_min, static_cast<float>(c.in.view_max / (1.0 + 0.3 * step * u(rng))));
        const CascadeSdsmResult rb = cascade_sdsm_fit(m.in, &ra, b, 16);
        REQUIRE(rb.status == Status::Ok);
        if (same_bits(ra, a, rb, b) && rb.rebuilt == 0) ++kept;
        // a move of two extents of the largest box: every box rebuilt
        const double el = ra.boxes[ra.count - 1].x1 - ra.boxes[ra.count - 1].x0;
        Config far = c;
        far.in.camera.camera_view = c.in.camera.camera_view * glm::translate(glm::mat4(1.0f), glm::vec3(static_cast<float>(2.0 * el), 0, 0));
        const CascadeSdsmResult rc = cascade_sdsm_fit(far.in, &ra, b, 16);
        if (rc.status == Status::Ok && rc.rebuilt == (1u << rc.count) - 1u) ++rebuilt_big;
    }
    CHECK(runs > 950);
    CHECK(kept == runs);
    CHECK(rebuilt_big == runs);
}

TEST_CASE("sdsm: a camera path chained through `previous` stays covered every frame") {
    // kept boxes must still hold every visible point: walk 200 frames, feeding each result to the next
    std::mt19937 rng(4242);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int bad = 0, rebuilt = 0, frames = 0;
    for (int path = 0; path < 20; ++path) {
        Config c = random_config(rng, 10.0);
        c.in.world_splits = path % 2 == 1;  // the splits following the camera's travel: still covered
        CascadeSdsmResult prev;
        Cascade cs[16];
        const glm::vec3 dir = rdir(rng);
        for (int t = 0; t < 200; ++t) {
            Config f = c;
            f.in.camera.camera_view = c.in.camera.camera_view * glm::translate(glm::mat4(1.0f), -dir * (0.002f * float(t) * c.in.view_min));
            const CascadeSdsmResult r = cascade_sdsm_fit(f.in, t ? &prev : nullptr, cs, 16);
            if (r.status != Status::Ok) break;
            ++frames;
            bad += count_outside(f, r, cs, rng, 16);
            rebuilt += t && r.rebuilt ? 1 : 0;
            prev = r;
        }
    }
    CHECK(bad == 0);
    CHECK(rebuilt < frames / 2);  // the hysteresis keeps most frames
    MESSAGE("frames " << frames << ", frames with a rebuilt box " << rebuilt);
}

TEST_CASE("sdsm: a dolly through `previous` keeps every box size and moves boxes by whole texels") {
    // camera looking down -z under a light shining straight down (map x = world x, map y = world -z):
    // every frame's view slice [d0, d1] is the first one translated along -z, so its light-space box
    // has the same extents and only its place changes. The fit must keep each length bit for bit and
    // move each box by whole texels of the first frame's grid (a resize would move filtered edges).
    CascadeSdsmInput in;
    in.camera.camera_proj = glm::perspective(glm::radians(90.0f), 1.0f, 0.5f, 100.0f);
    in.camera.light_position = glm::vec4(0, 1, 0, 0);
    in.camera.shadow_map_size = 1024;
    in.view_min = 2.0f;
    in.view_max = 32.0f;
    in.world_splits = false;  // the default: splits fixed in view depth
    CascadeSdsmResult first, prev;
    Cascade cs[4];
    int moved = 0, bad = 0;
    std::mt19937 rng(77);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int t = 0; t < 120; ++t) {
        in.camera.camera_view = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, 0.05f * float(t)));  // eye at z = -0.05 t
        const CascadeSdsmResult r = cascade_sdsm_fit(in, t ? &prev : nullptr, cs, 4);
        REQUIRE(r.status == Status::Ok);
        REQUIRE(r.count == 4);
        if (t == 0) first = r;
        for (int i = 0; i < 4; ++i) {
            const CascadeSdsmBox &b = r.boxes[i], &b0 = first.boxes[i];
            CHECK(r.splits[i] == first.splits[i]);
            CHECK(b.x1 - b.x0 == b0.x1 - b0.x0);
            CHECK(b.y1 - b.y0 == b0.y1 - b0.y0);
            const double ty = (b0.y1 - b0.y0) / 1024.0, shift = (b.y0 - b0.y0) / ty;
            CHECK(std::fabs(shift - std::round(shift)) < 1e-6);
            CHECK(b.x0 == b0.x0);  // nothing moves across the view
            moved += t && b.y0 != prev.boxes[i].y0 ? 1 : 0;
            // coverage: points of the slice through the float matrix
            for (int k = 0; k < 64; ++k) {
                const double d = r.splits[i] + 0.5 * (u(rng) + 1.0) * (r.splits[i + 1] - r.splits[i]);
                const glm::vec3 p = visible_point(in.camera.camera_view, glm::radians(90.0), 1.0, d, u(rng), u(rng));
                bad += lands_inside(cs[i].view_proj, p, ClipDepth::NegativeOneToOne) ? 0 : 1;
            }
        }
        prev = r;
    }
    CHECK(bad == 0);
    CHECK(moved > 4);  // the boxes did move (6 wu, over 2 extents of cascade 0): not a vacuous check
    MESSAGE("box moves over 119 frames x 4 cascades: " << moved);
}

TEST_CASE("sdsm: world_splits: a dolly keeps the interior splits on their world planes") {
    // camera at z = -0.05 t looking down -z (a dolly: the rotation never changes), view range [2, 32]
    // fixed (the report's dolly: the range of the first frame's depth buffer): the log partition is 2,
    // 4, 8, 16, 32. With world_splits each interior split moves with the camera, s_i(t) = s_i(a) -
    // 0.05 (t - a) from the last frame a they were cut, while |log2(s_1 / 4)| <= 4 / 8: 4 - 0.05 k >=
    // 4 * 2^-0.5 = 2.8284, k <= 23 (s_2, s_3 drift less in log); at k = 24 they are cut again (a = 24).
    CascadeSdsmInput in;
    in.camera.camera_proj = glm::perspective(glm::radians(90.0f), 1.0f, 0.5f, 100.0f);
    in.camera.light_position = glm::vec4(0, 1, 0, 0);
    in.camera.shadow_map_size = 1024;
    in.view_min = 2.0f;
    in.view_max = 32.0f;
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    // world points on the axis (z in [-30, -3.5]: view depth >= 2.35 > range_min = 2 up to frame 23,
    // away from the planes by 0.01): each keeps the cascade its view depth selects while the splits
    // stay anchored
    std::vector<glm::vec3> pts;
    for (int k = 0; k < 400; ++k) {
        const float z = -3.5f - 26.5f * float(0.5 * (u(rng) + 1.0));
        bool near_plane = false;
        for (float pz : {-4.0f, -8.0f, -16.0f}) near_plane = near_plane || std::fabs(z - pz) < 0.01f;
        if (!near_plane) pts.push_back(glm::vec3(0.0f, -0.5f, z));
    }
    for (bool world : {true, false}) {
        in.world_splits = world;
        CascadeSdsmResult prev;
        Cascade cs[4];
        int anchor = 0, bad = 0, interior_rebuilt = 0, switched = 0;
        std::vector<int> first(pts.size(), -2);
        for (int t = 0; t < 30; ++t) {
            in.camera.camera_view = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, 0.05f * float(t)));
            const CascadeSdsmResult r = cascade_sdsm_fit(in, t ? &prev : nullptr, cs, 4);
            REQUIRE(r.status == Status::Ok);
            REQUIRE(r.count == 4);
            CHECK(r.splits[0] == 2.0f);
            CHECK(r.splits[4] == 32.0f);
            if (world && t - anchor > 23) anchor = t;
            const float c = world ? 0.05f * float(t - anchor) : 0.0f;
            CHECK(r.splits[1] == doctest::Approx(4.0f - c).epsilon(1e-5));
            CHECK(r.splits[2] == doctest::Approx(8.0f - c).epsilon(1e-5));
            CHECK(r.splits[3] == doctest::Approx(16.0f - c).epsilon(1e-5));
            if (t && t != 24) interior_rebuilt += (r.rebuilt & 6u) ? 1 : 0;
            for (int i = 0; i < 4; ++i)
                for (int k = 0; k < 32; ++k) {
                    const double d = r.splits[i] + 0.5 * (u(rng) + 1.0) * (r.splits[i + 1] - r.splits[i]);
                    const glm::vec3 p = visible_point(in.camera.camera_view, glm::radians(90.0), 1.0, d, u(rng), u(rng));
                    bad += lands_inside(cs[i].view_proj, p, ClipDepth::NegativeOneToOne) ? 0 : 1;
                }
            if (t <= 23)
                for (std::size_t k = 0; k < pts.size(); ++k) {
                    const float vd = -(in.camera.camera_view * glm::vec4(pts[k], 1.0f)).z;
                    const int ci = cascade_select_by_depth(vd, r.splits, 4).index;
                    if (t == 0) first[k] = ci;
                    switched += ci != first[k] ? 1 : 0;
                }
            prev = r;
        }
        CHECK(bad == 0);
        if (world) {
            CHECK(switched == 0);          // every point keeps its cascade
            CHECK(interior_rebuilt == 0);  // cascades 1 and 2 (both ends anchored): boxes bit for bit kept
        } else {
            CHECK(switched > 0);  // fixed in view depth, the points cross the splits: not a vacuous check
        }
        MESSAGE(std::string(world ? "world" : "view") << " splits: cascade switches " << switched << ", frames rebuilding cascade 1 or 2 "
                                          << interior_rebuilt);
    }
    // a turn (1 degree) cuts the log partition again
    in.world_splits = true;
    Cascade cs[4];
    in.camera.camera_view = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, 0.3f));
    const CascadeSdsmResult a = cascade_sdsm_fit(in, nullptr, cs, 4);
    in.camera.camera_view = glm::rotate(glm::mat4(1.0f), glm::radians(1.0f), glm::vec3(0, 1, 0)) *
                            glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, 0.5f));
    const CascadeSdsmResult b = cascade_sdsm_fit(in, &a, cs, 4);
    REQUIRE(b.status == Status::Ok);
    CHECK(b.splits[1] == doctest::Approx(4.0f).epsilon(1e-6));
    CHECK(b.splits[2] == doctest::Approx(8.0f).epsilon(1e-6));
}

TEST_CASE("sdsm: a box grows only when it must, by a quarter more, and shrinks only when much too large") {
    // one cascade, slice [2, 4] of a 90-degree camera at the origin looking down -z, light straight
    // down: x in [-4, 4], y (= -z) in [2, 4]. The receivers (x0, y0, x1, y1) = (-a, 2.5, a, 3.5): tight
    // extents 2a and 1. By hand (margin 1/16, 1024 texels: border factor 1024 / 1022, lengths rounded
    // up to 1/32 of their power of two):
    //   a = 2: 4 (1 + 1/8) 1024/1022 = 4.5088 -> 4.625; y: 1.125 * 1024/1022 = 1.1272 -> 1.15625
    //   a up to 2.3 (tight 4.6, with the border 4.609 <= 4.625): kept, the same box bit for bit
    //   a = 3 (6.012 > 4.625): grows, to 6 (1 + 1/8 + 1/4) 1024/1022 = 8.266 -> 8.5
    //   a = 4 (8.016 <= 8.5): kept
    //   a = 1: 2 (1 + 1/8 + 1/2) 1024/1022 = 3.256 -> 3.3125 < 8.5: shrinks to 2 (1 + 1/8) = 2.254 -> 2.3125
    CascadeSdsmInput in;
    in.camera.camera_view = glm::mat4(1.0f);
    in.camera.camera_proj = glm::perspective(glm::radians(90.0f), 1.0f, 0.5f, 100.0f);
    in.camera.light_position = glm::vec4(0, 1, 0, 0);
    in.camera.shadow_map_size = 1024;
    in.view_min = 2.0f;
    in.view_max = 4.0f;
    in.cascade_count = 1;
    in.margin = 1.0f / 16.0f;
    CascadeSdsmResult prev;
    Cascade c[1];
    auto fit = [&](float a, bool chained) {
        const glm::vec4 rb(-a, 2.5f, a, 3.5f);
        in.receiver_bounds = &rb;
        const CascadeSdsmResult r = cascade_sdsm_fit(in, chained ? &prev : nullptr, c, 1);
        REQUIRE(r.status == Status::Ok);
        REQUIRE(r.count == 1);
        // every receiver lands inside (the four corners of the receiver rectangle at height 0 and +-3)
        for (int k = 0; k < 12; ++k) {
            const glm::vec3 p((k & 1) ? a : -a, float(k / 4 - 1) * 3.0f, (k & 2) ? -3.5f : -2.5f);
            CHECK(lands_inside(c[0].view_proj, p, ClipDepth::NegativeOneToOne));
        }
        prev = r;
        return r;
    };
    const CascadeSdsmResult r0 = fit(2.0f, false);
    CHECK(r0.boxes[0].x1 - r0.boxes[0].x0 == 4.625);
    CHECK(r0.boxes[0].y1 - r0.boxes[0].y0 == 1.15625);
    for (int k = 1; k <= 15; ++k) {  // grows 15% in 15 frames: inside the margins and the rounding
        const CascadeSdsmResult r = fit(2.0f * (1.0f + 0.01f * float(k)), true);
        CHECK(r.rebuilt == 0u);
        CHECK(std::memcmp(&r.boxes[0], &r0.boxes[0], sizeof(CascadeSdsmBox)) == 0);
    }
    const CascadeSdsmResult g = fit(3.0f, true);
    CHECK(g.rebuilt == 1u);
    CHECK(g.boxes[0].x1 - g.boxes[0].x0 == 8.5);
    CHECK(g.boxes[0].y1 - g.boxes[0].y0 == 1.15625);  // the other axis keeps its length
    const CascadeSdsmResult k = fit(4.0f, true);
    CHECK(k.rebuilt == 0u);
    CHECK(k.boxes[0].x1 - k.boxes[0].x0 == 8.5);
    const CascadeSdsmResult s = fit(1.0f, true);
    CHECK(s.boxes[0].x1 - s.boxes[0].x0 == 2.3125);
    // without `previous` the 15%-grown receivers get their own tight box: the hysteresis kept a box
    // larger than a fresh fit (the test above is not vacuous)
    const CascadeSdsmResult f = fit(2.3f, false);
    CHECK(f.boxes[0].x1 - f.boxes[0].x0 == 5.25);  // 4.6 (1 + 1/8) 1024/1022 = 5.186 -> 5.25
}

TEST_CASE("sdsm: stiff cases") {
    std::mt19937 rng(9);
    auto check = [&](const Config& c, const char* what) {
        Cascade cs[16];
        const CascadeSdsmResult r = cascade_sdsm_fit(c.in, nullptr, cs, 16);
        INFO(what);
        REQUIRE(r.status == Status::Ok);
        CHECK(count_outside(c, r, cs, rng, 2000) == 0);
    };
    Config c;
    c.in.camera.camera_proj = glm::perspective(1.0f, 1.5f, 0.1f, 1000.0f);
    c.in.camera.light_position = glm::vec4(glm::normalize(glm::vec3(-0.85f, 0.5f, -0.15f)), 0.0f);
    c.in.view_min = 1.0f;
    c.in.view_max = 300.0f;
    {
        Config s = c;  // camera 1e6 from the origin
        s.in.camera.camera_view = look(glm::vec3(1e6f, 10.0f, -1e6f), glm::normalize(glm::vec3(0.3f, -0.2f, -1.0f)));
        check(s, "camera 1e6 from the origin");
    }
    {
        Config s = c;  // near 1e-5, visible from the near plane on
        s.in.camera.camera_view = look(glm::vec3(1, 2, 3), glm::vec3(0, 0, -1));
        s.in.camera.camera_proj = glm::perspective(1.0f, 1.5f, 1e-5f, 10.0f);
        s.in.view_min = 1e-5f;
        s.in.view_max = 5.0f;
        check(s, "near 1e-5");
    }
    {
        Config s = c;  // far at infinity (the epsilon-tweaked P_inf), reversed-Z zero-to-one camera and light
        s.in.camera.camera_view = look(glm::vec3(5, 2, 3), glm::normalize(glm::vec3(1, -0.1f, 0)));
        const ProjectionResult p = projection_perspective_infinite(1.0f, 1.5f, 0.1f, ClipDepth::ZeroToOne, true, 1e-6f);
        REQUIRE(p.status == Status::Ok);
        s.in.camera.camera_proj = p.matrix;
        s.in.camera.camera_depth = ClipDepth::ZeroToOne;
        s.in.camera.camera_reversed_z = true;
        s.in.camera.light_depth = ClipDepth::ZeroToOne;
        s.in.camera.light_reversed_z = true;
        s.in.view_max = 5000.0f;
        check(s, "far at infinity, reversed-Z zero-to-one");
        s.in.camera.max_distance = 100.0f;  // the shadow distance clamps the range
        Cascade cs[16];
        const CascadeSdsmResult r = cascade_sdsm_fit(s.in, nullptr, cs, 16);
        REQUIRE(r.status == Status::Ok);
        CHECK(r.range_max >= 100.0f);
        CHECK(r.range_max < 100.0f * 1.1f);
    }
    for (bool reversed : {false, true}) {  // zero-to-one camera and light, reversed-Z or not, finite far
        Config s = c;
        s.in.camera.camera_view = look(glm::vec3(-3, 4, 1), glm::normalize(glm::vec3(0.5f, -0.4f, -1.0f)));
        s.in.camera.camera_proj = reversed ? glm::perspectiveRH_ZO(1.0f, 1.5f, 1000.0f, 0.1f)  // near <-> far: reversed
                                           : glm::perspectiveRH_ZO(1.0f, 1.5f, 0.1f, 1000.0f);
        s.in.camera.camera_depth = ClipDepth::ZeroToOne;
        s.in.camera.camera_reversed_z = reversed;
        s.in.camera.light_depth = ClipDepth::ZeroToOne;
        s.in.camera.light_reversed_z = reversed;
        check(s, reversed ? "reversed-Z zero-to-one, finite far" : "zero-to-one");
    }
    for (float sign : {1.0f, -1.0f}) {  // light parallel and anti-parallel to the view
        Config s = c;
        const glm::vec3 f = glm::normalize(glm::vec3(0.2f, -0.3f, -1.0f));
        s.in.camera.camera_view = look(glm::vec3(0, 2, 0), f);
        s.in.camera.light_position = glm::vec4(sign * f, 0.0f);
        check(s, sign > 0 ? "light along the view" : "light against the view");
    }
}

TEST_CASE("sdsm: receiver bounds (second reduction): visible points still land inside, boxes shrink") {
    // the bounds are computed here as the GPU reduction does: each visible point (float) through the
    // float light view of cascade_sdsm_light_view, into the cascade its view depth selects with the
    // splits of cascade_sdsm_splits (beyond the last split: the last)
    std::mt19937 rng(3125);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int bad = 0, fits = 0, smaller = 0, cascades = 0;
    for (int k = 0; k < 1000; ++k) {
        const Config c = random_config(rng, k % 2 ? 100.0 : 1.0);
        if (c.in.cascade_count > 4) continue;
        const CascadeSdsmResult sp = cascade_sdsm_splits(c.in, nullptr);
        REQUIRE(sp.status == Status::Ok);
        const CascadeSdsmLightView lv = cascade_sdsm_light_view(c.in.camera.light_position);
        REQUIRE(lv.status == Status::Ok);
        glm::vec4 b[4];
        for (glm::vec4& v : b) v = glm::vec4(3e38f, 3e38f, -3e38f, -3e38f);
        std::vector<glm::vec3> pts;
        const double lo = c.in.view_min, hi = c.in.view_max;
        for (int s = 0; s < 200; ++s) {  // a receiver surface: a random subset of the visible volume
            const double dep = lo * std::pow(hi / lo, u(rng));
            const glm::vec3 p = visible_point(c.in.camera.camera_view, c.fovy, c.aspect, dep, u(rng) - 0.3, 0.5 * u(rng));
            const float vd = -(c.in.camera.camera_view * glm::vec4(p, 1.0f)).z;
            int i = cascade_select_by_depth(vd, sp.splits, c.in.cascade_count).index;
            if (i < 0) i = vd < sp.splits[0] ? 0 : static_cast<int>(c.in.cascade_count) - 1;
            const glm::vec4 l = lv.view * glm::vec4(p, 1.0f);
            b[i] = glm::vec4(std::min(b[i].x, l.x), std::min(b[i].y, l.y), std::max(b[i].z, l.x), std::max(b[i].w, l.y));
            pts.push_back(p);
        }
        CascadeSdsmInput in = c.in;
        in.receiver_bounds = b;
        Cascade cs[4], whole[4];
        const CascadeSdsmResult r = cascade_sdsm_fit(in, nullptr, cs, 4);
        const CascadeSdsmResult rw = cascade_sdsm_fit(c.in, nullptr, whole, 4);
        if (r.status == Status::Overflow) continue;
        REQUIRE(r.status == Status::Ok);
        REQUIRE(rw.status == Status::Ok);
        ++fits;
        CHECK(std::memcmp(r.splits, sp.splits, sizeof(r.splits)) == 0);  // the splits the bounds were reduced with
        for (const glm::vec3& p : pts) {
            const float vd = -(c.in.camera.camera_view * glm::vec4(p, 1.0f)).z;
            int i = cascade_select_by_depth(vd, r.splits, static_cast<std::uint32_t>(r.count)).index;
            if (i < 0) i = vd < r.splits[0] ? 0 : static_cast<int>(r.count) - 1;
            if (!lands_inside(cs[i].view_proj, p, c.in.camera.light_depth)) ++bad;
        }
        for (std::size_t i = 0; i < r.count; ++i, ++cascades) {
            const double a = (r.boxes[i].x1 - r.boxes[i].x0) * (r.boxes[i].y1 - r.boxes[i].y0);
            const double aw = (rw.boxes[i].x1 - rw.boxes[i].x0) * (rw.boxes[i].y1 - rw.boxes[i].y0);
            CHECK(a <= aw);
            smaller += a < 0.5 * aw ? 1 : 0;
        }
    }
    CHECK(fits > 400);
    CHECK(bad == 0);
    CHECK(smaller > cascades / 4);  // receivers on a part of the view: much smaller maps
    MESSAGE("fits " << fits << ", cascades under half the slice's area " << smaller << " of " << cascades);
}

TEST_CASE("sdsm: receiver bounds validation, empty cascades, light view") {
    CascadeSdsmInput in;
    in.camera.camera_view = glm::mat4(1.0f);
    in.camera.camera_proj = glm::perspective(1.0f, 1.0f, 0.5f, 100.0f);
    in.camera.light_position = glm::vec4(0.2f, 1, 0.1f, 0);
    in.view_min = 1.0f;
    in.view_max = 10.0f;
    Cascade a[4], b[4];
    glm::vec4 rb[4];
    for (glm::vec4& v : rb) v = glm::vec4(3e38f, 3e38f, -3e38f, -3e38f);  // no receiver in any cascade
    const CascadeSdsmResult whole = cascade_sdsm_fit(in, nullptr, a, 4);
    in.receiver_bounds = rb;
    const CascadeSdsmResult empty = cascade_sdsm_fit(in, nullptr, b, 4);
    REQUIRE(whole.status == Status::Ok);
    REQUIRE(empty.status == Status::Ok);
    CHECK(same_bits(whole, a, empty, b));  // an empty cascade keeps its slice's box
    rb[2].x = std::nanf("");
    CHECK(cascade_sdsm_fit(in, nullptr, b, 4).status == Status::NonFinite);
    CHECK(cascade_sdsm_splits(in, nullptr).status == Status::Ok);  // the splits do not read the bounds
    CHECK(cascade_sdsm_light_view(glm::vec4(0, 1, 0, 1)).status == Status::InvalidLight);
    CHECK(cascade_sdsm_light_view(glm::vec4(0.0f)).status == Status::InvalidLight);
    CHECK(cascade_sdsm_light_view(glm::vec4(NAN, 1, 0, 0)).status == Status::InvalidLight);
    // closed form: light straight down -> map x = world x, map y = world -z, -z_light = distance = -y
    const CascadeSdsmLightView lv = cascade_sdsm_light_view(glm::vec4(0, 1, 0, 0));
    REQUIRE(lv.status == Status::Ok);
    const glm::vec4 l = lv.view * glm::vec4(1, 2, 3, 1);
    CHECK(l.x == doctest::Approx(1.0));
    CHECK(l.y == doctest::Approx(-3.0));
    CHECK(l.z == doctest::Approx(2.0));
}
