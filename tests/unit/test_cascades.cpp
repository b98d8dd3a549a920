// Unit and property tests for shadowkit/cascades.hpp.
// References: closed-form split schemes, closed-form frustum corners, brute-force selection.
#include <shadowkit/cascades.hpp>
#include <shadowkit/infinite_projection.hpp>
#include <shadowkit/shadow_cache.hpp>  // issue 25: the stable fit -> cache contract

#include <doctest/doctest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <random>
#include <string>
#include <vector>

using namespace shadowkit;

namespace {

constexpr double kPi = 3.14159265358979323846;

glm::vec3 rdir(std::mt19937& rng) {
    std::normal_distribution<float> g(0.0f, 1.0f);
    glm::vec3 d;
    do { d = glm::vec3(g(rng), g(rng), g(rng)); } while (glm::length(d) < 1e-3f);
    return glm::normalize(d);
}

glm::mat4 look(const glm::vec3& p, const glm::vec3& f) {
    return glm::lookAt(p, p + f, std::fabs(f.y) > 0.99f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0));
}

bool in_clip(const glm::mat4& m, const glm::dvec3& p, ClipDepth cd, double tol) {
    const glm::dvec4 h = glm::dmat4(m) * glm::dvec4(p, 1.0);
    if (!(h.w > 0.0)) return false;
    const double z = h.z / h.w, lo = cd == ClipDepth::ZeroToOne ? 0.0 : -1.0;
    return std::fabs(h.x / h.w) <= 1 + tol && std::fabs(h.y / h.w) <= 1 + tol && z >= lo - tol && z <= 1 + tol;
}

glm::dvec2 origin_texel(const glm::mat4& m, unsigned S) {
    const glm::dvec4 h = glm::dmat4(m) * glm::dvec4(0, 0, 0, 1);
    return (glm::dvec2(h) / h.w) * (0.5 * S) + 0.5 * double(S);
}

// A point of the camera's view volume at view depth dep, (sx, sy) in [-1, 1] across it (symmetric
// perspective with the given fovy / aspect): closed form.
glm::dvec3 view_point(const glm::mat4& view, double fovy, double aspect, double dep, double sx, double sy) {
    const double ty = std::tan(0.5 * fovy), tx = ty * aspect;
    const glm::dvec3 pv(sx * tx * dep, sy * ty * dep, -dep);
    return glm::dvec3(glm::inverse(glm::dmat4(view)) * glm::dvec4(pv, 1.0));
}

CascadeInput base_input() {
    CascadeInput in;
    in.camera_view = glm::lookAt(glm::vec3(0, 2, 0), glm::vec3(0, 2, -1), glm::vec3(0, 1, 0));
    in.camera_proj = glm::perspective(1.0f, 1.5f, 0.1f, 100.0f);
    in.light_position = glm::vec4(-glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f)), 0.0f);
    return in;
}

}  // namespace

TEST_CASE("cascades: split distances match the closed form, monotonic, exact ends") {
    CascadeSplits s = cascade_split_distances(0.5f, 200.0f, 0.0f, 4);
    REQUIRE(s.status == Status::Ok);
    CHECK(s.count == 4);
    for (int i = 0; i <= 4; ++i) CHECK(s.distances[i] == doctest::Approx(0.5 + 199.5 * i / 4.0));
    s = cascade_split_distances(0.5f, 200.0f, 1.0f, 4);
    REQUIRE(s.status == Status::Ok);
    for (int i = 0; i <= 4; ++i) CHECK(s.distances[i] == doctest::Approx(0.5 * std::pow(400.0, i / 4.0)));
    s = cascade_split_distances(1.0f, 100.0f, 0.5f, 2);
    REQUIRE(s.status == Status::Ok);
    CHECK(s.distances[1] == doctest::Approx(0.5 * 10.0 + 0.5 * 50.5));
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int it = 0; it < 5000; ++it) {
        const float n = std::pow(10.0f, -5.0f + 6.0f * u(rng));
        const float f = n * std::pow(10.0f, 7.0f * u(rng)) + n * 1e-3f;
        const std::uint32_t c = 1 + rng() % 8;
        const float l = u(rng);
        if (!(f > n)) continue;
        s = cascade_split_distances(n, f, l, c);
        REQUIRE(s.status == Status::Ok);
        CHECK(s.distances[0] == n);
        CHECK(s.distances[c] == f);
        for (std::uint32_t i = 0; i < c; ++i) CHECK(s.distances[i] < s.distances[i + 1]);
    }
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    CHECK(cascade_split_distances(0.0f, 10.0f, 0.5f, 4).status == Status::InvalidArgument);
    CHECK(cascade_split_distances(-1.0f, 10.0f, 0.5f, 4).status == Status::InvalidArgument);
    CHECK(cascade_split_distances(1.0f, 1.0f, 0.5f, 4).status == Status::InvalidArgument);
    CHECK(cascade_split_distances(1.0f, inf, 0.5f, 4).status == Status::NonFinite);  // was InfiniteFar
    CHECK(cascade_split_distances(nan, 10.0f, 0.5f, 4).status == Status::NonFinite);
    CHECK(cascade_split_distances(1.0f, 10.0f, 1.5f, 4).status == Status::InvalidArgument);
    CHECK(cascade_split_distances(1.0f, 10.0f, 0.5f, 0).status == Status::InvalidArgument);
    CHECK(cascade_split_distances(1.0f, 10.0f, 0.5f, 17).status == Status::InvalidArgument);
    // four splits between two adjacent floats cannot be strictly increasing
    CHECK(cascade_split_distances(1.0f, std::nextafter(1.0f, 2.0f), 0.5f, 4).status == Status::Overflow);
    CHECK(CascadeSplits{}.status == Status::NotRun);
}

