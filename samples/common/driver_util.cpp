// Internal helpers shared by the technique drivers of samples/common (old interface, until each family
// is ported to samples/<technique>/: see docs/samples.md).
#include "driver_util.hpp"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>

namespace sk {

double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

double median_of(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
}

bool median_cpu_ms(int runs, const std::function<bool()>& work, double& ms) {
    std::vector<double> samples;
    for (int it = 0; it < runs; ++it) {
        const auto t0 = Clock::now();
        if (!work()) return false;
        samples.push_back(ms_since(t0));
    }
    ms = median_of(samples);
    return true;
}


const char* depth_only_vs() {
    return R"(#version 450 core
layout(location = 0) in vec3 a_position;
uniform mat4 u_light_view_proj;
void main() { gl_Position = u_light_view_proj * vec4(a_position, 1.0); }
)";
}
const char* depth_only_fs() { return "#version 450 core\nvoid main() {}\n"; }

void measure_visibility(RunResult& r, const RunContext& ctx, const VisibilityPass& pass,
                        const std::function<void()>& frame) {
    r.gpu_ms = skgl::median_frame_ms(frame, ctx.warmup, ctx.frames);
    r.frames = ctx.frames;
    r.visibility = skgl::read_color_float(pass.target, 0, 1);
}

RunResult finish_run(RunResult r, std::initializer_list<GLuint> programs, const std::function<void()>& release) {
    const std::string err = skgl::gl_error_string();
    for (GLuint p : programs) glDeleteProgram(p);
    if (release) release();
    if (!err.empty()) return RunResult::failure(err);
    return r;
}

void draw_casters(const SceneGpu& gpu, const std::vector<std::uint32_t>* only) {
    if (only) {
        for (std::uint32_t i : *only)
            if (i < gpu.meshes.size() && gpu.caster[i]) skgl::draw_mesh(gpu.meshes[i]);
        return;
    }
    for (std::size_t i = 0; i < gpu.meshes.size(); ++i)
        if (gpu.caster[i]) skgl::draw_mesh(gpu.meshes[i]);
}

GLuint compile_depth_only_program(std::string& log) {
    return skgl::compile_program({{GL_VERTEX_SHADER, depth_only_vs()}, {GL_FRAGMENT_SHADER, depth_only_fs()}}, log);
}

bool compile_shadow_programs(const std::string& snippet, const std::string& body, const Light& L, GLuint& depth,
                             GLuint& vis, std::string& why) {
    const std::string text = snippet.empty() ? std::string() : load_snippet(snippet, why);
    if (!snippet.empty() && text.empty()) return false;
    std::string log;
    depth = compile_depth_only_program(log);
    vis = compile_visibility_program(text, body, log);
    if (!depth || !vis) {
        why = log;
        return false;
    }
    glUseProgram(vis);
    set_light_uniforms(vis, L);
    return true;
}

bool make_shadow_map_target(skgl::Target& sm, int size, std::string& why) {
    if (!skgl::make_target(sm, size, size, {}, GL_DEPTH_COMPONENT32F, why)) return false;
    skgl::set_depth_compare(sm.depth, true, true);
    return true;
}

void render_shadow_depth(const SceneGpu& gpu, GLuint fbo, int size, GLuint depth_prog, const glm::mat4& light_vp,
                         const std::vector<std::uint32_t>* only) {
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, size, size);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glClear(GL_DEPTH_BUFFER_BIT);
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(2.f, 2.f);
    glUseProgram(depth_prog);
    glUniformMatrix4fv(glGetUniformLocation(depth_prog, "u_light_view_proj"), 1, GL_FALSE, glm::value_ptr(light_vp));
    draw_casters(gpu, only);
    glDisable(GL_POLYGON_OFFSET_FILL);
}

