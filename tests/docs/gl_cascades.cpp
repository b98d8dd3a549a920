// docs/cascades.md, as one program: the parts marked <!-- example: gl_cascades/PART --> in the page
// are included below where a user's program would have them. The program adds what a user has anyway
// (a GL context, a scene, shader compilation) and the check: a grid of ground points seen by the
// camera is shaded by glsl/cascades.glsl on the GPU and compared with a CPU ray cast toward the sun.
// Exits 77 (skipped) without an EGL/GL 4.5 context (1 when SHADOWKIT_REQUIRE_GL is set), 1 if fewer than 99.5% of the points away from
// shadow edges agree.
#include <shadowkit/cascades.hpp>

#include <epoxy/egl.h>
#include <epoxy/gl.h>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#ifndef SHADOWKIT_GLSL_DIR
#define SHADOWKIT_GLSL_DIR "glsl"  // run from the repository root, or define it
#endif

namespace {

bool make_context() {
    const char* ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!ext || std::string(ext).find("EGL_MESA_platform_surfaceless") == std::string::npos) return false;
    EGLDisplay d = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    EGLint major = 0, minor = 0;
    if (d == EGL_NO_DISPLAY || !eglInitialize(d, &major, &minor) || !eglBindAPI(EGL_OPENGL_API)) return false;
    const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                              EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    EGLContext c = eglCreateContext(d, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attribs);
    return c != EGL_NO_CONTEXT && eglMakeCurrent(d, EGL_NO_SURFACE, EGL_NO_SURFACE, c);
}

std::string read_file(const std::string& path) {
    std::ifstream f(path);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

GLuint program(const std::string& vs, const std::string& fs) {
    GLuint p = glCreateProgram();
    for (int k = 0; k < 2; ++k) {
        const std::string& src = k ? fs : vs;
        GLuint sh = glCreateShader(k ? GL_FRAGMENT_SHADER : GL_VERTEX_SHADER);
        const char* s = src.c_str();
        glShaderSource(sh, 1, &s, nullptr);
        glCompileShader(sh);
        GLint ok = 0;
        glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
        if (!ok) {
            char log[4096];
            glGetShaderInfoLog(sh, sizeof log, nullptr, log);
            std::fprintf(stderr, "shader: %s\n", log);
        }
        glAttachShader(p, sh);
    }
    glLinkProgram(p);
    return p;
}

// Casters: axis-aligned boxes as triangles (12 per box) and as boxes for the CPU ray cast.
struct Box {
    glm::vec3 lo, hi;
};
void add_box(const Box& b, std::vector<glm::vec3>& tris) {
    const glm::vec3 c[8] = {{b.lo.x, b.lo.y, b.lo.z}, {b.hi.x, b.lo.y, b.lo.z}, {b.lo.x, b.hi.y, b.lo.z},
                            {b.hi.x, b.hi.y, b.lo.z}, {b.lo.x, b.lo.y, b.hi.z}, {b.hi.x, b.lo.y, b.hi.z},
                            {b.lo.x, b.hi.y, b.hi.z}, {b.hi.x, b.hi.y, b.hi.z}};
    const int q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}};
    for (const auto& f : q)
        for (int t : {0, 1, 2, 0, 2, 3}) tris.push_back(c[f[t]]);
}
bool ray_hits_box(const glm::dvec3& o, const glm::dvec3& d, const Box& b) {
    double t0 = 1e-4, t1 = 1e30;
    for (int a = 0; a < 3; ++a) {
        if (d[a] == 0.0) {
            if (o[a] < b.lo[a] || o[a] > b.hi[a]) return false;
            continue;
        }
        double ta = (b.lo[a] - o[a]) / d[a], tb = (b.hi[a] - o[a]) / d[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::fmax(t0, ta);
        t1 = std::fmin(t1, tb);
    }
    return t0 <= t1;
}

}  // namespace

int main() {
    if (!make_context()) {
        std::puts("no EGL/GL 4.5 context: skipped");
        return std::getenv("SHADOWKIT_REQUIRE_GL") != nullptr ? 1 : 77;  // CI requires GL
    }
    // --- the user's scene: a ground plane (receiver) and boxes (casters), a camera, the sun
    const std::vector<Box> boxes = {{{-1, 0, -11}, {1, 2.5f, -9}}, {{6, 0, -31}, {9, 6, -27}},
                                    {{-12, 0, -55}, {-6, 10, -49}}, {{-3, 1, -4}, {-2, 1.5f, -3}}};
    std::vector<glm::vec3> caster_tris;
    for (const Box& b : boxes) add_box(b, caster_tris);
    GLuint caster_vao = 0, vbo = 0;
    glGenVertexArrays(1, &caster_vao);
    glBindVertexArray(caster_vao);
    glGenBuffers(1, &vbo);
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(caster_tris.size() * sizeof(glm::vec3)), caster_tris.data(), GL_STATIC_DRAW);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
    glEnableVertexAttribArray(0);
    const GLsizei caster_vertex_count = GLsizei(caster_tris.size());
    const glm::mat4 view = glm::lookAt(glm::vec3(0, 6, 8), glm::vec3(0, 0, -20), glm::vec3(0, 1, 0));
    const float fovy = glm::radians(60.0f), aspect = 16.0f / 9.0f;
    const glm::mat4 proj = glm::perspective(fovy, aspect, 0.1f, 500.0f);
    const glm::vec3 to_sun = glm::normalize(glm::vec3(0.4f, 1.0f, 0.3f));  // direction toward the sun
    const GLsizei size = 1024;
    const GLuint depth_program = program(R"(#version 450 core
layout(location = 0) in vec3 position;
uniform mat4 u_view_proj;
void main() { gl_Position = u_view_proj * vec4(position, 1.0); })",
                                         "#version 450 core\nvoid main() {}\n");