TEST_CASE("cascades: every point of each slice is inside its cascade (random cameras and lights)") {
    std::mt19937 rng(77);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    int pts = 0, caster_pts = 0;
    for (int it = 0; it < 1500; ++it) {
        CascadeInput in;
        const glm::vec3 pos = glm::vec3(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f) * 100.0f;
        const glm::vec3 fwd = rdir(rng);
        in.camera_view = look(pos, fwd);
        const float fovy = 0.4f + 1.4f * u(rng), aspect = 0.5f + 1.5f * u(rng), n = 0.01f + u(rng), f = n * (10.0f + 1000.0f * u(rng));
        const bool inf = rng() % 3 == 0;
        const bool zo = rng() & 1;
        in.camera_proj = inf ? glm::infinitePerspective(fovy, aspect, n) : (zo ? glm::perspectiveZO(fovy, aspect, n, f) : glm::perspective(fovy, aspect, n, f));
        in.camera_depth = (zo && !inf) ? ClipDepth::ZeroToOne : ClipDepth::NegativeOneToOne;
        in.max_distance = inf ? f : (rng() % 2 ? f * u(rng) + n * 2.0f : 0.0f);
        const glm::vec3 toward = rdir(rng);
        in.light_position = glm::vec4(toward, 0.0f);
        in.shadow_map_size = 512u << (rng() % 4);
        in.light_depth = (rng() & 1) ? ClipDepth::ZeroToOne : ClipDepth::NegativeOneToOne;
        in.light_reversed_z = rng() % 3 == 0;
        in.has_caster_bounds = rng() % 2 == 0;
        in.caster_min = pos - glm::vec3(200);
        in.caster_max = pos + glm::vec3(200);
        Cascade c[4];
        const std::uint32_t count = 1 + rng() % 4;
        const CascadeFitResult fit = cascade_fit(in, u(rng), count, c, 4);
        REQUIRE(fit.status == Status::Ok);
        REQUIRE(fit.count == count);
        CHECK(fit.needed == count);
        const float* s = fit.splits;
        for (std::uint32_t i = 0; i < count; ++i) {
            CHECK(c[i].status == Status::Ok);
            {  // winding: a triangle counter-clockwise seen from the light stays counter-clockwise
                const glm::dvec3 e1 = glm::normalize(glm::cross(glm::dvec3(toward), glm::dvec3(rdir(rng))));
                const glm::dvec3 e2 = glm::cross(glm::dvec3(toward), e1);
                const glm::dvec3 a = glm::dvec3(glm::vec3(c[i].sphere));
                const glm::dvec3 b = a + e1, cc = a + e2;
                auto nd = [&](const glm::dvec3& p) {
                    const glm::dvec4 h = glm::dmat4(c[i].view_proj) * glm::dvec4(p, 1.0);
                    return glm::dvec2(h.x, h.y) / h.w;
                };
                const glm::dvec2 na = nd(a), nb = nd(b), nc = nd(cc);
                CHECK((nb.x - na.x) * (nc.y - na.y) - (nb.y - na.y) * (nc.x - na.x) > 0.0);
            }
            for (int k = 0; k < 30; ++k) {
                const double dep = s[i] + (s[i + 1] - s[i]) * double(u(rng));
                const glm::dvec3 p = view_point(in.camera_view, fovy, aspect, dep, 2 * double(u(rng)) - 1, 2 * double(u(rng)) - 1);
                ++pts;
                if (!in_clip(c[i].view_proj, p, in.light_depth, 1e-4)) {
                    FAIL_CHECK("slice point outside its cascade, it=" << it << " cascade " << i);
                    break;
                }
                // casters toward the light (light_position's xyz) inside the caster bounds are inside too
                if (in.has_caster_bounds) {
                    const glm::dvec3 q = p + glm::dvec3(toward) * (50.0 * double(u(rng)));
                    const glm::dvec3 d = glm::abs(q - glm::dvec3(pos));
                    if (d.x < 200 && d.y < 200 && d.z < 200) {
                        ++caster_pts;
                        CHECK(in_clip(c[i].view_proj, q, in.light_depth, 1e-4));
                    }
                }
                // selection by depth agrees with a linear scan
                const CascadeIndex sel = cascade_select_by_depth(float(dep), s, count);
                REQUIRE(sel.status == Status::Ok);
                CHECK((sel.index >= 0 && s[sel.index] <= float(dep) && float(dep) <= s[sel.index + 1]));
            }
        }
    }
    MESSAGE("cascade slice points checked: " << pts << ", caster points toward the light: " << caster_pts);
}

// Issue 13 item 2: the light is light_position (toward the light), no longer the direction the
// light travels. With the sun overhead the caster bounds above the receivers must be inside the
// cascade's depth range; the old convention put the near plane on the wrong side.
TEST_CASE("cascades: light_position points toward the light; point lights are rejected (issue 13 item 2)") {
    CascadeInput in = base_input();
    in.camera_view = glm::lookAt(glm::vec3(0, 2, 0), glm::vec3(0, 0, -10), glm::vec3(0, 1, 0));
    in.light_position = glm::vec4(0, 1, 0, 0);  // sun straight overhead
    in.has_caster_bounds = true;
    in.caster_min = glm::vec3(-100, -1, -100);
    in.caster_max = glm::vec3(100, 80, 100);
    Cascade c[4];
    const CascadeFitResult fit = cascade_fit(in, 0.75f, 4, c, 4);
    REQUIRE(fit.status == Status::Ok);
    for (int i = 0; i < 4; ++i) {
        const glm::dvec3 p = view_point(in.camera_view, 1.0, 1.5, 0.5 * (fit.splits[i] + fit.splits[i + 1]), 0.0, 0.0);
        CHECK(in_clip(c[i].view_proj, p, in.light_depth, 1e-4));
        CHECK(in_clip(c[i].view_proj, p + glm::dvec3(0, 60, 0), in.light_depth, 1e-4));  // a caster above
        // the light looks down: the point above is nearer to the light (smaller NDC depth)
        const glm::dvec4 a = glm::dmat4(c[i].view_proj) * glm::dvec4(p + glm::dvec3(0, 60, 0), 1.0);
        const glm::dvec4 b = glm::dmat4(c[i].view_proj) * glm::dvec4(p, 1.0);
        CHECK(a.z / a.w < b.z / b.w);
    }
    in.light_position = glm::vec4(0, 10, 0, 1);
    CHECK(cascade_fit(in, 0.75f, 4, c, 4).status == Status::InvalidLight);
    CHECK(cascade_fit_slice(in, 1.0f, 10.0f).status == Status::InvalidLight);
    in.light_position = glm::vec4(0, 0, 0, 0);
    CHECK(cascade_fit(in, 0.75f, 4, c, 4).status == Status::InvalidLight);
    in.light_position = glm::vec4(0, 1, 0, -1);
    CHECK(cascade_fit(in, 0.75f, 4, c, 4).status == Status::InvalidLight);
    in.light_position = glm::vec4(std::numeric_limits<float>::quiet_NaN(), 1, 0, 0);
    CHECK(cascade_fit(in, 0.75f, 4, c, 4).status == Status::InvalidLight);
}

