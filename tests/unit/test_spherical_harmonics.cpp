// Real spherical harmonics: orthonormality by Gauss-Legendre x uniform-phi quadrature (exact for
// the polynomials involved), the recurrence against the closed-form polynomials of bands 0-4,
// rotation against re-projection of rotated functions, the clamped-cosine convolution against an
// exact hemispherical quadrature, and the stiff inputs.
#include <doctest/doctest.h>

#include <shadowkit/spherical_harmonics.hpp>

#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace sk = shadowkit;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Gauss-Legendre nodes and weights on [-1, 1] (Newton on P_n, independent of the header).
void gauss_legendre(int n, std::vector<double>& x, std::vector<double>& w) {
    x.assign(static_cast<std::size_t>(n), 0.0);
    w.assign(static_cast<std::size_t>(n), 0.0);
    for (int i = 0; i < n; ++i) {
        double z = std::cos(kPi * (i + 0.75) / (n + 0.5));
        double dp = 0.0;
        for (int it = 0; it < 100; ++it) {
            double p0 = 1.0, p1 = z;
            for (int k = 2; k <= n; ++k) {
                const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            if (n == 1) {
                p1 = z;
                p0 = 1.0;
            }
            dp = n * (z * p1 - p0) / (z * z - 1.0);
            const double dz = p1 / dp;
            z -= dz;
            if (std::fabs(dz) < 1e-16) break;
        }
        x[static_cast<std::size_t>(i)] = z;
        w[static_cast<std::size_t>(i)] = 2.0 / ((1.0 - z * z) * dp * dp);
    }
}

// Product quadrature over the sphere: Gauss-Legendre in z = cos(theta), uniform in phi. Exact for
// polynomials in (x, y, z) of degree < min(2 nz, nphi).
struct SphereQuadrature {
    std::vector<glm::dvec3> dirs;
    std::vector<double> weights;
    SphereQuadrature(int nz, int nphi) {
        std::vector<double> x, w;
        gauss_legendre(nz, x, w);
        for (int i = 0; i < nz; ++i)
            for (int j = 0; j < nphi; ++j) {
                const double z = x[static_cast<std::size_t>(i)], r = std::sqrt(1.0 - z * z);
                const double phi = 2.0 * kPi * (j + 0.5) / nphi;
                dirs.emplace_back(r * std::cos(phi), r * std::sin(phi), z);
                weights.push_back(w[static_cast<std::size_t>(i)] * 2.0 * kPi / nphi);
            }
    }
};

std::vector<double> basis(int order, glm::dvec3 d) {
    std::vector<double> y(sk::sh_coefficient_count(order));
    REQUIRE(sk::sh_evaluate(order, d, y.data(), y.size()).status == sk::Status::Ok);
    return y;
}

// Closed-form real SH (no Condon-Shortley phase) for bands 0-4 at a unit direction.
std::vector<double> closed_form(glm::dvec3 d) {
    const double x = d.x, y = d.y, z = d.z, s = std::sqrt(1.0 / kPi);
    return {
        0.5 * s,
        std::sqrt(3.0 / (4.0 * kPi)) * y, std::sqrt(3.0 / (4.0 * kPi)) * z, std::sqrt(3.0 / (4.0 * kPi)) * x,
        0.5 * std::sqrt(15.0 / kPi) * x * y, 0.5 * std::sqrt(15.0 / kPi) * y * z,
        0.25 * std::sqrt(5.0 / kPi) * (3.0 * z * z - 1.0), 0.5 * std::sqrt(15.0 / kPi) * x * z,
        0.25 * std::sqrt(15.0 / kPi) * (x * x - y * y),
        0.25 * std::sqrt(35.0 / (2.0 * kPi)) * y * (3.0 * x * x - y * y), 0.5 * std::sqrt(105.0 / kPi) * x * y * z,
        0.25 * std::sqrt(21.0 / (2.0 * kPi)) * y * (5.0 * z * z - 1.0), 0.25 * std::sqrt(7.0 / kPi) * z * (5.0 * z * z - 3.0),
        0.25 * std::sqrt(21.0 / (2.0 * kPi)) * x * (5.0 * z * z - 1.0), 0.25 * std::sqrt(105.0 / kPi) * z * (x * x - y * y),
        0.25 * std::sqrt(35.0 / (2.0 * kPi)) * x * (x * x - 3.0 * y * y),
        0.75 * std::sqrt(35.0 / kPi) * x * y * (x * x - y * y), 0.75 * std::sqrt(35.0 / (2.0 * kPi)) * y * z * (3.0 * x * x - y * y),
        0.75 * std::sqrt(5.0 / kPi) * x * y * (7.0 * z * z - 1.0), 0.75 * std::sqrt(5.0 / (2.0 * kPi)) * y * z * (7.0 * z * z - 3.0),
        3.0 / 16.0 * s * (35.0 * z * z * z * z - 30.0 * z * z + 3.0),
        0.75 * std::sqrt(5.0 / (2.0 * kPi)) * x * z * (7.0 * z * z - 3.0), 3.0 / 8.0 * std::sqrt(5.0 / kPi) * (x * x - y * y) * (7.0 * z * z - 1.0),
        0.75 * std::sqrt(35.0 / (2.0 * kPi)) * x * z * (x * x - 3.0 * y * y),
        3.0 / 16.0 * std::sqrt(35.0 / kPi) * (x * x * (x * x - 3.0 * y * y) - y * y * (3.0 * x * x - y * y)),
    };
}

glm::dvec3 random_unit(std::mt19937& rng) {
    std::normal_distribution<double> g;
    for (;;) {
        glm::dvec3 v(g(rng), g(rng), g(rng));
        const double l = glm::length(v);
        if (l > 1e-6) return v / l;
    }
}

glm::dmat3 random_rotation(std::mt19937& rng) {
    std::normal_distribution<double> g;
    glm::dquat q(g(rng), g(rng), g(rng), g(rng));
    return glm::mat3_cast(glm::normalize(q));
}

std::vector<double> random_coeffs(std::mt19937& rng, int order) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<double> c(sk::sh_coefficient_count(order));
    for (auto& v : c) v = u(rng);
    return c;
}

