// Unit and property tests for shadowkit/perspective_shadow_maps.hpp.
// References: closed-form frustum corners and aliasing footprint, brute-force ray casting for
// "which caster points shadow a receiver", sampling for containment and depth order, triangle
// orientation from the light position (independent of the matrices), and light sweeps through the
// view direction and every fade/fallback threshold for continuity (issue 14).
#include <shadowkit/infinite_projection.hpp>  // its epsilon-tweaked P_inf must be accepted (issue 13.3)
#include <shadowkit/perspective_shadow_maps.hpp>

#include <doctest/doctest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <initializer_list>
#include <limits>
#include <random>
#include <string>
#include <vector>

using namespace shadowkit;

namespace {

const WarpMethod kMethods[4] = {WarpMethod::Uniform, WarpMethod::Psm, WarpMethod::Lispsm, WarpMethod::Tsm};
const std::string kNames[4] = {"uniform", "psm", "lispsm", "tsm"};

// GL/ZO, reversed or not, finite or infinite far; off-center when l != -r or b != -t (near-plane rect).
glm::mat4 make_frustum(double l, double r, double b, double t, double n, double f, ClipDepth cd, bool rev, bool inf) {
    glm::mat4 m(0.0f);
    m[0][0] = float(2 * n / (r - l));
    m[1][1] = float(2 * n / (t - b));
    m[2][0] = float((r + l) / (r - l));
    m[2][1] = float((t + b) / (t - b));
    m[2][3] = -1.0f;
    double zn, zf;
    if (cd == ClipDepth::ZeroToOne) { zn = rev ? 1 : 0; zf = rev ? 0 : 1; }
    else { zn = rev ? 1 : -1; zf = rev ? -1 : 1; }
    double a, bb;  // z_ndc(d) = -a + bb / d
    if (inf) { a = -zf; bb = (zn - zf) * n; }
    else {
        const double B = (zn - zf) * n * f / (f - n);
        a = -(zf - B / f);
        bb = B;
    }
    m[2][2] = float(a);
    m[3][2] = float(bb);
    return m;
}

glm::mat4 make_proj(float fovy, float aspect, float n, float f, ClipDepth cd, bool rev, bool inf) {
    const double t = std::tan(0.5 * double(fovy)) * n;
    return make_frustum(-t * aspect, t * aspect, -t, t, n, f, cd, rev, inf);
}

struct Scene {
    WarpInput in;
    glm::dvec3 corners[8];  // receiver slice corners, closed form
    glm::dvec3 eye, vdir;   // camera position and the view's center line direction
    double d0 = 0, d1 = 0;
};

glm::vec3 rdir(std::mt19937& rng) {
    std::normal_distribution<float> g(0.0f, 1.0f);
    glm::vec3 d;
    do { d = glm::vec3(g(rng), g(rng), g(rng)); } while (glm::length(d) < 1e-3f);
    return glm::normalize(d);
}

// camera at pos looking along fwd with near-plane rect (l, r, b, t) at n (off-center when asymmetric);
// slice corners from the closed form of the frustum
Scene make_scene_rect(const glm::vec3& pos, const glm::vec3& fwd, double l, double r, double b, double t, float n,
                      float f, bool inf, float maxd, ClipDepth cd, bool rev, float rmin, float rmax) {
    Scene s;
    const glm::vec3 up = std::fabs(fwd.y) > 0.99f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    s.in.camera_view = glm::lookAt(pos, pos + fwd, up);
    s.in.camera_proj = make_frustum(l, r, b, t, n, f, cd, rev, inf);
    s.in.camera_depth = cd;
    s.in.camera_reversed_z = rev;
    s.in.max_distance = maxd;
    s.in.receiver_min_depth = rmin;
    s.in.receiver_max_depth = rmax;
    double d0 = n, d1 = inf ? maxd : (maxd > 0 ? std::fmin(f, maxd) : f);
    if (rmax > rmin && rmin > 0) { d0 = std::fmax(d0, rmin); d1 = std::fmin(d1, rmax); }
    const glm::dmat4 iv = glm::inverse(glm::dmat4(s.in.camera_view));
    for (int i = 0; i < 8; ++i) {
        const double d = (i & 4) ? d1 : d0;
        const glm::dvec3 pv(((i & 1) ? r : l) * d / n, ((i & 2) ? t : b) * d / n, -d);
        s.corners[i] = glm::dvec3(iv * glm::dvec4(pv, 1.0));
    }
    s.eye = glm::dvec3(pos);
    s.vdir = glm::normalize(glm::dvec3(glm::mat3(iv) * glm::dvec3(0.5 * (l + r) / n, 0.5 * (b + t) / n, -1.0)));
    s.d0 = d0;
    s.d1 = d1;
    return s;
}

Scene make_scene(const glm::vec3& pos, const glm::vec3& fwd, float fovy, float aspect, float n, float f, bool inf,
                 float maxd, ClipDepth cd, bool rev, float rmin, float rmax) {
    const double t = std::tan(0.5 * double(fovy)) * n;
    return make_scene_rect(pos, fwd, -t * aspect, t * aspect, -t, t, n, f, inf, maxd, cd, rev, rmin, rmax);
}

glm::dvec3 sample_slice(const glm::dvec3 c[8], double u, double v, double t) {
    auto bil = [&](int o) { return glm::mix(glm::mix(c[o], c[o + 1], u), glm::mix(c[o + 2], c[o + 3], u), v); };
    return glm::mix(bil(0), bil(4), t);
}

bool in_box(const glm::dvec3& p, const glm::vec3& mn, const glm::vec3& mx) {
    return p.x >= mn.x && p.y >= mn.y && p.z >= mn.z && p.x <= mx.x && p.y <= mx.y && p.z <= mx.z;
}

// clip-space test of xy with m and depth with dm; returns NDC depth through z_out
bool in_clip2(const glm::mat4& m, const glm::mat4& dm, const glm::dvec3& p, ClipDepth cd, double tol, double* z_out = nullptr) {
    const glm::dvec4 h = glm::dmat4(m) * glm::dvec4(p, 1.0);
    const glm::dvec4 hd = glm::dmat4(dm) * glm::dvec4(p, 1.0);
    if (!(h.w > 0.0) || !(hd.w > 0.0)) return false;
    const double x = h.x / h.w, y = h.y / h.w, z = hd.z / hd.w;
    if (z_out) *z_out = z;
    const double zlo = cd == ClipDepth::ZeroToOne ? 0.0 : -1.0;
    return std::fabs(x) <= 1 + tol && std::fabs(y) <= 1 + tol && z >= zlo - tol && z <= 1 + tol;
}
bool in_clip(const glm::mat4& m, const glm::dvec3& p, ClipDepth cd, double tol, double* z_out = nullptr) {
    return in_clip2(m, m, p, cd, tol, z_out);
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

glm::dvec2 ndc_xy(const glm::mat4& m, const glm::dvec3& p) {
    const glm::dvec4 h = glm::dmat4(m) * glm::dvec4(p, 1.0);
    return glm::dvec2(h) / h.w;
}

// The light at `light_angle_deg_from_view` from the view direction: a sun whose rays travel along
// (0, -sin a, -cos a), so light_position (toward the light) is (0, sin a, cos a, 0).
WarpInput outdoor(float light_angle_deg_from_view, float nearp = 1.0f, float farp = 100.0f) {
    WarpInput in;
    in.camera_view = glm::lookAt(glm::vec3(0, 2, 0), glm::vec3(0, 2, -1), glm::vec3(0, 1, 0));
    in.camera_proj = glm::perspective(1.0f, 16.0f / 9.0f, nearp, farp);
    const float a = glm::radians(light_angle_deg_from_view);
    in.light_position = glm::vec4(0.0f, std::sin(a), std::cos(a), 0.0f);
    in.has_scene_bounds = true;
    in.scene_min = glm::vec3(-200, 0, -200);
    in.scene_max = glm::vec3(200, 10, 200);
    return in;
}

// The scene of issue 14: camera at (0, 10, 0) looking along (0, -0.2, -1), fovy 60, aspect 1.5, near
// 0.5, far 200, scene box (-300, -1, -300)..(300, 20, 300). `travel` is the issue's sun vector (the
// direction the light travels, the header's old convention): light_position = (-travel, 0).
WarpInput issue_scene(const glm::vec3& travel) {
    WarpInput in;
    in.camera_view = glm::lookAt(glm::vec3(0, 10, 0), glm::vec3(0, 10, 0) + glm::vec3(0, -0.2f, -1), glm::vec3(0, 1, 0));
    in.camera_proj = glm::perspective(glm::radians(60.0f), 1.5f, 0.5f, 200.0f);
    in.has_scene_bounds = true;
    in.scene_min = glm::vec3(-300, -1, -300);
    in.scene_max = glm::vec3(300, 20, 300);
    in.light_position = glm::vec4(-travel, 0.0f);
    return in;
}

// Receiver points of issue_scene: the view slice (near 0.5 .. far 200) inside the scene box.
std::vector<glm::dvec3> issue_receivers() {
    const Scene sc = make_scene(glm::vec3(0, 10, 0), glm::normalize(glm::vec3(0, -0.2f, -1)), glm::radians(60.0f), 1.5f,
                                0.5f, 200.0f, false, 0.0f, ClipDepth::NegativeOneToOne, false, 0, 0);
    std::vector<glm::dvec3> pts;
    for (int a = 0; a <= 8; ++a)
        for (int b = 0; b <= 8; ++b)
            for (int t = 0; t <= 8; ++t) {
                const glm::dvec3 p = sample_slice(sc.corners, a / 8.0, b / 8.0, std::pow(t / 8.0, 2.0));
                if (in_box(p, glm::vec3(-300, -1, -300), glm::vec3(300, 20, 300))) pts.push_back(p);
            }
    return pts;
}

glm::dvec2 ndc_extent(const glm::mat4& m, const std::vector<glm::dvec3>& pts, glm::dvec2* lo = nullptr) {
    glm::dvec2 mn(1e300), mx(-1e300);
    for (const glm::dvec3& p : pts) {
        const glm::dvec2 q = ndc_xy(m, p);
        mn = glm::min(mn, q);
        mx = glm::max(mx, q);
    }
    if (lo) *lo = mn;
    return mx - mn;
}

}  // namespace

TEST_CASE("warp: aliasing error of a uniform map matches the closed form; statuses") {
    // camera looking straight down from height H onto the ground, ortho light straight down covering
    // W x W world units with S texels: a texel is W/S wu; a pixel at distance H covers 2 H tan(fov/2)/P wu.
    const double H = 10.0, W = 64.0, S = 1024.0, P = 800.0, fov = 1.0;
    const glm::mat4 cam = glm::perspective(float(fov), 1.0f, 0.1f, 100.0f) *
                          glm::lookAt(glm::vec3(0, H, 0), glm::vec3(0, 0, 0), glm::vec3(0, 0, -1));
    const glm::mat4 light = glm::ortho(-32.0f, 32.0f, -32.0f, 32.0f, 0.0f, 50.0f) *
                            glm::lookAt(glm::vec3(0, 20, 0), glm::vec3(0, 0, 0), glm::vec3(0, 0, -1));
    const WarpAliasingValue e = warp_aliasing_error(light, cam, glm::vec3(0, 0, 0), glm::vec3(0, 1, 0), uint32_t(S), {800, 800});
    REQUIRE(e.status == Status::Ok);
    const double expected = (W / S) / (2.0 * H * std::tan(fov / 2) / P);
    CHECK(e.value == doctest::Approx(expected).epsilon(1e-4));
    CHECK(WarpAliasingValue{}.status == Status::NotRun);
    // behind the camera, degenerate, NaN, zero normal, size 0, edge-on: a status, never Ok with inf/NaN
    CHECK(warp_aliasing_error(light, cam, glm::vec3(0, 20, 0), glm::vec3(0, 1, 0), 1024, {800, 800}).status == Status::InvalidArgument);
    CHECK(warp_aliasing_error(glm::mat4(0.0f), cam, glm::vec3(0), glm::vec3(0, 1, 0), 1024, {800, 800}).status == Status::InvalidArgument);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    CHECK(warp_aliasing_error(light, cam, glm::vec3(nan), glm::vec3(0, 1, 0), 1024, {800, 800}).status == Status::NonFinite);
    CHECK(warp_aliasing_error(light, cam, glm::vec3(0), glm::vec3(0), 1024, {800, 800}).status == Status::InvalidArgument);
    CHECK(warp_aliasing_error(light, cam, glm::vec3(0), glm::vec3(0, 1, 0), 0, {800, 800}).status == Status::InvalidArgument);
    CHECK(warp_aliasing_error(light, cam, glm::vec3(0), glm::vec3(0, 1, 0), 1024, {0, 800}).status == Status::InvalidArgument);
    CHECK(warp_aliasing_error(light, cam, glm::vec3(0), glm::vec3(1, 0, 0), 1024, {800, 800}).status == Status::Overflow);
}

TEST_CASE("warp: warps reduce the max perspective aliasing error (README table, camera perpendicular to the light)") {
    struct Cfg { float angle, nearp, farp; };
    for (const Cfg c : {Cfg{90.0f, 1.0f, 100.0f}, Cfg{90.0f, 0.1f, 100.0f}, Cfg{60.0f, 0.5f, 200.0f}, Cfg{30.0f, 1.0f, 100.0f}}) {
        const WarpInput in = outdoor(c.angle, c.nearp, c.farp);
        double mx[4];
        for (int m = 0; m < 4; ++m) {
            const WarpResult r = warp_matrix(in, kMethods[m]);
            REQUIRE(r.status == Status::Ok);
            REQUIRE(r.visible);
            CHECK_FALSE(r.fallback_uniform);
            const WarpAliasingStats a = warp_measure_aliasing(in, r.light_view_proj, 2048, {1920, 1080}, 24, 24, 32);
            REQUIRE(a.status == Status::Ok);
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

TEST_CASE("warp: containment, depth order, orientation and finite Ok over thousands of random cameras and lights") {
    std::mt19937 rng(2024);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    int fitted[4] = {0, 0, 0, 0}, fallbacks[4] = {0, 0, 0, 0}, recv_pts = 0, caster_pts = 0, order_pairs = 0, tris = 0;
    const int N = 1200;
    for (int it = 0; it < N; ++it) {
        const glm::vec3 pos = glm::vec3(u(rng) - 0.5f, u(rng) * 0.3f, u(rng) - 0.5f) * 60.0f;
        const glm::vec3 fwd = rdir(rng);
        const float n = 0.05f + 2.0f * u(rng), f = n * (5.0f + 300.0f * u(rng));
        const bool inf = rng() % 5 == 0;
        const float maxd = inf ? f : 0.0f;
        const ClipDepth cd = (rng() & 1) ? ClipDepth::ZeroToOne : ClipDepth::NegativeOneToOne;
        float rmin = 0, rmax = 0;
        if (rng() % 3 == 0) { rmin = n * (1 + 2 * u(rng)); rmax = rmin + f * u(rng); }
        const float fovy = 0.4f + 1.3f * u(rng), aspect = 0.6f + 1.4f * u(rng);
        Scene sc;
        if (rng() % 4 == 0) {  // off-center frustum
            const double t = std::tan(0.5 * double(fovy)) * n, sx = (u(rng) - 0.5) * t, sy = (u(rng) - 0.5) * t;
            sc = make_scene_rect(pos, fwd, -t * aspect + sx, t * aspect + sx, -t + sy, t + sy, n, f, inf, maxd, cd,
                                 (rng() & 2) != 0, rmin, rmax);
        } else {
            sc = make_scene(pos, fwd, fovy, aspect, n, f, inf, maxd, cd, (rng() & 2) != 0, rmin, rmax);
        }
        WarpInput& in = sc.in;
        const bool point = rng() % 4 == 0;
        in.light_position = point ? glm::vec4(glm::vec3(u(rng) - 0.5f, 0.2f + u(rng), u(rng) - 0.5f) * 200.0f, 1.0f)
                                  : glm::vec4(rdir(rng), 0.0f);
        if (point && rng() % 3 == 0) in.light_position *= 0.5f + 4.0f * u(rng);  // w != 1
        in.has_scene_bounds = rng() % 3 != 0;
        in.scene_min = glm::vec3(-80, -5, -80) + glm::vec3(u(rng), 0.2f * u(rng), u(rng)) * 20.0f;
        in.scene_max = glm::vec3(80, 20, 80) - glm::vec3(u(rng), u(rng), u(rng)) * 10.0f;
        in.has_caster_bounds = rng() % 2 == 0;
        in.caster_min = in.scene_min;
        in.caster_max = in.scene_max + glm::vec3(0, 30.0f * u(rng), 0);
        in.light_depth = (rng() & 1) ? ClipDepth::ZeroToOne : ClipDepth::NegativeOneToOne;
        in.light_reversed_z = rng() % 4 == 0;
        const glm::dvec3 Lp = glm::dvec3(in.light_position) / (point ? double(in.light_position.w) : 1.0);
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
        auto toward = [&](const glm::dvec3& p) { return point ? glm::normalize(Lp - p) : glm::normalize(glm::dvec3(in.light_position)); };
        for (int m = 0; m < 4; ++m) {
            const WarpResult r = warp_matrix(in, kMethods[m]);
            REQUIRE(all_finite(r.light_view_proj));
            REQUIRE(all_finite(r.depth_view_proj));
            if (r.status != Status::Ok) {
                if (r.status != Status::LightInsideVolume) FAIL_CHECK(kNames[m] << ": status " << status_name(r.status) << " it=" << it);
                continue;
            }
            if (!r.visible) continue;
            ++fitted[m];
            if (r.fallback_uniform) ++fallbacks[m];
            CHECK(r.separate_depth == (m == 3 && !r.fallback_uniform));
            if (!r.separate_depth) CHECK(r.depth_view_proj == r.light_view_proj);
            // orientation (issue 14.4): det < 0 for GL depth, > 0 reversed (both: CCW in the window)
            const double det = glm::determinant(glm::dmat4(r.light_view_proj));
            if (!((in.light_reversed_z ? det : -det) > 0.0)) FAIL_CHECK(kNames[m] << ": orientation flipped, it=" << it);
            const double sgn = in.light_reversed_z ? -1.0 : 1.0;
            bool bad = false;
            for (int k = 0; k < 25 && !bad; ++k) {
                const glm::dvec3 p = sample_slice(sc.corners, u(rng), u(rng), u(rng));
                if (in.has_scene_bounds && !in_box(p, in.scene_min, in.scene_max)) continue;
                ++recv_pts;
                double zp = 0;
                if (!in_clip2(r.light_view_proj, r.depth_view_proj, p, in.light_depth, 1e-4, &zp)) {
                    FAIL_CHECK(kNames[m] << ": receiver outside the light clip volume, it=" << it);
                    bad = true;
                    break;
                }
                // a small triangle at p facing the light: counter-clockwise in the light's window
                {
                    const glm::dvec3 t = toward(p);
                    const glm::dvec3 a = glm::normalize(glm::cross(t, glm::dvec3(rdir(rng))));
                    const glm::dvec3 b = glm::cross(t, a);  // (a, b, t) right-handed: p, p+ea, p+eb is CCW seen from the light
                    const double e = 1e-3 * std::fmax(1.0, glm::length(p - sc.eye));
                    const glm::dvec3 q1 = p + e * a, q2 = p + e * b;
                    if (in_clip(r.light_view_proj, q1, in.light_depth, 1e-3) && in_clip(r.light_view_proj, q2, in.light_depth, 1e-3)) {
                        const glm::dvec2 s0 = ndc_xy(r.light_view_proj, p), s1 = ndc_xy(r.light_view_proj, q1),
                                         s2 = ndc_xy(r.light_view_proj, q2);
                        const double area = (s1.x - s0.x) * (s2.y - s0.y) - (s1.y - s0.y) * (s2.x - s0.x);
                        ++tris;
                        if (!(area > 0.0)) FAIL_CHECK(kNames[m] << ": front face clockwise in the light's window, it=" << it);
                    }
                }
                if (!have_casters) continue;
                // a caster point on the segment towards the light: inside, and nearer in depth
                const glm::dvec3 tl = point ? Lp - p : glm::dvec3(in.light_position);
                const double tmax = point ? 1.0 : 1e4;
                const double t = tmax * double(u(rng)) * (point ? 1.0 : 0.01);
                const glm::dvec3 q = p + t * (point ? tl : glm::normalize(tl));
                if (!in_box(q, cmn, cmx)) continue;
                if (point && glm::length(q - Lp) < 1e-3 * glm::length(tl)) continue;
                double zq = 0;
                ++order_pairs;
                if (!in_clip2(r.light_view_proj, r.depth_view_proj, q, in.light_depth, 1e-4, &zq)) {
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
                const glm::dvec3 dir = point ? q - Lp : -glm::dvec3(in.light_position);
                if (glm::length(dir) == 0.0 || !ray_hits(pl, np, q, glm::normalize(dir), 1e7)) continue;
                if (point && glm::length(dir) < 1e-3 * glm::length(sc.corners[7] - Lp)) continue;
                ++caster_pts;
                if (!in_clip2(r.light_view_proj, r.depth_view_proj, q, in.light_depth, 1e-4)) {
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
    MESSAGE("receiver samples " << recv_pts << ", caster samples " << caster_pts << ", depth-order pairs " << order_pairs
                                << ", oriented triangles " << tris);
    CHECK(tris > 10000);
}

TEST_CASE("warp: anchors - filament LiSPSM off within ~1 degree, DagorEngine TSM off at |cos gamma| >= 0.95") {
    // filament: sinLV <= 0.02 -> no LiSPSM. Ours: off below 0.02, fading to full strength at 0.03.
    CHECK(warp_lispsm_matrix(outdoor(1.0f)).fallback_uniform);   // sin 1 deg = 0.0175
    CHECK(warp_lispsm_matrix(outdoor(-1.0f)).fallback_uniform);
    CHECK_FALSE(warp_lispsm_matrix(outdoor(3.0f)).fallback_uniform);  // sin 3 deg = 0.052
    CHECK(warp_lispsm_matrix(outdoor(3.0f)).warp_strength == 1.0f);
    CHECK(warp_lispsm_matrix(outdoor(0.0f)).fallback_uniform);   // exactly parallel
    CHECK(warp_lispsm_matrix(outdoor(180.0f)).fallback_uniform); // exactly anti-parallel
    const float mid = glm::degrees(std::asin(0.025f));  // halfway through the fade: smoothstep(0.5) = 0.5
    CHECK(warp_lispsm_matrix(outdoor(mid)).warp_strength == doctest::Approx(0.5).epsilon(1e-3));
    // DagorEngine TSM: |cos gamma| >= 0.95 -> ortho
    const float a95 = glm::degrees(std::acos(0.96f)), a90 = glm::degrees(std::acos(0.89f));
    CHECK(warp_tsm_matrix(outdoor(a95)).fallback_uniform);
    CHECK(warp_tsm_matrix(outdoor(180.0f - a95)).fallback_uniform);
    CHECK_FALSE(warp_tsm_matrix(outdoor(a90)).fallback_uniform);
    CHECK_FALSE(warp_tsm_matrix(outdoor(180.0f - a90)).fallback_uniform);
    // thresholds are options
    WarpInput in = outdoor(a95);
    in.options.tsm_max_abs_cos_gamma = 0.99f;
    CHECK_FALSE(warp_tsm_matrix(in).fallback_uniform);
    in = outdoor(1.0f);
    in.options.lispsm_min_sin_gamma = 0.005f;
    CHECK_FALSE(warp_lispsm_matrix(in).fallback_uniform);
    // PSM never switches to the uniform fit near the view direction: it slides back (weaker warp)
    for (float a : {0.0f, 0.3f, 175.0f, 180.0f}) {
        const WarpResult r = warp_psm_matrix(outdoor(a));
        REQUIRE(r.status == Status::Ok);
        CHECK_FALSE(r.fallback_uniform);
        CHECK(r.warp_strength < 1.0f);
    }
    CHECK(warp_psm_matrix(outdoor(90.0f)).warp_strength == 1.0f);
}

// ------------------------------------------------------------------------------------ issue 14
TEST_CASE("warp: regression 14.1 - TSM is not mirrored and does not jump at its |cos gamma| = 0.95 fallback") {
    // Issue 14's scene and suns: the old TSM put world point (3, 0, -20) at x = +0.686 for one sun and
    // -0.686 for the other (1.37 NDC in 0.0015 degree), its trapezoid frame having determinant -1.
    const WarpInput a = issue_scene({0.298080862f, -0.277558357f, -0.913295746f});
    const WarpInput b = issue_scene({0.298066616f, -0.277554959f, -0.913301468f});
    const WarpResult ra = warp_tsm_matrix(a), rb = warp_tsm_matrix(b), ua = warp_uniform_matrix(a);
    REQUIRE(ra.status == Status::Ok);
    REQUIRE(rb.status == Status::Ok);
    const glm::dvec3 p(3, 0, -20);
    CHECK(glm::length(ndc_xy(ra.light_view_proj, p) - ndc_xy(rb.light_view_proj, p)) < 0.01);
    // on both sides of the threshold TSM agrees with the uniform fit (it fades into it), not its mirror
    CHECK(glm::length(ndc_xy(ra.light_view_proj, p) - ndc_xy(ua.light_view_proj, p)) < 0.01);
    CHECK(glm::determinant(glm::dmat4(ra.light_view_proj)) < 0.0);
    CHECK(glm::determinant(glm::dmat4(rb.light_view_proj)) < 0.0);
    CHECK(glm::determinant(glm::dmat4(warp_tsm_matrix(outdoor(90.0f)).light_view_proj)) < 0.0);
}

TEST_CASE("warp: regression 14.2 - LiSPSM just above its fade threshold uses the whole map width") {
    // Issue 14: the old pad_box padded every axis by the largest extent's epsilon, so with n large the
    // lateral axis shrank below the pad: receivers' x extent [-0.85, 0.91] became [-0.19, 0.18], then
    // jumped back 0.43 NDC at the switch.
    const std::vector<glm::dvec3> pts = issue_receivers();
    REQUIRE(pts.size() > 100);
    const WarpResult a = warp_lispsm_matrix(issue_scene({0.0191081017f, -0.201926261f, -0.979214311f}));
    const WarpResult b = warp_lispsm_matrix(issue_scene({0.0190997738f, -0.201923743f, -0.979214966f}));
    REQUIRE(a.status == Status::Ok);
    REQUIRE(b.status == Status::Ok);
    glm::dvec2 lo_a, lo_b;
    const glm::dvec2 ea = ndc_extent(a.light_view_proj, pts, &lo_a), eb = ndc_extent(b.light_view_proj, pts, &lo_b);
    MESSAGE("receivers' x extent: [" << lo_a.x << ", " << lo_a.x + ea.x << "] and [" << lo_b.x << ", " << lo_b.x + eb.x << "]");
    CHECK(ea.x > 1.5);  // the receivers' hull reaches both sides; these samples span 83% of it
    CHECK(eb.x > 1.5);
    CHECK(std::fabs(ea.x / eb.x - 1.0) < 0.05);
    CHECK(std::fabs(lo_a.x - lo_b.x) < 0.01);
}

TEST_CASE("warp: regression 14.3 - PSM's image does not rotate abruptly (persp_fit's up vector)") {
    // The old persp_fit took its up vector from perp_axis(f), which switches axis: on the issue's
    // camera with a sun facing it (gamma 167.9 degrees) world point (3, 0, -20) jumped from
    // (-0.630, -0.306) to (0.433, 0.633), 1.42 NDC in 0.0004 degree (the issue's own case, 1.72 NDC
    // between gamma 12.4070 and 12.4066, came from a scene it does not give; this one was found by
    // sweeping the old header). Suns as the old header took them (direction of travel).
    const WarpInput a = issue_scene({0.197006270f, 0.262069732f, 0.944726408f});
    const WarpInput b = issue_scene({0.197012693f, 0.262071729f, 0.944724500f});
    const WarpResult ra = warp_psm_matrix(a), rb = warp_psm_matrix(b);
    REQUIRE(ra.status == Status::Ok);
    REQUIRE(rb.status == Status::Ok);
    const glm::dvec3 p(3, 0, -20);
    CHECK(glm::length(ndc_xy(ra.light_view_proj, p) - ndc_xy(rb.light_view_proj, p)) < 0.01);
    // the same up rule for the point-light uniform fit and the LiSPSM point-light base
    for (WarpMethod m : {WarpMethod::Uniform, WarpMethod::Lispsm, WarpMethod::Psm}) {
        WarpInput pa = a, pb = b;
        pa.light_position = glm::vec4(glm::vec3(0, 10, -100) + 150.0f * glm::vec3(a.light_position), 1.0f);
        pb.light_position = glm::vec4(glm::vec3(0, 10, -100) + 150.0f * glm::vec3(b.light_position), 1.0f);
        const WarpResult qa = warp_matrix(pa, m), qb = warp_matrix(pb, m);
        REQUIRE(qa.status == Status::Ok);
        REQUIRE(qb.status == Status::Ok);
        CHECK(glm::length(ndc_xy(qa.light_view_proj, p) - ndc_xy(qb.light_view_proj, p)) < 0.01);
    }
}

TEST_CASE("warp: regression 14.4 - every method keeps the winding (point lights, lights behind the viewer)") {
    // The old fits: uniform counter-clockwise, LiSPSM clockwise for point lights, PSM flipping when the
    // light passes behind the viewer, TSM mirrored. A triangle facing the light must be CCW in the light's
    // window for every method, reference: the light position (not the matrix).
    const glm::vec4 lights[] = {glm::vec4(0, 1, 0.3f, 0), glm::vec4(0.2f, 1, -0.5f, 0), glm::vec4(0, 0.3f, -1, 0),
                                glm::vec4(0, 0.3f, 1, 0), glm::vec4(10, 30, 20, 1), glm::vec4(-20, 80, -30, 1),
                                glm::vec4(5, 20, 60, 1)};
    for (const glm::vec4& L : lights)
        for (int m = 0; m < 4; ++m)
            for (bool rev : {false, true}) {
                WarpInput in = outdoor(60.0f);
                in.light_position = L;
                in.light_reversed_z = rev;
                const WarpResult r = warp_matrix(in, kMethods[m]);
                REQUIRE(r.status == Status::Ok);
                for (const glm::dvec3 p : {glm::dvec3(0, 0, -10), glm::dvec3(5, 1, -40), glm::dvec3(-3, 0.5, -3)}) {
                    const glm::dvec3 t = L.w == 0.0f ? glm::normalize(glm::dvec3(L)) : glm::normalize(glm::dvec3(L) / double(L.w) - p);
                    const glm::dvec3 a = glm::normalize(glm::cross(t, glm::dvec3(0.3, 0.7, 0.2)));
                    const glm::dvec3 b = glm::cross(t, a);
                    const glm::dvec2 s0 = ndc_xy(r.light_view_proj, p), s1 = ndc_xy(r.light_view_proj, p + 0.01 * a),
                                     s2 = ndc_xy(r.light_view_proj, p + 0.01 * b);
                    const double area = (s1.x - s0.x) * (s2.y - s0.y) - (s1.y - s0.y) * (s2.x - s0.x);
                    if (!(area > 0.0)) FAIL_CHECK(kNames[m] << " light " << L.x << "," << L.y << "," << L.z << "," << L.w << " reversed " << rev);
                }
            }
}

TEST_CASE("warp: regression 14.5 - TSM's map depth is the light's own, not compressed by the trapezoid") {
    // Issue 14: the old TSM set z' = eta z_U, so on the README's 90-degree scene the depth resolution
    // along the light was 0.00049 NDC per world unit against 0.0476 for the uniform map. Martin & Tan
    // keep the light's post-perspective depth: depth_view_proj resolves depth exactly like the uniform map.
    const WarpInput in = outdoor(90.0f);
    const WarpResult t = warp_tsm_matrix(in), u = warp_uniform_matrix(in);
    REQUIRE(t.status == Status::Ok);
    REQUIRE(t.separate_depth);
    auto dz = [](const glm::mat4& m, const glm::dvec3& p, const glm::dvec3& dir) {
        const glm::dvec4 a = glm::dmat4(m) * glm::dvec4(p, 1.0), b = glm::dmat4(m) * glm::dvec4(p + 0.01 * dir, 1.0);
        return std::fabs(b.z / b.w - a.z / a.w) / 0.01;
    };
    const glm::dvec3 down(0, -1, 0);  // the sun is straight up: light rays travel down
    for (const glm::dvec3 p : {glm::dvec3(0, 1, -2), glm::dvec3(0, 1, -30), glm::dvec3(10, 1, -95)}) {
        const double ru = dz(u.light_view_proj, p, down), rt = dz(t.depth_view_proj, p, down), rw = dz(t.light_view_proj, p, down);
        MESSAGE("depth NDC per wu at view depth " << -p.z << ": uniform " << ru << ", TSM map depth " << rt << ", TSM warped z " << rw);
        CHECK(rt == doctest::Approx(ru).epsilon(1e-3));
        if (p.z < -10.0) CHECK(rw < 0.2 * ru);  // what the single matrix alone would store
    }
}

// ------------------------------------------------------------------------------------ continuity
namespace {

struct ContScene {
    WarpInput in;
    glm::dvec3 eye, vdir, e1, e2, P;  // P: a point on the view's center line
    double R = 0;                      // point-light distance from P
    std::vector<glm::dvec3> pts;       // fixed visible receiver points
};

bool make_cont_scene(std::mt19937& rng, ContScene& cs) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const glm::vec3 pos = glm::vec3(u(rng) - 0.5f, 0.1f + u(rng) * 0.3f, u(rng) - 0.5f) * 40.0f;
    glm::vec3 fwd = rdir(rng);
    fwd.y = -std::fabs(fwd.y) * 0.7f;
    fwd = glm::normalize(fwd);
    const float fovy = 0.5f + 1.0f * u(rng), aspect = 0.7f + 1.2f * u(rng), n = 0.1f + u(rng), f = n * (20.0f + 200.0f * u(rng));
    const ClipDepth cd = (rng() & 1) ? ClipDepth::ZeroToOne : ClipDepth::NegativeOneToOne;
    const bool rev = (rng() & 2) != 0;
    const int kind = int(rng() % 4);  // 0 finite, 1 infinite, 2 epsilon P_inf, 3 off-center finite
    const double t = std::tan(0.5 * double(fovy)) * n;
    const double sx = kind == 3 ? (u(rng) - 0.5) * t : 0.0, sy = kind == 3 ? (u(rng) - 0.5) * t : 0.0;
    Scene sc = make_scene_rect(pos, fwd, -t * aspect + sx, t * aspect + sx, -t + sy, t + sy, n, f, kind == 1 || kind == 2,
                               kind == 1 || kind == 2 ? f : 0.0f, cd, rev, 0, 0);
    if (kind == 2) sc.in.camera_proj = projection_perspective_infinite(fovy, aspect, n, cd, rev, 1e-3f + 0.3f * u(rng)).matrix;
    cs.in = sc.in;
    cs.in.has_scene_bounds = rng() % 4 != 0;
    cs.in.scene_min = glm::vec3(-60, -2, -60) + glm::vec3(u(rng), 0.0f, u(rng)) * 20.0f;
    cs.in.scene_max = glm::vec3(60, 15, 60) - glm::vec3(u(rng) * 20.0f, u(rng) * 5.0f, u(rng) * 20.0f);
    cs.in.has_caster_bounds = rng() % 2 == 0;
    cs.in.caster_min = cs.in.scene_min;
    cs.in.caster_max = cs.in.scene_max + glm::vec3(0, 10.0f * u(rng), 0);
    cs.in.light_depth = (rng() & 1) ? ClipDepth::ZeroToOne : ClipDepth::NegativeOneToOne;
    cs.in.light_reversed_z = rng() % 4 == 0;
    cs.eye = sc.eye;
    cs.vdir = sc.vdir;
    cs.e1 = glm::normalize(glm::cross(cs.vdir, glm::dvec3(0, 1, 0)));
    cs.e2 = glm::cross(cs.e1, cs.vdir);
    for (int k = 0; k < 4000 && cs.pts.size() < 24; ++k) {
        const glm::dvec3 p = sample_slice(sc.corners, u(rng), u(rng), std::pow(double(u(rng)), 2.0));
        if (cs.in.has_scene_bounds && !in_box(p, cs.in.scene_min, cs.in.scene_max)) continue;
        cs.pts.push_back(p);
    }
    if (cs.pts.size() < 8) return false;
    cs.P = cs.eye + cs.vdir * (0.5 * (sc.d0 + sc.d1) / glm::dot(cs.vdir, -glm::dvec3(glm::transpose(glm::dmat3(glm::dmat4(cs.in.camera_view)))[2])));
    double maxr = 0.0;
    for (const glm::dvec3& c : sc.corners) maxr = std::fmax(maxr, glm::length(c - cs.P));
    cs.R = 3.0 * maxr + 100.0;
    return true;
}

// One sweep: the light's direction of travel turns from the view direction (alpha = 0, parallel) to
// its opposite (alpha = 180) in the plane of vdir and an azimuth phi; a point light sits at distance R
// from P against that direction, so it crosses the view's center line at alpha = 0 and 180.
struct LightSweep {
    const ContScene* cs;
    bool point;
    double phi;
    WarpMethod method;
    WarpResult at(double alpha) const {
        const double ar = glm::radians(alpha), pr = glm::radians(phi);
        const glm::dvec3 d = std::cos(ar) * cs->vdir + std::sin(ar) * (std::cos(pr) * cs->e1 + std::sin(pr) * cs->e2);
        WarpInput in = cs->in;
        in.light_position = point ? glm::vec4(glm::vec3(cs->P - cs->R * d), 1.0f) : glm::vec4(glm::vec3(-d), 0.0f);
        return warp_matrix(in, method);
    }
};

struct SweepStats {
    double worst_move = 0.0, worst_move_at = 0.0;  // per 0.002 degree step
    double worst_extent = 0.0, worst_extent_at = 0.0;  // relative change within 0.01 degree
    int calls = 0, not_ok = 0, transitions = 0;
};

const double kStep = 0.002;  // degrees
const double kExceptSin = 0.0087265354983739347;  // sin(0.5 degree)

bool excepted(const WarpResult& r) { return r.sin_gamma < kExceptSin; }

double max_move(const ContScene& cs, const WarpResult& a, const WarpResult& b) {
    double mv = 0.0;
    for (const glm::dvec3& p : cs.pts) mv = std::fmax(mv, glm::length(ndc_xy(a.light_view_proj, p) - ndc_xy(b.light_view_proj, p)));
    return mv;
}

// 0.002 degree steps over [a0, a1]: movement per step and the extent change over 5 steps (0.01 degree)
void dense_sweep(const LightSweep& sw, double a0, double a1, SweepStats& st) {
    std::vector<WarpResult> hist;
    for (double a = a0; a <= a1 + 1e-12; a += kStep) {
        const WarpResult r = sw.at(a);
        ++st.calls;
        if (r.status != Status::Ok || !r.visible) { ++st.not_ok; hist.clear(); continue; }
        if (!hist.empty() && !excepted(r) && !excepted(hist.back())) {
            const double mv = max_move(*sw.cs, r, hist.back());
            if (mv > st.worst_move) { st.worst_move = mv; st.worst_move_at = a; }
        }
        hist.push_back(r);
        if (hist.size() >= 6) {
            bool outside = true;
            for (std::size_t k = hist.size() - 6; k < hist.size(); ++k) outside = outside && !excepted(hist[k]);
            if (outside) {
                const glm::dvec2 e0 = ndc_extent(hist[hist.size() - 6].light_view_proj, sw.cs->pts),
                                 e1 = ndc_extent(r.light_view_proj, sw.cs->pts);
                const double c = std::fmax(std::fabs(e1.x / e0.x - 1.0), std::fabs(e1.y / e0.y - 1.0));
                if (c > st.worst_extent) { st.worst_extent = c; st.worst_extent_at = a; }
            }
        }
    }
}

// Coarse steps of 0.25 degree over [0, 180]. An interval whose points move more than the
// 0.01-per-0.002-degree budget scaled to its length is re-swept in 0.002 degree steps; every place
// where the warp starts or stops fading (warp_strength leaves 1 or reaches 0, the fallback flag
// changes) gets a dense window of +-0.05 degree, and so do 0.5, 90 (PSM's light at infinity) and
// 179.5 degrees.
void sweep(const LightSweep& sw, SweepStats& st) {
    const double coarse = 0.25;
    std::vector<double> marks = {0.55, 90.0, 179.45};
    WarpResult prev;
    double prev_a = -1.0;
    for (double a = 0.0; a <= 180.0 + 1e-9; a += coarse) {
        const WarpResult r = sw.at(a);
        ++st.calls;
        if (prev_a >= 0.0 && r.status == Status::Ok && prev.status == Status::Ok) {
            const bool tr = (r.warp_strength >= 1.0f) != (prev.warp_strength >= 1.0f) ||
                            (r.warp_strength <= 0.0f) != (prev.warp_strength <= 0.0f) || r.fallback_uniform != prev.fallback_uniform;
            if (tr) {
                marks.push_back(a - 0.5 * coarse);
                ++st.transitions;
            }
            if (!excepted(r) && !excepted(prev) && max_move(*sw.cs, r, prev) > 0.01 * coarse / kStep) dense_sweep(sw, prev_a, a, st);
        }
        prev = r;
        prev_a = a;
    }
    for (double m : marks) dense_sweep(sw, m - 0.05, m + 0.05, st);
}

}  // namespace

TEST_CASE("warp: continuity - every method, directional and point lights, through the view direction and every threshold") {
    // Issue 14 "must hold": largest movement of fixed visible receiver points in light NDC between
    // consecutive 0.002-degree steps < 0.01, and the receivers' NDC extent changes by < 5% within
    // 0.01 degree, except within 0.5 degree of parallel / anti-parallel (there the roll is free). Random
    // cameras (finite, infinite, epsilon P_inf, off-center, GL/ZO, reversed-Z) and scenes; the sweep
    // passes exactly through the view direction and its opposite. See sweep() for the step plan.
    std::mt19937 rng(1414);
    const int kScenes = 16;
    double worst[4] = {0, 0, 0, 0}, worst_ext[4] = {0, 0, 0, 0};
    int transitions[4] = {0, 0, 0, 0}, calls = 0, scenes = 0;
    while (scenes < kScenes) {
        ContScene cs;
        if (!make_cont_scene(rng, cs)) continue;
        ++scenes;
        const double phi = std::uniform_real_distribution<double>(0.0, 360.0)(rng);
        for (int point = 0; point < 2; ++point)
            for (int m = 0; m < 4; ++m) {
                SweepStats st;
                sweep(LightSweep{&cs, point == 1, phi, kMethods[m]}, st);
                calls += st.calls;
                transitions[m] += st.transitions;
                CHECK(st.not_ok == 0);
                if (st.worst_move >= 0.01)
                    FAIL_CHECK(kNames[m] << (point ? " point" : " directional") << " scene " << scenes << ": " << st.worst_move
                                         << " NDC at alpha " << st.worst_move_at);
                if (st.worst_extent >= 0.05)
                    FAIL_CHECK(kNames[m] << (point ? " point" : " directional") << " scene " << scenes << ": extent changes by "
                                         << st.worst_extent << " at alpha " << st.worst_extent_at);
                worst[m] = std::fmax(worst[m], st.worst_move);
                worst_ext[m] = std::fmax(worst_ext[m], st.worst_extent);
            }
    }
    for (int m = 0; m < 4; ++m)
        MESSAGE(kNames[m] << ": largest step " << worst[m] << " NDC, largest extent change in 0.01 deg " << worst_ext[m]
                          << ", fade transitions swept " << transitions[m]);
    MESSAGE(calls << " fits");
    CHECK(transitions[2] >= 2 * kScenes);  // LiSPSM fades near both directions
    CHECK(transitions[3] >= 2 * kScenes);  // TSM too
}

TEST_CASE("warp: through exact parallel the map turns by 180 degrees about the light (same map, rotated)") {
    glm::dvec3 pts[27];
    {
        const glm::dvec3 c[8] = {{-3, 0.5, -3}, {3, 0.5, -3}, {-3, 3, -3}, {3, 3, -3}, {-30, 0.5, -60}, {30, 0.5, -60}, {-30, 9, -60}, {30, 9, -60}};
        int k = 0;
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
                for (int t = 0; t < 3; ++t) pts[k++] = sample_slice(c, a * 0.5, b * 0.5, t * 0.5);
    }
    for (int m : {0, 2, 3}) {
        const WarpResult ra = warp_matrix(outdoor(0.01f), kMethods[m]), rb = warp_matrix(outdoor(-0.01f), kMethods[m]);
        REQUIRE(ra.status == Status::Ok);
        for (const glm::dvec3& p : pts) {
            const glm::dvec2 pa = ndc_xy(ra.light_view_proj, p), pb = ndc_xy(rb.light_view_proj, p);
            CHECK(glm::length(pa + pb) < 1e-2);
        }
    }
}

// ------------------------------------------------------------------------------------ issues 13, 19
TEST_CASE("warp: the epsilon-tweaked and reversed-Z P_inf of infinite_projection.hpp is accepted (issue 13.3)") {
    // NDC z = +1 un-projects behind the eye when epsilon > 0: the far plane counts as infinite and
    // max_distance bounds the receivers.
    for (ClipDepth cd : {ClipDepth::NegativeOneToOne, ClipDepth::ZeroToOne})
        for (bool rev : {false, true})
            for (float eps : {0.0f, 2.4e-7f, 1e-3f, 0.5f}) {
                WarpInput in = outdoor(70.0f);
                const ProjectionResult pr = projection_perspective_infinite(1.0f, 16.0f / 9.0f, 0.1f, cd, rev, eps);
                REQUIRE(pr.status == Status::Ok);
                in.camera_proj = pr.matrix;
                in.camera_depth = cd;
                in.camera_reversed_z = rev;
                for (int m = 0; m < 4; ++m) CHECK(warp_matrix(in, kMethods[m]).status == Status::InvalidArgument);  // max_distance required
                in.max_distance = 80.0f;
                for (int m = 0; m < 4; ++m) {
                    const WarpResult r = warp_matrix(in, kMethods[m]);
                    REQUIRE(r.status == Status::Ok);
                    REQUIRE(r.visible);
                    for (const glm::dvec3 p : {glm::dvec3(0, 2, -79), glm::dvec3(0, 2, -0.2), glm::dvec3(20, 0, -60)})
                        CHECK(in_clip2(r.light_view_proj, r.depth_view_proj, p, in.light_depth, 1e-4));
                    // the same slice as a finite projection with far = max_distance
                    WarpInput fin = in;
                    fin.camera_proj = make_proj(1.0f, 16.0f / 9.0f, 0.1f, 80.0f, cd, rev, false);
                    const WarpResult rf = warp_matrix(fin, kMethods[m]);
                    REQUIRE(rf.status == Status::Ok);
                    for (const glm::dvec3 p : {glm::dvec3(0, 2, -79), glm::dvec3(5, 0, -20)})
                        CHECK(glm::length(ndc_xy(r.light_view_proj, p) - ndc_xy(rf.light_view_proj, p)) < 1e-3);
                }
            }
}

TEST_CASE("warp: honest statuses (issues 13, 19)") {
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    CHECK(WarpResult{}.status == Status::NotRun);
    CHECK(WarpAliasingStats{}.status == Status::NotRun);
    for (int m = 0; m < 4; ++m) {
        // a default-constructed input: required fields missing
        CHECK(warp_matrix(WarpInput{}, kMethods[m]).status != Status::Ok);
        WarpInput in = outdoor(60.0f);
        in.light_position = glm::vec4(0.0f);
        CHECK(warp_matrix(in, kMethods[m]).status == Status::InvalidLight);
        in.light_position = glm::vec4(0, 1, 0, -1);
        CHECK(warp_matrix(in, kMethods[m]).status == Status::InvalidLight);
        in.light_position = glm::vec4(nan, 1, 0, 0);
        CHECK(warp_matrix(in, kMethods[m]).status == Status::InvalidLight);
        in.light_position = glm::vec4(3e38f, 1, 0, 1e-30f);  // position beyond float
        CHECK(warp_matrix(in, kMethods[m]).status == Status::InvalidLight);
        in = outdoor(60.0f);
        in.camera_proj[0][0] = inf;
        CHECK(warp_matrix(in, kMethods[m]).status == Status::NonFinite);
        in = outdoor(60.0f);
        in.scene_min.x = nan;
        CHECK(warp_matrix(in, kMethods[m]).status == Status::NonFinite);
        in = outdoor(60.0f);
        in.camera_proj = glm::mat4(0.0f);
        CHECK(warp_matrix(in, kMethods[m]).status == Status::InvalidArgument);
        // issue 19: a projection whose near plane is at or behind the eye
        for (float n : {-0.1f, -5.0f}) {
            in = outdoor(60.0f);
            in.camera_proj = glm::perspective(1.0f, 1.5f, n, 100.0f);
            CHECK(warp_matrix(in, kMethods[m]).status == Status::InvalidArgument);
        }
        in = outdoor(60.0f);
        in.camera_proj = glm::perspective(1.0f, 1.5f, 10.0f, 1.0f);  // near > far
        CHECK(warp_matrix(in, kMethods[m]).status == Status::InvalidArgument);
        in = outdoor(60.0f);
        in.camera_reversed_z = true;  // a GL projection declared reversed: near and far swapped
        CHECK(warp_matrix(in, kMethods[m]).status == Status::InvalidArgument);
        in = outdoor(60.0f);
        in.max_distance = -1.0f;
        CHECK(warp_matrix(in, kMethods[m]).status == Status::InvalidArgument);
        in = outdoor(60.0f);
        in.options.tsm_focus_ratio = 1.5f;
        CHECK(warp_matrix(in, kMethods[m]).status == Status::InvalidArgument);
        in = outdoor(60.0f);
        in.options.psm_max_half_angle_deg = nan;
        CHECK(warp_matrix(in, kMethods[m]).status == Status::NonFinite);
        in = outdoor(60.0f);
        in.scene_min = glm::vec3(1);
        in.scene_max = glm::vec3(0);
        CHECK(warp_matrix(in, kMethods[m]).status == Status::InvalidArgument);
        // receivers out of view: Ok, nothing visible
        in = outdoor(60.0f);
        in.scene_min = glm::vec3(-10, 0, 10);
        in.scene_max = glm::vec3(10, 5, 20);  // behind the camera
        const WarpResult nv = warp_matrix(in, kMethods[m]);
        CHECK(nv.status == Status::Ok);
        CHECK_FALSE(nv.visible);
        in = outdoor(60.0f);
        in.light_position = glm::vec4(0, 3, -30, 1);  // a point light among the receivers
        CHECK(warp_matrix(in, kMethods[m]).status == Status::LightInsideVolume);
    }
    CHECK(warp_matrix(outdoor(60.0f), static_cast<WarpMethod>(7)).status == Status::InvalidArgument);
    WarpInput in = outdoor(60.0f);
    const WarpResult r = warp_lispsm_matrix(in);
    CHECK(warp_measure_aliasing(in, r.light_view_proj, 0, {64, 64}, 4, 4, 4).status == Status::InvalidArgument);
    CHECK(warp_measure_aliasing(in, r.light_view_proj, 64, {64, 64}, 0, 4, 4).status == Status::InvalidArgument);
    CHECK(warp_measure_aliasing(in, glm::mat4(nan), 64, {64, 64}, 4, 4, 4).status == Status::NonFinite);
    in.scene_min = glm::vec3(1);
    in.scene_max = glm::vec3(0);
    CHECK(warp_measure_aliasing(in, r.light_view_proj, 64, {64, 64}, 4, 4, 4).status == Status::InvalidArgument);
}

TEST_CASE("warp: stiff cases") {
    SUBCASE("directional light straight down on a camera looking straight down") {
        WarpInput in = outdoor(90.0f);
        in.camera_view = glm::lookAt(glm::vec3(0, 8, 0), glm::vec3(0, 0, 0), glm::vec3(0, 0, -1));
        in.light_position = glm::vec4(0, 1, 0, 0);
        for (int m = 0; m < 4; ++m) {
            const WarpResult r = warp_matrix(in, kMethods[m]);
            REQUIRE(r.status == Status::Ok);
            CHECK(all_finite(r.light_view_proj));
            CHECK(in_clip(r.light_view_proj, glm::dvec3(0, 0, 0), in.light_depth, 1e-4));
            CHECK(in_clip(r.light_view_proj, glm::dvec3(0, 9.9, 0), in.light_depth, 1e-4));
            if (m >= 2) CHECK(r.fallback_uniform);
        }
    }
    SUBCASE("directional light from behind the viewer: PSM inverts (light sink), all contain casters") {
        WarpInput in = outdoor(90.0f);
        in.light_position = glm::vec4(-glm::normalize(glm::vec3(0.1f, -1.0f, -0.3f)), 0.0f);  // travels forward: from behind
        for (int m = 0; m < 4; ++m) {
            const WarpResult r = warp_matrix(in, kMethods[m]);
            REQUIRE(r.status == Status::Ok);
            const glm::dvec3 recv(0, 0.5, -10);
            const glm::dvec3 caster = recv + 9.0 * glm::normalize(glm::dvec3(in.light_position));
            double zr = 0, zc = 0;
            CHECK(in_clip2(r.light_view_proj, r.depth_view_proj, recv, in.light_depth, 1e-4, &zr));
            CHECK(in_clip2(r.light_view_proj, r.depth_view_proj, caster, in.light_depth, 1e-4, &zc));
            CHECK(zc < zr);
        }
        CHECK_FALSE(warp_psm_matrix(in).fallback_uniform);
    }
    SUBCASE("point light behind the camera, exactly in the near plane") {
        WarpInput in = outdoor(90.0f);
        for (const glm::vec4 L : {glm::vec4(0, 30, 20, 1), glm::vec4(3, 2, -1, 1)}) {
            in.light_position = L;
            for (int m = 0; m < 4; ++m) {
                const WarpResult r = warp_matrix(in, kMethods[m]);
                CHECK(all_finite(r.light_view_proj));
                if (r.status != Status::Ok) {
                    CHECK(r.status == Status::LightInsideVolume);
                    continue;
                }
                CHECK(in_clip2(r.light_view_proj, r.depth_view_proj, glm::dvec3(0, 0.5, -20), in.light_depth, 1e-4));
            }
        }
    }
    SUBCASE("near 1e-5, infinite far, near/far ratio 1e-6") {
        WarpInput in = outdoor(70.0f);
        in.camera_proj = glm::infinitePerspective(1.0f, 1.0f, 1e-5f);
        for (int m = 0; m < 4; ++m) CHECK(warp_matrix(in, kMethods[m]).status == Status::InvalidArgument);
        in.max_distance = 10.0f;
        for (int m = 0; m < 4; ++m) {
            const WarpResult r = warp_matrix(in, kMethods[m]);
            REQUIRE(r.status == Status::Ok);
            CHECK(in_clip2(r.light_view_proj, r.depth_view_proj, glm::dvec3(0, 2, -9.9), in.light_depth, 1e-4));
            CHECK(in_clip2(r.light_view_proj, r.depth_view_proj, glm::dvec3(0, 2, -2e-5), in.light_depth, 1e-4));
        }
    }
    SUBCASE("coordinates at 1e6") {
        WarpInput in = outdoor(60.0f);
        const glm::vec3 o(1e6f, 0.0f, -1e6f);
        in.camera_view = glm::lookAt(o + glm::vec3(0, 2, 0), o + glm::vec3(0, 2, -1), glm::vec3(0, 1, 0));
        in.scene_min += o;
        in.scene_max += o;
        for (int m = 0; m < 4; ++m) {
            const WarpResult r = warp_matrix(in, kMethods[m]);
            REQUIRE(r.status == Status::Ok);
            CHECK(all_finite(r.light_view_proj));
            CHECK(in_clip2(r.light_view_proj, r.depth_view_proj, glm::dvec3(o) + glm::dvec3(0, 1, -50), in.light_depth, 1e-3));
        }
    }
    SUBCASE("coordinates at 1e-6") {
        WarpInput in = outdoor(60.0f, 1e-7f, 1e-5f);
        in.camera_view = glm::lookAt(glm::vec3(0, 2e-6f, 0), glm::vec3(0, 2e-6f, -1e-6f), glm::vec3(0, 1, 0));
        in.scene_min = glm::vec3(-2e-4f, 0, -2e-4f);
        in.scene_max = glm::vec3(2e-4f, 1e-5f, 2e-4f);
        for (int m = 0; m < 4; ++m) {
            const WarpResult r = warp_matrix(in, kMethods[m]);
            REQUIRE(r.status == Status::Ok);
            CHECK(in_clip2(r.light_view_proj, r.depth_view_proj, glm::dvec3(0, 1e-6, -5e-6), in.light_depth, 1e-3));
        }
    }
    SUBCASE("zero-size bounds and a camera inside the caster bounds") {
        WarpInput in = outdoor(60.0f);
        in.scene_min = in.scene_max = glm::vec3(0, 1, -5);
        for (int m = 0; m < 4; ++m) {
            const WarpResult r = warp_matrix(in, kMethods[m]);
            REQUIRE(r.status == Status::Ok);
            CHECK(r.visible);
            CHECK(all_finite(r.light_view_proj));
        }
        in = outdoor(60.0f);
        in.has_caster_bounds = true;
        in.caster_min = glm::vec3(-5, 0, -5);
        in.caster_max = glm::vec3(5, 20, 5);  // contains the camera
        for (int m = 0; m < 4; ++m) CHECK(warp_matrix(in, kMethods[m]).status == Status::Ok);
    }
}

TEST_CASE("warp: depth conventions agree (GL vs zero-to-one vs reversed)") {
    const WarpInput base = outdoor(50.0f);
    const glm::dvec3 p(1, 1, -20);
    for (int m = 0; m < 4; ++m) {
        WarpInput a = base, b = base, c = base;
        b.light_depth = ClipDepth::ZeroToOne;
        c.light_depth = ClipDepth::ZeroToOne;
        c.light_reversed_z = true;
        double za = 0, zb = 0, zc = 0;
        const WarpResult ra = warp_matrix(a, kMethods[m]), rb = warp_matrix(b, kMethods[m]), rc = warp_matrix(c, kMethods[m]);
        REQUIRE(in_clip2(ra.light_view_proj, ra.depth_view_proj, p, a.light_depth, 1e-5, &za));
        REQUIRE(in_clip2(rb.light_view_proj, rb.depth_view_proj, p, b.light_depth, 1e-5, &zb));
        REQUIRE(in_clip2(rc.light_view_proj, rc.depth_view_proj, p, c.light_depth, 1e-5, &zc));
        CHECK(zb == doctest::Approx(0.5 * za + 0.5).epsilon(1e-5));
        CHECK(zc == doctest::Approx(1.0 - zb).epsilon(1e-5));
    }
}

// Issue 13 (composition), follow-up: a point light just above a wide scene. light_frustum.hpp aims its
// point-light frustum at the axis of the narrowest cone holding the receivers and fits such a light;
// the warps aimed theirs at the receivers' box center (refined to the middle of their angular extent
// only when every point lay in front of that first axis), so the box center, below the scene's top,
// put the far receivers at the light's height beside or behind the axis: LightInsideVolume for the
// composition scene's point light 0.2 and 0.6 units above its top, which light_frustum_fit fits.
// Expected (closed form, as in test_light_frustum): a frustum pointing straight down holds every
// receiver with per-axis tangents <= 20 (the light is e above the box top, every box point within 20 e
// horizontally), so every method must give Ok, and every receiver point in the camera's slice must map
// into the map's clip volume (light_view_proj for x, y and depth_view_proj for the depth).
TEST_CASE("warp: a point light just above a wide scene gets one map (issue 13 composition)") {
    // the composition test's scene and camera (docs/composition.md), the light 0.2 and 0.6 above the top
    for (float above : {0.2f, 0.6f, 1.0f}) {
        WarpInput in;
        in.camera_view = glm::lookAt(glm::vec3(0.5f, 5.5f, 7.5f), glm::vec3(0.0f, 0.5f, 0.0f), glm::vec3(0, 1, 0));
        in.camera_proj = glm::infinitePerspective(glm::radians(50.0f), 192.0f / 144.0f, 0.1f);
        in.max_distance = 30.0f;
        in.has_scene_bounds = true;
        in.scene_min = glm::vec3(-4.0f, 0.0f, -4.0f);
        in.scene_max = glm::vec3(4.0f, 2.2f, 4.0f);
        in.light_position = glm::vec4(0.2f, 2.2f + above, 0.1f, 1.0f);
        for (int m = 0; m < 4; ++m) {
            const WarpResult r = warp_matrix(in, kMethods[m]);
            CHECK_MESSAGE(r.status == Status::Ok, kNames[m], " ", above, " above the top: ", std::string(status_name(r.status)));
            CHECK(r.visible);
        }
    }
    std::mt19937 rng(1313);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    int fitted[4] = {0, 0, 0, 0}, points = 0;
    const int N = 600;
    for (int it = 0; it < N; ++it) {
        const float a = 2.0f + 8.0f * u(rng), b = 2.0f + 8.0f * u(rng), h = 0.5f + 3.0f * u(rng);
        const glm::vec3 lo(-a, 0.0f, -b), hi(a, h, b);
        const glm::vec3 foot(a * (u(rng) - 0.5f), 0.0f, b * (u(rng) - 0.5f));
        const float reach = std::max(std::max(a + std::fabs(foot.x), b + std::fabs(foot.z)), 1e-3f);
        const float e = reach / 20.0f * (1.0f + 3.0f * u(rng));  // at least the height with tangents <= 20
        WarpInput in;
        const glm::vec3 eye(a * (u(rng) - 0.5f), h + 2.0f + 4.0f * u(rng), b + 2.0f + 6.0f * u(rng));
        in.camera_view = glm::lookAt(eye, glm::vec3(0.0f, 0.5f * h, 0.0f), glm::vec3(0, 1, 0));
        in.camera_proj = glm::infinitePerspective(glm::radians(40.0f + 40.0f * u(rng)), 1.0f + u(rng), 0.1f);
        in.max_distance = 100.0f;
        in.has_scene_bounds = true;
        in.scene_min = lo;
        in.scene_max = hi;
        in.light_position = glm::vec4(foot.x, h + e, foot.z, 1.0f);
        const glm::mat4 vp = in.camera_proj * in.camera_view;
        std::vector<glm::dvec3> recv;
        for (int k = 0; k < 200; ++k) {
            const glm::vec3 p = lo + (hi - lo) * glm::vec3(u(rng), u(rng), u(rng));
            const glm::vec4 c = vp * glm::vec4(p, 1.0f);
            const float d = -(in.camera_view * glm::vec4(p, 1.0f)).z;
            if (c.w > 0.0f && std::fabs(c.x) <= c.w && std::fabs(c.y) <= c.w && d >= 0.1f && d <= in.max_distance)
                recv.push_back(glm::dvec3(p));
        }
        for (int m = 0; m < 4; ++m) {
            const WarpResult r = warp_matrix(in, kMethods[m]);
            if (r.status != Status::Ok) {
                FAIL_CHECK(kNames[m] << " it=" << it << ": " << std::string(status_name(r.status)) << " for a light " << e << " above a "
                                     << 2 * a << " x " << 2 * b << " scene");
                continue;
            }
            if (!r.visible) continue;
            ++fitted[m];
            for (const glm::dvec3& p : recv) {
                ++points;
                if (!in_clip2(r.light_view_proj, r.depth_view_proj, p, in.light_depth, 1e-3)) {
                    FAIL_CHECK(kNames[m] << " it=" << it << ": receiver outside the map's clip volume");
                    break;
                }
            }
        }
    }
    MESSAGE("wide scenes, a point light just above: fitted uniform " << fitted[0] << ", psm " << fitted[1] << ", lispsm "
                                                                      << fitted[2] << ", tsm " << fitted[3] << " of " << N
                                                                      << "; " << points << " receiver checks");
    for (int m = 0; m < 4; ++m) CHECK(fitted[m] > N * 5 / 6);
}

// ------------------------------------------------------------------------------------ issue 25
// LiSPSM near the view direction, side by side with filament's LiSPSM. The filament side below is our
// own re-implementation of the warp parameter choice read in google/filament
// filament/src/ShadowMap.cpp (ShadowMap::applyLISPSM: sinLV, the virtual near/far planes
// shadowNearHint = 1 m / shadowFarHint = 100 m, nopt0 / nopt1, the sinLV > 0.02 switch; warpFrustum;
// computeLightRotation; computeFocusParams; intersectFrustumWithBox for its own receiver volume),
// not a copy of its code; it is evaluated on filament's own volume (the view frustum clipped by the
// scene box's light-space bounds) and on shadowkit's (detail::wp_prepare's body).
namespace {

struct Sweep { glm::dvec3 eye, v, up; double fovy, aspect, nearp, farp; };

// filament-like warp on a point set (world), light travel dir d
glm::dmat4 filament_warp(const std::vector<glm::dvec3>& vol, const glm::dvec3& d, const Sweep& c, double* nopt_out, bool* used) {
    // light view: look along d; up: any perpendicular (the rotation L fixes y below)
    glm::dvec3 vp = c.v - glm::dot(c.v, d) * d;
    const double lvp = glm::length(vp);
    glm::dvec3 y = lvp > 1e-9 ? vp / lvp : glm::dvec3(1, 0, 0);
    glm::dvec3 z = -d, x = glm::cross(y, z);
    glm::dmat4 LV(1.0);
    LV[0] = glm::dvec4(x.x, y.x, z.x, 0); LV[1] = glm::dvec4(x.y, y.y, z.y, 0); LV[2] = glm::dvec4(x.z, y.z, z.z, 0);
    LV[3] = glm::dvec4(0, 0, 0, 1);
    const glm::dmat4 V = glm::lookAt(c.eye, c.eye + c.v, c.up);
    double zn = 1e300, zf = -1e300, n = 1e300, f = -1e300;
    for (auto& p : vol) {
        double dep = -(V * glm::dvec4(p, 1)).z;
        zn = std::fmin(zn, dep); zf = std::fmax(zf, dep);
        double yy = (LV * glm::dvec4(p, 1)).y;
        n = std::fmin(n, yy); f = std::fmax(f, yy);
    }
    zn = std::fmax(zn, c.nearp); zf = std::fmin(zf, c.farp);
    const double dd = f - n;
    const double LoV = glm::dot(c.v, d), sinLV = std::sqrt(std::fmax(0.0, 1 - LoV * LoV));
    const double nearHint = 1.0, farHint = 100.0;
    const double dzn = std::fmax(0.0, nearHint - c.nearp), dzf = std::fmax(0.0, c.farp - farHint);
    const double z0 = zn, z1 = z0 + dd * sinLV;
    glm::dmat4 W(1.0);
    *used = false;
    if (f > n && sinLV > 0.02 && 3 * (dzn / (zf - zn)) < 2) {
        const double vz0 = std::fmax(0.0, std::fmax(std::fmax(zn, c.nearp + dzn), z0));
        const double vz1 = std::fmax(0.0, std::fmin(std::fmin(zf, c.farp - dzf), z1));
        const double nopt0 = (z0 + std::sqrt(vz0 * vz1)) / sinLV;
        const double nopt1 = dzn / (2 - 3 * (dzn / (zf - zn)));
        const double nopt = std::fmax(nopt0, nopt1);
        *nopt_out = nopt;
        *used = true;
        const glm::dvec3 cam = glm::dvec3(LV * glm::dvec4(c.eye, 1));
        const glm::dvec3 p(cam.x, n - nopt, 0);
        const double nn = nopt, ff = nopt + dd;
        glm::dmat4 Wp(0.0);
        Wp[0][0] = nn; Wp[1][1] = (ff + nn) / (ff - nn); Wp[3][1] = -2 * nn * ff / (ff - nn); Wp[2][2] = nn; Wp[1][3] = 1;
        W = Wp * glm::translate(glm::dmat4(1.0), -p);
    }
    const glm::dmat4 WL = W * LV;
    glm::dvec2 mn(1e300), mx(-1e300);
    for (auto& p : vol) { glm::dvec4 h = WL * glm::dvec4(p, 1); glm::dvec2 q = glm::dvec2(h) / h.w; mn = glm::min(mn, q); mx = glm::max(mx, q); }
    glm::dmat4 F(1.0);
    F[0][0] = 2 / (mx.x - mn.x); F[1][1] = 2 / (mx.y - mn.y);
    F[3][0] = -(mx.x + mn.x) / (mx.x - mn.x); F[3][1] = -(mx.y + mn.y) / (mx.y - mn.y);
    // depth irrelevant for the metric: scale z small
    glm::dmat4 Z(1.0); Z[2][2] = 1e-3;
    return F * Z * WL;
}

// frustum ∩ {light-space AABB of box}: vertices from plane triples
std::vector<glm::dvec3> filament_volume(const Sweep& c, const glm::dvec3& d, const glm::dvec3& bmn, const glm::dvec3& bmx) {
    glm::dvec3 vp = c.v - glm::dot(c.v, d) * d; glm::dvec3 y = glm::length(vp) > 1e-9 ? glm::normalize(vp) : glm::dvec3(1,0,0);
    glm::dvec3 z = -d, x = glm::cross(y, z);
    glm::dvec3 ax[3] = {x, y, z};
    std::vector<glm::dvec4> pl;
    for (int a = 0; a < 3; ++a) {
        double lo = 1e300, hi = -1e300;
        for (int k = 0; k < 8; ++k) { glm::dvec3 q((k&1)?bmx.x:bmn.x,(k&2)?bmx.y:bmn.y,(k&4)?bmx.z:bmn.z); double t = glm::dot(q, ax[a]); lo = std::fmin(lo,t); hi = std::fmax(hi,t);}
        pl.push_back(glm::dvec4(ax[a], -lo)); pl.push_back(glm::dvec4(-ax[a], hi));
    }
    // frustum planes (inward)
    const glm::dvec3 r = glm::normalize(glm::cross(c.v, c.up)), u = glm::cross(r, c.v);
    const double ty = std::tan(0.5 * c.fovy), tx = ty * c.aspect;
    auto addp = [&](glm::dvec3 nrm, glm::dvec3 pt) { nrm = glm::normalize(nrm); pl.push_back(glm::dvec4(nrm, -glm::dot(nrm, pt))); };
    addp(c.v, c.eye + c.nearp * c.v); addp(-c.v, c.eye + c.farp * c.v);
    addp(c.v * tx + r, c.eye); addp(c.v * tx - r, c.eye); addp(c.v * ty + u, c.eye); addp(c.v * ty - u, c.eye);
    std::vector<glm::dvec3> out;
    for (size_t i = 0; i < pl.size(); ++i) for (size_t j = i+1; j < pl.size(); ++j) for (size_t k = j+1; k < pl.size(); ++k) {
        glm::dvec3 a(pl[i]), b(pl[j]), cc(pl[k]); glm::dvec3 bc = glm::cross(b, cc); double det = glm::dot(a, bc);
        if (std::fabs(det) < 1e-12) continue;
        glm::dvec3 p = (-pl[i].w * bc - pl[j].w * glm::cross(cc, a) - pl[k].w * glm::cross(a, b)) / det;
        bool in = true; for (auto& q : pl) in = in && glm::dot(glm::dvec3(q), p) + q.w >= -1e-6 * (1 + glm::length(p));
        if (in) out.push_back(p);
    }
    return out;
}


struct AliasStat { double mx = 0, mean = 0; int n = 0; };

// 64 x 64 screen samples on the ground plane y = 0 (within the 400-unit box), surfaces facing the light,
// 2048^2 map, 1920 x 1080 screen: screen pixels per texel from warp_aliasing_error.
AliasStat ground_aliasing(const glm::mat4& L, const Sweep& c, const glm::dvec3& d) {
    const glm::mat4 P = glm::perspective(float(c.fovy), float(c.aspect), float(c.nearp), float(c.farp));
    const glm::mat4 V = glm::lookAt(glm::vec3(c.eye), glm::vec3(c.eye + c.v), glm::vec3(c.up));
    const glm::dmat4 iv = glm::inverse(glm::dmat4(P) * glm::dmat4(V));
    AliasStat st;
    double sum = 0;
    for (int j = 0; j < 64; ++j)
        for (int i = 0; i < 64; ++i) {
            const double x = -1 + (i + 0.5) / 32.0, y = -1 + (j + 0.5) / 32.0;
            const glm::dvec4 a = iv * glm::dvec4(x, y, -1, 1), b = iv * glm::dvec4(x, y, 1, 1);
            const glm::dvec3 pa = glm::dvec3(a) / a.w, pb = glm::dvec3(b) / b.w;
            if (!(pb.y < 0)) continue;
            const double t = pa.y / (pa.y - pb.y);
            if (t < 0 || t > 1) continue;
            const glm::dvec3 p = pa + t * (pb - pa);
            if (std::fabs(p.x) > 400 || std::fabs(p.z) > 400) continue;
            const WarpAliasingValue e = warp_aliasing_error(L, P * V, glm::vec3(p), glm::vec3(-d), 2048, {1920, 1080});
            if (e.status != Status::Ok) continue;
            st.mx = std::fmax(st.mx, e.value);
            sum += e.value;
            ++st.n;
        }
    st.mean = st.n ? sum / st.n : 0;
    return st;
}

// The camera over the ground: eye at height h, pitched down, the ground box +-400 wu, casters up to `top`.
Sweep ground_camera(double pitch_deg, double nearp, double h, double farp, double fovy) {
    Sweep c;
    c.nearp = nearp;
    c.farp = farp;
    c.fovy = fovy;
    c.aspect = 16.0 / 9.0;
    c.eye = glm::dvec3(0, h, 0);
    const double pr = glm::radians(pitch_deg);
    c.v = glm::dvec3(0, -std::sin(pr), -std::cos(pr));
    c.up = glm::dvec3(0, std::cos(pr), -std::sin(pr));
    return c;
}

// The light's direction of travel at gamma degrees from the view, rotated down (the sun behind and above).
glm::dvec3 ground_light(const Sweep& c, double gamma_deg) {
    const double g = glm::radians(gamma_deg);
    return std::cos(g) * c.v - std::sin(g) * c.up;
}

WarpInput ground_input(const Sweep& c, const glm::dvec3& d, double top) {
    WarpInput in;
    in.camera_view = glm::lookAt(glm::vec3(c.eye), glm::vec3(c.eye + c.v), glm::vec3(c.up));
    in.camera_proj = glm::perspective(float(c.fovy), float(c.aspect), float(c.nearp), float(c.farp));
    in.light_position = glm::vec4(glm::vec3(-d), 0.0f);
    in.has_scene_bounds = true;
    in.scene_min = glm::vec3(-400, 0, -400);
    in.scene_max = glm::vec3(400, float(top), 400);
    return in;
}

}  // namespace

TEST_CASE("warp: issue 25 - LiSPSM max aliasing no worse than filament's formulation from 90 to 1 degree") {
    struct Cam { double pitch, nearp, h, farp, fovy, top; };
    const Cam cams[3] = {{0, 1, 2, 400, 1.0, 10}, {10, 0.5, 5, 600, glm::radians(60.0), 10}, {20, 0.1, 10, 600, glm::radians(60.0), 1}};
    for (const Cam& cm : cams) {
        const Sweep c = ground_camera(cm.pitch, cm.nearp, cm.h, cm.farp, cm.fovy);
        MESSAGE("camera pitch " << cm.pitch << " deg, near " << cm.nearp << ", height " << cm.h << ", casters to " << cm.top
                                << "; max/mean screen px per texel: angle | Wimmer (before) | Lloyd, no virtual planes | default (Lloyd + virtual planes) | filament own | filament on shadowkit's volume");
        for (double g : {90.0, 60.0, 30.0, 10.0, 5.0, 3.0, 2.0, 1.0}) {
            const glm::dvec3 d = ground_light(c, g);
            const WarpInput in = ground_input(c, d, cm.top);
            WarpInput old = in, bare = in;
            old.options.lispsm_n_opt = LispsmNOpt::Wimmer;
            bare.options.lispsm_virtual_near = bare.options.lispsm_virtual_far = 0.0f;
            const WarpResult rn = warp_lispsm_matrix(in), ro = warp_lispsm_matrix(old), rb = warp_lispsm_matrix(bare);
            REQUIRE(rn.status == Status::Ok);
            REQUIRE(ro.status == Status::Ok);
            REQUIRE(rb.status == Status::Ok);
            const AliasStat sn = ground_aliasing(rn.light_view_proj, c, d), so = ground_aliasing(ro.light_view_proj, c, d),
                            sb = ground_aliasing(rb.light_view_proj, c, d);
            double nopt = 0;
            bool used = false;
            const std::vector<glm::dvec3> vol = filament_volume(c, d, glm::dvec3(-400, 0, -400), glm::dvec3(400, cm.top, 400));
            const AliasStat sf = ground_aliasing(glm::mat4(filament_warp(vol, d, c, &nopt, &used)), c, d);
            const detail::wp_Setup su = detail::wp_prepare(in);
            const std::vector<glm::dvec3> body(su.body, su.body + su.nbody);
            const AliasStat sk = ground_aliasing(glm::mat4(filament_warp(body, d, c, &nopt, &used)), c, d);
            MESSAGE(g << " | " << so.mx << " / " << so.mean << " | " << sb.mx << " / " << sb.mean << " | " << sn.mx << " / " << sn.mean << " | " << sf.mx << " / " << sf.mean
                      << " | " << sk.mx << " / " << sk.mean);
            REQUIRE(sn.n > 1000);
            CHECK(sn.mx <= 1.01 * sk.mx);  // filament's formulation on the same receivers
            CHECK(sn.mx <= 1.01 * sf.mx);  // filament's own fit
        }
    }
}

TEST_CASE("warp: issue 25 - the new n_opt stays continuous over the ground sweep (< 0.01 NDC per 0.002 degree)") {
    const Sweep c = ground_camera(0, 1, 2, 400, 1.0);
    std::vector<glm::dvec3> pts;
    for (int i = -4; i <= 4; ++i)
        for (int k = 1; k <= 12; ++k) pts.push_back(glm::dvec3(i * 0.5 * k, 0.0, -4.0 * k * k));
    for (LispsmNOpt opt : {LispsmNOpt::Lloyd, LispsmNOpt::Wimmer}) {
        const std::string name = opt == LispsmNOpt::Lloyd ? "Lloyd" : "Wimmer";
        // 0.002 degree steps through the fade (sin 0.02 .. 0.03: 1.15 .. 1.72 degrees) and past it, and
        // around 30 and 90 degrees
        for (const glm::dvec2 range : {glm::dvec2(0.6, 4.0), glm::dvec2(29.5, 30.5), glm::dvec2(89.5, 90.0)}) {
            double worst = 0, at = 0;
            WarpResult prev;
            for (double a = range.x; a <= range.y + 1e-9; a += 0.002) {
                WarpInput in = ground_input(c, ground_light(c, a), 10);
                in.options.lispsm_n_opt = opt;
                const WarpResult r = warp_lispsm_matrix(in);
                REQUIRE(r.status == Status::Ok);
                if (prev.status == Status::Ok)
                    for (const glm::dvec3& p : pts) {
                        const double mv = glm::length(ndc_xy(r.light_view_proj, p) - ndc_xy(prev.light_view_proj, p));
                        if (mv > worst) { worst = mv; at = a; }
                    }
                prev = r;
            }
            MESSAGE(name << ", " << range.x << " .. " << range.y << " deg: largest step " << worst << " NDC at " << at << " deg");
            CHECK(worst < 0.01);
        }
    }
}

TEST_CASE("warp: issue 25 - the n_opt options are checked") {
    WarpInput in = outdoor(30.0f);
    in.options.lispsm_virtual_near = -1.0f;
    CHECK(warp_lispsm_matrix(in).status == Status::InvalidArgument);
    in = outdoor(30.0f);
    in.options.lispsm_virtual_far = std::numeric_limits<float>::quiet_NaN();
    CHECK(warp_lispsm_matrix(in).status == Status::NonFinite);
    in = outdoor(30.0f);
    in.options.lispsm_n_opt = static_cast<LispsmNOpt>(7);
    CHECK(warp_lispsm_matrix(in).status == Status::InvalidArgument);
    // Lloyd without virtual planes at 90 degrees: n = z_n + sqrt(z_n z_f) (both formulas agree there)
    in = outdoor(90.0f);
    in.options.lispsm_virtual_near = 0.0f;
    in.options.lispsm_virtual_far = 0.0f;
    WarpInput w = in;
    w.options.lispsm_n_opt = LispsmNOpt::Wimmer;
    CHECK(warp_lispsm_matrix(in).warp_parameter == doctest::Approx(warp_lispsm_matrix(w).warp_parameter).epsilon(1e-5));
}
