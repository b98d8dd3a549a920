// samples/report/techniques/penumbra_wedges.cpp - "penumbra_wedges" in the report: the sample's
// PenumbraWedges class (samples/penumbra_wedges/, built on samples/shadow_volumes/) with timing, work
// counters and sweeps (report_technique.hpp).
//
// Sweep: only lights with an area (sphere, disk, square; stack, room and outdoor have none: their hard
// shadow is the shadow_volume row's), the old rows entry by entry: scissor and depth bounds off / on
// (the middle row is the sample's default), projection=infinite (the epsilon-tweaked P_inf), and for a
// square light rect_radius=bounding (the circumscribed disk). faces=back / front, method=zfail,
// horizon=off and light_scale are settings the GL tests use; the report does not sweep them.
//
// Work, from what the class exposes after the timed frames:
//   wedges, wedges_skipped (edges penumbra_wedge skipped or whose hull is not drawable), wedges_culled
//   (empty scissor rectangle), wedges_back (drawn with back faces), silhouette_edges (every caster's,
//   with a light radius), light_radius: wedges() and the class's accessors; volume_triangles,
//   casters_zfail: volumes().casters();
//   wedge_fragments: the hull fragments of draw_hulls() that reach the wedge test (after scissor, depth
//   test and depth bounds), counted with GL_SAMPLES_PASSED in the class's wedge pass state under a
//   program of the report's that keeps every fragment the depth-bounds emulation keeps (the class's own
//   program discards outside the wedge); wedge_fragments_in: the same with the class's program (the
//   fragments whose coverage is added); wedge_fragments_unculled: wedge_fragments with scissor and depth
//   bounds off (update and render re-run); wedge_ms / wedge_ms_unculled: median time of the wedge pass
//   alone (glFinish + steady clock), with the row's culling and without it, measured one after the other
//   (the old driver alternated them); wedge_speedup: their ratio; fs_invocations(_unculled): fragment-shader
//   runs where GL_ARB_pipeline_statistics_query exists; depth_bounds_native: GL_EXT_depth_bounds_test
//   used (the finite projection only, as the volumes: the old driver used it with P_inf too);
//   projection_epsilon (infinite); init_ms: init() (was adjacency_ms: the adjacency alone).
// gpu_bytes: the volumes' vertex and index buffers, the wedge buffers (hull vertices, wedge indices, hull
// indices, wedge data) for every possible silhouette edge, and per pixel the volumes' target (R32F +
// DEPTH32F_STENCIL8; its V is unused here), the coverage sum and V (R32F each): 4 bytes a pixel more than
// the old driver, which had no volume V target.
#include <algorithm>
#include <chrono>

#include "penumbra_wedges.hpp"
#include "report_technique.hpp"

