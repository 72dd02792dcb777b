// PMC-ER's population of light paths between two GPU iterations (Lai, Fan, Chenney and Dyer
// 2007, sec. 4.5): the alpha update, elimination by remaining energy and the choice of slots to
// regenerate. Pure C++ over the members' bookkeeping (shared/pmc_er_types.h PmcErMember); the
// paths themselves stay on the device.
//
// Energy contract. A member's E_remain counts the deposits it still owes the image, each of
// `shares` e_d. A mutation deposits and takes one from E_remain; below one, the last deposit is
// made with probability E_remain (Russian roulette, shaders/methods/pmc_er/pmc_er_mutate.comp). At
// elimination member i survives with probability p_i and a survivor's E_remain becomes
// E_remain / p_i; a member eliminated deposits nothing more. When a pass ends the members go on
// mutating without regeneration (the drain) and deposit whatever is left at once. By induction over
// the steps, the expected number of deposits a member still makes equals its E_remain at any time:
// a mutation gives 1 + (E - 1) for E >= 1 and E * 1 + 0 below; elimination gives
// p_i (E / p_i) + (1 - p_i) 0 = E; the end gives E. So every member deposits, in expectation,
// exactly its initial energy, and the image's expected total energy is the seeds'
// (tests/host/test_path_population.cpp, tests/stat/test_pmc_er.cpp).
//
// Energy in expectation is necessary, not sufficient, for an unbiased image. ERPT starts chains
// of a fixed length m in proportion to the seed's energy, so at every step the expected deposits
// are those of f-invariant chains started from f, which are f. With the paper's births
// (E_remain = the path's energy E, one share) a member's lifetime grows with E, and a chain of
// lifetime n(x0) deposits the average of K^1..K^n(x0) from x0, not f-invariant when n depends on
// x0. Two states A, B with f = 1 each, K the swap (reversible for f), p(A) = 0.9, p(B) = 0.1, so
// e(A) ~ 1.1, e(B) = 10; with e_d = 1.1 a path from A lives one step (deposits at B), one from B
// nine (A five times, B four): E[A] = 0.1 * 5 * 1.1 = 0.55, E[B] = 0.9 * 1.1 + 0.1 * 4 * 1.1 =
// 1.43, not 1 and 1. In images this blurs: long-lived bright paths spread their energy, short-lived
// dark ones keep theirs, so dark pixels come out too bright and bright ones too dark
// (tests/stat/test_pmc_er.cpp has the numbers). Equal births (the default) make every member
// start with the same E_remain = Q and carry n = floor(U + E / Q) shares (E[n Q] = E): the
// lifetime law then depends on nothing but the survival coins and E_remain histories, never on
// the member's path, and a member is n ERPT chains of one common trajectory. Survival by
// E_remain stays independent of the path for the same reason.
//
// Alpha adapted from a member's own acceptances is adaptive MCMC: in principle not exactly
// f-invariant either; the z-test does not detect it (pmc-er:epsilon=1 turns adaptation off).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/random.h"
#include "methods/pmc_pt/pixel_population.h"
#include "shared/host_device.h"

namespace pmcr {

// Survival probabilities p_i = min(1, c E_i) with sum p_i = keep (PMC-ER sec. 4.5: survival
// proportional to E_remain, capped at one by "water filling"). Members with E <= 0 get 0; when
// at most `keep` members have energy, each of them gets 1.
std::vector<double> survivalProbabilities(const std::vector<double>& energy, uint32_t keep);

// Systematic sampling (Madow 1949) of members with inclusion probabilities p (each <= 1, sum an
// integer n): exactly n members, member i with probability p_i. `u` is uniform in [0, 1).
std::vector<bool> systematicSample(const std::vector<double>& p, double u);

// The slots of the members with energy (E_remain > 0), ordered by their current pixel, then
// slot: the list the mutation kernel runs through (shared/pmc_er_types.h PMC_ER_BINDING_ACTIVE).
std::vector<uint32_t> activeMembers(const std::vector<gpu::PmcErMember>& members);

struct PathResampleResult {
    std::vector<uint32_t> regenerate;  // slots to refill from the pool, in ascending order
    uint32_t eliminated = 0;           // members eliminated (with and without energy)
    uint32_t survivors = 0;
    double energyBefore = 0.0;         // sum of E before and after (equal in expectation)
    double energyAfter = 0.0;
};

class PathPopulation {
public:
    // adaptRate r: adapt() moves alpha the share r of the way to the update (beyond the paper,
    // whose update is r = 1; r = 0 keeps every member's weights as they were born).
    PathPopulation(uint32_t size, int components, double resampleRate, double epsilon, double adaptRate = 1.0);

    uint32_t size() const { return m_size; }
    int components() const { return m_components; }
    // Members replaced per iteration: round(rate size), at least 1 (when rate > 0), at most size.
    uint32_t replacementsPerIteration() const { return m_replacements; }

    // The alpha update (sec. 4.5): alpha'_k = sum of the acceptance probabilities of component k
    // since the member was made, alpha_k = eps + (1 - eps) alpha'_k / sum alpha'; with adaptRate
    // r, alpha <- (1 - r) alpha + r (that update).
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
    double m_adaptRate;
    uint32_t m_replacements;
};

}  // namespace pmcr
