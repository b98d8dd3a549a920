// Technique drivers: shadow silhouette maps (silhouette_map.hpp + glsl/silhouette_map.glsl) and the
// plain shadow map of equal memory beside them.
//
// silhouette_map (size N): per frame, on the CPU, silhouette edges of every caster for the light's
// position (silhouette.hpp, adjacency built once) projected into texel space
// (silmap_project_edges); on the GPU, (1) the N x N depth map, (2) the N x N RGBA8 silhouette map
// (edges as instanced quads, the paper's point cases, occlusion test, weights), (3) the lookup.
// 8 bytes per texel. silmap_plain (size N): the plain 2x2-PCF shadow map of the same memory,
// side round(sqrt(2) N) (4 bytes per texel), so rows at equal `size` compare at equal memory.
#include <shadowkit/silhouette.hpp>
#include <shadowkit/silhouette_map.hpp>

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>

#include "driver_util.hpp"

namespace sk {

namespace {

bool silmap_scene(const Scene& s) {
    // hard lights with a perspective frustum: the straight-edged stack, the thin fence slats, duel
    return s.name == "stack" || s.name == "fence" || s.name == "duel";
}

const char* kEdgeVS = R"(
layout(location = 0) in vec4 a_ab;   // a.xy, b.xy (texel space)
layout(location = 1) in vec2 a_z;    // window depths at a and b
uniform vec2 u_size;
flat out vec4 v_ab;
flat out vec2 v_z;
void main() {
    v_ab = a_ab;
    v_z = a_z;
    gl_Position = sk_silmap_edge_vertex(a_ab.xy, a_ab.zw, gl_VertexID, u_size);
}
)";

const char* kEdgeFS = R"(
layout(binding = 2) uniform sampler2D u_depth;
flat in vec4 v_ab;
flat in vec2 v_z;
uniform float u_occlusion_bias;
layout(location = 0) out vec4 o_silmap;
void main() {
    vec2 local;
    float w;
    if (!sk_silmap_point(gl_FragCoord.xy, v_ab.xy, v_ab.zw, local, w)) discard;
    if (sk_silmap_occluded(u_depth, ivec2(gl_FragCoord.xy), v_ab.xy, v_ab.zw, v_z.x, v_z.y, local, u_occlusion_bias)) discard;
    o_silmap = vec4(local, 0.0, w / 255.0);
}
)";

class SilhouetteMapTech final : public Technique {
public:
    explicit SilhouetteMapTech(bool plain) : plain_(plain) {}
    std::string name() const override { return plain_ ? "silmap_plain" : "silhouette_map"; }
    std::string description() const override {
        return plain_ ? "plain 2x2-PCF shadow map with the memory of silhouette_map at the same size (side sqrt(2) N)"
                      : "shadow silhouette map (Sen et al. 2003): N^2 depth + N^2 RGBA8 silhouette points, "
                        "multi-edge texels fall back to the plain map";
    }
    bool hard() const override { return true; }
    std::vector<ParamSet> sweep(const Scene& scene, bool quick) const override {
        if (!silmap_scene(scene)) return {};
        std::vector<ParamSet> out;
        const std::vector<int> sizes = quick ? std::vector<int>{512} : std::vector<int>{256, 512, 1024};
        for (int s : sizes) out.push_back(ParamSet{{{"size", double(s)}}});
        return out;
    }
    RunResult run(const RunContext& ctx, const ParamSet& params) override {
        const Light& L = ctx.scene.light;
        if (L.type == LightType::Point || L.type == LightType::Directional)
            return RunResult::failure("silhouette_map driver: needs a light with a perspective frustum (spot/area)");
        const int n = std::max(8, static_cast<int>(params.get("size", 512)));
        return plain_ ? run_plain(ctx, int(std::lround(std::sqrt(2.0) * n))) : run_silmap(ctx, n);
    }

private:
    bool plain_;

    RunResult run_plain(const RunContext& ctx, int size) {
        RunResult r;
        const LightMatrices lm = fit_light(ctx.scene);
        r.work = {{"shadow_map_texels", double(size) * size}, {"triangles_drawn", double(ctx.gpu.caster_triangles)}};
        return run_single_shadow_map(ctx, std::move(r), size, lm.proj * lm.view, plain_shadow_map_lookup());
    }

