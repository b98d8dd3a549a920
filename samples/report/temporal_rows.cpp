// samples/report/temporal_rows.cpp - the report's temporal rows, see temporal_rows.hpp.
#include "temporal_rows.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <map>
#include <utility>

#include "temporal.hpp"

namespace skr {

namespace {

// The settings whose every value gets its own temporal row: the choices of method or fit (what
// stability depends on) and the cached map's cache, pass, depth range and culling.
const char* const kGroupKeys[] = {"method", "fit", "cache", "pass", "world_depth", "culling"};

std::string group_of(const Row& r) {
    std::string g;
    for (const char* key : kGroupKeys) {
        for (const auto& [k, v] : r.named_params)
            if (k == key) g += " " + k + "=" + v;
        for (const auto& [k, v] : r.params)
            if (k == key) {
                char b[32];
                std::snprintf(b, sizeof b, "%g", v);
                g += " " + k + "=" + b;
            }
    }
    return g;
}

}  // namespace

void run_temporal_rows(const sk::Scene& scene, const sk::SceneGpu& gpu, const sk::GBuffer& g, const sk::Reference& ref,
                       const TemporalOptions& o, const std::vector<sk::Technique*>& chosen, const std::vector<Row*>& rows) {
    if (o.frames < 2) return;
    // ---- the rows: the best setting of each technique, and of each method / fit / cache / pass
    std::map<std::string, Row*> best;
    std::map<std::pair<std::string, std::string>, Row*> best_group;
    for (Row* r : rows) {
        if (r->failed || r->gpu_ms + r->cpu_ms > o.max_ms) continue;
        Row*& b = best[r->technique];
        if (!b || r->m.rmse < b->m.rmse) b = r;
        const std::string grp = group_of(*r);
        if (grp.empty()) continue;
        Row*& bg = best_group[{r->technique, grp}];
        if (!bg || r->m.rmse < bg->m.rmse) bg = r;
    }
    std::vector<std::pair<Row*, sk::Technique*>> selected;
    for (Row* r : rows) {
        if (r->failed || r->gpu_ms + r->cpu_ms > o.max_ms) continue;
        const std::string grp = group_of(*r);
        const bool top = best[r->technique] == r, group_top = !grp.empty() && best_group[{r->technique, grp}] == r;
        if (!top && !group_top) continue;
        sk::Technique* tech = nullptr;
        for (sk::Technique* t : chosen)
            if (t->name() == r->technique) tech = t;
        if (!tech) continue;
        r->temporal_choice = top ? "best" : "best" + grp;
        selected.emplace_back(r, tech);
    }
    if (selected.empty()) return;

    // ---- the paths
    std::vector<sk::TemporalPath> paths = {sk::TemporalPath::Pan, sk::TemporalPath::Yaw, sk::TemporalPath::Dolly};
    if (!scene.light.is_area()) paths.push_back(sk::TemporalPath::Light);  // one exact ray per pixel and frame
    for (sk::TemporalPath path : paths) {
        const std::vector<sk::TemporalFrame> frames = sk::temporal_path(scene, path, o.frames);
        const bool camera = sk::temporal_path_moves_camera(path);
        // the reference per frame (the light path) and the compared pixels: receivers facing the light
        // in every frame, inside every frame's view
        std::vector<sk::Reference> refs;
        std::vector<const std::vector<float>*> ref_v{&ref.visibility};
        std::string ref_error;
        if (!camera) {
            refs.resize(frames.size());
            sk::ReferenceOptions ro;
            ro.progress = false;
            for (std::size_t t = 0; t < frames.size() && ref_error.empty(); ++t) {
                sk::Scene s = scene;
                s.light = frames[t].light;
                std::string why;
                if (!sk::cached_reference(s, g, ro, o.cache_dir, refs[t], why)) ref_error = "reference: " + why;
            }
            ref_v.clear();
            for (const sk::Reference& r : refs) ref_v.push_back(&r.visibility);
        }
        std::vector<std::uint8_t> mask(g.kind.size(), 0);
        if (camera) mask = sk::temporal_frustum_mask(g, frames);
        for (std::size_t k = 0; k < mask.size(); ++k) {
            bool keep = g.kind[k] == 1 && (camera ? mask[k] != 0 : true) && ref.faces_light[k] != 0;
            for (const sk::Reference& r : refs) keep = keep && r.faces_light[k] != 0;
            mask[k] = keep ? 1 : 0;
        }
        for (auto& [row, tech] : selected) {
            TemporalRow tr;
            tr.path = sk::temporal_path_name(path);
            tr.frames = o.frames;
            std::fprintf(stderr, "  %-9s %-12s %-24s %-5s", scene.name.c_str(), row->technique.c_str(), row->params_label.c_str(),
                         tr.path.c_str());
            if (!ref_error.empty()) {
                tr.note = ref_error;
            } else if (camera && !tech->honors_fit_camera()) {
                tr.note = "takes no fit camera (Technique::honors_fit_camera() is false)";
            } else {
                sk::ParamSet ps(row->params);
                ps.named = row->named_params;
                sk::RunContext ctx{scene, gpu, 1, 0, &g};
                const auto t0 = std::chrono::steady_clock::now();
                sk::SequenceResult sr;
                try {
                    sr = tech->run_sequence(ctx, ps, frames);
                } catch (const std::exception& e) {
                    sr = sk::SequenceResult::failure(std::string("exception: ") + e.what());
                }
                tr.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
                bool sizes = sr.visibility.size() == frames.size();
                for (const auto& v : sr.visibility) sizes = sizes && v.size() == g.kind.size();
                if (!sr.ok || !sizes) {
                    tr.note = "failed: " + (sr.ok ? std::string("wrong number or size of V images") : sr.error.substr(0, sr.error.find('\n')));
                } else {
                    const sk::TemporalMetrics m = sk::compute_temporal_metrics(sr.visibility, ref_v, mask);
                    tr.scored = true;
                    tr.pixels = m.pixels;
                    tr.temporal_rms = m.temporal_rms;
                    tr.flip_fraction = m.flip_fraction;
                    tr.worst_range = m.worst_range;
                    for (std::size_t t = 1; t < sr.visibility.size() && !tr.v_changed; ++t)
                        tr.v_changed = std::memcmp(sr.visibility[t].data(), sr.visibility[0].data(),
                                                   sr.visibility[0].size() * sizeof(float)) != 0;
                    tr.work = std::move(sr.work);
                }
            }
            if (tr.scored)
                std::fprintf(stderr, " temporal rms %.4f  flips %.2f%%  range %.3f  (%.1f s)\n", tr.temporal_rms,
                             100.0 * tr.flip_fraction, tr.worst_range, tr.seconds);
            else
                std::fprintf(stderr, " not scored: %s\n", tr.note.c_str());
            row->temporal.push_back(std::move(tr));
        }
    }
}

}  // namespace skr
