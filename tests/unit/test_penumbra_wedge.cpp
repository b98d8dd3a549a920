// Unit tests for shadowkit/penumbra_wedge.hpp.
// Expected values come from independent references written here, never from the header's output:
//  * coverage: (a) a per-angle quadrature over the light disk that intersects the 3D edge with the
//    plane through p, c and each disk direction (no chords, no atan); (b) a stratified jittered area
//    Monte Carlo of the literal definition "the edge meets the triangle (p, c, x)", segment-triangle
//    tests in double;
//  * visibility: stratified sampling of the light disk with exact segment-vs-convex-polytope (Cyrus-Beck)
//    or segment-triangle occlusion tests;
//  * containment: points of the swept penumbra q + s (q - y) built from random edge points and light
//    points, and brute-force penumbra points of random boxes, icospheres and planar polygons.
#include <shadowkit/penumbra_wedge.hpp>

#include <doctest/doctest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace sk = shadowkit;

namespace {

using dvec3 = glm::dvec3;
constexpr double kPi = 3.14159265358979323846;

double dot3(const dvec3& a, const dvec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
dvec3 cross3(const dvec3& a, const dvec3& b) { return dvec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x); }
double len3(const dvec3& a) { return std::sqrt(dot3(a, a)); }
dvec3 D(const glm::vec3& v) { return dvec3(v.x, v.y, v.z); }
glm::vec3 F(const dvec3& v) { return glm::vec3(static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)); }
// A sphere light at center c (w = 1) of radius r, and its center back.
sk::PenumbraSphereLight SL(const glm::vec3& c, float r) {
    sk::PenumbraSphereLight L;
    L.light_position = glm::vec4(c, 1.0f);
    L.radius = r;
    return L;
}
glm::vec3 ctr(const sk::PenumbraSphereLight& L) { return glm::vec3(L.light_position) / L.light_position.w; }
// A wedge to draw: Ok and not skipped.
bool drawn(const sk::PenumbraWedge& w) { return w.status == sk::Status::Ok && w.skip == sk::PenumbraWedgeSkip::None; }
double plane_eval(const glm::vec4& pl, const glm::vec3& p) { return sk::detail::pw_plane_eval(pl, p); }
// Coverage and visibility values of calls that must succeed (the status is checked).
double cov(glm::vec3 e0, glm::vec3 e1, const sk::PenumbraSphereLight& L, glm::vec3 p) {
    const sk::PenumbraValue v = sk::penumbra_edge_coverage(e0, e1, L, p);
    CHECK(v.status == sk::Status::Ok);
    return v.value;
}
double vis(const glm::vec3* ends, std::size_t n, const sk::PenumbraSphereLight& L, glm::vec3 p, int hard) {
    const sk::PenumbraValue v = sk::penumbra_visibility(ends, n, L, p, hard);
    CHECK(v.status == sk::Status::Ok);
    return v.value;
}

struct Rng {
    std::mt19937 g;
    explicit Rng(unsigned s) : g(s) {}
    double u(double a = 0.0, double b = 1.0) { return std::uniform_real_distribution<double>(a, b)(g); }
    dvec3 box(double a) { // sequenced: the same stream with every compiler
        const double x = u(-a, a), y = u(-a, a), z = u(-a, a);
        return dvec3(x, y, z);
    }
    dvec3 dir() {
        for (;;) {
            dvec3 v = box(1.0);
            const double l = len3(v);
            if (l > 0.1 && l <= 1.0) return v / l;
        }
    }
    dvec3 in_ball(double r) {
        for (;;) {
            dvec3 v = box(1.0);
            if (dot3(v, v) <= 1.0) return v * r;
        }
    }
};

void frame(const dvec3& z, dvec3& x, dvec3& y) {
    const dvec3 a = std::fabs(z.x) < 0.6 ? dvec3(1, 0, 0) : dvec3(0, 1, 0);
    x = cross3(a, z);
    x /= len3(x);
    y = cross3(z, x);
}

// Shirley-Chiu concentric map of [0,1]^2 to the unit disk (area preserving).
void concentric(double a, double b, double& x, double& y) {
    const double sx = 2.0 * a - 1.0, sy = 2.0 * b - 1.0;
    if (sx == 0.0 && sy == 0.0) { x = y = 0.0; return; }
    double r, phi;
    if (std::fabs(sx) > std::fabs(sy)) { r = sx; phi = (kPi / 4.0) * (sy / sx); }
    else { r = sy; phi = kPi / 2.0 - (kPi / 4.0) * (sx / sy); }
    x = r * std::cos(phi);
    y = r * std::sin(phi);
}

// Segment [o, o + d] (t in [0,1]) against triangle (a, b, c), two-sided, Moller-Trumbore in double.
bool seg_tri(const dvec3& o, const dvec3& d, const dvec3& a, const dvec3& b, const dvec3& c) {
    const dvec3 e1 = b - a, e2 = c - a;
    const dvec3 pv = cross3(d, e2);
    const double det = dot3(e1, pv);
    if (det == 0.0) return false;
    const double inv = 1.0 / det;
    const dvec3 tv = o - a;
    const double u = dot3(tv, pv) * inv;
    if (u < 0.0 || u > 1.0) return false;
    const dvec3 qv = cross3(tv, e1);
    const double v = dot3(d, qv) * inv;
    if (v < 0.0 || u + v > 1.0) return false;
    const double t = dot3(e2, qv) * inv;
    return t >= 0.0 && t <= 1.0;
}

// Sign convention of the header, restated from the papers: + in the positive half space of the hard
// plane through c, e0, e1 with normal cross(e0 - c, e1 - c).
double ref_sign(const dvec3& e0, const dvec3& e1, const dvec3& c, const dvec3& p) {
    return dot3(cross3(e0 - c, e1 - c), p - c) >= 0.0 ? 1.0 : -1.0;
}

// (a) Per-angle quadrature: for each direction u of the disk, the plane through p spanned by (c - p)
// and u meets the edge at X = p + alpha (c - p) + beta u; it occludes radii [beta / (alpha r), 1].
double coverage_quadrature(const dvec3& e0, const dvec3& e1, const dvec3& c, double r, const dvec3& p, int n) {
    const dvec3 dv = c - p;
    const double Dl = len3(dv);
    const dvec3 z = dv / Dl;
    dvec3 x, y;
    frame(z, x, y);
    double sum = 0.0;
    for (int k = 0; k < n; ++k) {
        const double psi = (k + 0.5) * 2.0 * kPi / n;
        const dvec3 u = std::cos(psi) * x + std::sin(psi) * y;
        const dvec3 np = cross3(dv, u);
        const double f0 = dot3(np, e0 - p), f1 = dot3(np, e1 - p);
        if ((f0 > 0.0) == (f1 > 0.0) || f0 == f1) continue;
        const double t = f0 / (f0 - f1);
        const dvec3 X = e0 + t * (e1 - e0) - p;
        const double alpha = dot3(X, z) / Dl, beta = dot3(X, u);
        if (!(alpha > 0.0) || alpha > 1.0 || beta < 0.0) continue;
        const double rho = beta / (alpha * r);
        if (rho < 1.0) sum += 0.5 * (1.0 - rho * rho);
    }
    return ref_sign(e0, e1, c, p) * sum * (2.0 * kPi / n) / kPi;
}

// (b) Stratified area Monte Carlo of "the edge meets the triangle (p, c, x)".
double coverage_montecarlo(const dvec3& e0, const dvec3& e1, const dvec3& c, double r, const dvec3& p, int n, Rng& rng) {
    const dvec3 z = (c - p) / len3(c - p);
    dvec3 x, y;
    frame(z, x, y);
    long hits = 0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            double dx, dy;
            concentric((i + rng.u()) / n, (j + rng.u()) / n, dx, dy);
            const dvec3 X = c + r * (dx * x + dy * y);
            if (seg_tri(e0, e1 - e0, p, c, X)) ++hits;
        }
    return ref_sign(e0, e1, c, p) * static_cast<double>(hits) / (static_cast<double>(n) * n);
}

// ---------------------------------------------------------------- convex occluders
struct Poly {
    std::vector<dvec3> v;
    std::vector<std::array<int, 3>> tri; // outward CCW
    bool planar = false;
};

Poly make_box(Rng& rng, const dvec3& centre, double size) {
    Poly P;
    const double hx = rng.u(0.2, 1.0) * size, hy = rng.u(0.2, 1.0) * size, hz = rng.u(0.2, 1.0) * size;
    const dvec3 h(hx, hy, hz);
    dvec3 ax = rng.dir(), ay, az;
    frame(ax, ay, az);
    for (int k = 0; k < 8; ++k) {
        const double sx = (k & 1) ? 1 : -1, sy = (k & 2) ? 1 : -1, sz = (k & 4) ? 1 : -1;
        P.v.push_back(centre + sx * h.x * ax + sy * h.y * ay + sz * h.z * az);
    }
    // faces of the unit cube (outward CCW in the right-handed (ax, ay, az) frame)
    const int q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (auto& f : q) {
        P.tri.push_back({f[0], f[1], f[2]});
        P.tri.push_back({f[0], f[2], f[3]});
    }
    return P;
}

