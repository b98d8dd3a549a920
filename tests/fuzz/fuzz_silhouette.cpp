// libFuzzer target for shadowkit/silhouette.hpp: arbitrary positions (NaN / Inf), indices (out of
// range), weld tolerances, lights and capacities. Invariants trap on violation.
#include <shadowkit/silhouette.hpp>

#include "fuzz_input.hpp"

#include <cstddef>
#include <cstdint>
#include <algorithm>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    namespace sk = shadowkit;
    shadowkit_fuzz::FuzzInput in(data, size);
    const std::uint8_t mode = in.u8();
    const std::size_t nv = in.size(47);
    const std::size_t ni = in.size(199);
    std::vector<glm::vec3> pos(nv);
    const bool small_grid = (mode & 1) != 0; // snap to a small integer grid: many shared / coplanar
    for (auto& v : pos) {
        if (small_grid) {
            const int x = in.range(0, 3), y = in.range(0, 3), z = in.range(0, 3);
            v = glm::vec3(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
        } else {
            v = in.vec3();
        }
    }
    std::vector<std::uint32_t> idx(ni);
    for (auto& i : idx) i = (mode & 2) ? in.u32() : in.range<std::uint32_t>(0, static_cast<std::uint32_t>(nv));
    sk::AdjacencyOptions o;
    o.weld_tolerance = (mode & 4) ? in.f32() : ((mode & 8) ? -1.0f : 0.0f);
    const glm::vec4 L(in.vec3(), (mode & 16) ? 0.0f : in.f32());
    const std::size_t cap = in.size(255);

    const sk::EdgeAdjacency adj = sk::build_edge_adjacency(nv ? pos.data() : nullptr, nv, ni ? idx.data() : nullptr, ni, o);
    if (adj.status != sk::SilhouetteStatus::Ok) {
        std::vector<std::uint8_t> f(4);
        if (sk::compute_facing(adj, pos.data(), nv, L, f.data(), f.size()).status != sk::SilhouetteStatus::InvalidAdjacency) __builtin_trap();
        return 0;
    }
    const std::size_t fc = adj.face_count();
    if (fc + adj.degenerate_triangles + adj.duplicate_triangles != ni / 3) __builtin_trap();
    for (std::size_t i = 0; i < nv; ++i) {
        if (adj.remap[i] > i || adj.remap[adj.remap[i]] != adj.remap[i]) __builtin_trap();
    }
    for (std::uint32_t v : adj.faces)
        if (v >= nv || adj.remap[v] != v) __builtin_trap();
    std::size_t halfedges = 0;
    for (const sk::AdjacencyEdge& e : adj.edges) {
        if (e.f0 >= fc || (e.f1 != sk::kNoFace && e.f1 >= fc) || e.v0 >= nv || e.v1 >= nv || e.v0 == e.v1) __builtin_trap();
        halfedges += e.f1 == sk::kNoFace ? 1 : 2;
    }
    for (const sk::NonManifoldEdge& e : adj.nonmanifold_edges) halfedges += e.count;
    if (halfedges != 3 * fc) __builtin_trap();

    std::vector<std::uint8_t> facing(fc + 1, 0xCD);
    const sk::FacingResult fr = sk::compute_facing(adj, pos.data(), nv, L, facing.data(), fc);
    if (fr.status != sk::SilhouetteStatus::Ok) {
        if (fr.status != sk::SilhouetteStatus::InvalidLight) __builtin_trap();
        return 0;
    }
    if (facing[fc] != 0xCD) __builtin_trap();
    for (std::size_t i = 0; i < fc; ++i)
        if (facing[i] > 1) __builtin_trap();
    std::vector<std::uint32_t> out(2 * cap + 2, 0xDEADBEEFu);
    std::vector<std::uint8_t> flags(cap + 1, 0xEE);
    const sk::SilhouetteResult r = sk::extract_silhouette(adj, facing.data(), fc, out.data(), flags.data(), cap);
    if (r.edge_count > adj.max_silhouette_edges()) __builtin_trap();
    if ((r.edge_count > cap) != (r.status == sk::SilhouetteStatus::BufferTooSmall)) __builtin_trap();
    if (out[2 * cap] != 0xDEADBEEFu || out[2 * cap + 1] != 0xDEADBEEFu || flags[cap] != 0xEE) __builtin_trap();
    const std::size_t written = r.edge_count < cap ? r.edge_count : cap;
    for (std::size_t k = 0; k < 2 * written; ++k)
        if (out[k] >= nv) __builtin_trap();
    // Closed meshes: silhouette loops are balanced.
    const sk::Silhouette s = sk::extract_silhouette(adj, pos.data(), nv, L);
    if (s.status != sk::SilhouetteStatus::Ok || s.indices.size() != 2 * r.edge_count) __builtin_trap();
    if (adj.closed()) {
        std::vector<long> bal(nv, 0);
        for (std::size_t k = 0; k < s.indices.size(); k += 2) { ++bal[s.indices[k]]; --bal[s.indices[k + 1]]; }
        for (long x : bal)
            if (x != 0) __builtin_trap();
    }
    // Chunked / parallel path (serial loop, chunks in reverse): identical to the serial result.
    const std::size_t chunks = 1 + in.size(40);
    const std::size_t pcap = adj.max_silhouette_edges() + in.size(3);
    std::vector<std::uint8_t> pf(fc + 1, 0xCD);
    std::vector<std::uint32_t> pidx(2 * pcap + 2, 0xDEADBEEFu);
    std::vector<std::uint8_t> pflags(pcap + 1, 0xEE);
    std::vector<sk::SilhouetteResult> per(chunks);
    auto rev_for = [](std::size_t n, const auto& fn) {
        for (std::size_t i = n; i-- > 0;) fn(i);
    };
    const sk::SilhouetteResult pr = sk::extract_silhouette_parallel(adj, pos.data(), nv, L, pf.data(), fc, pidx.data(),
                                                                    pflags.data(), pcap, per.data(), chunks, rev_for);
    if (pr.status != sk::SilhouetteStatus::Ok || pr.edge_count != r.edge_count) __builtin_trap();
    if (pf[fc] != 0xCD || pidx[2 * pcap] != 0xDEADBEEFu || pflags[pcap] != 0xEE) __builtin_trap();
    if (!std::equal(s.indices.begin(), s.indices.end(), pidx.begin()) || !std::equal(s.flags.begin(), s.flags.end(), pflags.begin()))
        __builtin_trap();
    // arbitrary chunk indices, capacities and (lying) chunk results are rejected, never overrun
    const std::size_t c = in.size(50), cc = in.size(50);
    (void)sk::compute_facing_chunk(adj, pos.data(), nv, L, pf.data(), in.size(fc + 2), c, cc);
    const std::size_t ccap = in.size(pcap);
    const sk::SilhouetteResult cr = sk::extract_silhouette_chunk(adj, pf.data(), fc, pidx.data(), pflags.data(), ccap, c, cc);
    if (cr.status == sk::SilhouetteStatus::Ok && cr.edge_count > adj.max_silhouette_edges()) __builtin_trap();
    for (auto& x : per) x.edge_count = in.size(pcap + 4);
    (void)sk::compact_silhouette_chunks(adj, per.data(), chunks, pidx.data(), pflags.data(), pcap);
    if (pidx[2 * pcap] != 0xDEADBEEFu || pflags[pcap] != 0xEE) __builtin_trap();

    // face_light_distance: the facing rule (lit iff d > 0) that compute_facing applied to every kept face.
    // Reversed winding negates d (exactly without FMA contraction; bound from the terms' magnitudes).
    const auto negated = [](double d2, double d, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c3, const glm::vec4& Lq) {
        const glm::dvec3 A(a), e1 = glm::dvec3(b) - A, e2 = glm::dvec3(c3) - A;
        const double lw = Lq.w;
        const glm::dvec3 q(double(Lq.x) - lw * A.x, double(Lq.y) - lw * A.y, double(Lq.z) - lw * A.z);
        const double m = (std::fabs(e1.x) + std::fabs(e1.y) + std::fabs(e1.z)) *
                         (std::fabs(e2.x) + std::fabs(e2.y) + std::fabs(e2.z)) * (std::fabs(q.x) + std::fabs(q.y) + std::fabs(q.z));
        return std::fabs(d2 + d) <= 1e-12 * m;
    };
    for (std::size_t f = 0; f < fc; ++f) {
        const glm::vec3 &A = pos[adj.faces[3 * f]], &B = pos[adj.faces[3 * f + 1]], &C = pos[adj.faces[3 * f + 2]];
        const double d = sk::face_light_distance(A, B, C, L);
        if (!std::isfinite(d)) __builtin_trap();  // finite positions and a valid light
        if ((d > 0.0) != (facing[f] != 0)) __builtin_trap();
        if (!negated(sk::face_light_distance(A, C, B, L), d, A, B, C, L)) __builtin_trap();  // reversed winding
    }
    // ... and on arbitrary triangles and lights (NaN/Inf, degenerate, w < 0)
    for (int it = 0; it < 4; ++it) {
        const bool raw = (in.u8() & 1) != 0;
        const glm::vec3 A = in.vec3(raw, 0.5f), B = in.vec3(raw, 0.5f);
        const std::uint8_t sel = in.u8();
        const glm::vec3 C = (sel & 1) ? A : ((sel & 2) ? B : in.vec3(raw, 0.5f));
        const glm::vec4 Lx((sel & 4) ? in.interesting_f32() : in.value(raw, 0.5f), in.value(raw, 0.5f),
                           in.value(raw, 0.5f), (sel & 8) ? 0.0f : ((sel & 16) ? in.interesting_f32() : in.value(raw, 0.5f)));
        const bool valid = sk::valid_light(Lx);
        const bool lfin = std::isfinite(Lx.x) && std::isfinite(Lx.y) && std::isfinite(Lx.z) && std::isfinite(Lx.w);
        if (valid != (lfin && Lx.w >= 0.0f && !(Lx.x == 0.0f && Lx.y == 0.0f && Lx.z == 0.0f && Lx.w == 0.0f)))
            __builtin_trap();
        const double d = sk::face_light_distance(A, B, C, Lx);
        const bool fin = shadowkit_fuzz::all_finite(A) && shadowkit_fuzz::all_finite(B) && shadowkit_fuzz::all_finite(C) && lfin;
        if (fin && !std::isfinite(d)) __builtin_trap();
        if (fin && (A == B || B == C || C == A) && d != 0.0) __builtin_trap();  // zero-area face: never lit
        if (fin && !negated(sk::face_light_distance(A, C, B, Lx), d, A, B, C, Lx)) __builtin_trap();
        // homogeneous light: scaling (x, y, z, w) by 2 doubles d exactly (no rounding in the scaling)
        const glm::vec4 L2 = 2.0f * Lx;
        if (fin && shadowkit_fuzz::all_finite(L2) && sk::face_light_distance(A, B, C, L2) != 2.0 * d) __builtin_trap();
    }
    // silhouette_chunk_offset: balanced split of the edge list, 0 for invalid arguments
    {
        const std::size_t ne = adj.edges.size();
        const std::size_t cnt = (in.u8() & 1) ? static_cast<std::size_t>(in.u64()) : in.size(70);
        const std::size_t probe = (in.u8() & 1) ? static_cast<std::size_t>(in.u64()) : in.size(72);
        const std::size_t off = sk::silhouette_chunk_offset(adj, probe, cnt);
        if ((cnt == 0 || probe >= cnt) && off != 0) __builtin_trap();
        if (off > ne) __builtin_trap();
        if (cnt != 0 && cnt <= 64) {
            std::size_t prev = sk::silhouette_chunk_offset(adj, 0, cnt);
            if (prev != 0) __builtin_trap();
            for (std::size_t c2 = 1; c2 <= cnt; ++c2) {
                const std::size_t next = c2 < cnt ? sk::silhouette_chunk_offset(adj, c2, cnt) : ne;
                if (next < prev || next - prev < ne / cnt || next - prev > ne / cnt + 1) __builtin_trap();
                prev = next;
            }
        }
    }
    return 0;
}