double eval(int order, const std::vector<double>& c, glm::dvec3 d) {
    const auto r = sk::sh_reconstruct(order, c.data(), c.size(), d);
    REQUIRE(r.status == sk::Status::Ok);
    return r.value;
}

// Projection by exact quadrature of any function of a direction.
template <class F>
std::vector<double> project_exact(int order, const SphereQuadrature& q, F&& f) {
    std::vector<double> values(q.dirs.size());
    for (std::size_t j = 0; j < q.dirs.size(); ++j) values[j] = f(q.dirs[j]);
    std::vector<double> c(sk::sh_coefficient_count(order));
    REQUIRE(sk::sh_project(order, q.dirs.data(), values.data(), q.weights.data(), q.dirs.size(), c.data(), c.size())
                .status == sk::Status::Ok);
    return c;
}

double max_abs_diff(const std::vector<double>& a, const std::vector<double>& b) {
    double m = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) m = std::max(m, std::fabs(a[i] - b[i]));
    return m;
}

}  // namespace

TEST_CASE("orthonormality of the basis by numerical integration") {
    const SphereQuadrature q(24, 48);  // exact to degree 47 in z, 47 in phi: y_i y_j has degree <= 8
    const int n = 25;
    std::vector<double> gram(n * n, 0.0);
    for (std::size_t j = 0; j < q.dirs.size(); ++j) {
        const auto y = basis(5, q.dirs[j]);
        for (int a = 0; a < n; ++a)
            for (int b = 0; b < n; ++b)
                gram[static_cast<std::size_t>(a * n + b)] +=
                    q.weights[j] * y[static_cast<std::size_t>(a)] * y[static_cast<std::size_t>(b)];
    }
    double err = 0.0;
    for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) err = std::max(err, std::fabs(gram[static_cast<std::size_t>(a * n + b)] - (a == b ? 1.0 : 0.0)));
    MESSAGE("orthonormality: max |G - I| over 25 x 25 = " << err);
    CHECK(err < 1e-6);
    CHECK(err < 1e-13);  // what double precision actually gives

    // float evaluation: same Gram matrix within float rounding
    double errf = 0.0;
    std::vector<double> gramf(n * n, 0.0);
    for (std::size_t j = 0; j < q.dirs.size(); ++j) {
        float y[25];
        REQUIRE(sk::sh_evaluate(5, glm::vec3(q.dirs[j]), y, 25).status == sk::Status::Ok);
        for (int a = 0; a < n; ++a)
            for (int b = 0; b < n; ++b) gramf[static_cast<std::size_t>(a * n + b)] += q.weights[j] * double(y[a]) * double(y[b]);
    }
    for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) errf = std::max(errf, std::fabs(gramf[static_cast<std::size_t>(a * n + b)] - (a == b ? 1.0 : 0.0)));
    MESSAGE("orthonormality (float evaluation): " << errf);
    CHECK(errf < 1e-6);
}

