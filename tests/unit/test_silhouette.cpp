// Unit tests for shadowkit/silhouette.hpp.
// Expected values: brute-force O(n^2) edge matching and facing in long double (independent of the
// header's sort-based adjacency), closed-mesh invariants, hand-built meshes (cube, book, strip).
#include <shadowkit/silhouette.hpp>

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <random>
#include <thread>
#include <utility>
#include <vector>

namespace sk = shadowkit;

namespace {

struct Mesh {
    std::vector<glm::vec3> p;
    std::vector<std::uint32_t> i;
};

// Closed, consistently wound (outward) torus grid with optional radial noise.
Mesh torus(int R, int S, float r0, float r1, std::mt19937* rng = nullptr, float noise = 0.0f) {
    Mesh m;
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int a = 0; a < R; ++a)
        for (int b = 0; b < S; ++b) {
            const float t = 6.2831853f * static_cast<float>(a) / static_cast<float>(R);
            const float s = 6.2831853f * static_cast<float>(b) / static_cast<float>(S);
            float rr = r1;
            if (rng) rr += noise * u(*rng);
            m.p.emplace_back((r0 + rr * std::cos(s)) * std::cos(t), (r0 + rr * std::cos(s)) * std::sin(t), rr * std::sin(s));
        }
    auto id = [&](int a, int b) { return static_cast<std::uint32_t>(((a + R) % R) * S + ((b + S) % S)); };
    for (int a = 0; a < R; ++a)
        for (int b = 0; b < S; ++b) {
            const std::uint32_t v00 = id(a, b), v10 = id(a + 1, b), v11 = id(a + 1, b + 1), v01 = id(a, b + 1);
            m.i.insert(m.i.end(), {v00, v10, v11, v00, v11, v01});
        }
    return m;
}

// Unit cube [0,1]^3, outward CCW, 8 shared vertices.
Mesh cube() {
    Mesh m;
    for (int k = 0; k < 8; ++k) m.p.emplace_back(static_cast<float>(k & 1), static_cast<float>((k >> 1) & 1), static_cast<float>((k >> 2) & 1));
    const std::uint32_t q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (auto& f : q) m.i.insert(m.i.end(), {f[0], f[1], f[2], f[0], f[2], f[3]});
    return m;
}

// Same cube with 24 vertices (each face its own copies): needs welding to be closed.
Mesh split_cube() {
    Mesh c = cube(), m;
    for (std::size_t t = 0; t < c.i.size(); t += 6) {
        const std::uint32_t base = static_cast<std::uint32_t>(m.p.size());
        const std::uint32_t q[4] = {c.i[t], c.i[t + 1], c.i[t + 2], c.i[t + 5]};
        for (std::uint32_t v : q) m.p.push_back(c.p[v]);
        m.i.insert(m.i.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    }
    return m;
}

using Edge = std::pair<std::uint32_t, std::uint32_t>;

// Brute-force reference: kept faces (degenerate / duplicates by O(n^2) comparison), facing in long
// double via the plane equation, and per-edge k by scanning all faces for each edge.
std::vector<Edge> brute_silhouette(const Mesh& m, const glm::vec4& L, std::vector<std::uint8_t>* lit_out = nullptr) {
    std::vector<std::array<std::uint32_t, 3>> faces;
    for (std::size_t t = 0; t + 2 < m.i.size(); t += 3) {
        std::array<std::uint32_t, 3> f = {m.i[t], m.i[t + 1], m.i[t + 2]};
        if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2]) continue;
        const glm::vec3 A = m.p[f[0]], B = m.p[f[1]], C = m.p[f[2]];
        const long double e1[3] = {(long double)B.x - A.x, (long double)B.y - A.y, (long double)B.z - A.z};
        const long double e2[3] = {(long double)C.x - A.x, (long double)C.y - A.y, (long double)C.z - A.z};
        const long double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        if (n[0] == 0 && n[1] == 0 && n[2] == 0) continue;
        bool dup = false;
        for (auto& g : faces)
            for (std::size_t r = 0; r < 3; ++r)
                if (g[0] == f[r] && g[1] == f[(r + 1) % 3] && g[2] == f[(r + 2) % 3]) dup = true;
        if (!dup) faces.push_back(f);
    }
    std::vector<std::uint8_t> lit;
    for (auto& f : faces) {
        const glm::vec3 A = m.p[f[0]], B = m.p[f[1]], C = m.p[f[2]];
        const long double e1[3] = {(long double)B.x - A.x, (long double)B.y - A.y, (long double)B.z - A.z};
        const long double e2[3] = {(long double)C.x - A.x, (long double)C.y - A.y, (long double)C.z - A.z};
        const long double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        const long double D = -(n[0] * A.x + n[1] * A.y + n[2] * A.z);
        const long double d = n[0] * L.x + n[1] * L.y + n[2] * L.z + D * L.w;
        lit.push_back(d > 0 ? 1 : 0);
    }
    if (lit_out) *lit_out = lit;
    std::vector<Edge> out;
    std::vector<Edge> seen;
    for (std::size_t f = 0; f < faces.size(); ++f)
        for (std::size_t j = 0; j < 3; ++j) {
            const std::uint32_t u = faces[f][j], v = faces[f][(j + 1) % 3];
            const Edge key(std::min(u, v), std::max(u, v));
            if (std::find(seen.begin(), seen.end(), key) != seen.end()) continue;
            seen.push_back(key);
            long k = 0;
            for (std::size_t g = 0; g < faces.size(); ++g)
                for (std::size_t jj = 0; jj < 3; ++jj) {
                    const std::uint32_t a = faces[g][jj], b = faces[g][(jj + 1) % 3];
                    if (!lit[g]) continue;
                    if (a == key.first && b == key.second) ++k;
                    if (a == key.second && b == key.first) --k;
                }
            for (long c = 0; c < std::labs(k); ++c) out.push_back(k > 0 ? key : Edge(key.second, key.first));
        }
    std::sort(out.begin(), out.end());
    return out;
}

