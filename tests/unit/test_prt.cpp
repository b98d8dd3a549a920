// Precomputed radiance transfer: the unshadowed transfer of a plane against the clamped-cosine
// convolution (exact), shadowed transfer against brute-force integration of environment x
// visibility x cosine for a sphere over a plane (analytic visibility), error decreasing with the
// order, and the stiff inputs. spherical_harmonics.hpp is the independent SH reference here.
#include <doctest/doctest.h>

#include <shadowkit/prt.hpp>
#include <shadowkit/spherical_harmonics.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace sk = shadowkit;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A sphere (center c, radius r) floating over the plane z = 0.
struct SphereOverPlane {
    glm::dvec3 c;
    double r;
    // True when the ray o + t d (t > 0) hits neither the sphere nor the plane.
    bool visible(glm::dvec3 o, glm::dvec3 d) const {
        if (d.z < 0.0 && o.z > 0.0) return false;  // the plane below
        const glm::dvec3 oc = o - c;
        const double b = glm::dot(oc, d), cc = glm::dot(oc, oc) - r * r;
        const double disc = b * b - cc;
        if (cc < 0.0) return false;  // origin inside the sphere
        if (disc < 0.0) return true;
        return !(-b - std::sqrt(disc) > 0.0);  // near root ahead: a hit
    }
};

// Brute force: integral over the hemisphere of n of L(s) V(s) max(n.s, 0) ds by the midpoint rule
// in (cos theta, phi) of the local frame (d omega = d cos theta d phi).
template <class L, class V>
double brute_force(glm::dvec3 n, L&& radiance, V&& vis, int nt = 192, int np = 384) {
    const glm::dvec3 a = std::fabs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    const glm::dvec3 tx = glm::normalize(glm::cross(a, n)), ty = glm::cross(n, tx);
    double s = 0.0;
    for (int i = 0; i < nt; ++i) {
        const double ct = (i + 0.5) / nt, st = std::sqrt(1.0 - ct * ct);
        for (int j = 0; j < np; ++j) {
            const double phi = 2 * kPi * (j + 0.5) / np;
            const glm::dvec3 d = ct * n + st * (std::cos(phi) * tx + std::sin(phi) * ty);
            if (vis(d)) s += ct * radiance(d);
        }
    }
    return s * (1.0 / nt) * (2 * kPi / np);
}

double eval_sh(int order, const std::vector<double>& c, glm::dvec3 d) {
    return sk::sh_reconstruct(order, c.data(), c.size(), d).value;
}

// Sky + sun environment (not band-limited): a bright lobe of sharpness k around `sun`.
struct SkySun {
    glm::dvec3 sun;
    double k;
    double operator()(glm::dvec3 s) const { return 0.4 + 0.25 * s.z + 4.0 * std::exp(k * (glm::dot(s, sun) - 1.0)); }
};

}  // namespace

TEST_CASE("the PRT basis is the spherical_harmonics.hpp basis") {
    sk::PrtSamples s;
    s = sk::prt_make_samples(5, 16, 9u);
    REQUIRE(s.status == sk::Status::Ok);
    REQUIRE(s.count() == 256);
    CHECK(s.weight == doctest::Approx(4 * kPi / 256));
    for (std::size_t j = 0; j < s.count(); ++j) {
        float y[25];
        REQUIRE(sk::sh_evaluate(5, s.directions[j], y, 25).status == sk::Status::Ok);
        for (std::size_t i = 0; i < 25; ++i) CHECK(s.basis[j * 25 + i] == y[i]);
        float p[25];
        REQUIRE(sk::prt_sh_basis(5, s.directions[j], p, 25).status == sk::Status::Ok);
        for (std::size_t i = 0; i < 25; ++i) CHECK(p[i] == y[i]);
    }
    // same stratification as sh_stratified_directions for the same seed
    std::vector<glm::vec3> d(256);
    REQUIRE(sk::sh_stratified_directions(16, 9u, d.data(), d.size()).status == sk::Status::Ok);
    for (std::size_t j = 0; j < d.size(); ++j) CHECK(glm::length(d[j] - s.directions[j]) < 1e-6f);
}

