// tests/gl/test_gl_composition.cpp - issue 13's composition test: ONE scene (boxes, a thin slab, a
// post, an open awning with a two-sided fin on a non-manifold edge, over an open floor), ONE camera
// whose projection is infinite_projection.hpp's epsilon-tweaked P_inf (GL depth, and reversed-Z
// zero-to-one), and the SAME `glm::vec4 light_position` handed to every header that takes a light,
// for a point light, a spot light (a point light plus a cone: no header takes a cone, see below), and
// a directional light from the camera's side and from behind the scene. Every technique is rendered
// the way its docs page shows, into a visibility V per camera pixel, and compared with a CPU ray
// cast (docs::segment_occluded from the pixel's surface point to the light) and with the stencil
// shadow volumes (the exact per-pixel technique) on the pixels away from shadow edges.
//
// Written against the public headers and glsl/ snippets only, as a user would (the GL context comes
// from gl_main.cpp, small helpers from tests/docs/docs_gl.hpp). It catches issue 13's seams: a sun
// vector meaning "toward" in one header and "along" in another (every directional row fails), the
// epsilon-tweaked P_inf rejected by a fit (the first test case fails), a silhouette that the volume,
// wedge or smoothie headers read in the other orientation (the volume closure, hard plane and
// smoothie side checks fail). On the headers before this test it failed 11 assertions:
// light_frustum_fit refused the point light with LightInsideVolume (the warps took it), and its
// directional view had its eye inside the scene, so smoothies lit receivers with a negative linear
// light depth (99.33% under the rear sun). docs/composition.md has the table this test prints.
//
// Cones: no header takes a spot cone (CONVENTIONS.md: cones are separate, named fields; none
// exists): a spot light is a point light to every header, its cone is the user's lighting term. The
// test therefore scores the spot light only inside its cone.
#include "../docs/docs_gl.hpp"

#include <shadowkit/cascades.hpp>
#include <shadowkit/infinite_projection.hpp>
#include <shadowkit/light_frustum.hpp>
#include <shadowkit/omni_shadow.hpp>
#include <shadowkit/pcss.hpp>
#include <shadowkit/penumbra_wedge.hpp>
#include <shadowkit/perspective_shadow_maps.hpp>
#include <shadowkit/shadow_bias.hpp>
#include <shadowkit/shadow_volume.hpp>
#include <shadowkit/silhouette.hpp>
#include <shadowkit/silhouette_map.hpp>
#include <shadowkit/smoothie.hpp>

#include <doctest/doctest.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace sk = shadowkit;