namespace sk {

namespace {

using S = PenumbraWedgeSettings;

// The counting program: the class's hull vertices and wedge data, each fragment kept unless the GLSL
// depth-bounds emulation (e != 0) drops it.
const char* kReachedVS =
    "#version 450 core\nlayout(location = 0) in vec4 p; layout(location = 1) in uint w; uniform mat4 m; flat out uint v_w;\n"
    "void main() { v_w = w; gl_Position = m * p; }\n";
const char* kReachedFS =
    "layout(std430, binding = 0) readonly buffer W { vec4 w[]; }; layout(binding = 2) uniform sampler2D d; uniform int e;\n"
    "flat in uint v_w; out float o;\n"
    "void main() {\n  if (e != 0 && sk_outside_depth_bounds_at(d, ivec2(gl_FragCoord.xy), w[7u * v_w + 6u].xy)) discard;\n"
    "  o = 0.0;\n}\n";

bool measure(PenumbraWedges& pw, const S& s, const app::View& v, const RunContext& ctx, RunResult& r) {
    std::string why;
    const std::string snippet = app::load_snippet("shadow_volume", why);
    const GLuint reached_prog = snippet.empty() ? 0u : skgl::compile_program(
        {{GL_VERTEX_SHADER, kReachedVS}, {GL_FRAGMENT_SHADER, "#version 450 core\n" + snippet + "\n" + kReachedFS}}, why);
    if (!reached_prog) {
        r = RunResult::failure(why);
        return false;
    }
    const bool has_stats = epoxy_has_gl_extension("GL_ARB_pipeline_statistics_query");
    // the wedge pass's fragments, no color written: `reached` under the counting program, else the class's
    auto count = [&](const S& cs, bool reached, double& fragments, double& invocations) {
        pw.begin_wedge_pass(v, cs);
        glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
        if (reached) {
            glUseProgram(reached_prog);
            glUniformMatrix4fv(glGetUniformLocation(reached_prog, "m"), 1, GL_FALSE,
                               &pw.volumes().volume_view_proj()[0][0]);
            glUniform1i(glGetUniformLocation(reached_prog, "e"), cs.depth_bounds && !pw.native_depth_bounds(cs) ? 1 : 0);
        }
        count_fragments(has_stats, [&] { pw.draw_hulls(cs); }, fragments, invocations);
        pw.end_wedge_pass();
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    };
    // the median time of the wedge pass alone
    auto time_pass = [&](const S& cs) {
        std::vector<double> ms;
        for (int it = 0; it < ctx.warmup + std::max(ctx.frames, 1); ++it) {
            glFinish();
            const auto t0 = std::chrono::steady_clock::now();
            pw.begin_wedge_pass(v, cs);
            pw.draw_hulls(cs);
            pw.end_wedge_pass();
            glFinish();
            const double elapsed = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
            if (it >= ctx.warmup) ms.push_back(elapsed);
        }
        std::nth_element(ms.begin(), ms.begin() + static_cast<std::ptrdiff_t>(ms.size() / 2), ms.end());
        return ms[ms.size() / 2];
    };
    // the depth and stencil of the last timed frame are still in the class's targets
    double frags = 0.0, frags_in = 0.0, frags_full = 0.0, inv = -1.0, inv_full = -1.0, unused = -1.0;
    count(s, true, frags, inv);
    count(s, false, frags_in, unused);
    const double wedge_ms = time_pass(s);
    std::size_t culled = 0, back = 0, triangles = 0, zfail = 0;
    for (const PenumbraWedges::Wedge& w : pw.wedges()) {
        culled += w.visible ? 0 : 1;
        back += w.visible && w.back ? 1 : 0;
    }
    for (const ShadowVolumes::Caster& c : pw.volumes().casters()) {
        if (!c.visible) continue;
        zfail += c.zfail ? 1 : 0;
        triangles += (c.side_count + c.cap_count) / 3;
    }
    const std::size_t wedges = pw.wedges().size(), skipped = pw.edges_without_wedge(), edges = pw.silhouette_edges();
    const bool native = pw.native_depth_bounds(s);
    double wedge_ms_full = wedge_ms;
    frags_full = frags;
    inv_full = inv;
    if (s.scissor || s.depth_bounds) {  // every wedge, no scissor, no depth bounds (the frame re-run)
        S unculled = s;
        unculled.scissor = unculled.depth_bounds = false;
        pw.update(v, unculled);
        pw.render(v, unculled);
        count(unculled, true, frags_full, inv_full);
        wedge_ms_full = time_pass(unculled);
    }
    glDeleteProgram(reached_prog);
    const std::size_t per_wedge = 6 * sizeof(glm::vec4) + 6 * 4 + 24 * 4 + 7 * sizeof(glm::vec4);
    r.gpu_bytes = std::int64_t(pw.volumes().vertex_count() * sizeof(glm::vec4) + pw.volumes().index_capacity() * 4 +
                               pw.wedge_capacity() * per_wedge) +
                  std::int64_t(v.width) * v.height * (4 + 8 + 4 + 4);
    r.work = {{"wedges", double(wedges)},
              {"wedges_skipped", double(skipped)},
              {"wedges_culled", double(culled)},
              {"wedges_back", double(back)},
              {"silhouette_edges", double(edges)},
              {"volume_triangles", double(triangles)},
              {"casters_zfail", double(zfail)},
              {"wedge_fragments", frags},
              {"wedge_fragments_in", frags_in},
              {"wedge_fragments_unculled", frags_full},
              {"wedge_ms", wedge_ms},
              {"wedge_ms_unculled", wedge_ms_full},
              {"wedge_speedup", wedge_ms > 0.0 ? wedge_ms_full / wedge_ms : 1.0},
              {"light_radius", double(pw.light_radius())},
              {"depth_bounds_native", native ? 1.0 : 0.0}};
    if (s.projection == S::Projection::Infinite)
        r.work.emplace_back("projection_epsilon", double(pw.volumes().projection_epsilon()));
    if (has_stats) {
        r.work.emplace_back("fs_invocations", inv);
        r.work.emplace_back("fs_invocations_unculled", inv_full);
    }
    return true;
}

}  // namespace

void add_wedge_techniques(std::vector<std::unique_ptr<Technique>>& out) {
    ReportSpec<PenumbraWedges, S> spec;
    spec.name = "penumbra_wedges";
    spec.description = "soft shadow volumes: hard stencil volume from the light center + one penumbra wedge per silhouette "
                       "edge (penumbra_wedge.hpp, glsl/penumbra_wedge.glsl), signed analytic coverage added into R32F; "
                       "per-wedge scissor and depth bounds; projection=infinite: epsilon-tweaked P_inf";
    spec.hard = false;
    spec.applies = [](const Scene& scene) {  // a light with an area
        const Light& L = scene.light;
        return (L.type == LightType::Rect || L.type == LightType::Disk || L.type == LightType::Sphere) && L.size > 0.f;
    };
    spec.sweep_for = [](const Scene& scene, bool quick) -> std::vector<std::string> {
        std::vector<std::string> rows;
        if (quick)
            rows = {"scissor=off depth_bounds=off", "scissor=on depth_bounds=on"};
        else if (scene.light.type == LightType::Rect)
            rows = {"scissor=off depth_bounds=off", "scissor=on depth_bounds=off",
                    "scissor=off depth_bounds=on",  "scissor=on depth_bounds=on",
                    "scissor=on depth_bounds=on projection=infinite", "scissor=on depth_bounds=on rect_radius=bounding"};
        else
            rows = {"scissor=off depth_bounds=off", "scissor=on depth_bounds=off", "scissor=on depth_bounds=on",
                    "scissor=off depth_bounds=on", "scissor=on depth_bounds=on projection=infinite"};
        // an open caster: the defaults with the two-sided volume and silhouette (the default is lit_only)
        if (scene_has_open_caster(scene)) rows.push_back("scissor=on depth_bounds=on open_meshes=two_sided");
        return rows;
    };
    // scanned meshes: the defaults (the others are speed settings) and the two-sided open-mesh mode
    spec.mesh_sweep = {"scissor=on depth_bounds=on", "scissor=on depth_bounds=on open_meshes=two_sided"};
    spec.measure = measure;
    add_technique(out, std::move(spec));
}

}  // namespace sk
