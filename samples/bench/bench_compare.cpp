// shadowkit-bench --compare [--reps N] [--threads T] [--only TEXT] [MESH.obj|MESH.ply ...]
//
// One run, one thread, the per-frame CPU geometry of a moving point light (a new light position
// every frame, the same sequence for every variant), on spheres of 10k / 100k / 1M triangles, a noisy
// grid of 100k / 1M, and every mesh file named on the command line:
//   bgfx    the edge-based SSE2 baseline of bgfx_style.hpp (planes precomputed at load, per edge the
//           two planes' signs, side quads emitted twice; z-fail: both caps, twice)
//   exact   shadowkit's per-frame path for fresh positions: silhouette_compute_facing +
//           silhouette_extract + volume_build_side_quads (+ volume_build_caps LitOnly for z-fail)
//   fast    shadowkit's rigid-mesh path: silhouette_compute_facing_planes +
//           silhouette_extract_planes_side_quads (+ the same caps) (identical output to `exact`,
//           checked here per mesh)
//   memcpy  a memcpy of the bytes the fast frame must read (planes 16 B per face, edge faces 8 B per
//           edge, the silhouette edges' vertices; z-fail also the faces' 12 B)
// Timing: per-thread CPU time (the machine is shared), the variants interleaved (each repetition runs
// every variant once, in a rotating order), each sample a batch of frames of >= 2 ms, the median of
// --reps samples (default 15). With --threads T (default 2) the fast path also runs on 1..T threads of
// a persistent pool (silhouette_extract_parallel_planes + per-chunk caps; wall time, medians).
// --only TEXT keeps the rows whose "name triangles" contains TEXT (e.g. --only "grid 999").
#include <shadowkit/shadow_volume.hpp>
#include <shadowkit/silhouette.hpp>

#include "bench_meshes.hpp"
#include "bench_pool.hpp"
#include "bgfx_style.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace {

namespace sk = shadowkit;

double cpu_ns() {
#if defined(__linux__) || defined(__APPLE__)
    timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) * 1e9 + double(ts.tv_nsec);
#else
    return std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now().time_since_epoch()).count();
