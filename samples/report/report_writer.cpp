#include "report_writer.hpp"

#include "light_sweep.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace skr {

bool is_default_row(const Row& r) { return r.params_label.find("settings=default") != std::string::npos; }

void mark_pareto(std::vector<Row>& rows) {
    for (auto& r : rows) {
        if (r.failed) continue;
        r.pareto = true;
        for (const auto& o : rows) {
            if (&o == &r || o.failed || o.scene != r.scene) continue;
            const bool no_worse = o.gpu_ms + o.cpu_ms <= r.gpu_ms + r.cpu_ms && o.m.rmse <= r.m.rmse;
            const bool better = o.gpu_ms + o.cpu_ms < r.gpu_ms + r.cpu_ms || o.m.rmse < r.m.rmse;
            if (no_worse && better) {
                r.pareto = false;
                break;
            }
        }
    }
}

std::string json_escape(const std::string& s) {
    std::string o;
    for (char c : s) {
        switch (c) {
            case '"': o += "\\\""; break;
            case '\\': o += "\\\\"; break;
            case '\n': o += "\\n"; break;
            case '\t': o += "\\t"; break;
            default:
                if (static_cast<unsigned char>(c) < 0x20) {
                    char b[8];
                    std::snprintf(b, sizeof b, "\\u%04x", c);
                    o += b;
                } else {
                    o += c;
                }
        }
    }
    return o;
}

static std::string num(double v) {
    if (!std::isfinite(v)) return "null";
    char b[40];
    std::snprintf(b, sizeof b, "%.6g", v);
    return b;
}

static void write_prt_json(std::ofstream& f, const PrtReport& p) {
    f << ",\n  \"prt\": {";
    if (p.failed) {
        f << "\"failed\": \"" << json_escape(p.error) << "\"}";
        return;
    }
    f << "\n    \"scene\": \"prt\", \"description\": \"" << json_escape(p.description) << "\", \"vertices\": "
      << p.vertices << ", \"triangles\": " << p.triangles << ", \"env_samples\": " << p.env_samples
      << ",\n    \"errors\": \"fraction of the mean reference radiance; per vertex |PRT - reference|, mean of RGB\""
      << ",\n    \"transfer\": {\"order\": " << p.transfer_order << ", \"samples\": " << p.transfer_samples
      << ", \"seconds\": " << num(p.transfer_seconds) << ", \"timing\": \"one run\", \"threads\": " << p.threads
      << ", \"rays\": " << p.transfer_rays << ", \"degenerate_vertices\": " << p.degenerate_vertices << "}"
      << ",\n    \"reference\": {\"vertices\": " << p.ref_vertices << ", \"vertex_stride\": " << p.ref_vertex_stride
      << ", \"samples\": " << p.ref_samples << ", \"stderr\": " << num(p.ref_stderr) << ", \"mean_radiance\": "
      << num(p.ref_mean) << ", \"seconds\": " << num(p.ref_seconds) << "}"
      << ",\n    \"shade\": {\"runs\": " << p.shade_runs << ", \"statistic\": \"median\", \"threads\": 1, \"vertices\": "
      << p.vertices << "}"
      << ",\n    \"orders\": [";
    bool first = true;
    const PrtOrderRow* cpca = nullptr;
    for (const auto& o : p.orders) {
        if (o.cpca) {
            cpca = &o;
            continue;
        }
        f << (first ? "\n" : ",\n") << "      {\"order\": " << o.order << ", \"coefficients\": " << o.coefficients
          << ", \"rms\": " << num(o.rms) << ", \"p95\": " << num(o.p95) << ", \"bias\": " << num(o.bias)
          << ", \"unshadowed_rms\": " << num(o.unshadowed_rms) << ", \"shade_ms\": " << num(o.shade_ms) << "}";
        first = false;
    }
    f << "\n    ]";
    if (cpca)
        f << ",\n    \"cpca\": {\"order\": " << cpca->order << ", \"clusters\": " << p.cpca_clusters
          << ", \"components\": " << p.cpca_components << ", \"rms\": " << num(cpca->rms) << ", \"p95\": "
          << num(cpca->p95) << ", \"bias\": " << num(cpca->bias) << ", \"shade_ms\": " << num(cpca->shade_ms)
          << ", \"compress_seconds\": " << num(p.cpca_seconds) << ", \"transfer_rms\": " << num(p.cpca_transfer_rms)
          << "}";
    f << "\n  }";
}

// A row's temporal paths (after its "pareto").
static void write_temporal_json(std::ofstream& f, const Row& r) {
    if (r.temporal.empty()) return;
    f << ", \"temporal_choice\": \"" << json_escape(r.temporal_choice) << "\", \"temporal\": [";
    for (std::size_t i = 0; i < r.temporal.size(); ++i) {
        const TemporalRow& t = r.temporal[i];
        f << (i ? ", " : "") << "{\"path\": \"" << json_escape(t.path) << "\", \"frames\": " << t.frames;
        if (!t.scored) {
            f << ", \"not_scored\": \"" << json_escape(t.note) << "\"}";
            continue;
        }
        f << ", \"pixels\": " << t.pixels << ", \"temporal_rms\": " << num(t.temporal_rms)
          << ", \"flip_fraction\": " << num(t.flip_fraction) << ", \"worst_range\": " << num(t.worst_range)
          << ", \"v_changed\": " << (t.v_changed ? "true" : "false") << ", \"seconds\": " << num(t.seconds) << ", \"work\": {";
        for (std::size_t k = 0; k < t.work.size(); ++k)
            f << (k ? ", " : "") << "\"" << json_escape(t.work[k].first) << "\": " << num(t.work[k].second);
        f << "}}";
    }
    f << "]";
}

