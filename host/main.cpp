// pmcr command-line entry point.
#include "cli/cli.h"
#include "core/process_clock.h"

int main(int argc, char** argv) {
    pmcr::processSeconds();  // starts the wall clock of the stats' wall_seconds
    return pmcr::cli::run(argc, argv);
}
