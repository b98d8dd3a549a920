// Drivers for the soft-shadow family: percentage-closer filtering (glsl/pcf.glsl), percentage-closer
// soft shadows (shadowkit/pcss.hpp on the CPU for the uniforms + glsl/pcss.glsl), Apelles'
// sampled area light (N spot-light shadow maps from Poisson positions on the emitter,
// shadowkit/poisson_disk.hpp) and a depth-bias study (shadowkit/shadow_bias.hpp's constant,
// slope-scaled, normal-offset and receiver-plane bias on the plain and PCF paths) that measures
// acne and peter-panning against a ray-traced reference.
//
// Shared conventions of these drivers:
// - The light frustum is fit_light(): a perspective from the light's centre along its direction
//   with near/far hugging the scene; the maps store GL window depth (glm::perspective, [-1,1]
//   clip, glDepthRange(0,1)). pcss.glsl linearizes it with the same near/far.
// - Receiver-plane depth bias uses the G-buffer's exact surface plane: the full-screen pass knows
//   each pixel's position and geometric normal, so the plane's depth gradient dz/duv comes from
//   projecting two tangent points, then the same 2x2 solve as sk_receiver_plane_depth_bias(uvz)
//   (whose dFdx/dFdy form would straddle silhouettes and the pass's early-return pixels). On top
//   of the gradient, a margin of `margin` texels of plane slope (the stored depth is the depth at
//   the texel centre, the 2x2 bilinear compare reads texels up to one texel away) plus a tiny
//   constant (kConstBias, window units).
// - Area lights: the reference counts light samples below the receiver's tangent plane as unseen.
//   PCF and PCSS (param horizon=1, the default) multiply their result by the emitter's fraction
//   above that plane (sk_emitter_horizon from driver_util, closed form); the sampled area light tests each sample.
// - Every single-map row also reports acne_fraction and peter_pan_px (add_bias_quality).
#include <shadowkit/pcss.hpp>
#include <shadowkit/poisson_disk.hpp>
#include <shadowkit/shadow_bias.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <map>
#include <mutex>
#include <tuple>

#include "driver_util.hpp"

