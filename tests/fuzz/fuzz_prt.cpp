// libFuzzer target for include/shadowkit/prt.hpp: orders, strata, positions and normals (NaN/Inf,
// zero), options (albedo, offset, mode), a visibility callback driven by the bytes, capacities,
// environment radiance (up to 3e38), and clustered-PCA parameters on the resulting transfer
// vectors. Calls every public function: also the function-pointer prt_compute_transfer (same
// result as the callable form), prt_shade / prt_shade_rgb / prt_shade_mesh against a double
// reference, prt_cpca_shade / prt_cpca_shade_mesh. Invariants trap: Status::Ok only with finite
// outputs, count == needed <= capacity when Ok, NaN input never Ok, Ok exactly when the
// double-precision radiance fits a float, nothing written past a capacity.
#include <shadowkit/prt.hpp>

#include "fuzz_input.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

using shadowkit_fuzz::all_finite;
using shadowkit_fuzz::check;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace shadowkit;
    shadowkit_fuzz::FuzzInput r(data, size);
    const uint8_t flags = r.u8();
    const bool raw = flags & 1, unshadowed = flags & 2;
    constexpr float kStep = 1.0f / 32.0f;  // quantized positions, normals and radiance scale
    const double fmax = double(std::numeric_limits<float>::max());
    const int order = r.range(-6, 6);
    const int strata = r.range(0, 9);
    const PrtSamples samples = prt_make_samples(order, strata, r.u32());
    shadowkit_fuzz::check_detail(samples);
    check(samples.status != Status::NotRun);
    if (samples.status == Status::Ok) check(samples.count() == size_t(strata * strata) && samples.order == order);
    else check(samples.count() == 0);
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
        [&](const glm::vec3& o, const glm::vec3& d) {
            check(std::fabs(glm::length(d) - 1.0f) < 1e-4f);
            check(all_finite(o));
            return ((pattern >> (calls++ % 32)) & 1u) != 0u;
        },
        T.data(), cap);
    shadowkit_fuzz::check_detail(tr);
    check(tr.status != Status::NotRun);
    check(tr.rays == calls);
    check(T[cap] == -7.0f);  // nothing written past the capacity
    check(tr.count <= cap);
    if (tr.status == Status::Ok) {
        check(tr.count == pos.size() * n && tr.count == tr.needed);
        for (size_t i = 0; i < tr.count; ++i) check(std::isfinite(T[i]));
        check(std::isfinite(opt.albedo) && std::isfinite(opt.ray_offset) && opt.ray_offset >= 0.0f);
        for (size_t v = 0; v < pos.size(); ++v) check(all_finite(nrm[v]) && (unshadowed || all_finite(pos[v])));
    } else {
        check(tr.count == 0 && tr.rays == 0);
    }

    // environment projection (radiance scale up to 3e38: Overflow reachable)
    glm::vec3 env[25];
    const float scale = (flags & 4) ? r.interesting_f32() : r.value(raw, kStep);
    const size_t ecap = r.size(29);
    const PrtResult pe = prt_project_environment(samples, [&](const glm::vec3& d) { return scale * d; }, env, ecap);
    shadowkit_fuzz::check_detail(pe);
    check(pe.status != Status::NotRun && pe.count <= ecap);
    if (pe.status == Status::Ok) {
        check(pe.count == n && std::isfinite(scale));
        for (size_t i = 0; i < n; ++i) check(all_finite(env[i]));
        if (tr.status == Status::Ok && tr.count > 0) {
            std::vector<glm::vec3> out(pos.size());
            const PrtResult sm = prt_shade_mesh(order, T.data(), n, pos.size(), env, out.data(), out.size());
            shadowkit_fuzz::check_detail(sm);
            check(sm.status == Status::Ok || sm.status == Status::Overflow);
            if (sm.status == Status::Ok) {
                check(sm.count == pos.size());
                for (const auto& o : out) check(all_finite(o));
            }
        }
    } else {
        check(pe.count == 0);
    }

    // clustered PCA on whatever transfer vectors came out
    if (tr.status == Status::Ok && tr.count > 0) {
        PrtCpcaOptions co;
        co.clusters = r.size(7);
        co.components = r.range(-29, 29);
        co.iterations = r.range(-1, 4);
        co.seed = r.u32();
        const PrtCpca cp = prt_cpca_compress(order, T.data(), n, pos.size(), co);
        shadowkit_fuzz::check_detail(cp);
        check(cp.status != Status::NotRun);
        if (cp.status == Status::Ok) {
            check(cp.clusters >= 1 && cp.clusters <= pos.size());
            check(std::isfinite(cp.rms_error));
            for (float w : cp.weights) check(std::isfinite(w));
            for (size_t v = 0; v < pos.size(); ++v) {
                check(cp.cluster_of[v] < cp.clusters);
                float rec[25];
                const PrtResult rr = prt_cpca_reconstruct(cp, v, rec, 25);
                shadowkit_fuzz::check_detail(rr);
                check(rr.status == Status::Ok || rr.status == Status::Overflow);
                if (rr.status == Status::Ok)
                    for (size_t i = 0; i < n; ++i) check(std::isfinite(rec[i]));
            }
            check(prt_cpca_reconstruct(cp, pos.size(), nullptr, 0).status == Status::IndexOutOfRange);
            if (pe.status == Status::Ok) {
                std::vector<glm::vec3> proj(cp.clusters * (size_t(cp.components) + 1));
                const PrtResult pp = prt_cpca_project_environment(cp, env, 25, proj.data(), proj.size());
                shadowkit_fuzz::check_detail(pp);
                check(pp.status == Status::Ok || pp.status == Status::Overflow);
                if (pp.status == Status::Ok) {
                    for (const auto& p : proj) check(all_finite(p));
                    std::vector<glm::vec3> shaded(pos.size());
                    const PrtResult sm = prt_cpca_shade_mesh(cp, proj.data(), shaded.data(), shaded.size());
                    shadowkit_fuzz::check_detail(sm);
                    check(sm.status == Status::Ok || sm.status == Status::Overflow);
                    for (size_t v = 0; v < pos.size(); ++v) {
                        const PrtRgbValue c = prt_cpca_shade(cp, proj.data(), v);
                        shadowkit_fuzz::check_detail(c);
                        check(c.status == Status::Ok || c.status == Status::Overflow);
                        if (c.status == Status::Ok) {
                            check(all_finite(c.value));
                            if (sm.status == Status::Ok) check(shaded[v] == c.value);
                        } else {
                            check(sm.status == Status::Overflow);
                        }
                    }
                }
            }
        } else {
            check(cp.clusters == 0);
        }
    }
    float y[25];
    const glm::vec3 bdir = r.vec3(raw, kStep);
    const size_t bcap = r.size(29);
    const PrtResult pb = prt_sh_basis(order, bdir, y, bcap);
    shadowkit_fuzz::check_detail(pb);
    check(pb.status != Status::NotRun && pb.count <= bcap);
    if (pb.status == Status::Ok) {
        check(all_finite(bdir) && pb.count == n);
        for (size_t i = 0; i < n; ++i) check(std::isfinite(y[i]));
    }

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
        shadowkit_fuzz::check_detail(tr2);
        check(T2[cap] == -7.0f);
        if (null_fn && !unshadowed) {
            check(tr2.status == Status::InvalidArgument && tr2.count == 0);
            check(tr2.rays == 0);
            for (float t : T2) check(t == -7.0f);
        } else {
            check(tr2.status == tr.status && tr2.count == tr.count && tr2.rays == tr.rays);
            check(tr2.degenerate_vertices == tr.degenerate_vertices);
            if (!null_fn) check(vis.calls == tr2.rays);
            if (tr.status == Status::Ok)
                for (size_t i = 0; i < tr.count; ++i) check(T2[i] == T[i]);
        }
    }

    // prt_shade / prt_shade_rgb / prt_shade_mesh: Ok with the dot product exactly when the
    // double-precision sum fits a float; NonFinite for NaN/Inf; InvalidArgument for a bad order or
    // a null array
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
        const PrtValue s1 = prt_shade(sorder, tp, ep);
        shadowkit_fuzz::check_detail(s1);
        const PrtRgbValue s3 = prt_shade_rgb(sorder, tp, e3p);
        shadowkit_fuzz::check_detail(s3);
        glm::vec3 mesh_out[1] = {glm::vec3(-7.0f)};
        const PrtResult sm = prt_shade_mesh(sorder, tp, 25, 1, e3p, mesh_out, 1);
        shadowkit_fuzz::check_detail(sm);
        if (sn == 0 || !tp || !ep) {
            check(s1.status == Status::InvalidArgument && s3.status == Status::InvalidArgument);
            check(sm.status == Status::InvalidArgument);
            check(s1.value == 0.0f && s3.value == glm::vec3(0.0f));
        } else {
            bool nonfinite3 = false, overflow3 = false;
            for (int ch = 0; ch < 4; ++ch) {
                double ref = 0.0, mag = 0.0;
                bool fin = true;
                for (size_t i = 0; i < sn; ++i) {
                    const float ev = ch == 3 ? e1[i] : e3[i][ch];
                    fin = fin && std::isfinite(t[i]) && std::isfinite(ev);
                    ref += double(t[i]) * double(ev);
                    mag += std::fabs(double(t[i]) * double(ev));
                }
                if (ch < 3)
                    for (size_t i = 0; i < sn; ++i) fin = fin && all_finite(e3[i]);  // the rgb form checks all channels
                const Status got = ch == 3 ? s1.status : s3.status;
                if (!fin) {
                    check(got == Status::NonFinite);
                    if (ch < 3) nonfinite3 = true;
                    continue;
                }
                const bool fits = std::fabs(ref) <= fmax;
                if (ch == 3) {
                    check(s1.status == (fits ? Status::Ok : Status::Overflow));
                    if (fits) check(std::isfinite(s1.value) && std::fabs(double(s1.value) - ref) <= 1e-5 * mag + 1e-37);
                } else if (!fits) {
                    overflow3 = true;
                } else if (s3.status == Status::Ok) {
                    check(std::isfinite(s3.value[ch]) && std::fabs(double(s3.value[ch]) - ref) <= 1e-5 * mag + 1e-37);
                }
            }
            const Status expect3 = nonfinite3 ? Status::NonFinite : overflow3 ? Status::Overflow : Status::Ok;
            check(s3.status == expect3);
            check(sm.status == expect3);
            if (sm.status == Status::Ok) check(mesh_out[0] == s3.value);
            else check(sm.count == 0);
        }
    }

    // per-vertex cluster shading: a compression no call filled, null projections
    {
        const PrtCpca empty;
        check(prt_cpca_shade(empty, env, r.size(3)).status == Status::InvalidArgument);
        glm::vec3 o[1];
        check(prt_cpca_shade_mesh(empty, env, o, 1).status == Status::InvalidArgument);
        check(prt_cpca_project_environment(empty, env, 25, o, 1).status == Status::InvalidArgument);
    }
    return 0;
}
