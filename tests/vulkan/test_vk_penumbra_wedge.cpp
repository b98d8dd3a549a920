// glsl/penumbra_wedge.glsl and hlsl/penumbra_wedge.hlsl RUN on Vulkan: sk_wedge_edge_coverage for
// 2048 random silhouette edges and receiver points under a sphere light, against
// shadowkit::penumbra_edge_coverage (the header's double-precision twin) with the GL test's
// tolerance (max 1e-4, mean 1e-6), and sk_wedge_world_from_depth with zero_to_one (Vulkan's window
// depth) against the inverse of a [0, 1] reversed-Z view-projection in double (relative 1e-4); one
// pixel per sample, no validation message.
// The wedge passes themselves (tests/gl/test_gl_penumbra_wedges.cpp's (a) and (d), the passes of
// samples/penumbra_wedges/): a floor and two boxes (the upper one's penumbra overlapping the lower
// one's) under a sphere light; a G-buffer pass; then in one render pass the scene's depth, the hard
// shadow of the light's center as z-fail stencil volumes (sk_extrude_shadow_volume of
// shadow_volume.glsl / .hlsl), and the wedge hulls (penumbra_wedge + penumbra_wedge_hull on the CPU,
// front faces with the depth test, back faces where a hull reaches the near plane) adding
// sk_wedge_edge_coverage at the G-buffer's points inside sk_wedge_inside4 into an R32F target
// (additive blending); last a full-screen pass reading the stencil (a stencil-aspect view) and the
// sum, V = sk_wedge_visibility. Against the GL test's CPU model: the hard count of lit triangles the
// segment to the light's center crosses, V = penumbra_visibility (double) at every second pixel away
// from changes of the count, max |V_gpu - V_cpu| < 1e-4, mean < 1e-6; radius 0: V = 1 - clamp(stencil)
// on every pixel and the stencil agrees with the CPU count on >= 99.8%. The GL test's (f): the eye
// inside a wedge, hulls that reach the near plane drawn with their back faces, the same bounds; drawn
// with their front faces (the control) > 100 sampled pixels are off by more than 0.05.
// The scene's vertex stage is written in the language under test as well: compiled from GLSL while the
// volumes came from HLSL, 13 sampled pixels of the lit faces shadowed themselves (the light caps
// rasterized a hair in front of the faces they lie on).
#include <doctest/doctest.h>

#include <shadowkit/infinite_projection.hpp>
#include <shadowkit/penumbra_wedge.hpp>
#include <shadowkit/shadow_volume.hpp>
#include <shadowkit/silhouette.hpp>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "vk_harness.hpp"
#include "vk_passes.hpp"
#include "vk_scene.hpp"

namespace {

using skvk::Source;

// per sample: e0, e1, (p, -), (ndc.xy, window depth, -)
const char* kGlsl = R"(
layout(set = 0, binding = 0, std430) readonly buffer Samples { vec4 s[]; };
layout(set = 0, binding = 1, std140) uniform Params { mat4 inv_view_proj; vec4 light_position; vec4 radius; } u;
layout(location = 0) out vec4 o_value;
void main() {
    int i = int(gl_FragCoord.x);
    float c = sk_wedge_edge_coverage(s[4 * i].xyz, s[4 * i + 1].xyz, u.light_position, u.radius.x, s[4 * i + 2].xyz);
    vec3 w = sk_wedge_world_from_depth(u.inv_view_proj, s[4 * i + 3].xy, s[4 * i + 3].z, true);
    o_value = vec4(c, w);
}
)";
const char* kHlsl = R"(
[[vk::binding(0, 0)]] StructuredBuffer<float4> s;
struct Params { column_major float4x4 inv_view_proj; float4 light_position; float4 radius; };
[[vk::binding(1, 0)]] ConstantBuffer<Params> u;
float4 ps_main(float4 position : SV_Position) : SV_Target0 {
    int i = int(position.x);
    float c = sk_wedge_edge_coverage(s[4 * i].xyz, s[4 * i + 1].xyz, u.light_position, u.radius.x, s[4 * i + 2].xyz);
    float3 w = sk_wedge_world_from_depth(u.inv_view_proj, s[4 * i + 3].xy, s[4 * i + 3].z, true);
    return float4(c, w);
}
)";

struct Params {
    glm::mat4 inv_view_proj;
    glm::vec4 light_position, radius;
};

