// Unit tests for shadowkit/shadow_volume.hpp.
// Expected values: topological closure (directed-edge balance), a CPU z-fail stencil count by
// homogeneous ray casting against the volume compared with a brute-force count of lit triangles
// crossed on the way to the light, brute-force sampled segments for the z-pass / z-fail decision,
// and sampled points of the clipped volume for the scissor rectangle and depth bounds.
#include <shadowkit/shadow_volume.hpp>
#include <shadowkit/silhouette.hpp>

#include <doctest/doctest.h>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <vector>

namespace sk = shadowkit;

namespace {

struct Mesh {
    std::vector<glm::vec3> p;
    std::vector<std::uint32_t> i;
};

Mesh torus(int R, int S, float r0, float r1, std::mt19937& rng, float noise) {
    Mesh m;
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int a = 0; a < R; ++a)
        for (int b = 0; b < S; ++b) {
            const float t = 6.2831853f * static_cast<float>(a) / static_cast<float>(R);
            const float s = 6.2831853f * static_cast<float>(b) / static_cast<float>(S);
            const float rr = r1 + noise * u(rng);
            m.p.emplace_back((r0 + rr * std::cos(s)) * std::cos(t), (r0 + rr * std::cos(s)) * std::sin(t), rr * std::sin(s));
        }
    auto id = [&](int a, int b) { return static_cast<std::uint32_t>(((a + R) % R) * S + ((b + S) % S)); };
    for (int a = 0; a < R; ++a)
        for (int b = 0; b < S; ++b)
            m.i.insert(m.i.end(), {id(a, b), id(a + 1, b), id(a + 1, b + 1), id(a, b), id(a + 1, b + 1), id(a, b + 1)});
    return m;
}

Mesh random_soup(std::mt19937& rng, int nv, int nt, float scale) {
    Mesh m;
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int k = 0; k < nv; ++k) m.p.emplace_back(u(rng) * scale, u(rng) * scale, u(rng) * scale);
    for (int t = 0; t < 3 * nt; ++t) m.i.push_back(static_cast<std::uint32_t>(rng() % static_cast<unsigned>(nv)));
    return m;
}

struct Volume {
    std::vector<glm::vec4> verts;      // 2n, from build_volume_vertices
    std::vector<std::uint32_t> tris;   // sides + caps
    std::vector<std::uint8_t> lit;     // per adjacency face
    sk::EdgeAdjacency adj;
};

Volume make_volume(const Mesh& m, const glm::vec4& L, sk::CapMode mode, bool caps = true) {
    Volume v;
    v.adj = sk::build_edge_adjacency(m.p.data(), m.p.size(), m.i.data(), m.i.size());
    REQUIRE(v.adj.status == sk::SilhouetteStatus::Ok);
    const sk::Silhouette s = sk::extract_silhouette(v.adj, m.p.data(), m.p.size(), L);
    REQUIRE(s.status == sk::SilhouetteStatus::Ok);
    v.lit = s.facing;
    v.verts.resize(2 * m.p.size());
    REQUIRE(sk::build_volume_vertices(m.p.data(), m.p.size(), v.verts.data(), v.verts.size()).status == sk::VolumeStatus::Ok);
    const std::size_t ne = s.indices.size() / 2;
    std::vector<std::uint32_t> side(6 * ne);
    const sk::VolumeCount sc = sk::build_side_quads(s.indices.data(), ne, m.p.size(), side.data(), side.size());
    REQUIRE(sc.status == sk::VolumeStatus::Ok);
    REQUIRE(sc.count == side.size());
    v.tris = side;
    if (caps) {
        const std::size_t fc = v.adj.face_count();
        const sk::VolumeCount need = sk::build_caps(v.adj.faces.data(), fc, v.lit.data(), m.p.size(), mode, true, nullptr, 0);
        REQUIRE(need.status == (need.count ? sk::VolumeStatus::BufferTooSmall : sk::VolumeStatus::Ok));
        std::vector<std::uint32_t> cap(need.count);
        REQUIRE(sk::build_caps(v.adj.faces.data(), fc, v.lit.data(), m.p.size(), mode, true, cap.data(), cap.size()).status == sk::VolumeStatus::Ok);
        v.tris.insert(v.tris.end(), cap.begin(), cap.end());
    }
    return v;
}

// Directed-edge balance: every edge (u, v) occurs as often as (v, u). Infinite vertices of a
// directional light are one point.
bool watertight(const Volume& v, std::size_t n, bool directional) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, long> bal;
    auto id = [&](std::uint32_t x) { return (directional && x >= n) ? static_cast<std::uint32_t>(n) : x; };
    for (std::size_t t = 0; t < v.tris.size(); t += 3) {
        const std::uint32_t a = id(v.tris[t]), b = id(v.tris[t + 1]), c = id(v.tris[t + 2]);
        if (a == b || b == c || a == c) continue;
        const std::uint32_t e[3][2] = {{a, b}, {b, c}, {c, a}};
        for (auto& x : e) {
            if (x[0] < x[1]) ++bal[{x[0], x[1]}];
            else --bal[{x[1], x[0]}];
        }
    }
    for (auto& kv : bal)
        if (kv.second != 0) return false;
    return true;
}

