// PSSMLT's bootstrap (Veach 1997 sec. 11.3.1): samples [push.first, push.first + push.count) of
// uniform primary vectors, path-traced; weights[i] = F(u_i), whose mean times the image's pixel
// count is the normalisation b = the image's total luminance. The host draws the chains' starts
// in proportion to them (host/methods/metropolis/bootstrap.h).
//
// Invocation i of N = ceil(count / P) takes samples i, i + N, ... (P = push.itemsPerInvocation)
// one after another, a new path as soon as the last ends (as pt.comp does on a CPU device).
// The body of pssmlt_bootstrap.comp and pssmlt_bootstrap_all_lights.comp (PMCR_OTHER_LIGHTS).
#include "shared/host_device.h"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(push_constant, scalar) uniform PushBlock { PssmltPush push; };
#define COUNTERS_BINDING ERPT_BINDING_COUNTERS
#define FILM_BINDING ERPT_BINDING_SPLAT
#include "common/film.glsl"
#include "methods/pssmlt/bootstrap_sampler.glsl"
#include "methods/pt/path_tracer.glsl"
#include "methods/pssmlt/pss_path.glsl"

layout(set = WORK_SET, binding = PSSMLT_BINDING_WEIGHTS, scalar) writeonly buffer WeightBuffer {
    float weights[];
};

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint rays = 0u, dropped = 0u, paths = 0u;
    uint P = max(push.itemsPerInvocation, 1u);
    uint N = (push.count + P - 1u) / P;
    uint total = i < N ? (push.count - i + N - 1u) / N : 0u;  // this invocation's samples
    if (total > 0u) {
        uint item = 0u;
        uint sampleIndex = push.first + i;
        Sampler s = bootstrapSampler(push.seed, sampleIndex);
        PathState p = pathBegin(pssRaster(s), 0u);
        // Each path takes at most maxDepth + 1 bounces.
        uint bounces = total * (push.maxDepth + 1u);
        for (uint b = 0u; b < bounces; ++b) {
            if (pathBounce(p, s, push.maxDepth, push.rrDepth, rays)) continue;
            if (!isFinite(p.L)) dropped += 1u;
            weights[sampleIndex] = pssTarget(p.L);
            paths += 1u;
            item += 1u;
            if (item == total) break;
            sampleIndex += N;
            s = bootstrapSampler(push.seed, sampleIndex);
            p = pathBegin(pssRaster(s), 0u);
        }
    }
    counterAdd(COUNTER_RAYS, rays);
    counterAdd(COUNTER_NAN_DROPPED, dropped);
    counterAdd(COUNTER_PATHS, paths);
}