Poly make_icosphere(Rng& rng, const dvec3& centre, double radius) {
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<dvec3> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                            {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    std::vector<std::array<int, 3>> f = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                                         {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
                                         {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    for (auto& p : v) p /= len3(p);
    // one subdivision (80 faces)
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
        auto key = std::make_pair(std::min(a, b), std::max(a, b));
        auto it = mid.find(key);
        if (it != mid.end()) return it->second;
        dvec3 m = v[static_cast<size_t>(a)] + v[static_cast<size_t>(b)];
        v.push_back(m / len3(m));
        const int id = static_cast<int>(v.size()) - 1;
        mid[key] = id;
        return id;
    };
    std::vector<std::array<int, 3>> g;
    for (auto& tr : f) {
        const int a = midpoint(tr[0], tr[1]), b = midpoint(tr[1], tr[2]), c = midpoint(tr[2], tr[0]);
        g.push_back({tr[0], a, c});
        g.push_back({tr[1], b, a});
        g.push_back({tr[2], c, b});
        g.push_back({a, b, c});
    }
    Poly P;
    const double sx = rng.u(0.6, 1.0), sy = rng.u(0.6, 1.0), sz = rng.u(0.6, 1.0);
    const dvec3 s(sx, sy, sz); // ellipsoid-like, still convex
    for (auto& p : v) P.v.push_back(centre + radius * dvec3(p.x * s.x, p.y * s.y, p.z * s.z));
    P.tri = g;
    return P;
}

// Planar convex polygon (regular-ish n-gon with jitter), wound to face the light centre.
Poly make_polygon(Rng& rng, const dvec3& centre, double radius, const dvec3& light) {
    Poly P;
    P.planar = true;
    dvec3 n = rng.dir(), x, y;
    if (dot3(n, light - centre) < 0.0) n = -n;
    if (std::fabs(dot3(n, (light - centre) / len3(light - centre))) < 0.3) n = (light - centre) / len3(light - centre);
    frame(n, x, y);
    const int k = 3 + static_cast<int>(rng.u(0.0, 4.0));
    for (int i = 0; i < k; ++i) {
        const double a = 2.0 * kPi * (i + rng.u(-0.3, 0.3)) / k;
        P.v.push_back(centre + radius * (std::cos(a) * x + std::sin(a) * y)); // CCW around n
    }
    for (int i = 1; i + 1 < k; ++i) P.tri.push_back({0, i, i + 1});
    return P;
}

// Silhouette from the light centre, edges oriented as in the light-facing triangle.
std::vector<glm::vec3> silhouette(const Poly& P, const dvec3& c) {
    std::map<std::pair<int, int>, int> dir; // directed edge -> lit(1)/unlit(0)
    std::vector<std::pair<int, int>> order;
    for (auto& t : P.tri) {
        const dvec3 a = P.v[static_cast<size_t>(t[0])], b = P.v[static_cast<size_t>(t[1])], d = P.v[static_cast<size_t>(t[2])];
        const int lit = dot3(cross3(b - a, d - a), c - a) > 0.0 ? 1 : 0;
        for (int k = 0; k < 3; ++k) {
            auto e = std::make_pair(t[static_cast<size_t>(k)], t[static_cast<size_t>((k + 1) % 3)]);
            dir[e] = lit;
            order.push_back(e);
        }
    }
    std::vector<glm::vec3> out;
    for (auto& e : order) {
        if (!dir[e]) continue;
        auto it = dir.find(std::make_pair(e.second, e.first));
        if (it == dir.end() || it->second == 0) {
            out.push_back(F(P.v[static_cast<size_t>(e.first)]));
            out.push_back(F(P.v[static_cast<size_t>(e.second)]));
        }
    }
    return out;
}

bool occluded(const Poly& P, const dvec3& a, const dvec3& b) {
    for (auto& t : P.tri)
        if (seg_tri(a, b - a, P.v[static_cast<size_t>(t[0])], P.v[static_cast<size_t>(t[1])], P.v[static_cast<size_t>(t[2])])) return true;
    return false;
}

// Brute-force visibility of the light disk (perpendicular to c - p) from p: n x n stratified samples.
double visibility_ref(const Poly& P, const dvec3& c, double r, const dvec3& p, int n, Rng& rng, int* blocked_out = nullptr) {
    const dvec3 z = (c - p) / len3(c - p);
    dvec3 x, y;
    frame(z, x, y);
    int blocked = 0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            double dx, dy;
            concentric((i + rng.u()) / n, (j + rng.u()) / n, dx, dy);
            if (occluded(P, p, c + r * (dx * x + dy * y))) ++blocked;
        }
    if (blocked_out) *blocked_out = blocked;
    return 1.0 - static_cast<double>(blocked) / (static_cast<double>(n) * n);
}

bool plane_ok(const glm::vec4& p) {
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) && std::isfinite(p.w);
}
bool wedge_finite(const sk::PenumbraWedge& w) {
    if (!plane_ok(w.outer_bound) || !plane_ok(w.inner_bound) || !plane_ok(w.side[0]) || !plane_ok(w.side[1]) ||
        !plane_ok(w.hard_plane))
        return false;
    for (int i = 0; i < 2; ++i)
        if (!std::isfinite(w.apex[i].x + w.apex[i].y + w.apex[i].z) || !std::isfinite(w.ray_outer[i].x + w.ray_outer[i].y + w.ray_outer[i].z) ||
            !std::isfinite(w.ray_inner[i].x + w.ray_inner[i].y + w.ray_inner[i].z))
            return false;
    return true;
}

// A random point of the swept penumbra of the edge: q + s (q - y).
dvec3 swept_point(Rng& rng, const dvec3& e0, const dvec3& e1, const dvec3& c, double r, double smax) {
    const dvec3 q = e0 + rng.u() * (e1 - e0);
    const dvec3 yl = c + rng.in_ball(r);
    return q + rng.u(0.0, smax) * (q - yl);
}

enum class EdgeKind { Generic, NearlyRadial, Grazing, CrossingLightPlane, Short, Huge };

// Random edge + light of a given kind; edge always outside the ball.
void random_edge(Rng& rng, EdgeKind kind, dvec3& c, double& r, dvec3& e0, dvec3& e1) {
    for (;;) {
        c = rng.box(2.0);
        r = rng.u(0.01, 1.5);
        const dvec3 dir = rng.dir();
        const double dist = r + rng.u(0.05, 4.0);
        const dvec3 m = c + dist * dir; // a point of the edge
        dvec3 t = rng.dir();
        double L = rng.u(0.05, 3.0);
        switch (kind) {
        case EdgeKind::Generic: break;
        case EdgeKind::NearlyRadial: t = dir + rng.box(1e-3); t /= len3(t); break;
        case EdgeKind::Grazing: {
            // line passes at distance r (1 + eps) from c
            dvec3 x, y;
            frame(dir, x, y);
            const double eps = std::pow(10.0, rng.u(-6.0, -1.0));
            e0 = c + r * (1.0 + eps) * x + rng.u(0.5, 4.0) * dir;
            e1 = e0 + rng.u(0.5, 6.0) * dir * (rng.u() < 0.5 ? 1.0 : -1.0);
            // keep the segment outside the ball
            break;
        }
        case EdgeKind::CrossingLightPlane: {
            // edge whose endpoints lie on both sides of a plane through c
            dvec3 x, y;
            frame(dir, x, y);
            e0 = c + rng.u(r * 1.05, 4.0) * x + rng.u(0.2, 3.0) * dir;
            e1 = c + rng.u(r * 1.05, 4.0) * x - rng.u(0.2, 3.0) * dir;
            break;
        }
        case EdgeKind::Short: L = 1e-6; break;
        case EdgeKind::Huge: break;
        }
        if (kind != EdgeKind::Grazing && kind != EdgeKind::CrossingLightPlane) {
            e0 = m - 0.5 * L * t;
            e1 = m + 0.5 * L * t;
        }
        if (kind == EdgeKind::Huge) {
            const dvec3 off(1e6, -1e6, 5e5);
            c = c * 1e3 + off;
            r *= 1e3;
            e0 = e0 * 1e3 + off;
            e1 = e1 * 1e3 + off;
        }
        // quantise to float (what the API takes), then re-check validity
        c = D(F(c));
        e0 = D(F(e0));
        e1 = D(F(e1));
        r = static_cast<double>(static_cast<float>(r));
        const dvec3 ed = e1 - e0;
        if (dot3(ed, ed) == 0.0) continue;
        const double tt = std::min(1.0, std::max(0.0, dot3(c - e0, ed) / dot3(ed, ed)));
        if (len3(c - (e0 + tt * ed)) <= r * 1.0001) continue;
        return;
    }
}

double plane_margin(const sk::PenumbraWedge& w, const dvec3& p) {
    const glm::vec4* pl[4] = {&w.outer_bound, &w.inner_bound, &w.side[0], &w.side[1]};
    double m = 1e300;
    for (auto* q : pl) m = std::min(m, q->x * p.x + q->y * p.y + q->z * p.z + static_cast<double>(q->w));
    return m;
}

} // namespace

TEST_CASE("coverage: per-angle quadrature reference, random configurations, error < 1e-3") {
    Rng rng(12345);
    double max_err = 0.0, sum_err = 0.0;
    int n = 0, nonzero = 0;
    for (int it = 0; it < 800; ++it) {
        const dvec3 c = rng.box(2.0);
        const double r = rng.u(0.02, 1.5);
        const dvec3 p = rng.box(6.0);
        if (len3(c - p) < r * 1.5) continue;
        dvec3 e0, e1;
        if (it % 4 != 3) {
            // occluding edge between p and the light (the interesting case)
            const double f = rng.u(0.05, 0.95);
            const dvec3 m = p + f * (c - p) + rng.box(1.5 * r * f);
            const dvec3 t = rng.dir() * rng.u(0.05, 4.0);
            e0 = m - 0.5 * t;
            e1 = m + t;
        } else {
            // generic: may straddle p's depth plane or reach beyond the light plane
            e0 = p + rng.box(4.0);
            e1 = c + rng.box(3.0);
        }
        const glm::vec3 fe0 = F(e0), fe1 = F(e1), fc = F(c), fp = F(p);
        e0 = D(fe0); e1 = D(fe1);
        const dvec3 cq = D(fc), pq = D(fp);
        const float fr = static_cast<float>(r);
        const double got = cov(fe0, fe1, SL(fc, fr), fp);
        const double ref = coverage_quadrature(e0, e1, cq, static_cast<double>(fr), pq, 8192);
        const double err = std::fabs(got - ref);
        CHECK(std::isfinite(got));
        CHECK(std::fabs(got) <= 0.5 + 1e-12);
        CHECK(err < 1e-3);
        max_err = std::max(max_err, err);
        sum_err += err;
        ++n;
        if (std::fabs(ref) > 1e-3) ++nonzero;
    }
    MESSAGE("coverage vs quadrature (8192 angles): configs " << n << ", non-zero " << nonzero
            << ", max |err| " << max_err << ", mean " << sum_err / n);
    CHECK(nonzero > n / 3); // the generator produces real penumbra configurations
}

