// Unit and property tests for shadowkit/cascades.hpp.
// References: closed-form split schemes, closed-form frustum corners, brute-force selection.
#include <shadowkit/cascades.hpp>

#include <doctest/doctest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <initializer_list>
#include <limits>
#include <random>

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

}  // namespace

TEST_CASE("cascades: split distances match the closed form, monotonic, exact ends") {
    float s[9];
    REQUIRE(cascade_split_distances(0.5f, 200.0f, 0.0f, 4, s) == CascadeStatus::Ok);
    for (int i = 0; i <= 4; ++i) CHECK(s[i] == doctest::Approx(0.5 + 199.5 * i / 4.0));
    REQUIRE(cascade_split_distances(0.5f, 200.0f, 1.0f, 4, s) == CascadeStatus::Ok);
    for (int i = 0; i <= 4; ++i) CHECK(s[i] == doctest::Approx(0.5 * std::pow(400.0, i / 4.0)));
    REQUIRE(cascade_split_distances(1.0f, 100.0f, 0.5f, 2, s) == CascadeStatus::Ok);
    CHECK(s[1] == doctest::Approx(0.5 * 10.0 + 0.5 * 50.5));
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int it = 0; it < 5000; ++it) {
        const float n = std::pow(10.0f, -5.0f + 6.0f * u(rng));
        const float f = n * std::pow(10.0f, 7.0f * u(rng)) + n * 1e-3f;
        const std::uint32_t c = 1 + rng() % 8;
        const float l = u(rng);
        if (!(f > n)) continue;
        REQUIRE(cascade_split_distances(n, f, l, c, s) == CascadeStatus::Ok);
        CHECK(s[0] == n);
        CHECK(s[c] == f);
        for (std::uint32_t i = 0; i < c; ++i) CHECK(s[i] < s[i + 1]);
    }
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    CHECK(cascade_split_distances(0.0f, 10.0f, 0.5f, 4, s) == CascadeStatus::InvalidInput);
    CHECK(cascade_split_distances(1.0f, 1.0f, 0.5f, 4, s) == CascadeStatus::InvalidInput);
    CHECK(cascade_split_distances(1.0f, inf, 0.5f, 4, s) == CascadeStatus::InfiniteFar);
    CHECK(cascade_split_distances(nan, 10.0f, 0.5f, 4, s) == CascadeStatus::InvalidInput);
    CHECK(cascade_split_distances(1.0f, 10.0f, 1.5f, 4, s) == CascadeStatus::InvalidInput);
    CHECK(cascade_split_distances(1.0f, 10.0f, 0.5f, 0, s) == CascadeStatus::InvalidInput);
    CHECK(cascade_split_distances(1.0f, 10.0f, 0.5f, 17, s) == CascadeStatus::InvalidInput);
    CHECK(cascade_split_distances(1.0f, 10.0f, 0.5f, 4, nullptr) == CascadeStatus::InvalidInput);
}

TEST_CASE("cascades: every point of each slice is inside its cascade (random cameras and lights)") {
    std::mt19937 rng(77);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    int pts = 0;
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
        in.light_dir = rdir(rng);
        in.shadow_map_size = 512u << (rng() % 4);
        in.light_depth = (rng() & 1) ? ClipDepth::ZeroToOne : ClipDepth::NegativeOneToOne;
        in.light_reversed_z = rng() % 3 == 0;
        in.has_caster_bounds = rng() % 2 == 0;
        in.caster_min = pos - glm::vec3(200);
        in.caster_max = pos + glm::vec3(200);
        Cascade c[4];
        float s[5];
        const std::uint32_t count = 1 + rng() % 4;
        REQUIRE(fit_cascades(in, u(rng), count, c, s) == CascadeStatus::Ok);
        const glm::mat4 iv = glm::inverse(in.camera_view);
        const double ty = std::tan(0.5 * double(fovy)), tx = ty * aspect;
        for (std::uint32_t i = 0; i < count; ++i) {
            for (int k = 0; k < 30; ++k) {
                const double dep = s[i] + (s[i + 1] - s[i]) * double(u(rng));
                const glm::dvec3 pv((2 * double(u(rng)) - 1) * tx * dep, (2 * double(u(rng)) - 1) * ty * dep, -dep);
                const glm::dvec3 p = glm::dvec3(glm::dmat4(iv) * glm::dvec4(pv, 1.0));
                ++pts;
                if (!in_clip(c[i].view_proj, p, in.light_depth, 1e-4)) {
                    FAIL_CHECK("slice point outside its cascade, it=" << it << " cascade " << i);
                    break;
                }
                // casters towards the light inside the caster bounds are inside too
                if (in.has_caster_bounds) {
                    const glm::dvec3 q = p - glm::dvec3(in.light_dir) * (50.0 * double(u(rng)));
                    const glm::dvec3 d = glm::abs(q - glm::dvec3(pos));
                    if (d.x < 200 && d.y < 200 && d.z < 200) CHECK(in_clip(c[i].view_proj, q, in.light_depth, 1e-4));
                }
                // selection by depth agrees with a linear scan
                const int sel = select_cascade_by_depth(float(dep), s, count);
                CHECK((sel >= 0 && s[sel] <= float(dep) && float(dep) <= s[sel + 1]));
            }
        }
    }
    MESSAGE("cascade slice points checked: " << pts);
}

