// libFuzzer target for shadowkit/silhouette.hpp: arbitrary positions (NaN / Inf), indices (out of
// range), weld tolerances, lights and capacities. Invariants trap on violation: Ok only with valid
// outputs, count <= capacity, count == needed when Ok, nothing written past a capacity, the
// chunked path identical to the serial one, the facing filter equal to the exact fallback, and the
// cached-plane fast path (silhouette_build_planes, *_planes, *_planes_chunk, and the side quads of
// silhouette_extract_planes_side_quads against shadow_volume.hpp's volume_build_side_quads) identical
// to the exact path.
#include <shadowkit/shadow_volume.hpp>
#include <shadowkit/silhouette.hpp>

#include "fuzz_input.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <map>
#include <utility>
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
    sk::SilhouetteAdjacencyOptions o;
    o.weld_tolerance = (mode & 4) ? in.f32() : ((mode & 8) ? -1.0f : 0.0f);
    // the light: raw, or exactly on a vertex (w = 1 or a power of two), or directional
    glm::vec4 L(in.vec3(), (mode & 16) ? 0.0f : in.f32());
    const std::uint8_t lsel = in.u8();
    if ((lsel & 3) == 1 && nv > 0) L = glm::vec4(pos[lsel % nv], 1.0f);
    if ((lsel & 3) == 2 && nv > 0) L = glm::vec4(pos[lsel % nv] * 4.0f, 4.0f);
    const std::size_t cap = in.size(255);

    const sk::SilhouetteAdjacency adj = sk::silhouette_build_adjacency(nv ? pos.data() : nullptr, nv, ni ? idx.data() : nullptr, ni, o);

    shadowkit_fuzz::check_detail(adj);
    // null pointers with non-zero counts are rejected
    if (nv > 0 && sk::silhouette_build_adjacency(nullptr, nv, idx.data(), ni, o).status != sk::Status::InvalidArgument) __builtin_trap();
    if (ni > 0 && sk::silhouette_build_adjacency(pos.data(), nv, nullptr, ni, o).status != sk::Status::InvalidArgument) __builtin_trap();
    if (adj.status == sk::Status::NotRun) __builtin_trap();
    if (adj.status != sk::Status::Ok) {
        std::vector<std::uint8_t> f(4);
        if (sk::silhouette_compute_facing(adj, pos.data(), nv, L, f.data(), f.size()).status != sk::Status::InvalidArgument) __builtin_trap();
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
    for (const sk::SilhouetteEdge& e : adj.edges) {
        if (e.f0 >= fc || (e.f1 != sk::kSilhouetteNoFace && e.f1 >= fc) || e.v0 >= nv || e.v1 >= nv || e.v0 == e.v1) __builtin_trap();
        halfedges += e.f1 == sk::kSilhouetteNoFace ? 1 : 2;
    }
    for (const sk::SilhouetteNonManifoldEdge& e : adj.nonmanifold_edges) halfedges += e.count;
    if (halfedges != 3 * fc) __builtin_trap();
    // every kept face has a non-zero exact cross product
    for (std::size_t f = 0; f < fc; ++f) {
        const glm::vec3 &A = pos[adj.faces[3 * f]], &B = pos[adj.faces[3 * f + 1]], &C = pos[adj.faces[3 * f + 2]];
        if (sk::detail::sil_face_sign_exact(A, B, C, glm::vec4(1, 0, 0, 0)) == 0 &&
            sk::detail::sil_face_sign_exact(A, B, C, glm::vec4(0, 1, 0, 0)) == 0 &&
            sk::detail::sil_face_sign_exact(A, B, C, glm::vec4(0, 0, 1, 0)) == 0)
            __builtin_trap();
    }

    std::vector<std::uint8_t> facing(fc + 1, 0xCD);
    const sk::SilhouetteFacing fr = sk::silhouette_compute_facing(adj, pos.data(), nv, L, facing.data(), fc);
    shadowkit_fuzz::check_detail(fr);
    if (fr.status != sk::Status::Ok) {
        if (fr.status != sk::Status::InvalidLight || sk::silhouette_valid_light(L)) __builtin_trap();
        return 0;
    }
    if (!sk::silhouette_valid_light(L) || fr.count != fc || fr.needed != fc || fr.lit_faces > fc) __builtin_trap();
    if (facing[fc] != 0xCD) __builtin_trap();
    for (std::size_t i = 0; i < fc; ++i)
        if (facing[i] > 1) __builtin_trap();
    // the facing bit is the exact sign: the filter never disagrees with the exact fallback; a face
    // incident to a vertex at the light (w = 1 or 4 above) is never lit
    for (std::size_t f = 0; f < fc; ++f) {
        const glm::vec3 &A = pos[adj.faces[3 * f]], &B = pos[adj.faces[3 * f + 1]], &C = pos[adj.faces[3 * f + 2]];
        const int exact = sk::detail::sil_face_sign_exact(A, B, C, L);
        if ((facing[f] != 0) != (exact > 0)) __builtin_trap();
        if ((lsel & 3) != 0 && (lsel & 3) != 3 && L.w > 0.0f) {
            const glm::vec3 at = glm::vec3(L) / L.w;
            if ((A == at || B == at || C == at) && facing[f]) __builtin_trap();
        }
    }
    std::vector<std::uint32_t> out(cap + 2, 0xDEADBEEFu);
    const std::size_t fcap = in.size(cap);
    std::vector<std::uint8_t> flags(fcap + 1, 0xEE);
    const sk::SilhouetteResult r = sk::silhouette_extract(adj, facing.data(), fc, out.data(), cap, flags.data(), fcap);
    shadowkit_fuzz::check_detail(r);
    if (r.needed > sk::silhouette_indices_capacity(adj) || r.count > cap || r.count % 2 != 0 || r.count / 2 > fcap) __builtin_trap();
    if ((r.count < r.needed) != (r.status == sk::Status::BufferTooSmall)) __builtin_trap();
    if (r.status != sk::Status::Ok && r.status != sk::Status::BufferTooSmall) __builtin_trap();
    if (out[cap] != 0xDEADBEEFu || flags[fcap] != 0xEE) __builtin_trap();
    for (std::size_t k = 0; k < r.count; ++k)
        if (out[k] >= nv) __builtin_trap();
    // the two-sided silhouette (open meshes): within its capacity; every boundary edge once; each
    // directed edge's net count over the output equals the face sum with unlit faces reversed
    {
        const std::size_t tcap = sk::silhouette_two_sided_indices_capacity(adj);
        std::vector<std::uint32_t> t2(tcap + 1, 0xDEADBEEFu);
        const std::size_t tc = std::min(cap, tcap);
        const sk::SilhouetteResult rt = sk::silhouette_extract_two_sided(adj, facing.data(), fc, t2.data(), tc, nullptr, 0);
        shadowkit_fuzz::check_detail(rt);
        if (rt.needed > tcap || rt.count > tc || rt.count % 2 != 0 || rt.boundary_edges != adj.boundary_edges) __builtin_trap();
        if ((rt.count < rt.needed) != (rt.status == sk::Status::BufferTooSmall)) __builtin_trap();
        if (rt.status != sk::Status::Ok && rt.status != sk::Status::BufferTooSmall) __builtin_trap();
        if (t2[tc] != 0xDEADBEEFu) __builtin_trap();
        if (rt.status == sk::Status::Ok && fc < 400) {
            std::map<std::pair<std::uint32_t, std::uint32_t>, long> net;  // (min, max) -> signed count
            auto add = [&](std::uint32_t a, std::uint32_t b, long w) {
                if (a < b) net[{a, b}] += w;
                else net[{b, a}] -= w;
            };
            for (std::size_t f = 0; f < fc; ++f)
                for (int j = 0; j < 3; ++j)
                    add(adj.faces[3 * f + std::size_t(j)], adj.faces[3 * f + std::size_t((j + 1) % 3)], facing[f] ? 1 : -1);
            for (std::size_t k = 0; k < rt.count; k += 2) add(t2[k], t2[k + 1], -1);
            for (const auto& e : net)
                if (e.second != 0) __builtin_trap();
        }
    }
    // Closed meshes: silhouette loops are balanced.
    const sk::Silhouette s = sk::silhouette_compute(adj, pos.data(), nv, L);
    shadowkit_fuzz::check_detail(s);
    if (s.status != sk::Status::Ok || s.indices.size() != r.needed || s.flags.size() != r.needed / 2) __builtin_trap();
    if (!std::equal(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(r.count), s.indices.begin())) __builtin_trap();
    if (adj.closed()) {
        std::vector<long> bal(nv, 0);
        for (std::size_t k = 0; k < s.indices.size(); k += 2) { ++bal[s.indices[k]]; --bal[s.indices[k + 1]]; }
        for (long x : bal)
            if (x != 0) __builtin_trap();
    }
    // Chunked / parallel path (serial loop, chunks in reverse): identical to the serial result.
    const std::size_t chunks = 1 + in.size(40);
    const std::size_t pcap = sk::silhouette_indices_capacity(adj) + in.size(3);
    std::vector<std::uint8_t> pf(fc + 1, 0xCD);
    std::vector<std::uint32_t> pidx(pcap + 2, 0xDEADBEEFu);
    std::vector<std::uint8_t> pflags(pcap / 2 + 1, 0xEE);
    std::vector<sk::SilhouetteResult> per(chunks);
    auto rev_for = [](std::size_t n, const auto& fn) {
        for (std::size_t i = n; i-- > 0;) fn(i);
    };
    const sk::SilhouetteResult pr = sk::silhouette_extract_parallel(adj, pos.data(), nv, L, pf.data(), fc, pidx.data(), pcap,
                                                                    pflags.data(), pcap / 2, per.data(), chunks, rev_for);
    shadowkit_fuzz::check_detail(pr);
    if (pr.status != sk::Status::Ok || pr.count != r.needed || pr.needed != r.needed) __builtin_trap();
    if (pf[fc] != 0xCD || pidx[pcap] != 0xDEADBEEFu || pflags[pcap / 2] != 0xEE) __builtin_trap();
    if (!std::equal(s.indices.begin(), s.indices.end(), pidx.begin()) || !std::equal(s.flags.begin(), s.flags.end(), pflags.begin()))
        __builtin_trap();
    if (pr.boundary_edges != r.boundary_edges || pr.nonmanifold_edges != r.nonmanifold_edges) __builtin_trap();
    // arbitrary chunk indices, capacities and (lying) chunk results are rejected, never overrun
    const std::size_t c = in.size(50), cc = in.size(50);
    const sk::SilhouetteFacing cf = sk::silhouette_compute_facing_chunk(adj, pos.data(), nv, L, pf.data(), in.size(fc + 2), c, cc);
    shadowkit_fuzz::check_detail(cf);
    if (cf.status == sk::Status::Ok && (cf.count > fc || cf.lit_faces > cf.count)) __builtin_trap();
    const std::size_t ccap = in.size(pcap);
    const sk::SilhouetteResult cr = sk::silhouette_extract_chunk(adj, pf.data(), fc, pidx.data(), ccap, pflags.data(), ccap / 2, c, cc);
    shadowkit_fuzz::check_detail(cr);
    if (cr.status == sk::Status::Ok && (cr.count > sk::silhouette_indices_capacity(adj) || cr.count > ccap)) __builtin_trap();
    for (auto& x : per) x.count = x.needed = in.size(pcap + 4);
    (void)sk::silhouette_compact_chunks(adj, per.data(), chunks, pidx.data(), pcap, pflags.data(), pcap / 2);
    if (pidx[pcap] != 0xDEADBEEFu || pflags[pcap / 2] != 0xEE) __builtin_trap();

    // The cached-plane fast path (issue 16): facing bits, silhouette, flags and counts identical to
    // the exact path; chunked and parallel forms identical; short buffers and bad chunk arguments
    // reported, nothing written past a capacity.
    {
        const sk::SilhouettePlanes pl = sk::silhouette_build_planes(adj, pos.data(), nv);
        shadowkit_fuzz::check_detail(pl);
        if (pl.status != sk::Status::Ok || pl.face_count() != fc || pl.exact_faces > fc) __builtin_trap();
        std::vector<std::uint8_t> ff(fc + 1, 0xCD);
        const std::size_t fcap2 = (in.u8() & 3) == 0 ? in.size(fc + 1) : fc;
        const sk::SilhouetteFacing pf2 = sk::silhouette_compute_facing_planes(adj, pl, L, ff.data(), fcap2);
        shadowkit_fuzz::check_detail(pf2);
        if (fcap2 < fc) {
            if (pf2.status != sk::Status::BufferTooSmall || pf2.needed != fc) __builtin_trap();
        } else {
            if (pf2.status != sk::Status::Ok || pf2.count != fc || pf2.lit_faces != fr.lit_faces) __builtin_trap();
            if (!std::equal(facing.begin(), facing.begin() + static_cast<std::ptrdiff_t>(fc), ff.begin())) __builtin_trap();
        }
        if (ff[fc] != 0xCD) __builtin_trap();
        // extraction on the planes' layout from the exact facing, any capacity
        std::vector<std::uint32_t> po(cap + 2, 0xDEADBEEFu);
        std::vector<std::uint8_t> pfl(fcap + 1, 0xEE);
        const bool with_flags = (in.u8() & 1) != 0;
        const sk::SilhouetteResult rp = sk::silhouette_extract_planes(adj, pl, facing.data(), fc, po.data(), cap,
                                                                      with_flags ? pfl.data() : nullptr, with_flags ? fcap : 0);
        shadowkit_fuzz::check_detail(rp);
        const std::size_t room = with_flags ? std::min(cap / 2, fcap) : cap / 2;
        if (rp.needed != r.needed || rp.count != std::min(2 * room, r.needed) || rp.boundary_edges != r.boundary_edges ||
            rp.nonmanifold_edges != r.nonmanifold_edges || (rp.count < rp.needed) != (rp.status == sk::Status::BufferTooSmall))
            __builtin_trap();
        if (po[cap] != 0xDEADBEEFu || pfl[fcap] != 0xEE) __builtin_trap();
        if (!std::equal(po.begin(), po.begin() + static_cast<std::ptrdiff_t>(rp.count), s.indices.begin())) __builtin_trap();
        if (with_flags && !std::equal(pfl.begin(), pfl.begin() + static_cast<std::ptrdiff_t>(rp.count / 2), s.flags.begin())) __builtin_trap();
        // facing bytes other than 0 / 1 (non-zero = lit): the same edges as silhouette_extract
        std::vector<std::uint8_t> odd(fc);
        for (std::size_t f = 0; f < fc; ++f) odd[f] = static_cast<std::uint8_t>(facing[f] ? 1 + in.u8() % 255 : 0);
        std::vector<std::uint32_t> o1(sk::silhouette_indices_capacity(adj) + 1, 1u), o2(o1.size(), 2u);
        const sk::SilhouetteResult a1 = sk::silhouette_extract(adj, odd.data(), fc, o1.data(), o1.size() - 1, nullptr, 0);
        shadowkit_fuzz::check_detail(a1);
        const sk::SilhouetteResult a2 = sk::silhouette_extract_planes(adj, pl, odd.data(), fc, o2.data(), o2.size() - 1, nullptr, 0);
        shadowkit_fuzz::check_detail(a2);
        if (a1.status != sk::Status::Ok || a2.status != sk::Status::Ok || a1.count != a2.count ||
            !std::equal(o1.begin(), o1.begin() + static_cast<std::ptrdiff_t>(a1.count), o2.begin()) || o2.back() != 2u)
            __builtin_trap();
        // side quads straight from the planes' extraction (exact or odd facing bytes, any capacity):
        // the whole quads of volume_build_side_quads(silhouette_extract's edges) that fit, nothing
        // written past count
        {
            const bool use_odd = (in.u8() & 1) != 0;
            const std::uint8_t* fb = use_odd ? odd.data() : facing.data();
            const sk::SilhouetteResult& ref = use_odd ? a1 : r;
            const std::vector<std::uint32_t>& ref_idx = use_odd ? o1 : s.indices;
            std::vector<std::uint32_t> rq(3 * ref.needed + 1);
            const sk::VolumeBuffer vq = sk::volume_build_side_quads(ref_idx.data(), ref.needed, nv, rq.data(), rq.size());
            if (vq.status != sk::Status::Ok || vq.count != 3 * ref.needed) __builtin_trap();
            const std::size_t qcap = (in.u8() & 3) == 0 ? 3 * sk::silhouette_indices_capacity(adj) : in.size(3 * ref.needed + 8);
            std::vector<std::uint32_t> qo(qcap + 4, 0xDEADBEEFu);
            const sk::SilhouetteResult rq2 = sk::silhouette_extract_planes_side_quads(adj, pl, fb, fc, qo.data(), qcap);
            shadowkit_fuzz::check_detail(rq2);
            const std::size_t want = 6 * std::min(qcap / 6, ref.needed / 2);
            if (rq2.count > qcap || rq2.count != want || rq2.needed != 3 * ref.needed || rq2.boundary_edges != ref.boundary_edges ||
                rq2.nonmanifold_edges != ref.nonmanifold_edges || (rq2.status == sk::Status::Ok) != (want == rq2.needed) ||
                (rq2.status != sk::Status::Ok && rq2.status != sk::Status::BufferTooSmall))
                __builtin_trap();
            if (!std::equal(qo.begin(), qo.begin() + static_cast<std::ptrdiff_t>(want), rq.begin())) __builtin_trap();
            for (std::size_t k = want; k < qo.size(); ++k)
                if (qo[k] != 0xDEADBEEFu) __builtin_trap();
            const sk::SilhouetteResult bad = sk::silhouette_extract_planes_side_quads(adj, pl, fb, fc + 1, qo.data(), qcap);
            shadowkit_fuzz::check_detail(bad);
            if (bad.status != sk::Status::InvalidArgument) __builtin_trap();
        }
        // parallel planes path (chunks in reverse), then arbitrary chunk arguments
        const std::size_t pchunks = 1 + in.size(40);
        std::vector<std::uint8_t> qf(fc + 1, 0xCD);
        std::vector<std::uint32_t> qidx(pcap + 2, 0xDEADBEEFu);
        std::vector<std::uint8_t> qfl(pcap / 2 + 1, 0xEE);
        std::vector<sk::SilhouetteResult> qper(pchunks);
        const sk::SilhouetteResult qr = sk::silhouette_extract_parallel_planes(adj, pl, L, qf.data(), fc, qidx.data(), pcap, qfl.data(),
                                                                               pcap / 2, qper.data(), pchunks, rev_for);
        shadowkit_fuzz::check_detail(qr);
        if (qr.status != sk::Status::Ok || qr.count != r.needed || qf[fc] != 0xCD || qidx[pcap] != 0xDEADBEEFu || qfl[pcap / 2] != 0xEE)
            __builtin_trap();
        if (!std::equal(s.indices.begin(), s.indices.end(), qidx.begin()) || !std::equal(s.flags.begin(), s.flags.end(), qfl.begin()) ||
            !std::equal(facing.begin(), facing.begin() + static_cast<std::ptrdiff_t>(fc), qf.begin()))
            __builtin_trap();
        const std::size_t c2 = in.size(50), cc2 = in.size(50), fcap3 = in.size(fc + 2), ccap2 = in.size(pcap);
        const sk::SilhouetteFacing cf2 = sk::silhouette_compute_facing_planes_chunk(adj, pl, L, qf.data(), fcap3, c2, cc2);
        shadowkit_fuzz::check_detail(cf2);
        if (cf2.status == sk::Status::Ok && (cf2.count > fc || cf2.lit_faces > cf2.count || fcap3 < fc || c2 >= cc2)) __builtin_trap();
        if (qf[fc] != 0xCD) __builtin_trap();
        const sk::SilhouetteResult cr2 = sk::silhouette_extract_planes_chunk(adj, pl, qf.data(), fc, qidx.data(), ccap2, qfl.data(), ccap2 / 2, c2, cc2);
        shadowkit_fuzz::check_detail(cr2);
        if (cr2.status == sk::Status::Ok && (cr2.count > sk::silhouette_indices_capacity(adj) || cr2.count > ccap2)) __builtin_trap();
        if (qidx[pcap] != 0xDEADBEEFu || qfl[pcap / 2] != 0xEE) __builtin_trap();
        // a mismatched adjacency (the empty one) is rejected
        const sk::SilhouetteAdjacency none = sk::silhouette_build_adjacency(nullptr, 0, nullptr, 0);
        shadowkit_fuzz::check_detail(none);
        if (fc > 0 && sk::silhouette_compute_facing_planes(none, pl, L, qf.data(), fc).status != sk::Status::InvalidArgument) __builtin_trap();
        if (nv > 0 && sk::silhouette_build_planes(adj, pos.data(), nv - 1).status != sk::Status::InvalidArgument) __builtin_trap();
    }

    // silhouette_face_orientation on arbitrary triangles and lights (NaN/Inf, degenerate, w < 0,
    // light on a corner): the filter equals the exact fallback; reversed winding negates the sign;
    // a rotation keeps it; scaling the light by 2 keeps it; a corner at the light gives 0.
    for (int it = 0; it < 4; ++it) {
        const bool raw = (in.u8() & 1) != 0;
        const glm::vec3 A = in.vec3(raw, 0.5f), B = in.vec3(raw, 0.5f);
        const std::uint8_t sel = in.u8();
        const glm::vec3 C = (sel & 1) ? A : ((sel & 2) ? B : in.vec3(raw, 0.5f));
        glm::vec4 Lx((sel & 4) ? in.interesting_f32() : in.value(raw, 0.5f), in.value(raw, 0.5f), in.value(raw, 0.5f),
                     (sel & 8) ? 0.0f : ((sel & 16) ? in.interesting_f32() : in.value(raw, 0.5f)));
        if (sel & 32) Lx = glm::vec4((sel & 64) ? A : B, 1.0f);
        const bool valid = sk::silhouette_valid_light(Lx);
        const bool lfin = std::isfinite(Lx.x) && std::isfinite(Lx.y) && std::isfinite(Lx.z) && std::isfinite(Lx.w);
        if (valid != (lfin && Lx.w >= 0.0f && !(Lx.x == 0.0f && Lx.y == 0.0f && Lx.z == 0.0f && Lx.w == 0.0f)))
            __builtin_trap();
        const sk::SilhouetteOrientation so = sk::silhouette_face_orientation(A, B, C, Lx);
        shadowkit_fuzz::check_detail(so);
        const bool fin = shadowkit_fuzz::all_finite(A) && shadowkit_fuzz::all_finite(B) && shadowkit_fuzz::all_finite(C);
        if (!fin) {
            if (so.status != sk::Status::NonFinite) __builtin_trap();
            continue;
        }
        if (!valid) {
            if (so.status != sk::Status::InvalidLight) __builtin_trap();
            continue;
        }
        if (so.status != sk::Status::Ok || so.lit != (so.sign > 0) || so.sign < -1 || so.sign > 1) __builtin_trap();
        if (so.sign != sk::detail::sil_face_sign_exact(A, B, C, Lx)) __builtin_trap();
        if ((A == B || B == C || C == A) && so.sign != 0) __builtin_trap();  // zero-area face: never lit
        if ((sel & 32) && so.sign != 0) __builtin_trap();                    // light on a corner
        if (sk::silhouette_face_orientation(A, C, B, Lx).sign != -so.sign) __builtin_trap();
        if (sk::silhouette_face_orientation(B, C, A, Lx).sign != so.sign) __builtin_trap();
        const glm::vec4 L2 = 2.0f * Lx;
        if (shadowkit_fuzz::all_finite(L2) && sk::silhouette_face_orientation(A, B, C, L2).sign != so.sign) __builtin_trap();
    }
    // silhouette_chunk_offset: balanced split of the edge list (uint32 elements), 0 for invalid arguments
    {
        const std::size_t ne = adj.edges.size();
        const std::size_t cnt = (in.u8() & 1) ? static_cast<std::size_t>(in.u64()) : in.size(70);
        const std::size_t probe = (in.u8() & 1) ? static_cast<std::size_t>(in.u64()) : in.size(72);
        const std::size_t off = sk::silhouette_chunk_offset(adj, probe, cnt);
        if ((cnt == 0 || probe >= cnt) && off != 0) __builtin_trap();
        if (off > 2 * ne || off % 2 != 0) __builtin_trap();
        if (cnt != 0 && cnt <= 64) {
            std::size_t prev = sk::silhouette_chunk_offset(adj, 0, cnt);
            if (prev != 0) __builtin_trap();
            for (std::size_t c2 = 1; c2 <= cnt; ++c2) {
                const std::size_t next = c2 < cnt ? sk::silhouette_chunk_offset(adj, c2, cnt) / 2 : ne;
                if (next < prev || next - prev < ne / cnt || next - prev > ne / cnt + 1) __builtin_trap();
                prev = next;
            }
        }
    }
    return 0;
}
