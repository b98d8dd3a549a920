// The Embree reference at contact points and at any scene scale: a box resting on a floor under
// a point light and under a square area light, evaluated at hand-placed surface points (no GL).
#include <doctest/doctest.h>

#include <cmath>

#include "reference.hpp"
#include "scene.hpp"

namespace {

struct Probe {
    glm::vec3 p, n;
};

sk::Reference trace(const sk::Scene& s, const std::vector<Probe>& probes, int strata = 32) {
    sk::GBuffer g;
    g.width = static_cast<int>(probes.size());
    g.height = 1;
    for (const auto& pr : probes) {
        g.position.insert(g.position.end(), {pr.p.x, pr.p.y, pr.p.z});
        g.normal.insert(g.normal.end(), {pr.n.x, pr.n.y, pr.n.z});
        g.kind.push_back(1);
    }
    sk::ReferenceOptions opt;
    opt.progress = false;
    opt.strata = strata;
    sk::Reference r;
    std::string why;
    REQUIRE_MESSAGE(sk::compute_reference(s, g, opt, r, why), why);
    return r;
}

sk::Scene resting_box(float scale, sk::LightType type) {
    sk::Scene s;
    s.name = "resting";
    s.meshes.push_back(sk::make_plane("floor", {0.f, 0.f, 0.f}, 4.f * scale, 4.f * scale));
    s.meshes.push_back(sk::make_box("box", {0.f, 0.5f * scale, 0.f}, glm::vec3(0.5f * scale)));
    s.light.type = type;
    s.light.position = glm::vec3(3.f, 4.f, 0.f) * scale;
    s.light.direction = glm::normalize(-s.light.position);
    s.light.size = type == sk::LightType::Rect ? 0.5f * scale : 0.f;
    return s;
}

}  // namespace

TEST_CASE("contact points of a resting box come out right at every scene scale") {
    for (float scale : {1e-3f, 1.f, 1e3f}) {
        CAPTURE(scale);
        for (auto type : {sk::LightType::Point, sk::LightType::Rect}) {
            CAPTURE(static_cast<int>(type));
            const sk::Scene s = resting_box(scale, type);
            const float gap = 1e-3f * scale;  // 1 mm from the contact line on a 1 m box
            const std::vector<Probe> probes = {
                {glm::vec3(0.5f * scale + gap, 0.f, 0.f), {0, 1, 0}},   // floor, lit side, at the contact
                {glm::vec3(-0.5f * scale - gap, 0.f, 0.f), {0, 1, 0}},  // floor, shadow side, at the contact
                {glm::vec3(0.5f * scale, gap, 0.f), {1, 0, 0}},         // box side facing the light, at the floor
                {glm::vec3(-0.5f * scale, gap, 0.f), {-1, 0, 0}},       // box side facing away
                {glm::vec3(0.f, scale, 0.f), {0, 1, 0}},                // box top
                {glm::vec3(0.f, 0.f, 2.f * scale), {0, 1, 0}},          // floor in front, clear of the box
            };
            const sk::Reference r = trace(s, probes);
            CHECK(r.visibility[0] == doctest::Approx(1.0));
            CHECK(r.visibility[1] == doctest::Approx(0.0));
            CHECK(r.visibility[2] == doctest::Approx(1.0));
            CHECK(r.visibility[3] == doctest::Approx(0.0));
            CHECK(r.faces_light[3] == 0);
            CHECK(r.visibility[4] == doctest::Approx(1.0));
            // from (0, 0, 2) the segment to the light passes the box at z > 1.6: unobstructed
            CHECK(r.visibility[5] == doctest::Approx(1.0));
        }
    }
}

TEST_CASE("disk light partially hidden by the box edge: fraction against brute force") {
    // Floor point p = (-0.5 - d, 0, 0) on the shadow side, disk light of radius 0.25 centred at
    // (3, 4, 0) facing the origin. The segment to the light centre grazes the box's top edge
    // (-0.5, 1) when d * 4 / (3.5 + d) = 1, i.e. d = 7/6: there the disk is about half hidden.
    // Brute force: a dense grid over the disk (rotation-symmetric, so any in-plane basis spans
    // the same set) and an exact slab test per segment.
    sk::Scene s = resting_box(1.f, sk::LightType::Disk);
    s.light.size = 0.25f;
    const float d = 7.f / 6.f;
    const Probe pr{{-0.5f - d, 0.f, 0.f}, {0, 1, 0}};
    const sk::Reference r = trace(s, {pr}, 64);
    const glm::vec3 n = glm::normalize(s.light.direction);
    const glm::vec3 t = glm::normalize(glm::cross(n, glm::vec3(0, 0, 1))), b = glm::cross(n, t);
    int seen = 0, total = 0;
    const int N = 400;
    for (int i = 0; i < N; ++i)
        for (int j = 0; j < N; ++j) {
            const float u = 2.f * (float(i) + 0.5f) / float(N) - 1.f, v = 2.f * (float(j) + 0.5f) / float(N) - 1.f;
            if (u * u + v * v > 1.f) continue;
            const glm::vec3 q = s.light.position + 0.25f * (u * t + v * b);
            const glm::vec3 o = pr.p, dir = q - pr.p;
            float t0 = 1e-6f, t1 = 1.f;
            bool hit = true;
            for (int k = 0; k < 3 && hit; ++k) {
                const float lo = k == 1 ? 0.f : -0.5f, hi = k == 1 ? 1.f : 0.5f;
                if (std::abs(dir[k]) < 1e-12f) {
                    if (o[k] < lo || o[k] > hi) hit = false;
                    continue;
                }
                float ta = (lo - o[k]) / dir[k], tb = (hi - o[k]) / dir[k];
                if (ta > tb) std::swap(ta, tb);
                t0 = std::max(t0, ta);
                t1 = std::min(t1, tb);
                if (t0 > t1) hit = false;
            }
            ++total;
            if (!hit) ++seen;
        }
    const double expected = double(seen) / double(total);
    MESSAGE("partially hidden disk light: reference " << r.visibility[0] << ", brute force " << expected);
    CHECK(expected > 0.2);
    CHECK(expected < 0.8);
    CHECK(std::abs(r.visibility[0] - expected) < 0.01);
}
