#include "cli/bench_command.h"

#include <cstdio>
#include <optional>

#include "bench/bench.h"
#include "bench/report.h"
#include "core/error.h"
#include "core/interrupt.h"
#include "core/log.h"
#include "scene/gltf_loader.h"
#include "vk/context.h"

namespace pmcr::cli {

namespace fs = std::filesystem;

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
        "%s"
        "  --device ID  --validate  -q, --quiet  --verbose\n",
        kDefaultDisplayWhite, kEnvironmentHelp);
}

int runBench(Args& args) {
    BenchOptions o;
    RenderSettings& s = o.base;
    std::optional<fs::path> scenePath, out;
    EnvironmentSpec environment;
    bool verbose = false;
    while (!args.done()) {
        const std::string a = args.next();
        if (parseEnvironmentOption(a, args, environment))
            continue;
        else if (a == "--methods")
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
        else if (a == "--verbose")
            verbose = true;
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
    // As for render: the warnings of loading wait until a method renders (renderScene), so
    // that bad input is one line (core/log.h).
    if (!verbose)
        log::hold();
    checkEnvironmentOptions(environment);
    Scene scene = loadScene(*scenePath, environment);
    BenchReport report = prepareBench(scene, o);

    vk::ContextOptions contextOptions;
    contextOptions.validate = s.validate;
    contextOptions.device = s.device;
    vk::Context context(contextOptions);
    log::info("device: " + context.deviceName() + " (" + context.deviceTypeName() + ")");

    installInterruptHandler();
    pmcr::runBench(context, scene, report);
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
