// The body of bdpt_subpaths.comp and bdpt_subpaths_all_lights.comp: per camera sample (one
// pixel of the pass) a camera subpath of up to maxDepth + 2 vertices and a light subpath of up to
// maxDepth + 1 (pbrt-v4 GenerateCameraSubpath, GenerateLightSubpath, RandomWalk), written to
// the vertex buffers for bdpt_connect.comp. Random numbers come from the pixel's sampler
// (common/sampler.glsl) in fixed dimensions: the raster position (0), the camera walk from 1,
// three per vertex (lobe, direction, roulette), then the light walk (bdptLightDimension), so
// that the light subpath's numbers do not depend on the camera subpath's length.
#include "shared/host_device.h"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(push_constant, scalar) uniform PushBlock { BdptPush push; };

#define FILM_BINDING BDPT_BINDING_FILM
#define COUNTERS_BINDING BDPT_BINDING_COUNTERS
#include "common/film.glsl"
#include "common/kernel_options.glsl"
#include "common/sampler.glsl"
#include "methods/bdpt/bdpt_vertex.glsl"
#include "methods/pm/photon_emission.glsl"

void storeVertex(bool light, uint index, BdptVertex v) {
    if (light)
        lightVertices[index] = v;
    else
        cameraVertices[index] = v;
}

// Continues a subpath whose vertex 0 is `prev` (stored here at base) from the ray (origin, dir)
// with throughput beta and solid-angle density pdfDir of dir at prev (for an infinite light: the
// density per unit area of the disc the ray leaves). Scatters by BSDF sampling (the adjoint BSDF
// on light subpaths), records each vertex's forward density and its predecessor's reverse one,
// and applies Russian roulette from rrDepth on the throughput gained since vertex 0 (times
// eta^2 on camera subpaths, as pt). Returns the vertex count, vertex 0 included.
uint randomWalk(bool light, uint base, BdptVertex prev, vec3 origin, vec3 dir, vec3 beta,
                float pdfDir, uint maxVertices, inout Sampler smp, inout uint rays) {
    // prev is vertex n - 1, stored once its reverse density is known (or the walk ends).
    uint n = 1u;
    float pdfFwd = pdfDir;
    vec3 rrThroughput = vec3(1.0);
    float etaScale = 1.0;
    for (uint i = 1u; i < maxVertices; ++i) {
        Hit hit;
        rays += 1u;
        if (!traceClosest(origin, dir, FLOAT_MAX, hit)) {
            storeVertex(light, base + n - 1u, prev);
            // A camera subpath that escapes reaches the environment: a light vertex (s = 0).
            if (!light && hasEnvironment()) {
                BdptVertex e = bdptVertex(BDPT_LIGHT_INFINITE);
                e.wo = dir;
                e.beta = beta;
                e.pdfFwd = pdfFwd;  // solid angle (convertDensity towards an infinite light)
                storeVertex(light, base + n, e);
                n += 1u;
            }
            return n;
        }
        SurfacePoint s = surfaceAt(hit.triangle, vec2(hit.b1, hit.b2));
        beta *= segmentTransmittance(s, dir, hit.t);
        vec3 wo = -dir;
        BdptVertex v = bdptVertex(BDPT_SURFACE);
        v.position = s.position;
        v.normal = s.normal;
        v.triangle = s.triangle;
        v.barycentrics = vec2(hit.b1, hit.b2);
        v.wo = wo;
        v.beta = beta;
        v.pdfFwd = convertDensity(prev, pdfFwd, v);
        ShadingPoint sh = makeShadingPoint(s, wo);
        float uLobe = samplerGet1D(smp);
        vec2 uDir = samplerGet2D(smp);
        float uRoulette = samplerGet1D(smp);
        BsdfSample bs;
        vec3 wi;
        if (i + 1u == maxVertices || !shadingSample(sh, uLobe, uDir, bs, wi)) {
            storeVertex(light, base + n - 1u, prev);
            storeVertex(light, base + n, v);
            return n + 1u;
        }
        vec3 factor = bs.f * abs(bs.wi.z) / bs.pdf;
        if (light) {
            // The adjoint BSDF (bdpt_vertex.glsl shadingEvalImportance, photon_shoot_kernel.glsl).
            if (bs.wi.z < 0.0) factor *= sqr(sh.bsdf.eta);
            float denom = abs(dot(wo, sh.ng)) * abs(bs.wi.z);
            factor *= denom > 0.0 ? abs(sh.woLocal.z) * abs(dot(wi, sh.ng)) / denom : 0.0;
        } else if (bs.wi.z < 0.0) {
            etaScale *= sqr(sh.bsdf.eta);
        }
        float pdfRev = 0.0;
        if (bs.delta) {
            v.flags |= BDPT_VERTEX_DELTA;
            pdfFwd = 0.0;
        } else {
            pdfFwd = bs.pdf;
            pdfRev = shadingPdf(sh, wi, wo);
        }
        beta *= factor;
        rrThroughput *= factor;
        prev.pdfRev = convertDensity(v, pdfRev, prev);
        storeVertex(light, base + n - 1u, prev);
        prev = v;
        n += 1u;
        // Russian roulette after rrDepth bounces (pt's rule; vertex i is bounce i - 1).
        bool alive = maxComponent(beta) > 0.0 && isFinite(beta);
        if (alive && i >= push.rrDepth) {
            float rrBeta = maxComponent(rrThroughput * etaScale);
            if (rrBeta < 1.0) {
                float q = max(0.0, 1.0 - rrBeta);
                if (uRoulette < q) {
                    alive = false;
                } else {
                    beta /= 1.0 - q;
                    rrThroughput /= 1.0 - q;
                }
            }
        }
        if (!alive) break;
        origin = spawnOrigin(sh, wi);
        dir = wi;
    }
    storeVertex(light, base + n - 1u, prev);
    return n;
}

