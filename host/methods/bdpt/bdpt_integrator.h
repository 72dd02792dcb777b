// Bidirectional path tracing (`bdpt`; Veach and Guibas 1995, Veach 1997 ch. 10, as pbrt-v4's
// BDPTIntegrator): progressive passes of one camera sample per pixel. Each dispatch of a pass
// covers a range of pixels with two kernels (shaders/methods/bdpt/): the first traces each
// sample's camera and light subpaths into vertex buffers, the second evaluates every connection
// strategy with its MIS weight, adding the camera-side strategies to the sample's pixel and
// splatting light tracing's (t = 1) as fixed-point sums, so that a seed gives the same image
// bit for bit. The splats are divided by the light subpaths traced per pixel.
#pragma once

#include "render/baseline_options.h"
#include "render/integrator.h"
#include "render/method_info.h"

namespace pmcr {

class BdptIntegrator : public Integrator {
public:
    explicit BdptIntegrator(const RenderSettings& settings);
    RenderOutput render(RenderSession& session) override;

    static constexpr uint32_t kDefaultSpp = 16;
    uint32_t defaultSpp() const override { return kDefaultSpp; }

private:
    BaselineOptions m_baseline;  // --mis (power or balance heuristic), --pixel-sampler
    bool m_strategyImages;       // --strategy-images: the (s, t) images as diagnostics
};

// The registry entry (render/methods.cpp) of `bdpt`.
MethodInfo bdptMethod();

}  // namespace pmcr
