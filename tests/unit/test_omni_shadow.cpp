// Unit and property tests for shadowkit/omni_shadow.hpp.
// Expected values come from closed forms (glm::lookAt / glm::perspective with the GL spec's face
// table written out here independently), brute force (dense sampling of edge images, polytope
// edge clipping and point-to-polytope distances for culling, rays through a texel footprint for
// the bias) and independent predicates (face ownership).
#include <shadowkit/omni_shadow.hpp>

#include <doctest/doctest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

using namespace shadowkit;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// OpenGL 4.6 sec. 8.13 cube map face selection, written from the spec table: major axis, sc, tc.
// Returns s, t for a direction known to be on `face`.
glm::dvec2 spec_st(int face, glm::dvec3 r) {
    double sc = 0, tc = 0, ma = 0;
    switch (face) {
        case 0: sc = -r.z; tc = -r.y; ma = r.x; break;
        case 1: sc = r.z; tc = -r.y; ma = r.x; break;
        case 2: sc = r.x; tc = r.z; ma = r.y; break;
        case 3: sc = r.x; tc = -r.z; ma = r.y; break;
        case 4: sc = r.x; tc = -r.y; ma = r.z; break;
        default: sc = -r.x; tc = -r.y; ma = r.z; break;
    }
    return {0.5 * (sc / std::fabs(ma) + 1.0), 0.5 * (tc / std::fabs(ma) + 1.0)};
}

// The camera orientation that renders a face so that window x = s and window y = t.
void spec_face_camera(int face, glm::vec3& fwd, glm::vec3& up) {
    const glm::vec3 f[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    const glm::vec3 u[6] = {{0, -1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0, -1, 0}, {0, -1, 0}};
    fwd = f[face];
    up = u[face];
}

// Independent ownership predicates of the documented tie rule (x before y before z).
bool owns(int face, glm::vec3 d) {
    const float ax = std::fabs(d.x), ay = std::fabs(d.y), az = std::fabs(d.z);
    const int axis = face / 2;
    const bool pos = face % 2 == 0;
    bool major = false;
    float comp = 0.f;
    if (axis == 0) { major = ax >= ay && ax >= az; comp = d.x; }
    if (axis == 1) { major = ay > ax && ay >= az; comp = d.y; }
    if (axis == 2) { major = az > ax && az > ay; comp = d.z; }
    return major && (pos ? comp > 0.f : comp < 0.f);
}

double rel_err(const glm::mat4& a, const glm::mat4& b) {
    double num = 0, den = 0;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) {
            num = std::max(num, std::fabs(double(a[c][r]) - double(b[c][r])));
            den = std::max(den, std::fabs(double(b[c][r])));
        }
    return num / std::max(den, 1e-30);
}

// A point light at p (w = 1), as the header takes it.
glm::vec4 pt(glm::vec3 p) { return glm::vec4(p, 1.f); }

glm::vec3 random_unit(std::mt19937& rng) {
    std::normal_distribution<float> n(0.f, 1.f);
    for (;;) {
        glm::vec3 v(n(rng), n(rng), n(rng));
        const float l = glm::length(v);
        if (l > 1e-6f) return v / l;
    }
}

// --- independent convex-polytope machinery for the culling brute force -----------------------
struct Poly {
    std::vector<glm::dvec4> planes;  // inside: dot(n, p) + w >= 0
    std::vector<glm::dvec3> verts;
    std::vector<std::array<int, 2>> edges;
    std::vector<std::vector<int>> faces;  // vertex loops, one per plane (same order)
};

