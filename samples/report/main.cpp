// shadowkit-report: every technique's error against a ray-traced reference, against its run time.
//
//   shadowkit-report [--out DIR] [--scenes a,b|default] [--techniques x,y] [--mesh FILE]... [--size WxH]
//                    [--frames N] [--light-sizes k,k|none] [--temporal N|off] [--light-sweep N|off]
//                    [--quick] [--list]
//
// Light sizes: `contact`, `overlap`, `stack`, `room` and every --mesh scene are also run with the
// light resized by each factor k (default 0.5,2; none with --quick): area lights scale their size,
// point and spot lights become sphere lights of radius 4k% of the scene's diagonal (k = 1 added).
// These variants (`NAME@light=K`) run only the soft techniques compared across light sizes (pcss,
// smoothie, penumbra_wedges, msm_soft, vsm_soft), each against its own area-light reference; report.md sums them up in
// "## light size".
//
// Over time (samples/report/temporal_rows.hpp): the chosen rows of every scene (not the
// light-size variants) run N frames (--temporal N, default 12, --quick 4; off: none) of camera paths
// and, for hard lights, a turning light, scored by flicker: DIR/flicker_vs_error.svg and the rows'
// "temporal" entries.
//
// Light sweep (samples/report/light_sweep.hpp, docs/report.md): after the scenes, the hard shadow-map
// techniques of the run at their defaults (shadow_map; pcf filter=hard; cached_shadow_map, warped_sm,
// cascades) on every built-in visibility scene and scanned mesh of the run (not the light-size
// variants, --mesh scenes or prt) under N random lights (--light-sweep N, default 1000, --quick 48;
// N / 4 on the scanned meshes; off: none) at 128x96: report.json's "light_sweep", report.md's
// "## light sweep".
//
// Writes DIR/index.html (the page: plots, images side by side; html_writer.hpp), DIR/report.md, DIR/report.json,
// DIR/error_vs_time.svg and DIR/images/. Bad input gets a one-line error and exit status 2; a technique that fails
// on a scene becomes a failed row.
// Scanned meshes (docs/report.md): `bunny`, `bunny_sun`, `dragon`, `dragon_sun` (in the default set) load
// npm packages from sk::mesh_dir() ($SHADOWKIT_MESH_DIR, else /usr/local/share/shadowkit/meshes; installed by
// cmake/install-deps.sh). When a package is missing, one line names it and its scenes are skipped (the exit
// status does not change). They run each technique's ReportSpec::mesh_sweep (its defaults and the one or
// two settings that matter; --quick: the defaults, 3 timed frames, and by default only bunny and dragon_sun),
// no light-size variants and no temporal rows (the report's time budget).
// The scene `prt` (in the default set) is not a visibility scene: it adds a "## prt" section and a
// top-level "prt" object (PRT shading error vs SH order against a Monte Carlo reference).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <exception>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <thread>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "gl.hpp"
#include "html_writer.hpp"
#include "light_sweep.hpp"
#include "metrics.hpp"
#include "prt_section.hpp"
#include "reference.hpp"
#include "report_writer.hpp"
#include "scene.hpp"
#include "techniques.hpp"
#include "temporal_rows.hpp"

namespace fs = std::filesystem;

