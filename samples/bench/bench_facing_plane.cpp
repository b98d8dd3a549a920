// Google Benchmark of the exact facing when every face is a tie (issue 27 item 7): a flat grid of
// 51,200 triangles on the plane y = 3x + 5z (integer x, z in [0, 160]: every vertex exactly on it),
// lit by (a) a point light above the plane (the generic case: the filters decide every face), (b) a
// point light in the plane and (c) a directional light parallel to it (d == 0 for every face: each
// face goes past the filters to the exact stages). silhouette_compute_facing and, on cached planes,
// silhouette_compute_facing_planes. Each benchmark first checks the facing: (a) every face lit or
// every face unlit (one side of a plane), (b) and (c) no face lit (d == 0 is not lit).
#include <shadowkit/silhouette.hpp>

#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <vector>

namespace {

struct PlaneScene {
    std::vector<glm::vec3> positions;
    std::vector<std::uint32_t> indices;
    shadowkit::SilhouetteAdjacency adj;
    shadowkit::SilhouettePlanes planes;
    std::vector<std::uint8_t> facing;
};

const PlaneScene& plane_scene() {
    static const PlaneScene s = [] {
        PlaneScene p;
        const int n = 160;  // 160 x 160 quads = 51,200 triangles
        for (int i = 0; i <= n; ++i)
            for (int k = 0; k <= n; ++k) p.positions.emplace_back(float(i), float(3 * i + 5 * k), float(k));
        for (int i = 0; i < n; ++i)
            for (int k = 0; k < n; ++k) {
                const std::uint32_t a = std::uint32_t(i * (n + 1) + k), b = a + 1, c = a + std::uint32_t(n + 1), d = c + 1;
                for (std::uint32_t v : {a, b, c, b, d, c}) p.indices.push_back(v);
            }
        p.adj = shadowkit::silhouette_build_adjacency(p.positions.data(), p.positions.size(), p.indices.data(), p.indices.size());
        p.planes = shadowkit::silhouette_build_planes(p.adj, p.positions.data(), p.positions.size());
        p.facing.resize(p.adj.face_count());
        return p;
    }();
    return s;
}

glm::vec4 light_of(int kind) {
    if (kind == 0) return glm::vec4(80.0f, 3.0f * 80.0f + 5.0f * 80.0f + 300.0f, 80.0f, 1.0f);  // above the plane
    if (kind == 1) return glm::vec4(-7.0f, 3.0f * -7.0f + 5.0f * 3.0f, 3.0f, 1.0f);              // in the plane
    return glm::vec4(1.0f, 3.0f, 0.0f, 0.0f);                                                    // parallel to it
}

void check_facing(const PlaneScene& s, std::size_t lit, int kind) {
    const bool ok = kind == 0 ? (lit == 0 || lit == s.facing.size()) : lit == 0;
    if (!ok) {
        std::fprintf(stderr, "facing bench: light %d lit %zu of %zu faces\n", kind, lit, s.facing.size());
        std::exit(1);
    }
}

void BM_facing_tie(benchmark::State& state) {
    PlaneScene& s = const_cast<PlaneScene&>(plane_scene());
    const glm::vec4 L = light_of(int(state.range(0)));
    auto run = [&] {
        return shadowkit::silhouette_compute_facing(s.adj, s.positions.data(), s.positions.size(), L, s.facing.data(), s.facing.size());
    };
    const shadowkit::SilhouetteFacing r = run();
    if (r.status != shadowkit::Status::Ok) std::exit(1);
    check_facing(s, r.lit_faces, int(state.range(0)));
    for (auto _ : state) benchmark::DoNotOptimize(run().lit_faces);
    state.SetLabel(state.range(0) == 0 ? "light above" : (state.range(0) == 1 ? "point light in the plane" : "directional, parallel"));
}

void BM_facing_planes_tie(benchmark::State& state) {
    PlaneScene& s = const_cast<PlaneScene&>(plane_scene());
    const glm::vec4 L = light_of(int(state.range(0)));
    auto run = [&] { return shadowkit::silhouette_compute_facing_planes(s.adj, s.planes, L, s.facing.data(), s.facing.size()); };
    const shadowkit::SilhouetteFacing r = run();
    if (r.status != shadowkit::Status::Ok) std::exit(1);
    check_facing(s, r.lit_faces, int(state.range(0)));
    for (auto _ : state) benchmark::DoNotOptimize(run().lit_faces);
    state.SetLabel(state.range(0) == 0 ? "light above" : (state.range(0) == 1 ? "point light in the plane" : "directional, parallel"));
}

}  // namespace

BENCHMARK(BM_facing_tie)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_facing_planes_tie)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);
