// Linear lights (Heidrich, Brabec & Seidel 2000): the exact box reference against brute-force
// sampling, zero-length = point light exactly, subdivision, skin construction on synthetic depth
// maps, the shade rule, and the skin interpolation against the closed form in flatland.
#include <doctest/doctest.h>

#include <shadowkit/linear_light.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

namespace sk = shadowkit;

namespace {

bool slab(glm::dvec3 p, glm::dvec3 q, glm::dvec3 lo, glm::dvec3 hi, double s0) {
    // independent of the header: parametric clip of p + s (q - p), s in [s0, 1]
    double t0 = s0, t1 = 1.0;
    for (int k = 0; k < 3; ++k) {
        const double d = q[k] - p[k];
        if (std::abs(d) < 1e-300) {
            if (p[k] < lo[k] || p[k] > hi[k]) return false;
            continue;
        }
        const double ta = (lo[k] - p[k]) / d, tb = (hi[k] - p[k]) / d;
        t0 = std::max(t0, std::min(ta, tb));
        t1 = std::min(t1, std::max(ta, tb));
    }
    return t0 <= t1;
}

// Brute force: fraction of M stratified light points visible from p.
double brute_fraction(glm::vec3 p, glm::vec3 n, glm::vec3 a, glm::vec3 b, const std::vector<sk::LinearLightBox>& boxes,
                      int M) {
    int seen = 0;
    for (int i = 0; i < M; ++i) {
        const double t = (i + 0.5) / M;
        const glm::dvec3 q = glm::dvec3(a) + t * (glm::dvec3(b) - glm::dvec3(a));
        if (n != glm::vec3(0.f) && !(glm::dot(glm::dvec3(n), q - glm::dvec3(p)) > 0.0)) continue;
        bool hit = false;
        for (const auto& bx : boxes) hit = hit || slab(glm::dvec3(p), q, glm::dvec3(bx.lo), glm::dvec3(bx.hi), 1e-4);
        seen += hit ? 0 : 1;
    }
    return double(seen) / M;
}

}  // namespace

TEST_CASE("segment from center, direction and length; zero length is a point") {
    sk::LinearLightSegment s = sk::linear_light_segment({1.f, 2.f, 3.f}, {0.f, 0.f, 4.f}, 2.f);
    CHECK(s.status == sk::Status::Ok);
    CHECK(s.end_a.z == doctest::Approx(2.f));
    CHECK(s.end_b.z == doctest::Approx(4.f));
    CHECK_FALSE(s.is_point);
    s = sk::linear_light_segment({1.f, 2.f, 3.f}, {0.f, 0.f, 0.f}, 0.f);
    CHECK(s.status == sk::Status::Ok);
    CHECK(s.is_point);
    CHECK(s.end_a == glm::vec3(1.f, 2.f, 3.f));
    CHECK(s.end_b == s.end_a);
    CHECK(sk::linear_light_segment({0.f, 0.f, 0.f}, {0.f, 0.f, 0.f}, 1.f).status == sk::Status::InvalidArgument);
    CHECK(sk::linear_light_segment({0.f, 0.f, 0.f}, {1.f, 0.f, 0.f}, -1.f).status == sk::Status::InvalidArgument);
    CHECK(sk::linear_light_segment({NAN, 0.f, 0.f}, {1.f, 0.f, 0.f}, 1.f).status == sk::Status::NonFinite);
    glm::vec3 e[5];
    s = sk::linear_light_segment({0.f, 0.f, 0.f}, {1.f, 0.f, 0.f}, 4.f);
    const sk::LinearLightSubdivideResult d = sk::linear_light_subdivide(s, 4, e, 5);
    CHECK(d.status == sk::Status::Ok);
    CHECK(d.count == 5);
    CHECK(e[0] == s.end_a);
    CHECK(e[4] == s.end_b);
    CHECK(e[1].x == doctest::Approx(-1.f));
    CHECK(sk::linear_light_subdivide(s, 0, e, 5).status == sk::Status::InvalidArgument);
    const sk::LinearLightSubdivideResult q = sk::linear_light_subdivide(s, 8, nullptr, 0);  // size query
    CHECK(q.status == sk::Status::BufferTooSmall);
    CHECK(q.needed == 9);
    // a null buffer with a capacity (was: a size query returning the count) and a default segment
    CHECK(sk::linear_light_subdivide(s, 8, nullptr, 9).status == sk::Status::InvalidArgument);
    CHECK(sk::linear_light_subdivide(sk::LinearLightSegment{}, 2, e, 5).status == sk::Status::InvalidArgument);
}

