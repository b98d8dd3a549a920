// The report's temporal metrics and paths (samples/report/temporal.cpp, issue 18) on synthetic
// sequences with closed forms:
// - a still V under a still reference: no flicker (temporal RMS, flips, range all 0);
// - a V that toggles 0/1 at 10 of 40 pixels: temporal RMS sqrt(10 / 40) = 0.5, flip fraction 10/40,
//   range 1; the same with 3 masked-out pixels among the toggling ones;
// - a V that follows a changing reference exactly: RMS 0 and the pixels whose reference crosses 0.5
//   are not counted as stable (so V following them is no flip); a V that lags the reference by one
//   frame: RMS from the closed form;
// - soft V drifting by 0.1 a frame at 4 of 16 pixels: RMS sqrt(4 * 0.01 / 16) = 0.05, no flip,
//   range 0.1 (N - 1);
// - the paths: frame 0 is the scene's camera and light, the pan's steps grow from 0.1 to 4 texels
//   and alternate in direction,
//   the yaw turns 0.25 degree a frame, the light turns about the scene's center, and the frustum
//   mask drops points that leave a frame's view.
// Catches: a sum over frames instead of frame differences, the reference's change ignored or added
// with the wrong sign, flips counted where the reference itself changes class, a mean over all
// pixels instead of the masked ones, a range of V instead of V - R.
#include <doctest/doctest.h>

#include <glm/glm.hpp>

#include <cmath>
#include <vector>

#include "temporal.hpp"

namespace {

std::vector<const std::vector<float>*> refs(const std::vector<std::vector<float>>& r) {
    std::vector<const std::vector<float>*> out;
    for (const auto& x : r) out.push_back(&x);
    return out;
}

}  // namespace

TEST_CASE("temporal metrics: a still V under a still reference does not flicker") {
    const std::vector<float> ref(40, 1.0f);
    std::vector<float> v0(40, 1.0f);
    for (int k = 0; k < 15; ++k) v0[std::size_t(k)] = 0.0f;  // wrong, but the same every frame
    v0[20] = 0.37f;
    const std::vector<std::vector<float>> v(6, v0);
    const std::vector<std::uint8_t> mask(40, 1);
    const sk::TemporalMetrics m = sk::compute_temporal_metrics(v, {&ref}, mask);
    CHECK(m.frames == 6);
    CHECK(m.pixels == 40u);
    CHECK(m.temporal_rms == 0.0);
    CHECK(m.flipped_pixels == 0u);
    CHECK(m.stable_pixels == 40u);
    CHECK(m.flip_fraction == 0.0);
    CHECK(m.worst_range == 0.0);
}

TEST_CASE("temporal metrics: a V that toggles gives the computed fraction") {
    const int N = 5;
    const std::vector<float> ref(40, 1.0f);
    std::vector<std::vector<float>> v(N, std::vector<float>(40, 1.0f));
    for (int t = 0; t < N; ++t)
        for (int k = 0; k < 10; ++k) v[std::size_t(t)][std::size_t(k)] = (t % 2 == 0) ? 1.0f : 0.0f;
    std::vector<std::uint8_t> mask(40, 1);
    sk::TemporalMetrics m = sk::compute_temporal_metrics(v, {&ref}, mask);
    // every frame difference: 10 pixels change by 1 -> mean of squares 10 / 40
    CHECK(m.temporal_rms == doctest::Approx(std::sqrt(10.0 / 40.0)));
    CHECK(m.flipped_pixels == 10u);
    CHECK(m.flip_fraction == doctest::Approx(10.0 / 40.0));
    CHECK(m.worst_range == doctest::Approx(1.0));
    // three toggling pixels and two still ones masked out: 7 of 35
    for (int k : {0, 1, 2, 30, 31}) mask[std::size_t(k)] = 0;
    m = sk::compute_temporal_metrics(v, {&ref}, mask);
    CHECK(m.pixels == 35u);
    CHECK(m.temporal_rms == doctest::Approx(std::sqrt(7.0 / 35.0)));
    CHECK(m.flip_fraction == doctest::Approx(7.0 / 35.0));
    // one frame: nothing to compare
    const std::vector<std::vector<float>> one(1, v[0]);
    CHECK(sk::compute_temporal_metrics(one, {&ref}, mask).temporal_rms == 0.0);
}

