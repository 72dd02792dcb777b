// The path tracer's sampler for PSSMLT's bootstrap (Veach 1997 sec. 11.3.1): a uniform primary
// vector per sample, coordinate j of sample i being bootstrapCoordinate(seed, i, j)
// (pss_mutation.glsl), so that a chain started at sample i regenerates the very same vector.
//
// Defines the Sampler of shaders/methods/pt/path_tracer.glsl (PMCR_CUSTOM_SAMPLER): include this
// file before it.
#ifndef PMCR_BOOTSTRAP_SAMPLER_GLSL
#define PMCR_BOOTSTRAP_SAMPLER_GLSL

#define PMCR_CUSTOM_SAMPLER
#include "methods/pssmlt/pss_mutation.glsl"

struct Sampler {
    uint seed;
    uint sampleIndex;
    uint dimension;  // next coordinate
};

Sampler bootstrapSampler(uint seed, uint sampleIndex) {
    Sampler s;
    s.seed = seed;
    s.sampleIndex = sampleIndex;
    s.dimension = 0u;
    return s;
}

float samplerGet1D(inout Sampler s) {
    s.dimension += 1u;
    return bootstrapCoordinate(s.seed, s.sampleIndex, s.dimension - 1u);
}

vec2 samplerGet2D(inout Sampler s) {
    float u = samplerGet1D(s);
    return vec2(u, samplerGet1D(s));
}

#endif
