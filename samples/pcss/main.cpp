// Sample: percentage-closer soft shadows (shadowkit/pcss.hpp for the uniforms, glsl/pcss.glsl for
// the blocker search and the filter) on the built-in area-light scenes.
//
//   sample_pcss [--scene contact] [--headless out.png] [--size WxH] [--param name=value]...
//   params: taps=16|32|64 (blocker search = filter taps), rotate=0|1 (per-pixel rotated Poisson),
//           light_scale=S (emitter width x S; 0 = the hard-shadow limit), depth24=0|1,
//           hard=1 (the plain 2x2 lookup with the same map and bias), horizon=0|1,
//           fit_near=0|1 (1: the light's near plane at the casters, pcss_fit_near_plane)
//   keys: 1-6 pick taps 16/32/64 x rotate 0/1, Tab + [ ] change a parameter live (light_scale
//   too), arrows move the light, T switches technique, N/P scene, Esc quits; drag to orbit.
#include <string>
#include <vector>

#include "viewer.hpp"

// T switches between PCSS, the PCF kernels, the bias study (Tab + [ ] change the bias method and
// setting live) and the sampled area light; Tab + [ ] also change taps, rotation and light_scale.
int main(int argc, char** argv) {
    return sk::run_viewer(argc, argv, std::vector<std::string>{"pcss", "pcf", "bias", "sampled_area"});
}