std::vector<Edge> to_edges(const std::vector<std::uint32_t>& idx) {
    std::vector<Edge> e;
    for (std::size_t k = 0; k + 1 < idx.size(); k += 2) e.emplace_back(idx[k], idx[k + 1]);
    std::sort(e.begin(), e.end());
    return e;
}

sk::AdjacencyOptions no_weld() {
    sk::AdjacencyOptions o;
    o.weld_tolerance = -1.0f;
    return o;
}

glm::vec4 random_light(std::mt19937& rng, float scale) {
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    const bool dir = (rng() % 4) == 0;
    return glm::vec4(u(rng) * scale, u(rng) * scale, u(rng) * scale, dir ? 0.0f : 1.0f);
}

} // namespace

TEST_CASE("cube: adjacency counts, closed, facing and silhouette by hand") {
    const Mesh c = cube();
    const sk::EdgeAdjacency adj = sk::build_edge_adjacency(c.p.data(), c.p.size(), c.i.data(), c.i.size());
    REQUIRE(adj.status == sk::SilhouetteStatus::Ok);
    CHECK(adj.face_count() == 12);
    CHECK(adj.manifold_edges == 18);
    CHECK(adj.boundary_edges == 0);
    CHECK(adj.nonmanifold_edges.empty());
    CHECK(adj.closed());
    // Directional light from +z: only the top face (z = 1, two triangles) is lit.
    const sk::Silhouette s = sk::extract_silhouette(adj, c.p.data(), c.p.size(), glm::vec4(0, 0, 1, 0));
    REQUIRE(s.status == sk::SilhouetteStatus::Ok);
    std::size_t lit = 0;
    for (auto f : s.facing) lit += f;
    CHECK(lit == 2);
    // Top quad 4 5 7 6 (CCW seen from +z): silhouette is its boundary loop in that order.
    const std::vector<Edge> expect = {{4, 5}, {5, 7}, {7, 6}, {6, 4}};
    std::vector<Edge> e = to_edges(s.indices);
    std::vector<Edge> ex = expect;
    std::sort(ex.begin(), ex.end());
    CHECK(e == ex);
    // Point light inside the cube: nothing lit (outward faces), no silhouette.
    const sk::Silhouette in = sk::extract_silhouette(adj, c.p.data(), c.p.size(), glm::vec4(0.5f, 0.5f, 0.5f, 1.0f));
    CHECK(in.indices.empty());
    // Light far along the diagonal: three faces lit, silhouette is a 6-edge loop.
    const sk::Silhouette dg = sk::extract_silhouette(adj, c.p.data(), c.p.size(), glm::vec4(10, 20, 30, 1));
    CHECK(dg.indices.size() == 12);
}

TEST_CASE("property: silhouette equals brute force on random (open, non-manifold, degenerate) meshes") {
    std::mt19937 rng(4242);
    int cases = 0;
    for (int it = 0; it < 2500; ++it) {
        Mesh m;
        const int nv = 4 + static_cast<int>(rng() % 12);
        std::uniform_real_distribution<float> u(-1.0f, 1.0f);
        // few distinct vertices -> many shared / non-manifold / duplicate edges
        for (int k = 0; k < nv; ++k) m.p.emplace_back(u(rng), u(rng), u(rng));
        const int nt = 1 + static_cast<int>(rng() % 24);
        for (int t = 0; t < 3 * nt; ++t) m.i.push_back(static_cast<std::uint32_t>(rng() % static_cast<unsigned>(nv)));
        if (it % 5 == 0 && nt > 1) m.i.insert(m.i.end(), m.i.begin(), m.i.begin() + 3); // exact duplicate
        const sk::EdgeAdjacency adj = sk::build_edge_adjacency(m.p.data(), m.p.size(), m.i.data(), m.i.size(), no_weld());
        REQUIRE(adj.status == sk::SilhouetteStatus::Ok);
        for (int l = 0; l < 4; ++l) {
            const glm::vec4 L = random_light(rng, 3.0f);
            std::vector<std::uint8_t> blit;
            const std::vector<Edge> ref = brute_silhouette(m, L, &blit);
            const sk::Silhouette s = sk::extract_silhouette(adj, m.p.data(), m.p.size(), L);
            REQUIRE(s.status == sk::SilhouetteStatus::Ok);
            CHECK(s.facing.size() == blit.size());
            CHECK(to_edges(s.indices) == ref);
            CHECK(s.indices.size() / 2 <= adj.max_silhouette_edges());
            ++cases;
        }
    }
    CHECK(cases == 10000);
}

