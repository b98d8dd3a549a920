// Unit tests for the cached-plane fast path of shadowkit/silhouette.hpp (silhouette_build_planes,
// silhouette_compute_facing_planes[_chunk], silhouette_extract_planes[_chunk],
// silhouette_extract_parallel_planes, silhouette_extract_planes_side_quads; issue 16).
// Expected values: the exact reference path of the same header (silhouette_compute_facing, which the
// tests of test_silhouette.cpp check against brute force) and, for the facing bits, the independent
// big-integer evaluation of exact_facing_reference.hpp. The claim tested: the fast path's facing bits
// and every output buffer (silhouette edges, flags, counts, side quads, caps) are identical to the
// exact path's, for any mesh and light, including lights on face planes and vertices, 1e-6 / 1e6
// scales, meshes far from the origin and denormal coordinates.
#include <shadowkit/shadow_volume.hpp>
#include <shadowkit/silhouette.hpp>

#include "exact_facing_reference.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <random>
#include <thread>
#include <vector>

namespace sk = shadowkit;

namespace {

struct Mesh {
    std::vector<glm::vec3> p;
    std::vector<std::uint32_t> i;
};

// Closed torus grid (outward), optional noise, offset and scale.
Mesh torus(int R, int S, std::mt19937& rng, float noise, glm::vec3 offset, float scale) {
    Mesh m;
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int a = 0; a < R; ++a)
        for (int b = 0; b < S; ++b) {
            const float t = 6.2831853f * static_cast<float>(a) / static_cast<float>(R);
            const float s = 6.2831853f * static_cast<float>(b) / static_cast<float>(S);
            const float rr = 0.4f + noise * u(rng);
            const glm::vec3 q((1.0f + rr * std::cos(s)) * std::cos(t), (1.0f + rr * std::cos(s)) * std::sin(t), rr * std::sin(s));
            m.p.push_back(offset + scale * q);
        }
    auto id = [&](int a, int b) { return static_cast<std::uint32_t>(((a + R) % R) * S + ((b + S) % S)); };
    for (int a = 0; a < R; ++a)
        for (int b = 0; b < S; ++b) {
            const std::uint32_t v00 = id(a, b), v10 = id(a + 1, b), v11 = id(a + 1, b + 1), v01 = id(a, b + 1);
            m.i.insert(m.i.end(), {v00, v10, v11, v00, v11, v01});
        }
    return m;
}

// Random soup: kind 0 uniform floats, 1 a small integer grid (coplanar faces, shared planes), 2
// denormal coordinates, 3 mixed magnitudes (1e-30 .. 1e30 per coordinate).
Mesh soup(std::mt19937& rng, int kind, float scale, glm::vec3 offset) {
    Mesh m;
    const int nv = 4 + static_cast<int>(rng() % 30), nt = 1 + static_cast<int>(rng() % 60);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int k = 0; k < nv; ++k) {
        glm::vec3 q;
        if (kind == 1) q = glm::vec3(float(rng() % 4), float(rng() % 4), float(rng() % 4));
        else if (kind == 2) q = glm::vec3(u(rng), u(rng), u(rng)) * 1e-39f;
        else if (kind == 3) q = glm::vec3(u(rng) * std::pow(10.0f, float(int(rng() % 61) - 30)), u(rng) * std::pow(10.0f, float(int(rng() % 61) - 30)),
                                          u(rng) * std::pow(10.0f, float(int(rng() % 61) - 30)));
        else q = glm::vec3(u(rng), u(rng), u(rng));
        m.p.push_back(kind >= 2 ? q : offset + scale * q);
    }
    for (int t = 0; t < 3 * nt; ++t) m.i.push_back(static_cast<std::uint32_t>(rng() % static_cast<unsigned>(nv)));
    return m;
}

// A light of many kinds: random point / directional, on a vertex (w = 1 or 4), in a face's plane
// (on an edge's line, on a corner's opposite extension), parallel to a face, at 1e6, denormal, w
// not a power of two.
glm::vec4 some_light(std::mt19937& rng, const Mesh& m, float scale, glm::vec3 offset) {
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    const glm::vec3& a = m.p[rng() % m.p.size()];
    const glm::vec3& b = m.p[rng() % m.p.size()];
    const glm::vec3& c = m.p[rng() % m.p.size()];
    switch (rng() % 10) {
    case 0: return glm::vec4(a, 1.0f);                                   // on a vertex
    case 1: return glm::vec4(4.0f * a, 4.0f);                            // on a vertex, w = 4
    case 2: return glm::vec4(a + (a - b), 1.0f);                         // on an edge's line (rounded)
    case 3: return glm::vec4(b - a, 0.0f).x == 0.0f && b.y == a.y && b.z == a.z ? glm::vec4(1, 0, 0, 0) : glm::vec4(b - a, 0.0f); // parallel to an edge
    case 4: return glm::vec4(glm::cross(b - a, c - a), 0.0f) == glm::vec4(0.0f) ? glm::vec4(0, 1, 0, 0)
                                                                                  : glm::vec4(glm::cross(b - a, c - a), 0.0f);
    case 5: return glm::vec4(offset + 3.0f * scale * glm::vec3(u(rng), u(rng), u(rng)), 1.0f);
    case 6: return glm::vec4(glm::vec3(u(rng), u(rng), u(rng)) * 1e6f, 1.0f);
    case 7: return glm::vec4(glm::vec3(u(rng), u(rng), u(rng)) * 1e-40f, (rng() & 1) ? 0.0f : 1e-41f); // denormal
    case 8: return glm::vec4(offset + scale * glm::vec3(u(rng), u(rng), u(rng)), 0.3f);                // w not a power of two
    default: return glm::vec4(u(rng), u(rng), u(rng), 0.0f);                                            // directional
    }
}

