// Unit and property tests for include/shadowkit/shadow_bias.hpp.
#include <shadowkit/shadow_bias.hpp>

#include <doctest/doctest.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <cmath>
#include <random>

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
double inverse_metric(DepthMetric m, double z, double n, double f) {
    switch (m) {
    case DepthMetric::PostProjective: return std::isinf(f) ? n / (1.0 - z) : f * n / (f - z * (f - n));
    case DepthMetric::PostProjectiveReversed: return std::isinf(f) ? n / z : f * n / (n + z * (f - n));
    case DepthMetric::LinearNormalized: return n + z * (f - n);
    case DepthMetric::LinearDistance: return z;
    }
    return NAN;
}

}  // namespace

TEST_CASE("depth formats: quantization step and rounding") {
    CHECK(depth_format_step(DepthFormat::Fixed24, 0.3) == doctest::Approx(1.0 / 16777215.0).epsilon(1e-12));
    CHECK(depth_format_step(DepthFormat::Fixed16, 0.3) == doctest::Approx(1.0 / 65535.0).epsilon(1e-12));
    CHECK(depth_format_step(DepthFormat::Float32, 0.75) == std::ldexp(1.0, -24));
    CHECK(depth_format_step(DepthFormat::Float32, 1.0) == std::ldexp(1.0, -23));
    CHECK(depth_format_step(DepthFormat::Float32, 0.5) == std::ldexp(1.0, -24));
    // About 1.07e9 float values lie in [0, 1) (the thesis's precision claim is wrong).
    CHECK(std::ldexp(1.0, -24) < 1e-7);
    CHECK(quantize_depth(DepthFormat::Fixed16, 0.5) == doctest::Approx(32768.0 / 65535.0).epsilon(1e-12));
    CHECK(quantize_depth(DepthFormat::Fixed16, -3.0) == 0.0);
    CHECK(quantize_depth(DepthFormat::Fixed16, 7.0) == 1.0);
    CHECK(std::isnan(quantize_depth(DepthFormat::Fixed24, NAN)));
    CHECK(std::isnan(depth_format_step(DepthFormat::Float32, NAN)));
}

TEST_CASE("depth resolution: closed forms and brute force against the next representable value") {
    const double n = 0.1, f = 100.0;
    // Closed form, post-projective UNORM24 at d = 50.
    const double expect = 50.0 * 50.0 * (f - n) / (f * n * 16777215.0);
    CHECK(depth_metric_resolution(DepthMetric::PostProjective, DepthFormat::Fixed24, 50.0, n, f) == doctest::Approx(expect).epsilon(1e-9));
    CHECK(depth_metric_resolution(DepthMetric::LinearNormalized, DepthFormat::Fixed16, 50.0, n, f) == doctest::Approx((f - n) / 65535.0).epsilon(1e-9));

    std::mt19937 g(2024);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    const DepthMetric metrics[4] = {DepthMetric::PostProjective, DepthMetric::PostProjectiveReversed,
                                    DepthMetric::LinearNormalized, DepthMetric::LinearDistance};
    const DepthFormat formats[3] = {DepthFormat::Float32, DepthFormat::Fixed24, DepthFormat::Fixed16};
    int checked = 0;
    for (int it = 0; it < 3000; ++it) {
        const DepthMetric m = metrics[it % 4];
        const DepthFormat fmt = formats[(it / 4) % 3];
        const double nn = std::pow(10.0, -2.0 + 2.0 * u01(g));
        const double ff = nn * std::pow(10.0, 1.0 + 4.0 * u01(g));
        const double d = nn * std::pow(ff / nn, u01(g));
        const double res = depth_metric_resolution(m, fmt, d, nn, ff);
        if (m == DepthMetric::LinearDistance && fmt != DepthFormat::Float32) {
            CHECK(std::isnan(res));
            continue;
        }
        // Brute force: stored value, the next stored value above, both mapped back to distance.
        const double v = depth_metric_value(m, d, nn, ff);
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
        const double rev = depth_metric_resolution(DepthMetric::PostProjectiveReversed, DepthFormat::Float32, d, n, INFINITY);
        CHECK(rev / d <= std::ldexp(1.0, -22));
        const double std_ = depth_metric_resolution(DepthMetric::PostProjective, DepthFormat::Float32, d, n, INFINITY);
        if (d >= 100.0) CHECK(std_ > 100.0 * rev);
        // 24-bit UNORM post-projective is comparable to standard float32 (values crowd near 1).
        const double u24 = depth_metric_resolution(DepthMetric::PostProjective, DepthFormat::Fixed24, d, n, 1e5);
        if (d >= 10.0) CHECK(u24 <= 2.5 * depth_metric_resolution(DepthMetric::PostProjective, DepthFormat::Float32, d, n, 1e5));
    }
    // Invalid input.
    CHECK(std::isnan(depth_metric_resolution(DepthMetric::PostProjective, DepthFormat::Float32, 0.05, 0.1, 10.0)));
    CHECK(std::isnan(depth_metric_resolution(DepthMetric::PostProjective, DepthFormat::Float32, 5.0, 0.0, 10.0)));
    CHECK(std::isnan(depth_metric_resolution(DepthMetric::PostProjective, DepthFormat::Float32, NAN, 0.1, 10.0)));
    CHECK(std::isnan(depth_metric_resolution(DepthMetric::LinearNormalized, DepthFormat::Fixed24, 5.0, 0.1, INFINITY)));
    CHECK(std::isnan(depth_metric_resolution(DepthMetric::PostProjective, DepthFormat::Float32, 5.0, 10.0, 1.0)));
}

