// samples/app/gbuffer.cpp - the camera G-buffer, the V pass every technique ends with, the composite.
#include "gbuffer.hpp"

#include <glm/gtc/type_ptr.hpp>

#include <cmath>

namespace app {

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

SceneGpu::~SceneGpu() {
    for (auto& m : meshes) skgl::destroy_mesh(m);
    skgl::destroy_target(gbuffer);
    if (gbuffer_program) glDeleteProgram(gbuffer_program);
}

void upload_scene(const sk::Scene& scene, SceneGpu& gpu) {
    for (auto& m : gpu.meshes) skgl::destroy_mesh(m);
    gpu.meshes.clear();
    gpu.caster.clear();
    gpu.caster_triangles = 0;
    for (const auto& m : scene.meshes) {
        gpu.meshes.push_back(skgl::upload_mesh(&m.positions[0].x, &m.normals[0].x, m.positions.size(), m.indices.data(),
                                               m.indices.size()));
        gpu.caster.push_back(m.caster);
        if (m.caster) gpu.caster_triangles += m.indices.size() / 3;
    }
}

bool render_gbuffer(const sk::Scene& scene, const sk::Camera& camera, int width, int height, SceneGpu& gpu,
                    std::string& why) {
    if (width <= 0 || height <= 0) {
        why = "size must be positive";
        return false;
    }
    if (gpu.gbuffer.fbo == 0 || gpu.width != width || gpu.height != height) {
        skgl::destroy_target(gpu.gbuffer);
        if (!skgl::make_target(gpu.gbuffer, width, height, {GL_RGBA32F, GL_RGBA32F}, GL_DEPTH32F_STENCIL8, why))
            return false;
    }
    if (!gpu.gbuffer_program) {
        std::string log;
        gpu.gbuffer_program = skgl::compile_program({{GL_VERTEX_SHADER, kGbufferVS}, {GL_FRAGMENT_SHADER, kGbufferFS}}, log);
        if (!gpu.gbuffer_program) {
            why = log;
            return false;
        }
    }
    gpu.width = width;
    gpu.height = height;
    gpu.camera = camera;
    gpu.view = camera.view();
    gpu.proj = camera.projection(float(width) / float(height));
    const glm::mat4 vp = gpu.proj * gpu.view;
    const GLuint prog = gpu.gbuffer_program;
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
    glUniform3fv(glGetUniformLocation(prog, "u_eye"), 1, glm::value_ptr(camera.eye));
    for (std::size_t i = 0; i < scene.meshes.size() && i < gpu.meshes.size(); ++i) {
        glUniform1f(glGetUniformLocation(prog, "u_kind"), scene.meshes[i].receiver ? 1.f : 2.f);
        skgl::draw_mesh(gpu.meshes[i]);
    }
    const std::string err = skgl::gl_error_string();
    if (!err.empty()) {
        why = "G-buffer pass: " + err;
        return false;
    }
    return true;
}

View make_view(const sk::Scene& scene, const SceneGpu& gpu) { return make_view(scene, gpu, gpu.camera); }

View make_view(const sk::Scene& scene, const SceneGpu& gpu, const sk::Camera& fit_camera) {
    View v;
    v.scene = &scene;
    v.gpu = &gpu;
    v.camera = fit_camera;
    v.width = gpu.width;
    v.height = gpu.height;
    v.view = fit_camera.view();
    v.proj = fit_camera.projection(float(gpu.width) / float(gpu.height));
    return v;
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

GLuint compile_fullscreen_program(const std::string& fragment_shader, std::string& why) {
    std::string log;
    const GLuint prog = skgl::compile_program({{GL_VERTEX_SHADER, fullscreen_vertex_shader()}, {GL_FRAGMENT_SHADER, fragment_shader}}, log);
    if (!prog) why = log;
    return prog;
}

glm::ivec2 begin_fullscreen_pass() {
    GLint vp[4] = {0, 0, 1, 1};
    glGetIntegerv(GL_VIEWPORT, vp);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_STENCIL_TEST);
    glDisable(GL_SCISSOR_TEST);
    return {vp[2], vp[3]};
}

GLuint compile_visibility_program(const std::string& snippets, const std::string& body, std::string& log) {
    return skgl::compile_program(
        {{GL_VERTEX_SHADER, fullscreen_vertex_shader()}, {GL_FRAGMENT_SHADER, visibility_fragment_shader(snippets, body)}}, log);
}

void set_light_uniforms(GLuint prog, const sk::Light& L) {
    glUniform1i(glGetUniformLocation(prog, "u_light_type"), static_cast<int>(L.type));
    glUniform3fv(glGetUniformLocation(prog, "u_light_position"), 1, glm::value_ptr(L.position));
    const glm::vec3 d = glm::normalize(L.direction);
    glUniform3fv(glGetUniformLocation(prog, "u_light_direction"), 1, glm::value_ptr(d));
    glUniform1f(glGetUniformLocation(prog, "u_light_cos_cone"), std::cos(L.spot_half_angle));
}

const char* emitter_horizon_glsl() {
    return R"(
uniform int u_emitter;       // 0 none, 1 rect, 2 disk, 3 sphere
uniform vec3 u_emitter_c;    // center
uniform vec3 u_emitter_t;    // rect: half-edge vector; disk: radius vector
uniform vec3 u_emitter_b;    // rect: half-edge vector; disk: radius vector
float sk_emitter_horizon(vec3 p, vec3 n) {
    if (u_emitter == 0) return 1.0;
    float alpha = dot(n, u_emitter_c - p);
    if (u_emitter == 1) {
        float beta = dot(n, u_emitter_t);
        float gamma = dot(n, u_emitter_b);
        float sum = 0.0;
        for (int i = 0; i < 16; ++i) {
            float r = alpha + beta * (-1.0 + (float(i) + 0.5) / 8.0);   // need r + gamma y > 0, |y| <= 1
            if (abs(gamma) < 1e-20) { sum += r > 0.0 ? 2.0 : 0.0; continue; }
            float y0 = -r / gamma;
            sum += gamma > 0.0 ? clamp(1.0 - y0, 0.0, 2.0) : clamp(y0 + 1.0, 0.0, 2.0);
        }
        return sum / 32.0;
    }
    float s;
    if (u_emitter == 3) {
        vec3 w = normalize(u_emitter_c - p);
        s = length(u_emitter_t) * length(n - dot(n, w) * w);
    } else {
        s = length(vec2(dot(n, u_emitter_t), dot(n, u_emitter_b)));
    }
    if (!(s > 1e-20)) return alpha > 0.0 ? 1.0 : 0.0;
    float d = clamp(-alpha / s, -1.0, 1.0);
    return (acos(d) - d * sqrt(1.0 - d * d)) / 3.14159265;
}
)";
}

