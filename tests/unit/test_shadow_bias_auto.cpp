// Unit and property tests of the automatic bias (shadow_bias.hpp: bias_plane_gradient, bias_auto_epsilon,
// bias_auto_lookup, bias_auto_visibility, bias_auto_filtered). The expected values come from closed forms
// (an orthographic light and a tilted plane) and from a double-precision ray cast of the receiver plane at
// each texel centre, quantized to the map's format: what the depth pass stores.
#include <shadowkit/shadow_bias.hpp>

#include <doctest/doctest.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat4x4.hpp>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

using namespace shadowkit;

namespace {

// A light: its view-projection (float, as the GPU gets it) and the same in double (the reference's).
struct LightSetup {
    glm::mat4 vp;
    glm::dmat4 vpd;
    ClipDepth clip = ClipDepth::NegativeOneToOne;
    bool reversed = false;
};

// z' = w - z in zero-to-one clip space: standard depth z_w becomes 1 - z_w (reversed-Z).
glm::dmat4 reverse_z() {
    glm::dmat4 r(1.0);
    r[2][2] = -1.0;
    r[3][2] = 1.0;
    return r;
}

LightSetup make_light(bool perspective, ClipDepth clip, bool reversed, glm::dvec3 eye, glm::dvec3 target, double scale,
                      double fov, double n, double f) {
    LightSetup L;
    L.clip = clip;
    L.reversed = reversed;
    const glm::dvec3 dir = glm::normalize(target - eye);
    const glm::dvec3 up = std::fabs(dir.y) > 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(0, 1, 0);
    const glm::dmat4 view = glm::lookAt(eye, target, up);
    glm::dmat4 proj;
    const bool z01 = clip == ClipDepth::ZeroToOne;
    if (perspective)
        proj = z01 ? glm::perspectiveRH_ZO(fov, 1.0, n, f) : glm::perspectiveRH_NO(fov, 1.0, n, f);
    else
        proj = z01 ? glm::orthoRH_ZO(-scale, scale, -scale, scale, n, f) : glm::orthoRH_NO(-scale, scale, -scale, scale, n, f);
    if (reversed) proj = reverse_z() * proj;  // needs zero-to-one clip
    L.vpd = proj * view;
    L.vp = glm::mat4(L.vpd);
    return L;
}

// Window coordinates (u, v, z) of a world point in double.
glm::dvec3 window(const LightSetup& L, glm::dvec3 p) {
    const glm::dvec4 c = L.vpd * glm::dvec4(p, 1.0);
    const glm::dvec3 ndc = glm::dvec3(c) / c.w;
    return {ndc.x * 0.5 + 0.5, ndc.y * 0.5 + 0.5, L.clip == ClipDepth::ZeroToOne ? ndc.z : ndc.z * 0.5 + 0.5};
}

// Window depth of the plane (p0, n) on the light ray through window (u, v): the ray from the unprojection
// of two depths, intersected with the plane, projected back. NaN when the ray misses the plane.
double plane_depth_at(const LightSetup& L, glm::dvec3 p0, glm::dvec3 n, double u, double v) {
    const glm::dmat4 inv = glm::inverse(L.vpd);
    const bool z01 = L.clip == ClipDepth::ZeroToOne;
    auto unproject = [&](double zn) {
        const glm::dvec4 w = inv * glm::dvec4(2.0 * u - 1.0, 2.0 * v - 1.0, zn, 1.0);
        return glm::dvec3(w) / w.w;
    };
    const glm::dvec3 a = unproject(z01 ? 0.25 : -0.5), b = unproject(z01 ? 0.75 : 0.5);
    const double den = glm::dot(n, b - a);
    if (std::fabs(den) < 1e-300) return std::nan("");
    const double t = glm::dot(n, p0 - a) / den;
    return window(L, a + t * (b - a)).z;
}

// What the depth pass stores: the value rounded to the format.
float store(DepthFormat f, double z) {
    if (f == DepthFormat::Float32) return static_cast<float>(z);
    const double levels = f == DepthFormat::Fixed24 ? 16777215.0 : 65535.0;
    const double c = std::min(1.0, std::max(0.0, z));
    return static_cast<float>(std::nearbyint(c * levels) / levels);
}

glm::dvec3 unit(std::mt19937& g) {
    std::normal_distribution<double> nd(0.0, 1.0);
    for (;;) {
        glm::dvec3 v(nd(g), nd(g), nd(g));
        if (glm::length(v) > 1e-3) return glm::normalize(v);
    }
}

}  // namespace