TEST_CASE("temporal metrics: a moving reference is subtracted, its own class changes are no flips") {
    const int N = 4, P = 20;
    // the reference: pixels 0..4 go 0 -> 1 at frame 2 (a shadow edge sweeping over them), the rest lit
    std::vector<std::vector<float>> r(N, std::vector<float>(P, 1.0f));
    for (int t = 0; t < 2; ++t)
        for (int k = 0; k < 5; ++k) r[std::size_t(t)][std::size_t(k)] = 0.0f;
    const std::vector<std::uint8_t> mask(P, 1);
    // V follows exactly: no flicker, no flips (the 5 pixels are not "stable")
    sk::TemporalMetrics m = sk::compute_temporal_metrics(r, refs(r), mask);
    CHECK(m.temporal_rms == 0.0);
    CHECK(m.stable_pixels == 15u);
    CHECK(m.flipped_pixels == 0u);
    CHECK(m.worst_range == 0.0);
    // V lags one frame: at t = 2 the reference changes by +1 and V not (-1), at t = 3 V catches up (+1):
    // 5 pixels x 2 frame differences of 1 over 20 pixels x 3 differences
    std::vector<std::vector<float>> lag = r;
    for (int k = 0; k < 5; ++k) lag[2][std::size_t(k)] = 0.0f;
    m = sk::compute_temporal_metrics(lag, refs(r), mask);
    CHECK(m.temporal_rms == doctest::Approx(std::sqrt(10.0 / 60.0)));
    CHECK(m.flipped_pixels == 0u);       // only the non-stable pixels changed class
    CHECK(m.worst_range == doctest::Approx(1.0));  // V - R: 0, 0, -1, 0
    // a still V under this moving reference is scored as missing the reference's change
    const std::vector<std::vector<float>> still(N, r[0]);
    m = sk::compute_temporal_metrics(still, refs(r), mask);
    CHECK(m.temporal_rms == doctest::Approx(std::sqrt(5.0 / 60.0)));
}

TEST_CASE("temporal metrics: soft V drifting by 0.1 a frame") {
    const int N = 6, P = 16;
    const std::vector<float> ref(P, 0.5f);
    std::vector<std::vector<float>> v(N, std::vector<float>(P, 0.2f));
    for (int t = 0; t < N; ++t)
        for (int k = 0; k < 4; ++k) v[std::size_t(t)][std::size_t(k)] = 0.1f + 0.05f * float(t);  // stays below 0.5
    const sk::TemporalMetrics m = sk::compute_temporal_metrics(v, {&ref}, std::vector<std::uint8_t>(P, 1));
    CHECK(m.temporal_rms == doctest::Approx(std::sqrt(4.0 * 0.0025 / 16.0)).epsilon(1e-5));
    CHECK(m.flipped_pixels == 0u);
    CHECK(m.worst_range == doctest::Approx(0.05 * (N - 1)).epsilon(1e-5));
}

