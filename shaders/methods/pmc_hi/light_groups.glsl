// Lights as PMC-HI sees them (host/scene/scene.h buildLightGroups): connected groups of emitter
// triangles, each sampled by its own alias table over its triangles' power (the same power
// formula as lights.glsl), a point uniform on the chosen triangle.
#ifndef PMCR_LIGHT_GROUPS_GLSL
#define PMCR_LIGHT_GROUPS_GLSL

#include "common/lights.glsl"

layout(set = SCENE_SET, binding = BINDING_TRIANGLE_LIGHTS, scalar) readonly buffer TriangleLightBuffer {
    uint triangleLights[];
};

// Density, per unit area, of light `light`'s sampler producing a point on its triangle `tri`.
float lightGroupAreaPdf(uint light, uint tri) {
    return emitterPowerPerArea(tri) / lightGroupAt(light).power;  // the area cancels
}

// A point on light `light`: a triangle by the light's alias table (uSelect), then uniform on it.
LightSample sampleLightGroup(uint light, float uSelect, vec2 uPoint) {
    uint tri = lightGroupTriangle(light, uSelect);
    return lightSampleOn(tri, uPoint, lightGroupAreaPdf(light, tri));
}

#endif
