// Cached cascades (issue 25, "Must hold"): samples/cascaded_shadow_maps with cache=on over the report's
// camera pan on `outdoor`, with a caster that moves (a box driving by, re-uploaded each frame like a
// renderer would). Every frame, each cascade's layer of the cached array must equal a full re-render
// bit for bit (a second instance of the class whose cache is invalidated every frame: every cascade
// rendered whole with the same translation-invariant pass), and V too. The texels re-rendered per
// frame (the plans' rectangles over all cascades) are counted and printed; the pan's mean must be at
// most 3% of the array's texels. What each check catches: a scroll with the wrong sign, offset or
// copy region, a missing border strip, a moving caster's old or new footprint left out, a depth
// range that follows the camera (every frame a full render: the fraction check), a reference that
// is not one (its plans must all be Render).
#include <doctest/doctest.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "cascaded_shadow_maps.hpp"
#include "gl_test.hpp"
#include "scene.hpp"
#include "temporal.hpp"

namespace {

constexpr int kW = 160, kH = 120, kFrames = 16;

std::vector<float> read_array(GLuint tex, int size, int layers) {
    std::vector<float> out(std::size_t(size) * std::size_t(size) * std::size_t(layers));
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glGetTextureImage(tex, 0, GL_DEPTH_COMPONENT, GL_FLOAT, GLsizei(out.size() * sizeof(float)), out.data());
    return out;
}

std::vector<float> read_v(GLuint tex) {
    std::vector<float> out(std::size_t(kW) * std::size_t(kH));
    glGetTextureImage(tex, 0, GL_RED, GL_FLOAT, GLsizei(out.size() * sizeof(float)), out.data());
    return out;
}

}  // namespace

TEST_CASE("cached cascades on a camera pan with a moving caster: every layer equals a full re-render, <= 3% re-rendered") {
    (void)gl_test_context();
    sk::Scene scene;
    REQUIRE(sk::make_builtin_scene("outdoor", scene));
    // the moving caster: a box in front of the camera, inside the scene box (which fixes the depth range)
    scene.meshes.push_back(sk::make_box("cart", {-4.f, 0.6f, -3.f}, {0.6f, 0.6f, 0.4f}));
    sk::SceneGpu gpu;
    sk::GBuffer g;
    std::string why;
    REQUIRE_MESSAGE(sk::prepare_scene_gpu(scene, kW, kH, gpu, g, why), why);
    const auto frames = sk::temporal_path(scene, sk::TemporalPath::Pan, kFrames);

    for (const std::string bias : {"auto", "polygon_offset"}) {
        CAPTURE(bias);
        CascadedShadowMapSettings s;
        s.size = 1024;
        s.count = 4;
        s.cache = true;
        s.bias = bias == "auto" ? CascadedShadowMapSettings::Bias::Auto : CascadedShadowMapSettings::Bias::PolygonOffset;
        CascadedShadowMaps cached, full;
        REQUIRE_MESSAGE(cached.init(app::make_view(scene, gpu, frames[0].camera), why), why);
        REQUIRE_MESSAGE(full.init(app::make_view(scene, gpu, frames[0].camera), why), why);
        const double array_texels = double(s.count) * double(s.size) * double(s.size);
        double fraction_sum = 0.0, fraction_max = 0.0;
        int differing = 0, v_differing = 0, scrolls = 0, updates = 0, renders = 0, full_not_render = 0, cart_frames_missed = 0;
        sk::Scene moved = scene;
        app::upload_scene(moved, gpu);  // the cart back at its start (the GPU holds the last pass's)
        for (int t = 0; t < kFrames; ++t) {
            const bool cart_moves = t > 0 && t % 3 != 0;  // the cart drives on two frames of three
            if (cart_moves) {
                for (glm::vec3& p : moved.meshes.back().positions) p.x += 0.37f;
                app::upload_scene(moved, gpu);
            }
            const app::View v = app::make_view(moved, gpu, frames[std::size_t(t)].camera);
            cached.update(v, s);
            full.invalidate_cache();  // the reference: every cascade rendered whole
            full.update(v, s);
            REQUIRE_MESSAGE(cached.error().empty(), cached.error());
            REQUIRE(cached.cache_active());
            cached.render(v, s);
            cached.render(v, s);  // again without update(): the same layers (a scroll is not repeated)
            full.render(v, s);
            int touched = 0;
            for (int i = 0; i < s.count; ++i) {
                const shadowkit::ShadowCachePlan& p = cached.plan(i);
                full_not_render += full.plan(i).action != shadowkit::ShadowCacheAction::Render ? 1 : 0;
                if (t == 0) continue;
                scrolls += p.action == shadowkit::ShadowCacheAction::Scroll ? 1 : 0;
                updates += p.action == shadowkit::ShadowCacheAction::Update ? 1 : 0;
                renders += p.action == shadowkit::ShadowCacheAction::Render ? 1 : 0;
                touched += p.count > 0 ? 1 : 0;
            }
            if (cart_moves && touched == 0) ++cart_frames_missed;
            if (t > 0) {
                const double f = double(cached.texels_rerendered()) / array_texels;
                fraction_sum += f;
                fraction_max = std::max(fraction_max, f);
            }
            const std::vector<float> a = read_array(cached.maps(), s.size, s.count), b = read_array(full.maps(), s.size, s.count);
            for (std::size_t k = 0; k < a.size(); ++k) differing += std::memcmp(&a[k], &b[k], 4) != 0 ? 1 : 0;
            const std::vector<float> va = read_v(cached.visibility()), vb = read_v(full.visibility());
            for (std::size_t k = 0; k < va.size(); ++k) v_differing += std::memcmp(&va[k], &vb[k], 4) != 0 ? 1 : 0;
        }
        const double mean = fraction_sum / double(kFrames - 1);
        MESSAGE("cached cascades, outdoor pan + moving cart, 4 x 1024^2, bias=" << bias << ": texels re-rendered per frame "
                << 100.0 * mean << "% mean, " << 100.0 * fraction_max << "% max; cascade-frames: " << scrolls << " scrolls, "
                << updates << " updates, " << renders << " full renders of " << (kFrames - 1) * s.count
                << "; texels differing from a full re-render: " << differing << ", V pixels: " << v_differing);
        CHECK(differing == 0);
        CHECK(v_differing == 0);
        CHECK(full_not_render == 0);  // the reference re-rendered everything
        CHECK(renders == 0);          // the depth range is fixed in the world: never a full render
        CHECK(scrolls > 0);
        CHECK(cart_frames_missed == 0);  // the moving cart's footprints were re-rendered
        CHECK(mean <= 0.03);
    }
    CHECK(skgl::gl_error_string().empty());
}
