// Unit and property tests for shadowkit/perspective_shadow_maps.hpp.
// References: closed-form frustum corners and aliasing footprint, brute-force ray casting for
// "which caster points shadow a receiver", sampling for containment and depth order.
#include <shadowkit/perspective_shadow_maps.hpp>

#include <doctest/doctest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <initializer_list>
#include <limits>
#include <random>
#include <string>

using namespace shadowkit;

namespace {

using Method = WarpResult (*)(const WarpInput&);
const Method kMethods[4] = {uniform_shadow_matrix, psm_shadow_matrix, lispsm_shadow_matrix, tsm_shadow_matrix};
const std::string kNames[4] = {"uniform", "psm", "lispsm", "tsm"};

glm::mat4 make_proj(float fovy, float aspect, float n, float f, ClipDepth cd, bool rev, bool inf) {
    const float t = 1.0f / std::tan(fovy * 0.5f);
    glm::mat4 m(0.0f);
    m[0][0] = t / aspect;
    m[1][1] = t;
    m[2][3] = -1.0f;
    double zn, zf;
    if (cd == ClipDepth::ZeroToOne) { zn = rev ? 1 : 0; zf = rev ? 0 : 1; }
    else { zn = rev ? 1 : -1; zf = rev ? -1 : 1; }
    double a, b;
    if (inf) { a = -zf; b = (zn - zf) * n; }
    else {
        const double B = (zn - zf) * double(n) * f / (double(f) - n);
        a = -(zf - B / f);
        b = B;
    }
    m[2][2] = float(a);
    m[3][2] = float(b);
    return m;
}

struct Scene {
    WarpInput in;
    glm::dvec3 corners[8];  // receiver slice corners, closed form
};

glm::vec3 rdir(std::mt19937& rng) {
    std::normal_distribution<float> g(0.0f, 1.0f);
    glm::vec3 d;
    do { d = glm::vec3(g(rng), g(rng), g(rng)); } while (glm::length(d) < 1e-3f);
    return glm::normalize(d);
}

// camera at pos looking along fwd; slice corners from the closed form of the frustum
Scene make_scene(const glm::vec3& pos, const glm::vec3& fwd, float fovy, float aspect, float n, float f, bool inf,
                 float maxd, ClipDepth cd, bool rev, float rmin, float rmax) {
    Scene s;
    const glm::vec3 up = std::fabs(fwd.y) > 0.99f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    s.in.camera_view = glm::lookAt(pos, pos + fwd, up);
    s.in.camera_proj = make_proj(fovy, aspect, n, f, cd, rev, inf);
    s.in.camera_depth = cd;
    s.in.camera_reversed_z = rev;
    s.in.max_distance = maxd;
    s.in.receiver_min_depth = rmin;
    s.in.receiver_max_depth = rmax;
    double d0 = n, d1 = inf ? maxd : (maxd > 0 ? std::fmin(f, maxd) : f);
    if (rmax > rmin && rmin > 0) { d0 = std::fmax(d0, rmin); d1 = std::fmin(d1, rmax); }
    const glm::dmat4 iv = glm::inverse(glm::dmat4(s.in.camera_view));
    const double ty = std::tan(0.5 * double(fovy)), tx = ty * aspect;
    for (int i = 0; i < 8; ++i) {
        const double d = (i & 4) ? d1 : d0;
        const glm::dvec3 pv(((i & 1) ? 1 : -1) * tx * d, ((i & 2) ? 1 : -1) * ty * d, -d);
        s.corners[i] = glm::dvec3(iv * glm::dvec4(pv, 1.0));
    }
    return s;
}

glm::dvec3 sample_slice(const glm::dvec3 c[8], double u, double v, double t) {
    auto bil = [&](int o) { return glm::mix(glm::mix(c[o], c[o + 1], u), glm::mix(c[o + 2], c[o + 3], u), v); };
    return glm::mix(bil(0), bil(4), t);
}

bool in_box(const glm::dvec3& p, const glm::vec3& mn, const glm::vec3& mx) {
    return p.x >= mn.x && p.y >= mn.y && p.z >= mn.z && p.x <= mx.x && p.y <= mx.y && p.z <= mx.z;
}

// clip-space test; returns NDC depth through z_out
bool in_clip(const glm::mat4& m, const glm::dvec3& p, ClipDepth cd, double tol, double* z_out = nullptr) {
    const glm::dvec4 h = glm::dmat4(m) * glm::dvec4(p, 1.0);
    if (!(h.w > 0.0)) return false;
    const double x = h.x / h.w, y = h.y / h.w, z = h.z / h.w;
    if (z_out) *z_out = z;
    const double zlo = cd == ClipDepth::ZeroToOne ? 0.0 : -1.0;
    return std::fabs(x) <= 1 + tol && std::fabs(y) <= 1 + tol && z >= zlo - tol && z <= 1 + tol;
}

bool all_finite(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}

void slice_planes(const glm::dvec3 c[8], glm::dvec4 out[6]) {
    const int f[6][3] = {{0, 1, 2}, {4, 6, 5}, {0, 4, 1}, {2, 3, 6}, {0, 2, 4}, {1, 5, 3}};
    const glm::dvec3 ctr = (c[0] + c[7]) * 0.5;
    for (int i = 0; i < 6; ++i) {
        const glm::dvec3 n = glm::normalize(glm::cross(c[f[i][1]] - c[f[i][0]], c[f[i][2]] - c[f[i][0]]));
        glm::dvec4 p(n, -glm::dot(n, c[f[i][0]]));
        if (glm::dot(glm::dvec3(p), ctr) + p.w < 0) p = -p;
        out[i] = p;
    }
}

bool ray_hits(const glm::dvec4* pl, int np, const glm::dvec3& q, const glm::dvec3& dir, double tmax) {
    double t0 = 0.0, t1 = tmax;
    for (int i = 0; i < np; ++i) {
        const double s = glm::dot(glm::dvec3(pl[i]), q) + pl[i].w, ds = glm::dot(glm::dvec3(pl[i]), dir);
        if (ds == 0.0) { if (s < 0) return false; continue; }
        const double t = -s / ds;
        if (ds > 0) t0 = std::fmax(t0, t); else t1 = std::fmin(t1, t);
        if (t0 > t1) return false;
    }
    return true;
}

// Sample points of the NDC unit square (receivers) to compare matrices
glm::dvec2 ndc_xy(const glm::mat4& m, const glm::dvec3& p) {
    const glm::dvec4 h = glm::dmat4(m) * glm::dvec4(p, 1.0);
    return glm::dvec2(h) / h.w;
}

WarpInput outdoor(float light_angle_deg_from_view, float nearp = 1.0f, float farp = 100.0f) {
    // camera at 2 wu looking along -z; light in the y-z plane at the given angle from the view direction
    WarpInput in;
    in.camera_view = glm::lookAt(glm::vec3(0, 2, 0), glm::vec3(0, 2, -1), glm::vec3(0, 1, 0));
    in.camera_proj = glm::perspective(1.0f, 16.0f / 9.0f, nearp, farp);
    const float a = glm::radians(light_angle_deg_from_view);
    in.light = glm::vec4(0.0f, -std::sin(a), -std::cos(a), 0.0f);
    in.has_scene_bounds = true;
    in.scene_min = glm::vec3(-200, 0, -200);
    in.scene_max = glm::vec3(200, 10, 200);
    return in;
}

}  // namespace

