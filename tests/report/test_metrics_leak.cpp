// The report's light-leaking metric (samples/common/metrics.cpp) on synthetic buffers with closed
// forms: the fraction of the reference's umbra (V_ref = 0) where V > 0.1, and the mean excess (the
// mean V over that umbra). Catches an umbra taken as V_ref < 0.5, a threshold applied to the error
// instead of V, or non-receiver pixels counted.
#include <doctest/doctest.h>

#include <vector>

#include "metrics.hpp"
#include "reference.hpp"

TEST_CASE("leak metric: closed form on a 10 x 10 buffer") {
    sk::GBuffer g;
    g.width = 10;
    g.height = 10;
    g.position.assign(300, 0.0f);
    g.normal.assign(300, 0.0f);
    g.kind.assign(100, 1);
    sk::Reference ref;
    ref.visibility.assign(100, 1.0f);
    ref.faces_light.assign(100, 1);
    std::vector<float> v(100, 1.0f);
    // umbra: the first 40 pixels; V there: 10 at 0.5 (leak), 10 at 0.1 (not above 0.1), 20 at 0
    for (int k = 0; k < 40; ++k) {
        ref.visibility[static_cast<std::size_t>(k)] = 0.0f;
        v[static_cast<std::size_t>(k)] = k < 10 ? 0.5f : (k < 20 ? 0.1f : 0.0f);
    }
    // penumbra pixels (V_ref = 0.5) with V = 1: not umbra, not counted
    for (int k = 40; k < 50; ++k) ref.visibility[static_cast<std::size_t>(k)] = 0.5f;
    // a background pixel in the umbra with V = 1: not a receiver, not counted
    g.kind[99] = 0;
    ref.visibility[99] = 0.0f;
    const sk::Metrics m = sk::compute_metrics(g, ref, v, false);
    REQUIRE(m.has_leak);
    CHECK(m.umbra_pixels == 40u);
    CHECK(m.leak_fraction == doctest::Approx(10.0 / 40.0));
    CHECK(m.leak_mean_excess == doctest::Approx((10 * 0.5 + 10 * 0.1) / 40.0));
    // no umbra: the metric is undefined
    std::vector<float> ones(100, 1.0f);
    sk::Reference lit = ref;
    lit.visibility.assign(100, 1.0f);
    CHECK_FALSE(sk::compute_metrics(g, lit, ones, false).has_leak);
}
