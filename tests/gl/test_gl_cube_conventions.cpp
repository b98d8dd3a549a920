// The two cube conventions (issue 25 item 3), measured on the GL driver: a point light at the origin
// in a 16 x 16 x 16 room with a sphere in it, two cube maps written texel by texel from the closed
// form (the distance along each texel's center direction to the nearest surface): one storing
// distance / range (omni_shadow.glsl's convention), one storing the face's window depth of the
// major-axis distance (six perspective faces, shadow_map.glsl's). Receivers on the walls, classified
// against the exact ray test (away from the sphere's shadow edge). Each lookup on its own cube is
// right (>= 99.5%); each on the other's cube compiles and is wrong: how wrong is what
// docs/omni_shadow.md and docs/shadow_map.md quote. The names (sk_cube_visibility_distance,
// sk_cube_visibility_hardware_depth) are what keeps them apart.
#include <doctest/doctest.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "../cube_auto_scene.hpp"
#include "gl_test.hpp"
#include "techniques.hpp"

namespace {

constexpr double kRoom = 8.0;    // walls at +-8
constexpr double kRange = 20.0;  // distance storage: distance / range
constexpr double kNear = 0.1, kFar = 20.0;  // the perspective faces' planes
const glm::dvec3 kSphereCenter(3.0, 1.0, 2.0);
constexpr double kSphereRadius = 1.5;

// Distance from the light (origin) along unit direction d to the nearest surface.
double hit_distance(const glm::dvec3& d) {
    const double wall = kRoom / std::max({std::fabs(d.x), std::fabs(d.y), std::fabs(d.z)});
    const double b = glm::dot(d, kSphereCenter), c = glm::dot(kSphereCenter, kSphereCenter) - kSphereRadius * kSphereRadius;
    const double disc = b * b - c;
    if (disc >= 0.0) {
        const double t = b - std::sqrt(disc);
        if (t > 0.0 && t < wall) return t;
    }
    return wall;
}

// The direction through texel (i, j) of cube face f (GL 4.6 table 8.19 inverted: s = (sc / |ma| + 1) / 2,
// t = (tc / |ma| + 1) / 2; row j holds t in [j / n, (j + 1) / n)).
glm::dvec3 face_direction(int f, int i, int j, int n) {
    const double u = 2.0 * (i + 0.5) / n - 1.0, v = 2.0 * (j + 0.5) / n - 1.0;
    switch (f) {
    case 0: return glm::normalize(glm::dvec3(1, -v, -u));
    case 1: return glm::normalize(glm::dvec3(-1, -v, u));
    case 2: return glm::normalize(glm::dvec3(u, 1, v));
    case 3: return glm::normalize(glm::dvec3(u, -1, -v));
    case 4: return glm::normalize(glm::dvec3(u, -v, 1));
    default: return glm::normalize(glm::dvec3(-u, -v, -1));
    }
}

// distance / range, or the perspective face's window depth of the major-axis distance
double stored_value(const glm::dvec3& d, bool hardware_depth) {
    const double t = hit_distance(d);
    if (!hardware_depth) return t / kRange;
    const double major = t * std::max({std::fabs(d.x), std::fabs(d.y), std::fabs(d.z)});
    const double ndc = (kFar + kNear) / (kFar - kNear) - 2.0 * kFar * kNear / ((kFar - kNear) * major);
    return ndc * 0.5 + 0.5;
}

GLuint make_cube(int n, bool hardware_depth) {
    GLuint t = 0;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_CUBE_MAP, t);
    glTexStorage2D(GL_TEXTURE_CUBE_MAP, 1, GL_DEPTH_COMPONENT32F, n, n);
    std::vector<float> face(static_cast<std::size_t>(n * n));
    for (int f = 0; f < 6; ++f) {
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i)
                face[static_cast<std::size_t>(j * n + i)] = float(stored_value(face_direction(f, i, j, n), hardware_depth));
        glTexSubImage2D(GLenum(GL_TEXTURE_CUBE_MAP_POSITIVE_X + f), 0, 0, 0, n, n, GL_DEPTH_COMPONENT, GL_FLOAT, face.data());
    }
    glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    return t;
}

const char* kBody = R"(
layout(binding = 0) uniform samplerCubeShadow u_cube;
layout(binding = 1) uniform sampler2D u_pts;  // xyz = world position on a wall
uniform bool u_distance_lookup;
layout(location = 0) out float o_value;
void main() {
    vec3 p = texelFetch(u_pts, ivec2(int(gl_FragCoord.x), 0), 0).xyz;
    vec4 light = vec4(0.0, 0.0, 0.0, 1.0);
    o_value = u_distance_lookup ? sk_cube_visibility_distance(u_cube, light, p, 20.0, 0.05)
                                : sk_cube_visibility_hardware_depth(u_cube, light, p, 0.1, 20.0, 1e-4);
}
)";

}  // namespace

