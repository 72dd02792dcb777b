// PMC energy redistribution (Lai, Fan, Chenney and Dyer, EGSR 2007; "PMC-ER equal deposition",
// its fig. 2). A population of `--population` light paths, each made by path-tracing one
// position of a stratified pool over the image (pt_record) and picking one of the sample's light
// paths by luminance (pmc_er_seed). Every iteration each living member makes `--mutations`
// mutations of its adapted kernel (pmc_er_mutate: radius d_k by the member's alpha, then caustic
// with gamma 0.9 where it applies, else lens; eq. 5, 9) and deposits e_d at its current pixel
// after each; between iterations the host adapts alpha from the acceptance probabilities,
// eliminates `--resample-rate` of the members with survival by remaining energy and refills
// their slots from the pool (methods/pmc_er/path_population.h). When the pass ends every member
// deposits what it has left (pmc_er_finish).
//
// Energy (sec. 4.3): a pass traces Npool = k P pool positions, N at first and R per iteration
// after, so a path of luminance L carries E = L P / Npool of pixel value (P pixels:
// each position is uniform over the image); e_d = E~ / (T N M) with E~ = P times the mean pixel
// luminance of a `--prepass-spp` path-traced pre-pass (eq. 4). Bookkeeping keeps every member's
// expected deposit equal to its energy (methods/pmc_er/path_population.h), so the image is unbiased
// in the sense of ERPT: its expected total energy is the seeds', and deposits follow the current
// paths of chains whose every kernel leaves the target function invariant. Deviations from the
// paper are listed in docs/methods.md ("PMC-ER").
//
// Passes: `--pass-spp` k pool positions per pixel per pass, exactly k in every pixel (the pool
// is stratified per pixel, methods/pmc_er/stratified_pixel_pool.h), and T = 1 + ceil((k P - N) / R)
// iterations use them up (the last regeneration takes what is left); each pass is an
// independent unbiased image and the passes are averaged, so `--spp N` is N path-traced paths
// per pixel in all (the paper's "initial PT paths") and `--time` renders whole passes until
// the time is up. Lanes (`--lanes`, issue 38): the population is split into lanes, each with
// its own members, buffers, command batch and share of every pass's pool (every lanes-th
// position), adapted and resampled on its own; while the device runs one lane's batch the host
// works on another's, so the device is not left waiting for the host at every iteration. A lane
// is a PMC-ER population of its own over its share of the pool: the pass's image is the sum of
// theirs, unbiased as each is. With `--redistribute indirect` (the default, as ERPT's) the seed paths with
// at most one scattering vertex are deposited at their pixel and only the rest make members.
#pragma once

#include <vector>

#include "render/integrator.h"
#include "render/method_info.h"
#include "shared/host_device.h"

namespace pmcr {

struct PmcErOptions {
    uint32_t population = 0;         // 0: auto (one per 4 pixels, at least 64)
    bool paperPopulation = false;    // --population paper: 5000 per 640x480 pixels, at least 64
    uint32_t mutations = 1;          // per member per iteration (paper: 16-20; 1 measured best)
    std::vector<double> radii = {5.0, 10.0, 50.0};
    double resampleRate = 0.4;
    double epsilon = 0.1;
    std::vector<double> initialAlpha;  // a new member's radius weights, normalised (uniform: the paper)
    double adaptRate = 1.0;          // share of the way to the sec. 4.5 update (1: the paper, 0: fixed)
    float causticProbability = 0.9f; // gamma_caustic
    uint32_t passSpp = 4;            // pool positions per pixel per pass (rounds of the pool)
    bool depositDirect = true;       // --redistribute indirect: direct seed paths at their pixel
    bool mixtureAcceptance = false;  // eq. 8 over the radii instead of eq. 9
    double lifetime = 100.0;         // Q of equal births in mutations; 0: auto (mean path energy)
    uint32_t refillRounds = 8;       // regenerations of slots left empty by a birth without shares
    uint32_t prepassSpp = 4;
    uint32_t stepsPerDispatch = 4;
    uint32_t birth = 0;              // gpu::PMC_ER_BIRTH_*
    uint32_t lanes = 0;              // 0: auto (2 once each holds kMinLaneMembers, else 1)

    static PmcErOptions fromSettings(const RenderSettings& settings);
};

class PmcEr : public Integrator {
public:
    explicit PmcEr(const RenderSettings& settings);
    RenderOutput render(RenderSession& session) override;

    static constexpr uint32_t kDefaultSpp = 16;
    uint32_t defaultSpp() const override { return kDefaultSpp; }

private:
    PmcErOptions m_options;
};

// The registry entry of `pmc-er` (render/methods.cpp).
MethodInfo pmcErMethod();

}  // namespace pmcr
