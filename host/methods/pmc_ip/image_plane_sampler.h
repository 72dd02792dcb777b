// PMC-IP's adaptive image-plane sampler (Fan, Lai, Chenney and Dyer, "Population Monte Carlo
// Samplers for Rendering", sec. 4), as a reusable component: it decides how many camera samples
// each pixel gets in the next iteration and turns the samples it receives into the pixel
// estimates. It knows nothing of Vulkan; the integrator that uses it (PMC-IP over `pt` or
// `direct`, later PMC-HI's feedback loop) traces the samples it asks for.
//
// One iteration t:
//   1. allocate(): each pixel's expected sample count from the mixture weights alpha_ij
//      (sec. 4.2), then deterministic mixture sampling (sec. 4.3): floor(n'_ij) samples, plus one
//      more with probability n'_ij - floor(n'_ij), drawn in one systematic (stratified) pass;
//   2. the caller traces the samples, pixel by pixel, and hands each result to addSample(); a
//      pixel's samples are the next points of its one stratified sequence (sequenceStart() is
//      the first), so that all the samples a pixel gets over the render are one stratified set,
//      as a path tracer's are; a pixel's first `minSamples` samples of an iteration (all of the
//      first iteration's) are its pilot samples;
//   3. finishIteration().
// The image is the average of all the samples each pixel received (the paper's estimator).
//
// Why that average is unbiased here, and where pmcr departs from the paper to make it so. The
// plain average S_ij / n_ij is unbiased when the count n_ij is independent of the pixel's own
// sample values: given the counts, the samples are uniform over the pixel (eq. 3 with the
// D-kernel density, sec. 4.1) and their mean has expectation I_ij. That holds for the points of
// one Owen-scrambled sequence too (each point alone is uniform over the pixel), so a pixel's
// samples continue its sequence from one iteration to the next instead of starting a freshly
// scrambled set each time: the stratification of pmcr's path tracer is kept across iterations
// (splitting 40 samples into five independently scrambled sets of 8 cost PMC-IP 20-25% of its
// P-Err on dragon-direct). The paper's criterion
// alpha'_ij = sigma-bar^2_ij / tvi(L_ij) breaks this: a pixel whose first samples happened to be
// dark looks smooth, gets few samples and keeps its dark average, while one that caught a rare
// bright path gets many and dilutes it, so rare bright paths (caustics) come out too dark on
// average (tests/host/test_image_plane_sampler.cpp measures it). pmcr therefore computes a
// pixel's weight from its neighbours only, and only from their pilot samples, whose counts are
// fixed in advance:
//   v_kl       = s^2_kl / tvi(L_kl)   pilot sample variance of pixel kl over the threshold at its
//                                     pilot mean luminance (Ferwerda et al. 1996),
//   alpha'_ij  = sqrt(mean of v_kl over the neighbours kl of ij within `radius`, ij excluded),
//   alpha_ij   = epsilon / P + (1 - epsilon) alpha'_ij / Z_-ij,
// with Z_-ij the sum of all alpha' computed as if pixel ij had no pilot data (v_ij = 0), so that
// neither the weight nor its normalisation depends on pixel ij's samples. The residual pass's
// draws are Bernoulli(fraction) for each pixel whatever the other fractions, so n_ij's law
// depends on other pixels' data only, and E[S_ij / n_ij] = I_ij exactly. The square root makes
// the allocation n ~ sigma / sqrt(tvi), the one that minimises the expected perceptual error
// sum sigma^2 / (n tvi) for a fixed budget (a Lagrange multiplier argument); the paper's
// sigma-bar^2 = sigma^2 / n reaches the same end by iterating, which needs each pixel's own count.
// Variance is spatially coherent (edges, caustics and soft shadows span several pixels), so the
// neighbours predict it well; an isolated noisy pixel gets its neighbours' share only. The
// default 5x5 neighbourhood (radius 2) also averages out the isolated fireflies of a few pilot
// samples, which with 8 neighbours left rings of wasted samples around each firefly: what is
// smooth over the image is the rate of fireflies, not where the first few landed.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include <glm/glm.hpp>

#include "image/image.h"

namespace pmcr {

// The mixture weights of a width x height image from each pixel's perceptual pilot variance v
// (see above): alpha = epsilon / P + (1 - epsilon) alpha' / Z_-ij, alpha' = sqrt of the mean of
// v over the neighbours within `radius` (the 8 around the pixel for radius 1), Z_-ij = sum of alpha' with v_ij set to 0. Each weight is at least
// epsilon / P (the paper's defensive term, Hesterberg 1995) and depends on no v_ij of its own
// pixel; the weights sum to 1 up to the leave-one-out normalisation (exactly 1 when v is 0
// everywhere: the uniform mixture).
std::vector<double> neighbourMixtureWeights(const std::vector<double>& v, int width, int height,
                                            double epsilon, int radius = 1);

// Deterministic mixture sampling (PMC-IP sec. 4.3, Hesterberg 1995) of expected counts n'_k:
// floor(n'_k) for component k, then one
// systematic pass with offset u in [0,1) over the fractions n'_k - floor(n'_k): component k gets
// one more sample with probability exactly its fraction, and the extra samples number
// ceil(sum of fractions - u) (so the total is exact when the expected counts sum to an integer).
std::vector<uint32_t> dmsRound(const std::vector<double>& expected, double u);

struct ImagePlaneOptions {
    double samplesPerIteration = 4.0;  // N / P: average samples per pixel per iteration
    uint32_t initialSpp = 4;           // the first iteration, uniform
    double epsilon = 0.01;             // the defensive weight of the uniform component
    uint32_t minSamples = 1;           // pilot samples every pixel gets in every adaptive iteration
    double displayWhite = 100.0;       // cd/m^2 that pixel luminance 1 stands for (tvi)
    int radius = 2;                    // neighbourhood: (2 radius + 1)^2 - 1 pixels
};

class ImagePlaneSampler {
public:
    ImagePlaneSampler(int width, int height, const ImagePlaneOptions& options);

