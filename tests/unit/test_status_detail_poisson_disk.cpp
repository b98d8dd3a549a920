// Where a status came from (issue #25 item 6): the first validation of every public function of
// poisson_disk.hpp that returns a result names the offending input in `detail`; Ok gives nullptr.
#include <shadowkit/poisson_disk.hpp>

#include "status_detail.hpp"

#include <limits>
#include <vector>

using namespace shadowkit;

namespace {
const float kNaN = std::numeric_limits<float>::quiet_NaN();
PoissonDomain annulus(float inner) {
    PoissonDomain d;
    d.shape = PoissonShape::Annulus;
    d.inner_radius = inner;
    return d;
}
}  // namespace

TEST_CASE("poisson_disk: the first validation of each function names its input") {
    SK_CHECK_DETAIL(poisson_domain_area(annulus(kNaN)), Status::NonFinite, "inner_radius");
    SK_CHECK_DETAIL(poisson_domain_area(annulus(2.0f)), Status::InvalidArgument, "inner_radius");
    SK_CHECK_DETAIL(poisson_packing_distance(annulus(kNaN), 8), Status::NonFinite, "inner_radius");
    SK_CHECK_DETAIL(poisson_packing_distance(PoissonDomain{}, 0), Status::InvalidArgument, "n");
    std::vector<glm::vec2> out(256);
    SK_CHECK_DETAIL(poisson_bridson(PoissonDomain{}, kNaN, 1, out.data(), out.size()), Status::NonFinite, "radius");
    SK_CHECK_DETAIL(poisson_bridson(PoissonDomain{}, 0.3f, 1, out.data(), 2), Status::BufferTooSmall, "out_capacity");
    SK_CHECK_DETAIL(poisson_eliminate(annulus(kNaN), 16, 1, out.data(), out.size()), Status::NonFinite, "inner_radius");
    SK_CHECK_DETAIL(poisson_eliminate(PoissonDomain{}, 16, 1, nullptr, 4), Status::InvalidArgument, "out");
    SK_CHECK_DETAIL(poisson_min_distance(nullptr, 4), Status::InvalidArgument, "pts");
    const glm::vec2 pts[3] = {glm::vec2(0.0f), glm::vec2(0.5f, 0.0f), glm::vec2(kNaN)};
    SK_CHECK_DETAIL(poisson_min_distance(pts, 3), Status::NonFinite, "pts");
    SK_CHECK_DETAIL(poisson_normalized_radius(annulus(kNaN), pts, 2), Status::NonFinite, "inner_radius");
    SK_CHECK_DETAIL(poisson_coverage_radius(annulus(kNaN), pts, 2), Status::NonFinite, "inner_radius");
    SK_CHECK_DETAIL(poisson_coverage_radius(PoissonDomain{}, pts, 0), Status::InvalidArgument, "n");
    SK_CHECK_DETAIL(poisson_coverage_radius_grid(annulus(kNaN), pts, 2, 16), Status::NonFinite, "inner_radius");
    char text[64];
    SK_CHECK_DETAIL(poisson_to_glsl(nullptr, 2, "taps", PoissonGlsl::Array, text, sizeof text), Status::InvalidArgument, "pts");
    SK_CHECK_DETAIL(poisson_to_glsl(pts, 2, "gl_taps", PoissonGlsl::Array, text, sizeof text), Status::InvalidArgument, "name");
}

TEST_CASE("poisson_disk: Ok results carry no detail") {
    SK_CHECK_OK_NO_DETAIL(poisson_domain_area(annulus(0.5f)));
    SK_CHECK_OK_NO_DETAIL(poisson_packing_distance(PoissonDomain{}, 16));
    std::vector<glm::vec2> out(poisson_bridson_capacity(PoissonDomain{}, 0.3f));
    const PoissonResult b = poisson_bridson(PoissonDomain{}, 0.3f, 1, out.data(), out.size());
    SK_CHECK_OK_NO_DETAIL(b);
    std::vector<glm::vec2> e(16);
    SK_CHECK_OK_NO_DETAIL(poisson_eliminate(PoissonDomain{}, 16, 1, e.data(), e.size()));
    SK_CHECK_OK_NO_DETAIL(poisson_min_distance(e.data(), e.size()));
    SK_CHECK_OK_NO_DETAIL(poisson_normalized_radius(PoissonDomain{}, e.data(), e.size()));
    SK_CHECK_OK_NO_DETAIL(poisson_coverage_radius(PoissonDomain{}, e.data(), e.size()));
    SK_CHECK_OK_NO_DETAIL(poisson_coverage_radius_grid(PoissonDomain{}, e.data(), e.size(), 16));
    std::vector<char> text(4096);
    SK_CHECK_OK_NO_DETAIL(poisson_to_glsl(e.data(), e.size(), "taps", PoissonGlsl::Array, text.data(), text.size()));
}
