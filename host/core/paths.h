// Whether a file lies inside a folder, for `--restrict-paths` (scene/gltf_loader.h): the scene's
// buffers, images and environment must not leave the scene's folder.
#pragma once

#include <filesystem>

namespace pmcr {

// True when `path` names something strictly inside `folder` once both are made absolute and
// resolved: `..` components and symbolic links (those that exist) followed, so that neither
// "../../etc/passwd" nor a link inside the folder that points out of it counts as inside. False
// on any filesystem error.
bool isInsideFolder(const std::filesystem::path& path, const std::filesystem::path& folder);

}  // namespace pmcr
