// samples/report/temporal_rows.hpp - the report's temporal rows: which rows of a scene run
// over time, and running them on every path (samples/report/temporal.hpp has the paths and metrics).
#pragma once

#include <string>
#include <vector>

#include "reference.hpp"
#include "report_writer.hpp"
#include "techniques.hpp"

namespace skr {

struct TemporalOptions {
    int frames = 16;       ///< per path; < 2: no temporal rows
    double max_ms = 40.0;  ///< settings slower than this (GPU + CPU ms a frame, still run) are left out
    std::string cache_dir; ///< the reference cache (the light path's per-frame references)
};

/// Chooses the scene's temporal rows among `rows` (the scene's still rows, already judged): per
/// technique the lowest-RMSE setting, and the lowest-RMSE setting of each combination of values of
/// its `method`, `fit`, `cache`, `pass`, `world_depth` and `culling` settings, among settings under
/// o.max_ms a frame. Runs each on the
/// pan, yaw and dolly paths and, for a hard light, the light path, and fills Row::temporal.
void run_temporal_rows(const sk::Scene& scene, const sk::SceneGpu& gpu, const sk::GBuffer& g, const sk::Reference& ref,
                       const TemporalOptions& o, const std::vector<sk::Technique*>& chosen, const std::vector<Row*>& rows);

}  // namespace skr