double det3(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) { return glm::dot(a, glm::cross(b, c)); }

// Solve 4x4 (columns c0..c3) x = rhs by Cramer; returns false if singular.
bool solve4(const glm::dvec4& c0, const glm::dvec4& c1, const glm::dvec4& c2, const glm::dvec4& c3, const glm::dvec4& rhs, double out[4]) {
    const glm::dmat4 M(c0, c1, c2, c3);
    const double d = glm::determinant(M);
    if (std::fabs(d) < 1e-300) return false;
    for (int k = 0; k < 4; ++k) {
        glm::dmat4 Mk = M;
        Mk[k] = rhs;
        out[k] = glm::determinant(Mk) / d;
    }
    return true;
}

// CPU z-fail count for the ray E + t r beyond t_x. ambiguous = true if the ray grazes an edge.
long zfail_count(const Volume& v, const glm::vec4& L, const glm::dvec3& E, const glm::dvec3& r, double tx, bool& ambiguous) {
    long count = 0;
    for (std::size_t t = 0; t < v.tris.size(); t += 3) {
        glm::dvec4 H[3];
        for (int k = 0; k < 3; ++k) {
            const glm::vec4 q = v.verts[v.tris[t + static_cast<std::size_t>(k)]];
            H[k] = q.w == 0.0f ? glm::dvec4(sk::extrude_to_infinity(glm::vec4(glm::vec3(q), 1.0f), L)) : glm::dvec4(q);
        }
        if (H[0] == H[1] || H[1] == H[2] || H[0] == H[2]) continue; // zero-area (directional light)
        const double side = -glm::determinant(glm::dmat4(H[0], H[1], H[2], glm::dvec4(E, 1.0)));
        double a[4];
        bool hit = false;
        if (H[0].w == 0.0 && H[1].w == 0.0 && H[2].w == 0.0) {
            const glm::dvec3 D0(H[0]), D1(H[1]), D2(H[2]);
            const double d = det3(D0, D1, D2);
            if (std::fabs(d) < 1e-300) continue;
            a[0] = det3(r, D1, D2) / d;
            a[1] = det3(D0, r, D2) / d;
            a[2] = det3(D0, D1, r) / d;
            hit = a[0] >= 0 && a[1] >= 0 && a[2] >= 0;
            const double mn = std::min(std::fabs(a[0]), std::min(std::fabs(a[1]), std::fabs(a[2])));
            const double mx = std::max(std::fabs(a[0]), std::max(std::fabs(a[1]), std::fabs(a[2])));
            if (mn < 1e-7 * mx) ambiguous = true;
        } else {
            if (!solve4(H[0], H[1], H[2], glm::dvec4(-r, 0.0), glm::dvec4(E, 1.0), a)) continue;
            hit = a[0] >= 0 && a[1] >= 0 && a[2] >= 0 && a[3] > tx;
            const double mn = std::min(std::fabs(a[0]), std::min(std::fabs(a[1]), std::fabs(a[2])));
            const double mx = std::max(std::fabs(a[0]), std::max(std::fabs(a[1]), std::fabs(a[2])));
            if (mn < 1e-7 * mx || std::fabs(a[3] - tx) < 1e-7 * std::fabs(tx)) ambiguous = true;
        }
        if (hit) count += side > 0 ? -1 : 1;
        if (std::fabs(side) < 1e-300 && hit) ambiguous = true;
    }
    return count;
}

// Brute force: lit triangles crossed by the segment X -> light (ray for w = 0).
long lit_crossings(const Mesh& m, const Volume& v, const glm::vec4& L, const glm::dvec3& X, bool& ambiguous) {
    const bool point = L.w > 0.0f;
    const glm::dvec3 target = point ? glm::dvec3(L) / static_cast<double>(L.w) : glm::dvec3(L);
    long c = 0;
    for (std::size_t f = 0; f < v.adj.face_count(); ++f) {
        if (!v.lit[f]) continue;
        const glm::dvec3 A(m.p[v.adj.faces[3 * f]]), B(m.p[v.adj.faces[3 * f + 1]]), C(m.p[v.adj.faces[3 * f + 2]]);
        const glm::dvec3 d = point ? target - X : target; // X + s d, s in [0, 1] (point) or [0, inf)
        const glm::dvec3 e1 = B - A, e2 = C - A, pv = glm::cross(d, e2);
        const double det = glm::dot(e1, pv);
        if (std::fabs(det) < 1e-300) continue;
        const glm::dvec3 tv = X - A;
        const double u = glm::dot(tv, pv) / det;
        const glm::dvec3 qv = glm::cross(tv, e1);
        const double w = glm::dot(d, qv) / det;
        const double s = glm::dot(e2, qv) / det;
        const bool in = u >= 0 && w >= 0 && u + w <= 1 && s > 0 && (!point || s < 1);
        if (std::min(std::fabs(u), std::min(std::fabs(w), std::fabs(1 - u - w))) < 1e-7 || std::fabs(s) < 1e-7 || (point && std::fabs(1 - s) < 1e-7)) ambiguous = true;
        if (in) ++c;
    }
    return c;
}

