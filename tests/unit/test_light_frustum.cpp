// Unit and property tests for shadowkit/light_frustum.hpp.
// Expected values: closed form (frustum corners, light directions), brute force (ray casting for
// culling, point sampling for containment), independent recomputation (texel snapping).
#include <shadowkit/infinite_projection.hpp>
#include <shadowkit/light_frustum.hpp>
#include <shadowkit/shadow_cache.hpp>  // issue 18: what the world-fixed depth range is for

#include <doctest/doctest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <limits>
#include <random>
#include <string>
#include <vector>

using namespace shadowkit;

namespace {

constexpr double kPi = 3.14159265358979323846;

struct Cam {
    glm::mat4 view, proj;
    ClipDepth cd;
    bool rev;
    float nearp, farp, maxd;
    float fovy, aspect;
    glm::vec3 pos, fwd;
};

// GL/ZO, optionally reversed-Z and/or infinite perspective, built from closed form.
glm::mat4 make_proj(float fovy, float aspect, float n, float f, ClipDepth cd, bool rev, bool inf) {
    const float t = 1.0f / std::tan(fovy * 0.5f);
    glm::mat4 m(0.0f);
    m[0][0] = t / aspect;
    m[1][1] = t;
    m[2][3] = -1.0f;
    // view depth z (negative) -> ndc. GL: near -1 far 1. ZO: near 0 far 1. Reversed swaps.
    double a, b;  // z_clip = a z + b, w = -z
    double zn, zf;
    if (cd == ClipDepth::ZeroToOne) { zn = rev ? 1 : 0; zf = rev ? 0 : 1; }
    else { zn = rev ? 1 : -1; zf = rev ? -1 : 1; }
    if (inf) {
        // ndc(d) = zf + (zn - zf) n / d  ->  z_clip = -zf z + (zn - zf) n
        a = -zf;
        b = (zn - zf) * n;
    } else {
        // ndc(d) = A + B/d with ndc(n)=zn, ndc(f)=zf
        const double B = (zn - zf) * double(n) * f / (double(f) - n);
        const double A = zf - B / f;
        a = -A;
        b = B;
    }
    m[2][2] = float(a);
    m[3][2] = float(b);
    return m;
}

glm::mat4 look(const glm::vec3& p, const glm::vec3& f) {
    return glm::lookAt(p, p + f, std::fabs(f.y) > 0.99f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0));
}

Cam random_camera(std::mt19937& rng, bool allow_inf = true, float coord_scale = 50.0f) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    Cam c;
    c.pos = glm::vec3(u(rng) - 0.5f, u(rng) * 0.5f, u(rng) - 0.5f) * coord_scale;
    const float yaw = u(rng) * 6.2831853f, pitch = (u(rng) - 0.5f) * 3.0f;
    c.fwd = glm::vec3(std::cos(pitch) * std::cos(yaw), std::sin(pitch), std::cos(pitch) * std::sin(yaw));
    c.view = look(c.pos, c.fwd);
    c.cd = (rng() & 1) ? ClipDepth::ZeroToOne : ClipDepth::NegativeOneToOne;
    c.rev = (rng() & 2) != 0;
    c.nearp = 0.05f + u(rng) * 2.0f;
    c.farp = c.nearp * (5.0f + u(rng) * 200.0f);
    const bool inf = allow_inf && (rng() % 4 == 0);
    c.maxd = inf ? c.farp : 0.0f;
    c.fovy = 0.4f + u(rng) * 1.4f;
    c.aspect = 0.5f + u(rng) * 1.5f;
    c.proj = make_proj(c.fovy, c.aspect, c.nearp, c.farp, c.cd, c.rev, inf);
    return c;
}

void set_camera(LightFrustumInput& in, const Cam& c) {
    in.camera_view = c.view;
    in.camera_proj = c.proj;
    in.camera_depth = c.cd;
    in.camera_reversed_z = c.rev;
    in.max_distance = c.maxd;
}

glm::vec3 random_dir(std::mt19937& rng) {
    std::normal_distribution<float> g(0.0f, 1.0f);
    glm::vec3 d;
    do { d = glm::vec3(g(rng), g(rng), g(rng)); } while (glm::length(d) < 1e-3f);
    return glm::normalize(d);
}

glm::dvec3 lerp3(const glm::vec3 c[8], double u, double v, double t) {
    auto bil = [&](int o) {
        const glm::dvec3 a = glm::mix(glm::dvec3(c[o + 0]), glm::dvec3(c[o + 1]), u);
        const glm::dvec3 b = glm::mix(glm::dvec3(c[o + 2]), glm::dvec3(c[o + 3]), u);
        return glm::mix(a, b, v);
    };
    return glm::mix(bil(0), bil(4), t);
}

bool in_box(const glm::dvec3& p, const glm::vec3& mn, const glm::vec3& mx, double tol) {
    return p.x >= mn.x - tol && p.y >= mn.y - tol && p.z >= mn.z - tol && p.x <= mx.x + tol && p.y <= mx.y + tol &&
           p.z <= mx.z + tol;
}

// Inside the light clip volume (relative tolerance), for the given convention.
bool in_clip(const glm::mat4& m, const glm::dvec3& p, ClipDepth cd, double tol = 1e-4) {
    const glm::dvec4 h = glm::dmat4(m) * glm::dvec4(p, 1.0);
    if (!(h.w > 0.0)) return false;
    const double x = h.x / h.w, y = h.y / h.w, z = h.z / h.w;
    const double zlo = cd == ClipDepth::ZeroToOne ? 0.0 : -1.0;
    return std::fabs(x) <= 1.0 + tol && std::fabs(y) <= 1.0 + tol && z >= zlo - tol && z <= 1.0 + tol;
}

glm::dvec2 ndc_xy(const glm::mat4& m, const glm::dvec3& p) {
    const glm::dvec4 h = glm::dmat4(m) * glm::dvec4(p, 1.0);
    return glm::dvec2(h.x / h.w, h.y / h.w);
}

// Hexahedron planes (inward) from 8 corners, independent of the header's helper.
void planes_of(const glm::vec3 c[8], glm::dvec4 out[6]) {
    const int f[6][3] = {{0, 1, 2}, {4, 6, 5}, {0, 4, 1}, {2, 3, 6}, {0, 2, 4}, {1, 5, 3}};
    glm::dvec3 ctr(0.0);
    for (int i = 0; i < 8; ++i) ctr += glm::dvec3(c[i]);
    ctr /= 8.0;
    for (int i = 0; i < 6; ++i) {
        const glm::dvec3 a(c[f[i][0]]), b(c[f[i][1]]), d(c[f[i][2]]);
        glm::dvec3 n = glm::normalize(glm::cross(b - a, d - a));
        glm::dvec4 p(n, -glm::dot(n, a));
        if (glm::dot(glm::dvec3(p), ctr) + p.w < 0) p = -p;
        out[i] = p;
    }
}

// Does the ray q + t*dir, t in [0, tmax], meet the convex volume (frustum planes + optional box)?
bool ray_hits(const glm::dvec4* pl, int np, const glm::dvec3& q, const glm::dvec3& dir, double tmax) {
    double t0 = 0.0, t1 = tmax;
    for (int i = 0; i < np; ++i) {
        const double s = glm::dot(glm::dvec3(pl[i]), q) + pl[i].w;
        const double ds = glm::dot(glm::dvec3(pl[i]), dir);
        if (ds == 0.0) {
            if (s < 0) return false;
            continue;
        }
        const double t = -s / ds;
        if (ds > 0) t0 = std::fmax(t0, t);
        else t1 = std::fmin(t1, t);
        if (t0 > t1) return false;
    }
    return true;
}

LightFrustumInput base_input() {
    LightFrustumInput in;
    in.camera_view = glm::lookAt(glm::vec3(0, 2, 0), glm::vec3(0, 2, -1), glm::vec3(0, 1, 0));
    in.camera_proj = glm::perspective(1.0f, 1.0f, 0.1f, 50.0f);
    in.light_position = glm::vec4(0, 1, 0, 0);  // sun straight overhead
    return in;
}

// ------------------------------------------------------------------ continuity sweep (issue 14)
// The light's travel direction d(theta) = v cos(theta) + w sin(theta) turns through the camera's view
// direction v (theta = 0: parallel, the light behind the camera; 180: anti-parallel). A fixed set of
// receiver points is projected with every fit; between consecutive steps no point may move more than
// 0.01 light NDC (x, y), and the points' NDC extent (x and y) may not change by more than 5% within
// 0.01 degree, except within 0.5 degree of parallel / anti-parallel (and, for the stable fit, within
// 0.5 degree of its one singular direction, a light shining straight up). Coarse 0.25-degree steps
// over the whole circle (a smooth fit moves the points ~0.005-0.015 NDC per coarse step); every coarse
// step that moves more than 0.03 or changes the extent more than 3% is re-walked in 0.002-degree
// steps, and so is [0.5, 1.5] degrees on both sides of both parallels (where the roll is fastest).
struct SweepStats {
    long fits = 0, fine_steps = 0, failures = 0, refined = 0;
    double max_move = 0.0, max_extent_change = 0.0;
    double max_move_exempt = 0.0;
};

struct Sample {
    bool ok = false;
    std::vector<glm::dvec2> p;
    glm::dvec2 ext{0.0};
};

template <class Fit>
Sample project(const Fit& fit, const glm::dvec3& d, const std::vector<glm::dvec3>& pts, SweepStats& st) {
    Sample s;
    glm::mat4 m;
    ++st.fits;
    if (!fit(d, m)) return s;
    s.ok = true;
    glm::dvec2 lo(1e300), hi(-1e300);
    for (const glm::dvec3& q : pts) {
        const glm::dvec2 n = ndc_xy(m, q);
        s.p.push_back(n);
        lo = glm::min(lo, n);
        hi = glm::max(hi, n);
    }
    s.ext = hi - lo;
    return s;
}

double move(const Sample& a, const Sample& b) {
    double m = 0.0;
    for (std::size_t i = 0; i < a.p.size(); ++i) m = std::fmax(m, glm::length(a.p[i] - b.p[i]));
    return m;
}
double ext_change(const Sample& a, const Sample& b) {
    return std::fmax(std::fabs(b.ext.x / a.ext.x - 1.0), std::fabs(b.ext.y / a.ext.y - 1.0));
}

// exempt(d): within 0.5 degree of a direction where the roll is free
template <class Fit, class Exempt>
void sweep(const Fit& fit, const Exempt& exempt, const glm::dvec3& v, const glm::dvec3& w,
           const std::vector<glm::dvec3>& pts, SweepStats& st, const char* what) {
    auto dir = [&](double deg) {
        const double t = deg * kPi / 180.0;
        return glm::normalize(v * std::cos(t) + w * std::sin(t));
    };
    auto check_fine = [&](double a_deg, double b_deg) {
        const int n = int(std::lround((b_deg - a_deg) / 0.002));
        std::vector<Sample> s;
        s.reserve(std::size_t(n) + 1);
        for (int k = 0; k <= n; ++k) s.push_back(project(fit, dir(a_deg + 0.002 * k), pts, st));
        st.fine_steps += n;
        for (int k = 0; k < n; ++k) {
            const double deg = a_deg + 0.002 * k;
            if (!s[size_t(k)].ok || !s[size_t(k) + 1].ok) continue;
            const bool ex = exempt(dir(deg)) || exempt(dir(deg + 0.002));
            const double mv = move(s[size_t(k)], s[size_t(k) + 1]);
            if (ex) { st.max_move_exempt = std::fmax(st.max_move_exempt, mv); continue; }
            st.max_move = std::fmax(st.max_move, mv);
            if (mv >= 0.01) {
                if (st.failures++ < 5) FAIL_CHECK(std::string(what) << ": receivers move " << mv << " NDC at " << deg << " deg");
            }
            for (int j = k + 1; j <= k + 5 && j <= n; ++j) {  // within 0.01 degree
                if (!s[size_t(j)].ok || exempt(dir(a_deg + 0.002 * j))) break;
                const double ec = ext_change(s[size_t(k)], s[size_t(j)]);
                st.max_extent_change = std::fmax(st.max_extent_change, ec);
                if (ec > 0.05 && st.failures++ < 5)
                    FAIL_CHECK(std::string(what) << ": extent changes " << ec * 100 << "% within 0.01 deg at " << deg);
            }
        }
    };
    // coarse circle with refinement
    Sample prev = project(fit, dir(0.0), pts, st);
    for (int k = 1; k <= 1440; ++k) {
        const double deg = 0.25 * k;
        Sample cur = project(fit, dir(deg), pts, st);
        if (prev.ok && cur.ok && (move(prev, cur) >= 0.03 || ext_change(prev, cur) > 0.03)) {
            ++st.refined;
            check_fine(deg - 0.25, deg);
        }
        prev = std::move(cur);
    }
    // fine walks just outside the exempt zones
    for (double c : {0.0, 180.0}) {
        check_fine(c + 0.5, c + 1.5);
        check_fine(c - 1.5, c - 0.5);
    }
}

