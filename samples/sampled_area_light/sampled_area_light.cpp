// samples/sampled_area_light/sampled_area_light.cpp - an area light as N spot lights, top to bottom:
//   init    once per scene: 256 Poisson points on the emitter's shape (poisson_eliminate, progressive:
//           the first N of them are a Poisson set too, so N can change without new points), the
//           depth-only program, the V program, the compare sampler, the V target
//   update  CPU, every frame: the light's frustum around the scene (sk::fit_light: a perspective from
//           its center), then per point on the emitter the same frustum moved there: N view-projections
//   render  GPU, every frame, 16 maps at a time: 1 the casters' depth from each point into a layer of a
//           depth array; 2 their lookups at the G-buffer's points, each a 2x2 filter with the automatic
//           bias of glsl/shadow_map.glsl (no constant), added (1/N each) into V with additive blending
// A point on the emitter below the receiver's tangent plane does not light it (the reference's rule).
#include "sampled_area_light.hpp"

#include <shadowkit/poisson_disk.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>

namespace {

// The lookups of one batch (after glsl/shadow_map.glsl): the maps at unit 2 (a depth array, compare on).
const char* kLookup = R"(
layout(binding = 2) uniform sampler2DArrayShadow u_maps;
uniform mat4 u_vp[16];
uniform vec3 u_pos[16];
uniform int u_count;
uniform float u_weight;    // 1 / N
float technique_visibility(vec3 p, vec3 n) {
    float sum = 0.0;
    for (int i = 0; i < u_count; ++i) {
        if (dot(n, u_pos[i] - p) <= 0.0) continue;   // the point is below the tangent plane
        // shadow_map.glsl's automatic bias: the 2x2 filter's four texel centres, each compared with the
        // receiver plane's own depth there (the plane from the G-buffer's normal: no constant to tune,
        // no dFdx/dFdy across silhouettes); outside this map: lit. The maps are float32: depth_step 0.
        sum += sk_shadow_map_visibility_auto(u_maps, float(i), u_vp[i], p, n, false, 0.0, 1.0);
    }
    return sum * u_weight;
}
)";

}  // namespace

