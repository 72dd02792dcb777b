// ERPT's seeds (methods/energy_redistribution/seed_paths.glsl) and how many chains each starts.
//
// Equal deposition (ERPT fig. 6): a path of energy e starts numChains = floor(U + e / (m e_d))
// chains of m mutations, each depositing e_d per mutation; E[numChains m e_d] = e, unbiased.
#ifndef PMCR_ERPT_SEEDS_GLSL
#define PMCR_ERPT_SEEDS_GLSL

#include "methods/energy_redistribution/seed_paths.glsl"

// Chains started by seed path s of record r; the random number comes from (seed, pass, r, s)
// so that the counting and the writing kernels agree.
uint seedChainCount(PathRecord rec, uint r, uint s) {
    vec3 c = seedContribution(rec, s);
    float e = luminance(c) * push.seedScale;
    if (!(e > 0.0) || !isFinite(c)) return 0u;
    if ((push.flags & ERPT_FLAG_DEPOSIT_DIRECT) != 0u && isDirectSeed(s)) return 0u;
    Rng rng = rngCreate(hash3(push.seed ^ 0x5eedc4a1u, push.pass, r * (2u * PATH_MAX_VERTICES) + s));
    float chains = floor(rngNext(rng) + e / (float(push.chainLength) * push.depositEnergy));
    return uint(min(chains, 4.0e9));
}

#endif