// The camera subpath through raster position `raster`: the pinhole, then the walk.
uint cameraSubpath(uint base, vec2 raster, inout Sampler smp, inout uint rays) {
    BdptVertex c = bdptVertex(BDPT_CAMERA);
    c.position = sceneInfo.cameraPosition;
    c.normal = sceneInfo.cameraForward;
    c.beta = vec3(1.0);  // We cos / (p_pos p_dir) = 1 for the pinhole
    c.pdfFwd = 1.0;
    vec3 dir = cameraDirection(raster);
    return randomWalk(false, base, c, sceneInfo.cameraPosition, dir, vec3(1.0),
                      cameraDirectionPdf(dir), push.cameraStride, smp, rays);
}

// The light subpath: a light picked as light sampling picks it (lights.glsl), a point on it and
// a direction, as photons leave lights (photon_emission.glsl), then the walk. Vertex 0's beta is
// its emitted radiance over the density of its position; the walk starts with
// Le |cos| / (p_select p_pos p_dir) (Veach 1997 sec. 10.2).
uint lightSubpath(uint base, inout Sampler smp, inout uint rays) {
    float uLight = samplerGet1D(smp);
    vec2 uPoint = samplerGet2D(smp);
    vec2 uDir = samplerGet2D(smp);
    BdptVertex l;
    vec3 origin, dir, beta;
    float pdfDir;
#ifdef PMCR_OTHER_LIGHTS
    float uPunctual = uLight - sceneInfo.envSelectPmf;
    if (hasEnvironment() && uLight < sceneInfo.envSelectPmf) {
        // From the environment: a direction by envSample, a ray from the disc on its side.
        EnvSample e = envSample(min(uLight / sceneInfo.envSelectPmf, ONE_MINUS_EPSILON), uPoint);
        l = bdptVertex(BDPT_LIGHT_INFINITE);
        l.wo = e.wi;
        l.pdfFwd = e.pdf * sceneInfo.envSelectPmf;
        l.beta = e.Le;
        if (!(e.pdf > 0.0)) return 0u;
        dir = -e.wi;
        origin = photonDiscOrigin(dir, uDir);
        pdfDir = 1.0 / photonDiscArea();  // per unit area of the disc (convertDensity: times |cos|)
        beta = e.Le / (l.pdfFwd * pdfDir);
    } else if (hasPunctualLights() &&
               (uPunctual < sceneInfo.punctualSelectPmf || !(sceneInfo.totalEmitterPower > 0.0))) {
        uint index = aliasTableTriangle(punctualAliasTexels, 0u, sceneInfo.punctualCount,
                                        min(uPunctual / sceneInfo.punctualSelectPmf, ONE_MINUS_EPSILON));
        PunctualLight p = punctualLightAt(index);
        float pmf = punctualLightPmf(index) * sceneInfo.punctualSelectPmf;
        if (p.type == PUNCTUAL_DIRECTIONAL) {
            l = bdptVertex(BDPT_LIGHT_INFINITE);
            l.flags = BDPT_VERTEX_DIRECTIONAL;
            l.wo = -p.direction;
            l.pdfFwd = 0.0;  // a delta in direction: no other strategy samples it
            l.beta = p.intensity;
            dir = p.direction;
            origin = photonDiscOrigin(dir, uDir);
            pdfDir = 1.0 / photonDiscArea();
            beta = p.intensity / (pmf * pdfDir);  // irradiance times the disc's area
        } else {
            l = bdptVertex(BDPT_LIGHT_POINT);
            l.position = p.position;
            l.triangle = index;
            l.pdfFwd = pmf;
            origin = p.position;
            vec3 I = p.intensity;
            if (p.type == PUNCTUAL_SPOT) {
                vec3 t, b;
                orthonormalBasis(p.direction, t, b);
                vec3 local = sampleUniformCone(uDir, p.cosOuter);
                dir = local.x * t + local.y * b + local.z * p.direction;
                pdfDir = uniformConePdf(p.cosOuter);
                I *= spotFalloff(p, local.z);
            } else {
                dir = sampleUniformSphere(uDir);
                pdfDir = 0.25 * INV_PI;
            }
            l.beta = I;
            beta = I / (pmf * pdfDir);
        }
    } else
#endif
    {
        // An emitter: a point uniform on a triangle picked by power, a cosine-distributed
        // direction on its emitting side (either side with probability 1/2 when double-sided).
        LightSample ls = sampleLight(uLight, uPoint);
        if (!(ls.pdfArea > 0.0)) return 0u;
        l = bdptVertex(BDPT_LIGHT_AREA);
        l.position = ls.point.position;
        l.normal = ls.point.normal;
        l.triangle = ls.point.triangle;
        l.barycentrics = ls.barycentrics;
        l.pdfFwd = ls.pdfArea;
        Material m = materialAt(ls.point.material);
        vec3 n = ls.point.normal;
        if ((m.flags & MATERIAL_DOUBLE_SIDED) != 0u) {
            if (uDir.x < 0.5) {
                uDir.x *= 2.0;
            } else {
                uDir.x = uDir.x * 2.0 - 1.0;
                n = -n;
            }
        }
        vec3 local = sampleCosineHemisphere(uDir);
        dir = toWorld(frameFromNormal(n), local);
        origin = offsetRayOrigin(ls.point.position, n);
        pdfDir = emitterDirectionPdf(l.triangle, l.normal, dir);
        vec3 Le = emittedRadiance(ls.point, dir);
        l.beta = Le / ls.pdfArea;
        beta = pdfDir > 0.0 ? Le * local.z / (ls.pdfArea * pdfDir) : vec3(0.0);
    }
    if (!(maxComponent(beta) > 0.0) || !isFinite(beta)) {
        storeVertex(true, base, l);
        return 1u;
    }
    return randomWalk(true, base, l, origin, dir, beta, pdfDir, push.lightStride, smp, rays);
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint rays = 0u;
    if (i < push.count) {
        uint pixel = push.pixelOffset + i;
        Sampler smp = samplerCreate(pixel, push.sampleIndex, push.seed);
        vec2 u = independentPixelSamples() ? samplerGetIndependent2D(smp) : samplerGet2D(smp);
        vec2 raster = vec2(float(pixel % sceneInfo.width), float(pixel / sceneInfo.width)) + u;
        uint cameraCount = cameraSubpath(i * push.cameraStride, raster, smp, rays);
        smp.dimension = bdptLightDimension(push.maxDepth);
        uint lightCount = lightSubpath(i * push.lightStride, smp, rays);
        vertexCounts[i] = uvec2(cameraCount, lightCount);
        // The raster position, for the connection kernel (camera vertex 0's barycentrics).
        cameraVertices[i * push.cameraStride].barycentrics = raster;
    }
    counterAdd(COUNTER_RAYS, rays);
}
