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

#define BVH_COUNT_STEPS  // bvhStepsTaken, for walks in turn (main)
#define FILM_BINDING BDPT_BINDING_FILM
#define COUNTERS_BINDING BDPT_BINDING_COUNTERS
#include "common/film.glsl"
#include "common/kernel_options.glsl"
#include "common/sampler.glsl"
#include "methods/bdpt/bdpt_vertex.glsl"
#include "methods/pm/photon_emission.glsl"

layout(set = WORK_SET, binding = BDPT_BINDING_QUEUE, scalar) buffer QueueBuffer { uint queue[]; };

void storeVertex(bool light, uint index, BdptVertex v) {
    if (light)
        lightVertices[index] = v;
    else
        cameraVertices[index] = v;
}

// A subpath being walked: vertex 0 is `prev` (stored at base once its reverse density is known)
// and the walk continues from the ray (origin, dir) with throughput beta and solid-angle density
// pdfFwd of dir at prev (for an infinite light: the density per unit area of the disc the ray
// leaves). It scatters by BSDF sampling (the adjoint BSDF on light subpaths), records each
// vertex's forward density and its predecessor's reverse one, and applies Russian roulette from
// rrDepth on the throughput gained since vertex 0 (times eta^2 on camera subpaths, as pt).
struct Walk {
    bool light;
    uint base;
    uint maxVertices;
    BdptVertex prev;   // vertex n - 1, not stored yet
    uint n;            // vertices so far
    float pdfFwd;
    vec3 rrThroughput;
    float etaScale;
    vec3 origin;
    vec3 dir;
    vec3 beta;
};

Walk walkBegin(bool light, uint base, BdptVertex first, vec3 origin, vec3 dir, vec3 beta, float pdfDir,
               uint maxVertices) {
    return Walk(light, base, maxVertices, first, 1u, pdfDir, vec3(1.0), 1.0, origin, dir, beta);
}

// One step of the walk: traces its ray and scatters at the hit. False when the walk has ended,
// every vertex stored: w.n is then the subpath's vertex count.
bool walkStep(inout Walk w, inout Sampler smp, inout uint rays) {
    if (w.n >= w.maxVertices) {
        storeVertex(w.light, w.base + w.n - 1u, w.prev);
        return false;
    }
    Hit hit;
    rays += 1u;
    if (!traceClosest(w.origin, w.dir, FLOAT_MAX, hit)) {
        storeVertex(w.light, w.base + w.n - 1u, w.prev);
        // A camera subpath that escapes reaches the environment: a light vertex (s = 0).
        if (!w.light && hasEnvironment()) {
            BdptVertex e = bdptVertex(BDPT_LIGHT_INFINITE);
            e.wo = w.dir;
            e.beta = w.beta;
            e.pdfFwd = w.pdfFwd;  // solid angle (convertDensity towards an infinite light)
            storeVertex(w.light, w.base + w.n, e);
            w.n += 1u;
        }
        return false;
    }
    SurfacePoint s = surfaceAt(hit.triangle, vec2(hit.b1, hit.b2));
    w.beta *= segmentTransmittance(s, w.dir, hit.t);
    vec3 wo = -w.dir;
    BdptVertex v = bdptVertex(BDPT_SURFACE);
    v.position = s.position;
    v.normal = s.normal;
    v.triangle = s.triangle;
    v.barycentrics = vec2(hit.b1, hit.b2);
    v.wo = wo;
    v.beta = w.beta;
    v.pdfFwd = convertDensity(w.prev, w.pdfFwd, v);
    ShadingPoint sh = makeShadingPoint(s, wo);
    float uLobe = samplerGet1D(smp);
    vec2 uDir = samplerGet2D(smp);
    float uRoulette = samplerGet1D(smp);
    BsdfSample bs;
    vec3 wi;
    if (w.n + 1u == w.maxVertices || !shadingSample(sh, uLobe, uDir, bs, wi)) {
        storeVertex(w.light, w.base + w.n - 1u, w.prev);
        storeVertex(w.light, w.base + w.n, v);
        w.n += 1u;
        return false;
    }
    vec3 factor = bs.f * abs(bs.wi.z) / bs.pdf;
    if (w.light) {
        // The adjoint BSDF (bdpt_vertex.glsl shadingEvalImportance, photon_shoot_kernel.glsl).
        factor *= sqr(bs.eta);  // a refraction's eta; 1 for a thin sheet or a BLEND pass
        float denom = abs(dot(wo, sh.ng)) * abs(bs.wi.z);
        factor *= denom > 0.0 ? abs(sh.woLocal.z) * abs(dot(wi, sh.ng)) / denom : 0.0;
    } else {
        w.etaScale *= sqr(bs.eta);
    }
    float pdfRev = 0.0;
    if (bs.delta) {
        v.flags |= BDPT_VERTEX_DELTA;
        w.pdfFwd = 0.0;
    } else {
        w.pdfFwd = bs.pdf;
        pdfRev = shadingPdf(sh, wi, wo);
    }
    w.beta *= factor;
    w.rrThroughput *= factor;
    w.prev.pdfRev = convertDensity(v, pdfRev, w.prev);
    storeVertex(w.light, w.base + w.n - 1u, w.prev);
    w.prev = v;
    w.n += 1u;
    // Russian roulette after rrDepth bounces (pt's rule; vertex n - 1 is bounce n - 2).
    bool alive = maxComponent(w.beta) > 0.0 && isFinite(w.beta);
    if (alive && w.n - 1u >= push.rrDepth) {
        float rrBeta = maxComponent(w.rrThroughput * w.etaScale);
        if (rrBeta < 1.0) {
            float q = max(0.0, 1.0 - rrBeta);
            if (uRoulette < q) {
                alive = false;
            } else {
                w.beta /= 1.0 - q;
                w.rrThroughput /= 1.0 - q;
            }
        }
    }
    if (!alive) {
        storeVertex(w.light, w.base + w.n - 1u, w.prev);
        return false;
    }
    w.origin = spawnOrigin(sh, wi);
    w.dir = wi;
    return true;
}