// Face frustum in world space (relative to the light at origin) from the spec camera: apex
// pyramid truncated at near/far along the face axis.
Poly frustum_poly(int face, double n, double f) {
    glm::vec3 fw, up;
    spec_face_camera(face, fw, up);
    const glm::dvec3 F(fw), U(up), R = glm::cross(F, U);
    Poly P;
    // corners: near 0..3, far 4..7 (order: -R-U, +R-U, +R+U, -R+U)
    const double sgn[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    for (double dist : {n, f})
        for (const auto& s : sgn) P.verts.push_back(dist * (F + s[0] * R + s[1] * U));
    for (int i = 0; i < 4; ++i) {
        P.edges.push_back({i, (i + 1) % 4});
        P.edges.push_back({4 + i, 4 + (i + 1) % 4});
        P.edges.push_back({i, 4 + i});
    }
    auto plane_from = [&](int a, int b, int c, glm::dvec3 inside) {
        glm::dvec3 nn = glm::normalize(glm::cross(P.verts[b] - P.verts[a], P.verts[c] - P.verts[a]));
        double w = -glm::dot(nn, P.verts[a]);
        if (glm::dot(nn, inside) + w < 0) { nn = -nn; w = -w; }
        P.planes.push_back(glm::dvec4(nn, w));
    };
    const glm::dvec3 centre = 0.5 * (n + f) * F;
    plane_from(0, 1, 2, centre); P.faces.push_back({0, 1, 2, 3});
    plane_from(4, 5, 6, centre); P.faces.push_back({4, 5, 6, 7});
    for (int i = 0; i < 4; ++i) {
        const int j = (i + 1) % 4;
        plane_from(i, j, 4 + j, centre);
        P.faces.push_back({i, j, 4 + j, 4 + i});
    }
    return P;
}

Poly box_poly(glm::dvec3 lo, glm::dvec3 hi) {
    Poly P;
    for (int i = 0; i < 8; ++i) P.verts.push_back({(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
    for (int i = 0; i < 8; ++i)
        for (int b = 1; b < 8; b <<= 1)
            if (!(i & b)) P.edges.push_back({i, i | b});
    P.planes = {{1, 0, 0, -lo.x}, {-1, 0, 0, hi.x}, {0, 1, 0, -lo.y}, {0, -1, 0, hi.y}, {0, 0, 1, -lo.z}, {0, 0, -1, hi.z}};
    return P;
}

// Does segment ab meet the convex solid (clip against every half-space, with a tiny tolerance)?
bool segment_meets(const Poly& P, glm::dvec3 a, glm::dvec3 b, double tol) {
    double t0 = 0, t1 = 1;
    for (const auto& pl : P.planes) {
        const glm::dvec3 nn(pl);
        const double da = glm::dot(nn, a) + pl.w, db = glm::dot(nn, b) + pl.w;
        if (da < -tol && db < -tol) return false;
        if (da >= -tol && db >= -tol) continue;
        const double t = (da + tol) / (da - db);  // crossing of the (tolerance-shifted) plane
        if (da < -tol) t0 = std::max(t0, t);
        else t1 = std::min(t1, t);
        if (t0 > t1) return false;
    }
    return true;
}

// Two convex polytopes meet iff an edge of one meets the other solid (vertices of the
// intersection are vertices or edge/face crossings of the two).
bool polys_meet(const Poly& A, const Poly& B, double tol) {
    for (const auto& e : A.edges)
        if (segment_meets(B, A.verts[size_t(e[0])], A.verts[size_t(e[1])], tol)) return true;
    for (const auto& e : B.edges)
        if (segment_meets(A, B.verts[size_t(e[0])], B.verts[size_t(e[1])], tol)) return true;
    return false;
}

double point_segment_dist(glm::dvec3 p, glm::dvec3 a, glm::dvec3 b) {
    const glm::dvec3 ab = b - a;
    const double l2 = glm::dot(ab, ab);
    const double t = l2 > 0 ? std::clamp(glm::dot(p - a, ab) / l2, 0.0, 1.0) : 0.0;
    return glm::length(p - (a + t * ab));
}

// Distance from a point to a convex polytope: 0 inside, else the nearest face polygon.
double point_poly_dist(const Poly& P, glm::dvec3 p) {
    bool inside = true;
    for (const auto& pl : P.planes)
        if (glm::dot(glm::dvec3(pl), p) + pl.w < 0) inside = false;
    if (inside) return 0.0;
    double best = std::numeric_limits<double>::infinity();
    for (size_t fi = 0; fi < P.faces.size(); ++fi) {
        const auto& loop = P.faces[fi];
        const glm::dvec3 nn(P.planes[fi]);
        const double h = glm::dot(nn, p) + P.planes[fi].w;
        const glm::dvec3 q = p - h * nn;  // projection on the face plane
        bool in_poly = true;
        for (size_t k = 0; k < loop.size(); ++k) {
            const glm::dvec3 a = P.verts[size_t(loop[k])], b = P.verts[size_t(loop[(k + 1) % loop.size()])];
            // inside test against the polygon's other vertices' side
            const glm::dvec3 c = P.verts[size_t(loop[(k + 2) % loop.size()])];
            const glm::dvec3 e = glm::cross(b - a, nn);
            if (glm::dot(e, q - a) * glm::dot(e, c - a) < 0) in_poly = false;
        }
        if (in_poly) best = std::min(best, std::fabs(h));
        for (size_t k = 0; k < loop.size(); ++k)
            best = std::min(best, point_segment_dist(p, P.verts[size_t(loop[k])], P.verts[size_t(loop[(k + 1) % loop.size()])]));
    }
    return best;
}

}  // namespace

// ==================================================================================== cube faces

TEST_CASE("face matrices equal glm::lookAt / glm::perspective closed forms for every convention") {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-50.f, 50.f), lg(-5.f, 3.f);
    const float fov = glm::radians(90.f);
    for (int it = 0; it < 2000; ++it) {
        OmniCubeInput in;
        in.light_position = pt({u(rng), u(rng), u(rng)});
        in.near_z = std::pow(10.f, lg(rng) - 1.f);
        in.far_z = in.near_z * std::pow(10.f, 1.f + std::fabs(lg(rng)));
        in.clip_depth = (it & 1) ? ClipDepth::ZeroToOne : ClipDepth::NegativeOneToOne;
        in.reversed_z = (it & 2) != 0;
        const bool inf = (it % 7) == 3;
        if (inf) in.far_z = kInf;
        const OmniCubeMatrices m = omni_cube_matrices(in);
        REQUIRE(m.status == Status::Ok);
        glm::mat4 P;
        const float n = in.near_z, f = in.far_z;
        if (in.clip_depth == ClipDepth::NegativeOneToOne && !in.reversed_z)
            P = inf ? glm::infinitePerspective(fov, 1.f, n) : glm::perspective(fov, 1.f, n, f);
        else if (in.clip_depth == ClipDepth::ZeroToOne && !in.reversed_z)
            P = inf ? glm::mat4(0.f) : glm::perspectiveRH_ZO(fov, 1.f, n, f);
        else if (in.clip_depth == ClipDepth::ZeroToOne)
            P = inf ? glm::mat4(0.f) : glm::perspectiveRH_ZO(fov, 1.f, f, n);  // reversed: swap
        else
            P = inf ? glm::infinitePerspective(fov, 1.f, n) : glm::perspective(fov, 1.f, n, f);
        if (in.reversed_z && in.clip_depth == ClipDepth::NegativeOneToOne) {
            // GL reversed: ndc negated -> the third row negated
            for (int c = 0; c < 4; ++c) P[c][2] = -P[c][2];
        }
        if (inf && in.clip_depth == ClipDepth::ZeroToOne) {
            // closed form of the infinite ZO limits (right-handed): ndc = 1 - n/d, reversed n/d
            P = glm::mat4(0.f);
            P[0][0] = P[1][1] = 1.f;
            P[2][3] = -1.f;
            P[2][2] = in.reversed_z ? 0.f : -1.f;
            P[3][2] = in.reversed_z ? n : -n;
        }
        CHECK(rel_err(m.proj, P) < 2e-6);
        // depth of the near and far planes in NDC (closed form of each convention)
        const double zn = in.clip_depth == ClipDepth::ZeroToOne ? (in.reversed_z ? 1 : 0) : (in.reversed_z ? 1 : -1);
        const glm::vec4 cn = m.proj * glm::vec4(0.f, 0.f, -n, 1.f);
        CHECK(std::fabs(cn.z / cn.w - zn) < 1e-4);
        for (int face = 0; face < 6; ++face) {
            glm::vec3 fw, up;
            spec_face_camera(face, fw, up);
            const glm::mat4 V = glm::lookAt(glm::vec3(in.light_position), glm::vec3(in.light_position) + fw, up);
            CHECK(rel_err(m.view[face], V) < 1e-6);
        }
    }
}

TEST_CASE("face view-projections reproduce the GL cube lookup coordinates (s, t) of the spec table") {
    std::mt19937 rng(12);
    OmniCubeInput in;
    in.light_position = pt({0.3f, -1.2f, 2.f});
    in.near_z = 0.01f;
    in.far_z = 100.f;
    const OmniCubeMatrices m = omni_cube_matrices(in);
    REQUIRE(m.status == Status::Ok);
    double worst = 0;
    for (int it = 0; it < 200000; ++it) {
        const glm::vec3 d = random_unit(rng) * 5.f;
        const OmniFaceHit h = omni_cube_face(d);
        REQUIRE(h.status == Status::Ok);
        const int face = int(h.face);
        const glm::dvec2 st = spec_st(face, glm::dvec3(d));
        worst = std::max(worst, std::max(std::fabs(st.x - h.st.x), std::fabs(st.y - h.st.y)));
        const glm::vec4 c = m.view_proj[face] * glm::vec4(glm::vec3(in.light_position) + d, 1.f);
        worst = std::max(worst, std::fabs((c.x / c.w) * 0.5 + 0.5 - st.x));
        worst = std::max(worst, std::fabs((c.y / c.w) * 0.5 + 0.5 - st.y));
        CHECK(c.w > 0.f);
    }
    MESSAGE("max |st - spec| over 200k directions: " << worst);
    CHECK(worst < 2e-6);
}

TEST_CASE("every direction maps to exactly one face: millions of random and adversarial directions") {
    std::mt19937 rng(13);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    std::size_t checked = 0, ties = 0;
    double worst_round_trip = 0;
    auto check = [&](glm::vec3 d) {
        const OmniFaceHit h = omni_cube_face(d);
        if (!(glm::length(glm::dvec3(d)) > 0)) {
            CHECK(h.status == Status::InvalidArgument);
            return;
        }
        REQUIRE(h.status == Status::Ok);
        int count = 0, which = -1;
        for (int f = 0; f < 6; ++f)
            if (owns(f, d)) {
                ++count;
                which = f;
            }
        if (count != 1 || which != int(h.face)) {
            FAIL_CHECK("direction (" << d.x << ", " << d.y << ", " << d.z << "): " << count << " owners, face "
                                     << int(h.face));
        }
        // the chosen face contains the direction (closed frustum): st in [0,1]^2
        if (!(h.st.x >= 0.f && h.st.x <= 1.f && h.st.y >= 0.f && h.st.y <= 1.f)) FAIL_CHECK("st outside the face");
        const float ax = std::fabs(d.x), ay = std::fabs(d.y), az = std::fabs(d.z);
        if ((ax == ay && ax >= az) || (ay == az && ay >= ax) || (ax == az && ax >= ay)) ++ties;
        const OmniDirection back = omni_cube_direction(h.face, h.st);
        REQUIRE(back.status == Status::Ok);
        const glm::dvec3 dn = glm::normalize(glm::dvec3(d));
        const double e = glm::length(glm::dvec3(back.direction) - dn);
        worst_round_trip = std::max(worst_round_trip, e);
        ++checked;
    };
    for (int it = 0; it < 2000000; ++it) check({u(rng), u(rng), u(rng)});
    // adversarial: edges and corners (|a| == |b|), signed zeros, denormals, huge, permutations
    const float vals[] = {0.f, -0.f, 1.f, -1.f, 1e-38f, -1e-38f, 1e-45f, -1e-45f, 3e38f, -3e38f, 0.5f, -0.5f, 1e-7f, -1e-7f};
    for (float a : vals)
        for (float b : vals)
            for (float c : vals) check({a, b, c});
    for (int it = 0; it < 300000; ++it) {
        const float a = u(rng), b = u(rng);
        const float sa = (it & 1) ? 1.f : -1.f, sb = (it & 2) ? 1.f : -1.f;
        const float m = std::fabs(a);
        switch ((it >> 2) % 6) {
            case 0: check({a, sa * m, b * m}); break;       // |x| == |y| edge
            case 1: check({a, b * m, sb * m}); break;       // |x| == |z|
            case 2: check({b * m, a, sa * m}); break;       // |y| == |z|
            case 3: check({a, sa * m, sb * m}); break;      // corners
            case 4: check({std::nextafter(a, 2.f), sa * m, sb * m}); break;  // one ulp off a corner
            default: check({b * m, sb * std::nextafter(m, 0.f), a}); break;
        }
    }
    MESSAGE(checked << " directions, " << ties << " on cube edges/corners; round trip max " << worst_round_trip);
    CHECK(checked > 2000000);
    CHECK(ties > 100000);
    CHECK(worst_round_trip < 1e-6);
    CHECK(omni_cube_face({kNaN, 1.f, 0.f}).status == Status::NonFinite);
    CHECK(omni_cube_face({kInf, 1.f, 0.f}).status == Status::NonFinite);
    CHECK(omni_cube_direction(static_cast<OmniCubeFace>(9), {0.5f, 0.5f}).status == Status::InvalidArgument);
    CHECK(omni_cube_direction(OmniCubeFace::PositiveY, {kNaN, 0.5f}).status == Status::NonFinite);
}

TEST_CASE("texel angles bound the angle between directions of texels a given distance apart") {
    // independent geometry in double: face plane through the spec camera, paraboloid inverse
    auto cube_dir = [](int face, glm::dvec2 st) {
        glm::vec3 fw, up;
        spec_face_camera(face, fw, up);
        const glm::dvec3 F(fw), U(up), R = glm::cross(F, U);
        return glm::normalize(F + (2.0 * st.x - 1.0) * R + (2.0 * st.y - 1.0) * U);
    };
    auto dp_dir = [](glm::dvec2 xy) {
        const double r2 = glm::dot(xy, xy);
        return glm::dvec3(2.0 * xy.x, 2.0 * xy.y, 1.0 - r2) / (1.0 + r2);
    };
    auto angle = [](glm::dvec3 a, glm::dvec3 b) { return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)); };
    std::mt19937 rng(14);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (std::uint32_t size : {16u, 256u, 1024u}) {
        const double ang = omni_cube_texel_angle(size).value;
        double worst = 0;
        for (int it = 0; it < 20000; ++it) {
            const int face = int(u(rng) * 5.999);
            const glm::dvec2 a(u(rng), u(rng));
            const double k = 3.0 * u(rng) + 0.1, phi = 6.283185307 * u(rng);
            const glm::dvec2 b = a + k / size * glm::dvec2(std::cos(phi), std::sin(phi));
            worst = std::max(worst, angle(cube_dir(face, a), cube_dir(face, b)) / (k * ang));
        }
        MESSAGE("cube size " << size << ": max angle / (texels * omni_cube_texel_angle) = " << worst);
        CHECK(worst <= 1.0 + 1e-6);
        CHECK(worst > 0.95);  // reached near the face centre
        // paraboloid: points up to 2 texels apart around map radius r <= 1.05
        double worst_dp = 0;
        for (int it = 0; it < 20000; ++it) {
            const double r = u(rng) * 1.05, phi = 6.283185307 * u(rng);
            const glm::dvec2 a(r * std::cos(phi), r * std::sin(phi));
            const double k = 2.0 * u(rng) + 0.05, psi = 6.283185307 * u(rng);
            const glm::dvec2 b = a + 2.0 * k / size * glm::dvec2(std::cos(psi), std::sin(psi));
            worst_dp = std::max(worst_dp, angle(dp_dir(a), dp_dir(b)) / (k * omni_paraboloid_texel_angle(size, float(r)).value));
        }
        MESSAGE("paraboloid size " << size << ": max angle / bound = " << worst_dp);
        CHECK(worst_dp <= 1.0 + 1e-6);
        CHECK(worst_dp > 0.9);
    }
    // issue 19: size 0 returned an angle of 0 (a bias of 0, acne) with no status
    CHECK(omni_cube_texel_angle(0).status == Status::InvalidArgument);
    CHECK(omni_paraboloid_texel_angle(0, 0.5f).status == Status::InvalidArgument);
    CHECK(omni_paraboloid_texel_angle(64, kNaN).status == Status::NonFinite);
    CHECK(omni_paraboloid_texel_angle(64, 3e38f).status == Status::Ok);
    CHECK(std::isfinite(omni_paraboloid_texel_angle(64, 3e38f).value));
}

