// contact_shadow.hpp: the march against depth buffers rendered here by ray casting an analytic scene
// (a floor, a box) in double precision and quantized to the buffer's format. Expected answers come
// from the geometry: a flat floor never occludes a ray leaving it toward a light above it; a ray
// through a box, seen from outside, passes behind the box's visible surface (occluded); a ray whose
// every point is seen by the camera with a margin around the box is lit. Cases closer than the
// margins to either answer are not asserted. Projections are written out here (not glm's). Every
// test that marches runs contact_shadow_march and contact_shadow_march_aligned (one sample per pixel,
// and 4 samples with jitter: a sample every few pixels, which may step over short occluded stretches).
#include <doctest/doctest.h>

#include <shadowkit/contact_shadow.hpp>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace sk = shadowkit;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;

struct Cam {
    glm::dvec3 eye{0.0, 2.0, 0.0}, target{0.0, 0.0, -6.0};
    double fovy = 1.0, near_z = 0.1, far_z = 100.0;  // far may be +inf
    int width = 160, height = 120;
    sk::ClipDepth clip = sk::ClipDepth::NegativeOneToOne;
    bool reversed = false;
    sk::DepthFormat format = sk::DepthFormat::Fixed24;
};

// Right-handed view (camera looks down -z), written out.
glm::dmat4 view_of(const Cam& c) {
    const glm::dvec3 f = glm::normalize(c.target - c.eye);
    const glm::dvec3 up = std::fabs(f.y) > 0.99 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    const glm::dvec3 s = glm::normalize(glm::cross(f, up));
    const glm::dvec3 u = glm::cross(s, f);
    glm::dmat4 v(1.0);
    for (int i = 0; i < 3; ++i) {
        v[i][0] = s[i];
        v[i][1] = u[i];
        v[i][2] = -f[i];
    }
    v[3][0] = -glm::dot(s, c.eye);
    v[3][1] = -glm::dot(u, c.eye);
    v[3][2] = glm::dot(f, c.eye);
    return v;
}

// Perspective projection: z row (a, b) for each clip depth / reversed / infinite far, w = -z.
glm::dmat4 proj_of(const Cam& c) {
    const double n = c.near_z, f = c.far_z, t = std::tan(c.fovy / 2.0);
    const double aspect = double(c.width) / double(c.height);
    double a, b;
    const bool inf = std::isinf(f);
    if (c.clip == sk::ClipDepth::NegativeOneToOne) {
        a = inf ? -1.0 : -(f + n) / (f - n);
        b = inf ? -2.0 * n : -2.0 * f * n / (f - n);
        if (c.reversed) { a = -a; b = -b; }  // ndc -> -ndc: 1 at near
    } else if (!c.reversed) {
        a = inf ? -1.0 : -f / (f - n);
        b = inf ? -n : -f * n / (f - n);
    } else {
        a = inf ? 0.0 : n / (f - n);
        b = inf ? n : f * n / (f - n);
    }
    glm::dmat4 p(0.0);
    p[0][0] = 1.0 / (aspect * t);
    p[1][1] = 1.0 / t;
    p[2][2] = a;
    p[3][2] = b;
    p[2][3] = -1.0;
    return p;
}

struct Box {
    glm::dvec3 lo, hi;
};

