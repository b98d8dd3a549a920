// Sample: virtual shadow maps for the sun (virtual_shadow_maps.hpp / .cpp): clipmap levels of 16k
// virtual texels, cut into 128-texel pages; each frame the visible pixels mark the pages they read, only
// the pages not yet in the pool are rendered, and the lookup walks the page table. The panel shows the
// pool and the pages requested / rendered / evicted. Starts on `outdoor` (a sun; other lights: no shadows).
//   sample_virtual_shadow_maps [--param pool_pages=256] [--param lod_bias=1] [--view pages]
//                              [--headless shot.png] [--help]
#include "virtual_shadow_maps.hpp"

#include <cstdio>

#if SHADOWKIT_APP_IMGUI
#include <imgui.h>
#endif

int main(int argc, char** argv) {
    VirtualShadowMapSettings s;
    app::App a("virtual shadow maps");
    bind_settings(a.params(), s);  // page_texels, virtual_texels, levels, pool_pages, lod_bias, pcf_radius
    a.default_scene("outdoor");
    VirtualShadowMaps vsm;         // after the App: its GL objects go before the App's context
    a.debug_view("pool", [&] { return vsm.debug_pool(); });
    a.debug_view("pages", [&] { return vsm.debug_pages(); });
    if (!a.start(argc, argv)) return a.exit_code();  // options, window or EGL, scene, G-buffer
    std::string why, said;
    while (a.next_frame()) {  // input, camera, light; the G-buffer when the camera moved
        if (a.scene_changed() && !vsm.init(a.view(), why)) return a.fail(why);
        a.cpu("frame", [&] { vsm.update(a.view(), s); });
        if (vsm.error() != said && !(said = vsm.error()).empty())  // a light that is not the sun
            std::fprintf(stderr, "virtual shadow maps: %s, no shadows\n", said.c_str());
        a.gpu("mark + plan + pages + lookup", [&] { vsm.render(a.view(), s); });
#if SHADOWKIT_APP_IMGUI
        a.panel([&] {  // what this frame rendered and what it left out
            const VirtualShadowMapStats& st = vsm.stats();
            const double mib = double(vsm.pool_bytes()) / (1024.0 * 1024.0);
            ImGui::Text("pool: %zu of %d pages resident (%.1f MiB)", st.resident, s.pool_pages, mib);
            ImGui::Text("pages requested %zu, kept %zu", st.requested, st.kept);
            ImGui::Text("pages rendered %zu, evicted %zu", st.rendered, st.evicted);
            if (st.fallback) ImGui::Text("pool too small: %zu requests on a coarser level", st.fallback);
        });
#endif
        a.present(vsm.visibility());  // the composite (or a debug view) and the panel; headless: the PNG
    }
    const VirtualShadowMapStats& st = vsm.stats();
    std::printf("virtual shadow maps: %zu frames, first rendered %zu pages; last: %zu requested, %zu rendered, %zu evicted, %zu resident\n",
                st.frames, st.first_frame_rendered, st.requested, st.rendered, st.evicted, st.resident);
    return a.exit_code();
}
