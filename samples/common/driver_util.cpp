// Internal helpers shared by the technique drivers (the GL ones live in techniques.cpp).
#include "driver_util.hpp"

#include <algorithm>

namespace sk {

double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

double median_of(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
}

bool median_cpu_ms(int runs, const std::function<bool()>& work, double& ms) {
    std::vector<double> samples;
    for (int it = 0; it < runs; ++it) {
        const auto t0 = Clock::now();
        if (!work()) return false;
        samples.push_back(ms_since(t0));
    }
    ms = median_of(samples);
    return true;
}

}  // namespace sk
