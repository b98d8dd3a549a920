// The Vulkan shadow-volume sample (labels sample, vulkan): every built-in scene rendered headless for 3
// frames exactly as `sample_shadow_volumes_vulkan --headless --frames 3` does (render_headless), then
// checked against a CPU ray cast that shares nothing with the GPU path: primary rays from the scene's
// camera (eye, target, up, fovy; not the P_inf matrix) find each pixel's surface, a shadow ray toward
// the last frame's light says lit or shadowed. On the pixels whose surface faces the camera and the
// light (n.l > 0.1), the stencil must be 0 exactly where the ray reaches the light, and the picture
// must be lit (red above the ambient 31) exactly there too, on >= 99% of them; zero validation-layer
// messages. Exit 77 without a Vulkan device (1 where SHADOWKIT_REQUIRE_GL is set).
#include <glm/glm.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#define STB_IMAGE_IMPLEMENTATION  // the reader: shadowkit_app holds only stb_image_write's implementation
#include <stb_image.h>
#include <stb_image_write.h>

#include "frames.hpp"

namespace {

struct Tri {
    glm::vec3 a, e1, e2, n;  // n: the winding normal (counter-clockwise outward), unit
    bool caster;
};

// Moller & Trumbore 1997: the ray's t at the triangle, or +inf.
float hit(const Tri& t, glm::vec3 o, glm::vec3 d) {
    const glm::vec3 p = glm::cross(d, t.e2);
    const float det = glm::dot(t.e1, p);
    if (std::fabs(det) < 1e-12f) return INFINITY;
    const float inv = 1.f / det;
    const glm::vec3 s = o - t.a;
    const float u = glm::dot(s, p) * inv;
    if (u < 0.f || u > 1.f) return INFINITY;
    const glm::vec3 q = glm::cross(s, t.e1);
    const float v = glm::dot(d, q) * inv;
    if (v < 0.f || u + v > 1.f) return INFINITY;
    const float tt = glm::dot(t.e2, q) * inv;
    return tt > 0.f ? tt : INFINITY;
}

struct Counts {
    int compared = 0, stencil_agree = 0, image_agree = 0, shadowed = 0, coverage_mismatch = 0;
    int stencil_lit_ray_blocked = 0, stencil_shadow_ray_free = 0;
};

Counts compare(const HeadlessFrames& f, std::uint8_t* marked) {
    const sk::Scene& s = f.scene;
    std::vector<Tri> tris;
    for (const sk::Mesh& m : s.meshes)
        for (std::size_t k = 0; k + 2 < m.indices.size(); k += 3) {
            const glm::vec3 a = m.positions[m.indices[k]], b = m.positions[m.indices[k + 1]], c = m.positions[m.indices[k + 2]];
            const glm::vec3 n = glm::cross(b - a, c - a);
            if (glm::length(n) < 1e-12f) continue;
            tris.push_back({a, b - a, c - a, glm::normalize(n), m.caster});
        }
    const sk::Camera& cam = s.camera;
    const glm::vec3 fwd = glm::normalize(cam.target - cam.eye), right = glm::normalize(glm::cross(fwd, cam.up)),
                    up = glm::cross(right, fwd);
    const float th = std::tan(0.5f * cam.fovy), aspect = float(f.width) / float(f.height);
    const sk::Light& L = s.light;
    Counts c;
    for (std::uint32_t row = 0; row < f.height; ++row)
        for (std::uint32_t x = 0; x < f.width; ++x) {
            const std::size_t k = std::size_t(row) * f.width + x;
            const float nx = 2.f * (float(x) + 0.5f) / float(f.width) - 1.f, ny = 1.f - 2.f * (float(row) + 0.5f) / float(f.height);
            const glm::vec3 d = glm::normalize(fwd + nx * th * aspect * right + ny * th * up);
            float best = INFINITY;
            const Tri* seen = nullptr;
            for (const Tri& t : tris) {
                const float h = hit(t, cam.eye, d);
                if (h < best) best = h, seen = &t;
            }
            const bool gpu_drawn = f.depth[k] > 0.f;
            if ((seen != nullptr) != gpu_drawn) ++c.coverage_mismatch;
            if (!seen || !gpu_drawn || glm::dot(seen->n, d) >= 0.f) continue;
            const glm::vec3 p = cam.eye + best * d;
            const glm::vec3 to = f.light.w == 0.f ? glm::vec3(f.light) : glm::vec3(f.light) - p;
            const float dist = f.light.w == 0.f ? INFINITY : glm::length(to);
            const glm::vec3 l = glm::normalize(to);
            if (glm::dot(seen->n, l) <= 0.1f) continue;
            const glm::vec3 o = p + seen->n * (1e-4f * best);  // off the surface, relative to the ray length
            bool blocked = false;
            for (const Tri& t : tris)
                if (t.caster && hit(t, o, l) < dist) {
                    blocked = true;
                    break;
                }
            const bool in_cone = L.type != sk::LightType::Spot || glm::dot(-l, glm::normalize(L.direction)) >= std::cos(L.spot_half_angle);
            ++c.compared;
            c.shadowed += blocked;
            c.stencil_agree += (f.stencil[k] == 0) == !blocked;
            c.stencil_lit_ray_blocked += f.stencil[k] == 0 && blocked;
            c.stencil_shadow_ray_free += f.stencil[k] != 0 && !blocked;
            if (marked && f.stencil[k] != 0 && !blocked) marked[4 * k] = 255, marked[4 * k + 1] = 0;
            if (marked && f.stencil[k] == 0 && blocked) marked[4 * k + 1] = 255, marked[4 * k] = 0;
            c.image_agree += (f.rgba[4 * k] > 40) == (!blocked && in_cone);
        }
    return c;
}

// `--gl-stencil FILE SCENE`: the GL twin's "stencil counts" view of SCENE (sample_shadow_volumes
// --view "stencil counts" --param method=zfail --param projection=reversed, 3 frames, 160 x 120: grey
// = 64 x the count) against this sample's stencil on every pixel: in a volume or not.
int compare_with_gl(skvk::Context& ctx, const char* file, const char* scene_name) {
    int w = 0, h = 0, n = 0;
    unsigned char* gl = stbi_load(file, &w, &h, &n, 1);
    sk::Scene scene;
    if (!gl || !sk::make_builtin_scene(scene_name, scene)) {
        std::printf("FAIL: cannot read %s or no scene %s\n", file, scene_name);
        return 1;
    }
    HeadlessFrames f;
    const std::string err = render_headless(ctx, scene, 3, std::uint32_t(w), std::uint32_t(h), f);
    int agree = 0, gl_shadow = 0, vk_shadow = 0;
    for (std::size_t k = 0; err.empty() && k < f.stencil.size(); ++k) {
        const bool a = gl[k] > 16, b = f.stencil[k] != 0;
        agree += a == b;
        gl_shadow += a;
        vk_shadow += b;
    }
    stbi_image_free(gl);
    const double frac = double(agree) / double(w * h);
    // both must show shadow (0.5% of the picture at least): agreement on empty masks is vacuous
    const bool ok = err.empty() && frac >= 0.99 && gl_shadow * 200 >= w * h && vk_shadow * 200 >= w * h;
    std::printf("%s %s: in a volume on GL %d, on Vulkan %d pixels of %d; the two agree on %.4f of them %s\n",
                ok ? "ok  " : "FAIL", scene_name, gl_shadow, vk_shadow, w * h, frac, err.c_str());
    return ok ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
    skvk::Context ctx;
    bool no_device = false;
    const std::string why = skvk::create_context(ctx, true, no_device);
    if (!why.empty()) {
        skvk::destroy_context(ctx);
        const char* req = std::getenv("SHADOWKIT_REQUIRE_GL");
        const bool required = req && *req && std::strcmp(req, "0") != 0;
        std::printf("%s: no Vulkan device with the validation layer: %s\n", required ? "FAILED" : "SKIPPED", why.c_str());
        return no_device && !required ? 77 : 1;
    }
    std::printf("Vulkan device: %s (validation layer on)\n", ctx.device_name.c_str());
    int failures = 0;
    const bool gl = argc == 4 && std::string(argv[1]) == "--gl-stencil";
    if (gl) failures += compare_with_gl(ctx, argv[2], argv[3]);
    for (const std::string& name : gl ? std::vector<std::string>{} : sk::builtin_scene_names()) {
        sk::Scene scene;
        if (!sk::make_builtin_scene(name, scene)) continue;
        HeadlessFrames f;
        const std::string err = render_headless(ctx, scene, 3, 160, 120, f);
        if (!err.empty()) {
            std::printf("FAIL %s: %s\n", name.c_str(), err.c_str());
            ++failures;
            continue;
        }
        // SHADOWKIT_DEBUG_DIR: the pictures with the disagreeing pixels marked (red: stencil shadow, ray
        // free; green: stencil lit, ray blocked), <dir>/vk_sample_<scene>.png
        const char* dir = std::getenv("SHADOWKIT_DEBUG_DIR");
        std::vector<std::uint8_t> marked = f.rgba;
        const Counts c = compare(f, dir ? marked.data() : nullptr);
        if (dir) stbi_write_png((std::string(dir) + "/vk_sample_" + name + ".png").c_str(), 160, 120, 4, marked.data(), 640);
        const double st = c.compared ? double(c.stencil_agree) / c.compared : 0.0, im = c.compared ? double(c.image_agree) / c.compared : 0.0;
        // the scene must show shadows (1% of the compared pixels at least): agreement is not vacuous
        const bool ok = c.compared > 2000 && c.shadowed * 100 >= c.compared && st >= 0.99 && im >= 0.99;
        std::printf("%s %-9s compared %5d (shadowed %5d): stencil == 0 agrees %.4f, picture lit agrees %.4f; coverage differs on %d of %d; stencil lit / ray blocked %d, stencil shadowed / ray free %d\n",
                    ok ? "ok  " : "FAIL", name.c_str(), c.compared, c.shadowed, st, im, c.coverage_mismatch, 160 * 120,
                    c.stencil_lit_ray_blocked, c.stencil_shadow_ray_free);
        failures += !ok;
    }
    skvk::destroy_context(ctx);
    const std::size_t n = skvk::message_count();
    std::printf("validation-layer warnings and errors: %zu\n", n);
    if (n) std::printf("%s", skvk::messages().c_str());
    return failures == 0 && n == 0 ? 0 : 1;
}