TEST_CASE("cascades: stable fits are rotation invariant and move by whole texels (anchor: no swimming)") {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int it = 0; it < 200; ++it) {
        CascadeInput in;
        in.camera_proj = glm::perspective(0.6f + u(rng), 0.8f + u(rng), 0.1f + u(rng), 50.0f + 200.0f * u(rng));
        in.light_position = glm::vec4(rdir(rng), 0.0f);
        in.shadow_map_size = 2048;
        const glm::vec3 pos = glm::vec3(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f) * 50.0f;
        in.camera_view = look(pos, rdir(rng));
        Cascade a[4], b[4];
        REQUIRE(cascade_fit(in, 0.7f, 4, a, 4).status == Status::Ok);
        in.camera_view = look(pos, rdir(rng));  // rotate about the position
        REQUIRE(cascade_fit(in, 0.7f, 4, b, 4).status == Status::Ok);
        for (int i = 0; i < 4; ++i) {
            CHECK(std::fmod(double(a[i].sphere.w) * 16.0, 1.0) == 0.0);
            CHECK(a[i].sphere.w == b[i].sphere.w);
            for (int col = 0; col < 3; ++col)
                for (int row = 0; row < 2; ++row) CHECK(a[i].view_proj[col][row] == b[i].view_proj[col][row]);
            const glm::dvec2 ta = origin_texel(a[i].view_proj, 2048), tb = origin_texel(b[i].view_proj, 2048);
            CHECK(std::fabs(ta.x - std::round(ta.x)) < 1e-3);
            CHECK(std::fabs(ta.y - std::round(ta.y)) < 1e-3);
            CHECK(std::fabs(tb.x - std::round(tb.x)) < 1e-3);
            CHECK(std::fabs(tb.y - std::round(tb.y)) < 1e-3);
        }
        // sub-texel translation: same texel size, origin stays on a texel corner
        const glm::vec3 f2 = rdir(rng);
        in.camera_view = look(pos, f2);
        REQUIRE(cascade_fit(in, 0.7f, 4, a, 4).status == Status::Ok);
        const glm::vec3 p2 = pos + rdir(rng) * (0.4f * a[0].texel_world_size);
        in.camera_view = look(p2, f2);
        REQUIRE(cascade_fit(in, 0.7f, 4, b, 4).status == Status::Ok);
        for (int i = 0; i < 4; ++i) {
            CHECK(a[i].texel_world_size == b[i].texel_world_size);
            const glm::dvec2 dt = origin_texel(b[i].view_proj, 2048) - origin_texel(a[i].view_proj, 2048);
            CHECK(std::fabs(dt.x - std::round(dt.x)) < 1e-3);
            CHECK(std::fabs(dt.y - std::round(dt.y)) < 1e-3);
        }
    }
}

TEST_CASE("cascades: selection by sphere and the blend band") {
    const CascadeInput in = base_input();
    Cascade c[4];
    const CascadeFitResult fit = cascade_fit(in, 0.8f, 4, c, 4);
    REQUIRE(fit.status == Status::Ok);
    const float* s = fit.splits;
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int k = 0; k < 2000; ++k) {
        const glm::vec3 p(u(rng) * 200 - 100, u(rng) * 50 - 25, -u(rng) * 120);
        int expect = -1;
        for (int i = 0; i < 4 && expect < 0; ++i)
            if (glm::length(glm::dvec3(p) - glm::dvec3(glm::vec3(c[i].sphere))) <= double(c[i].sphere.w) * (1 - 1e-6)) expect = i;
        const CascadeIndex got = cascade_select_by_sphere(p, c, 4);
        REQUIRE(got.status == Status::Ok);
        if (expect >= 0) CHECK(got.index == expect);
        if (got.index >= 0) CHECK(in_clip(c[got.index].view_proj, glm::dvec3(p), in.light_depth, 1e-4));
    }
    CHECK(cascade_select_by_sphere(glm::vec3(std::numeric_limits<float>::quiet_NaN()), c, 4).status == Status::NonFinite);
    CHECK(cascade_select_by_sphere(glm::vec3(0), nullptr, 4).status == Status::InvalidArgument);
    Cascade unfitted[2];
    CHECK(cascade_select_by_sphere(glm::vec3(0), unfitted, 2).status == Status::InvalidArgument);
    // blend: 0 before the band, 1 at the far split, linear and monotonic in between
    CHECK(cascade_blend_weight(5.0f, 0.0f, 10.0f, 0.2f) == 0.0f);
    CHECK(cascade_blend_weight(8.0f, 0.0f, 10.0f, 0.2f) == 0.0f);
    CHECK(cascade_blend_weight(9.0f, 0.0f, 10.0f, 0.2f) == doctest::Approx(0.5f));
    CHECK(cascade_blend_weight(10.0f, 0.0f, 10.0f, 0.2f) == 1.0f);
    CHECK(cascade_blend_weight(12.0f, 0.0f, 10.0f, 0.2f) == 1.0f);
    float prev = 0.0f;
    for (float d = 0.0f; d <= 10.0f; d += 0.01f) {
        const float w = cascade_blend_weight(d, 0.0f, 10.0f, 0.3f);
        CHECK(w >= prev);
        CHECK(w - prev < 0.01f / 3.0f + 1e-4f);
        prev = w;
    }
    CHECK(cascade_blend_weight(std::numeric_limits<float>::quiet_NaN(), 0.0f, 10.0f, 0.2f) == 0.0f);
    CHECK(cascade_blend_weight(5.0f, 10.0f, 0.0f, 0.2f) == 0.0f);
    // depth selection edges
    CHECK(cascade_select_by_depth(s[0], s, 4).index == 0);
    CHECK(cascade_select_by_depth(s[4], s, 4).index == 3);
    const CascadeIndex beyond = cascade_select_by_depth(s[4] * 1.01f, s, 4);
    CHECK(beyond.status == Status::Ok);
    CHECK(beyond.index == -1);
    CHECK(cascade_select_by_depth(0.5f * s[0], s, 4).index == -1);
    CHECK(cascade_select_by_depth(std::numeric_limits<float>::quiet_NaN(), s, 4).status == Status::NonFinite);
    CHECK(cascade_select_by_depth(1.0f, nullptr, 4).status == Status::InvalidArgument);
    CHECK(cascade_select_by_depth(1.0f, s, 0).status == Status::InvalidArgument);
    const float bad[3] = {1.0f, 5.0f, 3.0f};  // not increasing
    CHECK(cascade_select_by_depth(2.0f, bad, 2).status == Status::InvalidArgument);
}

