// Where a status came from (issue #25 item 6): the first validation of every public function of
// shadow_cache.hpp that returns a result names the offending input in `detail`; Ok gives nullptr.
#include <shadowkit/shadow_cache.hpp>

#include "status_detail.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <limits>

using namespace shadowkit;

namespace {
const double kNaN = std::numeric_limits<double>::quiet_NaN();
glm::dmat4 ortho() { return glm::ortho(-10.0, 10.0, -10.0, 10.0, 0.0, 50.0); }
ShadowCacheMapState state(const glm::dmat4& m) { return shadow_cache_map_state(m, 256, 256); }
}  // namespace

TEST_CASE("shadow_cache: the first validation of each function names its input") {
    const float box[6] = {-1, -1, -1, 1, 1, 1};
    const float bad_box[6] = {-1, -1, -1, 1, float(kNaN), 1};
    SK_CHECK_OK_NO_DETAIL(shadow_cache_footprint(ortho(), 256, 256, box));
    SK_CHECK_DETAIL(shadow_cache_footprint(ortho(), 256, 256, nullptr), Status::InvalidArgument, "bounds");
    SK_CHECK_DETAIL(shadow_cache_footprint(ortho(), 0, 256, box), Status::InvalidArgument, "width");
    SK_CHECK_DETAIL(shadow_cache_footprint(glm::dmat4(kNaN), 256, 256, box), Status::NonFinite, "view_proj");
    SK_CHECK_DETAIL(shadow_cache_footprint(ortho(), 256, 256, bad_box), Status::NonFinite, "bounds");
    SK_CHECK_DETAIL(shadow_cache_footprint(glm::dmat4(0.0), 256, 256, box), Status::InvalidArgument, "view_proj");
    SK_CHECK_DETAIL(shadow_cache_footprint(glm::mat4(glm::dmat4(0.0)), 256, 256, box), Status::InvalidArgument, "view_proj");

    ShadowCacheMapState prev = state(ortho());
    prev.has_content = true;
    const ShadowCacheMapState cur = state(ortho());
    ShadowCacheRect rects[8];
    ShadowCacheCaster c;
    for (int k = 0; k < 6; ++k) c.bounds[k] = c.previous_bounds[k] = box[k];
    SK_CHECK_OK_NO_DETAIL(shadow_cache_plan(prev, cur, &c, 1, rects, 8));
    SK_CHECK_DETAIL(shadow_cache_plan(prev, cur, nullptr, 1, rects, 8), Status::InvalidArgument, "casters");
    SK_CHECK_DETAIL(shadow_cache_plan(prev, cur, &c, 1, nullptr, 8), Status::InvalidArgument, "rects");
    ShadowCacheMapState small = cur;
    small.width = 0;
    SK_CHECK_DETAIL(shadow_cache_plan(prev, small, &c, 1, rects, 8), Status::InvalidArgument, "current.width");
    SK_CHECK_DETAIL(shadow_cache_plan(prev, state(glm::dmat4(kNaN)), &c, 1, rects, 8), Status::NonFinite, "current.view_proj");
    SK_CHECK_DETAIL(shadow_cache_plan(prev, state(glm::dmat4(0.0)), &c, 1, rects, 8), Status::InvalidArgument,
                    "current.view_proj");
    ShadowCacheCaster nan_caster = c;
    nan_caster.bounds[2] = float(kNaN);
    SK_CHECK_DETAIL(shadow_cache_plan(prev, cur, &nan_caster, 1, rects, 8), Status::NonFinite, "casters");
    ShadowCacheMapState bad_prev = prev;
    bad_prev.height = -3;
    SK_CHECK_DETAIL(shadow_cache_plan(bad_prev, cur, &c, 1, rects, 8), Status::InvalidArgument, "previous.width");
    bad_prev = prev;
    bad_prev.view_proj = glm::dmat4(kNaN);
    SK_CHECK_DETAIL(shadow_cache_plan(bad_prev, cur, &c, 1, rects, 8), Status::NonFinite, "previous.view_proj");
    bad_prev.view_proj = glm::dmat4(0.0);
    SK_CHECK_DETAIL(shadow_cache_plan(bad_prev, cur, &c, 1, rects, 8), Status::InvalidArgument, "previous.view_proj");
    // no map volume: a singular orthographic matrix (x row zero) one texel away from the last
    glm::dmat4 flat = ortho();
    flat[0][0] = flat[1][0] = flat[2][0] = 0.0;
    ShadowCacheMapState flat_prev = state(flat);
    flat_prev.has_content = true;
    glm::dmat4 flat_moved = flat;
    flat_moved[3][1] += 2.0 / 256.0;
    SK_CHECK_DETAIL(shadow_cache_plan(flat_prev, state(flat_moved), &c, 1, rects, 8), Status::InvalidArgument,
                    "current.view_proj");
    // a rectangle to write and no room for it
    ShadowCacheMapState fresh = state(ortho());
    SK_CHECK_DETAIL(shadow_cache_plan(fresh, cur, &c, 1, rects, 0), Status::BufferTooSmall, "rect_capacity");
}
