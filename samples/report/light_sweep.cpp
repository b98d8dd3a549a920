// shadowkit-report's light sweep (light_sweep.hpp; the definitions: docs/report.md, "Light sweep").
#include "light_sweep.hpp"

#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ostream>
#include <thread>

#include "cached_shadow_map.hpp"
#include "cascaded_shadow_maps.hpp"
#include "pcss.hpp"
#include "reference.hpp"
#include "report_writer.hpp"
#include "shadow_map.hpp"
#include "warped_shadow_maps.hpp"

namespace skr {

namespace {

constexpr float kPi = 3.14159265358979f;

// The techniques the sweep covers, at their class defaults (pcf: the hard 2x2 lookup), and their map
// size (per cascade for cascades). Each runs where its report rows run (warped_sm: outdoor, duel and the
// scanned meshes; cascades: suns; cached_shadow_map: every light but a point light).
struct SweepTechnique {
    const char* name;
    const char* settings;
    int map_size;
};
const SweepTechnique kSweepTechniques[] = {
    {"shadow_map", "", ShadowMapSettings{}.size},
    {"pcf", "filter=hard", PcssSettings{}.size},
    {"cached_shadow_map", "", CachedShadowMapSettings{}.size},
    {"warped_sm", "", WarpedShadowMapSettings{}.size},
    {"cascades", "", CascadedShadowMapSettings{}.size},
};

// Distance to the first caster along dir (unit) within tfar; INFINITY when none.
float first_hit(RTCScene scene, glm::vec3 org, glm::vec3 dir, float tfar) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh{};
    rh.ray.org_x = org.x;
    rh.ray.org_y = org.y;
    rh.ray.org_z = org.z;
    rh.ray.dir_x = dir.x;
    rh.ray.dir_y = dir.y;
    rh.ray.dir_z = dir.z;
    rh.ray.tnear = 0.f;
    rh.ray.tfar = tfar;
    rh.ray.mask = 0xffffffffu;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene, &ctx, &rh);
    return rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? INFINITY : rh.ray.tfar;
}

// How a scene's light is replaced: a directional light (scenes lit by a sun) or a spot light (every other
// scene: spot, point and area lights; one 2D map, which both shadow_map and pcf accept, where a point
// light would give shadow_map a cube map of six) at the original light's distance from the aim point
// (the camera target dropped onto the floor, y = the scene's lowest point), aimed at it.
struct SweepLights {
    sk::LightType type = sk::LightType::Spot;
    glm::vec3 aim{0.f};
    float distance = 1.f;
    std::vector<sk::Light> lights;
    std::vector<glm::vec3> towards;  // unit direction from the aim point towards each light
    int grazing = 0;
};

const char* type_name(sk::LightType t) { return t == sk::LightType::Directional ? "directional" : "spot"; }

std::uint64_t name_hash(const std::string& s) {
    std::uint64_t h = 1469598103934665603ull;
    for (char c : s) {
        h ^= static_cast<unsigned char>(c);
        h *= 1099511628211ull;
    }
    return h;
}

// Light i is grazing when i % 3 == 0 (elevation uniform in [1, 5] degrees at the aim point); the others
// are uniform in solid angle over the cap above 1 degree; azimuth uniform. Spot lights inside a caster's
// bounding box (one that does not hold the scene's own light: the room) are drawn again.
SweepLights make_lights(const sk::Scene& s, const sk::GBuffer& g, const LightSweepOptions& opt) {
    const int count = sk::is_scanned_scene(s.name) ? opt.mesh_lights : opt.lights;
    SweepLights out;
    const sk::Light& L0 = s.light;
    out.type = L0.type == sk::LightType::Directional ? sk::LightType::Directional : sk::LightType::Spot;
    const glm::vec3 lo = s.bounds_min(), hi = s.bounds_max();
    const float diag = glm::length(hi - lo);
    out.aim = glm::vec3(s.camera.target.x, lo.y, s.camera.target.z);
    out.distance = out.type == sk::LightType::Directional ? 2.f * diag : glm::length(L0.position - out.aim);
    struct Box {
        glm::vec3 lo, hi;
    };
    std::vector<Box> boxes;
    const float pad = 1e-3f * diag;
    for (const auto& m : s.meshes) {
        if (!m.caster || m.positions.empty()) continue;
        Box b{glm::vec3(INFINITY), glm::vec3(-INFINITY)};
        for (const auto& p : m.positions) {
            b.lo = glm::min(b.lo, p);
            b.hi = glm::max(b.hi, p);
        }
        b.lo -= pad;
        b.hi += pad;
        const bool holds_light = glm::all(glm::greaterThanEqual(L0.position, b.lo)) && glm::all(glm::lessThanEqual(L0.position, b.hi));
        if (!holds_light || out.type == sk::LightType::Directional) boxes.push_back(b);
    }
    auto inside = [&](glm::vec3 q) {
        for (const Box& b : boxes)
            if (glm::all(glm::greaterThanEqual(q, b.lo)) && glm::all(glm::lessThanEqual(q, b.hi))) return true;
        return false;
    };
    sk::Pcg rng(opt.seed ^ name_hash(s.name));
    const float s1 = std::sin(kPi / 180.f);
    for (int i = 0; i < count; ++i) {
        const bool grazing = i % 3 == 0;
        glm::vec3 w(0.f, 1.f, 0.f);
        for (int attempt = 0; attempt < 64; ++attempt) {
            const float e = grazing ? (1.f + 4.f * rng.uniform()) * kPi / 180.f : std::asin(s1 + (1.f - s1) * rng.uniform());
            const float phi = 2.f * kPi * rng.uniform();
            w = glm::vec3(std::cos(e) * std::cos(phi), std::sin(e), std::cos(e) * std::sin(phi));
            if (out.type == sk::LightType::Directional || !inside(out.aim + out.distance * w)) break;
        }
        sk::Light L;
        L.type = out.type;
        L.size = 0.f;
        L.position = out.aim + out.distance * w;
        L.direction = -w;
        if (out.type == sk::LightType::Spot) {
            // the cone: every visible point of the camera G-buffer plus 0.02 rad, at most 1.3 rad (75 degrees)
            float cmin = 1.f;
            for (std::size_t k = 0; k < g.kind.size(); ++k)
                if (g.kind[k] != 0) {
                    const glm::vec3 p(g.position[3 * k], g.position[3 * k + 1], g.position[3 * k + 2]);
                    cmin = std::min(cmin, glm::dot(glm::normalize(p - L.position), -w));
                }
            L.spot_half_angle = std::clamp(std::acos(std::clamp(cmin, -1.f, 1.f)) + 0.02f, 0.1f, 1.3f);
        }
        out.lights.push_back(L);
        out.towards.push_back(w);
        out.grazing += grazing ? 1 : 0;
    }
    return out;
}

