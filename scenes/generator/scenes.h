// The catalogue of scenes written by pmcr-scenegen (see scenes/README.md).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "gltf_writer.h"

namespace pmcr::scenegen {

// What a scene's build function may read: the folder of converted third-party files
// (meshes/stanford_dragon_res2.glb, rooms/veach_bidir.glb, direct/veach_mis.glb; see
// scenes/README.md). Empty when none was given.
struct SceneContext {
    std::filesystem::path assets;
};

struct SceneEntry {
    std::string name;         // also the file stem: <name>.glb or <name>.gltf
    std::string description;  // one line, for --list
    SceneDesc (*build)(const SceneContext&);
    std::string asset;  // the file under SceneContext::assets it needs; empty: none
};

const std::vector<SceneEntry>& sceneCatalog();

// Scenes defined in other files, one function each.
SceneDesc checkersTwoLights(const SceneContext&);
SceneDesc plantShadows(const SceneContext&);
SceneDesc glassCausticTorus(const SceneContext&);
SceneDesc skySpheres(const SceneContext&);
SceneDesc skyMaterials(const SceneContext&);
SceneDesc lampRoom(const SceneContext&);
SceneDesc dragonDirect(const SceneContext& context);
SceneDesc dragonCaustic(const SceneContext& context);
SceneDesc veachMis(const SceneContext& context);
SceneDesc room(const SceneContext& context);

}  // namespace pmcr::scenegen
