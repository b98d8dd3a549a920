// Sample: cascaded shadow maps for the sun (cascaded_shadow_maps.hpp / .cpp): up to four stable
// orthographic maps along the camera's depth (cascades.hpp), selected by view depth and blended over a
// band. Starts on `outdoor` (the only built-in scene with a sun: other lights are refused, no shadows).
//   sample_cascaded_shadow_maps [--param size=512] [--param count=3] [--param normal_offset=0] [--param cache=on]
//                               [--view "cascade 1"] [--headless shot.png] [--help]
#include <cstdio>

#include "cascaded_shadow_maps.hpp"

int main(int argc, char** argv) {
    CascadedShadowMapSettings s;
    app::App a("cascaded shadow maps");
    bind_settings(a.params(), s);  // size, count, lambda, band, normal_offset: --param, the panel
    a.default_scene("outdoor");
    CascadedShadowMaps c;          // after the App: its GL objects go before the App's context
    for (int i = 0; i < 4; ++i)
        a.debug_view("cascade " + std::to_string(i + 1), [&c, i] { return c.debug_layer(i); });
    if (!a.start(argc, argv)) return a.exit_code();  // options, window or EGL, scene, G-buffer
    std::string why, said;
    while (a.next_frame()) {  // input, camera, light; the G-buffer when the camera moved
        if (a.scene_changed() && !c.init(a.view(), why)) return a.fail(why);
        a.cpu("cascade fit", [&] { c.update(a.view(), s); });
        if (c.error() != said && !(said = c.error()).empty())  // a light that is not the sun
            std::fprintf(stderr, "cascaded shadow maps: %s, no shadows\n", said.c_str());
        a.gpu("cascades + lookup", [&] { c.render(a.view(), s); });
        a.present(c.visibility());  // the composite (or a debug view) and the panel; headless: the PNG
    }
    return a.exit_code();
}