// Nearest hit t > 0 of o + t d with the slab box, +inf if none.
double hit_box(const Box& b, glm::dvec3 o, glm::dvec3 d) {
    double t0 = 0.0, t1 = kInf;
    for (int i = 0; i < 3; ++i) {
        if (d[i] == 0.0) {
            if (o[i] < b.lo[i] || o[i] > b.hi[i]) return kInf;
            continue;
        }
        double ta = (b.lo[i] - o[i]) / d[i], tb = (b.hi[i] - o[i]) / d[i];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    return t0 <= t1 ? t0 : kInf;
}

struct Scene {
    bool floor = true;  // y = 0
    Box box{};
    bool has_box = false;
    double floor_y = 0.0;
};

double quantize(sk::DepthFormat f, double w) {
    if (f == sk::DepthFormat::Float32) return double(float(w));
    const double scale = f == sk::DepthFormat::Fixed24 ? 16777215.0 : 65535.0;
    return std::round(std::clamp(w, 0.0, 1.0) * scale) / scale;
}

struct Rendered {
    glm::dmat4 view, proj;
    std::vector<float> depth;
    std::vector<glm::dvec3> world;  // hit point per pixel (NaN: background)
    glm::dvec3 eye;
};

glm::dvec3 pixel_dir(const Cam& c, const Rendered& r, double px, double py) {
    const double ndc_x = px / c.width * 2.0 - 1.0, ndc_y = py / c.height * 2.0 - 1.0;
    const glm::dvec3 dv(ndc_x / r.proj[0][0], ndc_y / r.proj[1][1], -1.0);
    const glm::dmat3 rot_t = glm::transpose(glm::dmat3(r.view));  // view -> world rotation
    return rot_t * dv;
}

double window_of(const Cam& c, const Rendered& r, glm::dvec3 world) {
    const glm::dvec4 clip = r.proj * r.view * glm::dvec4(world, 1.0);
    const double ndc = clip.z / clip.w;
    return c.clip == sk::ClipDepth::ZeroToOne ? ndc : ndc * 0.5 + 0.5;
}

// Scene hit along the camera ray: nearest t (direction not normalized), +inf if none.
double scene_hit(const Scene& s, glm::dvec3 o, glm::dvec3 d) {
    double t = kInf;
    if (s.floor && d.y != 0.0) {
        const double tf = (s.floor_y - o.y) / d.y;
        if (tf > 0.0) t = tf;
    }
    if (s.has_box) t = std::min(t, hit_box(s.box, o, d));
    return t;
}

Rendered render(const Cam& c, const Scene& s) {
    Rendered r;
    r.view = view_of(c);
    r.proj = proj_of(c);
    r.eye = c.eye;
    r.depth.assign(std::size_t(c.width) * std::size_t(c.height), c.reversed ? 0.0f : 1.0f);
    r.world.assign(r.depth.size(), glm::dvec3(std::nan("")));
    for (int y = 0; y < c.height; ++y)
        for (int x = 0; x < c.width; ++x) {
            const glm::dvec3 d = pixel_dir(c, r, x + 0.5, y + 0.5);
            const double t = scene_hit(s, c.eye, d);
            if (!std::isfinite(t)) continue;
            const glm::dvec3 p = c.eye + t * d;
            const double w = window_of(c, r, p);
            if (!(w >= 0.0 && w <= 1.0)) continue;
            const std::size_t k = std::size_t(y) * std::size_t(c.width) + std::size_t(x);
            r.depth[k] = float(quantize(c.format, w));
            r.world[k] = p;
        }
    return r;
}

// The march under test: contact_shadow_march, or the pixel-aligned contact_shadow_march_aligned with
// one sample per pixel and with a sample every few pixels (max_steps 4, jitter 0.5). Every TEST_CASE
// that marches runs all three: they promise the same properties.
using MarchFn = sk::ContactShadowResult (*)(const float*, std::size_t, int, int, const glm::mat4&, glm::vec3, glm::vec4,
                                            const sk::ContactShadowParams&);
struct MarchCase {
    MarchFn fn;
    int max_steps;  // 0: the test's own (params_of: 256)
    float jitter;
    const char* name;
};
const MarchCase kMarches[3] = {
    {sk::contact_shadow_march, 0, 0.0f, "contact_shadow_march"},
    {sk::contact_shadow_march_aligned, 0, 0.0f, "contact_shadow_march_aligned"},
    {sk::contact_shadow_march_aligned, 4, 0.5f, "contact_shadow_march_aligned, max_steps 4, jitter 0.5"}};
MarchFn g_march = sk::contact_shadow_march;
const MarchCase* g_case = &kMarches[0];

sk::ContactShadowParams params_of(const Cam& c, float length) {
    sk::ContactShadowParams p;
    p.length_world = length;
    p.max_steps = 256;
    p.depth_format = c.format;
    p.clip_depth = c.clip;
    p.reversed_z = c.reversed;
    if (g_case->max_steps > 0) p.max_steps = g_case->max_steps;
    p.jitter = g_case->jitter;
    return p;
}

glm::vec3 view_point(const Rendered& r, glm::dvec3 world) { return glm::vec3(r.view * glm::dvec4(world, 1.0)); }
glm::vec4 view_light(const Rendered& r, glm::dvec4 light_world) { return glm::vec4(r.view * light_world); }

sk::ContactShadowResult march(const Cam& c, const Rendered& r, glm::dvec3 world, glm::dvec4 light, const sk::ContactShadowParams& p) {
    return g_march(r.depth.data(), r.depth.size(), c.width, c.height, glm::mat4(r.proj),
                                    view_point(r, world), view_light(r, light), p);
}

glm::dvec4 sun(double elevation_deg, double azimuth_deg) {
    const double e = elevation_deg * kPi / 180.0, a = azimuth_deg * kPi / 180.0;
    return glm::dvec4(std::cos(e) * std::cos(a), std::sin(e), std::cos(e) * std::sin(a), 0.0);
}

// Counts receivers on the floor (a pixel grid) that the march finds occluded.
int floor_hits(const Cam& c, const Rendered& r, glm::dvec4 light, float length, int stride, int* tested) {
    int hits = 0;
    *tested = 0;
    for (int y = stride / 2; y < c.height; y += stride)
        for (int x = stride / 2; x < c.width; x += stride) {
            const glm::dvec3 w = r.world[std::size_t(y) * std::size_t(c.width) + std::size_t(x)];
            if (std::isnan(w.x)) continue;
            const sk::ContactShadowResult m = march(c, r, w, light, params_of(c, length));
            REQUIRE(m.status == sk::Status::Ok);
            ++*tested;
            hits += m.hit;
        }
    return hits;
}

// The geometric reference for a ray from a floor point: march parameter s in [0, L] (world units).
// Occluded: the camera ray to some point of the ray (beyond 3 pixels from the receiver) meets the
// box shrunk by `margin` before the point, by more than `margin` of depth. Lit: no camera ray to
// any point of the ray meets the box grown by `margin`. Else undecided (0).
int reference(const Rendered& r, const Box& box, glm::dvec3 p0, glm::dvec3 dir, double len, double skip, double margin) {
    const Box small{box.lo + margin, box.hi - margin}, big{box.lo - margin, box.hi + margin};
    bool any_near = false, occluded = false;
    for (int i = 0; i <= 2000; ++i) {
        const double s = len * i / 2000.0;
        const glm::dvec3 q = p0 + s * dir;
        const glm::dvec3 d = q - r.eye;  // t = 1 at q
        if (hit_box(big, r.eye, d) < 1.0) any_near = true;
        if (s > skip && small.lo.x < small.hi.x && hit_box(small, r.eye, d) < 1.0 - margin / glm::length(d)) occluded = true;
    }
    if (occluded) return 1;
    if (!any_near) return -1;
    return 0;
}

}  // namespace

