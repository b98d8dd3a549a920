// libFuzzer target for include/shadowkit/prt.hpp: orders, strata, positions and normals (NaN/Inf,
// zero), options (albedo, offset, mode), a visibility callback driven by the bytes, capacities,
// environment radiance, and clustered-PCA parameters on the resulting transfer vectors.
// Invariants trap on violation.
#include <shadowkit/prt.hpp>

#include "fuzz_input.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

using shadowkit_fuzz::check;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace shadowkit;
    shadowkit_fuzz::FuzzInput r(data, size);
    const uint8_t flags = r.u8();
    const bool raw = flags & 1, unshadowed = flags & 2;
    constexpr float kStep = 1.0f / 32.0f;  // quantized positions, normals and radiance scale
    const int order = r.range(-6, 6);
    const int strata = r.range(0, 9);
    PrtSamples samples;
    const PrtStatus ms = prt_make_samples(order, strata, r.u32(), samples);
    if (ms == PrtStatus::Ok) check(samples.count() == size_t(strata * strata));
    const size_t n = prt_coefficient_count(order);

    PrtTransferOptions opt;
    opt.mode = unshadowed ? PrtMode::Unshadowed : PrtMode::Shadowed;
    opt.albedo = raw ? r.f32() : 1.0f;
    opt.ray_offset = raw ? r.f32() : 0.0f;
    const size_t verts = r.size(23);
    std::vector<glm::vec3> pos, nrm;
    for (size_t v = 0; v < verts; ++v) {
        pos.push_back(r.vec3(raw, kStep));
        nrm.push_back(r.vec3(raw, kStep));
    }
    const uint32_t pattern = r.u32();
    uint32_t calls = 0;
    const size_t cap = r.size(699);
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
    const float scale = r.value(raw, kStep);
    const PrtResult pe = prt_project_environment(samples, [&](const glm::vec3& d) { return scale * d; }, env, r.size(29));
    if (pe.status == PrtStatus::Ok) {
        for (size_t i = 0; i < n; ++i) check(shadowkit_fuzz::all_finite(env[i]));
        if (tr.status == PrtStatus::Ok && tr.count > 0) {
            std::vector<glm::vec3> out(pos.size());
            const PrtResult sm = prt_shade_mesh(order, T.data(), n, pos.size(), env, out.data(), out.size());
            check(sm.status == PrtStatus::Ok);
        }
    }

    // clustered PCA on whatever transfer vectors came out
    if (tr.status == PrtStatus::Ok && tr.count > 0) {
        PrtCpcaOptions co;
        co.clusters = r.size(7);
        co.components = r.range(-29, 29);
        co.iterations = r.range(0, 4);
        co.seed = r.u32();
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
    (void)prt_sh_basis(order, r.vec3(raw, kStep), y, r.size(29));
    return 0;
}