namespace {

constexpr int kW = 192, kH = 144;  // the camera's pixels
constexpr int kMap = 256;          // every shadow map, cascade, cube face and smoothie buffer
constexpr float kMaxDistance = 30.0f;

// ------------------------------------------------------------------------------------------ scene

// An awning (two quads facing +y, open: its outline is a boundary) with a two-sided fin hanging from
// its middle edge: that edge has four faces (non-manifold), the fin's diagonal too.
docs::Mesh awning_with_fin() {
    docs::Mesh m;
    m.positions = {{-1.4f, 1.7f, 0.9f}, {-1.4f, 1.7f, 2.1f}, {-0.8f, 1.7f, 0.9f}, {-0.8f, 1.7f, 2.1f},
                   {-0.2f, 1.7f, 0.9f}, {-0.2f, 1.7f, 2.1f}, {-0.8f, 1.3f, 0.9f}, {-0.8f, 1.3f, 2.1f}};
    enum : std::uint32_t { a0, a1, m0, m1, b0, b1, f0, f1 };
    m.indices = {a0, a1, m1, a0, m1, m0,   // left half, +y
                 m0, m1, b1, m0, b1, b0,   // right half, +y
                 m0, f0, f1, m0, f1, m1,   // fin, -x side
                 m0, f1, f0, m0, m1, f1};  // fin, +x side
    return m;
}

struct Scene {
    std::vector<docs::Mesh> meshes;  // 0: the floor (a single-sided quad); 1..: the occluders
    docs::Mesh all;                  // every triangle, for the CPU ray cast
    glm::vec3 lo{-4.0f, 0.0f, -4.0f}, hi{4.0f, 2.2f, 4.0f};
    std::vector<float> caster_boxes;  // 6 floats per mesh (light_frustum.hpp's casters)
};

void bounds(const docs::Mesh& m, glm::vec3& lo, glm::vec3& hi) {
    lo = hi = m.positions[0];
    for (const glm::vec3& p : m.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
}

Scene make_scene() {
    Scene s;
    s.meshes.push_back(docs::quad_y(0.0f, 4.0f));
    s.meshes.push_back(docs::box({-1.6f, 0.0f, -0.6f}, {-0.6f, 1.0f, 0.4f}));  // on the floor: contact
    s.meshes.push_back(docs::box({0.5f, 0.9f, -0.8f}, {1.6f, 0.96f, 0.3f}));   // a thin floating slab
    s.meshes.push_back(docs::box({1.2f, 0.0f, 1.2f}, {1.5f, 2.2f, 1.5f}));     // a post
    s.meshes.push_back(awning_with_fin());
    for (const docs::Mesh& m : s.meshes) {
        docs::append(s.all, m);
        glm::vec3 lo, hi;
        bounds(m, lo, hi);
        s.caster_boxes.insert(s.caster_boxes.end(), {lo.x, lo.y, lo.z, hi.x, hi.y, hi.z});
    }
    return s;
}

// ------------------------------------------------------------------------------------------ camera

struct Camera {
    glm::vec3 eye{0.5f, 5.5f, 7.5f};
    glm::mat4 view{1.0f}, proj{1.0f};
    float fovy = glm::radians(50.0f), aspect = float(kW) / float(kH), near_z = 0.1f;
    sk::ClipDepth clip_depth = sk::ClipDepth::NegativeOneToOne;
    bool reversed_z = false;
    float epsilon = 0.0f;
    std::string name;
};

// The camera with infinite_projection.hpp's P_inf: epsilon 0 or the float32 bound, either clip depth.
Camera make_camera(sk::ClipDepth clip_depth, bool reversed_z, bool tweaked) {
    Camera c;
    c.view = glm::lookAt(c.eye, glm::vec3(0.0f, 0.5f, 0.0f), glm::vec3(0.0f, 1.0f, 0.0f));
    c.clip_depth = clip_depth;
    c.reversed_z = reversed_z;
    sk::ProjectionDepth depth;
    depth.near_z = c.near_z;
    depth.clip_depth = clip_depth;
    depth.reversed_z = reversed_z;
    if (tweaked) {
        const sk::ProjectionEpsilonBound eps =
            sk::projection_infinite_epsilon_bound(c.fovy, c.aspect, clip_depth, reversed_z, sk::DepthFormat::Float32);
        REQUIRE(eps.status == sk::Status::Ok);
        depth.epsilon = eps.epsilon;
    }
    c.epsilon = depth.epsilon;
    const sk::ProjectionResult p = sk::projection_perspective(c.fovy, c.aspect, depth);
    REQUIRE(p.status == sk::Status::Ok);
    c.proj = p.matrix;
    char name[96];
    std::snprintf(name, sizeof name, "P_inf %s%s eps %.2g", clip_depth == sk::ClipDepth::ZeroToOne ? "0..1" : "GL",
                  reversed_z ? " reversed" : "", double(c.epsilon));
    c.name = name;
    return c;
}

// ------------------------------------------------------------------------------------------ lights

struct Light {
    const char* name;
    glm::vec4 light_position;  // the ONE value every header gets
    bool spot = false;         // a point light plus a cone (the cone is the lighting term's, not a header's)
    glm::vec3 spot_axis{0.0f};
    float spot_cos = -1.0f;
    bool point() const { return light_position.w > 0.0f; }
    glm::vec3 center() const { return glm::vec3(light_position) / light_position.w; }
};

std::vector<Light> make_lights() {
    std::vector<Light> l;
    l.push_back({"point", glm::vec4(0.2f, 3.2f, 0.1f, 1.0f)});
    Light spot{"spot", glm::vec4(2.5f, 6.0f, 3.0f, 1.0f)};
    spot.spot = true;
    spot.spot_axis = glm::normalize(glm::vec3(0.0f, 0.5f, 0.0f) - spot.center());
    spot.spot_cos = std::cos(glm::radians(30.0f));
    l.push_back(spot);
    l.push_back({"sun, camera side", glm::vec4(glm::normalize(glm::vec3(0.35f, 1.0f, 0.55f)), 0.0f)});
    l.push_back({"sun, behind", glm::vec4(glm::normalize(glm::vec3(-0.45f, 0.9f, -0.7f)), 0.0f)});
    return l;
}

// ------------------------------------------------------------------------------------------ CPU checks

// Receiver points the camera sees (floor and box tops on a grid), within max_distance.
std::vector<glm::vec3> visible_receivers(const Scene& s, const Camera& c) {
    std::vector<glm::vec3> pts;
    const glm::mat4 vp = c.proj * c.view;
    auto in_view = [&](const glm::vec3& p) {
        const glm::vec4 e = c.view * glm::vec4(p, 1.0f);
        if (!(-e.z > c.near_z && -e.z < kMaxDistance)) return false;
        const glm::vec4 h = vp * glm::vec4(p, 1.0f);
        return h.w > 0.0f && std::abs(h.x) <= h.w && std::abs(h.y) <= h.w;
    };
    for (int j = 0; j <= 40; ++j)
        for (int i = 0; i <= 40; ++i) {
            const glm::vec3 p(s.lo.x + (s.hi.x - s.lo.x) * float(i) / 40.0f, 0.0f, s.lo.z + (s.hi.z - s.lo.z) * float(j) / 40.0f);
            if (in_view(p)) pts.push_back(p);
        }
    for (std::size_t m = 1; m < s.meshes.size(); ++m) {
        glm::vec3 lo, hi;
        bounds(s.meshes[m], lo, hi);
        for (int k = 0; k < 9; ++k) {
            const glm::vec3 p(lo.x + (hi.x - lo.x) * float(k % 3) / 2.0f, hi.y, lo.z + (hi.z - lo.z) * float(k / 3) / 2.0f);
            if (in_view(p)) pts.push_back(p);
        }
    }
    return pts;
}

// True when every point lies in the clip volume of m (|x|, |y| <= w, depth inside the clip range).
bool all_inside(const glm::mat4& m, const std::vector<glm::vec3>& pts, sk::ClipDepth cd, std::string& why) {
    for (const glm::vec3& p : pts) {
        const glm::dvec4 h = glm::dmat4(m) * glm::dvec4(glm::dvec3(p), 1.0);
        const double tol = 1e-4 * std::abs(h.w);
        const double zlo = cd == sk::ClipDepth::ZeroToOne ? 0.0 : -h.w;
        if (!(h.w > 0.0) || std::abs(h.x) > h.w + tol || std::abs(h.y) > h.w + tol || h.z < zlo - tol || h.z > h.w + tol) {
            char b[160];
            std::snprintf(b, sizeof b, "(%g, %g, %g) -> clip (%g, %g, %g, %g)", double(p.x), double(p.y), double(p.z), h.x, h.y,
                          h.z, h.w);
            why = b;
            return false;
        }
    }
    return true;
}

// 2D convex hull (Andrew's monotone chain), counter-clockwise.
std::vector<glm::dvec2> convex_hull(std::vector<glm::dvec2> p) {
    std::sort(p.begin(), p.end(), [](const glm::dvec2& a, const glm::dvec2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
    std::vector<glm::dvec2> h(2 * p.size());
    std::size_t k = 0;
    auto cross = [](const glm::dvec2& o, const glm::dvec2& a, const glm::dvec2& b) {
        return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
    };
    for (std::size_t i = 0; i < p.size(); ++i) {
        while (k >= 2 && cross(h[k - 2], h[k - 1], p[i]) <= 0.0) --k;
        h[k++] = p[i];
    }
    for (std::size_t i = p.size() - 1, t = k + 1; i-- > 0;) {
        while (k >= t && cross(h[k - 2], h[k - 1], p[i]) <= 0.0) --k;
        h[k++] = p[i];
    }
    h.resize(k - 1);
    return h;
}

// Signed distance from q to a counter-clockwise convex polygon: > 0 outside.
double hull_distance(const std::vector<glm::dvec2>& h, const glm::dvec2& q) {
    double outside = -std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < h.size(); ++i) {
        const glm::dvec2 a = h[i], b = h[(i + 1) % h.size()];
        const glm::dvec2 n = glm::normalize(glm::dvec2(b.y - a.y, a.x - b.x));  // outward for CCW
        outside = std::max(outside, glm::dot(n, q - a));
    }
    return outside;
}

glm::dvec2 ndc_xy(const glm::mat4& m, const glm::vec3& p) {
    const glm::dvec4 h = glm::dmat4(m) * glm::dvec4(glm::dvec3(p), 1.0);
    return glm::dvec2(h.x, h.y) / h.w;
}

// What the three fits' inputs (LightFrustumInput, WarpInput, CascadeInput) share, under the same
// names: the camera (its depth convention also the light matrix's), kMaxDistance (required with the
// infinite far plane) and the light.
template <class Input>
Input fit_input(const Camera& c, const glm::vec4& light_position) {
    Input in;
    in.camera_view = c.view;
    in.camera_proj = c.proj;
    in.camera_depth = c.clip_depth;
    in.camera_reversed_z = c.reversed_z;
    in.max_distance = kMaxDistance;
    in.light_position = light_position;
    in.light_depth = c.clip_depth;  // the light's matrix in the camera's depth convention
    in.light_reversed_z = c.reversed_z;
    return in;
}

sk::LightFrustumInput light_frustum_input(const Scene& s, const Camera& c, const glm::vec4& light_position) {
    auto in = fit_input<sk::LightFrustumInput>(c, light_position);
    in.has_scene_bounds = true;
    in.scene_min = s.lo;
    in.scene_max = s.hi;
    in.casters = s.caster_boxes.data();
    in.caster_count = s.caster_boxes.size() / 6;
    return in;
}

sk::WarpInput warp_input(const Scene& s, const Camera& c, const glm::vec4& light_position) {
    auto in = fit_input<sk::WarpInput>(c, light_position);
    in.has_scene_bounds = true;
    in.scene_min = s.lo;
    in.scene_max = s.hi;
    return in;
}

sk::CascadeInput cascade_input(const Scene& s, const Camera& c, const glm::vec4& light_position) {
    auto in = fit_input<sk::CascadeInput>(c, light_position);
    in.shadow_map_size = kMap;
    in.has_caster_bounds = true;
    in.caster_min = s.lo;
    in.caster_max = s.hi;
    return in;
}

sk::ScissorParams scissor_params(const Camera& c) {
    sk::ScissorParams sp;
    sp.view_proj = c.proj * c.view;
    sp.clip_depth = c.clip_depth;
    sp.reversed_z = c.reversed_z;
    sp.viewport[2] = kW;
    sp.viewport[3] = kH;
    return sp;
}

const std::string kWarpNames[4] = {"uniform", "PSM", "LiSPSM", "TSM"};

// doctest prints a const char* as a pointer: the status name as a string
std::string st(sk::Status s) { return sk::status_name(s); }
const sk::WarpMethod kWarpMethods[4] = {sk::WarpMethod::Uniform, sk::WarpMethod::Psm, sk::WarpMethod::Lispsm, sk::WarpMethod::Tsm};

}  // namespace

// ================================================================================================
// The seams, on the CPU: one header's output is the next one's input.
// ================================================================================================
TEST_CASE("composition seams: infinite projections, silhouettes and light matrices cross the headers") {
    const Scene scene = make_scene();
    const std::vector<Light> lights = make_lights();

    // ---- every variant of infinite_projection.hpp's P_inf is accepted by every fit
    int variants = 0;
    for (const bool tweaked : {false, true})
        for (const sk::ClipDepth cd : {sk::ClipDepth::NegativeOneToOne, sk::ClipDepth::ZeroToOne})
            for (const bool rev : {false, true}) {
                const Camera cam = make_camera(cd, rev, tweaked);
                ++variants;
                const std::vector<glm::vec3> receivers = visible_receivers(scene, cam);
                REQUIRE(receivers.size() > 200);
                const sk::ScissorParams sp = scissor_params(cam);
                // the near-plane rectangle from the inverse view-projection = the one from fovy / aspect
                const sk::VolumeNearRect near_inv =
                    sk::volume_near_plane_rect_from_inverse(glm::inverse(cam.proj * cam.view), cd, rev);
                const sk::VolumeNearRect near_direct = sk::volume_near_plane_rect(cam.view, cam.fovy, cam.aspect, cam.near_z);
                REQUIRE_MESSAGE(near_inv.status == sk::Status::Ok, cam.name);
                REQUIRE(near_direct.status == sk::Status::Ok);
                for (int i = 0; i < 4; ++i)
                    CHECK_MESSAGE(glm::length(near_inv.corners[i] - near_direct.corners[i]) < 1e-5f, cam.name, " corner ", i);

                for (const Light& L : lights) {
                    INFO(cam.name, " / ", std::string(L.name));
                    std::string why;
                    // light_frustum.hpp: the tight fit; the stable one for a sun, InvalidLight for a point light
                    sk::LightFrustumInput lin = light_frustum_input(scene, cam, L.light_position);
                    std::vector<std::uint32_t> keep(lin.caster_count);
                    const sk::LightFrustumResult fit = sk::light_frustum_fit(lin, keep.data(), keep.size());
                    REQUIRE_MESSAGE(fit.status == sk::Status::Ok, st(fit.status));
                    CHECK(fit.visible);
                    CHECK_MESSAGE(all_inside(fit.view_proj, receivers, cd, why), "light_frustum_fit: ", why);
                    lin.stable = true;
                    lin.shadow_map_size = kMap;
                    const sk::LightFrustumResult stable = sk::light_frustum_fit(lin, keep.data(), keep.size());
                    if (L.point()) {
                        CHECK(stable.status == sk::Status::InvalidLight);  // documented: the stable fit is for suns
                    } else {
                        REQUIRE_MESSAGE(stable.status == sk::Status::Ok, st(stable.status));
                        CHECK_MESSAGE(all_inside(stable.view_proj, receivers, cd, why), "stable fit: ", why);
                    }
                    // perspective_shadow_maps.hpp: every method
                    const sk::WarpInput win = warp_input(scene, cam, L.light_position);
                    for (int m = 0; m < 4; ++m) {
                        const sk::WarpResult w = sk::warp_matrix(win, kWarpMethods[m]);
                        REQUIRE_MESSAGE(w.status == sk::Status::Ok, kWarpNames[m], ": ", st(w.status));
                        CHECK(w.visible);
                        CHECK_MESSAGE(all_inside(w.light_view_proj, receivers, cd, why), kWarpNames[m], ": ", why);
                    }
                    // cascades.hpp: suns only
                    sk::Cascade cascades[4];
                    const sk::CascadeFitResult cf = sk::cascade_fit(cascade_input(scene, cam, L.light_position), 0.75f, 4, cascades, 4);
                    if (L.point()) {
                        CHECK(cf.status == sk::Status::InvalidLight);
                    } else {
                        REQUIRE_MESSAGE(cf.status == sk::Status::Ok, st(cf.status));
                        CHECK(cf.splits[4] == doctest::Approx(kMaxDistance));
                        // every receiver is in the map of the cascade its view depth selects
                        std::vector<glm::vec3> per[4];
                        for (const glm::vec3& p : receivers) {
                            const float d = -(cam.view * glm::vec4(p, 1.0f)).z;
                            const sk::CascadeIndex ci = sk::cascade_select_by_depth(d, cf.splits, 4);
                            REQUIRE(ci.status == sk::Status::Ok);
                            if (ci.index >= 0) per[ci.index].push_back(p);
                        }
                        for (int i = 0; i < 4; ++i)
                            CHECK_MESSAGE(all_inside(cascades[i].view_proj, per[i], cd, why), "cascade ", i, ": ", why);
                    }
                    // shadow_volume.hpp: stencil method and scissor per occluder; penumbra_wedge.hpp's scissor
                    for (std::size_t m = 1; m < scene.meshes.size(); ++m) {
                        glm::vec3 lo, hi;
                        bounds(scene.meshes[m], lo, hi);
                        const sk::VolumeMethod a = sk::volume_choose_stencil_method_box(near_inv, L.light_position, lo, hi, 1e-4f);
                        const sk::VolumeMethod b = sk::volume_choose_stencil_method_box(near_direct, L.light_position, lo, hi, 1e-4f);
                        REQUIRE(a.status == sk::Status::Ok);
                        REQUIRE(b.status == sk::Status::Ok);
                        CHECK(a.method == b.method);
                        CHECK(a.method == sk::VolumeStencilMethod::ZPass);  // the camera is in no shadow
                        const sk::ScissorRect r = sk::volume_scissor(L.light_position, lo, hi, scene.lo, scene.hi, sp);
                        REQUIRE_MESSAGE(r.status == sk::Status::Ok, st(r.status));
                        REQUIRE(r.visible);
                        // conservative: points of the occluder's shadow region inside the light's box and
                        // in front of the camera lie in the rectangle and the depth bounds (window depth
                        // of this clip convention)
                        std::mt19937 rng(unsigned(m) * 7u + 1u);
                        std::uniform_real_distribution<float> u01(0.0f, 1.0f);
                        int tested = 0;
                        for (int k = 0; k < 4000; ++k) {
                            const glm::vec3 p = lo + (hi - lo) * glm::vec3(u01(rng), u01(rng), u01(rng));
                            const float t = 10.0f * u01(rng);  // up to 10 units beyond the occluder
                            const glm::vec3 x = L.point() ? p + t * glm::normalize(p - L.center()) : p - t * glm::vec3(L.light_position);
                            if (glm::any(glm::lessThan(x, scene.lo)) || glm::any(glm::greaterThan(x, scene.hi))) continue;
                            const glm::dvec4 h = glm::dmat4(sp.view_proj) * glm::dvec4(glm::dvec3(x), 1.0);
                            if (!(h.w > 0.0) || std::abs(h.x) > h.w || std::abs(h.y) > h.w) continue;
                            const double zn = h.z / h.w;
                            const double wz = cd == sk::ClipDepth::ZeroToOne ? zn : 0.5 * zn + 0.5;
                            if (wz < 0.0 || wz > 1.0) continue;  // beyond the near plane
                            ++tested;
                            const double px = (h.x / h.w * 0.5 + 0.5) * kW, py = (h.y / h.w * 0.5 + 0.5) * kH;
                            CHECK(px >= r.x - 1e-3);
                            CHECK(px <= r.x + r.width + 1e-3);
                            CHECK(py >= r.y - 1e-3);
                            CHECK(py <= r.y + r.height + 1e-3);
                            CHECK(wz >= double(r.depth_min) - 1e-6);
                            CHECK(wz <= double(r.depth_max) + 1e-6);
                        }
                        CHECK(tested > 100);
                    }
                    if (L.point()) {
                        sk::PenumbraSphereLight sl;
                        sl.light_position = L.light_position;
                        sl.radius = 0.05f;
                        const sk::PenumbraWedge w = sk::penumbra_wedge({1.2f, 2.2f, 1.2f}, {1.5f, 2.2f, 1.2f}, sl);
                        REQUIRE(w.status == sk::Status::Ok);
                        const sk::PenumbraWedgeHull hull = sk::penumbra_wedge_hull(w, std::numeric_limits<float>::infinity());
                        REQUIRE(hull.status == sk::Status::Ok);
                        const sk::ScissorRect r = sk::penumbra_wedge_scissor_in_box(hull, scene.lo, scene.hi, sp);
                        CHECK_MESSAGE(r.status == sk::Status::Ok, st(r.status));
                        CHECK(r.visible);
                    }
                }
            }
    CHECK(variants == 8);

    // ---- the silhouette (silhouette.hpp) as shadow_volume.hpp, penumbra_wedge.hpp and smoothie.hpp
    // read it, and a light frustum's matrix as smoothie.hpp and silhouette_map.hpp read it
    for (const bool rev : {false, true}) {
        const Camera cam = make_camera(rev ? sk::ClipDepth::ZeroToOne : sk::ClipDepth::NegativeOneToOne, rev, true);
        for (const Light& L : lights) {
            std::vector<std::uint32_t> keep(scene.caster_boxes.size() / 6);
            const sk::LightFrustumResult fit = sk::light_frustum_fit(light_frustum_input(scene, cam, L.light_position), keep.data(), keep.size());
            REQUIRE(fit.status == sk::Status::Ok);
            for (std::size_t m = 1; m < scene.meshes.size(); ++m) {
                INFO(cam.name, " / ", std::string(L.name), " / mesh ", m);
                const docs::Mesh& mesh = scene.meshes[m];
                const std::size_t n = mesh.positions.size();
                const sk::SilhouetteAdjacency adj =
                    sk::silhouette_build_adjacency(mesh.positions.data(), n, mesh.indices.data(), mesh.indices.size());
                REQUIRE(adj.status == sk::Status::Ok);
                CHECK(adj.closed() == (m != 4));  // the awning is open and non-manifold
                const sk::Silhouette sil = sk::silhouette_compute(adj, mesh.positions.data(), n, L.light_position);
                REQUIRE(sil.status == sk::Status::Ok);
                const std::size_t edges = sil.indices.size() / 2;
                REQUIRE(edges > 0);

                // shadow_volume.hpp: side quads + LitOnly caps form a closed, consistently oriented
                // volume (every directed edge has its reverse). For a sun all w = 0 vertices are the
                // one point (-L, 0) and the dark cap has zero area: indices >= n are that point.
                std::vector<std::uint32_t> ib(sk::volume_indices_capacity(sk::silhouette_indices_capacity(adj), adj.faces.size()));
                const sk::VolumeBuffer sides = sk::volume_build_side_quads(sil.indices.data(), sil.indices.size(), n, ib.data(), ib.size());
                REQUIRE(sides.status == sk::Status::Ok);
                CHECK(sides.count == 3 * sil.indices.size());
                const sk::VolumeBuffer caps =
                    sk::volume_build_caps(adj.faces.data(), adj.faces.size(), sil.facing.data(), sil.facing.size(), n,
                                          sk::VolumeCapMode::LitOnly, L.point(), ib.data() + sides.count, ib.size() - sides.count);
                REQUIRE(caps.status == sk::Status::Ok);
                std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
                for (std::size_t t = 0; t + 2 < sides.count + caps.count; t += 3) {
                    std::uint32_t v[3] = {ib[t], ib[t + 1], ib[t + 2]};
                    if (!L.point())
                        for (std::uint32_t& x : v) x = x >= n ? std::uint32_t(n) : x;
                    if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) continue;
                    for (int e = 0; e < 3; ++e) directed[{v[e], v[(e + 1) % 3]}] += 1;
                }
                bool closed = true;
                for (const auto& kv : directed) {
                    const auto rev_it = directed.find({kv.first.second, kv.first.first});
                    closed = closed && rev_it != directed.end() && rev_it->second == kv.second;
                }
                CHECK_MESSAGE(closed, "the volume of the silhouette is not closed");

                // the lit face of each silhouette edge: the one that runs u -> v (silhouette.hpp's order)
                auto third_of_lit_face = [&](std::uint32_t u, std::uint32_t v, glm::vec3& x) {
                    for (std::size_t f = 0; f < adj.face_count(); ++f) {
                        if (!sil.facing[f]) continue;
                        for (int e = 0; e < 3; ++e)
                            if (adj.faces[3 * f + std::size_t(e)] == u && adj.faces[3 * f + std::size_t((e + 1) % 3)] == v) {
                                x = mesh.positions[adj.faces[3 * f + std::size_t((e + 2) % 3)]];
                                return true;
                            }
                    }
                    return false;
                };
                // penumbra_wedge.hpp: the hard plane of every edge points out of the hard shadow (the
                // lit face lies inside it); radius 0 is the hard plane itself (inner_bound = -outer_bound = hard_plane); a sun is InvalidLight
                for (std::size_t e = 0; e < edges; ++e) {
                    const glm::vec3 e0 = mesh.positions[sil.indices[2 * e]], e1 = mesh.positions[sil.indices[2 * e + 1]];
                    sk::PenumbraSphereLight sl;
                    sl.light_position = L.light_position;
                    sl.radius = 0.05f;
                    const sk::PenumbraWedge w = sk::penumbra_wedge(e0, e1, sl);
                    if (!L.point()) {
                        CHECK(w.status == sk::Status::InvalidLight);
                        continue;
                    }
                    REQUIRE(w.status == sk::Status::Ok);
                    if (w.skip != sk::PenumbraWedgeSkip::None) continue;
                    glm::vec3 x(0.0f);
                    REQUIRE(third_of_lit_face(sil.indices[2 * e], sil.indices[2 * e + 1], x));
                    const float side = glm::dot(glm::vec3(w.hard_plane), x) + w.hard_plane.w;
                    CHECK_MESSAGE(side < 0.0f, "edge ", e, ": the lit face is outside the hard plane (", side, ")");
                    sl.radius = 0.0f;
                    const sk::PenumbraWedge w0 = sk::penumbra_wedge(e0, e1, sl);
                    REQUIRE(w0.status == sk::Status::Ok);
                    for (int k = 0; k < 4; ++k) {
                        CHECK(w0.inner_bound[k] == doctest::Approx(w0.hard_plane[k]).epsilon(1e-5));
                        CHECK(w0.outer_bound[k] == doctest::Approx(-w0.hard_plane[k]).epsilon(1e-5));
                    }
                }

                // smoothie.hpp with the light frustum's matrix: every edge gets its quad, on the outer
                // side (for the boxes: the outer vertices lie t outside the box's projected hull)
                const float t = 0.02f;
                sk::SmoothieEdges se;
                se.positions = mesh.positions.data();
                se.position_count = n;
                se.edges = sil.indices.data();
                se.edge_count = edges;
                sk::SmoothieParams params;
                params.t = t;
                params.clip_depth = cam.clip_depth;
                params.reversed_z = cam.reversed_z;
                std::vector<sk::SmoothieScratch> scratch(sk::smoothie_scratch_capacity(edges));
                std::vector<sk::SmoothieVertex> sv(sk::smoothie_vertex_capacity(edges));
                const sk::SmoothieResult sr = sk::smoothie_build(se, fit.view_proj, params, scratch.data(), scratch.size(), sv.data(), sv.size());
                REQUIRE_MESSAGE(sr.status == sk::Status::Ok, st(sr.status));
                CHECK(sr.edge_quads == edges);
                CHECK(sr.skipped_no_outward == 0);
                if (m != 4) {
                    std::vector<glm::dvec2> corners;
                    for (const glm::vec3& p : mesh.positions) corners.push_back(ndc_xy(fit.view_proj, p));
                    const std::vector<glm::dvec2> hull = convex_hull(corners);
                    for (std::size_t k = 0; k < 6 * sr.edge_quads; ++k)
                        if (sv[k].alpha == 1.0f)
                            CHECK_MESSAGE(hull_distance(hull, ndc_xy(fit.view_proj, sv[k].position)) > 0.99 * t,
                                          "smoothie vertex ", k, " is not outside the occluder");
                }
                // silhouette_map.hpp with the light frustum's matrix: every edge projected, none culled
                std::vector<sk::SilmapEdge> pe(edges);
                const sk::SilmapProjectResult pr = sk::silmap_project_edges(fit.view_proj, cam.clip_depth, {kMap, kMap},
                                                                            mesh.positions.data(), n, sil.indices.data(), edges,
                                                                            pe.data(), pe.size());
                REQUIRE_MESSAGE(pr.status == sk::Status::Ok, st(pr.status));
                CHECK(pr.count == edges);
                CHECK(pr.culled == 0);
                for (std::size_t e = 0; e < pr.count; ++e) {
                    const glm::dvec2 a = (ndc_xy(fit.view_proj, mesh.positions[sil.indices[2 * e]]) * 0.5 + 0.5) * double(kMap);
                    CHECK(std::abs(double(pe[e].a.x) - a.x) < 1e-2);
                    CHECK(std::abs(double(pe[e].a.y) - a.y) < 1e-2);
                    CHECK(pe[e].depth_a >= 0.0f);
                    CHECK(pe[e].depth_a <= 1.0f);
                }
            }
        }
    }

    // ---- light kinds a header cannot take are rejected with the documented status
    for (const Light& L : lights) {
        sk::OmniCubeInput oc;
        oc.light_position = L.light_position;
        CHECK(sk::omni_cube_matrices(oc).status == (L.point() ? sk::Status::Ok : sk::Status::InvalidLight));
        CHECK(sk::omni_paraboloid_frame(L.light_position, {0, 1, 0}, {0, 0, 1}).status ==
              (L.point() ? sk::Status::Ok : sk::Status::InvalidLight));
    }
}

// ================================================================================================
// The same light through every technique on the GPU, scored per camera pixel.
// ================================================================================================
namespace {

// ------------------------------------------------------------------------------------------ GL helpers

void u1f(GLuint p, const char* n, float v) { glUniform1f(glGetUniformLocation(p, n), v); }
void u1i(GLuint p, const char* n, int v) { glUniform1i(glGetUniformLocation(p, n), v); }
void u2f(GLuint p, const char* n, const glm::vec2& v) { glUniform2fv(glGetUniformLocation(p, n), 1, glm::value_ptr(v)); }
void u3f(GLuint p, const char* n, const glm::vec3& v) { glUniform3fv(glGetUniformLocation(p, n), 1, glm::value_ptr(v)); }
void u4f(GLuint p, const char* n, const glm::vec4& v) { glUniform4fv(glGetUniformLocation(p, n), 1, glm::value_ptr(v)); }
void um4(GLuint p, const char* n, const glm::mat4& m) {
    glUniformMatrix4fv(glGetUniformLocation(p, n), 1, GL_FALSE, glm::value_ptr(m));
}

// Every piece of state a pass may leave behind, back to GL's defaults (and the camera's target).
void reset_state() {
    glDisable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);
    glDisable(GL_STENCIL_TEST);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    glFrontFace(GL_CCW);
    glDisable(GL_POLYGON_OFFSET_FILL);
    glDisable(GL_DEPTH_CLAMP);
    glEnable(GL_DEPTH_TEST);
    glDepthMask(GL_TRUE);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glStencilMask(0xFF);
    for (GLuint unit = 0; unit < 4; ++unit) glBindSampler(unit, 0);
    glActiveTexture(GL_TEXTURE0);
}

GLuint texture_2d(GLenum format, int w, int h, GLenum filter) {
    GLuint t = 0;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    glTexStorage2D(GL_TEXTURE_2D, 1, format, w, h);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GLint(filter));
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GLint(filter));
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return t;
}

