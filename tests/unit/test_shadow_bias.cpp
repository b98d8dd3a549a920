// Unit and property tests for include/shadowkit/shadow_bias.hpp.
#include <shadowkit/shadow_bias.hpp>

#include <doctest/doctest.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <random>
#include <string>

using namespace shadowkit;

namespace {

struct Basis {
    glm::dvec3 r, u, f;  // right, up, forward (light travels along f)
};

glm::dvec3 random_unit(std::mt19937& g) {
    std::normal_distribution<double> n(0.0, 1.0);
    for (;;) {
        glm::dvec3 v(n(g), n(g), n(g));
        const double l = glm::length(v);
        if (l > 1e-3) return v / l;
    }
}

Basis random_basis(std::mt19937& g) {
    Basis b;
    b.f = random_unit(g);
    glm::dvec3 a = random_unit(g);
    b.r = glm::normalize(glm::cross(a, b.f));
    b.u = glm::cross(b.f, b.r);
    return b;
}

// Depth (along f) where the light ray through image-plane point (u, v) meets the plane n.x = c.
double ray_plane_depth(const Basis& b, glm::dvec3 n, double c, double u, double v) {
    // x = u r + v u_ + z f ; n.x = c
    return (c - u * glm::dot(n, b.r) - v * glm::dot(n, b.u)) / glm::dot(n, b.f);
}

glm::vec3 to_f(glm::dvec3 v) { return glm::vec3(v); }

// Independent inverses of the stored depth value.
double inverse_metric(BiasDepthMetric m, double z, double n, double f) {
    switch (m) {
    case BiasDepthMetric::PostProjective: return std::isinf(f) ? n / (1.0 - z) : f * n / (f - z * (f - n));
    case BiasDepthMetric::PostProjectiveReversed: return std::isinf(f) ? n / z : f * n / (n + z * (f - n));
    case BiasDepthMetric::LinearNormalized: return n + z * (f - n);
    case BiasDepthMetric::LinearDistance: return z;
    }
    return NAN;
}

// The value of an Ok result (the test fails if it is not Ok).
template <class R>
auto val(const R& r) -> decltype(r.value) {
    INFO("status " << std::string(status_name(r.status)));
    CHECK(r.status == Status::Ok);
    return r.value;
}
glm::vec3 val(const BiasPosition& r) {
    INFO("status " << std::string(status_name(r.status)));
    CHECK(r.status == Status::Ok);
    return r.position;
}

}  // namespace

TEST_CASE("depth formats: quantization step and rounding") {
    CHECK(val(bias_depth_format_step(DepthFormat::Fixed24, 0.3)) == doctest::Approx(1.0 / 16777215.0).epsilon(1e-12));
    CHECK(val(bias_depth_format_step(DepthFormat::Fixed16, 0.3)) == doctest::Approx(1.0 / 65535.0).epsilon(1e-12));
    CHECK(val(bias_depth_format_step(DepthFormat::Float32, 0.75)) == std::ldexp(1.0, -24));
    CHECK(val(bias_depth_format_step(DepthFormat::Float32, 1.0)) == std::ldexp(1.0, -23));
    CHECK(val(bias_depth_format_step(DepthFormat::Float32, 0.5)) == std::ldexp(1.0, -24));
    // About 1.07e9 float values lie in [0, 1) (the thesis's precision claim is wrong).
    CHECK(std::ldexp(1.0, -24) < 1e-7);
    CHECK(val(bias_quantize_depth(DepthFormat::Fixed16, 0.5)) == doctest::Approx(32768.0 / 65535.0).epsilon(1e-12));
    CHECK(val(bias_quantize_depth(DepthFormat::Fixed16, -3.0)) == 0.0);
    CHECK(val(bias_quantize_depth(DepthFormat::Fixed16, 7.0)) == 1.0);
    CHECK(bias_quantize_depth(DepthFormat::Fixed24, NAN).status == Status::NonFinite);
    CHECK(bias_depth_format_step(DepthFormat::Float32, NAN).status == Status::NonFinite);
    CHECK(bias_depth_format_step(DepthFormat::Float32, INFINITY).status == Status::NonFinite);
    CHECK(bias_depth_format_step(static_cast<DepthFormat>(5), 0.5).status == Status::InvalidArgument);
    CHECK(bias_quantize_depth(DepthFormat::Float32, 1e300).status == Status::Overflow);
    CHECK(bias_depth_format_step(DepthFormat::Float32, double(FLT_MAX)).status == Status::Overflow);
    CHECK(bias_depth_format_bits(DepthFormat::Fixed24) == 24);
    CHECK(bias_depth_format_bits(static_cast<DepthFormat>(5)) == 0);  // total
}

