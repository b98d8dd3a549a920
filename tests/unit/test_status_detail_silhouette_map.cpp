// Where a status came from (issue #25 item 6): the first validation of every public function of
// silhouette_map.hpp that returns a result names the offending input in `detail`; Ok gives nullptr.
#include <shadowkit/silhouette_map.hpp>

#include "status_detail.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <cstdint>
#include <limits>
#include <vector>

using namespace shadowkit;

namespace {
const float kNaN = std::numeric_limits<float>::quiet_NaN();
const glm::uvec2 kSize(8, 8);
const glm::mat4 kVP = glm::ortho(-2.0f, 2.0f, -2.0f, 2.0f, 0.1f, 20.0f) *
                      glm::lookAt(glm::vec3(0, 10, 0), glm::vec3(0), glm::vec3(0, 0, -1));
}  // namespace

TEST_CASE("silhouette_map: the first validation of each function names its input") {
    SilmapEdge out[4];
    const glm::vec3 pos[2] = {glm::vec3(-1, 0, 0), glm::vec3(1, 0, 0.3f)};
    SK_CHECK_DETAIL(silmap_project_edges(kVP, ClipDepth::NegativeOneToOne, kSize, pos, 2, nullptr, 1, out, 4),
                    Status::InvalidArgument, "edges");
    const std::uint32_t bad[2] = {0, 5};
    SK_CHECK_DETAIL(silmap_project_edges(kVP, ClipDepth::NegativeOneToOne, kSize, pos, 2, bad, 1, out, 4),
                    Status::IndexOutOfRange, "edges");
    glm::ivec2 cells[16];
    SK_CHECK_DETAIL(silmap_rasterize_edge(glm::vec2(kNaN), glm::vec2(1.0f), kSize, cells, 16), Status::NonFinite, "a");
    std::vector<glm::vec2> pts(64);
    std::vector<std::uint8_t> wts(64);
    std::vector<float> depth(64, 1.0f);
    SK_CHECK_DETAIL(silmap_build(nullptr, 0, glm::uvec2(0, 8), depth.data(), 0.0f, pts.data(), 64, wts.data(), 64),
                    Status::InvalidArgument, "size");
    SK_CHECK_DETAIL(silmap_build(nullptr, 0, kSize, depth.data(), 0.0f, pts.data(), 10, wts.data(), 64), Status::BufferTooSmall,
                    "points_capacity");
    SK_CHECK_DETAIL(silmap_reconstruct(glm::vec2(0.5f), glm::vec2(0.5f), glm::vec2(1.5f, 0.5f), glm::vec2(0.5f, 1.5f),
                                       glm::vec2(-0.5f, 0.5f), glm::vec2(0.5f, -0.5f), nullptr),
                    Status::InvalidArgument, "corner_lit");
    SK_CHECK_DETAIL(silmap_lookup(nullptr, wts.data(), depth.data(), kSize, glm::vec2(1.0f), 0.5f, 0.0f), Status::InvalidArgument,
                    "points");
    SK_CHECK_DETAIL(silmap_plain_lookup(depth.data(), kSize, glm::vec2(kNaN), 0.5f, 0.0f), Status::NonFinite, "q");
}

TEST_CASE("silhouette_map: Ok results carry no detail") {
    SilmapEdge out[4];
    const glm::vec3 pos[2] = {glm::vec3(-1, 0, 0), glm::vec3(1, 0, 0.3f)};
    const std::uint32_t idx[2] = {0, 1};
    SK_CHECK_OK_NO_DETAIL(silmap_project_edges(kVP, ClipDepth::NegativeOneToOne, kSize, pos, 2, idx, 1, out, 4));
    glm::ivec2 cells[64];
    SK_CHECK_OK_NO_DETAIL(silmap_rasterize_edge(glm::vec2(1.2f, 1.3f), glm::vec2(5.7f, 4.1f), kSize, cells, 64));
    std::vector<glm::vec2> pts(64);
    std::vector<std::uint8_t> wts(64);
    std::vector<float> depth(64, 1.0f);
    SK_CHECK_OK_NO_DETAIL(silmap_build(nullptr, 0, kSize, depth.data(), 0.0f, pts.data(), 64, wts.data(), 64));
    const bool lit[4] = {true, true, false, false};
    SK_CHECK_OK_NO_DETAIL(silmap_reconstruct(glm::vec2(0.5f), glm::vec2(0.5f), glm::vec2(1.5f, 0.5f), glm::vec2(0.5f, 1.5f),
                                             glm::vec2(-0.5f, 0.5f), glm::vec2(0.5f, -0.5f), lit));
    SK_CHECK_OK_NO_DETAIL(silmap_lookup(pts.data(), wts.data(), depth.data(), kSize, glm::vec2(3.0f), 0.5f, 0.0f));
    SK_CHECK_OK_NO_DETAIL(silmap_plain_lookup(depth.data(), kSize, glm::vec2(3.0f), 0.5f, 0.0f));
}
