// A glTF sample model set on a ground plane under the afternoon sky: the model's file is copied
// unchanged (meshes, materials, textures as they are encoded) and given a grey Lambertian ground
// square under its lowest point, a camera framing it from the front and above, and
// extras.pmcr.environment naming the sky, so that `pmcr render` shows it as a user would stage
// it. The sky is written by `pmcr-scenegen --sky`.
#pragma once

#include <filesystem>
#include <string>

namespace pmcr::scenegen {

// Reads `model` (.glb), writes `out` (.glb) lit by `environment` (a file name beside `out`).
// Throws pmcr::Error naming the file on failure.
void placeOnGround(const std::filesystem::path& model, const std::filesystem::path& out,
                   const std::string& environment);

}  // namespace pmcr::scenegen