TEST_CASE("unshadowed transfer of a plane reproduces the clamped-cosine convolution exactly") {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    sk::PrtSamples samples;
    samples = sk::prt_make_samples(5, 8, 1u);
    REQUIRE(samples.status == sk::Status::Ok);
    double worst = 0.0, worst_visible = 0.0;
    for (int t = 0; t < 200; ++t) {
        const glm::dvec3 n = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)));
        // vertices of a plane with normal n (positions irrelevant without shadows)
        std::vector<glm::vec3> pos(16), nrm(16, glm::vec3(n));
        for (auto& p : pos) p = glm::vec3(float(u(rng)), float(u(rng)), float(u(rng)));
        for (int order = 1; order <= 5; ++order) {
            sk::PrtSamples so;
            so = sk::prt_make_samples(order, 8, 1u);
            REQUIRE(so.status == sk::Status::Ok);
            const std::size_t n2 = sk::prt_coefficient_count(order);
            std::vector<float> T(16 * n2), Tv(16 * n2);
            sk::PrtTransferOptions opt;
            opt.mode = sk::PrtMode::Unshadowed;
            opt.albedo = 0.7f;
            auto r = sk::prt_compute_transfer(so, opt, pos.data(), nrm.data(), 16,
                                              [](const glm::vec3&, const glm::vec3&) { return false; }, T.data(), T.size());
            REQUIRE(r.status == sk::Status::Ok);
            CHECK(r.rays == 0);
            // shadowed mode with nothing in the way gives the same vectors, bit for bit
            opt.mode = sk::PrtMode::Shadowed;
            r = sk::prt_compute_transfer(so, opt, pos.data(), nrm.data(), 16,
                                         [](const glm::vec3&, const glm::vec3&) { return true; }, Tv.data(), Tv.size());
            REQUIRE(r.status == sk::Status::Ok);
            CHECK(r.rays > 0);
            // random environment; exit radiance = rho / pi * E(n), E from sh_convolve_clamped_cosine
            std::vector<double> L(n2), E(n2);
            for (auto& c : L) c = u(rng);
            REQUIRE(sk::sh_convolve_clamped_cosine(order, L.data(), n2, E.data(), n2).status == sk::Status::Ok);
            const double expect = 0.7 / kPi * eval_sh(order, E, n);
            for (int v = 0; v < 16; ++v) {
                double got = 0.0, got_v = 0.0;
                for (std::size_t i = 0; i < n2; ++i) {
                    got += double(T[std::size_t(v) * n2 + i]) * L[i];
                    got_v += double(Tv[std::size_t(v) * n2 + i]) * L[i];
                }
                worst = std::max(worst, std::fabs(got - expect));
                worst_visible = std::max(worst_visible, std::fabs(got_v - expect));
            }
        }
    }
    MESSAGE("unshadowed plane vs clamped-cosine convolution: max |difference| " << worst);
    CHECK(worst < 2e-6);  // float storage of the transfer vector
    CHECK(worst_visible == worst);
}

TEST_CASE("shadowed transfer against brute-force integration: sphere over a plane") {
    std::mt19937 rng(12345);
    std::uniform_real_distribution<double> u01(0.0, 1.0), u(-1.0, 1.0);
    sk::PrtSamples samples;
    samples = sk::prt_make_samples(5, 64, 77u);
    REQUIRE(samples.status == sk::Status::Ok);
    double worst_rel = 0.0, sum_err = 0.0, sum_abs = 0.0;
    int points = 0;
    for (int config = 0; config < 12; ++config) {
        SphereOverPlane scene;
        scene.r = 0.3 + 0.7 * u01(rng);
        scene.c = glm::dvec3(u(rng), u(rng), scene.r + 0.02 + 1.5 * u01(rng));
        // band-limited random environment of order 5 (so its SH projection is exact)
        std::vector<double> Ld(25);
        Ld[0] = 2.0 + u01(rng);
        for (std::size_t i = 1; i < 25; ++i) Ld[i] = 0.4 * u(rng);
        std::vector<float> Lf(Ld.begin(), Ld.end());
        auto radiance = [&](glm::dvec3 d) { return eval_sh(5, Ld, d); };
        // receivers: floor points around the sphere's foot, and points on the sphere
        std::vector<glm::vec3> pos, nrm;
        for (int k = 0; k < 3; ++k) {
            const double a = 2 * kPi * u01(rng), rad = 2.0 * scene.r * u01(rng);
            pos.emplace_back(float(scene.c.x + rad * std::cos(a)), float(scene.c.y + rad * std::sin(a)), 0.0f);
            nrm.emplace_back(0.0f, 0.0f, 1.0f);
        }
        {
            glm::dvec3 d(u(rng), u(rng), -0.5 - 0.5 * u01(rng));  // lower half: faces the floor
            d = glm::normalize(d);
            pos.emplace_back(scene.c + (scene.r + 1e-4) * d);
            nrm.emplace_back(d);
        }
        std::vector<float> T(pos.size() * 25);
        sk::PrtTransferOptions opt;
        auto r = sk::prt_compute_transfer(
            samples, opt, pos.data(), nrm.data(), pos.size(),
            [&](const glm::vec3& o, const glm::vec3& d) { return scene.visible(glm::dvec3(o), glm::dvec3(d)); }, T.data(),
            T.size());
        REQUIRE(r.status == sk::Status::Ok);
        for (std::size_t v = 0; v < pos.size(); ++v) {
            const glm::dvec3 p(pos[v]), n(nrm[v]);
            const double prt = sk::prt_shade(5, &T[v * 25], Lf.data()).value;
            const double ref = brute_force(n, radiance, [&](glm::dvec3 d) { return scene.visible(p, d); }) / kPi;
            const double unshadowed = brute_force(n, radiance, [](glm::dvec3) { return true; }) / kPi;
            const double rel = std::fabs(prt - ref) / unshadowed;
            worst_rel = std::max(worst_rel, rel);
            sum_err += prt - ref;
            sum_abs += std::fabs(prt - ref) / unshadowed;
            ++points;
        }
    }
    MESSAGE("PRT (order 5, 4096 samples) vs brute force, " << points << " points: max error " << worst_rel
                                                           << " of the unshadowed radiance, mean " << sum_abs / points);
    CHECK(worst_rel < 0.01);
    CHECK(sum_abs / points < 0.004);
}