TEST_CASE("flat floor: no self-occlusion at any light angle, 1 degree grazing included, every format and depth mode") {
    for (const MarchCase& mc : kMarches) {
        g_march = mc.fn;
        g_case = &mc;
        const std::string march_under_test = mc.name;
        CAPTURE(march_under_test);
        for (int mode = 0; mode < 6; ++mode) {
            Cam c;
            c.clip = mode >= 3 ? sk::ClipDepth::ZeroToOne : sk::ClipDepth::NegativeOneToOne;
            c.reversed = mode == 2 || mode == 5;
            c.far_z = (mode == 1 || mode == 5) ? kInf : 100.0;
            c.format = mode == 5 || mode == 2 ? sk::DepthFormat::Float32 : (mode == 4 ? sk::DepthFormat::Fixed16 : sk::DepthFormat::Fixed24);
            Scene s;
            const Rendered r = render(c, s);
            int total = 0;
            for (double elev : {1.0, 3.0, 10.0, 45.0, 89.0})
                for (double az = 0.0; az < 360.0; az += 45.0) {
                    int tested = 0;
                    const int hits = floor_hits(c, r, sun(elev, az), 0.5f, 9, &tested);
                    CHECK_MESSAGE(hits == 0, "mode " << mode << " elevation " << elev << " azimuth " << az);
                    total += tested;
                }
            // point lights above the floor, one behind the camera (view z > 0), one straight above it
            for (glm::dvec4 L : {glm::dvec4(0.0, 3.0, 4.0, 1.0), glm::dvec4(1.0, 0.05, -3.0, 1.0), glm::dvec4(0.0, 8.0, -6.0, 2.0)}) {
                int tested = 0;
                CHECK(floor_hits(c, r, L, 0.5f, 9, &tested) == 0);
            }
            CHECK(total > 1000);
        }
    }
}

TEST_CASE("light parallel and anti-parallel to the view direction, and behind the camera: Ok, no self-occlusion") {
    for (const MarchCase& mc : kMarches) {
        g_march = mc.fn;
        g_case = &mc;
        const std::string march_under_test = mc.name;
        CAPTURE(march_under_test);
        Cam c;
        Scene s;
        const Rendered r = render(c, s);
        const glm::dvec3 fwd = glm::normalize(c.target - c.eye);
        // toward the camera: the ray is clipped at the near plane; away from it: the ray goes down into the
        // floor's far side only if the light is below the floor, so use the elevated variants
        for (glm::dvec4 L : {glm::dvec4(-fwd, 0.0), glm::dvec4(fwd + glm::dvec3(0, 0.6, 0), 0.0), glm::dvec4(c.eye + 0.5 * glm::dvec3(0, 1, 1), 1.0)}) {
            int tested = 0;
            CHECK(floor_hits(c, r, L, 1.0f, 7, &tested) == 0);
            CHECK(tested > 100);
        }
        // exactly anti-parallel (toward the light = the view direction): the floor faces away from that
        // light and the ray goes under it; every result is Ok and the rays that leave their pixel mostly hit
        {
            int ok = 0, moved = 0, hit = 0;
            for (int y = 5; y < c.height; y += 10)
                for (int x = 5; x < c.width; x += 10) {
                    const glm::dvec3 w = r.world[std::size_t(y) * std::size_t(c.width) + std::size_t(x)];
                    if (std::isnan(w.x)) continue;
                    const sk::ContactShadowResult m = march(c, r, w, glm::dvec4(fwd, 0.0), params_of(c, 1.0f));
                    ok += m.status == sk::Status::Ok;
                    if (m.steps >= 4) {
                        ++moved;
                        hit += m.hit;
                    }
                }
            CHECK(ok > 100);
            CHECK(moved > 20);
            CHECK(hit * 10 >= moved * 9);
        }
        // a light exactly along the view axis from the receiver: the ray projects to (almost) its own pixel
        const glm::dvec3 p = r.world[std::size_t(60) * 160 + 80];
        const glm::dvec3 to_eye = glm::normalize(c.eye - p);
        const sk::ContactShadowResult m = march(c, r, p, glm::dvec4(to_eye, 0.0), params_of(c, 1.0f));
        CHECK(m.status == sk::Status::Ok);
        CHECK(m.visibility == 1.0f);
        CHECK(m.steps <= 2);
    }
}

