// Technique driver: smoothies (Chan & Durand 2003, "Rendering Fake Soft Shadows with Smoothies").
// Composes silhouette.hpp (edge adjacency once per scene, facing + silhouette per caster mesh per
// frame from the light's center), smoothie.hpp (edge quads, corners, valence > 2 vertices; per-edge
// scratch from the cache, no allocation per frame) and
// glsl/smoothie.glsl (three passes) the way a user would:
//   1. linear-depth shadow map (R32F colour + a depth buffer, GL_LESS, cleared to 1e30);
//   2. smoothie buffer (RG32F = (depth b, alpha), one pass with glBlendEquation(GL_MIN), smoothie
//      fragments behind a blocker discarded); by default (remap = 1) each smoothie fragment remaps
//      its own alpha with eq. 1 against the map's depth under it (the paper's variant), so GL_MIN
//      keeps the smallest REMAPPED alpha. With remap = 0 (remap in the final pass with the receiver's
//      depth) the two channels' minima can come from different smoothies: where a near smoothie
//      (small b) overlaps a far one at a contact (b ~ r, raw alpha ~ 0), the pair (near b, far alpha)
//      darkens a lit floor. remap = 1 needs the receivers in the map, so every mesh is drawn in pass 1.
//   3. the final lookup sk_smoothie_visibility (falloff, 2x2 filter) inside
//      visibility_fragment_shader's technique_visibility(p, n), with the receiver-plane depth
//      gradient of the G-buffer's plane (p, n) and a relative linear-depth bias.
// The light frustum is fit_light() (the plain shadow map's), smoothie width t in light NDC.
// The umbra is the hard shadow of the light's center and the smoothie penumbra lies wholly outside
// it (the area light's is centered on the hard edge): with the header's width mapping the shadows are
// too big by half a penumbra, which the report shows as a larger error than the hard map's.
//
// Params: t (light NDC; 0 = no smoothie geometry: the hard 2x2 test on the linear map) or t = -1:
// "t from the light": t = s w / b (smoothie.hpp smoothie_width_for_area_light) with s = P[0][0] of
// the light projection, w the emitter width (rect edge, disk / sphere diameter; 0 for spot and
// directional lights, which gives t = 0) and b = the median linear depth (distance from the light
// along its axis) of the silhouette-edge endpoints seen from the light's center: the typical depth
// of the edges that cast the penumbrae. size: shadow-map = smoothie-buffer resolution. remap: 1
// (default) eq. 1 in the smoothie pass, 0 in the final pass. Point lights are refused (one frustum).
#include <shadowkit/silhouette.hpp>
#include <shadowkit/smoothie.hpp>

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "driver_util.hpp"

