#version 460
// PMC-ER: when rendering ends, every member deposits the energy it has left, E_remain shares e_d,
// at its current pixel with its current colour, so that every member deposits its whole energy.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
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

void main() {
    uint i = gl_GlobalInvocationID.x;
    StepCounters counters = stepCountersCreate();
    if (i < push.memberCount) {
        uint member = push.memberBase + i;
        PmcErMember m = members[member];
        if (m.remaining > 0.0) {
            ChainState st = chains[member];
            Rng rng;
            rng.state = st.rng;
            depositAt(st, rasterPixel(st.raster), st.throughput, m.remaining * m.shares, rng, 0u, counters);
            st.rng = rng.state;
            chains[member] = st;
            m.remaining = 0.0;
            members[member] = m;
        }
    }
    flushStepCounters(counters);
}
