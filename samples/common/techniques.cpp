#include "techniques.hpp"
#include "driver_util.hpp"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace sk {

double ParamSet::get(const std::string& name, double fallback) const {
    for (const auto& [k, v] : values)
        if (k == name) return v;
    return fallback;
}

std::string ParamSet::label() const {
    std::ostringstream s;
    bool first = true;
    for (const auto& [k, v] : values) {
        if (!first) s << ' ';
        first = false;
        s << k << '=' << v;
    }
    return s.str();
}

DebugImage grey_debug_image(const std::string& name, int w, int h, const std::vector<float>& data, int stride, int c,
                            float ignore_above) {
    DebugImage d;
    d.name = name;
    d.width = w;
    d.height = h;
    const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
    float lo = INFINITY, hi = -INFINITY;
    for (std::size_t k = 0; k < n; ++k) {
        const float v = data[k * static_cast<std::size_t>(stride) + static_cast<std::size_t>(c)];
        if (std::isfinite(v) && v < ignore_above) {
            lo = std::min(lo, v);
            hi = std::max(hi, v);
        }
    }
    d.rgb.assign(n * 3, 255);
    for (std::size_t k = 0; k < n; ++k) {
        const float v = data[k * static_cast<std::size_t>(stride) + static_cast<std::size_t>(c)];
        if (!std::isfinite(v) || v >= ignore_above || !(hi > lo)) continue;
        const auto g = static_cast<std::uint8_t>(std::lround(255.0 * (v - lo) / (hi - lo)));
        d.rgb[3 * k] = d.rgb[3 * k + 1] = d.rgb[3 * k + 2] = g;
    }
    return d;
}

SceneGpu::~SceneGpu() {
    for (auto& m : meshes) skgl::destroy_mesh(m);
    skgl::destroy_target(gbuffer);
}

namespace {

const char* kGbufferVS = R"(#version 450 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
uniform mat4 u_view_proj;
out vec3 v_world;
out vec3 v_normal;
void main() {
    v_world = a_position;
    v_normal = a_normal;
    gl_Position = u_view_proj * vec4(a_position, 1.0);
}
)";
const char* kGbufferFS = R"(#version 450 core
in vec3 v_world;
in vec3 v_normal;
uniform float u_kind;
layout(location = 0) out vec4 o_position;
layout(location = 1) out vec4 o_normal;
uniform vec3 u_eye;
void main() {
    // The geometric normal of the rasterized triangle (derivatives of the interpolated world
    // position are exact within one primitive), turned to the side the camera sees. Visibility is
    // a property of the surface's tangent plane, not of smoothed shading normals.
    vec3 n = normalize(cross(dFdx(v_world), dFdy(v_world)));
    if (dot(n, u_eye - v_world) < 0.0) n = -n;
    o_position = vec4(v_world, u_kind);
    o_normal = vec4(n, 0.0);
}
)";

}  // namespace