TEST_CASE("box interval: exact against brute force (3000 random configurations)") {
    std::mt19937 rng(42);
    std::uniform_real_distribution<float> u(-2.f, 2.f);
    double worst = 0.0;
    int nonempty = 0;
    for (int it = 0; it < 3000; ++it) {
        const glm::vec3 p(u(rng), u(rng) - 1.f, u(rng));
        const glm::vec3 a(u(rng), 3.f + u(rng) * 0.3f, u(rng)), b(u(rng), 3.f + u(rng) * 0.3f, u(rng));
        const glm::vec3 c(u(rng) * 0.7f, 1.f + u(rng) * 0.3f, u(rng) * 0.7f), h(0.1f + std::abs(u(rng)) * 0.4f,
                                                                               0.1f + std::abs(u(rng)) * 0.4f,
                                                                               0.1f + std::abs(u(rng)) * 0.4f);
        const sk::LinearLightBox box{c - h, c + h};
        const sk::LinearLightInterval I = sk::linear_light_box_interval(p, a, b, box);
        const int M = 4000;
        int hits = 0;
        double tmin = 2.0, tmax = -1.0;
        for (int i = 0; i < M; ++i) {
            const double t = (i + 0.5) / M;
            const glm::dvec3 q = glm::dvec3(a) + t * (glm::dvec3(b) - glm::dvec3(a));
            if (slab(glm::dvec3(p), q, glm::dvec3(box.lo), glm::dvec3(box.hi), 1e-4)) {
                ++hits;
                tmin = std::min(tmin, t);
                tmax = std::max(tmax, t);
            }
        }
        if (hits) {
            ++nonempty;
            REQUIRE_FALSE(I.empty());
            // the sampled hits form one run (convexity) and match the interval to the sample spacing
            CHECK(hits == int(std::lround((tmax - tmin) * M)) + 1);
            worst = std::max({worst, std::abs(tmin - I.t0), std::abs(tmax - I.t1)});
        } else {
            CHECK(double(I.t1) - double(I.t0) < 2.0 / M);
        }
    }
    std::printf("box interval vs 4000-sample brute force: worst endpoint error %.2e (sample spacing 2.5e-4), %d hits\n",
                worst, nonempty);
    CHECK(worst <= 1.0 / 4000);
    CHECK(nonempty > 300);
}

TEST_CASE("visible fraction: several boxes and the tangent plane against brute force (2000 configurations)") {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    double worst = 0.0;
    for (int it = 0; it < 2000; ++it) {
        std::vector<sk::LinearLightBox> boxes;
        const int nb = 1 + it % 4;
        for (int k = 0; k < nb; ++k) {
            const glm::vec3 c(u(rng) * 1.5f, 1.f + 0.5f * u(rng), u(rng) * 1.5f);
            const glm::vec3 h(0.05f + 0.3f * std::abs(u(rng)), 0.05f + 0.3f * std::abs(u(rng)), 0.05f + 0.3f * std::abs(u(rng)));
            boxes.push_back({c - h, c + h});
        }
        const glm::vec3 p(u(rng) * 2.f, 0.f, u(rng) * 2.f);
        glm::vec3 n(0.f, 1.f, 0.f);
        if (it % 3 == 1) n = glm::normalize(glm::vec3(u(rng), 0.3f * u(rng), u(rng)));  // tilted: cuts the light
        if (it % 3 == 2) n = glm::vec3(0.f);
        const glm::vec3 a(-1.f + u(rng), 3.f, u(rng)), b(1.f + u(rng), 3.f + u(rng), u(rng));
        const sk::LinearLightFraction f = sk::linear_light_visible_fraction(p, n, a, b, boxes.data(), boxes.size());
        REQUIRE(f.status == sk::Status::Ok);
        const double bf = brute_fraction(p, n, a, b, boxes, 8000);
        worst = std::max(worst, std::abs(bf - double(f.fraction)));
    }
    std::printf("visible fraction vs 8000-sample brute force: worst |error| %.2e\n", worst);
    CHECK(worst < 5e-4);
}

