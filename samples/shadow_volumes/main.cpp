// Sample: robust stenciled shadow volumes (silhouette.hpp + shadow_volume.hpp +
// glsl/shadow_volume.glsl): per-caster z-pass / z-fail, scissor and depth bounds, two-sided stencil.
// `shadow_volumes --headless --frames 8 --out shot.png [--scene room] [--param method=0]` renders 8 frames
// with the light moving, without a display, and writes the last one.
#include "viewer.hpp"

int main(int argc, char** argv) { return sk::run_viewer(argc, argv, "shadow_volume"); }
