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

// A one-texel normal texture holding the tangent-space normal n (normalized, stored as
// (n + 1) / 2 in 8 bits, as glTF's normalTexture and clearcoatNormalTexture are).
Texture normalTexel(const std::string& name, const glm::vec3& n);

// Tangents for normal maps (Scene::tangents, sign +1): at each triangle's vertices a unit vector
// in its plane (the last triangle's where vertices are shared), for flat-faced scenes.
void setPlanarTangents(Scene& scene);

// A random width x height equirectangular image sky for environment-light tests: each pixel black
// with probability `blackFraction` (0: none drawn), else uniform in [0, 1) per channel times
// `scale`, drawn b, g, r in that order (the order in which the tests' skies were first drawn and
// validated); from its own seed, so a test's sky never changes. Callers
// add a sun pixel, the scale and rotation they need.
Environment randomSkyImage(uint32_t seed, float blackFraction, const glm::vec3& scale,
                           int width = 16, int height = 8);

// A KHR_lights_punctual light: `direction` (normalized here) is where a spot or directional
// light shines; `inner` and `outer` are a spot's cone angles (radians).
gpu::PunctualLight punctualLight(uint32_t type, const glm::vec3& position, const glm::vec3& direction,
                                 const glm::vec3& intensity, float inner = 0.0f, float outer = 0.0f);

}  // namespace pmcr::test
