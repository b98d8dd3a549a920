// samples/report/techniques/silhouette_maps.cpp - "silhouette_map" and "silmap_plain" in the report: the
// sample's SilhouetteMap class (samples/silhouette_maps/) with timing, work counters and sweeps
// (report_technique.hpp). Swept on the scenes with straight-edged casters under a spot light: stack,
// fence, duel (the class needs a perspective light frustum).
//
// Sweep: size N = 256 / 512 / 1024 (quick: 512); silmap_plain is the class with map=plain, the plain
// 2x2-PCF shadow map of side round(sqrt(2) N): the same memory, so rows of equal `size` compare at equal
// memory.
// Work, from what the class exposes after the timed frames: shadow_map_texels (the depth map),
// silhouette_edges (projected this frame), silhouette_texels (texels holding a silhouette point, read
// back from the silhouette map), triangles_drawn (the casters, once); quality: failure_texels (texels
// two silhouette edges cross: accumulated weight above kSilmapFailureWeight) and failure_fraction
// (of the silhouette texels). gpu_bytes: N^2 x kSilmapBytesPerTexel (plain: side^2 x 4).
#include "report_technique.hpp"
#include "silhouette_maps.hpp"

namespace sk {

namespace {

bool silmap_scene(const Scene& s) { return s.name == "stack" || s.name == "fence" || s.name == "duel"; }

bool measure(SilhouetteMap& sm, const SilhouetteMapSettings& s, const app::View& v, const RunContext&, RunResult& r) {
    const double side = sm.map_side(), texels = side * side;
    if (s.map == SilhouetteMapSettings::Map::Plain) {
        r.gpu_bytes = static_cast<std::int64_t>(texels * 4.0);
        r.work = {{"shadow_map_texels", texels}, {"triangles_drawn", double(v.gpu->caster_triangles)}};
        return true;
    }
    r.gpu_bytes = static_cast<std::int64_t>(texels) * shadowkit::kSilmapBytesPerTexel;
    // texels with a silhouette point, and failure texels (two silhouette curves in one texel), from the GPU map
    const std::vector<float> map = skgl::read_color_float(sm.silhouette_target(), 0, 4);
    std::size_t fail = 0, written = 0;
    for (std::size_t k = 0; k < map.size() / 4; ++k) {
        const float w = map[4 * k + 3] * 255.f;
        if (w > 0.5f) ++written;
        if (w > 2.5f) ++fail;
    }
    r.work = {{"shadow_map_texels", texels},
              {"silhouette_edges", double(sm.edge_count())},
              {"silhouette_texels", double(written)},
              {"triangles_drawn", double(v.gpu->caster_triangles)}};
    r.quality = {{"failure_texels", double(fail)}, {"failure_fraction", written ? double(fail) / double(written) : 0.0}};
    return true;
}

}  // namespace

void add_silmap_techniques(std::vector<std::unique_ptr<Technique>>& out) {
    using Spec = ReportSpec<SilhouetteMap, SilhouetteMapSettings>;
    Spec sil;
    sil.name = "silhouette_map";
    sil.description = "shadow silhouette map (Sen et al. 2003): N^2 depth + N^2 RGBA8 silhouette points, "
                      "multi-edge texels fall back to the plain map";
    sil.applies = silmap_scene;
    sil.sweep = {"size=256", "size=512", "size=1024"};
    sil.quick = {"size=512"};
    sil.measure = measure;
    Spec plain = sil;
    plain.name = "silmap_plain";
    plain.description = "plain 2x2-PCF shadow map with the memory of silhouette_map at the same size (side sqrt(2) N)";
    plain.sweep = {"map=plain size=256", "map=plain size=512", "map=plain size=1024"};
    plain.quick = {"map=plain size=512"};
    plain.identity = "map=plain";
    add_technique(out, std::move(sil));
    add_technique(out, std::move(plain));
}

}  // namespace sk
