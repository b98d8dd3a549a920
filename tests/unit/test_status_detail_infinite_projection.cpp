// Where a status came from (issue #25 item 6): the first validation of every public function of
// infinite_projection.hpp that returns a result names the offending input in `detail`; Ok gives nullptr.
#include <shadowkit/infinite_projection.hpp>

#include "status_detail.hpp"

#include <limits>

using namespace shadowkit;

namespace {
const float kNaN = std::numeric_limits<float>::quiet_NaN();
ProjectionDepth bad_near() {
    ProjectionDepth d;
    d.near_z = kNaN;  // the first check of projection_validate
    return d;
}
}  // namespace

TEST_CASE("infinite_projection: the first validation of each function names its input") {
    SK_CHECK_DETAIL(projection_depth_mapping(bad_near()), Status::NonFinite, "near_z");
    ProjectionDepth d;
    d.far_z = 10.0f;
    d.epsilon = 0.1f;
    SK_CHECK_DETAIL(projection_depth_mapping(d), Status::InvalidArgument, "epsilon");
    SK_CHECK_DETAIL(projection_frustum(-1.0f, 1.0f, -1.0f, 1.0f, bad_near()), Status::NonFinite, "near_z");
    SK_CHECK_DETAIL(projection_frustum(1.0f, -1.0f, -1.0f, 1.0f, ProjectionDepth{}), Status::InvalidArgument, "right");
    SK_CHECK_DETAIL(projection_perspective(1.0f, 1.0f, bad_near()), Status::NonFinite, "near_z");
    SK_CHECK_DETAIL(projection_perspective(4.0f, 1.0f, ProjectionDepth{}), Status::InvalidArgument, "fovy");
    SK_CHECK_DETAIL(projection_perspective_infinite(1.0f, 1.0f, -1.0f), Status::InvalidArgument, "near_z");
    SK_CHECK_DETAIL(projection_perspective_finite(1.0f, 1.0f, 1.0f, 0.5f), Status::InvalidArgument, "far_z");
    SK_CHECK_DETAIL(projection_ndc_depth(bad_near(), 1.0), Status::NonFinite, "near_z");
    SK_CHECK_DETAIL(projection_ndc_depth(ProjectionDepth{}, -1.0), Status::InvalidArgument, "eye_distance");
    SK_CHECK_DETAIL(projection_window_depth(bad_near(), 1.0), Status::NonFinite, "near_z");
    SK_CHECK_DETAIL(projection_eye_distance_from_window_depth(bad_near(), 0.5), Status::NonFinite, "near_z");
    SK_CHECK_DETAIL(projection_eye_distance_from_window_depth(ProjectionDepth{}, 1.5), Status::InvalidArgument, "window");
    SK_CHECK_DETAIL(projection_depth_resolution(bad_near(), DepthFormat::Fixed24, 1.0), Status::NonFinite, "near_z");
    SK_CHECK_DETAIL(projection_depth_resolution(ProjectionDepth{}, static_cast<DepthFormat>(9), 1.0), Status::InvalidArgument,
                    "format");
    SK_CHECK_DETAIL(projection_infinite_epsilon_bound(kNaN, 1.0f, ClipDepth::NegativeOneToOne, false, DepthFormat::Fixed24),
                    Status::NonFinite, "fovy");
    SK_CHECK_DETAIL(projection_infinite_epsilon_bound(1.0f, 1.0f, ClipDepth::NegativeOneToOne, false, DepthFormat::Fixed24, -1.0f),
                    Status::InvalidArgument, "ulps_per_op");
}

TEST_CASE("infinite_projection: Ok results carry no detail") {
    ProjectionDepth fin;
    fin.far_z = 100.0f;
    SK_CHECK_OK_NO_DETAIL(projection_depth_mapping(ProjectionDepth{}));
    SK_CHECK_OK_NO_DETAIL(projection_frustum(-1.0f, 1.0f, -1.0f, 1.0f, fin));
    SK_CHECK_OK_NO_DETAIL(projection_perspective(1.0f, 1.5f, ProjectionDepth{}));
    SK_CHECK_OK_NO_DETAIL(projection_perspective_infinite(1.0f, 1.0f, 0.1f));
    SK_CHECK_OK_NO_DETAIL(projection_perspective_finite(1.0f, 1.0f, 0.1f, 100.0f));
    SK_CHECK_OK_NO_DETAIL(projection_ndc_depth(fin, 5.0));
    SK_CHECK_OK_NO_DETAIL(projection_window_depth(fin, 5.0));
    SK_CHECK_OK_NO_DETAIL(projection_eye_distance_from_window_depth(fin, 0.5));
    SK_CHECK_OK_NO_DETAIL(projection_depth_resolution(fin, DepthFormat::Fixed24, 5.0));
    SK_CHECK_OK_NO_DETAIL(projection_infinite_epsilon_bound(1.0f, 1.0f, ClipDepth::NegativeOneToOne, false, DepthFormat::Fixed24));
}
