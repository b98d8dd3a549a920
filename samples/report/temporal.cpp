// samples/report/temporal.cpp - the report's temporal paths and flicker metrics, and the
// default Technique::run_sequence (run() once per frame, for a Technique that is not a ReportTechnique).
#include "temporal.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

namespace sk {

const char* temporal_path_name(TemporalPath p) {
    switch (p) {
    case TemporalPath::Pan: return "pan";
    case TemporalPath::Yaw: return "yaw";
    case TemporalPath::Dolly: return "dolly";
    case TemporalPath::Light: return "light";
    }
    return "?";
}

bool temporal_path_moves_camera(TemporalPath p) { return p != TemporalPath::Light; }

namespace {

constexpr double kDegree = 3.14159265358979323846 / 180.0;

// Rotation by `angle` about the vertical (y) axis.
glm::dvec3 turn_y(const glm::dvec3& v, double angle) {
    const double c = std::cos(angle), s = std::sin(angle);
    return {c * v.x + s * v.z, v.y, -s * v.x + c * v.z};
}

}  // namespace

std::vector<TemporalFrame> temporal_path(const Scene& scene, TemporalPath path, int frames) {
    std::vector<TemporalFrame> out;
    const Camera cam0 = scene.camera;
    const glm::dvec3 eye(cam0.eye), target(cam0.target), up(cam0.up);
    const glm::dvec3 fwd = glm::normalize(target - eye);
    const glm::dvec3 right = glm::normalize(glm::cross(fwd, up));
    const glm::dvec3 pan_dir = right;
    const double texel = double(glm::length(scene.bounds_max() - scene.bounds_min())) / 2048.0;
    const glm::dvec3 center = 0.5 * (glm::dvec3(scene.bounds_min()) + glm::dvec3(scene.bounds_max()));
    double pan = 0.0;
    for (int t = 0; t < frames; ++t) {
        TemporalFrame f{cam0, scene.light};
        switch (path) {
        case TemporalPath::Pan: {
            // steps of 0.1 to 4 texels, each the other way: the camera stays within about 2 texels of
            // its start (the points it sees stay in view on a 1 km scene too)
            if (t > 0) pan += (t % 2 ? 1.0 : -1.0) * texel * (frames > 2 ? 0.1 * std::pow(40.0, double(t - 1) / double(frames - 2)) : 1.0);
            const glm::dvec3 d = pan * pan_dir;
            f.camera.eye = glm::vec3(eye + d);
            f.camera.target = glm::vec3(target + d);
            break;
        }
        case TemporalPath::Yaw:
            f.camera.target = glm::vec3(eye + turn_y(target - eye, 0.25 * kDegree * t));
            break;
        case TemporalPath::Dolly:
            f.camera.eye = glm::vec3(eye + (target - eye) * (0.005 * t));
            break;
        case TemporalPath::Light: {
            const double a = 0.25 * kDegree * t;
            f.light.position = glm::vec3(center + turn_y(glm::dvec3(scene.light.position) - center, a));
            f.light.direction = glm::vec3(turn_y(glm::dvec3(scene.light.direction), a));
            break;
        }
        }
        out.push_back(f);
    }
    return out;
}

std::vector<std::uint8_t> temporal_frustum_mask(const GBuffer& g, const std::vector<TemporalFrame>& frames) {
    const std::size_t n = g.kind.size();
    std::vector<std::uint8_t> mask(n, 0);
    std::vector<glm::dmat4> vps;
    const float aspect = float(g.width) / float(std::max(g.height, 1));
    for (const TemporalFrame& f : frames) vps.push_back(glm::dmat4(f.camera.projection(aspect)) * glm::dmat4(f.camera.view()));
    for (std::size_t k = 0; k < n; ++k) {
        if (g.kind[k] == 0) continue;
        const glm::dvec4 p(g.position[3 * k], g.position[3 * k + 1], g.position[3 * k + 2], 1.0);
        bool inside = true;
        for (const glm::dmat4& m : vps) {
            const glm::dvec4 c = m * p;
            if (!(c.w > 0.0 && std::fabs(c.x) <= c.w && std::fabs(c.y) <= c.w && std::fabs(c.z) <= c.w)) {
                inside = false;
                break;
            }
        }
        mask[k] = inside ? 1 : 0;
    }
    return mask;
}

TemporalMetrics compute_temporal_metrics(const std::vector<std::vector<float>>& v,
                                         const std::vector<const std::vector<float>*>& ref,
                                         const std::vector<std::uint8_t>& mask) {
    TemporalMetrics m;
    m.frames = static_cast<int>(v.size());
    for (std::uint8_t b : mask) m.pixels += b ? 1 : 0;
    if (v.size() < 2 || ref.empty() || m.pixels == 0) return m;
    auto R = [&](std::size_t t) -> const std::vector<float>& { return *ref[ref.size() == 1 ? 0 : t]; };
    double sq = 0.0;
    for (std::size_t k = 0; k < mask.size(); ++k) {
        if (!mask[k]) continue;
        bool ref_class_changes = false, v_class_changes = false;
        const bool ref_lit0 = R(0)[k] >= 0.5f, v_lit0 = v[0][k] >= 0.5f;
        double emin = double(v[0][k]) - double(R(0)[k]), emax = emin;
        for (std::size_t t = 1; t < v.size(); ++t) {
            const double dv = double(v[t][k]) - double(v[t - 1][k]);
            const double dr = double(R(t)[k]) - double(R(t - 1)[k]);
            sq += (dv - dr) * (dv - dr);
            ref_class_changes = ref_class_changes || (R(t)[k] >= 0.5f) != ref_lit0;
            v_class_changes = v_class_changes || (v[t][k] >= 0.5f) != v_lit0;
            const double e = double(v[t][k]) - double(R(t)[k]);
            emin = std::min(emin, e);
            emax = std::max(emax, e);
        }
        m.worst_range = std::max(m.worst_range, emax - emin);
        if (!ref_class_changes) {
            ++m.stable_pixels;
            if (v_class_changes) ++m.flipped_pixels;
        }
    }
    m.temporal_rms = std::sqrt(sq / (double(m.pixels) * double(v.size() - 1)));
    m.flip_fraction = m.stable_pixels ? double(m.flipped_pixels) / double(m.stable_pixels) : 0.0;
    return m;
}

SequenceResult Technique::run_sequence(const RunContext& ctx, const ParamSet& params, const std::vector<TemporalFrame>& frames) {
    SequenceResult out;
    Scene scene = ctx.scene;  // its light turns with the frames
    for (const TemporalFrame& f : frames) {
        scene.light = f.light;
        RunContext c{scene, ctx.gpu, 1, 0, nullptr};
        c.fit_camera = &f.camera;
        RunResult r = run(c, params);
        if (!r.ok) return SequenceResult::failure(r.error);
        out.visibility.push_back(std::move(r.visibility));
    }
    return out;
}

}  // namespace sk