glm::vec4 random_light(std::mt19937& rng, float scale) {
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    const bool dir = (rng() % 3) == 0;
    return glm::vec4(u(rng) * scale, u(rng) * scale, u(rng) * scale, dir ? 0.0f : 1.0f);
}

} // namespace

TEST_CASE("extrusion closed form and vertex buffer layout") {
    const glm::vec4 p(1, 2, 3, 1);
    CHECK(sk::extrude_to_infinity(p, glm::vec4(4, 4, 4, 1)) == glm::vec4(-3, -2, -1, 0));
    CHECK(sk::extrude_to_infinity(p, glm::vec4(8, 8, 8, 2)) == glm::vec4(-6, -4, -2, 0)); // same direction, scaled
    CHECK(sk::extrude_to_infinity(p, glm::vec4(0, 0, 1, 0)) == glm::vec4(0, 0, -1, 0));   // directional: -L
    const std::vector<glm::vec3> pos = {{1, 2, 3}, {4, 5, 6}};
    std::vector<glm::vec4> out(4);
    CHECK(sk::build_volume_vertices(pos.data(), 2, out.data(), 4).count == 4);
    CHECK(out[0] == glm::vec4(1, 2, 3, 1));
    CHECK(out[3] == glm::vec4(4, 5, 6, 0));
    std::vector<std::uint32_t> q(6);
    const std::uint32_t e[2] = {0, 1};
    sk::build_side_quads(e, 1, 2, q.data(), q.size());
    CHECK(q == std::vector<std::uint32_t>{1, 0, 2, 1, 2, 3});
}

TEST_CASE("property: volumes of closed meshes are watertight for point and directional lights, both cap modes") {
    std::mt19937 rng(17);
    int n = 0;
    for (int it = 0; it < 600; ++it) {
        const Mesh m = torus(3 + static_cast<int>(rng() % 8), 3 + static_cast<int>(rng() % 8), 2.0f, 0.7f, rng, 0.3f);
        const glm::vec4 L = random_light(rng, 6.0f);
        for (sk::CapMode mode : {sk::CapMode::LitOnly, sk::CapMode::EverittKilgard}) {
            const Volume v = make_volume(m, L, mode);
            CHECK(watertight(v, m.p.size(), L.w == 0.0f));
            ++n;
        }
        // Side quads alone are open whenever there is a silhouette (the check can fail).
        const Volume s = make_volume(m, L, sk::CapMode::LitOnly, false);
        if (!s.tris.empty()) CHECK(!watertight(s, m.p.size(), L.w == 0.0f));
    }
    CHECK(n == 1200);
}

TEST_CASE("property: open / non-manifold soups: LitOnly volume is watertight, Everitt-Kilgard caps are not") {
    std::mt19937 rng(23);
    int ek_open = 0;
    for (int it = 0; it < 1500; ++it) {
        const Mesh m = random_soup(rng, 5 + static_cast<int>(rng() % 10), 1 + static_cast<int>(rng() % 20), 1.0f);
        const glm::vec4 L = random_light(rng, 4.0f);
        CHECK(watertight(make_volume(m, L, sk::CapMode::LitOnly), m.p.size(), L.w == 0.0f));
        if (!watertight(make_volume(m, L, sk::CapMode::EverittKilgard), m.p.size(), L.w == 0.0f)) ++ek_open;
    }
    CHECK(ek_open > 100);
}