TEST_CASE("a box on the floor: occluded iff the ray passes under it (geometric reference), at scales 1e-6 .. 1e6") {
    for (const MarchCase& mc : kMarches) {
        g_march = mc.fn;
        g_case = &mc;
        const std::string march_under_test = mc.name;
        CAPTURE(march_under_test);
        for (double scale : {1.0, 1e-6, 1e6}) {
            Cam c;
            c.eye = glm::dvec3(0.0, 4.0, 2.0) * scale;
            c.target = glm::dvec3(0.0, 0.0, -3.0) * scale;
            c.near_z = 0.05 * scale;
            c.far_z = 100.0 * scale;
            c.format = sk::DepthFormat::Float32;
            c.reversed = true;
            c.clip = sk::ClipDepth::ZeroToOne;
            Scene s;
            const Box box{glm::dvec3(-0.5, 0.0, -3.5) * scale, glm::dvec3(0.5, 0.6, -2.5) * scale};
            s.box = box;
            s.has_box = true;
            const Rendered r = render(c, s);
            // a floor point 0.4 in front of the box (+z side); light toward -z, low: the ray enters the box
            const glm::dvec3 p = glm::dvec3(0.0, 0.0, -2.1) * scale;
            const sk::ContactShadowParams prm = params_of(c, float(1.5 * scale));
            auto run = [&](glm::dvec4 L) {
                sk::ContactShadowParams q = prm;
                q.thickness_world = std::numeric_limits<float>::infinity();
                return g_march(r.depth.data(), r.depth.size(), c.width, c.height, glm::mat4(r.proj),
                                                view_point(r, p), view_light(r, L), q);
            };
            const sk::ContactShadowResult under = run(glm::dvec4(0.0, 0.5, -1.0, 0.0));
            REQUIRE(under.status == sk::Status::Ok);
            CHECK(under.hit);
            CHECK(under.visibility == 0.0f);
            // the ray enters the box where it crosses z = -2.5: s = 0.4 * |dir| / |dir.z|
            const double s_enter = 0.4 * std::sqrt(1.25) / 1.0 * scale;
            CHECK(double(under.hit_distance_world) >= s_enter - 0.05 * scale);
            // one sample per pixel: the first sample past the entry; 4 samples: at most one step (a quarter
            // of the 1.5-long march in screen space, up to a third of it on the ray here) past it
            CHECK(double(under.hit_distance_world) <= s_enter + (g_case->max_steps > 0 ? 0.5 : 0.1) * scale);
            // steep light: the ray rises 2 per unit of z, over the box top (0.6) before reaching it: lit
            // (the box top is below the ray at z = -2.5: height 0.8 > 0.6) - but is it hidden from the
            // camera? the camera (y = 4, z = 2) looks over the box, the ray is in front of it: lit
            const sk::ContactShadowResult over = run(glm::dvec4(0.0, 2.0, -1.0, 0.0));
            REQUIRE(over.status == sk::Status::Ok);
            CHECK_FALSE(over.hit);
            // away from the box (light toward +z): lit
            const sk::ContactShadowResult away = run(glm::dvec4(0.0, 0.3, 1.0, 0.0));
            REQUIRE(away.status == sk::Status::Ok);
            CHECK_FALSE(away.hit);
            // a march too short to reach the box: lit
            sk::ContactShadowParams shrt = prm;
            shrt.length_world = float(0.3 * scale);
            shrt.thickness_world = std::numeric_limits<float>::infinity();
            const sk::ContactShadowResult short_ray = g_march(
                r.depth.data(), r.depth.size(), c.width, c.height, glm::mat4(r.proj), view_point(r, p),
                view_light(r, glm::dvec4(0.0, 0.5, -1.0, 0.0)), shrt);
            REQUIRE(short_ray.status == sk::Status::Ok);
            CHECK_FALSE(short_ray.hit);
        }
    }
}

