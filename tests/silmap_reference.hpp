// The boundary error of the silhouette-map tests, shared by tests/gl/test_gl_silhouette_map.cpp and
// tests/vulkan/test_vk_silhouette_map.cpp: the distance, in texels of a map of `size`, from a
// receiver point projected into the light's image to the nearest projected silhouette edge (the
// exact shadow boundary). CPU only (GLM, std and the header under test).
#pragma once

#include <shadowkit/silhouette_map.hpp>

#include <glm/glm.hpp>

#include <algorithm>
#include <vector>

namespace silmap_ref {

/// Distance from q to the segment ab (in double).
inline double seg_dist(glm::vec2 q, glm::vec2 a, glm::vec2 b) {
    const glm::dvec2 ab = glm::dvec2(b) - glm::dvec2(a), aq = glm::dvec2(q) - glm::dvec2(a);
    const double dd = glm::dot(ab, ab);
    const double t = dd > 0.0 ? std::clamp(glm::dot(aq, ab) / dd, 0.0, 1.0) : 0.0;
    return glm::length(aq - t * ab);
}

/// World point p seen through the light's `vp`: its position q in the texels of a size x size map
/// and the distance (texels) to the nearest of `edges`.
struct EdgeDistance {
    glm::vec2 q{0.f};
    double texels = 1e30;
};
inline EdgeDistance edge_distance(const glm::mat4& vp, const glm::vec3& p, float size,
                                  const std::vector<shadowkit::SilmapEdge>& edges) {
    EdgeDistance r;
    const glm::vec4 c = vp * glm::vec4(p, 1.f);
    r.q = (glm::vec2(c) / c.w * 0.5f + 0.5f) * size;
    for (const auto& e : edges) r.texels = std::min(r.texels, seg_dist(r.q, e.a, e.b));
    return r;
}

}  // namespace silmap_ref
