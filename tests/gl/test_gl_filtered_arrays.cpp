// Filtered depth arrays on the GL driver (issue 25 item 2):
// (a) every kernel of glsl/pcf.glsl and glsl/pcss.glsl has a sampler2DArrayShadow (+ sampler2DArray for
//     the PCSS blocker search) overload with a layer; on the same depths placed in layer L of a 4-layer
//     array (the other layers hold other depths) it gives the 2D kernel's value within 1e-6, for several
//     L, and both match the CPU emulation the 2D kernels are tested against (pcf_reference.hpp);
//     reading a wrong layer differs (the comparison can fail);
// (b) glsl/cascades.glsl's sk_cascade_shadow_filtered (pcf.glsl pasted first): each kernel in the
//     selected cascade's layer, mixed with the next cascade's over the blend band, against the CPU
//     kernels on each layer's depths and the band weight computed here from the splits; with the hard
//     kernel it equals sk_cascade_shadow exactly.
#include <doctest/doctest.h>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "gl_test.hpp"
#include "pcf_reference.hpp"
#include "metrics.hpp"
#include "reference.hpp"
#include "scene.hpp"
#include "techniques.hpp"

using namespace pcfref;

namespace {

GLuint rgba32f_row(const std::vector<float>& rgba) {
    const int w = static_cast<int>(rgba.size() / 4);
    GLuint t = 0;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA32F, w, 1);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, w, 1, GL_RGBA, GL_FLOAT, rgba.data());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    return t;
}

// A depth texture: 2D (layers == 0) holding `tex`, or a 2D array whose layer `layer` holds `tex` and
// whose other layers hold `other`.
GLuint depth_texture(const DepthTexture& tex, int layers, int layer, const DepthTexture* other) {
    GLuint t = 0;
    glGenTextures(1, &t);
    if (layers == 0) {
        glBindTexture(GL_TEXTURE_2D, t);
        glTexStorage2D(GL_TEXTURE_2D, 1, GL_DEPTH_COMPONENT32F, tex.w, tex.h);
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, tex.w, tex.h, GL_DEPTH_COMPONENT, GL_FLOAT, tex.d.data());
        return t;
    }
    glBindTexture(GL_TEXTURE_2D_ARRAY, t);
    glTexStorage3D(GL_TEXTURE_2D_ARRAY, 1, GL_DEPTH_COMPONENT32F, tex.w, tex.h, layers);
    for (int l = 0; l < layers; ++l)
        glTexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, 0, 0, l, tex.w, tex.h, 1, GL_DEPTH_COMPONENT, GL_FLOAT,
                        (l == layer ? tex : *other).d.data());
    return t;
}