TEST_CASE("property: z-fail stencil count equals brute-force lit-triangle crossings (open and closed meshes)") {
    std::mt19937 rng(31);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int checked = 0, skipped = 0, skip_z = 0, skip_b = 0;
    for (int it = 0; it < 300; ++it) {
        const bool closed = it % 2 == 0;
        const Mesh m = closed ? torus(4 + static_cast<int>(rng() % 5), 4 + static_cast<int>(rng() % 5), 1.5f, 0.6f, rng, 0.2f)
                              : random_soup(rng, 8, 1 + static_cast<int>(rng() % 12), 1.5f);
        glm::vec4 L = random_light(rng, 5.0f);
        if (it % 7 == 0) L = glm::vec4(0.1f, 0.2f, 0.05f, 1.0f); // light inside the bounding box
        const std::vector<sk::CapMode> modes = closed ? std::vector<sk::CapMode>{sk::CapMode::LitOnly, sk::CapMode::EverittKilgard}
                                                      : std::vector<sk::CapMode>{sk::CapMode::LitOnly};
        for (sk::CapMode mode : modes) {
            const Volume v = make_volume(m, L, mode);
            for (int r = 0; r < 12; ++r) {
                const glm::dvec3 E(u(rng) * 8.0, u(rng) * 8.0, u(rng) * 8.0);
                const glm::dvec3 X(u(rng) * 3.0, u(rng) * 3.0, u(rng) * 3.0);
                const glm::dvec3 dir = X - E;
                const double len = glm::length(dir);
                bool amb = false, amb2 = false;
                const long z = zfail_count(v, L, E, dir / len, len, amb);
                const long b = lit_crossings(m, v, L, X, amb2);
                if (amb) ++skip_z;
                if (amb2) ++skip_b;
                if (amb || amb2) { ++skipped; continue; }
                // Everitt-Kilgard caps: compared with LitOnly in the next test (light outside).
                if (mode == sk::CapMode::LitOnly) CHECK(z == b);
                ++checked;
            }
        }
    }
    MESSAGE("z-fail count vs brute force: " << checked << " rays checked, " << skipped << " grazing rays skipped (" << skip_z << " volume, " << skip_b << " brute)");
    CHECK(checked > 3000);
    CHECK(skipped < checked / 20);
}

TEST_CASE("Everitt-Kilgard caps equal LitOnly for closed meshes with the light outside") {
    std::mt19937 rng(37);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int same = 0, total = 0;
    for (int it = 0; it < 150; ++it) {
        const Mesh m = torus(5, 5, 1.5f, 0.6f, rng, 0.15f);
        glm::vec4 L = random_light(rng, 6.0f);
        if (L.w != 0.0f && glm::length(glm::vec3(L)) < 2.5f) L = glm::vec4(glm::vec3(L) * 3.0f, 1.0f);
        const Volume a = make_volume(m, L, sk::CapMode::LitOnly), b = make_volume(m, L, sk::CapMode::EverittKilgard);
        for (int r = 0; r < 10; ++r) {
            const glm::dvec3 E(u(rng) * 8.0, u(rng) * 8.0, u(rng) * 8.0), X(u(rng) * 3.0, u(rng) * 3.0, u(rng) * 3.0);
            const glm::dvec3 d = X - E;
            bool amb = false;
            const long za = zfail_count(a, L, E, d / glm::length(d), glm::length(d), amb);
            const long zb = zfail_count(b, L, E, d / glm::length(d), glm::length(d), amb);
            if (amb) continue;
            ++total;
            same += za == zb;
        }
    }
    CHECK(total > 1000);
    CHECK(same == total);
}

