// pmcr-scenegen: writes pmcr's scenes as glTF files and validates them.
//   pmcr-scenegen [--assets DIR] <output-dir> [scene-name...]
//       write the named scenes (all if none), then check them; scenes built from third-party
//       files read them from DIR and are skipped when all scenes are written without it
//   pmcr-scenegen --check <file.glb|file.gltf>...   check existing files
//   pmcr-scenegen --list                             list the scenes
//   pmcr-scenegen --sky <file.exr>                   write the clear afternoon sky (sky.h)
//   pmcr-scenegen --on-ground <model.glb> <out.glb> <sky>   a sample model on a ground plane
//                                                    under the sky file <sky> (on_ground.h)
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "core/error.h"
#include "gltf_check.h"
#include "gltf_writer.h"
#include "image/image.h"
#include "on_ground.h"
#include "scene/gltf_loader.h"
#include "scenes.h"
#include "sky.h"

namespace {

void usage() {
    std::fprintf(stderr,
                 "usage: pmcr-scenegen [--assets DIR] <output-dir> [scene-name...]\n"
                 "       pmcr-scenegen --check <file.glb|file.gltf>...\n"
                 "       pmcr-scenegen --list\n"
                 "       pmcr-scenegen --sky <file.exr>\n"
                 "       pmcr-scenegen --on-ground <model.glb> <out.glb> <sky.exr>\n");
}

int run(std::vector<std::string> args) {
    using namespace pmcr::scenegen;
    if (args.empty()) {
        usage();
        return 2;
    }
    if (args[0] == "--list") {
        for (const auto& entry : sceneCatalog()) {
            std::printf("%-20s %s%s\n", entry.name.c_str(), entry.description.c_str(),
                        entry.asset.empty() ? "" : (" [needs " + entry.asset + "]").c_str());
        }
        return 0;
    }
    if (args[0] == "--sky") {
        if (args.size() != 2) {
            usage();
            return 2;
        }
        pmcr::writeHdr(args[1], preethamSky(SkyParams{}));
        std::printf("%s\n", args[1].c_str());
        return 0;
    }
    if (args[0] == "--on-ground") {
        if (args.size() != 4) {
            usage();
            return 2;
        }
        // The model keeps its own node transforms, which --check (made for the generator's
        // flat scenes) refuses: pmcr's loader validates the file instead.
        placeOnGround(args[1], args[2], args[3]);
        const pmcr::Scene scene = pmcr::loadScene(args[2]);
        std::printf("%s: %zu triangles, %zu materials, %zu textures\n", args[2].c_str(),
                    scene.triangles.size(), scene.materials.size(), scene.textures.size());
        return 0;
    }
    if (args[0] == "--check") {
        if (args.size() < 2) {
            usage();
            return 2;
        }
        for (size_t i = 1; i < args.size(); ++i) {
            std::printf("%s\n", formatReport(args[i], checkScene(args[i])).c_str());
        }
        return 0;
    }
    SceneContext context;
    if (args[0] == "--assets") {
        if (args.size() < 3) {
            usage();
            return 2;
        }
        context.assets = args[1];
        args.erase(args.begin(), args.begin() + 2);
    }
    if (args[0].starts_with("-")) {
        usage();
        return 2;
    }

    const std::filesystem::path outDir = args[0];
    std::vector<const SceneEntry*> selected;
    for (size_t i = 1; i < args.size(); ++i) {
        const SceneEntry* found = nullptr;
        for (const auto& entry : sceneCatalog()) {
            if (entry.name == args[i])
                found = &entry;
        }
        if (!found)
            pmcr::fail("", "unknown scene '" + args[i] + "' (see --list)");
        if (!found->asset.empty() && context.assets.empty())
            pmcr::fail("", "scene '" + args[i] + "' needs --assets (" + found->asset + ")");
        selected.push_back(found);
    }
    if (selected.empty()) {
        for (const auto& entry : sceneCatalog()) {
            if (!entry.asset.empty() && context.assets.empty()) {
                std::fprintf(stderr, "pmcr-scenegen: skipping %s: needs --assets (%s)\n",
                             entry.name.c_str(), entry.asset.c_str());
                continue;
            }
            selected.push_back(&entry);
        }
    }
    std::error_code ec;
    std::filesystem::create_directories(outDir, ec);
    if (ec)
        pmcr::fail(outDir.string(), "cannot create directory: " + ec.message());
    for (const SceneEntry* entry : selected) {
        const auto path = writeScene(entry->build(context), outDir);
        std::printf("%s\n", formatReport(path, checkScene(path)).c_str());
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        return run(std::vector<std::string>(argv + 1, argv + argc));
    } catch (const pmcr::Error& e) {
        std::fprintf(stderr, "pmcr-scenegen: %s\n", e.what());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "pmcr-scenegen: %s\n", e.what());
    }
    return 1;
}
