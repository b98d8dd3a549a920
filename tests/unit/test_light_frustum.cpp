// Unit and property tests for shadowkit/light_frustum.hpp.
// Expected values: closed form (frustum corners), brute force (ray casting for culling, point
// sampling for containment), independent recomputation (texel snapping).
#include <shadowkit/light_frustum.hpp>

#include <doctest/doctest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

using namespace shadowkit;

namespace {

struct Cam {
    glm::mat4 view, proj;
    ClipDepth cd;
    bool rev;
    float nearp, farp, maxd;
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

Cam random_camera(std::mt19937& rng, bool allow_inf = true, float coord_scale = 50.0f) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    Cam c;
    c.pos = glm::vec3(u(rng) - 0.5f, u(rng) * 0.5f, u(rng) - 0.5f) * coord_scale;
    const float yaw = u(rng) * 6.2831853f, pitch = (u(rng) - 0.5f) * 3.0f;
    c.fwd = glm::vec3(std::cos(pitch) * std::cos(yaw), std::sin(pitch), std::cos(pitch) * std::sin(yaw));
    const glm::vec3 up = std::fabs(c.fwd.y) > 0.99f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    c.view = glm::lookAt(c.pos, c.pos + c.fwd, up);
    c.cd = (rng() & 1) ? ClipDepth::ZeroToOne : ClipDepth::NegativeOneToOne;
    c.rev = (rng() & 2) != 0;
    c.nearp = 0.05f + u(rng) * 2.0f;
    c.farp = c.nearp * (5.0f + u(rng) * 200.0f);
    const bool inf = allow_inf && (rng() % 4 == 0);
    c.maxd = inf ? c.farp : 0.0f;
    c.proj = make_proj(0.4f + u(rng) * 1.4f, 0.5f + u(rng) * 1.5f, c.nearp, c.farp, c.cd, c.rev, inf);
    return c;
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

}  // namespace

TEST_CASE("light_frustum: camera slice corners match the closed form for every depth convention") {
    const float fovy = 1.0f, aspect = 1.5f, n = 0.5f, f = 40.0f;
    const double ty = std::tan(0.5), tx = ty * aspect;
    for (int cdi = 0; cdi < 2; ++cdi)
        for (int rev = 0; rev < 2; ++rev)
            for (int inf = 0; inf < 2; ++inf) {
                const ClipDepth cd = cdi ? ClipDepth::ZeroToOne : ClipDepth::NegativeOneToOne;
                const glm::mat4 P = make_proj(fovy, aspect, n, f, cd, rev != 0, inf != 0);
                glm::vec3 c[8];
                const float maxd = inf ? 25.0f : 0.0f;
                REQUIRE(camera_slice_corners(glm::mat4(1.0f), P, cd, rev != 0, maxd, 0, 0, c) == LightFrustumStatus::Ok);
                const double dfar = inf ? 25.0 : 40.0;
                for (int i = 0; i < 8; ++i) {
                    const double d = (i & 4) ? dfar : 0.5;
                    const double ex = ((i & 1) ? 1 : -1) * tx * d, ey = ((i & 2) ? 1 : -1) * ty * d;
                    CHECK(c[i].x == doctest::Approx(ex).epsilon(1e-4));
                    CHECK(c[i].y == doctest::Approx(ey).epsilon(1e-4));
                    CHECK(c[i].z == doctest::Approx(-d).epsilon(1e-4));
                }
                // receiver depth clip
                REQUIRE(camera_slice_corners(glm::mat4(1.0f), P, cd, rev != 0, maxd, 2.0f, 10.0f, c) == LightFrustumStatus::Ok);
                CHECK(c[0].z == doctest::Approx(-2.0));
                CHECK(c[7].z == doctest::Approx(-10.0));
                if (inf) {
                    CHECK(camera_slice_corners(glm::mat4(1.0f), P, cd, rev != 0, 0.0f, 0, 0, c) == LightFrustumStatus::InfiniteFar);
                }
            }
    // glm's own builders agree
    glm::vec3 c[8];
    REQUIRE(camera_slice_corners(glm::mat4(1.0f), glm::perspectiveZO(fovy, aspect, n, f), ClipDepth::ZeroToOne, false, 0, 0, 0, c) == LightFrustumStatus::Ok);
    CHECK(c[7].x == doctest::Approx(tx * 40.0).epsilon(1e-4));
    REQUIRE(camera_slice_corners(glm::mat4(1.0f), glm::infinitePerspective(fovy, aspect, n), ClipDepth::NegativeOneToOne, false, 100.0f, 0, 0, c) == LightFrustumStatus::Ok);
    CHECK(c[7].z == doctest::Approx(-100.0).epsilon(1e-4));
    // orthographic camera
    REQUIRE(camera_slice_corners(glm::mat4(1.0f), glm::ortho(-2.f, 2.f, -1.f, 1.f, 1.f, 9.f), ClipDepth::NegativeOneToOne, false, 0, 0, 0, c) == LightFrustumStatus::Ok);
    CHECK(c[0].x == doctest::Approx(-2.0));
    CHECK(c[7].z == doctest::Approx(-9.0));
}

TEST_CASE("light_frustum: containment and no false culling over thousands of random cameras and lights") {
    std::mt19937 rng(1234);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    int runs = 0, ok = 0, checked_points = 0, culled_total = 0, casters_total = 0, hits_checked = 0;
    for (int it = 0; it < 2500; ++it) {
        const Cam cam = random_camera(rng);
        LightFrustumInput in;
        in.camera_view = cam.view;
        in.camera_proj = cam.proj;
        in.camera_depth = cam.cd;
        in.camera_reversed_z = cam.rev;
        in.max_distance = cam.maxd;
        if (rng() % 3 == 0) {
            in.receiver_min_depth = cam.nearp * (1.0f + 3.0f * u(rng));
            in.receiver_max_depth = in.receiver_min_depth + cam.farp * u(rng);
        }
        const bool point = rng() % 3 == 0;
        in.light = point ? glm::vec4(glm::vec3(u(rng) - 0.5f, u(rng), u(rng) - 0.5f) * 150.0f, 1.0f)
                         : glm::vec4(random_dir(rng), 0.0f);
        in.has_scene_bounds = rng() % 2 == 0;
        in.scene_min = glm::vec3(-60, -10, -60) + glm::vec3(u(rng), u(rng), u(rng)) * 20.0f;
        in.scene_max = glm::vec3(60, 30, 60) - glm::vec3(u(rng), u(rng), u(rng)) * 20.0f;
        in.light_depth = (rng() & 1) ? ClipDepth::ZeroToOne : ClipDepth::NegativeOneToOne;
        in.light_reversed_z = false;
        in.stable = !point && rng() % 3 == 0;
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
        const LightFrustumResult r = fit_light_frustum(in, keep.data(), keep.size());
        ++runs;
        if (r.status == LightFrustumStatus::EmptyReceivers || r.status == LightFrustumStatus::LightInsideVolume) continue;
        REQUIRE(r.status == LightFrustumStatus::Ok);
        ++ok;
        for (int c = 0; c < 4; ++c)
            for (int k = 0; k < 4; ++k) REQUIRE(std::isfinite(r.view_proj[c][k]));
        CHECK(r.kept_count + r.culled_count == std::size_t(nc));
        casters_total += nc;
        culled_total += int(r.culled_count);

        glm::vec3 sc[8];
        REQUIRE(camera_slice_corners(in.camera_view, in.camera_proj, cam.cd, cam.rev, in.max_distance,
                                     in.receiver_min_depth, in.receiver_max_depth, sc) == LightFrustumStatus::Ok);
        glm::dvec4 pl[12];
        planes_of(sc, pl);
        int np = 6;
        if (in.has_scene_bounds) {
            pl[6] = {1, 0, 0, -in.scene_min.x}; pl[7] = {-1, 0, 0, in.scene_max.x};
            pl[8] = {0, 1, 0, -in.scene_min.y}; pl[9] = {0, -1, 0, in.scene_max.y};
            pl[10] = {0, 0, 1, -in.scene_min.z}; pl[11] = {0, 0, -1, in.scene_max.z};
            np = 12;
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
        //     and that sample must be inside the light clip volume (it is rendered into the map)
        std::vector<char> kept(nc, 0);
        for (std::size_t k = 0; k < r.kept_count; ++k) kept[keep[k]] = 1;
        for (int i = 0; i < nc; ++i) {
            const float* b = &boxes[size_t(6 * i)];
            for (int s = 0; s < 30; ++s) {
                const glm::dvec3 q(b[0] + (b[3] - b[0]) * double(u(rng)), b[1] + (b[4] - b[1]) * double(u(rng)),
                                   b[2] + (b[5] - b[2]) * double(u(rng)));
                const glm::dvec3 dir = point ? glm::dvec3(q) - glm::dvec3(in.light) : glm::dvec3(in.light);
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

TEST_CASE("light_frustum: culling on a fixed random scene (report numbers)") {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    LightFrustumInput in;
    in.camera_view = glm::lookAt(glm::vec3(0, 2, 0), glm::vec3(10, 1, 0), glm::vec3(0, 1, 0));
    in.camera_proj = glm::perspective(1.0f, 16.0f / 9.0f, 0.1f, 100.0f);
    in.light = glm::vec4(glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f)), 0.0f);
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
    const LightFrustumResult r = fit_light_frustum(in, keep.data(), keep.size());
    REQUIRE(r.status == LightFrustumStatus::Ok);
    MESSAGE("10000 random casters, camera 100 wu far plane: kept " << r.kept_count << ", culled " << r.culled_count);
    CHECK(r.culled_count > 8000);
    // receiver depth range from a reduction culls more
    in.receiver_min_depth = 5.0f;
    in.receiver_max_depth = 30.0f;
    const LightFrustumResult r2 = fit_light_frustum(in, keep.data(), keep.size());
    REQUIRE(r2.status == LightFrustumStatus::Ok);
    MESSAGE("with receivers in [5, 30]: kept " << r2.kept_count << ", culled " << r2.culled_count);
    CHECK(r2.kept_count < r.kept_count);
    // buffer too small: count still reported
    const LightFrustumResult r3 = fit_light_frustum(in, keep.data(), 3);
    CHECK(r3.status == LightFrustumStatus::BufferTooSmall);
    CHECK(r3.kept_count == r2.kept_count);
    const LightFrustumResult r4 = fit_light_frustum(in, nullptr, 0);
    CHECK(r4.kept_count == r2.kept_count);
}

TEST_CASE("light_frustum: stable mode is rotation invariant and moves by whole texels") {
    std::mt19937 rng(99);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const unsigned S = 2048;
    int rot_cases = 0, trans_cases = 0;
    for (int it = 0; it < 300; ++it) {
        LightFrustumInput in;
        in.camera_proj = glm::perspective(0.5f + u(rng), 0.7f + u(rng), 0.1f + u(rng), 30.0f + 100.0f * u(rng));
        in.light = glm::vec4(random_dir(rng), 0.0f);
        in.stable = true;
        in.shadow_map_size = S;
        const glm::vec3 pos = glm::vec3(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f) * 40.0f;
        auto fit = [&](const glm::vec3& p, const glm::vec3& fwd) {
            in.camera_view = glm::lookAt(p, p + fwd, std::fabs(fwd.y) > 0.99f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0));
            const LightFrustumResult r = fit_light_frustum(in, nullptr, 0);
            REQUIRE(r.status == LightFrustumStatus::Ok);
            return r;
        };
        const LightFrustumResult a = fit(pos, random_dir(rng));
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
            const LightFrustumResult b = fit(pos, random_dir(rng));
            ++rot_cases;
            for (int c = 0; c < 3; ++c)
                for (int row = 0; row < 2; ++row) CHECK(a.view_proj[c][row] == b.view_proj[c][row]);
            CHECK(a.bounding_sphere.w == b.bounding_sphere.w);
            const glm::dvec2 ta = origin_texel(a), tb = origin_texel(b);
            CHECK(std::fabs(ta.x - std::round(ta.x)) < 1e-3);
            CHECK(std::fabs(tb.y - std::round(tb.y)) < 1e-3);
            const glm::dvec2 dt = tb - ta;
            CHECK(std::fabs(dt.x - std::round(dt.x)) < 1e-3);
            CHECK(std::fabs(dt.y - std::round(dt.y)) < 1e-3);
        }
        // translation (sub-texel and larger): the origin moves by whole texels; texel size constant
        const glm::vec3 fwd = random_dir(rng);
        const LightFrustumResult c0 = fit(pos, fwd);
        for (int k = 0; k < 5; ++k) {
            const float step = (k < 2 ? 0.3f : 20.0f) * c0.texel_world_size;
            const LightFrustumResult c1 = fit(pos + random_dir(rng) * step, fwd);
            ++trans_cases;
            CHECK(c1.texel_world_size == c0.texel_world_size);
            const glm::dvec2 dt = origin_texel(c1) - origin_texel(c0);
            CHECK(std::fabs(dt.x - std::round(dt.x)) < 1e-3);
            CHECK(std::fabs(dt.y - std::round(dt.y)) < 1e-3);
        }
    }
    MESSAGE("stable: " << rot_cases << " rotations, " << trans_cases << " translations checked");
}

TEST_CASE("light_frustum: anchor - an unsnapped stable fit (SaschaWillems cascades) swims, ours does not") {
    // Reproduce the unsnapped variant by hand: ortho box centered on the sphere center without snapping.
    LightFrustumInput in;
    in.camera_proj = glm::perspective(1.0f, 1.0f, 0.5f, 50.0f);
    in.light = glm::vec4(glm::normalize(glm::vec3(0.2f, -1.0f, 0.4f)), 0.0f);
    in.stable = true;
    in.shadow_map_size = 1024;
    const glm::vec3 fwd = glm::normalize(glm::vec3(1, -0.2f, 0.3f));
    in.camera_view = glm::lookAt(glm::vec3(0), fwd, glm::vec3(0, 1, 0));
    const LightFrustumResult a = fit_light_frustum(in, nullptr, 0);
    const glm::vec3 side = glm::normalize(glm::cross(fwd, glm::vec3(0, 1, 0)));
    const glm::vec3 p = side * (0.37f * a.texel_world_size);
    in.camera_view = glm::lookAt(p, p + fwd, glm::vec3(0, 1, 0));
    const LightFrustumResult b = fit_light_frustum(in, nullptr, 0);
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

TEST_CASE("light_frustum: stiff cases") {
    LightFrustumInput base;
    base.camera_view = glm::lookAt(glm::vec3(0, 2, 0), glm::vec3(0, 2, -1), glm::vec3(0, 1, 0));
    base.camera_proj = glm::perspective(1.0f, 1.0f, 0.1f, 50.0f);
    base.light = glm::vec4(0, -1, 0, 0);

    SUBCASE("light parallel and anti-parallel to the view direction") {
        for (float s : {1.0f, -1.0f}) {
            LightFrustumInput in = base;
            in.light = glm::vec4(0, 0, -s, 0);
            for (int stable = 0; stable < 2; ++stable) {
                in.stable = stable != 0;
                const LightFrustumResult r = fit_light_frustum(in, nullptr, 0);
                REQUIRE(r.status == LightFrustumStatus::Ok);
                glm::vec3 c[8];
                camera_slice_corners(in.camera_view, in.camera_proj, in.camera_depth, false, 0, 0, 0, c);
                for (int i = 0; i < 8; ++i) CHECK(in_clip(r.view_proj, glm::dvec3(c[i]), in.light_depth));
            }
        }
    }
    SUBCASE("directional light straight down on a camera looking straight down") {
        LightFrustumInput in = base;
        in.camera_view = glm::lookAt(glm::vec3(0, 10, 0), glm::vec3(0, 0, 0), glm::vec3(0, 0, -1));
        const LightFrustumResult r = fit_light_frustum(in, nullptr, 0);
        REQUIRE(r.status == LightFrustumStatus::Ok);
    }
    SUBCASE("point light behind the camera, in the near plane, and inside the receivers") {
        LightFrustumInput in = base;
        in.light = glm::vec4(0, 3, 5, 1);  // behind
        CHECK(fit_light_frustum(in, nullptr, 0).status == LightFrustumStatus::Ok);
        in.light = glm::vec4(0.5f, 2, -0.1f, 1);  // in the camera's near plane
        const LightFrustumResult rn = fit_light_frustum(in, nullptr, 0);
        CHECK((rn.status == LightFrustumStatus::Ok || rn.status == LightFrustumStatus::LightInsideVolume));
        in.light = glm::vec4(0, 2, -20, 1);  // inside the frustum: needs a cube map
        CHECK(fit_light_frustum(in, nullptr, 0).status == LightFrustumStatus::LightInsideVolume);
    }
    SUBCASE("near 1e-5, far at infinity, and near/far ratio 1e-6") {
        LightFrustumInput in = base;
        in.camera_proj = glm::infinitePerspective(1.0f, 1.0f, 1e-5f);
        CHECK(fit_light_frustum(in, nullptr, 0).status == LightFrustumStatus::InfiniteFar);
        in.max_distance = 10.0f;
        const LightFrustumResult r = fit_light_frustum(in, nullptr, 0);
        REQUIRE(r.status == LightFrustumStatus::Ok);
        CHECK(in_clip(r.view_proj, glm::dvec3(0, 2, -9.99), in.light_depth));
        in.camera_proj = glm::perspective(1.0f, 1.0f, 1e-5f, 10.0f);
        in.max_distance = 0.0f;
        CHECK(fit_light_frustum(in, nullptr, 0).status == LightFrustumStatus::Ok);
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
        const LightFrustumResult r = fit_light_frustum(in, &k, 1);
        REQUIRE(r.status == LightFrustumStatus::Ok);
        CHECK(r.kept_count == 1);
        CHECK(k == 0);
        CHECK(in_clip(r.view_proj, glm::dvec3(p) + glm::dvec3(20, 0, 0), in.light_depth, 1e-3));
        in.stable = true;
        const LightFrustumResult rs = fit_light_frustum(in, &k, 1);
        CHECK(rs.status == LightFrustumStatus::Ok);
        CHECK(in_clip(rs.view_proj, glm::dvec3(p) + glm::dvec3(20, 0, 0), in.light_depth, 1e-3));
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
        const LightFrustumResult r = fit_light_frustum(in, k, 2);
        REQUIRE(r.status == LightFrustumStatus::Ok);
        CHECK(r.kept_count == 1);
        CHECK(k[0] == 0);
        CHECK(in_clip(r.view_proj, glm::dvec3(0, 2, -5), in.light_depth));
        in.scene_min = in.scene_max = glm::vec3(0, 2, 5);  // behind the camera
        CHECK(fit_light_frustum(in, k, 2).status == LightFrustumStatus::EmptyReceivers);
    }
    SUBCASE("NaN / Inf / invalid inputs give a status, never a NaN matrix") {
        const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
        LightFrustumInput in = base;
        in.camera_view[1][2] = nan;
        CHECK(fit_light_frustum(in, nullptr, 0).status == LightFrustumStatus::InvalidInput);
        in = base;
        in.light = glm::vec4(inf, 0, 0, 0);
        CHECK(fit_light_frustum(in, nullptr, 0).status == LightFrustumStatus::InvalidInput);
        in = base;
        in.light = glm::vec4(0, 0, 0, 0);
        CHECK(fit_light_frustum(in, nullptr, 0).status == LightFrustumStatus::InvalidInput);
        in = base;
        in.camera_proj = glm::mat4(0.0f);
        CHECK(fit_light_frustum(in, nullptr, 0).status == LightFrustumStatus::InvalidInput);
        in = base;
        const float bad[12] = {nan, 0, 0, 1, 1, 1, 1, 1, 1, 0, 0, 0};  // NaN box, min > max box
        in.casters = bad;
        in.caster_count = 2;
        const LightFrustumResult r = fit_light_frustum(in, nullptr, 0);
        CHECK(r.status == LightFrustumStatus::Ok);
        CHECK(r.invalid_count == 2);
        CHECK(r.culled_count == 2);
    }
    SUBCASE("casters behind the camera that shadow the view are kept (light from behind)") {
        LightFrustumInput in = base;
        in.light = glm::vec4(glm::normalize(glm::vec3(0, -1, -1)), 0);  // travels forward and down
        const float box[6] = {-1, 6, 3, 1, 8, 5};                         // above and behind the camera
        in.casters = box;
        in.caster_count = 1;
        const LightFrustumResult r = fit_light_frustum(in, nullptr, 0);
        CHECK(r.kept_count == 1);
        CHECK(in_clip(r.view_proj, glm::dvec3(0, 7, 4), in.light_depth, 1e-3));
    }
}
