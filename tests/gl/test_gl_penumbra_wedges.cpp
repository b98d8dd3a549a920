// "penumbra_wedges" (soft shadow volumes: silhouette.hpp + shadow_volume.hpp + penumbra_wedge.hpp +
// glsl/penumbra_wedge.glsl; the PenumbraWedges class of samples/penumbra_wedges/ through the report's
// wrapper, its settings by name) against the Embree area-light
// reference (sk::compute_reference) and against the CPU functions of penumbra_wedge.hpp:
//  (a) light radius 0 reduces to the hard stencil shadow volume exactly;
//  (b) the known over-darkening where two blockers' penumbrae overlap is measured on `overlap`;
//  (c) on `contact` the penumbra error is far below the hard shadow map's and within a bound derived
//      from the disk model of the square light;
//  (d) the GPU's accumulated coverage equals penumbra_visibility() on the CPU at sampled pixels;
//  (e) scissor and depth bounds leave V unchanged (float noise) and cut wedge fragments;
//  (f) a camera inside a wedge: back faces (chosen automatically) are needed and right;
//  (g) the epsilon-tweaked infinite projection gives the same hard and soft result as finite + clamp.
#include <doctest/doctest.h>

#include <shadowkit/penumbra_wedge.hpp>
#include <shadowkit/silhouette.hpp>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "gl_test.hpp"
#include "metrics.hpp"
#include "reference.hpp"
#include "scene.hpp"
#include "techniques.hpp"