// Everything the exact path and the fast path output for one light: identical or the test fails.
void check_same(const Mesh& m, const sk::SilhouetteAdjacency& adj, const sk::SilhouettePlanes& pl, const glm::vec4& L,
                std::size_t& checked_faces, std::size_t& lit_total) {
    if (!sk::silhouette_valid_light(L)) return;
    const std::size_t fc = adj.face_count();
    std::vector<std::uint8_t> ref(fc + 1, 7), fast(fc + 1, 9);
    const sk::SilhouetteFacing fr = sk::silhouette_compute_facing(adj, m.p.data(), m.p.size(), L, ref.data(), fc);
    const sk::SilhouetteFacing ff = sk::silhouette_compute_facing_planes(adj, pl, L, fast.data(), fc);
    REQUIRE(fr.status == sk::Status::Ok);
    REQUIRE(ff.status == sk::Status::Ok);
    CHECK(ff.count == fr.count);
    CHECK(ff.lit_faces == fr.lit_faces);
    CHECK(fast[fc] == 9);  // nothing past the capacity
    for (std::size_t f = 0; f < fc; ++f) {
        if (fast[f] != ref[f]) {
            const glm::vec3 &A = m.p[adj.faces[3 * f]], &B = m.p[adj.faces[3 * f + 1]], &C = m.p[adj.faces[3 * f + 2]];
            FAIL_CHECK("face " << f << " fast " << int(fast[f]) << " exact " << int(ref[f]) << " independent "
                                << exact_ref::facing_sign(A, B, C, L) << " light " << L.x << " " << L.y << " " << L.z << " " << L.w);
        }
    }
    checked_faces += fc;
    lit_total += ff.lit_faces;
    // silhouettes: indices, flags, counts
    const std::size_t cap = sk::silhouette_indices_capacity(adj);
    std::vector<std::uint32_t> si(cap + 1, 0xABu), fi(cap + 1, 0xCDu);
    std::vector<std::uint8_t> sf(cap / 2 + 1, 3), ffl(cap / 2 + 1, 4);
    const sk::SilhouetteResult rs = sk::silhouette_extract(adj, ref.data(), fc, si.data(), cap, sf.data(), cap / 2);
    const sk::SilhouetteResult rf = sk::silhouette_extract_planes(adj, pl, fast.data(), fc, fi.data(), cap, ffl.data(), cap / 2);
    REQUIRE(rs.status == sk::Status::Ok);
    REQUIRE(rf.status == sk::Status::Ok);
    CHECK(rf.count == rs.count);
    CHECK(rf.needed == rs.needed);
    CHECK(rf.boundary_edges == rs.boundary_edges);
    CHECK(rf.nonmanifold_edges == rs.nonmanifold_edges);
    CHECK(std::equal(si.begin(), si.begin() + static_cast<std::ptrdiff_t>(rs.count), fi.begin()));
    CHECK(std::equal(sf.begin(), sf.begin() + static_cast<std::ptrdiff_t>(rs.count / 2), ffl.begin()));
    CHECK(fi[cap] == 0xCDu);
    // the volume index buffers built from both: identical
    const std::size_t vcap = sk::volume_indices_capacity(cap, adj.faces.size());
    std::vector<std::uint32_t> vs(vcap), vf(vcap);
    for (int which = 0; which < 2; ++which) {
        std::vector<std::uint32_t>& v = which ? vf : vs;
        const std::vector<std::uint32_t>& s = which ? fi : si;
        const std::vector<std::uint8_t>& lit = which ? fast : ref;
        const sk::VolumeBuffer sq = sk::volume_build_side_quads(s.data(), rs.count, m.p.size(), v.data(), v.size());
        const sk::VolumeBuffer cp = sk::volume_build_caps(adj.faces.data(), adj.faces.size(), lit.data(), fc, m.p.size(),
                                                          sk::VolumeCapMode::LitOnly, true, v.data() + sq.count, v.size() - sq.count);
        REQUIRE(sq.status == sk::Status::Ok);
        REQUIRE(cp.status == sk::Status::Ok);
        v.resize(sq.count + cp.count);
    }
    CHECK(vs == vf);
    // the side quads straight from the fast extraction: the first 3 * rs.count elements of the exact
    // path's volume buffer (volume_build_side_quads of silhouette_extract's edges), nothing past them
    std::vector<std::uint32_t> q(3 * cap + 1, 0xFEu);
    const sk::SilhouetteResult rq = sk::silhouette_extract_planes_side_quads(adj, pl, fast.data(), fc, q.data(), 3 * cap);
    REQUIRE(rq.status == sk::Status::Ok);
    CHECK(rq.count == 3 * rs.count);
    CHECK(rq.needed == 3 * rs.needed);
    CHECK(rq.boundary_edges == rs.boundary_edges);
    CHECK(rq.nonmanifold_edges == rs.nonmanifold_edges);
    CHECK(std::equal(q.begin(), q.begin() + static_cast<std::ptrdiff_t>(rq.count), vs.begin()));
    CHECK(std::all_of(q.begin() + static_cast<std::ptrdiff_t>(rq.count), q.end(), [](std::uint32_t x) { return x == 0xFEu; }));
}

// Noisy open height field of nx * nz quads (boundary edges), optionally with `fins` extra triangles
// on interior edges (non-manifold: three faces on an edge) and a duplicated face. With `same_diagonal`
// every quad is split the same way: facing[f] = f % 2 then makes every interior edge a silhouette edge.
Mesh noisy_grid(int nx, int nz, int fins, std::mt19937& rng, bool same_diagonal = false) {
    Mesh m;
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int i = 0; i <= nx; ++i)
        for (int j = 0; j <= nz; ++j)
            m.p.emplace_back(static_cast<float>(i), 0.3f * u(rng), static_cast<float>(j));
    auto id = [&](int i, int j) { return static_cast<std::uint32_t>(i * (nz + 1) + j); };
    for (int i = 0; i < nx; ++i)
        for (int j = 0; j < nz; ++j) {
            const std::uint32_t a = id(i, j), b = id(i, j + 1), c = id(i + 1, j), d = id(i + 1, j + 1);
            if (same_diagonal || (rng() & 1)) m.i.insert(m.i.end(), {a, b, d, a, d, c});
            else m.i.insert(m.i.end(), {a, b, c, b, d, c});
        }
    for (int f = 0; f < fins; ++f) {
        const std::size_t t = rng() % (m.i.size() / 3);
        const std::uint32_t a = m.i[3 * t], b = m.i[3 * t + 1];
        m.p.push_back(0.5f * (m.p[a] + m.p[b]) + glm::vec3(0.1f * u(rng), 1.0f + u(rng), 0.1f * u(rng)));
        m.i.insert(m.i.end(), {a, b, static_cast<std::uint32_t>(m.p.size() - 1)});
    }
    if (fins > 0) m.i.insert(m.i.end(), {m.i[0], m.i[1], m.i[2]});
    return m;
}

} // namespace

