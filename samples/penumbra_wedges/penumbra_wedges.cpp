// samples/penumbra_wedges/penumbra_wedges.cpp - soft shadow volumes with penumbra wedges, top to bottom:
//   init    the volumes' init (adjacency and face planes of every caster, their vertex buffer), buffers for
//           one wedge per possible silhouette edge, the programs, a coverage target sharing the volumes'
//           depth-stencil
//   update  CPU, every frame: the volumes' stage (ShadowVolumes::update: the hard shadow of the light's
//           center); the spherical light; per silhouette edge of every caster a wedge (penumbra_wedge),
//           its hull reaching past every receiver (penumbra_wedge_hull), its scissor rectangle and depth
//           bounds (penumbra_wedge_scissor_in_box: the hull clipped to the receivers' box) and its faces
//   render  GPU, every frame: 1-2 the volumes' scene depth and stencil counts (ShadowVolumes::render_stencil);
//           3 the hulls into the R32F coverage sum (additive), each pixel inside a wedge adding its edge's
//           signed coverage of the light; 4 V = 1 - clamp(count + sum, 0, 1) at the G-buffer's points
#include "penumbra_wedges.hpp"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace {

// The wedge pass. A hull vertex carries its wedge's index; the fragment reads the receiver's world point
// from the G-buffer (the point the reference uses), drops it outside the wedge's four planes and adds the
// edge's signed coverage (outer half-wedge > 0, inner < 0). With emulated depth bounds it first drops the
// pixels whose scene depth (the G-buffer's, unit 2) lies outside the wedge's bounds.
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
flat in uint v_wedge;
layout(location = 0) out float o_coverage;
void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    SkWedge w = u_wedges[v_wedge];
    if (u_emulate_bounds != 0 && sk_outside_depth_bounds_at(u_scene_depth, px, w.bounds.xy)) discard;
    vec4 pk = texelFetch(u_gbuf_position, px, 0);
    if (pk.w < 0.5) discard;  // background
    vec4 p = vec4(pk.xyz, 1.0);
    if (!sk_wedge_inside4(p, w.outer_bound, w.inner_bound, w.side0, w.side1)) discard;
    o_coverage = sk_wedge_edge_coverage(w.e0.xyz, w.e1.xyz, vec4(u_sphere_light.xyz, 1.0), u_sphere_light.w, pk.xyz);
}
)";
// The last pass: the stencil's count of hard volumes (8 bits that wrap, read as signed) and the coverage sum.
const char* kCombine = R"(
layout(binding = 3) uniform sampler2D u_coverage;
layout(binding = 4) uniform usampler2D u_stencil;
// 1 when a caster's volume is two-sided (an open caster: its two layers count once, so the inner half-wedges
// still lighten its umbra; it also lets them lighten another layer's or caster's umbra there), else no cap
uniform float u_hard_max;
float technique_visibility(vec3 p, vec3 n) {
    ivec2 px = ivec2(gl_FragCoord.xy);
    uint s = texelFetch(u_stencil, px, 0).r & 255u;
    float hard = min(float(int(s) - (s >= 128u ? 256 : 0)), u_hard_max);
    return sk_wedge_visibility(hard, texelFetch(u_coverage, px, 0).r) * sk_emitter_horizon(p, n);
}
)";
const char* kWireFS = "out vec4 o_color;\nvoid main() { o_color = vec4(1.0, 0.55, 0.0, 1.0); }\n";

// The radius of the wedges' spherical light (PenumbraWedgeSettings::rect_radius).
float wedge_light_radius(const sk::Light& L, const PenumbraWedgeSettings& s) {
    float r = 0.f;
    if (L.type == sk::LightType::Sphere || L.type == sk::LightType::Disk) {
        r = L.size;
    } else if (L.type == sk::LightType::Rect && s.rect_radius == PenumbraWedgeSettings::RectLight::Bounding) {
        const glm::vec3 d = glm::normalize(L.direction);
        const glm::vec3 a = std::abs(d.y) < 0.9f ? glm::vec3(0.f, 1.f, 0.f) : glm::vec3(1.f, 0.f, 0.f);
        const glm::vec3 t = glm::normalize(glm::cross(a, d)), b = glm::cross(d, t);
        const glm::vec3 half_u = 0.5f * L.size * t, half_v = 0.5f * L.size * b;
        r = shadowkit::penumbra_rect_bounding_sphere(glm::vec4(L.position, 1.f), half_u, half_v).light.radius;
    } else if (L.type == sk::LightType::Rect) {
        r = L.size / std::sqrt(3.14159265358979f);
    }
    return std::max(0.f, r * s.light_scale);
}

}  // namespace

