// chooseChainStarts (host/methods/metropolis/bootstrap.h): b_hat is the mean weight, and chains
// start at bootstrap samples in proportion to their weights (chi-square), never at a zero weight.
#include <gtest/gtest.h>

#include <cmath>

#include "methods/metropolis/bootstrap.h"

namespace pmcr::test {
namespace {

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
    const MetropolisStart s = chooseChainStarts(w, n, 7);
    std::vector<double> counts(w.size(), 0.0);
    for (uint32_t i : s.samples) counts[i] += 1.0;
    EXPECT_EQ(counts[2], 0.0);
    double chi2 = 0.0;
    for (size_t i = 0; i < w.size(); ++i) {
        if (w[i] == 0.0f) continue;
        const double expected = n * w[i] / 16.0;
        chi2 += (counts[i] - expected) * (counts[i] - expected) / expected;
    }
    EXPECT_LT(chi2, 20.5);  // 4 degrees of freedom: p = 0.0004
}

TEST(MetropolisBootstrap, SameSeedSameStarts) {
    const std::vector<float> w = {1.0f, 2.0f, 3.0f};
    EXPECT_EQ(chooseChainStarts(w, 50, 3).samples, chooseChainStarts(w, 50, 3).samples);
    EXPECT_NE(chooseChainStarts(w, 50, 3).samples, chooseChainStarts(w, 50, 4).samples);
}

}  // namespace
}  // namespace pmcr::test
