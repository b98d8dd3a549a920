// Sample: soft shadow volumes with penumbra wedges (silhouette.hpp + shadow_volume.hpp +
// penumbra_wedge.hpp + glsl/penumbra_wedge.glsl): the hard stencil volume from the light centre plus
// one wedge per silhouette edge whose signed analytic coverage is added into a float buffer.
// `penumbra_wedges --headless out.png [--scene overlap] [--param scissor=0] [--param light_scale=2]`
// renders without a display; keys 1-9 pick a sweep entry (scissor / depth bounds / projection).
#include "viewer.hpp"

int main(int argc, char** argv) { return sk::run_viewer(argc, argv, "penumbra_wedges"); }
