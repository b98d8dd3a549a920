// A small interactive viewer shared by the per-technique samples: a GLFW window that shows one
// technique's visibility on a built-in scene, shaded, with an orbiting camera. `--headless`
// renders one frame on EGL (no display needed) and writes a PNG instead.
//
//   sample [--scene NAME] [--headless OUT.png] [--size WxH] [--param name=value]...
//   keys: 1-9 pick a sweep entry, N/P next/previous scene, Esc quits; drag to orbit.
#pragma once

#include <string>

namespace sk {

int run_viewer(int argc, char** argv, const std::string& technique_name);

}  // namespace sk