TEST_CASE("random boxes, cameras, lights and formats: the march agrees with the geometric reference where it decides") {
    for (const MarchCase& mc : kMarches) {
        g_march = mc.fn;
        g_case = &mc;
        const std::string march_under_test = mc.name;
        CAPTURE(march_under_test);
        std::mt19937 rng(20261204u);
        std::uniform_real_distribution<double> U(0.0, 1.0);
        int decided = 0, agree = 0, occluded_cases = 0, lit_cases = 0, occluded_agree = 0, lit_agree = 0;
        for (int scene_i = 0; scene_i < 64; ++scene_i) {
            Cam c;
            c.width = 96;
            c.height = 72;
            const double az = U(rng) * 2.0 * kPi;
            c.eye = glm::dvec3(5.0 * std::cos(az), 1.5 + 3.0 * U(rng), 5.0 * std::sin(az));
            c.target = glm::dvec3(U(rng) - 0.5, 0.0, U(rng) - 0.5);
            c.near_z = 0.05;
            c.far_z = scene_i % 3 == 0 ? kInf : 50.0;
            c.clip = scene_i % 2 ? sk::ClipDepth::ZeroToOne : sk::ClipDepth::NegativeOneToOne;
            c.reversed = scene_i % 4 == 1;
            c.format = scene_i % 5 == 2 ? sk::DepthFormat::Float32 : sk::DepthFormat::Fixed24;
            Scene s;
            const glm::dvec3 center(U(rng) - 0.5, 0.0, U(rng) - 0.5);
            const glm::dvec3 half(0.3 + 0.4 * U(rng), 0.3 + 0.6 * U(rng), 0.3 + 0.4 * U(rng));
            const Box box{glm::dvec3(center.x - half.x, 0.0, center.z - half.z), glm::dvec3(center.x + half.x, 2.0 * half.y, center.z + half.z)};
            s.box = box;
            s.has_box = true;
            const Rendered r = render(c, s);
            for (int k = 0; k < 400; ++k) {
                const int x = int(U(rng) * c.width), y = int(U(rng) * c.height);
                const glm::dvec3 p = r.world[std::size_t(y) * std::size_t(c.width) + std::size_t(x)];
                if (std::isnan(p.x) || p.y > 1e-9) continue;  // floor receivers only
                // half the lights aim at the box (low), half anywhere
                const double el = (2.0 + 60.0 * U(rng)) * kPi / 180.0;
                const double a = k % 2 ? std::atan2(center.z - p.z, center.x - p.x) + 0.6 * (U(rng) - 0.5) : U(rng) * 2.0 * kPi;
                const glm::dvec3 dir(std::cos(el) * std::cos(a), std::sin(el), std::cos(el) * std::sin(a));  // (x, y, z): azimuth in x-z
                const double len = 0.5 + 1.5 * U(rng);
                sk::ContactShadowParams prm = params_of(c, float(len));
                prm.thickness_world = std::numeric_limits<float>::infinity();
                const sk::ContactShadowResult m = g_march(r.depth.data(), r.depth.size(), c.width, c.height,
                                                                           glm::mat4(r.proj), view_point(r, p),
                                                                           view_light(r, glm::dvec4(dir, 0.0)), prm);
                REQUIRE(m.status == sk::Status::Ok);
                // the reference: skip the first 3 pixels' worth of ray (world length at that depth), margin
                // a few pixels' footprint
                const double dist = glm::length(p - c.eye);
                const double pixel_world = dist * 2.0 * std::tan(c.fovy / 2.0) / c.height;
                const int ref = reference(r, box, p, dir, len, 3.0 * pixel_world / std::max(0.2, std::sin(el)), 3.0 * pixel_world);
                if (ref == 0) continue;
                ++decided;
                (ref == 1 ? occluded_cases : lit_cases)++;
                agree += (ref == 1) == m.hit;
                (ref == 1 ? occluded_agree : lit_agree) += (ref == 1) == m.hit;
                if ((ref == 1) != m.hit)
                    MESSAGE("disagree: scene " << scene_i << " pixel " << x << "," << y << " ref " << ref << " march hit " << m.hit);
            }
        }
        MESSAGE("decided " << decided << " (occluded " << occluded_cases << ", lit " << lit_cases << "), agree " << agree
                            << " (occluded " << occluded_agree << ", lit " << lit_agree << ")");
        CHECK(occluded_cases > 50);
        CHECK(lit_cases > 200);
        CHECK(lit_agree == lit_cases);  // never a false hit
        if (g_case->max_steps == 0)
            CHECK(occluded_agree == occluded_cases);  // one sample per pixel: every occluder the reference sees
        else  // a sample every few pixels steps over a ray's short passes behind the box (3 of 219 here)
            CHECK(double(occluded_agree) >= 0.95 * double(occluded_cases));
    }
}

