// samples/shadow_volumes/shadow_volumes.cpp - robust stenciled shadow volumes, top to bottom:
//   init    once per scene: adjacency + face planes of every caster (silhouette.hpp), one vertex buffer
//           holding each caster vertex twice, (p, 1) and (p, 0) (volume_build_vertices: the second
//           copy is extruded to infinity by the vertex shader), the programs, the target
//   update  CPU, every frame, per caster: scissor rectangle and depth bounds (volume_scissor), facing
//           and silhouette for the light, z-pass or z-fail (volume_choose_stencil_method_box), side
//           quads (volume_build_side_quads) and for z-fail the caps (volume_build_caps, LitOnly)
//   render  GPU, every frame: 1 the scene's depth into our depth-stencil, 2 the volumes into the
//           stencil (two-sided: GL_INCR_WRAP / GL_DECR_WRAP), 3 V = (stencil == 0) at the G-buffer's points
// Area lights cast from their center; a point's count of volumes around it is the stencil value.
#include "shadow_volumes.hpp"

#include <shadowkit/infinite_projection.hpp>

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace {

// The volume program: the silhouette's quads and the caps; w = 0 vertices go to infinity, away from
// the light (sk_extrude_shadow_volume). With emulated depth bounds the fragment shader discards where
// the scene's depth (the G-buffer's depth texture at unit 2) lies outside the caster's bounds.
const char* kVolumeVS = R"(
layout(location = 0) in vec4 a_position;
uniform mat4 u_view_proj;
uniform vec4 u_light_position;
void main() { gl_Position = u_view_proj * sk_extrude_shadow_volume(a_position, u_light_position); }
)";
const char* kVolumeFS = "void main() {}\n";
const char* kVolumeBoundsFS = R"(
layout(binding = 2) uniform sampler2D u_scene_depth;
uniform vec2 u_bounds;
void main() {
    if (sk_outside_depth_bounds_at(u_scene_depth, ivec2(gl_FragCoord.xy), u_bounds)) discard;
}
)";
// The scene's depth drawn with the volumes' matrix (projection infinite / reversed).
const char* kDepthVS = R"(#version 450 core
layout(location = 0) in vec3 a_position;
uniform mat4 u_view_proj;
void main() { gl_Position = u_view_proj * vec4(a_position, 1.0); }
)";
const char* kDepthFS = "#version 450 core\nvoid main() {}\n";

bool failed(shadowkit::Status st, const char* what, std::string& error) {
    if (st == shadowkit::Status::Ok) return false;
    if (error.empty()) error = std::string(what) + ": " + shadowkit::status_name(st);
    return true;
}

}  // namespace

