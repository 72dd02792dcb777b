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

// A number in a stats JSON, 0 when it is absent: as a double, or as an unsigned count.
double statsNumber(const nlohmann::json& stats, const char* key);
uint64_t statsCount(const nlohmann::json& stats, const char* key);

// What several renders' stats add up to (`pmcr merge`'s pieces, the ranks of an MPI render):
// rays, NaN samples dropped, GPU time and the per-kernel totals ("gpu_kernels").
struct StatsTotals {
    uint64_t rays = 0;
    uint64_t nanDropped = 0;
    double gpuMilliseconds = 0.0;
    nlohmann::json kernels = nlohmann::json::object();

    void add(const nlohmann::json& stats);
    // Into `stats`, with rays per second over `renderSeconds`.
    void writeTo(nlohmann::json& stats, double renderSeconds) const;
};

// `image.exr` -> `image.json`.
std::filesystem::path statsPathFor(const std::filesystem::path& image);

void writeJsonAtomically(const std::filesystem::path& path, const nlohmann::json& json);

}  // namespace pmcr
