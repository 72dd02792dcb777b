// Multiplexed Metropolis light transport (Hachisuka, Kaplanyan and Dachsbacher 2014), as
// pbrt-v4's MLTIntegrator: primary-sample-space chains (Kelemen et al. 2002) over bidirectional
// path tracing in which each chain has a path depth d, fixed at its start, and each proposal
// also picks which one of the d + 2 connection strategies (s, t) it evaluates: a camera subpath
// of t vertices, a light subpath of s, the one connection, its MIS weight times d + 2. The
// Metropolis steps then favour the strategies whose weighted contribution is large, the
// multiplexing of the paper. A bootstrap stratified by depth, 16384 samples of each depth on
// average (or --bootstrap N per pixel of each depth), allocated to the depths by a pilot,
// estimates b (the sum over depths of each depth's mean) and starts the chains, the depth with
// the sample (shared/pssmlt_types.h; the chains, passes and deposits are pssmlt's over bdpt,
// host/methods/pssmlt: renderChainsOverBdpt).
#pragma once

#include "methods/pssmlt/pssmlt_integrator.h"

namespace pmcr {

class Mmlt : public Integrator {
public:
    explicit Mmlt(const RenderSettings& settings);
    RenderOutput render(RenderSession& session) override;

    static constexpr uint32_t kDefaultSpp = 64;
    // --bootstrap 0: 16384 samples of each depth on average, whatever the image's size
    // (PssmltOptions::bootstrapPerDepth). With one per pixel, a small image's chains started at
    // a handful of non-zero samples of the depth that carries the light (tests/stat: BLEND card,
    // 22 of 96 at depth 1), and renders of few passes varied too much for the z-tests. With 4096
    // of each depth, evenly, room's (160x90, 16 bounces) 4096 chains started at about 1800
    // distinct samples, up to 15 at one, and one render in three had a bright pixel that
    // doubled its error (docs/methods/mmlt.md).
    static constexpr uint32_t kDefaultBootstrap = 0;
    uint32_t defaultSpp() const override { return kDefaultSpp; }

private:
    PssmltOptions m_options;
};

// The registry entry of `mmlt` (render/methods.cpp).
MethodInfo mmltMethod();

}  // namespace pmcr