// The hard reference of one light at the G-buffer's points. cls: 0 not scored (background, not a
// receiver, facing away from the light, outside a spot light's cone), 1 lit, 2 shadowed; for shadowed
// pixels t = the distance to the occluder along the shadow ray and cos_n = n . (direction to the light).
struct LightRef {
    std::vector<std::uint8_t> cls;
    std::vector<float> t, cos_n, texel;  // texel: the map's texel world size at the point (per map size 1)
};

void hard_reference(const sk::Scene& s, const sk::GBuffer& g, const sk::EmbreeScene& e, const sk::Light& L, LightRef& r) {
    const std::size_t n = g.kind.size();
    r.cls.assign(n, 0);
    r.t.assign(n, 0.f);
    r.cos_n.assign(n, 0.f);
    r.texel.assign(n, 0.f);
    const float diag = glm::length(s.bounds_max() - s.bounds_min());
    const float eps = sk::ReferenceOptions{}.offset_fraction * diag;  // the reference's ray offset
    sk::Scene lit = s;
    lit.light = L;
    const sk::LightMatrices lm = sk::fit_light(lit);
    const float cos_cone = std::cos(L.spot_half_angle);
    const glm::vec3 ldir = glm::normalize(L.direction);
    for (std::size_t k = 0; k < n; ++k) {
        if (g.kind[k] != 1) continue;
        const glm::vec3 p(g.position[3 * k], g.position[3 * k + 1], g.position[3 * k + 2]);
        const glm::vec3 nn(g.normal[3 * k], g.normal[3 * k + 1], g.normal[3 * k + 2]);
        glm::vec3 d;
        float tfar = INFINITY;
        if (L.type == sk::LightType::Directional) {
            d = -ldir;
        } else {
            const glm::vec3 q = L.position - p;
            tfar = glm::length(q);
            d = q / tfar;
            if (L.type == sk::LightType::Spot && glm::dot(-d, ldir) < cos_cone) continue;
        }
        const float c = glm::dot(nn, d);
        if (!(c > 0.f)) continue;
        const glm::vec3 org = p + eps * nn;
        if (L.type != sk::LightType::Directional) tfar = glm::length(L.position - org) * (1.f - 1e-5f);
        const float t = first_hit(e.scene, org, glm::normalize(L.type == sk::LightType::Directional ? d : L.position - org), tfar);
        r.cls[k] = std::isfinite(t) ? 2 : 1;
        r.t[k] = std::isfinite(t) ? t : 0.f;
        r.cos_n[k] = c;
        // the map's texel at p, for a map of size 1: the frustum's width at p's depth
        if (lm.perspective) {
            r.texel[k] = 2.f * -(lm.view * glm::vec4(p, 1.f)).z / lm.proj[1][1];
        } else {
            r.texel[k] = std::max(2.f / lm.proj[0][0], 2.f / lm.proj[1][1]);
        }
    }
}

struct LightScore {
    double acne = 0.0, acne_texel = 0.0, leak = 0.0, leak_texel = 0.0, gap_texels = 0.0, gap_world = 0.0;
};

