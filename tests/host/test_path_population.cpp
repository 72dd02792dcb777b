// PMC-ER's host side (methods/pmc_er/path_population.h) on hand-made populations: the alpha update
// against the paper's formula (and its partial form, --adapt-rate), the survival probabilities (proportional to remaining energy,
// capped at one, summing to the survivors), systematic sampling's inclusion frequencies
// (chi-square), the energy invariant of elimination (survivors carry E / p) and the list of
// living members the mutation kernel runs through.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "methods/pmc_er/path_population.h"
#include "statistics.h"

namespace pmcr::test {
namespace {

gpu::PmcErMember member(float remaining, glm::vec3 acceptSum = glm::vec3(0.0f)) {
    gpu::PmcErMember m{};
    m.remaining = remaining;
    m.alpha = glm::vec3(1.0f / 3.0f);
    m.acceptSum = acceptSum;
    return m;
}

TEST(PathPopulation, AlphaFollowsTheAcceptanceSums) {
    PathPopulation population(4, 3, 0.4, 0.1);
    std::vector<gpu::PmcErMember> members = {member(1.0f, {1.0f, 3.0f, 0.0f}), member(1.0f)};
    population.adapt(members);
    // alpha_k = eps + (1 - eps) alpha'_k / sum alpha', normalised: / (3 eps + 1 - eps).
    const double norm = 3 * 0.1 + 0.9;
    EXPECT_NEAR(members[0].alpha[0], (0.1 + 0.9 * 0.25) / norm, 1e-6);
    EXPECT_NEAR(members[0].alpha[1], (0.1 + 0.9 * 0.75) / norm, 1e-6);
    EXPECT_NEAR(members[0].alpha[2], 0.1 / norm, 1e-6);
    // Nothing accepted yet: the weights stay as they were.
    EXPECT_FLOAT_EQ(members[1].alpha[0], 1.0f / 3.0f);
    EXPECT_FLOAT_EQ(members[1].alpha[2], 1.0f / 3.0f);
}

// --adapt-rate r (beyond the paper): the share r of the way from the current weights to the
// update; r = 0 keeps them.
TEST(PathPopulation, AdaptRateBlendsTheUpdateAndZeroKeepsTheWeights) {
    const glm::vec3 sums(1.0f, 3.0f, 0.0f);
    std::vector<gpu::PmcErMember> full = {member(1.0f, sums)}, half = full, fixed = full;
    PathPopulation(4, 3, 0.4, 0.1, 1.0).adapt(full);
    PathPopulation(4, 3, 0.4, 0.1, 0.5).adapt(half);
    PathPopulation(4, 3, 0.4, 0.1, 0.0).adapt(fixed);
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(half[0].alpha[k], 0.5 / 3.0 + 0.5 * full[0].alpha[k], 1e-6) << k;
        EXPECT_FLOAT_EQ(fixed[0].alpha[k], 1.0f / 3.0f) << k;
    }
}

TEST(PathPopulation, SurvivalIsProportionalToEnergyCappedAtOne) {
    const std::vector<double> energy = {0.0, 1.0, 2.0, 4.0, 100.0, 3.0};
    const auto p = survivalProbabilities(energy, 3);
    EXPECT_NEAR(std::accumulate(p.begin(), p.end(), 0.0), 3.0, 1e-12);
    EXPECT_EQ(p[0], 0.0);
    EXPECT_EQ(p[4], 1.0);  // capped
    // The rest share 2 survivors in proportion to energy: c = 2 / 10.
    EXPECT_NEAR(p[1], 0.2, 1e-12);
    EXPECT_NEAR(p[2], 0.4, 1e-12);
    EXPECT_NEAR(p[3], 0.8, 1e-12);
    EXPECT_NEAR(p[5], 0.6, 1e-12);
    // Capping cascades: 100 and 50 both survive surely, the rest share one.
    const auto q = survivalProbabilities({100.0, 50.0, 1.0, 1.0}, 3);
    EXPECT_EQ(q[0], 1.0);
    EXPECT_EQ(q[1], 1.0);
    EXPECT_NEAR(q[2], 0.5, 1e-12);
    // Fewer members with energy than survivors: all of them survive.
    const auto r = survivalProbabilities({0.0, 2.0, 0.0, 1.0}, 3);
    EXPECT_EQ(r, (std::vector<double>{0.0, 1.0, 0.0, 1.0}));
}

// Elimination over many trials: each member survives with its probability (chi-square over the
// members' survival counts), exactly n - R survive every time, and the expected energy after
// elimination equals the energy before, member by member.
TEST(PathPopulation, EliminationSurvivalStatisticsAndEnergy) {
    const std::vector<float> energy = {0.0f, 0.5f, 1.0f, 2.0f, 3.0f, 5.0f, 8.0f, 13.0f, 40.0f, 0.25f};
    PathPopulation population(uint32_t(energy.size()), 3, 0.4, 0.1);
    ASSERT_EQ(population.replacementsPerIteration(), 4u);
    std::vector<double> e(energy.begin(), energy.end());
    const auto p = survivalProbabilities(e, 6);
    Pcg32 rng(7);
    const int trials = 40000;
    std::vector<double> survived(energy.size(), 0.0), energyAfter(energy.size(), 0.0);
    for (int t = 0; t < trials; ++t) {
        std::vector<gpu::PmcErMember> members;
        for (float x : energy) members.push_back(member(x));
        const PathResampleResult r = population.eliminate(members, rng);
        ASSERT_EQ(r.survivors, 6u);
        ASSERT_EQ(r.regenerate.size(), 4u);
        for (size_t i = 0; i < members.size(); ++i) {
            const bool alive = members[i].remaining > 0.0f;
            survived[i] += alive ? 1.0 : 0.0;
            energyAfter[i] += members[i].remaining;
        }
    }
    // Survival counts against p: one cell per member whose fate is random. The counts sum to a
    // constant (exactly n - R survive each trial) and each varies at most binomially, so
    // Pearson's statistic with cells - 1 degrees of freedom is conservative, not anti.
    std::vector<double> observed, expected;
    for (size_t i = 0; i < energy.size(); ++i) {
        if (p[i] <= 0.0 || p[i] >= 1.0) {
            EXPECT_EQ(survived[i], p[i] * trials) << "member " << i;
            continue;
        }
        observed.push_back(survived[i]);
        expected.push_back(p[i] * trials);
    }
    const Chi2Result chi2 = chi2Test(observed, expected);
    EXPECT_GT(chi2.pValue, 1e-3) << chi2.describe();
    // E[E after] = E before: the standard error of member i's mean is E sqrt((1 - p) / p) / sqrt(n).
    for (size_t i = 0; i < energy.size(); ++i) {
        if (!(p[i] > 0.0)) continue;
        const double mean = energyAfter[i] / trials;
        const double se = energy[i] * std::sqrt((1.0 - p[i]) / p[i] / trials);
        EXPECT_NEAR(mean, energy[i], 5.0 * se + 1e-5 * energy[i]) << "member " << i;
    }
}

TEST(PathPopulation, ActiveListHasTheLivingMembersInPixelOrder) {
    std::vector<gpu::PmcErMember> members = {member(2.0f), member(0.0f), member(0.5f), member(-1.0f),
                                             member(7.0f), member(1.0f)};
    const uint32_t pixels[] = {40, 3, 12, 1, 12, 5};
    for (size_t i = 0; i < members.size(); ++i) members[i].pixel = pixels[i];
    // Dead members (E <= 0) left out; ties in pixel keep slot order.
    EXPECT_EQ(activeMembers(members), (std::vector<uint32_t>{5, 2, 4, 0}));
    EXPECT_TRUE(activeMembers({member(0.0f), member(-2.0f)}).empty());
}

TEST(PathPopulation, DeadMembersAreRegeneratedFirst) {
    PathPopulation population(5, 1, 0.4, 0.1);
    std::vector<gpu::PmcErMember> members = {member(0.0f), member(3.0f), member(0.0f), member(0.0f), member(1.0f)};
    Pcg32 rng(3);
    const PathResampleResult r = population.eliminate(members, rng);
    // Two replacements; three members without energy: two are refilled, the third stays dead.
    EXPECT_EQ(r.regenerate, (std::vector<uint32_t>{0, 2}));
    EXPECT_EQ(r.survivors, 2u);
    EXPECT_EQ(members[1].remaining, 3.0f);
    EXPECT_EQ(members[4].remaining, 1.0f);
    EXPECT_EQ(members[3].remaining, 0.0f);
}

}  // namespace
}  // namespace pmcr::test