TEST_CASE("error against the reference decreases with the order (sky + sun, sphere over plane)") {
    const SphereOverPlane scene{{0.0, 0.0, 1.2}, 0.8};
    const SkySun sky{glm::normalize(glm::dvec3(0.5, 0.2, 1.0)), 6.0};
    sk::PrtSamples samples;
    samples = sk::prt_make_samples(5, 64, 5u);
    REQUIRE(samples.status == sk::Status::Ok);
    std::vector<glm::vec3> env(25);
    REQUIRE(sk::prt_project_environment(samples, [&](const glm::vec3& s) { return glm::vec3(float(sky(glm::dvec3(s)))); },
                                        env.data(), env.size())
                .status == sk::Status::Ok);
    // floor points on a line through the shadow, and points on the sphere's lower half
    std::vector<glm::vec3> pos, nrm;
    for (int i = 0; i < 24; ++i) {
        pos.emplace_back(-2.5f + 0.2f * float(i), 0.3f, 0.0f);
        nrm.emplace_back(0.f, 0.f, 1.f);
    }
    for (int i = 0; i < 8; ++i) {
        const double a = 2 * kPi * i / 8;
        const glm::dvec3 d = glm::normalize(glm::dvec3(std::cos(a), std::sin(a), -0.6));
        pos.emplace_back(scene.c + (scene.r + 1e-4) * d);
        nrm.emplace_back(d);
    }
    std::vector<float> T(pos.size() * 25);
    sk::PrtTransferOptions opt;
    REQUIRE(sk::prt_compute_transfer(
                samples, opt, pos.data(), nrm.data(), pos.size(),
                [&](const glm::vec3& o, const glm::vec3& d) { return scene.visible(glm::dvec3(o), glm::dvec3(d)); },
                T.data(), T.size())
                .status == sk::Status::Ok);
    std::vector<double> ref(pos.size());
    double mean_ref = 0.0;
    for (std::size_t v = 0; v < pos.size(); ++v) {
        const glm::dvec3 p(pos[v]);
        ref[v] = brute_force(glm::dvec3(nrm[v]), sky, [&](glm::dvec3 d) { return scene.visible(p, d); }) / kPi;
        mean_ref += ref[v] / double(pos.size());
    }
    double prev = 1e30;
    for (int order = 1; order <= 5; ++order) {
        // a transfer at order 5 truncated to k^2 entries is the order-k transfer (bit for bit)
        sk::PrtSamples sk_samples;
        sk_samples = sk::prt_make_samples(order, 64, 5u);
        REQUIRE(sk_samples.status == sk::Status::Ok);
        const std::size_t n2 = sk::prt_coefficient_count(order);
        std::vector<float> Tk(pos.size() * n2);
        REQUIRE(sk::prt_compute_transfer(
                    sk_samples, opt, pos.data(), nrm.data(), pos.size(),
                    [&](const glm::vec3& o, const glm::vec3& d) { return scene.visible(glm::dvec3(o), glm::dvec3(d)); },
                    Tk.data(), Tk.size())
                    .status == sk::Status::Ok);
        for (std::size_t v = 0; v < pos.size(); ++v)
            for (std::size_t i = 0; i < n2; ++i) REQUIRE(Tk[v * n2 + i] == T[v * 25 + i]);
        std::vector<glm::vec3> shaded(pos.size());
        REQUIRE(sk::prt_shade_mesh(order, T.data(), 25, pos.size(), env.data(), shaded.data(), shaded.size()).status ==
                sk::Status::Ok);
        double se = 0.0;
        for (std::size_t v = 0; v < pos.size(); ++v) se += (double(shaded[v].x) - ref[v]) * (double(shaded[v].x) - ref[v]);
        const double rms = std::sqrt(se / double(pos.size())) / mean_ref;
        MESSAGE("order " << order << ": RMS error / mean radiance = " << rms);
        CHECK(rms < prev);
        prev = rms;
    }
    CHECK(prev < 0.05);
}

