// samples/cached_shadow_map/cached_shadow_map.cpp - a cached shadow map, top to bottom:
//   init    the programs: the plain caster pass, the translation-invariant caster pass
//           (glsl/shadow_cache.glsl), V = the map's compare (glsl/shadow_map.glsl); the V target
//   update  CPU, every frame: the light's matrix (a sun: light_frustum's stable fit to the camera with
//           the depth range fixed in the world; spot and area lights: the frustum around the scene),
//           the casters' bounds, and shadow_cache_plan: what of last frame's map is still right
//   render  GPU, every frame: 1 a scroll (copy by whole texels into the other texture of a pair),
//           2 clear + draw the casters inside each rectangle of the plan (scissor), 3 V at the G-buffer
//           with the automatic bias of glsl/shadow_map.glsl (bias=auto, the default; bias=offset: a
//           slope-scaled offset in the caster passes and the hardware 2x2 compare)
#include "cached_shadow_map.hpp"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cstdint>

namespace {

// The plain caster pass: hardware depth; `invariant` so every pass puts a vertex on the same spot.
const char* kPlainVS = R"(#version 450 core
layout(location = 0) in vec3 a_position;
uniform mat4 u_light_view_proj;
invariant gl_Position;
void main() { gl_Position = u_light_view_proj * vec4(a_position, 1.0); }
)";
const char* kEmptyFS = "#version 450 core\nvoid main() {}\n";

// The translation-invariant pass (glsl/shadow_cache.glsl): the vertex in global texel space (no
// anchor: the same bits every frame), exact whole-texel window positions, the depth plane per
// triangle, each texel's depth from its global texel plus a slope-scaled offset like
// glPolygonOffset(2, 2) (which does not apply to a written depth).
const char* kInvariantVS = R"(#version 450 core
layout(location = 0) in vec3 a_position;
uniform mat4 u_light_global;
out vec3 v_global;
void main() {
    v_global = (u_light_global * vec4(a_position, 1.0)).xyz;
    gl_Position = vec4(0.0);
}
)";
const char* kInvariantGS = R"(
layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;
in vec3 v_global[];
uniform ivec2 u_viewport_anchor;
uniform vec2 u_viewport_size;
flat out vec3 g_plane;
flat out vec2 g_origin;
void main() {
    vec3 plane;
    vec2 origin;
    if (!sk_shadow_cache_plane(v_global[0], v_global[1], v_global[2], plane, origin)) return;
    for (int i = 0; i < 3; ++i) {
        g_plane = plane;
        g_origin = origin;
        gl_Position = sk_shadow_cache_position(v_global[i].xy, u_viewport_anchor, u_viewport_size);
        EmitVertex();
    }
    EndPrimitive();
}
)";
const char* kInvariantFS = R"(
flat in vec3 g_plane;
flat in vec2 g_origin;
uniform ivec2 u_anchor;
uniform bool u_offset;  // bias=offset; bias=auto stores the true depth
void main() {
    float d = sk_shadow_cache_depth(g_plane, g_origin, gl_FragCoord.xy, u_anchor);
    gl_FragDepth = u_offset ? min(d + sk_shadow_cache_depth_offset(g_plane, 2.0, 2.4e-7), 1.0) : d;
}
)";

// V's lookup (after glsl/shadow_map.glsl): the map at unit 2. bias=auto: the automatic bias, the 2x2
// filter as four compares at texel centres against the receiver plane (GL_NEAREST); bias=offset: the
// hardware 2x2 compare (GL_LINEAR) of the offset depths.
const char* kLookup = R"(
layout(binding = 2) uniform sampler2DShadow u_shadow_map;
uniform mat4 u_light_view_proj;
uniform bool u_auto;
float technique_visibility(vec3 p, vec3 n) {
    if (u_auto) return sk_shadow_map_visibility_auto(u_shadow_map, u_light_view_proj, p, n, false, 0.0, 1.0);
    return sk_shadow_map_visibility(u_shadow_map, u_light_view_proj, p, false, 0.0, 1.0);
}
)";

constexpr int kGuardViewport = 4096;  // the invariant pass's viewport: the map plus a guard band

}  // namespace

