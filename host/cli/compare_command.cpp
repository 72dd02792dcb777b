#include "cli/compare_command.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>

#include <nlohmann/json.hpp>

#include "bench/bench.h"
#include "bench/report.h"
#include "core/error.h"
#include "core/interrupt.h"
#include "core/log.h"
#include "image/colormap.h"
#include "metrics/merge.h"
#include "metrics/metrics.h"
#include "render/methods.h"
#include "render/renderer.h"
#include "render/stats.h"
#include "scene/gltf_loader.h"
#include "vk/context.h"

namespace pmcr::cli {

namespace {

namespace fs = std::filesystem;

nlohmann::json finiteOrNull(double v) {
    return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json();
}

// The render time recorded beside an image: its stats' "sampling_seconds" (the render clock),
// else "render_seconds". Sets `source` to the stats file when found.
std::optional<double> recordedTime(const fs::path& image, std::string& source) {
    const fs::path statsPath = statsPathFor(image);
    std::error_code ec;
    if (!fs::exists(statsPath, ec))
        return std::nullopt;
    std::ifstream in(statsPath);
    const nlohmann::json stats = nlohmann::json::parse(in, nullptr, false);
    if (stats.is_discarded() || !stats.is_object())
        fail(statsPath.string(), "not a pmcr stats JSON object (or give --time)");
    for (const char* key : {"sampling_seconds", "render_seconds"}) {
        if (auto it = stats.find(key);
            it != stats.end() && it->is_number() && it->get<double>() > 0.0) {
            source = statsPath.string() + " " + key;
            return it->get<double>();
        }
    }
    return std::nullopt;
}

}  // namespace

void printCompareHelp() {
    std::printf(
        "usage: pmcr compare IMAGE REFERENCE [options]\n"
        "\n"
        "Measures IMAGE against REFERENCE (EXR or PFM, the same size) with the papers' metrics:\n"
        "  Err     luminance MSE: mean over pixels of e^2, e = Y - Y_ref (Rec. 709 luminance)\n"
        "  MSE RGB the same per channel\n"
        "  RMSE    sqrt(Err)\n"
        "  relMSE  mean over pixels and channels of (v - r)^2 / (r + 0.01)^2 (pbrt-v4's MRSE)\n"
        "  P-Err   mean of e^2 / tvi(Y_ref), Fan et al.'s perceptual Err with Ferwerda et al.\n"
        "          1996's threshold-versus-intensity\n"
        "  Eff     1 / (T Err) and P-Eff 1 / (T P-Err), when the render time T is known\n"
        "\n"
        "options:\n"
        "  --time SECONDS       render time T (default: \"sampling_seconds\" from the stats JSON\n"
        "                       beside IMAGE, else its \"render_seconds\"; none: no Eff)\n"
        "  --crop x,y,w,h       measure only this rectangle (top-left x, y; width, height)\n"
        "  --error-image FILE   write |e| in false colour (viridis) as a PNG (of the crop, if "
        "any)\n"
        "  --error-max V        |e| shown as full scale (default: the 99th percentile)\n"
        "  --display-white CD   cd/m^2 that pixel luminance 1 stands for in tvi (default %g)\n"
        "  --json               print one JSON object: mse, mse_rgb, rmse, relmse, pmse, region,\n"
        "                       display_white and, with a time, time, eff, peff\n",
        kDefaultDisplayWhite);
}

int runCompare(Args& args) {
    std::vector<fs::path> files;
    MetricOptions options;
    std::optional<double> time;
    std::optional<fs::path> errorImage;
    std::optional<double> errorMax;
    bool json = false;
    while (!args.done()) {
        const std::string a = args.next();
        if (a == "--time")
            time = parseDouble(a, args.value(a), 1e-9, 1e9);
        else if (a == "--crop") {
            options.cropped = true;
            options.crop = parsePixelRect(a, args.value(a));
        } else if (a == "--error-image")
            errorImage = args.value(a);
        else if (a == "--error-max")
            errorMax = parseDouble(a, args.value(a), 1e-30, 1e30);
        else if (a == "--display-white")
            options.displayWhite = parseDouble(a, args.value(a), 1e-6, 1e9);
        else if (a == "--json")
            json = true;
        else if (a.rfind("-", 0) == 0 && a.size() > 1)
            throw Error(a + ": unknown option for compare");
        else
            files.emplace_back(a);
    }
    if (files.size() != 2)
        throw Error("compare: expected IMAGE REFERENCE, got " + std::to_string(files.size()) +
                    " file(s) (see pmcr compare --help)");
    if (errorImage && errorImage->extension() != ".png")
        fail(errorImage->string(), "--error-image must end in .png");
    const Image image = readHdr(files[0]);
    const Image reference = readHdr(files[1]);
    options.imageName = files[0].string();
    options.referenceName = files[1].string();
    const ErrorMetrics m = measureError(image, reference, options);
    std::string timeSource = "--time";
    if (!time)
        time = recordedTime(files[0], timeSource);

    if (errorImage) {
        const PixelRect& r = m.region;
        const Image a = crop(image, r.x, r.y, r.width, r.height);
        const Image b = crop(reference, r.x, r.y, r.width, r.height);
        MetricOptions names = options;
        names.cropped = false;
        const std::vector<float> map = luminanceErrorMap(a, b, names);
        float scale = errorMax ? float(*errorMax) : quantile(map, 0.99);
        if (!(scale > 0.0f))
            scale = 1.0f;
        writePng(*errorImage, falseColor(map, r.width, r.height, scale));
    }

    if (json) {
        nlohmann::json j = {{"image", files[0].string()},
                            {"reference", files[1].string()},
                            {"region",
                             {{"x", m.region.x},
                              {"y", m.region.y},
                              {"width", m.region.width},
                              {"height", m.region.height}}},
                            {"mse", m.mse},
                            {"mse_rgb", {m.mseRgb.r, m.mseRgb.g, m.mseRgb.b}},
                            {"rmse", m.rmse},
                            {"relmse", m.relmse},
                            {"pmse", m.pmse},
                            {"display_white", options.displayWhite}};
        if (time) {
            j["time"] = *time;
            j["time_source"] = timeSource;
            j["eff"] = finiteOrNull(efficiency(*time, m.mse));
            j["peff"] = finiteOrNull(efficiency(*time, m.pmse));
        }
        std::printf("%s\n", j.dump(2).c_str());
        return 0;
    }
    std::printf("image       %s\n", files[0].string().c_str());
    std::printf("reference   %s\n", files[1].string().c_str());
    std::printf("region      %dx%d at (%d, %d)%s\n", m.region.width, m.region.height, m.region.x,
                m.region.y, options.cropped ? "" : " (whole image)");
    std::printf("Err         %.6e  (luminance MSE)\n", m.mse);
    std::printf("MSE R G B   %.6e %.6e %.6e\n", m.mseRgb.r, m.mseRgb.g, m.mseRgb.b);
    std::printf("RMSE        %.6e\n", m.rmse);
    std::printf("relMSE      %.6e\n", m.relmse);
    std::printf("P-Err       %.6e  (display white %g cd/m^2)\n", m.pmse, options.displayWhite);
    if (time) {
        std::printf("time        %.4g s  (%s)\n", *time, timeSource.c_str());
        std::printf("Eff         %.6g\n", efficiency(*time, m.mse));
        std::printf("P-Eff       %.6g\n", efficiency(*time, m.pmse));
    } else {
        std::printf("time        unknown (no stats JSON beside the image; give --time for Eff)\n");
    }
    if (errorImage)
        std::printf("wrote       %s\n", errorImage->string().c_str());
    return 0;
}

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

void printBenchHelp() {
    std::printf(
        "usage: pmcr bench SCENE --methods M1,M2,... (--time SECONDS | --budget-spp N)\n"
        "                  (--reference REF.exr | --reference-spp N) --out DIR [options]\n"
        "\n"
        "Runs each method on SCENE for the same render time (and/or sample budget), one after\n"
        "the other on one device, measures each against the reference and writes DIR/report.html,\n"
        "DIR/report.md and DIR/results.json: the papers' table (time, samples, Err, Eff, P-Err,\n"
        "P-Eff and efficiency ratios to the first method), the images side by side at one\n"
        "exposure, error images at one scale, crops, the methods' diagnostic images and plots of\n"
        "Err and P-Err against time (SVG). The table is printed too. Methods not implemented yet\n"
        "are listed as such. Time is the render clock: from a method's first sample to its end,\n"
        "without scene upload, BVH build, kernel compilation or the convergence snapshots.\n"
        "\n"
        "options:\n"
        "  --methods LIST       comma-separated methods; options after colons, e.g.\n"
        "                       pt,direct:light-samples=4 (see pmcr render --help for methods)\n"
        "  --time SECONDS       render time per method\n"
        "  --budget-spp N       samples per pixel per method (with --time: whichever ends first)\n"
        "  --reference FILE     the reference (EXR/PFM), e.g. a long pt render or a pmcr merge;\n"
        "                       its size sets the image size. Refused if its stats JSON lists the\n"
        "                       bench's seed (the methods would share its samples)\n"
        "  --reference-spp N    without --reference: render one with pt at N spp and a seed of\n"
        "                       its own (written to DIR/reference.exr, and said so in the report)\n"
        "  --out DIR            report directory; written whole or not at all. An existing DIR is\n"
        "                       replaced only if it is empty or an earlier report\n"
        "  --crop x,y,w,h       a region to zoom on and measure (repeatable)\n"
        "  --exposure EV        PNG exposure for every image (default: the reference's mean\n"
        "                       luminance at 18%% grey, log2(0.18 / mean))\n"
        "  --display-white CD   cd/m^2 of pixel luminance 1 for tvi (default %g)\n"
        "  --snapshots N        convergence points per method before the last: at budget / 2^k,\n"
        "                       k = 1..N (default 8)\n"
        "  --width W --height H --seed S --max-depth D --rr-depth D --camera N\n"
        "                       as for render (default seed 1; size: the reference's)\n"
        "  --device ID  --validate  -q, --quiet\n",
        kDefaultDisplayWhite);
}

int runBench(Args& args) {
    BenchOptions o;
    RenderSettings& s = o.base;
    std::optional<fs::path> scenePath, out;
    while (!args.done()) {
        const std::string a = args.next();
        if (a == "--methods")
            o.methods = parseBenchMethods(a, args.value(a));
        else if (a == "--time")
            s.timeLimit = parseDouble(a, args.value(a), 1e-3, 1e7);
        else if (a == "--budget-spp")
            s.spp = parseUint(a, args.value(a), 1, 1u << 30);
        else if (a == "--reference")
            o.reference = args.value(a);
        else if (a == "--reference-spp")
            o.referenceSpp = parseUint(a, args.value(a), 1, 1u << 30);
        else if (a == "--out")
            out = args.value(a);
        else if (a == "--crop")
            o.crops.push_back(parsePixelRect(a, args.value(a)));
        else if (a == "--exposure")
            o.exposure = float(parseDouble(a, args.value(a), -64, 64));
        else if (a == "--display-white")
            o.displayWhite = parseDouble(a, args.value(a), 1e-6, 1e9);
        else if (a == "--snapshots")
            o.snapshots = parseInt(a, args.value(a), 0, 30);
        else if (a == "--width")
            s.width = parseInt(a, args.value(a), 1, 16384);
        else if (a == "--height")
            s.height = parseInt(a, args.value(a), 1, 16384);
        else if (a == "--seed")
            s.seed = parseUint(a, args.value(a), 0, 0xffffffffu);
        else if (a == "--max-depth")
            s.maxDepth = parseUint(a, args.value(a), 1, 1024);
        else if (a == "--rr-depth")
            s.rrDepth = parseUint(a, args.value(a), 1, 1024);
        else if (a == "--camera")
            s.camera = parseInt(a, args.value(a), 0, 1 << 20);
        else if (a == "--device")
            s.device = args.value(a);
        else if (a == "--validate")
            s.validate = true;
        else if (a == "--quiet" || a == "-q")
            s.quiet = true;
        else if (a.rfind("-", 0) == 0 && a.size() > 1)
            throw Error(a + ": unknown option for bench");
        else if (!scenePath)
            scenePath = a;
        else
            throw Error(a + ": unexpected argument (one scene per bench)");
    }
    if (!scenePath)
        throw Error("bench: missing SCENE (a .gltf or .glb file)");
    if (o.methods.empty())
        throw Error("bench: missing --methods (e.g. --methods pt,direct)");
    if (s.timeLimit <= 0.0 && s.spp == 0)
        throw Error("bench: give a budget: --time SECONDS and/or --budget-spp N");
    if (!out)
        throw Error("bench: missing --out DIR");
    if (o.reference && o.referenceSpp > 0)
        throw Error("--reference and --reference-spp contradict each other");
    if (!o.reference && o.referenceSpp == 0)
        throw Error("bench: give --reference REF.exr, or --reference-spp N to render one");
    checkBenchOutputDir(*out);
    log::setQuiet(s.quiet);
    Scene scene = loadScene(*scenePath);
    BenchReport report = prepareBench(scene, o);

    vk::ContextOptions contextOptions;
    contextOptions.validate = s.validate;
    contextOptions.device = s.device;
    vk::Context context(contextOptions);
    log::info("device: " + context.deviceName() + " (" + context.deviceTypeName() + ")");

    installInterruptHandler();
    runBench(context, scene, report);
    if (report.interrupted) {
        std::fprintf(stderr, "pmcr: bench interrupted; no report written\n");
        return 130;
    }
    const auto messages = context.validationMessages();
    if (!messages.empty())
        throw Error("validation layer reported " + std::to_string(messages.size()) + " message(s)");
    writeBenchReport(report, *out);
    std::printf("%s: %dx%d, reference %s\n", scene.path.filename().string().c_str(), report.width,
                report.height, report.referenceInfo.value("path", "").c_str());
    std::printf("%s", benchTableText(report).c_str());
    if (!s.quiet)
        std::fprintf(stderr, "wrote %s\n", (*out / "report.html").string().c_str());
    return 0;
}

}  // namespace pmcr::cli