bool PenumbraWedges::init(const app::View& v, std::string& why) {
    release();
    if (!volumes_.init(v, why)) return false;
    // one wedge per silhouette edge at most; scratch for the silhouette of a caster the volumes cull
    for (const ShadowVolumes::Caster& c : volumes_.casters()) {
        capacity_ += c.sil.size() / 2;  // the volumes' silhouette capacity (twice as many edges if two-sided)
        facing_.resize(std::max(facing_.size(), c.adj.face_count()));
        sil_.resize(std::max(sil_.size(), c.sil.size()));
    }
    wedges_.reserve(capacity_);
    gpu_wedges_.reserve(7 * capacity_);
    hull_vertices_.reserve(6 * capacity_);
    hull_ids_.reserve(6 * capacity_);
    hull_local_.reserve(24 * capacity_);
    order_.reserve(capacity_);
    hull_indices_.reserve(24 * capacity_);

    // hull vertices (attribute 0) with their wedge's index (attribute 1), hull indices, the wedges' data
    const auto bytes = [&](std::size_t per_wedge) {
        return static_cast<GLsizeiptr>(std::max<std::size_t>(capacity_, 1) * per_wedge);
    };
    glGenVertexArrays(1, &vao_);
    glGenBuffers(1, &vbo_);
    glGenBuffers(1, &ids_);
    glGenBuffers(1, &ibo_);
    glGenBuffers(1, &ssbo_);
    glBindVertexArray(vao_);
    glBindBuffer(GL_ARRAY_BUFFER, vbo_);
    glBufferData(GL_ARRAY_BUFFER, bytes(6 * sizeof(glm::vec4)), nullptr, GL_DYNAMIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, sizeof(glm::vec4), nullptr);
    glBindBuffer(GL_ARRAY_BUFFER, ids_);
    glBufferData(GL_ARRAY_BUFFER, bytes(6 * sizeof(std::uint32_t)), nullptr, GL_DYNAMIC_DRAW);
    glEnableVertexAttribArray(1);
    glVertexAttribIPointer(1, 1, GL_UNSIGNED_INT, sizeof(std::uint32_t), nullptr);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ibo_);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, bytes(24 * sizeof(std::uint32_t)), nullptr, GL_DYNAMIC_DRAW);
    glBindVertexArray(0);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, ssbo_);
    glBufferData(GL_SHADER_STORAGE_BUFFER, bytes(7 * sizeof(glm::vec4)), nullptr, GL_DYNAMIC_DRAW);

    // programs: the wedges (after both snippets), the last pass (with the emitter's horizon), the wireframe
    const std::string sv = app::load_snippet("shadow_volume", why), pw = app::load_snippet("penumbra_wedge", why);
    if (sv.empty() || pw.empty()) return false;
    const std::string head = "#version 450 core\n" + sv + "\n" + pw + "\n";
    wedge_prog_ = skgl::compile_program({{GL_VERTEX_SHADER, head + kWedgeVS}, {GL_FRAGMENT_SHADER, head + kWedgeFS}}, why);
    combine_prog_ = app::compile_visibility_program(pw + app::emitter_horizon_glsl(), kCombine, why);
    wire_prog_ = skgl::compile_program({{GL_VERTEX_SHADER, head + kWedgeVS}, {GL_FRAGMENT_SHADER, head + kWireFS}}, why);
    if (!wedge_prog_ || !combine_prog_ || !wire_prog_) return false;

    // the coverage sum: R32F, depth-tested against the volumes' depth-stencil (their scene depth)
    if (!skgl::make_target(coverage_, v.width, v.height, {GL_R32F}, 0, why)) return false;
    glNamedFramebufferTexture(coverage_.fbo, GL_DEPTH_STENCIL_ATTACHMENT, volumes_.target().target.depth, 0);
    return pass_.init(v.width, v.height, why);
}