TEST_CASE("function-pointer callback, determinism, progress") {
    struct Ctx {
        SphereOverPlane s;
        int calls = 0;
    } ctx{{{0.2, 0.1, 1.0}, 0.5}, 0};
    auto fn = [](void* user, const glm::vec3& o, const glm::vec3& d) {
        auto* c = static_cast<Ctx*>(user);
        ++c->calls;
        return c->s.visible(glm::dvec3(o), glm::dvec3(d));
    };
    sk::PrtSamples samples;
    samples = sk::prt_make_samples(3, 16, 2u);
    REQUIRE(samples.status == sk::Status::Ok);
    std::vector<glm::vec3> pos = {{0, 0, 0}, {0.5f, 0, 0}}, nrm = {{0, 0, 1}, {0, 0, 1}};
    std::vector<float> a(18), b(18);
    std::size_t last = 0;
    sk::PrtTransferOptions opt;
    opt.progress = [](void* user, std::size_t done, std::size_t total) {
        *static_cast<std::size_t*>(user) = done;
        CHECK(done <= total);
    };
    opt.progress_user = &last;
    auto r = sk::prt_compute_transfer(samples, opt, pos.data(), nrm.data(), 2, +fn, &ctx, a.data(), a.size());
    REQUIRE(r.status == sk::Status::Ok);
    CHECK(last == 2);
    CHECK(std::uint64_t(ctx.calls) == r.rays);
    r = sk::prt_compute_transfer(
        samples, opt, pos.data(), nrm.data(), 2,
        [&](const glm::vec3& o, const glm::vec3& d) { return ctx.s.visible(glm::dvec3(o), glm::dvec3(d)); }, b.data(),
        b.size());
    CHECK(a == b);
    // the floor point under the sphere is darker than without shadows
    std::vector<float> un(18);
    opt.mode = sk::PrtMode::Unshadowed;
    REQUIRE(sk::prt_compute_transfer(samples, opt, pos.data(), nrm.data(), 2, +fn, &ctx, un.data(), un.size()).status ==
            sk::Status::Ok);
    CHECK(a[0] < un[0]);
}

