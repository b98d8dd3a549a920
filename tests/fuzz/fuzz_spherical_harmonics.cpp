// libFuzzer target for include/shadowkit/spherical_harmonics.hpp: orders (valid and not),
// directions, coefficient vectors, rotation matrices (raw floats, or a proper rotation / reflection
// built from a decoded quaternion), projection samples with values and weights (NaN/Inf, zero
// directions, huge counts capped by the input), zonal kernels and capacities decoded from bytes.
// Calls every public function. Invariants trap: Status::Ok only with finite outputs and count ==
// needed <= capacity, NaN input never Ok, NotRun never returned, the total functions
// (sh_clamped_cosine_band, sh_coefficient_count) finite and in range for every int.
#include <shadowkit/spherical_harmonics.hpp>

#include <glm/gtc/quaternion.hpp>

#include "fuzz_input.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

namespace {
using shadowkit_fuzz::check;

bool finite(const double* v, size_t n) {
    for (size_t i = 0; i < n; ++i)
        if (!std::isfinite(v[i])) return false;
    return true;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace shadowkit;
    shadowkit_fuzz::FuzzInput r(data, size);
    const uint8_t flags = r.u8();
    const bool raw = flags & 1, raw_matrix = flags & 2, reflect = flags & 4, use_weights = flags & 8;
    constexpr float kStep = 1.0f / 64.0f;  // quantized (not raw) values: a signed byte / 64
    const int order = r.range(-7, 7);
    const size_t cap = r.size(29);
    const size_t need = sh_coefficient_count(order);
    check(need == (sh_order_valid(order) ? static_cast<size_t>(order * order) : 0u));

    // evaluation and reconstruction at a direction
    const glm::vec3 dir = r.vec3(raw, kStep);
    float yf[32];
    SHResult e = sh_evaluate(order, dir, yf, cap);
    shadowkit_fuzz::check_detail(e);
    check(e.count <= cap && e.status != Status::NotRun);
    if (e.status == Status::Ok) {
        check(shadowkit_fuzz::all_finite(dir));
        check(e.count == need && e.count <= cap);
        double s = 0.0;
        for (size_t i = 0; i < e.count; ++i) {
            check(std::isfinite(yf[i]) && std::fabs(yf[i]) < 2.0f);  // |y_lm| <= sqrt((2l+1)/(4 pi)) < 0.85
            s += double(yf[i]) * double(yf[i]);
        }
        // addition theorem: sum_m y_lm^2 = (2l+1)/(4 pi) per band, so the total is order^2 / (4 pi)
        check(std::fabs(s - double(order * order) / (4.0 * 3.14159265358979323846)) < 1e-5);
    }
    if (e.status == Status::BufferTooSmall) check(e.needed == need && cap < need && e.count == 0);
    if (e.status != Status::Ok) check(e.count == 0);

    double c[25];
    for (double& v : c) v = static_cast<double>(r.value(raw, kStep));
    const glm::dvec3 ddir(dir);
    SHValue<double> rv = sh_reconstruct(order, c, cap, ddir);
    shadowkit_fuzz::check_detail(rv);
    check(rv.status != Status::NotRun);
    if (rv.status == Status::Ok) check(std::isfinite(rv.value) && finite(c, need) && shadowkit_fuzz::all_finite(dir));
    else check(rv.value == 0.0);

    // rotation
    glm::dmat3 R(1.0);
    if (raw_matrix) {
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) R[i][j] = static_cast<double>(r.f32());
    } else {
        const float qw = r.quantized(kStep), qx = r.quantized(kStep), qy = r.quantized(kStep), qz = r.quantized(kStep);
        glm::dquat q(qw, qx, qy, qz);
        if (glm::length(q) > 1e-3) R = glm::mat3_cast(glm::normalize(q));
        if (reflect) R = -R;
    }
    const SHRotation rot = sh_make_rotation(order, R);
    shadowkit_fuzz::check_detail(rot);
    const Status rs = rot.status;
    check(rs != Status::NotRun);
    if (!raw_matrix && sh_order_valid(order)) check(rs == Status::Ok);
    if (rs == Status::Ok) {
        for (int i = 0; i < 165; ++i) check(std::isfinite(rot.band[i]));
        double out[25];
        const SHResult rr = sh_rotate(rot, c, 25, out, cap);
        shadowkit_fuzz::check_detail(rr);
        check(rr.count <= cap);
        if (rr.status == Status::Ok) {
            check(rr.count == need);
            check(finite(out, need));
            // each band's length is preserved (orthogonal blocks; R orthogonal within 1e-3)
            for (int l = 0; l < order; ++l) {
                double a = 0.0, b = 0.0;
                for (int m = -l; m <= l; ++m) {
                    a += c[sh_index(l, m)] * c[sh_index(l, m)];
                    b += out[sh_index(l, m)] * out[sh_index(l, m)];
                }
                check(std::fabs(a - b) <= 0.05 * a + 1e-300);
            }
        } else {
            check(rr.status == Status::BufferTooSmall || rr.status == Status::NonFinite || rr.status == Status::Overflow);
            check(rr.count == 0);
        }
        // in place
        double inplace[25];
        std::memcpy(inplace, c, sizeof c);
        const SHResult ip = sh_rotate(rot, inplace, 25, inplace, 25);
        shadowkit_fuzz::check_detail(ip);
        if (ip.status == Status::Ok) check(finite(inplace, need));
        // the convenience form agrees with the two-step form
        double out2[25];
        const SHResult r2 = sh_rotate(order, R, c, 25, out2, 25);
        shadowkit_fuzz::check_detail(r2);
        check(r2.status == ip.status);
    } else {
        check(rot.order == 0);
        double out[25];
        check(sh_rotate(rot, c, 25, out, 25).status == Status::InvalidArgument);
        check(sh_rotate(order, R, c, 25, out, 25).status == rs);
    }