#include "fit.inc"
#include "textures.inc"
#include "shadow_pass.inc"

    // --- the check: ground points seen by the camera, shaded on the GPU by the snippet
    std::vector<glm::vec4> points;  // xyz world position, w = view depth
    const glm::mat4 inv_vp = glm::inverse(proj * view);
    for (int j = 0; j < 96; ++j)
        for (int i = 0; i < 96; ++i) {
            const glm::vec4 a = inv_vp * glm::vec4(-1.0f + 2.0f * (float(i) + 0.5f) / 96.0f, -1.0f + 2.0f * (float(j) + 0.5f) / 96.0f, -1, 1);
            const glm::vec4 b = inv_vp * glm::vec4(-1.0f + 2.0f * (float(i) + 0.5f) / 96.0f, -1.0f + 2.0f * (float(j) + 0.5f) / 96.0f, 1, 1);
            const glm::vec3 o = glm::vec3(a) / a.w, dir = glm::vec3(b) / b.w - o;
            if (!(dir.y < 0.0f)) continue;
            const glm::vec3 p = o - dir * (o.y / dir.y);  // on the ground y = 0
            const float depth = -(view * glm::vec4(p, 1)).z;
            if (depth < fit.splits[0] || depth > fit.splits[4]) continue;
            points.push_back(glm::vec4(p, depth));
        }
    const GLsizei n = GLsizei(points.size());
    const std::string snippet = read_file(SHADOWKIT_GLSL_DIR "/cascades.glsl");
    if (snippet.empty()) {
        std::fprintf(stderr, "cannot read %s/cascades.glsl\n", SHADOWKIT_GLSL_DIR);
        return 1;
    }
    const GLuint lookup_program = program(R"(#version 450 core
layout(location = 0) in vec4 point;
uniform int u_count_points;
flat out vec4 v_point;
void main() {
    v_point = point;
    gl_Position = vec4((float(gl_VertexID) + 0.5) / float(u_count_points) * 2.0 - 1.0, 0.0, 0.0, 1.0);
    gl_PointSize = 1.0;
})",
                                          "#version 450 core\n" + snippet + R"(
layout(binding = 0) uniform sampler2DArrayShadow u_cascades;
uniform mat4 u_cascade_vp[4];
uniform vec4 u_split_near;
uniform vec4 u_split_far;
uniform float u_texel[4];
flat in vec4 v_point;
out float lit;
void main() {
    // the page's normal offset (the ground's normal is +y) and its constant bias
    int i = sk_cascade_by_depth(v_point.w, u_split_far, 4);
    bool band = i >= 0 && i + 1 < 4 && sk_cascade_blend(v_point.w, u_split_near[i], u_split_far[i], 0.1) > 0.0;
    float texel = i < 0 ? 0.0 : u_texel[band ? i + 1 : i];
    vec3 p = v_point.xyz + vec3(0.0, 1.0, 0.0) * texel;
    lit = sk_cascade_shadow(u_cascades, u_cascade_vp, u_split_near, u_split_far, 4, p, v_point.w, 0.1, 0.0005, false);
})");
    glUseProgram(lookup_program);
    glUniform1i(glGetUniformLocation(lookup_program, "u_count_points"), n);
#include "lookup.inc"
    GLuint out_tex = 0, out_fbo = 0, pts_vao = 0, pts_vbo = 0;
    glGenTextures(1, &out_tex);
    glBindTexture(GL_TEXTURE_2D, out_tex);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_R32F, n, 1);
    glGenFramebuffers(1, &out_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, out_fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, out_tex, 0);
    glGenVertexArrays(1, &pts_vao);
    glBindVertexArray(pts_vao);
    glGenBuffers(1, &pts_vbo);
    glBindBuffer(GL_ARRAY_BUFFER, pts_vbo);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(points.size() * sizeof(glm::vec4)), points.data(), GL_STATIC_DRAW);
    glVertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, 0, nullptr);
    glEnableVertexAttribArray(0);
    glViewport(0, 0, n, 1);
    glDisable(GL_DEPTH_TEST);
    glDrawArrays(GL_POINTS, 0, n);
    std::vector<float> lit(points.size());
    glReadPixels(0, 0, n, 1, GL_RED, GL_FLOAT, lit.data());

    // CPU reference: a ray from the point toward the sun; points within 3 texels of a shadow edge
    // (the reference changes within that distance) are not counted
    int agree = 0, counted = 0;
    for (std::size_t k = 0; k < points.size(); ++k) {
        const glm::dvec3 p(points[k]);
        auto shadowed = [&](const glm::dvec3& q) {
            for (const Box& b : boxes)
                if (ray_hits_box(q, glm::dvec3(to_sun), b)) return true;
            return false;
        };
        const bool s = shadowed(p);
        const int c = shadowkit::cascade_select_by_depth(points[k].w, fit.splits, 4).index;
        if (c < 0) continue;
        const double e = 3.0 * double(cascades[c].texel_world_size);
        bool edge = false;
        for (int t = 0; t < 8 && !edge; ++t)
            edge = shadowed(p + e * glm::dvec3(std::cos(t * 0.785398), 0.0, std::sin(t * 0.785398))) != s;
        if (edge) continue;
        ++counted;
        agree += (lit[k] < 0.5f) == s;
    }
    const double ratio = counted ? double(agree) / counted : 0.0;
    std::printf("cascades: %d of %d ground points away from shadow edges agree with the ray cast (%.2f%%)\n", agree,
                counted, 100.0 * ratio);
    return (counted > 1000 && ratio >= 0.995) ? 0 : 1;
}
