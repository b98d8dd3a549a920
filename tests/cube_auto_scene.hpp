// The closed-form scene of the automatic bias on a point light's cube of hardware depth, shared by the
// GL test (tests/gl/test_gl_cube_conventions.cpp) and the Vulkan runs of the GLSL and HLSL twins
// (tests/vulkan/test_vk_cube_auto_bias.cpp): a 16-unit room (walls at +-8) with a sphere, a light off
// its center, the cube written texel by texel from the exact ray distance (each texel the face's
// window depth of the nearest surface along its center direction, GL 4.6 table 8.19 / Vulkan's cube
// addressing), and receivers on the walls and the sphere classified by the exact ray test, flagged
// `use` away from the sphere's silhouette and terminator and the room's edges. CPU only (GLM + std).
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <random>
#include <vector>

namespace cube_auto {

constexpr double kRoom = 8.0;               // walls at +-8
constexpr double kNear = 0.1, kFar = 20.0;  // the perspective faces' planes
const glm::dvec3 kSphereCenter(3.0, 1.0, 2.0);
constexpr double kSphereRadius = 1.5;
const glm::dvec3 kLight(0.5, 5.9, 0.0);  // off center, 2.1 below the ceiling: the ceiling grazing far out, seams across every wall

// The direction through texel (i, j) of cube face f (GL 4.6 table 8.19 inverted: s = (sc / |ma| + 1) / 2,
// t = (tc / |ma| + 1) / 2; row j holds t in [j / n, (j + 1) / n)).
inline glm::dvec3 face_direction(int f, int i, int j, int n) {
    const double u = 2.0 * (i + 0.5) / n - 1.0, v = 2.0 * (j + 0.5) / n - 1.0;
    switch (f) {
    case 0: return glm::normalize(glm::dvec3(1, -v, -u));
    case 1: return glm::normalize(glm::dvec3(-1, -v, u));
    case 2: return glm::normalize(glm::dvec3(u, 1, v));
    case 3: return glm::normalize(glm::dvec3(u, -1, -v));
    case 4: return glm::normalize(glm::dvec3(u, -v, 1));
    default: return glm::normalize(glm::dvec3(-u, -v, -1));
    }
}

// Distance from kLight along unit direction d to the nearest surface (walls at +-kRoom, the sphere).
inline double hit_from_light(const glm::dvec3& d, bool* on_sphere = nullptr) {
    double wall = 1e300;
    for (int a = 0; a < 3; ++a)
        if (d[a] != 0.0) wall = std::min(wall, ((d[a] > 0.0 ? kRoom : -kRoom) - kLight[a]) / d[a]);
    const glm::dvec3 oc = kSphereCenter - kLight;
    const double b = glm::dot(d, oc), c = glm::dot(oc, oc) - kSphereRadius * kSphereRadius;
    const double disc = b * b - c;
    if (on_sphere) *on_sphere = false;
    if (disc >= 0.0) {
        const double t = b - std::sqrt(disc);
        if (t > 0.0 && t < wall) {
            if (on_sphere) *on_sphere = true;
            return t;
        }
    }
    return wall;
}

// The six faces (+X, -X, +Y, -Y, +Z, -Z), n x n each, row j = t: the window depth of the major-axis distance.
inline std::vector<float> cube_faces(int n) {
    std::vector<float> data(static_cast<std::size_t>(6 * n * n));
    for (int f = 0; f < 6; ++f)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const glm::dvec3 d = face_direction(f, i, j, n);
                const double major = hit_from_light(d) * std::max({std::fabs(d.x), std::fabs(d.y), std::fabs(d.z)});
                const double ndc = (kFar + kNear) / (kFar - kNear) - 2.0 * kFar * kNear / ((kFar - kNear) * major);
                data[static_cast<std::size_t>((f * n + j) * n + i)] = float(ndc * 0.5 + 0.5);
            }
    return data;
}

struct Receivers {
    std::vector<float> pts, nrm;  // xyzw per receiver (w = 0)
    std::vector<int> truth, kind;  // truth 1 = lit; kind 0 wall, 1 sphere
    std::vector<bool> use;         // scored (away from edges)
    int used = 0, lit = 0, seam = 0;
};