namespace sk {

namespace {

constexpr float kConstBias = 2e-6f;  // window-depth units: float32 rounding of G-buffer positions and map depth
constexpr int kMapSize = 2048;       // PCF / PCSS / bias-study shadow map
constexpr int kSampledMapSize = 1024;
constexpr int kSampledBatch = 16;    // sampled-area maps rendered into one depth array per pass
constexpr int kMaxSampled = 256;

// The emitters these drivers model: rect, disk and sphere lights of nonzero size (line lights have
// their own family).
bool surface_area_light(const Light& L) {
    return L.is_area() && (L.type == LightType::Rect || L.type == LightType::Disk || L.type == LightType::Sphere);
}

// Width of the emitter in world units, as pcss.hpp's PcssLight::size wants it: rect edge, disk
// and sphere diameter (Light::size is the rect edge, the disk / sphere radius).
float light_width(const Light& L) {
    if (!surface_area_light(L)) return 0.f;
    return L.type == LightType::Rect ? L.size : 2.f * L.size;
}

// Scenes for the PCF / PCSS / sampled-area sweeps: rect, disk and sphere lights and user meshes
// ("grazing", the bias-study scene, is left to the bias study to keep the report's run time).
bool soft_scene(const Scene& s) {
    if (s.name == "grazing") return false;
    return surface_area_light(s.light) || (s.name.rfind("mesh:", 0) == 0 && s.light.type != LightType::Point &&
                                           s.light.type != LightType::Directional && s.light.type != LightType::Linear);
}

// One perspective map from the light's centre: spot lights and rect / disk / sphere emitters.
bool perspective_light(const Light& L) {
    return L.type == LightType::Spot || L.type == LightType::Rect || L.type == LightType::Disk || L.type == LightType::Sphere;
}


struct LightSetup {
    LightMatrices lm;
    glm::vec3 eye{0.f}, dir{0.f, -1.f, 0.f}, up{0.f, 1.f, 0.f};
    float tan_half = 1.f;  // tan(fov / 2) of the light frustum
    float width = 0.f;     // emitter width (light_width)
};

LightSetup setup_light(const Scene& s) {
    LightSetup ls;
    ls.lm = fit_light(s);
    ls.eye = s.light.position;
    const glm::mat4 inv = glm::inverse(ls.lm.view);
    ls.dir = -glm::normalize(glm::vec3(inv[2]));
    ls.up = glm::normalize(glm::vec3(inv[1]));
    ls.tan_half = 1.f / ls.lm.proj[1][1];
    ls.width = light_width(s.light);
    return ls;
}

shadowkit::PcssLight pcss_light(const LightSetup& ls, float width_scale) {
    shadowkit::PcssLight L;
    L.type = shadowkit::PcssLightType::Perspective;
    L.size = ls.width * width_scale;
    L.near_z = ls.lm.znear;
    L.far_z = ls.lm.zfar;
    L.frustum_width = 2.f * ls.tan_half;
    return L;
}

// Farthest surface along the light's axis (the ground under the light): Moller-Trumbore against
// every triangle; -1 when the axis hits nothing.
float farthest_axis_hit(const Scene& s, glm::vec3 o, glm::vec3 d) {
    float best = -1.f;
    for (const auto& m : s.meshes)
        for (std::size_t i = 0; i + 2 < m.indices.size(); i += 3) {
            const glm::vec3 a = m.positions[m.indices[i]], b = m.positions[m.indices[i + 1]], c = m.positions[m.indices[i + 2]];
            const glm::vec3 e1 = b - a, e2 = c - a, pv = glm::cross(d, e2);
            const float det = glm::dot(e1, pv);
            if (std::abs(det) < 1e-12f) continue;
            const float inv = 1.f / det;
            const glm::vec3 tv = o - a;
            const float u = glm::dot(tv, pv) * inv;
            if (u < 0.f || u > 1.f) continue;
            const glm::vec3 qv = glm::cross(tv, e1);
            const float v = glm::dot(d, qv) * inv;
            if (v < 0.f || u + v > 1.f) continue;
            const float t = glm::dot(e2, qv) * inv;
            if (t > 0.f) best = std::max(best, t);
        }
    return best;
}

// Default PCF filter radius (texels): half the penumbra (pcss_penumbra_width, in uv through
// pcss_width_to_uv, times the map size) of a blocker at the middle of the casters' depth
// extent along the light axis, on the receiver that the axis meets last (the ground; the casters'
// far side when it meets nothing). Clamped to [1, 32] texels; 2 texels for lights without area.
float default_pcf_radius_texels(const Scene& s, int size) {
    const LightSetup ls = setup_light(s);
    if (!(ls.width > 0.f)) return 2.f;
    float zmin = INFINITY, zmax = -INFINITY;
    for (const auto& m : s.meshes) {
        if (!m.caster) continue;
        for (const auto& p : m.positions) {
            const float z = -(ls.lm.view * glm::vec4(p, 1.f)).z;
            zmin = std::min(zmin, z);
            zmax = std::max(zmax, z);
        }
    }
    if (!(zmax >= zmin) || !(zmin > 0.f)) return 2.f;
    const float zb = 0.5f * (zmin + zmax);
    const float zr = std::max(farthest_axis_hit(s, ls.eye, ls.dir), zmax);
    const shadowkit::PcssValue w = shadowkit::pcss_penumbra_width(ls.width, zr, zb);
    const shadowkit::PcssValue uv = shadowkit::pcss_width_to_uv(w.value, zr, 2.f * ls.tan_half);
    if (w.status != shadowkit::Status::Ok || uv.status != shadowkit::Status::Ok) return 2.f;
    return std::clamp(0.5f * uv.value * float(size), 1.f, 32.f);
}

// ------------------------------------------------------------------------------ GL plumbing
// GLSL shared by the drivers' visibility passes, appended after the snippets.
const char* kCommonGlsl = R"(
uniform mat4 u_light_view_proj;
uniform mat4 u_light_view;
uniform vec3 u_light_eye;
uniform float u_near;
uniform float u_far;
uniform float u_texel_uv;
uniform float u_tan_half;
uniform float u_margin;      // receiver-plane margin in texels of plane slope
uniform float u_const_bias;  // window units
// shadow coordinate (uv, window z) of p; uv = -1 when p is behind the light
vec3 skd_uvz(mat4 vp, vec3 p) {
    vec4 c = sk_shadow_coord(vp, p, false);
    return c.w > 0.0 ? c.xyz : vec3(-1.0, -1.0, 0.0);
}
// window depth of the light's perspective at eye distance d
float skd_window_depth(float d) { return u_far * (d - u_near) / (d * (u_far - u_near)); }
// receiver-plane depth gradient dz/duv of the plane (p, n): the solve of
// sk_receiver_plane_depth_bias with two tangent steps instead of dFdx/dFdy (window z is affine in
// uv on a plane under a perspective, so the step size does not matter)
vec2 skd_plane_gradient(mat4 vp, vec3 eye, vec3 p, vec3 n) {
    vec3 a = abs(n.y) < 0.9 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
    vec3 t1 = normalize(cross(n, a));
    vec3 t2 = cross(n, t1);
    float h = 0.01 * max(length(p - eye), 1e-4);
    vec3 z0 = sk_shadow_coord(vp, p, false).xyz;
    vec3 d1 = sk_shadow_coord(vp, p + h * t1, false).xyz - z0;
    vec3 d2 = sk_shadow_coord(vp, p + h * t2, false).xyz - z0;
    float det = d1.x * d2.y - d1.y * d2.x;
    float scale = (abs(d1.x) + abs(d1.y)) * (abs(d2.x) + abs(d2.y));
    if (!(abs(det) > 1e-7 * scale)) return vec2(0.0);
    return vec2(d2.y * d1.z - d1.y * d2.z, d1.x * d2.z - d2.x * d1.z) / det;
}
// receiver-plane biased shadow coordinate: z minus margin texels of slope and the constant
vec3 skd_rp_bias(vec3 uvz, vec2 g, float texel_uv) {
    uvz.z -= u_margin * texel_uv * (abs(g.x) + abs(g.y)) + u_const_bias;
    return uvz;
}
)";

// A depth map (2D or a 2D array of `layers`) with one FBO per layer.
struct DepthMap {
    GLuint tex = 0;
    std::vector<GLuint> fbo;
    int size = 0, layers = 0;  // layers 0: GL_TEXTURE_2D
    DepthMap() = default;
    DepthMap(const DepthMap&) = delete;
    DepthMap& operator=(const DepthMap&) = delete;
    ~DepthMap() {
        if (!fbo.empty()) glDeleteFramebuffers(static_cast<GLsizei>(fbo.size()), fbo.data());
        if (tex) glDeleteTextures(1, &tex);
    }
    GLenum target() const { return layers ? GL_TEXTURE_2D_ARRAY : GL_TEXTURE_2D; }
    bool init(int s, GLenum format, int nlayers, std::string& why) {
        size = s;
        layers = nlayers;
        glGenTextures(1, &tex);
        glBindTexture(target(), tex);
        if (layers)
            glTexStorage3D(GL_TEXTURE_2D_ARRAY, 1, format, s, s, layers);
        else
            glTexStorage2D(GL_TEXTURE_2D, 1, format, s, s);
        const int n = std::max(layers, 1);
        fbo.resize(static_cast<std::size_t>(n));
        glGenFramebuffers(n, fbo.data());
        for (int i = 0; i < n; ++i) {
            glBindFramebuffer(GL_FRAMEBUFFER, fbo[static_cast<std::size_t>(i)]);
            if (layers)
                glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, tex, 0, i);
            else
                glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, tex, 0);
            glDrawBuffer(GL_NONE);
            glReadBuffer(GL_NONE);
            if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
                why = "depth map framebuffer incomplete";
                return false;
            }
        }
        const std::string err = skgl::gl_error_string();
        if (!err.empty()) {
            why = "depth map: " + err;
            return false;
        }
        return true;
    }
};