TEST_CASE("zero-length light gives the point-light result exactly") {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    const std::vector<sk::LinearLightBox> boxes = {{{-0.5f, 0.f, -0.5f}, {0.5f, 1.f, 0.5f}}, {{0.8f, 0.f, 0.2f}, {0.9f, 1.5f, 0.3f}}};
    int mismatches = 0, shadowed = 0;
    for (int it = 0; it < 20000; ++it) {
        const glm::vec3 L(u(rng) * 2.f, 3.f + u(rng), u(rng) * 2.f), p(u(rng) * 3.f, 0.f, u(rng) * 3.f);
        const sk::LinearLightSegment s = sk::linear_light_segment(L, {1.f, 0.f, 0.f}, 0.f);
        const float f = sk::linear_light_visible_fraction(p, {0.f, 1.f, 0.f}, s.end_a, s.end_b, boxes.data(), boxes.size()).fraction;
        bool hit = false;
        for (const auto& b : boxes) hit = hit || slab(glm::dvec3(p), glm::dvec3(L), glm::dvec3(b.lo), glm::dvec3(b.hi), 1e-4);
        const float point = hit ? 0.f : 1.f;
        mismatches += f != point;
        shadowed += hit;
        // shade rule: both endpoints are the same shadow map, no skin: 0.5 + 0.5 == 1 exactly
        const float v = sk::linear_light_shade(!hit, sk::kLinearLightDefaultVisibility, !hit, sk::kLinearLightDefaultVisibility);
        mismatches += v != point;
    }
    CHECK(mismatches == 0);
    CHECK(shadowed > 1000);
    // below the tangent plane: 0
    CHECK(sk::linear_light_visible_fraction({0, 0, 0}, {0, -1, 0}, {0, 3, 0}, {0, 3, 0}, nullptr, 0).fraction == 0.f);
    // tiny light (1e-6): continuous with the point result away from shadow edges
    const float tiny = sk::linear_light_visible_fraction({2.f, 0.f, 0.f}, {0, 1, 0}, {0.f, 3.f, 0.f}, {1e-6f, 3.f, 0.f},
                                                         boxes.data(), boxes.size()).fraction;
    CHECK(tiny == 1.f);
}