namespace sk {

namespace {

constexpr float kLookupBiasRel = 1e-3f;  // umbra test: r > z + kLookupBiasRel * r (linear depth)
constexpr float kHiddenBiasRel = 2e-3f;  // smoothie pass: discard fragments with b > z + kHiddenBiasRel * b

// Emitter width in world units: rect edge, disk and sphere diameter (Light::size is the rect edge,
// the disk / sphere radius); 0 for lights without area.
float emitter_width(const Light& L) {
    if (!L.is_area()) return 0.f;
    return L.type == LightType::Rect ? L.size : 2.f * L.size;
}

// The light's center for the silhouette: a point (w = 1), or a direction towards the light (w = 0).
glm::vec4 silhouette_light(const Light& L) {
    if (L.type == LightType::Directional) return glm::vec4(-glm::normalize(L.direction), 0.f);
    return glm::vec4(L.position, 1.f);
}

struct CasterData {
    std::size_t mesh = 0;
    shadowkit::SilhouetteAdjacency adj;
    std::vector<std::uint8_t> facing;
    std::vector<std::uint32_t> sil;       // 2 per silhouette edge (capacity max_silhouette_edges)
    std::vector<shadowkit::SmoothieScratch> scratch;  // smoothie_build's per-edge scratch (capacity max_silhouette_edges)
};

struct SceneCache {
    bool valid = false;
    std::uint64_t key = 0;
    std::string error;
    std::vector<CasterData> casters;
    std::size_t vertex_capacity = 0;  // smoothie vertices, worst case over all facings
    bool has_median = false;
    float median_depth = 0.f;         // median silhouette-vertex linear depth (t_from_light's b)
};

struct FrameStats {
    std::size_t silhouette_edges = 0;
    std::size_t vertices = 0;
    std::size_t corners = 0, caps = 0, fans = 0, skipped = 0;
    bool truncated = false;
    std::string error;
};

// ---------------------------------------------------------------------------------------- GLSL
const char* kDepthVS = R"(
layout(location = 0) in vec3 a_position;
uniform mat4 u_light_view_proj;
out vec3 v_world;
void main() {
    v_world = a_position;
    gl_Position = u_light_view_proj * vec4(a_position, 1.0);
}
)";
const char* kDepthFS = R"(
in vec3 v_world;
uniform mat4 u_light_view;
layout(location = 0) out float o_depth;
void main() { o_depth = sk_smoothie_linear_depth(u_light_view, v_world); }
)";
const char* kSmoothieVS = R"(
layout(location = 0) in vec3 a_position;
layout(location = 1) in float a_alpha;
layout(location = 2) in vec3 a_silhouette;
layout(location = 3) in float a_inv_t;
layout(location = 5) in float a_corner;
uniform mat4 u_light_view_proj;
uniform mat4 u_light_view;
noperspective out float v_alpha;
smooth out float v_depth;
flat out vec2 v_silhouette_ndc;
flat out float v_inv_t;
flat out float v_corner;
void main() {
    vec4 clip;
    sk_smoothie_vertex(u_light_view_proj, u_light_view, a_position, a_silhouette, clip, v_depth, v_silhouette_ndc);
    gl_Position = clip;
    v_alpha = a_alpha;
    v_inv_t = a_inv_t;
    v_corner = a_corner;
}
)";
const char* kSmoothieFS = R"(
noperspective in float v_alpha;
smooth in float v_depth;
flat in vec2 v_silhouette_ndc;
flat in float v_inv_t;
flat in float v_corner;
layout(binding = 4) uniform sampler2D u_linear_shadow_map;
uniform vec2 u_buffer_size;
uniform float u_hidden_bias_rel;
uniform int u_remap_here;
layout(location = 0) out vec2 o_smoothie;
void main() {
    if (sk_smoothie_hidden(u_linear_shadow_map, gl_FragCoord.xy, v_depth, u_hidden_bias_rel * v_depth)) discard;
    vec2 o = sk_smoothie_fragment(gl_FragCoord.xy, u_buffer_size, v_alpha, v_silhouette_ndc, v_inv_t, v_corner, v_depth);
    // the paper's variant: each smoothie remaps its own alpha with r = the shadow-map depth under it,
    // so GL_MIN keeps the smallest REMAPPED alpha; overlapping smoothies at different depths stay right
    if (u_remap_here != 0) o.y = sk_smoothie_remap(o.y, v_depth, sk_smoothie_shadow_depth_at(u_linear_shadow_map, gl_FragCoord.xy));
    o_smoothie = o;
}
)";
// The final pass: the receiver's light uv and linear depth r, the receiver-plane gradient dr/duv
// of the G-buffer plane (p, n) (tangent steps: the G-buffer pass has no useful screen derivatives
// across objects), clamped so that one texel changes r by at most 25 %.
const char* kLookupBody = R"(
layout(binding = 2) uniform sampler2D u_sm_linear;
layout(binding = 3) uniform sampler2D u_smoothie_map;
uniform mat4 u_light_view_proj;
uniform mat4 u_light_view;
uniform float u_bias_rel;
uniform bool u_alpha_is_remapped;
vec3 skd_uvr(vec3 p) {
    vec4 c = u_light_view_proj * vec4(p, 1.0);
    return vec3(c.xy / c.w * 0.5 + 0.5, sk_smoothie_linear_depth(u_light_view, p));
}
vec2 skd_depth_gradient(vec3 p, vec3 n, vec3 uvr) {
    vec3 a = abs(n.y) < 0.9 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
    vec3 t1 = normalize(cross(n, a));
    vec3 t2 = cross(n, t1);
    float h = 1e-3 * max(uvr.z, 1e-6);
    vec3 d1 = skd_uvr(p + h * t1) - uvr;
    vec3 d2 = skd_uvr(p + h * t2) - uvr;
    float det = d1.x * d2.y - d1.y * d2.x;
    float scale = (abs(d1.x) + abs(d1.y)) * (abs(d2.x) + abs(d2.y));
    if (!(abs(det) > 1e-6 * scale)) return vec2(0.0);
    vec2 g = vec2(d2.y * d1.z - d1.y * d2.z, d1.x * d2.z - d2.x * d1.z) / det;
    float texel = 1.0 / float(textureSize(u_sm_linear, 0).x);
    float gmax = 0.25 * uvr.z / texel;
    float gl = length(g);
    return gl > gmax ? g * (gmax / gl) : g;
}
float technique_visibility(vec3 p, vec3 n) {
    vec4 c = u_light_view_proj * vec4(p, 1.0);
    if (!(c.w > 0.0)) return 1.0;
    vec3 uvr = skd_uvr(p);
    vec2 g = skd_depth_gradient(p, n, uvr);
    return sk_smoothie_visibility(u_sm_linear, u_smoothie_map, uvr.xy, uvr.z, g, u_bias_rel * uvr.z, u_alpha_is_remapped);
}
)";