namespace {

struct Options {
    std::string out = "report";
    std::vector<std::string> scenes, techniques, meshes;
    int width = 400, height = 300;
    int frames = 12;  // timed frames per row after 3 warm-up frames (medians; rows with a frame budget run fewer)
    bool frames_set = false, size_set = false;
    bool quick = false, list = false;
    std::vector<double> light_sizes{0.5, 2.0};
    bool light_sizes_set = false;
    int temporal = 12;  // frames per temporal path; 0: off
    bool temporal_set = false;
    int light_sweep = 1000;  // lights per scene of the light sweep; 0: off
    bool light_sweep_set = false;
};

// The scanned-mesh scenes of the default set with --quick (one per mesh and per kind of light; the others
// when named): there each technique runs its defaults, 3 timed frames after 1 warm-up.
const std::set<std::string> kQuickScannedScenes = {"bunny", "dragon_sun"};

// Scenes with light-size variants (the techniques run on them: skr::kLightSizeTechniques).
const std::set<std::string> kLightSizeScenes = {"contact", "overlap", "stack", "room"};

std::string light_text(const sk::Light& L) {
    char b[96];
    switch (L.type) {
    case sk::LightType::Rect: std::snprintf(b, sizeof b, "square light, edge %.3g", double(L.size)); break;
    case sk::LightType::Disk: std::snprintf(b, sizeof b, "disk light, radius %.3g", double(L.size)); break;
    case sk::LightType::Sphere: std::snprintf(b, sizeof b, "sphere light, radius %.3g", double(L.size)); break;
    case sk::LightType::Linear: std::snprintf(b, sizeof b, "line light, length %.3g", double(L.size)); break;
    case sk::LightType::Point: std::snprintf(b, sizeof b, "point light"); break;
    case sk::LightType::Spot: std::snprintf(b, sizeof b, "spot light"); break;
    default: std::snprintf(b, sizeof b, "directional light"); break;
    }
    return b;
}

// The light of `base` resized by k (see the header comment); false if the light has no size.
bool resize_light(const sk::Scene& base, double k, sk::Scene& out) {
    out = base;
    sk::Light& L = out.light;
    if (L.type == sk::LightType::Rect || L.type == sk::LightType::Disk || L.type == sk::LightType::Sphere) {
        if (!(L.size > 0.f)) return false;
        L.size = static_cast<float>(double(L.size) * k);
    } else if (L.type == sk::LightType::Point || L.type == sk::LightType::Spot) {
        L.type = sk::LightType::Sphere;
        L.size = static_cast<float>(0.04 * k * double(glm::length(base.bounds_max() - base.bounds_min())));
    } else {
        return false;
    }
    char b[48];
    std::snprintf(b, sizeof b, "@light=%g", k);
    out.name = base.name + b;
    out.description = base.description + "; light resized x" + std::string(b + 7) + ": " + light_text(L);
    return true;
}

int fail(const std::string& msg) {
    std::fprintf(stderr, "shadowkit-report: %s\n", msg.c_str());
    return 2;
}

std::vector<std::string> split(const std::string& s) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, ','))
        if (!item.empty()) out.push_back(item);
    return out;
}

bool parse_int(const char* s, int& v) {
    char* end = nullptr;
    const long x = std::strtol(s, &end, 10);
    if (end == s || *end != '\0' || x < 0 || x > 1000000) return false;
    v = static_cast<int>(x);
    return true;
}

const char* kUsage =
    "usage: shadowkit-report [--out DIR] [--scenes a,b|default] [--techniques x,y] [--mesh FILE]... [--size WxH]\n"
    "                        [--frames N] [--light-sizes k,k|none] [--temporal N|off] [--light-sweep N|off]\n"
    "                        [--quick] [--list]\n";

std::string cpu_name() {
    std::ifstream f("/proc/cpuinfo");
    std::string line;
    while (std::getline(f, line))
        if (line.rfind("model name", 0) == 0) {
            const auto c = line.find(':');
            if (c != std::string::npos) return line.substr(c + 2);
        }
    return "unknown CPU";
}

std::string sanitize(std::string s) {
    for (char& c : s)
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_' && c != '.') c = '_';
    return s;
}

void write_visibility_png(const std::string& path, const sk::GBuffer& g, const std::vector<float>& v) {
    std::vector<std::uint8_t> px(v.size());
    for (std::size_t k = 0; k < v.size(); ++k)
        px[k] = g.kind[k] == 0 ? std::uint8_t(40)
                               : static_cast<std::uint8_t>(std::lround(255.0 * std::clamp(double(v[k]), 0.0, 1.0)));
    skgl::write_png(path, g.width, g.height, 1, px.data());
}

// Signed error heat map: red = too bright (light leaks), blue = too dark, white = exact.
void write_error_png(const std::string& path, const sk::GBuffer& g, const sk::Reference& ref, const std::vector<float>& v) {
    std::vector<std::uint8_t> px(v.size() * 3);
    for (std::size_t k = 0; k < v.size(); ++k) {
        std::uint8_t rgb[3] = {90, 90, 90};
        if (g.kind[k] == 1 && ref.faces_light[k]) {
            const double e = std::clamp(double(v[k]) - double(ref.visibility[k]), -1.0, 1.0);
            const auto a = static_cast<std::uint8_t>(std::lround(255.0 * (1.0 - std::abs(e))));
            if (e >= 0) {
                rgb[0] = 255; rgb[1] = a; rgb[2] = a;
            } else {
                rgb[0] = a; rgb[1] = a; rgb[2] = 255;
            }
        } else if (g.kind[k] != 0) {
            rgb[0] = rgb[1] = rgb[2] = 150;
        }
        std::memcpy(&px[3 * k], rgb, 3);
    }
    skgl::write_png(path, g.width, g.height, 3, px.data());
}

