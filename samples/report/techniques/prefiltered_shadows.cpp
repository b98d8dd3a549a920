// samples/report/techniques/prefiltered_shadows.cpp - "vsm", "esm", "evsm2", "evsm4", "msm",
// "msm_hausdorff", and the soft lookup "msm_soft" / "vsm_soft" (soft=on: two rows and one, area lights, also
// on the light-size variants, skr::kLightSizeTechniques) in the report: the sample's PrefilteredShadows class (samples/prefiltered_shadows/), one
// report technique per method (each its own colour on the error-vs-time chart), with timing, work
// counters and sweeps (report_technique.hpp).
//
// Sweep (the old driver's rows as named settings): map size x blur width: 1024 with a 3-texel blur and
// with the width of the light's penumbra (blur_from_light); 2048 with a 3-texel blur for VSM and MSM, one
// per family (a penumbra-wide blur of 2048^2 texels takes ~2 s a frame on llvmpipe); --quick: the
// 3-texel row (the class default). The methods other than MSM run with depth_bias=0 (the class's default, 0.002, is MSM's);
// format=auto (MSM: 16-bit unorm, quantized; the others float32). Spot, area and directional lights, not
// the line light's scene.
// Work, from what the class exposes: shadow_map_texels, blur_taps_per_texel (two passes of 2r + 1),
// kernel_radius, exponent (ESM c / EVSM c+), triangles_drawn (every mesh: receivers too);
// gpu_bytes: the moment map and the blur's intermediate, the depth buffer (MSAA: 4 samples), mipmaps.
// Debug images (ctx.debug_images, the GL tests): the moments 1..3 in light space.
#include <string>
#include <vector>

#include "prefiltered_shadows.hpp"
#include "report_technique.hpp"

