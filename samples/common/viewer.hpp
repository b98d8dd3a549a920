// A small interactive viewer shared by the per-technique samples: a GLFW window that shows one
// technique's visibility on a built-in scene, shaded, with an orbiting camera. `--headless`
// renders on EGL instead (no display needed) and writes a PNG: `--frames N` frames with the light
// turning about the scene's vertical axis (360/N degrees a frame), the last one to `--out FILE`
// (default shot.png; `--headless FILE` also works), printing the median CPU / GPU times.
//
//   sample [--scene NAME] [--headless [OUT.png]] [--frames N] [--out OUT.png] [--size WxH]
//          [--param name=value]...
//   --view N (or key V) shows the technique's N-th debug image (shadow map, smoothie buffer,
//   texel density, ...) instead of the shaded scene.
//   keys: 1-9 pick a sweep entry, Tab picks a parameter and [ ] change it live, arrow keys and
//   PageUp/PageDown move the light, T next technique, N/P next/previous scene, Esc quits;
//   drag to orbit.
#pragma once

#include <string>
#include <vector>

namespace sk {

#include <vector>

int run_viewer(int argc, char** argv, const std::string& technique_name);
// Several techniques, switched live with T (the first is shown first; --technique NAME picks).
int run_viewer(int argc, char** argv, const std::vector<std::string>& technique_names);

}  // namespace sk
