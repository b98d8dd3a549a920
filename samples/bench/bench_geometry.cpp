// shadowkit-bench: the CPU side of stencil shadow volumes on procedural meshes of 10k..1M triangles.
//
//   adjacency   silhouette_build_adjacency (once per mesh; weld of bit-identical positions, sort of half-edges)
//   facing      silhouette_compute_facing (exact sign per face: double filter, integer fallback)
//   silhouette  silhouette_extract (one pass over the edge list)
//   volume      volume_build_side_quads + volume_build_caps (z-fail index buffer: side quads, light and dark caps)
//   frame       facing + silhouette + volume: the per-frame work of a moving light
//   facing_planes / frame_planes: the same with the rigid-mesh fast path (silhouette_build_planes
//               once, silhouette_compute_facing_planes + silhouette_extract_planes_side_quads (+ caps)
//               per frame)
//   --compare   not Google Benchmark: the side-by-side table of bench_compare.cpp (a bgfx-style
//               baseline, the exact path, the fast path, memcpy; docs/benchmarks.md)
//   silhouette_parallel / frame_parallel: the same on T threads (third argument) of a persistent
//               pool, through silhouette_extract_parallel (chunked facing + silhouette, then the
//               serial compaction) and per-chunk volume_build_caps into each chunk's own range of the
//               index buffer (drawn as one range per chunk: no compaction of the caps)
//
// Meshes: "sphere" (closed UV sphere with shared vertices: few silhouette edges) and "grid" (a noisy
// height field: open, many silhouette edges). Every benchmark reports the bytes its stage reads
// (bytes_per_second), and measures in the same run a memcpy of the same number of bytes (buffers of
// that size, median of repeated copies): counter `x_memcpy` = stage time / memcpy time, the bound the
// issue asks to stay within 4x of. `edges_per_s` counts the mesh's edges processed per second.
#include <shadowkit/shadow_volume.hpp>
#include <shadowkit/silhouette.hpp>

#include <benchmark/benchmark.h>

#include "bench_meshes.hpp"
#include "bench_pool.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <memory>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;

using bench::BenchMesh;
using bench::make_grid;
using bench::make_sphere;
using bench::Pool;

// Everything a stage needs, built once per (mesh kind, size) and shared by the benchmarks.
struct Fixture {
    BenchMesh mesh;
    shadowkit::SilhouetteAdjacency adj;
    shadowkit::SilhouettePlanes planes;
    glm::vec4 light{0.f};
    std::vector<std::uint8_t> facing;
    std::vector<std::uint32_t> sil;
    std::size_t sil_edges = 0;
    std::vector<std::uint32_t> volume;
};

Fixture& fixture(int kind, std::size_t triangles) {
    static std::map<std::pair<int, std::size_t>, std::unique_ptr<Fixture>> cache;
    auto& slot = cache[{kind, triangles}];
    if (slot) return *slot;
    slot = std::make_unique<Fixture>();
    Fixture& f = *slot;
    f.mesh = kind == 0 ? make_sphere(triangles) : make_grid(triangles);
    f.adj = shadowkit::silhouette_build_adjacency(f.mesh.positions.data(), f.mesh.positions.size(), f.mesh.indices.data(),
                                                  f.mesh.indices.size());
    f.planes = shadowkit::silhouette_build_planes(f.adj, f.mesh.positions.data(), f.mesh.positions.size());
    f.light = kind == 0 ? glm::vec4(3.f, 2.f, 1.f, 1.f) : glm::vec4(0.6f, 1.5f, 0.4f, 1.f);
    f.facing.assign(f.adj.face_count(), 0);
    shadowkit::silhouette_compute_facing(f.adj, f.mesh.positions.data(), f.mesh.positions.size(), f.light, f.facing.data(),
                                         f.facing.size());
    f.sil.assign(shadowkit::silhouette_indices_capacity(f.adj), 0);
    f.sil_edges = shadowkit::silhouette_extract(f.adj, f.facing.data(), f.facing.size(), f.sil.data(), f.sil.size(),
                                                nullptr, 0)
                      .count / 2;
    f.volume.assign(6 * f.adj.max_silhouette_edges() + 6 * f.adj.face_count(), 0);
    return f;
}