TEST_CASE("property: z-pass / z-fail decision vs brute-force segments from the near rectangle") {
    std::mt19937 rng(41);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f), u01(0.0f, 1.0f);
    int zfail = 0, zpass = 0, over = 0, sphere_over = 0;
    for (int it = 0; it < 3000; ++it) {
        const glm::vec3 eye(u(rng) * 5, u(rng) * 5, u(rng) * 5);
        const glm::vec3 at = eye + glm::vec3(u(rng), u(rng), u(rng)) * 3.0f + glm::vec3(0.01f, 0, 0);
        const glm::mat4 view = glm::lookAt(eye, at, glm::vec3(0, 1, 0.1f));
        const float near_z = (it % 10 == 0) ? 1e-5f : 0.05f + u01(rng);
        const sk::NearPlaneRect rect = sk::near_plane_rect(view, 1.0f + u01(rng), 0.5f + 1.5f * u01(rng), near_z);
        glm::vec4 L = random_light(rng, 8.0f);
        if (it % 11 == 0) L = glm::vec4(eye - 2.0f * glm::normalize(at - eye), 1.0f); // behind the camera
        const glm::vec3 c = eye + (at - eye) * (u01(rng) * 2.0f) + glm::vec3(u(rng), u(rng), u(rng)) * 2.0f;
        const glm::vec3 h = glm::vec3(u01(rng), u01(rng), u01(rng)) * 1.0f + 0.01f;
        const sk::MethodResult m = sk::choose_stencil_method_box(rect, L, c - h, c + h);
        REQUIRE(m.status == sk::VolumeStatus::Ok);
        const float radius = glm::length(h) * 0.8f;
        const sk::MethodResult ms = sk::choose_stencil_method_sphere(rect, L, c, radius);
        REQUIRE(ms.status == sk::VolumeStatus::Ok);
        // Brute force: 24x24 points of the rectangle, segment to the light (ray for w = 0).
        bool hit = false, hit_s = false;
        for (int a = 0; a <= 24; ++a)
            for (int b = 0; b <= 24; ++b) {
                const double s = static_cast<double>(a) / 24.0, t = static_cast<double>(b) / 24.0;
                const glm::dvec3 q = glm::dvec3(rect.corners[0]) + s * (glm::dvec3(rect.corners[1]) - glm::dvec3(rect.corners[0])) +
                                     t * (glm::dvec3(rect.corners[3]) - glm::dvec3(rect.corners[0]));
                const glm::dvec3 d = L.w > 0 ? glm::dvec3(L) - q : glm::dvec3(L) * 1e4;
                double t0 = 0.0, t1 = 1.0;
                for (int k = 0; k < 3; ++k) {
                    const double lo = c[k] - h[k], hi = c[k] + h[k];
                    if (std::fabs(d[k]) < 1e-300) { if (q[k] < lo || q[k] > hi) t1 = -1.0; continue; }
                    double ta = (lo - q[k]) / d[k], tb = (hi - q[k]) / d[k];
                    if (ta > tb) std::swap(ta, tb);
                    t0 = std::max(t0, ta);
                    t1 = std::min(t1, tb);
                }
                if (t0 <= t1) hit = true;
                // segment-sphere distance
                const double dd = glm::dot(d, d);
                double ts = dd > 0 ? glm::dot(glm::dvec3(c) - q, d) / dd : 0.0;
                ts = std::min(1.0, std::max(0.0, ts));
                if (glm::length(q + ts * d - glm::dvec3(c)) <= radius) hit_s = true;
            }
        if (hit) CHECK(m.method == sk::StencilMethod::ZFail);
        if (hit_s) CHECK(ms.method == sk::StencilMethod::ZFail);
        if (!hit && m.method == sk::StencilMethod::ZFail) ++over;
        if (!hit_s && ms.method == sk::StencilMethod::ZFail) ++sphere_over;
        (m.method == sk::StencilMethod::ZFail ? zfail : zpass)++;
    }
    MESSAGE("decision: " << zfail << " z-fail, " << zpass << " z-pass; z-fail without a sampled hit: box " << over << ", sphere " << sphere_over);
    CHECK(zfail > 300);
    CHECK(zpass > 300);
    CHECK(over < 60);        // only near-tangent cases the 25x25 sampling misses
    CHECK(sphere_over < 60);
}

