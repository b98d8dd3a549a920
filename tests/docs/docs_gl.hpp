// tests/docs/docs_gl.hpp - what a user's renderer already has, for the documentation programs in
// tests/docs/gl_*.cpp: a GL 4.5 core context without a display, shader compilation, the text of a
// snippet, a few meshes, and a CPU ray cast to score a picture. Deliberately small and separate from
// samples/common: the docs programs show the path a user takes from README/docs pages and header
// comments alone, so nothing of the samples' framework may leak into them.
#pragma once

#include <epoxy/egl.h>
#include <epoxy/gl.h>
#include <glm/glm.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#ifndef SHADOWKIT_GLSL_DIR
#error "docs programs are compiled with SHADOWKIT_GLSL_DIR (the glsl/ folder)"
#endif

namespace docs {

/// Exit code of a docs program that cannot get a GL context: 77 (CTest: skipped), or 1 when the
/// environment sets SHADOWKIT_REQUIRE_GL (CI: GL must be there).
inline int no_gl_exit_code() { return std::getenv("SHADOWKIT_REQUIRE_GL") != nullptr ? 1 : 77; }

/// A GL 4.5 core context on EGL's surfaceless platform (Mesa llvmpipe here, the GPU driver
/// elsewhere), made current, with a w x h RGBA8 + DEPTH24_STENCIL8 framebuffer bound as the draw
/// target (the "window"). Returns false, with a reason on stderr, when there is none.
inline bool gl_context(int w, int h) {
    const char* ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (ext == nullptr || std::string(ext).find("EGL_MESA_platform_surfaceless") == std::string::npos) {
        std::fprintf(stderr, "docs: no EGL_MESA_platform_surfaceless\n");
        return false;
    }
    EGLDisplay d = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    EGLint major = 0, minor = 0;
    if (d == EGL_NO_DISPLAY || !eglInitialize(d, &major, &minor) || !eglBindAPI(EGL_OPENGL_API)) {
        std::fprintf(stderr, "docs: no EGL display\n");
        return false;
    }
    const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                              EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    EGLContext c = eglCreateContext(d, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attribs);
    if (c == EGL_NO_CONTEXT || !eglMakeCurrent(d, EGL_NO_SURFACE, EGL_NO_SURFACE, c)) {
        std::fprintf(stderr, "docs: no GL 4.5 core context\n");
        return false;
    }
    GLuint fbo = 0, color = 0, depth = 0;
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glGenRenderbuffers(1, &color);
    glBindRenderbuffer(GL_RENDERBUFFER, color);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, w, h);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color);
    glGenRenderbuffers(1, &depth);
    glBindRenderbuffer(GL_RENDERBUFFER, depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, w, h);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, depth);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        std::fprintf(stderr, "docs: incomplete default framebuffer\n");
        return false;
    }
    glViewport(0, 0, w, h);
    return true;
}

/// The framebuffer gl_context() made (the "window"), to bind again after rendering elsewhere.
inline GLuint window_framebuffer() {
    static GLuint fbo = 0;
    if (fbo == 0) glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, reinterpret_cast<GLint*>(&fbo));
    return fbo;
}

/// Compiles and links a vertex + fragment program; prints the log and exits 1 on error.
inline GLuint gl_program(const std::string& vs, const std::string& fs) {
    auto stage = [](GLenum type, const std::string& src) {
        GLuint s = glCreateShader(type);
        const char* p = src.c_str();
        glShaderSource(s, 1, &p, nullptr);
        glCompileShader(s);
        GLint ok = 0;
        glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
        if (!ok) {
            char log[4096];
            glGetShaderInfoLog(s, sizeof log, nullptr, log);
            std::fprintf(stderr, "%s shader:\n%s\n", type == GL_VERTEX_SHADER ? "vertex" : "fragment", log);
            std::exit(1);
        }
        return s;
    };
    GLuint p = glCreateProgram();
    glAttachShader(p, stage(GL_VERTEX_SHADER, vs));
    glAttachShader(p, stage(GL_FRAGMENT_SHADER, fs));
    glLinkProgram(p);
    GLint ok = 0;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[4096];
        glGetProgramInfoLog(p, sizeof log, nullptr, log);
        std::fprintf(stderr, "link:\n%s\n", log);
        std::exit(1);
    }
    return p;
}

/// The text of glsl/<name>.glsl (users paste it; the programs read the same file).
inline std::string snippet(const char* name) {
    std::ifstream f(std::string(SHADOWKIT_GLSL_DIR) + "/" + name + ".glsl");
    if (!f) {
        std::fprintf(stderr, "docs: no snippet glsl/%s.glsl\n", name);
        std::exit(1);
    }
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

/// An indexed triangle mesh (counter-clockwise front faces).
struct Mesh {
    std::vector<glm::vec3> positions;
    std::vector<std::uint32_t> indices;
};

/// An axis-aligned box: 8 corners, 12 triangles wound counter-clockwise seen from outside.
inline Mesh box(glm::vec3 lo, glm::vec3 hi) {
    Mesh m;
    for (int i = 0; i < 8; ++i)
        m.positions.push_back({(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
    const std::uint32_t q[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (const auto& f : q) m.indices.insert(m.indices.end(), {f[0], f[1], f[2], f[0], f[2], f[3]});
    return m;
}

/// A square at height y, |x|, |z| <= half_extent, facing +y (two triangles).
inline Mesh quad_y(float y, float half_extent) {
    const float e = half_extent;
    return Mesh{{{-e, y, -e}, {-e, y, e}, {e, y, e}, {e, y, -e}}, {0, 1, 2, 0, 2, 3}};
}

/// Appends `from` to `to` (indices offset).
inline void append(Mesh& to, const Mesh& from) {
    const auto base = static_cast<std::uint32_t>(to.positions.size());
    to.positions.insert(to.positions.end(), from.positions.begin(), from.positions.end());
    for (std::uint32_t i : from.indices) to.indices.push_back(base + i);
}

/// True when the open segment (from, to) crosses a triangle of m (Moller-Trumbore in double; the
/// end points themselves, within 1e-6 of the segment's length, do not count). Both sides of a
/// triangle block. The CPU reference the docs programs score their pictures against.
inline bool segment_occluded(const Mesh& m, glm::vec3 from, glm::vec3 to) {
    const glm::dvec3 o(from), d = glm::dvec3(to) - o;
    for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
        const glm::dvec3 a(m.positions[m.indices[t]]), b(m.positions[m.indices[t + 1]]), c(m.positions[m.indices[t + 2]]);
        const glm::dvec3 e1 = b - a, e2 = c - a, p = glm::cross(d, e2);
        const double det = glm::dot(e1, p);
        if (std::abs(det) < 1e-300) continue;
        const glm::dvec3 s = o - a;
        const double u = glm::dot(s, p) / det;
        if (u < 0.0 || u > 1.0) continue;
        const glm::dvec3 q = glm::cross(s, e1);
        const double v = glm::dot(d, q) / det;
        if (v < 0.0 || u + v > 1.0) continue;
        const double t_hit = glm::dot(e2, q) / det;
        if (t_hit > 1e-6 && t_hit < 1.0 - 1e-6) return true;
    }
    return false;
}

}  // namespace docs