// =============================================================================== dual paraboloid

TEST_CASE("paraboloid projection round trip error < 1e-6 over the sphere, and the seam continuation") {
    std::mt19937 rng(21);
    double worst = 0, worst_xy = 0;
    std::size_t n = 0;
    auto check_dir = [&](glm::vec3 d) {
        const OmniParaboloidPoint p = omni_paraboloid_project(d);
        REQUIRE(p.status == Status::Ok);
        CHECK(glm::length(p.xy) <= 1.f + 1e-6f);
        CHECK((p.hemisphere == OmniHemisphere::Front) == (d.z >= 0.f));
        const OmniDirection b = omni_paraboloid_unproject(p.hemisphere, p.xy);
        REQUIRE(b.status == Status::Ok);
        worst = std::max(worst, glm::length(glm::dvec3(b.direction) - glm::normalize(glm::dvec3(d))));
        ++n;
    };
    for (int it = 0; it < 1000000; ++it) check_dir(random_unit(rng));
    // Fibonacci sphere, the rim (z = 0, +-0), the poles, one ulp around the rim
    for (int i = 0; i < 100000; ++i) {
        const double z = 1.0 - 2.0 * (i + 0.5) / 100000.0, r = std::sqrt(1 - z * z), ph = i * 2.399963229728653;
        check_dir(glm::vec3(float(r * std::cos(ph)), float(r * std::sin(ph)), float(z)));
    }
    for (int i = 0; i < 10000; ++i) {
        const float a = 6.2831853f * float(i) / 10000.f;
        check_dir({std::cos(a), std::sin(a), 0.f});
        check_dir({std::cos(a), std::sin(a), -0.f});
        check_dir({std::cos(a), std::sin(a), 1e-30f});
        check_dir({std::cos(a), std::sin(a), -1e-30f});
        check_dir({std::cos(a), std::sin(a), std::nextafter(0.f, 1.f)});
    }
    check_dir({0, 0, 1});
    check_dir({0, 0, -1});
    check_dir({1e-30f, 0, -1});
    // the other way: map points in the disk
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    for (int it = 0; it < 300000; ++it) {
        glm::vec2 xy(u(rng), u(rng));
        if (glm::length(xy) > 1.f) continue;
        const OmniHemisphere h = (it & 1) ? OmniHemisphere::Back : OmniHemisphere::Front;
        const OmniDirection d = omni_paraboloid_unproject(h, xy);
        const OmniParaboloidPoint p = omni_paraboloid_project(d.direction);
        if (glm::length(xy) < 0.999f) CHECK(p.hemisphere == h);
        if (p.hemisphere == h) worst_xy = std::max(worst_xy, double(glm::length(p.xy - xy)));
    }
    // seam: front xy with r > 1 continues into the back map at xy / r^2 (same direction)
    double worst_seam = 0;
    for (int it = 0; it < 100000; ++it) {
        const glm::vec2 xy = glm::vec2(u(rng), u(rng)) * 3.f;
        const float r2 = glm::dot(xy, xy);
        if (r2 <= 1.f) continue;
        const glm::vec3 a = omni_paraboloid_unproject(OmniHemisphere::Front, xy).direction;
        const glm::vec3 b = omni_paraboloid_unproject(OmniHemisphere::Back, xy / r2).direction;
        CHECK(a.z <= 1e-6f);
        worst_seam = std::max(worst_seam, double(glm::length(a - b)));
    }
    MESSAGE(n << " directions: round trip max " << worst << "; xy round trip max " << worst_xy << "; seam max " << worst_seam);
    CHECK(worst < 1e-6);
    CHECK(worst_xy < 1e-6);
    CHECK(worst_seam < 1e-6);
    // stiff: zero, NaN, Inf; huge xy
    CHECK(omni_paraboloid_project({0, 0, 0}).status == Status::InvalidArgument);
    CHECK(omni_paraboloid_project({kNaN, 0, 1}).status == Status::NonFinite);
    CHECK(omni_paraboloid_project({kInf, 0, 1}).status == Status::NonFinite);
    CHECK(omni_paraboloid_project({1e-38f, 0, 0}).status == Status::Ok);
    CHECK(omni_paraboloid_project({3e38f, 3e38f, 3e38f}).status == Status::Ok);
    const OmniDirection far_xy = omni_paraboloid_unproject(OmniHemisphere::Front, {3e38f, 3e38f});
    CHECK(far_xy.status == Status::Ok);
    CHECK(far_xy.direction.z < -0.999f);
    CHECK(omni_paraboloid_unproject(OmniHemisphere::Front, {kNaN, 0}).status == Status::NonFinite);
    CHECK(omni_paraboloid_unproject(static_cast<OmniHemisphere>(7), {0, 0}).status == Status::InvalidArgument);
}

