// Internal: stencil shadow volumes of drivers_wedge.cpp (see the header).
#include "stencil_volumes.hpp"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>

#include "driver_util.hpp"

namespace sk::volumes {

glm::vec4 volume_light(const Light& L) {
    if (L.type == LightType::Directional) return glm::vec4(-glm::normalize(L.direction), 0.f);
    return glm::vec4(L.position, 1.f);
}

void light_receiver_bounds(const Scene& s, glm::vec3& lo, glm::vec3& hi) {
    lo = s.bounds_min();
    hi = s.bounds_max();
    const float pad = 1e-4f * std::max(1e-6f, glm::length(hi - lo));
    const Light& L = s.light;
    if (L.type == LightType::Spot && L.spot_half_angle < 1.5f) {
        glm::vec3 clo, chi;
        spot_cone_box(L, lo, hi, 1.5f, clo, chi);
        const glm::vec3 nlo = glm::max(lo, clo), nhi = glm::min(hi, chi);
        if (nlo.x <= nhi.x && nlo.y <= nhi.y && nlo.z <= nhi.z) {
            lo = nlo;
            hi = nhi;
        }
    }
    lo -= glm::vec3(pad);
    hi += glm::vec3(pad);
}

bool VolumeCache::prepare(const Scene& scene, std::uint64_t salt) {
    const std::uint64_t k = scene_hash(scene, 0, 0, salt);
    if (valid && key == k) return true;
    *this = VolumeCache{};
    key = k;
    const auto t0 = Clock::now();
    for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
        const Mesh& m = scene.meshes[i];
        if (!m.caster || m.indices.empty()) continue;
        CasterData c;
        c.mesh = i;
        if (!build_caster_adjacency(m, c.adj, error)) return false;
        c.planes = shadowkit::silhouette_build_planes(c.adj, m.positions.data(), m.positions.size());
        if (c.planes.status != shadowkit::Status::Ok) {
            error = std::string("silhouette_build_planes status ") + shadowkit::status_name(c.planes.status);
            return false;
        }
        welded += c.adj.welded_vertices;
        boundary += c.adj.boundary_edges;
        nonmanifold += c.adj.nonmanifold_edges.size();
        degenerate += c.adj.degenerate_triangles;
        casters.push_back(std::move(c));
    }
    adjacency_ms = ms_since(t0);
    for (CasterData& c : casters) {
        const Mesh& m = scene.meshes[c.mesh];
        mesh_bounds(m, c.lo, c.hi);
        c.base_vertex = static_cast<GLint>(total_vertices);
        total_vertices += 2 * m.positions.size();
        c.facing.assign(c.adj.face_count(), 0);
        const std::size_t max_sil = c.adj.max_silhouette_edges();
        c.sil.assign(2 * max_sil, 0);
        total_sil_capacity += max_sil;
        c.index_capacity = 6 * max_sil + 6 * c.adj.face_count();
        c.index_offset = total_index_capacity;
        total_index_capacity += c.index_capacity;
    }
    valid = true;
    return true;
}

VolumeSetup make_volume_setup(const Scene& scene, const SceneGpu& gpu, const glm::vec4& light, const glm::mat4& scissor_vp) {
    VolumeSetup s;
    s.light = light;
    s.point = light.w > 0.f;
    const float aspect = float(gpu.width) / float(gpu.height);
    s.near_rect = shadowkit::volume_near_plane_rect(gpu.view, scene.camera.fovy, aspect, scene.camera.znear);
    light_receiver_bounds(scene, s.rlo, s.rhi);
    s.margin = 1e-4f * std::max(1e-6f, glm::length(scene.bounds_max() - scene.bounds_min()));
    s.sp.view_proj = scissor_vp;
    s.sp.clip_depth = shadowkit::ClipDepth::NegativeOneToOne;
    s.sp.reversed_z = false;
    s.sp.viewport[0] = 0;
    s.sp.viewport[1] = 0;
    s.sp.viewport[2] = gpu.width;
    s.sp.viewport[3] = gpu.height;
    return s;
}