TEST_CASE("cascades: stable fits are rotation invariant and move by whole texels (anchor: no swimming)") {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int it = 0; it < 200; ++it) {
        CascadeInput in;
        in.camera_proj = glm::perspective(0.6f + u(rng), 0.8f + u(rng), 0.1f + u(rng), 50.0f + 200.0f * u(rng));
        in.light_dir = rdir(rng);
        in.shadow_map_size = 2048;
        const glm::vec3 pos = glm::vec3(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f) * 50.0f;
        in.camera_view = look(pos, rdir(rng));
        Cascade a[4], b[4];
        REQUIRE(fit_cascades(in, 0.7f, 4, a, nullptr) == CascadeStatus::Ok);
        in.camera_view = look(pos, rdir(rng));  // rotate about the position
        REQUIRE(fit_cascades(in, 0.7f, 4, b, nullptr) == CascadeStatus::Ok);
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
        REQUIRE(fit_cascades(in, 0.7f, 4, a, nullptr) == CascadeStatus::Ok);
        const glm::vec3 p2 = pos + rdir(rng) * (0.4f * a[0].texel_world_size);
        in.camera_view = look(p2, f2);
        REQUIRE(fit_cascades(in, 0.7f, 4, b, nullptr) == CascadeStatus::Ok);
        for (int i = 0; i < 4; ++i) {
            CHECK(a[i].texel_world_size == b[i].texel_world_size);
            const glm::dvec2 dt = origin_texel(b[i].view_proj, 2048) - origin_texel(a[i].view_proj, 2048);
            CHECK(std::fabs(dt.x - std::round(dt.x)) < 1e-3);
            CHECK(std::fabs(dt.y - std::round(dt.y)) < 1e-3);
        }
    }
}

TEST_CASE("cascades: selection by sphere and the blend band") {
    CascadeInput in;
    in.camera_view = glm::lookAt(glm::vec3(0, 2, 0), glm::vec3(0, 2, -1), glm::vec3(0, 1, 0));
    in.camera_proj = glm::perspective(1.0f, 1.5f, 0.1f, 100.0f);
    in.light_dir = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));
    Cascade c[4];
    float s[5];
    REQUIRE(fit_cascades(in, 0.8f, 4, c, s) == CascadeStatus::Ok);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int k = 0; k < 2000; ++k) {
        const glm::vec3 p(u(rng) * 200 - 100, u(rng) * 50 - 25, -u(rng) * 120);
        int expect = -1;
        for (int i = 0; i < 4 && expect < 0; ++i)
            if (glm::length(glm::dvec3(p) - glm::dvec3(glm::vec3(c[i].sphere))) <= double(c[i].sphere.w) * (1 - 1e-6)) expect = i;
        const int got = select_cascade_by_sphere(p, c, 4);
        if (expect >= 0) CHECK(got == expect);
        if (got >= 0) CHECK(in_clip(c[got].view_proj, glm::dvec3(p), in.light_depth, 1e-4));
    }
    CHECK(select_cascade_by_sphere(glm::vec3(std::numeric_limits<float>::quiet_NaN()), c, 4) == -1);
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
    CHECK(select_cascade_by_depth(s[0], s, 4) == 0);
    CHECK(select_cascade_by_depth(s[4], s, 4) == 3);
    CHECK(select_cascade_by_depth(s[4] * 1.01f, s, 4) == -1);
    CHECK(select_cascade_by_depth(0.5f * s[0], s, 4) == -1);
    CHECK(select_cascade_by_depth(std::numeric_limits<float>::quiet_NaN(), s, 4) == -1);
}

