// samples/omni_shadows/omni_shadows.cpp - a point light's cube shadow map, top to bottom:
//   init    once per scene: the casters' boxes, the programs, the V target
//   update  CPU, every frame: the range of the stored distance (the farthest scene corner from the
//           light), the six faces' matrices (omni_cube_matrices) and, with culling, the casters whose
//           box meets each face (omni_cull_face_lists)
//   render  GPU, every frame: 1 each face: the linear distance to the light of its casters
//           (sk_omni_linear_depth into gl_FragDepth); 2 V at the G-buffer's points: the distance
//           compared with the receiver-side bias of omni_distance_bias (sk_omni_bias)
// Spot and area lights are point lights at their center here (their cone is the V pass's lighting rule).
#include "omni_shadows.hpp"

#include <shadowkit/omni_shadow.hpp>

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>

namespace {

// The distance pass: the world position to the fragment stage, which stores the linear distance
// to the light over the range (no polygon offset: the bias is on the receiver side).
const char* kDistanceVS = R"(#version 450 core
layout(location = 0) in vec3 a_position;
uniform mat4 u_light_view_proj;
out vec3 v_world;
void main() { v_world = a_position; gl_Position = u_light_view_proj * vec4(a_position, 1.0); }
)";
const char* kDistanceFS = R"(
in vec3 v_world;
uniform vec3 u_light;
uniform float u_range;
void main() { gl_FragDepth = sk_omni_linear_depth(v_world, vec4(u_light, 1.0), u_range); }
)";
// V's lookup (after glsl/omni_shadow.glsl): the cube at unit 2 (compare on), the same cube without
// compare at unit 3 (a sampler object) for the manual lookup. The bias: the filter's footprint in
// texels (1/2, 2 or 4 texel diagonals), a 32-bit float's storage step (2^-22 of the distance) and a
// constant of 1e-5 of the range for the rasterizer's interpolation of world positions.
const char* kLookup = R"(
layout(binding = 2) uniform samplerCubeShadow u_cube;
layout(binding = 3) uniform samplerCube u_cube_distance;
uniform vec3 u_light;
uniform float u_range;
uniform float u_size;
uniform int u_lookup;
uniform vec2 u_storage;
float technique_visibility(vec3 p, vec3 n) {
    vec3 L = u_light - p;
    float d = length(L);
    float radius = u_lookup == 1 ? 0.7072 : (u_lookup == 2 ? 2.8285 : 1.4143);
    float b = sk_omni_bias(d, dot(n, L / d), sk_omni_cube_texel_angle(u_size), radius, 1.4835, u_storage);
    if (u_lookup == 1) return sk_cube_visibility_distance_manual(u_cube_distance, vec4(u_light, 1.0), p, u_range, b);
    if (u_lookup == 2) return sk_cube_visibility_distance_pcf(u_cube, vec4(u_light, 1.0), p, u_range, b, u_size, 1);
    return sk_cube_visibility_distance(u_cube, vec4(u_light, 1.0), p, u_range, b);
}
)";
// The debug view: the faces (a 2D-array view of the cube, compare off) side by side, 3 x 2.
const char* kAtlasFS = R"(#version 450 core
layout(binding = 0) uniform sampler2DArray u_faces;
uniform vec2 u_cell;  // pixels per face
out vec4 o_value;
void main() {
    vec2 c = gl_FragCoord.xy / u_cell;
    o_value = vec4(texture(u_faces, vec3(fract(c), float(int(c.x) + 3 * int(c.y)))).r);
}
)";

}  // namespace