TEST_CASE("depth resolution: closed forms and brute force against the next representable value") {
    const double n = 0.1, f = 100.0;
    // Closed form, post-projective UNORM24 at d = 50.
    const double expect = 50.0 * 50.0 * (f - n) / (f * n * 16777215.0);
    CHECK(val(bias_depth_metric_resolution(BiasDepthMetric::PostProjective, DepthFormat::Fixed24, 50.0, n, f)) == doctest::Approx(expect).epsilon(1e-9));
    CHECK(val(bias_depth_metric_resolution(BiasDepthMetric::LinearNormalized, DepthFormat::Fixed16, 50.0, n, f)) == doctest::Approx((f - n) / 65535.0).epsilon(1e-9));

    std::mt19937 g(2024);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    const BiasDepthMetric metrics[4] = {BiasDepthMetric::PostProjective, BiasDepthMetric::PostProjectiveReversed,
                                    BiasDepthMetric::LinearNormalized, BiasDepthMetric::LinearDistance};
    const DepthFormat formats[3] = {DepthFormat::Float32, DepthFormat::Fixed24, DepthFormat::Fixed16};
    int checked = 0;
    for (int it = 0; it < 3000; ++it) {
        const BiasDepthMetric m = metrics[it % 4];
        const DepthFormat fmt = formats[(it / 4) % 3];
        const double nn = std::pow(10.0, -2.0 + 2.0 * u01(g));
        const double ff = nn * std::pow(10.0, 1.0 + 4.0 * u01(g));
        const double d = nn * std::pow(ff / nn, u01(g));
        if (m == BiasDepthMetric::LinearDistance && fmt != DepthFormat::Float32) {
            CHECK(bias_depth_metric_resolution(m, fmt, d, nn, ff).status == Status::InvalidArgument);
            continue;
        }
        const double res = val(bias_depth_metric_resolution(m, fmt, d, nn, ff));
        // Brute force: stored value, the next stored value above, both mapped back to distance.
        const double v = val(bias_depth_metric_value(m, d, nn, ff));
        double q0, q1;
        if (fmt == DepthFormat::Float32) {
            const float fv = static_cast<float>(v);
            q0 = fv;
            q1 = std::nextafter(fv, INFINITY);
        } else {
            const double scale = std::ldexp(1.0, fmt == DepthFormat::Fixed24 ? 24 : 16) - 1.0;
            const double k = std::round(v * scale);
            if (k + 1 > scale) continue;
            q0 = k / scale;
            q1 = (k + 1) / scale;
        }
        const double d0 = inverse_metric(m, q0, nn, ff), d1 = inverse_metric(m, q1, nn, ff);
        if (!std::isfinite(d0) || !std::isfinite(d1)) continue;
        const double brute = std::fabs(d1 - d0);
        if (brute > 0.01 * d) continue;  // first order only holds for small steps
        INFO("metric " << int(m) << " fmt " << int(fmt) << " d " << d << " n " << nn << " f " << ff);
        CHECK(res == doctest::Approx(brute).epsilon(0.03));
        ++checked;
    }
    CHECK(checked > 1500);
}

TEST_CASE("depth resolution: reversed float32 keeps relative precision, standard does not") {
    const double n = 0.1;
    for (double d : {0.2, 1.0, 10.0, 100.0, 1000.0, 1e4}) {
        const double rev = val(bias_depth_metric_resolution(BiasDepthMetric::PostProjectiveReversed, DepthFormat::Float32, d, n, INFINITY));
        CHECK(rev / d <= std::ldexp(1.0, -22));
        const double std_ = val(bias_depth_metric_resolution(BiasDepthMetric::PostProjective, DepthFormat::Float32, d, n, INFINITY));
        if (d >= 100.0) CHECK(std_ > 100.0 * rev);
        // 24-bit UNORM post-projective is comparable to standard float32 (values crowd near 1).
        const double u24 = val(bias_depth_metric_resolution(BiasDepthMetric::PostProjective, DepthFormat::Fixed24, d, n, 1e5));
        if (d >= 10.0) CHECK(u24 <= 2.5 * val(bias_depth_metric_resolution(BiasDepthMetric::PostProjective, DepthFormat::Float32, d, n, 1e5)));
    }
    // Invalid input.
    CHECK(bias_depth_metric_resolution(BiasDepthMetric::PostProjective, DepthFormat::Float32, 0.05, 0.1, 10.0).status == Status::InvalidArgument);
    CHECK(bias_depth_metric_resolution(BiasDepthMetric::PostProjective, DepthFormat::Float32, 5.0, 0.0, 10.0).status == Status::InvalidArgument);
    CHECK(bias_depth_metric_resolution(BiasDepthMetric::PostProjective, DepthFormat::Float32, NAN, 0.1, 10.0).status == Status::NonFinite);
    CHECK(bias_depth_metric_resolution(BiasDepthMetric::LinearNormalized, DepthFormat::Fixed24, 5.0, 0.1, INFINITY).status == Status::InvalidArgument);
    CHECK(bias_depth_metric_resolution(BiasDepthMetric::PostProjective, DepthFormat::Float32, 5.0, 10.0, 1.0).status == Status::InvalidArgument);
    CHECK(bias_depth_metric_resolution(static_cast<BiasDepthMetric>(9), DepthFormat::Float32, 5.0, 1.0, 10.0).status == Status::InvalidArgument);
    CHECK(bias_depth_metric_resolution(BiasDepthMetric::PostProjective, static_cast<DepthFormat>(9), 5.0, 1.0, 10.0).status == Status::InvalidArgument);
    CHECK(bias_depth_metric_value(BiasDepthMetric::PostProjective, 5.0, 1.0, -INFINITY).status == Status::NonFinite);
    CHECK(BiasDepthValue{}.status == Status::NotRun);
}