class Smoothie final : public Technique {
public:
    std::string name() const override { return "smoothie"; }
    std::string description() const override {
        return "smoothies (Chan & Durand 2003): silhouette.hpp + smoothie.hpp + glsl/smoothie.glsl, linear-depth map, "
               "RG32F GL_MIN smoothie buffer; t in light NDC (t = -1: from the light's size at the median "
               "silhouette depth), size = map resolution";
    }
    bool hard() const override { return false; }
    std::vector<ParamSet> sweep(const Scene& scene, bool quick) const override {
        auto P = [](double t, int size) { return ParamSet{{{"t", t}, {"size", double(size)}}}; };
        const bool mesh = scene.name.rfind("mesh:", 0) == 0;
        // the report's light-size variants are named "<scene>@light=<k>"
        const std::string base = scene.name.substr(0, scene.name.find('@'));
        const bool variant = base.size() != scene.name.size() && scene.light.is_area();
        std::vector<ParamSet> out;
        if (scene.name == "stack") {
            // spot light (no area): the reference is hard; t = -1 maps to t = 0 (the hard limit) and
            // two small widths show the error that fake softness adds against a hard reference
            if (quick) return {P(0.02, 1024)};
            return {P(-1, 1024), P(0.02, 1024), P(0.05, 1024)};
        }
        if (scene.name != "contact" && scene.name != "overlap" && !mesh && !variant) return out;
        if (quick) return {P(0.05, 1024), P(-1, 1024)};
        for (int s : {256, 512, 1024, 2048})
            for (double t : {-1.0, 0.02, 0.05, 0.1, 0.2}) out.push_back(P(t, s));
        return out;  // the middle entry (the sample's default) is t = -1 at 1024
    }
    RunResult run(const RunContext& ctx, const ParamSet& params) override;

private:
    SceneCache cache_;
    bool prepare(const Scene& scene, const glm::mat4& light_view, const glm::mat4& light_vp);
    void build_frame(const Scene& scene, const glm::mat4& light_vp, float t, std::vector<shadowkit::SmoothieVertex>& vb,
                     FrameStats& st);
};