TEST_CASE("bias_plane_gradient: an orthographic light over a tilted plane, closed form W tan(theta) / (f - n)") {
    // light above the origin looking down -y: map x = world x, window depth (d - n) / (f - n), d = 10 - y
    const double W = 8.0, n = 1.0, f = 21.0;
    for (ClipDepth clip : {ClipDepth::NegativeOneToOne, ClipDepth::ZeroToOne}) {
        const LightSetup L = make_light(false, clip, false, {0, 10, 0}, {0, 0, 0}, W / 2, 0, n, f);
        for (double deg : {0.0, 1.0, 30.0, 60.0, 85.0, 89.0}) {
            const double th = deg * 3.14159265358979323846 / 180.0;
            // the plane y = -x tan(theta): normal (sin, cos, 0); depth d = 10 + x tan(theta), x = W (u - 1/2)
            const BiasPlaneGradient g = bias_plane_gradient(L.vp, clip, glm::vec3(0.3f, -0.3f * float(std::tan(th)), 0.2f),
                                                            glm::vec3(float(std::sin(th)), float(std::cos(th)), 0.0f));
            REQUIRE(g.status == Status::Ok);
            REQUIRE_FALSE(g.edge_on);
            const double expect_u = W * std::tan(th) / (f - n);
            // lookAt with up (0, 0, 1) for a light straight down: map u runs along -x or +x; compare magnitudes
            CHECK(std::fabs(std::fabs(double(g.dz_duv.x)) - expect_u) <= 2e-5 * (1.0 + expect_u));
            CHECK(std::fabs(double(g.dz_duv.y)) <= 2e-5 * (1.0 + expect_u));
        }
        // edge-on: the plane x = 0.3 contains the light's rays (all along -y)
        const BiasPlaneGradient e = bias_plane_gradient(L.vp, clip, glm::vec3(0.3f, 0.0f, 0.2f), glm::vec3(1.0f, 0.0f, 0.0f));
        CHECK(e.status == Status::Ok);
        CHECK(e.edge_on);
        CHECK(e.dz_duv == glm::vec2(0.0f));
    }
}

TEST_CASE("bias_plane_gradient equals a double-precision finite difference of the plane's window depth") {
    std::mt19937 rng(1234);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    int checked = 0;
    for (int i = 0; i < 3000; ++i) {
        const bool persp = i % 2 == 0;
        const ClipDepth clip = (i / 2) % 2 ? ClipDepth::ZeroToOne : ClipDepth::NegativeOneToOne;
        const bool rev = clip == ClipDepth::ZeroToOne && (i / 4) % 2;
        const glm::dvec3 eye = 6.0 * unit(rng);
        const LightSetup L = make_light(persp, clip, rev, eye, {0, 0, 0}, 3.0, 1.2, 0.5, 20.0);
        const glm::dvec3 p(U(rng), U(rng), U(rng));
        glm::dvec3 nrm = unit(rng);
        if (glm::dot(nrm, eye - p) < 0.0) nrm = -nrm;
        const BiasPlaneGradient g = bias_plane_gradient(L.vp, clip, glm::vec3(p), glm::vec3(nrm));
        REQUIRE(g.status == Status::Ok);
        if (g.edge_on || g.conditioning < 1e-2f) continue;
        // independent: window coordinates of p and of two points on the plane, in double
        const glm::dvec3 t1 = glm::normalize(glm::cross(nrm, glm::dvec3(0.3, 0.5, 0.8)));
        const glm::dvec3 t2 = glm::cross(nrm, t1);
        const double h = 1e-4;
        const glm::dvec3 w0 = window(L, p), d1 = window(L, p + h * t1) - w0, d2 = window(L, p + h * t2) - w0;
        const double det = d1.x * d2.y - d1.y * d2.x;
        const double gu = (d2.y * d1.z - d1.y * d2.z) / det, gv = (d1.x * d2.z - d2.x * d1.z) / det;
        const double mag = std::fabs(gu) + std::fabs(gv) + 1e-3;
        CHECK(std::fabs(g.dz_duv.x - gu) <= 1e-3 * mag / g.conditioning);
        CHECK(std::fabs(g.dz_duv.y - gv) <= 1e-3 * mag / g.conditioning);
        CHECK(std::fabs(g.coord.z - w0.z) <= 1e-5);
        ++checked;
    }
    MESSAGE(checked << " random planes and lights compared with the finite difference");
    CHECK(checked > 2000);
}

