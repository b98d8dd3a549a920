// The baseline of shadowkit-bench --compare: the edge-based CPU shadow-volume algorithm as bgfx's
// 14-shadowvolumes example describes it, written for this benchmark (no code copied):
//   load:  vertices welded (bgfx's example runs weldVertices, within an epsilon; here bit-identical
//          positions, as shadowkit's adjacency by default); per face a plane (float,
//          normalized normal + offset); per edge its two faces' planes,
//          stored with the edge (two float4 per edge), and whether each face traverses it reversed;
//          a face's edge shared with no other face keeps a zero second plane (as bgfx's loader).
//   frame: per edge, SSE2, two edges at a time (their four planes transposed into x / y / z / w
//          vectors): s_i = (plane_i . L > 0) xor reversed_i, k = 2 (s_0 + s_1) - 2 in {-2, 0, 2};
//          for k != 0 the edge's side quad: 4 vertices (position, extrusion flag, k) and the quad's
//          6 indices |k| = 2 times, winding by the sign of k (each side quad is drawn twice; the
//          stencil counts in steps of 2).
//          z-fail also: per face (SSE2, four faces at a time) the plane sign: lit faces into the
//          front cap, unlit faces into the back cap (extruded by the vertex shader), each twice, to
//          match the doubled side quads.
// Inexact (float planes): the facing of faces nearly edge-on to the light can be wrong; it is here
// for its speed only.
#pragma once

#include <emmintrin.h>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <unordered_map>
#include <vector>