    uint32_t iteration() const { return m_iteration; }

    // Rendering with several processes (core/communicator.h): `sum` adds a vector over them
    // in place, and allocate() then computes the weights from every process's pilot samples,
    // so that all of them draw from the same alpha (each keeps its own samples and image).
    // The weights still depend on no sample of their own pixel, on any process.
    void setPilotReduction(std::function<void(std::vector<double>&)> sum) { m_sumPilots = std::move(sum); }

    // The sample counts of the next iteration: uniform `initialSpp` for the first, then
    // adaptive, `spp` samples per pixel on average (less than samplesPerIteration for a last
    // iteration that ends a budget; the pilots are at most floor(spp)); `u` in [0,1) drives
    // the residual pass. Starts the iteration: its samples continue each pixel's sequence after
    // all the samples allocated before (taken or still to be added), so the next allocation
    // may be made before the last samples of this one are in (the weights then use the pilot
    // samples added so far: pmc_ip_integrator.cpp overlaps them with the device's work).
    const std::vector<uint32_t>& allocate(double u, double spp);
    const std::vector<uint32_t>& allocate(double u) { return allocate(u, m_options.samplesPerIteration); }
    // The result of sample `index` (0, 1, ... within the iteration) of `pixel` (NaN samples
    // already zeroed), in the iteration last allocated. A render stopped mid-iteration just
    // leaves some samples out: which ones depends on time, not on values.
    void addSample(uint32_t pixel, uint32_t index, const glm::vec3& radiance) {
        addResult(pixel, isPilot(index), radiance);
    }
    // Whether sample `index` of the iteration last allocated is a pilot sample (all of the
    // first iteration's are), and the result of a sample whose pilot status was taken then
    // (an iteration's samples may come in after the next one is allocated).
    bool isPilot(uint32_t index) const { return m_allocations <= 1 || index < m_iterationPilots; }
    void addResult(uint32_t pixel, bool pilot, const glm::vec3& radiance);
    // addResult without counting the sample: touches pixel `pixel`'s sums only, so results of
    // different pixels may be added on several threads at once; countResults(n) then counts them.
    void addPixelResult(uint32_t pixel, bool pilot, const glm::vec3& radiance);
    void countResults(uint64_t n) { m_samplesTaken += n; }
    // The point of the pixel's sampler sequence that sample 0 of this iteration is: the samples
    // it had before the iteration.
    uint32_t sequenceStart(uint32_t pixel) const { return m_sequenceStart[pixel]; }
    const std::vector<uint32_t>& sequenceStarts() const { return m_sequenceStart; }
    // Pilot samples per pixel of the iteration last allocated (every sample of the first).
    uint32_t iterationPilots() const { return m_iterationPilots; }
    void finishIteration() { ++m_iteration; }

    uint64_t samplesTaken() const { return m_samplesTaken; }
    Image image() const;          // the pixel estimates
    Image alphaImage() const;     // alpha * P (1 = the uniform share)
    Image sampleCountImage() const;
    Image varianceImage() const;  // estimated variance of each pixel estimate (luminance): s^2 / n

private:
    // v_ij = s^2_ij / tvi(L_ij) of the pilot samples (0 with fewer than two), over every
    // process's with a pilot reduction.
    std::vector<double> pilotPerceptualVariance() const;

    int m_width;
    int m_height;
    ImagePlaneOptions m_options;
    uint32_t m_iteration = 0;
    uint64_t m_samplesTaken = 0;
    uint32_t m_allocations = 0;      // iterations allocated
    std::vector<uint32_t> m_allocated;
    std::vector<uint32_t> m_sequenceStart;
    std::vector<uint32_t> m_scheduled;  // samples allocated to each pixel so far
    uint32_t m_iterationPilots = 0;  // pilot samples per pixel this iteration
    std::vector<double> m_alpha;
    // Every sample: radiance sum, count and luminance moments; the pilot samples' luminance
    // moments and count apart.
    std::vector<glm::dvec3> m_sum;
    std::vector<uint32_t> m_count;
    std::vector<double> m_lumSum;
    std::vector<double> m_lumSqSum;
    std::vector<double> m_pilotLumSum;
    std::vector<double> m_pilotLumSqSum;
    std::vector<uint32_t> m_pilotCount;
    std::function<void(std::vector<double>&)> m_sumPilots;
};

}  // namespace pmcr
