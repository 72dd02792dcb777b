#version 460
// Probes whether the driver caps loop iterations (Mesa's gallivm capped every loop at
// LP_MAX_TGSI_LOOP_ITERATIONS = 65535 in its TGSI days). The loop bodies read memory so the
// trip counts cannot be folded at compile time.
//   out[0]: iterations of one loop running push.iterations times
//   out[1]: iterations of push.outer nested loops of push.iterations each
//   out[2]: iterations of a while(true) loop that breaks after push.iterations
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "shared/host_device.h"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(set = WORK_SET, binding = 0, scalar) readonly buffer Ones { uint ones[8]; };
layout(set = WORK_SET, binding = 1, scalar) writeonly buffer Out { uint outValues[]; };
layout(push_constant, scalar) uniform Push { uint iterations; uint outer; } push;

void main() {
    if (gl_GlobalInvocationID.x != 0u) return;
    uint single = 0u;
    for (uint i = 0u; i < push.iterations; ++i) single += ones[i & 7u];
    outValues[0] = single;

    uint nested = 0u;
    for (uint o = 0u; o < push.outer; ++o)
        for (uint i = 0u; i < push.iterations; ++i) nested += ones[(i + o) & 7u];
    outValues[1] = nested;

    uint counted = 0u;
    uint i = 0u;
    while (true) {
        if (i >= push.iterations) break;
        counted += ones[i & 7u];
        ++i;
    }
    outValues[2] = counted;
}