// Issue 13 item 3 for the cascade fit: any output of infinite_projection.hpp's perspective /
// perspective_infinite works (epsilon-tweaked: NDC +1 lies beyond infinity), with max_distance.
TEST_CASE("cascades: every projection of infinite_projection.hpp is accepted (issue 13 item 3)") {
    const float fovy = 0.9f, aspect = 1.6f, n = 0.3f;
    int fits = 0;
    for (int cdi = 0; cdi < 2; ++cdi)
        for (int rev = 0; rev < 2; ++rev)
            for (float eps : {0.0f, 4.8e-7f, 1e-4f, 0.5f}) {
                const ClipDepth cd = cdi ? ClipDepth::ZeroToOne : ClipDepth::NegativeOneToOne;
                CascadeInput in = base_input();
                in.camera_proj = projection_perspective_infinite(fovy, aspect, n, cd, rev != 0, eps).matrix;
                REQUIRE(in.camera_proj[2][3] == -1.0f);
                in.camera_depth = cd;
                in.camera_reversed_z = rev != 0;
                Cascade c[4];
                INFO("clip depth " << cdi << " reversed " << rev << " epsilon " << eps);
                CHECK(cascade_fit(in, 0.75f, 4, c, 4).status == Status::InvalidArgument);  // needs max_distance
                in.max_distance = 250.0f;
                const CascadeFitResult fit = cascade_fit(in, 0.75f, 4, c, 4);
                REQUIRE(fit.status == Status::Ok);
                CHECK(fit.splits[0] == doctest::Approx(n));
                CHECK(fit.splits[4] == 250.0f);
                for (int i = 0; i < 4; ++i)
                    for (double sx : {-1.0, 1.0})
                        for (double sy : {-1.0, 1.0})
                            for (double dep : {double(fit.splits[i]), double(fit.splits[i + 1])})
                                CHECK(in_clip(c[i].view_proj, view_point(in.camera_view, fovy, aspect, dep, sx, sy), in.light_depth, 1e-4));
                ++fits;
                // a finite far plane from the same header
                ProjectionDepth dp;
                dp.near_z = n;
                dp.far_z = 120.0f;
                dp.clip_depth = cd;
                dp.reversed_z = rev != 0;
                in.camera_proj = projection_perspective(fovy, aspect, dp).matrix;
                in.max_distance = 0.0f;
                const CascadeFitResult ff = cascade_fit(in, 0.75f, 4, c, 4);
                REQUIRE(ff.status == Status::Ok);
                CHECK(ff.splits[4] == doctest::Approx(120.0f).epsilon(1e-5));
            }
    MESSAGE("cascade fits with infinite_projection.hpp matrices: " << fits);
}

// Issue 19 items 4 and 6: null output with a capacity, too small a buffer, and a camera near plane at
// or behind the eye are errors, never Ok.
TEST_CASE("cascades: null pointers, small buffers and bad projections are rejected (issue 19)") {
    CascadeInput in = base_input();
    Cascade c[4];
    CHECK(cascade_fit(in, 0.75f, 4, nullptr, 4).status == Status::InvalidArgument);
    const CascadeFitResult small = cascade_fit(in, 0.75f, 4, c, 3);
    CHECK(small.status == Status::BufferTooSmall);
    CHECK(small.needed == 4);
    CHECK(small.count == 0);
    CHECK(cascade_fit(in, 0.75f, 4, nullptr, 0).status == Status::BufferTooSmall);
    CHECK(cascade_fit(in, 0.75f, 0, c, 4).status == Status::InvalidArgument);
    CHECK(cascade_fit(in, 0.75f, 17, c, 4).status == Status::InvalidArgument);
    CHECK(cascade_fit(in, std::numeric_limits<float>::quiet_NaN(), 4, c, 4).status == Status::NonFinite);
    CHECK(cascade_fit(in, 1.5f, 4, c, 4).status == Status::InvalidArgument);
    for (float n : {-0.5f, -1e-3f, -20.0f}) {
        in.camera_proj = glm::perspective(1.0f, 1.5f, n, 100.0f);
        CHECK(cascade_fit(in, 0.75f, 4, c, 4).status == Status::InvalidArgument);
        CHECK(cascade_fit_slice(in, 1.0f, 10.0f).status == Status::InvalidArgument);
        in.camera_proj = glm::perspectiveZO(1.0f, 1.5f, n, 100.0f);
        in.camera_depth = ClipDepth::ZeroToOne;
        CHECK(cascade_fit(in, 0.75f, 4, c, 4).status == Status::InvalidArgument);
        in.camera_proj = glm::ortho(-5.f, 5.f, -5.f, 5.f, n, 100.f);
        in.camera_depth = ClipDepth::NegativeOneToOne;
        CHECK(cascade_fit(in, 0.75f, 4, c, 4).status == Status::InvalidArgument);
    }
    in.camera_proj = glm::perspective(1.0f, 1.5f, 0.0f, 100.0f);
    CHECK(cascade_fit(in, 0.75f, 4, c, 4).status == Status::InvalidArgument);
    in = base_input();
    in.max_distance = -5.0f;
    CHECK(cascade_fit(in, 0.75f, 4, c, 4).status == Status::InvalidArgument);
    in.max_distance = 0.05f;  // below the near plane 0.1
    CHECK(cascade_fit(in, 0.75f, 4, c, 4).status == Status::InvalidArgument);
    in = base_input();
    in.has_caster_bounds = true;
    in.caster_min = glm::vec3(1);
    in.caster_max = glm::vec3(0);
    CHECK(cascade_fit(in, 0.75f, 4, c, 4).status == Status::InvalidArgument);
    CHECK(cascade_fit(CascadeInput{}, 0.75f, 4, c, 4).status != Status::Ok);  // required fields
    CHECK(Cascade{}.status == Status::NotRun);
}