bool SampledAreaLight::init(const app::View& v, std::string& why) {
    release();
    // 256 points of the emitter's shape: the unit square for a rect light, else the unit disk (a sphere
    // light's disk facing the scene); any first N of them are well spread
    const sk::Light& L = v.light();
    shadowkit::PoissonDomain domain;
    if (L.is_area() && L.type == sk::LightType::Rect) domain.shape = shadowkit::PoissonShape::Square;
    const shadowkit::PoissonResult pr = shadowkit::poisson_eliminate(domain, kMaxMaps, /*seed*/ 7, points_, kMaxMaps);
    if (pr.status != shadowkit::Status::Ok) {
        why = std::string("poisson_eliminate: ") + shadowkit::status_name(pr.status);
        return false;
    }
    const std::string shadow_map = app::load_snippet("shadow_map", why);  // sk_shadow_coord
    if (shadow_map.empty()) return false;
    depth_prog_ = skgl::depth_only_program(why);  // gl_Position = u_light_view_proj * a_position, no color
    vis_prog_ = app::compile_visibility_program(shadow_map, kLookup, why);
    if (!depth_prog_ || !vis_prog_) return false;
    // the maps' compare: GL_LINEAR (a 2x2 percentage-closer compare), GL_LEQUAL, outside the map lit
    const float border[4] = {1.f, 1.f, 1.f, 1.f};
    glGenSamplers(1, &sampler_);
    glSamplerParameteri(sampler_, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_BORDER);
    glSamplerParameteri(sampler_, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_BORDER);
    glSamplerParameterfv(sampler_, GL_TEXTURE_BORDER_COLOR, border);
    glSamplerParameteri(sampler_, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glSamplerParameteri(sampler_, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glSamplerParameteri(sampler_, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glSamplerParameteri(sampler_, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    return pass_.init(v.width, v.height, why);
}

void SampledAreaLight::update(const app::View& v, const SampledAreaLightSettings& s) {
    const sk::Light& L = v.light();
    error_.clear();
    if (L.type != sk::LightType::Spot && L.type != sk::LightType::Rect && L.type != sk::LightType::Disk &&
        L.type != sk::LightType::Sphere) {
        error_ = "the sampled area light needs a spot, rect, disk or sphere light";
        return;
    }
    const bool area = L.is_area();  // a spot light, or an emitter of size 0: every point at the center
    // the light's frustum from its center: its direction, field of view, near and far serve every point
    const sk::LightMatrices lm = sk::fit_light(*v.scene);
    const glm::mat4 inv = glm::inverse(lm.view);
    const glm::vec3 dir = -glm::normalize(glm::vec3(inv[2])), up = glm::normalize(glm::vec3(inv[1]));
    // the emitter's plane as the reference orients it (rect, disk: the light's direction; a sphere: the
    // disk facing the scene) and its half edge or radius
    float scale = 0.f;
    glm::vec3 t(1.f, 0.f, 0.f), b(0.f, 0.f, 1.f);
    if (area) {
        scale = L.type == sk::LightType::Rect ? 0.5f * L.size : L.size;
        app::emitter_basis(L.type == sk::LightType::Sphere ? dir : glm::normalize(L.direction), t, b);
    }
    // the boxes every point's fit reads: the casters' and the scene's (once, not per point)
    glm::vec3 clo(0.f), chi(0.f);
    const bool fit = s.fit_casters && sk::caster_bounds(*v.scene, clo, chi);
    const glm::vec3 slo = v.scene->bounds_min(), shi = v.scene->bounds_max();
    const auto n = static_cast<std::size_t>(s.maps);
    positions_.resize(n);
    vps_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        positions_[i] = L.position + scale * (points_[i].x * t + points_[i].y * b);
        const glm::mat4 view = glm::lookAt(positions_[i], positions_[i] + dir, up);
        vps_[i] = fit ? caster_fit(clo, chi, slo, shi, view, lm.proj) * view : lm.proj * view;
    }
}

// Leave out what the scene does not need: the map only has to hold the casters. From the point's
// view, the frustum through the casters' bounding box (x, y) reaching the farthest receiver (depth:
// a receiver behind the casters must be inside the map); a receiver outside it is lit by this point
// (no caster lies between them), which the lookup's `outside` = 1 gives. The scene's fit (`fallback`)
// when the point is inside the casters' box. lo..hi: the casters' box; slo..shi: the scene's.
glm::mat4 SampledAreaLight::caster_fit(glm::vec3 lo, glm::vec3 hi, glm::vec3 slo, glm::vec3 shi, const glm::mat4& view,
                                       const glm::mat4& fallback) {
    float l = INFINITY, r = -INFINITY, bt = INFINITY, tp = -INFINITY, znear = INFINITY, zfar = 0.f;
    for (int k = 0; k < 8; ++k) {
        const glm::vec3 c = glm::vec3(view * glm::vec4(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z, 1.f));
        const glm::vec3 e = glm::vec3(view * glm::vec4(k & 1 ? shi.x : slo.x, k & 2 ? shi.y : slo.y, k & 4 ? shi.z : slo.z, 1.f));
        const float d = -c.z;  // view depth of a caster corner
        if (!(d > 0.f)) return fallback;
        l = std::min(l, c.x / d);
        r = std::max(r, c.x / d);
        bt = std::min(bt, c.y / d);
        tp = std::max(tp, c.y / d);
        znear = std::min(znear, d);
        zfar = std::max(zfar, -e.z);
    }
    znear *= 0.99f;
    zfar = std::max(zfar, znear * 2.f) * 1.01f;
    return glm::frustum(l * znear, r * znear, bt * znear, tp * znear, znear, zfar);
}

// A depth array of `layers` maps (size x size), one framebuffer per layer, and a 2D view of layer 0.
void SampledAreaLight::make_maps(int size, int layers) {
    if (maps_) glDeleteTextures(1, &maps_);
    if (first_map_) glDeleteTextures(1, &first_map_);
    if (fbo_[0]) glDeleteFramebuffers(kBatch, fbo_);
    std::fill(fbo_, fbo_ + kBatch, 0u);
    glGenTextures(1, &maps_);
    glBindTexture(GL_TEXTURE_2D_ARRAY, maps_);
    glTexStorage3D(GL_TEXTURE_2D_ARRAY, 1, GL_DEPTH_COMPONENT32F, size, size, layers);
    skgl::make_depth_framebuffers(GL_TEXTURE_2D_ARRAY, maps_, layers, fbo_);
    glGenTextures(1, &first_map_);
    glTextureView(first_map_, GL_TEXTURE_2D, maps_, GL_DEPTH_COMPONENT32F, 0, 1, 0, 1);
    size_ = size;
    layers_ = layers;
}

void SampledAreaLight::render(const app::View& v, const SampledAreaLightSettings& s) {
    const int n = static_cast<int>(vps_.size());
    if (s.size != size_ || std::min(n, kBatch) != layers_) make_maps(s.size, std::min(n, kBatch));
    const float zero[4] = {0.f, 0.f, 0.f, 0.f};
    glBindFramebuffer(GL_FRAMEBUFFER, pass_.target.fbo);
    glClearBufferfv(GL_COLOR, 0, zero);
    glUseProgram(vis_prog_);
    app::set_light_uniforms(vis_prog_, v.light());
    glUniform1f(glGetUniformLocation(vis_prog_, "u_weight"), 1.f / float(n));
    for (int first = 0; first < n; first += layers_) {
        const int count = std::min(layers_, n - first);
        // 1. The casters' depth from each point of this batch into its layer: depth test GL_LESS,
        //    cleared to the far plane, both faces, no polygon offset (the lookup biases).
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        glDepthMask(GL_TRUE);
        glDisable(GL_BLEND);
        glDisable(GL_CULL_FACE);
        glDisable(GL_POLYGON_OFFSET_FILL);
        glClearDepth(1.0);
        glUseProgram(depth_prog_);
        for (int i = 0; i < count; ++i) {
            glBindFramebuffer(GL_FRAMEBUFFER, fbo_[i]);
            glViewport(0, 0, size_, size_);
            glClear(GL_DEPTH_BUFFER_BIT);
            glUniformMatrix4fv(glGetUniformLocation(depth_prog_, "u_light_view_proj"), 1, GL_FALSE,
                               glm::value_ptr(vps_[static_cast<std::size_t>(first + i)]));
            for (std::size_t k = 0; k < v.gpu->meshes.size(); ++k)
                if (v.gpu->caster[k]) skgl::draw_mesh(v.gpu->meshes[k]);
        }
        // 2. The batch's lookups at the G-buffer's points, added into V: blending GL_ONE + GL_ONE.
        glUseProgram(vis_prog_);
        glUniformMatrix4fv(glGetUniformLocation(vis_prog_, "u_vp"), count, GL_FALSE,
                           glm::value_ptr(vps_[static_cast<std::size_t>(first)]));
        glUniform3fv(glGetUniformLocation(vis_prog_, "u_pos"), count, glm::value_ptr(positions_[static_cast<std::size_t>(first)]));
        glUniform1i(glGetUniformLocation(vis_prog_, "u_count"), count);
        glBindSampler(2, sampler_);
        glEnable(GL_BLEND);
        glBlendFunc(GL_ONE, GL_ONE);
        glBlendEquation(GL_FUNC_ADD);
        pass_.draw(vis_prog_, *v.gpu, GL_TEXTURE_2D_ARRAY, maps_);
        glDisable(GL_BLEND);
        glBindSampler(2, 0);
    }
}

void SampledAreaLight::release() {  // (no GL call without objects: the App may have no context)
    if (maps_) glDeleteTextures(1, &maps_);
    if (first_map_) glDeleteTextures(1, &first_map_);
    if (fbo_[0]) glDeleteFramebuffers(kBatch, fbo_);
    if (sampler_) glDeleteSamplers(1, &sampler_);
    if (depth_prog_) glDeleteProgram(depth_prog_);
    if (vis_prog_) glDeleteProgram(vis_prog_);
    maps_ = first_map_ = sampler_ = depth_prog_ = vis_prog_ = 0;
    std::fill(fbo_, fbo_ + kBatch, 0u);
    size_ = layers_ = 0;
    positions_.clear();
    vps_.clear();
}
