// samples/report/techniques.hpp - the report's technique registry (report-only code).
//
// Every technique the report scores is a `Technique`: a name, a sweep of settings and run(), which
// renders V at the camera G-buffer's points (the same points the ray-traced reference uses), times it
// and counts its work: the SAME technique classes the samples show (samples/<technique>/), wrapped by
// ReportTechnique (report_technique.hpp; one file per family in samples/report/techniques/), their
// settings named (`method=zfail scissor=on`), and the instrument check `unshadowed` (techniques.cpp).
// The GL tests reach them through make_techniques().
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "gbuffer.hpp"
#include "gl.hpp"
#include "reference.hpp"
#include "scene.hpp"

namespace sk {

// The app shell's names, unqualified.
using app::compile_visibility_program;
using app::fullscreen_vertex_shader;
using app::load_snippet;
using app::SceneGpu;
using app::set_light_uniforms;
using app::visibility_fragment_shader;
using app::VisibilityPass;

// One entry of a technique's sweep: named settings (`named`, ported techniques: the words of the
// technique's app::Params bindings, e.g. method=zfail scissor=on) or numbers (`values`, the old drivers).
struct ParamSet {
    ParamSet(std::vector<std::pair<std::string, double>> v = {}) : values(std::move(v)) {}  // NOLINT: ParamSet{{{"size", 512}}}
    std::vector<std::pair<std::string, double>> values;
    std::vector<std::pair<std::string, std::string>> named;
    double get(const std::string& name, double fallback) const;  // values only
    std::string label() const;  // "size=1024 taps=16", "method=zfail scissor=on"
    // "method=zfail scissor=on" -> named {{method, zfail}, {scissor, on}} (words split at spaces).
    static ParamSet parse_named(const std::string& text);
};

// Uploads the scene and renders the camera G-buffer (app::upload_scene + app::render_gbuffer with the
// scene's camera); `cpu` receives the read-back copy the reference and the metrics use.
bool prepare_scene_gpu(const Scene& scene, int width, int height, SceneGpu& gpu, GBuffer& cpu, std::string& why);
// The read-back copy of gpu's G-buffer.
void read_gbuffer(const SceneGpu& gpu, GBuffer& cpu);

// An extra image a technique can show in the samples (shadow map, smoothie buffer, texel density):
// 8-bit RGB, bottom-up rows.
struct DebugImage {
    std::string name;
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgb;
};

struct RunResult {
    bool ok = true;
    std::string error;
    std::vector<float> visibility;  // width * height, bottom-up rows
    double gpu_ms = 0.0;            // median GPU-pass time (glFinish + steady clock on llvmpipe)
    double cpu_ms = 0.0;            // median CPU time of the technique's own CPU work
    int frames = 0;
    std::int64_t gpu_bytes = 0;     // the technique's GPU buffers (shadow maps, vertex buffers)
    std::vector<std::pair<std::string, double>> work;  // texels, triangles drawn, casters culled...
    std::vector<std::pair<std::string, double>> quality;  // technique-specific quality metrics (aliasing...)
    std::vector<DebugImage> debug;  // filled only when RunContext::debug_images
    static RunResult failure(std::string why) {
        RunResult r;
        r.ok = false;
        r.error = std::move(why);
        return r;
    }
};

struct RunContext {
    const Scene& scene;
    const SceneGpu& gpu;
    int frames = 20;
    int warmup = 3;
    const GBuffer* gbuffer = nullptr;  // CPU copy of the G-buffer, for CPU-side metrics
    bool debug_images = false;         // the GL tests ask for RunResult::debug (never the report)
    // The camera techniques fit to (shadow-map fitting, warping, cascades) when it is not the G-buffer's
    // (the temporal rows: V is still evaluated at the G-buffer's points). Ported techniques get
    // it as app::View::camera; the old drivers ignore it.
    const Camera* fit_camera = nullptr;
    // run_sequence: also check what the sequence keeps against a full re-render each frame (the cached
    // map's bit-for-bit test of the temporal rows); the light sweep turns it off (only V is scored).
    bool verify_sequence = true;
};

// Shadows over time: one frame of a temporal sequence, the camera the technique fits to
// and the light (V stays at the G-buffer's points), and what a technique renders over the frames.
struct TemporalFrame {
    Camera camera;
    Light light;
};
struct SequenceResult {
    bool ok = true;
    std::string error;
    std::vector<std::vector<float>> visibility;        // per frame: width * height, bottom-up rows
    std::vector<std::pair<std::string, double>> work;  // the sequence's own counters (cached maps: texels re-rendered...)
    // per frame, when the technique says: its maps' world -> clip matrices (ReportSpec::light_matrices)
    std::vector<std::vector<glm::mat4>> light_matrices;
    static SequenceResult failure(std::string why) {
        SequenceResult r;
        r.ok = false;
        r.error = std::move(why);
        return r;
    }
};

// Grey image of a float buffer (w x h, `stride` floats per pixel, channel `c`), mapped from the
// [lo, hi] range of its finite values below `ignore_above` to [0, 255].
DebugImage grey_debug_image(const std::string& name, int w, int h, const std::vector<float>& data, int stride, int c,
                            float ignore_above);

class Technique {
public:
    virtual ~Technique() = default;
    virtual std::string name() const = 0;
    virtual std::string description() const = 0;
    virtual bool hard() const = 0;                 // produces 0/1 visibility
    virtual bool listed_by_default() const { return true; }
    // Parameter sweep for the report; `quick` gives a shorter one.
    virtual std::vector<ParamSet> sweep(const Scene& scene, bool quick) const = 0;
    virtual RunResult run(const RunContext& ctx, const ParamSet& params) = 0;
    // True when run() fits to RunContext::fit_camera (ReportTechnique: the View's camera). A
    // technique that does not (false: the instrument check `unshadowed`) gets no temporal camera paths.
    virtual bool honors_fit_camera() const { return false; }
    // V at the G-buffer's points for each frame in turn (its light, its fit camera). Default
    // (samples/report/temporal.cpp): run() once per frame (frames 1, warmup 0, no CPU G-buffer);
    // ReportTechnique initializes once and updates and renders per frame.
    virtual SequenceResult run_sequence(const RunContext& ctx, const ParamSet& params, const std::vector<TemporalFrame>& frames);
    // The family: the registration function that added it (make_techniques): "shadow_map", "warp", "soft", ...
    const std::string& family() const { return family_; }
    void set_family(std::string family) { family_ = std::move(family); }

private:
    std::string family_;
};

std::vector<std::unique_ptr<Technique>> make_techniques();

// Registration, one function per family, called by make_techniques(): defined in
// samples/report/techniques/<family>.cpp (ReportTechnique around the sample's class).
void add_shadow_map_techniques(std::vector<std::unique_ptr<Technique>>& out);
void add_warp_techniques(std::vector<std::unique_ptr<Technique>>& out);
void add_soft_techniques(std::vector<std::unique_ptr<Technique>>& out);
void add_volume_techniques(std::vector<std::unique_ptr<Technique>>& out);
void add_smoothie_techniques(std::vector<std::unique_ptr<Technique>>& out);
void add_wedge_techniques(std::vector<std::unique_ptr<Technique>>& out);
void add_omni_techniques(std::vector<std::unique_ptr<Technique>>& out);
void add_silmap_techniques(std::vector<std::unique_ptr<Technique>>& out);
void add_linear_techniques(std::vector<std::unique_ptr<Technique>>& out);
void add_prefilter_techniques(std::vector<std::unique_ptr<Technique>>& out);
void add_cached_shadow_map_techniques(std::vector<std::unique_ptr<Technique>>& out);
void add_vsm_techniques(std::vector<std::unique_ptr<Technique>>& out);

}  // namespace sk
