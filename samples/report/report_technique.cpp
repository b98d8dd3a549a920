// samples/report/report_technique.cpp - the measuring helpers of the technique wrappers.
#include "report_technique.hpp"

#include <shadowkit/silhouette.hpp>

namespace sk {

std::vector<float> read_r32f(GLuint texture, int w, int h) {
    std::vector<float> out(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glGetTextureImage(texture, 0, GL_RED, GL_FLOAT, static_cast<GLsizei>(out.size() * sizeof(float)), out.data());
    return out;
}

void count_fragments(bool has_stats, const std::function<void()>& draw, double& fragments, double& invocations) {
    GLuint q[2] = {0, 0};
    glGenQueries(has_stats ? 2 : 1, q);
    glBeginQuery(GL_SAMPLES_PASSED, q[0]);
    if (has_stats) glBeginQuery(GL_FRAGMENT_SHADER_INVOCATIONS_ARB, q[1]);
    draw();
    glEndQuery(GL_SAMPLES_PASSED);
    if (has_stats) glEndQuery(GL_FRAGMENT_SHADER_INVOCATIONS_ARB);
    GLuint64 v = 0;
    glGetQueryObjectui64v(q[0], GL_QUERY_RESULT, &v);
    fragments = double(v);
    if (has_stats) {
        glGetQueryObjectui64v(q[1], GL_QUERY_RESULT, &v);
        invocations = double(v);
    }
    glDeleteQueries(has_stats ? 2 : 1, q);
}

bool scene_has_open_caster(const Scene& scene) {
    for (const Mesh& m : scene.meshes) {
        if (!m.caster || m.indices.empty()) continue;
        const shadowkit::SilhouetteAdjacency adj =
            shadowkit::silhouette_build_adjacency(m.positions.data(), m.positions.size(), m.indices.data(), m.indices.size());
        if (adj.status == shadowkit::Status::Ok && !adj.closed()) return true;
    }
    return false;
}

}  // namespace sk