TEST_CASE("stiff inputs: bad normals, orders, buffers, callbacks, environments") {
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    sk::PrtSamples s;
    for (int order : {0, -3, 6, 1000}) {
        s = sk::prt_make_samples(order, 4, 1u);
        CHECK(s.status == sk::Status::InvalidArgument);
        CHECK(s.count() == 0);
        CHECK(sk::prt_coefficient_count(order) == 0);
        float y[25];
        CHECK(sk::prt_sh_basis(order, glm::vec3(0, 0, 1), y, 25).status == sk::Status::InvalidArgument);
        CHECK(sk::prt_shade(order, y, y).status == sk::Status::InvalidArgument);
    }
    CHECK(sk::prt_make_samples(3, 0, 1u).status == sk::Status::InvalidArgument);
    CHECK(sk::prt_make_samples(3, 1025, 1u).status == sk::Status::InvalidArgument);
    auto always = [](const glm::vec3&, const glm::vec3&) { return true; };
    // a sample set that no call filled (NotRun)
    std::vector<glm::vec3> pos = {{0, 0, 0}, {0.5f, 0, 0}, {1, 1, 1}, {2, 0, 0}, {0, 3, 0}},
                           nrm = {{0, 0, 1}, {0, 0, 1}, {0, 0, 0}, {1e-30f, 0, 0}, {0, 1, 0}};
    std::vector<float> T(5 * 9, 123.0f);
    CHECK(sk::prt_compute_transfer(s, {}, pos.data(), nrm.data(), 5, always, T.data(), T.size()).status ==
          sk::Status::InvalidArgument);
    s = sk::prt_make_samples(3, 8, 1u);
    REQUIRE(s.status == sk::Status::Ok);
    // a zero normal is a degenerate vertex (zero transfer, Ok); a tiny one is a direction
    auto r = sk::prt_compute_transfer(s, {}, pos.data(), nrm.data(), 5, always, T.data(), T.size());
    CHECK(r.status == sk::Status::Ok);
    CHECK(r.degenerate_vertices == 1);
    CHECK(r.count == 45);
    for (std::size_t i = 0; i < 9; ++i) CHECK(T[2 * 9 + i] == 0.0f);
    for (float t : T) CHECK(std::isfinite(t));
    // NaN / Inf normals or positions: NonFinite (they were zero-transfer "degenerate" vertices, Ok)
    pos[1].x = nan;
    CHECK(sk::prt_compute_transfer(s, {}, pos.data(), nrm.data(), 5, always, T.data(), T.size()).status ==
          sk::Status::NonFinite);
    pos[1].x = 0.5f;
    nrm[3].y = inf;
    CHECK(sk::prt_compute_transfer(s, {}, pos.data(), nrm.data(), 5, always, T.data(), T.size()).status ==
          sk::Status::NonFinite);
    nrm[3].y = 0.0f;
    // unshadowed: positions ignored (may be null)
    sk::PrtTransferOptions un;
    un.mode = sk::PrtMode::Unshadowed;
    r = sk::prt_compute_transfer(s, un, nullptr, nrm.data(), 5, always, T.data(), T.size());
    CHECK(r.status == sk::Status::Ok);
    CHECK(r.degenerate_vertices == 1);
    // buffers, pointers
    r = sk::prt_compute_transfer(s, {}, pos.data(), nrm.data(), 5, always, T.data(), 44);
    CHECK(r.status == sk::Status::BufferTooSmall);
    CHECK(r.needed == 45);
    CHECK(r.count == 0);
    CHECK(sk::prt_compute_transfer(s, {}, nullptr, nrm.data(), 5, always, T.data(), T.size()).status ==
          sk::Status::InvalidArgument);
    CHECK(sk::prt_compute_transfer(s, {}, pos.data(), nrm.data(), 5, sk::PrtVisibilityFn(nullptr), nullptr, T.data(),
                                   T.size())
              .status == sk::Status::InvalidArgument);
    CHECK(sk::prt_compute_transfer(s, {}, pos.data(), nrm.data(), 0, always, nullptr, 0).status == sk::Status::Ok);
    CHECK(sk::prt_compute_transfer(s, {}, pos.data(), nrm.data(), std::size_t(-1) / 4, always, T.data(), T.size()).status ==
          sk::Status::InvalidArgument);
    sk::PrtTransferOptions bad;
    bad.albedo = nan;
    CHECK(sk::prt_compute_transfer(s, bad, pos.data(), nrm.data(), 5, always, T.data(), T.size()).status ==
          sk::Status::NonFinite);
    bad.albedo = 2e30f;
    CHECK(sk::prt_compute_transfer(s, bad, pos.data(), nrm.data(), 5, always, T.data(), T.size()).status ==
          sk::Status::InvalidArgument);
    bad.albedo = 1.0f;
    bad.ray_offset = inf;
    CHECK(sk::prt_compute_transfer(s, bad, pos.data(), nrm.data(), 5, always, T.data(), T.size()).status ==
          sk::Status::NonFinite);
    bad.ray_offset = -1e-3f;  // negative offset: was accepted (rays started inside the surface)
    CHECK(sk::prt_compute_transfer(s, bad, pos.data(), nrm.data(), 5, always, T.data(), T.size()).status ==
          sk::Status::InvalidArgument);
    bad.ray_offset = 3e38f;  // the ray origin 3e38 + 3e38 along +x overflows
    pos[3].x = 3e38f;
    CHECK(sk::prt_compute_transfer(s, bad, pos.data(), nrm.data(), 5, always, T.data(), T.size()).status ==
          sk::Status::Overflow);
    pos[3].x = 2.0f;
    bad.ray_offset = 0.0f;
    bad.mode = static_cast<sk::PrtMode>(9);
    CHECK(sk::prt_compute_transfer(s, bad, pos.data(), nrm.data(), 5, always, T.data(), T.size()).status ==
          sk::Status::InvalidArgument);
    // environment projection
    glm::vec3 env[9];
    CHECK(sk::prt_project_environment(s, [&](const glm::vec3&) { return glm::vec3(nan); }, env, 9).status ==
          sk::Status::NonFinite);
    for (auto e : env) CHECK(e == glm::vec3(0.0f));
    CHECK(sk::prt_project_environment(s, [&](const glm::vec3&) { return glm::vec3(3e38f); }, env, 9).status ==
          sk::Status::Overflow);
    auto pr = sk::prt_project_environment(s, [&](const glm::vec3&) { return glm::vec3(1.0f); }, env, 8);
    CHECK(pr.status == sk::Status::BufferTooSmall);
    CHECK(pr.needed == 9);
    REQUIRE(sk::prt_project_environment(s, [&](const glm::vec3&) { return glm::vec3(1.0f); }, env, 9).status ==
            sk::Status::Ok);
    CHECK(env[0].x == doctest::Approx(std::sqrt(4 * kPi)).epsilon(1e-5));  // constant 1: L_00 = sqrt(4 pi)
    // shading a mesh
    glm::vec3 out[5];
    CHECK(sk::prt_shade_mesh(3, T.data(), 8, 5, env, out, 5).status == sk::Status::InvalidArgument);
    CHECK(sk::prt_shade_mesh(3, T.data(), 9, 5, env, out, 4).status == sk::Status::BufferTooSmall);
    CHECK(sk::prt_shade_mesh(3, T.data(), 9, 5, env, out, 5).status == sk::Status::Ok);
    CHECK(sk::prt_shade_mesh(3, T.data(), 9, 5, env, nullptr, 5).status == sk::Status::InvalidArgument);
    T[20] = nan;  // a NaN transfer: NonFinite (was NaN for that vertex with Ok)
    CHECK(sk::prt_shade_mesh(3, T.data(), 9, 5, env, out, 5).status == sk::Status::NonFinite);
    T[20] = 0.0f;
    env[2].y = inf;
    CHECK(sk::prt_shade_mesh(3, T.data(), 9, 5, env, out, 5).status == sk::Status::NonFinite);
    float y[9];
    CHECK(sk::prt_sh_basis(3, glm::vec3(0.0f), y, 9).status == sk::Status::InvalidArgument);
    CHECK(sk::prt_sh_basis(3, glm::vec3(nan, 0.0f, 1.0f), y, 9).status == sk::Status::NonFinite);
    CHECK(sk::prt_sh_basis(3, glm::vec3(0, 0, 1), y, 8).status == sk::Status::BufferTooSmall);
}

