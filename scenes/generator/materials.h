// Helpers shared by the scene definitions: materials as pmcr reads glTF
// (shaders/shared/scene_types.h, Material), cameras and units.
#pragma once

#include <string>

#include <glm/glm.hpp>

#include "gltf_writer.h"

namespace pmcr::scenegen {

double degrees(double d);

int addMaterial(SceneDesc& scene, MaterialDesc material);

// Lambertian: non-metal, roughness 1.
MaterialDesc lambertian(std::string name, glm::dvec3 albedo);

// Ideal mirror: metallic 1, roughness 0, Schlick F0 = baseColor = 1.
MaterialDesc mirror(std::string name);

// Smooth clear glass, ior 1.5, a solid body (KHR_materials_volume).
MaterialDesc glass(std::string name);

// Lambertian base under a GGX dielectric coat of ior 1.5 ("plastic"): non-metal, roughness < 1.
MaterialDesc plastic(std::string name, glm::dvec3 base, double roughness);

// GGX conductor with Schlick F0 = f0; roughness is perceptual (GGX alpha = roughness^2).
MaterialDesc conductor(std::string name, glm::dvec3 f0, double roughness);

// Normal-incidence reflectance of a conductor with complex index eta + i k, per channel:
// ((eta - 1)^2 + k^2) / ((eta + 1)^2 + k^2) (Fresnel equations at normal incidence; pbrt-v4
// section 9.5). pmcr's conductor takes it as Schlick's F0.
glm::dvec3 conductorF0(const glm::dvec3& eta, const glm::dvec3& k);

// A black, non-reflecting one-sided emitter of radiance `radiance`.
MaterialDesc emitter(std::string name, glm::dvec3 radiance);

// A camera at `eye` looking at `target` with +y up and the given vertical field of view.
CameraDesc lookAt(const glm::dvec3& eye, const glm::dvec3& target, double yfovDegrees);

}  // namespace pmcr::scenegen