// The promise: a receiver that is a plane never shadows itself. The depth pass stores, at each texel
// centre, the plane's depth on that centre's light ray rounded to the format (computed here in double);
// the lookup at a point of the plane is then fully lit, in float, for every light, clip convention,
// format, scale (1e-6 .. 1e6) and angle down to 1 degree above the plane.
TEST_CASE("automatic bias: a planar receiver never shadows itself (thousands of random configurations, in float)") {
    std::mt19937 rng(99);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    const DepthFormat formats[3] = {DepthFormat::Float32, DepthFormat::Fixed24, DepthFormat::Fixed16};
    const double scales[5] = {1e-6, 1e-3, 1.0, 1e3, 1e6};
    int runs = 0, grazing = 0, unlit = 0;
    double worst = 1.0;
    for (int i = 0; i < 20000; ++i) {
        const bool persp = i % 2 == 0;
        const ClipDepth clip = (i / 2) % 2 ? ClipDepth::ZeroToOne : ClipDepth::NegativeOneToOne;
        const bool rev = clip == ClipDepth::ZeroToOne && (i / 4) % 2 == 1;
        const DepthFormat fmt = formats[(i / 8) % 3];
        const double s = scales[(i / 24) % 5];
        const int size = 64 << ((i / 120) % 6);  // 64 .. 2048
        const glm::dvec3 eye = s * 6.0 * unit(rng);
        const LightSetup L = make_light(persp, clip, rev, eye, {0, 0, 0}, s * 3.0, 1.0, s * 0.5, s * 30.0);
        // a receiver point inside the map; its plane's angle to the light: a third of them grazing (1..5 degrees above)
        const glm::dvec3 p = s * glm::dvec3(U(rng) - 0.5, U(rng) - 0.5, U(rng) - 0.5);
        const glm::dvec3 to_light = glm::normalize(eye - p);
        double elev;  // degrees of the light above the plane
        if (i % 3 == 0) {
            elev = 1.0 + 4.0 * U(rng);
            ++grazing;
        } else {
            elev = 5.0 + 85.0 * U(rng);
        }
        const glm::dvec3 side = glm::normalize(glm::cross(to_light, unit(rng)));
        const double e = elev * 3.14159265358979323846 / 180.0;
        const glm::dvec3 nrm = std::sin(e) * to_light + std::cos(e) * side;  // angle(n, l) = 90 - elev
        const BiasAutoLookup a = bias_auto_lookup(L.vp, clip, rev, glm::vec3(p), glm::vec3(nrm), glm::ivec2(size), fmt);
        REQUIRE(a.status == Status::Ok);
        if (a.outside || a.edge_on) continue;
        float stored[4];
        for (int k = 0; k < 4; ++k) {
            double z = plane_depth_at(L, p, nrm, a.tap_uv[k].x, a.tap_uv[k].y);
            if (!std::isfinite(z)) z = rev ? 0.0 : 1.0;  // the ray misses the plane: the far clear
            const bool in_map = a.tap_uv[k].x >= 0.0f && a.tap_uv[k].x <= 1.0f && a.tap_uv[k].y >= 0.0f && a.tap_uv[k].y <= 1.0f;
            stored[k] = in_map && z >= 0.0 && z <= 1.0 ? store(fmt, z) : (rev ? 0.0f : 1.0f);
        }
        const float v = bias_auto_visibility(a, stored, rev, 1.0f);
        ++runs;
        if (v < 1.0f - 1e-6f) {  // the four weights sum to 1 within float rounding
            ++unlit;
            if (unlit <= 5)
                MESSAGE("self-shadowed: V " << v << " elev " << elev << " scale " << s << " size " << size << " persp " << persp
                                            << " rev " << rev << " fmt " << int(fmt));
        }
        worst = std::min(worst, double(v));
    }
    MESSAGE(runs << " lookups (" << grazing << " grazing at 1..5 degrees), self-shadowed: " << unlit << ", lowest V " << worst);
    CHECK(runs > 15000);
    CHECK(unlit == 0);
}

