// The `pmcr` command line: subcommands, help, and the one-line error convention
// ("pmcr: error: <file>: <problem>", exit status 1).
#pragma once

namespace pmcr::cli {

int run(int argc, char** argv);

}  // namespace pmcr::cli
