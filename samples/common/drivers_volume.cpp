// Technique drivers: volume family. "shadow_volume": robust stenciled shadow volumes composed from
// silhouette.hpp (adjacency, facing, silhouette), shadow_volume.hpp (side quads, caps, z-pass / z-fail
// decision, scissor rectangle and depth bounds) and glsl/shadow_volume.glsl (extrusion to infinity,
// depth-bounds emulation), the way a user would.
//
// Per frame, on the CPU (cpu_ms, median): for every caster mesh, facing of its faces for the
// homogeneous light (point / spot: (p, 1); directional: (-dir, 0); area lights: their centre as a
// point light), the silhouette (edge rule of silhouette.hpp: open and non-manifold meshes included),
// side quads, and for z-fail casters the light and dark caps (VolumeCapMode::LitOnly: closed for any
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
//         (volume_choose_stencil_method_box), 2 = z-pass for every caster (wrong when the camera is in a
//         shadow: the tests show it; swept, as the built-in cameras are lit); scissor {0, 1};
//         depth_bounds {0, 1};
//         projection 0 = finite + depth clamp (default), 1 = P_inf against the finite depth
//         (inconsistent: the check above; tests only, not swept), 2 = the scene depth re-drawn and
//         the volumes drawn with the epsilon-tweaked P_inf of infinite_projection.hpp (GL depth,
//         float32 epsilon of infinite_epsilon_bound), 3 = the same with reversed-Z zero-to-one P_inf
//         (glClipControl, clear depth 0, GL_GREATER, light-cap offset negated); 2 and 3 use the GLSL
//         depth-bounds emulation (the native bounds are window depths of the finite matrix).
// Work: volume_triangles, silhouette_edges, casters, casters_zfail, casters_culled (scissor polytope
// empty), scissor_pixels (sum of the scissor rectangles' areas), volume_fragments (fragments of the
// volume draws that survive scissor and depth bounds, counted with GL_SAMPLES_PASSED in an extra
// instrumented pass with the depth test set to GL_ALWAYS: the fill), volume_fragments_unculled (every
// caster's full volume without scissor and depth bounds, also those the polytope test culls),
// fs_invocations (GL_ARB_pipeline_statistics_query, where present: fragment shader runs, which the
// GLSL emulation does not save), adjacency_ms,
// depth_bounds_native (1 when GL_EXT_depth_bounds_test was used), projection_epsilon (projections 2, 3).
#include <shadowkit/infinite_projection.hpp>

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include "driver_util.hpp"
#include "stencil_volumes.hpp"

namespace sk {

namespace {

using volumes::CasterDraw;

struct FrameStats {
    std::size_t triangles = 0, sil_edges = 0, zfail = 0, culled = 0;
    double scissor_pixels = 0.0;
};

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
        // z-pass for every caster (method 2) is right only while the camera is in no shadow volume
        // (true on the built-in scenes); its rows show what the caps of z-fail cost
        return {P(0, 0, 0), P(1, 0, 0), P(2, 0, 0), P(0, 1, 1), P(1, 1, 1), P(2, 1, 1), P(1, 1, 0), P(1, 0, 1)};
    }
    RunResult run(const RunContext& ctx, const ParamSet& params) override;

private:
    volumes::VolumeCache cache_;
};