void run_wedge(Source lang) {
    skvk::Context& ctx = skvk::vk_test_context();
    skvk::Scope scope(ctx);
    const std::size_t before = skvk::message_count();
    std::vector<std::uint32_t> vs, fs;
    const char* entries[2] = {"main", "main"};
    if (lang == Source::Glsl) {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_GLSL_DIR) + "/penumbra_wedge.glsl");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, skvk::kFullscreenGlsl, "main", "wedge.glsl.vert");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, "#version 450 core\n" + snippet + kGlsl, "main",
                                   "wedge.glsl.frag");
    } else {
        const std::string snippet = skvk::read_text(std::string(SHADOWKIT_HLSL_DIR) + "/penumbra_wedge.hlsl");
        vs = skvk::compile_checked(lang, VK_SHADER_STAGE_VERTEX_BIT, snippet + skvk::kFullscreenHlsl + kHlsl, "vs_main", "wedge.hlsl.vert");
        fs = skvk::compile_checked(lang, VK_SHADER_STAGE_FRAGMENT_BIT, snippet + skvk::kFullscreenHlsl + kHlsl, "ps_main", "wedge.hlsl.frag");
        entries[0] = "vs_main";
        entries[1] = "ps_main";
    }
    // a sphere light of radius 0.5 at (0, 4, 0); edges around height 2, receivers on the ground
    const shadowkit::PenumbraSphereLight light{glm::vec4(0.f, 4.f, 0.f, 1.f), 0.5f};
    glm::mat4 proj = glm::perspectiveRH_ZO(0.9f, 4.f / 3.f, 0.1f, 50.f);
    glm::mat4 rev(1.f);
    rev[2][2] = -1.f;
    rev[3][2] = 1.f;
    const glm::mat4 view_proj = rev * proj * glm::lookAt(glm::vec3(0.f, 3.5f, 5.f), glm::vec3(0.f), glm::vec3(0.f, 1.f, 0.f));
    const glm::dmat4 inv = glm::inverse(glm::dmat4(view_proj));
    constexpr std::uint32_t M = 2048;
    std::mt19937 rng(2003);
    std::uniform_real_distribution<float> U(-1.f, 1.f), U01(0.f, 1.f);
    std::vector<glm::vec4> samples(std::size_t(M) * 4);
    for (std::uint32_t i = 0; i < M; ++i) {
        const glm::vec3 mid(U(rng), 2.f + 0.3f * U(rng), U(rng));
        const glm::vec3 dir = glm::normalize(glm::vec3(U(rng), 0.2f * U(rng), U(rng)));
        const glm::vec3 e0 = mid - dir * (0.5f + U01(rng)), e1 = mid + dir * (0.5f + U01(rng));
        // the receiver under the edge's hard shadow line, spread across its penumbra
        const glm::vec3 p(mid.x * 2.f + 0.6f * U(rng), 0.f, mid.z * 2.f + 0.6f * U(rng));
        samples[4 * i] = glm::vec4(e0, 0.f);
        samples[4 * i + 1] = glm::vec4(e1, 0.f);
        samples[4 * i + 2] = glm::vec4(p, 0.f);
        samples[4 * i + 3] = glm::vec4(U(rng), U(rng), 0.05f + 0.9f * U01(rng), 0.f);
    }
    const Params params{glm::inverse(view_proj), light.light_position, glm::vec4(light.radius)};
    skvk::Buffer& ssbo = scope.own<skvk::Buffer>();
    skvk::Buffer& ubo = scope.own<skvk::Buffer>();
    REQUIRE(skvk::make_buffer(ctx, samples.size() * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, ssbo));
    std::memcpy(ssbo.mapped, samples.data(), samples.size() * sizeof(glm::vec4));
    REQUIRE(skvk::make_buffer(ctx, sizeof(Params), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, ubo));
    std::memcpy(ubo.mapped, &params, sizeof params);
    skvk::DescriptorSet& ds = scope.own<skvk::DescriptorSet>();
    REQUIRE(skvk::make_descriptor_set(ctx, {{0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_FRAGMENT_BIT},
                                            {1, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, VK_SHADER_STAGE_FRAGMENT_BIT}}, ds));
    skvk::write_buffer(ctx, ds, 0, ssbo, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
    skvk::write_buffer(ctx, ds, 1, ubo);
    skvk::RowPass& row = scope.own<skvk::RowPass>();
    skvk::make_row_pass(ctx, vs, fs, entries[0], entries[1], ds, M, row, VK_FORMAT_R32G32B32A32_SFLOAT, 4);
    const std::vector<float> gpu = skvk::draw_row(ctx, row, ds);

    double max_c = 0, sum_c = 0, max_w = 0;
    int nonzero = 0, positive = 0, negative = 0;
    for (std::uint32_t i = 0; i < M; ++i) {
        const shadowkit::PenumbraValue cpu = shadowkit::penumbra_edge_coverage(
            glm::vec3(samples[4 * i]), glm::vec3(samples[4 * i + 1]), light, glm::vec3(samples[4 * i + 2]));
        REQUIRE(cpu.status == shadowkit::Status::Ok);
        const double e = std::abs(double(gpu[4 * i]) - double(cpu.value));
        max_c = std::max(max_c, e);
        sum_c += e;
        nonzero += cpu.value != 0.f;
        positive += cpu.value > 0.f;
        negative += cpu.value < 0.f;
        const glm::dvec4 w = inv * glm::dvec4(samples[4 * i + 3].x, samples[4 * i + 3].y, samples[4 * i + 3].z, 1.0);
        const glm::dvec3 ref = glm::dvec3(w) / w.w;
        const glm::dvec3 got(gpu[4 * i + 1], gpu[4 * i + 2], gpu[4 * i + 3]);
        max_w = std::max(max_w, glm::length(got - ref) / std::max(glm::length(ref), 1.0));
    }
    MESSAGE((lang == Source::Glsl ? "GLSL" : "HLSL") << ": coverage max |GPU - CPU| " << max_c << ", mean " << sum_c / M << " ("
                                                    << nonzero << " of " << M << " non-zero: " << positive << " > 0, "
                                                    << negative << " < 0); world from depth max relative error " << max_w);
    CHECK(nonzero > int(M) / 4);
    CHECK(positive > 50);
    CHECK(negative > 50);
    CHECK(max_c < 1e-4);
    CHECK(sum_c / M < 1e-6);
    CHECK(max_w < 1e-4);
    CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());
}

// ------------------------------------------------------------------------------ the wedge passes
constexpr std::uint32_t kW = 320, kH = 240;

// A box as an indexed closed mesh over its 8 corners (corner i: x, y, z high for bits 0, 1, 2),
// counter-clockwise from outside; the scene pass draws exactly these triangles (the z-fail light caps
// then lie at the lit faces' depths).
struct Caster {
    std::vector<glm::vec3> p;
    std::vector<std::uint32_t> tris;
};
Caster box_caster(glm::vec3 c, glm::vec3 h) {
    Caster m;
    for (int i = 0; i < 8; ++i)
        m.p.push_back(c + h * glm::vec3((i & 1) ? 1.f : -1.f, (i & 2) ? 1.f : -1.f, (i & 4) ? 1.f : -1.f));
    const std::uint32_t quads[6][4] = {{6, 7, 3, 2}, {0, 1, 5, 4}, {4, 5, 7, 6}, {1, 0, 2, 3}, {5, 1, 3, 7}, {0, 4, 6, 2}};
    for (const auto& q : quads)
        for (int k : {0, 1, 2, 0, 2, 3}) m.tris.push_back(q[k]);
    return m;
}

struct WedgeScene {
    std::vector<Caster> casters{box_caster({0.f, 0.8f, 0.f}, {0.6f, 0.3f, 0.45f}),
                                box_caster({0.45f, 1.75f, 0.2f}, {0.25f, 0.08f, 0.25f})};
    glm::vec3 light{1.f, 4.f, 0.5f};
    float ground = 3.f;
    glm::vec3 lo{-3.f, 0.f, -3.f}, hi{3.f, 1.83f, 3.f};  ///< the receivers' box (hull extents)
    std::vector<skvk::SceneVertex> vertices;            ///< the scene pass's triangle list
    WedgeScene() {
        const float g = ground;
        const glm::vec3 up(0.f, 1.f, 0.f);
        for (const glm::vec3& q : {glm::vec3(-g, 0.f, g), glm::vec3(g, 0.f, g), glm::vec3(g, 0.f, -g), glm::vec3(-g, 0.f, g),
                                   glm::vec3(g, 0.f, -g), glm::vec3(-g, 0.f, -g)})
            vertices.push_back({q, up});
        for (const Caster& m : casters)
            for (std::size_t t = 0; t < m.tris.size(); t += 3) {
                const glm::vec3 a = m.p[m.tris[t]], b = m.p[m.tris[t + 1]], c = m.p[m.tris[t + 2]];
                const glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
                for (const glm::vec3& q : {a, b, c}) vertices.push_back({q, n});
            }
    }
};

