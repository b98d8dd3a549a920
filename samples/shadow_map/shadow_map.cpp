// samples/shadow_map/shadow_map.cpp - the plain shadow map, top to bottom:
//   init    the programs: a depth-only pass, and V = the map's compare at each G-buffer point
//           (glsl/shadow_map.glsl); the V target
//   update  CPU, every frame: the light's frustum around the casters (shadowkit::light_frustum_fit_casters:
//           a perspective from spot and area lights, an orthographic box for a directional light; the
//           scene's with fit_casters=off), or for a point light the six 90-degree faces of a cube map
//           contact=on: V times contact_shadow.glsl's pixel-aligned march in the G-buffer's depth
//           (contact_pixels camera pixels long, a sample every 2nd pixel)
//   render  GPU, every frame: 1 the casters' depth from the light (bias=polygon_offset: with a
//           slope-scaled polygon offset against acne); 2 V at the G-buffer's points: bias=auto (the
//           default) the snippet's automatic bias, four compares at the 2x2 filter's texel centres
//           against the receiver plane's own depth (from the G-buffer's normal); polygon_offset: one
//           hardware compare (2x2 PCF with GL_LINEAR)
#include "shadow_map.hpp"

#include <shadowkit/light_frustum.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>

namespace {

// V's lookups (after glsl/shadow_map.glsl): the map is bound at unit 2.
// The automatic bias: no constant; the map is float32 (depth_step 0.0). u_hard: the nearest of the
// four taps only (hardware_pcf=off), a hard 0 / 1.
const char* kLookupAuto = R"(
layout(binding = 2) uniform sampler2DShadow u_shadow_map;
uniform mat4 u_light_view_proj;
uniform bool u_hard;
float map_visibility(vec3 p, vec3 n) {
    if (!u_hard) return sk_shadow_map_visibility_auto(u_shadow_map, u_light_view_proj, p, n, false, 0.0, 1.0);
    float v;
    vec2 uv[4];
    vec4 z, w;
    if (!sk_auto_bias_lookup(u_light_view_proj, p, n, false, vec2(textureSize(u_shadow_map, 0)), 0.0, 1.0, v, uv, z, w))
        return v;
    int k = (w.y + w.w > 0.5 ? 1 : 0) + (w.z + w.w > 0.5 ? 2 : 0);   // the nearest texel centre
    return texture(u_shadow_map, vec3(uv[k], z[k]));
}
)";
// contact=on: V times contact_shadow.glsl's pixel-aligned march (sk_contact_shadow_aligned, a sample
// every 2nd pixel: 8 for the default 16-pixel march, 3x cheaper than sk_contact_shadow's 32-step march
// on llvmpipe, docs/contact_shadow.md) toward the light in the G-buffer's depth (unit 4, float32: depth_step 0),
// contact_pixels camera pixels long at the receiver (a perspective camera: one pixel is
// 2 d / (P[1][1] height) world units at view depth d), occluders up to a tenth of that thick (the march
// length as thickness darkens the background around every silhouette: measured on `stack`, 0.0066 of
// the pixels misclassified against 0.0011); the light in view space.
const char* kContact = R"(
layout(binding = 4) uniform sampler2D u_camera_depth;   // the G-buffer's depth, compare off
uniform mat4 u_camera_view;
uniform mat4 u_camera_proj;
uniform vec4 u_view_light;        // view * light_position (w = 0: the direction toward the light)
uniform float u_contact_pixels;
float contact(vec3 p) {
    vec3 vp = (u_camera_view * vec4(p, 1.0)).xyz;
    float pixel_world = 2.0 * -vp.z / (u_camera_proj[1][1] * float(textureSize(u_camera_depth, 0).y));
    int samples = int(ceil(0.5 * u_contact_pixels));  // every 2nd pixel (8 for the default 16; the function clamps to 256)
    return sk_contact_shadow_aligned(u_camera_depth, u_camera_proj, vp, u_view_light, u_contact_pixels * pixel_world, samples,
                                     0.1 * u_contact_pixels * pixel_world, 0.0, false, sk_contact_noise(gl_FragCoord.xy));
}
float technique_visibility(vec3 p, vec3 n) {
    float v = map_visibility(p, n);
    return v > 0.0 ? v * contact(p) : 0.0;
}
)";
const char* kNoContact = R"(
float technique_visibility(vec3 p, vec3 n) { return map_visibility(p, n); }
)";
// The classic lookup: no bias here, the depth pass's polygon offset carries it.
const char* kLookup2D = R"(
layout(binding = 2) uniform sampler2DShadow u_shadow_map;
uniform mat4 u_light_view_proj;
float map_visibility(vec3 p, vec3 n) {
    return sk_shadow_map_visibility(u_shadow_map, u_light_view_proj, p, false, 0.0, 1.0);
}
)";
const char* kLookupCube = R"(
layout(binding = 2) uniform samplerCubeShadow u_cube;
uniform vec3 u_cube_light;
uniform float u_cube_near;
uniform float u_cube_far;
float technique_visibility(vec3 p, vec3 n) {
    return sk_cube_visibility_hardware_depth(u_cube, vec4(u_cube_light, 1.0), p, u_cube_near, u_cube_far, 0.0);
}
)";
// bias=auto on the cube: each face's 2x2 filter as four compares against the receiver plane's depth
// (across a face's edge, in the face the tap is read from); float32 faces: depth_step 0.0.
const char* kLookupCubeAuto = R"(
layout(binding = 2) uniform samplerCubeShadow u_cube;
uniform vec3 u_cube_light;
uniform float u_cube_near;
uniform float u_cube_far;
float technique_visibility(vec3 p, vec3 n) {
    return sk_cube_visibility_hardware_depth_auto(u_cube, vec4(u_cube_light, 1.0), p, n, u_cube_near, u_cube_far, 0.0);
}
)";

}  // namespace