// Whether the reference gives every point of p's neighbourhood in the map that the 2x2 filter reaches the
// class `shadowed`: a 7x7 grid, half a texel apart, over +-1.5 texels of the map on p's tangent plane (as
// the light sees it: b1 across the light, b2 along its projection on the plane, stretched by 1 / cos),
// each shadow ray from eps off the plane; `across_only`: the seven points on the b1 line (a shadow's side
// edge, not the contact it starts at).
bool uniform_within_filter_reach(const sk::EmbreeScene& e, const sk::Light& L, glm::vec3 p, glm::vec3 n, float texel, float eps,
                                 bool shadowed, bool across_only) {
    const bool sun = L.type == sk::LightType::Directional;
    const glm::vec3 d = sun ? -glm::normalize(L.direction) : glm::normalize(L.position - p);
    const float c = glm::dot(n, d);
    if (!(c > 0.f)) return false;
    glm::vec3 b1 = glm::cross(n, d);
    if (glm::length(b1) < 1e-6f) b1 = glm::cross(n, std::abs(n.x) < 0.9f ? glm::vec3(1.f, 0.f, 0.f) : glm::vec3(0.f, 1.f, 0.f));
    b1 = glm::normalize(b1);
    const glm::vec3 b2 = glm::cross(b1, n);
    for (int i = across_only ? 21 : 0; i < (across_only ? 28 : 49); ++i) {
        if (i == 24) continue;  // p itself
        const float u = 0.5f * float(i % 7 - 3), w = 0.5f * float(i / 7 - 3);
        const glm::vec3 q = p + texel * (u * b1 + w / c * b2) + eps * n;
        const glm::vec3 to = sun ? d : L.position - q;
        const float dist = sun ? INFINITY : glm::length(to) * (1.f - 1e-5f);
        if (std::isfinite(first_hit(e.scene, q, glm::normalize(to), dist)) != shadowed) return false;
    }
    return true;
}

// The contact gap's rule: over the umbra pixels sorted by their distance to the occluder in texels, the
// largest distance of a pixel lit by the technique up to which the pixels are mostly (more than half, at
// least two) lit by it; the gap in world units is that pixel's distance along its shadow ray.
struct GapPixel {
    float texels, world;
    bool lit;
};
void contact_gap(std::vector<GapPixel>& px, double& texels, double& world) {
    std::sort(px.begin(), px.end(), [](const GapPixel& a, const GapPixel& b) { return a.texels < b.texels; });
    std::size_t leaks = 0;
    texels = world = 0.0;
    for (std::size_t i = 0; i < px.size(); ++i) {
        leaks += px[i].lit ? 1 : 0;
        if (px[i].lit && leaks >= 2 && 2 * leaks > i + 1) {
            texels = px[i].texels;
            world = px[i].world;
        }
    }
}

// An orthonormal basis b1, b2 of the plane across the unit direction d (the map's plane for a light
// along d).
void basis_across(glm::vec3 d, glm::vec3& b1, glm::vec3& b2) {
    b1 = glm::normalize(glm::cross(d, std::abs(d.x) < 0.9f ? glm::vec3(1.f, 0.f, 0.f) : glm::vec3(0.f, 1.f, 0.f)));
    b2 = glm::cross(d, b1);
}

// Whether the light ray through q, a point of p's plane (normal n), first meets the scene no nearer to
// the light than that plane (less `tol`), or misses it. A ray nearly parallel to the plane (an edge-on
// receiver, the terminator of a curved mesh) fails: the map cannot tell that plane from what bends in
// front of it within a texel.
bool plane_point_clear(const sk::EmbreeScene& e, const sk::Light& L, glm::vec3 p, glm::vec3 n, glm::vec3 q, float tol, float far) {
    const bool sun = L.type == sk::LightType::Directional;
    const glm::vec3 d = -glm::normalize(L.direction);  // towards a sun
    const glm::vec3 org = sun ? q + far * d : L.position;
    const glm::vec3 dir = sun ? -d : glm::normalize(q - L.position);
    const float dn = glm::dot(dir, n);
    if (!(dn < -1e-3f)) return false;  // the ray runs along the plane, or meets its back
    const float t_plane = glm::dot(p - org, n) / dn;
    return !(first_hit(e.scene, org, dir, INFINITY) < t_plane - tol);
}

// Whether nothing occludes p's tangent plane within the 2x2 filter's reach in the map: the light rays
// through a 7x7 grid half a texel apart over +-1.5 texels around p, across the light (in the map's
// plane, not on the receiver), are each clear of p's plane (plane_point_clear). Then a lit p that the
// map shadows is acne: the map holds p's own plane there.
bool plane_clear_within_filter_reach(const sk::EmbreeScene& e, const sk::Light& L, glm::vec3 p, glm::vec3 n, float texel,
                                     float tol, float far) {
    const bool sun = L.type == sk::LightType::Directional;
    const glm::vec3 d = sun ? -glm::normalize(L.direction) : glm::normalize(L.position - p);  // towards the light
    glm::vec3 b1, b2;
    basis_across(d, b1, b2);
    for (int i = 0; i < 49; ++i) {
        const float u = 0.5f * float(i % 7 - 3), w = 0.5f * float(i / 7 - 3);
        if (!plane_point_clear(e, L, p, n, p + texel * (u * b1 + w * b2), tol, far)) return false;
    }
    return true;
}

