// Unit tests for shadowkit/infinite_projection.hpp.
// Expected values: glm::frustum / glm::perspective (independent reference), the closed forms
// 1 - N/d and N/d, the limit Far -> inf evaluated in double, brute-force quantization.
#include <shadowkit/infinite_projection.hpp>

#include <doctest/doctest.h>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <limits>
#include <random>

namespace sk = shadowkit;

namespace {

const float kInf = std::numeric_limits<float>::infinity();
const float kNaN = std::numeric_limits<float>::quiet_NaN();

sk::ProjectionDepth params(float n, float f, sk::ClipDepth c, bool rev, float eps = 0.0f) {
    sk::ProjectionDepth p;
    p.near_z = n;
    p.far_z = f;
    p.clip_depth = c;
    p.reversed_z = rev;
    p.epsilon = eps;
    return p;
}

bool mat_close(const glm::mat4& a, const glm::mat4& b, double rel) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) {
            const double x = a[c][r], y = b[c][r];
            if (std::fabs(x - y) > rel * std::fmax(1.0, std::fmax(std::fabs(x), std::fabs(y)))) return false;
        }
    return true;
}

// Window depth of eye distance d through the matrix itself (double arithmetic, GL depth range 0..1).
double window_via_matrix(const glm::mat4& m, double d, sk::ClipDepth c) {
    glm::dmat4 md(m);
    glm::dvec4 clip = md * glm::dvec4(0.0, 0.0, -d, 1.0);
    const double ndc = clip.z / clip.w;
    return c == sk::ClipDepth::NegativeOneToOne ? 0.5 * ndc + 0.5 : ndc;
}

// Random rotation (uniform quaternion) as float matrix.
glm::mat4 random_rotation(std::mt19937& rng) {
    std::normal_distribution<float> g(0.0f, 1.0f);
    glm::quat q(g(rng), g(rng), g(rng), g(rng));
    q = glm::normalize(q);
    return glm::mat4_cast(q);
}

const char* c_str(sk::ClipDepth c) { return c == sk::ClipDepth::ZeroToOne ? "ZO" : "GL"; }

} // namespace

TEST_CASE("finite far equals glm::perspective / glm::frustum (RH, NO and ZO)") {
    std::mt19937 rng(1234);
    std::uniform_real_distribution<float> fov(0.05f, 3.0f), asp(0.2f, 5.0f), nr(1e-4f, 10.0f), ratio(1.5f, 1e5f);
    for (int i = 0; i < 3000; ++i) {
        const float fy = fov(rng), a = asp(rng), n = nr(rng), f = n * ratio(rng);
        const sk::ProjectionResult gl = sk::projection_perspective_finite(fy, a, n, f, sk::ClipDepth::NegativeOneToOne);
        const sk::ProjectionResult zo = sk::projection_perspective_finite(fy, a, n, f, sk::ClipDepth::ZeroToOne);
        REQUIRE(gl.status == sk::Status::Ok);
        REQUIRE(zo.status == sk::Status::Ok);
        CHECK(mat_close(gl.matrix, glm::perspectiveRH_NO(fy, a, n, f), 2e-6));
        CHECK(mat_close(zo.matrix, glm::perspectiveRH_ZO(fy, a, n, f), 2e-6));
        // Off-center frustum.
        const float l = -n * asp(rng), r = n * asp(rng), b = -n * asp(rng), t = n * asp(rng);
        const sk::ProjectionResult fg = sk::projection_frustum(l, r, b, t, params(n, f, sk::ClipDepth::NegativeOneToOne, false));
        const sk::ProjectionResult fz = sk::projection_frustum(l, r, b, t, params(n, f, sk::ClipDepth::ZeroToOne, false));
        CHECK(mat_close(fg.matrix, glm::frustumRH_NO(l, r, b, t, n, f), 2e-6));
        CHECK(mat_close(fz.matrix, glm::frustumRH_ZO(l, r, b, t, n, f), 2e-6));
    }
}