TEST_CASE("recurrence matches the closed-form polynomials of bands 0-4, poles included") {
    std::mt19937 rng(7);
    std::vector<glm::dvec3> dirs = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1e-300}, {1e-12, 0, 1},
                                    {0, -1e-12, -1}, {1, 1, 1}, {-3, 2, 1e-8}};
    for (int i = 0; i < 5000; ++i) dirs.push_back(random_unit(rng));
    double err = 0.0;
    for (auto d : dirs) {
        const glm::dvec3 u = glm::normalize(d / std::max({std::fabs(d.x), std::fabs(d.y), std::fabs(d.z)}));
        const auto y = basis(5, d);
        const auto c = closed_form(u);
        err = std::max(err, max_abs_diff(y, c));
        // every order gives the prefix of the order-5 vector
        for (int o = 1; o <= 5; ++o) {
            const auto yo = basis(o, d);
            for (std::size_t i = 0; i < yo.size(); ++i) REQUIRE(yo[i] == y[i]);
        }
    }
    MESSAGE("recurrence vs closed form: max error " << err);
    CHECK(err < 1e-13);
    // at the north pole only the zonal functions are non-zero: y_l0 = sqrt((2l + 1) / (4 pi))
    const auto yp = basis(5, {0, 0, 1});
    for (int l = 0; l < 5; ++l)
        for (int m = -l; m <= l; ++m)
            CHECK(yp[static_cast<std::size_t>(sk::sh_index(l, m))] ==
                  doctest::Approx(m == 0 ? std::sqrt((2 * l + 1) / (4 * kPi)) : 0.0).epsilon(1e-14));
}

TEST_CASE("projection: exact with exact weights, converges with stratified samples") {
    std::mt19937 rng(11);
    const SphereQuadrature q(12, 24);
    for (int order = 1; order <= 5; ++order) {
        for (int t = 0; t < 20; ++t) {
            const auto c = random_coeffs(rng, order);
            const auto p = project_exact(order, q, [&](glm::dvec3 d) { return eval(order, c, d); });
            CHECK(max_abs_diff(p, c) < 1e-12);
        }
    }
    // stratified jittered directions with uniform weights 4 pi / N
    std::vector<glm::dvec3> dirs(128 * 128);
    REQUIRE(sk::sh_stratified_directions(128, 3u, dirs.data(), dirs.size()).count == dirs.size());
    const auto c = random_coeffs(rng, 5);
    std::vector<double> v(dirs.size());
    for (std::size_t j = 0; j < dirs.size(); ++j) v[j] = eval(5, c, dirs[j]);
    std::vector<double> p(25);
    REQUIRE(sk::sh_project(5, dirs.data(), v.data(), nullptr, dirs.size(), p.data(), p.size()).status == sk::Status::Ok);
    const double err = max_abs_diff(p, c);
    MESSAGE("stratified projection, 16384 samples, order 5: max coefficient error " << err);
    CHECK(err < 5e-3);
    // RGB projection equals three scalar projections
    std::vector<glm::dvec3> rgb(dirs.size());
    for (std::size_t j = 0; j < dirs.size(); ++j) rgb[j] = glm::dvec3(v[j], 2.0 * v[j], -v[j]);
    std::vector<glm::dvec3> prgb(25);
    REQUIRE(sk::sh_project_rgb(5, dirs.data(), rgb.data(), nullptr, dirs.size(), prgb.data(), prgb.size()).status ==
            sk::Status::Ok);
    for (std::size_t i = 0; i < 25; ++i) {
        CHECK(prgb[i].x == doctest::Approx(p[i]).epsilon(1e-12));
        CHECK(prgb[i].y == doctest::Approx(2.0 * p[i]).epsilon(1e-12));
        CHECK(prgb[i].z == doctest::Approx(-p[i]).epsilon(1e-12));
    }
}

