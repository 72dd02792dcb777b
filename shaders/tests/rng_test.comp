#version 460
// Test kernel for shaders/common/rng.glsl (tests/gpu/test_rng.cpp). Invocation i:
//   mode 0: words[4i..4i+3] = hashPcg(a), hashCombine(a, b), hash3(a, b, c), rngCreate(a).state
//           for (a, b, c) = inputs[i].xyz
//   mode 1: rng = rngCreate(seed + i); words[i * perStream + k] = rngNextUint(rng), k < perStream
//   mode 2: as mode 1 with the bits of rngNext(rng)
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "shared/host_device.h"

#include "common/rng.glsl"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(set = WORK_SET, binding = 0, scalar) readonly buffer Inputs { uvec4 inputs[]; };
layout(set = WORK_SET, binding = 1, scalar) writeonly buffer Words { uint words[]; };
layout(push_constant, scalar) uniform Push {
    uint mode;
    uint count;
    uint seed;
    uint perStream;
} push;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.count) return;
    if (push.mode == 0u) {
        uvec4 v = inputs[i];
        words[4u * i] = hashPcg(v.x);
        words[4u * i + 1u] = hashCombine(v.x, v.y);
        words[4u * i + 2u] = hash3(v.x, v.y, v.z);
        words[4u * i + 3u] = rngCreate(v.x).state;
        return;
    }
    Rng rng = rngCreate(push.seed + i);
    for (uint k = 0u; k < push.perStream; ++k)
        words[i * push.perStream + k] =
            push.mode == 1u ? rngNextUint(rng) : floatBitsToUint(rngNext(rng));
}