bool near_dir(const glm::dvec3& a, const glm::dvec3& b, double deg) {
    return glm::dot(a, b) >= std::cos(deg * kPi / 180.0);
}

}  // namespace

TEST_CASE("light_frustum: camera slice corners match the closed form for every depth convention") {
    const float fovy = 1.0f, aspect = 1.5f, n = 0.5f, f = 40.0f;
    const double ty = std::tan(0.5), tx = ty * aspect;
    for (int cdi = 0; cdi < 2; ++cdi)
        for (int rev = 0; rev < 2; ++rev)
            for (int inf = 0; inf < 2; ++inf) {
                const ClipDepth cd = cdi ? ClipDepth::ZeroToOne : ClipDepth::NegativeOneToOne;
                LightFrustumInput in;
                in.camera_view = glm::mat4(1.0f);
                in.camera_proj = make_proj(fovy, aspect, n, f, cd, rev != 0, inf != 0);
                in.camera_depth = cd;
                in.camera_reversed_z = rev != 0;
                in.max_distance = inf ? 25.0f : 0.0f;
                LightFrustumCorners c = light_frustum_slice_corners(in);
                REQUIRE(c.status == Status::Ok);
                REQUIRE(c.visible);
                const double dfar = inf ? 25.0 : 40.0;
                for (int i = 0; i < 8; ++i) {
                    const double d = (i & 4) ? dfar : 0.5;
                    const double ex = ((i & 1) ? 1 : -1) * tx * d, ey = ((i & 2) ? 1 : -1) * ty * d;
                    CHECK(c.corners[i].x == doctest::Approx(ex).epsilon(1e-4));
                    CHECK(c.corners[i].y == doctest::Approx(ey).epsilon(1e-4));
                    CHECK(c.corners[i].z == doctest::Approx(-d).epsilon(1e-4));
                }
                CHECK(c.near_depth == doctest::Approx(0.5));
                CHECK(c.far_depth == doctest::Approx(dfar));
                // receiver depth clip
                in.receiver_min_depth = 2.0f;
                in.receiver_max_depth = 10.0f;
                c = light_frustum_slice_corners(in);
                REQUIRE(c.status == Status::Ok);
                CHECK(c.corners[0].z == doctest::Approx(-2.0));
                CHECK(c.corners[7].z == doctest::Approx(-10.0));
                if (inf) {
                    in.max_distance = 0.0f;  // was InfiniteFar: the vocabulary has no such status
                    CHECK(light_frustum_slice_corners(in).status == Status::InvalidArgument);
                }
            }
    // glm's own builders agree
    LightFrustumInput in;
    in.camera_view = glm::mat4(1.0f);
    in.camera_proj = glm::perspectiveZO(fovy, aspect, n, f);
    in.camera_depth = ClipDepth::ZeroToOne;
    LightFrustumCorners c = light_frustum_slice_corners(in);
    REQUIRE(c.status == Status::Ok);
    CHECK(c.corners[7].x == doctest::Approx(tx * 40.0).epsilon(1e-4));
    in.camera_proj = glm::infinitePerspective(fovy, aspect, n);
    in.camera_depth = ClipDepth::NegativeOneToOne;
    in.max_distance = 100.0f;
    c = light_frustum_slice_corners(in);
    REQUIRE(c.status == Status::Ok);
    CHECK(c.corners[7].z == doctest::Approx(-100.0).epsilon(1e-4));
    // orthographic camera
    in.camera_proj = glm::ortho(-2.f, 2.f, -1.f, 1.f, 1.f, 9.f);
    in.max_distance = 0.0f;
    c = light_frustum_slice_corners(in);
    REQUIRE(c.status == Status::Ok);
    CHECK(c.corners[0].x == doctest::Approx(-2.0));
    CHECK(c.corners[7].z == doctest::Approx(-9.0));
    // empty range: visible = false with Ok (was EmptyReceivers)
    in.camera_proj = glm::perspective(fovy, aspect, n, f);
    in.max_distance = 0.25f;  // before the near plane
    c = light_frustum_slice_corners(in);
    CHECK(c.status == Status::Ok);
    CHECK_FALSE(c.visible);
}

// Issue 13 item 3: the epsilon-tweaked infinite projection (NDC z = +1 un-projects behind the eye)
// was InvalidInput; every output of infinite_projection.hpp must be accepted (with max_distance).
TEST_CASE("light_frustum: every projection of infinite_projection.hpp is accepted (issue 13 item 3)") {
    const float fovy = 1.1f, aspect = 1.7f, n = 0.2f;
    const double ty = std::tan(0.55), tx = ty * aspect;
    int fits = 0;
    for (int cdi = 0; cdi < 2; ++cdi)
        for (int rev = 0; rev < 2; ++rev)
            for (float eps : {0.0f, 1e-6f, 2.4e-7f, 1e-3f, 0.5f})
                for (int fin = 0; fin < 2; ++fin) {
                    if (fin && eps != 0.0f) continue;
                    const ClipDepth cd = cdi ? ClipDepth::ZeroToOne : ClipDepth::NegativeOneToOne;
                    ProjectionDepth dp;
                    dp.near_z = n;
                    dp.far_z = fin ? 500.0f : std::numeric_limits<float>::infinity();
                    dp.clip_depth = cd;
                    dp.reversed_z = rev != 0;
                    dp.epsilon = eps;
                    const glm::mat4 P = projection_perspective(fovy, aspect, dp).matrix;
                    REQUIRE(P[2][3] == -1.0f);  // a perspective matrix came back
                    // the convenience builder gives the same matrix
                    if (!fin) CHECK(projection_perspective_infinite(fovy, aspect, n, cd, rev != 0, eps).matrix == P);
                    LightFrustumInput in = base_input();
                    in.camera_view = glm::mat4(1.0f);
                    in.camera_proj = P;
                    in.camera_depth = cd;
                    in.camera_reversed_z = rev != 0;
                    in.max_distance = 300.0f;
                    const LightFrustumCorners c = light_frustum_slice_corners(in);
                    INFO("clip depth " << cdi << " reversed " << rev << " epsilon " << eps << " finite " << fin);
                    REQUIRE(c.status == Status::Ok);
                    for (int i = 0; i < 8; ++i) {
                        const double d = (i & 4) ? 300.0 : double(n);
                        CHECK(c.corners[i].x == doctest::Approx(((i & 1) ? 1 : -1) * tx * d).epsilon(1e-4));
                        CHECK(c.corners[i].z == doctest::Approx(-d).epsilon(1e-4));
                    }
                    for (int stable = 0; stable < 2; ++stable)
                        for (float w : {0.0f, 1.0f}) {
                            if (stable && w != 0.0f) continue;
                            in.stable = stable != 0;
                            in.light_position = w == 0.0f ? glm::vec4(0.3f, 1.0f, 0.2f, 0.0f) : glm::vec4(50, 400, 80, 1);
                            const LightFrustumResult r = light_frustum_fit(in, nullptr, 0);
                            REQUIRE(r.status == Status::Ok);
                            CHECK(r.visible);
                            for (int i = 0; i < 8; ++i) CHECK(in_clip(r.view_proj, glm::dvec3(c.corners[i]), in.light_depth, 1e-4));
                            ++fits;
                        }
                    // without max_distance an infinite far plane is an error, a finite one is used
                    in.max_distance = 0.0f;
                    in.stable = false;
                    CHECK(light_frustum_fit(in, nullptr, 0).status == (fin ? Status::Ok : Status::InvalidArgument));
                }
    MESSAGE("fits with infinite_projection.hpp matrices: " << fits);
}

TEST_CASE("light_frustum: containment and no false culling over thousands of random cameras and lights") {
    std::mt19937 rng(1234);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    int runs = 0, ok = 0, checked_points = 0, culled_total = 0, casters_total = 0, hits_checked = 0;
    for (int it = 0; it < 2500; ++it) {
        const Cam cam = random_camera(rng);
        LightFrustumInput in;
        set_camera(in, cam);
        if (rng() % 3 == 0) {
            in.receiver_min_depth = cam.nearp * (1.0f + 3.0f * u(rng));
            in.receiver_max_depth = in.receiver_min_depth + cam.farp * u(rng);
        }
        const bool point = rng() % 3 == 0;
        in.light_position = point ? glm::vec4(glm::vec3(u(rng) - 0.5f, u(rng), u(rng) - 0.5f) * 150.0f, 1.0f)
                                  : glm::vec4(random_dir(rng), 0.0f);
        in.has_scene_bounds = rng() % 2 == 0;
        in.scene_min = glm::vec3(-60, -10, -60) + glm::vec3(u(rng), u(rng), u(rng)) * 20.0f;
        in.scene_max = glm::vec3(60, 30, 60) - glm::vec3(u(rng), u(rng), u(rng)) * 20.0f;
        in.light_depth = (rng() & 1) ? ClipDepth::ZeroToOne : ClipDepth::NegativeOneToOne;
        in.light_reversed_z = false;
        in.stable = !point && rng() % 3 == 0;
        in.stable_world_depth = in.stable && in.has_scene_bounds && it % 2 == 0;  // issue 18 (no rng draw: same cases)
        in.shadow_map_size = 1024;
        std::vector<float> boxes;
        const int nc = 20;
        for (int i = 0; i < nc; ++i) {
            const glm::vec3 c = glm::vec3(u(rng) - 0.5f, u(rng) * 0.4f, u(rng) - 0.5f) * 120.0f;
            const glm::vec3 h = glm::vec3(u(rng), u(rng), u(rng)) * 6.0f;
            const glm::vec3 mn = c - h, mx = c + h;
            boxes.insert(boxes.end(), {mn.x, mn.y, mn.z, mx.x, mx.y, mx.z});
        }
        in.casters = boxes.data();
        in.caster_count = nc;
        std::vector<std::uint32_t> keep(nc);
        const LightFrustumResult r = light_frustum_fit(in, keep.data(), keep.size());
        ++runs;
        if (r.status == Status::LightInsideVolume) continue;
        REQUIRE(r.status == Status::Ok);
        if (!r.visible) {
            CHECK(r.culled_count == std::size_t(nc));
            continue;
        }
        ++ok;
        for (int c = 0; c < 4; ++c)
            for (int k = 0; k < 4; ++k) REQUIRE(std::isfinite(r.view_proj[c][k]));
        CHECK(r.needed + r.culled_count == std::size_t(nc));
        CHECK(r.count == r.needed);
        casters_total += nc;
        culled_total += int(r.culled_count);

        const LightFrustumCorners scc = light_frustum_slice_corners(in);
        REQUIRE(scc.status == Status::Ok);
        REQUIRE(scc.visible);
        const glm::vec3* sc = scc.corners;
        glm::dvec4 pl[12];
        planes_of(sc, pl);
        int np = 6;
        if (in.has_scene_bounds) {
            pl[6] = {1, 0, 0, -in.scene_min.x}; pl[7] = {-1, 0, 0, in.scene_max.x};
            pl[8] = {0, 1, 0, -in.scene_min.y}; pl[9] = {0, -1, 0, in.scene_max.y};
            pl[10] = {0, 0, 1, -in.scene_min.z}; pl[11] = {0, 0, -1, in.scene_max.z};
            np = 12;
        }
        // (0) winding: a triangle counter-clockwise seen from the light is counter-clockwise in the map
        for (int s = 0; s < 4; ++s) {
            const glm::dvec3 a = lerp3(sc, u(rng), u(rng), u(rng));
            if (in.has_scene_bounds && !in_box(a, in.scene_min, in.scene_max, 0.0)) continue;  // not a receiver
            const glm::dvec3 to_light = point ? glm::dvec3(in.light_position) - a : glm::dvec3(in.light_position);
            const glm::dvec3 e1 = glm::normalize(glm::cross(to_light, glm::dvec3(random_dir(rng))));
            const glm::dvec3 e2 = glm::normalize(glm::cross(to_light, e1));  // (e1 x e2) . to_light > 0
            const double sz = 1e-3 * glm::length(to_light);
            const glm::dvec3 b = a + sz * e1, c = a + sz * e2;
            REQUIRE(glm::dot(glm::cross(b - a, c - a), to_light) > 0.0);
            const glm::dvec2 na = ndc_xy(r.view_proj, a), nb = ndc_xy(r.view_proj, b), nt = ndc_xy(r.view_proj, c);
            const double area = (nb.x - na.x) * (nt.y - na.y) - (nb.y - na.y) * (nt.x - na.x);
            CHECK(area > 0.0);
        }
        // (1) every receiver point maps inside the light clip volume
        for (int s = 0; s < 40; ++s) {
            const glm::dvec3 p = lerp3(sc, u(rng), u(rng), u(rng));
            if (in.has_scene_bounds && !in_box(p, in.scene_min, in.scene_max, 0.0)) continue;
            ++checked_points;
            if (!in_clip(r.view_proj, p, in.light_depth)) {
                FAIL_CHECK("receiver point outside the light clip volume, it=" << it);
                break;
            }
        }
        // (2) culling: a caster with a sample whose shadow ray meets the receiver volume must be kept;
        //     and that sample must be inside the light clip volume (it is rendered into the map).
        //     The shadow ray runs from the caster along the light's travel direction (-xyz for w = 0).
        std::vector<char> kept(nc, 0);
        for (std::size_t k = 0; k < r.count; ++k) kept[keep[k]] = 1;
        for (int i = 0; i < nc; ++i) {
            const float* b = &boxes[size_t(6 * i)];
            for (int s = 0; s < 30; ++s) {
                const glm::dvec3 q(b[0] + (b[3] - b[0]) * double(u(rng)), b[1] + (b[4] - b[1]) * double(u(rng)),
                                   b[2] + (b[5] - b[2]) * double(u(rng)));
                const glm::dvec3 dir = point ? glm::dvec3(q) - glm::dvec3(in.light_position) : -glm::dvec3(in.light_position);
                if (glm::length(dir) == 0.0) continue;
                if (!ray_hits(pl, np, q, glm::normalize(dir), 1e7)) continue;
                ++hits_checked;
                if (!kept[size_t(i)]) {
                    FAIL_CHECK("caster culled although it shadows the receiver volume, it=" << it);
                    break;
                }
                if (!in_clip(r.view_proj, q, in.light_depth, 1e-3)) {
                    FAIL_CHECK("shadowing caster point outside the light clip volume, it=" << it);
                    break;
                }
            }
        }
    }
    MESSAGE("runs " << runs << ", fitted " << ok << ", receiver points " << checked_points << ", shadowing caster samples "
                    << hits_checked << ", casters culled " << culled_total << " / " << casters_total);
    CHECK(ok > runs / 2);
    CHECK(culled_total > 0);
}