TEST_CASE("stratified directions: unit, one per stratum, deterministic") {
    const int s = 32;
    std::vector<glm::vec3> a(static_cast<std::size_t>(s * s)), b(a.size()), c(a.size());
    REQUIRE(sk::sh_stratified_directions(s, 5u, a.data(), a.size()).status == sk::Status::Ok);
    REQUIRE(sk::sh_stratified_directions(s, 5u, b.data(), b.size()).status == sk::Status::Ok);
    REQUIRE(sk::sh_stratified_directions(s, 6u, c.data(), c.size()).status == sk::Status::Ok);
    std::vector<int> cells(a.size(), 0);
    int differ = 0;
    for (std::size_t k = 0; k < a.size(); ++k) {
        CHECK(glm::length(a[k]) == doctest::Approx(1.0f).epsilon(1e-6));
        CHECK(a[k] == b[k]);
        differ += a[k] != c[k];
        const double u = (1.0 - double(a[k].z)) / 2.0;
        double phi = std::atan2(double(a[k].y), double(a[k].x));
        if (phi < 0) phi += 2 * kPi;
        const int i = std::min(s - 1, int(u * s)), j = std::min(s - 1, int(phi / (2 * kPi) * s));
        cells[static_cast<std::size_t>(i * s + j)]++;
    }
    CHECK(differ > int(a.size()) - 4);
    CHECK(*std::min_element(cells.begin(), cells.end()) == 1);
    CHECK(*std::max_element(cells.begin(), cells.end()) == 1);
}

TEST_CASE("rotation matches re-projection of the rotated function (random rotations, orders 1-5)") {
    std::mt19937 rng(2024);
    const SphereQuadrature q(12, 24);  // exact for band-limited products of degree <= 8
    double worst = 0.0;
    for (int order = 1; order <= 5; ++order) {
        for (int t = 0; t < 60; ++t) {
            glm::dmat3 R = random_rotation(rng);
            if (t % 5 == 4) R = -R;  // reflections too
            const auto c = random_coeffs(rng, order);
            std::vector<double> rc(c.size());
            REQUIRE(sk::sh_rotate(order, R, c.data(), c.size(), rc.data(), rc.size()).status == sk::Status::Ok);
            const glm::dmat3 Rt = glm::transpose(R);
            const auto ref = project_exact(order, q, [&](glm::dvec3 d) { return eval(order, c, Rt * d); });
            worst = std::max(worst, max_abs_diff(rc, ref));
        }
    }
    MESSAGE("rotation vs re-projection: max coefficient error " << worst);
    CHECK(worst < 1e-10);

    // a lobe moves where R sends it: y_{1,1} (along x) turned 90 degrees about z is y_{1,-1} (along y)
    const glm::dmat3 Rz(glm::dvec3(0, 1, 0), glm::dvec3(-1, 0, 0), glm::dvec3(0, 0, 1));  // x -> y
    std::vector<double> c(9, 0.0), out(9);
    c[3] = 1.0;
    REQUIRE(sk::sh_rotate(3, Rz, c.data(), 9, out.data(), 9).status == sk::Status::Ok);
    CHECK(out[1] == doctest::Approx(1.0));
    CHECK(out[3] == doctest::Approx(0.0));

    // float path, in place, against the double path
    std::vector<float> f(25);
    const auto cd = random_coeffs(rng, 5);
    for (std::size_t i = 0; i < 25; ++i) f[i] = float(cd[i]);
    const glm::dmat3 R = random_rotation(rng);
    std::vector<double> rd(25);
    REQUIRE(sk::sh_rotate(5, R, cd.data(), 25, rd.data(), 25).status == sk::Status::Ok);
    REQUIRE(sk::sh_rotate(5, glm::mat3(R), f.data(), 25, f.data(), 25).status == sk::Status::Ok);
    for (std::size_t i = 0; i < 25; ++i) CHECK(double(f[i]) == doctest::Approx(rd[i]).epsilon(1e-5).scale(1.0));
}