TEST_CASE("z-pass / z-fail stiff cases") {
    const glm::mat4 view = glm::lookAt(glm::vec3(0, 0, 5), glm::vec3(0, 0, 0), glm::vec3(0, 1, 0));
    const sk::NearPlaneRect rect = sk::near_plane_rect(view, 1.0f, 1.0f, 0.1f);
    // Camera inside the shadow: occluder between the eye and the light.
    CHECK(sk::choose_stencil_method_box(rect, glm::vec4(0, 0, 20, 1), glm::vec3(-1, -1, 9), glm::vec3(1, 1, 10)).method == sk::StencilMethod::ZFail);
    // Light behind the occluder as seen from the eye: shadow goes away from the camera.
    // Light above, occluder beyond the origin: segments from the near rectangle to the light stay in z > 0.
    CHECK(sk::choose_stencil_method_box(rect, glm::vec4(0, 20, 0, 1), glm::vec3(-1, -1, -6), glm::vec3(1, 1, -4)).method == sk::StencilMethod::ZPass);
    CHECK(sk::choose_stencil_method_box(rect, glm::vec4(0, 20, 0, 1), glm::vec3(-1, -1, -6), glm::vec3(1, 25, 0.1f)).method == sk::StencilMethod::ZFail);
    // Directional light from behind the camera (+z): the prism toward +z misses a box at the origin.
    CHECK(sk::choose_stencil_method_box(rect, glm::vec4(0, 0, 1, 0), glm::vec3(-1, -1, -1), glm::vec3(1, 1, 1)).method == sk::StencilMethod::ZPass);
    CHECK(sk::choose_stencil_method_box(rect, glm::vec4(0, 0, -1, 0), glm::vec3(-1, -1, -1), glm::vec3(1, 1, 1)).method == sk::StencilMethod::ZFail);
    // Light exactly in the near plane (flat pyramid), box touching it.
    CHECK(sk::choose_stencil_method_box(rect, glm::vec4(3, 0, 4.9f, 1), glm::vec3(1, -0.1f, 4.8f), glm::vec3(1.2f, 0.1f, 5.0f)).method == sk::StencilMethod::ZFail);
    CHECK(sk::choose_stencil_method_box(rect, glm::vec4(3, 0, 4.9f, 1), glm::vec3(1, -0.1f, 3.0f), glm::vec3(1.2f, 0.1f, 4.0f)).method == sk::StencilMethod::ZPass);
    // Coordinates at 1e6 and 1e-6.
    const glm::mat4 vbig = glm::lookAt(glm::vec3(1e6f, 0, 5), glm::vec3(1e6f, 0, 0), glm::vec3(0, 1, 0));
    const sk::NearPlaneRect rb = sk::near_plane_rect(vbig, 1.0f, 1.0f, 0.1f);
    CHECK(sk::choose_stencil_method_box(rb, glm::vec4(1e6f, 0, 20, 1), glm::vec3(1e6f - 1, -1, 9), glm::vec3(1e6f + 1, 1, 10)).method == sk::StencilMethod::ZFail);
    CHECK(sk::choose_stencil_method_box(rb, glm::vec4(1e6f, 20, 0, 1), glm::vec3(1e6f - 1, -1, -6), glm::vec3(1e6f + 1, 1, -4)).method == sk::StencilMethod::ZPass);
    const glm::mat4 vs = glm::lookAt(glm::vec3(0, 0, 5e-6f), glm::vec3(0, 0, 0), glm::vec3(0, 1, 0));
    const sk::NearPlaneRect rs = sk::near_plane_rect(vs, 1.0f, 1.0f, 1e-7f);
    CHECK(sk::choose_stencil_method_box(rs, glm::vec4(0, 0, 2e-5f, 1), glm::vec3(-1e-6f, -1e-6f, 9e-6f), glm::vec3(1e-6f, 1e-6f, 1e-5f)).method == sk::StencilMethod::ZFail);
    CHECK(sk::choose_stencil_method_sphere(rs, glm::vec4(0, 0, 2e-5f, 1), glm::vec3(0, 0, 9.5e-6f), 1e-6f).method == sk::StencilMethod::ZFail);
    CHECK(sk::choose_stencil_method_sphere(rs, glm::vec4(0, 2e-5f, 0, 1), glm::vec3(0, 0, -1e-5f), 1e-6f).method == sk::StencilMethod::ZPass);
    CHECK(sk::choose_stencil_method_sphere(rs, glm::vec4(0, 2e-5f, 0, 1), glm::vec3(0, 1e-5f, 2.45e-6f), 1e-6f).method == sk::StencilMethod::ZFail);
    // Near rectangle from the inverse view-projection equals the one from the camera parameters.
    const glm::mat4 P = glm::perspectiveRH_NO(1.0f, 1.0f, 0.1f, 100.0f);
    const sk::NearPlaneRect ri = sk::near_plane_rect_from_inverse(glm::inverse(P * view), sk::ClipDepth::NegativeOneToOne, false);
    for (int k = 0; k < 4; ++k) CHECK(glm::length(ri.corners[k] - rect.corners[k]) < 1e-5f);
    // Invalid input.
    CHECK(sk::choose_stencil_method_box(rect, glm::vec4(0, 0, 0, 0), glm::vec3(0), glm::vec3(1)).status == sk::VolumeStatus::InvalidLight);
    CHECK(sk::choose_stencil_method_box(rect, glm::vec4(0, 0, 1, -1), glm::vec3(0), glm::vec3(1)).status == sk::VolumeStatus::InvalidLight);
    CHECK(sk::choose_stencil_method_box(rect, glm::vec4(0, 0, 1, 1), glm::vec3(1), glm::vec3(0)).status == sk::VolumeStatus::InvalidBounds);
    CHECK(sk::choose_stencil_method_box(rect, glm::vec4(0, 0, 1, 1), glm::vec3(std::nanf("")), glm::vec3(0)).status == sk::VolumeStatus::NonFinite);
    CHECK(sk::choose_stencil_method_sphere(rect, glm::vec4(0, 0, 1, 1), glm::vec3(0), -1.0f).status == sk::VolumeStatus::InvalidBounds);
}

