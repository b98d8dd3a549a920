// Ray-traced ground truth for the report (Embree 3): the fraction of the light that each
// camera-pixel surface point sees. Internal to samples/ and tests/, not a public header.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <embree3/rtcore.h>

#include "scene.hpp"

namespace sk {

// Camera G-buffer read back from the GPU: world position and normal per pixel (bottom-up rows,
// as glReadPixels returns them). kind: 0 = background, 1 = receiver, 2 = geometry that is not a
// receiver (drawn, but left out of the metrics).
/// PCG32 (O'Neill 2014), seeded: the reference's stratified jitter and the light sweep's directions.
struct Pcg {
    std::uint64_t state;
    explicit Pcg(std::uint64_t seed) : state(seed * 6364136223846793005ull + 1442695040888963407ull) { next(); }
    std::uint32_t next() {
        const std::uint64_t old = state;
        state = old * 6364136223846793005ull + 1442695040888963407ull;
        const auto xorshifted = static_cast<std::uint32_t>(((old >> 18u) ^ old) >> 27u);
        const auto rot = static_cast<std::uint32_t>(old >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
    }
    float uniform() { return static_cast<float>(next() >> 8) * (1.0f / 16777216.0f); }
};

/// The scene's casters in an Embree scene of its own device (released with it): what the reference's
/// and the light sweep's rays hit.
struct EmbreeScene {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    EmbreeScene() = default;
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;
    ~EmbreeScene() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
};
/// Builds e from the scene's caster meshes; false with `why` when Embree has no device.
bool build_embree(const Scene& s, EmbreeScene& e, std::string& why);

struct GBuffer {
    int width = 0, height = 0;
    std::vector<float> position;  // xyz per pixel
    std::vector<float> normal;    // xyz per pixel, unit length
    std::vector<std::uint8_t> kind;
};

struct ReferenceOptions {
    // Area lights: samples per pixel = strata * strata (stratified, jittered). Point, spot and
    // directional lights use one exact ray.
    int strata = 32;
    // Shadow-ray origin offset along the normal, as a fraction of the scene's bounding-box
    // diagonal (1e-5 * diagonal: 0.06 mm on a 6 m scene). Contact points stay right because the
    // offset is far below any gap the scenes model.
    float offset_fraction = 1e-5f;
    int threads = 0;             // 0 = std::thread::hardware_concurrency()
    bool progress = true;        // progress bar on stderr for runs longer than a second
    std::uint32_t seed = 1;
};

struct Reference {
    std::vector<float> visibility;  // V_ref in [0,1] per pixel (0 where kind == 0)
    std::vector<std::uint8_t> faces_light;  // 1 where the light's centre is in front of the surface
    int samples_per_pixel = 1;
    // RMS over receiver pixels of the per-pixel standard error of V_ref, estimated from two
    // interleaved half-sets of the strata (|V_a - V_b| / 2); 0 for hard lights.
    double stderr_rms = 0.0;
    double seconds = 0.0;
    bool from_cache = false;
};

// Visibility fraction as defined here: area lights are sampled uniformly over their area (rect,
// disk), uniformly over the solid angle they subtend (sphere) or along their length (linear); a sample behind the receiver's
// tangent plane, or (rect, disk) a receiver behind the emitter's plane, counts as unseen. Spot
// lights give 0 outside their cone.
bool compute_reference(const Scene& scene, const GBuffer& g, const ReferenceOptions& opt, Reference& out,
                       std::string& why);

// Reference with an on-disk cache keyed by the scene/view/light/size hash and the options.
bool cached_reference(const Scene& scene, const GBuffer& g, const ReferenceOptions& opt,
                      const std::string& cache_dir, Reference& out, std::string& why);

}  // namespace sk