// The CPU side: z-fail volumes of every caster (side quads of every lit triangle's edges, LitOnly caps),
// silhouettes from the light's center, and the GL test's model (hard count of crossed lit triangles,
// penumbra_visibility over every silhouette edge).
struct CpuSide {
    std::vector<glm::vec4> volume_vertices;
    std::vector<std::uint32_t> volume_indices;
    std::vector<glm::vec3> edges, lit;
};
CpuSide build_cpu_side(const WedgeScene& s) {
    CpuSide out;
    const glm::vec4 L(s.light, 1.f);
    for (const Caster& m : s.casters) {
        const auto base = static_cast<std::uint32_t>(out.volume_vertices.size());
        std::vector<std::uint8_t> litf(m.tris.size() / 3);
        std::vector<std::uint32_t> ed;
        for (std::size_t t = 0; t < litf.size(); ++t) {
            const glm::vec3 a = m.p[m.tris[3 * t]], b = m.p[m.tris[3 * t + 1]], c = m.p[m.tris[3 * t + 2]];
            litf[t] = glm::dot(glm::cross(b - a, c - a), s.light - (a + b + c) / 3.f) > 0.f;
            if (!litf[t]) continue;
            for (int e = 0; e < 3; ++e) {
                ed.push_back(m.tris[3 * t + std::size_t(e)]);
                ed.push_back(m.tris[3 * t + std::size_t((e + 1) % 3)]);
            }
            for (const glm::vec3& q : {a, b, c}) out.lit.push_back(q);
        }
        std::vector<glm::vec4> vv(16);
        REQUIRE(shadowkit::volume_build_vertices(m.p.data(), 8, vv.data(), vv.size()).status == shadowkit::Status::Ok);
        std::vector<std::uint32_t> idx(shadowkit::volume_indices_capacity(ed.size(), m.tris.size()));
        const shadowkit::VolumeBuffer sides = shadowkit::volume_build_side_quads(ed.data(), ed.size(), 8, idx.data(), idx.size());
        REQUIRE(sides.status == shadowkit::Status::Ok);
        const shadowkit::VolumeBuffer caps =
            shadowkit::volume_build_caps(m.tris.data(), m.tris.size(), litf.data(), litf.size(), 8, shadowkit::VolumeCapMode::LitOnly,
                                         true, idx.data() + sides.count, idx.size() - sides.count);
        REQUIRE(caps.status == shadowkit::Status::Ok);
        idx.resize(sides.count + caps.count);
        out.volume_vertices.insert(out.volume_vertices.end(), vv.begin(), vv.end());
        for (std::uint32_t i : idx) out.volume_indices.push_back(base + i);
        const shadowkit::SilhouetteAdjacency adj = shadowkit::silhouette_build_adjacency(m.p.data(), 8, m.tris.data(), m.tris.size());
        REQUIRE(adj.status == shadowkit::Status::Ok);
        const shadowkit::Silhouette sil = shadowkit::silhouette_compute(adj, m.p.data(), 8, L);
        REQUIRE(sil.status == shadowkit::Status::Ok);
        for (std::uint32_t i : sil.indices) out.edges.push_back(m.p[i]);
    }
    return out;
}

int cpu_hard_count(const CpuSide& c, glm::vec3 p, glm::vec3 light) {  // Moller-Trumbore in double
    const glm::dvec3 o(p), d = glm::dvec3(light) - o;
    int n = 0;
    for (std::size_t t = 0; t + 2 < c.lit.size(); t += 3) {
        const glm::dvec3 a(c.lit[t]), e1 = glm::dvec3(c.lit[t + 1]) - a, e2 = glm::dvec3(c.lit[t + 2]) - a, h = glm::cross(d, e2);
        const double det = glm::dot(e1, h);
        if (std::abs(det) < 1e-14) continue;
        const glm::dvec3 sv = o - a;
        const double u = glm::dot(sv, h) / det;
        if (u < 0.0 || u > 1.0) continue;
        const glm::dvec3 q = glm::cross(sv, e1);
        const double v = glm::dot(d, q) / det;
        if (v < 0.0 || u + v > 1.0) continue;
        const double th = glm::dot(e2, q) / det;
        if (th > 1e-4 && th < 1.0) ++n;  // not the receiver's own face (G-buffer rounding)
    }
    return n;
}

// The GPU's wedges: per wedge its planes and edge (binding 0), hull vertices tagged with the wedge's
// index, 24 hull indices each, the front-face group first.
struct HullVertex {
    glm::vec4 p;
    std::uint32_t wedge, pad[3];
};
struct GpuWedges {
    std::vector<glm::vec4> data;  ///< outer, inner, side0, side1, e0, e1
    std::vector<HullVertex> vertices;
    std::vector<std::uint32_t> indices;
    std::uint32_t front = 0, back = 0, skipped = 0;
};
GpuWedges build_wedges(const WedgeScene& s, const CpuSide& c, const shadowkit::PenumbraSphereLight& light, const glm::mat4& view,
                       float znear, bool front_only) {
    GpuWedges g;
    std::vector<std::uint32_t> local_front, local_back;
    for (std::size_t e = 0; light.radius > 0.f && e + 1 < c.edges.size(); e += 2) {
        const shadowkit::PenumbraWedge w = shadowkit::penumbra_wedge(c.edges[e], c.edges[e + 1], light);
        REQUIRE(w.status == shadowkit::Status::Ok);
        if (w.skip != shadowkit::PenumbraWedgeSkip::None) {
            ++g.skipped;
            continue;
        }
        float dmax = 0.f, cmin = 1.f;  // samples/penumbra_wedges: the hull reaches past every receiver
        for (int i = 0; i < 8; ++i) {
            const glm::vec3 q((i & 1) ? s.hi.x : s.lo.x, (i & 2) ? s.hi.y : s.lo.y, (i & 4) ? s.hi.z : s.lo.z);
            dmax = std::max({dmax, glm::length(q - w.apex[0]), glm::length(q - w.apex[1])});
        }
        for (int i = 0; i < 2; ++i) cmin = std::min({cmin, glm::dot(w.ray_outer[i], w.axis), glm::dot(w.ray_inner[i], w.axis)});
        const shadowkit::PenumbraWedgeHull h = shadowkit::penumbra_wedge_hull(w, dmax / std::max(cmin, 0.05f) * 1.01f);
        REQUIRE(h.status == shadowkit::Status::Ok);
        if (!h.drawable) {
            ++g.skipped;
            continue;
        }
        const auto id = static_cast<std::uint32_t>(g.data.size() / 6);
        g.data.insert(g.data.end(), {w.outer_bound, w.inner_bound, w.side[0], w.side[1], glm::vec4(c.edges[e], 1.f),
                                     glm::vec4(c.edges[e + 1], 1.f)});
        float min_depth = 1e30f;
        for (const glm::vec4& hv : h.vertices) min_depth = std::min(min_depth, -(view * hv).z);
        const bool back = !front_only && !(min_depth > znear * 1.001f);  // the hull reaches the near plane: its back faces
        for (int k = 0; k < 24; ++k) (back ? local_back : local_front).push_back(6 * id + h.indices[k]);
        for (const glm::vec4& hv : h.vertices) g.vertices.push_back({hv, id, {0, 0, 0}});
        ++(back ? g.back : g.front);
    }
    g.indices = local_front;
    g.indices.insert(g.indices.end(), local_back.begin(), local_back.end());
    return g;
}

