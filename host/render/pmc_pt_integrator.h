// Population Monte Carlo path tracing (Lai, Fan, Chenney and Dyer, "PMC Path Tracing", sec. 4):
// a population of pixel positions, each member mutating TR times per resample step in disks of
// radius 5, 10 or 50 pixels chosen by its adapted weights alpha (eq. 4), every mutation's
// position estimated with the full path tracer (the `pt` kernel, PT_SOURCE_POINTS), then
// elimination ∝ sigma^2 / N_used and regeneration from a stratified pool and from pixels drawn
// ∝ sigma^2 / tvi (sec. 4.3). The population lives on the host (render/pixel_population.h); the
// GPU only path traces the positions it is given, and the host reduces the results in a fixed
// order, so a seed gives the same image bit for bit.
//
// The estimator. The paper averages the samples that land in each pixel (its eq. 3 with the
// sample density dropped) and calls that unbiased. It is not, in general: (a) inside a pixel the
// positions are not uniform (disks cut by pixel edges, members clustered near edges and
// caustics), so the average estimates ∫L p / ∫p over the pixel, not ∫L; (b) where the positions
// go depends on earlier radiance values (beta, elimination, alpha), so a pixel's sample count is
// correlated with its values. The default here is the D-kernel PMC estimator (the paper's eq. 1;
// Douc, Guillin, Marin and Robert 2007) in its deterministic-mixture form. In step t every
// position x_j is drawn from a density q_j known given the past: a member's mutation from its
// disk mixture (eq. 4) restricted to the image, a pool position uniformly over the image. With
// Q_t = sum_j q_j, each pixel's
//     I_t = c + sum over the step's x_j in the pixel of (L(x_j) - c) / Q_t(x_j)
// has E[I_t | past] = c + sum_j ∫_pixel (L - c) q_j / Q_t = ∫_pixel L, the pixel value (pixel
// area 1), for any c fixed before the step, as long as Q_t > 0 on the whole image: hence a
// defensive share of every step's draws from the pool (`--defensive`), which also bounds the
// weights 1/Q_t by w h / D. c is a control variate: without it (c = 0) the estimate fluctuates
// with the number of samples the pixel happens to get (E[sum 1/Q_t] = 1 is all that is known).
// c = the plain average of the pixel's earlier samples (the image's while it has none) is known
// before the step, so any bias of that average stays out of the image; it settles after a sample
// or two where the pixel is uniform (a light seen directly), which the running D-kernel estimate
// does not (Err on cornell-glass 128x128, 64 eye paths per pixel: 2.1e-3 with it, 1.6e-3 with
// the plain average). The steps are averaged with deterministic weights min(t, 8) (the first
// steps' c are rough), which depend only on the number of steps, so the image stays unbiased.
// "Given the past" also needs each path's random numbers to be independent of the earlier
// paths', so every path has a sampler sequence of its own.
//
// Measured (tests/stat/test_pmc_pt.cpp, DISABLED_MeasurePlainAverageBias: cornell-glass 24x24,
// 100 renders of 16 eye paths per pixel against 32 pt renders of 256, adapting every 2 steps,
// --defensive 0.1):
// the weighted estimator passes the per-pixel z-test on 100% of pixels (sum of z^2 780 over 576
// pixels; pt itself, the control, 853: heavy tails inflate it), the plain average `--estimator
// average` on 99.13% (5 pixels fail; sum of z^2 1142), below the 99.75% an unbiased method
// passes. So the paper's average is biased and labelled so; the weighted estimator is the default.
//
// Departures from the paper, each so that the step's density is known and positive: a step's TR
// mutations of a member all start from the member's position (members move by resampling), a
// disk draw outside the image is redrawn inside it (so every eye path counts), the defensive
// pool draws are an addition, and the pool positions that regenerate members are ones the step
// just path traced (a position must not be both a member for step t and a draw of step t). The
// paper's alpha weights, which sum to 1 + (K-1) eps, are normalised.
#pragma once

#include "render/integrator.h"
#include "render/pixel_population.h"

namespace pmcr {

struct PmcPtOptions {
    uint32_t population = 0;        // 0: the paper's density, 5000 members per 640x480 pixels
    uint32_t mutations = 16;        // TR
    std::vector<double> radii = {5.0, 10.0, 50.0};
    uint32_t adaptEvery = 100;      // resample steps between alpha and beta updates (paper 100-200)
    double resampleRate = 0.4;
    double epsilon = 0.01;
    double defensive = 0.5;         // share of a step's eye paths drawn from the pool
    bool plainAverage = false;      // --estimator average: the paper's per-pixel average (biased)

    static PmcPtOptions fromSettings(const RenderSettings& settings);
    // Members for an image of `pixels` pixels.
    uint32_t populationFor(uint64_t pixels) const;
};

class PmcPt : public Integrator {
public:
    explicit PmcPt(const RenderSettings& settings);
    RenderOutput render(RenderSession& session) override;

    static constexpr uint32_t kDefaultSpp = 64;

private:
    PmcPtOptions m_options;
};

}  // namespace pmcr
