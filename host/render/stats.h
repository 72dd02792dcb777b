// The stats JSON written beside every rendered image: what was rendered, how, on what device,
// for how long, and what the kernels did. `pmcr compare` and `pmcr merge` read it back.
#pragma once

#include <filesystem>

#include <nlohmann/json.hpp>

#include "render/session.h"

namespace pmcr {

nlohmann::json renderStats(RenderSession& session, const RenderOutput& output,
                           const std::filesystem::path& scenePath, double renderSeconds);

// `image.exr` -> `image.json`.
std::filesystem::path statsPathFor(const std::filesystem::path& image);

void writeJsonAtomically(const std::filesystem::path& path, const nlohmann::json& json);

}  // namespace pmcr