// Step 1: the command line into `o`. Returns -1 to go on, else the exit status (--help: 0).
int parse_options(int argc, char** argv, Options& o) {
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&](const char* name) -> const char* {
            if (i + 1 >= argc) return nullptr;
            (void)name;
            return argv[++i];
        };
        if (a == "--help" || a == "-h") {
            std::fputs(kUsage, stdout);
            return 0;
        } else if (a == "--list") {
            o.list = true;
        } else if (a == "--quick") {
            o.quick = true;
        } else if (a == "--out") {
            const char* v = value("--out");
            if (!v || !*v) return fail("--out needs a directory");
            o.out = v;
        } else if (a == "--scenes") {
            const char* v = value("--scenes");
            if (!v) return fail("--scenes needs a comma-separated list");
            o.scenes = split(v);
        } else if (a == "--techniques") {
            const char* v = value("--techniques");
            if (!v) return fail("--techniques needs a comma-separated list");
            o.techniques = split(v);
        } else if (a == "--mesh") {
            const char* v = value("--mesh");
            if (!v) return fail("--mesh needs a file");
            o.meshes.push_back(v);
        } else if (a == "--size") {
            const char* v = value("--size");
            int w = 0, h = 0;
            char x = 0;
            char tail = 0;
            if (!v || std::sscanf(v, "%d%c%d%c", &w, &x, &h, &tail) != 3 || (x != 'x' && x != 'X'))
                return fail(std::string("--size wants WxH, got '") + (v ? v : "") + "'");
            if (w <= 0 || h <= 0 || w > 8192 || h > 8192)
                return fail(std::string("--size must be between 1x1 and 8192x8192, got '") + v + "'");
            o.width = w;
            o.height = h;
            o.size_set = true;
        } else if (a == "--light-sizes") {
            const char* v = value("--light-sizes");
            if (!v) return fail("--light-sizes needs a comma-separated list of factors or 'none'");
            o.light_sizes.clear();
            o.light_sizes_set = true;
            if (std::string(v) != "none") {
                for (const auto& item : split(v)) {
                    char* end = nullptr;
                    const double k = std::strtod(item.c_str(), &end);
                    if (end == item.c_str() || *end != '\0' || !(k > 0.0) || k > 100.0)
                        return fail("--light-sizes wants factors in (0, 100], got '" + item + "'");
                    o.light_sizes.push_back(k);
                }
                if (o.light_sizes.empty()) return fail("--light-sizes needs at least one factor or 'none'");
            }
        } else if (a == "--temporal") {
            const char* v = value("--temporal");
            if (!v || (std::string(v) != "off" && (!parse_int(v, o.temporal) || o.temporal < 2 || o.temporal > 1000)))
                return fail("--temporal wants a frame count from 2 to 1000 or 'off'");
            if (std::string(v) == "off") o.temporal = 0;
            o.temporal_set = true;
        } else if (a == "--light-sweep") {
            const char* v = value("--light-sweep");
            if (!v || (std::string(v) != "off" && (!parse_int(v, o.light_sweep) || o.light_sweep < 1 || o.light_sweep > 100000)))
                return fail("--light-sweep wants a light count from 1 to 100000 or 'off'");
            if (std::string(v) == "off") o.light_sweep = 0;
            o.light_sweep_set = true;
        } else if (a == "--frames") {
            const char* v = value("--frames");
            if (!v || !parse_int(v, o.frames) || o.frames < 1) return fail("--frames wants a positive integer");
            o.frames_set = true;
        } else {
            return fail("unknown argument '" + a + "'\n" + kUsage);
        }
    }
    if (o.quick) {
        if (!o.size_set) {
            o.width = 256;
            o.height = 192;
        }
        if (!o.frames_set) o.frames = 5;  // a preview: medians of 5 frames after 2 warm-up frames
        if (!o.light_sizes_set) o.light_sizes.clear();
        if (!o.temporal_set) o.temporal = 4;
        if (!o.light_sweep_set) o.light_sweep = 48;
    }
    return -1;
}

