// Google Benchmark of virtual_shadow_map.hpp's vsm_plan at 16k requested pages (16 clipmap levels of
// 128 x 128 pages, the centered 32 x 32 pages of each level requested: 16384 pages), per frame:
//   BM_vsm_plan_steady: camera still, every page resident: the cost of keeping (lookups, LRU moves);
//   BM_vsm_plan_pan: the camera pans one level-0 page per frame: scrolled-out pages freed, the new
//     border pages allocated (LRU evictions once the pool is full), their matrices built;
//   BM_vsm_plan_casters: steady plus 16 moved casters (each a few pages) invalidated and re-rendered;
//   BM_vsm_plan_small_pool: a 4096-page pool for the 16384 requests: the coarser-level fallback.
// docs/virtual_shadow_map.md quotes the figures.
#include <shadowkit/virtual_shadow_map.hpp>

#include <benchmark/benchmark.h>

#include <cstdint>
#include <vector>

namespace {

struct VsmBench {
    shadowkit::VsmState state;
    std::vector<shadowkit::VsmPageRequest> requests;
    std::vector<shadowkit::VsmPageRender> pages;
    shadowkit::VsmFrame frame;
    explicit VsmBench(int pool) {
        shadowkit::VsmLayout L;  // defaults: 128-texel pages, 16k virtual, 16 levels
        L.level0_extent_world = 64.0;
        L.pool_pages = pool;
        shadowkit::vsm_state_init(L, state);
        for (std::uint32_t l = 0; l < 16; ++l)
            for (std::uint32_t y = 48; y < 80; ++y)
                for (std::uint32_t x = 48; x < 80; ++x) requests.push_back(shadowkit::VsmPageRequest{l, x, y});
        pages.resize(std::size_t(pool));
        frame.light_position = glm::vec4(0.3f, 1.0f, 0.2f, 0.0f);
        frame.camera_position = glm::dvec3(1.0e6, 0.0, -2.0e5);
        frame.requests = requests.data();
        frame.request_count = requests.size();
        shadowkit::vsm_plan(state, frame, pages.data(), pages.size());  // warm: everything resident
    }
};

void report(benchmark::State& st, const shadowkit::VsmPlan& p) {
    st.counters["requested"] = double(p.requested);
    st.counters["rendered"] = double(p.count);
    st.counters["evicted"] = double(p.evicted);
    st.SetItemsProcessed(st.iterations() * std::int64_t(p.requested));
}

void BM_vsm_plan_steady(benchmark::State& st) {
    VsmBench b(20000);
    shadowkit::VsmPlan p;
    for (auto _ : st) {
        p = shadowkit::vsm_plan(b.state, b.frame, b.pages.data(), b.pages.size());
        benchmark::DoNotOptimize(p);
    }
    report(st, p);
}

void BM_vsm_plan_pan(benchmark::State& st) {
    VsmBench b(20000);
    const glm::dvec3 step = b.state.axis_x * b.state.levels[0].page_world;
    shadowkit::VsmPlan p;
    for (auto _ : st) {
        b.frame.camera_position += step;
        p = shadowkit::vsm_plan(b.state, b.frame, b.pages.data(), b.pages.size());
        benchmark::DoNotOptimize(p);
    }
    report(st, p);
}

void BM_vsm_plan_casters(benchmark::State& st) {
    VsmBench b(20000);
    std::vector<shadowkit::VsmCasterMove> moves(16);
    const glm::dvec3 c = b.frame.camera_position;
    for (std::size_t i = 0; i < moves.size(); ++i) {
        const float x = float(c.x) + float(i) * 3.0f - 24.0f, z = float(c.z) + 5.0f;
        const float box[6] = {x, 0.0f, z, x + 1.0f, 2.0f, z + 1.0f};
        for (int k = 0; k < 6; ++k) moves[i].previous_bounds[k] = moves[i].bounds[k] = box[k];
        moves[i].bounds[0] += 0.5f;
        moves[i].bounds[3] += 0.5f;
    }
    b.frame.moved_casters = moves.data();
    b.frame.moved_caster_count = moves.size();
    shadowkit::VsmPlan p;
    for (auto _ : st) {
        p = shadowkit::vsm_plan(b.state, b.frame, b.pages.data(), b.pages.size());
        benchmark::DoNotOptimize(p);
    }
    report(st, p);
    st.counters["invalidated"] = double(p.invalidated);
}

void BM_vsm_plan_small_pool(benchmark::State& st) {
    VsmBench b(4096);
    shadowkit::VsmPlan p;
    for (auto _ : st) {
        p = shadowkit::vsm_plan(b.state, b.frame, b.pages.data(), b.pages.size());
        benchmark::DoNotOptimize(p);
    }
    report(st, p);
    st.counters["fallback"] = double(p.fallback);
}

}  // namespace

BENCHMARK(BM_vsm_plan_steady)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_vsm_plan_pan)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_vsm_plan_casters)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_vsm_plan_small_pool)->Unit(benchmark::kMicrosecond);
