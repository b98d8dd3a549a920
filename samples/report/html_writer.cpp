#include "html_writer.hpp"

#include "light_sweep.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace skr {

// samples/report/html/, embedded by html/embed.cmake (page_assets.cpp in the build folder)
extern const char* const kPageHtml;
extern const char* const kPageCss;
extern const char* const kPageJs;

namespace {

// A JSON string that is also safe inside <script>: "<" written as \u003c ("</script>" cannot end it).
std::string js_string(const std::string& s) {
    std::string out = "\"";
    for (char c : json_escape(s)) out += c == '<' ? std::string("\\u003c") : std::string(1, c);
    return out + "\"";
}

std::string js_number(double v) {
    if (!std::isfinite(v)) return "null";
    char b[40];
    std::snprintf(b, sizeof b, "%.6g", v);
    return b;
}

void write_info_data(std::ostream& f, const ReportInfo& info) {
    f << "\"info\": {\"renderer\": " << js_string(info.renderer) << ", \"cpu\": " << js_string(info.cpu)
      << ", \"date\": " << js_string(info.date) << ", \"command\": " << js_string(info.command)
      << ", \"quick\": " << (info.quick ? "true" : "false") << ", \"width\": " << info.width
      << ", \"height\": " << info.height << ", \"frames\": " << info.frames << "}";
}

void write_scenes_data(std::ostream& f, const std::vector<SceneInfo>& scenes) {
    f << ",\n\"scenes\": [";
    for (std::size_t i = 0; i < scenes.size(); ++i) {
        const SceneInfo& s = scenes[i];
        f << (i ? ",\n " : "\n ") << "{\"name\": " << js_string(s.name) << ", \"description\": " << js_string(s.description)
          << ", \"light\": " << js_string(s.light) << ", \"light_size\": " << js_number(s.light_size)
          << ", \"base\": " << js_string(s.base) << ", \"triangles\": " << s.triangles
          << ", \"reference\": " << js_string(s.reference_image) << ", \"ref_samples\": " << s.ref_samples << "}";
    }
    f << "]";
}

// The row's scored temporal paths: [{path, rms, flips}].
void write_row_temporal(std::ostream& f, const Row& r) {
    f << ", \"temporal\": [";
    bool first = true;
    for (const TemporalRow& t : r.temporal) {
        if (!t.scored) continue;
        f << (first ? "" : ", ") << "{\"path\": " << js_string(t.path) << ", \"rms\": " << js_number(t.temporal_rms)
          << ", \"flips\": " << js_number(t.flip_fraction) << "}";
        first = false;
    }
    f << "]";
}

// One row: what the plots, the tooltips, the filters and the viewer need (report.json has the rest).
void write_row_data(std::ostream& f, const Row& r) {
    f << "{\"scene\": " << js_string(r.scene) << ", \"technique\": " << js_string(r.technique)
      << ", \"family\": " << js_string(r.family) << ", \"hard\": " << (r.hard ? "true" : "false")
      << ", \"settings\": " << js_string(r.params_label) << ", \"def\": " << (is_default_row(r) ? "true" : "false");
    if (r.failed) {
        f << ", \"failed\": " << js_string(r.error) << "}";
        return;
    }
    f << ", \"rmse\": " << js_number(r.m.rmse)
      << ", \"penumbra_rmse\": " << (r.m.has_penumbra ? js_number(r.m.penumbra_rmse) : "null")
      << ", \"leak\": " << (r.m.has_leak ? js_number(r.m.leak_fraction) : "null")
      << ", \"ms\": " << js_number(r.gpu_ms + r.cpu_ms) << ", \"mib\": " << js_number(double(r.gpu_bytes) / 1048576.0)
      << ", \"pareto\": " << (r.pareto ? "true" : "false") << ", \"images\": {\"reference\": " << js_string(r.image_ref)
      << ", \"technique\": " << js_string(r.image_v) << ", \"error\": " << js_string(r.image_err) << "}";
    write_row_temporal(f, r);
    f << "}";
}

// `const REPORT = {...};`: info, scenes, rows (report.json's order), light_sweep (report.json's entries).
std::string page_data(const ReportInfo& info, const std::vector<SceneInfo>& scenes, const std::vector<Row>& rows,
                      const LightSweep* sweep) {
    std::ostringstream f;
    f << "const REPORT = {";
    write_info_data(f, info);
    write_scenes_data(f, scenes);
    f << ",\n\"rows\": [";
    for (std::size_t i = 0; i < rows.size(); ++i) {
        f << (i ? ",\n " : "\n ");
        write_row_data(f, rows[i]);
    }
    f << "]";
    if (sweep) {  // report.json's "light_sweep" entries (numbers and plain words)
        std::ostringstream s;
        write_light_sweep_json(s, *sweep);
        std::string text = s.str();
        for (std::size_t p = text.find('<'); p != std::string::npos; p = text.find('<', p)) text.replace(p, 1, "\\u003c");
        f << text;
    }
    f << "};";
    return f.str();
}

// Replaces the placeholder `marker` of the page with `text`.
void fill(std::string& page, const std::string& marker, const std::string& text) {
    const std::size_t at = page.find(marker);
    if (at != std::string::npos) page.replace(at, marker.size(), text);
}

}  // namespace

bool write_html(const std::string& path, const ReportInfo& info, const std::vector<SceneInfo>& scenes,
                const std::vector<Row>& rows, const LightSweep* sweep) {
    std::string page = kPageHtml;
    // from the last marker to the first: each search finds the page's own marker, never one in inserted text
    fill(page, "/*SCRIPT*/", kPageJs);
    fill(page, "/*DATA*/", page_data(info, scenes, rows, sweep));
    fill(page, "/*STYLE*/", kPageCss);
    std::ofstream f(path);
    f << page;
    return static_cast<bool>(f);
}

}  // namespace skr