TEST_CASE("properties over seeded random configurations: visibility 0/1, thickness monotone, a farther buffer never occludes") {
    for (const MarchCase& mc : kMarches) {
        g_march = mc.fn;
        g_case = &mc;
        const std::string march_under_test = mc.name;
        CAPTURE(march_under_test);
        std::mt19937 rng(7u);
        std::uniform_real_distribution<double> U(0.0, 1.0);
        const int W = 40, H = 30;
        std::vector<float> depth(std::size_t(W) * H), far_depth(std::size_t(W) * H);
        int ok = 0;
        for (int it = 0; it < 4000; ++it) {
            Cam c;
            c.width = W;
            c.height = H;
            c.fovy = 0.3 + 1.5 * U(rng);
            c.near_z = std::pow(10.0, -5.0 + 4.0 * U(rng));
            c.far_z = U(rng) < 0.3 ? kInf : c.near_z * (2.0 + 1e4 * U(rng));
            c.clip = U(rng) < 0.5 ? sk::ClipDepth::ZeroToOne : sk::ClipDepth::NegativeOneToOne;
            c.reversed = U(rng) < 0.4;
            c.format = static_cast<sk::DepthFormat>(int(U(rng) * 3.0));
            const glm::mat4 P(proj_of(c));
            // random window depths (a rough surface)
            for (float& d : depth) d = float(quantize(c.format, U(rng)));
            // a receiver inside the frustum
            const double dist = c.near_z + (std::min(c.far_z, c.near_z * 1e3) - c.near_z) * (0.01 + 0.98 * U(rng));
            const double t = std::tan(c.fovy / 2.0);
            const glm::vec3 vp(float((2.0 * U(rng) - 1.0) * t * dist * W / H * 0.95), float((2.0 * U(rng) - 1.0) * t * dist * 0.95), float(-dist));
            glm::vec4 L(float(U(rng) - 0.5), float(U(rng) - 0.5), float(U(rng) - 0.5), U(rng) < 0.5 ? 0.0f : float(U(rng)));
            sk::ContactShadowParams p;
            p.length_world = float(dist * (0.01 + U(rng)));
            p.max_steps = 1 + int(U(rng) * 64);
            p.jitter = float(U(rng) * 0.99);
            p.depth_format = c.format;
            p.clip_depth = c.clip;
            p.reversed_z = c.reversed;
            p.thickness_world = float(dist * 0.1 * U(rng));
            const sk::ContactShadowResult a = g_march(depth.data(), depth.size(), W, H, P, vp, L, p);
            if (a.status != sk::Status::Ok) {
                CHECK(a.visibility == 1.0f);
                continue;
            }
            ++ok;
            CHECK((a.visibility == 0.0f || a.visibility == 1.0f));
            CHECK(a.hit == (a.visibility == 0.0f));
            CHECK(a.steps >= 0);
            CHECK(a.steps <= p.max_steps);
            const sk::ContactShadowDerived dv = sk::contact_shadow_derive(W, H, P, vp, L, p);
            REQUIRE(dv.status == sk::Status::Ok);
            if (g_march == sk::contact_shadow_march) CHECK(dv.steps == a.steps);  // derive describes this march's samples
            CHECK(std::isfinite(dv.bias_world));
            CHECK(dv.bias_world >= 0.0f);
            CHECK(a.hit_distance_world <= dv.march_length_world * 1.0001f);
            CHECK(dv.march_length_world <= p.length_world * 1.0001f);
            // thicker occluders occlude at least as much (the samples do not depend on the thickness)
            sk::ContactShadowParams thick = p;
            thick.thickness_world = std::numeric_limits<float>::infinity();
            const sk::ContactShadowResult b = g_march(depth.data(), depth.size(), W, H, P, vp, L, thick);
            REQUIRE(b.status == sk::Status::Ok);
            CHECK(b.visibility <= a.visibility);
            // a buffer farther than every point of the ray everywhere: never occluded
            const double far_d = (dist + double(p.length_world)) * 1.01;
            const glm::dvec4 fc = proj_of(c) * glm::dvec4(0.0, 0.0, -far_d, 1.0);
            double fw = c.clip == sk::ClipDepth::ZeroToOne ? fc.z / fc.w : fc.z / fc.w * 0.5 + 0.5;
            fw = std::clamp(fw, 0.0, 1.0);
            float fq = float(quantize(c.format, fw));
            if (c.reversed ? double(fq) > fw : double(fq) < fw)  // round toward far
                fq = c.format == sk::DepthFormat::Float32 ? std::nextafter(fq, c.reversed ? 0.0f : 1.0f)
                                                          : float(quantize(c.format, fw + (c.reversed ? -1.0 : 1.0) / (c.format == sk::DepthFormat::Fixed24 ? 16777215.0 : 65535.0)));
            std::fill(far_depth.begin(), far_depth.end(), fq);
            const sk::ContactShadowResult f = g_march(far_depth.data(), far_depth.size(), W, H, P, vp, L, thick);
            REQUIRE(f.status == sk::Status::Ok);
            CHECK_FALSE(f.hit);
        }
        CHECK(ok > 2000);
    }
}

TEST_CASE("a buffer whose surface is everywhere behind the ray never occludes (plane behind the receiver)") {
    for (const MarchCase& mc : kMarches) {
        g_march = mc.fn;
        g_case = &mc;
        const std::string march_under_test = mc.name;
        CAPTURE(march_under_test);
        Cam c;
        Scene s;
        s.floor_y = -0.5;  // the buffer shows a floor 0.5 below the receivers
        const Rendered r = render(c, s);
        Scene s0;
        const Rendered r0 = render(c, s0);  // receivers on y = 0 (their pixels)
        int tested = 0;
        for (int y = 3; y < c.height; y += 11)
            for (int x = 3; x < c.width; x += 11) {
                const glm::dvec3 w = r0.world[std::size_t(y) * std::size_t(c.width) + std::size_t(x)];
                if (std::isnan(w.x)) continue;
                for (double elev : {-30.0, 1.0, 20.0, 70.0}) {  // even a light below: the ray ends at y >= -0.5 * ... (length 0.4)
                    sk::ContactShadowParams p = params_of(c, 0.4f);
                    p.thickness_world = std::numeric_limits<float>::infinity();
                    const sk::ContactShadowResult m = g_march(r.depth.data(), r.depth.size(), c.width, c.height,
                                                                               glm::mat4(r.proj), view_point(r, w),
                                                                               view_light(r, sun(elev, 30.0 * x)), p);
                    REQUIRE(m.status == sk::Status::Ok);
                    CHECK_FALSE(m.hit);
                    ++tested;
                }
            }
        CHECK(tested > 100);
    }
}

