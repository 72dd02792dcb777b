#include "methods/mmlt/mmlt_integrator.h"

#include <memory>

namespace pmcr {

Mmlt::Mmlt(const RenderSettings& settings)
    : m_options(PssmltOptions::fromSettings(settings, "mmlt", kDefaultBootstrap)) {}

RenderOutput Mmlt::render(RenderSession& session) { return renderChainsOverBdpt(session, m_options, true); }

MethodInfo mmltMethod() {
    return {"mmlt",
            "multiplexed MLT (Hachisuka et al. 2014, as pbrt-v4's mlt): primary-sample-space chains of a fixed "
            "path depth over bdpt, each step one connection strategy picked by the chain",
            true,
            {{"bootstrap", "0",
               "samples per pixel of each depth, on average, estimating b and starting the chains (0: 16384 of "
               "each depth in all); a pilot of 512 of each depth gives the depths their shares"},
             {"chains", "0", "chains in parallel (0: one per pixel, at most 4096 on a CPU device, 65536 on a GPU)"},
             {"large-step", "0.3", "probability of a large step (every random number drawn anew)"},
             {"sigma", "0.01", "small step: standard deviation of the wrapped Gaussian offset"},
             {"steps-per-dispatch", "4", "mutations per chain per submission"},
             {"passes-per-batch", "0", "passes whose steps run in one submission (0: 1 on a CPU device, enough to fill a GPU)"}},
            [](const RenderSettings& s) { return std::make_unique<Mmlt>(s); }, ""};
}

}  // namespace pmcr
