// Sample: shadow silhouette maps (silhouette_map.hpp + glsl/silhouette_map.glsl) beside the plain
// shadow map of equal memory, on the stack scene (straight box edges) by default.
// Keys 1-9 pick the map size, T switches silhouette map / plain map; `--headless out.png` renders
// without a display.
#include <string>
#include <vector>

#include "viewer.hpp"

int main(int argc, char** argv) {
    bool scene_given = false;
    for (int i = 1; i < argc; ++i)
        if (std::string(argv[i]) == "--scene") scene_given = true;
    std::vector<char*> args(argv, argv + argc);
    static char scene_flag[] = "--scene", stack[] = "stack";
    if (!scene_given) {
        args.push_back(scene_flag);
        args.push_back(stack);
    }
    return sk::run_viewer(static_cast<int>(args.size()), args.data(),
                          std::vector<std::string>{"silhouette_map", "silmap_plain"});
}