// Whether the rays of the texels the 2x2 filter reads at p in the map `m` (size^2 texels) are clear of
// p's plane (plane_point_clear) where they meet it: the texel centres within one texel of p's map
// coordinate on each axis (plus 1e-3 texel: the GPU's float rounding of that coordinate), clamped to
// the map's edge, each centre's line unprojected in double through m's inverse. The grid above samples
// the reach half a (longest) texel apart: a caster thinner than that (outdoor's 0.3 m posts under
// LiSPSM's 1.3 m x 0.2 m texels at the map's edge) slips between its rays, never between the centres
// the map is rasterized at. True when p is outside m (or behind its light).
bool filter_taps_clear(const sk::EmbreeScene& e, const sk::Light& L, glm::vec3 p, glm::vec3 n, const glm::mat4& m, int size,
                       float tol, float far) {
    const glm::dmat4 md(m), mi = glm::inverse(md);
    const glm::dvec4 c = md * glm::dvec4(glm::dvec3(p), 1.0);
    if (!(c.w > 0.0)) return true;
    const glm::dvec2 f = (glm::dvec2(c) / c.w * 0.5 + 0.5) * double(size) - 0.5;  // texel-centre coordinates
    const glm::dvec3 pd(p), nd(n);
    const int hi = size - 1;
    const int x0 = std::clamp(int(std::ceil(f.x - 1.001)), 0, hi), x1 = std::clamp(int(std::floor(f.x + 1.001)), 0, hi);
    const int y0 = std::clamp(int(std::ceil(f.y - 1.001)), 0, hi), y1 = std::clamp(int(std::floor(f.y + 1.001)), 0, hi);
    for (int j = y0; j <= y1; ++j)
        for (int i = x0; i <= x1; ++i) {
            const glm::dvec2 ndc = (glm::dvec2(i, j) + 0.5) / double(size) * 2.0 - 1.0;
            const glm::dvec4 a = mi * glm::dvec4(ndc, -1.0, 1.0), b = mi * glm::dvec4(ndc, 1.0, 1.0);
            const glm::dvec3 A = glm::dvec3(a) / a.w, B = glm::dvec3(b) / b.w;
            const double den = glm::dot(B - A, nd);
            if (!(std::abs(den) > 1e-12 * glm::length(B - A))) return false;  // the texel's line along the plane
            const glm::dvec3 q = A + glm::dot(pd - A, nd) / den * (B - A);
            if (!plane_point_clear(e, L, p, n, glm::vec3(q), tol, far)) return false;
        }
    return true;
}

// The world size of one texel at p of the map `m` (size^2 texels) across the light direction d (towards
// the light): the longest world extent of a texel there, (2 / size) / the smallest singular value of
// d(ndc.xy)/d(world) on the plane across d; 0 when p is outside the map (or behind its light).
float texel_of_matrix(const glm::mat4& m, glm::vec3 p, glm::vec3 d, int size) {
    const glm::vec4 c = m * glm::vec4(p, 1.f);
    if (!(c.w > 0.f)) return 0.f;
    const glm::vec3 ndc = glm::vec3(c) / c.w;
    if (std::abs(ndc.x) > 1.f || std::abs(ndc.y) > 1.f || std::abs(ndc.z) > 1.f) return 0.f;
    const glm::vec3 rw(m[0][3], m[1][3], m[2][3]);
    const glm::vec3 jx = (glm::vec3(m[0][0], m[1][0], m[2][0]) - ndc.x * rw) / c.w;  // quotient rule
    const glm::vec3 jy = (glm::vec3(m[0][1], m[1][1], m[2][1]) - ndc.y * rw) / c.w;
    glm::vec3 b1, b2;
    basis_across(d, b1, b2);
    const double a11 = glm::dot(jx, b1), a12 = glm::dot(jx, b2), a21 = glm::dot(jy, b1), a22 = glm::dot(jy, b2);
    const double f = a11 * a11 + a12 * a12 + a21 * a21 + a22 * a22, det = a11 * a22 - a12 * a21;
    const double smin2 = 0.5 * (f - std::sqrt(std::max(0.0, f * f - 4.0 * det * det)));
    if (!(smin2 > 0.0)) return 0.f;
    return static_cast<float>(2.0 / double(size) / std::sqrt(smin2));
}

