// Shared byte decoder for the libFuzzer targets in tests/fuzz (a header, not a target: CMake globs
// fuzz_*.cpp). Every read takes bytes from the front of the input in host byte order; a read past
// the end gets the bytes that are left, zero-padded, so every input decodes to something and a
// target never checks the size itself. Plus the small invariant helpers the targets share.
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>

namespace shadowkit_fuzz {

class FuzzInput {
public:
    FuzzInput(const std::uint8_t* data, std::size_t bytes) : p_(data), n_(bytes) {}

    std::size_t remaining() const { return n_; }

    // The next sizeof(T) bytes as a T (trivially copyable); a short tail is zero-padded.
    template <class T>
    T raw() {
        static_assert(std::is_trivially_copyable<T>::value, "raw<T> copies bytes");
        T v{};
        const std::size_t k = n_ < sizeof(T) ? n_ : sizeof(T);
        if (k != 0) std::memcpy(&v, p_, k);
        p_ += k;
        n_ -= k;
        return v;
    }
    std::uint8_t u8() { return raw<std::uint8_t>(); }
    std::uint16_t u16() { return raw<std::uint16_t>(); }
    std::uint32_t u32() { return raw<std::uint32_t>(); }
    std::uint64_t u64() { return raw<std::uint64_t>(); }
    std::int8_t i8() { return raw<std::int8_t>(); }
    std::int32_t i32() { return raw<std::int32_t>(); }
    bool boolean() { return (u8() & 1u) != 0; }

    // An integer in [lo, hi] (lo <= hi) from 1, 2, 4 or 8 bytes, the fewest that cover the span.
    template <class Int>
    Int range(Int lo, Int hi) {
        static_assert(std::is_integral<Int>::value, "range<Int> needs an integer type");
        const std::uint64_t span = static_cast<std::uint64_t>(hi) - static_cast<std::uint64_t>(lo);
        std::uint64_t x = span <= 0xFFu ? u8() : span <= 0xFFFFu ? u16() : span <= 0xFFFFFFFFu ? u32() : u64();
        if (span != std::numeric_limits<std::uint64_t>::max()) x %= span + 1u;
        return static_cast<Int>(static_cast<std::uint64_t>(lo) + x);
    }
    // A size (count, capacity) in [0, cap].
    std::size_t size(std::size_t cap) { return range<std::size_t>(0, cap); }

    // Raw bit patterns: NaN, Inf, denormals and huge values all reachable.
    float f32() { return raw<float>(); }
    double f64() { return raw<double>(); }
    // One byte picks an edge value: +-0, +-1, +-1e-6, +-1e6, the smallest normal and denormal,
    // +-largest finite, +-Inf, NaN, 0.5.
    float interesting_f32() {
        static constexpr float kValues[16] = {0.0f,
                                              -0.0f,
                                              1.0f,
                                              -1.0f,
                                              1e-6f,
                                              -1e-6f,
                                              1e6f,
                                              -1e6f,
                                              std::numeric_limits<float>::min(),
                                              std::numeric_limits<float>::denorm_min(),
                                              std::numeric_limits<float>::max(),
                                              -std::numeric_limits<float>::max(),
                                              std::numeric_limits<float>::infinity(),
                                              -std::numeric_limits<float>::infinity(),
                                              std::numeric_limits<float>::quiet_NaN(),
                                              0.5f};
        return kValues[u8() % 16u];
    }
    // A signed byte times step: small exact values on a grid, so points, planes and depths coincide.
    float quantized(float step) { return static_cast<float>(i8()) * step; }
    // Raw bits or a quantized value (a target's "raw" mode flag picks).
    float value(bool raw_bits, float step) { return raw_bits ? f32() : quantized(step); }
    // Mostly reasonable: a selector byte, then raw bits; 3 selector values in 4 fold a finite value
    // into (-bound, bound) with fmod, the rest keep the raw bits (NaN, Inf, huge) as they are.
    float mostly_within(float bound) {
        const std::uint8_t sel = u8();
        const float x = f32();
        return (sel < 192 && std::isfinite(x)) ? std::fmod(x, bound) : x;
    }

    // Vectors and matrices of raw floats, components (columns for mat4) in order.
    glm::vec2 vec2() {
        const float x = f32(), y = f32();
        return glm::vec2(x, y);
    }
    glm::vec3 vec3() {
        const float x = f32(), y = f32(), z = f32();
        return glm::vec3(x, y, z);
    }
    glm::vec4 vec4() {
        const float x = f32(), y = f32(), z = f32(), w = f32();
        return glm::vec4(x, y, z, w);
    }
    glm::mat4 mat4() {
        glm::mat4 m;
        for (int c = 0; c < 4; ++c) m[c] = vec4();
        return m;
    }
    // The same with value(raw_bits, step) components.
    glm::vec2 vec2(bool raw_bits, float step) {
        const float x = value(raw_bits, step), y = value(raw_bits, step);
        return glm::vec2(x, y);
    }
    glm::vec3 vec3(bool raw_bits, float step) {
        const float x = value(raw_bits, step), y = value(raw_bits, step), z = value(raw_bits, step);
        return glm::vec3(x, y, z);
    }

    // A camera view (lookAt) from a raw eye position and forward direction (6 floats); identity when
    // the direction is ~0 or either is not finite, so the deep paths still get a well-formed camera.
    glm::mat4 look_at_view() {
        const glm::vec3 eye = vec3(), fwd = vec3();
        const float len = glm::length(fwd);
        if (!(len > 1e-6f) || !std::isfinite(len) || !std::isfinite(glm::length(eye))) return glm::mat4(1.0f);
        const glm::vec3 f = fwd / len;
        return glm::lookAt(eye, eye + f, std::fabs(f.y) > 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0));
    }
    // A GL perspective projection from raw fovy, near, far (far is read even when infinite).
    glm::mat4 perspective(float aspect, bool infinite) {
        const float fovy = f32(), near_z = f32(), far_z = f32();
        return infinite ? glm::infinitePerspective(fovy, aspect, near_z) : glm::perspective(fovy, aspect, near_z, far_z);
    }

private:
    const std::uint8_t* p_;
    std::size_t n_;
};

// Invariant check: traps (a libFuzzer crash) when violated.
inline void check(bool ok) {
    if (!ok) __builtin_trap();
}

// Where a status came from: a non-Ok result names the offending input (`detail` non-null), an Ok one
// has detail == nullptr. (A NotRun result traps too: every call fills its result.)
template <class R>
inline void check_detail(const R& r) {
    check((r.status == decltype(r.status)::Ok) == (r.detail == nullptr));
}

inline bool all_finite(float v) { return std::isfinite(v); }
inline bool all_finite(const glm::vec2& v) { return std::isfinite(v.x) && std::isfinite(v.y); }
inline bool all_finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
inline bool all_finite(const glm::vec4& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::isfinite(v.w);
}
inline bool all_finite(const glm::mat4& m) {
    return all_finite(m[0]) && all_finite(m[1]) && all_finite(m[2]) && all_finite(m[3]);
}

}  // namespace shadowkit_fuzz