TEST_CASE("cascades: stiff cases") {
    CascadeInput in = base_input();
    Cascade c[4];
    SUBCASE("near 1e-5 with an infinite far plane needs max_distance") {
        in.camera_proj = glm::infinitePerspective(1.0f, 1.0f, 1e-5f);
        CHECK(cascade_fit(in, 0.9f, 4, c, 4).status == Status::InvalidArgument);  // was InfiniteFar
        in.max_distance = 10.0f;  // ratio 1e-6
        const CascadeFitResult fit = cascade_fit(in, 0.9f, 4, c, 4);
        REQUIRE(fit.status == Status::Ok);
        CHECK(fit.splits[0] == doctest::Approx(1e-5f));
        CHECK(fit.splits[4] == 10.0f);
        CHECK(in_clip(c[0].view_proj, glm::dvec3(0, 2, -2e-5), in.light_depth, 1e-4));
    }
    SUBCASE("light parallel and anti-parallel to the view, straight down on a camera looking down") {
        in.camera_proj = glm::perspective(1.0f, 1.0f, 0.1f, 50.0f);
        for (const glm::vec3 l : {glm::vec3(0, 0, -1), glm::vec3(0, 0, 1)}) {
            in.light_position = glm::vec4(l, 0.0f);
            REQUIRE(cascade_fit(in, 0.5f, 3, c, 4).status == Status::Ok);
            CHECK(in_clip(c[2].view_proj, glm::dvec3(0, 2, -40), in.light_depth, 1e-4));
        }
        in.camera_view = glm::lookAt(glm::vec3(0, 10, 0), glm::vec3(0, 0, 0), glm::vec3(0, 0, -1));
        for (const glm::vec3 l : {glm::vec3(0, 1, 0), glm::vec3(0, -1, 0)}) {  // -1: the frame's singular direction
            in.light_position = glm::vec4(l, 0.0f);
            REQUIRE(cascade_fit(in, 0.5f, 3, c, 4).status == Status::Ok);
            CHECK(in_clip(c[0].view_proj, glm::dvec3(0, 9.8, 0), in.light_depth, 1e-4));
        }
    }
    SUBCASE("coordinates at 1e6") {
        const glm::vec3 o(1e6f, 1e6f, 1e6f);
        in.camera_view = glm::lookAt(o, o + glm::vec3(1, 0, 0), glm::vec3(0, 1, 0));
        // near 0.5: float receivers at 1e6 are 0.0625 apart and the float matrix's terms ~1e6 / half
        // width cancel; the worst case misplaces the first cascade's receivers by more than 0.01 NDC
        // (issue #27 item 3): Overflow, not an Ok that a vertex shader cannot honor
        in.camera_proj = glm::perspective(1.0f, 1.0f, 0.5f, 100.0f);
        CHECK(cascade_fit(in, 0.5f, 4, c, 4).status == Status::Overflow);
        in.camera_proj = glm::perspective(1.0f, 1.0f, 2.0f, 200.0f);
        REQUIRE(cascade_fit(in, 0.5f, 4, c, 4).status == Status::Ok);
        CHECK(in_clip(c[3].view_proj, glm::dvec3(o) + glm::dvec3(180, 0, 0), in.light_depth, 1e-3));
        // a camera at 3e38: the matrix's translation (3e38 / half-width) is beyond float: Overflow
        const glm::vec3 far_o(3e38f, 0.0f, 0.0f);
        in.camera_view = glm::lookAt(glm::vec3(0), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0)) * glm::translate(glm::mat4(1.0f), -far_o);
        const Cascade one = cascade_fit_slice(in, 1.0f, 2.0f);
        CHECK(one.status == Status::Overflow);
    }
    SUBCASE("NaN / degenerate input") {
        in.camera_proj = glm::perspective(1.0f, 1.0f, 0.5f, 100.0f);
        in.light_position = glm::vec4(0.0f);
        CHECK(cascade_fit(in, 0.5f, 4, c, 4).status == Status::InvalidLight);
        in.light_position = glm::vec4(0, 1, 0, 0);
        in.camera_proj = glm::mat4(0.0f);
        CHECK(cascade_fit(in, 0.5f, 4, c, 4).status == Status::InvalidArgument);
        in.camera_proj[0][0] = std::numeric_limits<float>::infinity();
        CHECK(cascade_fit(in, 0.5f, 4, c, 4).status == Status::NonFinite);
        in.camera_proj = glm::perspective(1.0f, 1.0f, 0.5f, 100.0f);
        in.shadow_map_size = 2;
        CHECK(cascade_fit(in, 0.5f, 4, c, 4).status == Status::InvalidArgument);
        in.shadow_map_size = 1024;
        CHECK(cascade_fit_slice(in, 5.0f, 5.0f).status == Status::InvalidArgument);  // zero-size slice
        CHECK(cascade_fit_slice(in, 5.0f, 5.001f).status == Status::Ok);
        CHECK(cascade_fit_slice(in, 200.0f, 300.0f).status == Status::InvalidArgument);  // beyond the far plane
    }
}

