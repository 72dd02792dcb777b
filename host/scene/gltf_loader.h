// glTF 2.0 scene loading (.gltf with external or data-URI resources, or .glb).
#pragma once

#include <filesystem>

#include "scene/environment.h"
#include "scene/scene.h"

namespace pmcr {

// Loads the default scene of a glTF 2.0 file: its triangles flattened to world space, materials
// (metallic-roughness plus KHR_materials_emissive_strength, _transmission, _ior, _volume), their
// textures (base colour, metallic-roughness, normal, emissive; alpha masks), KHR_lights_punctual
// lights and perspective cameras, then calls finalizeScene. Every index, range and
// value read is validated; bad input throws pmcr::Error "<file>: <problem>" (one line), input
// pmcr only partly supports gives one warning per kind.
// `environment` (--env), else the image the file's extras.pmcr.environment names (relative to
// the file), lights the scene too; a scene needs some light.
//
// External files (buffer and image uris, the environment image) are read relative to the
// scene's folder; a uri is never read as an absolute path. Relative paths may leave the folder
// ("../textures/wood.png", as real projects share files) unless options.restrictPaths is set.
struct SceneLoadOptions {
    // --restrict-paths: refuse any buffer, image or environment path that leaves the scene's
    // folder, symbolic links followed (for render farms that take scenes from others).
    bool restrictPaths = false;
};
Scene loadScene(const std::filesystem::path& path, const EnvironmentSpec& environment = {},
                const SceneLoadOptions& options = {});

}  // namespace pmcr