// --list: the scenes and techniques.
void print_list(const std::vector<std::unique_ptr<sk::Technique>>& techniques, const std::vector<std::string>& scene_names) {
    std::printf("scenes:\n");
    for (const auto& n : scene_names) {
        sk::Scene s;
        sk::make_builtin_scene(n, s);
        std::printf("  %-10s %s\n", n.c_str(), s.description.c_str());
    }
    for (const auto& n : sk::scanned_scene_names())
        std::printf("  %-10s %s%s\n", n.c_str(), sk::scanned_scene_description(n).c_str(),
                    sk::scanned_scene_present(n) ? ""
                                                 : (" [not installed: npm " + sk::scanned_scene_package(n) +
                                                    ", bash cmake/install-deps.sh]").c_str());
    std::printf("  %-10s %s\n", "prt", skr::prt_description());
    std::printf("techniques:\n");
    for (const auto& t : techniques)
        std::printf("  %-12s %s%s\n", t->name().c_str(), t->description().c_str(),
                    t->listed_by_default() ? "" : " [only when named]");
}

// Step 2a: the scene names to run (the default set unless named; `default` among the names stands for
// it, e.g. beside --mesh); run_prt for the `prt` pseudo-scene (not an sk::Scene, run after the
// visibility scenes).
std::vector<std::string> wanted_scene_names(const Options& o, const std::vector<std::string>& scene_names, bool& run_prt) {
    std::vector<std::string> wanted = o.scenes;
    run_prt = false;
    if (wanted.empty() && o.meshes.empty()) {
        for (const auto& n : scene_names)
            if (n != "square") wanted.push_back(n);
        for (const auto& n : sk::scanned_scene_names())
            if (!o.quick || kQuickScannedScenes.count(n)) wanted.push_back(n);
        run_prt = true;
    }
    if (std::find(wanted.begin(), wanted.end(), "default") != wanted.end()) {
        std::vector<std::string> expanded;
        for (const auto& n : wanted) {
            if (n != "default") {
                expanded.push_back(n);
                continue;
            }
            for (const auto& b : scene_names)
                if (b != "square") expanded.push_back(b);
            for (const auto& b : sk::scanned_scene_names())
                if (!o.quick || kQuickScannedScenes.count(b)) expanded.push_back(b);
            expanded.push_back("prt");
        }
        wanted = std::move(expanded);
    }
    return wanted;
}

// Step 2b: the scenes themselves (built-in, scanned meshes that are installed, --mesh files).
// False with `error` set for an unknown scene or a mesh that does not load.
bool load_scenes(const Options& o, const std::vector<std::string>& wanted, std::vector<sk::Scene>& scenes,
                 bool& run_prt, std::string& error) {
    std::vector<std::string> missing_scenes, missing_packages;  // scanned meshes not installed: skipped
    for (const auto& n : wanted) {
        if (n == "prt") {
            run_prt = true;
            continue;
        }
        sk::Scene s;
        if (sk::is_scanned_scene(n)) {
            if (!sk::scanned_scene_present(n)) {
                missing_scenes.push_back(n);
                const std::string pkg = sk::scanned_scene_package(n);
                if (std::find(missing_packages.begin(), missing_packages.end(), pkg) == missing_packages.end())
                    missing_packages.push_back(pkg);
                continue;
            }
            std::string why;
            if (!sk::make_scanned_scene(n, s, why)) {
                error = "scene " + n + ": " + why;
                return false;
            }
        } else if (!sk::make_builtin_scene(n, s)) {
            error = "unknown scene '" + n + "' (see --list)";
            return false;
        }
        scenes.push_back(std::move(s));
    }
    if (!missing_scenes.empty()) {
        auto join = [](const std::vector<std::string>& v) {
            std::string out;
            for (const auto& x : v) out += (out.empty() ? "" : ", ") + x;
            return out;
        };
        std::fprintf(stderr,
                     "shadowkit-report: skipping scenes %s: npm package%s %s not found in %s (install with `bash "
                     "cmake/install-deps.sh`, or set SHADOWKIT_MESH_DIR)\n",
                     join(missing_scenes).c_str(), missing_packages.size() > 1 ? "s" : "", join(missing_packages).c_str(),
                     sk::mesh_dir().c_str());
    }
    for (const auto& m : o.meshes) {
        sk::Scene s;
        if (!sk::load_mesh_scene(m, s, error)) return false;
        scenes.push_back(std::move(s));
    }
    return true;
}

