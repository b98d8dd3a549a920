// Sample: a point light's shadows from one cube map (omni_shadows.hpp / .cpp, omni_shadow.hpp): the
// linear distance to the light in six faces, the casters culled per face, a receiver-side bias.
// Starts on `room` (a point light inside a closed room). The dual-paraboloid map: samples/dual_paraboloid/.
//   sample_omni_shadows [--param size=1024] [--param culling=off] [--param lookup=pcf]
//                       [--view "cube faces"] [--headless shot.png] [--help]
#include <cstdio>

#include "omni_shadows.hpp"

int main(int argc, char** argv) {
    OmniShadowSettings s;
    app::App a("omni shadows (cube map)");
    bind_settings(a.params(), s);  // size, culling, lookup: --param, the panel
    a.default_scene("room");
    OmniShadows o;                 // after the App: its GL objects go before the App's context
    a.debug_view("cube faces", [&] { return o.debug_faces(); });
    if (!a.start(argc, argv)) return a.exit_code();  // options, window or EGL, scene, G-buffer
    std::string why, said;
    while (a.next_frame()) {  // input, camera, light; the G-buffer when the camera moved
        if (a.scene_changed() && !o.init(a.view(), why)) return a.fail(why);
        a.cpu("faces + culling", [&] { o.update(a.view(), s); });
        if (o.error() != said && !(said = o.error()).empty())  // the sun: no cube map
            std::fprintf(stderr, "omni shadows: %s, no shadows\n", said.c_str());
        a.gpu("6 faces + lookup", [&] { o.render(a.view(), s); });
        a.present(o.visibility());  // the composite (or a debug view) and the panel; headless: the PNG
    }
    return a.exit_code();
}
