#version 460
// Test kernel for shaders/common/environment.glsl over the bound scene's environment
// (tests/gpu/test_environment.cpp).
//   mode 0: envSample with uPixel, uPoint from rngCreate(hashCombine(i, seed)):
//           results[3i] = (wi, pdf), results[3i + 1] = (Le, envPdf(wi)),
//           results[3i + 2] = (envRadiance(wi), 0)
//   mode 1: a uniform direction d on the sphere: results[i] = (d, envPdf(d))
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "shared/host_device.h"

#include "common/environment.glsl"
#include "common/rng.glsl"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(set = WORK_SET, binding = 0, scalar) writeonly buffer Results { vec4 results[]; };
layout(push_constant, scalar) uniform Push {
    uint mode;
    uint count;
    uint seed;
} push;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.count) return;
    Rng rng = rngCreate(hashCombine(i, push.seed));
    if (push.mode == 0u) {
        float uPixel = rngNext(rng);
        EnvSample e = envSample(uPixel, rngNext2(rng));
        results[3u * i] = vec4(e.wi, e.pdf);
        results[3u * i + 1u] = vec4(e.Le, envPdf(e.wi));
        results[3u * i + 2u] = vec4(envRadiance(e.wi), 0.0);
    } else {
        vec3 d = sampleUniformSphere(rngNext2(rng));
        results[i] = vec4(d, envPdf(d));
    }
}
