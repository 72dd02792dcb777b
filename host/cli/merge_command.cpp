#include "cli/merge_command.h"

#include <cstdio>
#include <optional>

#include "core/error.h"
#include "metrics/merge.h"
#include "render/renderer.h"

namespace pmcr::cli {

namespace fs = std::filesystem;

void printMergeHelp() {
    std::printf(
        "usage: pmcr merge IMAGE IMAGE... -o OUT.exr [options]\n"
        "\n"
        "Averages independent renders of one scene, weighted by their sample counts (the\n"
        "\"samples\" of the stats JSON beside each image): a long reference can be rendered in\n"
        "pieces, each with its own --seed, on several machines or after an interruption, and\n"
        "merged. Refused unless the pieces share the scene, camera, method and settings and\n"
        "no two share a seed. Writes OUT (.exr or .pfm), its PNG preview and a stats JSON with\n"
        "the samples and times summed, the seeds, and the pieces under \"merged_from\".\n"
        "\n"
        "options:\n"
        "  -o, --output FILE    merged image (required)\n"
        "  --png FILE           PNG preview path (default: beside the output)\n"
        "  --no-png             no PNG preview\n"
        "  --exposure EV        PNG exposure in stops (default 0)\n"
        "  -q, --quiet          no messages\n");
}

int runMerge(Args& args) {
    std::vector<fs::path> inputs;
    std::optional<fs::path> output, png;
    bool noPng = false, quiet = false;
    float exposure = 0.0f;
    while (!args.done()) {
        const std::string a = args.next();
        if (a == "-o" || a == "--output")
            output = args.value(a);
        else if (a == "--png")
            png = args.value(a);
        else if (a == "--no-png")
            noPng = true;
        else if (a == "--exposure")
            exposure = float(parseDouble(a, args.value(a), -64, 64));
        else if (a == "--quiet" || a == "-q")
            quiet = true;
        else if (a.rfind("-", 0) == 0 && a.size() > 1)
            throw Error(a + ": unknown option for merge");
        else
            inputs.emplace_back(a);
    }
    if (!output)
        throw Error("merge: missing -o OUT.exr (see pmcr merge --help)");
    if (png && noPng)
        throw Error("--png and --no-png contradict each other");
    const OutputPaths paths = resolveOutputPaths(*output, output, png, noPng, exposure);
    std::vector<RenderPiece> pieces;
    for (const fs::path& p : inputs)
        pieces.push_back(readRenderPiece(p));
    MergedRender merged = mergeRenders(pieces);
    RenderResult result;
    result.output.image = std::move(merged.image);
    result.stats = std::move(merged.stats);
    writeRenderOutputs(result, paths);
    if (!quiet)
        std::fprintf(stderr, "merged %zu renders, %.4g spp -> %s\n", pieces.size(),
                     result.stats["spp"].get<double>(), paths.hdr.string().c_str());
    return 0;
}

}  // namespace pmcr::cli
