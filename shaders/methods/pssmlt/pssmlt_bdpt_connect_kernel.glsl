// PSSMLT over bdpt, the second dispatch of a step (shared/pssmlt_types.h): per chain, every
// connection strategy (s, t) of the proposal's subpaths, MIS-weighted as bdpt weighs them
// (bdpt_strategy.glsl), into the proposal's splat list: each light tracing (t = 1) contribution
// at the pixel its light vertex is seen through, then the t >= 2 sum at the camera sample's
// pixel. The s = 1 light samples read the chain's coordinates at bdpt's dimensions.
// The body of pssmlt_bdpt_connect.comp and pssmlt_bdpt_connect_all_lights.comp.
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
#include "methods/bdpt/bdpt_strategy.glsl"

// Appends (pixel, rgb) to chain's proposal list.
void appendSplat(uint chain, inout uint count, uint pixel, vec3 rgb) {
    if (count >= PSSMLT_BDPT_SPLATS(push.maxDepth)) return;  // never: one per light vertex, and one
    splatLists[pssSplatIndex(chain, 1u, count)] = PssmltSplat(rgb, pixel);
    count += 1u;
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint rays = 0u;
    if (i < push.count) {
        uint chain = pssBdptChain(i);
        PssmltBdptChain chainState = chains[chain];
        SampleState st;
        st.pixel = chainState.proposalPixel;
        gCameraBase = chain * push.cameraStride;
        gLightBase = chain * push.lightStride;
        st.counts = vertexCounts[chain];
        st.smp = pssBdptSampler(chain, chainState);
        uint count = 0u;
#ifdef PSS_MULTIPLEXED
        // Only the proposal's strategy, when its subpaths have their full lengths (else F = 0),
        // its MIS weight times the number of strategies of its depth (mmltStrategies;
        // Hachisuka et al. 2014 eq. 6; pbrt-v4 MLTIntegrator::L), at its pixel: the camera
        // sample's or, for t = 1, the one its light vertex is seen through.
        uint s = chainState.strategy;
        uint t = chainState.depth + 2u - s;
        if (st.counts.x == t && (s <= 1u || st.counts.y == s)) {
            beginStrategy(st, s, t);
            vec3 c;
            float w;
            uint target;
            if (evaluateStrategy(st, rays, c, w, target))
                appendSplat(chain, count, target, c * (w * float(mmltStrategies(chainState.depth))));
        }
#else
        st.L = vec3(0.0);
        st.cameraTail = 0.0;
        st.t = 1u;
        beginCameraVertex(st);
        // At most cameraStride (lightStride + 1) strategies.
        for (uint b = 0u; b < push.cameraStride * (push.lightStride + 1u); ++b) {
            vec3 c;
            float w;
            uint target;
            if (evaluateStrategy(st, rays, c, w, target)) {
                vec3 weighted = c * w;
                if (st.t == 1u) appendSplat(chain, count, target, weighted);
                else st.L += weighted;
            }
            if (!nextStrategy(st)) break;
        }
        appendSplat(chain, count, st.pixel, st.L);
#endif
        // Each camera vertex's s = 1 light sample sits further on than the one before.
        chainState.connectEnd = st.smp.dimension;
        chainState.proposalCount = count;
        chainState.rng = st.smp.rng.state;
        chains[chain] = chainState;
    }
    counterAdd(COUNTER_RAYS, rays);
}
