// samples/dual_paraboloid/dual_paraboloid.cpp - a point light's dual-paraboloid map, top to bottom:
//   init        once per scene: the programs, the V target
//   update      CPU, every frame: the range of the stored distance (the farthest scene corner from the
//               light) and the paraboloids' frame (omni_paraboloid_frame: its axis up, so the rim runs
//               around the horizon); when the light or the settings moved, tessellate
//   tessellate  each caster cut into n x n sub-triangles per triangle, n from the longest edge and the
//               edge length omni_paraboloid_max_edge_length allows at the triangle's distance
//   render      GPU, every frame: 1 both layers: the casters' linear distance, each vertex projected
//               onto its paraboloid (sk_dp_clip_position), the other hemisphere clipped away
//               (gl_ClipDistance); 2 V at the G-buffer's points with the receiver-side bias, whose
//               footprint adds the chords' deviation (tess texels)
#include "dual_paraboloid.hpp"

#include <shadowkit/omni_shadow.hpp>

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>

namespace {

// The distance pass: the vertex projected onto the layer's paraboloid (side +1 / -1), a clip distance
// that keeps the triangles of this hemisphere (and kMargin beyond its rim); the fragment stores the
// linear distance to the light over the range.
const char* kDistanceVS = R"(
layout(location = 0) in vec3 a_position;
uniform mat4 u_dp_view;
uniform float u_side;
uniform float u_range;
uniform float u_margin;
out vec3 v_world;
void main() {
    v_world = a_position;
    gl_Position = sk_dp_clip_position(u_dp_view, a_position, u_side, u_range, false);
    gl_ClipDistance[0] = sk_dp_clip_distance(u_dp_view, a_position, u_side, u_margin);
}
)";
const char* kDistanceFS = R"(
in vec3 v_world;
uniform vec3 u_light;
uniform float u_range;
void main() { gl_FragDepth = sk_omni_linear_depth(v_world, vec4(u_light, 1.0), u_range); }
)";
// V's lookup (after glsl/omni_shadow.glsl): both layers in one array at unit 2. The bias's footprint is
// the filter's (pcf + 1 texel diagonals) plus the chords' deviation from the curves (tess texels).
const char* kLookup = R"(
layout(binding = 2) uniform sampler2DArrayShadow u_dp;
uniform mat4 u_dp_view;
uniform vec3 u_light;
uniform float u_range;
uniform float u_size;
uniform float u_tess;
uniform int u_pcf;
uniform vec2 u_storage;
float technique_visibility(vec3 p, vec3 n) {
    vec3 L = u_light - p;
    float d = length(L);
    vec4 c = sk_dp_coord(u_dp_view, p);
    float radius = float(u_pcf + 1) * 1.4143 + u_tess;
    float b = sk_omni_bias(d, dot(n, L / d), sk_dp_texel_angle(u_size, c.w), radius, 1.4835, u_storage);
    if (u_pcf > 0) return sk_dp_shadow_pcf(u_dp, u_dp_view, p, u_range, b, u_size, u_pcf);
    return sk_dp_shadow(u_dp, u_dp_view, p, u_range, b);
}
)";

bool lex_less(const glm::vec3& a, const glm::vec3& b) {
    if (a.x != b.x) return a.x < b.x;
    if (a.y != b.y) return a.y < b.y;
    return a.z < b.z;
}

// Uniform n x n subdivision of every triangle of a mesh (one n per mesh, so a shared edge is split at
// the same points from both sides; each triangle's points are computed from its corners sorted
// lexicographically, so they are bit-identical on both sides and the mesh stays watertight).
void subdivide(const sk::Mesh& m, int n, std::vector<glm::vec3>& pos, std::vector<std::uint32_t>& idx) {
    pos.clear();
    idx.clear();
    for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
        glm::vec3 v[3] = {m.positions[m.indices[t]], m.positions[m.indices[t + 1]], m.positions[m.indices[t + 2]]};
        std::sort(v, v + 3, lex_less);
        const auto base = static_cast<std::uint32_t>(pos.size());
        std::vector<std::uint32_t> row(static_cast<std::size_t>(n) + 1);  // first point of row i (i + j <= n)
        for (int i = 0, k = 0; i <= n; k += n + 1 - i, ++i) row[static_cast<std::size_t>(i)] = base + static_cast<std::uint32_t>(k);
        auto id = [&](int i, int j) { return row[static_cast<std::size_t>(i)] + static_cast<std::uint32_t>(j); };
        for (int i = 0; i <= n; ++i)
            for (int j = 0; j <= n - i; ++j) {
                const double wa = i, wb = j, wc = n - i - j;
                pos.push_back(glm::vec3((wa * glm::dvec3(v[0]) + wb * glm::dvec3(v[1]) + wc * glm::dvec3(v[2])) / double(n)));
            }
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n - i; ++j) {
                idx.insert(idx.end(), {id(i, j), id(i + 1, j), id(i, j + 1)});
                if (j + 1 < n - i) idx.insert(idx.end(), {id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
            }
    }
}

}  // namespace

