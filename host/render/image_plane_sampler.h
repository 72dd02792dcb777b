// PMC-IP's adaptive image-plane sampler (Fan, Lai, Chenney and Dyer, "Population Monte Carlo
// Samplers for Rendering", sec. 4), as a reusable component: it decides how many camera samples
// each pixel gets in the next iteration and turns the samples it receives into the pixel
// estimates. It knows nothing of Vulkan; the integrator that uses it (PMC-IP over `pt` or
// `direct`, later PMC-HI's feedback loop) traces the samples it asks for.
//
// One iteration t:
//   1. allocate(): the mixture weights alpha_ij (sec. 4.2) from the perceptually weighted
//      variance of every sample so far, then deterministic mixture sampling (sec. 4.3) gives
//      each pixel floor(n'_ij) or floor(n'_ij) + 1 samples, n'_ij = N alpha_ij;
//   2. the caller traces the samples, pixel by pixel, each pixel's samples drawn uniformly over
//      the pixel from a sequence scrambled afresh for the iteration, and hands each result to
//      addSample();
//   3. finishIteration() folds the iteration's per-pixel estimate into the image.
//
// The estimator (why the image is unbiased). The paper's eq. 3 with the D-kernel density
// p(x) = alpha_ij inside pixel (i,j) (unit pixel area) gives, for one iteration, the pixel
// estimate (1/N) sum_{k in pixel} L(X_k) / alpha_ij = S_ij / m_ij with m_ij = N alpha_ij, the
// pixel's expected sample count. Given everything before iteration t (which fixes alpha and so
// m), each of the iteration's samples is uniform over its pixel and independent of the past
// (a fresh scramble per iteration), so E[S_ij | n_ij, past] = n_ij I_ij, where I_ij is the
// pixel integral. Hence the per-iteration estimate M_t = S/n (used where DMS guarantees n >= 1)
// and M_t = S/m (the eq. 3 form, used where n may be 0) both have conditional expectation I_ij.
// The image is sum_t c_t M_t with weights c_t fixed in advance (proportional to each
// iteration's sample budget, i.e. the paper's "unweighted average of the sub-images" when the
// budgets are equal, sec. 4.4), so by the tower rule E[image] = I_ij.
//
// Deviation from the paper, on purpose: the plain average of all samples a pixel received
// across iterations (sum of all samples / their count) is biased, because later counts depend on
// earlier samples: a pixel whose first samples happened to be dark looks smooth, gets few samples
// and keeps its dark average, while one that caught a rare bright path gets many and dilutes
// it, so rare bright paths (caustics) are darkened on average. The per-iteration form above has
// no such correlation. It needs every pixel to get a sample in every iteration (or the noisier
// S/m form where it may not), so `minSamples` (default 1) samples per pixel are set aside
// before the alpha-weighted allocation: the effective mixture weight of each pixel is still at
// least epsilon / pixels.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "image/image.h"

namespace pmcr {

// alpha_ij = epsilon / P + (1 - epsilon) alpha'_ij / sum alpha' (PMC-IP sec. 4.2), P = number of
// pixels, so that the weights sum to 1 and each is at least epsilon / P (the paper's defensive
// term, Hesterberg 1995). All-zero alpha' gives the uniform mixture.
std::vector<double> pmcIpMixtureWeights(const std::vector<double>& alphaPrime, double epsilon);

// Deterministic mixture sampling (PMC-IP sec. 4.3, Hesterberg 1995): `total` samples over the
// components: `minPerComponent` each first, then n'_k = (total - minPerComponent K) alpha_k;
// component k gets floor(n'_k) plus one more with probability n'_k - floor(n'_k), the leftover
// samples drawn from the fractions in one systematic (stratified) pass with offset u in [0,1).
// The counts always sum to `total` exactly. Requires total >= minPerComponent * K.
std::vector<uint32_t> dmsAllocate(const std::vector<double>& alpha, uint64_t total,
                                  uint32_t minPerComponent, double u);
// The expected count of each component under dmsAllocate (n'_k + minPerComponent).
std::vector<double> dmsExpectedCounts(const std::vector<double>& alpha, uint64_t total,
                                      uint32_t minPerComponent);

struct ImagePlaneOptions {
    double samplesPerIteration = 4.0;  // N / P: average samples per pixel per iteration
    uint32_t initialSpp = 4;           // the first iteration, uniform
    double epsilon = 0.01;             // the defensive weight of the uniform component
    uint32_t minSamples = 1;           // samples every pixel gets in every adaptive iteration
    double displayWhite = 100.0;       // cd/m^2 that pixel luminance 1 stands for (tvi)
};

class ImagePlaneSampler {
public:
    ImagePlaneSampler(int width, int height, const ImagePlaneOptions& options);

    int width() const { return m_width; }
    int height() const { return m_height; }
    uint32_t pixelCount() const { return uint32_t(m_estimateSum.size()); }
    uint32_t iteration() const { return m_iteration; }

    // The sample counts of the next iteration: uniform `initialSpp` for the first, then
    // adaptive; `u` in [0,1) drives the residual pass. Starts the iteration.
    const std::vector<uint32_t>& allocate(double u);
    // One sample's radiance for `pixel` in the current iteration (NaN samples already zeroed).
    void addSample(uint32_t pixel, const glm::vec3& radiance);
    // Ends the current iteration: pixels that received all their allocated samples fold their
    // estimate into the image with weight = the iteration's budget; the others (a render
    // stopped mid-iteration) skip this iteration, which depends on time only, not on values.
    void finishIteration();

    uint64_t samplesTaken() const { return m_samplesTaken; }
    // alpha'_ij = sigma-bar^2_ij / tvi(L_ij): the variance of the pixel's estimate (sample
    // variance of its samples' luminance over their count) over the threshold at its luminance.
    std::vector<double> perceptualVariance() const;
    // alpha of the last adaptive iteration (uniform before the first).
    const std::vector<double>& alpha() const { return m_alpha; }

    Image image() const;          // the pixel estimates
    Image alphaImage() const;     // alpha * P (1 = the uniform share)
    Image sampleCountImage() const;
    Image varianceImage() const;  // estimated variance of each pixel estimate (luminance)

private:
    int m_width;
    int m_height;
    ImagePlaneOptions m_options;
    uint32_t m_iteration = 0;
    uint64_t m_samplesTaken = 0;
    double m_iterationBudget = 0.0;  // the current iteration's average spp (its weight c_t)
    std::vector<uint32_t> m_allocated;
    std::vector<double> m_expected;  // m_ij of the current iteration
    std::vector<double> m_alpha;
    // Current iteration: per pixel sums of radiance, and the count received.
    std::vector<glm::dvec3> m_iterSum;
    std::vector<uint32_t> m_iterCount;
    // All iterations: weighted sum of per-iteration estimates, sum of weights, sum of
    // weight^2 / n (for the variance image), and luminance moments of every sample.
    std::vector<glm::dvec3> m_estimateSum;
    std::vector<double> m_weightSum;
    std::vector<double> m_weightSqOverN;
    std::vector<double> m_lumSum;
    std::vector<double> m_lumSqSum;
    std::vector<uint32_t> m_count;
};

}  // namespace pmcr
