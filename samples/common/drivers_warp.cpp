// Drivers for the shadow-map fitting and warping headers: light_frustum.hpp (tight fit with caster
// culling), perspective_shadow_maps.hpp (uniform, PSM, LiSPSM, TSM) and cascades.hpp. Each
// composes the public header with its GLSL snippet, as a user would, and adds the perspective
// aliasing metric (texel footprint in screen pixels) measured at the G-buffer's receiver points.
#include <shadowkit/cascades.hpp>
#include <shadowkit/light_frustum.hpp>
#include <shadowkit/perspective_shadow_maps.hpp>

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>

#include "driver_util.hpp"

namespace sk {

namespace {

void caster_bounds(const Scene& s, glm::vec3& lo, glm::vec3& hi) {
    lo = glm::vec3(INFINITY);
    hi = glm::vec3(-INFINITY);
    for (const auto& m : s.meshes) {
        if (!m.caster) continue;
        glm::vec3 a, b;
        mesh_bounds(m, a, b);
        lo = glm::min(lo, a);
        hi = glm::max(hi, b);
    }
}

// What the light can reach: the scene bounds, and for a spot light their intersection with a box
// around its cone (apex + the cap disk at the farthest scene corner). Receivers outside the cone
// are unlit anyway: "leave out what the scene does not need".
void receiver_bounds(const Scene& s, glm::vec3& lo, glm::vec3& hi) {
    lo = s.bounds_min();
    hi = s.bounds_max();
    const Light& L = s.light;
    if (L.type != LightType::Spot) return;
    glm::vec3 clo, chi;
    spot_cone_box(L, lo, hi, 1.5f, clo, chi);
    lo = glm::max(lo, clo);
    hi = glm::min(hi, chi);
}

// G-buffer pixel k when it is a receiver facing the light: its point p and normal n; false otherwise.
bool lit_receiver(const Scene& scene, const GBuffer& g, std::size_t k, glm::vec3& p, glm::vec3& n) {
    if (g.kind[k] != 1) return false;
    p = glm::vec3(g.position[3 * k], g.position[3 * k + 1], g.position[3 * k + 2]);
    n = glm::vec3(g.normal[3 * k], g.normal[3 * k + 1], g.normal[3 * k + 2]);
    const glm::vec3 l = scene.light.type == LightType::Directional ? -glm::normalize(scene.light.direction)
                                                                   : glm::normalize(scene.light.position - p);
    return !(glm::dot(n, l) <= 0.f);  // NaN counts as facing
}

// Perspective aliasing over the receiver pixels that face the light (shadowkit's per-point
// dp/ds measure): mean, max and the fraction of pixels where one texel covers > 1 pixel.
void add_aliasing(RunResult& r, const Scene& scene, const SceneGpu& gpu, const GBuffer& g,
                  const std::vector<glm::mat4>& light_vps, const std::vector<int>& which, int size) {
    const glm::mat4 cam_vp = gpu.proj * gpu.view;
    double sum = 0.0, mx = 0.0;
    std::size_t n = 0, under = 0;
    for (std::size_t k = 0; k < g.kind.size(); ++k) {
        glm::vec3 p, nn;
        if (!lit_receiver(scene, g, k, p, nn)) continue;
        const int c = which.empty() ? 0 : which[k];
        if (c < 0) continue;
        const shadowkit::WarpAliasingValue ev = shadowkit::warp_aliasing_error(
            light_vps[static_cast<std::size_t>(c)], cam_vp, p, nn, static_cast<std::uint32_t>(size),
            glm::uvec2(static_cast<unsigned>(g.width), static_cast<unsigned>(g.height)));
        if (ev.status != shadowkit::Status::Ok) continue;
        const double e = ev.value;
        sum += e;
        mx = std::max(mx, e);
        if (e > 1.0) ++under;
        ++n;
    }
    if (n) {
        r.quality.push_back({"aliasing_mean", sum / double(n)});
        r.quality.push_back({"aliasing_max", mx});
        r.quality.push_back({"undersampled_fraction", double(under) / double(n)});
    }
}

// The samples' texel-density view: per receiver pixel the perspective aliasing error (screen
// pixels per shadow-map texel) in false colour: blue = oversampled (< 1/4), green = 1, red =
// undersampled (> 4), log scale; grey = not a lit-facing receiver.
DebugImage texel_density_image(const Scene& scene, const SceneGpu& gpu, const GBuffer& g, const glm::mat4& light_vp,
                               int size) {
    DebugImage d;
    d.name = "texel density (blue oversampled, green 1 texel/pixel, red undersampled)";
    d.width = g.width;
    d.height = g.height;
    d.rgb.assign(g.kind.size() * 3, 60);
    const glm::mat4 cam_vp = gpu.proj * gpu.view;
    for (std::size_t k = 0; k < g.kind.size(); ++k) {
        glm::vec3 p, nn;
        if (!lit_receiver(scene, g, k, p, nn)) continue;
        const shadowkit::WarpAliasingValue ev = shadowkit::warp_aliasing_error(
            light_vp, cam_vp, p, nn, static_cast<std::uint32_t>(size),
            glm::uvec2(static_cast<unsigned>(g.width), static_cast<unsigned>(g.height)));
        const double e = ev.value;
        if (ev.status != shadowkit::Status::Ok || e <= 0.0) continue;
        const double t = std::clamp(std::log2(e) / 2.0, -1.0, 1.0);  // -1: 1/4, 0: 1, +1: 4
        const double r = t > 0 ? t : 0.0, b = t < 0 ? -t : 0.0, gg = 1.0 - std::abs(t);
        d.rgb[3 * k] = static_cast<std::uint8_t>(std::lround(255.0 * r));
        d.rgb[3 * k + 1] = static_cast<std::uint8_t>(std::lround(255.0 * gg));
        d.rgb[3 * k + 2] = static_cast<std::uint8_t>(std::lround(255.0 * b));
    }
    return d;
}

// ------------------------------------------------------------------------- warped / fitted maps
// TSM with Martin & Tan's depth: the map is rasterized with light_vp (x, y) and its depth written
// per fragment from depth_vp (the light's own post-perspective depth, undistorted by the trapezoid),
// with the slope-scaled offset of glPolygonOffset(2, 2) computed in the shader (sk_warp_map_depth);
// the lookup takes x, y from light_vp and the compare depth from depth_vp.
RunResult run_separate_depth_map(const RunContext& ctx, RunResult r, int size, const glm::mat4& light_vp,
                                 const glm::mat4& depth_vp,
                                 const std::function<void(RunResult&, const skgl::Target&)>& extras) {
    std::string why;
    skgl::Target sm;
    if (!make_shadow_map_target(sm, size, why)) return RunResult::failure(why);
    VisibilityPass pass;
    if (!pass.init(ctx.gpu.width, ctx.gpu.height, why)) return RunResult::failure(why);
    GLuint plain = 0, vis = 0;
    if (!compile_shadow_programs("perspective_shadow_maps", R"(
layout(binding = 2) uniform sampler2DShadow u_shadow_map;
uniform mat4 u_warp;
uniform mat4 u_depth_proj;
float technique_visibility(vec3 p, vec3 n) { return sk_warp_shadow(u_shadow_map, u_warp, u_depth_proj, p, 0.0, false); }
)", ctx.scene.light, plain, vis, why))
        return RunResult::failure(why);
    glDeleteProgram(plain);
    const std::string snippet = load_snippet("perspective_shadow_maps", why);
    std::string log;
    const GLuint depth = skgl::compile_program(
        {{GL_VERTEX_SHADER, R"(#version 450 core
layout(location = 0) in vec3 a_position;
uniform mat4 u_light_view_proj;
uniform mat4 u_depth_proj;
out vec4 v_depth_clip;
void main() {
    gl_Position = u_light_view_proj * vec4(a_position, 1.0);
    v_depth_clip = u_depth_proj * vec4(a_position, 1.0);
}
)"},
         {GL_FRAGMENT_SHADER, "#version 450 core\n" + snippet + R"(
in vec4 v_depth_clip;
void main() { gl_FragDepth = sk_warp_map_depth(v_depth_clip, 2.0, 0.0, false); }
)"}},
        log);
    if (!depth) {
        glDeleteProgram(vis);
        return RunResult::failure(log);
    }
    glUseProgram(vis);
    glUniformMatrix4fv(glGetUniformLocation(vis, "u_warp"), 1, GL_FALSE, glm::value_ptr(light_vp));
    glUniformMatrix4fv(glGetUniformLocation(vis, "u_depth_proj"), 1, GL_FALSE, glm::value_ptr(depth_vp));
    glUseProgram(depth);
    glUniformMatrix4fv(glGetUniformLocation(depth, "u_depth_proj"), 1, GL_FALSE, glm::value_ptr(depth_vp));
    measure_visibility(r, ctx, pass, [&] {
        render_shadow_depth(ctx.gpu, sm.fbo, size, depth, light_vp, nullptr);
        pass.draw(vis, ctx.gpu, GL_TEXTURE_2D, sm.depth);
    });
    r.gpu_bytes = std::int64_t(size) * size * 4;
    if (extras) extras(r, sm);
    return finish_run(std::move(r), {depth, vis}, [&] { skgl::destroy_target(sm); });
}

// method: 0 fitted (light_frustum.hpp: tight fit + caster culling), 1 uniform, 2 PSM, 3 LiSPSM, 4 TSM.
class WarpedShadowMap final : public Technique {
public:
    std::string name() const override { return "warped_sm"; }
    std::string description() const override {
        return "fitted (light_frustum, caster culling) / uniform / PSM / LiSPSM / TSM shadow maps "
               "(method 0..4), with the perspective aliasing metric";
    }
    bool hard() const override { return true; }
    std::vector<ParamSet> sweep(const Scene& scene, bool quick) const override {
        // the warps are about perspective aliasing: the outdoor and duelling-frusta scenes (and user meshes)
        if (scene.name != "outdoor" && scene.name != "duel" && scene.name.rfind("mesh:", 0) != 0) return {};
        std::vector<ParamSet> out;
        const std::vector<int> sizes = quick ? std::vector<int>{1024} : std::vector<int>{512, 1024, 2048};
        for (int m = 0; m <= 4; ++m)
            for (int s : sizes) out.push_back(ParamSet{{{"method", double(m)}, {"size", double(s)}}});
        return out;
    }
    RunResult run(const RunContext& ctx, const ParamSet& params) override {
        const int method = static_cast<int>(params.get("method", 0));
        const int size = static_cast<int>(params.get("size", 1024));
        const Scene& scene = ctx.scene;
        if (scene.light.type == LightType::Point)
            return RunResult::failure("point light: needs an omnidirectional map (issue 10)");
        RunResult r;
        glm::mat4 light_vp(1.f);
        std::vector<std::uint32_t> keep;
        bool culled_list = false;
        // the CPU work (matrix fit and culling) timed as a median like the GPU pass
        std::string fit_error;
        bool fallback = false;
        glm::mat4 depth_vp(1.f);     // TSM: the light's undistorted depth (Martin & Tan), else light_vp
        bool separate_depth = false;
        auto fit = [&]() -> bool {
            glm::vec3 slo, shi, clo, chi;
            receiver_bounds(scene, slo, shi);
            caster_bounds(scene, clo, chi);
            if (method == 0) {
                std::vector<float> boxes;
                for (const auto& m : scene.meshes) {
                    glm::vec3 a, b;
                    mesh_bounds(m, a, b);
                    boxes.insert(boxes.end(), {a.x, a.y, a.z, b.x, b.y, b.z});
                }
                shadowkit::LightFrustumInput in;
                in.camera_view = ctx.gpu.view;
                in.camera_proj = ctx.gpu.proj;
                in.has_scene_bounds = true;
                in.scene_min = slo;
                in.scene_max = shi;
                in.light_position = scene.light.type == LightType::Directional  // w = 0: toward the light
                                        ? glm::vec4(-glm::normalize(scene.light.direction), 0.f)
                                        : glm::vec4(scene.light.position, 1.f);
                in.casters = boxes.data();
                in.caster_count = scene.meshes.size();
                in.shadow_map_size = static_cast<std::uint32_t>(size);
                keep.assign(scene.meshes.size(), 0);
                const auto res = shadowkit::light_frustum_fit(in, keep.data(), keep.size());
                if (res.status != shadowkit::Status::Ok) {
                    fit_error = std::string("light_frustum_fit status ") + shadowkit::status_name(res.status);
                    return false;
                }
                keep.resize(res.count);
                light_vp = res.view_proj;
                culled_list = true;
            } else {
                shadowkit::WarpInput in;
                in.camera_view = ctx.gpu.view;
                in.camera_proj = ctx.gpu.proj;
                in.light_position = scene.light.type == LightType::Directional  // w = 0: toward the light
                                        ? glm::vec4(-glm::normalize(scene.light.direction), 0.f)
                                        : glm::vec4(scene.light.position, 1.f);
                in.has_scene_bounds = true;
                in.scene_min = slo;
                in.scene_max = shi;
                in.has_caster_bounds = true;
                in.caster_min = clo;
                in.caster_max = chi;
                const shadowkit::WarpMethod wm = method == 1   ? shadowkit::WarpMethod::Uniform
                                                 : method == 2 ? shadowkit::WarpMethod::Psm
                                                 : method == 3 ? shadowkit::WarpMethod::Lispsm
                                                               : shadowkit::WarpMethod::Tsm;
                const shadowkit::WarpResult w = shadowkit::warp_matrix(in, wm);
                if (w.status != shadowkit::Status::Ok || !w.visible) {
                    fit_error = std::string("warp status ") + shadowkit::status_name(w.status) + (w.visible ? "" : ", nothing visible");
                    return false;
                }
                light_vp = w.light_view_proj;
                depth_vp = w.depth_view_proj;
                separate_depth = w.separate_depth;
                fallback = w.fallback_uniform;
            }
            return true;
        };
        if (!median_cpu_ms(std::max(ctx.frames, 1), fit, r.cpu_ms)) return RunResult::failure(fit_error);

        std::size_t drawn_tris = 0, drawn = 0;
        for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
            const bool kept = !culled_list || std::find(keep.begin(), keep.end(), static_cast<std::uint32_t>(i)) != keep.end();
            if (scene.meshes[i].caster && kept) {
                drawn_tris += scene.meshes[i].indices.size() / 3;
                ++drawn;
            }
        }
        r.work = {{"shadow_map_texels", double(size) * size},
                  {"triangles_drawn", double(drawn_tris)},
                  {"casters_drawn", double(drawn)},
                  {"casters_culled", double(caster_count(ctx.gpu) - drawn)}};
        static const SingleMapLookup kWarpLookup{"perspective_shadow_maps", R"(
layout(binding = 2) uniform sampler2DShadow u_shadow_map;
uniform mat4 u_warp;
float technique_visibility(vec3 p, vec3 n) { return sk_warp_shadow(u_shadow_map, u_warp, u_warp, p, 0.0, false); }
)", "u_warp"};
        auto extras = [&](RunResult& rr, const skgl::Target& sm) {
            if (fallback) rr.quality.push_back({"fallback_uniform", 1.0});
            if (ctx.gbuffer) add_aliasing(rr, scene, ctx.gpu, *ctx.gbuffer, {light_vp}, {}, size);
            if (!ctx.debug_images || !ctx.gbuffer) return;
            rr.debug.push_back(texel_density_image(scene, ctx.gpu, *ctx.gbuffer, light_vp, size));
            std::vector<float> texels(static_cast<std::size_t>(size) * static_cast<std::size_t>(size));
            skgl::set_depth_compare(sm.depth, false, false);
            glBindTexture(GL_TEXTURE_2D, sm.depth);
            glPixelStorei(GL_PACK_ALIGNMENT, 1);
            glGetTexImage(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT, GL_FLOAT, texels.data());
            rr.debug.push_back(
                grey_debug_image("shadow map (window depth, near = black)", size, size, texels, 1, 0, 1.f));
        };
        if (separate_depth) return run_separate_depth_map(ctx, std::move(r), size, light_vp, depth_vp, extras);
        return run_single_shadow_map(ctx, std::move(r), size, light_vp, kWarpLookup, culled_list ? &keep : nullptr,
                                     extras);
    }
};

// ------------------------------------------------------------------------- cascaded shadow maps
class CascadedShadowMap final : public Technique {
public:
    std::string name() const override { return "cascades"; }
    std::string description() const override {
        return "4 stable cascades (practical split scheme, lambda 0.75) in a depth array, 10% blend band";
    }
    bool hard() const override { return true; }
    std::vector<ParamSet> sweep(const Scene& scene, bool quick) const override {
        if (scene.light.type != LightType::Directional) return {};
        std::vector<ParamSet> out;
        const std::vector<int> sizes = quick ? std::vector<int>{512} : std::vector<int>{256, 512, 1024};
        for (int s : sizes) out.push_back(ParamSet{{{"size", double(s)}, {"count", 4.0}}});
        return out;
    }
    RunResult run(const RunContext& ctx, const ParamSet& params) override {
        const int size = static_cast<int>(params.get("size", 512));
        constexpr std::uint32_t kCount = 4;
        const Scene& scene = ctx.scene;
        if (scene.light.type != LightType::Directional) return RunResult::failure("cascades need a directional light");
        RunResult r;
        shadowkit::Cascade cs[kCount];
        float splits[kCount + 1];
        shadowkit::Status st = shadowkit::Status::NotRun;
        auto fit = [&]() -> bool {
            shadowkit::CascadeInput in;
            in.camera_view = ctx.gpu.view;
            in.camera_proj = ctx.gpu.proj;
            in.light_position = glm::vec4(-glm::normalize(scene.light.direction), 0.f);  // toward the light
            in.shadow_map_size = static_cast<std::uint32_t>(size);
            glm::vec3 clo, chi;
            caster_bounds(scene, clo, chi);
            in.has_caster_bounds = true;
            in.caster_min = clo;
            in.caster_max = chi;
            const shadowkit::CascadeFitResult res = shadowkit::cascade_fit(in, 0.75f, kCount, cs, kCount);
            st = res.status;
            std::copy(res.splits, res.splits + kCount + 1, splits);
            return st == shadowkit::Status::Ok;
        };
        if (!median_cpu_ms(std::max(ctx.frames, 1), fit, r.cpu_ms))
            return RunResult::failure(std::string("cascade_fit status ") + shadowkit::status_name(st));

        const GLuint arr = make_depth_compare_texture(GL_TEXTURE_2D_ARRAY, size, kCount);
        GLuint fbo[kCount];
        make_depth_layer_fbos(GL_TEXTURE_2D_ARRAY, arr, kCount, fbo);
        std::string why;
        VisibilityPass pass;
        if (!pass.init(ctx.gpu.width, ctx.gpu.height, why)) return RunResult::failure(why);
        GLuint depth = 0, vis = 0;
        if (!compile_shadow_programs("cascades", R"(
layout(binding = 2) uniform sampler2DArrayShadow u_cascades;
uniform mat4 u_cascade_vp[4];
uniform vec4 u_split_near;
uniform vec4 u_split_far;
uniform mat4 u_camera_view;
float technique_visibility(vec3 p, vec3 n) {
    float view_depth = -(u_camera_view * vec4(p, 1.0)).z;
    return sk_cascade_shadow(u_cascades, u_cascade_vp, u_split_near, u_split_far, 4, p, view_depth, 0.1, 0.0, false);
}
)", scene.light, depth, vis, why))
            return RunResult::failure(why);
        glm::mat4 vps[kCount];
        for (std::uint32_t i = 0; i < kCount; ++i) vps[i] = cs[i].view_proj;
        glUniformMatrix4fv(glGetUniformLocation(vis, "u_cascade_vp"), kCount, GL_FALSE, glm::value_ptr(vps[0]));
        glUniform4f(glGetUniformLocation(vis, "u_split_near"), splits[0], splits[1], splits[2], splits[3]);
        glUniform4f(glGetUniformLocation(vis, "u_split_far"), splits[1], splits[2], splits[3], splits[4]);
        glUniformMatrix4fv(glGetUniformLocation(vis, "u_camera_view"), 1, GL_FALSE, glm::value_ptr(ctx.gpu.view));
        measure_visibility(r, ctx, pass, [&] {
            render_depth_layers(ctx.gpu, fbo, vps, kCount, size, depth);
            pass.draw(vis, ctx.gpu, GL_TEXTURE_2D_ARRAY, arr);
        });
        r.gpu_bytes = std::int64_t(size) * size * 4 * kCount;
        r.work = {{"shadow_map_texels", double(kCount) * size * size},
                  {"triangles_drawn", double(kCount) * double(ctx.gpu.caster_triangles)},
                  {"casters_drawn", double(kCount) * double(caster_count(ctx.gpu))},
                  {"casters_culled", 0.0}};
        if (ctx.gbuffer) {
            // aliasing per pixel with the cascade that the lookup selects (by view depth)
            const GBuffer& g = *ctx.gbuffer;
            std::vector<int> which(g.kind.size(), -1);
            for (std::size_t k = 0; k < g.kind.size(); ++k) {
                if (g.kind[k] == 0) continue;
                const glm::vec4 v = ctx.gpu.view * glm::vec4(g.position[3 * k], g.position[3 * k + 1], g.position[3 * k + 2], 1.f);
                which[k] = shadowkit::cascade_select_by_depth(-v.z, splits, kCount).index;
            }
            add_aliasing(r, scene, ctx.gpu, g, std::vector<glm::mat4>(vps, vps + kCount), which, size);
        }
        return finish_run(std::move(r), {depth, vis}, [&] {
            glDeleteFramebuffers(kCount, fbo);
            glDeleteTextures(1, &arr);
        });
    }
};

}  // namespace

void add_warp_techniques(std::vector<std::unique_ptr<Technique>>& out) {
    out.push_back(std::make_unique<WarpedShadowMap>());
    out.push_back(std::make_unique<CascadedShadowMap>());
}

}  // namespace sk
