// Unit and property tests for include/shadowkit/pcss.hpp.
#include <shadowkit/pcss.hpp>
#include <shadowkit/poisson_disk.hpp>

#include <doctest/doctest.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <utility>
#include <vector>

using namespace shadowkit;

namespace {

// Brute-force visibility of a square light (side w, centered at the origin in the plane z = 0,
// facing +z, sampled on an M x M grid including its edges) from receiver point (x, 0, z_r) past a
// square occluder (side s, centered on the axis) at depth z_b.
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

// The same with the occluder centered at (ox, oy) on its plane and the receiver point at
// (ox, oy) * z_r / z_b + (x, y): the square light (side w, centered at the origin, z = 0) sampled
// M x M from the receiver past the occluder.
double visibility_offset(double x, double y, double w, double s, double z_b, double z_r, double ox, double oy, int m = 24) {
    const double a = z_b / z_r;
    const double px = ox * z_r / z_b + x, py = oy * z_r / z_b + y;
    int visible = 0;
    for (int i = 0; i < m; ++i)
        for (int j = 0; j < m; ++j) {
            const double lx = -0.5 * w + w * i / (m - 1), ly = -0.5 * w + w * j / (m - 1);
            const double X = lx + (px - lx) * a, Y = ly + (py - ly) * a;
            visible += !(std::fabs(X - ox) <= 0.5 * s && std::fabs(Y - oy) <= 0.5 * s);
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
    L.near_z = n;
    L.far_z = f;
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

// The value of an Ok result (the test fails if it is not Ok).
float val(const PcssValue& r) {
    INFO("status " << std::string(status_name(r.status)));
    CHECK(r.status == Status::Ok);
    return r.value;
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
        const double formula = val(pcss_penumbra_width(float(w), float(z_r), float(z_b)));
        INFO("w " << w << " z_r " << z_r << " z_b " << z_b);
        CHECK(formula == doctest::Approx(brute).epsilon(1e-4));
        // The same penumbra, projected into the light's shadow map, is the PCF filter width in uv.
        const double fov = 0.8;
        const PcssLight L = spot(float(w), 0.5f, 100.0f, float(fov));
        PcssBlocker b;
        b.status = Status::Ok;
    b.blocker_found = true;
        b.average = float(z_b);
        PcssPolicy pol;
        pol.map_resolution = 2048.0f;
        pol.max_filter_uv = 1e9f;
        const PcssFilter f = pcss_filter(L, float(z_r), b, pol);
        REQUIRE(f.status == Status::Ok);
        const double uv_in = light_uv({x_in, 0.0, z_r}, fov, 0.5, 100.0).x;
        const double uv_out = light_uv({x_out, 0.0, z_r}, fov, 0.5, 100.0).x;
        CHECK(double(f.filter_uv) == doctest::Approx(std::fabs(uv_out - uv_in)).epsilon(1e-4));
        // The thesis's shader used the penumbra width itself: z_r / z_n times too wide.
        CHECK(double(val(pcss_width_to_uv(f.penumbra_width, 0.5f, L.frustum_width))) ==
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
        CHECK(double(val(pcss_penumbra_width_directional(float(theta), float(z_r), float(z_b)))) ==
              doctest::Approx(x_out - x_in).epsilon(1e-4));
    }
    PcssLight sun;
    sun.type = PcssLightType::Directional;
    sun.size = 0.0093f;
    sun.near_z = 0.0f;
    sun.far_z = 200.0f;
    sun.frustum_width = 50.0f;
    PcssBlocker b;
    b.status = Status::Ok;
    b.blocker_found = true;
    b.average = 40.0f;
    PcssPolicy pol;
    pol.map_resolution = 2048.0f;
    pol.max_filter_uv = 1.0f;
    const PcssFilter f = pcss_filter(sun, 60.0f, b, pol);
    REQUIRE(f.status == Status::Ok);
    CHECK(double(f.filter_uv) == doctest::Approx(2.0 * std::tan(0.00465) * 20.0 / 50.0).epsilon(1e-5));
    CHECK(double(val(pcss_search_uv(sun, 60.0f))) == doctest::Approx(2.0 * std::tan(0.00465) * 60.0 / 50.0).epsilon(1e-5));
    // GLSL uniform: uv per unit window depth.
    CHECK(double(val(pcss_light_uv_at_near(sun))) == doctest::Approx(2.0 * std::tan(0.00465) * 200.0 / 50.0).epsilon(1e-5));
}

TEST_CASE("blocker search region contains the projection of every point of the receiver-light pyramid") {
    std::mt19937 g(13);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    for (int it = 0; it < 2000; ++it) {
        const double fov = 0.4 + 1.2 * u01(g), n = 0.05 + u01(g), f = n * 1000.0;
        const double w = 0.01 + u01(g);
        const glm::dvec3 p((u01(g) - 0.5) * 2.0, (u01(g) - 0.5) * 2.0, n + 30.0 * u01(g));
        const PcssLight L = spot(float(w), float(n), float(f), float(fov));
        const double search = val(pcss_search_uv(L, float(p.z)));
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
        const float lin = val(pcss_linearize_ndc_depth(ndc, float(n), float(f), cd, rev));
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
        const float lin_w = val(pcss_linearize_window_depth(zw, float(n), float(f), rev));
        CHECK(std::fabs(double(lin_w) - d) <= 4.0 * e + 1e-6 * d);
        const float back = val(pcss_delinearize_window_depth(lin_w, float(n), float(f), rev));
        CHECK(std::fabs(double(back) - double(zw)) <= 4e-7);
    }
    // Ends of the range.
    CHECK(val(pcss_linearize_window_depth(0.0f, 0.1f, 50.0f, false)) == doctest::Approx(0.1));
    CHECK(val(pcss_linearize_window_depth(1.0f, 0.1f, 50.0f, false)) == doctest::Approx(50.0));
    CHECK(val(pcss_linearize_window_depth(1.0f, 0.1f, 50.0f, true)) == doctest::Approx(0.1));
    // The window depth of infinity (a cleared texel with an infinite far plane): no finite distance.
    CHECK(pcss_linearize_window_depth(1.0f, 0.1f, INFINITY, false).status == Status::Overflow);
    CHECK(pcss_linearize_window_depth(0.0f, 0.1f, INFINITY, true).status == Status::Overflow);
    CHECK(val(pcss_linearize_window_depth(-5.0f, 0.1f, 50.0f, false)) == doctest::Approx(0.1));  // clamped
    CHECK(pcss_linearize_window_depth(NAN, 0.1f, 50.0f, false).status == Status::NonFinite);
    CHECK(pcss_linearize_window_depth(0.5f, 0.0f, 50.0f, false).status == Status::InvalidArgument);
    CHECK(pcss_linearize_window_depth(0.5f, 1.0f, 0.5f, false).status == Status::InvalidArgument);
    CHECK(pcss_linearize_ndc_depth(0.5f, 0.1f, 50.0f, static_cast<ClipDepth>(3), false).status == Status::InvalidArgument);
    CHECK(val(pcss_delinearize_window_depth(INFINITY, 0.1f, INFINITY, false)) == 1.0f);
    CHECK(val(pcss_linearize_ortho_window_depth(0.25f, 2.0f, 10.0f, false)) == doctest::Approx(4.0));
    CHECK(val(pcss_linearize_ortho_window_depth(0.25f, 2.0f, 10.0f, true)) == doctest::Approx(8.0));
    CHECK(pcss_linearize_ortho_window_depth(0.25f, 2.0f, INFINITY, true).status == Status::NonFinite);
}

TEST_CASE("the penumbra ratio must use linear depth (three.js / pboechat bug)") {
    const float n = 0.1f, f = 100.0f, w = 1.0f;
    const float zr = val(pcss_delinearize_window_depth(20.0f, n, f, false)), zb = val(pcss_delinearize_window_depth(10.0f, n, f, false));
    const float right = val(pcss_penumbra_width_from_window_depth(w, zr, zb, n, f, false));
    CHECK(double(right) == doctest::Approx(1.0).epsilon(1e-3));  // (20 - 10) / 10
    const double naive = double(w) * (double(zr) - double(zb)) / double(zb);
    CHECK(naive < 0.01);  // the naive ratio on window depths is ~200 times too small
    // Reversed-Z too.
    const float zr2 = val(pcss_delinearize_window_depth(20.0f, n, f, true)), zb2 = val(pcss_delinearize_window_depth(10.0f, n, f, true));
    CHECK(double(val(pcss_penumbra_width_from_window_depth(w, zr2, zb2, n, f, true))) == doctest::Approx(1.0).epsilon(1e-3));
}

TEST_CASE("average blocker: only samples closer than the receiver, invalid samples ignored") {
    const float d[] = {2.0f, 4.0f, 9.0f, 10.0f, 11.0f, NAN, INFINITY, -1.0f, 0.0f};
    PcssBlocker b = pcss_average_blocker(d, 9, 10.0f, 0.5f);
    CHECK(b.status == Status::Ok);
    CHECK(b.blocker_found);
    CHECK(b.blocker_count == 3);
    CHECK(b.average == doctest::Approx(5.0));
    b = pcss_average_blocker(d, 9, 10.0f, 8.5f);
    CHECK(b.status == Status::Ok);  // no blocker is an outcome, not an error
    CHECK(b.blocker_count == 0);
    CHECK_FALSE(b.blocker_found);
    b = pcss_average_blocker(d, 0, 10.0f, 0.0f);
    CHECK(b.status == Status::Ok);
    CHECK_FALSE(b.blocker_found);
    CHECK(pcss_average_blocker(nullptr, 0, 10.0f, 0.0f).status == Status::Ok);
    CHECK(pcss_average_blocker(nullptr, 9, 10.0f, 0.0f).status == Status::InvalidArgument);
    CHECK(pcss_average_blocker(d, 9, NAN, 0.0f).status == Status::NonFinite);
    CHECK(pcss_average_blocker(d, 9, 10.0f, INFINITY).status == Status::NonFinite);
    CHECK(PcssBlocker{}.status == Status::NotRun);
    // All taps outside the map (cleared to far / invalid): no blocker, fully lit.
    const float outside[] = {INFINITY, NAN, 100.0f};
    CHECK_FALSE(pcss_average_blocker(outside, 3, 50.0f, 0.0f).blocker_found);
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
        CHECK(r.blocker_count == cnt);
        if (cnt > 0) {
            CHECK(r.average >= lo * (1 - 1e-6f));
            CHECK(r.average <= hi * (1 + 1e-6f));
        }
    }
}

TEST_CASE("stiff cases: zero-size light, blocker at receiver, receiver at near plane, blocker depth -> 0, NaN") {
    PcssBlocker b;
    b.status = Status::Ok;
    b.blocker_found = true;
    b.average = 5.0f;
    PcssPolicy pol;
    pol.map_resolution = 2048.0f;
    // Zero-size light: exactly a hard shadow (filter 0, minimum taps).
    PcssFilter f = pcss_filter(spot(0.0f, 0.1f, 100.0f, 1.0f), 10.0f, b, pol);
    CHECK(f.status == Status::Ok);
    CHECK(f.blocker_found);
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
    CHECK(val(pcss_search_uv(spot(1.0f, 0.1f, 100.0f, 1.0f), 0.1f)) == 0.0f);
    CHECK(val(pcss_search_width(1.0f, 0.05f, 0.1f)) == 0.0f);
    // Blocker depth tending to 0: penumbra -> huge, filter clamped, finite; beyond float: Overflow.
    for (float zb : {1e-3f, 1e-10f, 1e-30f}) {
        b.average = zb;
        f = pcss_filter(spot(1.0f, 0.1f, 100.0f, 1.0f), 10.0f, b, pol);
        CHECK(f.status == Status::Ok);
        CHECK(std::isfinite(f.filter_uv));
        CHECK(std::isfinite(f.penumbra_width));
        CHECK(f.filter_uv == pol.max_filter_uv);
        CHECK(f.taps >= pol.min_taps);
        CHECK(f.taps <= pol.max_taps);
    }
    b.average = 1e-45f;
    CHECK(pcss_filter(spot(1.0f, 0.1f, 100.0f, 1.0f), 10.0f, b, pol).status == Status::Overflow);
    for (float zb : {0.0f, -1.0f}) {
        b.average = zb;
        CHECK(pcss_filter(spot(1.0f, 0.1f, 100.0f, 1.0f), 10.0f, b, pol).status == Status::InvalidArgument);
    }
    // Very large light: clamped.
    b.average = 5.0f;
    f = pcss_filter(spot(1e30f, 0.1f, 100.0f, 1.0f), 10.0f, b, pol);
    CHECK(f.filter_uv == pol.max_filter_uv);
    CHECK(f.taps == pol.max_taps);
    CHECK(f.search_uv == pol.max_filter_uv);  // the search clamp
    // No blocker: fully lit, no filter work, Ok.
    PcssBlocker none;
    none.status = Status::Ok;
    f = pcss_filter(spot(1.0f, 0.1f, 100.0f, 1.0f), 10.0f, none, pol);
    CHECK(f.status == Status::Ok);
    CHECK_FALSE(f.blocker_found);
    CHECK(f.taps == 0);
    CHECK(f.filter_uv == 0.0f);
    // A blocker estimate no call filled (NotRun) is rejected.
    CHECK(pcss_filter(spot(1.0f, 0.1f, 100.0f, 1.0f), 10.0f, PcssBlocker{}, pol).status == Status::InvalidArgument);
    // NaN / invalid input.
    CHECK(pcss_filter(spot(1.0f, 0.1f, 100.0f, 1.0f), NAN, b, pol).status == Status::NonFinite);
    CHECK(pcss_filter(spot(NAN, 0.1f, 100.0f, 1.0f), 10.0f, b, pol).status == Status::NonFinite);
    CHECK(pcss_filter(spot(-1.0f, 0.1f, 100.0f, 1.0f), 10.0f, b, pol).status == Status::InvalidArgument);
    CHECK(pcss_filter(spot(1.0f, 0.0f, 100.0f, 1.0f), 10.0f, b, pol).status == Status::InvalidArgument);
    CHECK(pcss_filter(spot(1.0f, 1.0f, 0.5f, 1.0f), 10.0f, b, pol).status == Status::InvalidArgument);
    CHECK(pcss_filter(spot(1.0f, 0.1f, INFINITY, 1.0f), 10.0f, b, pol).status == Status::Ok);
    for (float bad : {NAN, INFINITY, -INFINITY}) {
        b.average = bad;
        CHECK(pcss_filter(spot(1.0f, 0.1f, 100.0f, 1.0f), 10.0f, b, pol).status == Status::InvalidArgument);
    }
    CHECK(val(pcss_penumbra_width_directional(0.0f, 10.0f, 5.0f)) == 0.0f);  // zero-size sun: hard
    CHECK(pcss_penumbra_width_directional(0.0f, 10.0f, -INFINITY).status == Status::NonFinite);
    PcssPolicy bad;
    bad.map_resolution = 2048.0f;
    bad.max_filter_uv = NAN;
    b.average = 5.0f;
    CHECK(pcss_filter(spot(1.0f, 0.1f, 100.0f, 1.0f), 10.0f, b, bad).status == Status::NonFinite);
    CHECK(pcss_filter(spot(1.0f, 0.1f, 100.0f, 1.0f), 10.0f, b, PcssPolicy{}).status == Status::InvalidArgument);  // map_resolution required
    CHECK(pcss_penumbra_width(1.0f, NAN, 1.0f).status == Status::NonFinite);
    CHECK(pcss_search_width(1.0f, NAN, 1.0f).status == Status::NonFinite);
    CHECK(pcss_light_uv_at_near(spot(1.0f, -1.0f, 100.0f, 1.0f)).status == Status::InvalidArgument);
    CHECK(pcss_light_uv_at_near(PcssLight{}).status == Status::InvalidArgument);  // required fields
    CHECK(double(val(pcss_light_uv_at_near(spot(1.0f, 0.5f, 100.0f, 1.0f)))) == doctest::Approx(1.0 / (0.5 * 2.0 * std::tan(0.5))));
    CHECK(pcss_validate_light(spot(1.0f, 0.5f, 100.0f, 1.0f)) == Status::Ok);
    PcssLight odd = spot(1.0f, 0.5f, 100.0f, 1.0f);
    odd.type = static_cast<PcssLightType>(7);
    CHECK(pcss_validate_light(odd) == Status::InvalidArgument);
}

TEST_CASE("filter clamp and tap budget policy") {
    CHECK(val(pcss_clamp_filter(NAN, 0.001f, 0.05f)) == 0.001f);
    CHECK(val(pcss_clamp_filter(INFINITY, 0.001f, 0.05f)) == 0.05f);
    CHECK(val(pcss_clamp_filter(-INFINITY, 0.001f, 0.05f)) == 0.001f);
    CHECK(val(pcss_clamp_filter(0.01f, 0.001f, 0.05f)) == 0.01f);
    CHECK(pcss_clamp_filter(0.01f, 0.05f, 0.001f).status == Status::InvalidArgument);
    CHECK(pcss_clamp_filter(0.01f, NAN, 0.001f).status == Status::NonFinite);
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

// Issue 13 item 6. The blocker search is cut at the light's near plane: with near 1 and casters 3
// away from the light the region is 5 times wider than the blockers' pyramid (0.47 of the map
// here), and 16 taps miss a small blocker for most receivers in its shadow (the old README path:
// "fully lit", light leaking into the shadow). pcss_fit_near_plane moves the near plane to the
// casters and the same 16 taps find the blocker. CPU emulation of sk_pcss's search: the snippet's
// 16 Poisson taps (poisson_eliminate(disk, 64, seed 1), progressive: its first 16), rotated per
// receiver, nearest reads of an analytic depth map (light at the origin looking down +z, a square
// blocker at depth 3, the receiver plane at depth 6), every receiver point the square light sees
// partly hidden (brute-force visibility < 0.98).
TEST_CASE("near-plane fit: the blocker search finds the blocker (issue 13.6)") {
    glm::vec2 disk[64];
    REQUIRE(poisson_eliminate(PoissonDomain{}, 64, 1, disk, 64).status == Status::Ok);
    const float fov = 1.0471976f, fw = 2.0f * std::tan(0.5f * fov);
    const float z_b = 3.0f, z_r = 6.0f, side = 0.4f;
    const glm::vec2 bc(0.4f, 0.2f);  // blocker center (x, y) at depth z_b
    PcssLight L = spot(0.65f, 1.0f, 50.0f, fov);
    const glm::mat4 view = glm::lookAt(glm::vec3(0.0f), glm::vec3(0.0f, 0.0f, 1.0f), glm::vec3(0.0f, 1.0f, 0.0f));
    const PcssFit fit = pcss_fit_near_plane(L, view, glm::vec3(bc - 0.5f * side, z_b), glm::vec3(bc + 0.5f * side, z_b + 0.1f));
    REQUIRE(fit.status == Status::Ok);
    REQUIRE(fit.raised);
    CHECK(fit.caster_near_z == doctest::Approx(z_b));
    CHECK(fit.light.near_z == doctest::Approx(0.99 * z_b));
    CHECK(fit.light.near_z < z_b);  // the nearest caster is not clipped
    const float old_search = val(pcss_search_uv(L, z_r)), new_search = val(pcss_search_uv(fit.light, z_r));
    MESSAGE("search width (uv): near 1: " << old_search << ", fitted near " << fit.light.near_z << ": " << new_search);
    CHECK(old_search == doctest::Approx(0.47).epsilon(0.01));
    // The fitted search is exactly the width of the receiver-to-light pyramid at the casters.
    CHECK(double(new_search) == doctest::Approx(0.65 * (6.0 - 0.99 * 3.0) / (6.0 * 0.99 * 3.0 * double(fw))).epsilon(1e-5));
    // Analytic map: depth seen through uv from the light's center.
    auto depth_at = [&](glm::vec2 uv) {
        const glm::vec2 slope = (uv - 0.5f) * fw;  // x / z, y / z
        const glm::vec2 hit = slope * z_b;
        return std::fabs(hit.x - bc.x) <= 0.5f * side && std::fabs(hit.y - bc.y) <= 0.5f * side ? z_b : z_r;
    };
    // The CPU sk_pcss: blocker search, pcss_filter, then 16 filter taps (compare: lit when the
    // map's depth is not closer than the receiver). Returns (blocker found, visibility).
    auto pcss = [&](const PcssLight& light, glm::vec2 p, float angle) {
        PcssPolicy pol;
        pol.map_resolution = 2048.0f;
        pol.max_filter_uv = 1.0f;  // no clamp here: the near plane alone decides
        const glm::vec2 uv = 0.5f + p / (z_r * fw);
        const float search = std::min(val(pcss_search_uv(light, z_r)), pol.max_filter_uv);
        const float c = std::cos(angle), s = std::sin(angle);
        float depths[16];
        for (int i = 0; i < 16; ++i) {
            const glm::vec2 o(c * disk[i].x - s * disk[i].y, s * disk[i].x + c * disk[i].y);
            depths[i] = depth_at(uv + o * (0.5f * search));
        }
        const PcssBlocker b = pcss_average_blocker(depths, 16, z_r, 0.01f);
        REQUIRE(b.status == Status::Ok);
        const PcssFilter f = pcss_filter(light, z_r, b, pol);
        REQUIRE(f.status == Status::Ok);
        if (!f.blocker_found) return std::make_pair(false, 1.0);
        int lit = 0;
        for (int i = 0; i < 16; ++i) {
            const glm::vec2 o(c * disk[i].x - s * disk[i].y, s * disk[i].x + c * disk[i].y);
            lit += depth_at(uv + o * (0.5f * f.filter_uv)) >= z_r - 0.01f;
        }
        return std::make_pair(true, lit / 16.0);
    };
    std::mt19937 g(136);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    int shadowed = 0, found_old = 0, found_new = 0, mid = 0, mid_old = 0, mid_new = 0;
    double se_old = 0.0, se_new = 0.0;
    for (int iy = 0; iy < 48; ++iy)
        for (int ix = 0; ix < 48; ++ix) {
            // receiver points around the blocker's shadow (the blocker projects 2x onto depth 6)
            const glm::vec2 p = 2.0f * bc + (glm::vec2(float(ix), float(iy)) / 47.0f - 0.5f) * 1.4f;
            // brute force: the square light (side 0.65 at depth 0) seen from (p, z_r) past the blocker
            const double v = visibility_offset(double(p.x - 2.0f * bc.x), double(p.y - 2.0f * bc.y), 0.65, side, z_b, z_r,
                                               double(bc.x), double(bc.y));
            if (!(v < 0.98)) continue;
            ++shadowed;
            const float angle = 6.2831853f * u01(g);
            const auto po = pcss(L, p, angle), pn = pcss(fit.light, p, angle);
            found_old += po.first;
            found_new += pn.first;
            se_old += (po.second - v) * (po.second - v);
            se_new += (pn.second - v) * (pn.second - v);
            if (v < 0.8) {  // a receiver at least a fifth in shadow
                ++mid;
                mid_old += po.first;
                mid_new += pn.first;
            }
        }
    const double rmse_old = std::sqrt(se_old / shadowed), rmse_new = std::sqrt(se_new / shadowed);
    MESSAGE("receivers in the blocker's shadow: " << shadowed << "; blocker found with near 1: " << found_old
            << ", with the fitted near: " << found_new << "; of the " << mid << " at least 20% shadowed: " << mid_old
            << " / " << mid_new << "; PCSS RMSE against the brute-force area light: " << rmse_old << " / " << rmse_new);
    CHECK(shadowed > 1000);
    CHECK(mid > 1000);
    CHECK(mid_new == mid);                 // fitted: the blocker is found wherever it hides a fifth of the light
    CHECK(mid_old <= mid * 9 / 10);        // near 1: missed for more than 10% of them (fully lit: a leak)
    CHECK(found_new > found_old);
    CHECK(rmse_new < 0.75 * rmse_old);
}

TEST_CASE("search clamp: the README's near 0.1, receiver 40 search is clamped to max_filter_uv") {
    // near 0.1, a 0.5 light, 60 degree cone, receiver 40: the pyramid cut at the near plane is 4.3
    // times the whole map. pcss_filter reports the search clamped to max_filter_uv (glsl/pcss.glsl
    // clamps the same way).
    const PcssLight L = spot(0.5f, 0.1f, 100.0f, 1.0471976f);
    CHECK(double(val(pcss_search_uv(L, 40.0f))) == doctest::Approx(4.32).epsilon(0.01));
    PcssBlocker b;
    b.status = Status::Ok;
    b.blocker_found = true;
    b.average = 20.0f;
    PcssPolicy pol;
    pol.map_resolution = 2048.0f;
    const PcssFilter f = pcss_filter(L, 40.0f, b, pol);
    REQUIRE(f.status == Status::Ok);
    CHECK(f.search_uv == pol.max_filter_uv);
    // pcss_fit_near_plane with casters from depth 15 on: the search becomes a fraction of the map.
    const glm::mat4 view = glm::lookAt(glm::vec3(0.0f), glm::vec3(0.0f, 0.0f, 1.0f), glm::vec3(0.0f, 1.0f, 0.0f));
    const PcssFit fit = pcss_fit_near_plane(L, view, glm::vec3(-2.0f, -2.0f, 15.0f), glm::vec3(2.0f, 2.0f, 25.0f));
    REQUIRE(fit.raised);
    const float s = val(pcss_search_uv(fit.light, 40.0f));
    MESSAGE("README example: search " << val(pcss_search_uv(L, 40.0f)) << " of the map at near 0.1, " << s << " at near " << fit.light.near_z);
    CHECK(s < 0.02f);
}

TEST_CASE("near-plane fit: never lowers the near plane, validates, directional lights") {
    const glm::mat4 view = glm::lookAt(glm::vec3(0.0f), glm::vec3(0.0f, 0.0f, 1.0f), glm::vec3(0.0f, 1.0f, 0.0f));
    const PcssLight L = spot(0.5f, 2.0f, 50.0f, 1.0f);
    // casters reaching the near plane, or behind the light: Ok, not raised
    PcssFit f = pcss_fit_near_plane(L, view, glm::vec3(-1.0f, -1.0f, 1.0f), glm::vec3(1.0f, 1.0f, 5.0f));
    CHECK(f.status == Status::Ok);
    CHECK_FALSE(f.raised);
    CHECK(f.light.near_z == 2.0f);
    f = pcss_fit_near_plane(L, view, glm::vec3(-1.0f, -1.0f, -3.0f), glm::vec3(1.0f, 1.0f, 5.0f));
    CHECK(f.status == Status::Ok);
    CHECK_FALSE(f.raised);
    CHECK(f.caster_near_z < 0.0f);
    // casters beyond the far plane: nothing to fit
    f = pcss_fit_near_plane(L, view, glm::vec3(-1.0f, -1.0f, 60.0f), glm::vec3(1.0f, 1.0f, 65.0f));
    CHECK(f.status == Status::Ok);
    CHECK_FALSE(f.raised);
    // validation
    CHECK(pcss_fit_near_plane(PcssLight{}, view, glm::vec3(0.0f), glm::vec3(1.0f)).status == Status::InvalidArgument);
    CHECK(pcss_fit_near_plane(L, view, glm::vec3(2.0f), glm::vec3(1.0f)).status == Status::InvalidArgument);
    CHECK(pcss_fit_near_plane(L, view, glm::vec3(NAN), glm::vec3(1.0f)).status == Status::NonFinite);
    glm::mat4 bad = view;
    bad[3][2] = INFINITY;
    CHECK(pcss_fit_near_plane(L, bad, glm::vec3(0.0f), glm::vec3(1.0f)).status == Status::NonFinite);
    // issue #27 item 6: a zero (or otherwise singular) view matrix maps every caster to depth 0:
    // not a view, InvalidArgument
    CHECK(pcss_fit_near_plane(L, glm::mat4(0.0f), glm::vec3(0.0f), glm::vec3(1.0f)).status == Status::InvalidArgument);
    glm::mat4 flat = view;  // rank 2: the z row duplicates x
    flat[0][2] = flat[0][0];
    flat[1][2] = flat[1][0];
    flat[2][2] = flat[2][0];
    CHECK(pcss_fit_near_plane(L, flat, glm::vec3(0.0f), glm::vec3(1.0f)).status == Status::InvalidArgument);
    CHECK(pcss_fit_near_plane(L, glm::scale(view, glm::vec3(1e-3f)), glm::vec3(0.0f), glm::vec3(1.0f)).status == Status::Ok);
    // directional: the ortho near plane moves to 1% of (far - depth) in front of the casters
    PcssLight sun;
    sun.type = PcssLightType::Directional;
    sun.size = 0.01f;
    sun.near_z = -10.0f;
    sun.far_z = 100.0f;
    sun.frustum_width = 40.0f;
    f = pcss_fit_near_plane(sun, view, glm::vec3(-5.0f, -5.0f, 20.0f), glm::vec3(5.0f, 5.0f, 30.0f));
    REQUIRE(f.status == Status::Ok);
    CHECK(f.raised);
    CHECK(double(f.light.near_z) == doctest::Approx(20.0 - 0.01 * 80.0));
    // Property: the fitted near plane lies in front of every corner of the casters' box and never
    // below the given one; the search region shrinks.
    std::mt19937 g(61);
    std::uniform_real_distribution<float> u(-10.0f, 10.0f), dz(0.5f, 40.0f);
    for (int it = 0; it < 3000; ++it) {
        const glm::vec3 eye(u(g), u(g), u(g));
        const glm::vec3 dir = glm::normalize(glm::vec3(u(g), u(g), u(g)) + glm::vec3(0.0f, 0.0f, 0.01f));
        const glm::mat4 v = glm::lookAt(eye, eye + dir, std::fabs(dir.y) > 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0));
        const glm::vec3 c = eye + dir * dz(g);
        const glm::vec3 h(std::fabs(u(g)) * 0.2f + 0.01f, std::fabs(u(g)) * 0.2f + 0.01f, std::fabs(u(g)) * 0.2f + 0.01f);
        const PcssLight l = spot(0.5f, 0.05f, 1000.0f, 1.2f);
        const PcssFit r = pcss_fit_near_plane(l, v, c - h, c + h);
        REQUIRE(r.status == Status::Ok);
        CHECK(r.light.near_z >= l.near_z);
        for (int k = 0; k < 8 && r.raised; ++k) {
            const glm::vec3 corner((k & 1) ? c.x + h.x : c.x - h.x, (k & 2) ? c.y + h.y : c.y - h.y, (k & 4) ? c.z + h.z : c.z - h.z);
            CHECK(-(v * glm::vec4(corner, 1.0f)).z >= r.light.near_z);
        }
        if (r.raised) CHECK(val(pcss_search_uv(r.light, 1000.0f)) <= val(pcss_search_uv(l, 1000.0f)));
    }
}