TEST_CASE("skin cells: discontinuities become triangles with 0 on the occluder and 1 on the receiver") {
    // a W x H map with an occluder (distance 2) in the left half and the receiver (distance 5) right
    const std::uint32_t W = 8, H = 6;
    std::vector<glm::vec3> pos(W * H);
    std::vector<float> dist(W * H);
    for (std::uint32_t j = 0; j < H; ++j)
        for (std::uint32_t i = 0; i < W; ++i) {
            const bool occ = i < 3;
            dist[j * W + i] = occ ? 2.f : 5.f + 0.01f * float(i);  // slight slope on the receiver
            pos[j * W + i] = glm::vec3(float(i), float(j), -dist[j * W + i]);
        }
    std::vector<sk::LinearLightSkinVertex> skin(sk::linear_light_skin_capacity(W, H));
    sk::LinearLightSkinResult r = sk::linear_light_build_skin(pos.data(), dist.data(), W, H, 0.05f, skin.data(), skin.size());
    CHECK(r.status == sk::Status::Ok);
    CHECK(r.cells == H - 1);                 // only the column of cells across i = 2|3
    CHECK(r.count == 6 * (H - 1));           // both triangles of each discontinuity cell
    for (std::size_t k = 0; k < r.count; ++k) {
        const bool occ = skin[k].position.x < 2.5f;
        CHECK(skin[k].value == (occ ? 0.f : 1.f));
    }
    // threshold above the jump: no skin; receiver slope below the threshold: no false skin
    r = sk::linear_light_build_skin(pos.data(), dist.data(), W, H, 2.0f, skin.data(), skin.size());
    CHECK(r.needed == 0);
    // truncated buffer reports the need
    r = sk::linear_light_build_skin(pos.data(), dist.data(), W, H, 0.05f, skin.data(), 4);
    CHECK(r.status == sk::Status::BufferTooSmall);
    CHECK(r.needed == 6 * (H - 1));
    CHECK(r.count == 4);
    // a corner cell: one occluder sample out of four; both triangles (a continuous skin)
    const sk::LinearLightSkinCell c1 = sk::linear_light_skin_cell({5.f, 2.f, 5.f, 5.f}, 0.05f);
    CHECK(c1.status == sk::Status::Ok);
    CHECK(c1.triangle_count == 2);
    CHECK(c1.value[1] == 0.f);
    CHECK(c1.value[0] == 1.f);
    CHECK(c1.triangles[0][1] == 1);
    CHECK(c1.triangles[1][2] == 2);
    const sk::LinearLightSkinCell c2 = sk::linear_light_skin_cell({5.f, 5.1f, 5.f, 5.f}, 0.05f);  // no discontinuity
    CHECK(c2.status == sk::Status::Ok);
    CHECK(c2.triangle_count == 0);
    // NaN / non-positive distances: an error (was: silently "no discontinuity")
    CHECK(sk::linear_light_skin_cell({5.f, NAN, 5.f, 5.f}, 0.05f).status == sk::Status::NonFinite);
    CHECK(sk::linear_light_skin_cell({5.f, 0.f, 5.f, 5.f}, 0.05f).status == sk::Status::InvalidArgument);
    CHECK(sk::linear_light_skin_cell({5.f, 1.f, 5.f, 5.f}, -0.05f).status == sk::Status::InvalidArgument);
    CHECK_FALSE(sk::linear_light_is_discontinuity(1.f, 1.04f, 0.05f));
    CHECK(sk::linear_light_is_discontinuity(1.f, 1.06f, 0.05f));
    CHECK_FALSE(sk::linear_light_is_discontinuity(0.f, 1.f, 0.05f));
}