bool CachedShadowMap::init(const app::View& v, std::string& why) {
    release();
    if (v.light().type == sk::LightType::Point) {
        why = "point light: needs a cube map (samples/shadow_map); this sample caches one 2D map";
        return false;
    }
    const std::string cache_glsl = app::load_snippet("shadow_cache", why);
    const std::string map_glsl = app::load_snippet("shadow_map", why);
    if (cache_glsl.empty() || map_glsl.empty()) return false;
    const std::string head = "#version 450 core\n" + cache_glsl;
    plain_prog_ = skgl::compile_program({{GL_VERTEX_SHADER, kPlainVS}, {GL_FRAGMENT_SHADER, kEmptyFS}}, why);
    invariant_prog_ = skgl::compile_program(
        {{GL_VERTEX_SHADER, kInvariantVS}, {GL_GEOMETRY_SHADER, head + kInvariantGS}, {GL_FRAGMENT_SHADER, head + kInvariantFS}}, why);
    vis_prog_ = app::compile_visibility_program(map_glsl, kLookup, why);
    if (!plain_prog_ || !invariant_prog_ || !vis_prog_) return false;
    for (std::size_t i = 0; i < v.scene->meshes.size(); ++i)
        if (v.gpu->caster[i] && !v.scene->meshes[i].positions.empty()) mesh_.push_back(i);
    casters_.assign(mesh_.size(), shadowkit::ShadowCacheCaster{});
    boxes_.assign(6 * mesh_.size(), 0.f);
    kept_.assign(mesh_.size(), 0u);
    drawn_.assign(mesh_.size(), 1);
    rects_.resize(shadowkit::shadow_cache_rect_capacity(mesh_.size()));
    previous_ = shadowkit::ShadowCacheMapState{};  // no content: the first frame renders the whole map
    return pass_.init(v.width, v.height, why);
}