TEST_CASE("property: cached-plane facing and silhouette equal the exact path bit for bit (thousands of meshes and lights)") {
    std::mt19937 rng(16016);
    std::size_t meshes = 0, lights = 0, faces = 0, lit = 0, exact_faces = 0;
    const float scales[] = {1e-6f, 1.0f, 1e6f};
    for (int it = 0; it < 2400; ++it) {
        const int kind = static_cast<int>(rng() % 6);
        const float scale = scales[rng() % 3];
        std::uniform_real_distribution<float> u(-1.0f, 1.0f);
        const glm::vec3 offset = (rng() % 3 == 0) ? glm::vec3(u(rng), u(rng), u(rng)) * scale * 1000.0f : glm::vec3(0.0f);
        const Mesh m = kind >= 4 ? torus(3 + static_cast<int>(rng() % 10), 3 + static_cast<int>(rng() % 8), rng, kind == 5 ? 0.05f : 0.0f,
                                         offset, scale)
                                 : soup(rng, kind, scale, offset);
        const sk::SilhouetteAdjacency adj = sk::silhouette_build_adjacency(m.p.data(), m.p.size(), m.i.data(), m.i.size());
        REQUIRE(adj.status == sk::Status::Ok);
        const sk::SilhouettePlanes pl = sk::silhouette_build_planes(adj, m.p.data(), m.p.size());
        REQUIRE(pl.status == sk::Status::Ok);
        REQUIRE(pl.face_count() == adj.face_count());
        exact_faces += pl.exact_faces;
        ++meshes;
        for (int k = 0; k < 4; ++k) {
            check_same(m, adj, pl, some_light(rng, m, scale, offset), faces, lit);
            ++lights;
        }
    }
    MESSAGE(meshes << " meshes, " << lights << " lights, " << faces << " face facings compared, " << lit << " lit, "
                   << exact_faces << " faces stored for the exact path only");
    CHECK(faces > 100000);
}

TEST_CASE("property: fast extraction and side quads on large open grids equal the exact path, any capacity, nothing past count") {
    // Meshes of 8 .. 5000 faces (many 64-edge groups, boundary edges in most groups, non-manifold
    // fins), facing from random lights, random bytes or a checkerboard (every interior edge on the
    // silhouette: full 64-edge groups), every buffer capacity from 0 to the full size: the fast pairs
    // / flags / side quads are a prefix of the exact path's (whole edges / quads), the statuses and
    // `needed` match, and no element past `count` is touched.
    std::mt19937 rng(160016);
    std::size_t configs = 0, edges_seen = 0, short_calls = 0;
    for (int it = 0; it < 160; ++it) {
        const Mesh m = noisy_grid(2 + static_cast<int>(rng() % 50), 2 + static_cast<int>(rng() % 50),
                                  (it % 4 == 0) ? static_cast<int>(rng() % 12) : 0, rng, it % 3 == 1);
        const sk::SilhouetteAdjacency adj = sk::silhouette_build_adjacency(m.p.data(), m.p.size(), m.i.data(), m.i.size());
        REQUIRE(adj.status == sk::Status::Ok);
        const sk::SilhouettePlanes pl = sk::silhouette_build_planes(adj, m.p.data(), m.p.size());
        REQUIRE(pl.status == sk::Status::Ok);
        const std::size_t fc = adj.face_count(), cap = sk::silhouette_indices_capacity(adj), n = m.p.size();
        std::vector<std::uint8_t> facing(fc);
        for (int k = 0; k < 3; ++k) {
            const glm::vec4 L = some_light(rng, m, 20.0f, glm::vec3(10.0f, 0.0f, 10.0f));
            if (!sk::silhouette_valid_light(L)) continue;
            REQUIRE(sk::silhouette_compute_facing_planes(adj, pl, L, facing.data(), fc).status == sk::Status::Ok);
            if (k == 1 && it % 3 == 1)  // checkerboard: the densest silhouette
                for (std::size_t f = 0; f < fc; ++f) facing[f] = static_cast<std::uint8_t>(f % 2);
            else if (k == 2 && it % 3 == 1)  // random bytes, any non-zero byte is lit
                for (auto& f : facing) f = static_cast<std::uint8_t>((rng() & 1) ? 1 + rng() % 255 : 0);
            else if (rng() % 5 == 0)
                for (auto& f : facing) f = static_cast<std::uint8_t>(f ? 1 + rng() % 255 : 0);
            std::vector<std::uint32_t> ref(cap);
            std::vector<std::uint8_t> rfl(cap / 2);
            const sk::SilhouetteResult rs = sk::silhouette_extract(adj, facing.data(), fc, ref.data(), cap, rfl.data(), cap / 2);
            REQUIRE(rs.status == sk::Status::Ok);
            std::vector<std::uint32_t> rq(3 * cap);
            REQUIRE(sk::volume_build_side_quads(ref.data(), rs.count, n, rq.data(), rq.size()).status == sk::Status::Ok);
            edges_seen += adj.edges.size();
            ++configs;
            for (int c = 0; c < 6; ++c) {
                // pairs + flags, capacities in elements (odd ones included), flags room from 0 up
                const std::size_t ic = c == 0 ? cap : rng() % (rs.count + 3), flc = c == 0 ? cap / 2 : ic / 2 + rng() % 3;
                std::vector<std::uint32_t> fi(ic + 8, 0xC0FFEEu);
                std::vector<std::uint8_t> ffl(flc + 8, 0xAAu);
                const sk::SilhouetteResult rf = sk::silhouette_extract_planes(adj, pl, facing.data(), fc, fi.data(), ic,
                                                                              (c % 2) ? ffl.data() : nullptr, (c % 2) ? flc : 0);
                const std::size_t room = std::min(ic / 2, (c % 2) ? flc : ic / 2), want = 2 * std::min(room, rs.count / 2);
                CHECK(rf.status == (want < rs.needed ? sk::Status::BufferTooSmall : sk::Status::Ok));
                CHECK(rf.count == want);
                CHECK(rf.needed == rs.needed);
                CHECK(rf.boundary_edges == rs.boundary_edges);
                CHECK(rf.nonmanifold_edges == rs.nonmanifold_edges);
                CHECK(std::equal(fi.begin(), fi.begin() + static_cast<std::ptrdiff_t>(want), ref.begin()));
                CHECK(std::all_of(fi.begin() + static_cast<std::ptrdiff_t>(want), fi.end(), [](std::uint32_t x) { return x == 0xC0FFEEu; }));
                if (c % 2) {
                    CHECK(std::equal(ffl.begin(), ffl.begin() + static_cast<std::ptrdiff_t>(want / 2), rfl.begin()));
                    CHECK(std::all_of(ffl.begin() + static_cast<std::ptrdiff_t>(want / 2), ffl.end(), [](std::uint8_t x) { return x == 0xAAu; }));
                }
                // side quads, any capacity: the whole quads that fit
                const std::size_t qc = c == 0 ? 3 * cap : rng() % (3 * rs.count + 7), qwant = 6 * std::min(qc / 6, rs.count / 2);
                std::vector<std::uint32_t> q(qc + 8, 0xC0FFEEu);
                const sk::SilhouetteResult rqf = sk::silhouette_extract_planes_side_quads(adj, pl, facing.data(), fc, q.data(), qc);
                CHECK(rqf.status == (qwant < 3 * rs.needed ? sk::Status::BufferTooSmall : sk::Status::Ok));
                CHECK(rqf.count == qwant);
                CHECK(rqf.needed == 3 * rs.needed);
                CHECK(rqf.boundary_edges == rs.boundary_edges);
                CHECK(rqf.nonmanifold_edges == rs.nonmanifold_edges);
                CHECK(std::equal(q.begin(), q.begin() + static_cast<std::ptrdiff_t>(qwant), rq.begin()));
                CHECK(std::all_of(q.begin() + static_cast<std::ptrdiff_t>(qwant), q.end(), [](std::uint32_t x) { return x == 0xC0FFEEu; }));
                short_calls += c > 0;
            }
            // chunked: any chunk count, chunks starting anywhere in a 64-edge group
            const std::size_t chunks = 1 + rng() % 13;
            std::vector<sk::SilhouetteResult> per(chunks);
            std::vector<std::uint32_t> ci(cap);
            std::vector<std::uint8_t> cf(cap / 2);
            for (std::size_t ch = 0; ch < chunks; ++ch)
                per[ch] = sk::silhouette_extract_planes_chunk(adj, pl, facing.data(), fc, ci.data(), cap, cf.data(), cap / 2, ch, chunks);
            const sk::SilhouetteResult rc = sk::silhouette_compact_chunks(adj, per.data(), chunks, ci.data(), cap, cf.data(), cap / 2);
            REQUIRE(rc.status == sk::Status::Ok);
            REQUIRE(rc.count == rs.count);
            CHECK(std::equal(ci.begin(), ci.begin() + static_cast<std::ptrdiff_t>(rs.count), ref.begin()));
            CHECK(std::equal(cf.begin(), cf.begin() + static_cast<std::ptrdiff_t>(rs.count / 2), rfl.begin()));
        }
    }
    MESSAGE(configs << " grid configurations, " << edges_seen << " edges, " << short_calls << " short-buffer calls");
    CHECK(configs > 300);
}

