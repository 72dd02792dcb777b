// `pmcr render SCENE [options]`.
#pragma once

#include <filesystem>
#include <optional>

#include "cli/args.h"
#include "render/settings.h"

namespace pmcr::cli {

struct RenderCommand {
    std::filesystem::path scene;
    EnvironmentSpec environment;
    RenderSettings settings;
    std::optional<std::filesystem::path> output;
    std::optional<std::filesystem::path> png;
    bool noPng = false;
    float exposure = 0.0f;
    bool stats = false;
    bool verbose = false;        // print warnings as they come, not once the render goes ahead
    bool restrictPaths = false;  // the scene's files must lie in its folder (scene/gltf_loader.h)
};

RenderCommand parseRenderCommand(Args& args);
int runRender(const RenderCommand& command);
void printRenderHelp();

}  // namespace pmcr::cli
