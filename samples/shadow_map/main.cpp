// Sample: the plain shadow map (shadow_map.hpp / .cpp), the kit's baseline: a depth pass from the
// light, then one hardware compare (2x2 PCF) at each G-buffer point; a cube map for point lights.
//   sample_shadow_map [--scene NAME] [--param size=1024] [--view "shadow map"] [--headless shot.png] [--help]
#include "shadow_map.hpp"

int main(int argc, char** argv) {
    ShadowMapSettings s;
    app::App a("shadow map");
    bind_settings(a.params(), s);  // size, hardware_pcf, bias, offset_factor, offset_units: --param, the panel
    ShadowMap sm;         // after the App: its GL objects go before the App's context
    a.debug_view("shadow map", [&] { return sm.debug_depth(); });
    if (!a.start(argc, argv)) return a.exit_code();  // options, window or EGL, scene, G-buffer
    std::string why;
    while (a.next_frame()) {  // input, camera, light; the G-buffer when the camera moved
        if (a.scene_changed() && !sm.init(a.view(), why)) return a.fail(why);
        a.cpu("light frustum", [&] { sm.update(a.view(), s); });
        a.gpu("depth + lookup", [&] { sm.render(a.view(), s); });
        a.present(sm.visibility());  // the composite (or a debug view) and the panel; headless: the PNG
    }
    return a.exit_code();
}