GLuint framebuffer(std::initializer_list<std::pair<GLenum, GLuint>> textures, GLuint depth_renderbuffer, GLenum depth_attachment) {
    GLuint f = 0;
    glGenFramebuffers(1, &f);
    glBindFramebuffer(GL_FRAMEBUFFER, f);
    std::vector<GLenum> draw;
    for (const auto& t : textures) {
        glFramebufferTexture2D(GL_FRAMEBUFFER, t.first, GL_TEXTURE_2D, t.second, 0);
        if (t.first != GL_DEPTH_ATTACHMENT) draw.push_back(t.first);
    }
    if (depth_renderbuffer != 0) glFramebufferRenderbuffer(GL_FRAMEBUFFER, depth_attachment, GL_RENDERBUFFER, depth_renderbuffer);
    if (draw.empty()) {
        glDrawBuffer(GL_NONE);
        glReadBuffer(GL_NONE);
    } else {
        glDrawBuffers(GLsizei(draw.size()), draw.data());
    }
    REQUIRE(glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE);
    return f;
}

// The scene as the user's renderer draws it: flat-shaded triangles (attribute 0 position, 1 normal),
// one range per mesh.
struct SceneGpu {
    GLuint vao = 0;
    std::vector<GLint> first;
    std::vector<GLsizei> count;
    GLsizei total = 0;
    void draw_all() const {
        glBindVertexArray(vao);
        glDrawArrays(GL_TRIANGLES, 0, total);
    }
    void draw(std::size_t mesh) const {
        glBindVertexArray(vao);
        glDrawArrays(GL_TRIANGLES, first[mesh], count[mesh]);
    }
};

SceneGpu upload(const Scene& s) {
    SceneGpu g;
    std::vector<glm::vec3> pos, nrm;
    for (const docs::Mesh& m : s.meshes) {
        g.first.push_back(GLint(pos.size()));
        for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
            const glm::vec3 a = m.positions[m.indices[t]], b = m.positions[m.indices[t + 1]], c = m.positions[m.indices[t + 2]];
            const glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
            for (const glm::vec3& p : {a, b, c}) {
                pos.push_back(p);
                nrm.push_back(n);
            }
        }
        g.count.push_back(GLsizei(pos.size()) - g.first.back());
    }
    g.total = GLsizei(pos.size());
    GLuint vbo[2] = {0, 0};
    glGenVertexArrays(1, &g.vao);
    glBindVertexArray(g.vao);
    glGenBuffers(2, vbo);
    for (GLuint k = 0; k < 2; ++k) {
        const std::vector<glm::vec3>& data = k == 0 ? pos : nrm;
        glBindBuffer(GL_ARRAY_BUFFER, vbo[k]);
        glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(data.size() * sizeof(glm::vec3)), data.data(), GL_STATIC_DRAW);
        glVertexAttribPointer(k, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
        glEnableVertexAttribArray(k);
    }
    glBindVertexArray(0);
    return g;
}

using docs::draw_vec4_triangles;

// ------------------------------------------------------------------------------------------ programs

const char* const kSceneVS = R"(
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
uniform mat4 u_view_proj;
out vec3 v_world;
out vec3 v_normal;
void main() { v_world = a_position; v_normal = a_normal; gl_Position = u_view_proj * vec4(a_position, 1.0); }
)";
const char* const kDepthVS = R"(
layout(location = 0) in vec3 a_position;
uniform mat4 u_light_view_proj;
out vec3 v_world;
void main() { v_world = a_position; gl_Position = u_light_view_proj * vec4(a_position, 1.0); }
)";

struct Programs {
    GLuint gbuffer = 0, flat = 0, depth = 0, lf = 0, warp = 0, tsm_depth = 0, cascade = 0, volume = 0, omni_depth = 0,
           omni = 0, wedge_count = 0, wedge = 0, wedge_combine = 0, smoothie_map = 0, smoothie = 0, smoothie_lookup = 0,
           pcss = 0, pcss_directional = 0;
};

