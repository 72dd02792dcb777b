// Re-reads a .glb, or a .gltf with its external buffers, written by the generator and validates
// it against the parts of glTF 2.0 that pmcr relies on: container layout, buffer files, buffer
// view / accessor bounds and alignment, POSITION
// min/max, index ranges, unit normals that agree with the winding, declared extensions, one
// perspective camera, at least one emitter, and the extras.pmcr image sizes.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

namespace pmcr::scenegen {

struct CheckReport {
    size_t fileBytes = 0;
    size_t meshes = 0;
    size_t vertices = 0;
    size_t triangles = 0;
    size_t smoothTriangles = 0;  // triangles whose primitive has NORMAL
    size_t materials = 0;
    size_t emissiveMaterials = 0;
    size_t emissiveTriangles = 0;
    double emitterArea = 0.0;
    double emittedPower = 0.0;      // sum of area * pi * luminance(Le): one-sided Lambertian
    glm::dvec3 emitterNormal{0.0};  // area-weighted mean front-face normal of the emitters
    glm::dvec3 boundsMin{0.0};
    glm::dvec3 boundsMax{0.0};
    glm::dvec3 cameraPosition{0.0};
    double cameraYfov = 0.0;
    int width = 0;
    int height = 0;
    int paperWidth = 0;  // 0: none given
    int paperHeight = 0;
    std::vector<std::string> externalFiles;  // buffer uris of a .gltf
    std::vector<std::string> extensionsUsed;
    // Primitives that are closed 2-manifolds with consistent winding, and their signed volume:
    // positive when the front faces point out, negative when they point in (an enclosure).
    std::vector<std::pair<std::string, double>> closedMeshes;
};

// Throws pmcr::Error("<path>: <problem>") at the first violation.
CheckReport checkScene(const std::filesystem::path& path);

// A short multi-line summary for the console.
std::string formatReport(const std::filesystem::path& path, const CheckReport& report);

}  // namespace pmcr::scenegen