bool ShadowVolumes::init(const app::View& v, std::string& why) {
    release();
    const sk::Scene& scene = *v.scene;
    // adjacency and face planes of every caster (allocates; once per mesh)
    std::size_t vertices = 0, indices = 0;
    for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
        const sk::Mesh& m = scene.meshes[i];
        if (!m.caster || m.indices.empty()) continue;
        Caster c;
        c.mesh = i;
        c.adj = shadowkit::silhouette_build_adjacency(m.positions.data(), m.positions.size(), m.indices.data(),
                                                      m.indices.size());
        if (failed(c.adj.status, ("silhouette_build_adjacency of mesh '" + m.name + "'").c_str(), why)) return false;
        c.planes = shadowkit::silhouette_build_planes(c.adj, m.positions.data(), m.positions.size());
        if (failed(c.planes.status, "silhouette_build_planes", why)) return false;
        c.lo = glm::vec3(INFINITY);
        c.hi = glm::vec3(-INFINITY);
        for (const glm::vec3& p : m.positions) {
            c.lo = glm::min(c.lo, p);
            c.hi = glm::max(c.hi, p);
        }
        c.base_vertex = static_cast<GLint>(vertices);
        vertices += 2 * m.positions.size();
        c.facing.assign(c.adj.face_count(), 0);
        // an open caster may draw the two-sided volume: up to twice the silhouette edges
        c.sil.assign(c.adj.closed() ? shadowkit::silhouette_indices_capacity(c.adj)
                                    : shadowkit::silhouette_two_sided_indices_capacity(c.adj), 0);
        c.index_capacity = 3 * c.sil.size() + 6 * c.adj.face_count();  // sides + both caps
        c.index_offset = indices;
        indices += c.index_capacity;
        casters_.push_back(std::move(c));
    }
    indices_.assign(indices, 0);
    vertex_count_ = vertices;

    // every caster vertex twice, (p, 1) and (p, 0), in one static buffer; one dynamic index buffer
    std::vector<glm::vec4> verts(vertices);
    for (const Caster& c : casters_) {
        const sk::Mesh& m = scene.meshes[c.mesh];
        shadowkit::volume_build_vertices(m.positions.data(), m.positions.size(), verts.data() + c.base_vertex,
                                         2 * m.positions.size());
    }
    glGenVertexArrays(1, &vao_);
    glGenBuffers(1, &vbo_);
    glGenBuffers(1, &ibo_);
    glBindVertexArray(vao_);
    glBindBuffer(GL_ARRAY_BUFFER, vbo_);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(std::max<std::size_t>(verts.size(), 1) * sizeof(glm::vec4)),
                 verts.empty() ? nullptr : verts.data(), GL_STATIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, sizeof(glm::vec4), nullptr);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ibo_);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(std::max<std::size_t>(indices, 1) * 4), nullptr,
                 GL_DYNAMIC_DRAW);
    glBindVertexArray(0);

    // programs: the volumes (with and without the depth-bounds emulation), the scene depth, V
    const std::string snippet = app::load_snippet("shadow_volume", why);
    if (snippet.empty()) return false;
    const std::string head = "#version 450 core\n" + snippet + "\n";
    volume_prog_ = skgl::compile_program({{GL_VERTEX_SHADER, head + kVolumeVS}, {GL_FRAGMENT_SHADER, head + kVolumeFS}}, why);
    volume_bounds_prog_ =
        skgl::compile_program({{GL_VERTEX_SHADER, head + kVolumeVS}, {GL_FRAGMENT_SHADER, head + kVolumeBoundsFS}}, why);
    depth_prog_ = skgl::compile_program({{GL_VERTEX_SHADER, kDepthVS}, {GL_FRAGMENT_SHADER, kDepthFS}}, why);
    vis_prog_ = app::compile_visibility_program("", "float technique_visibility(vec3 p, vec3 n) { return 1.0; }", why);
    if (!volume_prog_ || !volume_bounds_prog_ || !depth_prog_ || !vis_prog_) return false;
    native_bounds_ = epoxy_has_gl_extension("GL_EXT_depth_bounds_test");
    // R32F V and a depth-stencil of the G-buffer's format (glBlitFramebuffer copies depth only between equal formats)
    return pass_.init(v.width, v.height, why, GL_DEPTH32F_STENCIL8);
}

