// Smoothies on the GL driver (llvmpipe here; (c) and (d) run the Smoothies class of samples/smoothies/
// through the report's wrapper, its settings by name), every check against an independent CPU prediction:
// (a) the three passes of glsl/smoothie.glsl (linear map, GL_MIN smoothie buffer, final lookup)
//     on a square card over a floor give, at every texel, the visibility predicted on the CPU from
//     the card's closed-form light-NDC distance and smoothie.hpp's eq. 1 remap / falloff / tap rule
//     (both variants: remap in the final pass, and the paper's remap in the smoothie pass);
// (b) t = 0 (no smoothie geometry) is bit-identical to a hard 2x2 lookup written independently;
// (c) Chan & Durand Fig. 9: a box casting onto a box and the floor; the penumbra widths measured on
//     the rendered V image (iso-lines V = 0.05 / 0.95, world units from the G-buffer) follow
//     t (r - b) / s, so their ratio is (r1 - b) : (r2 - b);
// (d) `contact` against the Embree area-light reference: the umbra never shrinks (V_t <= V_0), the
//     t mapped from the light size loses to the hard map in the penumbra by the factor a 1D model of
//     outward-only penumbrae predicts, and an eighth of it wins only by a few per cent.
#include <doctest/doctest.h>

#include <shadowkit/smoothie.hpp>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "../smoothie_reference.hpp"
#include "gl_test.hpp"
#include "metrics.hpp"
#include "reference.hpp"
#include "scene.hpp"
#include "techniques.hpp"

namespace {

const std::string kH = "#version 450 core\n";

std::string snippet() {
    bool ok = false;
    std::string s = skgl::read_text_file(std::string(SHADOWKIT_GLSL_DIR) + "/smoothie.glsl", &ok);
    REQUIRE_MESSAGE(ok, "cannot read glsl/smoothie.glsl");
    return s;
}

// Pass 1: linear depth.
const char* kDepthVS = R"(
layout(location = 0) in vec3 a_p;
uniform mat4 u_vp;
out vec3 v_world;
void main() { v_world = a_p; gl_Position = u_vp * vec4(a_p, 1.0); }
)";
const char* kDepthFS = R"(
in vec3 v_world;
uniform mat4 u_view;
out float o_depth;
void main() { o_depth = sk_smoothie_linear_depth(u_view, v_world); }
)";
// Pass 2: smoothie buffer (SmoothieVertex layout), optional remap in the pass (paper, Fig. 11).
const char* kSmoothieVS = R"(
layout(location = 0) in vec3 a_position;
layout(location = 1) in float a_alpha;
layout(location = 2) in vec3 a_silhouette;
layout(location = 3) in float a_inv_t;
layout(location = 5) in float a_corner;
uniform mat4 u_vp;
uniform mat4 u_view;
noperspective out float v_alpha;
smooth out float v_depth;
flat out vec2 v_sil;
flat out float v_inv_t;
flat out float v_corner;
void main() {
    vec4 clip;
    sk_smoothie_vertex(u_vp, u_view, a_position, a_silhouette, clip, v_depth, v_sil);
    gl_Position = clip;
    v_alpha = a_alpha;
    v_inv_t = a_inv_t;
    v_corner = a_corner;
}
)";
const char* kSmoothieFS = R"(
noperspective in float v_alpha;
smooth in float v_depth;
flat in vec2 v_sil;
flat in float v_inv_t;
flat in float v_corner;
uniform sampler2D u_sm;
uniform vec2 u_size;
uniform int u_remap_here;
out vec2 o;
void main() {
    if (sk_smoothie_hidden(u_sm, gl_FragCoord.xy, v_depth, 0.01)) discard;
    vec2 s = sk_smoothie_fragment(gl_FragCoord.xy, u_size, v_alpha, v_sil, v_inv_t, v_corner, v_depth);
    if (u_remap_here != 0) s.y = sk_smoothie_remap(s.y, v_depth, sk_smoothie_shadow_depth_at(u_sm, gl_FragCoord.xy));
    o = s;
}
)";
// Pass 3 (or the hard lookup of (b)): any receiver drawn with u_cam, visibility per fragment.
const char* kLookupVS = R"(
layout(location = 0) in vec3 a_p;
uniform mat4 u_cam;
out vec3 v_world;
void main() { v_world = a_p; gl_Position = u_cam * vec4(a_p, 1.0); }
)";
const char* kLookupFS = R"(
in vec3 v_world;
uniform mat4 u_vp;
uniform mat4 u_view;
uniform sampler2D u_sm;
uniform sampler2D u_sb;
uniform int u_remapped;
uniform float u_bias;
out float o_v;
void main() {
    vec4 c = u_vp * vec4(v_world, 1.0);
    vec2 uv = c.xy / c.w * 0.5 + 0.5;
    float r = sk_smoothie_linear_depth(u_view, v_world);
    vec2 g = sk_smoothie_depth_gradient(dFdx(uv), dFdy(uv), dFdx(r), dFdy(r));
    o_v = sk_smoothie_visibility(u_sm, u_sb, uv, r, g, u_bias, u_remapped != 0);
}
)";
// (b)'s independent hard lookup: the same 4 texels, receiver plane and bias, 0/1 per texel.
const char* kHardFS = R"(
in vec3 v_world;
uniform mat4 u_vp;
uniform mat4 u_view;
uniform sampler2D u_sm;
uniform float u_bias;
out float o_v;
void main() {
    vec4 c = u_vp * vec4(v_world, 1.0);
    vec2 uv = c.xy / c.w * 0.5 + 0.5;
    float r = -(u_view * vec4(v_world, 1.0)).z;
    vec2 dx = dFdx(uv), dy = dFdy(uv);
    float rx = dFdx(r), ry = dFdy(r);
    float det = dx.x * dy.y - dx.y * dy.x;
    vec2 g = abs(det) < 1e-20 ? vec2(0.0) : vec2(rx * dy.y - ry * dx.y, ry * dx.x - rx * dy.x) / det;
    if (!(r > 0.0) || any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) { o_v = 1.0; return; }
    ivec2 size = textureSize(u_sm, 0);
    vec2 st = uv * vec2(size) - 0.5;
    vec2 base = floor(st);
    vec2 f = st - base;
    float v[4];
    for (int k = 0; k < 4; ++k) {
        ivec2 texel = clamp(ivec2(base) + ivec2(k & 1, k >> 1), ivec2(0), size - 1);
        float r_tap = r + dot(g, (vec2(texel) + 0.5) / vec2(size) - uv);
        v[k] = r_tap > texelFetch(u_sm, texel, 0).r + u_bias ? 0.0 : 1.0;
    }
    o_v = mix(mix(v[0], v[1], f.x), mix(v[2], v[3], f.x), f.y);
}
)";