namespace {

constexpr int kW = 320, kH = 240;

struct Run {
    sk::RunResult res;
    sk::Metrics m;
    double work(const std::string& k) const {
        for (const auto& [name, v] : res.work)
            if (name == k) return v;
        return -1.0;
    }
};

struct Prepared {
    sk::SceneGpu gpu;
    sk::GBuffer g;
    sk::Reference ref;
};

sk::Technique& technique(const std::string& name) {
    static auto all = sk::make_techniques();
    for (auto& t : all)
        if (t->name() == name) return *t;
    FAIL(name << " is not registered");
    return *all.front();
}

void prepare(const sk::Scene& scene, Prepared& p, bool reference = true) {
    std::string why;
    REQUIRE_MESSAGE(sk::prepare_scene_gpu(scene, kW, kH, p.gpu, p.g, why), why);
    if (!reference) return;
    sk::ReferenceOptions opt;
    opt.progress = false;
    REQUIRE_MESSAGE(sk::compute_reference(scene, p.g, opt, p.ref, why), why);
}

sk::Reference reference_for(const sk::Scene& scene, const sk::GBuffer& g) {
    sk::ReferenceOptions opt;
    opt.progress = false;
    sk::Reference ref;
    std::string why;
    REQUIRE_MESSAGE(sk::compute_reference(scene, g, opt, ref, why), why);
    return ref;
}

Run run(const std::string& tech, const sk::Scene& scene, Prepared& p, sk::ParamSet ps, bool hard_metrics = false) {
    sk::RunContext ctx{scene, p.gpu, 1, 0, &p.g};
    Run r;
    r.res = technique(tech).run(ctx, ps);
    REQUIRE_MESSAGE(r.res.ok, r.res.error);
    REQUIRE(r.res.visibility.size() == p.g.kind.size());
    if (!p.ref.visibility.empty()) r.m = sk::compute_metrics(p.g, p.ref, r.res.visibility, hard_metrics);
    return r;
}

// Named settings of samples/penumbra_wedges/ (bind_settings), e.g. "scissor=off faces=back"; "" the defaults.
sk::ParamSet P(const std::string& named) { return sk::ParamSet::parse_named(named); }

std::size_t count_different(const std::vector<float>& a, const std::vector<float>& b) {
    std::size_t n = 0;
    for (std::size_t k = 0; k < a.size(); ++k) n += a[k] != b[k];
    return n;
}

float max_abs_diff(const std::vector<float>& a, const std::vector<float>& b) {
    float m = 0.f;
    for (std::size_t k = 0; k < a.size(); ++k) m = std::max(m, std::abs(a[k] - b[k]));
    return m;
}

bool compared(const Prepared& p, const sk::Reference& ref, std::size_t k) {
    return p.g.kind[k] == 1 && ref.faces_light[k];
}

// RMSE over penumbra pixels (0 < V_ref < 1) of a visibility image
double penumbra_rmse(const Prepared& p, const sk::Reference& ref, const std::vector<float>& v) {
    double s = 0.0;
    std::size_t n = 0;
    for (std::size_t k = 0; k < v.size(); ++k)
        if (compared(p, ref, k) && ref.visibility[k] > 0.f && ref.visibility[k] < 1.f) {
            const double d = double(v[k]) - ref.visibility[k];
            s += d * d;
            ++n;
        }
    return n ? std::sqrt(s / double(n)) : 0.0;
}

glm::vec3 gpos(const sk::GBuffer& g, std::size_t k) {
    return {g.position[3 * k], g.position[3 * k + 1], g.position[3 * k + 2]};
}

// CPU model of the driver (horizon = 0): silhouettes of every caster from the light centre, the hard
// count as the number of light-facing triangles that the segment p -> c crosses (the LitOnly volume
// is one prism per lit triangle), V = penumbra_visibility(all silhouette edges, light, p, count).
struct CpuModel {
    std::vector<glm::vec3> edges;  // pairs
    std::vector<glm::vec3> lit;    // triangles (3 per lit face)
    shadowkit::PenumbraSphereLight light;
    void build(const sk::Scene& s, float radius) {
        light.light_position = glm::vec4(s.light.position, 1.f);
        light.radius = radius;
        const glm::vec4 L(s.light.position, 1.f);
        for (const sk::Mesh& m : s.meshes) {
            if (!m.caster) continue;
            const shadowkit::SilhouetteAdjacency adj =
                shadowkit::silhouette_build_adjacency(m.positions.data(), m.positions.size(), m.indices.data(), m.indices.size());
            REQUIRE(adj.status == shadowkit::Status::Ok);
            const shadowkit::Silhouette sil = shadowkit::silhouette_compute(adj, m.positions.data(), m.positions.size(), L);
            REQUIRE(sil.status == shadowkit::Status::Ok);
            for (std::uint32_t i : sil.indices) edges.push_back(m.positions[i]);
            for (std::size_t f = 0; f < adj.face_count(); ++f)
                if (sil.facing[f])
                    for (int c = 0; c < 3; ++c) lit.push_back(m.positions[adj.faces[3 * f + std::size_t(c)]]);
        }
    }
    int hard_count(glm::vec3 p) const {
        const glm::dvec3 o(p), d = glm::dvec3(glm::vec3(light.light_position)) - o;
        int n = 0;
        for (std::size_t t = 0; t + 2 < lit.size(); t += 3) {
            const glm::dvec3 a(lit[t]), b(lit[t + 1]), c(lit[t + 2]);
            const glm::dvec3 e1 = b - a, e2 = c - a, h = glm::cross(d, e2);
            const double det = glm::dot(e1, h);
            if (std::abs(det) < 1e-14) continue;
            const glm::dvec3 s = o - a;
            const double u = glm::dot(s, h) / det;
            if (u < 0.0 || u > 1.0) continue;
            const glm::dvec3 q = glm::cross(s, e1);
            const double v = glm::dot(d, q) / det;
            if (v < 0.0 || u + v > 1.0) continue;
            const double t_hit = glm::dot(e2, q) / det;
            if (t_hit > 1e-4 && t_hit < 1.0) ++n;  // not the receiver's own face (G-buffer rounding)
        }
        return n;
    }
    float visibility(glm::vec3 p, int count) const {
        return static_cast<float>(shadowkit::penumbra_visibility(edges.data(), edges.size() / 2, light, p, count).value);
    }
};

sk::Scene contact_scene() {
    sk::Scene s;
    REQUIRE(sk::make_builtin_scene("contact", s));
    return s;
}

}  // namespace