// push constants of every pass-1/2 stage: the camera, the light's center (w = 1), the sphere (center, radius)
struct WedgePush {
    glm::mat4 view_proj;
    glm::vec4 light_position, sphere;
};
const char* kWedgeScenePush = R"(
layout(push_constant) uniform Push { mat4 view_proj; vec4 light_position; vec4 sphere; } pc;
)";
// the volumes (shadow_volume.glsl) and the wedges (penumbra_wedge.glsl), after both snippets
const char* kWedgePassGlsl = R"(
layout(push_constant) uniform Push { mat4 view_proj; vec4 light_position; vec4 sphere; } pc;
#if defined(SK_VOLUME_VS)
layout(location = 0) in vec4 a_position;
void main() { gl_Position = pc.view_proj * sk_extrude_shadow_volume(a_position, pc.light_position); }
#elif defined(SK_WEDGE_VS)
layout(location = 0) in vec4 a_position;  // hull vertex (world)
layout(location = 1) in uint a_wedge;
layout(location = 0) flat out uint v_wedge;
void main() {
    v_wedge = a_wedge;
    gl_Position = pc.view_proj * a_position;
}
#else
struct SkWedge { vec4 outer_bound; vec4 inner_bound; vec4 side0; vec4 side1; vec4 e0; vec4 e1; };
layout(set = 0, binding = 0, std430) readonly buffer SkWedges { SkWedge u_wedges[]; };
layout(set = 0, binding = 1) uniform sampler2D u_world;
layout(location = 0) flat in uint v_wedge;
layout(location = 0) out float o_coverage;
void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    SkWedge w = u_wedges[v_wedge];
    vec4 pk = texelFetch(u_world, px, 0);
    if (pk.w < 0.5) discard;  // background
    if (!sk_wedge_inside4(vec4(pk.xyz, 1.0), w.outer_bound, w.inner_bound, w.side0, w.side1)) discard;
    o_coverage = sk_wedge_edge_coverage(w.e0.xyz, w.e1.xyz, vec4(pc.sphere.xyz, 1.0), pc.sphere.w, pk.xyz);
}
#endif
)";
const char* kWedgePassHlsl = R"(
struct Push { column_major float4x4 view_proj; float4 light_position; float4 sphere; };
[[vk::push_constant]] ConstantBuffer<Push> pc;
struct SkWedge { float4 outer_bound; float4 inner_bound; float4 side0; float4 side1; float4 e0; float4 e1; };
[[vk::binding(0, 0)]] StructuredBuffer<SkWedge> u_wedges;
[[vk::binding(1, 0)]] Texture2D<float4> u_world;
struct WedgeOut { float4 position : SV_Position; [[vk::location(0)]] nointerpolation uint wedge : WEDGE; };
// the scene's vertex stage in the language under test too: its lit faces and the volumes' light caps
// then come out of the same arithmetic (mul) at the same depths, as z-fail needs
struct SceneOut { float4 position : SV_Position; [[vk::location(0)]] float3 world : WORLD; [[vk::location(1)]] float3 normal : NORMAL; };
SceneOut vs_scene([[vk::location(0)]] float3 position : POSITION, [[vk::location(1)]] float3 normal : NORMAL) {
    SceneOut o;
    o.world = position;
    o.normal = normal;
    o.position = mul(pc.view_proj, float4(position, 1.0));
    return o;
}
float4 vs_volume([[vk::location(0)]] float4 position : POSITION) : SV_Position {
    return mul(pc.view_proj, sk_extrude_shadow_volume(position, pc.light_position));
}
WedgeOut vs_wedge([[vk::location(0)]] float4 position : POSITION, [[vk::location(1)]] uint wedge : WEDGE) {
    WedgeOut o;
    o.wedge = wedge;
    o.position = mul(pc.view_proj, position);
    return o;
}
float ps_wedge(WedgeOut i) : SV_Target0 {
    int2 px = int2(i.position.xy);
    SkWedge w = u_wedges[i.wedge];
    float4 pk = u_world.Load(int3(px, 0));
    if (pk.w < 0.5) discard;
    if (!sk_wedge_inside4(float4(pk.xyz, 1.0), w.outer_bound, w.inner_bound, w.side0, w.side1)) discard;
    return sk_wedge_edge_coverage(w.e0.xyz, w.e1.xyz, float4(pc.sphere.xyz, 1.0), pc.sphere.w, pk.xyz);
}
)";
// the last pass: the stencil's count (8 bits, read as signed) and the coverage sum
const char* kCombineGlsl = R"(
layout(set = 0, binding = 0) uniform sampler2D u_coverage;
layout(set = 0, binding = 1) uniform usampler2D u_stencil;
layout(location = 0) out vec4 o_v;
void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    uint s = texelFetch(u_stencil, px, 0).r & 255u;
    float hard = float(int(s) - (s >= 128u ? 256 : 0));
    float sum = texelFetch(u_coverage, px, 0).r;
    o_v = vec4(sk_wedge_visibility(hard, sum), hard, sum, 1.0);
}
)";
const char* kCombineHlsl = R"(
[[vk::binding(0, 0)]] Texture2D<float> u_coverage;
[[vk::binding(1, 0)]] Texture2D<uint> u_stencil;
float4 vs_full(uint id : SV_VertexID) : SV_Position {
    float2 p = float2(float((id << 1) & 2), float(id & 2));
    return float4(p * 2.0 - 1.0, 0.0, 1.0);
}
float4 ps_combine(float4 position : SV_Position) : SV_Target0 {
    int3 px = int3(int2(position.xy), 0);
    uint s = u_stencil.Load(px) & 255u;
    float hard = float(int(s) - (s >= 128u ? 256 : 0));
    float sum = u_coverage.Load(px);
    return float4(sk_wedge_visibility(hard, sum), hard, sum, 1.0);
}
)";

struct WedgeShaders {
    std::vector<std::uint32_t> scene_vs, scene_fs, volume_vs, wedge_vs, wedge_fs, full_vs, combine_fs;
    const char *scene_entry = "main", *volume_entry = "main", *wedge_vs_entry = "main", *wedge_fs_entry = "main", *full_entry = "main",
               *combine_entry = "main";
};
WedgeShaders compile_wedge_shaders(Source lang) {
    WedgeShaders w;
    const VkShaderStageFlagBits V = VK_SHADER_STAGE_VERTEX_BIT, F = VK_SHADER_STAGE_FRAGMENT_BIT;
    w.scene_fs = skvk::compile_checked(Source::Glsl, F, skvk::kGbufferGlslFs, "main", "wedges.scene.frag");
    if (lang == Source::Glsl) {
        const std::string head = "#version 450 core\n" + skvk::read_text(std::string(SHADOWKIT_GLSL_DIR) + "/shadow_volume.glsl") +
                                 "\n" + skvk::read_text(std::string(SHADOWKIT_GLSL_DIR) + "/penumbra_wedge.glsl") + "\n";
 w.scene_vs = skvk::compile_checked(lang, V, skvk::receiver_glsl_vs(kWedgeScenePush, "pc.view_proj"), "main", "wedges.glsl.scene.vert");
        w.volume_vs = skvk::compile_checked(lang, V, head + "#define SK_VOLUME_VS 1\n" + kWedgePassGlsl, "main", "wedges.glsl.volume.vert");
        w.wedge_vs = skvk::compile_checked(lang, V, head + "#define SK_WEDGE_VS 1\n" + kWedgePassGlsl, "main", "wedges.glsl.wedge.vert");
        w.wedge_fs = skvk::compile_checked(lang, F, head + kWedgePassGlsl, "main", "wedges.glsl.wedge.frag");
        w.full_vs = skvk::compile_checked(lang, V, skvk::kFullscreenGlsl, "main", "wedges.glsl.full.vert");
        w.combine_fs = skvk::compile_checked(lang, F, head + kCombineGlsl, "main", "wedges.glsl.combine.frag");
    } else {
        const std::string head = skvk::read_text(std::string(SHADOWKIT_HLSL_DIR) + "/shadow_volume.hlsl") + "\n" +
                                 skvk::read_text(std::string(SHADOWKIT_HLSL_DIR) + "/penumbra_wedge.hlsl") + "\n";
        w.scene_vs = skvk::compile_checked(lang, V, head + kWedgePassHlsl, "vs_scene", "wedges.hlsl.scene.vert");
        w.volume_vs = skvk::compile_checked(lang, V, head + kWedgePassHlsl, "vs_volume", "wedges.hlsl.volume.vert");
        w.wedge_vs = skvk::compile_checked(lang, V, head + kWedgePassHlsl, "vs_wedge", "wedges.hlsl.wedge.vert");
        w.wedge_fs = skvk::compile_checked(lang, F, head + kWedgePassHlsl, "ps_wedge", "wedges.hlsl.wedge.frag");
        w.full_vs = skvk::compile_checked(lang, V, head + kCombineHlsl, "vs_full", "wedges.hlsl.full.vert");
        w.combine_fs = skvk::compile_checked(lang, F, head + kCombineHlsl, "ps_combine", "wedges.hlsl.combine.frag");
        w.scene_entry = "vs_scene";
        w.volume_entry = "vs_volume";
        w.wedge_vs_entry = "vs_wedge";
        w.wedge_fs_entry = "ps_wedge";
        w.full_entry = "vs_full";
        w.combine_entry = "ps_combine";
    }
    return w;
}