// Step 2c: the light-size variants, right after the scenes they resize. Returns, per scene, the scene
// it resizes ("" for none).
std::vector<std::string> add_light_size_variants(const Options& o, std::vector<sk::Scene>& scenes) {
    std::vector<std::string> variant_base;
    const std::size_t mesh_first = scenes.size() - o.meshes.size();
    std::vector<sk::Scene> all;
    for (std::size_t i = 0; i < scenes.size(); ++i) {
        all.push_back(scenes[i]);
        variant_base.push_back("");
        if (!kLightSizeScenes.count(scenes[i].name) && i < mesh_first) continue;
        std::vector<double> ks = o.light_sizes;
        const bool point = scenes[i].light.type == sk::LightType::Point || scenes[i].light.type == sk::LightType::Spot;
        if (point && !ks.empty() && std::find(ks.begin(), ks.end(), 1.0) == ks.end()) ks.push_back(1.0);
        std::sort(ks.begin(), ks.end());
        for (double k : ks) {
            sk::Scene v;
            if (!resize_light(scenes[i], k, v)) continue;
            all.push_back(std::move(v));
            variant_base.push_back(scenes[i].name);
        }
    }
    scenes = std::move(all);
    return variant_base;
}

// Step 3: the techniques to run (the listed ones unless named). False with `error` for an unknown name.
bool choose_techniques(const Options& o, const std::vector<std::unique_ptr<sk::Technique>>& techniques,
                       std::vector<sk::Technique*>& chosen, std::string& error) {
    if (o.techniques.empty()) {
        for (auto& t : techniques)
            if (t->listed_by_default()) chosen.push_back(t.get());
        return true;
    }
    for (const auto& n : o.techniques) {
        auto it = std::find_if(techniques.begin(), techniques.end(), [&](const auto& t) { return t->name() == n; });
        if (it == techniques.end()) {
            error = "unknown technique '" + n + "' (see --list)";
            return false;
        }
        chosen.push_back(it->get());
    }
    return true;
}