TEST_CASE("flatland: the warped skin interpolates the penumbra (closed form) and the shade rule") {
    // 2D (x, y): line light from A = (-w/2, H) to B = (w/2, H); a thin occluder covering x < e at
    // height h; receiver y = 0. Points between B's shadow edge and A's shadow edge see B but not A.
    // The skin of A's map joins the occluder edge E = (e, h) (value 0) and its shadow from A,
    // R = E + (E - A) h / (H - h) on y = 0 (value 1). Warped into B's view and interpolated linearly
    // in B's image coordinate it gives v_B(x); V = shade(lit_A = false, ., lit_B = true, v_B).
    // Exact: the fraction of the light visible over the edge. With B looking straight down the image
    // coordinate is affine in x and the interpolation is exact; tilted views make it projective
    // (the paper's linear approximation of the rational function).
    const double w = 1.0, Hh = 3.0, h = 1.0, e = 0.2;
    const glm::dvec2 A(-w / 2, Hh), B(w / 2, Hh), E(e, h);
    const glm::dvec2 R = E + (E - A) * (h / (Hh - h));   // A's shadow edge
    const glm::dvec2 RB = E + (E - B) * (h / (Hh - h));  // B's shadow edge
    for (double tilt : {0.0, 0.3, 0.6}) {
        const glm::dvec2 fwd(std::sin(tilt), -std::cos(tilt)), right(std::cos(tilt), std::sin(tilt));
        auto img = [&](glm::dvec2 q) { return glm::dot(q - B, right) / glm::dot(q - B, fwd); };
        double worst = 0.0;
        int n = 0;
        for (int i = 0; i <= 200; ++i) {
            const glm::dvec2 q(RB.x + (double(i) / 200.0) * (R.x - RB.x), 0.0);
            const double sp = (img(q) - img(E)) / (img(R) - img(E));  // skin parameter, 0 at E, 1 at R
            if (sp < -1e-9 || sp > 1.0 + 1e-9) continue;
            const double V = sk::linear_light_shade(false, sk::kLinearLightDefaultVisibility, true, float(sp));
            const sk::LinearLightBox occ{{-100.f, float(h) - 1e-3f, -1.f}, {float(e), float(h), 1.f}};
            const double exact = sk::linear_light_visible_fraction(glm::vec3(float(q.x), 0.f, 0.f), {0.f, 1.f, 0.f},
                                                                   glm::vec3(float(A.x), float(Hh), 0.f),
                                                                   glm::vec3(float(B.x), float(Hh), 0.f), &occ, 1)
                                     .fraction;
            worst = std::max(worst, std::abs(V - exact));
            ++n;
        }
        std::printf("flatland penumbra, B's view tilted %.1f rad: max |V - exact| = %.4f over %d points\n", tilt, worst, n);
        CHECK(n > 150);
        CHECK(worst < (tilt == 0.0 ? 2e-3 : 0.05));
    }
}

TEST_CASE("stiff input: NaN, huge coordinates, degenerate boxes, receiver on the box") {
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    const sk::LinearLightBox box{{-1.f, 0.f, -1.f}, {1.f, 1.f, 1.f}};
    CHECK(sk::linear_light_box_interval({nan, 0, 0}, {0, 3, 0}, {1, 3, 0}, box).status == sk::Status::NonFinite);
    CHECK(sk::linear_light_visible_fraction({0, 0, 0}, {0, 1, 0}, {inf, 3, 0}, {1, 3, 0}, &box, 1).status ==
          sk::Status::NonFinite);
    CHECK(sk::linear_light_visible_fraction({0, 0, 0}, {0, 1, 0}, {0, 3, 0}, {1, 3, 0}, nullptr, 1).status ==
          sk::Status::InvalidArgument);
    // receiver on the box's top face sees the whole light (no self-occlusion)
    CHECK(sk::linear_light_visible_fraction({0.f, 1.f, 0.f}, {0, 1, 0}, {-1, 3, 0}, {1, 3, 0}, &box, 1).fraction == 1.f);
    // receiver under the box sees nothing
    CHECK(sk::linear_light_visible_fraction({0.f, -0.5f, 0.f}, {0, 1, 0}, {-1, 3, 0}, {1, 3, 0}, &box, 1).fraction == 0.f);
    // huge coordinates: finite fraction in [0,1]
    const sk::LinearLightFraction f =
        sk::linear_light_visible_fraction({1e6f, 0.f, 0.f}, {0, 1, 0}, {-1e6f, 1e6f, 0}, {1e6f, 1e6f, 0}, &box, 1);
    CHECK(f.fraction >= 0.f);
    CHECK(f.fraction <= 1.f);
    // flat (zero-thickness) box and a light in the box's plane
    const sk::LinearLightBox flat{{-1.f, 1.f, -1.f}, {1.f, 1.f, 1.f}};
    const float ff = sk::linear_light_visible_fraction({0.f, 0.f, 0.f}, {0, 1, 0}, {-1, 3, 0}, {1, 3, 0}, &flat, 1).fraction;
    CHECK(ff == 0.f);
    const float fp = sk::linear_light_visible_fraction({5.f, 0.f, 0.f}, {0, 1, 0}, {-3, 1, 0}, {3, 1, 0}, &flat, 1).fraction;
    CHECK(fp >= 0.f);
    CHECK(fp <= 1.f);
    // grazing: the light in the receiver's tangent plane counts as unseen
    CHECK(sk::linear_light_visible_fraction({0, 0, 0}, {0, 1, 0}, {-1, 0, 5}, {1, 0, 5}, nullptr, 0).fraction == 0.f);
    // shade clamps and treats NaN as the default
    CHECK(sk::linear_light_shade(true, nan, true, 2.f) == doctest::Approx(1.5f));
}