TEST_CASE("texel world size matches unprojected texel centers of glm::perspective") {
    CHECK(val(bias_texel_world_size_perspective(10.0f, 1.5707963f, 1000.0f)) == doctest::Approx(0.02).epsilon(1e-5));
    CHECK(val(bias_texel_world_size_ortho(20.0f, 1024.0f)) == doctest::Approx(20.0 / 1024.0));
    const float fov = 0.9f, res = 512.0f, d = 7.0f;
    const glm::mat4 p = glm::perspective(fov, 1.0f, 0.1f, 100.0f);
    const glm::mat4 inv = glm::inverse(p);
    auto unproject = [&](float ndc_x) {
        // Point on the ray through ndc_x at eye depth d.
        glm::vec4 a = inv * glm::vec4(ndc_x, 0.0f, 0.5f, 1.0f);
        glm::vec3 dir = glm::vec3(a) / a.w;
        return dir * (d / -dir.z);
    };
    const float w = glm::length(unproject(1.0f / res) - unproject(-1.0f / res));
    CHECK(double(val(bias_texel_world_size_perspective(d, fov, res))) == doctest::Approx(double(w)).epsilon(1e-4));
}

TEST_CASE("light_tan_angle closed forms") {
    CHECK(val(bias_light_tan_angle({0, 0, 1}, {0, 0, 1})) == 0.0f);
    CHECK(double(val(bias_light_tan_angle({0, 0, 1}, {1, 0, 1}))) == doctest::Approx(1.0));
    CHECK(double(val(bias_light_tan_angle({0, 0, 2}, {0, std::sqrt(3.0f), 1}))) == doctest::Approx(std::sqrt(3.0)).epsilon(1e-6));
    // Grazing and facing away: an outcome (faces_light = false with Ok), no infinite value.
    for (glm::vec3 l : {glm::vec3(1, 0, 0), glm::vec3(0, 0, -1), glm::vec3(1, 0, -1)}) {
        const BiasTanAngle a = bias_light_tan_angle({0, 0, 1}, l);
        CHECK(a.status == Status::Ok);
        CHECK_FALSE(a.faces_light);
        CHECK(a.value == 0.0f);
    }
    CHECK(bias_light_tan_angle({0, 0, 0}, {0, 0, 1}).status == Status::InvalidArgument);
    CHECK(bias_light_tan_angle({NAN, 0, 1}, {0, 0, 1}).status == Status::NonFinite);
    CHECK(bias_light_tan_angle({0, 0, 1}, {INFINITY, 0, 1}).status == Status::NonFinite);
    // tan beyond FLT_MAX (n . l of 1e-45 against 1): Overflow, never an infinite value with Ok.
    CHECK(bias_light_tan_angle({0, 0, 1}, {1, 0, 1e-45f}).status == Status::Overflow);
}

TEST_CASE("slope-scaled bias covers the brute-force depth range within a texel (random planes and lights)") {
    std::mt19937 g(77);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    int covered = 0, failed_small_scale = 0, total = 0;
    for (int it = 0; it < 4000; ++it) {
        const Basis b = random_basis(g);
        glm::dvec3 nrm = random_unit(g);
        if (glm::dot(nrm, -b.f) < 0) nrm = -nrm;  // faces the light
        if (glm::dot(nrm, -b.f) < 0.1) continue;  // tan <= ~10 (the default clamp)
        const double c = 10.0 * (u01(g) - 0.5);
        const double t = std::pow(10.0, -3.0 + 2.5 * u01(g));
        const double u0 = (std::floor(20.0 * (u01(g) - 0.5)) + 0.5) * t, v0 = (std::floor(20.0 * (u01(g) - 0.5)) + 0.5) * t;
        const double z0 = ray_plane_depth(b, nrm, c, u0, v0);
        double brute = 0;
        for (int i = 0; i <= 16; ++i)
            for (int j = 0; j <= 16; ++j) {
                const double z = ray_plane_depth(b, nrm, c, u0 + t * (i / 16.0 - 0.5), v0 + t * (j / 16.0 - 0.5));
                brute = std::max(brute, std::fabs(z - z0));
            }
        const float tn = val(bias_light_tan_angle(to_f(nrm), to_f(-b.f)));
        const BiasDepthGradient grad = bias_plane_depth_gradient(to_f(nrm), to_f(b.r), to_f(b.u), to_f(b.f));
        REQUIRE(grad.status == Status::Ok);
        REQUIRE_FALSE(grad.edge_on);
        CHECK(double(glm::length(grad.dz_duv)) == doctest::Approx(double(tn)).epsilon(1e-4));
        CHECK(double(val(bias_texel_depth_delta(grad.dz_duv, float(t)))) == doctest::Approx(brute).epsilon(1e-3));
        const double bias = val(bias_slope_scaled(float(t), tn));
        CHECK(bias >= brute * (1.0 - 1e-5));
        covered += bias >= brute * (1.0 - 1e-5);
        failed_small_scale += double(val(bias_slope_scaled(float(t), tn, 0.5f))) < brute * 0.999;
        ++total;
    }
    CHECK(covered == total);
    CHECK(failed_small_scale > total / 10);  // control: half a texel is not enough (diagonal gradients)
    const BiasDepthGradient edge = bias_plane_depth_gradient({1, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1});
    CHECK(edge.status == Status::Ok);
    CHECK(edge.edge_on);  // an outcome: the plane contains the light direction
    CHECK(edge.dz_duv == glm::vec2(0.0f));
    CHECK(bias_plane_depth_gradient({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}).status == Status::InvalidArgument);
    CHECK(bias_plane_depth_gradient({NAN, 0, 1}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}).status == Status::NonFinite);
    CHECK(bias_slope_scaled(1.0f, -1.0f).status == Status::InvalidArgument);
    CHECK(bias_slope_scaled(1.0f, NAN).status == Status::NonFinite);
    CHECK(bias_slope_scaled(-1.0f, 1.0f).status == Status::InvalidArgument);
    CHECK(bias_slope_scaled(1.0f, 1.0f, 0.7f, 0.0f, 0.0f).status == Status::InvalidArgument);
    CHECK(bias_slope_scaled(3e38f, 10.0f, 1.0f).status == Status::Overflow);
    CHECK(val(bias_slope_scaled(1.0f, INFINITY)) == doctest::Approx(10.0 * 0.70710678));
    CHECK(val(bias_slope_scaled(1.0f, 2.0f, 1.0f, 0.25f)) == doctest::Approx(2.25));
}

