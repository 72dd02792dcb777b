// Unidirectional path tracing with next-event estimation (emitters, punctual lights, the
// environment), combined with BSDF
// sampling by multiple importance sampling (Veach 1997 ch. 9, power heuristic; the balance
// heuristic with KERNEL_OPTION_BALANCE_HEURISTIC, --mis balance), and Russian roulette after
// rrDepth bounces (pbrt-v4 PathIntegrator). The baseline every method is
// compared with, and the sampler that seeds ERPT and PMC-ER.
//
// Depth semantics (pbrt-v4): maxDepth is the number of bounces; maxDepth = 1 is direct lighting.
// With PT_RECORD_PATHS defined, every eye vertex and its light connection is written to a
// PathRecord (shared/path_types.h) for the perturbation kernels.
//
// Every random number is drawn through samplerGet1D / samplerGet2D, in an order fixed by the
// path: the raster position (2D, the caller's), then per bounce uLight, uLightPoint, uLobe, uDir
// and uRoulette (a bounce draws all of them unless its path ends there). A kernel that defines
// PMCR_CUSTOM_SAMPLER supplies its own Sampler and samplerGet1D/2D before including this file
// (PSSMLT: methods/pssmlt/pss_sampler.glsl); otherwise common/sampler.glsl's are used.
#ifndef PMCR_PATH_TRACER_GLSL
#define PMCR_PATH_TRACER_GLSL

#include "common/camera.glsl"
#include "common/environment.glsl"
#include "common/kernel_options.glsl"
#include "common/lights.glsl"
#include "common/octahedral.glsl"
#include "common/punctual_sampling.glsl"
#ifndef PMCR_CUSTOM_SAMPLER
#include "common/sampler.glsl"
#endif
#include "common/shading.glsl"

#ifdef PT_RECORD_PATHS
layout(set = WORK_SET, binding = PT_BINDING_PATH_RECORDS, scalar) writeonly buffer RecordBuffer {
    PathRecord pathRecords[];
};
layout(set = WORK_SET, binding = PT_BINDING_PATH_VERTICES, scalar) writeonly buffer VertexRecordBuffer {
    PathVertex pathVertices[];
};
#endif

// The MIS weight of a sample of strategy A against strategy B (Veach 1997 ch. 9): the power
// heuristic, or the balance heuristic in kernels specialized for it (--mis balance, a paper
// baseline; common/kernel_options.glsl). With nA and nB: for nA samples of A and nB of B.
float misWeight(float pdfA, float pdfB) {
    return balanceHeuristicMis() ? balanceHeuristic(pdfA, pdfB) : powerHeuristic(pdfA, pdfB);
}
float misWeight(float nA, float pdfA, float nB, float pdfB) {
    return balanceHeuristicMis() ? balanceHeuristic(nA, pdfA, nB, pdfB)
                                 : powerHeuristic(nA, pdfA, nB, pdfB);
}

// A path under construction: what pathBounce carries from one bounce to the next. The path
// tracer is pathBegin, then pathBounce until it returns false, then pathEnd; pt.comp and
// pt_record.comp run several paths in turn in one invocation that way (a new one starts as soon
// as the last ends, camera_sample_kernel.glsl), so that SIMD lanes whose path ended early do not
// idle until their neighbours' paths end.
struct PathState {
    vec3 L;               // radiance gathered so far
    vec3 beta;            // path throughput
    vec3 origin;          // the next ray
    vec3 dir;
    vec3 prevPosition;    // the previous vertex (MIS weight of emission hit by BSDF sampling)
    float prevPdf;        // the solid-angle pdf of the BSDF sample that reached the next vertex
    float etaScale;       // product of eta^2 over transmissions (pbrt-v4), for roulette
    bool prevDelta;       // the next vertex was reached by a delta lobe (or is seen by the camera)
    uint depth;           // bounces so far
#ifdef PT_RECORD_PATHS
    uint firstVertex;
    uint vertexCount;
#endif
};

// The path whose first ray leaves the camera through raster position `raster`.
PathState pathBegin(vec2 raster, uint recordIndex) {
    PathState p;
    p.L = vec3(0.0);
    p.beta = vec3(1.0);
    p.etaScale = 1.0;
    p.prevDelta = true;   // the camera "samples" x1 with a delta, so x1's emission counts fully
    p.prevPdf = 0.0;
    p.prevPosition = sceneInfo.cameraPosition;
    p.origin = sceneInfo.cameraPosition;
    p.dir = cameraDirection(raster);
    p.depth = 0u;
#ifdef PT_RECORD_PATHS
    p.firstVertex = recordIndex * PATH_MAX_VERTICES;
    p.vertexCount = 0u;
#endif
    return p;
}

