// tests/docs/docs_gl.hpp - what a user's renderer already has, for the documentation programs in
// tests/docs/gl_*.cpp: a GL 4.5 core context without a display, shader compilation, the text of a
// snippet, a few meshes and their upload and draw calls, the programs' shared scenes, and what scores
// a picture (a G-buffer pass, a per-point lookup pass, CPU ray casts). Separate from the samples' app
// shell: the docs programs show the path a user takes from README/docs pages and header comments
// alone, so nothing of the samples' framework may leak into them; never the docs' own blocks either.
#pragma once

#include <epoxy/egl.h>
#include <epoxy/gl.h>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
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

/// An axis-aligned box as the CPU ray casts see it (docs::box() gives its triangles).
struct Box {
    glm::vec3 lo, hi;
};

/// Slab test: does o + t d for t in [t_min, t_max] meet the closed box? (An axis with |d| < 1e-12
/// counts as parallel: inside the slab or a miss.) A segment (a, b) is o = a, d = b - a, t in [0, 1].
inline bool ray_hits_box(const glm::dvec3& o, const glm::dvec3& d, const Box& box, double t_min, double t_max) {
    double t0 = t_min, t1 = t_max;
    for (int i = 0; i < 3; ++i) {
        if (std::abs(d[i]) < 1e-12) {
            if (o[i] < box.lo[i] || o[i] > box.hi[i]) return false;
            continue;
        }
        double u = (double(box.lo[i]) - o[i]) / d[i], v = (double(box.hi[i]) - o[i]) / d[i];
        if (u > v) std::swap(u, v);
        t0 = std::max(t0, u);
        t1 = std::min(t1, v);
        if (t0 > t1) return false;
    }
    return true;
}

/// The scene of gl_shadow_map, gl_pcss and gl_prefiltered_shadow: four boxes over a floor (the
/// floor is floor_scene()'s): one resting on it (contact shadows), a floating slab, a thin plate high
/// up (a wide penumbra under an area light) and a post.
inline std::vector<Box> floor_boxes() {
    return {{{-1.6f, 0.0f, -0.6f}, {-0.6f, 1.0f, 0.4f}},   // on the floor: contact shadows
            {{0.5f, 0.9f, -0.8f}, {1.6f, 1.3f, 0.3f}},     // floating slab
            {{-0.4f, 1.9f, 0.7f}, {0.7f, 2.0f, 1.7f}},     // thin plate, high: a wide penumbra
            {{1.2f, 0.0f, 1.2f}, {1.5f, 2.2f, 1.5f}}};     // a post
}

/// The floor (|x|, |z| <= 4 at y = 0) followed by floor_boxes(), as one mesh.
inline Mesh floor_scene() {
    Mesh m = quad_y(0.0f, 4.0f);
    for (const Box& b : floor_boxes()) append(m, box(b.lo, b.hi));
    return m;
}

/// A mesh as separate triangles: three vertices per triangle in index order, each with the
/// triangle's face normal (flat shading).
struct Triangles {
    std::vector<glm::vec3> positions, normals;
};
inline Triangles triangles(const Mesh& m) {
    Triangles f;
    for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
        const glm::vec3 a = m.positions[m.indices[t]], b = m.positions[m.indices[t + 1]], c = m.positions[m.indices[t + 2]];
        const glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
        for (const glm::vec3& p : {a, b, c}) {
            f.positions.push_back(p);
            f.normals.push_back(n);
        }
    }
    return f;
}

