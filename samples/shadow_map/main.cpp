// Sample: plain shadow mapping with the hardware 2x2 PCF (glsl/shadow_map.glsl), the report's
// baseline. `shadow_map --headless out.png` renders without a display.
#include "viewer.hpp"

int main(int argc, char** argv) { return sk::run_viewer(argc, argv, "shadow_map"); }
