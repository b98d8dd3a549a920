// Where a status came from (issue #25 item 6): the first validation of every public function of
// shadow_bias.hpp that returns a result names the offending input in `detail`; Ok gives nullptr.
#include <shadowkit/shadow_bias.hpp>

#include "status_detail.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <limits>

using namespace shadowkit;

namespace {
const float kNaN = std::numeric_limits<float>::quiet_NaN();
const double kNaNd = std::numeric_limits<double>::quiet_NaN();
const BiasDepthMetric kPP = BiasDepthMetric::PostProjective;
glm::mat4 light_vp() {
    return glm::perspective(1.0f, 1.0f, 0.5f, 50.0f) *
           glm::lookAt(glm::vec3(0.0f, 10.0f, 0.0f), glm::vec3(0.0f), glm::vec3(0.0f, 0.0f, -1.0f));
}
}  // namespace

TEST_CASE("shadow_bias: the first validation of each function names its input") {
    SK_CHECK_DETAIL(bias_quantize_depth(DepthFormat::Fixed24, kNaNd), Status::NonFinite, "v");
    SK_CHECK_DETAIL(bias_depth_format_step(DepthFormat::Fixed24, kNaNd), Status::NonFinite, "v");
    SK_CHECK_DETAIL(bias_depth_metric_value(kPP, kNaNd, 0.1, 100.0), Status::NonFinite, "d");
    SK_CHECK_DETAIL(bias_depth_metric_value(kPP, 1.0, 0.1, 0.05), Status::InvalidArgument, "f: not > n");
    SK_CHECK_DETAIL(bias_depth_metric_slope(kPP, 1.0, kNaNd, 100.0), Status::NonFinite, "n");
    SK_CHECK_DETAIL(bias_window_from_world(-1.0, kPP, 1.0, 0.1, 100.0), Status::InvalidArgument, "bias_world");
    SK_CHECK_DETAIL(bias_world_from_window(kNaNd, kPP, 1.0, 0.1, 100.0), Status::NonFinite, "bias_window");
    SK_CHECK_DETAIL(bias_depth_metric_resolution(kPP, DepthFormat::Fixed24, 1.0, 0.1, kNaNd), Status::NonFinite, "f");
    SK_CHECK_DETAIL(bias_depth_metric_resolution(kPP, DepthFormat::Fixed24, 200.0, 0.1, 100.0), Status::InvalidArgument,
                    "d: outside");
    SK_CHECK_DETAIL(bias_texel_world_size_perspective(1.0f, kNaN, 512.0f), Status::NonFinite, "fov");
    SK_CHECK_DETAIL(bias_texel_world_size_perspective(1.0f, 3.5f, 512.0f), Status::InvalidArgument, "fov");
    SK_CHECK_DETAIL(bias_texel_world_size_ortho(10.0f, kNaN), Status::NonFinite, "resolution");
    SK_CHECK_DETAIL(bias_light_tan_angle(glm::vec3(0.0f, kNaN, 0.0f), glm::vec3(0.0f, 1.0f, 0.0f)), Status::NonFinite,
                    "normal");
    SK_CHECK_DETAIL(bias_light_tan_angle(glm::vec3(0.0f, 1.0f, 0.0f), glm::vec3(0.0f)), Status::InvalidArgument,
                    "to_light");
    SK_CHECK_DETAIL(bias_plane_depth_gradient(glm::vec3(0, 1, 0), glm::vec3(1, 0, 0), glm::vec3(0, 0, kNaN), glm::vec3(0, -1, 0)),
                    Status::NonFinite, "up");
    SK_CHECK_DETAIL(bias_texel_depth_delta(glm::vec2(1.0f), kNaN), Status::NonFinite, "texel_world");
    SK_CHECK_DETAIL(bias_slope_scaled(1.0f, 0.5f, 0.7f, kNaN), Status::NonFinite, "constant");
    SK_CHECK_DETAIL(bias_slope_scaled(1.0f, -0.5f), Status::InvalidArgument, "tan_theta");
    SK_CHECK_DETAIL(bias_polygon_offset_r(DepthFormat::Fixed24, kNaN), Status::NonFinite, "max_window_z");
    SK_CHECK_DETAIL(bias_polygon_offset(1.0f, 1.0f, kNaN, 0.0f, DepthFormat::Fixed24, 1.0f), Status::NonFinite, "dzdx");
    SK_CHECK_DETAIL(bias_polygon_offset_units_for_world_bias(kNaNd, kPP, DepthFormat::Fixed24, 1.0, 0.1, 100.0),
                    Status::NonFinite, "world_bias");
    SK_CHECK_DETAIL(bias_normal_offset_position(glm::vec3(0.0f), glm::vec3(0, 1, 0), glm::vec3(kNaN), 1.0f, 1.0f),
                    Status::NonFinite, "to_light");
    SK_CHECK_DETAIL(bias_receiver_plane_depth_gradient(glm::vec3(1.0f), glm::vec3(kNaN)), Status::NonFinite, "duvz_dy");
    SK_CHECK_DETAIL(bias_receiver_plane_depth(0.5f, glm::vec2(0.0f), glm::vec2(kNaN)), Status::NonFinite, "offset_uv");
    SK_CHECK_DETAIL(bias_receiver_plane_texel_bias(glm::vec2(0.0f), glm::vec2(kNaN)), Status::NonFinite, "texel_uv");
    SK_CHECK_DETAIL(bias_second_depth_value(0.2f, 0.4f, kNaN), Status::NonFinite, "max_offset");
    SK_CHECK_DETAIL(bias_plane_gradient(light_vp(), ClipDepth::NegativeOneToOne, glm::vec3(kNaN), glm::vec3(0, 1, 0)),
                    Status::NonFinite, "world_pos");
    SK_CHECK_DETAIL(bias_auto_depth_step(static_cast<DepthFormat>(7)), Status::InvalidArgument, "f");
    SK_CHECK_DETAIL(bias_auto_epsilon(glm::vec2(0.0f), 1.0f, 0.0f, glm::vec2(0.0f), 0.5f, 0.0f, false),
                    Status::InvalidArgument, "texel_uv");
    SK_CHECK_DETAIL(bias_auto_lookup(light_vp(), ClipDepth::NegativeOneToOne, false, glm::vec3(0.0f), glm::vec3(0, 1, 0),
                                     glm::ivec2(0, 512), DepthFormat::Float32),
                    Status::InvalidArgument, "map_size");
    SK_CHECK_DETAIL(bias_auto_filtered(glm::vec2(kNaN), 1.0f, 0.0f, glm::vec2(0.01f), 0.5f, 0.0f, false), Status::NonFinite,
                    "dz_duv");
    // a propagated status keeps the inner function's detail
    SK_CHECK_DETAIL(bias_polygon_offset(1.0f, 1.0f, 0.0f, 0.0f, static_cast<DepthFormat>(9), 1.0f), Status::InvalidArgument,
                    "unknown DepthFormat");
}