    // convolution
    double zonal[5];
    for (double& z : zonal) z = static_cast<double>(r.value(raw, kStep));
    double conv[25];
    const SHResult cz = sh_convolve_zonal(order, zonal, 5, c, 25, conv, cap);
    shadowkit_fuzz::check_detail(cz);
    check(cz.count <= cap && cz.status != Status::NotRun);
    if (cz.status == Status::Ok) check(finite(conv, need) && finite(c, need) && finite(zonal, size_t(order)));
    const SHResult cc = sh_convolve_clamped_cosine(order, c, 25, conv, cap);
    shadowkit_fuzz::check_detail(cc);
    check(cc.count <= cap && cc.status != Status::NotRun);
    if (cc.status == Status::Ok) check(finite(conv, need) && finite(c, need));
    const SHValue<double> dv = sh_dot(order, c, 25, conv, cap);
    shadowkit_fuzz::check_detail(dv);
    if (dv.status == Status::Ok) check(std::isfinite(dv.value) && finite(c, need));

    // projection from samples (float values; count capped by the remaining input)
    const size_t samples = r.size(63);
    std::vector<glm::vec3> dirs;
    std::vector<float> vals, weights;
    std::vector<glm::vec3> rgb;
    for (size_t j = 0; j < samples && r.remaining() > 0; ++j) {
        dirs.push_back(r.vec3(raw, kStep));
        vals.push_back(r.value(raw, kStep));
        weights.push_back(r.value(raw, kStep));
        rgb.emplace_back(vals.back(), -vals.back(), r.value(raw, kStep));
    }
    float proj[25];
    const SHResult pr = sh_project(order, dirs.data(), vals.data(), use_weights ? weights.data() : nullptr, dirs.size(),
                                   proj, cap);
    shadowkit_fuzz::check_detail(pr);
    check(pr.count <= cap && pr.status != Status::NotRun);
    if (pr.status == Status::Ok) {
        check(pr.count == need);
        for (size_t i = 0; i < need; ++i) check(std::isfinite(proj[i]));
        for (size_t j = 0; j < dirs.size(); ++j)
            check(shadowkit_fuzz::all_finite(dirs[j]) && std::isfinite(vals[j]) && (!use_weights || std::isfinite(weights[j])));
    }
    glm::vec3 projrgb[25];
    const SHResult prgb = sh_project_rgb(order, dirs.data(), rgb.data(), use_weights ? weights.data() : nullptr,
                                         rgb.size(), projrgb, cap);
    shadowkit_fuzz::check_detail(prgb);
    check(prgb.count <= cap && prgb.status != Status::NotRun);
    if (prgb.status == Status::Ok)
        for (size_t i = 0; i < need; ++i)
            check(std::isfinite(projrgb[i].x) && std::isfinite(projrgb[i].y) && std::isfinite(projrgb[i].z));

    // stratified directions
    const int strata = r.range(-11, 11);
    glm::vec3 sd[128];
    const SHResult st = sh_stratified_directions(strata, r.u32(), sd, 128);
    shadowkit_fuzz::check_detail(st);
    check(st.status != Status::NotRun);
    if (st.status == Status::Ok) {
        check(st.count == size_t(strata * strata));
        for (size_t i = 0; i < st.count; ++i) check(std::fabs(glm::length(sd[i]) - 1.0f) < 1e-5f);
    }
    const int band = r.i32();
    const double a = sh_clamped_cosine_band(band);  // total: finite, in [-pi / 24, pi]
    check(std::isfinite(a) && a >= -3.14159265358979323846 / 24.0 - 1e-12 && a <= 3.14159265358979323846 + 1e-12);
    (void)sh_clamped_cosine_band(order);
    return 0;
}
