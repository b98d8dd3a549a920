// Technique drivers: wedge family. "penumbra_wedges": soft shadow volumes (Assarsson & Akenine-Moller
// 2003; Lengyel GDC 2005) composed from silhouette.hpp, shadow_volume.hpp, penumbra_wedge.hpp,
// infinite_projection.hpp and glsl/shadow_volume.glsl + glsl/penumbra_wedge.glsl, the way a user would.
//
// Light. The wedges need a spherical light (center c, radius r). Sphere lights: r = size. Disk lights:
// r = size (the disk's radius; the header models every light as the disk through c facing the receiver,
// so a tilted view of the real disk is not modelled). Rect lights (square, edge = size): rect_radius = 1
// (default) r = size / sqrt(pi), the disk of the square's area (same total occlusion in the middle of a
// penumbra; lowest error on `contact`), rect_radius = 0 r = penumbra_rect_bounding_sphere (the
// circumscribed disk: conservative wedges for the square itself, but the coverage then is that of a
// 1.57x larger disk: too wide penumbrae). Point, spot and directional lights: r = 0 (hard shadows only;
// the sweep skips them). light_scale multiplies r (tests: 0 = the hard limit; the report keeps 1 because
// the reference uses the scene's own light).
//
// Per frame, on the CPU (cpu_ms, median): exactly the shadow_volume driver's stage for the hard volume
// from the light center (facing, silhouette, side quads, LitOnly caps for z-fail casters, per-caster
// z-pass / z-fail choice, shadow_volume_scissor), then one wedge per silhouette edge (penumbra_wedge;
// skipped statuses are counted in work "wedges_skipped"), its hull (penumbra_wedge_hull, extent chosen so
// that the hull contains every wedge point inside the receiver bounds: extent = max distance from the
// apex edge to a receiver-box corner / min over the four rays of dot(ray, axis)), and, with scissor or
// depth bounds on, its scissor rectangle and depth bounds: penumbra_wedge_scissor_in_box, the hull
// clipped to the receiver box (Lengyel clips to the light's bounds; the unclipped hull,
// penumbra_wedge_scissor, reaches below the floor and gave depth bounds that culled nothing); a wedge
// whose clipped hull is empty is culled. Face choice per wedge: the hull's front faces (Lengyel: the depth test
// LEQUAL against the scene depth then rejects hull parts hidden behind the receivers) when every hull
// vertex lies beyond the near plane; otherwise (the camera is inside the wedge, or the hull crosses the
// near plane) its back faces with depth test GEQUAL: for a receiver point p inside the convex hull the
// pixel ray leaves the hull behind p, so exactly one back face covers the pixel and it is never clipped
// by the near plane. Front faces alone miss such pixels (the GL test shows it with faces = 2).
//
// On the GPU (gpu_ms, median of the whole frame): (1) the scene depth into the technique's own
// DEPTH32F_STENCIL8 target: projection 0 blits the G-buffer's depth (finite projection; volumes and hulls
// drawn with the same matrix and GL_DEPTH_CLAMP); projection 1 re-draws the scene depth with the
// epsilon-tweaked infinite projection P_inf of infinite_projection.hpp (epsilon =
// infinite_epsilon_bound(..., Float32)) and draws volumes and hulls with the same P_inf, no depth clamp
// (Everitt & Kilgard's intended use; issue 4). (2) The hard volumes, two-sided stencil (GL_INCR_WRAP /
// GL_DECR_WRAP). (3) The wedge hulls into an R32F accumulation target with GL_FUNC_ADD, GL_ONE/GL_ONE,
// depth test as above, no depth writes; the fragment shader reads the receiver's world position from the
// G-buffer (texelFetch at gl_FragCoord: exact, and the same point the reference uses), discards it
// outside the wedge's four planes (sk_wedge_inside4, world space) and outputs the signed coverage
// sk_wedge_edge_coverage (outer half-wedge > 0, inner < 0: one pass, no separate subtractive buffer).
// Per-wedge data live in a shader storage buffer indexed by a flat per-vertex wedge id, so without a
// scissor all wedges are drawn in two calls (front-face and back-face groups); with the scissor (or the
// native depth-bounds test) one call per wedge. (4) V = 1 - clamp(hard + accumulated, 0, 1) in a full-screen
// pass with the common light rules, hard = the stencil count read through stencil texturing
// (GL_DEPTH_STENCIL_TEXTURE_MODE = GL_STENCIL_INDEX, 8-bit wrap read as signed). The count, not
// (stencil != 0): where an inner half-wedge of one caster (coverage < 0) lies in the umbra of another
// caster (count 2) the count keeps V = 0; (stencil != 0) would give 1 - 0.3. horizon = 1 (default)
// multiplies V by the emitter's fraction above the receiver's tangent plane (the PCSS driver's closed
// form): the reference counts light below that plane as unseen, which the casters' silhouettes do not
// model on the casters' own lit faces (contact: RMSE 0.058 without, 0.009 with it).
//
// Depth bounds: GL_EXT_depth_bounds_test where present (bounds from the matrix of the depth buffer);
// on llvmpipe the GLSL emulation of shadow_volume.glsl: discard when the G-buffer depth at the fragment
// (a texture that is not attached here) lies outside the bounds, computed with the G-buffer's finite
// matrix for either projection (the test is on the receiver's depth, so any matrix works if bounds and
// stored depth share it). The emulation discards before the plane test and the coverage math, so it
// saves shading time, not rasterisation (work fs_invocations, where the pipeline statistics exist).
//
// Params: light_scale (default 1), rect_radius {0, 1} (default 1), horizon {0, 1} (default 1), scissor {0, 1}, depth_bounds {0, 1}
// (scissor rectangles / depth bounds for the hard volumes and the wedges), projection {0, 1}, method
// (hard volumes: 0 z-fail, 1 per caster (default)), faces (0 auto (default), 1 always back faces, 2 always
// front faces: tests only; 2 is wrong when the camera is inside a wedge).
// Work: wedges (built), wedges_skipped, wedges_culled (empty scissor), wedges_back (drawn with back
// faces), silhouette_edges, volume_triangles, wedge_fragments (hull fragments that reach the wedge
// shader's plane test: after scissor, depth test and depth bounds; GL_SAMPLES_PASSED in an instrumented
// pass), wedge_fragments_in (of those, inside the wedge: coverage evaluated), wedge_fragments_unculled
// (no scissor, no depth bounds, no wedge culling), wedge_ms / wedge_ms_unculled (median time of the
// wedge pass alone with the row's culling / without; glFinish + clock), wedge_speedup (their ratio),
// light_radius, depth_bounds_native, projection_epsilon (projection 1), fs_invocations(_unculled)
// (GL_ARB_pipeline_statistics_query: wedge fragment-shader runs; on llvmpipe the scissor is what cuts
// them, the emulated depth bounds only discard after the run starts).
#include <shadowkit/infinite_projection.hpp>
#include <shadowkit/penumbra_wedge.hpp>

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include "driver_util.hpp"
#include "stencil_volumes.hpp"