// M receivers: a third along face seams, a third towards the sphere, a third anywhere (seed 2323).
inline Receivers make_receivers(int M, int n) {
    Receivers r;
    const double texel_angle = 2.0 / n;
    std::mt19937 rng(2323);
    std::normal_distribution<double> g(0.0, 1.0);
    r.pts.assign(static_cast<std::size_t>(4 * M), 0.f);
    r.nrm.assign(static_cast<std::size_t>(4 * M), 0.f);
    r.truth.assign(static_cast<std::size_t>(M), 0);
    r.kind.assign(static_cast<std::size_t>(M), 0);
    r.use.assign(static_cast<std::size_t>(M), false);
    for (int i = 0; i < M; ++i) {
        const std::size_t ui = static_cast<std::size_t>(i);
        glm::dvec3 d;
        if (i % 3 == 1) {  // along a face seam: two equal major components (within 2 texels), the third anywhere
            const int a = static_cast<int>(rng() % 3), b = (a + 1 + static_cast<int>(rng() % 2)) % 3;
            std::uniform_real_distribution<double> u(-1.0, 1.0);
            d = glm::dvec3(0.0);
            d[a] = rng() % 2 ? 1.0 : -1.0;
            d[b] = (rng() % 2 ? 1.0 : -1.0) * (1.0 + 2.0 * texel_angle * u(rng));
            d[3 - a - b] = 0.98 * u(rng);
        } else {
            do d = glm::dvec3(g(rng), g(rng), g(rng)) + (i % 3 == 0 ? glm::normalize(kSphereCenter - kLight) * 3.0 : glm::dvec3(0.0));
            while (glm::length(d) < 1e-3);
        }
        d = glm::normalize(d);
        bool sphere = false;
        const double t = hit_from_light(d, &sphere);
        glm::dvec3 p = kLight + t * d, nn;
        if (sphere) {
            nn = glm::normalize(p - kSphereCenter);
            if (i % 2) {  // half of them on the sphere's far side (shadowed by itself): reflect through the center
                p = 2.0 * kSphereCenter - p;
                nn = -nn;
            }
        } else {
            int a = 0;
            for (int k = 1; k < 3; ++k)
                if (std::fabs(std::fabs(p[k]) - kRoom) < std::fabs(std::fabs(p[a]) - kRoom)) a = k;
            nn = glm::dvec3(0.0);
            nn[a] = p[a] > 0.0 ? -1.0 : 1.0;
        }
        const glm::dvec3 to = p - kLight;
        const double dist = glm::length(to);
        const glm::dvec3 dd = to / dist;
        const double cosi = -glm::dot(nn, dd);  // > 0: faces the light
        const double first = hit_from_light(dd);
        r.truth[ui] = cosi > 0.0 && first >= dist - 1e-6 * dist ? 1 : 0;
        r.kind[ui] = sphere ? 1 : 0;
        // away from edges: the sphere's silhouette seen from the light (3 texels' angle), the terminator
        // (cos > 0.05), the room's edges (3 texels of the wall's footprint: 3 texel_angle dist / cos)
        const glm::dvec3 oc = kSphereCenter - kLight;
        const double silhouette = std::asin(kSphereRadius / glm::length(oc));
        const double ang = std::acos(std::clamp(glm::dot(dd, glm::normalize(oc)), -1.0, 1.0));
        bool ok = std::fabs(ang - silhouette) > 3.0 * texel_angle && std::fabs(cosi) > 0.05;
        if (!sphere) {
            const double reach = 3.0 * texel_angle * dist / std::max(cosi, 1e-3);
            int near_edges = 0;
            for (int k = 0; k < 3; ++k) near_edges += std::fabs(std::fabs(p[k]) - kRoom) < reach;
            ok = ok && near_edges <= 1;
        }
        r.use[ui] = ok;
        const glm::dvec3 ad = glm::abs(dd);
        const double m1 = std::max({ad.x, ad.y, ad.z}), m3 = std::min({ad.x, ad.y, ad.z}), m2 = ad.x + ad.y + ad.z - m1 - m3;
        if (ok && (m1 - m2) / m1 < 2.0 * texel_angle) ++r.seam;  // within two texels of a face seam
        if (ok) {
            ++r.used;
            r.lit += r.truth[ui];
        }
        for (int k = 0; k < 3; ++k) r.pts[4 * ui + static_cast<std::size_t>(k)] = float(p[k]), r.nrm[4 * ui + static_cast<std::size_t>(k)] = float(nn[k]);
    }
    return r;
}

}  // namespace cube_auto
