// samples/report/techniques/shadow_volumes.cpp - "shadow_volume" in the report: the sample's
// ShadowVolumes class (samples/shadow_volumes/) with timing, work counters and sweeps
// (report_technique.hpp).
//
// Sweep: method zfail / auto / zpass x scissor and depth bounds (the middle row, method=auto with both
// on, is the samples' default). method=zpass (z-pass for every caster: wrong wherever the camera is in
// a shadow, right on the built-in cameras) is a research row and a setting of the class; so are
// projection=infinite / reversed (the GL tests run them, the report does not sweep them). The old
// "projection 1" (the infinite projection against the G-buffer's finite depth, a documented failure)
// is no setting: tests/gl/test_gl_shadow_volume.cpp builds it by handing the class a G-buffer whose
// matrix is not the one its depth was written with.
//
// Work, from what the class exposes after the timed frames:
//   volume_triangles, silhouette_edges, casters, casters_zfail, casters_culled (empty scissor
//   rectangle), scissor_pixels (the rectangles' areas; without scissor the view per drawn caster):
//   casters();
//   volume_fragments: the fragments of draw_volumes() that survive scissor and depth bounds, counted
//   with GL_SAMPLES_PASSED in the class's volume state with the depth test GL_ALWAYS and no stencil
//   (the fill); volume_fragments_unculled: the same with scissor and depth bounds off (every caster's
//   full volume, the frame re-run); fs_invocations(_unculled): fragment-shader runs where
//   GL_ARB_pipeline_statistics_query exists (the GLSL depth-bounds emulation does not save them);
//   boundary_edges, nonmanifold_edges: the casters' adjacency; depth_bounds_native: 1 with
//   GL_EXT_depth_bounds_test; projection_epsilon (infinite, reversed); init_ms: init() (adjacency,
//   face planes, buffers, programs).
// gpu_bytes: the vertex and index buffers and the target (R32F + DEPTH32F_STENCIL8).
// Debug image (ctx.debug_images, the GL tests): "stencil counts", red = the raw 8-bit stencil value.
#include <algorithm>

#include "report_technique.hpp"
#include "shadow_volumes.hpp"

