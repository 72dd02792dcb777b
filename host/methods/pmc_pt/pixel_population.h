// PMC-PT's population of pixel positions (Lai, Fan, Chenney and Dyer, "PMC Path Tracing",
// sec. 4), everything the host decides between two GPU dispatches: the stratified pool of
// positions, the members and their disk-mixture kernels (eq. 4), the mutations they propose,
// the density of a step's proposals on the image plane (for the unbiased estimator, see
// methods/pmc_pt/pmc_pt_integrator.h), the alpha adaptation (sec. 4.3.3), the perceptual pixel
// importance beta (sec. 4.3.2) and resampling (sec. 4.3.1-4.3.2). Pure C++, no device.
//
// Coordinates are raster positions in pixels: x in [0, width), y in [0, height), pixel (i, j)
// covering [i, i+1) x [j, j+1).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/random.h"

namespace pmcr {

constexpr int kMaxPopulationRadii = 3;  // the strategy image shows them as red, green, blue

// Running count, sum and sum of squares of a scalar (a sample's luminance).
struct RunningStats {
    uint32_t count = 0;
    double sum = 0.0;
    double sumSq = 0.0;

    void add(double v) {
        ++count;
        sum += v;
        sumSq += v * v;
    }
    void merge(const RunningStats& o) {
        count += o.count;
        sum += o.sum;
        sumSq += o.sumSq;
    }
    double mean() const { return count > 0 ? sum / double(count) : 0.0; }
    // Unbiased sample variance (n - 1); 0 with fewer than two values.
    double variance() const;
};

// PMC-PT's kernels here are discrete: a member sits at a pixel and a mutation picks a pixel of
// the "pixel disk" of radius r around it, the pixels at integer offsets (dx, dy) with
// dx^2 + dy^2 <= r^2, clipped to the image. The position inside the picked pixel comes from the
// pixel's own stratified sequence (see methods/pmc_pt/pmc_pt_integrator.h), so a step's proposal
// density is constant over each pixel and the path tracer keeps its stratification.

// A uniform pixel of that clipped pixel disk (by rejection from its bounding square).
glm::ivec2 samplePixelDisk(glm::ivec2 c, double r, int w, int h, Pcg32& rng);

// The defensive mixture weights of PMC-PT sec. 4.3.3 and PMC-ER sec. 4.5 from unnormalised
// scores alpha'_k: alpha_k = eps + (1 - eps) alpha'_k / sum alpha'. The papers' weights sum to
// 1 + (K - 1) eps; they are normalised here so they stay a mixture. With every alpha' zero
// nothing was learned and `current` is kept.
std::array<double, kMaxPopulationRadii> mixtureWeights(
    const std::array<double, kMaxPopulationRadii>& prime, int components, double epsilon,
    const std::array<double, kMaxPopulationRadii>& current);

// `--radii`: 1 to 3 positive radii in pixels separated by , or / (PMC-PT, PMC-ER).
std::vector<double> parseRadii(const std::string& text);

// The alpha update of PMC-PT sec. 4.3.3: alpha'_k = 1 / sigma^2_k, 0 if sigma_k = 0 (also when a
// component has fewer than two samples, so no spread was seen), alpha_k = eps + (1 - eps)
// alpha'_k / sum alpha'. The paper's weights sum to 1 + (K - 1) eps; they are normalised here
// so they stay a mixture. With every alpha' zero nothing was learned and `current` is kept.
std::array<double, kMaxPopulationRadii> adaptAlpha(
    const std::array<RunningStats, kMaxPopulationRadii>& tagged, int components, double epsilon,
    const std::array<double, kMaxPopulationRadii>& current);

// The stratified pool of positions (PMC-PT sec. 4.3.2 "Stratification"): the R2 sequence
// (Roberts 2018, the 2D golden-ratio Kronecker sequence) over the image, so any run of
// consecutive positions is evenly spread. Each chunk gets a fresh random toroidal shift
// (Cranley-Patterson rotation), so a chunk's positions are uniform over the image given
// everything drawn before it. PMC-PT regenerates members from it.
class PositionPool {
public:
    PositionPool(int width, int height) : m_width(width), m_height(height) {}
    std::vector<glm::dvec2> next(uint32_t count, Pcg32& rng);

private:
    int m_width;
    int m_height;
    uint64_t m_index = 0;
};

// Perceptual pixel importance (PMC-PT sec. 4.3.2): beta_ij ∝ sigma^2_ij / tvi(I_ij), from the
// luminance of the samples that landed in each pixel and the pixel's current estimate.
class PixelImportance {
public:
    void update(const std::vector<RunningStats>& pixelLuminance,
                const std::vector<double>& estimateLuminance);
    bool empty() const { return m_total <= 0.0; }
    double probability(uint32_t pixel) const;
    uint32_t samplePixel(double u) const;

private:
    std::vector<double> m_cdf;  // running sums of beta'
    double m_total = 0.0;
};

struct PopulationSettings {
    uint32_t size = 5000;        // members (paper: 5000 at 640x480)
    uint32_t mutations = 16;     // TR, mutations per member per resample step
    std::vector<double> radii = {5.0, 10.0, 50.0};  // disk radii in pixels, 1..3 of them
    double resampleRate = 0.4;   // share of the population replaced per step
    double epsilon = 0.01;       // floor of the alpha weights
};

// One camera sample a step asks the path tracer for: a pixel (its position inside the pixel
// comes from the pixel's sequence) and who proposed it.
struct PositionDraw {
    static constexpr uint32_t kPool = 0xffffffffu;
    uint32_t pixel;      // linear pixel index
    uint32_t member;     // the member whose kernel proposed it, or kPool
    uint32_t component;  // the radius it was drawn with (members only)
};

struct PopulationMember {
    glm::ivec2 pixel{0};
    std::array<double, kMaxPopulationRadii> alpha{};
    uint32_t stepsUsed = 0;  // N_used: resample steps since (re)generation
    std::array<RunningStats, kMaxPopulationRadii> tagged{};  // luminance per component since then
    RunningStats all() const;
};

struct ResampleCounts {
    uint32_t eliminated = 0;
    uint32_t fromPool = 0;
    uint32_t fromImportance = 0;
};

class PixelPopulation {
public:
    // The initial population: one member in each cell of a jittered grid of about `size` cells.
    PixelPopulation(const PopulationSettings& settings, int width, int height, Pcg32& rng);