#ifdef PT_RECORD_PATHS
// A record vertex with every field cleared (no lobe), for pathShade to fill.
PathVertex clearedPathVertex() {
    return PathVertex(vec3(0.0), 0u, vec3(0.0), 0u, vec3(0.0), 0u, vec2(0.0), 0.0, LOBE_NONE,
                      vec3(0.0), 0u, vec3(0.0), 0.0, vec3(0.0), 0.0);
}
#endif

// A light sample seen from shading point sh: an emitter point or an environment direction.
struct LightSampleFrom {
    vec3 wi;            // towards the light
    vec3 Le;            // radiance arriving along wi (before visibility)
    float pdf;          // solid-angle density, light selection included; 0: no sample
    ShadowRay ray;      // the segment that must be clear
    LightSample area;   // the emitter point (when from an emitter)
    bool delta;         // a punctual light: pdf is its selection probability, no MIS
    bool environment;   // the environment (wi is the direction)
    uint punctual;      // the punctual light's index (when delta)
};

// Next-event estimation's light sample, the light picked by uLight (with the probabilities
// host/render/gpu_scene.cpp sets, lights.glsl): the environment (a direction by envSample), a punctual light (its one
// direction), or an emitter triangle and a uniform point on it.
LightSampleFrom sampleLightFrom(ShadingPoint sh, float uLight, vec2 uLightPoint) {
    LightSampleFrom ls;
    ls.delta = false;
    ls.environment = false;
    ls.punctual = 0u;
    if (hasEnvironment() && uLight < sceneInfo.envSelectPmf) {
        EnvSample e = envSample(min(uLight / sceneInfo.envSelectPmf, ONE_MINUS_EPSILON), uLightPoint);
        ls.wi = e.wi;
        ls.Le = e.Le;
        ls.pdf = e.pdf * sceneInfo.envSelectPmf;
        ls.ray = ShadowRay(spawnOrigin(sh, e.wi), e.wi, FLOAT_MAX);
        ls.environment = true;
        return ls;
    }
    float uPunctual = uLight - sceneInfo.envSelectPmf;
    // (Without emitters, rounding may leave a sliver of u above both intervals: it goes here.)
    if (hasPunctualLights() &&
        (uPunctual < sceneInfo.punctualSelectPmf || !(sceneInfo.totalEmitterPower > 0.0))) {
        // A delta light: the estimator divides by its selection probability alone, and BSDF
        // sampling never reaches it, so it takes no MIS weight (punctual_sampling.glsl).
        PunctualSample ps = samplePunctualLight(
            sh.surface.position, min(uPunctual / sceneInfo.punctualSelectPmf, ONE_MINUS_EPSILON));
        ls.delta = true;
        ls.punctual = ps.index;
        ls.pdf = ps.pmf * sceneInfo.punctualSelectPmf;
        ls.wi = ps.wi;
        ls.Le = ps.Li;
        ls.ray = punctualShadowRay(ps, spawnOrigin(sh, ps.wi));
        return ls;
    }
    vec3 position = sh.surface.position;
    ls.area = sampleLight(uLight, uLightPoint);
    vec3 toLight = ls.area.point.position - position;
    float dist2 = dot(toLight, toLight);
    ls.wi = toLight * inversesqrt(dist2);
    ls.Le = emittedRadiance(ls.area.point, -ls.wi);
    ls.pdf = areaToSolidAngle(ls.area.pdfArea, position, ls.area.point.position,
                              ls.area.point.normal);
    ls.ray = shadowRay(sh, ls.area.point);
    return ls;
}

// Radiance of the environment seen along a ray that escaped the scene, MIS-weighted against
// light sampling (the environment's share of it) unless the ray's direction came from a delta
// (or from the camera): the escaped-ray term of pbrt-v4's PathIntegrator.
vec3 escapedRadiance(vec3 dir, bool prevDelta, float prevPdf) {
    if (!hasEnvironment()) return vec3(0.0);
    vec3 Le = envRadiance(dir);
    if (prevDelta) return Le;
    return Le * misWeight(prevPdf, envPdf(dir) * sceneInfo.envSelectPmf);
}

