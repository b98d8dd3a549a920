// samples/linear_light/linear_light.cpp - soft shadows from a line light, top to bottom:
//   init    the programs (depth pass, the skin on the GPU or from CPU triangles, the two lookups), the V target
//   update  CPU, every frame: the segment (linear_light_segment), split into sub-lights
//           (linear_light_subdivide), a perspective frustum from each end toward the scene
//   render  1 (GPU) a depth map from every end; 2 (CPU, skin=cpu) each map read back and its depth
//           discontinuities triangulated into a skin (linear_light_build_skin); 3 (GPU) for every
//           sub-light, each end's skin drawn into the OTHER end's view, MIN-blended into that end's
//           visibility map (0 on the occluder, 1 on the receiver: how far into the penumbra a point
//           is), then V = mean over sub-lights of the two ends' lit fraction (sk_linear_light_visibility)
// method=sampled: step 1 from `samples` points along the line into a depth-compare array, then V =
// the mean of their 2x2 PCF lookups. A zero-length line (or another light) is a point light: one
// map, its depth test.
#include "linear_light.hpp"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>

namespace {

// The skin on the GPU: 6 vertices per 2x2 cell of the other end's depth map, no attributes; the
// vertex shader unprojects the cell and keeps it where the depths jump (else a point off screen).
const char* kSkinGpuVS = R"(
layout(binding = 4) uniform sampler2D u_other_depth;
uniform mat4 u_other_inv_vp;
uniform vec2 u_other_near_far;
uniform mat4 u_this_vp;
uniform float u_threshold;
noperspective out float v_value;
void main() {
    gl_Position = sk_linear_light_skin_vertex(u_other_depth, u_other_inv_vp, u_other_near_far.x, u_other_near_far.y,
                                              u_this_vp, u_threshold, gl_VertexID, v_value);
}
)";
// The skin from the CPU (linear_light_build_skin): world position + value per vertex.
const char* kSkinCpuVS = R"(
layout(location = 0) in vec3 a_position;
layout(location = 1) in float a_value;
uniform mat4 u_this_vp;
noperspective out float v_value;
void main() {
    v_value = a_value;
    gl_Position = u_this_vp * vec4(a_position, 1.0);
}
)";
const char* kSkinFS = R"(
noperspective in float v_value;
layout(location = 0) out vec4 o_vis;
void main() { o_vis = sk_linear_light_skin_output(v_value, gl_FragCoord.z); }
)";

// V for method=sampled (after glsl/shadow_map.glsl): the array of depth maps at unit 2, per sample the
// automatic bias's 2x2 lookup (u_auto) or one hardware compare of the offset depths.
const char* kSampledLookup = R"(
layout(binding = 2) uniform sampler2DArrayShadow u_maps;
uniform mat4 u_vp[16];
uniform vec3 u_pos[16];
uniform int u_count;
uniform bool u_auto;
float technique_visibility(vec3 p, vec3 n) {
    float v = 0.0;
    for (int i = 0; i < u_count; ++i) {
        if (dot(n, u_pos[i] - p) <= 0.0) continue;
        if (u_auto) {
            v += sk_shadow_map_visibility_auto(u_maps, float(i), u_vp[i], p, n, false, 0.0, 1.0);
            continue;
        }
        vec4 c = u_vp[i] * vec4(p, 1.0);
        if (c.w <= 0.0) { v += 1.0; continue; }
        vec3 w = c.xyz / c.w * 0.5 + 0.5;
        if (any(lessThan(w.xy, vec2(0.0))) || any(greaterThan(w.xy, vec2(1.0)))) { v += 1.0; continue; }
        v += texture(u_maps, vec4(w.xy, float(i), w.z));
    }
    return v / float(u_count);
}
)";

