// The body of bdpt_connect.comp and bdpt_connect_all_lights.comp: per camera sample, every
// connection strategy (s, t) of its two subpaths (bdpt_subpaths_kernel.glsl) with s + t - 2 <=
// maxDepth bounces (pbrt-v4 ConnectBDPT), each weighted by multiple importance sampling over all
// the strategies that could have made the same path (bdptMisWeight):
//   s = 0       the camera subpath's vertex t - 1 is on a light (an emitter, the environment);
//   t = 1       light tracing: light vertex s - 1 is connected to the pinhole and its
//               contribution splatted at the pixel it is seen through (fixed-point sums,
//               methods/energy_redistribution/splat.glsl: the same image for the same seed);
//   s = 1       next-event estimation: a light sampled from camera vertex t - 1 as pt samples it
//               (path_tracer.glsl sampleLightFrom), with that light sample's densities;
//   otherwise   light vertex s - 1 and camera vertex t - 1 joined by a shadow ray.
// (s, t) = (1, 1) is skipped (the camera sees a light through s = 0, t = 2), as pbrt does. The
// t >= 2 contributions go to the camera sample's pixel (FilmPixel: per-pixel mean); the host
// divides the splat film by the light subpaths traced per pixel.
#include "shared/host_device.h"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(push_constant, scalar) uniform PushBlock { BdptPush push; };

#define BVH_COUNT_STEPS  // bvhStepsTaken, for connections in turn (main)
#define FILM_BINDING BDPT_BINDING_FILM
#define COUNTERS_BINDING BDPT_BINDING_COUNTERS
#include "common/film.glsl"
#include "methods/bdpt/bdpt_strategy.glsl"
#include "methods/energy_redistribution/splat.glsl"

layout(set = WORK_SET, binding = BDPT_BINDING_STRATEGIES, scalar) buffer StrategyBuffer {
    float strategies[];
};
layout(set = WORK_SET, binding = BDPT_BINDING_QUEUE, scalar) buffer QueueBuffer { uint queue[]; };

// Adds a strategy's contribution to its image (--strategy-images): weighted and unweighted.
void addToStrategyImage(uint pixel, uint s, uint t, vec3 weighted, vec3 unweighted) {
    uint depth = s + t - 2u;
    if (depth > BDPT_STRATEGY_MAX_DEPTH || !isFinite(weighted) || !isFinite(unweighted)) return;
    uint base = (pixel * BDPT_STRATEGY_COUNT + depth * (depth + 3u) / 2u + s) * 6u;
    for (uint c = 0u; c < 3u; ++c) {
        if (weighted[c] != 0.0) atomicAdd(strategies[base + c], weighted[c]);
        if (unweighted[c] != 0.0) atomicAdd(strategies[base + 3u + c], unweighted[c]);
    }
}

// Starts camera sample `index` of the dispatch at strategy (0, 1).
void beginSample(inout SampleState st, uint index) {
    st.pixel = push.pixelOffset + index;
    gCameraBase = index * push.cameraStride;
    gLightBase = index * push.lightStride;
    st.counts = vertexCounts[index];
    st.smp = samplerCreate(st.pixel, push.sampleIndex, push.seed);
    st.rng = rngCreate(hash3(push.seed ^ 0x5bd1e995u, st.pixel, push.sampleIndex));
    st.L = vec3(0.0);
    st.cameraTail = 0.0;
    st.t = 1u;
    beginCameraVertex(st);
}

// Connections in turn: on a CPU device (itemsPerInvocation > 1) each invocation takes camera
// samples from a queue, one strategy per loop iteration, and starts its next sample as soon as
// one is done, so that the SIMD lanes lavapipe runs together (whose subpaths differ in length)
// stay busy, as pt's paths in turn (camera_sample_kernel.glsl). It stops taking samples once
// its traversal steps and iterations pass BDPT_LOOP_STEPS_BEFORE_STOP, far below lavapipe's
// budget of 65535 loop iterations per invocation (tests/gpu/test_loop_limits.cpp); the
// dispatch has an invocation per sample, so every sample is taken. A pixel still has one sample
// per dispatch, added to the film by whichever invocation took it, so the image does not depend
// on who did: the same seed gives the same image. On a GPU each invocation takes its own sample.
const uint BDPT_LOOP_STEPS_BEFORE_STOP = 16384u;

void main() {
    uint rays = 0u;
    uint dropped = 0u;
    uint paths = 0u;
    bool fromQueue = push.itemsPerInvocation > 1u;
    uint index = fromQueue ? atomicAdd(queue[push.queueSlot], 1u) : gl_GlobalInvocationID.x;
    if (index < push.count) {
        bool strategyImages = (push.flags & BDPT_FLAG_STRATEGY_IMAGES) != 0u;
        SampleState st;
        beginSample(st, index);
        uint steps = max(push.itemsPerInvocation, 1u) * push.cameraStride * (push.lightStride + 1u);
        for (uint b = 0u; b < steps; ++b) {
            vec3 c;
            float w;
            uint target;
            if (evaluateStrategy(st, rays, c, w, target)) {
                // MIS-weighted: to the sample's pixel (t >= 2), or splatted where light vertex
                // s - 1 is seen (t = 1).
                vec3 weighted = c * w;
                if (strategyImages) addToStrategyImage(target, st.s, st.t, weighted, c);
                if (st.t == 1u) {
                    if (!splatDeposit(target, weighted, 1.0, st.rng)) dropped += 1u;
                } else {
                    st.L += weighted;
                }
            }
            if (nextStrategy(st)) continue;
            PixelAccumulator acc = accumulatorCreate();
            accumulatorAdd(acc, st.L);
            filmAccumulate(st.pixel, acc.sum, acc.lumSum, acc.lumSqSum, acc.count);
            dropped += acc.dropped;
            paths += 1u;
            if (!fromQueue || paths >= push.itemsPerInvocation ||
                bvhStepsTaken + b > BDPT_LOOP_STEPS_BEFORE_STOP)
                break;
            index = atomicAdd(queue[push.queueSlot], 1u);
            if (index >= push.count) break;
            beginSample(st, index);
        }
    }
    counterAdd(COUNTER_RAYS, rays);
    counterAdd(COUNTER_NAN_DROPPED, dropped);
    counterAdd(COUNTER_PATHS, paths);
}
