// samples/report/techniques/cached_shadow_map.cpp - "cached_shadow_map" in the report: the
// sample's CachedShadowMap class (samples/cached_shadow_map/) with timing, work counters and sweeps
// (report_technique.hpp).
//
// Rows: a sun (directional light): the stable fit with the cache and the translation-invariant caster
// pass (the sample's default), the same with the plain pass, without the cache, with the depth range
// from the receivers (world_depth=off: every camera move renders the whole map), with caster culling,
// and the tight fit (which follows the camera: nothing to keep); spot and area lights: the frustum
// around the scene, cached and not; point lights: none (a cube map, samples/shadow_map).
// Still rows: ReportTechnique calls update() for every timed frame before the first render(), so their
// plan is the first frame's (no content yet: the whole map) and their GPU ms is a full map plus the
// lookup, comparable with shadow_map's; the temporal rows (sequence below) time the cache on moving
// paths.
//
// Work (still rows), from what the class exposes: shadow_map_texels (the pair: 2 size^2), casters_drawn
// and casters_culled (culling=on); gpu_bytes: the two depth textures.
// Work (temporal rows, frames after the first, which renders the whole map): frames_kept /
// frames_updated / frames_scrolled / frames_rendered (the plan's action), rerendered_fraction (mean
// texels re-rendered / map texels), map_ms and map_ms_max (median and slowest time of render_map:
// the scroll copy and the scissored caster pass; glFinish + steady clock), culling_changes (culling=on: frames whose set of
// drawn casters differs from the frame before: a caster crossed the culling boundary), and with the
// cache on, a second instance with the
// cache off renders the same frames for comparison: full_map_ms (its median), texels_differing (texel
// frames where the kept map and the full re-render differ bit for bit), texels_differing_16ulp (by
// more than 16 float steps: another surface), max_ulps, v_pixels_differing (V bit for bit).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "cached_shadow_map.hpp"
#include "report_technique.hpp"

