// PSSMLT's chains [push.first, push.first + push.count): with PSSMLT_FLAG_START each starts at
// its bootstrap sample (its primary vector regenerated, its path traced again); otherwise each
// makes push.steps Metropolis steps (pssmlt_chain.glsl), a new proposal as soon as the last path
// ends, so that SIMD lanes whose path ended early do not idle (as pt.comp does).
// The body of pssmlt_chains.comp and pssmlt_chains_all_lights.comp (PMCR_OTHER_LIGHTS).
#include "shared/host_device.h"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(push_constant, scalar) uniform PushBlock { PssmltPush push; };
#include "methods/pssmlt/pssmlt_chain.glsl"

layout(set = WORK_SET, binding = PSSMLT_BINDING_CHAIN_STARTS, scalar) readonly buffer StartBuffer {
    uint chainStarts[];
};
layout(set = WORK_SET, binding = PSSMLT_BINDING_CHAINS, scalar) buffer ChainBuffer {
    PssmltChain chains[];
};

// Chain `chain` at the primary vector of its bootstrap sample, iteration 0.
void startChain(uint chain, inout PssCounters c) {
    uint start = chainStarts[chain];
    for (uint d = 0u; d < push.dimensions; ++d) {
        float v = bootstrapCoordinate(push.seed, start, d);
        primarySamples[d * push.chainStride + chain] = PrimarySample(v, 0u, v, 0u);
    }
    PssmltChain st;
    st.iteration = 0u;
    st.lastLargeStep = 0u;
    st.rng = hash3(push.seed ^ 0x3c5a17e1u, chain, 0u);
    st.pad = 0u;
    Sampler s = pssChainSampler(chain, st);  // iteration 0: reads the coordinates as they are
    vec2 raster = pssRaster(s);
    PathState p = pathBegin(raster, 0u);
    for (uint b = 0u; b <= push.maxDepth; ++b)
        if (!pathBounce(p, s, push.maxDepth, push.rrDepth, c.rays)) break;
    st.radiance = p.L;
    st.pixel = pssPixel(raster);
    st.rng = s.rng.state;
    chains[chain] = st;
    c.paths += 1u;
}

void runChain(uint chain, inout PssCounters c) {
    PssmltChain st = chains[chain];
    Sampler s = pssChainSampler(chain, st);
    pssBeginIteration(s, push.largeStepProbability);
    vec2 raster = pssRaster(s);
    PathState p = pathBegin(raster, 0u);
    uint done = 0u;
    // Each path takes at most maxDepth + 1 bounces.
    uint bounces = push.steps * (push.maxDepth + 1u);
    for (uint b = 0u; b < bounces; ++b) {
        if (pathBounce(p, s, push.maxDepth, push.rrDepth, c.rays)) continue;
        pssStep(st, s, p.L, pssPixel(raster), c);
        done += 1u;
        if (done == push.steps) break;
        pssBeginIteration(s, push.largeStepProbability);
        raster = pssRaster(s);
        p = pathBegin(raster, 0u);
    }
    st.rng = s.rng.state;
    st.iteration = s.iteration;
    st.lastLargeStep = s.lastLargeStep;
    chains[chain] = st;
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    PssCounters c = pssCountersCreate();
    if (i < push.count) {
        uint chain = push.first + i;
        if ((push.flags & PSSMLT_FLAG_START) != 0u) startChain(chain, c);
        else runChain(chain, c);
    }
    flushPssCounters(c);
}