TEST_CASE("coverage: stratified area Monte Carlo of the edge-meets-triangle(p, c, x) definition") {
    Rng rng(777);
    double max_err = 0.0;
    int n = 0;
    for (int it = 0; it < 40; ++it) {
        const dvec3 c = rng.box(2.0);
        const double r = rng.u(0.1, 1.2);
        const dvec3 p = c + rng.dir() * rng.u(3.0, 8.0);
        const double f = rng.u(0.1, 0.9);
        const dvec3 m = p + f * (c - p) + rng.box(r * f);
        const dvec3 t = rng.dir() * rng.u(0.1, 3.0);
        const glm::vec3 fe0 = F(m - 0.5 * t), fe1 = F(m + t), fc = F(c), fp = F(p);
        const float fr = static_cast<float>(r);
        const double got = cov(fe0, fe1, SL(fc, fr), fp);
        const double ref = coverage_montecarlo(D(fe0), D(fe1), D(fc), static_cast<double>(fr), D(fp), 256, rng);
        CHECK(std::fabs(got - ref) < 1e-3);
        max_err = std::max(max_err, std::fabs(got - ref));
        ++n;
    }
    MESSAGE("coverage vs stratified MC (65536 samples): configs " << n << ", max |err| " << max_err);
}

TEST_CASE("wedge contains the swept penumbra of its edge, and every point with non-zero coverage") {
    Rng rng(4242);
    const EdgeKind kinds[] = {EdgeKind::Generic, EdgeKind::NearlyRadial, EdgeKind::Grazing,
                              EdgeKind::CrossingLightPlane, EdgeKind::Short, EdgeKind::Huge};
    const char* names[] = {"generic", "nearly-radial", "grazing", "crossing", "short(1e-6)", "coords 1e6"};
    for (int k = 0; k < 6; ++k) {
        int configs = 0, points = 0, outside = 0, skipped = 0, shapes[4] = {0, 0, 0, 0}, cov_pts = 0, cov_out = 0,
            sign_bad = 0;
        double worst = 0.0;
        for (int it = 0; it < 1500; ++it) {
            dvec3 c, e0, e1;
            double r;
            random_edge(rng, kinds[k], c, r, e0, e1);
            const sk::PenumbraSphereLight L = SL(F(c), static_cast<float>(r));
            const sk::PenumbraWedge w = sk::penumbra_wedge(F(e0), F(e1), L);
            if (!drawn(w)) {
                ++skipped;
                CHECK(w.status == sk::Status::Ok);
                CHECK(w.skip == sk::PenumbraWedgeSkip::RadialEdge);
                continue;
            }
            REQUIRE(wedge_finite(w));
            ++configs;
            ++shapes[static_cast<int>(w.shape)];
            const double scale = std::max({len3(e0), len3(e1), len3(c), 1.0});
            const double tol = 2e-6 * scale; // float storage of the planes
            for (int j = 0; j < 20; ++j) {
                const dvec3 x = swept_point(rng, e0, e1, c, r, j < 10 ? 1.0 : 20.0);
                ++points;
                const double mg = plane_margin(w, x);
                if (mg < -tol) {
                    ++outside;
                    worst = std::min(worst, mg / scale);
                }
            }
            if (kinds[k] == EdgeKind::Huge) continue;
            // coverage != 0  =>  inside the wedge, and its sign says which half-wedge
            for (int j = 0; j < 20; ++j) {
                const dvec3 x = swept_point(rng, e0, e1, c, r * 1.3, 6.0) + rng.box(0.2);
                const double cv = cov(F(e0), F(e1), L, F(x));
                if (std::fabs(cv) < 1e-9) continue;
                ++cov_pts;
                const dvec3 xq = D(F(x));
                if (plane_margin(w, xq) < -tol) ++cov_out;
                const double hp = w.hard_plane.x * xq.x + w.hard_plane.y * xq.y + w.hard_plane.z * xq.z + static_cast<double>(w.hard_plane.w);
                if (std::fabs(hp) > tol && (hp > 0.0) != (cv > 0.0)) ++sign_bad;
            }
        }
        MESSAGE(std::string(names[k]) << ": wedges " << configs << " (equidistant " << shapes[0] << ", original "
                         << shapes[1] << ", cone " << shapes[2] << ", half-space " << shapes[3] << "), skipped " << skipped << ", swept points "
                         << points << " outside " << outside << " (worst " << worst << " x scale), coverage!=0 points "
                         << cov_pts << " outside " << cov_out << ", sign mismatches " << sign_bad);
        CHECK(outside == 0);
        CHECK(cov_out == 0);
        CHECK(sign_bad == 0);
        CHECK(configs > 1000);
    }
}

namespace {
struct OccluderStats {
    int points = 0, penumbra = 0, penumbra_outside = 0, outside_all = 0, outside_all_mixed = 0, unexplained = 0;
    double max_missed = 0.0, max_err = 0.0, sum_err = 0.0;
    std::vector<double> errs;
};

void run_occluders(int kind, int configs, int pts_per, int samples, unsigned seed, OccluderStats& st) {
    Rng rng(seed);
    for (int it = 0; it < configs; ++it) {
        const dvec3 oc = rng.box(1.0);
        const double size = rng.u(0.4, 1.2);
        const dvec3 ldir = rng.dir();
        const double ldist = rng.u(2.5, 6.0);
        const dvec3 c = oc + ldist * ldir;
        const double r = rng.u(0.1, 1.0) * std::min(1.5, ldist - 1.5 * size);
        Poly P = kind == 0 ? make_box(rng, oc, size * 0.6) : kind == 1 ? make_icosphere(rng, oc, size) : make_polygon(rng, oc, size, c);
        // light must be outside the occluder's bounding sphere
        double rad = 0.0;
        for (auto& v : P.v) rad = std::max(rad, len3(v - oc));
        if (len3(c - oc) < rad + r + 0.05) continue;
        const sk::PenumbraSphereLight L = SL(F(c), static_cast<float>(r));
        const dvec3 cq = D(ctr(L));
        const double rq = static_cast<double>(L.radius);
        for (auto& v : P.v) v = D(F(v));
        const std::vector<glm::vec3> sil = silhouette(P, cq);
        std::vector<sk::PenumbraWedge> wedges;
        for (size_t i = 0; i + 1 < sil.size(); i += 2) {
            const sk::PenumbraWedge w = sk::penumbra_wedge(sil[i], sil[i + 1], L);
            REQUIRE((drawn(w) || w.skip == sk::PenumbraWedgeSkip::RadialEdge));
            if (drawn(w)) wedges.push_back(w);
        }
        for (int j = 0; j < pts_per; ++j) {
            // receivers behind the occluder, spread across umbra, penumbra and lit region
            const dvec3 back = oc + (oc - cq) * rng.u(0.2, 2.0);
            const dvec3 p = D(F(back + rng.box(size * 2.0)));
            bool inside_occ = true; // skip points inside a closed occluder
            if (!P.planar) {
                for (auto& t : P.tri) {
                    const dvec3 a = P.v[static_cast<size_t>(t[0])], b = P.v[static_cast<size_t>(t[1])], d = P.v[static_cast<size_t>(t[2])];
                    if (dot3(cross3(b - a, d - a), p - a) > 0.0) { inside_occ = false; break; }
                }
                if (inside_occ) continue;
            }
            if (len3(p - cq) < rq * 1.5) continue;
            int blocked = 0;
            const double vref = visibility_ref(P, cq, rq, p, samples, rng, &blocked);
            const int hard = occluded(P, p, cq) ? 1 : 0;
            const double vest = vis(sil.data(), sil.size() / 2, L, F(p), hard);
            ++st.points;
            const double err = std::fabs(vest - vref);
            st.errs.push_back(err);
            st.max_err = std::max(st.max_err, err);
            st.sum_err += err;
            bool in_any = false;
            for (auto& w : wedges)
                if (sk::penumbra_point_in_wedge(F(p), w, 1e-5f)) { in_any = true; break; }
            const bool mixed = blocked > 0 && blocked < samples * samples;
            if (mixed) {
                ++st.penumbra;
                if (!in_any) {
                    ++st.penumbra_outside;
                    st.max_missed = std::max(st.max_missed, std::min(vref, 1.0 - vref));
                    // explained by the single-silhouette approximation? p must then lie in the wedge of
                    // an edge that is a silhouette edge from some other point of the light
                    bool explained = false;
                    for (auto& t : P.tri)
                        for (int k = 0; k < 3 && !explained; ++k) {
                            const glm::vec3 a = F(P.v[static_cast<size_t>(t[static_cast<size_t>(k)])]);
                            const glm::vec3 b = F(P.v[static_cast<size_t>(t[static_cast<size_t>((k + 1) % 3)])]);
                            const sk::PenumbraWedge we = sk::penumbra_wedge(a, b, L);
                            if (sk::penumbra_point_in_wedge(F(p), we, 1e-5f)) explained = true;
                        }
                    if (!explained) ++st.unexplained;
                }
            }
            if (!in_any) {
                ++st.outside_all;
                if (mixed) ++st.outside_all_mixed;
                // outside every wedge the A&AM estimate is exactly the hard result
                CHECK(vest == static_cast<float>(1 - hard));
            }
        }
    }
    std::sort(st.errs.begin(), st.errs.end());
}
} // namespace

