// samples/report/techniques/shadow_map.cpp - "shadow_map" in the report: the sample's ShadowMap class
// (samples/shadow_map/) with timing, work counters and sweeps (report_technique.hpp).
// Work, from what the class exposes: shadow_map_texels (size^2, six faces for a point light's cube
// map), triangles_drawn and casters_drawn (every caster, per face), casters_culled (0: no culling);
// gpu_bytes: the depth map (4 bytes a texel).
#include "report_technique.hpp"
#include "shadow_map.hpp"

namespace sk {

void add_shadow_map_techniques(std::vector<std::unique_ptr<Technique>>& out) {
    ReportSpec<ShadowMap, ShadowMapSettings> spec;
    spec.light_matrices = [](const ShadowMap& m) { return std::vector<glm::mat4>{m.light_view_proj()}; };
    spec.name = "shadow_map";
    spec.description = "plain shadow map, 2x2 PCF; bias=auto (default: each texel compared with the receiver plane, nothing to tune) or polygon_offset (slope-scaled glPolygonOffset(2, 2))";
    spec.sweep = {"size=512", "size=1024", "size=2048", "size=4096", "size=2048 fit_casters=off", "size=2048 bias=polygon_offset fit_casters=off", "size=2048 contact=on"};
    spec.quick = {"size=512", "size=2048", "size=2048 bias=polygon_offset fit_casters=off", "size=2048 contact=on"};
    spec.mesh_sweep = {"size=2048", "size=2048 bias=polygon_offset fit_casters=off", "size=2048 contact=on"};  // scanned meshes
    spec.measure = [](ShadowMap& sm, const ShadowMapSettings&, const app::View& v, const RunContext&, RunResult& r) {
        const double faces = sm.cube() ? 6.0 : 1.0, texels = double(sm.size()) * double(sm.size());
        std::size_t casters = 0;
        for (bool c : v.gpu->caster) casters += c ? 1 : 0;
        r.gpu_bytes = static_cast<std::int64_t>(faces * texels * 4.0);
        r.work = {{"shadow_map_texels", faces * texels},
                  {"triangles_drawn", faces * double(v.gpu->caster_triangles)},
                  {"casters_drawn", faces * double(casters)},
                  {"casters_culled", 0.0}};
        return true;
    };
    add_technique(out, std::move(spec));
}

}  // namespace sk