// The programs of the docs pages; SK_REVERSED_Z before the snippets that read it (reversed mode).
Programs make_programs(bool rev) {
    const std::string v = "#version 450 core\n";
    const std::string h = rev ? v + "#define SK_REVERSED_Z\n" : v;
    const std::string fs_in = "in vec3 v_world;\nin vec3 v_normal;\nlayout(location = 0) out vec4 o_color;\n";
    Programs p;
    p.gbuffer = docs::gl_program(v + kSceneVS, v + R"(
in vec3 v_world;
in vec3 v_normal;
layout(location = 0) out vec4 o_position;
layout(location = 1) out vec4 o_normal;
void main() { o_position = vec4(v_world, 1.0); o_normal = vec4(normalize(v_normal), 1.0); })");
    p.flat = docs::gl_program(v + kSceneVS, v + "uniform float u_value;\nlayout(location = 0) out vec4 o_color;\nvoid main() { o_color = vec4(u_value); }\n");
    p.depth = docs::gl_program(v + kDepthVS, v + "void main() {}\n");
    // light_frustum.hpp + shadow_map.glsl: one texel of normal offset and a few float steps (docs/shadow_map.md)
    p.lf = docs::gl_program(v + kSceneVS, h + docs::snippet("shadow_map") + fs_in + R"(
uniform sampler2DShadow u_shadow_map;
uniform mat4 u_light_view_proj;
uniform float u_texel_scale;  // world size of a texel at clip w = 1
uniform float u_bias;         // window depth
uniform bool u_zero_to_one;
void main() {
    vec3 n = normalize(v_normal);
    float texel = u_texel_scale * sk_shadow_coord(u_light_view_proj, v_world, u_zero_to_one).w;
    vec3 p = v_world + n * texel;
    o_color = vec4(sk_shadow_map_visibility(u_shadow_map, u_light_view_proj, p, u_zero_to_one, u_bias, 1.0));
})");
    // perspective_shadow_maps.hpp + perspective_shadow_maps.glsl (docs/perspective_shadow_maps.md)
    p.warp = docs::gl_program(v + kSceneVS, v + docs::snippet("perspective_shadow_maps") + fs_in + R"(
uniform sampler2DShadow u_shadow_map;
uniform mat4 u_warp;
uniform mat4 u_depth_proj;
uniform bool u_zero_to_one;
void main() { o_color = vec4(sk_warp_shadow(u_shadow_map, u_warp, u_depth_proj, v_world, 0.0, u_zero_to_one)); })");
    p.tsm_depth = docs::gl_program(v + R"(
layout(location = 0) in vec3 a_position;
uniform mat4 u_light_view_proj;
uniform mat4 u_depth_proj;
out vec4 v_depth_clip;
void main() { gl_Position = u_light_view_proj * vec4(a_position, 1.0); v_depth_clip = u_depth_proj * vec4(a_position, 1.0); })",
                                   v + docs::snippet("perspective_shadow_maps") + R"(
in vec4 v_depth_clip;
uniform float u_slope;
uniform bool u_zero_to_one;
void main() { gl_FragDepth = sk_warp_map_depth(v_depth_clip, u_slope, 0.0, u_zero_to_one); })");
    // cascades.hpp + cascades.glsl (docs/cascades.md)
    p.cascade = docs::gl_program(v + kSceneVS, v + docs::snippet("cascades") + fs_in + R"(
uniform sampler2DArrayShadow u_cascades;
uniform mat4 u_cascade_vp[4];
uniform vec4 u_split_near;
uniform vec4 u_split_far;
uniform mat4 u_camera_view;
uniform float u_bias;
uniform bool u_zero_to_one;
uniform float u_texel[4];       // Cascade::texel_world_size
uniform float u_normal_offset;  // texels (0: the page's constant bias alone)
void main() {
    float view_depth = -(u_camera_view * vec4(v_world, 1.0)).z;
    // one texel of the cascade that serves the point (the next one's inside the blend band) along the
    // normal, as docs/shadow_map.md offsets a plain map
    int i = sk_cascade_by_depth(view_depth, u_split_far, 4);
    bool band = i >= 0 && i + 1 < 4 && sk_cascade_blend(view_depth, u_split_near[i], u_split_far[i], 0.1) > 0.0;
    float texel = i < 0 ? 0.0 : u_texel[band ? i + 1 : i];
    vec3 p = v_world + normalize(v_normal) * (u_normal_offset * texel);
    o_color = vec4(sk_cascade_shadow(u_cascades, u_cascade_vp, u_split_near, u_split_far, 4, p, view_depth, 0.1,
                                     u_bias, u_zero_to_one));
})");
    // silhouette.hpp + shadow_volume.hpp + shadow_volume.glsl (docs/shadow_volume.md)
    p.volume = docs::gl_program(v + docs::snippet("shadow_volume") + R"(
layout(location = 0) in vec4 a_position;
uniform mat4 u_view_proj;
uniform vec4 u_light_position;
void main() { gl_Position = u_view_proj * sk_extrude_shadow_volume(a_position, u_light_position); })",
                                v + "void main() {}\n");
    // omni_shadow.hpp + omni_shadow.glsl (docs/omni_shadow.md)
    p.omni_depth = docs::gl_program(v + kDepthVS, v + docs::snippet("omni_shadow") + R"(
in vec3 v_world;
uniform vec4 u_light_position;
uniform float u_range;
void main() { gl_FragDepth = sk_omni_linear_depth(v_world, u_light_position, u_range); })");
    p.omni = docs::gl_program(v + kSceneVS, v + docs::snippet("omni_shadow") + fs_in + R"(
uniform samplerCubeShadow u_cube;
uniform vec4 u_light_position;
uniform float u_range;
uniform float u_size;
void main() {
    vec3 L = sk_omni_light_point(u_light_position) - v_world;
    float d = length(L);
    float b = sk_omni_bias(d, dot(normalize(v_normal), L / d), sk_omni_cube_texel_angle(u_size), 1.4143, 1.4835,
                           vec2(0.0, 2.4e-7));
    o_color = vec4(sk_cube_visibility_distance(u_cube, u_light_position, v_world, u_range, b));
})");
    // penumbra_wedge.hpp + penumbra_wedge.glsl (docs/penumbra_wedge.md)
    const std::string wedge = docs::snippet("penumbra_wedge");
    const std::string hull_vs = v + R"(
layout(location = 0) in vec4 a_position;
uniform mat4 u_view_proj;
void main() { gl_Position = u_view_proj * a_position; })";
    p.wedge_count = docs::gl_program(hull_vs, v + R"(
layout(location = 0) out float o_count;
void main() { o_count = gl_FrontFacing ? 1.0 : -1.0; })");
    p.wedge = docs::gl_program(hull_vs, v + wedge + R"(
layout(binding = 0) uniform sampler2D u_position;
uniform vec4 u_outer_bound, u_inner_bound, u_side0, u_side1;
uniform vec3 u_e0, u_e1;
uniform vec4 u_light_position;
uniform float u_light_radius;
layout(location = 0) out float o_coverage;
void main() {
    vec4 p = texelFetch(u_position, ivec2(gl_FragCoord.xy), 0);
    if (p.w == 0.0) discard;
    if (!sk_wedge_inside4(vec4(p.xyz, 1.0), u_outer_bound, u_inner_bound, u_side0, u_side1)) discard;
    o_coverage = sk_wedge_edge_coverage(u_e0, u_e1, u_light_position, u_light_radius, p.xyz);
})");
    p.wedge_combine = docs::gl_program(v + "void main() { gl_Position = vec4(vec2(gl_VertexID & 1, gl_VertexID >> 1) * 4.0 - 1.0, 0.0, 1.0); }\n",
                                       v + wedge + R"(
layout(binding = 0) uniform sampler2D u_accumulated;
layout(location = 0) out float o_visibility;
void main() { o_visibility = sk_wedge_visibility(texelFetch(u_accumulated, ivec2(gl_FragCoord.xy), 0).r, 0.0); })");
    // smoothie.hpp + smoothie.glsl (docs/smoothie.md)
    const std::string smoothie = docs::snippet("smoothie");
    p.smoothie_map = docs::gl_program(v + kDepthVS, v + smoothie + R"(
in vec3 v_world;
uniform mat4 u_light_view;
layout(location = 0) out float o_depth;
void main() { o_depth = sk_smoothie_linear_depth(u_light_view, v_world); })");
    p.smoothie = docs::gl_program(v + smoothie + R"(
layout(location = 0) in vec3 a_position;
layout(location = 1) in float a_alpha;
layout(location = 2) in vec3 a_silhouette;
layout(location = 3) in float a_inv_t;
layout(location = 5) in float a_corner;
uniform mat4 u_light_view_proj;
uniform mat4 u_light_view;
noperspective out float v_alpha;
smooth out float v_depth;
flat out vec2 v_silhouette;
flat out float v_inv_t;
flat out float v_corner;
void main() {
    vec4 clip;
    sk_smoothie_vertex(u_light_view_proj, u_light_view, a_position, a_silhouette, clip, v_depth, v_silhouette);
    gl_Position = clip;
    v_alpha = a_alpha;
    v_inv_t = a_inv_t;
    v_corner = a_corner;
})",
                                  v + smoothie + R"(
noperspective in float v_alpha;
smooth in float v_depth;
flat in vec2 v_silhouette;
flat in float v_inv_t;
flat in float v_corner;
uniform sampler2D u_shadow_map;
uniform vec2 u_size;
layout(location = 0) out vec2 o_smoothie;
void main() {
    if (sk_smoothie_hidden(u_shadow_map, gl_FragCoord.xy, v_depth, 2e-3 * v_depth)) discard;
    o_smoothie = sk_smoothie_fragment(gl_FragCoord.xy, u_size, v_alpha, v_silhouette, v_inv_t, v_corner, v_depth);
})");
    p.smoothie_lookup = docs::gl_program(v + kSceneVS, v + smoothie + fs_in + R"(
uniform sampler2D u_shadow_map;
uniform sampler2D u_smoothie_map;
uniform mat4 u_light_view_proj;
uniform mat4 u_light_view;
void main() {
    vec4 c = u_light_view_proj * vec4(v_world, 1.0);
    vec2 uv = c.xy / c.w * 0.5 + 0.5;
    float r = sk_smoothie_linear_depth(u_light_view, v_world);
    vec2 dr_duv = sk_smoothie_depth_gradient(dFdx(uv), dFdy(uv), dFdx(r), dFdy(r));
    o_color = vec4(sk_smoothie_visibility(u_shadow_map, u_smoothie_map, uv, r, dr_duv, 1e-3 * r, false));
})");
    // pcss.hpp + pcss.glsl (docs/pcss.md); the bias sign follows the depth direction
    const std::string pcss_head = h + docs::snippet("shadow_map") + docs::snippet("pcf") + docs::snippet("pcss") + fs_in + R"(
uniform sampler2D u_depth_map;
uniform sampler2DShadow u_shadow_map;
uniform mat4 u_light_view_proj;
uniform float u_light_uv;      // pcss_light_uv_at_near (perspective) / light_uv_per_depth (directional)
uniform float u_near;
uniform float u_far;
uniform float u_texel_uv;
uniform bool u_zero_to_one;
vec3 biased_coord(out vec2 g) {
    vec3 uvz = sk_shadow_coord(u_light_view_proj, v_world, u_zero_to_one).xyz;
    g = sk_receiver_plane_depth_bias(uvz);
#ifdef SK_REVERSED_Z
    uvz.z += 1.5 * u_texel_uv * (abs(g.x) + abs(g.y)) + 2e-6;
#else
    uvz.z -= 1.5 * u_texel_uv * (abs(g.x) + abs(g.y)) + 2e-6;
#endif
    return uvz;
}
)";
    p.pcss = docs::gl_program(v + kSceneVS, pcss_head + R"(
void main() {
    vec2 g;
    vec3 uvz = biased_coord(g);
    float angle = 6.2831853 * sk_interleaved_gradient_noise(gl_FragCoord.xy);
    o_color = vec4(sk_pcss(u_depth_map, u_shadow_map, uvz, g, u_light_uv, u_near, u_far, 32, 32, angle, 0.08));
})");
    p.pcss_directional = docs::gl_program(v + kSceneVS, pcss_head + R"(
void main() {
    vec2 g;
    vec3 uvz = biased_coord(g);
    float angle = 6.2831853 * sk_interleaved_gradient_noise(gl_FragCoord.xy);
    o_color = vec4(sk_pcss_directional(u_depth_map, u_shadow_map, uvz, g, u_light_uv, 32, 32, angle, 0.08));
})");
    return p;
}

// ------------------------------------------------------------------------------------------ GL scene state

// One occluder of the stencil volumes: once per mesh the adjacency, planes and buffers (docs/shadow_volume.md).
struct VolumeMesh {
    const docs::Mesh* mesh = nullptr;
    sk::SilhouetteAdjacency adj;
    sk::SilhouettePlanes planes;
    glm::vec3 lo{0.0f}, hi{0.0f};
    std::vector<std::uint8_t> lit;
    std::vector<std::uint32_t> silhouette;
    std::vector<std::uint32_t> indices;
    GLuint vao = 0, vbo = 0, ibo = 0;
    bool zfail = false;
    std::size_t side_count = 0, cap_count = 0;
    sk::ScissorRect scissor;
};