TEST_CASE("skin cell midpoint at the float extremes: one occluder and one receiver corner (fuzz regression)") {
    // Found by fuzz_linear_light: 0.5f * (lo + hi) overflowed near FLT_MAX and rounded onto hi for
    // adjacent floats, so no corner was a receiver. Expected by hand: nearer than the midpoint -> 0.
    const float one_up = std::nextafter(1.f, 2.f), two_up = std::nextafter(one_up, 2.f);
    const float tiny = std::numeric_limits<float>::denorm_min();
    const struct {
        float d[4];
        float threshold;
    } cases[] = {{{1e38f, 3e38f, 1e38f, 3e38f}, 0.5f}, {{one_up, two_up, one_up, two_up}, 0.f},
                 {{tiny, 2 * tiny, tiny, 2 * tiny}, 0.f}};
    for (const auto& c : cases) {
        const sk::LinearLightSkinCell cell = sk::linear_light_skin_cell(glm::vec4(c.d[0], c.d[1], c.d[2], c.d[3]), c.threshold);
        REQUIRE(cell.triangle_count == 2);
        CHECK(cell.value[0] == 0.f);
        CHECK(cell.value[1] == 1.f);
        CHECK(cell.value[2] == 0.f);
        CHECK(cell.value[3] == 1.f);
    }
}

TEST_CASE("segment whose endpoint overflows float: Overflow, not Ok with Inf (issue 19 item 5)") {
    // Regression: the old code returned Ok with end_b.z = +Inf for a center at 3.4e38 and length
    // 3.4e38 (center + length / 2 = 5.1e38 > FLT_MAX).
    const sk::LinearLightSegment s = sk::linear_light_segment({0.f, 0.f, 3.4e38f}, {0.f, 0.f, 1.f}, 3.4e38f);
    CHECK(s.status == sk::Status::Overflow);
    CHECK(sk::linear_light_segment({-3e38f, 0.f, 0.f}, {-1.f, 0.f, 0.f}, 1e38f).status == sk::Status::Overflow);
    // the largest that fits: ends at +-1.5e38, length 3e38 < FLT_MAX
    const sk::LinearLightSegment big = sk::linear_light_segment({0.f, 0.f, 0.f}, {1.f, 0.f, 0.f}, 3e38f);
    CHECK(big.status == sk::Status::Ok);
    CHECK(big.end_b.x == doctest::Approx(1.5e38f));
    CHECK(std::isfinite(big.end_b.x - big.end_a.x));
    // direction Inf is NonFinite (was InvalidArgument), a zero direction with a length InvalidArgument
    CHECK(sk::linear_light_segment({0.f, 0.f, 0.f}, {INFINITY, 0.f, 0.f}, 1.f).status == sk::Status::NonFinite);
    CHECK(sk::linear_light_segment({0.f, 0.f, 0.f}, {0.f, 0.f, 0.f}, 1.f).status == sk::Status::InvalidArgument);
}

