// The CPU side of the prefiltered_shadow GPU tests, shared by tests/gl/test_gl_prefiltered_shadow.cpp
// and its Vulkan runs in tests/vulkan/test_vk_prefiltered_shadow.cpp: the settings every pass uses, the
// casters seen by the light, the moment pass's cases and tolerance, the brute-force 2D convolution the
// separable blur must equal, the mean of the samples' moments an MSAA resolve must equal, and the soft
// lookup's receivers, CPU trilinear mirror of the read-back mip chain and ray-cast penumbra. CPU only
// (GLM, std and the header under test).
#pragma once

#include <shadowkit/prefiltered_shadow.hpp>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <vector>

namespace prefiltered_ref {

/// The settings of every pass: method, format, both exponents (-1: the header's default), minimum
/// variance 1e-4, bleed reduction 0.2.
inline shadowkit::PrefilterUniforms test_uniforms(shadowkit::PrefilterMethod m, shadowkit::PrefilterFormat f,
                                                  float exponent = -1.0f) {
    shadowkit::PrefilterSettings s;
    s.method = m;
    s.format = f;
    s.exponent_positive = exponent;
    s.exponent_negative = exponent;
    s.min_variance = 1e-4f;
    s.bleed_reduction = 0.2f;
    return shadowkit::prefilter_uniforms(s);
}

/// Casters seen by a light at the origin looking down -z: a floor at z = -8, a tilted quad and a box,
/// as five quads (a, b, c, d counter-clockwise) handed to `quad`.
template <class Quad>
void light_scene_quads(Quad&& quad) {
    quad(glm::vec3{-9, -9, -8}, glm::vec3{9, -9, -8}, glm::vec3{9, 9, -8}, glm::vec3{-9, 9, -8});
    quad(glm::vec3{-3, -1, -4}, glm::vec3{1, -1, -5.5f}, glm::vec3{1, 3, -5.5f}, glm::vec3{-3, 3, -4});  // tilted
    const glm::vec3 lo(0.5f, -3.0f, -6.5f), hi(2.5f, -1.0f, -5.0f);
    quad(glm::vec3{lo.x, lo.y, hi.z}, glm::vec3{hi.x, lo.y, hi.z}, glm::vec3{hi.x, hi.y, hi.z}, glm::vec3{lo.x, hi.y, hi.z});
    quad(glm::vec3{lo.x, lo.y, lo.z}, glm::vec3{lo.x, lo.y, hi.z}, glm::vec3{lo.x, hi.y, hi.z}, glm::vec3{lo.x, hi.y, lo.z});
    quad(glm::vec3{hi.x, lo.y, lo.z}, glm::vec3{hi.x, hi.y, lo.z}, glm::vec3{hi.x, hi.y, hi.z}, glm::vec3{hi.x, lo.y, hi.z});
}

/// The moment pass's cases: every method, in the formats it is stored in.
struct MomentCase {
    shadowkit::PrefilterMethod m;
    shadowkit::PrefilterFormat fmt;
};
inline const MomentCase kMomentCases[] = {
    {shadowkit::PrefilterMethod::Vsm, shadowkit::PrefilterFormat::Float32},
    {shadowkit::PrefilterMethod::Vsm, shadowkit::PrefilterFormat::Unorm16},
    {shadowkit::PrefilterMethod::Esm, shadowkit::PrefilterFormat::Float32},
    {shadowkit::PrefilterMethod::Esm, shadowkit::PrefilterFormat::Float16},
    {shadowkit::PrefilterMethod::Evsm2, shadowkit::PrefilterFormat::Float32},
    {shadowkit::PrefilterMethod::Evsm4, shadowkit::PrefilterFormat::Float32},
    {shadowkit::PrefilterMethod::Evsm4, shadowkit::PrefilterFormat::Float16},
    {shadowkit::PrefilterMethod::Msm, shadowkit::PrefilterFormat::Float32},
    {shadowkit::PrefilterMethod::Msm, shadowkit::PrefilterFormat::Unorm16},
    {shadowkit::PrefilterMethod::MsmHausdorff, shadowkit::PrefilterFormat::Unorm16}};

/// How far a stored moment may be from prefilter_store of the CPU's: relative 2e-5 (fp32), 1e-3 (fp16),
/// 1.5 steps of 16-bit unorm.
inline double moment_tolerance(shadowkit::PrefilterFormat f, double expect) {
    return f == shadowkit::PrefilterFormat::Float32   ? 2e-5 * std::max(1.0, std::abs(expect))
           : f == shadowkit::PrefilterFormat::Float16 ? 1e-3 * std::max(1.0, std::abs(expect))
                                                      : 1.5 / 65535.0;
}

/// The separable blur's brute force: the 2D kernel w[|i|] w[|j|] (radius `radius`), coordinates
/// clamped to the W x H RGBA map `data`.
inline std::vector<double> blur_reference(const std::vector<float>& data, int W, int H, const float* w, int radius) {
    std::vector<double> ref(data.size(), 0.0);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            for (int j = -radius; j <= radius; ++j)
                for (int i = -radius; i <= radius; ++i) {
                    const int sx = std::clamp(x + i, 0, W - 1), sy = std::clamp(y + j, 0, H - 1);
                    const double wt = double(w[std::abs(i)]) * double(w[std::abs(j)]);
                    for (int c = 0; c < 4; ++c)
                        ref[static_cast<std::size_t>((y * W + x) * 4 + c)] +=
                            wt * double(data[static_cast<std::size_t>((sy * W + sx) * 4 + c)]);
                }
    return ref;
}

/// What a resolve of texel i must hold: the mean of its S samples' moments (window depths z, 4 a
/// texel), quantized afterwards where the method asks.
inline glm::vec4 resolve_reference(const std::vector<float>& z, std::size_t i, int S, const glm::vec4& window_map,
                                   const shadowkit::PrefilterUniforms& u) {
    glm::vec4 mean(0.0f);
    for (int s = 0; s < S; ++s) {
        const float t = shadowkit::prefilter_depth_from_window(z[4 * i + static_cast<std::size_t>(s)], window_map);
        shadowkit::PrefilterUniforms raw = u;
        raw.quantized = false;
        mean += shadowkit::prefilter_moments(t, glm::vec2(0.0f), raw) / float(S);
    }
    if (u.quantized) mean = shadowkit::prefilter_msm_quantize(mean);
    return mean;
}

/// The soft lookup's scene: a half-plane blocker x < x_edge at distance db over a floor at dr under a
/// square emitter of width w; receivers on the floor across the penumbra (centered on x_edge dr / db),
/// (u, v, t, 0) in `in`, their x in `xs`.
struct SoftScene {
    float w = 1.0f, db = 4.0f, dr = 8.0f, x_edge = 0.37f;
    std::vector<glm::vec4> in;
    std::vector<double> xs;
    SoftScene(const glm::mat4& P, const shadowkit::PrefilterDepthRange& range, int RX, int RY) {
        in.resize(static_cast<std::size_t>(RX * RY));
        xs.resize(in.size());
        const double xc = x_edge * dr / db, half = 1.5 * w * (dr - db) / db;
        for (int j = 0; j < RY; ++j)
            for (int i = 0; i < RX; ++i) {
                const auto k = static_cast<std::size_t>(j * RX + i);
                const double x = xc - half + 2.0 * half * (i + 0.5) / RX, y = -1.3 + 0.9 * j;
                const glm::vec4 c = P * glm::vec4(float(x), float(y), -dr, 1.0f);
                xs[k] = x;
                in[k] = glm::vec4(0.5f * c.x / c.w + 0.5f, 0.5f * c.y / c.w + 0.5f, shadowkit::prefilter_depth(dr, range), 0.0f);
            }
    }
    /// The ray-cast visibility at receiver k (the emitter's uncovered fraction).
    double exact(std::size_t k) const {
        return 1.0 - std::clamp(((x_edge * dr - xs[k] * db) / (dr - db) + 0.5 * w) / w, 0.0, 1.0);
    }
};

/// A CPU trilinear lookup (clamp to edge) of a mip chain of `levels` levels, level 0 n x n, whose
/// texels `texel(level, x, y)` gives (coordinates already clamped by the caller's texel).
template <class Texel>
struct MipMirror {
    Texel texel;
    int n = 0, levels = 0;
    glm::vec4 bilinear(int l, float uu, float vv) const {
        const float nl = float(n >> l), fx = uu * nl - 0.5f, fy = vv * nl - 0.5f;
        const int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
        const float ax = fx - float(x0), ay = fy - float(y0);
        return (1.0f - ay) * ((1.0f - ax) * texel(l, x0, y0) + ax * texel(l, x0 + 1, y0)) +
               ay * ((1.0f - ax) * texel(l, x0, y0 + 1) + ax * texel(l, x0 + 1, y0 + 1));
    }
    glm::vec4 sample(float uu, float vv, float level) const {
        const float l = std::clamp(level, 0.0f, float(levels - 1));
        const int l0 = int(std::floor(l));
        const float fr = l - float(l0);
        const glm::vec4 a = bilinear(l0, uu, vv);
        return fr > 0.0f ? (1.0f - fr) * a + fr * bilinear(std::min(l0 + 1, levels - 1), uu, vv) : a;
    }
};
template <class Texel>
MipMirror<Texel> mip_mirror(Texel texel, int n, int levels) {
    return MipMirror<Texel>{texel, n, levels};
}

/// At receiver k: the CPU mirror of the soft lookup and the hard lookup (level 0), both at t - bias.
struct SoftPoint {
    float cpu = 0.f;
    double hard = 0.0;
};
template <class Texel>
SoftPoint soft_point(const MipMirror<Texel>& mirror, const glm::vec4& in, float bias, const shadowkit::PrefilterUniforms& u,
                     const shadowkit::PrefilterSoftUniforms& su) {
    const float uu = in.x, vv = in.y, t = in.z - bias;
    auto sample = [&](float level) { return mirror.sample(uu, vv, level); };
    SoftPoint p;
    p.cpu = shadowkit::prefilter_soft_visibility(sample, t, u, su);
    p.hard = shadowkit::prefilter_visibility(sample(0.0f), t, u);
    return p;
}

}  // namespace prefiltered_ref
