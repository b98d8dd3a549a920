// Sample: soft shadows from a line light (linear_light.hpp + glsl/linear_light.glsl, Heidrich et
// al. 2000) on the linear scene, beside N shadow maps sampled along the line.
// Keys 1-9 pick size x segments, T switches linear_light / sampled_line; `--headless out.png`
// renders without a display.
#include <string>
#include <vector>

#include "viewer.hpp"

int main(int argc, char** argv) {
    bool scene_given = false;
    for (int i = 1; i < argc; ++i)
        if (std::string(argv[i]) == "--scene") scene_given = true;
    std::vector<char*> args(argv, argv + argc);
    static char scene_flag[] = "--scene", linear[] = "linear";
    if (!scene_given) {
        args.push_back(scene_flag);
        args.push_back(linear);
    }
    return sk::run_viewer(static_cast<int>(args.size()), args.data(),
                          std::vector<std::string>{"linear_light", "sampled_line"});
}
