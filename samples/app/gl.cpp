#include "gl.hpp"

#include <epoxy/egl.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "stb_image_write.h"

namespace skgl {

Context::~Context() {
    if (display != nullptr) {
        auto d = static_cast<EGLDisplay>(display);
        eglMakeCurrent(d, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        if (context != nullptr) eglDestroyContext(d, static_cast<EGLContext>(context));
        eglTerminate(d);
    }
}

// Set by create_context: GL timer queries are meaningful only on a real GPU driver.
static bool g_use_timer_queries = false;

std::unique_ptr<Context> create_context(std::string& why) {
    // eglGetPlatformDisplayEXT: libepoxy cannot resolve the EGL 1.5 core entry point
    // before a display exists, the EXT one is resolved from the client extensions.
    const char* client_ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (client_ext == nullptr || std::string(client_ext).find("EGL_MESA_platform_surfaceless") == std::string::npos) {
        why = "EGL_MESA_platform_surfaceless is not available (no Mesa EGL?)";
        return nullptr;
    }
    EGLDisplay d = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (d == EGL_NO_DISPLAY) {
        why = "eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA) returned no display";
        return nullptr;
    }
    EGLint major = 0, minor = 0;
    if (!eglInitialize(d, &major, &minor)) {
        why = "eglInitialize failed on the surfaceless display";
        return nullptr;
    }
    auto ctx = std::make_unique<Context>();
    ctx->display = d;
    if (!eglBindAPI(EGL_OPENGL_API)) {
        why = "eglBindAPI(EGL_OPENGL_API) failed";
        return nullptr;
    }
    const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                              EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                              EGL_NONE};
    EGLContext c = eglCreateContext(d, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attribs);
    if (c == EGL_NO_CONTEXT) {
        char buf[96];
        std::snprintf(buf, sizeof buf, "eglCreateContext(GL 4.5 core) failed: EGL error 0x%x", eglGetError());
        why = buf;
        return nullptr;
    }
    ctx->context = c;
    if (!eglMakeCurrent(d, EGL_NO_SURFACE, EGL_NO_SURFACE, c)) {
        why = "eglMakeCurrent without a surface failed";
        return nullptr;
    }
    ctx->renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    ctx->version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    ctx->llvmpipe = ctx->renderer.find("llvmpipe") != std::string::npos ||
                    ctx->renderer.find("softpipe") != std::string::npos;
    ctx->has_depth_bounds_test = epoxy_has_gl_extension("GL_EXT_depth_bounds_test");
    ctx->has_clip_control = epoxy_gl_version() >= 45 || epoxy_has_gl_extension("GL_ARB_clip_control");
    g_use_timer_queries = !ctx->llvmpipe;
    return ctx;
}

static const char* stage_name(GLenum type) {
    switch (type) {
        case GL_VERTEX_SHADER: return "vertex";
        case GL_FRAGMENT_SHADER: return "fragment";
        case GL_GEOMETRY_SHADER: return "geometry";
        case GL_COMPUTE_SHADER: return "compute";
        default: return "shader";
    }
}

static std::string numbered(const std::string& src) {
    std::ostringstream out;
    std::istringstream in(src);
    std::string line;
    int n = 1;
    while (std::getline(in, line)) {
        out << (n < 10 ? "   " : n < 100 ? "  " : n < 1000 ? " " : "") << n << ": " << line << '\n';
        ++n;
    }
    return out.str();
}

GLuint compile_program(const std::vector<ShaderStage>& stages, std::string& log, bool separable) {
    GLuint prog = glCreateProgram();
    if (separable) glProgramParameteri(prog, GL_PROGRAM_SEPARABLE, GL_TRUE);
    std::vector<GLuint> shaders;
    bool ok = true;
    for (const auto& s : stages) {
        GLuint sh = glCreateShader(s.type);
        const char* src = s.source.c_str();
        glShaderSource(sh, 1, &src, nullptr);
        glCompileShader(sh);
        GLint status = 0;
        glGetShaderiv(sh, GL_COMPILE_STATUS, &status);
        if (!status) {
            GLint len = 0;
            glGetShaderiv(sh, GL_INFO_LOG_LENGTH, &len);
            std::string info(static_cast<std::size_t>(std::max(len, 1)), '\0');
            glGetShaderInfoLog(sh, len, nullptr, info.data());
            log += std::string(stage_name(s.type)) + " shader failed to compile:\n" + info.c_str() +
                   "\n" + numbered(s.source);
            ok = false;
        }
        glAttachShader(prog, sh);
        shaders.push_back(sh);
    }
    if (ok) {
        glLinkProgram(prog);
        GLint status = 0;
        glGetProgramiv(prog, GL_LINK_STATUS, &status);
        if (!status) {
            GLint len = 0;
            glGetProgramiv(prog, GL_INFO_LOG_LENGTH, &len);
            std::string info(static_cast<std::size_t>(std::max(len, 1)), '\0');
            glGetProgramInfoLog(prog, len, nullptr, info.data());
            log += "program failed to link:\n" + std::string(info.c_str());
            ok = false;
        }
    }
    for (GLuint sh : shaders) glDeleteShader(sh);
    if (!ok) {
        glDeleteProgram(prog);
        return 0;
    }
    return prog;
}

std::string read_text_file(const std::string& path, bool* ok) {
    std::ifstream f(path, std::ios::binary);
    if (!f) {
        if (ok) *ok = false;
        return {};
    }
    std::ostringstream ss;
    ss << f.rdbuf();
    if (ok) *ok = true;
    return ss.str();
}

static GLenum color_base_format(GLenum internal) {
    switch (internal) {
        case GL_R32F: case GL_R16F: case GL_R8: return GL_RED;
        case GL_RG32F: case GL_RG16F: return GL_RG;
        case GL_RGB32F: return GL_RGB;
        default: return GL_RGBA;
    }
}

bool make_target(Target& t, int width, int height, const std::vector<GLenum>& color_formats,
                 GLenum depth_format, std::string& why) {
    if (width <= 0 || height <= 0) {
        why = "render target size must be positive";
        return false;
    }
    t = Target{};
    t.width = width;
    t.height = height;
    t.depth_format = depth_format;
    glGenFramebuffers(1, &t.fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, t.fbo);
    std::vector<GLenum> bufs;
    for (std::size_t i = 0; i < color_formats.size(); ++i) {
        GLuint tex = 0;
        glGenTextures(1, &tex);
        glBindTexture(GL_TEXTURE_2D, tex);
        glTexStorage2D(GL_TEXTURE_2D, 1, color_formats[i], width, height);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        const auto att = static_cast<GLenum>(GL_COLOR_ATTACHMENT0 + i);
        glFramebufferTexture2D(GL_FRAMEBUFFER, att, GL_TEXTURE_2D, tex, 0);
        t.color.push_back(tex);
        bufs.push_back(att);
    }
    if (depth_format != 0) {
        glGenTextures(1, &t.depth);
        glBindTexture(GL_TEXTURE_2D, t.depth);
        glTexStorage2D(GL_TEXTURE_2D, 1, depth_format, width, height);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_BORDER);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_BORDER);
        const float far_border[4] = {1.f, 1.f, 1.f, 1.f};
        glTexParameterfv(GL_TEXTURE_2D, GL_TEXTURE_BORDER_COLOR, far_border);
        const bool stencil = depth_format == GL_DEPTH24_STENCIL8 || depth_format == GL_DEPTH32F_STENCIL8;
        glFramebufferTexture2D(GL_FRAMEBUFFER, stencil ? GL_DEPTH_STENCIL_ATTACHMENT : GL_DEPTH_ATTACHMENT,
                               GL_TEXTURE_2D, t.depth, 0);
    }
    if (bufs.empty()) {
        glDrawBuffer(GL_NONE);
        glReadBuffer(GL_NONE);
    } else {
        glDrawBuffers(static_cast<GLsizei>(bufs.size()), bufs.data());
    }
    const GLenum st = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (st != GL_FRAMEBUFFER_COMPLETE) {
        char buf[80];
        std::snprintf(buf, sizeof buf, "framebuffer incomplete: 0x%x", st);
        why = buf;
        destroy_target(t);
        return false;
    }
    return true;
}