TEST_CASE("normal offset: scale >= sqrt(2)/2 removes acne on planes, smaller scales do not (brute force)") {
    std::mt19937 g(5);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    int acne_full = 0, acne_small = 0, acne_none = 0, total = 0;
    for (int it = 0; it < 4000; ++it) {
        const Basis b = random_basis(g);
        glm::dvec3 nrm = random_unit(g);
        if (glm::dot(nrm, -b.f) < 0) nrm = -nrm;
        if (glm::dot(nrm, -b.f) < 0.05) continue;
        const double c = 4.0 * (u01(g) - 0.5);
        const double t = std::pow(10.0, -2.5 + 2.0 * u01(g));
        // A receiver point on the plane.
        const double up = 3.0 * (u01(g) - 0.5), vp = 3.0 * (u01(g) - 0.5);
        const glm::dvec3 p = up * b.r + vp * b.u + ray_plane_depth(b, nrm, c, up, vp) * b.f;
        auto acne = [&](float scale) {
            const glm::dvec3 q = glm::dvec3(bias_normal_offset_position(to_f(p), to_f(nrm), to_f(-b.f), float(t), scale).position);
            const double uq = glm::dot(q, b.r), vq = glm::dot(q, b.u), zq = glm::dot(q, b.f);
            const double uc = (std::floor(uq / t) + 0.5) * t, vc = (std::floor(vq / t) + 0.5) * t;
            const double stored = ray_plane_depth(b, nrm, c, uc, vc);
            return zq > stored + 1e-5;  // shadowed by its own plane
        };
        acne_full += acne(0.75f);
        acne_small += acne(0.25f);
        acne_none += acne(0.0f);
        ++total;
    }
    CHECK(acne_full == 0);
    CHECK(acne_small > 0);
    CHECK(acne_none > total / 5);
    // Degenerate input is an error, not a silently unchanged point.
    const glm::vec3 p(1, 2, 3);
    CHECK(bias_normal_offset_position(p, {0, 0, 0}, {0, 0, 1}, 1.0f, 1.0f).status == Status::InvalidArgument);
    CHECK(bias_normal_offset_position(p, {NAN, 0, 0}, {0, 0, 1}, 1.0f, 1.0f).status == Status::NonFinite);
    CHECK(bias_normal_offset_position(p, {0, 0, 1}, {0, 0, 1}, -1.0f, 1.0f).status == Status::InvalidArgument);
    CHECK(bias_normal_offset_position({3e38f, 0, 0}, {1, 0, 0}, {0, 0, 1}, 1e38f, 1.0f).status == Status::Overflow);
    // Light along the normal: sin = 0, no offset.
    CHECK(val(bias_normal_offset_position(p, {0, 0, 1}, {0, 0, 5}, 1.0f, 1.0f)) == p);
    // 90 degrees: full offset; tiny and huge vectors give the same offset (computed in double).
    CHECK(val(bias_normal_offset_position(p, {0, 0, 1}, {1, 0, 0}, 0.5f, 2.0f)).z == doctest::Approx(4.0));
    CHECK(val(bias_normal_offset_position(p, {0, 0, 1e-44f}, {3e38f, 0, 0}, 0.5f, 2.0f)).z == doctest::Approx(4.0));
}