namespace sk {

namespace {

bool measure(ShadowVolumes& sv, const ShadowVolumeSettings& s, const app::View& v, const RunContext& ctx, RunResult& r) {
    const int W = v.width, H = v.height;
    if (ctx.debug_images) {  // the stencil of the last timed frame
        std::vector<std::uint8_t> st(static_cast<std::size_t>(W) * static_cast<std::size_t>(H));
        glBindFramebuffer(GL_READ_FRAMEBUFFER, sv.target().target.fbo);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadPixels(0, 0, W, H, GL_STENCIL_INDEX, GL_UNSIGNED_BYTE, st.data());
        DebugImage d;
        d.name = "stencil counts (red: raw count, grey: 64 x count)";
        d.width = W;
        d.height = H;
        for (std::uint8_t c : st) {
            const auto shown = static_cast<std::uint8_t>(std::min(255, 64 * int(c)));
            d.rgb.insert(d.rgb.end(), {c, shown, shown});
        }
        r.debug.push_back(std::move(d));
    }
    // the fill: draw_volumes in the class's state, depth test GL_ALWAYS, no stencil
    const bool has_stats = epoxy_has_gl_extension("GL_ARB_pipeline_statistics_query");
    auto fill = [&](const ShadowVolumeSettings& cs, double& fragments, double& invocations) {
        sv.begin_volume_state(cs);
        glDepthFunc(GL_ALWAYS);
        glDisable(GL_STENCIL_TEST);
        count_fragments(has_stats, [&] { sv.draw_volumes(cs); }, fragments, invocations);
        sv.end_volume_state();
    };
    double frags = 0.0, frags_full = 0.0, inv = -1.0, inv_full = -1.0;
    fill(s, frags, inv);
    std::size_t triangles = 0, sil_edges = 0, zfail = 0, culled = 0, boundary = 0, nonmanifold = 0;
    double scissor_pixels = 0.0;
    for (const ShadowVolumes::Caster& c : sv.casters()) {
        boundary += c.adj.boundary_edges;
        nonmanifold += c.adj.nonmanifold_edges.size();
        if (!c.visible) {
            ++culled;
            continue;
        }
        if (s.scissor) scissor_pixels += double(c.sc.width) * double(c.sc.height);
        zfail += c.zfail ? 1 : 0;
        sil_edges += c.sil_edges;
        triangles += (c.side_count + c.cap_count) / 3;
    }
    const std::size_t casters = sv.casters().size();
    ShadowVolumeSettings unculled = s;  // every caster's full volume
    unculled.scissor = unculled.depth_bounds = false;
    sv.update(v, unculled);
    sv.render(v, unculled);
    fill(unculled, frags_full, inv_full);
    r.gpu_bytes = std::int64_t(sv.vertex_count() * sizeof(glm::vec4) + sv.index_capacity() * sizeof(std::uint32_t)) +
                  std::int64_t(W) * H * (8 + 4);
    r.work = {{"volume_triangles", double(triangles)},
              {"silhouette_edges", double(sil_edges)},
              {"casters", double(casters)},
              {"casters_zfail", double(zfail)},
              {"casters_culled", double(culled)},
              {"scissor_pixels", s.scissor ? scissor_pixels : double(W) * H * double(casters - culled)},
              {"volume_fragments", frags},
              {"volume_fragments_unculled", frags_full},
              {"boundary_edges", double(boundary)},
              {"nonmanifold_edges", double(nonmanifold)},
              {"depth_bounds_native", sv.native_depth_bounds() && s.depth_bounds &&
                                              s.projection == ShadowVolumeSettings::Projection::Finite
                                          ? 1.0
                                          : 0.0}};
    if (s.projection != ShadowVolumeSettings::Projection::Finite)
        r.work.emplace_back("projection_epsilon", double(sv.projection_epsilon()));
    if (has_stats) {
        r.work.emplace_back("fs_invocations", inv);
        r.work.emplace_back("fs_invocations_unculled", inv_full);
    }
    return true;
}

}  // namespace

void add_volume_techniques(std::vector<std::unique_ptr<Technique>>& out) {
    ReportSpec<ShadowVolumes, ShadowVolumeSettings> spec;
    spec.name = "shadow_volume";
    spec.description = "robust stenciled shadow volumes (Everitt-Kilgard; z-fail, or z-pass / z-fail per caster), "
                       "Lengyel scissor and depth bounds; area lights from their center";
    spec.quick = {"method=auto scissor=off depth_bounds=off", "method=auto scissor=on depth_bounds=on"};
    spec.sweep = {"method=zfail scissor=off depth_bounds=off", "method=auto scissor=off depth_bounds=off",
                  "method=zpass scissor=off depth_bounds=off", "method=zfail scissor=on depth_bounds=on",
                  "method=auto scissor=on depth_bounds=on",    "method=zpass scissor=on depth_bounds=on",
                  "method=auto scissor=on depth_bounds=off",   "method=auto scissor=off depth_bounds=on"};
    // a scene with an open caster (a --mesh bowl, a built-in scene with a hole): the default row again with
    // the one-sided volume (open_meshes=lit_only, the sample's behaviour before two-sided volumes)
    spec.sweep_for = [sweep = spec.sweep, quick = spec.quick](const Scene& scene, bool q) {
        std::vector<std::string> rows = q ? quick : sweep;
        if (scene_has_open_caster(scene)) rows.push_back("method=auto scissor=on depth_bounds=on open_meshes=lit_only");
        return rows;
    };
    // scanned meshes (open, with holes): the defaults, and z-fail for every caster
    spec.mesh_sweep = {"method=auto scissor=on depth_bounds=on", "method=zfail scissor=on depth_bounds=on"};
    spec.measure = measure;
    add_technique(out, std::move(spec));
}

}  // namespace sk