namespace sk {

namespace {

using volumes::CasterDraw;

// Radius of the spherical light the wedges use (see the header comment).
float wedge_light_radius(const Light& L, int rect_radius, float scale) {
    float r = 0.f;
    if (L.type == LightType::Sphere || L.type == LightType::Disk) {
        r = L.size;
    } else if (L.type == LightType::Rect) {
        if (rect_radius == 0) {
            const glm::vec3 d = glm::normalize(L.direction);
            const glm::vec3 a = std::abs(d.y) < 0.9f ? glm::vec3(0.f, 1.f, 0.f) : glm::vec3(1.f, 0.f, 0.f);
            const glm::vec3 t = glm::normalize(glm::cross(a, d)), b = glm::cross(d, t);
            r = shadowkit::penumbra_rect_bounding_sphere(glm::vec4(L.position, 1.f), 0.5f * L.size * t, 0.5f * L.size * b).light.radius;
        } else {
            r = L.size / std::sqrt(3.14159265358979f);
        }
    }
    return std::max(0.f, r * scale);
}


// One wedge as the fragment shader reads it (std430: 7 vec4).
struct WedgeGpu {
    glm::vec4 outer_bound, inner_bound, side0, side1, e0, e1, bounds;
};

struct WedgeDraw {
    bool back = false;     // draw the hull's back faces
    bool visible = true;   // scissor rectangle not empty (always true without culling)
    shadowkit::ScissorRect sc;
};

struct FrameStats {
    std::size_t triangles = 0, sil_edges = 0, zfail = 0, culled = 0;
    std::size_t wedges = 0, skipped = 0, wedges_culled = 0, wedges_back = 0;
};

const char* kWedgeVS = R"(
layout(location = 0) in vec4 a_position;  // hull vertex (world)
layout(location = 1) in uint a_wedge;
uniform mat4 u_view_proj;
flat out uint v_wedge;
void main() {
    v_wedge = a_wedge;
    gl_Position = u_view_proj * a_position;
}
)";
const char* kWedgeFS = R"(
struct SkWedge { vec4 outer_bound; vec4 inner_bound; vec4 side0; vec4 side1; vec4 e0; vec4 e1; vec4 bounds; };
layout(std430, binding = 0) readonly buffer SkWedges { SkWedge u_wedges[]; };
layout(binding = 0) uniform sampler2D u_gbuf_position;
layout(binding = 2) uniform sampler2D u_scene_depth;
uniform vec4 u_sphere_light;  // center, radius
uniform int u_emulate_bounds;
uniform int u_count_reached;  // instrumented pass: stop after the depth-bounds test
flat in uint v_wedge;
layout(location = 0) out float o_coverage;
void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    SkWedge w = u_wedges[v_wedge];
    if (u_emulate_bounds != 0 && sk_outside_depth_bounds_at(u_scene_depth, px, w.bounds.xy)) discard;
    if (u_count_reached != 0) { o_coverage = 0.0; return; }
    vec4 pk = texelFetch(u_gbuf_position, px, 0);
    if (pk.w < 0.5) discard;  // background
    vec4 p = vec4(pk.xyz, 1.0);
    if (!sk_wedge_inside4(p, w.outer_bound, w.inner_bound, w.side0, w.side1)) discard;
    o_coverage = sk_wedge_edge_coverage(w.e0.xyz, w.e1.xyz, vec4(u_sphere_light.xyz, 1.0), u_sphere_light.w, pk.xyz);
}
)";
// The combine multiplies by sk_emitter_horizon (driver_util): the fraction of the emitter above the
// receiver's tangent plane, which the reference counts as unseen and the wedges do not model.
const char* kCombineBody = R"(
layout(binding = 3) uniform sampler2D u_accum;
layout(binding = 4) uniform usampler2D u_stencil;
float technique_visibility(vec3 p, vec3 n) {
    ivec2 px = ivec2(gl_FragCoord.xy);
    uint s = texelFetch(u_stencil, px, 0).r & 255u;
    float hard = float(int(s) - (s >= 128u ? 256 : 0));  // wrapped 8-bit count, signed
    return sk_wedge_visibility(hard, texelFetch(u_accum, px, 0).r) * sk_emitter_horizon(p, n);
}
)";