TEST_CASE("P_inf is the limit of glm::frustum as far -> infinity (Everitt-Kilgard 3.2.1)") {
    std::mt19937 rng(77);
    std::uniform_real_distribution<double> nr(1e-5, 10.0), w(0.01, 3.0);
    for (int i = 0; i < 2000; ++i) {
        const double n = nr(rng);
        const double l = -n * w(rng), r = n * w(rng), b = -n * w(rng), t = n * w(rng);
        for (int c = 0; c < 2; ++c) {
            const sk::ClipDepth cd = c ? sk::ClipDepth::ZeroToOne : sk::ClipDepth::NegativeOneToOne;
            const sk::ProjectionResult p = sk::projection_frustum(static_cast<float>(l), static_cast<float>(r),
                                                       static_cast<float>(b), static_cast<float>(t),
                                                       params(static_cast<float>(n), kInf, cd, false));
            REQUIRE(p.status == sk::Status::Ok);
            // Reference: double-precision frustum with far = 1e12 * near; entries converge like N/F.
            const double far = n * 1e12;
            const glm::dmat4 ref = c ? glm::frustumRH_ZO(l, r, b, t, n, far) : glm::frustumRH_NO(l, r, b, t, n, far);
            const glm::mat4 lf(ref);
            CHECK(mat_close(p.matrix, lf, 1e-6));
        }
    }
    // Exact closed form for the GL case: row 3 = (0, 0, -1, -2N), w row = (0, 0, -1, 0).
    const sk::ProjectionResult p = sk::projection_perspective_infinite(1.0f, 1.5f, 0.25f);
    CHECK(p.matrix[2][2] == -1.0f);
    CHECK(p.matrix[3][2] == -0.5f);
    CHECK(p.matrix[2][3] == -1.0f);
    CHECK(p.matrix[3][3] == 0.0f);
    const sk::ProjectionResult z = sk::projection_perspective_infinite(1.0f, 1.5f, 0.25f, sk::ClipDepth::ZeroToOne);
    CHECK(z.matrix[2][2] == -1.0f);
    CHECK(z.matrix[3][2] == -0.25f);
    const sk::ProjectionResult rz = sk::projection_perspective_infinite(1.0f, 1.5f, 0.25f, sk::ClipDepth::ZeroToOne, true);
    CHECK(rz.matrix[2][2] == 0.0f);
    CHECK(rz.matrix[3][2] == 0.25f);
}

TEST_CASE("window depth closed forms and agreement with the matrix") {
    std::mt19937 rng(99);
    std::uniform_real_distribution<double> nr(1e-5, 5.0), dist(1.0, 1e7);
    for (int i = 0; i < 4000; ++i) {
        const float n = static_cast<float>(nr(rng));
        const double N = n;
        const double d = N * dist(rng);
        for (int c = 0; c < 2; ++c)
            for (int rev = 0; rev < 2; ++rev) {
                const sk::ClipDepth cd = c ? sk::ClipDepth::ZeroToOne : sk::ClipDepth::NegativeOneToOne;
                const sk::ProjectionDepth p = params(n, kInf, cd, rev != 0);
                const double w = sk::projection_window_depth(p, d).value;
                const double expect = rev ? N / d : 1.0 - N / d; // closed forms, infinite far
                CHECK(std::fabs(w - expect) < 1e-12);
                const sk::ProjectionResult pr = sk::projection_perspective(1.2f, 1.0f, p);
                CHECK(std::fabs(window_via_matrix(pr.matrix, d, cd) - w) < 1e-6);
                // Near plane -> 0 (reversed: 1), infinity -> 1 (reversed: 0).
                CHECK(std::fabs(sk::projection_window_depth(p, N).value - (rev ? 1.0 : 0.0)) < 1e-12);
                CHECK(sk::projection_window_depth(p, std::numeric_limits<double>::infinity()).value == (rev ? 0.0 : 1.0));
                // Inverse.
                const double back = sk::projection_eye_distance_from_window_depth(p, w).value;
                CHECK(std::fabs(back - d) <= 1e-6 * d + 1e-9);
            }
        // Finite far: w(F) = 1, w(N) = 0 and the value from glm's matrix.
        const float f = static_cast<float>(N * 1000.0);
        for (int c = 0; c < 2; ++c) {
            const sk::ClipDepth cd = c ? sk::ClipDepth::ZeroToOne : sk::ClipDepth::NegativeOneToOne;
            const sk::ProjectionDepth p = params(n, f, cd, false);
            const glm::mat4 g = c ? glm::perspectiveRH_ZO(1.0f, 1.0f, n, f) : glm::perspectiveRH_NO(1.0f, 1.0f, n, f);
            const double dd = N * (1.0 + 998.0 * (d - N) / (d + 1e7 * N));
            CHECK(std::fabs(sk::projection_window_depth(p, dd).value - window_via_matrix(g, dd, cd)) < 2e-5);
            CHECK(std::fabs(sk::projection_window_depth(p, static_cast<double>(f)).value - 1.0) < 1e-12);
            const sk::ProjectionDepth pr = params(n, f, cd, true);
            CHECK(std::fabs(sk::projection_window_depth(pr, dd).value - (1.0 - sk::projection_window_depth(p, dd).value)) < 1e-12);
        }
    }
}

