// Independent exact reference for the facing sign of silhouette.hpp, for the unit tests:
// d = dot(cross(B - A, C - A), l - w A) evaluated literally (differences first, as the definition
// reads) in exact signed big-integer arithmetic on the float inputs scaled to integers (every float
// is an integer multiple of 2^-149). Shares nothing with the header's expanded-monomial fixed-point
// evaluation: different formula, different number representation, schoolbook multiplication.
#pragma once

#include <glm/glm.hpp>

#include <cmath>
#include <cstdint>
#include <vector>

namespace exact_ref {

// Signed magnitude, little-endian base 2^32 limbs, no leading zero limbs (zero: empty).
struct Big {
    bool neg = false;
    std::vector<std::uint32_t> mag;
};

inline void trim(Big& a) {
    while (!a.mag.empty() && a.mag.back() == 0u) a.mag.pop_back();
    if (a.mag.empty()) a.neg = false;
}

inline int cmp_mag(const std::vector<std::uint32_t>& a, const std::vector<std::uint32_t>& b) {
    if (a.size() != b.size()) return a.size() < b.size() ? -1 : 1;
    for (std::size_t i = a.size(); i-- > 0;)
        if (a[i] != b[i]) return a[i] < b[i] ? -1 : 1;
    return 0;
}

inline std::vector<std::uint32_t> add_mag(const std::vector<std::uint32_t>& a, const std::vector<std::uint32_t>& b) {
    std::vector<std::uint32_t> r(std::max(a.size(), b.size()) + 1, 0u);
    std::uint64_t c = 0;
    for (std::size_t i = 0; i < r.size(); ++i) {
        const std::uint64_t t = c + (i < a.size() ? a[i] : 0u) + (i < b.size() ? b[i] : 0u);
        r[i] = static_cast<std::uint32_t>(t);
        c = t >> 32;
    }
    return r;
}

// |a| >= |b|
inline std::vector<std::uint32_t> sub_mag(const std::vector<std::uint32_t>& a, const std::vector<std::uint32_t>& b) {
    std::vector<std::uint32_t> r(a.size(), 0u);
    std::int64_t borrow = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        std::int64_t t = static_cast<std::int64_t>(a[i]) - (i < b.size() ? static_cast<std::int64_t>(b[i]) : 0) - borrow;
        borrow = t < 0 ? 1 : 0;
        if (t < 0) t += (std::int64_t(1) << 32);
        r[i] = static_cast<std::uint32_t>(t);
    }
    return r;
}

inline Big add(const Big& a, const Big& b) {
    Big r;
    if (a.neg == b.neg) {
        r.mag = add_mag(a.mag, b.mag);
        r.neg = a.neg;
    } else if (cmp_mag(a.mag, b.mag) >= 0) {
        r.mag = sub_mag(a.mag, b.mag);
        r.neg = a.neg;
    } else {
        r.mag = sub_mag(b.mag, a.mag);
        r.neg = b.neg;
    }
    trim(r);
    return r;
}

inline Big neg(Big a) {
    if (!a.mag.empty()) a.neg = !a.neg;
    return a;
}
inline Big sub(const Big& a, const Big& b) { return add(a, neg(b)); }

inline Big mul(const Big& a, const Big& b) {
    Big r;
    if (a.mag.empty() || b.mag.empty()) return r;
    r.mag.assign(a.mag.size() + b.mag.size(), 0u);
    for (std::size_t i = 0; i < a.mag.size(); ++i) {
        std::uint64_t c = 0;
        for (std::size_t j = 0; j < b.mag.size(); ++j) {
            const std::uint64_t t = static_cast<std::uint64_t>(a.mag[i]) * b.mag[j] + r.mag[i + j] + c;
            r.mag[i + j] = static_cast<std::uint32_t>(t);
            c = t >> 32;
        }
        std::size_t k = i + b.mag.size();
        while (c) {
            const std::uint64_t t = static_cast<std::uint64_t>(r.mag[k]) + c;
            r.mag[k] = static_cast<std::uint32_t>(t);
            c = t >> 32;
            ++k;
        }
    }
    r.neg = a.neg != b.neg;
    trim(r);
    return r;
}

inline Big shl(Big a, int bits) {
    if (a.mag.empty()) return a;
    const int limbs = bits / 32, b = bits % 32;
    std::vector<std::uint32_t> r(a.mag.size() + static_cast<std::size_t>(limbs) + 1, 0u);
    for (std::size_t i = 0; i < a.mag.size(); ++i) {
        const std::uint64_t v = static_cast<std::uint64_t>(a.mag[i]) << b;
        r[i + static_cast<std::size_t>(limbs)] |= static_cast<std::uint32_t>(v);
        r[i + static_cast<std::size_t>(limbs) + 1] |= static_cast<std::uint32_t>(v >> 32);
    }
    a.mag = r;
    trim(a);
    return a;
}

// f * 2^149 as an exact integer (finite f).
inline Big from_float(float f) {
    Big r;
    if (f == 0.0f) return r;
    int e = 0;
    const double frac = std::frexp(static_cast<double>(std::fabs(f)), &e);  // |f| = frac 2^e
    std::uint64_t m = static_cast<std::uint64_t>(std::ldexp(frac, 24));   // exact: 24 bits
    int s = e - 24 + 149;
    while (s < 0) { m >>= 1; ++s; }  // exact: f is a multiple of 2^-149
    r.mag = {static_cast<std::uint32_t>(m & 0xFFFFFFFFu), static_cast<std::uint32_t>(m >> 32)};
    trim(r);
    r = shl(r, s);
    r.neg = f < 0.0f;
    return r;
}

inline int sign(const Big& a) { return a.mag.empty() ? 0 : (a.neg ? -1 : 1); }

// Exact sign of dot(cross(B - A, C - A), l - w A) for finite float inputs.
inline int facing_sign(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec4& L) {
    const Big A[3] = {from_float(a.x), from_float(a.y), from_float(a.z)};
    const Big B[3] = {from_float(b.x), from_float(b.y), from_float(b.z)};
    const Big C[3] = {from_float(c.x), from_float(c.y), from_float(c.z)};
    const Big l[3] = {from_float(L.x), from_float(L.y), from_float(L.z)};
    const Big w = from_float(L.w);
    Big e1[3], e2[3], q[3];
    for (int i = 0; i < 3; ++i) {
        e1[i] = sub(B[i], A[i]);                     // scale 2^149
        e2[i] = sub(C[i], A[i]);
        q[i] = sub(shl(l[i], 149), mul(w, A[i]));    // scale 2^298
    }
    const Big n[3] = {sub(mul(e1[1], e2[2]), mul(e1[2], e2[1])), sub(mul(e1[2], e2[0]), mul(e1[0], e2[2])),
                      sub(mul(e1[0], e2[1]), mul(e1[1], e2[0]))};  // scale 2^298
    return sign(add(add(mul(n[0], q[0]), mul(n[1], q[1])), mul(n[2], q[2])));
}

}  // namespace exact_ref