void destroy_target(Target& t) {
    if (!t.color.empty()) glDeleteTextures(static_cast<GLsizei>(t.color.size()), t.color.data());
    if (t.depth) glDeleteTextures(1, &t.depth);
    if (t.fbo) glDeleteFramebuffers(1, &t.fbo);
    t = Target{};
}

void set_depth_compare(GLuint depth_texture, bool compare, bool linear_filter) {
    glBindTexture(GL_TEXTURE_2D, depth_texture);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, compare ? GL_COMPARE_REF_TO_TEXTURE : GL_NONE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    const GLint f = linear_filter ? GL_LINEAR : GL_NEAREST;
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, f);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, f);
}

void set_nearest_clamped(GLuint texture) {
    glBindTexture(GL_TEXTURE_2D, texture);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

GLuint depth_only_program(std::string& log) {
    const char* vs = R"(#version 450 core
layout(location = 0) in vec3 a_position;
uniform mat4 u_light_view_proj;
void main() { gl_Position = u_light_view_proj * vec4(a_position, 1.0); }
)";
    return compile_program({{GL_VERTEX_SHADER, vs}, {GL_FRAGMENT_SHADER, "#version 450 core\nvoid main() {}\n"}}, log);
}

GLuint make_depth_texture(GLenum target, int size, int layers, GLenum filter, GLenum wrap) {
    GLuint tex = 0;
    glGenTextures(1, &tex);
    glBindTexture(target, tex);
    if (target == GL_TEXTURE_2D_ARRAY)
        glTexStorage3D(target, 1, GL_DEPTH_COMPONENT32F, size, size, layers);
    else
        glTexStorage2D(target, 1, GL_DEPTH_COMPONENT32F, size, size);
    glTexParameteri(target, GL_TEXTURE_MIN_FILTER, static_cast<GLint>(filter));
    glTexParameteri(target, GL_TEXTURE_MAG_FILTER, static_cast<GLint>(filter));
    glTexParameteri(target, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glTexParameteri(target, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    glTexParameteri(target, GL_TEXTURE_WRAP_S, static_cast<GLint>(wrap));
    glTexParameteri(target, GL_TEXTURE_WRAP_T, static_cast<GLint>(wrap));
    if (wrap == GL_CLAMP_TO_BORDER) {
        const float far_border[4] = {1.f, 1.f, 1.f, 1.f};
        glTexParameterfv(target, GL_TEXTURE_BORDER_COLOR, far_border);
    }
    return tex;
}

void make_depth_framebuffers(GLenum target, GLuint texture, int count, GLuint* fbo) {
    glGenFramebuffers(count, fbo);
    for (int i = 0; i < count; ++i) {
        glBindFramebuffer(GL_FRAMEBUFFER, fbo[i]);
        if (target == GL_TEXTURE_2D_ARRAY)
            glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, texture, 0, i);
        else
            glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT,
                                   target == GL_TEXTURE_CUBE_MAP ? static_cast<GLenum>(GL_TEXTURE_CUBE_MAP_POSITIVE_X + i) : target,
                                   texture, 0);
        glDrawBuffer(GL_NONE);
        glReadBuffer(GL_NONE);
    }
}

