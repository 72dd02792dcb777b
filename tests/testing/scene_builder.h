// Small scenes built in code for the host and shader tests.
#pragma once

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace pmcr::test {

// A grey (0.5) material emitting `emission`; Lambertian at roughness 1, else under a GGX coat.
gpu::Material testMaterial(const glm::vec3& emission, bool doubleSided = false, float roughness = 1.0f);

// Appends a triangle with vertices of its own (not shared, as glTF meshes often have them).
void addTriangle(Scene& scene, const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2,
                 uint32_t material);

// A UV sphere (flat facets, no vertex normals) of `rings` x `segments`, triangles facing out.
void addSphere(Scene& scene, const glm::vec3& center, float radius, int rings, int segments,
               uint32_t material);

// A KHR_lights_punctual light: `direction` (normalized here) is where a spot or directional
// light shines; `inner` and `outer` are a spot's cone angles (radians).
gpu::PunctualLight punctualLight(uint32_t type, const glm::vec3& position, const glm::vec3& direction,
                                 const glm::vec3& intensity, float inner = 0.0f, float outer = 0.0f);

}  // namespace pmcr::test