// Sampler objects: the compare view (GL_LINEAR = hardware 2x2 PCF) and the raw depth view.
struct Samplers {
    GLuint cmp = 0, raw = 0;
    Samplers() {
        const float border[4] = {1.f, 1.f, 1.f, 1.f};
        glGenSamplers(1, &cmp);
        glGenSamplers(1, &raw);
        for (GLuint s : {cmp, raw}) {
            glSamplerParameteri(s, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_BORDER);
            glSamplerParameteri(s, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_BORDER);
            glSamplerParameterfv(s, GL_TEXTURE_BORDER_COLOR, border);
        }
        glSamplerParameteri(cmp, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glSamplerParameteri(cmp, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glSamplerParameteri(cmp, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
        glSamplerParameteri(cmp, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
        glSamplerParameteri(raw, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glSamplerParameteri(raw, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glSamplerParameteri(raw, GL_TEXTURE_COMPARE_MODE, GL_NONE);
    }
    Samplers(const Samplers&) = delete;
    Samplers& operator=(const Samplers&) = delete;
    ~Samplers() {
        glDeleteSamplers(1, &cmp);
        glDeleteSamplers(1, &raw);
    }
};

struct Program {
    GLuint id = 0;
    Program() = default;
    Program(const Program&) = delete;
    Program& operator=(const Program&) = delete;
    ~Program() {
        if (id) glDeleteProgram(id);
    }
    GLint loc(const char* n) const { return glGetUniformLocation(id, n); }
};

void set_common_uniforms(const Program& p, const Scene& s, const LightSetup& ls, int size, bool horizon = false) {
    glUseProgram(p.id);
    set_light_uniforms(p.id, s.light);
    const glm::mat4 vp = ls.lm.proj * ls.lm.view;
    glUniformMatrix4fv(p.loc("u_light_view_proj"), 1, GL_FALSE, glm::value_ptr(vp));
    glUniformMatrix4fv(p.loc("u_light_view"), 1, GL_FALSE, glm::value_ptr(ls.lm.view));
    glUniform3fv(p.loc("u_light_eye"), 1, glm::value_ptr(ls.eye));
    glUniform1f(p.loc("u_near"), ls.lm.znear);
    glUniform1f(p.loc("u_far"), ls.lm.zfar);
    glUniform1f(p.loc("u_texel_uv"), 1.f / float(size));
    glUniform1f(p.loc("u_tan_half"), ls.tan_half);
    glUniform1f(p.loc("u_margin"), 1.f);
    glUniform1f(p.loc("u_const_bias"), kConstBias);
    set_emitter_uniforms(p.id, s.light, horizon && surface_area_light(s.light));
}

// Renders the casters into layer `layer` of the map with view-projection vp.
void render_depth(const DepthMap& dm, int layer, GLuint depth_prog, const glm::mat4& vp, const SceneGpu& gpu) {
    glBindFramebuffer(GL_FRAMEBUFFER, dm.fbo[static_cast<std::size_t>(layer)]);
    glViewport(0, 0, dm.size, dm.size);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glDisable(GL_POLYGON_OFFSET_FILL);  // the drivers bias in the lookup, never in the map
    glClear(GL_DEPTH_BUFFER_BIT);
    glUseProgram(depth_prog);
    glUniformMatrix4fv(glGetUniformLocation(depth_prog, "u_light_view_proj"), 1, GL_FALSE, glm::value_ptr(vp));
    draw_casters(gpu);
}

bool compile_visibility(Program& p, const std::vector<std::string>& snippet_names, const std::string& defines,
                        const std::string& body, std::string& why) {
    std::string snippets = defines;
    for (const auto& n : snippet_names) {
        const std::string s = load_snippet(n, why);
        if (s.empty()) return false;
        snippets += s + "\n";
    }
    snippets += kCommonGlsl;
    snippets += emitter_horizon_glsl();
    std::string log;
    p.id = compile_visibility_program(snippets, body, log);
    if (!p.id) why = log;
    return p.id != 0;
}

bool compile_depth(Program& p, std::string& why) {
    std::string log;
    p.id = compile_depth_only_program(log);
    if (!p.id) why = log;
    return p.id != 0;
}

// ------------------------------------------------------------------------------ acne / peter-panning
// A low-sample reference of the same definition as the report's (strata 6 = 36 rays per pixel for
// area lights, exact for hard lights), cached per scene and size: enough to classify pixels as
// fully lit (all rays reach the light) or deep in shadow.
const Reference* classification_reference(const Scene& s, const GBuffer& g) {
    static std::mutex mu;
    static std::map<std::tuple<std::uint64_t, int, int>, Reference> cache;
    std::lock_guard<std::mutex> lock(mu);
    const auto key = std::make_tuple(scene_hash(s, g.width, g.height, 0x50f7u), g.width, g.height);
    auto it = cache.find(key);
    if (it != cache.end()) return &it->second;
    ReferenceOptions o;
    o.strata = 6;
    o.progress = false;
    Reference r;
    std::string why;
    if (!compute_reference(s, g, o, r, why)) return nullptr;
    return &cache.emplace(key, std::move(r)).first->second;
}

// acne_fraction: receiver pixels that face the light and are fully lit in the reference (V_ref == 1)
// but get V < 0.5. peter_pan_px: the gap between contact lines and the start of their shadow, in
// pixels: contact pixels are receiver pixels on a concave crease (a 4-neighbour whose normal turns
// by more than 60 degrees towards it, within 6 pixel footprints in world space) that are in the
// reference's shadow (V_ref < 0.25); the gap is the number of pixels within 16 pixels of those
// that the reference puts in shadow (V_ref < 0.25) and the technique lights (V >= 0.5), divided by
// the number of shadowed contact pixels (the length of the contact line): the mean width of the
// wrongly lit band along the contact.
void add_bias_quality(RunResult& r, const Scene& s, const GBuffer* gp) {
    if (!gp) return;
    const GBuffer& g = *gp;
    const Reference* ref = classification_reference(s, g);
    if (!ref) return;
    const int w = g.width, h = g.height;
    auto idx = [w](int x, int y) { return static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x); };
    auto P = [&](std::size_t k) { return glm::vec3(g.position[3 * k], g.position[3 * k + 1], g.position[3 * k + 2]); };
    auto N = [&](std::size_t k) { return glm::vec3(g.normal[3 * k], g.normal[3 * k + 1], g.normal[3 * k + 2]); };
    auto counted = [&](std::size_t k) { return g.kind[k] == 1 && ref->faces_light[k]; };
    std::size_t lit = 0, acne = 0;
    for (std::size_t k = 0; k < g.kind.size(); ++k)
        if (counted(k) && ref->visibility[k] >= 1.f) {
            ++lit;
            if (r.visibility[k] < 0.5f) ++acne;
        }
    const float tan_half = std::tan(0.5f * s.camera.fovy);
    const glm::vec3 eye = s.camera.eye;
    std::vector<std::uint8_t> contact(g.kind.size(), 0);
    std::size_t contacts = 0;
    for (int y = 1; y < h - 1; ++y)
        for (int x = 1; x < w - 1; ++x) {
            const std::size_t k = idx(x, y);
            if (!counted(k) || ref->visibility[k] >= 0.25f) continue;
            const glm::vec3 p = P(k), n = N(k);
            const float foot = 2.f * glm::length(p - eye) * tan_half / float(h);
            const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
            for (int i = 0; i < 4; ++i) {
                const std::size_t q = idx(x + dx[i], y + dy[i]);
                if (g.kind[q] == 0) continue;
                const glm::vec3 pq = P(q), nq = N(q);
                const glm::vec3 d = pq - p;
                if (glm::dot(n, nq) < 0.5f && glm::length(d) < 6.f * foot && glm::dot(n, d) > 0.f &&
                    glm::dot(nq, -d) > 0.f) {
                    contact[k] = 1;
                    ++contacts;
                    break;
                }
            }
        }
    std::size_t gap = 0;
    if (contacts) {
        // pixels within 16 (Chebyshev) of a contact pixel: dilate with a separable max filter
        const int R = 16;
        std::vector<std::uint8_t> tmp(contact.size(), 0), near_c(contact.size(), 0);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                std::uint8_t m = 0;
                for (int i = std::max(0, x - R); i <= std::min(w - 1, x + R) && !m; ++i) m = contact[idx(i, y)];
                tmp[idx(x, y)] = m;
            }
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                std::uint8_t m = 0;
                for (int j = std::max(0, y - R); j <= std::min(h - 1, y + R) && !m; ++j) m = tmp[idx(x, j)];
                near_c[idx(x, y)] = m;
            }
        for (std::size_t k = 0; k < g.kind.size(); ++k)
            if (near_c[k] && counted(k) && ref->visibility[k] < 0.25f && r.visibility[k] >= 0.5f) ++gap;
    }
    r.quality.push_back({"acne_fraction", lit ? double(acne) / double(lit) : 0.0});
    r.quality.push_back({"peter_pan_px", contacts ? double(gap) / double(contacts) : 0.0});
    r.quality.push_back({"lit_pixels", double(lit)});
    r.quality.push_back({"contact_pixels", double(contacts)});
}

// Times `frame`: ctx.warmup warm-up runs (at least two: llvmpipe compiles shader variants in the
// first), then the median over ctx.frames runs, or fewer when the warm frame is slow: the timed
// runs are kept within ~0.4 s per row (llvmpipe on a shared machine; the median of a few long
// frames is stable), never fewer than 3. A warm frame slower than 100 ms ends the warm-up. (The
// timed runs go through skgl::median_frame_ms: wall time on llvmpipe, timer queries on a GPU.)
double time_frames(const RunContext& ctx, const std::function<void()>& frame, int& frames_used) {
    double last = 0.0;
    for (int i = 0; i < std::max(ctx.warmup, 2); ++i) {
        const auto t0 = Clock::now();
        frame();
        glFinish();
        last = ms_since(t0);
        if (i >= 1 && last > 100.0) break;
    }
    frames_used = ctx.frames;
    if (ctx.frames > 3 && last > 0.0) frames_used = std::clamp(static_cast<int>(400.0 / last), 3, ctx.frames);
    return skgl::median_frame_ms(frame, 0, frames_used);
}

// ------------------------------------------------------------------------------ single-map techniques
// Shared run() of PCF, PCSS and the bias study: one 2048 map from the light's centre, one
// full-screen pass whose body is given. `setup` sets the technique's own uniforms.
struct SingleMapConfig {
    std::vector<std::string> snippets;
    std::string defines;
    std::string body;
    GLenum depth_format = GL_DEPTH_COMPONENT32F;
    bool raw_view = false;  // also bind the raw depth view at unit 2 (compare view at unit 3)
    std::function<void(const Program&)> setup;
    double taps_per_pixel = 1.0;
    bool horizon = false;  // multiply by sk_emitter_horizon (the emitter's fraction above the tangent plane)
    std::function<void(LightSetup&)> adjust_light;  // e.g. PCSS's near-plane fit, after setup_light
};

RunResult run_single_map(const RunContext& ctx, const SingleMapConfig& cfg) {
    const Scene& scene = ctx.scene;
    if (!perspective_light(scene.light))
        return RunResult::failure("needs a spot or area light (a perspective shadow map from the light's centre)");
    RunResult r;
    std::string why;
    std::vector<double> cpu;
    LightSetup ls;
    for (int i = 0; i < 5; ++i) {
        const auto t0 = Clock::now();
        ls = setup_light(scene);
        if (cfg.adjust_light) cfg.adjust_light(ls);
        cpu.push_back(ms_since(t0));
    }
    r.cpu_ms = median_of(cpu);
    DepthMap dm;
    if (!dm.init(kMapSize, cfg.depth_format, 0, why)) return RunResult::failure(why);
    Samplers smp;
    VisibilityPass pass;
    if (!pass.init(ctx.gpu.width, ctx.gpu.height, why)) return RunResult::failure(why);
    Program depth, vis;
    if (!compile_depth(depth, why) || !compile_visibility(vis, cfg.snippets, cfg.defines, cfg.body, why))
        return RunResult::failure(why);
    set_common_uniforms(vis, scene, ls, kMapSize, cfg.horizon);
    if (cfg.setup) cfg.setup(vis);
    const glm::mat4 vp = ls.lm.proj * ls.lm.view;
    auto frame = [&] {
        render_depth(dm, 0, depth.id, vp, ctx.gpu);
        glActiveTexture(GL_TEXTURE2);
        glBindTexture(GL_TEXTURE_2D, dm.tex);
        glBindSampler(2, cfg.raw_view ? smp.raw : smp.cmp);
        glActiveTexture(GL_TEXTURE3);
        glBindTexture(GL_TEXTURE_2D, dm.tex);
        glBindSampler(3, smp.cmp);
        pass.draw(vis.id, ctx.gpu);
    };
    r.gpu_ms = time_frames(ctx, frame, r.frames);
    r.visibility = skgl::read_color_float(pass.target, 0, 1);
    glBindSampler(2, 0);
    glBindSampler(3, 0);
    GLint bits = 0;
    glBindTexture(GL_TEXTURE_2D, dm.tex);
    glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_DEPTH_SIZE, &bits);
    r.gpu_bytes = std::int64_t(kMapSize) * kMapSize * 4;  // D24 is padded to 32 bits
    r.work = {{"shadow_map_texels", double(kMapSize) * kMapSize},
              {"taps_per_pixel", cfg.taps_per_pixel},
              {"maps_rendered", 1.0},
              {"triangles_drawn", double(ctx.gpu.caster_triangles)},
              {"depth_bits", double(bits)}};
    const std::string err = skgl::gl_error_string();
    if (!err.empty()) return RunResult::failure(err);
    add_bias_quality(r, scene, ctx.gbuffer);
    return r;
}

// ------------------------------------------------------------------------------ PCF
// kernel: 0 box, 1 tent (radius r = 1, 2, 3 texels: (2r+1)^2 = 9, 25, 49 taps, the squares closest
// to 16, 32, 64), 2 Poisson, 3 rotated Poisson (16, 32, 64 taps in a disk of `radius` texels),
// 4 hard (one 2x2 hardware compare: the family's baseline with the same bias and horizon factor).
class PcfTechnique final : public Technique {
public:
    std::string name() const override { return "pcf"; }
    std::string description() const override {
        return "PCF (glsl/pcf.glsl) on a 2048 map, receiver-plane bias: kernel 4 hard 2x2, 0 box / 1 tent (r = 1..3 texels, 9/25/49 "
               "taps), 2 Poisson / 3 rotated Poisson (16/32/64 taps, radius = half the penumbra of a mid-height blocker); "
               "x the emitter's fraction above the tangent plane";
    }
    bool hard() const override { return false; }
    std::vector<ParamSet> sweep(const Scene& scene, bool quick) const override {
        // area lights, and spot lights (stack, fence, duel) where the kernels filter a hard shadow
        if (!soft_scene(scene) && scene.light.type != LightType::Spot) return {};
        const double radius = std::round(10.0 * double(default_pcf_radius_texels(scene, kMapSize))) / 10.0;
        std::vector<ParamSet> out;
        out.push_back(ParamSet{{{"kernel", 4.0}, {"taps", 1.0}}});  // the hard 2x2 compare, same bias and horizon
        const std::vector<int> taps = quick ? std::vector<int>{16, 64} : std::vector<int>{16, 32, 64};
        for (int k = 0; k < 4; ++k)
            for (int t : taps) {
                if (k < 2)
                    out.push_back(ParamSet{{{"kernel", double(k)}, {"taps", double(box_taps(t))}}});
                else
                    out.push_back(ParamSet{{{"kernel", double(k)}, {"taps", double(t)}, {"radius", radius}}});
            }
        return out;
    }
    static int box_radius(int taps) { return taps <= 16 ? 1 : (taps <= 36 ? 2 : 3); }
    static int box_taps(int taps) { return (2 * box_radius(taps) + 1) * (2 * box_radius(taps) + 1); }
    RunResult run(const RunContext& ctx, const ParamSet& params) override {
        const int kernel = std::clamp(static_cast<int>(params.get("kernel", 2)), 0, 4);
        const int taps = std::clamp(static_cast<int>(params.get("taps", 16)), 1, 64);
        const double radius = params.get("radius", double(default_pcf_radius_texels(ctx.scene, kMapSize)));
        SingleMapConfig cfg;
        cfg.snippets = {"shadow_map", "pcf"};
        cfg.defines = "#define SKD_KERNEL " + std::to_string(kernel) + "\n";
        cfg.body = R"(
layout(binding = 2) uniform sampler2DShadow u_sm;
uniform int u_radius_texels;
uniform float u_radius_uv;
uniform int u_taps;
float technique_visibility(vec3 p, vec3 n) {
    vec3 uvz = skd_uvz(u_light_view_proj, p);
    if (uvz.x < -0.5) return 1.0;
    vec2 g = skd_plane_gradient(u_light_view_proj, u_light_eye, p, n);
    uvz = skd_rp_bias(uvz, g, u_texel_uv);
#if SKD_KERNEL == 0
    float v = sk_pcf_box(u_sm, uvz, g, u_radius_texels);
#elif SKD_KERNEL == 1
    float v = sk_pcf_tent(u_sm, uvz, g, u_radius_texels);
#elif SKD_KERNEL == 2
    float v = sk_pcf_poisson(u_sm, uvz, g, u_radius_uv, u_taps, 0.0);
#elif SKD_KERNEL == 3
    float v = sk_pcf_poisson_rotated(u_sm, uvz, g, u_radius_uv, u_taps);
#else
    float v = sk_pcf_hard(u_sm, uvz);
#endif
    return v * sk_emitter_horizon(p, n);
}
)";
        const int r_texels = kernel < 2 ? box_radius(taps) : 0;
        cfg.setup = [&](const Program& p) {
            glUniform1i(p.loc("u_radius_texels"), r_texels);
            glUniform1f(p.loc("u_radius_uv"), float(radius) / float(kMapSize));
            glUniform1i(p.loc("u_taps"), taps);
        };
        cfg.taps_per_pixel = kernel < 2 ? double((2 * r_texels + 1) * (2 * r_texels + 1)) : (kernel == 4 ? 1.0 : double(taps));
        cfg.horizon = params.get("horizon", 1) != 0.0;
        return run_single_map(ctx, cfg);
    }
};

// ------------------------------------------------------------------------------ PCSS
// taps: blocker-search taps = filter taps (16+16, 32+32, 64+64); rotate: per-pixel rotation by
// interleaved gradient noise; depth24: GL_DEPTH_COMPONENT24 map instead of 32F; light_scale:
// multiplies the emitter width (0: a point light, the hard limit); hard: the plain 2x2 lookup
// with the same map and bias (the reference point for light_scale = 0); fit_near (default 1): the
// light's near plane moved to the casters' bounds (pcss_fit_near_plane) for the map and the search.
class PcssTechnique final : public Technique {
public:
    std::string name() const override { return "pcss"; }
    std::string description() const override {
        return "PCSS (pcss.hpp uniforms + glsl/pcss.glsl) on a 2048 map, receiver-plane bias: taps = search = filter "
               "(16/32/64), rotate 0/1; x the emitter's fraction above the tangent plane; params depth24, light_scale, hard";
    }
    bool hard() const override { return false; }
    std::vector<std::pair<std::string, double>> live_params() const override { return {{"light_scale", 1.0}}; }
    std::vector<ParamSet> sweep(const Scene& scene, bool quick) const override {
        if (!soft_scene(scene)) return {};
        std::vector<ParamSet> out;
        const std::vector<int> taps = quick ? std::vector<int>{16, 64} : std::vector<int>{16, 32, 64};
        for (int rot = 0; rot <= 1; ++rot)
            for (int t : taps) out.push_back(ParamSet{{{"taps", double(t)}, {"rotate", double(rot)}}});
        return out;
    }
    RunResult run(const RunContext& ctx, const ParamSet& params) override {
        const int taps = std::clamp(static_cast<int>(params.get("taps", 32)), 1, 64);
        const bool rotate = params.get("rotate", 1) != 0.0;
        const bool d24 = params.get("depth24", 0) != 0.0;
        const float scale = static_cast<float>(params.get("light_scale", 1.0));
        const bool hard_lookup = params.get("hard", 0) != 0.0;
        if (!perspective_light(ctx.scene.light)) return RunResult::failure("needs a spot or area light");
        // The blocker search is cut at the light's near plane: put it at the casters (pcss_fit_near_plane).
        const bool fit_near = params.get("fit_near", 1) != 0.0;
        glm::vec3 casters_lo(INFINITY), casters_hi(-INFINITY);
        for (const auto& m : ctx.scene.meshes)
            if (m.caster) {
                glm::vec3 lo, hi;
                mesh_bounds(m, lo, hi);
                casters_lo = glm::min(casters_lo, lo);
                casters_hi = glm::max(casters_hi, hi);
            }
        const auto adjust = [&](LightSetup& s) {
            if (!fit_near) return;
            const shadowkit::PcssFit fit = shadowkit::pcss_fit_near_plane(pcss_light(s, 1.f), s.lm.view, casters_lo, casters_hi);
            if (fit.status != shadowkit::Status::Ok || !fit.raised) return;
            s.lm.znear = fit.light.near_z;
            s.lm.proj = glm::perspective(2.f * std::atan(s.tan_half), 1.f, s.lm.znear, s.lm.zfar);
        };
        LightSetup ls = setup_light(ctx.scene);
        adjust(ls);
        const shadowkit::PcssLight L = pcss_light(ls, scale);
        const shadowkit::PcssValue light_uv_at_near = shadowkit::pcss_light_uv_at_near(L);
        if (light_uv_at_near.status != shadowkit::Status::Ok)
            return RunResult::failure(std::string("invalid PCSS light: ") + shadowkit::status_name(light_uv_at_near.status));
        const float light_uv = light_uv_at_near.value;
        const shadowkit::PcssPolicy policy;  // max_filter_uv 0.05
        SingleMapConfig cfg;
        cfg.snippets = {"shadow_map", "pcf", "pcss"};
        cfg.defines = std::string("#define SKD_ROTATE ") + (rotate ? "1" : "0") + "\n#define SKD_HARD " +
                      (hard_lookup ? "1" : "0") + "\n";
        cfg.body = R"(
layout(binding = 2) uniform sampler2D u_depth;
layout(binding = 3) uniform sampler2DShadow u_sm;
uniform float u_light_uv_at_near;
uniform int u_taps;
uniform float u_max_filter_uv;
float technique_visibility(vec3 p, vec3 n) {
    vec3 uvz = skd_uvz(u_light_view_proj, p);
    if (uvz.x < -0.5) return 1.0;
    vec2 g = skd_plane_gradient(u_light_view_proj, u_light_eye, p, n);
    uvz = skd_rp_bias(uvz, g, u_texel_uv);
#if SKD_HARD
    float v = sk_pcf_hard(u_sm, uvz);
#else
#if SKD_ROTATE
    float angle = 6.28318531 * sk_interleaved_gradient_noise(gl_FragCoord.xy);
#else
    float angle = 0.0;
#endif
    float v = sk_pcss(u_depth, u_sm, uvz, g, u_light_uv_at_near, u_near, u_far, u_taps, u_taps, angle, u_max_filter_uv);
#endif
    return v * sk_emitter_horizon(p, n);
}
)";
        cfg.depth_format = d24 ? GL_DEPTH_COMPONENT24 : GL_DEPTH_COMPONENT32F;
        cfg.raw_view = true;
        cfg.setup = [&](const Program& p) {
            glUniform1f(p.loc("u_light_uv_at_near"), light_uv);
            glUniform1i(p.loc("u_taps"), taps);
            glUniform1f(p.loc("u_max_filter_uv"), policy.max_filter_uv);
        };
        cfg.taps_per_pixel = hard_lookup ? 1.0 : 2.0 * taps;
        cfg.horizon = params.get("horizon", 1) != 0.0;
        cfg.adjust_light = adjust;
        return run_single_map(ctx, cfg);
    }
};