/// The user's mesh upload: a vertex array (left bound) with attribute 0 the positions and, when
/// `normals` is not empty, attribute 1 the normals, one buffer each, for glDrawArrays.
inline GLuint vertex_array(const std::vector<glm::vec3>& positions, const std::vector<glm::vec3>& normals = {}) {
    const int attributes = normals.empty() ? 1 : 2;
    GLuint vao = 0, vbo[2] = {0, 0};
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    glGenBuffers(attributes, vbo);
    for (int k = 0; k < attributes; ++k) {
        const std::vector<glm::vec3>& data = k == 0 ? positions : normals;
        glBindBuffer(GL_ARRAY_BUFFER, vbo[k]);
        glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(data.size() * sizeof(glm::vec3)), data.data(), GL_STATIC_DRAW);
        glVertexAttribPointer(static_cast<GLuint>(k), 3, GL_FLOAT, GL_FALSE, 0, nullptr);
        glEnableVertexAttribArray(static_cast<GLuint>(k));
    }
    return vao;
}

/// The user's draw call: a vertex array and its vertex count, drawn with glDrawArrays(GL_TRIANGLES).
struct DrawCall {
    GLuint vao = 0;
    GLsizei count = 0;
    void operator()() const {
        glBindVertexArray(vao);
        glDrawArrays(GL_TRIANGLES, 0, count);
    }
};

/// floor_scene() flat-shaded and uploaded (attribute 0 position, attribute 1 normal), as a draw call.
inline DrawCall floor_scene_draw() {
    const Triangles t = triangles(floor_scene());
    return DrawCall{vertex_array(t.positions, t.normals), static_cast<GLsizei>(t.positions.size())};
}

/// The camera of the programs on floor_scene(): at (0.5, 5.5, 7.5), looking at (0, 0.5, 0), y up,
/// 50 degrees vertical field of view, aspect w / h, near 0.1, far 50 (projection * view).
inline glm::mat4 floor_scene_camera(int w, int h) {
    return glm::perspective(glm::radians(50.0f), float(w) / float(h), 0.1f, 50.0f) *
           glm::lookAt(glm::vec3(0.5f, 5.5f, 7.5f), glm::vec3(0.0f, 0.5f, 0.0f), glm::vec3(0.0f, 1.0f, 0.0f));
}

/// A depth-only program: gl_Position = u_view_proj * vec4(position, 1.0) (attribute 0), no color.
inline GLuint depth_only_program() {
    return gl_program(R"(#version 450 core
layout(location = 0) in vec3 position;
uniform mat4 u_view_proj;
void main() { gl_Position = u_view_proj * vec4(position, 1.0); })",
                      "#version 450 core\nvoid main() {}\n");
}

/// Draws a triangle list of homogeneous positions (attribute 0, a vec4 each) with the program in use,
/// from a vertex array and a stream buffer of its own (left bound); an empty list draws nothing.
inline void draw_vec4_triangles(const std::vector<glm::vec4>& vertices) {
    static GLuint vao = 0, vbo = 0;
    if (vao == 0) {
        glGenVertexArrays(1, &vao);
        glGenBuffers(1, &vbo);
        glBindVertexArray(vao);
        glBindBuffer(GL_ARRAY_BUFFER, vbo);
        glEnableVertexAttribArray(0);
        glVertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, sizeof(glm::vec4), nullptr);
    }
    if (vertices.empty()) return;
    glBindVertexArray(vao);
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices.size() * sizeof(glm::vec4)), vertices.data(),
                 GL_STREAM_DRAW);
    glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(vertices.size()));
}

/// The window's pixels (RGBA8, bottom row first), read from window_framebuffer().
inline std::vector<unsigned char> window_rgba(int w, int h) {
    std::vector<unsigned char> rgba(static_cast<std::size_t>(w * h) * 4);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, window_framebuffer());
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    return rgba;
}

/// The program's G-buffer, for the score only (not a docs part): per pixel the world position
/// (w = 1 on a surface, 0 on the background) and the normal, bottom row first.
struct GBuffer {
    std::vector<glm::vec4> position, normal;
};

