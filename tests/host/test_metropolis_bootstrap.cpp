// chooseChainStarts (host/methods/metropolis/bootstrap.h): b_hat is the mean weight, and chains
// start at bootstrap samples in proportion to their weights (chi-square), never at a zero weight.
// Stratified (mmlt's depths): b_hat is the sum of the strata's means, starts in proportion to
// W_i / n_d; allocateBootstrapByDepth's sizes add up, keep their floor and follow the pilot.
#include <gtest/gtest.h>

#include <cmath>

#include "methods/metropolis/bootstrap.h"
#include "statistics.h"

namespace pmcr::test {
namespace {

// The starts' counts per sample against probabilities p (chi-square; a start where p is 0 fails).
void expectStartsDrawnWith(const MetropolisStart& s, const std::vector<double>& p, uint32_t n) {
    ASSERT_EQ(s.samples.size(), n);
    std::vector<double> counts(p.size(), 0.0), expected(p.size());
    for (uint32_t i : s.samples) counts.at(i) += 1.0;
    for (size_t i = 0; i < p.size(); ++i) expected[i] = double(n) * p[i];
    const Chi2Result r = chi2Test(counts, expected);
    EXPECT_GT(r.pValue, 4e-4) << r.describe();
}

TEST(MetropolisBootstrap, NormalizationIsTheMeanWeight) {
    const std::vector<float> w = {0.0f, 1.0f, 3.0f, NAN, -2.0f, 4.0f};
    const MetropolisStart s = chooseChainStarts(w, 10, 1);
    EXPECT_DOUBLE_EQ(s.normalization, 8.0 / 6.0);
    ASSERT_EQ(s.samples.size(), 10u);
    for (uint32_t i : s.samples) EXPECT_TRUE(i == 1 || i == 2 || i == 5) << i;
}

TEST(MetropolisBootstrap, NoWeightNoStarts) {
    EXPECT_TRUE(chooseChainStarts({0.0f, 0.0f}, 4, 1).samples.empty());
    EXPECT_TRUE(chooseChainStarts({}, 4, 1).samples.empty());
}

TEST(MetropolisBootstrap, StartsAreDrawnInProportionToWeight) {
    const std::vector<float> w = {1.0f, 2.0f, 0.0f, 4.0f, 8.0f, 1.0f};
    const uint32_t n = 200000;
    std::vector<double> p(w.size());
    for (size_t i = 0; i < w.size(); ++i) p[i] = w[i] / 16.0;
    expectStartsDrawnWith(chooseChainStarts(w, n, 7), p, n);
}

TEST(MetropolisBootstrap, SameSeedSameStarts) {
    const std::vector<float> w = {1.0f, 2.0f, 3.0f};
    EXPECT_EQ(chooseChainStarts(w, 50, 3).samples, chooseChainStarts(w, 50, 3).samples);
    EXPECT_NE(chooseChainStarts(w, 50, 3).samples, chooseChainStarts(w, 50, 4).samples);
}

TEST(MetropolisBootstrap, StrataNormalizationIsTheSumOfTheirMeans) {
    // Stratum 0: 2 samples, mean 1.5; stratum 1: 4 samples, mean 2; stratum 2: 1 sample, 0.
    const std::vector<float> w = {1.0f, 2.0f, 0.0f, 4.0f, 4.0f, 0.0f, 0.0f};
    const MetropolisStart s = chooseChainStartsByStratum(w, {2, 4, 1}, 10, 1);
    EXPECT_NEAR(s.normalization, 3.5, 1e-6);
    for (uint32_t i : s.samples) EXPECT_TRUE(i == 0 || i == 1 || i == 3 || i == 4) << i;
    // Equal sizes: chooseChainStarts with b_hat times the strata, the same starts.
    const std::vector<float> e = {1.0f, 3.0f, 2.0f, 0.5f};
    const MetropolisStart a = chooseChainStartsByStratum(e, {2, 2}, 20, 5), b = chooseChainStarts(e, 20, 5);
    EXPECT_NEAR(a.normalization, 2.0 * b.normalization, 1e-6);
    EXPECT_EQ(a.samples, b.samples);
}

TEST(MetropolisBootstrap, StrataStartsAreDrawnInProportionToWeightOverSize) {
    // In proportion to W_i / n_d: 1/2, 2/2 | 4/3, 4/3, 0/3 | 2/1, or 3, 6, 8, 8, 0, 12 of 37.
    const std::vector<float> w = {1.0f, 2.0f, 4.0f, 4.0f, 0.0f, 2.0f};
    const uint32_t n = 200000;
    const std::vector<double> p = {3.0 / 37, 6.0 / 37, 8.0 / 37, 8.0 / 37, 0.0, 12.0 / 37};
    expectStartsDrawnWith(chooseChainStartsByStratum(w, {2, 3, 1}, n, 9), p, n);
}

TEST(MetropolisBootstrap, DepthAllocationFollowsThePilotAboveAFloor) {
    // Floor 0.25 over 4 depths: 1/16 each, the rest as 0 : 1 : 3 : 0.
    const std::vector<uint64_t> n = allocateBootstrapByDepth({0.0, 1.0, 3.0, 0.0}, 16004, 0.25);
    ASSERT_EQ(n.size(), 4u);
    EXPECT_EQ(n[0] + n[1] + n[2] + n[3], 16004u);
    EXPECT_NEAR(double(n[0]), 1000.0, 1.0);
    EXPECT_NEAR(double(n[1]), 1000.0 + 3000.0, 1.0);
    EXPECT_NEAR(double(n[2]), 1000.0 + 9000.0, 1.0);
    EXPECT_NEAR(double(n[3]), 1000.0, 1.0);
    // A dark or broken pilot: evenly; at least one sample of each depth, always.
    EXPECT_EQ(allocateBootstrapByDepth({0.0, NAN, -1.0}, 9, 0.25), (std::vector<uint64_t>{3, 3, 3}));
    EXPECT_EQ(allocateBootstrapByDepth({0.0, 5.0, 0.0}, 3, 0.0), (std::vector<uint64_t>{1, 1, 1}));
    const std::vector<uint64_t> m = allocateBootstrapByDepth({1.0, 1e-9, 7.0}, 100, 0.0);
    EXPECT_EQ(m[0] + m[1] + m[2], 100u);
    EXPECT_GE(m[1], 1u);
}

}  // namespace
}  // namespace pmcr::test