void PenumbraWedges::update(const app::View& v, const PenumbraWedgeSettings& s) {
    const sk::Scene& scene = *v.scene;
    // 1. The hard shadow of the light's center: the volumes' CPU stage, with our settings.
    using V = ShadowVolumeSettings;
    volume_settings_.method = s.method == PenumbraWedgeSettings::Method::ZFail ? V::Method::ZFail : V::Method::Auto;
    volume_settings_.scissor = s.scissor;
    volume_settings_.depth_bounds = s.depth_bounds;
    volume_settings_.projection =
        s.projection == PenumbraWedgeSettings::Projection::Finite ? V::Projection::Finite : V::Projection::Infinite;
    volume_settings_.open_meshes = s.open_meshes;
    volumes_.update(v, volume_settings_);
    if (!volumes_.error().empty()) {
        if (error_.empty()) error_ = volumes_.error();
        return;
    }
    // Wedges are rasterized at the G-buffer's pixels, like the volumes: its camera decides here.
    cam_vp_ = v.gpu->proj * v.gpu->view;
    cam_view_ = v.gpu->view;
    znear_ = v.gpu->camera.znear;

    // 2. The spherical light (0: the hard shadow alone), then one wedge per silhouette edge of every caster,
    //    also of a caster whose hard volume is culled: its penumbra reaches beyond that volume. The volumes
    //    found the silhouettes of the casters they draw; a culled caster's is found here, the same way.
    sphere_.light_position = glm::vec4(v.light().position, 1.f);
    sphere_.radius = wedge_light_radius(v.light(), s);
    wedges_.clear();
    gpu_wedges_.clear();
    hull_vertices_.clear();
    hull_ids_.clear();
    hull_local_.clear();
    skipped_ = silhouette_edges_ = 0;
    any_two_sided_ = false;
    for (const ShadowVolumes::Caster& c : volumes_.casters()) {
        if (!(sphere_.radius > 0.f)) break;  // no radius: no wedges
        const std::uint32_t* sil = c.sil.data();
        std::size_t edges = c.sil_edges;
        if (!c.visible) {
            const glm::vec4 light(v.light().position, 1.f);
            const shadowkit::SilhouetteFacing fr =
                shadowkit::silhouette_compute_facing_planes(c.adj, c.planes, light, facing_.data(), c.adj.face_count());
            const shadowkit::SilhouetteResult sr =  // the volumes' rule: two-sided on an open caster
                c.two_sided ? shadowkit::silhouette_extract_two_sided(c.adj, facing_.data(), c.adj.face_count(), sil_.data(),
                                                                       sil_.size(), nullptr, 0)
                            : shadowkit::silhouette_extract_planes(c.adj, c.planes, facing_.data(), c.adj.face_count(),
                                                                   sil_.data(), sil_.size(), nullptr, 0);
            if (fr.status != shadowkit::Status::Ok || sr.status != shadowkit::Status::Ok) {
                error_ = std::string("silhouette of a culled caster: ") +
                         shadowkit::status_name(fr.status != shadowkit::Status::Ok ? fr.status : sr.status);
                return;
            }
            sil = sil_.data();
            edges = sr.count / 2;
        }
        silhouette_edges_ += edges;
        any_two_sided_ = any_two_sided_ || c.two_sided;
        const sk::Mesh& m = scene.meshes[c.mesh];
        for (std::size_t e = 0; e < edges; ++e) {
            // two-sided: an edge between a lit and an unlit face comes twice (once per layer, in a row);
            // the light it hides is counted once
            if (c.two_sided && e > 0 && sil[2 * e] == sil[2 * e - 2] && sil[2 * e + 1] == sil[2 * e - 1]) continue;
            add_wedge(m.positions[sil[2 * e]], m.positions[sil[2 * e + 1]], s);
        }
    }

    // 3. The draw order: the wedges drawn with their front faces, then those with their back faces, then the
    //    culled ones (never drawn; the wireframe shows them); 24 hull indices each, in that order.
    order_.clear();
    const auto group = [&](bool visible, bool back) {
        for (std::size_t i = 0; i < wedges_.size(); ++i)
            if (wedges_[i].visible == visible && (!visible || wedges_[i].back == back))
                order_.push_back(static_cast<std::uint32_t>(i));
    };
    group(true, false);
    front_ = order_.size();
    group(true, true);
    back_ = order_.size() - front_;
    group(false, false);
    hull_indices_.clear();
    for (const std::uint32_t i : order_)
        for (std::size_t t = 0; t < 24; ++t) hull_indices_.push_back(6 * i + hull_local_[24 * i + t]);
}