#endif
}
double wall_ns() { return std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

struct Case {
    std::string name;
    bench::BenchMesh mesh;
    sk::SilhouetteAdjacency adj;
    sk::SilhouettePlanes planes;
    bgfx_style::Mesh bg;
    bgfx_style::Output bgo;
    std::vector<glm::vec4> lights;
    std::vector<std::uint8_t> facing;
    std::vector<std::uint32_t> sil, volume;
    std::size_t sil_edges = 0;
    double setup_bgfx_ms = 0.0, setup_adj_ms = 0.0, setup_planes_ms = 0.0;
};

std::size_t g_sink = 0;

// One frame of shadowkit (exact or fast facing): returns the index count.
std::size_t sk_frame(Case& c, const glm::vec4& L, bool fast, bool zfail) {
    const std::size_t fc = c.adj.face_count(), n = c.mesh.positions.size();
    std::size_t k = 0;
    if (fast) {  // side quads straight from the cached-plane extraction (no edge buffer)
        sk::silhouette_compute_facing_planes(c.adj, c.planes, L, c.facing.data(), fc);
        k = sk::silhouette_extract_planes_side_quads(c.adj, c.planes, c.facing.data(), fc, c.volume.data(), c.volume.size()).count;
    } else {
        sk::silhouette_compute_facing(c.adj, c.mesh.positions.data(), n, L, c.facing.data(), fc);
        const sk::SilhouetteResult sr = sk::silhouette_extract(c.adj, c.facing.data(), fc, c.sil.data(), c.sil.size(), nullptr, 0);
        k = sk::volume_build_side_quads(c.sil.data(), sr.count, n, c.volume.data(), c.volume.size()).count;
    }
    if (zfail)
        k += bench::lit_caps(c.adj, c.facing.data(), 0, fc, n, c.volume.data() + k, c.volume.size() - k).count;
    return k;
}

// The bytes the fast frame must read: the cached plane (16 per face), the edge's face pair (8 per
// edge: edge_faces is one uint64 per edge), the silhouette edges' vertex pairs (8 each), for z-fail
// the faces' indices (12 per face).
std::size_t fast_bytes(const Case& c, bool zfail) {
    return c.adj.face_count() * 16 + c.planes.edge_faces.size() * sizeof(std::uint64_t) + c.sil_edges * 8 +
           (zfail ? c.adj.faces.size() * 4 : 0);
}

void prepare(Case& c) {
    const auto& p = c.mesh.positions;
    const auto& t = c.mesh.indices;
    double t0 = wall_ns();
    c.bg = bgfx_style::load(p.data(), t.data(), t.size());
    c.setup_bgfx_ms = (wall_ns() - t0) / 1e6;
    bgfx_style::reserve(c.bg, c.bgo);
    t0 = wall_ns();
    c.adj = sk::silhouette_build_adjacency(p.data(), p.size(), t.data(), t.size());
    c.setup_adj_ms = (wall_ns() - t0) / 1e6;
    t0 = wall_ns();
    c.planes = sk::silhouette_build_planes(c.adj, p.data(), p.size());
    c.setup_planes_ms = (wall_ns() - t0) / 1e6;
    glm::vec3 lo = p[0], hi = p[0];
    for (const glm::vec3& q : p) lo = glm::min(lo, q), hi = glm::max(hi, q);
    const glm::vec3 ctr = 0.5f * (lo + hi);
    const float r = 0.5f * glm::length(hi - lo);
    for (int i = 0; i < 16; ++i) {  // an orbit at 3 radii, rising and falling
        const float a = 6.2831853f * float(i) / 16.0f;
        c.lights.emplace_back(ctr + r * glm::vec3(3.0f * std::cos(a), 1.5f + std::sin(2.0f * a), 3.0f * std::sin(a)), 1.0f);
    }
    c.facing.assign(c.adj.face_count(), 0);
    c.sil.assign(sk::silhouette_indices_capacity(c.adj), 0);
    c.volume.assign(sk::volume_indices_capacity(c.sil.size(), c.adj.faces.size()), 0);
    // average silhouette size over the orbit, and the check that fast == exact
    std::vector<std::uint8_t> f2(c.facing.size());
    std::vector<std::uint32_t> v2(c.volume.size());
    std::size_t total = 0;
    for (const glm::vec4& L : c.lights) {
        const std::size_t k1 = sk_frame(c, L, false, true);
        std::copy(c.facing.begin(), c.facing.end(), f2.begin());
        std::copy(c.volume.begin(), c.volume.begin() + static_cast<std::ptrdiff_t>(k1), v2.begin());
        const std::size_t k2 = sk_frame(c, L, true, true);
        if (k1 != k2 || !std::equal(f2.begin(), f2.end(), c.facing.begin()) ||
            !std::equal(v2.begin(), v2.begin() + static_cast<std::ptrdiff_t>(k1), c.volume.begin())) {
            std::fprintf(stderr, "%s: fast path differs from the exact path\n", c.name.c_str());
            std::exit(1);
        }
        total += sk::silhouette_extract(c.adj, c.facing.data(), c.facing.size(), c.sil.data(), c.sil.size(), nullptr, 0).count / 2;
    }
    c.sil_edges = total / c.lights.size();
}

// Median ns per frame of each variant, interleaved.
std::vector<double> measure(const std::vector<std::function<void(std::size_t)>>& vs, int reps) {
    // batch size: >= 2 ms of the slowest variant's CPU time per sample
    double slow = 0.0;
    for (const auto& v : vs) {
        const double t0 = cpu_ns();
        v(0);
        slow = std::max(slow, cpu_ns() - t0);
    }
    const std::size_t batch = std::max<std::size_t>(1, static_cast<std::size_t>(2e6 / std::max(slow, 1.0)));
    std::vector<std::vector<double>> t(vs.size());
    std::size_t frame = 0;
    for (int r = 0; r < reps; ++r)
        for (std::size_t k = 0; k < vs.size(); ++k) {
            const std::size_t v = (k + static_cast<std::size_t>(r)) % vs.size();
            const double t0 = cpu_ns();
            for (std::size_t b = 0; b < batch; ++b) vs[v](frame + b);
            t[v].push_back((cpu_ns() - t0) / double(batch));
            frame += batch;
        }
    std::vector<double> out;
    for (auto& x : t) out.push_back(median(x));
    return out;
}

}  // namespace

