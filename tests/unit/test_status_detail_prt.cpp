// Where a status came from (issue #25 item 6): the first validation of every public function of
// prt.hpp that returns a result names the offending input in `detail`; Ok gives nullptr.
#include <shadowkit/prt.hpp>

#include "status_detail.hpp"

#include <limits>
#include <vector>

using namespace shadowkit;

namespace {
const float kNaN = std::numeric_limits<float>::quiet_NaN();
bool always_visible(void*, const glm::vec3&, const glm::vec3&) { return true; }
}  // namespace

TEST_CASE("prt: the first validation of each function names its input") {
    float y[25];
    SK_CHECK_DETAIL(prt_sh_basis(0, glm::vec3(0, 0, 1), y, 25), Status::InvalidArgument, "order");
    SK_CHECK_DETAIL(prt_make_samples(3, 0, 1u), Status::InvalidArgument, "strata");
    const PrtSamples samples = prt_make_samples(3, 8, 1u);
    REQUIRE(samples.status == Status::Ok);
    PrtTransferOptions opt;
    opt.albedo = kNaN;
    const glm::vec3 pos[1] = {glm::vec3(0.0f)}, nrm[1] = {glm::vec3(0, 1, 0)};
    std::vector<float> t(9);
    SK_CHECK_DETAIL(prt_compute_transfer(PrtSamples{}, PrtTransferOptions{}, pos, nrm, 1, always_visible, nullptr, t.data(), 9),
                    Status::InvalidArgument, "samples");
    SK_CHECK_DETAIL(prt_compute_transfer(samples, opt, pos, nrm, 1, always_visible, nullptr, t.data(), 9), Status::NonFinite,
                    "albedo");
    SK_CHECK_DETAIL(prt_compute_transfer(samples, PrtTransferOptions{}, pos, nrm, 1, nullptr, nullptr, t.data(), 9),
                    Status::InvalidArgument, "visible");
    glm::vec3 env[9];
    SK_CHECK_DETAIL(prt_project_environment(PrtSamples{}, [](const glm::vec3&) { return glm::vec3(1.0f); }, env, 9),
                    Status::InvalidArgument, "samples");
    const float tr[9] = {1.0f};
    const glm::vec3 env3[9] = {glm::vec3(1.0f)};
    SK_CHECK_DETAIL(prt_shade_rgb(3, nullptr, env3), Status::InvalidArgument, "transfer");
    SK_CHECK_DETAIL(prt_shade(0, tr, tr), Status::InvalidArgument, "order");
    glm::vec3 out[2];
    SK_CHECK_DETAIL(prt_shade_mesh(3, tr, 4, 1, env3, out, 1), Status::InvalidArgument, "stride");
    PrtCpcaOptions co;
    co.clusters = 0;
    SK_CHECK_DETAIL(prt_cpca_compress(3, tr, 9, 1, co), Status::InvalidArgument, "clusters");
    const PrtCpca none;
    float rec[9];
    SK_CHECK_DETAIL(prt_cpca_reconstruct(none, 0, rec, 9), Status::InvalidArgument, "cp");
    glm::vec3 proj[16];
    SK_CHECK_DETAIL(prt_cpca_project_environment(none, env3, 9, proj, 16), Status::InvalidArgument, "cp");
    SK_CHECK_DETAIL(prt_cpca_shade(none, nullptr, 0), Status::InvalidArgument, "projected");
    SK_CHECK_DETAIL(prt_cpca_shade_mesh(none, proj, out, 1), Status::InvalidArgument, "cp");
}

TEST_CASE("prt: Ok results carry no detail") {
    float y[25];
    SK_CHECK_OK_NO_DETAIL(prt_sh_basis(3, glm::vec3(0, 0, 1), y, 25));
    const PrtSamples samples = prt_make_samples(3, 8, 1u);
    SK_CHECK_OK_NO_DETAIL(samples);
    const glm::vec3 pos[2] = {glm::vec3(0.0f), glm::vec3(1.0f, 0.0f, 0.0f)}, nrm[2] = {glm::vec3(0, 1, 0), glm::vec3(0, 1, 0)};
    std::vector<float> t(18);
    SK_CHECK_OK_NO_DETAIL(prt_compute_transfer(samples, PrtTransferOptions{}, pos, nrm, 2, always_visible, nullptr, t.data(), 18));
    glm::vec3 env[9];
    SK_CHECK_OK_NO_DETAIL(prt_project_environment(samples, [](const glm::vec3& d) { return d * d; }, env, 9));
    SK_CHECK_OK_NO_DETAIL(prt_shade_rgb(3, t.data(), env));
    const float envs[9] = {1.0f, 0.5f};
    SK_CHECK_OK_NO_DETAIL(prt_shade(3, t.data(), envs));
    glm::vec3 out[2];
    SK_CHECK_OK_NO_DETAIL(prt_shade_mesh(3, t.data(), 9, 2, env, out, 2));
    PrtCpcaOptions co;
    co.clusters = 1;
    co.components = 1;
    const PrtCpca cp = prt_cpca_compress(3, t.data(), 9, 2, co);
    SK_CHECK_OK_NO_DETAIL(cp);
    float rec[9];
    SK_CHECK_OK_NO_DETAIL(prt_cpca_reconstruct(cp, 1, rec, 9));
    std::vector<glm::vec3> proj(cp.clusters * (static_cast<std::size_t>(cp.components) + 1));
    SK_CHECK_OK_NO_DETAIL(prt_cpca_project_environment(cp, env, 9, proj.data(), proj.size()));
    SK_CHECK_OK_NO_DETAIL(prt_cpca_shade(cp, proj.data(), 0));
    SK_CHECK_OK_NO_DETAIL(prt_cpca_shade_mesh(cp, proj.data(), out, 2));
}