TEST_CASE("clustered PCA: exact limits, synthetic low-rank clusters, shading, stiff inputs") {
    std::mt19937 rng(8);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    // 6 well-separated clusters, each mean + 2 random directions (rank 2): CPCA(6, 2) is exact
    const int order = 4;
    const std::size_t n = 16, per = 200, K = 6;
    std::vector<float> T;
    for (std::size_t k = 0; k < K; ++k) {
        std::vector<double> mean(n), d1(n), d2(n);
        for (std::size_t i = 0; i < n; ++i) {
            mean[i] = 10.0 * u(rng);
            d1[i] = u(rng);
            d2[i] = u(rng);
        }
        for (std::size_t p = 0; p < per; ++p) {
            const double a = u(rng), b = u(rng);
            for (std::size_t i = 0; i < n; ++i) T.push_back(float(mean[i] + a * d1[i] + b * d2[i]));
        }
    }
    const std::size_t V = K * per;
    sk::PrtCpcaOptions opt;
    opt.clusters = K;
    opt.components = 2;
    sk::PrtCpca cp;
    cp = sk::prt_cpca_compress(order, T.data(), n, V, opt);
    REQUIRE(cp.status == sk::Status::Ok);
    MESSAGE("CPCA on rank-2 clusters: RMS reconstruction error " << cp.rms_error);
    CHECK(cp.rms_error < 1e-4);
    for (std::size_t v = 0; v < V; ++v) CHECK(cp.cluster_of[v] == cp.cluster_of[(v / per) * per]);
    // fewer components: larger error, monotone
    double prev = cp.rms_error;
    for (int c : {1, 0}) {
        opt.components = c;
        sk::PrtCpca cc;
        cc = sk::prt_cpca_compress(order, T.data(), n, V, opt);
        REQUIRE(cc.status == sk::Status::Ok);
        CHECK(cc.rms_error > prev);
        prev = cc.rms_error;
    }
    // all components: exact for any data; one cluster per vertex: exact with no components
    std::vector<float> R(300 * 25);
    for (auto& x : R) x = float(u(rng));
    sk::PrtCpcaOptions full;
    full.clusters = 3;
    full.components = 25;
    sk::PrtCpca cf;
    cf = sk::prt_cpca_compress(5, R.data(), 25, 300, full);
    REQUIRE(cf.status == sk::Status::Ok);
    CHECK(cf.rms_error < 1e-5);
    full.clusters = 1000;  // clamped to the vertex count
    full.components = 0;
    cf = sk::prt_cpca_compress(5, R.data(), 25, 300, full);
    REQUIRE(cf.status == sk::Status::Ok);
    CHECK(cf.clusters == 300);
    CHECK(cf.rms_error < 1e-6);
    // shading from per-cluster projections = shading the reconstructed vector
    opt.components = 2;
    cp = sk::prt_cpca_compress(order, T.data(), n, V, opt);
    REQUIRE(cp.status == sk::Status::Ok);
    std::vector<glm::vec3> env(16);
    for (auto& e : env) e = glm::vec3(float(u(rng)), float(u(rng)), float(u(rng)));
    std::vector<glm::vec3> proj(cp.clusters * 3);
    REQUIRE(sk::prt_cpca_project_environment(cp, env.data(), env.size(), proj.data(), proj.size()).status ==
            sk::Status::Ok);
    // the batch form gives the per-vertex results bit for bit; a short buffer is BufferTooSmall
    std::vector<glm::vec3> all(V);
    REQUIRE(sk::prt_cpca_shade_mesh(cp, proj.data(), all.data(), all.size()).status == sk::Status::Ok);
    for (std::size_t v = 0; v < V; ++v) REQUIRE(all[v] == sk::prt_cpca_shade(cp, proj.data(), v).value);
    CHECK(sk::prt_cpca_shade_mesh(cp, proj.data(), all.data(), V - 1).status == sk::Status::BufferTooSmall);
    CHECK(sk::prt_cpca_shade_mesh(sk::PrtCpca{}, proj.data(), all.data(), V).status == sk::Status::InvalidArgument);
    for (std::size_t v = 0; v < V; v += 7) {
        float rec[16];
        REQUIRE(sk::prt_cpca_reconstruct(cp, v, rec, 16).status == sk::Status::Ok);
        const glm::vec3 a = sk::prt_cpca_shade(cp, proj.data(), v).value, b = sk::prt_shade_rgb(order, rec, env.data()).value;
        const glm::vec3 exact = sk::prt_shade_rgb(order, &T[v * n], env.data()).value;
        CHECK(glm::length(a - b) < 1e-3f * (1.f + glm::length(b)));
        CHECK(glm::length(a - exact) < 1e-3f * (1.f + glm::length(exact)));
    }
    // stiff inputs
    sk::PrtCpca bad;
    CHECK((bad = sk::prt_cpca_compress(0, T.data(), n, V, opt)).status == sk::Status::InvalidArgument);
    CHECK((bad = sk::prt_cpca_compress(6, T.data(), n, V, opt)).status == sk::Status::InvalidArgument);
    CHECK((bad = sk::prt_cpca_compress(order, T.data(), 15, V, opt)).status == sk::Status::InvalidArgument);
    CHECK((bad = sk::prt_cpca_compress(order, T.data(), n, 0, opt)).status == sk::Status::InvalidArgument);
    CHECK((bad = sk::prt_cpca_compress(order, nullptr, n, V, opt)).status == sk::Status::InvalidArgument);
    sk::PrtCpcaOptions o2 = opt;
    o2.clusters = 0;
    CHECK((bad = sk::prt_cpca_compress(order, T.data(), n, V, o2)).status == sk::Status::InvalidArgument);
    o2 = opt;
    o2.components = 17;
    CHECK((bad = sk::prt_cpca_compress(order, T.data(), n, V, o2)).status == sk::Status::InvalidArgument);
    T[37] = std::numeric_limits<float>::quiet_NaN();
    CHECK((bad = sk::prt_cpca_compress(order, T.data(), n, V, opt)).status == sk::Status::NonFinite);
    CHECK(bad.clusters == 0);
    float rec[16];
    CHECK(sk::prt_cpca_reconstruct(cp, V, rec, 16).status == sk::Status::IndexOutOfRange);
    CHECK(sk::prt_cpca_reconstruct(cp, 0, rec, 15).status == sk::Status::BufferTooSmall);
    CHECK(sk::prt_cpca_shade(cp, proj.data(), V).status == sk::Status::IndexOutOfRange);
    CHECK(sk::prt_cpca_shade(cp, proj.data(), V).value == glm::vec3(0.0f));
    CHECK(sk::prt_cpca_project_environment(cp, env.data(), 15, proj.data(), proj.size()).status ==
          sk::Status::BufferTooSmall);
    // identical vectors everywhere (zero covariance) and a single vertex
    std::vector<float> same(50 * 9, 0.25f);
    sk::PrtCpca cs;
    sk::PrtCpcaOptions o3;
    o3.components = 3;
    cs = sk::prt_cpca_compress(3, same.data(), 9, 50, o3);
    REQUIRE(cs.status == sk::Status::Ok);
    CHECK(cs.rms_error < 1e-6);
    for (float w : cs.weights) CHECK(std::isfinite(w));
    cs = sk::prt_cpca_compress(3, same.data(), 9, 1, o3);
    REQUIRE(cs.status == sk::Status::Ok);
    CHECK(cs.clusters == 1);
}