class PenumbraWedges final : public Technique {
public:
    std::vector<std::pair<std::string, double>> live_params() const override { return {{"light_scale", 1.0}}; }
    std::string name() const override { return "penumbra_wedges"; }
    std::string description() const override {
        return "soft shadow volumes: hard stencil volume from the light center + one penumbra wedge per silhouette "
               "edge (penumbra_wedge.hpp, glsl/penumbra_wedge.glsl), signed analytic coverage added into R32F; "
               "per-wedge scissor and depth bounds; projection 1 = epsilon-tweaked P_inf";
    }
    bool hard() const override { return false; }
    std::vector<ParamSet> sweep(const Scene& scene, bool quick) const override {
        const Light& L = scene.light;
        const bool area = (L.type == LightType::Rect || L.type == LightType::Disk || L.type == LightType::Sphere) &&
                          L.size > 0.f;
        if (!area) return {};  // stack (spot), room (point), outdoor (directional): hard only, see shadow_volume
        auto P = [](int sc, int db, int proj = 0, int rr = 1) {
            ParamSet p{{{"scissor", double(sc)}, {"depth_bounds", double(db)}}};
            if (proj) p.values.push_back({"projection", double(proj)});
            if (rr != 1) p.values.push_back({"rect_radius", double(rr)});
            return p;
        };
        if (quick) return {P(0, 0), P(1, 1)};
        // the middle entry (the sample's default) is the full technique P(1, 1)
        if (L.type == LightType::Rect) return {P(0, 0), P(1, 0), P(0, 1), P(1, 1), P(1, 1, 1), P(1, 1, 0, 0)};
        return {P(0, 0), P(1, 0), P(1, 1), P(0, 1), P(1, 1, 1)};
    }
    RunResult run(const RunContext& ctx, const ParamSet& params) override;

private:
    volumes::VolumeCache cache_;
};

