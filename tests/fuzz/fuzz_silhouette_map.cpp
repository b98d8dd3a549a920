// libFuzzer target for include/shadowkit/silhouette_map.hpp: positions, edge indices (out of range
// included), a light matrix (raw floats or a perspective light), map sizes, texel-space edges,
// depth maps, lookup positions and biases decoded from bytes (NaN/Inf possible). Calls every
// public function. Invariants trap: Status::Ok only with finite outputs (edges, cells in the map,
// points inside [0,1]^2, weights consistent), count <= capacity, count == needed when Ok, NaN
// input never Ok, a NotRun status never returned.
#include <shadowkit/silhouette_map.hpp>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>

#include "fuzz_input.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace {

using shadowkit_fuzz::all_finite;
using shadowkit_fuzz::check;

bool finite_edge(const shadowkit::SilmapEdge& e) {
    return all_finite(e.a) && all_finite(e.b) && std::isfinite(e.depth_a) && std::isfinite(e.depth_b);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    namespace sk = shadowkit;
    using St = sk::Status;
    shadowkit_fuzz::FuzzInput r(data, size);
    const uint8_t mode = r.u8();
    const bool raw = (mode & 1) != 0;
    // mode bit 7 with a width of 37..40: a side of 0 or past kSilmapMaxSize (InvalidArgument) or the
    // largest valid one (no extra byte read: inputs kept in regressions/ decode as before)
    static const uint32_t odd_sides[4] = {0u, 32768u, 32769u, 0xFFFFFFFFu};
    uint32_t mw = r.range(1u, 40u);
    const uint32_t mh = r.range(1u, 40u);
    if ((mode & 128) && mw > 36) mw = odd_sides[mw - 37];
    const glm::uvec2 msize(mw, mh);
    const bool size_ok = mw >= 1 && mw <= sk::kSilmapMaxSize && mh >= 1 && mh <= sk::kSilmapMaxSize;
    // geometry
    const size_t nv = r.size(15);
    std::vector<glm::vec3> pos(nv);
    for (auto& p : pos) p = r.vec3(raw, 0.1f);
    const size_t ne = r.size(15);
    std::vector<uint32_t> idx(2 * ne);
    for (auto& i : idx) i = r.range(0u, 19u);
    glm::mat4 vp;
    if (mode & 2) {
        vp = r.mat4();
    } else {
        glm::vec3 eye = r.vec3(raw, 0.1f);
        eye.y += 5.f;
        vp = glm::perspective(1.2f, 1.f, 0.1f, 50.f) * glm::lookAt(eye, glm::vec3(0.f), glm::vec3(0.f, 0.f, 1.f));
    }
    const size_t cap = r.size(19);
    std::vector<sk::SilmapEdge> edges(cap + 1);
    const sk::ClipDepth cd = (mode & 4) ? sk::ClipDepth::ZeroToOne : sk::ClipDepth::NegativeOneToOne;
    const sk::SilmapProjectResult pr =
        sk::silmap_project_edges(vp, cd, msize, pos.data(), pos.size(), idx.data(), ne, edges.data(), cap);
    shadowkit_fuzz::check_detail(pr);
    check(pr.status != St::NotRun);
    check(pr.count <= cap && pr.count <= pr.needed);
    check(pr.needed + pr.culled <= ne);
    if (pr.status == St::Ok) {
        check(size_ok && pr.count == pr.needed && pr.needed + pr.culled == ne);
        check(all_finite(vp));
        for (size_t k = 0; k < 2 * ne; ++k) check(idx[k] < nv && all_finite(pos[idx[k]]));
    }
    if (pr.status == St::Ok || pr.status == St::BufferTooSmall)
        for (size_t k = 0; k < pr.count; ++k) check(finite_edge(edges[k]));
    else
        check(pr.count == 0);
    // raw texel-space edges appended (NaN, huge)
    std::vector<sk::SilmapEdge> all(edges.begin(), edges.begin() + static_cast<std::ptrdiff_t>(pr.count));
    const size_t extra = r.size(7);
    for (size_t k = 0; k < extra; ++k) {
        sk::SilmapEdge e;
        e.a = r.vec2(raw, 0.5f);
        e.b = r.vec2(raw, 0.5f);
        e.depth_a = r.value(raw, 0.01f);
        e.depth_b = r.value(raw, 0.01f);
        all.push_back(e);
        glm::ivec2 cells[64];
        const size_t ccap = r.size(64);
        const float margin = r.value(raw, 0.001f);
        const sk::SilmapRasterResult rr = sk::silmap_rasterize_edge(e.a, e.b, msize, cells, ccap, margin);
        shadowkit_fuzz::check_detail(rr);
        check(rr.status != St::NotRun && rr.count <= ccap && rr.count <= rr.needed);
        if (rr.status == St::Ok) check(rr.count == rr.needed && all_finite(e.a) && all_finite(e.b) && margin >= 0.f);
        for (size_t c = 0; c < rr.count; ++c)
            check(cells[c].x >= 0 && cells[c].y >= 0 && cells[c].x < int(msize.x) && cells[c].y < int(msize.y));
        // total: local in [0,1]^2, weight 0..2, for any input
        const sk::SilmapPoint sp = sk::silmap_select_point(e.a, e.b, glm::ivec2(r.i32(), r.i32()));
        check(sp.local.x >= 0.f && sp.local.x <= 1.f && sp.local.y >= 0.f && sp.local.y <= 1.f);
        check(sp.weight >= 0 && sp.weight <= 2);
    }
    if (size_ok && size_t(msize.x) * msize.y > 4096) return 0;  // a 32768-wide map: too slow to build per run
    const size_t texels = size_ok ? size_t(msize.x) * msize.y : 16;
    std::vector<float> depth(texels);
    for (auto& d : depth) d = (mode & 8) ? r.value(raw, 0.01f) : 0.5f;
    std::vector<glm::vec2> pts(texels);
    std::vector<uint8_t> wts(texels);
    const size_t bcap = (mode & 16) ? texels / 2 : texels;
    const float dbias = r.value(raw, 0.01f);
    const bool use_depth = (mode & 32) != 0;
    const sk::SilmapBuildResult br = sk::silmap_build(all.data(), all.size(), msize, use_depth ? depth.data() : nullptr,
                                                      dbias, pts.data(), bcap, wts.data(), texels);
    shadowkit_fuzz::check_detail(br);
    check(br.status != St::NotRun && br.count <= bcap);
    if (br.status != St::Ok) {
        check(br.count == 0);
        if (br.status == St::BufferTooSmall) check(bcap < texels && br.needed == texels);
        return 0;
    }
    check(size_ok && br.count == texels && br.needed == texels && std::isfinite(dbias));
    for (const auto& e : all) check(finite_edge(e));
    size_t fails = 0;
    for (size_t k = 0; k < texels; ++k) {
        check(pts[k].x >= 0.f && pts[k].x <= 1.f && pts[k].y >= 0.f && pts[k].y <= 1.f);
        if (wts[k] > sk::kSilmapFailureWeight) ++fails;
    }
    check(fails == br.failure_texels);
    for (int k = 0; k < 8; ++k) {
        const glm::vec2 q = r.vec2(raw, 0.4f);
        const float z = r.value(raw, 0.01f), bias = r.value(raw, 0.001f);
        const bool finite_in = all_finite(q) && std::isfinite(z) && std::isfinite(bias);
        const sk::SilmapLookup l = sk::silmap_lookup(pts.data(), wts.data(), depth.data(), msize, q, z, bias);
        shadowkit_fuzz::check_detail(l);
        check(l.status == (finite_in ? St::Ok : St::NonFinite));
        check(l.corner >= 0 && l.corner <= 3);
        const sk::SilmapPlainLookup pl = sk::silmap_plain_lookup(depth.data(), msize, q, z, bias);
        shadowkit_fuzz::check_detail(pl);
        check(pl.status == (finite_in ? St::Ok : St::NonFinite));
        const bool lit[4] = {(k & 1) != 0, (k & 2) != 0, (k & 4) != 0, true};
        const glm::vec2 right(r.value(raw, 0.1f)), left(r.value(raw, 0.1f), 0.f);
        const sk::SilmapLookup l2 = sk::silmap_reconstruct(q, pts[0], right, pts[texels - 1], left, pts[0], lit);
        shadowkit_fuzz::check_detail(l2);
        check(l2.status == (all_finite(q) && all_finite(right) && all_finite(left) ? St::Ok : St::NonFinite));
        if (l2.status == St::Ok) check(l2.corner >= 0 && l2.corner <= 3 && l2.lit == lit[l2.corner]);
    }
    return 0;
}
