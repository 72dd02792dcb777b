// Film, counters and the path tracer's dispatch parameters.

// One film pixel: running sums of every sample that landed in it (box filter). The pixel
// estimate is sum / sampleCount for per-pixel estimators (pt, direct, pmc-ip, pmc-pt); splatting
// estimators (erpt, pmc-er) use a fixed scale instead (see host/render/film.h).
// lumSum/lumSqSum give the per-pixel sample variance that PMC-IP and PMC-PT adapt to.
struct FilmPixel {
    vec3 sum;
    float lumSum;
    float lumSqSum;
    uint sampleCount;
};
PMCR_CHECK_SIZE(FilmPixel, 24);

// Counters every kernel may add to (reduced per subgroup, then one atomic). The host reads
// and clears them after each batch, so 32 bits never overflow.
PMCR_CONST uint COUNTER_RAYS = 0;           // closest-hit and shadow rays traced
PMCR_CONST uint COUNTER_NAN_DROPPED = 1;    // samples dropped for NaN/Inf before deposition
PMCR_CONST uint COUNTER_PATHS = 2;          // camera paths completed
PMCR_CONST uint COUNTER_PROPOSALS = 3;      // mutation bookkeeping (erpt, pmc-er)
PMCR_CONST uint COUNTER_COUNT = 16;

// Work-set bindings of the path tracing kernels (pt.comp, direct.comp).
PMCR_CONST uint PT_BINDING_FILM = 0;         // FilmPixel[width * height]
PMCR_CONST uint PT_BINDING_COUNTERS = 1;     // uint[COUNTER_COUNT]
PMCR_CONST uint PT_BINDING_REQUESTS = 2;     // SampleRequest[] (PT_SOURCE_LIST / _POINTS)
PMCR_CONST uint PT_BINDING_RESULTS = 3;      // vec4[] per request (PT_FLAG_WRITE_RESULTS)
PMCR_CONST uint PT_BINDING_PATH_RECORDS = 4; // PathRecord[] (PT_FLAG_RECORD_PATHS)
PMCR_CONST uint PT_BINDING_PATH_VERTICES = 5;// PathVertex[] (PT_FLAG_RECORD_PATHS)

// Where a path tracing dispatch gets its camera samples from.
PMCR_CONST uint PT_SOURCE_TILE = 0;    // invocation i: pixel pixelOffset + i, samples sampleBase .. + samplesPerPixel - 1
PMCR_CONST uint PT_SOURCE_LIST = 1;    // invocation i: requests[i] names the pixel and its sample index
PMCR_CONST uint PT_SOURCE_POINTS = 2;  // invocation i: requests[i] gives a raster position

PMCR_CONST uint PT_FLAG_DEPOSIT = 1u;        // add each sample to the film at its pixel
PMCR_CONST uint PT_FLAG_WRITE_RESULTS = 2u;  // write each sample's radiance to results[i]
PMCR_CONST uint PT_FLAG_RECORD_PATHS = 4u;   // write each sample's path vertices (ERPT, PMC-ER)

// Options a render specializes its kernels for (specialization constant 1, kKernelOptions in
// common/kernel_options.glsl): the papers' weaker baselines (host/render/baseline_options.h).
PMCR_CONST uint KERNEL_OPTION_INDEPENDENT_PIXELS = 1u;  // --pixel-sampler independent: a camera
                                                        // sample uniform in its pixel, no strata
PMCR_CONST uint KERNEL_OPTION_BALANCE_HEURISTIC = 2u;   // --mis balance: MIS weights by the
                                                        // balance heuristic (default: power)

// A camera sample asked for by an adaptive sampler. For PT_SOURCE_LIST the position inside
// the pixel comes from the pixel's own stratified sequence at sampleIndex (or is independent of
// the pixel's other samples, KERNEL_OPTION_INDEPENDENT_PIXELS); for
// PT_SOURCE_POINTS `raster` is used as given and sampleIndex only seeds the path's sampler.
struct SampleRequest {
    uint pixel;
    uint sampleIndex;
    vec2 raster;
};
PMCR_CHECK_SIZE(SampleRequest, 16);

// Push constants of pt.comp and direct.comp.
struct PtPush {
    uint source;           // PT_SOURCE_*
    uint flags;            // PT_FLAG_*
    uint pixelOffset;      // PT_SOURCE_TILE: first linear pixel index of this dispatch
    uint invocationCount;  // number of samples in this dispatch
    uint samplesPerPixel;  // PT_SOURCE_TILE: samples per pixel in this dispatch
    uint sampleBase;       // PT_SOURCE_TILE: index of the first of them in each pixel's sequence
    uint seed;             // render seed: same seed, same image
    uint maxDepth;         // maximum number of scattering events (path length in segments - 1)
    uint rrDepth;          // Russian roulette starts after this many bounces
    uint lightSamples;     // direct.comp: light samples per camera sample (plus as many BSDF samples)
    uint recordOffset;     // PT_FLAG_RECORD_PATHS: index of this dispatch's first PathRecord
    uint requestOffset;    // PT_SOURCE_LIST / _POINTS: index of this dispatch's first request
                           // (and result), so one batch can walk a request list in slices
    uint itemsPerInvocation;  // pt.comp (paths in turn, camera_sample_kernel.glsl): P > 1
                              // dispatches the invocationCount items (tile pixels or
                              // requests) as ceil(count / P) invocations that each take up
                              // to P of them in turn (0 or 1: one each)
};
PMCR_CHECK_SIZE(PtPush, 52);