TEST_CASE("planar convex polygons: summed visibility equals brute force, penumbra inside the wedges") {
    OccluderStats st;
    run_occluders(2, 80, 10, 96, 99, st);
    const double p95 = st.errs.empty() ? 0.0 : st.errs[st.errs.size() * 95 / 100];
    MESSAGE("polygons: points " << st.points << ", penumbra " << st.penumbra << ", penumbra outside all wedges "
                                << st.penumbra_outside << ", |V - V_ref| max " << st.max_err << " mean "
                                << st.sum_err / std::max(1, st.points) << " p95 " << p95);
    CHECK(st.points > 600);
    CHECK(st.penumbra > 200);
    CHECK(st.penumbra_outside == 0);
    CHECK(st.max_err < 5e-3); // 96^2 stratified samples
}

TEST_CASE("convex boxes and icospheres: wedge containment of the brute-force penumbra; summed visibility error") {
    for (int kind = 0; kind < 2; ++kind) {
        OccluderStats st;
        run_occluders(kind, kind == 0 ? 120 : 50, 10, 32, kind == 0 ? 5u : 6u, st);
        const double p95 = st.errs.empty() ? 0.0 : st.errs[st.errs.size() * 95 / 100];
        MESSAGE(std::string(kind == 0 ? "boxes" : "icospheres")
                << ": points " << st.points << ", penumbra (0<V_ref<1) " << st.penumbra
                << ", penumbra outside all wedges " << st.penumbra_outside << " (largest min(V,1-V) there "
                << st.max_missed << "; inside the wedge of a non-centre-silhouette edge: "
                << st.penumbra_outside - st.unexplained << "), |V - V_ref| max " << st.max_err << " mean "
                << st.sum_err / std::max(1, st.points) << " p95 " << p95);
        CHECK(st.points > 300);
        CHECK(st.penumbra > 100);
        // Every miss must be the single-silhouette approximation (the point lies in the wedge of an edge
        // that is a silhouette edge from another light point, not from the centre); misses are rare.
        CHECK(st.unexplained == 0);
        CHECK(st.penumbra_outside <= st.penumbra / 50);
        CHECK(st.max_missed < 0.2); // regression bound; measured 0.12 (boxes), 0 (icospheres)
        CHECK(st.sum_err / std::max(1, st.points) < 0.02);
    }
}

TEST_CASE("stiff: light radius 0 reduces to the hard shadow volume exactly") {
    Rng rng(31);
    int n = 0;
    for (int it = 0; it < 2000; ++it) {
        dvec3 c, e0, e1;
        double r;
        random_edge(rng, EdgeKind::Generic, c, r, e0, e1);
        const sk::PenumbraSphereLight L = SL(F(c), 0.0f);
        const sk::PenumbraWedge w = sk::penumbra_wedge(F(e0), F(e1), L);
        REQUIRE(drawn(w));
        REQUIRE(wedge_finite(w));
        // front and back planes are the hard plane, with opposite orientations
        const dvec3 nh = D(glm::vec3(w.hard_plane));
        CHECK(std::fabs(len3(nh) - 1.0) < 1e-6);
        CHECK(len3(D(glm::vec3(w.outer_bound)) + D(glm::vec3(w.inner_bound))) < 1e-6);
        CHECK(std::fabs(std::fabs(dot3(D(glm::vec3(w.outer_bound)), nh)) - 1.0) < 1e-6);
        // as the header says: inner_bound = -outer_bound = the hard plane (issue 13: the comment had
        // the signs the other way round; the composition test reads the planes by that comment)
        CHECK(dot3(D(glm::vec3(w.inner_bound)), nh) > 1.0 - 1e-6);
        CHECK(dot3(D(glm::vec3(w.outer_bound)), nh) < -1.0 + 1e-6);
        const double scale = std::max({len3(e0), len3(e1), len3(c), 1.0});
        CHECK(std::fabs(w.outer_bound.w + w.inner_bound.w) < 1e-5 * scale);
        // points off the hard plane are outside; coverage is exactly 0; visibility = 1 - hard
        for (int j = 0; j < 10; ++j) {
            const dvec3 p = rng.box(6.0);
            const double hp = dot3(nh, p) + static_cast<double>(w.hard_plane.w);
            if (std::fabs(hp) > 1e-3) CHECK_FALSE(sk::penumbra_point_in_wedge(F(p), w));
            CHECK(cov(F(e0), F(e1), L, F(p)) == 0.0f);
            const glm::vec3 ends[2] = {F(e0), F(e1)};
            CHECK(vis(ends, 1, L, F(p), 1) == 0.0f);
            CHECK(vis(ends, 1, L, F(p), 0) == 1.0f);
        }
        // the hard shadow quad (edge points pushed away from c) lies in the degenerate wedge
        for (int j = 0; j < 5; ++j) {
            const dvec3 q = e0 + rng.u() * (e1 - e0);
            const dvec3 x = q + rng.u(0.0, 5.0) * (q - c);
            CHECK(plane_margin(w, x) > -1e-5 * scale);
        }
        ++n;
    }
    CHECK(n == 2000);
}

TEST_CASE("stiff: receiver exactly on a wedge plane; hard-plane jump is compensated by the hard count") {
    Rng rng(55);
    int checked = 0;
    for (int it = 0; it < 500; ++it) {
        dvec3 c, e0, e1;
        double r;
        random_edge(rng, EdgeKind::Generic, c, r, e0, e1);
        const sk::PenumbraSphereLight L = SL(F(c), static_cast<float>(r));
        const sk::PenumbraWedge w = sk::penumbra_wedge(F(e0), F(e1), L);
        if (!drawn(w) || w.shape != sk::PenumbraWedgeShape::Equidistant) continue;
        // points on the outer / inner bound planes between the side planes: the projected edge line is
        // tangent to the disk there, so the coverage is 0 (continuous with the outside)
        for (int j = 0; j < 4; ++j) {
            const double s = rng.u(0.5, 5.0), a = rng.u(0.1, 0.9);
            const int i = j & 1;
            const dvec3 ray0 = D(i ? w.ray_inner[0] : w.ray_outer[0]), ray1 = D(i ? w.ray_inner[1] : w.ray_outer[1]);
            const dvec3 x = (1.0 - a) * (D(w.apex[0]) + s * ray0) + a * (D(w.apex[1]) + s * ray1);
            const double cv = cov(F(e0), F(e1), L, F(x));
            CHECK(std::isfinite(cv));
            // the apex edge lies in the plane through x: its projected line is tangent to the disk
            CHECK(std::fabs(cov(w.apex[0], w.apex[1], L, F(x))) < 1e-4f);
            CHECK(std::fabs(cv) <= 0.5f);
            CHECK(sk::penumbra_point_in_wedge(F(x), w, 1e-4f * static_cast<float>(std::max(1.0, len3(x)))));
            ++checked;
        }
        // across the hard plane: coverage jumps by ~1 and hard count by 1, visibility is continuous
        const dvec3 q = e0 + 0.5 * (e1 - e0);
        const dvec3 on = q + rng.u(0.5, 3.0) * (q - c);
        const dvec3 nh = D(glm::vec3(w.hard_plane));
        const dvec3 po = on + 1e-4 * nh, pi = on - 1e-4 * nh;
        const double co = cov(F(e0), F(e1), L, F(po));
        const double ci = cov(F(e0), F(e1), L, F(pi));
        CHECK(co >= 0.0);
        CHECK(ci <= 0.0);
        CHECK(std::fabs((0.0 + co) - (1.0 + ci)) < 0.02); // 0 + outside vs 1 + inside
        // exactly on the plane (as far as floats allow): finite, within [-1/2, 1/2]
        const double con = cov(F(e0), F(e1), L, F(on));
        CHECK(std::isfinite(con));
        CHECK(std::fabs(con) <= 0.5);
    }
    CHECK(checked > 100);
}