TEST_CASE("paraboloid frame: right-handed, light at the origin, axis to +z; bad input statuses") {
    const glm::vec3 light(1.f, 2.f, 3.f), axis(0.f, 2.f, 0.f), up(0.f, 0.f, 1.f);
    const OmniParaboloidFrame fr = omni_paraboloid_frame(pt(light), axis, up);
    REQUIRE(fr.status == Status::Ok);
    const glm::vec4 o = fr.view * glm::vec4(light, 1.f);
    CHECK(glm::length(glm::vec3(o)) < 1e-6f);
    const glm::vec4 a = fr.view * glm::vec4(light + glm::vec3(0, 1, 0), 1.f);
    CHECK(std::fabs(a.z - 1.f) < 1e-6f);
    CHECK(glm::determinant(glm::mat3(fr.view)) > 0.999f);
    CHECK(omni_paraboloid_frame(pt(light), {0, 1, 0}, {0, 3, 0}).status == Status::InvalidArgument);
    CHECK(omni_paraboloid_frame(pt(light), {0, 0, 0}, up).status == Status::InvalidArgument);
    CHECK(omni_paraboloid_frame(pt({kNaN, 0, 0}), axis, up).status == Status::InvalidLight);
    CHECK(omni_paraboloid_frame(pt(light), {kInf, 0, 0}, up).status == Status::NonFinite);
    // a directional light has no position for the paraboloids
    CHECK(omni_paraboloid_frame(glm::vec4(0, 1, 0, 0), axis, up).status == Status::InvalidLight);
    CHECK(omni_paraboloid_frame(glm::vec4(0.f), axis, up).status == Status::InvalidLight);
    CHECK(omni_paraboloid_frame(glm::vec4(1, 2, 3, -1), axis, up).status == Status::InvalidLight);
    // w != 1: the light is at xyz / w
    const OmniParaboloidFrame fw = omni_paraboloid_frame(glm::vec4(2.f * light, 2.f), axis, up);
    REQUIRE(fw.status == Status::Ok);
    CHECK(glm::length(glm::vec3(fw.view * glm::vec4(light, 1.f))) < 1e-5f);
    CHECK(omni_paraboloid_frame(pt({1e6f, 1e6f, 1e6f}), axis, up).status == Status::Ok);
}

namespace {
// Brute force: the largest distance (map units) between the paraboloid image of segment ab
// (front map, frame = identity, light at the origin) and the chord between its end images.
double brute_edge_deviation(glm::dvec3 a, glm::dvec3 b, int samples) {
    auto proj = [](glm::dvec3 p) {
        const glm::dvec3 n = glm::normalize(p);
        return glm::dvec2(n.x, n.y) / (1.0 + n.z);
    };
    const glm::dvec2 pa = proj(a), pb = proj(b);
    double worst = 0;
    for (int i = 1; i < samples; ++i) {
        const double t = double(i) / samples;
        const glm::dvec2 q = proj(a + t * (b - a));
        const glm::dvec2 ab = pb - pa;
        const double l2 = glm::dot(ab, ab);
        const double s = l2 > 0 ? std::clamp(glm::dot(q - pa, ab) / l2, 0.0, 1.0) : 0.0;
        worst = std::max(worst, glm::length(q - (pa + s * ab)));
    }
    return worst;
}
double segment_distance_to_origin(glm::dvec3 a, glm::dvec3 b) { return point_segment_dist(glm::dvec3(0.0), a, b); }
}  // namespace