TEST_CASE("visible fraction behind 100 slats: exact past 64 intervals (closed form)") {
    // Regression: the old union kept at most 64 visible pieces and silently dropped the rest, so
    // a fence of more than 63 slats between the receiver and the light gave too small a fraction
    // with Ok. Closed form: light from (-1, 3, 0) to (1, 3, 0), receiver at the origin; a ray to
    // L(t) crosses y = 1.5 at x = t - 0.5, so a flat slat over x in [x0, x1] at y = 1.5 hides
    // t in [x0 + 0.5, x1 + 0.5]. 100 slats 0.005 wide every 0.01 hide exactly half of the light.
    std::vector<sk::LinearLightBox> slats;
    for (int k = 0; k < 100; ++k) {
        const float x0 = -0.5f + 0.01f * float(k);
        slats.push_back({{x0, 1.5f, -1.f}, {x0 + 0.005f, 1.5f, 1.f}});
    }
    double expect = 1.0;
    for (const auto& b : slats) expect -= double(b.hi.x) - double(b.lo.x);
    const sk::LinearLightFraction f =
        sk::linear_light_visible_fraction({0.f, 0.f, 0.f}, {0.f, 1.f, 0.f}, {-1.f, 3.f, 0.f}, {1.f, 3.f, 0.f}, slats.data(),
                                          slats.size(), 0.f);
    REQUIRE(f.status == sk::Status::Ok);
    CHECK(f.fraction == doctest::Approx(expect).epsilon(1e-5));
    CHECK(f.fraction == doctest::Approx(brute_fraction({0.f, 0.f, 0.f}, {0.f, 1.f, 0.f}, {-1.f, 3.f, 0.f}, {1.f, 3.f, 0.f},
                                                       slats, 20000))
                            .epsilon(1e-3));
    // the same slats in reverse order and shuffled (the sweep does not depend on the order)
    std::vector<sk::LinearLightBox> shuffled = slats;
    std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(5));
    CHECK(sk::linear_light_visible_fraction({0.f, 0.f, 0.f}, {0.f, 1.f, 0.f}, {-1.f, 3.f, 0.f}, {1.f, 3.f, 0.f},
                                            shuffled.data(), shuffled.size(), 0.f)
              .fraction == doctest::Approx(expect).epsilon(1e-5));
    // a box with lo > hi is InvalidArgument (was: an empty box)
    const sk::LinearLightBox inverted{{1.f, 1.f, 1.f}, {-1.f, 2.f, 2.f}};
    CHECK(sk::linear_light_visible_fraction({0.f, 0.f, 0.f}, {0.f, 1.f, 0.f}, {-1.f, 3.f, 0.f}, {1.f, 3.f, 0.f}, &inverted, 1)
              .status == sk::Status::InvalidArgument);
    CHECK(sk::linear_light_box_interval({0.f, 0.f, 0.f}, {-1.f, 3.f, 0.f}, {1.f, 3.f, 0.f}, slats[0], 1.f).status ==
          sk::Status::InvalidArgument);
}