int run_compare(int argc, char** argv) {
    int reps = 15;
    std::size_t max_threads = 2;
    std::vector<std::string> files;
    std::string only;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--compare") continue;
        if (a == "--reps" && i + 1 < argc) reps = std::max(1, std::atoi(argv[++i]));
        else if (a == "--only" && i + 1 < argc) only = argv[++i];
        else if (a == "--threads" && i + 1 < argc) max_threads = static_cast<std::size_t>(std::max(1, std::atoi(argv[++i])));
        else files.push_back(a);
    }
    std::vector<std::unique_ptr<Case>> cases;
    auto add = [&](const std::string& name, bench::BenchMesh&& m) {
        const std::size_t tris = m.indices.size() / 3;
        if (!only.empty() && (name + " " + std::to_string(tris)).find(only) == std::string::npos) return;
        cases.push_back(std::make_unique<Case>());
        cases.back()->name = name;
        cases.back()->mesh = std::move(m);
    };
    for (std::size_t n : {10000u, 100000u, 1000000u}) add("sphere", bench::make_sphere(n));
    for (std::size_t n : {100000u, 1000000u}) add("noisy grid", bench::make_grid(n));
    for (const std::string& f : files) {
        bench::BenchMesh m;
        std::string err;
        if (!bench::read_mesh(f, m, err)) {
            std::fprintf(stderr, "%s\n", err.c_str());
            return 1;
        }
        const std::size_t slash = f.find_last_of('/');
        add(slash == std::string::npos ? f : f.substr(slash + 1), std::move(m));
    }
    if (cases.empty()) {
        std::fprintf(stderr, "shadowkit-bench --compare: no mesh matches --only \"%s\"\n", only.c_str());
        return 2;
    }
    std::printf("shadowkit-bench --compare: %d repetitions, medians of per-thread CPU time per frame (us)\n", reps);
    std::printf("\n| mesh | triangles | edges | silhouette edges | z-pass bgfx | exact | fast | memcpy | fast vs bgfx | fast / memcpy "
                "| z-fail bgfx | exact | fast | memcpy | fast vs bgfx | fast / memcpy |\n");
    std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (auto& cp : cases) {
        Case& c = *cp;
        prepare(c);
        const std::size_t nl = c.lights.size();
        std::vector<unsigned char> src(fast_bytes(c, true), 1), dst(src.size(), 0);
        std::vector<double> res[2];
        for (int zf = 0; zf < 2; ++zf) {
            const bool zfail = zf == 1;
            const std::size_t bytes = fast_bytes(c, zfail);
            std::vector<std::function<void(std::size_t)>> vs = {
                [&](std::size_t i) {
                    bgfx_style::frame(c.bg, c.lights[i % nl], zfail, c.bgo);
                    g_sink += c.bgo.ns + c.bgo.nf;
                },
                [&](std::size_t i) { g_sink += sk_frame(c, c.lights[i % nl], false, zfail); },
                [&](std::size_t i) { g_sink += sk_frame(c, c.lights[i % nl], true, zfail); },
                [&](std::size_t i) {
                    std::memcpy(dst.data(), src.data(), bytes);
                    g_sink += dst[i % bytes];
                },
            };
            res[zf] = measure(vs, reps);
        }
        std::printf("| %s | %zu | %zu | %zu |", c.name.c_str(), c.adj.face_count(), c.adj.edges.size(), c.sil_edges);
        for (int zf = 0; zf < 2; ++zf) {
            const auto& r = res[zf];
            std::printf(" %.1f | %.1f | %.1f | %.1f | %.2fx | %.2fx |", r[0] / 1e3, r[1] / 1e3, r[2] / 1e3, r[3] / 1e3, r[0] / r[2],
                        r[2] / r[3]);
        }
        std::printf("\n");
        std::fflush(stdout);
        std::fprintf(stderr, "  %s %zu: setup bgfx %.1f ms, adjacency %.1f ms + planes %.1f ms; bytes per frame: fast %.2f / %.2f MB, "
                             "bgfx %.2f / %.2f MB (z-pass / z-fail)\n",
                     c.name.c_str(), c.adj.face_count(), c.setup_bgfx_ms, c.setup_adj_ms, c.setup_planes_ms, double(fast_bytes(c, false)) / 1e6,
                     double(fast_bytes(c, true)) / 1e6, double(bgfx_style::input_bytes(c.bg, false)) / 1e6,
                     double(bgfx_style::input_bytes(c.bg, true)) / 1e6);
    }
    if (max_threads > 1) {
        std::printf("\nParallel fast path (silhouette_extract_parallel_planes, 4 chunks per thread, then side quads and per-chunk "
                    "LitOnly caps), wall time per frame (us), medians:\n\n| mesh | triangles |");
        for (std::size_t t = 1; t <= max_threads; ++t) std::printf(" z-pass %zu thr |", t);
        for (std::size_t t = 1; t <= max_threads; ++t) std::printf(" z-fail %zu thr |", t);
        std::printf("\n|---|---:|");
        for (std::size_t t = 0; t < 2 * max_threads; ++t) std::printf("---:|");
        std::printf("\n");
        for (auto& cp : cases) {
            Case& c = *cp;
            if (c.adj.face_count() < 100000) continue;
            std::printf("| %s | %zu |", c.name.c_str(), c.adj.face_count());
            for (int zf = 0; zf < 2; ++zf)
                for (std::size_t threads = 1; threads <= max_threads; ++threads) {
                    bench::Pool pool(threads);
                    const std::size_t chunks = 4 * threads, fc = c.adj.face_count(), n = c.mesh.positions.size();
                    const std::size_t side_room = 6 * c.adj.max_silhouette_edges();
                    std::vector<sk::SilhouetteResult> per(chunks);
                    std::vector<double> t;
                    for (int r = 0; r < std::max(reps, 9); ++r) {
                        const glm::vec4 L = c.lights[static_cast<std::size_t>(r) % c.lights.size()];
                        const double t0 = wall_ns();
                        const sk::SilhouetteResult sr = sk::silhouette_extract_parallel_planes(
                            c.adj, c.planes, L, c.facing.data(), fc, c.sil.data(), c.sil.size(), nullptr, 0, per.data(), chunks, pool);
                        const sk::VolumeBuffer sq = sk::volume_build_side_quads(c.sil.data(), sr.count, n, c.volume.data(), c.volume.size());
                        g_sink += sq.count;
                        if (zf)
                            pool(chunks, [&](std::size_t ch) {
                                const std::size_t b = bench::chunk_begin(fc, chunks, ch), e = bench::chunk_begin(fc, chunks, ch + 1);
                                bench::lit_caps(c.adj, c.facing.data(), b, e, n, c.volume.data() + side_room + 6 * b, 6 * (e - b));
                            });
                        t.push_back(wall_ns() - t0);
                    }
                    std::printf(" %.1f |", median(t) / 1e3);
                }
            std::printf("\n");
        }
    }
    std::printf("\n(sink %zu)\n", g_sink % 10);
    return 0;
}
