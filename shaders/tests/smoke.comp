#version 460
// Smallest possible kernel: out[i] = in[i] * 2 + i. Proves the build, the SPIR-V registry and
// a dispatch round trip.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "shared/host_device.h"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(set = WORK_SET, binding = 0, scalar) readonly buffer In { uint inValues[]; };
layout(set = WORK_SET, binding = 1, scalar) writeonly buffer Out { uint outValues[]; };
layout(push_constant, scalar) uniform Push { uint count; } push;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.count) return;
    outValues[i] = inValues[i] * 2u + i;
}
