// Primary-sample-space Metropolis light transport (Kelemen, Szirmay-Kalos, Antal and Csonka
// 2002) over bidirectional path tracing (--over bdpt, the default, as Mitsuba's PSSMLT) or the
// path tracer (--over pt). A chain's state is the vector of the estimator's random numbers
// (shared/pssmlt_types.h); its target is F(u) = lum(L(u)), L(u) the estimator's whole estimate
// for u: over pt every NEE and MIS-weighted emission term of one path; over bdpt every
// MIS-weighted strategy (s, t) of one camera and one light subpath, light tracing's (t = 1)
// landing on other pixels than the camera sample's, so that a state is a list of splats. Small steps add a wrapped Gaussian offset of
// --sigma to every coordinate, large steps (probability --large-step) draw them anew; both are
// symmetric, so a = min(1, F(y) / F(x)) (shaders/methods/pssmlt/).
//
// A bootstrap of --bootstrap uniform samples per pixel estimates b = the image's total luminance
// and starts the chains at samples drawn in proportion to their weight (Veach 1997 sec. 11.3.1:
// no start-up bias; host/methods/metropolis/bootstrap.h). One pass is about one mutation per
// pixel: steps = max(1, round(pixels / chains)) per chain, each depositing by expected values
// a e_d at the proposal and (1 - a) e_d at the current path, e_d = b / (chains steps), so each
// pass is an unbiased image and --spp N averages N passes (host/methods/energy_redistribution:
// SplatFilm, RedistributionBatch). Under --time alone passes may be shorter (PssmltOptions::
// timedStepsPerPass); each is still an unbiased image, and the spp reported counts mutations
// per pixel.
//
// Options and their defaults are listed in pssmltMethod() (pssmlt_integrator.cpp).
#pragma once

#include "render/integrator.h"
#include "render/method_info.h"

namespace pmcr {

struct PssmltOptions {
    bool overBdpt = true;                // --over bdpt (default) or pt: the estimator of a sample
    uint32_t bootstrapSpp = 4;           // bootstrap samples per pixel; 0: automatic (mmlt)
    uint32_t chains = 0;                 // 0: min(pixels, defaultChains(device))
    float largeStepProbability = 0.3f;   // Kelemen et al. 2002 sec. 4: p_large
    float sigma = 0.01f;                 // small step: wrapped Gaussian (pbrt-v3 MLTSampler)
    uint32_t stepsPerDispatch = 4;
    uint32_t passesPerBatch = 0;         // passes in one submission (0: from the device)

    static constexpr uint32_t kMaxChains = 1u << 20;
    // Chains when --chains is 0 (at most one per pixel). On lavapipe fewer, longer chains run
    // faster: the primary-sample storage of 16384 chains (32 MiB at depth 16) overflows the
    // caches, and a mutation took 5.8 us there against 4.2 us with 4096 (cornell-glass 160x120);
    // a GPU needs many more invocations in flight.
    static uint32_t defaultChains(bool cpuDevice) { return cpuDevice ? 4096u : 65536u; }
    // Passes in one submission when --passes-per-batch is 0: 1 on a CPU device (lavapipe's
    // dispatches are sized by time instead); on a GPU enough for 2^20 mutations (issue 38: a
    // pass of one mutation per pixel lasts about a millisecond there, and the device would wait
    // for the host between passes), at most 64.
    static uint32_t defaultPassesPerBatch(bool cpuDevice, uint64_t mutationsPerPass);

    // The options as pssmlt and mmlt take them (`method` names the method in the errors);
    // --bootstrap defaults to defaultBootstrap, and takes 0 (automatic) only where that is 0.
    static PssmltOptions fromSettings(const RenderSettings& settings, const char* method = "pssmlt",
                                      uint32_t defaultBootstrap = 4);
    // mmlt's --bootstrap 0: kAutoBootstrapPerDepth samples of each depth on average, whatever
    // the image's size (pbrt-v4 counts them per depth too); N > 0: N per pixel of each depth.
    // They are allocated to the depths by a pilot (renderChainsOverBdpt).
    static constexpr uint32_t kAutoBootstrapPerDepth = 16384;
    uint64_t bootstrapPerDepth(uint32_t pixels) const;

    // --time without --spp (issue 38: the pre-passes inside the budget). The bootstrap stops at
    // a submission's end once the clock has passed kBootstrapShareOfTime of the budget (b_hat is
    // then the mean of fewer samples, their count set by the clock, not by their values), and a
    // pass is cut to the steps that take about kPassShareOfTime of the budget at the bootstrap's
    // rate, at least one (over bdpt on lavapipe a 256x256 bootstrap of 4 spp took 8.7 s and a
    // pass of one mutation per pixel 2.6 s: `--time 2` had returned after 8.9 s). mmlt's
    // bootstrap, split over the depths, does not stop early: its size is set from its pilot's
    // rate to end at the same share.
    static constexpr double kBootstrapShareOfTime = 0.2;
    static constexpr double kPassShareOfTime = 0.1;
    static bool timeBudgeted(const RenderSettings& settings);
    // Under timeBudgeted, whether the bootstrap stops now: some samples taken, and the clock
    // past its share of the budget.
    static bool bootstrapTimeUp(const RenderSession& session, uint64_t taken);
    // Steps per pass under timeBudgeted: `steps` (one mutation per pixel) or fewer.
    static uint32_t timedStepsPerPass(uint32_t steps, uint32_t chains, double samplesPerSecond, double timeLimit);
};

class Pssmlt : public Integrator {
public:
    explicit Pssmlt(const RenderSettings& settings);
    RenderOutput render(RenderSession& session) override;

    static constexpr uint32_t kDefaultSpp = 64;
    uint32_t defaultSpp() const override { return kDefaultSpp; }

private:
    RenderOutput renderOverPt(RenderSession& session);

    PssmltOptions m_options;
};

// The chains over bdpt samples, of pssmlt --over bdpt or, `multiplexed`, of mmlt
// (host/methods/mmlt): the bootstrap, the chains' starts, the passes of three dispatches a
// step (shaders/methods/pssmlt/pssmlt_bdpt_*, shaders/methods/mmlt/), the image and the stats.
RenderOutput renderChainsOverBdpt(RenderSession& session, const PssmltOptions& options, bool multiplexed);

// The registry entry of `pssmlt` (render/methods.cpp).
MethodInfo pssmltMethod();

}  // namespace pmcr