TEST_CASE("receiver plane depth bias is exact for planar receivers under perspective lights") {
    std::mt19937 g(31);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    int tested = 0, flat_worse = 0;
    for (int it = 0; it < 3000; ++it) {
        const bool zo = it % 2 == 0;
        const double near = 0.1 + u01(g), far = near * (10.0 + 1000.0 * u01(g));
        const double fov = 0.3 + 1.5 * u01(g);
        glm::dmat4 proj = zo ? glm::perspectiveRH_ZO(fov, 1.0, near, far) : glm::perspectiveRH_NO(fov, 1.0, near, far);
        const glm::dvec3 eye = 5.0 * random_unit(g);
        const glm::dmat4 view = glm::lookAtRH(eye, glm::dvec3(0.0), glm::dvec3(0.3, 1.0, 0.2));
        const glm::dmat4 m = proj * view;
        // Plane through a point near the origin, random orientation.
        const glm::dvec3 p0 = 0.5 * random_unit(g);
        glm::dvec3 nrm = random_unit(g);
        const glm::dvec3 a = glm::normalize(glm::cross(nrm, random_unit(g))), bb = glm::cross(nrm, a);
        auto uvz = [&](glm::dvec3 x) {
            glm::dvec4 c = m * glm::dvec4(x, 1.0);
            glm::dvec3 ndc = glm::dvec3(c) / c.w;
            const double z = zo ? ndc.z : 0.5 * ndc.z + 0.5;
            return glm::dvec3(0.5 * ndc.x + 0.5, 0.5 * ndc.y + 0.5, z);
        };
        // Exact derivatives of uvz along a and bb (quotient rule).
        auto deriv = [&](glm::dvec3 dir) {
            const glm::dvec4 c = m * glm::dvec4(p0, 1.0), dc = m * glm::dvec4(dir, 0.0);
            glm::dvec3 dn = (glm::dvec3(dc) * c.w - glm::dvec3(c) * dc.w) / (c.w * c.w);
            return glm::dvec3(0.5 * dn.x, 0.5 * dn.y, zo ? dn.z : 0.5 * dn.z);
        };
        const glm::dvec4 c0 = m * glm::dvec4(p0, 1.0);
        if (c0.w < near * 1.01) continue;
        const glm::dvec3 s0 = uvz(p0);
        if (s0.z <= 0 || s0.z >= 1 || s0.x < 0 || s0.x > 1 || s0.y < 0 || s0.y > 1) continue;
        const BiasReceiverPlane rp = bias_receiver_plane_depth_gradient(glm::vec3(deriv(a)), glm::vec3(deriv(bb)));
        REQUIRE(rp.status == Status::Ok);
        if (rp.singular) continue;
        // A tap offset up to 8 texels of a 1024 map: the light ray through s0.xy + o meets the plane.
        const glm::dvec2 o((u01(g) - 0.5) * 16.0 / 1024.0, (u01(g) - 0.5) * 16.0 / 1024.0);
        const glm::dmat4 inv = glm::inverse(m);
        auto unproj = [&](double u, double v, double zw) {
            const double zn = zo ? zw : 2.0 * zw - 1.0;
            glm::dvec4 h = inv * glm::dvec4(2.0 * u - 1.0, 2.0 * v - 1.0, zn, 1.0);
            return glm::dvec3(h) / h.w;
        };
        const glm::dvec3 r0 = unproj(s0.x + o.x, s0.y + o.y, 0.2), r1 = unproj(s0.x + o.x, s0.y + o.y, 0.8);
        const double den = glm::dot(nrm, r1 - r0);
        if (std::fabs(den) < 1e-9) continue;
        const double tt = glm::dot(nrm, p0 - r0) / den;
        const glm::dvec3 hit = r0 + tt * (r1 - r0);
        const double exact = uvz(hit).z;
        if (!(exact > 0 && exact < 1)) continue;
        const double pred = val(bias_receiver_plane_depth(float(s0.z), rp.dz_duv, glm::vec2(o)));
        const double slope_term = std::fabs(double(rp.dz_duv.x) * o.x) + std::fabs(double(rp.dz_duv.y) * o.y);
        // Exact up to float rounding of the inputs, amplified by the condition number of the uv
        // Jacobian (kappa <= |J|_F^2 / |det J|); a wrong formula errs by O(slope_term).
        const glm::dvec3 ja = deriv(a), jb = deriv(bb);
        const double kappa = (ja.x * ja.x + ja.y * ja.y + jb.x * jb.x + jb.y * jb.y) / std::fabs(ja.x * jb.y - ja.y * jb.x);
        CHECK(std::fabs(pred - exact) <= 2e-7 + 1e-6 * (1.0 + kappa) * slope_term);
        flat_worse += std::fabs(double(float(s0.z)) - exact) > std::fabs(pred - exact) + 1e-7;
        ++tested;
    }
    CHECK(tested > 1500);
    CHECK(flat_worse > tested / 2);  // control: without the plane the tap depth is wrong
    // Singular and invalid Jacobians.
    for (const BiasReceiverPlane& sg : {bias_receiver_plane_depth_gradient({1, 2, 3}, {2, 4, 1}),
                                        bias_receiver_plane_depth_gradient({0, 0, 0}, {0, 0, 0})}) {
        CHECK(sg.status == Status::Ok);  // an outcome: fall back to slope-scaled bias
        CHECK(sg.singular);
        CHECK(sg.dz_duv == glm::vec2(0.0f));
    }
    CHECK(bias_receiver_plane_depth_gradient({NAN, 0, 0}, {0, 1, 0}).status == Status::NonFinite);
    CHECK(bias_receiver_plane_depth_gradient({INFINITY, 0, 0}, {0, 1, 0}).status == Status::NonFinite);
    CHECK(bias_receiver_plane_depth_gradient({1e-3f, 0, 3e38f}, {0, 1e-3f, 0}).status == Status::Overflow);
    const BiasReceiverPlane id = bias_receiver_plane_depth_gradient({1, 0, 0.5f}, {0, 1, -0.25f});
    CHECK(id.status == Status::Ok);
    CHECK_FALSE(id.singular);
    CHECK(id.dz_duv.x == doctest::Approx(0.5));
    CHECK(id.dz_duv.y == doctest::Approx(-0.25));
    CHECK(val(bias_receiver_plane_texel_bias({2.0f, -4.0f}, {0.01f, 0.01f})) == doctest::Approx(0.03));
}

