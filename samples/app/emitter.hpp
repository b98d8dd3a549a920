// samples/app/emitter.hpp - the area light's fraction above a receiver's tangent plane (part of the app
// shell, like the common light rules of gbuffer.hpp).
//
// The report's reference counts the light samples below a receiver's tangent plane as unseen. A
// technique that models only the casters (penumbra wedges, PCSS) multiplies its V by this fraction to
// agree: on the casters' own lit faces near the terminator the silhouettes say nothing about it.
#pragma once

#include <glm/glm.hpp>

#include "gl.hpp"
#include "scene.hpp"

namespace app {

/// GLSL declaring the uniforms u_emitter* and `float sk_emitter_horizon(vec3 p, vec3 n)`: the emitter's
/// fraction above the plane through p with normal n (rect: 16 columns of the square, each clipped exactly;
/// disk: the circular segment; sphere: the disk of its radius facing p; u_emitter = 0: 1).
const char* emitter_horizon_glsl();
/// The uniforms of emitter_horizon_glsl() on `prog` for light L; `enabled` false (or a light without
/// area) sets u_emitter = 0 (the factor is 1).
void set_emitter_uniforms(GLuint prog, const sk::Light& L, bool enabled);
/// Duff et al. 2017 orthonormal basis: the reference's basis of an emitter plane with normal n.
void emitter_basis(glm::vec3 n, glm::vec3& t, glm::vec3& b);

}  // namespace app
