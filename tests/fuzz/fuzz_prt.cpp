// libFuzzer target for include/shadowkit/prt.hpp: orders, strata, positions and normals (NaN/Inf,
// zero), options (albedo, offset, mode), a visibility callback driven by the bytes, capacities,
// environment radiance, and clustered-PCA parameters on the resulting transfer vectors.
// Invariants trap on violation.
#include <shadowkit/prt.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

namespace {
struct Reader {
    const uint8_t* p;
    size_t n;
    template <class T>
    T get() {
        T v{};
        const size_t k = n < sizeof(T) ? n : sizeof(T);
        std::memcpy(&v, p, k);
        p += k;
        n -= k;
        return v;
    }
    float value(bool raw) {
        if (raw) return get<float>();
        return static_cast<float>(static_cast<int8_t>(get<uint8_t>())) / 32.0f;
    }
};

void check(bool ok) {
    if (!ok) __builtin_trap();
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace shadowkit;
    Reader r{data, size};
    const uint8_t flags = r.get<uint8_t>();
    const bool raw = flags & 1, unshadowed = flags & 2;
    const int order = static_cast<int>(static_cast<int8_t>(r.get<uint8_t>())) % 7;
    const int strata = static_cast<int>(r.get<uint8_t>() % 10);
    PrtSamples samples;
    const PrtStatus ms = prt_make_samples(order, strata, r.get<uint32_t>(), samples);
    if (ms == PrtStatus::Ok) check(samples.count() == size_t(strata * strata));
    const size_t n = prt_coefficient_count(order);

    PrtTransferOptions opt;
    opt.mode = unshadowed ? PrtMode::Unshadowed : PrtMode::Shadowed;
    opt.albedo = raw ? r.get<float>() : 1.0f;
    opt.ray_offset = raw ? r.get<float>() : 0.0f;
    const size_t verts = r.get<uint8_t>() % 24;
    std::vector<glm::vec3> pos, nrm;
    for (size_t v = 0; v < verts; ++v) {
        pos.emplace_back(r.value(raw), r.value(raw), r.value(raw));
        nrm.emplace_back(r.value(raw), r.value(raw), r.value(raw));
    }
    const uint32_t pattern = r.get<uint32_t>();
    uint32_t calls = 0;
    const size_t cap = static_cast<size_t>(r.get<uint16_t>() % 700);
    std::vector<float> T(cap + 1, -7.0f);
    const PrtTransferResult tr = prt_compute_transfer(
        samples, opt, pos.data(), nrm.data(), pos.size(),
        [&](const glm::vec3&, const glm::vec3& d) {
            check(std::fabs(glm::length(d) - 1.0f) < 1e-4f);
            return ((pattern >> (calls++ % 32)) & 1u) != 0u;
        },
        T.data(), cap);
    check(tr.rays == calls);
    check(T[cap] == -7.0f);  // nothing written past the capacity
    if (tr.status == PrtStatus::Ok) {
        check(tr.count == pos.size() * n && tr.count <= cap);
        for (size_t i = 0; i < tr.count; ++i) check(std::isfinite(T[i]));
    }

    // environment projection
    glm::vec3 env[25];
    const float scale = r.value(raw);
    const PrtResult pe = prt_project_environment(samples, [&](const glm::vec3& d) { return scale * d; }, env,
                                                 static_cast<size_t>(r.get<uint8_t>() % 30));
    if (pe.status == PrtStatus::Ok) {
        for (size_t i = 0; i < n; ++i) check(std::isfinite(env[i].x) && std::isfinite(env[i].y) && std::isfinite(env[i].z));
        if (tr.status == PrtStatus::Ok && tr.count > 0) {
            std::vector<glm::vec3> out(pos.size());
            const PrtResult sm = prt_shade_mesh(order, T.data(), n, pos.size(), env, out.data(), out.size());
            check(sm.status == PrtStatus::Ok);
        }
    }

    // clustered PCA on whatever transfer vectors came out
    if (tr.status == PrtStatus::Ok && tr.count > 0) {
        PrtCpcaOptions co;
        co.clusters = r.get<uint8_t>() % 8;
        co.components = static_cast<int>(static_cast<int8_t>(r.get<uint8_t>())) % 30;
        co.iterations = r.get<uint8_t>() % 5;
        co.seed = r.get<uint32_t>();
        PrtCpca cp;
        const PrtStatus cs = prt_cpca_compress(order, T.data(), n, pos.size(), co, cp);
        if (cs == PrtStatus::Ok) {
            check(cp.clusters >= 1 && cp.clusters <= pos.size());
            check(std::isfinite(cp.rms_error));
            for (size_t v = 0; v < pos.size(); ++v) {
                check(cp.cluster_of[v] < cp.clusters);
                float rec[25];
                check(prt_cpca_reconstruct(cp, v, rec, 25).status == PrtStatus::Ok);
                for (size_t i = 0; i < n; ++i) check(std::isfinite(rec[i]));
            }
            if (pe.status == PrtStatus::Ok) {
                std::vector<glm::vec3> proj(cp.clusters * (size_t(cp.components) + 1));
                check(prt_cpca_project_environment(cp, env, 25, proj.data(), proj.size()).status == PrtStatus::Ok);
                for (size_t v = 0; v < pos.size(); ++v) (void)prt_cpca_shade(cp, proj.data(), v);
            }
        } else {
            check(cp.clusters == 0);
        }
    }
    float y[25];
    (void)prt_sh_basis(order, glm::vec3(r.value(raw), r.value(raw), r.value(raw)), y, r.get<uint8_t>() % 30);
    return 0;
}
