// Internal: the stencil shadow-volume machinery of the hard part of the penumbra_wedges driver
// (drivers_wedge.cpp, old interface), composed from silhouette.hpp, shadow_volume.hpp and
// glsl/shadow_volume.glsl. The shadow_volume technique itself is ported: samples/shadow_volumes/ (the
// class the sample shows and the report wraps); this file goes when the wedges are ported.
//
// CPU: the per-scene adjacency cache (VolumeCache), and per caster and frame the scissor rectangle and
// depth bounds, facing + silhouette, the z-pass / z-fail choice and the side quads + LitOnly caps.
// GPU: the volume program, the static extruded vertex buffer and the dynamic index buffer
// (VolumeGpu), the draw of every visible caster's volume with two-sided stencil, scissor and depth
// bounds (native or emulated), the stencil pass state, the G-buffer depth blit, and fragment counting
// with GL_SAMPLES_PASSED (+ fragment-shader invocations where the pipeline statistics exist).
#pragma once

#include <shadowkit/shadow_volume.hpp>
#include <shadowkit/silhouette.hpp>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "gl.hpp"
#include "report_technique.hpp"
#include "techniques.hpp"

namespace sk::volumes {

// Homogeneous light for silhouette.hpp / shadow_volume.hpp: w = 1 point (spot, and the centre of area
// lights), w = 0 the direction TOWARD a directional light.
glm::vec4 volume_light(const Light& L);

// Everything that can receive this light's shadows (the scissor polytope is clipped to it): the scene
// bounds, for a spot light intersected with a box around its cone (receivers outside the cone are
// unlit by the common light rules, whatever the stencil says), inflated a little for rounding.
void light_receiver_bounds(const Scene& s, glm::vec3& lo, glm::vec3& hi);

// Per caster mesh: adjacency (once per scene) and per-frame scratch buffers (allocated once).
struct CasterData {
    std::size_t mesh = 0;
    shadowkit::SilhouetteAdjacency adj;
    shadowkit::SilhouettePlanes planes;  // cached face planes (rigid meshes): the fast exact facing
    glm::vec3 lo{0.f}, hi{0.f};
    GLint base_vertex = 0;  // first vertex of this caster's 2n-vertex block in the shared buffer
    std::vector<std::uint8_t> facing;
    std::vector<std::uint32_t> sil;
    std::size_t index_capacity = 0;
    std::size_t index_offset = 0;  // into the shared index array
};

struct VolumeCache {
    std::uint64_t key = 0;
    bool valid = false;
    std::string error;
    std::vector<CasterData> casters;
    double adjacency_ms = 0.0;
    std::size_t total_vertices = 0, total_index_capacity = 0, total_sil_capacity = 0;
    std::size_t welded = 0, boundary = 0, nonmanifold = 0, degenerate = 0;

    // Adjacency of every caster mesh, built once per scene (cache key: scene_hash with the driver's
    // salt); false with `error` set when silhouette_build_adjacency fails.
    bool prepare(const Scene& scene, std::uint64_t salt);
};

// Per-frame output of the CPU stage for one caster.
struct CasterDraw {
    bool visible = true;
    bool zfail = true;
    std::size_t side_first = 0, side_count = 0;  // indices
    std::size_t cap_first = 0, cap_count = 0;
    std::size_t sil_edges = 0;
    shadowkit::ScissorRect sc;
};

// Per-run inputs of the CPU stage.
struct VolumeSetup {
    glm::vec4 light{0.f};
    bool point = true;  // light.w > 0
    shadowkit::VolumeNearRect near_rect;
    glm::vec3 rlo{0.f}, rhi{0.f};  // light_receiver_bounds
    float margin = 0.f;            // of volume_choose_stencil_method_box
    shadowkit::ScissorParams sp;   // view_proj = scissor_vp, viewport = the G-buffer's
};
VolumeSetup make_volume_setup(const Scene& scene, const SceneGpu& gpu, const glm::vec4& light, const glm::mat4& scissor_vp);

// volume_scissor of the caster's volume into d.sc, d.visible = d.sc.visible.
bool caster_scissor(const CasterData& c, const VolumeSetup& s, CasterDraw& d, std::string& error);
// Facing for the light (cached planes: silhouette_compute_facing_planes) and the silhouette into
// c.sil; d.sil_edges = the edge count.
bool caster_silhouette(CasterData& c, const Mesh& m, const VolumeSetup& s, CasterDraw& d, std::string& error);
// z-fail for method 0, z-pass for method 2, else volume_choose_stencil_method_box (d.zfail); then the side
// quads and, for z-fail, the LitOnly caps into indices[c.index_offset ...] (d.side_*, d.cap_*).
bool caster_volume(CasterData& c, const Mesh& m, const VolumeSetup& s, int method, std::uint32_t* indices, CasterDraw& d,
                   std::string& error);

// The volume program: "#version 450 core\n" + shadow_volume snippet + "\n" before each stage.
const char* volume_vs();
const char* volume_fs(bool emulate_bounds);

// GPU side of the hard volumes (owns its program, buffers and vertex array).
class VolumeGpu {
public:
    VolumeGpu() = default;
    VolumeGpu(const VolumeGpu&) = delete;
    VolumeGpu& operator=(const VolumeGpu&) = delete;
    ~VolumeGpu();

