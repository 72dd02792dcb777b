#version 460
// Test kernel for shaders/common/bvh.glsl: invocation i traces queries[i] with traceClosest
// and traceAny and writes hits[i] and occluded[i], to be compared with Bvh::traceClosest and
// Bvh::traceAny on the host.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "shared/host_device.h"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(set = WORK_SET, binding = 0, scalar) readonly buffer Queries { BvhQuery queries[]; };
layout(set = WORK_SET, binding = 1, scalar) writeonly buffer Hits { Hit hits[]; };
layout(set = WORK_SET, binding = 2, scalar) writeonly buffer Occluded { uint occluded[]; };
layout(push_constant, scalar) uniform Push { uint count; } push;

#include "common/bvh.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.count) {
        return;
    }
    BvhQuery query = queries[i];
    Hit hit;
    traceClosest(query.origin, query.direction, query.tMax, hit);
    hits[i] = hit;
    occluded[i] = traceAny(query.origin, query.direction, query.tMax) ? 1u : 0u;
}