void ShadowVolumes::update(const app::View& v, const ShadowVolumeSettings& s) {
    const sk::Scene& scene = *v.scene;
    const app::SceneGpu& gpu = *v.gpu;
    const sk::Light& L = v.light();
    // Volumes are rasterized at the G-buffer's pixels: its camera, not a fit camera, decides here.
    const sk::Camera& cam = gpu.camera;
    const float aspect = float(gpu.width) / float(gpu.height);
    const glm::mat4 cam_vp = gpu.proj * gpu.view;  // exactly the G-buffer's matrix (the same float product)
    gbuffer_depth_ = gpu.gbuffer.depth;
    // the homogeneous light: (p, 1) for point, spot and area lights (their center), (-direction, 0) at infinity
    light_ = L.homogeneous_position();
    if (!shadowkit::silhouette_valid_light(light_) && error_.empty()) error_ = "invalid light";

    // the volumes' matrix: the G-buffer's finite one (with depth clamp), or P_inf (infinite_projection.hpp)
    volume_vp_ = cam_vp;
    epsilon_ = 0.f;
    if (s.projection != ShadowVolumeSettings::Projection::Finite) {
        const bool reversed = s.projection == ShadowVolumeSettings::Projection::Reversed;
        shadowkit::ProjectionDepth dp;
        dp.near_z = cam.znear;
        dp.far_z = std::numeric_limits<float>::infinity();
        dp.clip_depth = reversed ? shadowkit::ClipDepth::ZeroToOne : shadowkit::ClipDepth::NegativeOneToOne;
        dp.reversed_z = reversed;
        const shadowkit::ProjectionEpsilonBound eb = shadowkit::projection_infinite_epsilon_bound(
            cam.fovy, aspect, dp.clip_depth, reversed, shadowkit::DepthFormat::Float32);
        if (failed(eb.status, "projection_infinite_epsilon_bound", error_)) return;
        dp.epsilon = epsilon_ = eb.epsilon;
        const shadowkit::ProjectionResult pr = shadowkit::projection_perspective(cam.fovy, aspect, dp);
        if (failed(pr.status, "projection_perspective", error_)) return;
        volume_vp_ = pr.matrix * gpu.view;
    }

    // What the scissor and the z-pass / z-fail choice need: the near plane's rectangle, the box of
    // everything that can receive this light's shadows (the scene; for a spot light cut to a box around
    // its cone: receivers outside the cone are unlit by the light rules anyway), the camera.
    const shadowkit::VolumeNearRect near_rect = shadowkit::volume_near_plane_rect(gpu.view, cam.fovy, aspect, cam.znear);
    glm::vec3 rlo = scene.bounds_min(), rhi = scene.bounds_max();
    const float diag = std::max(1e-6f, glm::length(rhi - rlo));
    if (L.type == sk::LightType::Spot && L.spot_half_angle < 1.5f) {
        float far_d = 0.f;
        for (int i = 0; i < 8; ++i)
            far_d = std::max(far_d, glm::length(glm::vec3(i & 1 ? rhi.x : rlo.x, i & 2 ? rhi.y : rlo.y, i & 4 ? rhi.z : rlo.z) -
                                                L.position));
        const glm::vec3 d = glm::normalize(L.direction), cap = L.position + d * far_d;
        const glm::vec3 ext = far_d * std::tan(L.spot_half_angle) * glm::sqrt(glm::max(glm::vec3(0.f), 1.f - d * d));
        const glm::vec3 clo = glm::max(rlo, glm::min(L.position, cap - ext)), chi = glm::min(rhi, glm::max(L.position, cap + ext));
        if (clo.x <= chi.x && clo.y <= chi.y && clo.z <= chi.z) {
            rlo = clo;
            rhi = chi;
        }
    }
    rlo -= glm::vec3(1e-4f * diag);
    rhi += glm::vec3(1e-4f * diag);
    receiver_lo_ = rlo;
    receiver_hi_ = rhi;
    shadowkit::ScissorParams sp;
    sp.view_proj = cam_vp;
    sp.viewport[2] = gpu.width;
    sp.viewport[3] = gpu.height;
    const bool culling = s.scissor || s.depth_bounds;

    for (Caster& c : casters_) {
        const sk::Mesh& m = scene.meshes[c.mesh];
        c.visible = true;
        c.zfail = true;
        // an open caster: every face an occluder (light entering through a hole and leaving through
        // back faces crosses no lit face), its unlit faces reversed (silhouette.hpp's two-sided rule)
        c.two_sided = !c.adj.closed() && s.open_meshes == ShadowVolumeSettings::OpenMeshes::TwoSided;
        c.sil_edges = c.side_count = c.cap_count = 0;
        c.sc = shadowkit::ScissorRect{};
        if (culling) {  // Lengyel: the rectangle and depth range the volume can touch; empty: skip it
            c.sc = shadowkit::volume_scissor(light_, c.lo, c.hi, rlo, rhi, sp);
            if (failed(c.sc.status, "volume_scissor", error_)) return;
            c.visible = c.sc.visible;
            if (!c.visible) continue;
        }
        // facing for the light and the silhouette (cached planes: the exact facing of a rigid mesh)
        const shadowkit::SilhouetteFacing fr =
            shadowkit::silhouette_compute_facing_planes(c.adj, c.planes, light_, c.facing.data(), c.facing.size());
        if (failed(fr.status, "silhouette_compute_facing_planes", error_)) return;
        const shadowkit::SilhouetteResult sr =
            c.two_sided ? shadowkit::silhouette_extract_two_sided(c.adj, c.facing.data(), c.facing.size(), c.sil.data(),
                                                                   c.sil.size(), nullptr, 0)
                        : shadowkit::silhouette_extract_planes(c.adj, c.planes, c.facing.data(), c.facing.size(),
                                                               c.sil.data(), c.sil.size(), nullptr, 0);
        if (failed(sr.status, "silhouette_extract", error_)) return;
        c.sil_edges = sr.count / 2;
        // z-pass only where the near plane cannot be inside this caster's volume
        if (s.method == ShadowVolumeSettings::Method::Auto) {
            const shadowkit::VolumeMethod mr =
                shadowkit::volume_choose_stencil_method_box(near_rect, light_, c.lo, c.hi, 1e-4f * diag);
            if (failed(mr.status, "volume_choose_stencil_method_box", error_)) return;
            c.zfail = mr.method == shadowkit::VolumeStencilMethod::ZFail;
        } else {
            c.zfail = s.method == ShadowVolumeSettings::Method::ZFail;
        }
        // the side quads, and for z-fail the light cap (lit faces) and the dark cap (extruded; a
        // directional light's dark cap is a single point: left out)
        std::uint32_t* out = indices_.data() + c.index_offset;
        const shadowkit::VolumeBuffer sq =
            shadowkit::volume_build_side_quads(c.sil.data(), 2 * c.sil_edges, m.positions.size(), out, c.index_capacity);
        if (failed(sq.status, "volume_build_side_quads", error_)) return;
        c.side_count = sq.count;
        if (c.zfail) {
            const shadowkit::VolumeBuffer cp = shadowkit::volume_build_caps(
                c.adj.faces.data(), c.adj.faces.size(), c.facing.data(), c.facing.size(), m.positions.size(),
                c.two_sided ? shadowkit::VolumeCapMode::TwoSided : shadowkit::VolumeCapMode::LitOnly, light_.w > 0.f,
                out + sq.count, c.index_capacity - sq.count);
            if (failed(cp.status, "volume_build_caps", error_)) return;
            c.cap_count = cp.count;
        }
    }
}