TEST_CASE("shading a finite transfer whose radiance overflows float: Overflow, not Ok with Inf (issue 19 item 5)") {
    // Regression: prt_shade_mesh(order 1, T = 10, env = 3e38) returned Ok with +Inf (10 * 3e38 =
    // 3e39 > FLT_MAX); prt_shade_rgb returned the Inf as a plain vec3.
    const float T[4] = {10.f, 0.f, 0.f, 0.f};
    const glm::vec3 env[4] = {glm::vec3(3e38f), glm::vec3(0.f), glm::vec3(0.f), glm::vec3(0.f)};
    glm::vec3 out[1];
    const sk::PrtResult r = sk::prt_shade_mesh(1, T, 1, 1, env, out, 1);
    CHECK(r.status == sk::Status::Overflow);
    CHECK(r.count == 0);
    CHECK(sk::prt_shade_rgb(1, T, env).status == sk::Status::Overflow);
    const float envf[1] = {3e38f};
    CHECK(sk::prt_shade(1, T, envf).status == sk::Status::Overflow);
    // products that overflow float but cancel: the float sum is Inf - Inf = NaN; the true radiance
    // is 1e30 * 3e38 - 1e30 * 3e38 + 2 * 1 = 2 (double), which fits: Ok with 2
    const float T2[4] = {1e30f, 1e30f, 2.f, 0.f};
    const glm::vec3 env2[4] = {glm::vec3(3e38f), glm::vec3(-3e38f), glm::vec3(1.f), glm::vec3(0.f)};
    const sk::PrtRgbValue v = sk::prt_shade_rgb(2, T2, env2);
    CHECK(v.status == sk::Status::Ok);
    CHECK(v.value == glm::vec3(2.f));
    glm::vec3 out2[1];
    CHECK(sk::prt_shade_mesh(2, T2, 4, 1, env2, out2, 1).status == sk::Status::Ok);
    CHECK(out2[0] == glm::vec3(2.f));
    // a clustered PCA whose per-cluster projections overflow when summed
    std::vector<float> Tm(2 * 4, 0.f);
    Tm[0] = 1.f;
    Tm[4] = 1e30f;
    sk::PrtCpcaOptions o;
    o.clusters = 2;
    o.components = 0;
    const sk::PrtCpca cp = sk::prt_cpca_compress(2, Tm.data(), 4, 2, o);
    REQUIRE(cp.status == sk::Status::Ok);
    const glm::vec3 envc[4] = {glm::vec3(1e10f), glm::vec3(0.f), glm::vec3(0.f), glm::vec3(0.f)};
    glm::vec3 proj[2];
    CHECK(sk::prt_cpca_project_environment(cp, envc, 4, proj, 2).status == sk::Status::Overflow);  // 1e40
    proj[0] = glm::vec3(1.f);
    proj[1] = glm::vec3(std::numeric_limits<float>::infinity());
    glm::vec3 shaded[2];
    CHECK(sk::prt_cpca_shade_mesh(cp, proj, shaded, 2).status == sk::Status::NonFinite);
}

