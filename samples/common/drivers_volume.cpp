// Technique drivers: volume family. "shadow_volume": robust stenciled shadow volumes composed from
// silhouette.hpp (adjacency, facing, silhouette), shadow_volume.hpp (side quads, caps, z-pass / z-fail
// decision, scissor rectangle and depth bounds) and glsl/shadow_volume.glsl (extrusion to infinity,
// depth-bounds emulation), the way a user would.
//
// Per frame, on the CPU (cpu_ms, median): for every caster mesh, facing of its faces for the
// homogeneous light (point / spot: (p, 1); directional: (-dir, 0); area lights: their centre as a
// point light), the silhouette (edge rule of silhouette.hpp: open and non-manifold meshes included),
// side quads, and for z-fail casters the light and dark caps (CapMode::LitOnly: closed for any
// triangle soup), the z-pass / z-fail decision (near-plane occlusion pyramid vs the caster's box) and
// the scissor rectangle and depth bounds (Lengyel). The adjacency is built once per scene (cached
// across parameter sets; its build time is reported as work "adjacency_ms").
//
// On the GPU (gpu_ms, median): index upload, blit of the G-buffer depth into the technique's own
// DEPTH32F_STENCIL8 target (same format as the G-buffer: glBlitFramebuffer needs it), the volumes with
// two-sided stencil (GL_INCR_WRAP / GL_DECR_WRAP via glStencilOpSeparate, per caster z-pass or
// z-fail), scissor per caster, depth bounds (GL_EXT_depth_bounds_test where present, else the GLSL
// emulation of shadow_volume.glsl reading the G-buffer's depth texture, which is a different texture
// from the one attached here), then V = (stencil == 0) through the stencil test (GL_EQUAL 0) into the
// R32F visibility target with the common light rules of visibility_fragment_shader().
//
// Projection of the volume pass. The G-buffer depth was written with the camera's finite projection
// (near N, far F). The infinite projection P_inf with the same near plane does NOT compare
// consistently with it: window depth w_fin(d) = F/(F-N) (1 - N/d) vs w_inf(d) = 1 - N/d, a difference
// of N/(F-N) (1 - N/d) (5e-4 at d = 100 N for the built-in cameras: ~8000 float32 steps of 2^-24),
// so a light cap drawn with P_inf lands in front of its own surface and z-fail shadows lit faces (the
// GL test shows it with projection=1). The driver therefore draws the volumes with the same finite
// matrix as the G-buffer and GL_DEPTH_CLAMP: vertices at infinity (w = 0) are not clipped by the far
// (or near) plane and their depth clamps to 1, behind every receiver (receivers lie inside the far
// plane). The light cap coincides with the G-buffer's own triangles (same vertices, same matrix); it
// is drawn with a small constant polygon offset (units only) so that it reliably fails the depth test
// at its own surface also for two-sided or re-triangulated copies of it (llvmpipe needs no offset:
// the GL test passes without it).
//
// Params: method 0 = z-fail for every caster, 1 = z-pass / z-fail chosen per caster
//         (choose_stencil_method_box), 2 = z-pass for every caster (wrong when the camera is in a
//         shadow; for tests only, not swept); scissor {0, 1}; depth_bounds {0, 1};
//         projection 0 = finite + depth clamp (default), 1 = P_inf against the finite depth
//         (inconsistent: the check above; tests only, not swept).
// Work: volume_triangles, silhouette_edges, casters, casters_zfail, casters_culled (scissor polytope
// empty), scissor_pixels (sum of the scissor rectangles' areas), volume_fragments (fragments of the
// volume draws that survive scissor and depth bounds, counted with GL_SAMPLES_PASSED in an extra
// instrumented pass with the depth test set to GL_ALWAYS: the fill), volume_fragments_unculled (every
// caster's full volume without scissor and depth bounds, also those the polytope test culls),
// fs_invocations (GL_ARB_pipeline_statistics_query, where present: fragment shader runs, which the
// GLSL emulation does not save), adjacency_ms,
// depth_bounds_native (1 when GL_EXT_depth_bounds_test was used).
#include <shadowkit/shadow_volume.hpp>
#include <shadowkit/silhouette.hpp>

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>

#include "driver_util.hpp"

