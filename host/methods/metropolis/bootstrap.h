// Metropolis light transport's start (Veach 1997 sec. 11.3.1; Kelemen et al. 2002 sec. 4): a
// bootstrap of N independent samples x_i with weights W_i = F(x_i) / p(x_i) (F the target
// function, the luminance of the contribution; p the density that drew x_i) estimates the
// normalisation b = integral of F as the mean of W_i, and each chain starts at a bootstrap sample
// drawn with probability W_i / sum W. Started that way a chain has no start-up bias: for any
// function g, E[b_hat g(x_0)] = E[(1/N) sum_i W_i g(x_i)] = integral of F g, and the Metropolis
// steps that follow keep F invariant. MLT and PSSMLT share this (host/methods/mlt, pssmlt).
#pragma once

#include <cstdint>
#include <vector>

namespace pmcr {

struct MetropolisStart {
    double normalization = 0.0;     // b_hat = (1/N) sum_i W_i
    std::vector<uint32_t> samples;  // the bootstrap sample each chain starts from
};

// Draws `chains` start samples, independently and in proportion to `weights` (the W_i; zero,
// negative and non-finite weights are never drawn and count as zero in b_hat), with a PCG32
// seeded by `seed`. No start samples when every weight is zero.
MetropolisStart chooseChainStarts(const std::vector<float>& weights, uint32_t chains, uint64_t seed);

// A bootstrap stratified by strata of fixed sizes (mmlt: a stratum per path depth, pbrt-v4's
// MLTIntegrator): `weights` holds stratum 0's sizes[0] samples, then stratum 1's, and so on. b_hat
// is the sum of the strata's mean weights, and a chain starts at sample i of stratum d with
// probability (W_i / n_d) / sum_j (W_j / n_d(j)); the same start-up argument holds stratum by
// stratum. With equal sizes this is chooseChainStarts with b_hat times the strata.
MetropolisStart chooseChainStartsByStratum(const std::vector<float>& weights, const std::vector<uint64_t>& sizes,
                                           uint32_t chains, uint64_t seed);

// mmlt: how many of `total` bootstrap samples each depth gets, from a pilot's mean weight of each
// depth (`pilotMeans`): a share `floorShare` spread evenly over the depths, the rest in
// proportion to the pilot means (all of it evenly when they are all zero), rounded by largest
// remainder so that they add up to `total`; each depth gets at least one. The sizes must not
// depend on the samples they are used with (a pilot's, drawn apart), or b_hat is biased.
std::vector<uint64_t> allocateBootstrapByDepth(const std::vector<double>& pilotMeans, uint64_t total,
                                               double floorShare);

}  // namespace pmcr