void ShadowVolumes::render_stencil(const app::View& v, const ShadowVolumeSettings& s) {
    const app::SceneGpu& gpu = *v.gpu;
    const int W = pass_.target.width, H = pass_.target.height;
    // this frame's indices: each visible caster's sides and caps
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ibo_);
    for (const Caster& c : casters_)
        if (c.visible && c.side_count + c.cap_count > 0)
            glBufferSubData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLintptr>(c.index_offset * sizeof(std::uint32_t)),
                            static_cast<GLsizeiptr>((c.side_count + c.cap_count) * sizeof(std::uint32_t)),
                            indices_.data() + c.index_offset);

    // 1. The scene's depth in our depth-stencil: the G-buffer's, copied (finite), or re-drawn with the
    //    volumes' P_inf (reversed: cleared to 0, GL_GREATER, zero-to-one clip depth).
    glDisable(GL_SCISSOR_TEST);
    if (s.projection == ShadowVolumeSettings::Projection::Finite) {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, gpu.gbuffer.fbo);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, pass_.target.fbo);
        glBlitFramebuffer(0, 0, W, H, 0, 0, W, H, GL_DEPTH_BUFFER_BIT, GL_NEAREST);
        glBindFramebuffer(GL_FRAMEBUFFER, pass_.target.fbo);
    } else {
        const bool reversed = s.projection == ShadowVolumeSettings::Projection::Reversed;
        glBindFramebuffer(GL_FRAMEBUFFER, pass_.target.fbo);
        glViewport(0, 0, W, H);
        glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
        glDepthMask(GL_TRUE);
        glClearDepth(reversed ? 0.0 : 1.0);
        glClear(GL_DEPTH_BUFFER_BIT);
        glClearDepth(1.0);
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(reversed ? GL_GREATER : GL_LESS);
        if (reversed) glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
        glDisable(GL_CULL_FACE);
        glUseProgram(depth_prog_);
        glUniformMatrix4fv(glGetUniformLocation(depth_prog_, "u_view_proj"), 1, GL_FALSE, glm::value_ptr(volume_vp_));
        for (const auto& m : gpu.meshes) skgl::draw_mesh(m);
        glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
        glDepthFunc(GL_LESS);
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    }
    glStencilMask(0xFF);
    glClearStencil(0);
    glClear(GL_STENCIL_BUFFER_BIT);

    // 2. The volumes into the stencil: no colour or depth writes, both faces, each caster z-pass or
    //    z-fail (the stencil ops in draw_volumes).
    begin_volume_state(s);
    glEnable(GL_STENCIL_TEST);
    glStencilFunc(GL_ALWAYS, 0, 0xFF);
    draw_volumes(s);
    end_volume_state();
}