TEST_CASE("polygon offset: r per format, o = m factor + r units, equivalence with slope-scaled bias") {
    CHECK(val(bias_polygon_offset_r(DepthFormat::Fixed24, 0.5f)) == std::ldexp(1.0, -24));
    CHECK(val(bias_polygon_offset_r(DepthFormat::Fixed16, 0.5f)) == std::ldexp(1.0, -16));
    CHECK(val(bias_polygon_offset_r(DepthFormat::Float32, 0.75f)) == std::ldexp(1.0, -24));  // 0.75 = 1.5 * 2^-1
    CHECK(val(bias_polygon_offset_r(DepthFormat::Float32, 1.0f)) == std::ldexp(1.0, -23));
    CHECK(val(bias_polygon_offset_r(DepthFormat::Float32, 0.01f)) == std::ldexp(1.0, -7 - 23));  // 0.01 = 1.28 * 2^-7
    CHECK(bias_polygon_offset_r(DepthFormat::Float32, NAN).status == Status::NonFinite);
    CHECK(val(bias_polygon_offset(2.0f, 3.0f, 0.001f, -0.004f, DepthFormat::Fixed16, 0.5f)) ==
          doctest::Approx(2.0 * 0.004 + 3.0 / 65536.0).epsilon(1e-6));
    CHECK(val(bias_polygon_offset(1.0f, 0.0f, 0.003f, 0.004f, DepthFormat::Fixed16, 0.5f, true)) == doctest::Approx(0.005).epsilon(1e-6));

    std::mt19937 g(3);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    for (int it = 0; it < 2000; ++it) {
        const Basis b = random_basis(g);
        glm::dvec3 nrm = random_unit(g);
        if (glm::dot(nrm, -b.f) < 0) nrm = -nrm;
        if (glm::dot(nrm, -b.f) < 0.1) continue;
        const double n = 1.0, f = 1.0 + 100.0 * u01(g), t = 0.001 + 0.1 * u01(g);
        // Window depth (d - n)/(f - n) per shadow-map pixel along x and y, by differencing the plane.
        const double z00 = ray_plane_depth(b, nrm, 0.0, 0.0, 0.0);
        const double dzdx = (ray_plane_depth(b, nrm, 0.0, t, 0.0) - z00) / (f - n);
        const double dzdy = (ray_plane_depth(b, nrm, 0.0, 0.0, t) - z00) / (f - n);
        const float k = 0.5f + float(u01(g));
        const double o = val(bias_polygon_offset(k, 0.0f, float(dzdx), float(dzdy), DepthFormat::Fixed24, 0.5f, true));
        const double world = val(bias_slope_scaled(float(t), val(bias_light_tan_angle(to_f(nrm), to_f(-b.f))), k));
        CHECK(o * (f - n) == doctest::Approx(world).epsilon(1e-4));
        const double o_max = val(bias_polygon_offset(k * 1.41421356f, 0.0f, float(dzdx), float(dzdy), DepthFormat::Fixed24, 0.5f, false));
        CHECK(o_max * (f - n) >= world * (1.0 - 1e-5));
    }
    // units for a world bias: r * units / slope gives the bias back.
    const double units = val(bias_polygon_offset_units_for_world_bias(0.05, BiasDepthMetric::PostProjective, DepthFormat::Fixed24, 20.0, 0.5, 200.0));
    CHECK(units * std::ldexp(1.0, -24) / val(bias_depth_metric_slope(BiasDepthMetric::PostProjective, 20.0, 0.5, 200.0)) == doctest::Approx(0.05));
    // Post-projective: the same units mean a world bias growing with d^2.
    const double u_near = val(bias_polygon_offset_units_for_world_bias(0.05, BiasDepthMetric::PostProjective, DepthFormat::Fixed24, 2.0, 0.5, 200.0));
    CHECK(u_near / units == doctest::Approx(100.0).epsilon(1e-6));
}

TEST_CASE("constant bias comparison, standard and reversed") {
    CHECK(bias_shadow_test_lit(0.5f, 0.5f, 0.0f, false));
    CHECK_FALSE(bias_shadow_test_lit(0.51f, 0.5f, 0.005f, false));
    CHECK(bias_shadow_test_lit(0.51f, 0.5f, 0.02f, false));
    CHECK(bias_shadow_test_lit(0.49f, 0.5f, 0.02f, true));
    CHECK_FALSE(bias_shadow_test_lit(0.45f, 0.5f, 0.02f, true));
    CHECK_FALSE(bias_shadow_test_lit(NAN, 0.5f, 0.02f, false));
    CHECK_FALSE(bias_shadow_test_lit(0.5f, NAN, 0.02f, true));
}