bool ShadowMap::init(const app::View& v, std::string& why) {
    release();
    cube_ = v.light().type == sk::LightType::Point;
    snippet_ = app::load_snippet("shadow_map", why);
    if (snippet_.empty()) return false;
    const std::string contact = app::load_snippet("contact_shadow", why);
    if (contact.empty()) return false;
    snippet_ += "\n" + contact;
    depth_prog_ = skgl::depth_only_program(why);  // gl_Position = u_light_view_proj * a_position, no color
    if (!depth_prog_ || !make_visibility_program(ShadowMapSettings{}, why)) return false;
    return pass_.init(v.width, v.height, why);
}

// The V program of the chosen bias and contact setting (the cube map has one lookup, no contact).
bool ShadowMap::make_visibility_program(const ShadowMapSettings& s, std::string& why) {
    const bool automatic = s.bias == ShadowMapSettings::Bias::Auto, contact = !cube_ && s.contact;
    const int variant = int(automatic) + 2 * int(contact);
    if (vis_prog_ && vis_variant_ == variant) return true;
    if (vis_prog_) glDeleteProgram(vis_prog_);
    const std::string body = cube_ ? std::string(automatic ? kLookupCubeAuto : kLookupCube)
                                   : std::string(automatic ? kLookupAuto : kLookup2D) + (contact ? kContact : kNoContact);
    vis_prog_ = app::compile_visibility_program(snippet_, body, why);
    vis_variant_ = variant;
    return vis_prog_ != 0;
}

void ShadowMap::update(const app::View& v, const ShadowMapSettings& s) {
    const sk::Scene& scene = *v.scene;
    if (!cube_) {
        // the map around the casters, deep enough for every receiver (light_frustum.hpp); the scene's
        // frustum (the app shell's sk::fit_light: the spot's own cone, or the whole scene) when the
        // light sits among its casters, needs a cone wider than its own, or fit_casters is off
        const sk::Light& L = scene.light;
        shadowkit::LightCasterFitInput in;
        in.light_position = L.homogeneous_position();
        in.receiver_min = scene.bounds_min();
        in.receiver_max = scene.bounds_max();
        in.max_half_angle_radians = L.type == sk::LightType::Directional ? 1.4f : std::min(L.spot_half_angle, 1.4f);
        const bool has_casters = sk::caster_bounds(scene, in.caster_min, in.caster_max);
        const bool one_frustum = L.type == sk::LightType::Directional || L.type == sk::LightType::Spot ||
                                 L.type == sk::LightType::Rect || L.type == sk::LightType::Disk;
        const shadowkit::LightFrustumResult fit = shadowkit::light_frustum_fit_casters(in);
        if (s.fit_casters && has_casters && one_frustum && fit.status == shadowkit::Status::Ok) {
            light_vp_[0] = fit.view_proj;
            return;
        }
        const sk::LightMatrices lm = sk::fit_light(scene);
        light_vp_[0] = lm.proj * lm.view;
        return;
    }
    // a point light: six 90-degree faces whose far plane passes the farthest corner of the scene
    const glm::vec3 lo = scene.bounds_min(), hi = scene.bounds_max(), L = v.light().position;
    far_ = 0.f;
    for (int i = 0; i < 8; ++i)
        far_ = std::max(far_, glm::length(glm::vec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z) - L));
    far_ *= 1.01f;
    near_ = far_ * 2e-3f;
    const glm::mat4 proj = glm::perspective(glm::radians(90.f), 1.f, near_, far_);
    // the cube-map faces' orientation (GL 4.5 spec 8.13: major axis -> s, t)
    const glm::vec3 dirs[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    const glm::vec3 ups[6] = {{0, -1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0, -1, 0}, {0, -1, 0}};
    for (int f = 0; f < 6; ++f) light_vp_[f] = proj * glm::lookAt(L, L + dirs[f], ups[f]);
}

