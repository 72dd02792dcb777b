#version 460
// Probes the driver's loop limits (see tests/gpu/test_loop_limits.cpp). Loop bodies read memory
// so trip counts cannot be folded at compile time. One invocation runs one pattern:
//   mode 0: for loop of a iterations                      -> out[0]
//   mode 1: for loop of a, then a second for loop of b    -> out[0], out[1]
//   mode 2: a outer x b inner nested for loops            -> out[1]
//   mode 3: while (true) { if (i >= a) break; ... }        -> out[0]
//   mode 4: a separate loops of b iterations each, in a   -> out[1] (total), out[2] (last loop)
//           loop that the driver cannot unroll
//   mode 5: every invocation runs a for loop of a iterations -> out[3 + invocation]
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "shared/host_device.h"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(set = WORK_SET, binding = 0, scalar) readonly buffer Ones { uint ones[8]; };
layout(set = WORK_SET, binding = 1, scalar) writeonly buffer Out { uint outValues[]; };
layout(push_constant, scalar) uniform Push { uint a; uint b; uint mode; } push;

void main() {
    if (push.mode == 5u) {
        uint c = 0u;
        for (uint i = 0u; i < push.a; ++i) c += ones[i & 7u];
        outValues[3u + gl_GlobalInvocationID.x] = c;
        return;
    }
    if (gl_GlobalInvocationID.x != 0u) return;
    uint c0 = 0u, c1 = 0u, c2 = 0u;
    if (push.mode == 0u || push.mode == 1u) {
        for (uint i = 0u; i < push.a; ++i) c0 += ones[i & 7u];
        if (push.mode == 1u)
            for (uint i = 0u; i < push.b; ++i) c1 += ones[i & 7u];
    } else if (push.mode == 2u) {
        for (uint o = 0u; o < push.a; ++o)
            for (uint i = 0u; i < push.b; ++i) c1 += ones[(i + o) & 7u];
    } else if (push.mode == 3u) {
        uint i = 0u;
        while (true) {
            if (i >= push.a) break;
            c0 += ones[i & 7u];
            ++i;
        }
    } else {
        for (uint o = 0u; o < push.a; ++o) {
            c2 = 0u;
            for (uint i = 0u; i < push.b; ++i) c2 += ones[(i + o) & 7u];
            c1 += c2;
        }
    }
    outValues[0] = c0;
    outValues[1] = c1;
    outValues[2] = c2;
}
