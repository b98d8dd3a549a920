// Technique drivers: soft shadows from linear lights.
//
// linear_light (size, segments k): Heidrich, Brabec & Seidel 2000 with linear_light.hpp and
// glsl/linear_light.glsl. The light is split into k sub-lights (k + 1 endpoint shadow maps); for
// each sub-light, the skin of each endpoint's map is warped into the other endpoint's view and
// MIN-blended into that endpoint's RG16F visibility map; V = mean over sub-lights of
// lit_a v_a + lit_b v_b. k = 1 is the paper's method; k > 1 its fix for thin occluders that hide
// the middle of the light from points that see both ends. A zero-length light (or a point light)
// takes the point-light path: one map, V = its depth test.
// sampled_line (size, samples N): N shadow maps at the centers of N equal pieces of the segment
// (2x2 hardware PCF each), averaged: the brute-force baseline for equal-time comparisons.
#include <shadowkit/linear_light.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "driver_util.hpp"

namespace sk {

namespace {

struct EndpointView {
    glm::vec3 pos{0.f};
    glm::mat4 view{1.f}, proj{1.f}, vp{1.f}, inv_vp{1.f};
    float znear = 0.f, zfar = 0.f;
};

// A perspective frustum from `pos` looking at the scene's bounding-box center, covering the box.
EndpointView endpoint_view(const Scene& s, glm::vec3 pos) {
    EndpointView e;
    e.pos = pos;
    const glm::vec3 lo = s.bounds_min(), hi = s.bounds_max(), center = 0.5f * (lo + hi);
    glm::vec3 dir = center - pos;
    dir = glm::length(dir) > 0.f ? glm::normalize(dir) : glm::vec3(0.f, -1.f, 0.f);
    const glm::vec3 up = std::abs(dir.y) > 0.9f ? glm::vec3(0.f, 0.f, 1.f) : glm::vec3(0.f, 1.f, 0.f);
    e.view = glm::lookAt(pos, pos + dir, up);
    float tan_max = 0.f;
    fit_box_depth(e.view, lo, hi, e.znear, e.zfar, tan_max);
    const float half = std::min(std::atan(tan_max) * 1.02f, 1.45f);
    e.proj = glm::perspective(2.f * half, 1.f, e.znear, e.zfar);
    e.vp = e.proj * e.view;
    e.inv_vp = glm::inverse(e.vp);
    return e;
}

bool linear_scene(const Scene& s) { return s.light.type == LightType::Linear; }

shadowkit::LinearLightSegment scene_segment(const Light& L) {
    if (L.type != LightType::Linear) return shadowkit::linear_light_segment(L.position, glm::vec3(1.f, 0.f, 0.f), 0.f);
    return shadowkit::linear_light_segment(L.position, L.direction, L.size);
}

constexpr int kMaxSegments = 4;

const char* kSkinVS = R"(
layout(binding = 4) uniform sampler2D u_other_depth;
uniform mat4 u_other_inv_vp;
uniform vec2 u_other_near_far;
uniform mat4 u_this_vp;
uniform float u_threshold;
noperspective out float v_value;
void main() {
    gl_Position = sk_linear_light_skin_vertex(u_other_depth, u_other_inv_vp, u_other_near_far.x, u_other_near_far.y,
                                              u_this_vp, u_threshold, gl_VertexID, v_value);
}
)";
const char* kSkinFS = R"(
noperspective in float v_value;
layout(location = 0) out vec4 o_vis;
void main() { o_vis = sk_linear_light_skin_output(v_value, gl_FragCoord.z); }
)";
// CPU-built skin (linear_light_build_skin): world position + value per vertex.
const char* kSkinCpuVS = R"(
layout(location = 0) in vec3 a_position;
layout(location = 1) in float a_value;
uniform mat4 u_this_vp;
noperspective out float v_value;
void main() {
    v_value = a_value;
    gl_Position = u_this_vp * vec4(a_position, 1.0);
}
)";

