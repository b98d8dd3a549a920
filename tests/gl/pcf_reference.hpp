// CPU emulation of glsl/pcf.glsl's and glsl/pcss.glsl's kernels, shared by the GL tests that check
// them (test_gl_soft_shadows.cpp: the 2D kernels; test_gl_filtered_arrays.cpp: the depth-array
// overloads and the filtered cascades): taps, weights and the hardware 2x2 bilinear depth compare
// (GL 4.6 sec. 8.23.1) written from the snippets' comments, in double.
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

namespace pcfref {

struct DepthTexture {
    int w = 0, h = 0;
    std::vector<float> d;  // row-major, row 0 = v in [0, 1/h)
    float at(int x, int y) const {  // GL_CLAMP_TO_EDGE
        x = std::clamp(x, 0, w - 1);
        y = std::clamp(y, 0, h - 1);
        return d[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)];
    }
};

// The hardware 2x2 compare with GL_LINEAR and GL_LEQUAL: each texel passes when ref <= stored,
// the four results weighted bilinearly (texel centres at (i + 0.5) / w).
inline double bilinear_compare(const DepthTexture& t, double u, double v, double ref) {
    const double x = u * t.w - 0.5, y = v * t.h - 0.5;
    const double fx = std::floor(x), fy = std::floor(y);
    const double a = x - fx, b = y - fy;
    const int i0 = static_cast<int>(fx), j0 = static_cast<int>(fy);
    auto pass = [&](int i, int j) { return ref <= double(t.at(i, j)) ? 1.0 : 0.0; };
    return (1 - a) * (1 - b) * pass(i0, j0) + a * (1 - b) * pass(i0 + 1, j0) + (1 - a) * b * pass(i0, j0 + 1) +
           a * b * pass(i0 + 1, j0 + 1);
}

// One tap of pcf.glsl as its comment defines it: offset o in uv, receiver plane z + g.o, lit outside.
inline double cpu_tap(const DepthTexture& t, glm::dvec3 uvz, glm::dvec2 g, glm::dvec2 o) {
    const glm::dvec2 uv = glm::dvec2(uvz) + o;
    if (uv.x < 0 || uv.y < 0 || uv.x > 1 || uv.y > 1) return 1.0;
    return bilinear_compare(t, uv.x, uv.y, uvz.z + glm::dot(g, o));
}

inline double cpu_box(const DepthTexture& t, glm::dvec3 uvz, glm::dvec2 g, int r, bool tent) {
    double sum = 0, wsum = 0;
    for (int j = -r; j <= r; ++j)
        for (int i = -r; i <= r; ++i) {
            const double w = tent ? double(r + 1 - std::abs(i)) * double(r + 1 - std::abs(j)) : 1.0;
            sum += w * cpu_tap(t, uvz, g, glm::dvec2(i / double(t.w), j / double(t.h)));
            wsum += w;
        }
    return sum / wsum;
}

// The 64 Poisson points of the snippet, parsed from its text (the data the GPU uses).
inline std::vector<glm::dvec2> parse_poisson(const std::string& src) {
    std::vector<glm::dvec2> pts;
    std::size_t p = src.find("sk_poisson_disk64[64] = vec2[64](");
    if (p == std::string::npos) return pts;
    p = src.find('(', p + 25);
    while (pts.size() < 64) {
        p = src.find("vec2(", p + 1);
        if (p == std::string::npos) break;
        const char* s = src.c_str() + p + 5;
        char* end = nullptr;
        const double x = std::strtod(s, &end);
        const double y = std::strtod(end + 1, nullptr);
        pts.emplace_back(x, y);
    }
    return pts;
}

// Interleaved gradient noise as the snippet computes it, in float32.
inline float ign(float x, float y) {
    const float d = x * 0.06711056f + y * 0.00583715f;
    const float f = 52.9829189f * (d - std::floor(d));
    return f - std::floor(f);
}

