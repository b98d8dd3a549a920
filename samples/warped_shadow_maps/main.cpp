// Sample: one shadow map spent where the camera looks (warped_shadow_maps.hpp / .cpp): the light's
// frustum fitted around what the camera sees (light_frustum.hpp, casters culled), or warped by the
// camera's perspective (perspective_shadow_maps.hpp: uniform, PSM, LiSPSM, TSM). Starts on `outdoor`.
//   sample_warped_shadow_maps [--scene duel] [--param method=tsm] [--param size=512]
//                             [--view "texel density"] [--headless shot.png] [--help]
#include <cstdio>

#include "warped_shadow_maps.hpp"

int main(int argc, char** argv) {
    WarpedShadowMapSettings s;
    app::App a("warped shadow maps");
    bind_settings(a.params(), s);  // method, size: --param, the panel
    a.default_scene("outdoor");    // a sun over 1 km of ground, the camera near it: what the warps are for
    WarpedShadowMaps w;            // after the App: its GL objects go before the App's context
    a.debug_view("shadow map", [&] { return w.debug_depth(); });
    a.debug_view("texel density", [&] { return w.debug_texel_density(a.view()); });
    if (!a.start(argc, argv)) return a.exit_code();  // options, window or EGL, scene, G-buffer
    std::string why, said;
    while (a.next_frame()) {  // input, camera, light; the G-buffer when the camera moved
        if (a.scene_changed() && !w.init(a.view(), why)) return a.fail(why);
        a.cpu("fit / warp", [&] { w.update(a.view(), s); });
        if (w.error() != said && !(said = w.error()).empty())  // e.g. a point light inside the scene
            std::fprintf(stderr, "warped shadow maps: %s, no shadows\n", said.c_str());
        a.gpu("depth + lookup", [&] { w.render(a.view(), s); });
        a.present(w.visibility());  // the composite (or a debug view) and the panel; headless: the PNG
    }
    return a.exit_code();
}