TEST_CASE("property: scissor rectangle and depth bounds contain every sampled point of the clipped volume") {
    std::mt19937 rng(53);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f), u01(0.0f, 1.0f);
    double fill = 0.0;
    int vis = 0, invisible = 0, samples = 0;
    for (int it = 0; it < 1500; ++it) {
        const glm::vec3 eye(u(rng) * 10, u(rng) * 10, u(rng) * 10);
        const glm::vec3 at(u(rng) * 2, u(rng) * 2, u(rng) * 2);
        const bool zo = it % 2 == 1, rev = it % 4 >= 2;
        const float n = it % 9 == 0 ? 1e-5f : 0.1f;
        glm::mat4 P = zo ? glm::perspectiveRH_ZO(1.0f, 1.5f, n, 1e4f) : glm::perspectiveRH_NO(1.0f, 1.5f, n, 1e4f);
        if (rev) { // reversed depth: z' = w - z (ZO) or -z (GL)
            for (int c = 0; c < 4; ++c) P[c][2] = zo ? P[c][3] - P[c][2] : -P[c][2];
        }
        sk::ScissorParams sp;
        sp.view_proj = P * glm::lookAt(eye, at, glm::vec3(0, 1, 0));
        sp.clip_depth = zo ? sk::ClipDepth::ZeroToOne : sk::ClipDepth::NegativeOneToOne;
        sp.reversed_z = rev;
        sp.viewport[0] = 10; sp.viewport[1] = 20; sp.viewport[2] = 640; sp.viewport[3] = 480;
        const glm::vec3 lc(u(rng) * 4, u(rng) * 4, u(rng) * 4);
        const glm::vec4 L = it % 5 == 0 ? glm::vec4(u(rng), u(rng), u(rng), 0.0f) : glm::vec4(lc, 1.0f);
        const glm::vec3 lmin = lc - glm::vec3(3.0f + 3.0f * u01(rng)), lmax = lc + glm::vec3(3.0f + 3.0f * u01(rng));
        const glm::vec3 oc = lc + glm::vec3(u(rng), u(rng), u(rng)) * 4.0f, oh = glm::vec3(u01(rng), u01(rng), u01(rng)) * 0.8f + 0.01f;
        const sk::ScissorResult s = sk::shadow_volume_scissor(L, oc - oh, oc + oh, lmin, lmax, sp);
        REQUIRE(s.status == sk::VolumeStatus::Ok);
        if (s.visible) {
            ++vis;
            fill += static_cast<double>(s.width) * s.height / (640.0 * 480.0);
            CHECK(s.x >= 10);
            CHECK(s.y >= 20);
            CHECK(s.x + s.width <= 650);
            CHECK(s.y + s.height <= 500);
            CHECK(s.depth_min <= s.depth_max);
        } else {
            ++invisible;
        }
        const glm::dmat4 M(sp.view_proj);
        for (int k = 0; k < 400; ++k) {
            const glm::dvec3 p = glm::dvec3(oc) + glm::dvec3(u(rng), u(rng), u(rng)) * glm::dvec3(oh);
            const double t = std::pow(10.0, 2.5 * static_cast<double>(u01(rng)));
            const glm::dvec3 q = L.w > 0 ? glm::dvec3(L) + t * (p - glm::dvec3(L)) : p - (t - 1.0) * 3.0 * glm::dvec3(L);
            if (q.x < lmin.x || q.y < lmin.y || q.z < lmin.z || q.x > lmax.x || q.y > lmax.y || q.z > lmax.z) continue;
            const glm::dvec4 c = M * glm::dvec4(q, 1.0);
            const bool in_front = rev ? c.z <= c.w : (zo ? c.z >= 0.0 : c.z >= -c.w);
            if (!(c.w > 0.0) || !in_front) continue;
            const double nx = c.x / c.w, ny = c.y / c.w, nz = c.z / c.w;
            if (std::fabs(nx) > 1.0 || std::fabs(ny) > 1.0) continue; // outside the viewport anyway
            ++samples;
            CHECK(s.visible);
            if (!s.visible) break;
            const double px = 10.0 + (nx + 1.0) * 0.5 * 640.0, py = 20.0 + (ny + 1.0) * 0.5 * 480.0;
            const double wz = zo ? nz : 0.5 * nz + 0.5;
            CHECK(px >= s.x - 1e-6);
            CHECK(px <= s.x + s.width + 1e-6);
            CHECK(py >= s.y - 1e-6);
            CHECK(py <= s.y + s.height + 1e-6);
            CHECK(wz >= static_cast<double>(s.depth_min) - 1e-7);
            CHECK(wz <= static_cast<double>(s.depth_max) + 1e-7);
        }
    }
    MESSAGE("scissor: " << vis << " visible (mean scissor area " << (vis ? 100.0 * fill / vis : 0.0) << "% of the viewport), "
                        << invisible << " culled, " << samples << " sampled volume points checked");
    CHECK(samples > 20000);
    CHECK(invisible > 20);
    CHECK(fill / vis < 0.8);
}

