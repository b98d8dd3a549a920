// Where a status came from (issue #25 item 6): the first validation of every public function of
// pcss.hpp that returns a result names the offending input in `detail`; Ok gives nullptr.
#include <shadowkit/pcss.hpp>

#include "status_detail.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <limits>

using namespace shadowkit;

namespace {
const float kNaN = std::numeric_limits<float>::quiet_NaN();
PcssLight light() {
    PcssLight L;
    L.type = PcssLightType::Perspective;
    L.size = 0.5f;
    L.near_z = 0.5f;
    L.far_z = 50.0f;
    L.frustum_width = 2.0f;
    return L;
}
PcssPolicy policy() {
    PcssPolicy p;
    p.map_resolution = 1024.0f;
    return p;
}
}  // namespace

TEST_CASE("pcss: the first validation of each function names its input") {
    SK_CHECK_DETAIL(pcss_linearize_window_depth(0.5f, kNaN, 50.0f, false), Status::NonFinite, "near_z");
    SK_CHECK_DETAIL(pcss_linearize_window_depth(0.5f, 1.0f, 0.5f, false), Status::InvalidArgument, "far_z");
    SK_CHECK_DETAIL(pcss_delinearize_window_depth(1.0f, 0.0f, 50.0f, false), Status::InvalidArgument, "near_z");
    SK_CHECK_DETAIL(pcss_linearize_ndc_depth(0.5f, 0.5f, 50.0f, static_cast<ClipDepth>(5), false), Status::InvalidArgument,
                    "clip");
    SK_CHECK_DETAIL(pcss_linearize_ortho_window_depth(kNaN, 0.5f, 50.0f, false), Status::NonFinite, "z_w");
    SK_CHECK_DETAIL(pcss_search_width(kNaN, 2.0f, 0.5f), Status::NonFinite, "light_width");
    SK_CHECK_DETAIL(pcss_penumbra_width(1.0f, 2.0f, -1.0f), Status::InvalidArgument, "z_b");
    SK_CHECK_DETAIL(pcss_filter_width(-1.0f, 2.0f, 0.5f), Status::InvalidArgument, "w_penumbra");
    SK_CHECK_DETAIL(pcss_width_to_uv(1.0f, 2.0f, kNaN), Status::NonFinite, "frustum_width");
    SK_CHECK_DETAIL(pcss_search_width_directional(4.0f, 2.0f, 0.5f), Status::InvalidArgument, "angular_diameter");
    SK_CHECK_DETAIL(pcss_penumbra_width_directional(kNaN, 2.0f, 0.5f), Status::NonFinite, "angular_diameter");
    PcssLight L = light();
    L.size = kNaN;
    SK_CHECK_DETAIL(pcss_light_uv_at_near(L), Status::NonFinite, "size");
    L = light();
    L.frustum_width = 0.0f;  // the required field left at its default
    SK_CHECK_DETAIL(pcss_search_uv(L, 2.0f), Status::InvalidArgument, "frustum_width");
    L = light();
    L.near_z = -1.0f;
    SK_CHECK_DETAIL(pcss_fit_near_plane(L, glm::mat4(1.0f), glm::vec3(-1.0f), glm::vec3(1.0f)), Status::InvalidArgument,
                    "near_z");
    SK_CHECK_DETAIL(pcss_fit_near_plane(light(), glm::mat4(0.0f), glm::vec3(-1.0f), glm::vec3(1.0f)), Status::InvalidArgument,
                    "light_view");
    SK_CHECK_DETAIL(pcss_average_blocker(nullptr, 4, kNaN, 0.0f), Status::NonFinite, "z_r");
    SK_CHECK_DETAIL(pcss_average_blocker(nullptr, 4, 2.0f, 0.0f), Status::InvalidArgument, "linear_depths");
    SK_CHECK_DETAIL(pcss_clamp_filter(0.1f, kNaN, 0.5f), Status::NonFinite, "min_uv");
    L = light();
    L.far_z = 0.1f;
    PcssBlocker b;
    b.status = Status::Ok;
    SK_CHECK_DETAIL(pcss_filter(L, 2.0f, b, policy()), Status::InvalidArgument, "far_z");
    SK_CHECK_DETAIL(pcss_filter(light(), 2.0f, b, PcssPolicy{}), Status::InvalidArgument, "map_resolution");
    SK_CHECK_DETAIL(pcss_penumbra_width_from_window_depth(1.0f, 0.5f, 0.4f, 0.5f, kNaN, false), Status::NonFinite, "far_z");
}

TEST_CASE("pcss: Ok results carry no detail") {
    SK_CHECK_OK_NO_DETAIL(pcss_linearize_window_depth(0.5f, 0.5f, 50.0f, false));
    SK_CHECK_OK_NO_DETAIL(pcss_linearize_ndc_depth(0.5f, 0.5f, 50.0f, ClipDepth::NegativeOneToOne, false));
    SK_CHECK_OK_NO_DETAIL(pcss_penumbra_width(1.0f, 2.0f, 1.0f));
    SK_CHECK_OK_NO_DETAIL(pcss_search_uv(light(), 2.0f));
    SK_CHECK_OK_NO_DETAIL(pcss_fit_near_plane(light(), glm::lookAt(glm::vec3(0, 10, 0), glm::vec3(0), glm::vec3(0, 0, -1)),
                                              glm::vec3(-1.0f), glm::vec3(1.0f)));
    const float depths[3] = {1.0f, 1.5f, 3.0f};
    const PcssBlocker b = pcss_average_blocker(depths, 3, 2.0f, 0.01f);
    SK_CHECK_OK_NO_DETAIL(b);
    SK_CHECK_OK_NO_DETAIL(pcss_filter(light(), 2.0f, b, policy()));
    SK_CHECK_OK_NO_DETAIL(pcss_clamp_filter(0.1f, 0.0f, 0.05f));
}