GLint U(GLuint p, const char* n) { return glGetUniformLocation(p, n); }

// The card (square of half size h at light-view depth b) over a floor at depth rf
// (smoothie_reference.hpp), with its vertex array.
struct CardScene : smoothie_ref::Card {
    GLuint vao = 0, vbo = 0;
    CardScene() {
        glGenVertexArrays(1, &vao);
        glBindVertexArray(vao);
        glGenBuffers(1, &vbo);
        glBindBuffer(GL_ARRAY_BUFFER, vbo);
        glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(tris.size() * sizeof(glm::vec3)), tris.data(), GL_STATIC_DRAW);
        glEnableVertexAttribArray(0);
        glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 12, nullptr);
        glBindVertexArray(0);
    }
    ~CardScene() {
        glDeleteBuffers(1, &vbo);
        glDeleteVertexArrays(1, &vao);
    }
};

struct Passes {
    GLuint depth = 0, smoothie = 0, lookup = 0, hard = 0;
    Passes() {
        const std::string s = kH + snippet();
        std::string log;
        depth = skgl::compile_program({{GL_VERTEX_SHADER, s + kDepthVS}, {GL_FRAGMENT_SHADER, s + kDepthFS}}, log);
        REQUIRE_MESSAGE(depth != 0, log);
        smoothie = skgl::compile_program({{GL_VERTEX_SHADER, s + kSmoothieVS}, {GL_FRAGMENT_SHADER, s + kSmoothieFS}}, log);
        REQUIRE_MESSAGE(smoothie != 0, log);
        lookup = skgl::compile_program({{GL_VERTEX_SHADER, s + kLookupVS}, {GL_FRAGMENT_SHADER, s + kLookupFS}}, log);
        REQUIRE_MESSAGE(lookup != 0, log);
        hard = skgl::compile_program({{GL_VERTEX_SHADER, kH + kLookupVS}, {GL_FRAGMENT_SHADER, kH + kHardFS}}, log);
        REQUIRE_MESSAGE(hard != 0, log);
    }
    ~Passes() {
        for (GLuint p : {depth, smoothie, lookup, hard}) glDeleteProgram(p);
    }
};