// A wedge of edge e0 -> e1 (penumbra_wedge), its hull long enough to hold every wedge point in the box of the
// receivers (extent: the farthest box corner from the apex edge over the rays' smallest slope along the
// axis), its scissor rectangle and depth bounds (the hull clipped to that box; empty: not drawn) and its faces.
void PenumbraWedges::add_wedge(const glm::vec3& e0, const glm::vec3& e1, const PenumbraWedgeSettings& s) {
    const shadowkit::PenumbraWedge w = shadowkit::penumbra_wedge(e0, e1, sphere_);
    if (w.status != shadowkit::Status::Ok || w.skip != shadowkit::PenumbraWedgeSkip::None) {
        ++skipped_;  // degenerate, or the light's center on the edge's line
        return;
    }
    const glm::vec3 lo = volumes_.receiver_min(), hi = volumes_.receiver_max();
    float dmax = 0.f;
    for (int i = 0; i < 8; ++i) {
        const glm::vec3 q((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
        dmax = std::max({dmax, glm::length(q - w.apex[0]), glm::length(q - w.apex[1])});
    }
    float cmin = 1.f;
    for (int i = 0; i < 2; ++i) cmin = std::min({cmin, glm::dot(w.ray_outer[i], w.axis), glm::dot(w.ray_inner[i], w.axis)});
    const shadowkit::PenumbraWedgeHull h = shadowkit::penumbra_wedge_hull(w, dmax / std::max(cmin, 0.05f) * 1.01f);
    if (!h.drawable) {
        ++skipped_;
        return;
    }
    Wedge d;
    const bool culling = s.scissor || s.depth_bounds;
    if (culling) {
        shadowkit::ScissorParams sp;
        sp.view_proj = cam_vp_;
        sp.viewport[2] = pass_.target.width;
        sp.viewport[3] = pass_.target.height;
        d.sc = shadowkit::penumbra_wedge_scissor_in_box(h, lo, hi, sp);
        d.visible = d.sc.status == shadowkit::Status::Ok && d.sc.visible;
    }
    // back faces (GL_GEQUAL) where the hull reaches the near plane: the pixel ray of a receiver point inside
    // the hull leaves it behind the point through exactly one back face, which the near plane never clips
    float min_depth = std::numeric_limits<float>::infinity();
    for (const glm::vec4& hv : h.vertices) min_depth = std::min(min_depth, -(cam_view_ * hv).z);
    d.back = s.faces == PenumbraWedgeSettings::Faces::Back ||
             (s.faces == PenumbraWedgeSettings::Faces::Auto && !(min_depth > znear_ * 1.001f));
    const glm::vec4 bounds = culling && s.depth_bounds ? glm::vec4(d.sc.depth_min, d.sc.depth_max, 0.f, 0.f)
                                                       : glm::vec4(-1.f, 2.f, 0.f, 0.f);
    gpu_wedges_.insert(gpu_wedges_.end(), {w.outer_bound, w.inner_bound, w.side[0], w.side[1], glm::vec4(e0, 1.f),
                                           glm::vec4(e1, 1.f), bounds});
    const auto id = static_cast<std::uint32_t>(wedges_.size());
    for (int i = 0; i < 6; ++i) {
        hull_vertices_.push_back(h.vertices[i]);
        hull_ids_.push_back(id);
    }
    hull_local_.insert(hull_local_.end(), h.indices, h.indices + 24);
    wedges_.push_back(d);
}

void PenumbraWedges::render(const app::View& v, const PenumbraWedgeSettings& s) {
    // 1-2. The volumes' passes: the scene's depth, and each point's count of hard volumes in the stencil.
    volumes_.render_stencil(v, volume_settings_);

    // this frame's wedges: hull vertices and their wedge's index, the hull indices, the wedges' planes and edges
    const std::size_t n = wedges_.size();
    if (n) {
        glNamedBufferSubData(vbo_, 0, static_cast<GLsizeiptr>(6 * n * sizeof(glm::vec4)), hull_vertices_.data());
        glNamedBufferSubData(ids_, 0, static_cast<GLsizeiptr>(6 * n * sizeof(std::uint32_t)), hull_ids_.data());
        glNamedBufferSubData(ibo_, 0, static_cast<GLsizeiptr>(24 * n * sizeof(std::uint32_t)), hull_indices_.data());
        glNamedBufferSubData(ssbo_, 0, static_cast<GLsizeiptr>(7 * n * sizeof(glm::vec4)), gpu_wedges_.data());
    }

    // 3. The wedges: their hulls into the coverage sum, cleared to 0, adding (state in begin_wedge_pass and
    //    draw_hulls).
    const float zero[4] = {0.f, 0.f, 0.f, 0.f};
    glClearNamedFramebufferfv(coverage_.fbo, GL_COLOR, 0, zero);
    begin_wedge_pass(v, s);
    draw_hulls(s);
    end_wedge_pass();

    // 4. V at the G-buffer's points (the common light rules): the stencil count read through stencil texturing
    //    of the volumes' depth-stencil, the coverage sum, and the emitter's part above the tangent plane.
    const sk::Light& L = v.light();
    const GLuint depth_stencil = volumes_.target().target.depth;
    glUseProgram(combine_prog_);
    app::set_light_uniforms(combine_prog_, L);
    app::set_emitter_uniforms(combine_prog_, L, s.horizon && sphere_.radius > 0.f && L.is_area());
    glUniform1f(glGetUniformLocation(combine_prog_, "u_hard_max"), any_two_sided_ ? 1.f : 1e9f);
    glTextureParameteri(depth_stencil, GL_DEPTH_STENCIL_TEXTURE_MODE, GL_STENCIL_INDEX);
    glBindTextureUnit(3, coverage_.color[0]);
    glBindTextureUnit(4, depth_stencil);
    pass_.draw(combine_prog_, *v.gpu);
    glBindTextureUnit(3, 0);
    glBindTextureUnit(4, 0);
    glTextureParameteri(depth_stencil, GL_DEPTH_STENCIL_TEXTURE_MODE, GL_DEPTH_COMPONENT);
}

// The state of the wedge pass: the coverage target (its depth the volumes' scene depth), no stencil, additive
// blending; the wedge program with this frame's matrix (the volumes'), light and wedges, the G-buffer's
// positions (unit 0) and depth (unit 2, for emulated depth bounds).
void PenumbraWedges::begin_wedge_pass(const app::View& v, const PenumbraWedgeSettings& s) const {
    glBindFramebuffer(GL_FRAMEBUFFER, coverage_.fbo);
    glViewport(0, 0, coverage_.width, coverage_.height);
    glDisable(GL_STENCIL_TEST);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glEnable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);
    glBlendFunc(GL_ONE, GL_ONE);
    glUseProgram(wedge_prog_);
    glUniformMatrix4fv(glGetUniformLocation(wedge_prog_, "u_view_proj"), 1, GL_FALSE,
                       glm::value_ptr(volumes_.volume_view_proj()));
    glUniform4f(glGetUniformLocation(wedge_prog_, "u_sphere_light"), sphere_.light_position.x, sphere_.light_position.y,
                sphere_.light_position.z, sphere_.radius);
    glUniform1i(glGetUniformLocation(wedge_prog_, "u_emulate_bounds"), s.depth_bounds && !native_depth_bounds(s) ? 1 : 0);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, ssbo_);
    glBindTextureUnit(0, v.gpu->gbuffer.color[0]);
    glBindTextureUnit(2, v.gpu->gbuffer.depth);
}

