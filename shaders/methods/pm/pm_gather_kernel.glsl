// The body of the photon mapping gather kernels (pm_gather*.comp): one camera sample's radiance
// with the photon map of the current pass (photon_map.glsl), in the two-pass renderer of Jensen
// 2001 ch. 9 as the PMC paper's sec. 6 starts from:
//  - the camera ray follows delta (specular) scattering, counting the emission it sees, to the
//    first point x whose BSDF has a non-delta lobe: the gather point;
//  - direct light at x by MIS of light and BSDF sampling (path_tracer.glsl addDirectLighting),
//    or with PM_PMC_HI by PMC-HI with the PMC-IP feedback (methods/pmc_hi/pmc_hi.glsl);
//  - caustics at x (L S+ D) from the caustic photons within the radius, seen directly;
//  - the rest of the indirect light by a final gather: gatherRays BSDF-sampled rays (cosine
//    rays on a Lambertian surface) that follow delta scattering to the first point y with a
//    non-delta lobe and read every photon there (Jensen 2001 sec. 9.2). Emission the gather
//    rays reach is the direct estimate's at their first hit; after delta scattering it counts
//    only when x's own sample was a delta lobe (otherwise the path is a caustic at x, already
//    in the caustic photons). With gatherDirect (--gather-direct on) the direct light at y is
//    estimated by light sampling instead and only y's non-direct photons are read. gatherRays
//    = 0 reads the non-direct, non-caustic photons at x instead.
// Each part estimates its own set of paths, so at a fixed radius the sum is the path tracer's
// image up to density estimation's bias (blur), which vanishes as the radius shrinks.
#include "shared/host_device.h"

layout(local_size_x = WORKGROUP_SIZE) in;
#ifdef PM_PMC_HI
layout(push_constant, scalar) uniform PushBlock {
    PtPush push;
    PmcHiParams hi;
};
#else
layout(push_constant, scalar) uniform PushBlock { PtPush push; };
#endif

#include "common/film.glsl"
#include "methods/pm/photon_map.glsl"
#include "methods/pt/path_tracer.glsl"
#ifdef PM_PMC_HI
#include "methods/pmc_hi/pmc_hi.glsl"
#include "methods/pmc_hi/pmc_hi_feedback.glsl"
#endif

// Delta scatterings a final gather ray follows at most (each a traced ray: lavapipe's loop budget).
const uint PM_GATHER_MAX_DELTA = 8u;

LookupStats gLookups = LookupStats(0u, 0u, 0u, 0u);

// Radiance of the final gather at x (sh): the photon map read where the gather rays land.
vec3 finalGather(ShadingPoint sh, uint depth, inout Sampler smp, inout uint rays) {
    vec3 L = vec3(0.0);
    uint G = photonMap.gatherRays;
    uint chainMax = min(push.maxDepth - depth - 1u, PM_GATHER_MAX_DELTA);
    for (uint g = 0u; g < G; ++g) {
        float uLobe = samplerGet1D(smp);
        vec2 uDir = samplerGet2D(smp);
        BsdfSample bs;
        vec3 wi;
        if (!shadingSample(sh, uLobe, uDir, bs, wi)) continue;
        vec3 w = bs.f * abs(bs.wi.z) / (bs.pdf * float(G));
        bool deltaAtX = bs.delta;
        vec3 origin = spawnOrigin(sh, wi);
        vec3 dir = wi;
        for (uint k = 0u; k <= chainMax; ++k) {
            Hit hit;
            rays += 1u;
            if (!traceClosest(origin, dir, FLOAT_MAX, hit)) {
                if (deltaAtX && k > 0u && hasEnvironment()) L += w * envRadiance(dir);
                break;
            }
            SurfacePoint s = surfaceAt(hit.triangle, vec2(hit.b1, hit.b2));
            w *= segmentTransmittance(s, dir, hit.t);
            ShadingPoint y = makeShadingPoint(s, -dir);
            if (deltaAtX && k > 0u) L += w * emittedRadiance(s, -dir);
            if (bsdfHasNonDelta(y.bsdf)) {
                float uLookup = samplerGet1D(smp);
                // The path has depth + 1 + k bounces before y (the camera's delta ones, x, the
                // gather ray's delta ones) and y's scattering makes one more: photons of hit
                // h <= maxDepth - depth - k - 1 keep it within maxDepth.
                uint maxHit = push.maxDepth - min(push.maxDepth, depth + k + 1u);
                if (photonMap.gatherDirect == 0u) {
                    L += w * photonRadiance(y, false, 0u, maxHit, uLookup, gLookups);
                } else if (maxHit >= 1u) {
                    // y's direct light by MIS of light and BSDF sampling (one of each), its
                    // indirect light from the photons that are not the lights' first hits, so
                    // the density estimate no longer blurs direct light's sharp edges. The
                    // direct light at y ends a path of depth + 2 + k bounces.
                    vec3 Ly = photonRadiance(y, false, PHOTON_DIRECT, maxHit, uLookup, gLookups);
                    addDirectLighting(y, smp, 1u, rays, Ly);
                    L += w * Ly;
                }
                break;
            }
            if (k == chainMax) break;
            BsdfSample next;
            vec3 wn;
            if (!shadingSample(y, samplerGet1D(smp), samplerGet2D(smp), next, wn)) break;
            w *= next.f * abs(next.wi.z) / next.pdf;
            origin = spawnOrigin(y, wn);
            dir = wn;
        }
    }
    return L;
}