std::vector<float> read_color_float(const Target& t, int attachment, int channels) {
    std::vector<float> out(static_cast<std::size_t>(t.width) * static_cast<std::size_t>(t.height) *
                           static_cast<std::size_t>(channels));
    const GLenum fmt = channels == 1 ? GL_RED : channels == 2 ? GL_RG : channels == 3 ? GL_RGB : GL_RGBA;
    glBindFramebuffer(GL_READ_FRAMEBUFFER, t.fbo);
    glReadBuffer(static_cast<GLenum>(GL_COLOR_ATTACHMENT0 + attachment));
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, t.width, t.height, fmt, GL_FLOAT, out.data());
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    (void)color_base_format;
    return out;
}

std::vector<float> read_depth_float(const Target& t) {
    std::vector<float> out(static_cast<std::size_t>(t.width) * static_cast<std::size_t>(t.height));
    glBindFramebuffer(GL_READ_FRAMEBUFFER, t.fbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, t.width, t.height, GL_DEPTH_COMPONENT, GL_FLOAT, out.data());
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    return out;
}

bool write_png(const std::string& path, int width, int height, int channels, const std::uint8_t* pixels,
               bool flip_y) {
    stbi_flip_vertically_on_write(flip_y ? 1 : 0);
    return stbi_write_png(path.c_str(), width, height, channels, pixels, width * channels) != 0;
}

