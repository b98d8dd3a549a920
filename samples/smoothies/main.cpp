// Sample: smoothies (Chan & Durand 2003): silhouette.hpp + smoothie.hpp + glsl/smoothie.glsl. The
// default is t mapped from the scene's area-light size (t = -1); pick another with --param t=0.1,
// the map size with --param size=2048. `smoothies --headless out.png` renders without a display.
#include "viewer.hpp"

int main(int argc, char** argv) { return sk::run_viewer(argc, argv, "smoothie"); }
