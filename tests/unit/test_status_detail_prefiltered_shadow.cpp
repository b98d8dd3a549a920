// Where a status came from (issue #25 item 6): the first validation of every public function of
// prefiltered_shadow.hpp that returns a result names the offending input in `detail`; Ok gives nullptr.
#include <shadowkit/prefiltered_shadow.hpp>

#include "status_detail.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <limits>

using namespace shadowkit;

namespace {
const float kNaN = std::numeric_limits<float>::quiet_NaN();
PrefilterSoftSettings soft_settings() {
    PrefilterSoftSettings s;
    s.light_proj = glm::perspective(1.0f, 1.0f, 0.5f, 50.0f);
    s.light_width = 0.5f;
    s.range = prefilter_depth_range(0.5f, 50.0f);
    s.map_size = 512;
    return s;
}
}  // namespace

TEST_CASE("prefiltered_shadow: the first validation of each function names its input") {
    SK_CHECK_DETAIL(prefilter_depth_range(kNaN, 10.0f), Status::NonFinite, "near");
    SK_CHECK_DETAIL(prefilter_depth_range(5.0f, 1.0f), Status::InvalidArgument, "far");
    SK_CHECK_DETAIL(prefilter_window_depth_map(0.5f, 50.0f, true, false, PrefilterDepthRange{}), Status::InvalidArgument, "r");
    SK_CHECK_DETAIL(prefilter_store(std::numeric_limits<double>::infinity(), PrefilterFormat::Float32), Status::NonFinite, "v");
    SK_CHECK_DETAIL(prefilter_store(1e6, PrefilterFormat::Float16), Status::Overflow, "v");
    SK_CHECK_DETAIL(prefilter_exponent_limit(PrefilterMethod::Vsm, PrefilterFormat::Float32, 1u), Status::InvalidArgument,
                    "method");
    PrefilterSettings ps;
    ps.min_variance = kNaN;
    SK_CHECK_DETAIL(prefilter_uniforms(ps), Status::NonFinite, "min_variance");
    ps = PrefilterSettings{};
    ps.method = PrefilterMethod::Esm;
    ps.format = PrefilterFormat::Unorm16;
    SK_CHECK_DETAIL(prefilter_uniforms(ps), Status::InvalidArgument, "format");
    float w[8];
    SK_CHECK_DETAIL(prefilter_blur_weights(PrefilterBlur::Box, kNaN, w, 8), Status::NonFinite, "width_texels");
    SK_CHECK_DETAIL(prefilter_blur_weights(PrefilterBlur::Box, 9.0f, w, 2), Status::BufferTooSmall, "weights_capacity");
    SK_CHECK_DETAIL(prefilter_kernel_texels(glm::perspective(1.0f, 1.0f, 0.5f, 50.0f), 1.0f, kNaN, 512, 512),
                    Status::NonFinite, "eye_distance");
    PrefilterSoftSettings ss = soft_settings();
    ss.light_width = kNaN;
    SK_CHECK_DETAIL(prefilter_soft_uniforms(ss), Status::NonFinite, "light_width");
    ss = soft_settings();
    ss.map_size = 500;
    SK_CHECK_DETAIL(prefilter_soft_uniforms(ss), Status::InvalidArgument, "map_size");
    SK_CHECK_DETAIL(prefilter_soft_blocker(glm::vec4(0.5f), 0.5f, PrefilterUniforms{}), Status::InvalidArgument, "u");
    SK_CHECK_DETAIL(prefilter_soft_penumbra(kNaN, 0.2f, prefilter_soft_uniforms(soft_settings())), Status::NonFinite,
                    "t_receiver");
}

TEST_CASE("prefiltered_shadow: Ok results carry no detail") {
    const PrefilterDepthRange r = prefilter_depth_range(0.5f, 50.0f);
    SK_CHECK_OK_NO_DETAIL(r);
    SK_CHECK_OK_NO_DETAIL(prefilter_window_depth_map(0.5f, 50.0f, true, false, r));
    SK_CHECK_OK_NO_DETAIL(prefilter_store(0.5, PrefilterFormat::Float32));
    SK_CHECK_OK_NO_DETAIL(prefilter_exponent_limit(PrefilterMethod::Esm, PrefilterFormat::Float32, 1u));
    const PrefilterUniforms u = prefilter_uniforms(PrefilterSettings{});
    SK_CHECK_OK_NO_DETAIL(u);
    float w[8];
    SK_CHECK_OK_NO_DETAIL(prefilter_blur_weights(PrefilterBlur::Gaussian, 5.0f, w, 8));
    SK_CHECK_OK_NO_DETAIL(prefilter_kernel_texels(glm::perspective(1.0f, 1.0f, 0.5f, 50.0f), 1.0f, 10.0f, 512, 512));
    const PrefilterSoftUniforms su = prefilter_soft_uniforms(soft_settings());
    SK_CHECK_OK_NO_DETAIL(su);
    SK_CHECK_OK_NO_DETAIL(prefilter_soft_blocker(glm::vec4(0.5f, 0.3f, 0.0f, 0.0f), 0.7f, u));
    SK_CHECK_OK_NO_DETAIL(prefilter_soft_penumbra(0.6f, 0.3f, su));
}
