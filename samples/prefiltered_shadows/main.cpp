// Sample: pre-filtered shadow maps (prefiltered_shadows.hpp / .cpp): the moments of the depth from the
// light, blurred like an image, and a bound of the lit fraction from them (VSM, ESM, EVSM2/4, MSM).
//   sample_prefiltered_shadows [--scene overlap] [--param method=vsm] [--param bleed_reduction=0.3]
//                              [--view moments] [--headless shot.png] [--help]
// Light bleeding: --scene overlap or stack with method=vsm, then raise bleed_reduction.
#include "prefiltered_shadows.hpp"

int main(int argc, char** argv) {
    PrefilteredShadowSettings s;
    app::App a("pre-filtered shadow maps");
    bind_settings(a.params(), s);  // method, format, size, blur, exponents, biases, mips, msaa: --param, the panel
    PrefilteredShadows ps;         // after the App: its GL objects go before the App's context
    a.debug_view("moments", [&] { return ps.debug_moments(); });
    if (!a.start(argc, argv)) return a.exit_code();  // options, window or EGL, scene, G-buffer
    std::string why;
    while (a.next_frame()) {  // input, camera, light; the G-buffer when the camera moved
        if (a.scene_changed() && !ps.init(a.view(), why)) return a.fail(why);
        a.cpu("uniforms + blur weights", [&] { ps.update(a.view(), s); });
        a.gpu("moments + blur + lookup", [&] { ps.render(a.view(), s); });
        if (!ps.error().empty()) return a.fail(ps.error());
        a.present(ps.visibility());  // the composite (or a debug view) and the panel; headless: the PNG
    }
    return a.exit_code();
}
