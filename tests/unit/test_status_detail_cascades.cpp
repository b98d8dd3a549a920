// Where a status came from (issue #25 item 6): the first validation of every public function of
// cascades.hpp that returns a result names the offending input in `detail`; Ok gives nullptr.
#include <shadowkit/cascades.hpp>

#include "status_detail.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <limits>

using namespace shadowkit;

namespace {
const float kNaN = std::numeric_limits<float>::quiet_NaN();
CascadeInput input() {
    CascadeInput in;
    in.camera_view = glm::lookAt(glm::vec3(0, 5, 10), glm::vec3(0), glm::vec3(0, 1, 0));
    in.camera_proj = glm::perspective(1.0f, 1.5f, 0.5f, 100.0f);
    in.light_position = glm::vec4(0.3f, 1.0f, 0.2f, 0.0f);
    in.shadow_map_size = 1024;
    return in;
}
CascadeSdsmInput sdsm() {
    CascadeSdsmInput in;
    in.camera = input();
    in.view_min = 1.0f;
    in.view_max = 60.0f;
    return in;
}
}  // namespace

TEST_CASE("cascades: the first validation of each function names its input") {
    // cascade_split_distances
    SK_CHECK_OK_NO_DETAIL(cascade_split_distances(0.5f, 100.0f, 0.75f, 4));
    SK_CHECK_DETAIL(cascade_split_distances(kNaN, 100.0f, 0.75f, 4), Status::NonFinite, "near_z");
    SK_CHECK_DETAIL(cascade_split_distances(0.5f, std::numeric_limits<float>::infinity(), 0.75f, 4), Status::NonFinite,
                    "far_z");
    SK_CHECK_DETAIL(cascade_split_distances(0.5f, 100.0f, kNaN, 4), Status::NonFinite, "lambda");
    SK_CHECK_DETAIL(cascade_split_distances(0.5f, 100.0f, 0.75f, 0), Status::InvalidArgument, "count");
    SK_CHECK_DETAIL(cascade_split_distances(0.0f, 100.0f, 0.75f, 4), Status::InvalidArgument, "near_z");
    SK_CHECK_DETAIL(cascade_split_distances(0.5f, 0.5f, 0.75f, 4), Status::InvalidArgument, "far_z");
    SK_CHECK_DETAIL(cascade_split_distances(0.5f, 100.0f, 1.5f, 4), Status::InvalidArgument, "lambda");
    SK_CHECK_DETAIL(cascade_split_distances(1.0f, std::nextafter(1.0f, 2.0f), 0.5f, 8), Status::Overflow, "far_z");

    // cascade_fit_slice and cascade_fit: the common input check, then their own
    SK_CHECK_OK_NO_DETAIL(cascade_fit_slice(input(), 1.0f, 10.0f));
    CascadeInput in = input();
    in.camera_view[0][0] = kNaN;
    SK_CHECK_DETAIL(cascade_fit_slice(in, 1.0f, 10.0f), Status::NonFinite, "camera_view");
    in = input();
    in.light_position.w = 1.0f;
    SK_CHECK_DETAIL(cascade_fit_slice(in, 1.0f, 10.0f), Status::InvalidLight, "light_position");
    in = input();
    in.shadow_map_size = 2;
    SK_CHECK_DETAIL(cascade_fit_slice(in, 1.0f, 10.0f), Status::InvalidArgument, "shadow_map_size");
    in = input();
    in.radius_quantum = 0.0f;
    SK_CHECK_DETAIL(cascade_fit_slice(in, 1.0f, 10.0f), Status::InvalidArgument, "radius_quantum");
    in = input();
    in.max_distance = -1.0f;
    SK_CHECK_DETAIL(cascade_fit_slice(in, 1.0f, 10.0f), Status::InvalidArgument, "max_distance");
    in = input();
    in.has_caster_bounds = true;
    in.caster_min = glm::vec3(1.0f);
    SK_CHECK_DETAIL(cascade_fit_slice(in, 1.0f, 10.0f), Status::InvalidArgument, "caster_min");
    in = input();
    in.stable_world_depth = true;
    SK_CHECK_DETAIL(cascade_fit_slice(in, 1.0f, 10.0f), Status::InvalidArgument, "stable_world_depth");
    SK_CHECK_DETAIL(cascade_fit_slice(input(), kNaN, 10.0f), Status::NonFinite, "split_near");
    SK_CHECK_DETAIL(cascade_fit_slice(input(), 0.0f, 10.0f), Status::InvalidArgument, "split_near");
    SK_CHECK_DETAIL(cascade_fit_slice(input(), 5.0f, 4.0f), Status::InvalidArgument, "split_far");
    SK_CHECK_DETAIL(cascade_fit_slice(input(), 200.0f, 300.0f), Status::InvalidArgument, "camera's near and far");
    in = input();
    in.camera_proj = glm::perspective(1.0f, 1.5f, -0.5f, 100.0f);  // near plane behind the eye
    SK_CHECK_DETAIL(cascade_fit_slice(in, 1.0f, 10.0f), Status::InvalidArgument, "camera_proj");
    in = input();
    in.camera_view = glm::mat4(1.0f);
    in.camera_view[1] = glm::vec4(0.0f);  // singular view
    SK_CHECK_DETAIL(cascade_fit_slice(in, 1.0f, 10.0f), Status::InvalidArgument, "camera_view");

    Cascade c[4];
    SK_CHECK_OK_NO_DETAIL(cascade_fit(input(), 0.75f, 4, c, 4));
    SK_CHECK_DETAIL(cascade_fit(input(), 0.75f, 4, nullptr, 4), Status::InvalidArgument, "out_cascades");
    SK_CHECK_DETAIL(cascade_fit(input(), 0.75f, 0, c, 4), Status::InvalidArgument, "cascade_count");
    SK_CHECK_DETAIL(cascade_fit(input(), kNaN, 4, c, 4), Status::NonFinite, "lambda");
    SK_CHECK_DETAIL(cascade_fit(input(), 0.75f, 4, c, 3), Status::BufferTooSmall, "out_capacity");
    SK_CHECK_DETAIL(cascade_fit(input(), 2.0f, 4, c, 4), Status::InvalidArgument, "lambda");  // from the split distances
    in = input();
    in.camera_proj = glm::infinitePerspective(1.0f, 1.5f, 0.5f);
    SK_CHECK_DETAIL(cascade_fit(in, 0.75f, 4, c, 4), Status::InvalidArgument, "max_distance");
    in.max_distance = 50.0f;
    SK_CHECK_OK_NO_DETAIL(cascade_fit(in, 0.75f, 4, c, 4));

    // selection
    const CascadeFitResult fit = cascade_fit(input(), 0.75f, 4, c, 4);
    REQUIRE(fit.status == Status::Ok);
    SK_CHECK_OK_NO_DETAIL(cascade_select_by_depth(5.0f, fit.splits, 4));
    SK_CHECK_DETAIL(cascade_select_by_depth(5.0f, nullptr, 4), Status::InvalidArgument, "splits");
    SK_CHECK_DETAIL(cascade_select_by_depth(5.0f, fit.splits, 0), Status::InvalidArgument, "count");
    const float bad_splits[3] = {1.0f, 0.5f, 2.0f};
    SK_CHECK_DETAIL(cascade_select_by_depth(5.0f, bad_splits, 2), Status::InvalidArgument, "splits");
    SK_CHECK_DETAIL(cascade_select_by_depth(kNaN, fit.splits, 4), Status::NonFinite, "view_depth");
    SK_CHECK_OK_NO_DETAIL(cascade_select_by_sphere(glm::vec3(0.0f), c, 4));
    SK_CHECK_DETAIL(cascade_select_by_sphere(glm::vec3(0.0f), nullptr, 4), Status::InvalidArgument, "cascades");
    SK_CHECK_DETAIL(cascade_select_by_sphere(glm::vec3(0.0f), c, 17), Status::InvalidArgument, "count");
    Cascade not_ok[1];
    SK_CHECK_DETAIL(cascade_select_by_sphere(glm::vec3(0.0f), not_ok, 1), Status::InvalidArgument, "cascades");
    SK_CHECK_DETAIL(cascade_select_by_sphere(glm::vec3(kNaN), c, 4), Status::NonFinite, "world_pos");
}

