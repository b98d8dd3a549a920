// libFuzzer target for include/shadowkit/poisson_disk.hpp: every public function with decoded
// domains, radii, counts, seeds, capacities and GLSL names; invariants trap on violation (no
// result says NotRun; Ok only with finite outputs; count <= capacity).
#include <shadowkit/poisson_disk.hpp>

#include "fuzz_input.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

namespace {
void check_set(const shadowkit::PoissonDomain& d, const glm::vec2* pts, size_t n) {
    for (size_t i = 0; i < n; ++i)
        if (!shadowkit::poisson_domain_contains(d, pts[i])) __builtin_trap();
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace shadowkit;
    shadowkit_fuzz::FuzzInput r(data, size);
    const uint8_t op = r.u8();
    PoissonDomain d;
    d.shape = static_cast<PoissonShape>(r.range(0, 3));  // 3 is invalid on purpose
    d.inner_radius = r.f32();
    const float radius = r.f32();
    const uint32_t count_raw = r.u32();
    const uint64_t seed = r.u64();
    const size_t capacity = r.size(4095);
    const uint8_t flags = r.u8();
    const int attempts = r.range(-4, 251);
    const int factor = r.range(0, 79);

    const PoissonValue area = poisson_domain_area(d);
    shadowkit_fuzz::check_detail(area);
    if (area.status == Status::NotRun || (area.status == Status::Ok && !(area.value > 0.0f))) __builtin_trap();
    const PoissonValue pk = poisson_packing_distance(d, count_raw);
    shadowkit_fuzz::check_detail(pk);
    if (pk.status == Status::NotRun || (pk.status == Status::Ok && !(std::isfinite(pk.value) && pk.value > 0.0f))) __builtin_trap();
    std::vector<glm::vec2> buf(capacity ? capacity : 1);
    glm::vec2* out = (flags & 1) && capacity == 0 ? nullptr : buf.data();

    if (op % 3 == 0) {
        const size_t cap_bound = poisson_bridson_capacity(d, radius);
        if (cap_bound > 1024 && cap_bound <= kPoissonMaxPoints) return 0;  // valid but slow: skip
        PoissonBridsonOptions o;
        o.attempts = attempts;
        o.fill_gaps = (flags & 2) != 0;
        const PoissonResult res = poisson_bridson(d, radius, seed, out, capacity, o);
        shadowkit_fuzz::check_detail(res);
        if (res.count > capacity || res.status == Status::NotRun) __builtin_trap();
        if (res.status == Status::Ok || res.status == Status::BufferTooSmall) {
            if (res.needed > cap_bound) __builtin_trap();
            if (res.status == Status::Ok && res.count != res.needed) __builtin_trap();
            check_set(d, out, res.count);
            if (res.count >= 2 && res.count <= 300) {
                const PoissonValue md = poisson_min_distance(out, res.count);
                shadowkit_fuzz::check_detail(md);
                if (md.status != Status::Ok || !(double(md.value) >= double(radius) * (1.0 - 1e-7))) __builtin_trap();
            }
        } else if (res.count != 0) {
            __builtin_trap();
        }
    } else {
        size_t count = (flags & 4) ? count_raw : count_raw % 300;
        const size_t f2 = size_t(factor) * size_t(factor);  // work grows with count * factor^2
        if (factor >= 2 && factor <= 64 && count <= 300 && count * f2 > 20000)
            count = 20000 / f2;  // keep each run fast
        PoissonEliminationOptions o;
        o.candidate_factor = factor;
        o.progressive = (flags & 8) != 0;
        o.weight_limiting = (flags & 16) != 0;
        if (count > 300 && count <= kPoissonMaxPoints) return 0;  // valid but slow: skip
        const PoissonResult res = poisson_eliminate(d, count, seed, out, capacity, o);
        shadowkit_fuzz::check_detail(res);
        if (res.count > capacity || res.status == Status::NotRun) __builtin_trap();
        if (res.status == Status::Ok) {
            if (res.count != count || !std::isfinite(res.radius)) __builtin_trap();
            check_set(d, out, res.count);
            const PoissonValue md = poisson_min_distance(out, res.count);
            shadowkit_fuzz::check_detail(md);
            if (res.count >= 2 && (md.status != Status::Ok || md.value != res.radius)) __builtin_trap();
            const PoissonValue rho = poisson_normalized_radius(d, out, res.count);
            shadowkit_fuzz::check_detail(rho);
            if (rho.status == Status::Ok ? !std::isfinite(rho.value) : res.count >= 2) __builtin_trap();
            if (res.count <= 24) {
                const PoissonValue cov = poisson_coverage_radius(d, out, res.count);
                shadowkit_fuzz::check_detail(cov);
                const PoissonValue grid = poisson_coverage_radius_grid(d, out, res.count, 33);
                shadowkit_fuzz::check_detail(grid);
                if ((cov.status == Status::Ok) != (res.count > 0) || (grid.status == Status::Ok) != (res.count > 0)) __builtin_trap();
                if (res.count > 0 && !(grid.value <= cov.value + 1e-5f)) __builtin_trap();
            }
            // GLSL emission with a fuzzed name and capacity.
            char name[9];
            for (int i = 0; i < 8; ++i) name[i] = static_cast<char>(r.range(0, 127));
            name[8] = '\0';
            if (flags & 32) std::memcpy(name, "SK_TAPS", 8);
            const size_t text_cap = r.u16();
            std::vector<char> text(text_cap + 1, 'x');
            const PoissonGlsl mode = static_cast<PoissonGlsl>(r.range(0, 2));  // 2: invalid
            const PoissonGlslResult g = poisson_to_glsl(out, res.count, name, mode, text_cap ? text.data() : nullptr, text_cap);
            shadowkit_fuzz::check_detail(g);
            if (text[text_cap] != 'x') __builtin_trap();  // never writes past capacity
            if (g.status == Status::NotRun || g.count > text_cap) __builtin_trap();
            if (g.status == Status::Ok || g.status == Status::BufferTooSmall) {
                if (text_cap > 0 && std::memchr(text.data(), '\0', text_cap) == nullptr) __builtin_trap();
                if (g.status == Status::Ok && (std::strlen(text.data()) + 1 != g.needed || g.count != g.needed)) __builtin_trap();
                if (g.status == Status::Ok && std::strstr(text.data(), "__") != nullptr) __builtin_trap();
            }
        }
    }
    return 0;
}
