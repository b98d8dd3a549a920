// Where a status came from (issue #25 item 6): the first validation of every public function of
// light_frustum.hpp that returns a result names the offending input in `detail`; Ok gives nullptr.
#include <shadowkit/light_frustum.hpp>

#include "status_detail.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <cstdint>
#include <limits>

using namespace shadowkit;

namespace {
const float kNaN = std::numeric_limits<float>::quiet_NaN();
LightFrustumInput base_input() {
    LightFrustumInput in;
    in.camera_view = glm::lookAt(glm::vec3(0, 2, 0), glm::vec3(0, 2, -1), glm::vec3(0, 1, 0));
    in.camera_proj = glm::perspective(1.0f, 1.0f, 0.1f, 50.0f);
    in.light_position = glm::vec4(0, 1, 0, 0);
    return in;
}
LightCasterFitInput caster_input() {
    LightCasterFitInput in;
    in.light_position = glm::vec4(0, 1, 0, 0);
    in.caster_min = glm::vec3(-1.0f);
    in.caster_max = glm::vec3(1.0f);
    in.receiver_min = glm::vec3(-5.0f, -2.0f, -5.0f);
    in.receiver_max = glm::vec3(5.0f, 2.0f, 5.0f);
    return in;
}
}  // namespace

TEST_CASE("light_frustum: the first validation of each function names its input") {
    {  // slice corners: camera_view is checked first
        LightFrustumInput in = base_input();
        in.camera_view[1][1] = kNaN;
        SK_CHECK_DETAIL(light_frustum_slice_corners(in), Status::NonFinite, "camera_view");
        in = base_input();  // a later check: the near plane behind the eye
        in.camera_proj = glm::perspective(1.0f, 1.0f, -0.1f, 50.0f);
        SK_CHECK_DETAIL(light_frustum_slice_corners(in), Status::InvalidArgument, "camera_proj");
    }
    {  // extruded planes: null vertices with a count
        SK_CHECK_DETAIL(light_frustum_extruded_planes(nullptr, 3, nullptr, 0, glm::vec4(0, 1, 0, 0)), Status::InvalidArgument,
                        "receiver_vertices");
        const glm::dvec3 v[1] = {glm::dvec3(0.0)};
        SK_CHECK_DETAIL(light_frustum_extruded_planes(v, 1, nullptr, 0, glm::vec4(0, 1, 0, -1)), Status::InvalidLight,
                        "light_position: w < 0");
    }
    {  // fit: casters null with a count
        LightFrustumInput in = base_input();
        in.caster_count = 2;
        SK_CHECK_DETAIL(light_frustum_fit(in, nullptr, 0), Status::InvalidArgument, "casters");
        in = base_input();
        in.light_position = glm::vec4(0.0f);
        SK_CHECK_DETAIL(light_frustum_fit(in, nullptr, 0), Status::InvalidLight, "light_position");
        in = base_input();
        in.camera_proj = glm::perspective(1.0f, 1.0f, -0.1f, 50.0f);
        SK_CHECK_DETAIL(light_frustum_fit(in, nullptr, 0), Status::InvalidArgument, "camera_proj: near plane");
        in = base_input();  // BufferTooSmall names the capacity
        const float box[6] = {-1.0f, 0.0f, -6.0f, 1.0f, 1.0f, -4.0f};
        in.casters = box;
        in.caster_count = 1;
        SK_CHECK_DETAIL(light_frustum_fit(in, nullptr, 0), Status::BufferTooSmall, "capacity");
    }
    {  // fit_casters: caster box NaN
        LightCasterFitInput in = caster_input();
        in.caster_min.x = kNaN;
        SK_CHECK_DETAIL(light_frustum_fit_casters(in), Status::NonFinite, "caster_min");
        in = caster_input();
        in.light_position = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);  // a point light at the casters' center
        SK_CHECK_DETAIL(light_frustum_fit_casters(in), Status::LightInsideVolume, "light_position");
    }
}

TEST_CASE("light_frustum: Ok results carry no detail") {
    const LightFrustumInput in = base_input();
    SK_CHECK_OK_NO_DETAIL(light_frustum_slice_corners(in));
    std::uint32_t kept[4];
    SK_CHECK_OK_NO_DETAIL(light_frustum_fit(in, kept, 4));
    SK_CHECK_OK_NO_DETAIL(light_frustum_fit_casters(caster_input()));
    const glm::dvec3 v[1] = {glm::dvec3(0.0)};
    SK_CHECK_OK_NO_DETAIL(light_frustum_extruded_planes(v, 1, nullptr, 0, glm::vec4(0, 1, 0, 0)));
}