// Median time (ns) of a memcpy of `bytes` bytes between two buffers of that size (same run, warm).
double memcpy_ns(std::size_t bytes) {
    static std::map<std::size_t, double> cache;
    if (auto it = cache.find(bytes); it != cache.end()) return it->second;
    std::vector<unsigned char> src(bytes, 1), dst(bytes, 0);
    std::vector<double> t;
    for (int rep = 0; rep < 31; ++rep) {
        const auto t0 = Clock::now();
        std::memcpy(dst.data(), src.data(), bytes);
        benchmark::ClobberMemory();
        t.push_back(std::chrono::duration<double, std::nano>(Clock::now() - t0).count());
        benchmark::DoNotOptimize(dst.data());
    }
    std::nth_element(t.begin(), t.begin() + 15, t.end());
    return cache[bytes] = t[15];
}

// Runs `body` in the benchmark loop; reports bytes, edges/s and the ratio to memcpy of `bytes`.
template <typename F>
void measure(benchmark::State& state, std::size_t bytes, std::size_t edges, F&& body) {
    const double mc = memcpy_ns(bytes);
    const auto t0 = Clock::now();
    std::int64_t iters = 0;
    for (auto _ : state) {
        body();
        ++iters;
    }
    const double ns = std::chrono::duration<double, std::nano>(Clock::now() - t0).count() / double(std::max<std::int64_t>(iters, 1));
    state.SetBytesProcessed(static_cast<std::int64_t>(bytes) * iters);
    state.counters["input_MB"] = double(bytes) / 1e6;
    state.counters["memcpy_us"] = mc / 1e3;
    state.counters["x_memcpy"] = ns / mc;
    state.counters["edges_per_s"] = benchmark::Counter(double(edges) * double(iters), benchmark::Counter::kIsRate);
}

std::size_t edge_bytes(const shadowkit::SilhouetteAdjacency& a) {
    return a.edges.size() * sizeof(shadowkit::SilhouetteEdge) +
           a.nonmanifold_edges.size() * sizeof(shadowkit::SilhouetteNonManifoldEdge) + a.nonmanifold_faces.size() * 4;
}

void set_label(benchmark::State& state, const Fixture& f) {
    state.SetLabel(std::string(state.range(0) == 0 ? "sphere" : "grid") + " tris=" + std::to_string(f.adj.face_count()) +
                   " edges=" + std::to_string(f.adj.edges.size()) + " sil=" + std::to_string(f.sil_edges));
}

void BM_adjacency(benchmark::State& state) {
    Fixture& f = fixture(static_cast<int>(state.range(0)), static_cast<std::size_t>(state.range(1)));
    const std::size_t bytes = f.mesh.positions.size() * sizeof(glm::vec3) + f.mesh.indices.size() * 4;
    measure(state, bytes, f.adj.edges.size(), [&] {
        auto a = shadowkit::silhouette_build_adjacency(f.mesh.positions.data(), f.mesh.positions.size(), f.mesh.indices.data(),
                                                       f.mesh.indices.size());
        benchmark::DoNotOptimize(a.edges.data());
    });
    set_label(state, f);
}

void BM_facing(benchmark::State& state) {
    Fixture& f = fixture(static_cast<int>(state.range(0)), static_cast<std::size_t>(state.range(1)));
    const std::size_t bytes = f.adj.faces.size() * 4 + f.mesh.positions.size() * sizeof(glm::vec3);
    measure(state, bytes, f.adj.edges.size(), [&] {
        auto r = shadowkit::silhouette_compute_facing(f.adj, f.mesh.positions.data(), f.mesh.positions.size(), f.light,
                                                      f.facing.data(), f.facing.size());
        benchmark::DoNotOptimize(r);
        benchmark::ClobberMemory();
    });
    set_label(state, f);
}

void BM_silhouette(benchmark::State& state) {
    Fixture& f = fixture(static_cast<int>(state.range(0)), static_cast<std::size_t>(state.range(1)));
    const std::size_t bytes = edge_bytes(f.adj) + f.facing.size();
    measure(state, bytes, f.adj.edges.size(), [&] {
        auto r = shadowkit::silhouette_extract(f.adj, f.facing.data(), f.facing.size(), f.sil.data(), f.sil.size(),
                                               nullptr, 0);
        benchmark::DoNotOptimize(r);
        benchmark::ClobberMemory();
    });
    set_label(state, f);
}