bool write_json(const std::string& path, const ReportInfo& info, const std::vector<Row>& rows, const PrtReport* prt,
                const LightSweep* sweep) {
    std::ofstream f(path);
    if (!f) return false;
    f << "{\n  \"renderer\": \"" << json_escape(info.renderer) << "\",\n  \"gl_version\": \""
      << json_escape(info.gl_version) << "\",\n  \"cpu\": \"" << json_escape(info.cpu) << "\",\n  \"date\": \""
      << json_escape(info.date) << "\",\n  \"quick\": " << (info.quick ? "true" : "false")
      << ",\n  \"gpu_timing\": \"" << (info.timer_queries ? "GL_TIME_ELAPSED" : "glFinish+steady_clock")
      << "\",\n  \"temporal_frames\": " << info.temporal_frames << ",\n  \"rows\": [";
    bool first = true;
    for (const auto& r : rows) {
        f << (first ? "\n" : ",\n") << "    {\"technique\": \"" << json_escape(r.technique) << "\", \"params\": {";
        first = false;
        for (std::size_t i = 0; i < r.params.size(); ++i)
            f << (i ? ", " : "") << "\"" << json_escape(r.params[i].first) << "\": " << num(r.params[i].second);
        // named settings (ported techniques): a number stays a number, a word is a string
        for (std::size_t i = 0; i < r.named_params.size(); ++i) {
            const std::string& v = r.named_params[i].second;
            char* end = nullptr;
            const double x = std::strtod(v.c_str(), &end);
            const bool number = !v.empty() && end && *end == '\0' && std::isfinite(x);
            f << (i || !r.params.empty() ? ", " : "") << "\"" << json_escape(r.named_params[i].first)
              << "\": " << (number ? num(x) : "\"" + json_escape(v) + "\"");
        }
        f << "}, \"scene\": \"" << json_escape(r.scene) << "\", \"family\": \"" << json_escape(r.family)
          << "\", \"hard\": " << (r.hard ? "true" : "false") << ", \"width\": " << r.width << ", \"height\": " << r.height;
        if (r.failed) {
            f << ", \"failed\": \"" << json_escape(r.error) << "\"";
            f << ", \"rmse\": null, \"mean_abs\": null, \"p99_abs\": null, \"penumbra_rmse\": null, \"misclassified\": null"
              << ", \"leak_fraction\": null, \"leak_mean_excess\": null"
              << ", \"gpu_ms\": null, \"cpu_ms\": null, \"frames\": 0, \"gpu_bytes\": 0, \"work\": {}";
        } else {
            f << ", \"rmse\": " << num(r.m.rmse) << ", \"mean_abs\": " << num(r.m.mean_abs)
              << ", \"p99_abs\": " << num(r.m.p99_abs)
              << ", \"penumbra_rmse\": " << (r.m.has_penumbra ? num(r.m.penumbra_rmse) : "null")
              << ", \"misclassified\": " << (r.m.has_misclassified ? num(r.m.misclassified) : "null")
              << ", \"leak_fraction\": " << (r.m.has_leak ? num(r.m.leak_fraction) : "null")
              << ", \"leak_mean_excess\": " << (r.m.has_leak ? num(r.m.leak_mean_excess) : "null")
              << ", \"umbra_pixels\": " << r.m.umbra_pixels
              << ", \"gpu_ms\": " << num(r.gpu_ms) << ", \"cpu_ms\": " << num(r.cpu_ms) << ", \"frames\": " << r.frames
              << ", \"gpu_bytes\": " << r.gpu_bytes << ", \"work\": {";
            for (std::size_t i = 0; i < r.work.size(); ++i)
                f << (i ? ", " : "") << "\"" << json_escape(r.work[i].first) << "\": " << num(r.work[i].second);
            f << "}, \"quality\": {";
            for (std::size_t i = 0; i < r.quality.size(); ++i)
                f << (i ? ", " : "") << "\"" << json_escape(r.quality[i].first) << "\": " << num(r.quality[i].second);
            f << "}, \"pixels\": " << r.m.pixels << ", \"penumbra_pixels\": " << r.m.penumbra_pixels
              << ", \"pareto\": " << (r.pareto ? "true" : "false") << ", \"images\": {\"reference\": \""
              << json_escape(r.image_ref) << "\", \"technique\": \"" << json_escape(r.image_v) << "\", \"error\": \""
              << json_escape(r.image_err) << "\"}";
            write_temporal_json(f, r);
        }
        f << ", \"ref_samples\": " << r.ref_samples << ", \"ref_stderr\": " << num(r.ref_stderr) << "}";
    }
    f << "\n  ]";
    if (prt && prt->requested) write_prt_json(f, *prt);
    if (sweep) write_light_sweep_json(f, *sweep);
    f << "\n}\n";
    return static_cast<bool>(f);
}

static std::string fmt(const char* spec, double v) {
    char b[48];
    std::snprintf(b, sizeof b, spec, v);
    return b;
}

static std::string work_text(const Row& r) {
    std::string s;
    for (const auto& [k, v] : r.work) {
        if (!s.empty()) s += ", ";
        s += k + " " + (v >= 1e6 ? fmt("%.3gM", v / 1e6) : v == std::floor(v) ? fmt("%.0f", v) : fmt("%.3g", v));
    }
    return s;
}

static std::string quality_text(const Row& r) {
    std::string s;
    for (const auto& [k, v] : r.quality) {
        if (!s.empty()) s += ", ";
        s += k + " " + fmt("%.3g", v);
    }
    return s.empty() ? "-" : s;
}