// The hulls, depth-tested against the scene without writing depth: the front-face group with GL_LEQUAL (hull
// parts behind the receivers drop out), the back-face group with GL_GEQUAL; GL_DEPTH_CLAMP with the finite
// matrix (the far plane would cut long hulls). With a scissor or native depth bounds, one draw per wedge.
void PenumbraWedges::draw_hulls(const PenumbraWedgeSettings& s) const {
    if (front_ + back_ == 0) return;
    const bool native = native_depth_bounds(s), per_wedge = s.scissor || native;
    glBindVertexArray(vao_);
    glEnable(GL_DEPTH_TEST);
    glDepthMask(GL_FALSE);
    glEnable(GL_CULL_FACE);
    glFrontFace(GL_CCW);
    if (s.projection == PenumbraWedgeSettings::Projection::Finite) glEnable(GL_DEPTH_CLAMP);
    const auto at = [](std::size_t wedge) { return reinterpret_cast<const void*>(24 * wedge * sizeof(std::uint32_t)); };
    std::size_t first = 0;
    for (const bool back : {false, true}) {
        const std::size_t count = back ? back_ : front_;
        glCullFace(back ? GL_FRONT : GL_BACK);
        glDepthFunc(back ? GL_GEQUAL : GL_LEQUAL);
        if (!per_wedge && count) glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(24 * count), GL_UNSIGNED_INT, at(first));
        for (std::size_t j = first; per_wedge && j < first + count; ++j) {
            ShadowVolumes::set_scissor_and_depth_bounds(wedges_[order_[j]].sc, s.scissor, native);
            glDrawElements(GL_TRIANGLES, 24, GL_UNSIGNED_INT, at(j));
        }
        first += count;
    }
    glDisable(GL_SCISSOR_TEST);
    if (native) glDisable(GL_DEPTH_BOUNDS_TEST_EXT);
    glDisable(GL_CULL_FACE);
    glDisable(GL_DEPTH_CLAMP);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glBindVertexArray(0);
}