// The maps of `mats` the technique reads at p (d: towards the light): the first whose map holds p, and
// the next one if it does too (cascades' blend band reads both); count 0 when none holds p.
struct PixelMaps {
    std::size_t first = 0, count = 0;
};
PixelMaps maps_at(const std::vector<glm::mat4>& mats, glm::vec3 p, glm::vec3 d, int size) {
    for (std::size_t i = 0; i < mats.size(); ++i)
        if (texel_of_matrix(mats[i], p, d, size) > 0.f)
            return {i, i + 1 < mats.size() && texel_of_matrix(mats[i + 1], p, d, size) > 0.f ? 2u : 1u};
    return {};
}

// The technique's texel at each scored pixel: from the matrices it reported for the frame (maps_at: the
// larger of the two cascades of a blend band), else (or outside them all) the scene frustum's texel at
// its map size.
std::vector<float> pixel_texels(const sk::GBuffer& g, const LightRef& r, const std::vector<glm::mat4>& mats, int map_size,
                                const sk::Light& L) {
    std::vector<float> out(r.cls.size(), 0.f);
    for (std::size_t k = 0; k < out.size(); ++k) {
        if (r.cls[k] == 0) continue;
        const glm::vec3 p(g.position[3 * k], g.position[3 * k + 1], g.position[3 * k + 2]);
        const glm::vec3 d = L.type == sk::LightType::Directional ? -glm::normalize(L.direction) : glm::normalize(L.position - p);
        const PixelMaps pm = maps_at(mats, p, d, map_size);
        float t = 0.f;
        for (std::size_t i = pm.first; i < pm.first + pm.count; ++i) t = std::max(t, texel_of_matrix(mats[i], p, d, map_size));
        out[k] = t > 0.f ? t : r.texel[k] / static_cast<float>(map_size);
    }
    return out;
}

LightScore score(const sk::GBuffer& g, const LightRef& r, const std::vector<float>& v, const std::vector<float>& texels,
                 const std::vector<glm::mat4>& mats, int map_size, const sk::EmbreeScene& e, const sk::Light& L, float eps) {
    const float far = 2e5f * eps;  // twice the scene's diagonal (eps: 1e-5 of it): a sun's rays start there
    LightScore s;
    const int w = g.width, h = g.height;
    std::size_t lit = 0, acne = 0, acne_texel = 0, umbra = 0, leak = 0, leak_texel = 0;
    std::vector<GapPixel> umbra_px;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t k = static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x);
            const int c = r.cls[k];
            if (c == 0) continue;
            // away from the reference's 1-pixel edges: no 8-neighbour of the other class
            bool edge = false;
            for (int dy = -1; dy <= 1 && !edge; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
                    const int o = r.cls[static_cast<std::size_t>(yy) * static_cast<std::size_t>(w) + static_cast<std::size_t>(xx)];
                    if (o != 0 && o != c) {
                        edge = true;
                        break;
                    }
                }
            if (edge) continue;
            if (c == 1) {
                ++lit;
                if (v[k] < 0.5f) {
                    ++acne;
                    const glm::vec3 p(g.position[3 * k], g.position[3 * k + 1], g.position[3 * k + 2]);
                    const glm::vec3 nn(g.normal[3 * k], g.normal[3 * k + 1], g.normal[3 * k + 2]);
                    bool clear = plane_clear_within_filter_reach(e, L, p, nn, texels[k], 4.f * eps, far);
                    // and the texels the filter reads, where the technique reports its maps
                    const glm::vec3 d = L.type == sk::LightType::Directional ? -glm::normalize(L.direction) : glm::normalize(L.position - p);
                    const PixelMaps pm = maps_at(mats, p, d, map_size);
                    for (std::size_t i = pm.first; clear && i < pm.first + pm.count; ++i)
                        clear = filter_taps_clear(e, L, p, nn, mats[i], map_size, 4.f * eps, far);
                    if (clear) ++acne_texel;
                }
            } else {
                ++umbra;
                const bool l = v[k] > 0.5f;
                const float texel = texels[k];
                // a leak at a shadow's side edge (hidden from the screen-space edge test behind its
                // occluder) is no contact gap
                bool side = false;
                if (l) {
                    ++leak;
                    const glm::vec3 p(g.position[3 * k], g.position[3 * k + 1], g.position[3 * k + 2]);
                    const glm::vec3 nn(g.normal[3 * k], g.normal[3 * k + 1], g.normal[3 * k + 2]);
                    if (uniform_within_filter_reach(e, L, p, nn, texel, eps, true, false))
                        ++leak_texel;
                    else
                        side = !uniform_within_filter_reach(e, L, p, nn, texel, eps, true, true);
                }
                const float cn = r.cos_n[k];
                const float tan_n = std::sqrt(std::max(0.f, 1.f - cn * cn)) / cn;
                umbra_px.push_back({r.t[k] / (texel * std::max(1.f, tan_n)), r.t[k], l && !side});
            }
        }
    s.acne = lit ? double(acne) / double(lit) : 0.0;
    s.acne_texel = lit ? double(acne_texel) / double(lit) : 0.0;
    s.leak_texel = umbra ? double(leak_texel) / double(umbra) : 0.0;
    s.leak = umbra ? double(leak) / double(umbra) : 0.0;
    contact_gap(umbra_px, s.gap_texels, s.gap_world);
    return s;
}

