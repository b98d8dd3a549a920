// samples/silhouette_maps/silhouette_maps.cpp - shadow silhouette maps, top to bottom:
//   init    once per scene: each caster's edge adjacency (silhouette.hpp), the programs, one vertex
//           buffer of silhouette edges (one instance per edge), the V target
//   update  CPU, every frame: the light's frustum (sk::fit_light), each caster's facing and silhouette
//           for the light, the silhouette edges projected into the map's texel space with their
//           window depths (silmap_project_edges)
//   render  GPU, every frame: 1 the casters' depth from the light; 2 the silhouette map: every edge
//           as a quad widened over the texels it crosses, each texel storing one point on the edge
//           (glsl/silhouette_map.glsl); 3 V at the G-buffer's points: the four depth tests, and where
//           they disagree the silhouette points decide (sk_silmap_visibility)
// map=plain keeps only pass 1 at side sqrt(2) N with hardware 2x2 PCF (glsl/shadow_map.glsl): the
// same memory as the N x N silhouette map's 8 bytes a texel.
#include "silhouette_maps.hpp"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>

namespace {

// Pass 2, one instance per edge: a quad around the edge; each fragment (a texel of the dual grid the
// edge crosses) writes the paper's silhouette point unless the depth map shows the edge occluded there.
const char* kEdgeVS = R"(
layout(location = 0) in vec4 a_ab;   // a.xy, b.xy (texel space)
layout(location = 1) in vec2 a_z;    // window depths at a and b
uniform vec2 u_size;
flat out vec4 v_ab;
flat out vec2 v_z;
void main() {
    v_ab = a_ab;
    v_z = a_z;
    gl_Position = sk_silmap_edge_vertex(a_ab.xy, a_ab.zw, gl_VertexID, u_size);
}
)";
const char* kEdgeFS = R"(
layout(binding = 2) uniform sampler2D u_depth;
flat in vec4 v_ab;
flat in vec2 v_z;
uniform float u_occlusion_bias;
layout(location = 0) out vec4 o_silmap;
void main() {
    vec2 local;
    float w;
    if (!sk_silmap_point(gl_FragCoord.xy, v_ab.xy, v_ab.zw, local, w)) discard;
    if (sk_silmap_occluded(u_depth, ivec2(gl_FragCoord.xy), v_ab.xy, v_ab.zw, v_z.x, v_z.y, local, u_occlusion_bias)) discard;
    o_silmap = vec4(local, 0.0, w / 255.0);
}
)";

// Pass 3: the depth map at unit 2 (compare off), the silhouette map at unit 3; outside the map: lit.
const char* kLookup = R"(
layout(binding = 2) uniform sampler2D u_depth;
layout(binding = 3) uniform sampler2D u_silmap;
uniform mat4 u_light_view_proj;
float technique_visibility(vec3 p, vec3 n) {
    vec4 c = u_light_view_proj * vec4(p, 1.0);
    if (c.w <= 0.0) return 1.0;
    vec3 w = c.xyz / c.w * 0.5 + 0.5;
    if (any(lessThan(w.xy, vec2(0.0))) || any(greaterThan(w.xy, vec2(1.0)))) return 1.0;
    return sk_silmap_visibility(u_depth, u_silmap, w.xy * vec2(textureSize(u_depth, 0)), w.z, 0.0);
}
)";
// map=plain: one hardware compare (2x2 PCF) of the depth map at unit 2.
const char* kLookupPlain = R"(
layout(binding = 2) uniform sampler2DShadow u_shadow_map;
uniform mat4 u_light_view_proj;
float technique_visibility(vec3 p, vec3 n) {
    return sk_shadow_map_visibility(u_shadow_map, u_light_view_proj, p, false, 0.0, 1.0);
}
)";

bool failed(shadowkit::Status st, const char* what, std::string& error) {
    if (st == shadowkit::Status::Ok) return false;
    if (error.empty()) error = std::string(what) + ": " + shadowkit::status_name(st);
    return true;
}

}  // namespace

