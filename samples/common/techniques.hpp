// Technique drivers: each composes public headers and GLSL snippets the way a user would and
// renders the visibility factor V in [0,1] per camera pixel into a float target, evaluated at the
// camera G-buffer's surface points (the same points the ray-traced reference uses).
// Shared by the report tool, the samples and the GL tests. Internal (not a public header).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "gl_harness.hpp"
#include "reference.hpp"
#include "scene.hpp"

namespace sk {

struct ParamSet {
    std::vector<std::pair<std::string, double>> values;
    double get(const std::string& name, double fallback) const;
    std::string label() const;  // "size=1024 taps=16"
};

// Scene geometry on the GPU plus the camera G-buffer.
struct SceneGpu {
    std::vector<skgl::GpuMesh> meshes;  // same order as Scene::meshes
    std::vector<bool> caster;
    std::size_t caster_triangles = 0;
    int width = 0, height = 0;
    glm::mat4 view{1.f}, proj{1.f};
    skgl::Target gbuffer;  // colour 0: RGBA32F position + kind, 1: RGBA32F normal; DEPTH32F_STENCIL8
    ~SceneGpu();
};

// Uploads the scene and renders the camera G-buffer; `cpu` receives the read-back copy.
bool prepare_scene_gpu(const Scene& scene, int width, int height, SceneGpu& gpu, GBuffer& cpu, std::string& why);

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
    bool debug_images = false;         // the samples ask for RunResult::debug (never the report)
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
    // Parameters a viewer may change live besides the swept ones, with their defaults (e.g. the
    // light size of PCSS or penumbra wedges, which the report keeps at the scene's light).
    virtual std::vector<std::pair<std::string, double>> live_params() const { return {}; }
    // Parameter sweep for the report; `quick` gives a shorter one.
    virtual std::vector<ParamSet> sweep(const Scene& scene, bool quick) const = 0;
    virtual RunResult run(const RunContext& ctx, const ParamSet& params) = 0;
};

std::vector<std::unique_ptr<Technique>> make_techniques();

// Light frustum used by shadow-map drivers for spot, area (from their centre) and sphere lights:
// a perspective looking along the light direction (or at the scene for sphere lights) whose
// near/far hug the scene bounds. Directional: an orthographic fit to the scene bounds.
struct LightMatrices {
    glm::mat4 view{1.f}, proj{1.f};
    float znear = 0.f, zfar = 0.f;
    bool perspective = true;
};
LightMatrices fit_light(const Scene& scene);

// Runs a full-screen pass that reads the G-buffer (sampler2D at unit 0: position+kind,
// unit 1: normal) and writes V to an R32F target. `body` is GLSL that defines
// `float technique_visibility(vec3 p, vec3 n)`; common light rules (facing, spot cone,
// one-sided emitters) are applied around it identically to the reference.
std::string visibility_fragment_shader(const std::string& snippets, const std::string& body);
std::string fullscreen_vertex_shader();

// Reads glsl/<name>.glsl from the source tree (snippets are copy-pasted by users; the drivers
// read the same files at run time).
std::string load_snippet(const std::string& name, std::string& why);

}  // namespace sk