TEST_CASE("epsilon tweak: w = 0 vertices stay inside the clip volume in float32 (random views)") {
    std::mt19937 rng(2024);
    std::uniform_real_distribution<float> fovd(0.3f, 2.6f), aspd(0.5f, 2.5f), u01(-1.0f, 1.0f), sc(1e-3f, 1e3f);
    int tested = 0;
    for (int cfg = 0; cfg < 200; ++cfg) {
        const float fy = fovd(rng), a = aspd(rng);
        for (int c = 0; c < 2; ++c)
            for (int rev = 0; rev < 2; ++rev) {
                const sk::ClipDepth cd = c ? sk::ClipDepth::ZeroToOne : sk::ClipDepth::NegativeOneToOne;
                const sk::ProjectionEpsilonBound eb = sk::projection_infinite_epsilon_bound(fy, a, cd, rev != 0, sk::DepthFormat::Float32);
                REQUIRE(eb.status == sk::Status::Ok);
                const sk::ProjectionResult pr = sk::projection_perspective_infinite(fy, a, 0.1f, cd, rev != 0, eb.epsilon);
                REQUIRE(pr.status == sk::Status::Ok);
                const glm::mat4 V = glm::scale(random_rotation(rng), glm::vec3(sc(rng)));
                const glm::mat4 PV = pr.matrix * V;
                const glm::mat4 Vinv = glm::inverse(V);
                const float th = std::tan(0.5f * fy);
                for (int k = 0; k < 50; ++k) {
                    // Direction inside the view frustum (eye space), mapped to object space.
                    const glm::vec4 e(u01(rng) * th * a, u01(rng) * th, -1.0f, 0.0f);
                    glm::vec4 x = Vinv * e;
                    x.w = 0.0f;
                    const glm::vec4 c1 = PV * x;          // (P V) x
                    const glm::vec4 c2 = pr.matrix * (V * x); // P (V x)
                    for (const glm::vec4& cc : {c1, c2}) {
                        ++tested;
                        const float lo = c ? 0.0f : -cc.w;
                        REQUIRE(cc.w > 0.0f);
                        CHECK(cc.z <= cc.w);
                        CHECK(cc.z >= lo);
                    }
                }
            }
    }
    CHECK(tested == 200 * 4 * 50 * 2);
}

TEST_CASE("epsilon bound is needed: a too-small epsilon lets w = 0 vertices past the far plane") {
    // With epsilon = 1 ulp the concatenated P V rounds the depth row; some vertices near the frustum
    // corners land beyond the far plane. With the bound, none does (previous test). This shows the
    // property test above can fail.
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u01(-1.0f, 1.0f);
    const float fy = 2.4f, a = 2.0f;
    int outside_small = 0, outside_bound = 0;
    const float eps_small = 1.0f / 16777216.0f;
    const float eps_bound = sk::projection_infinite_epsilon_bound(fy, a, sk::ClipDepth::NegativeOneToOne, false,
                                                       sk::DepthFormat::Float32).epsilon;
    const sk::ProjectionResult ps = sk::projection_perspective_infinite(fy, a, 0.1f, sk::ClipDepth::NegativeOneToOne, false, eps_small);
    const sk::ProjectionResult pb = sk::projection_perspective_infinite(fy, a, 0.1f, sk::ClipDepth::NegativeOneToOne, false, eps_bound);
    const float th = std::tan(0.5f * fy);
    for (int cfg = 0; cfg < 4000; ++cfg) {
        const glm::mat4 V = random_rotation(rng);
        const glm::mat4 Vinv = glm::transpose(V);
        const glm::mat4 PVs = ps.matrix * V, PVb = pb.matrix * V;
        for (int k = 0; k < 20; ++k) {
            const float sx = u01(rng) > 0 ? 1.0f : -1.0f, sy = u01(rng) > 0 ? 1.0f : -1.0f;
            const glm::vec4 e(sx * th * a * (0.9f + 0.1f * std::fabs(u01(rng))), sy * th * (0.9f + 0.1f * std::fabs(u01(rng))), -1.0f, 0.0f);
            glm::vec4 x = Vinv * e;
            x.w = 0.0f;
            const glm::vec4 cs = PVs * x, cb = PVb * x;
            if (cs.z > cs.w) ++outside_small;
            if (cb.z > cb.w) ++outside_bound;
        }
    }
    MESSAGE("w=0 vertices beyond far plane: eps=2^-24: " << outside_small << " / 80000, eps=bound (" << eps_bound << "): " << outside_bound);
    CHECK(outside_small > 0);
    CHECK(outside_bound == 0);
}

