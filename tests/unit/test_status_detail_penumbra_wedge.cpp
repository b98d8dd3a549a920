// Where a status came from (issue #25 item 6): the first validation of every public function of
// penumbra_wedge.hpp that returns a result names the offending input in `detail`; Ok gives nullptr.
#include <shadowkit/penumbra_wedge.hpp>

#include "status_detail.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <limits>

using namespace shadowkit;

namespace {
const float kNaN = std::numeric_limits<float>::quiet_NaN();
PenumbraSphereLight light() {
    PenumbraSphereLight L;
    L.light_position = glm::vec4(0.0f, 10.0f, 0.0f, 1.0f);
    L.radius = 0.5f;
    return L;
}
ScissorParams params() {
    ScissorParams p;
    p.view_proj = glm::perspective(1.0f, 1.0f, 0.5f, 100.0f) *
                  glm::lookAt(glm::vec3(0, 3, 10), glm::vec3(0, 0, 0), glm::vec3(0, 1, 0));
    p.viewport[2] = 640;
    p.viewport[3] = 480;
    return p;
}
const glm::vec3 kE0(-1.0f, 2.0f, 0.0f), kE1(1.0f, 2.0f, 0.0f);
}  // namespace

TEST_CASE("penumbra_wedge: the first validation of each function names its input") {
    SK_CHECK_DETAIL(penumbra_rect_bounding_sphere(glm::vec4(0.0f, 1.0f, 0.0f, 0.0f), glm::vec3(1.0f), glm::vec3(1.0f)),
                    Status::InvalidLight, "light_position");
    PenumbraSphereLight L = light();
    L.radius = -1.0f;
    SK_CHECK_DETAIL(penumbra_wedge(kE0, kE1, L), Status::InvalidArgument, "radius");
    SK_CHECK_DETAIL(penumbra_wedge(kE0, kE1, light(), -1.0f), Status::InvalidArgument, "padding");
    SK_CHECK_DETAIL(penumbra_transform_plane(glm::vec4(0, 1, 0, 0), glm::mat4(kNaN)), Status::NonFinite, "M");
    SK_CHECK_DETAIL(penumbra_viewport_transform(nullptr, ClipDepth::NegativeOneToOne), Status::InvalidArgument, "viewport");
    L = light();
    L.light_position.x = kNaN;
    SK_CHECK_DETAIL(penumbra_edge_coverage(kE0, kE1, L, glm::vec3(0.0f)), Status::InvalidLight, "light_position");
    SK_CHECK_DETAIL(penumbra_visibility(nullptr, 2, light(), glm::vec3(0.0f), 0), Status::InvalidArgument, "endpoints");
    SK_CHECK_DETAIL(penumbra_wedge_hull(PenumbraWedge{}, 10.0f), Status::InvalidArgument, "w");
    SK_CHECK_DETAIL(penumbra_points_scissor(nullptr, 3, params()), Status::InvalidArgument, "points");
    SK_CHECK_DETAIL(penumbra_wedge_scissor(PenumbraWedgeHull{}, params()), Status::InvalidArgument, "hull");
    SK_CHECK_DETAIL(penumbra_wedge_scissor_in_box(PenumbraWedgeHull{}, glm::vec3(-1.0f), glm::vec3(1.0f), ScissorParams{}),
                    Status::InvalidArgument, "viewport");
}

TEST_CASE("penumbra_wedge: Ok results carry no detail") {
    SK_CHECK_OK_NO_DETAIL(penumbra_rect_bounding_sphere(glm::vec4(0, 10, 0, 1), glm::vec3(1, 0, 0), glm::vec3(0, 0, 1)));
    const PenumbraWedge w = penumbra_wedge(kE0, kE1, light());
    SK_CHECK_OK_NO_DETAIL(w);
    SK_CHECK_OK_NO_DETAIL(penumbra_transform_plane(glm::vec4(0, 1, 0, 0), params().view_proj));
    const int vp[4] = {0, 0, 640, 480};
    SK_CHECK_OK_NO_DETAIL(penumbra_viewport_transform(vp, ClipDepth::NegativeOneToOne));
    SK_CHECK_OK_NO_DETAIL(penumbra_edge_coverage(kE0, kE1, light(), glm::vec3(0.0f)));
    const glm::vec3 ends[2] = {kE0, kE1};
    SK_CHECK_OK_NO_DETAIL(penumbra_visibility(ends, 1, light(), glm::vec3(0.0f), 0));
    const PenumbraWedgeHull h = penumbra_wedge_hull(w, 20.0f);
    SK_CHECK_OK_NO_DETAIL(h);
    SK_CHECK_OK_NO_DETAIL(penumbra_points_scissor(h.vertices, 6, params()));
    SK_CHECK_OK_NO_DETAIL(penumbra_wedge_scissor(h, params()));
    SK_CHECK_OK_NO_DETAIL(penumbra_wedge_scissor_in_box(h, glm::vec3(-5.0f), glm::vec3(5.0f), params()));
}