TEST_CASE("tessellation bound >= brute-force deviation of edge images, attained on the rim (factor 1)") {
    std::mt19937 rng(31);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const std::uint32_t size = 1024;
    const double to_texels = size / 2.0;
    double worst_ratio = 0, sum_ratio = 0;
    int n = 0, violations = 0;
    for (int it = 0; it < 20000; ++it) {
        // end points in the front hemisphere (z >= 0), biased towards the rim half the time
        auto pick = [&]() {
            glm::dvec3 d = glm::dvec3(random_unit(rng));
            d.z = std::fabs(d.z);
            if (it & 1) d.z *= 0.05;
            return glm::normalize(d) * (0.2 + 5.0 * u(rng));
        };
        const glm::dvec3 a = pick(), b = pick();
        const double L = glm::length(b - a), D = segment_distance_to_origin(a, b);
        if (!(D > 1e-3)) continue;
        const OmniEdgeErrorResult e = omni_paraboloid_edge_error(float(L), float(D), size);
        REQUIRE(e.status == Status::Ok);
        const double brute = brute_edge_deviation(a, b, 2000) * to_texels;
        if (brute > double(e.texels) * (1.0 + 1e-5) + 1e-6) ++violations;
        if (e.texels > 1e-3f) {
            const double ratio = brute / e.texels;
            worst_ratio = std::max(worst_ratio, ratio);
            sum_ratio += ratio;
            ++n;
        }
    }
    MESSAGE("random edges in a hemisphere: " << n << " compared, brute/bound max " << worst_ratio << ", mean "
                                               << sum_ratio / n);
    CHECK(violations == 0);
    CHECK(worst_ratio > 0.9);
    // the worst case: an edge on the rim plane (z = 0), centred on its foot point -> bound attained
    for (double D : {0.1, 1.0, 30.0})
        for (double L : {0.001, 0.05, 0.5, 3.0}) {
            const glm::dvec3 a(D, -0.5 * L * D, 0.0), b(D, 0.5 * L * D, 0.0);
            const OmniEdgeErrorResult e = omni_paraboloid_edge_error(float(L * D), float(D), size);
            const double brute = brute_edge_deviation(a, b, 20000) * to_texels;
            MESSAGE("rim edge L/D = " << L << ": bound " << e.texels << " texels, brute force " << brute);
            CHECK(brute <= double(e.texels) * (1.0 + 1e-5) + 1e-6);
            CHECK(brute >= double(e.texels) * 0.999 - 1e-6);
        }
    // the inverse gives the longest edge for a tolerance
    for (float tol : {0.25f, 1.f, 4.f, 50.f}) {
        const OmniEdgeLengthResult l = omni_paraboloid_max_edge_length(2.f, size, tol);
        REQUIRE(l.status == Status::Ok);
        const OmniEdgeErrorResult e = omni_paraboloid_edge_error(l.length, 2.f, size);
        CHECK(std::fabs(e.texels - tol) < 1e-3f * tol);
        const glm::dvec3 a(2.0, -0.5 * l.length, 0.0), b(2.0, 0.5 * l.length, 0.0);
        CHECK(brute_edge_deviation(a, b, 20000) * to_texels <= double(tol) * 1.0001);
    }
    // issue 19: "any edge passes" was Ok with length +inf; now a field, with a finite length
    const OmniEdgeLengthResult any = omni_paraboloid_max_edge_length(1.f, 64, 1e6f);
    CHECK(any.status == Status::Ok);
    CHECK(any.unlimited);
    CHECK(any.length == std::numeric_limits<float>::max());
    CHECK_FALSE(omni_paraboloid_max_edge_length(1.f, 64, 1.f).unlimited);
    // finite input whose length is beyond float
    CHECK(omni_paraboloid_max_edge_length(3e38f, 64, 10.f).status == Status::Overflow);
    // stiff and bad input
    CHECK(omni_paraboloid_edge_error(1.f, 0.f, size).status == Status::Ok);  // edge through the light
    CHECK(omni_paraboloid_edge_error(0.f, 0.f, size).texels == 0.f);
    CHECK(omni_paraboloid_edge_error(1.f, kInf, size).texels == 0.f);
    CHECK(omni_paraboloid_edge_error(1e-6f, 1e6f, size).texels < 1e-9f);
    CHECK(omni_paraboloid_edge_error(kNaN, 1.f, size).status == Status::NonFinite);
    CHECK(omni_paraboloid_edge_error(1.f, -1.f, size).status == Status::InvalidArgument);
    CHECK(omni_paraboloid_edge_error(1.f, 1.f, 0).status == Status::InvalidArgument);
    CHECK(omni_paraboloid_max_edge_length(1.f, 0, 1.f).status == Status::InvalidArgument);
    CHECK(omni_paraboloid_max_edge_length(kNaN, 64, 1.f).status == Status::NonFinite);
    // R > 1 (clip margin): still an upper bound for edges whose image stays within R
    int margin_violations = 0, margin_checked = 0;
    for (int it = 0; it < 3000; ++it) {
        auto pick = [&]() {
            glm::dvec3 d = glm::dvec3(random_unit(rng));
            d.z = -0.09 * u(rng);  // map radius up to ~1.1
            return glm::normalize(d) * (0.5 + u(rng));
        };
        const glm::dvec3 a = pick(), b = pick();
        const double D = segment_distance_to_origin(a, b);
        if (!(D > 1e-3)) continue;
        // only edges whose image stays within map radius 1.1 (the segment dips towards -z between
        // its end points): the precondition of the bound
        bool within = true;
        for (int k = 0; k <= 200 && within; ++k) {
            const glm::dvec3 nn = glm::normalize(a + (k / 200.0) * (b - a));
            if (glm::length(glm::dvec2(nn.x, nn.y)) / (1.0 + nn.z) > 1.1) within = false;
        }
        if (!within) continue;
        ++margin_checked;
        const OmniEdgeErrorResult e = omni_paraboloid_edge_error(float(glm::length(b - a)), float(D), size, 1.1f);
        if (brute_edge_deviation(a, b, 1000) * to_texels > double(e.texels) * (1.0 + 1e-5) + 1e-6) ++margin_violations;
    }
    MESSAGE(margin_checked << " edges within map radius 1.1 checked");
    CHECK(margin_checked > 500);
    CHECK(margin_violations == 0);
}

// ============================================================================== linear distance