bool prepare_scene_gpu(const Scene& scene, int width, int height, SceneGpu& gpu, GBuffer& cpu, std::string& why) {
    if (width <= 0 || height <= 0) {
        why = "size must be positive";
        return false;
    }
    gpu.width = width;
    gpu.height = height;
    gpu.caster_triangles = 0;
    for (const auto& m : scene.meshes) {
        gpu.meshes.push_back(skgl::upload_mesh(&m.positions[0].x, &m.normals[0].x, m.positions.size(), m.indices.data(),
                                               m.indices.size()));
        gpu.caster.push_back(m.caster);
        if (m.caster) gpu.caster_triangles += m.indices.size() / 3;
    }
    if (!skgl::make_target(gpu.gbuffer, width, height, {GL_RGBA32F, GL_RGBA32F}, GL_DEPTH32F_STENCIL8, why))
        return false;
    std::string log;
    GLuint prog = skgl::compile_program({{GL_VERTEX_SHADER, kGbufferVS}, {GL_FRAGMENT_SHADER, kGbufferFS}}, log);
    if (!prog) {
        why = log;
        return false;
    }
    gpu.view = scene.camera.view();
    gpu.proj = scene.camera.projection(float(width) / float(height));
    const glm::mat4 vp = gpu.proj * gpu.view;
    glBindFramebuffer(GL_FRAMEBUFFER, gpu.gbuffer.fbo);
    glViewport(0, 0, width, height);
    const float zero[4] = {0.f, 0.f, 0.f, 0.f};
    glClearBufferfv(GL_COLOR, 0, zero);
    glClearBufferfv(GL_COLOR, 1, zero);
    glClearDepth(1.0);
    glClearStencil(0);
    glClear(GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDisable(GL_CULL_FACE);
    glUseProgram(prog);
    glUniformMatrix4fv(glGetUniformLocation(prog, "u_view_proj"), 1, GL_FALSE, glm::value_ptr(vp));
    glUniform3fv(glGetUniformLocation(prog, "u_eye"), 1, glm::value_ptr(scene.camera.eye));
    for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
        glUniform1f(glGetUniformLocation(prog, "u_kind"), scene.meshes[i].receiver ? 1.f : 2.f);
        skgl::draw_mesh(gpu.meshes[i]);
    }
    glDeleteProgram(prog);
    const auto pos = skgl::read_color_float(gpu.gbuffer, 0, 4);
    const auto nrm = skgl::read_color_float(gpu.gbuffer, 1, 4);
    const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    cpu.width = width;
    cpu.height = height;
    cpu.position.resize(3 * n);
    cpu.normal.resize(3 * n);
    cpu.kind.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
        for (std::size_t c = 0; c < 3; ++c) {
            cpu.position[3 * k + c] = pos[4 * k + c];
            cpu.normal[3 * k + c] = nrm[4 * k + c];
        }
        cpu.kind[k] = static_cast<std::uint8_t>(std::lround(pos[4 * k + 3]));
    }
    const std::string err = skgl::gl_error_string();
    if (!err.empty()) {
        why = "G-buffer pass: " + err;
        return false;
    }
    return true;
}

std::string load_snippet(const std::string& name, std::string& why) {
    bool ok = false;
    std::string s = skgl::read_text_file(std::string(SHADOWKIT_SOURCE_DIR) + "/glsl/" + name + ".glsl", &ok);
    if (!ok) why = "cannot read glsl/" + name + ".glsl";
    return s;
}

std::string fullscreen_vertex_shader() {
    return R"(#version 450 core
void main() {
    vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
)";
}

std::string visibility_fragment_shader(const std::string& snippets, const std::string& body) {
    return std::string("#version 450 core\n") + snippets + "\n" + body + R"(
layout(binding = 0) uniform sampler2D u_gbuf_position;
layout(binding = 1) uniform sampler2D u_gbuf_normal;
uniform int u_light_type;        // 0 point, 1 spot, 2 directional, 3 rect, 4 disk, 5 sphere, 6 linear
uniform vec3 u_light_position;
uniform vec3 u_light_direction;
uniform float u_light_cos_cone;
layout(location = 0) out float o_visibility;
void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec4 pk = texelFetch(u_gbuf_position, px, 0);
    if (pk.w < 0.5) { o_visibility = 0.0; return; }
    vec3 p = pk.xyz;
    vec3 n = texelFetch(u_gbuf_normal, px, 0).xyz;
    vec3 to_light = u_light_type == 2 ? -u_light_direction : u_light_position - p;
    bool area = u_light_type >= 3;
    // the same light rules as the reference: hard lights see nothing behind the tangent plane,
    // spot lights nothing outside their cone, one-sided emitters nothing behind their plane
    if (!area && dot(n, to_light) <= 0.0) { o_visibility = 0.0; return; }
    if (u_light_type == 1 && dot(normalize(p - u_light_position), u_light_direction) < u_light_cos_cone) { o_visibility = 0.0; return; }
    if ((u_light_type == 3 || u_light_type == 4) && dot(p - u_light_position, u_light_direction) <= 0.0) { o_visibility = 0.0; return; }
    o_visibility = clamp(technique_visibility(p, n), 0.0, 1.0);
}
)";
}

