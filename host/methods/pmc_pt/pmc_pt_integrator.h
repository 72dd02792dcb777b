// Population Monte Carlo path tracing (Lai, Fan, Chenney and Dyer, "PMC Path Tracing", sec. 4):
// a population of pixels, each member mutating TR times per resample step into the pixels of
// disks of radius 5, 10 or 50 pixels chosen by its adapted weights alpha (eq. 4), every sample
// estimated with the full path tracer (the `pt` kernel, PT_SOURCE_LIST), then elimination
// ∝ sigma^2 / N_used and regeneration from a stratified pool and from pixels drawn
// ∝ sigma^2 / tvi (sec. 4.3). The population lives on the host (methods/pmc_pt/pixel_population.h);
// the GPU only path traces the samples it is given, and the host reduces the results in a fixed
// order, so a seed gives the same image bit for bit.
//
// The kernel is discrete (a departure from the paper's continuous disks): a mutation picks a
// pixel of the member's pixel disk, and where inside the pixel comes from the pixel's own
// stratified sequence. In step t pixel p gets poolSpp pool samples plus the members' mutations
// that landed there, n_p in all, and they are points 0 .. n_p - 1 of p's (0,2)-sequence with a
// scramble of the step's own: a stratified set, as path tracing's samples are (render seeds
// and step seeds come from one PCG generator per render). That is what
// makes PMC-PT competitive at all: with independent positions and random numbers per sample it
// had the error of unstratified sampling, 22% above pt's perceptual error on cornell-glass
// 128x128 at 64 eye paths (1.57e-3 Err against pt's 1.00e-3; pt's own renders merged from 64
// independent 1-spp renders: 1.49e-3).
//
// The estimator. The paper averages all the samples that land in each pixel and calls that
// unbiased. It is not, in general: where the samples go depends on earlier radiance values
// (beta, elimination, alpha), so how many samples a pixel gets in later steps is correlated with
// the values of its earlier ones (measured below). Within one step there is no such problem:
// which pixels the step's n_p samples go to is decided before any of them is traced (by the past
// and the host's random numbers), and given n_p they are points of a freshly scrambled sequence,
// each uniform over the pixel. So the step's plain average I_t(p) = (1/n_p) sum L(x_i) has
// E[I_t(p) | past] = I_p, the pixel value (n_p >= poolSpp >= 1: the pool samples keep every
// pixel covered), and the image is the average of the steps' I_t weighted by the steps' sizes
// m_t (in units of the first step), which depend only on a schedule fixed in advance: unbiased.
// (With --time the last step's size and the number of steps come from the clock, as pt's last
// pass does.) It gives up the paper's weighting of samples by per-pixel counts, which costs
// little where the counts vary slowly from step to step, and the stratification between steps:
// each step is one stratified set per pixel, the steps are independent. That loss grows with
// the number of steps, so the steps grow: m_t = round(G^t) (--step-growth, 1.5), small at first
// so that the population adapts soon, large later so that most samples are in a few sets.
// "Given the past" also needs each step's random numbers to be independent of the earlier
// steps', hence the fresh scramble per step. (A first version weighted each sample by the
// inverse of its expected count, the D-kernel estimator of the paper's eq. 1, with a control
// variate; it had the same error on cornell-glass and cornell-specular, but the control variate
// carried rare very bright paths from step to step, and room came out worse.)
//
// Measured (tests/stat/test_pmc_pt.cpp, DISABLED_MeasurePlainAverageBias: cornell-glass 24x24,
// 100 renders of 16 eye paths per pixel against 32 pt renders of 256, adapting every 2 steps,
// --defensive 0.1). With the first version's continuous disks and independent samples, the
// unbiased estimator passed the per-pixel z-test on 100% of pixels (sum of z^2 780 over 576
// pixels; pt itself, the control, 853: heavy tails inflate it) and the paper's plain average
// `--estimator average` on 99.13% (5 pixels fail; sum of z^2 1142), below the 99.75% an unbiased
// method passes. With the kernel here both pass on 100% (sums of z^2 756 for the step average,
// 757 for the plain average): the stratified steps leave the counts too little room to show the
// bias at this power. The argument above still holds, so the plain average stays labelled biased
// and is not the default.
//
// What image-plane adaptation can gain here (bench/image-plane-ceiling: an allocation
// n ∝ sqrt(s^2 / tvi) learned from 4 independent 64-spp pt renders, neighbourhood-averaged, judged
// on 4 others at equal samples): x1.27 in P-Err on cornell-glass 128x128 and x1.10 on
// cornell-specular, against pmcr's path tracer, whose samples are stratified in every dimension;
// most of their error is rare bright paths, which no allocation predicts. (MIS direct lighting on
// dragon-direct 160x80: x3.4.) PMC-PT pays for its adaptation with steps of a few samples per
// pixel instead of one stratified set (pt's own renders, 8 merged renders of 8 spp against one
// of 64: P-Err +2% on cornell-glass, +3% on cornell-specular; more at more steps), so on
// cornell-specular it can at best break even.
//
// Other departures from the paper, each so that the step's counts do not depend on its values
// and are positive: a step's TR mutations of a member all start from the member's pixel (members move by
// resampling), their radii are chosen systematically (about TR alpha_k each), the pool samples
// are an addition, and the steps are larger (the first: pool 4 spp plus as many member samples,
// about 30 times the paper's 5000 x 16 eye paths at 640x480; later ones m_t times that, with
// m_t TR mutations per member), so alpha and beta adapt after every step. With --time a render
// ends at the step boundary nearest the limit (the last step sized to fit): a step cut by the
// limit would be dropped whole, its time spent for nothing.
#pragma once

#include "methods/pmc_pt/pixel_population.h"
#include "render/baseline_options.h"
#include "render/integrator.h"
#include "render/method_info.h"

namespace pmcr {

struct PmcPtOptions {
    uint32_t population = 0;        // 0: as many as make `defensive` of a step's draws the pool's
    uint32_t mutations = 16;        // TR
    std::vector<double> radii = {5.0, 10.0, 50.0};
    uint32_t poolSpp = 4;           // pool draws in every pixel per step (stratified together)
    uint32_t adaptEvery = 1;        // resample steps between alpha and beta updates
    double resampleRate = 0.4;
    double epsilon = 0.01;
    double defensive = 0.5;         // share of a step's eye paths drawn from the pool (sets
                                    // the population unless --population is given)
    double stepGrowth = 1.5;        // step t is m_t = round(G^t) units (first steps), m_t TR
                                    // mutations per member and m_t poolSpp per pixel
    bool plainAverage = false;      // --estimator average: the paper's per-pixel average (biased)
                                    // instead of the average of step averages

    static PmcPtOptions fromSettings(const RenderSettings& settings);
    // Members for an image of `pixels` pixels.
    uint32_t populationFor(uint64_t pixels) const;
};

class PmcPt : public Integrator {
public:
    explicit PmcPt(const RenderSettings& settings);
    RenderOutput render(RenderSession& session) override;

    static constexpr uint32_t kDefaultSpp = 64;
    uint32_t defaultSpp() const override { return kDefaultSpp; }

private:
    PmcPtOptions m_options;
    BaselineOptions m_baseline;  // --pixel-sampler (where in its pixel a sample lands), --mis
};

// The registry entry of `pmc-pt` (render/methods.cpp).
MethodInfo pmcPtMethod();

}  // namespace pmcr