static void write_prt_markdown(std::ofstream& f, const PrtReport& p) {
    f << "## prt\n\n";
    if (p.failed) {
        f << "Precomputed radiance transfer: failed: " << p.error << "\n\n";
        return;
    }
    f << "Precomputed radiance transfer (shadowed diffuse transfer, Sloan, Kautz & Snyder 2002) on the procedural "
         "`prt` scene: "
      << p.description << ", projected into SH with " << p.env_samples << " sphere samples. Transfer: order "
      << p.transfer_order << " (orders 1-4 are its prefixes), " << p.transfer_samples
      << " stratified samples per vertex, Embree visibility, " << p.threads << " threads: "
      << fmt("%.2f s", p.transfer_seconds) << " (one timed run), " << fmt("%.2f", double(p.transfer_rays) * 1e-6)
      << " M rays. Reference: Monte Carlo of the same environment with visibility at " << p.ref_vertices
      << " vertices (every " << p.ref_vertex_stride << "th: floor, blob, box) x " << p.ref_samples
      << " cosine-weighted samples, standard error " << fmt("%.2f%%", 100.0 * p.ref_stderr) << " of the mean, "
      << fmt("%.1f s", p.ref_seconds) << ".\n\n";
    f << "| SH order | coefficients | RMS error | p95 error | bias | unshadowed RMS error | shade ms |\n";
    f << "|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const auto& o : p.orders)
        f << "| " << o.label << " | " << o.storage << " | " << fmt("%.2f%%", 100.0 * o.rms) << " | "
          << fmt("%.2f%%", 100.0 * o.p95) << " | " << fmt("%+.2f%%", 100.0 * o.bias) << " | "
          << (o.unshadowed_rms >= 0.0 ? fmt("%.1f%%", 100.0 * o.unshadowed_rms) : std::string("-")) << " | "
          << fmt("%.3f", o.shade_ms) << " |\n";
    f << "\nErrors: per vertex |PRT - reference| (mean of RGB, albedo 1), relative to the mean reference radiance; "
         "unshadowed: the same order without visibility (what the shadows add). Shade ms: CPU, one thread, the "
         "dot products of all "
      << p.vertices << " vertices (CPCA: the per-cluster projections of the environment, then the weighted sum per "
         "vertex), median of "
      << p.shade_runs << " runs. CPCA compression took " << fmt("%.2f s", p.cpca_seconds) << ".\n\n";
}


// Light-size groups: each scene that has variants, followed by its variants (report order).
static std::vector<std::vector<const SceneInfo*>> light_size_groups(const std::vector<SceneInfo>& scenes) {
    std::vector<std::vector<const SceneInfo*>> groups;
    for (const auto& sc : scenes) {
        if (!sc.base.empty()) continue;
        std::vector<const SceneInfo*> g{&sc};
        for (const auto& v : scenes)
            if (v.base == sc.name) g.push_back(&v);
        if (g.size() > 1) {
            std::stable_sort(g.begin(), g.end(),
                             [](const SceneInfo* a, const SceneInfo* b) { return a->light_size < b->light_size; });
            groups.push_back(std::move(g));
        }
    }
    return groups;
}

// The lowest-RMSE row of a technique on a scene (nullptr if none ran).
static const Row* best_row(const std::vector<Row>& rows, const std::string& scene, const std::string& tech) {
    const Row* best = nullptr;
    for (const auto& r : rows)
        if (r.scene == scene && r.technique == tech && !r.failed && (!best || r.m.rmse < best->m.rmse)) best = &r;
    return best;
}

static void write_light_size_markdown(std::ofstream& f, const std::vector<SceneInfo>& scenes, const std::vector<Row>& rows) {
    const auto groups = light_size_groups(scenes);
    if (groups.empty()) return;
    f << "## light size\n\nThe soft techniques on the same scene with the light resized (area lights scaled; point and "
         "spot lights replaced by sphere lights), each against its own area-light reference: the lowest-RMSE "
         "setting of each technique's sweep. Plot: `error_vs_light_size.svg`.\n\n";
    f << "| scene | light | technique | best setting | RMSE | penumbra RMSE | ms |\n|---|---|---|---|---:|---:|---:|\n";
    for (const auto& g : groups)
        for (const SceneInfo* sc : g)
            for (const char* tech : kLightSizeTechniques) {
                const Row* r = best_row(rows, sc->name, tech);
                if (!r) continue;
                f << "| " << sc->name << " | " << sc->light << " | " << tech << " | " << r->params_label << " | "
                  << fmt("%.4f", r->m.rmse) << " | " << (r->m.has_penumbra ? fmt("%.4f", r->m.penumbra_rmse) : "-")
                  << " | " << fmt("%.2f", r->gpu_ms + r->cpu_ms) << " |\n";
            }
    f << "\n";
}

// What the temporal tables mean (report.md's header).
static void write_temporal_header(std::ofstream& f, const ReportInfo& info) {
    if (info.temporal_frames <= 0) return;
    f << "- over time: chosen rows run " << info.temporal_frames
      << " frames of each path (pan: the camera slides sideways, back and forth, by 0.1 to 4 texels of a 2048 map over "
         "the scene's diagonal a frame; yaw: it turns 0.25 degree a frame; dolly: it moves 0.5% closer a frame; light: the light "
         "turns 0.25 degree a frame about the scene's vertical axis, hard lights only). V is evaluated every frame at "
         "the first frame's G-buffer points while the technique fits to the moving camera, over the points every "
         "frame's camera sees. Temporal RMS: RMS over pixels and frames of (V_t - V_t-1) - (R_t - R_t-1) (the "
         "reference R is constant on the camera paths: every change of V is error); flips: pixels that cross 0.5 "
         "(lit <-> shadowed) at least once while the reference does not; range: the worst pixel's max - min of V - R. "
         "Rows: per technique the lowest-RMSE setting, and the lowest of each combination of its `method`, `fit`, "
         "`cache`, `pass`, `world_depth` and `culling` settings, among settings under "
      << fmt("%.0f", info.temporal_max_ms)
      << " ms a frame. A technique that takes no fit camera (Technique::honors_fit_camera) gets its camera paths "
         "marked not scored. Plot: `flicker_vs_error.svg`.\n";
}

