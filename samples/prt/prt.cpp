// samples/prt/prt.cpp - precomputed radiance transfer, top to bottom:
//   init        once per scene: every mesh into one vertex buffer (position, albedo) and index buffer,
//               the environment projected into SH (prt_project_environment, order 5), the program
//               (glsl/prt.glsl), an RGBA8 + depth target
//   precompute  CPU + Embree, when the sampling changes: per vertex the SH projection of the incoming
//               light's transfer (cosine x visibility, or cosine only) over strata^2 directions
//               (prt_compute_transfer through prt_scene.hpp's threads), into two storage buffers
//   update      CPU, every frame: the environment's coefficients turned (sh_make_rotation, sh_rotate)
//   render      GPU, every frame: the meshes with depth test and back-face culling; per vertex
//               radiance = albedo x dot(transfer, environment) (sk_prt_shade_vertex), Gouraud,
//               tone-mapped in the fragment shader
#include "prt.hpp"

#include <shadowkit/spherical_harmonics.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>

namespace {

const char* kVertexMain = R"(
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_albedo;
uniform mat4 u_view_proj;
uniform vec3 u_env[25];
uniform int u_count;
uniform int u_stride;
out vec3 v_radiance;
void main() {
    v_radiance = a_albedo * sk_prt_shade_vertex(gl_VertexID, u_stride, u_count, u_env);
    gl_Position = u_view_proj * vec4(a_position, 1.0);
}
)";
const char* kFragmentMain = R"(
in vec3 v_radiance;
uniform float u_exposure;
layout(location = 0) out vec4 o_color;
void main() {
    vec3 c = 1.0 - exp(-max(v_radiance, vec3(0.0)) * u_exposure);
    o_color = vec4(pow(c, vec3(1.0 / 2.2)), 1.0);
}
)";

// Albedo by mesh index (a Scene has no colors): the prt scene's floor, blob and box, then again.
const glm::vec3 kAlbedo[3] = {{0.8f, 0.78f, 0.74f}, {0.85f, 0.55f, 0.35f}, {0.45f, 0.6f, 0.85f}};

// The azimuth of the direction toward the light (a directional light's -direction, else its position
// seen from the scene's center), about the vertical axis.
float light_azimuth(const sk::Scene& scene) {
    const sk::Light& L = scene.light;
    const glm::vec3 toward = L.type == sk::LightType::Directional
                                 ? -L.direction
                                 : L.position - 0.5f * (scene.bounds_min() + scene.bounds_max());
    return std::atan2(toward.x, toward.z);
}

}  // namespace

sk::Scene prt_app_scene() {
    const skprt::PrtScene p = skprt::make_prt_scene(1);
    sk::Scene s;
    s.name = "prt";
    s.description = "a lumpy blob and a box over a finely tessellated floor under a sky + sun environment (samples/prt)";
    const char* names[3] = {"floor", "blob", "box"};
    for (std::size_t k = 0; k < p.part_begin.size(); ++k) {
        const std::size_t begin = p.part_begin[k], end = k + 1 < p.part_begin.size() ? p.part_begin[k + 1] : p.positions.size();
        sk::Mesh m;
        m.name = names[k % 3];
        m.positions.assign(p.positions.begin() + std::ptrdiff_t(begin), p.positions.begin() + std::ptrdiff_t(end));
        m.normals.assign(p.normals.begin() + std::ptrdiff_t(begin), p.normals.begin() + std::ptrdiff_t(end));
        for (std::size_t t = 0; t + 2 < p.indices.size(); t += 3)
            if (p.indices[t] >= begin && p.indices[t] < end)
                for (std::size_t c = 0; c < 3; ++c) m.indices.push_back(p.indices[t + c] - static_cast<std::uint32_t>(begin));
        s.meshes.push_back(std::move(m));
    }
    s.camera.eye = {2.3f, 2.4f, 3.6f};
    s.camera.target = {0.15f, 0.35f, 0.f};
    s.camera.fovy = 0.75f;
    s.camera.zfar = 50.f;
    s.light.type = sk::LightType::Directional;
    s.light.direction = -skprt::Environment().sun_dir;
    s.light.position = 4.f * skprt::Environment().sun_dir;
    return s;
}