TEST_CASE("property: closed random meshes -> silhouette loops are balanced (in-degree == out-degree)") {
    std::mt19937 rng(99);
    for (int it = 0; it < 1500; ++it) {
        const int R = 3 + static_cast<int>(rng() % 10), S = 3 + static_cast<int>(rng() % 10);
        const Mesh m = torus(R, S, 2.0f, 0.7f, &rng, 0.3f);
        const sk::EdgeAdjacency adj = sk::build_edge_adjacency(m.p.data(), m.p.size(), m.i.data(), m.i.size());
        REQUIRE(adj.status == sk::SilhouetteStatus::Ok);
        REQUIRE(adj.closed());
        const glm::vec4 L = random_light(rng, 5.0f);
        const sk::Silhouette s = sk::extract_silhouette(adj, m.p.data(), m.p.size(), L);
        std::vector<int> in(m.p.size(), 0), out(m.p.size(), 0);
        for (std::size_t k = 0; k < s.indices.size(); k += 2) { ++out[s.indices[k]]; ++in[s.indices[k + 1]]; }
        bool balanced = true;
        for (std::size_t v = 0; v < m.p.size(); ++v) balanced = balanced && in[v] == out[v] && (in[v] + out[v]) % 2 == 0;
        CHECK(balanced);
        // Orientation "as in the lit face": each emitted (a, b) appears as a -> b in some lit face.
        for (std::size_t k = 0; k < s.indices.size(); k += 2) {
            bool found = false;
            for (std::size_t f = 0; f < adj.face_count() && !found; ++f) {
                if (!s.facing[f]) continue;
                for (int j = 0; j < 3; ++j)
                    if (adj.faces[3 * f + static_cast<std::size_t>(j)] == s.indices[k] && adj.faces[3 * f + static_cast<std::size_t>((j + 1) % 3)] == s.indices[k + 1]) found = true;
            }
            CHECK(found);
        }
    }
}

TEST_CASE("open and non-manifold meshes: boundary flags, book edge multiplicity, same-winding pairs") {
    // Single triangle: boundary edges, emitted iff lit, oriented as the triangle.
    {
        const std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
        const std::vector<std::uint32_t> i = {0, 1, 2};
        const sk::EdgeAdjacency adj = sk::build_edge_adjacency(p.data(), p.size(), i.data(), i.size());
        CHECK(adj.boundary_edges == 3);
        CHECK(!adj.closed());
        const sk::Silhouette up = sk::extract_silhouette(adj, p.data(), p.size(), glm::vec4(0.2f, 0.2f, 1.0f, 1.0f));
        CHECK(to_edges(up.indices) == std::vector<Edge>{{0, 1}, {1, 2}, {2, 0}});
        for (auto f : up.flags) CHECK(f == sk::SilhouetteBoundary);
        const sk::Silhouette dn = sk::extract_silhouette(adj, p.data(), p.size(), glm::vec4(0.2f, 0.2f, -1.0f, 1.0f));
        CHECK(dn.indices.empty());
    }
    // Book: three triangles sharing edge (0,1), pages 2, 3, 4, all wound 0 -> 1.
    {
        const std::vector<glm::vec3> p = {{0, 0, 0}, {0, 0, 1}, {1, 0, 0}, {0, 1, 0}, {-1, -1, 0}};
        const std::vector<std::uint32_t> i = {0, 1, 2, 0, 1, 3, 1, 0, 4};
        const sk::EdgeAdjacency adj = sk::build_edge_adjacency(p.data(), p.size(), i.data(), i.size());
        REQUIRE(adj.nonmanifold_edges.size() == 1);
        CHECK(adj.nonmanifold_edges[0].count == 3);
        for (int l = 0; l < 200; ++l) {
            std::mt19937 rng(static_cast<unsigned>(l));
            const glm::vec4 L = random_light(rng, 4.0f);
            const Mesh m{p, i};
            const sk::Silhouette s = sk::extract_silhouette(adj, p.data(), p.size(), L);
            CHECK(to_edges(s.indices) == brute_silhouette(m, L));
        }
        // Light making faces 0 and 1 lit, 2 unlit: k = +2 on edge 0->1.
        const sk::Silhouette s = sk::extract_silhouette(adj, p.data(), p.size(), glm::vec4(-5, -6, 0.5f, 1));
        int k01 = 0;
        for (std::size_t e = 0; e < s.indices.size(); e += 2)
            if (s.indices[e] == 0 && s.indices[e + 1] == 1) { ++k01; CHECK(s.flags[e / 2] == sk::SilhouetteNonManifold); }
        std::vector<std::uint8_t> bl;
        brute_silhouette(Mesh{p, i}, glm::vec4(-5, -6, 0.5f, 1), &bl);
        int expect = 0;
        for (int f = 0; f < 3; ++f) expect += bl[static_cast<std::size_t>(f)] ? (f < 2 ? 1 : -1) : 0;
        CHECK(k01 == std::abs(expect));
    }
    // Two faces sharing an edge with the same winding (inconsistent orientation) -> non-manifold.
    {
        const std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
        const std::vector<std::uint32_t> i = {0, 1, 2, 0, 1, 3};
        const sk::EdgeAdjacency adj = sk::build_edge_adjacency(p.data(), p.size(), i.data(), i.size());
        CHECK(adj.nonmanifold_edges.size() == 1);
        CHECK(adj.boundary_edges == 4);
        // Light above: face 0 (CCW from +z) lit, face 1 (CW from +z) unlit -> k = +1.
        const sk::Silhouette s = sk::extract_silhouette(adj, p.data(), p.size(), glm::vec4(0.1f, 0.1f, 3.0f, 1.0f));
        CHECK(to_edges(s.indices) == brute_silhouette(Mesh{p, i}, glm::vec4(0.1f, 0.1f, 3.0f, 1.0f)));
    }
    // Two-sided triangle (same vertices, opposite winding): closed pair, all 3 edges silhouettes.
    {
        const std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
        const std::vector<std::uint32_t> i = {0, 1, 2, 0, 2, 1};
        const sk::EdgeAdjacency adj = sk::build_edge_adjacency(p.data(), p.size(), i.data(), i.size());
        CHECK(adj.duplicate_triangles == 0);
        CHECK(adj.closed());
        const sk::Silhouette s = sk::extract_silhouette(adj, p.data(), p.size(), glm::vec4(0, 0, 1, 0));
        CHECK(to_edges(s.indices) == std::vector<Edge>{{0, 1}, {1, 2}, {2, 0}});
    }
}