// The scene's temporal rows, after its table.
static void write_temporal_markdown(std::ofstream& f, const std::vector<const Row*>& rs) {
    bool any = false;
    for (const Row* r : rs) any = any || !r->temporal.empty();
    if (!any) return;
    f << "Over time (per path: temporal RMS, flips, the worst pixel's range; \"same V\": V bit for bit the same in "
         "every frame):\n\n| technique | params | chosen as | RMSE | ms | path | temporal RMS | flips | range | work |\n"
         "|---|---|---|---:|---:|---|---:|---:|---:|---|\n";
    for (const Row* r : rs) {
        for (const TemporalRow& t : r->temporal) {
            f << "| " << r->technique << " | " << r->params_label << " | " << r->temporal_choice << " | "
              << fmt("%.4f", r->m.rmse) << " | " << fmt("%.2f", r->gpu_ms + r->cpu_ms) << " | " << t.path << " | ";
            if (!t.scored) {
                f << "not scored: " << t.note << " | | | |\n";
                continue;
            }
            std::string work;
            for (const auto& [k, v] : t.work)
                work += (work.empty() ? "" : ", ") + k + " " + (v == std::floor(v) && std::fabs(v) < 1e6 ? fmt("%.0f", v) : fmt("%.3g", v));
            f << fmt("%.4f", t.temporal_rms) << (t.v_changed ? "" : " (same V)") << " | "
              << fmt("%.2f%%", 100.0 * t.flip_fraction) << " | " << fmt("%.3f", t.worst_range) << " | "
              << (work.empty() ? "-" : work) << " |\n";
        }
    }
    f << "\n";
}

// The time a row is plotted and ranked by: GPU + CPU ms per frame.
static double row_ms(const Row& r) { return r.gpu_ms + r.cpu_ms; }

// "technique setting (RMSE, ms)".
static std::string row_text(const Row& r) {
    return r.technique + (r.params_label.empty() ? "" : " " + r.params_label) + " (" + fmt("%.4f", r.m.rmse) + ", " +
           fmt("%.2f ms", row_ms(r)) + ")";
}

// Summary, best per scene: the most accurate row and the scene's Pareto front, fastest first.
static void write_best_per_scene(std::ofstream& f, const std::vector<SceneInfo>& scenes, const std::vector<Row>& rows) {
    f << "Best per scene: the most accurate row, and the Pareto front (no other row both faster and more accurate), "
         "fastest first; RMSE and GPU + CPU ms per frame.\n\n| scene | most accurate | Pareto front |\n|---|---|---|\n";
    for (const auto& sc : scenes) {
        const Row* best = nullptr;
        std::vector<const Row*> front;
        for (const auto& r : rows) {
            if (r.scene != sc.name || r.failed) continue;
            if (!best || r.m.rmse < best->m.rmse) best = &r;
            if (r.pareto) front.push_back(&r);
        }
        if (!best) continue;
        std::sort(front.begin(), front.end(), [](const Row* a, const Row* b) { return row_ms(*a) < row_ms(*b); });
        std::string list;
        for (const Row* r : front) list += (list.empty() ? "" : "; ") + row_text(*r);
        f << "| " << sc.name << " | " << row_text(*best) << " | " << list << " |\n";
    }
    f << "\n";
}

// Summary, best per family: each family's lowest RMSE on each scene (not the light-size variants).
static void write_best_per_family(std::ofstream& f, const std::vector<SceneInfo>& scenes, const std::vector<Row>& rows) {
    std::vector<std::string> families;
    for (const auto& r : rows)
        if (std::find(families.begin(), families.end(), r.family) == families.end()) families.push_back(r.family);
    std::vector<const SceneInfo*> base;
    for (const auto& sc : scenes)
        if (sc.base.empty()) base.push_back(&sc);
    f << "Best per family (the families of samples/report/techniques/): its lowest RMSE on each scene, the technique "
         "and ms.\n\n| family |";
    for (const SceneInfo* sc : base) f << " " << sc->name << " |";
    f << "\n|---|";
    for (std::size_t i = 0; i < base.size(); ++i) f << "---|";
    f << "\n";
    for (const auto& fam : families) {
        f << "| " << fam << " |";
        for (const SceneInfo* sc : base) {
            const Row* best = nullptr;
            for (const auto& r : rows)
                if (r.scene == sc->name && r.family == fam && !r.failed && (!best || r.m.rmse < best->m.rmse)) best = &r;
            const double ms = best ? row_ms(*best) : 0.0;
            f << " " << (best ? fmt("%.4f ", best->m.rmse) + best->technique + fmt(ms < 10.0 ? " %.1f ms" : " %.0f ms", ms) : "-")
              << " |";
        }
        f << "\n";
    }
    f << "\n";
}

// report.md's opening: the summary before the full record.
static void write_summary_markdown(std::ofstream& f, const std::vector<SceneInfo>& scenes, const std::vector<Row>& rows) {
    f << "## summary\n\n";
    write_best_per_scene(f, scenes, rows);
    write_best_per_family(f, scenes, rows);
    f << "The full record follows: the run, the plots, a table per scene (every row, over time), the light sweep. "
         "`index.html` shows the same with the images.\n\n";
}