TEST_CASE("epsilon storage bound: infinity stores strictly inside the cleared depth value") {
    // Float pipeline: ndc = z_c / w_c, window = 0.5 ndc + 0.5 (GL) or ndc, then quantize.
    auto stored = [](const glm::mat4& P, sk::ClipDepth cd, sk::DepthFormat fmt) -> double {
        const glm::vec4 cc = P * glm::vec4(0.3f, -0.2f, -1.0f, 0.0f);
        const float ndc = cc.z / cc.w;
        const float w = cd == sk::ClipDepth::NegativeOneToOne ? 0.5f * ndc + 0.5f : ndc;
        if (fmt == sk::DepthFormat::Float32) return static_cast<double>(w);
        const double M = fmt == sk::DepthFormat::Fixed24 ? 16777215.0 : 65535.0;
        return std::nearbyint(static_cast<double>(w) * M) / M;
    };
    const sk::DepthFormat fmts[3] = {sk::DepthFormat::Float32, sk::DepthFormat::Fixed24, sk::DepthFormat::Fixed16};
    for (int c = 0; c < 2; ++c)
        for (int rev = 0; rev < 2; ++rev)
            for (sk::DepthFormat fmt : fmts) {
                const sk::ClipDepth cd = c ? sk::ClipDepth::ZeroToOne : sk::ClipDepth::NegativeOneToOne;
                const sk::ProjectionEpsilonBound eb = sk::projection_infinite_epsilon_bound(1.0f, 1.0f, cd, rev != 0, fmt);
                const double clear = rev ? 0.0 : 1.0;
                const sk::ProjectionResult p0 = sk::projection_perspective_infinite(1.0f, 1.0f, 0.1f, cd, rev != 0, 0.0f);
                const sk::ProjectionResult pe = sk::projection_perspective_infinite(1.0f, 1.0f, 0.1f, cd, rev != 0, eb.storage);
                CHECK(stored(p0.matrix, cd, fmt) == clear); // untweaked: exactly the clear value
                const double s = stored(pe.matrix, cd, fmt);
                CHECK(s != clear);
                CHECK(s >= 0.0);
                CHECK(s <= 1.0);
                if (fmt != sk::DepthFormat::Float32 || !rev) {
                    // Half the bound is not enough for fixed formats and non-reversed float.
                    const sk::ProjectionResult ph = sk::projection_perspective_infinite(1.0f, 1.0f, 0.1f, cd, rev != 0, 0.45f * eb.storage);
                    CHECK(stored(ph.matrix, cd, fmt) == clear);
                }
            }
    const sk::ProjectionEpsilonBound e24 = sk::projection_infinite_epsilon_bound(1.5707963f, 1.0f, sk::ClipDepth::NegativeOneToOne, false, sk::DepthFormat::Fixed24);
    CHECK(e24.storage == doctest::Approx(2.0 / 16777215.0).epsilon(1e-6));
    CHECK(e24.clip == doctest::Approx((7.0 * std::sqrt(3.0) + 1.0) / 16777216.0).epsilon(1e-5));
    MESSAGE("eps bound (fovy 90, aspect 1, GL): clip " << e24.clip << ", storage 24-bit " << e24.storage);
}

TEST_CASE("depth resolution: closed forms, brute-force quantization, reversed-Z float wins") {
    const double N = 0.1, d = 100.0;
    const float n = 0.1f;
    const sk::ProjectionDepth gl = params(n, kInf, sk::ClipDepth::NegativeOneToOne, false);
    const sk::ProjectionDepth zo = params(n, kInf, sk::ClipDepth::ZeroToOne, false);
    const sk::ProjectionDepth glr = params(n, kInf, sk::ClipDepth::NegativeOneToOne, true);
    const sk::ProjectionDepth zor = params(n, kInf, sk::ClipDepth::ZeroToOne, true);
    const double Nn = static_cast<double>(n);
    // Fixed24, infinite far: w = 1 - N/d, dw/dd = N/d^2 -> delta = d^2 / (N (2^24 - 1)).
    const double r24 = sk::projection_depth_resolution(gl, sk::DepthFormat::Fixed24, d).value;
    CHECK(r24 == doctest::Approx(d * d / (Nn * 16777215.0)).epsilon(1e-9));
    const double r16 = sk::projection_depth_resolution(zo, sk::DepthFormat::Fixed16, d).value;
    CHECK(r16 == doctest::Approx(d * d / (Nn * 65535.0)).epsilon(1e-9));
    // Brute force for Fixed24: eye distances at the two code boundaries around d.
    {
        const double M = 16777215.0;
        const double code = std::nearbyint((1.0 - Nn / d) * M);
        const double d_lo = Nn / (1.0 - (code - 0.5) / M), d_hi = Nn / (1.0 - (code + 0.5) / M);
        CHECK(r24 == doctest::Approx(d_hi - d_lo).epsilon(1e-3));
    }
    // Brute force for reversed ZO float32: w = N/d stored as float; neighbours' eye distances.
    const double rzr = sk::projection_depth_resolution(zor, sk::DepthFormat::Float32, d).value;
    {
        const float f = static_cast<float>(Nn / d);
        const float f2 = std::nextafter(f, 1.0f);
        CHECK(rzr == doctest::Approx(Nn / static_cast<double>(f) - Nn / static_cast<double>(f2)).epsilon(1e-3));
    }
    // Brute force for reversed GL float32: NDC = 2N/d - 1 computed in float (steps of 2^-24 near -1).
    const double rglr = sk::projection_depth_resolution(glr, sk::DepthFormat::Float32, d).value;
    {
        const float f = static_cast<float>(2.0 * Nn / d - 1.0);
        const float f2 = std::nextafter(f, 1.0f);
        const double da = 2.0 * Nn / (static_cast<double>(f) + 1.0), db = 2.0 * Nn / (static_cast<double>(f2) + 1.0);
        CHECK(rglr == doctest::Approx(da - db).epsilon(1e-2));
    }
    const double rgf = sk::projection_depth_resolution(gl, sk::DepthFormat::Float32, d).value;
    const double rzf = sk::projection_depth_resolution(zo, sk::DepthFormat::Float32, d).value;
    const double r24r = sk::projection_depth_resolution(zor, sk::DepthFormat::Fixed24, d).value;
    MESSAGE("resolution at d=100, near=0.1 (infinite far): GL f32 " << rgf << ", ZO f32 " << rzf << ", GL rev f32 "
            << rglr << ", ZO rev f32 " << rzr << ", 24-bit " << r24 << ", 24-bit rev " << r24r << ", 16-bit " << r16);
    CHECK(rzr * 100.0 < rzf);     // reversed-Z float32 with ZeroToOne wins by > 100x
    CHECK(rglr * 4.0 > rgf);      // with GL [-1,1] reversed-Z gains at most 2x
    CHECK(r24r == doctest::Approx(r24).epsilon(1e-3)); // fixed point: reversing changes nothing
    CHECK(r16 > 200.0 * r24);
    (void)N;
}