void PenumbraWedges::end_wedge_pass() const {
    glDisable(GL_BLEND);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, 0);
}

app::DebugImage PenumbraWedges::debug_hulls() {
    const int W = pass_.target.width, H = pass_.target.height;
    std::string why;
    if (wire_view_.width != W || wire_view_.height != H) {
        skgl::destroy_target(wire_view_);
        if (!skgl::make_target(wire_view_, W, H, {GL_RGBA8}, 0, why)) return {};
    }
    // transparent, then every hull's triangles as lines in the G-buffer's camera (clipped by its near plane)
    const float clear[4] = {0.f, 0.f, 0.f, 0.f};
    glBindFramebuffer(GL_FRAMEBUFFER, wire_view_.fbo);
    glViewport(0, 0, W, H);
    glClearBufferfv(GL_COLOR, 0, clear);
    if (!wedges_.empty()) {
        glUseProgram(wire_prog_);
        glUniformMatrix4fv(glGetUniformLocation(wire_prog_, "u_view_proj"), 1, GL_FALSE, glm::value_ptr(cam_vp_));
        glDisable(GL_DEPTH_TEST);
        glEnable(GL_DEPTH_CLAMP);
        glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
        glBindVertexArray(vao_);
        glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(hull_indices_.size()), GL_UNSIGNED_INT, nullptr);
        glBindVertexArray(0);
        glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
        glDisable(GL_DEPTH_CLAMP);
    }
    return {wire_view_.color[0], app::DebugImage::Show::Overlay};
}

void PenumbraWedges::release() {  // (no GL call without objects: the App may have no context)
    if (vao_) glDeleteVertexArrays(1, &vao_);
    for (GLuint* b : {&vbo_, &ids_, &ibo_, &ssbo_})
        if (*b) glDeleteBuffers(1, b);
    for (GLuint p : {wedge_prog_, combine_prog_, wire_prog_})
        if (p) glDeleteProgram(p);
    vao_ = vbo_ = ids_ = ibo_ = ssbo_ = wedge_prog_ = combine_prog_ = wire_prog_ = 0;
    skgl::destroy_target(coverage_);
    skgl::destroy_target(wire_view_);
    capacity_ = 0;
    facing_.clear();
    sil_.clear();
    wedges_.clear();
    error_.clear();
}