TEST_CASE("psm: aliasing error of a uniform map matches the closed form") {
    // camera looking straight down from height H onto the ground, ortho light straight down covering
    // W x W world units with S texels: a texel is W/S wu; a pixel at distance H covers 2 H tan(fov/2)/P wu.
    const double H = 10.0, W = 64.0, S = 1024.0, P = 800.0, fov = 1.0;
    const glm::mat4 cam = glm::perspective(float(fov), 1.0f, 0.1f, 100.0f) *
                          glm::lookAt(glm::vec3(0, H, 0), glm::vec3(0, 0, 0), glm::vec3(0, 0, -1));
    const glm::mat4 light = glm::ortho(-32.0f, 32.0f, -32.0f, 32.0f, 0.0f, 50.0f) *
                            glm::lookAt(glm::vec3(0, 20, 0), glm::vec3(0, 0, 0), glm::vec3(0, 0, -1));
    const double e = perspective_aliasing_error(light, cam, glm::vec3(0, 0, 0), glm::vec3(0, 1, 0), uint32_t(S), {800, 800});
    const double expected = (W / S) / (2.0 * H * std::tan(fov / 2) / P);
    CHECK(e == doctest::Approx(expected).epsilon(1e-4));
    // behind the camera / degenerate: +inf, never NaN
    CHECK(std::isinf(perspective_aliasing_error(light, cam, glm::vec3(0, 20, 0), glm::vec3(0, 1, 0), 1024, {800, 800})));
    CHECK(std::isinf(perspective_aliasing_error(glm::mat4(0.0f), cam, glm::vec3(0), glm::vec3(0, 1, 0), 1024, {800, 800})));
    const float nan = std::numeric_limits<float>::quiet_NaN();
    CHECK(std::isinf(perspective_aliasing_error(light, cam, glm::vec3(nan), glm::vec3(0, 1, 0), 1024, {800, 800})));
}