TEST_CASE("texel world size matches unprojected texel centres of glm::perspective") {
    CHECK(texel_world_size_perspective(10.0f, 1.5707963f, 1000.0f) == doctest::Approx(0.02).epsilon(1e-5));
    CHECK(texel_world_size_ortho(20.0f, 1024.0f) == doctest::Approx(20.0 / 1024.0));
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
    CHECK(double(texel_world_size_perspective(d, fov, res)) == doctest::Approx(double(w)).epsilon(1e-4));
}

TEST_CASE("light_tan_angle closed forms") {
    CHECK(light_tan_angle({0, 0, 1}, {0, 0, 1}) == 0.0f);
    CHECK(double(light_tan_angle({0, 0, 1}, {1, 0, 1})) == doctest::Approx(1.0));
    CHECK(double(light_tan_angle({0, 0, 2}, {0, std::sqrt(3.0f), 1})) == doctest::Approx(std::sqrt(3.0)).epsilon(1e-6));
    CHECK(std::isinf(light_tan_angle({0, 0, 1}, {1, 0, 0})));   // grazing
    CHECK(std::isinf(light_tan_angle({0, 0, 1}, {0, 0, -1})));  // facing away
    CHECK(std::isnan(light_tan_angle({0, 0, 0}, {0, 0, 1})));
    CHECK(std::isnan(light_tan_angle({NAN, 0, 1}, {0, 0, 1})));
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
        const float tn = light_tan_angle(to_f(nrm), to_f(-b.f));
        const DepthGradient grad = plane_depth_gradient(to_f(nrm), to_f(b.r), to_f(b.u), to_f(b.f));
        REQUIRE(grad.ok);
        CHECK(double(glm::length(grad.dz_duv)) == doctest::Approx(double(tn)).epsilon(1e-4));
        CHECK(double(texel_depth_delta(grad.dz_duv, float(t))) == doctest::Approx(brute).epsilon(1e-3));
        const double bias = slope_scaled_bias(float(t), tn);
        CHECK(bias >= brute * (1.0 - 1e-5));
        covered += bias >= brute * (1.0 - 1e-5);
        failed_small_scale += double(slope_scaled_bias(float(t), tn, 0.5f)) < brute * 0.999;
        ++total;
    }
    CHECK(covered == total);
    CHECK(failed_small_scale > total / 10);  // control: half a texel is not enough (diagonal gradients)
    CHECK(plane_depth_gradient({1, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}).ok == false);
    CHECK(slope_scaled_bias(1.0f, INFINITY) == doctest::Approx(10.0 * 0.70710678));
    CHECK(slope_scaled_bias(1.0f, 2.0f, 1.0f, 0.25f) == doctest::Approx(2.25));
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
            const glm::dvec3 q = glm::dvec3(normal_offset_position(to_f(p), to_f(nrm), to_f(-b.f), float(t), scale));
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
    // Degenerate input leaves the point unchanged.
    const glm::vec3 p(1, 2, 3);
    CHECK(normal_offset_position(p, {0, 0, 0}, {0, 0, 1}, 1.0f, 1.0f) == p);
    CHECK(normal_offset_position(p, {NAN, 0, 0}, {0, 0, 1}, 1.0f, 1.0f) == p);
    // Light along the normal: sin = 0, no offset.
    CHECK(normal_offset_position(p, {0, 0, 1}, {0, 0, 5}, 1.0f, 1.0f) == p);
    // 90 degrees: full offset.
    CHECK(normal_offset_position(p, {0, 0, 1}, {1, 0, 0}, 0.5f, 2.0f).z == doctest::Approx(4.0));
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
        const ReceiverPlaneGradient rp = receiver_plane_depth_gradient(glm::vec3(deriv(a)), glm::vec3(deriv(bb)));
        if (!rp.ok) continue;
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
        const double pred = receiver_plane_depth(float(s0.z), rp.dz_duv, glm::vec2(o));
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
    CHECK_FALSE(receiver_plane_depth_gradient({1, 2, 3}, {2, 4, 1}).ok);
    CHECK_FALSE(receiver_plane_depth_gradient({0, 0, 0}, {0, 0, 0}).ok);
    CHECK_FALSE(receiver_plane_depth_gradient({NAN, 0, 0}, {0, 1, 0}).ok);
    CHECK_FALSE(receiver_plane_depth_gradient({INFINITY, 0, 0}, {0, 1, 0}).ok);
    const ReceiverPlaneGradient id = receiver_plane_depth_gradient({1, 0, 0.5f}, {0, 1, -0.25f});
    CHECK(id.ok);
    CHECK(id.dz_duv.x == doctest::Approx(0.5));
    CHECK(id.dz_duv.y == doctest::Approx(-0.25));
    CHECK(receiver_plane_texel_bias({2.0f, -4.0f}, {0.01f, 0.01f}) == doctest::Approx(0.03));
}