// The camera subpath through raster position `raster`: the pinhole, then the walk.
Walk cameraWalk(uint base, vec2 raster) {
    BdptVertex c = bdptVertex(BDPT_CAMERA);
    c.position = sceneInfo.cameraPosition;
    c.normal = sceneInfo.cameraForward;
    c.beta = vec3(1.0);  // We cos / (p_pos p_dir) = 1 for the pinhole
    c.pdfFwd = 1.0;
    vec3 dir = cameraDirection(raster);
    return walkBegin(false, base, c, sceneInfo.cameraPosition, dir, vec3(1.0), cameraDirectionPdf(dir),
                     push.cameraStride);
}

// The light subpath: a light picked as light sampling picks it (lights.glsl), a point on it and
// a direction, as photons leave lights (photon_emission.glsl), then the walk. Vertex 0's beta is
// its emitted radiance over the density of its position; the walk starts with
// Le |cos| / (p_select p_pos p_dir) (Veach 1997 sec. 10.2).
// False when the subpath ends at its light (w.n: 0 or 1 vertices, stored); else w is its walk.
bool lightWalk(uint base, inout Sampler smp, out Walk w) {
    w.n = 0u;
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
        if (!(e.pdf > 0.0)) return false;
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
        if (!(ls.pdfArea > 0.0)) return false;
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
        w.n = 1u;
        return false;
    }
    w = walkBegin(true, base, l, origin, dir, beta, pdfDir, push.lightStride);
    return true;
}

// A camera sample's two subpaths, walked one after the other.
struct SampleWalks {
    uint index;       // in the dispatch
    Sampler smp;
    Walk walk;
    bool lightPhase;  // walking the light subpath
    uint cameraCount;
};

void beginSample(inout SampleWalks sw, uint index) {
    uint pixel = push.pixelOffset + index;
    sw.index = index;
    sw.smp = samplerCreate(pixel, push.sampleIndex, push.seed);
    vec2 u = independentPixelSamples() ? samplerGetIndependent2D(sw.smp) : samplerGet2D(sw.smp);
    vec2 raster = vec2(float(pixel % sceneInfo.width), float(pixel / sceneInfo.width)) + u;
    sw.walk = cameraWalk(index * push.cameraStride, raster);
    sw.lightPhase = false;
    sw.cameraCount = 0u;
}

// Walks in turn, as the connection kernel's connections in turn (bdpt_connect_kernel.glsl): on
// a CPU device each invocation takes samples from a queue, one ray per loop iteration, and
// starts its next sample as soon as one is done, within lavapipe's loop budget.
const uint BDPT_LOOP_STEPS_BEFORE_STOP = 16384u;

void main() {
    uint rays = 0u;
    bool fromQueue = push.itemsPerInvocation > 1u;
    uint index = fromQueue ? atomicAdd(queue[push.queueSlot], 1u) : gl_GlobalInvocationID.x;
    if (index < push.count) {
        SampleWalks sw;
        beginSample(sw, index);
        uint done = 0u;
        uint steps = max(push.itemsPerInvocation, 1u) * (push.cameraStride + push.lightStride + 1u);
        for (uint b = 0u; b < steps; ++b) {
            if (walkStep(sw.walk, sw.smp, rays)) continue;
            if (!sw.lightPhase) {
                sw.cameraCount = sw.walk.n;
                sw.smp.dimension = bdptLightDimension(push.maxDepth);
                sw.lightPhase = true;
                if (lightWalk(sw.index * push.lightStride, sw.smp, sw.walk)) continue;
            }
            vertexCounts[sw.index] = uvec2(sw.cameraCount, sw.walk.n);
            done += 1u;
            if (!fromQueue || done >= push.itemsPerInvocation || bvhStepsTaken + b > BDPT_LOOP_STEPS_BEFORE_STOP)
                break;
            index = atomicAdd(queue[push.queueSlot], 1u);
            if (index >= push.count) break;
            beginSample(sw, index);
        }
    }
    counterAdd(COUNTER_RAYS, rays);
}