TEST_CASE("stiff: degenerate input gives documented statuses, never NaN") {
    const sk::PenumbraSphereLight L = SL(glm::vec3(0.0f), 1.0f);
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    // Issue 13: edges to skip are not errors: Ok with a skip reason (they were error statuses).
    auto skip_of = [&](glm::vec3 a, glm::vec3 b) {
        const sk::PenumbraWedge w = sk::penumbra_wedge(a, b, L);
        CHECK(w.status == sk::Status::Ok);
        return w.skip;
    };
    CHECK(skip_of(glm::vec3(5, 0, 0), glm::vec3(5, 0, 0)) == sk::PenumbraWedgeSkip::DegenerateEdge);
    CHECK(skip_of(glm::vec3(2, 0, 0), glm::vec3(5, 0, 0)) == sk::PenumbraWedgeSkip::RadialEdge);
    CHECK(skip_of(glm::vec3(0.5f, 0, 0), glm::vec3(5, 1, 0)) == sk::PenumbraWedgeSkip::EdgeTouchesLight);
    CHECK(skip_of(glm::vec3(-5, 0.5f, 0), glm::vec3(5, 0.5f, 0)) == sk::PenumbraWedgeSkip::EdgeTouchesLight);
    CHECK(skip_of(glm::vec3(3, 0, 0), glm::vec3(5, 1, 0)) == sk::PenumbraWedgeSkip::None);
    CHECK(sk::penumbra_wedge(glm::vec3(nan, 0, 0), glm::vec3(5, 1, 0), L).status == sk::Status::NonFinite);
    CHECK(sk::penumbra_wedge(glm::vec3(inf, 0, 0), glm::vec3(5, 1, 0), L).status == sk::Status::NonFinite);
    CHECK(sk::penumbra_wedge(glm::vec3(3, 0, 0), glm::vec3(5, 1, 0), SL(glm::vec3(0.0f), -1.0f)).status ==
          sk::Status::InvalidArgument);
    CHECK(sk::penumbra_wedge(glm::vec3(3, 0, 0), glm::vec3(5, 1, 0), SL(glm::vec3(0.0f), nan)).status ==
          sk::Status::NonFinite);
    CHECK(sk::penumbra_wedge(glm::vec3(3, 0, 0), glm::vec3(5, 1, 0), L, -1.0f).status == sk::Status::InvalidArgument);
    CHECK(sk::penumbra_wedge(glm::vec3(3, 0, 0), glm::vec3(5, 1, 0), L, nan).status == sk::Status::NonFinite);
    // lights: the default light, w = 0 (a directional disk light, not supported), w < 0, NaN
    CHECK(sk::penumbra_wedge(glm::vec3(3, 0, 0), glm::vec3(5, 1, 0), sk::PenumbraSphereLight{}).status == sk::Status::InvalidLight);
    sk::PenumbraSphereLight bad = L;
    bad.light_position = glm::vec4(0, 1, 0, 0);
    CHECK(sk::penumbra_wedge(glm::vec3(3, 0, 0), glm::vec3(5, 1, 0), bad).status == sk::Status::InvalidLight);
    CHECK(sk::penumbra_edge_coverage(glm::vec3(3, 0, 0), glm::vec3(5, 1, 0), bad, glm::vec3(9)).status == sk::Status::InvalidLight);
    bad.light_position = glm::vec4(0, 0, 0, -1);
    CHECK(sk::penumbra_wedge(glm::vec3(3, 0, 0), glm::vec3(5, 1, 0), bad).status == sk::Status::InvalidLight);
    bad.light_position = glm::vec4(nan, 0, 0, 1);
    CHECK(sk::penumbra_visibility(nullptr, 0, bad, glm::vec3(9), 0).status == sk::Status::InvalidLight);
    // w != 1: the same light
    sk::PenumbraSphereLight w2 = L;
    w2.light_position = glm::vec4(0, 0, 0, 2);
    CHECK(sk::penumbra_edge_coverage(glm::vec3(3, -1, 0.2f), glm::vec3(3, 1, 0.2f), w2, glm::vec3(7, 0, 0.5f)).value ==
          cov(glm::vec3(3, -1, 0.2f), glm::vec3(3, 1, 0.2f), L, glm::vec3(7, 0, 0.5f)));
    // coverage: NaN input is an error (it returned 0 before), p at c or on the edge's line is 0 (Ok)
    CHECK(sk::penumbra_edge_coverage(glm::vec3(nan), glm::vec3(1), L, glm::vec3(5)).status == sk::Status::NonFinite);
    CHECK(cov(glm::vec3(3, 0, 0), glm::vec3(3, 1, 0), L, glm::vec3(0.0f)) == 0.0); // p at c
    // receiver on the edge's line: 0, not NaN
    CHECK(cov(glm::vec3(3, -1, 0), glm::vec3(3, 1, 0), L, glm::vec3(3, 5, 0)) == 0.0);
    // receiver exactly at an endpoint
    CHECK(std::isfinite(cov(glm::vec3(3, -1, 0), glm::vec3(3, 1, 0), L, glm::vec3(3, 1, 0))));
    const sk::PenumbraWedge skip = sk::penumbra_wedge(glm::vec3(5, 0, 0), glm::vec3(5, 0, 0), L);
    CHECK_FALSE(sk::penumbra_point_in_wedge(glm::vec3(6, 0, 0), skip));
    const sk::PenumbraWedgeHull sh = sk::penumbra_wedge_hull(skip, 10.0f);
    CHECK(sh.status == sk::Status::Ok);
    CHECK_FALSE(sh.drawable);
    CHECK(sk::penumbra_wedge_hull(sk::PenumbraWedge{}, 10.0f).status == sk::Status::InvalidArgument);  // never built
    const sk::PenumbraWedge good = sk::penumbra_wedge(glm::vec3(3, 0, 0), glm::vec3(5, 1, 0), L);
    CHECK(sk::penumbra_wedge_hull(good, 0.0f).status == sk::Status::InvalidArgument);
    CHECK(sk::penumbra_wedge_hull(good, nan).status == sk::Status::NonFinite);
    const sk::PenumbraWedgeHull huge = sk::penumbra_wedge_hull(good, std::numeric_limits<float>::max());
    CHECK((huge.status == sk::Status::Overflow || huge.status == sk::Status::Ok));  // never Ok with Inf vertices
    if (huge.status == sk::Status::Ok)
        for (const glm::vec4& v : huge.vertices) CHECK((std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z)));
    glm::vec3 ends[2] = {glm::vec3(3, -1, 0), glm::vec3(3, 1, 0)};
    // issue 19: a null pointer with a count returned visibility 1 (fully lit) with no status
    CHECK(sk::penumbra_visibility(nullptr, 3, L, glm::vec3(5), 0).status == sk::Status::InvalidArgument);
    CHECK(vis(nullptr, 0, L, glm::vec3(5), 0) == 1.0);
    CHECK(vis(ends, 1, L, glm::vec3(5, 0, 0), 7) == 0.0);
    CHECK(vis(ends, 1, L, glm::vec3(5, 0, 0), -7) == 1.0);
    glm::vec3 nan_ends[2] = {glm::vec3(3, -1, 0), glm::vec3(nan)};
    CHECK(sk::penumbra_visibility(nan_ends, 1, L, glm::vec3(5), 0).status == sk::Status::NonFinite);
    // results no call filled
    CHECK(sk::PenumbraWedge{}.status == sk::Status::NotRun);
    CHECK(sk::PenumbraValue{}.status == sk::Status::NotRun);
    CHECK(sk::ScissorRect{}.status == sk::Status::NotRun);
}

TEST_CASE("stiff: fallback shapes - cone for an edge line through the light, original endpoints when grazing") {
    const sk::PenumbraSphereLight L = SL(glm::vec3(0.0f), 1.0f);
    // nearly radial edge: the moved apex edge is tiny and perpendicular to the radius -> still Equidistant
    const sk::PenumbraWedge nr = sk::penumbra_wedge(glm::vec3(2.0f, 0.001f, 0.0f), glm::vec3(6.0f, 0.0f, 0.0f), L);
    REQUIRE(nr.status == sk::Status::Ok);
    CHECK(nr.shape == sk::PenumbraWedgeShape::Equidistant);
    // edge line through the ball, subtending a large angle near the light: the moved line crosses the
    // ball too -> Cone around the near endpoint (1.01, 0, 0)
    const glm::vec3 n0(1.01f, 0.0f, 0.0f), n1 = n0 + 5.0f * glm::vec3(1.01f, -0.9f, 0.0f);
    const sk::PenumbraWedge w = sk::penumbra_wedge(n1, n0, L);
    REQUIRE(drawn(w));
    CHECK(w.shape == sk::PenumbraWedgeShape::Cone);
    CHECK(w.apex[0] == n0);
    CHECK(w.apex[1] == n0);
    REQUIRE(wedge_finite(w));
    // a grazing edge whose moved apex line would cross the ball falls back to the original endpoints
    const sk::PenumbraWedge g = sk::penumbra_wedge(glm::vec3(1.1f, 0.0f, 0.0f), glm::vec3(0.0f, 100.0f, 0.0f), L);
    REQUIRE(g.status == sk::Status::Ok);
    CHECK(g.shape == sk::PenumbraWedgeShape::OriginalEndpoints);
    // both keep the swept penumbra inside
    Rng rng(3);
    for (int j = 0; j < 2000; ++j) {
        CHECK(plane_margin(w, swept_point(rng, D(n1), D(n0), dvec3(0.0), 1.0, 10.0)) > -1e-5);
        CHECK(plane_margin(g, swept_point(rng, dvec3(1.1, 0, 0), dvec3(0, 100, 0), dvec3(0.0), 1.0, 10.0)) > -1e-4);
    }
}

