// The "shadow_map" technique - the ShadowMap class of samples/shadow_map/, reached through the report's
// registry (its ReportTechnique wrapper, settings by name) - against the Embree reference: one 2D map
// for a spot light (stack), a cube map for a point light (room); its settings take effect
// (hardware_pcf=off gives only 0 and 1, bias=polygon_offset without an offset gives self-shadowing
// acne, the automatic bias (the default) none); and the View's
// contract of issue 18: a fit camera that differs from the G-buffer's leaves V at the G-buffer's points
// (the plain map fits the scene, the shadow volumes are drawn in the G-buffer's camera), so V is the
// same bit for bit; an unknown setting is an error naming the valid ones.
#include <doctest/doctest.h>

#include <glm/glm.hpp>

#include <string>
#include <vector>

#include "gl_test.hpp"
#include "metrics.hpp"
#include "reference.hpp"
#include "scene.hpp"
#include "techniques.hpp"

namespace {

constexpr int kW = 256, kH = 192;

sk::Technique& technique(const std::string& name) {
    static auto all = sk::make_techniques();
    for (auto& t : all)
        if (t->name() == name) return *t;
    FAIL(name << " is not registered");
    return *all.front();
}

struct Prepared {
    sk::SceneGpu gpu;
    sk::GBuffer g;
    sk::Reference ref;
};

void prepare(const std::string& scene_name, sk::Scene& scene, Prepared& p) {
    REQUIRE(sk::make_builtin_scene(scene_name, scene));
    std::string why;
    REQUIRE_MESSAGE(sk::prepare_scene_gpu(scene, kW, kH, p.gpu, p.g, why), why);
    sk::ReferenceOptions opt;
    opt.progress = false;
    REQUIRE_MESSAGE(sk::compute_reference(scene, p.g, opt, p.ref, why), why);
}

sk::RunResult run(const std::string& name, const sk::Scene& scene, Prepared& p, const std::string& settings,
                  const sk::Camera* fit = nullptr) {
    sk::RunContext ctx{scene, p.gpu, 1, 0, &p.g};
    ctx.fit_camera = fit;
    sk::RunResult r = technique(name).run(ctx, sk::ParamSet::parse_named(settings));
    REQUIRE_MESSAGE(r.ok, r.error);
    REQUIRE(r.visibility.size() == p.g.kind.size());
    return r;
}

double work(const sk::RunResult& r, const std::string& k) {
    for (const auto& [name, v] : r.work)
        if (name == k) return v;
    return -1.0;
}

}  // namespace

TEST_CASE("plain shadow map: a 2D map (spot light) and a cube map (point light) agree with the reference") {
    for (const char* name : {"stack", "room"}) {
        sk::Scene scene;
        Prepared p;
        prepare(name, scene, p);
        const sk::RunResult r = run("shadow_map", scene, p, "size=2048");
        const sk::Metrics m = sk::compute_metrics(p.g, p.ref, r.visibility, true);
        const bool cube = scene.light.type == sk::LightType::Point;
        MESSAGE(std::string(name) << (cube ? " (cube map)" : " (2D map)") << ": misclassified " << m.misclassified << " of " << m.pixels
                     << ", RMSE " << m.rmse << ", texels " << work(r, "shadow_map_texels"));
        CHECK(m.pixels > std::size_t(kW * kH / 5));
        CHECK(m.misclassified <= 0.005);
        CHECK(work(r, "shadow_map_texels") == (cube ? 6.0 : 1.0) * 2048.0 * 2048.0);
    }
}

TEST_CASE("plain shadow map: hardware_pcf=off compares one texel (0 or 1), on filters 2x2; no offset gives acne") {
    sk::Scene scene;
    Prepared p;
    prepare("stack", scene, p);
    auto fractions = [&](const std::vector<float>& v) {
        std::size_t n = 0;
        for (std::size_t k = 0; k < v.size(); ++k) n += p.g.kind[k] == 1 && v[k] > 0.f && v[k] < 1.f;
        return n;
    };
    const sk::RunResult pcf = run("shadow_map", scene, p, "size=512 hardware_pcf=on");
    const sk::RunResult one = run("shadow_map", scene, p, "size=512 hardware_pcf=off");
    MESSAGE("receiver pixels strictly between 0 and 1: 2x2 filter " << fractions(pcf.visibility) << ", one texel "
                                                                     << fractions(one.visibility));
    CHECK(fractions(one.visibility) == 0);
    CHECK(fractions(pcf.visibility) > 50);
    const sk::Metrics with = sk::compute_metrics(
        p.g, p.ref, run("shadow_map", scene, p, "size=512 hardware_pcf=off bias=polygon_offset").visibility, true);
    const sk::Metrics without = sk::compute_metrics(
        p.g, p.ref, run("shadow_map", scene, p, "size=512 hardware_pcf=off bias=polygon_offset offset_factor=0 offset_units=0").visibility,
        true);
    const sk::Metrics automatic = sk::compute_metrics(p.g, p.ref, one.visibility, true);
    MESSAGE("misclassified with the polygon offset (2, 2): " << with.misclassified << ", without: " << without.misclassified
                                                             << ", automatic bias (the default): " << automatic.misclassified);
    CHECK(without.misclassified > 2.0 * with.misclassified + 0.01);
    CHECK(automatic.misclassified <= with.misclassified);  // no constant, no acne: at least as right as the tuned offset
}

TEST_CASE("a fit camera other than the G-buffer's: V stays at the G-buffer's points (shadow_map, shadow_volume)") {
    sk::Scene scene;
    Prepared p;
    prepare("stack", scene, p);
    sk::Camera moved = scene.camera;
    moved.eye += glm::vec3(0.7f, 0.4f, -0.5f);
    moved.target += glm::vec3(0.2f, 0.f, 0.1f);
    for (const char* name : {"shadow_map", "shadow_volume"}) {
        const sk::RunResult a = run(name, scene, p, "");
        const sk::RunResult b = run(name, scene, p, "", &moved);
        std::size_t differ = 0;
        for (std::size_t k = 0; k < a.visibility.size(); ++k) differ += a.visibility[k] != b.visibility[k];
        MESSAGE(std::string(name) << ": pixels that differ with the moved fit camera: " << differ);
        CHECK(differ == 0);
    }
}

TEST_CASE("ported techniques take their settings by name: unknown names and values list the valid ones") {
    sk::Scene scene;
    REQUIRE(sk::make_builtin_scene("stack", scene));
    sk::SceneGpu gpu;
    sk::GBuffer g;
    std::string why;
    REQUIRE_MESSAGE(sk::prepare_scene_gpu(scene, 64, 48, gpu, g, why), why);
    sk::RunContext ctx{scene, gpu, 1, 0, &g};
    const sk::RunResult a = technique("shadow_volume").run(ctx, sk::ParamSet::parse_named("method=zfial"));
    CHECK_FALSE(a.ok);
    CHECK(a.error.find("valid: zfail, auto, zpass") != std::string::npos);
    const sk::RunResult b = technique("shadow_map").run(ctx, sk::ParamSet::parse_named("sise=512"));
    CHECK_FALSE(b.ok);
    CHECK(b.error.find("valid: size, hardware_pcf, bias, offset_factor, offset_units") != std::string::npos);
    const sk::RunResult c = technique("shadow_map").run(ctx, sk::ParamSet{{{"size", 512.0}}});  // numbers: the old drivers' form
    CHECK_FALSE(c.ok);
}
