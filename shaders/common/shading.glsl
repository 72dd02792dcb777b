// A shading point: the surface hit, its BSDF and local frame, with the geometric-normal checks
// that keep shading normals from leaking light (pbrt-v3 sec. 9.1: a direction must be on the
// same side of the geometric and the shading normal).
#ifndef PMCR_SHADING_GLSL
#define PMCR_SHADING_GLSL

#include "common/bsdf.glsl"
#include "common/scene.glsl"

struct ShadingPoint {
    SurfacePoint surface;
    Frame frame;        // z = shading normal on the side of wo
    vec3 ng;            // geometric normal on the side of wo
    vec3 woLocal;
    bool front;         // wo is on the front (CCW) side
    Bsdf bsdf;
};

ShadingPoint makeShadingPoint(SurfacePoint s, vec3 wo) {
    ShadingPoint sh;
    sh.surface = s;
    sh.front = dot(s.normal, wo) > 0.0;
    sh.ng = sh.front ? s.normal : -s.normal;
    Material m = materialAt(s.material);
    MaterialSample ms = materialTextures(m, s);
    sh.frame = frameFromNormal(sh.front ? ms.shadingNormal : -ms.shadingNormal);
    sh.woLocal = toLocal(sh.frame, wo);
    // The issue 41 features under their scene feature bits, so that a scene without them runs
    // code without them (constants the compiler folds through the BSDF).
    sh.bsdf = makeBsdf(ms.baseColor, ms.metallic, ms.roughness, ms.transmission, m.ior, sh.front,
                       sceneHasThin() && (m.flags & MATERIAL_THIN_WALLED) != 0u, ms.coverage);
    if (sceneHasSpecular() && (m.flags & MATERIAL_SPECULAR) != 0u)
        bsdfSetSpecular(sh.bsdf, ms.specular, ms.specularColor);
    if (sceneHasClearcoat() && m.clearcoat > 0.0) {
        bsdfSetClearcoat(sh.bsdf, ms.clearcoat, ms.clearcoatRoughness);
        // The coat's own normal (bsdf.glsl clearcoatNormal), the front's, in the local frame.
        if (sceneHasClearcoatNormals())
            bsdfSetClearcoatNormal(sh.bsdf, toLocal(sh.frame, ms.clearcoatNormal));
    }
    if (sceneHasSheen() && maxComponent(m.sheenColor) > 0.0)
        bsdfSetSheen(sh.bsdf, ms.sheenColor, ms.sheenRoughness, sh.woLocal);
    // In a scene without GGX lobes (SCENE_FEATURE_NO_GLOSSY) every alpha that matters is below
    // SMOOTH_ALPHA, and without transmission every glass weight is 0: as constants they let the
    // compiler drop the microfacet code, or the glass lobe's, from every kernel.
    if (!sceneHasGlossy()) {
        sh.bsdf.alpha = 0.0;
        sh.bsdf.clearcoatAlpha = 0.0;
    }
    if (!sceneHasTransmission()) sh.bsdf.wDielectric = 0.0;
    return sh;
}

// BSDF value and sampling density for world direction wi (wiLocal in the shading frame), zero
// when the geometric and the shading normal disagree about the side of wi.
vec3 shadingEvalLocal(ShadingPoint sh, vec3 wi, vec3 wiLocal, out float pdf) {
    pdf = 0.0;
    if ((dot(wi, sh.ng) > 0.0) != (wiLocal.z > 0.0)) return vec3(0.0);
    return bsdfEvalPdf(sh.bsdf, sh.woLocal, wiLocal, pdf);
}

vec3 shadingEval(ShadingPoint sh, vec3 wi, out float pdf, out float absCos) {
    vec3 wiLocal = toLocal(sh.frame, wi);
    absCos = abs(wiLocal.z);
    return shadingEvalLocal(sh, wi, wiLocal, pdf);
}

// Samples the BSDF; fails when nothing is sampled or the geometric check rejects the direction.
bool shadingSample(ShadingPoint sh, float uLobe, vec2 u, out BsdfSample s, out vec3 wi) {
    wi = vec3(0.0);
    if (!bsdfSample(sh.bsdf, sh.woLocal, uLobe, u, s)) return false;
    wi = toWorld(sh.frame, s.wi);
    return (dot(wi, sh.ng) > 0.0) == (s.wi.z > 0.0);
}

// bsdfSampleDirection at a shading point: a non-delta sample has only its direction (s.wi
// local, wi world), for shadingEvalLocal.
bool shadingSampleDirection(ShadingPoint sh, float uLobe, vec2 u, out BsdfSample s, out vec3 wi) {
    wi = vec3(0.0);
    if (!bsdfSampleDirection(sh.bsdf, sh.woLocal, uLobe, u, s)) return false;
    wi = toWorld(sh.frame, s.wi);
    return (dot(wi, sh.ng) > 0.0) == (s.wi.z > 0.0);
}

// Beer-Lambert transmittance exp(-sigma_a d) of a segment of length `dist` along `dir` that
// ends at s: a segment that reaches the back of a surface whose material absorbs
// (KHR_materials_volume) ran inside that material's medium. Every method applies it where a
// segment ends on a surface (path tracing, PMC-HI's camera ray, path evaluation of ERPT and
// PMC-ER), so they estimate the same image. An emitter's material never absorbs here: light
// sampling reaches emitters by shadow rays, which take no transmittance, and BSDF sampling
// must then score the same path alike.
vec3 segmentTransmittance(SurfacePoint s, vec3 dir, float dist) {
    if (!sceneHasAbsorption()) return vec3(1.0);
    if (!(dot(s.normal, dir) > 0.0)) return vec3(1.0);
    Material m = materialAt(s.material);
    if (maxComponent(m.emission) > 0.0) return vec3(1.0);
    return exp(-m.absorption * dist);
}

// Origin for a ray leaving the shading point in direction w.
vec3 spawnOrigin(ShadingPoint sh, vec3 w) {
    return offsetRayOrigin(sh.surface.position, dot(w, sh.ng) > 0.0 ? sh.ng : -sh.ng);
}

// The shadow ray from a shading point to a point on a light, both ends offset off their
// surfaces: occluded when anything is hit with t < tMax.
struct ShadowRay {
    vec3 origin;
    vec3 dir;
    float tMax;
};

// The segment from `origin` to just short of `target`.
ShadowRay shadowSegment(vec3 origin, vec3 target) {
    ShadowRay r;
    r.origin = origin;
    vec3 d = target - origin;
    float dist = length(d);
    r.dir = d / dist;
    r.tMax = dist * (1.0 - 1e-4);
    return r;
}

ShadowRay shadowRay(ShadingPoint sh, SurfacePoint light) {
    vec3 toLight = light.position - sh.surface.position;
    vec3 target = offsetRayOrigin(light.position,
                                  dot(toLight, light.normal) < 0.0 ? light.normal : -light.normal);
    return shadowSegment(spawnOrigin(sh, toLight), target);
}

#endif