// The technique's frames (its run_sequence: one init, then update + render + read-back per frame);
// a failure (exception, wrong frame count) is a failed SequenceResult whose error is one line.
sk::SequenceResult run_frames(sk::Technique& t, const sk::RunContext& ctx, const sk::ParamSet& params,
                              const std::vector<sk::TemporalFrame>& frames) {
    sk::SequenceResult res;
    try {
        res = t.run_sequence(ctx, params, frames);
    } catch (const std::exception& ex) {
        res = sk::SequenceResult::failure(std::string("exception: ") + ex.what());
    }
    if (res.ok && res.visibility.size() != frames.size()) res = sk::SequenceResult::failure("wrong frame count");
    if (!res.ok) res.error = res.error.substr(0, res.error.find('\n'));
    return res;
}

// The frames one at a time: frame_ok[f] = 0 where the technique failed (its visibility left empty);
// error: the first failure's.
sk::SequenceResult run_one_by_one(sk::Technique& t, const sk::RunContext& ctx, const sk::ParamSet& params,
                                  const std::vector<sk::TemporalFrame>& frames, std::vector<std::uint8_t>& frame_ok) {
    sk::SequenceResult out;
    out.visibility.resize(frames.size());
    out.light_matrices.resize(frames.size());
    for (std::size_t f = 0; f < frames.size(); ++f) {
        sk::SequenceResult one = run_frames(t, ctx, params, {frames[f]});
        frame_ok[f] = one.ok ? 1 : 0;
        if (one.ok) {
            out.visibility[f] = std::move(one.visibility[0]);
            if (!one.light_matrices.empty()) out.light_matrices[f] = std::move(one.light_matrices[0]);
        } else if (out.error.empty()) {
            out.error = one.error;
        }
    }
    return out;
}

double since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

