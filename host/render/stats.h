// The stats JSON written beside every rendered image: what was rendered, how, on what device,
// for how long, and what the kernels did. `pmcr compare` and `pmcr merge` read it back.
#pragma once

#include <filesystem>

#include <nlohmann/json.hpp>

#include "render/session.h"

namespace pmcr {

// renderSeconds: wall time of the method (kernel creation included); samplingSeconds: the render
// clock, from the method's first sample to its end (what --time limits and `pmcr bench` reports).
nlohmann::json renderStats(RenderSession& session, const RenderOutput& output,
                           const std::filesystem::path& scenePath, double renderSeconds,
                           double samplingSeconds);

// Adds a stats JSON's "gpu_kernels" ({name: {milliseconds, dispatches}}) into `totals`
// (`pmcr merge` and the ranks of an MPI render).
void addKernelTotals(nlohmann::json& totals, const nlohmann::json& kernels);

// `image.exr` -> `image.json`.
std::filesystem::path statsPathFor(const std::filesystem::path& image);

void writeJsonAtomically(const std::filesystem::path& path, const nlohmann::json& json);

}  // namespace pmcr