struct Gpu {
    SceneGpu scene;
    std::vector<VolumeMesh> volumes;
    GLuint ds = 0;                                        // the camera's depth + stencil (every camera pass)
    GLuint gpos = 0, gnrm = 0, gfbo = 0;                  // G-buffer
    GLuint vtex = 0, vfbo = 0;                            // visibility V
    GLuint acc = 0, accfbo = 0;                           // wedge accumulation
    GLuint map2d = 0, map2d_fbo = 0;                      // light frustum, warps, PCSS
    GLuint cascades = 0, cascade_fbo[4] = {0, 0, 0, 0};   // 4 layers
    GLuint cube = 0, cube_fbo = 0;                        // omni
    GLuint sm_linear = 0, sm_depth = 0, sm_fbo = 0;       // smoothie linear map
    GLuint sm_buffer = 0, sm_buffer_fbo = 0;              // smoothie buffer
    GLuint sm_vao = 0, sm_vbo = 0;
    GLuint pcss_raw = 0, pcss_compare = 0;                // PCSS sampler objects
    bool has_depth_bounds = false;
};

void make_gpu(Gpu& g, const Scene& s) {
    g.scene = upload(s);
    glGenRenderbuffers(1, &g.ds);
    glBindRenderbuffer(GL_RENDERBUFFER, g.ds);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH32F_STENCIL8, kW, kH);
    g.gpos = texture_2d(GL_RGBA32F, kW, kH, GL_NEAREST);
    g.gnrm = texture_2d(GL_RGBA32F, kW, kH, GL_NEAREST);
    g.gfbo = framebuffer({{GL_COLOR_ATTACHMENT0, g.gpos}, {GL_COLOR_ATTACHMENT1, g.gnrm}}, g.ds, GL_DEPTH_STENCIL_ATTACHMENT);
    g.vtex = texture_2d(GL_R32F, kW, kH, GL_NEAREST);
    g.vfbo = framebuffer({{GL_COLOR_ATTACHMENT0, g.vtex}}, g.ds, GL_DEPTH_STENCIL_ATTACHMENT);
    g.acc = texture_2d(GL_R32F, kW, kH, GL_NEAREST);
    g.accfbo = framebuffer({{GL_COLOR_ATTACHMENT0, g.acc}}, g.ds, GL_DEPTH_STENCIL_ATTACHMENT);
    // a depth texture compared in hardware (GL_LINEAR: 2x2 PCF); the compare function per mode
    g.map2d = texture_2d(GL_DEPTH_COMPONENT32F, kMap, kMap, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    g.map2d_fbo = framebuffer({{GL_DEPTH_ATTACHMENT, g.map2d}}, 0, GL_NONE);
    glGenTextures(1, &g.cascades);
    glBindTexture(GL_TEXTURE_2D_ARRAY, g.cascades);
    glTexStorage3D(GL_TEXTURE_2D_ARRAY, 1, GL_DEPTH_COMPONENT32F, kMap, kMap, 4);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glGenFramebuffers(4, g.cascade_fbo);
    for (int i = 0; i < 4; ++i) {
        glBindFramebuffer(GL_FRAMEBUFFER, g.cascade_fbo[i]);
        glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, g.cascades, 0, i);
        glDrawBuffer(GL_NONE);
        glReadBuffer(GL_NONE);
    }
    glGenTextures(1, &g.cube);
    glBindTexture(GL_TEXTURE_CUBE_MAP, g.cube);
    glTexStorage2D(GL_TEXTURE_CUBE_MAP, 1, GL_DEPTH_COMPONENT32F, kMap, kMap);
    glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);  // linear distance storage
    glEnable(GL_TEXTURE_CUBE_MAP_SEAMLESS);
    glGenFramebuffers(1, &g.cube_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, g.cube_fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_CUBE_MAP_POSITIVE_X, g.cube, 0);
    glDrawBuffer(GL_NONE);
    glReadBuffer(GL_NONE);
    g.sm_linear = texture_2d(GL_R32F, kMap, kMap, GL_NEAREST);
    glGenRenderbuffers(1, &g.sm_depth);
    glBindRenderbuffer(GL_RENDERBUFFER, g.sm_depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, kMap, kMap);
    g.sm_fbo = framebuffer({{GL_COLOR_ATTACHMENT0, g.sm_linear}}, g.sm_depth, GL_DEPTH_ATTACHMENT);
    g.sm_buffer = texture_2d(GL_RG32F, kMap, kMap, GL_NEAREST);
    g.sm_buffer_fbo = framebuffer({{GL_COLOR_ATTACHMENT0, g.sm_buffer}}, 0, GL_NONE);
    glGenVertexArrays(1, &g.sm_vao);
    glGenBuffers(1, &g.sm_vbo);
    glBindVertexArray(g.sm_vao);
    glBindBuffer(GL_ARRAY_BUFFER, g.sm_vbo);
    const GLsizei stride = sizeof(sk::SmoothieVertex);
    const GLint sizes[6] = {3, 1, 3, 1, 2, 1};
    std::size_t offset = 0;
    for (GLuint a = 0; a < 6; ++a) {
        glEnableVertexAttribArray(a);
        glVertexAttribPointer(a, sizes[a], GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(offset));
        offset += std::size_t(sizes[a]) * sizeof(float);
    }
    glBindVertexArray(0);
    glGenSamplers(1, &g.pcss_raw);
    glGenSamplers(1, &g.pcss_compare);
    g.has_depth_bounds = epoxy_has_gl_extension("GL_EXT_depth_bounds_test");

    // the stencil volumes' occluders, once per mesh (docs/shadow_volume.md "Once per mesh")
    g.volumes.resize(s.meshes.size() - 1);
    for (std::size_t k = 0; k < g.volumes.size(); ++k) {
        VolumeMesh& v = g.volumes[k];
        v.mesh = &s.meshes[k + 1];
        const std::vector<glm::vec3>& p = v.mesh->positions;
        const std::vector<std::uint32_t>& t = v.mesh->indices;
        v.adj = sk::silhouette_build_adjacency(p.data(), p.size(), t.data(), t.size());
        v.planes = sk::silhouette_build_planes(v.adj, p.data(), p.size());
        std::vector<glm::vec4> vertices(2 * p.size());
        const sk::VolumeBuffer vb = sk::volume_build_vertices(p.data(), p.size(), vertices.data(), vertices.size());
        REQUIRE(v.adj.status == sk::Status::Ok);
        REQUIRE(v.planes.status == sk::Status::Ok);
        REQUIRE(vb.status == sk::Status::Ok);
        bounds(*v.mesh, v.lo, v.hi);
        v.lit.resize(v.adj.face_count());
        v.silhouette.resize(sk::silhouette_indices_capacity(v.adj));
        v.indices.resize(sk::volume_indices_capacity(v.silhouette.size(), v.adj.faces.size()));
        glGenVertexArrays(1, &v.vao);
        glBindVertexArray(v.vao);
        glGenBuffers(1, &v.vbo);
        glBindBuffer(GL_ARRAY_BUFFER, v.vbo);
        glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertices.size() * sizeof(glm::vec4)), vertices.data(), GL_STATIC_DRAW);
        glEnableVertexAttribArray(0);
        glVertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, sizeof(glm::vec4), nullptr);
        glGenBuffers(1, &v.ibo);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, v.ibo);
        glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(v.indices.size() * 4), nullptr, GL_DYNAMIC_DRAW);
        glBindVertexArray(0);
    }
}

// ------------------------------------------------------------------------------------------ one frame

// What every technique shares in one (camera, light) frame.
struct Frame {
    const Scene* scene = nullptr;
    Gpu* gpu = nullptr;
    const Programs* prog = nullptr;
    Camera cam;
    Light light;
    bool rev = false;
    GLenum less() const { return rev ? GL_GREATER : GL_LESS; }
    GLenum compare() const { return rev ? GL_GEQUAL : GL_LEQUAL; }
    double far_depth() const { return rev ? 0.0 : 1.0; }
    sk::ClipDepth cd() const { return cam.clip_depth; }
    bool zo() const { return cam.clip_depth == sk::ClipDepth::ZeroToOne; }
    glm::mat4 view_proj() const { return cam.proj * cam.view; }
};

// A technique's visibility per camera pixel, or the status with which its header refused the light.
struct Outcome {
    sk::Status status = sk::Status::NotRun;
    std::vector<float> v;
    std::string note;
};

std::vector<float> read_visibility(const Gpu& g) {
    std::vector<float> v(std::size_t(kW) * std::size_t(kH));
    glBindFramebuffer(GL_READ_FRAMEBUFFER, g.vfbo);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glReadPixels(0, 0, kW, kH, GL_RED, GL_FLOAT, v.data());
    return v;
}

// The camera's lighting pass of a map technique: the scene, back faces culled, V into the target.
void begin_camera_pass(const Frame& f, GLuint program) {
    reset_state();
    glBindFramebuffer(GL_FRAMEBUFFER, f.gpu->vfbo);
    glViewport(0, 0, kW, kH);
    const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    glClearBufferfv(GL_COLOR, 0, zero);
    glClearDepth(f.far_depth());
    glClear(GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
    glDepthFunc(f.less());
    glEnable(GL_CULL_FACE);
    glUseProgram(program);
    um4(program, "u_view_proj", f.view_proj());
}

// A light pass into a depth target of kMap^2.
void begin_light_pass(const Frame& f, GLuint fbo, GLuint program, const glm::mat4& light_view_proj) {
    reset_state();
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, kMap, kMap);
    glClearDepth(f.far_depth());
    glClear(GL_DEPTH_BUFFER_BIT);
    glDepthFunc(f.less());
    glUseProgram(program);
    um4(program, "u_light_view_proj", light_view_proj);
}

// ---- light_frustum.hpp + shadow_map.glsl
Outcome run_light_frustum(const Frame& f) {
    Outcome o;
    const sk::LightFrustumInput in = light_frustum_input(*f.scene, f.cam, f.light.light_position);
    std::vector<std::uint32_t> keep(in.caster_count);
    const sk::LightFrustumResult fit = sk::light_frustum_fit(in, keep.data(), keep.size());
    o.status = fit.status;
    if (fit.status != sk::Status::Ok) return o;
    REQUIRE(fit.visible);
    glBindTexture(GL_TEXTURE_2D, f.gpu->map2d);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GLint(f.compare()));
    begin_light_pass(f, f.gpu->map2d_fbo, f.prog->depth, fit.view_proj);
    for (std::size_t k = 0; k < fit.count; ++k) f.gpu->scene.draw(keep[k]);  // only the kept casters
    char note[64];
    std::snprintf(note, sizeof note, "%zu of %zu casters kept", fit.count, in.caster_count);
    o.note = note;
    // one texel of normal offset: the texel's world size at clip w = 1 from the fitted projection
    const float texel_scale = 2.0f / (std::min(std::abs(fit.proj[0][0]), std::abs(fit.proj[1][1])) * float(kMap));
    begin_camera_pass(f, f.prog->lf);
    glBindTexture(GL_TEXTURE_2D, f.gpu->map2d);
    um4(f.prog->lf, "u_light_view_proj", fit.view_proj);
    u1f(f.prog->lf, "u_texel_scale", texel_scale);
    u1f(f.prog->lf, "u_bias", 8.0f * float(sk::bias_depth_format_step(sk::DepthFormat::Float32, 0.999).value));
    u1i(f.prog->lf, "u_zero_to_one", f.zo());
    f.gpu->scene.draw_all();
    o.v = read_visibility(*f.gpu);
    return o;
}

// ---- perspective_shadow_maps.hpp + perspective_shadow_maps.glsl
Outcome run_warp(const Frame& f, sk::WarpMethod method) {
    Outcome o;
    const sk::WarpResult w = sk::warp_matrix(warp_input(*f.scene, f.cam, f.light.light_position), method);
    o.status = w.status;
    if (w.status != sk::Status::Ok) return o;
    REQUIRE(w.visible);
    if (w.fallback_uniform) o.note = "uniform fallback";
    glBindTexture(GL_TEXTURE_2D, f.gpu->map2d);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GLint(f.compare()));
    const GLuint prog = w.separate_depth ? f.prog->tsm_depth : f.prog->depth;
    begin_light_pass(f, f.gpu->map2d_fbo, prog, w.light_view_proj);
    glFrontFace(GL_CCW);  // every method keeps the winding
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    const float sign = f.rev ? -1.0f : 1.0f;  // offsets toward the far plane
    if (w.separate_depth) {
        um4(prog, "u_depth_proj", w.depth_view_proj);
        u1f(prog, "u_slope", 2.0f * sign);
        u1i(prog, "u_zero_to_one", f.zo());
    } else {
        glEnable(GL_POLYGON_OFFSET_FILL);
        glPolygonOffset(2.0f * sign, 2.0f * sign);
    }
    f.gpu->scene.draw_all();
    begin_camera_pass(f, f.prog->warp);
    glBindTexture(GL_TEXTURE_2D, f.gpu->map2d);
    um4(f.prog->warp, "u_warp", w.light_view_proj);
    um4(f.prog->warp, "u_depth_proj", w.depth_view_proj);
    u1i(f.prog->warp, "u_zero_to_one", f.zo());
    f.gpu->scene.draw_all();
    o.v = read_visibility(*f.gpu);
    return o;
}

