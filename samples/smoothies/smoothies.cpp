// samples/smoothies/smoothies.cpp - smoothies, top to bottom:
//   init    per caster its adjacency (silhouette.hpp), the smoothie vertex buffer sized for the worst case
//           (smoothie_vertex_capacity), the three programs (glsl/smoothie.glsl), the V target
//   update  CPU, every frame: the light's frustum around the scene (sk::fit_light), per caster the facing
//           and silhouette seen from the light's center, t (given, or from the light's size at the median
//           depth of the silhouette vertices), the smoothies (smoothie_build: edge quads, corners, caps)
//   render  GPU, every frame: 1 the linear-depth shadow map (R32F, cleared to 1e30); 2 the smoothie buffer
//           (RG32F depth b and alpha, one pass with GL_MIN blending; fragments behind a blocker dropped);
//           3 V at the G-buffer's points (sk_smoothie_visibility: falloff, 2x2 filter, receiver-plane bias)
#include "smoothies.hpp"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace {

constexpr float kLookupBiasRel = 1e-3f;  // umbra test: r > z + kLookupBiasRel * r (linear depth)
constexpr float kHiddenBiasRel = 2e-3f;  // smoothie pass: drop fragments with b > z + kHiddenBiasRel * b

// 1. The linear-depth map: the light-view distance along the light's axis.
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
// 2. The smoothie buffer: per fragment (depth b, alpha), kept by GL_MIN.
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
// 3. The final pass: the receiver's light uv and linear depth r, the receiver-plane gradient dr/duv
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

// A debug view: one channel of the smoothie buffer as R32F (depth: +inf where no smoothie, left out of the view's range).
const char* kDebugFS = R"(#version 450 core
layout(binding = 0) uniform sampler2D u_buffer;
uniform int u_channel;
layout(location = 0) out float o_value;
void main() {
    vec2 ba = texelFetch(u_buffer, ivec2(gl_FragCoord.xy), 0).rg;
    o_value = u_channel == 1 ? ba.y : (ba.x < 1e29 ? ba.x : uintBitsToFloat(0x7f800000u));
}
)";

// Emitter width in world units: rect edge, disk and sphere diameter (Light::size: the rect's edge, the disk's
// or sphere's radius); 0 for lights without area.
float emitter_width(const sk::Light& L) {
    if (!L.is_area()) return 0.f;
    return L.type == sk::LightType::Rect ? L.size : 2.f * L.size;
}

}  // namespace

