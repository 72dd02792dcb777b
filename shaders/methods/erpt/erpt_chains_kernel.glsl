// ERPT: advances chains [chainBase, chainBase + chainCount) by push.steps mutations each.
//
// The body of erpt_chains.comp and erpt_chains_all_lights.comp (PMCR_OTHER_LIGHTS: punctual
// lights and the environment compiled in); the host picks the variant by the scene's lights
// (lightsKernelVariant, host/methods/pt/pt_integrator.h).
#include "shared/host_device.h"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(push_constant, scalar) uniform PushBlock { ErptPush push; };
#define FILM_BINDING ERPT_BINDING_SPLAT
#define COUNTERS_BINDING ERPT_BINDING_COUNTERS
#include "methods/energy_redistribution/erpt_chain.glsl"

layout(set = WORK_SET, binding = ERPT_BINDING_CHAINS, scalar) buffer ChainBuffer { ChainState chains[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    StepCounters counters = stepCountersCreate();
    if (i < push.chainCount) {
        uint chain = push.chainBase + i;
        ChainState st = chains[chain];
        Rng rng;
        rng.state = st.rng;
        AngleSampler angle = angleSampler(push.causticThetaMin, push.causticThetaMax, false);
        for (uint s = 0u; s < push.steps; ++s) {
            float a;
            bool caustic;
            chainStep(chain, st, rng, push.mutationMode, push.causticProbability, push.lensRadius,
                      angle, angle, push.flags, push.consecutiveCap, 1.0, counters, a, caustic);
        }
        st.rng = rng.state;
        chains[chain] = st;
    }
    flushStepCounters(counters);
}