// Issue 13 item 2: light_position w = 0 is the direction *toward* the light. Before, the header
// took the direction the light travels, so this sun overhead kept the box under the floor and
// culled the one above the receivers.
TEST_CASE("light_frustum: a directional light_position points toward the light (issue 13 item 2)") {
    LightFrustumInput in = base_input();
    in.camera_view = glm::lookAt(glm::vec3(0, 10, 10), glm::vec3(0, 0, 0), glm::vec3(0, 1, 0));
    in.has_scene_bounds = true;
    in.scene_min = glm::vec3(-20, -1, -20);
    in.scene_max = glm::vec3(20, 0, 20);      // receivers: a floor slab
    const float boxes[12] = {-1, 5, -1, 1, 6, 1,           // above the floor: shadows it (sun overhead)
                             -1, -9, -1, 1, -8, 1};        // below the floor: cannot shadow it
    in.casters = boxes;
    in.caster_count = 2;
    std::uint32_t keep[2] = {7, 7};
    for (int stable = 0; stable < 2; ++stable) {
        in.stable = stable != 0;
        in.light_position = glm::vec4(0, 1, 0, 0);  // the sun straight overhead
        LightFrustumResult r = light_frustum_fit(in, keep, 2);
        REQUIRE(r.status == Status::Ok);
        CHECK(r.needed == 1);
        CHECK(keep[0] == 0);
        // the light looks down: the box above is nearer to the light than the floor
        const glm::dvec4 a = glm::dmat4(r.view) * glm::dvec4(0, 5.5, 0, 1), f = glm::dmat4(r.view) * glm::dvec4(0, 0, 0, 1);
        CHECK(-a.z < -f.z);
        // the sun straight below (light_position (0, -1, 0, 0)) is the other way round
        in.light_position = glm::vec4(0, -1, 0, 0);
        r = light_frustum_fit(in, keep, 2);
        REQUIRE(r.status == Status::Ok);
        CHECK(r.needed == 1);
        CHECK(keep[0] == 1);
    }
    // a point light above: the same box kept
    in.stable = false;
    in.light_position = glm::vec4(0, 30, 0, 1);
    const LightFrustumResult r = light_frustum_fit(in, keep, 2);
    REQUIRE(r.status == Status::Ok);
    CHECK(r.needed == 1);
    CHECK(keep[0] == 0);
    // a homogeneous point with w != 1 is the point xyz / w
    in.light_position = glm::vec4(0, 60, 0, 2);
    const LightFrustumResult r2 = light_frustum_fit(in, keep, 2);
    REQUIRE(r2.status == Status::Ok);
    for (int c = 0; c < 4; ++c)
        for (int k = 0; k < 4; ++k) CHECK(r2.view_proj[c][k] == doctest::Approx(r.view_proj[c][k]).epsilon(1e-5));
}

TEST_CASE("light_frustum: culling on a fixed random scene (report numbers)") {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    LightFrustumInput in;
    in.camera_view = glm::lookAt(glm::vec3(0, 2, 0), glm::vec3(10, 1, 0), glm::vec3(0, 1, 0));
    in.camera_proj = glm::perspective(1.0f, 16.0f / 9.0f, 0.1f, 100.0f);
    in.light_position = glm::vec4(-glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f)), 0.0f);
    in.has_scene_bounds = true;
    in.scene_min = glm::vec3(-200, -1, -200);
    in.scene_max = glm::vec3(200, 20, 200);
    std::vector<float> boxes;
    const int n = 10000;
    for (int i = 0; i < n; ++i) {
        const glm::vec3 c(u(rng) * 400 - 200, u(rng) * 10, u(rng) * 400 - 200);
        const float h = 0.5f + 2.0f * u(rng);
        boxes.insert(boxes.end(), {c.x - h, c.y - h, c.z - h, c.x + h, c.y + h, c.z + h});
    }
    in.casters = boxes.data();
    in.caster_count = n;
    std::vector<std::uint32_t> keep(n);
    const LightFrustumResult r = light_frustum_fit(in, keep.data(), keep.size());
    REQUIRE(r.status == Status::Ok);
    MESSAGE("10000 random casters, camera 100 wu far plane: kept " << r.needed << ", culled " << r.culled_count);
    CHECK(r.culled_count > 8000);
    // receiver depth range from a reduction culls more
    in.receiver_min_depth = 5.0f;
    in.receiver_max_depth = 30.0f;
    const LightFrustumResult r2 = light_frustum_fit(in, keep.data(), keep.size());
    REQUIRE(r2.status == Status::Ok);
    MESSAGE("with receivers in [5, 30]: kept " << r2.needed << ", culled " << r2.culled_count);
    CHECK(r2.needed < r.needed);
    // buffer too small: the valid prefix and the count still reported, matrices valid
    const LightFrustumResult r3 = light_frustum_fit(in, keep.data(), 3);
    CHECK(r3.status == Status::BufferTooSmall);
    CHECK(r3.count == 3);
    CHECK(r3.needed == r2.needed);
    CHECK(r3.view_proj == r2.view_proj);
    // size query: nullptr with capacity 0
    const LightFrustumResult r4 = light_frustum_fit(in, nullptr, 0);
    CHECK(r4.status == Status::BufferTooSmall);
    CHECK(r4.count == 0);
    CHECK(r4.needed == r2.needed);
}

TEST_CASE("light_frustum: stable mode is rotation invariant and moves by whole texels") {
    std::mt19937 rng(99);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const unsigned S = 2048;
    int rot_cases = 0, trans_cases = 0;
    for (int it = 0; it < 300; ++it) {
        LightFrustumInput in;
        in.camera_proj = glm::perspective(0.5f + u(rng), 0.7f + u(rng), 0.1f + u(rng), 30.0f + 100.0f * u(rng));
        in.light_position = glm::vec4(random_dir(rng), 0.0f);
        in.stable = true;
        in.shadow_map_size = S;
        // with scene bounds (every third case) smaller than the slice: the tight and stable window
        in.has_scene_bounds = it % 3 == 0;
        in.scene_min = glm::vec3(-10, -2, -10) + glm::vec3(u(rng), u(rng), u(rng)) * 3.0f;
        in.scene_max = glm::vec3(10, 4, 10) - glm::vec3(u(rng), u(rng), u(rng)) * 3.0f;
        const glm::vec3 pos = in.has_scene_bounds ? glm::vec3(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f) * 8.0f
                                                  : glm::vec3(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f) * 40.0f;
        auto fit = [&](const glm::vec3& p, const glm::vec3& fwd) {
            in.camera_view = look(p, fwd);
            const LightFrustumResult r = light_frustum_fit(in, nullptr, 0);
            REQUIRE(r.status == Status::Ok);
            return r;
        };
        // a camera that sees the box (bounded cases)
        auto see = [&](glm::vec3 f) { return in.has_scene_bounds ? glm::normalize(-pos + f * 3.0f) : f; };
        const LightFrustumResult a = fit(pos, see(random_dir(rng)));
        if (!a.visible) continue;
        // radius rounded up to 1/16
        CHECK(std::fmod(double(a.bounding_sphere.w) * 16.0, 1.0) == 0.0);
        // texel coordinates of the world origin
        auto origin_texel = [&](const LightFrustumResult& r) {
            const glm::dvec4 h = glm::dmat4(r.view_proj) * glm::dvec4(0, 0, 0, 1);
            return glm::dvec2(h.x / h.w, h.y / h.w) * (0.5 * S) + 0.5 * S;
        };
        // rotation about the camera position: x/y rows identical (scale and orientation), translation
        // moves by whole texels
        for (int k = 0; k < 5; ++k) {
            const LightFrustumResult b = fit(pos, see(random_dir(rng)));
            if (!b.visible) continue;
            ++rot_cases;
            for (int c = 0; c < 3; ++c)
                for (int row = 0; row < 2; ++row) CHECK(a.view_proj[c][row] == b.view_proj[c][row]);
            CHECK(a.bounding_sphere.w == b.bounding_sphere.w);
            CHECK(a.texel_world_size == b.texel_world_size);
            const glm::dvec2 ta = origin_texel(a), tb = origin_texel(b);
            CHECK(std::fabs(ta.x - std::round(ta.x)) < 1e-3);
            CHECK(std::fabs(tb.y - std::round(tb.y)) < 1e-3);
            const glm::dvec2 dt = tb - ta;
            CHECK(std::fabs(dt.x - std::round(dt.x)) < 1e-3);
            CHECK(std::fabs(dt.y - std::round(dt.y)) < 1e-3);
        }
        // translation (sub-texel and larger): the origin moves by whole texels; texel size constant
        const glm::vec3 fwd = see(random_dir(rng));
        const LightFrustumResult c0 = fit(pos, fwd);
        if (!c0.visible) continue;
        for (int k = 0; k < 5; ++k) {
            const float step = (k < 2 ? 0.3f : 20.0f) * c0.texel_world_size;
            const LightFrustumResult c1 = fit(pos + random_dir(rng) * step, fwd);
            if (!c1.visible) continue;
            ++trans_cases;
            CHECK(c1.texel_world_size == c0.texel_world_size);
            const glm::dvec2 dt = origin_texel(c1) - origin_texel(c0);
            CHECK(std::fabs(dt.x - std::round(dt.x)) < 1e-3);
            CHECK(std::fabs(dt.y - std::round(dt.y)) < 1e-3);
        }
    }
    MESSAGE("stable: " << rot_cases << " rotations, " << trans_cases << " translations checked");
    CHECK(rot_cases > 1000);
}

