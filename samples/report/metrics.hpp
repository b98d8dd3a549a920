// Error metrics of a technique's visibility against the reference, over receiver pixels that face
// the light (GBuffer kind == 1 and the light's centre in front of the surface).
#pragma once

#include <cstddef>
#include <vector>

#include "reference.hpp"

namespace sk {

struct Metrics {
    double rmse = 0.0;
    double mean_abs = 0.0;
    double p99_abs = 0.0;
    bool has_penumbra = false;  // penumbra_rmse defined (some pixels with 0 < V_ref < 1)
    double penumbra_rmse = 0.0;
    bool has_misclassified = false;  // hard techniques only
    double misclassified = 0.0;      // fraction of compared pixels away from 1-pixel edges
    std::size_t pixels = 0, penumbra_pixels = 0;
    // Light leaking into the reference's umbra (compared pixels with V_ref == 0): the fraction of
    // them where V > 0.1, and the mean excess V - V_ref (= mean V) over all of them.
    bool has_leak = false;  // some compared pixels have V_ref == 0
    double leak_fraction = 0.0, leak_mean_excess = 0.0;
    std::size_t umbra_pixels = 0;
};

// `hard`: the technique produces 0/1 visibility, so the misclassified-pixel rate is computed
// against round(V_ref), skipping pixels within one pixel of a change of that class.
Metrics compute_metrics(const GBuffer& g, const Reference& ref, const std::vector<float>& v, bool hard);

}  // namespace sk