bool Smoothies::init(const app::View& v, std::string& why) {
    release();
    const sk::Scene& scene = *v.scene;
    if (v.light().type == sk::LightType::Point) {
        why = "point light: smoothies need one light frustum (omnidirectional not implemented)";
        return false;
    }
    // adjacency of every caster (once per mesh); the smoothie vertices of the worst facing
    std::size_t capacity = 0;
    for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
        const sk::Mesh& m = scene.meshes[i];
        if (!m.caster || m.indices.empty()) continue;
        Caster c;
        c.mesh = i;
        c.adj = shadowkit::silhouette_build_adjacency(m.positions.data(), m.positions.size(), m.indices.data(), m.indices.size());
        if (c.adj.status != shadowkit::Status::Ok) {
            why = "silhouette_build_adjacency of mesh '" + m.name + "': " + shadowkit::status_name(c.adj.status);
            return false;
        }
        const std::size_t max_sil = c.adj.max_silhouette_edges();
        c.facing.assign(c.adj.face_count(), 0);
        c.sil.assign(2 * max_sil, 0);
        c.scratch.resize(shadowkit::smoothie_scratch_capacity(max_sil));
        capacity += shadowkit::smoothie_vertex_capacity(max_sil);
        casters_.push_back(std::move(c));
    }
    vertices_.resize(std::max<std::size_t>(capacity, 3));

    // the smoothie vertex buffer (SmoothieVertex: position, alpha, silhouette vertex, 1 / t, corner)
    glGenVertexArrays(1, &vao_);
    glGenBuffers(1, &vbo_);
    glBindVertexArray(vao_);
    glBindBuffer(GL_ARRAY_BUFFER, vbo_);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices_.size() * sizeof(shadowkit::SmoothieVertex)), nullptr,
                 GL_STREAM_DRAW);
    const auto attribute = [](GLuint location, GLint n, std::size_t offset) {
        glEnableVertexAttribArray(location);
        glVertexAttribPointer(location, n, GL_FLOAT, GL_FALSE, sizeof(shadowkit::SmoothieVertex),
                              reinterpret_cast<const void*>(offset));
    };
    attribute(0, 3, offsetof(shadowkit::SmoothieVertex, position));
    attribute(1, 1, offsetof(shadowkit::SmoothieVertex, alpha));
    attribute(2, 3, offsetof(shadowkit::SmoothieVertex, silhouette_vertex));
    attribute(3, 1, offsetof(shadowkit::SmoothieVertex, inv_t));
    attribute(5, 1, offsetof(shadowkit::SmoothieVertex, corner));
    glBindVertexArray(0);

    // programs: the linear depth map, the smoothie buffer, V (and a debug view of the buffer)
    const std::string snippet = app::load_snippet("smoothie", why);
    if (snippet.empty()) return false;
    const std::string head = "#version 450 core\n" + snippet;
    depth_prog_ = skgl::compile_program({{GL_VERTEX_SHADER, head + kDepthVS}, {GL_FRAGMENT_SHADER, head + kDepthFS}}, why);
    smoothie_prog_ =
        skgl::compile_program({{GL_VERTEX_SHADER, head + kSmoothieVS}, {GL_FRAGMENT_SHADER, head + kSmoothieFS}}, why);
    vis_prog_ = app::compile_visibility_program(snippet, kLookupBody, why);
    debug_prog_ =
        skgl::compile_program({{GL_VERTEX_SHADER, app::fullscreen_vertex_shader()}, {GL_FRAGMENT_SHADER, kDebugFS}}, why);
    if (!depth_prog_ || !smoothie_prog_ || !vis_prog_ || !debug_prog_) return false;
    return pass_.init(v.width, v.height, why);
}

void Smoothies::update(const app::View& v, const SmoothieSettings& s) {
    const sk::Scene& scene = *v.scene;
    const sk::Light& L = v.light();
    // the light's frustum around the scene (the plain shadow map's)
    const sk::LightMatrices lm = sk::fit_light(scene);
    light_view_ = lm.view;
    light_vp_ = lm.proj * lm.view;
    // the light's center: a point (w = 1), or the direction toward a directional light (w = 0)
    const glm::vec4 light = L.homogeneous_position();

    // facing and silhouette of every caster; the light depths of its silhouette vertices inside the map
    depths_.clear();
    for (Caster& c : casters_) {
        const sk::Mesh& m = scene.meshes[c.mesh];
        const shadowkit::SilhouetteFacing fr = shadowkit::silhouette_compute_facing(
            c.adj, m.positions.data(), m.positions.size(), light, c.facing.data(), c.facing.size());
        const shadowkit::SilhouetteResult sr =
            shadowkit::silhouette_extract(c.adj, c.facing.data(), c.facing.size(), c.sil.data(), c.sil.size(), nullptr, 0);
        if (fr.status != shadowkit::Status::Ok || sr.status != shadowkit::Status::Ok) {
            const shadowkit::Status st = fr.status != shadowkit::Status::Ok ? fr.status : sr.status;
            error_ = std::string("silhouette: ") + shadowkit::status_name(st);
            return;
        }
        c.sil_edges = sr.count / 2;
        for (std::size_t i = 0; s.t_from_light && i < 2 * c.sil_edges; ++i) {
            const glm::vec3 p = m.positions[c.sil[i]];
            const glm::vec4 cl = light_vp_ * glm::vec4(p, 1.f);
            if (!(cl.w > 0.f) || std::abs(cl.x) > cl.w || std::abs(cl.y) > cl.w) continue;  // outside the map
            depths_.push_back(-(light_view_ * glm::vec4(p, 1.f)).z);
        }
    }

    // t: given, or t = s w / b with b the median depth (smoothie.hpp); 0 without an emitter width, and for an
    // orthographic map (a directional light: t would agree at one receiver depth only)
    t_ = s.t_from_light ? 0.f : s.t;
    b_median_ = 0.f;
    const float w = emitter_width(L);
    if (s.t_from_light && w > 0.f) {
        if (!depths_.empty()) {
            std::nth_element(depths_.begin(), depths_.begin() + static_cast<std::ptrdiff_t>(depths_.size() / 2), depths_.end());
            b_median_ = depths_[depths_.size() / 2];
        }
        if (!(b_median_ > 0.f)) {
            error_ = "t from the light: no silhouette inside the light frustum";
            return;
        }
        if (lm.perspective) {
            const shadowkit::SmoothieValue tv = shadowkit::smoothie_width_for_area_light(w, b_median_, lm.proj[0][0]);
            if (tv.status != shadowkit::Status::Ok) {
                error_ = std::string("smoothie_width_for_area_light: ") + shadowkit::status_name(tv.status);
                return;
            }
            t_ = tv.value;
        }
    }

    // the smoothies of every caster, one after the other; the outward side of an edge is its orientation
    // (silhouette.hpp emits it as in its lit face), so no face normals are looked up
    shadowkit::SmoothieParams sp;
    sp.t = t_;
    vertex_count_ = 0;
    for (Caster& c : casters_) {
        const sk::Mesh& m = scene.meshes[c.mesh];
        shadowkit::SmoothieEdges in;
        in.positions = m.positions.data();
        in.position_count = m.positions.size();
        in.edges = c.sil.data();
        in.edge_count = c.sil_edges;
        c.first = vertex_count_;
        c.built = shadowkit::smoothie_build(in, light_vp_, sp, c.scratch.data(), c.scratch.size(),
                                            vertices_.data() + vertex_count_, vertices_.size() - vertex_count_);
        if (c.built.status != shadowkit::Status::Ok) {
            error_ = std::string("smoothie_build: ") + shadowkit::status_name(c.built.status);
            return;
        }
        vertex_count_ += c.built.count;
    }
}