TEST_CASE("(a) light radius 0: the hard stencil shadow volume, pixel for pixel") {
    // contact (square light) with light_scale 0: the wedges vanish, V = 1 - clamp(stencil count)
    {
        const sk::Scene s = contact_scene();
        Prepared p;
        prepare(s, p, false);
        const Run w = run("penumbra_wedges", s, p, P("light_scale=0"));
        const Run v = run("shadow_volume", s, p, sk::ParamSet::parse_named("method=auto scissor=on depth_bounds=on"));
        MESSAGE("contact, light_scale 0: wedges " << w.work("wedges") << ", pixels different from shadow_volume "
                                                  << count_different(w.res.visibility, v.res.visibility));
        CHECK(w.work("wedges") == 0);
        CHECK(count_different(w.res.visibility, v.res.visibility) == 0);
    }
    // the same scene with a point light at the square's centre: against the hard reference
    {
        sk::Scene s = contact_scene();
        s.light.type = sk::LightType::Point;
        s.light.size = 0.f;
        Prepared p;
        prepare(s, p);
        const Run w = run("penumbra_wedges", s, p, P(""), true);
        const Run v = run("shadow_volume", s, p, P(""), true);
        std::size_t shadowed = 0;
        for (std::size_t k = 0; k < p.g.kind.size(); ++k) shadowed += compared(p, p.ref, k) && p.ref.visibility[k] < 0.5f;
        MESSAGE("contact with a point light: misclassified " << w.m.misclassified << " of " << w.m.pixels << " (shadowed "
                                                            << shadowed << "), different from shadow_volume "
                                                            << count_different(w.res.visibility, v.res.visibility));
        CHECK(shadowed > 500);
        CHECK(w.m.misclassified <= 0.002);
        CHECK(count_different(w.res.visibility, v.res.visibility) == 0);
    }
}

TEST_CASE("(b) overlap: the additive combination over-darkens where two penumbrae overlap (measured)") {
    sk::Scene s;
    REQUIRE(sk::make_builtin_scene("overlap", s));
    Prepared p;
    prepare(s, p);
    // per-blocker references on the same G-buffer (the reference traces casters only)
    sk::Scene only_high = s, only_low = s;
    for (auto& m : only_high.meshes)
        if (m.name == "low") m.caster = false;
    for (auto& m : only_low.meshes)
        if (m.name == "high") m.caster = false;
    const sk::Reference rh = reference_for(only_high, p.g), rl = reference_for(only_low, p.g);
    const Run w = run("penumbra_wedges", s, p, P(""));
    auto pen = [](float v) { return v > 0.02f && v < 0.98f; };
    double se_o = 0.0, sd_o = 0.0, se_s = 0.0, sd_s = 0.0, se_add = 0.0;
    std::size_t n_o = 0, n_s = 0;
    for (std::size_t k = 0; k < p.g.kind.size(); ++k) {
        if (!compared(p, p.ref, k)) continue;
        const float vh = rh.visibility[k], vl = rl.visibility[k];
        const double d = double(w.res.visibility[k]) - p.ref.visibility[k];
        if (pen(vh) && pen(vl)) {
            se_o += d * d;
            sd_o += d;
            ++n_o;
            // A&AM's sum of occlusions, with the exact per-blocker visibilities
            const double v_add = std::max(0.0, double(vh) + vl - 1.0);
            se_add += (double(w.res.visibility[k]) - v_add) * (double(w.res.visibility[k]) - v_add);
        } else if ((pen(vh) && vl > 0.999f) || (pen(vl) && vh > 0.999f)) {
            se_s += d * d;
            sd_s += d;
            ++n_s;
        }
    }
    REQUIRE(n_o > 0);
    REQUIRE(n_s > 0);
    const double rmse_o = std::sqrt(se_o / double(n_o)), rmse_s = std::sqrt(se_s / double(n_s));
    const double bias_o = sd_o / double(n_o), bias_s = sd_s / double(n_s);
    const double rmse_add = std::sqrt(se_add / double(n_o));
    MESSAGE("overlap: overall RMSE " << w.m.rmse << ", penumbra RMSE " << w.m.penumbra_rmse << "\n  both penumbrae ("
                                     << n_o << " px): RMSE " << rmse_o << ", mean V - V_ref " << bias_o
                                     << "\n  one penumbra (" << n_s << " px): RMSE " << rmse_s << ", mean V - V_ref "
                                     << bias_s << "\n  both penumbrae, V vs max(0, V_high + V_low - 1): RMSE " << rmse_add);
    CHECK(n_o > 200);
    CHECK(rmse_o > 2.0 * rmse_s);  // the error concentrates where the penumbrae overlap
    CHECK(bias_o < -0.02);         // and it is over-darkening (V too small)
    CHECK(bias_o < bias_s);
    CHECK(rmse_add < 0.5 * rmse_o);  // what the additive model predicts: the measured error is that limitation
}