bool Smoothie::prepare(const Scene& scene, const glm::mat4& light_view, const glm::mat4& light_vp) {
    const std::uint64_t key = scene_hash(scene, 0, 0, 0x5700750ull);
    if (cache_.valid && cache_.key == key) return true;
    cache_ = SceneCache{};
    cache_.key = key;
    for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
        const Mesh& m = scene.meshes[i];
        if (!m.caster || m.indices.empty()) continue;
        CasterData c;
        c.mesh = i;
        if (!build_caster_adjacency(m, c.adj, cache_.error)) return false;
        const std::size_t fc = c.adj.face_count();
        c.facing.assign(fc, 0);
        const std::size_t max_sil = c.adj.max_silhouette_edges();
        c.sil.assign(2 * max_sil, 0);
        c.scratch.resize(shadowkit::smoothie_scratch_capacity(max_sil));
        cache_.vertex_capacity += shadowkit::smoothie_vertex_capacity(max_sil);
        cache_.casters.push_back(std::move(c));
    }
    // t_from_light's blocker depth: the median linear depth of the silhouette-edge endpoints
    const glm::vec4 L4 = silhouette_light(scene.light);
    std::vector<float> depths;
    for (CasterData& c : cache_.casters) {
        const Mesh& m = scene.meshes[c.mesh];
        shadowkit::silhouette_compute_facing(c.adj, m.positions.data(), m.positions.size(), L4, c.facing.data(), c.facing.size());
        const auto r = shadowkit::silhouette_extract(c.adj, c.facing.data(), c.facing.size(), c.sil.data(), c.sil.size(),
                                                     nullptr, 0);
        const std::size_t n = r.count / 2;
        for (std::size_t i = 0; i < 2 * n; ++i) {
            const glm::vec3 p = m.positions[c.sil[i]];
            const glm::vec4 cl = light_vp * glm::vec4(p, 1.f);
            if (!(cl.w > 0.f) || std::abs(cl.x) > cl.w || std::abs(cl.y) > cl.w) continue;  // outside the map
            depths.push_back(-(light_view * glm::vec4(p, 1.f)).z);
        }
    }
    if (!depths.empty()) {
        std::nth_element(depths.begin(), depths.begin() + static_cast<std::ptrdiff_t>(depths.size() / 2), depths.end());
        cache_.median_depth = depths[depths.size() / 2];
        cache_.has_median = cache_.median_depth > 0.f;
    }
    cache_.valid = true;
    return true;
}

// The per-frame CPU work: facing + silhouette per caster mesh, smoothie geometry appended to vb
// (sized to the worst case by prepare()); the outward side of each edge comes from its orientation
// (silhouette.hpp emits it as in the lit face), so no face normals are looked up.
void Smoothie::build_frame(const Scene& scene, const glm::mat4& light_vp, float t,
                           std::vector<shadowkit::SmoothieVertex>& vb, FrameStats& st) {
    st = FrameStats{};
    const glm::vec4 L4 = silhouette_light(scene.light);
    shadowkit::SmoothieParams sp;
    sp.t = t;
    for (CasterData& c : cache_.casters) {
        const Mesh& m = scene.meshes[c.mesh];
        const auto fr = shadowkit::silhouette_compute_facing(c.adj, m.positions.data(), m.positions.size(), L4, c.facing.data(),
                                                             c.facing.size());
        if (fr.status != shadowkit::Status::Ok) {
            st.error = std::string("silhouette_compute_facing status ") + shadowkit::status_name(fr.status);
            return;
        }
        const auto sr = shadowkit::silhouette_extract(c.adj, c.facing.data(), c.facing.size(), c.sil.data(), c.sil.size(),
                                                      nullptr, 0);
        const std::size_t n = sr.count / 2;
        st.silhouette_edges += n;
        shadowkit::SmoothieEdges in;
        in.positions = m.positions.data();
        in.position_count = m.positions.size();
        in.edges = c.sil.data();
        in.edge_count = n;
        // no face normals: the silhouette's edges run as in their lit face, which decides the side
        const auto r = shadowkit::smoothie_build(in, light_vp, sp, c.scratch.data(), c.scratch.size(), vb.data() + st.vertices,
                                                 vb.size() - st.vertices);
        if (r.status == shadowkit::Status::BufferTooSmall) st.truncated = true;
        else if (r.status != shadowkit::Status::Ok) {
            st.error = std::string("smoothie_build status ") + shadowkit::status_name(r.status);
            return;
        }
        st.vertices += r.count;
        st.corners += r.corners;
        st.caps += r.caps;
        st.fans += r.fans;
        st.skipped += r.skipped_invalid + r.skipped_behind + r.skipped_end_on + r.skipped_no_outward +
                      r.skipped_unprojectable;
    }
}

