#include "cli/cli.h"

#include <cstdio>
#include <exception>
#include <string>

#include "cli/args.h"
#include "cli/bench_command.h"
#include "cli/compare_command.h"
#include "cli/merge_command.h"
#include "cli/render_command.h"
#include "core/communicator.h"
#include "core/error.h"
#include "core/log.h"
#include "vk/context.h"

namespace pmcr::cli {

namespace {

void printUsage() {
    std::printf(
        "pmcr %s - adaptive Monte Carlo rendering (ERPT, PMC-IP/HI/PT/ER) on Vulkan compute\n"
        "\n"
        "usage:\n"
        "  pmcr render SCENE [options]   render a glTF scene (pmcr render --help for options)\n"
        "  pmcr compare IMAGE REFERENCE  Err, relMSE, perceptual Err, Eff and P-Eff of an image\n"
        "  pmcr merge IMAGE... -o OUT    average independent renders by their sample counts\n"
        "  pmcr bench SCENE [options]    run methods side by side; HTML/Markdown/JSON report\n"
        "  pmcr --list-devices           list Vulkan devices and whether pmcr can use them\n"
        "  pmcr --help | --version\n",
        PMCR_VERSION);
}

int listDevices() {
    auto devices = vk::Context::listDevices();
    if (devices.empty()) std::printf("no Vulkan devices\n");
    for (const auto& d : devices) {
        std::printf("%u: %s (%s, Vulkan %s, %s)", d.index, d.name.c_str(), d.type.c_str(),
                    d.apiVersion.c_str(), d.driver.c_str());
        if (d.missing.empty()) {
            std::printf(" - usable\n");
        } else {
            std::printf(" - missing:");
            for (const auto& m : d.missing) std::printf(" %s", m.c_str());
            std::printf("\n");
        }
    }
    return 0;
}

}  // namespace

int run(int argc, char** argv) {
    try {
        if (argc < 2) {
            printUsage();
            return 2;
        }
        const std::string command = argv[1];
        if (command == "--help" || command == "-h" || command == "help") {
            printUsage();
            return 0;
        }
        if (command == "--version") {
            std::printf("pmcr %s\n", PMCR_VERSION);
            return 0;
        }
        if (command == "--list-devices") return listDevices();
        // Subcommands: `--help` anywhere prints the subcommand's help.
        struct Subcommand {
            const char* name;
            void (*help)();
            int (*run)(Args&);
        };
        static const Subcommand subcommands[] = {
            {"render", printRenderHelp, [](Args& a) { return runRender(parseRenderCommand(a)); }},
            {"compare", printCompareHelp, runCompare},
            {"merge", printMergeHelp, runMerge},
            {"bench", printBenchHelp, runBench},
        };
        for (const Subcommand& sub : subcommands) {
            if (command != sub.name) continue;
            for (int i = 2; i < argc; ++i) {
                const std::string a = argv[i];
                if (a == "--help" || a == "-h") {
                    sub.help();
                    return 0;
                }
            }
            Args args(argc, argv, 2);
            const int status = sub.run(args);
            log::release();  // whatever a command still holds (core/log.h)
            return status;
        }
        throw Error(command + ": unknown command (see pmcr --help)");
    } catch (const std::exception& e) {
        // The error is the one line: messages held while the input was checked are dropped.
        log::discard();
        // Under mpirun every rank fails alike on bad input: rank 0 alone says so (a rank's own
        // failure is named by rank, render/distributed.h).
        if (worldCommunicator().rank() == 0) std::fprintf(stderr, "pmcr: error: %s\n", e.what());
        return 1;
    }
}

}  // namespace pmcr::cli