TEST_CASE("rotation: band matrices are orthogonal, compose, and invert") {
    std::mt19937 rng(99);
    for (int t = 0; t < 200; ++t) {
        const glm::dmat3 A = random_rotation(rng), B = random_rotation(rng);
        const auto c = random_coeffs(rng, 5);
        std::vector<double> ab(25), a_b(25), back(25);
        REQUIRE(sk::sh_rotate(5, A * B, c.data(), 25, ab.data(), 25).status == sk::Status::Ok);
        REQUIRE(sk::sh_rotate(5, B, c.data(), 25, a_b.data(), 25).status == sk::Status::Ok);
        REQUIRE(sk::sh_rotate(5, A, a_b.data(), 25, a_b.data(), 25).status == sk::Status::Ok);
        CHECK(max_abs_diff(ab, a_b) < 1e-12);
        REQUIRE(sk::sh_rotate(5, glm::transpose(A * B), ab.data(), 25, back.data(), 25).status == sk::Status::Ok);
        CHECK(max_abs_diff(back, c) < 1e-12);
        // norm per band is preserved (orthogonal blocks)
        for (int l = 0; l < 5; ++l) {
            double n0 = 0.0, n1 = 0.0;
            for (int m = -l; m <= l; ++m) {
                n0 += c[static_cast<std::size_t>(sk::sh_index(l, m))] * c[static_cast<std::size_t>(sk::sh_index(l, m))];
                n1 += ab[static_cast<std::size_t>(sk::sh_index(l, m))] * ab[static_cast<std::size_t>(sk::sh_index(l, m))];
            }
            CHECK(n1 == doctest::Approx(n0).epsilon(1e-12));
        }
    }
    // identity
    const auto c = random_coeffs(rng, 5);
    std::vector<double> out(25);
    REQUIRE(sk::sh_rotate(5, glm::dmat3(1.0), c.data(), 25, out.data(), 25).status == sk::Status::Ok);
    CHECK(max_abs_diff(out, c) < 1e-15);
}

TEST_CASE("clamped-cosine convolution: closed form and exact hemispherical integration") {
    CHECK(sk::sh_clamped_cosine_band(0) == doctest::Approx(kPi));
    CHECK(sk::sh_clamped_cosine_band(1) == doctest::Approx(2 * kPi / 3));
    CHECK(sk::sh_clamped_cosine_band(2) == doctest::Approx(kPi / 4));
    CHECK(sk::sh_clamped_cosine_band(3) == 0.0);
    CHECK(sk::sh_clamped_cosine_band(4) == doctest::Approx(-kPi / 24));
    CHECK(sk::sh_clamped_cosine_band(5) == 0.0);
    CHECK(sk::sh_clamped_cosine_band(-1) == 0.0);
    // A_l against direct integration of the zonal coefficient: A_l = 2 pi * integral_0^1 z P_l(z) dz
    std::vector<double> gx, gw;
    gauss_legendre(16, gx, gw);
    for (int l = 0; l < 5; ++l) {
        double s = 0.0;
        for (std::size_t i = 0; i < gx.size(); ++i) {
            const double z = 0.5 * (gx[i] + 1.0);  // [0, 1]
            double p0 = 1.0, p1 = z, pl = l == 0 ? 1.0 : z;
            for (int k = 2; k <= l; ++k) {
                pl = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
                p0 = p1;
                p1 = pl;
            }
            s += 0.5 * gw[i] * z * pl;
        }
        CHECK(sk::sh_clamped_cosine_band(l) == doctest::Approx(2 * kPi * s).epsilon(1e-12));
    }
    // E(n) = integral f(s) max(n.s, 0) ds for band-limited f: Gauss-Legendre over the hemisphere
    // around n (cos in [0, 1]) x uniform phi is exact (polynomial integrand of degree <= 5).
    std::mt19937 rng(5);
    double worst = 0.0;
    for (int order = 1; order <= 5; ++order)
        for (int t = 0; t < 100; ++t) {
            const auto c = random_coeffs(rng, order);
            std::vector<double> e(c.size());
            REQUIRE(sk::sh_convolve_clamped_cosine(order, c.data(), c.size(), e.data(), e.size()).status ==
                    sk::Status::Ok);
            const glm::dvec3 n = random_unit(rng);
            const glm::dvec3 a = std::fabs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
            const glm::dvec3 tx = glm::normalize(glm::cross(a, n)), ty = glm::cross(n, tx);
            double ref = 0.0;
            for (std::size_t i = 0; i < gx.size(); ++i) {
                const double ct = 0.5 * (gx[i] + 1.0), st = std::sqrt(1.0 - ct * ct);
                for (int j = 0; j < 32; ++j) {
                    const double phi = 2 * kPi * (j + 0.5) / 32;
                    const glm::dvec3 s = ct * n + st * (std::cos(phi) * tx + std::sin(phi) * ty);
                    ref += 0.5 * gw[i] * (2 * kPi / 32) * ct * eval(order, c, s);
                }
            }
            worst = std::max(worst, std::fabs(eval(order, e, n) - ref));
        }
    MESSAGE("clamped-cosine convolution vs exact hemispherical quadrature: " << worst);
    CHECK(worst < 1e-12);
    // zonal convolution with the clamped cosine's own zonal coefficients gives the same thing
    const auto c = random_coeffs(rng, 5);
    std::vector<double> zonal(5), e1(25), e2(25);
    for (int l = 0; l < 5; ++l) zonal[static_cast<std::size_t>(l)] = std::sqrt((2.0 * l + 1.0) / (4 * kPi)) * sk::sh_clamped_cosine_band(l);
    REQUIRE(sk::sh_convolve_zonal(5, zonal.data(), 5, c.data(), 25, e1.data(), 25).status == sk::Status::Ok);
    REQUIRE(sk::sh_convolve_clamped_cosine(5, c.data(), 25, e2.data(), 25).status == sk::Status::Ok);
    CHECK(max_abs_diff(e1, e2) < 1e-14);
    // dot product = integral of the product
    const auto d = random_coeffs(rng, 5);
    const SphereQuadrature q(12, 24);
    double integral = 0.0;
    for (std::size_t j = 0; j < q.dirs.size(); ++j) integral += q.weights[j] * eval(5, c, q.dirs[j]) * eval(5, d, q.dirs[j]);
    CHECK(sk::sh_dot(5, c.data(), 25, d.data(), 25).value == doctest::Approx(integral).epsilon(1e-12));
}

