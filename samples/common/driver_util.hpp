// Internal helpers shared by the technique drivers of samples/common/drivers_*.cpp: the old interface
// (Technique::run), kept until each family is ported to samples/<technique>/ (docs/samples.md says
// how); then its driver file and the helpers only it used go.
#pragma once

#include <chrono>
#include <functional>
#include <initializer_list>
#include <memory>
#include <string>
#include <vector>

#include "gl.hpp"
#include "techniques.hpp"

namespace sk {

// CPU timing of the drivers' own CPU work.
using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0);
// Median of CPU time samples (the upper median for an even count; 0 for none).
double median_of(std::vector<double> v);
// Runs work() `runs` times and sets ms to the median of its CPU times; false at the first failing run.
bool median_cpu_ms(int runs, const std::function<bool()>& work, double& ms);

// Position-only depth pass (u_light_view_proj).
const char* depth_only_vs();
const char* depth_only_fs();

// Times `frame` (median over ctx.frames after ctx.warmup) and reads V back from pass into r.
void measure_visibility(RunResult& r, const RunContext& ctx, const VisibilityPass& pass,
                        const std::function<void()>& frame);
// Closes a run: takes the pending GL error, then deletes the programs and runs release (may be empty);
// r, or the GL error as a failure.
RunResult finish_run(RunResult r, std::initializer_list<GLuint> programs, const std::function<void()>& release = {});

// The depth-only program (depth_only_vs / depth_only_fs); 0 on failure, the message appended to log.
// (compile_visibility_program, VisibilityPass, set_light_uniforms: samples/app/gbuffer.hpp.)
GLuint compile_depth_only_program(std::string& log);
// Loads glsl/<snippet>.glsl (none for "") and compiles the depth-only program and the visibility program
// (snippet + body), then binds vis with L's light uniforms; false with the message in why.
bool compile_shadow_programs(const std::string& snippet, const std::string& body, const Light& L, GLuint& depth,
                             GLuint& vis, std::string& why);

// size x size GL_DEPTH_COMPONENT32F target with hardware depth compare (2x2 PCF): a plain shadow map.
bool make_shadow_map_target(skgl::Target& sm, int size, std::string& why);
// The shadow-map pass: clears fbo's depth and draws the casters (all, or only the listed mesh
// indices) with depth_prog (u_light_view_proj = light_vp), depth test GL_LESS, polygon offset (2, 2).
void render_shadow_depth(const SceneGpu& gpu, GLuint fbo, int size, GLuint depth_prog, const glm::mat4& light_vp,
                         const std::vector<std::uint32_t>* only = nullptr);

// How a single 2D shadow map is read: glsl/<snippet>.glsl and a visibility body sampling a
// sampler2DShadow at binding 2, with the light's view-projection in uniform `matrix_uniform`.
struct SingleMapLookup {
    const char* snippet;
    const char* body;
    const char* matrix_uniform;
};
// The single-map pipeline (warped_sm): each frame a size x size map from
// light_vp (render_shadow_depth, casters `only` or all), then the lookup's visibility pass. Fills r's
// gpu_ms, frames, visibility and gpu_bytes; extras (may be empty) runs before the map is freed.
RunResult run_single_shadow_map(const RunContext& ctx, RunResult r, int size, const glm::mat4& light_vp,
                                const SingleMapLookup& lookup, const std::vector<std::uint32_t>* only = nullptr,
                                const std::function<void(RunResult&, const skgl::Target&)>& extras = {});

// GL_DEPTH_COMPONENT32F texture (a 2D array of `layers`, or a cube map) with linear filtering,
// clamp-to-edge and depth compare GL_LEQUAL: a layered hardware-PCF shadow map.
GLuint make_depth_compare_texture(GLenum target, int size, int layers);
// Shadow-depth pass state: depth_prog bound, depth test GL_LESS, polygon offset (2, 2) enabled.
void begin_offset_depth_pass(GLuint depth_prog);
// Binds fbo with a size x size viewport and clears its depth.
void clear_depth_layer(GLuint fbo, int size);
// Depth-only passes into count layers (fbo[i] from vps[i], as begin_offset_depth_pass): the casters, or every mesh.
void render_depth_layers(const SceneGpu& gpu, const GLuint* fbo, const glm::mat4* vps, int count, int size,
                         GLuint depth_prog, bool every_mesh = false);

// Draws the caster meshes (all, or only the listed mesh indices).
void draw_casters(const SceneGpu& gpu, const std::vector<std::uint32_t>* only = nullptr);
void mesh_bounds(const Mesh& m, glm::vec3& lo, glm::vec3& hi);
// Box around a spot light's cone: the apex and the cap disk at the farthest corner of lo..hi, the half
// angle clamped to max_half_angle.
void spot_cone_box(const Light& L, const glm::vec3& lo, const glm::vec3& hi, float max_half_angle, glm::vec3& clo,
                   glm::vec3& chi);

}  // namespace sk
