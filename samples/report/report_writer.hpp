// Output side of shadowkit-report: rows -> report.md, report.json, error_vs_time.svg.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "metrics.hpp"

namespace skr {

// One path of a row's temporal sequence (samples/report/temporal_rows.cpp).
struct TemporalRow {
    std::string path;         // pan, yaw, dolly, light (sk::temporal_path_name)
    bool scored = false;      // false: `note` says why (a driver that ignores the fit camera, a failure)
    std::string note;
    int frames = 0;
    std::size_t pixels = 0;   // compared: receivers facing the light in every frame, inside every frame's view
    double temporal_rms = 0.0, flip_fraction = 0.0, worst_range = 0.0;
    bool v_changed = false;   // V differed between frames at some pixel (bit for bit)
    double seconds = 0.0;     // the sequence's wall time
    std::vector<std::pair<std::string, double>> work;  // the sequence's counters (cached maps)
};

struct Row {
    std::string technique, params_label, scene;
    std::string family;  // Technique::family(): "shadow_map", "soft", ...
    bool hard = false;   // Technique::hard(): 0/1 visibility
    std::vector<std::pair<std::string, double>> params;              // old drivers: numbers
    std::vector<std::pair<std::string, std::string>> named_params;   // ported techniques: settings by name
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
    std::string image_v, image_err, image_ref;  // paths relative to the output folder: V, signed error, the scene's reference
    std::vector<TemporalRow> temporal;  // empty when the row was not chosen (or --temporal off)
    std::string temporal_choice;        // why it was chosen: "best", "best method=lispsm"
};

// The soft techniques run on the light-size variants (and listed, in this order, in "## light size").
inline const char* const kLightSizeTechniques[] = {"penumbra_wedges", "pcss", "smoothie", "msm_soft", "vsm_soft"};

struct SceneInfo {
    std::string name, description, reference_image;
    std::string base;   // light-size variant: the scene it resizes (empty otherwise)
    std::string light;  // the light, in words (type and size)
    double light_size = 0.0;  // Light::size (0 for point, spot and directional lights)
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
    int temporal_frames = 0;  // frames per temporal path; 0: off
    double temporal_max_ms = 0.0;  // rows slower than this (GPU + CPU ms a frame) get no temporal rows
};

// The `prt` pseudo-scene (not an sk::Scene): precomputed radiance transfer shading of the
// procedural prt scene against a Monte Carlo reference with visibility, error vs SH order.
// Errors are fractions of the mean reference radiance (report.md shows them in %).
struct PrtOrderRow {
    std::string label;     // "1" .. "5", or "5, CPCA 64 x (mean + 4)"
    std::string storage;   // per-vertex storage: "25" coefficients, or "4 weights + cluster id"
    int order = 0;
    int coefficients = 0;  // floats per vertex
    bool cpca = false;
    double rms = 0.0, p95 = 0.0, bias = 0.0;
    double unshadowed_rms = -1.0;  // < 0: not measured (CPCA row)
    double shade_ms = 0.0;         // CPU, one thread, all vertices, median of shade_runs
};

struct PrtReport {
    bool requested = false;
    bool failed = false;
    std::string error;
    std::string description;
    std::size_t vertices = 0, triangles = 0;
    int env_samples = 0;               // sphere samples projecting the environment into SH
    int transfer_order = 5, transfer_samples = 0;
    double transfer_seconds = 0.0;     // one timed run (shadowed, all cores)
    std::uint64_t transfer_rays = 0;
    std::size_t degenerate_vertices = 0;
    unsigned threads = 1;
    std::size_t ref_vertices = 0, ref_vertex_stride = 1;
    int ref_samples = 0;               // cosine-weighted samples per reference vertex
    double ref_stderr = 0.0;           // RMS standard error, relative to the mean reference radiance
    double ref_seconds = 0.0, ref_mean = 0.0;
    std::size_t cpca_clusters = 0;
    int cpca_components = 0;
    double cpca_seconds = 0.0, cpca_transfer_rms = 0.0;
    int shade_runs = 0;
    std::vector<PrtOrderRow> orders;   // orders 1 .. 5, then the CPCA row
};

struct LightSweep;  // light_sweep.hpp

// True for a technique's `settings=default` row.
bool is_default_row(const Row& r);

// Marks rows on each scene's Pareto front (no other row of the scene is both faster and lower RMSE).
void mark_pareto(std::vector<Row>& rows);

std::string json_escape(const std::string& s);
// `prt` (may be null or not requested): a top-level "prt" object / a "## prt" section after the scenes;
// `sweep` (may be null or not requested) likewise: a top-level "light_sweep" array / "## light sweep".
bool write_json(const std::string& path, const ReportInfo& info, const std::vector<Row>& rows,
                const PrtReport* prt = nullptr, const LightSweep* sweep = nullptr);
bool write_markdown(const std::string& path, const ReportInfo& info, const std::vector<SceneInfo>& scenes,
                    const std::vector<Row>& rows, const PrtReport* prt = nullptr, const LightSweep* sweep = nullptr);
bool write_svg(const std::string& path, const std::vector<SceneInfo>& scenes, const std::vector<Row>& rows);
// flicker_vs_error.svg: per scene with temporal rows, each (row, path) as a point at
// (RMSE, temporal RMS); nothing is written without temporal rows.
bool write_flicker_svg(const std::string& path, const std::vector<SceneInfo>& scenes, const std::vector<Row>& rows);
// error_vs_light_size.svg: per scene with light-size variants, each soft technique's best RMSE
// against the light's size (false if it cannot be written; nothing is written without variants).
bool write_light_size_svg(const std::string& path, const std::vector<SceneInfo>& scenes, const std::vector<Row>& rows);

}  // namespace skr
