// samples/app/gbuffer.hpp - what every technique reads and how its last pass writes V.
//
// Part of the app shell (samples/app, library shadowkit_app): a technique uses these, never changes them.
//
// - SceneGpu: the scene's meshes on the GPU and the camera G-buffer (world position + kind, normal,
//   depth-stencil), rendered with the camera of the frame. A technique evaluates its visibility V at
//   the G-buffer's surface points: the same points the report's ray-traced reference uses.
// - View: what a technique's init / update / render get each frame: the scene (meshes, light), its
//   SceneGpu, and the camera the technique fits to (`view`, `proj`). That camera is the G-buffer's in
//   the samples; the report may move it away from the G-buffer's (the report's temporal rows): a
//   technique fits to view.view / view.proj and evaluates at the G-buffer's points, never re-derives
//   one from the other.
// - The last pass of every technique: a full-screen triangle over the G-buffer whose fragment shader is
//   the technique's snippet(s) plus `float technique_visibility(vec3 p, vec3 n)`, wrapped by
//   visibility_fragment_shader() in the common light rules (facing, spot cone, one-sided emitters),
//   writing V into an R32F target (VisibilityPass).
// - Composite: albedo * (ambient + V N.L) on the GPU from the G-buffer and V (what the samples show).
#pragma once

#include <glm/glm.hpp>

#include <cstddef>
#include <string>
#include <vector>

#include "gl.hpp"
#include "scene.hpp"