TEST_CASE("welding: split cube closes with exact weld and tolerance, stays open without") {
    const Mesh s = split_cube();
    const sk::EdgeAdjacency open = sk::build_edge_adjacency(s.p.data(), s.p.size(), s.i.data(), s.i.size(), no_weld());
    CHECK(open.boundary_edges == 24);
    const sk::EdgeAdjacency exact = sk::build_edge_adjacency(s.p.data(), s.p.size(), s.i.data(), s.i.size());
    CHECK(exact.closed());
    CHECK(exact.welded_vertices == 16);
    CHECK(exact.manifold_edges == 18);
    // Perturbed copies at 1e6 offset, tolerance weld.
    for (float scale : {1e-6f, 1.0f, 1e6f}) {
        Mesh t = s;
        std::mt19937 rng(3);
        std::uniform_real_distribution<float> u(-1.0f, 1.0f);
        for (auto& v : t.p) v = v * scale + glm::vec3(3.0f * scale) + glm::vec3(u(rng), u(rng), u(rng)) * (1e-3f * scale);
        sk::AdjacencyOptions o;
        o.weld_tolerance = 0.01f * scale;
        const sk::EdgeAdjacency w = sk::build_edge_adjacency(t.p.data(), t.p.size(), t.i.data(), t.i.size(), o);
        CHECK(w.status == sk::SilhouetteStatus::Ok);
        CHECK(w.closed());
        CHECK(w.welded_vertices == 16);
        o.weld_tolerance = 1e-6f * scale; // below the perturbation: no weld
        const sk::EdgeAdjacency nw = sk::build_edge_adjacency(t.p.data(), t.p.size(), t.i.data(), t.i.size(), o);
        CHECK(nw.boundary_edges == 24);
        // Exact weld on perturbed copies: nothing welded.
        const sk::EdgeAdjacency ex = sk::build_edge_adjacency(t.p.data(), t.p.size(), t.i.data(), t.i.size());
        CHECK(ex.welded_vertices == 0);
        // Silhouette of the welded cube = brute force on the mesh re-indexed to representatives
        // (light on a diagonal so the perturbed, non-planar faces are far from grazing).
        Mesh re = t;
        for (auto& v : re.i) v = w.remap[v];
        const glm::vec4 L(1.0f, 2.0f, 3.0f, 0.0f);
        const sk::Silhouette sw = sk::extract_silhouette(w, t.p.data(), t.p.size(), L);
        CHECK(to_edges(sw.indices) == brute_silhouette(re, L));
        CHECK(sw.indices.size() == 12);
    }
    // -0 and +0 weld exactly.
    const std::vector<glm::vec3> p = {{0.0f, 0, 0}, {-0.0f, 0, 0}, {1, 0, 0}};
    const std::vector<std::uint32_t> i = {0, 1, 2};
    const sk::EdgeAdjacency z = sk::build_edge_adjacency(p.data(), p.size(), i.data(), i.size());
    CHECK(z.remap[1] == 0);
    CHECK(z.degenerate_triangles == 1);
}