RunResult Smoothie::run(const RunContext& ctx, const ParamSet& params) {
    const Scene& scene = ctx.scene;
    const SceneGpu& gpu = ctx.gpu;
    const int size = static_cast<int>(params.get("size", 1024));
    const double t_param = params.get("t", -1.0);
    const bool remap_in_smoothie_pass = params.get("remap", 1) != 0.0;
    if (size < 1 || size > 16384) return RunResult::failure("size must be in [1, 16384]");
    if (!(t_param >= 0.0) && t_param != -1.0) return RunResult::failure("t must be >= 0, or -1 (from the light's size)");
    if (scene.light.type == LightType::Point)
        return RunResult::failure("point light: smoothies need one light frustum (omnidirectional not implemented)");

    const LightMatrices lm = fit_light(scene);
    const glm::mat4 light_vp = lm.proj * lm.view;
    if (!prepare(scene, lm.view, light_vp)) return RunResult::failure(cache_.error);

    // t: given, or mapped from the emitter's width (smoothie.hpp: t = s w / b)
    float t = static_cast<float>(t_param);
    float b_used = 0.f;
    if (t_param == -1.0) {
        t = 0.f;
        const float w = emitter_width(scene.light);
        if (w > 0.f) {
            if (!cache_.has_median) return RunResult::failure("t from the light: no silhouette inside the light frustum");
            b_used = cache_.median_depth;
            if (lm.perspective) {
                const shadowkit::SmoothieValue tv = shadowkit::smoothie_width_for_area_light(w, b_used, lm.proj[0][0]);
                if (tv.status != shadowkit::Status::Ok) return RunResult::failure("smoothie_width_for_area_light failed");
                t = tv.value;
            } else {
                // orthographic: agree at the median receiver depth only (smoothie.hpp): t = theta s r_ref
                t = 0.f;
            }
        }
    }

    RunResult r;
    std::string why;
    // ---- CPU: silhouette + smoothie build, median over the frames after warm-up
    std::vector<shadowkit::SmoothieVertex> vb(std::max<std::size_t>(cache_.vertex_capacity, 3));
    FrameStats st;
    std::vector<double> cpu;
    for (int it = 0; it < ctx.warmup + std::max(ctx.frames, 1); ++it) {
        const auto t0 = Clock::now();
        build_frame(scene, light_vp, t, vb, st);
        const double ms = ms_since(t0);
        if (!st.error.empty()) return RunResult::failure(st.error);
        if (it >= ctx.warmup) cpu.push_back(ms);
    }
    if (st.truncated) return RunResult::failure("smoothie vertex buffer too small (capacity bound violated)");
    r.cpu_ms = median_of(cpu);

    // ---- GL resources
    const std::string snippet = load_snippet("smoothie", why);
    if (snippet.empty()) return RunResult::failure(why);
    const std::string H = "#version 450 core\n" + snippet;
    std::string log;
    GLuint p_depth = skgl::compile_program({{GL_VERTEX_SHADER, H + kDepthVS}, {GL_FRAGMENT_SHADER, H + kDepthFS}}, log);
    if (!p_depth) return RunResult::failure(log);
    GLuint p_smoothie =
        skgl::compile_program({{GL_VERTEX_SHADER, H + kSmoothieVS}, {GL_FRAGMENT_SHADER, H + kSmoothieFS}}, log);
    if (!p_smoothie) {
        glDeleteProgram(p_depth);
        return RunResult::failure(log);
    }
    GLuint p_vis = compile_visibility_program(snippet, kLookupBody, log);
    if (!p_vis) {
        glDeleteProgram(p_depth);
        glDeleteProgram(p_smoothie);
        return RunResult::failure(log);
    }
    skgl::Target sm, sb;
    VisibilityPass pass;
    bool ok = skgl::make_target(sm, size, size, {GL_R32F}, GL_DEPTH_COMPONENT32F, why) &&
              skgl::make_target(sb, size, size, {GL_RG32F}, 0, why) && pass.init(gpu.width, gpu.height, why);
    GLuint vao = 0, vbo = 0;
    const GLsizeiptr vb_bytes = static_cast<GLsizeiptr>(vb.size() * sizeof(shadowkit::SmoothieVertex));
    if (ok) {
        glGenVertexArrays(1, &vao);
        glBindVertexArray(vao);
        glGenBuffers(1, &vbo);
        glBindBuffer(GL_ARRAY_BUFFER, vbo);
        glBufferData(GL_ARRAY_BUFFER, vb_bytes, nullptr, GL_STREAM_DRAW);
        const GLsizei stride = sizeof(shadowkit::SmoothieVertex);
        auto attr = [&](GLuint loc, GLint n, std::size_t offset) {
            glEnableVertexAttribArray(loc);
            glVertexAttribPointer(loc, n, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(offset));
        };
        attr(0, 3, offsetof(shadowkit::SmoothieVertex, position));
        attr(1, 1, offsetof(shadowkit::SmoothieVertex, alpha));
        attr(2, 3, offsetof(shadowkit::SmoothieVertex, silhouette_vertex));
        attr(3, 1, offsetof(shadowkit::SmoothieVertex, inv_t));
        attr(5, 1, offsetof(shadowkit::SmoothieVertex, corner));
        glBindVertexArray(0);
    }
    auto cleanup = [&] {
        if (vbo) glDeleteBuffers(1, &vbo);
        if (vao) glDeleteVertexArrays(1, &vao);
        skgl::destroy_target(sm);
        skgl::destroy_target(sb);
        glDeleteProgram(p_depth);
        glDeleteProgram(p_smoothie);
        glDeleteProgram(p_vis);
    };
    if (!ok) {
        cleanup();
        return RunResult::failure(why);
    }
    glUseProgram(p_depth);
    glUniformMatrix4fv(glGetUniformLocation(p_depth, "u_light_view_proj"), 1, GL_FALSE, glm::value_ptr(light_vp));
    glUniformMatrix4fv(glGetUniformLocation(p_depth, "u_light_view"), 1, GL_FALSE, glm::value_ptr(lm.view));
    glUseProgram(p_smoothie);
    glUniformMatrix4fv(glGetUniformLocation(p_smoothie, "u_light_view_proj"), 1, GL_FALSE, glm::value_ptr(light_vp));
    glUniformMatrix4fv(glGetUniformLocation(p_smoothie, "u_light_view"), 1, GL_FALSE, glm::value_ptr(lm.view));
    glUniform2f(glGetUniformLocation(p_smoothie, "u_buffer_size"), float(size), float(size));
    glUniform1f(glGetUniformLocation(p_smoothie, "u_hidden_bias_rel"), kHiddenBiasRel);
    glUniform1i(glGetUniformLocation(p_smoothie, "u_remap_here"), remap_in_smoothie_pass ? 1 : 0);
    glUseProgram(p_vis);
    set_light_uniforms(p_vis, scene.light);
    glUniformMatrix4fv(glGetUniformLocation(p_vis, "u_light_view_proj"), 1, GL_FALSE, glm::value_ptr(light_vp));
    glUniformMatrix4fv(glGetUniformLocation(p_vis, "u_light_view"), 1, GL_FALSE, glm::value_ptr(lm.view));
    glUniform1f(glGetUniformLocation(p_vis, "u_bias_rel"), kLookupBiasRel);
    glUniform1i(glGetUniformLocation(p_vis, "u_alpha_is_remapped"), remap_in_smoothie_pass ? 1 : 0);

    const GLsizei nverts = static_cast<GLsizei>(st.vertices);
    auto frame = [&] {
        // 1. linear-depth shadow map
        glBindFramebuffer(GL_FRAMEBUFFER, sm.fbo);
        glViewport(0, 0, size, size);
        glDisable(GL_BLEND);
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        glDepthMask(GL_TRUE);
        const float far_depth[4] = {1e30f, 0.f, 0.f, 0.f};
        glClearBufferfv(GL_COLOR, 0, far_depth);
        glClearDepth(1.0);
        glClear(GL_DEPTH_BUFFER_BIT);
        glUseProgram(p_depth);
        if (remap_in_smoothie_pass) {
            // the smoothie pass reads the receivers' depth from the map: receivers are drawn too
            for (const auto& m : gpu.meshes) skgl::draw_mesh(m);
        } else {
            draw_casters(gpu);
        }
        // 2. smoothie buffer: one pass, GL_MIN blending of (depth, alpha)
        glBindFramebuffer(GL_FRAMEBUFFER, sb.fbo);
        glViewport(0, 0, size, size);
        glDisable(GL_DEPTH_TEST);
        glDisable(GL_CULL_FACE);
        const float clear_smoothie[4] = {1e30f, 1.f, 0.f, 0.f};
        glClearBufferfv(GL_COLOR, 0, clear_smoothie);
        if (nverts > 0) {
            glBindBuffer(GL_ARRAY_BUFFER, vbo);
            glBufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(nverts) * GLsizeiptr(sizeof(shadowkit::SmoothieVertex)),
                            vb.data());
            glEnable(GL_BLEND);
            glBlendEquation(GL_MIN);
            glUseProgram(p_smoothie);
            glActiveTexture(GL_TEXTURE4);
            glBindTexture(GL_TEXTURE_2D, sm.color[0]);
            glBindVertexArray(vao);
            glDrawArrays(GL_TRIANGLES, 0, nverts);
            glBindVertexArray(0);
            glDisable(GL_BLEND);
            glBlendEquation(GL_FUNC_ADD);
        }
        // 3. final lookup over the G-buffer
        glActiveTexture(GL_TEXTURE2);
        glBindTexture(GL_TEXTURE_2D, sm.color[0]);
        glActiveTexture(GL_TEXTURE3);
        glBindTexture(GL_TEXTURE_2D, sb.color[0]);
        pass.draw(p_vis, gpu);
    };
    r.gpu_ms = skgl::median_frame_ms(frame, ctx.warmup, ctx.frames);
    r.frames = ctx.frames;
    r.visibility = skgl::read_color_float(pass.target, 0, 1);
    if (ctx.debug_images) {
        // the smoothie buffer (light space): alpha (0 on the silhouette, 1 at the smoothie's outer
        // edge, white where no smoothie), and its depth b
        const std::vector<float> buf = skgl::read_color_float(sb, 0, 2);
        r.debug.push_back(grey_debug_image("smoothie buffer alpha (light space)", size, size, buf, 2, 1, 1.f));
        r.debug.push_back(grey_debug_image("smoothie buffer depth b (light space)", size, size, buf, 2, 0, 1e29f));
    }
    r.gpu_bytes = std::int64_t(size) * size * (4 + 4 + 8) + std::int64_t(vb_bytes);
    const double smoothie_tris = double(st.vertices / 3);
    std::size_t map_triangles = gpu.caster_triangles;
    if (remap_in_smoothie_pass) {
        map_triangles = 0;
        for (const auto& m : scene.meshes) map_triangles += m.indices.size() / 3;
    }
    r.work = {{"t", double(t)},
              {"silhouette_edges", double(st.silhouette_edges)},
              {"smoothie_triangles", smoothie_tris},
              {"corners", double(st.corners + st.caps + st.fans)},
              {"shadow_map_texels", double(size) * size},
              {"triangles_drawn", double(map_triangles) + smoothie_tris}};
    if (t_param == -1.0 && b_used > 0.f) r.work.push_back({"b_median", double(b_used)});
    if (st.skipped) r.work.push_back({"edges_skipped", double(st.skipped)});
    const std::string err = skgl::gl_error_string();
    cleanup();
    if (!err.empty()) return RunResult::failure(err);
    return r;
}

}  // namespace

void add_smoothie_techniques(std::vector<std::unique_ptr<Technique>>& out) { out.push_back(std::make_unique<Smoothie>()); }

}  // namespace sk
