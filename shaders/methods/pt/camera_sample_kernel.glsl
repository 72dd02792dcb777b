// The body shared by the per-camera-sample kernels (pt, pt_record, direct): where each
// invocation's camera samples come from (a tile of pixels, a list of requested pixel samples,
// or given raster positions), and where their estimates go (film, results buffer).
// The including .comp defines `vec3 estimateRadiance(vec2 raster, inout Sampler s, inout uint
// rays, uint recordIndex)` before including this file, or defines CAMERA_SAMPLE_PATH_STATES
// when it path-traces: pathBegin / pathBounce / pathEnd are then used directly, for paths in
// turn. It may define CAMERA_SAMPLE_FINISH() as a statement main runs last, in uniform control
// flow (counters of its own).
#ifndef PMCR_CAMERA_SAMPLE_KERNEL_GLSL
#define PMCR_CAMERA_SAMPLE_KERNEL_GLSL

#include "common/kernel_options.glsl"

layout(set = WORK_SET, binding = PT_BINDING_REQUESTS, scalar) readonly buffer RequestBuffer {
    SampleRequest requests[];
};
layout(set = WORK_SET, binding = PT_BINDING_RESULTS, scalar) writeonly buffer ResultBuffer {
    vec4 results[];
};

vec2 pixelCorner(uint pixel) {
    return vec2(float(pixel % sceneInfo.width), float(pixel / sceneInfo.width));
}

// The raster position of camera sample s in `pixel`: the first dimension pair of the pixel's
// stratified sequence, or in kernels specialized for independent pixel samples (--pixel-sampler
// independent, a paper baseline; common/kernel_options.glsl) a point uniform in the pixel and
// independent of its other samples. Either way the path's other random numbers are the
// sequence's.
vec2 pixelSamplePosition(uint pixel, inout Sampler s) {
    vec2 u = independentPixelSamples() ? samplerGetIndependent2D(s) : samplerGet2D(s);
    return pixelCorner(pixel) + u;
}

// The camera sample a request asks for: its sampler, raster position and pixel.
void requestedSample(SampleRequest r, out Sampler s, out vec2 raster, out uint pixel) {
    s = samplerCreate(r.pixel, r.sampleIndex, push.seed);
    raster = r.raster;
    pixel = r.pixel;
    if (push.source == PT_SOURCE_LIST) {
        raster = pixelSamplePosition(r.pixel, s);
    } else {
        raster = clamp(raster, vec2(0.0),
                       vec2(sceneInfo.width, sceneInfo.height) * ONE_MINUS_EPSILON);
        pixel = uint(raster.y) * sceneInfo.width + uint(raster.x);
    }
}

#ifdef CAMERA_SAMPLE_PATH_STATES
// Paths in turn (pt.comp and pt_record.comp, which define CAMERA_SAMPLE_PATH_STATES): with
// itemsPerInvocation P > 1 the dispatch's invocationCount items (the tile's pixels, or
// requests) go to N = ceil(count / P) invocations, invocation i taking items i, i + N, i + 2N,
// ... (so neighbouring lanes trace neighbouring pixels), a tile pixel with all its samples in
// order. A lane starts its next path as soon as one ends, so the loop runs until the lane with
// the most bounces in all has finished, not P times the longest single path: on SIMD lanes
// (lavapipe runs 8 invocations as one vector) fewer lanes idle. Each pixel still has one writer
// per dispatch in tile mode and gets its samples in the same order, and each request and path
// record is written by its own path, so film, results and records are the same bit for bit
// whatever P is (tests/gpu/test_pt_dispatch.cpp, test_path_records.cpp).

// Starts path `item` of invocation i of N: its pixel, result slot (lists), raster position,
// record index (PT_RECORD_PATHS: as the one-path-per-invocation body numbers them), sampler
// and path.
void pathsInTurnStart(uint i, uint N, uint item, out uint pixel, out uint slot, out vec2 raster,
                      out uint record, out Sampler s, out PathState p) {
    slot = 0u;
    if (push.source == PT_SOURCE_TILE) {
        uint k = item % push.samplesPerPixel;
        uint tileIndex = i + (item / push.samplesPerPixel) * N;
        pixel = push.pixelOffset + tileIndex;
        record = push.recordOffset + tileIndex * push.samplesPerPixel + k;
        s = samplerCreate(pixel, push.sampleBase + k, push.seed);
        raster = pixelSamplePosition(pixel, s);
    } else {
        uint index = i + item * N;
        slot = push.requestOffset + index;
        record = push.recordOffset + index;
        requestedSample(requests[slot], s, raster, pixel);
    }
    p = pathBegin(raster, record);
}

