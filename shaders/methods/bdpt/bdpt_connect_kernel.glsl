// The body of bdpt_connect.comp and bdpt_connect_all_lights.comp: per camera sample, every
// connection strategy (s, t) of its two subpaths (bdpt_subpaths_kernel.glsl) with s + t - 2 <=
// maxDepth bounces (pbrt-v4 ConnectBDPT), each weighted by multiple importance sampling over all
// the strategies that could have made the same path (bdptMisWeight):
//   s = 0       the camera subpath's vertex t - 1 is on a light (an emitter, the environment);
//   t = 1       light tracing: light vertex s - 1 is connected to the pinhole and its
//               contribution splatted at the pixel it is seen through (fixed-point sums,
//               methods/energy_redistribution/splat.glsl: the same image for the same seed);
//   s = 1       next-event estimation: a light sampled from camera vertex t - 1 as pt samples it
//               (path_tracer.glsl sampleLightFrom), with that light sample's densities;
//   otherwise   light vertex s - 1 and camera vertex t - 1 joined by a shadow ray.
// (s, t) = (1, 1) is skipped (the camera sees a light through s = 0, t = 2), as pbrt does. The
// t >= 2 contributions go to the camera sample's pixel (FilmPixel: per-pixel mean); the host
// divides the splat film by the light subpaths traced per pixel.
#include "shared/host_device.h"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(push_constant, scalar) uniform PushBlock { BdptPush push; };

#define BVH_COUNT_STEPS  // bvhStepsTaken, for connections in turn (main)
#define FILM_BINDING BDPT_BINDING_FILM
#define COUNTERS_BINDING BDPT_BINDING_COUNTERS
#include "common/film.glsl"
#include "methods/bdpt/bdpt_mis.glsl"
#include "methods/energy_redistribution/splat.glsl"
#include "methods/pt/path_tracer.glsl"

layout(set = WORK_SET, binding = BDPT_BINDING_STRATEGIES, scalar) buffer StrategyBuffer {
    float strategies[];
};
layout(set = WORK_SET, binding = BDPT_BINDING_QUEUE, scalar) buffer QueueBuffer { uint queue[]; };

// The light vertex of next-event estimation's sample ls (s = 1): its position or direction and
// the density with which light sampling picks it (vertexPdfLightOrigin).
BdptVertex sampledLightVertex(LightSampleFrom ls) {
    BdptVertex v;
    if (ls.environment) {
        v = bdptVertex(BDPT_LIGHT_INFINITE);
        v.wo = ls.wi;
    } else if (ls.delta) {
#ifdef PMCR_OTHER_LIGHTS
        PunctualLight p = punctualLightAt(ls.punctual);
        if (p.type == PUNCTUAL_DIRECTIONAL) {
            v = bdptVertex(BDPT_LIGHT_INFINITE);
            v.flags = BDPT_VERTEX_DIRECTIONAL;
            v.wo = ls.wi;
        } else {
            v = bdptVertex(BDPT_LIGHT_POINT);
            v.position = p.position;
            v.triangle = ls.punctual;
        }
#else
        v = bdptVertex(BDPT_LIGHT_POINT);
#endif
    } else {
        v = bdptVertex(BDPT_LIGHT_AREA);
        v.position = ls.area.point.position;
        v.normal = ls.area.point.normal;
        v.triangle = ls.area.point.triangle;
        v.barycentrics = ls.area.barycentrics;
    }
    v.pdfFwd = ls.delta ? ls.pdf : ls.environment ? ls.pdf : ls.area.pdfArea;
    return v;
}

// Adds a strategy's contribution to its image (--strategy-images): weighted and unweighted.
void addToStrategyImage(uint pixel, uint s, uint t, vec3 weighted, vec3 unweighted) {
    uint depth = s + t - 2u;
    if (depth > BDPT_STRATEGY_MAX_DEPTH || !isFinite(weighted) || !isFinite(unweighted)) return;
    uint base = (pixel * BDPT_STRATEGY_COUNT + depth * (depth + 3u) / 2u + s) * 6u;
    for (uint c = 0u; c < 3u; ++c) {
        if (weighted[c] != 0.0) atomicAdd(strategies[base + c], weighted[c]);
        if (unweighted[c] != 0.0) atomicAdd(strategies[base + 3u + c], unweighted[c]);
    }
}

// The camera sample whose strategies an invocation is evaluating, and where it is: strategy
// (s, t), with what stays the same along s for its camera vertex t - 1.
struct SampleState {
    uint pixel;
    uvec2 counts;    // camera and light vertices
    uint t;
    uint s;
    Sampler smp;
    Rng rng;         // the splats' rounding
    vec3 L;          // the t >= 2 strategies so far
    float cameraTail;  // bdptMisWeight's tails for (s, t)
    float lightTail;
    BdptVertex pt;     // camera vertex t - 1
    ShadingPoint shPt;
    bool ptConnectible;
    float uLight;      // its s = 1 light sample's numbers
    vec2 uLightPoint;
};