void CachedShadowMap::update(const app::View& v, const CachedShadowMapSettings& s) {
    error_.clear();
    // The casters' bounds this frame (the scene here is still; a renderer with moving objects takes
    // them from its transforms). previous_bounds hold them as the map was last rendered.
    for (std::size_t i = 0; i < mesh_.size(); ++i) {
        glm::vec3 lo(INFINITY), hi(-INFINITY);
        for (const glm::vec3& p : v.scene->meshes[mesh_[i]].positions) {
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
        const float b[6] = {lo.x, lo.y, lo.z, hi.x, hi.y, hi.z};
        std::copy(b, b + 6, casters_[i].bounds);
        std::copy(b, b + 6, boxes_.begin() + std::ptrdiff_t(6 * i));
    }
    const sk::Light& L = v.light();
    const double S = double(s.size);
    std::uint64_t settings = (s.pass == CachedShadowMapSettings::Pass::Invariant ? 1u : 2u) + (s.bias == CachedShadowMapSettings::Bias::Auto ? 4u : 0u);
    std::fill(drawn_.begin(), drawn_.end(), std::uint8_t(1));
    if (L.type == sk::LightType::Directional) {
        // the sun's frustum fitted to the camera: stable (snapped, the depth range from the scene box)
        shadowkit::LightFrustumInput in;
        in.camera_view = v.view;
        in.camera_proj = v.proj;
        in.has_scene_bounds = true;
        in.scene_min = v.scene->bounds_min();
        in.scene_max = v.scene->bounds_max();
        in.light_position = glm::vec4(-glm::normalize(L.direction), 0.f);  // w = 0: toward the light
        in.stable = s.fit == CachedShadowMapSettings::Fit::Stable;
        in.stable_world_depth = s.world_depth;
        in.shadow_map_size = static_cast<std::uint32_t>(s.size);
        in.casters = boxes_.data();
        in.caster_count = mesh_.size();
        const shadowkit::LightFrustumResult r = shadowkit::light_frustum_fit(in, kept_.data(), kept_.size());
        if (r.status != shadowkit::Status::Ok) {
            error_ = std::string("light_frustum_fit: ") + shadowkit::status_name(r.status);
            return;
        }
        light_vp_ = glm::dmat4(r.view_proj);
        ortho_ = true;
        invariant_ = in.stable && s.pass == CachedShadowMapSettings::Pass::Invariant;
        if (in.stable) {
            // the x/y translation exactly, from the anchor: two frames then differ by whole texels in
            // double, which the plan certifies (docs/light_frustum.md)
            anchor_ = glm::ivec2(glm::dvec2(r.texel_anchor));
            light_vp_[3][0] = -2.0 * r.texel_anchor.x / S - 1.0;
            light_vp_[3][1] = -2.0 * r.texel_anchor.y / S - 1.0;
        }
        if (s.culling) {  // only the kept casters: the kept set becomes part of the map's settings
            std::fill(drawn_.begin(), drawn_.end(), std::uint8_t(0));
            for (std::size_t k = 0; k < r.count; ++k) {
                drawn_[kept_[k]] = 1;
                settings = (settings ^ (kept_[k] + 1u)) * 1099511628211ull;  // FNV-1a of the kept indices
            }
        }
    } else {
        // spot and area lights: the frustum around the scene from the light's center, camera-independent
        const sk::LightMatrices lm = sk::fit_light(*v.scene);
        light_vp_ = glm::dmat4(lm.proj * lm.view);
        ortho_ = !lm.perspective;
        invariant_ = false;
    }
    light_vp_f_ = glm::mat4(light_vp_);
    if (invariant_) {  // world -> (global texel x, y, window depth): no anchor, the same every frame
        glm::dmat4 g(0.0);
        for (int c = 0; c < 4; ++c) {
            g[c][0] = 0.5 * S * light_vp_[c][0];
            g[c][1] = 0.5 * S * light_vp_[c][1];
            g[c][2] = 0.5 * light_vp_[c][2];
        }
        g[3][0] += 0.5 * S + double(anchor_.x);  // = 0: the grid is anchored at the world origin
        g[3][1] += 0.5 * S + double(anchor_.y);
        g[3][2] += 0.5;
        g[3][3] = 1.0;
        light_global_ = glm::mat4(g);
    }
    // the plan: this frame's state against the one the map was last rendered with
    current_ = shadowkit::ShadowCacheMapState{};
    current_.view_proj = light_vp_;
    current_.width = current_.height = s.size;
    current_.settings = settings * 2u + (ortho_ ? 1u : 0u);
    if (s.size != size_) previous_.has_content = false;  // a new map
    const shadowkit::ShadowCacheMapState none;           // cache off: no content, render everything
    scrolled_ = false;
    plan_ = shadowkit::shadow_cache_plan(s.cache ? previous_ : none, current_, casters_.data(), casters_.size(), rects_.data(),
                                         rects_.size());
    if (plan_.status != shadowkit::Status::Ok) error_ = std::string("shadow_cache_plan: ") + shadowkit::status_name(plan_.status);
}

// A pair of size x size depth textures that compare (sampler2DShadow, GL_LEQUAL, GL_LINEAR for the 2x2
// filter, the far depth outside the map) and their framebuffers: a scroll copies from one into the other.
void CachedShadowMap::make_map(int size) {
    glDeleteTextures(2, tex_);
    glDeleteFramebuffers(2, fbo_);
    glCreateTextures(GL_TEXTURE_2D, 2, tex_);
    glCreateFramebuffers(2, fbo_);
    const float far_border[4] = {1.f, 1.f, 1.f, 1.f};
    for (int i = 0; i < 2; ++i) {
        glTextureStorage2D(tex_[i], 1, GL_DEPTH_COMPONENT32F, size, size);
        glTextureParameteri(tex_[i], GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTextureParameteri(tex_[i], GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTextureParameteri(tex_[i], GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
        glTextureParameteri(tex_[i], GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
        glTextureParameteri(tex_[i], GL_TEXTURE_WRAP_S, GL_CLAMP_TO_BORDER);
        glTextureParameteri(tex_[i], GL_TEXTURE_WRAP_T, GL_CLAMP_TO_BORDER);
        glTextureParameterfv(tex_[i], GL_TEXTURE_BORDER_COLOR, far_border);
        glNamedFramebufferTexture(fbo_[i], GL_DEPTH_ATTACHMENT, tex_[i], 0);
        glNamedFramebufferDrawBuffer(fbo_[i], GL_NONE);
        glNamedFramebufferReadBuffer(fbo_[i], GL_NONE);
    }
    size_ = size;
    cur_ = 0;
}

void CachedShadowMap::render_map(const app::View& v, const CachedShadowMapSettings& s) {
    if (s.size != size_) make_map(s.size);
    const int S = size_;

    // 1. Scroll: what stays on the map, copied by the whole-texel offset into the other texture
    //    (glCopyImageSubData's regions must not overlap within one image).
    if (plan_.action == shadowkit::ShadowCacheAction::Scroll && !scrolled_) {  // once per update()
        const shadowkit::ShadowCacheCopy& c = plan_.copy;
        glCopyImageSubData(tex_[cur_], GL_TEXTURE_2D, 0, c.src_x, c.src_y, 0, tex_[1 - cur_], GL_TEXTURE_2D, 0, c.dst_x,
                           c.dst_y, 0, c.width, c.height, 1);
        cur_ = 1 - cur_;
        scrolled_ = true;
    }

    // 2. Each rectangle of the plan (Keep: none; Render: the whole map): clear it and draw the casters
    //    whose footprint meets it. Depth test GL_LESS with writes on (a scissored clear needs them),
    //    the scissor bounding both. Plain pass: the map's viewport and a slope-scaled polygon offset;
    //    invariant pass: a guard viewport around the map (triangles are clipped far outside it) and
    //    the global texel grid's anchors.
    if (plan_.count > 0) {
        glBindFramebuffer(GL_FRAMEBUFFER, fbo_[cur_]);
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        glDepthMask(GL_TRUE);
        glClearDepth(1.0);
        glDisable(GL_CULL_FACE);
        if (invariant_) {
            const int guard = (kGuardViewport - S) / 2;
            glViewport(-guard, -guard, kGuardViewport, kGuardViewport);
            glUseProgram(invariant_prog_);
            glUniformMatrix4fv(glGetUniformLocation(invariant_prog_, "u_light_global"), 1, GL_FALSE, glm::value_ptr(light_global_));
            glUniform2i(glGetUniformLocation(invariant_prog_, "u_anchor"), anchor_.x, anchor_.y);
            glUniform2i(glGetUniformLocation(invariant_prog_, "u_viewport_anchor"), anchor_.x - guard, anchor_.y - guard);
            glUniform2f(glGetUniformLocation(invariant_prog_, "u_viewport_size"), float(kGuardViewport), float(kGuardViewport));
            glUniform1i(glGetUniformLocation(invariant_prog_, "u_offset"), s.bias == CachedShadowMapSettings::Bias::Offset ? 1 : 0);
        } else {
            glViewport(0, 0, S, S);
            glUseProgram(plain_prog_);
            glUniformMatrix4fv(glGetUniformLocation(plain_prog_, "u_light_view_proj"), 1, GL_FALSE, glm::value_ptr(light_vp_f_));
            if (s.bias == CachedShadowMapSettings::Bias::Offset) {
                glEnable(GL_POLYGON_OFFSET_FILL);
                glPolygonOffset(2.f, 2.f);
            }
        }
        glEnable(GL_SCISSOR_TEST);
        for (std::size_t k = 0; k < plan_.count; ++k) {
            const shadowkit::ShadowCacheRect& r = rects_[k];
            glScissor(r.x, r.y, r.width, r.height);
            glClear(GL_DEPTH_BUFFER_BIT);
            for (std::size_t i = 0; i < mesh_.size(); ++i) {
                if (!drawn_[i]) continue;
                const shadowkit::ShadowCacheFootprint f = shadowkit::shadow_cache_footprint(light_vp_, S, S, casters_[i].bounds);
                if (f.status != shadowkit::Status::Ok || !f.visible) continue;
                if (f.rect.x >= r.x + r.width || r.x >= f.rect.x + f.rect.width || f.rect.y >= r.y + r.height ||
                    r.y >= f.rect.y + f.rect.height)
                    continue;
                skgl::draw_mesh(v.gpu->meshes[mesh_[i]]);
            }
        }
        glDisable(GL_SCISSOR_TEST);
        glDisable(GL_POLYGON_OFFSET_FILL);
    }
    // the map now holds this frame's state
    previous_ = current_;
    previous_.has_content = true;
    for (shadowkit::ShadowCacheCaster& c : casters_) std::copy(c.bounds, c.bounds + 6, c.previous_bounds);
}

void CachedShadowMap::render_visibility(const app::View& v, const CachedShadowMapSettings& s) {
    // 3. V at the G-buffer's points: the snippet's compare, 2x2 PCF (bias=auto: four texel-centre
    //    compares, GL_NEAREST; bias=offset: GL_LINEAR), the far border outside.
    const bool automatic = s.bias == CachedShadowMapSettings::Bias::Auto;
    const GLint filter = automatic ? GL_NEAREST : GL_LINEAR;
    glTextureParameteri(tex_[cur_], GL_TEXTURE_MIN_FILTER, filter);
    glTextureParameteri(tex_[cur_], GL_TEXTURE_MAG_FILTER, filter);
    glUseProgram(vis_prog_);
    glUniform1i(glGetUniformLocation(vis_prog_, "u_auto"), automatic ? 1 : 0);
    app::set_light_uniforms(vis_prog_, v.light());
    glUniformMatrix4fv(glGetUniformLocation(vis_prog_, "u_light_view_proj"), 1, GL_FALSE, glm::value_ptr(light_vp_f_));
    pass_.draw(vis_prog_, *v.gpu, GL_TEXTURE_2D, tex_[cur_]);
}

std::size_t CachedShadowMap::casters_drawn() const {
    return static_cast<std::size_t>(std::count(drawn_.begin(), drawn_.end(), std::uint8_t(1)));
}

void CachedShadowMap::release() {  // (no GL call without objects: the App may have no context)
    if (tex_[0]) glDeleteTextures(2, tex_);
    if (fbo_[0]) glDeleteFramebuffers(2, fbo_);
    if (plain_prog_) glDeleteProgram(plain_prog_);
    if (invariant_prog_) glDeleteProgram(invariant_prog_);
    if (vis_prog_) glDeleteProgram(vis_prog_);
    tex_[0] = tex_[1] = fbo_[0] = fbo_[1] = 0;
    plain_prog_ = invariant_prog_ = vis_prog_ = 0;
    size_ = 0;
    cur_ = 0;
    mesh_.clear();
    casters_.clear();
}