    const PopulationSettings& settings() const { return m_settings; }
    const std::vector<PopulationMember>& members() const { return m_members; }
    int components() const { return int(m_settings.radii.size()); }
    int width() const { return m_width; }
    int height() const { return m_height; }

    // Each member's TR mutations (PMC-PT eq. 4): component k for about TR alpha_k of them
    // (systematic sampling over the alpha CDF: mutation t takes u = (t + U) / TR, so each
    // component's expected count is exactly TR alpha_k), then a uniform pixel of the pixel disk
    // of radius d_k around the member. All of a step's mutations start from the member's pixel
    // at the start of the step, so the step's expected counts are known:
    //   E[draws in pixel p] = sum_i sum_k TR alpha_ik 1[p in pixel disk k of i] / |pixel disk k of i|.
    // Appends member by member, in order. `mutations`: TR for this step (0: the settings' TR).
    void drawMutations(Pcg32& rng, std::vector<PositionDraw>& out, uint32_t mutations = 0) const;
    // Tags a mutation's luminance with its member and component (sec. 4.3.1, 4.3.3).
    void record(const PositionDraw& draw, double luminance);
    // Ends a resample step: every member has been used once more.
    void endStep();
    // The alpha update for every member (sec. 4.3.3).
    void adapt();
    // Elimination and regeneration (sec. 4.3.1-4.3.2): round(rate n) members are eliminated, the
    // survivors drawn without replacement with probability ∝ w_i = sigma^2_i / N_used
    // (Efraimidis-Spirakis keys; members with w = 0 go first). Half of the replacements take the
    // next of `poolPositions`, half a pixel drawn ∝ beta jittered by one pixel (all from the
    // pool while beta is empty). New members get uniform alpha.
    ResampleCounts resample(Pcg32& rng, const std::vector<glm::dvec2>& poolPositions,
                            const PixelImportance& importance);

    // Replacements per step, and how many of them come from the pool.
    uint32_t replacementsPerStep() const;
    uint32_t poolReplacementsPerStep(bool importanceAvailable) const;

    // A member at the pixel containing raster `position`, with uniform alpha and no history.
    PopulationMember makeMember(glm::dvec2 position) const;

private:
    PopulationSettings m_settings;
    int m_width;
    int m_height;
    std::vector<PopulationMember> m_members;
};

}  // namespace pmcr