TEST_CASE("automatic bias: a caster in front of the receiver plane by more than the margin is caught at every tap") {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    int checked = 0;
    for (int i = 0; i < 4000; ++i) {
        const bool persp = i % 2 == 0;
        const LightSetup L = make_light(persp, ClipDepth::NegativeOneToOne, false, 6.0 * unit(rng), {0, 0, 0}, 3.0, 1.0, 0.5, 30.0);
        const glm::dvec3 p(U(rng) - 0.5, U(rng) - 0.5, U(rng) - 0.5);
        glm::dvec3 nrm = unit(rng);
        if (glm::dot(nrm, glm::dvec3(glm::inverse(L.vpd)[3]) - p) < 0.0) nrm = -nrm;
        const BiasAutoLookup a = bias_auto_lookup(L.vp, ClipDepth::NegativeOneToOne, false, glm::vec3(p), glm::vec3(nrm),
                                                  glm::ivec2(1024), DepthFormat::Float32);
        REQUIRE(a.status == Status::Ok);
        if (a.outside || a.edge_on) continue;
        // the margin is what the derivation says, no more: <= 1/8 texel of slope plus the rounding terms
        const double plane = std::fabs(a.dz_duv.x) / 1024.0 + std::fabs(a.dz_duv.y) / 1024.0;
        const BiasPlaneGradient pg = bias_plane_gradient(L.vp, ClipDepth::NegativeOneToOne, glm::vec3(p), glm::vec3(nrm));
        // the position term: 4 ulps of p's coordinates through |dz/dp| (computed here in double)
        const glm::dvec4 row_w(L.vpd[0][3], L.vpd[1][3], L.vpd[2][3], L.vpd[3][3]);
        const glm::dvec4 cp = L.vpd * glm::dvec4(p, 1.0);
        const glm::dvec3 jz = (glm::dvec3(L.vpd[0][2], L.vpd[1][2], L.vpd[2][2]) - (cp.z / cp.w) * glm::dvec3(row_w)) / cp.w;
        const double pos = std::ldexp(1.0, -21) * (std::fabs(p.x) + std::fabs(p.y) + std::fabs(p.z)) *
                           (std::fabs(jz.x) + std::fabs(jz.y) + std::fabs(jz.z)) * 0.5;
        CHECK(std::fabs(pg.position_error - pos) <= 1e-3 * pos + 1e-12);
        CHECK(a.epsilon <= 0.126 * plane + 1e-6 + plane * 1e-3 + 2.01 * pos);
        CHECK(a.epsilon > 0.0f);
        // a caster 2 epsilon (plus the float error of the taps' extrapolation) in front at every tap: V = 0
        float stored[4];
        bool in_range = true;  // the plane beyond the far plane at a tap: nothing can be stored behind it
        for (int k = 0; k < 4; ++k) {
            const double z = plane_depth_at(L, p, nrm, a.tap_uv[k].x, a.tap_uv[k].y);
            in_range = in_range && z > 0.0 && z < 1.0;
            stored[k] = static_cast<float>(z - 2.0 * a.epsilon - 1e-6);
        }
        if (in_range) CHECK(bias_auto_visibility(a, stored, false, 1.0f) == 0.0f);
        // and the bilinear weights: in [0, 1], sum 1
        float sum = 0.0f;
        for (float w : a.tap_weight) {
            CHECK(w >= 0.0f);
            CHECK(w <= 1.0f);
            sum += w;
        }
        CHECK(std::fabs(sum - 1.0f) <= 1e-5f);
        ++checked;
    }
    CHECK(checked > 3000);
}