TEST_CASE("brute-force weld reference on random clustered points") {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int it = 0; it < 300; ++it) {
        std::vector<glm::vec3> p;
        const float tol = 0.05f;
        for (int k = 0; k < 60; ++k) {
            if (!p.empty() && u(rng) < 0.5f) p.push_back(p[rng() % p.size()] + (glm::vec3(u(rng), u(rng), u(rng)) - 0.5f) * 0.05f);
            else p.emplace_back(u(rng), u(rng), u(rng));
        }
        std::vector<std::uint32_t> idx = {0, 1, 2};
        sk::AdjacencyOptions o;
        o.weld_tolerance = tol;
        const sk::EdgeAdjacency a = sk::build_edge_adjacency(p.data(), p.size(), idx.data(), idx.size(), o);
        // Reference: greedy in input order, lowest-index representative within tol (O(n^2)).
        std::vector<std::uint32_t> rep;
        std::vector<std::uint32_t> remap(p.size());
        for (std::uint32_t v = 0; v < p.size(); ++v) {
            std::uint32_t best = sk::kNoFace;
            for (std::uint32_t r : rep) {
                const double dx = (double)p[v].x - p[r].x, dy = (double)p[v].y - p[r].y, dz = (double)p[v].z - p[r].z;
                if (dx * dx + dy * dy + dz * dz <= (double)tol * tol && r < best) best = r;
            }
            if (best == sk::kNoFace) { rep.push_back(v); remap[v] = v; }
            else remap[v] = best;
        }
        CHECK(a.remap == remap);
    }
}

TEST_CASE("light in a face plane: tie rule (d == 0 is not lit), consistent across coplanar faces") {
    // Flat 4x4 grid in z = 0; light in the plane: no face lit, no silhouette.
    Mesh g;
    for (int y = 0; y <= 4; ++y)
        for (int x = 0; x <= 4; ++x) g.p.emplace_back(static_cast<float>(x), static_cast<float>(y), 0.0f);
    for (std::uint32_t y = 0; y < 4; ++y)
        for (std::uint32_t x = 0; x < 4; ++x) {
            const std::uint32_t a = y * 5 + x;
            g.i.insert(g.i.end(), {a, a + 1, a + 6, a, a + 6, a + 5});
        }
    const sk::EdgeAdjacency adj = sk::build_edge_adjacency(g.p.data(), g.p.size(), g.i.data(), g.i.size());
    for (const glm::vec4& L : {glm::vec4(2.5f, 7.0f, 0.0f, 1.0f), glm::vec4(1, 2, 0, 0), glm::vec4(2, 2, 0, 1)}) {
        const sk::Silhouette s = sk::extract_silhouette(adj, g.p.data(), g.p.size(), L);
        for (auto f : s.facing) CHECK(f == 0);
        CHECK(s.indices.empty());
        CHECK(to_edges(s.indices) == brute_silhouette(g, L));
    }
    // Cube, light in the plane of the top face (z = 1): top not lit; the side x = 1 lit.
    const Mesh c = cube();
    const sk::EdgeAdjacency ca = sk::build_edge_adjacency(c.p.data(), c.p.size(), c.i.data(), c.i.size());
    const glm::vec4 L(5.0f, 0.5f, 1.0f, 1.0f);
    const sk::Silhouette s = sk::extract_silhouette(ca, c.p.data(), c.p.size(), L);
    CHECK(to_edges(s.indices) == brute_silhouette(c, L));
    std::size_t lit = 0;
    for (auto f : s.facing) lit += f;
    CHECK(lit == 2); // only the two triangles of face x = 1
    CHECK(s.indices.size() == 8);
}

TEST_CASE("stiff: scale 1e-6 and 1e6, light at infinity, light behind, sliver triangles") {
    std::mt19937 rng(8);
    const Mesh base = torus(12, 9, 2.0f, 0.6f, &rng, 0.2f);
    for (int l = 0; l < 200; ++l) {
        const glm::vec4 L = random_light(rng, 6.0f);
        const sk::EdgeAdjacency a0 = sk::build_edge_adjacency(base.p.data(), base.p.size(), base.i.data(), base.i.size());
        const sk::Silhouette s0 = sk::extract_silhouette(a0, base.p.data(), base.p.size(), L);
        for (float scale : {0.0009765625f /* 2^-10, exact */, 1048576.0f /* 2^20 */}) {
            Mesh m = base;
            for (auto& v : m.p) v *= scale;
            const glm::vec4 Ls(glm::vec3(L) * (L.w == 0.0f ? 1.0f : scale), L.w);
            const sk::EdgeAdjacency a = sk::build_edge_adjacency(m.p.data(), m.p.size(), m.i.data(), m.i.size());
            const sk::Silhouette s = sk::extract_silhouette(a, m.p.data(), m.p.size(), Ls);
            CHECK(s.indices == s0.indices); // power-of-two scaling is exact: identical silhouettes
        }
        // Non power-of-two scales 1e-6 and 1e6: against brute force.
        for (float scale : {1e-6f, 1e6f}) {
            Mesh m = base;
            for (auto& v : m.p) v *= scale;
            const glm::vec4 Ls(glm::vec3(L) * (L.w == 0.0f ? 1.0f : scale), L.w);
            const sk::EdgeAdjacency a = sk::build_edge_adjacency(m.p.data(), m.p.size(), m.i.data(), m.i.size());
            CHECK(to_edges(sk::extract_silhouette(a, m.p.data(), m.p.size(), Ls).indices) == brute_silhouette(m, Ls));
        }
    }
    // Slivers: a needle triangle and a collinear (zero-area) triangle.
    const std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}, {0.5f, 1e-7f, 0}, {2, 0, 0}, {0, 1, 0}};
    const std::vector<std::uint32_t> i = {0, 1, 2, 0, 1, 3, 0, 3, 4};
    const sk::EdgeAdjacency a = sk::build_edge_adjacency(p.data(), p.size(), i.data(), i.size());
    CHECK(a.degenerate_triangles == 1); // (0, 1, 3) collinear
    CHECK(a.face_count() == 2);
    const sk::Silhouette s = sk::extract_silhouette(a, p.data(), p.size(), glm::vec4(0.3f, 0.3f, 2.0f, 1.0f));
    CHECK(to_edges(s.indices) == brute_silhouette(Mesh{p, i}, glm::vec4(0.3f, 0.3f, 2.0f, 1.0f)));
}

