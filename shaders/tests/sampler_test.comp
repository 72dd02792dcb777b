#version 460
// Test kernel for shaders/common/sampler.glsl (tests/gpu/test_sampler.cpp). Invocation i:
//   mode 0: words[4i..4i+3] = sobolSecondDimension(a), laineKarrasPermutation(a, b),
//           nestedUniformScramble(a, b), 0 for (a, b) = inputs[i].xy
//   mode 1: sample s = i % samplesPerPixel of pixel pixelBase + (i / samplesPerPixel) * pixelStride,
//           index sampleBase + s: `dimensions` calls of samplerGet2D, as floats at
//           words[2 (i * dimensions + d) + {0, 1}]
//   mode 2: as mode 1 with samplerGet1D, at words[i * dimensions + d]
//   mode 3: as mode 1 with samplerGetIndependent2D in place of the first samplerGet2D
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "shared/host_device.h"

#include "common/sampler.glsl"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(set = WORK_SET, binding = 0, scalar) readonly buffer Inputs { uvec4 inputs[]; };
layout(set = WORK_SET, binding = 1, scalar) writeonly buffer Words { uint words[]; };
layout(push_constant, scalar) uniform Push {
    uint mode;
    uint count;
    uint seed;
    uint dimensions;
    uint samplesPerPixel;
    uint pixelBase;
    uint pixelStride;
    uint sampleBase;
} push;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.count) return;
    if (push.mode == 0u) {
        uvec4 v = inputs[i];
        words[4u * i] = sobolSecondDimension(v.x);
        words[4u * i + 1u] = laineKarrasPermutation(v.x, v.y);
        words[4u * i + 2u] = nestedUniformScramble(v.x, v.y);
        words[4u * i + 3u] = 0u;
        return;
    }
    uint pixel = push.pixelBase + (i / push.samplesPerPixel) * push.pixelStride;
    Sampler s = samplerCreate(pixel, push.sampleBase + i % push.samplesPerPixel, push.seed);
    for (uint d = 0u; d < push.dimensions; ++d) {
        uint slot = i * push.dimensions + d;
        if (push.mode == 1u || push.mode == 3u) {
            vec2 u = push.mode == 3u && d == 0u ? samplerGetIndependent2D(s) : samplerGet2D(s);
            words[2u * slot] = floatBitsToUint(u.x);
            words[2u * slot + 1u] = floatBitsToUint(u.y);
        } else {
            words[slot] = floatBitsToUint(samplerGet1D(s));
        }
    }
}