TEST_CASE("psm: warps reduce the max perspective aliasing error (camera perpendicular to the light)") {
    struct Cfg { float angle, nearp, farp; };
    for (const Cfg c : {Cfg{90.0f, 1.0f, 100.0f}, Cfg{90.0f, 0.1f, 100.0f}, Cfg{60.0f, 0.5f, 200.0f}, Cfg{30.0f, 1.0f, 100.0f}}) {
        const WarpInput in = outdoor(c.angle, c.nearp, c.farp);
        double mx[4];
        for (int m = 0; m < 4; ++m) {
            const WarpResult r = kMethods[m](in);
            REQUIRE(r.status == WarpStatus::Ok);
            if (m != 1 || c.angle == 90.0f) CHECK_FALSE(r.fallback_uniform);  // PSM may fall back (wide light frustum)
            const AliasingStats a = measure_perspective_aliasing(in, r.light_view_proj, 2048, {1920, 1080}, 24, 24, 32);
            mx[m] = a.max_error;
            MESSAGE("light " << c.angle << " deg from view, near " << c.nearp << ", far " << c.farp << ", 2048^2 map, 1920x1080: "
                             << kNames[m] << " max " << a.max_error << " mean " << a.mean_error << " undersampled "
                             << a.undersampled_fraction);
        }
        if (c.angle == 90.0f) {
            CHECK(mx[2] < 0.5 * mx[0]);  // LiSPSM
            CHECK(mx[3] < 0.5 * mx[0]);  // TSM
            CHECK(mx[1] < 0.5 * mx[0]);  // PSM
        } else {
            CHECK(mx[2] < mx[0]);
            CHECK(mx[3] < mx[0]);
        }
    }
}