    // Compiles the volume program (0 on failure, the message appended to log).
    GLuint compile(const std::string& head, bool emulate_bounds, std::string& log);
    // Static vertex buffer of every caster's 2n-vertex block (p, 1), (p, 0) and the dynamic index
    // buffer (index_count indices); returns the vertex count.
    std::size_t create_buffers(const Scene& scene, const VolumeCache& cache, std::size_t index_count);
    void set_uniforms(const glm::mat4& view_proj, const glm::vec4& light);
    // Uploads each visible caster's used index range of this frame.
    void upload(const VolumeCache& cache, const std::vector<CasterDraw>& draws, const std::vector<std::uint32_t>& indices);
    // Draws every visible caster's volume; `stencil` false = no stencil ops (instrumented fill count);
    // `cull` = the scissor rectangle (use_scissor) and depth bounds (native or emulated) of the caster.
    void draw(const VolumeCache& cache, const std::vector<CasterDraw>& draws, GLuint gbuffer_depth, bool stencil,
              bool cull) const;

    bool use_scissor = false;
    bool native_bounds = false;   // GL_EXT_depth_bounds_test
    bool emulate_bounds = false;  // shadow_volume.glsl's emulation (G-buffer depth on unit 2)
    bool reversed_z = false;      // volumes drawn with a reversed-Z matrix (light-cap offset away from the eye)

private:
    GLuint prog_ = 0, vao_ = 0, vbo_ = 0, ibo_ = 0;
    GLint loc_bounds_ = -1;
};

// State of the volume draws into fbo: no colour or depth writes, depth test GL_LESS (reversed_z:
// GL_GREATER and glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE)), no face culling, GL_DEPTH_CLAMP when
// depth_clamp; end_volume_state restores the masks, GL_LESS and the GL clip depth, disables clamp and
// stencil.
void begin_volume_state(GLuint fbo, int w, int h, bool depth_clamp, bool reversed_z = false);
void end_volume_state();
// The stencil pass: begin_volume_state (reversed_z of gpu_volumes), stencil test GL_ALWAYS,
// VolumeGpu::draw with stencil, end.
void stencil_pass(const VolumeGpu& gpu_volumes, const VolumeCache& cache, const std::vector<CasterDraw>& draws,
                  GLuint fbo, int w, int h, bool depth_clamp, GLuint gbuffer_depth, bool cull);

// Blits the G-buffer's depth into fbo's depth (same format), scissor off; leaves fbo bound.
void blit_gbuffer_depth(const SceneGpu& gpu, GLuint fbo);
// Re-draws every mesh's depth into fbo (w x h) with depth_prog (its matrix already set): cleared to
// 1 with GL_LESS, or for reversed_z cleared to 0 with GL_GREATER and zero-to-one clip depth (restored
// afterwards). Scissor off, no colour writes; leaves fbo bound.
void draw_scene_depth(const SceneGpu& gpu, GLuint fbo, int w, int h, GLuint depth_prog, bool reversed_z);
// Stencil = 0 in the bound framebuffer (stencil mask 0xFF).
void clear_stencil();

// count_fragments: the report's instrument (samples/report/report_technique.hpp).
using sk::count_fragments;

}  // namespace sk::volumes