TEST_CASE("property: monotone window depth inside [0,1] over random configurations") {
    std::mt19937 rng(31337);
    std::uniform_real_distribution<double> lnr(-11.5, 2.0), lfr(0.1, 14.0), ld(0.0, 16.0);
    for (int i = 0; i < 5000; ++i) {
        const float n = static_cast<float>(std::exp(lnr(rng)));
        const bool inf = (i % 3) == 0;
        const float f = inf ? kInf : static_cast<float>(static_cast<double>(n) * std::exp(lfr(rng)));
        const sk::ClipDepth cd = (i & 1) ? sk::ClipDepth::ZeroToOne : sk::ClipDepth::NegativeOneToOne;
        const bool rev = (i & 2) != 0;
        const float eps = inf ? 1e-6f : 0.0f;
        const sk::ProjectionDepth p = params(n, f, cd, rev, eps);
        REQUIRE(sk::projection_validate(p) == sk::Status::Ok);
        const double N = n, F = inf ? 1e300 : static_cast<double>(f);
        double d1 = N * std::exp(ld(rng)), d2 = N * std::exp(ld(rng));
        if (d1 > F) d1 = F;
        if (d2 > F) d2 = F;
        if (d1 > d2) std::swap(d1, d2);
        const double w1 = sk::projection_window_depth(p, d1).value, w2 = sk::projection_window_depth(p, d2).value;
        CHECK(w1 >= -1e-12);
        CHECK(w2 <= 1.0 + 1e-12);
        CHECK(w2 >= -1e-12);
        if (d2 > d1) CHECK((rev ? w1 > w2 : w1 < w2));
        const double res = sk::projection_depth_resolution(p, sk::DepthFormat::Fixed24, d1).value;
        CHECK(res > 0.0);
    }
}