TEST_CASE("bias keeps a planar receiver lit over its filter footprint (brute-force rays), exact without storage") {
    std::mt19937 rng(41);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int violations = 0, stored_violations = 0;
    double worst_tightness = 0;
    for (int it = 0; it < 20000; ++it) {
        OmniBiasInput in;
        in.distance = float(0.01 + 20.0 * u(rng));
        const double theta = 1.45 * u(rng);  // below max_angle (85 deg)
        in.cos_theta = float(std::cos(theta));
        in.texel_angle = omni_cube_texel_angle(64u << (it % 5)).value;
        in.filter_radius = (it & 1) ? 1.41422f : 4.24265f;
        in.range = in.distance * float(1.0 + 3.0 * u(rng));
        in.format = it % 3 == 0 ? DepthFormat::Fixed24 : (it % 3 == 1 ? DepthFormat::Float32 : DepthFormat::Fixed16);
        const OmniBiasResult b = omni_distance_bias(in);
        REQUIRE(b.status == Status::Ok);
        CHECK(std::fabs(b.bias_stored - b.bias_world / in.range) <= 1e-6f * b.bias_stored + 1e-12f);
        // plane at perpendicular distance h = d cos(theta) (theta recomputed from the float input);
        // rays at angle psi from the lookup ray, in the plane of incidence (the extreme) and random
        const double d = in.distance, th = std::acos(double(in.cos_theta)), h = d * std::cos(th);
        const double alpha = double(in.filter_radius) * in.texel_angle;
        double max_drop = 0;
        for (int k = 0; k <= 64; ++k) {
            const double psi = alpha * (k / 64.0);
            // rotating towards the normal by psi (the extreme), or by psi around a random axis
            const double thp = std::max(th - psi, 0.0);
            const double dp = h / std::cos(thp);
            max_drop = std::max(max_drop, d - dp);
            const double phi = 6.283185307 * u(rng);
            // angle to the normal after a rotation by psi at azimuth phi (spherical law of cosines)
            const double c2 = std::cos(th) * std::cos(psi) + std::sin(th) * std::sin(psi) * std::cos(phi);
            const double dp2 = h / std::max(c2, 1e-12);
            if (c2 > 0) max_drop = std::max(max_drop, d - dp2);
            // what a lookup compares: quantized stored value vs (d - bias) / range
            const OmniDepthResult st = omni_linear_depth(float(dp), in.range, in.format);
            REQUIRE(st.status == Status::Ok);
            const double ref = (double(in.distance) - double(b.bias_world)) / double(in.range);
            if (!(ref <= double(st.value) + 1e-12)) {
                ++stored_violations;
                MESSAGE("format " << int(in.format) << " ref " << ref << " stored " << st.value << " d " << d << " range " << in.range);
            }
        }
        if (max_drop > double(b.bias_world) * (1.0 + 1e-6) + 1e-9) ++violations;
        // exactness of the geometric term: bias minus its storage part vs the brute-force drop
        OmniBiasInput g = in;
        g.format = DepthFormat::Fixed24;
        g.range = 1e-30f;  // storage term ~0 (range / 2^24)
        const OmniBiasResult bg = omni_distance_bias(g);
        if (bg.status == Status::Ok && max_drop > 1e-6 * d)
            worst_tightness = std::max(worst_tightness, double(bg.bias_world) / max_drop);
    }
    MESSAGE("bias / brute-force drop (geometric part): max " << worst_tightness);
    CHECK(violations == 0);
    CHECK(stored_violations == 0);
    CHECK(worst_tightness < 1.001);
    // stiff and bad input
    OmniBiasInput in;
    CHECK(omni_distance_bias(in).status == Status::InvalidArgument);  // range and texel_angle are required
    in.range = 1.f;
    CHECK(omni_distance_bias(in).status == Status::InvalidArgument);
    in.texel_angle = 0.01f;
    in.cos_theta = -0.5f;  // facing away: clamped to max_angle, still finite
    CHECK(omni_distance_bias(in).status == Status::Ok);
    in.cos_theta = kNaN;
    CHECK(omni_distance_bias(in).status == Status::NonFinite);
    in.cos_theta = 1.f;
    in.range = 0.f;
    CHECK(omni_distance_bias(in).status == Status::InvalidArgument);
    in.range = 1.f;
    in.max_angle = 2.f;
    CHECK(omni_distance_bias(in).status == Status::InvalidArgument);
    in.max_angle = 1.f;
    in.distance = 1e6f;
    in.range = 2e6f;
    CHECK(omni_distance_bias(in).status == Status::Ok);
    CHECK(omni_linear_depth(2.f, 1.f, DepthFormat::Float32).value == 1.f);
    CHECK(omni_linear_depth(-1.f, 1.f, DepthFormat::Float32).status == Status::InvalidArgument);
    CHECK(omni_linear_depth(1.f, kInf, DepthFormat::Float32).status == Status::NonFinite);
    CHECK(omni_linear_depth(kInf, 1.f, DepthFormat::Float32).value == 1.f);  // beyond the range: clamped
    CHECK(omni_linear_depth(1.f, 2.f, static_cast<DepthFormat>(7)).status == Status::InvalidArgument);
    CHECK(OmniDepthResult{}.status == Status::NotRun);
}

// ==================================================================================== culling

TEST_CASE("per-face culling never culls a caster that meets a face frustum (exact brute force) and counts saved draws") {
    std::mt19937 rng(51);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::size_t pairs = 0, kept_brute = 0, kept_header = 0, missed = 0, extra = 0;
    std::size_t spairs = 0, smissed = 0, sextra = 0;
    for (int it = 0; it < 4000; ++it) {
        const double scale = std::pow(10.0, -2.0 + 4.0 * u(rng));
        const glm::vec3 light = glm::vec3(float((u(rng) - 0.5) * scale), float((u(rng) - 0.5) * scale),
                                          float((u(rng) - 0.5) * scale));
        const float nearz = float(scale * std::pow(10.0, -4.0 + 3.0 * u(rng)));
        const bool inf = (it % 5) == 0;
        const float farz = inf ? kInf : float(scale * (0.3 + 2.0 * u(rng)));
        // brute force uses a finite far beyond every caster when the far plane is infinite
        const double far_b = inf ? 100.0 * scale : double(farz);
        const glm::dvec3 L(light);
        // box: random centre around the light, random extents (some zero-size, some thin)
        const glm::dvec3 c = L + glm::dvec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5) * (3.0 * scale);
        glm::dvec3 h = glm::dvec3(u(rng), u(rng), u(rng)) * (0.3 * scale);
        if (it % 7 == 0) h = glm::dvec3(0.0);
        if (it % 11 == 0) h.y = 0.0;
        const glm::vec3 lo(c - h), hi(c + h);
        const std::uint8_t mask = omni_cube_box_mask(pt(light), nearz, farz, lo, hi);
        const Poly box = box_poly(glm::dvec3(lo) - L, glm::dvec3(hi) - L);
        for (int f = 0; f < 6; ++f) {
            const Poly fr = frustum_poly(f, nearz, far_b);
            const bool meet = polys_meet(box, fr, 1e-9 * scale);
            const bool meet_strict = polys_meet(box, fr, -1e-7 * scale);  // clearly inside
            const bool kept = (mask >> f) & 1;
            ++pairs;
            kept_brute += meet;
            kept_header += kept;
            if (meet_strict && !kept) ++missed;
            if (kept && !meet) ++extra;
        }
        // sphere around the same centre
        const float r = (it % 9 == 0) ? 0.f : float(0.3 * scale * u(rng));
        const std::uint8_t smask = omni_cube_sphere_mask(pt(light), nearz, farz, glm::vec3(c), r);
        for (int f = 0; f < 6; ++f) {
            const Poly fr = frustum_poly(f, nearz, far_b);
            const double dist = point_poly_dist(fr, glm::dvec3(glm::vec3(c)) - L);
            const bool kept = (smask >> f) & 1;
            ++spairs;
            if (dist < double(r) - 1e-7 * scale && !kept) ++smissed;
            if (kept && dist > double(r) + 1e-6 * scale) ++sextra;
        }
    }
    MESSAGE("boxes: " << pairs << " box-face pairs, brute force keeps " << kept_brute << ", header keeps "
                      << kept_header << ", culled that meet: " << missed << ", kept that do not meet: " << extra);
    MESSAGE("spheres: " << spairs << " pairs, culled that meet: " << smissed << ", kept that do not: " << sextra);
    CHECK(missed == 0);
    CHECK(smissed == 0);
    CHECK(extra <= pairs / 1000);   // exact up to touching cases
    CHECK(sextra <= spairs / 1000);
    CHECK(kept_header < pairs);     // something was culled
}

