// The catalogue of procedural scenes written by pmcr-scenegen (see scenes/README.md).
#pragma once

#include <string>
#include <vector>

#include "gltf_writer.h"

namespace pmcr::scenegen {

struct SceneEntry {
    std::string name;         // also the file stem: <name>.glb
    std::string description;  // one line, for --list
    SceneDesc (*build)();
};

const std::vector<SceneEntry>& sceneCatalog();

}  // namespace pmcr::scenegen
