// Where a status came from (issue #25 item 6): the first validation of every public function of
// silhouette.hpp that returns a result names the offending input in `detail`; Ok gives nullptr.
#include <shadowkit/silhouette.hpp>

#include "status_detail.hpp"

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

using namespace shadowkit;

namespace {
const float kNaN = std::numeric_limits<float>::quiet_NaN();
// a tetrahedron (closed, 4 faces, 6 edges)
const glm::vec3 kPos[4] = {glm::vec3(0, 0, 0), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, 0, 1)};
const std::uint32_t kIdx[12] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
const glm::vec4 kLight(2.0f, 3.0f, 4.0f, 1.0f);
struct Serial {
    template <class Fn>
    void operator()(std::size_t n, Fn&& fn) const {
        for (std::size_t i = 0; i < n; ++i) fn(i);
    }
};
}  // namespace

TEST_CASE("silhouette: the first validation of each function names its input") {
    SK_CHECK_DETAIL(silhouette_build_adjacency(nullptr, 4, kIdx, 12), Status::InvalidArgument, "positions");
    const std::uint32_t bad_idx[3] = {0, 1, 7};
    SK_CHECK_DETAIL(silhouette_build_adjacency(kPos, 4, bad_idx, 3), Status::IndexOutOfRange, "indices");
    SK_CHECK_DETAIL(silhouette_face_orientation(glm::vec3(kNaN), kPos[1], kPos[2], kLight), Status::NonFinite, "a");
    const SilhouetteAdjacency adj = silhouette_build_adjacency(kPos, 4, kIdx, 12);
    REQUIRE(adj.status == Status::Ok);
    const SilhouetteAdjacency none;  // NotRun
    std::vector<std::uint8_t> facing(4);
    std::vector<std::uint32_t> idx(silhouette_indices_capacity(adj));
    std::vector<std::uint8_t> flags(idx.size() / 2);
    SK_CHECK_DETAIL(silhouette_compute_facing(none, kPos, 4, kLight, facing.data(), 4), Status::InvalidArgument, "adj");
    SK_CHECK_DETAIL(silhouette_compute_facing(adj, kPos, 4, kLight, facing.data(), 2), Status::BufferTooSmall, "facing_capacity");
    SK_CHECK_DETAIL(silhouette_extract(none, facing.data(), 4, idx.data(), idx.size(), nullptr, 0), Status::InvalidArgument, "adj");
    SK_CHECK_DETAIL(silhouette_extract_two_sided(adj, facing.data(), 3, idx.data(), idx.size(), nullptr, 0), Status::InvalidArgument,
                    "facing_count");
    SK_CHECK_DETAIL(silhouette_compute_facing_chunk(adj, kPos, 4, kLight, facing.data(), 4, 0, 0), Status::InvalidArgument,
                    "chunk_count");
    SK_CHECK_DETAIL(silhouette_extract_chunk(adj, facing.data(), 4, idx.data(), idx.size(), nullptr, 0, 2, 2),
                    Status::InvalidArgument, "chunk");
    SK_CHECK_DETAIL(silhouette_compact_chunks(adj, nullptr, 1, idx.data(), idx.size(), nullptr, 0), Status::InvalidArgument,
                    "chunks");
    std::vector<SilhouetteResult> chunks(2);
    SK_CHECK_DETAIL(silhouette_extract_parallel(adj, kPos, 4, kLight, facing.data(), 4, idx.data(), idx.size(), nullptr, 0,
                                                nullptr, 2, Serial{}),
                    Status::InvalidArgument, "chunk_results");
    SK_CHECK_DETAIL(silhouette_build_planes(none, kPos, 4), Status::InvalidArgument, "adj");
    const SilhouettePlanes pl = silhouette_build_planes(adj, kPos, 4);
    REQUIRE(pl.status == Status::Ok);
    const SilhouettePlanes no_planes;
    SK_CHECK_DETAIL(silhouette_compute_facing_planes(adj, no_planes, kLight, facing.data(), 4), Status::InvalidArgument, "planes");
    SK_CHECK_DETAIL(silhouette_compute_facing_planes_chunk(adj, pl, kLight, facing.data(), 4, 0, 0), Status::InvalidArgument,
                    "chunk_count");
    SK_CHECK_DETAIL(silhouette_extract_planes(adj, pl, nullptr, 4, idx.data(), idx.size(), nullptr, 0), Status::InvalidArgument,
                    "facing");
    SK_CHECK_DETAIL(silhouette_extract_planes_side_quads(none, pl, facing.data(), 4, idx.data(), idx.size()), Status::InvalidArgument,
                    "adj");
    SK_CHECK_DETAIL(silhouette_extract_planes_chunk(adj, pl, facing.data(), 4, idx.data(), idx.size(), nullptr, 0, 0, 0),
                    Status::InvalidArgument, "chunk_count");
    SK_CHECK_DETAIL(silhouette_extract_parallel_planes(adj, pl, kLight, facing.data(), 4, idx.data(), idx.size(), nullptr, 0,
                                                       chunks.data(), 0, Serial{}),
                    Status::InvalidArgument, "chunk_count");
    SK_CHECK_DETAIL(silhouette_compute(adj, kPos, 4, glm::vec4(0.0f)), Status::InvalidLight, "light_position");
}

