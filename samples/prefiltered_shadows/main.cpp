// Sample: pre-filtered shadow maps (shadowkit/prefiltered_shadow.hpp for the depth range, the
// uniforms checked against the texture format, the blur weights and the kernel width;
// glsl/prefiltered_shadow.glsl for the moment pass, the blur, the MSAA resolve and the lookup).
//
//   sample_prefiltered_shadows [--scene overlap] [--technique vsm] [--headless out.png] [--size WxH]
//                              [--param name=value]... [--view N]
//   techniques (T switches): vsm, esm, evsm2, evsm4, msm, msm_hausdorff, and pcf to compare
//   params: size (map texels), width (blur, texels; the sweep's second value matches the light's
//           penumbra from world units), format 0 RGBA32F / 1 RGBA16F / 2 RGBA16 (MSM: quantized),
//           exponent (c+ as a fraction of the format's limit: above 1 the settings are refused with
//           Overflow), exponent_neg (EVSM4's c-), bleed (light-bleeding reduction, 0..0.99),
//           min_variance and moment_bias (multiples of the format's defaults), depth_bias (t units),
//           blur 0 box / 1 Gaussian, mips 0/1 (trilinear), msaa 0/1 (4x depth, resolved into moments)
//   keys: Tab picks a parameter and [ ] change it live, V shows the moment maps (debug view: the
//   first moments in light space), 1-9 pick a sweep entry, arrows move the light, N/P scene, Esc.
//   Light bleeding: --scene overlap or stack with vsm and a wide blur, then raise `bleed`.
#include <string>
#include <vector>

#include "viewer.hpp"

int main(int argc, char** argv) {
    return sk::run_viewer(argc, argv,
                          std::vector<std::string>{"vsm", "esm", "evsm2", "evsm4", "msm", "msm_hausdorff", "pcf"});
}
