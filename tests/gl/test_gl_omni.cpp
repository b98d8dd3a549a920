// Omnidirectional shadows through the report's wrappers of the samples' classes (samples/omni_shadows/,
// samples/dual_paraboloid/: omni_shadow.hpp + omni_shadow.glsl)
// against the Embree point-light reference on the `room` scene:
// (a) cube map: >= 99% of the receiver pixels away from 1-pixel shadow edges classified like the
//     reference, for the hardware compare, the manual compare and 3x3 PCF (seams crossed);
// (b) per-face caster culling leaves the image pixel-identical and saves the draws counted by hand;
// (c) dual paraboloid at equal texel counts (2 s^2 = 6 c^2): the error falls with tessellation and
//     stays within the bound argued below; PCF across the rim (seam) stays within it too.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "gl_test.hpp"
#include "metrics.hpp"
#include "reference.hpp"
#include "scene.hpp"
#include "techniques.hpp"

namespace {

struct RoomFixture {
    sk::Scene scene;
    sk::SceneGpu gpu;
    sk::GBuffer g;
    sk::Reference ref;
    std::vector<std::unique_ptr<sk::Technique>> techniques;
    RoomFixture() {
        REQUIRE(sk::make_builtin_scene("room", scene));
        REQUIRE(scene.light.type == sk::LightType::Point);
        std::string why;
        REQUIRE_MESSAGE(sk::prepare_scene_gpu(scene, 320, 240, gpu, g, why), why);
        sk::ReferenceOptions opt;
        opt.progress = false;
        REQUIRE_MESSAGE(sk::compute_reference(scene, g, opt, ref, why), why);
        techniques = sk::make_techniques();
    }
    sk::Technique& technique(const std::string& name) {
        auto it = std::find_if(techniques.begin(), techniques.end(), [&](const auto& t) { return t->name() == name; });
        REQUIRE(it != techniques.end());
        return **it;
    }
    sk::RunResult run(const std::string& name, const sk::ParamSet& ps) {
        sk::RunContext ctx{scene, gpu, 1, 0, &g};
        sk::RunResult r = technique(name).run(ctx, ps);
        REQUIRE_MESSAGE(r.ok, r.error);
        REQUIRE(r.visibility.size() == g.kind.size());
        return r;
    }
};

double work(const sk::RunResult& r, const std::string& key) {
    for (const auto& [k, v] : r.work)
        if (k == key) return v;
    return -1.0;
}

}  // namespace

TEST_CASE("cube shadow map agrees with the Embree reference on room; culling is pixel-identical") {
    RoomFixture f;
    std::size_t shadowed = 0, compared = 0;
    for (std::size_t k = 0; k < f.g.kind.size(); ++k)
        if (f.g.kind[k] == 1 && f.ref.faces_light[k]) {
            ++compared;
            if (f.ref.visibility[k] < 0.5f) ++shadowed;
        }
    MESSAGE("room: " << compared << " receiver pixels facing the light, " << shadowed << " shadowed in the reference");
    REQUIRE(shadowed > compared / 20);  // the view has shadows to get right
    for (const std::string size : {"256", "512", "1024"}) {
        const sk::RunResult off = f.run("cube_sm", sk::ParamSet::parse_named("size=" + size + " culling=off"));
        const sk::RunResult on = f.run("cube_sm", sk::ParamSet::parse_named("size=" + size + " culling=on"));
        const sk::Metrics m = sk::compute_metrics(f.g, f.ref, on.visibility, true);
        MESSAGE("cube " << size << ": misclassified " << m.misclassified << " of " << m.pixels << " pixels, RMSE " << m.rmse
                        << ", draws " << work(on, "draws") << " (saved " << work(on, "draws_saved") << ")");
        CHECK(m.has_misclassified);
        CHECK(m.misclassified <= 0.01);
        // culling changes nothing in the image
        std::size_t differ = 0;
        for (std::size_t k = 0; k < on.visibility.size(); ++k) differ += on.visibility[k] != off.visibility[k];
        CHECK(differ == 0);
        // room mesh 6 faces, table 1 (-Y), ball 2 (-X, -Y), pillar 3 (-X, -Y, +Z): 12 of 24
        CHECK(work(on, "draws") == 12.0);
        CHECK(work(on, "draws_saved") == 12.0);
        CHECK(work(off, "draws") == 24.0);
    }
    for (const std::string lookup : {"manual", "pcf"}) {
        const sk::RunResult r = f.run("cube_sm", sk::ParamSet::parse_named("size=512 culling=on lookup=" + lookup));
        const sk::Metrics m = sk::compute_metrics(f.g, f.ref, r.visibility, true);
        const std::string label = lookup == "manual" ? "manual compare" : "3x3 PCF";
        MESSAGE("cube 512 lookup " << label << ": misclassified " << m.misclassified
                                   << ", RMSE " << m.rmse);
        CHECK(m.misclassified <= 0.01);
    }
}

// The bound for the paraboloid map. At equal texel counts (s = sqrt(3) c) a paraboloid texel
// subtends at most 4 / s = 2.31 / c radians (map centre), against 2 / c for a cube texel (face
// centre), so its sampling error is within 1.16x of the cube's; tessellated to e <= 4 texels of
// curve error (omni_paraboloid_edge_error), the drawn silhouettes move by at most e texels more,
// which at 887 texels and the room's caster distances (>= 0.8 m) is < 1.5 cm, under a camera pixel
// over most of the view: the misclassified rate away from 1-pixel edges must stay within the
// cube's 1% budget. Untessellated, the room's 6 m wall triangles cross the rim and their chords
// cut through the maps (bound in the hundreds of texels): the error must be large (> 5%).
TEST_CASE("dual-paraboloid error falls with tessellation and stays within its bound on room") {
    RoomFixture f;
    const sk::RunResult cube = f.run("cube_sm", sk::ParamSet::parse_named("size=512 culling=on"));
    const sk::Metrics mc = sk::compute_metrics(f.g, f.ref, cube.visibility, true);
    double prev = 1.0;
    for (double tess : {0.0, 4.0, 1.0}) {
        const sk::RunResult r = f.run("dual_paraboloid", sk::ParamSet::parse_named("size=887 tess=" + std::to_string(int(tess))));
        const sk::Metrics m = sk::compute_metrics(f.g, f.ref, r.visibility, true);
        double bound = -1;
        for (const auto& [k, v] : r.quality)
            if (k == "edge_error_bound_texels") bound = v;
        MESSAGE("dual paraboloid 887 (= cube 512 texels), tess " << tess << ": misclassified " << m.misclassified
                                                                  << ", RMSE " << m.rmse << ", triangles "
                                                                  << work(r, "triangles_drawn") << ", edge bound "
                                                                  << bound << " texels; cube 512: " << mc.misclassified);
        CHECK(m.misclassified <= prev + 1e-3);
        if (tess == 0.0) {
            CHECK(m.misclassified > 0.05);
            CHECK(bound > 100.0);
        } else {
            CHECK(m.misclassified <= 0.01);
            CHECK(bound <= tess * 1.0001);
        }
        prev = m.misclassified;
    }
    const sk::RunResult pcf = f.run("dual_paraboloid", sk::ParamSet::parse_named("size=887 tess=1 pcf=1"));
    const sk::Metrics mp = sk::compute_metrics(f.g, f.ref, pcf.visibility, true);
    MESSAGE("dual paraboloid 887 tess 1, 3x3 PCF across the rim: misclassified " << mp.misclassified << ", RMSE " << mp.rmse);
    CHECK(mp.misclassified <= 0.01);
}