TEST_CASE("parameter validation: one Status set (NonFinite, InvalidArgument, Overflow)") {
    using S = sk::Status;
    CHECK(sk::ProjectionResult{}.status == S::NotRun);
    CHECK(sk::ProjectionValue{}.status == S::NotRun);
    CHECK(sk::projection_perspective_infinite(1.0f, 1.0f, 0.0f).status == S::InvalidArgument);
    CHECK(sk::projection_perspective_infinite(1.0f, 1.0f, -1.0f).status == S::InvalidArgument);
    CHECK(sk::projection_perspective_infinite(1.0f, 1.0f, kNaN).status == S::NonFinite);
    CHECK(sk::projection_perspective_infinite(1.0f, 1.0f, kInf).status == S::NonFinite);
    CHECK(sk::projection_perspective_finite(1.0f, 1.0f, 1.0f, 1.0f).status == S::InvalidArgument);
    CHECK(sk::projection_perspective_finite(1.0f, 1.0f, 1.0f, 0.5f).status == S::InvalidArgument);
    CHECK(sk::projection_perspective_finite(1.0f, 1.0f, 1.0f, kNaN).status == S::NonFinite);
    CHECK(sk::projection_perspective_finite(1.0f, 1.0f, 1.0f, -kInf).status == S::NonFinite);
    CHECK(sk::projection_perspective_infinite(0.0f, 1.0f, 0.1f).status == S::InvalidArgument);
    CHECK(sk::projection_perspective_infinite(-0.5f, 1.0f, 0.1f).status == S::InvalidArgument);
    CHECK(sk::projection_perspective_infinite(3.1416f, 1.0f, 0.1f).status == S::InvalidArgument);
    CHECK(sk::projection_perspective_infinite(kNaN, 1.0f, 0.1f).status == S::NonFinite);
    CHECK(sk::projection_perspective_infinite(kInf, 1.0f, 0.1f).status == S::NonFinite);
    CHECK(sk::projection_perspective_infinite(1.0f, 0.0f, 0.1f).status == S::InvalidArgument);
    CHECK(sk::projection_perspective_infinite(1.0f, -2.0f, 0.1f).status == S::InvalidArgument);
    CHECK(sk::projection_perspective_infinite(1.0f, kNaN, 0.1f).status == S::NonFinite);
    CHECK(sk::projection_perspective_infinite(1.0f, kInf, 0.1f).status == S::NonFinite);
    CHECK(sk::projection_perspective_infinite(1.0f, 1.0f, 0.1f, sk::ClipDepth::ZeroToOne, false, -1e-7f).status == S::InvalidArgument);
    CHECK(sk::projection_perspective_infinite(1.0f, 1.0f, 0.1f, sk::ClipDepth::ZeroToOne, false, 0.6f).status == S::InvalidArgument);
    CHECK(sk::projection_perspective_infinite(1.0f, 1.0f, 0.1f, sk::ClipDepth::ZeroToOne, false, kNaN).status == S::NonFinite);
    CHECK(sk::projection_perspective(1.0f, 1.0f, params(0.1f, 100.0f, sk::ClipDepth::ZeroToOne, false, 1e-6f)).status == S::InvalidArgument);
    CHECK(sk::projection_perspective(1.0f, 1.0f, params(0.1f, 100.0f, static_cast<sk::ClipDepth>(7), false)).status == S::InvalidArgument);
    CHECK(sk::projection_frustum(1.0f, 1.0f, -1.0f, 1.0f, params(0.1f, kInf, sk::ClipDepth::ZeroToOne, false)).status == S::InvalidArgument);
    CHECK(sk::projection_frustum(-1.0f, 1.0f, 1.0f, -1.0f, params(0.1f, kInf, sk::ClipDepth::ZeroToOne, false)).status == S::InvalidArgument);
    CHECK(sk::projection_frustum(-1.0f, kNaN, -1.0f, 1.0f, params(0.1f, kInf, sk::ClipDepth::ZeroToOne, false)).status == S::NonFinite);
    // Overflow: a fov so small that cot(fov/2) is not a float.
    CHECK(sk::projection_perspective_infinite(1e-40f, 1.0f, 0.1f).status == S::Overflow);
    CHECK(sk::projection_frustum(-1e-38f, 1e-38f, -1.0f, 1.0f, params(1e30f, kInf, sk::ClipDepth::ZeroToOne, false)).status == S::Overflow);
    // Helpers.
    CHECK(sk::projection_window_depth(params(0.1f, kInf, sk::ClipDepth::ZeroToOne, false), 0.0).status == S::InvalidArgument);
    CHECK(sk::projection_window_depth(params(0.1f, kInf, sk::ClipDepth::ZeroToOne, false), -3.0).status == S::InvalidArgument);
    CHECK(sk::projection_window_depth(params(0.1f, kInf, sk::ClipDepth::ZeroToOne, false), std::nan("")).status == S::NonFinite);
    const sk::ProjectionValue bad_near = sk::projection_window_depth(params(0.0f, kInf, sk::ClipDepth::ZeroToOne, false), 1.0);
    CHECK(bad_near.status == S::InvalidArgument);
    CHECK(bad_near.value == 0.0);  // no NaN sentinel
    CHECK(sk::projection_depth_resolution(params(0.1f, kInf, sk::ClipDepth::ZeroToOne, false), sk::DepthFormat::Float32, kNaN).status == S::NonFinite);
    CHECK(sk::projection_depth_resolution(params(0.1f, kInf, sk::ClipDepth::ZeroToOne, false), static_cast<sk::DepthFormat>(9), 1.0).status == S::InvalidArgument);
    CHECK(sk::projection_eye_distance_from_window_depth(params(0.1f, kInf, sk::ClipDepth::ZeroToOne, false), -0.5).status == S::InvalidArgument);
    CHECK(sk::projection_eye_distance_from_window_depth(params(0.1f, kInf, sk::ClipDepth::ZeroToOne, false), std::nan("")).status == S::NonFinite);
    // The window depth of infinity is an outcome (at_infinity with Ok), never an infinite value.
    const sk::ProjectionEyeDistance at_inf = sk::projection_eye_distance_from_window_depth(params(0.1f, kInf, sk::ClipDepth::ZeroToOne, false), 1.0);
    CHECK(at_inf.status == S::Ok);
    CHECK(at_inf.at_infinity);
    CHECK(at_inf.value == 0.0);
    // A tweaked projection maps infinity below 1: windows beyond it are outside the mapped range.
    CHECK(sk::projection_eye_distance_from_window_depth(params(0.1f, kInf, sk::ClipDepth::ZeroToOne, false, 0.25f), 0.9).status == S::InvalidArgument);
    // Resolution only inside [near, far] (fuzzer find: denormal near, d far below it gave NaN).
    CHECK(sk::projection_depth_resolution(params(2.0244e-39f, kInf, sk::ClipDepth::ZeroToOne, true), sk::DepthFormat::Float32, 1.55744e-308).status != S::Ok);
    CHECK(sk::projection_depth_resolution(params(0.1f, 10.0f, sk::ClipDepth::NegativeOneToOne, false), sk::DepthFormat::Fixed24, 0.05).status == S::InvalidArgument);
    CHECK(sk::projection_depth_resolution(params(0.1f, 10.0f, sk::ClipDepth::NegativeOneToOne, false), sk::DepthFormat::Fixed24, 11.0).status == S::InvalidArgument);
    CHECK(sk::projection_depth_resolution(params(0.1f, 10.0f, sk::ClipDepth::NegativeOneToOne, false), sk::DepthFormat::Fixed24, 10.0).status == S::Ok);
    CHECK(sk::projection_depth_resolution(params(0.1f, 10.0f, sk::ClipDepth::NegativeOneToOne, true), sk::DepthFormat::Fixed24, static_cast<double>(0.1f)).status == S::Ok);
    CHECK(sk::projection_infinite_epsilon_bound(0.0f, 1.0f, sk::ClipDepth::ZeroToOne, false, sk::DepthFormat::Float32).status == S::InvalidArgument);
    CHECK(sk::projection_infinite_epsilon_bound(1.0f, kNaN, sk::ClipDepth::ZeroToOne, false, sk::DepthFormat::Float32).status == S::NonFinite);
    CHECK(sk::projection_infinite_epsilon_bound(1.0f, 1.0f, sk::ClipDepth::ZeroToOne, false, sk::DepthFormat::Float32, 1e6f).status == S::InvalidArgument);
}