TEST_CASE("temporal paths: closed forms") {
    sk::Scene s;
    REQUIRE(sk::make_builtin_scene("stack", s));
    const int N = 16;
    for (sk::TemporalPath p : {sk::TemporalPath::Pan, sk::TemporalPath::Yaw, sk::TemporalPath::Dolly, sk::TemporalPath::Light}) {
        const auto f = sk::temporal_path(s, p, N);
        REQUIRE(f.size() == std::size_t(N));
        CHECK(f[0].camera.eye == s.camera.eye);
        CHECK(f[0].camera.target == s.camera.target);
        CHECK(f[0].light.position == s.light.position);
        CHECK(sk::temporal_path_moves_camera(p) == (p != sk::TemporalPath::Light));
    }
    const double texel = double(glm::length(s.bounds_max() - s.bounds_min())) / 2048.0;
    const auto pan = sk::temporal_path(s, sk::TemporalPath::Pan, N);
    CHECK(glm::length(glm::dvec3(pan[1].camera.eye - pan[0].camera.eye)) == doctest::Approx(0.1 * texel).epsilon(1e-3));
    CHECK(glm::length(glm::dvec3(pan[N - 1].camera.eye - pan[N - 2].camera.eye)) == doctest::Approx(4.0 * texel).epsilon(1e-3));
    // each step the other way: frame 2 lies between frames 0 and 1
    CHECK(glm::dot(glm::dvec3(pan[2].camera.eye - pan[1].camera.eye), glm::dvec3(pan[1].camera.eye - pan[0].camera.eye)) < 0.0);
    CHECK(glm::length(glm::dvec3(pan[N - 1].camera.eye - s.camera.eye)) < 2.5 * texel);
    const glm::vec3 d0 = s.camera.target - s.camera.eye, d5 = pan[5].camera.target - pan[5].camera.eye;
    CHECK(glm::length(d5 - d0) < 1e-5f);  // a translation: the view direction stays
    const auto yaw = sk::temporal_path(s, sk::TemporalPath::Yaw, N);
    const glm::vec3 a = glm::normalize(glm::vec3(d0.x, 0, d0.z)), b = yaw[4].camera.target - yaw[4].camera.eye;
    const float ang = std::acos(glm::dot(a, glm::normalize(glm::vec3(b.x, 0, b.z))));
    CHECK(double(ang) == doctest::Approx(4 * 0.25 * 3.14159265358979 / 180.0).epsilon(1e-3));
    const auto light = sk::temporal_path(s, sk::TemporalPath::Light, N);
    const glm::vec3 c = 0.5f * (s.bounds_min() + s.bounds_max());
    CHECK(glm::length(light[N - 1].light.position - c) == doctest::Approx(glm::length(s.light.position - c)).epsilon(1e-5));
    CHECK(light[N - 1].light.position.y == doctest::Approx(s.light.position.y));
    CHECK(light[N - 1].camera.eye == s.camera.eye);
    // the frustum mask: a synthetic G-buffer (4 x 1) with a point in the middle of the view, one at its
    // left and one at its right edge, and a background pixel: the yaw turns one edge out of view
    sk::GBuffer g;
    g.width = 4;
    g.height = 1;
    g.kind = {1, 1, 1, 0};
    const glm::vec3 f0 = glm::normalize(d0);
    const glm::vec3 right = glm::normalize(glm::cross(f0, s.camera.up));
    const glm::vec3 up = glm::cross(right, f0);
    const float half_w = std::tan(0.5f * s.camera.fovy) * 4.0f;  // aspect 4
    const glm::vec3 mid = s.camera.eye + 3.0f * f0;
    const glm::vec3 left = s.camera.eye + 3.0f * (f0 - 0.999f * half_w * right + 0.0f * up);
    const glm::vec3 rgt = s.camera.eye + 3.0f * (f0 + 0.999f * half_w * right);
    for (const glm::vec3& p : {mid, left, rgt, mid}) g.position.insert(g.position.end(), {p.x, p.y, p.z});
    CHECK(sk::temporal_frustum_mask(g, {yaw[0]}) == std::vector<std::uint8_t>{1, 1, 1, 0});
    const std::vector<std::uint8_t> m = sk::temporal_frustum_mask(g, yaw);
    CHECK(m[0] == 1);
    CHECK(m[1] + m[2] == 1);  // 4 degrees: one edge point leaves, the other stays
    CHECK(m[3] == 0);
}