namespace sk {

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

double median_of(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
}

// Homogeneous light for silhouette.hpp / shadow_volume.hpp: w = 1 point (spot, and the centre of area
// lights), w = 0 the direction TOWARD a directional light.
glm::vec4 volume_light(const Light& L) {
    if (L.type == LightType::Directional) return glm::vec4(-glm::normalize(L.direction), 0.f);
    return glm::vec4(L.position, 1.f);
}

// Everything that can receive this light's shadows (the scissor polytope is clipped to it): the scene
// bounds, for a spot light intersected with a box around its cone (receivers outside the cone are
// unlit by the common light rules, whatever the stencil says), inflated a little for rounding.
void light_receiver_bounds(const Scene& s, glm::vec3& lo, glm::vec3& hi) {
    lo = s.bounds_min();
    hi = s.bounds_max();
    const float pad = 1e-4f * std::max(1e-6f, glm::length(hi - lo));
    const Light& L = s.light;
    if (L.type == LightType::Spot && L.spot_half_angle < 1.5f) {
        float far_d = 0.f;
        for (int i = 0; i < 8; ++i) {
            const glm::vec3 c((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
            far_d = std::max(far_d, glm::length(c - L.position));
        }
        const glm::vec3 d = glm::normalize(L.direction);
        const glm::vec3 cap = L.position + d * far_d;
        const float r = far_d * std::tan(L.spot_half_angle);
        const glm::vec3 ext = r * glm::sqrt(glm::max(glm::vec3(0.f), 1.f - d * d));
        const glm::vec3 clo = glm::min(L.position, cap - ext), chi = glm::max(L.position, cap + ext);
        const glm::vec3 nlo = glm::max(lo, clo), nhi = glm::min(hi, chi);
        if (nlo.x <= nhi.x && nlo.y <= nhi.y && nlo.z <= nhi.z) {
            lo = nlo;
            hi = nhi;
        }
    }
    lo -= glm::vec3(pad);
    hi += glm::vec3(pad);
}

// Per caster mesh: adjacency (once per scene) and per-frame scratch buffers (allocated once).
struct CasterData {
    std::size_t mesh = 0;
    shadowkit::EdgeAdjacency adj;
    glm::vec3 lo{0.f}, hi{0.f};
    GLint base_vertex = 0;  // first vertex of this caster's 2n-vertex block in the shared buffer
    std::vector<std::uint8_t> facing;
    std::vector<std::uint32_t> sil;
    std::size_t index_capacity = 0;
    std::size_t index_offset = 0;  // into the shared index array
};

struct SceneCache {
    std::uint64_t key = 0;
    bool valid = false;
    std::string error;
    std::vector<CasterData> casters;
    double adjacency_ms = 0.0;
    std::size_t total_vertices = 0, total_index_capacity = 0;
    std::size_t welded = 0, boundary = 0, nonmanifold = 0, degenerate = 0;
};

// Per-frame output of the CPU stage for one caster.
struct CasterDraw {
    bool visible = true;
    bool zfail = true;
    std::size_t side_first = 0, side_count = 0;  // indices
    std::size_t cap_first = 0, cap_count = 0;
    std::size_t sil_edges = 0;
    shadowkit::ScissorResult sc;
};

struct FrameStats {
    std::size_t triangles = 0, sil_edges = 0, zfail = 0, culled = 0;
    double scissor_pixels = 0.0;
};

const char* kVolumeVS = R"(
layout(location = 0) in vec4 a_position;
uniform mat4 u_view_proj;
uniform vec4 u_light;
void main() { gl_Position = u_view_proj * sk_extrude_shadow_volume(a_position, u_light); }
)";
const char* kVolumeFSPlain = R"(
void main() {}
)";
const char* kVolumeFSBounds = R"(
layout(binding = 2) uniform sampler2D u_scene_depth;
uniform vec2 u_bounds;
void main() {
    if (sk_outside_depth_bounds_at(u_scene_depth, ivec2(gl_FragCoord.xy), u_bounds)) discard;
}
)";

