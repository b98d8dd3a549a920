// Sample: robust stenciled shadow volumes (silhouette.hpp + shadow_volume.hpp +
// glsl/shadow_volume.glsl): per-caster z-pass / z-fail, scissor and depth bounds, two-sided stencil.
// `shadow_volumes --headless out.png [--scene room] [--param method=0]` renders without a display.
#include "viewer.hpp"

int main(int argc, char** argv) { return sk::run_viewer(argc, argv, "shadow_volume"); }