void BM_volume(benchmark::State& state) {
    Fixture& f = fixture(static_cast<int>(state.range(0)), static_cast<std::size_t>(state.range(1)));
    const std::size_t bytes = f.sil_edges * 8 + f.adj.faces.size() * 4 + f.facing.size();
    measure(state, bytes, f.adj.edges.size(), [&] {
        const auto sq = shadowkit::volume_build_side_quads(f.sil.data(), 2 * f.sil_edges, f.mesh.positions.size(),
                                                           f.volume.data(), f.volume.size());
        const auto cp = bench::lit_caps(f.adj, f.facing.data(), 0, f.facing.size(), f.mesh.positions.size(),
                                        f.volume.data() + sq.count, f.volume.size() - sq.count);
        benchmark::DoNotOptimize(cp);
        benchmark::ClobberMemory();
    });
    set_label(state, f);
}

void BM_frame(benchmark::State& state) {
    Fixture& f = fixture(static_cast<int>(state.range(0)), static_cast<std::size_t>(state.range(1)));
    const std::size_t bytes = f.adj.faces.size() * 4 + f.mesh.positions.size() * sizeof(glm::vec3) + edge_bytes(f.adj);
    measure(state, bytes, f.adj.edges.size(), [&] {
        shadowkit::silhouette_compute_facing(f.adj, f.mesh.positions.data(), f.mesh.positions.size(), f.light, f.facing.data(),
                                             f.facing.size());
        const auto sr = shadowkit::silhouette_extract(f.adj, f.facing.data(), f.facing.size(), f.sil.data(), f.sil.size(),
                                                      nullptr, 0);
        const auto sq = shadowkit::volume_build_side_quads(f.sil.data(), sr.count, f.mesh.positions.size(), f.volume.data(),
                                                           f.volume.size());
        const auto cp = bench::lit_caps(f.adj, f.facing.data(), 0, f.facing.size(), f.mesh.positions.size(),
                                        f.volume.data() + sq.count, f.volume.size() - sq.count);
        benchmark::DoNotOptimize(cp);
        benchmark::ClobberMemory();
    });
    set_label(state, f);
}

void BM_facing_planes(benchmark::State& state) {
    Fixture& f = fixture(static_cast<int>(state.range(0)), static_cast<std::size_t>(state.range(1)));
    const std::size_t bytes = f.adj.face_count() * 16;
    measure(state, bytes, f.adj.edges.size(), [&] {
        auto r = shadowkit::silhouette_compute_facing_planes(f.adj, f.planes, f.light, f.facing.data(), f.facing.size());
        benchmark::DoNotOptimize(r);
        benchmark::ClobberMemory();
    });
    set_label(state, f);
}

void BM_frame_planes(benchmark::State& state) {
    Fixture& f = fixture(static_cast<int>(state.range(0)), static_cast<std::size_t>(state.range(1)));
    const std::size_t bytes = f.adj.face_count() * 16 + f.planes.edge_faces.size() * 8 + f.sil_edges * 8 + f.adj.faces.size() * 4;
    measure(state, bytes, f.adj.edges.size(), [&] {
        shadowkit::silhouette_compute_facing_planes(f.adj, f.planes, f.light, f.facing.data(), f.facing.size());
        const auto sq = shadowkit::silhouette_extract_planes_side_quads(f.adj, f.planes, f.facing.data(), f.facing.size(),
                                                                        f.volume.data(), f.volume.size());
        const auto cp = bench::lit_caps(f.adj, f.facing.data(), 0, f.facing.size(), f.mesh.positions.size(),
                                        f.volume.data() + sq.count, f.volume.size() - sq.count);
        benchmark::DoNotOptimize(cp);
        benchmark::ClobberMemory();
    });
    set_label(state, f);
}

Pool& pool(std::size_t threads) {
    static std::map<std::size_t, std::unique_ptr<Pool>> pools;
    auto& p = pools[threads];
    if (!p) p = std::make_unique<Pool>(threads);
    return *p;
}

