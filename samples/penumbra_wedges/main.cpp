// Sample: soft shadow volumes with penumbra wedges (penumbra_wedges.hpp / .cpp): the hard stencil volume
// of the light's center (the shadow_volumes sample's class) plus one wedge per silhouette edge whose signed
// coverage of a spherical light is summed in a float buffer.
//   sample_penumbra_wedges [--scene overlap] [--param scissor=off] [--param light_scale=2] [--view "wedge hulls"]
//                          [--headless shot.png] [--help]
#include "penumbra_wedges.hpp"

int main(int argc, char** argv) {
    PenumbraWedgeSettings s;
    app::App a("penumbra wedges");
    bind_settings(a.params(), s);  // scissor, depth_bounds, projection, rect_radius, horizon, method, faces, light_scale
    PenumbraWedges pw;             // after the App: its GL objects go before the App's context
    a.debug_view("wedge hulls", [&] { return pw.debug_hulls(); });
    a.debug_view("stencil counts", [&] { return pw.volumes().debug_stencil(); });
    if (!a.start(argc, argv)) return a.exit_code();  // options, window or EGL, scene, G-buffer
    std::string why;
    while (a.next_frame()) {  // input, camera, light; the G-buffer when the camera moved
        if (a.scene_changed() && !pw.init(a.view(), why)) return a.fail(why);
        a.cpu("volumes + wedges", [&] { pw.update(a.view(), s); });
        if (!pw.error().empty()) return a.fail(pw.error());
        a.gpu("stencil + wedges + V", [&] { pw.render(a.view(), s); });
        a.present(pw.visibility());  // the composite (or a debug view) and the panel; headless: the PNG
    }
    return a.exit_code();
}