// Issue 18: the stable fit's depth range followed the receivers the camera sees, so every camera move
// shifted or resized the near/far planes: shadow_cache_plan called it DepthMoved or ProjectionChanged
// and a cached map was rendered whole on almost every frame (1526 of 1561 moves here). With stable_world_depth the range comes from the scene box and every caster:
// the depth row and the x/y scale stay bit for bit, the map moves by whole texels (texel_anchor),
// and the plan scrolls or keeps. Expected values: the world origin's window position (closed form:
// -texel_anchor), the plan's offset (= the change of the anchor), brute-force depth containment.
TEST_CASE("light_frustum: stable_world_depth fixes the depth range in the world; camera moves are whole-texel scrolls (issue 18)") {
    std::mt19937 rng(1818);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const unsigned S = 1024;
    int moves = 0, scrolls = 0, keeps = 0, default_rendered = 0;
    for (int it = 0; it < 200; ++it) {
        LightFrustumInput in;
        in.camera_proj = glm::perspective(0.5f + u(rng), 0.7f + u(rng), 0.1f + u(rng), 20.0f + 60.0f * u(rng));
        in.light_position = glm::vec4(random_dir(rng), 0.0f);
        if (in.light_position.y < -0.99f) in.light_position.y = 0.5f;  // away from the stable fit's singular direction
        in.stable = true;
        in.stable_world_depth = true;
        in.shadow_map_size = S;
        in.has_scene_bounds = true;
        // a scene the camera sees whole (even cases) or in part (odd: 400 units wide, far plane <= 80)
        const float half_w = it % 2 == 0 ? 20.0f : 200.0f;
        in.scene_min = glm::vec3(-half_w, -2, -half_w) + glm::vec3(u(rng), u(rng), u(rng)) * 4.0f;
        in.scene_max = glm::vec3(half_w, 6, half_w) - glm::vec3(u(rng), u(rng), u(rng)) * 4.0f;
        std::vector<float> boxes;
        for (int i = 0; i < 8; ++i) {  // casters in the box, and one beside it (its depth counts too)
            const glm::vec3 c = i == 7 ? glm::vec3(30, 12, 0) : glm::vec3(u(rng) - 0.5f, u(rng) * 0.3f, u(rng) - 0.5f) * 30.0f;
            const glm::vec3 h = glm::vec3(0.2f) + glm::vec3(u(rng), u(rng), u(rng)) * 2.0f;
            boxes.insert(boxes.end(), {c.x - h.x, c.y - h.y, c.z - h.z, c.x + h.x, c.y + h.y, c.z + h.z});
        }
        in.casters = boxes.data();
        in.caster_count = 8;
        const glm::vec3 pos = glm::vec3(u(rng) - 0.5f, u(rng) * 0.5f, u(rng) - 0.5f) * 16.0f;
        auto fit = [&](const glm::vec3& p, const glm::vec3& fwd) {
            in.camera_view = look(p, fwd);
            std::uint32_t keep[8];
            return light_frustum_fit(in, keep, 8);
        };
        auto origin_window = [&](const LightFrustumResult& r) {  // the world origin in map texels
            const glm::dvec4 h = glm::dmat4(r.view_proj) * glm::dvec4(0, 0, 0, 1);
            return glm::dvec2(h.x / h.w, h.y / h.w) * (0.5 * S) + 0.5 * S;
        };
        // the plan's matrix: the float result in double with its x/y translation rebuilt exactly from
        // the anchor (-2 anchor / S - 1: what the float entry rounds), as docs/light_frustum.md says
        auto state = [&](const LightFrustumResult& r) {
            ShadowCacheMapState st;
            st.view_proj = glm::dmat4(r.view_proj);
            st.view_proj[3][0] = -2.0 * r.texel_anchor.x / double(S) - 1.0;
            st.view_proj[3][1] = -2.0 * r.texel_anchor.y / double(S) - 1.0;
            st.width = st.height = int(S);
            st.has_content = true;
            return st;
        };
        const glm::vec3 fwd0 = glm::normalize(-pos + random_dir(rng) * 4.0f);
        const LightFrustumResult a = fit(pos, fwd0);
        REQUIRE(a.status == Status::Ok);
        if (!a.visible) continue;
        // closed form: the world origin lies at window -texel_anchor (whole numbers: S is even)
        CHECK(a.texel_anchor.x == std::round(a.texel_anchor.x));
        CHECK(std::fabs(origin_window(a).x + a.texel_anchor.x) < 1e-2);
        CHECK(std::fabs(origin_window(a).y + a.texel_anchor.y) < 1e-2);
        // the depth range holds the whole scene box and every caster (brute force over corners)
        for (int c = 0; c < 8; ++c) {
            const glm::dvec3 p((c & 1) ? in.scene_max.x : in.scene_min.x, (c & 2) ? in.scene_max.y : in.scene_min.y,
                               (c & 4) ? in.scene_max.z : in.scene_min.z);
            const glm::dvec4 h = glm::dmat4(a.view_proj) * glm::dvec4(p, 1.0);
            CHECK(std::fabs(h.z / h.w) <= 1.0 + 1e-5);
            for (int i = 0; i < 8; ++i) {
                const float* b = &boxes[std::size_t(6 * i)];
                const glm::dvec3 q((c & 1) ? b[3] : b[0], (c & 2) ? b[4] : b[1], (c & 4) ? b[5] : b[2]);
                const glm::dvec4 hq = glm::dmat4(a.view_proj) * glm::dvec4(q, 1.0);
                CHECK(std::fabs(hq.z / hq.w) <= 1.0 + 1e-5);
            }
        }
        for (int k = 0; k < 8; ++k) {
            // rotations (k even) and translations from sub-texel to ~40 texels (k odd)
            const bool rotate = k % 2 == 0;
            const float step = (k < 4 ? 0.3f : 40.0f) * a.texel_world_size;
            const glm::vec3 p = rotate ? pos : pos + random_dir(rng) * step;
            const glm::vec3 f = rotate ? glm::normalize(fwd0 + random_dir(rng) * 0.3f) : fwd0;
            const LightFrustumResult b = fit(p, f);
            REQUIRE(b.status == Status::Ok);
            if (!b.visible) continue;
            ++moves;
            // the depth planes, the depth row and the texel size: bit for bit
            CHECK(b.near_z == a.near_z);
            CHECK(b.far_z == a.far_z);
            CHECK(b.texel_world_size == a.texel_world_size);
            for (int c = 0; c < 4; ++c) CHECK(b.view_proj[c][2] == a.view_proj[c][2]);
            for (int c = 0; c < 3; ++c)
                for (int row = 0; row < 2; ++row) CHECK(b.view_proj[c][row] == a.view_proj[c][row]);
            // the map moved by the change of the anchor, in whole texels
            const glm::dvec2 moved = origin_window(b) - origin_window(a), da = b.texel_anchor - a.texel_anchor;
            CHECK(std::fabs(moved.x + da.x) < 1e-2);
            CHECK(std::fabs(moved.y + da.y) < 1e-2);
            // shadow_cache_plan: keep (same texels) or scroll by the anchor's change; never a full render
            ShadowCacheRect rects[4];
            const ShadowCachePlan plan = shadow_cache_plan(state(a), state(b), nullptr, 0, rects, 4);
            REQUIRE(plan.status == Status::Ok);
            CHECK_MESSAGE(plan.action != ShadowCacheAction::Render, "reason " << std::string(shadow_cache_reason_name(plan.reason)) << " anchor change " << (b.texel_anchor.x - a.texel_anchor.x) << " " << (b.texel_anchor.y - a.texel_anchor.y)
                                                                             << " residual " << plan.residual_texels);
            if (plan.action == ShadowCacheAction::Scroll) {
                ++scrolls;
                CHECK(plan.offset_x == int(a.texel_anchor.x - b.texel_anchor.x));
                CHECK(plan.offset_y == int(a.texel_anchor.y - b.texel_anchor.y));
            } else if (plan.action == ShadowCacheAction::Keep) {
                ++keeps;
                CHECK(da == glm::dvec2(0.0));
            }
            // the default range (the receivers the camera sees): the same move shifts the depth planes
            in.stable_world_depth = false;
            const LightFrustumResult a0 = fit(pos, fwd0), b0 = fit(p, f);
            in.stable_world_depth = true;
            if (a0.visible && b0.visible) {
                const ShadowCachePlan p0 = shadow_cache_plan(state(a0), state(b0), nullptr, 0, rects, 4);
                // the depth planes moved (DepthMoved) or the range changed size (ProjectionChanged)
                if (p0.action == ShadowCacheAction::Render) ++default_rendered;
            }
        }
    }
    MESSAGE("stable_world_depth: " << moves << " camera moves, " << scrolls << " scrolls, " << keeps
                                   << " keeps; the default depth range: " << default_rendered << " whole-map renders");
    CHECK(moves > 1000);
    CHECK(scrolls > moves / 4);
    CHECK(default_rendered > moves / 2);  // what the option is for
    // needs the scene bounds; ignored without `stable`
    LightFrustumInput in = base_input();
    in.stable = true;
    in.stable_world_depth = true;
    CHECK(light_frustum_fit(in, nullptr, 0).status == Status::InvalidArgument);
    in.stable = false;
    const LightFrustumResult with = light_frustum_fit(in, nullptr, 0);
    in.stable_world_depth = false;
    const LightFrustumResult without = light_frustum_fit(in, nullptr, 0);
    REQUIRE(with.status == Status::Ok);
    CHECK(with.view_proj == without.view_proj);
}

// Issue 13 item 4: the stable fit ignored has_scene_bounds (texel 0.244 for a 1-unit box at
// max_distance 300, its shadow 4 texels wide). Now the window is W = min(2 r, E), E the box's
// light-space extent: closed form for the box below.
TEST_CASE("light_frustum: the stable fit honours the scene bounds (issue 13 item 4)") {
    LightFrustumInput in;
    in.camera_view = glm::lookAt(glm::vec3(0, 2, 5), glm::vec3(0, 0, 0), glm::vec3(0, 1, 0));
    in.camera_proj = projection_perspective_infinite(60.0f * float(kPi) / 180.0f, 1.0f, 0.1f).matrix;
    in.max_distance = 300.0f;
    in.light_position = glm::vec4(0, 1, 0, 0);  // straight down: map axes = world x and -z
    in.stable = true;
    in.shadow_map_size = 2048;
    const LightFrustumResult unb = light_frustum_fit(in, nullptr, 0);
    REQUIRE(unb.status == Status::Ok);
    CHECK(unb.texel_world_size == doctest::Approx(2.0 * unb.bounding_sphere.w / 2046.0));
    CHECK(unb.texel_world_size > 0.2f);  // the 0.244: 2 r / 2046 with r ~ 250
    in.has_scene_bounds = true;
    in.scene_min = glm::vec3(-0.5f, 0.0f, -0.5f);
    in.scene_max = glm::vec3(0.5f, 1.0f, 0.5f);
    const LightFrustumResult b = light_frustum_fit(in, nullptr, 0);
    REQUIRE(b.status == Status::Ok);
    CHECK(b.visible);
    // closed form: the box seen from straight above is a 1 x 1 square: W = 1, texel = 1 / 2046
    CHECK(b.texel_world_size == doctest::Approx(1.0 / 2046.0).epsilon(1e-6));
    MESSAGE("1-unit box, max_distance 300, sun overhead: texel " << unb.texel_world_size << " unbounded -> "
                                                                 << b.texel_world_size << " bounded");
    // every point of the box is in the map, and the box covers >= 2040 texels across
    std::mt19937 rng(4);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    glm::dvec2 lo(1e9), hi(-1e9);
    for (int k = 0; k < 2000; ++k) {
        const glm::dvec3 p(u(rng) - 0.5, u(rng), u(rng) - 0.5);
        CHECK(in_clip(b.view_proj, p, in.light_depth, 0.0));
        lo = glm::min(lo, ndc_xy(b.view_proj, p));
        hi = glm::max(hi, ndc_xy(b.view_proj, p));
    }
    CHECK((hi.x - lo.x) * 1024.0 > 2030.0);
    // a tilted sun: E is the larger side of the box's light-space rectangle (closed form)
    const glm::vec3 toward = glm::normalize(glm::vec3(0.3f, 1.0f, 0.2f));
    in.light_position = glm::vec4(toward, 0.0f);
    const LightFrustumResult t = light_frustum_fit(in, nullptr, 0);
    REQUIRE(t.status == Status::Ok);
    const glm::dmat3 R(glm::dmat4(t.view));
    double ex = 0, ey = 0;
    for (int k = 0; k < 3; ++k) {  // the box's extent along the map axes: sum of |axis . edge|
        ex += std::fabs(R[k][0]) * 1.0;
        ey += std::fabs(R[k][1]) * 1.0;
    }
    CHECK(t.texel_world_size == doctest::Approx(std::max(ex, ey) / 2046.0).epsilon(1e-5));
    MESSAGE("tilted sun: texel " << t.texel_world_size);
    // a box bigger than the slice's sphere: the sphere decides, as without bounds
    in.light_position = glm::vec4(0, 1, 0, 0);
    in.scene_min = glm::vec3(-1000, -1, -1000);
    in.scene_max = glm::vec3(1000, 10, 1000);
    const LightFrustumResult big = light_frustum_fit(in, nullptr, 0);
    REQUIRE(big.status == Status::Ok);
    CHECK(big.texel_world_size == unb.texel_world_size);
    // a box that lies partly outside the camera's view is covered where the camera sees it
    in.scene_min = glm::vec3(-40, -1, -40);
    in.scene_max = glm::vec3(40, 3, 40);
    const LightFrustumResult part = light_frustum_fit(in, nullptr, 0);
    REQUIRE(part.status == Status::Ok);
    CHECK(part.texel_world_size == doctest::Approx(80.0 / 2046.0).epsilon(1e-6));
    const LightFrustumCorners sc = light_frustum_slice_corners(in);
    int pts = 0;
    for (int k = 0; k < 4000; ++k) {
        const glm::dvec3 p = lerp3(sc.corners, u(rng), u(rng), u(rng));
        if (!in_box(p, in.scene_min, in.scene_max, 0.0)) continue;
        ++pts;
        CHECK(in_clip(part.view_proj, p, in.light_depth, 0.0));
    }
    CHECK(pts > 100);
}

