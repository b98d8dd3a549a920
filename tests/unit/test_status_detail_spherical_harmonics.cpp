// Where a status came from (issue #25 item 6): the first validation of every public function of
// spherical_harmonics.hpp that returns a result names the offending input in `detail`; Ok gives nullptr.
#include <shadowkit/spherical_harmonics.hpp>

#include "status_detail.hpp"

#include <limits>

using namespace shadowkit;

namespace {
const float kNaN = std::numeric_limits<float>::quiet_NaN();
}  // namespace

TEST_CASE("spherical_harmonics: the first validation of each function names its input") {
    float out[25], c[25] = {1.0f}, zonal[5] = {1.0f, 0.5f, 0.25f, 0.1f, 0.05f};
    SK_CHECK_DETAIL(sh_evaluate(0, glm::vec3(0, 0, 1), out, 25), Status::InvalidArgument, "order");
    SK_CHECK_DETAIL(sh_evaluate(3, glm::vec3(0.0f), out, 25), Status::InvalidArgument, "dir");
    SK_CHECK_DETAIL(sh_reconstruct(9, c, 25, glm::vec3(0, 0, 1)), Status::InvalidArgument, "order");
    SK_CHECK_DETAIL(sh_reconstruct(3, c, 25, glm::vec3(kNaN)), Status::NonFinite, "dir");
    const glm::vec3 dirs[2] = {glm::vec3(0, 0, 1), glm::vec3(0, 1, 0)};
    const float vals[2] = {1.0f, kNaN};
    SK_CHECK_DETAIL(sh_project(0, dirs, vals, static_cast<const float*>(nullptr), 2, out, 25), Status::InvalidArgument, "order");
    SK_CHECK_DETAIL(sh_project(3, dirs, vals, static_cast<const float*>(nullptr), 2, out, 25), Status::NonFinite, "values");
    const glm::vec3 rgb[2] = {glm::vec3(1.0f), glm::vec3(1.0f)};
    glm::vec3 out_rgb[25];
    SK_CHECK_DETAIL(sh_project_rgb(6, dirs, rgb, static_cast<const float*>(nullptr), 2, out_rgb, 25), Status::InvalidArgument,
                    "order");
    glm::vec3 sd[16];
    SK_CHECK_DETAIL(sh_stratified_directions(0, 1u, sd, 16), Status::InvalidArgument, "strata");
    SK_CHECK_DETAIL(sh_make_rotation(0, glm::mat3(1.0f)), Status::InvalidArgument, "order");
    SK_CHECK_DETAIL(sh_make_rotation(3, glm::mat3(2.0f)), Status::InvalidArgument, "R");
    SK_CHECK_DETAIL(sh_rotate(SHRotation{}, c, 25, out, 25), Status::InvalidArgument, "rot");
    SK_CHECK_DETAIL(sh_rotate(3, glm::mat3(kNaN), c, 25, out, 25), Status::NonFinite, "R");
    SK_CHECK_DETAIL(sh_convolve_zonal(0, zonal, 5, c, 25, out, 25), Status::InvalidArgument, "order");
    SK_CHECK_DETAIL(sh_convolve_zonal(3, zonal, 1, c, 25, out, 25), Status::BufferTooSmall, "zonal_count");
    SK_CHECK_DETAIL(sh_convolve_clamped_cosine(0, c, 25, out, 25), Status::InvalidArgument, "order");
    SK_CHECK_DETAIL(sh_dot(0, c, 25, c, 25), Status::InvalidArgument, "order");
    SK_CHECK_DETAIL(sh_dot(3, c, 25, static_cast<const float*>(nullptr), 25), Status::InvalidArgument, "b");
}

TEST_CASE("spherical_harmonics: Ok results carry no detail") {
    float out[25], c[25] = {1.0f, 0.2f, 0.3f, 0.1f}, zonal[5] = {1.0f, 0.5f, 0.25f, 0.1f, 0.05f};
    SK_CHECK_OK_NO_DETAIL(sh_evaluate(3, glm::vec3(0, 0, 1), out, 25));
    SK_CHECK_OK_NO_DETAIL(sh_reconstruct(3, c, 25, glm::vec3(0, 0, 1)));
    const glm::vec3 dirs[2] = {glm::vec3(0, 0, 1), glm::vec3(0, 1, 0)};
    const float vals[2] = {1.0f, 2.0f};
    SK_CHECK_OK_NO_DETAIL(sh_project(3, dirs, vals, static_cast<const float*>(nullptr), 2, out, 25));
    const glm::vec3 rgb[2] = {glm::vec3(1.0f), glm::vec3(1.0f)};
    glm::vec3 out_rgb[25];
    SK_CHECK_OK_NO_DETAIL(sh_project_rgb(3, dirs, rgb, static_cast<const float*>(nullptr), 2, out_rgb, 25));
    glm::vec3 sd[16];
    SK_CHECK_OK_NO_DETAIL(sh_stratified_directions(4, 1u, sd, 16));
    const SHRotation rot = sh_make_rotation(3, glm::mat3(1.0f));
    SK_CHECK_OK_NO_DETAIL(rot);
    SK_CHECK_OK_NO_DETAIL(sh_rotate(rot, c, 25, out, 25));
    SK_CHECK_OK_NO_DETAIL(sh_rotate(3, glm::mat3(1.0f), c, 25, out, 25));
    SK_CHECK_OK_NO_DETAIL(sh_convolve_zonal(3, zonal, 5, c, 25, out, 25));
    SK_CHECK_OK_NO_DETAIL(sh_convolve_clamped_cosine(3, c, 25, out, 25));
    SK_CHECK_OK_NO_DETAIL(sh_dot(3, c, 25, c, 25));
}
