// Sample: shadow silhouette maps (silhouette_maps.hpp / .cpp): a depth map plus a map of points on the
// silhouette edges, so straight shadow boundaries stay straight at a fraction of a texel; map=plain is
// the plain shadow map of the same memory. Starts on the stack scene (straight box edges).
//   sample_silhouette_maps [--scene NAME] [--param map=plain] [--param size=256] [--view "silhouette points"]
//                          [--headless shot.png] [--help]
#include "silhouette_maps.hpp"

int main(int argc, char** argv) {
    SilhouetteMapSettings s;
    app::App a("silhouette maps");
    bind_settings(a.params(), s);  // map, size, occlusion_bias: --param, the panel
    a.default_scene("stack");
    SilhouetteMap sm;  // after the App: its GL objects go before the App's context
    a.debug_view("depth map", [&] { return sm.debug_depth(); });
    a.debug_view("silhouette points", [&] { return sm.debug_silhouette(); });
    if (!a.start(argc, argv)) return a.exit_code();  // options, window or EGL, scene, G-buffer
    std::string why;
    while (a.next_frame()) {  // input, camera, light; the G-buffer when the camera moved
        if (a.scene_changed() && !sm.init(a.view(), why)) return a.fail(why);
        a.cpu("silhouette edges", [&] { sm.update(a.view(), s); });
        if (!sm.error().empty()) return a.fail(sm.error());
        a.gpu("depth + silhouette map + V", [&] { sm.render(a.view(), s); });
        a.present(sm.visibility());  // the composite (or a debug view) and the panel; headless: the PNG
    }
    return a.exit_code();
}