TEST_CASE("cube conventions: each lookup is right on its own cube and wrong on the other's") {
    (void)gl_test_context();
    std::string why, log;
    const std::string shadow_map = sk::load_snippet("shadow_map", why), omni = sk::load_snippet("omni_shadow", why);
    REQUIRE(!shadow_map.empty());
    REQUIRE(!omni.empty());
    const GLuint prog = skgl::compile_program(
        {{GL_VERTEX_SHADER, sk::fullscreen_vertex_shader()},
         {GL_FRAGMENT_SHADER, "#version 450 core\n" + shadow_map + omni + kBody}},
        log);
    REQUIRE_MESSAGE(prog != 0, log);
    glEnable(GL_TEXTURE_CUBE_MAP_SEAMLESS);
    const int n = 512;
    const GLuint cube[2] = {make_cube(n, false), make_cube(n, true)};  // [0] distance / range, [1] hardware depth

    // receivers on the walls, more of them toward the sphere (its shadow), and their exact visibility
    std::mt19937 rng(2503);
    std::normal_distribution<double> g(0.0, 1.0);
    const int M = 4096;
    std::vector<float> pts(4 * M);
    std::vector<int> truth(M);
    std::vector<bool> use(M);
    const double sphere_angle = std::asin(kSphereRadius / glm::length(kSphereCenter));
    const double margin = 3.0 * 2.0 / n;  // three texels' angle: away from the shadow edge
    int lit = 0, used = 0;
    for (int i = 0; i < M; ++i) {
        glm::dvec3 d;
        do d = glm::dvec3(g(rng), g(rng), g(rng)) + (i % 2 ? glm::normalize(kSphereCenter) * 4.0 : glm::dvec3(0.0));
        while (glm::length(d) < 1e-3);
        d = glm::normalize(d);
        const glm::dvec3 p = d * (kRoom / std::max({std::fabs(d.x), std::fabs(d.y), std::fabs(d.z)}));
        pts[4 * i] = float(p.x), pts[4 * i + 1] = float(p.y), pts[4 * i + 2] = float(p.z), pts[4 * i + 3] = 0.f;
        const double angle = std::acos(std::clamp(glm::dot(d, glm::normalize(kSphereCenter)), -1.0, 1.0));
        truth[i] = hit_distance(d) < glm::length(p) - 1e-9 ? 0 : 1;
        use[i] = std::fabs(angle - sphere_angle) > margin;
        if (use[i]) {
            ++used;
            lit += truth[i];
        }
    }
    REQUIRE(used > M * 8 / 10);
    REQUIRE(lit > used / 4);
    REQUIRE(lit < used * 3 / 4);  // both classes well represented

    GLuint tp = 0;
    glGenTextures(1, &tp);
    glBindTexture(GL_TEXTURE_2D, tp);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA32F, M, 1);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, M, 1, GL_RGBA, GL_FLOAT, pts.data());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    skgl::Target target;
    REQUIRE(skgl::make_target(target, M, 1, {GL_R32F}, 0, why));
    GLuint vao = 0;
    glGenVertexArrays(1, &vao);
    double wrong[2][2] = {{0, 0}, {0, 0}};  // [lookup: 0 distance, 1 hardware depth][cube]
    for (int lookup = 0; lookup < 2; ++lookup)
        for (int c = 0; c < 2; ++c) {
            glBindFramebuffer(GL_FRAMEBUFFER, target.fbo);
            glViewport(0, 0, M, 1);
            glDisable(GL_DEPTH_TEST);
            glUseProgram(prog);
            glUniform1i(glGetUniformLocation(prog, "u_distance_lookup"), lookup == 0 ? 1 : 0);
            glActiveTexture(GL_TEXTURE0);
            glBindTexture(GL_TEXTURE_CUBE_MAP, cube[c]);
            glActiveTexture(GL_TEXTURE1);
            glBindTexture(GL_TEXTURE_2D, tp);
            glBindVertexArray(vao);
            glDrawArrays(GL_TRIANGLES, 0, 3);
            const std::vector<float> v = skgl::read_color_float(target, 0, 1);
            REQUIRE(skgl::gl_error_string().empty());
            int w = 0;
            for (int i = 0; i < M; ++i)
                if (use[i] && (v[static_cast<std::size_t>(i)] >= 0.5f ? 1 : 0) != truth[i]) ++w;
            wrong[lookup][c] = double(w) / used;
        }
    MESSAGE("misclassified receivers (" << used << ", " << lit << " lit): distance lookup on the distance cube "
                                        << 100 * wrong[0][0] << "%, on the hardware-depth cube " << 100 * wrong[0][1]
                                        << "%; hardware-depth lookup on the hardware-depth cube " << 100 * wrong[1][1]
                                        << "%, on the distance cube " << 100 * wrong[1][0] << "%");
    CHECK(wrong[0][0] <= 0.005);  // each on its own cube: right
    CHECK(wrong[1][1] <= 0.005);
    // Each on the other's cube compiles and loses a whole class of receivers. Here, in closed form: a
    // wall point's major-axis distance is 8, so the hardware-depth reference is the window depth
    // 0.5 (1 + (f + n) / (f - n) - 2 f n / ((f - n) 8)) = 0.9925, above every stored distance / range
    // (<= 8 sqrt(3) / 20 = 0.69): every receiver reads as shadowed, every lit one is wrong. The
    // distance reference (|p| - 0.05) / 20 <= 0.69 is below every stored window depth (the nearest
    // surface, the sphere at >= 2.24 from the light, major axis >= 1.29: >= 0.927): every receiver
    // reads as lit, every shadowed one is wrong.
    CHECK(wrong[1][0] == doctest::Approx(double(lit) / used));
    CHECK(wrong[0][1] == doctest::Approx(double(used - lit) / used));
    glDeleteVertexArrays(1, &vao);
    skgl::destroy_target(target);
    glDeleteTextures(2, cube);
    glDeleteTextures(1, &tp);
    glDeleteProgram(prog);
}

