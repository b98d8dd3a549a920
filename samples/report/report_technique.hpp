// samples/report/report_technique.hpp - the report's wrapper of a sample's technique class.
//
// A ported technique lives once, in samples/<technique>/ (class T with Settings S, `bind_settings(Params&, S&)`,
// init / update / render / visibility). The report measures that same class from outside:
//   ReportTechnique<T, S> is a Technique of the registry; run() sets the sweep entry's named settings
//   through the same app::Params bindings the sample's --param uses, calls T::init once (timed: work
//   "init_ms"), times T::update on the CPU (median over the frames) and T::render on the GPU
//   (skgl::median_frame_ms: glFinish + steady clock on llvmpipe, timer queries on a GPU), reads back
//   T::visibility(), then lets the family's `measure` read the work counters from what T exposes
//   (sizes, per-caster results, passes it can run one at a time) - never from counters inside T.
// One file per family in samples/report/techniques/ defines its add_<family>_techniques() with the
// name, description, sweeps and `measure`, and registers each spec with add_technique().
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "app.hpp"
#include "gbuffer.hpp"
#include "params.hpp"
#include "techniques.hpp"

namespace sk {

/// R32F texture (w x h) -> floats, bottom-up rows.
std::vector<float> read_r32f(GLuint texture, int w, int h);
/// Runs draw() inside a GL_SAMPLES_PASSED query (and GL_FRAGMENT_SHADER_INVOCATIONS_ARB when
/// has_stats); fragments = the samples, invocations = the shader runs (left unchanged without stats).
void count_fragments(bool has_stats, const std::function<void()>& draw, double& fragments, double& invocations);
/// True if a caster of `scene` has boundary or non-manifold edges (silhouette.hpp's adjacency, no weld
/// tolerance): the volume families add an `open_meshes=lit_only` row there (the one-sided volume).
bool scene_has_open_caster(const Scene& scene);

/// How the report shows a wrapped technique.
template <class T, class S>
struct ReportSpec {
    std::string name, description;
    bool hard = true;                           ///< 0/1 visibility: misclassified pixels are scored
    std::vector<std::string> sweep, quick;      ///< named settings per row, e.g. "method=zfail scissor=off"
    /// The named settings that make this row family what it is, on top of the class's defaults, when
    /// several families share a class ("method=vsm", "filter=poisson", "map=plain"): its `settings=default`
    /// row is the class's defaults with these.
    std::string identity;
    bool default_row = true;  ///< false: no `settings=default` row (a study of settings, not a technique)
    std::function<bool(const Scene&)> applies;  ///< the scenes it is swept on (empty: every scene)
    /// Rows that differ between the scenes it applies to (the light's type, the scene): when set, used
    /// instead of sweep / quick.
    std::function<std::vector<std::string>(const Scene&, bool quick)> sweep_for;
    /// The rows on the scanned-mesh scenes (bunny, dragon, ...: is_scanned_scene), the report's time budget:
    /// the class's default settings first (the only row with --quick), then the one or two settings that
    /// matter there. Used instead of sweep / quick / sweep_for on those scenes; empty: those as elsewhere.
    /// `applies` sees a scanned-mesh scene as a mesh scene (named "mesh:<name>", like --mesh scenes).
    std::vector<std::string> mesh_sweep;
    /// After the timed frames and the read-back: work counters, gpu_bytes, debug images (ctx.debug_images).
    std::function<bool(T&, const S&, const app::View&, const RunContext&, RunResult&)> measure;
    /// The class's failure after update() ("" when fine), for classes that report one.
    std::function<std::string(const T&)> error;
    /// The matrices of the map(s) V read this frame (world -> clip; cascades: one per cascade, near to
    /// far), for the light sweep's texel at each pixel; empty: the sweep uses the scene's frustum.
    std::function<std::vector<glm::mat4>(const T&)> light_matrices;
    /// > 0: a slow row times fewer frames: after the warm-up (at least two frames; one slower than 100 ms
    /// ends it) the timed frames stay within about this many ms, never fewer than 3 (llvmpipe: the median
    /// of a few long frames is stable, and the full report keeps its run time).
    double frame_budget_ms = 0.0;
    /// The temporal rows' sequence, for a family that measures more than V per frame (the
    /// cached shadow map: texels re-rendered, time against a full re-render, the maps compared); unset:
    /// init once, then update, render and read back V per frame.
    std::function<SequenceResult(const RunContext&, const S&, const std::vector<TemporalFrame>&)> sequence;
};

template <class T, class S>
class ReportTechnique final : public Technique {
public:
    explicit ReportTechnique(ReportSpec<T, S> spec) : spec_(std::move(spec)) {}
    std::string name() const override { return spec_.name; }
    std::string description() const override { return spec_.description; }
    bool hard() const override { return spec_.hard; }
    /// The rows on `scene`: the sweep's, and the class's defaults (what a user gets with no tuning) marked
    /// `settings=default`: on the sweep's row that has exactly the default settings, or a row of its own
    /// first when none has.
    std::vector<ParamSet> sweep(const Scene& scene, bool quick) const override {
        std::vector<ParamSet> out;
        const bool scanned = is_scanned_scene(scene.name);
        if (spec_.applies && !spec_.applies(scene)) {
            if (!scanned) return out;
            Scene alias = scene;  // the families' rules name mesh scenes by the prefix "mesh:"
            alias.name = "mesh:" + scene.name;
            if (!spec_.applies(alias)) return out;
        }
        std::vector<std::string> rows;
        if (scanned && !spec_.mesh_sweep.empty())
            rows = quick ? std::vector<std::string>{spec_.mesh_sweep.front()} : spec_.mesh_sweep;
        else
            rows = spec_.sweep_for ? spec_.sweep_for(scene, quick) : quick ? spec_.quick : spec_.sweep;
        for (const auto& text : rows) out.push_back(ParamSet::parse_named(text));
        if (!spec_.default_row) return out;
        const ParamSet identity = ParamSet::parse_named(spec_.identity);
        S d;
        if (!set_named(identity, d).empty()) return out;
        const std::string defaults = settings_label(d);
        bool marked = false;
        for (ParamSet& ps : out) {
            S s;
            if (!set_named(ps, s).empty() || settings_label(s) != defaults) continue;
            ps.named.emplace_back("settings", "default");
            marked = true;
            break;
        }
        if (!marked) out.insert(out.begin(), ParamSet::parse_named(spec_.identity + (spec_.identity.empty() ? "" : " ") + "settings=default"));
        return out;
    }
    RunResult run(const RunContext& ctx, const ParamSet& params) override {
        S s;
        std::string why = set_named(params, s);
        if (!why.empty()) return RunResult::failure(why);
        const app::View view =
            ctx.fit_camera ? app::make_view(ctx.scene, ctx.gpu, *ctx.fit_camera) : app::make_view(ctx.scene, ctx.gpu);
        T t;
        RunResult r;
        const auto t0 = std::chrono::steady_clock::now();
        const bool ok = t.init(view, why);
        const double init_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        if (!ok) return RunResult::failure(why);
        std::vector<double> cpu;
        for (int i = 0; i < std::max(ctx.frames, 1); ++i) {
            const auto c0 = std::chrono::steady_clock::now();
            t.update(view, s);
            cpu.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - c0).count());
            if (spec_.error && !spec_.error(t).empty()) return RunResult::failure(spec_.error(t));
        }
        std::nth_element(cpu.begin(), cpu.begin() + static_cast<std::ptrdiff_t>(cpu.size() / 2), cpu.end());
        r.cpu_ms = cpu[cpu.size() / 2];
        int warmup = ctx.warmup, frames = ctx.frames;
        if (spec_.frame_budget_ms > 0.0) {
            double last = 0.0;
            for (int i = 0; i < std::max(ctx.warmup, 2); ++i) {
                const auto w0 = std::chrono::steady_clock::now();
                t.render(view, s);
                glFinish();
                last = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - w0).count();
                if (i >= 1 && last > 100.0) break;
            }
            warmup = 0;
            if (frames > 3 && last > 0.0) frames = std::clamp(static_cast<int>(spec_.frame_budget_ms / last), 3, frames);
        }
        r.gpu_ms = skgl::median_frame_ms([&] { t.render(view, s); }, warmup, frames);
        r.frames = frames;
        r.visibility = read_r32f(t.visibility(), view.width, view.height);
        if (spec_.measure && !spec_.measure(t, s, view, ctx, r)) return r;
        r.work.emplace_back("init_ms", init_ms);
        const std::string err = skgl::gl_error_string();
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        if (!err.empty()) return RunResult::failure(spec_.name + ": " + err);
        return r;
    }

    bool honors_fit_camera() const override { return true; }  // the View's camera is RunContext::fit_camera
    SequenceResult run_sequence(const RunContext& ctx, const ParamSet& params, const std::vector<TemporalFrame>& frames) override {
        S s;
        std::string why = set_named(params, s);
        if (!why.empty()) return SequenceResult::failure(why);
        if (frames.empty()) return SequenceResult{};
        if (spec_.sequence) return spec_.sequence(ctx, s, frames);
        Scene scene = ctx.scene;  // its light turns with the frames
        scene.light = frames[0].light;
        T t;
        if (!t.init(app::make_view(scene, ctx.gpu, frames[0].camera), why)) return SequenceResult::failure(why);
        SequenceResult out;
        for (const TemporalFrame& f : frames) {
            scene.light = f.light;
            const app::View view = app::make_view(scene, ctx.gpu, f.camera);
            t.update(view, s);
            if (spec_.error && !spec_.error(t).empty()) return SequenceResult::failure(spec_.error(t));
            t.render(view, s);
            out.visibility.push_back(read_r32f(t.visibility(), view.width, view.height));
            if (spec_.light_matrices) out.light_matrices.push_back(spec_.light_matrices(t));
        }
        const std::string err = skgl::gl_error_string();
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        if (!err.empty()) return SequenceResult::failure(spec_.name + ": " + err);
        return out;
    }

