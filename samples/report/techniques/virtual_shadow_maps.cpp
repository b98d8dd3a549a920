// samples/report/techniques/virtual_shadow_maps.cpp - "virtual_sm" in the report: the sample's
// VirtualShadowMaps class (samples/virtual_shadow_maps/) with timing, work counters and sweeps
// (report_technique.hpp).
//
// Rows: scenes with a sun. The class's defaults (128-texel pages, 16k virtual texels per level, 16
// levels, a pool of 1024 pages = 64 MiB, lod_bias -2: texels no larger than a quarter of the pixel's
// footprint), then pools of 256 pages (16 MiB: the memory of 4 cascades of 1024^2) and 64 pages (4 MiB:
// too small, coarser pages), lod_bias -1 and 0 (a quarter and a sixteenth of the pages), pcf_radius=1
// and 64-texel pages.
// Still rows: every timed frame marks, plans and looks up; the first renders the requested pages into
// an empty pool, the others find them resident (a static scene and camera: 0 pages rendered), so the
// GPU ms is the steady frame (marking, the bitmask's read-back, the plan, the lookup).
// Work, from what the class exposes: pages_requested, pages_rendered_first_frame (a cold pool),
// pages_rendered (the last frame: 0 when nothing moved), pages_resident, pages_fallback (requests on
// a coarser level: the pool was too small), triangles_drawn_first_frame; gpu_bytes: the physical pool
// (float32 texels). Quality: the aliasing of the warped maps (screen pixels per shadow texel: mean,
// max, undersampled_fraction with > 1) with the level each pixel's lookup reads (the CPU walks the
// page table as the shader does).
// Temporal rows (sequence below): pages_rendered_mean (frames after the first), rerendered_fraction
// (pages rendered / resident pages, mean), pages_evicted_mean.
#include <shadowkit/perspective_shadow_maps.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "report_technique.hpp"
#include "virtual_shadow_maps.hpp"