// ---- cascades.hpp + cascades.glsl
Outcome run_cascades(const Frame& f, float normal_offset) {
    Outcome o;
    sk::Cascade cascades[4];
    const sk::CascadeFitResult fit = sk::cascade_fit(cascade_input(*f.scene, f.cam, f.light.light_position), 0.75f, 4, cascades, 4);
    o.status = fit.status;
    if (fit.status != sk::Status::Ok) return o;
    glBindTexture(GL_TEXTURE_2D_ARRAY, f.gpu->cascades);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_COMPARE_FUNC, GLint(f.compare()));
    for (int i = 0; i < 4; ++i) {
        begin_light_pass(f, f.gpu->cascade_fbo[i], f.prog->depth, cascades[i].view_proj);
        f.gpu->scene.draw_all();
    }
    begin_camera_pass(f, f.prog->cascade);
    glBindTexture(GL_TEXTURE_2D_ARRAY, f.gpu->cascades);
    glm::mat4 vps[4];
    for (int i = 0; i < 4; ++i) vps[i] = cascades[i].view_proj;
    glUniformMatrix4fv(glGetUniformLocation(f.prog->cascade, "u_cascade_vp"), 4, GL_FALSE, glm::value_ptr(vps[0]));
    u4f(f.prog->cascade, "u_split_near", glm::vec4(fit.splits[0], fit.splits[1], fit.splits[2], fit.splits[3]));
    u4f(f.prog->cascade, "u_split_far", glm::vec4(fit.splits[1], fit.splits[2], fit.splits[3], fit.splits[4]));
    um4(f.prog->cascade, "u_camera_view", f.cam.view);
    u1f(f.prog->cascade, "u_bias", f.rev ? -0.0005f : 0.0005f);
    u1i(f.prog->cascade, "u_zero_to_one", f.zo());
    const float texel[4] = {cascades[0].texel_world_size, cascades[1].texel_world_size, cascades[2].texel_world_size,
                            cascades[3].texel_world_size};
    glUniform1fv(glGetUniformLocation(f.prog->cascade, "u_texel"), 4, texel);
    u1f(f.prog->cascade, "u_normal_offset", normal_offset);
    f.gpu->scene.draw_all();
    o.v = read_visibility(*f.gpu);
    return o;
}

// ---- silhouette.hpp + shadow_volume.hpp + shadow_volume.glsl: the whole frame of docs/shadow_volume.md
Outcome run_stencil_volumes(const Frame& f) {
    Outcome o;
    Gpu& g = *f.gpu;
    const glm::vec4 L = f.light.light_position;
    // per frame: the near rectangle of the infinite projection, facing, silhouette, method, quads, caps, scissor
    const sk::VolumeNearRect near_rect = sk::volume_near_plane_rect_from_inverse(glm::inverse(f.view_proj()), f.cd(), f.rev);
    REQUIRE(near_rect.status == sk::Status::Ok);
    const sk::ScissorParams sp = scissor_params(f.cam);
    int zfail = 0;
    for (VolumeMesh& v : g.volumes) {
        const std::vector<glm::vec3>& p = v.mesh->positions;
        const sk::SilhouetteFacing facing = sk::silhouette_compute_facing_planes(v.adj, v.planes, L, v.lit.data(), v.lit.size());
        const sk::SilhouetteResult sil = sk::silhouette_extract_planes(v.adj, v.planes, v.lit.data(), v.lit.size(),
                                                                       v.silhouette.data(), v.silhouette.size(), nullptr, 0);
        const sk::VolumeMethod method = sk::volume_choose_stencil_method_box(near_rect, L, v.lo, v.hi, 1e-4f);
        v.zfail = method.method == sk::VolumeStencilMethod::ZFail;
        zfail += v.zfail ? 1 : 0;
        const sk::VolumeBuffer sides = sk::volume_build_side_quads(v.silhouette.data(), sil.count, p.size(), v.indices.data(), v.indices.size());
        sk::VolumeBuffer caps;
        caps.status = sk::Status::Ok;
        if (v.zfail)
            caps = sk::volume_build_caps(v.adj.faces.data(), v.adj.faces.size(), v.lit.data(), v.lit.size(), p.size(),
                                         sk::VolumeCapMode::LitOnly, L.w != 0.0f, v.indices.data() + sides.count,
                                         v.indices.size() - sides.count);
        v.scissor = sk::volume_scissor(L, v.lo, v.hi, f.scene->lo, f.scene->hi, sp);
        for (const sk::Status s : {facing.status, sil.status, method.status, sides.status, caps.status, v.scissor.status})
            if (s != sk::Status::Ok) {
                o.status = s;
                return o;
            }
        v.side_count = sides.count;
        v.cap_count = caps.count;
        glNamedBufferSubData(v.ibo, 0, GLsizeiptr((sides.count + caps.count) * 4), v.indices.data());
    }
    o.status = sk::Status::Ok;
    o.note = std::to_string(zfail) + " z-fail";
    // 1. depth pre-pass (V = 0: the ambient), 2. stencil clear
    begin_camera_pass(f, f.prog->flat);
    u1f(f.prog->flat, "u_value", 0.0f);
    g.scene.draw_all();
    glStencilMask(0xFF);
    glClearStencil(0);
    glClear(GL_STENCIL_BUFFER_BIT);
    // 3. the volume pass
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glDepthMask(GL_FALSE);
    glDepthFunc(f.less());
    glDisable(GL_CULL_FACE);
    glEnable(GL_DEPTH_CLAMP);
    glEnable(GL_STENCIL_TEST);
    glStencilFunc(GL_ALWAYS, 0, 0xFF);
    glUseProgram(f.prog->volume);
    um4(f.prog->volume, "u_view_proj", f.view_proj());
    u4f(f.prog->volume, "u_light_position", L);
    for (const VolumeMesh& v : g.volumes) {
        if (!v.scissor.visible) continue;
        glEnable(GL_SCISSOR_TEST);
        glScissor(v.scissor.x, v.scissor.y, v.scissor.width, v.scissor.height);
        if (g.has_depth_bounds) {
            glEnable(GL_DEPTH_BOUNDS_TEST_EXT);
            glDepthBoundsEXT(v.scissor.depth_min, v.scissor.depth_max);
        }
        if (v.zfail) {
            glStencilOpSeparate(GL_BACK, GL_KEEP, GL_INCR_WRAP, GL_KEEP);
            glStencilOpSeparate(GL_FRONT, GL_KEEP, GL_DECR_WRAP, GL_KEEP);
        } else {
            glStencilOpSeparate(GL_FRONT, GL_KEEP, GL_KEEP, GL_INCR_WRAP);
            glStencilOpSeparate(GL_BACK, GL_KEEP, GL_KEEP, GL_DECR_WRAP);
        }
        glBindVertexArray(v.vao);
        glDrawElements(GL_TRIANGLES, GLsizei(v.side_count), GL_UNSIGNED_INT, nullptr);
        if (v.cap_count > 0) {
            glEnable(GL_POLYGON_OFFSET_FILL);
            glPolygonOffset(0.0f, f.rev ? -8.0f : 8.0f);  // the light cap fails the depth test on its own surface
            glDrawElements(GL_TRIANGLES, GLsizei(v.cap_count), GL_UNSIGNED_INT, reinterpret_cast<const void*>(v.side_count * 4));
            glDisable(GL_POLYGON_OFFSET_FILL);
        }
        glBindVertexArray(0);
    }
    glDisable(GL_DEPTH_CLAMP);
    // 4. the lighting pass: scissor and depth bounds off first
    glDisable(GL_SCISSOR_TEST);
    if (g.has_depth_bounds) glDisable(GL_DEPTH_BOUNDS_TEST_EXT);
    glStencilFunc(GL_EQUAL, 0, 0xFF);
    glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthFunc(GL_EQUAL);
    glEnable(GL_CULL_FACE);
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE);
    glUseProgram(f.prog->flat);
    u1f(f.prog->flat, "u_value", 1.0f);
    g.scene.draw_all();
    o.v = read_visibility(g);
    return o;
}

// ---- omni_shadow.hpp + omni_shadow.glsl
Outcome run_omni(const Frame& f) {
    Outcome o;
    Gpu& g = *f.gpu;
    sk::OmniCubeInput in;
    in.light_position = f.light.light_position;
    in.near_z = 0.05f;
    in.far_z = 2.0f * glm::length(f.scene->hi - f.scene->lo);
    in.clip_depth = f.cd();
    in.reversed_z = f.rev;
    const sk::OmniCubeMatrices cube = sk::omni_cube_matrices(in);
    o.status = cube.status;
    if (cube.status != sk::Status::Ok) return o;
    for (int face = 0; face < 6; ++face) {
        glBindFramebuffer(GL_FRAMEBUFFER, g.cube_fbo);  // face f into GL_TEXTURE_CUBE_MAP_POSITIVE_X + f
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_CUBE_MAP_POSITIVE_X + GLenum(face), g.cube, 0);
        begin_light_pass(f, g.cube_fbo, f.prog->omni_depth, cube.view_proj[face]);
        glClearDepth(1.0);  // the stored value is the linear distance / range: GL_LESS whatever the matrix's depth
        glClear(GL_DEPTH_BUFFER_BIT);
        glDepthFunc(GL_LESS);
        u4f(f.prog->omni_depth, "u_light_position", in.light_position);
        u1f(f.prog->omni_depth, "u_range", in.far_z);
        g.scene.draw_all();
    }
    begin_camera_pass(f, f.prog->omni);
    glBindTexture(GL_TEXTURE_CUBE_MAP, g.cube);
    u4f(f.prog->omni, "u_light_position", in.light_position);
    u1f(f.prog->omni, "u_range", in.far_z);
    u1f(f.prog->omni, "u_size", float(kMap));
    g.scene.draw_all();
    o.v = read_visibility(g);
    return o;
}

// ---- silhouette.hpp + penumbra_wedge.hpp + penumbra_wedge.glsl (docs/penumbra_wedge.md)
Outcome run_wedges(const Frame& f, float radius) {
    Outcome o;
    Gpu& g = *f.gpu;
    sk::PenumbraSphereLight light;
    light.light_position = f.light.light_position;
    light.radius = radius;
    const sk::ScissorParams camera = scissor_params(f.cam);
    struct WedgeDraw {
        glm::vec3 e0, e1;
        sk::PenumbraWedge wedge;
        sk::PenumbraWedgeHull hull;
        sk::ScissorRect rect;
        bool back_faces = false;
    };
    std::vector<WedgeDraw> wedges;
    std::vector<glm::vec4> quads;
    for (const VolumeMesh& v : g.volumes) {
        const docs::Mesh& box = *v.mesh;
        const sk::Silhouette silhouette = sk::silhouette_compute(v.adj, box.positions.data(), box.positions.size(), light.light_position);
        if (silhouette.status != sk::Status::Ok) {
            o.status = silhouette.status;
            return o;
        }
        for (std::size_t i = 0; i + 1 < silhouette.indices.size(); i += 2) {
            WedgeDraw d;
            d.e0 = box.positions[silhouette.indices[i]];
            d.e1 = box.positions[silhouette.indices[i + 1]];
            d.wedge = sk::penumbra_wedge(d.e0, d.e1, light);
            if (d.wedge.status != sk::Status::Ok) {
                o.status = d.wedge.status;  // a sun: InvalidLight
                return o;
            }
            // the hard volume's side quad of this edge
            const glm::vec3 c = f.light.center();
            const glm::vec4 a(d.e1, 1.0f), b(d.e0, 1.0f), ci(d.e0 - c, 0.0f), di(d.e1 - c, 0.0f);
            quads.insert(quads.end(), {a, b, ci, a, ci, di});
            if (d.wedge.skip != sk::PenumbraWedgeSkip::None) continue;
            d.hull = sk::penumbra_wedge_hull(d.wedge, std::numeric_limits<float>::infinity());
            REQUIRE(d.hull.status == sk::Status::Ok);
            if (!d.hull.drawable) continue;
            d.rect = sk::penumbra_wedge_scissor_in_box(d.hull, f.scene->lo, f.scene->hi, camera);
            REQUIRE(d.rect.status == sk::Status::Ok);
            if (!d.rect.visible) continue;
            d.back_faces = sk::penumbra_point_in_wedge(f.cam.eye, d.wedge);
            for (const glm::vec4& hv : d.hull.vertices) {
                const glm::vec4 in_view = f.cam.view * hv;
                if (hv.w == 0.0f ? in_view.z >= 0.0f : -in_view.z < 1.001f * f.cam.near_z) d.back_faces = true;
            }
            wedges.push_back(d);
        }
    }
    o.status = sk::Status::Ok;
    o.note = std::to_string(wedges.size()) + " wedges";
    // the depth pre-pass into the accumulation target, cleared to 0
    reset_state();
    glBindFramebuffer(GL_FRAMEBUFFER, g.accfbo);
    glViewport(0, 0, kW, kH);
    const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    glClearBufferfv(GL_COLOR, 0, zero);
    glClearDepth(f.far_depth());
    glClear(GL_DEPTH_BUFFER_BIT);
    glDepthFunc(f.less());
    glEnable(GL_CULL_FACE);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glUseProgram(f.prog->flat);
    um4(f.prog->flat, "u_view_proj", f.view_proj());
    g.scene.draw_all();
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDisable(GL_CULL_FACE);
    // hard pass: z-pass counts of the hard volume's side quads
    glDepthFunc(f.less());
    glDepthMask(GL_FALSE);
    glEnable(GL_DEPTH_CLAMP);
    glEnable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);
    glBlendFunc(GL_ONE, GL_ONE);
    glUseProgram(f.prog->wedge_count);
    um4(f.prog->wedge_count, "u_view_proj", f.view_proj());
    draw_vec4_triangles(quads);
    // wedge pass
    const GLuint wp = f.prog->wedge;
    glUseProgram(wp);
    um4(wp, "u_view_proj", f.view_proj());
    u4f(wp, "u_light_position", light.light_position);
    u1f(wp, "u_light_radius", light.radius);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, g.gpos);
    glEnable(GL_CULL_FACE);
    glFrontFace(GL_CCW);
    glEnable(GL_SCISSOR_TEST);
    const GLenum toward = f.rev ? GL_GEQUAL : GL_LEQUAL, away = f.rev ? GL_LEQUAL : GL_GEQUAL;
    for (const WedgeDraw& d : wedges) {
        glCullFace(d.back_faces ? GL_FRONT : GL_BACK);
        glDepthFunc(d.back_faces ? away : toward);
        glScissor(d.rect.x, d.rect.y, d.rect.width, d.rect.height);
        u4f(wp, "u_outer_bound", d.wedge.outer_bound);
        u4f(wp, "u_inner_bound", d.wedge.inner_bound);
        u4f(wp, "u_side0", d.wedge.side[0]);
        u4f(wp, "u_side1", d.wedge.side[1]);
        u3f(wp, "u_e0", d.e0);
        u3f(wp, "u_e1", d.e1);
        std::vector<glm::vec4> triangles;
        for (std::uint8_t k : d.hull.indices) triangles.push_back(d.hull.vertices[k]);
        draw_vec4_triangles(triangles);
    }
    // combine into V
    reset_state();
    glBindFramebuffer(GL_FRAMEBUFFER, g.vfbo);
    glDisable(GL_DEPTH_TEST);
    glUseProgram(f.prog->wedge_combine);
    glBindTexture(GL_TEXTURE_2D, g.acc);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    o.v = read_visibility(g);
    return o;
}