// The light sample of one bounce (next-event estimation): what it adds to the path's radiance
// when its shadow ray reaches the light unoccluded.
struct LightConnection {
    ShadowRay ray;
    vec3 contribution;  // beta f |cos| Le w / pdf, MIS-weighted against BSDF sampling
    bool valid;         // false: no light sample (delta BSDF, last bounce, zero contribution)
};

// The part of a bounce after its ray's closest hit (hit.triangle == BVH_NO_HIT: the ray
// escaped, the path ends): adds the emission found there, draws one light sample (its shadow
// ray is the caller's to trace, `light`), then samples the BSDF for the next ray (p.origin,
// p.dir) and applies Russian roulette. Returns false when the path has ended (escaped,
// absorbed, maxDepth reached or stopped by Russian roulette); its light sample may still count.
// With PT_RECORD_PATHS, `pv` is the vertex record but for the light sample's visibility.
bool pathShade(inout PathState p, Hit hit, inout Sampler smp, uint maxDepth, uint rrDepth,
               out LightConnection light
#ifdef PT_RECORD_PATHS
               , out PathVertex pv
#endif
               ) {
    light.valid = false;
    if (hit.triangle == BVH_NO_HIT) {
        vec3 contribution = p.beta * escapedRadiance(p.dir, p.prevDelta, p.prevPdf);
        p.L += contribution;
#ifdef PT_RECORD_PATHS
        // The environment as one more vertex of the record (shared/path_types.h), when it adds.
        pv = clearedPathVertex();
        pv.flags = maxComponent(contribution) > 0.0 ? VERTEX_ENVIRONMENT | VERTEX_EMITTER : 0u;
        pv.barycentrics = octEncode(p.dir);
        pv.implicitContribution = contribution;
#endif
        return false;
    }
    SurfacePoint s = surfaceAt(hit.triangle, vec2(hit.b1, hit.b2));
    p.beta *= segmentTransmittance(s, p.dir, hit.t);  // p.dir is unit: t is the distance
    vec3 wo = -p.dir;
    ShadingPoint sh = makeShadingPoint(s, wo);
#ifdef PT_RECORD_PATHS
    pv = clearedPathVertex();
    pv.position = s.position;
    pv.triangle = s.triangle;
    pv.normal = s.normal;
    pv.flags = sh.front ? 0u : VERTEX_BACKFACE;
    pv.shadingNormal = s.shadingNormal;
    pv.material = s.material;
    pv.barycentrics = vec2(hit.b1, hit.b2);
#endif
    // Emission at the hit, MIS-weighted against light sampling unless reached by a delta.
    vec3 Le = emittedRadiance(s, wo);
    if (maxComponent(Le) > 0.0) {
        float w = 1.0;
        if (!p.prevDelta) {
            float pdfLight = areaToSolidAngle(emitterAreaPdf(s.triangle), p.prevPosition,
                                              s.position, s.normal);
            w = misWeight(p.prevPdf, pdfLight);
        }
        vec3 contribution = p.beta * Le * w;
        p.L += contribution;
#ifdef PT_RECORD_PATHS
        pv.flags |= VERTEX_EMITTER;
        pv.implicitContribution = contribution;
#endif
    }
    bool stop = p.depth == maxDepth;
    // Next-event estimation: one light sample, MIS-weighted against BSDF sampling.
    float uLight = samplerGet1D(smp);
    vec2 uLightPoint = samplerGet2D(smp);
    if (!stop && bsdfHasNonDelta(sh.bsdf)) {
        LightSampleFrom ls = sampleLightFrom(sh, uLight, uLightPoint);
        if (maxComponent(ls.Le) > 0.0 && ls.pdf > 0.0) {
            float pdfBsdf, absCos;
            vec3 f = shadingEval(sh, ls.wi, pdfBsdf, absCos);
            if (maxComponent(f) > 0.0) {
                light.ray = ls.ray;
                float w = ls.delta ? 1.0 : misWeight(ls.pdf, pdfBsdf);
                light.contribution = p.beta * f * absCos * ls.Le * w / ls.pdf;
                light.valid = true;
#ifdef PT_RECORD_PATHS
                if (ls.environment) {
                    // A direction, not a point (shared/path_types.h).
                    vec2 e = octEncode(ls.wi);
                    pv.flags |= VERTEX_SAMPLED_ENVIRONMENT;
                    pv.lightB1 = e.x;
                    pv.lightB2 = e.y;
                } else if (ls.delta) {
                    pv.flags |= VERTEX_SAMPLED_PUNCTUAL;
                    pv.lightTriangle = ls.punctual;
                } else {
                    pv.lightPosition = ls.area.point.position;
                    pv.lightTriangle = ls.area.point.triangle;
                    pv.lightB1 = ls.area.barycentrics.x;
                    pv.lightB2 = ls.area.barycentrics.y;
                }
#endif
            }
        }
    }
    // Continue the path by sampling the BSDF.
    float uLobe = samplerGet1D(smp);
    vec2 uDir = samplerGet2D(smp);
    BsdfSample bs;
    vec3 wi;
    bool scattered = !stop && shadingSample(sh, uLobe, uDir, bs, wi);
#ifdef PT_RECORD_PATHS
    if (scattered) {
        pv.lobe = bs.lobe;
        pv.pdfForward = bs.delta ? 0.0 : bs.pdf;
        if (bs.delta) pv.flags |= VERTEX_SPECULAR;
        if (bs.wi.z < 0.0) pv.flags |= VERTEX_TRANSMISSION;
    }
#endif
    if (!scattered) return false;
    p.beta *= bs.f * abs(bs.wi.z) / bs.pdf;
    p.etaScale *= sqr(bs.eta);
    p.prevDelta = bs.delta;
    p.prevPdf = bs.pdf;
    p.prevPosition = s.position;
    p.origin = spawnOrigin(sh, wi);
    p.dir = wi;
    // Russian roulette on the throughput without the eta^2 factors (pbrt-v4).
    float uRoulette = samplerGet1D(smp);
    if (p.depth + 1u >= rrDepth) {
        float rrBeta = maxComponent(p.beta * p.etaScale);
        if (rrBeta < 1.0) {
            float q = max(0.0, 1.0 - rrBeta);
            if (uRoulette < q) return false;
            p.beta /= 1.0 - q;
        }
    }
    if (maxComponent(p.beta) <= 0.0) return false;
    p.depth += 1u;
    return true;
}