// Two sampler objects: [0] compare mode, GL_LINEAR (the kernels' taps); [1] no compare, GL_NEAREST
// (the PCSS blocker search). Clamped to the edge.
void make_samplers(GLuint smp[2]) {
    glGenSamplers(2, smp);
    for (int k = 0; k < 2; ++k) {
        glSamplerParameteri(smp[k], GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glSamplerParameteri(smp[k], GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        glSamplerParameteri(smp[k], GL_TEXTURE_MIN_FILTER, k == 0 ? GL_LINEAR : GL_NEAREST);
        glSamplerParameteri(smp[k], GL_TEXTURE_MAG_FILTER, k == 0 ? GL_LINEAR : GL_NEAREST);
        glSamplerParameteri(smp[k], GL_TEXTURE_COMPARE_MODE, k == 0 ? GL_COMPARE_REF_TO_TEXTURE : GL_NONE);
        glSamplerParameteri(smp[k], GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    }
}

// One fragment per lookup (a row of `n` pixels) into an R32F target; `bind` sets uniforms and textures.
std::vector<float> run_row(GLuint prog, int n, const std::function<void()>& bind) {
    std::string why;
    skgl::Target target;
    REQUIRE(skgl::make_target(target, n, 1, {GL_R32F}, 0, why));
    GLuint vao = 0;
    glGenVertexArrays(1, &vao);
    glBindFramebuffer(GL_FRAMEBUFFER, target.fbo);
    glViewport(0, 0, n, 1);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glUseProgram(prog);
    bind();
    glBindVertexArray(vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    std::vector<float> out = skgl::read_color_float(target, 0, 1);
    CHECK(skgl::gl_error_string().empty());
    glDeleteVertexArrays(1, &vao);
    skgl::destroy_target(target);
    return out;
}

// The calls of both versions, written once: $SM / $DM are the sampler types, $L the layer argument.
const char* kKernelTemplate = R"(
layout(binding = 0) uniform $SM u_sm;
layout(binding = 1) uniform sampler2D u_pts;   // xyz = uvz
layout(binding = 2) uniform sampler2D u_grad;  // xy = dz_duv
layout(binding = 3) uniform $DM u_depth;
uniform float u_layer;
uniform int u_kernel;
uniform int u_r;
uniform int u_taps;
uniform float u_radius_uv;
uniform float u_angle;
uniform float u_light;
uniform float u_max_w;
layout(location = 0) out float o_value;
void main() {
    ivec2 i = ivec2(int(gl_FragCoord.x), 0);
    vec3 uvz = texelFetch(u_pts, i, 0).xyz;
    vec2 g = texelFetch(u_grad, i, 0).xy;
    if (u_kernel == 0) o_value = sk_pcf_box(u_sm, $Luvz, g, u_r);
    else if (u_kernel == 1) o_value = sk_pcf_tent(u_sm, $Luvz, g, u_r);
    else if (u_kernel == 2) o_value = sk_pcf_poisson(u_sm, $Luvz, g, u_radius_uv, u_taps, u_angle);
    else if (u_kernel == 3) o_value = sk_pcf_poisson_rotated(u_sm, $Luvz, g, u_radius_uv, u_taps);
    else if (u_kernel == 4) o_value = sk_pcf_hard(u_sm, $Luvz);
    else if (u_kernel == 5) o_value = sk_pcf_tap(u_sm, $Luvz, g, vec2(u_radius_uv, -0.5 * u_radius_uv));
    else if (u_kernel == 6)
        o_value = sk_pcss(u_depth, u_sm, $Luvz, g, u_light, 1.0, 10.0, u_taps, u_taps, u_angle, u_max_w);
    else if (u_kernel == 7)
        o_value = sk_pcss_directional(u_depth, u_sm, $Luvz, g, u_light, u_taps, u_taps, u_angle, u_max_w);
    else if (u_kernel == 8) o_value = sk_pcss_filter(u_sm, $Luvz, g, u_radius_uv, u_taps, u_angle);
    else if (u_kernel == 9) o_value = sk_pcss_blocker_window_depth(u_depth, $Luvz, g, u_radius_uv, u_taps, u_angle);
    else o_value = sk_pcss_blocker_window_depth(u_depth, $Luvz, u_radius_uv, u_taps, u_angle);
}
)";

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
    for (std::size_t p = s.find(from); p != std::string::npos; p = s.find(from, p + to.size())) s.replace(p, from.size(), to);
    return s;
}

GLuint kernel_program(bool array) {
    std::string why, log;
    const std::string pcf = sk::load_snippet("pcf", why), pcss = sk::load_snippet("pcss", why);
    REQUIRE(!pcf.empty());
    REQUIRE(!pcss.empty());
    std::string body = replace_all(kKernelTemplate, "$SM", array ? "sampler2DArrayShadow" : "sampler2DShadow");
    body = replace_all(body, "$DM", array ? "sampler2DArray" : "sampler2D");
    body = replace_all(body, "$L", array ? "u_layer, " : "");
    const GLuint prog = skgl::compile_program(
        {{GL_VERTEX_SHADER, sk::fullscreen_vertex_shader()},
         {GL_FRAGMENT_SHADER, std::string("#version 450 core\n") + pcf + pcss + body}},
        log);
    REQUIRE_MESSAGE(prog != 0, log);
    return prog;
}

struct KernelCase {
    const char* name;
    int kernel, r, taps;
    double radius_uv, angle, light, max_w;
};

// 128 x 128: left half PCSS's scene (a floor at 0.95, blockers at 0.6 and 0.3, a strip at the near
// plane), right half a random field (bottom) and a diagonal step edge 0.25 | 0.75 (top).
DepthTexture test_field() {
    DepthTexture t;
    t.w = t.h = 128;
    t.d.resize(128 * 128);
    std::mt19937 rng(4321);
    std::uniform_real_distribution<float> U(0.1f, 0.95f);
    for (int y = 0; y < 128; ++y)
        for (int x = 0; x < 128; ++x) {
            float d = 0.95f;
            if (x < 64) {
                if (x >= 10 && x < 35 && y >= 40 && y < 90) d = 0.6f;
                if (x >= 40 && x < 60 && y >= 20 && y < 60) d = 0.3f;
                if (x >= 30 && y >= 100 && y < 108) d = 0.0f;
            } else {
                d = y < 64 ? U(rng) : (2 * (x - 64) + (y - 64) < 90 ? 0.25f : 0.75f);
            }
            t.d[static_cast<std::size_t>(y * 128 + x)] = d;
        }
    return t;
}

// The CPU value of kernel case `kc` at lookup i (the same definitions the 2D kernels are tested with).
double cpu_value(const DepthTexture& t, const std::vector<glm::dvec2>& disk, const KernelCase& kc, glm::dvec3 uvz,
                 glm::dvec2 g, std::size_t i) {
    switch (kc.kernel) {
    case 0: return cpu_box(t, uvz, g, kc.r, false);
    case 1: return cpu_box(t, uvz, g, kc.r, true);
    case 2: return cpu_poisson(t, disk, uvz, g, kc.radius_uv, kc.taps, kc.angle);
    case 3: return cpu_poisson(t, disk, uvz, g, kc.radius_uv, kc.taps, 6.28318531 * double(ign(float(i) + 0.5f, 0.5f)));
    case 4: return cpu_tap(t, uvz, glm::dvec2(0), glm::dvec2(0));
    case 5: return cpu_tap(t, uvz, g, glm::dvec2(kc.radius_uv, -0.5 * kc.radius_uv));
    case 6: return cpu_pcss(t, disk, uvz, g, kc.light, 1.0, 10.0, kc.taps, kc.angle, kc.max_w);
    case 7: return cpu_pcss_directional(t, disk, uvz, g, kc.light, kc.taps, kc.angle, kc.max_w);
    case 8: return cpu_poisson(t, disk, uvz, g, 0.5 * kc.radius_uv, kc.taps, kc.angle);
    case 9: return cpu_blocker(t, disk, uvz, g, kc.radius_uv, kc.taps, kc.angle);
    default: return cpu_blocker(t, disk, uvz, glm::dvec2(0), kc.radius_uv, kc.taps, kc.angle);
    }
}

}  // namespace

TEST_CASE("pcf.glsl and pcss.glsl on a layer of a depth array equal the 2D kernels and the CPU emulation") {
    (void)gl_test_context();
    std::string why;
    const auto disk = parse_poisson(sk::load_snippet("pcf", why));
    REQUIRE(disk.size() == 64);
    const DepthTexture field = test_field();
    DepthTexture other = field;  // the other layers: the field mirrored and inverted
    for (int y = 0; y < 128; ++y)
        for (int x = 0; x < 128; ++x)
            other.d[static_cast<std::size_t>(y * 128 + x)] = 1.0f - field.d[static_cast<std::size_t>(y * 128 + (127 - x))];

    std::mt19937 rng(77);
    std::uniform_real_distribution<float> Uuv(0.04f, 0.96f), Uz(0.2f, 0.9f), Ug(-0.3f, 0.3f);
    const int M = 1024;
    std::vector<float> a(4 * M), b(4 * M, 0.f);
    for (int i = 0; i < M; ++i) {
        const float z = i % 4 == 0 ? 0.94f : (i % 4 == 1 ? 0.7f : Uz(rng));
        a[4 * i] = Uuv(rng), a[4 * i + 1] = Uuv(rng), a[4 * i + 2] = i % 37 == 0 ? 0.f : z, a[4 * i + 3] = 0.f;
        if (i % 2) b[4 * i] = Ug(rng), b[4 * i + 1] = Ug(rng);
    }
    const GLuint tp = rgba32f_row(a), tg = rgba32f_row(b);
    const GLuint prog2d = kernel_program(false), prog_arr = kernel_program(true);
    GLuint smp[2];
    make_samplers(smp);
    const GLuint map2d = depth_texture(field, 0, 0, nullptr);

    const KernelCase cases[] = {
        {"box r=1", 0, 1, 0, 0, 0, 0, 0},
        {"box r=3", 0, 3, 0, 0, 0, 0, 0},
        {"tent r=2", 1, 2, 0, 0, 0, 0, 0},
        {"poisson 16, 4 texels, angle 0.7", 2, 0, 16, 4.0 / 128, 0.7, 0, 0},
        {"poisson rotated 32, 3 texels", 3, 0, 32, 3.0 / 128, 0, 0, 0},
        {"hard", 4, 0, 0, 0, 0, 0, 0},
        {"one tap at an offset", 5, 0, 0, 2.5 / 128, 0, 0, 0},
        {"pcss light 0.2, 16 taps", 6, 0, 16, 0, 0.3, 0.2, 0.05},
        {"pcss light 1.0, clamped, 32 taps", 6, 0, 32, 0, 1.1, 1.0, 0.03},
        {"pcss_directional 0.05, 32 taps", 7, 0, 32, 0, 0.4, 0.05, 0.05},
        {"pcss_filter width 0.04, 24 taps", 8, 0, 24, 0.04, 0.2, 0, 0},
        {"blocker search with plane, 0.05", 9, 0, 32, 0.05, 0.5, 0, 0},
        {"blocker search, 0.05", 10, 0, 32, 0.05, 0.5, 0, 0},
    };
    const bool llvmpipe = gl_test_context().llvmpipe;
    for (const KernelCase& kc : cases) {
        auto bind = [&](GLuint prog, GLenum target, GLuint map, float layer) {
            return [=]() {
                glUniform1f(glGetUniformLocation(prog, "u_layer"), layer);
                glUniform1i(glGetUniformLocation(prog, "u_kernel"), kc.kernel);
                glUniform1i(glGetUniformLocation(prog, "u_r"), kc.r);
                glUniform1i(glGetUniformLocation(prog, "u_taps"), kc.taps);
                glUniform1f(glGetUniformLocation(prog, "u_radius_uv"), float(kc.radius_uv));
                glUniform1f(glGetUniformLocation(prog, "u_angle"), float(kc.angle));
                glUniform1f(glGetUniformLocation(prog, "u_light"), float(kc.light));
                glUniform1f(glGetUniformLocation(prog, "u_max_w"), float(kc.max_w));
                const GLuint units[4] = {map, tp, tg, map};
                for (GLuint u = 0; u < 4; ++u) {
                    glActiveTexture(GL_TEXTURE0 + u);
                    glBindTexture(u == 0 || u == 3 ? target : GL_TEXTURE_2D, units[u]);
                }
                glBindSampler(0, smp[0]);
                glBindSampler(3, smp[1]);
            };
        };
        const std::vector<float> v2d = run_row(prog2d, M, bind(prog2d, GL_TEXTURE_2D, map2d, 0.f));
        // against the CPU: pcf kernels to float rounding; PCSS and the blocker search may flip a tap whose
        // depth ties the receiver within rounding (0.5% of lookups, as the 2D test allows)
        const bool pcss = kc.kernel >= 6;
        std::size_t off_cpu = 0, partial = 0;
        double max_cpu = 0;
        for (std::size_t i = 0; i < std::size_t(M); ++i) {
            const glm::dvec3 uvz(a[4 * i], a[4 * i + 1], a[4 * i + 2]);
            const double e = std::abs(double(v2d[i]) - cpu_value(field, disk, kc, uvz, glm::dvec2(b[4 * i], b[4 * i + 1]), i));
            max_cpu = std::max(max_cpu, e);
            if (e > 1e-4) ++off_cpu;
            if (v2d[i] > 0.01f && v2d[i] < 0.99f) ++partial;
        }
        if (pcss) CHECK_MESSAGE(off_cpu <= std::size_t(M) / 200, kc.name);
        else CHECK_MESSAGE(max_cpu < (llvmpipe ? 1e-5 : 5e-3), kc.name);
        CHECK_MESSAGE(partial > 20, kc.name);  // the lookups exercise partial values (blocker depths too)

        for (int layer : {0, 1, 3}) {
            const GLuint arr = depth_texture(field, 4, layer, &other);
            const std::vector<float> va = run_row(prog_arr, M, bind(prog_arr, GL_TEXTURE_2D_ARRAY, arr, float(layer)));
            const std::vector<float> wrong =
                run_row(prog_arr, M, bind(prog_arr, GL_TEXTURE_2D_ARRAY, arr, float((layer + 1) % 4)));
            glDeleteTextures(1, &arr);
            double max_diff = 0;
            std::size_t identical = 0, wrong_differs = 0;
            for (std::size_t i = 0; i < std::size_t(M); ++i) {
                max_diff = std::max(max_diff, std::abs(double(va[i]) - double(v2d[i])));
                identical += va[i] == v2d[i] ? 1 : 0;
                wrong_differs += std::abs(wrong[i] - v2d[i]) > 1e-3f ? 1 : 0;
            }
            MESSAGE(std::string(kc.name) << ", layer " << layer << ": max |array - 2D| = " << max_diff << ", " << identical << " of " << M
                            << " bit-identical; |2D - CPU| max " << max_cpu << " (" << off_cpu << " > 1e-4); a wrong layer differs at "
                            << wrong_differs);
            CHECK(max_diff <= 1e-6);
            CHECK(wrong_differs > std::size_t(M) / 10);  // the comparison sees the layer
        }
    }
    glBindSampler(0, 0);
    glBindSampler(3, 0);
    glDeleteSamplers(2, smp);
    const GLuint texs[3] = {map2d, tp, tg};
    glDeleteTextures(3, texs);
    glDeleteProgram(prog2d);
    glDeleteProgram(prog_arr);
}

// ------------------------------------------------------------------------------ filtered cascades

namespace {

const char* kCascadeBody = R"(
layout(binding = 0) uniform sampler2DArrayShadow u_maps;
layout(binding = 1) uniform sampler2D u_pts;  // xyz = world position, w = view depth
uniform mat4 u_vp[4];
uniform vec4 u_near;
uniform vec4 u_far;
uniform float u_band;
uniform int u_kernel;
uniform int u_r;
uniform int u_taps;
uniform float u_angle;
layout(location = 0) out float o_value;
void main() {
    vec4 p = texelFetch(u_pts, ivec2(int(gl_FragCoord.x), 0), 0);
    if (u_kernel < 0)
        o_value = sk_cascade_shadow(u_maps, u_vp, u_near, u_far, 2, p.xyz, p.w, u_band, 0.0, false);
    else
        o_value = sk_cascade_shadow_filtered(u_maps, u_vp, u_near, u_far, 2, p.xyz, p.w, u_band, 0.0, false, u_kernel,
                                             u_r, u_taps, u_angle);
}
)";

}  // namespace