namespace sk {

namespace {

using Clock = std::chrono::steady_clock;

std::vector<float> read_depth(GLuint tex, int size) {
    std::vector<float> out(static_cast<std::size_t>(size) * static_cast<std::size_t>(size));
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glGetTextureImage(tex, 0, GL_DEPTH_COMPONENT, GL_FLOAT, static_cast<GLsizei>(out.size() * sizeof(float)), out.data());
    return out;
}

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
    return v[v.size() / 2];
}

// render_map between two glFinish calls: its time in ms (llvmpipe runs the GPU work on the CPU).
double timed_map(CachedShadowMap& m, const app::View& v, const CachedShadowMapSettings& s) {
    glFinish();
    const auto t0 = Clock::now();
    m.render_map(v, s);
    glFinish();
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

SequenceResult sequence(const RunContext& ctx, const CachedShadowMapSettings& s, const std::vector<TemporalFrame>& frames) {
    Scene scene = ctx.scene;  // its light turns with the frames
    scene.light = frames[0].light;
    CachedShadowMapSettings full_s = s;  // the reference: the whole map every frame
    full_s.cache = false;
    CachedShadowMap cached, full;
    std::string why;
    const app::View v0 = app::make_view(scene, ctx.gpu, frames[0].camera);
    const bool verify = s.cache && ctx.verify_sequence;
    if (!cached.init(v0, why) || (verify && !full.init(v0, why))) return SequenceResult::failure(why);
    SequenceResult out;
    std::vector<double> cached_ms, full_ms;
    double actions[4] = {0, 0, 0, 0}, rerendered = 0, differing = 0, differing_far = 0, max_ulps = 0, v_differing = 0;
    double culling_changes = 0;  // frames whose set of drawn casters differs from the frame before
    std::vector<std::uint8_t> drawn;
    for (std::size_t t = 0; t < frames.size(); ++t) {
        scene.light = frames[t].light;
        const app::View v = app::make_view(scene, ctx.gpu, frames[t].camera);
        cached.update(v, s);
        if (!cached.error().empty()) return SequenceResult::failure(cached.error());
        const double ms = timed_map(cached, v, s);
        cached.render_visibility(v, s);
        out.visibility.push_back(read_r32f(cached.visibility(), v.width, v.height));
        out.light_matrices.push_back({cached.light_view_proj()});
        const shadowkit::ShadowCachePlan& plan = cached.plan();
        if (t > 0 && cached.drawn() != drawn) culling_changes += 1.0;
        drawn = cached.drawn();
        if (t > 0) {  // the first frame renders the whole map
            actions[static_cast<int>(plan.action)] += 1.0;
            rerendered += double(plan.texels) / (double(s.size) * double(s.size));
            cached_ms.push_back(ms);
        }
        if (!s.cache || !ctx.verify_sequence) continue;
        full.update(v, full_s);
        if (!full.error().empty()) return SequenceResult::failure(full.error());
        const double fms = timed_map(full, v, full_s);
        if (t > 0) full_ms.push_back(fms);
        const std::vector<float> a = read_depth(cached.map(), s.size), b = read_depth(full.map(), s.size);
        for (std::size_t k = 0; k < a.size(); ++k) {
            std::int32_t ia = 0, ib = 0;
            std::memcpy(&ia, &a[k], 4);
            std::memcpy(&ib, &b[k], 4);
            if (ia == ib) continue;
            const double ulps = std::fabs(double(ia) - double(ib));  // depths in [0, 1]: ordered like their bits
            differing += 1.0;
            if (ulps > 16.0) differing_far += 1.0;
            max_ulps = std::max(max_ulps, ulps);
        }
        full.render_visibility(v, full_s);
        const std::vector<float> vf = read_r32f(full.visibility(), v.width, v.height);
        for (std::size_t k = 0; k < vf.size(); ++k) v_differing += std::memcmp(&vf[k], &out.visibility.back()[k], 4) != 0 ? 1.0 : 0.0;
    }
    const double later = double(frames.size() > 1 ? frames.size() - 1 : 1);
    out.work = {{"frames_kept", actions[0]},     {"frames_updated", actions[1]},
                {"frames_scrolled", actions[2]}, {"frames_rendered", actions[3]},
                {"rerendered_fraction", rerendered / later}, {"map_ms", median(cached_ms)},
                {"map_ms_max", cached_ms.empty() ? 0.0 : *std::max_element(cached_ms.begin(), cached_ms.end())}};
    if (s.culling) out.work.emplace_back("culling_changes", culling_changes);
    if (verify) {
        out.work.emplace_back("full_map_ms", median(full_ms));
        out.work.emplace_back("texels_differing", differing);
        out.work.emplace_back("texels_differing_16ulp", differing_far);
        out.work.emplace_back("max_ulps", max_ulps);
        out.work.emplace_back("v_pixels_differing", v_differing);
    }
    const std::string err = skgl::gl_error_string();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (!err.empty()) return SequenceResult::failure("cached_shadow_map: " + err);
    return out;
}

}  // namespace

void add_cached_shadow_map_techniques(std::vector<std::unique_ptr<Technique>>& out) {
    ReportSpec<CachedShadowMap, CachedShadowMapSettings> spec;
    spec.name = "cached_shadow_map";
    spec.description = "cached shadow map (shadow_cache.hpp): a sun's stable light_frustum fit (depth range fixed in the "
                       "world) follows the camera, each frame keep / scroll + border / re-render; spot and area lights: "
                       "the scene's frustum, kept. Still rows: a full map + the lookup; the cache's cost is in the temporal rows";
    spec.sweep_for = [](const Scene& scene, bool quick) -> std::vector<std::string> {
        switch (scene.light.type) {
        case LightType::Point: return {};  // a cube map
        case LightType::Directional:
            if (quick) return {"fit=stable cache=on pass=invariant size=1024", "fit=tight cache=off pass=plain size=1024"};
            return {"fit=stable cache=on pass=invariant",         "fit=stable cache=on pass=invariant bias=offset",
                    "fit=stable cache=on pass=plain",
                    "fit=stable cache=off pass=plain",            "fit=stable cache=on pass=plain world_depth=off",
                    "fit=stable cache=off pass=plain culling=on", "fit=tight cache=off pass=plain",
                    "fit=tight cache=off pass=plain culling=on"};
        default:
            if (quick) return {"cache=on size=1024"};
            return {"cache=on", "cache=on bias=offset", "cache=off"};
        }
    };
    spec.mesh_sweep = {"fit=stable cache=on pass=invariant", "fit=stable cache=on pass=invariant bias=offset"};  // scanned meshes
    spec.measure = [](CachedShadowMap& m, const CachedShadowMapSettings& s, const app::View& v, const RunContext&, RunResult& r) {
        const double texels = double(m.size()) * double(m.size());
        std::size_t casters = 0;
        for (bool c : v.gpu->caster) casters += c ? 1 : 0;
        r.gpu_bytes = static_cast<std::int64_t>(2.0 * texels * 4.0);
        r.work = {{"shadow_map_texels", 2.0 * texels},
                  {"casters_drawn", double(m.casters_drawn())},
                  {"casters_culled", double(casters - std::min(casters, m.casters_drawn()))}};
        (void)s;
        return true;
    };
    spec.sequence = sequence;
    add_technique(out, std::move(spec));
}

}  // namespace sk
