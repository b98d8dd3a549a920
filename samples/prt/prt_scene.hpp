// Internal helper shared by samples/prt, the report's PRT section and tests/report/test_prt_reference.cpp
// (NOT a public header): the procedural `prt` scene (a lumpy blob and a box over a floor, indexed meshes with
// smooth per-vertex normals, y up), its sky + sun environment, Embree visibility for
// shadowkit/prt.hpp's callback, multi-threaded transfer precomputation with a progress line, and
// the Monte Carlo reference (environment x visibility x cosine, cosine-weighted, Embree rays).
#pragma once

#include <embree3/rtcore.h>

#include <shadowkit/prt.hpp>

#include <glm/glm.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

namespace skprt {

constexpr float kPi = 3.14159265358979f;

struct PrtScene {
    std::vector<glm::vec3> positions, normals, albedo;  // per vertex
    std::vector<std::uint32_t> indices;
    std::size_t floor_vertices = 0;  // vertices [0, floor_vertices) are the floor
    std::vector<std::size_t> part_begin;  // first vertex of each object: floor, blob, box (in that order)
    float size = 4.0f;               // floor edge length (scene scale)
};

inline void add_grid(PrtScene& s, glm::vec3 origin, glm::vec3 du, glm::vec3 dv, int n, glm::vec3 normal, glm::vec3 albedo) {
    const auto base = static_cast<std::uint32_t>(s.positions.size());
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) {
            const float u = static_cast<float>(i) / static_cast<float>(n), v = static_cast<float>(j) / static_cast<float>(n);
            s.positions.push_back(origin + u * du + v * dv);
            s.normals.push_back(normal);
            s.albedo.push_back(albedo);
        }
    const auto row = static_cast<std::uint32_t>(n + 1);
    for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(n); ++i)
        for (std::uint32_t j = 0; j < static_cast<std::uint32_t>(n); ++j) {
            const std::uint32_t a = base + i * row + j, b = a + row;
            // counter-clockwise about `normal` when du x dv points along it
            for (std::uint32_t k : {a, b, b + 1, a, b + 1, a + 1}) s.indices.push_back(k);
        }
}