TEST_CASE("sk_cascade_shadow_filtered: a pcf.glsl kernel in each cascade's layer, blended over the band") {
    (void)gl_test_context();
    std::string why;
    const std::string pcf = sk::load_snippet("pcf", why), cascades = sk::load_snippet("cascades", why);
    REQUIRE(!cascades.empty());
    const auto disk = parse_poisson(pcf);
    REQUIRE(disk.size() == 64);
    // two 64 x 64 cascades with different depths: random fields split by different step edges
    DepthTexture layer[2];
    std::mt19937 rng(555);
    std::uniform_real_distribution<float> U(0.1f, 0.95f);
    for (int l = 0; l < 2; ++l) {
        layer[l].w = layer[l].h = 64;
        layer[l].d.resize(64 * 64);
        for (int y = 0; y < 64; ++y)
            for (int x = 0; x < 64; ++x)
                layer[l].d[static_cast<std::size_t>(y * 64 + x)] =
                    (l == 0 ? x < 32 : y < 32) ? U(rng) : ((l == 0 ? 2 * x + y : x + 3 * y) < 100 ? 0.3f : 0.8f);
    }
    GLuint maps = 0;
    glGenTextures(1, &maps);
    glBindTexture(GL_TEXTURE_2D_ARRAY, maps);
    glTexStorage3D(GL_TEXTURE_2D_ARRAY, 1, GL_DEPTH_COMPONENT32F, 64, 64, 2);
    for (int l = 0; l < 2; ++l)
        glTexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, 0, 0, l, 64, 64, 1, GL_DEPTH_COMPONENT, GL_FLOAT, layer[l].d.data());
    GLuint smp[2];
    make_samplers(smp);

    // Cascade 0's matrix is the identity (uv = world xy / 2 + 1/2), cascade 1's scales x and y by 0.8:
    // a point reads different texels in the two layers. Splits: [0, 10] and [10, 20], band 0.3.
    const glm::mat4 vp[4] = {glm::mat4(1.f), glm::scale(glm::mat4(1.f), glm::vec3(0.8f, 0.8f, 1.f)), glm::mat4(1.f),
                             glm::mat4(1.f)};
    const float split_near[4] = {0.f, 10.f, 20.f, 30.f}, split_far[4] = {10.f, 20.f, 30.f, 40.f};
    const double band = 0.3;
    const int M = 1024;
    std::vector<float> pts(4 * M);
    std::uniform_real_distribution<float> Uxy(-0.95f, 0.95f), Uz(-0.6f, 0.8f), Ud(0.f, 22.f);
    for (int i = 0; i < M; ++i) {
        pts[4 * i] = Uxy(rng), pts[4 * i + 1] = Uxy(rng), pts[4 * i + 2] = Uz(rng);
        // a quarter inside the band of cascade 0 (view depth 7..10), the rest anywhere to 22 (beyond 20: lit)
        pts[4 * i + 3] = i % 4 == 0 ? 7.f + 3.f * float(i % 97) / 97.f : Ud(rng);
    }
    const GLuint tp = rgba32f_row(pts);
    std::string log;
    const GLuint prog = skgl::compile_program(
        {{GL_VERTEX_SHADER, sk::fullscreen_vertex_shader()},
         {GL_FRAGMENT_SHADER, std::string("#version 450 core\n") + pcf + cascades + kCascadeBody}},
        log);
    REQUIRE_MESSAGE(prog != 0, log);

    struct Case {
        const char* name;
        int kernel, r, taps;
        double angle;
    };
    // -1: sk_cascade_shadow (hardware 2x2), the reference for the hard kernel
    const Case cases[] = {{"sk_cascade_shadow", -1, 0, 0, 0},        {"hard", 0, 0, 0, 0},
                          {"box r=1", 1, 1, 0, 0},                   {"tent r=2", 2, 2, 0, 0},
                          {"poisson 16, 3 texels, angle 0.4", 3, 3, 16, 0.4}};
    std::vector<float> unfiltered;
    for (const Case& c : cases) {
        const std::vector<float> gpu = run_row(prog, M, [&]() {
            glUniformMatrix4fv(glGetUniformLocation(prog, "u_vp"), 4, GL_FALSE, glm::value_ptr(vp[0]));
            glUniform4fv(glGetUniformLocation(prog, "u_near"), 1, split_near);
            glUniform4fv(glGetUniformLocation(prog, "u_far"), 1, split_far);
            glUniform1f(glGetUniformLocation(prog, "u_band"), float(band));
            glUniform1i(glGetUniformLocation(prog, "u_kernel"), c.kernel);
            glUniform1i(glGetUniformLocation(prog, "u_r"), c.r);
            glUniform1i(glGetUniformLocation(prog, "u_taps"), c.taps);
            glUniform1f(glGetUniformLocation(prog, "u_angle"), float(c.angle));
            glActiveTexture(GL_TEXTURE0);
            glBindTexture(GL_TEXTURE_2D_ARRAY, maps);
            glBindSampler(0, smp[0]);
            glActiveTexture(GL_TEXTURE1);
            glBindTexture(GL_TEXTURE_2D, tp);
        });
        glBindSampler(0, 0);
        if (c.kernel < 0) {
            unfiltered = gpu;
            continue;
        }
        std::size_t off = 0, blended = 0, beyond = 0;
        double max_err = 0;
        for (std::size_t i = 0; i < std::size_t(M); ++i) {
            const glm::dvec3 p(pts[4 * i], pts[4 * i + 1], pts[4 * i + 2]);
            const double d = pts[4 * i + 3];
            auto kernel = [&](int l) {
                const double s = l == 0 ? 1.0 : 0.8;
                const glm::dvec3 uvz(s * p.x * 0.5 + 0.5, s * p.y * 0.5 + 0.5, p.z * 0.5 + 0.5);
                if (uvz.x < 0 || uvz.y < 0 || uvz.x > 1 || uvz.y > 1) return 1.0;
                const DepthTexture& t = layer[l];
                switch (c.kernel) {
                case 1: return cpu_box(t, uvz, glm::dvec2(0), c.r, false);
                case 2: return cpu_box(t, uvz, glm::dvec2(0), c.r, true);
                case 3: return cpu_poisson(t, disk, uvz, glm::dvec2(0), c.r / 64.0, c.taps, c.angle);
                default: return cpu_tap(t, uvz, glm::dvec2(0), glm::dvec2(0));
                }
            };
            // the cascade whose far split holds d, the next one's weight over the last 30% of [near, far]
            double cpu = 1.0;
            const int first = d <= 10.0 ? 0 : (d <= 20.0 ? 1 : -1);
            if (first >= 0) {
                cpu = kernel(first);
                const double start = split_far[first] - band * (split_far[first] - split_near[first]);
                const double w = std::clamp((d - start) / (split_far[first] - start), 0.0, 1.0);
                if (first == 0 && w > 0) {
                    cpu = (1 - w) * cpu + w * kernel(1);
                    ++blended;
                }
            } else {
                ++beyond;
                CHECK(gpu[i] == 1.0f);
            }
            const double e = std::abs(double(gpu[i]) - cpu);
            max_err = std::max(max_err, e);
            if (e > 1e-4) ++off;
        }
        std::size_t same_as_unfiltered = 0;
        for (std::size_t i = 0; i < std::size_t(M); ++i) same_as_unfiltered += gpu[i] == unfiltered[i] ? 1 : 0;
        MESSAGE(std::string(c.name) << ": max |GPU - CPU| " << max_err << ", " << off << " of " << M << " > 1e-4; " << blended
                       << " in the band, " << beyond << " beyond the last split; equal to sk_cascade_shadow at "
                       << same_as_unfiltered);
        CHECK(blended > 200);
        CHECK(beyond > 50);
        CHECK(off <= std::size_t(M) / 200);  // a tap whose depth ties the receiver within rounding may flip
        if (c.kernel == 0) CHECK(same_as_unfiltered == std::size_t(M));  // the hard kernel is sk_cascade_shadow
        else CHECK(same_as_unfiltered < std::size_t(M) * 9 / 10);        // a wider kernel is not
    }
    glDeleteSamplers(2, smp);
    const GLuint texs[2] = {maps, tp};
    glDeleteTextures(2, texs);
    glDeleteProgram(prog);
}