// V for method=heidrich: sub-light i uses the depth maps of ends i, i + 1 (units 2 + i) and its two
// visibility maps 2i, 2i + 1 (units 7 + ...); a point light: one map, its depth test.
std::string heidrich_lookup(int max_segments) {
    const std::string maps = std::to_string(max_segments + 1);
    std::string body = "uniform mat4 u_vp[" + maps + "];\nuniform vec3 u_end[" + maps + "];\nuniform int u_segments;\n" +
                       "uniform bool u_point;\nuniform bool u_auto;\nuniform float u_size;\n" +
                       "layout(binding = 2) uniform sampler2D u_depth[" + maps + "];\n" +
                       "layout(binding = 7) uniform sampler2D u_vis[" + std::to_string(2 * max_segments) + "];\n";
    body += R"(
// bias=auto: the end depth test reads the nearest texel (within half a texel of p): the receiver
// plane's slope over one texel plus the precision margin covers it (glsl/shadow_map.glsl).
float end_bias(mat4 vp, vec3 p, vec3 n) {
    if (!u_auto) return 0.0;
    vec4 g = sk_plane_depth_gradient(vp, p, n, false);
    return sk_auto_filtered_bias(g, vec2(1.0 / u_size), sk_shadow_coord(vp, p, false).z, 0.0);
}
float technique_visibility(vec3 p, vec3 n) {
    if (u_point) {
        if (dot(n, u_end[0] - p) <= 0.0) return 0.0;
        vec4 c = u_vp[0] * vec4(p, 1.0);
        if (c.w <= 0.0) return 1.0;
        vec3 w = c.xyz / c.w * 0.5 + 0.5;
        if (any(lessThan(w.xy, vec2(0.0))) || any(greaterThan(w.xy, vec2(1.0)))) return 1.0;
        ivec2 sz = textureSize(u_depth[0], 0);
        float stored = texelFetch(u_depth[0], clamp(ivec2(w.xy * vec2(sz)), ivec2(0), sz - 1), 0).r;
        return w.z <= stored + end_bias(u_vp[0], p, n) ? 1.0 : 0.0;
    }
    float v = 0.0;
)";
    for (int i = 0; i < max_segments; ++i) {  // (GLSL 4.50 indexes sampler arrays with constants only)
        const std::string a = std::to_string(i), b = std::to_string(i + 1);
        body += "    if (" + a + " < u_segments) v += sk_linear_light_visibility(u_depth[" + a + "], u_vis[" +
                std::to_string(2 * i) + "], u_vp[" + a + "], u_end[" + a + "], u_depth[" + b + "], u_vis[" +
                std::to_string(2 * i + 1) + "], u_vp[" + b + "], u_end[" + b + "], p, n, max(end_bias(u_vp[" + a +
                "], p, n), end_bias(u_vp[" + b + "], p, n)));\n";
    }
    return body + "    return v / float(u_segments);\n}\n";
}

// Whether the depth passes store true depths for the automatic bias (method=sampled with bias=auto,
// heidrich with bias=heidrich_auto), or offset depths (LinearLightSettings::bias).
bool true_depths(const LinearLightSettings& s) {
    using B = LinearLightSettings::Bias;
    return s.method == LinearLightSettings::Method::Sampled ? s.bias == B::Auto : s.bias == B::HeidrichAuto;
}

}  // namespace

bool LinearLight::init(const app::View& v, std::string& why) {
    release();
    if (v.light().type == sk::LightType::Directional) {
        why = "a line light needs a position (a linear light, or a point it shrinks to): not a directional light";
        return false;
    }
    const std::string snippet = app::load_snippet("linear_light", why);
    if (snippet.empty()) return false;
    const std::string head = "#version 450 core\n" + snippet;
    depth_prog_ = skgl::depth_only_program(why);  // gl_Position = u_light_view_proj * a_position, no color
    skin_gpu_prog_ = skgl::compile_program({{GL_VERTEX_SHADER, head + kSkinGpuVS}, {GL_FRAGMENT_SHADER, head + kSkinFS}}, why);
    skin_cpu_prog_ = skgl::compile_program({{GL_VERTEX_SHADER, head + kSkinCpuVS}, {GL_FRAGMENT_SHADER, head + kSkinFS}}, why);
    const std::string map_snippet = app::load_snippet("shadow_map", why);
    if (map_snippet.empty()) return false;
    vis_prog_ = app::compile_visibility_program(snippet + map_snippet, heidrich_lookup(kMaxSegments), why);
    sampled_prog_ = app::compile_visibility_program(map_snippet, kSampledLookup, why);
    if (!depth_prog_ || !skin_gpu_prog_ || !skin_cpu_prog_ || !vis_prog_ || !sampled_prog_) return false;
    // the CPU skin's vertices (position, value); an empty vertex array for the GPU skin
    glGenVertexArrays(1, &empty_vao_);
    glGenVertexArrays(1, &skin_vao_);
    glGenBuffers(1, &skin_vbo_);
    glBindVertexArray(skin_vao_);
    glBindBuffer(GL_ARRAY_BUFFER, skin_vbo_);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(shadowkit::LinearLightSkinVertex), nullptr);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 1, GL_FLOAT, GL_FALSE, sizeof(shadowkit::LinearLightSkinVertex),
                          reinterpret_cast<const void*>(sizeof(glm::vec3)));
    glBindVertexArray(0);
    return pass_.init(v.width, v.height, why);
}

