// tests/docs/gl_shadow_map.cpp - the "new user" trial for docs/shadow_map.md: a hard shadow map
// built only from that page's blocks (named parts gl_shadow_map/*, #included below) and the
// comments of glsl/shadow_map.glsl and include/shadowkit/shadow_bias.hpp. The program adds what a
// user's renderer has anyway: a GL context, a scene (boxes over a floor, one on the floor, two
// floating) with its draw call, a camera, and the check: the lit/shadowed result read back per
// pixel against a CPU ray cast from the same surface points, for a spot light, a point light (cube
// map) and a directional light from either side of the camera (both hemispheres), at least 99.5%
// agreement on pixels away from shadow edges. Prints the score; exit 0 when every light passes.
#include "docs_gl.hpp"

#include <shadowkit/shadow_bias.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

namespace {

// The score: per pixel the surface point and normal (a G-buffer pass of the program, not of the
// docs), the CPU ray cast to the light, and the docs' visibility read back from the window.
struct Score {
    int counted = 0, agree = 0;  // away from shadow edges
    int all = 0, all_agree = 0;  // every receiver pixel (edges: the bias's peter-panning, the 2x2 filter)
    double fraction() const { return counted ? double(agree) / double(counted) : 0.0; }
};

}  // namespace

int main() {
    const int W = 320, H = 240;
    if (!docs::gl_context(W, H)) return docs::no_gl_exit_code();
    const GLuint window = docs::window_framebuffer();
    // The scene (a floor and four boxes, one resting on it: contact shadows), the user's draw call
    // (attribute 0 position, attribute 1 normal) and the camera (docs_gl.hpp).
    const docs::Mesh scene = docs::floor_scene();
    const docs::DrawCall draw_scene = docs::floor_scene_draw();
    const glm::mat4 camera_view_proj = docs::floor_scene_camera(W, H);
    // The scene's bounds (for the light frusta below).
    const glm::vec3 scene_min(-4.0f, 0.0f, -4.0f), scene_max(4.0f, 2.2f, 4.0f);

    namespace sk = shadowkit;
#include "map.inc"
#include "programs.inc"

    // The program's G-buffer: world position and normal per pixel (RGBA32F), for the score only.
    const docs::GBuffer g = docs::gbuffer(W, H, camera_view_proj, draw_scene);
    const std::vector<glm::vec4>& gpos = g.position;
    const std::vector<glm::vec4>& gnrm = g.normal;

    struct Case {
        const char* name;
        glm::vec4 light_position;  // shadowkit's convention: w = 1 point/spot, w = 0 direction toward the light
    };
    const Case cases[] = {{"spot light", glm::vec4(2.5f, 6.0f, 3.0f, 1.0f)},
                          {"point light (cube map)", glm::vec4(0.2f, 3.2f, 0.1f, 1.0f)},
                          {"directional, from the camera's side", glm::vec4(0.35f, 1.0f, 0.55f, 0.0f)},
                          {"directional, from behind the scene", glm::vec4(-0.45f, 0.9f, -0.7f, 0.0f)}};
    bool all_ok = true;
    for (int ci = 0; ci < 4; ++ci) {
        const glm::vec4 light_position = cases[ci].light_position;
        const bool cube = ci == 1;
        if (!cube) {
#include "light.inc"
#include "render_map.inc"
#include "lighting.inc"
        } else {
#include "render_cube.inc"
#include "lighting_cube.inc"
        }
        const std::vector<unsigned char> rgba = docs::window_rgba(W, H);

        // CPU ray cast per pixel: -1 not a receiver (background, facing away or grazing), 0 shadowed, 1 lit.
        std::vector<int> cls(gpos.size(), -1);
        for (std::size_t k = 0; k < gpos.size(); ++k) {
            if (gpos[k].w == 0.0f) continue;
            const glm::vec3 p(gpos[k]), n(gnrm[k]);
            const glm::vec3 to_light = light_position.w > 0.0f ? glm::vec3(light_position) / light_position.w - p
                                                               : glm::normalize(glm::vec3(light_position));
            if (glm::dot(n, glm::normalize(to_light)) < 0.1f) continue;  // facing away or grazing: the terminator is an edge
            const glm::vec3 from = p + n * 1e-4f;
            const glm::vec3 to = light_position.w > 0.0f ? glm::vec3(light_position) / light_position.w : p + to_light * 100.0f;
            cls[k] = docs::segment_occluded(scene, from, to) ? 0 : 1;
        }
        // Away from shadow edges: every pixel within 2 of it has the same class.
        Score s;
        for (int y = 2; y < H - 2; ++y)
            for (int x = 2; x < W - 2; ++x) {
                const std::size_t k = static_cast<std::size_t>(y * W + x);
                if (cls[k] < 0) continue;
                ++s.all;
                s.all_agree += (rgba[4 * k] >= 128 ? 1 : 0) == cls[k];
                bool interior = true;
                for (int dy = -2; dy <= 2 && interior; ++dy)
                    for (int dx = -2; dx <= 2 && interior; ++dx)
                        interior = cls[static_cast<std::size_t>((y + dy) * W + x + dx)] == cls[k];
                if (!interior) continue;
                ++s.counted;
                const int gpu = rgba[4 * k] >= 128 ? 1 : 0;
                s.agree += gpu == cls[k];
            }
        const bool ok = s.counted > 10000 && s.fraction() >= 0.995;
        all_ok = all_ok && ok;
        std::printf("gl_shadow_map: %-36s %6d pixels away from shadow edges, %.3f%% agree with the ray cast%s"
                    " (all %d receiver pixels: %.2f%%)\n",
                    cases[ci].name, s.counted, 100.0 * s.fraction(), ok ? "" : "  FAIL (< 99.5%)", s.all,
                    100.0 * double(s.all_agree) / double(std::max(s.all, 1)));
    }
    const GLenum err = glGetError();
    if (err != GL_NO_ERROR) {
        std::printf("gl_shadow_map: GL error 0x%x\n", err);
        return 1;
    }
    return all_ok ? 0 : 1;
}