// The linear depth map (R32F and a depth buffer) and the smoothie buffer (RG32F), size x size each.
void Smoothies::make_targets(int size) {
    skgl::destroy_target(map_);
    skgl::destroy_target(buffer_);
    std::string why;
    if (!skgl::make_target(map_, size, size, {GL_R32F}, GL_DEPTH_COMPONENT32F, why) ||
        !skgl::make_target(buffer_, size, size, {GL_RG32F}, 0, why))
        error_ = why;
    size_ = size;
}

void Smoothies::render(const app::View& v, const SmoothieSettings& s) {
    if (s.size != size_) make_targets(s.size);
    const bool remap_here = s.remap == SmoothieSettings::Remap::SmoothiePass;

    // 1. The linear-depth shadow map: depth test GL_LESS, cleared to 1e30 (nothing) and the far plane. The
    //    smoothie pass remaps against the depth under each smoothie: then every mesh is drawn (receivers too).
    glBindFramebuffer(GL_FRAMEBUFFER, map_.fbo);
    glViewport(0, 0, size_, size_);
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    const float far_depth[4] = {1e30f, 0.f, 0.f, 0.f};
    glClearBufferfv(GL_COLOR, 0, far_depth);
    glClearDepth(1.0);
    glClear(GL_DEPTH_BUFFER_BIT);
    glUseProgram(depth_prog_);
    glUniformMatrix4fv(glGetUniformLocation(depth_prog_, "u_light_view_proj"), 1, GL_FALSE, glm::value_ptr(light_vp_));
    glUniformMatrix4fv(glGetUniformLocation(depth_prog_, "u_light_view"), 1, GL_FALSE, glm::value_ptr(light_view_));
    for (std::size_t i = 0; i < v.gpu->meshes.size(); ++i)
        if (remap_here || v.gpu->caster[i]) skgl::draw_mesh(v.gpu->meshes[i]);

    // 2. The smoothie buffer: no depth test, both faces, cleared to (1e30, 1); GL_MIN keeps the nearest depth
    //    and the smallest alpha (remapped here by default) per texel; the map at unit 4 drops hidden fragments.
    glBindFramebuffer(GL_FRAMEBUFFER, buffer_.fbo);
    glViewport(0, 0, size_, size_);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    const float no_smoothie[4] = {1e30f, 1.f, 0.f, 0.f};
    glClearBufferfv(GL_COLOR, 0, no_smoothie);
    if (vertex_count_ > 0) {
        const auto bytes = static_cast<GLsizeiptr>(vertex_count_ * sizeof(shadowkit::SmoothieVertex));
        glNamedBufferSubData(vbo_, 0, bytes, vertices_.data());
        glEnable(GL_BLEND);
        glBlendEquation(GL_MIN);
        glUseProgram(smoothie_prog_);
        glUniformMatrix4fv(glGetUniformLocation(smoothie_prog_, "u_light_view_proj"), 1, GL_FALSE, glm::value_ptr(light_vp_));
        glUniformMatrix4fv(glGetUniformLocation(smoothie_prog_, "u_light_view"), 1, GL_FALSE, glm::value_ptr(light_view_));
        glUniform2f(glGetUniformLocation(smoothie_prog_, "u_buffer_size"), float(size_), float(size_));
        glUniform1f(glGetUniformLocation(smoothie_prog_, "u_hidden_bias_rel"), kHiddenBiasRel);
        glUniform1i(glGetUniformLocation(smoothie_prog_, "u_remap_here"), remap_here ? 1 : 0);
        glBindTextureUnit(4, map_.color[0]);
        glBindVertexArray(vao_);
        glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(vertex_count_));
        glBindVertexArray(0);
        glDisable(GL_BLEND);
        glBlendEquation(GL_FUNC_ADD);
    }

    // 3. V at the G-buffer's points: the map (unit 2) and the smoothie buffer (unit 3), the common light rules.
    glUseProgram(vis_prog_);
    app::set_light_uniforms(vis_prog_, v.light());
    glUniformMatrix4fv(glGetUniformLocation(vis_prog_, "u_light_view_proj"), 1, GL_FALSE, glm::value_ptr(light_vp_));
    glUniformMatrix4fv(glGetUniformLocation(vis_prog_, "u_light_view"), 1, GL_FALSE, glm::value_ptr(light_view_));
    glUniform1f(glGetUniformLocation(vis_prog_, "u_bias_rel"), kLookupBiasRel);
    glUniform1i(glGetUniformLocation(vis_prog_, "u_alpha_is_remapped"), remap_here ? 1 : 0);
    glBindTextureUnit(2, map_.color[0]);
    glBindTextureUnit(3, buffer_.color[0]);
    pass_.draw(vis_prog_, *v.gpu);
}

