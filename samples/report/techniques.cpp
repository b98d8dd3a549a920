// samples/report/techniques.cpp - the registry (make_techniques), sweeps' ParamSet, the report's
// G-buffer read-back, and the instrument check `unshadowed`.
#include "techniques.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace sk {

double ParamSet::get(const std::string& name, double fallback) const {
    for (const auto& [k, v] : values)
        if (k == name) return v;
    return fallback;
}

std::string ParamSet::label() const {
    std::ostringstream s;
    bool first = true;
    for (const auto& [k, v] : values) {
        if (!first) s << ' ';
        first = false;
        s << k << '=' << v;
    }
    for (const auto& [k, v] : named) {
        if (!first) s << ' ';
        first = false;
        s << k << '=' << v;
    }
    return s.str();
}

ParamSet ParamSet::parse_named(const std::string& text) {
    ParamSet p;
    std::istringstream in(text);
    std::string word;
    while (in >> word) {
        const auto eq = word.find('=');
        if (eq == std::string::npos) p.named.emplace_back(word, "");
        else p.named.emplace_back(word.substr(0, eq), word.substr(eq + 1));
    }
    return p;
}

DebugImage grey_debug_image(const std::string& name, int w, int h, const std::vector<float>& data, int stride, int c,
                            float ignore_above) {
    DebugImage d;
    d.name = name;
    d.width = w;
    d.height = h;
    const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
    float lo = INFINITY, hi = -INFINITY;
    for (std::size_t k = 0; k < n; ++k) {
        const float v = data[k * static_cast<std::size_t>(stride) + static_cast<std::size_t>(c)];
        if (std::isfinite(v) && v < ignore_above) {
            lo = std::min(lo, v);
            hi = std::max(hi, v);
        }
    }
    d.rgb.assign(n * 3, 255);
    for (std::size_t k = 0; k < n; ++k) {
        const float v = data[k * static_cast<std::size_t>(stride) + static_cast<std::size_t>(c)];
        if (!std::isfinite(v) || v >= ignore_above || !(hi > lo)) continue;
        const auto g = static_cast<std::uint8_t>(std::lround(255.0 * (v - lo) / (hi - lo)));
        d.rgb[3 * k] = d.rgb[3 * k + 1] = d.rgb[3 * k + 2] = g;
    }
    return d;
}

void read_gbuffer(const SceneGpu& gpu, GBuffer& cpu) {
    const auto pos = skgl::read_color_float(gpu.gbuffer, 0, 4);
    const auto nrm = skgl::read_color_float(gpu.gbuffer, 1, 4);
    const std::size_t n = static_cast<std::size_t>(gpu.width) * static_cast<std::size_t>(gpu.height);
    cpu.width = gpu.width;
    cpu.height = gpu.height;
    cpu.position.resize(3 * n);
    cpu.normal.resize(3 * n);
    cpu.kind.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
        for (std::size_t c = 0; c < 3; ++c) {
            cpu.position[3 * k + c] = pos[4 * k + c];
            cpu.normal[3 * k + c] = nrm[4 * k + c];
        }
        cpu.kind[k] = static_cast<std::uint8_t>(std::lround(pos[4 * k + 3]));
    }
}

bool prepare_scene_gpu(const Scene& scene, int width, int height, SceneGpu& gpu, GBuffer& cpu, std::string& why) {
    app::upload_scene(scene, gpu);
    if (!app::render_gbuffer(scene, scene.camera, width, height, gpu, why)) return false;
    read_gbuffer(gpu, cpu);
    const std::string err = skgl::gl_error_string();
    if (!err.empty()) {
        why = "G-buffer read-back: " + err;
        return false;
    }
    return true;
}

namespace {

// --------------------------------------------------------------------------- unshadowed (V = 1)
// A deliberately wrong technique: proves that the instrument gives a large error when it should.
class Unshadowed final : public Technique {
public:
    std::string name() const override { return "unshadowed"; }
    std::string description() const override { return "V = 1 wherever the light's rules allow (no shadows): instrument check"; }
    bool hard() const override { return true; }
    bool listed_by_default() const override { return false; }
    std::vector<ParamSet> sweep(const Scene&, bool) const override { return {ParamSet{}}; }
    RunResult run(const RunContext& ctx, const ParamSet&) override {
        RunResult r;
        std::string why;
        VisibilityPass pass;
        if (!pass.init(ctx.gpu.width, ctx.gpu.height, why)) return RunResult::failure(why);
        std::string log;
        GLuint prog = compile_visibility_program("", "float technique_visibility(vec3 p, vec3 n) { return 1.0; }", log);
        if (!prog) return RunResult::failure(log);
        glUseProgram(prog);
        set_light_uniforms(prog, ctx.scene.light);
        r.gpu_ms = skgl::median_frame_ms([&] { pass.draw(prog, ctx.gpu); }, ctx.warmup, ctx.frames);
        r.frames = ctx.frames;
        r.visibility = skgl::read_color_float(pass.target, 0, 1);
        glDeleteProgram(prog);
        return r;
    }
};

}  // namespace

std::vector<std::unique_ptr<Technique>> make_techniques() {
    std::vector<std::unique_ptr<Technique>> t;
    // each family's techniques, marked with the family's id (report.json's "family", index.html's filters)
    auto add = [&t](const char* family, void (*add_family)(std::vector<std::unique_ptr<Technique>>&)) {
        const std::size_t first = t.size();
        add_family(t);
        for (std::size_t i = first; i < t.size(); ++i) t[i]->set_family(family);
    };
    add("shadow_map", add_shadow_map_techniques);
    add("warp", add_warp_techniques);
    add("soft", add_soft_techniques);
    add("volume", add_volume_techniques);
    add("smoothie", add_smoothie_techniques);
    add("wedge", add_wedge_techniques);
    add("omni", add_omni_techniques);
    add("silmap", add_silmap_techniques);
    add("linear", add_linear_techniques);
    add("prefilter", add_prefilter_techniques);
    add("cache", add_cached_shadow_map_techniques);
    add("vsm", add_vsm_techniques);
    t.push_back(std::make_unique<Unshadowed>());
    t.back()->set_family("check");
    return t;
}

}  // namespace sk