class ShadowVolume final : public Technique {
public:
    std::string name() const override { return "shadow_volume"; }
    std::string description() const override {
        return "robust stenciled shadow volumes (Everitt-Kilgard; z-fail 0 / per-caster z-pass|z-fail 1), "
               "Lengyel scissor and depth bounds; area lights from their centre";
    }
    bool hard() const override { return true; }
    std::vector<ParamSet> sweep(const Scene&, bool quick) const override {
        auto P = [](int m, int s, int d) {
            return ParamSet{{{"method", double(m)}, {"scissor", double(s)}, {"depth_bounds", double(d)}}};
        };
        // the middle entry (the samples' default) is the full technique
        if (quick) return {P(1, 0, 0), P(1, 1, 1)};
        return {P(0, 0, 0), P(1, 0, 0), P(0, 1, 1), P(1, 1, 1), P(1, 1, 0), P(1, 0, 1)};
    }
    RunResult run(const RunContext& ctx, const ParamSet& params) override;

private:
    SceneCache cache_;
    bool prepare(const Scene& scene);
};

bool ShadowVolume::prepare(const Scene& scene) {
    const std::uint64_t key = scene_hash(scene, 0, 0, 0x5eed5eedull);
    if (cache_.valid && cache_.key == key) return true;
    cache_ = SceneCache{};
    cache_.key = key;
    const auto t0 = Clock::now();
    for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
        const Mesh& m = scene.meshes[i];
        if (!m.caster || m.indices.empty()) continue;
        CasterData c;
        c.mesh = i;
        c.adj = shadowkit::build_edge_adjacency(m.positions.data(), m.positions.size(), m.indices.data(), m.indices.size());
        if (c.adj.status != shadowkit::SilhouetteStatus::Ok) {
            cache_.error = "build_edge_adjacency failed on mesh '" + m.name + "' (status " +
                           std::to_string(static_cast<int>(c.adj.status)) + ")";
            return false;
        }
        cache_.welded += c.adj.welded_vertices;
        cache_.boundary += c.adj.boundary_edges;
        cache_.nonmanifold += c.adj.nonmanifold_edges.size();
        cache_.degenerate += c.adj.degenerate_triangles;
        cache_.casters.push_back(std::move(c));
    }
    cache_.adjacency_ms = ms_since(t0);
    for (CasterData& c : cache_.casters) {
        const Mesh& m = scene.meshes[c.mesh];
        mesh_bounds(m, c.lo, c.hi);
        c.base_vertex = static_cast<GLint>(cache_.total_vertices);
        cache_.total_vertices += 2 * m.positions.size();
        c.facing.assign(c.adj.face_count(), 0);
        const std::size_t max_sil = c.adj.max_silhouette_edges();
        c.sil.assign(2 * max_sil, 0);
        c.index_capacity = 6 * max_sil + 6 * c.adj.face_count();
        c.index_offset = cache_.total_index_capacity;
        cache_.total_index_capacity += c.index_capacity;
    }
    cache_.valid = true;
    return true;
}