/// Renders the G-buffer with draw() (attribute 0 position, attribute 1 normal) seen through
/// view_proj into a w x h framebuffer of its own (RGBA32F x 2 + DEPTH_COMPONENT32F) and reads it
/// back. Leaves that framebuffer bound, the viewport w x h and the depth test on (GL_LESS).
template <class Draw>
GBuffer gbuffer(int w, int h, const glm::mat4& view_proj, Draw draw) {
    GLuint fbo = 0, tex[2] = {0, 0}, depth = 0;
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glGenTextures(2, tex);
    for (int k = 0; k < 2; ++k) {
        glBindTexture(GL_TEXTURE_2D, tex[k]);
        glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA32F, w, h);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(k), GL_TEXTURE_2D, tex[k], 0);
    }
    glGenRenderbuffers(1, &depth);
    glBindRenderbuffer(GL_RENDERBUFFER, depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, w, h);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
    const GLenum bufs[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glDrawBuffers(2, bufs);
    const GLuint prog = gl_program(R"(#version 450 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
uniform mat4 u_view_proj;
out vec3 v_world;
out vec3 v_normal;
void main() { v_world = a_position; v_normal = a_normal; gl_Position = u_view_proj * vec4(a_position, 1.0); })",
                                   R"(#version 450 core
in vec3 v_world;
in vec3 v_normal;
layout(location = 0) out vec4 o_pos;
layout(location = 1) out vec4 o_nrm;
void main() { o_pos = vec4(v_world, 1.0); o_nrm = vec4(normalize(v_normal), 1.0); })");
    glViewport(0, 0, w, h);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    glClearBufferfv(GL_COLOR, 0, zero);
    glClearBufferfv(GL_COLOR, 1, zero);
    glClear(GL_DEPTH_BUFFER_BIT);
    glUseProgram(prog);
    glUniformMatrix4fv(glGetUniformLocation(prog, "u_view_proj"), 1, GL_FALSE, &view_proj[0][0]);
    draw();
    GBuffer g;
    g.position.resize(static_cast<std::size_t>(w * h));
    g.normal.resize(g.position.size());
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glReadPixels(0, 0, w, h, GL_RGBA, GL_FLOAT, g.position.data());
    glReadBuffer(GL_COLOR_ATTACHMENT1);
    glReadPixels(0, 0, w, h, GL_RGBA, GL_FLOAT, g.normal.data());
    return g;
}

/// Points of the ground plane y = 0 seen through the centers of a 96 x 96 grid over the camera's
/// picture (view, proj), with the view depth in w; points whose depth is below near_depth or above
/// far_depth are left out.
inline std::vector<glm::vec4> ground_points(const glm::mat4& view, const glm::mat4& proj, float near_depth, float far_depth) {
    std::vector<glm::vec4> points;
    const glm::mat4 inv_vp = glm::inverse(proj * view);
    for (int j = 0; j < 96; ++j)
        for (int i = 0; i < 96; ++i) {
            const glm::vec4 a = inv_vp * glm::vec4(-1.0f + 2.0f * (float(i) + 0.5f) / 96.0f, -1.0f + 2.0f * (float(j) + 0.5f) / 96.0f, -1, 1);
            const glm::vec4 b = inv_vp * glm::vec4(-1.0f + 2.0f * (float(i) + 0.5f) / 96.0f, -1.0f + 2.0f * (float(j) + 0.5f) / 96.0f, 1, 1);
            const glm::vec3 o = glm::vec3(a) / a.w, dir = glm::vec3(b) / b.w - o;
            if (!(dir.y < 0.0f)) continue;
            const glm::vec3 p = o - dir * (o.y / dir.y);  // on the ground y = 0
            const float depth = -(view * glm::vec4(p, 1)).z;
            if (depth < near_depth || depth > far_depth) continue;
            points.push_back(glm::vec4(p, depth));
        }
    return points;
}

/// The vertex shader of a per-point lookup pass: point k (attribute 0, a vec4, handed on as
/// `flat out vec4 v_point`) of u_count_points lands on pixel k of an n x 1 target.
inline std::string points_vertex_shader() {
    return R"(#version 450 core
layout(location = 0) in vec4 point;
uniform int u_count_points;
flat out vec4 v_point;
void main() {
    v_point = point;
    gl_Position = vec4((float(gl_VertexID) + 0.5) / float(u_count_points) * 2.0 - 1.0, 0.0, 0.0, 1.0);
    gl_PointSize = 1.0;
})";
}

