// samples/report/techniques/soft_shadows.cpp - "pcf", "pcss", "bias" and "sampled_area" in the report:
// the samples' Pcss class (samples/pcss/) and SampledAreaLight class (samples/sampled_area_light/) with
// timing, work counters, sweeps and the acne / peter-panning metrics (report_technique.hpp).
//
// Sweeps (the old drivers' rows, entry by entry, as named settings):
//   pcf    area lights and spot lights: filter=hard, box and tent of radius 1 texel (9 taps), poisson
//          rotate off (16 taps) and on (16, 32, 64 taps) of radius_from_light (half the penumbra of a
//          mid-height blocker, to 0.1 texel); fit_near=off: the light's near plane as sk::fit_light puts it
//          (pruned for the report's time budget: the rows that never won are gone; --quick: box and tent
//          of radius 1 and 3, poisson 16 and 64 taps rotate off / on)
//   pcss   area lights: taps 16, 32, 64 x rotate off / on (the class's defaults otherwise: near plane at
//          the casters, receiver-plane bias, the emitter's horizon)
//   bias   the depth-bias study, a report-only sweep of the class's bias settings (no sample of its own:
//          the sample's panel has the same settings): bias none / constant (world units) / slope_scaled /
//          normal_offset / receiver_plane at a few amounts, filter=hard (one 2x2 compare) and poisson
//          (16 rotated taps, radius 4 texels), horizon=off, on contact, fence, stack and grazing; its
//          figures are acne_fraction and peter_pan_px
//   sampled_area  area lights: maps=4, 16, 64, 256
//   scanned meshes (mesh_sweep, docs/report.md): pcf the class's defaults with filter=poisson and the radius
//          from the light; pcss taps 32 (the default) and 64; sampled_area 16 maps (the default) and 64
// The old params light_scale and hard=1 (a light of width 0, the plain lookup of PCSS's map) are no
// settings: tests/gl/test_gl_soft_shadows.cpp builds them (a scene whose light has size 0; filter=hard).
//
// Work, from what the classes expose: shadow_map_texels, taps_per_pixel (hard 1, box / tent (2r+1)^2,
// poisson taps, pcss search + filter taps; sampled_area N), maps_rendered, triangles_drawn, depth_bits
// (pcf, pcss, bias: of the class's map); init_ms (sampled_area: the Poisson set too, once the old
// poisson_setup_ms). gpu_bytes: the map(s), 4 bytes a texel (24-bit depth is padded).
// Quality (pcf, pcss, bias): acne_fraction, peter_pan_px, lit_pixels, contact_pixels (add_bias_quality).
// Timing: frame_budget_ms 400 (bias 100: a quality study, its timings indicative only).
#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <tuple>

#include "pcss.hpp"
#include "reference.hpp"
#include "report_technique.hpp"
#include "sampled_area_light.hpp"