TEST_CASE("hull: inside every plane, outward winding; scissor and depth bounds contain the hull") {
    Rng rng(8080);
    int tested = 0, front_pts = 0;
    for (int it = 0; it < 800; ++it) {
        dvec3 c, e0, e1;
        double r;
        random_edge(rng, it % 3 == 0 ? EdgeKind::NearlyRadial : EdgeKind::Generic, c, r, e0, e1);
        const sk::PenumbraSphereLight L = SL(F(c), static_cast<float>(r));
        const sk::PenumbraWedge w = sk::penumbra_wedge(F(e0), F(e1), L);
        if (!drawn(w)) continue;
        const float extent = static_cast<float>(rng.u(1.0, 10.0));
        const sk::PenumbraWedgeHull h = sk::penumbra_wedge_hull(w, extent);
        REQUIRE(h.status == sk::Status::Ok);
        REQUIRE(h.drawable);
        const double scale = std::max({len3(e0), len3(e1), len3(c), 1.0, static_cast<double>(extent)});
        dvec3 centroid(0.0);
        for (auto& v : h.vertices) {
            CHECK(v.w == 1.0f);
            centroid += D(glm::vec3(v)) / 6.0;
            CHECK(plane_margin(w, D(glm::vec3(v))) > -1e-4 * scale);
        }
        for (int t = 0; t < 8; ++t) {
            const dvec3 a = D(glm::vec3(h.vertices[h.indices[3 * t]])), b = D(glm::vec3(h.vertices[h.indices[3 * t + 1]])),
                        d = D(glm::vec3(h.vertices[h.indices[3 * t + 2]]));
            const dvec3 n = cross3(b - a, d - a);
            if (len3(n) < 1e-9 * scale * scale) continue; // degenerate (cone apex)
            CHECK(dot3(n, (a + b + d) / 3.0 - centroid) > -1e-9 * scale * scale * scale);
        }
        // scissor: random camera looking at the wedge
        const dvec3 target = centroid;
        const dvec3 eye = target + rng.dir() * rng.u(0.5, 3.0) * scale;
        glm::dmat4 view(1.0);
        {
            const dvec3 f = (target - eye) / len3(target - eye);
            dvec3 up = std::fabs(f.y) < 0.9 ? dvec3(0, 1, 0) : dvec3(1, 0, 0);
            dvec3 s = cross3(f, up);
            s /= len3(s);
            const dvec3 u = cross3(s, f);
            view = glm::dmat4(s.x, u.x, -f.x, 0, s.y, u.y, -f.y, 0, s.z, u.z, -f.z, 0, -dot3(s, eye), -dot3(u, eye), dot3(f, eye), 1);
        }
        const double fov = rng.u(0.5, 1.5), nearz = 0.05 * scale, farz = 50.0 * scale;
        const bool zo = (it & 1) != 0, rev = (it & 2) != 0;
        glm::dmat4 proj(0.0);
        const double ft = 1.0 / std::tan(fov / 2.0);
        proj[0][0] = ft;
        proj[1][1] = ft;
        proj[2][3] = -1.0;
        if (!zo) { proj[2][2] = -(farz + nearz) / (farz - nearz); proj[3][2] = -2.0 * farz * nearz / (farz - nearz); }
        else { proj[2][2] = -farz / (farz - nearz); proj[3][2] = -farz * nearz / (farz - nearz); }
        if (rev) { // z' = w - z (ZeroToOne) / -z (GL)
            glm::dmat4 R(1.0);
            if (zo) { R[2][2] = -1.0; R[3][2] = 1.0; } else { R[2][2] = -1.0; }
            proj = R * proj;
        }
        sk::ScissorParams sp;
        sp.view_proj = glm::mat4(proj * view);
        sp.clip_depth = zo ? sk::ClipDepth::ZeroToOne : sk::ClipDepth::NegativeOneToOne;
        sp.reversed_z = rev;
        sp.viewport[0] = 0; sp.viewport[1] = 0; sp.viewport[2] = 640; sp.viewport[3] = 480;
        const sk::ScissorRect s = sk::penumbra_wedge_scissor(h, sp);
        for (int j = 0; j < 60; ++j) {
            // random point of the hull: convex combination of the vertices
            double wsum = 0.0, wts[6];
            for (double& x : wts) { x = -std::log(rng.u(1e-12, 1.0)); wsum += x; }
            dvec3 x(0.0);
            for (int k = 0; k < 6; ++k) x += wts[k] / wsum * D(glm::vec3(h.vertices[k]));
            const glm::dvec4 cl = glm::dmat4(sp.view_proj) * glm::dvec4(x, 1.0);
            const double ndz = cl.z / cl.w;
            const bool in_front = cl.w > 0.0 && (rev ? ndz <= 1.0 : (zo ? ndz >= 0.0 : ndz >= -1.0));
            if (!in_front) continue;
            const double nx = cl.x / cl.w, ny = cl.y / cl.w;
            if (std::fabs(nx) > 1.0 || std::fabs(ny) > 1.0) continue;
            const double wz = zo ? ndz : 0.5 * ndz + 0.5;
            if (wz < 0.0 || wz > 1.0) continue;
            ++front_pts;
            REQUIRE(s.visible);
            const double px = (0.5 * nx + 0.5) * 640.0, py = (0.5 * ny + 0.5) * 480.0;
            CHECK(px >= s.x - 1e-3);
            CHECK(px <= s.x + s.width + 1e-3);
            CHECK(py >= s.y - 1e-3);
            CHECK(py <= s.y + s.height + 1e-3);
            CHECK(wz >= static_cast<double>(s.depth_min) - 1e-6);
            CHECK(wz <= static_cast<double>(s.depth_max) + 1e-6);
        }
        // infinite extent: w = 0 far vertices, same directions as the rays
        const sk::PenumbraWedgeHull hi = sk::penumbra_wedge_hull(w, std::numeric_limits<float>::infinity());
        REQUIRE(hi.drawable);
        CHECK(hi.vertices[2].w == 0.0f);
        CHECK(glm::vec3(hi.vertices[2]) == w.ray_outer[0]);
        ++tested;
    }
    CHECK(tested > 500);
    CHECK(front_pts > 5000);
    // entirely behind the camera: not visible
    {
        const sk::PenumbraSphereLight L = SL(glm::vec3(0, 10, 0), 0.5f);
        const sk::PenumbraWedge w = sk::penumbra_wedge(glm::vec3(-1, 5, 0), glm::vec3(1, 5, 0.2f), L);
        const sk::PenumbraWedgeHull h = sk::penumbra_wedge_hull(w, 3.0f);
        sk::ScissorParams sp;
        glm::mat4 view(1.0f);
        view[3][2] = 100.0f; // camera at z = 100 looking down -z... everything at z ~ 0 is then at view z = 100 > 0: behind
        glm::mat4 proj(0.0f);
        proj[0][0] = proj[1][1] = 1.0f;
        proj[2][2] = -1.0f;
        proj[2][3] = -1.0f;
        proj[3][2] = -0.2f;
        sp.view_proj = proj * view;
        sp.viewport[2] = 100;
        sp.viewport[3] = 100;
        CHECK_FALSE(sk::penumbra_wedge_scissor(h, sp).visible);
    }
}

