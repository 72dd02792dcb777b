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

}  // namespace pmcr
