// index.html of shadowkit-report: one self-contained page beside report.md (samples/report/html/:
// the markup, report.css and report.js, embedded at build time, and the run's data as a JS literal).
#pragma once

#include <string>
#include <vector>

#include "report_writer.hpp"

namespace skr {

struct LightSweep;  // light_sweep.hpp

// Writes `path` (DIR/index.html): per scene the error-against-time plot with the Pareto front, the
// image viewer (reference | technique | signed error), filters, the light-size, flicker and light-sweep
// sections and the best-per-scene and per-family tables. `sweep` may be null.
bool write_html(const std::string& path, const ReportInfo& info, const std::vector<SceneInfo>& scenes,
                const std::vector<Row>& rows, const LightSweep* sweep);

}  // namespace skr