TEST_CASE("(c) contact: penumbra error far below the hard shadow map's, within the disk-model bound") {
    const sk::Scene s = contact_scene();
    Prepared p;
    prepare(s, p);
    const Run w = run("penumbra_wedges", s, p, P(""));
    const Run sm = run("shadow_map", s, p, sk::ParamSet::parse_named("size=2048"));
    // The wedges compute the shadow of a disk light (here the disk of the square's area). The floor of
    // their error is the difference between the square and that disk: the reference of the same scene
    // with the disk light, compared with the square's.
    sk::Scene sd = s;
    sd.light.type = sk::LightType::Disk;
    sd.light.size = s.light.size / std::sqrt(3.14159265f);
    const sk::Reference rdisk = reference_for(sd, p.g);
    const double model_floor = penumbra_rmse(p, p.ref, rdisk.visibility);
    const double bound = model_floor + 0.02;
    MESSAGE("contact: wedges RMSE " << w.m.rmse << ", penumbra RMSE " << w.m.penumbra_rmse << " ("
                                    << w.m.penumbra_pixels << " px); shadow_map 2048: RMSE " << sm.m.rmse
                                    << ", penumbra RMSE " << sm.m.penumbra_rmse << "; disk-vs-square reference "
                                    << "penumbra RMSE " << model_floor << " -> bound " << bound);
    CHECK(w.m.penumbra_pixels > 1000);
    CHECK(w.m.penumbra_rmse < 0.5 * sm.m.penumbra_rmse);
    CHECK(w.m.penumbra_rmse < bound);
    CHECK(w.m.rmse < sm.m.rmse);
}

TEST_CASE("(d) the GPU coverage sum equals penumbra_visibility() on the CPU at sampled pixels") {
    for (const std::string name : {"contact", "overlap"}) {
        sk::Scene s;
        REQUIRE(sk::make_builtin_scene(name, s));
        Prepared p;
        prepare(s, p, false);
        const Run w = run("penumbra_wedges", s, p, P("horizon=off"));
        CpuModel cpu;
        cpu.build(s, float(w.work("light_radius")));
        // hard counts per pixel, then compare away from changes of the count (where the rasterised
        // volume and the CPU ray test may disagree by a pixel)
        std::vector<int> count(p.g.kind.size(), -1);
        for (std::size_t k = 0; k < count.size(); ++k)
            if (p.g.kind[k] == 1) count[k] = cpu.hard_count(gpos(p.g, k));
        double max_d = 0.0, sum_d = 0.0;
        std::size_t n = 0, soft_px = 0;
        for (int y = 1; y < kH - 1; y += 2)
            for (int x = 1; x < kW - 1; x += 2) {
                const std::size_t k = std::size_t(y) * kW + std::size_t(x);
                if (p.g.kind[k] != 1) continue;
                const glm::vec3 pk = gpos(p.g, k);
                const glm::vec3 nk(p.g.normal[3 * k], p.g.normal[3 * k + 1], p.g.normal[3 * k + 2]);
                if (glm::dot(nk, s.light.position - pk) <= 0.f) continue;  // not compared by the metrics either
                bool edge = false;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const std::size_t q = std::size_t(y + dy) * kW + std::size_t(x + dx);
                        edge = edge || (count[q] >= 0 && count[q] != count[k]);
                    }
                if (edge) continue;
                // the driver's light rules: area lights give 0 behind their plane
                const glm::vec3 ld = glm::normalize(s.light.direction);
                if (glm::dot(pk - s.light.position, ld) <= 0.f) continue;
                const float vc = cpu.visibility(pk, count[k]);
                const double d = std::abs(double(w.res.visibility[k]) - vc);
                max_d = std::max(max_d, d);
                sum_d += d;
                ++n;
                soft_px += vc > 0.f && vc < 1.f;
            }
        MESSAGE(name << ": " << n << " sampled pixels (" << soft_px << " in a penumbra), " << cpu.edges.size() / 2
                     << " silhouette edges: max |V_gpu - V_cpu| " << max_d << ", mean " << sum_d / double(n));
        CHECK(soft_px > 200);
        CHECK(max_d < 1e-4);
        CHECK(sum_d / double(n) < 1e-6);
    }
}

