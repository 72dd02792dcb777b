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

#define FILM_BINDING BDPT_BINDING_FILM
#define COUNTERS_BINDING BDPT_BINDING_COUNTERS
#include "common/film.glsl"
#include "methods/bdpt/bdpt_vertex.glsl"
#include "methods/energy_redistribution/splat.glsl"
#include "methods/pt/path_tracer.glsl"

layout(set = WORK_SET, binding = BDPT_BINDING_STRATEGIES, scalar) buffer StrategyBuffer {
    float strategies[];
};

uint gCameraBase;
uint gLightBase;
BdptVertex cameraVertex(uint i) { return cameraVertices[gCameraBase + i]; }
BdptVertex lightVertex(uint i) { return lightVertices[gLightBase + i]; }

float remap0(float f) { return f != 0.0 ? f : 1.0; }
// A ratio of densities p_i / p_s as it enters the weight: squared for the power heuristic
// (w_s = p_s^2 / sum_i p_i^2), as is for the balance heuristic (--mis balance).
float misTerm(float r) { return balanceHeuristicMis() ? r : r * r; }

// The MIS weight of strategy (s, t) for the path it made (Veach 1997 sec. 10.2.1; pbrt-v4
// BDPTIntegrator MISWeight): w = 1 / (1 + sum over the other strategies i of (p_i / p_s)^k),
// the ratios built vertex by vertex from the forward and reverse densities recorded along both
// subpaths, with the densities at the four vertices around the connection evaluated for this
// path, and no strategy that would have to connect at a delta vertex or hit a delta light.
// qs (with shQs) is the light end (the sampled light for s = 1), pt (shPt) the camera end.
float bdptMisWeight(uint s, uint t, BdptVertex qs, ShadingPoint shQs, BdptVertex pt, ShadingPoint shPt) {
    if (s + t == 2u) return 1.0;
    bool hasQsMinus = s > 1u;
    bool hasPtMinus = t > 1u;
    BdptVertex qsMinus = hasQsMinus ? lightVertex(s - 2u) : bdptVertex(BDPT_CAMERA);
    BdptVertex ptMinus = hasPtMinus ? cameraVertex(t - 2u) : bdptVertex(BDPT_CAMERA);
    float ptRev = s > 0u ? vertexPdf(qs, shQs, hasQsMinus, qsMinus, pt) : vertexPdfLightOrigin(pt);
    float ptMinusRev = 0.0;
    if (hasPtMinus)
        ptMinusRev = s > 0u ? vertexPdf(pt, shPt, true, qs, ptMinus) : vertexPdfLight(pt, ptMinus);
    float qsRev = s > 0u ? vertexPdf(pt, shPt, hasPtMinus, ptMinus, qs) : 0.0;
    float qsMinusRev = hasQsMinus ? vertexPdf(qs, shQs, true, pt, qsMinus) : 0.0;

    float sum = 0.0;
    // Strategies with fewer camera vertices: camera vertex i sampled by the light subpath.
    float ri = 1.0;
    for (uint i = t - 1u; i > 0u; --i) {
        BdptVertex v = i == t - 1u ? pt : cameraVertex(i);
        float rev = i == t - 1u ? ptRev : i + 2u == t ? ptMinusRev : v.pdfRev;
        ri *= remap0(rev) / remap0(v.pdfFwd);
        bool delta = i != t - 1u && vertexDelta(v);
        if (!delta && !vertexDelta(cameraVertex(i - 1u))) sum += misTerm(ri);
    }
    // Strategies with fewer light vertices: light vertex i sampled by the camera subpath.
    ri = 1.0;
    for (uint k = 0u; k < s; ++k) {
        uint i = s - 1u - k;
        BdptVertex v = i == s - 1u ? qs : lightVertex(i);
        float rev = i == s - 1u ? qsRev : i + 2u == s ? qsMinusRev : v.pdfRev;
        ri *= remap0(rev) / remap0(v.pdfFwd);
        bool delta = i != s - 1u && vertexDelta(v);
        bool deltaBefore = i > 0u ? vertexDelta(lightVertex(i - 1u)) : vertexDeltaLight(v);
        if (!delta && !deltaBefore) sum += misTerm(ri);
    }
    return 1.0 / (1.0 + sum);
}

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

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint rays = 0u;
    uint dropped = 0u;
    uint paths = 0u;
    if (i < push.count) {
        uint pixel = push.pixelOffset + i;
        gCameraBase = i * push.cameraStride;
        gLightBase = i * push.lightStride;
        uvec2 counts = vertexCounts[i];
        Sampler smp = samplerCreate(pixel, push.sampleIndex, push.seed);
        Rng rng = rngCreate(hash3(push.seed ^ 0x5bd1e995u, pixel, push.sampleIndex));
        bool strategyImages = (push.flags & BDPT_FLAG_STRATEGY_IMAGES) != 0u;
        ShadingPoint none;
        vec3 L = vec3(0.0);
        for (uint t = 1u; t <= counts.x; ++t) {
            BdptVertex pt = cameraVertex(t - 1u);
            ShadingPoint shPt;
            bool ptConnectible = false;
            if (pt.type == BDPT_SURFACE) {
                shPt = vertexShading(pt);
                ptConnectible = bsdfHasNonDelta(shPt.bsdf);
            }
            smp.dimension = bdptConnectDimension(push.maxDepth) + 2u * (t - 1u);
            float uLight = samplerGet1D(smp);
            vec2 uLightPoint = samplerGet2D(smp);
            for (uint s = 0u; s <= counts.y; ++s) {
                if (s + t < 2u || s + t - 2u > push.maxDepth || (s == 1u && t == 1u)) continue;
                vec3 c = vec3(0.0);
                float w = 0.0;
                uint target = pixel;
                if (s == 0u) {
                    // The camera subpath found a light.
                    if (pt.type == BDPT_LIGHT_INFINITE)
                        c = pt.beta * envRadiance(pt.wo);
                    else if (pt.type == BDPT_SURFACE)
                        c = pt.beta * emittedRadiance(shPt.surface, pt.wo);
                    if (maxComponent(c) > 0.0) w = bdptMisWeight(0u, t, pt, none, pt, shPt);
                } else if (t == 1u) {
                    // Light tracing: light vertex s - 1 seen by the pinhole, We cos / d^2
                    // (pbrt-v4 PerspectiveCamera::SampleWi with a lens of area 1).
                    BdptVertex qs = lightVertex(s - 1u);
                    if (qs.type != BDPT_SURFACE) continue;
                    ShadingPoint shQs = vertexShading(qs);
                    if (!bsdfHasNonDelta(shQs.bsdf)) continue;
                    vec3 toCamera = sceneInfo.cameraPosition - qs.position;
                    float dist2 = dot(toCamera, toCamera);
                    vec3 wCamera = toCamera * inversesqrt(dist2);
                    vec2 raster;
                    float cosCamera = cameraCosine(-wCamera);
                    if (!(cosCamera > 0.0) || !cameraRasterPosition(-wCamera, raster)) continue;
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
                    if (maxComponent(c) > 0.0) w = bdptMisWeight(s, 1u, qs, shQs, cameraVertex(0u), none);
                } else if (s == 1u) {
                    // Next-event estimation from camera vertex t - 1.
                    if (!ptConnectible) continue;
                    LightSampleFrom ls = sampleLightFrom(shPt, uLight, uLightPoint);
                    if (!(maxComponent(ls.Le) > 0.0) || !(ls.pdf > 0.0)) continue;
                    float pdfBsdf, absCos;
                    vec3 f = shadingEval(shPt, ls.wi, pdfBsdf, absCos);
                    c = pt.beta * f * absCos * ls.Le / ls.pdf;
                    if (maxComponent(c) > 0.0) {
                        rays += 1u;
                        if (traceAny(ls.ray.origin, ls.ray.dir, ls.ray.tMax)) c = vec3(0.0);
                    }
                    if (maxComponent(c) > 0.0)
                        w = bdptMisWeight(1u, t, sampledLightVertex(ls), none, pt, shPt);
                } else {
                    // Light vertex s - 1 and camera vertex t - 1 joined by a shadow ray.
                    if (!ptConnectible) continue;
                    BdptVertex qs = lightVertex(s - 1u);
                    if (qs.type != BDPT_SURFACE) continue;
                    ShadingPoint shQs = vertexShading(qs);
                    if (!bsdfHasNonDelta(shQs.bsdf)) continue;
                    vec3 d = qs.position - pt.position;
                    float dist2 = dot(d, d);
                    if (!(dist2 > 0.0)) continue;
                    vec3 w1 = d * inversesqrt(dist2);
                    float pdfBsdf, cosPt, cosQs;
                    vec3 fPt = shadingEval(shPt, w1, pdfBsdf, cosPt);
                    vec3 fQs = shadingEvalImportance(shQs, -w1, cosQs);
                    c = qs.beta * fQs * fPt * pt.beta * (cosPt * cosQs / dist2);
                    if (maxComponent(c) > 0.0) {
                        rays += 1u;
                        ShadowRay r = shadowSegment(spawnOrigin(shPt, w1), spawnOrigin(shQs, -w1));
                        if (traceAny(r.origin, r.dir, r.tMax)) c = vec3(0.0);
                    }
                    if (maxComponent(c) > 0.0) w = bdptMisWeight(s, t, qs, shQs, pt, shPt);
                }
                if (!(maxComponent(c) > 0.0)) continue;
                vec3 weighted = c * w;
                if (strategyImages) addToStrategyImage(target, s, t, weighted, c);
                if (t == 1u) {
                    if (!splatDeposit(target, weighted, 1.0, rng)) dropped += 1u;
                } else {
                    L += weighted;
                }
            }
        }
        PixelAccumulator acc = accumulatorCreate();
        accumulatorAdd(acc, L);
        filmAccumulate(pixel, acc.sum, acc.lumSum, acc.lumSqSum, acc.count);
        dropped += acc.dropped;
        paths = 1u;
    }
    counterAdd(COUNTER_RAYS, rays);
    counterAdd(COUNTER_NAN_DROPPED, dropped);
    counterAdd(COUNTER_PATHS, paths);
}
