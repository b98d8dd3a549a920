// Sample: point-light shadows from a cube map (omni_shadow.hpp: six faces, per-face caster culling,
// linear distance + receiver bias) and from a dual-paraboloid map (casters tessellated from the
// header's tessellation-error bound) on the room scene.
// Keys 1-9 pick a sweep entry (size x culling / size x tess), T switches technique;
// `--headless out.png` renders without a display.
#include <string>
#include <vector>

#include "viewer.hpp"

int main(int argc, char** argv) {
    bool scene_given = false;
    for (int i = 1; i < argc; ++i)
        if (std::string(argv[i]) == "--scene") scene_given = true;
    std::vector<char*> args(argv, argv + argc);
    static char scene_flag[] = "--scene", room[] = "room";
    if (!scene_given) {
        args.push_back(scene_flag);
        args.push_back(room);
    }
    return sk::run_viewer(static_cast<int>(args.size()), args.data(), std::vector<std::string>{"cube_sm", "dual_paraboloid"});
}
