// Population Monte Carlo path tracing (Lai, Fan, Chenney and Dyer, "PMC Path Tracing", sec. 4):
// a population of pixels, each member mutating TR times per resample step into the pixels of
// disks of radius 5, 10 or 50 pixels chosen by its adapted weights alpha (eq. 4), every sample
// estimated with the full path tracer (the `pt` kernel, PT_SOURCE_LIST), then elimination
// ∝ sigma^2 / N_used and regeneration from a stratified pool and from pixels drawn
// ∝ sigma^2 / tvi (sec. 4.3). The population lives on the host (render/pixel_population.h); the
// GPU only path traces the samples it is given, and the host reduces the results in a fixed
// order, so a seed gives the same image bit for bit.
//
// The kernel is discrete (a departure from the paper's continuous disks): a mutation picks a
// pixel of the member's pixel disk, and where inside the pixel comes from the pixel's own
// stratified sequence. In step t pixel p gets poolSpp pool samples plus the members' mutations
// that landed there, n_p in all, and they are points 0 .. n_p - 1 of p's (0,2)-sequence with a
// scramble of the step's own: a stratified set, as path tracing's samples are. That is what
// makes PMC-PT competitive at all: with independent positions and random numbers per sample it
// had the error of unstratified sampling, 22% above pt's perceptual error on cornell-glass
// 128x128 at 64 eye paths (1.57e-3 Err against pt's 1.00e-3; pt's own renders merged from 64
// independent 1-spp renders: 1.49e-3).
//
// The estimator. The paper averages the samples that land in each pixel and calls that
// unbiased. It is not, in general: where the samples go depends on earlier radiance values
// (beta, elimination, alpha), so a pixel's sample count is correlated with its values (measured
// below). The default here is the D-kernel PMC estimator (the paper's eq. 1; Douc, Guillin,
// Marin and Robert 2007) in its deterministic-mixture form over pixels. Given the past, step t's
// expected number of samples in pixel p is
//     Q_p = poolSpp + sum_i sum_k TR alpha_ik 1[p in pixel disk k of member i] / |disk_ik|,
// and given n_p the samples are uniform over the pixel (each point of a scrambled sequence is),
// so with c fixed before the step
//     I_t(p) = c + sum over the step's samples x in p of (L(x) - c) / Q_p
// has E[I_t | past] = c + E[n_p | past] (I_p - c) / Q_p = I_p, the pixel value, as long as
// Q_p > 0: hence the pool samples in every pixel of every step (`--defensive` share), which also
// bound the weights 1 / Q_p by 1 / poolSpp. c is a control variate, the plain average of the
// pixel's earlier samples: without it the estimate would swing with the number of samples the
// pixel happens to get. For c to be real samples from the start, the first step is the pool's
// alone, the size of the others (every pixel the same count, where I_t is the plain average).
// The image averages the steps with equal weights. "Given the past" also needs each step's
// random numbers to be independent of the earlier steps', hence the fresh scramble per step.
//
// Measured (tests/stat/test_pmc_pt.cpp, DISABLED_MeasurePlainAverageBias, with the continuous
// kernel of the first version: cornell-glass 24x24, 100 renders of 16 eye paths per pixel
// against 32 pt renders of 256, adapting every 2 steps, --defensive 0.1): the weighted estimator
// passes the per-pixel z-test on 100% of pixels (sum of z^2 780 over 576 pixels; pt itself, the
// control, 853: heavy tails inflate it), the plain average `--estimator average` on 99.13% (5
// pixels fail; sum of z^2 1142), below the 99.75% an unbiased method passes. So the paper's
// average is biased and labelled so; the weighted estimator is the default.
//
// Other departures from the paper, each so that the step's counts are known and positive: a
// step's TR mutations of a member all start from the member's pixel (members move by
// resampling), their radii are chosen systematically (about TR alpha_k each), the pool samples
// are an addition, and the steps are larger (pool 4 spp plus as many member samples: about 30
// times the paper's 5000 x 16 eye paths at 640x480), so alpha and beta adapt after every step.
#pragma once

#include "render/integrator.h"
#include "render/pixel_population.h"

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