TEST_CASE("light_frustum: anchor - an unsnapped stable fit (SaschaWillems cascades) swims, ours does not") {
    // Reproduce the unsnapped variant by hand: ortho box centered on the sphere center without snapping.
    LightFrustumInput in;
    in.camera_proj = glm::perspective(1.0f, 1.0f, 0.5f, 50.0f);
    in.light_position = glm::vec4(-glm::normalize(glm::vec3(0.2f, -1.0f, 0.4f)), 0.0f);
    in.stable = true;
    in.shadow_map_size = 1024;
    const glm::vec3 fwd = glm::normalize(glm::vec3(1, -0.2f, 0.3f));
    in.camera_view = glm::lookAt(glm::vec3(0), fwd, glm::vec3(0, 1, 0));
    const LightFrustumResult a = light_frustum_fit(in, nullptr, 0);
    REQUIRE(a.status == Status::Ok);
    const glm::vec3 side = glm::normalize(glm::cross(fwd, glm::vec3(0, 1, 0)));
    const glm::vec3 p = side * (0.37f * a.texel_world_size);
    in.camera_view = glm::lookAt(p, p + fwd, glm::vec3(0, 1, 0));
    const LightFrustumResult b = light_frustum_fit(in, nullptr, 0);
    REQUIRE(b.status == Status::Ok);
    // unsnapped: origin texel coordinate shifts by the fraction of the motion
    const glm::dvec3 ca = glm::dvec3(glm::dmat4(a.view) * glm::dvec4(glm::dvec3(a.bounding_sphere), 1.0));
    const glm::dvec3 cb = glm::dvec3(glm::dmat4(b.view) * glm::dvec4(glm::dvec3(b.bounding_sphere), 1.0));
    const double unsnapped_shift = (cb.x - ca.x) / a.texel_world_size;
    CHECK(std::fabs(unsnapped_shift - std::round(unsnapped_shift)) > 0.05);
    // ours: the world origin stays on a texel corner (integer texel coordinate)
    const glm::dvec4 ha = glm::dmat4(a.view_proj) * glm::dvec4(0, 0, 0, 1), hb = glm::dmat4(b.view_proj) * glm::dvec4(0, 0, 0, 1);
    const double sa = (ha.x * 0.5 + 0.5) * 1024.0, sb = (hb.x * 0.5 + 0.5) * 1024.0;
    CHECK(std::fabs(sa - std::round(sa)) < 1e-4);
    CHECK(std::fabs(sb - std::round(sb)) < 1e-4);
}

// Issue 19 items 4 and 6: null pointers with counts returned Ok (casters ignored, nothing written),
// and a camera projection with a negative near plane was accepted by light_frustum_fit.
TEST_CASE("light_frustum: null pointers with counts and bad projections are rejected (issue 19)") {
    const LightFrustumInput base = base_input();
    const float box[6] = {-1, 3, -6, 1, 4, -4};
    SUBCASE("null pointers with counts") {
        LightFrustumInput in = base;
        in.casters = nullptr;
        in.caster_count = 5;
        CHECK(light_frustum_fit(in, nullptr, 0).status == Status::InvalidArgument);
        in.caster_count = 0;
        in.caster_spheres = nullptr;
        in.caster_sphere_count = 2;
        CHECK(light_frustum_fit(in, nullptr, 0).status == Status::InvalidArgument);
        in.caster_sphere_count = 0;
        in.casters = box;
        in.caster_count = 1;
        const LightFrustumResult r = light_frustum_fit(in, nullptr, 5);  // kept_indices null, capacity 5
        CHECK(r.status == Status::InvalidArgument);
        CHECK(r.count == 0);
        std::uint32_t k = 99;
        const LightFrustumResult ok = light_frustum_fit(in, &k, 1);
        CHECK(ok.status == Status::Ok);
        CHECK(ok.count == 1);
        CHECK(k == 0);
        LightFrustumInput d = base;
        d.camera_proj = glm::mat4(0.0f);  // the required fields' defaults are rejected
        CHECK(light_frustum_fit(d, nullptr, 0).status == Status::InvalidArgument);
        CHECK(light_frustum_fit(LightFrustumInput{}, nullptr, 0).status != Status::Ok);
        LightFrustumInput e = base;
        e.light_position = glm::vec4(0.0f);
        CHECK(light_frustum_fit(e, nullptr, 0).status == Status::InvalidLight);
        CHECK(light_frustum_extruded_planes(nullptr, 3, nullptr, 0, glm::vec4(0, 1, 0, 0)).status == Status::InvalidArgument);
        const glm::dvec3 v(0.0);
        CHECK(light_frustum_extruded_planes(&v, 1, nullptr, 2, glm::vec4(0, 1, 0, 0)).status == Status::InvalidArgument);
        CHECK(light_frustum_extruded_planes(&v, 1, nullptr, 0, glm::vec4(0, 1, 0, 0)).status == Status::Ok);
    }
    SUBCASE("camera near plane negative or zero, for every fit") {
        for (float n : {-0.5f, -1e-3f, -10.0f}) {
            for (int stable = 0; stable < 2; ++stable)
                for (float w : {0.0f, 1.0f}) {
                    if (stable && w != 0.0f) continue;
                    LightFrustumInput in = base;
                    in.stable = stable != 0;
                    in.light_position = w == 0.0f ? glm::vec4(0, 1, 0, 0) : glm::vec4(3, 20, -5, 1);
                    in.camera_proj = glm::perspective(1.0f, 1.0f, n, 50.0f);
                    CHECK(light_frustum_fit(in, nullptr, 0).status == Status::InvalidArgument);
                    in.camera_proj = glm::perspectiveZO(1.0f, 1.0f, n, 50.0f);
                    in.camera_depth = ClipDepth::ZeroToOne;
                    CHECK(light_frustum_fit(in, nullptr, 0).status == Status::InvalidArgument);
                    in.camera_proj = make_proj(1.0f, 1.0f, n, 50.0f, ClipDepth::ZeroToOne, true, true);  // reversed, infinite
                    in.camera_reversed_z = true;
                    in.max_distance = 40.0f;
                    CHECK(light_frustum_fit(in, nullptr, 0).status == Status::InvalidArgument);
                    in.camera_proj = glm::ortho(-2.f, 2.f, -2.f, 2.f, n, 30.f);  // orthographic, near behind the eye
                    in.camera_depth = ClipDepth::NegativeOneToOne;
                    in.camera_reversed_z = false;
                    in.max_distance = 0.0f;
                    CHECK(light_frustum_fit(in, nullptr, 0).status == Status::InvalidArgument);
                    CHECK(light_frustum_slice_corners(in).status == Status::InvalidArgument);
                }
        }
        LightFrustumInput in = base;
        in.camera_proj = glm::perspective(1.0f, 1.0f, 0.0f, 50.0f);  // near 0: singular
        CHECK(light_frustum_fit(in, nullptr, 0).status == Status::InvalidArgument);
        in.camera_proj = glm::perspective(1.0f, 1.0f, 1e-5f, 50.0f);  // tiny but positive: fine
        CHECK(light_frustum_fit(in, nullptr, 0).status == Status::Ok);
    }
    SUBCASE("parameters outside their limits") {
        LightFrustumInput in = base;
        in.max_distance = -1.0f;
        CHECK(light_frustum_fit(in, nullptr, 0).status == Status::InvalidArgument);
        in = base;
        in.receiver_min_depth = 5.0f;
        in.receiver_max_depth = 3.0f;
        CHECK(light_frustum_fit(in, nullptr, 0).status == Status::InvalidArgument);
        in.receiver_min_depth = -1.0f;
        CHECK(light_frustum_fit(in, nullptr, 0).status == Status::InvalidArgument);
        in = base;
        in.shadow_map_size = 3;
        CHECK(light_frustum_fit(in, nullptr, 0).status == Status::InvalidArgument);
        in = base;
        in.radius_quantum = 0.0f;
        CHECK(light_frustum_fit(in, nullptr, 0).status == Status::InvalidArgument);
        in = base;
        in.point_min_near_ratio = 1.0f;
        CHECK(light_frustum_fit(in, nullptr, 0).status == Status::InvalidArgument);
        in = base;
        in.has_scene_bounds = true;
        in.scene_min = glm::vec3(1);
        in.scene_max = glm::vec3(0);
        CHECK(light_frustum_fit(in, nullptr, 0).status == Status::InvalidArgument);
        in = base;
        in.stable = true;
        in.light_position = glm::vec4(0, 10, 0, 1);  // stable fit needs a directional light
        CHECK(light_frustum_fit(in, nullptr, 0).status == Status::InvalidLight);
        in.light_position = glm::vec4(0, 1, 0, -1);
        in.stable = false;
        CHECK(light_frustum_fit(in, nullptr, 0).status == Status::InvalidLight);
    }
}

