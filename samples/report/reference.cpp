#include "reference.hpp"

#include <embree3/rtcore.h>

#include <glm/glm.hpp>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <thread>

#include <unistd.h>  // isatty

namespace sk {

namespace {

constexpr float kPi = 3.14159265358979f;

void orthonormal_basis(glm::vec3 n, glm::vec3& t, glm::vec3& b) {
    // Duff et al. 2017, "Building an Orthonormal Basis, Revisited"
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z);
    const float bb = n.x * n.y * a;
    t = glm::vec3(1.0f + sign * n.x * n.x * a, sign * bb, -sign * n.x);
    b = glm::vec3(bb, sign + n.y * n.y * a, -n.y);
}

// Shirley & Chiu concentric square-to-disk map (keeps the strata's shape).
glm::vec2 concentric_disk(float u, float v) {
    const float a = 2.f * u - 1.f, b = 2.f * v - 1.f;
    if (a == 0.f && b == 0.f) return {0.f, 0.f};
    float r, phi;
    if (std::abs(a) > std::abs(b)) {
        r = a;
        phi = (kPi / 4.f) * (b / a);
    } else {
        r = b;
        phi = (kPi / 2.f) - (kPi / 4.f) * (a / b);
    }
    return {r * std::cos(phi), r * std::sin(phi)};
}


bool occluded(RTCScene scene, glm::vec3 org, glm::vec3 dir, float tfar) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRay ray{};
    ray.org_x = org.x;
    ray.org_y = org.y;
    ray.org_z = org.z;
    ray.dir_x = dir.x;
    ray.dir_y = dir.y;
    ray.dir_z = dir.z;
    ray.tnear = 0.f;
    ray.tfar = tfar;
    ray.mask = 0xffffffffu;
    ray.flags = 0;
    ray.time = 0.f;
    rtcOccluded1(scene, &ctx, &ray);
    return ray.tfar < 0.f;
}

}  // namespace

bool build_embree(const Scene& s, EmbreeScene& e, std::string& why) {
    e.device = rtcNewDevice(nullptr);
    if (!e.device) {
        why = "rtcNewDevice failed";
        return false;
    }
    e.scene = rtcNewScene(e.device);
    rtcSetSceneBuildQuality(e.scene, RTC_BUILD_QUALITY_HIGH);
    for (const auto& m : s.meshes) {
        if (!m.caster || m.indices.empty()) continue;
        RTCGeometry geom = rtcNewGeometry(e.device, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                              3 * sizeof(float), m.positions.size()));
        for (std::size_t i = 0; i < m.positions.size(); ++i) {
            v[3 * i] = m.positions[i].x;
            v[3 * i + 1] = m.positions[i].y;
            v[3 * i + 2] = m.positions[i].z;
        }
        auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                   3 * sizeof(unsigned), m.indices.size() / 3));
        std::memcpy(idx, m.indices.data(), (m.indices.size() / 3) * 3 * sizeof(unsigned));
        rtcCommitGeometry(geom);
        rtcAttachGeometry(e.scene, geom);
        rtcReleaseGeometry(geom);
    }
    rtcCommitScene(e.scene);
    return true;
}