TEST_CASE("second-depth midpoint: margins for closed slabs, caps for open casters") {
    CHECK(val(bias_second_depth_value(2.0f, 4.0f)) == 3.0f);
    CHECK(val(bias_second_depth_value(4.0f, 2.0f)) == 3.0f);
    CHECK(val(bias_second_depth_value(2.0f, INFINITY, 0.5f)) == 2.5f);  // no second surface: capped
    CHECK(val(bias_second_depth_value(2.0f, 4.0f, 0.5f)) == 2.5f);
    CHECK(bias_second_depth_value(2.0f, INFINITY).status == Status::InvalidArgument);  // uncapped: at infinity
    CHECK(bias_second_depth_value(NAN, 1.0f).status == Status::NonFinite);
    CHECK(bias_second_depth_value(2.0f, 4.0f, -1.0f).status == Status::InvalidArgument);
    CHECK(bias_second_depth_value(3e38f, INFINITY, 3e38f).status == Status::Overflow);
    CHECK(val(bias_second_depth_value(3e38f, 3.4e38f)) == doctest::Approx(3.2e38));  // no overflow
    // Brute force: a closed slab of thickness T tilted against an orthographic light. Front-face
    // receivers compared with the texel-center midpoint are lit without any bias when the depth
    // change over a texel is below T/2 along the ray, back faces and the floor below are shadowed.
    std::mt19937 g(8);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    int acne = 0, leak = 0, naive_acne = 0;
    for (int it = 0; it < 4000; ++it) {
        const double tn = 3.0 * u01(g);   // slope of the slab along u
        const double thick = 0.05 + u01(g);  // thickness along the light ray
        const double t = 0.5 * thick / (tn + 1e-3) * u01(g);  // texel: delta = t tn / 2 < T/2
        const double u = 10.0 * u01(g);
        const double uc = (std::floor(u / t) + 0.5) * t;
        const double front = 1.0 + tn * u, front_c = 1.0 + tn * uc;
        const double mid = val(bias_second_depth_value(float(front_c), float(front_c + thick)));
        acne += !(front <= mid);
        leak += !(front + thick > mid);
        naive_acne += !(front <= front_c);
    }
    CHECK(acne == 0);
    CHECK(leak == 0);
    CHECK(naive_acne > 1000);  // control: the first depth alone self-shadows about half the time
}

// Issue 19 item 6 (regressions: the old functions returned these without any status).
TEST_CASE("validation: fov pi, resolution 0, denormal and 3e38 vectors, second depth of -inf") {
    // texel_world_size_perspective(10, pi, 2048) was -223,411 (float(pi) > pi: tan < 0), a negative bias.
    CHECK(bias_texel_world_size_perspective(10.0f, 3.14159265f, 2048.0f).status == Status::InvalidArgument);
    // resolution 0 gave +inf.
    CHECK(bias_texel_world_size_perspective(10.0f, 1.0f, 0.0f).status == Status::InvalidArgument);
    CHECK(bias_texel_world_size_ortho(10.0f, 0.0f).status == Status::InvalidArgument);
    CHECK(bias_texel_world_size_perspective(10.0f, 1.0f, NAN).status == Status::NonFinite);
    CHECK(bias_texel_world_size_perspective(-1.0f, 1.0f, 2048.0f).status == Status::InvalidArgument);
    CHECK(bias_texel_world_size_perspective(3e38f, 3.1f, 1e-30f).status == Status::Overflow);
    // light_tan_angle was NaN for denormal or 3e38 vectors (float length under/overflowed).
    for (float s : {1e-45f, 1e-40f, 1e-30f, 1.0f, 1e30f, 3e38f}) {
        const BiasTanAngle a = bias_light_tan_angle(glm::vec3(0.0f, 0.0f, s), glm::vec3(s, 0.0f, s));
        INFO("scale " << s);
        CHECK(a.status == Status::Ok);
        CHECK(a.faces_light);
        CHECK(double(a.value) == doctest::Approx(1.0).epsilon(1e-6));
        const BiasTanAngle b = bias_light_tan_angle(glm::vec3(0.0f, s, 0.0f), glm::vec3(0.0f, 1.0f, 1.0f));
        CHECK(double(val(b)) == doctest::Approx(1.0).epsilon(1e-6));
    }
    // second_depth_value(-inf, 0.5) was NaN.
    CHECK(bias_second_depth_value(-INFINITY, 0.5f).status == Status::NonFinite);
    CHECK(bias_second_depth_value(0.5f, -INFINITY).status == Status::NonFinite);
    CHECK(bias_second_depth_value(INFINITY, INFINITY, 1.0f).status == Status::NonFinite);
}

