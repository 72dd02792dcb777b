// The body shared by the per-camera-sample kernels (pt, pt_record, direct): where each
// invocation's camera samples come from (a tile of pixels, a list of requested pixel samples,
// or given raster positions), and where their estimates go (film, results buffer).
// The including .comp defines `vec3 estimateRadiance(vec2 raster, inout Sampler s, inout uint
// rays, uint recordIndex)` before including this file, and CAMERA_SAMPLE_PATH_STATES when
// estimateRadiance is pathTrace without path records (pathBegin / pathBounce are then used
// directly for the tile source).
#ifndef PMCR_CAMERA_SAMPLE_KERNEL_GLSL
#define PMCR_CAMERA_SAMPLE_KERNEL_GLSL

layout(set = WORK_SET, binding = PT_BINDING_REQUESTS, scalar) readonly buffer RequestBuffer {
    SampleRequest requests[];
};
layout(set = WORK_SET, binding = PT_BINDING_RESULTS, scalar) writeonly buffer ResultBuffer {
    vec4 results[];
};

vec2 pixelCorner(uint pixel) {
    return vec2(float(pixel % sceneInfo.width), float(pixel / sceneInfo.width));
}

#ifdef CAMERA_SAMPLE_PATH_STATES
// The tile source with paths in turn (pt.comp, which defines CAMERA_SAMPLE_PATH_STATES): the
// tile's invocationCount pixels go to N = ceil(count / P) invocations, invocation i taking
// pixels i, i + N, i + 2N, ... (so neighbouring lanes trace neighbouring pixels), each with all
// its samples in order. A lane starts its next path as soon as one ends, so the loop runs until
// the lane with the most bounces in all has finished, not P times the longest single path: on
// SIMD lanes (lavapipe runs 8 invocations as one vector) fewer lanes idle. Each pixel still has
// one writer per dispatch and gets its samples in the same order, so the film is the same bit
// for bit whatever P is.
void tileWithPathsInTurn(uint i, inout uint rays, inout uint dropped, inout uint paths) {
    uint P = max(push.pixelsPerInvocation, 1u);
    uint N = (push.invocationCount + P - 1u) / P;
    if (i >= N) return;
    uint spp = push.samplesPerPixel;
    uint total = ((push.invocationCount - i + N - 1u) / N) * spp;  // this invocation's paths
    if (total == 0u) return;
    uint item = 0u;
    uint pixel = push.pixelOffset + i;
    Sampler s = samplerCreate(pixel, push.sampleBase, push.seed);
    PathState p = pathBegin(pixelCorner(pixel) + samplerGet2D(s), 0u);
    // Each path takes at most maxDepth + 1 bounces.
    uint bounces = total * (push.maxDepth + 1u);
    for (uint b = 0u; b < bounces; ++b) {
        if (pathBounce(p, s, push.maxDepth, push.rrDepth, rays)) continue;
        PixelAccumulator acc = accumulatorCreate();
        accumulatorAdd(acc, p.L);
        if ((push.flags & PT_FLAG_DEPOSIT) != 0u)
            filmAccumulate(pixel, acc.sum, acc.lumSum, acc.lumSqSum, acc.count);
        dropped += acc.dropped;
        paths += acc.count;
        item += 1u;
        if (item == total) break;
        pixel = push.pixelOffset + i + (item / spp) * N;
        s = samplerCreate(pixel, push.sampleBase + item % spp, push.seed);
        p = pathBegin(pixelCorner(pixel) + samplerGet2D(s), 0u);
    }
}
#endif

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint rays = 0u;
    uint dropped = 0u;
    uint paths = 0u;
#ifdef CAMERA_SAMPLE_PATH_STATES
    if (push.source == PT_SOURCE_TILE) {
        tileWithPathsInTurn(i, rays, dropped, paths);
    } else
#endif
    if (i < push.invocationCount) {
        if (push.source == PT_SOURCE_TILE) {
            // One invocation per pixel, all its samples: each pixel has one writer per dispatch,
            // so the film sums are deterministic. Each sample goes to the film on its own, in
            // order, so the sums are the same bit for bit however the samples are split into
            // dispatches.
            uint pixel = push.pixelOffset + i;
            for (uint k = 0u; k < push.samplesPerPixel; ++k) {
                Sampler s = samplerCreate(pixel, push.sampleBase + k, push.seed);
                vec2 raster = pixelCorner(pixel) + samplerGet2D(s);
                PixelAccumulator acc = accumulatorCreate();
                accumulatorAdd(acc, estimateRadiance(raster, s, rays,
                                                     push.recordOffset + i * push.samplesPerPixel + k));
                if ((push.flags & PT_FLAG_DEPOSIT) != 0u)
                    filmAccumulate(pixel, acc.sum, acc.lumSum, acc.lumSqSum, acc.count);
                dropped += acc.dropped;
                paths += acc.count;
            }
        } else {
            SampleRequest r = requests[push.requestOffset + i];
            Sampler s = samplerCreate(r.pixel, r.sampleIndex, push.seed);
            vec2 raster = r.raster;
            uint pixel = r.pixel;
            if (push.source == PT_SOURCE_LIST) {
                raster = pixelCorner(r.pixel) + samplerGet2D(s);
            } else {
                raster = clamp(raster, vec2(0.0),
                               vec2(sceneInfo.width, sceneInfo.height) * ONE_MINUS_EPSILON);
                pixel = uint(raster.y) * sceneInfo.width + uint(raster.x);
            }
            PixelAccumulator acc = accumulatorCreate();
            accumulatorAdd(acc, estimateRadiance(raster, s, rays, push.recordOffset + i));
            if ((push.flags & PT_FLAG_DEPOSIT) != 0u)
                filmAccumulate(pixel, acc.sum, acc.lumSum, acc.lumSqSum, acc.count);
            if ((push.flags & PT_FLAG_WRITE_RESULTS) != 0u) results[push.requestOffset + i] = vec4(acc.sum, acc.lumSum);
            dropped = acc.dropped;
            paths = 1u;
        }
    }
    counterAdd(COUNTER_RAYS, rays);
    counterAdd(COUNTER_NAN_DROPPED, dropped);
    counterAdd(COUNTER_PATHS, paths);
}

#endif
