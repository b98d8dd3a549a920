// Where a status came from (issue #25 item 6): the first validation of every public function of
// perspective_shadow_maps.hpp that returns a result names the offending input in `detail`; Ok gives nullptr.
#include <shadowkit/perspective_shadow_maps.hpp>

#include "status_detail.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <limits>

using namespace shadowkit;

namespace {
const float kNaN = std::numeric_limits<float>::quiet_NaN();
WarpInput input() {
    WarpInput in;
    in.camera_view = glm::lookAt(glm::vec3(0, 2, 0), glm::vec3(0, 2, -1), glm::vec3(0, 1, 0));
    in.camera_proj = glm::perspective(1.0f, 1.0f, 0.1f, 50.0f);
    in.light_position = glm::vec4(0.3f, 1.0f, 0.2f, 0.0f);
    return in;
}
const WarpMethod kMethods[4] = {WarpMethod::Uniform, WarpMethod::Psm, WarpMethod::Lispsm, WarpMethod::Tsm};
}  // namespace

TEST_CASE("perspective_shadow_maps: the first validation of each function names its input") {
    WarpInput in = input();
    in.camera_view[0][0] = kNaN;  // the first check: finite inputs
    SK_CHECK_DETAIL(warp_uniform_matrix(in), Status::NonFinite, "camera_view");
    SK_CHECK_DETAIL(warp_psm_matrix(in), Status::NonFinite, "camera_view");
    SK_CHECK_DETAIL(warp_lispsm_matrix(in), Status::NonFinite, "camera_view");
    SK_CHECK_DETAIL(warp_tsm_matrix(in), Status::NonFinite, "camera_view");
    for (const WarpMethod m : kMethods) SK_CHECK_DETAIL(warp_matrix(in, m), Status::NonFinite, "camera_view");
    SK_CHECK_DETAIL(warp_matrix(input(), static_cast<WarpMethod>(9)), Status::InvalidArgument, "method");
    in = input();
    in.light_position = glm::vec4(0.0f, 1.0f, 0.0f, -1.0f);
    SK_CHECK_DETAIL(warp_lispsm_matrix(in), Status::InvalidLight, "light_position: w < 0");
    in = input();  // LiSPSM checks its own options first
    in.options.lispsm_virtual_near = -1.0f;
    SK_CHECK_DETAIL(warp_lispsm_matrix(in), Status::InvalidArgument, "lispsm_virtual_near");
    in.options.lispsm_virtual_near = kNaN;
    SK_CHECK_DETAIL(warp_lispsm_matrix(in), Status::NonFinite, "lispsm_virtual_near");
    in = input();
    in.camera_proj = glm::perspective(1.0f, 1.0f, -0.1f, 50.0f);
    SK_CHECK_DETAIL(warp_tsm_matrix(in), Status::InvalidArgument, "camera_proj");
    const glm::mat4 cvp = input().camera_proj * input().camera_view;
    SK_CHECK_DETAIL(warp_aliasing_error(glm::mat4(kNaN), cvp, glm::vec3(0, 0, -5), glm::vec3(0, 1, 0), 1024, glm::uvec2(800, 600)),
                    Status::NonFinite, "light_view_proj");
    SK_CHECK_DETAIL(warp_aliasing_error(cvp, cvp, glm::vec3(0, 0, -5), glm::vec3(0.0f), 1024, glm::uvec2(800, 600)),
                    Status::InvalidArgument, "normal");
    in = input();
    in.max_distance = kNaN;  // wp_prepare's first check
    SK_CHECK_DETAIL(warp_measure_aliasing(in, cvp, 1024, glm::uvec2(800, 600), 4, 4, 4), Status::NonFinite, "max_distance");
    SK_CHECK_DETAIL(warp_measure_aliasing(input(), cvp, 1024, glm::uvec2(800, 600), 0, 4, 4), Status::InvalidArgument, "nx");
}

TEST_CASE("perspective_shadow_maps: Ok results carry no detail") {
    const WarpInput in = input();
    for (const WarpMethod m : kMethods) {
        const WarpResult w = warp_matrix(in, m);
        SK_CHECK_OK_NO_DETAIL(w);
        SK_CHECK_OK_NO_DETAIL(warp_measure_aliasing(in, w.light_view_proj, 1024, glm::uvec2(800, 600), 4, 4, 4));
    }
    const WarpResult u = warp_uniform_matrix(in);
    SK_CHECK_OK_NO_DETAIL(warp_aliasing_error(u.light_view_proj, in.camera_proj * in.camera_view, glm::vec3(0.5f, 0.0f, -5.0f),
                                              glm::vec3(0.3f, 1.0f, 0.2f), 1024, glm::uvec2(800, 600)));
}