vec3 estimateRadiance(vec2 raster, inout Sampler smp, inout uint rays, uint recordIndex) {
#ifdef PM_PMC_HI
    const uint m = pmcHiSlots(hi);
    const uint feedbackSlots = (hi.flags & PMC_HI_FLAG_FEEDBACK) != 0u ? m : 0u;
    uint pixel = uint(raster.y) * sceneInfo.width + uint(raster.x);
    float start[PMC_HI_MAX_COMPONENTS];
    float startSum = pmcHiStartingAlpha(pixel, feedbackSlots, start);
    float alpha[PMC_HI_MAX_COMPONENTS];
    bool adapted = false;
#endif
    // The camera ray through delta scattering to the gather point.
    vec3 L = vec3(0.0);
    vec3 beta = vec3(1.0);
    vec3 origin = sceneInfo.cameraPosition;
    vec3 dir = cameraDirection(raster);
    ShadingPoint sh;
    bool found = false;
    uint depth = 0u;
    for (; depth <= push.maxDepth; ++depth) {
        Hit hit;
        rays += 1u;
        if (!traceClosest(origin, dir, FLOAT_MAX, hit)) {
            if (hasEnvironment()) L += beta * envRadiance(dir);
            break;
        }
        SurfacePoint s = surfaceAt(hit.triangle, vec2(hit.b1, hit.b2));
        beta *= segmentTransmittance(s, dir, hit.t);
        sh = makeShadingPoint(s, -dir);
        L += beta * emittedRadiance(s, -dir);
        if (bsdfHasNonDelta(sh.bsdf)) {
            found = depth < push.maxDepth;  // x's light needs one more bounce
            break;
        }
        if (depth == push.maxDepth) break;
        BsdfSample bs;
        vec3 wi;
        if (!shadingSample(sh, samplerGet1D(smp), samplerGet2D(smp), bs, wi)) break;
        beta *= bs.f * abs(bs.wi.z) / bs.pdf;
        origin = spawnOrigin(sh, wi);
        dir = wi;
    }
    if (found) {
        vec3 Lx = vec3(0.0);
#ifdef PM_PMC_HI
        Lx += pmcHiEstimate(sh, hi, start, startSum > 0.0, smp, rays, alpha, adapted);
        if (hasPunctualLights()) Lx += pmcHiPunctualDirect(sh, samplerGet1D(smp), rays);
#else
        addDirectLighting(sh, smp, push.lightSamples, rays, Lx);
#endif
        if (depth + 1u < push.maxDepth) {
            // x's photons of hit h end paths of depth + h bounces.
            uint maxHit = push.maxDepth - depth;
            float uCaustic = samplerGet1D(smp);
            if (photonMap.causticCount > 0u)
                Lx += photonRadiance(sh, true, 0u, maxHit, uCaustic, gLookups);
            if (photonMap.gatherRays > 0u)
                Lx += finalGather(sh, depth, smp, rays);
            else
                Lx += photonRadiance(sh, false, PHOTON_DIRECT | PHOTON_CAUSTIC, maxHit,
                                     samplerGet1D(smp), gLookups);
        }
        L += beta * Lx;
    }
#ifdef PM_PMC_HI
    pmcHiWriteFinalAlpha(recordIndex, feedbackSlots, adapted, alpha);
#endif
    return L;
}

#define CAMERA_SAMPLE_FINISH() lookupStatsCount(gLookups)
#include "methods/pt/camera_sample_kernel.glsl"