private:
    /// The sweep entry's named settings into s, through the same app::Params bindings as the sample's
    /// --param (the technique header's names): "" or what is wrong.
    /// `settings=default` names the class's defaults: it sets nothing.
    std::string set_named(const ParamSet& params, S& s) const {
        app::Params bindings;
        bind_settings(bindings, s);
        if (!params.values.empty()) return spec_.name + " takes named settings (name=value words)";
        std::string why;
        for (const auto& [k, v] : params.named) {
            if (k == "settings" && v == "default") continue;
            if (!bindings.set(k, v, why)) return why;
        }
        return "";
    }
    /// Every bound setting of s as text ("size=2048 hardware_pcf=on ..."): equal labels, equal settings.
    static std::string settings_label(S s) {
        app::Params bindings;
        bind_settings(bindings, s);
        return bindings.label();
    }

    ReportSpec<T, S> spec_;
};

namespace detail {
template <class T, class = void>
struct has_error : std::false_type {};
template <class T>
struct has_error<T, std::void_t<decltype(std::string(std::declval<const T&>().error()))>> : std::true_type {};
}  // namespace detail

/// Adds `spec` to the registry as a ReportTechnique<T, S>. A spec without `error` reads the class's
/// own error() when T has one (every sample class but ShadowMap).
template <class T, class S>
void add_technique(std::vector<std::unique_ptr<Technique>>& out, ReportSpec<T, S> spec) {
    if constexpr (detail::has_error<T>::value)
        if (!spec.error) spec.error = [](const T& t) { return std::string(t.error()); };
    out.push_back(std::make_unique<ReportTechnique<T, S>>(std::move(spec)));
}

}  // namespace sk