// ------------------------------------------------------------------------------ sampled area light
// Apelles' SampledAreaLight: N spot-light maps (1024^2) from Poisson positions on the emitter
// (poisson_eliminate, progressive: the first N of one 256-point set), each with its own
// perspective (fit_light's direction, fov, near, far; eye at the sample), looked up with the 2x2
// hardware PCF and accumulated. Maps are rendered 16 at a time into a depth array; each batch's
// lookups are added (V / N) into the R32F target with additive blending.
class SampledAreaTechnique final : public Technique {
public:
    std::string name() const override { return "sampled_area"; }
    std::string description() const override {
        return "sampled area light (Apelles): N = 4..256 spot-light maps (1024^2) from Poisson points on the emitter, "
               "2x2 PCF each, accumulated";
    }
    bool hard() const override { return false; }
    std::vector<ParamSet> sweep(const Scene& scene, bool quick) const override {
        if (!soft_scene(scene)) return {};
        std::vector<ParamSet> out;
        const std::vector<int> ns = quick ? std::vector<int>{4, 16, 64} : std::vector<int>{4, 16, 64, 256};
        for (int n : ns) out.push_back(ParamSet{{{"maps", double(n)}}});
        return out;
    }
    RunResult run(const RunContext& ctx, const ParamSet& params) override {
        const Scene& scene = ctx.scene;
        const int n = std::clamp(static_cast<int>(params.get("maps", 16)), 1, kMaxSampled);
        if (!perspective_light(scene.light)) return RunResult::failure("needs a spot or area light");
        RunResult r;
        std::string why;
        // The 256-point progressive Poisson set is a constant table (generated once, reported as
        // work.poisson_setup_ms); the per-frame CPU work is the light frustum and N view matrices.
        glm::vec2 pts[kMaxSampled];
        const Light& L = scene.light;
        shadowkit::PoissonDomain dom;
        if (surface_area_light(L) && L.type == LightType::Rect) dom.shape = shadowkit::PoissonShape::Square;
        const auto tp0 = Clock::now();
        const auto res = shadowkit::poisson_eliminate(dom, kMaxSampled, /*seed*/ 7, pts, kMaxSampled);
        const double poisson_ms = ms_since(tp0);
        if (res.status != shadowkit::Status::Ok) return RunResult::failure("poisson_eliminate failed");
        LightSetup ls;
        std::vector<glm::vec3> pos(static_cast<std::size_t>(n));
        std::vector<glm::mat4> vps(static_cast<std::size_t>(n));
        std::vector<double> cpu;
        for (int it = 0; it < 5; ++it) {
            const auto t0 = Clock::now();
            ls = setup_light(scene);
            float scale = 0.f;  // emitter half-edge (rect) or radius (disk, sphere)
            glm::vec3 t(1.f, 0.f, 0.f), b(0.f, 0.f, 1.f);
            if (surface_area_light(L)) {
                scale = L.type == LightType::Rect ? 0.5f * L.size : L.size;
                // rect / disk: the emitter's plane as the reference orients it; sphere: the disk facing the scene
                emitter_basis(L.type == LightType::Sphere ? ls.dir : glm::normalize(L.direction), t, b);
            }
            for (int i = 0; i < n; ++i) {
                const auto k = static_cast<std::size_t>(i);
                pos[k] = L.position + scale * (pts[i].x * t + pts[i].y * b);
                vps[k] = ls.lm.proj * glm::lookAt(pos[k], pos[k] + ls.dir, ls.up);
            }
            cpu.push_back(ms_since(t0));
        }
        r.cpu_ms = median_of(cpu);
        const int batch = std::min(n, kSampledBatch);
        DepthMap dm;
        if (!dm.init(kSampledMapSize, GL_DEPTH_COMPONENT32F, batch, why)) return RunResult::failure(why);
        Samplers smp;
        VisibilityPass pass;
        if (!pass.init(ctx.gpu.width, ctx.gpu.height, why)) return RunResult::failure(why);
        Program depth, vis;
        if (!compile_depth(depth, why)) return RunResult::failure(why);
        const std::string body = R"(
layout(binding = 2) uniform sampler2DArrayShadow u_maps;
uniform mat4 u_vp[16];
uniform vec3 u_pos[16];
uniform int u_count;
uniform float u_weight;
float technique_visibility(vec3 p, vec3 n) {
    float sum = 0.0;
    for (int i = 0; i < u_count; ++i) {
        if (dot(n, u_pos[i] - p) <= 0.0) continue;   // the sample is below the tangent plane
        vec3 uvz = skd_uvz(u_vp[i], p);
        if (uvz.x < -0.5 || any(lessThan(uvz.xy, vec2(0.0))) || any(greaterThan(uvz.xy, vec2(1.0)))) {
            sum += 1.0;
            continue;
        }
        vec2 g = skd_plane_gradient(u_vp[i], u_pos[i], p, n);
        uvz = skd_rp_bias(uvz, g, u_texel_uv);
        sum += texture(u_maps, vec4(uvz.xy, float(i), uvz.z));
    }
    return sum * u_weight;
}
)";
        if (!compile_visibility(vis, {"shadow_map"}, "", body, why)) return RunResult::failure(why);
        set_common_uniforms(vis, scene, ls, kSampledMapSize);
        glUniform1f(vis.loc("u_weight"), 1.f / float(n));
        const float zero[4] = {0.f, 0.f, 0.f, 0.f};
        auto frame = [&] {
            glBindFramebuffer(GL_FRAMEBUFFER, pass.target.fbo);
            glClearBufferfv(GL_COLOR, 0, zero);
            for (int first = 0; first < n; first += batch) {
                const int count = std::min(batch, n - first);
                for (int i = 0; i < count; ++i)
                    render_depth(dm, i, depth.id, vps[static_cast<std::size_t>(first + i)], ctx.gpu);
                glUseProgram(vis.id);
                glUniformMatrix4fv(vis.loc("u_vp"), count, GL_FALSE, glm::value_ptr(vps[static_cast<std::size_t>(first)]));
                glUniform3fv(vis.loc("u_pos"), count, glm::value_ptr(pos[static_cast<std::size_t>(first)]));
                glUniform1i(vis.loc("u_count"), count);
                glActiveTexture(GL_TEXTURE2);
                glBindTexture(GL_TEXTURE_2D_ARRAY, dm.tex);
                glBindSampler(2, smp.cmp);
                glEnable(GL_BLEND);
                glBlendFunc(GL_ONE, GL_ONE);
                glBlendEquation(GL_FUNC_ADD);
                pass.draw(vis.id, ctx.gpu);
                glDisable(GL_BLEND);
            }
        };
        r.gpu_ms = time_frames(ctx, frame, r.frames);
        r.visibility = skgl::read_color_float(pass.target, 0, 1);
        glBindSampler(2, 0);
        r.gpu_bytes = std::int64_t(batch) * kSampledMapSize * kSampledMapSize * 4;
        r.work = {{"shadow_map_texels", double(n) * kSampledMapSize * kSampledMapSize},
                  {"taps_per_pixel", double(n)},
                  {"maps_rendered", double(n)},
                  {"triangles_drawn", double(n) * double(ctx.gpu.caster_triangles)},
                  {"poisson_setup_ms", poisson_ms}};
        const std::string err = skgl::gl_error_string();
        if (!err.empty()) return RunResult::failure(err);
        return r;
    }
};

