// Unit and property tests for include/shadowkit/pcss.hpp.
#include <shadowkit/pcss.hpp>

#include <doctest/doctest.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

using namespace shadowkit;

namespace {

// Brute-force visibility of a square light (side w, centred at the origin in the plane z = 0,
// facing +z, sampled on an M x M grid including its edges) from receiver point (x, 0, z_r) past a
// square occluder (side s, centred on the axis) at depth z_b.
double visibility(double x, double w, double s, double z_b, double z_r, int m = 32) {
    const double a = z_b / z_r;
    int visible = 0;
    for (int i = 0; i < m; ++i)
        for (int j = 0; j < m; ++j) {
            const double lx = -0.5 * w + w * i / (m - 1), ly = -0.5 * w + w * j / (m - 1);
            const double X = lx + (x - lx) * a, Y = ly + (0.0 - ly) * a;
            visible += !(std::fabs(X) <= 0.5 * s && std::fabs(Y) <= 0.5 * s);
        }
    return double(visible) / double(m * m);
}

// Smallest x in [lo, hi] where pred(x) holds, pred monotone (false then true).
template <class F>
double first_true(double lo, double hi, F pred) {
    for (int k = 0; k < 60; ++k) {
        const double mid = 0.5 * (lo + hi);
        (pred(mid) ? hi : lo) = mid;
    }
    return hi;
}

PcssLight spot(float size, float n, float f, float fov) {
    PcssLight L;
    L.type = PcssLightType::Perspective;
    L.size = size;
    L.near = n;
    L.far = f;
    L.frustum_width = 2.0f * std::tan(0.5f * fov);
    return L;
}

// uv of a point seen by a light at the origin looking down +z (glm conventions: RH, looks at -z
// in view space), projection glm::perspective.
glm::dvec2 light_uv(glm::dvec3 p, double fov, double n, double f) {
    const glm::dmat4 view = glm::lookAtRH(glm::dvec3(0.0), glm::dvec3(0, 0, 1), glm::dvec3(0, 1, 0));
    const glm::dmat4 proj = glm::perspectiveRH_NO(fov, 1.0, n, f);
    const glm::dvec4 c = proj * view * glm::dvec4(p, 1.0);
    return glm::dvec2(c.x / c.w * 0.5 + 0.5, c.y / c.w * 0.5 + 0.5);
}

}  // namespace

TEST_CASE("penumbra width equals the brute-force penumbra of a square occluder under a square light") {
    std::mt19937 g(11);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    for (int it = 0; it < 300; ++it) {
        const double w = 0.05 + 2.0 * u01(g);
        const double z_r = 1.0 + 20.0 * u01(g);
        const double z_b = z_r * (0.05 + 0.9 * u01(g));
        const double s = 4.0 * w + 10.0;  // large occluder: edges are far apart
        // Inner edge: first x with any light visible; outer edge: first x with all of it visible.
        const double hi = 0.5 * s * z_r / z_b + 2.0 * w * z_r / z_b;
        const double x_in = first_true(0.0, hi, [&](double x) { return visibility(x, w, s, z_b, z_r) > 0.0; });
        const double x_out = first_true(0.0, hi, [&](double x) { return visibility(x, w, s, z_b, z_r) >= 1.0; });
        const double brute = x_out - x_in;
        const double formula = pcss_penumbra_width(float(w), float(z_r), float(z_b));
        INFO("w " << w << " z_r " << z_r << " z_b " << z_b);
        CHECK(formula == doctest::Approx(brute).epsilon(1e-4));
        // The same penumbra, projected into the light's shadow map, is the PCF filter width in uv.
        const double fov = 0.8;
        const PcssLight L = spot(float(w), 0.5f, 100.0f, float(fov));
        PcssBlocker b;
        b.found = true;
        b.average = float(z_b);
        PcssPolicy pol;
        pol.max_filter_uv = 1e9f;
        const PcssFilter f = pcss_filter(L, float(z_r), b, pol);
        REQUIRE(f.status == PcssStatus::Ok);
        const double uv_in = light_uv({x_in, 0.0, z_r}, fov, 0.5, 100.0).x;
        const double uv_out = light_uv({x_out, 0.0, z_r}, fov, 0.5, 100.0).x;
        CHECK(double(f.filter_uv) == doctest::Approx(std::fabs(uv_out - uv_in)).epsilon(1e-4));
        // The thesis's shader used the penumbra width itself: z_r / z_n times too wide.
        CHECK(double(perspective_width_to_uv(f.penumbra_width, 0.5f, L.frustum_width)) ==
              doctest::Approx(double(f.filter_uv) * z_r / 0.5).epsilon(1e-4));
    }
}