inline double cpu_poisson(const DepthTexture& t, const std::vector<glm::dvec2>& disk, glm::dvec3 uvz, glm::dvec2 g,
                   double radius_uv, int taps, double angle) {
    const int n = std::clamp(taps, 1, 64);
    if (!(radius_uv > 0) || n == 1) return cpu_tap(t, uvz, g, glm::dvec2(0));
    const double c = std::cos(angle), s = std::sin(angle);
    double sum = 0;
    for (int i = 0; i < n; ++i) {
        const glm::dvec2 q = disk[static_cast<std::size_t>(i)];
        const glm::dvec2 o(c * q.x - s * q.y, s * q.x + c * q.y);  // mat2(c, s, -s, c) * q
        sum += cpu_tap(t, uvz, g, o * radius_uv);
    }
    return sum / n;
}


inline double lin_depth(double z, double n, double f) { return f * n / (f - std::clamp(z, 0.0, 1.0) * (f - n)); }

// The blocker search of pcss.glsl: mean stored depth of the taps (nearest texel) closer than the
// receiver plane at their offset, in a disk of diameter `search`; -1 when none.
inline double cpu_blocker(const DepthTexture& t, const std::vector<glm::dvec2>& disk, glm::dvec3 uvz, glm::dvec2 g,
                          double search, int taps, double angle) {
    const double c = std::cos(angle), s = std::sin(angle);
    double sum = 0, count = 0;
    for (int i = 0; i < taps; ++i) {
        const glm::dvec2 q = disk[static_cast<std::size_t>(i)];
        const glm::dvec2 o = glm::dvec2(c * q.x - s * q.y, s * q.x + c * q.y) * (0.5 * search);
        const glm::dvec2 uv = glm::dvec2(uvz) + o;
        if (uv.x < 0 || uv.y < 0 || uv.x > 1 || uv.y > 1) continue;
        const double d = t.at(static_cast<int>(std::floor(uv.x * t.w)), static_cast<int>(std::floor(uv.y * t.h)));
        if (d < uvz.z + glm::dot(g, o)) {
            sum += d;
            count += 1;
        }
    }
    return count == 0 ? -1.0 : sum / count;
}

// CPU sk_pcss as pcss.glsl's comment defines it: blocker search with nearest-texel depth reads
// (receiver plane per tap) in a search width clamped to max_w, linear depths, filter width
// L (z_r - z_b)/z_b * n / z_r clamped,
// Poisson PCF with the emulated 2x2 compare; a search narrower than a texel is the hard compare.
inline double cpu_pcss(const DepthTexture& t, const std::vector<glm::dvec2>& disk, glm::dvec3 uvz, glm::dvec2 g, double L,
                       double n, double f, int taps, double angle, double max_w) {
    const double zr = lin_depth(uvz.z, n, f);
    const double search = std::min(L * std::max(zr - n, 0.0) / zr, max_w);
    if (!(search * t.w > 1.0)) return cpu_tap(t, uvz, g, glm::dvec2(0));
    const double b = cpu_blocker(t, disk, uvz, g, search, taps, angle);
    if (b < 0) return 1.0;
    const double zb = std::max(lin_depth(b, n, f), 1e-30);
    const double w = std::clamp(L * std::max(zr - zb, 0.0) / zb * n / zr, 0.0, max_w);
    return cpu_poisson(t, disk, uvz, g, 0.5 * w, taps, angle);
}

// CPU sk_pcss_directional: window depth is linear, search L z_r, filter L (z_r - z_b), both clamped.
inline double cpu_pcss_directional(const DepthTexture& t, const std::vector<glm::dvec2>& disk, glm::dvec3 uvz,
                                   glm::dvec2 g, double L, int taps, double angle, double max_w) {
    const double zr = uvz.z;
    const double search = std::min(L * std::max(zr, 0.0), max_w);
    if (!(search * t.w > 1.0)) return cpu_tap(t, uvz, g, glm::dvec2(0));
    const double b = cpu_blocker(t, disk, uvz, g, search, taps, angle);
    if (b < 0) return 1.0;
    const double w = std::clamp(L * std::max(zr - b, 0.0), 0.0, max_w);
    return cpu_poisson(t, disk, uvz, g, 0.5 * w, taps, angle);
}

}  // namespace pcfref