RunResult PenumbraWedges::run(const RunContext& ctx, const ParamSet& params) {
    const float light_scale = static_cast<float>(params.get("light_scale", 1.0));
    const int rect_radius = static_cast<int>(params.get("rect_radius", 1));
    const bool use_scissor = params.get("scissor", 1) != 0.0;
    const bool use_bounds = params.get("depth_bounds", 1) != 0.0;
    const int projection = static_cast<int>(params.get("projection", 0));
    const int method = static_cast<int>(params.get("method", 1));
    const int faces = static_cast<int>(params.get("faces", 0));
    const bool horizon = params.get("horizon", 1) != 0.0;
    const Scene& scene = ctx.scene;
    const SceneGpu& gpu = ctx.gpu;
    if (method < 0 || method > 1) return RunResult::failure("method must be 0 or 1");
    if (projection < 0 || projection > 1) return RunResult::failure("projection must be 0 or 1");
    if (faces < 0 || faces > 2) return RunResult::failure("faces must be 0, 1 or 2");
    if (!(light_scale >= 0.f) || !std::isfinite(light_scale)) return RunResult::failure("light_scale must be >= 0");
    if (!cache_.prepare(scene, 0x3ed9e5ull)) return RunResult::failure(cache_.error);

    const glm::vec4 light = volumes::volume_light(scene.light);
    if (!shadowkit::silhouette_valid_light(light)) return RunResult::failure("invalid light");
    const bool point = light.w > 0.f;
    shadowkit::PenumbraSphereLight sphere;
    sphere.light_position = glm::vec4(scene.light.position, 1.f);
    sphere.radius = point ? wedge_light_radius(scene.light, rect_radius, light_scale) : 0.f;
    const bool soft = sphere.radius > 0.f;

    const int W = gpu.width, H = gpu.height;
    const float aspect = float(W) / float(H);
    const glm::mat4 cam_vp = gpu.proj * gpu.view;  // the G-buffer's matrix
    glm::mat4 draw_vp = cam_vp;                    // volumes, hulls and (projection 1) the own depth pass
    float proj_epsilon = 0.f;
    if (projection == 1) {
        shadowkit::ProjectionDepth dp;
        dp.near_z = scene.camera.znear;
        dp.far_z = std::numeric_limits<float>::infinity();
        const shadowkit::ProjectionEpsilonBound eb = shadowkit::projection_infinite_epsilon_bound(
            scene.camera.fovy, aspect, shadowkit::ClipDepth::NegativeOneToOne, false, shadowkit::DepthFormat::Float32);
        if (eb.status != shadowkit::Status::Ok) return RunResult::failure("infinite_epsilon_bound failed");
        dp.epsilon = eb.epsilon;
        proj_epsilon = eb.epsilon;
        const shadowkit::ProjectionResult pr = shadowkit::projection_perspective(scene.camera.fovy, aspect, dp);
        if (pr.status != shadowkit::Status::Ok) return RunResult::failure("shadowkit::perspective failed");
        draw_vp = pr.matrix * gpu.view;
    }
    const bool native_bounds = use_bounds && epoxy_has_gl_extension("GL_EXT_depth_bounds_test");
    const bool emulate_bounds = use_bounds && !native_bounds;
    // bounds for the emulation are tested against the G-buffer depth (finite matrix); native bounds
    // against the depth buffer drawn with draw_vp
    const glm::mat4 bounds_vp = native_bounds ? draw_vp : cam_vp;

    const volumes::VolumeSetup setup = volumes::make_volume_setup(scene, gpu, light, bounds_vp);
    const glm::vec3 rlo = setup.rlo, rhi = setup.rhi;
    shadowkit::ScissorParams wsp;
    wsp.view_proj = bounds_vp;
    wsp.viewport[2] = W;
    wsp.viewport[3] = H;
    glm::vec3 corners[8];
    for (int i = 0; i < 8; ++i) corners[i] = glm::vec3((i & 1) ? rhi.x : rlo.x, (i & 2) ? rhi.y : rlo.y, (i & 4) ? rhi.z : rlo.z);
    const glm::mat4& V = gpu.view;
    const float near_z = scene.camera.znear;

    std::vector<std::uint32_t> indices(cache_.total_index_capacity);
    std::vector<CasterDraw> draws(cache_.casters.size());
    const std::size_t max_wedges = soft ? cache_.total_sil_capacity : 0;
    std::vector<WedgeGpu> wedges(max_wedges);
    std::vector<WedgeDraw> wdraws(max_wedges);
    std::vector<glm::vec4> hull_verts(6 * max_wedges);
    std::vector<std::uint32_t> hull_wedge(6 * max_wedges);
    std::vector<std::uint32_t> hull_idx(24 * max_wedges);
    std::vector<std::uint8_t> hull_local(24 * max_wedges);
    std::vector<std::uint32_t> order(max_wedges);  // draw order: front visible, front culled, back visible, back culled
    std::size_t group[4] = {0, 0, 0, 0};
    FrameStats stats;
    std::string build_error;
    bool culling = use_scissor || use_bounds;
    std::size_t wedge_count = 0;

    auto build = [&]() -> bool {
        stats = FrameStats{};
        std::size_t nw = 0;
        for (std::size_t ci = 0; ci < cache_.casters.size(); ++ci) {
            volumes::CasterData& c = cache_.casters[ci];
            CasterDraw& d = draws[ci];
            d = CasterDraw{};
            const Mesh& m = scene.meshes[c.mesh];
            if (!volumes::caster_silhouette(c, m, setup, d, build_error)) return false;
            stats.sil_edges += d.sil_edges;
            // wedges: every silhouette edge, also of casters whose hard volume is culled (the penumbra
            // reaches beyond the hard volume)
            for (std::size_t e = 0; soft && e < d.sil_edges; ++e) {
                const glm::vec3 e0 = m.positions[c.sil[2 * e]], e1 = m.positions[c.sil[2 * e + 1]];
                const shadowkit::PenumbraWedge w = shadowkit::penumbra_wedge(e0, e1, sphere);
                if (w.status != shadowkit::Status::Ok || w.skip != shadowkit::PenumbraWedgeSkip::None) {
                    ++stats.skipped;
                    continue;
                }
                float dmax = 0.f;
                for (const glm::vec3& q : corners)
                    dmax = std::max({dmax, glm::length(q - w.apex[0]), glm::length(q - w.apex[1])});
                float cmin = 1.f;
                for (int i = 0; i < 2; ++i)
                    cmin = std::min({cmin, glm::dot(w.ray_outer[i], w.axis), glm::dot(w.ray_inner[i], w.axis)});
                const float extent = dmax / std::max(cmin, 0.05f) * 1.01f;
                const shadowkit::PenumbraWedgeHull h = shadowkit::penumbra_wedge_hull(w, extent);
                if (!h.drawable) {
                    ++stats.skipped;
                    continue;
                }
                WedgeDraw& wd = wdraws[nw];
                wd = WedgeDraw{};
                if (culling) {
                    // the hull clipped to the receiver box (empty: nothing to receive)
                    wd.sc = shadowkit::penumbra_wedge_scissor_in_box(h, rlo, rhi, wsp);
                    wd.visible = wd.sc.status == shadowkit::Status::Ok && wd.sc.visible;
                }
                float min_depth = std::numeric_limits<float>::infinity();
                for (const glm::vec4& hv : h.vertices) min_depth = std::min(min_depth, -(V * hv).z);
                wd.back = faces == 1 || (faces == 0 && !(min_depth > near_z * 1.001f));
                WedgeGpu& g = wedges[nw];
                g.outer_bound = w.outer_bound;
                g.inner_bound = w.inner_bound;
                g.side0 = w.side[0];
                g.side1 = w.side[1];
                g.e0 = glm::vec4(e0, 1.f);
                g.e1 = glm::vec4(e1, 1.f);
                g.bounds = culling && use_bounds ? glm::vec4(wd.sc.depth_min, wd.sc.depth_max, 0.f, 0.f)
                                                 : glm::vec4(-1.f, 2.f, 0.f, 0.f);
                for (std::size_t t = 0; t < 24; ++t) hull_local[24 * nw + t] = h.indices[t];
                for (int i = 0; i < 6; ++i) {
                    hull_verts[6 * nw + std::size_t(i)] = h.vertices[i];
                    hull_wedge[6 * nw + std::size_t(i)] = static_cast<std::uint32_t>(nw);
                }
                ++nw;
                ++stats.wedges;
                if (!wd.visible) ++stats.wedges_culled;
                else if (wd.back) ++stats.wedges_back;
            }
            // hard volume (the shadow_volume driver's CPU stage)
            if (culling) {
                if (!volumes::caster_scissor(c, setup, d, build_error)) return false;
                if (!d.visible) {
                    ++stats.culled;
                    continue;
                }
            }
            if (!volumes::caster_volume(c, m, setup, method, indices.data(), d, build_error)) return false;
            if (d.zfail) ++stats.zfail;
            stats.triangles += (d.side_count + d.cap_count) / 3;
        }
        // draw order and hull indices (24 per wedge, in draw order)
        std::size_t k = 0;
        for (int gi = 0; gi < 4; ++gi) {
            const bool back = gi >= 2, vis = (gi % 2) == 0;
            const std::size_t start = k;
            for (std::size_t i = 0; i < nw; ++i)
                if (wdraws[i].back == back && wdraws[i].visible == vis) order[k++] = static_cast<std::uint32_t>(i);
            group[gi] = k - start;
        }
        wedge_count = nw;
        for (std::size_t j = 0; j < nw; ++j) {
            const std::uint32_t i = order[j];
            for (std::size_t t = 0; t < 24; ++t) hull_idx[24 * j + t] = 6 * i + hull_local[24 * i + t];
        }
        return true;
    };
    RunResult r;
    if (!median_cpu_ms(std::max(ctx.frames, 1), build, r.cpu_ms)) return RunResult::failure(build_error);

    // ------------------------------------------------------------------ GPU resources
    std::string why, log;
    skgl::Target target;  // colour 0: R32F coverage accumulation; DEPTH32F_STENCIL8 (G-buffer format, for the blit)
    if (!skgl::make_target(target, W, H, {GL_R32F}, GL_DEPTH32F_STENCIL8, why)) return RunResult::failure(why);
    VisibilityPass vis_pass;
    if (!vis_pass.init(W, H, why)) {
        skgl::destroy_target(target);
        return RunResult::failure(why);
    }
    const std::string sv_snippet = load_snippet("shadow_volume", why);
    const std::string pw_snippet = load_snippet("penumbra_wedge", why);
    if (sv_snippet.empty() || pw_snippet.empty()) {
        skgl::destroy_target(target);
        return RunResult::failure(why);
    }
    const std::string head = std::string("#version 450 core\n") + sv_snippet + "\n";
    const std::string whead = std::string("#version 450 core\n") + sv_snippet + "\n" + pw_snippet + "\n";
    std::vector<GLuint> programs;
    auto compile = [&](const std::vector<skgl::ShaderStage>& st) {
        const GLuint p = skgl::compile_program(st, log);
        if (p) programs.push_back(p);
        return p;
    };
    volumes::VolumeGpu vol;
    vol.use_scissor = use_scissor;
    vol.native_bounds = native_bounds;
    vol.emulate_bounds = emulate_bounds;
    const GLuint vol_prog = vol.compile(head, emulate_bounds, log);
    const GLuint wedge_prog = compile({{GL_VERTEX_SHADER, whead + kWedgeVS}, {GL_FRAGMENT_SHADER, whead + kWedgeFS}});
    const GLuint comb_prog = compile(
        {{GL_VERTEX_SHADER, fullscreen_vertex_shader()}, {GL_FRAGMENT_SHADER, visibility_fragment_shader(pw_snippet + emitter_horizon_glsl(), kCombineBody)}});
    const GLuint depth_prog = compile({{GL_VERTEX_SHADER, depth_only_vs()}, {GL_FRAGMENT_SHADER, depth_only_fs()}});
    auto cleanup_programs = [&]() {
        for (GLuint p : programs) glDeleteProgram(p);
        programs.clear();
    };
    if (!vol_prog || !wedge_prog || !comb_prog || !depth_prog) {
        cleanup_programs();
        skgl::destroy_target(target);
        return RunResult::failure(log);
    }
    // hard volumes: one static vertex buffer, per caster the 2n-vertex block (p, 1), (p, 0)
    const std::size_t vertex_count = vol.create_buffers(scene, cache_, indices.size());
    GLuint wvao = 0, wvbo[2] = {0, 0}, wibo = 0, wssbo = 0;
    glGenVertexArrays(1, &wvao);
    glGenBuffers(2, wvbo);
    glGenBuffers(1, &wibo);
    glGenBuffers(1, &wssbo);
    glBindVertexArray(wvao);
    glBindBuffer(GL_ARRAY_BUFFER, wvbo[0]);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(std::max<std::size_t>(hull_verts.size(), 1) * sizeof(glm::vec4)),
                 nullptr, GL_DYNAMIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, sizeof(glm::vec4), nullptr);
    glBindBuffer(GL_ARRAY_BUFFER, wvbo[1]);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(std::max<std::size_t>(hull_wedge.size(), 1) * 4), nullptr,
                 GL_DYNAMIC_DRAW);
    glEnableVertexAttribArray(1);
    glVertexAttribIPointer(1, 1, GL_UNSIGNED_INT, 4, nullptr);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, wibo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(std::max<std::size_t>(hull_idx.size(), 1) * 4), nullptr,
                 GL_DYNAMIC_DRAW);
    glBindVertexArray(0);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, wssbo);
    glBufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(std::max<std::size_t>(wedges.size(), 1) * sizeof(WedgeGpu)),
                 nullptr, GL_DYNAMIC_DRAW);
    // stencil texturing of the own depth-stencil texture (read by the combine pass only)
    glBindTexture(GL_TEXTURE_2D, target.depth);
    glTexParameteri(GL_TEXTURE_2D, GL_DEPTH_STENCIL_TEXTURE_MODE, GL_STENCIL_INDEX);
    glBindTexture(GL_TEXTURE_2D, 0);

    vol.set_uniforms(draw_vp, light);
    glUseProgram(wedge_prog);
    glUniformMatrix4fv(glGetUniformLocation(wedge_prog, "u_view_proj"), 1, GL_FALSE, glm::value_ptr(draw_vp));
    glUniform4f(glGetUniformLocation(wedge_prog, "u_sphere_light"), sphere.light_position.x, sphere.light_position.y,
                sphere.light_position.z, sphere.radius);
    const GLint loc_emulate = glGetUniformLocation(wedge_prog, "u_emulate_bounds");
    const GLint loc_count = glGetUniformLocation(wedge_prog, "u_count_reached");
    glUniform1i(loc_count, 0);
    glUseProgram(comb_prog);
    set_light_uniforms(comb_prog, scene.light);
    set_emitter_uniforms(comb_prog, scene.light, horizon && soft && scene.light.is_area());
    glUseProgram(depth_prog);
    glUniformMatrix4fv(glGetUniformLocation(depth_prog, "u_light_view_proj"), 1, GL_FALSE, glm::value_ptr(draw_vp));

    // the wedge pass: hulls into the accumulation target (state set by the caller: colour mask, blend)
    auto draw_wedges = [&](bool cull) {
        if (wedge_count == 0) return;
        glUseProgram(wedge_prog);
        glUniform1i(loc_emulate, cull && emulate_bounds ? 1 : 0);
        glBindVertexArray(wvao);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, wssbo);
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(GL_TEXTURE_2D, gpu.gbuffer.color[0]);
        glActiveTexture(GL_TEXTURE2);
        glBindTexture(GL_TEXTURE_2D, gpu.gbuffer.depth);
        glEnable(GL_DEPTH_TEST);
        glDepthMask(GL_FALSE);
        glEnable(GL_CULL_FACE);
        glFrontFace(GL_CCW);
        if (projection == 0) glEnable(GL_DEPTH_CLAMP);
        const bool per_wedge = cull && (use_scissor || native_bounds);
        std::size_t first = 0;
        for (int gi = 0; gi < 4; ++gi) {
            const std::size_t n = group[gi];
            const bool back = gi >= 2, vis = (gi % 2) == 0;
            const std::size_t begin = first;
            first += n;
            if (n == 0 || (cull && !vis)) continue;
            glCullFace(back ? GL_FRONT : GL_BACK);
            glDepthFunc(back ? GL_GEQUAL : GL_LEQUAL);
            if (!per_wedge) {
                glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(24 * n), GL_UNSIGNED_INT,
                               reinterpret_cast<const void*>(24 * begin * sizeof(std::uint32_t)));
                continue;
            }
            for (std::size_t j = begin; j < begin + n; ++j) {
                const WedgeDraw& wd = wdraws[order[j]];
                if (use_scissor) {
                    glEnable(GL_SCISSOR_TEST);
                    glScissor(wd.sc.x, wd.sc.y, wd.sc.width, wd.sc.height);
                }
                if (native_bounds) {
                    glEnable(GL_DEPTH_BOUNDS_TEST_EXT);
                    glDepthBoundsEXT(wd.sc.depth_min, wd.sc.depth_max);
                }
                glDrawElements(GL_TRIANGLES, 24, GL_UNSIGNED_INT, reinterpret_cast<const void*>(24 * j * sizeof(std::uint32_t)));
            }
        }
        glDisable(GL_SCISSOR_TEST);
        if (native_bounds) glDisable(GL_DEPTH_BOUNDS_TEST_EXT);
        glDisable(GL_CULL_FACE);
        glDisable(GL_DEPTH_CLAMP);
        glDepthFunc(GL_LESS);
        glDepthMask(GL_TRUE);
        glBindVertexArray(0);
    };
    auto begin_accum_state = [&]() {
        glBindFramebuffer(GL_FRAMEBUFFER, target.fbo);
        glViewport(0, 0, W, H);
        glDisable(GL_STENCIL_TEST);
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        glEnable(GL_BLEND);
        glBlendEquation(GL_FUNC_ADD);
        glBlendFunc(GL_ONE, GL_ONE);
    };
    auto upload = [&]() {
        vol.upload(cache_, draws, indices);
        if (wedge_count) {
            glBindBuffer(GL_ARRAY_BUFFER, wvbo[0]);
            glBufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(6 * wedge_count * sizeof(glm::vec4)), hull_verts.data());
            glBindBuffer(GL_ARRAY_BUFFER, wvbo[1]);
            glBufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(6 * wedge_count * 4), hull_wedge.data());
            glBindVertexArray(wvao);
            glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, wibo);
            glBufferSubData(GL_ELEMENT_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(24 * wedge_count * 4), hull_idx.data());
            glBindVertexArray(0);
            glBindBuffer(GL_SHADER_STORAGE_BUFFER, wssbo);
            glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, static_cast<GLsizeiptr>(wedge_count * sizeof(WedgeGpu)), wedges.data());
        }
    };
    auto scene_depth = [&]() {  // projection 1: the scene's depth drawn with P_inf (every mesh)
        if (projection == 1) volumes::draw_scene_depth(gpu, target.fbo, W, H, depth_prog, false);
        else volumes::blit_gbuffer_depth(gpu, target.fbo);
    };
    auto frame_passes = [&](bool cull) {
        scene_depth();
        glBindFramebuffer(GL_FRAMEBUFFER, target.fbo);
        glViewport(0, 0, W, H);
        volumes::clear_stencil();
        const float zero[4] = {0.f, 0.f, 0.f, 0.f};
        glClearBufferfv(GL_COLOR, 0, zero);
        // (2) hard volumes
        volumes::stencil_pass(vol, cache_, draws, target.fbo, W, H, projection == 0, gpu.gbuffer.depth, cull);
        // (3) wedges, additive
        begin_accum_state();
        draw_wedges(cull);
        glDisable(GL_BLEND);
        glDepthMask(GL_TRUE);
        // (4) combine
        glActiveTexture(GL_TEXTURE3);
        glBindTexture(GL_TEXTURE_2D, target.color[0]);
        glActiveTexture(GL_TEXTURE4);
        glBindTexture(GL_TEXTURE_2D, target.depth);
        vis_pass.draw(comb_prog, gpu);
        glActiveTexture(GL_TEXTURE4);
        glBindTexture(GL_TEXTURE_2D, 0);
        glActiveTexture(GL_TEXTURE3);
        glBindTexture(GL_TEXTURE_2D, 0);
        glActiveTexture(GL_TEXTURE0);
    };
    auto frame = [&]() {
        upload();
        frame_passes(true);
    };
    r.gpu_ms = skgl::median_frame_ms(frame, ctx.warmup, ctx.frames);
    r.frames = ctx.frames;
    r.visibility = skgl::read_color_float(vis_pass.target, 0, 1);
    if (ctx.debug_images) {
        // the samples' wedge view: V in grey with every wedge hull's edges (projected, clipped to
        // the near side of the camera) drawn in orange
        DebugImage d = grey_debug_image("penumbra wedges (hull wireframe over V)", W, H, r.visibility, 1, 0, 2.f);
        auto to_pixel = [&](const glm::vec4& world, glm::vec2& px) {
            const glm::vec4 c = cam_vp * world;
            if (!(c.w > 1e-6f)) return false;
            px = glm::vec2((c.x / c.w * 0.5f + 0.5f) * float(W), (c.y / c.w * 0.5f + 0.5f) * float(H));
            return std::isfinite(px.x) && std::isfinite(px.y);
        };
        for (std::size_t wi = 0; wi < wedge_count; ++wi)
            for (std::size_t t = 0; t < 24; t += 3)
                for (std::size_t e = 0; e < 3; ++e) {
                    const std::size_t a = 6 * wi + hull_local[24 * wi + t + e];
                    const std::size_t b = 6 * wi + hull_local[24 * wi + t + (e + 1) % 3];
                    glm::vec2 pa, pb;
                    if (!to_pixel(hull_verts[a], pa) || !to_pixel(hull_verts[b], pb)) continue;
                    const float len = std::min(glm::length(pb - pa), 4.f * float(W + H));
                    const int steps = std::max(1, static_cast<int>(len));
                    for (int i = 0; i <= steps; ++i) {
                        const glm::vec2 q = pa + (pb - pa) * (float(i) / float(steps));
                        const int x = static_cast<int>(q.x), y = static_cast<int>(q.y);
                        if (x < 0 || y < 0 || x >= W || y >= H) continue;
                        const std::size_t k = 3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(W) + static_cast<std::size_t>(x));
                        d.rgb[k] = 255;
                        d.rgb[k + 1] = 140;
                        d.rgb[k + 2] = 0;
                    }
                }
        r.debug.push_back(std::move(d));
    }

    // ------------------------------------------------------------------ instrumented fill and wedge-pass time
    const bool has_stats = epoxy_has_gl_extension("GL_ARB_pipeline_statistics_query");
    // wedge fragments: `reached` = after scissor, depth test and depth bounds; else inside the wedge
    auto count_wedges = [&](bool cull, bool reached, double& fragments, double& invocations) {
        fragments = 0.0;
        invocations = -1.0;
        if (wedge_count == 0) return;
        begin_accum_state();
        glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
        glUseProgram(wedge_prog);
        glUniform1i(loc_count, reached ? 1 : 0);
        volumes::count_fragments(has_stats, [&] { draw_wedges(cull); }, fragments, invocations);
        glUseProgram(wedge_prog);
        glUniform1i(loc_count, 0);
        glDisable(GL_BLEND);
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    };
    // median time of the wedge pass alone, with the row's culling and without it, measured in alternation
    // (the machine's load affects both alike); the unculled draw needs no rebuild: it draws every group
    // (also the wedges whose rectangle is empty) without scissor and depth bounds
    auto time_wedges = [&](double& culled_ms, double& unculled_ms) {
        culled_ms = unculled_ms = 0.0;
        if (wedge_count == 0) return;
        std::vector<double> tc, tu;
        for (int it = 0; it < ctx.warmup + ctx.frames; ++it) {
            for (int variant = 0; variant < (culling ? 2 : 1); ++variant) {
                glFinish();
                const auto t0 = Clock::now();
                begin_accum_state();
                draw_wedges(variant == 0);
                glDisable(GL_BLEND);
                glFinish();
                if (it >= ctx.warmup) (variant == 0 ? tc : tu).push_back(ms_since(t0));
            }
        }
        culled_ms = median_of(tc);
        unculled_ms = culling ? median_of(tu) : culled_ms;
    };
    // depth and stencil of the last frame are still in `target`: the instrumented passes see the same depth
    double frags = 0.0, frags_in = 0.0, frags_full = 0.0, inv = -1.0, inv_full = -1.0, dummy = 0.0;
    count_wedges(true, true, frags, inv);
    count_wedges(true, false, frags_in, dummy);
    count_wedges(false, true, frags_full, inv_full);
    double wedge_ms = 0.0, wedge_ms_full = 0.0;
    time_wedges(wedge_ms, wedge_ms_full);

    r.gpu_bytes = std::int64_t(vertex_count * sizeof(glm::vec4) + indices.size() * 4) +
                  std::int64_t(max_wedges) * std::int64_t(6 * 16 + 6 * 4 + 24 * 4 + sizeof(WedgeGpu)) +
                  std::int64_t(W) * H * (4 + 8 + 4);
    r.work = {{"wedges", double(stats.wedges)},
              {"wedges_skipped", double(stats.skipped)},
              {"wedges_culled", double(stats.wedges_culled)},
              {"wedges_back", double(stats.wedges_back)},
              {"silhouette_edges", double(stats.sil_edges)},
              {"volume_triangles", double(stats.triangles)},
              {"casters_zfail", double(stats.zfail)},
              {"wedge_fragments", frags},
              {"wedge_fragments_in", frags_in},
              {"wedge_fragments_unculled", frags_full},
              {"wedge_ms", wedge_ms},
              {"wedge_ms_unculled", wedge_ms_full},
              {"wedge_speedup", wedge_ms > 0.0 ? wedge_ms_full / wedge_ms : 1.0},
              {"light_radius", double(sphere.radius)},
              {"adjacency_ms", cache_.adjacency_ms},
              {"depth_bounds_native", native_bounds ? 1.0 : 0.0}};
    if (projection == 1) r.work.push_back({"projection_epsilon", double(proj_epsilon)});
    if (has_stats) {
        r.work.push_back({"fs_invocations", inv});
        r.work.push_back({"fs_invocations_unculled", inv_full});
    }
    const std::string err = skgl::gl_error_string();
    glBindTexture(GL_TEXTURE_2D, target.depth);
    glTexParameteri(GL_TEXTURE_2D, GL_DEPTH_STENCIL_TEXTURE_MODE, GL_DEPTH_COMPONENT);
    glBindTexture(GL_TEXTURE_2D, 0);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, 0);
    glDeleteBuffers(2, wvbo);
    glDeleteBuffers(1, &wibo);
    glDeleteBuffers(1, &wssbo);
    glDeleteVertexArrays(1, &wvao);
    cleanup_programs();
    skgl::destroy_target(target);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (!err.empty()) return RunResult::failure("penumbra_wedges: " + err);
    return r;
}


}  // namespace

void add_wedge_techniques(std::vector<std::unique_ptr<Technique>>& out) { out.push_back(std::make_unique<PenumbraWedges>()); }

}  // namespace sk