RunResult ShadowVolume::run(const RunContext& ctx, const ParamSet& params) {
    const int method = static_cast<int>(params.get("method", 1));
    const bool use_scissor = params.get("scissor", 1) != 0.0;
    const bool use_bounds = params.get("depth_bounds", 1) != 0.0;
    const int projection = static_cast<int>(params.get("projection", 0));
    const Scene& scene = ctx.scene;
    const SceneGpu& gpu = ctx.gpu;
    if (method < 0 || method > 2) return RunResult::failure("method must be 0, 1 or 2");
    if (projection < 0 || projection > 3) return RunResult::failure("projection must be 0, 1, 2 or 3");
    const bool own_depth = projection >= 2;  // the scene depth re-drawn with the volumes' matrix
    const bool reversed = projection == 3;
    if (!cache_.prepare(scene, 0x5eed5eedull)) return RunResult::failure(cache_.error);

    const glm::vec4 light = volumes::volume_light(scene.light);
    if (!shadowkit::silhouette_valid_light(light)) return RunResult::failure("invalid light");
    const float aspect = float(gpu.width) / float(gpu.height);
    const glm::mat4 cam_vp = gpu.proj * gpu.view;  // exactly the G-buffer's matrix (same float product)
    glm::mat4 volume_vp = cam_vp;
    float proj_epsilon = 0.f;
    if (own_depth) {
        // infinite_projection.hpp: GL depth with the float32 epsilon of infinite_epsilon_bound
        // (projection 2), or reversed-Z zero-to-one depth (projection 3, its bound is 0 or tiny)
        shadowkit::ProjectionDepth dp;
        dp.near_z = scene.camera.znear;
        dp.far_z = std::numeric_limits<float>::infinity();
        dp.clip_depth = reversed ? shadowkit::ClipDepth::ZeroToOne : shadowkit::ClipDepth::NegativeOneToOne;
        dp.reversed_z = reversed;
        const shadowkit::ProjectionEpsilonBound eb = shadowkit::projection_infinite_epsilon_bound(scene.camera.fovy, aspect, dp.clip_depth,
                                                                             reversed, shadowkit::DepthFormat::Float32);
        if (eb.status != shadowkit::Status::Ok) return RunResult::failure("infinite_epsilon_bound failed");
        dp.epsilon = proj_epsilon = eb.epsilon;
        const shadowkit::ProjectionResult pr = shadowkit::projection_perspective(scene.camera.fovy, aspect, dp);
        if (pr.status != shadowkit::Status::Ok) return RunResult::failure("shadowkit::perspective failed");
        volume_vp = pr.matrix * gpu.view;
    } else if (projection == 1) {
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
    const volumes::VolumeSetup setup = volumes::make_volume_setup(scene, gpu, light, cam_vp);

    std::vector<std::uint32_t> indices(cache_.total_index_capacity);
    std::vector<CasterDraw> draws(cache_.casters.size());
    FrameStats stats;
    std::string build_error;

    // ------------------------------------------------------------------ CPU stage (no allocation)
    bool culling = use_scissor || use_bounds;  // false only for the instrumented "unculled" fill count
    auto build = [&]() -> bool {
        stats = FrameStats{};
        for (std::size_t ci = 0; ci < cache_.casters.size(); ++ci) {
            volumes::CasterData& c = cache_.casters[ci];
            CasterDraw& d = draws[ci];
            d = CasterDraw{};
            const Mesh& m = scene.meshes[c.mesh];
            if (culling) {
                if (!volumes::caster_scissor(c, setup, d, build_error)) return false;
                if (!d.visible) {
                    ++stats.culled;
                    continue;
                }
                if (use_scissor) stats.scissor_pixels += double(d.sc.width) * double(d.sc.height);
            }
            if (!volumes::caster_silhouette(c, m, setup, d, build_error)) return false;
            if (!volumes::caster_volume(c, m, setup, method, indices.data(), d, build_error)) return false;
            if (d.zfail) ++stats.zfail;
            stats.sil_edges += d.sil_edges;
            stats.triangles += (d.side_count + d.cap_count) / 3;
        }
        return true;
    };

    RunResult r;
    if (!median_cpu_ms(std::max(ctx.frames, 1), build, r.cpu_ms)) return RunResult::failure(build_error);

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
    volumes::VolumeGpu vol;
    vol.use_scissor = use_scissor;
    // native bounds are window depths of cam_vp: only where the depth buffer holds cam_vp's depth
    vol.native_bounds = use_bounds && !own_depth && epoxy_has_gl_extension("GL_EXT_depth_bounds_test");
    vol.emulate_bounds = use_bounds && !vol.native_bounds;
    vol.reversed_z = reversed;
    const std::string head = std::string("#version 450 core\n") + snippet + "\n";
    const GLuint vol_prog = vol.compile(head, vol.emulate_bounds, log);
    GLuint vis_prog = compile_visibility_program("", "float technique_visibility(vec3 p, vec3 n) { return 1.0; }", log);
    GLuint depth_prog = 0;
    if (own_depth) depth_prog = compile_depth_only_program(log);
    if (!vol_prog || !vis_prog || (own_depth && !depth_prog)) {
        if (vis_prog) glDeleteProgram(vis_prog);
        if (depth_prog) glDeleteProgram(depth_prog);
        skgl::destroy_target(target);
        return RunResult::failure(log);
    }
    const std::size_t vertex_count = vol.create_buffers(scene, cache_, indices.size());
    GLuint empty_vao = 0;
    glGenVertexArrays(1, &empty_vao);
    vol.set_uniforms(volume_vp, light);
    glUseProgram(vis_prog);
    set_light_uniforms(vis_prog, scene.light);
    if (depth_prog) {
        glUseProgram(depth_prog);
        glUniformMatrix4fv(glGetUniformLocation(depth_prog, "u_light_view_proj"), 1, GL_FALSE, glm::value_ptr(volume_vp));
    }

    const int W = gpu.width, H = gpu.height;
    // scene depth -> own depth-stencil: the G-buffer's (projections 0, 1) or every mesh re-drawn with
    // the volumes' infinite matrix (2; 3 with zero-to-one clip depth, clear 0 and GL_GREATER)
    auto scene_depth = [&]() {
        if (own_depth) volumes::draw_scene_depth(gpu, target.fbo, W, H, depth_prog, reversed);
        else volumes::blit_gbuffer_depth(gpu, target.fbo);
    };
    auto frame = [&]() {
        vol.upload(cache_, draws, indices);  // the CPU stage's output of this frame: each caster's used index range
        scene_depth();  // stencil = 0 below
        volumes::clear_stencil();
        // volumes: two-sided stencil, z-pass or z-fail per caster
        volumes::stencil_pass(vol, cache_, draws, target.fbo, W, H, projection == 0, gpu.gbuffer.depth, true);
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
    if (ctx.debug_images) {
        // the stencil counts of the last frame: red = the raw 8-bit stencil value (the number of
        // shadow volumes around the pixel's surface point; the GL tests compare it with a CPU ray
        // count), green and blue = 64 x the count (saturated) to look at
        {
            std::vector<std::uint8_t> st(static_cast<std::size_t>(W) * static_cast<std::size_t>(H));
            glBindFramebuffer(GL_READ_FRAMEBUFFER, target.fbo);
            glPixelStorei(GL_PACK_ALIGNMENT, 1);
            glReadPixels(0, 0, W, H, GL_STENCIL_INDEX, GL_UNSIGNED_BYTE, st.data());
            DebugImage sd;
            sd.name = "stencil counts (red: raw count, grey: 64 x count)";
            sd.width = W;
            sd.height = H;
            sd.rgb.resize(3 * st.size());
            for (std::size_t k = 0; k < st.size(); ++k) {
                const auto shown = static_cast<std::uint8_t>(std::min(255, 64 * int(st[k])));
                sd.rgb[3 * k] = st[k];
                sd.rgb[3 * k + 1] = shown;
                sd.rgb[3 * k + 2] = shown;
            }
            r.debug.push_back(std::move(sd));
        }
        // the samples' scissor view: V in grey, each caster's scissor rectangle outlined (red:
        // z-fail caster, green: z-pass caster)
        DebugImage d = grey_debug_image("scissor rectangles (red z-fail, green z-pass)", W, H, r.visibility, 1, 0, 2.f);
        for (const CasterDraw& cd : draws) {
            if (!cd.visible || !use_scissor) continue;
            const int x0 = std::max(cd.sc.x, 0), y0 = std::max(cd.sc.y, 0);
            const int x1 = std::min(cd.sc.x + cd.sc.width - 1, W - 1), y1 = std::min(cd.sc.y + cd.sc.height - 1, H - 1);
            auto put = [&](int x, int y) {
                const std::size_t k = 3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(W) + static_cast<std::size_t>(x));
                d.rgb[k] = cd.zfail ? 255 : 0;
                d.rgb[k + 1] = cd.zfail ? 0 : 200;
                d.rgb[k + 2] = 0;
            };
            for (int x = x0; x <= x1; ++x) {
                put(x, y0);
                put(x, y1);
            }
            for (int y = y0; y <= y1; ++y) {
                put(x0, y);
                put(x1, y);
            }
        }
        r.debug.push_back(std::move(d));
    }

    // ------------------------------------------------------------------ instrumented fill count
    const bool has_stats = epoxy_has_gl_extension("GL_ARB_pipeline_statistics_query");
    auto count_fill = [&](bool cull, double& fragments, double& invocations) {
        volumes::begin_volume_state(target.fbo, W, H, projection == 0, reversed);
        glDepthFunc(GL_ALWAYS);
        glDisable(GL_STENCIL_TEST);
        volumes::count_fragments(
            has_stats, [&] { vol.draw(cache_, draws, gpu.gbuffer.depth, false, cull); }, fragments, invocations);
        volumes::end_volume_state();
    };
    double frags = 0.0, frags_full = 0.0, inv = -1.0, inv_full = -1.0;
    count_fill(true, frags, inv);
    const FrameStats culled_stats = stats;
    if (culling) {  // every caster's full volume, no scissor, no depth bounds
        culling = false;
        if (build()) vol.upload(cache_, draws, indices);  // cannot fail where the culled build succeeded
    }
    count_fill(false, frags_full, inv_full);
    stats = culled_stats;

    std::size_t casters_total = cache_.casters.size();
    r.gpu_bytes = std::int64_t(vertex_count * sizeof(glm::vec4) + indices.size() * sizeof(std::uint32_t)) +
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
              {"depth_bounds_native", vol.native_bounds ? 1.0 : 0.0}};
    if (own_depth) r.work.push_back({"projection_epsilon", double(proj_epsilon)});
    if (has_stats) {
        r.work.push_back({"fs_invocations", inv});
        r.work.push_back({"fs_invocations_unculled", inv_full});
    }
    const std::string err = skgl::gl_error_string();
    glDeleteVertexArrays(1, &empty_vao);
    glDeleteProgram(vis_prog);
    if (depth_prog) glDeleteProgram(depth_prog);
    skgl::destroy_target(target);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (!err.empty()) return RunResult::failure("shadow_volume: " + err);
    return r;
}

}  // namespace

void add_volume_techniques(std::vector<std::unique_ptr<Technique>>& out) { out.push_back(std::make_unique<ShadowVolume>()); }

}  // namespace sk