bool caster_scissor(const CasterData& c, const VolumeSetup& s, CasterDraw& d, std::string& error) {
    d.sc = shadowkit::volume_scissor(s.light, c.lo, c.hi, s.rlo, s.rhi, s.sp);
    if (d.sc.status != shadowkit::Status::Ok) {
        error = std::string("volume_scissor status ") + shadowkit::status_name(d.sc.status);
        return false;
    }
    d.visible = d.sc.visible;
    return true;
}

bool caster_silhouette(CasterData& c, const Mesh& m, const VolumeSetup& s, CasterDraw& d, std::string& error) {
    (void)m;  // rigid: the planes were cached from m.positions in VolumeCache::prepare
    const shadowkit::SilhouetteFacing fr =
        shadowkit::silhouette_compute_facing_planes(c.adj, c.planes, s.light, c.facing.data(), c.facing.size());
    if (fr.status != shadowkit::Status::Ok) {
        error = std::string("silhouette_compute_facing_planes status ") + shadowkit::status_name(fr.status);
        return false;
    }
    const shadowkit::SilhouetteResult sr =
        shadowkit::silhouette_extract_planes(c.adj, c.planes, c.facing.data(), c.facing.size(), c.sil.data(), c.sil.size(), nullptr, 0);
    if (sr.status != shadowkit::Status::Ok) {
        error = std::string("silhouette_extract_planes status ") + shadowkit::status_name(sr.status);
        return false;
    }
    d.sil_edges = sr.count / 2;
    return true;
}

bool caster_volume(CasterData& c, const Mesh& m, const VolumeSetup& s, int method, std::uint32_t* indices, CasterDraw& d,
                   std::string& error) {
    if (method == 0) d.zfail = true;
    else if (method == 2) d.zfail = false;
    else {
        const shadowkit::VolumeMethod mr = shadowkit::volume_choose_stencil_method_box(s.near_rect, s.light, c.lo, c.hi, s.margin);
        if (mr.status != shadowkit::Status::Ok) {
            error = std::string("volume_choose_stencil_method_box status ") + shadowkit::status_name(mr.status);
            return false;
        }
        d.zfail = mr.method == shadowkit::VolumeStencilMethod::ZFail;
    }
    std::uint32_t* out = indices + c.index_offset;
    const shadowkit::VolumeBuffer sq =
        shadowkit::volume_build_side_quads(c.sil.data(), 2 * d.sil_edges, m.positions.size(), out, c.index_capacity);
    if (sq.status != shadowkit::Status::Ok) {
        error = std::string("volume_build_side_quads status ") + shadowkit::status_name(sq.status);
        return false;
    }
    d.side_first = c.index_offset;
    d.side_count = sq.count;
    if (d.zfail) {
        const shadowkit::VolumeBuffer cp = shadowkit::volume_build_caps(
            c.adj.faces.data(), c.adj.faces.size(), c.facing.data(), c.facing.size(), m.positions.size(),
            shadowkit::VolumeCapMode::LitOnly, s.point /* a directional light's dark cap has zero area */, out + sq.count,
            c.index_capacity - sq.count);
        if (cp.status != shadowkit::Status::Ok) {
            error = std::string("volume_build_caps status ") + shadowkit::status_name(cp.status);
            return false;
        }
        d.cap_first = c.index_offset + sq.count;
        d.cap_count = cp.count;
    }
    return true;
}

const char* volume_vs() {
    return R"(
layout(location = 0) in vec4 a_position;
uniform mat4 u_view_proj;
uniform vec4 u_light_position;
void main() { gl_Position = u_view_proj * sk_extrude_shadow_volume(a_position, u_light_position); }
)";
}

const char* volume_fs(bool emulate_bounds) {
    if (!emulate_bounds) return R"(
void main() {}
)";
    return R"(