void BM_silhouette_parallel(benchmark::State& state) {
    Fixture& f = fixture(static_cast<int>(state.range(0)), static_cast<std::size_t>(state.range(1)));
    const std::size_t threads = static_cast<std::size_t>(state.range(2)), chunks = 4 * threads;
    Pool& pl = pool(threads);
    std::vector<shadowkit::SilhouetteResult> per(chunks);
    const std::size_t bytes = f.adj.faces.size() * 4 + f.mesh.positions.size() * sizeof(glm::vec3) + edge_bytes(f.adj);
    measure(state, bytes, f.adj.edges.size(), [&] {
        auto r = shadowkit::silhouette_extract_parallel(f.adj, f.mesh.positions.data(), f.mesh.positions.size(), f.light,
                                                        f.facing.data(), f.facing.size(), f.sil.data(), f.sil.size(),
                                                        nullptr, 0, per.data(), chunks, pl);
        benchmark::DoNotOptimize(r);
        benchmark::ClobberMemory();
    });
    set_label(state, f);
    state.counters["threads"] = double(threads);
}

void BM_frame_parallel(benchmark::State& state) {
    Fixture& f = fixture(static_cast<int>(state.range(0)), static_cast<std::size_t>(state.range(1)));
    const std::size_t threads = static_cast<std::size_t>(state.range(2)), chunks = 4 * threads;
    Pool& pl = pool(threads);
    std::vector<shadowkit::SilhouetteResult> per(chunks);
    std::vector<std::size_t> cap_counts(chunks);
    const std::size_t fc = f.adj.face_count(), side_room = 6 * f.adj.max_silhouette_edges();
    const std::size_t bytes = f.adj.faces.size() * 4 + f.mesh.positions.size() * sizeof(glm::vec3) + edge_bytes(f.adj);
    measure(state, bytes, f.adj.edges.size(), [&] {
        const auto sr = shadowkit::silhouette_extract_parallel(f.adj, f.mesh.positions.data(), f.mesh.positions.size(),
                                                               f.light, f.facing.data(), f.facing.size(), f.sil.data(),
                                                               f.sil.size(), nullptr, 0, per.data(), chunks, pl);
        const auto sq = shadowkit::volume_build_side_quads(f.sil.data(), sr.count, f.mesh.positions.size(), f.volume.data(),
                                                           f.volume.size());
        pl(chunks, [&](std::size_t c) {  // caps: chunk c's faces into its own 6-per-face range
            const std::size_t b = bench::chunk_begin(fc, chunks, c), e = bench::chunk_begin(fc, chunks, c + 1);
            cap_counts[c] = bench::lit_caps(f.adj, f.facing.data(), b, e, f.mesh.positions.size(),
                                            f.volume.data() + side_room + 6 * b, 6 * (e - b))
                                .count;
        });
        benchmark::DoNotOptimize(sq);
        benchmark::DoNotOptimize(cap_counts.data());
        benchmark::ClobberMemory();
    });
    set_label(state, f);
    state.counters["threads"] = double(threads);
}

void sizes(benchmark::internal::Benchmark* b) {
    for (int kind : {0, 1})
        for (std::int64_t t : {10000, 100000, 1000000}) b->Args({kind, t});
    b->Unit(benchmark::kMicrosecond);
}

BENCHMARK(BM_adjacency)->Apply(sizes);
BENCHMARK(BM_facing)->Apply(sizes);
BENCHMARK(BM_silhouette)->Apply(sizes);
BENCHMARK(BM_volume)->Apply(sizes);
BENCHMARK(BM_frame)->Apply(sizes);
BENCHMARK(BM_facing_planes)->Apply(sizes);
BENCHMARK(BM_frame_planes)->Apply(sizes);

void parallel_sizes(benchmark::internal::Benchmark* b) {
    for (int kind : {0, 1})
        for (std::int64_t t : {100000, 1000000})
            for (std::int64_t threads : {1, 2, 4}) b->Args({kind, t, threads});
    b->Unit(benchmark::kMicrosecond)->UseRealTime();
}
BENCHMARK(BM_silhouette_parallel)->Apply(parallel_sizes);
BENCHMARK(BM_frame_parallel)->Apply(parallel_sizes);

}  // namespace

int run_compare(int argc, char** argv);  // bench_compare.cpp

// `--compare [...]`: the side-by-side table of bench_compare.cpp; otherwise Google Benchmark.
int main(int argc, char** argv) {
    for (int i = 1; i < argc; ++i)
        if (std::string(argv[i]) == "--compare") return run_compare(argc, argv);
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