bool compute_reference(const Scene& s, const GBuffer& g, const ReferenceOptions& opt, Reference& out,
                       std::string& why) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::size_t n = static_cast<std::size_t>(g.width) * static_cast<std::size_t>(g.height);
    if (g.width <= 0 || g.height <= 0 || g.position.size() != 3 * n || g.normal.size() != 3 * n || g.kind.size() != n) {
        why = "reference: G-buffer has the wrong size";
        return false;
    }
    EmbreeScene e;
    if (!build_embree(s, e, why)) return false;

    const Light& L = s.light;
    const float diag = glm::length(s.bounds_max() - s.bounds_min());
    const float eps = opt.offset_fraction * (std::isfinite(diag) && diag > 0.f ? diag : 1.f);
    const bool area = L.is_area();
    const int strata = area ? std::max(opt.strata, 2) : 1;
    out = Reference{};
    out.visibility.assign(n, 0.f);
    out.faces_light.assign(n, 0);
    out.samples_per_pixel = strata * strata;
    std::vector<float> half_diff(area ? n : 0, 0.f);
    glm::vec3 lt, lb;
    const glm::vec3 ldir = glm::normalize(L.direction);
    orthonormal_basis(ldir, lt, lb);
    const float cos_cone = std::cos(L.spot_half_angle);

    std::atomic<int> next_row{0}, rows_done{0};
    auto worker = [&]() {
        for (;;) {
            const int y = next_row.fetch_add(1);
            if (y >= g.height) break;
            for (int x = 0; x < g.width; ++x) {
                const auto k = static_cast<std::size_t>(y) * static_cast<std::size_t>(g.width) + static_cast<std::size_t>(x);
                if (g.kind[k] == 0) continue;
                const glm::vec3 p(g.position[3 * k], g.position[3 * k + 1], g.position[3 * k + 2]);
                const glm::vec3 nn(g.normal[3 * k], g.normal[3 * k + 1], g.normal[3 * k + 2]);
                const glm::vec3 org = p + eps * nn;
                const glm::vec3 to_center = L.type == LightType::Directional ? -ldir : L.position - p;
                out.faces_light[k] = glm::dot(nn, to_center) > 0.f ? 1 : 0;
                if (!area) {
                    float v = 0.f;
                    if (L.type == LightType::Directional) {
                        if (glm::dot(nn, -ldir) > 0.f && !occluded(e.scene, org, -ldir, INFINITY)) v = 1.f;
                    } else {
                        const glm::vec3 d = L.position - org;
                        const float dist = glm::length(d);
                        const glm::vec3 dn = d / dist;
                        const bool in_cone = L.type != LightType::Spot || glm::dot(-dn, ldir) >= cos_cone;
                        if (in_cone && glm::dot(nn, dn) > 0.f && !occluded(e.scene, org, dn, dist * (1.f - 1e-5f))) v = 1.f;
                    }
                    out.visibility[k] = v;
                    continue;
                }
                Pcg rng(static_cast<std::uint64_t>(k) * 0x9E3779B97F4A7C15ull + opt.seed);
                int seen[2] = {0, 0}, count[2] = {0, 0};
                const glm::vec3 pc = L.position - p;
                const float dc = glm::length(pc);
                const bool behind_emitter =
                    (L.type == LightType::Rect || L.type == LightType::Disk) && glm::dot(p - L.position, ldir) <= 0.f;
                const bool inside_sphere = L.type == LightType::Sphere && dc <= L.size;
                glm::vec3 ct, cb;
                const glm::vec3 cw = pc / dc;
                orthonormal_basis(cw, ct, cb);
                const float sin2 = L.type == LightType::Sphere && !inside_sphere ? (L.size * L.size) / (dc * dc) : 0.f;
                const float cos_max = std::sqrt(std::max(0.f, 1.f - sin2));
                for (int i = 0; i < strata; ++i)
                    for (int j = 0; j < strata; ++j) {
                        const int half = (i + j) & 1;
                        ++count[half];
                        if (behind_emitter || inside_sphere) continue;
                        const float u = (static_cast<float>(i) + rng.uniform()) / static_cast<float>(strata);
                        const float v = (static_cast<float>(j) + rng.uniform()) / static_cast<float>(strata);
                        glm::vec3 dir;
                        float tfar;
                        if (L.type == LightType::Sphere) {
                            // uniform over the cone subtended by the sphere (solid angle)
                            const float ct_ = 1.f - u * (1.f - cos_max);
                            const float st_ = std::sqrt(std::max(0.f, 1.f - ct_ * ct_));
                            const float phi = 2.f * kPi * v;
                            dir = ct_ * cw + st_ * std::cos(phi) * ct + st_ * std::sin(phi) * cb;
                            const float b = dc * ct_;
                            const float disc = L.size * L.size - dc * dc * st_ * st_;
                            tfar = b - std::sqrt(std::max(0.f, disc));
                        } else if (L.type == LightType::Linear) {
                            // stratified along the segment: strata * strata strata, one jittered sample each
                            const float t = (static_cast<float>(i) + v) / static_cast<float>(strata);
                            const glm::vec3 q = L.position + (t - 0.5f) * L.size * ldir;
                            dir = q - org;
                            tfar = glm::length(dir);
                            dir /= tfar;
                        } else {
                            glm::vec2 o = L.type == LightType::Rect ? glm::vec2((u - 0.5f) * L.size, (v - 0.5f) * L.size)
                                                                    : concentric_disk(u, v) * L.size;
                            const glm::vec3 q = L.position + o.x * lt + o.y * lb;
                            dir = q - org;
                            tfar = glm::length(dir);
                            dir /= tfar;
                        }
                        if (glm::dot(dir, nn) <= 0.f) continue;  // below the tangent plane
                        if (!occluded(e.scene, org, dir, tfar * (1.f - 1e-5f))) ++seen[half];
                    }
                const float va = count[0] ? float(seen[0]) / float(count[0]) : 0.f;
                const float vb = count[1] ? float(seen[1]) / float(count[1]) : 0.f;
                out.visibility[k] = float(seen[0] + seen[1]) / float(count[0] + count[1]);
                half_diff[k] = 0.5f * std::abs(va - vb);
            }
            rows_done.fetch_add(1);
        }
    };
    int threads = opt.threads > 0 ? opt.threads : static_cast<int>(std::thread::hardware_concurrency());
    threads = std::max(threads, 1);
    std::vector<std::thread> pool;
    for (int i = 0; i < threads; ++i) pool.emplace_back(worker);
    bool shown = false;
    // a bar redrawn with carriage returns on a terminal; in a log (not a terminal) one line when done
    const bool redraw = opt.progress && isatty(fileno(stderr)) != 0;
    while (rows_done.load() < g.height) {
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (redraw && el > 1.0) {
            const int done = rows_done.load();
            const int bar = 30 * done / g.height;
            std::fprintf(stderr, "\r  reference %-9s [%.*s%*s] %3d%% %5.1fs", s.name.c_str(), bar,
                         "##############################", 30 - bar, "", 100 * done / g.height, el);
            shown = true;
        }
    }
    for (auto& t : pool) t.join();
    const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (shown)
        std::fprintf(stderr, "\n");
    else if (opt.progress && !redraw && total > 1.0)
        std::fprintf(stderr, "  reference %-9s %d rays per pixel, %.1fs\n", s.name.c_str(), out.samples_per_pixel, total);
    if (area) {
        double sum = 0.0;
        std::size_t cnt = 0;
        for (std::size_t k = 0; k < n; ++k)
            if (g.kind[k] == 1) {
                sum += double(half_diff[k]) * double(half_diff[k]);
                ++cnt;
            }
        out.stderr_rms = cnt ? std::sqrt(sum / double(cnt)) : 0.0;
    }
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return true;
}