bool SilhouetteMap::init(const app::View& v, std::string& why) {
    release();
    const sk::Scene& scene = *v.scene;
    if (v.light().type == sk::LightType::Point || v.light().type == sk::LightType::Directional) {
        why = "silhouette maps need a light with a perspective frustum (spot or area light)";
        return false;
    }
    // each caster's edge adjacency (allocates; once per mesh)
    std::size_t max_edges = 0;
    for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
        const sk::Mesh& m = scene.meshes[i];
        if (!m.caster) continue;
        Caster c;
        c.mesh = i;
        c.adj = shadowkit::silhouette_build_adjacency(m.positions.data(), m.positions.size(), m.indices.data(),
                                                      m.indices.size());
        if (failed(c.adj.status, ("silhouette_build_adjacency of mesh '" + m.name + "'").c_str(), why)) return false;
        c.facing.assign(c.adj.face_count(), 0);
        c.sil.assign(2 * c.adj.max_silhouette_edges(), 0);
        max_edges += c.adj.max_silhouette_edges();
        casters_.push_back(std::move(c));
    }
    edges_.assign(max_edges, {});
    edge_vertices_.assign(6 * std::max<std::size_t>(max_edges, 1), 0.f);

    // the edges: one instance each, a.xy b.xy (vec4) and the two depths (vec2), rewritten every frame
    glGenVertexArrays(1, &vao_);
    glGenBuffers(1, &vbo_);
    glBindVertexArray(vao_);
    glBindBuffer(GL_ARRAY_BUFFER, vbo_);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(edge_vertices_.size() * sizeof(float)), nullptr, GL_STREAM_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
    glVertexAttribDivisor(0, 1);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, 6 * sizeof(float), reinterpret_cast<const void*>(4 * sizeof(float)));
    glVertexAttribDivisor(1, 1);
    glBindVertexArray(0);

    // programs: the depth pass, the silhouette-map pass, the two lookups
    const std::string snippet = app::load_snippet("silhouette_map", why);
    const std::string plain = app::load_snippet("shadow_map", why);
    if (snippet.empty() || plain.empty()) return false;
    const std::string head = "#version 450 core\n" + snippet;
    depth_prog_ = skgl::depth_only_program(why);  // gl_Position = u_light_view_proj * a_position, no color
    edge_prog_ = skgl::compile_program({{GL_VERTEX_SHADER, head + kEdgeVS}, {GL_FRAGMENT_SHADER, head + kEdgeFS}}, why);
    vis_prog_ = app::compile_visibility_program(snippet, kLookup, why);
    plain_prog_ = app::compile_visibility_program(plain, kLookupPlain, why);
    if (!depth_prog_ || !edge_prog_ || !vis_prog_ || !plain_prog_) return false;
    return pass_.init(v.width, v.height, why);
}

void SilhouetteMap::update(const app::View& v, const SilhouetteMapSettings& s) {
    const sk::Scene& scene = *v.scene;
    const sk::LightMatrices lm = sk::fit_light(scene);  // a perspective frustum from the light around the scene
    light_vp_ = lm.proj * lm.view;
    edge_count_ = 0;
    if (s.map == SilhouetteMapSettings::Map::Plain) return;
    const glm::vec4 light(v.light().position, 1.f);
    const glm::uvec2 size(static_cast<unsigned>(s.size), static_cast<unsigned>(s.size));
    for (Caster& c : casters_) {
        const sk::Mesh& m = scene.meshes[c.mesh];
        // the silhouette for the light: edges between a lit and an unlit face
        const shadowkit::SilhouetteFacing fr = shadowkit::silhouette_compute_facing(
            c.adj, m.positions.data(), m.positions.size(), light, c.facing.data(), c.facing.size());
        const shadowkit::SilhouetteResult sr = shadowkit::silhouette_extract(c.adj, c.facing.data(), c.facing.size(),
                                                                             c.sil.data(), c.sil.size(), nullptr, 0);
        // its edges in the map's texel space, with window depths (edges behind the light: culled)
        const shadowkit::SilmapProjectResult pr = shadowkit::silmap_project_edges(
            light_vp_, shadowkit::ClipDepth::NegativeOneToOne, size, m.positions.data(), m.positions.size(),
            c.sil.data(), sr.count / 2, edges_.data() + edge_count_, edges_.size() - edge_count_);
        if (failed(fr.status, "silhouette_compute_facing", error_) || failed(sr.status, "silhouette_extract", error_) ||
            failed(pr.status, "silmap_project_edges", error_))
            return;
        edge_count_ += pr.count;
    }
    for (std::size_t e = 0; e < edge_count_; ++e) {
        const shadowkit::SilmapEdge& E = edges_[e];
        const float vtx[6] = {E.a.x, E.a.y, E.b.x, E.b.y, E.depth_a, E.depth_b};
        std::copy(vtx, vtx + 6, edge_vertices_.begin() + static_cast<std::ptrdiff_t>(6 * e));
    }
}