void LinearLight::update(const app::View& v, const LinearLightSettings& s) {
    const sk::Scene& scene = *v.scene;
    const sk::Light& L = v.light();
    seg_ = L.type == sk::LightType::Linear ? shadowkit::linear_light_segment(L.position, L.direction, L.size)
                                           : shadowkit::linear_light_segment(L.position, glm::vec3(1.f, 0.f, 0.f), 0.f);
    if (seg_.status != shadowkit::Status::Ok) {
        error_ = std::string("linear_light_segment: ") + shadowkit::status_name(seg_.status);
        return;
    }
    // the points that get a depth map: the ends of every sub-light, or the centers of N equal pieces
    std::vector<glm::vec3> points;
    if (s.method == LinearLightSettings::Method::Sampled) {
        for (int i = 0; i < s.samples; ++i)
            points.push_back(seg_.end_a + (float(i) + 0.5f) / float(s.samples) * (seg_.end_b - seg_.end_a));
    } else {
        k_ = seg_.is_point ? 1 : std::clamp(s.segments, 1, kMaxSegments);
        glm::vec3 ends[kMaxSegments + 1];
        const shadowkit::LinearLightSubdivideResult sr =
            shadowkit::linear_light_subdivide(seg_, static_cast<std::uint32_t>(k_), ends, kMaxSegments + 1);
        if (sr.status != shadowkit::Status::Ok) {
            error_ = std::string("linear_light_subdivide: ") + shadowkit::status_name(sr.status);
            return;
        }
        points.assign(ends, ends + (seg_.is_point ? 1 : k_ + 1));
    }
    // from each point, a perspective frustum looking at the scene's center that holds the whole scene
    const glm::vec3 lo = scene.bounds_min(), hi = scene.bounds_max(), center = 0.5f * (lo + hi);
    views_.clear();
    for (const glm::vec3& pos : points) {
        EndpointView e;
        e.pos = pos;
        const glm::vec3 dir = glm::length(center - pos) > 0.f ? glm::normalize(center - pos) : glm::vec3(0.f, -1.f, 0.f);
        const glm::vec3 up = std::abs(dir.y) > 0.9f ? glm::vec3(0.f, 0.f, 1.f) : glm::vec3(0.f, 1.f, 0.f);
        const glm::mat4 view = glm::lookAt(pos, pos + dir, up);
        float tan_max = 0.f;
        sk::fit_box_depth(view, lo, hi, e.znear, e.zfar, tan_max);
        const float half = std::min(std::atan(tan_max) * 1.02f, 1.45f);
        e.vp = glm::perspective(2.f * half, 1.f, e.znear, e.zfar) * view;
        e.inv_vp = glm::inverse(e.vp);
        views_.push_back(e);
    }
}