class LinearLightTech final : public Technique {
public:
    std::string name() const override { return "linear_light"; }
    std::string description() const override {
        return "linear light (Heidrich et al. 2000): endpoint shadow maps + skin visibility maps; the light split "
               "into `segments` sub-lights";
    }
    bool hard() const override { return false; }
    std::vector<ParamSet> sweep(const Scene& scene, bool quick) const override {
        if (!linear_scene(scene)) return {};
        std::vector<ParamSet> out;
        if (quick) {
            for (int k : {1, 2}) out.push_back(ParamSet{{{"size", 512.0}, {"segments", double(k)}}});
            return out;
        }
        for (int k : {1, 2, 4}) out.push_back(ParamSet{{{"size", 512.0}, {"segments", double(k)}}});
        out.push_back(ParamSet{{{"size", 512.0}, {"segments", 1.0}, {"gpu_skin", 1.0}}});
        return out;
    }
    RunResult run(const RunContext& ctx, const ParamSet& params) override {
        const Scene& scene = ctx.scene;
        const Light& L = scene.light;
        if (L.type != LightType::Linear && L.type != LightType::Point)
            return RunResult::failure("linear_light driver: needs a linear (or point) light");
        const int size = std::max(16, static_cast<int>(params.get("size", 512)));
        const shadowkit::LinearLightSegment seg = scene_segment(L);
        if (seg.status != shadowkit::Status::Ok) return RunResult::failure("invalid linear light");
        const int k = seg.is_point ? 1 : std::clamp(static_cast<int>(params.get("segments", 1)), 1, kMaxSegments);
        const float threshold = static_cast<float>(params.get("threshold", 0.05));
        // skin built on the CPU from the read-back depth map (linear_light_build_skin: only the
        // discontinuity cells are drawn) or, gpu_skin = 1, by sk_linear_light_skin_vertex for every cell
        const bool gpu_skin = params.get("gpu_skin", 0.0) != 0.0;
        std::string why;
        const auto c0 = Clock::now();
        glm::vec3 ends[kMaxSegments + 1];
        if (shadowkit::linear_light_subdivide(seg, static_cast<std::uint32_t>(k), ends, kMaxSegments + 1).status !=
            shadowkit::Status::Ok)
            return RunResult::failure("linear_light_subdivide failed");
        const int nmaps = seg.is_point ? 1 : k + 1;
        std::vector<EndpointView> views;
        for (int i = 0; i < nmaps; ++i) views.push_back(endpoint_view(scene, ends[i]));
        RunResult r;
        r.cpu_ms = ms_since(c0);

        std::vector<skgl::Target> maps(static_cast<std::size_t>(nmaps)), vmaps(seg.is_point ? 0 : static_cast<std::size_t>(2 * k));
        for (auto& t : maps) {
            if (!skgl::make_target(t, size, size, {}, GL_DEPTH_COMPONENT32F, why)) return RunResult::failure(why);
            skgl::set_depth_compare(t.depth, false, false);
            set_nearest_clamped(t.depth);
        }
        for (auto& t : vmaps) {
            if (!skgl::make_target(t, size, size, {GL_RGBA32F}, 0, why)) return RunResult::failure(why);
            set_nearest_clamped(t.color[0]);
        }
        VisibilityPass pass;
        if (!pass.init(ctx.gpu.width, ctx.gpu.height, why)) return RunResult::failure(why);
        const std::string snippet = load_snippet("linear_light", why);
        if (snippet.empty()) return RunResult::failure(why);
        std::string log;
        GLuint depth = compile_depth_only_program(log);
        GLuint skin = skgl::compile_program({{GL_VERTEX_SHADER, "#version 450 core\n" + snippet + kSkinVS},
                                             {GL_FRAGMENT_SHADER, "#version 450 core\n" + snippet + kSkinFS}},
                                            log);
        // lookup: sub-light i uses maps i, i+1 (units 2 + i) and visibility maps 2i, 2i+1 (units 7 + ...)
        std::string body = "uniform mat4 u_vp[" + std::to_string(kMaxSegments + 1) + "];\nuniform vec3 u_end[" +
                           std::to_string(kMaxSegments + 1) + "];\nuniform int u_segments;\nuniform bool u_point;\n";
        body += "layout(binding = 2) uniform sampler2D u_depth[" + std::to_string(kMaxSegments + 1) + "];\n";
        body += "layout(binding = 7) uniform sampler2D u_vis[" + std::to_string(2 * kMaxSegments) + "];\n";
        body += R"(
float technique_visibility(vec3 p, vec3 n) {
    if (u_point) {   // zero length: the point-light result (one map, its depth test)
        if (dot(n, u_end[0] - p) <= 0.0) return 0.0;
        vec4 c = u_vp[0] * vec4(p, 1.0);
        if (c.w <= 0.0) return 1.0;
        vec3 w = c.xyz / c.w * 0.5 + 0.5;
        if (any(lessThan(w.xy, vec2(0.0))) || any(greaterThan(w.xy, vec2(1.0)))) return 1.0;
        ivec2 sz = textureSize(u_depth[0], 0);
        return w.z <= texelFetch(u_depth[0], clamp(ivec2(w.xy * vec2(sz)), ivec2(0), sz - 1), 0).r ? 1.0 : 0.0;
    }
    float v = 0.0;
)";
        for (int i = 0; i < kMaxSegments; ++i)
            body += "    if (" + std::to_string(i) + " < u_segments) v += sk_linear_light_visibility(u_depth[" +
                    std::to_string(i) + "], u_vis[" + std::to_string(2 * i) + "], u_vp[" + std::to_string(i) +
                    "], u_end[" + std::to_string(i) + "], u_depth[" + std::to_string(i + 1) + "], u_vis[" +
                    std::to_string(2 * i + 1) + "], u_vp[" + std::to_string(i + 1) + "], u_end[" +
                    std::to_string(i + 1) + "], p, n, 0.0);\n";
        body += "    return v / float(u_segments);\n}\n";
        GLuint vis = compile_visibility_program(snippet, body, log);
        GLuint skin_cpu = skgl::compile_program({{GL_VERTEX_SHADER, "#version 450 core\n" + snippet + kSkinCpuVS},
                                                 {GL_FRAGMENT_SHADER, "#version 450 core\n" + snippet + kSkinFS}},
                                                log);
        if (!depth || !skin || !skin_cpu || !vis) return RunResult::failure(log);
        glUseProgram(vis);
        set_light_uniforms(vis, L);
        std::vector<glm::mat4> vps(kMaxSegments + 1, glm::mat4(1.f));
        std::vector<glm::vec3> es(kMaxSegments + 1, glm::vec3(0.f));
        for (int i = 0; i < nmaps; ++i) {
            vps[static_cast<std::size_t>(i)] = views[static_cast<std::size_t>(i)].vp;
            es[static_cast<std::size_t>(i)] = views[static_cast<std::size_t>(i)].pos;
        }
        glUniformMatrix4fv(glGetUniformLocation(vis, "u_vp"), kMaxSegments + 1, GL_FALSE, glm::value_ptr(vps[0]));
        glUniform3fv(glGetUniformLocation(vis, "u_end"), kMaxSegments + 1, glm::value_ptr(es[0]));
        glUniform1i(glGetUniformLocation(vis, "u_segments"), k);
        glUniform1i(glGetUniformLocation(vis, "u_point"), seg.is_point ? 1 : 0);
        GLuint empty_vao = 0;
        glGenVertexArrays(1, &empty_vao);
        const GLsizei skin_vertices = 6 * (size - 1) * (size - 1);
        // CPU skin: per endpoint map, read back depth, unproject, triangulate the discontinuities
        std::vector<float> zbuf(static_cast<std::size_t>(size) * static_cast<std::size_t>(size));
        std::vector<glm::vec3> spos(zbuf.size());
        std::vector<float> sdist(zbuf.size());
        std::vector<std::vector<shadowkit::LinearLightSkinVertex>> skins(static_cast<std::size_t>(nmaps));
        GLuint skin_vao = 0, skin_vbo = 0;
        glGenVertexArrays(1, &skin_vao);
        glGenBuffers(1, &skin_vbo);
        glBindVertexArray(skin_vao);
        glBindBuffer(GL_ARRAY_BUFFER, skin_vbo);
        glEnableVertexAttribArray(0);
        glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(shadowkit::LinearLightSkinVertex), nullptr);
        glEnableVertexAttribArray(1);
        glVertexAttribPointer(1, 1, GL_FLOAT, GL_FALSE, sizeof(shadowkit::LinearLightSkinVertex),
                              reinterpret_cast<const void*>(sizeof(glm::vec3)));
        glBindVertexArray(0);
        double cpu_skin_ms = 0.0;
        std::size_t skin_vertex_total = 0;
        auto build_skin_cpu = [&](int m) {
            const auto t0 = Clock::now();
            const EndpointView& o = views[static_cast<std::size_t>(m)];
            glBindFramebuffer(GL_READ_FRAMEBUFFER, maps[static_cast<std::size_t>(m)].fbo);
            glReadPixels(0, 0, size, size, GL_DEPTH_COMPONENT, GL_FLOAT, zbuf.data());
            const float n = o.znear, f = o.zfar;
            for (int j = 0; j < size; ++j)
                for (int i = 0; i < size; ++i) {
                    const std::size_t q = static_cast<std::size_t>(j) * static_cast<std::size_t>(size) + static_cast<std::size_t>(i);
                    const float zn = zbuf[q] * 2.f - 1.f;
                    sdist[q] = 2.f * n * f / (f + n - zn * (f - n));
                    const glm::vec4 w = o.inv_vp * glm::vec4((float(i) + 0.5f) / float(size) * 2.f - 1.f,
                                                             (float(j) + 0.5f) / float(size) * 2.f - 1.f, zn, 1.f);
                    spos[q] = glm::vec3(w) / w.w;
                }
            auto& sk_ = skins[static_cast<std::size_t>(m)];
            sk_.resize(shadowkit::linear_light_skin_capacity(static_cast<std::uint32_t>(size), static_cast<std::uint32_t>(size)) / 8);
            shadowkit::LinearLightSkinResult sr = shadowkit::linear_light_build_skin(
                spos.data(), sdist.data(), static_cast<std::uint32_t>(size), static_cast<std::uint32_t>(size), threshold,
                sk_.data(), sk_.size());
            if (sr.status == shadowkit::Status::BufferTooSmall) {
                sk_.resize(sr.needed);
                sr = shadowkit::linear_light_build_skin(spos.data(), sdist.data(), static_cast<std::uint32_t>(size),
                                                        static_cast<std::uint32_t>(size), threshold, sk_.data(), sk_.size());
            }
            sk_.resize(sr.count);
            skin_vertex_total += sr.count;
            cpu_skin_ms += ms_since(t0);
        };
        // binds the visibility map vt (size x size) and clears it to 1 (all visible)
        auto clear_to_visible = [&](skgl::Target& vt) {
            glBindFramebuffer(GL_FRAMEBUFFER, vt.fbo);
            glViewport(0, 0, size, size);
            const float one[4] = {1.f, 1.f, 1.f, 1.f};
            glClearBufferfv(GL_COLOR, 0, one);
        };
        auto draw_skin = [&](int from, int into, skgl::Target& vt) {
            const EndpointView& o = views[static_cast<std::size_t>(from)];
            if (!gpu_skin) {
                const auto& sv = skins[static_cast<std::size_t>(from)];
                glUseProgram(skin_cpu);
                glUniformMatrix4fv(glGetUniformLocation(skin_cpu, "u_this_vp"), 1, GL_FALSE,
                                   glm::value_ptr(views[static_cast<std::size_t>(into)].vp));
                clear_to_visible(vt);
                if (sv.empty()) return;
                glBindBuffer(GL_ARRAY_BUFFER, skin_vbo);
                glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(sv.size() * sizeof(sv[0])), sv.data(), GL_STREAM_DRAW);
                glBindVertexArray(skin_vao);
                glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(sv.size()));
                glBindVertexArray(empty_vao);
                return;
            }
            glUseProgram(skin);
            glUniformMatrix4fv(glGetUniformLocation(skin, "u_other_inv_vp"), 1, GL_FALSE, glm::value_ptr(o.inv_vp));
            glUniform2f(glGetUniformLocation(skin, "u_other_near_far"), o.znear, o.zfar);
            glUniformMatrix4fv(glGetUniformLocation(skin, "u_this_vp"), 1, GL_FALSE,
                               glm::value_ptr(views[static_cast<std::size_t>(into)].vp));
            clear_to_visible(vt);
            glActiveTexture(GL_TEXTURE4);
            glBindTexture(GL_TEXTURE_2D, maps[static_cast<std::size_t>(from)].depth);
            glDrawArrays(GL_TRIANGLES, 0, skin_vertices);
        };
        std::vector<GLuint> map_fbos;
        for (const auto& t : maps) map_fbos.push_back(t.fbo);
        auto frame = [&] {
            // every mesh: the skins need the receivers' depth behind the discontinuities
            // (non-casters below everything they receive cannot shadow anything)
            render_depth_layers(ctx.gpu, map_fbos.data(), vps.data(), nmaps, size, depth, true);
            glDisable(GL_DEPTH_TEST);
            if (!seg.is_point) {
                if (!gpu_skin) {
                    cpu_skin_ms = 0.0;
                    skin_vertex_total = 0;
                    for (int i = 0; i < nmaps; ++i) build_skin_cpu(i);
                }
                glUseProgram(skin);
                glUniform1f(glGetUniformLocation(skin, "u_threshold"), threshold);
                glEnable(GL_BLEND);
                glBlendEquation(GL_MIN);
                glBindVertexArray(empty_vao);
                for (int i = 0; i < k; ++i) {
                    draw_skin(i + 1, i, vmaps[static_cast<std::size_t>(2 * i)]);      // at endpoint i, from i+1's map
                    draw_skin(i, i + 1, vmaps[static_cast<std::size_t>(2 * i + 1)]);  // at endpoint i+1, from i's map
                }
                glBindVertexArray(0);
                glBlendEquation(GL_FUNC_ADD);
                glDisable(GL_BLEND);
            }
            for (int i = 0; i < nmaps; ++i) {
                glActiveTexture(static_cast<GLenum>(GL_TEXTURE2 + i));
                glBindTexture(GL_TEXTURE_2D, maps[static_cast<std::size_t>(i)].depth);
            }
            for (std::size_t i = 0; i < vmaps.size(); ++i) {
                glActiveTexture(static_cast<GLenum>(GL_TEXTURE7 + i));
                glBindTexture(GL_TEXTURE_2D, vmaps[i].color[0]);
            }
            pass.draw(vis, ctx.gpu);
        };
        measure_visibility(r, ctx, pass, frame);
        r.cpu_ms += cpu_skin_ms;  // read-back + skin triangulation of the last frame (inside gpu_ms too)
        r.gpu_bytes = std::int64_t(size) * size * (4 * nmaps + 16 * std::int64_t(vmaps.size()));
        r.work = {{"shadow_maps", double(nmaps)},
                  {"visibility_maps", double(vmaps.size())},
                  {"skin_vertices_drawn",
                   seg.is_point ? 0.0 : (gpu_skin ? double(skin_vertices) * 2.0 * k : 2.0 * double(skin_vertex_total))},
                  {"triangles_drawn", double(ctx.gpu.caster_triangles) * nmaps}};
        return finish_run(std::move(r), {skin_cpu, depth, skin, vis}, [&] {
            glDeleteVertexArrays(1, &empty_vao);
            glDeleteVertexArrays(1, &skin_vao);
            glDeleteBuffers(1, &skin_vbo);
            for (auto& t : maps) skgl::destroy_target(t);
            for (auto& t : vmaps) skgl::destroy_target(t);
        });
    }
};

