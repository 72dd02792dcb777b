// Next-event estimation of the punctual lights (KHR_lights_punctual) alone: one light picked by
// the alias table over their power, its one direction, and what it delivers. A punctual light
// is a delta distribution in direction, so this estimate has no density to weigh against BSDF
// or other sampling: it divides by the selection probability alone (pbrt-v4 PointLight::SampleLi,
// SpotLight, DistantLight), and no other sampler can reach the light. Used by PMC-HI beside its
// mixture (methods/pmc_hi/pmc_hi.glsl), and by pt's light choice among all lights
// (path_tracer.glsl sampleLightFrom).
#ifndef PMCR_PUNCTUAL_SAMPLING_GLSL
#define PMCR_PUNCTUAL_SAMPLING_GLSL

#include "common/bvh.glsl"
#include "common/lights.glsl"
#include "common/shading.glsl"

// One punctual light as seen from a point.
struct PunctualSample {
    vec3 wi;           // towards the light
    vec3 Li;           // I / d^2 (a spot's times its falloff), or a directional light's E
    float pmf;         // probability that the alias table picked it
    vec3 position;     // the light's position (point and spot lights)
    bool directional;  // no position: the shadow ray runs to infinity
    uint index;        // which light
};

// Probability that the alias table over the punctual lights' power picks light `index`.
float punctualLightPmf(uint index) {
    return uintBitsToFloat(texelFetch(punctualAliasTexels, int(index)).y);
}

// The punctual light u picks (u in [0, 1)), seen from `from`.
PunctualSample samplePunctualLight(vec3 from, float u) {
    PunctualSample ps;
    uint index = aliasTableTriangle(punctualAliasTexels, 0u, sceneInfo.punctualCount, u);
    PunctualLight l = punctualLightAt(index);
    ps.index = index;
    ps.pmf = punctualLightPmf(index);
    ps.position = l.position;
    ps.directional = l.type == PUNCTUAL_DIRECTIONAL;
    if (ps.directional) {
        ps.wi = -l.direction;
        ps.Li = l.intensity;
        return ps;
    }
    // Radiant intensity over the squared distance (inverse-square law).
    vec3 toLight = l.position - from;
    float dist2 = dot(toLight, toLight);
    ps.wi = toLight * inversesqrt(dist2);
    ps.Li = l.intensity / dist2;
    if (l.type == PUNCTUAL_SPOT) ps.Li *= spotFalloff(l, dot(-ps.wi, l.direction));
    return ps;
}

// The segment a punctual sample's light must be visible along, from `origin`.
ShadowRay punctualShadowRay(PunctualSample ps, vec3 origin) {
    return ps.directional ? ShadowRay(origin, ps.wi, FLOAT_MAX) : shadowSegment(origin, ps.position);
}

// The light reflected at `sh` from the punctual lights, estimated with one of them picked by u:
// f_r |cos| Li / pmf when the shadow ray reaches it (Veach 1997 eq. 10.3 with a delta light).
vec3 punctualDirectLighting(ShadingPoint sh, float u, inout uint rays) {
    PunctualSample ps = samplePunctualLight(sh.surface.position, u);
    if (!(maxComponent(ps.Li) > 0.0) || !(ps.pmf > 0.0)) return vec3(0.0);
    float pdfBsdf, absCos;
    vec3 f = shadingEval(sh, ps.wi, pdfBsdf, absCos);
    if (!(maxComponent(f) > 0.0)) return vec3(0.0);
    vec3 origin = spawnOrigin(sh, ps.wi);
    ShadowRay ray = punctualShadowRay(ps, origin);
    rays += 1u;
    if (traceAny(ray.origin, ray.dir, ray.tMax)) return vec3(0.0);
    return f * absCos * ps.Li / ps.pmf;
}

#endif
