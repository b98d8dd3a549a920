// Where a status came from (issue #25 item 6): the first validation of every public function of
// smoothie.hpp that returns a result names the offending input in `detail`; Ok gives nullptr.
#include <shadowkit/smoothie.hpp>

#include "status_detail.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <cstdint>
#include <limits>
#include <vector>

using namespace shadowkit;

namespace {
const float kNaN = std::numeric_limits<float>::quiet_NaN();
const glm::mat4 kLightVP = glm::ortho(-5.0f, 5.0f, -5.0f, 5.0f, 0.1f, 20.0f) *
                           glm::lookAt(glm::vec3(0, 10, 0), glm::vec3(0), glm::vec3(0, 0, -1));
const glm::vec3 kPos[3] = {glm::vec3(-1, 1, -1), glm::vec3(1, 1, -1), glm::vec3(0, 1, 1)};
const std::uint32_t kEdges[6] = {0, 1, 1, 2, 2, 0};
SmoothieEdges edges() {
    SmoothieEdges e;
    e.positions = kPos;
    e.position_count = 3;
    e.edges = kEdges;
    e.edge_count = 3;
    return e;
}
SmoothieParams params() {
    SmoothieParams p;
    p.t = 0.05f;
    return p;
}
}  // namespace

TEST_CASE("smoothie: the first validation of each function names its input") {
    SK_CHECK_DETAIL(smoothie_width_for_area_light(kNaN, 1.0f, 1.0f), Status::NonFinite, "light_width");
    SK_CHECK_DETAIL(smoothie_area_light_width(0.1f, 0.0f, 1.0f), Status::InvalidArgument, "b");
    SK_CHECK_DETAIL(smoothie_penumbra_width(0.1f, 1.0f, 2.0f, kNaN), Status::NonFinite, "proj_scale");
    SmoothieEdges e = edges();
    e.edges = nullptr;  // the first check: a null pointer with a count
    SK_CHECK_DETAIL(smoothie_build(e, kLightVP, params(), nullptr, 0, nullptr, 0), Status::InvalidArgument, "edges");
    SmoothieParams p = params();
    p.t = -1.0f;
    SK_CHECK_DETAIL(smoothie_build(edges(), kLightVP, p, nullptr, 0, nullptr, 0), Status::InvalidArgument, "t");
    SK_CHECK_DETAIL(smoothie_build(edges(), kLightVP, params(), nullptr, 0, nullptr, 0), Status::BufferTooSmall,
                    "scratch_capacity");
}

TEST_CASE("smoothie: Ok results carry no detail") {
    SK_CHECK_OK_NO_DETAIL(smoothie_width_for_area_light(0.5f, 2.0f, 1.0f));
    SK_CHECK_OK_NO_DETAIL(smoothie_area_light_width(0.1f, 2.0f, 1.0f));
    SK_CHECK_OK_NO_DETAIL(smoothie_penumbra_width(0.1f, 1.0f, 2.0f, 1.0f));
    std::vector<SmoothieScratch> scratch(smoothie_scratch_capacity(3));
    std::vector<SmoothieVertex> out(smoothie_vertex_capacity(3));
    SK_CHECK_OK_NO_DETAIL(smoothie_build(edges(), kLightVP, params(), scratch.data(), scratch.size(), out.data(), out.size()));
}
