// Rendering a loaded scene with one method, and writing what it produced. Shared by
// `pmcr render`, `pmcr bench` and the tests, so all three run exactly the same path.
#pragma once

#include <chrono>
#include <filesystem>
#include <optional>

#include <nlohmann/json.hpp>

#include "render/session.h"
#include "render/settings.h"
#include "scene/scene.h"

namespace pmcr {

struct RenderResult {
    RenderOutput output;
    nlohmann::json stats;
    double seconds = 0.0;          // wall time of the method, kernel creation included
    double samplingSeconds = 0.0;  // the render clock (RenderSession::startClock) at the end
    // When the render clock would read 0 (snapshot overhead taken off): writeRenderOutputs
    // adds the clock at the image written (what --time limits) to the stats.
    std::chrono::steady_clock::time_point clockStart{};
    bool interrupted = false;
    std::vector<Snapshot> snapshots;  // settings.snapshotSeconds / snapshotSpp, in order
};

// Fills in width/height: explicit values win; else the scene's default size; else 640 wide at
// the camera's aspect ratio (4:3 when the file gives none). Only one given: the other follows
// the aspect ratio. Throws pmcr::Error when settings.camera is not one of the scene's cameras.
void resolveImageSize(const Scene& scene, RenderSettings& settings);

// Renders `scene` with settings.method on `context` (settings must have a resolved size): this
// process's share of the render when `comm` has several ranks (render/distributed.h).
RenderResult renderScene(vk::Context& context, const Scene& scene, const RenderSettings& settings,
                         Communicator& comm = localCommunicator());

struct OutputPaths {
    std::filesystem::path hdr;                  // .exr or .pfm
    std::optional<std::filesystem::path> png;   // tonemapped preview
    std::filesystem::path stats;                // JSON beside hdr
    float exposure = 0.0f;
};

// Default paths named after the scene: `<scene stem>.exr` (+ .png, .json) in the current
// directory unless --output/--png say otherwise. Fails early (before any rendering) when the
// output directory does not exist or the extension is not .exr/.pfm.
OutputPaths resolveOutputPaths(const std::filesystem::path& scene,
                               const std::optional<std::filesystem::path>& output,
                               const std::optional<std::filesystem::path>& png, bool noPng,
                               float exposure);

// Writes the HDR image, its PNG, the diagnostics (`<stem>.<suffix>.exr` and .png) and the stats
// JSON, each atomically; the JSON gets `written_seconds` (the render clock when the images were
// written) and `wall_seconds` (the process's time then). Returns the paths written.
std::vector<std::filesystem::path> writeRenderOutputs(const RenderResult& result,
                                                      const OutputPaths& paths);

}  // namespace pmcr