TEST_CASE("derive: bias from the depth format's precision (d^2 / n), steps from projected pixels, start one pixel") {
    Cam c;
    c.far_z = kInf;
    const glm::mat4 P(proj_of(c));
    sk::ContactShadowParams p;
    p.length_world = 0.5f;
    p.max_steps = 64;
    const glm::vec4 sideways(1.0f, 0.0f, 0.0f, 0.0f);  // toward +x in view space, at constant depth
    for (double d : {1.0, 4.0, 16.0}) {
        const glm::vec3 vp(0.0f, 0.0f, float(-d));
        for (sk::DepthFormat f : {sk::DepthFormat::Fixed24, sk::DepthFormat::Fixed16}) {
            p.depth_format = f;
            const sk::ContactShadowDerived dv = sk::contact_shadow_derive(c.width, c.height, P, vp, sideways, p);
            REQUIRE(dv.status == sk::Status::Ok);
            // GL infinite perspective: window = 1/2 - n/d + 1/2 ... dw/dd = n / d^2: one step is step * d^2 / n
            const double step = f == sk::DepthFormat::Fixed24 ? 1.0 / 16777215.0 : 1.0 / 65535.0;
            const double win = 1.0 - c.near_z / d;
            const double expect = 4.0 * (step + std::ldexp(1.0, -22) * win) * d * d / c.near_z;
            CHECK(dv.bias_world == doctest::Approx(expect).epsilon(1e-4));
            CHECK(dv.depth_step_window == doctest::Approx(step).epsilon(1e-6));
            // the ray: 0.5 sideways at depth d spans 0.5 / (2 d tan(fovy/2)) * height pixels
            const double pixels = 0.5 / (2.0 * d * std::tan(c.fovy / 2.0)) * c.height;
            CHECK(dv.projected_pixels == doctest::Approx(pixels).epsilon(1e-4));
            CHECK(dv.steps == std::min(64, int(std::ceil(pixels - 1e-4))));
            CHECK(dv.start_offset_pixels == 1.0f);
            CHECK(dv.march_length_world == doctest::Approx(0.5));
            CHECK(dv.thickness_world == 0.5f);  // derived: the march length
        }
    }
    // a point light closer than the march length cuts it
    const sk::ContactShadowDerived cut = sk::contact_shadow_derive(c.width, c.height, P, glm::vec3(0, 0, -4), glm::vec4(0.2f, 0, -4, 1), p);
    REQUIRE(cut.status == sk::Status::Ok);
    CHECK(cut.march_length_world == doctest::Approx(0.2));
    // a light behind the camera: the ray toward it is clipped at the near plane (z = -0.1)
    p.length_world = 100.0f;
    const sk::ContactShadowDerived back = sk::contact_shadow_derive(c.width, c.height, P, glm::vec3(0, 0, -4), glm::vec4(0, 0, 1, 0), p);
    REQUIRE(back.status == sk::Status::Ok);
    CHECK(back.march_length_world == doctest::Approx(3.9).epsilon(1e-4));
    CHECK(back.steps == 0);  // straight toward the camera: it stays in its own pixel
    // near 1e-5 with a 16-bit buffer: the bias is larger than the scene (contact shadows vanish, honestly)
    Cam tiny = c;
    tiny.near_z = 1e-5;
    p.length_world = 0.5f;
    p.depth_format = sk::DepthFormat::Fixed16;
    const sk::ContactShadowDerived t16 = sk::contact_shadow_derive(c.width, c.height, glm::mat4(proj_of(tiny)), glm::vec3(0, 0, -10), sideways, p);
    REQUIRE(t16.status == sk::Status::Ok);
    CHECK(t16.bias_world > 100.0f);
}