void pathsInTurn(uint i, inout uint rays, inout uint dropped, inout uint paths) {
    uint P = max(push.itemsPerInvocation, 1u);
    uint N = (push.invocationCount + P - 1u) / P;
    if (i >= N) return;
    uint total = (push.invocationCount - i + N - 1u) / N;  // this invocation's items
    if (push.source == PT_SOURCE_TILE) total *= push.samplesPerPixel;
    if (total == 0u) return;
    uint maxDepth = pathMaxDepth(push.maxDepth);
    uint item = 0u;
    uint pixel, slot, record;
    vec2 raster;
    Sampler s;
    PathState p;
    pathsInTurnStart(i, N, item, pixel, slot, raster, record, s, p);
    // Each path takes at most maxDepth + 1 bounces.
    uint bounces = total * (maxDepth + 1u);
    for (uint b = 0u; b < bounces; ++b) {
        if (pathBounce(p, s, maxDepth, push.rrDepth, rays)) continue;
        pathEnd(p, raster, record);
        PixelAccumulator acc = accumulatorCreate();
        accumulatorAdd(acc, p.L);
        if ((push.flags & PT_FLAG_DEPOSIT) != 0u)
            filmAccumulate(pixel, acc.sum, acc.lumSum, acc.lumSqSum, acc.count);
        if (push.source != PT_SOURCE_TILE && (push.flags & PT_FLAG_WRITE_RESULTS) != 0u)
            results[slot] = vec4(acc.sum, acc.lumSum);
        dropped += acc.dropped;
        paths += acc.count;
        item += 1u;
        if (item == total) break;
        pathsInTurnStart(i, N, item, pixel, slot, raster, record, s, p);
    }
}
#endif

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint rays = 0u;
    uint dropped = 0u;
    uint paths = 0u;
#ifdef CAMERA_SAMPLE_PATH_STATES
    pathsInTurn(i, rays, dropped, paths);
#else
    if (i < push.invocationCount) {
        if (push.source == PT_SOURCE_TILE) {
            // One invocation per pixel, all its samples: each pixel has one writer per dispatch,
            // so the film sums are deterministic. Each sample goes to the film on its own, in
            // order, so the sums are the same bit for bit however the samples are split into
            // dispatches.
            uint pixel = push.pixelOffset + i;
            for (uint k = 0u; k < push.samplesPerPixel; ++k) {
                Sampler s = samplerCreate(pixel, push.sampleBase + k, push.seed);
                vec2 raster = pixelSamplePosition(pixel, s);
                PixelAccumulator acc = accumulatorCreate();
                accumulatorAdd(acc, estimateRadiance(raster, s, rays,
                                                     push.recordOffset + i * push.samplesPerPixel + k));
                if ((push.flags & PT_FLAG_DEPOSIT) != 0u)
                    filmAccumulate(pixel, acc.sum, acc.lumSum, acc.lumSqSum, acc.count);
                dropped += acc.dropped;
                paths += acc.count;
            }
        } else {
            Sampler s;
            vec2 raster;
            uint pixel;
            requestedSample(requests[push.requestOffset + i], s, raster, pixel);
            PixelAccumulator acc = accumulatorCreate();
            accumulatorAdd(acc, estimateRadiance(raster, s, rays, push.recordOffset + i));
            if ((push.flags & PT_FLAG_DEPOSIT) != 0u)
                filmAccumulate(pixel, acc.sum, acc.lumSum, acc.lumSqSum, acc.count);
            if ((push.flags & PT_FLAG_WRITE_RESULTS) != 0u) results[push.requestOffset + i] = vec4(acc.sum, acc.lumSum);
            dropped = acc.dropped;
            paths = 1u;
        }
    }
#endif
    counterAdd(COUNTER_RAYS, rays);
    counterAdd(COUNTER_NAN_DROPPED, dropped);
    counterAdd(COUNTER_PATHS, paths);
#ifdef CAMERA_SAMPLE_FINISH
    CAMERA_SAMPLE_FINISH();
#endif
}

#endif