namespace sk {

namespace {

// The level the lookup reads at world point p (sk_vsm_level_for_footprint, then up the table to the
// first current page holding p); -1 for none.
int lookup_level(const shadowkit::VsmState& st, const glm::dvec3& p, double footprint, float lod_bias) {
    const double texel0 = st.layout.level0_extent_world / double(st.layout.virtual_texels);
    const double l = std::floor(std::log2(footprint / texel0) + double(lod_bias));
    const int n = st.pages_per_side;
    for (int k = int(std::clamp(l, 0.0, double(st.layout.level_count - 1))); k < st.layout.level_count; ++k) {
        const glm::dvec4 h = st.levels[k].world_to_uv * glm::dvec4(p, 1.0);
        const double u = h.x / h.w, v = h.y / h.w;
        if (!(u >= 0.0 && v >= 0.0 && u < 1.0 && v < 1.0)) continue;
        const std::size_t e = shadowkit::vsm_table_index(st, std::uint32_t(k), std::uint32_t(u * n), std::uint32_t(v * n));
        if (st.page_table[e] & shadowkit::kVsmPageValid) return k;
    }
    return -1;
}

// Aliasing over the receiver pixels facing the sun: screen pixels per shadow texel of the level read.
void add_vsm_aliasing(RunResult& r, const VirtualShadowMaps& m, const VirtualShadowMapSettings& s, const app::View& v,
                      const GBuffer& g) {
    const shadowkit::VsmState& st = m.state();
    if (!st.has_light) return;
    std::vector<glm::mat4> level_vp;  // the whole window of each level, world -> clip
    glm::dmat4 to_clip(2.0);
    to_clip[3] = glm::dvec4(-1.0, -1.0, 0.0, 1.0);
    to_clip[2][2] = 1.0;
    for (int k = 0; k < st.layout.level_count; ++k) level_vp.push_back(glm::mat4(to_clip * st.levels[k].world_to_uv));
    const glm::mat4 cam_vp = v.gpu->proj * v.gpu->view;
    const glm::vec3 l = -glm::normalize(v.light().direction);
    const glm::dvec3 eye(v.gpu->camera.eye);
    double sum = 0.0, mx = 0.0;
    std::size_t n = 0, under = 0;
    for (std::size_t k = 0; k < g.kind.size(); ++k) {
        if (g.kind[k] != 1) continue;
        const glm::vec3 p(g.position[3 * k], g.position[3 * k + 1], g.position[3 * k + 2]);
        const glm::vec3 nn(g.normal[3 * k], g.normal[3 * k + 1], g.normal[3 * k + 2]);
        if (glm::dot(nn, l) <= 0.f) continue;
        const int level = lookup_level(st, glm::dvec3(p), glm::length(glm::dvec3(p) - eye) * double(m.pixel_angle()), s.lod_bias);
        if (level < 0) continue;
        const shadowkit::WarpAliasingValue ev = shadowkit::warp_aliasing_error(
            level_vp[std::size_t(level)], cam_vp, p, nn, static_cast<std::uint32_t>(st.layout.virtual_texels),
            glm::uvec2(static_cast<unsigned>(g.width), static_cast<unsigned>(g.height)));
        if (ev.status != shadowkit::Status::Ok) continue;
        sum += ev.value;
        mx = std::max(mx, ev.value);
        under += ev.value > 1.0 ? 1 : 0;
        ++n;
    }
    if (n) {
        r.quality.push_back({"aliasing_mean", sum / double(n)});
        r.quality.push_back({"aliasing_max", mx});
        r.quality.push_back({"undersampled_fraction", double(under) / double(n)});
    }
}

bool measure_vsm(VirtualShadowMaps& m, const VirtualShadowMapSettings& s, const app::View& v, const RunContext& ctx,
                 RunResult& r) {
    const VirtualShadowMapStats& st = m.stats();
    r.gpu_bytes = m.pool_bytes();
    r.work = {{"pages_requested", double(st.requested)},
              {"pages_rendered_first_frame", double(st.first_frame_rendered)},
              {"pages_rendered", double(st.rendered)},
              {"pages_resident", double(st.resident)},
              {"pages_fallback", double(st.fallback)},
              {"triangles_drawn_first_frame", double(st.first_frame_triangles)}};
    if (ctx.gbuffer) add_vsm_aliasing(r, m, s, v, *ctx.gbuffer);
    return true;
}

// The temporal rows: one instance over the frames; pages rendered per frame against the pool's resident pages.
SequenceResult sequence(const RunContext& ctx, const VirtualShadowMapSettings& s, const std::vector<TemporalFrame>& frames) {
    Scene scene = ctx.scene;  // its light turns with the frames
    scene.light = frames[0].light;
    VirtualShadowMaps m;
    std::string why;
    if (!m.init(app::make_view(scene, ctx.gpu, frames[0].camera), why)) return SequenceResult::failure(why);
    SequenceResult out;
    double rendered = 0.0, fraction = 0.0, evicted = 0.0;
    for (std::size_t t = 0; t < frames.size(); ++t) {
        scene.light = frames[t].light;
        const app::View v = app::make_view(scene, ctx.gpu, frames[t].camera);
        m.update(v, s);
        if (!m.error().empty()) return SequenceResult::failure(m.error());
        m.render(v, s);
        out.visibility.push_back(read_r32f(m.visibility(), v.width, v.height));
        if (t == 0) continue;  // the first frame fills the pool
        rendered += double(m.stats().rendered);
        evicted += double(m.stats().evicted);
        fraction += double(m.stats().rendered) / double(std::max<std::size_t>(m.stats().resident, 1));
    }
    const double frames_after = double(std::max<std::size_t>(frames.size(), 2) - 1);
    out.work = {{"pages_rendered_mean", rendered / frames_after},
                {"rerendered_fraction", fraction / frames_after},
                {"pages_evicted_mean", evicted / frames_after}};
    return out;
}

}  // namespace

void add_vsm_techniques(std::vector<std::unique_ptr<Technique>>& out) {
    ReportSpec<VirtualShadowMaps, VirtualShadowMapSettings> vsm;
    vsm.name = "virtual_sm";
    vsm.description = "virtual shadow maps: 16k clipmap levels of 128-texel pages, only the pages visible pixels "
                      "request rendered into a physical pool and kept across frames";
    vsm.applies = [](const Scene& s) { return s.light.type == LightType::Directional; };
    vsm.sweep = {"pool_pages=1024", "pool_pages=256", "pool_pages=64", "lod_bias=-1", "lod_bias=0", "pcf_radius=1", "page_texels=64"};
    vsm.quick = {"pool_pages=1024", "pool_pages=256"};
    vsm.mesh_sweep = {"pool_pages=1024", "pool_pages=256"};
    vsm.measure = measure_vsm;
    vsm.sequence = sequence;
    add_technique(out, std::move(vsm));
}

}  // namespace sk