bool write_markdown(const std::string& path, const ReportInfo& info, const std::vector<SceneInfo>& scenes,
                    const std::vector<Row>& rows, const PrtReport* prt, const LightSweep* sweep) {
    std::ofstream f(path);
    if (!f) return false;
    f << "# shadowkit report: error against run time\n\n";
    write_summary_markdown(f, scenes, rows);
    f << "## the run\n\n";
    f << "- renderer: `" << info.renderer << "` (" << info.gl_version << ")\n";
    f << "- CPU: " << info.cpu << "\n- date: " << info.date << "\n";
    f << "- image: " << info.width << "x" << info.height << " camera pixels; GPU time = median of " << info.frames
      << " frames after warm-up ("
      << (info.timer_queries ? "GL_TIME_ELAPSED timer queries" : "glFinish + steady clock; llvmpipe is a software rasterizer, timer queries are meaningless there")
      << ")" << (info.quick ? "; **--quick** run" : "") << "\n";
    f << "- error: |V - V_ref| over receiver pixels facing the light; V_ref ray traced with Embree from the same "
         "G-buffer points. Penumbra RMSE: pixels with 0 < V_ref < 1. Misclassified: hard techniques, pixels "
         "away from 1-pixel edges of round(V_ref). Leak: light leaking into the reference's umbra, the fraction of "
         "pixels with V_ref = 0 where V > 0.1 / the mean V over them.\n";
    write_temporal_header(f, info);
    f << "- command: `" << info.command << "`\n\n";
    f << "![error against time](error_vs_time.svg)\n\n";
    if (info.temporal_frames > 0) f << "![flicker against error](flicker_vs_error.svg)\n\n";
    write_light_size_markdown(f, scenes, rows);
    for (const auto& sc : scenes) {
        std::vector<const Row*> rs;
        for (const auto& r : rows)
            if (r.scene == sc.name) rs.push_back(&r);
        // best error-for-time first: the Pareto front by time, then the rest by RMSE
        std::stable_sort(rs.begin(), rs.end(), [](const Row* a, const Row* b) {
            if (a->failed != b->failed) return !a->failed;
            if (a->pareto != b->pareto) return a->pareto;
            if (a->pareto) return a->gpu_ms + a->cpu_ms < b->gpu_ms + b->cpu_ms;
            return a->m.rmse < b->m.rmse;
        });
        f << "## " << sc.name << "\n\n" << sc.description << " (" << sc.triangles << " triangles). Reference: "
          << (sc.ref_samples > 1 ? std::to_string(sc.ref_samples) + " stratified shadow rays per pixel"
                                 : std::string("one exact shadow ray per pixel (hard light)"));
        if (sc.ref_samples > 1) f << ", standard error " << fmt("%.4f", sc.ref_stderr) << " RMS";
        f << (sc.ref_cached ? " (cached)" : fmt(", %.1f s", sc.ref_seconds)) << ".\n\n";
        double min_err = INFINITY;
        for (const Row* r : rs)
            if (!r->failed && r->m.rmse > 0.0) min_err = std::min(min_err, r->m.rmse);
        if (sc.ref_samples > 1 && std::isfinite(min_err))
            f << "Reference error / smallest RMSE judged: " << fmt("%.3f", sc.ref_stderr / min_err)
              << (sc.ref_stderr <= 0.1 * min_err
                      ? std::string(" (below 1/10: the reference is accurate enough)")
                      : sc.ref_samples >= 128 * 128
                            ? std::string(" (**above 1/10** at the reference's cap of 128^2 rays per pixel: the "
                                          "smallest errors on this scene are within a few times the reference's own "
                                          "noise, so rows below about ") +
                                  fmt("%.4f", 10.0 * sc.ref_stderr) + " RMSE are not ranked reliably)"
                            : std::string(" (**above 1/10**)"))
              << ".\n\n";
        f << "| technique | params | RMSE | mean abs | p99 abs | penumbra RMSE | misclassified | leak | GPU ms | CPU ms | GPU MiB | work | other metrics |\n";
        f << "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---|\n";
        for (const Row* r : rs) {
            if (r->failed) {
                f << "| " << r->technique << " | " << r->params_label << " | failed: " << r->error
                  << " | | | | | | | | | | |\n";
                continue;
            }
            f << "| " << (r->pareto ? "**" + r->technique + "**" : r->technique) << " | " << r->params_label << " | "
              << fmt("%.4f", r->m.rmse) << " | " << fmt("%.4f", r->m.mean_abs) << " | " << fmt("%.3f", r->m.p99_abs)
              << " | " << (r->m.has_penumbra ? fmt("%.4f", r->m.penumbra_rmse) : "-") << " | "
              << (r->m.has_misclassified ? fmt("%.2f%%", 100.0 * r->m.misclassified) : "-") << " | "
              << (r->m.has_leak ? fmt("%.1f%%", 100.0 * r->m.leak_fraction) + fmt(" / %.3f", r->m.leak_mean_excess) : "-") << " | "
              << fmt("%.2f", r->gpu_ms) << " | " << fmt("%.3f", r->cpu_ms) << " | "
              << fmt("%.2f", double(r->gpu_bytes) / 1048576.0) << " | " << work_text(*r) << " | " << quality_text(*r) << " |\n";
        }
        f << "\nBold: on the Pareto front (no other row is both faster and more accurate). Images: reference `"
          << sc.reference_image << "`";
        const Row* most_accurate = nullptr;
        for (const Row* r : rs)
            if (!r->failed && (!most_accurate || r->m.rmse < most_accurate->m.rmse)) most_accurate = r;
        if (most_accurate)
            f << "; most accurate row (" << most_accurate->technique << " " << most_accurate->params_label << ") `"
              << most_accurate->image_v << "` and its signed error `" << most_accurate->image_err
              << "` (red: too bright, blue: too dark)";
        f << ".\n\n";
        write_temporal_markdown(f, rs);
    }
    if (prt && prt->requested) write_prt_markdown(f, *prt);
    if (sweep) write_light_sweep_markdown(f, *sweep);
    return static_cast<bool>(f);
}

