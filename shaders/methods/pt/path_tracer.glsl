// Unidirectional path tracing with next-event estimation on area lights, combined with BSDF
// sampling by multiple importance sampling (Veach 1997 ch. 9, power heuristic), and Russian
// roulette after rrDepth bounces (pbrt-v4 PathIntegrator). The baseline every method is
// compared with, and the sampler that seeds ERPT and PMC-ER.
//
// Depth semantics (pbrt-v4): maxDepth is the number of bounces; maxDepth = 1 is direct lighting.
// With PT_RECORD_PATHS defined, every eye vertex and its light connection is written to a
// PathRecord (shared/path_types.h) for the perturbation kernels.
#ifndef PMCR_PATH_TRACER_GLSL
#define PMCR_PATH_TRACER_GLSL

#include "common/camera.glsl"
#include "common/lights.glsl"
#include "common/sampler.glsl"
#include "common/shading.glsl"

#ifdef PT_RECORD_PATHS
layout(set = WORK_SET, binding = PT_BINDING_PATH_RECORDS, scalar) writeonly buffer RecordBuffer {
    PathRecord pathRecords[];
};
layout(set = WORK_SET, binding = PT_BINDING_PATH_VERTICES, scalar) writeonly buffer VertexRecordBuffer {
    PathVertex pathVertices[];
};
#endif

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