namespace sk {

namespace {

bool surface_area_light(const Light& L) {
    return L.is_area() && (L.type == LightType::Rect || L.type == LightType::Disk || L.type == LightType::Sphere);
}

// The scenes of the soft rows: rect, disk and sphere lights and user meshes ("grazing", the bias study's
// scene, is left to the bias study to keep the report's run time).
bool soft_scene(const Scene& s) {
    if (s.name == "grazing") return false;
    return surface_area_light(s.light) || (s.name.rfind("mesh:", 0) == 0 && s.light.type != LightType::Point &&
                                           s.light.type != LightType::Directional && s.light.type != LightType::Linear);
}

// ------------------------------------------------------------------------------ acne / peter-panning
// A low-sample reference of the same definition as the report's (strata 6 = 36 rays per pixel for
// area lights, exact for hard lights), cached per scene and size: enough to classify pixels as
// fully lit (all rays reach the light) or deep in shadow.
const Reference* classification_reference(const Scene& s, const GBuffer& g) {
    static std::mutex mu;
    static std::map<std::tuple<std::uint64_t, int, int>, Reference> cache;
    std::lock_guard<std::mutex> lock(mu);
    const auto key = std::make_tuple(scene_hash(s, g.width, g.height, 0x50f7u), g.width, g.height);
    auto it = cache.find(key);
    if (it != cache.end()) return &it->second;
    ReferenceOptions o;
    o.strata = 6;
    o.progress = false;
    Reference r;
    std::string why;
    if (!compute_reference(s, g, o, r, why)) return nullptr;
    return &cache.emplace(key, std::move(r)).first->second;
}

// acne_fraction: receiver pixels that face the light and are fully lit in the reference (V_ref == 1)
// but get V < 0.5. peter_pan_px: the gap between contact lines and the start of their shadow, in
// pixels: contact pixels are receiver pixels on a concave crease (a 4-neighbour whose normal turns
// by more than 60 degrees towards it, within 6 pixel footprints in world space) that are in the
// reference's shadow (V_ref < 0.25); the gap is the number of pixels within 16 pixels of those
// that the reference puts in shadow (V_ref < 0.25) and the technique lights (V >= 0.5), divided by
// the number of shadowed contact pixels (the length of the contact line): the mean width of the
// wrongly lit band along the contact.
void add_bias_quality(RunResult& r, const Scene& s, const GBuffer* gp) {
    if (!gp) return;
    const GBuffer& g = *gp;
    const Reference* ref = classification_reference(s, g);
    if (!ref) return;
    const int w = g.width, h = g.height;
    auto idx = [w](int x, int y) { return static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x); };
    auto P = [&](std::size_t k) { return glm::vec3(g.position[3 * k], g.position[3 * k + 1], g.position[3 * k + 2]); };
    auto N = [&](std::size_t k) { return glm::vec3(g.normal[3 * k], g.normal[3 * k + 1], g.normal[3 * k + 2]); };
    auto counted = [&](std::size_t k) { return g.kind[k] == 1 && ref->faces_light[k]; };
    std::size_t lit = 0, acne = 0;
    for (std::size_t k = 0; k < g.kind.size(); ++k)
        if (counted(k) && ref->visibility[k] >= 1.f) {
            ++lit;
            if (r.visibility[k] < 0.5f) ++acne;
        }
    const float tan_half = std::tan(0.5f * s.camera.fovy);
    const glm::vec3 eye = s.camera.eye;
    std::vector<std::uint8_t> contact(g.kind.size(), 0);
    std::size_t contacts = 0;
    for (int y = 1; y < h - 1; ++y)
        for (int x = 1; x < w - 1; ++x) {
            const std::size_t k = idx(x, y);
            if (!counted(k) || ref->visibility[k] >= 0.25f) continue;
            const glm::vec3 p = P(k), n = N(k);
            const float foot = 2.f * glm::length(p - eye) * tan_half / float(h);
            const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
            for (int i = 0; i < 4; ++i) {
                const std::size_t q = idx(x + dx[i], y + dy[i]);
                if (g.kind[q] == 0) continue;
                const glm::vec3 pq = P(q), nq = N(q);
                const glm::vec3 d = pq - p;
                if (glm::dot(n, nq) < 0.5f && glm::length(d) < 6.f * foot && glm::dot(n, d) > 0.f &&
                    glm::dot(nq, -d) > 0.f) {
                    contact[k] = 1;
                    ++contacts;
                    break;
                }
            }
        }
    std::size_t gap = 0;
    if (contacts) {
        // pixels within 16 (Chebyshev) of a contact pixel: dilate with a separable max filter
        const int R = 16;
        std::vector<std::uint8_t> tmp(contact.size(), 0), near_c(contact.size(), 0);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                std::uint8_t m = 0;
                for (int i = std::max(0, x - R); i <= std::min(w - 1, x + R) && !m; ++i) m = contact[idx(i, y)];
                tmp[idx(x, y)] = m;
            }
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                std::uint8_t m = 0;
                for (int j = std::max(0, y - R); j <= std::min(h - 1, y + R) && !m; ++j) m = tmp[idx(x, j)];
                near_c[idx(x, y)] = m;
            }
        for (std::size_t k = 0; k < g.kind.size(); ++k)
            if (near_c[k] && counted(k) && ref->visibility[k] < 0.25f && r.visibility[k] >= 0.5f) ++gap;
    }
    r.quality.push_back({"acne_fraction", lit ? double(acne) / double(lit) : 0.0});
    r.quality.push_back({"peter_pan_px", contacts ? double(gap) / double(contacts) : 0.0});
    r.quality.push_back({"lit_pixels", double(lit)});
    r.quality.push_back({"contact_pixels", double(contacts)});
}

