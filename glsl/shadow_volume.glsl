// shadowkit/glsl/shadow_volume.glsl - stencil shadow volume extrusion (vertex) and depth-bounds test emulation (fragment).
// versions: 330, 450
// stages: vertex, fragment
//
// Functions:
//   vec4 sk_extrude_shadow_volume(vec4 position, vec4 light_position)
//     position:       object-space vertex of the 2n-vertex volume buffer built by
//                     shadowkit::volume_build_vertices: w = 1 -> the vertex itself, w = 0 -> extruded
//                     to infinity away from the light, (position.xyz * light_position.w -
//                     light_position.xyz, 0) (the CPU twin: shadowkit::volume_extrude_to_infinity).
//     light_position: the light as a homogeneous position in the same (object) space, the shadowkit
//                     convention: w > 0 a point light at xyz / w (use w = 1), w = 0 a directional
//                     light, xyz the direction TOWARD the light. The same value the facing
//                     (shadowkit/silhouette.hpp) was computed for.
//     Returns a homogeneous object-space position; multiply by the model-view-projection (use an
//     infinite projection, shadowkit/infinite_projection.hpp, or enable GL_DEPTH_CLAMP).
//   bool sk_outside_depth_bounds(float stored_depth, vec2 bounds)
//     Emulates GL_EXT_depth_bounds_test where it is missing (e.g. llvmpipe): stored_depth is the
//     window depth already in the depth buffer at this pixel (NOT gl_FragCoord.z), bounds =
//     (depth_min, depth_max) from shadowkit::volume_scissor. Usage in a fragment shader:
//       if (sk_outside_depth_bounds(texelFetch(u_scene_depth, ivec2(gl_FragCoord.xy), 0).r, u_bounds)) discard;
//     The scene depth must be a copy of the depth buffer (sampling the attached depth texture while
//     it is bound for depth testing is a feedback loop). discard costs early-Z; the stencil savings
//     of the real extension (no stencil write) are kept, the rasterization cost is not.
//   bool sk_outside_depth_bounds_at(sampler2D scene_depth, ivec2 pixel, vec2 bounds)
//     Same, reading the copied depth texture at `pixel` (level 0).
//
// GL state of the volume pass (docs/shadow_volume.md has the whole frame): the scene's depth already
// in the depth buffer (depth pre-pass), stencil cleared to 0, depth test on with depth writes off
// (GL_LESS, or GL_GREATER for reversed-Z), color writes off, face culling off, two-sided stencil
// (z-pass: front GL_INCR_WRAP / back GL_DECR_WRAP on depth pass; z-fail: back GL_INCR_WRAP / front
// GL_DECR_WRAP on depth fail), GL_DEPTH_CLAMP unless the projection is infinite, optionally the
// scissor and depth bounds of shadowkit::volume_scissor, which must be disabled again before the
// lighting pass (stencil test GL_EQUAL 0, depth test GL_EQUAL or GL_LEQUAL).
//
// Based on: C. Everitt, M. J. Kilgard, "Practical and Robust Stenciled Shadow Volumes for
// Hardware-Accelerated Rendering", NVIDIA 2002 (extrusion X_inf = (X.xyz L.w - L.xyz, 0), sec. 3.2.2);
// E. Lengyel, "Advanced Stencil Shadow and Penumbral Wedge Rendering", GDC 2005 (depth bounds).
// MIT License. Copyright (c) shadowkit contributors.

vec4 sk_extrude_shadow_volume(vec4 position, vec4 light_position)
{
    if (position.w > 0.5)
        return vec4(position.xyz, 1.0);
    // Homogeneous difference of the vertex and the light, a point at infinity (w = 0).
    return vec4(position.xyz * light_position.w - light_position.xyz, 0.0);
}

bool sk_outside_depth_bounds(float stored_depth, vec2 bounds)
{
    return stored_depth < bounds.x || stored_depth > bounds.y;
}

bool sk_outside_depth_bounds_at(sampler2D scene_depth, ivec2 pixel, vec2 bounds)
{
    return sk_outside_depth_bounds(texelFetch(scene_depth, pixel, 0).r, bounds);
}