// Passes 1 and 2 for the card scene: linear map sm (R32F) and smoothie buffer sb (RG32F), N x N.
void render_buffers(const CardScene& cs, const Passes& P, int N, float t, bool remap_here, skgl::Target& sm,
                    skgl::Target& sb, shadowkit::SmoothieResult& res) {
    std::string why;
    REQUIRE(skgl::make_target(sm, N, N, {GL_R32F}, GL_DEPTH_COMPONENT32F, why));
    REQUIRE(skgl::make_target(sb, N, N, {GL_RG32F}, 0, why));
    glBindFramebuffer(GL_FRAMEBUFFER, sm.fbo);
    glViewport(0, 0, N, N);
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    const float big[4] = {1e30f, 0, 0, 0};
    glClearBufferfv(GL_COLOR, 0, big);
    glClear(GL_DEPTH_BUFFER_BIT);
    glUseProgram(P.depth);
    glUniformMatrix4fv(U(P.depth, "u_vp"), 1, GL_FALSE, glm::value_ptr(cs.vp));
    glUniformMatrix4fv(U(P.depth, "u_view"), 1, GL_FALSE, glm::value_ptr(cs.view));
    glBindVertexArray(cs.vao);
    glDrawArrays(GL_TRIANGLES, 0, 12);

    const auto sv = cs.smoothies(t, res);
    glBindFramebuffer(GL_FRAMEBUFFER, sb.fbo);
    glViewport(0, 0, N, N);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    const float clear[4] = {1e30f, 1.f, 0.f, 0.f};
    glClearBufferfv(GL_COLOR, 0, clear);
    if (!sv.empty()) {
        GLuint vao = 0, vbo = 0;
        glGenVertexArrays(1, &vao);
        glBindVertexArray(vao);
        glGenBuffers(1, &vbo);
        glBindBuffer(GL_ARRAY_BUFFER, vbo);
        glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(sv.size() * sizeof(shadowkit::SmoothieVertex)), sv.data(), GL_STATIC_DRAW);
        const GLsizei st = sizeof(shadowkit::SmoothieVertex);
        const GLuint loc[5] = {0, 1, 2, 3, 5};
        const GLint cnt[5] = {3, 1, 3, 1, 1};
        const std::size_t off[5] = {0, 12, 16, 28, 40};
        for (int i = 0; i < 5; ++i) {
            glEnableVertexAttribArray(loc[i]);
            glVertexAttribPointer(loc[i], cnt[i], GL_FLOAT, GL_FALSE, st, reinterpret_cast<const void*>(off[i]));
        }
        glEnable(GL_BLEND);
        glBlendEquation(GL_MIN);
        glUseProgram(P.smoothie);
        glUniformMatrix4fv(U(P.smoothie, "u_vp"), 1, GL_FALSE, glm::value_ptr(cs.vp));
        glUniformMatrix4fv(U(P.smoothie, "u_view"), 1, GL_FALSE, glm::value_ptr(cs.view));
        glUniform2f(U(P.smoothie, "u_size"), float(N), float(N));
        glUniform1i(U(P.smoothie, "u_remap_here"), remap_here ? 1 : 0);
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(GL_TEXTURE_2D, sm.color[0]);
        glUniform1i(U(P.smoothie, "u_sm"), 0);
        glDrawArrays(GL_TRIANGLES, 0, GLsizei(sv.size()));
        glDisable(GL_BLEND);
        glBlendEquation(GL_FUNC_ADD);
        glDeleteBuffers(1, &vbo);
        glDeleteVertexArrays(1, &vao);
    }
    CHECK(skgl::gl_error_string() == "");
}