// detail 1 = about 11k vertices (floor 64 x 64 quads, blob 64 x 96, box 6 x 12 x 12).
inline PrtScene make_prt_scene(int detail = 1) {
    detail = std::max(detail, 1);
    PrtScene s;
    const int fn = 64 * detail;
    s.part_begin.push_back(0);
    add_grid(s, {-2.f, 0.f, 2.f}, {4.f, 0.f, 0.f}, {0.f, 0.f, -4.f}, fn, {0.f, 1.f, 0.f}, {0.8f, 0.78f, 0.74f});
    s.floor_vertices = s.positions.size();
    s.part_begin.push_back(s.positions.size());
    // blob: a sphere of radius 0.72 with low-frequency bumps, just above the floor near x = -0.6
    {
        const glm::vec3 c(-0.6f, 0.74f, 0.1f);
        const int stacks = 64 * detail, slices = 96 * detail;
        const auto base = static_cast<std::uint32_t>(s.positions.size());
        for (int i = 0; i <= stacks; ++i)
            for (int j = 0; j <= slices; ++j) {
                const float th = kPi * static_cast<float>(i) / static_cast<float>(stacks);
                const float ph = 2.f * kPi * static_cast<float>(j) / static_cast<float>(slices);
                const glm::vec3 d(std::sin(th) * std::cos(ph), std::cos(th), -std::sin(th) * std::sin(ph));
                // polynomial bumps in the direction's coordinates: smooth everywhere, poles included
                const float bump = 1.f + 0.18f * (d.x * d.x - d.z * d.z) + 0.6f * d.x * d.y * d.z + 0.1f * d.y -
                                   0.12f * d.y * d.y * d.x;
                s.positions.push_back(c + 0.72f * bump * d);
                s.normals.push_back(glm::vec3(0.f));
                s.albedo.push_back({0.85f, 0.55f, 0.35f});
            }
        const auto row = static_cast<std::uint32_t>(slices + 1);
        std::vector<std::uint32_t> idx;
        for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(stacks); ++i)
            for (std::uint32_t j = 0; j < static_cast<std::uint32_t>(slices); ++j) {
                const std::uint32_t a = base + i * row + j, b = a + row;
                for (std::uint32_t k : {a, b, b + 1, a, b + 1, a + 1}) idx.push_back(k);
            }
        // smooth normals: area-weighted face normals, the seam column welded by position
        for (std::size_t t = 0; t < idx.size(); t += 3) {
            const glm::vec3 &p0 = s.positions[idx[t]], &p1 = s.positions[idx[t + 1]], &p2 = s.positions[idx[t + 2]];
            const glm::vec3 fnrm = glm::cross(p1 - p0, p2 - p0);
            for (int k = 0; k < 3; ++k) s.normals[idx[t + static_cast<std::size_t>(k)]] += fnrm;
        }
        for (std::uint32_t i = 0; i <= static_cast<std::uint32_t>(stacks); ++i) {
            const std::uint32_t a = base + i * row, b = a + static_cast<std::uint32_t>(slices);
            const glm::vec3 sum = s.normals[a] + s.normals[b];
            s.normals[a] = s.normals[b] = sum;
        }
        // poles: every vertex of the first / last row is the same point; weld their normals
        for (std::uint32_t r : {0u, static_cast<std::uint32_t>(stacks)}) {
            glm::vec3 sum(0.f);
            for (std::uint32_t j = 0; j <= static_cast<std::uint32_t>(slices); ++j) sum += s.normals[base + r * row + j];
            for (std::uint32_t j = 0; j <= static_cast<std::uint32_t>(slices); ++j) s.normals[base + r * row + j] = sum;
        }
        for (std::size_t v = base; v < s.positions.size(); ++v) {
            const float len = glm::length(s.normals[v]);
            s.normals[v] = len > 0.f ? s.normals[v] / len : glm::normalize(s.positions[v] - c);
        }
        s.indices.insert(s.indices.end(), idx.begin(), idx.end());
    }
    // box: 0.7 x 0.9 x 0.7, standing at x = 0.9, each face a 12 x 12 grid
    s.part_begin.push_back(s.positions.size());
    {
        const glm::vec3 lo(0.55f, 0.f, -0.55f), hi(1.25f, 0.9f, 0.15f), e = hi - lo;
        const glm::vec3 alb(0.45f, 0.6f, 0.85f);
        const int n = 12 * detail;
        add_grid(s, {lo.x, lo.y, hi.z}, {e.x, 0, 0}, {0, e.y, 0}, n, {0, 0, 1}, alb);             // +z
        add_grid(s, {hi.x, lo.y, lo.z}, {-e.x, 0, 0}, {0, e.y, 0}, n, {0, 0, -1}, alb);           // -z
        add_grid(s, {hi.x, lo.y, hi.z}, {0, 0, -e.z}, {0, e.y, 0}, n, {1, 0, 0}, alb);            // +x
        add_grid(s, {lo.x, lo.y, lo.z}, {0, 0, e.z}, {0, e.y, 0}, n, {-1, 0, 0}, alb);            // -x
        add_grid(s, {lo.x, hi.y, hi.z}, {e.x, 0, 0}, {0, 0, -e.z}, n, {0, 1, 0}, alb);            // +y
    }
    return s;
}

// Sky + sun environment radiance (linear RGB), in world directions (y up): a blue-white sky
// gradient, a dim ground below the horizon and a warm sun lobe exp(k (cos - 1)) of sharpness k.
struct Environment {
    glm::vec3 sun_dir = glm::normalize(glm::vec3(0.6f, 0.5f, -0.55f));
    float sharpness = 16.0f;
    glm::vec3 sun_color{9.0f, 8.0f, 6.5f};
    glm::vec3 operator()(const glm::vec3& s) const {
        const float h = s.y;
        glm::vec3 sky = h > 0.f ? glm::mix(glm::vec3(0.75f, 0.8f, 0.9f), glm::vec3(0.25f, 0.4f, 0.8f), std::sqrt(h))
                                : glm::vec3(0.12f, 0.1f, 0.08f);
        return sky + sun_color * std::exp(sharpness * (glm::dot(s, sun_dir) - 1.f));
    }
};

