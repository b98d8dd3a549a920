// Sample: robust stenciled shadow volumes (shadow_volumes.hpp / .cpp): per-caster z-pass / z-fail,
// scissor rectangle and depth bounds, two-sided stencil, V = (stencil == 0).
//   sample_shadow_volumes [--scene NAME] [--param method=zfail] [--view "stencil counts"] [--headless shot.png] [--help]
#include "shadow_volumes.hpp"

int main(int argc, char** argv) {
    ShadowVolumeSettings s;
    app::App a("shadow volumes");
    bind_settings(a.params(), s);// method, scissor, depth_bounds, projection: --param, the panel
    ShadowVolumes sv;     // after the App: its GL objects go before the App's context
    a.debug_view("stencil counts", [&] { return sv.debug_stencil(); });
    a.debug_view("scissor rectangles", [&] { return sv.debug_scissor(); });
    if (!a.start(argc, argv)) return a.exit_code();  // options, window or EGL, scene, G-buffer
    std::string why;
    while (a.next_frame()) {  // input, camera, light; the G-buffer when the camera moved
        if (a.scene_changed() && !sv.init(a.view(), why)) return a.fail(why);
        a.cpu("silhouettes + volumes", [&] { sv.update(a.view(), s); });
        if (!sv.error().empty()) return a.fail(sv.error());
        a.gpu("depth + stencil + V", [&] { sv.render(a.view(), s); });
        a.present(sv.visibility());  // the composite (or a debug view) and the panel; headless: the PNG
    }
    return a.exit_code();
}
