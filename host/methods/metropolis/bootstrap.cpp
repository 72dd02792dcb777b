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

}  // namespace pmcr