namespace bgfx_style {

struct Plane {
    float v[4];
};

struct Edge {
    std::uint32_t i0, i1;
    std::uint8_t reversed[2];
    std::uint8_t faces;
};

struct SideVertex {
    float x, y, z, extrude, k;
};

struct Mesh {
    std::vector<Plane> face_planes;       // one per face (the caps)
    std::vector<std::uint32_t> faces;     // 3 per face
    std::vector<Edge> edges;
    std::vector<Plane> edge_planes;       // 2 per edge, 16-byte aligned by std::vector<Plane>'s allocator? see load
    const glm::vec3* positions = nullptr;
};

inline Plane plane_of(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
    glm::vec3 n(( b.y - a.y) * (c.z - a.z) - (b.z - a.z) * (c.y - a.y), (b.z - a.z) * (c.x - a.x) - (b.x - a.x) * (c.z - a.z),
                (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
    const float len = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
    if (len > 0.0f) n *= 1.0f / len;
    return Plane{{n.x, n.y, n.z, -(n.x * a.x + n.y * a.y + n.z * a.z)}};
}

// Load: face planes, edges with their two faces' planes (hash map keyed by the undirected edge).
inline Mesh load(const glm::vec3* positions, const std::uint32_t* indices, std::size_t index_count) {
    Mesh m;
    m.positions = positions;
    const std::size_t fc = index_count / 3;
    m.faces.assign(indices, indices + 3 * fc);
    m.face_planes.resize(fc);
    struct Slot {
        Edge e;
        Plane p[2];
    };
    // bgfx's example welds the vertices at load (weldVertices) and keys the edges by welded index, so
    // a mesh with split vertices (normals, UVs: a PLY or OBJ export) still shares its edges. Here:
    // bit-identical positions, each vertex mapped to the first vertex at its position. (Without it a
    // split-vertex mesh such as Wuson.ply shares almost no edge: about 6,100 side quads a frame
    // instead of 750, and a 3x slower frame.)
    struct PosKey {
        std::uint32_t x, y, z;
        bool operator==(const PosKey& o) const { return x == o.x && y == o.y && z == o.z; }
    };
    struct PosHash {
        std::size_t operator()(const PosKey& k) const {
            return static_cast<std::size_t>((std::uint64_t(k.x) * 0x9E3779B97F4A7C15ull) ^ (std::uint64_t(k.y) * 0xC2B2AE3D27D4EB4Full) ^
                                            (std::uint64_t(k.z) * 0x165667B19E3779F9ull));
        }
    };
    std::uint32_t vcount = 0;
    for (std::size_t i = 0; i < 3 * fc; ++i) vcount = std::max(vcount, indices[i] + 1);
    std::vector<std::uint32_t> weld(vcount);
    {
        std::unordered_map<PosKey, std::uint32_t, PosHash> first;
        first.reserve(vcount);
        for (std::uint32_t v = 0; v < vcount; ++v) {
            PosKey k;
            std::memcpy(&k.x, &positions[v].x, 4);
            std::memcpy(&k.y, &positions[v].y, 4);
            std::memcpy(&k.z, &positions[v].z, 4);
            weld[v] = first.emplace(k, v).first->second;
        }
    }
    std::unordered_map<std::uint64_t, std::uint32_t> map;
    map.reserve(3 * fc);
    std::vector<Slot> slots;
    slots.reserve(3 * fc / 2 + 16);
    for (std::size_t f = 0; f < fc; ++f) {
        const std::uint32_t* t = indices + 3 * f;
        const Plane p = plane_of(positions[t[0]], positions[t[1]], positions[t[2]]);
        m.face_planes[f] = p;
        for (int j = 0; j < 3; ++j) {
            const std::uint32_t u = weld[t[j]], v = weld[t[(j + 1) % 3]];
            const std::uint64_t key = u < v ? (std::uint64_t(u) << 32 | v) : (std::uint64_t(v) << 32 | u);
            auto it = map.find(key);
            if (it == map.end()) {
                Slot s{};
                s.e.i0 = u;
                s.e.i1 = v;
                s.e.reversed[0] = 0;
                s.e.faces = 1;
                s.p[0] = p;
                map.emplace(key, static_cast<std::uint32_t>(slots.size()));
                slots.push_back(s);
            } else {
                Slot& s = slots[it->second];
                if (s.e.faces < 2) {  // a third face on an edge is dropped (bgfx: two faces per edge)
                    s.e.reversed[1] = 1;
                    s.p[1] = p;
                    s.e.faces = 2;
                }
            }
        }
    }
    m.edges.resize(slots.size());
    m.edge_planes.resize(2 * slots.size());
    for (std::size_t i = 0; i < slots.size(); ++i) {
        m.edges[i] = slots[i].e;
        m.edge_planes[2 * i] = slots[i].p[0];
        m.edge_planes[2 * i + 1] = slots[i].p[1];
    }
    return m;
}

struct Output {
    std::vector<SideVertex> side_vertices;
    std::vector<std::uint32_t> side_indices, front_cap, back_cap;
    std::size_t nv = 0, ns = 0, nf = 0, nb = 0;  // elements written
};

// Sizes the output once for any light (no allocation per frame).
inline void reserve(const Mesh& m, Output& o) {
    o.side_vertices.resize(4 * m.edges.size() + 4);
    o.side_indices.resize(12 * m.edges.size() + 12);
    o.front_cap.resize(6 * (m.faces.size() / 3) + 6);
    o.back_cap.resize(6 * (m.faces.size() / 3) + 6);
}

inline void emit_side(const Mesh& m, const Edge& e, int k, Output& o) {
    const glm::vec3& a = m.positions[e.i0];
    const glm::vec3& b = m.positions[e.i1];
    const float kf = static_cast<float>(k);
    const std::uint32_t base = static_cast<std::uint32_t>(o.nv);
    SideVertex* v = o.side_vertices.data() + o.nv;
    v[0] = SideVertex{a.x, a.y, a.z, 0.0f, kf};
    v[1] = SideVertex{a.x, a.y, a.z, 1.0f, kf};
    v[2] = SideVertex{b.x, b.y, b.z, 0.0f, kf};
    v[3] = SideVertex{b.x, b.y, b.z, 1.0f, kf};
    o.nv += 4;
    const std::uint32_t wnd = k > 0 ? 1u : 0u;
    std::uint32_t* ix = o.side_indices.data() + o.ns;
    for (int r = 0, n = k < 0 ? -k : k; r < n; ++r, ix += 6) {
        ix[0] = base;
        ix[1] = base + 2 - wnd;
        ix[2] = base + 1 + wnd;
        ix[3] = base + 2;
        ix[4] = base + 3 - 2 * wnd;
        ix[5] = base + 1 + 2 * wnd;
        o.ns += 6;
    }
}

// One frame: side quads (and caps for z-fail) for light (x, y, z, w).
inline void frame(const Mesh& m, const glm::vec4& light, bool zfail, Output& o) {
    o.nv = o.ns = o.nf = o.nb = 0;
    const std::size_t ne = m.edges.size();
    const __m128 lx = _mm_set1_ps(light.x), ly = _mm_set1_ps(light.y), lz = _mm_set1_ps(light.z), lw = _mm_set1_ps(light.w);
    const __m128 zero = _mm_setzero_ps();
    const __m128i one = _mm_set1_epi32(1);
    std::size_t i = 0;
    for (; i + 2 <= ne; i += 2) {
        const Edge& e0 = m.edges[i];
        const Edge& e1 = m.edges[i + 1];
        const float* p = m.edge_planes[2 * i].v;  // p00 p01 p10 p11, 16 floats
        const __m128 a = _mm_loadu_ps(p), b = _mm_loadu_ps(p + 4), c = _mm_loadu_ps(p + 8), d = _mm_loadu_ps(p + 12);
        // transpose: lanes (edge0 face0, edge1 face0, edge0 face1, edge1 face1)
        const __m128 t0 = _mm_unpacklo_ps(a, c), t1 = _mm_unpackhi_ps(a, c), t2 = _mm_unpacklo_ps(b, d), t3 = _mm_unpackhi_ps(b, d);
        const __m128 vx = _mm_movelh_ps(t0, t2), vy = _mm_movehl_ps(t2, t0), vz = _mm_movelh_ps(t1, t3), vw = _mm_movehl_ps(t3, t1);
        const __m128 f = _mm_add_ps(_mm_add_ps(_mm_mul_ps(vx, lx), _mm_mul_ps(vy, ly)), _mm_add_ps(_mm_mul_ps(vz, lz), _mm_mul_ps(vw, lw)));
        const __m128i front = _mm_and_si128(_mm_castps_si128(_mm_cmpgt_ps(f, zero)), one);
        const __m128i rev = _mm_set_epi32(e1.reversed[1], e0.reversed[1], e1.reversed[0], e0.reversed[0]);
        const __m128i s = _mm_sub_epi32(_mm_slli_epi32(_mm_xor_si128(front, rev), 1), one);  // +-1 per face
        alignas(16) std::int32_t res[4];
        _mm_store_si128(reinterpret_cast<__m128i*>(res), s);
        for (int j = 0; j < 2; ++j) {
            const int k = res[j] + res[j + 2];
            if (k != 0) emit_side(m, m.edges[i + static_cast<std::size_t>(j)], k, o);
        }
    }
    for (; i < ne; ++i) {
        const Edge& e = m.edges[i];
        int s = 0;
        for (int j = 0; j < 2; ++j) {
            const float* p = m.edge_planes[2 * i + static_cast<std::size_t>(j)].v;
            const bool fr = p[0] * light.x + p[1] * light.y + p[2] * light.z + p[3] * light.w > 0.0f;
            s += (fr != (e.reversed[j] != 0)) ? 1 : 0;
        }
        const int k = 2 * s - 2;
        if (k != 0) emit_side(m, e, k, o);
    }
    if (!zfail) return;
    const std::size_t fc = m.faces.size() / 3;
    std::size_t f = 0;
    for (; f + 4 <= fc; f += 4) {
        const float* p = m.face_planes[f].v;
        const __m128 a = _mm_loadu_ps(p), b = _mm_loadu_ps(p + 4), c = _mm_loadu_ps(p + 8), d = _mm_loadu_ps(p + 12);
        const __m128 t0 = _mm_unpacklo_ps(a, b), t1 = _mm_unpackhi_ps(a, b), t2 = _mm_unpacklo_ps(c, d), t3 = _mm_unpackhi_ps(c, d);
        const __m128 vx = _mm_movelh_ps(t0, t2), vy = _mm_movehl_ps(t2, t0), vz = _mm_movelh_ps(t1, t3), vw = _mm_movehl_ps(t3, t1);
        const __m128 dd = _mm_add_ps(_mm_add_ps(_mm_mul_ps(vx, lx), _mm_mul_ps(vy, ly)), _mm_add_ps(_mm_mul_ps(vz, lz), _mm_mul_ps(vw, lw)));
        const int mask = _mm_movemask_ps(_mm_cmpgt_ps(dd, zero));
        for (int j = 0; j < 4; ++j) {
            const std::uint32_t* t = m.faces.data() + 3 * (f + static_cast<std::size_t>(j));
            std::uint32_t* out = (mask >> j) & 1 ? o.front_cap.data() + o.nf : o.back_cap.data() + o.nb;
            out[0] = t[0]; out[1] = t[1]; out[2] = t[2];
            out[3] = t[0]; out[4] = t[1]; out[5] = t[2];
            ((mask >> j) & 1 ? o.nf : o.nb) += 6;
        }
    }
    for (; f < fc; ++f) {
        const float* p = m.face_planes[f].v;
        const bool fr = p[0] * light.x + p[1] * light.y + p[2] * light.z + p[3] * light.w > 0.0f;
        const std::uint32_t* t = m.faces.data() + 3 * f;
        std::uint32_t* out = fr ? o.front_cap.data() + o.nf : o.back_cap.data() + o.nb;
        out[0] = t[0]; out[1] = t[1]; out[2] = t[2];
        out[3] = t[0]; out[4] = t[1]; out[5] = t[2];
        (fr ? o.nf : o.nb) += 6;
    }
}

// Bytes a frame reads: per edge its record and two planes; z-fail also per face its plane and indices.
inline std::size_t input_bytes(const Mesh& m, bool zfail) {
    return m.edges.size() * (sizeof(Edge) + 2 * sizeof(Plane)) + (zfail ? m.face_planes.size() * sizeof(Plane) + m.faces.size() * 4 : 0);
}

}  // namespace bgfx_style
