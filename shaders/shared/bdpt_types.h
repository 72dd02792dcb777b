// Bidirectional path tracing (Veach and Guibas 1995; Veach 1997 ch. 10; pbrt-v4 BDPTIntegrator):
// per camera sample one camera subpath and one light subpath, written to storage buffers by
// bdpt_subpaths.comp, then every connection strategy (s light vertices, t camera vertices)
// evaluated and MIS-weighted by bdpt_connect.comp (shaders/methods/bdpt/).

// What a subpath vertex is (BdptVertex.type).
PMCR_CONST uint BDPT_CAMERA = 0u;       // the pinhole (camera subpath vertex 0)
PMCR_CONST uint BDPT_SURFACE = 1u;      // a surface hit (an emitter's too: it also scatters)
PMCR_CONST uint BDPT_LIGHT_AREA = 2u;   // light subpath vertex 0 on an emitter triangle
PMCR_CONST uint BDPT_LIGHT_POINT = 3u;  // light subpath vertex 0 at a point or spot light
PMCR_CONST uint BDPT_LIGHT_INFINITE = 4u;  // the environment or a directional light: a direction

// BdptVertex.flags
PMCR_CONST uint BDPT_VERTEX_DELTA = 1u;        // scattered by a delta lobe (pbrt-v4 Vertex::delta)
PMCR_CONST uint BDPT_VERTEX_DIRECTIONAL = 2u;  // BDPT_LIGHT_INFINITE: a directional light (a delta
                                               // in direction), not the environment

// One subpath vertex, as pbrt-v4's Vertex: throughput beta, the area densities of the subpath
// reaching it forwards and backwards (solid angle towards an infinite light), and what the
// connection kernel needs to evaluate its BSDF again (the triangle and barycentrics, and wo: the
// direction towards the previous vertex of its subpath). An infinite light vertex keeps in wo
// the direction from the scene towards the light; a point light's `triangle` is its index.
struct BdptVertex {
    vec3 position;
    uint type;       // BDPT_*
    vec3 normal;     // geometric normal as wound (surfaces, emitters)
    uint triangle;   // surface, area light: the triangle; point light: the punctual index
    vec3 beta;
    float pdfFwd;
    vec3 wo;
    float pdfRev;
    vec2 barycentrics;
    uint flags;      // BDPT_VERTEX_*
    float pad;
};
PMCR_CHECK_SIZE(BdptVertex, 80);

// The sampler dimensions of a camera sample (common/sampler.glsl): the raster position (0), the
// camera walk from 1 (three per vertex: lobe, direction, roulette), the light subpath from
// BDPT_LIGHT_DIMENSION (the light, its point and direction, then three per vertex), and the
// light samples of the s = 1 connections from BDPT_CONNECT_DIMENSION (bdpt_vertex.glsl).
#define BDPT_LIGHT_DIMENSION(maxDepth) (1u + 3u * ((maxDepth) + 2u))
#define BDPT_CONNECT_DIMENSION(maxDepth) (BDPT_LIGHT_DIMENSION(maxDepth) + 3u + 3u * ((maxDepth) + 1u))

// Strategy images (--strategy-images): the (s, t) strategies of paths of up to
// BDPT_STRATEGY_MAX_DEPTH bounces, depth d = s + t - 2 holding s = 0 .. d + 1, indexed
// d (d + 3) / 2 + s; per pixel and strategy the weighted and the unweighted contribution.
PMCR_CONST uint BDPT_STRATEGY_MAX_DEPTH = 4u;
PMCR_CONST uint BDPT_STRATEGY_COUNT = 20u;  // sum over d = 0..4 of d + 2

// Work-set bindings of the bdpt kernels. 6 is ERPT's splat film (shared/chain_types.h), so that
// splat.glsl deposits light tracing's (t = 1) contributions with order-independent integer sums.
PMCR_CONST uint BDPT_BINDING_FILM = 0;             // FilmPixel[]: t >= 2 strategies per camera sample
PMCR_CONST uint BDPT_BINDING_COUNTERS = 1;         // uint[COUNTER_COUNT]
PMCR_CONST uint BDPT_BINDING_CAMERA_VERTICES = 2;  // BdptVertex[sample * cameraStride + i]
PMCR_CONST uint BDPT_BINDING_LIGHT_VERTICES = 3;   // BdptVertex[sample * lightStride + i]
PMCR_CONST uint BDPT_BINDING_COUNTS = 4;           // uvec2[sample]: camera and light vertex counts
PMCR_CONST uint BDPT_BINDING_STRATEGIES = 5;       // float[(pixel * COUNT + strategy) * 6]
PMCR_CONST uint BDPT_BINDING_SPLAT = 6;            // SplatPixel[] (= ERPT_BINDING_SPLAT)
PMCR_CONST uint BDPT_BINDING_QUEUE = 8;            // uint[BDPT_QUEUE_SLOTS]: walks and connections in turn
PMCR_CONST uint BDPT_QUEUE_SLOTS = 4096;           // two per pair of dispatches of a batch

PMCR_CONST uint BDPT_FLAG_STRATEGY_IMAGES = 1u;  // write the strategy images

struct BdptPush {
    uint pixelOffset;      // first linear pixel of this dispatch (one sample per pixel per pass)
    uint count;            // camera samples in this dispatch
    uint sampleIndex;      // the pass: each pixel's sample index
    uint seed;
    uint maxDepth;         // bounces, as pt's (s + t - 2 <= maxDepth)
    uint rrDepth;
    uint cameraStride;     // maxDepth + 2 vertices
    uint lightStride;      // maxDepth + 1 vertices
    uint flags;            // BDPT_FLAG_*
    uint pad2;
    uint itemsPerInvocation;  // > 1: samples from queue[queueSlot] in turn (CPU)
    uint queueSlot;
};
PMCR_CHECK_SIZE(BdptPush, 48);
