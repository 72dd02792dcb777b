// PMC-ER: the members activeList[memberBase, memberBase + memberCount) make push.steps mutations each
// (PMC-ER fig. 2 lines 8-12, equal deposition). Each mutation picks a radius d_k by the member's
// alpha (eq. 5), then a caustic perturbation with probability gamma_caustic where it applies
// (angles uniform in [0, thetaMax(d_k)], eq. 6) or a lens perturbation in the disk of radius
// d_k, is accepted with that component's own transition density (eq. 9, Tierney 1998; with
// PMC_ER_FLAG_MIXTURE_ACCEPTANCE, with the density of the mixture over the radii, eq. 8), and
// `shares` e_d are deposited at the (new) current path's pixel with its colour
// (methods/energy_redistribution/erpt_chain.glsl).
//
// Bookkeeping: each mutation takes one from E_remain. When less than one is left, Russian
// roulette: the member makes its last mutation with probability E_remain and dies either way,
// so the expected number of deposits is E_remain exactly (host/methods/pmc_er/path_population.h).
//
// The body of pmc_er_mutate.comp and pmc_er_mutate_all_lights.comp (PMCR_OTHER_LIGHTS: punctual
// lights and the environment compiled in); the host picks the variant by the scene's lights
// (lightsKernelVariant, host/methods/pt/pt_integrator.h).
#include "shared/host_device.h"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(push_constant, scalar) uniform PushBlock { PmcErPush push; };
#define FILM_BINDING ERPT_BINDING_SPLAT
#define COUNTERS_BINDING ERPT_BINDING_COUNTERS
#include "methods/energy_redistribution/erpt_chain.glsl"

layout(set = WORK_SET, binding = ERPT_BINDING_CHAINS, scalar) buffer ChainBuffer { ChainState chains[]; };
layout(set = WORK_SET, binding = PMC_ER_BINDING_MEMBERS, scalar) buffer MemberBuffer {
    PmcErMember members[];
};
layout(set = WORK_SET, binding = PMC_ER_BINDING_STRATEGY, scalar) buffer StrategyBuffer {
    uint strategy[];
};
layout(set = WORK_SET, binding = PMC_ER_BINDING_ACTIVE, scalar) readonly buffer ActiveBuffer {
    uint activeList[];
};

// Component k with probability alpha_k.
uint chooseComponent(vec3 alpha, float u) {
    for (uint k = 0u; k + 1u < push.componentCount; ++k) {
        if (u < alpha[k]) return k;
        u -= alpha[k];
    }
    return push.componentCount - 1u;
}

// Radians that move the image point by one pixel at the image centre: theta(d) = d * this.
float thetaPerPixel() {
    vec2 c = 0.5 * vec2(sceneInfo.width, sceneInfo.height);
    return acos(clamp(dot(cameraDirection(c), cameraDirection(c + vec2(1.0, 0.0))), -1.0, 1.0));
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    StepCounters counters = stepCountersCreate();
    if (i < push.memberCount) {
        uint member = activeList[push.memberBase + i];
        PmcErMember m = members[member];
        if (m.remaining > 0.0) {
            ChainState st = chains[member];
            Rng rng;
            rng.state = st.rng;
            AngleSampler lensAngle = angleSampler(push.lensThetaMin, push.lensThetaMax, false);
            float perPixel = thetaPerPixel();
            // theta(d_k) of every radius, eq. 6.
            vec3 thetas = push.radii * perPixel;
            bool mixture = (push.flags & PMC_ER_FLAG_MIXTURE_ACCEPTANCE) != 0u;
            for (uint s = 0u; s < push.steps && m.remaining > 0.0; ++s) {
                // Russian roulette on the last, partial deposit.
                if (m.remaining < 1.0) {
                    bool last = rngNext(rng) < m.remaining;
                    m.remaining = 0.0;
                    if (!last) break;
                } else {
                    m.remaining -= 1.0;
                }
                uint k = chooseComponent(m.alpha, rngNext(rng));
                atomicAdd(strategy[rasterPixel(st.raster) * PMC_ER_MAX_RADII + k], 1u);
                AngleSampler causticAngle = angleSampler(0.0, thetas[k], true);
                if (mixture) {
                    causticAngle.mixtureCount = push.componentCount;
                    causticAngle.mixtureWeights = m.alpha;
                    causticAngle.mixtureThetas = thetas;
                }
                float a;
                bool caustic;
                chainStep(member, st, rng, MUTATION_MIX, push.causticProbability, push.radii[k],
                          lensAngle, causticAngle, 0u, 0u, m.shares, counters, a, caustic);
                m.acceptSum[k] += a;
                m.mutations += 1u;
            }
            st.rng = rng.state;
            m.pixel = rasterPixel(st.raster);
            chains[member] = st;
            members[member] = m;
        }
    }
    flushStepCounters(counters);
}
