// Where a status came from (issue #25 item 6): the first validation of every public function of
// virtual_shadow_map.hpp that returns a result names the offending input in `detail`; Ok gives nullptr.
#include <shadowkit/virtual_shadow_map.hpp>

#include "status_detail.hpp"

#include <limits>
#include <vector>

using namespace shadowkit;

namespace {
const float kNaN = std::numeric_limits<float>::quiet_NaN();
VsmLayout layout() {
    VsmLayout L;
    L.page_texels = 16;
    L.virtual_texels = 128;
    L.level_count = 3;
    L.pool_pages = 8;
    L.level0_extent_world = 32.0;
    return L;
}
VsmFrame sun(const VsmPageRequest* req, std::size_t n) {
    VsmFrame f;
    f.light_position = glm::vec4(0.3f, 1.0f, 0.2f, 0.0f);
    f.requests = req;
    f.request_count = n;
    return f;
}
}  // namespace

TEST_CASE("virtual_shadow_map: the first validation of each function names its input") {
    VsmState s;
    VsmLayout bad = layout();
    bad.level0_extent_world = double(kNaN);
    SK_CHECK_DETAIL(vsm_state_init(bad, s), Status::NonFinite, "level0_extent_world");
    const VsmLayout def;  // level0_extent_world is required
    SK_CHECK_DETAIL(vsm_state_init(def, s), Status::InvalidArgument, "layout.level0_extent_world");
    bad = layout();
    bad.page_texels = 4;
    SK_CHECK_DETAIL(vsm_state_init(bad, s), Status::InvalidArgument, "layout.page_texels");
    bad = layout();
    bad.virtual_texels = 100;
    SK_CHECK_DETAIL(vsm_state_init(bad, s), Status::InvalidArgument, "layout.virtual_texels");
    bad = layout();
    bad.level_count = 0;
    SK_CHECK_DETAIL(vsm_state_init(bad, s), Status::InvalidArgument, "layout.level_count");
    bad = layout();
    bad.pool_pages = 0;
    SK_CHECK_DETAIL(vsm_state_init(bad, s), Status::InvalidArgument, "layout.pool_pages");
    bad = layout();
    bad.spot_far_world = bad.spot_near_world;
    SK_CHECK_DETAIL(vsm_state_init(bad, s), Status::InvalidArgument, "layout.spot_far_world");

    // before vsm_state_init
    VsmState none;
    std::vector<VsmPageRender> pages(8);
    std::uint32_t word = 0;
    SK_CHECK_DETAIL(vsm_requests_from_bitmask(none, &word, 1, nullptr, 0), Status::InvalidArgument, "s:");
    SK_CHECK_DETAIL(vsm_plan(none, sun(nullptr, 0), pages.data(), pages.size()), Status::InvalidArgument, "s:");
    SK_CHECK_DETAIL(vsm_slot_page(none, 0), Status::InvalidArgument, "s:");

    SK_CHECK_OK_NO_DETAIL(vsm_state_init(layout(), s));
    // before the first plan: no levels placed
    std::vector<std::uint32_t> block(vsm_gpu_block_words(s));
    SK_CHECK_DETAIL(vsm_gpu_block(s, glm::dvec3(0.0), block.data(), block.size()), Status::InvalidArgument, "vsm_plan");
    SK_CHECK_DETAIL(vsm_slot_page(s, 0), Status::InvalidArgument, "vsm_plan");

    std::vector<std::uint32_t> mask(vsm_bitmask_words(s), 0u);
    mask[0] = 0x7u;
    VsmPageRequest req[4];
    SK_CHECK_DETAIL(vsm_requests_from_bitmask(s, nullptr, mask.size(), req, 4), Status::InvalidArgument, "mask");
    SK_CHECK_DETAIL(vsm_requests_from_bitmask(s, mask.data(), mask.size() + 1, req, 4), Status::InvalidArgument, "word_count");
    SK_CHECK_DETAIL(vsm_requests_from_bitmask(s, mask.data(), mask.size(), nullptr, 4), Status::InvalidArgument, "out");
    SK_CHECK_DETAIL(vsm_requests_from_bitmask(s, mask.data(), mask.size(), req, 2), Status::BufferTooSmall, "out_capacity");
    const VsmRequestList rl = vsm_requests_from_bitmask(s, mask.data(), mask.size(), req, 4);
    SK_CHECK_OK_NO_DETAIL(rl);

    VsmFrame f = sun(req, rl.count);
    f.light_position = glm::vec4(kNaN);
    SK_CHECK_DETAIL(vsm_plan(s, f, pages.data(), pages.size()), Status::InvalidLight, "f.light_position");
    f = sun(req, rl.count);
    f.light_position = glm::vec4(0.0f, 0.0f, 0.0f, 0.0f);
    SK_CHECK_DETAIL(vsm_plan(s, f, pages.data(), pages.size()), Status::InvalidLight, "f.light_position");
    f = sun(req, rl.count);
    f.light_position.w = 1.0f;  // a spot light: needs its cone (and one level)
    SK_CHECK_DETAIL(vsm_plan(s, f, pages.data(), pages.size()), Status::InvalidLight, "spot_cone_half_angle_radians");
    f.spot_cone_half_angle_radians = kNaN;
    SK_CHECK_DETAIL(vsm_plan(s, f, pages.data(), pages.size()), Status::NonFinite, "spot_cone_half_angle_radians");
    f.spot_cone_half_angle_radians = 0.5f;
    SK_CHECK_DETAIL(vsm_plan(s, f, pages.data(), pages.size()), Status::InvalidLight, "f.spot_direction");
    f.spot_direction = glm::vec3(0.0f, -1.0f, 0.0f);
    SK_CHECK_DETAIL(vsm_plan(s, f, pages.data(), pages.size()), Status::InvalidLight, "layout.level_count");
    f = sun(req, rl.count);
    f.camera_position.x = double(kNaN);
    SK_CHECK_DETAIL(vsm_plan(s, f, pages.data(), pages.size()), Status::NonFinite, "f.camera_position");
    f = sun(nullptr, 2);
    SK_CHECK_DETAIL(vsm_plan(s, f, pages.data(), pages.size()), Status::InvalidArgument, "f.requests");
    f = sun(req, rl.count);
    f.moved_caster_count = 1;
    SK_CHECK_DETAIL(vsm_plan(s, f, pages.data(), pages.size()), Status::InvalidArgument, "f.moved_casters");
    f = sun(req, rl.count);
    SK_CHECK_DETAIL(vsm_plan(s, f, nullptr, pages.size()), Status::InvalidArgument, "pages");
    SK_CHECK_DETAIL(vsm_plan(s, f, pages.data(), 7), Status::InvalidArgument, "capacity");
    VsmPageRequest out_of_range{5, 0, 0};
    SK_CHECK_DETAIL(vsm_plan(s, sun(&out_of_range, 1), pages.data(), pages.size()), Status::IndexOutOfRange, "f.requests");
    f = sun(req, rl.count);
    f.camera_position.x = 1e300;
    SK_CHECK_DETAIL(vsm_plan(s, f, pages.data(), pages.size()), Status::Overflow, "f.camera_position");

    const VsmPlan p = vsm_plan(s, sun(req, rl.count), pages.data(), pages.size());
    SK_CHECK_OK_NO_DETAIL(p);
    REQUIRE(p.count == 3);
    // more distinct pages than the pool: a usable plan with BufferTooSmall
    std::vector<VsmPageRequest> many;
    for (std::uint32_t y = 0; y < 4; ++y)
        for (std::uint32_t x = 0; x < 4; ++x) many.push_back(VsmPageRequest{0, x, y});
    VsmState s2;
    REQUIRE(vsm_state_init(layout(), s2).status == Status::Ok);
    SK_CHECK_DETAIL(vsm_plan(s2, sun(many.data(), many.size()), pages.data(), pages.size()), Status::BufferTooSmall,
                    "layout.pool_pages");

    // caster lists of the plan's pages
    const float box[6] = {-1, -1, -1, 1, 1, 1};
    const float nan_box[6] = {-1, -1, -1, 1, kNaN, 1};
    std::uint32_t first[16], counts[16], idx[8];
    SK_CHECK_OK_NO_DETAIL(vsm_page_casters(s, pages.data(), p.count, box, 1, first, counts, idx, 8));
    SK_CHECK_DETAIL(vsm_page_casters(s, nullptr, p.count, box, 1, first, counts, idx, 8), Status::InvalidArgument, "pages");
    SK_CHECK_DETAIL(vsm_page_casters(s, pages.data(), p.count, nullptr, 1, first, counts, idx, 8), Status::InvalidArgument,
                    "bounds");
    SK_CHECK_DETAIL(vsm_page_casters(s, pages.data(), p.count, box, 1, nullptr, counts, idx, 8), Status::InvalidArgument,
                    "first");
    SK_CHECK_DETAIL(vsm_page_casters(s, pages.data(), p.count, box, 1, first, counts, nullptr, 8), Status::InvalidArgument,
                    "indices");
    SK_CHECK_DETAIL(vsm_page_casters(s, pages.data(), 9, box, 1, first, counts, idx, 8), Status::InvalidArgument, "count");
    VsmPageRender forged = pages[0];
    forged.slot = 7;
    SK_CHECK_DETAIL(vsm_page_casters(s, &forged, 1, box, 1, first, counts, idx, 8), Status::InvalidArgument, "last vsm_plan");
    SK_CHECK_DETAIL(vsm_page_casters(s, pages.data(), p.count, nan_box, 1, first, counts, idx, 8), Status::NonFinite, "bounds");

    // the GPU block and the slots
    SK_CHECK_OK_NO_DETAIL(vsm_gpu_block(s, glm::dvec3(0.0), block.data(), block.size()));
    SK_CHECK_DETAIL(vsm_gpu_block(s, glm::dvec3(0.0), nullptr, block.size()), Status::InvalidArgument, "out");
    SK_CHECK_DETAIL(vsm_gpu_block(s, glm::dvec3(0.0), block.data(), block.size() - 1), Status::BufferTooSmall, "capacity");
    SK_CHECK_DETAIL(vsm_gpu_block(s, glm::dvec3(double(kNaN)), block.data(), block.size()), Status::NonFinite, "anchor");
    SK_CHECK_DETAIL(vsm_slot_page(s, 8), Status::InvalidArgument, "slot");
    SK_CHECK_OK_NO_DETAIL(vsm_slot_page(s, 0));
    SK_CHECK_OK_NO_DETAIL(vsm_relative_matrix(glm::dmat4(1.0), glm::dvec3(1.0)));
    SK_CHECK_DETAIL(vsm_relative_matrix(glm::dmat4(1.0), glm::dvec3(double(kNaN))), Status::NonFinite, "anchor");
    SK_CHECK_DETAIL(vsm_relative_matrix(glm::dmat4(1e30), glm::dvec3(1e30)), Status::Overflow, "beyond float");
}