TEST_CASE("automatic bias: validation, outside, edge-on, formats") {
    const LightSetup L = make_light(true, ClipDepth::NegativeOneToOne, false, {0, 10, 0}, {0, 0, 0}, 1, 1.0, 1.0, 30.0);
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    const glm::vec3 p(0.1f, 0.0f, 0.2f), up(0.0f, 1.0f, 0.0f);
    CHECK(bias_auto_lookup(L.vp, ClipDepth::NegativeOneToOne, false, p, up, glm::ivec2(512), DepthFormat::Fixed24).status == Status::Ok);
    CHECK(bias_auto_lookup(L.vp, ClipDepth::NegativeOneToOne, false, glm::vec3(nan, 0, 0), up, glm::ivec2(512), DepthFormat::Fixed24).status == Status::NonFinite);
    CHECK(bias_auto_lookup(L.vp, ClipDepth::NegativeOneToOne, false, p, glm::vec3(0, inf, 0), glm::ivec2(512), DepthFormat::Fixed24).status == Status::NonFinite);
    glm::mat4 bad = L.vp;
    bad[2][1] = nan;
    CHECK(bias_auto_lookup(bad, ClipDepth::NegativeOneToOne, false, p, up, glm::ivec2(512), DepthFormat::Fixed24).status == Status::NonFinite);
    CHECK(bias_auto_lookup(L.vp, ClipDepth::NegativeOneToOne, false, p, glm::vec3(0.0f), glm::ivec2(512), DepthFormat::Fixed24).status == Status::InvalidArgument);
    CHECK(bias_auto_lookup(L.vp, ClipDepth::NegativeOneToOne, false, p, up, glm::ivec2(0, 512), DepthFormat::Fixed24).status == Status::InvalidArgument);
    CHECK(bias_auto_lookup(L.vp, ClipDepth::NegativeOneToOne, false, p, up, glm::ivec2(512), static_cast<DepthFormat>(7)).status == Status::InvalidArgument);
    // behind the light and outside the map: outside, with Ok; the caller's value comes back
    const BiasAutoLookup behind = bias_auto_lookup(L.vp, ClipDepth::NegativeOneToOne, false, glm::vec3(0, 20, 0), up, glm::ivec2(512), DepthFormat::Fixed24);
    CHECK(behind.status == Status::Ok);
    CHECK(behind.outside);
    const BiasAutoLookup far_side = bias_auto_lookup(L.vp, ClipDepth::NegativeOneToOne, false, glm::vec3(50, 0, 0), up, glm::ivec2(512), DepthFormat::Fixed24);
    CHECK(far_side.outside);
    const float any[4] = {0.f, 0.f, 0.f, 0.f};
    CHECK(bias_auto_visibility(far_side, any, false, 0.25f) == 0.25f);
    CHECK(bias_auto_visibility(far_side, any, false, nan) == 0.0f);
    CHECK(bias_auto_visibility(BiasAutoLookup{}, any, false, 1.0f) == 0.0f);
    // the plane x = 0.1 seen from (0, 10, 0) contains the ray through (0.1, 0, 0.2)? no: edge-on needs the ray in
    // the plane; the plane through p containing the light: normal perpendicular to (p - light)
    const glm::vec3 to_p = glm::normalize(p - glm::vec3(0, 10, 0));
    const glm::vec3 edge_n = glm::normalize(glm::cross(to_p, glm::vec3(1, 0, 0)));
    const BiasAutoLookup e = bias_auto_lookup(L.vp, ClipDepth::NegativeOneToOne, false, p, edge_n, glm::ivec2(512), DepthFormat::Fixed24);
    CHECK(e.status == Status::Ok);
    CHECK(e.edge_on);
    CHECK(bias_auto_visibility(e, any, false, 0.0f) == 1.0f);
    // depth steps of the formats
    CHECK(bias_auto_depth_step(DepthFormat::Fixed16).value == doctest::Approx(1.0 / 65535.0));
    CHECK(bias_auto_depth_step(DepthFormat::Fixed24).value == doctest::Approx(1.0 / 16777215.0));
    CHECK(bias_auto_depth_step(DepthFormat::Float32).value == 0.0f);
    CHECK(bias_auto_epsilon(glm::vec2(1.0f), 0.5f, 0.0f, glm::vec2(0.0f), 0.5f, 0.0f, false).status == Status::InvalidArgument);
    CHECK(bias_auto_epsilon(glm::vec2(1.0f), 0.0f, 0.0f, glm::vec2(1e-3f), 0.5f, 0.0f, false).status == Status::InvalidArgument);
    CHECK(bias_auto_epsilon(glm::vec2(nan), 0.5f, 0.0f, glm::vec2(1e-3f), 0.5f, 0.0f, false).status == Status::NonFinite);
    CHECK(bias_auto_epsilon(glm::vec2(1.0f), 0.5f, -1.0f, glm::vec2(1e-3f), 0.5f, 0.0f, false).status == Status::InvalidArgument);
    CHECK(bias_auto_epsilon(glm::vec2(3e38f), 1.0f, 0.0f, glm::vec2(1.0f), 0.5f, 0.0f, false).status == Status::Overflow);
    // the filtered taps' bias: one texel of slope more than the margin (closed form)
    const BiasValue fb = bias_auto_filtered(glm::vec2(2.0f, -1.0f), 1.0f, 1e-6f, glm::vec2(1.0f / 1024.0f), 0.5f, 0.0f, false);
    REQUIRE(fb.status == Status::Ok);
    CHECK(fb.value == doctest::Approx(3.0 / 1024.0 * (1.0 + 0.125 + 9.5367e-7 + 2.3842e-7) + 4.76837e-7 * 1.5 + 2e-6).epsilon(1e-5));
}
