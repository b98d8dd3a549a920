// tests/docs/gl_pcss.cpp - the "new user" trial for docs/pcss.md: percentage-closer soft shadows
// built only from that page's blocks (named parts gl_pcss/*, #included below) and the comments of
// glsl/pcf.glsl, glsl/pcss.glsl, glsl/shadow_map.glsl, include/shadowkit/pcss.hpp and
// poisson_disk.hpp. The program adds what a user's renderer has anyway: a GL context, a scene (boxes
// over a floor under a square area light) with its draw call, a camera, and the check: the
// visibility read back per pixel against a CPU ray cast to 8 x 8 stratified points of the square
// light from the same surface points (the light's emitter sampled, as the report's reference does).
// Scored on receiver pixels that see the whole emitter above their tangent plane (floor and box
// tops; PCSS does not model an emitter crossing the horizon). Prints the RMSE and the penumbra RMSE;
// fails above 0.05 (a hard shadow map scores about 0.08 on such scenes in the report).
#include "docs_gl.hpp"

#include <shadowkit/pcss.hpp>
#include <shadowkit/poisson_disk.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

int main() {
    const int W = 256, H = 192;
    if (!docs::gl_context(W, H)) return docs::no_gl_exit_code();
    const GLuint window = docs::window_framebuffer();
    // The scene (boxes over a floor), the user's draw call (attribute 0 position, attribute 1
    // normal) and the camera (docs_gl.hpp).
    const docs::DrawCall draw_scene = docs::floor_scene_draw();
    const glm::mat4 camera_view_proj = docs::floor_scene_camera(W, H);
    // The area light: a square of side light_size at light_center, facing down; and the casters' bounds.
    const glm::vec3 light_center(0.3f, 5.0f, 0.4f);
    const float light_size = 1.0f;
    const glm::vec3 casters_min(-1.6f, 0.0f, -0.8f), casters_max(1.6f, 2.2f, 1.7f);
    const glm::vec3 scene_min(-4.0f, 0.0f, -4.0f), scene_max(4.0f, 2.2f, 4.0f);

    namespace sk = shadowkit;
#include "light.inc"
#include "map.inc"
#include "taps.inc"
#include "program.inc"
#include "render.inc"
#include "lighting.inc"

    // The score: the program's G-buffer, then the ray cast to the emitter (docs_gl.hpp).
    const std::vector<unsigned char> rgba = docs::window_rgba(W, H);
    const docs::GBuffer g = docs::gbuffer(W, H, camera_view_proj, draw_scene);
    const docs::AreaLightScore score = docs::score_square_light(g, rgba, light_center, light_size, docs::floor_boxes());
    return docs::area_light_verdict("gl_pcss", score, 0.05);
}
