// The body of trace_rays.comp and trace_rays_steps.comp: one ray per invocation, its closest
// hit (or occlusion: t = 0 when occluded, tMax when clear) into a buffer.
#include "shared/host_device.h"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(set = WORK_SET, binding = 0, scalar) readonly buffer Queries { BvhQuery queries[]; };
layout(set = WORK_SET, binding = 1, scalar) writeonly buffer Hits { Hit hits[]; };
layout(push_constant, scalar) uniform Push { uint count; uint anyHit; } push;

#include "common/scene.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.count) return;
    BvhQuery q = queries[i];
    Hit hit;
    if (push.anyHit != 0u) {
        hit.t = traceAny(q.origin, q.direction, q.tMax) ? 0.0 : q.tMax;
        hit.triangle = 0u;
        hit.b1 = 0.0;
        hit.b2 = 0.0;
    } else if (!traceClosest(q.origin, q.direction, q.tMax, hit)) {
        hit.triangle = BVH_NO_HIT;
    }
#ifdef BVH_COUNT_STEPS
    hit.b1 = uintBitsToFloat(bvhInteriorSteps);
    hit.b2 = uintBitsToFloat(bvhTriangleSteps);
#endif
    hits[i] = hit;
}
