// Google Benchmark of shadow_cache_plan (shadow_cache.hpp) with many moved casters on a 4096 x 4096
// orthographic map (docs/shadow_cache.md, "cost"):
//   disjoint:    32,000 casters on a grid, 22 texels apart, each moved by one texel: every caster's
//                old and new footprint overlap each other and nothing else (32,000 rectangles out);
//                `_diagonal`: moved by one texel in x and in y (three rectangles per caster exactly,
//                more than the capacity: each caster's two footprints merge into one, n in all)
//   overlapping: 32,000 casters scattered over a 256 x 256-texel patch: the footprints pile up
// The capacity is shadow_cache_rect_capacity(n) (no merging needed for the disjoint case). Each
// benchmark checks its plan before timing (Ok, Update, the expected rectangle count for the grid).
#include <shadowkit/shadow_cache.hpp>

#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

namespace {

constexpr int kMap = 4096;
constexpr double kTexel = 0.25;  // world units

// Top-down orthographic map: world x -> map x, world z -> map y, [0, kMap * kTexel) each.
shadowkit::ShadowCacheMapState top_down_state() {
    shadowkit::ShadowCacheMapState s;
    s.view_proj = glm::dmat4(0.0);
    s.view_proj[0][0] = 2.0 / (kMap * kTexel);
    s.view_proj[2][1] = 2.0 / (kMap * kTexel);
    s.view_proj[1][2] = -0.01;
    s.view_proj[3][0] = -1.0;
    s.view_proj[3][1] = -1.0;
    s.view_proj[3][3] = 1.0;
    s.width = s.height = kMap;
    s.has_content = true;
    return s;
}

void set_box(float* b, double x, double z, double half) {
    const float v[6] = {float(x - half), -1.0f, float(z - half), float(x + half), 1.0f, float(z + half)};
    for (int k = 0; k < 6; ++k) b[k] = v[k];
}

std::vector<shadowkit::ShadowCacheCaster> grid_casters(int n, bool diagonal) {
    std::vector<shadowkit::ShadowCacheCaster> cs(static_cast<std::size_t>(n));
    const int per_row = 180;
    for (int i = 0; i < n; ++i) {
        const double x = (10.5 + 22.0 * (i % per_row)) * kTexel, z = (10.5 + 22.0 * (i / per_row)) * kTexel;
        set_box(cs[std::size_t(i)].previous_bounds, x, z, 1.0 * kTexel);
        set_box(cs[std::size_t(i)].bounds, x + kTexel, diagonal ? z + kTexel : z, 1.0 * kTexel);  // one texel aside
    }
    return cs;
}

std::vector<shadowkit::ShadowCacheCaster> piled_casters(int n) {
    std::vector<shadowkit::ShadowCacheCaster> cs(static_cast<std::size_t>(n));
    std::mt19937 rng(32000);
    std::uniform_real_distribution<double> pos(1900.0 * kTexel, 2156.0 * kTexel), ext(0.5 * kTexel, 8.0 * kTexel);
    for (auto& c : cs) {
        set_box(c.previous_bounds, pos(rng), pos(rng), ext(rng));
        set_box(c.bounds, pos(rng), pos(rng), ext(rng));
    }
    return cs;
}

void run_plan(benchmark::State& state, const std::vector<shadowkit::ShadowCacheCaster>& cs, std::size_t expect_count,
              bool expect_merged = false) {
    const shadowkit::ShadowCacheMapState s = top_down_state();
    std::vector<shadowkit::ShadowCacheRect> rects(shadowkit::shadow_cache_rect_capacity(cs.size()));
    const shadowkit::ShadowCachePlan check = shadowkit::shadow_cache_plan(s, s, cs.data(), cs.size(), rects.data(), rects.size());
    if (check.status != shadowkit::Status::Ok || check.action != shadowkit::ShadowCacheAction::Update || check.merged != expect_merged ||
        (expect_count != 0 && check.count != expect_count)) {
        std::fprintf(stderr, "shadow_cache bench: unexpected plan (%s, %zu rectangles)\n", shadowkit::status_name(check.status),
                     check.count);
        std::exit(1);
    }
    for (auto _ : state) {
        const shadowkit::ShadowCachePlan p = shadowkit::shadow_cache_plan(s, s, cs.data(), cs.size(), rects.data(), rects.size());
        benchmark::DoNotOptimize(p.texels);
    }
    state.counters["rects"] = double(check.count);
    state.counters["texels"] = double(check.texels);
}

void BM_shadow_cache_disjoint(benchmark::State& state) {
    const int n = int(state.range(0));
    run_plan(state, grid_casters(n, false), std::size_t(n));  // each caster's two footprints: one rectangle
}

void BM_shadow_cache_disjoint_diagonal(benchmark::State& state) {
    const int n = int(state.range(0));
    // two footprints offset diagonally: three disjoint rectangles, 3n > shadow_cache_rect_capacity(n):
    // the plan merges each caster's two (a free merge) into one rectangle, n in all
    run_plan(state, grid_casters(n, true), std::size_t(n), true);
}

void BM_shadow_cache_overlapping(benchmark::State& state) { run_plan(state, piled_casters(int(state.range(0))), 0); }

}  // namespace

BENCHMARK(BM_shadow_cache_disjoint)->Arg(2000)->Arg(8000)->Arg(32000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_shadow_cache_disjoint_diagonal)->Arg(2000)->Arg(8000)->Arg(32000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_shadow_cache_overlapping)->Arg(2000)->Arg(8000)->Arg(32000)->Unit(benchmark::kMillisecond);