TEST_CASE("scissor clipped to a box: contains every point of (hull and box), culls hulls outside it, statuses") {
    // Issue 13: the wedge driver had to clip the hull to the receivers' box itself because the header's
    // scissor culled nothing. Reference: random points of the hull (convex combinations of its
    // vertices; for an infinite hull, points along the rays) kept when inside the box, projected
    // independently here; every one must lie in the clipped rectangle and depth bounds.
    Rng rng(4242);
    int tested = 0, pts = 0, culled = 0, tighter = 0;
    for (int it = 0; it < 1500; ++it) {
        dvec3 c, e0, e1;
        double r;
        random_edge(rng, EdgeKind::Generic, c, r, e0, e1);
        const sk::PenumbraSphereLight L = SL(F(c), static_cast<float>(r));
        const sk::PenumbraWedge w = sk::penumbra_wedge(F(e0), F(e1), L);
        if (!drawn(w) || w.shape == sk::PenumbraWedgeShape::HalfSpace) continue;
        const bool infinite = it % 4 == 3;
        const double scale = std::max({len3(e0), len3(e1), len3(c), 1.0});
        const float extent = infinite ? std::numeric_limits<float>::infinity() : static_cast<float>(rng.u(1.0, 10.0) * scale);
        const sk::PenumbraWedgeHull h = sk::penumbra_wedge_hull(w, extent);
        REQUIRE(h.drawable);
        // a random box around some point near the wedge (sometimes far away: culled)
        const dvec3 mid = D(w.apex[0]) + rng.u(0.0, 3.0) * scale * D(w.axis) + rng.box(1.5 * scale);
        const dvec3 half(rng.u(0.05, 1.5) * scale, rng.u(0.05, 1.5) * scale, rng.u(0.05, 1.5) * scale);
        const glm::vec3 lo = F(mid - half), hi = F(mid + half);
        // camera
        const dvec3 target = mid;
        const dvec3 eye = target + rng.dir() * rng.u(2.0, 6.0) * scale;
        const dvec3 f = (target - eye) / len3(target - eye);
        dvec3 up = std::fabs(f.y) < 0.9 ? dvec3(0, 1, 0) : dvec3(1, 0, 0);
        dvec3 sx = cross3(f, up);
        sx /= len3(sx);
        const dvec3 u = cross3(sx, f);
        const glm::dmat4 view(sx.x, u.x, -f.x, 0, sx.y, u.y, -f.y, 0, sx.z, u.z, -f.z, 0, -dot3(sx, eye), -dot3(u, eye), dot3(f, eye), 1);
        const double nearz = 0.05 * scale, farz = 100.0 * scale, ft = 1.0 / std::tan(0.6);
        glm::dmat4 proj(0.0);
        proj[0][0] = ft; proj[1][1] = ft; proj[2][3] = -1.0;
        proj[2][2] = -(farz + nearz) / (farz - nearz); proj[3][2] = -2.0 * farz * nearz / (farz - nearz);
        sk::ScissorParams sp;
        sp.view_proj = glm::mat4(proj * view);
        sp.viewport[2] = 320;
        sp.viewport[3] = 240;
        const sk::ScissorRect sb = sk::penumbra_wedge_scissor_in_box(h, lo, hi, sp);
        REQUIRE(sb.status == sk::Status::Ok);
        const sk::ScissorRect sw = sk::penumbra_wedge_scissor(h, sp);
        REQUIRE(sw.status == sk::Status::Ok);
        ++tested;
        if (!sb.visible) ++culled;
        if (sb.visible && sw.visible && (long(sb.width) * sb.height < long(sw.width) * sw.height || sb.depth_max - sb.depth_min < sw.depth_max - sw.depth_min))
            ++tighter;
        for (int j = 0; j < 200; ++j) {
            dvec3 x;
            if (infinite) {  // apex-edge point + non-negative combination of the four rays
                const double t = rng.u(0.0, 1.0);
                x = (1.0 - t) * D(w.apex[0]) + t * D(w.apex[1]);
                const double kmax = 4.0 * scale;
                x += rng.u(0.0, kmax) * D(t < 0.5 ? w.ray_outer[0] : w.ray_outer[1]) * rng.u(0.0, 1.0);
                x += rng.u(0.0, kmax) * D(t < 0.5 ? w.ray_inner[0] : w.ray_inner[1]) * rng.u(0.0, 1.0);
                if (plane_margin(w, x) < 0.0) continue;  // only points of the wedge
            } else {
                double wsum = 0.0, wts[6];
                for (double& q : wts) { q = std::pow(-std::log(rng.u(1e-12, 1.0)), 3.0); wsum += q; }
                x = dvec3(0.0);
                for (int k = 0; k < 6; ++k) x += wts[k] / wsum * D(glm::vec3(h.vertices[k]));
            }
            if (x.x < lo.x || x.y < lo.y || x.z < lo.z || x.x > hi.x || x.y > hi.y || x.z > hi.z) continue;
            const glm::dvec4 cl = glm::dmat4(sp.view_proj) * glm::dvec4(x, 1.0);
            if (!(cl.w > nearz)) continue;
            const double nx = cl.x / cl.w, ny = cl.y / cl.w, wz = 0.5 * cl.z / cl.w + 0.5;
            if (std::fabs(nx) > 1.0 || std::fabs(ny) > 1.0 || wz < 0.0 || wz > 1.0) continue;
            ++pts;
            REQUIRE(sb.visible);
            const double px = (0.5 * nx + 0.5) * 320.0, py = (0.5 * ny + 0.5) * 240.0;
            CHECK(px >= sb.x - 1e-3);
            CHECK(px <= sb.x + sb.width + 1e-3);
            CHECK(py >= sb.y - 1e-3);
            CHECK(py <= sb.y + sb.height + 1e-3);
            CHECK(wz >= static_cast<double>(sb.depth_min) - 1e-6);
            CHECK(wz <= static_cast<double>(sb.depth_max) + 1e-6);
        }
    }
    MESSAGE("box-clipped scissor: " << tested << " hulls, " << pts << " points of (hull and box) inside, " << culled
                                    << " hulls culled, " << tighter << " rectangles tighter than the unclipped one");
    CHECK(tested > 1000);
    CHECK(pts > 10000);
    CHECK(culled > 50);
    CHECK(tighter > 200);

    // the documented cases
    const sk::PenumbraSphereLight L = SL(glm::vec3(0, 10, 0), 0.5f);
    const sk::PenumbraWedge w = sk::penumbra_wedge(glm::vec3(-1, 5, 0), glm::vec3(1, 5, 0.2f), L);
    const sk::PenumbraWedgeHull h = sk::penumbra_wedge_hull(w, 8.0f);
    sk::ScissorParams sp;
    sp.view_proj = glm::perspective(1.0f, 1.0f, 0.1f, 100.0f) * glm::lookAt(glm::vec3(0, 8, 12), glm::vec3(0), glm::vec3(0, 1, 0));
    sp.viewport[2] = 100;
    sp.viewport[3] = 100;
    // the floor under the edge receives its penumbra: visible
    const sk::ScissorRect on = sk::penumbra_wedge_scissor_in_box(h, glm::vec3(-5, -0.1f, -5), glm::vec3(5, 0, 5), sp);
    CHECK(on.status == sk::Status::Ok);
    CHECK(on.visible);
    // a box beside the light that the wedge (below the edge) never reaches: Ok, not visible
    const sk::ScissorRect off = sk::penumbra_wedge_scissor_in_box(h, glm::vec3(20, 20, 20), glm::vec3(21, 21, 21), sp);
    CHECK(off.status == sk::Status::Ok);
    CHECK_FALSE(off.visible);
    CHECK(sk::penumbra_wedge_scissor(h, sp).visible);  // the unclipped hull is on screen
    // the infinite hull: same answer for both boxes
    const sk::PenumbraWedgeHull hinf = sk::penumbra_wedge_hull(w, std::numeric_limits<float>::infinity());
    CHECK(sk::penumbra_wedge_scissor_in_box(hinf, glm::vec3(-5, -0.1f, -5), glm::vec3(5, 0, 5), sp).visible);
    CHECK_FALSE(sk::penumbra_wedge_scissor_in_box(hinf, glm::vec3(20, 20, 20), glm::vec3(21, 21, 21), sp).visible);
    // a zero viewport (the default ScissorParams) and a zero matrix: InvalidArgument, never Ok
    sk::ScissorParams zero_vp = sp;
    zero_vp.viewport[2] = zero_vp.viewport[3] = 0;
    CHECK(sk::penumbra_wedge_scissor_in_box(h, glm::vec3(-5), glm::vec3(5), zero_vp).status == sk::Status::InvalidArgument);
    CHECK(sk::penumbra_wedge_scissor(h, zero_vp).status == sk::Status::InvalidArgument);
    sk::ScissorParams zero_m = sp;
    zero_m.view_proj = glm::mat4(0.0f);
    CHECK(sk::penumbra_wedge_scissor_in_box(h, glm::vec3(-5), glm::vec3(5), zero_m).status == sk::Status::InvalidArgument);
    CHECK(sk::penumbra_points_scissor(h.vertices, 6, sk::ScissorParams{}).status == sk::Status::InvalidArgument);
    // box and point errors
    CHECK(sk::penumbra_wedge_scissor_in_box(h, glm::vec3(1), glm::vec3(-1), sp).status == sk::Status::InvalidArgument);
    CHECK(sk::penumbra_wedge_scissor_in_box(h, glm::vec3(std::nanf("")), glm::vec3(1), sp).status == sk::Status::NonFinite);
    CHECK(sk::penumbra_points_scissor(nullptr, 3, sp).status == sk::Status::InvalidArgument);
    const glm::vec4 neg_w[1] = {glm::vec4(0, 0, 0, -1)};
    CHECK(sk::penumbra_points_scissor(neg_w, 1, sp).status == sk::Status::InvalidArgument);
    const sk::ScissorRect none = sk::penumbra_points_scissor(nullptr, 0, sp);
    CHECK(none.status == sk::Status::Ok);
    CHECK_FALSE(none.visible);
    CHECK(sk::penumbra_wedge_scissor_in_box(sk::PenumbraWedgeHull{}, glm::vec3(-1), glm::vec3(1), sp).status ==
          sk::Status::InvalidArgument);
}

TEST_CASE("plane transform: inverse transpose keeps plane values (affine) and signs (projective, w > 0)") {
    Rng rng(2024);
    for (int it = 0; it < 500; ++it) {
        glm::dmat4 M(2.0); // well conditioned: 2 I + perturbation
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 4; ++j) M[j][i] += rng.u(-1.0, 1.0);
        const bool projective = it % 2 == 1;
        if (projective)
            for (int j = 0; j < 4; ++j) M[j][3] = rng.u(-0.5, 0.5) + (j == 3 ? 2.0 : 0.0);
        const glm::vec4 pl(F(rng.dir()), static_cast<float>(rng.u(-3.0, 3.0)));
        const sk::PenumbraPlane tr = sk::penumbra_transform_plane(pl, glm::mat4(M));
        if (tr.status != sk::Status::Ok) continue;
        const glm::vec4 tp = tr.plane;
        for (int j = 0; j < 10; ++j) {
            const glm::dvec4 X(rng.box(3.0), 1.0);
            const glm::dvec4 Y = M * X;
            const double v0 = pl.x * X.x + pl.y * X.y + pl.z * X.z + pl.w;
            const double v1 = tp.x * Y.x + tp.y * Y.y + tp.z * Y.z + tp.w * Y.w;
            const double mag = std::fabs(tp.x * Y.x) + std::fabs(tp.y * Y.y) + std::fabs(tp.z * Y.z) + std::fabs(tp.w * Y.w);
            CHECK(std::fabs(v1 - v0) <= 1e-6 * mag + 1e-9); // float storage of the transformed plane
            if (projective && Y.w > 0.0 && std::fabs(v0) > 1e-3) {
                const glm::dvec4 V = Y / Y.w; // viewport-space point (x, y, z, 1)
                const double v2 = tp.x * V.x + tp.y * V.y + tp.z * V.z + tp.w;
                CHECK((v2 > 0.0) == (v0 > 0.0));
            }
        }
    }
    // issue 19: a singular matrix returned the zero plane with no status
    CHECK(sk::penumbra_transform_plane(glm::vec4(1, 0, 0, 0), glm::mat4(0.0f)).status == sk::Status::InvalidArgument);
    CHECK(sk::penumbra_transform_plane(glm::vec4(std::nanf(""), 0, 0, 0), glm::mat4(1.0f)).status == sk::Status::NonFinite);
    // viewport transform maps NDC corners to pixels and depth to [0, 1]
    const int vp[4] = {10, 20, 640, 480};
    const sk::PenumbraMatrix VM = sk::penumbra_viewport_transform(vp, sk::ClipDepth::NegativeOneToOne);
    REQUIRE(VM.status == sk::Status::Ok);
    const glm::mat4 V = VM.matrix;
    const glm::vec4 a = V * glm::vec4(-1, -1, -1, 1), b = V * glm::vec4(1, 1, 1, 1);
    CHECK(a == glm::vec4(10, 20, 0, 1));
    CHECK(b == glm::vec4(650, 500, 1, 1));
    const int vp2[4] = {0, 0, 2, 2};
    const glm::mat4 V2 = sk::penumbra_viewport_transform(vp2, sk::ClipDepth::ZeroToOne).matrix;
    CHECK((V2 * glm::vec4(0, 0, 0.25f, 1)).z == 0.25f);
    const int zero[4] = {0, 0, 0, 0};
    CHECK(sk::penumbra_viewport_transform(zero, sk::ClipDepth::ZeroToOne).status == sk::Status::InvalidArgument);
    CHECK(sk::penumbra_viewport_transform(nullptr, sk::ClipDepth::ZeroToOne).status == sk::Status::InvalidArgument);
}