// ---- the automatic bias on a cube of hardware depth (issue #23: the plain shadow map's point light)
namespace {

using cube_auto::kLight;

// The closed-form cube (tests/cube_auto_scene.hpp, shared with the Vulkan runs).
GLuint make_offset_cube(int n) {
    GLuint t = 0;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_CUBE_MAP, t);
    glTexStorage2D(GL_TEXTURE_CUBE_MAP, 1, GL_DEPTH_COMPONENT32F, n, n);
    const std::vector<float> faces = cube_auto::cube_faces(n);
    for (int f = 0; f < 6; ++f)
        glTexSubImage2D(GLenum(GL_TEXTURE_CUBE_MAP_POSITIVE_X + f), 0, 0, 0, n, n, GL_DEPTH_COMPONENT, GL_FLOAT,
                        faces.data() + static_cast<std::size_t>(f * n * n));
    glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    return t;
}

const char* kAutoBody = R"(
layout(binding = 0) uniform samplerCubeShadow u_cube;
layout(binding = 1) uniform sampler2D u_pts;  // xyz = world position
layout(binding = 2) uniform sampler2D u_nrm;  // xyz = its geometric normal
uniform int u_mode;                           // 0 automatic bias, 1 constant window bias u_bias
uniform float u_bias;
uniform vec3 u_light;
layout(location = 0) out float o_value;
void main() {
    vec3 p = texelFetch(u_pts, ivec2(int(gl_FragCoord.x), 0), 0).xyz;
    vec3 n = texelFetch(u_nrm, ivec2(int(gl_FragCoord.x), 0), 0).xyz;
    vec4 light = vec4(u_light, 1.0);
    o_value = u_mode == 0 ? sk_cube_visibility_hardware_depth_auto(u_cube, light, p, n, 0.1, 20.0, 0.0)
                          : sk_cube_visibility_hardware_depth(u_cube, light, p, 0.1, 20.0, u_bias);
}
)";

}  // namespace