namespace sk {

namespace {

bool measure(PrefilteredShadows& t, const PrefilteredShadowSettings& s, const app::View& v, const RunContext& ctx,
             RunResult& r) {
    if (!t.error().empty()) {  // render() could not make the maps
        r = RunResult::failure(t.error());
        return false;
    }
    const shadowkit::PrefilterUniforms& u = t.uniforms();
    const int radius = t.kernel().radius;
    std::size_t triangles = 0;
    for (const auto& mesh : v.gpu->meshes) triangles += static_cast<std::size_t>(mesh.index_count) / 3u;
    const std::int64_t texel_bytes = std::int64_t(u.channels) * (t.format() == shadowkit::PrefilterFormat::Float32 ? 4 : 2);
    const std::int64_t texels = std::int64_t(t.size()) * t.size();
    r.gpu_bytes = texels * (2 * texel_bytes + 4 * (s.msaa ? 4 : 1)) + (s.mips || s.soft ? texels * texel_bytes / 3 : 0);
    r.work = {{"shadow_map_texels", double(texels)},
              {"blur_taps_per_texel", radius > 0 ? 2.0 * (2 * radius + 1) : 0.0},
              {"kernel_radius", double(radius)},
              {"exponent", double(u.exponents.x)},
              {"triangles_drawn", double(triangles)}};
    if (ctx.debug_images) {
        std::vector<float> m(static_cast<std::size_t>(texels) * 4u);
        glPixelStorei(GL_PACK_ALIGNMENT, 4);
        glGetTextureImage(t.moments(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(m.size() * sizeof(float)), m.data());
        const int n = t.size();
        r.debug.push_back(grey_debug_image("moment 1 (light space)", n, n, m, 4, 0, 1e37f));
        if (u.channels > 1) r.debug.push_back(grey_debug_image("moment 2 (light space)", n, n, m, 4, 1, 1e37f));
        if (u.channels > 2) r.debug.push_back(grey_debug_image("moment 3 (light space)", n, n, m, 4, 2, 1e37f));
    }
    return true;
}

}  // namespace

void add_prefilter_techniques(std::vector<std::unique_ptr<Technique>>& out) {
    struct Method {
        const char* name;
        const char* what;
    };
    const Method methods[] = {{"vsm", "variance shadow map (t, t^2), Chebyshev bound"},
                              {"esm", "exponential shadow map e^(c t)"},
                              {"evsm2", "exponential variance shadow map, positive warp"},
                              {"evsm4", "exponential variance shadow map, both warps"},
                              {"msm", "moment shadow map, Hamburger 4MSM"},
                              {"msm_hausdorff", "moment shadow map, Hausdorff reconstruction on [0, 1]"}};
    for (const Method& m : methods) {
        const std::string name = m.name;
        const bool msm = name.rfind("msm", 0) == 0;
        ReportSpec<PrefilteredShadows, PrefilteredShadowSettings> spec;
        spec.name = name;
        spec.description = std::string(m.what) +
                           " (prefiltered_shadow.hpp + glsl/prefiltered_shadow.glsl): map size x Gaussian blur width "
                           "(texels: 3, and the light's penumbra from world units); format " +
                           (msm ? "unorm16, quantized" : "float32");
        spec.hard = false;
        spec.applies = [](const Scene& s) {
            return s.light.type != LightType::Point && s.light.type != LightType::Linear && s.name != "linear";
        };
        const std::string head = "method=" + name + " ", tail = msm ? "" : " depth_bias=0";
        spec.sweep.push_back(head + "size=1024 blur_from_light=off blur_texels=3" + tail);
        if (name == "vsm" || name == "msm") spec.sweep.push_back(head + "size=2048 blur_from_light=off blur_texels=3" + tail);
        spec.sweep.push_back(head + "size=1024 blur_from_light=on" + tail);
        spec.quick = {head + "size=1024 blur_from_light=off blur_texels=3" + tail};
        spec.identity = "method=" + name + tail;
        // scanned meshes: the defaults (their settings=default row: the 3-texel blur); VSM and MSM also
        // the blur from the light's penumbra
        spec.mesh_sweep = {spec.identity};
        if (name == "vsm" || name == "msm") spec.mesh_sweep.push_back(head + "size=1024 blur_from_light=on" + tail);
        spec.measure = measure;
        spec.frame_budget_ms = 400.0;
        add_technique(out, std::move(spec));
    }
    // Soft shadows with contact hardening (soft=on): the blocker search and the penumbra's filter from the mip
    // chain of a 3-texel-blurred map, on area lights and on the light-size variants (against PCSS)
    for (const char* name : {"msm_soft", "vsm_soft"}) {
        const bool msm = name[0] == 'm';
        ReportSpec<PrefilteredShadows, PrefilteredShadowSettings> spec;
        spec.name = name;
        spec.description = std::string(msm ? "moment" : "variance") +
                           " soft shadows with contact hardening (prefilter_soft_uniforms + sk_prefilter_soft_visibility): "
                           "blocker depth from the moments over the search region, the penumbra's width by similar "
                           "triangles, both read from the mip chain of a 1024 map blurred by 3 texels; format " +
                           (msm ? "unorm16, quantized" : "float32");
        spec.hard = false;
        spec.applies = [](const Scene& s) {
            return s.light.is_area() && (s.light.type == LightType::Rect || s.light.type == LightType::Disk ||
                                         s.light.type == LightType::Sphere);
        };
        // rows: MSM without and with the receiver-plane slope bias capped at 0.2 of the range (it removes the
        // self-shadowing of lit faces steep to the light: contact 0.060 -> 0.021; 0.02 and 0.05 lie between);
        // VSM with the slope bias capped at 0.02 (its best of 0, 0.02, 0.05, 0.2 on contact)
        const std::string row = std::string("method=") + (msm ? "msm" : "vsm") +
                                " size=1024 soft=on blur_from_light=off blur_texels=3" + (msm ? "" : " depth_bias=0");
        spec.sweep = msm ? std::vector<std::string>{row, row + " slope_bias=1 slope_bias_max=0.2"}
                         : std::vector<std::string>{row + " slope_bias=1 slope_bias_max=0.02"};
        spec.quick = spec.sweep;
        spec.identity = std::string("method=") + (msm ? "msm" : "vsm") + " soft=on" + (msm ? "" : " depth_bias=0");
        spec.mesh_sweep = {spec.identity, spec.sweep.back()};  // defaults first
        spec.measure = measure;
        spec.frame_budget_ms = 400.0;
        add_technique(out, std::move(spec));
    }
}

}  // namespace sk