struct WedgeRun {
    std::vector<float> world, normal, vis;  ///< RGBA32F each; vis = (V, hard count, coverage sum, 1)
    std::vector<std::uint8_t> stencil;
    std::uint32_t wedges = 0, wedges_back = 0, skipped = 0;
};

VkFormat wedge_depth_stencil_format(skvk::Context& ctx) {
    for (VkFormat f : {VK_FORMAT_D32_SFLOAT_S8_UINT, VK_FORMAT_D24_UNORM_S8_UINT}) {
        VkFormatProperties fp;
        vkGetPhysicalDeviceFormatProperties(ctx.physical, f, &fp);
        const VkFormatFeatureFlags need = VK_FORMAT_FEATURE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT;
        if ((fp.optimalTilingFeatures & need) == need) return f;
    }
    return VK_FORMAT_UNDEFINED;
}

// The pipelines of passes 1 and 2 (the G-buffer; depth, volumes, wedges) and 3 (the combine).
struct WedgePipelines {
    VkPipeline gbuffer = VK_NULL_HANDLE, depth = VK_NULL_HANDLE, volume = VK_NULL_HANDLE, front = VK_NULL_HANDLE,
               back = VK_NULL_HANDLE, combine = VK_NULL_HANDLE;
};
/// The six pipelines, handed to `scope`.
WedgePipelines make_wedge_pipelines(skvk::Context& ctx, skvk::Scope& scope, const WedgeShaders& sh, VkPipelineLayout layout, VkPipelineLayout combine_layout,
                                    VkRenderPass gbuffer_rp, VkRenderPass main_rp, VkRenderPass combine_rp) {
    WedgePipelines p;
    std::string why;
    // the scene: reversed-Z depth (GREATER), back faces culled
    skvk::PipelineDesc sd = skvk::scene_pipeline(sh.scene_vs, sh.scene_fs, sh.scene_entry);
    sd.depth_compare = VK_COMPARE_OP_GREATER;
    sd.cull = VK_CULL_MODE_BACK_BIT;
    sd.color_count = 2;
    p.gbuffer = scope.keep(skvk::make_pipeline(ctx, sd, layout, gbuffer_rp, why), vkDestroyPipeline);
    sd.fs.clear();  // the same depth again in pass 2, no colour
    sd.color_count = 1;
    sd.color_write = false;
    p.depth = scope.keep(skvk::make_pipeline(ctx, sd, layout, main_rp, why), vkDestroyPipeline);
    skvk::PipelineDesc vd;  // z-fail, two-sided stencil
    vd.vs = sh.volume_vs;
    vd.vs_entry = sh.volume_entry;
    vd.vertex_stride = sizeof(glm::vec4);
    vd.attributes = {{0, 0, VK_FORMAT_R32G32B32A32_SFLOAT, 0}};
    vd.depth_compare = VK_COMPARE_OP_GREATER;
    vd.depth_write = false;
    vd.color_count = 1;
    vd.color_write = false;
    vd.stencil = true;
    vd.stencil_back = {VK_STENCIL_OP_KEEP, VK_STENCIL_OP_KEEP, VK_STENCIL_OP_INCREMENT_AND_WRAP, VK_COMPARE_OP_ALWAYS, 0xff, 0xff, 0};
    vd.stencil_front = {VK_STENCIL_OP_KEEP, VK_STENCIL_OP_KEEP, VK_STENCIL_OP_DECREMENT_AND_WRAP, VK_COMPARE_OP_ALWAYS, 0xff, 0xff, 0};
    p.volume = scope.keep(skvk::make_pipeline(ctx, vd, layout, main_rp, why), vkDestroyPipeline);
    skvk::PipelineDesc wd;  // the hulls: depth-tested, no depth writes, additive into the coverage sum
    wd.vs = sh.wedge_vs;
    wd.fs = sh.wedge_fs;
    wd.vs_entry = sh.wedge_vs_entry;
    wd.fs_entry = sh.wedge_fs_entry;
    wd.vertex_stride = sizeof(HullVertex);
    wd.attributes = {{0, 0, VK_FORMAT_R32G32B32A32_SFLOAT, 0}, {1, 0, VK_FORMAT_R32_UINT, 16}};
    wd.depth_write = false;
    wd.color_count = 1;
    wd.blend = true;  // additive: ADD, ONE, ONE (the defaults)
    wd.depth_compare = VK_COMPARE_OP_GREATER_OR_EQUAL;  // GL_LEQUAL turned around (reversed-Z)
    wd.cull = VK_CULL_MODE_BACK_BIT;
    p.front = scope.keep(skvk::make_pipeline(ctx, wd, layout, main_rp, why), vkDestroyPipeline);
    wd.depth_compare = VK_COMPARE_OP_LESS_OR_EQUAL;  // GL_GEQUAL turned around
    wd.cull = VK_CULL_MODE_FRONT_BIT;
    p.back = scope.keep(skvk::make_pipeline(ctx, wd, layout, main_rp, why), vkDestroyPipeline);
    skvk::PipelineDesc cd;
    cd.vs = sh.full_vs;
    cd.fs = sh.combine_fs;
    cd.vs_entry = sh.full_entry;
    cd.fs_entry = sh.combine_entry;
    cd.depth_test = cd.depth_write = false;
    cd.color_count = 1;
    p.combine = scope.keep(skvk::make_pipeline(ctx, cd, combine_layout, combine_rp, why), vkDestroyPipeline);
    for (VkPipeline q : {p.gbuffer, p.depth, p.volume, p.front, p.back, p.combine}) REQUIRE_MESSAGE(q != VK_NULL_HANDLE, why);
    return p;
}