bool Prt::init(const app::View& v, std::string& why) {
    release();
    const sk::Scene& scene = *v.scene;
    GLint blocks = 0;
    glGetIntegerv(GL_MAX_VERTEX_SHADER_STORAGE_BLOCKS, &blocks);
    if (blocks < 1) {
        why = "the GL implementation has no shader storage blocks in the vertex stage";
        return false;
    }
    // every mesh in one: positions, normals (what the transfer integrates around), albedo, indices
    mesh_ = skprt::PrtScene{};
    for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
        const sk::Mesh& m = scene.meshes[i];
        if (m.normals.size() != m.positions.size()) {
            why = "PRT needs a normal per vertex; mesh '" + m.name + "' has none";
            return false;
        }
        const auto base = static_cast<std::uint32_t>(mesh_.positions.size());
        mesh_.positions.insert(mesh_.positions.end(), m.positions.begin(), m.positions.end());
        mesh_.normals.insert(mesh_.normals.end(), m.normals.begin(), m.normals.end());
        mesh_.albedo.insert(mesh_.albedo.end(), m.positions.size(), kAlbedo[i % 3]);
        for (std::uint32_t k : m.indices) mesh_.indices.push_back(base + k);
    }
    const glm::vec3 extent = scene.bounds_max() - scene.bounds_min();
    mesh_.size = std::max(extent.x, std::max(extent.y, extent.z));  // the rays' start offset scales with it

    // the environment (sky + sun) in SH, order 5, from 128^2 stratified directions
    const skprt::Environment environment;
    const shadowkit::PrtSamples env_samples = shadowkit::prt_make_samples(5, 128, 7u);
    env_.assign(25, glm::vec3(0.f));
    if (shadowkit::prt_project_environment(env_samples, environment, env_.data(), env_.size()).status !=
        shadowkit::Status::Ok) {
        why = "prt_project_environment failed";
        return false;
    }
    base_azimuth_ = light_azimuth(scene);

    // the program: glsl/prt.glsl's storage buffer of transfer vectors (binding 0) and sk_prt_shade_vertex
    const std::string snippet = app::load_snippet("prt", why);
    if (snippet.empty()) return false;
    program_ = skgl::compile_program({{GL_VERTEX_SHADER, "#version 450 core\n" + snippet + kVertexMain},
                                      {GL_FRAGMENT_SHADER, std::string("#version 450 core\n") + kFragmentMain}},
                                     why);
    if (!program_) return false;
    // one vertex buffer (position, albedo), one index buffer: gl_VertexID indexes the transfer
    std::vector<float> vb;
    vb.reserve(mesh_.positions.size() * 6);
    for (std::size_t i = 0; i < mesh_.positions.size(); ++i)
        vb.insert(vb.end(), {mesh_.positions[i].x, mesh_.positions[i].y, mesh_.positions[i].z, mesh_.albedo[i].x,
                             mesh_.albedo[i].y, mesh_.albedo[i].z});
    glGenVertexArrays(1, &vao_);
    glBindVertexArray(vao_);
    glGenBuffers(1, &vbo_);
    glBindBuffer(GL_ARRAY_BUFFER, vbo_);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vb.size() * sizeof(float)), vb.data(), GL_STATIC_DRAW);
    glGenBuffers(1, &ibo_);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ibo_);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(mesh_.indices.size() * sizeof(std::uint32_t)),
                 mesh_.indices.data(), GL_STATIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), reinterpret_cast<const void*>(3 * sizeof(float)));
    glBindVertexArray(0);
    glGenBuffers(2, ssbo_);
    return skgl::make_target(target_, v.width, v.height, {GL_RGBA8}, GL_DEPTH_COMPONENT24, why);
}

void Prt::precompute(const app::View&, const PrtSettings& s) {
    if (s.strata == strata_) return;
    // Embree visibility of the whole scene; strata^2 directions (order 5: orders 1..4 are prefixes)
    skprt::EmbreeVisibility vis;
    const shadowkit::PrtSamples samples = shadowkit::prt_make_samples(5, s.strata, 1u);
    if (!vis.build(mesh_, error_) || samples.status != shadowkit::Status::Ok) {
        if (error_.empty()) error_ = std::string("prt_make_samples: ") + shadowkit::status_name(samples.status);
        return;
    }
    std::vector<float> transfer[2];
    double unshadowed_seconds = 0.0;
    const shadowkit::PrtTransferResult shadowed =
        skprt::compute_transfer(mesh_, vis, samples, shadowkit::PrtMode::Shadowed, transfer[0], seconds_);
    const shadowkit::PrtTransferResult unshadowed = skprt::compute_transfer(
        mesh_, vis, samples, shadowkit::PrtMode::Unshadowed, transfer[1], unshadowed_seconds, false);
    if (shadowed.status != shadowkit::Status::Ok || unshadowed.status != shadowkit::Status::Ok) {
        error_ = "prt_compute_transfer failed";
        return;
    }
    // 25 floats per vertex, tightly packed (std430 float arrays have no padding): the vectors as computed
    for (int k = 0; k < 2; ++k) {
        glBindBuffer(GL_SHADER_STORAGE_BUFFER, ssbo_[k]);
        glBufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(transfer[k].size() * sizeof(float)),
                     transfer[k].data(), GL_STATIC_DRAW);
    }
    strata_ = s.strata;
}