TEST_CASE("polygon offset: r per format, o = m factor + r units, equivalence with slope-scaled bias") {
    CHECK(polygon_offset_r(DepthFormat::Fixed24, 0.5f) == std::ldexp(1.0, -24));
    CHECK(polygon_offset_r(DepthFormat::Fixed16, 0.5f) == std::ldexp(1.0, -16));
    CHECK(polygon_offset_r(DepthFormat::Float32, 0.75f) == std::ldexp(1.0, -24));  // 0.75 = 1.5 * 2^-1
    CHECK(polygon_offset_r(DepthFormat::Float32, 1.0f) == std::ldexp(1.0, -23));
    CHECK(polygon_offset_r(DepthFormat::Float32, 0.01f) == std::ldexp(1.0, -7 - 23));  // 0.01 = 1.28 * 2^-7
    CHECK(std::isnan(polygon_offset_r(DepthFormat::Float32, NAN)));
    CHECK(polygon_offset(2.0f, 3.0f, 0.001f, -0.004f, DepthFormat::Fixed16, 0.5f) ==
          doctest::Approx(2.0 * 0.004 + 3.0 / 65536.0).epsilon(1e-6));
    CHECK(polygon_offset(1.0f, 0.0f, 0.003f, 0.004f, DepthFormat::Fixed16, 0.5f, true) == doctest::Approx(0.005).epsilon(1e-6));

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
        const double o = polygon_offset(k, 0.0f, float(dzdx), float(dzdy), DepthFormat::Fixed24, 0.5f, true);
        const double world = slope_scaled_bias(float(t), light_tan_angle(to_f(nrm), to_f(-b.f)), k);
        CHECK(o * (f - n) == doctest::Approx(world).epsilon(1e-4));
        const double o_max = polygon_offset(k * 1.41421356f, 0.0f, float(dzdx), float(dzdy), DepthFormat::Fixed24, 0.5f, false);
        CHECK(o_max * (f - n) >= world * (1.0 - 1e-5));
    }
    // units for a world bias: r * units / slope gives the bias back.
    const double units = polygon_offset_units_for_world_bias(0.05, DepthMetric::PostProjective, DepthFormat::Fixed24, 20.0, 0.5, 200.0);
    CHECK(units * std::ldexp(1.0, -24) / depth_metric_slope(DepthMetric::PostProjective, 20.0, 0.5, 200.0) == doctest::Approx(0.05));
    // Post-projective: the same units mean a world bias growing with d^2.
    const double u_near = polygon_offset_units_for_world_bias(0.05, DepthMetric::PostProjective, DepthFormat::Fixed24, 2.0, 0.5, 200.0);
    CHECK(u_near / units == doctest::Approx(100.0).epsilon(1e-6));
}

TEST_CASE("constant bias comparison, standard and reversed") {
    CHECK(shadow_test_lit(0.5f, 0.5f, 0.0f, false));
    CHECK_FALSE(shadow_test_lit(0.51f, 0.5f, 0.005f, false));
    CHECK(shadow_test_lit(0.51f, 0.5f, 0.02f, false));
    CHECK(shadow_test_lit(0.49f, 0.5f, 0.02f, true));
    CHECK_FALSE(shadow_test_lit(0.45f, 0.5f, 0.02f, true));
    CHECK_FALSE(shadow_test_lit(NAN, 0.5f, 0.02f, false));
    CHECK_FALSE(shadow_test_lit(0.5f, NAN, 0.02f, true));
}

TEST_CASE("second-depth midpoint: margins for closed slabs, caps for open casters") {
    CHECK(second_depth_value(2.0f, 4.0f) == 3.0f);
    CHECK(second_depth_value(4.0f, 2.0f) == 3.0f);
    CHECK(second_depth_value(2.0f, INFINITY, 0.5f) == 2.5f);  // no second surface: capped
    CHECK(second_depth_value(2.0f, 4.0f, 0.5f) == 2.5f);
    CHECK(std::isinf(second_depth_value(2.0f, INFINITY)));
    CHECK(std::isnan(second_depth_value(NAN, 1.0f)));
    CHECK(second_depth_value(3e38f, 3.4e38f) == doctest::Approx(3.2e38));  // no overflow
    // Brute force: a closed slab of thickness T tilted against an orthographic light. Front-face
    // receivers compared with the texel-centre midpoint are lit without any bias when the depth
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
        const double mid = second_depth_value(float(front_c), float(front_c + thick));
        acne += !(front <= mid);
        leak += !(front + thick > mid);
        naive_acne += !(front <= front_c);
    }
    CHECK(acne == 0);
    CHECK(leak == 0);
    CHECK(naive_acne > 1000);  // control: the first depth alone self-shadows about half the time
}
