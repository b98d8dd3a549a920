// Sample: soft shadows from one shadow map (pcss.hpp / .cpp): percentage-closer soft shadows (a blocker
// search, the penumbra from the average blocker depth, a Poisson filter of that width), or PCF with a
// fixed kernel, and the depth bias of the lookup (receiver plane, constant, slope-scaled, normal offset).
//   sample_pcss [--scene contact] [--param filter=poisson] [--param bias=constant] [--view "shadow map"]
//               [--headless shot.png] [--help]
// Scenes: contact (square light), overlap (disk), stack (a spot light: a hard shadow, filtered); the light's
// size is in the panel. `--scene grazing --param bias=none` shows the acne a lookup without bias gets.
#include "pcss.hpp"

int main(int argc, char** argv) {
    PcssSettings s;
    app::App a("PCSS / PCF");
    bind_settings(a.params(), s);  // filter, taps, rotate, radius, size, depth, fit_near, bias, horizon: --param, the panel
    Pcss pcss;  // after the App: its GL objects go before the App's context
    a.debug_view("shadow map", [&] { return pcss.debug_depth(); });
    if (!a.start(argc, argv)) return a.exit_code();  // options, window or EGL, scene, G-buffer
    std::string why;
    while (a.next_frame()) {  // input, camera, light; the G-buffer when the camera moved
        if (a.scene_changed() && !pcss.init(a.view(), why)) return a.fail(why);
        a.cpu("light frustum", [&] { pcss.update(a.view(), s); });
        a.gpu("depth + filter", [&] { pcss.render(a.view(), s); });
        if (!pcss.error().empty()) return a.fail(pcss.error());
        a.present(pcss.visibility());  // the composite (or a debug view) and the panel; headless: the PNG
    }
    return a.exit_code();
}