TEST_CASE("cube of hardware depth, automatic bias: no acne on walls or the sphere, the seams included, nothing to tune") {
    // A point light off the center of the 16-unit room (the faces' seams cross the walls), the cube
    // written texel by texel from the closed form (each texel the face's window depth of the nearest
    // surface along its center direction). Receivers: wall points (inward normals) and sphere points
    // (outward normals), classified by the exact ray test; scored away from the sphere's shadow edge
    // and terminator and from the room's edges (a concave crease: its other wall is within the 2x2
    // filter's reach). The automatic lookup must leave no lit receiver shadowed (acne) and misclassify
    // at most 0.5%; a constant bias small enough for the sphere's contact is shown to acne at grazing wall
    // points, and one large enough for them to leak at the contact, as the comparison.
    (void)gl_test_context();
    std::string why, log;
    const std::string shadow_map = sk::load_snippet("shadow_map", why);
    REQUIRE(!shadow_map.empty());
    const GLuint prog = skgl::compile_program(
        {{GL_VERTEX_SHADER, sk::fullscreen_vertex_shader()}, {GL_FRAGMENT_SHADER, "#version 450 core\n" + shadow_map + kAutoBody}}, log);
    REQUIRE_MESSAGE(prog != 0, log);
    glEnable(GL_TEXTURE_CUBE_MAP_SEAMLESS);
    const int n = 256;
    const GLuint cube = make_offset_cube(n);
    const int M = 8192;
    const cube_auto::Receivers rc = cube_auto::make_receivers(M, n);
    const std::vector<float>& pts = rc.pts;
    const std::vector<float>& nrm = rc.nrm;
    const std::vector<int>& truth = rc.truth;
    const std::vector<int>& kind = rc.kind;
    const std::vector<bool>& use = rc.use;
    const int used = rc.used, lit = rc.lit, seam = rc.seam;
    REQUIRE(used > M / 2);
    REQUIRE(seam > 500);
    auto upload = [&](const std::vector<float>& data) {
        GLuint tx = 0;
        glGenTextures(1, &tx);
        glBindTexture(GL_TEXTURE_2D, tx);
        glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA32F, M, 1);
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, M, 1, GL_RGBA, GL_FLOAT, data.data());
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        return tx;
    };
    const GLuint tp = upload(pts), tn = upload(nrm);
    skgl::Target target;
    REQUIRE(skgl::make_target(target, M, 1, {GL_R32F}, 0, why));
    GLuint vao = 0;
    glGenVertexArrays(1, &vao);
    struct Score {
        int acne = 0, leak = 0, wrong = 0, acne_wall = 0, acne_sphere = 0;
    };
    auto run = [&](int mode, float bias, GLenum filter) {
        glTextureParameteri(cube, GL_TEXTURE_MIN_FILTER, static_cast<GLint>(filter));
        glTextureParameteri(cube, GL_TEXTURE_MAG_FILTER, static_cast<GLint>(filter));
        glBindFramebuffer(GL_FRAMEBUFFER, target.fbo);
        glViewport(0, 0, M, 1);
        glDisable(GL_DEPTH_TEST);
        glUseProgram(prog);
        glUniform1i(glGetUniformLocation(prog, "u_mode"), mode);
        glUniform1f(glGetUniformLocation(prog, "u_bias"), bias);
        glUniform3f(glGetUniformLocation(prog, "u_light"), float(kLight.x), float(kLight.y), float(kLight.z));
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(GL_TEXTURE_CUBE_MAP, cube);
        glActiveTexture(GL_TEXTURE1);
        glBindTexture(GL_TEXTURE_2D, tp);
        glActiveTexture(GL_TEXTURE2);
        glBindTexture(GL_TEXTURE_2D, tn);
        glBindVertexArray(vao);
        glDrawArrays(GL_TRIANGLES, 0, 3);
        const std::vector<float> v = skgl::read_color_float(target, 0, 1);
        REQUIRE(skgl::gl_error_string().empty());
        Score s;
        for (int i = 0; i < M; ++i) {
            if (!use[i]) continue;
            const float x = v[static_cast<std::size_t>(i)];
            REQUIRE(std::isfinite(x));
            if (truth[i] == 1 && x < 0.5f) {
                ++s.acne;
                ++(kind[i] ? s.acne_sphere : s.acne_wall);
            }
            if (truth[i] == 0 && x > 0.5f) ++s.leak;
        }
        s.wrong = s.acne + s.leak;
        return s;
    };
    // the automatic lookup with GL_NEAREST (what the sample binds: its taps are texel centres, past a
    // face's edge the neighbour's) and with GL_LINEAR (each tap then a hardware 2x2 of its own)
    const Score a = run(0, 0.0f, GL_NEAREST), al = run(0, 0.0f, GL_LINEAR), small = run(1, 2e-6f, GL_LINEAR),
                large = run(1, 2e-4f, GL_LINEAR);
    MESSAGE(used << " receivers (" << lit << " lit, " << seam << " within two texels of a face seam): automatic bias acne "
                 << a.acne << " (walls " << a.acne_wall << ", sphere " << a.acne_sphere << "), leak " << a.leak << " (GL_LINEAR: acne "
                 << al.acne << ", leak " << al.leak << ")"
                 << "; constant window bias 2e-6: acne " << small.acne << " leak " << small.leak << "; 2e-4: acne " << large.acne
                 << " leak " << large.leak);
    CHECK(a.acne == 0);
    CHECK(al.acne == 0);
    CHECK(double(a.wrong) / used <= 0.005);
    CHECK(double(al.wrong) / used <= 0.005);
    CHECK(small.acne > 0);  // the comparison: a small constant acnes at grazing walls (a larger one is the tuning this removes)
    glDeleteVertexArrays(1, &vao);
    skgl::destroy_target(target);
    glDeleteTextures(1, &cube);
    GLuint tx[2] = {tp, tn};
    glDeleteTextures(2, tx);
    glDeleteProgram(prog);
}
