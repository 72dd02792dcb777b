#version 460
// PSSMLT over bdpt, the last dispatch of a step (shared/pssmlt_types.h): per chain, the
// Metropolis step of Kelemen et al. 2002 sec. 4 on the proposal y whose splat list the connect
// kernel wrote. F = lum(sum of the list's contributions); a = min(1, F(y) / F(x)) (eq. 6, the
// mutations being symmetric); the step's deposit replaced by its expected value (Veach 1997
// sec. 11.3.4): a e_d spread over y's list and (1 - a) e_d over x's, splat k of a state with
// colour c_k receiving its share c_k / F, so that a state deposits its contributions in
// proportion, summing to one e_d of luminance. Then y is accepted with probability a (its list
// becomes x's) or its coordinates restored (pss_sampler.glsl).
// With PSSMLT_FLAG_START: y is the chain's start, which becomes x, no deposit; with
// PSSMLT_FLAG_BOOTSTRAP as well, F(y) of bootstrap sample push.first + i goes to the weights.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "shared/host_device.h"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(push_constant, scalar) uniform PushBlock { PssmltPush push; };

#include "methods/pssmlt/pss_deposit.glsl"
#include "methods/pssmlt/pss_bdpt.glsl"
#include "common/scene.glsl"
#include "methods/pssmlt/pss_path.glsl"

layout(set = WORK_SET, binding = PSSMLT_BINDING_WEIGHTS, scalar) writeonly buffer WeightBuffer {
    float weights[];
};

// The sum of the contributions in chain's list.
vec3 listSum(uint chain, uint list, uint count) {
    vec3 sum = vec3(0.0);
    for (uint k = 0u; k < count; ++k) sum += splatLists[pssSplatIndex(chain, list, k)].rgb;
    return sum;
}

// Deposits `amount` e_d spread over chain's list whose target is F: rgb / F at each splat's
// pixel (luminance lum(rgb) / F of the amount; pssDeposit).
void depositList(uint chain, uint list, uint count, float F, float amount, inout Rng rng,
                 inout PssCounters c) {
    if (!(amount > 0.0)) return;
    for (uint k = 0u; k < count; ++k) {
        PssmltSplat e = splatLists[pssSplatIndex(chain, list, k)];
        if (!(maxComponent(e.rgb) > 0.0) && isFinite(e.rgb)) continue;  // nothing to deposit
        c.deposits += 1u;
        if (!(F > 0.0) || !splatDeposit(e.pixel, e.rgb / F, amount, rng)) {
            c.dropped += 1u;
            continue;
        }
        c.deposited += amount * luminance(e.rgb) / F;
    }
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    PssCounters c = pssCountersCreate();
    if (i < push.count) {
        uint chain = pssBdptChain(i);
        PssmltBdptChain st = chains[chain];
        vec3 Ly = listSum(chain, 1u, st.proposalCount);
        float Fy = pssTarget(Ly);
        c.paths += 1u;
        if (!isFinite(Ly)) c.nanPaths += 1u;
        if ((push.flags & PSSMLT_FLAG_BOOTSTRAP) != 0u) {
            weights[push.first + i] = Fy;
        } else if ((push.flags & PSSMLT_FLAG_START) != 0u) {
            for (uint k = 0u; k < st.proposalCount; ++k)
                splatLists[pssSplatIndex(chain, 0u, k)] = splatLists[pssSplatIndex(chain, 1u, k)];
            st.currentCount = st.proposalCount;
            chains[chain] = st;
        } else {
            Sampler s = pssBdptSampler(chain, st);
            float Fx = pssTarget(listSum(chain, 0u, st.currentCount));
            // Kelemen et al. 2002 eq. 6 with T(x -> y) = T(y -> x).
            float a = Fx > 0.0 ? min(1.0, Fy / Fx) : 1.0;
            depositList(chain, 1u, st.proposalCount, Fy, a, s.rng, c);
            depositList(chain, 0u, st.currentCount, Fx, 1.0 - a, s.rng, c);
            bool accept = rngNext(s.rng) < a;
            if (s.largeStep) {
                c.largeProposed += 1u;
                if (accept) c.largeAccepted += 1u;
            } else {
                c.smallProposed += 1u;
                if (accept) c.smallAccepted += 1u;
            }
            if (accept) {
                pssAccept(s);
                for (uint k = 0u; k < st.proposalCount; ++k)
                    splatLists[pssSplatIndex(chain, 0u, k)] = splatLists[pssSplatIndex(chain, 1u, k)];
                st.currentCount = st.proposalCount;
            } else {
                pssBdptReject(s, st);
            }
            st.rng = s.rng.state;
            st.iteration = s.iteration;
            st.lastLargeStep = s.lastLargeStep;
            st.largeStep = 0u;
            chains[chain] = st;
        }
    }
    flushPssCounters(c);
}