TEST_CASE("culling outputs: masks, per-face lists, saved draws on a room, buffers and bad casters") {
    // a room around a light with furniture: the saved draws are countable by hand
    const glm::vec3 light(0.2f, 2.2f, 0.f);
    const std::vector<float> boxes = {
        -3.f, 0.f, -3.f, 3.f, 3.f, 3.f,            // room: contains the light -> all 6 faces
        0.2f, 0.f, -0.1f, 1.4f, 0.8f, 0.7f,        // table below the light: -Y only
        -1.5f, 0.f, -1.1f, -0.5f, 1.f, -0.1f,      // ball's box: -X and -Y
        -1.75f, 0.f, 1.25f, -1.25f, 3.f, 1.75f,    // pillar: -X, -Y, +Z
    };
    OmniCullInput in;
    in.light_position = pt(light);
    in.near_z = 0.01f;
    in.far_z = 10.f;
    in.boxes = boxes.data();
    in.box_count = 4;
    std::uint8_t masks[4] = {};
    const OmniCullResult r = omni_cull_casters(in, masks, 4);
    REQUIRE(r.status == Status::Ok);
    CHECK(masks[0] == omni_all_faces_mask);
    CHECK(masks[1] == (1u << 3));
    CHECK(masks[2] == ((1u << 1) | (1u << 3)));
    CHECK(masks[3] == ((1u << 1) | (1u << 3) | (1u << 4)));
    CHECK(r.draws == 12);
    CHECK(r.draws_saved == 12);
    CHECK(r.face_draws[0] == 1);
    CHECK(r.face_draws[3] == 4);
    std::vector<std::uint32_t> lists(r.draws);
    std::size_t off[7] = {};
    const OmniCullResult lr = omni_cull_face_lists(in, lists.data(), lists.size(), off);
    REQUIRE(lr.status == Status::Ok);
    CHECK(off[6] == 12);
    for (int f = 0; f < 6; ++f)
        for (std::size_t k = off[f]; k < off[f + 1]; ++k) CHECK(((masks[lists[k]] >> f) & 1) == 1);
    // buffers too small
    const OmniCullResult small = omni_cull_face_lists(in, lists.data(), 5, off);
    CHECK(small.status == Status::BufferTooSmall);
    CHECK(small.needed == 12);
    std::uint8_t two[2];
    const OmniCullResult small2 = omni_cull_casters(in, two, 2);
    CHECK(small2.status == Status::BufferTooSmall);
    CHECK(small2.needed == 4);
    CHECK(two[1] == masks[1]);
    // spheres continue the indices; NaN and min > max casters are never culled, and counted
    const std::vector<float> bad = {kNaN, 0, 0, 1, 1, 1, 2, 2, 2, 1, 1, 1, 0, 0, 0, 0, 0, 0};
    const std::vector<float> spheres = {-1.f, 0.5f, -0.6f, 0.5f, 0, 0, 0, -1.f, 5, 5, 5, kInf};
    OmniCullInput b;
    b.light_position = pt(light);
    b.near_z = 0.01f;
    b.far_z = kInf;
    b.boxes = bad.data();
    b.box_count = 3;
    b.spheres = spheres.data();
    b.sphere_count = 3;
    std::uint8_t bm[6];
    const OmniCullResult br = omni_cull_casters(b, bm, 6);
    REQUIRE(br.status == Status::Ok);
    CHECK(br.invalid_count == 4);
    CHECK(bm[0] == omni_all_faces_mask);
    CHECK(bm[1] == omni_all_faces_mask);
    CHECK(bm[3] == ((1u << 1) | (1u << 3)));  // the ball as a sphere: -X and -Y
    CHECK(bm[4] == omni_all_faces_mask);
    CHECK(bm[5] == omni_all_faces_mask);
    // bad light / range / pointers
    OmniCullInput e = in;
    e.light_position.x = kNaN;
    CHECK(omni_cull_casters(e, masks, 4).status == Status::InvalidLight);
    e = in;
    e.near_z = 0.f;
    CHECK(omni_cull_casters(e, masks, 4).status == Status::InvalidArgument);
    e = in;
    e.far_z = e.near_z;
    CHECK(omni_cull_casters(e, masks, 4).status == Status::InvalidArgument);
    e = in;
    e.boxes = nullptr;
    CHECK(omni_cull_casters(e, masks, 4).status == Status::InvalidArgument);
    e = in;
    e.box_count = std::numeric_limits<std::size_t>::max();
    CHECK(omni_cull_casters(e, masks, 4).status == Status::InvalidArgument);
    OmniCullInput empty;
    CHECK(omni_cull_face_lists(empty, nullptr, 0, off).status == Status::InvalidLight);  // the light is required
    empty.light_position = pt(light);
    CHECK(omni_cull_face_lists(empty, nullptr, 0, off).status == Status::Ok);
    CHECK(off[6] == 0);
    // issue 19: null output buffers with a capacity are InvalidArgument (they were treated as capacity 0)
    CHECK(omni_cull_casters(in, nullptr, 4).status == Status::InvalidArgument);
    CHECK(omni_cull_face_lists(in, nullptr, 12, off).status == Status::InvalidArgument);
    CHECK(omni_cull_face_lists(in, lists.data(), lists.size(), nullptr).status == Status::InvalidArgument);
    const OmniCullResult query = omni_cull_casters(in, nullptr, 0);  // size query
    CHECK(query.status == Status::BufferTooSmall);
    CHECK(query.needed == 4);
    CHECK(query.count == 0);
    CHECK(lr.count == 12);
    // directional light: no cube
    e = in;
    e.light_position = glm::vec4(0.f, 1.f, 0.f, 0.f);
    CHECK(omni_cull_casters(e, masks, 4).status == Status::InvalidLight);
    CHECK(omni_cube_box_mask(glm::vec4(0.f, 1.f, 0.f, 0.f), 0.01f, 10.f, {1, 1, 1}, {2, 2, 2}) == omni_all_faces_mask);
}