// Embree scene of the mesh; visible() is a shadow ray that starts at `tnear` (scene scale).
struct EmbreeVisibility {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    float tnear = 0.f;
    EmbreeVisibility() = default;
    EmbreeVisibility(const EmbreeVisibility&) = delete;
    EmbreeVisibility& operator=(const EmbreeVisibility&) = delete;
    ~EmbreeVisibility() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
    bool build(const PrtScene& s, std::string& why) {
        device = rtcNewDevice(nullptr);
        if (!device) {
            why = "rtcNewDevice failed";
            return false;
        }
        scene = rtcNewScene(device);
        rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
        RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* v = static_cast<float*>(
            rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), s.positions.size()));
        for (std::size_t i = 0; i < s.positions.size(); ++i) {
            v[3 * i] = s.positions[i].x;
            v[3 * i + 1] = s.positions[i].y;
            v[3 * i + 2] = s.positions[i].z;
        }
        auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                   3 * sizeof(unsigned), s.indices.size() / 3));
        std::copy(s.indices.begin(), s.indices.end(), idx);
        rtcCommitGeometry(g);
        rtcAttachGeometry(scene, g);
        rtcReleaseGeometry(g);
        rtcCommitScene(scene);
        tnear = 2e-4f * s.size;
        return true;
    }
    bool visible(const glm::vec3& o, const glm::vec3& d) const {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        RTCRay ray{};
        ray.org_x = o.x;
        ray.org_y = o.y;
        ray.org_z = o.z;
        ray.dir_x = d.x;
        ray.dir_y = d.y;
        ray.dir_z = d.z;
        ray.tnear = tnear;
        ray.tfar = 1e30f;
        ray.mask = 0xffffffffu;
        rtcOccluded1(scene, &ctx, &ray);
        return ray.tfar >= 0.f;
    }
    // shadowkit::PrtVisibilityFn form
    static bool callback(void* user, const glm::vec3& o, const glm::vec3& d) {
        return static_cast<const EmbreeVisibility*>(user)->visible(o, d);
    }
};

// Runs job(begin, end) over [0, count) in chunks on all cores; a progress line on stderr when
// the run takes longer than a second. Returns seconds.
template <class Job>
double parallel_for(std::size_t count, const char* label, Job&& job, bool progress = true) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::size_t chunk = 64;
    std::atomic<std::size_t> next{0}, done{0};
    const unsigned nt = std::max(1u, std::thread::hardware_concurrency());
    std::vector<std::thread> pool;
    for (unsigned t = 0; t < nt; ++t)
        pool.emplace_back([&] {
            for (;;) {
                const std::size_t b = next.fetch_add(chunk);
                if (b >= count) break;
                const std::size_t e = std::min(count, b + chunk);
                job(b, e);
                done.fetch_add(e - b);
            }
        });
    bool printed = false;
    for (;;) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        const std::size_t d = done.load();
        const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (progress && el > 1.0) {
            const int w = 30, filled = static_cast<int>(static_cast<double>(w) * static_cast<double>(d) / static_cast<double>(std::max<std::size_t>(count, 1)));
            std::fprintf(stderr, "\r%s [%.*s%*s] %zu/%zu  %.1f s", label, filled, "##############################",
                         w - filled, "", d, count, el);
            printed = true;
        }
        if (d >= count) break;
    }
    for (auto& t : pool) t.join();
    if (printed) std::fprintf(stderr, "\n");
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Transfer vectors of every vertex (n = order^2 floats each) with Embree visibility.
inline shadowkit::PrtTransferResult compute_transfer(const PrtScene& s, const EmbreeVisibility& vis,
                                                      const shadowkit::PrtSamples& samples, shadowkit::PrtMode mode,
                                                      std::vector<float>& out, double& seconds, bool progress = true) {
    const std::size_t n = shadowkit::prt_coefficient_count(samples.order);
    out.assign(s.positions.size() * n, 0.f);
    std::atomic<std::size_t> degenerate{0};
    std::atomic<std::uint64_t> rays{0};
    std::atomic<int> failed{0};
    shadowkit::PrtTransferOptions opt;
    opt.mode = mode;
    seconds = parallel_for(s.positions.size(), "PRT precomputation", [&](std::size_t b, std::size_t e) {
        const auto r = shadowkit::prt_compute_transfer(samples, opt, s.positions.data() + b, s.normals.data() + b, e - b,
                                                       &EmbreeVisibility::callback, const_cast<EmbreeVisibility*>(&vis),
                                                       out.data() + b * n, (e - b) * n);
        if (r.status != shadowkit::Status::Ok) failed = 1;
        degenerate += r.degenerate_vertices;
        rays += r.rays;
    }, progress);
    shadowkit::PrtTransferResult res;
    res.status = failed ? shadowkit::Status::InvalidArgument : shadowkit::Status::Ok;
    res.count = res.needed = out.size();
    res.degenerate_vertices = degenerate;
    res.rays = rays;
    return res;
}