TEST_CASE("stiff inputs: bad directions, orders, buffers, rotations, samples") {
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    double y[25];
    for (glm::dvec3 d : {glm::dvec3(0.0), glm::dvec3(nan, 0, 1), glm::dvec3(inf, 0, 0), glm::dvec3(0, -inf, inf)}) {
        const auto r = sk::sh_evaluate(5, d, y, 25);
        const sk::Status expect = d == glm::dvec3(0.0) ? sk::Status::InvalidArgument : sk::Status::NonFinite;
        CHECK(r.status == expect);
        for (double v : y) CHECK(v == 0.0);
        CHECK(sk::sh_reconstruct(5, y, 25, d).status == expect);
    }
    // tiny and huge but finite directions are fine
    for (glm::dvec3 d : {glm::dvec3(1e-300, 0, 0), glm::dvec3(1e300, 1e300, 0), glm::dvec3(0, 0, -1e-320)}) {
        REQUIRE(sk::sh_evaluate(5, d, y, 25).status == sk::Status::Ok);
        const glm::dvec3 scaled = d / std::max({std::fabs(d.x), std::fabs(d.y), std::fabs(d.z)});
        const auto c = closed_form(glm::normalize(scaled));
        for (std::size_t i = 0; i < 25; ++i) CHECK(y[i] == doctest::Approx(c[i]).epsilon(1e-12).scale(1.0));
    }
    {
        float yf[25];
        CHECK(sk::sh_evaluate(5, glm::vec3(1e-30f, 0.f, 0.f), yf, 25).status == sk::Status::Ok);
        CHECK(yf[3] == doctest::Approx(std::sqrt(3 / (4 * kPi))));
        CHECK(sk::sh_evaluate(5, glm::vec3(3e38f, 3e38f, 0.f), yf, 25).status == sk::Status::Ok);
    }
    for (int order : {0, -1, 6, 100}) {
        CHECK(sk::sh_evaluate(order, glm::dvec3(0, 0, 1), y, 25).status == sk::Status::InvalidArgument);
        CHECK(sk::sh_coefficient_count(order) == 0);
        CHECK(sk::sh_make_rotation(order, glm::dmat3(1.0)).status == sk::Status::InvalidArgument);
        CHECK(sk::sh_convolve_clamped_cosine(order, y, 25, y, 25).status == sk::Status::InvalidArgument);
        CHECK(sk::sh_reconstruct(order, y, 25, glm::dvec3(0, 0, 1)).status == sk::Status::InvalidArgument);
    }
    // buffers
    auto r = sk::sh_evaluate(4, glm::dvec3(0, 0, 1), y, 15);
    CHECK(r.status == sk::Status::BufferTooSmall);
    CHECK(r.count == 0);
    CHECK(r.needed == 16);
    CHECK(sk::sh_evaluate(4, glm::dvec3(0, 0, 1), static_cast<double*>(nullptr), 16).status == sk::Status::InvalidArgument);
    CHECK(sk::sh_rotate(3, glm::dmat3(1.0), y, 8, y, 9).status == sk::Status::BufferTooSmall);
    // non-orthogonal or non-finite rotations
    CHECK(sk::sh_make_rotation(3, glm::dmat3(2.0)).status == sk::Status::InvalidArgument);
    CHECK(sk::sh_make_rotation(3, glm::dmat3(0.0)).status == sk::Status::InvalidArgument);
    glm::dmat3 bad(1.0);
    bad[1][2] = nan;
    const sk::SHRotation rot = sk::sh_make_rotation(3, bad);
    CHECK(rot.status == sk::Status::NonFinite);
    CHECK(rot.order == 0);
    CHECK(sk::sh_rotate(rot, y, 25, y, 25).status == sk::Status::InvalidArgument);
    CHECK(sk::sh_rotate(sk::SHRotation{}, y, 25, y, 25).status == sk::Status::InvalidArgument);  // never built
    // NaN coefficients
    double c[25] = {};
    c[4] = nan;
    CHECK(sk::sh_rotate(5, glm::dmat3(1.0), c, 25, y, 25).status == sk::Status::NonFinite);
    CHECK(sk::sh_convolve_clamped_cosine(5, c, 25, y, 25).status == sk::Status::NonFinite);
    CHECK(sk::sh_reconstruct(5, c, 25, glm::dvec3(0, 0, 1)).status == sk::Status::NonFinite);
    CHECK(sk::sh_dot(5, c, 25, c, 25).status == sk::Status::NonFinite);
    // projection samples
    std::vector<glm::dvec3> dirs = {{0, 0, 1}, {1, 0, 0}, {0, 0, 0}};
    std::vector<double> vals = {1, 2, 3};
    r = sk::sh_project(3, dirs.data(), vals.data(), nullptr, dirs.size(), y, 25);
    CHECK(r.status == sk::Status::InvalidArgument);  // a zero direction
    for (int i = 0; i < 9; ++i) CHECK(y[i] == 0.0);
    dirs[2] = {0, 1, 0};
    vals[1] = inf;
    CHECK(sk::sh_project(3, dirs.data(), vals.data(), nullptr, dirs.size(), y, 25).status == sk::Status::NonFinite);
    vals[1] = 1e308;
    std::vector<double> w = {1e308, 1e308, 1e308};
    CHECK(sk::sh_project(3, dirs.data(), vals.data(), w.data(), dirs.size(), y, 25).status == sk::Status::Overflow);
    CHECK(sk::sh_project(3, dirs.data(), vals.data(), nullptr, 0, y, 25).status == sk::Status::Ok);
    CHECK(sk::sh_stratified_directions(0, 1u, dirs.data(), dirs.size()).status == sk::Status::InvalidArgument);
    r = sk::sh_stratified_directions(2, 1u, dirs.data(), dirs.size());
    CHECK(r.status == sk::Status::BufferTooSmall);
    CHECK(r.needed == 4);
}