namespace app {

/// The scene's meshes on the GPU and the camera G-buffer.
struct SceneGpu {
    std::vector<skgl::GpuMesh> meshes;  ///< same order as Scene::meshes
    std::vector<bool> caster;           ///< Mesh::caster of each
    std::size_t caster_triangles = 0;
    int width = 0, height = 0;          ///< the G-buffer's size
    sk::Camera camera;                  ///< the camera the G-buffer was rendered with
    glm::mat4 view{1.f}, proj{1.f};     ///< its matrices (proj for the aspect width / height)
    /// colour 0: RGBA32F world position + kind (0 background, 1 receiver, 2 other geometry),
    /// colour 1: RGBA32F normal (geometric, facing the camera); DEPTH32F_STENCIL8 (depth of `proj * view`)
    skgl::Target gbuffer;
    GLuint gbuffer_program = 0;
    SceneGpu() = default;
    SceneGpu(const SceneGpu&) = delete;
    SceneGpu& operator=(const SceneGpu&) = delete;
    ~SceneGpu();
};

/// Uploads the scene's meshes (replacing earlier ones; the G-buffer stays until render_gbuffer).
void upload_scene(const sk::Scene& scene, SceneGpu& gpu);
/// Renders the G-buffer of `camera` at width x height (re-creating the target when the size changes).
bool render_gbuffer(const sk::Scene& scene, const sk::Camera& camera, int width, int height, SceneGpu& gpu,
                    std::string& why);

/// What a technique sees each frame.
struct View {
    const sk::Scene* scene = nullptr;  ///< meshes (CPU) and the light
    const SceneGpu* gpu = nullptr;     ///< meshes (GPU) and the G-buffer, with the camera it was rendered with
    sk::Camera camera;                 ///< the camera a technique fits to (shadow-map fitting, warping, cascades)
    glm::mat4 view{1.f}, proj{1.f};    ///< camera.view(), camera.projection(width / height)
    int width = 0, height = 0;         ///< the G-buffer's size: V has one value per G-buffer pixel
    const sk::Light& light() const { return scene->light; }
};
/// The View of the G-buffer's own camera.
View make_view(const sk::Scene& scene, const SceneGpu& gpu);
/// A View whose fit camera differs from the G-buffer's (the report's temporal rows).
View make_view(const sk::Scene& scene, const SceneGpu& gpu, const sk::Camera& fit_camera);

/// glsl/<name>.glsl of the source tree ("" and `why` when unreadable): the snippets a user pastes,
/// read at run time.
std::string load_snippet(const std::string& name, std::string& why);
/// One full-screen triangle from gl_VertexID (draw 3 vertices with an empty vertex array).
std::string fullscreen_vertex_shader();
/// The V pass's fragment shader: `snippets`, then `body` (which defines
/// `float technique_visibility(vec3 p, vec3 n)`), then a main() that reads the G-buffer (sampler2D
/// unit 0: position + kind, unit 1: normal), applies the common light rules (set_light_uniforms) and
/// writes clamp(V, 0, 1) to location 0 (0 on background pixels).
std::string visibility_fragment_shader(const std::string& snippets, const std::string& body);
/// fullscreen_vertex_shader() + `fragment_shader`; 0 on failure, `why` then replaced by the log.
GLuint compile_fullscreen_program(const std::string& fragment_shader, std::string& why);
/// A full-screen pass into the bound framebuffer's viewport (the composite, the debug views): turns
/// the depth, stencil and scissor tests off and returns the viewport's width and height.
glm::ivec2 begin_fullscreen_pass();
/// fullscreen_vertex_shader() + visibility_fragment_shader(snippets, body); 0 with the log on failure.
GLuint compile_visibility_program(const std::string& snippets, const std::string& body, std::string& log);
/// The light uniforms of the common light rules (u_light_type, position, direction, cone) on `prog`.
void set_light_uniforms(GLuint prog, const sk::Light& L);
/// Area lights seen through one shadow map (PCF, PCSS, pre-filtered maps): the emitter's fraction above a
/// receiver's tangent plane, by which such a technique multiplies its V (the reference counts light samples
/// below that plane as unseen; a map from the light's center cannot). GLSL declaring u_emitter* and
/// `float sk_emitter_horizon(vec3 p, vec3 n)`: rect (16 columns of the square, each clipped exactly),
/// disk (the circular segment), sphere (the disk of its radius facing p); u_emitter = 0: 1.
const char* emitter_horizon_glsl();
/// Its uniforms on `prog` for L (a rect, disk or sphere light); `enabled` false sets u_emitter = 0 (V unchanged).
void set_emitter_uniforms(GLuint prog, const sk::Light& L, bool enabled);
/// Duff et al. 2017 orthonormal basis (t, b) of the plane with unit normal n: the reference's basis of an emitter.
void emitter_basis(glm::vec3 n, glm::vec3& t, glm::vec3& b);

/// The last pass of every technique: V into an R32F target, one full-screen triangle over the G-buffer.
struct VisibilityPass {
    skgl::Target target;  ///< colour 0: R32F V; plus the depth(-stencil) format given to init (0: none)
    GLuint vao = 0;       ///< empty vertex array for the full-screen triangle
    VisibilityPass() = default;
    VisibilityPass(const VisibilityPass&) = delete;
    VisibilityPass& operator=(const VisibilityPass&) = delete;
    ~VisibilityPass();
    bool init(int w, int h, std::string& why, GLenum depth_format = 0);
    /// Binds target (viewport, depth test off) and the G-buffer (units 0, 1), then draws with `prog`.
    void draw(GLuint prog, const SceneGpu& gpu);
    /// draw() with `map` (a texture of map_target) bound at unit 2, where the lookups read their shadow map.
    void draw(GLuint prog, const SceneGpu& gpu, GLenum map_target, GLuint map);
    GLuint texture() const { return target.color.empty() ? 0u : target.color[0]; }
};

/// albedo * (ambient + V N.L), gamma 2.2, from the G-buffer and a V texture (R32F) into the bound
/// framebuffer's viewport: what the samples show.
class Composite {
public:
    Composite() = default;
    Composite(const Composite&) = delete;
    Composite& operator=(const Composite&) = delete;
    ~Composite();
    bool init(std::string& why);
    void draw(const SceneGpu& gpu, const sk::Light& light, GLuint visibility);

private:
    GLuint prog_ = 0, vao_ = 0;
};

}  // namespace app