float DualParaboloid::max_radius() { return std::sqrt((1.f + kMargin) / (1.f - kMargin)); }

bool DualParaboloid::init(const app::View& v, std::string& why) {
    release();
    const std::string snippet = app::load_snippet("omni_shadow", why);
    if (snippet.empty()) return false;
    depth_prog_ = skgl::compile_program({{GL_VERTEX_SHADER, "#version 450 core\n" + snippet + kDistanceVS},
                                         {GL_FRAGMENT_SHADER, "#version 450 core\n" + snippet + kDistanceFS}},
                                        why);
    vis_prog_ = app::compile_visibility_program(snippet, kLookup, why);
    if (!depth_prog_ || !vis_prog_) return false;
    return pass_.init(v.width, v.height, why);
}

void DualParaboloid::update(const app::View& v, const DualParaboloidSettings& s) {
    const sk::Light& L = v.light();
    error_.clear();
    const glm::vec3 lo = v.scene->bounds_min(), hi = v.scene->bounds_max();
    range_ = 0.f;
    for (int i = 0; i < 8; ++i)
        range_ = std::max(range_, glm::length(glm::vec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z) - L.position));
    range_ *= 1.01f;
    // the frame: the light at the origin, +y the front paraboloid's axis (the sun, w = 0, is refused)
    const glm::vec4 light = L.homogeneous_position();
    const shadowkit::OmniParaboloidFrame fr = shadowkit::omni_paraboloid_frame(light, {0.f, 1.f, 0.f}, {0.f, 0.f, 1.f});
    if (fr.status != shadowkit::Status::Ok) {
        error_ = std::string("omni_paraboloid_frame status ") + shadowkit::status_name(fr.status);
        return;
    }
    frame_ = fr.view;
    if (L.position != tess_light_ || s.size != tess_size_ || s.tess != tess_tess_) tessellate(v, s);
}

void DualParaboloid::tessellate(const app::View& v, const DualParaboloidSettings& s) {
    for (auto& m : meshes_) skgl::destroy_mesh(m);
    meshes_.clear();
    triangles_ = 0;
    max_n_ = 1;
    const glm::vec3 light = v.light().position;
    for (const sk::Mesh& m : v.scene->meshes) {
        if (!m.caster) continue;
        int n = 1;  // the mesh's subdivision: enough for its worst triangle
        for (std::size_t t = 0; t + 2 < m.indices.size() && s.tess > 0.f; t += 3) {
            const glm::vec3 a = m.positions[m.indices[t]], b = m.positions[m.indices[t + 1]], c = m.positions[m.indices[t + 2]];
            const auto ml = shadowkit::omni_paraboloid_max_edge_length(distance_to_triangle(light, a, b, c),
                                                                       static_cast<std::uint32_t>(s.size), s.tess, max_radius());
            if (ml.status != shadowkit::Status::Ok) continue;
            const float longest = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
            if (ml.length > 0.f && std::isfinite(ml.length)) n = std::max(n, static_cast<int>(std::ceil(longest / ml.length)));
            else if (!(ml.length > 0.f)) n = 256;  // a caster through the light: as fine as allowed
        }
        n = std::min(n, 256);
        max_n_ = std::max(max_n_, n);
        std::vector<glm::vec3> pos = m.positions;
        std::vector<std::uint32_t> idx = m.indices;
        if (n > 1) subdivide(m, n, pos, idx);
        triangles_ += idx.size() / 3;
        meshes_.push_back(skgl::upload_mesh(&pos[0].x, &pos[0].x, pos.size(), idx.data(), idx.size()));
    }
    tess_light_ = light;
    tess_size_ = s.size;
    tess_tess_ = s.tess;
}

// Both paraboloids in one 2-layer array of 32-bit float depths that compares (sampler2DArrayShadow:
// GL_LEQUAL, GL_LINEAR), clamped; a framebuffer and a 2D view (the debug views) per layer.
void DualParaboloid::make_maps(int size) {
    if (maps_) glDeleteTextures(1, &maps_);
    if (layer_view_[0]) glDeleteTextures(2, layer_view_);
    if (fbo_[0]) glDeleteFramebuffers(2, fbo_);
    maps_ = skgl::make_depth_texture(GL_TEXTURE_2D_ARRAY, size, 2, GL_LINEAR, GL_CLAMP_TO_EDGE);
    skgl::make_depth_framebuffers(GL_TEXTURE_2D_ARRAY, maps_, 2, fbo_);
    glGenTextures(2, layer_view_);
    for (int i = 0; i < 2; ++i)
        glTextureView(layer_view_[i], GL_TEXTURE_2D, maps_, GL_DEPTH_COMPONENT32F, 0, 1, static_cast<GLuint>(i), 1);
    size_ = size;
}