TEST_CASE("directional light: penumbra width equals the brute-force penumbra for an angular source") {
    std::mt19937 g(12);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    for (int it = 0; it < 300; ++it) {
        const double theta = 0.001 + 0.2 * u01(g);
        const double t = std::tan(0.5 * theta);
        const double z_r = 1.0 + 50.0 * u01(g), z_b = z_r * u01(g);
        // Occluder half-plane x < 0 at depth z_b; light directions (sx, 1) with |sx| <= t, 257 samples.
        auto vis = [&](double x) {
            int v = 0;
            for (int i = 0; i <= 256; ++i) {
                const double sx = -t + 2.0 * t * i / 256.0;
                v += (x - sx * (z_r - z_b)) >= 0.0;
            }
            return double(v) / 257.0;
        };
        const double span = 4.0 * t * z_r + 1.0;
        const double x_in = first_true(-span, span, [&](double x) { return vis(x) > 0.0; });
        const double x_out = first_true(-span, span, [&](double x) { return vis(x) >= 1.0; });
        CHECK(double(pcss_penumbra_width_directional(float(theta), float(z_r), float(z_b))) ==
              doctest::Approx(x_out - x_in).epsilon(1e-4));
    }
    PcssLight sun;
    sun.type = PcssLightType::Directional;
    sun.size = 0.0093f;
    sun.near = 0.0f;
    sun.far = 200.0f;
    sun.frustum_width = 50.0f;
    PcssBlocker b;
    b.found = true;
    b.average = 40.0f;
    PcssPolicy pol;
    pol.max_filter_uv = 1.0f;
    const PcssFilter f = pcss_filter(sun, 60.0f, b, pol);
    REQUIRE(f.status == PcssStatus::Ok);
    CHECK(double(f.filter_uv) == doctest::Approx(2.0 * std::tan(0.00465) * 20.0 / 50.0).epsilon(1e-5));
    CHECK(double(pcss_search_uv(sun, 60.0f)) == doctest::Approx(2.0 * std::tan(0.00465) * 60.0 / 50.0).epsilon(1e-5));
    // GLSL uniform: uv per unit window depth.
    CHECK(double(pcss_light_uv_at_near(sun)) == doctest::Approx(2.0 * std::tan(0.00465) * 200.0 / 50.0).epsilon(1e-5));
}

TEST_CASE("blocker search region contains the projection of every point of the receiver-light pyramid") {
    std::mt19937 g(13);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    for (int it = 0; it < 2000; ++it) {
        const double fov = 0.4 + 1.2 * u01(g), n = 0.05 + u01(g), f = n * 1000.0;
        const double w = 0.01 + u01(g);
        const glm::dvec3 p((u01(g) - 0.5) * 2.0, (u01(g) - 0.5) * 2.0, n + 30.0 * u01(g));
        const PcssLight L = spot(float(w), float(n), float(f), float(fov));
        const double search = pcss_search_uv(L, float(p.z));
        // Corners of the pyramid's cut by the near plane project to exactly the search square.
        auto cut = [&](double lx) { return glm::dvec3(lx, 0.0, 0.0) + (p - glm::dvec3(lx, 0.0, 0.0)) * (n / p.z); };
        const double u_lo = light_uv(cut(-0.5 * w), fov, n, f).x, u_hi = light_uv(cut(0.5 * w), fov, n, f).x;
        CHECK(search == doctest::Approx(std::fabs(u_hi - u_lo)).epsilon(1e-4));  // lookAt mirrors x
        // A random point of the pyramid between the near plane and the receiver.
        const glm::dvec3 l((u01(g) - 0.5) * w, (u01(g) - 0.5) * w, 0.0);
        const double tt = n / p.z + (1.0 - n / p.z) * u01(g);
        const glm::dvec3 q = l + (p - l) * tt;
        const glm::dvec2 dq = light_uv(q, fov, n, f) - light_uv(p, fov, n, f);
        CHECK(std::fabs(dq.x) <= 0.5 * search * (1.0 + 1e-5) + 1e-7);
        CHECK(std::fabs(dq.y) <= 0.5 * search * (1.0 + 1e-5) + 1e-7);
    }
}