RunResult ShadowVolume::run(const RunContext& ctx, const ParamSet& params) {
    const int method = static_cast<int>(params.get("method", 1));
    const bool use_scissor = params.get("scissor", 1) != 0.0;
    const bool use_bounds = params.get("depth_bounds", 1) != 0.0;
    const int projection = static_cast<int>(params.get("projection", 0));
    const Scene& scene = ctx.scene;
    const SceneGpu& gpu = ctx.gpu;
    if (method < 0 || method > 2) return RunResult::failure("method must be 0, 1 or 2");
    if (!prepare(scene)) return RunResult::failure(cache_.error);

    const glm::vec4 light = volume_light(scene.light);
    if (!shadowkit::valid_light(light)) return RunResult::failure("invalid light");
    const bool point = light.w > 0.f;
    const float aspect = float(gpu.width) / float(gpu.height);
    const glm::mat4 cam_vp = gpu.proj * gpu.view;  // exactly the G-buffer's matrix (same float product)
    glm::mat4 volume_vp = cam_vp;
    if (projection == 1) {
        // P_inf with the camera's near plane (Everitt-Kilgard 3.2.1): inconsistent with the finite depth
        const float t = 1.f / std::tan(0.5f * scene.camera.fovy);
        glm::mat4 P(0.f);
        P[0][0] = t / aspect;
        P[1][1] = t;
        P[2][2] = -1.f;
        P[2][3] = -1.f;
        P[3][2] = -2.f * scene.camera.znear;
        volume_vp = P * gpu.view;
    }
    const shadowkit::NearPlaneRect near_rect =
        shadowkit::near_plane_rect(gpu.view, scene.camera.fovy, aspect, scene.camera.znear);
    glm::vec3 rlo, rhi;
    light_receiver_bounds(scene, rlo, rhi);
    const float margin = 1e-4f * std::max(1e-6f, glm::length(scene.bounds_max() - scene.bounds_min()));
    shadowkit::ScissorParams sp;
    sp.view_proj = cam_vp;
    sp.clip_depth = shadowkit::ClipDepth::NegativeOneToOne;
    sp.reversed_z = false;
    sp.viewport[0] = 0;
    sp.viewport[1] = 0;
    sp.viewport[2] = gpu.width;
    sp.viewport[3] = gpu.height;

    std::vector<std::uint32_t> indices(cache_.total_index_capacity);
    std::vector<CasterDraw> draws(cache_.casters.size());
    FrameStats stats;
    std::string build_error;

    // ------------------------------------------------------------------ CPU stage (no allocation)
    bool culling = use_scissor || use_bounds;  // false only for the instrumented "unculled" fill count
    auto build = [&]() -> bool {
        stats = FrameStats{};
        for (std::size_t ci = 0; ci < cache_.casters.size(); ++ci) {
            CasterData& c = cache_.casters[ci];
            CasterDraw& d = draws[ci];
            d = CasterDraw{};
            const Mesh& m = scene.meshes[c.mesh];
            if (culling) {
                d.sc = shadowkit::shadow_volume_scissor(light, c.lo, c.hi, rlo, rhi, sp);
                if (d.sc.status != shadowkit::VolumeStatus::Ok) {
                    build_error = "shadow_volume_scissor status " + std::to_string(static_cast<int>(d.sc.status));
                    return false;
                }
                if (!d.sc.visible) {
                    d.visible = false;
                    ++stats.culled;
                    continue;
                }
                if (use_scissor) stats.scissor_pixels += double(d.sc.width) * double(d.sc.height);
            }
            const shadowkit::FacingResult fr = shadowkit::compute_facing(c.adj, m.positions.data(), m.positions.size(), light,
                                                                         c.facing.data(), c.facing.size());
            if (fr.status != shadowkit::SilhouetteStatus::Ok) {
                build_error = "compute_facing status " + std::to_string(static_cast<int>(fr.status));
                return false;
            }
            const shadowkit::SilhouetteResult sr = shadowkit::extract_silhouette(
                c.adj, c.facing.data(), c.facing.size(), c.sil.data(), nullptr, c.sil.size() / 2);
            if (sr.status != shadowkit::SilhouetteStatus::Ok) {
                build_error = "extract_silhouette status " + std::to_string(static_cast<int>(sr.status));
                return false;
            }
            d.sil_edges = sr.edge_count;
            if (method == 0) d.zfail = true;
            else if (method == 2) d.zfail = false;
            else {
                const shadowkit::MethodResult mr = shadowkit::choose_stencil_method_box(near_rect, light, c.lo, c.hi, margin);
                if (mr.status != shadowkit::VolumeStatus::Ok) {
                    build_error = "choose_stencil_method_box status " + std::to_string(static_cast<int>(mr.status));
                    return false;
                }
                d.zfail = mr.method == shadowkit::StencilMethod::ZFail;
            }
            std::uint32_t* out = indices.data() + c.index_offset;
            const shadowkit::VolumeCount sq =
                shadowkit::build_side_quads(c.sil.data(), sr.edge_count, m.positions.size(), out, c.index_capacity);
            if (sq.status != shadowkit::VolumeStatus::Ok) {
                build_error = "build_side_quads status " + std::to_string(static_cast<int>(sq.status));
                return false;
            }
            d.side_first = c.index_offset;
            d.side_count = sq.count;
            if (d.zfail) {
                const shadowkit::VolumeCount cp = shadowkit::build_caps(
                    c.adj.faces.data(), c.adj.face_count(), c.facing.data(), m.positions.size(), shadowkit::CapMode::LitOnly,
                    point /* a directional light's dark cap has zero area */, out + sq.count, c.index_capacity - sq.count);
                if (cp.status != shadowkit::VolumeStatus::Ok) {
                    build_error = "build_caps status " + std::to_string(static_cast<int>(cp.status));
                    return false;
                }
                d.cap_first = c.index_offset + sq.count;
                d.cap_count = cp.count;
                ++stats.zfail;
            }
            stats.sil_edges += d.sil_edges;
            stats.triangles += (d.side_count + d.cap_count) / 3;
        }
        return true;
    };

    RunResult r;
    std::vector<double> cpu_samples;
    for (int it = 0; it < std::max(ctx.frames, 1); ++it) {
        const auto t0 = Clock::now();
        if (!build()) return RunResult::failure(build_error);
        cpu_samples.push_back(ms_since(t0));
    }
    r.cpu_ms = median_of(cpu_samples);

    // ------------------------------------------------------------------ GPU resources
    std::string why, log;
    skgl::Target target;  // colour 0: R32F visibility; DEPTH32F_STENCIL8 (G-buffer format, for the blit)
    if (!skgl::make_target(target, gpu.width, gpu.height, {GL_R32F}, GL_DEPTH32F_STENCIL8, why))
        return RunResult::failure(why);
    const std::string snippet = load_snippet("shadow_volume", why);
    if (snippet.empty()) {
        skgl::destroy_target(target);
        return RunResult::failure(why);
    }
    const bool native_bounds = use_bounds && epoxy_has_gl_extension("GL_EXT_depth_bounds_test");
    const bool emulate_bounds = use_bounds && !native_bounds;
    const std::string head = std::string("#version 450 core\n") + snippet + "\n";
    GLuint vol_prog = skgl::compile_program(
        {{GL_VERTEX_SHADER, head + kVolumeVS}, {GL_FRAGMENT_SHADER, head + (emulate_bounds ? kVolumeFSBounds : kVolumeFSPlain)}},
        log);
    GLuint vis_prog = skgl::compile_program(
        {{GL_VERTEX_SHADER, fullscreen_vertex_shader()},
         {GL_FRAGMENT_SHADER, visibility_fragment_shader("", "float technique_visibility(vec3 p, vec3 n) { return 1.0; }")}},
        log);
    if (!vol_prog || !vis_prog) {
        if (vol_prog) glDeleteProgram(vol_prog);
        if (vis_prog) glDeleteProgram(vis_prog);
        skgl::destroy_target(target);
        return RunResult::failure(log);
    }
    // one static vertex buffer: per caster the 2n-vertex block (p, 1), (p, 0)
    std::vector<glm::vec4> verts(cache_.total_vertices);
    for (const CasterData& c : cache_.casters) {
        const Mesh& m = scene.meshes[c.mesh];
        shadowkit::build_volume_vertices(m.positions.data(), m.positions.size(), verts.data() + c.base_vertex,
                                         2 * m.positions.size());
    }
    GLuint vao = 0, vbo = 0, ibo = 0, empty_vao = 0;
    glGenVertexArrays(1, &vao);
    glGenVertexArrays(1, &empty_vao);
    glGenBuffers(1, &vbo);
    glGenBuffers(1, &ibo);
    glBindVertexArray(vao);
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(verts.size() * sizeof(glm::vec4)), verts.data(), GL_STATIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, sizeof(glm::vec4), nullptr);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ibo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(std::max<std::size_t>(indices.size(), 1) * 4), nullptr,
                 GL_DYNAMIC_DRAW);
    glBindVertexArray(0);

    glUseProgram(vol_prog);
    glUniformMatrix4fv(glGetUniformLocation(vol_prog, "u_view_proj"), 1, GL_FALSE, glm::value_ptr(volume_vp));
    glUniform4fv(glGetUniformLocation(vol_prog, "u_light"), 1, glm::value_ptr(light));
    const GLint loc_bounds = glGetUniformLocation(vol_prog, "u_bounds");
    glUseProgram(vis_prog);
    set_light_uniforms(vis_prog, scene.light);

    const int W = gpu.width, H = gpu.height;
    // draws every visible caster's volume; `stencil` false = the instrumented fill count (no writes)
    auto draw_volumes = [&](bool stencil, bool cull) {
        glUseProgram(vol_prog);
        glBindVertexArray(vao);
        if (emulate_bounds) {
            glActiveTexture(GL_TEXTURE2);
            glBindTexture(GL_TEXTURE_2D, gpu.gbuffer.depth);
        }
        for (std::size_t ci = 0; ci < draws.size(); ++ci) {
            const CasterDraw& d = draws[ci];
            if (!d.visible) continue;
            if (stencil) {
                if (d.zfail) {
                    glStencilOpSeparate(GL_BACK, GL_KEEP, GL_INCR_WRAP, GL_KEEP);
                    glStencilOpSeparate(GL_FRONT, GL_KEEP, GL_DECR_WRAP, GL_KEEP);
                } else {
                    glStencilOpSeparate(GL_FRONT, GL_KEEP, GL_KEEP, GL_INCR_WRAP);
                    glStencilOpSeparate(GL_BACK, GL_KEEP, GL_KEEP, GL_DECR_WRAP);
                }
            }
            if (cull && use_scissor) {
                glEnable(GL_SCISSOR_TEST);
                glScissor(d.sc.x, d.sc.y, d.sc.width, d.sc.height);
            } else {
                glDisable(GL_SCISSOR_TEST);
            }
            if (cull && use_bounds && native_bounds) {
                glEnable(GL_DEPTH_BOUNDS_TEST_EXT);
                glDepthBoundsEXT(d.sc.depth_min, d.sc.depth_max);
            } else if (native_bounds) {
                glDisable(GL_DEPTH_BOUNDS_TEST_EXT);
            }
            if (emulate_bounds)
                glUniform2f(loc_bounds, cull ? d.sc.depth_min : -1.f, cull ? d.sc.depth_max : 2.f);
            const GLint base = cache_.casters[ci].base_vertex;
            if (d.side_count)
                glDrawElementsBaseVertex(GL_TRIANGLES, static_cast<GLsizei>(d.side_count), GL_UNSIGNED_INT,
                                         reinterpret_cast<const void*>(d.side_first * sizeof(std::uint32_t)), base);
            if (d.cap_count) {
                // the light cap coincides with the caster's own surface: a constant offset makes it fail
                // the depth test there robustly (it must count as "behind" the lit surface)
                glEnable(GL_POLYGON_OFFSET_FILL);
                glPolygonOffset(0.f, 8.f);
                glDrawElementsBaseVertex(GL_TRIANGLES, static_cast<GLsizei>(d.cap_count), GL_UNSIGNED_INT,
                                         reinterpret_cast<const void*>(d.cap_first * sizeof(std::uint32_t)), base);
                glDisable(GL_POLYGON_OFFSET_FILL);
            }
        }
        glDisable(GL_SCISSOR_TEST);
        if (native_bounds) glDisable(GL_DEPTH_BOUNDS_TEST_EXT);
        glBindVertexArray(0);
    };
    auto begin_volume_state = [&]() {
        glBindFramebuffer(GL_FRAMEBUFFER, target.fbo);
        glViewport(0, 0, W, H);
        glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
        glDepthMask(GL_FALSE);
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        glDisable(GL_CULL_FACE);
        if (projection == 0) glEnable(GL_DEPTH_CLAMP);
    };
    auto end_volume_state = [&]() {
        glDisable(GL_DEPTH_CLAMP);
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        glDepthMask(GL_TRUE);
        glDisable(GL_STENCIL_TEST);
    };
    auto upload = [&]() {
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ibo);
        for (std::size_t ci = 0; ci < draws.size(); ++ci) {
            const std::size_t first = cache_.casters[ci].index_offset, n = draws[ci].side_count + draws[ci].cap_count;
            if (draws[ci].visible && n)
                glBufferSubData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLintptr>(first * sizeof(std::uint32_t)),
                                static_cast<GLsizeiptr>(n * sizeof(std::uint32_t)), indices.data() + first);
        }
    };
    auto frame = [&]() {
        upload();  // the CPU stage's output of this frame: each caster's used index range
        // scene depth -> own depth-stencil, stencil = 0
        glDisable(GL_SCISSOR_TEST);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, gpu.gbuffer.fbo);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target.fbo);
        glBlitFramebuffer(0, 0, W, H, 0, 0, W, H, GL_DEPTH_BUFFER_BIT, GL_NEAREST);
        glBindFramebuffer(GL_FRAMEBUFFER, target.fbo);
        glStencilMask(0xFF);
        glClearStencil(0);
        glClear(GL_STENCIL_BUFFER_BIT);
        // volumes: two-sided stencil, z-pass or z-fail per caster
        begin_volume_state();
        glEnable(GL_STENCIL_TEST);
        glStencilFunc(GL_ALWAYS, 0, 0xFF);
        draw_volumes(true, true);
        end_volume_state();
        // V = (stencil == 0), with the common light rules
        const float zero[4] = {0.f, 0.f, 0.f, 0.f};
        glClearBufferfv(GL_COLOR, 0, zero);
        glDisable(GL_DEPTH_TEST);
        glEnable(GL_STENCIL_TEST);
        glStencilFunc(GL_EQUAL, 0, 0xFF);
        glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
        glUseProgram(vis_prog);
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(GL_TEXTURE_2D, gpu.gbuffer.color[0]);
        glActiveTexture(GL_TEXTURE1);
        glBindTexture(GL_TEXTURE_2D, gpu.gbuffer.color[1]);
        glBindVertexArray(empty_vao);
        glDrawArrays(GL_TRIANGLES, 0, 3);
        glBindVertexArray(0);
        glDisable(GL_STENCIL_TEST);
    };
    r.gpu_ms = skgl::median_frame_ms(frame, ctx.warmup, ctx.frames);
    r.frames = ctx.frames;
    r.visibility = skgl::read_color_float(target, 0, 1);

    // ------------------------------------------------------------------ instrumented fill count
    const bool has_stats = epoxy_has_gl_extension("GL_ARB_pipeline_statistics_query");
    auto count_fill = [&](bool cull, double& fragments, double& invocations) {
        GLuint q[2] = {0, 0};
        glGenQueries(has_stats ? 2 : 1, q);
        begin_volume_state();
        glDepthFunc(GL_ALWAYS);
        glDisable(GL_STENCIL_TEST);
        glBeginQuery(GL_SAMPLES_PASSED, q[0]);
        if (has_stats) glBeginQuery(GL_FRAGMENT_SHADER_INVOCATIONS_ARB, q[1]);
        draw_volumes(false, cull);
        glEndQuery(GL_SAMPLES_PASSED);
        if (has_stats) glEndQuery(GL_FRAGMENT_SHADER_INVOCATIONS_ARB);
        end_volume_state();
        glDepthFunc(GL_LESS);
        GLuint64 v = 0;
        glGetQueryObjectui64v(q[0], GL_QUERY_RESULT, &v);
        fragments = double(v);
        if (has_stats) {
            glGetQueryObjectui64v(q[1], GL_QUERY_RESULT, &v);
            invocations = double(v);
        }
        glDeleteQueries(has_stats ? 2 : 1, q);
    };
    double frags = 0.0, frags_full = 0.0, inv = -1.0, inv_full = -1.0;
    count_fill(true, frags, inv);
    const FrameStats culled_stats = stats;
    if (culling) {  // every caster's full volume, no scissor, no depth bounds
        culling = false;
        if (build()) upload();  // cannot fail where the culled build succeeded (same inputs, fewer calls)
    }
    count_fill(false, frags_full, inv_full);
    stats = culled_stats;

    std::size_t casters_total = cache_.casters.size();
    r.gpu_bytes = std::int64_t(verts.size() * sizeof(glm::vec4) + indices.size() * sizeof(std::uint32_t)) +
                  std::int64_t(W) * H * (8 + 4);
    r.work = {{"volume_triangles", double(stats.triangles)},
              {"silhouette_edges", double(stats.sil_edges)},
              {"casters", double(casters_total)},
              {"casters_zfail", double(stats.zfail)},
              {"casters_culled", double(stats.culled)},
              {"scissor_pixels", use_scissor ? stats.scissor_pixels : double(W) * H * double(casters_total - stats.culled)},
              {"volume_fragments", frags},
              {"volume_fragments_unculled", frags_full},
              {"adjacency_ms", cache_.adjacency_ms},
              {"boundary_edges", double(cache_.boundary)},
              {"nonmanifold_edges", double(cache_.nonmanifold)},
              {"depth_bounds_native", native_bounds ? 1.0 : 0.0}};
    if (has_stats) {
        r.work.push_back({"fs_invocations", inv});
        r.work.push_back({"fs_invocations_unculled", inv_full});
    }
    const std::string err = skgl::gl_error_string();
    glDeleteBuffers(1, &vbo);
    glDeleteBuffers(1, &ibo);
    glDeleteVertexArrays(1, &vao);
    glDeleteVertexArrays(1, &empty_vao);
    glDeleteProgram(vol_prog);
    glDeleteProgram(vis_prog);
    skgl::destroy_target(target);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (!err.empty()) return RunResult::failure("shadow_volume: " + err);
    return r;
}

}  // namespace

void add_volume_techniques(std::vector<std::unique_ptr<Technique>>& out) { out.push_back(std::make_unique<ShadowVolume>()); }

}  // namespace sk
