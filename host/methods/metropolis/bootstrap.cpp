#include "methods/metropolis/bootstrap.h"

#include <algorithm>
#include <cmath>

#include "core/random.h"

namespace pmcr {

MetropolisStart chooseChainStarts(const std::vector<float>& weights, uint32_t chains, uint64_t seed) {
    MetropolisStart start;
    std::vector<double> cdf(weights.size());
    double total = 0.0;
    for (size_t i = 0; i < weights.size(); ++i) {
        const double w = double(weights[i]);
        if (std::isfinite(w) && w > 0.0) total += w;
        cdf[i] = total;
    }
    if (weights.empty() || !(total > 0.0)) return start;
    start.normalization = total / double(weights.size());
    Pcg32 rng(seed, 0x6d6c7462u);
    start.samples.reserve(chains);
    for (uint32_t c = 0; c < chains; ++c) {
        const double u = rng.nextDouble() * total;
        // The first sample whose cumulative weight exceeds u: never a zero-weight one.
        auto it = std::upper_bound(cdf.begin(), cdf.end(), u);
        if (it == cdf.end()) it = std::lower_bound(cdf.begin(), cdf.end(), total);
        start.samples.push_back(uint32_t(it - cdf.begin()));
    }
    return start;
}

MetropolisStart chooseChainStartsByStratum(const std::vector<float>& weights, const std::vector<uint64_t>& sizes,
                                           uint32_t chains, uint64_t seed) {
    // Sample i of stratum d weighs W_i N / (S n_d): chooseChainStarts then draws in proportion
    // to W_i / n_d, and its b_hat, the mean of those, is (1 / S) sum_d mean_d(W).
    const double strata = double(sizes.size());
    std::vector<float> scaled(weights.size());
    size_t i = 0;
    for (uint64_t n : sizes)
        for (uint64_t k = 0; k < n && i < weights.size(); ++k, ++i)
            scaled[i] = float(double(weights[i]) * double(weights.size()) / (strata * double(n)));
    MetropolisStart start = chooseChainStarts(scaled, chains, seed);
    start.normalization *= strata;
    return start;
}

std::vector<uint64_t> allocateBootstrapByDepth(const std::vector<double>& pilotMeans, uint64_t total,
                                               double floorShare) {
    const size_t depths = pilotMeans.size();
    std::vector<uint64_t> sizes(depths, 0);
    if (depths == 0) return sizes;
    double sum = 0.0;
    for (double m : pilotMeans) sum += std::isfinite(m) && m > 0.0 ? m : 0.0;
    const uint64_t spare = total - std::min<uint64_t>(total, depths);  // one each first
    std::vector<double> remainder(depths);
    uint64_t given = 0;
    for (size_t d = 0; d < depths; ++d) {
        const double m = std::isfinite(pilotMeans[d]) && pilotMeans[d] > 0.0 ? pilotMeans[d] : 0.0;
        const double share = sum > 0.0 ? floorShare / double(depths) + (1.0 - floorShare) * m / sum
                                        : 1.0 / double(depths);
        const double exact = share * double(spare);
        sizes[d] = 1 + uint64_t(std::floor(exact));
        remainder[d] = exact - std::floor(exact);
        given += sizes[d];
    }
    // Largest remainders first (ties to the lower depth), until the sizes add up to total.
    std::vector<size_t> order(depths);
    for (size_t d = 0; d < depths; ++d) order[d] = d;
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return remainder[a] > remainder[b]; });
    for (size_t k = 0; given < total; k = (k + 1) % depths, ++given) ++sizes[order[k]];
    return sizes;
}

}  // namespace pmcr