TEST_CASE("invalid input: statuses, empty input, NaN, buffer too small") {
    using S = sk::SilhouetteStatus;
    const Mesh c = cube();
    // Empty mesh is Ok.
    const sk::EdgeAdjacency e = sk::build_edge_adjacency(nullptr, 0, nullptr, 0);
    CHECK(e.status == S::Ok);
    CHECK(e.face_count() == 0);
    CHECK(sk::extract_silhouette(e, nullptr, 0, glm::vec4(0, 0, 1, 0)).status == S::Ok);
    CHECK(sk::build_edge_adjacency(nullptr, 3, c.i.data(), 3).status == S::InvalidArgument);
    CHECK(sk::build_edge_adjacency(c.p.data(), c.p.size(), nullptr, 3).status == S::InvalidArgument);
    CHECK(sk::build_edge_adjacency(c.p.data(), c.p.size(), c.i.data(), 4).status == S::IndexCountNotMultipleOf3);
    std::vector<std::uint32_t> bad = c.i;
    bad[5] = 8;
    CHECK(sk::build_edge_adjacency(c.p.data(), c.p.size(), bad.data(), bad.size()).status == S::IndexOutOfRange);
    bad[5] = 0xFFFFFFFFu;
    CHECK(sk::build_edge_adjacency(c.p.data(), c.p.size(), bad.data(), bad.size()).status == S::IndexOutOfRange);
    std::vector<glm::vec3> pn = c.p;
    pn[3].y = std::numeric_limits<float>::quiet_NaN();
    CHECK(sk::build_edge_adjacency(pn.data(), pn.size(), c.i.data(), c.i.size()).status == S::NonFinitePosition);
    pn[3].y = std::numeric_limits<float>::infinity();
    CHECK(sk::build_edge_adjacency(pn.data(), pn.size(), c.i.data(), c.i.size()).status == S::NonFinitePosition);
    sk::AdjacencyOptions o;
    o.weld_tolerance = std::numeric_limits<float>::quiet_NaN();
    CHECK(sk::build_edge_adjacency(c.p.data(), c.p.size(), c.i.data(), c.i.size(), o).status == S::InvalidTolerance);
    // Degenerate and duplicate counting.
    std::vector<std::uint32_t> d = c.i;
    d.insert(d.end(), {0, 0, 1, 2, 3, 2});     // two repeated-index triangles
    d.insert(d.end(), {2, 3, 0, 3, 0, 2});     // rotations of the first triangle (0 2 3): duplicates
    const sk::EdgeAdjacency da = sk::build_edge_adjacency(c.p.data(), c.p.size(), d.data(), d.size());
    CHECK(da.degenerate_triangles == 2);
    CHECK(da.duplicate_triangles == 2);
    CHECK(da.closed());
    // Light validation.
    const sk::EdgeAdjacency adj = sk::build_edge_adjacency(c.p.data(), c.p.size(), c.i.data(), c.i.size());
    std::vector<std::uint8_t> f(adj.face_count());
    CHECK(sk::compute_facing(adj, c.p.data(), c.p.size(), glm::vec4(0, 0, 0, 0), f.data(), f.size()).status == S::InvalidLight);
    CHECK(sk::compute_facing(adj, c.p.data(), c.p.size(), glm::vec4(0, 0, 1, -1), f.data(), f.size()).status == S::InvalidLight);
    CHECK(sk::compute_facing(adj, c.p.data(), c.p.size(), glm::vec4(std::numeric_limits<float>::quiet_NaN(), 0, 1, 1), f.data(), f.size()).status == S::InvalidLight);
    CHECK(sk::compute_facing(adj, c.p.data(), c.p.size(), glm::vec4(0, 0, 1, 0), f.data(), f.size() - 1).status == S::BufferTooSmall);
    CHECK(sk::compute_facing(adj, c.p.data(), 7, glm::vec4(0, 0, 1, 0), f.data(), f.size()).status == S::InvalidArgument);
    CHECK(sk::compute_facing(e, c.p.data(), 0, glm::vec4(0, 0, 1, 0), f.data(), f.size()).status == S::Ok);
    sk::EdgeAdjacency broken = sk::build_edge_adjacency(c.p.data(), c.p.size(), c.i.data(), 4);
    CHECK(sk::compute_facing(broken, c.p.data(), c.p.size(), glm::vec4(0, 0, 1, 0), f.data(), f.size()).status == S::InvalidAdjacency);
    // Buffer too small: needed count reported, nothing written past capacity.
    REQUIRE(sk::compute_facing(adj, c.p.data(), c.p.size(), glm::vec4(10, 20, 30, 1), f.data(), f.size()).status == S::Ok);
    std::vector<std::uint32_t> buf(2 * 3 + 2, 0xDEADBEEFu);
    std::vector<std::uint8_t> fl(4, 0xAB);
    const sk::SilhouetteResult r = sk::extract_silhouette(adj, f.data(), f.size(), buf.data(), fl.data(), 3);
    CHECK(r.status == S::BufferTooSmall);
    CHECK(r.edge_count == 6);
    CHECK(buf[6] == 0xDEADBEEFu);
    CHECK(buf[7] == 0xDEADBEEFu);
    CHECK(fl[3] == 0xAB);
    CHECK(sk::extract_silhouette(adj, f.data(), f.size() - 1, buf.data(), nullptr, 3).status == S::InvalidArgument);
    CHECK(sk::extract_silhouette(adj, f.data(), f.size(), nullptr, nullptr, 0).edge_count == 6);
}