// Final pass (P.lookup, or P.hard) over the card scene's triangles seen through `cam`.
std::vector<float> render_lookup(const CardScene& cs, GLuint prog, const glm::mat4& cam, int w, int h, bool floor_only,
                                 const skgl::Target& sm, const skgl::Target& sb, bool remapped, float bias) {
    std::string why;
    skgl::Target out;
    REQUIRE(skgl::make_target(out, w, h, {GL_R32F}, GL_DEPTH_COMPONENT32F, why));
    glBindFramebuffer(GL_FRAMEBUFFER, out.fbo);
    glViewport(0, 0, w, h);
    glEnable(GL_DEPTH_TEST);
    const float neg[4] = {-1.f, 0, 0, 0};
    glClearBufferfv(GL_COLOR, 0, neg);
    glClear(GL_DEPTH_BUFFER_BIT);
    glUseProgram(prog);
    glUniformMatrix4fv(U(prog, "u_cam"), 1, GL_FALSE, glm::value_ptr(cam));
    glUniformMatrix4fv(U(prog, "u_vp"), 1, GL_FALSE, glm::value_ptr(cs.vp));
    glUniformMatrix4fv(U(prog, "u_view"), 1, GL_FALSE, glm::value_ptr(cs.view));
    glUniform1f(U(prog, "u_bias"), bias);
    glUniform1i(U(prog, "u_remapped"), remapped ? 1 : 0);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, sm.color[0]);
    glUniform1i(U(prog, "u_sm"), 0);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, sb.color[0]);
    glUniform1i(U(prog, "u_sb"), 1);
    glBindVertexArray(cs.vao);
    if (floor_only)
        glDrawArrays(GL_TRIANGLES, 6, 6);
    else
        glDrawArrays(GL_TRIANGLES, 0, 12);
    glBindVertexArray(0);
    CHECK(skgl::gl_error_string() == "");
    auto v = skgl::read_color_float(out, 0, 1);
    skgl::destroy_target(out);
    return v;
}

sk::Technique* find_technique(std::vector<std::unique_ptr<sk::Technique>>& ts, const std::string& name) {
    for (auto& t : ts)
        if (t->name() == name) return t.get();
    return nullptr;
}

// The named settings of samples/smoothies/ (bind_settings) for a given width t (exact: %.17g) and map size.
sk::ParamSet named_t(double t, int size) {
    char b[96];
    std::snprintf(b, sizeof b, "t_from_light=off t=%.17g size=%d", t, size);
    return sk::ParamSet::parse_named(b);
}

}  // namespace

TEST_CASE("(a) three passes through glsl/smoothie.glsl match the CPU prediction at every texel (|dV| <= 1e-4)") {
    gl_test_context();
    const CardScene cs;
    const Passes P;
    const int N = 512;
    const float bias = 0.01f;
    for (float t : {0.05f, 0.1f, 0.2f})
        for (bool remap_here : {false, true}) {
            CAPTURE(t);
            CAPTURE(remap_here);
            skgl::Target sm, sb;
            shadowkit::SmoothieResult res;
            render_buffers(cs, P, N, t, remap_here, sm, sb, res);
            CHECK(res.edge_quads == 4);
            CHECK(res.corners == 4);
            const auto sbuf = skgl::read_color_float(sb, 0, 2);
            // the floor seen from the light itself: output pixel centres are texel centres
            const auto vis = render_lookup(cs, P.lookup, cs.vp, N, N, true, sm, sb, remap_here, bias);
            double max_err = 0.0, max_alpha_err = 0.0;
            std::size_t compared = 0, penumbra = 0, umbra = 0;
            for (int y = 0; y < N; ++y)
                for (int x = 0; x < N; ++x) {
                    // the card's closed-form light-NDC distance (smoothie_reference.hpp)
                    const smoothie_ref::CardTexel ref = smoothie_ref::card_texel(cs, N, x, y, t, remap_here, bias);
                    if (ref.skip) continue;
                    const std::size_t k = std::size_t(y) * N + std::size_t(x);
                    if (ref.alpha_known) {
                        max_alpha_err = std::max(max_alpha_err, std::abs(double(sbuf[2 * k + 1]) - double(ref.a_expect)));
                        CHECK(std::abs(sbuf[2 * k] - cs.b) < 1e-4f);
                    }
                    const float expect = ref.expect;
                    max_err = std::max(max_err, std::abs(double(vis[k]) - double(expect)));
                    ++compared;
                    if (expect > 0.f && expect < 1.f) ++penumbra;
                    if (expect == 0.f) ++umbra;
                }
            MESSAGE("t = " << t << std::string(remap_here ? " (remap in the smoothie pass)" : " (remap in the final pass)") << ": "
                           << compared << " texels, " << penumbra << " penumbra, " << umbra
                           << " umbra; max |V - V_cpu| = " << max_err << ", smoothie-buffer max |alpha - expected| = "
                           << max_alpha_err);
            CHECK(compared > std::size_t(N) * N * 9 / 10);
            CHECK(penumbra > 1000);
            CHECK(umbra > 1000);
            CHECK(max_err <= 1e-4);
            CHECK(max_alpha_err <= 1e-4);
            skgl::destroy_target(sm);
            skgl::destroy_target(sb);
        }
}

