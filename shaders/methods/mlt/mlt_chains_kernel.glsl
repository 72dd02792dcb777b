// MLT: advances chains [chainBase, chainBase + chainCount) by push.steps mutations each. A step
// is the independent mutation with probability push.largeStep (independent_path.glsl), else
// ERPT's lens or caustic perturbation (erpt_chain.glsl chainStep, the same code ERPT runs: the
// ERPT paper's comparison shares the mutations between MLT and ERPT, sec. 5). Deposits are
// expected values: a at the proposal, 1 - a at the current path, in units of e_d
// (host/methods/mlt/mlt_integrator.cpp sets e_d = b_hat / mutations per pass).
//
// The body of mlt_chains.comp and mlt_chains_all_lights.comp (PMCR_OTHER_LIGHTS).
#include "shared/host_device.h"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(push_constant, scalar) uniform PushBlock { MltPush push; };
#define FILM_BINDING ERPT_BINDING_SPLAT
#define COUNTERS_BINDING ERPT_BINDING_COUNTERS
#include "methods/energy_redistribution/erpt_chain.glsl"
#include "methods/mlt/independent_path.glsl"

layout(set = WORK_SET, binding = ERPT_BINDING_CHAINS, scalar) buffer ChainBuffer { ChainState chains[]; };
layout(set = WORK_SET, binding = MLT_BINDING_ACCEPTED, scalar) buffer AcceptedBuffer { uint accepted[]; };

// The independent mutation: y from the sampler, a = min(1, W(y) / W(x)) (T(x -> y) = p(y)).
// Returns whether y was accepted.
bool independentStep(uint chain, inout ChainState st, inout Rng rng, inout StepCounters counters) {
    uint yBase = pathBase(chain, st.slot ^ 1u);
    vec2 rasterY;
    uint kY;
    vec3 throughputY = vec3(0.0), throughputX;
    float wY = 0.0;
    // (With --direct separate, paths of fewer than push.minVertices vertices are not the chains'.)
    if (sampleIndependentPath(yBase, push.maxDepth, rng, counters.rays, rasterY, kY) && kY >= push.minVertices)
        wY = luminance(independentWeight(yBase, kY, push.maxDepth, throughputY));
    float wX = luminance(independentWeight(pathBase(chain, st.slot), st.vertexCount, push.maxDepth, throughputX));
    float a = 0.0;
    if (wY > 0.0 && isFinite(wY) && !isnan(wX)) a = wX > 0.0 ? min(1.0, wY / wX) : 1.0;
    if (!(wY > 0.0)) counters.invalid += 1u;
    else atomicAdd(pixelStats[rasterPixel(rasterY)].proposals, 1u);
    if (a > 0.0) depositAt(st, rasterPixel(rasterY), throughputY, a, rng, 0u, counters);
    depositAt(st, rasterPixel(st.raster), st.throughput, 1.0 - a, rng, 0u, counters);
    if (!(rngNext(rng) < a)) return false;
    st.slot ^= 1u;
    st.raster = rasterY;
    st.vertexCount = kY;
    st.throughput = throughputY;
    return true;
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    StepCounters counters = stepCountersCreate();
    uint largeProposed = 0u, largeAccepted = 0u;
    if (i < push.chainCount) {
        uint chain = push.chainBase + i;
        ChainState st = chains[chain];
        Rng rng;
        rng.state = st.rng;
        AngleSampler angle = angleSampler(push.causticThetaMin, push.causticThetaMax, false);
        for (uint s = 0u; s < push.steps; ++s) {
            bool moved;
            if (rngNext(rng) < push.largeStep) {
                largeProposed += 1u;
                moved = independentStep(chain, st, rng, counters);
                if (moved) largeAccepted += 1u;
            } else {
                uint slot = st.slot;
                float a;
                bool caustic;
                chainStep(chain, st, rng, push.mutationMode, push.causticProbability, push.lensRadius,
                          angle, angle, ERPT_FLAG_EXPECTED_VALUES, 0u, 1.0, counters, a, caustic);
                moved = st.slot != slot;
            }
            if (moved) atomicAdd(accepted[rasterPixel(st.raster)], 1u);
        }
        st.rng = rng.state;
        chains[chain] = st;
    }
    flushStepCounters(counters);
    counterAdd(COUNTER_LARGE_PROPOSED, largeProposed);
    counterAdd(COUNTER_LARGE_ACCEPTED, largeAccepted);
}