TEST_CASE("property: chunked / parallel silhouettes equal extract_silhouette exactly (any chunk count, threads)") {
    // reference: the serial compute_facing + extract_silhouette (itself checked against brute force
    // above); chunk counts 1..97 (more chunks than edges included), serial and std::thread loops
    auto serial_for = [](std::size_t n, const auto& fn) {
        for (std::size_t i = n; i-- > 0;) fn(i);  // reverse order: chunks must not depend on each other
    };
    auto thread_for = [](std::size_t n, const auto& fn) {
        std::vector<std::thread> ts;
        for (std::size_t i = 0; i < n; ++i) ts.emplace_back([&fn, i] { fn(i); });
        for (auto& t : ts) t.join();
    };
    std::mt19937 rng(777);
    int cases = 0;
    for (int it = 0; it < 1200; ++it) {
        Mesh m;
        if (it % 4 == 0) {
            m = torus(6 + static_cast<int>(rng() % 20), 4 + static_cast<int>(rng() % 12), 3.f, 1.f, &rng, 0.2f);
        } else {
            const int nv = 4 + static_cast<int>(rng() % 30);
            std::uniform_real_distribution<float> u(-1.0f, 1.0f);
            for (int k = 0; k < nv; ++k) m.p.emplace_back(u(rng), u(rng), u(rng));
            const int nt = static_cast<int>(rng() % 60);
            for (int t = 0; t < 3 * nt; ++t) m.i.push_back(static_cast<std::uint32_t>(rng() % static_cast<unsigned>(nv)));
        }
        const sk::EdgeAdjacency adj = sk::build_edge_adjacency(m.p.data(), m.p.size(), m.i.data(), m.i.size(), no_weld());
        REQUIRE(adj.status == sk::SilhouetteStatus::Ok);
        const glm::vec4 L = random_light(rng, 4.0f);
        const sk::Silhouette ref = sk::extract_silhouette(adj, m.p.data(), m.p.size(), L);
        REQUIRE(ref.status == sk::SilhouetteStatus::Ok);
        std::size_t ref_boundary = 0, ref_nonmanifold = 0;
        for (std::uint8_t f : ref.flags) {
            ref_boundary += (f & sk::SilhouetteBoundary) != 0;
            ref_nonmanifold += (f & sk::SilhouetteNonManifold) != 0;
        }
        const std::size_t chunks = 1 + rng() % (it % 3 == 0 ? 97 : 8);
        const std::size_t cap = adj.max_silhouette_edges();
        std::vector<std::uint8_t> facing(adj.face_count(), 7);
        std::vector<std::uint32_t> idx(2 * cap + 2, 0xDEADBEEFu);
        std::vector<std::uint8_t> flags(cap + 1, 0xEE);
        std::vector<sk::SilhouetteResult> per(chunks);
        const sk::SilhouetteResult r =
            it % 2 ? sk::extract_silhouette_parallel(adj, m.p.data(), m.p.size(), L, facing.data(), facing.size(), idx.data(),
                                                     flags.data(), cap, per.data(), chunks, serial_for)
                   : sk::extract_silhouette_parallel(adj, m.p.data(), m.p.size(), L, facing.data(), facing.size(), idx.data(),
                                                     flags.data(), cap, per.data(), chunks, thread_for);
        REQUIRE(r.status == sk::SilhouetteStatus::Ok);
        CHECK(facing == ref.facing);
        REQUIRE(r.edge_count == ref.indices.size() / 2);
        CHECK(std::equal(ref.indices.begin(), ref.indices.end(), idx.begin()));
        CHECK(std::equal(ref.flags.begin(), ref.flags.end(), flags.begin()));
        CHECK(r.boundary_edges == ref_boundary);
        CHECK(r.nonmanifold_edges == ref_nonmanifold);
        CHECK(idx[2 * cap] == 0xDEADBEEFu);  // nothing written past the capacity
        // facing chunks: lit counts add up to the serial count, face counts to the face count
        std::size_t lit = 0, faces = 0;
        for (std::size_t c = 0; c < chunks; ++c) {
            const sk::FacingResult fr = sk::compute_facing_chunk(adj, m.p.data(), m.p.size(), L, facing.data(), facing.size(), c, chunks);
            REQUIRE(fr.status == sk::SilhouetteStatus::Ok);
            lit += fr.lit_faces;
            faces += fr.face_count;
        }
        CHECK(faces == adj.face_count());
        CHECK(lit == static_cast<std::size_t>(std::count(ref.facing.begin(), ref.facing.end(), 1)));
        ++cases;
    }
    CHECK(cases == 1200);
}

