// Drivers for omni_shadow.hpp + glsl/omni_shadow.glsl: point-light shadows from a cube map
// ("cube_sm", with per-face caster culling on/off) and from a dual-paraboloid map
// ("dual_paraboloid", with casters re-tessellated to a target deviation from the header's
// tessellation-error bound). Both store the linear distance to the light and bias on the receiver
// side with omni_distance_bias's formula (its GLSL twin sk_omni_bias).
#include <shadowkit/omni_shadow.hpp>

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <string>

#include "driver_util.hpp"

namespace sk {

namespace {

// Range of the stored distance: the farthest scene corner from the light (plus 1%).
float omni_range(const Scene& s) {
    const glm::vec3 lo = s.bounds_min(), hi = s.bounds_max();
    float r = 0.f;
    for (int i = 0; i < 8; ++i) {
        const glm::vec3 c((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
        r = std::max(r, glm::length(c - s.light.position));
    }
    return r * 1.01f;
}

// Depth pass fragment stage shared by both techniques: the linear distance to the light.
std::string distance_fs(const std::string& snippet) {
    return "#version 450 core\n" + snippet + R"(
in vec3 v_world;
uniform vec3 u_light;
uniform float u_range;
void main() { gl_FragDepth = sk_omni_linear_depth(v_world, vec4(u_light, 1.0), u_range); }
)";
}

// Receiver bias terms of a 32-bit float depth texture (omni_distance_bias: 2^-22 d) plus a small
// constant for the rasterizer's interpolation of world positions (a few float ulps of the scene).
const float kStorageRelative = 2.3841858e-7f;  // 2^-22

// Distance-pass state shared by both techniques: depth_prog bound, depth test GL_LESS, no culling, clear depth 1.
void begin_distance_pass(GLuint depth_prog) {
    glUseProgram(depth_prog);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDisable(GL_CULL_FACE);
    glClearDepth(1.0);
}

// u_light and u_range (the stored distance's range), read by both the distance pass and the lookup.
void set_distance_uniforms(GLuint prog, const glm::vec3& light, float range) {
    glUniform3fv(glGetUniformLocation(prog, "u_light"), 1, glm::value_ptr(light));
    glUniform1f(glGetUniformLocation(prog, "u_range"), range);
}

// ----------------------------------------------------------------------------------- cube map
// params: size (face texels), culling (0/1: omni_cull_face_lists on mesh boxes), lookup (not swept:
// 0 hardware 2x2 compare, 1 manual nearest compare, 2 3x3 PCF of 2x2 compares).
class CubeShadowMap final : public Technique {
public:
    std::string name() const override { return "cube_sm"; }
    std::string description() const override {
        return "point-light cube shadow map, linear distance, receiver bias, per-face caster culling (omni_shadow)";
    }
    bool hard() const override { return true; }
    std::vector<ParamSet> sweep(const Scene& scene, bool quick) const override {
        if (scene.light.type != LightType::Point) return {};
        std::vector<ParamSet> out;
        const std::vector<int> sizes = quick ? std::vector<int>{512} : std::vector<int>{256, 512, 1024};
        for (int s : sizes)
            for (int c : {0, 1}) out.push_back(ParamSet{{{"size", double(s)}, {"culling", double(c)}}});
        return out;
    }
    RunResult run(const RunContext& ctx, const ParamSet& params) override {
        const Scene& scene = ctx.scene;
        if (scene.light.type != LightType::Point) return RunResult::failure("cube_sm needs a point light");
        const int size = static_cast<int>(params.get("size", 512));
        const bool culling = params.get("culling", 1) != 0.0;
        const int lookup = static_cast<int>(params.get("lookup", 0));
        if (size < 4 || size > 8192) return RunResult::failure("size out of range");
        RunResult r;
        const float range = omni_range(scene);
        shadowkit::OmniCubeInput ci;
        ci.light_position = glm::vec4(scene.light.position, 1.f);
        ci.far_z = range;
        ci.near_z = range * 1e-3f;
        // caster boxes (mesh indices), culled per face each frame (CPU time = median)
        std::vector<float> boxes;
        std::vector<std::uint32_t> mesh_of;
        for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
            if (!scene.meshes[i].caster) continue;
            glm::vec3 a, b;
            mesh_bounds(scene.meshes[i], a, b);
            boxes.insert(boxes.end(), {a.x, a.y, a.z, b.x, b.y, b.z});
            mesh_of.push_back(static_cast<std::uint32_t>(i));
        }
        shadowkit::OmniCubeMatrices cm;
        shadowkit::OmniCullResult cr;
        std::vector<std::uint32_t> lists(6 * mesh_of.size() + 1);
        std::size_t off[7] = {0, 0, 0, 0, 0, 0, 0};
        const char* failed = "";
        auto cull = [&]() -> bool {
            cm = shadowkit::omni_cube_matrices(ci);
            if (cm.status != shadowkit::Status::Ok) {
                failed = "omni_cube_matrices failed";
                return false;
            }
            if (culling) {
                shadowkit::OmniCullInput in;
                in.light_position = ci.light_position;
                in.near_z = ci.near_z;
                in.far_z = ci.far_z;
                in.boxes = boxes.data();
                in.box_count = mesh_of.size();
                cr = shadowkit::omni_cull_face_lists(in, lists.data(), lists.size(), off);
                if (cr.status != shadowkit::Status::Ok) {
                    failed = "omni_cull_face_lists failed";
                    return false;
                }
            }
            return true;
        };
        if (!median_cpu_ms(std::max(ctx.frames, 1), cull, r.cpu_ms)) return RunResult::failure(failed);
        std::array<std::vector<std::uint32_t>, 6> face_meshes;
        for (int f = 0; f < 6; ++f) {
            if (culling)
                for (std::size_t k = off[f]; k < off[f + 1]; ++k) face_meshes[static_cast<std::size_t>(f)].push_back(mesh_of[lists[k]]);
            else
                face_meshes[static_cast<std::size_t>(f)] = mesh_of;
        }

        std::string why;
        const std::string snippet = load_snippet("omni_shadow", why);
        if (snippet.empty()) return RunResult::failure(why);
        std::string log;
        const std::string vs = R"(#version 450 core
layout(location = 0) in vec3 a_position;
uniform mat4 u_light_view_proj;
out vec3 v_world;
void main() { v_world = a_position; gl_Position = u_light_view_proj * vec4(a_position, 1.0); }
)";
        GLuint depth = skgl::compile_program({{GL_VERTEX_SHADER, vs}, {GL_FRAGMENT_SHADER, distance_fs(snippet)}}, log);
        if (!depth) return RunResult::failure(log);
        GLuint vis = compile_visibility_program(snippet, R"(
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
    if (u_lookup == 1) return sk_omni_cube_shadow_manual(u_cube_distance, vec4(u_light, 1.0), p, u_range, b);
    if (u_lookup == 2) return sk_omni_cube_pcf(u_cube, vec4(u_light, 1.0), p, u_range, b, u_size, 1);
    return sk_omni_cube_shadow(u_cube, vec4(u_light, 1.0), p, u_range, b);
}
)", log);
        if (!vis) {
            glDeleteProgram(depth);
            return RunResult::failure(log);
        }
        const GLuint cube = make_depth_compare_texture(GL_TEXTURE_CUBE_MAP, size, 1);
        glEnable(GL_TEXTURE_CUBE_MAP_SEAMLESS);
        GLuint nearest = 0;  // the manual variant reads the same texture without compare
        glGenSamplers(1, &nearest);
        glSamplerParameteri(nearest, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glSamplerParameteri(nearest, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glSamplerParameteri(nearest, GL_TEXTURE_COMPARE_MODE, GL_NONE);
        GLuint fbo[6];
        make_depth_layer_fbos(GL_TEXTURE_CUBE_MAP, cube, 6, fbo);
        VisibilityPass pass;
        if (!pass.init(ctx.gpu.width, ctx.gpu.height, why)) return RunResult::failure(why);
        glUseProgram(vis);
        set_light_uniforms(vis, scene.light);
        set_distance_uniforms(vis, scene.light.position, range);
        glUniform1f(glGetUniformLocation(vis, "u_size"), float(size));
        glUniform1i(glGetUniformLocation(vis, "u_lookup"), lookup);
        glUniform2f(glGetUniformLocation(vis, "u_storage"), 1e-5f * range, kStorageRelative);
        glUseProgram(depth);
        set_distance_uniforms(depth, scene.light.position, range);
        const GLint loc_vp = glGetUniformLocation(depth, "u_light_view_proj");
        auto frame = [&] {
            begin_distance_pass(depth);
            for (int f = 0; f < 6; ++f) {
                clear_depth_layer(fbo[f], size);
                glUniformMatrix4fv(loc_vp, 1, GL_FALSE, glm::value_ptr(cm.view_proj[f]));
                draw_casters(ctx.gpu, &face_meshes[static_cast<std::size_t>(f)]);
            }
            glActiveTexture(GL_TEXTURE3);
            glBindTexture(GL_TEXTURE_CUBE_MAP, cube);
            glBindSampler(3, nearest);
            pass.draw(vis, ctx.gpu, GL_TEXTURE_CUBE_MAP, cube);
            glBindSampler(3, 0);
        };
        measure_visibility(r, ctx, pass, frame);
        r.gpu_bytes = std::int64_t(size) * size * 4 * 6;
        double tris = 0.0, draws = 0.0;
        static const char* kFace[6] = {"+x", "-x", "+y", "-y", "+z", "-z"};
        r.work.push_back({"shadow_map_texels", 6.0 * size * size});
        for (int f = 0; f < 6; ++f) {
            const auto& fm = face_meshes[static_cast<std::size_t>(f)];
            for (std::uint32_t i : fm) tris += double(scene.meshes[i].indices.size() / 3);
            draws += double(fm.size());
            r.work.push_back({std::string("draws_") + kFace[f], double(fm.size())});
        }
        r.work.push_back({"draws", draws});
        r.work.push_back({"draws_saved", 6.0 * double(mesh_of.size()) - draws});
        r.work.push_back({"triangles_drawn", tris});
        return finish_run(std::move(r), {depth, vis}, [&] {
            glDeleteSamplers(1, &nearest);
            glDeleteFramebuffers(6, fbo);
            glDeleteTextures(1, &cube);
        });
    }
};

// -------------------------------------------------------------------------- dual paraboloid

// Distance from p to triangle abc (closest point by regions; Ericson, Real-Time Collision Detection 5.1.5).
float point_triangle_distance(glm::vec3 p, glm::vec3 a, glm::vec3 b, glm::vec3 c) {
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
    const float v = vb / den, w = vc / den;
    return glm::length(p - (a + ab * v + ac * w));
}

bool lex_less(const glm::vec3& a, const glm::vec3& b) {
    if (a.x != b.x) return a.x < b.x;
    if (a.y != b.y) return a.y < b.y;
    return a.z < b.z;
}

// Uniform n x n subdivision of every triangle of a mesh (one n per mesh, so shared edges are split
// at the same points from both sides; vertices are computed from the lexicographically sorted
// corners in a fixed order, so they are bit-identical and the mesh stays watertight).
void subdivide(const Mesh& m, int n, std::vector<glm::vec3>& pos, std::vector<std::uint32_t>& idx) {
    pos.clear();
    idx.clear();
    for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
        glm::vec3 v[3] = {m.positions[m.indices[t]], m.positions[m.indices[t + 1]], m.positions[m.indices[t + 2]]};
        std::sort(v, v + 3, lex_less);
        const auto base = static_cast<std::uint32_t>(pos.size());
        // row-major grid of barycentric points (i along v0, j along v1)
        std::vector<std::uint32_t> row(static_cast<std::size_t>(n) + 1);  // first index of row i (i + j <= n)
        for (int i = 0, k = 0; i <= n; k += n + 1 - i, ++i) row[static_cast<std::size_t>(i)] = base + static_cast<std::uint32_t>(k);
        auto id = [&](int i, int j) { return row[static_cast<std::size_t>(i)] + static_cast<std::uint32_t>(j); };
        for (int i = 0; i <= n; ++i)
            for (int j = 0; j <= n - i; ++j) {
                const double wa = i, wb = j, wc = n - i - j;
                const glm::dvec3 p = (wa * glm::dvec3(v[0]) + wb * glm::dvec3(v[1]) + wc * glm::dvec3(v[2])) / double(n);
                pos.push_back(glm::vec3(p));
            }
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n - i; ++j) {
                idx.insert(idx.end(), {id(i, j), id(i + 1, j), id(i, j + 1)});
                if (j + 1 < n - i) idx.insert(idx.end(), {id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
            }
    }
}

// params: size (map texels per side; size = sqrt(3) cube size gives equal texel counts,
// 2 size^2 = 6 cube^2: 443, 887, 1774 for cube 256, 512, 1024), tess (target
// deviation in texels of omni_paraboloid_edge_error; 0 = the scene's meshes as they are).
class DualParaboloid final : public Technique {
public:
    std::string name() const override { return "dual_paraboloid"; }
    std::string description() const override {
        return "point-light dual-paraboloid shadow map (Brabec 2002), casters tessellated to tess texels of curve error";
    }
    bool hard() const override { return true; }
    std::vector<ParamSet> sweep(const Scene& scene, bool quick) const override {
        if (scene.light.type != LightType::Point) return {};
        std::vector<ParamSet> out;
        if (quick) {
            for (double t : {0.0, 1.0}) out.push_back(ParamSet{{{"size", 887.0}, {"tess", t}}});
            return out;
        }
        for (int s : {443, 887, 1774})
            for (double t : {0.0, 4.0, 1.0}) out.push_back(ParamSet{{{"size", double(s)}, {"tess", t}}});
        return out;
    }
    RunResult run(const RunContext& ctx, const ParamSet& params) override {
        const Scene& scene = ctx.scene;
        if (scene.light.type != LightType::Point) return RunResult::failure("dual_paraboloid needs a point light");
        const int size = static_cast<int>(params.get("size", 887));
        const double tess = params.get("tess", 1.0);
        const int radius = static_cast<int>(params.get("pcf", 0));
        if (size < 4 || size > 8192) return RunResult::failure("size out of range");
        if (!(tess >= 0.0) || radius < 0 || radius > 4) return RunResult::failure("bad tess / pcf");
        RunResult r;
        const float range = omni_range(scene);
        const glm::vec3 light = scene.light.position;
        const float margin = 0.1f;                                   // clip margin beyond the rim
        const float max_r = std::sqrt((1.f + margin) / (1.f - margin));  // map radius at n.z = -margin
        // frame: axis up, so the seam runs around the horizon
        shadowkit::OmniParaboloidFrame fr;
        median_cpu_ms(std::max(ctx.frames, 1), [&] {
            fr = shadowkit::omni_paraboloid_frame(glm::vec4(light, 1.f), {0.f, 1.f, 0.f}, {0.f, 0.f, 1.f});
            return true;
        }, r.cpu_ms);
        if (fr.status != shadowkit::Status::Ok) return RunResult::failure("omni_paraboloid_frame failed");

        // tessellate the casters (once per light position: reported as tess_ms, not per frame)
        const auto t_tess = Clock::now();
        std::vector<skgl::GpuMesh> meshes;
        double tris = 0.0;
        int max_n = 1;
        for (const auto& m : scene.meshes) {
            if (!m.caster) continue;
            int n = 1;
            if (tess > 0.0) {
                for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
                    const glm::vec3 a = m.positions[m.indices[t]], b = m.positions[m.indices[t + 1]],
                                    c = m.positions[m.indices[t + 2]];
                    const float D = point_triangle_distance(light, a, b, c);
                    const float longest = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
                    const auto ml = shadowkit::omni_paraboloid_max_edge_length(D, static_cast<std::uint32_t>(size),
                                                                               static_cast<float>(tess), max_r);
                    if (ml.status != shadowkit::Status::Ok) continue;
                    if (ml.length > 0.f && std::isfinite(ml.length))
                        n = std::max(n, static_cast<int>(std::ceil(longest / ml.length)));
                    else if (!(ml.length > 0.f))
                        n = 256;  // a caster through the light: as fine as allowed
                }
                n = std::min(n, 256);
            }
            max_n = std::max(max_n, n);
            std::vector<glm::vec3> pos;
            std::vector<std::uint32_t> idx;
            if (n == 1) {
                pos = m.positions;
                idx = m.indices;
            } else {
                subdivide(m, n, pos, idx);
            }
            tris += double(idx.size() / 3);
            meshes.push_back(skgl::upload_mesh(&pos[0].x, &pos[0].x, pos.size(), idx.data(), idx.size()));
        }
        const double tess_ms = ms_since(t_tess);

