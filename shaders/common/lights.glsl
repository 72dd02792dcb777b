// Area light sampling: an emitter triangle chosen in proportion to its power through the alias
// table, then a point uniform in its area. The selection probability is recomputed from the
// same power formula as the host (host/scene/scene.cpp emitterPower), so the MIS weight of a
// BSDF-sampled hit uses exactly the density light sampling has.
#ifndef PMCR_LIGHTS_GLSL
#define PMCR_LIGHTS_GLSL

#include "common/environment.glsl"
#include "common/sampling.glsl"
#include "common/scene.glsl"

// Power per unit area of an emitter triangle: luminance(Le) * pi * (2 if double-sided), the
// radiant exitance of a diffuse area light (pbrt-v4 DiffuseAreaLight::Phi over its area; the
// host's emitterPower in host/scene/scene.cpp is this times the area).
// With emissive textures, the luminance is the triangle's mean (Scene::triangleEmission).
layout(set = SCENE_SET, binding = BINDING_TRIANGLE_EMISSION) uniform samplerBuffer triangleEmissionTexels;

float emitterPowerPerArea(uint tri) {
    Material m = materialAt(triangleAt(tri).material);
    float sides = (m.flags & MATERIAL_DOUBLE_SIDED) != 0u ? 2.0 : 1.0;
    float lum = sceneHasEmissiveTextures()
                    ? texelFetch(triangleEmissionTexels, int(tri >> 2))[tri & 3u]
                    : luminance(m.emission);
    return lum * PI * sides;
}

// Power of an emitter triangle: area * luminance(Le) * pi * (2 if double-sided).
float emitterPower(uint tri) { return triangleArea(tri) * emitterPowerPerArea(tri); }

// Light sampling picks the environment with probability envSelectPmf (u in [0, envSelectPmf)),
// a punctual light with punctualSelectPmf (the next interval), else an emitter triangle
// (probabilities from chooseLights, host/scene/scene.h).
bool hasPunctualLights() {
#ifdef PMCR_OTHER_LIGHTS  // see hasEnvironment
    return sceneInfo.punctualCount > 0u;
#else
    return false;
#endif
}

bool hasOtherLights() { return hasEnvironment() || hasPunctualLights(); }

// Probability that light sampling picks an emitter triangle.
float emittersSelectPmf() {
    return hasOtherLights() ? 1.0 - sceneInfo.envSelectPmf - sceneInfo.punctualSelectPmf : 1.0;
}

// The punctual lights (KHR_lights_punctual), and the alias table over their power.
layout(set = SCENE_SET, binding = BINDING_PUNCTUAL_LIGHTS) uniform usamplerBuffer punctualTexels;
layout(set = SCENE_SET, binding = BINDING_PUNCTUAL_ALIAS) uniform usamplerBuffer punctualAliasTexels;

PunctualLight punctualLightAt(uint i) {
    uvec4 a = texelFetch(punctualTexels, int(PUNCTUAL_LIGHT_TEXELS * i));
    vec4 b = uintBitsToFloat(texelFetch(punctualTexels, int(PUNCTUAL_LIGHT_TEXELS * i + 1u)));
    vec4 c = uintBitsToFloat(texelFetch(punctualTexels, int(PUNCTUAL_LIGHT_TEXELS * i + 2u)));
    return PunctualLight(uintBitsToFloat(a.xyz), a.w, b.xyz, b.w, c.xyz, c.w);
}

// A spot light's falloff at cosTheta off its axis, as the KHR_lights_punctual specification's
// implementation note gives it (its lightAngleScale = 1 / max(0.001, cos inner - cos outer),
// squared): 1 inside the inner cone, 0 outside the outer, smooth in between.
float spotFalloff(PunctualLight l, float cosTheta) {
    float t = clamp((cosTheta - l.cosOuter) / max(1e-3, l.cosInner - l.cosOuter), 0.0, 1.0);
    return t * t;
}

// Probability of selecting triangle `tri` when sampling lights.
float emitterSelectPmf(uint tri) {
    return emitterPower(tri) / sceneInfo.totalEmitterPower * emittersSelectPmf();
}

// Density, per unit area of the emitter, of light sampling producing a point on triangle `tri`:
// the selection probability over the area, in which the area cancels (no vertex is read).
float emitterAreaPdf(uint tri) {
    return emitterPowerPerArea(tri) / sceneInfo.totalEmitterPower * emittersSelectPmf();
}

struct LightSample {
    SurfacePoint point;
    vec2 barycentrics; // (b1, b2) of the point on its triangle
    float pdfArea;     // selection pmf / triangle area
};

// The point uPoint picks uniformly on emitter triangle `tri`, with area density pdfArea.
LightSample lightSampleOn(uint tri, vec2 uPoint, float pdfArea) {
    LightSample ls;
    ls.barycentrics = sampleUniformTriangle(uPoint);
    ls.point = surfaceAt(tri, ls.barycentrics);
    ls.pdfArea = pdfArea;
    return ls;
}

// The light groups and their alias tables, one uint texel per LightGroup and per Emitter:
// PMC-HI's lights (light_groups.glsl), then at index sceneInfo.lightCount the group of all
// emitters, whose table selects in proportion to power (host/scene/scene.cpp buildEmitters).
layout(set = SCENE_SET, binding = BINDING_LIGHT_GROUPS) uniform usamplerBuffer lightGroupTexels;
layout(set = SCENE_SET, binding = BINDING_LIGHT_EMITTERS) uniform usamplerBuffer lightEmitterTexels;

LightGroup lightGroupAt(uint i) {
    uvec4 t = texelFetch(lightGroupTexels, int(i));
    return LightGroup(t.x, t.y, uintBitsToFloat(t.z), t.w);
}

// The triangle group `group`'s alias table picks with u.
uint lightGroupTriangle(uint group, float u) {
    LightGroup g = lightGroupAt(group);
    return aliasTableTriangle(lightEmitterTexels, g.firstEmitter, g.emitterCount, u);
}

// Picks an emitter with uSelect (the alias table of all emitters) and a point on it with uPoint.
// With other lights, the caller has picked the emitters with uSelect in
// [envSelectPmf + punctualSelectPmf, 1), which is stretched back to [0, 1).
LightSample sampleLight(float uSelect, vec2 uPoint) {
    float others = sceneInfo.envSelectPmf + sceneInfo.punctualSelectPmf;
    if (hasOtherLights() && others < 1.0) {
        uSelect = clamp((uSelect - others) / (1.0 - others), 0.0, ONE_MINUS_EPSILON);
    }
    uint tri = lightGroupTriangle(sceneInfo.lightCount, uSelect);
    return lightSampleOn(tri, uPoint, emitterAreaPdf(tri));
}

// Converts an area density at `lightPoint` (seen from `from`) to solid angle: p_A d^2 / |cos|.
float areaToSolidAngle(float pdfArea, vec3 from, vec3 lightPoint, vec3 lightNormal) {
    vec3 d = lightPoint - from;
    float dist2 = dot(d, d);
    float cosLight = abs(dot(lightNormal, d)) * inversesqrt(dist2);
    return cosLight > 0.0 ? pdfArea * dist2 / cosLight : 0.0;
}

#endif
