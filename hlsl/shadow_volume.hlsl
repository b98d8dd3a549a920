// shadowkit/hlsl/shadow_volume.hlsl - stencil shadow volume extrusion (vertex) and depth-bounds test emulation (pixel) in HLSL.
// stages: vertex (sk_extrude_shadow_volume), pixel (the depth-bounds emulation)
//
// The HLSL twin of glsl/shadow_volume.glsl: the same sk_ functions, arguments and results;
// glsl/shadow_volume.glsl and docs/shadow_volume.md say what each means and the whole frame.
//   float4 sk_extrude_shadow_volume(float4 position, float4 light_position): a vertex of
//     shadowkit::volume_build_vertices' buffer (w = 1: itself, w = 0: extruded to infinity away from
//     the light); multiply the result by the view-projection with mul(M, v) (`column_major` GLM
//     data: hlsl/shadow_map.hlsl states the rule).
//   bool sk_outside_depth_bounds(float stored_depth, float2 bounds) and
//   bool sk_outside_depth_bounds_at(Texture2D<float> scene_depth, int2 pixel, float2 bounds): for
//     devices without depth-bounds testing (Vulkan's depthBounds feature, D3D12's depth-bounds test).
// Vulkan state of the volume pass (tests/vulkan/test_vk_shadow_volume.cpp runs it): the scene's depth
// and a cleared stencil in one depth-stencil attachment, depth test on (VK_COMPARE_OP_GREATER for
// reversed-Z), depth writes off, colour writes off, no culling, two-sided stencil with
// VK_FRONT_FACE_COUNTER_CLOCKWISE (a negative-height viewport or a projection flip both keep GL's
// winding): z-fail back faces INCREMENT_AND_WRAP and front faces DECREMENT_AND_WRAP on depth fail;
// an infinite projection (shadowkit/infinite_projection.hpp, ClipDepth::ZeroToOne, reversed-Z, with
// its epsilon) or depthClampEnable.
// Compiled in the tests by glslang's HLSL front end to SPIR-V and run on Vulkan; written for DXC
// (shader model 6.0) as well, but not compiled with it here (DXC is not packaged in Debian 12).
// Based on: C. Everitt, M. J. Kilgard, "Practical and Robust Stenciled Shadow Volumes for
// Hardware-Accelerated Rendering", NVIDIA 2002 (extrusion X_inf = (X.xyz L.w - L.xyz, 0), sec. 3.2.2);
// E. Lengyel, "Advanced Stencil Shadow and Penumbral Wedge Rendering", GDC 2005 (depth bounds).
// MIT License. Copyright (c) shadowkit contributors.

float4 sk_extrude_shadow_volume(float4 position, float4 light_position) {
    if (position.w > 0.5)
        return float4(position.xyz, 1.0);
    // Homogeneous difference of the vertex and the light, a point at infinity (w = 0).
    return float4(position.xyz * light_position.w - light_position.xyz, 0.0);
}

bool sk_outside_depth_bounds(float stored_depth, float2 bounds) {
    return stored_depth < bounds.x || stored_depth > bounds.y;
}

bool sk_outside_depth_bounds_at(Texture2D<float> scene_depth, int2 pixel, float2 bounds) {
    return sk_outside_depth_bounds(scene_depth.Load(int3(pixel, 0)), bounds);
}
