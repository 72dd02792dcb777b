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
    uint cameraStride;         // over bdpt: camera subpath vertices per chain (maxDepth + 2)
    uint lightStride;          // over bdpt: light subpath vertices per chain (maxDepth + 1)
    uint sampleOffset;         // over bdpt, bootstrap: sample push.first + i is bootstrap sample
                               // push.first + i + sampleOffset (its weight's index push.first + i)
};
PMCR_CHECK_SIZE(PssmltPush, 60);

// PSSMLT over bidirectional path tracing (--over bdpt; Kelemen et al. 2002 sec. 4 with
// Veach 1997 ch. 10's estimator, as Mitsuba's PSSMLT): the primary vector drives one whole bdpt
// sample (shaders/methods/bdpt/: the camera subpath, the light subpath, every strategy (s, t)
// MIS-weighted) and F is the luminance of the sum of its contributions. Light tracing's (t = 1)
// contributions land on other pixels than the camera sample's, so a state is a list of splats
// (pixel, colour): its light tracing contributions, then the camera sample's pixel with the
// t >= 2 sum. One Metropolis step is three dispatches over the chains (pssmlt_bdpt_*.comp):
// the subpaths of the proposal, its connections into its splat list, then the expected-value
// deposits and the acceptance.

// Coordinates of a bdpt sample of up to maxDepth bounces: two per dimension of the bdpt
// kernels' sampler (pss_sampler.glsl PSS_SAMPLER_PAIRS), which are those below
// BDPT_CONNECT_DIMENSION, then the s = 1 light samples of camera vertices 0 .. maxDepth + 1 at
// BDPT_CONNECT_DIMENSION + 2 (t - 1), two each (bdpt_vertex.glsl).
#define PSSMLT_BDPT_DIMENSIONS(maxDepth) (2u * (BDPT_CONNECT_DIMENSION(maxDepth) + 2u * ((maxDepth) + 2u)))
// Multiplexed MLT (`mmlt`; Hachisuka, Kaplanyan and Dachsbacher 2014, as pbrt-v4's
// MLTIntegrator) runs the same three dispatches (the mmlt_*.comp kernels: the pssmlt_bdpt
// bodies with PSS_MULTIPLEXED) over chains of a fixed depth d: a proposal picks one strategy
// (s, t), s + t = d + 2, from the coordinates at MMLT_STRATEGY_DIMENSION, walks a camera subpath
// of exactly t vertices and a light subpath of s, and evaluates only that connection, its MIS
// weight times the d + 2 strategies (eq. 6 of the paper; pbrt-v4 MLTIntegrator::L). Its list is
// one splat. The three streams of pbrt-v4 (camera, light, connection) are bdpt's dimension
// ranges: from 0, from BDPT_LIGHT_DIMENSION, from BDPT_CONNECT_DIMENSION.
#define MMLT_STRATEGY_DIMENSION(maxDepth) (BDPT_CONNECT_DIMENSION(maxDepth) + 2u * ((maxDepth) + 2u))
#define MMLT_DIMENSIONS(maxDepth) (2u * (MMLT_STRATEGY_DIMENSION(maxDepth) + 1u))
// mmlt's bootstrap sample k of depth d is sample number (d << MMLT_DEPTH_SHIFT) + k: its primary
// vector's hashes (pss_mutation.glsl bootstrapCoordinate) and its chain's depth come from it.
// 2^25 samples of each of the at most 101 depths.
PMCR_CONST uint MMLT_DEPTH_SHIFT = 25u;
// Splats in a state's list: at most one per light vertex s >= 2 (t = 1) and the camera pixel's.
#define PSSMLT_BDPT_SPLATS(maxDepth) ((maxDepth) + 2u)

struct PssmltSplat {
    vec3 rgb;    // the contribution (MIS-weighted)
    uint pixel;
};
PMCR_CHECK_SIZE(PssmltSplat, 16);

// The chain state over bdpt; its splat lists are at PSSMLT_BINDING_SPLATS, list 0 the current
// state x's and list 1 the proposal y's: PssmltSplat[(2 chain + list) * PSSMLT_BDPT_SPLATS + k].
struct PssmltBdptChain {
    uint rng;                  // Rng state (mutations, acceptance, splat rounding)
    uint iteration;            // accepted steps so far, plus the proposal's between its dispatches
    uint lastLargeStep;        // the iteration of the last accepted large step
    uint largeStep;            // 1: the proposal is a large step
    uint currentCount;         // splats in x's list
    uint proposalCount;        // splats in y's list
    uint proposalPixel;        // y's camera sample pixel
    uint depth;                // mmlt: the chain's path depth (bounces), fixed at its start
    uint strategy;             // mmlt: the proposal's s (light vertices); t = depth + 2 - s
    // The proposal's reads, as the dimension after the last one it read in each range (camera
    // from 0, light from BDPT_LIGHT_DIMENSION, connection from BDPT_CONNECT_DIMENSION): a
    // rejection restores only these (pss_bdpt.glsl pssBdptReject).
    uint cameraEnd;
    uint lightEnd;
    uint connectEnd;
};
PMCR_CHECK_SIZE(PssmltBdptChain, 48);

// Work-set bindings of the pssmlt-over-bdpt kernels, besides 0 .. 3, 6, 7 and 9 above.
PMCR_CONST uint PSSMLT_BINDING_CAMERA_VERTICES = 10;  // BdptVertex[chain * cameraStride + i]
PMCR_CONST uint PSSMLT_BINDING_LIGHT_VERTICES = 11;   // BdptVertex[chain * lightStride + i]
PMCR_CONST uint PSSMLT_BINDING_VERTEX_COUNTS = 12;    // uvec2[chain]
PMCR_CONST uint PSSMLT_BINDING_SPLATS = 13;           // PssmltSplat[]: the chains' splat lists
PMCR_CONST uint PSSMLT_BINDING_BDPT_CHAINS = 14;      // PssmltBdptChain[chain]

// Over bdpt, with PSSMLT_FLAG_START: the chains are slots 0 .. count - 1 of bootstrap samples
// first .. first + count - 1, whose F the last kernel writes to the weights.
PMCR_CONST uint PSSMLT_FLAG_BOOTSTRAP = 2u;
