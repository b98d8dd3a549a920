// samples/report/temporal.hpp - shadows over time: the report's camera and light paths and
// the flicker metrics (report-only code, part of shadowkit_report_core).
//
// A temporal row runs a technique over N frames of a path and evaluates V every frame at the SAME
// surface points, the first frame's G-buffer, while the technique fits to the frame's camera
// (RunContext::fit_camera, app::View::camera) and lights with the frame's light. With a still light the
// reference does not change, so every change of V between frames is error (flicker, popping); with a
// turning light the change of V is scored against the change of the reference (one per frame).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "reference.hpp"
#include "scene.hpp"
#include "techniques.hpp"

namespace sk {

/// The paths, all deterministic and starting at the scene's own camera and light:
/// Pan:   the camera translates sideways (along its right vector) by steps growing geometrically
///        from 0.1 to 4 "texels" (scene diagonal / 2048) a frame, each step the other way (so it stays
///        within about 2 texels of its start and the points it sees stay in view);
/// Yaw:   the camera turns about the world's vertical axis through its eye, 0.25 degree per frame;
/// Dolly: the camera moves toward its target by 0.5% of the distance per frame;
/// Light: the camera stays; the light turns about the vertical axis through the scene's center by
///        0.25 degree per frame (position and direction).
enum class TemporalPath { Pan, Yaw, Dolly, Light };
const char* temporal_path_name(TemporalPath p);
bool temporal_path_moves_camera(TemporalPath p);
/// The `frames` frames of `path` on `scene` (frame 0: the scene's camera and light).
std::vector<TemporalFrame> temporal_path(const Scene& scene, TemporalPath path, int frames);

/// 1 where the G-buffer point lies inside the view frustum of every frame's camera (aspect = the
/// G-buffer's): the points every fit must cover. 0 on background pixels.
std::vector<std::uint8_t> temporal_frustum_mask(const GBuffer& g, const std::vector<TemporalFrame>& frames);

struct TemporalMetrics {
    int frames = 0;
    std::size_t pixels = 0;  ///< compared pixels (mask != 0)
    /// sqrt of the mean over compared pixels and frames t = 1..N-1 of ((V_t - V_{t-1}) - (R_t - R_{t-1}))^2
    double temporal_rms = 0.0;
    /// pixels whose reference stays on one side of 0.5 in every frame, and those of them where V crosses
    /// 0.5 (lit <-> shadowed) at least once; flip_fraction = flipped / stable (0 without stable pixels)
    std::size_t stable_pixels = 0, flipped_pixels = 0;
    double flip_fraction = 0.0;
    /// the largest range (max - min over the frames) of V_t - R_t at one pixel: with a still reference,
    /// the range of V
    double worst_range = 0.0;
};

/// `v`: V per frame (each `mask.size()` values); `ref`: the reference per frame (same count as `v`,
/// or one entry: a reference that does not change); `mask`: the pixels to compare. Fewer than two
/// frames: every metric 0.
TemporalMetrics compute_temporal_metrics(const std::vector<std::vector<float>>& v,
                                         const std::vector<const std::vector<float>*>& ref,
                                         const std::vector<std::uint8_t>& mask);

}  // namespace sk