TEST_CASE("stiff cases: light at 1e6, near 1e-5, far at infinity, zero-size casters, NaN") {
    OmniCubeInput in;
    in.light_position = pt({1e6f, -1e6f, 1e6f});
    in.near_z = 1e-5f;
    in.far_z = 1e4f;
    OmniCubeMatrices m = omni_cube_matrices(in);
    REQUIRE(m.status == Status::Ok);
    // a point 10 units off the light along +X: centre of face 0, ndc depth of distance 10
    const glm::dvec4 c = glm::dmat4(m.view_proj[0]) * glm::dvec4(glm::dvec3(glm::vec3(in.light_position)) + glm::dvec3(10, 0, 0), 1.0);
    CHECK(std::fabs(c.w - 10.0) < 1e-6 * 1e6);  // float translation of 1e6: a few ulps
    CHECK(std::fabs(c.x / c.w) < 0.02);
    in.far_z = kInf;
    in.clip_depth = ClipDepth::ZeroToOne;
    in.reversed_z = true;
    m = omni_cube_matrices(in);
    REQUIRE(m.status == Status::Ok);
    CHECK(m.proj[2][2] == 0.f);
    CHECK(m.proj[3][2] == 1e-5f);
    in.far_z = in.near_z;
    CHECK(omni_cube_matrices(in).status == Status::InvalidArgument);
    in.far_z = kNaN;
    CHECK(omni_cube_matrices(in).status == Status::NonFinite);
    in.far_z = 1.f;
    in.near_z = -1.f;
    CHECK(omni_cube_matrices(in).status == Status::InvalidArgument);
    in.near_z = 1e-5f;
    in.light_position.y = kNaN;
    CHECK(omni_cube_matrices(in).status == Status::InvalidLight);
    in.light_position = pt({3e38f, 3e38f, 3e38f});
    CHECK(omni_cube_matrices(in).status == Status::Ok);
    in.light_position = glm::vec4(1.f, 2.f, 3.f, 0.f);  // directional: no cube
    CHECK(omni_cube_matrices(in).status == Status::InvalidLight);
    in.light_position = glm::vec4(3e38f, 0.f, 0.f, 1e-3f);  // xyz / w beyond float
    CHECK(omni_cube_matrices(in).status == Status::Overflow);
    CHECK(omni_cube_matrices(OmniCubeInput{}).status == Status::InvalidLight);  // the light is required
    // culling with the light at 1e6 and near 1e-5: a zero-size caster 1 unit off along each axis
    const glm::vec3 L(1e6f, 1e6f, -1e6f);
    const glm::vec3 offs[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (int f = 0; f < 6; ++f) {
        const glm::vec3 p = L + offs[f] * 0.5f;  // exactly representable at 1e6 (ulp 0.0625)
        CHECK(omni_cube_box_mask(pt(L), 1e-5f, kInf, p, p) == (1u << f));
        CHECK(omni_cube_sphere_mask(pt(L), 1e-5f, kInf, p, 0.f) == (1u << f));
        // inside the near plane: culled from every face
        CHECK(omni_cube_box_mask(pt(L), 1.f, kInf, p, p) == 0);
    }
    // a point exactly on a cube edge belongs to both faces' closed frusta
    const glm::vec3 e = L + glm::vec3(0.5f, 0.5f, 0.f);
    CHECK(omni_cube_box_mask(pt(L), 1e-5f, kInf, e, e) == ((1u << 0) | (1u << 2)));
    // the light inside a caster: every face
    CHECK(omni_cube_box_mask(pt(L), 1e-5f, 10.f, L - 1.f, L + 1.f) == omni_all_faces_mask);
    CHECK(omni_cube_sphere_mask(pt(L), 1e-5f, 10.f, L, 1.f) == omni_all_faces_mask);
    CHECK(omni_cube_sphere_mask(pt(L), 1e-5f, 10.f, L, kNaN) == omni_all_faces_mask);
    CHECK(omni_cube_sphere_mask(pt(L), 1e-5f, 10.f, L, -1.f) == omni_all_faces_mask);
    // beyond the far plane: nothing
    CHECK(omni_cube_sphere_mask(pt(L), 1e-5f, 10.f, L + glm::vec3(20.f, 0.f, 0.f), 1.f) == 0);
}

TEST_CASE("issue 19: near and far within a few ulps are rejected, every Ok matrix maps near and far right") {
    // Regression: near 1, far 1 + 1 ulp returned Ok with the near plane at NDC -2 (GL convention).
    const ClipDepth cds[2] = {ClipDepth::NegativeOneToOne, ClipDepth::ZeroToOne};
    for (ClipDepth cd : cds)
        for (bool rev : {false, true}) {
            OmniCubeInput in;
            in.light_position = pt({0.f, 0.f, 0.f});
            in.clip_depth = cd;
            in.reversed_z = rev;
            // GL [-1, 1]: (f + n) / (f - n) and 2 f n / (f - n) round apart, near lands at -2 (issue 19).
            // Zero-to-one: A = -f / (f - n) and B = -f n / (f - n) are equal for n = 1 and the float
            // matrix maps near and far exactly (checked below), so it may stay Ok.
            for (float n : {1.f, 1e-5f}) {
                in.near_z = n;
                in.far_z = std::nextafter(n, 2.f);
                const OmniCubeMatrices m = omni_cube_matrices(in);
                if (cd == ClipDepth::NegativeOneToOne) CHECK(m.status == Status::Overflow);
                else CHECK((m.status == Status::Overflow || m.status == Status::Ok));
                if (m.status == Status::Ok) {
                    const glm::dvec4 cn = glm::dmat4(m.proj) * glm::dvec4(0.0, 0.0, -double(n), 1.0);
                    CHECK(std::fabs(cn.z / cn.w - (rev ? 1.0 : 0.0)) <= 1e-4);
                }
            }
            in.near_z = 1.f;
            in.far_z = 1.01f;  // well above the documented limit (far / near > ~1.0012)
            CHECK(omni_cube_matrices(in).status == Status::Ok);
            in.far_z = 1.002f;
            CHECK(omni_cube_matrices(in).status == Status::Ok);
        }
    // Property: for near / far ratios from 1 + 1e-7 to 1e6, every Ok matrix maps the near and far
    // planes to their NDC depths within 1e-4 (evaluated in double from the float entries, as a
    // closed form of each convention), and every ratio above 1.002 is Ok.
    std::mt19937 rng(19);
    std::uniform_real_distribution<double> lg(-7.0, 6.0), ln(-5.0, 3.0);
    int ok = 0, rejected = 0;
    for (int it = 0; it < 20000; ++it) {
        OmniCubeInput in;
        in.light_position = pt({1.f, 2.f, 3.f});
        in.clip_depth = cds[it & 1];
        in.reversed_z = (it & 2) != 0;
        in.near_z = float(std::pow(10.0, ln(rng)));
        in.far_z = float(double(in.near_z) * (1.0 + std::pow(10.0, lg(rng))));
        if (!(in.far_z > in.near_z)) continue;
        const OmniCubeMatrices m = omni_cube_matrices(in);
        const double ratio = double(in.far_z) / double(in.near_z);
        if (m.status != Status::Ok) {
            CHECK(m.status == Status::Overflow);
            CHECK(ratio < 1.002);
            ++rejected;
            continue;
        }
        ++ok;
        const bool zo = in.clip_depth == ClipDepth::ZeroToOne;
        const double zn = zo ? (in.reversed_z ? 1 : 0) : (in.reversed_z ? 1 : -1);
        const double zf = zo ? (in.reversed_z ? 0 : 1) : (in.reversed_z ? -1 : 1);
        auto ndc = [&](double d) {
            const glm::dvec4 c = glm::dmat4(m.proj) * glm::dvec4(0.0, 0.0, -d, 1.0);
            return c.z / c.w;
        };
        CHECK(std::fabs(ndc(in.near_z) - zn) <= 1e-4);
        CHECK(std::fabs(ndc(in.far_z) - zf) <= 1e-4);
    }
    MESSAGE("near/far property: " << ok << " Ok, " << rejected << " rejected as Overflow");
    CHECK(ok > 10000);
    CHECK(rejected > 100);
}
