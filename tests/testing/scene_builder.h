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

}  // namespace pmcr::test
