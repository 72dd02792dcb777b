// The body of trace_rays.comp and trace_rays_steps.comp: closest hits (or occlusion: t = 0 when
// occluded, tMax when clear) of a buffer of rays into a buffer. With raysPerInvocation P > 1
// the count rays go to N = ceil(count / P) invocations, invocation i taking rays i, i + N, ...
// in turn: a lane starts its next ray as soon as its last one ends, so that SIMD lanes (lavapipe
// runs 8 invocations as one vector) do not idle until the longest ray of their vector ends.
#include "shared/host_device.h"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(set = WORK_SET, binding = 0, scalar) readonly buffer Queries { BvhQuery queries[]; };
layout(set = WORK_SET, binding = 1, scalar) writeonly buffer Hits { Hit hits[]; };
layout(push_constant, scalar) uniform Push {
    uint count;
    uint anyHit;
    uint raysPerInvocation;
} push;

#include "common/scene.glsl"

void startRay(uint i, out BvhTraversal t) {
#ifdef BVH_COUNT_STEPS
    bvhNodeSteps = 0u;
    bvhLeafSteps = 0u;
#endif
    BvhQuery q = queries[i];
    bvhBegin(q.origin, q.direction, q.tMax, push.anyHit != 0u, t);
}

void finishRay(uint i, BvhTraversal t) {
    Hit hit = t.hit;
    if (push.anyHit != 0u) {
        hit = Hit(t.found ? 0.0 : t.hit.t, 0u, 0.0, 0.0);
    }
#ifdef BVH_COUNT_STEPS
    hit.b1 = uintBitsToFloat(bvhNodeSteps);
    hit.b2 = uintBitsToFloat(bvhLeafSteps);
#endif
    hits[i] = hit;
}

void main() {
    uint P = max(push.raysPerInvocation, 1u);
    uint N = (push.count + P - 1u) / P;
    uint ray = gl_GlobalInvocationID.x;
    if (ray >= N) return;
    BvhTraversal t;
    startRay(ray, t);
    bool running = true;
    // Each ray takes fewer steps than the BVH has texels (bvh.glsl), plus one to finish it.
    uint steps = P * (uint(textureSize(bvhTexels)) + 1u);
    for (uint step = 0u; step < steps; ++step) {
        if (running) {
            running = bvhStep(t);
        }
        if (!running) {
            finishRay(ray, t);
            ray += N;
            if (ray >= push.count) break;
            startRay(ray, t);
            running = true;
        }
    }
}
