// The report's instrument checked against closed form: a square occluder parallel to a floor
// under a parallel square area light has an analytic penumbra (separable 1D overlaps). The
// Embree reference must match it to RMSE < 0.01; a deliberately wrong technique (V = 1) must
// score the large error the closed form predicts; the metrics must agree with a direct computation.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "gl_test.hpp"
#include "metrics.hpp"
#include "reference.hpp"
#include "scene.hpp"
#include "techniques.hpp"

namespace {

// Length of [c - r, c + r] inside [-half, half].
double overlap(double c, double r, double half) { return std::max(0.0, std::min(c + r, half) - std::max(c - r, -half)); }

// Fraction of a square light (edge L, centred above the origin at height H) seen from floor point
// (x, 0, z) past a square occluder (half size a) at height h: similar triangles project the
// occluder onto the light plane as a square of half size a H / h centred at p (1 - H / h).
double analytic_visibility(double x, double z, double L, double H, double a, double h) {
    const double s = H / h;
    const double ox = overlap(x * (1.0 - s), a * s, 0.5 * L);
    const double oz = overlap(z * (1.0 - s), a * s, 0.5 * L);
    return 1.0 - ox * oz / (L * L);
}

}  // namespace

TEST_CASE("Embree reference matches the closed-form penumbra of a square occluder (RMSE < 0.01)") {
    sk::Scene scene;
    REQUIRE(sk::make_builtin_scene("square", scene));
    REQUIRE(scene.light.type == sk::LightType::Rect);
    sk::SceneGpu gpu;
    sk::GBuffer g;
    std::string why;
    REQUIRE_MESSAGE(sk::prepare_scene_gpu(scene, 200, 200, gpu, g, why), why);
    sk::ReferenceOptions opt;
    opt.strata = 32;
    opt.progress = false;
    sk::Reference ref;
    REQUIRE_MESSAGE(sk::compute_reference(scene, g, opt, ref, why), why);

    const double L = scene.light.size, H = scene.light.position.y, a = 0.5, h = 1.0;
    double sq = 0.0, sq_unshadowed = 0.0, max_err = 0.0;
    std::size_t n = 0, penumbra = 0, umbra = 0;
    std::vector<float> analytic(g.kind.size(), 0.f);
    for (std::size_t k = 0; k < g.kind.size(); ++k) {
        if (g.kind[k] != 1) continue;
        const double x = g.position[3 * k], z = g.position[3 * k + 2];
        CHECK(std::abs(g.position[3 * k + 1]) < 1e-4);  // receivers are floor points
        const double va = analytic_visibility(x, z, L, H, a, h);
        analytic[k] = float(va);
        const double e = double(ref.visibility[k]) - va;
        sq += e * e;
        max_err = std::max(max_err, std::abs(e));
        sq_unshadowed += (1.0 - va) * (1.0 - va);
        ++n;
        if (va > 0.0 && va < 1.0) ++penumbra;
        if (va == 0.0) ++umbra;
    }
    REQUIRE(n > 10000);
    const double rmse = std::sqrt(sq / double(n));
    MESSAGE("reference vs closed form: RMSE " << rmse << ", max " << max_err << ", stderr estimate "
                                              << ref.stderr_rms << ", " << penumbra << " penumbra pixels, " << umbra
                                              << " umbra pixels, " << ref.samples_per_pixel << " rays/pixel");
    CHECK(penumbra > n / 20);  // the view really contains a penumbra to get right
    CHECK(umbra > n / 50);
    CHECK(rmse < 0.01);
    CHECK(ref.stderr_rms < 0.01);

    // A wrong technique (V = 1) must score the large error the closed form predicts.
    auto techniques = sk::make_techniques();
    auto it = std::find_if(techniques.begin(), techniques.end(), [](const auto& t) { return t->name() == "unshadowed"; });
    REQUIRE(it != techniques.end());
    sk::RunContext ctx{scene, gpu, 3, 1};
    const sk::RunResult res = (*it)->run(ctx, sk::ParamSet{});
    REQUIRE_MESSAGE(res.ok, res.error);
    const sk::Metrics m = sk::compute_metrics(g, ref, res.visibility, true);
    const double expected = std::sqrt(sq_unshadowed / double(n));
    MESSAGE("V = 1 scores RMSE " << m.rmse << " (closed form predicts " << expected << ")");
    CHECK(m.rmse > 0.15);
    CHECK(m.rmse == doctest::Approx(expected).epsilon(0.05));
    CHECK(m.pixels == n);

    // The metrics themselves: the closed form scored against the reference gives the RMSE above.
    const sk::Metrics ma = sk::compute_metrics(g, ref, analytic, false);
    CHECK(ma.rmse == doctest::Approx(rmse).epsilon(1e-6));
    CHECK(ma.has_penumbra);
    CHECK_FALSE(ma.has_misclassified);
}

TEST_CASE("hard lights give an exact 0/1 reference: no pixel strictly between") {
    sk::Scene scene;
    REQUIRE(sk::make_builtin_scene("stack", scene));
    sk::SceneGpu gpu;
    sk::GBuffer g;
    std::string why;
    REQUIRE_MESSAGE(sk::prepare_scene_gpu(scene, 96, 72, gpu, g, why), why);
    sk::ReferenceOptions opt;
    opt.progress = false;
    sk::Reference ref;
    REQUIRE(sk::compute_reference(scene, g, opt, ref, why));
    std::size_t lit = 0, dark = 0;
    for (std::size_t k = 0; k < g.kind.size(); ++k) {
        if (g.kind[k] != 1 || !ref.faces_light[k]) continue;
        const float v = ref.visibility[k];
        CHECK((v == 0.f || v == 1.f));
        (v == 1.f ? lit : dark)++;
    }
    CHECK(ref.samples_per_pixel == 1);
    CHECK(lit > 0);
    CHECK(dark > 0);
}