layout(binding = 2) uniform sampler2D u_scene_depth;
uniform vec2 u_bounds;
void main() {
    if (sk_outside_depth_bounds_at(u_scene_depth, ivec2(gl_FragCoord.xy), u_bounds)) discard;
}
)";
}

VolumeGpu::~VolumeGpu() {
    if (vbo_) glDeleteBuffers(1, &vbo_);
    if (ibo_) glDeleteBuffers(1, &ibo_);
    if (vao_) glDeleteVertexArrays(1, &vao_);
    if (prog_) glDeleteProgram(prog_);
}

GLuint VolumeGpu::compile(const std::string& head, bool emulate, std::string& log) {
    prog_ = skgl::compile_program({{GL_VERTEX_SHADER, head + volume_vs()}, {GL_FRAGMENT_SHADER, head + volume_fs(emulate)}},
                                  log);
    return prog_;
}

std::size_t VolumeGpu::create_buffers(const Scene& scene, const VolumeCache& cache, std::size_t index_count) {
    std::vector<glm::vec4> verts(cache.total_vertices);
    for (const CasterData& c : cache.casters) {
        const Mesh& m = scene.meshes[c.mesh];
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
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(std::max<std::size_t>(index_count, 1) * 4), nullptr,
                 GL_DYNAMIC_DRAW);
    glBindVertexArray(0);
    return verts.size();
}

void VolumeGpu::set_uniforms(const glm::mat4& view_proj, const glm::vec4& light) {
    glUseProgram(prog_);
    glUniformMatrix4fv(glGetUniformLocation(prog_, "u_view_proj"), 1, GL_FALSE, glm::value_ptr(view_proj));
    glUniform4fv(glGetUniformLocation(prog_, "u_light_position"), 1, glm::value_ptr(light));
    loc_bounds_ = glGetUniformLocation(prog_, "u_bounds");
}

void VolumeGpu::upload(const VolumeCache& cache, const std::vector<CasterDraw>& draws, const std::vector<std::uint32_t>& indices) {
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ibo_);
    for (std::size_t ci = 0; ci < draws.size(); ++ci) {
        const std::size_t first = cache.casters[ci].index_offset, n = draws[ci].side_count + draws[ci].cap_count;
        if (draws[ci].visible && n)
            glBufferSubData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLintptr>(first * sizeof(std::uint32_t)),
                            static_cast<GLsizeiptr>(n * sizeof(std::uint32_t)), indices.data() + first);
    }
}

void VolumeGpu::draw(const VolumeCache& cache, const std::vector<CasterDraw>& draws, GLuint gbuffer_depth, bool stencil,
                     bool cull) const {
    glUseProgram(prog_);
    glBindVertexArray(vao_);
    if (emulate_bounds) {
        glActiveTexture(GL_TEXTURE2);
        glBindTexture(GL_TEXTURE_2D, gbuffer_depth);
    }
    for (std::size_t ci = 0; ci < draws.size(); ++ci) {
        const CasterDraw& d = draws[ci];
        if (!d.visible) continue;
        if (stencil) {
            if (d.zfail) {
                glStencilOpSeparate(GL_BACK, GL_KEEP, GL_INCR_WRAP, GL_KEEP);
                glStencilOpSeparate(GL_FRONT, GL_KEEP, GL_DECR_WRAP, GL_KEEP);
            } else {
                glStencilOpSeparate(GL_FRONT, GL_KEEP, GL_KEEP, GL_INCR_WRAP);
                glStencilOpSeparate(GL_BACK, GL_KEEP, GL_KEEP, GL_DECR_WRAP);
            }
        }
        if (cull && use_scissor) {
            glEnable(GL_SCISSOR_TEST);
            glScissor(d.sc.x, d.sc.y, d.sc.width, d.sc.height);
        } else {
            glDisable(GL_SCISSOR_TEST);
        }
        if (cull && native_bounds) {
            glEnable(GL_DEPTH_BOUNDS_TEST_EXT);
            glDepthBoundsEXT(d.sc.depth_min, d.sc.depth_max);
        } else if (native_bounds) {
            glDisable(GL_DEPTH_BOUNDS_TEST_EXT);
        }
        if (emulate_bounds) glUniform2f(loc_bounds_, cull ? d.sc.depth_min : -1.f, cull ? d.sc.depth_max : 2.f);
        const GLint base = cache.casters[ci].base_vertex;
        if (d.side_count)
            glDrawElementsBaseVertex(GL_TRIANGLES, static_cast<GLsizei>(d.side_count), GL_UNSIGNED_INT,
                                     reinterpret_cast<const void*>(d.side_first * sizeof(std::uint32_t)), base);
        if (d.cap_count) {
            // the light cap coincides with the caster's own surface: a constant offset makes it fail
            // the depth test there robustly (it must count as "behind" the lit surface)
            glEnable(GL_POLYGON_OFFSET_FILL);
            glPolygonOffset(0.f, reversed_z ? -8.f : 8.f);  // away from the eye in either depth direction
            glDrawElementsBaseVertex(GL_TRIANGLES, static_cast<GLsizei>(d.cap_count), GL_UNSIGNED_INT,
                                     reinterpret_cast<const void*>(d.cap_first * sizeof(std::uint32_t)), base);
            glDisable(GL_POLYGON_OFFSET_FILL);
        }
    }
    glDisable(GL_SCISSOR_TEST);
    if (native_bounds) glDisable(GL_DEPTH_BOUNDS_TEST_EXT);
    glBindVertexArray(0);
}