// The work of one map (pcf, pcss, bias), its depth bits and the acne / peter-panning figures.
bool measure_pcss(Pcss& t, const PcssSettings& s, const app::View& v, const RunContext& ctx, RunResult& r) {
    if (!t.error().empty()) {  // a program that did not compile (render() stops there)
        r = RunResult::failure(t.error());
        return false;
    }
    using F = PcssSettings::Filter;
    const int box_r = static_cast<int>(std::lround(t.radius_texels()));
    const double taps = s.filter == F::Hard                         ? 1.0
                        : s.filter == F::Box || s.filter == F::Tent ? double((2 * box_r + 1) * (2 * box_r + 1))
                        : s.filter == F::Pcss                       ? 2.0 * s.taps
                                                                    : double(s.taps);
    GLint bits = 0;
    glGetTextureLevelParameteriv(t.map(), 0, GL_TEXTURE_DEPTH_SIZE, &bits);
    const double texels = double(t.size()) * double(t.size());
    r.gpu_bytes = static_cast<std::int64_t>(texels * 4.0);
    r.work = {{"shadow_map_texels", texels},
              {"taps_per_pixel", taps},
              {"maps_rendered", 1.0},
              {"triangles_drawn", double(v.gpu->caster_triangles)},
              {"depth_bits", double(bits)}};
    add_bias_quality(r, ctx.scene, ctx.gbuffer);
    return true;
}

ReportSpec<Pcss, PcssSettings> pcss_spec(const char* name, const char* description) {
    ReportSpec<Pcss, PcssSettings> spec;
    spec.light_matrices = [](const Pcss& m) { return std::vector<glm::mat4>{m.light_view_proj()}; };
    spec.name = name;
    spec.description = description;
    spec.hard = false;
    spec.measure = measure_pcss;
    spec.frame_budget_ms = 400.0;
    return spec;
}

}  // namespace