TEST_CASE("light_frustum: stiff cases") {
    const LightFrustumInput base = base_input();

    SUBCASE("light parallel and anti-parallel to the view direction") {
        for (float s : {1.0f, -1.0f}) {
            LightFrustumInput in = base;
            in.light_position = glm::vec4(0, 0, s, 0);
            for (int stable = 0; stable < 2; ++stable) {
                in.stable = stable != 0;
                const LightFrustumResult r = light_frustum_fit(in, nullptr, 0);
                REQUIRE(r.status == Status::Ok);
                const LightFrustumCorners c = light_frustum_slice_corners(in);
                for (int i = 0; i < 8; ++i) CHECK(in_clip(r.view_proj, glm::dvec3(c.corners[i]), in.light_depth));
                // exactly parallel, the tight fit's map +y is the camera's up vector (0, 1, 0)
                if (!in.stable) CHECK(r.view[1][1] == doctest::Approx(1.0));
            }
        }
    }
    SUBCASE("a near plane that underflows float: Overflow, never Ok with near_z 0 (fuzz, 2026-12-05)") {
        // point_min_near_ratio 9e-41 (subnormal) times a far plane of 5e-7: the double near plane is
        // 4.6e-47, 0 in float. The fit returned Ok with near_z = 0, which the header promises is > 0.
        LightFrustumInput in;
        in.camera_view = glm::mat4(1.0f);
        in.camera_proj = glm::mat4(0.0f);
        in.camera_proj[0][0] = 2.50649079e-22f;
        in.camera_proj[1][1] = 2.42301488f;
        in.camera_proj[2][2] = -1.0f;
        in.camera_proj[2][3] = -1.0f;
        in.camera_proj[3][2] = -4.23388318e-41f;
        in.max_distance = 4.59149455e-41f;
        in.receiver_min_depth = in.receiver_max_depth = 0.0f;
        in.light_position = glm::vec4(0.0f, 3.85456536e-37f, 7.34718542e-37f, 1.61484467e-30f);
        in.has_scene_bounds = true;
        in.scene_min = glm::vec3(1.77360889e-38f, 1.26425981e-09f, 6.42743636e-10f);
        in.scene_max = glm::vec3(2.41016946e-11f, 1.26425981e-09f, 0.000710401975f);
        in.shadow_map_size = 4080;
        in.radius_quantum = 0.0625f;
        in.point_min_near_ratio = 9.00488406e-41f;
        const LightFrustumResult r = light_frustum_fit(in, nullptr, 0);
        CHECK(r.status == Status::Overflow);
        CHECK(r.near_z == 0.0f);  // the failed result's defaults
        // the same with a ratio whose near plane float holds: Ok, near_z = ratio * far_z (the receivers
        // reach the light, so the ratio sets the near plane)
        for (float ratio : {1e-30f, 1e-4f}) {
            in.point_min_near_ratio = ratio;
            const LightFrustumResult ok = light_frustum_fit(in, nullptr, 0);
            REQUIRE(ok.status == Status::Ok);
            CHECK(ok.visible);
            CHECK(ok.near_z > 0.0f);
            CHECK(ok.near_z == doctest::Approx(double(ratio) * double(ok.far_z)).epsilon(1e-5));
        }
    }
    SUBCASE("directional light straight down on a camera looking straight down") {
        LightFrustumInput in = base;
        in.camera_view = glm::lookAt(glm::vec3(0, 10, 0), glm::vec3(0, 0, 0), glm::vec3(0, 0, -1));
        const LightFrustumResult r = light_frustum_fit(in, nullptr, 0);
        REQUIRE(r.status == Status::Ok);
        in.light_position = glm::vec4(0, -1, 0, 0);  // the stable fit's singular direction
        in.stable = true;
        const LightFrustumResult s = light_frustum_fit(in, nullptr, 0);
        REQUIRE(s.status == Status::Ok);
        CHECK(in_clip(s.view_proj, glm::dvec3(0, 0.5, 0), in.light_depth));
    }
    SUBCASE("point light behind the camera, in the near plane, and inside the receivers") {
        LightFrustumInput in = base;
        in.light_position = glm::vec4(0, 3, 5, 1);  // behind
        CHECK(light_frustum_fit(in, nullptr, 0).status == Status::Ok);
        in.light_position = glm::vec4(0.5f, 2, -0.1f, 1);  // in the camera's near plane
        const LightFrustumResult rn = light_frustum_fit(in, nullptr, 0);
        CHECK((rn.status == Status::Ok || rn.status == Status::LightInsideVolume));
        in.light_position = glm::vec4(0, 2, -20, 1);  // inside the frustum: needs a cube map
        CHECK(light_frustum_fit(in, nullptr, 0).status == Status::LightInsideVolume);
    }
    SUBCASE("near 1e-5, far at infinity, and near/far ratio 1e-6") {
        LightFrustumInput in = base;
        in.camera_proj = glm::infinitePerspective(1.0f, 1.0f, 1e-5f);
        CHECK(light_frustum_fit(in, nullptr, 0).status == Status::InvalidArgument);  // needs max_distance
        in.max_distance = 10.0f;
        const LightFrustumResult r = light_frustum_fit(in, nullptr, 0);
        REQUIRE(r.status == Status::Ok);
        CHECK(in_clip(r.view_proj, glm::dvec3(0, 2, -9.99), in.light_depth));
        in.camera_proj = glm::perspective(1.0f, 1.0f, 1e-5f, 10.0f);
        in.max_distance = 0.0f;
        CHECK(light_frustum_fit(in, nullptr, 0).status == Status::Ok);
    }
    SUBCASE("coordinates at 1e6") {
        LightFrustumInput in = base;
        const glm::vec3 p(1e6f, 1e6f, -1e6f);
        in.camera_view = glm::lookAt(p, p + glm::vec3(1, 0, 0), glm::vec3(0, 1, 0));
        in.has_scene_bounds = true;
        in.scene_min = p - glm::vec3(100);
        in.scene_max = p + glm::vec3(100);
        const float box[6] = {p.x + 5, p.y - 1, p.z - 1, p.x + 7, p.y + 1, p.z + 1};
        in.casters = box;
        in.caster_count = 1;
        std::uint32_t k = 99;
        const LightFrustumResult r = light_frustum_fit(in, &k, 1);
        REQUIRE(r.status == Status::Ok);
        CHECK(r.needed == 1);
        CHECK(k == 0);
        CHECK(in_clip(r.view_proj, glm::dvec3(p) + glm::dvec3(20, 0, 0), in.light_depth, 1e-3));
        in.stable = true;
        const LightFrustumResult rs = light_frustum_fit(in, &k, 1);
        CHECK(rs.status == Status::Ok);
        CHECK(in_clip(rs.view_proj, glm::dvec3(p) + glm::dvec3(20, 0, 0), in.light_depth, 1e-3));
        // zero-size bounds at 1e6, stable: the window (2 r * 1e-6 wide, texel 2.4e-8) is far below
        // float spacing there (0.06), the float matrix cannot place the point: Overflow, never an Ok
        // that misplaces the receivers. The tight fit pads its window to 1e-6 of the coordinates: Ok.
        in.scene_min = in.scene_max = p + glm::vec3(10, 0, 0);
        const LightFrustumResult tiny = light_frustum_fit(in, &k, 1);
        CHECK(tiny.status == Status::Overflow);
        in.stable = false;
        const LightFrustumResult tight = light_frustum_fit(in, &k, 1);
        REQUIRE(tight.status == Status::Ok);
        CHECK(in_clip(tight.view_proj, glm::dvec3(in.scene_min), in.light_depth, 1e-2));
    }
    SUBCASE("zero-size scene bounds and zero-size casters") {
        LightFrustumInput in = base;
        in.has_scene_bounds = true;
        in.scene_min = in.scene_max = glm::vec3(0, 2, -5);
        const float box[6] = {0, 5, -5, 0, 5, -5};           // a point above the receiver point: shadows it
        const float box2[6] = {30, 5, -5, 30, 5, -5};        // off to the side: culled
        float boxes[12];
        for (int i = 0; i < 6; ++i) { boxes[i] = box[i]; boxes[6 + i] = box2[i]; }
        in.casters = boxes;
        in.caster_count = 2;
        std::uint32_t k[2] = {9, 9};
        for (int stable = 0; stable < 2; ++stable) {
            in.stable = stable != 0;
            const LightFrustumResult r = light_frustum_fit(in, k, 2);
            REQUIRE(r.status == Status::Ok);
            CHECK(r.visible);
            CHECK(r.needed == 1);
            CHECK(k[0] == 0);
            CHECK(in_clip(r.view_proj, glm::dvec3(0, 2, -5), in.light_depth));
        }
        in.scene_min = in.scene_max = glm::vec3(0, 2, 5);  // behind the camera: not visible (was EmptyReceivers)
        const LightFrustumResult e = light_frustum_fit(in, k, 2);
        CHECK(e.status == Status::Ok);
        CHECK_FALSE(e.visible);
        CHECK(e.culled_count == 2);
        CHECK(e.needed == 0);
    }
    SUBCASE("NaN / Inf / invalid inputs give a status, never a NaN matrix") {
        const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
        LightFrustumInput in = base;
        in.camera_view[1][2] = nan;
        CHECK(light_frustum_fit(in, nullptr, 0).status == Status::NonFinite);
        in = base;
        in.light_position = glm::vec4(inf, 0, 0, 0);
        CHECK(light_frustum_fit(in, nullptr, 0).status == Status::InvalidLight);
        in = base;
        in.light_position = glm::vec4(0, 0, 0, 0);
        CHECK(light_frustum_fit(in, nullptr, 0).status == Status::InvalidLight);
        in = base;
        in.camera_proj = glm::mat4(0.0f);
        CHECK(light_frustum_fit(in, nullptr, 0).status == Status::InvalidArgument);
        in = base;
        in.max_distance = nan;
        CHECK(light_frustum_fit(in, nullptr, 0).status == Status::NonFinite);
        in = base;
        const float bad[12] = {nan, 0, 0, 1, 1, 1, 1, 1, 1, 0, 0, 0};  // NaN box, min > max box
        in.casters = bad;
        in.caster_count = 2;
        const LightFrustumResult r = light_frustum_fit(in, nullptr, 0);
        CHECK(r.status == Status::Ok);
        CHECK(r.invalid_count == 2);
        CHECK(r.culled_count == 2);
    }
    SUBCASE("casters behind the camera that shadow the view are kept (light from behind)") {
        LightFrustumInput in = base;
        in.light_position = glm::vec4(glm::normalize(glm::vec3(0, 1, 1)), 0);  // travels forward and down
        const float box[6] = {-1, 6, 3, 1, 8, 5};                                // above and behind the camera
        in.casters = box;
        in.caster_count = 1;
        std::uint32_t k = 9;
        const LightFrustumResult r = light_frustum_fit(in, &k, 1);
        CHECK(r.needed == 1);
        CHECK(in_clip(r.view_proj, glm::dvec3(0, 7, 4), in.light_depth, 1e-3));
    }
}