void begin_volume_state(GLuint fbo, int w, int h, bool depth_clamp, bool reversed_z) {
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, w, h);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glDepthMask(GL_FALSE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(reversed_z ? GL_GREATER : GL_LESS);
    if (reversed_z) glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glDisable(GL_CULL_FACE);
    if (depth_clamp) glEnable(GL_DEPTH_CLAMP);
}

void end_volume_state() {
    glDisable(GL_DEPTH_CLAMP);
    glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
    glDepthFunc(GL_LESS);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_TRUE);
    glDisable(GL_STENCIL_TEST);
}

void stencil_pass(const VolumeGpu& gpu_volumes, const VolumeCache& cache, const std::vector<CasterDraw>& draws,
                  GLuint fbo, int w, int h, bool depth_clamp, GLuint gbuffer_depth, bool cull) {
    begin_volume_state(fbo, w, h, depth_clamp, gpu_volumes.reversed_z);
    glEnable(GL_STENCIL_TEST);
    glStencilFunc(GL_ALWAYS, 0, 0xFF);
    gpu_volumes.draw(cache, draws, gbuffer_depth, true, cull);
    end_volume_state();
}

void blit_gbuffer_depth(const SceneGpu& gpu, GLuint fbo) {
    glDisable(GL_SCISSOR_TEST);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, gpu.gbuffer.fbo);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo);
    glBlitFramebuffer(0, 0, gpu.width, gpu.height, 0, 0, gpu.width, gpu.height, GL_DEPTH_BUFFER_BIT, GL_NEAREST);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
}

void draw_scene_depth(const SceneGpu& gpu, GLuint fbo, int w, int h, GLuint depth_prog, bool reversed_z) {
    glDisable(GL_SCISSOR_TEST);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, w, h);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glDepthMask(GL_TRUE);
    glClearDepth(reversed_z ? 0.0 : 1.0);
    glClear(GL_DEPTH_BUFFER_BIT);
    glClearDepth(1.0);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(reversed_z ? GL_GREATER : GL_LESS);
    if (reversed_z) glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glDisable(GL_CULL_FACE);
    glUseProgram(depth_prog);
    for (const auto& m : gpu.meshes) skgl::draw_mesh(m);
    if (reversed_z) glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
    glDepthFunc(GL_LESS);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
}

void clear_stencil() {
    glStencilMask(0xFF);
    glClearStencil(0);
    glClear(GL_STENCIL_BUFFER_BIT);
}

}  // namespace sk::volumes
