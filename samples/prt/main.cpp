// Sample: precomputed radiance transfer (prt.hpp / .cpp; shadowkit/prt.hpp + spherical_harmonics.hpp,
// glsl/prt.glsl): a blob and a box over a floor under a sky + sun environment. Per vertex, once, the
// transfer vector (order 5, Embree visibility); per frame the environment's SH turned on the CPU and
// one dot product per vertex on the GPU. The light's controls (arrows, headless: its turn) turn the
// environment's sun about the vertical.
//   sample_prt [--scene NAME] [--param order=3] [--param strata=16] [--param shadows=off]
//              [--param yaw=90] [--headless shot.png] [--help]
#include "prt.hpp"

int main(int argc, char** argv) {
    PrtSettings s;
    app::App a("PRT");
    bind_settings(a.params(), s);  // order, strata, shadows, yaw, pitch, exposure: --param, the panel
    a.add_scene(prt_app_scene());  // the tessellated prt scene (the built-in ones work too, coarsely)
    a.default_scene("prt");
    Prt prt;  // after the App: its GL objects go before the App's context
    a.debug_view("ambient occlusion", [&] { return prt.debug_occlusion(a.view()); });
    if (!a.start(argc, argv)) return a.exit_code();  // options, window or EGL, scene
    std::string why;
    while (a.next_frame()) {  // input, camera, light
        if (a.scene_changed() && !prt.init(a.view(), why)) return a.fail(why);
        a.cpu("transfer precomputation", [&] { prt.precompute(a.view(), s); });  // when strata changed
        a.cpu("environment rotation", [&] { prt.update(a.view(), s); });
        if (!prt.error().empty()) return a.fail(prt.error());
        a.gpu("shade vertices", [&] { prt.render(a.view(), s); });
        a.present_color(prt.color());  // PRT's own picture and the panel; headless: the PNG
    }
    return a.exit_code();
}
