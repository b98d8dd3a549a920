// Shadow silhouette maps on the GL harness (llvmpipe or a real driver) against the Embree
// reference: fewer misclassified pixels than a plain shadow map of equal memory on the
// straight-edged stack scene, and the boundary error measured in shadow-map texels (distance in
// the light's texel space from each misclassified pixel to the exact shadow boundary, i.e. the
// projected silhouette edges) within the paper's sub-texel claim; failure texels on the fence.
#include <doctest/doctest.h>

#include <shadowkit/silhouette.hpp>
#include <shadowkit/silhouette_map.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "../silmap_reference.hpp"
#include "gl_test.hpp"
#include "metrics.hpp"
#include "reference.hpp"
#include "scene.hpp"
#include "techniques.hpp"

namespace {

sk::Technique* find(std::vector<std::unique_ptr<sk::Technique>>& t, const std::string& name) {
    for (auto& x : t)
        if (x->name() == name) return x.get();
    return nullptr;
}

// Texel-space silhouette edges of all casters (the exact shadow boundary in the light's image).
std::vector<shadowkit::SilmapEdge> boundary_edges(const sk::Scene& s, const glm::mat4& vp, int size) {
    std::vector<shadowkit::SilmapEdge> out;
    for (const auto& m : s.meshes) {
        if (!m.caster) continue;
        const auto adj = shadowkit::silhouette_build_adjacency(m.positions.data(), m.positions.size(), m.indices.data(), m.indices.size());
        const auto sil = shadowkit::silhouette_compute(adj, m.positions.data(), m.positions.size(), glm::vec4(s.light.position, 1.f));
        std::vector<shadowkit::SilmapEdge> e(sil.indices.size() / 2);
        const auto pr = shadowkit::silmap_project_edges(vp, shadowkit::ClipDepth::NegativeOneToOne, glm::uvec2(size, size),
                                                        m.positions.data(), m.positions.size(), sil.indices.data(),
                                                        sil.indices.size() / 2, e.data(), e.size());
        out.insert(out.end(), e.begin(), e.begin() + static_cast<std::ptrdiff_t>(pr.count));
    }
    return out;
}

struct Boundary {
    double p50 = 0.0, p95 = 0.0, max = 0.0;
    std::size_t wrong = 0;
};

// Distance in texels (of a map of `size`) from each misclassified receiver pixel to the boundary.
Boundary boundary_error(const sk::Scene& s, const sk::GBuffer& g, const sk::Reference& ref, const std::vector<float>& v,
                        int size) {
    const sk::LightMatrices lm = sk::fit_light(s);
    const glm::mat4 vp = lm.proj * lm.view;
    const auto edges = boundary_edges(s, vp, size);
    std::vector<double> d;
    for (std::size_t k = 0; k < g.kind.size(); ++k) {
        if (g.kind[k] != 1 || !ref.faces_light[k]) continue;
        if ((v[k] >= 0.5f) == (ref.visibility[k] >= 0.5f)) continue;
        const silmap_ref::EdgeDistance ed =
            silmap_ref::edge_distance(vp, glm::vec3(g.position[3 * k], g.position[3 * k + 1], g.position[3 * k + 2]), float(size), edges);
        const glm::vec2 q = ed.q;
        const double best = ed.texels;
        if (std::getenv("SILMAP_DEBUG") && best > 0.7)
            std::printf("wrong px %zu %zu p %.3f %.3f %.3f n %.2f %.2f %.2f V %.0f ref %.0f q %.2f %.2f d %.2f\n",
                        k % std::size_t(g.width), k / std::size_t(g.width), double(g.position[3 * k]),
                        double(g.position[3 * k + 1]), double(g.position[3 * k + 2]), double(g.normal[3 * k]),
                        double(g.normal[3 * k + 1]), double(g.normal[3 * k + 2]), double(v[k]),
                        double(ref.visibility[k]), double(q.x), double(q.y), best);
        d.push_back(best);
    }
    Boundary b;
    b.wrong = d.size();
    if (d.empty()) return b;
    std::sort(d.begin(), d.end());
    b.p50 = d[d.size() / 2];
    b.p95 = d[std::min(d.size() - 1, std::size_t(0.95 * double(d.size())))];
    b.max = d.back();
    return b;
}


// Straight shadow boundaries only: two boxes floating over a floor under the stack scene's spot
// light; only the floor is a receiver (no grazing box faces, where the four depth tests disagree
// because of a depth crease, not a shadow: there neither map helps and the plain map's finer
// grid wins; the report's stack rows show that case).
sk::Scene floating_boxes() {
    sk::Scene s;
    REQUIRE(sk::make_builtin_scene("stack", s));
    s.name = "floating";
    s.meshes.clear();
    s.meshes.push_back(sk::make_plane("floor", {0.f, 0.f, 0.f}, 4.f, 4.f));
    s.meshes.back().caster = false;
    s.meshes.push_back(sk::make_box("a", {-0.3f, 1.0f, 0.1f}, {0.6f, 0.15f, 0.5f}));
    s.meshes.back().receiver = false;
    s.meshes.push_back(sk::make_box("b", {0.5f, 1.8f, -0.4f}, {0.25f, 0.25f, 0.25f}));
    s.meshes.back().receiver = false;
    return s;
}

void compare(const sk::Scene& scene, bool check) {
    sk::SceneGpu gpu;
    sk::GBuffer g;
    std::string why;
    REQUIRE_MESSAGE(sk::prepare_scene_gpu(scene, 320, 240, gpu, g, why), why);
    sk::ReferenceOptions opt;
    opt.progress = false;
    sk::Reference ref;
    REQUIRE_MESSAGE(sk::compute_reference(scene, g, opt, ref, why), why);
    auto techniques = sk::make_techniques();
    sk::Technique* sil = find(techniques, "silhouette_map");
    sk::Technique* plain = find(techniques, "silmap_plain");
    REQUIRE(sil);
    REQUIRE(plain);
    sk::RunContext ctx{scene, gpu, 2, 1, &g};
    for (int size : {128, 256}) {
        const std::string n = "size=" + std::to_string(size);
        const sk::RunResult rs = sil->run(ctx, sk::ParamSet::parse_named(n)),
                            rp = plain->run(ctx, sk::ParamSet::parse_named("map=plain " + n));
        REQUIRE_MESSAGE(rs.ok, rs.error);
        REQUIRE_MESSAGE(rp.ok, rp.error);
        CHECK(rs.gpu_bytes == doctest::Approx(double(rp.gpu_bytes)).epsilon(0.01));  // equal memory
        for (float x : rs.visibility) REQUIRE((x == 0.f || x == 1.f));                // hard result
        const sk::Metrics ms = sk::compute_metrics(g, ref, rs.visibility, true);
        const sk::Metrics mp = sk::compute_metrics(g, ref, rp.visibility, true);
        const Boundary bs = boundary_error(scene, g, ref, rs.visibility, size);
        const int plain_size = int(std::lround(std::sqrt(2.0) * size));
        const Boundary bp = boundary_error(scene, g, ref, rp.visibility, plain_size);
        double fail = 0.0;
        for (const auto& q : rs.quality)
            if (q.first == "failure_texels") fail = q.second;
        MESSAGE(scene.name << " size " << size << ": silhouette map misclassified " << ms.misclassified << " ("
                           << bs.wrong << " pixels; boundary error in its texels p50 " << bs.p50 << ", p95 " << bs.p95
                           << ", max " << bs.max << "; failure texels " << fail << ") vs plain " << plain_size
                           << "^2 misclassified " << mp.misclassified << " (" << bp.wrong << " pixels; p50 " << bp.p50
                           << ", p95 " << bp.p95 << ", max " << bp.max << " of its texels); rmse " << ms.rmse << " vs "
                           << mp.rmse);
        if (!check) continue;
        // the metric's misclassified rate skips pixels next to a reference edge; count every wrong pixel too
        CHECK(ms.misclassified <= mp.misclassified);
        CHECK(bs.wrong * 5 < bp.wrong);
        CHECK(ms.rmse < 0.5 * mp.rmse);
        // the paper's claim: edges located to a fraction of a texel (piecewise-linear reconstruction)
        CHECK(bs.p50 < 0.5);
    }
}

}  // namespace

