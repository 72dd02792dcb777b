#include "render/renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "core/error.h"
#include "core/log.h"
#include "core/process_clock.h"
#include "image/image.h"
#include "render/methods.h"
#include "render/stats.h"
#include "vk/context.h"

namespace pmcr {

void resolveImageSize(const Scene& scene, RenderSettings& s) {
    // Checked here, before any device is opened: a bad --camera is the only line printed.
    if (s.camera < 0 || s.camera >= int(scene.cameras.size()))
        fail(scene.path.string(), "--camera " + std::to_string(s.camera) +
                                      " out of range (the scene has " +
                                      std::to_string(scene.cameras.size()) + " camera(s))");
    const int maxSize = 16384;
    float aspect = 4.0f / 3.0f;
    if (scene.cameras[size_t(s.camera)].aspect > 0.0f)
        aspect = scene.cameras[size_t(s.camera)].aspect;
    if (s.paperSize) {
        if (s.width != 0 || s.height != 0) throw Error("--paper-size and --width/--height contradict each other");
        if (scene.paperWidth == 0) fail(scene.path.string(), "--paper-size: the scene names no paper size");
        s.width = scene.paperWidth;
        s.height = scene.paperHeight;
    }
    if (s.width == 0 && s.height == 0) {
        if (scene.defaultWidth > 0 && scene.defaultHeight > 0) {
            s.width = scene.defaultWidth;
            s.height = scene.defaultHeight;
        } else {
            s.width = 640;
        }
    }
    if (s.height == 0) s.height = std::max(1, int(std::lround(float(s.width) / aspect)));
    if (s.width == 0) s.width = std::max(1, int(std::lround(float(s.height) * aspect)));
    if (s.width > maxSize || s.height > maxSize)
        throw Error("image size " + std::to_string(s.width) + "x" + std::to_string(s.height) +
                    " exceeds " + std::to_string(maxSize) + " pixels per side");
}

RenderResult renderScene(vk::Context& context, const Scene& scene, const RenderSettings& settings,
                         Communicator& comm) {
    validateMethodOptions(settings);
    const MethodInfo* method = findMethod(settings.method);
    auto integrator = method->create(settings);
    RenderSession session(context, scene, settings, settings.width, settings.height, comm);
    // The scene is on the device and the render goes ahead: print the messages `pmcr render`
    // held while it checked the input (core/log.h), before the progress bar.
    log::release();
    auto start = std::chrono::steady_clock::now();
    RenderResult result;
    result.output = integrator->render(session);
    result.samplingSeconds = session.elapsedSeconds();
    result.clockStart = std::chrono::steady_clock::now() -
                        std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                            std::chrono::duration<double>(result.samplingSeconds));
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() -
                     session.snapshotOverheadSeconds();
    result.interrupted = session.interrupted();
    result.snapshots = session.takeSnapshots();
    result.stats =
        renderStats(session, result.output, scene.path, result.seconds, result.samplingSeconds);
    return result;
}

OutputPaths resolveOutputPaths(const std::filesystem::path& scene,
                               const std::optional<std::filesystem::path>& output,
                               const std::optional<std::filesystem::path>& png, bool noPng,
                               float exposure) {
    namespace fs = std::filesystem;
    OutputPaths paths;
    paths.exposure = exposure;
    paths.hdr = output ? *output : fs::path(scene.stem().string() + ".exr");
    const std::string ext = paths.hdr.extension().string();
    if (ext != ".exr" && ext != ".pfm")
        fail(paths.hdr.string(), "output must end in .exr or .pfm");
    auto checkDirectory = [](const fs::path& file) {
        fs::path dir = file.parent_path().empty() ? fs::path(".") : file.parent_path();
        std::error_code ec;
        if (!fs::is_directory(dir, ec)) fail(file.string(), "output directory does not exist");
    };
    checkDirectory(paths.hdr);
    if (!noPng) {
        paths.png = png ? *png : fs::path(paths.hdr).replace_extension(".png");
        if (paths.png->extension() != ".png") fail(paths.png->string(), "--png must end in .png");
        checkDirectory(*paths.png);
    }
    paths.stats = statsPathFor(paths.hdr);
    return paths;
}

std::vector<std::filesystem::path> writeRenderOutputs(const RenderResult& result,
                                                      const OutputPaths& paths) {
    std::vector<std::filesystem::path> written;
    writeHdr(paths.hdr, result.output.image);
    written.push_back(paths.hdr);
    if (paths.png) {
        writePng(*paths.png, result.output.image, paths.exposure);
        written.push_back(*paths.png);
    }
    for (const auto& [suffix, image] : result.output.diagnostics) {
        std::filesystem::path hdr = paths.hdr;
        hdr.replace_extension("." + suffix + paths.hdr.extension().string());
        writeHdr(hdr, image);
        written.push_back(hdr);
    }
    nlohmann::json stats = result.stats;
    if (result.clockStart != std::chrono::steady_clock::time_point{}) {  // not `pmcr merge`
        stats["written_seconds"] =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - result.clockStart).count();
        stats["wall_seconds"] = processSeconds();
    }
    writeJsonAtomically(paths.stats, stats);
    written.push_back(paths.stats);
    return written;
}

}  // namespace pmcr