TEST_CASE("(e) scissor and depth bounds: V unchanged (float noise), fewer wedge fragments") {
    for (const std::string name : {"contact", "overlap"}) {
        sk::Scene s;
        REQUIRE(sk::make_builtin_scene(name, s));
        Prepared p;
        prepare(s, p, false);
        const Run base = run("penumbra_wedges", s, p, P("scissor=off depth_bounds=off"));
        for (auto [sc, db] : {std::pair{1, 0}, std::pair{0, 1}, std::pair{1, 1}}) {
            const std::string named = std::string("scissor=") + (sc ? "on" : "off") + " depth_bounds=" + (db ? "on" : "off");
            const Run c = run("penumbra_wedges", s, p, P(named));
            const float d = max_abs_diff(base.res.visibility, c.res.visibility);
            MESSAGE(name << " scissor " << sc << " depth_bounds " << db << ": wedge_fragments "
                         << c.work("wedge_fragments") << " of " << base.work("wedge_fragments") << " (in-wedge "
                         << c.work("wedge_fragments_in") << " vs " << base.work("wedge_fragments_in")
                         << "), max |dV| " << d << ", wedge pass " << c.work("wedge_ms") << " ms vs "
                         << c.work("wedge_ms_unculled") << " ms unculled");
            CHECK(d <= 1e-5f);
            CHECK(c.work("wedge_fragments") <= base.work("wedge_fragments"));
            CHECK(c.work("wedge_fragments_in") == base.work("wedge_fragments_in"));
            CHECK(c.work("wedge_fragments_unculled") == base.work("wedge_fragments"));
            if (sc && db) CHECK(c.work("wedge_fragments") < 0.8 * base.work("wedge_fragments"));
        }
    }
}

TEST_CASE("(f) camera inside a wedge: back faces are drawn for it, front faces alone miss pixels") {
    sk::Scene s = contact_scene();
    // eye inside the wedge of one of the box's silhouette edges (the middle of its rays, 0.35 above the
    // floor), looking across the penumbra on the floor
    CpuModel cpu;
    cpu.build(s, s.light.size / std::sqrt(3.14159265f));
    bool placed = false;
    for (std::size_t e = 0; e + 1 < cpu.edges.size() && !placed; e += 2) {
        const shadowkit::PenumbraWedge w = shadowkit::penumbra_wedge(cpu.edges[e], cpu.edges[e + 1], cpu.light);
        if (w.status != shadowkit::Status::Ok || w.skip != shadowkit::PenumbraWedgeSkip::None) continue;
        const glm::vec3 a = 0.5f * (w.apex[0] + w.apex[1]);
        if (a.x > -0.2f || a.y < 0.9f) continue;  // a top edge of the box (x < -0.3)
        const glm::vec3 dir = glm::normalize(w.ray_outer[0] + w.ray_outer[1] + w.ray_inner[0] + w.ray_inner[1]);
        if (dir.y > -0.1f) continue;
        const glm::vec3 eye = a + dir * ((a.y - 0.35f) / -dir.y);
        if (!shadowkit::penumbra_point_in_wedge(eye, w)) continue;
        s.camera.eye = eye;
        s.camera.target = eye + glm::vec3(dir.x, 0.f, dir.z) * 2.f - glm::vec3(0.f, 0.6f, 0.f);
        placed = true;
        MESSAGE("eye " << eye.x << " " << eye.y << " " << eye.z << " inside the wedge of edge " << e / 2);
    }
    REQUIRE(placed);
    Prepared p;
    prepare(s, p);
    const Run autof = run("penumbra_wedges", s, p, P(""));
    const Run back = run("penumbra_wedges", s, p, P("faces=back"));
    const Run front = run("penumbra_wedges", s, p, P("faces=front"));
    std::size_t wrong = 0;
    for (std::size_t k = 0; k < p.g.kind.size(); ++k) wrong += std::abs(front.res.visibility[k] - autof.res.visibility[k]) > 0.05f;
    MESSAGE("camera in a wedge: wedges drawn with back faces " << autof.work("wedges_back") << " of " << autof.work("wedges")
                                                              << "; RMSE auto " << autof.m.rmse << " (penumbra "
                                                              << autof.m.penumbra_rmse << "), front faces only "
                                                              << front.m.rmse << " with " << wrong
                                                              << " pixels off by > 0.05; max |auto - all back| "
                                                              << max_abs_diff(autof.res.visibility, back.res.visibility));
    CHECK(autof.work("wedges_back") >= 1);
    CHECK(max_abs_diff(autof.res.visibility, back.res.visibility) <= 1e-5f);
    CHECK(wrong > 100);
    CHECK(autof.m.rmse < front.m.rmse);
    CHECK(autof.m.penumbra_rmse < 0.08);
}

