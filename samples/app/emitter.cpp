// samples/app/emitter.cpp - the area light's fraction above a receiver's tangent plane (emitter.hpp).
#include "emitter.hpp"

#include <glm/gtc/type_ptr.hpp>

#include <cmath>

namespace app {

const char* emitter_horizon_glsl() {
    return R"(
uniform int u_emitter;       // 0 none, 1 rect, 2 disk, 3 sphere
uniform vec3 u_emitter_c;    // center
uniform vec3 u_emitter_t;    // rect: half-edge vector; disk: radius vector
uniform vec3 u_emitter_b;    // rect: half-edge vector; disk: radius vector
float sk_emitter_horizon(vec3 p, vec3 n) {
    if (u_emitter == 0) return 1.0;
    float alpha = dot(n, u_emitter_c - p);
    if (u_emitter == 1) {
        float beta = dot(n, u_emitter_t);
        float gamma = dot(n, u_emitter_b);
        float sum = 0.0;
        for (int i = 0; i < 16; ++i) {
            float r = alpha + beta * (-1.0 + (float(i) + 0.5) / 8.0);   // need r + gamma y > 0, |y| <= 1
            if (abs(gamma) < 1e-20) { sum += r > 0.0 ? 2.0 : 0.0; continue; }
            float y0 = -r / gamma;
            sum += gamma > 0.0 ? clamp(1.0 - y0, 0.0, 2.0) : clamp(y0 + 1.0, 0.0, 2.0);
        }
        return sum / 32.0;
    }
    float s;
    if (u_emitter == 3) {
        vec3 w = normalize(u_emitter_c - p);
        s = length(u_emitter_t) * length(n - dot(n, w) * w);
    } else {
        s = length(vec2(dot(n, u_emitter_t), dot(n, u_emitter_b)));
    }
    if (!(s > 1e-20)) return alpha > 0.0 ? 1.0 : 0.0;
    float d = clamp(-alpha / s, -1.0, 1.0);
    return (acos(d) - d * sqrt(1.0 - d * d)) / 3.14159265;
}
)";
}

void emitter_basis(glm::vec3 n, glm::vec3& t, glm::vec3& b) {
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z);
    const float bb = n.x * n.y * a;
    t = glm::vec3(1.0f + sign * n.x * n.x * a, sign * bb, -sign * n.x);
    b = glm::vec3(bb, sign + n.y * n.y * a, -n.y);
}

void set_emitter_uniforms(GLuint prog, const sk::Light& L, bool enabled) {
    int emitter = 0;
    glm::vec3 t(0.f), b(0.f);
    if (enabled) {
        emitter = L.type == sk::LightType::Rect ? 1 : (L.type == sk::LightType::Disk ? 2 : 3);
        emitter_basis(glm::normalize(L.direction), t, b);
        const float r = L.type == sk::LightType::Rect ? 0.5f * L.size : L.size;  // half edge or radius
        t *= r;
        b *= r;
    }
    glUseProgram(prog);
    glUniform1i(glGetUniformLocation(prog, "u_emitter"), emitter);
    glUniform3fv(glGetUniformLocation(prog, "u_emitter_c"), 1, glm::value_ptr(L.position));
    glUniform3fv(glGetUniformLocation(prog, "u_emitter_t"), 1, glm::value_ptr(t));
    glUniform3fv(glGetUniformLocation(prog, "u_emitter_b"), 1, glm::value_ptr(b));
}

}  // namespace app