void begin_pass(VkCommandBuffer cmd, VkRenderPass rp, VkFramebuffer fb, const std::vector<VkClearValue>& clears) {
    VkRenderPassBeginInfo bi{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    bi.renderPass = rp;
    bi.framebuffer = fb;
    bi.renderArea = {{0, 0}, {kW, kH}};
    bi.clearValueCount = static_cast<std::uint32_t>(clears.size());
    bi.pClearValues = clears.data();
    vkCmdBeginRenderPass(cmd, &bi, VK_SUBPASS_CONTENTS_INLINE);
    const VkViewport vp = skvk::viewport(kW, kH, true);
    const VkRect2D sc{{0, 0}, {kW, kH}};
    vkCmdSetViewport(cmd, 0, 1, &vp);
    vkCmdSetScissor(cmd, 0, 1, &sc);
}

/// A host-visible buffer holding `v` (at least one byte), owned by `scope`.
template <class T>
skvk::Buffer& upload(skvk::Context& ctx, skvk::Scope& scope, const std::vector<T>& v, VkBufferUsageFlags usage) {
    skvk::Buffer& b = scope.own<skvk::Buffer>();
    REQUIRE(skvk::make_buffer(ctx, std::max<std::size_t>(1, v.size()) * sizeof(T), usage, b));
    if (!v.empty()) std::memcpy(b.mapped, v.data(), v.size() * sizeof(T));
    return b;
}

struct WedgeCamera {
    glm::vec3 eye{0.f, 3.5f, 5.f}, target{0.f, 0.3f, 0.f};
    bool front_only = false;  ///< control: every hull drawn with its front faces, also where it reaches the near plane
};

WedgeRun run_wedge_passes(Source lang, const WedgeScene& scene, const CpuSide& cpu, float radius, const WedgeCamera& cam) {
    skvk::Context& ctx = skvk::vk_test_context();
    skvk::Scope scope(ctx);
    const float fovy = 0.9f, aspect = float(kW) / float(kH), znear = 0.1f;
    const float eps = shadowkit::projection_infinite_epsilon_bound(fovy, aspect, shadowkit::ClipDepth::ZeroToOne, true,
                                                                   shadowkit::DepthFormat::Float32).epsilon;
    const shadowkit::ProjectionResult pr =
        shadowkit::projection_perspective_infinite(fovy, aspect, znear, shadowkit::ClipDepth::ZeroToOne, true, eps);
    REQUIRE(pr.status == shadowkit::Status::Ok);
    const glm::mat4 view = glm::lookAt(cam.eye, cam.target, glm::vec3(0.f, 1.f, 0.f));
    const shadowkit::PenumbraSphereLight light{glm::vec4(scene.light, 1.f), radius};
    const WedgePush push{pr.matrix * view, glm::vec4(scene.light, 1.f), glm::vec4(scene.light, radius)};
    const GpuWedges gw = build_wedges(scene, cpu, light, view, znear, cam.front_only);
    WedgeRun out;
    out.wedges = gw.front + gw.back;
    out.wedges_back = gw.back;
    out.skipped = gw.skipped;

    const WedgeShaders sh = compile_wedge_shaders(lang);
    const VkFormat dsf = wedge_depth_stencil_format(ctx);
    REQUIRE_MESSAGE(dsf != VK_FORMAT_UNDEFINED, "no sampled depth-stencil format");
    const VkImageUsageFlags rt = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
    skvk::Image& world = scope.own<skvk::Image>();
    skvk::Image& normal = scope.own<skvk::Image>();
    skvk::Image& gdepth = scope.own<skvk::Image>();
    skvk::Image& coverage = scope.own<skvk::Image>();
    skvk::Image& ds = scope.own<skvk::Image>();
    skvk::Image& vis = scope.own<skvk::Image>();
    REQUIRE(skvk::make_image(ctx, kW, kH, 1, VK_FORMAT_R32G32B32A32_SFLOAT, rt, world));
    REQUIRE(skvk::make_image(ctx, kW, kH, 1, VK_FORMAT_R32G32B32A32_SFLOAT, rt, normal));
    REQUIRE(skvk::make_image(ctx, kW, kH, 1, VK_FORMAT_D32_SFLOAT, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, gdepth));
    REQUIRE(skvk::make_image(ctx, kW, kH, 1, VK_FORMAT_R32_SFLOAT, rt, coverage));
    REQUIRE(skvk::make_image(ctx, kW, kH, 1, dsf,
                             VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_SAMPLED_BIT, ds));
    REQUIRE(skvk::make_image(ctx, kW, kH, 1, VK_FORMAT_R32G32B32A32_SFLOAT, rt, vis));
    VkImageViewCreateInfo vi{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};  // the stencil aspect, sampled in pass 3
    vi.image = ds.image;
    vi.viewType = VK_IMAGE_VIEW_TYPE_2D;
    vi.format = dsf;
    vi.subresourceRange = {VK_IMAGE_ASPECT_STENCIL_BIT, 0, 1, 0, 1};
    VkImageView stencil_view = VK_NULL_HANDLE;
    REQUIRE(vkCreateImageView(ctx.device, &vi, nullptr, &stencil_view) == VK_SUCCESS);
    scope.keep(stencil_view, vkDestroyImageView);

    VkRenderPass gbuffer_rp = scope.keep(skvk::make_render_pass(ctx, {VK_FORMAT_R32G32B32A32_SFLOAT, VK_FORMAT_R32G32B32A32_SFLOAT},
                                                     VK_FORMAT_D32_SFLOAT, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL), vkDestroyRenderPass);
    VkRenderPass main_rp = scope.keep(skvk::make_render_pass(ctx, {VK_FORMAT_R32_SFLOAT}, dsf, VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL), vkDestroyRenderPass);
    VkRenderPass combine_rp = scope.keep(skvk::make_render_pass(ctx, {VK_FORMAT_R32G32B32A32_SFLOAT}, VK_FORMAT_UNDEFINED, VK_IMAGE_LAYOUT_UNDEFINED), vkDestroyRenderPass);
    VkFramebuffer gbuffer_fb = scope.keep(skvk::make_framebuffer(ctx, gbuffer_rp, {world.view, normal.view, gdepth.view}, kW, kH), vkDestroyFramebuffer);
    VkFramebuffer main_fb = scope.keep(skvk::make_framebuffer(ctx, main_rp, {coverage.view, ds.view}, kW, kH), vkDestroyFramebuffer);
    VkFramebuffer combine_fb = scope.keep(skvk::make_framebuffer(ctx, combine_rp, {vis.view}, kW, kH), vkDestroyFramebuffer);

    const bool glsl = lang == Source::Glsl;
    const VkDescriptorType tex = skvk::texture_type(lang);
    const VkShaderStageFlags F = VK_SHADER_STAGE_FRAGMENT_BIT;
    VkSampler nearest = scope.keep(skvk::make_sampler(ctx, VK_FILTER_NEAREST, VK_COMPARE_OP_NEVER), vkDestroySampler);
    skvk::Buffer& vb = upload(ctx, scope, scene.vertices, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
    skvk::Buffer& volume_vb = upload(ctx, scope, cpu.volume_vertices, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
    skvk::Buffer& volume_ib = upload(ctx, scope, cpu.volume_indices, VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
    skvk::Buffer& hull_vb = upload(ctx, scope, gw.vertices, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
    skvk::Buffer& hull_ib = upload(ctx, scope, gw.indices, VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
    skvk::Buffer& wedges = upload(ctx, scope, gw.data, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    skvk::DescriptorSet& set = scope.own<skvk::DescriptorSet>();
    skvk::DescriptorSet& combine_set = scope.own<skvk::DescriptorSet>();
    REQUIRE(skvk::make_descriptor_set(ctx, {{0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, F}, {1, tex, F}}, set));
    skvk::write_buffer(ctx, set, 0, wedges, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
    skvk::write_image(ctx, set, 1, tex, world.view, glsl ? nearest : VK_NULL_HANDLE, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    REQUIRE(skvk::make_descriptor_set(ctx, {{0, tex, F}, {1, tex, F}}, combine_set));
    skvk::write_image(ctx, combine_set, 0, tex, coverage.view, glsl ? nearest : VK_NULL_HANDLE, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    skvk::write_image(ctx, combine_set, 1, tex, stencil_view, glsl ? nearest : VK_NULL_HANDLE,
                      VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL);
    VkPipelineLayout layout = scope.keep(skvk::make_pipeline_layout(ctx, &set, sizeof(WedgePush), VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT), vkDestroyPipelineLayout);
    VkPipelineLayout combine_layout = scope.keep(skvk::make_pipeline_layout(ctx, &combine_set), vkDestroyPipelineLayout);
    WedgePipelines p = make_wedge_pipelines(ctx, scope, sh, layout, combine_layout, gbuffer_rp, main_rp, combine_rp);

    VkCommandBuffer cmd = skvk::begin_commands(ctx);
    const VkShaderStageFlags push_stages = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
    const VkDeviceSize offset = 0;
    VkClearValue zero{}, ds_clear{};
    ds_clear.depthStencil = {0.f, 0};  // reversed-Z: far (and infinity) is 0
    // 1. the G-buffer (world point, normal)
    begin_pass(cmd, gbuffer_rp, gbuffer_fb, {zero, zero, ds_clear});
    vkCmdPushConstants(cmd, layout, push_stages, 0, sizeof push, &push);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p.gbuffer);
    vkCmdBindVertexBuffers(cmd, 0, 1, &vb.buffer, &offset);
    vkCmdDraw(cmd, static_cast<std::uint32_t>(scene.vertices.size()), 1, 0, 0);
    vkCmdEndRenderPass(cmd);
    skvk::transition(cmd, world, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    // 2. the scene's depth, the hard counts in the stencil, the wedges into the coverage sum
    begin_pass(cmd, main_rp, main_fb, {zero, ds_clear});
    vkCmdPushConstants(cmd, layout, push_stages, 0, sizeof push, &push);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout, 0, 1, &set.set, 0, nullptr);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p.depth);
    vkCmdBindVertexBuffers(cmd, 0, 1, &vb.buffer, &offset);
    vkCmdDraw(cmd, static_cast<std::uint32_t>(scene.vertices.size()), 1, 0, 0);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p.volume);
    vkCmdBindVertexBuffers(cmd, 0, 1, &volume_vb.buffer, &offset);
    vkCmdBindIndexBuffer(cmd, volume_ib.buffer, 0, VK_INDEX_TYPE_UINT32);
    vkCmdDrawIndexed(cmd, static_cast<std::uint32_t>(cpu.volume_indices.size()), 1, 0, 0, 0);
    if (out.wedges) {
        vkCmdBindVertexBuffers(cmd, 0, 1, &hull_vb.buffer, &offset);
        vkCmdBindIndexBuffer(cmd, hull_ib.buffer, 0, VK_INDEX_TYPE_UINT32);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p.front);
        if (gw.front) vkCmdDrawIndexed(cmd, 24 * gw.front, 1, 0, 0, 0);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p.back);
        if (gw.back) vkCmdDrawIndexed(cmd, 24 * gw.back, 1, 24 * gw.front, 0, 0);
    }
    vkCmdEndRenderPass(cmd);
    skvk::transition(cmd, coverage, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    // 3. V = sk_wedge_visibility(stencil count, coverage sum)
    begin_pass(cmd, combine_rp, combine_fb, {zero});
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p.combine);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, combine_layout, 0, 1, &combine_set.set, 0, nullptr);
    vkCmdDraw(cmd, 3, 1, 0, 0);
    vkCmdEndRenderPass(cmd);
    REQUIRE(skvk::submit_and_wait(ctx, cmd));

    out.world = skvk::read_image(ctx, world, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, 4);
    out.normal = skvk::read_image(ctx, normal, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 4);
    out.vis = skvk::read_image(ctx, vis, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 4);
    out.stencil = skvk::read_stencil(ctx, ds, VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL);

    return out;
}

// The GL test's (d): V against penumbra_visibility at every second pixel away from changes of the CPU's
// hard count (where the rasterized volume and the ray test may disagree by a pixel), receivers facing
// the light; and the hard count against the stencil there.
struct WedgeCompare {
    double max_d = 0.0, sum_d = 0.0;
    std::size_t n = 0, soft = 0, hard_agree = 0, hard_n = 0, shadowed = 0, off = 0;  ///< off: |V_gpu - V_cpu| > 0.05
    std::size_t combine_exact = 0;  ///< pixels where V == 1 - clamp(stencil + sum) as the CPU computes it from the read-back values
};
WedgeCompare compare_wedges(const WedgeScene& s, const CpuSide& cpu, const WedgeRun& r, float radius) {
    const shadowkit::PenumbraSphereLight light{glm::vec4(s.light, 1.f), radius};
    const std::size_t N = std::size_t(kW) * kH;
    std::vector<int> count(N, -1);
    for (std::size_t k = 0; k < N; ++k)
        if (r.world[4 * k + 3] > 0.5f) count[k] = cpu_hard_count(cpu, glm::vec3(r.world[4 * k], r.world[4 * k + 1], r.world[4 * k + 2]), s.light);
    WedgeCompare c;
    for (std::size_t k = 0; k < N; ++k) {
        const auto sv = static_cast<int>(r.stencil[k] >= 128 ? int(r.stencil[k]) - 256 : int(r.stencil[k]));
        const float expect = 1.f - std::min(1.f, std::max(0.f, float(sv) + r.vis[4 * k + 2]));
        c.combine_exact += r.vis[4 * k] == expect && r.vis[4 * k + 1] == float(sv);
    }
    for (std::uint32_t y = 1; y + 1 < kH; y += 2)
        for (std::uint32_t x = 1; x + 1 < kW; x += 2) {
            const std::size_t k = std::size_t(y) * kW + x;
            if (count[k] < 0) continue;
            const glm::vec3 p(r.world[4 * k], r.world[4 * k + 1], r.world[4 * k + 2]);
            const glm::vec3 n(r.normal[4 * k], r.normal[4 * k + 1], r.normal[4 * k + 2]);
            if (glm::dot(n, s.light - p) <= 0.f) continue;  // facing away: not compared by the GL test either
            bool edge = false;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int q = count[std::size_t(int(k) + dy * int(kW) + dx)];
                    edge = edge || (q >= 0 && q != count[k]);
                }
            if (edge) continue;
            ++c.hard_n;
            c.hard_agree += (r.stencil[k] > 0) == (count[k] > 0);
            c.shadowed += count[k] > 0;
            const shadowkit::PenumbraValue v = shadowkit::penumbra_visibility(cpu.edges.data(), cpu.edges.size() / 2, light, p, count[k]);
            REQUIRE(v.status == shadowkit::Status::Ok);
            const double d = std::abs(double(r.vis[4 * k]) - v.value);
            c.max_d = std::max(c.max_d, d);
            c.sum_d += d;
            c.off += d > 0.05;
            ++c.n;
            c.soft += v.value > 0.0 && v.value < 1.0;
        }
    return c;
}

void check_wedge_passes(Source lang) {
    const WedgeScene scene;
    const CpuSide cpu = build_cpu_side(scene);
    const std::string name = lang == Source::Glsl ? "GLSL" : "HLSL";
    for (const float radius : {0.f, 0.5f}) {
        const std::size_t before = skvk::message_count();
        const WedgeRun r = run_wedge_passes(lang, scene, cpu, radius, WedgeCamera{});
        REQUIRE(r.vis.size() == std::size_t(kW) * kH * 4);
        REQUIRE(r.stencil.size() == std::size_t(kW) * kH);
        const WedgeCompare c = compare_wedges(scene, cpu, r, radius);
        INFO(name << ", light radius " << radius);
        MESSAGE(name << ", light radius " << radius << ": " << r.wedges << " wedges (" << r.wedges_back << " with back faces, "
                     << r.skipped << " skipped) of " << cpu.edges.size() / 2 << " silhouette edges; " << c.n
                     << " sampled pixels (" << c.soft << " in a penumbra, " << c.shadowed << " in the hard shadow): max |V_gpu - V_cpu| "
                     << c.max_d << ", mean " << c.sum_d / double(std::max<std::size_t>(c.n, 1)) << "; stencil vs CPU count "
                     << c.hard_agree << " of " << c.hard_n << "; combine exact on " << c.combine_exact << " of " << kW * kH);
        CHECK(c.combine_exact == std::size_t(kW) * kH);
        CHECK(c.n > 5000);
        CHECK(c.shadowed > 300);
        CHECK(double(c.hard_agree) >= 0.998 * double(c.hard_n));
        CHECK(c.max_d < 1e-4);
        CHECK(c.sum_d / double(c.n) < 1e-6);
        if (radius > 0.f) {
            CHECK(r.wedges >= 8);
            CHECK(c.soft > 200);
        } else {
            CHECK(r.wedges == 0);
            CHECK(c.soft == 0);
        }
        CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());
    }
}

// The GL test's (f): the eye inside the wedge of one of the lower box's top edges (the middle of its rays,
// 0.35 above the floor), looking across the penumbra on the floor. Hulls reaching the near plane are drawn
// with their back faces (LESS_OR_EQUAL, front faces culled); drawn with their front faces instead (the
// control) the pixels inside them lose their coverage.
WedgeCamera camera_in_wedge(const WedgeScene& s, const CpuSide& cpu, float radius) {
    const shadowkit::PenumbraSphereLight light{glm::vec4(s.light, 1.f), radius};
    for (std::size_t e = 0; e + 1 < cpu.edges.size(); e += 2) {
        const shadowkit::PenumbraWedge w = shadowkit::penumbra_wedge(cpu.edges[e], cpu.edges[e + 1], light);
        if (w.status != shadowkit::Status::Ok || w.skip != shadowkit::PenumbraWedgeSkip::None) continue;
        const glm::vec3 a = 0.5f * (w.apex[0] + w.apex[1]);
        if (a.y < 1.f || a.y > 1.2f || a.x > -0.2f) continue;  // a top edge of the lower box, on the side away from the light
        const glm::vec3 dir = glm::normalize(w.ray_outer[0] + w.ray_outer[1] + w.ray_inner[0] + w.ray_inner[1]);
        if (dir.y > -0.1f) continue;
        const glm::vec3 eye = a + dir * ((a.y - 0.35f) / -dir.y);
        if (!shadowkit::penumbra_point_in_wedge(eye, w)) continue;
        WedgeCamera c;
        c.eye = eye;
        c.target = eye + glm::vec3(dir.x, 0.f, dir.z) * 2.f - glm::vec3(0.f, 0.6f, 0.f);
        return c;
    }
    FAIL("no wedge to put the eye in");
    return {};
}

void check_camera_in_wedge(Source lang) {
    const WedgeScene scene;
    const CpuSide cpu = build_cpu_side(scene);
    const float radius = 0.5f;
    WedgeCamera cam = camera_in_wedge(scene, cpu, radius);
    const std::string name = lang == Source::Glsl ? "GLSL" : "HLSL";
    for (const bool front_only : {false, true}) {
        cam.front_only = front_only;
        const std::size_t before = skvk::message_count();
        const WedgeRun r = run_wedge_passes(lang, scene, cpu, radius, cam);
        REQUIRE(r.vis.size() == std::size_t(kW) * kH * 4);
        const WedgeCompare c = compare_wedges(scene, cpu, r, radius);
        const std::string variant = front_only ? ", every hull with its front faces (control)" : "";
        INFO(name << variant);
        MESSAGE(name << ", eye " << cam.eye.x << " " << cam.eye.y << " " << cam.eye.z << " inside a wedge"
                     << variant << ": " << r.wedges << " wedges ("
                     << r.wedges_back << " with back faces); " << c.n << " sampled pixels (" << c.soft
                     << " in a penumbra): max |V_gpu - V_cpu| " << c.max_d << ", mean " << c.sum_d / double(std::max<std::size_t>(c.n, 1))
                     << ", off by > 0.05: " << c.off);
        CHECK(c.n > 2000);
        CHECK_MESSAGE(skvk::message_count() == before, skvk::messages());
        if (front_only) {
            CHECK(c.off > 100);
            continue;
        }
        CHECK(r.wedges_back >= 1);
        CHECK(c.soft > 200);
        CHECK(c.max_d < 1e-4);
        CHECK(c.sum_d / double(c.n) < 1e-6);
    }
}

}  // namespace

TEST_CASE("penumbra_wedge.glsl on Vulkan: edge coverage equals penumbra_edge_coverage, world from [0,1] depth") {
    run_wedge(Source::Glsl);
}

TEST_CASE("HLSL penumbra_wedge.hlsl on Vulkan: edge coverage equals penumbra_edge_coverage, world from [0,1] depth") {
    run_wedge(Source::Hlsl);
}

TEST_CASE("penumbra_wedge.glsl on Vulkan: the wedge passes (stencil volumes, hulls, additive coverage, combine) equal penumbra_visibility") {
    check_wedge_passes(Source::Glsl);
}

TEST_CASE("HLSL penumbra_wedge.hlsl on Vulkan: the wedge passes (stencil volumes, hulls, additive coverage, combine) equal penumbra_visibility") {
    check_wedge_passes(Source::Hlsl);
}

TEST_CASE("penumbra_wedge.glsl on Vulkan: the eye inside a wedge, its hull drawn with back faces") {
    check_camera_in_wedge(Source::Glsl);
}

TEST_CASE("HLSL penumbra_wedge.hlsl on Vulkan: the eye inside a wedge, its hull drawn with back faces") {
    check_camera_in_wedge(Source::Hlsl);
}