void ShadowVolumes::render(const app::View& v, const ShadowVolumeSettings& s) {
    render_stencil(v, s);  // 1 and 2

    // 3. V = (stencil == 0) at the G-buffer's points, with the common light rules (pixels in a volume keep 0).
    glBindFramebuffer(GL_FRAMEBUFFER, pass_.target.fbo);
    const float zero[4] = {0.f, 0.f, 0.f, 0.f};
    glClearBufferfv(GL_COLOR, 0, zero);
    glEnable(GL_STENCIL_TEST);
    glStencilFunc(GL_EQUAL, 0, 0xFF);
    glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
    glUseProgram(vis_prog_);
    app::set_light_uniforms(vis_prog_, v.light());
    pass_.draw(vis_prog_, *v.gpu);
    glDisable(GL_STENCIL_TEST);
}

// The state of the volume pass: our framebuffer, no colour or depth writes, depth test against the
// scene's depth, both faces; the finite matrix clamps depth so the vertices at infinity (w = 0) are
// not clipped by the far plane and land behind every receiver (at 1).
void ShadowVolumes::begin_volume_state(const ShadowVolumeSettings& s) const {
    const bool reversed = s.projection == ShadowVolumeSettings::Projection::Reversed;
    glBindFramebuffer(GL_FRAMEBUFFER, pass_.target.fbo);
    glViewport(0, 0, pass_.target.width, pass_.target.height);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glDepthMask(GL_FALSE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(reversed ? GL_GREATER : GL_LESS);
    if (reversed) glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glDisable(GL_CULL_FACE);
    glDisable(GL_SCISSOR_TEST);
    if (s.projection == ShadowVolumeSettings::Projection::Finite) glEnable(GL_DEPTH_CLAMP);
}

void ShadowVolumes::end_volume_state() const {
    glDisable(GL_DEPTH_CLAMP);
    glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
    glDepthFunc(GL_LESS);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_TRUE);
    glDisable(GL_STENCIL_TEST);
}

// Every visible caster's volume. z-fail counts the volume's faces BEHIND the scene (back faces +1,
// front faces -1), z-pass those in front (front +1, back -1); both wrap. Scissor and depth bounds
// (native where the bound depth is the G-buffer's finite one, else emulated in the fragment shader
// against the G-buffer's depth) leave the count unchanged: they cut only fill no point can see.
void ShadowVolumes::draw_volumes(const ShadowVolumeSettings& s) const {
    const bool finite = s.projection == ShadowVolumeSettings::Projection::Finite;
    const bool native = s.depth_bounds && finite && native_bounds_, emulate = s.depth_bounds && !native;
    const GLuint prog = emulate ? volume_bounds_prog_ : volume_prog_;
    glUseProgram(prog);
    glUniformMatrix4fv(glGetUniformLocation(prog, "u_view_proj"), 1, GL_FALSE, glm::value_ptr(volume_vp_));
    glUniform4fv(glGetUniformLocation(prog, "u_light_position"), 1, glm::value_ptr(light_));
    const GLint bounds = glGetUniformLocation(prog, "u_bounds");
    if (emulate) {
        glActiveTexture(GL_TEXTURE2);
        glBindTexture(GL_TEXTURE_2D, gbuffer_depth_);
    }
    glBindVertexArray(vao_);
    for (const Caster& c : casters_) {
        if (!c.visible) continue;
        if (c.zfail) {
            glStencilOpSeparate(GL_BACK, GL_KEEP, GL_INCR_WRAP, GL_KEEP);
            glStencilOpSeparate(GL_FRONT, GL_KEEP, GL_DECR_WRAP, GL_KEEP);
        } else {
            glStencilOpSeparate(GL_FRONT, GL_KEEP, GL_KEEP, GL_INCR_WRAP);
            glStencilOpSeparate(GL_BACK, GL_KEEP, GL_KEEP, GL_DECR_WRAP);
        }
        set_scissor_and_depth_bounds(c.sc, s.scissor, native);
        if (emulate) glUniform2f(bounds, c.sc.depth_min, c.sc.depth_max);
        const auto at = [](std::size_t first) { return reinterpret_cast<const void*>(first * sizeof(std::uint32_t)); };
        if (c.side_count)
            glDrawElementsBaseVertex(GL_TRIANGLES, static_cast<GLsizei>(c.side_count), GL_UNSIGNED_INT, at(c.index_offset),
                                     c.base_vertex);
        if (c.cap_count) {
            // the light cap lies on the caster's own surface: a constant offset away from the eye makes
            // it fail the depth test there (it must count as behind the lit surface)
            glEnable(GL_POLYGON_OFFSET_FILL);
            glPolygonOffset(0.f, s.projection == ShadowVolumeSettings::Projection::Reversed ? -8.f : 8.f);
            glDrawElementsBaseVertex(GL_TRIANGLES, static_cast<GLsizei>(c.cap_count), GL_UNSIGNED_INT,
                                     at(c.index_offset + c.side_count), c.base_vertex);
            glDisable(GL_POLYGON_OFFSET_FILL);
        }
    }
    glDisable(GL_SCISSOR_TEST);
    if (native) glDisable(GL_DEPTH_BOUNDS_TEST_EXT);
    glBindVertexArray(0);
}