TEST_CASE("silhouette: Ok results carry no detail") {
    const SilhouetteAdjacency adj = silhouette_build_adjacency(kPos, 4, kIdx, 12);
    SK_CHECK_OK_NO_DETAIL(adj);
    SK_CHECK_OK_NO_DETAIL(silhouette_face_orientation(kPos[0], kPos[2], kPos[1], kLight));
    std::vector<std::uint8_t> facing(4);
    SK_CHECK_OK_NO_DETAIL(silhouette_compute_facing(adj, kPos, 4, kLight, facing.data(), 4));
    std::vector<std::uint32_t> idx(silhouette_indices_capacity(adj));
    std::vector<std::uint8_t> flags(idx.size() / 2);
    SK_CHECK_OK_NO_DETAIL(silhouette_extract(adj, facing.data(), 4, idx.data(), idx.size(), flags.data(), flags.size()));
    std::vector<std::uint32_t> two(silhouette_two_sided_indices_capacity(adj));
    SK_CHECK_OK_NO_DETAIL(silhouette_extract_two_sided(adj, facing.data(), 4, two.data(), two.size(), nullptr, 0));
    std::vector<SilhouetteResult> chunks(2);
    SK_CHECK_OK_NO_DETAIL(silhouette_extract_parallel(adj, kPos, 4, kLight, facing.data(), 4, idx.data(), idx.size(), flags.data(),
                                                      flags.size(), chunks.data(), 2, Serial{}));
    const SilhouettePlanes pl = silhouette_build_planes(adj, kPos, 4);
    SK_CHECK_OK_NO_DETAIL(pl);
    SK_CHECK_OK_NO_DETAIL(silhouette_compute_facing_planes(adj, pl, kLight, facing.data(), 4));
    SK_CHECK_OK_NO_DETAIL(silhouette_extract_planes(adj, pl, facing.data(), 4, idx.data(), idx.size(), nullptr, 0));
    std::vector<std::uint32_t> quads(3 * idx.size());
    SK_CHECK_OK_NO_DETAIL(silhouette_extract_planes_side_quads(adj, pl, facing.data(), 4, quads.data(), quads.size()));
    SK_CHECK_OK_NO_DETAIL(silhouette_extract_parallel_planes(adj, pl, kLight, facing.data(), 4, idx.data(), idx.size(), flags.data(),
                                                             flags.size(), chunks.data(), 2, Serial{}));
    SK_CHECK_OK_NO_DETAIL(silhouette_compute(adj, kPos, 4, kLight));
}