// Monte Carlo reference of the exit radiance (albedo 1): (1/pi) integral L V max(n.s, 0) ds with
// strata^2 cosine-weighted stratified samples per vertex (estimator: mean of L V), a per-vertex
// random shift, Embree visibility. `stderr_out` gets each vertex's standard error estimate
// (two interleaved halves).
inline double reference_radiance(const PrtScene& s, const EmbreeVisibility& vis, const Environment& env,
                                 const std::vector<std::size_t>& vertices, int strata, std::vector<glm::vec3>& out,
                                 std::vector<float>& stderr_out, bool progress = true) {
    out.assign(vertices.size(), glm::vec3(0.f));
    stderr_out.assign(vertices.size(), 0.f);
    return parallel_for(vertices.size(), "Monte Carlo reference", [&](std::size_t b, std::size_t e) {
        for (std::size_t k = b; k < e; ++k) {
            const std::size_t v = vertices[k];
            const glm::vec3 n = glm::normalize(s.normals[v]);
            const glm::vec3 a = std::fabs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
            const glm::vec3 tx = glm::normalize(glm::cross(a, n)), ty = glm::cross(n, tx);
            std::uint32_t h = static_cast<std::uint32_t>(v) * 747796405u + 2891336453u;
            auto rnd = [&h] {
                h = h * 747796405u + 2891336453u;
                std::uint32_t w = ((h >> ((h >> 28u) + 4u)) ^ h) * 277803737u;
                w = (w >> 22u) ^ w;
                return static_cast<float>(w >> 8) * (1.0f / 16777216.0f);
            };
            glm::dvec3 half[2] = {glm::dvec3(0.0), glm::dvec3(0.0)};
            for (int i = 0; i < strata; ++i)
                for (int j = 0; j < strata; ++j) {
                    const float u = (static_cast<float>(i) + rnd()) / static_cast<float>(strata);
                    const float w = (static_cast<float>(j) + rnd()) / static_cast<float>(strata);
                    const float r = std::sqrt(u), phi = 2.f * kPi * w;  // cosine-weighted (Malley)
                    const glm::vec3 d = glm::normalize(r * std::cos(phi) * tx + r * std::sin(phi) * ty +
                                                       std::sqrt(std::max(0.f, 1.f - u)) * n);
                    if (vis.visible(s.positions[v], d)) half[(i + j) & 1] += glm::dvec3(env(d));
                }
            const double cnt = static_cast<double>(strata) * static_cast<double>(strata);
            out[k] = glm::vec3((half[0] + half[1]) / cnt);
            const glm::dvec3 diff = (half[0] - half[1]) / cnt;  // |mean_a - mean_b| / 2 ~ std error
            stderr_out[k] = static_cast<float>(std::fabs(diff.x + diff.y + diff.z) / 3.0);
        }
    }, progress);
}

// Errors of PRT shading against the reference at the same vertices: per vertex |PRT - ref| (mean
// of RGB), relative to the mean reference radiance (or `mean` when > 0).
struct PrtErrors {
    double rms = 0.0;   // RMS over vertices
    double p95 = 0.0;   // 95th percentile
    double bias = 0.0;  // mean signed error
};

inline PrtErrors compare_to_reference(const std::vector<glm::vec3>& prt, const std::vector<glm::vec3>& ref,
                                      double mean = 0.0) {
    PrtErrors out;
    if (ref.empty() || prt.size() < ref.size()) return out;
    if (!(mean > 0.0)) {
        mean = 0.0;
        for (const auto& r : ref) mean += (double(r.x) + double(r.y) + double(r.z)) / 3.0;
        mean /= double(ref.size());
    }
    std::vector<double> e(ref.size());
    double se = 0.0, sum = 0.0;
    for (std::size_t i = 0; i < ref.size(); ++i) {
        const glm::dvec3 d = glm::dvec3(prt[i]) - glm::dvec3(ref[i]);
        const double m = (d.x + d.y + d.z) / 3.0;
        e[i] = std::fabs(m);
        se += m * m;
        sum += m;
    }
    std::sort(e.begin(), e.end());
    const double n = double(ref.size());
    out.rms = std::sqrt(se / n) / mean;
    out.p95 = e[static_cast<std::size_t>(0.95 * (n - 1.0))] / mean;
    out.bias = sum / n / mean;
    return out;
}

}  // namespace skprt