TEST_CASE("(b) t = 0 builds no geometry and is bit-identical to an independent hard 2x2 lookup") {
    gl_test_context();
    const CardScene cs;
    const Passes P;
    const int N = 256;  // coarse map: the bilinear weights matter
    skgl::Target sm, sb;
    shadowkit::SmoothieResult res;
    render_buffers(cs, P, N, 0.f, false, sm, sb, res);
    CHECK(res.status == shadowkit::Status::Ok);
    CHECK(res.needed == 0);
    // an oblique camera looking at the card and its shadow on the floor
    const int w = 320, h = 240;
    const glm::mat4 cam = smoothie_ref::oblique_camera(w, h);
    for (bool remapped : {false, true}) {
        const auto v_smoothie = render_lookup(cs, P.lookup, cam, w, h, false, sm, sb, remapped, 0.01f);
        const auto v_hard = render_lookup(cs, P.hard, cam, w, h, false, sm, sb, remapped, 0.01f);
        const auto [drawn, differ, fractional, dark] = smoothie_ref::tally_hard(v_smoothie, v_hard);
        MESSAGE("t = 0" << std::string(remapped ? " (alpha_is_remapped)" : "") << ": " << drawn << " pixels, " << differ
                        << " differ, " << dark << " in shadow, " << fractional << " filtered (0 < V < 1)");
        CHECK(drawn > std::size_t(w * h / 2));
        CHECK(dark > 1000);
        CHECK(fractional > 100);
        CHECK(differ == 0);
    }
    skgl::destroy_target(sm);
    skgl::destroy_target(sb);
}