bool timer_queries_in_use() { return g_use_timer_queries; }

std::string note_current_context() {
    const auto* r = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    const std::string renderer = r ? r : "";
    g_use_timer_queries = renderer.find("llvmpipe") == std::string::npos && renderer.find("softpipe") == std::string::npos;
    return renderer;
}

double median_frame_ms(const std::function<void()>& frame, int warmup, int frames, std::vector<double>* samples) {
    for (int i = 0; i < warmup; ++i) {
        frame();
        glFinish();
    }
    std::vector<double> ms;
    ms.reserve(static_cast<std::size_t>(std::max(frames, 1)));
    glFinish();
    GLuint query = 0;
    if (g_use_timer_queries) glGenQueries(1, &query);
    for (int i = 0; i < std::max(frames, 1); ++i) {
        if (g_use_timer_queries) {
            // real GPU: the GPU's own elapsed time for the frame's commands
            glBeginQuery(GL_TIME_ELAPSED, query);
            frame();
            glEndQuery(GL_TIME_ELAPSED);
            GLuint64 ns = 0;
            glGetQueryObjectui64v(query, GL_QUERY_RESULT, &ns);
            ms.push_back(static_cast<double>(ns) * 1e-6);
            continue;
        }
        // software rasterizer: the work happens on the CPU; time it to completion
        const auto t0 = std::chrono::steady_clock::now();
        frame();
        glFinish();
        const auto t1 = std::chrono::steady_clock::now();
        ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    }
    if (query) glDeleteQueries(1, &query);
    if (samples) *samples = ms;
    std::vector<double> s = ms;
    std::nth_element(s.begin(), s.begin() + static_cast<std::ptrdiff_t>(s.size() / 2), s.end());
    return s[s.size() / 2];
}

GpuMesh upload_mesh(const float* positions, const float* normals, std::size_t vertex_count,
                    const std::uint32_t* indices, std::size_t index_count) {
    GpuMesh m;
    std::vector<float> interleaved(vertex_count * 6);
    for (std::size_t i = 0; i < vertex_count; ++i) {
        for (int k = 0; k < 3; ++k) {
            interleaved[i * 6 + static_cast<std::size_t>(k)] = positions[i * 3 + static_cast<std::size_t>(k)];
            interleaved[i * 6 + 3 + static_cast<std::size_t>(k)] = normals ? normals[i * 3 + static_cast<std::size_t>(k)] : 0.f;
        }
    }
    glGenVertexArrays(1, &m.vao);
    glBindVertexArray(m.vao);
    glGenBuffers(1, &m.vbo);
    glBindBuffer(GL_ARRAY_BUFFER, m.vbo);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(interleaved.size() * sizeof(float)), interleaved.data(),
                 GL_STATIC_DRAW);
    glGenBuffers(1, &m.ibo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, m.ibo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(index_count * sizeof(std::uint32_t)), indices,
                 GL_STATIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), reinterpret_cast<const void*>(3 * sizeof(float)));
    glBindVertexArray(0);
    m.index_count = static_cast<GLsizei>(index_count);
    return m;
}

void destroy_mesh(GpuMesh& m) {
    if (m.ibo) glDeleteBuffers(1, &m.ibo);
    if (m.vbo) glDeleteBuffers(1, &m.vbo);
    if (m.vao) glDeleteVertexArrays(1, &m.vao);
    m = GpuMesh{};
}

void draw_mesh(const GpuMesh& m) {
    glBindVertexArray(m.vao);
    glDrawElements(GL_TRIANGLES, m.index_count, GL_UNSIGNED_INT, nullptr);
    glBindVertexArray(0);
}

std::string gl_error_string() {
    std::string first;
    for (GLenum e = glGetError(); e != GL_NO_ERROR; e = glGetError()) {
        if (first.empty()) {
            char buf[48];
            std::snprintf(buf, sizeof buf, "GL error 0x%x", e);
            first = buf;
        }
    }
    return first;
}

int no_context_exit_code() {
    const char* v = std::getenv("SHADOWKIT_REQUIRE_GL");
    return v && *v && std::string(v) != "0" ? 1 : kSkipReturnCode;
}

}  // namespace skgl