TEST_CASE("silhouette map beats the plain shadow map of equal memory on straight shadow boundaries") {
    (void)gl_test_context();
    compare(floating_boxes(), true);
}

TEST_CASE("stack scene (grazing box faces): measured, not asserted") {
    (void)gl_test_context();
    sk::Scene scene;
    REQUIRE(sk::make_builtin_scene("stack", scene));
    compare(scene, false);
}

TEST_CASE("fence at low resolution: multi-edge texels are detected, the map still works") {
    (void)gl_test_context();
    sk::Scene scene;
    REQUIRE(sk::make_builtin_scene("fence", scene));
    sk::SceneGpu gpu;
    sk::GBuffer g;
    std::string why;
    REQUIRE_MESSAGE(sk::prepare_scene_gpu(scene, 200, 150, gpu, g, why), why);
    sk::ReferenceOptions opt;
    opt.progress = false;
    sk::Reference ref;
    REQUIRE_MESSAGE(sk::compute_reference(scene, g, opt, ref, why), why);
    auto techniques = sk::make_techniques();
    sk::Technique* sil = find(techniques, "silhouette_map");
    REQUIRE(sil);
    sk::RunContext ctx{scene, gpu, 2, 1, &g};
    const sk::RunResult r = sil->run(ctx, sk::ParamSet::parse_named("size=128"));
    REQUIRE_MESSAGE(r.ok, r.error);
    double fail = -1.0, frac = -1.0;
    for (const auto& q : r.quality) {
        if (q.first == "failure_texels") fail = q.second;
        if (q.first == "failure_fraction") frac = q.second;
    }
    const sk::Metrics m = sk::compute_metrics(g, ref, r.visibility, true);
    MESSAGE("fence, 128^2: failure texels " << fail << " (" << frac << " of silhouette texels), misclassified "
                                            << m.misclassified);
    CHECK(fail > 0.0);
    CHECK(m.misclassified < 0.05);
}