TEST_CASE("(c) Fig. 9: penumbra widths on two receivers scale with (r - b) / b") {
    gl_test_context();
    // Light straight down from (0.3, 5, 0): blocker top at y = 2.05 (b = 2.95), base box top at y = 1
    // (r1 = 4), floor at y = 0 (r2 = 5). The blocker's left edge shadows the base box top, its right
    // edge the floor beyond the base box. The camera looks straight down from above the light.
    sk::Scene scene;
    scene.name = "fig9";
    scene.meshes.push_back(sk::make_plane("floor", {0.f, 0.f, 0.f}, 4.f, 4.f));
    scene.meshes.back().caster = false;
    scene.meshes.push_back(sk::make_box("base", {-1.f, 0.5f, 0.f}, {1.f, 0.5f, 2.f}));
    scene.meshes.push_back(sk::make_box("blocker", {0.f, 2.f, 0.f}, {0.5f, 0.05f, 1.f}));
    scene.light.type = sk::LightType::Spot;
    scene.light.position = {0.3f, 5.f, 0.f};
    scene.light.direction = {0.f, -1.f, 0.f};
    scene.light.spot_half_angle = 0.7f;
    scene.camera.eye = {0.3f, 10.f, 0.f};
    scene.camera.target = {0.3f, 0.f, 0.f};
    scene.camera.up = {0.f, 0.f, -1.f};
    scene.camera.fovy = 0.28f;
    const int W = 512, H = 512;
    sk::SceneGpu gpu;
    sk::GBuffer g;
    std::string why;
    REQUIRE_MESSAGE(sk::prepare_scene_gpu(scene, W, H, gpu, g, why), why);
    auto ts = sk::make_techniques();
    sk::Technique* smoothie = find_technique(ts, "smoothie");
    REQUIRE(smoothie != nullptr);
    const float t = 0.2f;
    sk::RunContext ctx{scene, gpu, 1, 0};
    const sk::RunResult res = smoothie->run(ctx, named_t(t, 2048));
    REQUIRE_MESSAGE(res.ok, res.error);

    const sk::LightMatrices lm = sk::fit_light(scene);
    const double s = double(lm.proj[0][0]);
    const double b = 5.0 - 2.05, r1 = 4.0, r2 = 5.0;
    // iso-lines of the sinusoidal falloff: sin^2(pi a / 2) = 0.05 and 0.95
    const double a05 = 2.0 / M_PI * std::asin(std::sqrt(0.05)), a95 = 2.0 / M_PI * std::asin(std::sqrt(0.95));
    const double w1_expect = (a95 - a05) * double(t) * (r1 - b) / s;
    const double w2_expect = (a95 - a05) * double(t) * (r2 - b) / s;

    // Along each pixel row with world z in [-0.5, 0.5]: on receiver y = level, walking from the
    // umbra outwards (dir = -1: to smaller x on the box top, +1: to larger x on the floor), the world
    // x where V crosses 0.05 and 0.95 (linear interpolation between pixel centres).
    auto width_on = [&](float level, int dir, double x_min, double x_max, int& rows) {
        double sum = 0.0;
        rows = 0;
        for (int y = 0; y < H; ++y) {
            std::vector<std::pair<double, double>> prof;  // (x, V) on this receiver, ordered outwards
            double z = 0.0;
            for (int x = 0; x < W; ++x) {
                const std::size_t k = std::size_t(y) * W + std::size_t(x);
                if (g.kind[k] != 1 || std::abs(g.position[3 * k + 1] - level) > 1e-3f) continue;
                const double px = g.position[3 * k];
                if (px < x_min || px > x_max) continue;
                z = g.position[3 * k + 2];
                prof.emplace_back(px, double(res.visibility[k]));
            }
            if (std::abs(z) > 0.5 || prof.size() < 20) continue;
            std::sort(prof.begin(), prof.end());
            if (dir < 0) std::reverse(prof.begin(), prof.end());
            double x05 = NAN, x95 = NAN;
            for (std::size_t i = 1; i < prof.size(); ++i) {
                const auto [xa, va] = prof[i - 1];
                const auto [xb, vb] = prof[i];
                if (std::isnan(x05) && va < 0.05 && vb >= 0.05) x05 = xa + (0.05 - va) / (vb - va) * (xb - xa);
                if (std::isnan(x95) && va < 0.95 && vb >= 0.95) x95 = xa + (0.95 - va) / (vb - va) * (xb - xa);
            }
            if (std::isnan(x05) || std::isnan(x95)) continue;
            sum += std::abs(x95 - x05);
            ++rows;
        }
        return rows ? sum / rows : 0.0;
    };
    int rows1 = 0, rows2 = 0;
    const double w1 = width_on(1.f, -1, -1.6, -0.2, rows1);  // box top, left of the blocker's shadow
    const double w2 = width_on(0.f, +1, 0.4, 1.6, rows2);    // floor, right of it
    const double ratio = w1 / w2, ratio_expect = (r1 - b) / (r2 - b);
    MESSAGE("t = " << t << ", s = " << s << ", b = " << b << ": box top (r1 = 4) width " << w1 << " (expected "
                   << w1_expect << ", " << rows1 << " rows), floor (r2 = 5) width " << w2 << " (expected " << w2_expect
                   << ", " << rows2 << " rows); ratio " << ratio << " vs (r1-b)/(r2-b) = " << ratio_expect);
    REQUIRE(rows1 > 20);
    REQUIRE(rows2 > 20);
    CHECK(ratio == doctest::Approx(ratio_expect).epsilon(0.05));
    CHECK(w1 == doctest::Approx(w1_expect).epsilon(0.08));
    CHECK(w2 == doctest::Approx(w2_expect).epsilon(0.08));
}