TEST_CASE("(g) epsilon-tweaked P_inf (own depth pass) gives the finite + depth clamp result") {
    // hard part on stack (spot light: radius 0)
    {
        sk::Scene s;
        REQUIRE(sk::make_builtin_scene("stack", s));
        Prepared p;
        prepare(s, p);
        for (int method : {0, 1}) {
            const std::string m = std::string("method=") + (method ? "auto" : "zfail");
            const Run fin = run("penumbra_wedges", s, p, P(m), true);
            const Run inf = run("penumbra_wedges", s, p, P(m + " projection=infinite"), true);
            const std::size_t diff = count_different(fin.res.visibility, inf.res.visibility);
            MESSAGE("stack, method " << method << ": misclassified finite " << fin.m.misclassified << ", P_inf "
                                     << inf.m.misclassified << " (epsilon " << inf.work("projection_epsilon")
                                     << "), pixels different " << diff);
            CHECK(fin.m.misclassified <= 0.002);
            CHECK(inf.m.misclassified <= 0.002);
            CHECK(diff <= 20);
        }
    }
    // soft: the wedge coverage reads the G-buffer's world positions, identical for both projections
    for (const std::string name : {"contact", "overlap"}) {
        sk::Scene s;
        REQUIRE(sk::make_builtin_scene(name, s));
        Prepared p;
        prepare(s, p, false);
        const Run fin = run("penumbra_wedges", s, p, P(""));
        const Run inf = run("penumbra_wedges", s, p, P("projection=infinite"));
        std::size_t big = 0;
        for (std::size_t k = 0; k < fin.res.visibility.size(); ++k)
            big += std::abs(fin.res.visibility[k] - inf.res.visibility[k]) > 1e-4f;
        MESSAGE(name << ": P_inf vs finite: pixels with |dV| > 1e-4: " << big << ", max |dV| "
                     << max_abs_diff(fin.res.visibility, inf.res.visibility));
        CHECK(big <= 20);
    }
}

TEST_CASE("(h) open mesh (issue 27.5): a one-sided cup facing the area light: two_sided leaks far less than lit_only") {
    // contact's floor and square light, its casters replaced by a box without its lid (outward-wound, one
    // face per side), the opening towards the light: light entering through the opening leaves through
    // back faces, which a volume of the lit faces misses
    sk::Scene s = contact_scene();
    s.meshes.erase(std::remove_if(s.meshes.begin(), s.meshes.end(), [](const sk::Mesh& m) { return m.caster; }), s.meshes.end());
    sk::Mesh cup = sk::make_box("cup", {0.f, 0.51f, 0.f}, {0.6f, 0.5f, 0.5f});
    const std::size_t before = cup.indices.size();
    // make_box's quads: drop the +y one (the lid), found by its normal
    for (std::size_t t = 0; t < cup.indices.size(); t += 3) {
        const glm::vec3 a = cup.positions[cup.indices[t]], b = cup.positions[cup.indices[t + 1]], c = cup.positions[cup.indices[t + 2]];
        if (glm::normalize(glm::cross(b - a, c - a)).y > 0.9f) {
            cup.indices.erase(cup.indices.begin() + std::ptrdiff_t(t), cup.indices.begin() + std::ptrdiff_t(t + 3));
            t -= 3;
        }
    }
    REQUIRE(cup.indices.size() + 6 == before);
    s.meshes.push_back(cup);
    Prepared p;
    prepare(s, p);
    const Run two = run("penumbra_wedges", s, p, P("open_meshes=two_sided"));
    const Run one = run("penumbra_wedges", s, p, P("open_meshes=lit_only"));
    MESSAGE("open cup under contact's square light: umbra pixels " << two.m.umbra_pixels << "; two_sided RMSE " << two.m.rmse
                                                                  << ", leak " << two.m.leak_fraction << "; lit_only RMSE "
                                                                  << one.m.rmse << ", leak " << one.m.leak_fraction);
    CHECK(two.m.umbra_pixels > 100);
    CHECK(one.m.leak_fraction > 0.2);
    CHECK(two.m.leak_fraction < 0.5 * one.m.leak_fraction);
    CHECK(two.m.rmse < 0.5 * one.m.rmse);
}
