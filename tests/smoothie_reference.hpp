// The CPU side of the smoothie card tests, shared by tests/gl/test_gl_smoothie.cpp (a), (b) and their
// Vulkan runs in tests/vulkan/test_vk_smoothie.cpp: the card scene (a square card of half size h at
// light-view depth b over a floor at depth rf; the light at the origin looking down -z with a square
// perspective of projection scale s = P[0][0]), its four edges' smoothies from smoothie.hpp, the
// visibility each floor texel seen from the light must have (the card's closed-form light-NDC
// distance, smoothie.hpp's eq. 1 remap / falloff / tap rule), and the tally of a t = 0 lookup against
// the hard 2x2 lookup. CPU only (GLM, std and the header under test).
#pragma once

#include <shadowkit/smoothie.hpp>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace smoothie_ref {

/// The card over the floor, as triangles (card + floor, 12 vertices) seen from the light.
struct Card {
    float b = 2.f, h = 0.4f, rf = 5.f;
    glm::mat4 view{1.f}, proj{1.f}, vp{1.f};
    std::vector<glm::vec3> card, tris;  // card corners; card + floor triangles (12 vertices)
    Card() {
        proj = glm::perspective(1.2f, 1.f, 0.1f, 100.f);
        vp = proj * view;
        card = {{-h, -h, -b}, {h, -h, -b}, {h, h, -b}, {-h, h, -b}};
        std::vector<glm::vec3> fl = {{-20, -20, -rf}, {20, -20, -rf}, {20, 20, -rf}, {-20, 20, -rf}};
        for (const std::vector<glm::vec3>* q : {&card, &fl})
            for (int i : {0, 1, 2, 0, 2, 3}) tris.push_back((*q)[static_cast<std::size_t>(i)]);
    }
    // Smoothies of the card's 4 edges (counter-clockwise seen from the light, facing it).
    std::vector<shadowkit::SmoothieVertex> smoothies(float t, shadowkit::SmoothieResult& res) const {
        const std::vector<std::uint32_t> e = {0, 1, 1, 2, 2, 3, 3, 0};
        std::vector<glm::vec3> n;
        for (int i = 0; i < 4; ++i) {
            n.push_back({0, 0, 1});
            n.push_back({0, 0, 0});
        }
        shadowkit::SmoothieEdges in;
        in.positions = card.data();
        in.position_count = 4;
        in.edges = e.data();
        in.edge_count = 4;
        in.face_normals = n.data();
        shadowkit::SmoothieParams p;
        p.t = t;
        std::vector<shadowkit::SmoothieVertex> v(shadowkit::smoothie_vertex_capacity(4));
        std::vector<shadowkit::SmoothieScratch> scratch(shadowkit::smoothie_scratch_capacity(4));
        res = shadowkit::smoothie_build(in, vp, p, scratch.data(), scratch.size(), v.data(), v.size());
        v.resize(res.count);
        return v;
    }
};

/// What texel (x, y) of the N x N floor seen from the light (texel centres = output pixel centres)
/// must hold after the three passes with smoothie width t and the final pass's bias.
struct CardTexel {
    bool skip = false;         ///< centre within 1.5 texels of the card's outline: the rasterization rule decides
    bool alpha_known = false;  ///< inside a smoothie and away from its far edge: the buffer's alpha is a_expect
    float a_expect = 1.f;      ///< the smoothie buffer's alpha (remapped in the pass when remap_here)
    float expect = 1.f;        ///< the final visibility (smoothie_visibility_tap)
};
inline CardTexel card_texel(const Card& cs, int N, int x, int y, float t, bool remap_here, float bias) {
    CardTexel r;
    const double edge = double(cs.proj[0][0]) * double(cs.h) / double(cs.b);  // the card's half size in light NDC
    const double nx = (x + 0.5) / N * 2.0 - 1.0, ny = (y + 0.5) / N * 2.0 - 1.0;
    const double dx = std::max(0.0, std::abs(nx) - edge), dy = std::max(0.0, std::abs(ny) - edge);
    const double d = std::sqrt(dx * dx + dy * dy);  // light-NDC distance to the card
    const double dout = std::max(std::abs(nx), std::abs(ny)) - edge;
    r.skip = std::abs(dout) < 1.5 * 2.0 / N;
    // smoothie buffer: the card's smoothie (depth b, alpha = d / t) within t of it
    const bool in_smoothie = d > 0.0 && d < double(t);
    const float b_sm = in_smoothie ? cs.b : 1e30f;
    const float a_sm = in_smoothie ? float(d / double(t)) : 1.f;
    r.alpha_known = in_smoothie && std::abs(d - double(t)) > 2.0 / N;
    r.a_expect = remap_here ? shadowkit::smoothie_remap_alpha(a_sm, cs.b, cs.rf) : a_sm;
    const float z = d > 0.0 ? cs.rf : cs.b;  // linear map: the card over its footprint
    r.expect = shadowkit::smoothie_visibility_tap(cs.rf, z, b_sm, a_sm, bias);
    return r;
}

/// Test (b)'s oblique camera (w x h) looking at the card and its shadow on the floor.
inline glm::mat4 oblique_camera(int w, int h) {
    return glm::perspective(0.9f, float(w) / float(h), 0.1f, 50.f) *
           glm::lookAt(glm::vec3(2.5f, 1.5f, 0.5f), glm::vec3(0.f, 0.f, -4.f), glm::vec3(0.f, 0.f, -1.f));
}

/// Test (b)'s tally: the lookup at t = 0 against the hard 2x2 lookup (-1: background, left out).
struct HardTally {
    std::size_t drawn = 0, differ = 0, fractional = 0, dark = 0;
};
inline HardTally tally_hard(const std::vector<float>& v_smoothie, const std::vector<float>& v_hard) {
    HardTally r;
    for (std::size_t k = 0; k < v_hard.size(); ++k) {
        if (v_hard[k] < -0.5f) continue;  // background
        ++r.drawn;
        if (v_smoothie[k] != v_hard[k]) ++r.differ;
        if (v_hard[k] > 0.f && v_hard[k] < 1.f) ++r.fractional;
        if (v_hard[k] == 0.f) ++r.dark;
    }
    return r;
}

}  // namespace smoothie_ref