/// Runs `program` (vertex shader points_vertex_shader(), a float output; in use, with its uniforms
/// and textures set) once per point into an n x 1 R32F target of its own and reads the n values back.
/// Creates its objects with direct state access, so no texture unit's binding changes.
inline std::vector<float> shade_points(GLuint program, const std::vector<glm::vec4>& points) {
    const auto n = static_cast<GLsizei>(points.size());
    glProgramUniform1i(program, glGetUniformLocation(program, "u_count_points"), n);
    GLuint out_tex = 0, out_fbo = 0, pts_vao = 0, pts_vbo = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &out_tex);
    glTextureStorage2D(out_tex, 1, GL_R32F, n, 1);
    glCreateFramebuffers(1, &out_fbo);
    glNamedFramebufferTexture(out_fbo, GL_COLOR_ATTACHMENT0, out_tex, 0);
    glCreateBuffers(1, &pts_vbo);
    glNamedBufferData(pts_vbo, static_cast<GLsizeiptr>(points.size() * sizeof(glm::vec4)), points.data(), GL_STATIC_DRAW);
    glCreateVertexArrays(1, &pts_vao);
    glVertexArrayVertexBuffer(pts_vao, 0, pts_vbo, 0, sizeof(glm::vec4));
    glVertexArrayAttribFormat(pts_vao, 0, 4, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(pts_vao, 0, 0);
    glEnableVertexArrayAttrib(pts_vao, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, out_fbo);
    glBindVertexArray(pts_vao);
    glViewport(0, 0, n, 1);
    glDisable(GL_DEPTH_TEST);
    glDrawArrays(GL_POINTS, 0, n);
    std::vector<float> out(points.size());
    glReadPixels(0, 0, n, 1, GL_RED, GL_FLOAT, out.data());
    return out;
}

/// The check of a sun's hard shadow on ground points (gl_cascades, gl_light_frustum): the GPU's
/// `lit` (< 0.5: shadowed) against a ray from each point toward the sun past `boxes` (from t =
/// 1e-4 on). A point is not counted when edge_radius(k) < 0, or when the reference changes within
/// edge_radius(k) of it (8 directions on the ground): near a shadow edge.
struct GroundScore {
    int agree = 0, counted = 0;
    double ratio() const { return counted ? double(agree) / counted : 0.0; }
};
template <class EdgeRadius>
GroundScore score_ground_points(const std::vector<glm::vec4>& points, const std::vector<float>& lit,
                                const std::vector<Box>& boxes, glm::vec3 to_sun, EdgeRadius edge_radius) {
    GroundScore r;
    for (std::size_t k = 0; k < points.size(); ++k) {
        const glm::dvec3 p(points[k]);
        auto shadowed = [&](const glm::dvec3& q) {
            for (const Box& b : boxes)
                if (ray_hits_box(q, glm::dvec3(to_sun), b, 1e-4, 1e30)) return true;
            return false;
        };
        const bool s = shadowed(p);
        const double e = edge_radius(k);
        if (e < 0.0) continue;
        bool edge = false;
        for (int t = 0; t < 8 && !edge; ++t)
            edge = shadowed(p + e * glm::dvec3(std::cos(t * 0.785398), 0.0, std::sin(t * 0.785398))) != s;
        if (edge) continue;
        ++r.counted;
        r.agree += (lit[k] < 0.5f) == s;
    }
    return r;
}