constexpr int kMaxLineSamples = 16;

class SampledLine final : public Technique {
public:
    std::string name() const override { return "sampled_line"; }
    std::string description() const override {
        return "N shadow maps at the centers of N equal pieces of the line light, 2x2 PCF each, averaged (baseline)";
    }
    bool hard() const override { return false; }
    std::vector<ParamSet> sweep(const Scene& scene, bool quick) const override {
        if (!linear_scene(scene)) return {};
        std::vector<ParamSet> out;
        const std::vector<int> ns = quick ? std::vector<int>{2, 8} : std::vector<int>{2, 4, 8, 16};
        for (int n : ns) out.push_back(ParamSet{{{"size", 512.0}, {"samples", double(n)}}});
        return out;
    }
    RunResult run(const RunContext& ctx, const ParamSet& params) override {
        const Scene& scene = ctx.scene;
        const shadowkit::LinearLightSegment seg = scene_segment(scene.light);
        if (seg.status != shadowkit::Status::Ok) return RunResult::failure("invalid linear light");
        const int size = std::max(16, static_cast<int>(params.get("size", 512)));
        const int n = std::clamp(static_cast<int>(params.get("samples", 4)), 1, kMaxLineSamples);
        std::vector<EndpointView> views;
        for (int i = 0; i < n; ++i) {
            const float t = (static_cast<float>(i) + 0.5f) / static_cast<float>(n);
            views.push_back(endpoint_view(scene, seg.end_a + t * (seg.end_b - seg.end_a)));
        }
        RunResult r;
        const GLuint arr = make_depth_compare_texture(GL_TEXTURE_2D_ARRAY, size, n);
        GLuint fbo = 0;
        glGenFramebuffers(1, &fbo);
        std::string why;
        VisibilityPass pass;
        if (!pass.init(ctx.gpu.width, ctx.gpu.height, why)) return RunResult::failure(why);
        GLuint depth = 0, vis = 0;
        if (!compile_shadow_programs("", R"(
layout(binding = 2) uniform sampler2DArrayShadow u_maps;
uniform mat4 u_vp[16];
uniform vec3 u_pos[16];
uniform int u_count;
float technique_visibility(vec3 p, vec3 n) {
    float v = 0.0;
    for (int i = 0; i < u_count; ++i) {
        if (dot(n, u_pos[i] - p) <= 0.0) continue;
        vec4 c = u_vp[i] * vec4(p, 1.0);
        if (c.w <= 0.0) { v += 1.0; continue; }
        vec3 w = c.xyz / c.w * 0.5 + 0.5;
        if (any(lessThan(w.xy, vec2(0.0))) || any(greaterThan(w.xy, vec2(1.0)))) { v += 1.0; continue; }
        v += texture(u_maps, vec4(w.xy, float(i), w.z));
    }
    return v / float(u_count);
}
)", scene.light, depth, vis, why))
            return RunResult::failure(why);
        std::vector<glm::mat4> vps(kMaxLineSamples, glm::mat4(1.f));
        std::vector<glm::vec3> ps(kMaxLineSamples, glm::vec3(0.f));
        for (int i = 0; i < n; ++i) {
            vps[static_cast<std::size_t>(i)] = views[static_cast<std::size_t>(i)].vp;
            ps[static_cast<std::size_t>(i)] = views[static_cast<std::size_t>(i)].pos;
        }
        glUniformMatrix4fv(glGetUniformLocation(vis, "u_vp"), kMaxLineSamples, GL_FALSE, glm::value_ptr(vps[0]));
        glUniform3fv(glGetUniformLocation(vis, "u_pos"), kMaxLineSamples, glm::value_ptr(ps[0]));
        glUniform1i(glGetUniformLocation(vis, "u_count"), n);
        auto frame = [&] {
            glBindFramebuffer(GL_FRAMEBUFFER, fbo);
            glDrawBuffer(GL_NONE);
            glReadBuffer(GL_NONE);
            glViewport(0, 0, size, size);
            begin_offset_depth_pass(depth);
            for (int i = 0; i < n; ++i) {
                glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, arr, 0, i);
                glClear(GL_DEPTH_BUFFER_BIT);
                glUniformMatrix4fv(glGetUniformLocation(depth, "u_light_view_proj"), 1, GL_FALSE,
                                   glm::value_ptr(views[static_cast<std::size_t>(i)].vp));
                draw_casters(ctx.gpu);
            }
            glDisable(GL_POLYGON_OFFSET_FILL);
            pass.draw(vis, ctx.gpu, GL_TEXTURE_2D_ARRAY, arr);
        };
        measure_visibility(r, ctx, pass, frame);
        r.gpu_bytes = std::int64_t(size) * size * 4 * n;
        r.work = {{"shadow_maps", double(n)}, {"triangles_drawn", double(ctx.gpu.caster_triangles) * n}};
        return finish_run(std::move(r), {depth, vis}, [&] {
            glActiveTexture(GL_TEXTURE2);
            glBindTexture(GL_TEXTURE_2D_ARRAY, 0);
            glDeleteFramebuffers(1, &fbo);
            glDeleteTextures(1, &arr);
        });
    }
};

}  // namespace

void add_linear_techniques(std::vector<std::unique_ptr<Technique>>& out) {
    out.push_back(std::make_unique<LinearLightTech>());
    out.push_back(std::make_unique<SampledLine>());
}

}  // namespace sk