    RunResult run_silmap(const RunContext& ctx, int size) {
        RunResult r;
        std::string why;
        const Scene& scene = ctx.scene;
        const LightMatrices lm = fit_light(scene);
        const glm::mat4 light_vp = lm.proj * lm.view;
        const glm::vec4 light4(scene.light.position, 1.f);
        // adjacency once per run (allocates; not part of the per-frame CPU time)
        std::vector<shadowkit::SilhouetteAdjacency> adj;
        std::vector<std::size_t> which;
        std::size_t max_edges = 0;
        for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
            const Mesh& m = scene.meshes[i];
            if (!m.caster) continue;
            adj.push_back(shadowkit::silhouette_build_adjacency(m.positions.data(), m.positions.size(), m.indices.data(),
                                                                m.indices.size()));
            if (adj.back().status != shadowkit::Status::Ok) return RunResult::failure("adjacency failed for " + m.name);
            which.push_back(i);
            max_edges += adj.back().max_silhouette_edges();
        }
        std::vector<std::uint8_t> facing;
        std::vector<std::uint32_t> sil;
        std::vector<shadowkit::SilmapEdge> edges(max_edges);
        std::vector<float> vb(6 * std::max<std::size_t>(max_edges, 1));
        std::size_t edge_count = 0;
        const glm::uvec2 usz(static_cast<unsigned>(size), static_cast<unsigned>(size));
        auto cpu_work = [&]() -> bool {
            edge_count = 0;
            for (std::size_t k = 0; k < adj.size(); ++k) {
                const Mesh& m = scene.meshes[which[k]];
                facing.resize(adj[k].face_count());
                if (shadowkit::silhouette_compute_facing(adj[k], m.positions.data(), m.positions.size(), light4, facing.data(),
                                                         facing.size())
                        .status != shadowkit::Status::Ok)
                    return false;
                sil.resize(2 * adj[k].max_silhouette_edges());
                const auto sr = shadowkit::silhouette_extract(adj[k], facing.data(), facing.size(), sil.data(), sil.size(),
                                                              nullptr, 0);
                const auto pr = shadowkit::silmap_project_edges(light_vp, shadowkit::ClipDepth::NegativeOneToOne, usz,
                                                                m.positions.data(), m.positions.size(), sil.data(),
                                                                sr.count / 2, edges.data() + edge_count,
                                                                edges.size() - edge_count);
                if (pr.status != shadowkit::Status::Ok) return false;
                edge_count += pr.count;
            }
            for (std::size_t e = 0; e < edge_count; ++e) {
                const auto& E = edges[e];
                const float v[6] = {E.a.x, E.a.y, E.b.x, E.b.y, E.depth_a, E.depth_b};
                std::copy(v, v + 6, vb.begin() + static_cast<std::ptrdiff_t>(6 * e));
            }
            return true;
        };
        if (!median_cpu_ms(5, cpu_work, r.cpu_ms)) return RunResult::failure("silhouette extraction failed");