// ---- silhouette.hpp + light_frustum.hpp's matrix + smoothie.hpp + smoothie.glsl (docs/smoothie.md)
Outcome run_smoothies(const Frame& f, bool soft) {
    Outcome o;
    Gpu& g = *f.gpu;
    const sk::LightFrustumInput in = light_frustum_input(*f.scene, f.cam, f.light.light_position);
    std::vector<std::uint32_t> keep(in.caster_count);
    const sk::LightFrustumResult fit = sk::light_frustum_fit(in, keep.data(), keep.size());
    o.status = fit.status;
    if (fit.status != sk::Status::Ok) return o;
    // t: a light 0.1 wide for a point light, blockers ~2 from it (smoothie_width_for_area_light);
    // for a sun 0.01 light NDC (docs: t = theta s r_ref)
    float t = 0.0f;
    if (soft) {
        if (f.light.point()) {
            const sk::SmoothieValue tv = sk::smoothie_width_for_area_light(0.1f, 2.0f, fit.proj[0][0]);
            REQUIRE(tv.status == sk::Status::Ok);
            t = tv.value;
        } else {
            t = 0.01f;
        }
    }
    std::vector<sk::SmoothieVertex> all;
    for (const VolumeMesh& v : g.volumes) {
        const docs::Mesh& m = *v.mesh;
        const sk::Silhouette sil = sk::silhouette_compute(v.adj, m.positions.data(), m.positions.size(), f.light.light_position);
        REQUIRE(sil.status == sk::Status::Ok);
        const std::size_t edges = sil.indices.size() / 2;
        std::vector<sk::SmoothieScratch> scratch(sk::smoothie_scratch_capacity(edges));
        std::vector<sk::SmoothieVertex> vertices(sk::smoothie_vertex_capacity(edges));
        sk::SmoothieEdges se;
        se.positions = m.positions.data();
        se.position_count = m.positions.size();
        se.edges = sil.indices.data();
        se.edge_count = edges;
        sk::SmoothieParams params;
        params.t = t;
        params.clip_depth = f.cd();
        params.reversed_z = f.rev;
        const sk::SmoothieResult r = sk::smoothie_build(se, fit.view_proj, params, scratch.data(), scratch.size(), vertices.data(), vertices.size());
        if (r.status != sk::Status::Ok) {
            o.status = r.status;
            return o;
        }
        if (t == 0.0f) CHECK(r.count == 0);  // t = 0 builds nothing: the hard shadow
        all.insert(all.end(), vertices.begin(), vertices.begin() + std::ptrdiff_t(r.count));
    }
    char note[64];
    std::snprintf(note, sizeof note, "t %.3f, %zu vertices", double(t), all.size());
    o.note = note;
    // 1. linear shadow map
    reset_state();
    glBindFramebuffer(GL_FRAMEBUFFER, g.sm_fbo);
    glViewport(0, 0, kMap, kMap);
    const float far_value[4] = {1e30f, 0.0f, 0.0f, 0.0f};
    glClearBufferfv(GL_COLOR, 0, far_value);
    glClearDepth(f.far_depth());
    glClear(GL_DEPTH_BUFFER_BIT);
    glDepthFunc(f.less());
    glUseProgram(f.prog->smoothie_map);
    um4(f.prog->smoothie_map, "u_light_view_proj", fit.view_proj);
    um4(f.prog->smoothie_map, "u_light_view", fit.view);
    g.scene.draw_all();
    // 2. smoothie buffer, one pass, minimum blending
    reset_state();
    glBindFramebuffer(GL_FRAMEBUFFER, g.sm_buffer_fbo);
    glViewport(0, 0, kMap, kMap);
    const float cleared[4] = {1e30f, 1.0f, 0.0f, 0.0f};
    glClearBufferfv(GL_COLOR, 0, cleared);
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_BLEND);
    glBlendEquation(GL_MIN);
    if (!all.empty()) {
        glUseProgram(f.prog->smoothie);
        um4(f.prog->smoothie, "u_light_view_proj", fit.view_proj);
        um4(f.prog->smoothie, "u_light_view", fit.view);
        u2f(f.prog->smoothie, "u_size", glm::vec2(float(kMap)));
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(GL_TEXTURE_2D, g.sm_linear);
        u1i(f.prog->smoothie, "u_shadow_map", 0);
        glBindVertexArray(g.sm_vao);
        glBindBuffer(GL_ARRAY_BUFFER, g.sm_vbo);
        glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(all.size() * sizeof(sk::SmoothieVertex)), all.data(), GL_STREAM_DRAW);
        glDrawArrays(GL_TRIANGLES, 0, GLsizei(all.size()));
    }
    // 3. the lookup
    begin_camera_pass(f, f.prog->smoothie_lookup);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, g.sm_linear);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, g.sm_buffer);
    u1i(f.prog->smoothie_lookup, "u_shadow_map", 0);
    u1i(f.prog->smoothie_lookup, "u_smoothie_map", 1);
    um4(f.prog->smoothie_lookup, "u_light_view_proj", fit.view_proj);
    um4(f.prog->smoothie_lookup, "u_light_view", fit.view);
    g.scene.draw_all();
    glActiveTexture(GL_TEXTURE0);
    o.v = read_visibility(g);
    return o;
}