TEST_CASE("cached planes: every face's bit equals the independent big-integer sign, light on every vertex") {
    // a noisy torus far from the origin (the plane form n . l + c w cancels there: the local frame
    // and the filter must still give exact bits), the light on each vertex in turn: all faces around
    // it are d == 0 (not lit) and must come out of the exact path
    std::mt19937 rng(7);
    const Mesh m = torus(12, 8, rng, 0.05f, glm::vec3(1000.0f, -250.0f, 4096.0f), 3.0f);
    const sk::SilhouetteAdjacency adj = sk::silhouette_build_adjacency(m.p.data(), m.p.size(), m.i.data(), m.i.size());
    const sk::SilhouettePlanes pl = sk::silhouette_build_planes(adj, m.p.data(), m.p.size());
    REQUIRE(pl.status == sk::Status::Ok);
    std::vector<std::uint8_t> fast(adj.face_count());
    std::size_t zero = 0;
    for (std::size_t v = 0; v < m.p.size(); ++v)
        for (float w : {1.0f, 2.0f}) {
            const glm::vec4 L(m.p[v] * w, w);
            REQUIRE(sk::silhouette_compute_facing_planes(adj, pl, L, fast.data(), fast.size()).status == sk::Status::Ok);
            for (std::size_t f = 0; f < adj.face_count(); ++f) {
                const int s = exact_ref::facing_sign(m.p[adj.faces[3 * f]], m.p[adj.faces[3 * f + 1]], m.p[adj.faces[3 * f + 2]], L);
                zero += s == 0;
                CHECK((fast[f] != 0) == (s > 0));
            }
        }
    CHECK(zero >= 6 * 2 * m.p.size());  // each vertex has 6 faces, all exactly in the light's planes
}

TEST_CASE("regression (issue 16): a plane cached in float without a filter gets the light-on-vertex faces wrong") {
    // What the filter is for: the naive cached plane (float n, c = -n . A, sign of n . l + c w)
    // lights faces whose plane contains the light (d == 0 exactly) or misses the sign of tiny d; the
    // fast path never does.
    std::mt19937 rng(99);
    const Mesh m = torus(16, 12, rng, 0.05f, glm::vec3(37.0f, 11.0f, -5.0f), 1.0f);
    const sk::SilhouetteAdjacency adj = sk::silhouette_build_adjacency(m.p.data(), m.p.size(), m.i.data(), m.i.size());
    const sk::SilhouettePlanes pl = sk::silhouette_build_planes(adj, m.p.data(), m.p.size());
    std::vector<std::uint8_t> fast(adj.face_count());
    std::size_t naive_wrong = 0, fast_wrong = 0;
    for (std::size_t v = 0; v < m.p.size(); ++v) {
        const glm::vec4 L(m.p[v], 1.0f);
        sk::silhouette_compute_facing_planes(adj, pl, L, fast.data(), fast.size());
        for (std::size_t f = 0; f < adj.face_count(); ++f) {
            const glm::vec3 &A = m.p[adj.faces[3 * f]], &B = m.p[adj.faces[3 * f + 1]], &C = m.p[adj.faces[3 * f + 2]];
            const glm::vec3 n = glm::cross(B - A, C - A);
            const float naive = glm::dot(n, glm::vec3(L)) - glm::dot(n, A) * L.w;
            const bool truth = exact_ref::facing_sign(A, B, C, L) > 0;
            naive_wrong += (naive > 0.0f) != truth;
            fast_wrong += (fast[f] != 0) != truth;
        }
    }
    MESSAGE("naive float planes: " << naive_wrong << " wrong bits; fast path: " << fast_wrong);
    CHECK(naive_wrong > 0);
    CHECK(fast_wrong == 0);
}