bool write_svg(const std::string& path, const std::vector<SceneInfo>& scenes, const std::vector<Row>& rows) {
    std::ofstream f(path);
    if (!f) return false;
    const int pw = 440, ph = 300, cols = 2;
    std::vector<SceneInfo> panels;  // light-size variants have their own plot
    for (const auto& sc : scenes)
        if (sc.base.empty()) panels.push_back(sc);
    const int n = static_cast<int>(panels.size());
    const int nrows = (n + cols - 1) / cols;
    const int W = pw * cols, H = ph * std::max(nrows, 1);
    // 20 distinguishable colours (techniques keep their colour across panels)
    static const char* palette[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2",
                                    "#17becf", "#7f7f7f", "#bcbd22", "#000000", "#00a087", "#ffc000", "#4b0082",
                                    "#ff1493", "#556b2f", "#00008b", "#a0522d", "#20b2aa", "#b30000"};
    std::map<std::string, int> color;
    for (const auto& r : rows)
        if (!color.count(r.technique)) color[r.technique] = static_cast<int>(color.size()) % 20;
    f << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H
      << "\" font-family=\"sans-serif\" font-size=\"11\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    for (int si = 0; si < n; ++si) {
        const auto& sc = panels[static_cast<std::size_t>(si)];
        const int ox = (si % cols) * pw, oy = (si / cols) * ph;
        const int l = ox + 55, r = ox + pw - 15, t = oy + 25, b = oy + ph - 40;
        std::vector<const Row*> rs;
        for (const auto& row : rows)
            if (row.scene == sc.name && !row.failed) rs.push_back(&row);
        f << "<text x=\"" << ox + pw / 2 << "\" y=\"" << oy + 15 << "\" text-anchor=\"middle\" font-weight=\"bold\">"
          << sc.name << "</text>\n";
        f << "<rect x=\"" << l << "\" y=\"" << t << "\" width=\"" << r - l << "\" height=\"" << b - t
          << "\" fill=\"none\" stroke=\"#444\"/>\n";
        if (rs.empty()) continue;
        double tmin = INFINITY, tmax = 0.0, emax = 0.0;
        for (const Row* row : rs) {
            const double tt = std::max(row->gpu_ms + row->cpu_ms, 1e-3);
            tmin = std::min(tmin, tt);
            tmax = std::max(tmax, tt);
            emax = std::max(emax, row->m.rmse);
        }
        double lx0 = std::floor(std::log10(tmin)), lx1 = std::ceil(std::log10(tmax));
        if (lx1 <= lx0) lx1 = lx0 + 1;
        emax = emax > 0 ? emax * 1.1 : 1.0;
        auto X = [&](double ms) { return l + (std::log10(std::max(ms, 1e-3)) - lx0) / (lx1 - lx0) * (r - l); };
        auto Y = [&](double e) { return b - e / emax * (b - t); };
        for (double d = lx0; d <= lx1 + 1e-9; d += 1.0) {
            const double x = l + (d - lx0) / (lx1 - lx0) * (r - l);
            f << "<line x1=\"" << x << "\" y1=\"" << t << "\" x2=\"" << x << "\" y2=\"" << b
              << "\" stroke=\"#ddd\"/><text x=\"" << x << "\" y=\"" << b + 14 << "\" text-anchor=\"middle\">"
              << fmt("%g", std::pow(10.0, d)) << "</text>\n";
        }
        for (int k = 0; k <= 4; ++k) {
            const double e = emax * k / 4.0;
            f << "<line x1=\"" << l << "\" y1=\"" << Y(e) << "\" x2=\"" << r << "\" y2=\"" << Y(e)
              << "\" stroke=\"#eee\"/><text x=\"" << l - 4 << "\" y=\"" << Y(e) + 4 << "\" text-anchor=\"end\">"
              << fmt("%.3g", e) << "</text>\n";
        }
        f << "<text x=\"" << (l + r) / 2 << "\" y=\"" << b + 30 << "\" text-anchor=\"middle\">time per frame, ms (log)</text>\n";
        f << "<text x=\"" << ox + 12 << "\" y=\"" << (t + b) / 2 << "\" transform=\"rotate(-90 " << ox + 12 << ' '
          << (t + b) / 2 << ")\" text-anchor=\"middle\">RMSE</text>\n";
        // per technique: every swept setting as a dot, and a line through the technique's own best
        // error-for-time settings (its Pareto front), so multi-parameter sweeps stay readable
        std::map<std::string, std::vector<const Row*>> by_tech;
        for (const Row* row : rs) by_tech[row->technique].push_back(row);
        int legend = 0;
        for (const auto& [tech, list] : by_tech) {
            const char* col = palette[color[tech]];
            std::vector<const Row*> own;
            for (const Row* row : list) {
                bool dominated = false;
                for (const Row* o : list) {
                    const double to = o->gpu_ms + o->cpu_ms, tr = row->gpu_ms + row->cpu_ms;
                    if (o != row && to <= tr && o->m.rmse <= row->m.rmse && (to < tr || o->m.rmse < row->m.rmse)) {
                        dominated = true;
                        break;
                    }
                }
                if (!dominated) own.push_back(row);
            }
            std::sort(own.begin(), own.end(),
                      [](const Row* a, const Row* c) { return a->gpu_ms + a->cpu_ms < c->gpu_ms + c->cpu_ms; });
            f << "<polyline fill=\"none\" stroke=\"" << col << "\" stroke-width=\"1.5\" points=\"";
            for (const Row* row : own) f << X(row->gpu_ms + row->cpu_ms) << ',' << Y(row->m.rmse) << ' ';
            f << "\"/>\n";
            for (const Row* row : list)
                f << "<circle cx=\"" << X(row->gpu_ms + row->cpu_ms) << "\" cy=\"" << Y(row->m.rmse) << "\" r=\"3\" fill=\""
                  << col << "\"><title>" << tech << ' ' << row->params_label << ": " << fmt("%.4f", row->m.rmse) << " @ "
                  << fmt("%.2f ms", row->gpu_ms + row->cpu_ms) << "</title></circle>\n";
            f << "<text x=\"" << r - 5 << "\" y=\"" << t + 14 + 13 * legend++ << "\" text-anchor=\"end\" fill=\"" << col
              << "\">" << tech << "</text>\n";
        }
        // the Pareto front: rings and a dashed staircase
        std::vector<const Row*> front;
        for (const Row* row : rs)
            if (row->pareto) front.push_back(row);
        std::sort(front.begin(), front.end(),
                  [](const Row* a, const Row* c) { return a->gpu_ms + a->cpu_ms < c->gpu_ms + c->cpu_ms; });
        if (!front.empty()) {
            f << "<polyline fill=\"none\" stroke=\"black\" stroke-dasharray=\"4 3\" points=\"";
            for (std::size_t i = 0; i < front.size(); ++i) {
                const double x = X(front[i]->gpu_ms + front[i]->cpu_ms), y = Y(front[i]->m.rmse);
                if (i) f << x << ',' << Y(front[i - 1]->m.rmse) << ' ';
                f << x << ',' << y << ' ';
            }
            f << "\"/>\n";
            for (const Row* row : front)
                f << "<circle cx=\"" << X(row->gpu_ms + row->cpu_ms) << "\" cy=\"" << Y(row->m.rmse)
                  << "\" r=\"6\" fill=\"none\" stroke=\"black\"/>\n";
            f << "<text x=\"" << r - 5 << "\" y=\"" << b - 6 << "\" text-anchor=\"end\">rings: Pareto front</text>\n";
        }
    }
    f << "</svg>\n";
    return static_cast<bool>(f);
}