void fit_box_depth(const glm::mat4& view, const glm::vec3& lo, const glm::vec3& hi, float& znear, float& zfar,
                   float& tan_max) {
    float zmin = INFINITY, zmax = 0.f;
    tan_max = 0.f;
    for (int i = 0; i < 8; ++i) {
        const glm::vec3 c((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
        const glm::vec3 v = glm::vec3(view * glm::vec4(c, 1.f));
        zmax = std::max(zmax, -v.z);
        zmin = std::min(zmin, -v.z);
        if (-v.z > 1e-6f) tan_max = std::max(tan_max, std::max(std::abs(v.x), std::abs(v.y)) / -v.z);
    }
    zfar = zmax * 1.01f;
    znear = std::max(zmin * 0.9f, zfar * 2e-3f);
}

LightMatrices fit_light(const Scene& s) {
    LightMatrices m;
    const glm::vec3 lo = s.bounds_min(), hi = s.bounds_max();
    const glm::vec3 center = 0.5f * (lo + hi);
    const float radius = 0.5f * glm::length(hi - lo);
    const Light& L = s.light;
    glm::vec3 dir = glm::normalize(L.direction);
    // lights without a facing direction (sphere, point; a line light's direction is its axis)
    // look at the scene's centre
    if (L.type == LightType::Sphere || L.type == LightType::Point || L.type == LightType::Linear)
        dir = glm::normalize(center - L.position);
    const glm::vec3 up = std::abs(dir.y) > 0.9f ? glm::vec3(0.f, 0.f, 1.f) : glm::vec3(0.f, 1.f, 0.f);
    if (L.type == LightType::Directional) {
        m.perspective = false;
        m.view = glm::lookAt(center - dir * radius * 2.f, center, up);
        // orthographic fit to the scene's bounding box corners in light space
        glm::vec3 a(INFINITY), b(-INFINITY);
        for (int i = 0; i < 8; ++i) {
            const glm::vec3 c((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
            const glm::vec3 v = glm::vec3(m.view * glm::vec4(c, 1.f));
            a = glm::min(a, v);
            b = glm::max(b, v);
        }
        m.znear = -b.z - 1e-3f * radius;
        m.zfar = -a.z + 1e-3f * radius;
        m.proj = glm::ortho(a.x, b.x, a.y, b.y, m.znear, m.zfar);
        return m;
    }
    m.view = glm::lookAt(L.position, L.position + dir, up);
    float tan_max = 0.f;
    fit_box_depth(m.view, lo, hi, m.znear, m.zfar, tan_max);
    float half = L.spot_half_angle;
    if (L.type == LightType::Sphere || L.type == LightType::Linear) half = std::min(std::atan(tan_max), 1.4f);
    m.proj = glm::perspective(2.f * half, 1.f, m.znear, m.zfar);
    return m;
}

void set_light_uniforms(GLuint prog, const Light& L) {
    glUniform1i(glGetUniformLocation(prog, "u_light_type"), static_cast<int>(L.type));
    glUniform3fv(glGetUniformLocation(prog, "u_light_position"), 1, glm::value_ptr(L.position));
    const glm::vec3 d = glm::normalize(L.direction);
    glUniform3fv(glGetUniformLocation(prog, "u_light_direction"), 1, glm::value_ptr(d));
    glUniform1f(glGetUniformLocation(prog, "u_light_cos_cone"), std::cos(L.spot_half_angle));
}

const char* depth_only_vs() {
    return R"(#version 450 core
layout(location = 0) in vec3 a_position;
uniform mat4 u_light_view_proj;
void main() { gl_Position = u_light_view_proj * vec4(a_position, 1.0); }
)";
}
const char* depth_only_fs() { return "#version 450 core\nvoid main() {}\n"; }

VisibilityPass::~VisibilityPass() {
    skgl::destroy_target(target);
    if (vao) glDeleteVertexArrays(1, &vao);
}

bool VisibilityPass::init(int w, int h, std::string& why) {
    glGenVertexArrays(1, &vao);
    return skgl::make_target(target, w, h, {GL_R32F}, 0, why);
}

void VisibilityPass::draw(GLuint prog, const SceneGpu& gpu) {
    glBindFramebuffer(GL_FRAMEBUFFER, target.fbo);
    glViewport(0, 0, target.width, target.height);
    glDisable(GL_DEPTH_TEST);
    glUseProgram(prog);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, gpu.gbuffer.color[0]);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, gpu.gbuffer.color[1]);
    glBindVertexArray(vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
}

void VisibilityPass::draw(GLuint prog, const SceneGpu& gpu, GLenum map_target, GLuint map) {
    glActiveTexture(GL_TEXTURE2);
    glBindTexture(map_target, map);
    draw(prog, gpu);
}

void measure_visibility(RunResult& r, const RunContext& ctx, const VisibilityPass& pass,
                        const std::function<void()>& frame) {
    r.gpu_ms = skgl::median_frame_ms(frame, ctx.warmup, ctx.frames);
    r.frames = ctx.frames;
    r.visibility = skgl::read_color_float(pass.target, 0, 1);
}

RunResult finish_run(RunResult r, std::initializer_list<GLuint> programs, const std::function<void()>& release) {
    const std::string err = skgl::gl_error_string();
    for (GLuint p : programs) glDeleteProgram(p);
    if (release) release();
    if (!err.empty()) return RunResult::failure(err);
    return r;
}

void draw_casters(const SceneGpu& gpu, const std::vector<std::uint32_t>* only) {
    if (only) {
        for (std::uint32_t i : *only)
            if (i < gpu.meshes.size() && gpu.caster[i]) skgl::draw_mesh(gpu.meshes[i]);
        return;
    }
    for (std::size_t i = 0; i < gpu.meshes.size(); ++i)
        if (gpu.caster[i]) skgl::draw_mesh(gpu.meshes[i]);
}

GLuint compile_depth_only_program(std::string& log) {
    return skgl::compile_program({{GL_VERTEX_SHADER, depth_only_vs()}, {GL_FRAGMENT_SHADER, depth_only_fs()}}, log);
}

GLuint compile_visibility_program(const std::string& snippets, const std::string& body, std::string& log) {
    return skgl::compile_program(
        {{GL_VERTEX_SHADER, fullscreen_vertex_shader()}, {GL_FRAGMENT_SHADER, visibility_fragment_shader(snippets, body)}}, log);
}

bool compile_shadow_programs(const std::string& snippet, const std::string& body, const Light& L, GLuint& depth,
                             GLuint& vis, std::string& why) {
    const std::string text = snippet.empty() ? std::string() : load_snippet(snippet, why);
    if (!snippet.empty() && text.empty()) return false;
    std::string log;
    depth = compile_depth_only_program(log);
    vis = compile_visibility_program(text, body, log);
    if (!depth || !vis) {
        why = log;
        return false;
    }
    glUseProgram(vis);
    set_light_uniforms(vis, L);
    return true;
}

bool make_shadow_map_target(skgl::Target& sm, int size, std::string& why) {
    if (!skgl::make_target(sm, size, size, {}, GL_DEPTH_COMPONENT32F, why)) return false;
    skgl::set_depth_compare(sm.depth, true, true);
    return true;
}

void render_shadow_depth(const SceneGpu& gpu, GLuint fbo, int size, GLuint depth_prog, const glm::mat4& light_vp,
                         const std::vector<std::uint32_t>* only) {
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, size, size);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glClear(GL_DEPTH_BUFFER_BIT);
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(2.f, 2.f);
    glUseProgram(depth_prog);
    glUniformMatrix4fv(glGetUniformLocation(depth_prog, "u_light_view_proj"), 1, GL_FALSE, glm::value_ptr(light_vp));
    draw_casters(gpu, only);
    glDisable(GL_POLYGON_OFFSET_FILL);
}

const SingleMapLookup& plain_shadow_map_lookup() {
    static const SingleMapLookup lookup{"shadow_map", R"(
layout(binding = 2) uniform sampler2DShadow u_shadow_map;
uniform mat4 u_light_view_proj;
float technique_visibility(vec3 p, vec3 n) {
    return sk_shadow_map_visibility(u_shadow_map, u_light_view_proj, p, false, 0.0, 1.0);
}
)", "u_light_view_proj"};
    return lookup;
}

RunResult run_single_shadow_map(const RunContext& ctx, RunResult r, int size, const glm::mat4& light_vp,
                                const SingleMapLookup& lookup, const std::vector<std::uint32_t>* only,
                                const std::function<void(RunResult&, const skgl::Target&)>& extras) {
    std::string why;
    skgl::Target sm;
    if (!make_shadow_map_target(sm, size, why)) return RunResult::failure(why);
    VisibilityPass pass;
    if (!pass.init(ctx.gpu.width, ctx.gpu.height, why)) return RunResult::failure(why);
    GLuint depth = 0, vis = 0;
    if (!compile_shadow_programs(lookup.snippet, lookup.body, ctx.scene.light, depth, vis, why))
        return RunResult::failure(why);
    glUniformMatrix4fv(glGetUniformLocation(vis, lookup.matrix_uniform), 1, GL_FALSE, glm::value_ptr(light_vp));
    measure_visibility(r, ctx, pass, [&] {
        render_shadow_depth(ctx.gpu, sm.fbo, size, depth, light_vp, only);
        pass.draw(vis, ctx.gpu, GL_TEXTURE_2D, sm.depth);
    });
    r.gpu_bytes = std::int64_t(size) * size * 4;
    if (extras) extras(r, sm);
    return finish_run(std::move(r), {depth, vis}, [&] { skgl::destroy_target(sm); });
}

GLuint make_depth_compare_texture(GLenum target, int size, int layers) {
    GLuint tex = 0;
    glGenTextures(1, &tex);
    glBindTexture(target, tex);
    if (target == GL_TEXTURE_2D_ARRAY) glTexStorage3D(target, 1, GL_DEPTH_COMPONENT32F, size, size, layers);
    else glTexStorage2D(target, 1, GL_DEPTH_COMPONENT32F, size, size);
    glTexParameteri(target, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(target, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(target, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(target, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTexParameteri(target, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glTexParameteri(target, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    return tex;
}

void make_depth_layer_fbos(GLenum target, GLuint tex, int count, GLuint* fbo) {
    glGenFramebuffers(count, fbo);
    for (int i = 0; i < count; ++i) {
        glBindFramebuffer(GL_FRAMEBUFFER, fbo[i]);
        if (target == GL_TEXTURE_CUBE_MAP)
            glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT,
                                   static_cast<GLenum>(GL_TEXTURE_CUBE_MAP_POSITIVE_X + i), tex, 0);
        else
            glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, tex, 0, i);
        glDrawBuffer(GL_NONE);
        glReadBuffer(GL_NONE);
    }
}

void set_nearest_clamped(GLuint tex) {
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

void begin_offset_depth_pass(GLuint depth_prog) {
    glUseProgram(depth_prog);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(2.f, 2.f);
}

void clear_depth_layer(GLuint fbo, int size) {
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, size, size);
    glClear(GL_DEPTH_BUFFER_BIT);
}

void render_depth_layers(const SceneGpu& gpu, const GLuint* fbo, const glm::mat4* vps, int count, int size,
                         GLuint depth_prog, bool every_mesh) {
    begin_offset_depth_pass(depth_prog);
    for (int i = 0; i < count; ++i) {
        clear_depth_layer(fbo[i], size);
        glUniformMatrix4fv(glGetUniformLocation(depth_prog, "u_light_view_proj"), 1, GL_FALSE, glm::value_ptr(vps[i]));
        if (every_mesh)
            for (const auto& m : gpu.meshes) skgl::draw_mesh(m);
        else
            draw_casters(gpu);
    }
    glDisable(GL_POLYGON_OFFSET_FILL);
}

std::size_t caster_count(const SceneGpu& gpu) {
    std::size_t n = 0;
    for (bool c : gpu.caster) n += c ? 1 : 0;
    return n;
}

void mesh_bounds(const Mesh& m, glm::vec3& lo, glm::vec3& hi) {
    lo = glm::vec3(INFINITY);
    hi = glm::vec3(-INFINITY);
    for (const auto& p : m.positions) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
}

void spot_cone_box(const Light& L, const glm::vec3& lo, const glm::vec3& hi, float max_half_angle, glm::vec3& clo,
                   glm::vec3& chi) {
    float far_d = 0.f;
    for (int i = 0; i < 8; ++i) {
        const glm::vec3 c((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
        far_d = std::max(far_d, glm::length(c - L.position));
    }
    const glm::vec3 d = glm::normalize(L.direction);
    const glm::vec3 cap = L.position + d * far_d;
    const float r = far_d * std::tan(std::min(L.spot_half_angle, max_half_angle));
    // the cap disk's extent along each axis: r * sqrt(1 - d_axis^2)
    const glm::vec3 ext = r * glm::sqrt(glm::max(glm::vec3(0.f), 1.f - d * d));
    clo = glm::min(L.position, cap - ext);
    chi = glm::max(L.position, cap + ext);
}

bool build_caster_adjacency(const Mesh& m, shadowkit::SilhouetteAdjacency& adj, std::string& error) {
    adj = shadowkit::silhouette_build_adjacency(m.positions.data(), m.positions.size(), m.indices.data(), m.indices.size());
    if (adj.status == shadowkit::Status::Ok) return true;
    error = "silhouette_build_adjacency failed on mesh '" + m.name + "' (status " + shadowkit::status_name(adj.status) +
            ")";
    return false;
}

namespace {

// --------------------------------------------------------------------------- unshadowed (V = 1)
// A deliberately wrong technique: proves that the instrument gives a large error when it should.
class Unshadowed final : public Technique {
public:
    std::string name() const override { return "unshadowed"; }
    std::string description() const override { return "V = 1 wherever the light's rules allow (no shadows): instrument check"; }
    bool hard() const override { return true; }
    bool listed_by_default() const override { return false; }
    std::vector<ParamSet> sweep(const Scene&, bool) const override { return {ParamSet{}}; }
    RunResult run(const RunContext& ctx, const ParamSet&) override {
        RunResult r;
        std::string why;
        VisibilityPass pass;
        if (!pass.init(ctx.gpu.width, ctx.gpu.height, why)) return RunResult::failure(why);
        std::string log;
        GLuint prog = compile_visibility_program("", "float technique_visibility(vec3 p, vec3 n) { return 1.0; }", log);
        if (!prog) return RunResult::failure(log);
        glUseProgram(prog);
        set_light_uniforms(prog, ctx.scene.light);
        measure_visibility(r, ctx, pass, [&] { pass.draw(prog, ctx.gpu); });
        glDeleteProgram(prog);
        return r;
    }
};

// --------------------------------------------------------------------------- plain shadow map
// Williams 1978 with the hardware 2x2 percentage-closer filter (GL_LINEAR on a compare texture)
// and slope-scaled polygon offset. Spot/area/sphere lights: one perspective map from the light's
// centre; directional: orthographic fit to the scene; point: a cube map of six 90-degree faces.
class PlainShadowMap final : public Technique {
public:
    std::string name() const override { return "shadow_map"; }
    std::string description() const override {
        return "plain shadow map, 2x2 hardware PCF, slope-scaled polygon offset (baseline)";
    }
    bool hard() const override { return true; }
    std::vector<ParamSet> sweep(const Scene&, bool quick) const override {
        std::vector<ParamSet> out;
        const std::vector<int> sizes = quick ? std::vector<int>{512, 2048} : std::vector<int>{512, 1024, 2048, 4096};
        for (int s : sizes) out.push_back(ParamSet{{{"size", double(s)}}});
        return out;
    }
    RunResult run(const RunContext& ctx, const ParamSet& params) override {
        const int size = static_cast<int>(params.get("size", 1024));
        if (ctx.scene.light.type == LightType::Point) return run_cube(ctx, size);
        RunResult r;
        const auto c0 = Clock::now();
        const LightMatrices lm = fit_light(ctx.scene);
        const glm::mat4 light_vp = lm.proj * lm.view;
        r.cpu_ms = ms_since(c0);
        r.work = {{"shadow_map_texels", double(size) * size},
                  {"triangles_drawn", double(ctx.gpu.caster_triangles)},
                  {"casters_drawn", double(caster_count(ctx.gpu))},
                  {"casters_culled", 0.0}};
        return run_single_shadow_map(ctx, std::move(r), size, light_vp, plain_shadow_map_lookup());
    }

private:
    RunResult run_cube(const RunContext& ctx, int size) {
        RunResult r;
        std::string why;
        const Light& L = ctx.scene.light;
        const glm::vec3 lo = ctx.scene.bounds_min(), hi = ctx.scene.bounds_max();
        float far_plane = 0.f;
        for (int i = 0; i < 8; ++i) {
            const glm::vec3 c((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
            far_plane = std::max(far_plane, glm::length(c - L.position));
        }
        far_plane *= 1.01f;
        const float near_plane = far_plane * 2e-3f;
        const glm::mat4 proj = glm::perspective(glm::radians(90.f), 1.f, near_plane, far_plane);
        // cube-map face orientation (GL spec 8.13, major axis -> s, t)
        const glm::vec3 dirs[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
        const glm::vec3 ups[6] = {{0, -1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0, -1, 0}, {0, -1, 0}};
        glm::mat4 face_vp[6];
        for (int f = 0; f < 6; ++f) face_vp[f] = proj * glm::lookAt(L.position, L.position + dirs[f], ups[f]);
        GLuint cube = 0;
        glGenTextures(1, &cube);
        glBindTexture(GL_TEXTURE_CUBE_MAP, cube);
        glTexStorage2D(GL_TEXTURE_CUBE_MAP, 1, GL_DEPTH_COMPONENT32F, size, size);
        glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
        glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
        glEnable(GL_TEXTURE_CUBE_MAP_SEAMLESS);
        GLuint fbo[6];
        make_depth_layer_fbos(GL_TEXTURE_CUBE_MAP, cube, 6, fbo);
        VisibilityPass pass;
        if (!pass.init(ctx.gpu.width, ctx.gpu.height, why)) return RunResult::failure(why);
        GLuint depth = 0, vis = 0;
        if (!compile_shadow_programs("shadow_map", R"(
layout(binding = 2) uniform samplerCubeShadow u_cube;
uniform vec3 u_cube_light;
uniform float u_cube_near;
uniform float u_cube_far;
float technique_visibility(vec3 p, vec3 n) {
    return sk_cube_shadow_visibility(u_cube, vec4(u_cube_light, 1.0), p, u_cube_near, u_cube_far, 0.0);
}
)", L, depth, vis, why))
            return RunResult::failure(why);
        glUniform3fv(glGetUniformLocation(vis, "u_cube_light"), 1, glm::value_ptr(L.position));
        glUniform1f(glGetUniformLocation(vis, "u_cube_near"), near_plane);
        glUniform1f(glGetUniformLocation(vis, "u_cube_far"), far_plane);
        measure_visibility(r, ctx, pass, [&] {
            render_depth_layers(ctx.gpu, fbo, face_vp, 6, size, depth);
            pass.draw(vis, ctx.gpu, GL_TEXTURE_CUBE_MAP, cube);
        });
        r.gpu_bytes = std::int64_t(size) * size * 4 * 6;
        const std::size_t casters = caster_count(ctx.gpu);
        r.work = {{"shadow_map_texels", 6.0 * size * size},
                  {"triangles_drawn", 6.0 * double(ctx.gpu.caster_triangles)},
                  {"casters_drawn", 6.0 * double(casters)},
                  {"casters_culled", 0.0}};
        return finish_run(std::move(r), {depth, vis}, [&] {
            glDeleteFramebuffers(6, fbo);
            glDeleteTextures(1, &cube);
        });
    }
};

}  // namespace

std::vector<std::unique_ptr<Technique>> make_techniques() {
    std::vector<std::unique_ptr<Technique>> t;
    t.push_back(std::make_unique<PlainShadowMap>());
    add_warp_techniques(t);
    add_soft_techniques(t);
    add_volume_techniques(t);
    add_smoothie_techniques(t);
    add_wedge_techniques(t);
    add_omni_techniques(t);
    add_silmap_techniques(t);
    add_linear_techniques(t);
    t.push_back(std::make_unique<Unshadowed>());
    return t;
}

}  // namespace sk