// Moves st to camera vertex st.t - 1 and strategy (0, t).
void beginCameraVertex(inout SampleState st) {
    uint t = st.t;
    if (t >= 4u) st.cameraTail = tailStep(st.cameraTail, cameraVertex(t - 3u), vertexDelta(cameraVertex(t - 4u)));
    st.pt = cameraVertex(t - 1u);
    st.ptConnectible = false;
    if (st.pt.type == BDPT_SURFACE) {
        st.shPt = vertexShading(st.pt);
        st.ptConnectible = bsdfHasNonDelta(st.shPt.bsdf);
    }
    st.smp.dimension = bdptConnectDimension(push.maxDepth) + 2u * (t - 1u);
    st.uLight = samplerGet1D(st.smp);
    st.uLightPoint = samplerGet2D(st.smp);
    st.s = 0u;
    st.lightTail = 0.0;
}

// Starts camera sample `index` of the dispatch at strategy (0, 1).
void beginSample(inout SampleState st, uint index) {
    st.pixel = push.pixelOffset + index;
    gCameraBase = index * push.cameraStride;
    gLightBase = index * push.lightStride;
    st.counts = vertexCounts[index];
    st.smp = samplerCreate(st.pixel, push.sampleIndex, push.seed);
    st.rng = rngCreate(hash3(push.seed ^ 0x5bd1e995u, st.pixel, push.sampleIndex));
    st.L = vec3(0.0);
    st.cameraTail = 0.0;
    st.t = 1u;
    beginCameraVertex(st);
}

// Moves st to its next strategy: s + 1, else the next camera vertex; false when none is left.
bool nextStrategy(inout SampleState st) {
    st.s += 1u;
    if (st.s > st.counts.y || st.s + st.t > push.maxDepth + 2u) {
        st.t += 1u;
        if (st.t > st.counts.x) return false;
        beginCameraVertex(st);
        return true;
    }
    if (st.s >= 3u) {
        BdptVertex v = lightVertex(st.s - 3u);
        bool deltaBefore = st.s >= 4u ? vertexDelta(lightVertex(st.s - 4u)) : vertexDeltaLight(v);
        st.lightTail = tailStep(st.lightTail, v, deltaBefore);
    }
    return true;
}

// Strategy (st.s, st.t): its contribution, MIS-weighted, added to st.L (t >= 2) or splatted at
// the pixel the light vertex is seen through (t = 1).
void evaluateStrategy(inout SampleState st, bool strategyImages, inout uint rays, inout uint dropped) {
    uint s = st.s;
    uint t = st.t;
    if (s + t < 2u || (s == 1u && t == 1u)) return;
    ShadingPoint none;
    vec3 c = vec3(0.0);
    float w = 0.0;
    uint target = st.pixel;
    if (s == 0u) {
        // The camera subpath found a light.
        if (st.pt.type == BDPT_LIGHT_INFINITE)
            c = st.pt.beta * envRadiance(st.pt.wo);
        else if (st.pt.type == BDPT_SURFACE)
            c = st.pt.beta * emittedRadiance(st.shPt.surface, st.pt.wo);
        if (maxComponent(c) > 0.0) w = bdptMisWeight(0u, t, st.pt, none, st.pt, st.shPt, st.cameraTail, st.lightTail);
    } else if (t == 1u) {
        // Light tracing: light vertex s - 1 seen by the pinhole, We cos / d^2
        // (pbrt-v4 PerspectiveCamera::SampleWi with a lens of area 1).
        BdptVertex qs = lightVertex(s - 1u);
        if (qs.type != BDPT_SURFACE) return;
        ShadingPoint shQs = vertexShading(qs);
        if (!bsdfHasNonDelta(shQs.bsdf)) return;
        vec3 toCamera = sceneInfo.cameraPosition - qs.position;
        float dist2 = dot(toCamera, toCamera);
        vec3 wCamera = toCamera * inversesqrt(dist2);
        vec2 raster;
        float cosCamera = cameraCosine(-wCamera);
        if (!(cosCamera > 0.0) || !cameraRasterPosition(-wCamera, raster)) return;
        target = min(uint(raster.y), sceneInfo.height - 1u) * sceneInfo.width +
                 min(uint(raster.x), sceneInfo.width - 1u);
        float absCos;
        vec3 f = shadingEvalImportance(shQs, wCamera, absCos);
        float We = 1.0 / (cameraImageArea() * sqr(sqr(cosCamera)));
        c = qs.beta * f * absCos * We * cosCamera / dist2;
        if (maxComponent(c) > 0.0) {
            rays += 1u;
            ShadowRay r = shadowSegment(spawnOrigin(shQs, wCamera), sceneInfo.cameraPosition);
            if (traceAny(r.origin, r.dir, r.tMax)) c = vec3(0.0);
        }
        if (maxComponent(c) > 0.0) w = bdptMisWeight(s, 1u, qs, shQs, cameraVertex(0u), none, st.cameraTail, st.lightTail);
    } else if (s == 1u) {
        // Next-event estimation from camera vertex t - 1.
        if (!st.ptConnectible) return;
        LightSampleFrom ls = sampleLightFrom(st.shPt, st.uLight, st.uLightPoint);
        if (!(maxComponent(ls.Le) > 0.0) || !(ls.pdf > 0.0)) return;
        float pdfBsdf, absCos;
        vec3 f = shadingEval(st.shPt, ls.wi, pdfBsdf, absCos);
        c = st.pt.beta * f * absCos * ls.Le / ls.pdf;
        if (maxComponent(c) > 0.0) {
            rays += 1u;
            if (traceAny(ls.ray.origin, ls.ray.dir, ls.ray.tMax)) c = vec3(0.0);
        }
        if (maxComponent(c) > 0.0)
            w = bdptMisWeight(1u, t, sampledLightVertex(ls), none, st.pt, st.shPt, st.cameraTail, st.lightTail);
    } else {
        // Light vertex s - 1 and camera vertex t - 1 joined by a shadow ray.
        if (!st.ptConnectible) return;
        BdptVertex qs = lightVertex(s - 1u);
        if (qs.type != BDPT_SURFACE) return;
        ShadingPoint shQs = vertexShading(qs);
        if (!bsdfHasNonDelta(shQs.bsdf)) return;
        vec3 d = qs.position - st.pt.position;
        float dist2 = dot(d, d);
        if (!(dist2 > 0.0)) return;
        vec3 w1 = d * inversesqrt(dist2);
        float pdfBsdf, cosPt, cosQs;
        vec3 fPt = shadingEval(st.shPt, w1, pdfBsdf, cosPt);
        vec3 fQs = shadingEvalImportance(shQs, -w1, cosQs);
        c = qs.beta * fQs * fPt * st.pt.beta * (cosPt * cosQs / dist2);
        if (maxComponent(c) > 0.0) {
            rays += 1u;
            ShadowRay r = shadowSegment(spawnOrigin(st.shPt, w1), spawnOrigin(shQs, -w1));
            if (traceAny(r.origin, r.dir, r.tMax)) c = vec3(0.0);
        }
        if (maxComponent(c) > 0.0) w = bdptMisWeight(s, t, qs, shQs, st.pt, st.shPt, st.cameraTail, st.lightTail);
    }
    if (!(maxComponent(c) > 0.0)) return;
    vec3 weighted = c * w;
    if (strategyImages) addToStrategyImage(target, s, t, weighted, c);
    if (t == 1u) {
        if (!splatDeposit(target, weighted, 1.0, st.rng)) dropped += 1u;
    } else {
        st.L += weighted;
    }
}