// One bounce: traces the path's next ray, shades its hit (pathShade) and traces the light
// sample's shadow ray. Returns false when the path has ended; p.L is then final. A path takes
// at most maxDepth + 1 bounces.
bool pathBounce(inout PathState p, inout Sampler smp, uint maxDepth, uint rrDepth,
                inout uint rays) {
    Hit hit;
    rays += 1u;
    traceClosest(p.origin, p.dir, FLOAT_MAX, hit);
    LightConnection light;
#ifdef PT_RECORD_PATHS
    PathVertex pv;
    bool hitSurface = hit.triangle != BVH_NO_HIT;
    bool more = pathShade(p, hit, smp, maxDepth, rrDepth, light, pv);
#else
    bool more = pathShade(p, hit, smp, maxDepth, rrDepth, light);
#endif
    if (light.valid) {
        rays += 1u;
        if (!traceAny(light.ray.origin, light.ray.dir, light.ray.tMax)) {
            p.L += light.contribution;
#ifdef PT_RECORD_PATHS
            pv.flags |= VERTEX_HAS_LIGHT_SAMPLE;
            pv.explicitContribution = light.contribution;
#endif
        }
    }
#ifdef PT_RECORD_PATHS
    if ((pv.flags & VERTEX_HAS_LIGHT_SAMPLE) == 0u) {  // a record keeps visible light samples only
        pv.flags &= ~(VERTEX_SAMPLED_PUNCTUAL | VERTEX_SAMPLED_ENVIRONMENT);
        pv.lightPosition = vec3(0.0);
        pv.lightTriangle = 0u;
        pv.lightB1 = 0.0;
        pv.lightB2 = 0.0;
    }
#endif
#ifdef PT_RECORD_PATHS
    if (hitSurface || (pv.flags & VERTEX_ENVIRONMENT) != 0u) {
        pathVertices[p.firstVertex + p.vertexCount] = pv;
        p.vertexCount += 1u;
    }
#endif
    return more;
}

// The most bounces a path may take: maxDepth, or fewer when every vertex is recorded.
uint pathMaxDepth(uint maxDepth) {
#ifdef PT_RECORD_PATHS
    return min(maxDepth, PATH_MAX_VERTICES - 1u);
#else
    return maxDepth;
#endif
}