TEST_CASE("linearization round trip against glm::perspective (NO, ZO, reversed, infinite far)") {
    std::mt19937 g(14);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    for (int it = 0; it < 6000; ++it) {
        const int mode = it % 4;  // 0 NO, 1 ZO, 2 ZO reversed, 3 NO infinite
        const double n = std::pow(10.0, -2.0 + 2.0 * u01(g));
        const double f = mode == 3 ? INFINITY : n * std::pow(10.0, 1.0 + 3.0 * u01(g));
        const double d = mode == 3 ? n * std::pow(10.0, 3.0 * u01(g)) : n * std::pow(f / n, u01(g));
        glm::dmat4 P;
        if (mode == 0) P = glm::perspectiveRH_NO(1.0, 1.0, n, f);
        if (mode == 1) P = glm::perspectiveRH_ZO(1.0, 1.0, n, f);
        if (mode == 2) {
            glm::dmat4 flip(1.0);
            flip[2][2] = -1.0;  // z' = w - z
            flip[3][2] = 1.0;
            P = flip * glm::perspectiveRH_ZO(1.0, 1.0, n, f);
        }
        if (mode == 3) P = glm::infinitePerspectiveRH(1.0, 1.0, n);
        const glm::dvec4 c = P * glm::dvec4(0.1, -0.2, -d, 1.0);
        const float ndc = float(c.z / c.w);
        const ClipDepth cd = (mode == 0 || mode == 3) ? ClipDepth::NegativeOneToOne : ClipDepth::ZeroToOne;
        const bool rev = mode == 2;
        const float lin = linearize_ndc_depth(ndc, float(n), float(f), cd, rev);
        // Tolerance: one float ulp of ndc mapped through |d d / d ndc| (computed from the float
        // value's neighbours with the exact inverse in double), plus float rounding of the result.
        auto inv = [&](double z) {
            if (mode == 0) return 2.0 * f * n / ((f + n) - z * (f - n));
            if (mode == 3) return 2.0 * n / (1.0 - z);
            if (mode == 1) return f * n / (f - z * (f - n));
            return f * n / (n + z * (f - n));
        };
        const double e = std::fabs(inv(std::nextafter(ndc, 2.0f)) - inv(double(ndc))) +
                         std::fabs(inv(double(ndc)) - inv(std::nextafter(ndc, -2.0f)));
        INFO("mode " << mode << " n " << n << " f " << f << " d " << d);
        if (!std::isfinite(e)) continue;
        CHECK(std::fabs(double(lin) - d) <= 1.01 * e + 4e-7 * d);
        // Window depth path and the inverse.
        const float zw = cd == ClipDepth::NegativeOneToOne ? 0.5f * ndc + 0.5f : ndc;
        const float lin_w = linearize_window_depth(zw, float(n), float(f), rev);
        CHECK(std::fabs(double(lin_w) - d) <= 4.0 * e + 1e-6 * d);
        const float back = delinearize_window_depth(lin_w, float(n), float(f), rev);
        CHECK(std::fabs(double(back) - double(zw)) <= 4e-7);
    }
    // Ends of the range.
    CHECK(linearize_window_depth(0.0f, 0.1f, 50.0f, false) == doctest::Approx(0.1));
    CHECK(linearize_window_depth(1.0f, 0.1f, 50.0f, false) == doctest::Approx(50.0));
    CHECK(linearize_window_depth(1.0f, 0.1f, 50.0f, true) == doctest::Approx(0.1));
    CHECK(std::isinf(linearize_window_depth(1.0f, 0.1f, INFINITY, false)));
    CHECK(std::isinf(linearize_window_depth(0.0f, 0.1f, INFINITY, true)));
    CHECK(linearize_window_depth(-5.0f, 0.1f, 50.0f, false) == doctest::Approx(0.1));  // clamped
    CHECK(std::isnan(linearize_window_depth(NAN, 0.1f, 50.0f, false)));
    CHECK(linearize_ortho_window_depth(0.25f, 2.0f, 10.0f, false) == doctest::Approx(4.0));
    CHECK(linearize_ortho_window_depth(0.25f, 2.0f, 10.0f, true) == doctest::Approx(8.0));
}

TEST_CASE("the penumbra ratio must use linear depth (three.js / pboechat bug)") {
    const float n = 0.1f, f = 100.0f, w = 1.0f;
    const float zr = delinearize_window_depth(20.0f, n, f, false), zb = delinearize_window_depth(10.0f, n, f, false);
    const float right = pcss_penumbra_width_from_window_depth(w, zr, zb, n, f, false);
    CHECK(double(right) == doctest::Approx(1.0).epsilon(1e-3));  // (20 - 10) / 10
    const double naive = double(w) * (double(zr) - double(zb)) / double(zb);
    CHECK(naive < 0.01);  // the naive ratio on window depths is ~200 times too small
    // Reversed-Z too.
    const float zr2 = delinearize_window_depth(20.0f, n, f, true), zb2 = delinearize_window_depth(10.0f, n, f, true);
    CHECK(double(pcss_penumbra_width_from_window_depth(w, zr2, zb2, n, f, true)) == doctest::Approx(1.0).epsilon(1e-3));
}

