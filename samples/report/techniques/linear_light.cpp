// samples/report/techniques/linear_light.cpp - "linear_light" and "sampled_line" in the report: the
// sample's LinearLight class (samples/linear_light/) with timing, work counters and sweeps
// (report_technique.hpp). Swept on the scenes with a linear light (the linear scene).
//
// linear_light (method=heidrich): maps of 512^2, segments 1 / 2 / 4 with the skin built on the CPU,
// and segments=1 skin=gpu (quick: segments 1 and 2). sampled_line (method=sampled): 2 / 4 / 8 / 16
// maps of 512^2 (quick: 2 and 8).
// cpu_ms: update() (the segment and the frusta) plus, for skin=cpu, one build_skins() timed after the
// frames (the read-back and triangulation: inside gpu_ms as well, as render() runs it between its
// GPU passes).
// Work, from what the class exposes: shadow_maps, visibility_maps, skin_vertices_drawn (skin=cpu: the
// skins' vertices, each skin drawn twice; skin=gpu: 6 (size - 1)^2 per skin drawn, 2 per sub-light),
// triangles_drawn (the casters' triangles per map). gpu_bytes: 4 bytes a depth texel, 16 a visibility
// texel.
#include <chrono>

#include "linear_light.hpp"
#include "report_technique.hpp"

namespace sk {

namespace {

bool linear_scene(const Scene& s) { return s.light.type == LightType::Linear; }

bool measure(LinearLight& ll, const LinearLightSettings& s, const app::View& v, const RunContext&, RunResult& r) {
    const double texels = double(ll.map_size()) * double(ll.map_size()), maps = double(ll.map_count());
    if (s.method == LinearLightSettings::Method::Sampled) {
        r.gpu_bytes = static_cast<std::int64_t>(texels * 4.0 * maps);
        r.work = {{"shadow_maps", maps}, {"triangles_drawn", double(v.gpu->caster_triangles) * maps}};
        return true;
    }
    if (s.skin == LinearLightSettings::Skin::Cpu && !ll.point()) {
        const auto t0 = std::chrono::steady_clock::now();
        ll.build_skins(s);
        r.cpu_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    }
    if (!ll.error().empty()) {
        r = RunResult::failure(ll.error());
        return false;
    }
    const double vmaps = double(ll.visibility_map_count());
    const double skin = ll.point() ? 0.0
                        : s.skin == LinearLightSettings::Skin::Gpu
                            ? 6.0 * (ll.map_size() - 1.0) * (ll.map_size() - 1.0) * 2.0 * ll.sub_lights()
                            : 2.0 * double(ll.skin_vertices());
    r.gpu_bytes = static_cast<std::int64_t>(texels * (4.0 * maps + 16.0 * vmaps));
    r.work = {{"shadow_maps", maps},
              {"visibility_maps", vmaps},
              {"skin_vertices_drawn", skin},
              {"triangles_drawn", double(v.gpu->caster_triangles) * maps}};
    return true;
}

}  // namespace

void add_linear_techniques(std::vector<std::unique_ptr<Technique>>& out) {
    using Spec = ReportSpec<LinearLight, LinearLightSettings>;
    Spec lin;
    lin.name = "linear_light";
    lin.description = "linear light (Heidrich et al. 2000): endpoint shadow maps + skin visibility maps; the light split "
                      "into `segments` sub-lights";
    lin.hard = false;
    lin.applies = linear_scene;
    lin.sweep = {"size=512 segments=1", "size=512 segments=2", "size=512 segments=4", "size=512 segments=1 skin=gpu",
                 "size=512 segments=1 bias=heidrich_auto"};
    lin.quick = {"size=512 segments=1", "size=512 segments=2"};
    lin.measure = measure;
    Spec sampled = lin;
    sampled.name = "sampled_line";
    sampled.description = "N shadow maps at the centers of N equal pieces of the line light, 2x2 PCF each, averaged (baseline)";
    sampled.sweep = {"method=sampled size=512 samples=2", "method=sampled size=512 samples=4",
                     "method=sampled size=512 samples=8", "method=sampled size=512 samples=16",
                     "method=sampled size=512 samples=8 bias=offset"};
    sampled.quick = {"method=sampled size=512 samples=2", "method=sampled size=512 samples=8"};
    sampled.identity = "method=sampled";
    add_technique(out, std::move(lin));
    add_technique(out, std::move(sampled));
}

}  // namespace sk