// ---- pcss.hpp + pcss.glsl (docs/pcss.md): the map from the light's center, near plane at the casters.
// Its own frustum, as the page builds it: a PcssLight describes a symmetric square frustum (one
// frustum_width), and light_frustum_fit's point-light frustum is off-center with two widths, so its
// matrix cannot be handed to pcss.hpp as it is (reported in docs/composition.md).
Outcome run_pcss(const Frame& f, float size) {
    Outcome o;
    Gpu& g = *f.gpu;
    const Scene& s = *f.scene;
    glm::vec3 casters_min(1e30f), casters_max(-1e30f);
    for (std::size_t m = 1; m < s.meshes.size(); ++m) {
        glm::vec3 lo, hi;
        bounds(s.meshes[m], lo, hi);
        casters_min = glm::min(casters_min, lo);
        casters_max = glm::max(casters_max, hi);
    }
    // the reversed-Z mode's matrices: zero-to-one, near at 1 (glClipControl is on for every pass)
    glm::mat4 to_depth(1.0f);
    if (f.rev) {
        to_depth[2][2] = -0.5f;
        to_depth[3][2] = 0.5f;
    }
    sk::PcssLight light;
    glm::mat4 light_view(1.0f), light_view_proj(1.0f);
    if (f.light.point()) {
        // a spot light's frustum from its center, looking down, wide enough for the whole floor
        const glm::vec3 c = f.light.center();
        light_view = glm::lookAt(c, c - glm::vec3(0.0f, 1.0f, 0.0f), glm::vec3(0.0f, 0.0f, 1.0f));
        const float reach = std::max(std::max(s.hi.x - c.x, c.x - s.lo.x), std::max(s.hi.z - c.z, c.z - s.lo.z));
        const float fov = 2.0f * std::atan(reach / (c.y - s.lo.y));
        light.size = size;
        light.near_z = 0.05f;
        light.far_z = c.y - s.lo.y + 0.5f;
        light.frustum_width = 2.0f * std::tan(0.5f * fov);
        const sk::PcssFit fit = sk::pcss_fit_near_plane(light, light_view, casters_min, casters_max);
        REQUIRE(fit.status == sk::Status::Ok);
        light = fit.light;
        if (f.rev) {
            sk::ProjectionDepth depth;  // infinite_projection.hpp, finite far, zero-to-one reversed
            depth.near_z = light.near_z;
            depth.far_z = light.far_z;
            depth.clip_depth = sk::ClipDepth::ZeroToOne;
            depth.reversed_z = true;
            const sk::ProjectionResult pr = sk::projection_perspective(fov, 1.0f, depth);
            REQUIRE(pr.status == sk::Status::Ok);
            light_view_proj = pr.matrix * light_view;
        } else {
            light_view_proj = glm::perspective(fov, 1.0f, light.near_z, light.far_z) * light_view;
        }
    } else {
        // a sun: an orthographic box around the scene (docs/shadow_map.md), size = angular diameter
        const glm::vec3 center = 0.5f * (s.lo + s.hi);
        const float radius = 0.5f * glm::length(s.hi - s.lo);
        const glm::vec3 dir = glm::normalize(glm::vec3(f.light.light_position));
        const glm::vec3 up = std::abs(dir.y) > 0.9f ? glm::vec3(0.0f, 0.0f, 1.0f) : glm::vec3(0.0f, 1.0f, 0.0f);
        light_view = glm::lookAt(center + 2.0f * radius * dir, center, up);
        light.type = sk::PcssLightType::Directional;
        light.size = size;
        light.near_z = radius;
        light.far_z = 3.0f * radius;
        light.frustum_width = 2.0f * radius;
        const sk::PcssFit fit = sk::pcss_fit_near_plane(light, light_view, casters_min, casters_max);
        REQUIRE(fit.status == sk::Status::Ok);
        light = fit.light;
        light_view_proj = to_depth * glm::ortho(-radius, radius, -radius, radius, light.near_z, light.far_z) * light_view;
    }
    const sk::PcssValue light_uv = sk::pcss_light_uv_at_near(light);
    o.status = light_uv.status;
    if (light_uv.status != sk::Status::Ok) return o;
    // the map: one texture, two sampler objects, a border that is lit
    const float border = f.rev ? 0.0f : 1.0f;
    const float border4[4] = {border, border, border, border};
    for (GLuint smp : {g.pcss_raw, g.pcss_compare}) {
        glSamplerParameteri(smp, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_BORDER);
        glSamplerParameteri(smp, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_BORDER);
        glSamplerParameterfv(smp, GL_TEXTURE_BORDER_COLOR, border4);
    }
    glSamplerParameteri(g.pcss_raw, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glSamplerParameteri(g.pcss_raw, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glSamplerParameteri(g.pcss_raw, GL_TEXTURE_COMPARE_MODE, GL_NONE);
    glSamplerParameteri(g.pcss_compare, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glSamplerParameteri(g.pcss_compare, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glSamplerParameteri(g.pcss_compare, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glSamplerParameteri(g.pcss_compare, GL_TEXTURE_COMPARE_FUNC, GLint(f.compare()));
    begin_light_pass(f, g.map2d_fbo, f.prog->depth, light_view_proj);
    g.scene.draw_all();
    const GLuint prog = f.light.point() ? f.prog->pcss : f.prog->pcss_directional;
    begin_camera_pass(f, prog);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, g.map2d);
    glBindSampler(0, g.pcss_raw);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, g.map2d);
    glBindSampler(1, g.pcss_compare);
    u1i(prog, "u_depth_map", 0);
    u1i(prog, "u_shadow_map", 1);
    um4(prog, "u_light_view_proj", light_view_proj);
    u1f(prog, "u_light_uv", light_uv.value);
    u1f(prog, "u_near", light.near_z);
    u1f(prog, "u_far", light.far_z);
    u1f(prog, "u_texel_uv", 1.0f / float(kMap));
    u1i(prog, "u_zero_to_one", f.zo());
    g.scene.draw_all();
    glBindSampler(0, 0);
    glBindSampler(1, 0);
    glActiveTexture(GL_TEXTURE0);
    o.v = read_visibility(g);
    return o;
}

// ------------------------------------------------------------------------------------------ scoring

// The CPU ray cast per pixel: -1 not scored (background, facing away or grazing, outside the spot's
// cone), 0 shadowed, 1 lit; and the pixels away from shadow edges (every pixel within 2 has the class).
struct Reference {
    std::vector<int> cls;
    std::vector<std::uint8_t> interior;
    int receivers = 0, counted = 0, lit = 0;
};

Reference ray_cast(const Scene& s, const std::vector<glm::vec4>& gpos, const std::vector<glm::vec4>& gnrm, const Light& L) {
    Reference r;
    r.cls.assign(gpos.size(), -1);
    for (std::size_t k = 0; k < gpos.size(); ++k) {
        if (gpos[k].w == 0.0f) continue;
        const glm::vec3 p(gpos[k]), n(gnrm[k]);
        const glm::vec3 to_light = L.point() ? glm::normalize(L.center() - p) : glm::normalize(glm::vec3(L.light_position));
        if (glm::dot(n, to_light) < 0.1f) continue;  // facing away or grazing: the terminator is an edge
        if (L.spot && glm::dot(-to_light, L.spot_axis) < L.spot_cos) continue;  // outside the cone: unlit anyway
        const glm::vec3 from = p + n * 1e-4f;
        const glm::vec3 to = L.point() ? L.center() : p + to_light * 100.0f;
        r.cls[k] = docs::segment_occluded(s.all, from, to) ? 0 : 1;
        ++r.receivers;
    }
    r.interior.assign(gpos.size(), 0);
    for (int y = 2; y < kH - 2; ++y)
        for (int x = 2; x < kW - 2; ++x) {
            const std::size_t k = std::size_t(y * kW + x);
            if (r.cls[k] < 0) continue;
            bool in = true;
            for (int dy = -2; dy <= 2 && in; ++dy)
                for (int dx = -2; dx <= 2 && in; ++dx) in = r.cls[std::size_t((y + dy) * kW + x + dx)] == r.cls[k];
            if (!in) continue;
            r.interior[k] = 1;
            ++r.counted;
            r.lit += r.cls[k];
        }
    return r;
}

struct Row {
    std::string camera, light, technique, status, note;
    int counted = 0, penumbra = 0;
    double vs_ray = -1.0, vs_volumes = -1.0, threshold = 0.0;
};

}  // namespace

TEST_CASE("composition: one scene, one light value, every technique agrees with a ray cast and with each other") {
    const Scene scene = make_scene();
    const std::vector<Light> lights = make_lights();
    Gpu gpu;
    make_gpu(gpu, scene);
    std::vector<Row> rows;
    for (const bool rev : {false, true}) {
        // the camera: epsilon-tweaked P_inf, GL depth; then reversed-Z zero-to-one (glClipControl for every pass)
        const Camera cam = make_camera(rev ? sk::ClipDepth::ZeroToOne : sk::ClipDepth::NegativeOneToOne, rev, true);
        glClipControl(GL_LOWER_LEFT, rev ? GL_ZERO_TO_ONE : GL_NEGATIVE_ONE_TO_ONE);
        const Programs prog = make_programs(rev);
        // the G-buffer (the score's surface points and normals)
        reset_state();
        glBindFramebuffer(GL_FRAMEBUFFER, gpu.gfbo);
        glViewport(0, 0, kW, kH);
        const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
        glClearBufferfv(GL_COLOR, 0, zero);
        glClearBufferfv(GL_COLOR, 1, zero);
        glClearDepth(rev ? 0.0 : 1.0);
        glClear(GL_DEPTH_BUFFER_BIT);
        glDepthFunc(rev ? GL_GREATER : GL_LESS);
        glEnable(GL_CULL_FACE);
        glUseProgram(prog.gbuffer);
        um4(prog.gbuffer, "u_view_proj", cam.proj * cam.view);
        gpu.scene.draw_all();
        std::vector<glm::vec4> gpos(std::size_t(kW) * std::size_t(kH)), gnrm(gpos.size());
        glBindFramebuffer(GL_READ_FRAMEBUFFER, gpu.gfbo);
        glReadBuffer(GL_COLOR_ATTACHMENT0);
        glReadPixels(0, 0, kW, kH, GL_RGBA, GL_FLOAT, gpos.data());
        glReadBuffer(GL_COLOR_ATTACHMENT1);
        glReadPixels(0, 0, kW, kH, GL_RGBA, GL_FLOAT, gnrm.data());

        for (const Light& L : lights) {
            const Reference ref = ray_cast(scene, gpos, gnrm, L);
            Frame f;
            f.scene = &scene;
            f.gpu = &gpu;
            f.prog = &prog;
            f.cam = cam;
            f.light = L;
            f.rev = rev;
            std::vector<float> volumes_v;
            // name, outcome, threshold (0: a rejection expected), the status it must be rejected with
            auto score = [&](const std::string& name, const Outcome& o, double threshold, sk::Status expected, bool soft_row = false) {
                Row row;
                row.camera = cam.name;
                row.light = L.name;
                row.technique = name;
                row.status = st(o.status);
                row.note = o.note;
                row.threshold = threshold;
                INFO(cam.name, " / ", std::string(L.name), " / ", name);
                CHECK_MESSAGE(o.status == expected, "status ", st(o.status), ", expected ", st(expected));
                if (o.status == sk::Status::Ok && !o.v.empty()) {
                    int agree = 0, agree_sv = 0;
                    for (std::size_t k = 0; k < o.v.size(); ++k) {
                        if (!ref.interior[k]) continue;
                        const int mine = o.v[k] >= 0.5f ? 1 : 0;
                        agree += mine == ref.cls[k] ? 1 : 0;
                        if (!volumes_v.empty()) agree_sv += mine == (volumes_v[k] >= 0.5f ? 1 : 0) ? 1 : 0;
                    }
                    int penumbra = 0;  // receiver pixels strictly between shadow and light
                    for (std::size_t k = 0; k < o.v.size(); ++k) penumbra += ref.cls[k] >= 0 && o.v[k] > 0.02f && o.v[k] < 0.98f ? 1 : 0;
                    row.penumbra = penumbra;
                    if (soft_row) CHECK_MESSAGE(penumbra > 50, "a soft technique with ", penumbra, " penumbra pixels");
                    row.counted = ref.counted;
                    row.vs_ray = ref.counted ? double(agree) / ref.counted : 0.0;
                    row.vs_volumes = volumes_v.empty() || !ref.counted ? -1.0 : double(agree_sv) / ref.counted;
                    CHECK(ref.counted > 3000);
                    CHECK_MESSAGE(row.vs_ray >= threshold, "agreement with the ray cast ", row.vs_ray);
                    if (row.vs_volumes >= 0.0) CHECK_MESSAGE(row.vs_volumes >= threshold, "agreement with the volumes ", row.vs_volumes);
                }
                rows.push_back(row);
                // SHADOWKIT_COMPOSITION_IMAGES=<folder>: one PGM per row, V | ray cast (grey: not scored) |
                // disagreement (white) on the scored pixels away from edges, for looking at a failure
                const char* images = std::getenv("SHADOWKIT_COMPOSITION_IMAGES");
                if (images != nullptr && o.status == sk::Status::Ok && !o.v.empty()) {
                    std::string fn = std::string(images) + "/" + (rev ? "reversed_" : "gl_") + std::string(L.name) + "_" + name + ".pgm";
                    for (char& ch : fn) if (ch == ' ' || ch == ',') ch = '_';
                    FILE* fp = std::fopen(fn.c_str(), "wb");
                    REQUIRE(fp != nullptr);
                    std::fprintf(fp, "P5 %d %d 255\n", kW * 3, kH);
                    for (int y = kH - 1; y >= 0; --y) {
                        for (int x = 0; x < kW; ++x) std::fputc(int(255.0f * std::min(1.0f, std::max(0.0f, o.v[std::size_t(y * kW + x)]))), fp);
                        for (int x = 0; x < kW; ++x) { const int c = ref.cls[std::size_t(y * kW + x)]; std::fputc(c < 0 ? 128 : c * 255, fp); }
                        for (int x = 0; x < kW; ++x) {
                            const std::size_t k = std::size_t(y * kW + x);
                            std::fputc(!ref.interior[k] ? (ref.cls[k] < 0 ? 0 : 60) : ((o.v[k] >= 0.5f) == (ref.cls[k] == 1) ? 120 : 255), fp);
                        }
                    }
                    std::fclose(fp);
                }
            };
            const double hard = 0.995, soft = 0.99;
            const sk::Status ok = sk::Status::Ok, point_only = L.point() ? ok : sk::Status::InvalidLight;
            const sk::Status sun_only = L.point() ? sk::Status::InvalidLight : ok;

            const Outcome sv = run_stencil_volumes(f);
            score("stencil volumes", sv, hard, ok);
            volumes_v = sv.v;
            score("light frustum + map", run_light_frustum(f), hard, ok);
            for (int m = 0; m < 4; ++m) score("warp " + kWarpNames[m], run_warp(f, kWarpMethods[m]), hard, ok);
            // docs/cascades.md's constant bias alone (0.0005 window depth) acnes at 256^2: shown, not asserted
            score("cascades, bias only", run_cascades(f, 0.0f), 0.0, sun_only);
            score("cascades", run_cascades(f, 1.0f), hard, sun_only);
            score("omni cube", run_omni(f), hard, point_only);
            const Outcome w0 = run_wedges(f, 0.0f);
            score("wedges r = 0", w0, hard, point_only);
            if (w0.status == sk::Status::Ok) {
                // radius 0 is the hard volume: the same pixels as the stencil volumes, edges included
                int same = 0, all = 0;
                for (std::size_t k = 0; k < w0.v.size(); ++k) {
                    if (ref.cls[k] < 0) continue;
                    ++all;
                    same += (w0.v[k] >= 0.5f) == (sv.v[k] >= 0.5f) ? 1 : 0;
                }
                INFO(cam.name, " / ", std::string(L.name));
                CHECK_MESSAGE(same == all, "wedges r = 0 differ from the stencil volumes on ", all - same, " of ", all,
                              " receiver pixels");
                rows.back().note += ", = volumes on " + std::to_string(same) + " of " + std::to_string(all) + " receiver pixels";
            }
            score("wedges r = 0.05", run_wedges(f, 0.05f), soft, point_only, true);
            score("smoothies t = 0", run_smoothies(f, false), hard, ok);
            score("smoothies t > 0", run_smoothies(f, true), soft, ok, true);
            score("PCSS size 0", run_pcss(f, 0.0f), hard, ok);
            score("PCSS small", run_pcss(f, L.point() ? 0.2f : 0.05f), soft, ok, true);
            // each soft row is softer than its own hard limit (more pixels strictly between 0 and 1)
            for (std::size_t k = rows.size() - 6; k < rows.size(); k += 2)
                if (rows[k].status == "Ok" && rows[k + 1].status == "Ok")
                    CHECK_MESSAGE(rows[k + 1].penumbra > rows[k].penumbra, rows[k + 1].technique, " is not softer than ", rows[k].technique);
            const GLenum err = glGetError();
            CHECK_MESSAGE(err == GL_NO_ERROR, "GL error ", int(err));
        }
    }
    glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
    reset_state();
    std::printf("\ncomposition: V >= 0.5 against the CPU ray cast and the stencil volumes, pixels away from shadow edges\n");
    std::printf("%-27s %-17s %-20s %-13s %6s %8s %8s %6s  %s\n", "camera", "light", "technique", "status", "pixels", "ray cast",
                "volumes", "0<V<1", "note");
    for (const Row& r : rows) {
        char a[16] = "-", b[16] = "-";
        if (r.vs_ray >= 0.0) std::snprintf(a, sizeof a, "%.2f%%", 100.0 * r.vs_ray);
        if (r.vs_volumes >= 0.0) std::snprintf(b, sizeof b, "%.2f%%", 100.0 * r.vs_volumes);
        std::printf("%-27s %-17s %-20s %-13s %6d %8s %8s %6d  %s\n", r.camera.c_str(), r.light.c_str(), r.technique.c_str(),
                    r.status.c_str(), r.counted, a, b, r.penumbra, r.note.c_str());
    }
}
