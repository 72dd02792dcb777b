// PMC-ER: makes new population members from path-traced samples (sec. 4.5 "Regeneration").
// Invocation i turns record i into member seedSlots[slotBase + i]: one of the record's light
// paths, chosen with probability lum(c_s) / sum_s lum(c_s), carrying the whole sample's energy
// E = seedScale * sum_s lum(c_s) (PMC-ER eq. 2, in units of e_d). In expectation path s then
// carries lum(c_s) seedScale, the energy it would carry on its own (as ERPT's chain counts do).
// With ERPT_FLAG_DEPOSIT_DIRECT (--redistribute indirect) the direct seed paths
// (methods/energy_redistribution/seed_paths.glsl isDirectSeed) are deposited at the sample's pixel
// instead, as path tracing would, and the member is made of the others: unbiased term by term (ERPT
// sec. 3.2), and with the per-pixel stratified pool (host/methods/pmc_er/stratified_pixel_pool.h)
// the direct part is exactly a path tracer's.
// Equal births (the default) give every member the same E_remain = Q and n = floor(U + E / Q)
// shares (e_d per deposit), so that no member's lifetime depends on its path; the paper's births
// give E_remain = E and one share (host/methods/pmc_er/path_population.h says why that is biased).
//
// The body of pmc_er_seed.comp and pmc_er_seed_all_lights.comp (PMCR_OTHER_LIGHTS: punctual
// lights and the environment compiled in); the host picks the variant by the scene's lights
// (lightsKernelVariant, host/methods/pt/pt_integrator.h).
#include "shared/host_device.h"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(push_constant, scalar) uniform PushBlock { PmcErPush push; };
#include "methods/energy_redistribution/path_space.glsl"
#include "methods/energy_redistribution/seed_paths.glsl"
#include "methods/energy_redistribution/splat.glsl"

layout(set = WORK_SET, binding = ERPT_BINDING_CHAINS, scalar) writeonly buffer ChainBuffer {
    ChainState chains[];
};
layout(set = WORK_SET, binding = PMC_ER_BINDING_MEMBERS, scalar) buffer MemberBuffer {
    PmcErMember members[];
};
layout(set = WORK_SET, binding = PMC_ER_BINDING_SEED_SLOTS, scalar) readonly buffer SlotBuffer {
    uint seedSlots[];
};
layout(set = WORK_SET, binding = ERPT_BINDING_PIXEL_STATS, scalar) buffer PixelStatsBuffer {
    PixelChainStats pixelStats[];
};
layout(set = WORK_SET, binding = ERPT_BINDING_ENERGY, scalar) buffer EnergyBuffer { float energy[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    float seedEnergy = 0.0, directEnergy = 0.0;
    if (i < push.memberCount) {
        uint member = seedSlots[push.slotBase + i];
        PathRecord rec = records[i];
        Rng rng = rngCreate(hash3(push.seed ^ 0x9ce2e5u, hashCombine(push.pass, push.iteration), i));
        bool depositDirect = (push.flags & ERPT_FLAG_DEPOSIT_DIRECT) != 0u;
        float total = 0.0;
        for (uint s = 0u; s < 2u * rec.vertexCount; ++s) {
            vec3 c = seedContribution(rec, s);
            float y = luminance(c);
            if (!isFinite(c) || !(y > 0.0)) continue;
            if (depositDirect && isDirectSeed(s)) {
                float e = y * push.seedScale;  // units of e_d
                if (splatDeposit(rec.pixel, c / y, e, rng)) directEnergy += e;
            } else {
                total += y;
            }
        }
        PmcErMember m;
        m.remaining = 0.0;
        m.alpha = push.initialAlpha;  // the host zeroes the weights beyond componentCount
        m.acceptSum = vec3(0.0);
        m.mutations = 0u;
        m.shares = 0.0;
        m.pixel = rec.pixel;
        ChainState st;
        st.vertexCount = 0u;
        if (total > 0.0) {
            // Pick light path s with probability lum(c_s) / total.
            float u = rngNext(rng) * total;
            uint chosen = 0u;
            bool found = false;
            for (uint s = 0u; s < 2u * rec.vertexCount; ++s) {
                vec3 c = seedContribution(rec, s);
                if (!isFinite(c) || !(luminance(c) > 0.0) || (depositDirect && isDirectSeed(s))) continue;
                chosen = s;
                found = true;
                u -= luminance(c);
                if (u < 0.0) break;
            }
            float e = total * push.seedScale;
            // Equal births: n = floor(U + E / Q) shares of one member of energy Q (E[n Q] = E).
            float shares = push.birth == PMC_ER_BIRTH_EQUAL ? floor(rngNext(rng) + e / push.birthEnergy) : 1.0;
            if (found && shares > 0.0) {
                st = chainFromSeedPath(member, rec, chosen);
                m.remaining = push.birth == PMC_ER_BIRTH_EQUAL ? push.birthEnergy : e;
                m.shares = shares;
                atomicAdd(pixelStats[rec.pixel].chainsStarted, 1u);
            }
            seedEnergy = e;
        }
        if (st.vertexCount == 0u) {
            st.raster = rec.raster;
            st.slot = 0u;
            st.throughput = vec3(0.0);
            st.lastPixel = 0xffffffffu;
            st.consecutive = 0u;
            st.pad = 0u;
        }
        st.rng = rngNextUint(rng);
        st.origin = i;
        chains[member] = st;
        members[member] = m;
    }
    float sum = subgroupAdd(seedEnergy);
    if (subgroupElect() && sum != 0.0) atomicAdd(energy[ENERGY_SEED], sum);
    float direct = subgroupAdd(directEnergy);
    if (subgroupElect() && direct != 0.0) atomicAdd(energy[ENERGY_DIRECT], direct);
}
