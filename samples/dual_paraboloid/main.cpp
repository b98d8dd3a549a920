// Sample: a point light's shadows from a dual-paraboloid map (dual_paraboloid.hpp / .cpp,
// omni_shadow.hpp): two hemispheres projected in the vertex shader, the casters tessellated so their
// straight chords stay within `tess` texels of the curves. Starts on `room`. The cube map: samples/omni_shadows/.
//   sample_dual_paraboloid [--param size=1774] [--param tess=0] [--param pcf=1]
//                          [--view "paraboloid +y"] [--headless shot.png] [--help]
#include <cstdio>

#include "dual_paraboloid.hpp"

int main(int argc, char** argv) {
    DualParaboloidSettings s;
    app::App a("dual-paraboloid shadows");
    bind_settings(a.params(), s);  // size, tess, pcf: --param, the panel
    a.default_scene("room");
    DualParaboloid dp;             // after the App: its GL objects go before the App's context
    a.debug_view("paraboloid +y", [&] { return dp.debug_layer(0); });
    a.debug_view("paraboloid -y", [&] { return dp.debug_layer(1); });
    if (!a.start(argc, argv)) return a.exit_code();  // options, window or EGL, scene, G-buffer
    std::string why, said;
    while (a.next_frame()) {  // input, camera, light; the G-buffer when the camera moved
        if (a.scene_changed() && !dp.init(a.view(), why)) return a.fail(why);
        a.cpu("frame + tessellation", [&] { dp.update(a.view(), s); });
        if (dp.error() != said && !(said = dp.error()).empty())  // the sun: no paraboloids
            std::fprintf(stderr, "dual paraboloid: %s, no shadows\n", said.c_str());
        a.gpu("2 paraboloids + lookup", [&] { dp.render(a.view(), s); });
        a.present(dp.visibility());  // the composite (or a debug view) and the panel; headless: the PNG
    }
    return a.exit_code();
}
