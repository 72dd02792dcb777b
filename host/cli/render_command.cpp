#include "cli/render_command.h"

#include <algorithm>
#include <cstdio>

#include "core/communicator.h"
#include "core/error.h"
#include "core/interrupt.h"
#include "core/log.h"
#include "render/distributed.h"
#include "render/methods.h"
#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "vk/context.h"

namespace pmcr::cli {

RenderCommand parseRenderCommand(Args& args) {
    RenderCommand c;
    RenderSettings& s = c.settings;
    bool sceneSeen = false;
    while (!args.done()) {
        const std::string a = args.next();
        if (a == "--method") s.method = args.value(a);
        else if (a == "--spp") s.spp = parseUint(a, args.value(a), 1, 1u << 30);
        else if (a == "--time") s.timeLimit = parseDouble(a, args.value(a), 1e-3, 1e7);
        else if (a == "--width") s.width = parseInt(a, args.value(a), 1, 16384);
        else if (a == "--height") s.height = parseInt(a, args.value(a), 1, 16384);
        else if (a == "--paper-size") s.paperSize = true;
        else if (a == "--seed") s.seed = parseUint(a, args.value(a), 0, 0xffffffffu);
        else if (a == "--max-depth") s.maxDepth = parseUint(a, args.value(a), 1, 1024);
        else if (a == "--rr-depth") s.rrDepth = parseUint(a, args.value(a), 1, 1024);
        else if (a == "--camera") s.camera = parseInt(a, args.value(a), 0, 1 << 20);
        else if (a == "-o" || a == "--output") c.output = args.value(a);
        else if (a == "--png") c.png = args.value(a);
        else if (a == "--no-png") c.noPng = true;
        else if (a == "--exposure") c.exposure = float(parseDouble(a, args.value(a), -64, 64));
        else if (a == "--device") s.device = args.value(a);
        else if (a == "--validate") s.validate = true;
        else if (a == "--stats") c.stats = true;
        else if (a == "--quiet" || a == "-q") s.quiet = true;
        else if (a == "--verbose") c.verbose = true;
        else if (a == "--restrict-paths") c.restrictPaths = true;
        else if (parseEnvironmentOption(a, args, c.environment)) continue;
        else if (a.rfind("--", 0) == 0 && a.size() > 2) {
            // A method's option. Check the name before taking a value, so that an unknown flag
            // is named as such instead of swallowing the next argument.
            const std::string name = a.substr(2);
            bool known = false;
            for (const auto& m : methods())
                for (const auto& o : m.options) known = known || o.name == name;
            if (!known) throw Error(a + ": unknown option (see pmcr render --help)");
            s.options[name] = args.value(a);
        }
        else if (a.rfind("-", 0) == 0 && a.size() > 1) throw Error(a + ": unknown option");
        else if (!sceneSeen) {
            c.scene = a;
            sceneSeen = true;
        } else {
            throw Error(a + ": unexpected argument (one scene per render)");
        }
    }
    if (!sceneSeen) throw Error("render: missing SCENE (a .gltf or .glb file)");
    checkEnvironmentOptions(c.environment);
    if (c.png && c.noPng) throw Error("--png and --no-png contradict each other");
    validateMethodOptions(s);
    // Creating the integrator parses its option values and touches no device: a bad value
    // fails here, as one line, before the device is opened.
    findMethod(s.method)->create(s);
    return c;
}

int runRender(const RenderCommand& command) {
    // Under mpirun, every rank runs this with its share of the render; rank 0 alone reports,
    // shows progress and writes (render/distributed.h). Without MPI: one rank, the whole render.
    Communicator& comm = worldCommunicator();
    RenderSettings requested = command.settings;
    requested.quiet = requested.quiet || comm.rank() > 0;
    log::setQuiet(requested.quiet);
    // Bad input is one line on stderr: the warnings of loading and the device line wait until
    // the render goes ahead (renderScene releases them; an error discards them, cli.cpp), unless
    // --verbose asks for them as they come.
    if (!command.verbose) log::hold();
    RenderSettings settings;
    OutputPaths paths;
    Scene scene;
    // Bad input fails before anything renders, alike on every rank. Check the outputs first: a
    // bad path fails at once.
    onEveryRank(comm, [&] {
        paths = resolveOutputPaths(command.scene, command.output, command.png, command.noPng,
                                   command.exposure);
        scene = loadScene(command.scene, command.environment, {command.restrictPaths});
        resolveImageSize(scene, requested);
        settings = rankSettings(requested, findMethod(requested.method)->create(requested)->defaultSpp(), comm);
    });

    std::unique_ptr<vk::Context> context;
    onEveryRank(comm, [&] {
        const std::string choice = chooseRankDevice(settings, comm);
        vk::ContextOptions options;
        options.validate = settings.validate;
        options.device = settings.device;
        context = std::make_unique<vk::Context>(options);
        if (!choice.empty()) log::info("rank 0: " + choice);
    });
    log::info("device: " + context->deviceName() + " (" + context->deviceTypeName() + ")" +
              (comm.distributed() ? ", " + std::to_string(comm.size()) + " ranks" : ""));

    installInterruptHandler();
    RenderResult result;
    try {
        result = renderScene(*context, scene, settings, comm);
    } catch (const std::exception& e) {
        // The other ranks may be waiting for this one in a collective: end the job.
        if (!comm.distributed()) throw;
        std::fprintf(stderr, "pmcr: error: rank %d: %s\n", comm.rank(), e.what());
        std::fflush(stderr);
        comm.abortJob(1);
        throw;  // abortJob does not return under MPI
    }
    result = reduceRenderResults(std::move(result), requested, comm);
    if (comm.rank() > 0) {
        const size_t messages = context->validationMessages().size();
        if (messages == 0) return result.interrupted ? 130 : 0;
        std::fprintf(stderr, "pmcr: error: rank %d: validation layer reported %zu message(s)\n",
                     comm.rank(), messages);
        return 1;
    }
    auto written = writeRenderOutputs(result, paths);

    const auto& st = result.stats;
    if (!settings.quiet) {
        std::fprintf(stderr, "%s: %dx%d, %.4g spp, %.2f s%s -> %s\n", settings.method.c_str(),
                     settings.width, settings.height, result.output.samplesPerPixel, result.seconds,
                     result.interrupted ? " (interrupted)" : "", paths.hdr.string().c_str());
    }
    if (command.stats) {
        std::printf("method            %s\n", settings.method.c_str());
        std::printf("device            %s\n", context->deviceName().c_str());
        std::printf("resolution        %dx%d\n", settings.width, settings.height);
        if (comm.distributed()) std::printf("ranks             %d (MPI)\n", comm.size());
        std::printf("samples/pixel     %.4g\n", result.output.samplesPerPixel);
        std::printf("render time       %.3f s\n", result.seconds);
        std::printf("BVH build         %.3f s (%zu nodes)\n", st["bvh_build_seconds"].get<double>(),
                    st["bvh_nodes"].get<size_t>());
        std::printf("rays traced       %llu (%.3g rays/s)\n",
                    (unsigned long long)st["rays"].get<uint64_t>(), st["rays_per_second"].get<double>());
        std::printf("NaN/Inf dropped   %llu\n", (unsigned long long)st["nan_samples_dropped"].get<uint64_t>());
        std::printf("GPU time          %.1f ms\n", st["gpu_milliseconds"].get<double>());
        // Kernels by name, their paths under shaders/ ("methods/pmc_er/pmc_er_mutate"): one column.
        int nameWidth = 16;
        for (const auto& [name, k] : st["gpu_kernels"].items())
            nameWidth = std::max(nameWidth, int(name.size()));
        for (const auto& [name, k] : st["gpu_kernels"].items())
            std::printf("  %-*s %10.1f ms  %6llu dispatches\n", nameWidth, name.c_str(),
                        k["milliseconds"].get<double>(), (unsigned long long)k["dispatches"].get<uint64_t>());
        // The method's own figures (ERPT: chains started, proposals and acceptance per
        // mutation type, dropped deposits), as in the stats JSON's method_stats.
        if (st.contains("method_stats") && st["method_stats"].is_object() && !st["method_stats"].empty()) {
            std::printf("%s:\n", settings.method.c_str());
            for (const auto& [name, value] : st["method_stats"].items())
                std::printf("  %-28s %s\n", name.c_str(), value.dump().c_str());
        }
        for (const auto& path : written) std::printf("wrote             %s\n", path.string().c_str());
    }
    auto messages = context->validationMessages();
    if (!messages.empty())
        throw Error("validation layer reported " + std::to_string(messages.size()) + " message(s)");
    return result.interrupted ? 130 : 0;
}

void printRenderHelp() {
    std::printf(
        "usage: pmcr render SCENE [options]\n"
        "\n"
        "Renders a glTF 2.0 scene (.gltf or .glb) and writes an HDR image, a PNG preview and a\n"
        "stats JSON beside it.\n"
        "\n"
        "options:\n"
        "  --method NAME        rendering method (default pt; see the list below)\n"
        "  --spp N              samples per pixel (default 64 for pt/direct)\n"
        "  --time SECONDS       render for this long (with --spp: whichever comes first)\n"
        "  --width W --height H image size (default: the scene's, else 640 at the camera's aspect)\n"
        "  --paper-size         the size the scene's paper rendered it at (scenes/README.md)\n"
        "  --seed S             random seed; the same seed and device give the same image (default 1)\n"
        "  --max-depth D        maximum bounces, 1 = direct lighting (default 16)\n"
        "  --rr-depth D         Russian roulette from this bounce on (default 3)\n"
        "  --camera N           use the scene's N-th camera (default 0)\n"
        "%s"
        "  -o, --output FILE    HDR output, .exr or .pfm (default: SCENE-NAME.exr here)\n"
        "  --png FILE           PNG preview path (default: beside the output)\n"
        "  --no-png             no PNG preview\n"
        "  --exposure EV        PNG exposure in stops (default 0)\n"
        "  --device ID          Vulkan device index or name substring (see --list-devices)\n"
        "  --validate           enable the Khronos validation layer\n"
        "  --stats              print timings, rays/s and per-kernel GPU time\n"
        "  -q, --quiet          no progress bar or messages\n"
        "  --verbose            print warnings as they come (by default they wait until the\n"
        "                       render starts, and an error is the only line printed)\n"
        "  --restrict-paths     refuse buffers, images and environment images outside the\n"
        "                       scene's folder (for scenes from others; docs/scenes.md)\n"
        "\n"
        "Ctrl-C stops the render and still writes the image so far (exit status 130).\n"
        "\n"
        "Under mpirun (`mpirun -n N pmcr render ...`) the ranks render one image together:\n"
        "--spp is the total over the ranks, each has its own seed and device, the adaptive\n"
        "methods adapt as one population, rank 0 writes (docs/mpi.md).\n"
        "\n"
        "Method options marked [BIASED] make the method biased (off by default); those marked\n"
        "[PAPER BASELINE] select the weaker baseline a paper compared with\n"
        "(docs/paper-baselines.md).\n"
        "\n"
        "methods:\n",
        kEnvironmentHelp);
    for (const auto& m : methods()) {
        std::printf("  %-14s %s%s\n", m.name.c_str(), m.summary.c_str(),
                    m.create ? "" : (" [not implemented yet: " + m.plannedIn + "]").c_str());
        for (const auto& o : m.options) {
            const std::string baseline =
                o.paperBaseline.empty() ? "" : " [PAPER BASELINE " + o.paperBaseline + "]";
            std::printf("      --%-18s %s (default %s)%s%s\n", o.name.c_str(), o.help.c_str(),
                        o.defaultValue.c_str(), o.biased ? " [BIASED]" : "", baseline.c_str());
        }
    }
}

}  // namespace pmcr::cli