/// The score of a soft-shadow picture under a square area light (side light_size, centered at
/// light_center, facing down), against a CPU ray cast from each G-buffer point (offset 1e-4 along
/// its normal) to 8 x 8 stratified, jittered points of the emitter (std::mt19937 seed 2005) past
/// `boxes`. Only receiver pixels that see every emitter corner above their tangent plane count.
struct AreaLightScore {
    int counted = 0, penumbra = 0;          // scored pixels; those with a reference in (0, 1)
    double rmse = 0.0, penumbra_rmse = 0.0;  // picture's red channel / 255 against the reference
};
inline AreaLightScore score_square_light(const GBuffer& g, const std::vector<unsigned char>& rgba, glm::vec3 light_center,
                                         float light_size, const std::vector<Box>& boxes) {
    std::vector<Mesh> box_meshes;
    for (const Box& b : boxes) box_meshes.push_back(box(b.lo, b.hi));
    std::mt19937 rng(2005);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    const int strata = 8;
    double se = 0.0, se_pen = 0.0;
    AreaLightScore r;
    for (std::size_t k = 0; k < g.position.size(); ++k) {
        if (g.position[k].w == 0.0f) continue;
        const glm::vec3 p(g.position[k]), n(g.normal[k]);
        bool whole_light_above = true;  // every emitter corner above the tangent plane
        for (int c = 0; c < 4; ++c) {
            const glm::vec3 corner = light_center + 0.5f * light_size * glm::vec3((c & 1) ? 1.0f : -1.0f, 0.0f, (c & 2) ? 1.0f : -1.0f);
            whole_light_above = whole_light_above && glm::dot(n, corner - p) > 0.0f;
        }
        if (!whole_light_above) continue;
        int visible = 0;
        for (int i = 0; i < strata; ++i)
            for (int j = 0; j < strata; ++j) {
                const glm::vec3 s = light_center + light_size * glm::vec3((float(i) + u01(rng)) / strata - 0.5f, 0.0f,
                                                                          (float(j) + u01(rng)) / strata - 0.5f);
                const glm::vec3 from = p + n * 1e-4f;
                bool blocked = false;  // the slab test first, the triangles only when it hits
                for (std::size_t b = 0; b < boxes.size() && !blocked; ++b)
                    blocked = ray_hits_box(glm::dvec3(from), glm::dvec3(s) - glm::dvec3(from), boxes[b], 0.0, 1.0) &&
                              segment_occluded(box_meshes[b], from, s);
                visible += blocked ? 0 : 1;
            }
        const double ref = double(visible) / double(strata * strata);
        const double v = double(rgba[4 * k]) / 255.0;
        se += (v - ref) * (v - ref);
        ++r.counted;
        if (ref > 0.0 && ref < 1.0) {
            se_pen += (v - ref) * (v - ref);
            ++r.penumbra;
        }
    }
    r.rmse = std::sqrt(se / std::max(r.counted, 1));
    r.penumbra_rmse = std::sqrt(se_pen / std::max(r.penumbra, 1));
    return r;
}

/// Prints the score as "<name>: N receiver pixels (M in penumbrae), RMSE .., penumbra RMSE .." (with
/// "FAIL (> max_rmse)" above it) and a GL error if there is one; the program's exit code: 0 when there
/// is no GL error, counted > 10000, penumbra > 500 and rmse <= max_rmse, else 1.
inline int area_light_verdict(const char* name, const AreaLightScore& s, double max_rmse) {
    char fail[48];
    std::snprintf(fail, sizeof fail, "  FAIL (> %g)", max_rmse);
    std::printf("%s: %d receiver pixels (%d in penumbrae), RMSE %.4f, penumbra RMSE %.4f against an 8x8-sample "
                "area-light ray cast%s\n",
                name, s.counted, s.penumbra, s.rmse, s.penumbra_rmse, s.rmse <= max_rmse ? "" : fail);
    const GLenum err = glGetError();
    if (err != GL_NO_ERROR) {
        std::printf("%s: GL error 0x%x\n", name, err);
        return 1;
    }
    return s.counted > 10000 && s.penumbra > 500 && s.rmse <= max_rmse ? 0 : 1;
}

}  // namespace docs
