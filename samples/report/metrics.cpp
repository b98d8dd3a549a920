#include "metrics.hpp"

#include <algorithm>
#include <cmath>

namespace sk {

Metrics compute_metrics(const GBuffer& g, const Reference& ref, const std::vector<float>& v, bool hard) {
    Metrics m;
    const int w = g.width, h = g.height;
    std::vector<double> abs_err;
    double sq = 0.0, ab = 0.0, psq = 0.0;
    std::size_t compared = 0, wrong = 0;
    auto receiver = [&](std::size_t k) { return g.kind[k] == 1 && ref.faces_light[k] != 0; };
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const auto k = static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x);
            if (!receiver(k)) continue;
            const double vr = ref.visibility[k];
            const double e = double(v[k]) - vr;
            sq += e * e;
            ab += std::abs(e);
            abs_err.push_back(std::abs(e));
            ++m.pixels;
            if (vr > 0.0 && vr < 1.0) {
                psq += e * e;
                ++m.penumbra_pixels;
            }
            if (vr == 0.0) {
                ++m.umbra_pixels;
                m.leak_mean_excess += double(v[k]);
                if (v[k] > 0.1f) m.leak_fraction += 1.0;
            }
            if (hard && x > 0 && y > 0 && x < w - 1 && y < h - 1) {
                const int cls = vr >= 0.5 ? 1 : 0;
                bool edge = false;
                for (int dy = -1; dy <= 1 && !edge; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const auto kk = static_cast<std::size_t>(y + dy) * static_cast<std::size_t>(w) +
                                        static_cast<std::size_t>(x + dx);
                        if (receiver(kk) && (ref.visibility[kk] >= 0.5f ? 1 : 0) != cls) edge = true;
                    }
                if (!edge) {
                    ++compared;
                    if ((v[k] >= 0.5f ? 1 : 0) != cls) ++wrong;
                }
            }
        }
    if (m.pixels) {
        m.rmse = std::sqrt(sq / double(m.pixels));
        m.mean_abs = ab / double(m.pixels);
        const std::size_t idx = std::min(abs_err.size() - 1, static_cast<std::size_t>(0.99 * double(abs_err.size())));
        std::nth_element(abs_err.begin(), abs_err.begin() + static_cast<std::ptrdiff_t>(idx), abs_err.end());
        m.p99_abs = abs_err[idx];
    }
    if (m.umbra_pixels) {
        m.has_leak = true;
        m.leak_fraction /= double(m.umbra_pixels);
        m.leak_mean_excess /= double(m.umbra_pixels);
    }
    if (m.penumbra_pixels) {
        m.has_penumbra = true;
        m.penumbra_rmse = std::sqrt(psq / double(m.penumbra_pixels));
    }
    if (hard) {
        m.has_misclassified = true;
        m.misclassified = compared ? double(wrong) / double(compared) : 0.0;
    }
    return m;
}

}  // namespace sk