// Property (issue 19): finite inputs inside the documented ranges give Ok with finite outputs;
// the same functions with a NaN, an Inf or an out-of-range value give a non-Ok status.
TEST_CASE("property: in-range inputs are Ok and finite, out-of-range inputs are not Ok") {
    std::mt19937 g(19);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    auto logu = [&](double lo, double hi) { return std::exp(std::log(lo) + (std::log(hi) - std::log(lo)) * u01(g)); };
    auto vec = [&](double scale) {
        return glm::vec3(float((u01(g) - 0.5) * scale), float((u01(g) - 0.5) * scale), float((u01(g) - 0.5) * scale));
    };
    const BiasDepthMetric metrics[4] = {BiasDepthMetric::PostProjective, BiasDepthMetric::PostProjectiveReversed,
                                        BiasDepthMetric::LinearNormalized, BiasDepthMetric::LinearDistance};
    const DepthFormat formats[3] = {DepthFormat::Float32, DepthFormat::Fixed24, DepthFormat::Fixed16};
    int ok = 0;
    for (int it = 0; it < 5000; ++it) {
        const float d = float(logu(1e-3, 1e4)), fov = float(0.01 + 3.1 * u01(g)), res = float(logu(1.0, 16384.0));
        const BiasValue t = bias_texel_world_size_perspective(d, fov, res);
        REQUIRE(t.status == Status::Ok);
        CHECK(std::isfinite(t.value));
        CHECK(t.value >= 0.0f);
        const float scale = float(logu(1e-30, 1e30));
        const glm::vec3 n = vec(scale), l = vec(logu(1e-30, 1e30));
        if (n == glm::vec3(0.0f) || l == glm::vec3(0.0f)) continue;
        const BiasTanAngle a = bias_light_tan_angle(n, l);
        CHECK((a.status == Status::Ok || a.status == Status::Overflow));
        if (a.status == Status::Ok) {
            CHECK(std::isfinite(a.value));
            CHECK(a.value >= 0.0f);
            const BiasValue b = bias_slope_scaled(t.value, a.value, float(2.0 * u01(g)), float(u01(g)), 10.0f);
            CHECK(b.status == Status::Ok);
            CHECK(std::isfinite(b.value));
            ++ok;
        }
        const BiasPosition q = bias_normal_offset_position(vec(100.0), n, l, t.value, float(2.0 * u01(g)));
        CHECK(q.status == Status::Ok);
        CHECK(std::isfinite(q.position.x + q.position.y + q.position.z));
        const BiasDepthMetric m = metrics[it % 4];
        const DepthFormat fmt = m == BiasDepthMetric::LinearDistance ? DepthFormat::Float32 : formats[it % 3];
        const double nn = logu(1e-3, 10.0), ff = (it % 7 == 0 && m != BiasDepthMetric::LinearNormalized) ? INFINITY : nn * logu(1.01, 1e5);
        const double dd = std::isinf(ff) ? nn * logu(1.0, 1e6) : nn + (ff - nn) * u01(g);
        const BiasDepthValue r = bias_depth_metric_resolution(m, fmt, dd, nn, ff);
        CHECK(r.status == Status::Ok);
        CHECK(std::isfinite(r.value));
        CHECK(r.value > 0.0);
        const BiasValue sd = bias_second_depth_value(d, d + float(u01(g)) * d, float(u01(g)));
        CHECK(sd.status == Status::Ok);
        // The same calls with a NaN or an Inf, or outside the range, are never Ok.
        CHECK(bias_texel_world_size_perspective(d, fov, -res).status != Status::Ok);
        CHECK(bias_texel_world_size_perspective(NAN, fov, res).status != Status::Ok);
        CHECK(bias_light_tan_angle(n, glm::vec3(l.x, INFINITY, l.z)).status != Status::Ok);
        CHECK(bias_slope_scaled(t.value, NAN).status != Status::Ok);
        CHECK(bias_depth_metric_resolution(m, fmt, ff * 2.0, nn, ff).status != Status::Ok);
        CHECK(bias_second_depth_value(-INFINITY, d).status != Status::Ok);
    }
    CHECK(ok > 3000);
}

TEST_CASE("bias unit converters: world <-> window / t / distance, closed form, finite differences, round trip (issue #25 item 4)") {
    // closed form: a perspective light n = 1, f = 100, at d = 10 the window depth moves by f n / (d^2 (f - n)) per world unit
    const BiasDepthValue w = bias_window_from_world(0.1, BiasDepthMetric::PostProjective, 10.0, 1.0, 100.0);
    REQUIRE(w.status == Status::Ok);
    CHECK(w.value == doctest::Approx(0.1 * 100.0 / (100.0 * 99.0)).epsilon(1e-12));
    // a pre-filtered map's t over [0.5, 50.5]: 1 / 50 per world unit
    const BiasDepthValue t = bias_window_from_world(0.1, BiasDepthMetric::LinearNormalized, 20.0, 0.5, 50.5);
    REQUIRE(t.status == Status::Ok);
    CHECK(t.value == doctest::Approx(0.002).epsilon(1e-12));
    // against finite differences of the metric itself, and the round trip, over many configurations
    std::mt19937 rng(2504);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int checked = 0;
    for (int it = 0; it < 4000; ++it) {
        const BiasDepthMetric m = static_cast<BiasDepthMetric>(it % 4);
        const double n = std::pow(10.0, -3.0 + 3.0 * u(rng)), f = n * std::pow(10.0, 0.5 + 4.0 * u(rng));
        const double d = n + (f - n) * (0.01 + 0.98 * u(rng)), b = 1e-6 * d * (1.0 + 100.0 * u(rng));
        const BiasDepthValue bw = bias_window_from_world(b, m, d, n, f);
        REQUIRE(bw.status == Status::Ok);
        const double h = 1e-4 * d;
        const BiasDepthValue v0 = bias_depth_metric_value(m, d - h, n, f), v1 = bias_depth_metric_value(m, d + h, n, f);
        REQUIRE(v0.status == Status::Ok);
        REQUIRE(v1.status == Status::Ok);
        const double fd = std::fabs(v1.value - v0.value) / (2.0 * h);
        CHECK(bw.value == doctest::Approx(b * fd).epsilon(1e-6));
        const BiasDepthValue back = bias_world_from_window(bw.value, m, d, n, f);
        REQUIRE(back.status == Status::Ok);
        CHECK(back.value == doctest::Approx(b).epsilon(1e-12));
        ++checked;
    }
    CHECK(checked == 4000);
    // statuses
    CHECK(bias_window_from_world(-1.0, BiasDepthMetric::PostProjective, 10.0, 1.0, 100.0).status == Status::InvalidArgument);
    CHECK(bias_window_from_world(std::nan(""), BiasDepthMetric::PostProjective, 10.0, 1.0, 100.0).status == Status::NonFinite);
    CHECK(bias_world_from_window(1e-3, BiasDepthMetric::PostProjective, 10.0, 1.0, 0.5).status == Status::InvalidArgument);  // f < n
    CHECK(bias_world_from_window(1e-3, BiasDepthMetric::PostProjective, 10.0, 1.0, INFINITY).status == Status::Ok);  // far at infinity
}
