// Where a photon path starts: a light picked with the probabilities light sampling uses
// (lights.glsl: the environment with envSelectPmf, a punctual light with punctualSelectPmf, else
// an emitter triangle in proportion to its power), a point on it and a direction, and the
// flux the path carries: Le |cos| / (p_select p_A(x) p_w(w)) (Veach 1997 sec. 8.2: the light
// subpath's first throughput; Jensen 2001 sec. 5.1: photon power = light power / photons).
#ifndef PMCR_PHOTON_EMISSION_GLSL
#define PMCR_PHOTON_EMISSION_GLSL

#include "common/environment.glsl"
#include "common/lights.glsl"
#include "common/punctual_sampling.glsl"
#include "common/rng.glsl"
#include "common/sampling.glsl"

struct PhotonRay {
    vec3 origin;
    vec3 dir;
    vec3 power;  // flux of the whole path (before the caller's 1 / paths)
};

// A point on the disc of radius sceneRadius perpendicular to `dir` through the scene's centre,
// moved back by sceneRadius against dir: rays from it along dir cover the whole scene, for
// lights at infinity (the environment, directional lights; pbrt-v4 DistantLight::SampleLe).
// Area density 1 / (pi R^2).
vec3 photonDiscOrigin(vec3 dir, vec2 u) {
    vec3 t, b;
    orthonormalBasis(dir, t, b);
    vec2 d = sampleUniformDiskConcentric(u) * sceneInfo.sceneRadius;
    return sceneInfo.sceneCenter - dir * sceneInfo.sceneRadius + d.x * t + d.y * b;
}

float photonDiscArea() { return PI * sqr(sceneInfo.sceneRadius); }

#ifdef PMCR_OTHER_LIGHTS
// A punctual light's photon: a point light's direction uniform on the sphere, a spot's uniform
// in its outer cone, a directional light's ray from the disc (photonDiscOrigin).
PhotonRay punctualPhoton(float uPick, vec2 uDir, vec2 uDisc, float selectPmf) {
    uint index = aliasTableTriangle(punctualAliasTexels, 0u, sceneInfo.punctualCount, uPick);
    PunctualLight l = punctualLightAt(index);
    float pmf = punctualLightPmf(index) * selectPmf;
    PhotonRay r;
    if (l.type == PUNCTUAL_DIRECTIONAL) {
        r.dir = l.direction;
        r.origin = photonDiscOrigin(r.dir, uDisc);
        r.power = l.intensity * photonDiscArea() / pmf;  // E * area of the disc
        return r;
    }
    r.origin = l.position;
    if (l.type == PUNCTUAL_SPOT) {
        vec3 t, b;
        orthonormalBasis(l.direction, t, b);
        vec3 local = sampleUniformCone(uDir, l.cosOuter);
        r.dir = local.x * t + local.y * b + local.z * l.direction;
        r.power = l.intensity * spotFalloff(l, local.z) / (uniformConePdf(l.cosOuter) * pmf);
    } else {
        r.dir = sampleUniformSphere(uDir);
        r.power = l.intensity * (4.0 * PI) / pmf;
    }
    return r;
}
#endif

// The start of a photon path, from five uniform numbers in [0, 1).
PhotonRay emitPhoton(inout Rng rng) {
    float uLight = rngNext(rng);
    vec2 uPoint = rngNext2(rng);
    vec2 uDir = rngNext2(rng);
    PhotonRay r;
#ifdef PMCR_OTHER_LIGHTS
    if (hasEnvironment() && uLight < sceneInfo.envSelectPmf) {
        // Arriving from e.wi: the photon travels along -e.wi, from the disc on the light's side.
        EnvSample e = envSample(min(uLight / sceneInfo.envSelectPmf, ONE_MINUS_EPSILON), uPoint);
        r.dir = -e.wi;
        r.origin = photonDiscOrigin(r.dir, uDir);
        r.power = e.pdf > 0.0 ? e.Le * photonDiscArea() / (e.pdf * sceneInfo.envSelectPmf) : vec3(0.0);
        return r;
    }
    float uPunctual = uLight - sceneInfo.envSelectPmf;
    if (hasPunctualLights() &&
        (uPunctual < sceneInfo.punctualSelectPmf || !(sceneInfo.totalEmitterPower > 0.0))) {
        return punctualPhoton(min(uPunctual / sceneInfo.punctualSelectPmf, ONE_MINUS_EPSILON),
                              uDir, uPoint, sceneInfo.punctualSelectPmf);
    }
#endif
    // An emitter: a point uniform on a triangle picked by power, a cosine-distributed direction
    // on its emitting side (either side with probability 1/2 when double-sided).
    LightSample ls = sampleLight(uLight, uPoint);
    Material m = materialAt(ls.point.material);
    bool twoSided = (m.flags & MATERIAL_DOUBLE_SIDED) != 0u;
    vec3 n = ls.point.normal;
    float sides = 1.0;
    if (twoSided) {
        sides = 2.0;
        // The side from the first number's low bits, which the triangle pick hardly uses.
        if (uDir.x < 0.5) {
            uDir.x *= 2.0;
        } else {
            uDir.x = uDir.x * 2.0 - 1.0;
            n = -n;
        }
    }
    vec3 local = sampleCosineHemisphere(uDir);
    Frame f = frameFromNormal(n);
    r.dir = toWorld(f, local);
    r.origin = offsetRayOrigin(ls.point.position, n);
    // Le cos / (p_A * cos / (pi * sides)) = Le pi sides / p_A.
    float pdfDir = cosineHemispherePdf(local.z) / sides;
    r.power = pdfDir > 0.0 && ls.pdfArea > 0.0
                  ? emittedRadiance(ls.point, r.dir) * local.z / (ls.pdfArea * pdfDir)
                  : vec3(0.0);
    return r;
}

#endif