// Issue 14 "must hold" for the light-frustum fits: no jump, no collapse when the light direction
// turns through the view direction. The old fits picked the light's up vector with the world axis
// least aligned with the light, which switches axis when two components of the direction are equal:
// the map rolls by 90 degrees in one step (receivers jump by up to ~1.4 NDC).
TEST_CASE("light_frustum: continuity of every fit while the light turns through the view direction (issue 14)") {
    std::mt19937 rng(20240514);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    SweepStats tight, stable, bounded, point;
    const glm::dvec3 up_travel(0.0, 1.0, 0.0);  // the stable fit's singular travel direction
    for (int cs = 0; cs < 8; ++cs) {
        Cam cam = random_camera(rng, true, 30.0f);
        if (cs == 0) {  // the camera
            cam.pos = glm::vec3(0, 10, 0);
            cam.fwd = glm::normalize(glm::vec3(0, -0.2f, -1));
            cam.view = look(cam.pos, cam.fwd);
        }
        LightFrustumInput in;
        set_camera(in, cam);
        if (in.max_distance == 0.0f) in.max_distance = std::fmin(cam.farp, 60.0f);
        in.shadow_map_size = 2048;
        const glm::dvec3 v = glm::normalize(glm::dvec3(cam.fwd));
        glm::dvec3 w = glm::normalize(glm::cross(v, glm::dvec3(random_dir(rng))));  // sweep plane through v
        if (cs == 1) w = glm::normalize(glm::cross(v, glm::dvec3(0, 1, 0)));       // horizontal sweep
        // receiver points: inside the slice, and inside the scene box for the bounded fits
        const LightFrustumCorners sc = light_frustum_slice_corners(in);
        REQUIRE(sc.status == Status::Ok);
        // the scene box: the bounds of a part of the slice (u, v in [0.2, 0.7], depth in [0.1, 0.4])
        std::vector<glm::dvec3> pts, bpts;
        glm::vec3 bmin(1e30f), bmax(-1e30f);
        for (int k = 0; k < 8; ++k) {
            const glm::vec3 q(lerp3(sc.corners, (k & 1) ? 0.7 : 0.2, (k & 2) ? 0.7 : 0.2, (k & 4) ? 0.4 : 0.1));
            bmin = glm::min(bmin, q);
            bmax = glm::max(bmax, q);
        }
        for (int k = 0; k < 48; ++k) {
            pts.push_back(lerp3(sc.corners, u(rng), u(rng), u(rng)));
            bpts.push_back(lerp3(sc.corners, 0.2 + 0.5 * u(rng), 0.2 + 0.5 * u(rng), 0.1 + 0.3 * u(rng)));
        }
        auto directional = [&](bool st, bool bounds) {
            return [&in, st, bounds, bmin, bmax](const glm::dvec3& d, glm::mat4& m) {
                LightFrustumInput x = in;
                x.stable = st;
                x.has_scene_bounds = bounds;
                x.scene_min = bmin;
                x.scene_max = bmax;
                x.light_position = glm::vec4(glm::vec3(-d), 0.0f);
                const LightFrustumResult r = light_frustum_fit(x, nullptr, 0);
                REQUIRE(r.status == Status::Ok);
                m = r.view_proj;
                return r.visible;
            };
        };
        auto ex_parallel = [&](const glm::dvec3& d) { return near_dir(d, v, 0.5) || near_dir(d, -v, 0.5); };
        auto ex_stable = [&](const glm::dvec3& d) { return ex_parallel(d) || near_dir(d, up_travel, 0.5); };
        sweep(directional(false, false), ex_parallel, v, w, pts, tight, "tight directional");
        sweep(directional(false, true), ex_parallel, v, w, bpts, tight, "tight directional, bounded");
        sweep(directional(true, false), ex_stable, v, w, pts, stable, "stable directional");
        sweep(directional(true, true), ex_stable, v, w, bpts, bounded, "stable directional, bounded");
        // point light: on a sphere around the slice's center, its direction to the center = d
        glm::dvec3 c(0.0);
        double rad = 0.0;
        for (const glm::vec3& k : sc.corners) c += glm::dvec3(k) / 8.0;
        for (const glm::vec3& k : sc.corners) rad = std::fmax(rad, glm::length(glm::dvec3(k) - c));
        auto point_fit = [&in, c, rad](const glm::dvec3& d, glm::mat4& m) {
            LightFrustumInput x = in;
            x.light_position = glm::vec4(glm::vec3(c - 3.0 * rad * d), 1.0f);
            const LightFrustumResult r = light_frustum_fit(x, nullptr, 0);
            REQUIRE(r.status == Status::Ok);
            m = r.view_proj;
            return r.visible;
        };
        sweep(point_fit, ex_parallel, v, w, pts, point, "point light");
    }
    // the stable fit's singular direction: a light shining straight up; what it does around it
    {
        LightFrustumInput in;
        in.camera_view = look(glm::vec3(0, 5, 0), glm::normalize(glm::vec3(1, 0.3f, 0)));
        in.camera_proj = glm::perspective(1.0f, 1.0f, 0.1f, 50.0f);
        in.stable = true;
        const LightFrustumCorners sc = light_frustum_slice_corners(in);
        std::vector<glm::dvec3> pts;
        for (int k = 0; k < 48; ++k) pts.push_back(lerp3(sc.corners, u(rng), u(rng), u(rng)));
        SweepStats pole;
        auto fit = [&in](const glm::dvec3& d, glm::mat4& m) {
            LightFrustumInput x = in;
            x.light_position = glm::vec4(glm::vec3(-d), 0.0f);
            const LightFrustumResult r = light_frustum_fit(x, nullptr, 0);
            REQUIRE(r.status == Status::Ok);
            m = r.view_proj;
            return r.visible;
        };
        auto ex = [](const glm::dvec3& d) { return near_dir(d, glm::dvec3(0, 1, 0), 0.5); };
        sweep(fit, ex, glm::dvec3(0, 1, 0), glm::dvec3(0.6, 0, 0.8), pts, pole, "stable, through its singular direction");
        MESSAGE("stable fit through straight-up light: max move outside 0.5 deg " << pole.max_move
                                                                                 << " NDC, inside " << pole.max_move_exempt);
    }
    const SweepStats* all[4] = {&tight, &stable, &bounded, &point};
    const char* names[4] = {"tight directional", "stable", "stable bounded", "point"};
    for (int k = 0; k < 4; ++k) {
        const SweepStats& s = *all[k];
        MESSAGE(std::string(names[k]) << ": fits " << s.fits << ", fine steps " << s.fine_steps << " (coarse steps refined "
                                      << s.refined << "), max move " << s.max_move
                     << " NDC (within 0.5 deg of parallel: " << s.max_move_exempt << "), max extent change in 0.01 deg "
                     << s.max_extent_change * 100 << "%");
        CHECK(s.failures == 0);
        CHECK(s.fine_steps > 10000);
    }
}

// Issue 13 (composition): a point light just above a wide bounded scene was rejected with
// LightInsideVolume although a frustum pointing straight down holds every receiver (and
// perspective_shadow_maps.hpp's uniform fit accepts the same light): the fit aimed its axis at the
// mean of the receiver volume's vertices, which the far corners of the camera slice pull away from
// the light's foot, so near receivers came out beyond 89.4 degrees. The axis is now that of the
// narrowest cone around the light holding the receivers (detail::cone_axis; the warps start from it too).
// Expected: Ok whenever a straight-down frustum with per-axis tangents <= 20 exists (closed form:
// the light is e above the box top, every box point within 20 e horizontally), and every receiver
// point inside the slice maps into the fitted clip volume.
TEST_CASE("light_frustum: a point light just above a wide scene gets one frustum (issue 13 composition)") {
    std::mt19937 rng(1313);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    int runs = 0, fitted = 0, points = 0;
    for (int it = 0; it < 600; ++it) {
        const float a = 2.0f + 8.0f * u(rng), b = 2.0f + 8.0f * u(rng), h = 0.5f + 3.0f * u(rng);
        const glm::vec3 lo(-a, 0.0f, -b), hi(a, h, b);
        const glm::vec3 L(a * (u(rng) - 0.5f), 0.0f, b * (u(rng) - 0.5f));
        // the least height above the top for which straight down has per-axis tangents <= 20
        const float reach = std::max(std::max(a + std::fabs(L.x), b + std::fabs(L.z)), 1e-3f);
        const float e = reach / 20.0f * (1.0f + 3.0f * u(rng));
        const glm::vec3 light(L.x, h + e, L.z);
        LightFrustumInput in;
        const glm::vec3 eye(a * (u(rng) - 0.5f), h + 2.0f + 4.0f * u(rng), b + 2.0f + 6.0f * u(rng));
        in.camera_view = glm::lookAt(eye, glm::vec3(0.0f, 0.5f * h, 0.0f), glm::vec3(0, 1, 0));
        in.camera_proj = glm::infinitePerspective(glm::radians(40.0f + 40.0f * u(rng)), 1.0f + u(rng), 0.1f);
        in.max_distance = 100.0f;
        in.has_scene_bounds = true;
        in.scene_min = lo;
        in.scene_max = hi;
        in.light_position = glm::vec4(light, 1.0f);
        ++runs;
        const LightFrustumResult r = light_frustum_fit(in, nullptr, 0);
        if (r.status != Status::Ok) {
            FAIL_CHECK("it=" << it << ": " << std::string(status_name(r.status)) << " for a light " << e << " above a " << 2 * a << " x "
                             << 2 * b << " scene");
            continue;
        }
        if (!r.visible) continue;
        ++fitted;
        const glm::mat4 vp = in.camera_proj * in.camera_view;
        for (int k = 0; k < 400; ++k) {
            const glm::vec3 p = lo + (hi - lo) * glm::vec3(u(rng), u(rng), u(rng));
            const glm::vec4 c = vp * glm::vec4(p, 1.0f);
            const float d = -(in.camera_view * glm::vec4(p, 1.0f)).z;
            if (!(c.w > 0.0f) || std::fabs(c.x) > c.w || std::fabs(c.y) > c.w || d < 0.1f || d > in.max_distance) continue;
            ++points;
            if (!in_clip(r.view_proj, glm::dvec3(p), in.light_depth)) {
                FAIL_CHECK("it=" << it << ": receiver outside the light's clip volume");
                break;
            }
        }
    }
    MESSAGE("wide scenes: " << runs << " runs, " << fitted << " fitted, " << points << " receiver points checked");
    CHECK(fitted > 500);
}

// Issue 13 (composition): the directional fits put the light view's eye inside the receiver volume
// (tight: at its centroid; stable: at the world origin), so -(view * p).z, the linear light depth
// that smoothie.glsl, linear-depth maps and pcss_fit_near_plane read as a distance from the light,
// was negative for part of the scene (near_z -3.3 to -5.6 on the composition scene) and
// smoothies lit every receiver there. Now every receiver and kept caster lies in front of the eye
// (near_z > 0), the eye moves only along the light's axis (view_proj's x and y rows, hence the
// stable fit's texel grid, are those of the plain fit), and view_proj still holds every receiver.
TEST_CASE("light_frustum: directional fits keep every receiver and caster in front of the light's eye (issue 13)") {
    std::mt19937 rng(4242);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    int fits = 0, points = 0;
    for (int it = 0; it < 400; ++it) {
        LightFrustumInput in;
        const glm::vec3 off(200.0f * (u(rng) - 0.5f), 20.0f * u(rng), 200.0f * (u(rng) - 0.5f));
        const glm::vec3 eye = off + glm::vec3(10.0f * (u(rng) - 0.5f), 2.0f + 8.0f * u(rng), 10.0f * (u(rng) - 0.5f));
        in.camera_view = glm::lookAt(eye, off + glm::vec3(u(rng) - 0.5f, 0.0f, u(rng) - 0.5f), glm::vec3(0, 1, 0));
        in.camera_proj = glm::infinitePerspective(1.0f, 1.5f, 0.1f);
        in.max_distance = 20.0f + 40.0f * u(rng);
        in.has_scene_bounds = rng() % 2 == 0;
        in.scene_min = off - glm::vec3(30.0f, 1.0f, 30.0f);
        in.scene_max = off + glm::vec3(30.0f, 15.0f, 30.0f);
        const float box[6] = {off.x - 1, off.y, off.z - 1, off.x + 1, off.y + 12, off.z + 1};  // a tower
        in.casters = box;
        in.caster_count = 1;
        const glm::vec3 to_light = glm::normalize(glm::vec3(2.0f * u(rng) - 1.0f, 0.2f + u(rng), 2.0f * u(rng) - 1.0f));
        in.light_position = glm::vec4(to_light, 0.0f);
        in.stable = rng() % 2 == 0;
        in.light_depth = rng() % 2 ? ClipDepth::ZeroToOne : ClipDepth::NegativeOneToOne;
        in.light_reversed_z = rng() % 2 == 0;
        std::uint32_t keep = 0;
        const LightFrustumResult r = light_frustum_fit(in, &keep, 1);
        REQUIRE(r.status == Status::Ok);
        if (!r.visible) continue;
        ++fits;
        CHECK_MESSAGE(r.near_z > 0.0f, "it=" << it << ": near_z " << r.near_z);
        CHECK(r.far_z > r.near_z);
        // the kept caster's corners and the receivers in the slice: positive light depth, inside the map
        const glm::mat4 cvp = in.camera_proj * in.camera_view;
        for (int k = 0; k < 300; ++k) {
            const glm::vec3 lo = in.has_scene_bounds ? in.scene_min : eye - glm::vec3(60.0f);
            const glm::vec3 hi = in.has_scene_bounds ? in.scene_max : eye + glm::vec3(60.0f);
            const glm::vec3 p = lo + (hi - lo) * glm::vec3(u(rng), u(rng), u(rng));
            const glm::vec4 c = cvp * glm::vec4(p, 1.0f);
            const float dep = -(in.camera_view * glm::vec4(p, 1.0f)).z;
            if (!(c.w > 0.0f) || std::fabs(c.x) > c.w || std::fabs(c.y) > c.w || dep < 0.1f || dep > in.max_distance) continue;
            ++points;
            CHECK(-(r.view * glm::vec4(p, 1.0f)).z >= r.near_z * (1.0f - 1e-5f) - 1e-4f);
            CHECK(in_clip(r.view_proj, glm::dvec3(p), in.light_depth));
        }
        if (r.needed == 1)
            for (int c = 0; c < 8; ++c) {
                const glm::vec3 q(box[(c & 1) ? 3 : 0], box[(c & 2) ? 4 : 1], box[(c & 4) ? 5 : 2]);
                CHECK(-(r.view * glm::vec4(q, 1.0f)).z > 0.0f);
            }
    }
    MESSAGE("directional eye placement: " << fits << " fits, " << points << " receiver points");
    CHECK(fits > 300);
}

// ------------------------------------------------------------------ light_frustum_fit_casters
namespace {

// Clip position of p through the float matrix a vertex shader uses, and whether it lies in the
// clip volume of depth convention cd within a relative tolerance.
bool caster_fit_inside(const glm::mat4& vp, const glm::vec3& p, ClipDepth cd, float tol, float* depth01 = nullptr) {
    const glm::vec4 c = vp * glm::vec4(p, 1.0f);
    if (!(c.w > 0.0f)) return false;
    const float x = c.x / c.w, y = c.y / c.w, z = c.z / c.w;
    const float zlo = cd == ClipDepth::ZeroToOne ? 0.0f : -1.0f;
    if (depth01) *depth01 = cd == ClipDepth::ZeroToOne ? z : 0.5f * z + 0.5f;
    return std::fabs(x) <= 1.0f + tol && std::fabs(y) <= 1.0f + tol && z >= zlo - tol && z <= 1.0f + tol;
}

}  // namespace