// The maps of these settings: the depth map (N x N, read with texelFetch-like GL_NEAREST and no
// compare; map=plain: sqrt(2) N, hardware compare with GL_LINEAR for the 2x2 filter) and the N x N
// RGBA8 silhouette map. Outside the depth map: the far border (lit).
void SilhouetteMap::make_maps(const SilhouetteMapSettings& s) {
    skgl::destroy_target(depth_);
    skgl::destroy_target(silmap_);
    std::string why;
    const bool plain = s.map == SilhouetteMapSettings::Map::Plain;
    const int side = plain ? static_cast<int>(std::lround(std::sqrt(2.0) * s.size)) : s.size;
    skgl::make_target(depth_, side, side, {}, GL_DEPTH_COMPONENT32F, why);
    if (plain) {
        skgl::set_depth_compare(depth_.depth, true, true);
    } else {
        skgl::make_target(silmap_, side, side, {GL_RGBA8}, 0, why);
        for (GLuint t : {depth_.depth, silmap_.color[0]}) skgl::set_nearest_clamped(t);
        skgl::set_depth_compare(depth_.depth, false, false);
    }
    built_ = s;
    have_maps_ = true;
}

void SilhouetteMap::render(const app::View& v, const SilhouetteMapSettings& s) {
    if (!have_maps_ || s.size != built_.size || s.map != built_.map) make_maps(s);
    const bool plain = s.map == SilhouetteMapSettings::Map::Plain;
    const int side = depth_.width;

    // 1. The casters' depth from the light: depth test GL_LESS, cleared to the far plane, a
    //    slope-scaled polygon offset (2, 2) pushing the stored depth away from the light.
    glBindFramebuffer(GL_FRAMEBUFFER, depth_.fbo);
    glViewport(0, 0, side, side);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glClear(GL_DEPTH_BUFFER_BIT);
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(2.f, 2.f);
    glUseProgram(depth_prog_);
    glUniformMatrix4fv(glGetUniformLocation(depth_prog_, "u_light_view_proj"), 1, GL_FALSE, glm::value_ptr(light_vp_));
    for (std::size_t i = 0; i < v.gpu->meshes.size(); ++i)
        if (v.gpu->caster[i]) skgl::draw_mesh(v.gpu->meshes[i]);
    glDisable(GL_POLYGON_OFFSET_FILL);
    glDisable(GL_DEPTH_TEST);

    if (!plain) {
        // 2. The silhouette map: cleared to "no point" (0.5, 0.5, weight 0); every edge's quad (6
        //    vertices, one instance an edge); blending keeps the last point's rgb and adds the edges'
        //    weights in alpha (two edges in one texel: a weight above 2, the lookup falls back to the
        //    depth tests there). The depth map at unit 2 for the occlusion test.
        glBindBuffer(GL_ARRAY_BUFFER, vbo_);
        glBufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(6 * edge_count_ * sizeof(float)), edge_vertices_.data());
        glBindFramebuffer(GL_FRAMEBUFFER, silmap_.fbo);
        const float none[4] = {0.5f, 0.5f, 0.f, 0.f};
        glClearBufferfv(GL_COLOR, 0, none);
        glEnable(GL_BLEND);
        glBlendEquation(GL_FUNC_ADD);
        glBlendFuncSeparate(GL_ONE, GL_ZERO, GL_ONE, GL_ONE);
        glUseProgram(edge_prog_);
        glUniform2f(glGetUniformLocation(edge_prog_, "u_size"), float(side), float(side));
        glUniform1f(glGetUniformLocation(edge_prog_, "u_occlusion_bias"), s.occlusion_bias);
        glActiveTexture(GL_TEXTURE2);
        glBindTexture(GL_TEXTURE_2D, depth_.depth);
        glBindVertexArray(vao_);
        glDrawArraysInstanced(GL_TRIANGLES, 0, 6, static_cast<GLsizei>(edge_count_));
        glBindVertexArray(0);
        glDisable(GL_BLEND);
        glActiveTexture(GL_TEXTURE3);
        glBindTexture(GL_TEXTURE_2D, silmap_.color[0]);
    }

    // 3. V at the G-buffer's points (the depth map at unit 2, the silhouette map at unit 3).
    const GLuint prog = plain ? plain_prog_ : vis_prog_;
    glUseProgram(prog);
    app::set_light_uniforms(prog, v.light());
    glUniformMatrix4fv(glGetUniformLocation(prog, "u_light_view_proj"), 1, GL_FALSE, glm::value_ptr(light_vp_));
    pass_.draw(prog, *v.gpu, GL_TEXTURE_2D, depth_.depth);
}

void SilhouetteMap::release() {  // (no GL call without objects: the App may have no context)
    skgl::destroy_target(depth_);
    skgl::destroy_target(silmap_);
    if (vao_) glDeleteVertexArrays(1, &vao_);
    if (vbo_) glDeleteBuffers(1, &vbo_);
    for (GLuint p : {depth_prog_, edge_prog_, vis_prog_, plain_prog_})
        if (p) glDeleteProgram(p);
    vao_ = vbo_ = depth_prog_ = edge_prog_ = vis_prog_ = plain_prog_ = 0;
    casters_.clear();
    error_.clear();
    have_maps_ = false;
}