// Issue 14 "must hold" for the cascades: the light's travel direction turns through the view direction
// (and, coarser, the whole circle); a fixed set of slice points moves < 0.01 NDC per 0.002-degree step
// and the points' NDC extent changes < 5% within 0.01 degree, except within 0.5 degree of the frame's
// singular direction (a light shining straight up). The old frame (world axis least aligned with the
// light) rolled the cascades by 90 degrees when two components of the direction were equal.
TEST_CASE("cascades: continuity while the light turns through the view direction (issue 14)") {
    std::mt19937 rng(99);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    long fits = 0, fine = 0, failures = 0;
    double max_move = 0.0, max_ext = 0.0, max_move_pole = 0.0;
    auto near_dir = [](const glm::dvec3& a, const glm::dvec3& b, double deg) {
        return glm::dot(a, b) >= std::cos(deg * kPi / 180.0);
    };
    for (int cs = 0; cs < 8; ++cs) {
        CascadeInput in;
        const glm::vec3 pos = glm::vec3(u(rng) - 0.5f, u(rng) * 0.2f, u(rng) - 0.5f) * 40.0f;
        glm::vec3 fwd = rdir(rng);
        if (cs == 0) fwd = glm::normalize(glm::vec3(0, -0.2f, -1));
        if (cs == 1) fwd = glm::vec3(0, 1, 0);  // looking straight up: parallel and the pole coincide
        in.camera_view = look(pos, fwd);
        const float fovy = 0.6f + u(rng), aspect = 1.0f + u(rng);
        in.camera_proj = glm::infinitePerspective(fovy, aspect, 0.1f);
        in.max_distance = 80.0f + 200.0f * u(rng);
        in.shadow_map_size = 1024;
        const glm::dvec3 v(fwd);
        const glm::dvec3 w = glm::normalize(glm::cross(v, glm::dvec3(rdir(rng))));
        // 48 points in each cascade's slice (closed form), for cascades 0 and 3
        const CascadeSplits sp = cascade_split_distances(0.1f, in.max_distance, 0.75f, 4);
        REQUIRE(sp.status == Status::Ok);
        std::vector<glm::dvec3> pts[4];
        for (int i = 0; i < 4; ++i)
            for (int k = 0; k < 48; ++k) {
                const double dep = sp.distances[i] + (sp.distances[i + 1] - sp.distances[i]) * double(u(rng));
                pts[i].push_back(view_point(in.camera_view, fovy, aspect, dep, 2 * double(u(rng)) - 1, 2 * double(u(rng)) - 1));
            }
        auto sample = [&](double deg, std::vector<glm::dvec2> out[4], glm::dvec2 ext[4]) {
            const double t = deg * kPi / 180.0;
            const glm::dvec3 d = glm::normalize(v * std::cos(t) + w * std::sin(t));
            CascadeInput x = in;
            x.light_position = glm::vec4(glm::vec3(-d), 0.0f);
            Cascade c[4];
            ++fits;
            REQUIRE(cascade_fit(x, 0.75f, 4, c, 4).status == Status::Ok);
            for (int i = 0; i < 4; ++i) {
                out[i].clear();
                glm::dvec2 lo(1e300), hi(-1e300);
                for (const glm::dvec3& p : pts[i]) {
                    const glm::dvec4 h = glm::dmat4(c[i].view_proj) * glm::dvec4(p, 1.0);
                    out[i].push_back(glm::dvec2(h.x, h.y) / h.w);
                    lo = glm::min(lo, out[i].back());
                    hi = glm::max(hi, out[i].back());
                }
                ext[i] = hi - lo;
            }
            return d;
        };
        auto walk = [&](double a, double b, double step, bool check) {
            std::vector<glm::dvec2> p0[4], p1[4];
            glm::dvec2 e0[4], e1[4], ew[4];
            glm::dvec3 d0 = sample(a, p0, e0);
            for (int i = 0; i < 4; ++i) ew[i] = e0[i];
            const int n = int(std::lround((b - a) / step));
            double coarse_max = 0.0;
            for (int k = 1; k <= n; ++k) {
                const glm::dvec3 d1 = sample(a + step * k, p1, e1);
                const bool pole = near_dir(d0, glm::dvec3(0, 1, 0), 0.5) || near_dir(d1, glm::dvec3(0, 1, 0), 0.5);
                for (int i = 0; i < 4; ++i) {
                    double mv = 0.0;
                    for (std::size_t j = 0; j < p0[i].size(); ++j) mv = std::fmax(mv, glm::length(p1[i][j] - p0[i][j]));
                    const double ec = std::fmax(std::fabs(e1[i].x / e0[i].x - 1), std::fabs(e1[i].y / e0[i].y - 1));
                    coarse_max = std::fmax(coarse_max, std::fmax(mv / 0.03, ec / 0.03));
                    if (!check) continue;
                    if (pole) { max_move_pole = std::fmax(max_move_pole, mv); continue; }
                    max_move = std::fmax(max_move, mv);
                    if (mv >= 0.01 && failures++ < 5) FAIL_CHECK("cascade " << i << " moves " << mv << " NDC at " << a + step * k);
                    if (k % 5 == 0) {  // extent over the last 0.01 degree
                        const double ew_c = std::fmax(std::fabs(e1[i].x / ew[i].x - 1), std::fabs(e1[i].y / ew[i].y - 1));
                        max_ext = std::fmax(max_ext, ew_c);
                        if (ew_c > 0.05 && failures++ < 5) FAIL_CHECK("cascade " << i << " extent changes " << ew_c);
                        ew[i] = e1[i];
                    }
                }
                for (int i = 0; i < 4; ++i) { p0[i].swap(p1[i]); e0[i] = e1[i]; }
                d0 = d1;
            }
            return coarse_max;
        };
        // coarse circle (0.5 degree): re-walk in 0.002-degree steps where a step moves > 0.03 or the
        // extent changes > 3%; and always across [-1.5, 1.5] degrees around parallel and anti-parallel
        for (int k = 0; k < 720; ++k)
            if (walk(0.5 * k, 0.5 * (k + 1), 0.5, false) >= 1.0) {
                fine += 250;
                walk(0.5 * k, 0.5 * (k + 1), 0.002, true);
            }
        for (double c : {0.0, 180.0}) {
            walk(c - 1.5, c + 1.5, 0.002, true);
            fine += 1500;
        }
    }
    MESSAGE("cascades: fits " << fits << ", fine steps " << fine << ", max move " << max_move
                              << " NDC (within 0.5 deg of a light shining straight up: " << max_move_pole
                              << "), max extent change in 0.01 deg " << max_ext * 100 << "%");
    CHECK(failures == 0);
}

