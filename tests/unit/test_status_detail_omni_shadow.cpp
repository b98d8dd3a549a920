// Where a status came from (issue #25 item 6): the first validation of every public function of
// omni_shadow.hpp that returns a result names the offending input in `detail`; Ok gives nullptr.
#include <shadowkit/omni_shadow.hpp>

#include "status_detail.hpp"

#include <cstddef>
#include <cstdint>
#include <limits>

using namespace shadowkit;

namespace {
const float kNaN = std::numeric_limits<float>::quiet_NaN();
const glm::vec4 kPoint(0.0f, 3.0f, 0.0f, 1.0f);
}  // namespace

TEST_CASE("omni_shadow: the first validation of each function names its input") {
    OmniCubeInput ci;
    ci.light_position = glm::vec4(0.0f, 1.0f, 0.0f, 0.0f);  // directional: no cube
    SK_CHECK_DETAIL(omni_cube_matrices(ci), Status::InvalidLight, "light_position");
    ci.light_position = kPoint;
    ci.near_z = 0.0f;
    SK_CHECK_DETAIL(omni_cube_matrices(ci), Status::InvalidArgument, "near_z");
    SK_CHECK_DETAIL(omni_cube_face(glm::vec3(kNaN)), Status::NonFinite, "d");
    SK_CHECK_DETAIL(omni_cube_direction(static_cast<OmniCubeFace>(6), glm::vec2(0.5f)), Status::InvalidArgument, "face");
    SK_CHECK_DETAIL(omni_cube_texel_angle(0), Status::InvalidArgument, "size");
    SK_CHECK_DETAIL(omni_linear_depth(1.0f, kNaN, DepthFormat::Float32), Status::NonFinite, "range");
    OmniBiasInput bi;
    bi.range = 10.0f;
    bi.texel_angle = 0.01f;
    bi.cos_theta = kNaN;
    SK_CHECK_DETAIL(omni_distance_bias(bi), Status::NonFinite, "cos_theta");
    bi.cos_theta = 1.0f;
    bi.texel_angle = 0.0f;  // the required field left at its default
    SK_CHECK_DETAIL(omni_distance_bias(bi), Status::InvalidArgument, "texel_angle");
    OmniCullInput cu;
    cu.light_position = kPoint;
    std::uint8_t masks[4];
    SK_CHECK_DETAIL(omni_cull_casters(cu, nullptr, 4), Status::InvalidArgument, "face_masks");
    cu.box_count = 2;  // boxes null
    SK_CHECK_DETAIL(omni_cull_casters(cu, masks, 4), Status::InvalidArgument, "boxes");
    std::size_t off[7];
    SK_CHECK_DETAIL(omni_cull_face_lists(cu, nullptr, 0, nullptr), Status::InvalidArgument, "face_offsets");
    const float box[12] = {-1, 0, -1, 1, 1, 1, 2, 0, 2, 3, 1, 3};
    cu.boxes = box;
    SK_CHECK_DETAIL(omni_cull_face_lists(cu, nullptr, 0, off), Status::BufferTooSmall, "capacity");
    SK_CHECK_DETAIL(omni_cull_casters(cu, masks, 1), Status::BufferTooSmall, "mask_capacity");
    SK_CHECK_DETAIL(omni_paraboloid_frame(glm::vec4(0.0f, 0.0f, 0.0f, -1.0f), glm::vec3(0, 1, 0), glm::vec3(1, 0, 0)),
                    Status::InvalidLight, "light_position");
    SK_CHECK_DETAIL(omni_paraboloid_frame(kPoint, glm::vec3(0, 1, 0), glm::vec3(0, 2, 0)), Status::InvalidArgument, "up");
    SK_CHECK_DETAIL(omni_paraboloid_project(glm::vec3(0.0f)), Status::InvalidArgument, "d");
    SK_CHECK_DETAIL(omni_paraboloid_unproject(static_cast<OmniHemisphere>(2), glm::vec2(0.0f)), Status::InvalidArgument, "h");
    SK_CHECK_DETAIL(omni_paraboloid_texel_angle(0, 0.5f), Status::InvalidArgument, "size");
    SK_CHECK_DETAIL(omni_paraboloid_edge_error(kNaN, 1.0f, 512), Status::NonFinite, "edge_length");
    SK_CHECK_DETAIL(omni_paraboloid_max_edge_length(1.0f, 512, -1.0f), Status::InvalidArgument, "max_texels");
}

TEST_CASE("omni_shadow: Ok results carry no detail") {
    OmniCubeInput ci;
    ci.light_position = kPoint;
    SK_CHECK_OK_NO_DETAIL(omni_cube_matrices(ci));
    SK_CHECK_OK_NO_DETAIL(omni_cube_face(glm::vec3(1, 0.5f, 0)));
    SK_CHECK_OK_NO_DETAIL(omni_cube_direction(OmniCubeFace::PositiveY, glm::vec2(0.3f)));
    SK_CHECK_OK_NO_DETAIL(omni_linear_depth(1.0f, 10.0f, DepthFormat::Fixed24));
    OmniBiasInput bi;
    bi.range = 10.0f;
    bi.texel_angle = 0.01f;
    SK_CHECK_OK_NO_DETAIL(omni_distance_bias(bi));
    OmniCullInput cu;
    cu.light_position = kPoint;
    const float box[6] = {-1, 0, -1, 1, 1, 1};
    cu.boxes = box;
    cu.box_count = 1;
    std::uint8_t masks[1];
    SK_CHECK_OK_NO_DETAIL(omni_cull_casters(cu, masks, 1));
    std::uint32_t lists[6];
    std::size_t off[7];
    SK_CHECK_OK_NO_DETAIL(omni_cull_face_lists(cu, lists, 6, off));
    SK_CHECK_OK_NO_DETAIL(omni_paraboloid_frame(kPoint, glm::vec3(0, 1, 0), glm::vec3(1, 0, 0)));
    SK_CHECK_OK_NO_DETAIL(omni_paraboloid_project(glm::vec3(0.2f, 1, 0)));
    SK_CHECK_OK_NO_DETAIL(omni_paraboloid_unproject(OmniHemisphere::Back, glm::vec2(0.1f)));
    SK_CHECK_OK_NO_DETAIL(omni_paraboloid_texel_angle(512, 0.5f));
    SK_CHECK_OK_NO_DETAIL(omni_paraboloid_edge_error(0.1f, 1.0f, 512));
    SK_CHECK_OK_NO_DETAIL(omni_paraboloid_max_edge_length(1.0f, 512, 0.5f));
}
