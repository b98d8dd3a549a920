// tests/docs/gl_prefiltered_shadow.cpp - the "new user" trial for docs/prefiltered_shadow.md: a moment
// shadow map (quantized to GL_RGBA16, Gaussian-blurred to the penumbra's width) built only from that
// page's blocks (named parts gl_prefiltered_shadow/*, #included below) and the comments of
// glsl/prefiltered_shadow.glsl, glsl/shadow_map.glsl and include/shadowkit/prefiltered_shadow.hpp. The
// program adds what a user's renderer has anyway: a GL context, a scene (boxes over a floor under a
// square area light, the scene of gl_pcss.cpp) with its draw call, a camera, and the check: the
// visibility read back per pixel against a CPU ray cast to 8 x 8 stratified points of the square
// light from the same surface points. Scored on receiver pixels that see the whole emitter above
// their tangent plane. Prints the RMSE and the penumbra RMSE; fails above 0.06 (a hard shadow map
// scores about 0.08 on such scenes in the report; a blur of one width cannot follow the contact
// hardening, so this stays above PCSS's 0.023: measured 0.047, VSM and EVSM4 0.046-0.047).
#include "docs_gl.hpp"

#include <shadowkit/prefiltered_shadow.hpp>

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
    // The area light: a square of side light_size at light_center, facing down.
    const glm::vec3 light_center(0.3f, 5.0f, 0.4f);
    const float light_size = 1.0f;

    namespace sk = shadowkit;
    GLuint empty_vao = 0;
    glGenVertexArrays(1, &empty_vao);
#include "setup.inc"
#include "textures.inc"
#include "programs.inc"
#include "render.inc"

    // The score: the program's G-buffer, then the ray cast to the emitter (docs_gl.hpp).
    const std::vector<unsigned char> rgba = docs::window_rgba(W, H);
    const docs::GBuffer g = docs::gbuffer(W, H, camera_view_proj, draw_scene);
    const docs::AreaLightScore score = docs::score_square_light(g, rgba, light_center, light_size, docs::floor_boxes());
    return docs::area_light_verdict("gl_prefiltered_shadow", score, 0.06);
}
