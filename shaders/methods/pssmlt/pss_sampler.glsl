// The path tracer's sampler over a chain's primary sample vector (Kelemen et al. 2002 sec. 3):
// samplerGet1D / samplerGet2D read the chain's coordinates in order, mutating each lazily when
// it is first read in an iteration, as pbrt-v3's MLTSampler does (Pharr, Jakob and Humphreys,
// PBR 3rd ed., sec. 16.4.3): a coordinate last set at iteration m, read at iteration t,
//   - is drawn anew (uniform) when a large step was accepted after m (the value it would have
//     had since), then
//   - is drawn anew when this iteration is a large step, or else takes the t - m small steps of
//     the accepted iterations in between in one (smallStep, pss_mutation.glsl).
// Iterations count accepted steps plus the one being proposed: on rejection every coordinate
// set in this iteration goes back to its backup and the iteration number is reused.
//
// Defines the Sampler of shaders/methods/pt/path_tracer.glsl (PMCR_CUSTOM_SAMPLER): include this
// file before it. With PSS_SAMPLER_PAIRS it is the Sampler of the bdpt kernels instead. The
// including kernel declares nothing else at PSSMLT_BINDING_PRIMARY_SAMPLES.
#ifndef PMCR_PSS_SAMPLER_GLSL
#define PMCR_PSS_SAMPLER_GLSL

#define PMCR_CUSTOM_SAMPLER
#include "methods/pssmlt/pss_mutation.glsl"

layout(set = WORK_SET, binding = PSSMLT_BINDING_PRIMARY_SAMPLES, scalar) buffer PrimarySampleBuffer {
    PrimarySample primarySamples[];
};

struct Sampler {
    uint chain;          // column of the primary-sample storage
    uint stride;         // its row length (chains allocated)
    uint dimensions;     // coordinates stored per chain
    uint dimension;      // next coordinate to read
    uint iteration;      // the iteration being proposed (0: the start, nothing mutates)
    uint lastLargeStep;  // the iteration of the last accepted large step
    bool largeStep;
    float sigma;
    Rng rng;
    uint seed;             // the render's: bootstrap coordinates (pss_mutation.glsl)
    uint bootstrapSample;  // PSS_NO_BOOTSTRAP, or the bootstrap sample whose vector this reads
};

// A sampler of a chain, not of a bootstrap sample.
const uint PSS_NO_BOOTSTRAP = 0xffffffffu;

// Brings coordinate d up to date for this iteration (pbrt-v3 MLTSampler::EnsureReady) and
// returns it.
float pssCoordinateAt(inout Sampler s, uint d) {
    // Beyond the storage (never with dimensions = PSSMLT_DIMENSIONS(maxDepth)): a fresh number.
    if (d >= s.dimensions) return rngNext(s.rng);
    // A bootstrap sample's vector is its coordinates' hashes, which a chain started at it stores:
    // read without storing the vector (292 coordinates at --max-depth 16 over bdpt, where a
    // sample reads about 10).
    if (s.bootstrapSample != PSS_NO_BOOTSTRAP) return bootstrapCoordinate(s.seed, s.bootstrapSample, d);
    uint index = d * s.stride + s.chain;
    PrimarySample x = primarySamples[index];
    if (x.lastModification == s.iteration) return x.value;  // the start, or read twice
    // A large step accepted since x was set resampled it.
    if (x.lastModification < s.lastLargeStep) {
        x.value = rngNext(s.rng);
        x.lastModification = s.lastLargeStep;
    }
    x.valueBackup = x.value;
    x.modificationBackup = x.lastModification;
    if (s.largeStep) x.value = rngNext(s.rng);
    else x.value = smallStep(x.value, s.sigma, s.iteration - x.lastModification, s.rng);
    x.lastModification = s.iteration;
    primarySamples[index] = x;
    return x.value;
}

// The sampler of chain `chain` at dimension 0, from its state (rng, iteration, last large step,
// whether the proposal is a large step) and the kernel's push constants p (the storage's row
// length, the coordinates stored, the small step's sigma). Over pt and over bdpt.
Sampler pssSampler(PssmltPush p, uint chain, uint rng, uint iteration, uint lastLargeStep, bool largeStep) {
    Sampler s;
    s.chain = chain;
    s.stride = p.chainStride;
    s.dimensions = p.dimensions;
    s.dimension = 0u;
    s.iteration = iteration;
    s.lastLargeStep = lastLargeStep;
    s.largeStep = largeStep;
    s.sigma = p.sigma;
    s.rng.state = rng;
    s.seed = p.seed;
    s.bootstrapSample = PSS_NO_BOOTSTRAP;
    return s;
}

#ifdef PSS_SAMPLER_PAIRS
// A dimension is a pair of coordinates, 2 d and 2 d + 1, whether the caller draws one number or
// two: the dimensions of common/sampler.glsl, which the bdpt kernels address (bdpt_vertex.glsl).
float samplerGet1D(inout Sampler s) {
    s.dimension += 1u;
    return pssCoordinateAt(s, 2u * s.dimension - 2u);
}

vec2 samplerGet2D(inout Sampler s) {
    s.dimension += 1u;
    float u = pssCoordinateAt(s, 2u * s.dimension - 2u);
    return vec2(u, pssCoordinateAt(s, 2u * s.dimension - 1u));
}
#else
// Coordinate `dimension`, the next one.
float pssCoordinate(inout Sampler s) {
    uint d = s.dimension;
    s.dimension += 1u;
    return pssCoordinateAt(s, d);
}

float samplerGet1D(inout Sampler s) { return pssCoordinate(s); }

vec2 samplerGet2D(inout Sampler s) {
    float u = pssCoordinate(s);
    return vec2(u, pssCoordinate(s));
}
#endif

// Starts a proposal: iteration + 1, a large step with probability `largeStepProbability`.
void pssBeginIteration(inout Sampler s, float largeStepProbability) {
    s.iteration += 1u;
    s.largeStep = rngNext(s.rng) < largeStepProbability;
    s.dimension = 0u;
}

void pssAccept(inout Sampler s) {
    if (s.largeStep) s.lastLargeStep = s.iteration;
}

// Restores coordinates [begin, end) that this iteration changed.
void pssRestore(Sampler s, uint begin, uint end) {
    for (uint d = begin; d < min(end, s.dimensions); ++d) {
        uint index = d * s.stride + s.chain;
        if (primarySamples[index].lastModification == s.iteration) {
            primarySamples[index].value = primarySamples[index].valueBackup;
            primarySamples[index].lastModification = primarySamples[index].modificationBackup;
        }
    }
}

#ifndef PSS_SAMPLER_PAIRS
// Restores the coordinates this iteration changed (those read, 0 .. dimension - 1). Over bdpt,
// whose reads are spread over kernels: pssBdptReject (pss_bdpt.glsl).
void pssReject(inout Sampler s) {
    pssRestore(s, 0u, s.dimension);
    s.iteration -= 1u;
}
#endif

#endif