TEST_CASE("psm: containment, depth order and no NaN over thousands of random cameras and lights") {
    std::mt19937 rng(2024);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    int fitted[4] = {0, 0, 0, 0}, fallbacks[4] = {0, 0, 0, 0}, recv_pts = 0, caster_pts = 0, order_pairs = 0;
    const int N = 1500;
    for (int it = 0; it < N; ++it) {
        const glm::vec3 pos = glm::vec3(u(rng) - 0.5f, u(rng) * 0.3f, u(rng) - 0.5f) * 60.0f;
        const glm::vec3 fwd = rdir(rng);
        const float n = 0.05f + 2.0f * u(rng), f = n * (5.0f + 300.0f * u(rng));
        const bool inf = rng() % 5 == 0;
        const float maxd = inf ? f : 0.0f;
        const ClipDepth cd = (rng() & 1) ? ClipDepth::ZeroToOne : ClipDepth::NegativeOneToOne;
        float rmin = 0, rmax = 0;
        if (rng() % 3 == 0) { rmin = n * (1 + 2 * u(rng)); rmax = rmin + f * u(rng); }
        Scene sc = make_scene(pos, fwd, 0.4f + 1.3f * u(rng), 0.6f + 1.4f * u(rng), n, f, inf, maxd, cd, (rng() & 2) != 0, rmin, rmax);
        WarpInput& in = sc.in;
        const bool point = rng() % 4 == 0;
        in.light = point ? glm::vec4(glm::vec3(u(rng) - 0.5f, 0.2f + u(rng), u(rng) - 0.5f) * 200.0f, 1.0f)
                         : glm::vec4(rdir(rng), 0.0f);
        in.has_scene_bounds = rng() % 3 != 0;
        in.scene_min = glm::vec3(-80, -5, -80) + glm::vec3(u(rng), 0.2f * u(rng), u(rng)) * 20.0f;
        in.scene_max = glm::vec3(80, 20, 80) - glm::vec3(u(rng), u(rng), u(rng)) * 10.0f;
        in.has_caster_bounds = rng() % 2 == 0;
        in.caster_min = in.scene_min - glm::vec3(0, 0, 0);
        in.caster_max = in.scene_max + glm::vec3(0, 30.0f * u(rng), 0);
        in.light_depth = (rng() & 1) ? ClipDepth::ZeroToOne : ClipDepth::NegativeOneToOne;
        in.light_reversed_z = rng() % 4 == 0;
        const glm::vec3 cmn = in.has_caster_bounds ? in.caster_min : in.scene_min;
        const glm::vec3 cmx = in.has_caster_bounds ? in.caster_max : in.scene_max;
        const bool have_casters = in.has_caster_bounds || in.has_scene_bounds;
        glm::dvec4 pl[12];
        slice_planes(sc.corners, pl);
        int np = 6;
        if (in.has_scene_bounds) {
            pl[6] = {1, 0, 0, -in.scene_min.x}; pl[7] = {-1, 0, 0, in.scene_max.x};
            pl[8] = {0, 1, 0, -in.scene_min.y}; pl[9] = {0, -1, 0, in.scene_max.y};
            pl[10] = {0, 0, 1, -in.scene_min.z}; pl[11] = {0, 0, -1, in.scene_max.z};
            np = 12;
        }
        for (int m = 0; m < 4; ++m) {
            const WarpResult r = kMethods[m](in);
            REQUIRE(all_finite(r.light_view_proj));
            if (r.status != WarpStatus::Ok) {
                const bool ok_status = r.status == WarpStatus::EmptyReceivers || r.status == WarpStatus::LightInsideVolume;
                if (!ok_status) FAIL_CHECK(kNames[m] << ": status " << int(r.status) << " it=" << it);
                continue;
            }
            ++fitted[m];
            if (r.fallback_uniform) ++fallbacks[m];
            const double sgn = in.light_reversed_z ? -1.0 : 1.0;
            bool bad = false;
            for (int k = 0; k < 25 && !bad; ++k) {
                const glm::dvec3 p = sample_slice(sc.corners, u(rng), u(rng), u(rng));
                if (in.has_scene_bounds && !in_box(p, in.scene_min, in.scene_max)) continue;
                ++recv_pts;
                double zp = 0;
                if (!in_clip(r.light_view_proj, p, in.light_depth, 1e-4, &zp)) {
                    FAIL_CHECK(kNames[m] << ": receiver outside the light clip volume, it=" << it);
                    bad = true;
                    break;
                }
                if (!have_casters) continue;
                // a caster point on the segment towards the light: inside, and nearer in depth
                const glm::dvec3 tl = point ? glm::dvec3(in.light) - p : -glm::dvec3(in.light);
                const double tmax = point ? 1.0 : 1e4;
                const double t = tmax * double(u(rng)) * (point ? 1.0 : 0.01);
                const glm::dvec3 q = p + t * (point ? tl : glm::normalize(tl));
                if (!in_box(q, cmn, cmx)) continue;
                if (point && glm::length(q - glm::dvec3(in.light)) < 1e-3 * glm::length(tl)) continue;
                double zq = 0;
                ++order_pairs;
                if (!in_clip(r.light_view_proj, q, in.light_depth, 1e-4, &zq)) {
                    FAIL_CHECK(kNames[m] << ": shadowing caster point outside the light clip volume, it=" << it);
                    bad = true;
                    break;
                }
                if (sgn * (zq - zp) > 1e-6) {
                    FAIL_CHECK(kNames[m] << ": depth order along a light ray reversed, it=" << it);
                    bad = true;
                }
            }
            // caster points sampled in the caster bounds whose shadow ray meets the receiver volume
            for (int k = 0; k < 25 && have_casters && !bad; ++k) {
                const glm::dvec3 q(cmn.x + (cmx.x - cmn.x) * double(u(rng)), cmn.y + (cmx.y - cmn.y) * double(u(rng)),
                                   cmn.z + (cmx.z - cmn.z) * double(u(rng)));
                const glm::dvec3 dir = point ? q - glm::dvec3(in.light) : glm::dvec3(in.light);
                if (glm::length(dir) == 0.0 || !ray_hits(pl, np, q, glm::normalize(dir), 1e7)) continue;
                if (point) {
                    // skip points closer to the light than the body extends (1e-4 of the receiver range)
                    if (glm::length(dir) < 1e-3 * glm::length(glm::dvec3(sc.corners[7]) - glm::dvec3(in.light))) continue;
                }
                ++caster_pts;
                if (!in_clip(r.light_view_proj, q, in.light_depth, 1e-4)) {
                    FAIL_CHECK(kNames[m] << ": caster point that shadows a receiver is outside, it=" << it);
                    bad = true;
                }
            }
        }
    }
    for (int m = 0; m < 4; ++m) {
        MESSAGE(kNames[m] << ": fitted " << fitted[m] << " / " << N << ", fallback " << fallbacks[m]);
        CHECK(fitted[m] > N / 2);
    }
    MESSAGE("receiver samples " << recv_pts << ", caster samples " << caster_pts << ", depth-order pairs " << order_pairs);
}