TEST_CASE("average blocker: only samples closer than the receiver, invalid samples ignored") {
    const float d[] = {2.0f, 4.0f, 9.0f, 10.0f, 11.0f, NAN, INFINITY, -1.0f, 0.0f};
    PcssBlocker b = pcss_average_blocker(d, 9, 10.0f, 0.5f);
    CHECK(b.found);
    CHECK(b.count == 3);
    CHECK(b.average == doctest::Approx(5.0));
    b = pcss_average_blocker(d, 9, 10.0f, 8.5f);
    CHECK(b.count == 0);
    CHECK_FALSE(b.found);
    b = pcss_average_blocker(d, 0, 10.0f, 0.0f);
    CHECK_FALSE(b.found);
    b = pcss_average_blocker(nullptr, 9, 10.0f, 0.0f);
    CHECK_FALSE(b.found);
    b = pcss_average_blocker(d, 9, NAN, 0.0f);
    CHECK_FALSE(b.found);
    // All taps outside the map (cleared to far / invalid): no blocker, fully lit.
    const float outside[] = {INFINITY, NAN, 100.0f};
    CHECK_FALSE(pcss_average_blocker(outside, 3, 50.0f, 0.0f).found);
    // Property: the average lies between the min and max of the blocking samples.
    std::mt19937 g(15);
    std::uniform_real_distribution<float> u(0.0f, 20.0f);
    for (int it = 0; it < 2000; ++it) {
        std::vector<float> s(1 + std::size_t(it % 64));
        for (float& x : s) x = u(g);
        const float zr = u(g);
        const PcssBlocker r = pcss_average_blocker(s.data(), s.size(), zr, 0.0f);
        float lo = INFINITY, hi = -INFINITY;
        std::size_t cnt = 0;
        for (float x : s)
            if (x > 0.0f && x < zr) {
                lo = std::min(lo, x);
                hi = std::max(hi, x);
                ++cnt;
            }
        CHECK(r.count == cnt);
        if (cnt > 0) {
            CHECK(r.average >= lo * (1 - 1e-6f));
            CHECK(r.average <= hi * (1 + 1e-6f));
        }
    }
}

