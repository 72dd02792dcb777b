// The random walks of bidirectional path tracing (pbrt-v4 GenerateCameraSubpath,
// GenerateLightSubpath, RandomWalk): a camera subpath of up to push.cameraStride vertices and a
// light subpath of up to push.lightStride, written to the vertex buffers (bdpt_vertex.glsl) one
// ray at a time (walkStep), so that kernels can walk in turn within lavapipe's loop budget.
// Random numbers come from the kernel's Sampler (common/sampler.glsl for bdpt, the primary
// sample vector for pssmlt over bdpt and mmlt) at the dimensions of bdpt_vertex.glsl. The
// kernel's push constants have rrDepth.
#ifndef PMCR_BDPT_WALK_GLSL
#define PMCR_BDPT_WALK_GLSL

#include "methods/bdpt/bdpt_vertex.glsl"
#include "methods/pm/photon_emission.glsl"

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
    // Light subpaths carry importance: the clear coat's adjoint term (bsdf.glsl clearcoatNormal).
    sh.bsdf.adjoint = w.light;
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
        // The adjoint BSDF (bdpt_vertex.glsl shadingEvalImportance, photon_shoot_kernel.glsl;
        // the clear coat's adjoint term is in bs.f).
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

// The camera subpath through raster position `raster`, of at most maxVertices vertices: the
// pinhole, then the walk.
Walk cameraWalk(uint base, vec2 raster, uint maxVertices) {
    BdptVertex c = bdptVertex(BDPT_CAMERA);
    c.position = sceneInfo.cameraPosition;
    c.normal = sceneInfo.cameraForward;
    c.beta = vec3(1.0);  // We cos / (p_pos p_dir) = 1 for the pinhole
    c.pdfFwd = 1.0;
    vec3 dir = cameraDirection(raster);
    return walkBegin(false, base, c, sceneInfo.cameraPosition, dir, vec3(1.0), cameraDirectionPdf(dir),
                     maxVertices);
}

// The light subpath: a light picked as light sampling picks it (lights.glsl), a point on it and
// a direction, as photons leave lights (photon_emission.glsl), then the walk. Vertex 0's beta is
// its emitted radiance over the density of its position; the walk starts with
// Le |cos| / (p_select p_pos p_dir) (Veach 1997 sec. 10.2).
// False when the subpath ends at its light (w.n: 0 or 1 vertices, stored); else w is its walk,
// of at most maxVertices vertices.
bool lightWalk(uint base, inout Sampler smp, uint maxVertices, out Walk w) {
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
    w = walkBegin(true, base, l, origin, dir, beta, pdfDir, maxVertices);
    return true;
}

#endif