TEST_CASE("rectangular light: circumscribed sphere contains the rectangle; wedges stay conservative") {
    Rng rng(606);
    for (int it = 0; it < 300; ++it) {
        const dvec3 cc = rng.box(2.0), hu = rng.box(1.0), hv = rng.box(1.0);
        const sk::PenumbraBoundingSphere B = sk::penumbra_rect_bounding_sphere(glm::vec4(F(cc), 1.0f), F(hu), F(hv));
        REQUIRE(B.status == sk::Status::Ok);
        const sk::PenumbraSphereLight& L = B.light;
        for (int k = 0; k < 4; ++k) {
            const dvec3 corner = D(F(cc)) + ((k & 1) ? 1.0 : -1.0) * D(F(hu)) + ((k & 2) ? 1.0 : -1.0) * D(F(hv));
            CHECK(len3(corner - D(ctr(L))) <= static_cast<double>(L.radius));
        }
    }
    CHECK(sk::penumbra_rect_bounding_sphere(glm::vec4(0, 1, 0, 0), glm::vec3(1, 0, 0), glm::vec3(0, 0, 1)).status ==
          sk::Status::InvalidLight);
    CHECK(sk::penumbra_rect_bounding_sphere(glm::vec4(0, 1, 0, 1), glm::vec3(std::nanf(""), 0, 0), glm::vec3(0, 0, 1)).status ==
          sk::Status::NonFinite);
    CHECK(sk::penumbra_rect_bounding_sphere(glm::vec4(0, 1, 0, 1), glm::vec3(3e38f, 0, 0), glm::vec3(0, 0, 3e38f)).status ==
          sk::Status::Overflow);
}

TEST_CASE("depth bounds: fragments a wedge pass shades on a floor scene, with and without bounds") {
    // Box on a floor under a sphere light; camera above looking down at 45 degrees. For each wedge:
    // fragments of the hull's front faces (pixel rays hitting the hull), those whose stored floor depth
    // passes the depth-bounds test, and those whose floor point lies in the wedge (useful work).
    Rng rng(1);
    Poly box = make_box(rng, dvec3(0, 1.0, 0), 0.7);
    const dvec3 c(1.5, 6.0, 0.5);
    const sk::PenumbraSphereLight L = SL(F(c), 0.8f);
    for (auto& v : box.v) v = D(F(v));
    const std::vector<glm::vec3> sil = silhouette(box, c);
    const dvec3 eye(0.0, 9.0, 9.0), target(0.0, 0.0, 0.0);
    const dvec3 f = (target - eye) / len3(target - eye);
    dvec3 s = cross3(f, dvec3(0, 1, 0));
    s /= len3(s);
    const dvec3 u = cross3(s, f);
    const glm::dmat4 view(s.x, u.x, -f.x, 0, s.y, u.y, -f.y, 0, s.z, u.z, -f.z, 0, -dot3(s, eye), -dot3(u, eye), dot3(f, eye), 1);
    const double nearz = 0.1, farz = 100.0, ft = 1.0 / std::tan(0.5);
    glm::dmat4 proj(0.0);
    proj[0][0] = ft; proj[1][1] = ft; proj[2][3] = -1.0;
    proj[2][2] = -(farz + nearz) / (farz - nearz); proj[3][2] = -2.0 * farz * nearz / (farz - nearz);
    const glm::dmat4 VP = proj * view;
    const int W = 160, H = 160;
    sk::ScissorParams sp;
    sp.view_proj = glm::mat4(VP);
    sp.viewport[2] = W;
    sp.viewport[3] = H;
    long frag = 0, frag_db = 0, useful = 0, scissor_area = 0, frag_box = 0, box_area = 0, culled = 0;
    // the receivers' bounds: the floor (|x|, |z| <= 8 at y = 0) and the box on it
    const glm::vec3 rlo(-8.0f, 0.0f, -8.0f), rhi(8.0f, 2.0f, 8.0f);
    for (size_t e = 0; e + 1 < sil.size(); e += 2) {
        const sk::PenumbraWedge w = sk::penumbra_wedge(sil[e], sil[e + 1], L);
        if (!drawn(w)) continue;
        const float extent = 8.0f;
        const sk::PenumbraWedgeHull h = sk::penumbra_wedge_hull(w, extent);
        const sk::ScissorRect sc = sk::penumbra_wedge_scissor(h, sp);
        if (!sc.visible) continue;
        scissor_area += static_cast<long>(sc.width) * sc.height;
        const sk::ScissorRect sb = sk::penumbra_wedge_scissor_in_box(h, rlo, rhi, sp);
        REQUIRE(sb.status == sk::Status::Ok);
        if (sb.visible) box_area += static_cast<long>(sb.width) * sb.height;
        else ++culled;
        // hull as planes (outward triangle normals) for a Cyrus-Beck pixel-ray test
        std::vector<std::pair<dvec3, double>> hp; // inside: dot(n, x) <= d
        for (int t = 0; t < 8; ++t) {
            const dvec3 a = D(glm::vec3(h.vertices[h.indices[3 * t]])), b = D(glm::vec3(h.vertices[h.indices[3 * t + 1]])),
                        d = D(glm::vec3(h.vertices[h.indices[3 * t + 2]]));
            const dvec3 n = cross3(b - a, d - a);
            if (len3(n) < 1e-12) continue;
            hp.emplace_back(n / len3(n), dot3(n / len3(n), a));
        }
        for (int py = 0; py < H; ++py)
            for (int px = 0; px < W; ++px) {
                const double nx = (px + 0.5) / W * 2.0 - 1.0, ny = (py + 0.5) / H * 2.0 - 1.0;
                const dvec3 dir = glm::normalize(nx / ft * s + ny / ft * u + f);
                if (dir.y >= 0.0) continue;
                const double tf = -eye.y / dir.y; // floor y = 0
                const dvec3 fp = eye + tf * dir;
                // Cyrus-Beck: does the pixel ray meet the hull (planes + cap)?
                double t0 = nearz, t1 = 1e30;
                bool hit = true;
                for (size_t k = 0; k < hp.size() && hit; ++k) {
                    const double num = hp[k].second - dot3(hp[k].first, eye), den = dot3(hp[k].first, dir); // den t <= num
                    if (den == 0.0) { if (num < 0.0) hit = false; continue; }
                    const double t = num / den;
                    if (den > 0.0) t1 = std::min(t1, t); else t0 = std::max(t0, t);
                    if (t0 > t1) hit = false;
                }
                if (!hit) continue;
                ++frag;
                const glm::dvec4 cl = VP * glm::dvec4(fp, 1.0);
                const double wz = 0.5 * cl.z / cl.w + 0.5;
                CHECK(px >= sc.x);
                CHECK(px < sc.x + sc.width);
                if (wz >= sc.depth_min && wz <= sc.depth_max) ++frag_db;
                const bool in_box_rect = sb.visible && px >= sb.x && px < sb.x + sb.width && py >= sb.y &&
                                         py < sb.y + sb.height && wz >= sb.depth_min && wz <= sb.depth_max;
                if (in_box_rect) ++frag_box;
                if (sk::penumbra_point_in_wedge(F(fp), w)) {
                    ++useful;
                    CHECK((wz >= sc.depth_min && wz <= sc.depth_max)); // the bounds never reject useful work
                    // the floor point inside the hull (and in the receivers' box): the clipped
                    // rectangle and bounds keep it too
                    bool in_hull = true;
                    for (const auto& pl : hp) in_hull = in_hull && dot3(pl.first, fp) <= pl.second + 1e-9 * 10.0;
                    if (in_hull) CHECK(in_box_rect);
                }
            }
    }
    MESSAGE("floor scene " << W << "x" << H << ", " << sil.size() / 2 << " wedges: hull fragments " << frag
                           << ", after depth bounds " << frag_db << " (" << 100.0 * (1.0 - double(frag_db) / double(std::max(1L, frag)))
                           << "% rejected), useful (receiver in wedge) " << useful << ", scissor area " << scissor_area
                           << "; clipped to the receivers' box: area " << box_area << ", fragments in rect and bounds "
                           << frag_box << ", wedges culled " << culled);
    CHECK(box_area < scissor_area);
    CHECK(frag_box < frag_db);
    CHECK(frag > 0);
    CHECK(useful > 0);
    CHECK(frag_db <= frag);
    CHECK(frag_db >= useful);
}

TEST_CASE("hard plane of a very short edge far from the light passes through the edge (fuzz regression)") {
    // Found by fuzz_penumbra_wedge: cross(e0 - c, e1 - c) cancels when |e1 - e0| << |e0 - c|; the
    // plane then missed e0 by up to 5.7 units. The plane through c, e0, e1 must contain all three
    // (to rounding of their size), whenever the wedge is built.
    const sk::PenumbraSphereLight light = SL({8.f, 92.f, -84.f}, 0.5f);
    for (float len : {1e-3f, 1e-6f, 1e-9f, 1e-12f}) {
        const glm::vec3 e0(1.8e-3f, 0.f, 0.f), e1 = e0 + glm::vec3(0.f, 0.f, len);
        const sk::PenumbraWedge w = sk::penumbra_wedge(e0, e1, light);
        if (!drawn(w)) continue;
        const double scale = 125.0;  // |c|
        for (const glm::vec3& q : {e0, e1, ctr(light)}) CHECK(std::abs(plane_eval(w.hard_plane, q)) <= 1e-6 * scale);
    }
}