// A size x size depth texture (GL_DEPTH_COMPONENT32F) that compares (sampler2DShadow /
// samplerCubeShadow): GL_LEQUAL against the receiver's depth, GL_LINEAR for the hardware 2x2 filter; a
// 2D map's border is the far depth (outside the map: lit), a cube map keeps GL's default wrap (its
// lookups are seamless). One framebuffer per face, depth only.
void ShadowMap::make_map(int size) {
    if (map_) glDeleteTextures(1, &map_);
    glDeleteFramebuffers(6, fbo_);
    std::fill(fbo_, fbo_ + 6, 0u);
    const GLenum target = cube_ ? GL_TEXTURE_CUBE_MAP : GL_TEXTURE_2D;
    map_ = skgl::make_depth_texture(target, size, 1, GL_LINEAR, cube_ ? GL_REPEAT : GL_CLAMP_TO_BORDER);
    skgl::make_depth_framebuffers(target, map_, cube_ ? 6 : 1, fbo_);
    size_ = size;
}

void ShadowMap::render(const app::View& v, const ShadowMapSettings& s) {
    if (s.size != size_) make_map(s.size);
    std::string why;
    if (!make_visibility_program(s, why)) return;
    const bool automatic = s.bias == ShadowMapSettings::Bias::Auto;

    // 1. The casters' depth from the light (each cube face in turn): depth test GL_LESS, cleared to
    //    the far plane; bias=polygon_offset: a slope-scaled polygon offset pushing the stored depth
    //    away from the light. The automatic bias needs the true depths: no offset.
    glUseProgram(depth_prog_);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glClearDepth(1.0);
    if (!automatic) {
        glEnable(GL_POLYGON_OFFSET_FILL);
        glPolygonOffset(s.offset_factor, s.offset_units);
    }
    for (int f = 0; f < (cube_ ? 6 : 1); ++f) {
        glBindFramebuffer(GL_FRAMEBUFFER, fbo_[f]);
        glViewport(0, 0, size_, size_);
        glClear(GL_DEPTH_BUFFER_BIT);
        glUniformMatrix4fv(glGetUniformLocation(depth_prog_, "u_light_view_proj"), 1, GL_FALSE, glm::value_ptr(light_vp_[f]));
        for (std::size_t i = 0; i < v.gpu->meshes.size(); ++i)
            if (v.gpu->caster[i]) skgl::draw_mesh(v.gpu->meshes[i]);
    }
    glDisable(GL_POLYGON_OFFSET_FILL);

    // 2. V at the G-buffer's points: the snippet's compare, one texel (GL_NEAREST) or the 2x2 filter
    //    (the automatic bias's taps sit on texel centres: GL_NEAREST, the filter is in the shader).
    const GLenum filter = s.hardware_pcf && !automatic ? GL_LINEAR : GL_NEAREST;
    glTextureParameteri(map_, GL_TEXTURE_MIN_FILTER, static_cast<GLint>(filter));
    glTextureParameteri(map_, GL_TEXTURE_MAG_FILTER, static_cast<GLint>(filter));
    glUseProgram(vis_prog_);
    app::set_light_uniforms(vis_prog_, v.light());
    if (cube_) {
        glEnable(GL_TEXTURE_CUBE_MAP_SEAMLESS);  // the 2x2 filter reads across face edges
        glUniform3fv(glGetUniformLocation(vis_prog_, "u_cube_light"), 1, glm::value_ptr(v.light().position));
        glUniform1f(glGetUniformLocation(vis_prog_, "u_cube_near"), near_);
        glUniform1f(glGetUniformLocation(vis_prog_, "u_cube_far"), far_);
    } else {
        glUniformMatrix4fv(glGetUniformLocation(vis_prog_, "u_light_view_proj"), 1, GL_FALSE, glm::value_ptr(light_vp_[0]));
        if (automatic) glUniform1i(glGetUniformLocation(vis_prog_, "u_hard"), s.hardware_pcf ? 0 : 1);
        if (s.contact) {  // the G-buffer's camera and depth (not the fit camera: V is at the G-buffer's points)
            const sk::Light& L = v.light();
            const glm::vec4 light_world = L.homogeneous_position();
            glUniformMatrix4fv(glGetUniformLocation(vis_prog_, "u_camera_view"), 1, GL_FALSE, glm::value_ptr(v.gpu->view));
            glUniformMatrix4fv(glGetUniformLocation(vis_prog_, "u_camera_proj"), 1, GL_FALSE, glm::value_ptr(v.gpu->proj));
            glUniform4fv(glGetUniformLocation(vis_prog_, "u_view_light"), 1, glm::value_ptr(v.gpu->view * light_world));
            glUniform1f(glGetUniformLocation(vis_prog_, "u_contact_pixels"), s.contact_pixels);
            glBindTextureUnit(4, v.gpu->gbuffer.depth);
        }
    }
    pass_.draw(vis_prog_, *v.gpu, cube_ ? GL_TEXTURE_CUBE_MAP : GL_TEXTURE_2D, map_);
}

void ShadowMap::release() {  // (no GL call without objects: the App may have no context)
    if (map_) glDeleteTextures(1, &map_);
    if (fbo_[0]) glDeleteFramebuffers(6, fbo_);
    if (depth_prog_) glDeleteProgram(depth_prog_);
    if (vis_prog_) glDeleteProgram(vis_prog_);
    map_ = depth_prog_ = vis_prog_ = 0;
    vis_variant_ = -1;
    std::fill(fbo_, fbo_ + 6, 0u);
    size_ = 0;
}