// The report's header: machine, date, command and run settings.
skr::ReportInfo report_info(const Options& o, const std::string& renderer, const std::string& gl_version,
                            const std::string& command, const skr::TemporalOptions& temporal) {
    skr::ReportInfo info;
    info.renderer = renderer;
    info.gl_version = gl_version;
    info.cpu = cpu_name() + " (" + std::to_string(std::max(1u, std::thread::hardware_concurrency())) + " threads)";
    {
        const std::time_t now = std::time(nullptr);
        char b[32];
        std::strftime(b, sizeof b, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
        info.date = b;
    }
    info.command = command;
    info.width = o.width;
    info.height = o.height;
    info.frames = o.frames;
    info.quick = o.quick;
    info.timer_queries = skgl::timer_queries_in_use();
    info.temporal_frames = o.temporal;
    info.temporal_max_ms = temporal.max_ms;
    return info;
}

// A row run but not judged yet: its visibility is kept until the reference is final.
struct Pending {
    skr::Row row;
    std::vector<float> v;
    bool hard = false;
};

// Step 4a, one row: run technique t with parameter set ps on the scene (a driver that throws becomes
// a failed row, not a crash).
Pending run_row(const Options& o, const sk::Scene& scene, sk::SceneGpu& gpu, const sk::GBuffer& g,
                const sk::Reference& ref, sk::Technique* t, const sk::ParamSet& ps) {
    Pending p;
    skr::Row& r = p.row;
    r.technique = t->name();
    r.params = ps.values;
    r.named_params = ps.named;
    r.params_label = ps.label();
    r.scene = scene.name;
    r.family = t->family();
    r.hard = t->hard();
    r.width = o.width;
    r.height = o.height;
    std::fprintf(stderr, "  %-9s %-12s %-24s", scene.name.c_str(), t->name().c_str(), r.params_label.c_str());
    sk::RunContext ctx{scene, gpu, o.frames, o.quick ? 2 : 3, &g};
    if (o.quick && sk::is_scanned_scene(scene.name) && !o.frames_set) {  // a preview of the scanned meshes: the time budget
        ctx.frames = std::min(ctx.frames, 3);
        ctx.warmup = 1;
    }
    sk::RunResult res;
    try {
        res = t->run(ctx, ps);
    } catch (const std::exception& e) {
        res = sk::RunResult::failure(std::string("exception: ") + e.what());
    } catch (...) {
        res = sk::RunResult::failure("exception of unknown type");
    }
    if (res.ok && res.visibility.size() != g.kind.size()) {
        res.ok = false;
        res.error = "technique returned a visibility image of the wrong size";
    }
    if (!res.ok) {
        r.failed = true;
        r.error = res.error.substr(0, res.error.find('\n'));
        std::fprintf(stderr, " failed: %s\n", r.error.c_str());
        return p;
    }
    r.gpu_ms = res.gpu_ms;
    r.cpu_ms = res.cpu_ms;
    r.frames = res.frames;
    r.gpu_bytes = res.gpu_bytes;
    r.work = res.work;
    r.quality = res.quality;
    p.hard = t->hard();
    p.v = std::move(res.visibility);
    std::fprintf(stderr, " rmse %.4f  %.2f ms\n", sk::compute_metrics(g, ref, p.v, p.hard).rmse, r.gpu_ms);
    return p;
}

// Step 4b: judge the rows against the reference, refining it (more strata, cached) until its standard
// error is below 1/10 of the smallest error it judges on this scene, or 128^2 samples per pixel.
void judge_rows(const Options& o, const sk::Scene& scene, const sk::GBuffer& g, sk::ReferenceOptions& ro,
                sk::Reference& ref, std::vector<Pending>& pending) {
    auto judge = [&]() {
        double min_rmse = INFINITY;
        for (auto& p : pending) {
            if (p.row.failed) continue;
            p.row.m = sk::compute_metrics(g, ref, p.v, p.hard);
            if (p.row.m.rmse > 0.0) min_rmse = std::min(min_rmse, p.row.m.rmse);
        }
        return min_rmse;
    };
    std::string why;
    double min_rmse = judge();
    while (ref.samples_per_pixel > 1 && std::isfinite(min_rmse) && ref.stderr_rms > 0.1 * min_rmse && ro.strata < 128) {
        ro.strata = std::min(128, ro.strata * 3 / 2);
        std::fprintf(stderr, "  %-9s reference stderr %.5f > 1/10 of RMSE %.5f: refining to %d^2 rays per pixel\n",
                     scene.name.c_str(), ref.stderr_rms, min_rmse, ro.strata);
        if (!sk::cached_reference(scene, g, ro, (fs::path(o.out) / "cache").string(), ref, why)) break;
        min_rmse = judge();
    }
}

// Step 4: one scene: its reference, every chosen technique's rows, the temporal rows, the images.
// Appends to rows and infos; false (the scene skipped) when it cannot be prepared.
bool run_scene(const Options& o, const sk::Scene& scene, const std::string& base,
               const std::vector<sk::Technique*>& chosen, const skr::TemporalOptions& temporal,
               std::vector<skr::Row>& rows, std::vector<skr::SceneInfo>& infos) {
    sk::SceneGpu gpu;
    sk::GBuffer g;
    skr::SceneInfo si;
    si.name = scene.name;
    si.base = base;
    si.light = light_text(scene.light);
    si.light_size = scene.light.is_area() ? double(scene.light.size) : 0.0;
    si.description = scene.description;
    si.triangles = scene.triangle_count();
    const bool scanned = sk::is_scanned_scene(scene.name);
    std::string why;
    if (!sk::prepare_scene_gpu(scene, o.width, o.height, gpu, g, why)) {
        std::fprintf(stderr, "shadowkit-report: scene %s: %s\n", scene.name.c_str(), why.c_str());
        return false;
    }
    sk::ReferenceOptions ro;
    // stratified area-light samples per pixel: 48^2 = 2304 (quick: 32^2 = 1024), enough that the
    // reference's standard error stays below 1/10 of the smallest error it judges (checked in report.md)
    ro.strata = o.quick ? 32 : 48;
    sk::Reference ref;
    if (!sk::cached_reference(scene, g, ro, (fs::path(o.out) / "cache").string(), ref, why)) {
        std::fprintf(stderr, "shadowkit-report: reference for %s: %s\n", scene.name.c_str(), why.c_str());
        return false;
    }
    const std::string stem = sanitize(scene.name);
    si.reference_image = "images/" + stem + "__reference.png";
    // Run every technique first, keep its visibility, then judge (the reference may be refined).
    std::vector<Pending> pending;
    for (sk::Technique* t : chosen) {
        if (!si.base.empty() && std::find(std::begin(skr::kLightSizeTechniques), std::end(skr::kLightSizeTechniques),
                                          t->name()) == std::end(skr::kLightSizeTechniques))
            continue;  // a light-size variant runs only the soft techniques compared across sizes
        for (const auto& ps : t->sweep(scene, o.quick)) pending.push_back(run_row(o, scene, gpu, g, ref, t, ps));
    }
    judge_rows(o, scene, g, ro, ref, pending);
    si.ref_samples = ref.samples_per_pixel;
    si.ref_stderr = ref.stderr_rms;
    si.ref_seconds = ref.seconds;
    si.ref_cached = ref.from_cache;
    infos.push_back(si);
    write_visibility_png((fs::path(o.out) / si.reference_image).string(), g, ref.visibility);
    if (si.base.empty() && o.temporal > 0 && !scanned) {  // the chosen rows over time (not on scanned meshes: time budget)
        std::vector<skr::Row*> scene_rows;
        for (auto& p : pending) scene_rows.push_back(&p.row);
        skr::run_temporal_rows(scene, gpu, g, ref, temporal, chosen, scene_rows);
    }
    for (auto& p : pending) {
        skr::Row& r = p.row;
        r.ref_samples = ref.samples_per_pixel;
        r.ref_stderr = ref.stderr_rms;
        r.image_ref = si.reference_image;
        if (!r.failed) {
            const std::string img = "images/" + stem + "__" + sanitize(r.technique) + "__" + sanitize(r.params_label);
            r.image_v = img + "_V.png";
            r.image_err = img + "_err.png";
            write_visibility_png((fs::path(o.out) / r.image_v).string(), g, p.v);
            write_error_png((fs::path(o.out) / r.image_err).string(), g, ref, p.v);
        }
        rows.push_back(std::move(r));
    }
    return true;
}

// Step 5a: the PRT section (CPU, Embree).
void run_prt_section(const Options& o, skr::PrtReport& prt) {
    std::string why;
    std::fprintf(stderr, "  prt       PRT error vs SH order against a Monte Carlo reference (CPU, Embree)\n");
    if (!skr::run_prt(o.quick, prt, why)) {
        prt = skr::PrtReport{};
        prt.requested = true;
        prt.failed = true;
        prt.error = why;
        std::fprintf(stderr, "shadowkit-report: prt: %s\n", why.c_str());
        return;
    }
    for (const auto& r : prt.orders)
        std::fprintf(stderr, "  prt       order %-26s RMS %.2f%%  p95 %.2f%%  bias %+.2f%%  shade %.3f ms\n",
                     r.label.c_str(), 100.0 * r.rms, 100.0 * r.p95, 100.0 * r.bias, r.shade_ms);
    std::fprintf(stderr, "  prt       precompute %.2f s, reference %.2f s (stderr %.2f%%)\n", prt.transfer_seconds,
                 prt.ref_seconds, 100.0 * prt.ref_stderr);
}

// Step 5b: the light sweep over the built-in visibility scenes and scanned meshes of the run (no
// light-size variants, no --mesh scene, no prt).
void run_light_sweep_section(const Options& o, const std::vector<sk::Scene>& scenes,
                             const std::vector<std::string>& variant_base, const std::vector<sk::Technique*>& chosen,
                             skr::LightSweep& sweep) {
    std::vector<sk::Scene> sweep_scenes;
    for (std::size_t i = 0; i < scenes.size(); ++i) {
        sk::Scene b;
        if (variant_base[i].empty() && (sk::is_scanned_scene(scenes[i].name) || sk::make_builtin_scene(scenes[i].name, b)))
            sweep_scenes.push_back(scenes[i]);
    }
    skr::LightSweepOptions so;
    so.lights = o.light_sweep;
    so.mesh_lights = std::max(1, o.light_sweep / 4);  // scanned meshes: a quarter (their frames cost 5 to 20x)
    std::fprintf(stderr, "  sweep     %d lights per scene (%d per scanned mesh) at %dx%d, %zu scenes\n", so.lights,
                 so.mesh_lights, so.width, so.height, sweep_scenes.size());
    skr::run_light_sweep(sweep_scenes, chosen, so, sweep);
    std::fprintf(stderr, "  sweep     %.1f s\n", sweep.seconds);
}

// Step 6: report.json, report.md, the plots and index.html. False when a file cannot be written.
bool write_outputs(const Options& o, const skr::ReportInfo& info, const std::vector<skr::SceneInfo>& infos,
                   std::vector<skr::Row>& rows, const skr::PrtReport& prt, const skr::LightSweep& sweep) {
    skr::mark_pareto(rows);
    const fs::path out(o.out);
    bool ok = skr::write_json((out / "report.json").string(), info, rows, &prt, &sweep);
    ok = skr::write_markdown((out / "report.md").string(), info, infos, rows, &prt, &sweep) && ok;
    ok = skr::write_svg((out / "error_vs_time.svg").string(), infos, rows) && ok;
    ok = skr::write_light_size_svg((out / "error_vs_light_size.svg").string(), infos, rows) && ok;
    ok = skr::write_flicker_svg((out / "flicker_vs_error.svg").string(), infos, rows) && ok;
    ok = skr::write_html((out / "index.html").string(), info, infos, rows, &sweep) && ok;
    return ok;
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    std::string command = "shadowkit-report";
    for (int i = 1; i < argc; ++i) command += std::string(" ") + argv[i];
    const int parsed = parse_options(argc, argv, o);  // 1. options
    if (parsed >= 0) return parsed;
    auto techniques = sk::make_techniques();
    const auto scene_names = sk::builtin_scene_names();
    if (o.list) {
        print_list(techniques, scene_names);
        return 0;
    }
    // 2. scenes: the names, the scenes, their light-size variants
    bool run_prt = false;
    const std::vector<std::string> wanted = wanted_scene_names(o, scene_names, run_prt);
    std::vector<sk::Scene> scenes;
    std::string error;
    if (!load_scenes(o, wanted, scenes, run_prt, error)) return fail(error);
    const std::vector<std::string> variant_base = add_light_size_variants(o, scenes);
    // 3. techniques, output directory, GL context
    std::vector<sk::Technique*> chosen;
    if (!choose_techniques(o, techniques, chosen, error)) return fail(error);
    std::error_code ec;
    fs::create_directories(fs::path(o.out) / "images", ec);
    if (ec) return fail("cannot create output directory '" + o.out + "': " + ec.message());
    std::string why;
    auto gl = skgl::create_context(why);
    if (!gl) return fail("no OpenGL 4.5 context: " + why);
    std::fprintf(stderr, "shadowkit-report: %s, %zu scenes x %zu techniques at %dx%d%s\n", gl->renderer.c_str(),
                 scenes.size(), chosen.size(), o.width, o.height, run_prt ? ", and prt" : "");
    skr::TemporalOptions temporal;
    temporal.frames = o.temporal;
    temporal.max_ms = o.quick ? 20.0 : 60.0;  // 60: the virtual shadow map (38 ms a frame at 400x300) is over time what it is for
    temporal.cache_dir = (fs::path(o.out) / "cache").string();
    const skr::ReportInfo info = report_info(o, gl->renderer, gl->version, command, temporal);
    // 4. rows, scene by scene
    std::vector<skr::Row> rows;
    std::vector<skr::SceneInfo> infos;
    for (std::size_t i = 0; i < scenes.size(); ++i) run_scene(o, scenes[i], variant_base[i], chosen, temporal, rows, infos);
    // 5. sections: PRT, light sweep
    skr::PrtReport prt;
    if (run_prt) run_prt_section(o, prt);
    skr::LightSweep sweep;
    if (o.light_sweep > 0) run_light_sweep_section(o, scenes, variant_base, chosen, sweep);
    // 6. outputs
    if (!write_outputs(o, info, infos, rows, prt, sweep)) return fail("cannot write the report files in '" + o.out + "'");
    std::fprintf(stderr, "shadowkit-report: wrote %s/index.html, report.md, report.json, error_vs_time.svg (%zu rows)\n",
                 o.out.c_str(), rows.size());
    return infos.size() == scenes.size() && !prt.failed ? 0 : 1;
}
