// Metropolis light transport over pmcr's path space (--method mlt; host/methods/mlt): chains of
// light paths (shared/chain_types.h ChainState, ChainVertex), mutated by ERPT's lens and caustic
// perturbations and by an independent mutation, a fresh path drawn by the one-path sampler of
// shaders/methods/mlt/independent_path.glsl.
//
// The kernels use the ERPT work-set bindings (chain states and vertices, splat film, counters,
// pixel statistics, energy sums) and these:
PMCR_CONST uint MLT_BINDING_WEIGHTS = 10;   // float[sample]: bootstrap weights lum(W) = F / p
PMCR_CONST uint MLT_BINDING_STARTS = 11;    // uint[chain]: the bootstrap sample it starts from
PMCR_CONST uint MLT_BINDING_ACCEPTED = 12;  // uint[pixel]: accepted mutations landing there

PMCR_CONST uint MLT_FLAG_START = 1u;  // mlt_seed: start chains (else: bootstrap weights)

struct MltPush {
    uint chainBase;          // mlt_chains: first chain of this dispatch; mlt_seed: first sample
    uint chainCount;         // invocations of this dispatch
    uint steps;              // mlt_chains: mutations per chain in this dispatch
    uint seed;
    uint maxDepth;           // bounces, at most PATH_MAX_VERTICES - 1
    uint mutationMode;       // MUTATION_* for the perturbations (chain_types.h)
    uint flags;              // MLT_FLAG_*
    float largeStep;         // probability of the independent mutation
    float lensRadius;        // pixels
    float causticThetaMin;   // radians
    float causticThetaMax;
    float causticProbability;
    uint minVertices;        // paths of fewer vertices have F = 0 (--direct separate: 3)
    uint pad0;
    uint pad1;
    uint pad2;
};
PMCR_CHECK_SIZE(MltPush, 64);