app::DebugImage Smoothies::debug_channel(int channel) {
    if (!size_) return {};
    std::string why;
    if (debug_.width != size_) {
        skgl::destroy_target(debug_);
        if (!skgl::make_target(debug_, size_, size_, {GL_R32F}, 0, why)) return {};
    }
    glBindFramebuffer(GL_FRAMEBUFFER, debug_.fbo);
    glViewport(0, 0, size_, size_);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glUseProgram(debug_prog_);
    glUniform1i(glGetUniformLocation(debug_prog_, "u_channel"), channel);
    glBindTextureUnit(0, buffer_.color[0]);
    glBindVertexArray(pass_.vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    return {debug_.color[0], app::DebugImage::Show::Value};
}

void Smoothies::release() {  // (no GL call without objects: the App may have no context)
    if (vao_) glDeleteVertexArrays(1, &vao_);
    if (vbo_) glDeleteBuffers(1, &vbo_);
    for (GLuint p : {depth_prog_, smoothie_prog_, vis_prog_, debug_prog_})
        if (p) glDeleteProgram(p);
    vao_ = vbo_ = depth_prog_ = smoothie_prog_ = vis_prog_ = debug_prog_ = 0;
    skgl::destroy_target(map_);
    skgl::destroy_target(buffer_);
    skgl::destroy_target(debug_);
    size_ = 0;
    casters_.clear();
    vertices_.clear();
    vertex_count_ = 0;
    error_.clear();
}