// The maps of these settings. heidrich: per end a size^2 depth map read exactly (GL_NEAREST, no
// compare), per sub-light two RGBA32F visibility maps; sampled: one depth-compare array (GL_LINEAR:
// the 2x2 filter), a layer per sample, and one framebuffer whose depth attachment moves layer to layer.
void LinearLight::make_maps(const LinearLightSettings& s) {
    for (auto& t : maps_) skgl::destroy_target(t);
    for (auto& t : vmaps_) skgl::destroy_target(t);
    if (array_) glDeleteTextures(1, &array_);
    if (array_view_) glDeleteTextures(1, &array_view_);
    if (array_fbo_) glDeleteFramebuffers(1, &array_fbo_);
    array_ = array_view_ = array_fbo_ = 0;
    std::string why;
    size_ = s.size;
    made_method_ = s.method;
    made_points_ = views_.size();
    const bool sampled = s.method == LinearLightSettings::Method::Sampled;
    maps_.assign(sampled ? 0 : views_.size(), {});
    vmaps_.assign(sampled || seg_.is_point ? 0 : static_cast<std::size_t>(2 * k_), {});
    for (auto& t : maps_) {
        skgl::make_target(t, size_, size_, {}, GL_DEPTH_COMPONENT32F, why);
        skgl::set_depth_compare(t.depth, false, false);
        skgl::set_nearest_clamped(t.depth);
    }
    for (auto& t : vmaps_) {
        skgl::make_target(t, size_, size_, {GL_RGBA32F}, 0, why);
        skgl::set_nearest_clamped(t.color[0]);
    }
    if (!sampled) return;
    // sampled: one depth array that compares (sampler2DArrayShadow: GL_LEQUAL, GL_LINEAR), clamped
    array_ = skgl::make_depth_texture(GL_TEXTURE_2D_ARRAY, size_, static_cast<int>(views_.size()), GL_LINEAR, GL_CLAMP_TO_EDGE);
    glGenFramebuffers(1, &array_fbo_);
    glBindFramebuffer(GL_FRAMEBUFFER, array_fbo_);
    glDrawBuffer(GL_NONE);
    glReadBuffer(GL_NONE);
    glGenTextures(1, &array_view_);  // (the debug view: layer 0 as a 2D texture)
    glTextureView(array_view_, GL_TEXTURE_2D, array_, GL_DEPTH_COMPONENT32F, 0, 1, 0, 1);
}

void LinearLight::render_depth_maps(const app::View& v, const LinearLightSettings& s) {
    const bool sampled = s.method == LinearLightSettings::Method::Sampled;
    const std::size_t vmaps = sampled || seg_.is_point ? 0 : 2 * std::size_t(k_);
    if (s.size != size_ || s.method != made_method_ || views_.size() != made_points_ || vmaps_.size() != vmaps) make_maps(s);
    // 1. A depth map from every point: depth test GL_LESS, cleared to the far plane, polygon offset
    //    (2, 2). heidrich draws every mesh (a skin needs the receiver's depth behind the
    //    discontinuity); sampled the casters only.
    glUseProgram(depth_prog_);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    if (!true_depths(s)) {
        glEnable(GL_POLYGON_OFFSET_FILL);
        glPolygonOffset(2.f, 2.f);
    }
    for (std::size_t i = 0; i < views_.size(); ++i) {
        glBindFramebuffer(GL_FRAMEBUFFER, sampled ? array_fbo_ : maps_[i].fbo);
        if (sampled) glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, array_, 0, static_cast<GLint>(i));
        glViewport(0, 0, size_, size_);
        glClear(GL_DEPTH_BUFFER_BIT);
        glUniformMatrix4fv(glGetUniformLocation(depth_prog_, "u_light_view_proj"), 1, GL_FALSE, glm::value_ptr(views_[i].vp));
        for (std::size_t m = 0; m < v.gpu->meshes.size(); ++m)
            if (!sampled || v.gpu->caster[m]) skgl::draw_mesh(v.gpu->meshes[m]);
    }
    glDisable(GL_POLYGON_OFFSET_FILL);
    glDisable(GL_DEPTH_TEST);
}

