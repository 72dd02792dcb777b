// PMC-IP (Fan, Lai, Chenney and Dyer, "Population Monte Carlo Samplers for Rendering", sec. 4):
// adaptive image-plane sampling over path tracing (`pmc-ip`) or MIS direct lighting
// (`pmc-ip-direct`, the paper's Buddha case). The image-plane sampler (render/
// image_plane_sampler.h) decides each iteration's per-pixel sample counts and forms the
// estimates; this integrator traces the samples it asks for with the same kernels as `pt` and
// `direct` (camera samples from a request list, one result per sample, reduced on the host in
// request order so that a seed gives the same image bit for bit).
//
// Budget: the first iteration takes `--initial-spp` uniformly, each later one `--spp-per-iteration`
// on average; `--iterations` adaptive iterations, or as many as `--spp` allows (average samples
// per pixel in total), or as many as fit in `--time`. Options and defaults: pmcIpMethod() and
// the other registry entries (pmc_ip_integrator.cpp).
//
// `pmc-ip-hi` traces its samples with PMC-HI adaptive direct lighting
// (shaders/methods/pmc_hi/pmc_hi.comp) and feeds back (sec. 6.1): after each image-plane iteration,
// each pixel's mean of the final alpha of its samples' first-hit estimates goes into an auxiliary
// image, which seeds the PMC-HI weights of the pixel's samples in the next iteration.
//
// `pm-pmc` (sec. 6, figures 1 and 10) is `pmc-ip-hi` over photon mapping's gather
// (methods/pm/pm_integrator.h): each image-plane iteration gets a new photon pass (or the one
// map, --progressive off) and traces its samples with shaders/methods/pm/pm_gather_hi.comp,
// PMC-HI direct lighting with the feedback at each sample's gather point.
#pragma once

#include "methods/pm/photon_map.h"
#include "methods/pmc_hi/pmc_hi.h"
#include "methods/pmc_ip/image_plane_sampler.h"
#include "render/baseline_options.h"
#include "render/integrator.h"
#include "render/method_info.h"

namespace pmcr {

class PmcIp : public Integrator {
public:
    enum class Estimator { Full, Direct, PmcHi, PhotonGather };
    PmcIp(const RenderSettings& settings, Estimator estimator);
    RenderOutput render(RenderSession& session) override;

    static constexpr uint32_t kDefaultSpp = 64;
    uint32_t defaultSpp() const override { return kDefaultSpp; }

private:
    Estimator m_estimator;
    ImagePlaneOptions m_options;
    bool m_samplesPerIterationGiven = false;  // else sized to the device in render()
    uint32_t m_iterations = 0;  // adaptive iterations after the first; 0: from --spp or --time
    uint32_t m_hostThreads = 0;  // --host-threads; 0: from the device
    uint32_t m_lightSamples = 1;
    PmcHiOptions m_hi;
    bool m_feedback = true;
    PhotonMapOptions m_photons;  // PhotonGather
    BaselineOptions m_baseline;  // --pixel-sampler (every estimator), --mis (Full and Direct)
};

// The registry entries (render/methods.cpp) of `pmc-ip`, `pmc-ip-direct`, `pmc-ip-hi` and
// `pm-pmc`.
MethodInfo pmcIpMethod();
MethodInfo pmcIpDirectMethod();
MethodInfo pmcIpHiMethod();
MethodInfo pmPmcMethod();

}  // namespace pmcr