void Prt::update(const app::View& v, const PrtSettings& s) {
    // the environment turned by yaw (and by as much as the light turned about the vertical since
    // init), then pitch: R acts on directions, the rotated coefficients represent env(R^T s)
    const float yaw = glm::radians(s.yaw) + light_azimuth(*v.scene) - base_azimuth_;
    const glm::mat3 R = glm::mat3(glm::rotate(glm::mat4(1.f), yaw, glm::vec3(0, 1, 0)) *
                                  glm::rotate(glm::mat4(1.f), glm::radians(s.pitch), glm::vec3(1, 0, 0)));
    const shadowkit::SHRotation rot = shadowkit::sh_make_rotation(5, R);
    if (rot.status != shadowkit::Status::Ok) {
        error_ = std::string("sh_make_rotation: ") + shadowkit::status_name(rot.status);
        return;
    }
    env_rotated_.assign(25, glm::vec3(0.f));
    for (int c = 0; c < 3; ++c) {  // one channel at a time
        float ch[25];
        for (std::size_t i = 0; i < 25; ++i) ch[i] = env_[i][c];
        shadowkit::sh_rotate(rot, ch, 25, ch, 25);
        for (std::size_t i = 0; i < 25; ++i) env_rotated_[i][c] = ch[i];
    }
}

void Prt::render(const app::View& v, const PrtSettings& s) {
    draw(v, env_rotated_.data(), s.order * s.order, s.shadows, s.exposure);
}

// The ambient occlusion: the shadowed transfer's band 0 lit by a constant environment (coefficient
// 0 only): how much of the cosine-weighted sky each vertex sees.
app::DebugImage Prt::debug_occlusion(const app::View& v) {
    std::vector<glm::vec3> constant(25, glm::vec3(0.f));
    constant[0] = glm::vec3(std::sqrt(4.f * 3.14159265f));  // a radiance of 1 in every direction
    draw(v, constant.data(), 1, true, 1.f);
    return {color(), app::DebugImage::Show::Value};
}

void Prt::draw(const app::View& v, const glm::vec3* env, int count, bool shadows, float exposure) {
    // The meshes into our target with the camera: depth test GL_LESS, back faces culled; the transfer
    // (shadowed or unshadowed) at storage-buffer binding 0; the first count = order^2 coefficients shade.
    glBindFramebuffer(GL_FRAMEBUFFER, target_.fbo);
    glViewport(0, 0, target_.width, target_.height);
    glClearColor(0.05f, 0.06f, 0.08f, 1.f);
    glClearDepth(1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glClearColor(0.f, 0.f, 0.f, 0.f);
    if (strata_ == 0 || env_rotated_.size() != 25) return;  // (precompute() and update() first)
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glEnable(GL_CULL_FACE);
    glUseProgram(program_);
    const glm::mat4 view_proj = v.proj * v.view;
    glUniformMatrix4fv(glGetUniformLocation(program_, "u_view_proj"), 1, GL_FALSE, glm::value_ptr(view_proj));
    glUniform3fv(glGetUniformLocation(program_, "u_env"), 25, glm::value_ptr(env[0]));
    glUniform1i(glGetUniformLocation(program_, "u_count"), count);
    glUniform1i(glGetUniformLocation(program_, "u_stride"), 25);
    glUniform1f(glGetUniformLocation(program_, "u_exposure"), exposure);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, ssbo_[shadows ? 0 : 1]);
    glBindVertexArray(vao_);
    glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(mesh_.indices.size()), GL_UNSIGNED_INT, nullptr);
    glBindVertexArray(0);
    glDisable(GL_CULL_FACE);
    glDisable(GL_DEPTH_TEST);
}

void Prt::release() {  // (no GL call without objects: the App may have no context)
    if (ssbo_[0]) glDeleteBuffers(2, ssbo_);
    if (ibo_) glDeleteBuffers(1, &ibo_);
    if (vbo_) glDeleteBuffers(1, &vbo_);
    if (vao_) glDeleteVertexArrays(1, &vao_);
    if (program_) glDeleteProgram(program_);
    ssbo_[0] = ssbo_[1] = ibo_ = vbo_ = vao_ = program_ = 0;
    skgl::destroy_target(target_);
    strata_ = 0;
    error_.clear();
}
