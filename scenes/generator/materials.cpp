#include "materials.h"

#include <numbers>

namespace pmcr::scenegen {

double degrees(double d) {
    return d * std::numbers::pi / 180.0;
}

int addMaterial(SceneDesc& scene, MaterialDesc material) {
    scene.materials.push_back(std::move(material));
    return int(scene.materials.size()) - 1;
}

MaterialDesc lambertian(std::string name, glm::dvec3 albedo) {
    MaterialDesc m;
    m.name = std::move(name);
    m.baseColor = albedo;
    return m;
}

MaterialDesc mirror(std::string name) {
    MaterialDesc m;
    m.name = std::move(name);
    m.metallic = 1.0;
    m.roughness = 0.0;
    return m;
}

MaterialDesc glass(std::string name) {
    MaterialDesc m;
    m.name = std::move(name);
    m.roughness = 0.0;
    m.transmission = 1.0;
    m.ior = 1.5;
    return m;
}

MaterialDesc plastic(std::string name, glm::dvec3 base, double roughness) {
    MaterialDesc m = lambertian(std::move(name), base);
    m.roughness = roughness;
    return m;
}

MaterialDesc conductor(std::string name, glm::dvec3 f0, double roughness) {
    MaterialDesc m;
    m.name = std::move(name);
    m.baseColor = f0;
    m.metallic = 1.0;
    m.roughness = roughness;
    return m;
}

glm::dvec3 conductorF0(const glm::dvec3& eta, const glm::dvec3& k) {
    return ((eta - 1.0) * (eta - 1.0) + k * k) / ((eta + 1.0) * (eta + 1.0) + k * k);
}

MaterialDesc emitter(std::string name, glm::dvec3 radiance) {
    MaterialDesc m = lambertian(std::move(name), glm::dvec3(0.0));
    m.emission = radiance;
    return m;
}

CameraDesc lookAt(const glm::dvec3& eye, const glm::dvec3& target, double yfovDegrees) {
    CameraDesc camera;
    camera.position = eye;
    camera.forward = glm::normalize(target - eye);
    camera.up = {0.0, 1.0, 0.0};
    camera.yfov = degrees(yfovDegrees);
    return camera;
}

}  // namespace pmcr::scenegen
