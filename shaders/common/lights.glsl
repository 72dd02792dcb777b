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
float emitterPowerPerArea(uint tri) {
    Material m = materialAt(triangleAt(tri).material);
    float sides = (m.flags & MATERIAL_DOUBLE_SIDED) != 0u ? 2.0 : 1.0;
    return luminance(m.emission) * PI * sides;
}

// Power of an emitter triangle: area * luminance(Le) * pi * (2 if double-sided).
float emitterPower(uint tri) { return triangleArea(tri) * emitterPowerPerArea(tri); }

// Probability that light sampling picks an emitter triangle rather than the environment.
float emittersSelectPmf() { return hasEnvironment() ? 1.0 - sceneInfo.envSelectPmf : 1.0; }

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
// With an environment, the caller has picked the emitters with uSelect in
// [envSelectPmf, 1), which is stretched back to [0, 1).
LightSample sampleLight(float uSelect, vec2 uPoint) {
    if (hasEnvironment() && sceneInfo.envSelectPmf < 1.0) {
        uSelect = clamp((uSelect - sceneInfo.envSelectPmf) / (1.0 - sceneInfo.envSelectPmf), 0.0,
                        ONE_MINUS_EPSILON);
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