void add_soft_techniques(std::vector<std::unique_ptr<Technique>>& out) {
    // PCF: the hard 2x2 compare with the same bias and horizon, box and tent of radius 1..3 texels, Poisson
    // unrotated and rotated of 16..64 taps in a disk of half the penumbra of a mid-height blocker
    auto pcf = pcss_spec("pcf", "PCF (glsl/pcf.glsl) on a 2048 map, receiver-plane bias: filter hard 2x2, box / tent "
                                "(radius 1..3 texels, 9/25/49 taps), poisson rotate off / on (16/32/64 taps, radius "
                                "from the light: half the penumbra of a mid-height blocker); x the emitter's fraction "
                                "above the tangent plane");
    pcf.applies = [](const Scene& s) { return soft_scene(s) || s.light.type == LightType::Spot; };
    pcf.identity = "filter=poisson";
    // The full sweep is pruned to the rows that won somewhere (the full report of 2026-12-04: the best
    // row or on the Pareto front of some scene): box and tent of radius 2 and 3 and unrotated Poisson
    // of 32 and 64 taps never did; box radius 1 stays as the box filter's row.
    pcf.sweep = {"filter=hard fit_near=off", "filter=box radius_texels=1 fit_near=off",
                 "filter=tent radius_texels=1 fit_near=off"};
    for (const char* rows : {"taps=16 rotate=off", "taps=16 rotate=on", "taps=32 rotate=on", "taps=64 rotate=on"})
        pcf.sweep.push_back(std::string("filter=poisson ") + rows + " radius_from_light=on fit_near=off");
    pcf.quick.push_back("filter=hard fit_near=off");
    for (const char* f : {"box", "tent"})
        for (int r : {1, 3}) pcf.quick.push_back(std::string("filter=") + f + " radius_texels=" + std::to_string(r) + " fit_near=off");
    for (const char* rot : {"off", "on"})
        for (int t : {16, 64})
            pcf.quick.push_back("filter=poisson taps=" + std::to_string(t) + " rotate=" + rot + " radius_from_light=on fit_near=off");
    // scanned meshes: the class's defaults with a Poisson filter (32 rotated taps, radius 2 texels), and the radius
    // from the light
    pcf.mesh_sweep = {"filter=poisson", "filter=poisson radius_from_light=on"};
    add_technique(out, std::move(pcf));

    auto pcss = pcss_spec("pcss", "PCSS (pcss.hpp uniforms + glsl/pcss.glsl) on a 2048 map, near plane at the casters, "
                                  "receiver-plane bias: taps = search = filter (16/32/64), rotate off / on; x the "
                                  "emitter's fraction above the tangent plane");
    pcss.applies = soft_scene;
    pcss.identity = "filter=pcss";
    for (const char* rot : {"off", "on"}) {
        for (int t : {16, 32, 64}) pcss.sweep.push_back("filter=pcss taps=" + std::to_string(t) + " rotate=" + rot);
        for (int t : {16, 64}) pcss.quick.push_back("filter=pcss taps=" + std::to_string(t) + " rotate=" + rot);
    }
    pcss.mesh_sweep = {"filter=pcss taps=32 rotate=on", "filter=pcss taps=64 rotate=on"};
    add_technique(out, std::move(pcss));

    ReportSpec<SampledAreaLight, SampledAreaLightSettings> sampled;
    sampled.name = "sampled_area";
    sampled.description = "sampled area light (Apelles): N = 4..256 spot-light maps (1024^2) from Poisson points on "
                          "the emitter, 2x2 PCF each, accumulated";
    sampled.hard = false;
    sampled.applies = soft_scene;
    sampled.sweep = {"maps=4", "maps=16", "maps=64", "maps=256"};
    sampled.quick = {"maps=4", "maps=16", "maps=64"};
    sampled.mesh_sweep = {"maps=16", "maps=64"};  // 64: does it converge on fine geometry (issue: within 1.5x of the wedges)
    sampled.frame_budget_ms = 400.0;
    sampled.measure = [](SampledAreaLight& t, const SampledAreaLightSettings&, const app::View& v, const RunContext&,
                         RunResult& r) {
        const double n = t.maps(), texels = double(t.size()) * double(t.size());
        r.gpu_bytes = static_cast<std::int64_t>(double(t.layers()) * texels * 4.0);
        r.work = {{"shadow_map_texels", n * texels},
                  {"taps_per_pixel", n},
                  {"maps_rendered", n},
                  {"triangles_drawn", n * double(v.gpu->caster_triangles)}};
        return true;
    };
    add_technique(out, std::move(sampled));

    // The bias study: each method at a few amounts, on the plain 2x2 compare and on a 16-tap rotated
    // Poisson PCF of radius 4 texels (the full sweep's PCF rows: the amounts that show the kernel-radius rule)
    auto bias = pcss_spec("bias", "depth-bias study (shadow_bias.hpp): bias none / constant [world] / slope_scaled / "
                                  "normal_offset / receiver_plane [texels] at a few amounts, filter hard 2x2 / poisson 16 "
                                  "taps r=4; acne and peter-panning");
    bias.default_row = false;  // a study of the bias settings: the class's default is pcss's row
    bias.applies = [](const Scene& s) {
        return s.name == "contact" || s.name == "fence" || s.name == "stack" || s.name == "grazing";
    };
    bias.frame_budget_ms = 100.0;
    struct Amounts {
        const char* method;
        const char* field;
        std::vector<const char*> full, quick, pcf;
    };
    const Amounts amounts[] = {{"none", nullptr, {""}, {""}, {""}},
                               {"constant", "constant_bias", {"0.002", "0.01", "0.05"}, {"0.01"}, {"0.01"}},
                               {"slope_scaled", "slope_scale", {"0.7", "1.5", "4"}, {"1.5"}, {"0.7", "4"}},
                               {"normal_offset", "normal_offset", {"0.7", "1.5", "4"}, {"1.5"}, {"0.7", "4"}},
                               {"receiver_plane", "plane_margin", {"0", "1", "2"}, {"1"}, {"1"}}};
    for (bool quick : {false, true})
        for (const char* filter : {"filter=hard", "filter=poisson taps=16 rotate=on radius_texels=4"})
            for (const Amounts& a : amounts) {
                const bool pcf_rows = std::string(filter) != "filter=hard" && !quick;
                for (const char* amount : pcf_rows ? a.pcf : (quick ? a.quick : a.full)) {
                    std::string row = std::string(filter) + " bias=" + a.method;
                    if (a.field) row += std::string(" ") + a.field + "=" + amount;
                    (quick ? bias.quick : bias.sweep).push_back(row + " fit_near=off horizon=off");
                }
            }
    add_technique(out, std::move(bias));
}

}  // namespace sk