TEST_CASE("psm: anchors - filament LiSPSM off within ~1 degree, DagorEngine TSM off at |cos gamma| >= 0.95") {
    // filament: sinLV <= 0.02 -> no LiSPSM. Ours: off below 0.02, fading to full strength at 0.04.
    CHECK(lispsm_shadow_matrix(outdoor(1.0f)).fallback_uniform);   // sin 1 deg = 0.0175
    CHECK(lispsm_shadow_matrix(outdoor(-1.0f)).fallback_uniform);
    CHECK_FALSE(lispsm_shadow_matrix(outdoor(3.0f)).fallback_uniform);  // sin 3 deg = 0.052
    CHECK(lispsm_shadow_matrix(outdoor(0.0f)).fallback_uniform);   // exactly parallel
    CHECK(lispsm_shadow_matrix(outdoor(180.0f)).fallback_uniform); // exactly anti-parallel
    // DagorEngine TSM: |cos gamma| >= 0.95 -> ortho
    const float a95 = glm::degrees(std::acos(0.96f)), a90 = glm::degrees(std::acos(0.89f));
    CHECK(tsm_shadow_matrix(outdoor(a95)).fallback_uniform);
    CHECK(tsm_shadow_matrix(outdoor(180.0f - a95)).fallback_uniform);
    CHECK_FALSE(tsm_shadow_matrix(outdoor(a90)).fallback_uniform);
    CHECK_FALSE(tsm_shadow_matrix(outdoor(180.0f - a90)).fallback_uniform);
    // thresholds are options
    WarpInput in = outdoor(a95);
    in.options.tsm_max_abs_cos_gamma = 0.99f;
    CHECK_FALSE(tsm_shadow_matrix(in).fallback_uniform);
    in = outdoor(1.0f);
    in.options.lispsm_min_sin_gamma = 0.005f;
    CHECK_FALSE(lispsm_shadow_matrix(in).fallback_uniform);
}

TEST_CASE("psm: LiSPSM and TSM change continuously as the light sweeps towards parallel") {
    // Sweep the light from 12 degrees to 0.01 degrees off the view direction; the NDC position of
    // fixed receiver points must move by a bounded amount per degree (no jumps at the fade/fallback).
    const WarpInput base = outdoor(12.0f);
    glm::dvec3 pts[27];
    {
        const glm::dvec3 c[8] = {{-3, 0.5, -3}, {3, 0.5, -3}, {-3, 3, -3}, {3, 3, -3}, {-30, 0.5, -60}, {30, 0.5, -60}, {-30, 9, -60}, {30, 9, -60}};
        int k = 0;
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
                for (int t = 0; t < 3; ++t) pts[k++] = sample_slice(c, a * 0.5, b * 0.5, t * 0.5);
    }
    for (int m = 2; m < 4; ++m) {
        double worst = 0.0;
        WarpInput in = base;
        glm::mat4 prev(0.0f);
        const double step = 0.01;
        bool first = true;
        for (double ang = 12.0; ang >= 0.01; ang -= step) {
            const double a = glm::radians(ang);
            in.light = glm::vec4(0.0f, float(-std::sin(a)), float(-std::cos(a)), 0.0f);
            const WarpResult r = kMethods[m](in);
            REQUIRE(r.status == WarpStatus::Ok);
            if (!first) {
                double mv = 0.0;
                for (const glm::dvec3& p : pts) mv = std::fmax(mv, glm::length(ndc_xy(r.light_view_proj, p) - ndc_xy(prev, p)));
                worst = std::fmax(worst, mv / step);
            }
            prev = r.light_view_proj;
            first = false;
        }
        MESSAGE(kNames[m] << ": max NDC displacement per degree over the sweep 12 -> 0.01 deg: " << worst);
        CHECK(worst < 2.0);
    }
    // through exact parallel the fitted frame turns by 180 degrees about the light: same map, mirrored
    for (int m = 2; m < 4; ++m) {
        WarpInput a = base, b = base;
        a.light = glm::vec4(0.0f, -std::sin(glm::radians(0.01f)), -std::cos(glm::radians(0.01f)), 0.0f);
        b.light = glm::vec4(0.0f, std::sin(glm::radians(0.01f)), -std::cos(glm::radians(0.01f)), 0.0f);
        const WarpResult ra = kMethods[m](a), rb = kMethods[m](b);
        REQUIRE(ra.fallback_uniform);
        REQUIRE(rb.fallback_uniform);
        for (const glm::dvec3& p : pts) {
            const glm::dvec2 pa = ndc_xy(ra.light_view_proj, p), pb = ndc_xy(rb.light_view_proj, p);
            CHECK(glm::length(pa + pb) < 1e-2);
        }
    }
}