TEST_CASE("chunked silhouettes: invalid arguments and small buffers are reported") {
    const Mesh m = cube();
    const sk::EdgeAdjacency adj = sk::build_edge_adjacency(m.p.data(), m.p.size(), m.i.data(), m.i.size());
    REQUIRE(adj.status == sk::SilhouetteStatus::Ok);
    const glm::vec4 L(3.f, 4.f, 5.f, 1.f);
    std::vector<std::uint8_t> f(adj.face_count());
    std::vector<std::uint32_t> idx(2 * adj.max_silhouette_edges());
    const std::size_t cap = idx.size() / 2;
    CHECK(sk::compute_facing_chunk(adj, m.p.data(), m.p.size(), L, f.data(), f.size(), 2, 2).status ==
          sk::SilhouetteStatus::InvalidArgument);
    CHECK(sk::compute_facing_chunk(adj, m.p.data(), m.p.size(), L, f.data(), f.size(), 0, 0).status ==
          sk::SilhouetteStatus::InvalidArgument);
    CHECK(sk::compute_facing_chunk(adj, m.p.data(), m.p.size(), glm::vec4(0.f), f.data(), f.size(), 0, 1).status ==
          sk::SilhouetteStatus::InvalidLight);
    CHECK(sk::compute_facing_chunk(adj, m.p.data(), m.p.size(), L, f.data(), f.size() - 1, 0, 1).status ==
          sk::SilhouetteStatus::BufferTooSmall);
    sk::compute_facing(adj, m.p.data(), m.p.size(), L, f.data(), f.size());
    CHECK(sk::extract_silhouette_chunk(adj, f.data(), f.size(), idx.data(), nullptr, cap - 1, 0, 1).status ==
          sk::SilhouetteStatus::BufferTooSmall);
    CHECK(sk::extract_silhouette_chunk(adj, f.data(), f.size() - 1, idx.data(), nullptr, cap, 0, 1).status ==
          sk::SilhouetteStatus::InvalidArgument);
    CHECK(sk::extract_silhouette_chunk(adj, f.data(), f.size(), idx.data(), nullptr, cap, 3, 3).status ==
          sk::SilhouetteStatus::InvalidArgument);
    sk::SilhouetteResult bad;
    bad.status = sk::SilhouetteStatus::InvalidLight;
    CHECK(sk::compact_silhouette_chunks(adj, &bad, 1, idx.data(), nullptr, cap).status == sk::SilhouetteStatus::InvalidLight);
    CHECK(sk::compact_silhouette_chunks(adj, nullptr, 1, idx.data(), nullptr, cap).status ==
          sk::SilhouetteStatus::InvalidArgument);
    CHECK(sk::silhouette_chunk_offset(adj, 5, 2) == 0);
    std::size_t calls = 0;
    auto counting_for = [&calls](std::size_t n, const auto& fn) {
        for (std::size_t i = 0; i < n; ++i) fn(i);
        ++calls;
    };
    std::vector<sk::SilhouetteResult> per(4);
    CHECK(sk::extract_silhouette_parallel(adj, m.p.data(), m.p.size(), L, f.data(), f.size(), idx.data(), nullptr, cap - 1,
                                          per.data(), 4, counting_for)
              .status == sk::SilhouetteStatus::BufferTooSmall);
    CHECK(calls == 0);  // rejected before any work
    const sk::SilhouetteResult ok = sk::extract_silhouette_parallel(adj, m.p.data(), m.p.size(), L, f.data(), f.size(),
                                                                    idx.data(), nullptr, cap, per.data(), 4, counting_for);
    CHECK(ok.status == sk::SilhouetteStatus::Ok);
    CHECK(ok.edge_count == 6);  // a cube seen from a general point: a hexagon
    CHECK(calls == 2);          // facing, then silhouette
}
