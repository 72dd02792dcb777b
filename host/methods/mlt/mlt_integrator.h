// Metropolis light transport (Veach and Guibas 1997) over pmcr's path space, the baseline the
// ERPT paper compares against with "the functions that mutate paths shared between MLT and
// ERPT" (Cline et al. 2005 sec. 5). A bootstrap of independent paths estimates the normalisation
// b and starts the chains in proportion to their weights (host/methods/metropolis/bootstrap.h);
// each chain then mutates its path by ERPT's lens and caustic perturbations or, with probability
// --large-step, by an independent mutation (a fresh path, shaders/methods/mlt/independent_path.glsl)
// that makes the chains ergodic. Deposits are expected values, e_d = b_hat / (mutations per pass).
//
// --spp N runs N passes of about one mutation per pixel each; the chains carry on from pass to
// pass, and each pass's deposits are an unbiased image (E[b_hat h(x_t)] = integral of F h for
// chains started by resampling, Veach 1997 sec. 11.3.1), so the image is their average.
#pragma once

#include "methods/energy_redistribution/redistribution.h"
#include "render/integrator.h"
#include "render/method_info.h"

namespace pmcr {

struct MltOptions {
    uint32_t bootstrapSpp = 4;        // bootstrap samples per pixel
    uint32_t chains = 0;              // 0: pixels / 16, within [1024, 65536]
    float largeStep = 0.25f;          // probability of the independent mutation
    PerturbationOptions perturbation;  // ERPT's, with its defaults
    uint32_t stepsPerDispatch = 4;
    uint32_t passesPerBatch = 0;      // passes in one submission (0: 1 on a CPU device; on a GPU
                                      // enough for 2^20 chain steps, at most 64: issue 38)
    // Paths with at most one scattering vertex (the emitter seen directly, direct light at x1)
    // by path tracing at depth 1, one sample per pixel per pass, not by the chains (Veach 1997
    // sec. 11.5: direct lighting by standard techniques; ERPT's --redistribute indirect).
    bool separateDirect = true;

    static MltOptions fromSettings(const RenderSettings& settings);
};

class Mlt : public Integrator {
public:
    explicit Mlt(const RenderSettings& settings);
    RenderOutput render(RenderSession& session) override;

    static constexpr uint32_t kDefaultSpp = 16;
    uint32_t defaultSpp() const override { return kDefaultSpp; }

private:
    MltOptions m_options;
};

// The registry entry of `mlt` (render/methods.cpp).
MethodInfo mltMethod();

}  // namespace pmcr
