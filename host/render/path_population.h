// PMC-ER's population of light paths between two GPU iterations (Lai, Fan, Chenney and Dyer
// 2007, sec. 4.5): the alpha update, elimination by remaining energy and the choice of slots to
// regenerate. Pure C++ over the members' bookkeeping (shared/pmc_er_types.h PmcErMember); the
// paths themselves stay on the device.
//
// Energy contract. A member's energy E (units of e_d) is what it still owes the image. A mutation
// deposits one e_d and takes one from E; below one, the last deposit is made with probability E
// (Russian roulette, shaders/pmc_er_mutate.comp). At elimination member i survives with
// probability p_i and a survivor's E becomes E / p_i; a member eliminated deposits nothing more.
// When rendering ends every member deposits its E at once. By induction over the steps, the
// expected energy a member still deposits equals its E at any time: a mutation step gives
// 1 + (E - 1) for E >= 1 and E * 1 + 0 below; elimination gives p_i (E / p_i) + (1 - p_i) 0 = E;
// the end gives E. So every member deposits, in expectation, exactly its initial energy, and the
// image's expected total energy is the seeds' (tests/host/test_path_population.cpp,
// tests/stat/test_pmc_er.cpp).
//
// What this does not prove. Energy in expectation is necessary, not sufficient, for an
// unbiased image. ERPT starts chains of a fixed length m in proportion to the seed's energy,
// so at every step the expected deposits are those of f-invariant chains started from f, and
// they are f. Here a member's lifetime grows with its energy, and the deposits of a chain of
// lifetime n(x0) average K^1..K^n(x0) from x0, which is not f-invariant when n depends on x0.
// Two states A, B with f = 1 each, K the swap (reversible for f), p(A) = 0.9, p(B) = 0.1, so
// e(A) = 1.1, e(B) = 10; with e_d = 1.1, a path from A lives one step (deposits at B), one
// from B nine (A five times, B four): E[A] = 0.1 * 5 * 1.1 = 0.55, E[B] = 0.9 * 1.1 + 0.1 * 4 * 1.1
// = 1.43, not 1 and 1. The same holds for alpha adapted from a member's own acceptances (adaptive
// MCMC). Both effects are small where a path's neighbourhood holds paths of similar energy, and
// the per-pixel z-test against path tracing measures them; splitting each seed into members of
// equal energy (ERPT's chain counts) whose lifetimes do not depend on their paths would make the
// image exact.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/random.h"
#include "render/pixel_population.h"
#include "shared/host_device.h"

namespace pmcr {

// Survival probabilities p_i = min(1, c E_i) with sum p_i = keep (PMC-ER sec. 4.5: survival
// proportional to E_remain, capped at one by "water filling"). Members with E <= 0 get 0; when
// at most `keep` members have energy, each of them gets 1.
std::vector<double> survivalProbabilities(const std::vector<double>& energy, uint32_t keep);

// Systematic sampling (Madow 1949) of members with inclusion probabilities p (each <= 1, sum an
// integer n): exactly n members, member i with probability p_i. `u` is uniform in [0, 1).
std::vector<bool> systematicSample(const std::vector<double>& p, double u);

struct PathResampleResult {
    std::vector<uint32_t> regenerate;  // slots to refill from the pool, in ascending order
    uint32_t eliminated = 0;           // members eliminated (with and without energy)
    uint32_t survivors = 0;
    double energyBefore = 0.0;         // sum of E before and after (equal in expectation)
    double energyAfter = 0.0;
};

class PathPopulation {
public:
    PathPopulation(uint32_t size, int components, double resampleRate, double epsilon);

    uint32_t size() const { return m_size; }
    int components() const { return m_components; }
    // Members replaced per iteration: round(rate size), at least 1 (when rate > 0), at most size.
    uint32_t replacementsPerIteration() const { return m_replacements; }

    // The alpha update (sec. 4.5): alpha'_k = sum of the acceptance probabilities of component k
    // since the member was made, alpha_k = eps + (1 - eps) alpha'_k / sum alpha'.
    void adapt(std::vector<gpu::PmcErMember>& members) const;
    // Elimination: exactly replacementsPerIteration() members are eliminated when enough have
    // energy (members without energy go first, and when there are more of those, the rest stay
    // dead with E = 0); survivors' E is divided by their survival probability. The eliminated
    // slots to regenerate are returned; their members are reset to E = 0.
    PathResampleResult eliminate(std::vector<gpu::PmcErMember>& members, Pcg32& rng) const;

private:
    uint32_t m_size;
    int m_components;
    double m_epsilon;
    uint32_t m_replacements;
};

}  // namespace pmcr