void DualParaboloid::render(const app::View& v, const DualParaboloidSettings& s) {
    if (s.size != size_) make_maps(s.size);
    const glm::vec3 light = v.light().position;

    // 1. Both layers: the casters' linear distance, depth test GL_LESS, cleared to the range's end, no
    //    culling of back faces, no polygon offset, the other hemisphere clipped (GL_CLIP_DISTANCE0).
    glUseProgram(depth_prog_);
    glUniformMatrix4fv(glGetUniformLocation(depth_prog_, "u_dp_view"), 1, GL_FALSE, glm::value_ptr(frame_));
    glUniform3fv(glGetUniformLocation(depth_prog_, "u_light"), 1, glm::value_ptr(light));
    glUniform1f(glGetUniformLocation(depth_prog_, "u_range"), range_);
    glUniform1f(glGetUniformLocation(depth_prog_, "u_margin"), kMargin);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_CULL_FACE);
    glClearDepth(1.0);
    glEnable(GL_CLIP_DISTANCE0);
    for (int layer = 0; layer < 2; ++layer) {
        glBindFramebuffer(GL_FRAMEBUFFER, fbo_[layer]);
        glViewport(0, 0, size_, size_);
        glClear(GL_DEPTH_BUFFER_BIT);
        if (!error_.empty()) continue;  // the sun: empty maps, all lit
        glUniform1f(glGetUniformLocation(depth_prog_, "u_side"), layer == 0 ? 1.f : -1.f);
        for (const skgl::GpuMesh& m : meshes_) skgl::draw_mesh(m);
    }
    glDisable(GL_CLIP_DISTANCE0);

    // 2. V at the G-buffer's points.
    glUseProgram(vis_prog_);
    app::set_light_uniforms(vis_prog_, v.light());
    glUniformMatrix4fv(glGetUniformLocation(vis_prog_, "u_dp_view"), 1, GL_FALSE, glm::value_ptr(frame_));
    glUniform3fv(glGetUniformLocation(vis_prog_, "u_light"), 1, glm::value_ptr(light));
    glUniform1f(glGetUniformLocation(vis_prog_, "u_range"), range_);
    glUniform1f(glGetUniformLocation(vis_prog_, "u_size"), float(size_));
    glUniform1f(glGetUniformLocation(vis_prog_, "u_tess"), s.tess);
    glUniform1i(glGetUniformLocation(vis_prog_, "u_pcf"), s.pcf);
    glUniform2f(glGetUniformLocation(vis_prog_, "u_storage"), 1e-5f * range_, 2.3841858e-7f /* 2^-22 */);
    pass_.draw(vis_prog_, *v.gpu, GL_TEXTURE_2D_ARRAY, maps_);
}

// The closest point by regions (Ericson, Real-Time Collision Detection 5.1.5).
float DualParaboloid::distance_to_triangle(glm::vec3 p, glm::vec3 a, glm::vec3 b, glm::vec3 c) {
    const glm::vec3 ab = b - a, ac = c - a, ap = p - a;
    const float d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0.f && d2 <= 0.f) return glm::length(p - a);
    const glm::vec3 bp = p - b;
    const float d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0.f && d4 <= d3) return glm::length(p - b);
    const float vc = d1 * d4 - d3 * d2;
    if (vc <= 0.f && d1 >= 0.f && d3 <= 0.f) return glm::length(p - (a + ab * (d1 / (d1 - d3))));
    const glm::vec3 cp = p - c;
    const float d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0.f && d5 <= d6) return glm::length(p - c);
    const float vb = d5 * d2 - d1 * d6;
    if (vb <= 0.f && d2 >= 0.f && d6 <= 0.f) return glm::length(p - (a + ac * (d2 / (d2 - d6))));
    const float va = d3 * d6 - d5 * d4;
    if (va <= 0.f && (d4 - d3) >= 0.f && (d5 - d6) >= 0.f)
        return glm::length(p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))));
    const float den = va + vb + vc;
    if (!(std::fabs(den) > 0.f)) return std::min({glm::length(p - a), glm::length(p - b), glm::length(p - c)});
    return glm::length(p - (a + ab * (vb / den) + ac * (vc / den)));
}

void DualParaboloid::release() {  // (no GL call without objects: the App may have no context)
    if (maps_) glDeleteTextures(1, &maps_);
    if (layer_view_[0]) glDeleteTextures(2, layer_view_);
    if (fbo_[0]) glDeleteFramebuffers(2, fbo_);
    if (depth_prog_) glDeleteProgram(depth_prog_);
    if (vis_prog_) glDeleteProgram(vis_prog_);
    maps_ = depth_prog_ = vis_prog_ = 0;
    fbo_[0] = fbo_[1] = layer_view_[0] = layer_view_[1] = 0;
    for (auto& m : meshes_) skgl::destroy_mesh(m);
    meshes_.clear();
    tess_light_ = glm::vec3(NAN);
    tess_size_ = 0;
    size_ = 0;
    error_.clear();
}