TEST_CASE("property: chunked and parallel cached-plane silhouettes equal silhouette_extract (any chunk count, threads)") {
    std::mt19937 rng(4242);
    for (int it = 0; it < 300; ++it) {
        const Mesh m = (it % 3 == 0) ? torus(4 + it % 9, 3 + it % 7, rng, 0.1f, glm::vec3(0.0f), 1.0f)
                                     : soup(rng, static_cast<int>(rng() % 2), 1.0f, glm::vec3(0.0f));
        const sk::SilhouetteAdjacency adj = sk::silhouette_build_adjacency(m.p.data(), m.p.size(), m.i.data(), m.i.size());
        const sk::SilhouettePlanes pl = sk::silhouette_build_planes(adj, m.p.data(), m.p.size());
        const glm::vec4 L = some_light(rng, m, 1.0f, glm::vec3(0.0f));
        if (!sk::silhouette_valid_light(L)) continue;
        const sk::Silhouette ref = sk::silhouette_compute(adj, m.p.data(), m.p.size(), L);
        REQUIRE(ref.status == sk::Status::Ok);
        const std::size_t cap = sk::silhouette_indices_capacity(adj), fc = adj.face_count();
        const std::size_t chunks = 1 + rng() % 9;
        std::vector<std::uint8_t> facing(fc);
        std::vector<std::uint32_t> idx(cap);
        std::vector<std::uint8_t> flags(cap / 2);
        std::vector<sk::SilhouetteResult> per(chunks);
        auto threads = [](std::size_t n, const auto& fn) {
            std::vector<std::thread> t;
            for (std::size_t i = 0; i < n; ++i) t.emplace_back([&fn, i] { fn(i); });
            for (auto& x : t) x.join();
        };
        const sk::SilhouetteResult r = sk::silhouette_extract_parallel_planes(adj, pl, L, facing.data(), fc, idx.data(), cap,
                                                                              flags.data(), cap / 2, per.data(), chunks, threads);
        REQUIRE(r.status == sk::Status::Ok);
        CHECK(facing == ref.facing);
        REQUIRE(r.count == ref.indices.size());
        CHECK(std::equal(ref.indices.begin(), ref.indices.end(), idx.begin()));
        CHECK(std::equal(ref.flags.begin(), ref.flags.end(), flags.begin()));
        // the same with the chunk functions, run in reverse order
        std::vector<std::uint8_t> f2(fc, 5);
        for (std::size_t c = chunks; c-- > 0;)
            REQUIRE(sk::silhouette_compute_facing_planes_chunk(adj, pl, L, f2.data(), fc, c, chunks).status == sk::Status::Ok);
        CHECK(f2 == ref.facing);
    }
}

TEST_CASE("cached planes: statuses (mismatched adjacency, failed build, bad light, short buffers, NaN)") {
    std::mt19937 rng(1);
    const Mesh m = torus(6, 5, rng, 0.0f, glm::vec3(0.0f), 1.0f);
    const sk::SilhouetteAdjacency adj = sk::silhouette_build_adjacency(m.p.data(), m.p.size(), m.i.data(), m.i.size());
    const sk::SilhouettePlanes pl = sk::silhouette_build_planes(adj, m.p.data(), m.p.size());
    REQUIRE(pl.status == sk::Status::Ok);
    std::vector<std::uint8_t> facing(adj.face_count());
    const glm::vec4 L(3.0f, 2.0f, 1.0f, 1.0f);
    CHECK(sk::SilhouettePlanes{}.status == sk::Status::NotRun);
    CHECK(sk::silhouette_build_planes(adj, m.p.data(), m.p.size() - 1).status == sk::Status::InvalidArgument);
    CHECK(sk::silhouette_build_planes(adj, nullptr, m.p.size()).status == sk::Status::InvalidArgument);
    CHECK(sk::silhouette_build_planes(sk::SilhouetteAdjacency{}, m.p.data(), m.p.size()).status == sk::Status::InvalidArgument);
    std::vector<glm::vec3> bad = m.p;
    bad[3].y = std::nanf("");
    CHECK(sk::silhouette_build_planes(adj, bad.data(), bad.size()).status == sk::Status::NonFinite);
    CHECK(sk::silhouette_compute_facing_planes(adj, pl, glm::vec4(0.0f), facing.data(), facing.size()).status == sk::Status::InvalidLight);
    CHECK(sk::silhouette_compute_facing_planes(adj, pl, glm::vec4(1, 1, 1, -1), facing.data(), facing.size()).status ==
          sk::Status::InvalidLight);
    const sk::SilhouetteFacing small = sk::silhouette_compute_facing_planes(adj, pl, L, facing.data(), facing.size() - 1);
    CHECK(small.status == sk::Status::BufferTooSmall);
    CHECK(small.needed == adj.face_count());
    CHECK(sk::silhouette_compute_facing_planes(adj, pl, L, nullptr, 5).status == sk::Status::InvalidArgument);
    CHECK(sk::silhouette_compute_facing_planes(adj, sk::SilhouettePlanes{}, L, facing.data(), facing.size()).status ==
          sk::Status::InvalidArgument);
    // planes of another mesh
    const Mesh m2 = torus(7, 5, rng, 0.0f, glm::vec3(0.0f), 1.0f);
    const sk::SilhouetteAdjacency adj2 = sk::silhouette_build_adjacency(m2.p.data(), m2.p.size(), m2.i.data(), m2.i.size());
    CHECK(sk::silhouette_compute_facing_planes(adj2, pl, L, facing.data(), facing.size()).status == sk::Status::InvalidArgument);
    CHECK(sk::silhouette_compute_facing_planes_chunk(adj, pl, L, facing.data(), facing.size(), 2, 2).status == sk::Status::InvalidArgument);
    CHECK(sk::silhouette_compute_facing_planes_chunk(adj, pl, L, facing.data(), facing.size(), 0, 0).status == sk::Status::InvalidArgument);
    REQUIRE(sk::silhouette_compute_facing_planes(adj, pl, L, facing.data(), facing.size()).status == sk::Status::Ok);
    std::vector<std::uint32_t> idx(sk::silhouette_indices_capacity(adj));
    const sk::SilhouetteResult full = sk::silhouette_extract_planes(adj, pl, facing.data(), facing.size(), idx.data(), idx.size(), nullptr, 0);
    REQUIRE(full.status == sk::Status::Ok);
    REQUIRE(full.count >= 4);
    std::vector<std::uint32_t> shortbuf(full.count - 2 + 1, 0xEEu);
    const sk::SilhouetteResult part = sk::silhouette_extract_planes(adj, pl, facing.data(), facing.size(), shortbuf.data(),
                                                                    full.count - 2, nullptr, 0);
    CHECK(part.status == sk::Status::BufferTooSmall);
    CHECK(part.count == full.count - 2);
    CHECK(part.needed == full.count);
    CHECK(shortbuf.back() == 0xEEu);
    CHECK(std::equal(shortbuf.begin(), shortbuf.end() - 1, idx.begin()));
    CHECK(sk::silhouette_extract_planes(adj, pl, facing.data(), facing.size() - 1, idx.data(), idx.size(), nullptr, 0).status ==
          sk::Status::InvalidArgument);
    CHECK(sk::silhouette_extract_planes(adj2, pl, facing.data(), facing.size(), idx.data(), idx.size(), nullptr, 0).status ==
          sk::Status::InvalidArgument);
    CHECK(sk::silhouette_extract_planes_chunk(adj, pl, facing.data(), facing.size(), idx.data(), idx.size() - 1, nullptr, 0, 0, 1)
              .status == sk::Status::BufferTooSmall);
    // the side quads entry point: the same argument checks, no flags
    std::vector<std::uint32_t> quads(3 * idx.size());
    const sk::SilhouetteResult fq = sk::silhouette_extract_planes_side_quads(adj, pl, facing.data(), facing.size(), quads.data(), quads.size());
    CHECK(fq.status == sk::Status::Ok);
    CHECK(fq.count == 3 * full.count);
    CHECK(sk::silhouette_extract_planes_side_quads(adj, pl, facing.data(), facing.size() - 1, quads.data(), quads.size()).status ==
          sk::Status::InvalidArgument);
    CHECK(sk::silhouette_extract_planes_side_quads(adj2, pl, facing.data(), facing.size(), quads.data(), quads.size()).status ==
          sk::Status::InvalidArgument);
    CHECK(sk::silhouette_extract_planes_side_quads(adj, pl, nullptr, facing.size(), quads.data(), quads.size()).status ==
          sk::Status::InvalidArgument);
    CHECK(sk::silhouette_extract_planes_side_quads(adj, pl, facing.data(), facing.size(), nullptr, 6).status ==
          sk::Status::InvalidArgument);
    CHECK(sk::silhouette_extract_planes_side_quads(sk::SilhouetteAdjacency{}, pl, facing.data(), facing.size(), quads.data(),
                                                   quads.size()).status == sk::Status::InvalidArgument);
    const sk::SilhouetteResult none = sk::silhouette_extract_planes_side_quads(adj, pl, facing.data(), facing.size(), nullptr, 0);
    CHECK(none.status == sk::Status::BufferTooSmall);
    CHECK(none.count == 0);
    CHECK(none.needed == 3 * full.count);
    // an empty mesh is Ok
    const sk::SilhouetteAdjacency empty = sk::silhouette_build_adjacency(nullptr, 0, nullptr, 0);
    const sk::SilhouettePlanes pe = sk::silhouette_build_planes(empty, nullptr, 0);
    CHECK(pe.status == sk::Status::Ok);
    CHECK(sk::silhouette_compute_facing_planes(empty, pe, L, nullptr, 0).status == sk::Status::Ok);
    const sk::SilhouetteResult eq = sk::silhouette_extract_planes_side_quads(empty, pe, nullptr, 0, nullptr, 0);
    CHECK(eq.status == sk::Status::Ok);
    CHECK(eq.count == 0);
}

