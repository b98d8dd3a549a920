// Where a status came from (issue #25 item 6): the first validation of every public function of
// contact_shadow.hpp that returns a result names the offending input in `detail`; Ok gives nullptr.
#include <shadowkit/contact_shadow.hpp>

#include "status_detail.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <limits>
#include <vector>

using namespace shadowkit;

namespace {
const float kNaN = std::numeric_limits<float>::quiet_NaN();
const glm::mat4 kProj = glm::perspective(1.0f, 1.0f, 0.1f, 100.0f);
const glm::vec3 kPos(0.0f, -1.0f, -5.0f);
const glm::vec4 kLight(0.3f, 1.0f, 0.2f, 0.0f);
ContactShadowParams params() {
    ContactShadowParams p;
    p.length_world = 0.5f;
    return p;
}
}  // namespace

TEST_CASE("contact_shadow: the first validation of each function names its input") {
    ContactShadowParams p = params();
    p.length_world = kNaN;  // the first check
    SK_CHECK_DETAIL(contact_shadow_derive(64, 64, kProj, kPos, kLight, p), Status::NonFinite, "length_world");
    std::vector<float> depth(64 * 64, 1.0f);
    SK_CHECK_DETAIL(contact_shadow_march(depth.data(), depth.size(), 64, 64, kProj, kPos, kLight, p), Status::NonFinite,
                    "length_world");
    SK_CHECK_DETAIL(contact_shadow_march_aligned(depth.data(), depth.size(), 64, 64, kProj, kPos, kLight, p), Status::NonFinite,
                    "length_world");
    SK_CHECK_DETAIL(contact_shadow_derive(64, 64, kProj, kPos, kLight, ContactShadowParams{}), Status::InvalidArgument,
                    "length_world");
    SK_CHECK_DETAIL(contact_shadow_derive(64, 64, kProj, kPos, glm::vec4(0.0f), params()), Status::InvalidLight, "light_position");
    SK_CHECK_DETAIL(contact_shadow_march(nullptr, 0, 64, 64, kProj, kPos, kLight, params()), Status::InvalidArgument, "depth");
    SK_CHECK_DETAIL(contact_shadow_march_aligned(depth.data(), 10, 64, 64, kProj, kPos, kLight, params()), Status::BufferTooSmall,
                    "depth_capacity");
}

TEST_CASE("contact_shadow: Ok results carry no detail") {
    std::vector<float> depth(64 * 64, 1.0f);
    SK_CHECK_OK_NO_DETAIL(contact_shadow_derive(64, 64, kProj, kPos, kLight, params()));
    SK_CHECK_OK_NO_DETAIL(contact_shadow_march(depth.data(), depth.size(), 64, 64, kProj, kPos, kLight, params()));
    SK_CHECK_OK_NO_DETAIL(contact_shadow_march_aligned(depth.data(), depth.size(), 64, 64, kProj, kPos, kLight, params()));
}
