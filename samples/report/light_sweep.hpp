// shadowkit-report's light sweep: each hard shadow-map technique at its default settings, under
// many random light directions per scene (a third of them grazing), scored against a hard Embree
// reference for acne, umbra leaks and the contact gap (peter-panning). The definitions, the lights
// and the resolution are in docs/report.md ("Light sweep"); report.json's top-level `light_sweep`
// array and report.md's "## light sweep" section show the maxima over the lights.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "scene.hpp"
#include "techniques.hpp"

namespace skr {

struct LightSweepOptions {
    int lights = 1000;              // per scene; a third of them grazing (1 to 5 degrees above the floor)
    int mesh_lights = 250;          // per scanned-mesh scene (sk::is_scanned_scene): their frames cost 5 to 20x
    int width = 128, height = 96;   // the camera G-buffer the sweep renders and scores (low resolution)
    std::uint64_t seed = 0x5eedu;   // the light directions (deterministic)
    int chunk = 250;                // lights per technique init (run_sequence call)
};

// One (scene, technique) of the sweep: maxima over the lights, each with its worst light (the unit
// direction from the scene's aim point towards the light).
struct LightSweepRow {
    std::string scene, technique, settings, light;  // light: "directional" or "spot"
    int lights = 0, grazing_lights = 0, width = 0, height = 0;
    int map_size = 0;
    // the texel at each pixel from the technique's own map matrices (ReportSpec::light_matrices), not
    // the scene frustum's at map_size
    bool texels_from_technique = false;
    double acne_fraction_max = 0.0, gap_texels_max = 0.0, gap_world_max = 0.0, leak_fraction_max = 0.0;
    glm::vec3 acne_worst_light{0.f}, gap_worst_light{0.f}, leak_worst_light{0.f};
    // acne away from the map's resolution: acne pixels whose tangent plane nothing occludes within the
    // 2x2 filter's reach in the map (the light rays over +-1.5 texels around them meet the scene no
    // nearer than that plane), over the same lit pixels: the map holds the receiver's own plane there
    double acne_beyond_filter_max = 0.0;
    glm::vec3 acne_beyond_filter_worst_light{0.f};
    // likewise leaks whose whole neighbourhood within the filter's reach the reference shadows
    double leak_beyond_filter_max = 0.0;
    glm::vec3 leak_beyond_filter_worst_light{0.f};
    int lights_with_acne = 0, lights_with_gap = 0, lights_with_leak = 0;
    // lights the technique rejected with a status (e.g. a warp's LightInsideVolume: no single frustum
    // holds the receivers): not scored; the row fails only when every light does
    int lights_failed = 0;
    std::string first_light_error;
    double seconds = 0.0;            // the technique's frames and scoring
    double reference_seconds = 0.0;  // the scene's hard references (shared by its techniques)
    bool failed = false;
    std::string error;
};

struct LightSweep {
    bool requested = false;
    LightSweepOptions options;
    std::vector<LightSweepRow> rows;
    double seconds = 0.0;  // the whole sweep, wall clock
};

// Runs the sweep on `scenes` (built-in visibility scenes; the caller leaves out light-size variants and
// prt) with the techniques of `chosen` that the sweep covers (shadow_map, pcf; each where it accepts the
// sweep's light). Progress on stderr.
void run_light_sweep(const std::vector<sk::Scene>& scenes, const std::vector<sk::Technique*>& chosen,
                     const LightSweepOptions& opt, LightSweep& out);

// ",\n  \"light_sweep\": [...]" (report.json) and the "## light sweep" section (report.md).
void write_light_sweep_json(std::ostream& f, const LightSweep& s);
void write_light_sweep_markdown(std::ostream& f, const LightSweep& s);

}  // namespace skr