TEST_CASE("cached planes: the float filter's error bound (2^-20 ||L_f||_1) holds for every face, both summation orders") {
    // The fast path (SSE2, NEON or scalar) decides a face by d_float = P_f . L_f against
    // bound = 2^-20 ||L_f||_1 (silhouette.hpp, "cached face planes": proven |d_float - s d| <
    // 12.2 * 2^-24 ||L_f||_1 + 2^-121, with s > 0 the two power-of-two scalings). Checked here against d
    // evaluated in long double from the positions: d = n . (l - w A), n = (B - A) x (C - A), which is
    // P . L* of the derivation; s from the stored P_f and L_f. Both summation orders of the 4-term dot
    // product (the scalar tail's left to right, the SIMD paths' pairwise) are checked.
    std::mt19937 rng(1919);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    const float kProven = 12.2f;  // in units of 2^-24 ||L_f||_1
    double worst = 0.0;           // the largest error seen, same units
    std::size_t faces_checked = 0;
    for (int it = 0; it < 60; ++it) {
        const float scale = std::pow(10.0f, float(int(rng() % 9)) - 4.0f);  // 1e-4 .. 1e4
        const glm::vec3 offset = glm::vec3(u(rng), u(rng), u(rng)) * (it % 3 == 0 ? 1e5f : 10.0f);
        // tori (closed) and slivers (open: random triangles, some nearly flat), coordinates within a
        // few binades of each other so that the long double reference is exact to far below 2^-24
        Mesh m = torus(12, 10, rng, 0.1f, offset, scale);
        if (it % 2 == 1) {
            m = Mesh{};
            for (int t = 0; t < 80; ++t) {
                const glm::vec3 a = offset + glm::vec3(u(rng), u(rng), u(rng)) * scale;
                const glm::vec3 d1 = glm::vec3(u(rng), u(rng), u(rng)) * scale, d2 = glm::vec3(u(rng), u(rng), u(rng)) * scale;
                const float flat = t % 4 == 0 ? 1e-4f : 1.0f;
                for (const glm::vec3& q : {a, a + d1, a + d1 * 0.5f + d2 * flat}) m.p.push_back(q);
                for (int c = 0; c < 3; ++c) m.i.push_back(static_cast<std::uint32_t>(3 * t + c));
            }
        }
        const sk::SilhouetteAdjacency adj = sk::silhouette_build_adjacency(m.p.data(), m.p.size(), m.i.data(), m.i.size());
        REQUIRE(adj.status == sk::Status::Ok);
        const sk::SilhouettePlanes pl = sk::silhouette_build_planes(adj, m.p.data(), m.p.size());
        REQUIRE(pl.status == sk::Status::Ok);
        for (int k = 0; k < 8; ++k) {
            glm::vec4 L(offset + glm::vec3(u(rng), u(rng), u(rng)) * scale * 3.0f, 1.0f);
            if (k == 1) L = glm::vec4(u(rng), u(rng), u(rng), 0.0f);                   // directional
            if (k == 2) L = glm::vec4(m.p[rng() % m.p.size()], 1.0f);                 // on a vertex
            if (k == 3) L = glm::vec4(offset + glm::vec3(1e3f, -2e3f, 5e2f) * scale, 1.0f);  // far
            float Lf[4], bound = 0.0f;
            sk::detail::sil_planes_light(pl, L, Lf, &bound);
            const long double Ls[4] = {(long double)L.x - (long double)L.w * pl.origin.x, (long double)L.y - (long double)L.w * pl.origin.y,
                                       (long double)L.z - (long double)L.w * pl.origin.z, (long double)L.w * pl.scale};
            long double lmax = 0.0L, lfmax = 0.0L;
            float l1 = 0.0f;
            for (int c = 0; c < 4; ++c) {
                lmax = std::max(lmax, std::fabs(Ls[c]));
                lfmax = std::max(lfmax, (long double)std::fabs(Lf[c]));
                l1 += std::fabs(Lf[c]);
            }
            const double unit = std::ldexp(double(l1), -24);
            // the bound the code uses exceeds the proven error
            CHECK(double(bound) >= 16.0 * unit);
            CHECK(double(bound) > double(kProven) * unit + std::ldexp(1.0, -121));
            const long double sL = std::exp2(std::round(std::log2(lfmax / lmax)));
            for (std::size_t f = 0; f < pl.face_count(); ++f) {
                const float P[4] = {pl.plane_x[f], pl.plane_y[f], pl.plane_z[f], pl.plane_w[f]};
                if (P[0] == 0.0f && P[1] == 0.0f && P[2] == 0.0f && P[3] == 0.0f) continue;  // always exact
                const glm::vec3& A = m.p[adj.faces[3 * f]];
                const glm::vec3& B = m.p[adj.faces[3 * f + 1]];
                const glm::vec3& C = m.p[adj.faces[3 * f + 2]];
                const long double e1[3] = {(long double)B.x - A.x, (long double)B.y - A.y, (long double)B.z - A.z};
                const long double e2[3] = {(long double)C.x - A.x, (long double)C.y - A.y, (long double)C.z - A.z};
                const long double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
                const long double O[3] = {pl.origin.x, pl.origin.y, pl.origin.z};
                const long double c = n[0] * (O[0] - A.x) + n[1] * (O[1] - A.y) + n[2] * (O[2] - A.z);
                const long double Pe[4] = {n[0], n[1], n[2], c / (long double)pl.scale};
                long double pmax = 0.0L, pfmax = 0.0L;
                for (int q = 0; q < 4; ++q) {
                    pmax = std::max(pmax, std::fabs(Pe[q]));
                    pfmax = std::max(pfmax, (long double)std::fabs(P[q]));
                }
                if (pmax == 0.0L) continue;
                const long double sP = std::exp2(std::round(std::log2(pfmax / pmax)));
                const long double d = Pe[0] * Ls[0] + Pe[1] * Ls[1] + Pe[2] * Ls[2] + Pe[3] * Ls[3];
                volatile float t0 = P[0] * Lf[0], t1 = P[1] * Lf[1], t2 = P[2] * Lf[2], t3 = P[3] * Lf[3];  // no contraction
                const float left = ((t0 + t1) + t2) + t3, pairwise = (t0 + t1) + (t2 + t3);
                for (float df : {left, pairwise}) {
                    const double err = double(std::fabs((long double)df - sP * sL * d));
                    worst = std::max(worst, err / unit);
                    CHECK(err <= double(kProven) * unit + std::ldexp(1.0, -121));
                }
                ++faces_checked;
            }
        }
    }
    MESSAGE(faces_checked, " face-light pairs: the largest filter error was ", worst,
            " x 2^-24 ||L_f||_1 (proven < 12.2, the code's bound 16)");
    CHECK(faces_checked > 20000);
}