RunResult run_single_shadow_map(const RunContext& ctx, RunResult r, int size, const glm::mat4& light_vp,
                                const SingleMapLookup& lookup, const std::vector<std::uint32_t>* only,
                                const std::function<void(RunResult&, const skgl::Target&)>& extras) {
    std::string why;
    skgl::Target sm;
    if (!make_shadow_map_target(sm, size, why)) return RunResult::failure(why);
    VisibilityPass pass;
    if (!pass.init(ctx.gpu.width, ctx.gpu.height, why)) return RunResult::failure(why);
    GLuint depth = 0, vis = 0;
    if (!compile_shadow_programs(lookup.snippet, lookup.body, ctx.scene.light, depth, vis, why))
        return RunResult::failure(why);
    glUniformMatrix4fv(glGetUniformLocation(vis, lookup.matrix_uniform), 1, GL_FALSE, glm::value_ptr(light_vp));
    measure_visibility(r, ctx, pass, [&] {
        render_shadow_depth(ctx.gpu, sm.fbo, size, depth, light_vp, only);
        pass.draw(vis, ctx.gpu, GL_TEXTURE_2D, sm.depth);
    });
    r.gpu_bytes = std::int64_t(size) * size * 4;
    if (extras) extras(r, sm);
    return finish_run(std::move(r), {depth, vis}, [&] { skgl::destroy_target(sm); });
}

GLuint make_depth_compare_texture(GLenum target, int size, int layers) {
    GLuint tex = 0;
    glGenTextures(1, &tex);
    glBindTexture(target, tex);
    if (target == GL_TEXTURE_2D_ARRAY) glTexStorage3D(target, 1, GL_DEPTH_COMPONENT32F, size, size, layers);
    else glTexStorage2D(target, 1, GL_DEPTH_COMPONENT32F, size, size);
    glTexParameteri(target, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(target, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(target, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(target, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTexParameteri(target, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glTexParameteri(target, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    return tex;
}

void begin_offset_depth_pass(GLuint depth_prog) {
    glUseProgram(depth_prog);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(2.f, 2.f);
}

void clear_depth_layer(GLuint fbo, int size) {
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, size, size);
    glClear(GL_DEPTH_BUFFER_BIT);
}

void render_depth_layers(const SceneGpu& gpu, const GLuint* fbo, const glm::mat4* vps, int count, int size,
                         GLuint depth_prog, bool every_mesh) {
    begin_offset_depth_pass(depth_prog);
    for (int i = 0; i < count; ++i) {
        clear_depth_layer(fbo[i], size);
        glUniformMatrix4fv(glGetUniformLocation(depth_prog, "u_light_view_proj"), 1, GL_FALSE, glm::value_ptr(vps[i]));
        if (every_mesh)
            for (const auto& m : gpu.meshes) skgl::draw_mesh(m);
        else
            draw_casters(gpu);
    }
    glDisable(GL_POLYGON_OFFSET_FILL);
}

void mesh_bounds(const Mesh& m, glm::vec3& lo, glm::vec3& hi) {
    lo = glm::vec3(INFINITY);
    hi = glm::vec3(-INFINITY);
    for (const auto& p : m.positions) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
}

void spot_cone_box(const Light& L, const glm::vec3& lo, const glm::vec3& hi, float max_half_angle, glm::vec3& clo,
                   glm::vec3& chi) {
    float far_d = 0.f;
    for (int i = 0; i < 8; ++i) {
        const glm::vec3 c((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
        far_d = std::max(far_d, glm::length(c - L.position));
    }
    const glm::vec3 d = glm::normalize(L.direction);
    const glm::vec3 cap = L.position + d * far_d;
    const float r = far_d * std::tan(std::min(L.spot_half_angle, max_half_angle));
    // the cap disk's extent along each axis: r * sqrt(1 - d_axis^2)
    const glm::vec3 ext = r * glm::sqrt(glm::max(glm::vec3(0.f), 1.f - d * d));
    clo = glm::min(L.position, cap - ext);
    chi = glm::max(L.position, cap + ext);
}

}  // namespace sk
