// The body of bdpt_subpaths.comp and bdpt_subpaths_all_lights.comp: per camera sample (one
// pixel of the pass) a camera subpath of up to maxDepth + 2 vertices and a light subpath of up to
// maxDepth + 1 (bdpt_walk.glsl), written to the vertex buffers for bdpt_connect.comp. Random
// numbers come from the pixel's sampler (common/sampler.glsl) in fixed dimensions: the raster
// position (0), the camera walk from 1, three per vertex (lobe, direction, roulette), then the
// light walk (bdptLightDimension), so that the light subpath's numbers do not depend on the
// camera subpath's length.
#include "shared/host_device.h"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(push_constant, scalar) uniform PushBlock { BdptPush push; };

#define BVH_COUNT_STEPS  // bvhStepsTaken, for walks in turn (main)
#define FILM_BINDING BDPT_BINDING_FILM
#define COUNTERS_BINDING BDPT_BINDING_COUNTERS
#include "common/film.glsl"
#include "common/kernel_options.glsl"
#include "common/sampler.glsl"
#include "methods/bdpt/bdpt_walk.glsl"

layout(set = WORK_SET, binding = BDPT_BINDING_QUEUE, scalar) buffer QueueBuffer { uint queue[]; };

// A camera sample's two subpaths, walked one after the other.
struct SampleWalks {
    uint index;       // in the dispatch
    Sampler smp;
    Walk walk;
    bool lightPhase;  // walking the light subpath
    uint cameraCount;
};

void beginSample(inout SampleWalks sw, uint index) {
    uint pixel = push.pixelOffset + index;
    sw.index = index;
    sw.smp = samplerCreate(pixel, push.sampleIndex, push.seed);
    vec2 u = independentPixelSamples() ? samplerGetIndependent2D(sw.smp) : samplerGet2D(sw.smp);
    vec2 raster = vec2(float(pixel % sceneInfo.width), float(pixel / sceneInfo.width)) + u;
    sw.walk = cameraWalk(index * push.cameraStride, raster, push.cameraStride);
    sw.lightPhase = false;
    sw.cameraCount = 0u;
}

// Walks in turn, as the connection kernel's connections in turn (bdpt_connect_kernel.glsl): on
// a CPU device each invocation takes samples from a queue, one ray per loop iteration, and
// starts its next sample as soon as one is done, within lavapipe's loop budget.
const uint BDPT_LOOP_STEPS_BEFORE_STOP = 16384u;

void main() {
    uint rays = 0u;
    bool fromQueue = push.itemsPerInvocation > 1u;
    uint index = fromQueue ? atomicAdd(queue[push.queueSlot], 1u) : gl_GlobalInvocationID.x;
    if (index < push.count) {
        SampleWalks sw;
        beginSample(sw, index);
        uint done = 0u;
        uint steps = max(push.itemsPerInvocation, 1u) * (push.cameraStride + push.lightStride + 1u);
        for (uint b = 0u; b < steps; ++b) {
            if (walkStep(sw.walk, sw.smp, rays)) continue;
            if (!sw.lightPhase) {
                sw.cameraCount = sw.walk.n;
                sw.smp.dimension = bdptLightDimension(push.maxDepth);
                sw.lightPhase = true;
                if (lightWalk(sw.index * push.lightStride, sw.smp, push.lightStride, sw.walk)) continue;
            }
            vertexCounts[sw.index] = uvec2(sw.cameraCount, sw.walk.n);
            done += 1u;
            if (!fromQueue || done >= push.itemsPerInvocation || bvhStepsTaken + b > BDPT_LOOP_STEPS_BEFORE_STOP)
                break;
            index = atomicAdd(queue[push.queueSlot], 1u);
            if (index >= push.count) break;
            beginSample(sw, index);
        }
    }
    counterAdd(COUNTER_RAYS, rays);
}