TEST_CASE("cascades: stiff cases") {
    CascadeInput in;
    in.camera_view = glm::lookAt(glm::vec3(0, 2, 0), glm::vec3(0, 2, -1), glm::vec3(0, 1, 0));
    Cascade c[4];
    float s[5];
    SUBCASE("near 1e-5 with an infinite far plane needs max_distance") {
        in.camera_proj = glm::infinitePerspective(1.0f, 1.0f, 1e-5f);
        CHECK(fit_cascades(in, 0.9f, 4, c, s) == CascadeStatus::InfiniteFar);
        in.max_distance = 10.0f;  // ratio 1e-6
        REQUIRE(fit_cascades(in, 0.9f, 4, c, s) == CascadeStatus::Ok);
        CHECK(s[0] == doctest::Approx(1e-5f));
        CHECK(s[4] == 10.0f);
        CHECK(in_clip(c[0].view_proj, glm::dvec3(0, 2, -2e-5), in.light_depth, 1e-4));
    }
    SUBCASE("light parallel and anti-parallel to the view, straight down on a camera looking down") {
        in.camera_proj = glm::perspective(1.0f, 1.0f, 0.1f, 50.0f);
        for (const glm::vec3 l : {glm::vec3(0, 0, -1), glm::vec3(0, 0, 1)}) {
            in.light_dir = l;
            REQUIRE(fit_cascades(in, 0.5f, 3, c, s) == CascadeStatus::Ok);
            CHECK(in_clip(c[2].view_proj, glm::dvec3(0, 2, -40), in.light_depth, 1e-4));
        }
        in.camera_view = glm::lookAt(glm::vec3(0, 10, 0), glm::vec3(0, 0, 0), glm::vec3(0, 0, -1));
        in.light_dir = glm::vec3(0, -1, 0);
        REQUIRE(fit_cascades(in, 0.5f, 3, c, s) == CascadeStatus::Ok);
        CHECK(in_clip(c[0].view_proj, glm::dvec3(0, 9.8, 0), in.light_depth, 1e-4));
    }
    SUBCASE("coordinates at 1e6") {
        in.camera_proj = glm::perspective(1.0f, 1.0f, 0.5f, 100.0f);
        const glm::vec3 o(1e6f, 1e6f, 1e6f);
        in.camera_view = glm::lookAt(o, o + glm::vec3(1, 0, 0), glm::vec3(0, 1, 0));
        REQUIRE(fit_cascades(in, 0.5f, 4, c, s) == CascadeStatus::Ok);
        CHECK(in_clip(c[3].view_proj, glm::dvec3(o) + glm::dvec3(90, 0, 0), in.light_depth, 1e-3));
    }
    SUBCASE("NaN / degenerate input") {
        in.camera_proj = glm::perspective(1.0f, 1.0f, 0.5f, 100.0f);
        in.light_dir = glm::vec3(0.0f);
        CHECK(fit_cascades(in, 0.5f, 4, c, s) == CascadeStatus::InvalidInput);
        in.light_dir = glm::vec3(std::numeric_limits<float>::quiet_NaN(), -1, 0);
        CHECK(fit_cascades(in, 0.5f, 4, c, s) == CascadeStatus::InvalidInput);
        in.light_dir = glm::vec3(0, -1, 0);
        in.camera_proj = glm::mat4(0.0f);
        CHECK(fit_cascades(in, 0.5f, 4, c, s) == CascadeStatus::InvalidInput);
        in.camera_proj = glm::perspective(1.0f, 1.0f, 0.5f, 100.0f);
        in.shadow_map_size = 2;
        CHECK(fit_cascades(in, 0.5f, 4, c, s) == CascadeStatus::InvalidInput);
        in.shadow_map_size = 1024;
        Cascade one;
        CHECK(fit_cascade(in, 5.0f, 5.0f, one) == CascadeStatus::InvalidInput);  // zero-size slice
        CHECK(fit_cascade(in, 5.0f, 5.001f, one) == CascadeStatus::Ok);
    }
}