void run_light_sweep(const std::vector<sk::Scene>& scenes, const std::vector<sk::Technique*>& chosen,
                     const LightSweepOptions& opt, LightSweep& out) {
    const auto t_all = std::chrono::steady_clock::now();
    out = LightSweep{};
    out.requested = true;
    out.options = opt;
    const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
    for (const sk::Scene& base : scenes) {
        sk::SceneGpu gpu;
        sk::GBuffer g;
        std::string why;
        if (!sk::prepare_scene_gpu(base, opt.width, opt.height, gpu, g, why)) {
            std::fprintf(stderr, "  sweep     %s: %s\n", base.name.c_str(), why.c_str());
            continue;
        }
        sk::EmbreeScene e;
        if (!sk::build_embree(base, e, why)) {
            std::fprintf(stderr, "  sweep     %s: %s\n", base.name.c_str(), why.c_str());
            continue;
        }
        const SweepLights sl = make_lights(base, g, opt);
        sk::Scene scene = base;
        scene.light = sl.lights.empty() ? base.light : sl.lights[0];
        struct Job {
            sk::Technique* t;
            sk::ParamSet params;
            std::size_t row;
        };
        std::vector<Job> jobs;
        const std::size_t first_row = out.rows.size();
        for (const SweepTechnique& st : kSweepTechniques) {
            auto it = std::find_if(chosen.begin(), chosen.end(), [&](const sk::Technique* t) { return t->name() == st.name; });
            if (it == chosen.end() || (*it)->sweep(scene, false).empty()) continue;  // not chosen, or not on this light
            LightSweepRow row;
            row.scene = base.name;
            row.technique = st.name;
            row.settings = st.settings;
            row.light = type_name(sl.type);
            row.lights = static_cast<int>(sl.lights.size());
            row.grazing_lights = sl.grazing;
            row.width = opt.width;
            row.height = opt.height;
            row.map_size = st.map_size;
            jobs.push_back({*it, sk::ParamSet::parse_named(st.settings), out.rows.size()});
            out.rows.push_back(row);
        }
        if (jobs.empty()) continue;
        double ref_seconds = 0.0;
        const float eps = sk::ReferenceOptions{}.offset_fraction * glm::length(base.bounds_max() - base.bounds_min());  // the reference's ray offset
        const std::size_t chunk = static_cast<std::size_t>(std::max(1, opt.chunk));
        std::vector<LightRef> refs;
        for (std::size_t c0 = 0; c0 < sl.lights.size(); c0 += chunk) {
            const std::size_t c1 = std::min(sl.lights.size(), c0 + chunk);
            // the chunk's hard references, one light per thread at a time
            const auto t_ref = std::chrono::steady_clock::now();
            refs.resize(c1 - c0);
            std::atomic<std::size_t> next{c0};
            std::vector<std::thread> pool;
            for (unsigned i = 0; i < threads; ++i)
                pool.emplace_back([&] {
                    for (std::size_t l; (l = next.fetch_add(1)) < c1;) hard_reference(base, g, e, sl.lights[l], refs[l - c0]);
                });
            for (auto& th : pool) th.join();
            ref_seconds += since(t_ref);
            std::vector<sk::TemporalFrame> frames;
            for (std::size_t l = c0; l < c1; ++l) frames.push_back({base.camera, sl.lights[l]});
            for (const Job& j : jobs) {
                LightSweepRow& row = out.rows[j.row];
                if (row.failed) continue;
                const auto t0 = std::chrono::steady_clock::now();
                sk::RunContext ctx{scene, gpu, 1, 0, &g};
                ctx.verify_sequence = false;  // V only
                sk::SequenceResult res = run_frames(*j.t, ctx, j.params, frames);
                std::vector<std::uint8_t> frame_ok(frames.size(), 1);
                if (!res.ok) {  // a light the technique rejects (a status): retry the chunk's lights one by one
                    res = run_one_by_one(*j.t, ctx, j.params, frames, frame_ok);
                    for (std::size_t f = 0; f < frames.size(); ++f)
                        if (!frame_ok[f]) {
                            if (row.lights_failed++ == 0) row.first_light_error = res.error;
                        }
                    if (row.lights_failed == row.lights) {
                        row.failed = true;
                        row.error = row.first_light_error;
                    }
                }
                for (std::size_t l = c0; l < c1; ++l) {
                    if (!frame_ok[l - c0]) continue;
                    const std::vector<float>& v = res.visibility[l - c0];
                    if (v.size() != g.kind.size()) continue;
                    const std::vector<glm::mat4> none;
                    const std::vector<glm::mat4>& mats = l - c0 < res.light_matrices.size() ? res.light_matrices[l - c0] : none;
                    if (!mats.empty()) row.texels_from_technique = true;
                    const LightScore s =
                        score(g, refs[l - c0], v, pixel_texels(g, refs[l - c0], mats, row.map_size, sl.lights[l]), mats, row.map_size, e,
                              sl.lights[l], eps);
                    const glm::vec3 wl = sl.towards[l];
                    if (s.acne > 0.0) ++row.lights_with_acne;
                    if (s.leak > 0.0) ++row.lights_with_leak;
                    if (s.gap_texels > 0.0) ++row.lights_with_gap;
                    auto keep_max = [&wl](double value, double& max, glm::vec3& worst) {  // and the light it came from
                        if (value > max) max = value, worst = wl;
                    };
                    keep_max(s.acne_texel, row.acne_beyond_filter_max, row.acne_beyond_filter_worst_light);
                    keep_max(s.acne, row.acne_fraction_max, row.acne_worst_light);
                    keep_max(s.leak_texel, row.leak_beyond_filter_max, row.leak_beyond_filter_worst_light);
                    keep_max(s.leak, row.leak_fraction_max, row.leak_worst_light);
                    keep_max(s.gap_texels, row.gap_texels_max, row.gap_worst_light);
                    row.gap_world_max = std::max(row.gap_world_max, s.gap_world);
                }
                row.seconds += since(t0);
            }
        }
        for (std::size_t i = first_row; i < out.rows.size(); ++i) {
            LightSweepRow& r = out.rows[i];
            r.reference_seconds = ref_seconds;
            if (r.failed)
                std::fprintf(stderr, "  sweep     %-9s %-11s failed: %s\n", r.scene.c_str(), r.technique.c_str(), r.error.c_str());
            else
                std::fprintf(stderr,
                             "  sweep     %-9s %-11s %4d %-11s lights: acne max %.4f (beyond the filter %.4f), gap max %.2f texels "
                             "(%.3g world), leak max %.4f (beyond the filter %.4f); %.1f s (+ references %.1f s)\n",
                             r.scene.c_str(), r.technique.c_str(), r.lights, r.light.c_str(), r.acne_fraction_max,
                             r.acne_beyond_filter_max,
                             r.gap_texels_max, r.gap_world_max, r.leak_fraction_max, r.leak_beyond_filter_max, r.seconds, ref_seconds);
        }
    }
    out.seconds = since(t_all);
}

namespace {

std::string num(double v) {
    if (!std::isfinite(v)) return "null";
    char b[40];
    std::snprintf(b, sizeof b, "%.6g", v);
    return b;
}

std::string vec(glm::vec3 v) { return "[" + num(v.x) + ", " + num(v.y) + ", " + num(v.z) + "]"; }

std::string elevation_text(glm::vec3 w) {
    char b[64];
    std::snprintf(b, sizeof b, "el %.1f, az %.0f", double(std::asin(std::clamp(w.y, -1.f, 1.f)) * 180.f / kPi),
                  double(std::atan2(w.z, w.x) * 180.f / kPi));
    return b;
}

}  // namespace

