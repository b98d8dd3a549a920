// shadowkit-report's `prt` pseudo-scene: PRT shading (shadowkit/prt.hpp) of the procedural prt
// scene against a Monte Carlo reference of the same environment with Embree visibility, error and
// CPU shading time per SH order 1..5 and for the CPCA-compressed order 5.
#pragma once

#include <string>

#include "report_writer.hpp"

namespace skr {

// One-line description for --list.
const char* prt_description();

// Runs the measurement (--quick: fewer reference vertices and samples). False with `why` on failure.
bool run_prt(bool quick, PrtReport& out, std::string& why);

}  // namespace skr