// Issue #27 item 3: a vertex shader transforms float world positions with the float matrix in float.
// Far from the origin (camera at ~1e5, slices a few hundredths wide) the guard on the 8 float-rounded
// corners passed while other receivers landed 0.5 NDC outside. Receivers here: the slice corners
// computed in float (closed-form view-space corners, float inverse view) and float blends of them,
// through the float view_proj in float; every Ok cascade must hold them within 0.01 NDC.
TEST_CASE("cascades: far from the origin every Ok cascade holds its float receivers (float corners, float matrix)") {
    std::mt19937 rng(2027);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    int fits = 0, ok_cascades = 0, overflow = 0, outside = 0;
    float worst = 0.0f;
    for (int it = 0; it < 1000; ++it) {
        CascadeInput in;
        const glm::vec3 pos = rdir(rng) * std::pow(10.0f, 3.0f + 2.3f * u(rng));
        const glm::vec3 fwd = rdir(rng);
        in.camera_view = look(pos, fwd);
        const float fovy = 0.4f + 1.4f * u(rng), aspect = 0.5f + 1.5f * u(rng);
        const float n = std::pow(10.0f, -3.0f + 2.0f * u(rng)), f = n * (2.0f + 30.0f * u(rng));
        in.camera_proj = glm::perspective(fovy, aspect, n, f);
        in.light_position = glm::vec4(rdir(rng), 0.0f);
        in.shadow_map_size = 512u << (rng() % 4);
        in.light_depth = (rng() & 1) ? ClipDepth::ZeroToOne : ClipDepth::NegativeOneToOne;
        Cascade c[4];
        const std::uint32_t count = 1 + rng() % 4;
        const CascadeFitResult fit = cascade_fit(in, u(rng), count, c, 4);
        ++fits;
        if (fit.status == Status::Overflow) ++overflow;
        const glm::mat4 inv_view = glm::inverse(in.camera_view);  // float, as an application has it
        const float ty = std::tan(0.5f * fovy), tx = ty * aspect;
        for (std::size_t i = 0; i < fit.count; ++i) {
            REQUIRE(c[i].status == Status::Ok);
            ++ok_cascades;
            glm::vec3 corner[8];
            for (int k = 0; k < 8; ++k) {
                const float dep = (k & 4) ? fit.splits[i + 1] : fit.splits[i];
                const float sx = (k & 1) ? 1.0f : -1.0f, sy = (k & 2) ? 1.0f : -1.0f;
                corner[k] = glm::vec3(inv_view * glm::vec4(sx * tx * dep, sy * ty * dep, -dep, 1.0f));
            }
            const float zlo = in.light_depth == ClipDepth::ZeroToOne ? 0.0f : -1.0f;
            for (int k = 0; k < 64; ++k) {
                glm::vec3 p = corner[k % 8];
                if (k >= 8) {  // a float blend of two corners: a receiver inside the slice
                    const float a = u(rng);
                    p = corner[rng() % 8] * a + corner[rng() % 8] * (1.0f - a);
                }
                const glm::vec4 h = c[i].view_proj * glm::vec4(p, 1.0f);  // float, as the vertex shader
                const float x = h.x / h.w, y = h.y / h.w, z = h.z / h.w;
                const float out = std::max({std::fabs(x) - 1.0f, std::fabs(y) - 1.0f, zlo - z, z - 1.0f});
                worst = std::max(worst, out);
                if (!(out <= 0.01f)) {
                    ++outside;
                    break;
                }
            }
        }
    }
    MESSAGE(fits << " far fits: " << ok_cascades << " Ok cascades, " << overflow << " Overflow; receivers outside by "
                 << worst << " NDC at worst; " << outside << " cascades with a receiver outside");
    CHECK(outside == 0);
}

// Issue 25 ("Must hold": the stable-fit -> cache contract). A cascade's default depth range follows the
// camera (the slice's sphere), so a camera move with any component along the light moved the depth
// planes and shadow_cache_plan rendered the whole map (DepthMoved). With stable_world_depth the range
// comes from the scene box: a move of n whole texels of cascade j along the light frame's x axis plus
// any distance along the rays must be a Scroll by -n texels in cascade j (expected from the move itself;
// the light frame's x axis is the direction of the matrix's x row), and no camera move (translations
// from sub-texel to 40 texels, rotations) may give a full render in any cascade. The plan's matrices
// are the float results in double with the x/y translation rebuilt from texel_anchor (closed form:
// the world origin lies at window -texel_anchor). Control: the default range renders most such moves.
namespace {

ShadowCacheMapState cascade_state(const Cascade& c, unsigned S) {
    ShadowCacheMapState st;
    st.view_proj = glm::dmat4(c.view_proj);
    st.view_proj[3][0] = -2.0 * c.texel_anchor.x / double(S) - 1.0;
    st.view_proj[3][1] = -2.0 * c.texel_anchor.y / double(S) - 1.0;
    st.width = st.height = int(S);
    st.has_content = true;
    return st;
}

}  // namespace