TEST_CASE("stiff cases: zero-size light, blocker at receiver, receiver at near plane, blocker depth -> 0, NaN") {
    PcssBlocker b;
    b.found = true;
    b.average = 5.0f;
    PcssPolicy pol;
    // Zero-size light: exactly a hard shadow (filter 0, minimum taps).
    PcssFilter f = pcss_filter(spot(0.0f, 0.1f, 100.0f, 1.0f), 10.0f, b, pol);
    CHECK(f.status == PcssStatus::Ok);
    CHECK(f.filter_uv == 0.0f);
    CHECK(f.penumbra_width == 0.0f);
    CHECK(f.search_uv == 0.0f);
    CHECK(f.taps == pol.min_taps);
    // Blocker at the receiver: contact, zero penumbra.
    b.average = 10.0f;
    f = pcss_filter(spot(1.0f, 0.1f, 100.0f, 1.0f), 10.0f, b, pol);
    CHECK(f.penumbra_width == 0.0f);
    CHECK(f.filter_uv == 0.0f);
    // Receiver at the near plane: no room for blockers, search width 0.
    CHECK(pcss_search_uv(spot(1.0f, 0.1f, 100.0f, 1.0f), 0.1f) == 0.0f);
    CHECK(pcss_search_width(1.0f, 0.05f, 0.1f) == 0.0f);
    // Blocker depth tending to 0: penumbra -> Inf, filter clamped, finite.
    for (float zb : {1e-3f, 1e-10f, 1e-30f, 1e-45f, 0.0f, -1.0f}) {
        b.average = zb;
        f = pcss_filter(spot(1.0f, 0.1f, 100.0f, 1.0f), 10.0f, b, pol);
        CHECK(f.status == PcssStatus::Ok);
        CHECK(std::isfinite(f.filter_uv));
        CHECK(f.filter_uv <= pol.max_filter_uv);
        CHECK(f.taps >= pol.min_taps);
        CHECK(f.taps <= pol.max_taps);
    }
    b.average = 0.0f;
    CHECK(pcss_filter(spot(1.0f, 0.1f, 100.0f, 1.0f), 10.0f, b, pol).filter_uv == pol.max_filter_uv);
    // Very large light: clamped.
    b.average = 5.0f;
    f = pcss_filter(spot(1e30f, 0.1f, 100.0f, 1.0f), 10.0f, b, pol);
    CHECK(f.filter_uv == pol.max_filter_uv);
    CHECK(f.taps == pol.max_taps);
    // No blocker: fully lit, no filter work.
    PcssBlocker none;
    f = pcss_filter(spot(1.0f, 0.1f, 100.0f, 1.0f), 10.0f, none, pol);
    CHECK(f.status == PcssStatus::NoBlocker);
    CHECK(f.taps == 0);
    // NaN / invalid input.
    CHECK(pcss_filter(spot(1.0f, 0.1f, 100.0f, 1.0f), NAN, b, pol).status == PcssStatus::InvalidArgument);
    CHECK(pcss_filter(spot(NAN, 0.1f, 100.0f, 1.0f), 10.0f, b, pol).status == PcssStatus::InvalidArgument);
    CHECK(pcss_filter(spot(-1.0f, 0.1f, 100.0f, 1.0f), 10.0f, b, pol).status == PcssStatus::InvalidArgument);
    CHECK(pcss_filter(spot(1.0f, 0.0f, 100.0f, 1.0f), 10.0f, b, pol).status == PcssStatus::InvalidArgument);
    CHECK(pcss_filter(spot(1.0f, 1.0f, 0.5f, 1.0f), 10.0f, b, pol).status == PcssStatus::InvalidArgument);
    CHECK(pcss_filter(spot(1.0f, 0.1f, INFINITY, 1.0f), 10.0f, b, pol).status == PcssStatus::Ok);
    for (float bad : {NAN, INFINITY, -INFINITY}) {
        b.average = bad;
        CHECK(pcss_filter(spot(1.0f, 0.1f, 100.0f, 1.0f), 10.0f, b, pol).status == PcssStatus::InvalidArgument);
    }
    CHECK(pcss_penumbra_width_directional(0.0f, 10.0f, -INFINITY) == 0.0f);  // zero-size sun: hard
    PcssPolicy bad;
    bad.max_filter_uv = NAN;
    b.average = 5.0f;
    CHECK(pcss_filter(spot(1.0f, 0.1f, 100.0f, 1.0f), 10.0f, b, bad).status == PcssStatus::InvalidArgument);
    CHECK(std::isnan(pcss_penumbra_width(1.0f, NAN, 1.0f)));
    CHECK(std::isnan(pcss_search_width(1.0f, NAN, 1.0f)));
    CHECK(std::isnan(pcss_light_uv_at_near(spot(1.0f, -1.0f, 100.0f, 1.0f))));
    CHECK(double(pcss_light_uv_at_near(spot(1.0f, 0.5f, 100.0f, 1.0f))) == doctest::Approx(1.0 / (0.5 * 2.0 * std::tan(0.5))));
}

TEST_CASE("filter clamp and tap budget policy") {
    CHECK(pcss_clamp_filter(NAN, 0.001f, 0.05f) == 0.001f);
    CHECK(pcss_clamp_filter(INFINITY, 0.001f, 0.05f) == 0.05f);
    CHECK(pcss_clamp_filter(-INFINITY, 0.001f, 0.05f) == 0.001f);
    CHECK(pcss_clamp_filter(0.01f, 0.001f, 0.05f) == 0.01f);
    // ceil(pi (D/2)^2) taps for D texels.
    CHECK(pcss_tap_budget(4.0f, 1, 64) == 13);
    CHECK(pcss_tap_budget(10.0f, 1, 64) == 64);
    CHECK(pcss_tap_budget(10.0f, 1, 1000) == 79);
    CHECK(pcss_tap_budget(10.0f, 1, 1000, 2.0f) == 20);
    CHECK(pcss_tap_budget(0.5f, 4, 64) == 4);
    CHECK(pcss_tap_budget(NAN, 4, 64) == 4);
    CHECK(pcss_tap_budget(INFINITY, 4, 64) == 64);
    CHECK(pcss_tap_budget(-3.0f, 4, 64) == 4);
    CHECK(pcss_tap_budget(1e30f, 4, 64) == 64);
    CHECK(pcss_tap_budget(5.0f, 0, -3) == 1);
    CHECK(pcss_tap_budget(5.0f, 16, 8) == 16);
    CHECK(pcss_tap_budget(5.0f, 1, 64, NAN) == 20);
    int prev = 0;
    for (int i = 0; i < 4000; ++i) {
        const float D = 0.01f * float(i);
        const int t = pcss_tap_budget(D, 4, 64);
        CHECK(t >= prev);
        CHECK(t >= 4);
        CHECK(t <= 64);
        prev = t;
    }
}