TEST_CASE("shadow_bias: Ok results carry no detail") {
    SK_CHECK_OK_NO_DETAIL(bias_quantize_depth(DepthFormat::Fixed24, 0.5));
    SK_CHECK_OK_NO_DETAIL(bias_depth_metric_resolution(kPP, DepthFormat::Fixed24, 1.0, 0.1, 100.0));
    SK_CHECK_OK_NO_DETAIL(bias_window_from_world(0.01, kPP, 1.0, 0.1, 100.0));
    SK_CHECK_OK_NO_DETAIL(bias_texel_world_size_perspective(1.0f, 1.0f, 512.0f));
    SK_CHECK_OK_NO_DETAIL(bias_light_tan_angle(glm::vec3(0, 1, 0), glm::vec3(1, 1, 0)));
    SK_CHECK_OK_NO_DETAIL(bias_slope_scaled(1.0f, 0.5f));
    SK_CHECK_OK_NO_DETAIL(bias_normal_offset_position(glm::vec3(0.0f), glm::vec3(0, 1, 0), glm::vec3(1, 1, 0), 1.0f, 1.0f));
    SK_CHECK_OK_NO_DETAIL(bias_auto_lookup(light_vp(), ClipDepth::NegativeOneToOne, false, glm::vec3(0.3f, 0.0f, 0.2f),
                                           glm::vec3(0, 1, 0), glm::ivec2(512), DepthFormat::Float32));
    SK_CHECK_OK_NO_DETAIL(bias_auto_filtered(glm::vec2(0.01f), 1.0f, 0.0f, glm::vec2(0.01f), 0.5f, 0.0f, false));
}
