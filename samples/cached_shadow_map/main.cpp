// Sample: a cached shadow map (cached_shadow_map.hpp / .cpp): the sun's stable frustum follows the
// camera and each frame shadow_cache.hpp says what to keep, scroll or re-render; the panel shows the plan.
//   sample_cached_shadow_map [--scene outdoor] [--param pass=plain] [--view "shadow map"] [--headless shot.png] [--help]
#include "cached_shadow_map.hpp"

#include <cstdio>

#if SHADOWKIT_APP_IMGUI
#include <imgui.h>
#endif

int main(int argc, char** argv) {
    CachedShadowMapSettings s;
    app::App a("cached shadow map");
    bind_settings(a.params(), s);  // fit, cache, pass, world_depth, culling, size: --param, the panel
    a.default_scene("outdoor");    // a sun over 1 km of ground: its stable map scrolls with the camera
    CachedShadowMap sm;            // after the App: its GL objects go before the App's context
    a.debug_view("shadow map", [&] { return sm.debug_map(); });
    if (!a.start(argc, argv)) return a.exit_code();  // options, window or EGL, scene, G-buffer
    std::string why;
    while (a.next_frame()) {  // input, camera, light; the G-buffer when the camera moved
        if (a.scene_changed() && !sm.init(a.view(), why)) return a.fail(why);
        a.cpu("fit + plan", [&] { sm.update(a.view(), s); });
        if (!sm.error().empty()) return a.fail(sm.error());
        a.gpu("map (cached) + lookup", [&] { sm.render(a.view(), s); });
#if SHADOWKIT_APP_IMGUI
        a.panel([&] {  // what this frame left out
            const shadowkit::ShadowCachePlan& p = sm.plan();
            ImGui::Text("%s %s, offset (%d, %d)", shadowkit::shadow_cache_action_name(p.action),
                        shadowkit::shadow_cache_reason_name(p.reason), p.offset_x, p.offset_y);
            ImGui::Text("re-rendered: %.3f%% of the map", 100.0 * double(p.texels) / (double(sm.size()) * sm.size()));
        });
#endif
        a.present(sm.visibility());  // the composite (or a debug view) and the panel; headless: the PNG
    }
    return a.exit_code();
}
