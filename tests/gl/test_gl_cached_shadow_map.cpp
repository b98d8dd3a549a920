// The cached shadow map of issue 18 - the CachedShadowMap class of samples/cached_shadow_map/, through
// the report's registry (its ReportTechnique wrapper: the temporal sequence that compares the kept map
// with a full re-render) and directly (casters that move):
//  (a) the sun's stable fit with the depth range fixed in the world, on the report's camera paths over
//      `outdoor`: no frame renders the whole map (keep or scroll), the kept map equals a full
//      re-render bit for bit with the translation-invariant pass, and V too; the plain pass keeps the
//      same surfaces (no texel more than 16 float steps off);
//  (b) the default depth range (world_depth=off): every camera move renders the whole map (what
//      light_frustum's stable_world_depth fixes);
//  (c) the fit camera reaches the class: the tight fit's V changes along a camera path, the stable
//      fit's does not under a pan (the View's camera of issue 18, not the G-buffer's);
//  (d) casters that move (a box driving by, re-uploaded each frame) while the camera pans: the plan
//      updates their old and new footprints, and the kept map equals a full re-render bit for bit,
//      also when render() runs twice after one update() (a repeated scroll would shift the map twice).
// What each check catches: a scroll with the wrong sign or copy region, a missing border strip or
// caster footprint, a depth range that follows the camera, a class that fits to the G-buffer's camera.
#include <doctest/doctest.h>

#include <glm/glm.hpp>

#include <cstring>
#include <string>
#include <vector>

#include "cached_shadow_map.hpp"
#include "gl_test.hpp"
#include "reference.hpp"
#include "scene.hpp"
#include "techniques.hpp"
#include "temporal.hpp"

namespace {

constexpr int kW = 160, kH = 120, kFrames = 10;

sk::Technique& technique(const std::string& name) {
    static auto all = sk::make_techniques();
    for (auto& t : all)
        if (t->name() == name) return *t;
    FAIL(name << " is not registered");
    return *all.front();
}

double work(const sk::SequenceResult& r, const std::string& k) {
    for (const auto& [name, v] : r.work)
        if (name == k) return v;
    FAIL("no work counter " << k);
    return 0.0;
}

bool same_v(const std::vector<std::vector<float>>& v) {
    for (const auto& f : v)
        if (std::memcmp(f.data(), v[0].data(), v[0].size() * sizeof(float)) != 0) return false;
    return true;
}

}  // namespace

TEST_CASE("cached shadow map on the report's camera paths: kept or scrolled, equal to a full re-render") {
    (void)gl_test_context();
    sk::Scene scene;
    REQUIRE(sk::make_builtin_scene("outdoor", scene));
    sk::SceneGpu gpu;
    sk::GBuffer g;
    std::string why;
    REQUIRE_MESSAGE(sk::prepare_scene_gpu(scene, kW, kH, gpu, g, why), why);
    sk::RunContext ctx{scene, gpu, 1, 0, &g};
    sk::Technique& t = technique("cached_shadow_map");
    CHECK(t.honors_fit_camera());
    for (sk::TemporalPath path : {sk::TemporalPath::Pan, sk::TemporalPath::Yaw, sk::TemporalPath::Dolly}) {
        const std::string path_name = sk::temporal_path_name(path);
        CAPTURE(path_name);
        const auto frames = sk::temporal_path(scene, path, kFrames);
        // (a) invariant pass: bit for bit
        const sk::SequenceResult inv =
            t.run_sequence(ctx, sk::ParamSet::parse_named("fit=stable cache=on pass=invariant size=1024"), frames);
        REQUIRE_MESSAGE(inv.ok, inv.error);
        REQUIRE(inv.visibility.size() == std::size_t(kFrames));
        CHECK(work(inv, "frames_rendered") == 0.0);
        CHECK(work(inv, "frames_kept") + work(inv, "frames_scrolled") == double(kFrames - 1));
        CHECK(work(inv, "rerendered_fraction") < 0.01);
        CHECK(work(inv, "texels_differing") == 0.0);
        CHECK(work(inv, "v_pixels_differing") == 0.0);
        // the plain pass: the same surfaces (a few float steps of depth at most), the same V here
        const sk::SequenceResult plain =
            t.run_sequence(ctx, sk::ParamSet::parse_named("fit=stable cache=on pass=plain size=1024"), frames);
        REQUIRE_MESSAGE(plain.ok, plain.error);
        CHECK(work(plain, "texels_differing_16ulp") == 0.0);
        MESSAGE("plain pass, " << path_name << ": " << work(plain, "texels_differing")
                               << " texel-frames differ, by up to " << work(plain, "max_ulps") << " float steps; V differs at "
                               << work(plain, "v_pixels_differing") << " pixel-frames");
        // (b) the depth range from the receivers: every move renders the whole map
        const sk::SequenceResult moving =
            t.run_sequence(ctx, sk::ParamSet::parse_named("fit=stable cache=on pass=plain world_depth=off size=1024"), frames);
        REQUIRE_MESSAGE(moving.ok, moving.error);
        if (path != sk::TemporalPath::Yaw)  // a turn may leave the receivers' depth range as it was
            CHECK(work(moving, "frames_rendered") >= double(kFrames - 2));
        // (c) the fit camera reaches the class: the tight fit's V changes, the stable fit's keeps its texels
        const sk::SequenceResult tight =
            t.run_sequence(ctx, sk::ParamSet::parse_named("fit=tight cache=off pass=plain size=1024"), frames);
        REQUIRE_MESSAGE(tight.ok, tight.error);
        CHECK_FALSE(same_v(tight.visibility));
        if (path == sk::TemporalPath::Pan) CHECK(same_v(inv.visibility));
    }
}

