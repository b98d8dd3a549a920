// PRT on the procedural `prt` scene (a lumpy blob and a box over a floor under a sky + sun
// environment) against a Monte Carlo reference of the same environment with Embree visibility:
// shading error per SH order 1..5 (must decrease with the order and stay under stated bounds),
// the unshadowed (no visibility) error for comparison, and the precomputation time. Prints the
// error-vs-order table, in markdown too, for the README.
#include <doctest/doctest.h>

#include <shadowkit/prt.hpp>
#include <shadowkit/spherical_harmonics.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include "../../samples/prt/prt_scene.hpp"

namespace sk = shadowkit;

namespace {

using Errors = skprt::PrtErrors;

Errors compare(const std::vector<glm::vec3>& prt, const std::vector<glm::vec3>& ref) {
    return skprt::compare_to_reference(prt, ref);
}

}  // namespace

TEST_CASE("prt scene: PRT shading against a Monte Carlo reference, error vs SH order") {
    const skprt::PrtScene scene = skprt::make_prt_scene(1);
    const skprt::Environment env;
    skprt::EmbreeVisibility vis;
    std::string why;
    REQUIRE_MESSAGE(vis.build(scene, why), why);

    // transfer at order 5 (lower orders are its prefixes) from 32 x 32 stratified samples
    const int strata = 32;
    const sk::PrtSamples samples = sk::prt_make_samples(5, strata, 1u);
    REQUIRE(samples.status == sk::Status::Ok);
    std::vector<float> transfer, unshadowed;
    double seconds = 0.0, seconds_un = 0.0;
    const auto tr = skprt::compute_transfer(scene, vis, samples, sk::PrtMode::Shadowed, transfer, seconds);
    REQUIRE(tr.status == sk::Status::Ok);
    CHECK(tr.degenerate_vertices == 0);
    REQUIRE(skprt::compute_transfer(scene, vis, samples, sk::PrtMode::Unshadowed, unshadowed, seconds_un, false).status ==
            sk::Status::Ok);

    // environment in SH from a denser, independent sample set (128^2), order 5
    const sk::PrtSamples env_samples = sk::prt_make_samples(5, 128, 99u);
    REQUIRE(env_samples.status == sk::Status::Ok);
    std::vector<glm::vec3> env_sh(25);
    REQUIRE(sk::prt_project_environment(env_samples, env, env_sh.data(), env_sh.size()).status == sk::Status::Ok);

    // reference at every 4th vertex (all parts of the scene), 48 x 48 cosine-weighted samples
    std::vector<std::size_t> verts;
    for (std::size_t v = 0; v < scene.positions.size(); v += 4) verts.push_back(v);
    std::vector<glm::vec3> ref;
    std::vector<float> ref_err;
    const double ref_seconds = skprt::reference_radiance(scene, vis, env, verts, 48, ref, ref_err);
    double ref_stderr = 0.0, mean_ref = 0.0;
    for (std::size_t k = 0; k < verts.size(); ++k) {
        ref_stderr += double(ref_err[k]) * double(ref_err[k]);
        mean_ref += (ref[k].x + ref[k].y + ref[k].z) / 3.0;
    }
    mean_ref /= double(verts.size());
    ref_stderr = std::sqrt(ref_stderr / double(verts.size())) / mean_ref;

    std::vector<Errors> shadowed(6), flat(6);
    for (int order = 1; order <= 5; ++order) {
        std::vector<glm::vec3> a(verts.size()), b(verts.size());
        for (std::size_t k = 0; k < verts.size(); ++k) {
            a[k] = sk::prt_shade_rgb(order, &transfer[verts[k] * 25], env_sh.data()).value;
            b[k] = sk::prt_shade_rgb(order, &unshadowed[verts[k] * 25], env_sh.data()).value;
        }
        shadowed[std::size_t(order)] = compare(a, ref);
        flat[std::size_t(order)] = compare(b, ref);
    }

    // clustered PCA of the order-5 transfer vectors (Sloan et al. 2003): 64 clusters x (mean + 4)
    sk::PrtCpcaOptions copt;
    copt.clusters = 64;
    copt.components = 4;
    const auto c0 = std::chrono::steady_clock::now();
    const sk::PrtCpca cp = sk::prt_cpca_compress(5, transfer.data(), 25, scene.positions.size(), copt);
    REQUIRE(cp.status == sk::Status::Ok);
    const double cpca_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - c0).count();
    std::vector<glm::vec3> proj(cp.clusters * 5), cpca_shaded(verts.size());
    REQUIRE(sk::prt_cpca_project_environment(cp, env_sh.data(), 25, proj.data(), proj.size()).status == sk::Status::Ok);
    for (std::size_t k = 0; k < verts.size(); ++k) cpca_shaded[k] = sk::prt_cpca_shade(cp, proj.data(), verts[k]).value;
    const Errors cpca = compare(cpca_shaded, ref);

    const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
    std::printf("\nPRT on the procedural `prt` scene: %zu vertices, %zu triangles; environment = sky + sun lobe "
                "(sharpness %.0f)\n",
                scene.positions.size(), scene.indices.size() / 3, double(env.sharpness));
    std::printf("precomputation (shadowed, order 5, %d x %d samples, Embree, %u threads): %.2f s, %.2f Mrays, "
                "%.1f us/vertex\n",
                strata, strata, threads, seconds, double(tr.rays) * 1e-6, 1e6 * seconds / double(scene.positions.size()));
    std::printf("reference: %zu vertices x %d cosine-weighted samples, %.2f s, standard error %.2f%% of the mean\n\n",
                verts.size(), 48 * 48, ref_seconds, 100.0 * ref_stderr);
    std::printf("| SH order | coefficients | shadowed PRT: RMS error | p95 error | bias | unshadowed: RMS error |\n");
    std::printf("|---:|---:|---:|---:|---:|---:|\n");
    for (int order = 1; order <= 5; ++order) {
        const Errors& s = shadowed[std::size_t(order)];
        std::printf("| %d | %d | %.2f%% | %.2f%% | %+.2f%% | %.1f%% |\n", order, order * order, 100.0 * s.rms,
                    100.0 * s.p95, 100.0 * s.bias, 100.0 * flat[std::size_t(order)].rms);
    }
    std::printf("| 5, CPCA 64 x (mean + 4) | 4 weights + cluster id | %.2f%% | %.2f%% | %+.2f%% | - |\n", 100.0 * cpca.rms,
                100.0 * cpca.p95, 100.0 * cpca.bias);
    std::printf("\nErrors relative to the mean reference radiance over %zu vertices (floor, blob, box). CPCA "
                "compression took %.2f s.\n",
                verts.size(), cpca_seconds);
    std::fflush(stdout);

    for (int order = 2; order <= 5; ++order) CHECK(shadowed[std::size_t(order)].rms < shadowed[std::size_t(order - 1)].rms);
    // measured (seeds fixed, deterministic): 55.9%, 16.0%, 7.0%, 4.2%, 2.4%
    CHECK(shadowed[1].rms < 0.75);
    CHECK(shadowed[3].rms < 0.10);
    CHECK(shadowed[5].rms < 0.04);
    CHECK(std::fabs(shadowed[5].bias) < 0.01);
    CHECK(cpca.rms < 0.05);
    // visibility matters: without it the error stays large whatever the order
    CHECK(flat[5].rms > 2.0 * shadowed[5].rms);
    CHECK(ref_stderr < 0.02);
}
