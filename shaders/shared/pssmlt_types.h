// Primary-sample-space MLT (Kelemen, Szirmay-Kalos, Antal and Csonka 2002) over the path tracer.
//
// A chain's state is the vector u in [0,1)^D of the random numbers the path tracer draws
// (shaders/methods/pt/path_tracer.glsl): the camera's raster position (2), then per bounce the
// light choice (1), the point on the light (2), the lobe (1), the direction (2) and Russian
// roulette (1). Coordinate j of chain c is a PrimarySample at index j * chainStride + c, mutated
// lazily as pbrt-v3's MLTSampler does (shaders/methods/pssmlt/pss_sampler.glsl): it is brought
// up to date only when the path reads it, and backed up so that a rejection restores it.

// Coordinates of a path of up to maxDepth bounces: 2 for the camera, 7 per bounce (the last
// bounce, at maxDepth, draws 6: no roulette).
#define PSSMLT_DIMENSIONS(maxDepth) (2u + 7u * ((maxDepth) + 1u))
PMCR_CONST uint PSSMLT_MAX_DEPTH = 100u;  // --max-depth beyond this is an error for pssmlt

struct PrimarySample {
    float value;               // in [0, 1)
    uint lastModification;     // the chain iteration that last set `value`
    float valueBackup;         // before this iteration's change (restored on rejection)
    uint modificationBackup;
};
PMCR_CHECK_SIZE(PrimarySample, 16);

struct PssmltChain {
    vec3 radiance;             // L(x): the path tracer's estimate for the current vector x
    uint pixel;                // x's pixel
    uint rng;                  // Rng state (mutations, acceptance, splat rounding)
    uint iteration;            // accepted steps so far (pbrt-v3 MLTSampler::currentIteration)
    uint lastLargeStep;        // the iteration of the last accepted large step
    uint pad;
};
PMCR_CHECK_SIZE(PssmltChain, 32);

// Work-set bindings of the pssmlt kernels. 6 (splat film), 7 (counters) and 9 (energy sums)
// are ERPT's (shared/chain_types.h), so that splat.glsl and the RedistributionBatch serve both.
PMCR_CONST uint PSSMLT_BINDING_WEIGHTS = 0;          // float[]: F(u_i) of each bootstrap sample
PMCR_CONST uint PSSMLT_BINDING_CHAIN_STARTS = 1;     // uint[chain]: its bootstrap sample
PMCR_CONST uint PSSMLT_BINDING_CHAINS = 2;           // PssmltChain[chain]
PMCR_CONST uint PSSMLT_BINDING_PRIMARY_SAMPLES = 3;  // PrimarySample[dimension * stride + chain]

PMCR_CONST uint PSSMLT_FLAG_START = 1u;  // chains kernel: start the chains (no mutation)

struct PssmltPush {
    uint first;                // bootstrap: first sample; chains: first chain of this dispatch
    uint count;                // samples or chains in this dispatch
    uint itemsPerInvocation;   // bootstrap: samples per invocation, in turn (0 or 1: one)
    uint steps;                // chains: mutations per chain in this dispatch
    uint seed;                 // render seed
    uint maxDepth;
    uint rrDepth;
    uint dimensions;           // PSSMLT_DIMENSIONS(maxDepth)
    uint chainStride;          // chains allocated: the stride of the primary-sample storage
    uint flags;                // PSSMLT_FLAG_*
    float largeStepProbability;
    float sigma;               // standard deviation of a small step (Gaussian, wrapped)
};
PMCR_CHECK_SIZE(PssmltPush, 48);