bool OmniShadows::init(const app::View& v, std::string& why) {
    release();
    const sk::Scene& scene = *v.scene;
    for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
        if (!scene.meshes[i].caster) continue;
        glm::vec3 lo(INFINITY), hi(-INFINITY);
        for (const glm::vec3& p : scene.meshes[i].positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
        boxes_.insert(boxes_.end(), {lo.x, lo.y, lo.z, hi.x, hi.y, hi.z});
        mesh_of_.push_back(static_cast<std::uint32_t>(i));
    }
    lists_.assign(6 * mesh_of_.size() + 1, 0);
    const std::string snippet = app::load_snippet("omni_shadow", why);
    if (snippet.empty()) return false;
    depth_prog_ = skgl::compile_program(
        {{GL_VERTEX_SHADER, kDistanceVS}, {GL_FRAGMENT_SHADER, "#version 450 core\n" + snippet + kDistanceFS}}, why);
    vis_prog_ = app::compile_visibility_program(snippet, kLookup, why);
    atlas_prog_ = skgl::compile_program({{GL_VERTEX_SHADER, app::fullscreen_vertex_shader()}, {GL_FRAGMENT_SHADER, kAtlasFS}}, why);
    if (!depth_prog_ || !vis_prog_ || !atlas_prog_) return false;
    // the manual lookup reads the cube through a sampler without compare, nearest texel
    glGenSamplers(1, &nearest_);
    glSamplerParameteri(nearest_, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glSamplerParameteri(nearest_, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glSamplerParameteri(nearest_, GL_TEXTURE_COMPARE_MODE, GL_NONE);
    glGenVertexArrays(1, &vao_);
    return pass_.init(v.width, v.height, why);
}

void OmniShadows::update(const app::View& v, const OmniShadowSettings& s) {
    const sk::Light& L = v.light();
    error_.clear();
    // the stored distance's range: the farthest scene corner from the light (+1%)
    const glm::vec3 lo = v.scene->bounds_min(), hi = v.scene->bounds_max();
    range_ = 0.f;
    for (int i = 0; i < 8; ++i)
        range_ = std::max(range_, glm::length(glm::vec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z) - L.position));
    range_ *= 1.01f;
    shadowkit::OmniCubeInput in;  // the light as one vec4: the sun (w = 0) is refused
    in.light_position = L.homogeneous_position();
    in.far_z = range_;
    in.near_z = range_ * 1e-3f;
    const shadowkit::OmniCubeMatrices cm = shadowkit::omni_cube_matrices(in);
    if (cm.status != shadowkit::Status::Ok) {
        error_ = std::string("omni_cube_matrices status ") + shadowkit::status_name(cm.status);
        return;
    }
    std::copy(cm.view_proj, cm.view_proj + 6, face_vp_);
    for (auto& f : face_meshes_) f = mesh_of_;
    if (!s.culling) return;
    // per face, the casters whose box meets its frustum
    shadowkit::OmniCullInput ci;
    ci.light_position = in.light_position;
    ci.near_z = in.near_z;
    ci.far_z = in.far_z;
    ci.boxes = boxes_.data();
    ci.box_count = mesh_of_.size();
    std::size_t offsets[7] = {0, 0, 0, 0, 0, 0, 0};
    const shadowkit::OmniCullResult cr = shadowkit::omni_cull_face_lists(ci, lists_.data(), lists_.size(), offsets);
    if (cr.status != shadowkit::Status::Ok) {
        error_ = std::string("omni_cull_face_lists status ") + shadowkit::status_name(cr.status);
        return;
    }
    for (int f = 0; f < 6; ++f) {
        face_meshes_[f].clear();
        for (std::size_t k = offsets[f]; k < offsets[f + 1]; ++k) face_meshes_[f].push_back(mesh_of_[lists_[k]]);
    }
}

// A size^2 cube map of 32-bit float depths that compares (samplerCubeShadow: GL_LEQUAL, GL_LINEAR for
// the 2x2 filter), a framebuffer per face, and a 2D-array view of its faces for the debug view.
void OmniShadows::make_cube(int size) {
    if (cube_) glDeleteTextures(1, &cube_);
    if (faces_view_) glDeleteTextures(1, &faces_view_);
    if (fbo_[0]) glDeleteFramebuffers(6, fbo_);
    cube_ = skgl::make_depth_texture(GL_TEXTURE_CUBE_MAP, size, 1, GL_LINEAR, GL_CLAMP_TO_EDGE);
    skgl::make_depth_framebuffers(GL_TEXTURE_CUBE_MAP, cube_, 6, fbo_);
    glGenTextures(1, &faces_view_);
    glTextureView(faces_view_, GL_TEXTURE_2D_ARRAY, cube_, GL_DEPTH_COMPONENT32F, 0, 1, 0, 6);
    glTextureParameteri(faces_view_, GL_TEXTURE_COMPARE_MODE, GL_NONE);
    glTextureParameteri(faces_view_, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(faces_view_, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    size_ = size;
}

void OmniShadows::render(const app::View& v, const OmniShadowSettings& s) {
    if (s.size != size_) make_cube(s.size);
    const bool ok = error_.empty();

    // 1. Each face: its casters' linear distance (gl_FragDepth), depth test GL_LESS, cleared to the
    //    range's end, no culling of back faces, no polygon offset. No cube (the sun): empty faces, all lit.
    glUseProgram(depth_prog_);
    glUniform3fv(glGetUniformLocation(depth_prog_, "u_light"), 1, glm::value_ptr(v.light().position));
    glUniform1f(glGetUniformLocation(depth_prog_, "u_range"), range_);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_CULL_FACE);
    glClearDepth(1.0);
    for (int f = 0; f < 6; ++f) {
        glBindFramebuffer(GL_FRAMEBUFFER, fbo_[f]);
        glViewport(0, 0, size_, size_);
        glClear(GL_DEPTH_BUFFER_BIT);
        if (!ok) continue;
        glUniformMatrix4fv(glGetUniformLocation(depth_prog_, "u_light_view_proj"), 1, GL_FALSE, glm::value_ptr(face_vp_[f]));
        for (std::uint32_t m : face_meshes_[f]) skgl::draw_mesh(v.gpu->meshes[m]);
    }

    // 2. V at the G-buffer's points: the cube at unit 2 (compare), and at unit 3 without compare;
    //    seamless filtering, so the 2x2 compares and the PCF read across face edges.
    glEnable(GL_TEXTURE_CUBE_MAP_SEAMLESS);
    glUseProgram(vis_prog_);
    app::set_light_uniforms(vis_prog_, v.light());
    glUniform3fv(glGetUniformLocation(vis_prog_, "u_light"), 1, glm::value_ptr(v.light().position));
    glUniform1f(glGetUniformLocation(vis_prog_, "u_range"), range_);
    glUniform1f(glGetUniformLocation(vis_prog_, "u_size"), float(size_));
    glUniform1i(glGetUniformLocation(vis_prog_, "u_lookup"), static_cast<int>(s.lookup));
    glUniform2f(glGetUniformLocation(vis_prog_, "u_storage"), 1e-5f * range_, 2.3841858e-7f /* 2^-22 */);
    glActiveTexture(GL_TEXTURE3);
    glBindTexture(GL_TEXTURE_CUBE_MAP, cube_);
    glBindSampler(3, nearest_);
    pass_.draw(vis_prog_, *v.gpu, GL_TEXTURE_CUBE_MAP, cube_);
    glBindSampler(3, 0);
}

app::DebugImage OmniShadows::debug_faces() {
    const int cell = std::min(size_, 256);
    std::string why;
    if (atlas_.width != 3 * cell || atlas_.height != 2 * cell) {
        skgl::destroy_target(atlas_);
        if (!skgl::make_target(atlas_, 3 * cell, 2 * cell, {GL_R32F}, 0, why)) return {};
    }
    glBindFramebuffer(GL_FRAMEBUFFER, atlas_.fbo);
    glViewport(0, 0, atlas_.width, atlas_.height);
    glDisable(GL_DEPTH_TEST);
    glUseProgram(atlas_prog_);
    glUniform2f(glGetUniformLocation(atlas_prog_, "u_cell"), float(cell), float(cell));
    glBindTextureUnit(0, faces_view_);
    glBindVertexArray(vao_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    return {atlas_.color[0], app::DebugImage::Show::Value};
}

void OmniShadows::release() {  // (no GL call without objects: the App may have no context)
    for (GLuint t : {cube_, faces_view_})
        if (t) glDeleteTextures(1, &t);
    if (fbo_[0]) glDeleteFramebuffers(6, fbo_);
    for (GLuint p : {depth_prog_, vis_prog_, atlas_prog_})
        if (p) glDeleteProgram(p);
    if (nearest_) glDeleteSamplers(1, &nearest_);
    if (vao_) glDeleteVertexArrays(1, &vao_);
    cube_ = faces_view_ = nearest_ = depth_prog_ = vis_prog_ = atlas_prog_ = vao_ = 0;
    std::fill(fbo_, fbo_ + 6, 0u);
    size_ = 0;
    skgl::destroy_target(atlas_);
    boxes_.clear();
    mesh_of_.clear();
    for (auto& f : face_meshes_) f.clear();
    error_.clear();
}