// ------------------------------------------------------------------------------ the sample's setting

// samples/cascaded_shadow_maps' pcf_radius (through the report's wrapper, as shadowkit-report runs it)
// on `outdoor` against the Embree reference: a tent of radius 2 softens the edges (more pixels strictly
// between 0 and 1); thresholded at 0.5 it keeps the hard shadow's classification away from edges.
TEST_CASE("the cascaded sample's pcf_radius: a tent in each cascade's layer, softer, same classification") {
    (void)gl_test_context();
    sk::Scene scene;
    REQUIRE(sk::make_builtin_scene("outdoor", scene));
    sk::SceneGpu gpu;
    sk::GBuffer g;
    std::string why;
    REQUIRE_MESSAGE(sk::prepare_scene_gpu(scene, 200, 150, gpu, g, why), why);
    sk::ReferenceOptions opt;
    opt.strata = 1;  // a sun: one ray per pixel
    opt.progress = false;
    sk::Reference ref;
    REQUIRE_MESSAGE(sk::compute_reference(scene, g, opt, ref, why), why);
    auto techniques = sk::make_techniques();
    auto run = [&](const std::string& settings) {
        for (auto& t : techniques)
            if (t->name() == "cascades") {
                sk::RunContext ctx{scene, gpu, 1, 0, nullptr};
                return t->run(ctx, sk::ParamSet::parse_named(settings));
            }
        return sk::RunResult::failure("no technique cascades");
    };
    for (const char* bias : {"bias=auto", "bias=polygon_offset"}) {
        const sk::RunResult r0 = run(std::string(bias) + " size=512 pcf_radius=0");
        const sk::RunResult r2 = run(std::string(bias) + " size=512 pcf_radius=2");
        REQUIRE_MESSAGE(r0.ok, r0.error);
        REQUIRE_MESSAGE(r2.ok, r2.error);
        auto partial = [](const std::vector<float>& v) {
            std::size_t n = 0;
            for (float x : v) n += x > 0.02f && x < 0.98f ? 1 : 0;
            return n;
        };
        const sk::Metrics m0 = sk::compute_metrics(g, ref, r0.visibility, true);
        const sk::Metrics m2 = sk::compute_metrics(g, ref, r2.visibility, true);
        MESSAGE(std::string(bias) << ": RMSE " << m0.rmse << " (2x2) -> " << m2.rmse << " (tent r=2); misclassified "
                                  << m0.misclassified << " -> " << m2.misclassified << "; partial pixels "
                                  << partial(r0.visibility) << " -> " << partial(r2.visibility));
        CHECK(partial(r2.visibility) > partial(r0.visibility) * 3 / 2);
        CHECK(m2.misclassified <= m0.misclassified + 0.005);
    }
}
