#include "methods/pmc_er/path_population.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/error.h"

namespace pmcr {

std::vector<double> survivalProbabilities(const std::vector<double>& energy, uint32_t keep) {
    const size_t n = energy.size();
    std::vector<double> p(n, 0.0);
    std::vector<size_t> positive;
    for (size_t i = 0; i < n; ++i)
        if (energy[i] > 0.0 && std::isfinite(energy[i])) positive.push_back(i);
    if (positive.size() <= keep) {
        for (size_t i : positive) p[i] = 1.0;
        return p;
    }
    if (keep == 0) return p;
    // Largest first: the members capped at 1 are a prefix. c = (keep - m) / (sum of the rest),
    // the smallest m for which c E stays below 1 on the rest.
    std::sort(positive.begin(), positive.end(), [&](size_t a, size_t b) { return energy[a] > energy[b]; });
    double rest = 0.0;
    for (size_t i : positive) rest += energy[i];
    size_t capped = 0;
    double c = double(keep) / rest;
    while (capped < positive.size() && c * energy[positive[capped]] >= 1.0) {
        rest -= energy[positive[capped]];
        ++capped;
        c = rest > 0.0 ? double(keep - capped) / rest : 0.0;
    }
    for (size_t j = 0; j < positive.size(); ++j)
        p[positive[j]] = j < capped ? 1.0 : std::min(1.0, c * energy[positive[j]]);
    return p;
}

std::vector<bool> systematicSample(const std::vector<double>& p, double u) {
    std::vector<bool> chosen(p.size(), false);
    double cumulative = 0.0;
    double next = u;  // the next point u, u + 1, u + 2, ...
    for (size_t i = 0; i < p.size(); ++i) {
        cumulative += p[i];
        // p_i <= 1, so at most one point falls in [cumulative - p_i, cumulative).
        if (p[i] > 0.0 && next < cumulative) {
            chosen[i] = true;
            next += 1.0;
        }
    }
    return chosen;
}

std::vector<uint32_t> activeMembers(const std::vector<gpu::PmcErMember>& members) {
    std::vector<uint32_t> list;
    list.reserve(members.size());
    for (uint32_t i = 0; i < uint32_t(members.size()); ++i)
        if (members[i].remaining > 0.0f) list.push_back(i);
    std::sort(list.begin(), list.end(), [&](uint32_t a, uint32_t b) {
        return members[a].pixel != members[b].pixel ? members[a].pixel < members[b].pixel : a < b;
    });
    return list;
}

PathPopulation::PathPopulation(uint32_t size, int components, double resampleRate, double epsilon,
                               double adaptRate)
    : m_size(size), m_components(components), m_epsilon(epsilon), m_adaptRate(adaptRate) {
    if (size == 0) throw Error("--population: expected at least one member");
    if (!(resampleRate >= 0.0 && resampleRate <= 1.0)) throw Error("--resample-rate: expected 0..1");
    const double r = std::round(resampleRate * double(size));
    m_replacements = resampleRate > 0.0 ? std::clamp(uint32_t(r), 1u, size) : 0u;
}

void PathPopulation::adapt(std::vector<gpu::PmcErMember>& members) const {
    if (m_adaptRate <= 0.0) return;
    for (gpu::PmcErMember& m : members) {
        std::array<double, kMaxPopulationRadii> prime{}, current{};
        for (int k = 0; k < m_components; ++k) {
            prime[size_t(k)] = m.acceptSum[k];
            current[size_t(k)] = m.alpha[k];
        }
        const auto alpha = mixtureWeights(prime, m_components, m_epsilon, current);
        for (int k = 0; k < m_components; ++k)
            m.alpha[k] = float((1.0 - m_adaptRate) * current[size_t(k)] + m_adaptRate * alpha[size_t(k)]);
    }
}

PathResampleResult PathPopulation::eliminate(std::vector<gpu::PmcErMember>& members, Pcg32& rng) const {
    PathResampleResult result;
    std::vector<double> energy(members.size());
    for (size_t i = 0; i < members.size(); ++i) {
        energy[i] = std::max(0.0, double(members[i].remaining));
        result.energyBefore += energy[i];
    }
    const uint32_t keep = uint32_t(members.size()) - std::min(m_replacements, uint32_t(members.size()));
    const std::vector<double> p = survivalProbabilities(energy, keep);
    const std::vector<bool> survive = systematicSample(p, rng.nextDouble());
    for (size_t i = 0; i < members.size(); ++i) {
        if (survive[i]) {
            // E / p: the survivor carries the eliminated members' expected energy.
            members[i].remaining = float(energy[i] / p[i]);
            result.energyAfter += double(members[i].remaining);
            ++result.survivors;
            continue;
        }
        members[i].remaining = 0.0f;
        ++result.eliminated;
        if (result.regenerate.size() < m_replacements) result.regenerate.push_back(uint32_t(i));
    }
    return result;
}

}  // namespace pmcr