void LinearLight::build_skins(const LinearLightSettings& s) {
    skins_.resize(maps_.size());
    if (s.method != LinearLightSettings::Method::Heidrich || s.skin != LinearLightSettings::Skin::Cpu || seg_.is_point) {
        for (auto& skin : skins_) skin.clear();
        return;
    }
    // 2. Per depth map: read back, unproject every texel to its world position and linear distance,
    //    triangulate the cells whose distances jump (only those are drawn).
    const auto n = static_cast<std::uint32_t>(size_);
    depth_.resize(std::size_t(n) * n);
    position_.resize(depth_.size());
    distance_.resize(depth_.size());
    for (std::size_t m = 0; m < maps_.size(); ++m) {
        const EndpointView& o = views_[m];
        glBindFramebuffer(GL_READ_FRAMEBUFFER, maps_[m].fbo);
        glReadPixels(0, 0, size_, size_, GL_DEPTH_COMPONENT, GL_FLOAT, depth_.data());
        for (std::uint32_t j = 0; j < n; ++j)
            for (std::uint32_t i = 0; i < n; ++i) {
                const std::size_t q = std::size_t(j) * n + i;
                const float zn = depth_[q] * 2.f - 1.f;
                distance_[q] = 2.f * o.znear * o.zfar / (o.zfar + o.znear - zn * (o.zfar - o.znear));
                const glm::vec4 w =
                    o.inv_vp * glm::vec4((float(i) + 0.5f) / float(n) * 2.f - 1.f, (float(j) + 0.5f) / float(n) * 2.f - 1.f, zn, 1.f);
                position_[q] = glm::vec3(w) / w.w;
            }
        std::vector<shadowkit::LinearLightSkinVertex>& skin = skins_[m];
        skin.resize(shadowkit::linear_light_skin_capacity(n, n) / 8);  // a guess; grown to `needed` when short
        shadowkit::LinearLightSkinResult sr = shadowkit::linear_light_build_skin(
            position_.data(), distance_.data(), n, n, s.threshold, skin.data(), skin.size());
        if (sr.status == shadowkit::Status::BufferTooSmall) {
            skin.resize(sr.needed);
            sr = shadowkit::linear_light_build_skin(position_.data(), distance_.data(), n, n, s.threshold, skin.data(),
                                                    skin.size());
        }
        if (sr.status != shadowkit::Status::Ok && error_.empty())
            error_ = std::string("linear_light_build_skin: ") + shadowkit::status_name(sr.status);
        skin.resize(sr.count);
    }
}

// One skin into a visibility map: the map cleared to "no skin" (1), the skin of depth map `from`
// drawn with the view-projection of end `into` (blending GL_MIN, set by render_visibility).
void LinearLight::draw_skin(std::size_t from, std::size_t into, const LinearLightSettings& s) {
    skgl::Target& target = vmaps_[2 * std::min(from, into) + (from < into ? 1 : 0)];
    const bool cpu = s.skin == LinearLightSettings::Skin::Cpu;
    const GLuint prog = cpu ? skin_cpu_prog_ : skin_gpu_prog_;
    glUseProgram(prog);
    glUniformMatrix4fv(glGetUniformLocation(prog, "u_this_vp"), 1, GL_FALSE, glm::value_ptr(views_[into].vp));
    glBindFramebuffer(GL_FRAMEBUFFER, target.fbo);
    glViewport(0, 0, size_, size_);
    const float one[4] = {1.f, 1.f, 1.f, 1.f};
    glClearBufferfv(GL_COLOR, 0, one);
    if (cpu) {
        const auto& skin = skins_[from];
        if (skin.empty()) return;
        glBindBuffer(GL_ARRAY_BUFFER, skin_vbo_);
        glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(skin.size() * sizeof(skin[0])), skin.data(), GL_STREAM_DRAW);
        glBindVertexArray(skin_vao_);
        glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(skin.size()));
        return;
    }
    glUniformMatrix4fv(glGetUniformLocation(prog, "u_other_inv_vp"), 1, GL_FALSE, glm::value_ptr(views_[from].inv_vp));
    glUniform2f(glGetUniformLocation(prog, "u_other_near_far"), views_[from].znear, views_[from].zfar);
    glUniform1f(glGetUniformLocation(prog, "u_threshold"), s.threshold);
    glActiveTexture(GL_TEXTURE4);
    glBindTexture(GL_TEXTURE_2D, maps_[from].depth);
    glBindVertexArray(empty_vao_);
    glDrawArrays(GL_TRIANGLES, 0, 6 * (size_ - 1) * (size_ - 1));
}