namespace {

// An open box of five flat grids (k x k quads a side, every vertex on an integer lattice: each side
// one exact plane, the top open) plus `folds` folded-back triangles on rim edges: on a rim edge
// (a, b) of face (a, b, c) the face (b, a, d), d = (a + c) / 2 (exactly in the side's axis-aligned
// plane, on c's side of the edge): the same plane, the opposite normal (a flipped class member).
Mesh lattice_box(int k, int folds, std::mt19937& rng, float scale, glm::vec3 offset) {
    Mesh m;
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side) {
            if (axis == 1 && side == 1) continue;  // open top
            const std::uint32_t base = static_cast<std::uint32_t>(m.p.size());
            for (int i = 0; i <= k; ++i)
                for (int j = 0; j <= k; ++j) {
                    glm::vec3 p(0.0f);
                    p[axis] = static_cast<float>(side * k);
                    p[(axis + 1) % 3] = static_cast<float>(i);
                    p[(axis + 2) % 3] = static_cast<float>(j);
                    m.p.push_back(p * scale + offset);
                }
            auto id = [&](int i, int j) { return base + static_cast<std::uint32_t>(i * (k + 1) + j); };
            for (int i = 0; i < k; ++i)
                for (int j = 0; j < k; ++j) {
                    const std::uint32_t a = id(i, j), b = id(i, j + 1), c = id(i + 1, j), d = id(i + 1, j + 1);
                    if (side) m.i.insert(m.i.end(), {a, b, d, a, d, c});
                    else m.i.insert(m.i.end(), {a, d, b, a, c, d});
                }
        }
    // rim edges: directed edges (a, b) of a face whose reverse no face has, with the face's third vertex
    std::vector<std::array<std::uint32_t, 3>> rim;
    const std::size_t faces = m.i.size() / 3;
    for (std::size_t t = 0; t < faces; ++t)
        for (int e = 0; e < 3; ++e) {
            const std::uint32_t a = m.i[3 * t + std::size_t(e)], b = m.i[3 * t + std::size_t((e + 1) % 3)],
                                c = m.i[3 * t + std::size_t((e + 2) % 3)];
            bool shared = false;
            for (std::size_t u = 0; u < faces && !shared; ++u)
                for (int g = 0; g < 3; ++g)
                    if (m.i[3 * u + std::size_t(g)] == b && m.i[3 * u + std::size_t((g + 1) % 3)] == a) shared = true;
            if (!shared) rim.push_back({a, b, c});
        }
    std::shuffle(rim.begin(), rim.end(), rng);
    for (int f = 0; f < folds && f < static_cast<int>(rim.size()); ++f) {
        const auto& r = rim[std::size_t(f)];
        m.p.push_back(0.5f * (m.p[r[0]] + m.p[r[2]]));
        m.i.insert(m.i.end(), {r[1], r[0], static_cast<std::uint32_t>(m.p.size() - 1)});
    }
    return m;
}

} // namespace