TEST_CASE("psm: stiff cases") {
    SUBCASE("directional light straight down on a camera looking straight down") {
        WarpInput in = outdoor(90.0f);
        in.camera_view = glm::lookAt(glm::vec3(0, 8, 0), glm::vec3(0, 0, 0), glm::vec3(0, 0, -1));
        in.light = glm::vec4(0, -1, 0, 0);
        for (int m = 0; m < 4; ++m) {
            const WarpResult r = kMethods[m](in);
            REQUIRE(r.status == WarpStatus::Ok);
            CHECK(all_finite(r.light_view_proj));
            CHECK(in_clip(r.light_view_proj, glm::dvec3(0, 0, 0), in.light_depth, 1e-4));
            CHECK(in_clip(r.light_view_proj, glm::dvec3(0, 9.9, 0), in.light_depth, 1e-4));
            if (m >= 2) CHECK(r.fallback_uniform);
        }
    }
    SUBCASE("directional light from behind the viewer: PSM inverts (light sink), all contain casters") {
        WarpInput in = outdoor(90.0f);
        in.light = glm::vec4(glm::normalize(glm::vec3(0.1f, -1.0f, -0.3f)), 0.0f);  // travels forward: from behind
        for (int m = 0; m < 4; ++m) {
            const WarpResult r = kMethods[m](in);
            REQUIRE(r.status == WarpStatus::Ok);
            const glm::dvec3 recv(0, 0.5, -10);
            const glm::dvec3 caster = recv - 9.0 * glm::dvec3(in.light) / double(glm::length(glm::vec3(in.light)));
            double zr = 0, zc = 0;
            CHECK(in_clip(r.light_view_proj, recv, in.light_depth, 1e-4, &zr));
            CHECK(in_clip(r.light_view_proj, caster, in.light_depth, 1e-4, &zc));
            CHECK(zc < zr);
        }
        CHECK_FALSE(psm_shadow_matrix(in).fallback_uniform);
    }
    SUBCASE("point light behind the camera, exactly in the near plane, inside the receivers") {
        WarpInput in = outdoor(90.0f);
        for (const glm::vec4 L : {glm::vec4(0, 30, 20, 1), glm::vec4(3, 2, -1, 1)}) {
            in.light = L;
            for (int m = 0; m < 4; ++m) {
                const WarpResult r = kMethods[m](in);
                CHECK(all_finite(r.light_view_proj));
                if (r.status != WarpStatus::Ok) continue;
                CHECK(in_clip(r.light_view_proj, glm::dvec3(0, 0.5, -20), in.light_depth, 1e-4));
            }
        }
        in.light = glm::vec4(0, 3, -30, 1);
        for (int m = 0; m < 4; ++m) CHECK(kMethods[m](in).status == WarpStatus::LightInsideVolume);
    }
    SUBCASE("near 1e-5, infinite far, near/far ratio 1e-6") {
        WarpInput in = outdoor(70.0f);
        in.camera_proj = glm::infinitePerspective(1.0f, 1.0f, 1e-5f);
        for (int m = 0; m < 4; ++m) CHECK(kMethods[m](in).status == WarpStatus::InfiniteFar);
        in.max_distance = 10.0f;
        for (int m = 0; m < 4; ++m) {
            const WarpResult r = kMethods[m](in);
            REQUIRE(r.status == WarpStatus::Ok);
            CHECK(in_clip(r.light_view_proj, glm::dvec3(0, 2, -9.9), in.light_depth, 1e-4));
            CHECK(in_clip(r.light_view_proj, glm::dvec3(0, 2, -2e-5), in.light_depth, 1e-4));
        }
    }
    SUBCASE("coordinates at 1e6") {
        WarpInput in = outdoor(60.0f);
        const glm::vec3 o(1e6f, 0.0f, -1e6f);
        in.camera_view = glm::lookAt(o + glm::vec3(0, 2, 0), o + glm::vec3(0, 2, -1), glm::vec3(0, 1, 0));
        in.scene_min += o;
        in.scene_max += o;
        for (int m = 0; m < 4; ++m) {
            const WarpResult r = kMethods[m](in);
            REQUIRE(r.status == WarpStatus::Ok);
            CHECK(all_finite(r.light_view_proj));
            CHECK(in_clip(r.light_view_proj, glm::dvec3(o) + glm::dvec3(0, 1, -50), in.light_depth, 1e-3));
        }
    }
    SUBCASE("zero-size bounds and a camera inside the caster bounds") {
        WarpInput in = outdoor(60.0f);
        in.scene_min = in.scene_max = glm::vec3(0, 1, -5);
        for (int m = 0; m < 4; ++m) {
            const WarpResult r = kMethods[m](in);
            REQUIRE(r.status == WarpStatus::Ok);
            CHECK(all_finite(r.light_view_proj));
        }
        in = outdoor(60.0f);
        in.has_caster_bounds = true;
        in.caster_min = glm::vec3(-5, 0, -5);
        in.caster_max = glm::vec3(5, 20, 5);  // contains the camera
        for (int m = 0; m < 4; ++m) CHECK(kMethods[m](in).status == WarpStatus::Ok);
    }
    SUBCASE("NaN/Inf input and bad options give a status") {
        const float nan = std::numeric_limits<float>::quiet_NaN();
        WarpInput in = outdoor(60.0f);
        in.light.x = nan;
        for (int m = 0; m < 4; ++m) {
            const WarpResult r = kMethods[m](in);
            CHECK(r.status == WarpStatus::InvalidInput);
            CHECK(all_finite(r.light_view_proj));
        }
        in = outdoor(60.0f);
        in.camera_proj[0][0] = std::numeric_limits<float>::infinity();
        CHECK(psm_shadow_matrix(in).status == WarpStatus::InvalidInput);
        in = outdoor(60.0f);
        in.options.tsm_focus_ratio = 1.5f;
        CHECK(tsm_shadow_matrix(in).status == WarpStatus::InvalidInput);
        in = outdoor(60.0f);
        in.scene_min = glm::vec3(1);
        in.scene_max = glm::vec3(0);
        CHECK(lispsm_shadow_matrix(in).status == WarpStatus::InvalidInput);
        CHECK(measure_perspective_aliasing(in, glm::mat4(1.0f), 1024, {64, 64}, 4, 4, 4).samples == 0);
    }
}

TEST_CASE("psm: depth conventions agree (GL vs zero-to-one vs reversed)") {
    const WarpInput base = outdoor(50.0f);
    const glm::dvec3 p(1, 1, -20);
    for (int m = 0; m < 4; ++m) {
        WarpInput a = base, b = base, c = base;
        b.light_depth = ClipDepth::ZeroToOne;
        c.light_depth = ClipDepth::ZeroToOne;
        c.light_reversed_z = true;
        double za = 0, zb = 0, zc = 0;
        REQUIRE(in_clip(kMethods[m](a).light_view_proj, p, a.light_depth, 1e-5, &za));
        REQUIRE(in_clip(kMethods[m](b).light_view_proj, p, b.light_depth, 1e-5, &zb));
        REQUIRE(in_clip(kMethods[m](c).light_view_proj, p, c.light_depth, 1e-5, &zc));
        CHECK(zb == doctest::Approx(0.5 * za + 0.5).epsilon(1e-5));
        CHECK(zc == doctest::Approx(1.0 - zb).epsilon(1e-5));
    }
}
