// Film deposition and statistics counters, on the work set.
// The includer may #define FILM_BINDING / COUNTERS_BINDING before including (defaults: the path
// tracer's bindings). Samples with NaN/Inf are dropped before the atomic add and counted
// (Tungsten SplatQueue, pbrt-v4): a dropped sample still counts as a sample (of value zero).
#ifndef PMCR_FILM_GLSL
#define PMCR_FILM_GLSL

#extension GL_EXT_shader_atomic_float : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_basic : require

#include "common/math.glsl"

#ifndef FILM_BINDING
#define FILM_BINDING PT_BINDING_FILM
#endif
#ifndef COUNTERS_BINDING
#define COUNTERS_BINDING PT_BINDING_COUNTERS
#endif

layout(set = WORK_SET, binding = FILM_BINDING, scalar) buffer FilmBuffer { FilmPixel film[]; };
layout(set = WORK_SET, binding = COUNTERS_BINDING, scalar) buffer CounterBuffer { uint counters[]; };

// Adds `value` to a counter: one atomic per subgroup.
void counterAdd(uint counter, uint value) {
    uint total = subgroupAdd(value);
    if (subgroupElect() && total != 0u) atomicAdd(counters[counter], total);
}

// Adds pre-summed samples to a pixel (sum of radiance, of luminance and of squared luminance).
void filmAccumulate(uint pixel, vec3 sum, float lumSum, float lumSqSum, uint count) {
    if (sum.x != 0.0) atomicAdd(film[pixel].sum.x, sum.x);
    if (sum.y != 0.0) atomicAdd(film[pixel].sum.y, sum.y);
    if (sum.z != 0.0) atomicAdd(film[pixel].sum.z, sum.z);
    if (lumSum != 0.0) atomicAdd(film[pixel].lumSum, lumSum);
    if (lumSqSum != 0.0) atomicAdd(film[pixel].lumSqSum, lumSqSum);
    atomicAdd(film[pixel].sampleCount, count);
}

// Per-invocation accumulator for the samples of one pixel.
struct PixelAccumulator {
    vec3 sum;
    float lumSum;
    float lumSqSum;
    uint count;
    uint dropped;
};

PixelAccumulator accumulatorCreate() {
    PixelAccumulator a;
    a.sum = vec3(0.0);
    a.lumSum = 0.0;
    a.lumSqSum = 0.0;
    a.count = 0u;
    a.dropped = 0u;
    return a;
}

void accumulatorAdd(inout PixelAccumulator a, vec3 L) {
    a.count += 1u;
    if (!isFinite(L)) {
        a.dropped += 1u;
        return;
    }
    float y = luminance(L);
    a.sum += L;
    a.lumSum += y;
    a.lumSqSum += y * y;
}

#endif
