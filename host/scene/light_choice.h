// How next-event estimation picks a light (shaders/common/lights.glsl, sampleLightFrom in
// shaders/methods/pt/path_tracer.glsl): the environment with probability envPmf, a punctual
// light with punctualPmf (which one by punctualTable), else an emitter triangle, by power.
//
// Power alone (pbrt-v4's PowerLightSampler) can starve a light: a directional light's power is
// its irradiance times the scene's cross-section (pi R^2 E) and an environment's pi R^2 times
// the integral of its luminance, so in a large scene a nearby lamp would be picked once in
// thousands of samples. So each choice (between the kinds present, then between the punctual
// lights) takes half its probability from power and half uniformly: every light keeps at least
// half its uniform share at each choice, and the estimators, which divide by the probability
// used, stay unbiased.
#pragma once

#include <vector>

#include "scene/scene.h"

namespace pmcr {

struct LightChoice {
    float envPmf = 0.0f;       // 0 without an environment
    float punctualPmf = 0.0f;  // 0 without punctual lights
    std::vector<gpu::Emitter> punctualTable;  // alias table over the punctual lights (`triangle`: the light)
};

// The choice for `scene`, whose emitter triangles have total power `emitterPower`, R the scene's
// bounding radius. Without emitters envPmf + punctualPmf is exactly 1.
LightChoice chooseLights(const Scene& scene, double emitterPower, float sceneRadius);

}  // namespace pmcr