TEST_CASE("clamped-cosine band for large l: finite (was NaN past l = 170), against quadrature") {
    // Regression (issue 19 item 6): l! and ((l/2)!)^2 overflowed double for l >= 172, so
    // sh_clamped_cosine_band(200) was inf / inf = NaN for a documented total function. Reference:
    // A_l = 2 pi integral_0^1 z P_l(z) dz by 160-node Gauss-Legendre (exact to degree 319), Legendre
    // polynomials by the three-term recurrence (independent of the header).
    std::vector<double> gx, gw;
    gauss_legendre(160, gx, gw);
    for (int l : {2, 4, 30, 62, 64, 66, 100, 170, 172, 200, 250}) {
        double s = 0.0;
        for (std::size_t i = 0; i < gx.size(); ++i) {
            const double z = 0.5 * (gx[i] + 1.0);
            double p0 = 1.0, p1 = z;
            for (int k = 2; k <= l; ++k) {
                const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            s += 0.5 * gw[i] * z * (l == 0 ? 1.0 : p1);
        }
        const double a = sk::sh_clamped_cosine_band(l);
        REQUIRE(std::isfinite(a));
        CHECK(a == doctest::Approx(2 * kPi * s).epsilon(1e-8).scale(1e-12));
    }
    for (int l : {1001, 1000000, std::numeric_limits<int>::max() - 1, std::numeric_limits<int>::max()}) {
        const double a = sk::sh_clamped_cosine_band(l);
        CHECK(std::isfinite(a));
        CHECK(std::fabs(a) <= kPi / 24);
    }
}

TEST_CASE("property: finite coefficients and directions give Ok and finite output, or Overflow (6,000 configurations)") {
    std::mt19937 rng(77);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    const float scales[7] = {1e-30f, 1e-6f, 1.f, 1e6f, 1e30f, 1e37f, 3e38f};
    int overflow = 0, ok = 0;
    for (int it = 0; it < 6000; ++it) {
        const int order = 1 + it % 5;
        const std::size_t n = sk::sh_coefficient_count(order);
        const float cs = scales[it % 7], ds = scales[(it / 7) % 5];
        float c[25], d[25], out[25];
        for (std::size_t i = 0; i < n; ++i) {
            c[i] = u(rng) * cs;
            d[i] = u(rng);
        }
        glm::vec3 dir(u(rng) * ds, u(rng) * ds, u(rng) * ds);
        if (dir == glm::vec3(0.f)) dir.z = ds;
        auto check_result = [&](sk::Status s, const float* v, std::size_t count) {
            REQUIRE((s == sk::Status::Ok || s == sk::Status::Overflow));
            if (s == sk::Status::Overflow) {
                ++overflow;
                return;
            }
            ++ok;
            for (std::size_t i = 0; i < count; ++i) REQUIRE(std::isfinite(v[i]));
        };
        const auto e = sk::sh_evaluate(order, dir, out, 25);
        REQUIRE(e.status == sk::Status::Ok);
        check_result(e.status, out, n);
        const auto rv = sk::sh_reconstruct(order, c, 25, dir);
        check_result(rv.status, &rv.value, 1);
        // a random rotation (and reflection every other time)
        const glm::quat q = glm::normalize(glm::quat(u(rng), u(rng), u(rng), u(rng) + 1e-3f));
        glm::mat3 R = glm::mat3_cast(q);
        if (it % 2) R[0] = -R[0];
        const sk::SHRotation rot = sk::sh_make_rotation(order, R);
        REQUIRE(rot.status == sk::Status::Ok);
        const auto rr = sk::sh_rotate(rot, c, 25, out, 25);
        check_result(rr.status, out, rr.count);
        const auto cv = sk::sh_convolve_clamped_cosine(order, c, 25, out, 25);
        check_result(cv.status, out, cv.count);
        const auto zv = sk::sh_convolve_zonal(order, d, 25, c, 25, out, 25);
        check_result(zv.status, out, zv.count);
        const auto dv = sk::sh_dot(order, c, 25, d, 25);
        check_result(dv.status, &dv.value, 1);
        // projection of finite samples
        glm::vec3 dirs[16];
        float vals[16], w[16];
        REQUIRE(sk::sh_stratified_directions(4, std::uint32_t(it), dirs, 16).status == sk::Status::Ok);
        for (int j = 0; j < 16; ++j) {
            vals[j] = u(rng) * cs;
            w[j] = std::fabs(u(rng)) * ds;
        }
        const auto pr = sk::sh_project(order, dirs, vals, it % 3 ? w : nullptr, 16, out, 25);
        check_result(pr.status, out, pr.count);
        // NaN in any input: NonFinite
        c[n - 1] = std::numeric_limits<float>::quiet_NaN();
        REQUIRE(sk::sh_reconstruct(order, c, 25, dir).status == sk::Status::NonFinite);
        REQUIRE(sk::sh_rotate(rot, c, 25, out, 25).status == sk::Status::NonFinite);
        REQUIRE(sk::sh_dot(order, c, 25, d, 25).status == sk::Status::NonFinite);
        vals[it % 16] = std::numeric_limits<float>::infinity();
        REQUIRE(sk::sh_project(order, dirs, vals, nullptr, 16, out, 25).status == sk::Status::NonFinite);
    }
    CHECK(overflow > 0);
    CHECK(ok > 10000);
}