TEST_CASE("light_frustum_fit_casters: closed form (a point light above a box, a sun)") {
    LightCasterFitInput in;
    in.light_position = glm::vec4(0.0f, 5.0f, 0.0f, 1.0f);
    in.caster_min = glm::vec3(-1.0f, 0.0f, -1.0f);
    in.caster_max = glm::vec3(1.0f, 1.0f, 1.0f);
    in.receiver_min = glm::vec3(-4.0f, 0.0f, -4.0f);
    in.receiver_max = glm::vec3(4.0f, 1.0f, 4.0f);
    LightFrustumResult r = light_frustum_fit_casters(in);
    REQUIRE(r.status == Status::Ok);
    // straight down at the box's center (0, 0.5, 0); nearest corner depth 4, widest tan 1/4
    CHECK(r.near_z == doctest::Approx(0.9 * 4.0));
    CHECK(r.far_z == doctest::Approx(1.01 * 5.0));
    CHECK(r.proj[0][0] == doctest::Approx(1.0 / (1.02 * 0.25)).epsilon(3e-5));  // cot(half) = 1 / (1.02 tan_max) (+ 64 ulps of 5 / 4)
    // the floor right under a caster corner's silhouette lies at x = 1 * 5 / 4 = 1.25: inside; 1.4 is outside
    CHECK(caster_fit_inside(r.view_proj, glm::vec3(1.25f, 0.0f, 0.0f), in.light_depth, 0.0f));
    CHECK(!caster_fit_inside(r.view_proj, glm::vec3(1.4f, 0.0f, 0.0f), in.light_depth, 0.0f));
    // an emitter of radius 1 widens the cone by atan(1 / 4) at the nearest corner
    in.emitter_radius_world = 1.0f;
    r = light_frustum_fit_casters(in);
    REQUIRE(r.status == Status::Ok);
    CHECK(r.proj[0][0] == doctest::Approx(1.0 / (1.02 * 0.25 + 0.25)).epsilon(3e-5));
    // a sun: the window is the box across the light, the depth spans the receivers
    in = LightCasterFitInput{};
    in.light_position = glm::vec4(0.0f, 1.0f, 0.0f, 0.0f);
    in.caster_min = glm::vec3(-1.0f, 0.0f, -2.0f);
    in.caster_max = glm::vec3(1.0f, 1.0f, 2.0f);
    in.receiver_min = glm::vec3(-10.0f, -3.0f, -10.0f);
    in.receiver_max = glm::vec3(10.0f, 1.0f, 10.0f);
    r = light_frustum_fit_casters(in);
    REQUIRE(r.status == Status::Ok);
    CHECK(2.0 / double(r.proj[0][0]) == doctest::Approx(2.0).epsilon(3e-4));  // x extent: the box's 2 units (+ 1e-4 a side)
    CHECK(2.0 / double(r.proj[1][1]) == doctest::Approx(4.0).epsilon(3e-4));  // y extent: its 4 units (light down: map y = -z)
    CHECK(r.far_z - r.near_z == doctest::Approx(4.0).epsilon(0.02));  // receivers from y = 1 down to -3 (+ 1e-3 of the diagonal)
    CHECK(r.near_z > 0.0f);                                                  // the eye before every receiver
}

TEST_CASE("property: light_frustum_fit_casters holds every caster and every shadow it throws (thousands of lights, scales, conventions)") {
    // Independent check by sampling: each caster box corner maps inside the clip volume through the
    // float view_proj; for point lights, points on the shadows' rays (from the light, or from a point of
    // an emitter of radius r, through a random caster point, on to the receivers' box) map inside too;
    // every receiver corner's depth is within the map's range (no receiver clipped away by far).
    std::mt19937 rng(2027);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    int ok = 0, inside_volume = 0, points = 0;
    const float scales[] = {1e-6f, 1e-3f, 1.0f, 1e3f, 1e6f};
    for (int it = 0; it < 4000; ++it) {
        const float s = scales[rng() % 5];
        const glm::vec3 off = (rng() % 2) ? glm::vec3(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f) * 100.0f * s : glm::vec3(0.0f);
        LightCasterFitInput in;
        const glm::vec3 c0 = (glm::vec3(u(rng), u(rng), u(rng)) * 4.0f - 2.0f) * s + off;
        const glm::vec3 c1 = c0 + glm::vec3(u(rng), u(rng), u(rng)) * 2.0f * s;
        in.caster_min = c0;
        in.caster_max = c1;
        in.receiver_min = glm::min(c0, glm::vec3(-5.0f, -1.0f, -5.0f) * s + off);
        in.receiver_max = glm::max(c1, glm::vec3(5.0f, 3.0f, 5.0f) * s + off);
        const bool directional = rng() % 3 == 0;
        const glm::vec3 dir = glm::normalize(glm::vec3(u(rng) - 0.5f, u(rng) + 0.02f, u(rng) - 0.5f));
        const float dist = (2.0f + 20.0f * u(rng)) * s;
        in.light_position = directional ? glm::vec4(dir, 0.0f) : glm::vec4(0.5f * (c0 + c1) + dir * dist, 1.0f);
        in.emitter_radius_world = directional || rng() % 2 ? 0.0f : u(rng) * 0.5f * s;
        in.light_depth = rng() % 2 ? ClipDepth::ZeroToOne : ClipDepth::NegativeOneToOne;
        in.light_reversed_z = rng() % 2 == 0;
        const LightFrustumResult r = light_frustum_fit_casters(in);
        if (r.status == Status::LightInsideVolume) {
            ++inside_volume;
            CHECK(!directional);
            continue;
        }
        REQUIRE(r.status == Status::Ok);
        ++ok;
        CHECK(r.visible);
        CHECK((r.near_z > 0.0f && r.near_z < r.far_z));
        const float tol = 1e-4f;
        for (int c = 0; c < 8; ++c) {
            const glm::vec3 p((c & 1) ? c1.x : c0.x, (c & 2) ? c1.y : c0.y, (c & 4) ? c1.z : c0.z);
            INFO("scale " << s << " offset " << off.x << " light " << in.light_position.x << " " << in.light_position.y << " "
                          << in.light_position.z << " " << in.light_position.w << " corner " << p.x << " " << p.y << " " << p.z);
            CHECK(caster_fit_inside(r.view_proj, p, in.light_depth, 0.0f));  // in float, no tolerance
            const glm::vec3 q((c & 1) ? in.receiver_max.x : in.receiver_min.x, (c & 2) ? in.receiver_max.y : in.receiver_min.y,
                              (c & 4) ? in.receiver_max.z : in.receiver_min.z);
            const float d = -(r.view * glm::vec4(q, 1.0f)).z;  // light-view distance
            if (directional) CHECK((d >= r.near_z * (1.0f - tol) && d <= r.far_z * (1.0f + tol)));
            else if (d > 0.0f) CHECK(d <= r.far_z * (1.0f + tol));
        }
        if (directional) continue;
        const glm::vec3 L = glm::vec3(in.light_position);
        for (int k = 0; k < 16; ++k) {
            const glm::vec3 cp = c0 + glm::vec3(u(rng), u(rng), u(rng)) * (c1 - c0);
            glm::vec3 e(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f);
            e = glm::length(e) > 0.0f ? glm::normalize(e) * in.emitter_radius_world * u(rng) : glm::vec3(0.0f);
            const glm::vec3 from = L + e;  // a point of the emitter
            const glm::vec3 ray = cp - from;
            // past the caster point, up to the receivers' farthest depth from the light
            const float t = 1.0f + u(rng) * 0.9f * (r.far_z / 1.01f - glm::length(cp - L)) / glm::length(ray);
            const glm::vec3 p = from + ray * std::max(t, 1.0f);
            if (glm::length(p - L) > r.far_z * 0.99f) continue;
            ++points;
            INFO("scale " << s << " emitter " << in.emitter_radius_world);
            CHECK(caster_fit_inside(r.view_proj, p, in.light_depth, 1e-3f));
        }
    }
    MESSAGE(ok << " fits, " << inside_volume << " lights beside or inside their casters (LightInsideVolume), " << points
               << " shadow points checked");
    CHECK(ok > 3000);
    CHECK(points > 20000);
}

TEST_CASE("light_frustum_fit_casters: statuses (bad boxes, NaN, limits, the light among its casters, a cone too wide)") {
    LightCasterFitInput in;
    CHECK(light_frustum_fit_casters(in).status == Status::InvalidArgument);  // defaults: empty boxes
    in.caster_min = glm::vec3(-1.0f);
    in.caster_max = glm::vec3(1.0f);
    in.receiver_min = glm::vec3(-5.0f);
    in.receiver_max = glm::vec3(5.0f);
    CHECK(light_frustum_fit_casters(in).status == Status::InvalidLight);  // (0, 0, 0, 0)
    in.light_position = glm::vec4(0.0f, 10.0f, 0.0f, -1.0f);
    CHECK(light_frustum_fit_casters(in).status == Status::InvalidLight);
    in.light_position = glm::vec4(0.0f, 10.0f, 0.0f, 1.0f);
    CHECK(light_frustum_fit_casters(in).status == Status::Ok);
    LightCasterFitInput b = in;
    b.caster_max.x = std::numeric_limits<float>::quiet_NaN();
    CHECK(light_frustum_fit_casters(b).status == Status::NonFinite);
    b = in;
    b.emitter_radius_world = -1.0f;
    CHECK(light_frustum_fit_casters(b).status == Status::InvalidArgument);
    b = in;
    b.max_half_angle_radians = 1.6f;
    CHECK(light_frustum_fit_casters(b).status == Status::InvalidArgument);
    b = in;
    b.min_near_ratio = 0.0f;
    CHECK(light_frustum_fit_casters(b).status == Status::InvalidArgument);
    b = in;
    b.light_position = glm::vec4(0.0f, 0.5f, 0.0f, 1.0f);  // inside the casters' box
    CHECK(light_frustum_fit_casters(b).status == Status::LightInsideVolume);
    b.light_position = glm::vec4(0.0f, 1.0f, 0.0f, 1.0f);  // on its top face: corners beside the light
    CHECK(light_frustum_fit_casters(b).status == Status::LightInsideVolume);
    b.light_position = glm::vec4(0.0f, 1.12f, 0.0f, 1.0f);  // just above: a half angle of atan(1.02 / 0.12) = 1.454
    CHECK(light_frustum_fit_casters(b).status == Status::LightInsideVolume);
    b.max_half_angle_radians = 1.5f;
    CHECK(light_frustum_fit_casters(b).status == Status::Ok);
    // a box 1e-44 from a light at the origin (fuzz_light_frustum): in double every corner is in front
    // and the cone is 0.24 rad wide, but float rounds the nearest corner's clip w to 0
    b = in;
    b.light_position = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
    b.caster_min = glm::vec3(2.8026e-45f, 0.0f, 0.0f);
    b.caster_max = glm::vec3(2.8026e-45f, 0.0f, 2.24208e-44f);
    CHECK(light_frustum_fit_casters(b).status == Status::LightInsideVolume);
    b.caster_min *= 1e20f;  // the same shape scaled to 1e-24 away: float holds it
    b.caster_max *= 1e20f;
    b.max_half_angle_radians = 1.5f;
    CHECK(light_frustum_fit_casters(b).status == Status::Ok);
    // reversed-Z, zero-to-one: the near plane maps to 1, the far plane to 0
    b = in;
    b.light_depth = ClipDepth::ZeroToOne;
    b.light_reversed_z = true;
    const LightFrustumResult r = light_frustum_fit_casters(b);
    REQUIRE(r.status == Status::Ok);
    const glm::vec4 n = r.proj * glm::vec4(0.0f, 0.0f, -r.near_z, 1.0f), f = r.proj * glm::vec4(0.0f, 0.0f, -r.far_z, 1.0f);
    CHECK(n.z / n.w == doctest::Approx(1.0).epsilon(1e-5));
    CHECK(f.z / f.w == doctest::Approx(0.0).epsilon(1e-5));
}