// Issue 19 item 2 (regression: the old perspective() returned Ok here). The NDC depth the float32
// matrix itself gives the near and far planes (evaluated in double from the float entries).
TEST_CASE("near and far a few ulps apart: rejected with Overflow, never Ok with a wrong mapping") {
    auto ndc_through_matrix = [](const glm::mat4& m, double d) {
        const double zc = -static_cast<double>(m[2][2]) * d + static_cast<double>(m[3][2]);
        return zc / d;
    };
    // The cases: near 0.1, far 0.1 + 1 ulp mapped near to +0.90 and far to +2.90; near 1e-5,
    // far 1e-5 + a few ulps to -1.40 / +0.60.
    const float n1 = 0.1f, f1 = std::nextafter(0.1f, 1.0f);
    const float n2 = 1e-5f, f2 = std::nextafter(std::nextafter(std::nextafter(1e-5f, 1.0f), 1.0f), 1.0f);
    for (int c = 0; c < 2; ++c)
        for (int rev = 0; rev < 2; ++rev) {
            const sk::ClipDepth cd = c ? sk::ClipDepth::ZeroToOne : sk::ClipDepth::NegativeOneToOne;
            CHECK(sk::projection_perspective(1.0f, 1.0f, params(n1, f1, cd, rev != 0)).status == sk::Status::Overflow);
            CHECK(sk::projection_perspective(1.0f, 1.0f, params(n2, f2, cd, rev != 0)).status == sk::Status::Overflow);
            CHECK(sk::projection_frustum(-1.0f, 1.0f, -1.0f, 1.0f, params(n1, f1, cd, rev != 0)).status == sk::Status::Overflow);
            CHECK(sk::projection_window_depth(params(n1, f1, cd, rev != 0), 0.1).status == sk::Status::Overflow);
        }
    // Property: for far / near from 1 + 1e-7 to 1.01 (log-uniform), near from 1e-5 to 1e4, every
    // projection that is Ok maps near and far through its float matrix to within 1e-3 of their NDC
    // values; and the documented limit holds: Ok from far / near >= 1.001 (GL) / 1.0005 (ZO).
    std::mt19937 rng(4242);
    std::uniform_real_distribution<double> lr(std::log(1e-7), std::log(0.01)), ln(std::log(1e-5), std::log(1e4));
    int ok = 0, rejected = 0;
    for (int i = 0; i < 20000; ++i) {
        const float n = static_cast<float>(std::exp(ln(rng)));
        const float f = static_cast<float>(static_cast<double>(n) * (1.0 + std::exp(lr(rng))));
        if (!(f > n)) continue;
        const sk::ClipDepth cd = (i & 1) ? sk::ClipDepth::ZeroToOne : sk::ClipDepth::NegativeOneToOne;
        const bool rev = (i & 2) != 0;
        const sk::ProjectionResult p = sk::projection_perspective(1.0f, 1.0f, params(n, f, cd, rev));
        const double ratio = static_cast<double>(f) / static_cast<double>(n);
        if (p.status != sk::Status::Ok) {
            CHECK(p.status == sk::Status::Overflow);
            CHECK(ratio < (cd == sk::ClipDepth::ZeroToOne ? 1.0005 : 1.001));
            ++rejected;
            continue;
        }
        ++ok;
        const double lo = cd == sk::ClipDepth::ZeroToOne ? 0.0 : -1.0;
        const double at_near = rev ? 1.0 : lo, at_far = rev ? lo : 1.0;
        INFO("n " << n << " f " << f << " clip " << c_str(cd) << " rev " << rev);
        CHECK(std::fabs(ndc_through_matrix(p.matrix, n) - at_near) < 1e-3);
        CHECK(std::fabs(ndc_through_matrix(p.matrix, f) - at_far) < 1e-3);
    }
    MESSAGE("near/far a hair apart: " << ok << " Ok (mapping within 1e-3), " << rejected << " Overflow");
    CHECK(ok > 1000);
    CHECK(rejected > 1000);
}