TEST_CASE("every bad input gives its status and visibility 1") {
    for (const MarchCase& mc : kMarches) {
        g_march = mc.fn;
        g_case = &mc;
        const std::string march_under_test = mc.name;
        CAPTURE(march_under_test);
        Cam c;
        const glm::mat4 P(proj_of(c));
        std::vector<float> depth(std::size_t(c.width) * c.height, 1.0f);
        const glm::vec3 vp(0.0f, 0.0f, -3.0f);
        const glm::vec4 L(0.0f, 1.0f, 0.0f, 0.0f);
        sk::ContactShadowParams p;
        p.length_world = 0.5f;
        auto st = [&](const float* d, std::size_t cap, int w, int h, const glm::mat4& pr, glm::vec3 v, glm::vec4 l,
                      const sk::ContactShadowParams& q) {
            const sk::ContactShadowResult r = g_march(d, cap, w, h, pr, v, l, q);
            CHECK(r.visibility == 1.0f);
            CHECK_FALSE(r.hit);
            return r.status;
        };
        const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
        CHECK(st(depth.data(), depth.size(), c.width, c.height, P, vp, L, p) == sk::Status::Ok);
        CHECK(sk::ContactShadowResult{}.status == sk::Status::NotRun);
        CHECK(st(nullptr, depth.size(), c.width, c.height, P, vp, L, p) == sk::Status::InvalidArgument);
        const sk::ContactShadowResult small = g_march(depth.data(), depth.size() - 1, c.width, c.height, P, vp, L, p);
        CHECK(small.status == sk::Status::BufferTooSmall);
        CHECK(small.needed == depth.size());
        CHECK(st(depth.data(), depth.size(), 0, c.height, P, vp, L, p) == sk::Status::InvalidArgument);
        CHECK(st(depth.data(), depth.size(), c.width, -1, P, vp, L, p) == sk::Status::InvalidArgument);
        sk::ContactShadowParams q = p;
        q.length_world = 0.0f;  // the required sentinel
        CHECK(st(depth.data(), depth.size(), c.width, c.height, P, vp, L, q) == sk::Status::InvalidArgument);
        q.length_world = -1.0f;
        CHECK(st(depth.data(), depth.size(), c.width, c.height, P, vp, L, q) == sk::Status::InvalidArgument);
        q.length_world = nan;
        CHECK(st(depth.data(), depth.size(), c.width, c.height, P, vp, L, q) == sk::Status::NonFinite);
        q.length_world = inf;
        CHECK(st(depth.data(), depth.size(), c.width, c.height, P, vp, L, q) == sk::Status::NonFinite);
        q = p;
        q.max_steps = 0;
        CHECK(st(depth.data(), depth.size(), c.width, c.height, P, vp, L, q) == sk::Status::InvalidArgument);
        q.max_steps = 257;
        CHECK(st(depth.data(), depth.size(), c.width, c.height, P, vp, L, q) == sk::Status::InvalidArgument);
        q = p;
        q.thickness_world = -0.1f;
        CHECK(st(depth.data(), depth.size(), c.width, c.height, P, vp, L, q) == sk::Status::InvalidArgument);
        q.thickness_world = nan;
        CHECK(st(depth.data(), depth.size(), c.width, c.height, P, vp, L, q) == sk::Status::NonFinite);
        q.thickness_world = inf;  // allowed: solid
        CHECK(st(depth.data(), depth.size(), c.width, c.height, P, vp, L, q) == sk::Status::Ok);
        q = p;
        q.jitter = 1.0f;
        CHECK(st(depth.data(), depth.size(), c.width, c.height, P, vp, L, q) == sk::Status::InvalidArgument);
        q.jitter = nan;
        CHECK(st(depth.data(), depth.size(), c.width, c.height, P, vp, L, q) == sk::Status::NonFinite);
        q = p;
        q.depth_format = static_cast<sk::DepthFormat>(7);
        CHECK(st(depth.data(), depth.size(), c.width, c.height, P, vp, L, q) == sk::Status::InvalidArgument);
        q = p;
        q.clip_depth = static_cast<sk::ClipDepth>(5);
        CHECK(st(depth.data(), depth.size(), c.width, c.height, P, vp, L, q) == sk::Status::InvalidArgument);
        // projections: NaN, depth depending on x, depth not varying
        glm::mat4 bad = P;
        bad[1][1] = nan;
        CHECK(st(depth.data(), depth.size(), c.width, c.height, bad, vp, L, p) == sk::Status::NonFinite);
        bad = P;
        bad[0][2] = 0.1f;
        CHECK(st(depth.data(), depth.size(), c.width, c.height, bad, vp, L, p) == sk::Status::InvalidArgument);
        bad = P;
        bad[2][2] = 0.0f;
        bad[3][2] = 0.0f;
        CHECK(st(depth.data(), depth.size(), c.width, c.height, bad, vp, L, p) == sk::Status::InvalidArgument);
        CHECK(st(depth.data(), depth.size(), c.width, c.height, glm::mat4(0.0f), vp, L, p) == sk::Status::InvalidArgument);
        // receivers: NaN, behind the camera, in front of the near plane, off screen
        CHECK(st(depth.data(), depth.size(), c.width, c.height, P, glm::vec3(nan, 0, -1), L, p) == sk::Status::NonFinite);
        CHECK(st(depth.data(), depth.size(), c.width, c.height, P, glm::vec3(0, 0, 1), L, p) == sk::Status::InvalidArgument);
        CHECK(st(depth.data(), depth.size(), c.width, c.height, P, glm::vec3(0, 0, -0.05f), L, p) == sk::Status::InvalidArgument);
        CHECK(st(depth.data(), depth.size(), c.width, c.height, P, glm::vec3(100, 0, -1), L, p) == sk::Status::InvalidArgument);
        // lights
        for (glm::vec4 l : {glm::vec4(0.0f), glm::vec4(0, 1, 0, -1), glm::vec4(nan, 1, 0, 0), glm::vec4(0, inf, 0, 1), glm::vec4(0, 0, -3, 1)})
            CHECK(st(depth.data(), depth.size(), c.width, c.height, P, vp, l, p) == sk::Status::InvalidLight);
        // finite input beyond float: a light at 3e38 / 1e-30
        CHECK(st(depth.data(), depth.size(), c.width, c.height, P, vp, glm::vec4(3e38f, 0, 0, 1e-30f), p) == sk::Status::Overflow);
        CHECK(st(depth.data(), depth.size(), c.width, c.height, P, vp, L, [&] { auto x = p; x.length_world = 3e38f; return x; }()) ==
              sk::Status::Overflow);
        // derive rejects the same
        CHECK(sk::contact_shadow_derive(c.width, c.height, P, vp, L, sk::ContactShadowParams{}).status == sk::Status::InvalidArgument);
        CHECK(sk::contact_shadow_derive(c.width, c.height, P, vp, glm::vec4(0.0f), p).status == sk::Status::InvalidLight);
        CHECK(std::string(sk::status_name(sk::Status::BufferTooSmall)) == "BufferTooSmall");
    }
}