// ------------------------------------------------------------------------------ bias study
// method: 0 none, 1 constant (`setting` world units along the light axis), 2 slope-scaled
// (slope_scaled_bias: setting x texel x min(tan(theta), 10)), 3 normal offset
// (normal_offset_position with scale = setting), 4 receiver-plane (exact plane gradient, margin =
// setting texels of slope, + 2e-6 window). kernel: 0 plain (one 2x2 hardware-PCF tap), 1 PCF
// (16-tap rotated Poisson, radius 4 texels; only the receiver-plane method tilts the taps).
// No polygon offset: the bias is applied in the lookup. Rows report acne_fraction and
// peter_pan_px; run on contact, stack and fence (grazing light on the slats and the stack's boxes).
class BiasStudyTechnique final : public Technique {
public:
    std::string name() const override { return "bias"; }
    std::string description() const override {
        return "depth-bias study (shadow_bias.hpp): method 0 none / 1 constant [world] / 2 slope-scaled / 3 normal offset "
               "/ 4 receiver plane [texels] at a few settings, kernel 0 plain 2x2 / 1 PCF 16 taps r=4; acne and "
               "peter-panning";
    }
    bool hard() const override { return false; }
    static std::vector<double> settings(int method, bool quick, int kernel) {
        if (kernel == 1 && !quick) {  // the PCF path: the settings that show the kernel-radius rule
            switch (method) {
            case 1: return {0.01};
            case 2: return {0.7, 4.0};
            case 3: return {0.7, 4.0};
            case 4: return {1.0};
            default: return {0.0};
            }
        }
        switch (method) {
        case 1: return quick ? std::vector<double>{0.01} : std::vector<double>{0.002, 0.01, 0.05};
        case 2: return quick ? std::vector<double>{1.5} : std::vector<double>{0.7, 1.5, 4.0};
        case 3: return quick ? std::vector<double>{1.5} : std::vector<double>{0.7, 1.5, 4.0};
        case 4: return quick ? std::vector<double>{1.0} : std::vector<double>{0.0, 1.0, 2.0};
        default: return {0.0};
        }
    }
    std::vector<ParamSet> sweep(const Scene& scene, bool quick) const override {
        if (scene.name != "contact" && scene.name != "fence" && scene.name != "stack" && scene.name != "grazing") return {};
        std::vector<ParamSet> out;
        for (int kernel = 0; kernel <= 1; ++kernel)
            for (int m = 0; m <= 4; ++m)
                for (double s : settings(m, quick, kernel))
                    out.push_back(ParamSet{{{"method", double(m)}, {"setting", s}, {"kernel", double(kernel)}}});
        return out;
    }
    RunResult run(const RunContext& ctx, const ParamSet& params) override {
        const int method = std::clamp(static_cast<int>(params.get("method", 4)), 0, 4);
        const float setting = static_cast<float>(params.get("setting", 1.0));
        const int kernel = std::clamp(static_cast<int>(params.get("kernel", 0)), 0, 1);
        SingleMapConfig cfg;
        cfg.snippets = {"shadow_map", "pcf"};
        cfg.defines = "#define SKD_METHOD " + std::to_string(method) + "\n#define SKD_KERNEL " + std::to_string(kernel) + "\n";
        cfg.body = R"(
layout(binding = 2) uniform sampler2DShadow u_sm;
uniform float u_setting;
float technique_visibility(vec3 p, vec3 n) {
    vec3 l = normalize(u_light_eye - p);
    float c = dot(n, l);
    float s = sqrt(max(0.0, 1.0 - c * c));
    float texel_world = 2.0 * max(-(u_light_view * vec4(p, 1.0)).z, 0.0) * u_tan_half * u_texel_uv;
    vec3 q = p;
#if SKD_METHOD == 3
    q = p + n * (u_setting * texel_world * s);   // normal_offset_position
#endif
    vec3 uvz = skd_uvz(u_light_view_proj, q);
    if (uvz.x < -0.5) return 1.0;
    float dq = -(u_light_view * vec4(q, 1.0)).z;
    vec2 g = vec2(0.0);
#if SKD_METHOD == 1
    uvz.z = skd_window_depth(dq - u_setting);
#elif SKD_METHOD == 2
    float tan_t = c > 0.0 ? s / c : 1e30;
    uvz.z = skd_window_depth(dq - u_setting * texel_world * min(tan_t, 10.0));   // slope_scaled_bias
#elif SKD_METHOD == 4
    g = skd_plane_gradient(u_light_view_proj, u_light_eye, p, n);
    uvz = skd_rp_bias(uvz, g, u_texel_uv);
#endif
#if SKD_KERNEL == 0
    return sk_pcf_hard(u_sm, uvz);
#else
    return sk_pcf_poisson_rotated(u_sm, uvz, g, 4.0 * u_texel_uv, 16);
#endif
}
)";
        cfg.setup = [&](const Program& p) {
            glUniform1f(p.loc("u_setting"), setting);
            glUniform1f(p.loc("u_margin"), method == 4 ? setting : 0.f);
        };
        cfg.taps_per_pixel = kernel == 0 ? 1.0 : 16.0;
        // a quality study: its timings are indicative only, 5 frames keep its many rows cheap
        const RunContext short_ctx{ctx.scene, ctx.gpu, std::min(ctx.frames, 5), std::min(ctx.warmup, 1), ctx.gbuffer};
        return run_single_map(short_ctx, cfg);
    }
};

}  // namespace

void add_soft_techniques(std::vector<std::unique_ptr<Technique>>& out) {
    out.push_back(std::make_unique<PcfTechnique>());
    out.push_back(std::make_unique<PcssTechnique>());
    out.push_back(std::make_unique<SampledAreaTechnique>());
    out.push_back(std::make_unique<BiasStudyTechnique>());
}

}  // namespace sk
