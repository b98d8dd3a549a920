// The CPU side of the virtual shadow map GPU tests, shared by tests/gl/test_gl_virtual_shadow_map.cpp
// and tests/vulkan/test_vk_virtual_shadow_map.cpp: the layout both use, the slab test of the ray cast,
// and the CPU's page marking that the GPU's request mask must equal (in double: the pages the 2x2
// kernel touches, with the level and texel position moved by +-1e-3; `sure` in every variant, `maybe`
// in any). CPU only (GLM, std and the header under test).
#pragma once

#include <shadowkit/virtual_shadow_map.hpp>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace vsm_ref {

/// The tests' layout: 32-texel pages, 1024 virtual texels, 8 levels, level 0 4 units wide, depth 200,
/// a pool of 400 pages.
inline shadowkit::VsmLayout test_layout() {
    shadowkit::VsmLayout layout;
    layout.page_texels = 32;
    layout.virtual_texels = 1024;
    layout.level_count = 8;
    layout.level0_extent_world = 4.0;
    layout.depth_range_world = 200.0;
    layout.pool_pages = 400;
    return layout;
}

/// Slab test: does the ray from p along d hit the box (`b`: min xyz, max xyz) beyond t = 1e-3?
template <class Box>
bool ray_hits(const Box& box, const glm::dvec3& p, const glm::dvec3& d) {
    double t0 = -1e30, t1 = 1e30;
    for (int k = 0; k < 3; ++k) {
        if (std::fabs(d[k]) < 1e-12) {
            if (p[k] < box.b[k] || p[k] > box.b[3 + k]) return false;
            continue;
        }
        double a = (box.b[k] - p[k]) / d[k], b = (box.b[3 + k] - p[k]) / d[k];
        if (a > b) std::swap(a, b);
        t0 = std::max(t0, a);
        t1 = std::min(t1, b);
    }
    return t1 >= std::max(t0, 1e-3);
}

/// The CPU's marking of one position (double): the bits of the pages the 2x2 kernel touches, with the
/// level and texel position moved by +-1e-3, one entry a variant (`variants` of them).
inline void cpu_mark(const shadowkit::VsmState& s, const glm::dvec3& world, double dist, double pixel_angle,
                     std::vector<std::size_t>& votes, int& variants) {
    votes.clear();
    const int n = s.pages_per_side, pt = s.layout.page_texels, size = n * pt;
    const double texel0 = s.layout.level0_extent_world / double(s.layout.virtual_texels);
    variants = 0;
    for (double dl : {-1e-3, 1e-3})
        for (double dx : {-1e-3, 1e-3})
            for (double dy : {-1e-3, 1e-3}) {
                ++variants;
                const double lf = std::floor(std::log2(dist * pixel_angle / texel0) + dl);
                const int level = int(std::min(std::max(lf, 0.0), double(s.layout.level_count - 1)));
                for (int l = level; l < s.layout.level_count; ++l) {
                    const glm::dvec4 h = s.levels[l].world_to_uv * glm::dvec4(world, 1.0);
                    const double fx = h.x / h.w * size - 0.5 + dx, fy = h.y / h.w * size - 0.5 + dy;
                    const int ix = int(std::floor(fx)), iy = int(std::floor(fy));
                    if (ix < 0 || iy < 0 || ix + 1 >= size || iy + 1 >= size) continue;
                    for (int y = iy / pt; y <= (iy + 1) / pt; ++y)
                        for (int x = ix / pt; x <= (ix + 1) / pt; ++x)
                            votes.push_back((std::size_t(l) * std::size_t(n) + std::size_t(y)) * std::size_t(n) + std::size_t(x));
                    break;
                }
            }
}

/// The GPU's request mask against the CPU's marking of every covered pixel (`rel`: its position
/// relative to the camera): bits the GPU set, the CPU's sure and maybe bits, sure bits the GPU
/// missed and bits it set beyond maybe.
struct MarkTally {
    std::size_t covered = 0, gpu_set = 0, sure_n = 0, maybe_n = 0, missing = 0, extra = 0;
};
inline MarkTally mark_tally(const shadowkit::VsmState& vsm, const glm::dvec3& camera, float pixel_angle,
                            const std::vector<glm::dvec3>& rel, const std::vector<std::uint32_t>& mask) {
    const std::size_t bits = std::size_t(vsm.layout.level_count) * std::size_t(vsm.pages_per_side * vsm.pages_per_side);
    std::vector<std::uint8_t> sure(bits, 0), maybe(bits, 0);
    std::vector<std::size_t> votes;
    MarkTally t;
    for (const glm::dvec3& r : rel) {
        ++t.covered;
        int variants = 0;
        cpu_mark(vsm, camera + r, glm::length(r), double(pixel_angle), votes, variants);
        for (std::size_t b : votes) {
            maybe[b] = 1;
            if (std::count(votes.begin(), votes.end(), b) == variants) sure[b] = 1;
        }
    }
    for (std::size_t b = 0; b < bits; ++b) {
        const bool set = (mask[b / 32] >> (b % 32)) & 1u;
        t.gpu_set += set;
        t.sure_n += sure[b];
        t.maybe_n += maybe[b];
        t.missing += sure[b] && !set;
        t.extra += set && !maybe[b];
    }
    return t;
}

}  // namespace vsm_ref
