// ERPT: builds chain states from seed paths. Invocation i makes chain push.chainOffset + i of
// the pass (at chain slot push.chainBase + i): it finds its record by binary search over the
// exclusive prefix sums of the chain counts, then its seed path within the record.
//
// The body of erpt_seed.comp and erpt_seed_all_lights.comp (PMCR_OTHER_LIGHTS: punctual
// lights and the environment compiled in); the host picks the variant by the scene's lights
// (lightsKernelVariant, host/methods/pt/pt_integrator.h).
#include "shared/host_device.h"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(push_constant, scalar) uniform PushBlock { ErptPush push; };
#include "methods/energy_redistribution/path_space.glsl"
#include "methods/erpt/erpt_seeds.glsl"

layout(set = WORK_SET, binding = ERPT_BINDING_CHAIN_OFFSETS, scalar) readonly buffer OffsetBuffer {
    uint chainOffsets[];
};
layout(set = WORK_SET, binding = ERPT_BINDING_CHAINS, scalar) writeonly buffer ChainBuffer {
    ChainState chains[];
};
layout(set = WORK_SET, binding = ERPT_BINDING_PIXEL_STATS, scalar) buffer PixelStatsBuffer {
    PixelChainStats pixelStats[];
};

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i < push.chainCount) {
        uint c = push.chainOffset + i;
        // Last record whose offset is <= c (offsets are non-decreasing; 32 steps bound it).
        uint lo = 0u, hi = push.recordCount;
        for (uint step = 0u; step < 32u && hi - lo > 1u; ++step) {
            uint mid = (lo + hi) / 2u;
            if (chainOffsets[mid] <= c) lo = mid; else hi = mid;
        }
        uint r = lo;
        PathRecord rec = records[r];
        uint within = c - chainOffsets[r];
        uint s = 0u;
        uint n = 0u;
        for (; s < 2u * rec.vertexCount; ++s) {
            n = seedChainCount(rec, r, s);
            if (within < n) break;
            within -= n;
        }

        // Copy the seed path into slot 0.
        uint chain = push.chainBase + i;
        ChainState st = chainFromSeedPath(chain, rec, s);
        st.rng = hash3(push.seed ^ 0xc4a1e5u, push.pass, c);
        st.origin = r * (2u * PATH_MAX_VERTICES) + s;
        chains[chain] = st;
        atomicAdd(pixelStats[rec.pixel].chainsStarted, 1u);
    }
}
