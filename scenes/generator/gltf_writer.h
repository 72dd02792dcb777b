// Writes a scene as glTF 2.0: world-space triangle meshes (float positions, optional float
// normals, u32 indices), metallic-roughness materials with the extensions pmcr reads, one
// perspective camera, the default image size in extras.pmcr.{width,height} and the papers' size
// in extras.pmcr.{paper_width,paper_height}. A scene is one binary file (.glb, section 4.4) unless
// it uses a shared mesh: then it is a .gltf with its own .bin beside it and the shared mesh in a
// file of its own that every scene using it references, so large third-party data is stored
// once. Written directly with nlohmann::json (glTF 2.0 specification, sections 3.6-3.9).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "mesh.h"

namespace pmcr::scenegen {

// A material as pmcr interprets glTF (shaders/shared/scene_types.h, Material):
// non-metal with roughness 1 = Lambertian; metallic 1 roughness 0 = mirror;
// transmission 1 + volume = smooth glass of the given ior; without the volume, a thin sheet.
struct MaterialDesc {
    std::string name;
    glm::dvec3 baseColor{1.0};
    double metallic = 0.0;
    double roughness = 1.0;
    double transmission = 0.0;  // > 0 writes KHR_materials_transmission, _ior and _volume
    double ior = 1.5;
    bool thinWalled = false;    // transmission without KHR_materials_volume (a sheet)
    glm::dvec3 emission{0.0};  // radiance; written as emissiveFactor * emissive_strength
    int baseColorTexture = -1;  // index into SceneDesc::textures (read through TEXCOORD_0)
    bool blend = false;         // alphaMode BLEND, of coverage `alpha` (times the texture's alpha)
    double alpha = 1.0;         // baseColorFactor's alpha
    double specular = -1.0;     // >= 0 writes KHR_materials_specular with specularFactor
    glm::dvec3 specularColor{1.0};  // and specularColorFactor
    double clearcoat = 0.0;     // > 0 writes KHR_materials_clearcoat (factor, roughness)
    double clearcoatRoughness = 0.0;
    glm::dvec3 sheenColor{0.0};  // non-zero writes KHR_materials_sheen (colour, roughness)
    double sheenRoughness = 0.0;
};

// An RGBA8 image (rows top to bottom), embedded in the scene as a PNG.
struct TextureDesc {
    std::string name;
    int width = 0;
    int height = 0;
    std::vector<uint8_t> rgba;
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
    // Non-empty: the mesh is written to this file (a path relative to the scene's folder, e.g.
    // "meshes/stanford-dragon.bin": positions, then normals if any, then indices) and
    // referenced as an external buffer; the scene becomes a .gltf.
    std::string sharedUri;
};

struct SceneDesc {
    std::string name;
    std::string copyright;  // asset.copyright: source and licence of third-party data
    int width = 256;        // default image size
    int height = 256;
    int paperWidth = 0;  // the size the papers render this scene at; 0: not written
    int paperHeight = 0;
    std::string environment;  // extras.pmcr.environment: the --env it is lit by when none is given
    std::vector<MaterialDesc> materials;
    std::vector<TextureDesc> textures;
    std::vector<ObjectDesc> objects;
    CameraDesc camera;
};

// Writes `scene` into `dir` as <name>.glb, or as <name>.gltf + <name>.bin plus its shared mesh
// files when it has any; returns the scene file's path. Throws pmcr::Error naming the file on
// failure.
std::filesystem::path writeScene(const SceneDesc& scene, const std::filesystem::path& dir);

}  // namespace pmcr::scenegen
