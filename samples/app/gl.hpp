// samples/app/gl.hpp - the app shell's GL helpers (was samples/common/gl_harness.hpp). Part of the
// shell every sample, the report and the GL tests share; not a public header (EGL + libepoxy).
//
// - headless OpenGL 4.5 core context on the EGL surfaceless platform (Mesa llvmpipe on a
//   machine without a GPU, the real driver elsewhere);
// - render targets with float colour and depth, shader compile/link with readable logs,
//   readback to float arrays, PNG writing (stb_image_write);
// - timing with glFinish + steady_clock (median over frames after warm-up), GL timer queries
//   only where the renderer is not llvmpipe (timer queries are meaningless there).
// A technique's code uses compile_program, depth_only_program, make_target / destroy_target,
// make_depth_texture / make_depth_framebuffers, GpuMesh / draw_mesh; the rest is the shell's and the
// report's.
#pragma once

#include <epoxy/gl.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace skgl {

struct Context {
    std::string renderer;  // GL_RENDERER
    std::string version;   // GL_VERSION
    bool llvmpipe = false; // software rasterizer: no timer queries, no depth-bounds test
    bool has_depth_bounds_test = false;
    bool has_clip_control = false;
    void* display = nullptr;  // EGLDisplay
    void* context = nullptr;  // EGLContext
    Context() = default;
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;
    ~Context();
};

// Creates a GL 4.5 core context on EGL's surfaceless platform and makes it current.
// Returns nullptr and a one-line reason in `why` when no such context can be had.
std::unique_ptr<Context> create_context(std::string& why);

// Process exit code for "skipped" that tests register with CTest's SKIP_RETURN_CODE.
constexpr int kSkipReturnCode = 77;
// The exit code when no GL context can be had: kSkipReturnCode, or 1 (a failure) when the
// environment sets SHADOWKIT_REQUIRE_GL (CI does: there the GL tests must run, never skip).
int no_context_exit_code();

struct ShaderStage {
    GLenum type;         // GL_VERTEX_SHADER, GL_FRAGMENT_SHADER, ...
    std::string source;  // complete source, including #version
};

// Compiles and links; returns 0 and a readable log (stage name, numbered source lines near
// the error) on failure. `separable` links a program of any subset of stages on its own
// (GL_PROGRAM_SEPARABLE), so a single fragment stage with free inputs links too.
GLuint compile_program(const std::vector<ShaderStage>& stages, std::string& log, bool separable = false);

// Reads a text file (GLSL snippet); empty string and `ok == false` if unreadable.
std::string read_text_file(const std::string& path, bool* ok = nullptr);

struct Target {
    GLuint fbo = 0;
    GLuint depth = 0;            // depth texture (0 if none)
    std::vector<GLuint> color;   // colour textures
    int width = 0, height = 0;
    GLenum depth_format = 0;
};

// Colour formats such as GL_R32F, GL_RGBA32F, GL_RGBA8; depth GL_DEPTH_COMPONENT32F,
// GL_DEPTH_COMPONENT24, GL_DEPTH24_STENCIL8, GL_DEPTH32F_STENCIL8 or 0 for none.
// Depth textures get nearest filtering and compare mode off; enable compare for
// sampler2DShadow with set_depth_compare().
bool make_target(Target& t, int width, int height, const std::vector<GLenum>& color_formats,
                 GLenum depth_format, std::string& why);
void destroy_target(Target& t);
void set_depth_compare(GLuint depth_texture, bool compare, bool linear_filter);
// A 2D texture read texel by texel: GL_NEAREST min and mag, S and T GL_CLAMP_TO_EDGE (left bound).
void set_nearest_clamped(GLuint texture);

// The depth-only program of a shadow map's pass: attribute 0 the position, gl_Position =
// u_light_view_proj * vec4(a_position, 1.0), no color output. 0 and the log on failure.
GLuint depth_only_program(std::string& log);

// A depth texture that compares in hardware (sampler2DShadow, sampler2DArrayShadow,
// samplerCubeShadow): GL_DEPTH_COMPONENT32F, one level, size x size, of `target` (GL_TEXTURE_2D,
// GL_TEXTURE_2D_ARRAY with `layers` layers, GL_TEXTURE_CUBE_MAP); GL_COMPARE_REF_TO_TEXTURE with
// GL_LEQUAL, `filter` for min and mag (GL_LINEAR: the 2x2 percentage-closer filter), S and T wrapped
// with `wrap` (GL_CLAMP_TO_BORDER: the border is the far depth 1, outside the map is lit). Left bound
// to `target` on the active texture unit.
GLuint make_depth_texture(GLenum target, int size, int layers, GLenum filter, GLenum wrap);
// `count` depth-only framebuffers of `texture` (of `target`): fbo[i]'s depth attachment is layer i of
// a 2D array, face GL_TEXTURE_CUBE_MAP_POSITIVE_X + i of a cube map, or the 2D texture; no color
// (draw and read buffer GL_NONE). Leaves fbo[count - 1] bound.
void make_depth_framebuffers(GLenum target, GLuint texture, int count, GLuint* fbo);

std::vector<float> read_color_float(const Target& t, int attachment, int channels);
std::vector<float> read_depth_float(const Target& t);

// 8-bit PNG; channels 1, 3 or 4; rows are written top-down from bottom-up GL data when
// flip_y is true.
bool write_png(const std::string& path, int width, int height, int channels,
               const std::uint8_t* pixels, bool flip_y = true);

// Median time in milliseconds of `frame` over `frames` runs after `warmup` runs. On llvmpipe
// (and any software rasterizer) each run is closed by glFinish() and timed with steady_clock; on
// a real GPU driver GL_TIME_ELAPSED timer queries measure the GPU's own time. Samples (ms) are
// returned in `samples` if non-null.
double median_frame_ms(const std::function<void()>& frame, int warmup, int frames,
                       std::vector<double>* samples = nullptr);

// True when median_frame_ms uses GL timer queries (a real GPU driver).
bool timer_queries_in_use();
// For a context made elsewhere (a GLFW window): reads GL_RENDERER of the current context and decides,
// as create_context does, whether timing uses timer queries (not on llvmpipe / softpipe). Returns it.
std::string note_current_context();

// Indexed triangle mesh on the GPU: attribute 0 = position (vec3), 1 = normal (vec3).
struct GpuMesh {
    GLuint vao = 0, vbo = 0, ibo = 0;
    GLsizei index_count = 0;
};
GpuMesh upload_mesh(const float* positions, const float* normals, std::size_t vertex_count,
                    const std::uint32_t* indices, std::size_t index_count);
void destroy_mesh(GpuMesh& m);
void draw_mesh(const GpuMesh& m);

// Returns the first GL error as text ("" if none) and clears the error queue.
std::string gl_error_string();

}  // namespace skgl