TEST_CASE("cached shadow map: casters that move dirty their old and new footprints, the kept map stays exact") {
    (void)gl_test_context();
    sk::Scene scene;
    scene.name = "cart";
    scene.meshes.push_back(sk::make_plane("ground", {0.f, 0.f, 0.f}, 20.f, 20.f, 4));
    scene.meshes.back().caster = false;
    for (int i = 0; i < 6; ++i)
        scene.meshes.push_back(sk::make_box("box" + std::to_string(i), {-6.f + 2.5f * float(i), 0.6f, -2.f + float(i % 3)},
                                            {0.4f, 0.6f, 0.4f}));
    scene.meshes.push_back(sk::make_box("cart", {-3.f, 0.3f, 2.f}, {0.5f, 0.3f, 0.3f}));
    scene.light.type = sk::LightType::Directional;
    scene.light.direction = glm::normalize(glm::vec3(0.5f, -1.f, 0.3f));
    scene.camera.eye = {0.f, 4.f, 10.f};
    scene.camera.target = {0.f, 0.f, 0.f};
    sk::SceneGpu gpu;
    sk::GBuffer g;
    std::string why;
    REQUIRE_MESSAGE(sk::prepare_scene_gpu(scene, kW, kH, gpu, g, why), why);
    CachedShadowMapSettings s;  // the sample's defaults: stable, cached, invariant pass, world depth
    s.size = 1024;
    CachedShadowMapSettings full_s = s;
    full_s.cache = false;
    CachedShadowMap cached, full;
    const auto frames = sk::temporal_path(scene, sk::TemporalPath::Pan, 12);
    REQUIRE(cached.init(app::make_view(scene, gpu, frames[0].camera), why));
    REQUIRE(full.init(app::make_view(scene, gpu, frames[0].camera), why));
    int updates = 0, scrolls = 0, differing = 0;
    for (std::size_t t = 0; t < frames.size(); ++t) {
        if (t % 3 != 2) {  // the cart drives on (two frames of three); re-uploaded like a renderer would
            for (glm::vec3& p : scene.meshes.back().positions) p.x += 0.37f;
            app::upload_scene(scene, gpu);
        }
        const app::View v = app::make_view(scene, gpu, frames[t].camera);
        cached.update(v, s);
        full.update(v, full_s);
        REQUIRE_MESSAGE(cached.error().empty(), cached.error());
        cached.render(v, s);
        cached.render(v, s);  // again without update(): the same map (a scroll is not repeated)
        full.render(v, full_s);
        const shadowkit::ShadowCachePlan& p = cached.plan();
        if (t > 0) {
            CHECK(p.action != shadowkit::ShadowCacheAction::Render);
            if (t % 3 != 2) CHECK(p.count > 0);  // the cart moved: its old and new footprints at least
            updates += p.action == shadowkit::ShadowCacheAction::Update ? 1 : 0;
            scrolls += p.action == shadowkit::ShadowCacheAction::Scroll ? 1 : 0;
        }
        std::vector<float> a(std::size_t(s.size) * std::size_t(s.size)), b(a.size());
        glGetTextureImage(cached.map(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, GLsizei(a.size() * 4), a.data());
        glGetTextureImage(full.map(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, GLsizei(b.size() * 4), b.data());
        for (std::size_t k = 0; k < a.size(); ++k) differing += std::memcmp(&a[k], &b[k], 4) != 0 ? 1 : 0;
    }
    MESSAGE("cart: " << updates << " updates, " << scrolls << " scrolls in " << frames.size() - 1 << " frames");
    CHECK(differing == 0);
    CHECK(updates > 0);
    CHECK(skgl::gl_error_string().empty());
}