void ShadowVolumes::set_scissor_and_depth_bounds(const shadowkit::ScissorRect& sc, bool scissor, bool native_bounds) {
    if (scissor) {
        glEnable(GL_SCISSOR_TEST);
        glScissor(sc.x, sc.y, sc.width, sc.height);
    }
    if (native_bounds) {
        glEnable(GL_DEPTH_BOUNDS_TEST_EXT);
        glDepthBoundsEXT(sc.depth_min, sc.depth_max);
    }
}

app::DebugImage ShadowVolumes::debug_scissor() {
    const int W = pass_.target.width, H = pass_.target.height;
    std::string why;
    if (scissor_view_.width != W || scissor_view_.height != H) {
        skgl::destroy_target(scissor_view_);
        if (!skgl::make_target(scissor_view_, W, H, {GL_RGBA8}, 0, why)) return {};
    }
    // transparent, then each visible caster's rectangle outlined with four one-pixel scissored clears
    glBindFramebuffer(GL_FRAMEBUFFER, scissor_view_.fbo);
    const float clear[4] = {0.f, 0.f, 0.f, 0.f}, red[4] = {1.f, 0.f, 0.f, 1.f}, green[4] = {0.f, 0.8f, 0.f, 1.f};
    glClearBufferfv(GL_COLOR, 0, clear);
    glEnable(GL_SCISSOR_TEST);
    for (const Caster& c : casters_) {
        if (!c.visible || c.sc.status != shadowkit::Status::Ok || c.sc.width <= 0) continue;
        const int x = c.sc.x, y = c.sc.y, w = c.sc.width, h = c.sc.height;
        const int edges[4][4] = {{x, y, w, 1}, {x, y + h - 1, w, 1}, {x, y, 1, h}, {x + w - 1, y, 1, h}};
        for (const auto& e : edges) {
            glScissor(e[0], e[1], e[2], e[3]);
            glClearBufferfv(GL_COLOR, 0, c.zfail ? red : green);
        }
    }
    glDisable(GL_SCISSOR_TEST);
    return {scissor_view_.color[0], app::DebugImage::Show::Overlay};
}

void ShadowVolumes::release() {
    if (vao_) glDeleteVertexArrays(1, &vao_);
    if (vbo_) glDeleteBuffers(1, &vbo_);
    if (ibo_) glDeleteBuffers(1, &ibo_);
    for (GLuint p : {volume_prog_, volume_bounds_prog_, depth_prog_, vis_prog_})
        if (p) glDeleteProgram(p);
    vao_ = vbo_ = ibo_ = volume_prog_ = volume_bounds_prog_ = depth_prog_ = vis_prog_ = 0;
    skgl::destroy_target(scissor_view_);
    casters_.clear();
    indices_.clear();
    error_.clear();
}
