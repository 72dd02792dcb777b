// PMC-IP's image-plane sampler on the host: mixture weights (sec. 4.2), deterministic mixture
// sampling (sec. 4.3) and the estimator's unbiasedness, with a synthetic "renderer" whose pixel
// integrals are known, so that thousands of independent runs take milliseconds.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <random>

#include "render/image_plane_sampler.h"
#include "statistics.h"

namespace pmcr {
namespace {

std::vector<double> randomWeights(std::mt19937_64& rng, size_t n, double spread) {
    std::lognormal_distribution<double> dist(0.0, spread);
    std::vector<double> a(n);
    double sum = 0.0;
    for (double& v : a) sum += v = dist(rng);
    for (double& v : a) v /= sum;
    return a;
}

TEST(MixtureWeights, SumToOneAndNeverBelowEpsilonOverPixels) {
    std::mt19937_64 rng(1);
    for (double epsilon : {0.01, 0.1, 0.5, 1.0}) {
        std::vector<double> alphaPrime = randomWeights(rng, 1000, 3.0);
        for (size_t i = 0; i < alphaPrime.size(); i += 7) alphaPrime[i] = 0.0;  // smooth pixels
        const auto alpha = pmcIpMixtureWeights(alphaPrime, epsilon);
        double sum = 0.0;
        for (double a : alpha) {
            EXPECT_GE(a, epsilon / 1000.0 * (1.0 - 1e-12));
            sum += a;
        }
        EXPECT_NEAR(sum, 1.0, 1e-12);
        // The adaptive part is proportional to alpha'.
        const double total = std::accumulate(alphaPrime.begin(), alphaPrime.end(), 0.0);
        for (size_t i = 0; i < alpha.size(); ++i)
            EXPECT_NEAR(alpha[i], epsilon / 1000.0 + (1.0 - epsilon) * alphaPrime[i] / total, 1e-15);
    }
}

TEST(MixtureWeights, NoVarianceAnywhereIsUniform) {
    const auto alpha = pmcIpMixtureWeights(std::vector<double>(50, 0.0), 0.01);
    for (double a : alpha) EXPECT_DOUBLE_EQ(a, 1.0 / 50.0);
}

TEST(DeterministicMixtureSampling, CountsSumExactlyAndAreFloorOrFloorPlusOne) {
    std::mt19937_64 rng(2);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int trial = 0; trial < 200; ++trial) {
        const size_t k = 1 + size_t(rng() % 3000);
        const auto alpha = randomWeights(rng, k, trial % 2 ? 4.0 : 0.5);
        const uint32_t minimum = uint32_t(rng() % 3);
        const uint64_t total = minimum * k + rng() % (8 * k + 1);
        const auto counts = dmsAllocate(alpha, total, minimum, u(rng));
        const auto expected = dmsExpectedCounts(alpha, total, minimum);
        uint64_t sum = 0;
        for (size_t i = 0; i < k; ++i) {
            sum += counts[i];
            const double whole = std::floor(expected[i]);
            EXPECT_TRUE(counts[i] == whole || counts[i] == whole + 1.0)
                << "component " << i << " got " << counts[i] << " of expected " << expected[i];
            EXPECT_GE(counts[i], minimum);
        }
        EXPECT_EQ(sum, total) << "trial " << trial;
    }
}

TEST(DeterministicMixtureSampling, EdgeOffsetsStillSumExactly) {
    std::mt19937_64 rng(3);
    const auto alpha = randomWeights(rng, 777, 2.0);
    for (double u : {0.0, 1e-300, 0.5, 1.0 - 1e-16}) {
        const auto counts = dmsAllocate(alpha, 3001, 1, u);
        EXPECT_EQ(std::accumulate(counts.begin(), counts.end(), uint64_t(0)), 3001u) << "u = " << u;
    }
}

// Over random offsets, component k gets its extra sample with probability equal to its
// fraction n'_k - floor(n'_k): a chi-square test of the extra counts against the fractions.
TEST(DeterministicMixtureSampling, ResidualDrawsFollowTheFractions) {
    std::mt19937_64 rng(4);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const size_t k = 40;
    const auto alpha = randomWeights(rng, k, 1.0);
    const uint64_t total = 97;
    const auto expected = dmsExpectedCounts(alpha, total, 0);
    const int trials = 20000;
    std::vector<double> observed(k, 0.0), wanted(k, 0.0);
    for (int t = 0; t < trials; ++t) {
        const auto counts = dmsAllocate(alpha, total, 0, u(rng));
        for (size_t i = 0; i < k; ++i) observed[i] += counts[i] - std::floor(expected[i]);
    }
    for (size_t i = 0; i < k; ++i) wanted[i] = trials * (expected[i] - std::floor(expected[i]));
    const auto result = test::chi2Test(observed, wanted);
    EXPECT_GT(result.pValue, 0.001) << result.describe();
}

TEST(DeterministicMixtureSampling, RefusesFewerSamplesThanTheMinimum) {
    EXPECT_ANY_THROW(dmsAllocate(std::vector<double>(10, 0.1), 9, 1, 0.5));
}

// A synthetic image whose pixels have known integrals: pixel i returns `bright` with
// probability p_i, else `dim_i`. Rare bright values are the case adaptive sampling biases.
struct SyntheticImage {
    std::vector<double> p, dim;
    double bright = 40.0;
    double mean(size_t i) const { return p[i] * bright + (1.0 - p[i]) * dim[i]; }
    float sample(size_t i, std::mt19937_64& rng) const {
        return std::uniform_real_distribution<double>(0.0, 1.0)(rng) < p[i] ? float(bright) : float(dim[i]);
    }
};

SyntheticImage makeSyntheticImage(size_t pixels) {
    SyntheticImage img;
    for (size_t i = 0; i < pixels; ++i) {
        img.p.push_back(i % 4 == 0 ? 0.02 : i % 4 == 1 ? 0.2 : 0.0);
        img.dim.push_back(0.05 + 0.1 * double(i % 5));
    }
    return img;
}

// Runs the sampler over the synthetic image; `plainAverage` returns sum of samples / count
// instead (the estimator the sampler avoids).
std::vector<double> runSampler(const SyntheticImage& img, const ImagePlaneOptions& options,
                               int iterations, uint64_t seed, bool plainAverage = false) {
    const int width = int(img.p.size());
    ImagePlaneSampler sampler(width, 1, options);
    std::mt19937_64 rng(seed);
    std::vector<double> sum(width, 0.0), count(width, 0.0);
    for (int t = 0; t <= iterations; ++t) {
        const auto& counts = sampler.allocate(std::uniform_real_distribution<double>(0.0, 1.0)(rng));
        for (int i = 0; i < width; ++i)
            for (uint32_t k = 0; k < counts[i]; ++k) {
                const float v = img.sample(size_t(i), rng);
                sampler.addSample(uint32_t(i), glm::vec3(v));
                sum[i] += v;
                count[i] += 1.0;
            }
        sampler.finishIteration();
    }
    std::vector<double> result(width);
    const Image image = sampler.image();
    for (int i = 0; i < width; ++i) result[i] = plainAverage ? sum[i] / count[i] : image.rgb[3 * i];
    return result;
}

// Mean over independent runs, per pixel, against the known integral: |z| below the Sidak level.
struct BiasCheck {
    int failing = 0;
    double worstZ = 0.0;
};

BiasCheck checkBias(const SyntheticImage& img, const ImagePlaneOptions& options, int runs,
                    bool plainAverage) {
    const size_t n = img.p.size();
    std::vector<double> sum(n, 0.0), sumSq(n, 0.0);
    for (int r = 0; r < runs; ++r) {
        const auto est = runSampler(img, options, 4, 1000 + uint64_t(r), plainAverage);
        for (size_t i = 0; i < n; ++i) {
            sum[i] += est[i];
            sumSq[i] += est[i] * est[i];
        }
    }
    const double level = test::sidakLevel(0.01, int(n));
    BiasCheck check;
    for (size_t i = 0; i < n; ++i) {
        const double mean = sum[i] / runs;
        const double var = std::max(1e-30, (sumSq[i] - runs * mean * mean) / (runs - 1));
        // Float images: allow their rounding (constant pixels have no variance at all).
        const double err = std::max(0.0, std::abs(mean - img.mean(i)) - 1e-6 * img.mean(i));
        const double z = err / std::sqrt(var / runs);
        check.worstZ = std::max(check.worstZ, std::abs(z));
        if (2.0 * (1.0 - test::normalCdf(std::abs(z))) < level) ++check.failing;
    }
    return check;
}

TEST(ImagePlaneSampler, EstimatorIsUnbiasedWhereThePlainAverageIsNot) {
    const SyntheticImage img = makeSyntheticImage(64);
    ImagePlaneOptions options;
    options.initialSpp = 2;
    const BiasCheck ours = checkBias(img, options, 4000, false);
    EXPECT_EQ(ours.failing, 0) << "worst |z| " << ours.worstZ;
    // The deviation from the paper's plain average is needed: it darkens rare bright pixels.
    const BiasCheck plain = checkBias(img, options, 4000, true);
    EXPECT_GT(plain.failing, 0) << "worst |z| " << plain.worstZ;
}

// min-spp 0 is the paper's pure mixture: pixels may get no sample in an iteration, and their
// iteration estimate is eq. 3's S / (N alpha). Still unbiased.
TEST(ImagePlaneSampler, PureMixtureWithoutAMinimumIsUnbiased) {
    const SyntheticImage img = makeSyntheticImage(64);
    ImagePlaneOptions options;
    options.initialSpp = 2;
    options.minSamples = 0;
    options.epsilon = 0.2;
    const BiasCheck ours = checkBias(img, options, 4000, false);
    EXPECT_EQ(ours.failing, 0) << "worst |z| " << ours.worstZ;
}

TEST(ImagePlaneSampler, AdaptiveIterationsSpendTheBudgetWhereTheVarianceIs) {
    const SyntheticImage img = makeSyntheticImage(64);
    ImagePlaneOptions options;
    ImagePlaneSampler sampler(64, 1, options);
    std::mt19937_64 rng(9);
    for (int t = 0; t < 6; ++t) {
        const auto& counts = sampler.allocate(0.5);
        uint64_t total = 0;
        for (int i = 0; i < 64; ++i) {
            total += counts[i];
            EXPECT_GE(counts[i], t == 0 ? options.initialSpp : options.minSamples);
            for (uint32_t k = 0; k < counts[i]; ++k) sampler.addSample(uint32_t(i), glm::vec3(img.sample(size_t(i), rng)));
        }
        EXPECT_EQ(total, t == 0 ? 64u * options.initialSpp : uint64_t(64 * options.samplesPerIteration));
        sampler.finishIteration();
    }
    // Constant pixels (i % 4 == 2, 3) end with the minimum; noisy ones with more.
    const Image counts = sampler.sampleCountImage();
    double noisy = 0.0, flat = 0.0;
    for (int i = 0; i < 64; ++i) (i % 4 == 1 ? noisy : i % 4 >= 2 ? flat : noisy) += counts.rgb[3 * i];
    EXPECT_GT(noisy, 2.0 * flat);
    EXPECT_EQ(sampler.samplesTaken(), 64u * (options.initialSpp + 5 * 4));
}

// A render stopped mid-iteration: pixels that did not get all their samples skip it.
TEST(ImagePlaneSampler, AnUnfinishedIterationIsSkippedPerPixel) {
    ImagePlaneOptions options;
    ImagePlaneSampler sampler(2, 1, options);
    sampler.allocate(0.5);
    for (uint32_t i = 0; i < 2; ++i)
        for (int k = 0; k < 4; ++k) sampler.addSample(i, glm::vec3(1.0f));
    sampler.finishIteration();
    const auto& counts = sampler.allocate(0.5);
    for (uint32_t k = 0; k < counts[0]; ++k) sampler.addSample(0, glm::vec3(3.0f));
    sampler.addSample(1, glm::vec3(100.0f));  // pixel 1 gets fewer than allocated
    ASSERT_GT(counts[1], 1u);
    sampler.finishIteration();
    const Image img = sampler.image();
    EXPECT_FLOAT_EQ(img.rgb[0], 2.0f);  // (4 * 1 + 4 * 3) / 8: equal budgets, equal weights
    EXPECT_FLOAT_EQ(img.rgb[3], 1.0f);
}

}  // namespace
}  // namespace pmcr