TEST_CASE("cascades: stable_world_depth makes camera moves whole-texel scrolls for shadow_cache_plan, never a full render") {
    std::mt19937 rng(2525);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const unsigned S = 1024;
    int plans = 0, renders = 0, scrolls = 0, exact = 0, near_exact = 0, whole_moves = 0, default_renders = 0;
    for (int it = 0; it < 60; ++it) {
        CascadeInput in;
        in.camera_proj = glm::perspective(0.6f + u(rng), 1.0f + u(rng), 0.1f + 0.5f * u(rng), 40.0f + 80.0f * u(rng));
        glm::vec3 to_sun = rdir(rng);
        if (to_sun.y < 0.1f) to_sun.y = 0.1f + u(rng);  // a sun above the horizon
        in.light_position = glm::vec4(glm::normalize(to_sun), 0.0f);
        in.shadow_map_size = S;
        in.has_scene_bounds = true;
        in.scene_min = glm::vec3(-150.0f, -2.0f, -150.0f) + glm::vec3(u(rng), u(rng), u(rng));
        in.scene_max = glm::vec3(150.0f, 12.0f, 150.0f) - glm::vec3(u(rng), u(rng), u(rng));
        in.has_caster_bounds = true;
        in.caster_min = glm::vec3(-100.0f, 0.0f, -100.0f);
        in.caster_max = glm::vec3(100.0f, 30.0f, 100.0f);  // taller than the scene box: it counts too
        in.stable_world_depth = true;
        const glm::vec3 pos = glm::vec3(u(rng) - 0.5f, 0.1f * u(rng), u(rng) - 0.5f) * 40.0f + glm::vec3(0.0f, 2.0f, 0.0f);
        const glm::vec3 fwd = glm::normalize(glm::vec3(u(rng) - 0.5f, -0.2f * u(rng), u(rng) - 0.5f));
        auto fit = [&](const glm::vec3& p, const glm::vec3& f, Cascade* out) {
            in.camera_view = look(p, f);
            return cascade_fit(in, 0.7f, 4, out, 4);
        };
        Cascade a[4];
        REQUIRE(fit(pos, fwd, a).status == Status::Ok);
        const glm::dvec3 d = -glm::normalize(glm::dvec3(in.light_position));  // the rays' direction
        for (int i = 0; i < 4; ++i) {
            // closed form: the world origin at window -texel_anchor, whole numbers (S even)
            CHECK(a[i].texel_anchor.x == std::round(a[i].texel_anchor.x));
            CHECK(a[i].texel_anchor.y == std::round(a[i].texel_anchor.y));
            CHECK(std::fabs(origin_texel(a[i].view_proj, S).x + a[i].texel_anchor.x) < 1e-2);
            CHECK(std::fabs(origin_texel(a[i].view_proj, S).y + a[i].texel_anchor.y) < 1e-2);
            // the depth range holds the scene box and the caster box (brute force over their corners)
            for (int c = 0; c < 16; ++c) {
                const glm::vec3 lo = c < 8 ? in.scene_min : in.caster_min, hi = c < 8 ? in.scene_max : in.caster_max;
                const glm::dvec3 p((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z);
                const glm::dvec4 h = glm::dmat4(a[i].view_proj) * glm::dvec4(p, 1.0);
                CHECK(std::fabs(h.z / h.w) <= 1.0 + 1e-5);
            }
        }
        for (int k = 0; k < 12; ++k) {
            glm::vec3 p = pos, f = fwd;
            const int j = k % 4;
            int n = 0;
            // the light frame's x axis of cascade j: the direction of its matrix's x row
            const glm::dvec3 sx = glm::normalize(glm::dvec3(a[j].view_proj[0][0], a[j].view_proj[1][0], a[j].view_proj[2][0]));
            if (k < 8) {  // n whole texels of cascade j along x, plus up to 3 units along the rays
                n = int(rng() % 61) - 30;
                if (n == 0) n = 7;
                p = glm::vec3(glm::dvec3(pos) + double(n) * double(a[j].texel_world_size) * sx + (6.0 * u(rng) - 3.0) * d);
                ++whole_moves;
            } else if (k < 10) {  // any translation, sub-texel to 40 texels of cascade 0
                p = pos + rdir(rng) * (k == 8 ? 0.3f : 40.0f) * a[0].texel_world_size;
            } else {  // a rotation
                f = glm::normalize(fwd + rdir(rng) * 0.4f);
            }
            Cascade b[4];
            REQUIRE(fit(p, f, b).status == Status::Ok);
            for (int i = 0; i < 4; ++i) {
                ShadowCacheRect rects[4];
                const ShadowCachePlan plan = shadow_cache_plan(cascade_state(a[i], S), cascade_state(b[i], S), nullptr, 0, rects, 4);
                REQUIRE(plan.status == Status::Ok);
                ++plans;
                if (plan.action == ShadowCacheAction::Render) ++renders;
                CHECK_MESSAGE(plan.action != ShadowCacheAction::Render,
                              "cascade " << i << " reason " << std::string(shadow_cache_reason_name(plan.reason)));
                if (plan.action == ShadowCacheAction::Scroll) {
                    ++scrolls;
                    // the plan's certified offset is the fit's anchor change
                    CHECK(plan.offset_x == int(a[i].texel_anchor.x - b[i].texel_anchor.x));
                    CHECK(plan.offset_y == int(a[i].texel_anchor.y - b[i].texel_anchor.y));
                }
                if (k < 8 && i == j) {
                    // the map follows the camera by the whole texels it moved: a world point lands n
                    // texels back; the float camera can put the snap one texel off when the sphere's
                    // center sits within round-off of a texel edge (counted, rare)
                    const bool hit = plan.action == ShadowCacheAction::Scroll && plan.offset_x == -n && plan.offset_y == 0;
                    exact += hit ? 1 : 0;
                    near_exact += plan.action == ShadowCacheAction::Scroll && std::abs(plan.offset_x + n) <= 1 &&
                                  std::abs(plan.offset_y) <= 1;
                }
            }
            if (k < 8) {  // control: the same move with the default depth range (the slice's sphere)
                in.stable_world_depth = false;
                Cascade a0[4], b0[4];
                REQUIRE(fit(pos, fwd, a0).status == Status::Ok);
                REQUIRE(fit(p, f, b0).status == Status::Ok);
                in.stable_world_depth = true;
                ShadowCacheRect rects[4];
                const ShadowCachePlan p0 = shadow_cache_plan(cascade_state(a0[j], S), cascade_state(b0[j], S), nullptr, 0, rects, 4);
                if (p0.action == ShadowCacheAction::Render) ++default_renders;
            }
        }
    }
    MESSAGE("stable_world_depth cascades: " << plans << " plans, " << renders << " full renders, " << scrolls << " scrolls; "
                                            << whole_moves << " whole-texel moves: " << exact << " scrolled by exactly -n, "
                                            << near_exact << " within one texel; the default depth range rendered "
                                            << default_renders);
    CHECK(renders == 0);
    CHECK(near_exact == whole_moves);
    CHECK(exact >= whole_moves * 98 / 100);
    CHECK(default_renders > whole_moves * 3 / 4);  // what the option is for
}

TEST_CASE("cascades: stable_world_depth needs scene bounds; bad scene bounds are rejected") {
    CascadeInput in = base_input();
    Cascade c[4];
    in.stable_world_depth = true;
    CHECK(cascade_fit(in, 0.7f, 4, c, 4).status == Status::InvalidArgument);  // no scene bounds
    in.has_scene_bounds = true;
    in.scene_min = glm::vec3(-50.0f, -1.0f, -50.0f);
    in.scene_max = glm::vec3(50.0f, 5.0f, 50.0f);
    CHECK(cascade_fit(in, 0.7f, 4, c, 4).status == Status::Ok);
    in.scene_min.x = 60.0f;  // min > max
    CHECK(cascade_fit(in, 0.7f, 4, c, 4).status == Status::InvalidArgument);
    in.scene_min.x = std::numeric_limits<float>::quiet_NaN();
    CHECK(cascade_fit(in, 0.7f, 4, c, 4).status == Status::NonFinite);
    // without the option the scene bounds change nothing (the default range, bit for bit)
    in.scene_min.x = -50.0f;
    in.stable_world_depth = false;
    Cascade with[4], without[4];
    REQUIRE(cascade_fit(in, 0.7f, 4, with, 4).status == Status::Ok);
    in.has_scene_bounds = false;
    REQUIRE(cascade_fit(in, 0.7f, 4, without, 4).status == Status::Ok);
    for (int i = 0; i < 4; ++i)
        for (int col = 0; col < 4; ++col)
            for (int row = 0; row < 4; ++row) CHECK(with[i].view_proj[col][row] == without[i].view_proj[col][row]);
}
