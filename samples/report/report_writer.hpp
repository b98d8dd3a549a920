// Output side of shadowkit-report: rows -> report.md, report.json, error_vs_time.svg.
#pragma once

#include <string>
#include <vector>

#include "metrics.hpp"

namespace skr {

struct Row {
    std::string technique, params_label, scene;
    std::vector<std::pair<std::string, double>> params;
    int width = 0, height = 0;
    bool failed = false;
    std::string error;
    sk::Metrics m;
    double gpu_ms = 0.0, cpu_ms = 0.0;
    int frames = 0;
    long long gpu_bytes = 0;
    std::vector<std::pair<std::string, double>> work;
    std::vector<std::pair<std::string, double>> quality;
    int ref_samples = 0;
    double ref_stderr = 0.0;
    bool pareto = false;
    std::string image_v, image_err;
};

struct SceneInfo {
    std::string name, description, reference_image;
    std::size_t triangles = 0;
    int ref_samples = 0;
    double ref_stderr = 0.0, ref_seconds = 0.0;
    bool ref_cached = false;
};

struct ReportInfo {
    std::string renderer, gl_version, cpu, date, command;
    int width = 0, height = 0, frames = 0;
    bool quick = false;
    bool timer_queries = false;
};

// Marks rows on each scene's Pareto front (no other row of the scene is both faster and lower RMSE).
void mark_pareto(std::vector<Row>& rows);

std::string json_escape(const std::string& s);
bool write_json(const std::string& path, const ReportInfo& info, const std::vector<Row>& rows);
bool write_markdown(const std::string& path, const ReportInfo& info, const std::vector<SceneInfo>& scenes,
                    const std::vector<Row>& rows);
bool write_svg(const std::string& path, const std::vector<SceneInfo>& scenes, const std::vector<Row>& rows);

}  // namespace skr