void LinearLight::render_visibility(const app::View& v, const LinearLightSettings& s) {
    if (s.method == LinearLightSettings::Method::Sampled) {
        // V = the mean of the samples' 2x2 PCF lookups (the array at unit 2)
        std::vector<glm::mat4> vps(kMaxSamples, glm::mat4(1.f));
        std::vector<glm::vec3> pos(kMaxSamples, glm::vec3(0.f));
        for (std::size_t i = 0; i < views_.size(); ++i) {
            vps[i] = views_[i].vp;
            pos[i] = views_[i].pos;
        }
        glUseProgram(sampled_prog_);
        app::set_light_uniforms(sampled_prog_, v.light());
        glUniformMatrix4fv(glGetUniformLocation(sampled_prog_, "u_vp"), kMaxSamples, GL_FALSE, glm::value_ptr(vps[0]));
        glUniform3fv(glGetUniformLocation(sampled_prog_, "u_pos"), kMaxSamples, glm::value_ptr(pos[0]));
        glUniform1i(glGetUniformLocation(sampled_prog_, "u_count"), static_cast<GLint>(views_.size()));
        glUniform1i(glGetUniformLocation(sampled_prog_, "u_auto"), true_depths(s) ? 1 : 0);
        pass_.draw(sampled_prog_, *v.gpu, GL_TEXTURE_2D_ARRAY, array_);
        return;
    }
    // 3. Per sub-light i, both directions: the skin of end i + 1's map into end i's visibility map,
    //    and the skin of end i's map into end i + 1's. No depth test, blending GL_MIN: the smallest
    //    skin value (and its depth) wins where skins overlap.
    if (!seg_.is_point) {
        glEnable(GL_BLEND);
        glBlendEquation(GL_MIN);
        for (std::size_t i = 0; i < static_cast<std::size_t>(k_); ++i) {
            draw_skin(i + 1, i, s);
            draw_skin(i, i + 1, s);
        }
        glBindVertexArray(0);
        glBlendEquation(GL_FUNC_ADD);
        glDisable(GL_BLEND);
    }
    // 4. V at the G-buffer's points: the depth maps at units 2.., the visibility maps at units 7..
    std::vector<glm::mat4> vps(kMaxSegments + 1, glm::mat4(1.f));
    std::vector<glm::vec3> ends(kMaxSegments + 1, glm::vec3(0.f));
    for (std::size_t i = 0; i < views_.size(); ++i) {
        vps[i] = views_[i].vp;
        ends[i] = views_[i].pos;
        glActiveTexture(static_cast<GLenum>(GL_TEXTURE2 + i));
        glBindTexture(GL_TEXTURE_2D, maps_[i].depth);
    }
    for (std::size_t i = 0; i < vmaps_.size(); ++i) {
        glActiveTexture(static_cast<GLenum>(GL_TEXTURE7 + i));
        glBindTexture(GL_TEXTURE_2D, vmaps_[i].color[0]);
    }
    glUseProgram(vis_prog_);
    app::set_light_uniforms(vis_prog_, v.light());
    glUniformMatrix4fv(glGetUniformLocation(vis_prog_, "u_vp"), kMaxSegments + 1, GL_FALSE, glm::value_ptr(vps[0]));
    glUniform3fv(glGetUniformLocation(vis_prog_, "u_end"), kMaxSegments + 1, glm::value_ptr(ends[0]));
    glUniform1i(glGetUniformLocation(vis_prog_, "u_segments"), k_);
    glUniform1i(glGetUniformLocation(vis_prog_, "u_point"), seg_.is_point ? 1 : 0);
    glUniform1i(glGetUniformLocation(vis_prog_, "u_auto"), true_depths(s) ? 1 : 0);
    glUniform1f(glGetUniformLocation(vis_prog_, "u_size"), float(size_));
    pass_.draw(vis_prog_, *v.gpu);
}

std::size_t LinearLight::skin_vertices() const {
    std::size_t n = 0;
    for (const auto& skin : skins_) n += skin.size();
    return n;
}

void LinearLight::release() {  // (no GL call without objects: the App may have no context)
    for (auto& t : maps_) skgl::destroy_target(t);
    for (auto& t : vmaps_) skgl::destroy_target(t);
    maps_.clear();
    vmaps_.clear();
    if (array_) glDeleteTextures(1, &array_);
    if (array_view_) glDeleteTextures(1, &array_view_);
    if (array_fbo_) glDeleteFramebuffers(1, &array_fbo_);
    for (GLuint* a : {&empty_vao_, &skin_vao_})
        if (*a) glDeleteVertexArrays(1, a);
    if (skin_vbo_) glDeleteBuffers(1, &skin_vbo_);
    for (GLuint p : {depth_prog_, skin_gpu_prog_, skin_cpu_prog_, vis_prog_, sampled_prog_})
        if (p) glDeleteProgram(p);
    array_ = array_view_ = array_fbo_ = empty_vao_ = skin_vao_ = skin_vbo_ = 0;
    depth_prog_ = skin_gpu_prog_ = skin_cpu_prog_ = vis_prog_ = sampled_prog_ = 0;
    size_ = 0;
    error_.clear();
}