TEST_CASE("property: finite input in range gives Ok and finite output, NaN gives NonFinite (5,000 configurations)") {
    std::mt19937 rng(1905);
    std::uniform_real_distribution<float> u(-1.f, 1.f), u01(0.f, 1.f);
    const float scales[6] = {1e-6f, 1e-3f, 1.f, 1e3f, 1e6f, 1e30f};
    int overflow = 0;
    for (int it = 0; it < 5000; ++it) {
        const float sc = scales[it % 6];
        glm::vec3 c(u(rng) * sc, u(rng) * sc, u(rng) * sc), dir(u(rng), u(rng), u(rng));
        float len = u01(rng) * sc * 2.f;
        if (it % 11 == 0) {  // near the float limit: some overflow
            c.x = u(rng) * 3.3e38f;
            len = u01(rng) * 3e38f;
        }
        const sk::LinearLightSegment s = sk::linear_light_segment(c, dir, len);
        // expected by double arithmetic: Ok iff both ends and their difference fit a float
        const double dl = glm::length(glm::dvec3(dir));
        const glm::dvec3 h = glm::dvec3(dir) * (0.5 * double(len) / dl);
        const double fmax = double(std::numeric_limits<float>::max());
        const bool fits = glm::all(glm::lessThanEqual(glm::abs(glm::dvec3(c) + h), glm::dvec3(fmax))) &&
                          glm::all(glm::lessThanEqual(glm::abs(glm::dvec3(c) - h), glm::dvec3(fmax))) &&
                          glm::all(glm::lessThanEqual(glm::abs(2.0 * h), glm::dvec3(fmax * (1.0 - 1e-6))));
        if (len > 0.f && dl == 0.0) continue;
        if (fits) {
            REQUIRE(s.status == sk::Status::Ok);
        } else if (s.status != sk::Status::Ok) {
            REQUIRE(s.status == sk::Status::Overflow);
            ++overflow;
            continue;
        }
        REQUIRE(sk::detail::ll_finite(s.end_a));
        REQUIRE(sk::detail::ll_finite(s.end_b));
        glm::vec3 ends[5];
        const auto d = sk::linear_light_subdivide(s, 4, ends, 5);
        REQUIRE(d.status == sk::Status::Ok);
        for (const auto& e : ends) REQUIRE(sk::detail::ll_finite(e));
        // boxes and receivers around the light at its scale
        std::vector<sk::LinearLightBox> boxes(std::size_t(it % 80));
        for (auto& b : boxes) {
            const glm::vec3 lo = c + glm::vec3(u(rng), u(rng), u(rng)) * sc;
            b = {lo, lo + glm::abs(glm::vec3(u(rng), u(rng), u(rng))) * sc * 0.3f};
        }
        const glm::vec3 p = c + glm::vec3(u(rng), u(rng), u(rng)) * sc * 3.f, n(u(rng), u(rng), u(rng));
        const float mf = it % 3 == 0 ? 0.f : 1e-4f;
        const sk::LinearLightFraction f = sk::linear_light_visible_fraction(p, n, s.end_a, s.end_b, boxes.data(), boxes.size(), mf);
        REQUIRE(f.status == sk::Status::Ok);
        REQUIRE((f.fraction >= 0.f && f.fraction <= 1.f));
        for (const auto& b : boxes) {
            const sk::LinearLightInterval I = sk::linear_light_box_interval(p, s.end_a, s.end_b, b, mf);
            REQUIRE(I.status == sk::Status::Ok);
            REQUIRE((I.empty() || (I.t0 >= 0.f && I.t1 <= 1.f)));
        }
        const sk::LinearLightInterval T = sk::linear_light_tangent_interval(p, n, s.end_a, s.end_b);
        REQUIRE(T.status == sk::Status::Ok);
        // a 6 x 5 skin map of positive finite distances
        std::vector<glm::vec3> pos(30);
        std::vector<float> dist(30);
        for (std::size_t k = 0; k < 30; ++k) {
            pos[k] = c + glm::vec3(u(rng), u(rng), u(rng)) * sc;
            dist[k] = (0.5f + u01(rng)) * sc;
        }
        std::vector<sk::LinearLightSkinVertex> skin(sk::linear_light_skin_capacity(6, 5));
        const auto sr = sk::linear_light_build_skin(pos.data(), dist.data(), 6, 5, 0.05f, skin.data(), skin.size());
        REQUIRE(sr.status == sk::Status::Ok);
        REQUIRE(sr.count == sr.needed);
        // NaN anywhere: NonFinite
        boxes.push_back({{NAN, 0.f, 0.f}, {1.f, 1.f, 1.f}});
        REQUIRE(sk::linear_light_visible_fraction(p, n, s.end_a, s.end_b, boxes.data(), boxes.size(), mf).status ==
                sk::Status::NonFinite);
        dist[std::size_t(it % 30)] = NAN;
        REQUIRE(sk::linear_light_build_skin(pos.data(), dist.data(), 6, 5, 0.05f, skin.data(), skin.size()).status ==
                sk::Status::NonFinite);
        dist[std::size_t(it % 30)] = -1.f;
        REQUIRE(sk::linear_light_build_skin(pos.data(), dist.data(), 6, 5, 0.05f, skin.data(), skin.size()).status ==
                sk::Status::InvalidArgument);
    }
    CHECK(overflow > 0);
    CHECK(sk::linear_light_skin_capacity(0xFFFFFFFFu, 0xFFFFFFFFu) == std::numeric_limits<std::size_t>::max());
}