// One bounce: traces the path's next ray, adds the emission found there and one light sample
// (next-event estimation), then samples the BSDF for the next ray. Returns false when the path
// has ended (escaped, absorbed, maxDepth reached or stopped by Russian roulette); p.L is then
// final. A path takes at most maxDepth + 1 bounces.
bool pathBounce(inout PathState p, inout Sampler smp, uint maxDepth, uint rrDepth,
                inout uint rays) {
    Hit hit;
    rays += 1u;
    if (!traceClosest(p.origin, p.dir, FLOAT_MAX, hit)) return false;
    SurfacePoint s = surfaceAt(hit.triangle, vec2(hit.b1, hit.b2));
    vec3 wo = -p.dir;
    ShadingPoint sh = makeShadingPoint(s, wo);
#ifdef PT_RECORD_PATHS
    PathVertex pv;
    pv.position = s.position;
    pv.triangle = s.triangle;
    pv.normal = s.normal;
    pv.flags = sh.front ? 0u : VERTEX_BACKFACE;
    pv.shadingNormal = s.shadingNormal;
    pv.material = s.material;
    pv.barycentrics = vec2(hit.b1, hit.b2);
    pv.pdfForward = 0.0;
    pv.lobe = LOBE_NONE;
    pv.lightPosition = vec3(0.0);
    pv.lightTriangle = 0u;
    pv.explicitContribution = vec3(0.0);
    pv.lightB1 = 0.0;
    pv.implicitContribution = vec3(0.0);
    pv.lightB2 = 0.0;
#endif

    // Emission at the hit, MIS-weighted against light sampling unless reached by a delta.
    vec3 Le = emittedRadiance(s, wo);
    if (maxComponent(Le) > 0.0) {
        float w = 1.0;
        if (!p.prevDelta) {
            float pdfLight = areaToSolidAngle(emitterAreaPdf(s.triangle), p.prevPosition,
                                              s.position, s.normal);
            w = powerHeuristic(p.prevPdf, pdfLight);
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
        LightSample ls = sampleLight(uLight, uLightPoint);
        vec3 toLight = ls.point.position - s.position;
        float dist2 = dot(toLight, toLight);
        vec3 wi = toLight * inversesqrt(dist2);
        vec3 Lemit = emittedRadiance(ls.point, -wi);
        float pdfLight = areaToSolidAngle(ls.pdfArea, s.position, ls.point.position, ls.point.normal);
        if (maxComponent(Lemit) > 0.0 && pdfLight > 0.0) {
            float pdfBsdf, absCos;
            vec3 f = shadingEval(sh, wi, pdfBsdf, absCos);
            if (maxComponent(f) > 0.0 && visible(sh, ls.point, rays)) {
                vec3 contribution = p.beta * f * absCos * Lemit * powerHeuristic(pdfLight, pdfBsdf) / pdfLight;
                p.L += contribution;
#ifdef PT_RECORD_PATHS
                pv.flags |= VERTEX_HAS_LIGHT_SAMPLE;
                pv.lightPosition = ls.point.position;
                pv.lightTriangle = ls.point.triangle;
                pv.lightB1 = ls.barycentrics.x;
                pv.lightB2 = ls.barycentrics.y;
                pv.explicitContribution = contribution;
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
    pathVertices[p.firstVertex + p.vertexCount] = pv;
    p.vertexCount += 1u;
#endif
    if (!scattered) return false;
    p.beta *= bs.f * abs(bs.wi.z) / bs.pdf;
    if (bs.wi.z < 0.0) p.etaScale *= sqr(sh.bsdf.eta);
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

// Direct lighting only (MIS of light and BSDF sampling, Veach 1997 sec. 9.2.4): emission seen
// at x1 plus light reflected at x1 towards the camera, estimated with `lightSamples` light and
// as many BSDF samples, each weighted by the power heuristic with sample counts. Its expected
// value equals a path traced with maxDepth = 1. The PMC-HI baseline.
vec3 directLighting(vec2 raster, inout Sampler smp, uint lightSamples, inout uint rays) {
    vec3 origin = sceneInfo.cameraPosition;
    vec3 dir = cameraDirection(raster);
    Hit hit;
    rays += 1u;
    if (!traceClosest(origin, dir, FLOAT_MAX, hit)) return vec3(0.0);
    SurfacePoint s = surfaceAt(hit.triangle, vec2(hit.b1, hit.b2));
    vec3 wo = -dir;
    ShadingPoint sh = makeShadingPoint(s, wo);
    vec3 L = emittedRadiance(s, wo);
    float n = float(lightSamples);

    for (uint i = 0u; i < lightSamples; ++i) {
        // Light sample.
        float uLight = samplerGet1D(smp);
        vec2 uLightPoint = samplerGet2D(smp);
        if (bsdfHasNonDelta(sh.bsdf)) {
            LightSample ls = sampleLight(uLight, uLightPoint);
            vec3 toLight = ls.point.position - s.position;
            vec3 wi = normalize(toLight);
            vec3 Lemit = emittedRadiance(ls.point, -wi);
            float pdfLight = areaToSolidAngle(ls.pdfArea, s.position, ls.point.position, ls.point.normal);
            if (maxComponent(Lemit) > 0.0 && pdfLight > 0.0) {
                float pdfBsdf, absCos;
                vec3 f = shadingEval(sh, wi, pdfBsdf, absCos);
                if (maxComponent(f) > 0.0 && visible(sh, ls.point, rays))
                    L += f * absCos * Lemit * powerHeuristic(n, pdfLight, n, pdfBsdf) / (n * pdfLight);
            }
        }
        // BSDF sample.
        float uLobe = samplerGet1D(smp);
        vec2 uDir = samplerGet2D(smp);
        BsdfSample bs;
        vec3 wi;
        if (!shadingSample(sh, uLobe, uDir, bs, wi)) continue;
        Hit lightHit;
        rays += 1u;
        if (!traceClosest(spawnOrigin(sh, wi), wi, FLOAT_MAX, lightHit)) continue;
        SurfacePoint l = surfaceAt(lightHit.triangle, vec2(lightHit.b1, lightHit.b2));
        vec3 Lemit = emittedRadiance(l, -wi);
        if (maxComponent(Lemit) <= 0.0) continue;
        float w = 1.0;
        if (!bs.delta) {
            float pdfLight = areaToSolidAngle(emitterAreaPdf(l.triangle), s.position, l.position, l.normal);
            w = powerHeuristic(n, bs.pdf, n, pdfLight);
        }
        L += bs.f * abs(bs.wi.z) * Lemit * w / (n * bs.pdf);
    }
    return L;
}

#endif
