// Sample: an area light as N spot lights (sampled_area_light.hpp / .cpp): N shadow maps from Poisson
// points on the emitter, one hardware 2x2 compare each, averaged: converges to the true soft shadow.
//   sample_sampled_area_light [--scene overlap] [--param maps=64] [--view "first map"] [--headless shot.png] [--help]
#include "sampled_area_light.hpp"

int main(int argc, char** argv) {
    SampledAreaLightSettings s;
    app::App a("sampled area light");
    bind_settings(a.params(), s);  // maps, size: --param, the panel
    SampledAreaLight sal;          // after the App: its GL objects go before the App's context
    a.debug_view("first map", [&] { return sal.debug_first_map(); });
    if (!a.start(argc, argv)) return a.exit_code();  // options, window or EGL, scene, G-buffer
    std::string why;
    while (a.next_frame()) {  // input, camera, light; the G-buffer when the camera moved
        if (a.scene_changed() && !sal.init(a.view(), why)) return a.fail(why);
        a.cpu("points + frusta", [&] { sal.update(a.view(), s); });
        if (!sal.error().empty()) return a.fail(sal.error());
        a.gpu("maps + lookups", [&] { sal.render(a.view(), s); });
        a.present(sal.visibility());  // the composite (or a debug view) and the panel; headless: the PNG
    }
    return a.exit_code();
}