TEST_CASE("(d) contact vs the Embree area-light reference: umbra never shrinks; penumbra error as predicted") {
    gl_test_context();
    sk::Scene scene;
    REQUIRE(sk::make_builtin_scene("contact", scene));
    const int W = 320, H = 240;
    sk::SceneGpu gpu;
    sk::GBuffer g;
    std::string why;
    REQUIRE_MESSAGE(sk::prepare_scene_gpu(scene, W, H, gpu, g, why), why);
    sk::ReferenceOptions opt;
    opt.strata = 16;
    opt.progress = false;
    sk::Reference ref;
    REQUIRE_MESSAGE(sk::compute_reference(scene, g, opt, ref, why), why);
    auto ts = sk::make_techniques();
    sk::Technique* hard = find_technique(ts, "shadow_map");
    sk::Technique* smoothie = find_technique(ts, "smoothie");
    REQUIRE(hard != nullptr);
    REQUIRE(smoothie != nullptr);
    sk::RunContext ctx{scene, gpu, 1, 0};
    const auto r_hard = hard->run(ctx, sk::ParamSet::parse_named("size=1024"));
    const auto r_t0 = smoothie->run(ctx, named_t(0.0, 1024));
    const auto r_map = smoothie->run(ctx, sk::ParamSet::parse_named("t_from_light=on size=1024"));
    REQUIRE(r_hard.ok);
    REQUIRE(r_t0.ok);
    REQUIRE_MESSAGE(r_map.ok, r_map.error);
    double t_map = 0.0;
    for (const auto& [k, v] : r_map.work)
        if (k == "t") t_map = v;
    REQUIRE(t_map > 0.0);
    const auto r_small = smoothie->run(ctx, named_t(t_map / 8.0, 1024));
    REQUIRE(r_small.ok);

    // smoothies only darken: V_t <= V_0 at every pixel, so the umbra never shrinks
    std::size_t brighter = 0;
    for (std::size_t k = 0; k < g.kind.size(); ++k)
        if (r_map.visibility[k] > r_t0.visibility[k] + 1e-6f || r_small.visibility[k] > r_t0.visibility[k] + 1e-6f)
            ++brighter;
    CHECK(brighter == 0);

    const sk::Metrics m_hard = sk::compute_metrics(g, ref, r_hard.visibility, true);
    const sk::Metrics m_t0 = sk::compute_metrics(g, ref, r_t0.visibility, false);
    const sk::Metrics m_map = sk::compute_metrics(g, ref, r_map.visibility, false);
    const sk::Metrics m_q = sk::compute_metrics(g, ref, r_small.visibility, false);
    REQUIRE(m_hard.has_penumbra);
    MESSAGE("contact, " << m_hard.penumbra_pixels << " penumbra pixels; penumbra RMSE: shadow_map " << m_hard.penumbra_rmse
                        << ", smoothie t=0 " << m_t0.penumbra_rmse << ", mapped t=" << t_map << " " << m_map.penumbra_rmse
                        << " (ratio " << m_map.penumbra_rmse / m_hard.penumbra_rmse << "), t/8 " << m_q.penumbra_rmse
                        << " (ratio " << m_q.penumbra_rmse / m_hard.penumbra_rmse << ", " << m_q.penumbra_rmse / m_t0.penumbra_rmse
                        << " of t=0); RMSE " << m_hard.rmse << " / "
                        << m_map.rmse << " / " << m_q.rmse);
    // t = 0 is the hard test on the linear map: as good as the plain shadow map (within 10 %)
    CHECK(m_t0.penumbra_rmse == doctest::Approx(m_hard.penumbra_rmse).epsilon(0.1));
    // The smoothie penumbra lies wholly outside the hard shadow; the area light's is centred on it.
    // A 1D model (straight edge of a square light: a linear ramp of width W centred on the hard edge,
    // against a sinusoidal falloff of width k W outside it) predicts a penumbra RMSE of 1.56x the
    // hard edge's for k = 1 (the header's mapping t = s w / b) and at best 0.92x (k ~ 0.2). On
    // `contact` the mapped t loses accordingly and a small t (k = 1/8, the best of 1/32 .. 1/2 here)
    // wins by only a few per cent over the hard test on the same map: no clear win in the penumbra.
    CHECK(m_map.penumbra_rmse > 1.2 * m_hard.penumbra_rmse);
    CHECK(m_map.penumbra_rmse < 2.0 * m_hard.penumbra_rmse);
    CHECK(m_q.penumbra_rmse < m_t0.penumbra_rmse);
    CHECK(m_q.penumbra_rmse > 0.9 * m_t0.penumbra_rmse);
}
