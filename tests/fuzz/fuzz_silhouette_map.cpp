// libFuzzer target for include/shadowkit/silhouette_map.hpp: positions, edge indices (out of range
// included), a light matrix (raw floats or a perspective light), map sizes, texel-space edges,
// depth maps, lookup positions and biases decoded from bytes (NaN/Inf possible). Invariants trap:
// counts <= capacity, points inside [0,1]^2, weights consistent, lookups never crash.
#include <shadowkit/silhouette_map.hpp>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>

#include "fuzz_input.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    namespace sk = shadowkit;
    shadowkit_fuzz::FuzzInput r(data, size);
    const uint8_t mode = r.u8();
    const bool raw = (mode & 1) != 0;
    const uint32_t mw = r.range(1u, 40u), mh = r.range(1u, 40u);
    const glm::uvec2 msize(mw, mh);
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
    if (pr.written > cap || pr.written > pr.needed) __builtin_trap();
    if (pr.needed + pr.skipped > ne) __builtin_trap();
    for (size_t k = 0; k < pr.written; ++k)
        if (!std::isfinite(edges[k].a.x) || !std::isfinite(edges[k].b.y) || !std::isfinite(edges[k].depth_a))
            __builtin_trap();
    // raw texel-space edges appended (NaN, huge)
    std::vector<sk::SilmapEdge> all(edges.begin(), edges.begin() + static_cast<std::ptrdiff_t>(pr.written));
    const size_t extra = r.size(7);
    for (size_t k = 0; k < extra; ++k) {
        sk::SilmapEdge e;
        e.a = r.vec2(raw, 0.5f);
        e.b = r.vec2(raw, 0.5f);
        e.depth_a = r.value(raw, 0.01f);
        e.depth_b = r.value(raw, 0.01f);
        all.push_back(e);
        glm::ivec2 cells[64];
        const size_t nc = sk::silmap_rasterize_edge(e.a, e.b, msize, cells, 64, r.value(raw, 0.001f));
        for (size_t c = 0; c < (nc < 64 ? nc : 64); ++c)
            if (cells[c].x < 0 || cells[c].y < 0 || cells[c].x >= int(msize.x) || cells[c].y >= int(msize.y))
                __builtin_trap();
        const sk::SilmapPoint sp = sk::silmap_select_point(e.a, e.b, glm::ivec2(r.i8(), r.i8()));
        if (sp.kase != sk::SilmapCase::NoIntersection &&
            (!(sp.local.x >= 0.f && sp.local.x <= 1.f && sp.local.y >= 0.f && sp.local.y <= 1.f) || sp.weight < 0 ||
             sp.weight > 2))
            __builtin_trap();
    }
    const size_t texels = size_t(msize.x) * msize.y;
    std::vector<float> depth(texels);
    for (auto& d : depth) d = (mode & 8) ? r.value(raw, 0.01f) : 0.5f;
    std::vector<glm::vec2> pts(texels);
    std::vector<uint8_t> wts(texels);
    const size_t bcap = (mode & 16) ? texels / 2 : texels;
    const sk::SilmapBuildResult br = sk::silmap_build(all.data(), all.size(), msize, (mode & 32) ? depth.data() : nullptr,
                                                      r.value(raw, 0.01f), pts.data(), wts.data(), bcap);
    if (br.needed != texels) __builtin_trap();
    if (bcap < texels) {
        if (br.status != sk::SilmapStatus::BufferTooSmall) __builtin_trap();
        return 0;
    }
    size_t fails = 0;
    for (size_t k = 0; k < texels; ++k) {
        if (!(pts[k].x >= 0.f && pts[k].x <= 1.f && pts[k].y >= 0.f && pts[k].y <= 1.f)) __builtin_trap();
        if (wts[k] > sk::kSilmapFailureWeight) ++fails;
    }
    if (fails != br.failure_texels) __builtin_trap();
    for (int k = 0; k < 8; ++k) {
        const glm::vec2 q = r.vec2(raw, 0.4f);
        const float z = r.value(raw, 0.01f), bias = r.value(raw, 0.001f);
        const sk::SilmapLookup l = sk::silmap_lookup(pts.data(), wts.data(), depth.data(), msize, q, z, bias);
        if (l.corner < 0 || l.corner > 3) __builtin_trap();
        (void)sk::silmap_plain_lookup(depth.data(), msize, q, z, bias);
        const bool lit[4] = {(k & 1) != 0, (k & 2) != 0, (k & 4) != 0, true};
        const sk::SilmapLookup l2 = sk::silmap_reconstruct(q, pts[0], glm::vec2(r.value(raw, 0.1f)), pts[texels - 1],
                                                           glm::vec2(r.value(raw, 0.1f), 0.f), pts[0], lit);
        if (l2.lit != lit[l2.corner]) __builtin_trap();
    }
    return 0;
}