TEST_CASE("cached planes: the exact stage runs once per plane, not per face, when a light is in a flat region's plane (issue #27 item 7)") {
    // The worst case of the issue: 51,200 faces on the plane y = 3x + 5z with the light in it took the
    // exact stage for every face (130x the generic case). Faces joined by exactly coplanar edges form
    // one plane class; the exact predicate runs once per class in a row.
    Mesh g;
    const int n = 160;
    for (int i = 0; i <= n; ++i)
        for (int k = 0; k <= n; ++k) g.p.emplace_back(float(i), float(3 * i + 5 * k), float(k));
    for (int i = 0; i < n; ++i)
        for (int k = 0; k < n; ++k) {
            const std::uint32_t a = std::uint32_t(i * (n + 1) + k), b = a + 1, c = a + std::uint32_t(n + 1), d = c + 1;
            g.i.insert(g.i.end(), {a, b, c, b, d, c});
        }
    const sk::SilhouetteAdjacency adj = sk::silhouette_build_adjacency(g.p.data(), g.p.size(), g.i.data(), g.i.size());
    const sk::SilhouettePlanes pl = sk::silhouette_build_planes(adj, g.p.data(), g.p.size());
    REQUIRE(pl.status == sk::Status::Ok);
    REQUIRE(adj.face_count() == 51200);
    // one class: every face's root is face 0, none flipped (a consistently wound flat grid)
    CHECK(std::all_of(pl.plane_class.begin(), pl.plane_class.end(), [](std::uint32_t c) { return c == 0u; }));
    std::vector<std::uint8_t> fast(adj.face_count()), ref(adj.face_count());
    const glm::vec4 lights[] = {glm::vec4(-7.0f, 3.0f * -7.0f + 5.0f * 3.0f, 3.0f, 1.0f),  // in the plane
                                glm::vec4(1.0f, 3.0f, 0.0f, 0.0f),                        // parallel to it
                                glm::vec4(80.0f, 940.0f, 80.0f, 1.0f)};                   // above it
    for (const glm::vec4& L : lights) {
        const sk::SilhouetteFacing rf = sk::silhouette_compute_facing_planes(adj, pl, L, fast.data(), fast.size());
        const sk::SilhouetteFacing rr = sk::silhouette_compute_facing(adj, g.p.data(), g.p.size(), L, ref.data(), ref.size());
        REQUIRE(rf.status == sk::Status::Ok);
        REQUIRE(rr.status == sk::Status::Ok);
        CHECK(fast == ref);
        CHECK(rf.lit_faces == rr.lit_faces);
        INFO("light " << L.x << " " << L.y << " " << L.z << " " << L.w);
        CHECK(rf.exact_evaluations <= 1u);  // was one per face: 51,200
    }
    REQUIRE(sk::silhouette_compute_facing_planes(adj, pl, lights[0], fast.data(), fast.size()).lit_faces == 0u);  // d == 0: unlit
}

TEST_CASE("property: plane classes (lattice boxes with folded-back faces, lights in their planes) keep the exact bits") {
    // Six exact planes per box, folds in them with the opposite normal (flipped class members), lights
    // on lattice points (in one, two or three of the planes), directional lights parallel to sides,
    // and random ones; every bit equals the independent big-integer sign and the per-face exact path,
    // serial and chunked, and the exact stage runs at most once per class met in a row.
    std::mt19937 rng(2707);
    std::size_t compared = 0, zero = 0, flipped = 0, evaluations = 0, undecided_faces = 0;
    const float scales[] = {1e-6f, 1.0f, 1e6f};
    for (int it = 0; it < 300; ++it) {
        const int k = 1 + static_cast<int>(rng() % 6);
        const float scale = scales[rng() % 3];
        const glm::vec3 offset = (rng() % 2) ? glm::vec3(float(rng() % 64), -float(rng() % 64), float(rng() % 64)) * scale : glm::vec3(0.0f);
        const Mesh m = lattice_box(k, static_cast<int>(rng() % 6), rng, scale, offset);
        const sk::SilhouetteAdjacency adj = sk::silhouette_build_adjacency(m.p.data(), m.p.size(), m.i.data(), m.i.size());
        REQUIRE(adj.status == sk::Status::Ok);
        const sk::SilhouettePlanes pl = sk::silhouette_build_planes(adj, m.p.data(), m.p.size());
        REQUIRE(pl.status == sk::Status::Ok);
        for (std::uint32_t c : pl.plane_class) flipped += (c >> 31);
        const std::size_t fc = adj.face_count();
        std::vector<std::uint8_t> fast(fc), ref(fc), chunked(fc);
        for (int l = 0; l < 12; ++l) {
            glm::vec4 L;
            const int kind = static_cast<int>(rng() % 5);
            if (kind == 0) L = glm::vec4(m.p[rng() % m.p.size()], 1.0f);  // on a lattice point: in up to three planes
            else if (kind == 4) {  // one ulp off a lattice point across an axis: d tiny, not 0 (the filter cannot tell)
                glm::vec3 p = m.p[rng() % m.p.size()];
                const int a = static_cast<int>(rng() % 3);
                p[a] = std::nextafter(p[a], (rng() & 1) ? INFINITY : -INFINITY);
                L = glm::vec4(p, 1.0f);
            }
            else if (kind == 1) {                                        // parallel to a side
                glm::vec3 d(0.0f);
                d[static_cast<int>(rng() % 3)] = (rng() & 1) ? 1.0f : -1.0f;
                d[static_cast<int>(rng() % 3)] += 0.5f;
                L = glm::vec4(d, 0.0f);
            } else if (kind == 2) {  // in a side's plane, off the box
                glm::vec3 p = glm::vec3(float(rng() % 9) - 1.0f, float(rng() % 9) - 1.0f, float(rng() % 9) - 1.0f);
                p[static_cast<int>(rng() % 3)] = float((rng() & 1) * static_cast<unsigned>(k));
                L = glm::vec4(p * scale + offset, 1.0f);
            } else {
                std::uniform_real_distribution<float> u(-3.0f, 3.0f);
                L = glm::vec4(glm::vec3(u(rng), u(rng), u(rng)) * float(k) * scale + offset, 1.0f);
            }
            const sk::SilhouetteFacing rf = sk::silhouette_compute_facing_planes(adj, pl, L, fast.data(), fc);
            REQUIRE(rf.status == sk::Status::Ok);
            REQUIRE(sk::silhouette_compute_facing(adj, m.p.data(), m.p.size(), L, ref.data(), fc).status == sk::Status::Ok);
            CHECK(fast == ref);
            const std::size_t chunks = 1 + rng() % 5;
            for (std::size_t c = 0; c < chunks; ++c)
                REQUIRE(sk::silhouette_compute_facing_planes_chunk(adj, pl, L, chunked.data(), fc, c, chunks).status == sk::Status::Ok);
            CHECK(chunked == ref);
            std::size_t classes_undecided = 0, last = 0xFFFFFFFFu;
            for (std::size_t f = 0; f < fc; ++f) {
                const int s = exact_ref::facing_sign(m.p[adj.faces[3 * f]], m.p[adj.faces[3 * f + 1]], m.p[adj.faces[3 * f + 2]], L);
                zero += s == 0;
                CHECK((fast[f] != 0) == (s > 0));
                ++compared;
                if (s == 0) {  // surely undecided by the filter: one run per change of class
                    ++undecided_faces;
                    if ((pl.plane_class[f] & 0x7FFFFFFFu) != last) ++classes_undecided;
                    last = pl.plane_class[f] & 0x7FFFFFFFu;
                }
            }
            evaluations += rf.exact_evaluations;
            CHECK(rf.exact_evaluations <= fc);
        }
    }
    MESSAGE(compared << " facings compared, " << zero << " with d == 0 (light in the face's plane), " << flipped
                     << " flipped class members, " << evaluations << " exact runs for " << undecided_faces << " faces with d == 0");
    CHECK(zero > 10000);
    CHECK(flipped > 100);
    CHECK(evaluations * 4 < undecided_faces);  // the classes share the exact stage
}
