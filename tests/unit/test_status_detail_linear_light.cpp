// Where a status came from (issue #25 item 6): the first validation of every public function of
// linear_light.hpp that returns a result names the offending input in `detail`; Ok gives nullptr.
#include <shadowkit/linear_light.hpp>

#include "status_detail.hpp"

#include <limits>
#include <vector>

using namespace shadowkit;

namespace {
const float kNaN = std::numeric_limits<float>::quiet_NaN();
const glm::vec3 kA(-1.0f, 5.0f, 0.0f), kB(1.0f, 5.0f, 0.0f);
}  // namespace

TEST_CASE("linear_light: the first validation of each function names its input") {
    SK_CHECK_DETAIL(linear_light_segment(glm::vec3(kNaN), glm::vec3(1, 0, 0), 2.0f), Status::NonFinite, "center");
    SK_CHECK_DETAIL(linear_light_segment(glm::vec3(0.0f), glm::vec3(1, 0, 0), -2.0f), Status::InvalidArgument, "length");
    glm::vec3 ends[8];
    SK_CHECK_DETAIL(linear_light_subdivide(linear_light_segment(glm::vec3(0.0f), glm::vec3(1, 0, 0), 2.0f), 0, ends, 8),
                    Status::InvalidArgument, "k");
    SK_CHECK_DETAIL(linear_light_subdivide(linear_light_segment(glm::vec3(0.0f), glm::vec3(1, 0, 0), 2.0f), 4, ends, 2),
                    Status::BufferTooSmall, "out_capacity");
    LinearLightBox box;
    box.lo = glm::vec3(-0.5f, 1.0f, -0.5f);
    box.hi = glm::vec3(0.5f, 2.0f, 0.5f);
    SK_CHECK_DETAIL(linear_light_box_interval(glm::vec3(kNaN), kA, kB, box), Status::NonFinite, "p");
    SK_CHECK_DETAIL(linear_light_tangent_interval(glm::vec3(0.0f), glm::vec3(kNaN), kA, kB), Status::NonFinite, "n");
    SK_CHECK_DETAIL(linear_light_visible_fraction(glm::vec3(0.0f), glm::vec3(0, 1, 0), kA, kB, nullptr, 3), Status::InvalidArgument,
                    "boxes");
    SK_CHECK_DETAIL(linear_light_skin_cell(glm::vec4(1.0f), kNaN), Status::NonFinite, "threshold");
    SK_CHECK_DETAIL(linear_light_skin_cell(glm::vec4(1.0f, 0.0f, 1.0f, 1.0f), 0.1f), Status::InvalidArgument, "distances");
    LinearLightSkinVertex out[6];
    SK_CHECK_DETAIL(linear_light_build_skin(nullptr, nullptr, 2, 2, 0.1f, out, 6), Status::InvalidArgument, "positions");
}

TEST_CASE("linear_light: Ok results carry no detail") {
    const LinearLightSegment s = linear_light_segment(glm::vec3(0, 5, 0), glm::vec3(1, 0, 0), 2.0f);
    SK_CHECK_OK_NO_DETAIL(s);
    glm::vec3 ends[5];
    SK_CHECK_OK_NO_DETAIL(linear_light_subdivide(s, 4, ends, 5));
    LinearLightBox box;
    box.lo = glm::vec3(-0.5f, 1.0f, -0.5f);
    box.hi = glm::vec3(0.5f, 2.0f, 0.5f);
    SK_CHECK_OK_NO_DETAIL(linear_light_box_interval(glm::vec3(0.0f), kA, kB, box));
    SK_CHECK_OK_NO_DETAIL(linear_light_tangent_interval(glm::vec3(0.0f), glm::vec3(0, 1, 0), kA, kB));
    SK_CHECK_OK_NO_DETAIL(linear_light_visible_fraction(glm::vec3(0.0f), glm::vec3(0, 1, 0), kA, kB, &box, 1));
    SK_CHECK_OK_NO_DETAIL(linear_light_skin_cell(glm::vec4(1.0f, 1.0f, 5.0f, 5.0f), 0.5f));
    const glm::vec3 pos[4] = {glm::vec3(0, 0, 0), glm::vec3(1, 0, 0), glm::vec3(0, 0, 1), glm::vec3(1, 0, 1)};
    const float dist[4] = {1.0f, 1.0f, 5.0f, 5.0f};
    LinearLightSkinVertex out[6];
    SK_CHECK_OK_NO_DETAIL(linear_light_build_skin(pos, dist, 2, 2, 0.5f, out, 6));
}
