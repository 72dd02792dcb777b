#version 460
// ERPT: how many chains each path-traced sample (record) of this pass starts, and the energy of
// all seed paths that start chains (in units of e_d; ENERGY_SEED), which the chains must deposit in
// expectation. With ERPT_FLAG_DEPOSIT_DIRECT, the direct seed paths (erpt_seeds.glsl) are
// deposited here at their pixel instead (ENERGY_DIRECT).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#extension GL_EXT_shader_atomic_float : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "shared/host_device.h"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(push_constant, scalar) uniform PushBlock { ErptPush push; };
#include "common/math.glsl"
#include "methods/erpt/erpt_seeds.glsl"
#include "methods/energy_redistribution/splat.glsl"

layout(set = WORK_SET, binding = ERPT_BINDING_CHAIN_COUNTS, scalar) writeonly buffer CountBuffer {
    uint chainCounts[];
};

layout(set = WORK_SET, binding = ERPT_BINDING_ENERGY, scalar) buffer EnergyBuffer { float energy[]; };

void main() {
    uint r = gl_GlobalInvocationID.x;
    float seedEnergy = 0.0, directEnergy = 0.0;
    if (r < push.recordCount) {
        PathRecord rec = records[r];
        bool depositDirect = (push.flags & ERPT_FLAG_DEPOSIT_DIRECT) != 0u;
        Rng rng = rngCreate(hash3(push.seed ^ 0xd1ec7u, push.pass, r));
        uint total = 0u;
        for (uint s = 0u; s < 2u * rec.vertexCount; ++s) {
            total += seedChainCount(rec, r, s);
            vec3 c = seedContribution(rec, s);
            float e = luminance(c) * push.seedScale / push.depositEnergy;  // in units of e_d
            if (!isFinite(c) || !(e > 0.0)) continue;
            if (depositDirect && isDirectSeed(s)) {
                if (splatDeposit(rec.pixel, c / luminance(c), e, rng)) directEnergy += e;
            } else {
                seedEnergy += e;
            }
        }
        chainCounts[r] = total;
    }
    float sum = subgroupAdd(seedEnergy);
    if (subgroupElect() && sum != 0.0) atomicAdd(energy[ENERGY_SEED], sum);
    float direct = subgroupAdd(directEnergy);
    if (subgroupElect() && direct != 0.0) atomicAdd(energy[ENERGY_DIRECT], direct);
}