// Issue 19 item 5 (regression: ndc_depth({0.1, inf}, 1e-310) was -inf with Ok, and window_depth too).
TEST_CASE("ndc and window depth: finite with Ok, Overflow beyond float range") {
    const sk::ProjectionDepth p = params(0.1f, kInf, sk::ClipDepth::NegativeOneToOne, false);
    for (double d : {1e-310, 1e-300, 1e-40}) {
        CHECK(sk::projection_ndc_depth(p, d).status == sk::Status::Overflow);
        CHECK(sk::projection_window_depth(p, d).status == sk::Status::Overflow);
    }
    // Below the near plane but representable: Ok, below -1 (clipped), finite.
    const sk::ProjectionValue below = sk::projection_ndc_depth(p, 1e-3);
    CHECK(below.status == sk::Status::Ok);
    CHECK(below.value == doctest::Approx(1.0 - 2.0 * static_cast<double>(0.1f) / 1e-3));
    // Property: Ok <=> finite and within float range, over random depths, distances and clip modes.
    std::mt19937 rng(515);
    std::uniform_real_distribution<double> le(-320.0 * std::log(10.0), 300.0 * std::log(10.0)), ln(std::log(1e-30), std::log(1e30));
    for (int i = 0; i < 20000; ++i) {
        const float n = static_cast<float>(std::exp(ln(rng)));
        const bool inf = (i % 3) != 0;
        const float f = inf ? kInf : n * 1000.0f;
        const sk::ProjectionDepth q = params(n, f, (i & 1) ? sk::ClipDepth::ZeroToOne : sk::ClipDepth::NegativeOneToOne, (i & 2) != 0);
        if (sk::projection_validate(q) != sk::Status::Ok) continue;
        const double d = std::exp(le(rng));
        for (const sk::ProjectionValue& v : {sk::projection_ndc_depth(q, d), sk::projection_window_depth(q, d)}) {
            if (v.status == sk::Status::Ok) {
                CHECK(std::isfinite(v.value));
                CHECK(std::fabs(v.value) <= static_cast<double>(std::numeric_limits<float>::max()));
            } else {
                CHECK(v.status == sk::Status::Overflow);
            }
        }
    }
}

TEST_CASE("stiff: near 1e-5, distances 1e-6..1e6, float32 vs 24-bit") {
    const sk::ProjectionDepth zor = params(1e-5f, kInf, sk::ClipDepth::ZeroToOne, true);
    const sk::ProjectionDepth gl = params(1e-5f, kInf, sk::ClipDepth::NegativeOneToOne, false);
    // Reversed float32 keeps distinct depth values for objects 1 unit apart at 1e6; 24-bit does not.
    const float a = static_cast<float>(sk::projection_window_depth(zor, 1e6).value);
    const float b = static_cast<float>(sk::projection_window_depth(zor, 1e6 + 1.0).value);
    CHECK(a != b);
    const double M = 16777215.0;
    CHECK(std::nearbyint(sk::projection_window_depth(gl, 1e6).value * M) == std::nearbyint(sk::projection_window_depth(gl, 1e6 + 1000.0).value * M));
    CHECK(sk::projection_depth_resolution(zor, sk::DepthFormat::Float32, 1e6).value < 1.0);
    CHECK(sk::projection_depth_resolution(gl, sk::DepthFormat::Fixed24, 1e6).value > 1e6);
    // Matrix with near 1e-5 stays finite; the near plane maps to NDC 1 (reversed ZO).
    const sk::ProjectionResult p = sk::projection_perspective(0.8f, 1.0f, zor);
    REQUIRE(p.status == sk::Status::Ok);
    const glm::vec4 c = p.matrix * glm::vec4(0.0f, 0.0f, -1e-5f, 1.0f);
    CHECK(c.z / c.w == doctest::Approx(1.0f).epsilon(1e-6));
    // Distance below near: window depth outside [0, 1] (clipped by the near plane).
    CHECK(sk::projection_window_depth(gl, 1e-6).value < 0.0);
}