static std::uint64_t fnv(const void* data, std::size_t bytes, std::uint64_t h) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < bytes; ++i) {
        h ^= p[i];
        h *= 1099511628211ull;
    }
    return h;
}

bool cached_reference(const Scene& s, const GBuffer& g, const ReferenceOptions& opt, const std::string& cache_dir,
                      Reference& out, std::string& why) {
    std::uint64_t salt = 0x5eed0002ull;  // bump when the reference's definition changes
    salt = fnv(&opt.strata, sizeof opt.strata, salt);
    salt = fnv(&opt.offset_fraction, sizeof opt.offset_fraction, salt);
    salt = fnv(&opt.seed, sizeof opt.seed, salt);
    salt = fnv(g.position.data(), g.position.size() * sizeof(float), salt);
    salt = fnv(g.kind.data(), g.kind.size(), salt);
    const std::uint64_t key = scene_hash(s, g.width, g.height, salt);
    char name[64];
    std::snprintf(name, sizeof name, "ref-%016llx.bin", static_cast<unsigned long long>(key));
    const std::filesystem::path path = std::filesystem::path(cache_dir) / name;
    const std::size_t n = static_cast<std::size_t>(g.width) * static_cast<std::size_t>(g.height);
    {
        std::ifstream f(path, std::ios::binary);
        if (f) {
            std::uint64_t k2 = 0;
            Reference r;
            r.visibility.resize(n);
            r.faces_light.resize(n);
            f.read(reinterpret_cast<char*>(&k2), sizeof k2);
            f.read(reinterpret_cast<char*>(&r.samples_per_pixel), sizeof r.samples_per_pixel);
            f.read(reinterpret_cast<char*>(&r.stderr_rms), sizeof r.stderr_rms);
            f.read(reinterpret_cast<char*>(&r.seconds), sizeof r.seconds);
            f.read(reinterpret_cast<char*>(r.visibility.data()), static_cast<std::streamsize>(n * sizeof(float)));
            f.read(reinterpret_cast<char*>(r.faces_light.data()), static_cast<std::streamsize>(n));
            if (f && k2 == key) {
                r.from_cache = true;
                out = std::move(r);
                return true;
            }
        }
    }
    if (!compute_reference(s, g, opt, out, why)) return false;
    std::error_code ec;
    std::filesystem::create_directories(cache_dir, ec);
    std::ofstream f(path, std::ios::binary);
    if (f) {
        f.write(reinterpret_cast<const char*>(&key), sizeof key);
        f.write(reinterpret_cast<const char*>(&out.samples_per_pixel), sizeof out.samples_per_pixel);
        f.write(reinterpret_cast<const char*>(&out.stderr_rms), sizeof out.stderr_rms);
        f.write(reinterpret_cast<const char*>(&out.seconds), sizeof out.seconds);
        f.write(reinterpret_cast<const char*>(out.visibility.data()), static_cast<std::streamsize>(n * sizeof(float)));
        f.write(reinterpret_cast<const char*>(out.faces_light.data()), static_cast<std::streamsize>(n));
    }
    return true;
}

}  // namespace sk
