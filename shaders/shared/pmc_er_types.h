// PMC energy redistribution (Lai, Fan, Chenney and Dyer 2007): the population of light paths.
// Member i's path lives in chain slot i (shared/chain_types.h ChainState, two vertex slots);
// its bookkeeping is a PmcErMember. The host resamples and adapts between iterations
// (host/methods/pmc_er/path_population.h); the kernels mutate and deposit.

PMCR_CONST uint PMC_ER_MAX_RADII = 3;  // strategy image: red, green, blue

struct PmcErMember {
    float remaining;     // E_remain in mutations left: each deposits `shares` e_d; <= 0: dead
    vec3 alpha;          // mixture weights of the radius components (eq. 5), sum 1
    vec3 acceptSum;      // alpha'_k: sum of acceptance probabilities per component (sec. 4.5)
    uint mutations;      // mutations made since the last count (the host resets it)
    float shares;        // e_d per deposit: 1 with the paper's births; n with equal births
    uint pixel;          // the current path's pixel: the host orders the active list by it
};
PMCR_CHECK_SIZE(PmcErMember, 40);

// How a member is born from a path of energy E (units of e_d), PmcErPush.birthEnergy.
PMCR_CONST uint PMC_ER_BIRTH_EQUAL = 0;  // E_remain = Q, shares n = floor(U + E / Q) (n = 0: none)
PMCR_CONST uint PMC_ER_BIRTH_PATH = 1;   // the paper's: E_remain = E, shares 1

// PmcErPush.flags beyond ERPT_FLAG_DEPOSIT_DIRECT (shared/chain_types.h):
PMCR_CONST uint PMC_ER_FLAG_MIXTURE_ACCEPTANCE = 16u;  // eq. 8 over the radii, not eq. 9

// Work-set bindings: ERPT's 0..9 (shared/chain_types.h) keep their meaning, then:
PMCR_CONST uint PMC_ER_BINDING_MEMBERS = 10;     // PmcErMember[population]
PMCR_CONST uint PMC_ER_BINDING_STRATEGY = 11;    // uint[pixel * 3 + component]: mutations made there
PMCR_CONST uint PMC_ER_BINDING_SEED_SLOTS = 12;  // uint[]: member slot of each new path's record
// uint[]: the members with energy, ordered by their current pixel; mutate's invocation i works
// on member activeList[memberBase + i]. Neighbouring invocations then trace neighbouring paths
// (coherent traversal on a SIMD device) and no invocation idles on a dead member.
PMCR_CONST uint PMC_ER_BINDING_ACTIVE = 13;

struct PmcErPush {
    uint memberBase;         // mutate: first entry of the active list; finish: first member
    uint memberCount;        // entries (mutate), members (finish) or new paths (seed)
    uint steps;              // mutate: mutations per member in this dispatch
    uint seed;
    uint pass;
    uint iteration;
    uint componentCount;     // radii in use, 1..PMC_ER_MAX_RADII
    float seedScale;         // seed: a path's energy in units of e_d per unit of luminance
    vec3 radii;              // pixels
    float causticProbability;// gamma_caustic where the caustic perturbation applies (0.9)
    float lensThetaMin;      // lens perturbation's angles past a D vertex (log-uniform, ERPT)
    float lensThetaMax;
    uint birth;              // PMC_ER_BIRTH_*
    float birthEnergy;       // Q, units of e_d (PMC_ER_BIRTH_EQUAL)
    uint flags;              // ERPT_FLAG_DEPOSIT_DIRECT (shared/chain_types.h): seed paths
                             // with at most one scattering vertex go to their own pixel;
                             // PMC_ER_FLAG_MIXTURE_ACCEPTANCE
    uint slotBase;           // seed: first entry of the seed-slot list this dispatch reads
    uint pad1;
    uint pad2;
    vec3 initialAlpha;       // seed: a new member's radius weights (sum 1; --initial-alpha)
    float pad3;
};
PMCR_CHECK_SIZE(PmcErPush, 96);
