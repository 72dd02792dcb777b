// PSSMLT over bdpt (shared/pssmlt_types.h): the chain state and splat lists the three kernels of
// a step share (pssmlt_bdpt_subpaths_kernel.glsl, pssmlt_bdpt_connect_kernel.glsl,
// pssmlt_bdpt_step.comp), and the sampler over a chain's primary vector that the bdpt walks and
// connections read (pss_sampler.glsl, a dimension to a pair of coordinates).
#ifndef PMCR_PSS_BDPT_GLSL
#define PMCR_PSS_BDPT_GLSL

#define PSS_SAMPLER_PAIRS
#include "methods/pssmlt/pss_sampler.glsl"

layout(set = WORK_SET, binding = PSSMLT_BINDING_BDPT_CHAINS, scalar) buffer BdptChainBuffer {
    PssmltBdptChain chains[];
};
layout(set = WORK_SET, binding = PSSMLT_BINDING_SPLATS, scalar) buffer SplatListBuffer {
    PssmltSplat splatLists[];
};

// The chain of invocation i: slot i while bootstrapping, else chain push.first + i.
uint pssBdptChain(uint i) { return (push.flags & PSSMLT_FLAG_BOOTSTRAP) != 0u ? i : push.first + i; }

// Entry k of chain's list: 0 the current state x's, 1 the proposal y's.
uint pssSplatIndex(uint chain, uint list, uint k) {
    return (2u * chain + list) * PSSMLT_BDPT_SPLATS(push.maxDepth) + k;
}

// mmlt: the strategies of a path of `depth` bounces that one proposal picks from: (s, t) with
// s + t = depth + 2 and t >= 1, but only (0, 2) at depth 0 ((1, 1) is never evaluated, as in
// bdpt: the camera sees a light through (0, 2); pbrt-v4 MLTIntegrator::L).
uint mmltStrategies(uint depth) { return depth == 0u ? 1u : depth + 2u; }

// The sampler of chain `chain` in state st, at its proposal (st.iteration; at 0 the start, which
// reads the coordinates as they are), at dimension 0. While bootstrapping, chain is a slot and
// the sampler reads bootstrap sample push.first + chain + push.sampleOffset, which nothing stores.
Sampler pssBdptSampler(uint chain, PssmltBdptChain st) {
    Sampler s = pssSampler(push, chain, st.rng, st.iteration, st.lastLargeStep, st.largeStep != 0u);
    if ((push.flags & PSSMLT_FLAG_BOOTSTRAP) != 0u) s.bootstrapSample = push.first + chain + push.sampleOffset;
    return s;
}

// Restores the coordinates the rejected proposal of chain st changed: those its kernels read,
// range by range (st's ends, which they record), and mmlt's strategy, the last pair (none over
// bdpt). Restoring every coordinate, as before, took as long as mmlt's walks on lavapipe (292
// coordinates at --max-depth 16, of which a step reads about 10).
void pssBdptReject(inout Sampler s, PssmltBdptChain st) {
    pssRestore(s, 0u, 2u * st.cameraEnd);
    pssRestore(s, 2u * BDPT_LIGHT_DIMENSION(push.maxDepth), 2u * st.lightEnd);
    pssRestore(s, 2u * BDPT_CONNECT_DIMENSION(push.maxDepth), 2u * st.connectEnd);
    pssRestore(s, 2u * MMLT_STRATEGY_DIMENSION(push.maxDepth), s.dimensions);
    s.iteration -= 1u;
}

#endif
