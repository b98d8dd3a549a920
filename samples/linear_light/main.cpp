// Sample: soft shadows from a line light (linear_light.hpp / .cpp, Heidrich et al. 2000): a depth map at
// each end of the line and a "skin" over each map's depth discontinuities say how much of the line a
// point sees; method=sampled is the baseline of N shadow maps along the line. Starts on the linear scene.
//   sample_linear_light [--scene NAME] [--param segments=2] [--param skin=gpu] [--param method=sampled]
//                       [--view "visibility map"] [--headless shot.png] [--help]
#include "linear_light.hpp"

int main(int argc, char** argv) {
    LinearLightSettings s;
    app::App a("linear light");
    bind_settings(a.params(), s);  // method, size, segments, skin, threshold, samples: --param, the panel
    a.default_scene("linear");
    LinearLight ll;  // after the App: its GL objects go before the App's context
    a.debug_view("depth map", [&] { return ll.debug_depth(); });
    a.debug_view("visibility map", [&] { return ll.debug_skin(); });
    if (!a.start(argc, argv)) return a.exit_code();  // options, window or EGL, scene, G-buffer
    std::string why;
    while (a.next_frame()) {  // input, camera, light; the G-buffer when the camera moved
        if (a.scene_changed() && !ll.init(a.view(), why)) return a.fail(why);
        a.cpu("sub-lights + frusta", [&] { ll.update(a.view(), s); });
        a.gpu("depth maps", [&] { ll.render_depth_maps(a.view(), s); });
        a.cpu("skins (read-back + triangulation)", [&] { ll.build_skins(s); });
        if (!ll.error().empty()) return a.fail(ll.error());
        a.gpu("skins + V", [&] { ll.render_visibility(a.view(), s); });
        a.present(ll.visibility());  // the composite (or a debug view) and the panel; headless: the PNG
    }
    return a.exit_code();
}