// Connections in turn: on a CPU device (itemsPerInvocation > 1) each invocation takes camera
// samples from a queue, one strategy per loop iteration, and starts its next sample as soon as
// one is done, so that the SIMD lanes lavapipe runs together (whose subpaths differ in length)
// stay busy, as pt's paths in turn (camera_sample_kernel.glsl). It stops taking samples once
// its traversal steps and iterations pass BDPT_LOOP_STEPS_BEFORE_STOP, far below lavapipe's
// budget of 65535 loop iterations per invocation (tests/gpu/test_loop_limits.cpp); the
// dispatch has an invocation per sample, so every sample is taken. A pixel still has one sample
// per dispatch, added to the film by whichever invocation took it, so the image does not depend
// on who did: the same seed gives the same image. On a GPU each invocation takes its own sample.
const uint BDPT_LOOP_STEPS_BEFORE_STOP = 16384u;

void main() {
    uint rays = 0u;
    uint dropped = 0u;
    uint paths = 0u;
    bool fromQueue = push.itemsPerInvocation > 1u;
    uint index = fromQueue ? atomicAdd(queue[push.queueSlot], 1u) : gl_GlobalInvocationID.x;
    if (index < push.count) {
        bool strategyImages = (push.flags & BDPT_FLAG_STRATEGY_IMAGES) != 0u;
        SampleState st;
        beginSample(st, index);
        uint steps = max(push.itemsPerInvocation, 1u) * push.cameraStride * (push.lightStride + 1u);
        for (uint b = 0u; b < steps; ++b) {
            evaluateStrategy(st, strategyImages, rays, dropped);
            if (nextStrategy(st)) continue;
            PixelAccumulator acc = accumulatorCreate();
            accumulatorAdd(acc, st.L);
            filmAccumulate(st.pixel, acc.sum, acc.lumSum, acc.lumSqSum, acc.count);
            dropped += acc.dropped;
            paths += 1u;
            if (!fromQueue || paths >= push.itemsPerInvocation ||
                bvhStepsTaken + b > BDPT_LOOP_STEPS_BEFORE_STOP)
                break;
            index = atomicAdd(queue[push.queueSlot], 1u);
            if (index >= push.count) break;
            beginSample(st, index);
        }
    }
    counterAdd(COUNTER_RAYS, rays);
    counterAdd(COUNTER_NAN_DROPPED, dropped);
    counterAdd(COUNTER_PATHS, paths);
}