bool write_light_size_svg(const std::string& path, const std::vector<SceneInfo>& scenes, const std::vector<Row>& rows) {
    const auto groups = light_size_groups(scenes);
    if (groups.empty()) return true;
    std::ofstream f(path);
    if (!f) return false;
    const int pw = 360, ph = 260, cols = 2;
    const int n = static_cast<int>(groups.size());
    const int W = pw * std::min(n, cols), H = ph * ((n + cols - 1) / cols);
    static const char* colors[] = {"#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#8c564b"};
    f << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H
      << "\" font-family=\"sans-serif\" font-size=\"11\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    for (int gi = 0; gi < n; ++gi) {
        const auto& g = groups[static_cast<std::size_t>(gi)];
        const int ox = (gi % cols) * pw, oy = (gi / cols) * ph;
        const int l = ox + 55, r = ox + pw - 15, t = oy + 25, b = oy + ph - 40;
        double smax = 0.0, emax = 0.0;
        for (const SceneInfo* sc : g) {
            smax = std::max(smax, sc->light_size);
            for (const char* tech : kLightSizeTechniques)
                if (const Row* row = best_row(rows, sc->name, tech)) emax = std::max(emax, row->m.rmse);
        }
        smax = smax > 0 ? smax * 1.05 : 1.0;
        emax = emax > 0 ? emax * 1.1 : 1.0;
        auto X = [&](double s) { return l + s / smax * (r - l); };
        auto Y = [&](double e) { return b - e / emax * (b - t); };
        f << "<text x=\"" << ox + pw / 2 << "\" y=\"" << oy + 15 << "\" text-anchor=\"middle\" font-weight=\"bold\">"
          << (g.front()->base.empty() ? g.front()->name : g.front()->base) << "</text>\n<rect x=\"" << l << "\" y=\"" << t << "\" width=\"" << r - l << "\" height=\""
          << b - t << "\" fill=\"none\" stroke=\"#444\"/>\n";
        for (int k = 0; k <= 4; ++k) {
            f << "<text x=\"" << X(smax * k / 4.0) << "\" y=\"" << b + 14 << "\" text-anchor=\"middle\">"
              << fmt("%.2g", smax * k / 4.0) << "</text>\n";
            f << "<line x1=\"" << l << "\" y1=\"" << Y(emax * k / 4.0) << "\" x2=\"" << r << "\" y2=\"" << Y(emax * k / 4.0)
              << "\" stroke=\"#eee\"/><text x=\"" << l - 4 << "\" y=\"" << Y(emax * k / 4.0) + 4
              << "\" text-anchor=\"end\">" << fmt("%.3g", emax * k / 4.0) << "</text>\n";
        }
        f << "<text x=\"" << (l + r) / 2 << "\" y=\"" << b + 30 << "\" text-anchor=\"middle\">light size (edge or radius)</text>\n";
        f << "<text x=\"" << ox + 12 << "\" y=\"" << (t + b) / 2 << "\" transform=\"rotate(-90 " << ox + 12 << ' '
          << (t + b) / 2 << ")\" text-anchor=\"middle\">best RMSE</text>\n";
        for (int ti = 0; ti < int(std::size(kLightSizeTechniques)); ++ti) {
            const char* tech = kLightSizeTechniques[ti];
            f << "<polyline fill=\"none\" stroke=\"" << colors[ti] << "\" stroke-width=\"1.5\" points=\"";
            for (const SceneInfo* sc : g)
                if (const Row* row = best_row(rows, sc->name, tech)) f << X(sc->light_size) << ',' << Y(row->m.rmse) << ' ';
            f << "\"/>\n";
            for (const SceneInfo* sc : g)
                if (const Row* row = best_row(rows, sc->name, tech))
                    f << "<circle cx=\"" << X(sc->light_size) << "\" cy=\"" << Y(row->m.rmse) << "\" r=\"3\" fill=\""
                      << colors[ti] << "\"><title>" << tech << ' ' << row->params_label << ": " << fmt("%.4f", row->m.rmse)
                      << "</title></circle>\n";
            f << "<text x=\"" << l + 6 << "\" y=\"" << t + 14 + 13 * ti << "\" fill=\"" << colors[ti] << "\">" << tech
              << "</text>\n";
        }
    }
    f << "</svg>\n";
    return static_cast<bool>(f);
}