        skgl::Target sm, silmap;
        if (!skgl::make_target(sm, size, size, {}, GL_DEPTH_COMPONENT32F, why)) return RunResult::failure(why);
        if (!skgl::make_target(silmap, size, size, {GL_RGBA8}, 0, why)) return RunResult::failure(why);
        for (GLuint t : {sm.depth, silmap.color[0]}) set_nearest_clamped(t);
        skgl::set_depth_compare(sm.depth, false, false);
        VisibilityPass pass;
        if (!pass.init(ctx.gpu.width, ctx.gpu.height, why)) return RunResult::failure(why);
        const std::string snippet = load_snippet("silhouette_map", why);
        if (snippet.empty()) return RunResult::failure(why);
        std::string log;
        GLuint depth = compile_depth_only_program(log);
        GLuint edge_prog = skgl::compile_program({{GL_VERTEX_SHADER, "#version 450 core\n" + snippet + kEdgeVS},
                                                  {GL_FRAGMENT_SHADER, "#version 450 core\n" + snippet + kEdgeFS}},
                                                 log);
        GLuint vis = compile_visibility_program(snippet, R"(
layout(binding = 2) uniform sampler2D u_depth;
layout(binding = 3) uniform sampler2D u_silmap;
uniform mat4 u_light_view_proj;
float technique_visibility(vec3 p, vec3 n) {
    vec4 c = u_light_view_proj * vec4(p, 1.0);
    if (c.w <= 0.0) return 1.0;
    vec3 w = c.xyz / c.w * 0.5 + 0.5;
    if (any(lessThan(w.xy, vec2(0.0))) || any(greaterThan(w.xy, vec2(1.0)))) return 1.0;
    return sk_silmap_visibility(u_depth, u_silmap, w.xy * vec2(textureSize(u_depth, 0)), w.z, 0.0);
}
)", log);
        if (!depth || !edge_prog || !vis) return RunResult::failure(log);
        GLuint vao = 0, vbo = 0;
        glGenVertexArrays(1, &vao);
        glGenBuffers(1, &vbo);
        glBindVertexArray(vao);
        glBindBuffer(GL_ARRAY_BUFFER, vbo);
        glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vb.size() * sizeof(float)), nullptr, GL_STREAM_DRAW);
        glEnableVertexAttribArray(0);
        glVertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
        glVertexAttribDivisor(0, 1);
        glEnableVertexAttribArray(1);
        glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, 6 * sizeof(float), reinterpret_cast<const void*>(4 * sizeof(float)));
        glVertexAttribDivisor(1, 1);
        glBindVertexArray(0);
        glUseProgram(edge_prog);
        glUniform2f(glGetUniformLocation(edge_prog, "u_size"), float(size), float(size));
        glUniform1f(glGetUniformLocation(edge_prog, "u_occlusion_bias"), 2e-4f);
        glUseProgram(vis);
        set_light_uniforms(vis, scene.light);
        glUniformMatrix4fv(glGetUniformLocation(vis, "u_light_view_proj"), 1, GL_FALSE, glm::value_ptr(light_vp));
        auto frame = [&] {
            // (1) depth map
            render_shadow_depth(ctx.gpu, sm.fbo, size, depth, light_vp);
            glDisable(GL_DEPTH_TEST);
            // (2) silhouette map: edges (this frame's CPU output) as widened quads
            glBindBuffer(GL_ARRAY_BUFFER, vbo);
            glBufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(6 * edge_count * sizeof(float)), vb.data());
            glBindFramebuffer(GL_FRAMEBUFFER, silmap.fbo);
            const float clear[4] = {0.5f, 0.5f, 0.f, 0.f};
            glClearBufferfv(GL_COLOR, 0, clear);
            glEnable(GL_BLEND);
            glBlendEquation(GL_FUNC_ADD);
            glBlendFuncSeparate(GL_ONE, GL_ZERO, GL_ONE, GL_ONE);
            glUseProgram(edge_prog);
            glActiveTexture(GL_TEXTURE2);
            glBindTexture(GL_TEXTURE_2D, sm.depth);
            glBindVertexArray(vao);
            glDrawArraysInstanced(GL_TRIANGLES, 0, 6, static_cast<GLsizei>(edge_count));
            glBindVertexArray(0);
            glDisable(GL_BLEND);
            // (3) lookup
            glActiveTexture(GL_TEXTURE3);
            glBindTexture(GL_TEXTURE_2D, silmap.color[0]);
            pass.draw(vis, ctx.gpu, GL_TEXTURE_2D, sm.depth);
        };
        measure_visibility(r, ctx, pass, frame);
        r.gpu_bytes = std::int64_t(size) * size * shadowkit::kSilmapBytesPerTexel;
        // failure texels (two silhouette curves in one texel) from the GPU map
        const std::vector<float> sv = skgl::read_color_float(silmap, 0, 4);
        std::size_t fail = 0, written = 0;
        for (std::size_t k = 0; k < sv.size() / 4; ++k) {
            const float w = sv[4 * k + 3] * 255.f;
            if (w > 0.5f) ++written;
            if (w > 2.5f) ++fail;
        }
        r.work = {{"shadow_map_texels", double(size) * size},
                  {"silhouette_edges", double(edge_count)},
                  {"silhouette_texels", double(written)},
                  {"triangles_drawn", double(ctx.gpu.caster_triangles)}};
        r.quality = {{"failure_texels", double(fail)},
                     {"failure_fraction", written ? double(fail) / double(written) : 0.0}};
        return finish_run(std::move(r), {depth, edge_prog, vis}, [&] {
            glDeleteBuffers(1, &vbo);
            glDeleteVertexArrays(1, &vao);
            skgl::destroy_target(sm);
            skgl::destroy_target(silmap);
        });
    }
};

}  // namespace

void add_silmap_techniques(std::vector<std::unique_ptr<Technique>>& out) {
    out.push_back(std::make_unique<SilhouetteMapTech>(false));
    out.push_back(std::make_unique<SilhouetteMapTech>(true));
}

}  // namespace sk
