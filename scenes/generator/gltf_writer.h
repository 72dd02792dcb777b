// Writes a scene as a single-file glTF 2.0 binary (.glb): world-space triangle meshes (float
// positions, optional float normals, u32 indices), metallic-roughness materials with the
// extensions pmcr reads, one perspective camera, and the default image size in
// extras.pmcr.{width,height}. Written directly with nlohmann::json (glTF 2.0 specification,
// sections 3.6-3.9 and 4.4 for the binary container).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "mesh.h"

namespace pmcr::scenegen {

// A material as pmcr interprets glTF (shaders/shared/scene_types.h, Material):
// non-metal with roughness 1 = Lambertian; metallic 1 roughness 0 = mirror;
// transmission 1 + volume = smooth glass of the given ior.
struct MaterialDesc {
    std::string name;
    glm::dvec3 baseColor{1.0};
    double metallic = 0.0;
    double roughness = 1.0;
    double transmission = 0.0;  // > 0 writes KHR_materials_transmission, _ior and _volume
    double ior = 1.5;
    glm::dvec3 emission{0.0};  // radiance; written as emissiveFactor * emissive_strength
};

struct CameraDesc {
    std::string name = "Camera";
    glm::dvec3 position{0.0};
    glm::dvec3 forward{0.0, 0.0, -1.0};
    glm::dvec3 up{0.0, 1.0, 0.0};
    double yfov = 0.8;  // radians
    double znear = 0.01;
};

struct ObjectDesc {
    Mesh mesh;
    int material = 0;
};

struct SceneDesc {
    std::string name;
    std::string copyright;  // asset.copyright: source and licence of third-party data
    int width = 256;
    int height = 256;
    std::vector<MaterialDesc> materials;
    std::vector<ObjectDesc> objects;
    CameraDesc camera;
};

// Writes `scene` to `path` (.glb); throws pmcr::Error naming the file on failure.
void writeGlb(const SceneDesc& scene, const std::filesystem::path& path);

}  // namespace pmcr::scenegen
