// Sample: smoothies (smoothies.hpp / .cpp): a linear-depth shadow map, a smoothie per silhouette edge into
// a GL_MIN buffer of (depth, alpha), and one lookup at each G-buffer point. The default width t comes from
// the light's size; pick one with --param t_from_light=off --param t=0.1.
//   sample_smoothies [--scene NAME] [--param size=2048] [--view "smoothie alpha"] [--headless shot.png] [--help]
#include "smoothies.hpp"

int main(int argc, char** argv) {
    SmoothieSettings s;
    app::App a("smoothies");
    bind_settings(a.params(), s);  // t_from_light, t, size, remap: --param, the panel
    Smoothies sm;                  // after the App: its GL objects go before the App's context
    a.debug_view("smoothie alpha", [&] { return sm.debug_alpha(); });
    a.debug_view("smoothie depth", [&] { return sm.debug_depth(); });
    if (!a.start(argc, argv)) return a.exit_code();  // options, window or EGL, scene, G-buffer
    std::string why;
    while (a.next_frame()) {  // input, camera, light; the G-buffer when the camera moved
        if (a.scene_changed() && !sm.init(a.view(), why)) return a.fail(why);
        a.cpu("silhouettes + smoothies", [&] { sm.update(a.view(), s); });
        if (!sm.error().empty()) return a.fail(sm.error());
        a.gpu("map + smoothies + lookup", [&] { sm.render(a.view(), s); });
        a.present(sm.visibility());  // the composite (or a debug view) and the panel; headless: the PNG
    }
    return a.exit_code();
}
