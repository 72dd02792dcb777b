#version 460
// Test kernel for PSSMLT's mutations (tests/gpu/test_pssmlt_mutation.cpp): runs the renderer's own
// lazy sampler (methods/pssmlt/pss_sampler.glsl) on one coordinate per chain. Invocation i is
// chain i (stride count, one dimension); its coordinate starts at push.x, set at iteration 0.
//   mode 0 (composed small steps): one read at iteration n (n small steps in one);
//          results[i] = the coordinate read
//   mode 1 (successive small steps): reads at iterations 1, 2, ..., n, each accepted;
//          results[i] = the last coordinate read
//   mode 2 (large step): one read at iteration 1, a large step; results[i] = the coordinate
//   mode 3 (rejection): a small step at iteration 1, then pssReject; results[4i ..] = (proposed
//          value, value after, its last modification after, the sampler's iteration after)
//   mode 4 (a large step accepted in between): a read at iteration n after a large step was
//          accepted at iteration n - 1 that did not read the coordinate: uniform again;
//          results[i] = the coordinate read
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "shared/host_device.h"

#include "methods/pssmlt/pss_sampler.glsl"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(set = WORK_SET, binding = 0, scalar) writeonly buffer Results { float results[]; };
layout(push_constant, scalar) uniform Push {
    uint mode;
    uint count;
    uint seed;
    uint n;
    float x;
    float sigma;
} push;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.count) return;
    primarySamples[i] = PrimarySample(push.x, 0u, push.x, 0u);
    Sampler s;
    s.chain = i;
    s.stride = push.count;
    s.dimensions = 1u;
    s.dimension = 0u;
    s.iteration = 0u;
    s.lastLargeStep = 0u;
    s.largeStep = false;
    s.sigma = push.sigma;
    s.rng = rngCreate(hash3(push.seed, i, 0x5a3e11u));
    if (push.mode == 0u) {
        s.iteration = push.n;
        results[i] = samplerGet1D(s);
    } else if (push.mode == 1u) {
        float u = push.x;
        for (uint k = 1u; k <= push.n; ++k) {
            s.iteration = k;
            s.dimension = 0u;
            u = samplerGet1D(s);
            pssAccept(s);
        }
        results[i] = u;
    } else if (push.mode == 2u) {
        s.iteration = 1u;
        s.largeStep = true;
        results[i] = samplerGet1D(s);
        pssAccept(s);
    } else if (push.mode == 3u) {
        s.iteration = 1u;
        float proposed = samplerGet1D(s);
        pssReject(s);
        PrimarySample after = primarySamples[i];
        results[4u * i] = proposed;
        results[4u * i + 1u] = after.value;
        results[4u * i + 2u] = float(after.lastModification);
        results[4u * i + 3u] = float(s.iteration);
    } else {
        s.lastLargeStep = push.n - 1u;
        s.iteration = push.n;
        results[i] = samplerGet1D(s);
    }
}