void emitter_basis(glm::vec3 n, glm::vec3& t, glm::vec3& b) {
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z);
    const float bb = n.x * n.y * a;
    t = glm::vec3(1.0f + sign * n.x * n.x * a, sign * bb, -sign * n.x);
    b = glm::vec3(bb, sign + n.y * n.y * a, -n.y);
}

void set_emitter_uniforms(GLuint prog, const sk::Light& L, bool enabled) {
    int emitter = 0;
    glm::vec3 t(0.f), b(0.f);
    if (enabled) {
        emitter = L.type == sk::LightType::Rect ? 1 : (L.type == sk::LightType::Disk ? 2 : 3);
        emitter_basis(glm::normalize(L.direction), t, b);
        const float r = L.type == sk::LightType::Rect ? 0.5f * L.size : L.size;  // half edge or radius
        t *= r;
        b *= r;
    }
    glUseProgram(prog);
    glUniform1i(glGetUniformLocation(prog, "u_emitter"), emitter);
    glUniform3fv(glGetUniformLocation(prog, "u_emitter_c"), 1, glm::value_ptr(L.position));
    glUniform3fv(glGetUniformLocation(prog, "u_emitter_t"), 1, glm::value_ptr(t));
    glUniform3fv(glGetUniformLocation(prog, "u_emitter_b"), 1, glm::value_ptr(b));
}

VisibilityPass::~VisibilityPass() {
    skgl::destroy_target(target);
    if (vao) glDeleteVertexArrays(1, &vao);
}

bool VisibilityPass::init(int w, int h, std::string& why, GLenum depth_format) {
    if (!vao) glGenVertexArrays(1, &vao);
    skgl::destroy_target(target);
    return skgl::make_target(target, w, h, {GL_R32F}, depth_format, why);
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

Composite::~Composite() {
    if (prog_) glDeleteProgram(prog_);
    if (vao_) glDeleteVertexArrays(1, &vao_);
}

bool Composite::init(std::string& why) {
    if (prog_) return true;
    const char* fs = R"(#version 450 core
layout(binding = 0) uniform sampler2D u_gbuf_position;
layout(binding = 1) uniform sampler2D u_gbuf_normal;
layout(binding = 2) uniform sampler2D u_visibility;
uniform bool u_directional;
uniform vec3 u_light_position;
uniform vec3 u_light_direction;
uniform vec2 u_scale;   // G-buffer pixels per viewport pixel
layout(location = 0) out vec4 o_color;
void main() {
    ivec2 px = ivec2(gl_FragCoord.xy * u_scale);
    vec4 pk = texelFetch(u_gbuf_position, px, 0);
    vec3 c = vec3(0.18, 0.2, 0.24);
    if (pk.w > 0.5) {
        vec3 n = texelFetch(u_gbuf_normal, px, 0).xyz;
        vec3 l = u_directional ? -u_light_direction : normalize(u_light_position - pk.xyz);
        float v = texelFetch(u_visibility, px, 0).r;
        vec3 albedo = pk.w < 1.5 ? vec3(0.85, 0.82, 0.75) : vec3(0.6, 0.7, 0.9);
        c = albedo * (0.15 + 0.85 * v * max(0.0, dot(n, l)));
    }
    o_color = vec4(pow(clamp(c, 0.0, 1.0), vec3(1.0 / 2.2)), 1.0);
}
)";
    prog_ = compile_fullscreen_program(fs, why);
    if (!prog_) return false;
    glGenVertexArrays(1, &vao_);
    return true;
}

void Composite::draw(const SceneGpu& gpu, const sk::Light& light, GLuint visibility) {
    const glm::ivec2 vp = begin_fullscreen_pass();
    glUseProgram(prog_);
    glUniform1i(glGetUniformLocation(prog_, "u_directional"), light.type == sk::LightType::Directional ? 1 : 0);
    glUniform3fv(glGetUniformLocation(prog_, "u_light_position"), 1, glm::value_ptr(light.position));
    const glm::vec3 d = glm::normalize(light.direction);
    glUniform3fv(glGetUniformLocation(prog_, "u_light_direction"), 1, glm::value_ptr(d));
    glUniform2f(glGetUniformLocation(prog_, "u_scale"), float(gpu.width) / float(vp.x), float(gpu.height) / float(vp.y));
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, gpu.gbuffer.color[0]);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, gpu.gbuffer.color[1]);
    glActiveTexture(GL_TEXTURE2);
    glBindTexture(GL_TEXTURE_2D, visibility);
    glBindVertexArray(vao_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
}

}  // namespace app
