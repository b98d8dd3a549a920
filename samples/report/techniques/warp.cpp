// samples/report/techniques/warp.cpp - "warped_sm" and "cascades" in the report: the samples'
// WarpedShadowMaps (samples/warped_shadow_maps/) and CascadedShadowMaps (samples/cascaded_shadow_maps/)
// classes with timing, work counters, sweeps (report_technique.hpp) and the perspective aliasing metric.
//
// Sweeps, translated entry by entry from the old drivers (method 0..4 = fitted, uniform, psm, lispsm,
// tsm): warped_sm on outdoor, duel and mesh files, every method x size 512 / 1024 / 2048 (quick: 1024);
// cascades on scenes with a sun, size 256 / 512 / 1024 with 4 cascades (quick: 512).
// Work, from what the classes expose: shadow_map_texels, triangles_drawn and casters_drawn (warped_sm:
// the casters drawn(); cascades: every caster into each of count() layers), casters_culled (fitted: the
// casters light_frustum_fit proved unable to shadow the view; 0 otherwise); gpu_bytes: the maps (4 bytes
// a texel). Quality: fallback_uniform (1 when the warp fell back to the uniform fit), and over the lit
// receiver pixels of the G-buffer (ctx.gbuffer) the perspective aliasing warp_aliasing_error (screen
// pixels per texel: aliasing_mean, aliasing_max, undersampled_fraction with > 1), for cascades with
// the cascade the view depth selects (cascade_select_by_depth).
#include <shadowkit/cascades.hpp>
#include <shadowkit/perspective_shadow_maps.hpp>

#include <algorithm>
#include <chrono>
#include <cstring>

#include "cascaded_shadow_maps.hpp"
#include "report_technique.hpp"
#include "warped_shadow_maps.hpp"