        std::string why;
        const std::string snippet = load_snippet("omni_shadow", why);
        if (snippet.empty()) return RunResult::failure(why);
        std::string log;
        const std::string vs = "#version 450 core\n" + snippet + R"(
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
        GLuint depth = skgl::compile_program({{GL_VERTEX_SHADER, vs}, {GL_FRAGMENT_SHADER, distance_fs(snippet)}}, log);
        GLuint vis = depth ? compile_visibility_program(snippet, R"(
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
    // filter footprint plus the drawn chord's deviation from the curve (tessellation bound)
    float radius = float(u_pcf + 1) * 1.4143 + u_tess;
    float b = sk_omni_bias(d, dot(n, L / d), sk_dp_texel_angle(u_size, c.w), radius, 1.4835, u_storage);
    if (u_pcf > 0) return sk_dp_shadow_pcf(u_dp, u_dp_view, p, u_range, b, u_size, u_pcf);
    return sk_dp_shadow(u_dp, u_dp_view, p, u_range, b);
}
)", log)
                           : 0;
        if (!depth || !vis) {
            for (auto& m : meshes) skgl::destroy_mesh(m);
            if (depth) glDeleteProgram(depth);
            return RunResult::failure(log);
        }
        const GLuint tex = make_depth_compare_texture(GL_TEXTURE_2D_ARRAY, size, 2);
        GLuint fbo[2];
        make_depth_layer_fbos(GL_TEXTURE_2D_ARRAY, tex, 2, fbo);
        VisibilityPass pass;
        if (!pass.init(ctx.gpu.width, ctx.gpu.height, why)) return RunResult::failure(why);
        glUseProgram(vis);
        set_light_uniforms(vis, scene.light);
        glUniformMatrix4fv(glGetUniformLocation(vis, "u_dp_view"), 1, GL_FALSE, glm::value_ptr(fr.view));
        set_distance_uniforms(vis, light, range);
        glUniform1f(glGetUniformLocation(vis, "u_size"), float(size));
        glUniform1f(glGetUniformLocation(vis, "u_tess"), float(tess));
        glUniform1i(glGetUniformLocation(vis, "u_pcf"), radius);
        glUniform2f(glGetUniformLocation(vis, "u_storage"), 1e-5f * range, kStorageRelative);
        glUseProgram(depth);
        glUniformMatrix4fv(glGetUniformLocation(depth, "u_dp_view"), 1, GL_FALSE, glm::value_ptr(fr.view));
        set_distance_uniforms(depth, light, range);
        glUniform1f(glGetUniformLocation(depth, "u_margin"), margin);
        const GLint loc_side = glGetUniformLocation(depth, "u_side");
        auto frame = [&] {
            begin_distance_pass(depth);
            glEnable(GL_CLIP_DISTANCE0);
            for (int layer = 0; layer < 2; ++layer) {
                clear_depth_layer(fbo[layer], size);
                glUniform1f(loc_side, layer == 0 ? 1.f : -1.f);
                for (const auto& m : meshes) skgl::draw_mesh(m);
            }
            glDisable(GL_CLIP_DISTANCE0);
            pass.draw(vis, ctx.gpu, GL_TEXTURE_2D_ARRAY, tex);
        };
        measure_visibility(r, ctx, pass, frame);
        r.gpu_bytes = std::int64_t(size) * size * 4 * 2;
        r.work = {{"shadow_map_texels", 2.0 * size * size},
                  {"draws", 2.0 * double(meshes.size())},
                  {"triangles_drawn", 2.0 * tris},
                  {"tess_max_n", double(max_n)},
                  {"tess_ms", tess_ms}};
        // the bound for the scene's own (untessellated) edges: how far off the drawn chords can be
        double worst = 0.0;
        for (const auto& m : scene.meshes) {
            if (!m.caster) continue;
            for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
                const glm::vec3 a = m.positions[m.indices[t]], b = m.positions[m.indices[t + 1]], c = m.positions[m.indices[t + 2]];
                const float D = point_triangle_distance(light, a, b, c);
                const float longest = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)}) / float(max_n);
                const auto e = shadowkit::omni_paraboloid_edge_error(longest, D, static_cast<std::uint32_t>(size), max_r);
                if (e.status == shadowkit::Status::Ok) worst = std::max(worst, double(e.texels));
            }
        }
        r.quality.push_back({"edge_error_bound_texels", worst});
        return finish_run(std::move(r), {depth, vis}, [&] {
            glDeleteFramebuffers(2, fbo);
            glDeleteTextures(1, &tex);
            for (auto& m : meshes) skgl::destroy_mesh(m);
        });
    }
};

}  // namespace

void add_omni_techniques(std::vector<std::unique_ptr<Technique>>& out) {
    out.push_back(std::make_unique<CubeShadowMap>());
    out.push_back(std::make_unique<DualParaboloid>());
}

}  // namespace sk