void write_light_sweep_json(std::ostream& f, const LightSweep& s) {
    if (!s.requested) return;
    f << ",\n  \"light_sweep\": [";
    bool first = true;
    for (const LightSweepRow& r : s.rows) {
        f << (first ? "\n" : ",\n") << "    {\"scene\": \"" << json_escape(r.scene) << "\", \"technique\": \""
          << json_escape(r.technique) << "\", \"settings\": \"" << json_escape(r.settings) << "\", \"light\": \""
          << r.light << "\", \"lights\": " << r.lights << ", \"grazing_lights\": " << r.grazing_lights
          << ", \"width\": " << r.width << ", \"height\": " << r.height << ", \"map_size\": " << r.map_size
          << ", \"texels_from_technique\": " << (r.texels_from_technique ? "true" : "false");
        first = false;
        if (r.failed) {
            f << ", \"failed\": \"" << json_escape(r.error) << "\", \"acne_fraction_max\": null, \"gap_texels_max\": null"
              << ", \"gap_world_max\": null, \"leak_fraction_max\": null";
        } else {
            f << ", \"acne_fraction_max\": " << num(r.acne_fraction_max) << ", \"acne_worst_light\": " << vec(r.acne_worst_light)
              << ", \"lights_with_acne\": " << r.lights_with_acne
              << ", \"acne_beyond_filter_max\": " << num(r.acne_beyond_filter_max)
              << ", \"acne_beyond_filter_worst_light\": " << vec(r.acne_beyond_filter_worst_light)
              << ", \"gap_texels_max\": " << num(r.gap_texels_max)
              << ", \"gap_world_max\": " << num(r.gap_world_max) << ", \"gap_worst_light\": " << vec(r.gap_worst_light)
              << ", \"lights_with_gap\": " << r.lights_with_gap << ", \"leak_fraction_max\": " << num(r.leak_fraction_max)
              << ", \"leak_worst_light\": " << vec(r.leak_worst_light)
              << ", \"leak_beyond_filter_max\": " << num(r.leak_beyond_filter_max)
              << ", \"leak_beyond_filter_worst_light\": " << vec(r.leak_beyond_filter_worst_light) << ", \"lights_with_leak\": " << r.lights_with_leak
              << ", \"lights_failed\": " << r.lights_failed;
            if (r.lights_failed > 0) f << ", \"first_light_error\": \"" << json_escape(r.first_light_error) << "\"";
        }
        f << ", \"seconds\": " << num(r.seconds) << ", \"reference_seconds\": " << num(r.reference_seconds) << "}";
    }
    f << (s.rows.empty() ? "]" : "\n  ]");
}

void write_light_sweep_markdown(std::ostream& f, const LightSweep& s) {
    if (!s.requested) return;
    char b[512];
    f << "## light sweep\n\n";
    std::snprintf(b, sizeof b,
                  "Each hard shadow-map technique at its default settings under %d random lights per scene (a third "
                  "grazing, 1 to 5 degrees above the floor), scored at %dx%d camera pixels against a hard Embree "
                  "reference per light; the maxima over the lights (definitions: docs/report.md, \"Light sweep\"). "
                  "Worst light: elevation and azimuth in degrees of the direction towards it. Sweep time %.1f s.\n\n",
                  s.options.lights, s.options.width, s.options.height, s.seconds);
    f << b;
    if (s.rows.empty()) {
        f << "No scene of this run has a technique the sweep covers.\n\n";
        return;
    }
    f << "| scene | technique | light | lights (grazing) | acne max | worst (acne) | acne beyond the filter | gap max, texels | gap max, world | "
         "worst (gap) | leak max | worst (leak) | leak beyond the filter | lights with acne / gap / leak | seconds |\n"
      << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const LightSweepRow& r : s.rows) {
        std::string label = r.technique + (r.settings.empty() ? "" : " " + r.settings);
        if (r.lights_failed > 0 && !r.failed)
            label += " (" + std::to_string(r.lights_failed) + " lights rejected: " + r.first_light_error + ")";
        if (r.failed) {
            f << "| " << r.scene << " | " << label << " | " << r.light << " | failed: " << r.error
              << " | | | | | | | | | | | |\n";
            continue;
        }
        std::snprintf(b, sizeof b,
                      "| %s | %s | %s | %d (%d) | %.4f | %s | %.4f | %.2f | %.3g | %s | %.4f | %s | %.4f | %d / %d / %d | %.1f + %.1f |\n",
                      r.scene.c_str(), label.c_str(), r.light.c_str(), r.lights, r.grazing_lights, r.acne_fraction_max,
                      r.acne_fraction_max > 0 ? elevation_text(r.acne_worst_light).c_str() : "-", r.acne_beyond_filter_max,
                      r.gap_texels_max,
                      r.gap_world_max, r.gap_texels_max > 0 ? elevation_text(r.gap_worst_light).c_str() : "-",
                      r.leak_fraction_max, r.leak_fraction_max > 0 ? elevation_text(r.leak_worst_light).c_str() : "-",
                      r.leak_beyond_filter_max,
                      r.lights_with_acne, r.lights_with_gap, r.lights_with_leak, r.seconds, r.reference_seconds);
        f << b;
    }
    f << "\nseconds: the technique's frames and scoring + the scene's hard references (shared by its techniques).\n\n";
}

}  // namespace skr
