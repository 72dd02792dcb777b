// Reads a third-party scene converted to .glb (the files listed in scenes/README.md, "Sources")
// so that a scene can re-emit its geometry: every triangle primitive of every mesh as a Mesh.
// The converted files place meshes by nodes without transforms, so their positions are world
// space; a node transform or an unsupported layout is an error naming the file.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "mesh.h"

namespace pmcr::scenegen {

struct SourcePrimitive {
    std::string meshName;
    int material = -1;  // index into the source's materials
    Mesh mesh;          // positions, normals when present, u32 indices
};

struct SourceGlb {
    nlohmann::json json;
    std::vector<SourcePrimitive> primitives;  // in mesh order
};

SourceGlb readSourceGlb(const std::filesystem::path& path);

// The primitive of the source mesh named `meshName`; throws pmcr::Error if there is none.
const SourcePrimitive& sourcePrimitive(const SourceGlb& source, const std::string& meshName,
                                       const std::filesystem::path& path);

}  // namespace pmcr::scenegen