TEST_CASE("cascades (SDSM): the first validation of each function names its input") {
    const glm::mat4 P = glm::perspective(1.0f, 1.5f, 0.5f, 100.0f);
    SK_CHECK_OK_NO_DETAIL(cascade_sdsm_view_range(P, ClipDepth::NegativeOneToOne, false, 0.2f, 0.9f));
    SK_CHECK_DETAIL(cascade_sdsm_view_range(P, ClipDepth::NegativeOneToOne, false, kNaN, 0.9f), Status::NonFinite, "window_min");
    SK_CHECK_DETAIL(cascade_sdsm_view_range(glm::mat4(kNaN), ClipDepth::NegativeOneToOne, false, 0.2f, 0.9f), Status::NonFinite,
                    "camera_proj");
    SK_CHECK_DETAIL(cascade_sdsm_view_range(P, ClipDepth::NegativeOneToOne, false, 0.9f, 0.2f), Status::InvalidArgument,
                    "window_min");
    SK_CHECK_DETAIL(cascade_sdsm_view_range(P, ClipDepth::NegativeOneToOne, false, 0.2f, 1.5f), Status::InvalidArgument,
                    "window_max");
    SK_CHECK_DETAIL(cascade_sdsm_view_range(glm::mat4(0.0f), ClipDepth::NegativeOneToOne, false, 0.2f, 0.9f),
                    Status::NonFinite, "camera_proj");
    // window depth 1 of an infinite projection: at infinity
    SK_CHECK_DETAIL(cascade_sdsm_view_range(glm::infinitePerspective(1.0f, 1.5f, 0.5f), ClipDepth::NegativeOneToOne, false,
                                            0.2f, 1.0f),
                    Status::InvalidArgument, "window_min, window_max");

    SK_CHECK_OK_NO_DETAIL(cascade_sdsm_light_view(glm::vec4(0.3f, 1.0f, 0.2f, 0.0f)));
    SK_CHECK_DETAIL(cascade_sdsm_light_view(glm::vec4(kNaN)), Status::InvalidLight, "light_position");
    SK_CHECK_DETAIL(cascade_sdsm_light_view(glm::vec4(0.3f, 1.0f, 0.2f, 1.0f)), Status::InvalidLight, "w != 0");

    Cascade c[4];
    SK_CHECK_OK_NO_DETAIL(cascade_sdsm_splits(sdsm(), nullptr));
    SK_CHECK_OK_NO_DETAIL(cascade_sdsm_fit(sdsm(), nullptr, c, 4));
    SK_CHECK_DETAIL(cascade_sdsm_fit(sdsm(), nullptr, nullptr, 4), Status::InvalidArgument, "out_cascades");
    SK_CHECK_DETAIL(cascade_sdsm_fit(sdsm(), nullptr, c, 3), Status::BufferTooSmall, "out_capacity");
    CascadeSdsmInput in = sdsm();
    in.cascade_count = 0;
    SK_CHECK_DETAIL(cascade_sdsm_fit(in, nullptr, c, 4), Status::InvalidArgument, "cascade_count");
    SK_CHECK_DETAIL(cascade_sdsm_splits(in, nullptr), Status::InvalidArgument, "cascade_count");
    in = sdsm();
    in.camera.light_position = glm::vec4(0.0f);
    SK_CHECK_DETAIL(cascade_sdsm_fit(in, nullptr, c, 4), Status::InvalidLight, "light_position");
    in = sdsm();
    in.view_min = kNaN;
    SK_CHECK_DETAIL(cascade_sdsm_fit(in, nullptr, c, 4), Status::NonFinite, "view_min");
    in = sdsm();
    in.view_max = 0.5f;
    SK_CHECK_DETAIL(cascade_sdsm_splits(in, nullptr), Status::InvalidArgument, "view_max");
    in = sdsm();
    in.margin = 0.7f;
    SK_CHECK_DETAIL(cascade_sdsm_fit(in, nullptr, c, 4), Status::InvalidArgument, "margin");
    in = sdsm();
    in.range_steps_per_octave = 0.0f;
    SK_CHECK_DETAIL(cascade_sdsm_fit(in, nullptr, c, 4), Status::InvalidArgument, "range_steps_per_octave");
    in = sdsm();
    in.lambda = -1.0f;
    SK_CHECK_DETAIL(cascade_sdsm_fit(in, nullptr, c, 4), Status::InvalidArgument, "lambda");
    in = sdsm();
    in.camera.stable_world_depth = true;
    in.camera.has_scene_bounds = true;
    in.camera.scene_max = glm::vec3(1.0f);
    SK_CHECK_DETAIL(cascade_sdsm_fit(in, nullptr, c, 4), Status::InvalidArgument, "stable_world_depth");
    in = sdsm();
    glm::vec4 rb[4] = {glm::vec4(0.0f), glm::vec4(kNaN), glm::vec4(0.0f), glm::vec4(0.0f)};
    in.receiver_bounds = rb;
    SK_CHECK_DETAIL(cascade_sdsm_fit(in, nullptr, c, 4), Status::NonFinite, "receiver_bounds");
    in = sdsm();
    in.camera.camera_view = glm::mat4(1.0f);
    in.camera.camera_view[2] = glm::vec4(0.0f);
    SK_CHECK_DETAIL(cascade_sdsm_fit(in, nullptr, c, 4), Status::InvalidArgument, "camera_view");
}
