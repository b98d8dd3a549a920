// Sample: fitted (light_frustum.hpp, caster culling), uniform, PSM, LiSPSM and TSM shadow maps
// (perspective_shadow_maps.hpp) and stable cascades (cascades.hpp) on the outdoor scene.
// Keys 1-9 pick method x size, T switches to cascades; `--headless out.png` renders without a display.
#include <string>
#include <vector>

#include "viewer.hpp"

int main(int argc, char** argv) {
    bool scene_given = false;
    for (int i = 1; i < argc; ++i)
        if (std::string(argv[i]) == "--scene") scene_given = true;
    std::vector<char*> args(argv, argv + argc);
    static char scene_flag[] = "--scene", outdoor[] = "outdoor";
    if (!scene_given) {
        args.push_back(scene_flag);
        args.push_back(outdoor);
    }
    return sk::run_viewer(static_cast<int>(args.size()), args.data(), std::vector<std::string>{"warped_sm", "cascades"});
}