namespace sk {

namespace {

// Perspective aliasing over the G-buffer's receiver pixels that face the light: light_vps[which[k]]
// at pixel k (which empty: light_vps[0]; which[k] < 0: not counted).
void add_aliasing(RunResult& r, const Scene& scene, const SceneGpu& gpu, const GBuffer& g,
                  const std::vector<glm::mat4>& light_vps, const std::vector<int>& which, int size) {
    const glm::mat4 cam_vp = gpu.proj * gpu.view;
    double sum = 0.0, mx = 0.0;
    std::size_t n = 0, under = 0;
    for (std::size_t k = 0; k < g.kind.size(); ++k) {
        if (g.kind[k] != 1) continue;
        const glm::vec3 p(g.position[3 * k], g.position[3 * k + 1], g.position[3 * k + 2]);
        const glm::vec3 nn(g.normal[3 * k], g.normal[3 * k + 1], g.normal[3 * k + 2]);
        const glm::vec3 l = scene.light.type == LightType::Directional ? -glm::normalize(scene.light.direction)
                                                                       : glm::normalize(scene.light.position - p);
        if (glm::dot(nn, l) <= 0.f) continue;  // facing away (NaN counts as facing)
        const int c = which.empty() ? 0 : which[k];
        if (c < 0) continue;
        const shadowkit::WarpAliasingValue ev = shadowkit::warp_aliasing_error(
            light_vps[static_cast<std::size_t>(c)], cam_vp, p, nn, static_cast<std::uint32_t>(size),
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

bool measure_warped(WarpedShadowMaps& w, const WarpedShadowMapSettings&, const app::View& v, const RunContext& ctx,
                    RunResult& r) {
    const double texels = double(w.size()) * double(w.size());
    std::size_t casters = 0, drawn = 0, triangles = 0;
    for (std::size_t i = 0; i < v.scene->meshes.size(); ++i) {
        casters += v.gpu->caster[i] ? 1 : 0;
        if (!w.drawn(i)) continue;
        ++drawn;
        triangles += v.scene->meshes[i].indices.size() / 3;
    }
    r.gpu_bytes = static_cast<std::int64_t>(texels * 4.0);
    r.work = {{"shadow_map_texels", texels},
              {"triangles_drawn", double(triangles)},
              {"casters_drawn", double(drawn)},
              {"casters_culled", double(casters - drawn)}};
    if (w.fallback_uniform()) r.quality.push_back({"fallback_uniform", 1.0});
    if (ctx.gbuffer) add_aliasing(r, *v.scene, *v.gpu, *ctx.gbuffer, {w.light_view_proj()}, {}, w.size());
    return true;
}

bool measure_cascades(CascadedShadowMaps& c, const CascadedShadowMapSettings&, const app::View& v,
                      const RunContext& ctx, RunResult& r) {
    const int count = c.count();
    const double texels = double(count) * double(c.size()) * double(c.size());
    std::size_t casters = 0;
    for (bool k : v.gpu->caster) casters += k ? 1 : 0;
    r.gpu_bytes = static_cast<std::int64_t>(texels * 4.0);
    r.work = {{"shadow_map_texels", texels},
              {"triangles_drawn", double(count) * double(v.gpu->caster_triangles)},
              {"casters_drawn", double(count) * double(casters)},
              {"casters_culled", 0.0}};
    if (!ctx.gbuffer) return true;
    // aliasing per pixel with the cascade the lookup selects (by view depth)
    const GBuffer& g = *ctx.gbuffer;
    std::vector<int> which(g.kind.size(), -1);
    for (std::size_t k = 0; k < g.kind.size(); ++k) {
        if (g.kind[k] == 0) continue;
        const glm::vec4 p = v.gpu->view * glm::vec4(g.position[3 * k], g.position[3 * k + 1], g.position[3 * k + 2], 1.f);
        which[k] = shadowkit::cascade_select_by_depth(-p.z, c.splits(), static_cast<std::uint32_t>(count)).index;
    }
    std::vector<glm::mat4> vps;
    for (int i = 0; i < count; ++i) vps.push_back(c.cascade(i).view_proj);
    add_aliasing(r, *v.scene, *v.gpu, g, vps, which, c.size());
    return true;
}

// The temporal rows of cascades (as ReportTechnique's default: update + render per frame, V and the
// matrices), plus what the cache did (frames after the first, which renders every layer whole):
// rerendered_fraction (mean texels re-rendered per frame / the array's texels; cache=off: 1),
// rerendered_max, and with cache=on the plans' actions over cascade-frames (cascade_frames_kept /
// _updated / _scrolled / _rendered) and, when the sequence is verified, texels_differing: array texels
// (all frames) where the cached layers differ bit for bit from a second instance that re-renders every
// layer whole each frame (its cache invalidated); frame_ms: the median of update + render (the layers
// and V, between glFinish calls: llvmpipe runs the GPU work on the CPU) over the frames after the first.
SequenceResult cascades_sequence(const RunContext& ctx, const CascadedShadowMapSettings& s, const std::vector<TemporalFrame>& frames) {
    Scene scene = ctx.scene;  // its light turns with the frames
    scene.light = frames[0].light;
    CascadedShadowMaps c, full;
    std::string why;
    const app::View v0 = app::make_view(scene, ctx.gpu, frames[0].camera);
    const bool verify = s.cache && ctx.verify_sequence;
    if (!c.init(v0, why) || (verify && !full.init(v0, why))) return SequenceResult::failure(why);
    SequenceResult out;
    double actions[4] = {0, 0, 0, 0}, fraction = 0.0, fraction_max = 0.0, differing = 0.0;
    std::vector<float> a, b;
    std::vector<double> ms;
    for (std::size_t t = 0; t < frames.size(); ++t) {
        scene.light = frames[t].light;
        const app::View v = app::make_view(scene, ctx.gpu, frames[t].camera);
        glFinish();
        const auto t0 = std::chrono::steady_clock::now();
        c.update(v, s);
        if (!c.error().empty()) return SequenceResult::failure(c.error());
        c.render(v, s);
        glFinish();
        if (t > 0) ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        out.visibility.push_back(read_r32f(c.visibility(), v.width, v.height));
        std::vector<glm::mat4> mats;
        for (int i = 0; i < c.count(); ++i) mats.push_back(c.cascade(i).view_proj);
        out.light_matrices.push_back(mats);
        const double texels = double(c.count()) * double(c.size()) * double(c.size());
        if (t > 0) {
            const double f = double(c.texels_rerendered()) / texels;
            fraction += f;
            fraction_max = std::max(fraction_max, f);
            for (int i = 0; i < c.count() && c.cache_active(); ++i) actions[static_cast<int>(c.plan(i).action)] += 1.0;
        }
        if (!verify || !c.cache_active()) continue;
        full.invalidate_cache();
        full.update(v, s);
        full.render(v, s);
        a.resize(static_cast<std::size_t>(texels));
        b.resize(a.size());
        glGetTextureImage(c.maps(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, static_cast<GLsizei>(a.size() * 4), a.data());
        glGetTextureImage(full.maps(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, static_cast<GLsizei>(b.size() * 4), b.data());
        for (std::size_t k = 0; k < a.size(); ++k) differing += std::memcmp(&a[k], &b[k], 4) != 0 ? 1.0 : 0.0;
    }
    const double later = double(frames.size() > 1 ? frames.size() - 1 : 1);
    std::sort(ms.begin(), ms.end());
    out.work = {{"rerendered_fraction", fraction / later}, {"rerendered_max", fraction_max},
                {"frame_ms", ms.empty() ? 0.0 : ms[ms.size() / 2]}};
    if (s.cache) {
        out.work.emplace_back("cascade_frames_kept", actions[0]);
        out.work.emplace_back("cascade_frames_updated", actions[1]);
        out.work.emplace_back("cascade_frames_scrolled", actions[2]);
        out.work.emplace_back("cascade_frames_rendered", actions[3]);
    }
    if (verify) out.work.emplace_back("texels_differing", differing);
    const std::string err = skgl::gl_error_string();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (!err.empty()) return SequenceResult::failure("cascades: " + err);
    return out;
}

}  // namespace

void add_warp_techniques(std::vector<std::unique_ptr<Technique>>& out) {
    ReportSpec<WarpedShadowMaps, WarpedShadowMapSettings> warped;
    warped.light_matrices = [](const WarpedShadowMaps& m) { return std::vector<glm::mat4>{m.light_view_proj()}; };
    warped.name = "warped_sm";
    warped.description = "fitted (light_frustum, caster culling) / uniform / PSM / LiSPSM / TSM shadow maps, "
                         "with the perspective aliasing metric";
    // the warps are about perspective aliasing: the outdoor and duelling-frusta scenes (and user meshes)
    warped.applies = [](const Scene& s) { return s.name == "outdoor" || s.name == "duel" || s.name.rfind("mesh:", 0) == 0; };
    for (const char* m : {"fitted", "uniform", "psm", "lispsm", "tsm"}) {
        for (const char* size : {"512", "1024", "2048"}) warped.sweep.push_back(std::string("method=") + m + " size=" + size);
        warped.quick.push_back(std::string("method=") + m + " size=1024");
    }
    warped.sweep.push_back("method=lispsm size=1024 bias=offset");  // the automatic bias against the classic offset
    warped.mesh_sweep = {"method=lispsm size=1024", "method=lispsm size=1024 bias=offset",
                         "method=fitted size=1024"};  // scanned meshes: default, its offset twin, fitted
    warped.measure = measure_warped;
    add_technique(out, std::move(warped));

    ReportSpec<CascadedShadowMaps, CascadedShadowMapSettings> cascades;
    cascades.light_matrices = [](const CascadedShadowMaps& m) {
        std::vector<glm::mat4> mats;
        for (int i = 0; i < m.count(); ++i) mats.push_back(m.cascade(i).view_proj);
        return mats;
    };
    cascades.name = "cascades";
    cascades.description = "4 stable cascades (practical split scheme, lambda 0.75) in a depth array, 5% blend band; "
                           "fit=sdsm: sample distribution shadow maps (GPU min/max depth reduction, log partition, "
                           "tight light-space boxes with hysteresis)";
    cascades.applies = [](const Scene& s) { return s.light.type == LightType::Directional; };
    cascades.sweep = {"size=256 count=4", "size=512 count=4", "size=1024 count=4 fit=fixed", "size=1024 count=4 bias=polygon_offset",
                      "size=512 count=4 fit=sdsm", "size=1024 count=4 fit=sdsm", "size=1024 count=4 fit=sdsm receiver_bounds=off"};
    cascades.quick = {"size=512 count=4", "size=1024 count=4 fit=fixed", "size=1024 count=4 fit=sdsm", "size=1024 count=4 fit=sdsm receiver_bounds=off"};
    cascades.mesh_sweep = {"size=1024 count=4", "size=512 count=4", "size=1024 count=4 fit=sdsm"};
    // cached cascades (issue 25) beside the default fixed-split row: still rows render every layer whole
    // (the plan's first frame), the temporal rows show the texels re-rendered per frame
    cascades.sweep.push_back("size=1024 count=4 fit=fixed cache=on");
    cascades.quick.push_back("size=1024 count=4 fit=fixed cache=on");
    cascades.mesh_sweep.push_back("size=1024 count=4 fit=fixed cache=on");
    cascades.measure = measure_cascades;
    cascades.sequence = cascades_sequence;
    add_technique(out, std::move(cascades));
}

}  // namespace sk
