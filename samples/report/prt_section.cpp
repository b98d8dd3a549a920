#include "prt_section.hpp"

#include <shadowkit/prt.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>
#include <vector>

#include "../prt/prt_scene.hpp"

namespace skp = shadowkit;  // (sk is the harness namespace)

namespace skr {

namespace {

// Per-vertex |PRT - ref| (mean of RGB) over the reference vertices, relative to the mean reference.
void compare(const std::vector<glm::vec3>& prt, const std::vector<glm::vec3>& ref, double mean, PrtOrderRow& row) {
    const skprt::PrtErrors e = skprt::compare_to_reference(prt, ref, mean);
    row.rms = e.rms;
    row.p95 = e.p95;
    row.bias = e.bias;
}

template <class F>
double median_ms(int runs, F&& f) {
    std::vector<double> t;
    for (int i = 0; i < runs; ++i) {
        const auto t0 = std::chrono::steady_clock::now();
        f();
        t.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    std::sort(t.begin(), t.end());
    return t[t.size() / 2];
}

}  // namespace

const char* prt_description() {
    return "PRT (SH transfer with visibility) on a blob and a box over a floor under a sky + sun: "
           "error vs SH order 1..5 against Monte Carlo, CPU + Embree [pseudo-scene]";
}

bool run_prt(bool quick, PrtReport& out, std::string& why) {
    out.requested = true;
    const skprt::PrtScene scene = skprt::make_prt_scene(1);
    const skprt::Environment env;
    skprt::EmbreeVisibility vis;
    if (!vis.build(scene, why)) return false;
    out.vertices = scene.positions.size();
    out.triangles = scene.indices.size() / 3;
    out.threads = std::max(1u, std::thread::hardware_concurrency());
    char desc[200];
    std::snprintf(desc, sizeof desc,
                  "a lumpy blob and a box over a floor (%zu vertices, %zu triangles) under a sky + sun-lobe "
                  "environment (sharpness %.0f)",
                  out.vertices, out.triangles, double(env.sharpness));
    out.description = desc;

    // shadowed transfer at order 5 (orders 1..4 are its prefixes); unshadowed for comparison
    const int strata = 32;
    const skp::PrtSamples samples = skp::prt_make_samples(out.transfer_order, strata, 1u);
    if (samples.status != skp::Status::Ok) {
        why = "prt_make_samples failed";
        return false;
    }
    out.transfer_samples = strata * strata;
    const std::size_t n = skp::prt_coefficient_count(out.transfer_order);
    std::vector<float> transfer, unshadowed;
    double unshadowed_seconds = 0.0;
    const auto tr = skprt::compute_transfer(scene, vis, samples, skp::PrtMode::Shadowed, transfer, out.transfer_seconds);
    if (tr.status != skp::Status::Ok ||
        skprt::compute_transfer(scene, vis, samples, skp::PrtMode::Unshadowed, unshadowed, unshadowed_seconds, false)
                .status != skp::Status::Ok) {
        why = "prt_compute_transfer failed";
        return false;
    }
    out.transfer_rays = tr.rays;
    out.degenerate_vertices = tr.degenerate_vertices;

    // the environment in SH from a denser, independent sample set
    const int env_strata = 128;
    const skp::PrtSamples env_samples = skp::prt_make_samples(out.transfer_order, env_strata, 99u);
    std::vector<glm::vec3> env_sh(n);
    if (env_samples.status != skp::Status::Ok ||
        skp::prt_project_environment(env_samples, env, env_sh.data(), env_sh.size()).status != skp::Status::Ok) {
        why = "prt_project_environment failed";
        return false;
    }
    out.env_samples = env_strata * env_strata;

    // Monte Carlo reference at every 4th vertex (quick: every 8th) with 48^2 (quick: 32^2) samples
    out.ref_vertex_stride = quick ? 8 : 4;
    const int ref_strata = quick ? 32 : 48;
    std::vector<std::size_t> verts;
    for (std::size_t v = 0; v < scene.positions.size(); v += out.ref_vertex_stride) verts.push_back(v);
    std::vector<glm::vec3> ref;
    std::vector<float> ref_err;
    out.ref_seconds = skprt::reference_radiance(scene, vis, env, verts, ref_strata, ref, ref_err);
    out.ref_vertices = verts.size();
    out.ref_samples = ref_strata * ref_strata;
    double se2 = 0.0, mean = 0.0;
    for (std::size_t k = 0; k < verts.size(); ++k) {
        se2 += double(ref_err[k]) * double(ref_err[k]);
        mean += (double(ref[k].x) + double(ref[k].y) + double(ref[k].z)) / 3.0;
    }
    mean /= double(verts.size());
    if (!(mean > 0.0)) {
        why = "the Monte Carlo reference is black";
        return false;
    }
    out.ref_mean = mean;
    out.ref_stderr = std::sqrt(se2 / double(verts.size())) / mean;

    // per order: error at the reference vertices, CPU shading time over all vertices
    out.shade_runs = 20;
    std::vector<glm::vec3> shaded(scene.positions.size()), a(verts.size()), b(verts.size());
    for (int order = 1; order <= out.transfer_order; ++order) {
        PrtOrderRow row;
        row.order = order;
        row.coefficients = order * order;
        row.label = std::to_string(order);
        row.storage = std::to_string(row.coefficients);
        for (std::size_t k = 0; k < verts.size(); ++k) {
            a[k] = skp::prt_shade_rgb(order, &transfer[verts[k] * n], env_sh.data()).value;
            b[k] = skp::prt_shade_rgb(order, &unshadowed[verts[k] * n], env_sh.data()).value;
        }
        compare(a, ref, mean, row);
        PrtOrderRow flat;
        compare(b, ref, mean, flat);
        row.unshadowed_rms = flat.rms;
        bool ok = true;
        row.shade_ms = median_ms(out.shade_runs, [&] {
            ok = skp::prt_shade_mesh(order, transfer.data(), n, scene.positions.size(), env_sh.data(), shaded.data(),
                                    shaded.size()).status == skp::Status::Ok && ok;
        });
        if (!ok) {
            why = "prt_shade_mesh failed";
            return false;
        }
        out.orders.push_back(row);
    }

    // clustered PCA of the order-5 transfer (Sloan et al. 2003): 64 clusters x (mean + 4 vectors)
    skp::PrtCpcaOptions copt;
    copt.clusters = 64;
    copt.components = 4;
    const auto c0 = std::chrono::steady_clock::now();
    const skp::PrtCpca cp = skp::prt_cpca_compress(out.transfer_order, transfer.data(), n, scene.positions.size(), copt);
    if (cp.status != skp::Status::Ok) {
        why = "prt_cpca_compress failed";
        return false;
    }
    out.cpca_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - c0).count();
    out.cpca_clusters = cp.clusters;
    out.cpca_components = cp.components;
    out.cpca_transfer_rms = cp.rms_error;
    const std::size_t C = static_cast<std::size_t>(cp.components);
    std::vector<glm::vec3> proj(cp.clusters * (C + 1));
    PrtOrderRow row;
    row.order = out.transfer_order;
    row.coefficients = cp.components;
    row.cpca = true;
    row.label = std::to_string(out.transfer_order) + ", CPCA " + std::to_string(cp.clusters) + " x (mean + " +
                std::to_string(cp.components) + ")";
    row.storage = std::to_string(cp.components) + " weights + cluster id";
    bool ok = true;
    // per frame: the per-cluster projections of the environment, then a C-term sum per vertex
    row.shade_ms = median_ms(out.shade_runs, [&] {
        ok = skp::prt_cpca_project_environment(cp, env_sh.data(), env_sh.size(), proj.data(), proj.size()).status ==
                 skp::Status::Ok && ok;
        ok = skp::prt_cpca_shade_mesh(cp, proj.data(), shaded.data(), shaded.size()).status == skp::Status::Ok && ok;
    });
    if (!ok) {
        why = "prt_cpca_project_environment failed";
        return false;
    }
    for (std::size_t k = 0; k < verts.size(); ++k) a[k] = shaded[verts[k]];
    compare(a, ref, mean, row);
    out.orders.push_back(row);
    return true;
}

}  // namespace skr
