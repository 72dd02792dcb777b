// PSSMLT over bdpt, the first dispatch of a step (shared/pssmlt_types.h): per chain, the
// proposal y's camera subpath, through the raster position its first two coordinates place
// anywhere on the image (pss_path.glsl), and its light subpath (bdpt_walk.glsl), into the
// vertex buffers. With PSSMLT_FLAG_START the chain is first set to its start instead: its
// bootstrap sample's primary vector, iteration 0 (nothing mutates; host/methods/metropolis).
// Otherwise the step begins here: iteration + 1, a large step with probability
// push.largeStepProbability (Kelemen et al. 2002 sec. 3.3), kept in the chain for the kernels
// after this one.
// The body of pssmlt_bdpt_subpaths.comp and pssmlt_bdpt_subpaths_all_lights.comp.
#include "shared/host_device.h"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(push_constant, scalar) uniform PushBlock { PssmltPush push; };

#define CAMERA_VERTICES_BINDING PSSMLT_BINDING_CAMERA_VERTICES
#define LIGHT_VERTICES_BINDING PSSMLT_BINDING_LIGHT_VERTICES
#define VERTEX_COUNTS_BINDING PSSMLT_BINDING_VERTEX_COUNTS
#define COUNTERS_BINDING ERPT_BINDING_COUNTERS
#define FILM_BINDING ERPT_BINDING_SPLAT
#include "common/film.glsl"
#include "methods/pssmlt/pss_bdpt.glsl"
#include "methods/bdpt/bdpt_walk.glsl"
#include "methods/pssmlt/pss_path.glsl"

layout(set = WORK_SET, binding = PSSMLT_BINDING_CHAIN_STARTS, scalar) readonly buffer StartBuffer {
    uint chainStarts[];
};

// Chain `chain` at the primary vector of bootstrap sample `start`, iteration 0. A bootstrap
// sample's vector is not stored: its sampler reads the coordinates' hashes (pssBdptSampler).
PssmltBdptChain startChain(uint chain, uint start) {
    if ((push.flags & PSSMLT_FLAG_BOOTSTRAP) == 0u) {
        for (uint d = 0u; d < push.dimensions; ++d) {
            float v = bootstrapCoordinate(push.seed, start, d);
            primarySamples[d * push.chainStride + chain] = PrimarySample(v, 0u, v, 0u);
        }
    }
    PssmltBdptChain st;
    st.rng = hash3(push.seed ^ 0x3c5a17e1u, chain, 0u);
    st.iteration = 0u;
    st.lastLargeStep = 0u;
    st.largeStep = 0u;
    st.currentCount = 0u;
    st.proposalCount = 0u;
    st.proposalPixel = 0u;
    st.depth = start >> MMLT_DEPTH_SHIFT;  // mmlt (shared/pssmlt_types.h)
    st.strategy = 0u;
    st.cameraEnd = 0u;
    st.lightEnd = 0u;
    st.connectEnd = 0u;
    return st;
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint rays = 0u;
    if (i < push.count) {
        uint chain = pssBdptChain(i);
        PssmltBdptChain st;
        if ((push.flags & PSSMLT_FLAG_BOOTSTRAP) != 0u) st = startChain(chain, push.first + i + push.sampleOffset);
        else if ((push.flags & PSSMLT_FLAG_START) != 0u) st = startChain(chain, chainStarts[chain]);
        else st = chains[chain];
        Sampler smp = pssBdptSampler(chain, st);
        if ((push.flags & PSSMLT_FLAG_START) == 0u) pssBeginIteration(smp, push.largeStepProbability);
#ifdef PSS_MULTIPLEXED
        // One strategy of the chain's depth d: s uniform in 0 .. d + 1, t = d + 2 - s, and
        // subpaths of exactly t and s vertices (pbrt-v4 MLTIntegrator::L; depth 0 has s = 0).
        uint strategies = mmltStrategies(st.depth);
        smp.dimension = MMLT_STRATEGY_DIMENSION(push.maxDepth);
        uint s = min(uint(samplerGet1D(smp) * float(strategies)), strategies - 1u);
        smp.dimension = 0u;
        uint cameraVertexCount = st.depth + 2u - s;
        // s <= 1 needs no light subpath: s = 1 samples a light from the camera vertex.
        uint lightVertexCount = s >= 2u ? s : 0u;
        st.strategy = s;
#else
        uint cameraVertexCount = push.cameraStride;
        uint lightVertexCount = push.lightStride;
#endif
        vec2 raster = pssRaster(smp);
        st.proposalPixel = pssPixel(raster);
        // The camera subpath, then the light subpath at its own dimensions; each walk takes at
        // most its stride in steps.
        Walk w = cameraWalk(chain * push.cameraStride, raster, cameraVertexCount);
        uint cameraCount = 0u;
        bool lightPhase = false;
        for (uint b = 0u; b < push.cameraStride + push.lightStride + 1u; ++b) {
            if (walkStep(w, smp, rays)) continue;
            if (lightPhase) break;
            cameraCount = w.n;
            st.cameraEnd = smp.dimension;
            smp.dimension = bdptLightDimension(push.maxDepth);
            lightPhase = true;
            w.n = 0u;
            if (lightVertexCount == 0u || !lightWalk(chain * push.lightStride, smp, lightVertexCount, w)) break;
        }
        // The walks read their ranges in order from their starts; no light walk reads none.
        if (!lightPhase) st.cameraEnd = smp.dimension;
        st.lightEnd = lightPhase ? smp.dimension : 0u;
        vertexCounts[chain] = uvec2(cameraCount, w.n);
        st.iteration = smp.iteration;
        st.largeStep = smp.largeStep ? 1u : 0u;
        st.rng = smp.rng.state;
        chains[chain] = st;
    }
    counterAdd(COUNTER_RAYS, rays);
}