TEST_CASE("property: finite transfers and environments give Ok with the double-precision radiance, or Overflow (4,000 meshes)") {
    std::mt19937 rng(4242);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    const float scales[6] = {1e-30f, 1e-3f, 1.f, 1e10f, 1e19f, 1e30f};
    int ok = 0, overflow = 0;
    for (int it = 0; it < 4000; ++it) {
        const int order = 1 + it % 5;
        const std::size_t n = sk::prt_coefficient_count(order), V = 8;
        const float ts = scales[it % 6], es = scales[(it / 6) % 6] * (it % 13 == 0 ? 3e8f : 1.f);
        std::vector<float> T(V * 25);
        for (auto& t : T) t = u(rng) * ts;
        glm::vec3 env[25];
        for (auto& e : env) e = glm::vec3(u(rng), u(rng), u(rng)) * es;
        glm::vec3 out[8];
        const sk::PrtResult r = sk::prt_shade_mesh(order, T.data(), 25, V, env, out, V);
        bool any_overflow = false;
        for (std::size_t v = 0; v < V; ++v) {
            glm::dvec3 ref(0.0);
            for (std::size_t i = 0; i < n; ++i) ref += double(T[v * 25 + i]) * glm::dvec3(env[i]);
            const double fmax = double(std::numeric_limits<float>::max());
            const bool fits = std::fabs(ref.x) <= fmax && std::fabs(ref.y) <= fmax && std::fabs(ref.z) <= fmax;
            any_overflow = any_overflow || !fits;
            const sk::PrtRgbValue one = sk::prt_shade_rgb(order, &T[v * 25], env);
            if (!fits) {
                REQUIRE(one.status == sk::Status::Overflow);
                continue;
            }
            REQUIRE(one.status == sk::Status::Ok);
            // float accumulation: within n ulps of the sum of magnitudes
            glm::dvec3 mag(0.0);
            for (std::size_t i = 0; i < n; ++i) mag += glm::abs(double(T[v * 25 + i]) * glm::dvec3(env[i]));
            for (int c = 0; c < 3; ++c)
                REQUIRE(std::fabs(double(one.value[c]) - ref[c]) <= 1e-6 * double(n) * mag[c] + 1e-37);
            if (r.status == sk::Status::Ok) REQUIRE(out[v] == one.value);
        }
        REQUIRE(r.status == (any_overflow ? sk::Status::Overflow : sk::Status::Ok));
        (any_overflow ? overflow : ok) += 1;
    }
    CHECK(ok > 1000);
    CHECK(overflow > 50);
}
