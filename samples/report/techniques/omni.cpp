// samples/report/techniques/omni.cpp - "cube_sm" and "dual_paraboloid" in the report: the samples'
// OmniShadows (samples/omni_shadows/) and DualParaboloid (samples/dual_paraboloid/) classes with
// timing, work counters and sweeps (report_technique.hpp), on the scenes with a point light.
//
// Sweeps, translated entry by entry from the old drivers: cube_sm size 256 / 512 / 1024 x culling
// off / on (quick: 512); dual_paraboloid size 443 / 887 / 1774 (the cube's texel counts at sqrt(3)
// times the face) x tess 0 / 4 / 1 (quick: 887 with tess 0 and 1). The lookups (cube_sm lookup=manual
// / pcf, dual_paraboloid pcf=1) are settings the GL tests run, not swept.
// Work, from what the classes expose: cube_sm shadow_map_texels (six faces), draws_<face> (the casters
// drawn into each face: face_meshes()), draws, draws_saved (6 x casters - draws), triangles_drawn;
// dual_paraboloid shadow_map_texels (two layers), draws and triangles_drawn (the tessellated casters,
// both layers), tess_max_n (the finest subdivision), tess_ms (DualParaboloid::tessellate timed here:
// it runs when the light moves, not every frame). gpu_bytes: the maps (4 bytes a texel).
// Quality (dual_paraboloid): edge_error_bound_texels, the largest omni_paraboloid_edge_error of the
// scene's caster edges cut tess_max_n times: how far the drawn chords can be off the curves.
#include <shadowkit/omni_shadow.hpp>

#include <algorithm>
#include <chrono>

#include "dual_paraboloid.hpp"
#include "omni_shadows.hpp"
#include "report_technique.hpp"

namespace sk {

namespace {

bool point_light(const Scene& s) { return s.light.type == LightType::Point; }

bool measure_cube(OmniShadows& o, const OmniShadowSettings&, const app::View& v, const RunContext&, RunResult& r) {
    const double texels = 6.0 * double(o.size()) * double(o.size());
    static const char* kFace[6] = {"+x", "-x", "+y", "-y", "+z", "-z"};
    r.gpu_bytes = static_cast<std::int64_t>(texels * 4.0);
    r.work.push_back({"shadow_map_texels", texels});
    double triangles = 0.0, draws = 0.0;
    for (int f = 0; f < 6; ++f) {
        for (std::uint32_t m : o.face_meshes(f)) triangles += double(v.scene->meshes[m].indices.size() / 3);
        draws += double(o.face_meshes(f).size());
        r.work.push_back({std::string("draws_") + kFace[f], double(o.face_meshes(f).size())});
    }
    r.work.push_back({"draws", draws});
    r.work.push_back({"draws_saved", 6.0 * double(o.caster_count()) - draws});
    r.work.push_back({"triangles_drawn", triangles});
    return true;
}

bool measure_paraboloid(DualParaboloid& dp, const DualParaboloidSettings& s, const app::View& v, const RunContext&,
                        RunResult& r) {
    const auto t0 = std::chrono::steady_clock::now();
    dp.tessellate(v, s);
    const double tess_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    const double texels = 2.0 * double(dp.size()) * double(dp.size());
    r.gpu_bytes = static_cast<std::int64_t>(texels * 4.0);
    r.work = {{"shadow_map_texels", texels},
              {"draws", 2.0 * double(dp.draws())},
              {"triangles_drawn", 2.0 * double(dp.triangles())},
              {"tess_max_n", double(dp.subdivision())},
              {"tess_ms", tess_ms}};
    // the bound for the scene's own edges cut max_n times: how far off the drawn chords can be
    double worst = 0.0;
    const glm::vec3 light = v.light().position;
    for (const Mesh& m : v.scene->meshes) {
        if (!m.caster) continue;
        for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
            const glm::vec3 a = m.positions[m.indices[t]], b = m.positions[m.indices[t + 1]], c = m.positions[m.indices[t + 2]];
            const float longest = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)}) / float(dp.subdivision());
            const auto e = shadowkit::omni_paraboloid_edge_error(longest, DualParaboloid::distance_to_triangle(light, a, b, c),
                                                                 static_cast<std::uint32_t>(dp.size()), DualParaboloid::max_radius());
            if (e.status == shadowkit::Status::Ok) worst = std::max(worst, double(e.texels));
        }
    }
    r.quality.push_back({"edge_error_bound_texels", worst});
    return true;
}

}  // namespace

void add_omni_techniques(std::vector<std::unique_ptr<Technique>>& out) {
    ReportSpec<OmniShadows, OmniShadowSettings> cube;
    cube.name = "cube_sm";
    cube.description = "point-light cube shadow map, linear distance, receiver bias, per-face caster culling (omni_shadow)";
    cube.applies = point_light;
    for (const char* size : {"256", "512", "1024"})
        for (const char* culling : {"off", "on"}) cube.sweep.push_back(std::string("size=") + size + " culling=" + culling);
    cube.quick = {"size=512 culling=off", "size=512 culling=on"};
    cube.measure = measure_cube;
    add_technique(out, std::move(cube));

    ReportSpec<DualParaboloid, DualParaboloidSettings> dp;
    dp.name = "dual_paraboloid";
    dp.description = "point-light dual-paraboloid shadow map (Brabec 2002), casters tessellated to tess texels of curve error";
    dp.applies = point_light;
    for (const char* size : {"443", "887", "1774"})
        for (const char* tess : {"0", "4", "1"}) dp.sweep.push_back(std::string("size=") + size + " tess=" + tess);
    dp.quick = {"size=887 tess=0", "size=887 tess=1"};
    dp.measure = measure_paraboloid;
    add_technique(out, std::move(dp));
}

}  // namespace sk