TEST_CASE("scissor: hand case, invalid input") {
    // Camera at +z looking at the origin, light above a small box; shadow straight down into the
    // light box whose floor is y = -1: the region is a thin column; scissor covers its projection.
    sk::ScissorParams sp;
    sp.view_proj = glm::perspectiveRH_NO(1.0f, 1.0f, 0.1f, 100.0f) * glm::lookAt(glm::vec3(0, 0, 10), glm::vec3(0), glm::vec3(0, 1, 0));
    sp.viewport[2] = 100; sp.viewport[3] = 100;
    const sk::ScissorResult s = sk::shadow_volume_scissor(glm::vec4(0, 5, 0, 1), glm::vec3(-0.1f, 1, -0.1f), glm::vec3(0.1f, 1.2f, 0.1f),
                                                          glm::vec3(-5, -1, -5), glm::vec3(5, 5, 5), sp);
    REQUIRE(s.visible);
    CHECK(s.width < 10);           // narrow column around x = 50
    CHECK(s.x <= 50);
    CHECK(s.x + s.width >= 50);
    CHECK(s.height < 50);
    // Shadow pointing away from the light box: region empty -> not visible.
    const sk::ScissorResult e = sk::shadow_volume_scissor(glm::vec4(0, 5, 0, 1), glm::vec3(-0.1f, 1, -0.1f), glm::vec3(0.1f, 1.2f, 0.1f),
                                                          glm::vec3(-5, 6, -5), glm::vec3(5, 9, 5), sp);
    CHECK(!e.visible);
    // Light inside the occluder bounds: whole light box.
    const sk::ScissorResult in = sk::shadow_volume_scissor(glm::vec4(0, 1.1f, 0, 1), glm::vec3(-0.1f, 1, -0.1f), glm::vec3(0.1f, 1.2f, 0.1f),
                                                           glm::vec3(-1, -1, -1), glm::vec3(1, 1, 1), sp);
    CHECK(in.visible);
    CHECK(in.width > 10);
    // Invalid.
    CHECK(sk::shadow_volume_scissor(glm::vec4(0), glm::vec3(0), glm::vec3(1), glm::vec3(0), glm::vec3(1), sp).status == sk::VolumeStatus::InvalidLight);
    CHECK(sk::shadow_volume_scissor(glm::vec4(0, 1, 0, 1), glm::vec3(1), glm::vec3(0), glm::vec3(0), glm::vec3(1), sp).status == sk::VolumeStatus::InvalidBounds);
    sk::ScissorParams bad = sp;
    bad.viewport[2] = 0;
    CHECK(sk::shadow_volume_scissor(glm::vec4(0, 1, 0, 1), glm::vec3(0), glm::vec3(1), glm::vec3(0), glm::vec3(1), bad).status == sk::VolumeStatus::InvalidArgument);
    bad = sp;
    bad.view_proj[1][1] = std::numeric_limits<float>::infinity();
    CHECK(sk::shadow_volume_scissor(glm::vec4(0, 1, 0, 1), glm::vec3(0), glm::vec3(1), glm::vec3(0), glm::vec3(1), bad).status == sk::VolumeStatus::NonFinite);
}

TEST_CASE("buffers: statuses, too-small capacity reports the needed count and writes nothing past it") {
    const std::uint32_t edges[4] = {0, 1, 1, 2};
    std::vector<std::uint32_t> out(8, 0xFFFFFFFFu);
    const sk::VolumeCount r = sk::build_side_quads(edges, 2, 3, out.data(), 8);
    CHECK(r.status == sk::VolumeStatus::BufferTooSmall);
    CHECK(r.count == 12);
    CHECK(out[6] == 0xFFFFFFFFu); // only whole quads are written
    CHECK(sk::build_side_quads(edges, 2, 2, out.data(), 8).status == sk::VolumeStatus::IndexOutOfRange);
    CHECK(sk::build_side_quads(nullptr, 2, 3, out.data(), 8).status == sk::VolumeStatus::InvalidArgument);
    CHECK(sk::build_side_quads(nullptr, 0, 0, nullptr, 0).status == sk::VolumeStatus::Ok);
    const std::uint32_t tris[6] = {0, 1, 2, 0, 2, 3};
    const std::uint8_t lit[2] = {1, 0};
    CHECK(sk::build_caps(tris, 2, lit, 4, sk::CapMode::LitOnly, true, nullptr, 0).count == 6);
    CHECK(sk::build_caps(tris, 2, lit, 4, sk::CapMode::EverittKilgard, true, nullptr, 0).count == 6);
    CHECK(sk::build_caps(tris, 2, lit, 4, sk::CapMode::EverittKilgard, false, nullptr, 0).count == 3);
    CHECK(sk::build_caps(tris, 2, lit, 3, sk::CapMode::LitOnly, true, out.data(), 8).status == sk::VolumeStatus::IndexOutOfRange);
    CHECK(sk::build_caps(tris, 2, nullptr, 4, sk::CapMode::LitOnly, true, out.data(), 8).status == sk::VolumeStatus::InvalidArgument);
    std::vector<std::uint32_t> c(6);
    sk::build_caps(tris, 2, lit, 4, sk::CapMode::LitOnly, true, c.data(), c.size());
    CHECK(c == std::vector<std::uint32_t>{0, 1, 2, 4, 6, 5});
    const glm::vec3 bad[1] = {glm::vec3(std::numeric_limits<float>::quiet_NaN())};
    glm::vec4 o[2];
    CHECK(sk::build_volume_vertices(bad, 1, o, 2).status == sk::VolumeStatus::NonFinite);
    const glm::vec3 ok[1] = {glm::vec3(1)};
    CHECK(sk::build_volume_vertices(ok, 1, o, 1).status == sk::VolumeStatus::BufferTooSmall);
}
