#version 460
// Deposits values[i] into pixel i % pixelCount through the renderer's accumulator and film
// code, so the test can check that NaN/Inf samples are dropped and counted, not added.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "shared/host_device.h"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(push_constant, scalar) uniform Push { uint count; uint pixelCount; } push;
#define FILM_BINDING 0
#define COUNTERS_BINDING 1
#include "common/film.glsl"
layout(set = WORK_SET, binding = 2, scalar) readonly buffer Values { vec3 values[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint dropped = 0u;
    if (i < push.count) {
        PixelAccumulator acc = accumulatorCreate();
        accumulatorAdd(acc, values[i]);
        filmAccumulate(i % push.pixelCount, acc.sum, acc.lumSum, acc.lumSqSum, acc.count);
        dropped = acc.dropped;
    }
    counterAdd(COUNTER_NAN_DROPPED, dropped);
}