bool write_flicker_svg(const std::string& path, const std::vector<SceneInfo>& scenes, const std::vector<Row>& rows) {
    std::vector<const SceneInfo*> panels;
    for (const auto& sc : scenes) {
        bool any = false;
        for (const auto& r : rows)
            if (r.scene == sc.name && !r.failed)
                for (const TemporalRow& t : r.temporal) any = any || t.scored;
        if (any) panels.push_back(&sc);
    }
    if (panels.empty()) return true;
    std::ofstream f(path);
    if (!f) return false;
    const int pw = 440, ph = 300, cols = 2;
    const int n = static_cast<int>(panels.size());
    const int W = pw * std::min(n, cols), H = ph * ((n + cols - 1) / cols);
    static const char* palette[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2",
                                    "#17becf", "#7f7f7f", "#bcbd22", "#000000", "#00a087", "#ffc000", "#4b0082",
                                    "#ff1493", "#556b2f", "#00008b", "#a0522d", "#20b2aa", "#b30000"};
    std::map<std::string, int> color;  // the same colours as error_vs_time.svg
    for (const auto& r : rows)
        if (!color.count(r.technique)) color[r.technique] = static_cast<int>(color.size()) % 20;
    // one marker per path: circle pan, square yaw, triangle dolly, diamond light
    auto marker = [&](const std::string& p, double x, double y, const char* col, const std::string& title) {
        std::ostringstream m;
        if (p == "yaw")
            m << "<rect x=\"" << x - 3 << "\" y=\"" << y - 3 << "\" width=\"6\" height=\"6\"";
        else if (p == "dolly")
            m << "<polygon points=\"" << x << ',' << y - 4 << ' ' << x - 4 << ',' << y + 3 << ' ' << x + 4 << ',' << y + 3 << "\"";
        else if (p == "light")
            m << "<polygon points=\"" << x << ',' << y - 4 << ' ' << x - 4 << ',' << y << ' ' << x << ',' << y + 4 << ' ' << x + 4
              << ',' << y << "\"";
        else
            m << "<circle cx=\"" << x << "\" cy=\"" << y << "\" r=\"3\"";
        m << " fill=\"" << col << "\" fill-opacity=\"0.8\"><title>" << title << "</title></" << (p == "yaw" ? "rect" : p == "pan" ? "circle" : "polygon") << ">\n";
        return m.str();
    };
    f << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H
      << "\" font-family=\"sans-serif\" font-size=\"11\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    for (int si = 0; si < n; ++si) {
        const SceneInfo& sc = *panels[static_cast<std::size_t>(si)];
        const int ox = (si % cols) * pw, oy = (si / cols) * ph;
        const int l = ox + 55, r = ox + pw - 15, t = oy + 25, b = oy + ph - 40;
        double emax = 0.0, fmax = 0.0;
        for (const auto& row : rows)
            if (row.scene == sc.name && !row.failed)
                for (const TemporalRow& tr : row.temporal)
                    if (tr.scored) {
                        emax = std::max(emax, row.m.rmse);
                        fmax = std::max(fmax, tr.temporal_rms);
                    }
        emax = emax > 0 ? emax * 1.1 : 1.0;
        fmax = fmax > 0 ? fmax * 1.1 : 1.0;
        auto X = [&](double e) { return l + e / emax * (r - l); };
        auto Y = [&](double v) { return b - v / fmax * (b - t); };
        f << "<text x=\"" << ox + pw / 2 << "\" y=\"" << oy + 15 << "\" text-anchor=\"middle\" font-weight=\"bold\">"
          << sc.name << "</text>\n<rect x=\"" << l << "\" y=\"" << t << "\" width=\"" << r - l << "\" height=\"" << b - t
          << "\" fill=\"none\" stroke=\"#444\"/>\n";
        for (int k = 0; k <= 4; ++k) {
            f << "<text x=\"" << X(emax * k / 4.0) << "\" y=\"" << b + 14 << "\" text-anchor=\"middle\">"
              << fmt("%.3g", emax * k / 4.0) << "</text>\n";
            f << "<line x1=\"" << l << "\" y1=\"" << Y(fmax * k / 4.0) << "\" x2=\"" << r << "\" y2=\"" << Y(fmax * k / 4.0)
              << "\" stroke=\"#eee\"/><text x=\"" << l - 4 << "\" y=\"" << Y(fmax * k / 4.0) + 4 << "\" text-anchor=\"end\">"
              << fmt("%.3g", fmax * k / 4.0) << "</text>\n";
        }
        f << "<text x=\"" << (l + r) / 2 << "\" y=\"" << b + 30 << "\" text-anchor=\"middle\">RMSE (still frame)</text>\n";
        f << "<text x=\"" << ox + 12 << "\" y=\"" << (t + b) / 2 << "\" transform=\"rotate(-90 " << ox + 12 << ' ' << (t + b) / 2
          << ")\" text-anchor=\"middle\">temporal RMS</text>\n";
        std::set<std::string> techs;
        for (const auto& row : rows) {
            if (row.scene != sc.name || row.failed) continue;
            for (const TemporalRow& tr : row.temporal) {
                if (!tr.scored) continue;
                techs.insert(row.technique);
                f << marker(tr.path, X(row.m.rmse), Y(tr.temporal_rms), palette[color[row.technique]],
                            row.technique + " " + row.params_label + ", " + tr.path + ": temporal RMS " +
                                fmt("%.4f", tr.temporal_rms) + ", flips " + fmt("%.2f%%", 100.0 * tr.flip_fraction) +
                                ", RMSE " + fmt("%.4f", row.m.rmse));
            }
        }
        int legend = 0;
        for (const std::string& tech : techs)
            f << "<text x=\"" << r - 5 << "\" y=\"" << t + 14 + 13 * legend++ << "\" text-anchor=\"end\" fill=\""
              << palette[color[tech]] << "\">" << tech << "</text>\n";
        f << "<text x=\"" << l + 5 << "\" y=\"" << t + 14 << "\">circle pan, square yaw, triangle dolly, diamond light</text>\n";
    }
    f << "</svg>\n";
    return static_cast<bool>(f);
}

}  // namespace skr
