// libFuzzer target for include/shadowkit/prt.hpp: orders, strata, positions and normals (NaN/Inf,
// zero), options (albedo, offset, mode), a visibility callback driven by the bytes, capacities,
// environment radiance, and clustered-PCA parameters on the resulting transfer vectors.
// Also the function-pointer prt_compute_transfer (same result as the callable form) and
// prt_shade / prt_shade_rgb (0 for invalid order or null arrays, else the dot product: finite for
// bounded finite input, NaN propagated). Invariants trap on violation.
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

    // function-pointer form: the same transfer as the callable form for the same visibility answers
    {
        struct Vis {
            uint32_t pattern, calls;
        } vis{pattern, 0};
        const bool null_fn = (r.u8() & 3) == 0;
        const PrtVisibilityFn fn = null_fn ? nullptr : [](void* user, const glm::vec3&, const glm::vec3&) {
            Vis& v = *static_cast<Vis*>(user);
            return ((v.pattern >> (v.calls++ % 32)) & 1u) != 0u;
        };
        std::vector<float> T2(cap + 1, -7.0f);
        const PrtTransferResult tr2 = prt_compute_transfer(samples, opt, pos.data(), nrm.data(), pos.size(), fn,
                                                           null_fn ? nullptr : &vis, T2.data(), cap);
        check(T2[cap] == -7.0f);
        if (null_fn && !unshadowed) {
            check(tr2.status == PrtStatus::NullPointer && tr2.count == prt_coefficient_count(samples.order) * pos.size());
            check(tr2.rays == 0);
            for (float t : T2) check(t == -7.0f);
        } else {
            check(tr2.status == tr.status && tr2.count == tr.count && tr2.rays == tr.rays);
            check(tr2.degenerate_vertices == tr.degenerate_vertices);
            if (!null_fn) check(vis.calls == tr2.rays);
            if (tr.status == PrtStatus::Ok)
                for (size_t i = 0; i < tr.count; ++i) check(T2[i] == T[i] || (std::isnan(T2[i]) && std::isnan(T[i])));
        }
    }

    // prt_shade / prt_shade_rgb: sum_i T_i L_i; 0 for an invalid order or a null array
    {
        const uint8_t sf = r.u8();
        const int sorder = (sf & 1) ? r.i32() : r.range(-2, 7);
        const size_t sn = prt_coefficient_count(sorder);
        float t[25], e1[25];
        glm::vec3 e3[25];
        const bool interesting = (sf & 2) != 0;
        for (size_t i = 0; i < 25; ++i) {
            t[i] = interesting ? r.interesting_f32() : r.value(raw, kStep);
            e3[i] = interesting ? glm::vec3(r.interesting_f32(), r.interesting_f32(), r.interesting_f32()) : r.vec3(raw, kStep);
            e1[i] = e3[i].y;
        }
        const float* tp = (sf & 4) ? nullptr : t;
        const float* ep = (sf & 8) ? nullptr : e1;
        const glm::vec3* e3p = (sf & 8) ? nullptr : e3;
        const float s1 = prt_shade(sorder, tp, ep);
        const glm::vec3 s3 = prt_shade_rgb(sorder, tp, e3p);
        if (sn == 0 || !tp || !ep) {
            check(s1 == 0.0f && s3 == glm::vec3(0.0f));
        } else {
            // reference in double per channel (channel 3: the scalar form on the green channel);
            // float accumulation of <= 25 products
            for (int ch = 0; ch < 4; ++ch) {
                double ref = 0.0, mag = 0.0;
                bool fin = true, has_nan = false;
                for (size_t i = 0; i < sn; ++i) {
                    const float ev = ch == 3 ? e1[i] : e3[i][ch];
                    fin = fin && std::isfinite(t[i]) && std::isfinite(ev) && std::fabs(t[i]) <= 1e18f && std::fabs(ev) <= 1e18f;
                    has_nan = has_nan || std::isnan(t[i]) || std::isnan(ev);
                    ref += double(t[i]) * double(ev);
                    mag += std::fabs(double(t[i]) * double(ev));
                }
                const float got = ch == 3 ? s1 : s3[ch];
                if (has_nan) check(std::isnan(got));  // NaN in a coefficient is never hidden
                if (fin) {
                    check(std::isfinite(got));
                    check(std::fabs(double(got) - ref) <= 1e-5 * mag + 1e-37);
                }
            }
        }
    }

    // per-vertex cluster shading: out-of-range vertex or null projections give 0
    {
        PrtCpca empty;
        const glm::vec3 z = prt_cpca_shade(empty, env, r.size(3));
        check(z == glm::vec3(0.0f));
        check(prt_cpca_shade(empty, nullptr, 0) == glm::vec3(0.0f));
    }
    return 0;
}