// Ends path p that left the camera through `raster`: with PT_RECORD_PATHS, writes its record.
void pathEnd(PathState p, vec2 raster, uint recordIndex) {
#ifdef PT_RECORD_PATHS
    PathRecord record;
    record.raster = raster;
    record.pixel = uint(raster.y) * sceneInfo.width + uint(raster.x);
    record.vertexCount = p.vertexCount;
    record.radiance = p.L;
    record.firstVertex = p.firstVertex;
    pathRecords[recordIndex] = record;
#endif
}

// Adds to L the light reflected at sh from the lights, by MIS of light and BSDF sampling
// (Veach 1997 sec. 9.2.4): `lightSamples` light and as many BSDF samples, each weighted by the
// power (or balance, misWeight) heuristic with sample counts; a BSDF sample counts the emitter it hits, or the
// environment when it escapes. Direct lighting's estimate at x1 (directLighting), and photon
// mapping's at its gather points (methods/pm/pm_gather_kernel.glsl).
void addDirectLighting(ShadingPoint sh, inout Sampler smp, uint lightSamples, inout uint rays,
                       inout vec3 L) {
    float n = float(lightSamples);
    for (uint i = 0u; i < lightSamples; ++i) {
        // Light sample.
        float uLight = samplerGet1D(smp);
        vec2 uLightPoint = samplerGet2D(smp);
        if (bsdfHasNonDelta(sh.bsdf)) {
            LightSampleFrom ls = sampleLightFrom(sh, uLight, uLightPoint);
            if (maxComponent(ls.Le) > 0.0 && ls.pdf > 0.0) {
                float pdfBsdf, absCos;
                vec3 f = shadingEval(sh, ls.wi, pdfBsdf, absCos);
                if (maxComponent(f) > 0.0) {
                    rays += 1u;
                    float w = ls.delta ? 1.0 : misWeight(n, ls.pdf, n, pdfBsdf);
                    if (!traceAny(ls.ray.origin, ls.ray.dir, ls.ray.tMax))
                        L += f * absCos * ls.Le * w / (n * ls.pdf);
                }
            }
        }
        // BSDF sample: an emitter it hits, or the environment when it escapes.
        float uLobe = samplerGet1D(smp);
        vec2 uDir = samplerGet2D(smp);
        BsdfSample bs;
        vec3 wi;
        if (!shadingSample(sh, uLobe, uDir, bs, wi)) continue;
        Hit lightHit;
        rays += 1u;
        vec3 Lemit;
        float pdfLight;
        if (traceClosest(spawnOrigin(sh, wi), wi, FLOAT_MAX, lightHit)) {
            SurfacePoint l = surfaceAt(lightHit.triangle, vec2(lightHit.b1, lightHit.b2));
            Lemit = emittedRadiance(l, -wi) * segmentTransmittance(l, wi, lightHit.t);
            pdfLight = areaToSolidAngle(emitterAreaPdf(l.triangle), sh.surface.position,
                                        l.position, l.normal);
        } else {
            if (!hasEnvironment()) continue;
            Lemit = envRadiance(wi);
            pdfLight = envPdf(wi) * sceneInfo.envSelectPmf;
        }
        if (maxComponent(Lemit) <= 0.0) continue;
        float w = bs.delta ? 1.0 : misWeight(n, bs.pdf, n, pdfLight);
        L += bs.f * abs(bs.wi.z) * Lemit * w / (n * bs.pdf);
    }
}

// Direct lighting only: emission seen at x1 plus light reflected at x1 towards the camera
// (addDirectLighting). Its expected value equals a path traced with maxDepth = 1. The PMC-HI
// baseline.
vec3 directLighting(vec2 raster, inout Sampler smp, uint lightSamples, inout uint rays) {
    vec3 origin = sceneInfo.cameraPosition;
    vec3 dir = cameraDirection(raster);
    Hit hit;
    rays += 1u;
    if (!traceClosest(origin, dir, FLOAT_MAX, hit)) return escapedRadiance(dir, true, 0.0);
    SurfacePoint s = surfaceAt(hit.triangle, vec2(hit.b1, hit.b2));
    vec3 wo = -dir;
    ShadingPoint sh = makeShadingPoint(s, wo);
    vec3 L = emittedRadiance(s, wo);
    addDirectLighting(sh, smp, lightSamples, rays, L);
    return L * segmentTransmittance(s, dir, hit.t);
}

#endif
